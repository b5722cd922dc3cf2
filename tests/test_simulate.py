"""Motion under forces (issue 22, docs/reference/simulation.md: mech.simulate), each against a
reference written here without mechgen's equations: a compound pendulum against its own ODE in the
angle alone; the slider-crank of test_forces started from rest by a motor torque law T0 (1 − ω/ω0),
against the equivalent-inertia equation J(θ) θ̈ + ½ J′(θ) θ̇² = T − ∂V/∂θ + F·∂r_C/∂θ in the crank
angle alone, J and J′ from the closed-form kinematics; a four-bar swinging under gravity (energy
kept, constraints kept); a double pendulum whose first link is still driven while the second swings
free, the driver's torque against Lagrange's equation written out by hand."""
import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import mechgen
from mechgen import Model, T, dt, rotation
from test_forces import G, MASS, PRESS, closed_form, slider_crank

RTOL = 1e-10


def _compile(model, tmp_path):
    return mechgen.compile(model, outdir=str(tmp_path), tier="python")


def _phi(mech, q, t):
    r = np.empty(mech.m)
    mech.module.phi(q, float(t), mech.p, r)
    return r


# -- a compound pendulum --------------------------------------------------------------------
L1, MB, JB = 1.2, 2.0, 0.15


def pendulum():
    m = Model("sim_pendulum")
    base = m.ground("base", points=[(0, 0)])
    bar = m.body("bar", points=[(0, 0), (L1, 0)], guess=(0, 0, -0.3), mass=MB, inertia=JB,
                 centroid=(L1 / 2, 0))
    m.revolute(base[1], bar[1])
    w = m.param("w", 0.0)
    m.rotation_lock(bar, -0.3 + w * T, name="hold")
    m.gravity(G)
    return m


def test_a_released_pendulum_swings_as_its_own_equation(tmp_path):
    mech = _compile(pendulum(), tmp_path)
    sw = mech.simulate(0.0, 4.0, 201, free=["hold"], rtol=RTOL, atol=1e-12)
    JO = JB + MB * (L1 / 2) ** 2
    ref = solve_ivp(lambda t, y: [y[1], -MB * G * (L1 / 2) * math.cos(y[0]) / JO], (0, 4.0),
                    [-0.3, 0.0], method="DOP853", rtol=1e-12, atol=1e-14, t_eval=sw.t)
    assert np.abs(sw["Th2"] - ref.y[0]).max() < 1e-8
    assert np.abs(sw["Th2d"] - ref.y[1]).max() < 1e-8
    e = sw.energy()["total"]
    assert np.abs(e - e[0]).max() <= 1e-8 * abs(e[0])
    assert sw.free == (mech.constraint_labels[2],)
    assert np.all(sw.LAM[:, 2] == 0.0)             # the freed driver carries nothing


# -- the slider-crank started by a motor -----------------------------------------------------
T0, W0 = 300.0, 30.0


def motor_slider_crank():
    m = slider_crank()
    crank = m.bodies["crank"]
    m.moment(crank, T0 * (1 - dt(rotation(crank)) / W0), name="motor")
    return m


def equivalent_inertia(theta):
    """J(θ), J′(θ) and the generalized load Q(θ) (gravity, the press) of the slider-crank,
    from test_forces' closed form at the speed it was written for (θ̈ = 0 there, so a_G =
    k_G′ θ̇² with k_G = v_G / θ̇ the velocity coefficients)."""
    from test_forces import TH0, W
    k = closed_form((theta - TH0) / W)
    J = dJ = Q = 0.0
    for name, (rg, vg, ag, om, al) in k["bodies"].items():
        m, Ji = MASS[name]
        kv, ka = vg / W, ag / W ** 2
        J += m * kv @ kv + Ji * (om / W) ** 2
        dJ += 2 * m * kv @ ka + 2 * Ji * (om / W) * (al / W ** 2)
        Q += m * np.array([0.0, -G]) @ kv
    Q += np.array(PRESS) @ (k["vC"] / W)
    return J, dJ, Q


