"""Singular and toggle positions, configurations that cannot assemble, lock points,
redundant constraints, branch keeping and continuous angles (issue 7)."""
import math
import os
import warnings

import numpy as np
import pytest

import mechgen
from mechgen.runtime.analysis.locks import Singularity

# -- the slider-driven quick-return of seed 001, section 3B ------------------------------
# X4 = C + A sin 2πT overshoots the stroke [XMIN, XMAX] the linkage can reach: the crank
# is tangent to the slotted lever (colisa) at the two extremes, Th3 = ∓asin(3/5).
C, A = 4.13931, 5.40447
XMAX = 5.4 + math.sqrt(17.16)            # 9.542463 (seed: the crank-driven maximum)
XMIN = -5.4 + math.sqrt(17.16)
T1 = math.asin((XMAX - C) / A) / (2 * math.pi)
T2 = 0.5 - T1
T3 = (math.pi + math.asin((C - XMIN) / A)) / (2 * math.pi)
T4 = 1.5 - T3
LOCKS = [T1, T2, T3, T4]
NEAR_T1 = {"Th2": -0.64, "Th3": -0.64, "X4": 9.54}
SEED_249 = {"Th2": -1.17501, "Th3": -0.643842, "X4": 9.54367}   # Mech's last iterate


def same_angle(a, b, tol):
    return np.all(np.abs(np.remainder(np.asarray(a) - b + np.pi, 2 * np.pi) - np.pi) <= tol)


def test_lock_times_are_the_issue_figures():
    assert [round(t, 6) for t in LOCKS] == [0.246486, 0.253514, 0.741546, 0.758454]
    assert round(XMAX, 6) == 9.542463


# -- singular configurations ----------------------------------------------------------------
@pytest.mark.parametrize("method", ["auto", "sorted", "full"])
def test_exact_toggle_position_flagged_velocity_refused(qr_slider, method):
    s = qr_slider.solve(T1, guess=NEAR_T1, method=method)
    assert s.singular
    assert s.residual <= 1e-9
    assert abs(s["X4"] - XMAX) < 1e-9
    assert same_angle(s["Th3"], -math.asin(0.6), 1e-6)      # the lever tangent to the crank
    for level in ("velocity", "acceleration"):
        with pytest.raises(mechgen.SingularError) as info:
            qr_slider.solve(T1, guess=NEAR_T1, method=method, level=level)
        err = info.value
        assert err.level == "velocity" and err.t == T1
        assert f"{T1:.10g}" in str(err)
        assert err.constraints[0].startswith("3 point_on_line")     # loses its grip on Th2
        assert "cannot fix Th2" in str(err)
        assert err.q is not None and abs(err.q[6] - XMAX) < 1e-9


def test_near_toggle_is_regular(qr_slider):
    """1e-6 before the toggle the velocity is large but determined: no false alarm."""
    s = qr_slider.solve(T1 - 1e-6, guess=NEAR_T1, level="acceleration")
    assert not s.singular and s.residual <= 1e-10
    J, nu = qr_slider.jacobian(s.q, s.t), np.empty(9)
    qr_slider.module.nu(s.q, s.t, qr_slider.p, nu)
    assert np.allclose(J @ s.qd, nu, atol=1e-8 * np.abs(s.qd).max())
    assert abs(s["Th2d"]) > 100


def _dead_centre(model_kind, omega):
    """Four-bar a=1, b=1, c=1.5, d=2: the crank limit where coupler and rocker stretch
    into one line, |A − D| = b + c, cos θ2 = −0.3125."""
    th = math.acos(-0.3125)
    A = np.array([math.cos(th), math.sin(th)])
    u = (np.array([2.0, 0.0]) - A) / np.linalg.norm(np.array([2.0, 0.0]) - A)
    th3, th4 = math.atan2(u[1], u[0]), math.atan2(-u[1], -u[0])
    params = dict(a=1.0, b=1.0, c=1.5, d=2.0, theta2=th, omega=omega)
    if model_kind == "bodies":
        guess = {"Th2": th, "X3": A[0], "Y3": A[1], "Th3": th3 + 0.01, "X4": 2.0, "Y4": 0.0,
                 "Th4": th4 - 0.01}
        return params, guess, ("Th3", "Th4"), (th3, th4)
    return params, {"theta3": th3 + 0.01, "theta4": th4 - 0.01}, ("theta3", "theta4"), (th3, th4)


