"""Mech's 2D library beyond the first eleven kinds: gears, gear_ratio, rack_and_pinion,
rack_ratio, point_on_lines, origin_lock, directed_distance, gen_revolute, gen_translate
and the complex loop form.

For every kind: Φ_q, ν, γ against Φ by the chain rule (sympy) and against finite
differences of solved trajectories (lambdified, solved here by Newton); the generated
module's phi, phi_q, nu, gamma and points against lambdify at random points (in a
subprocess without numba's JIT, as tests/test_codegen_numbers.py does); and the worked
examples against closed forms: exact gear ratios, s = r θ, the GenRevolute-driven
four-bar against the rotation_lock-driven one, a slider crank's travel, and seed 000's
printed solutions from the loop form.
"""
import json
import math
import os
import subprocess
import sys

import numpy as np
import pytest
import sympy as sp

from conftest import example_model
from fd_helpers import STENCIL, H, check_fd, newton, numeric
from test_equations_derivatives import chain_rule

from mechgen import I, Line, Model, ModelError, T, exp

# (example file, model, times to check the derivatives at)
MODELS = [("gear_train", None, (0.1, 0.37)), ("internal_gear", "internal_gear", (0.2,)),
          ("internal_gear", "planetary", (0.15, 0.6)), ("rack_pinion", "rack_pinion", (0.3,)),
          ("rack_pinion", "rolling_pinion", (0.3,)), ("fourbar_joints", "fourbar_gen", (0.1, 0.4)),
          ("fourbar_joints", "slider_crank_gen", (0.2,)), ("yoke", None, (0.1, 0.7)),
          ("fourbar_loop", None, (0.0,))]
IDS = [f"{f}:{m}" if m else f for f, m, _ in MODELS]


def zero(matrix):
    """Every entry 0 (expanded, or simplified where expanding leaves sin/cos of sums)."""
    return all(e == 0 or sp.simplify(e) == 0 for e in matrix.applyfunc(sp.expand))


def kinds_of(model):
    return {c.kind for c in model.constraints}


def test_every_new_kind_is_exercised():
    kinds = set()
    for f, name, _ in MODELS:
        kinds |= kinds_of(example_model(f, name))
    assert {"gears", "gear_ratio", "rack_and_pinion", "rack_ratio", "point_on_lines",
            "origin_lock", "directed_distance", "gen_revolute", "gen_translate",
            "loop"} <= kinds


@pytest.mark.parametrize("spec", MODELS, ids=IDS)
def test_derivatives_by_the_chain_rule_and_finite_differences(spec):
    f, name, times = spec
    model = example_model(f, name)
    eq = model.equations()
    assert zero(eq.phi_q - eq.phi.jacobian(eq.q))
    assert eq.nu == -eq.phi.diff(eq.T)
    d1, d2 = chain_rule(eq)
    assert zero(d1 - (eq.phi_q * eq.qd - eq.nu))
    assert zero(d2 - (eq.phi_q * eq.qdd - eq.gamma))
    params = dict(model.param_defaults)
    if f == "fourbar_loop":
        params["omega"] = 2 * math.pi
    call = numeric(eq, params)
    q = np.array(model.guess_vector())
    for t in times:
        Q = []
        for k in STENCIL:
            q = newton(call, q, t + k * H)
            Q.append(q)
        check_fd(call, t, Q)
        q = Q[2]


