"""A small statement IR for the bodies of generated functions, and its printing.

Emitters build statements (frozen data holding sympy expressions and symbols); ``render``
prints them as lines of Python, indenting nested bodies itself. Nothing is ever searched
or edited as text after printing: what differs between two uses of the same statements
(``return 4`` in a solver, ``return k`` written out in the fast sweep's loop; sin and cos
called afresh or turned from the last point) is a printing option.
"""
from __future__ import annotations

import string
from dataclasses import dataclass, field

import sympy as sp

from .printer import printer_for

INDENT = "    "


@dataclass(frozen=True)
class Assign:
    """``target = expr`` (target a Symbol: a local variable)."""
    target: sp.Symbol
    expr: object
    comment: str = ""


@dataclass(frozen=True)
class Store:
    """``lhs = expr`` with ``lhs`` an array slot such as ``out[3]`` (no model names in it)."""
    lhs: str
    expr: object
    comment: str = ""


@dataclass(frozen=True)
class Guard:
    """``if not abs(value) > bound: return status``: a pivot check before a division.
    ``value`` is a Symbol assigned earlier, ``bound`` an expression."""
    value: sp.Symbol
    bound: object
    status: int


@dataclass(frozen=True)
class Comment:
    """``# text``."""
    text: str


@dataclass(frozen=True)
class Code:
    """One line of code: ``text`` with ``{0}``, ``{1}``, ... replaced by the printed
    ``args`` (symbols or expressions, so that model names go through the name map)."""
    text: str
    args: tuple = ()


@dataclass(frozen=True)
class Return:
    """``return status``: an int status (0 success), or an expression (``_d``)."""
    status: object


@dataclass(frozen=True)
class Break:
    """``break``."""


@dataclass(frozen=True)
class TrigPair:
    """The sin and cos of an angle as a pair, into ``sin`` and ``cos``. Printed as two
    calls; with ``Options.turn`` (the fast sweep's step) as the pair turned from the last
    accepted point, whose angle, sin and cos the loop keeps in ``memory`` (three symbols)."""
    angle: sp.Symbol
    sin: sp.Symbol
    cos: sp.Symbol
    memory: tuple


@dataclass(frozen=True)
class Variant:
    """Statements printed as ``body`` in a solver and as ``turned`` in the fast sweep's
    step (``Options.turn``), where the loop's memory of the last point can stand in for
    work: a dyad's sign kept from the first point, its angles from the last point's."""
    body: tuple
    turned: tuple


@dataclass(frozen=True)
class If:
    """``if test:`` body, ``else:`` orelse (when not empty); ``test`` a Code, ``tail``
    printed after the colon as it is (a comment with its spacing)."""
    test: Code
    body: tuple
    orelse: tuple = ()
    tail: str = ""


@dataclass(frozen=True)
class Loop:
    """``header:`` body, ``else:`` orelse (when not empty); ``header`` a Code such as
    ``for _it in range(maxit)``."""
    header: Code
    body: tuple
    orelse: tuple = ()


@dataclass(frozen=True)
class Options:
    """How to print: ``names`` maps symbols to identifiers (None: their own names);
    ``failure`` replaces every non-zero int status of a Return or Guard (``"k"`` in the
    fast sweep's loop, which returns the count of points accepted); ``turn`` prints each
    TrigPair turned from the last point (the fast sweep's step)."""
    names: object = None
    failure: str | None = None
    turn: bool = False
    printer: object = field(default=None, compare=False)

    def __post_init__(self):
        object.__setattr__(self, "printer", printer_for(self.names))


PLAIN = Options()


def render(statements, options: Options = PLAIN, depth: int = 0) -> list[str]:
    """The lines of code of ``statements`` (indented by ``depth`` levels)."""
    out = []
    for st in statements:
        out += _lines(st, options, depth)
    return out


def _status(status, options):
    if isinstance(status, int):
        if status != 0 and options.failure is not None:
            return options.failure
        return str(status)
    return options.printer.doprint(status)