@pytest.mark.parametrize("omega", [0.0, 2 * math.pi])
@pytest.mark.parametrize("kind", ["bodies", "loop"])
def test_fourbar_dead_centre(fourbar, fourbar_loop, kind, omega):
    params, guess, names, exact = _dead_centre(kind, omega)
    mech = (fourbar if kind == "bodies" else fourbar_loop).with_params(**params)
    s = mech.solve(0.0, guess=guess)
    assert s.singular and s.residual <= 1e-9
    for name, value in zip(names, exact):
        assert same_angle(s[name], value, 1e-5)
    # with the crank turning (omega ≠ 0) no velocity exists; at rest (omega = 0) it is
    # not unique: either way the constraints do not determine it
    with pytest.raises(mechgen.SingularError) as info:
        mech.solve(0.0, guess=guess, level="velocity")
    assert info.value.level == "velocity"
    assert "t=0" in str(info.value)


# -- no assembly ----------------------------------------------------------------------------
def test_no_assembly_at_0249_says_why(qr_slider):
    with pytest.raises(mechgen.ConvergenceError) as info:
        qr_slider.solve(0.249, guess=SEED_249)
    err = info.value
    text = str(err)
    assert err.t == 0.249 and "t=0.249" in text
    assert "cannot assemble" in text
    assert "slider driver" in text                                   # the culprit driver
    assert "3 point_on_line" in text and "Th2" in text
    assert f"{T1:.10g}" in text and f"{T2:.10g}" in text
    assert [s.kind for s in err.locks] == ["lock", "lock"]
    assert abs(err.locks[0] - T1) < 1e-8 and abs(err.locks[1] - T2) < 1e-8
    assert err.constraints == ("3 point_on_line(manivela[2], colisa.line(1, 2))",)


@pytest.mark.parametrize("t", [0.2465, 0.248, 0.25, 0.252, 0.2535])
def test_no_assembly_anywhere_in_the_first_gap(qr_slider, t):
    """X4 > XMAX: no assembly mode reaches it; whatever the guess, the solve raises."""
    for guess in (None, NEAR_T1, SEED_249, {"Th2": 2.5, "Th3": 0.64, "X4": 9.6},
                  {"Th2": -0.6, "Th3": -0.6, "X4": 9.6, "Th4": math.pi}):
        with pytest.raises(mechgen.ConvergenceError) as info:
            qr_slider.solve(t, guess=guess)
        assert f"t={t:.10g}" in str(info.value)


@pytest.mark.parametrize("t", [0.742, 0.75, 0.758])
def test_second_gap_only_in_the_other_assembly_mode(qr_slider, t):
    """X4 < XMIN: the seed's mode (slider right of the lever tip) cannot reach it; the mode
    with the slider on the other side of the tip can (tests/closed_forms.py: the lever at
    Th3 ≈ −0.393, the crank pin on either side). From a guess near one of those
    configurations the solve must return it; from the model's guess it may refuse, and
    what it returns is one of them."""
    from closed_forms import slider_driven_configurations
    configs = slider_driven_configurations(t)
    assert len(configs) == 2
    for th2, th3, x4 in configs:
        assert x4 < -9 * math.sin(th3)                 # the slider left of the tip: the other mode

    def which(s):
        assert s.residual <= 1e-10
        for k, (th2, th3, x4) in enumerate(configs):
            if same_angle(s["Th2"], th2, 1e-9) and same_angle(s["Th3"], th3, 1e-9) and \
                    abs(s["X4"] - x4) < 1e-9:
                return k
        raise AssertionError(f"not a configuration of the closed form: {s.q}")

    for k, (th2, th3, x4) in enumerate(configs):
        s = qr_slider.solve(t, guess={"Th2": th2 + 0.05, "Th3": th3 - 0.05, "X4": x4 + 0.05})
        assert which(s) == k
    try:
        which(qr_slider.solve(t))
    except mechgen.ConvergenceError as exc:
        assert "no configuration" in str(exc)