def test_the_gear_row_is_the_rolling_relation():
    """The rolling row equals (r1 + r2) (ψ − β) wrapped to (−π, π], β = atan2 of the centre
    line: zero exactly where r1 (Th1 − β) + r2 (Th2 − β) = c (mod 2π (r1 + r2)), never
    half a turn of phase away (tests/test_gear_phase.py)."""
    model = example_model("gear_train")
    con = next(c for c in model.constraints if c.kind == "gears")
    dist, roll = con.exprs
    eq = model.equations()
    x3, y3, th3, x4, y4, th4 = sp.symbols("X3 Y3 Th3 X4 Y4 Th4", real=True)
    rng = np.random.default_rng(1)
    subs = {sp.Symbol(k, real=True): v for k, v in model.param_defaults.items()}
    rC, rD = subs[sp.Symbol("rC", real=True)], subs[sp.Symbol("rD", real=True)]
    for _ in range(5):
        v = dict(zip((x3, y3, th3, x4, y4, th4), rng.uniform(-3, 3, 6)))
        ux, uy = v[x4] - v[x3], v[y4] - v[y3]
        beta = math.atan2(uy, ux)
        psi = (rC * v[th3] + rD * v[th4]) / (rC + rD)
        got = float(roll.subs(subs).subs(v))
        assert abs(got - (rC + rD) * math.remainder(psi - beta, 2 * math.pi)) < 1e-12
        assert abs(float(dist.subs(subs).subs(v)) - (ux ** 2 + uy ** 2 - (rC + rD) ** 2)) < 1e-12
    assert len(eq.phi) == 9


def test_the_rack_rows_are_the_signed_distance_and_the_travel():
    model = example_model("rack_pinion", "rolling_pinion")
    offset, rolling = model.constraints[0].exprs
    X2, Y2, Th2 = sp.symbols("X2 Y2 Th2", real=True)
    r, c = sp.symbols("r c", real=True)
    assert sp.simplify(offset - (Y2 - r)) == 0          # centre r above the rack (its left)
    assert sp.simplify(rolling - (X2 + 4 + r * Th2 - (c + 4))) == 0


def test_loop_rows_are_the_real_and_imaginary_parts():
    m = Model("loops")
    a = m.param("a", 1.0)
    x = m.coordinate("x", 0.1)
    y = m.coordinate("y", 0.2)
    one = m.loop(a * exp(I * x) + 2 * exp(I * (y + T)) - 3)
    two = m.loop(exp(I * x) * (1 + I) - y, name="second")
    eq = m.equations()
    assert eq.labels == ("1 loop 1 re", "1 loop 1 im", "2 second: loop 2 re",
                         "2 second: loop 2 im")
    z = a * exp(I * x) + 2 * exp(I * (y + T)) - 3
    for row, want in zip(one.exprs, (sp.re(z), sp.im(z))):
        assert sp.simplify(sp.expand_complex(row - want)) == 0
    assert sp.simplify(two.exprs[0] - (sp.cos(x) - sp.sin(x) - y)) == 0
    assert sp.simplify(two.exprs[1] - (sp.cos(x) + sp.sin(x))) == 0


# -- bad input ------------------------------------------------------------------------------
def parts():
    m = Model("bad")
    base = m.ground("base", points=[(0, 0), (1, 0)])
    g = m.body("g", points=[(0, 0), (1, 0)])
    h = m.body("h", points=[(0, 0), (1, 0)])
    return m, base, g, h


@pytest.mark.parametrize("call, words", [
    (lambda m, b, g, h: m.gears(g[1], 0, h[1], 1), "radius r1 is 0"),
    (lambda m, b, g, h: m.gears(g[1], 1, g[2], 1), "two bodies"),
    (lambda m, b, g, h: m.gear_ratio(g[1], 2, h[1], -2), "r1 + r2 = 0"),
    (lambda m, b, g, h: m.gears(g[1], T, h[1], 1), "may not depend on T"),
    (lambda m, b, g, h: m.rack_and_pinion(g[1], 1, g.line(1, 2)), "same body"),
    (lambda m, b, g, h: m.rack_ratio(g[1], 1, Line(b[1], h[1])), "fixed in one body"),
    (lambda m, b, g, h: m.gen_revolute(Line(b[1], h[1]), g.line(1, 2), "phi"),
     "fixed in one body"),
    (lambda m, b, g, h: m.gen_translate(g.line(1, 2), g.line(2, 1), "s"), "two bodies"),
    (lambda m, b, g, h: m.gen_revolute(b.line(1, 2), g.line(1, 2), g.th), "body's coordinate"),
    (lambda m, b, g, h: m.loop(g.x + 2), "holds no coordinate; a loop is a complex"),
    (lambda m, b, g, h: m.origin_lock(g, g), "locked to itself"),
    (lambda m, b, g, h: m.directed_distance(g[1], h[1], (0, 0)), "has no direction"),
])
def test_bad_input_is_refused_by_name(call, words):
    m, b, g, h = parts()
    with pytest.raises(ModelError) as info:
        call(m, b, g, h)
    assert words in str(info.value)
    assert not m.constraints


