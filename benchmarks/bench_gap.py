"""Where the quick-return's compiled sweep spends its time beside the hand-written closed
form (benchmarks/baselines.hand_closed_sweep), issue 24's two last targets: variants of
the committed module's sweep_fast text, side by side in one process, ns a point.

- "as emitted": generated/quick_return.py's sweep_fast;
- "no checks": the same with every one of sweep()'s tests taken out (a body's turn, the
  reach margins, the branch test, the finite test, det Φ_q's signs and rate, and a
  position sweep's evaluations of det Φ_q): what the solver's own arithmetic costs,
  safety aside (its position sweep then vouches for no point: timed all the same);
  with --each, also the module without each one of those tests in turn (what that
  test costs);
- "hand, every coordinate": the hand-written closed form filling every coordinate's
  row of Q, QD and QDD, as mechgen's sweep returns them (the hand loop above writes six
  numbers a point; a sweep of mechgen 27, plus its status);
- "two passes": the positions first (sweep_fast at level position, storing the sin and
  cos that the derivative code shares), then the derivatives of every point in a loop
  of their own (the iterations independent of each other), det Φ_q's signs checked at
  every point; compared bit for bit with "as emitted".

    python benchmarks/bench_gap.py [--points 100000] [--rounds 15] [--each]

A measurement tool, not a product path: the variants are cut from the module's text by
the emitter's own lines, and it raises where they are not found.
"""
from __future__ import annotations

import argparse
import os
import re
import sys
import textwrap
import time
import types

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)

import baselines  # noqa: E402

MODULE = os.path.join(ROOT, "generated", "quick_return.py")

# sweep()'s tests as sweep_fast prints them: (first line, last line) of each, and which
# test it belongs to (--each takes the tests out one at a time)
CHECKS = (
    ("        if k > 0 and (abs(_sw_q_", "return _sw_good\n", "a body's turn"),
    ("        if k > 0:\n            if not reach_kept", "_sw_ms = (_sw_mc - _sw_m) / abs(t - _sw_mt)\n",
     "the reach margins"),
    ("        if k > 1 or k == 1 and (_sw_all or", "return _sw_good\n", "the branch test"),
    ("        if _sw_all:\n            _sw_bad = ", " * 0.0\n        else:", "the finite test"),
    ("            _sw_bad = ", " * 0.0\n", "the finite test"),
    ("        if _sw_bad != 0.0:", "return _sw_good\n", "the finite test"),
    ("            if k > 0 and (not _sw_piv_0 * _sw_det > 0.0",
     "_sw_rate = abs(_sw_piv_0 - _sw_det) / abs(t - _sw_tk)\n", "det Φ_q's signs and rate"),
    ("        else:\n            if k < 2 or k + 1 - _sw_good >= BRANCH_DET_EVERY", "_sw_tk = t\n",
     "det Φ_q's signs and rate"),
)


def _cut(text, first, last):
    i = text.index(first)
    return text[:i] + text[text.index(last, i) + len(last):]


def _function(src, name):
    start = src.index(f"def {name}(")
    return start, src.index("\n\n\n", start) + 3


def no_checks(src, which=None):
    """The module's text with sweep_fast's tests cut out (``which``: only that one's)."""
    a, b = _function(src, "sweep_fast")
    body = src[a:b]
    for first, last, name in CHECKS:
        if which is None or name == which:
            body = _cut(body, first, last)
    return src[:a] + body + src[b:]


def two_passes(src, coordinates):
    """The module's text with sweep_fast_sc (sweep_fast storing the shared sin and cos
    into SC) and derivative_pass (the derivatives of every row of Q) added."""
    a, b = _function(src, "sweep_fast")
    body = src[a:b]
    i = body.index("        if _sw_all or k == 0 and")
    i = body.index("\n", i) + 1
    derivs = textwrap.dedent(body[i:body.index("            _sw_qd_0 = ", i)])
    before = body[body.index("    # the parameters, and the blocks"):
                  body.index("    # the loop's scratch as locals")]
    shared = sorted(set(re.findall(r"_(?:sin|cos)_\w+", derivs)) -
                    set(re.findall(r"^\s*(_(?:sin|cos)_\w+)", before, re.M)) -
                    set(re.findall(r"(_(?:sin|cos)_\w+), _(?:sin|cos)_\w+ = ", before)))
    store = "".join(f"        SC[k, {j}] = {name}\n" for j, name in enumerate(shared))
    sc = body.replace("def sweep_fast(ts, q0, p, tol, xtol, maxit, Q, QD, QDD, STATUS):",
                      "def sweep_fast_sc(ts, q0, p, tol, xtol, maxit, Q, QD, QDD, STATUS, SC):")
    sc = sc.replace("        Q[k, 0] = ", store + "        Q[k, 0] = ", 1)
    load = "".join(f"        {c} = Q[k, {j}]\n" for j, c in enumerate(coordinates))
    load += "".join(f"        {name} = SC[k, {j}]\n" for j, name in enumerate(shared))
    rows = "".join(f"        QD[k, {j}] = {c}d\n        QDD[k, {j}] = {c}dd\n"
                   for j, c in enumerate(coordinates))
    derivs = derivs.replace("return _sw_good", "return k").replace("_sw_piv_", "_piv_")
    deriv = ("@njit(cache=False)\n"
             "def derivative_pass(ts, q0, p, Q, SC, QD, QDD):\n"
             "    q = q0.copy()\n" + before +
             "    _det, _sig = 0.0, 0.0\n"
             "    for k in range(ts.shape[0]):\n"
             "        t = ts[k]\n        T = t\n" + load +
             textwrap.indent(derivs, " " * 8) +
             "        if k > 0 and (not _piv_0 * _det > 0.0 or _piv_1 != _sig):\n"
             "            return k\n"
             "        _det, _sig = _piv_0, _piv_1\n" + rows +
             "    return ts.shape[0]\n\n\n")
    return src[:b] + "@njit(cache=False)\n" + sc + deriv + src[b:]


