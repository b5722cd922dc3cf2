"""The printer, the statement IR and the scheduling of common subexpressions, alone: exact
text of small expressions and statements, name mangling, the two printings of Return and
TrigPair, nested bodies, and trivial temporaries written into their uses bit for bit."""
import math
import random
import re

import sympy as sp

from mechgen.compiler.codegen.ir import (Assign, Break, Code, Comment, Guard, If, Loop, Options,
                                         Return, Store, TrigPair, code_words, count_lines, render)
from mechgen.compiler.codegen.names import Names
from mechgen.compiler.codegen.printer import Alias, Derived, Local, pycode
from mechgen.compiler.codegen.schedule import TempNames, emit

x, y, z, q, k = sp.symbols("x y z q k", real=True)


# -- printer -----------------------------------------------------------------------------
def test_small_expressions_print_exactly():
    cases = {x ** 2: "(x*x)", 1 / x: "1.0/x", y / x ** 2: "y/(x*x)",
             sp.sqrt(x + y): "math.sqrt(x + y)", sp.Rational(1, 3) * x: "(1.0/3.0)*x",
             sp.Float(0.1) * x: "0.1*x", sp.sin(x) * sp.cos(y): "math.sin(x)*math.cos(y)",
             sp.atan2(y, x): "math.atan2(y, x)", sp.Abs(x - y): "abs(x - y)",
             x ** 3 * y: "(x*x*x)*y", sp.pi - x: "math.pi - x", -x / (y + z): "-x/(y + z)"}
    for expr, text in cases.items():
        assert pycode(expr) == text


def test_symbols_print_through_the_name_map():
    names = Names([q, k, x], used={"q", "k", "math"})
    assert pycode(q + k * x, names) == "k_*x + q_"
    assert names.mangled() == {"q": "q_", "k": "k_"}
    # names made from model names take the mapped parts; locals keep their own
    assert pycode(Derived("_sin_", q) * Local("_t0", real=True), names) == "_sin_q_*_t0"
    assert pycode(Derived("_d", q, "_d", x), names) == "_dq__dx"


def test_mangled_names_avoid_every_other_name():
    a, a_, under = (sp.Symbol(n, real=True) for n in ("a", "a_", "_a"))
    names = Names([a, a_, under], used={"a"})
    assert [names.ident(s) for s in (a, a_, under)] == ["a__", "a_", "a___"]
    # derived names made the same from different parts stay apart
    d1, d2 = Derived("_sw_", a_), Derived("_sw_a", sp.Symbol("_", real=True))
    assert d1 != d2 and d1.name == d2.name


def test_an_alias_prints_its_target_where_the_temporary_stood():
    t7, t4 = (Local(n, real=True) for n in ("_t7", "_t4"))
    X2, X3 = sp.symbols("X2 X3", real=True)
    expr = -X2 - t4 - t7 + 2 * t7 * y
    assert pycode(expr) == "-X2 - _t4 + 2*_t7*y - _t7"
    assert pycode(expr.xreplace({t7: -Alias(X3, "_t7")})) == "-X2 - _t4 - 2*X3*y + X3"


# -- IR ------------------------------------------------------------------------------------
def test_return_and_guard_print_as_status_or_as_the_sweep_count():
    st = [Guard(x, sp.Float(1e-12), 4), Return(2), Return(0), Return(Local("_d", real=True))]
    assert render(st) == ["if not abs(x) > 1e-12:", "    return 4", "return 2", "return 0",
                          "return _d"]
    assert render(st, Options(failure="k")) == ["if not abs(x) > 1e-12:", "    return k",
                                                "return k", "return 0", "return _d"]