def test_a_motor_starts_the_slider_crank_as_the_equivalent_inertia_says(tmp_path):
    mech = _compile(motor_slider_crank(), tmp_path).with_params(w=0.0)
    sw = mech.simulate(0.0, 1.5, 151, free=["crank driver"], rtol=RTOL, atol=1e-12)
    th0 = float(sw["Th2"][0])

    def rhs(t, y):
        J, dJ, Q = equivalent_inertia(y[0])
        return [y[1], (T0 * (1 - y[1] / W0) + Q - 0.5 * dJ * y[1] ** 2) / J]
    ref = solve_ivp(rhs, (0, 1.5), [th0, 0.0], method="DOP853", rtol=1e-12, atol=1e-13,
                    t_eval=sw.t)
    assert np.abs(sw["Th2"] - ref.y[0]).max() < 1e-8 * (1 + np.abs(ref.y[0]).max())
    assert np.abs(sw["Th2d"] - ref.y[1]).max() < 1e-8 * (1 + np.abs(ref.y[1]).max())
    assert sw["Th2d"][-1] > 10.0                      # it did start
    p = sw.power()
    assert np.abs(p["residual"]).max() <= 1e-8 * np.abs(p["loads"]).max()


# -- a four-bar swinging under gravity ------------------------------------------------------
def swinging_four_bar():
    m = Model("sim_fourbar")
    base = m.ground("base", points=[(0, 0), (2.0, 0)])
    crank = m.body("crank", points=[(0, 0), (1.0, 0)], guess=(0, 0, 1.2), mass=1.0,
                   inertia=0.1, centroid=(0.5, 0))
    coupler = m.body("coupler", points=[(0, 0), (2.2, 0)], guess=(0.36, 0.93, -0.2),
                     mass=2.0, inertia=0.8, centroid=(1.1, 0.1))
    rocker = m.body("rocker", points=[(0, 0), (1.6, 0)], guess=(2, 0, 1.7), mass=1.5,
                    inertia=0.3, centroid=(0.8, 0))
    m.revolute(base[1], crank[1])
    m.revolute(crank[2], coupler[1])
    m.revolute(coupler[2], rocker[2])
    m.revolute(base[2], rocker[1])
    w = m.param("w", 0.0)
    m.rotation_lock(crank, 1.2 + w * T, name="hold")
    m.gravity(G)
    return m


def test_a_four_bar_swinging_keeps_its_energy_and_its_constraints(tmp_path):
    mech = _compile(swinging_four_bar(), tmp_path)
    sw = mech.simulate(0.0, 12.0, 241, free=["hold"], rtol=RTOL, atol=1e-12)
    e = sw.energy()["total"]
    swing = sw["Th2"]
    assert swing.max() - swing.min() > 0.5                   # it swings
    assert np.count_nonzero(np.diff(np.sign(sw["Th2d"][1:])) != 0) >= 6
    assert np.abs(e - e[0]).max() <= 1e-8 * np.abs(sw.energy()["kinetic"]).max()
    rows = [i for i, lab in enumerate(mech.constraint_labels) if lab not in sw.free]
    worst = max(np.abs(_phi(mech, sw.Q[k], sw.t[k])[rows]).max() for k in range(len(sw)))
    assert worst < 1e-10


# -- a double pendulum: the first link driven, the second free ------------------------------
LA, LB, MA, MBB, JA, JBB = 1.0, 0.8, 1.5, 1.0, 0.12, 0.06
WA = 2.0


def double_pendulum():
    m = Model("sim_double")
    base = m.ground("base", points=[(0, 0)])
    a = m.body("a", points=[(0, 0), (LA, 0)], guess=(0, 0, 0.0), mass=MA, inertia=JA,
               centroid=(LA / 2, 0))
    b = m.body("b", points=[(0, 0), (LB, 0)], guess=(LA, 0, -1.0), mass=MBB, inertia=JBB,
               centroid=(LB / 2, 0))
    m.revolute(base[1], a[1])
    m.revolute(a[2], b[1])
    m.rotation_lock(a, WA * T, name="arm")
    w = m.param("w", 0.0)
    m.rotation_lock(b, a, -1.0 + w * T, name="elbow")
    m.gravity(G)
    return m