def _lines(st, o: Options, depth):
    pad = INDENT * depth
    p = o.printer.doprint
    if isinstance(st, Assign):
        tail = f"  # {st.comment}" if st.comment else ""
        return [f"{pad}{p(st.target)} = {p(st.expr)}{tail}"]
    if isinstance(st, Store):
        tail = f"  # {st.comment}" if st.comment else ""
        return [f"{pad}{st.lhs} = {p(st.expr)}{tail}"]
    if isinstance(st, Guard):
        return [f"{pad}if not abs({p(st.value)}) > {p(st.bound)}:",
                f"{pad}{INDENT}return {_status(st.status, o)}"]
    if isinstance(st, Comment):
        return [f"{pad}# {st.text}"]
    if isinstance(st, Code):
        return [pad + code_text(st, o)]
    if isinstance(st, Return):
        return [f"{pad}return {_status(st.status, o)}"]
    if isinstance(st, Break):
        return [f"{pad}break"]
    if isinstance(st, TrigPair):
        y, s, c = p(st.angle), p(st.sin), p(st.cos)
        calls = [f"{s} = math.sin({y})", f"{c} = math.cos({y})"]
        if not o.turn:
            return [pad + x for x in calls]
        last, last_sin, last_cos = (p(x) for x in st.memory)
        return [f"{pad}if _sw_warm:",
                f"{pad}{INDENT}{s}, {c} = _turn({last_sin}, {last_cos}, {last} - {y}, {y})",
                f"{pad}else:"] + [pad + INDENT + x for x in calls]
    if isinstance(st, Variant):
        return render(st.turned if o.turn else st.body, o, depth)
    if isinstance(st, (If, Loop)):
        head = st.test if isinstance(st, If) else st.header
        tail = st.tail if isinstance(st, If) else ""
        out = [f"{pad}{'if ' if isinstance(st, If) else ''}{code_text(head, o)}:{tail}"]
        out += render(st.body, o, depth + 1)
        if st.orelse:
            out.append(f"{pad}else:")
            out += render(st.orelse, o, depth + 1)
        return out
    raise TypeError(f"not a statement: {st!r}")


def code_text(code: Code, o: Options = PLAIN) -> str:
    return code.text.format(*(o.printer.doprint(a) for a in code.args))


def count_lines(statements) -> int:
    """How many lines ``render`` prints for the statements (without printing them)."""
    n = 0
    for st in statements:
        if isinstance(st, (Guard, TrigPair)):
            n += 2
        elif isinstance(st, Variant):
            n += count_lines(st.body)
        elif isinstance(st, (If, Loop)):
            n += 1 + count_lines(st.body) + (1 + count_lines(st.orelse) if st.orelse else 0)
        else:
            n += 1
    return n


def replaced(st, fn):
    """A statement with ``fn`` applied to its expression (others as they are)."""
    if isinstance(st, Assign):
        return Assign(st.target, fn(st.expr), st.comment)
    if isinstance(st, Store):
        return Store(st.lhs, fn(st.expr), st.comment)
    if isinstance(st, Guard):
        return Guard(st.value, fn(st.bound), st.status)
    return st


def load(sym, array: str, index) -> Code:
    """``sym = array[index]``: a local from an argument array."""
    return Code(f"{{0}} = {array}[{index}]", (sym,))


@dataclass(frozen=True)
class Helper:
    """A function of its own that a large function is split into (``_phi_part0``)."""
    name: str
    args: str
    doc: str
    body: tuple


# -- what a body holds: its symbols and the names its code text uses -------------------------
def walk(statements):
    """Every statement, nested bodies included (depth first, in order)."""
    for st in statements:
        yield st
        if isinstance(st, (If, Loop)):
            yield from walk(st.body)
            yield from walk(st.orelse)
        elif isinstance(st, Variant):
            yield from walk(st.body)
            yield from walk(st.turned)


def expressions(st):
    """The sympy expressions and symbols a statement prints."""
    if isinstance(st, Assign):
        return [st.target, st.expr]
    if isinstance(st, Store):
        return [st.expr]
    if isinstance(st, Guard):
        return [st.value, st.bound]
    if isinstance(st, Code):
        return list(st.args)
    if isinstance(st, If):
        return list(st.test.args)
    if isinstance(st, Loop):
        return list(st.header.args)
    if isinstance(st, Return) and not isinstance(st.status, int):
        return [st.status]
    if isinstance(st, TrigPair):
        return [st.angle, st.sin, st.cos, *st.memory]
    return []


def symbols(statements) -> set:
    """Every symbol the statements print."""
    out = set()
    for st in walk(statements):
        for e in expressions(st):
            out |= sp.sympify(e).free_symbols
    return out


# the words each kind of statement prints around its expressions
_FIXED = {Guard: "if not abs ( ) > : return", Return: "return", Break: "break",
          TrigPair: "math . sin cos if _sw_warm : _turn else", If: "if else", Loop: "else"}


def code_words(statements) -> list[str]:
    """The code text of the statements, without their expressions: what the emitters
    write themselves (tokenized by mechgen.compiler.codegen.names to find the names they use)."""
    out = []
    for st in walk(statements):
        if isinstance(st, (Code, If, Loop)):
            code = st if isinstance(st, Code) else st.test if isinstance(st, If) else st.header
            out.append(" ".join(lit for lit, *_ in string.Formatter().parse(code.text)))
        elif isinstance(st, Store):
            out.append(st.lhs)
        out.append(_FIXED.get(type(st), ""))
    return out
