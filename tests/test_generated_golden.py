"""The committed modules in generated/ are exactly what the generator emits today, and a
module that was edited by hand (or comes from another format) is refused by mechgen.load.

The comparison renders in memory; only with ``pytest --update-golden`` (or the environment
variable MECHGEN_UPDATE_GOLDEN=1) are the modules that differ rewritten, and the test
then says which."""
from __future__ import annotations

import ast
import difflib
import glob
import os
import re
import shutil

import pytest

import mechgen
from conftest import EXAMPLES, GENERATED
from mechgen.protocol import SENSITIVITY_SUFFIX

EXAMPLE_FILES = sorted(glob.glob(os.path.join(EXAMPLES, "*.py")))
COMPANION = SENSITIVITY_SUFFIX + ".py"     # a sensitivity module, built where asked (ignored)


def _models_of(path):
    from mechgen.model.loader import load_models
    try:
        return load_models(path)
    except mechgen.ModelError as exc:
        if "defines no mechgen.Model" in str(exc):
            return []
        raise


DIFF_LINES = 80     # of a mismatch's unified diff, shown in the failure


def _diff(committed, fresh, name):
    """The first DIFF_LINES lines of the unified diff from the committed module to a fresh one."""
    lines = list(difflib.unified_diff(
        committed.splitlines(True), fresh.splitlines(True),
        fromfile=f"generated/{name}.py (committed)",
        tofile=f"generated/{name}.py (rendered now)", n=2))
    if len(lines) > DIFF_LINES:
        lines = lines[:DIFF_LINES] + [f"... ({len(lines) - DIFF_LINES} more diff lines)\n"]
    return "".join(lines)


@pytest.mark.parametrize("path", EXAMPLE_FILES, ids=os.path.basename)
def test_generated_module_is_up_to_date(path, update_golden):
    """Rebuilding every model of examples/ gives the committed bytes."""
    from mechgen.compiler.build import render, write_module
    models = _models_of(path)
    if not models:
        pytest.skip(f"{os.path.basename(path)} defines no model (a script)")
    rel = os.path.relpath(path, os.path.dirname(EXAMPLES))
    rewritten = []
    for model in models:
        target = os.path.join(GENERATED, f"{model.name}.py")
        fresh = render(model)
        if update_golden and not os.path.isfile(target):
            write_module(fresh, target)
            rewritten.append(target)
            continue
        assert os.path.isfile(target), (
            f"generated/{model.name}.py is missing: run `mechgen build {rel}` and commit it "
            f"(or pytest --update-golden)")
        with open(target, encoding="utf-8", newline="") as fh:
            committed = fh.read()
        if fresh == committed:
            continue
        if update_golden:
            write_module(fresh, target)
            rewritten.append(target)
            continue
        pytest.fail(f"generated/{model.name}.py is out of date with the generator; refresh it "
                    f"with `pytest tests/test_generated_golden.py --update-golden` (or "
                    f"`mechgen build {rel}` from the repository root) and commit it.\n"
                    f"{_diff(committed, fresh, model.name)}", pytrace=False)
    if rewritten:
        pytest.skip("rewrote " + ", ".join(os.path.relpath(t, os.path.dirname(GENERATED))
                                          for t in rewritten) + " (--update-golden)")


def test_every_generated_module_has_a_model():
    """No stale module lingers in generated/ for a model that no longer exists."""
    names = {m.name for path in EXAMPLE_FILES for m in _models_of(path)}
    files = {os.path.splitext(os.path.basename(p))[0]
             for p in glob.glob(os.path.join(GENERATED, "*.py")) if not p.endswith("__init__.py")
             and not p.endswith(COMPANION)}
    assert files <= names, f"modules without a model in examples/: {sorted(files - names)}"


def test_render_is_deterministic():
    """Two renders of a freshly loaded model give the same bytes (no timestamps, no set order)."""
    from conftest import example_model
    from mechgen.compiler.build import render
    a = render(example_model("quick_return"))
    b = render(example_model("quick_return"))
    assert a == b


# -- the content stamp -------------------------------------------------------------------
def _copy(tmp_path, name="quick_return", numba_cache=False):
    src = os.path.join(GENERATED, f"{name}.py")
    dst = tmp_path / f"{name}.py"
    shutil.copy2(src, dst)
    if numba_cache:     # numba's compiled code of it, valid for an unchanged copy (same mtime)
        (tmp_path / "__pycache__").mkdir()
        for f in glob.glob(os.path.join(GENERATED, "__pycache__", f"{name}.*.nb[ic]")):
            shutil.copy2(f, tmp_path / "__pycache__" / os.path.basename(f))
    return dst


def test_hand_edited_module_is_refused(tmp_path):
    path = _copy(tmp_path)
    text = path.read_text(encoding="utf-8")
    edited = re.sub(r"^GUESS = \(0\.0, 5\.0,", "GUESS = (0.0, 6.0,", text, count=1, flags=re.M)
    assert edited != text
    path.write_text(edited, encoding="utf-8")
    with pytest.raises(mechgen.MechgenError) as info:
        mechgen.load(str(path))
    msg = str(info.value)
    assert "edited" in msg and str(path) in msg and "mechgen build" in msg


def test_unstamped_module_is_refused(tmp_path):
    path = _copy(tmp_path)
    text = path.read_text(encoding="utf-8")
    path.write_text(re.sub(r"^# content-sha256: .*\n", "", text, count=1, flags=re.M),
                    encoding="utf-8")
    with pytest.raises(mechgen.MechgenError, match="not a module generated by mechgen"):
        mechgen.load(str(path))