def test_trig_pair_prints_as_calls_or_turned_from_the_last_point():
    names = Names([q], used={"q"})
    pair = TrigPair(q, Derived("_sin_", q), Derived("_cos_", q),
                    (Derived("_sw_", q), Derived("_sw_sin_", q), Derived("_sw_cos_", q)))
    assert render([pair], Options(names=names)) == ["_sin_q_ = math.sin(q_)",
                                                    "_cos_q_ = math.cos(q_)"]
    assert render([pair], Options(names=names, turn=True), depth=1) == [
        "    if _sw_warm:",
        "        _sin_q_, _cos_q_ = _turn(_sw_sin_q_, _sw_cos_q_, _sw_q_ - q_, q_)",
        "    else:",
        "        _sin_q_ = math.sin(q_)",
        "        _cos_q_ = math.cos(q_)"]


def test_nested_bodies_indent_themselves():
    st = [Comment("block"),
          Loop(Code("for _it in range(maxit)"), (
              Assign(y, x * 2, "row 0"),
              If(Code("abs({0}) <= tol", (y,)), (Break(),), tail="  # converged"),
              Store("out[0]", y)),
              (If(Code("{0} > 1", (x,)), (Return(1),), (Code("{0} = 0.0", (x,)),)),)),
          Code("_iters = max(_iters, _it + 1)")]
    lines = render(st)
    assert lines == ["# block",
                     "for _it in range(maxit):",
                     "    y = 2*x  # row 0",
                     "    if abs(y) <= tol:  # converged",
                     "        break",
                     "    out[0] = y",
                     "else:",
                     "    if x > 1:",
                     "        return 1",
                     "    else:",
                     "        x = 0.0",
                     "_iters = max(_iters, _it + 1)"]
    assert count_lines(st) == len(lines)
    words = " ".join(code_words(st))
    assert "maxit" in words and "tol" in words and "_iters" in words and "{0}" not in words


# -- scheduling ------------------------------------------------------------------------------
def _old_way(exprs):
    """CSE and print as the code generator did before trivial temporaries were written
    into their uses: every temporary its own line."""
    reps, reduced = sp.cse(exprs, symbols=TempNames(), order="none")
    return ([f"{s.name} = {pycode(e)}" for s, e in reps] +
            [f"out[{i}] = {pycode(e)}" for i, e in enumerate(reduced)])


def test_trivial_temporaries_are_written_into_their_uses_bit_for_bit():
    X2, X3, Y2, Y3, X4, Y4, Th2, Th3, L = sp.symbols("X2 X3 Y2 Y3 X4 Y4 Th2 Th3 L", real=True)
    c, s = 9 * sp.cos(Th3), 9 * sp.sin(Th3)
    exprs = [-X3, -Y3, c * (-X2 + X3 - L * sp.cos(Th2)) + s * (-Y2 + Y3 - L * sp.sin(Th2)),
             (-X4 + X3 - s) ** 2 + (Y3 - Y4 + c) ** 2 - 25,
             -(-X2 + X3) * (X3 - X4) / (Y2 - X3)]
    old = _old_way(exprs)
    assert any(re.fullmatch(r"_t\d+ = -?\w+", line) for line in old)   # -X3 was a temporary
    new = render(emit([Store(f"out[{i}]", e) for i, e in enumerate(exprs)]))
    assert not any(re.fullmatch(r"_t\d+ = -?[\w.]+", line) for line in new)
    temps = [int(m) for line in new for m in re.findall(r"^_t(\d+) =", line)]
    assert temps == list(range(len(temps)))                           # renumbered in order
    rng = random.Random(3)
    for _ in range(200):
        env = {"math": math}
        env.update({n: rng.uniform(-3, 3) for n in ("X2", "X3", "Y2", "Y3", "X4", "Y4",
                                                     "Th2", "Th3", "L")})
        results = []
        for lines in (old, new):
            scope = dict(env, out=[None] * len(exprs))
            exec("\n".join(lines), scope)
            results.append(scope["out"])
        assert results[0] == results[1]          # the same floats, bit for bit


def test_hoisting_keeps_what_a_loop_changes_inside():
    den = Derived("_den_", y)
    st = [Assign(den, 2 * sp.cos(z)), Guard(den, sp.Float(1e-12), 4), Assign(y, x / den)]
    before, inside = emit(st, variant={x})
    assert render(before)[0].startswith("_den_y = ")
    assert render(inside) == ["y = x/_den_y"]