def test_a_driven_arm_with_a_free_elbow(tmp_path):
    """Lagrange for θ1 (driven at WA), θ2 free: τ1 = (JA + MA c1² + MB LA²) θ̈1
    + MB LA c2 (θ̈2 cos(θ1 − θ2) + θ̇2² sin(θ1 − θ2)) + (MA c1 + MB LA) g cos θ1, with
    c1 = LA/2, c2 = LB/2, θ̈1 = 0; and θ2's own equation holds on the simulated motion."""
    mech = _compile(double_pendulum(), tmp_path)
    sw = mech.simulate(0.0, 2.0, 101, free=["elbow"], rtol=RTOL, atol=1e-12)
    t1, t2 = sw["Th2"], sw["Th3"]
    d2, dd2 = sw["Th3d"], sw["Th3dd"]
    c1, c2 = LA / 2, LB / 2
    np.testing.assert_allclose(t1, WA * sw.t, atol=1e-10)
    tau = MBB * LA * c2 * (dd2 * np.cos(t1 - t2) + d2 ** 2 * np.sin(t1 - t2)) + \
        (MA * c1 + MBB * LA) * G * np.cos(t1)
    got = sw.driver("arm")
    np.testing.assert_allclose(got, tau, rtol=1e-8, atol=1e-8 * np.abs(tau).max())
    # θ2: (JB + MB c2²) θ̈2 + MB LA c2 (θ̈1 cos(θ1 − θ2) − θ̇1² sin(θ1 − θ2)) + MB c2 g cos θ2 = 0
    res = (JBB + MBB * c2 ** 2) * dd2 - MBB * LA * c2 * WA ** 2 * np.sin(t1 - t2) + \
        MBB * c2 * G * np.cos(t2)
    assert np.abs(res).max() < 1e-8


def test_simulate_refuses_what_it_cannot_do(tmp_path):
    mech = _compile(pendulum(), tmp_path)
    with pytest.raises(ValueError, match="no constraint 'nope'"):
        mech.simulate(0, 1, 11, free=["nope"])
    with pytest.raises(ValueError, match="is not a driver"):
        mech.simulate(0, 1, 11, free=[1])
    plain = mechgen.compile(Model_without_loads(), outdir=str(tmp_path / "plain"),
                            tier="python")
    with pytest.raises(ValueError, match="no masses and no loads"):
        plain.simulate(0, 1, 11, free=["hold"])


def Model_without_loads():  # noqa: N802 - a model factory
    m = Model("sim_no_loads")
    base = m.ground("base", points=[(0, 0)])
    bar = m.body("bar", points=[(0, 0), (1, 0)], guess=(0, 0, 0))
    m.revolute(base[1], bar[1])
    m.rotation_lock(bar, T, name="hold")
    return m


PENDULUM_FILE = '''
from mechgen import Model, T
m = Model("cli_pendulum")
base = m.ground("base", points=[(0, 0)])
bar = m.body("bar", points=[(0, 0), (1.2, 0)], guess=(0, 0, -0.3), mass=2.0, inertia=0.15,
             centroid=(0.6, 0))
m.revolute(base[1], bar[1])
w = m.param("w", 0.0)
m.rotation_lock(bar, -0.3 + w * T, name="hold")
m.gravity(9.807)
'''


def test_the_command_line_writes_the_simulated_motion(tmp_path, monkeypatch, capsys):
    import csv
    from mechgen.cli import main
    model = tmp_path / "pend.py"
    model.write_text(PENDULUM_FILE)
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("MECHGEN_TIER", "python")
    out = tmp_path / "motion.csv"
    rc = main(["simulate", str(model), "--free", "hold", "--t1", "2", "-n", "21",
               "--rtol", "1e-10", "-o", str(out)])
    assert rc in (0, None)
    assert "simulated 21 times" in capsys.readouterr().err
    rows = list(csv.DictReader(open(out)))
    th = np.array([float(r["Th2"]) for r in rows])
    JO = 0.15 + 2.0 * 0.6 ** 2
    ref = solve_ivp(lambda t, y: [y[1], -2.0 * 9.807 * 0.6 * math.cos(y[0]) / JO], (0, 2),
                    [-0.3, 0.0], method="DOP853", rtol=1e-12, atol=1e-14,
                    t_eval=np.linspace(0, 2, 21))
    assert np.abs(th - ref.y[0]).max() < 1e-7


