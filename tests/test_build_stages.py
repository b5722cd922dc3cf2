"""The build's cheaper stages give what the slower ones gave: the library's module-level
names read line by line (the same set as Python's parser), the reach margins' floor left
unevaluated where sympy's comparison would decide nothing, the template compiled once."""
from __future__ import annotations

import sympy as sp

from mechgen.compiler.codegen.names import _parsed_names, module_level_names
from mechgen.compiler.library import library_text
from mechgen.compiler.render import environment
from mechgen.compiler.solver.dyads import margin
from mechgen.compiler.solver.blocks import DYAD_RRR
from mechgen.protocol import TINY


def test_library_names_read_by_lines_are_the_parsers():
    for forces in (False, True):
        text = library_text(forces)
        assert module_level_names(text) == _parsed_names(text)
        assert {"sweep", "unwrap_turns", "_fp_eliminate"} <= module_level_names(text)


def test_other_text_is_parsed():
    text = "import numpy as np\nX, Y = 1, 2\n\n@njit\ndef f(a):\n    b = 1\n    return a\n"
    assert module_level_names(text) == {"np", "X", "Y", "f"}


class _Block:
    method = DYAD_RRR

    def __init__(self, form):
        self.form = form


def test_margin_floor_numeric_and_symbolic():
    x, y = sp.symbols("x y", real=True)
    symbolic = margin(_Block((x, y, 1, 0, 0, 1)))
    den = [d for d in sp.preorder_traversal(symbolic) if isinstance(d, sp.Max)]
    assert den and den[0] == sp.Max(4 * (x ** 2 + y ** 2), sp.Float(TINY))
    # a denominator that is a number is compared now: no Max left in the margin
    numeric = margin(_Block((sp.Integer(3), sp.Integer(4), 1, 0, 0, 1)))
    assert numeric == 1 - sp.Integer(25) ** 2 / 100
    assert not numeric.atoms(sp.Max)


def test_template_compiled_once_per_process():
    assert environment().get_template("module.py.j2") is \
        environment().get_template("module.py.j2")