def test_sweep_stops_at_the_lock(qr_slider):
    with pytest.raises(mechgen.ConvergenceError) as info:
        qr_slider.sweep(0.0, 1.0, 101)
    err = info.value
    assert len(err.sweep) == 25 and err.sweep.t[-1] == pytest.approx(0.24)
    assert np.all([qr_slider.residual(q, t) <= 1e-10 for q, t in zip(err.sweep.Q, err.sweep.t)])
    assert "t=0.25" in str(err) and "reached t=0.24648" in str(err)
    assert abs(err.locks[0] - T1) < 1e-8
    assert f"lock (toggle) position at t≈{T1:.10g}" in str(err)


@pytest.mark.parametrize("level", ["position", "velocity", "acceleration"])
def test_sweep_does_not_step_over_a_gap(qr_slider, level):
    """Both times assemble, but the mechanism cannot move from one to the other."""
    assert qr_slider.solve(0.245, guess=NEAR_T1).residual < 1e-10
    with pytest.raises(mechgen.ConvergenceError) as info:
        qr_slider.sweep(None, None, None, times=[0.245, 0.255], guess=NEAR_T1, level=level)
    assert len(info.value.sweep) == 1
    assert abs(info.value.locks[0] - T1) < 1e-8


def test_sweep_onto_the_exact_toggle(qr_slider):
    with pytest.warns(mechgen.BranchJumpWarning, match="singular configuration"):
        sw = qr_slider.sweep(0.0, T1, 11)                 # positions exist up to the lock
    assert list(sw.crossings) == [T1]
    assert len(sw) == 11 and abs(sw["X4"][-1] - XMAX) < 1e-9
    for level in ("velocity", "acceleration"):
        with pytest.raises(mechgen.SingularError) as info:
            qr_slider.sweep(0.0, T1, 11, level=level)
        assert len(info.value.sweep) == 10 and info.value.t == pytest.approx(T1, abs=1e-12)



# a crank pushed by its slider from the outer dead centre (x = R + L at t = 0), R = 0.3,
# L = 1 (tests/test_cli_core.py runs the command on it too)
DEAD_CENTRE = """
from mechgen import Model, T
m = Model("from_dead_centre")
base = m.ground("base", points=[(0, 0), (1, 0)])
crank = m.body("crank", points=[(0, 0), (0.3, 0)], guess=(0, 0, {guess}))
rod = m.body("rod", points=[(0, 0), (1.0, 0)], guess=(0.3, 0, 0.0))
slider = m.body("slider", points=[(0, 0), (1, 0)], guess=(1.3, 0, 0))
m.revolute(base[1], crank[1])
m.revolute(crank[2], rod[1])
m.revolute(rod[2], slider[1])
m.translate(base.line(1, 2), slider.line(1, 2))
m.relative_x(slider[1], 1.3 - T, name="push")
"""


def _slider_from_its_dead_centre(tmp_path, guess):
    """DEAD_CENTRE built with the crank's guess ``guess``, and its crank angle on the
    guess's side by the law of cosines."""
    from mechgen.model.loader import load_models
    R, L = 0.3, 1.0
    path = tmp_path / f"dead_centre_{guess}.py"
    path.write_text(DEAD_CENTRE.format(guess=guess))
    mech = mechgen.compile(load_models(str(path))[0], outdir=str(tmp_path / f"g{guess}"),
                           tier="python")

    def th2(t):
        x = R + L - t
        return math.copysign(math.acos(min(1.0, (x * x + R * R - L * L) / (2 * x * R))), guess)
    return mech, th2