def load(name, text):
    mod = types.ModuleType(name)
    sys.modules[name] = mod
    exec(compile(text.replace("cache=True", "cache=False"), name, "exec"), mod.__dict__)
    return mod


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--points", type=int, default=100_000)
    ap.add_argument("--rounds", type=int, default=15)
    ap.add_argument("--each", action="store_true",
                    help="also each test's own cost: the module without that one test")
    args = ap.parse_args()
    with open(MODULE, encoding="utf-8") as fh:
        src = fh.read()
    emitted = load("gap_emitted", src)
    coords = list(emitted.COORDINATES)
    bare = load("gap_no_checks", no_checks(src))
    split = load("gap_two_passes", two_passes(src, coords))

    N, n = args.points, emitted.N_COORDS
    ts = np.linspace(0.0, 1.0, N, endpoint=False)
    p, q0 = np.array(emitted.PARAMETER_DEFAULTS), np.array(emitted.GUESS)
    none = np.zeros((0, n))
    A = {k: np.zeros((N, n)) for k in ("Q", "QD", "QDD", "Q2", "QD2", "QDD2", "Q3", "QD3",
                                        "QDD3")}
    S = np.zeros((N, 3), dtype=np.int16)
    SC = np.zeros((N, 8))
    H = np.zeros((N, 6))

    def fast(m, full):
        return lambda: m.sweep_fast(ts, q0, p, 1e-10, 1e-10, 50, A["Q"],
                                    A["QD"] if full else none, A["QDD"] if full else none, S)

    def both():
        done = split.sweep_fast_sc(ts, q0, p, 1e-10, 1e-10, 50, A["Q2"], none, none, S, SC)
        return min(done, split.derivative_pass(ts, q0, p, A["Q2"], SC, A["QD2"], A["QDD2"]))

    cases = {
        "hand-written closed form, all levels": lambda: baselines.hand_closed_sweep(ts, 2, H),
        "hand-written closed form, positions": lambda: baselines.hand_closed_sweep(ts, 0, H),
        "hand, every coordinate, all levels":
            lambda: baselines.hand_closed_sweep_full(ts, 2, A["Q3"], A["QD3"], A["QDD3"]),
        "hand, every coordinate, positions":
            lambda: baselines.hand_closed_sweep_full(ts, 0, A["Q3"], none, none),
        "as emitted, all levels": fast(emitted, True),
        "as emitted, positions": fast(emitted, False),
        "no checks, all levels": fast(bare, True),
        "no checks, positions": fast(bare, False),
        "two passes, all levels": both,
    }
    if args.each:
        for name in dict.fromkeys(c[2] for c in CHECKS):
            m = load("gap_without_" + str(len(cases)), no_checks(src, name))
            cases[f"without {name}, all levels"] = fast(m, True)
            cases[f"without {name}, positions"] = fast(m, False)
    for f in cases.values():
        f()
    assert fast(emitted, True)() == N and both() == N
    same = all(np.array_equal(A[k], A[k + "2"]) for k in ("Q", "QD", "QDD"))
    baselines.hand_closed_sweep_full(ts, 2, A["Q3"], A["QD3"], A["QDD3"])
    full_err = max(float(np.max(np.abs(A[k] - A[k + "3"]) / (1.0 + np.abs(A[k]))))
                   for k in ("Q", "QD", "QDD"))
    best = {name: float("inf") for name in cases}
    for _ in range(args.rounds):
        for name, f in cases.items():
            t0 = time.perf_counter()
            f()
            best[name] = min(best[name], (time.perf_counter() - t0) / N * 1e9)
    hand = best["hand-written closed form, all levels"]
    print(f"quick-return, {N} points, best of {args.rounds} interleaved rounds, ns a point")
    for name, ns in best.items():
        print(f"  {name:48s} {ns:7.1f}   {ns / hand:5.2f} × the hand-written all levels")
    print(f"  as emitted, positions / all levels: "
          f"{best['as emitted, positions'] / best['as emitted, all levels']:.3f}")
    print(f"  two passes against as emitted: the same bits: {same}")
    print(f"  hand, every coordinate against as emitted: largest relative difference "
          f"{full_err:.1e}")


if __name__ == "__main__":
    main()