def test_a_released_driver_has_no_force_columns(tmp_path):
    """Its multiplier is 0 by construction: a column of zeros would read as a measured
    effort."""
    mech = _compile(pendulum(), tmp_path)
    sw = mech.simulate(0.0, 0.5, 6, free=["hold"])
    header, _ = sw.table()
    assert not any(h.startswith("hold") for h in header)
    assert any(h.startswith("1 on bar") for h in header)


def test_the_guide_quotes_the_press_example(capsys, monkeypatch, tmp_path):
    """The user guide's press figures (docs/guide/simulation.md) are what
    examples/press_motor_demo.py prints (its large flywheel, run here in the plain tier:
    the same numbers)."""
    import importlib.util
    import os
    import re
    from conftest import ROOT
    monkeypatch.setenv("MECHGEN_CACHE", str(tmp_path))
    spec = importlib.util.spec_from_file_location(
        "press_demo", os.path.join(ROOT, "examples", "press_motor_demo.py"))
    demo = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(demo)
    mech = mechgen.compile(os.path.join(ROOT, "examples", "press_motor.py"),
                           outdir=str(tmp_path), tier="python")
    demo.run(mech, 2.0)
    out = capsys.readouterr().out
    from docs_pages import page
    section = page("guide/simulation.md")
    figures = re.findall(r"\d+\.\d+", out.split(";", 1)[1])
    assert len(figures) >= 5
    missing = [x for x in figures if x not in section]
    assert not missing, f"docs/guide/simulation.md does not quote the demo's {missing}"


def test_a_stalling_press_stops_with_a_clear_error(monkeypatch, tmp_path):
    """Pressing 6000 N, the ram stalls on the work: the pressing force switches off as
    the ram stops and on as it moves, and the integrator would spend its steps there for
    ever. It stops after a budget of evaluations, naming the time."""
    import os
    from conftest import ROOT
    import mechgen.runtime.forces.simulate as simulation
    monkeypatch.setattr(simulation, "INTERVAL_EVALUATIONS", 3000)
    mech = mechgen.compile(os.path.join(ROOT, "examples", "press_motor.py"),
                           outdir=str(tmp_path), tier="python").with_params(press=6000.0)
    with pytest.raises(mechgen.ConvergenceError, match=r"stalled near t=0\.14"):
        mech.simulate(0.0, 0.3, 4, free=["crank driver"])


def test_a_given_start_is_made_consistent_and_said_so(tmp_path):
    """q0 off the constraints (the pendulum's pin pulled 1 cm off its pivot), qd0 at rest:
    projected back with a warning, then the swing from there; a wrong qd0 is refused."""
    mech = _compile(pendulum(), tmp_path)
    with pytest.warns(UserWarning, match="made consistent"):
        sw = mech.simulate(0.0, 1.0, 11, free=["hold"], q0={"X2": 0.01, "Y2": 0.0,
                                                            "Th2": -0.3})
    assert abs(sw["X2"][0]) < 1e-12 and sw["Th2d"][0] == 0.0
    with pytest.raises(ValueError, match="qd0 must be 3 finite velocities"):
        mech.simulate(0.0, 1.0, 11, free=["hold"], qd0=[0.0, 1.0])


def test_the_coordinates_a_start_names_are_kept_and_the_others_follow(tmp_path):
    """q0={"Th2": θ}: the crank starts at θ exactly (the rod and the slider moved onto the
    constraints around it, the slider where the law of cosines puts it), not at a
    minimum-norm compromise that moves the crank too."""
    from test_forces import L, R
    mech = _compile(motor_slider_crank(), tmp_path).with_params(w=0.0)
    th = float(mech.guess[mech.coordinates.index("Th2")]) + 0.4
    with pytest.warns(UserWarning, match="made consistent"):
        sw = mech.simulate(0.0, 0.01, 2, free=["crank driver"], q0={"Th2": th})
    assert sw["Th2"][0] == th
    acting = [k for k, label in enumerate(mech.constraint_labels) if "crank driver" not in label]
    assert np.abs(_phi(mech, sw.Q[0], 0.0)[acting]).max() < 1e-10
    x = R * math.cos(th) + math.sqrt(L ** 2 - (R * math.sin(th)) ** 2)
    assert sw["X4"][0] == pytest.approx(x, abs=1e-10)


