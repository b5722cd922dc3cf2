"""The user guide's sensitivity snippet (docs/guide/sensitivities.md) runs as printed (from
the top of the repository, in a fresh interpreter, plain-Python tier), and its number is the derivative: ∂X4/∂longitud
against a central difference of the slider's closed form written here (examples/
quick_return.py: the crank's pivot 5 above the lever's, the lever 9 long, the slider 5 from
its tip on the guide y = 10, ahead of it)."""
import math
import os
import subprocess
import sys

from conftest import ROOT
from docs_pages import page, python_blocks


def test_sensitivity_snippet_runs_as_printed(tmp_path):
    code = python_blocks(page("guide/sensitivities.md"))[0]
    assert code.lstrip().startswith("import mechgen")
    probe = code + ("\nprint('dX4', s.sensitivity('X4', 'longitud'))"
                    "\nprint('shape', s.dq_dp.shape, sw.sensitivity('X4', 'longitud').shape)\n")
    env = dict(os.environ, MECHGEN_CACHE=str(tmp_path / "cache"), MECHGEN_TIER="python")
    env["PYTHONPATH"] = ROOT + os.pathsep + env.get("PYTHONPATH", "")
    got = subprocess.run([sys.executable, "-c", probe], cwd=ROOT, env=env,
                         capture_output=True, text=True, timeout=600)
    assert got.returncode == 0, got.stderr[-2000:]
    out = dict(line.split(" ", 1) for line in got.stdout.splitlines() if " " in line)
    h = 1e-6
    ref = (slider_x(3.0 + h, 0.3) - slider_x(3.0 - h, 0.3)) / (2 * h)
    assert abs(float(out["dX4"]) - ref) < 1e-6 * (1 + abs(ref))
    assert out["shape"] == "(9, 2) (361,)"


def slider_x(longitud, t):
    """X4 of the quick-return in closed form."""
    th = 2 * math.pi * t
    px, py = longitud * math.cos(th), 5 + longitud * math.sin(th)
    r = math.hypot(px, py)
    tx, ty = 9 * px / r, 9 * py / r
    return tx + math.sqrt(25 - (10 - ty) ** 2)