def test_a_refused_joint_leaves_no_coordinate_behind():
    m, b, g, h = parts()
    with pytest.raises(ModelError):
        m.gen_revolute(Line(b[1], h[1]), g.line(1, 2), "phi", guess=0.3)
    assert [c.name for c in m.coords] == ["X2", "Y2", "Th2", "X3", "Y3", "Th3"]
    joint = m.gen_revolute(b.line(1, 2), g.line(1, 2), "phi", guess=0.3)   # the name is free
    assert str(joint.coordinate) == "phi" and m.guess[joint.coordinate] == 0.3


# -- the generated modules, without numba's JIT ----------------------------------------------
_SCRIPT = r"""
import json, math, os, sys
sys.path.insert(0, {tests!r})
import numba
assert numba.config.DISABLE_JIT
import numpy as np
import mechgen
from mechgen.compiler.build import build
from mechgen.compiler.functions.equations_code import point_list
from conftest import example_model, GENERATED
import test_codegen_numbers as C
import sympy as sp

out = {outdir!r}
report = {{}}
mechs = {{}}
for f, name in {models!r}:
    model = example_model(f, name)
    ref = C.Reference(model)
    mech = mechgen.load(build(model, out))
    mechs[model.name] = mech
    rng = np.random.default_rng(3)
    errors = {{}}
    mod = mech.module
    pts = sp.lambdify(ref.args, sp.Matrix([[pt.r[0], pt.r[1]] for _, _, pt in point_list(model)]))
    for _ in range(4):
        q, qd, qdd, t, p = C.random_state(mech, rng)
        for key, args in (("phi", (q, t, p)), ("phi_q", (q, t, p)), ("nu", (q, t, p)),
                          ("gamma", (q, qd, t, p))):
            shape = (mech.m, mech.n) if key == "phi_q" else (mech.m,)
            got = np.full(shape, np.nan)
            getattr(mod, key)(*args, got)
            errors[key] = max(errors.get(key, 0.0), C.assert_close(got, ref(key, q, qd, qdd, t, p), key))
        P = np.full((len(mod.POINTS), 2), np.nan)
        mod.points(q, t, p, P)
        want = np.array(pts(*q, *qd, *qdd, t, *p), dtype=float)
        errors["points"] = max(errors.get("points", 0.0), C.assert_close(P, want, "points"))
    report[model.name] = errors

ts = np.linspace(0.0, 1.0, 21)
closed = {{}}

def sweep(name, **params):
    return mechs[name].with_params(**params).sweep(0.0, 1.0, 21, level="acceleration")

def worst(a, b):
    return float(np.max(np.abs(np.asarray(a) - np.asarray(b))))

w = 2 * math.pi
sw = sweep("gear_train")
i_bc, i_d = 1.0 / 3.0, 1.0 * 1.5 / (3.0 * 2.5)
closed["gear_train"] = max(worst(sw["Th3"], -i_bc * w * ts), worst(sw["Th3d"], -i_bc * w),
                           worst(sw["Th4"], i_d * w * ts), worst(sw["Th4d"], i_d * w),
                           worst(sw["Th4dd"], 0.0), worst(sw["X4"], 4 + 1.5 + 2.5))
sw = sweep("internal_gear")
closed["internal_gear"] = max(worst(sw["Th2"], w * ts / 2.5), worst(sw["Th2d"], w / 2.5),
                              worst(sw["Th2dd"], 0.0))
sw = sweep("planetary")
rs, rq = 1.0, 0.75
arm = w * rs / (rs + rs + 2 * rq)
planet = arm - (rs / rq) * (w - arm)
closed["planetary"] = max(worst(sw["Th3"], arm * ts), worst(sw["Th4"], planet * ts),
                          worst(sw["Th4d"], planet), worst(sw["Th4dd"], 0.0))
sw = sweep("rack_pinion")
r, om = 0.8, math.pi
closed["rack_pinion"] = max(worst(sw["X3"], r * om * ts), worst(sw["X3d"], r * om),
                            worst(sw["X3dd"], 0.0), worst(sw["Y3"], 0.0))
sw = sweep("rolling_pinion")
closed["rolling_pinion"] = max(worst(sw["X2"], 1.0 - r * om * ts), worst(sw["Y2"], r),
                               worst(sw["X2d"], -r * om))
# the GenRevolute four-bar against the committed rotation_lock one
gen = sweep("fourbar_gen")
ref = mechgen.load(os.path.join(GENERATED, "fourbar.py")).sweep(0.0, 1.0, 21, level="acceleration")
e = 0.0
for c in mechs["fourbar_gen"].coordinates:
    if c == "phi":
        continue
    for s in ("", "d", "dd"):
        e = max(e, worst(gen[c + s], ref[c + s]))
e = max(e, worst(gen["phi"], math.pi / 3 + w * ts), worst(gen["phid"], w))
closed["fourbar_gen"] = e
sw = sweep("slider_crank_gen")
th = sp.Symbol("th")
x = sp.cos(th) + sp.sqrt(9 - sp.sin(th) ** 2)
f0, f1, f2 = (sp.lambdify(th, g) for g in (x, x.diff(th), x.diff(th, 2)))
ang = 0.3 + w * ts
closed["slider_crank_gen"] = max(worst(sw["travel"], f0(ang)), worst(sw["travel"], sw["X4"]),
                                 worst(sw["traveld"], f1(ang) * w),
                                 worst(sw["traveldd"], f2(ang) * w * w))
sw = sweep("yoke")
closed["yoke"] = max(worst(sw["Y3"], 2 * np.tan(math.pi / 4 * ts)),
                     worst(sw["Th4"], np.arcsin(0.5 * np.sin(2 * math.pi * ts))),
                     worst(sw["X4"], 2.0), worst(sw["Y4"], sw["Y3"]))
seed = []
for th3, th4 in ((0.5274103891, 1.792465604), (-1.048246730, -2.313301945)):
    s = mechs["fourbar_loop"].solve(0.0, guess={{"theta3": th3 + 0.1, "theta4": th4 - 0.1}})
    seed.append(max(abs(s["theta3"] - th3), abs(s["theta4"] - th4)))
closed["fourbar_loop"] = max(seed)

import matplotlib
matplotlib.use("Agg")
from matplotlib.collections import LineCollection
from matplotlib.patches import Circle
from mechgen import plot
pictures = {{}}
for name, mech in mechs.items():
    if name == "fourbar_loop":
        continue
    s0, s1 = mech.solve(0.1), mech.solve(0.35)
    d = plot.draw(mech, s0, labels=False)
    d.ax.figure.savefig(os.path.join(out, name + ".png"), dpi=50)
    info = {{"circles": {{}}, "turned": 0.0, "ticks": 0}}
    for body, arts in d.artists.items():
        for a in arts:
            if isinstance(a, Circle) and a.get_radius() > 0.3:
                info["circles"].setdefault(body, []).append(round(a.get_radius(), 9))
            if isinstance(a, LineCollection) and body in d.transforms and a.get_zorder() in (1.9, 2.7):
                info["ticks"] += len(a.get_segments())
    # ticks turn with their body: the first tick of every gear body, before and after
    before = {{b: d.transforms[b].get_matrix().copy() for b in d.transforms}}
    d.set_state(s1.points(), s1.q, s1.t)
    for b, m0 in before.items():
        m1 = d.transforms[b].get_matrix()
        k = mech.coordinates.index(f"Th{{[x.number for x in d.structure.bodies if x.name == b][0]}}")
        turn = math.atan2(m1[1, 0], m1[0, 0]) - math.atan2(m0[1, 0], m0[0, 0])
        want = s1.q[k] - s0.q[k]
        info["turned"] = max(info["turned"], abs(math.remainder(turn - want, 2 * math.pi)))
    pictures[name] = info
print(json.dumps({{"functions": report, "closed": closed, "pictures": pictures}}))
"""


