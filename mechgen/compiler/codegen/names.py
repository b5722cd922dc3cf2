"""Name mangling: which identifier each model symbol gets in the generated module.

A model may name its parameters and coordinates as it likes (``i``, ``k``, ``t``, ``q``,
``tol``, ``E``, ...). The generated module keeps those names wherever they are free, and
only where the module uses the same name for itself (a function argument, a local of the
numerics, a module global, a builtin) does the model's symbol get a mangled form: ``q``
becomes ``q_``, with more ``_`` until the name is unique.

The names the module uses are read from its sources, never kept by hand: the template's
Python tokens (the generated functions' arguments among them), the names the numeric
library binds at module level (mechgen.compiler.library, as a module holds it: its
functions' own locals never share a scope with the model's names), the header constants
(mechgen.protocol), Python's builtins, and the code the emitters write
(mechgen.compiler.codegen.ir.code_words). Names the code
generator makes up all begin with ``_`` (``_t0``, ``_sin_Th3``); a model name that begins
with ``_`` is written with its underscores at the end instead (``_a`` as ``a_``), so the
two never meet. Names made from model names (``_sin_<y>``, ``_d<z>_d<y>``) take the
mapped names of their parts.
"""
from __future__ import annotations

import ast
import builtins
import functools
import io
import keyword
import os
import re
import tokenize
from importlib import resources

from ...protocol import header_constants
from ..library import library_text
from .printer import Alias, Derived, Local

_HERE = os.path.dirname(os.path.abspath(__file__))
_JINJA_TAG = re.compile(r"\{%.*?%\}|\{#.*?#\}", re.S)
_JINJA_VALUE = re.compile(r"\{\{.*?\}\}", re.S)
_WORD = re.compile(r"(?<![\w.])[A-Za-z_]\w*")
_MACRO_NAME = re.compile(r"\{\{\s*function\(\s*\"(\w+)\"")


def identifiers(source: str) -> set[str]:
    """The names a piece of Python code uses (NAME tokens that are not keywords nor
    attributes after a dot; strings and comments skipped)."""
    lines = [x.lstrip() for x in source.splitlines()]    # indentation cannot fail then
    out, after_dot = set(), False
    try:
        for tok in tokenize.generate_tokens(io.StringIO("\n".join(lines) + "\n").readline):
            if tok.type == tokenize.NAME and not after_dot and not keyword.iskeyword(tok.string):
                out.add(tok.string)
            after_dot = tok.type == tokenize.OP and tok.string == "."
    except (tokenize.TokenError, SyntaxError):
        # a fragment tokenize cannot finish: words outside comments, as a superset
        for line in lines:
            out |= set(_WORD.findall(line.split("#", 1)[0]))
    return out


def template_dir() -> str:
    """templates/ of this checkout (beside the mechgen package), else the installed copy
    (the package data mechgen.templates of a wheel)."""
    here = os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(_HERE))), "templates")
    if os.path.isfile(os.path.join(here, "module.py.j2")):
        return here
    return str(resources.files("mechgen.templates"))


def _template_sources():
    folder = template_dir()
    for name in sorted(os.listdir(folder)):
        if name.endswith(".j2"):
            with open(os.path.join(folder, name), encoding="utf-8") as fh:
                text = fh.read()
            # layout: jinja's tags go, its values become a number (no names of their own),
            # but a function the shared macro lays out keeps its name (def phi(...))
            defined = " ".join(f"def {name}(): pass\n" for name in _MACRO_NAME.findall(text))
            yield _JINJA_VALUE.sub("0", _JINJA_TAG.sub("", text)) + "\n" + defined


@functools.lru_cache(maxsize=1)
def module_words() -> frozenset:
    """The names every generated module may use for itself: the template's, the numeric
    library's (as a module holds it), the header constants' and Python's builtins."""
    out = set(dir(builtins))
    for text in _template_sources():
        out |= identifiers(text)
    out |= module_level_names(library_text(forces=True))
    out |= {name for _, names in header_constants() for name, _ in names}
    return frozenset(out)


