"""``mechgen view`` needs Bokeh, which ``pip install -e .`` (the README's first command)
does not install: where it is missing the error says exactly how to get it, with the
extra that pyproject.toml declares."""
import importlib.util
import pathlib
import tomllib

import pytest

from mechgen.cli import main
from mechgen.errors import MechgenError
from mechgen.view import need_bokeh

ROOT = pathlib.Path(__file__).resolve().parents[1]


def _no_bokeh(monkeypatch):
    real = importlib.util.find_spec
    monkeypatch.setattr(importlib.util, "find_spec",
                        lambda name, *a: None if name == "bokeh" else real(name, *a))


def test_the_view_extra_holds_bokeh():
    extras = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"][
        "optional-dependencies"]
    assert any(dep.startswith("bokeh") for dep in extras["view"])


def test_missing_bokeh_says_the_install_command(monkeypatch):
    _no_bokeh(monkeypatch)
    with pytest.raises(MechgenError) as info:
        need_bokeh()
    text = str(info.value)
    assert 'pip install -e ".[view]"' in text          # from a clone, as the README installs
    assert "pip install bokeh" in text


def test_mechgen_view_prints_it(monkeypatch, capsys):
    _no_bokeh(monkeypatch)
    assert main(["view", "examples/fourbar.py", "--no-browser"]) == 1
    err = capsys.readouterr().err
    assert 'pip install -e ".[view]"' in err and err.count("\n") == 1