@pytest.fixture(scope="module")
def jitless(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("mech2d")
    script = tmp / "run.py"
    models = [(f, m) for f, m, _ in MODELS]
    script.write_text(_SCRIPT.format(tests=os.path.dirname(__file__), outdir=str(tmp / "out"),
                                     models=models))
    env = dict(os.environ, NUMBA_DISABLE_JIT="1")
    proc = subprocess.run([sys.executable, str(script)], capture_output=True, text=True,
                          env=env, timeout=600)
    assert proc.returncode == 0, proc.stderr[-3000:]
    return json.loads(proc.stdout.strip().splitlines()[-1])


def test_generated_functions_agree_with_lambdify(jitless):
    report = jitless["functions"]
    assert len(report) == len(MODELS)
    for name, errors in report.items():
        assert set(errors) == {"phi", "phi_q", "nu", "gamma", "points"}, name
        assert max(errors.values()) < 1e-10, (name, errors)


@pytest.mark.parametrize("name, tol", [
    ("gear_train", 1e-12), ("internal_gear", 1e-12), ("planetary", 1e-12),
    ("rack_pinion", 1e-12), ("rolling_pinion", 1e-12), ("fourbar_gen", 1e-10),
    ("slider_crank_gen", 1e-12), ("yoke", 1e-12),
    ("fourbar_loop", 1e-9)])          # the seed prints 10 digits
def test_worked_examples_against_closed_forms(jitless, name, tol):
    assert jitless["closed"][name] < tol, jitless["closed"]


def test_pictures_show_pitch_circles_that_turn_with_their_gears(jitless):
    pics = jitless["pictures"]
    assert set(pics) == {"gear_train", "internal_gear", "planetary", "rack_pinion",
                         "rolling_pinion", "fourbar_gen", "slider_crank_gen", "yoke"}
    c = pics["gear_train"]["circles"]
    assert sorted(c["A"]) == [1.0] and sorted(c["BC"]) == [1.5, 3.0] and c["D"] == [2.5]
    ring = pics["internal_gear"]["circles"]["ring"]
    assert 2.5 in ring and len(ring) == 2                   # pitch circle and rim
    assert sorted(pics["planetary"]["circles"]["frame"])[0] == 2.5   # the fixed ring
    assert pics["rack_pinion"]["circles"]["pinion"] == [0.8]
    for name in ("gear_train", "internal_gear", "planetary", "rack_pinion", "rolling_pinion"):
        assert pics[name]["ticks"] >= 18, name          # a pitch circle's ticks at least
    for name, info in pics.items():
        assert info["turned"] < 1e-9, name


@pytest.mark.parametrize("spec", MODELS, ids=IDS)
def test_equations_print_as_text_and_latex(spec):
    from mechgen.model.printing import equations_text
    model = example_model(spec[0], spec[1])
    text = equations_text(model)
    latex = equations_text(model, latex=True)
    assert latex.count(r"\begin{align*}") == latex.count(r"\end{align*}") == 4
    for con in model.constraints:
        for _, label in con.rows():
            assert f"# {label}" in text
            from mechgen.model.printing import _latex_text
            assert rf"\text{{{_latex_text(label)}}}" in latex