_TOP_DEF = re.compile(r"(?:def|class)\s+([A-Za-z_]\w*)")


def module_level_names(source: str) -> set[str]:
    """The names a piece of Python binds at module level (functions, classes, assignments,
    imports): the library's locals live in its own functions' scopes and never meet the
    model's names, which live in the generated functions'. Text whose unindented lines are
    all decorators, functions and classes (the library: parsing it cost a build 0.03 s) is
    read line by line; any other is parsed."""
    names = set()
    for line in source.splitlines():
        if not line or line[0] in " \t#" or line[0] == "@":
            continue
        found = _TOP_DEF.match(line)
        if found is None:
            return _parsed_names(source)
        names.add(found.group(1))
    return names


def _parsed_names(source: str) -> set[str]:
    out = set()
    for node in ast.parse(source).body:
        if isinstance(node, (ast.FunctionDef, ast.ClassDef)):
            out.add(node.name)
        elif isinstance(node, (ast.Assign, ast.AnnAssign, ast.AugAssign)):
            targets = node.targets if isinstance(node, ast.Assign) else [node.target]
            out |= {n.id for t in targets for n in ast.walk(t) if isinstance(n, ast.Name)}
        elif isinstance(node, (ast.Import, ast.ImportFrom)):
            out |= {(a.asname or a.name).split(".")[0] for a in node.names}
    return out


def _free_form(name: str) -> str:
    """A model name as the module may write it: leading underscores moved to the end."""
    core = name.lstrip("_")
    return (core or "u") + "_" * (len(name) - len(core))


class Names:
    """The identifier of every model symbol and every Derived name in one module.

    ``model_symbols``: in declaration order (parameters, coordinates, their derivatives,
    T); ``used``: the names the module uses for itself; ``derived``: the Derived symbols
    its code holds."""

    def __init__(self, model_symbols, used, derived=()):
        used = set(used)
        own = {s.name for s in model_symbols}
        self._ident = {}
        wanted = [(s, _free_form(s.name)) for s in model_symbols]
        taken = used | own
        # a name the module leaves free is kept as it is; the others are mangled after
        for s, name in wanted:
            if name == s.name and name not in used:
                self._ident[s] = name
        for s, name in wanted:
            if s not in self._ident:
                while name in taken or name in self._ident.values():
                    name += "_"
                self._ident[s] = name
        taken |= set(self._ident.values())
        for d in sorted(set(derived), key=lambda x: (x.name, repr(x.parts))):
            name = "".join(p if isinstance(p, str) else self.ident(p) for p in d.parts)
            while name in taken:
                name += "_"
            taken.add(name)
            self._ident[d] = name

    def ident(self, sym) -> str:
        """The identifier of ``sym`` in the module (its own name when not mapped)."""
        found = self._ident.get(sym)
        if found is not None:
            return found
        if isinstance(sym, Derived):
            return "".join(p if isinstance(p, str) else self.ident(p) for p in sym.parts)
        return sym.name

    def mangled(self) -> dict:
        """{model name: identifier} for the model names that had to change."""
        return {s.name: v for s, v in self._ident.items()
                if not isinstance(s, Derived) and s.name != v}


def emitter_symbols(symbols):
    """The code generator's symbols in a module's code: (Derived symbols, names of the
    Local ones), looking through Alias symbols to what they print."""
    derived, plain, stack = set(), set(), list(symbols)
    while stack:
        s = stack.pop()
        if isinstance(s, Alias):
            stack.extend(getattr(s.target, "free_symbols", ()))
        elif isinstance(s, Derived):
            derived.add(s)
            stack.extend(p for p in s.parts if not isinstance(p, str))
        elif isinstance(s, Local):
            plain.add(s.name)
    return derived, plain
