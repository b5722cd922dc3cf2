"""The documentation cannot lose a public name: every name of ``mechgen.__all__`` is
mentioned on a reference page (docs/reference/*.md, docs/constraints.md); every one that
is mechgen's own (not a sympy name re-exported, not a constant) has a docstring, and where
it takes arguments, numpydoc sections naming each of them (``Parameters``; ``Returns`` for
a function), as do the Mechanism methods the runtime's contract names. The command-line
page has a section for every subcommand, the gallery runs every file of examples/, and the
README is a landing page that links every page of the guide."""
import glob
import inspect
import os
import re

import pytest

import mechgen
from docs_pages import DOCS, ROOT, page

SYMPY = set(mechgen._SYMPY_NAMES)
CONSTANTS = {"T", "__version__"}
OWN = [n for n in mechgen.__all__ if n not in SYMPY | CONSTANTS]
# the methods the runtime reference (docs/reference/runtime.md and the pages after it) is
# about: each documents its parameters and what it returns
MECHANISM = ("with_params", "set_guess", "solve", "sweep", "singularities", "assemblies",
             "simulate", "optimize", "tolerance", "fit", "evaluate", "explore")


def reference_text() -> str:
    paths = sorted(glob.glob(os.path.join(DOCS, "reference", "*.md")))
    paths.append(os.path.join(DOCS, "constraints.md"))
    return "\n".join(open(p, encoding="utf-8").read() for p in paths)


def sections(doc) -> dict:
    """{numpydoc section title: its text} of a docstring."""
    doc = inspect.cleandoc(doc or "")
    found = {}
    parts = re.split(r"^(\w[\w ]*)\n-{3,}\n", doc, flags=re.M)
    for title, body in zip(parts[1::2], parts[2::2]):
        found[title.strip()] = body
    return found


def arguments(func) -> list:
    """The names of a callable's arguments, but self, *args and **kwargs."""
    try:
        sig = inspect.signature(func)
    except (TypeError, ValueError):
        return []
    return [p.name for p in sig.parameters.values()
            if p.name not in ("self", "cls")
            and p.kind not in (p.VAR_POSITIONAL, p.VAR_KEYWORD)]


def missing_sections(name, func, doc, needs_returns):
    """What a docstring lacks: the Parameters section naming every argument, Returns."""
    found = sections(doc)
    wrong = []
    args = arguments(func)
    if args:
        params = found.get("Parameters", "")
        if not params:
            wrong.append(f"{name}: no Parameters section")
        else:
            named = set(re.findall(r"^(\w+)(?:,\s*\w+)*\s*:", params, re.M))
            named |= {a for line in re.findall(r"^([\w, ]+)\s*:", params, re.M)
                      for a in re.split(r",\s*", line.strip())}
            absent = [a for a in args if a not in named]
            if absent:
                wrong.append(f"{name}: Parameters does not name {absent}")
    if needs_returns and "Returns" not in found and "Yields" not in found:
        wrong.append(f"{name}: no Returns section")
    return wrong


def test_every_public_name_is_on_a_reference_page():
    text = reference_text()
    absent = [n for n in mechgen.__all__
              if f"`{n}`" not in text and f"mechgen.{n}" not in text]
    assert not absent, f"no reference page mentions {absent}"


@pytest.mark.parametrize("name", OWN)
def test_every_public_name_has_a_docstring_with_its_sections(name):
    obj = getattr(mechgen, name)
    doc = obj.__dict__.get("__doc__") if inspect.isclass(obj) else obj.__doc__
    assert doc and doc.strip(), f"mechgen.{name} has no docstring of its own"
    if inspect.isclass(obj):
        if issubclass(obj, (Exception, Warning)):
            return          # raised by mechgen, never called by a user
        init = obj.__dict__.get("__init__")
        if init is not None and obj.__name__ in ("Model", "Line"):   # built by the user
            wrong = missing_sections(name, init, doc + "\n" + (init.__doc__ or ""), False)
            assert not wrong, wrong
        return
    wrong = missing_sections(name, obj, doc, needs_returns=True)
    assert not wrong, wrong


@pytest.mark.parametrize("method", MECHANISM)
def test_the_mechanism_methods_have_their_sections(method):
    func = getattr(mechgen.Mechanism, method)
    assert func.__doc__, f"Mechanism.{method} has no docstring"
    wrong = missing_sections(f"Mechanism.{method}", func, func.__doc__,
                             needs_returns=method not in ("set_guess",))
    assert not wrong, wrong


def test_the_command_line_page_has_every_subcommand():
    import argparse
    from mechgen.cli import parser
    subs = next(a for a in parser()._actions if isinstance(a, argparse._SubParsersAction))
    text = page("reference/cli.md")
    absent = [c for c in subs.choices if f"```{{mechgen-help}} {c}\n" not in text]
    assert not absent, f"docs/reference/cli.md has no help of {absent}"


def test_the_gallery_runs_every_example():
    scripts = "\n".join(open(p, encoding="utf-8").read()
                        for p in glob.glob(os.path.join(DOCS, "gallery", "plot_*.py")))
    files = sorted(os.listdir(os.path.join(ROOT, "examples")))
    absent = [f for f in files if not f.startswith((".", "__"))
              and os.path.splitext(f)[0] not in scripts]
    assert not absent, f"no gallery script of docs/gallery/ runs {absent}"


def test_the_readme_is_a_landing_page_linking_every_guide_page():
    readme = open(os.path.join(ROOT, "README.md"), encoding="utf-8").read()
    assert len(readme.splitlines()) <= 200
    guide = sorted(os.path.relpath(p, ROOT).replace(os.sep, "/")
                   for p in glob.glob(os.path.join(DOCS, "guide", "*.md")))
    absent = [p for p in guide if not p.endswith("index.md") and f"]({p})" not in readme]
    assert not absent, f"README does not link {absent}"
    assert "](docs/getting-started.md)" in readme
    assert "sphinx -W" in readme                      # how to build the site locally
