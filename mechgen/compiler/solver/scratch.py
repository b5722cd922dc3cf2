"""A written-out fast sweep's scratch as locals: the loop's slots of q, qd and qdd (the
last point and the prediction), of the predictor's history (_sw_qp, _sw_q1, _sw_q2), of
det Φ_q and its sign pattern (piv) and the iteration count (info), renamed to plain
locals (``q[5]`` -> ``_sw_q_5``).

Why: numba's arrays carry no aliasing information, so LLVM must assume that every store
into the caller's Q, QD, QDD may write over the scratch arrays, and stores and reloads
each slot at every point; locals live in registers. benchmarks/bench_scratch.py builds a
model with and without this pass (10^5 points, every array bit for bit the same): the
quick-return's position sweep 44.5 -> 42.0 ns a point, the Strandbeest leg's full sweep
138 -> 132 ns (2 to 6 % on every written sweep, forces included).

A text pass over the rendered lines, applied only where the solvers are written out in
the loop (sweep.written_step) and the loop hands no scratch array to a call but
``reach_slope(q, qd, ...)`` at its first point and a position sweep's
``jacobian_det(q, t, p, piv)`` (piv then stays an array): q and qd are filled from the
locals before those calls and before the ``jacobian_det(q, ...)`` after the loop.
Anything else leaves the lines as they were.
"""
from __future__ import annotations

import re

LOOP = "for k in range(ts.shape[0]):"
_SLOT = re.compile(r"(?<![\w.])(q|qd|qdd|_sw_qp|_sw_q1|_sw_q2|piv)\[(\d+)\]")
_ITERATIONS = re.compile(r"(?<![\w.])info\[(?:0|INFO_ITERATIONS)\]")
# a scratch array named whole (not one of its slots): handed to a call
_WHOLE = re.compile(r"(?<![\w.])(q|qd|qdd|_sw_qp|_sw_q1|_sw_q2|piv|info)\b(?!\s*\[)")
_SLOPE = "_sw_ms = reach_slope(q, qd, "
_DET = "jacobian_det(q, t, p, piv)"     # a position sweep's det Φ_q, where not written out
_LAST_DET = "if not jacobian_det(q, ts[ts.shape[0] - 1], p, piv)"
# the allocations no line reads once the loop uses locals
_UNUSED = ("_sw_qp = q0.copy()", "_sw_q1 = q0.copy()", "_sw_q2 = q0.copy()",
           "info = np.zeros(POSITION_INFO_SIZE)", "qd = np.zeros(N_COORDS)",
           "qdd = np.zeros(N_COORDS)")


def _indent(line):
    return len(line) - len(line.lstrip(" "))


# array -> the stem of its slots' locals
_STEM = {"q": "_sw_q", "qd": "_sw_qd", "qdd": "_sw_qdd", "_sw_qp": "_sw_qp", "_sw_q1": "_sw_q1",
         "_sw_q2": "_sw_q2", "piv": "_sw_piv"}
# the value each slot's local starts from (what the array held when the loop began)
_START = {"q": "q[{j}]", "qd": "0.0", "qdd": "0.0", "_sw_qp": "q0[{j}]", "_sw_q1": "q0[{j}]",
          "_sw_q2": "q0[{j}]", "piv": "0.0"}


def scratch_names(n: int) -> str:
    """Every local the pass may write for a model of n coordinates, as code: the names
    the module keeps for itself (codegen.names), so that no name derived from the model's
    (a turned angle's memory, _sw_<coordinate>) takes one of them."""
    return " ".join([f"{stem}_{j}" for stem in _STEM.values() for j in range(max(n, 3))]
                    + ["_sw_its"])


def _name(match):
    return f"{_STEM[match.group(1)]}_{match.group(2)}"


def scalar_scratch(lines: list[str], n: int) -> list[str]:
    """The lines of a written sweep_fast body (depth 0) with the loop's scratch slots as
    locals; the lines unchanged where the loop passes a scratch array to another call."""
    try:
        start = lines.index(LOOP)
    except ValueError:
        return lines
    end = start + 1
    while end < len(lines) and (not lines[end].strip() or _indent(lines[end]) > 0):
        end += 1
    loop = lines[start + 1:end]
    for line in loop:
        code = line.split("#", 1)[0]
        rest = code.replace(_SLOPE, "").replace(_DET, "")
        if _WHOLE.search(rest):
            return lines            # a call reads or writes a scratch array: as it was
    # where jacobian_det fills piv in the loop, piv stays an array
    slot = _SLOT if not any(_DET in line for line in loop) else \
        re.compile(_SLOT.pattern.replace("|piv)", ")"))
    body = []
    for line in loop:
        pad = " " * _indent(line)
        if _SLOPE in line:              # (the first point's tangent: the arrays filled)
            body += _assign([f"q[{j}]" for j in range(n)], [f"_sw_q_{j}" for j in range(n)],
                            pad)
            body += _assign([f"qd[{j}]" for j in range(n)], [f"_sw_qd_{j}" for j in range(n)],
                            pad)
        if _DET in line:
            body += _assign([f"q[{j}]" for j in range(n)], [f"_sw_q_{j}" for j in range(n)],
                            pad)
        code, hash_, comment = line.partition("#")     # (comments as they were)
        body.append(_ITERATIONS.sub("_sw_its", slot.sub(_name, code)) + hash_ + comment)
    # every slot of q and qd (the calls' arrays are filled from them), the others read
    slots = {(a, j) for a in ("q", "qd", "qdd") for j in range(n)}
    slots |= {(m.group(1), int(m.group(2))) for line in loop
              for m in slot.finditer(line.partition("#")[0])}
    init = ["# the loop's scratch as locals (_sw_q_5 is q[5]): arrays could alias Q, QD and",
            "# QDD, and would be stored and read again at every point"]
    for a in _STEM:
        js = sorted(j for b, j in slots if b == a)
        init += _assign([f"{_STEM[a]}_{j}" for j in js], [_START[a].format(j=j) for j in js])
    init.append("_sw_its = 0")
    after = []
    for line in lines[end:]:
        if line.lstrip().startswith(_LAST_DET):
            after += _assign([f"q[{j}]" for j in range(n)], [f"_sw_q_{j}" for j in range(n)],
                             " " * _indent(line))
        after.append(line)
    text = lines[:start] + init + [LOOP] + body + after
    used = "\n".join(x for x in text if _code(x) not in _UNUSED)
    return [x for x in text if _code(x) not in _UNUSED or _still_read(x, used)]


def _code(line):
    return line.split("#", 1)[0].strip()


def _assign(targets, values, pad="", width=92):
    """``a, b, c = x, y, z`` in lines of at most ``width`` characters."""
    out, tl, vl = [], [], []
    for t, v in zip(targets, values):
        if tl and len(pad) + len(", ".join(tl + [t])) + len(", ".join(vl + [v])) + 3 > width:
            out.append(f"{pad}{', '.join(tl)} = {', '.join(vl)}")
            tl, vl = [], []
        tl.append(t)
        vl.append(v)
    if tl:
        out.append(f"{pad}{', '.join(tl)} = {', '.join(vl)}")
    return out


def _still_read(line, text) -> bool:
    """Whether the array an allocation line makes is still named elsewhere."""
    name = _code(line).split(" = ", 1)[0]
    return re.search(rf"(?<![\w.]){re.escape(name)}(?![\w])", text) is not None