# -- models with no driver: held at the guess, simulated from it ----------------------------
def free_pendulum():
    m = Model("sim_free_pendulum")
    base = m.ground("base", points=[(0, 0)])
    m.body("bar", points=[(0, 0), (L1, 0)], guess=(0, 0, -0.3), mass=MB, inertia=JB,
           centroid=(L1 / 2, 0))
    m.revolute(base[1], m.bodies["bar"][1])
    m.gravity(G)
    return m


def test_a_model_without_a_driver_is_held_at_its_guess_and_swings_from_it(tmp_path):
    """No driver, one degree of freedom: the build holds Th2 at its guess (a driver that
    stands still, its effort the torque that holds the bar against gravity), and simulate
    lets it go with no free= at all."""
    mech = _compile(free_pendulum(), tmp_path)
    assert mech.constraint_labels[-1] == "2 hold Th2: hold(Th2, -0.3)"
    s = mech.solve(0.0, level="static")
    assert s["Th2"] == -0.3
    hold = MB * G * (L1 / 2) * math.cos(-0.3)
    assert abs(s.driver("hold Th2") - hold) <= 1e-12 * hold
    sw = mech.simulate(0.0, 3.0, 61, rtol=RTOL, atol=1e-12)
    assert sw.free == ("2 hold Th2: hold(Th2, -0.3)",)
    JO = JB + MB * (L1 / 2) ** 2
    ref = solve_ivp(lambda t, y: [y[1], -MB * G * (L1 / 2) * math.cos(y[0]) / JO], (0, 3.0),
                    [-0.3, 0.0], method="DOP853", rtol=1e-12, atol=1e-14, t_eval=sw.t)
    assert np.abs(sw["Th2"] - ref.y[0]).max() < 1e-8


def test_the_users_model_is_left_as_it_was_and_a_massless_one_still_needs_a_driver(tmp_path):
    model = free_pendulum()
    mechgen.compile(model, outdir=str(tmp_path), tier="python")
    assert [c.kind for c in model.constraints] == ["revolute"]
    bare = Model("sim_bare")
    base = bare.ground("base", points=[(0, 0)])
    bar = bare.body("bar", points=[(0, 0), (1, 0)], guess=(0, 0, 0))
    bare.revolute(base[1], bar[1])
    with pytest.raises(mechgen.ModelError, match="not square"):
        mechgen.compile(bare, outdir=str(tmp_path / "bare"), tier="python")


def free_four_bar():
    m = swinging_four_bar()
    m.constraints.pop()             # the "hold" driver: this four-bar has none
    m._equations = None
    m.name = "sim_free_fourbar"
    return m


def test_a_free_four_bar_swings_a_hundred_times_keeping_energy_and_constraints(tmp_path):
    """Issue 22: a conservative four-bar, no driver, no damping, over 100 swings at rtol
    1e-10: energy drift below 1e-8 of its kinetic swing, |Φ| below 1e-10 at every output."""
    mech = mechgen.compile(free_four_bar(), outdir=str(tmp_path), tier="compiled")
    sw = mech.simulate(0.0, 420.0, 2101, rtol=RTOL, atol=1e-12)
    swings = np.count_nonzero(np.diff(np.sign(sw["Th2d"][1:])) != 0) // 2
    assert swings >= 100
    e = sw.energy()
    assert np.abs(e["total"] - e["total"][0]).max() <= 1e-8 * np.abs(e["kinetic"]).max()
    kept = [i for i, lab in enumerate(mech.constraint_labels) if "hold" not in lab]
    worst = max(np.abs(_phi(mech, sw.Q[k], sw.t[k])[kept]).max() for k in range(len(sw)))
    assert worst < 1e-10


