"""Blocks that stay the same at every point of a sweep (mechgen.compiler.solver.plan: steady):
they lead the solving order, and the fast sweep solves them once, before its loop
(position.position_in_sweep), with the parameters loaded there. The numbers are those of
the point-by-point solver: a sweep_fast of the quick-return, its slider's angle solved
before the loop in closed form, and again with Newton blocks (closed_forms="none"),
equals solve_point_sorted at every point, from either guess of that angle; a steady
block that keeps a reach margin (a signed closed form) stays in the loop."""
import math

import numpy as np
import pytest

import mechgen
from mechgen import Model, T, pi
from mechgen.compiler.build import build
from mechgen.compiler.solver.plan import make_plan
from mechgen.protocol import OK, POINT_INFO_SIZE


def quick_return(brace=None):
    """The seed's quick-return; with ``brace``, a body pinned to the ground whose far end
    keeps a distance from a ground point ("distance": a steady Newton block, its sin and
    cos turned by each step) or lies on a ground line ("line": a steady closed form whose
    root a sign picks, which keeps a reach margin)."""
    m = Model("quick_return_steady" + (f"_{brace}" if brace else ""))
    longitud = m.param("longitud", 3.0)
    velocidad = m.param("velocidad", 2 * pi)
    base = m.ground("base", points=[(0, 0), (0, 5), (-5, 10), (12, 10)])
    manivela = m.body("manivela", points=[(0, 0), (longitud, 0)], guess=(0, 5, 0))
    colisa = m.body("colisa", points=[(0, 0), (0, 9)], guess=(0, 0, -0.5))
    deslizadera = m.body("deslizadera", points=[(0, 0), (2, 0)], guess=(6, 10, 0))
    m.revolute(base[2], manivela[1])
    m.rotation_lock(manivela, base, velocidad * T, name="crank driver")
    m.revolute(base[1], colisa[1])
    m.point_on_line(manivela[2], colisa.line(1, 2))
    m.relative_distance(colisa[2], deslizadera[1], 5)
    m.translate(base.line(3, 4), deslizadera.line(1, 2))
    if brace:
        brazo = m.param("brazo", 4.0)      # a length that a design table may vary
        tirante = m.body("tirante", points=[(0, 0), (brazo, 0)], guess=(0, 5, 0.3))
        m.revolute(base[2], tirante[1])
        if brace == "distance":
            m.relative_distance(tirante[2], base[4], 11)
        else:
            m.point_on_line(tirante[2], base.line(1, 4))
    return m


def loop_text(module_path):
    """sweep_fast's text: (before its loop, the loop)."""
    text = open(module_path).read()
    body = text[text.index("def sweep_fast("):]
    body = body[:body.index("\n    return ts.shape[0]")]
    cut = body.index("    for k in range(ts.shape[0]):")
    return body[:cut], body[cut:]


@pytest.fixture(scope="module")
def built(tmp_path_factory):
    """{name: (path, Mechanism in plain Python)}: closed forms, Newton, with a brace."""
    out = tmp_path_factory.mktemp("steady")
    made = {}
    for name, model, kw in (("closed", quick_return(), {}),
                            ("newton", quick_return(), {"closed_forms": "none"}),
                            ("distance", quick_return("distance"), {}),
                            ("line", quick_return("line"), {})):
        path = build(model, str(out / name), **kw)
        made[name] = path, mechgen.load(path, tier="python")
    return made


def test_steady_blocks_lead_a_solving_order():
    model = quick_return("distance")
    eq = model.equations()
    plan = make_plan(model, eq)
    q = list(eq.q)
    names = [[str(q[v]) for v in b.vars] for b in plan.blocks]
    steady = {n for b in names[:plan.steady] for n in b}
    assert {"Th4", "Th5", "X2", "Y3"} <= steady
    assert not steady & {"Th2", "Th3", "X4", "Y4"}
    solved = set(eq.params)
    for b in plan.blocks:            # every block reads only what blocks before it solved
        own = {q[v] for v in b.vars}
        syms = set().union(*(eq.phi[e].free_symbols for e in b.rows)) - {T}
        assert syms <= solved | own, [str(q[v]) for v in b.vars]
        solved |= own
    for b in plan.blocks[:plan.steady]:
        assert all(T not in eq.phi[e].free_symbols for e in b.rows)


@pytest.mark.parametrize("name", ["closed", "newton", "distance"])
def test_the_slider_angle_is_solved_before_the_loop(built, name):
    before, loop = loop_text(built[name][0])
    solve = "Th4 -= _s0" if name == "newton" else "the root nearest Th4"
    assert solve in before and solve not in loop
    if name == "distance":   # the brace's Newton, its sin and cos called (not turned)
        assert "Th5 -= _s0" in before and "Th5 -= _s0" not in loop
        assert "_sw_warm = False" in before
    assert "longitud = p[0]" in before and "= p[" not in loop
    assert "# block: Th3 from" in loop and "# block: Th3 from" not in before


def test_a_steady_block_that_keeps_a_margin_stays_in_the_loop(built):
    before, loop = loop_text(built["line"][0])
    assert "a sin(Th5) + b cos(Th5) + c = 0" in loop
    assert "Th5" not in before.split("longitud = p[0]")[1]
    assert "_sg_Th5" in loop


@pytest.mark.parametrize("name", ["closed", "newton", "distance", "line"])
@pytest.mark.parametrize("flip", [False, True])
def test_sweep_fast_equals_the_point_solver(built, name, flip):
    """Every point of sweep_fast, at both levels, against solve_point_sorted from the
    sweep's own point before it; the slider's angle from its guess (0, or π: the slider
    turned over), the same at every point."""
    mod = built[name][1].module
    n, N = mod.N_COORDS, 400
    p = np.array(mod.PARAMETER_DEFAULTS, dtype=float)
    q0 = np.array(mod.GUESS, dtype=float)
    j = list(mod.COORDINATES).index("Th4")
    if flip:
        q0[j] = math.pi - 0.2
    ts = np.linspace(0.0, 1.0, N)
    for full in (True, False):
        Q, QD, QDD = np.zeros((N, n)), np.zeros((N, n)), np.zeros((N, n))
        S = np.zeros((N, 3), dtype=np.int16)
        rows = (QD, QDD) if full else (np.zeros((0, n)), np.zeros((0, n)))
        done = mod.sweep_fast(ts, q0, p, 1e-12, 1e-12, 50, Q, *rows, S)
        assert done == N
        assert np.all(S[:, 0] == OK)
        assert np.all(Q[:, j] == (math.pi if flip else 0.0))
        for k in range(0, N, 7):
            q = (q0 if k == 0 else Q[k - 1]).copy()
            info = np.zeros(POINT_INFO_SIZE)
            assert mod.solve_point_sorted(q, ts[k], p, 1e-12, 1e-12, 50, info) == OK
            assert np.allclose(Q[k], q, rtol=0, atol=1e-12), (name, k)
        if full:
            qd, qdd = np.zeros(n), np.zeros(n)
            assert mod.solve_derivatives_sorted(Q[N // 3], ts[N // 3], p, qd, qdd) == OK
            assert np.allclose(QD[N // 3], qd, atol=1e-10)
            assert np.allclose(QDD[N // 3], qdd, atol=1e-9)