@pytest.mark.parametrize("n", [11, 101])
@pytest.mark.parametrize("guess", [0.01, -0.01])
def test_leaving_a_dead_centre_is_a_crossing_not_a_jump(tmp_path, n, guess):
    """At t = 0 the crank stands at the dead centre, where both of its branches meet, and
    leaves it as √t, which no step size follows: the first point after it is marked as
    reached out of a singular configuration, whatever the step (it was a branch jump at
    11 points and a crossing at 101), and the branch taken is the guess's."""
    mech, th2 = _slider_from_its_dead_centre(tmp_path, guess)
    assert mech.solve(0.0).singular
    with pytest.warns(mechgen.BranchJumpWarning, match="singular configuration") as rec:
        sw = mech.sweep(0.0, 0.1, n)
    assert not any("could not keep" in str(w.message) for w in rec)
    assert len(sw.jumps) == 0 and list(sw.crossings) == [sw.t[1]]
    assert np.all(sw.status[2:] == 0)
    ref = np.array([th2(t) for t in sw.t])
    assert np.abs(sw["Th2"] - ref).max() < 1e-7     # (√ of the tolerance at t = 0)
    assert np.abs(sw["Th2"][1:] - ref[1:]).max() < 1e-9

# -- locating lock points ---------------------------------------------------------------------
def test_singularities_of_the_slider_driven_quick_return(qr_slider):
    found = qr_slider.singularities(0.0, 1.0)
    assert len(found) == 4
    for s, exact in zip(found, LOCKS):
        assert isinstance(s, Singularity) and isinstance(s, float)
        assert s.kind == "lock"
        assert abs(s - exact) < 1e-8 and abs(s.t - exact) < 1e-8
        assert s.solution.singular and s.solution.residual <= 1e-9
        assert qr_slider.pivot_ratio(s.q, s.t) < qr_slider.sing_rtol
        assert s.coordinates == ("Th2",)
        assert s.lock == ("3 point_on_line(manivela[2], colisa.line(1, 2))",)
        assert abs(abs(s["X4"] - C) - (XMAX - C if s.t < 0.5 else C - XMIN)) < 1e-9
    # the API example: the two locks of the first gap
    assert [round(s, 6) for s in qr_slider.singularities(0.2, 0.3)] == [0.246486, 0.253514]


def test_no_singularities_along_a_regular_cycle(qr):
    assert qr.singularities(0.0, 1.0) == []


def test_dead_centre_crossings_of_a_parallelogram(fourbar):
    """A parallelogram four-bar (a = c, b = d) passes change points at θ2 = π and 2π."""
    mech = fourbar.with_params(a=1.0, b=3.0, c=1.0, d=3.0, theta2=0.5, omega=2 * math.pi)
    guess = {"Th2": 0.5, "X3": math.cos(0.5), "Y3": math.sin(0.5), "Th3": 0.05, "X4": 3.0,
             "Y4": 0.0, "Th4": 0.55}
    found = mech.singularities(0.0, 1.0, guess=guess)
    exact = [(math.pi - 0.5) / (2 * math.pi), (2 * math.pi - 0.5) / (2 * math.pi)]
    assert [s.kind for s in found] == ["crossing", "crossing"]
    assert np.allclose(found, exact, atol=1e-8)
    # a sweep reports them and, with velocities, keeps to the parallelogram
    for level in ("velocity", "acceleration"):
        with pytest.warns(mechgen.BranchJumpWarning, match="singular configuration"):
            sw = mech.sweep(0.0, 1.0, 101, guess=guess, level=level)
        assert np.allclose(sw.crossings, [0.43, 0.93])
        assert np.abs(sw["Th3"]).max() < 1e-10 and np.abs(sw["Th4"] - sw["Th2"]).max() < 1e-10