def test_the_compiled_integrator_takes_scipys_rk45_steps(tmp_path):
    """method "dopri5" (the module's integrate_span) is the Dormand–Prince pair of scipy's
    RK45 with the same error control: on the motor-started slider-crank the same steps
    within a few and the same motion to the tolerance."""
    mech = _compile(motor_slider_crank(), tmp_path).with_params(w=0.0)
    a = mech.simulate(0.0, 0.5, 6, free=["crank driver"], rtol=1e-9, atol=1e-11)
    b = mech.simulate(0.0, 0.5, 6, free=["crank driver"], rtol=1e-9, atol=1e-11,
                      method="RK45")
    assert abs(a.steps - b.steps) <= 0.05 * b.steps
    np.testing.assert_allclose(a.Q, b.Q, rtol=0, atol=1e-7)
    with pytest.raises(ValueError, match="method"):
        mech.simulate(0.0, 0.5, 6, free=["crank driver"], method="Euler")


@pytest.mark.parametrize("massless", [False, True])
def test_the_three_ways_of_free_accelerations_agree(tmp_path, massless):
    """free_accelerations goes by the sorted blocks (a sorted build), by M's Cholesky
    factor (an unsorted build, every body with mass and inertia) or by the whole
    saddle-point system (a body without mass): the same q̈ and λ at random states."""
    model = motor_slider_crank()
    if massless:
        rod = model.bodies["rod"]
        rod.mass, rod.inertia = 0, 0
    a = mechgen.compile(model, outdir=str(tmp_path / "a"), tier="python")
    b = mechgen.compile(model, outdir=str(tmp_path / "b"), tier="python", sort=False)
    assert a.module.FORCE_SORTED and not b.module.FORCE_SORTED
    keep = np.ones(a.m, dtype=np.bool_)
    keep[[i for i, lab in enumerate(a.constraint_labels) if "crank driver" in lab]] = False
    rng = np.random.default_rng(5)
    for _ in range(5):
        s = a.with_params(w=rng.uniform(-5, 5)).solve(rng.uniform(0, 1), level="velocity")
        qd = s.qd + rng.normal(size=a.n)
        out = []
        for mech in (a, b):
            qdd, lam = np.empty(mech.n), np.empty(mech.m)
            assert mech.module.free_accelerations(s.q, qd, 0.3, mech.p, keep, qdd, lam) == \
                mech.n + int(keep.sum())
            out.append((qdd, lam))
        np.testing.assert_allclose(out[0][0], out[1][0], rtol=1e-11,
                                   atol=1e-11 * np.abs(out[1][0]).max())
        np.testing.assert_allclose(out[0][1], out[1][1], rtol=1e-11,
                                   atol=1e-11 * np.abs(out[1][1]).max())


def test_the_command_line_moves_a_model_without_a_driver_and_draws_it(tmp_path, monkeypatch,
                                                                     capsys):
    from mechgen.cli import main
    model = tmp_path / "free_pend.py"
    model.write_text(PENDULUM_FILE.replace('w = m.param("w", 0.0)\n', "").replace(
        'm.rotation_lock(bar, -0.3 + w * T, name="hold")\n', ""))
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("MECHGEN_TIER", "python")
    rc = main(["simulate", str(model), "--t1", "1", "-n", "11", "-o", "m.csv",
               "--plot", "Th2,Th2d", "--plot-file", "swing.png", "--animate", "swing.gif"])
    assert rc in (0, None)
    out = capsys.readouterr().out
    assert "wrote swing.png (Th2, Th2d over 11 times)" in out
    assert "wrote swing.gif (11 frames" in out
    from PIL import Image
    assert Image.open(tmp_path / "swing.png").size[0] > 300
    assert Image.open(tmp_path / "swing.gif").n_frames == 11


def _hanging_four_bar(name, ground, a, b, c, th):
    m = Model(name)
    base = m.ground("base", points=[(0, 0), (ground, 0)])
    crank = m.body("crank", points=[(0, 0), (a, 0)], guess=(0, 0, th), mass=1.0,
                   inertia=0.1, centroid=(a / 2, 0))
    coupler = m.body("coupler", points=[(0, 0), (b, 0)],
                     guess=(a * math.cos(th), a * math.sin(th), -0.3), mass=1.0, inertia=0.1,
                     centroid=(b / 2, 0))
    rocker = m.body("rocker", points=[(0, 0), (c, 0)], guess=(ground, 0, 2.0), mass=1.0,
                    inertia=0.1, centroid=(c / 2, 0))
    m.revolute(base[1], crank[1])
    m.revolute(crank[2], coupler[1])
    m.revolute(coupler[2], rocker[2])
    m.revolute(base[2], rocker[1])
    m.gravity(G)
    return m


