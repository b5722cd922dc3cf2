"""Run by tests/test_sensitivity_tables.py in a subprocess with NUMBA_ENABLE_CUDASIM=1 (numba
reads it when first imported): a design table with sensitivities on backend="cuda" (numba's
CUDA simulator) against each design's own sweep with sensitivities on the CPU, printed as
one JSON line: the largest difference of every derivative."""
import json
import os
import sys
import warnings

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, ROOT)

import mechgen  # noqa: E402


def main():
    folder = sys.argv[1]
    import shutil
    shutil.copy(os.path.join(ROOT, "examples", "fourbar.py"), os.path.join(folder, "model.py"))
    mech = mechgen.compile(os.path.join(folder, "model.py"), outdir=folder, tier="python")
    params = {"a": [0.7, 0.8], "c": [1.9, 2.1]}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        tab = mech.sweep(0.0, 0.5, 6, level="acceleration", params=params, backend="cuda",
                         sensitivities=["a", "d"])
    worst = 0.0
    for i, a in enumerate(params["a"]):
        for j, c in enumerate(params["c"]):
            sw = mech.with_params(a=a, c=c).sweep(0.0, 0.5, 6, level="acceleration",
                                                  sensitivities=["a", "d"])
            for name in ("Th3", "Th4d", "X3dd"):
                for p in ("a", "d"):
                    diff = np.max(np.abs(tab.sensitivity(name, p)[i, j] - sw.sensitivity(name, p)))
                    worst = max(worst, float(diff))
    print(json.dumps({"worst": worst, "shape": list(tab.sensitivity("Th3", "a").shape)}))


if __name__ == "__main__":
    main()
