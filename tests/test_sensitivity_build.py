"""The sensitivity module built ahead of the first call that asks for it:
``mechgen.compile(..., sensitivities=True)`` and ``mechgen build --sensitivities`` write
``<name>_sensitivities.py`` beside the module, stamped with its MODEL_HASH, and its
derivatives answer without building again."""
import os

import numpy as np
import pytest

import mechgen
from mechgen.cli import main
from mechgen.errors import MechgenError

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
FOURBAR = os.path.join(ROOT, "examples", "fourbar.py")


def _hash(path):
    with open(path, encoding="utf-8") as fh:
        return next(line.split('"')[1] for line in fh if line.startswith("MODEL_HASH = ")
                    or line.startswith("MODULE_HASH = "))


def test_compile_with_sensitivities_writes_the_companion(tmp_path):
    mech = mechgen.compile(FOURBAR, outdir=str(tmp_path), tier="python", sensitivities=True)
    module = tmp_path / "fourbar.py"
    companion = tmp_path / "fourbar_sensitivities.py"
    assert companion.is_file()
    assert _hash(companion) == _hash(module)
    before = companion.stat().st_mtime_ns
    s = mech.solve(0.1, sensitivities=True)
    assert np.all(np.isfinite(s.dq_dp))
    assert companion.stat().st_mtime_ns == before       # found, not built again
    assert not (tmp_path / "other_sensitivities.py").exists()


def test_build_command_writes_the_companion(tmp_path, capsys):
    assert main(["build", FOURBAR, "-o", str(tmp_path), "--sensitivities"]) in (0, None)
    out = capsys.readouterr().out
    companion = tmp_path / "fourbar_sensitivities.py"
    assert companion.is_file() and str(companion) in out
    assert _hash(companion) == _hash(tmp_path / "fourbar.py")
    mech = mechgen.load(str(tmp_path / "fourbar.py"), tier="python")
    s = mech.solve(0.1, sensitivities=True)      # no symbolic side: the file must be there
    assert np.all(np.isfinite(s.dq_dp))


def test_a_plain_build_writes_none(tmp_path):
    assert main(["build", FOURBAR, "-o", str(tmp_path)]) in (0, None)
    assert not (tmp_path / "fourbar_sensitivities.py").exists()
    mech = mechgen.load(str(tmp_path / "fourbar.py"), tier="python")
    with pytest.raises(MechgenError, match="sensitivities"):
        mech.solve(0.1, sensitivities=True)


def test_a_pruned_build_with_sensitivities_is_refused(tmp_path, capsys):
    code = main(["build", FOURBAR, "-o", str(tmp_path), "--sensitivities", "--outputs",
                 "nothing"])
    assert code not in (0, None)
    assert "--outputs" in capsys.readouterr().err
    assert not os.listdir(tmp_path) or not (tmp_path / "fourbar_sensitivities.py").exists()


def test_the_parameters_asked_are_read_again_at_every_solve(tmp_path):
    """A list of parameter names changed in place between two solves is read afresh (the
    last question is remembered by identity and value), and another module's mechanism
    gets its own columns."""
    mech = mechgen.compile(FOURBAR, outdir=str(tmp_path), tier="python", sensitivities=True)
    names = list(mech.parameter_names)
    asked = [names[0]]
    first = mech.solve(0.1, sensitivities=asked)
    asked[:] = [names[2], names[1]]
    second = mech.solve(0.1, sensitivities=asked)
    assert first.sensitivities.params == (names[0],)
    assert second.sensitivities.params == (names[2], names[1])
    both = mech.solve(0.1, sensitivities=True)
    assert np.array_equal(second.dq_dp, both.dq_dp[:, [2, 1]])
    assert np.array_equal(first.dq_dp, both.dq_dp[:, [0]])
