"""The written fast sweep's scratch as locals (mechgen.compiler.solver.scratch): the pass
on its own, on lines written here, and on the committed quick-return."""
import os
import re

from mechgen.compiler.solver.scratch import LOOP, scalar_scratch, scratch_names

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

LINES = [
    "q = q0.copy()",
    "qd = np.zeros(N_COORDS)",
    "qdd = np.zeros(N_COORDS)",
    "piv = np.zeros(2)",
    "info = np.zeros(POSITION_INFO_SIZE)",
    "_sw_qp = q0.copy()",
    LOOP,
    "    t = ts[k]",
    "    _sw_qp[1] = q[1] + 0.5 * qd[1]",
    "    q[1] = math.sin(t)  # q[0] in a comment stays",
    "    qd[1] = math.cos(t)",
    "    qdd[1] = -q[1]",
    "    info[0] = 3",
    "    piv[0] = qd[1]",
    "    if k == 0:",
    "        _sw_ms = reach_slope(q, qd, t, ts[1] - t, p, 1.0)",
    "    Q[k, 1] = q[1]",
    "    STATUS[k, 1] = min(info[INFO_ITERATIONS], 9)",
    "if not jacobian_det(q, ts[ts.shape[0] - 1], p, piv) * 1.0 > 0.0 or piv[1] != 0.0:",
    "    return 0",
    "return ts.shape[0]",
]


def _run(lines, n=2):
    """Execute the body as a function of plain Python (no numba), with stub calls."""
    import math

    import numpy as np
    seen = {}

    def reach_slope(q, qd, t, h, p, m):
        seen["slope"] = (q.copy(), qd.copy())
        return 0.0

    def jacobian_det(q, t, p, piv):
        seen["det"] = q.copy()
        piv[0], piv[1] = 1.0, 0.0
        return 1.0
    src = "def f(ts, q0, p, Q, STATUS):\n" + "\n".join("    " + x for x in lines)
    env = dict(np=np, math=math, N_COORDS=n, POSITION_INFO_SIZE=4, INFO_ITERATIONS=0,
               reach_slope=reach_slope, jacobian_det=jacobian_det)
    exec(src, env)
    ts = np.linspace(0.0, 1.0, 5)
    Q, S = np.zeros((5, n)), np.zeros((5, 2))
    r = env["f"](ts, np.array([0.5, 0.25]), None, Q, S)
    return r, Q, S, seen


def test_the_slots_become_locals_and_the_numbers_stay():
    out = scalar_scratch(list(LINES), 2)
    loop = out[out.index(LOOP) + 1:]
    loop = loop[:next(i for i, x in enumerate(loop) if x and not x.startswith(" "))]
    code = [x.split("#")[0] for x in loop]
    # no slot of a scratch array in the loop but the filling of q and qd before the call
    slots = [x for x in code if re.search(r"(?<![\w.])(q|qd|qdd|piv|info|_sw_qp)\[", x)]
    assert all(re.match(r"^\s+(q|qd)\[0\], (q|qd)\[1\] = ", x) for x in slots), slots
    assert "    q[1] = math.sin(t)  # q[0] in a comment stays" not in out
    assert any(x.endswith("# q[0] in a comment stays") for x in out)
    # the arrays no line names any more are not made
    assert "_sw_qp = q0.copy()" not in out and "info = np.zeros(POSITION_INFO_SIZE)" not in out
    assert "qdd = np.zeros(N_COORDS)" not in out and "qd = np.zeros(N_COORDS)" in out
    before, after = _run(LINES), _run(out)
    assert before[0] == after[0]
    assert (before[1] == after[1]).all() and (before[2] == after[2]).all()
    for key in ("slope", "det"):        # the calls see the same arrays
        a, b = before[3][key], after[3][key]
        a, b = (a if isinstance(a, tuple) else (a,)), (b if isinstance(b, tuple) else (b,))
        assert all((x == y).all() for x, y in zip(a, b))


def test_a_loop_handing_an_array_to_another_call_is_left_as_it_was():
    lines = list(LINES)
    lines.insert(lines.index(LOOP) + 2, "    solve(q, t)")
    assert scalar_scratch(list(lines), 2) == lines
    assert scalar_scratch(["x = 1"], 2) == ["x = 1"]        # no loop


def test_a_det_call_in_the_loop_keeps_piv_an_array():
    lines = list(LINES)
    at = lines.index("    piv[0] = qd[1]")
    lines[at:at + 1] = ["    _sw_d = jacobian_det(q, t, p, piv)", "    x = piv[1] + piv[0]"]
    out = scalar_scratch(list(lines), 2)
    assert "    x = piv[1] + piv[0]" in out
    i = out.index("    _sw_d = jacobian_det(q, t, p, piv)")
    assert out[i - 1] == "    q[0], q[1] = _sw_q_0, _sw_q_1"        # q filled before it


def test_the_committed_quick_return_sweeps_on_locals():
    with open(os.path.join(ROOT, "generated", "quick_return.py"), encoding="utf-8") as fh:
        text = fh.read()
    body = text[text.index("def sweep_fast("):text.index("\n\n\n", text.index("def sweep_fast("))]
    loop = body[body.index("    for k in range(ts.shape[0]):"):]
    loop = loop[:loop.index("\n    if _sw_good < ts.shape[0]:")]
    assert not re.search(r"(?<![\w.])(qdd|piv|info|_sw_qp|_sw_q1|_sw_q2)\[", loop)
    assert re.search(r"^\s+_sw_q_5 = Th3$", loop, re.M)
    # the names the pass writes are the module's own: no model name may take one
    assert {"_sw_q_0", "_sw_qdd_8", "_sw_piv_2", "_sw_its"} <= set(scratch_names(9).split())