# -- redundant constraints --------------------------------------------------------------------
PARALLELOGRAM = '''
"""Parallelogram four-bar with an extra parallel link: 13 equations for 12 coordinates."""
from mechgen import Model, T, pi

m = Model("parallelogram_extra")
a = m.param("a", 1.0)
d = m.param("d", 3.0)
e = m.param("e", 1.0)        # the extra link; consistent only when e = a
omega = m.param("omega", 2 * pi)

ground = m.ground("ground", points=[(0, 0), (d, 0), (d / 2, 0)])
crank = m.body("crank", points=[(0, 0), (a, 0)], guess=(0, 0, 0.5))
coupler = m.body("coupler", points=[(0, 0), (d, 0), (d / 2, 0)], guess=(0.9, 0.5, 0.0))
rocker = m.body("rocker", points=[(0, 0), (a, 0)], guess=(3, 0, 0.5))
extra = m.body("extra", points=[(0, 0), (e, 0)], guess=(1.5, 0, 0.5))

m.revolute(ground[1], crank[1])
m.revolute(crank[2], coupler[1])
m.revolute(ground[2], rocker[1])
m.revolute(coupler[2], rocker[2])
m.revolute(ground[3], extra[1])
m.revolute(coupler[3], extra[2], name="extra link")
m.rotation_lock(crank, 0.5 + omega * T, name="crank angle")
'''


@pytest.fixture(scope="module")
def redundant(tmp_path_factory):
    from mechgen.compiler.build import build
    from mechgen.model.loader import load_models
    d = tmp_path_factory.mktemp("redundant")
    src = d / "parallelogram_extra.py"
    src.write_text(PARALLELOGRAM)
    path = build(load_models(str(src))[0], str(d / "gen"))
    return str(src), mechgen.load(path)


def test_redundant_constraints_solve_and_are_reported_once(redundant):
    _, mech = redundant
    with pytest.warns(mechgen.RedundancyWarning, match="13 equations for 12 coordinates") as rec:
        s = mech.solve(0.0, level="acceleration")
    assert "extra link" in str(rec[0].message)
    assert s.residual < 1e-12 and not s.singular
    assert abs(s["Th3"]) < 1e-12 and abs(s["Th4"] - 0.5) < 1e-12 and abs(s["Th5"] - 0.5) < 1e-12
    assert abs(s["Th4d"] - 2 * math.pi) < 1e-9 and abs(s["Th4dd"]) < 1e-9
    with warnings.catch_warnings():
        warnings.simplefilter("error")                        # reported once, not again
        sw = mech.sweep(0.0, 2.0, 201, level="acceleration", tol=1e-12)
        mech.with_params(d=2.5).solve(0.3)
    th2 = 0.5 + 2 * math.pi * sw.t
    assert np.abs(sw["Th3"]).max() < 1e-9
    assert np.abs(sw["Th4"] - th2).max() < 1e-9 and np.abs(sw["Th5"] - th2).max() < 1e-9
    assert np.abs(sw["Th4d"] - 2 * math.pi).max() < 1e-7


def test_redundant_model_locates_its_shaky_positions(redundant):
    """With all links aligned (θ2 = π, 2π) Φ_q loses rank although the extra link keeps
    the mechanism a parallelogram: its minors vanish without changing sign."""
    _, mech = redundant
    found = mech.singularities(0.0, 1.0)
    exact = [(math.pi - 0.5) / (2 * math.pi), (2 * math.pi - 0.5) / (2 * math.pi)]
    assert np.allclose(found, exact, atol=1e-8)


def test_inconsistent_redundant_constraints_raise(redundant):
    _, mech = redundant
    with pytest.raises(mechgen.ConvergenceError) as info:
        mech.with_params(e=1.3).solve(0.0)
    assert "disagree" in str(info.value) or "cannot assemble" in str(info.value)


def test_check_names_the_redundant_equations(redundant, capsys):
    from mechgen.cli import main
    src, _ = redundant
    assert main(["check", src]) == 0
    out = capsys.readouterr().out
    assert "redundant" in out and "6 extra link: revolute(coupler[3], extra[2])" in out