def test_other_format_version_is_refused(tmp_path):
    """A correctly stamped module of another FORMAT_VERSION (a future mechgen, say)."""
    from mechgen.compiler.build import STAMP
    from mechgen.protocol import FORMAT_VERSION as SUPPORTED_FORMAT, content_digest
    path = _copy(tmp_path)
    text = path.read_text(encoding="utf-8")
    body = re.sub(r"^# content-sha256: .*\n", "", text, count=1, flags=re.M)
    body, count = re.subn(r"^FORMAT_VERSION = \d+$", f"FORMAT_VERSION = {SUPPORTED_FORMAT + 1}",
                          body, count=1, flags=re.M)
    assert count == 1
    path.write_text(STAMP.format(digest=content_digest(body)) + body, encoding="utf-8")
    with pytest.raises(mechgen.MechgenError) as info:
        mechgen.load(str(path))
    msg = str(info.value)
    assert f"format {SUPPORTED_FORMAT + 1}" in msg and "rebuild" in msg


def test_a_faithful_copy_loads(tmp_path):
    """The stamp is about content, not place: an unedited copy loads and solves."""
    mech = mechgen.load(str(_copy(tmp_path, "fourbar_loop", numba_cache=True)))
    s = mech.solve(0.0)
    assert abs(s["theta3"] - 0.5274103891) < 1e-9


# -- the header and the library in a generated module --------------------------------------
GENERATED_FILES = sorted(p for p in glob.glob(os.path.join(GENERATED, "*.py"))
                         if not p.endswith("__init__.py") and not p.endswith(COMPANION))


def _read(path):
    with open(path, encoding="utf-8") as fh:
        return fh.read()


def _top_level(text):
    """{name: value} of a module's top-level constant assignments, and the set of every
    name it defines at top level (assignments, functions, imports)."""
    values, defined = {}, set()
    nodes = []
    for node in ast.parse(text).body:
        nodes.append(node)
        if isinstance(node, ast.Try):      # the header's numba import (or the Python tier's)
            nodes += node.body + [x for h in node.handlers for x in h.body]
    for node in nodes:
        if isinstance(node, ast.Assign):
            for target in node.targets:
                if isinstance(target, ast.Tuple):
                    defined.update(x.id for x in target.elts if isinstance(x, ast.Name))
                if isinstance(target, ast.Name):
                    defined.add(target.id)
                    try:
                        values[target.id] = ast.literal_eval(node.value)
                    except ValueError:
                        pass
        elif isinstance(node, ast.FunctionDef):
            defined.add(node.name)
        elif isinstance(node, (ast.Import, ast.ImportFrom)):
            defined.update((a.asname or a.name).split(".")[0] for a in node.names)
    return values, defined


@pytest.mark.parametrize("path", GENERATED_FILES, ids=os.path.basename)
def test_header_constants_are_the_protocol_s(path):
    """The status codes, info columns and tolerances a module states (and its solvers use
    by name) are mechgen.protocol's, value and type."""
    from mechgen import protocol
    values, _ = _top_level(_read(path))
    names = [n for _, group in protocol.HEADER_CONSTANTS for n in group]
    assert {"OK", "GAVE_UP", "STATUS_CODE", "SING_RTOL", "BRANCH_NEAR"} <= set(names)
    for name in names:
        assert name in values, f"{name} missing from the header of {os.path.basename(path)}"
        want = getattr(protocol, name)
        assert values[name] == want and type(values[name]) is type(want), name
    assert values["FORMAT_VERSION"] == protocol.FORMAT_VERSION


def _library_names(forces=False):
    from mechgen.compiler.library import toy
    return set(toy.__all__) - (set() if forces else set(toy.FORCE_NAMES))


@pytest.mark.parametrize("path", GENERATED_FILES, ids=os.path.basename)
def test_module_holds_the_library_and_what_it_needs(path):
    """The library's text verbatim (with its force part where the model has mass or
    loads), and every name the library takes from a module."""
    from mechgen.compiler.library import library_text
    text = _read(path)
    values, defined = _top_level(text)
    forces = bool(values.get("FORCES", False))
    assert library_text(forces) in text
    assert forces or library_text(True) not in text
    assert _library_names(forces) <= defined, sorted(_library_names(forces) - defined)


@pytest.mark.parametrize("options", [dict(sort=False), dict(level="position"),
                                     dict(level="velocity", outputs=["Th3"])],
                         ids=["no-sort", "position", "pruned"])
def test_a_module_without_the_fast_path_has_stubs(options):
    """What a module does not build (sorted solvers, a level) is there as a stub, so the
    library always compiles; its header says which (SORTED, LEVEL, ALL_SOLVED)."""
    from conftest import example_model
    from mechgen.compiler.build import render
    text = render(example_model("quick_return"), **options)
    values, defined = _top_level(text)
    assert _library_names() <= defined, sorted(_library_names() - defined)
    assert values["SORTED"] is options.get("sort", True)
    assert values["LEVEL"] == {"position": 0, "velocity": 1}.get(options.get("level"), 2)
    assert values["ALL_SOLVED"] is ("outputs" not in options)
    assert "    return GAVE_UP\n" in text and "{%" not in text and "{{" not in text
    assert re.search(r"^def sweep_fast\(.*\):\n    \"\"\"Not built.*\n    return 0\n", text, re.M)
