"""The constraint reference (docs/constraints.md) cannot rot: every printed block on it is
what `mechgen equations` prints today for the models of docs/constraint_examples.py, every
constraint kind has its section, and every public name of the model language has a
docstring. ``--update-golden`` rewrites the printed blocks after a deliberate change."""
import inspect
import os
import re

import pytest

from mechgen.model import constraints, geometry, language
from mechgen.model.loader import load_models
from mechgen.model.printing import equations_text
from conftest import ROOT

DOC = os.path.join(ROOT, "docs", "constraints.md")
EXAMPLES = os.path.join(ROOT, "docs", "constraint_examples.py")
# a marker, then the fenced block that holds the printed rows
BLOCK = re.compile(r"<!-- printed: (\w+) (phi|nu|gamma) -->\n```text\n(.*?)```", re.S)
HEADERS = {"phi": "Phi(q, t) = 0", "nu": "nu = -Phi_t", "gamma": "gamma:"}


@pytest.fixture(scope="module")
def models():
    return {m.name: m for m in load_models(EXAMPLES)}


def printed_rows(model, section) -> str:
    """The rows of one section of equations_text (the lines after its header, up to the
    blank line that ends it), as the reference quotes them."""
    lines = equations_text(model).splitlines()
    start = next(i for i, line in enumerate(lines) if line.startswith(HEADERS[section]))
    rows = []
    for line in lines[start + 1:]:
        if not line.strip():
            break
        rows.append(line)
    return "\n".join(rows) + "\n"


def test_printed_rows_are_what_the_printer_gives(models, update_golden):
    text = open(DOC, encoding="utf-8").read()
    blocks = BLOCK.findall(text)
    assert len(blocks) >= 20
    wrong = []

    def fill(match):
        name, section, quoted = match.groups()
        assert name in models, f"docs/constraints.md quotes model {name!r}, which " \
                               f"constraint_examples.py does not define"
        rows = printed_rows(models[name], section)
        if rows != quoted:
            wrong.append(f"{name} {section}:\n--- quoted\n{quoted}--- printed\n{rows}")
        return match.group(0).replace(f"```text\n{quoted}```", f"```text\n{rows}```")

    new = BLOCK.sub(fill, text)
    if wrong and update_golden:
        with open(DOC, "w", encoding="utf-8") as fh:
            fh.write(new)
        return
    assert not wrong, ("docs/constraints.md differs from the printer (run with "
                       "--update-golden after a deliberate change):\n" + "\n".join(wrong))


def test_every_example_is_quoted_and_every_row_is_labelled(models):
    text = open(DOC, encoding="utf-8").read()
    quoted = {name for name, _, _ in BLOCK.findall(text)}
    assert quoted == set(models), f"examples never quoted: {set(models) - quoted}"
    for name, section, rows in BLOCK.findall(text):
        assert rows.strip(), f"empty block {name} {section}"
        assert all(re.match(r"^  \[\d+\]|^ {5,}", line) for line in rows.splitlines())
        # every row names the constraint it comes from
        assert "# 1 " in rows


def test_every_kind_has_a_section_with_its_rows(models):
    text = open(DOC, encoding="utf-8").read()
    sections = dict(re.findall(r"^## (\w+)\n(.*?)(?=^## |\Z)", text, re.S | re.M))
    for kind in constraints.KINDS:
        assert kind in sections, f"no section for {kind}"
        body = sections[kind]
        assert f"`m.{kind}(" in body, f"section {kind} does not show the call"
        rows = [r for _, _, r in BLOCK.findall(body)]
        # (a loop's rows read "loop 1 re": its label is not a call)
        assert any(f"# 1 {kind}(" in r or f"# 1 {kind} " in r for r in rows), \
            f"section {kind} quotes no {kind} row"
    # body[0] is documented where points are
    assert "`body[0]`" in text and "origin" in sections["revolute"]


def test_the_printed_rows_are_the_equations(models):
    """Numbers first: the rows quoted for two forms are the equations they should be."""
    import sympy as sp
    eq = models["relative_angle"].equations()
    th2, th3 = sp.symbols("Th2 Th3", real=True)
    assert sp.simplify(eq.phi[0] - (th3 + sp.pi / 2 - th2 - sp.pi / 3)) == 0
    eq = models["translate"].equations()
    assert len(eq.phi) == 2 and sp.simplify(eq.phi[0] - 8 * sp.sin(th2)) == 0


def test_the_site_links_the_reference():
    from docs_pages import page
    assert "../constraints" in page("reference/index.md")           # in the reference's toc
    assert "constraints.md" in page("guide/model.md")
    analysis = page("guide/analysis.md")
    assert "load_model" in analysis and "MECHGEN_CACHE" in analysis


PUBLIC = [language.Model, geometry.Body, geometry.Point, geometry.Line, constraints.Constraint,
          *constraints.KINDS.values()]


@pytest.mark.parametrize("cls", PUBLIC, ids=lambda c: c.__name__)
def test_public_names_have_docstrings(cls):
    assert cls.__doc__ and cls.__doc__.strip()
    missing = []
    for name, value in vars(cls).items():
        if name.startswith("_") and name != "__getitem__":
            continue
        if isinstance(value, property):
            value = value.fget
        if not inspect.isfunction(value):
            continue
        # an override may share its base's docstring (Constraint.build)
        if not (inspect.getdoc(getattr(cls, name)) or "").strip():
            missing.append(name)
    assert not missing, f"{cls.__name__}: no docstring on {', '.join(missing)}"


def test_body_getitem_documents_the_origin():
    assert "origin" in geometry.Body.__getitem__.__doc__
    assert "body[0]" in geometry.Body.__getitem__.__doc__