# -- branch keeping ------------------------------------------------------------------------------
def fourbar_closed(a, b, c, d, th2, sigma):
    """Coupler and rocker angles of the assembly mode sigma = ±1 (circle intersection)."""
    B = np.stack([a * np.cos(th2), a * np.sin(th2)])
    D = np.array([d, 0.0])[:, None]
    e = D - B
    L = np.hypot(e[0], e[1])
    x = (b * b - c * c + L * L) / (2 * L)
    y = sigma * np.sqrt(b * b - x * x)
    ex = e / L
    Cp = B + x * ex + y * np.stack([-ex[1], ex[0]])
    return np.arctan2(Cp[1] - B[1], Cp[0] - B[0]), np.arctan2(Cp[1], Cp[0] - d)


NEAR_CHANGE_POINT = [  # Grashof by a hair: a + d = b + c − eps, the two modes nearly touch
    (1.0, 2.4215598704, 1.3105786168, 2.7320061957, 1.3e-4),
    (1.0, 2.0, 1.9999, 3.0, 1e-4),
    (1.0, 2.5, 1.51, 3.0, 1e-2),
]


@pytest.mark.parametrize("a,b,c,d,eps", NEAR_CHANGE_POINT)
@pytest.mark.parametrize("level", ["position", "velocity", "acceleration"])
def test_sweep_keeps_its_assembly_mode_near_a_change_point(fourbar, a, b, c, d, eps, level):
    c = a + d - b + eps
    mech = fourbar.with_params(a=a, b=b, c=c, d=d, theta2=0.3, omega=2 * math.pi)
    for sigma in (1, -1):
        th3, th4 = fourbar_closed(a, b, c, d, np.array([0.3]), sigma)
        guess = {"Th2": 0.3, "X3": a * math.cos(0.3), "Y3": a * math.sin(0.3),
                 "Th3": th3[0] + 1e-3, "X4": d, "Y4": 0.0, "Th4": th4[0] - 1e-3}
        for n in (21, 41, 101):
            with warnings.catch_warnings():
                warnings.simplefilter("error")        # nothing to report: no jump at all
                sw = mech.sweep(0.0, 1.0, n, guess=guess, level=level)
            e3, e4 = fourbar_closed(a, b, c, d, 0.3 + 2 * math.pi * sw.t, sigma)
            assert same_angle(sw["Th3"], e3, 1e-7), (sigma, n)
            assert same_angle(sw["Th4"], e4, 1e-7), (sigma, n)


@pytest.mark.parametrize("n", [3, 4, 5, 7])
@pytest.mark.parametrize("level", ["position", "velocity", "acceleration"])
def test_coarse_sweeps_keep_the_assembly_mode(qr, n, level):
    """Three crank turns in a handful of points: substeps, not the other assembly mode;
    every point (and its derivatives) the closed form's (tests/closed_forms.py)."""
    from closed_forms import motion, quick_return
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        sw = qr.sweep(0.0, 3.0, n, level=level)
    for k, t in enumerate(sw.t):
        q, qd, qdd = motion(quick_return, t)
        assert np.abs(sw.Q[k] - q).max() < 1e-10, (k, t)       # Th2 = 2πT, unwrapped too
        if sw.QD is not None:
            assert np.abs(sw.QD[k] - qd).max() < 1e-9 * (1 + np.abs(qd).max()), (k, t)
        if sw.QDD is not None:
            assert np.abs(sw.QDD[k] - qdd).max() < 1e-9 * (1 + np.abs(qdd).max()), (k, t)
    # (the quick-return's blocks are closed forms whose roots a sign picks: the mode is
    # kept by the sign, and no substeps are needed to keep it)


JUMPY = '''
from mechgen import Model, T, cos, sin, tanh
m = Model("snapping_fourbar")
th2 = 1.0 + 1.5 * tanh(1e9 * (T - 0.5))          # the crank snaps through 3 rad at T = 0.5
th3 = m.coordinate("theta3", guess=0.5)
th4 = m.coordinate("theta4", guess=1.8)
m.constraint(0.8 * cos(th2) + 2.5 * cos(th3) - 2 * cos(th4) - 3, name="loop real")
m.constraint(0.8 * sin(th2) + 2.5 * sin(th3) - 2 * sin(th4), name="loop imaginary")
'''