def test_a_free_swing_passes_the_cranks_toggle_and_stops_at_a_true_lock(tmp_path):
    """A crank-rocker left to swing reaches the crank's toggle (coupler and rocker in
    line: a dead centre only for a crank driver) and turns back through it, energy kept;
    a parallelogram swinging down to its flat change point (every pin in line: the
    constraints themselves lose rank) stops there with a SingularError naming the time
    and the constraints."""
    toggle = mechgen.compile(_hanging_four_bar("sim_toggle", 3.0, 1.0, 1.0, 1.5, 0.3),
                             outdir=str(tmp_path / "a"), tier="python")
    sw = toggle.simulate(0.0, 3.0, 61, rtol=RTOL, atol=1e-12)
    # the toggle angle: |A − D| = coupler + rocker
    reach = -math.acos((1.0 + 9.0 - 2.5 ** 2) / (2 * 3.0))
    assert sw["Th2"].min() > reach and sw["Th2"].min() < reach + 0.05   # turned back close
    e = sw.energy()["total"]
    assert np.abs(e - e[0]).max() <= 1e-8 * np.abs(sw.energy()["kinetic"]).max()
    flat = mechgen.compile(_hanging_four_bar("sim_flat", 2.0, 1.0, 2.0, 1.0, 0.8),
                           outdir=str(tmp_path / "b"), tier="python")
    with pytest.raises(mechgen.SingularError, match="lock there") as info:
        flat.simulate(0.0, 3.0, 61, rtol=RTOL, atol=1e-12)
    assert set(info.value.constraints) == {f"{k} {lab}" for k, lab in zip(
        range(1, 5), ["revolute(base[1], crank[1])", "revolute(crank[2], coupler[1])",
                      "revolute(coupler[2], rocker[2])", "revolute(base[2], rocker[1])"])}
    assert "at t=0.42" in str(info.value)


def test_extremes_of_a_simulated_motion_are_refined_on_the_motion_not_the_kinematics(tmp_path):
    """A pendulum let go at −0.3 swings to −π + 0.3 (energy: the mirror image about the
    vertical). extrema() refines between the outputs by integrating again from the output
    before, never by solving the kinematics (which hold the bar at its guess)."""
    mech = _compile(free_pendulum(), tmp_path)
    sw = mech.simulate(0.0, 3.0, 31, rtol=RTOL, atol=1e-12)
    low = sw.extrema("Th2").minima
    assert len(low) == 2
    for e in low:
        assert abs(e.value - (-math.pi + 0.3)) < 5e-9       # the integration's error
    stops = sw.roots("Th2d").interior
    assert np.allclose(np.diff(stops.t), stops.t[0], rtol=1e-8)   # half periods, even
    assert sw.at_level("velocity").simulation == sw.simulation


def test_a_simulated_motion_reads_like_any_sweep(tmp_path):
    """Its statuses (all OK), the table of earlier versions, its CSV and its repr: a
    simulated Sweep gave a status vector of the wrong shape, and sw.status raised."""
    mech = _compile(pendulum(), tmp_path)
    sw = mech.simulate(0.0, 1.0, 11, free=["hold"])
    assert sw.status.shape == (11,) and np.all(sw.status == 0)
    assert sw.iterations is None and sw.info.shape[0] == 11
    sw.to_csv(str(tmp_path / "swing.csv"))
    with open(tmp_path / "swing.csv") as fh:
        rows = fh.read().splitlines()
    assert len(rows) == 12 and rows[0].startswith("T,X2,Y2,Th2")
    assert "11 points" in repr(sw) and "level dynamic" in repr(sw)
    assert "level static" in repr(mech.sweep(0.0, 1.0, 3, level="static"))
