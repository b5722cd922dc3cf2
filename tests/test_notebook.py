"""examples/quick_return.ipynb, the walk through seed 001, runs (nbclient, a fresh kernel, from
examples/ as Jupyter starts it), prints the seed's numbers, and renders its LaTeX; the
committed copy carries its outputs. ``--update-golden`` writes the executed notebook back."""
import copy
import os
import re

import nbformat
import pytest
from matplotlib.mathtext import MathTextParser
from nbclient import NotebookClient

from conftest import EXAMPLES, ROOT

NOTEBOOK = os.path.join(EXAMPLES, "quick_return.ipynb")

# What seed 001 prints, as the notebook prints it (Mech's 6 digits), by section.
SEED = {
    "positions": ["Th3 -> -0.54042, X4 -> 9.07905", "Th2 -> 3.14159", "X4 -> -0.181877",
                  "Th2 -> 5.34071", "Th3 -> -0.600822, X4 -> 9.37314"],
    "assembly modes": ["X4 -> 0.802632"],
    "output functions": ["{-1.05511, 8.93794}", "{-3.03987, 8.47108}", "11.0022", "9.38401",
                         "0.58617", "12.2638", "{0, 9.16729}", "{-1.15799, 8.91557}",
                         "{4.62876, 1.89067}", "13.3458", "{2.81812, 18}", "{3, 8}",
                         "{10.1639, 1.39095}", "Magnitude[link] /. LastSolve[] = 5",
                         "Abs(longitud) = 3"],
    "velocities": ["Th2 -> 0.942478", "X4 -> 6.92194", "Th2d -> 6.28319", "Th3d -> 2.27897",
                   "X4d -> -18.7395", "-15.1909"],
    "accelerations": ["Th3 -> -0.233107", "Th3dd -> 1.64018", "X4dd -> -40.9024", "-19.056"],
    "stroke": ["T = 0.602307 and 0.897082", "-1.26516 and 9.54378", "half stroke 5.40447",
               "centre 4.13931"],
    "slider": ["Th2 -> 1.7945", "Th3 -> 0.083778, X4 -> 4.13931", "lock at T = 0.246486",
               "lock at T = 0.253514", "lock at T = 0.741546", "lock at T = 0.758454",
               "Th2 -> -0.611293", "Th3 -> -0.643121, X4 -> 9.54111", "-35.0245", "53.1519",
               "88.1764", "SolveMech[.249]: ConvergenceError"],
    "equations": ["-6.28319 T + Th2 = 0", "34 Sin[Th4] = 0", "X4 - 5.40447 Sin[2 Pi T] - 4.13931 = 0"],
}
SECTIONS = ["(1) Bodies", "(2A) Constraints", "(2) The constraint equations", "(3) Position",
            "(3) Assembly modes", "(4) The drawing", "(5) Output functions", "(5) Time plots",
            "(6) Velocities", "(7) Accelerations", "The stroke", "(2B) The slider-driven",
            "(3B) The lock points", "(8) Forces"]


def texts(nb, kind="text"):
    """Every stdout stream and text/plain result (kind "text"), or every text/latex output."""
    out = []
    for cell in nb.cells:
        for o in cell.get("outputs", []):
            if kind == "text" and o.output_type == "stream" and o.name == "stdout":
                out.append(o.text)
            elif o.output_type in ("execute_result", "display_data"):
                key = "text/plain" if kind == "text" else "text/latex"
                if key in o.data:
                    out.append(o.data[key])
    return out


def check_outputs(nb):
    errors = [o for c in nb.cells for o in c.get("outputs", []) if o.output_type == "error"]
    assert not errors, errors[0].get("evalue")
    text = "\n".join(texts(nb))
    missing = [f"{section}: {n}" for section, numbers in SEED.items() for n in numbers
               if n not in text]
    assert not missing, "the notebook does not print " + "; ".join(missing)
    pictures = sum("image/png" in o.get("data", {}) for c in nb.cells
                   for o in c.get("outputs", []))
    assert pictures >= 8
    check_latex(texts(nb, "latex"))


def check_latex(outputs):
    """The model's LaTeX: Φ_1 .. Φ_9, each row well formed; every row parses as math."""
    model = next(t for t in outputs if r"\Phi_{1}" in t)
    for i in range(1, 10):
        assert rf"\Phi_{{{i}}} &=" in model
    assert r"\frac{\partial \Phi_{6}}{\partial \theta_{3}}" in model
    assert r"\gamma_{9}" in model and r"\nu_{3}" in model
    parser = MathTextParser("path")
    rows = 0
    for text in outputs:
        assert text.count("{") == text.count("}"), "unbalanced braces"
        assert text.count(r"\begin{align*}") == text.count(r"\end{align*}")
        for line in text.splitlines():
            if "&=" not in line and not line.startswith("$\\displaystyle"):
                continue
            body = line.strip().strip("$").removesuffix("\\\\").replace("&", "")
            body = body.replace(r"\displaystyle", "")
            assert body.count("{") == body.count("}"), line
            if r"\begin{matrix}" in body:      # sympy's Matrix: MathJax's, not mathtext's
                continue
            parser.parse(f"${body}$", dpi=72)          # raises ValueError if not valid
            rows += 1
    assert rows >= 45


def test_committed_notebook_has_its_outputs():
    nb = nbformat.read(NOTEBOOK, as_version=4)
    nbformat.validate(nb)
    headings = "\n".join(c.source for c in nb.cells if c.cell_type == "markdown")
    for section in SECTIONS:
        assert f"## {section}" in headings, section
    check_outputs(nb)
    # nothing of the machine it ran on
    assert ROOT not in "\n".join(texts(nb))


@pytest.mark.slow
def test_notebook_runs_and_prints_the_seed(monkeypatch, update_golden):
    nb = nbformat.read(NOTEBOOK, as_version=4)
    fresh = copy.deepcopy(nb)
    for cell in fresh.cells:
        if cell.cell_type == "code":
            cell.outputs, cell.execution_count = [], None
    # the kernel imports this checkout's mechgen, and draws off screen
    monkeypatch.setenv("PYTHONPATH", ROOT + os.pathsep + os.environ.get("PYTHONPATH", ""))
    client = NotebookClient(fresh, timeout=300, kernel_name="python3", record_timing=False,
                            resources={"metadata": {"path": EXAMPLES}})
    client.execute()
    check_outputs(fresh)
    # the same cells, the same printed numbers (to 6 digits) as the committed copy
    assert [c.source for c in fresh.cells] == [c.source for c in nb.cells]
    if update_golden:
        nbformat.write(fresh, NOTEBOOK)
    else:
        def numbers(book):       # to Mech's 6 digits: the last bits may differ by machine
            return [f"{float(x):.6g}" for x in re.findall(r"-?\d+\.\d+", "\n".join(
                t for t in texts(book) if not t.startswith("<Figure")))]
        assert numbers(fresh) == numbers(nb), "the committed notebook's outputs are stale: " \
            "run tests/test_notebook.py with --update-golden"