def test_a_jump_the_step_control_cannot_avoid_is_reported(tmp_path):
    from mechgen.compiler.build import build
    from mechgen.model.loader import load_models
    (tmp_path / "snapping.py").write_text(JUMPY)
    model = load_models(str(tmp_path / "snapping.py"))[0]
    # Newton blocks: the snap throws the loop's Newton into the other mode
    mech = mechgen.load(build(model, str(tmp_path / "newton"), closed_forms="none"),
                        tier="python")          # (plain Python: the same numbers)
    with pytest.warns(mechgen.BranchJumpWarning, match="could not keep the assembly mode"):
        sw = mech.sweep(0.0, 1.0, 11)
    assert 0.5 in sw.jumps or 0.6 in sw.jumps
    assert np.all([mech.residual(q, t) < 1e-10 for q, t in zip(sw.Q, sw.t)])
    # the loop as an RRR dyad: the snap is reported as well (the configuration jumps with
    # the crank), and its sign keeps the first point's mode across it
    dyad = mechgen.load(build(model, str(tmp_path / "dyad")), tier="python")
    with pytest.warns(mechgen.BranchJumpWarning, match="could not keep the assembly mode"):
        sw = dyad.sweep(0.0, 1.0, 11)
    assert np.any(np.isclose(sw.jumps, 0.5) | np.isclose(sw.jumps, 0.6))
    assert np.all([dyad.residual(q, t) < 1e-10 for q, t in zip(sw.Q, sw.t)])
    det = [dyad.module.jacobian_det(q, t, dyad.p, np.zeros(2)) for q, t in zip(sw.Q, sw.t)]
    assert np.all(np.sign(det) == np.sign(det[0]))


# -- angles -------------------------------------------------------------------------------------
def test_angles_are_continuous_along_sweeps(qr, fourbar_loop):
    sw = qr.sweep(0.0, 3.0, 301, level="velocity")
    assert np.abs(sw["Th2"] - 2 * math.pi * sw.t).max() < 1e-9          # unwrapped: 0 → 6π
    for name in ("Th2", "Th3", "Th4"):
        assert np.abs(np.diff(sw[name])).max() < 0.1
    loop = fourbar_loop.with_params(omega=2 * math.pi)
    sw = loop.sweep(0.0, 2.0, 201, level="acceleration")
    assert np.abs(np.diff(sw["theta3"])).max() < 0.1 and np.abs(np.diff(sw["theta4"])).max() < 0.1
    # started a turn away, the whole sweep stays a turn away (equal modulo 2π)
    s0 = loop.solve(0.0)
    sw2 = loop.sweep(0.0, 2.0, 201, guess={"theta3": s0["theta3"] + 2 * math.pi,
                                           "theta4": s0["theta4"] - 2 * math.pi})
    assert np.allclose(sw2["theta3"] - sw["theta3"], 2 * math.pi, atol=1e-9)
    assert np.allclose(sw2["theta4"] - sw["theta4"], -2 * math.pi, atol=1e-9)
    assert same_angle(sw2["theta3"], sw["theta3"], 1e-9)


def test_singularity_analysis_stays_on_the_runtime_side():
    """mechgen.runtime.analysis.singular runs on the generated module with numpy: sympy is never imported."""
    import subprocess
    import sys
    code = ("import sys, mechgen; m = mechgen.load(%r); "
            "s = m.singularities(0.2, 0.3); "
            "assert [round(x, 6) for x in s] == [0.246486, 0.253514], s; "
            "assert 'sympy' not in sys.modules; print('ok')"
            % os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))),
                           "generated", "quick_return_slider.py"))
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0 and proc.stdout.strip() == "ok", proc.stderr
