"""A generated module runs where mechgen (and sympy) cannot be imported, and the runtime
never loads sympy."""
from __future__ import annotations

import glob
import json
import os
import shutil
import subprocess
import sys
import textwrap

from conftest import GENERATED

# Prepended to every subprocess script: make `import mechgen` and `import sympy` fail
# whatever the environment (an editable install, a .pth file, PYTHONPATH), and prove it.
BLOCKER = textwrap.dedent("""
    import importlib.abc, importlib.util, sys

    class _Blocker(importlib.abc.MetaPathFinder):
        BLOCKED = ("mechgen", "sympy")

        def find_spec(self, name, path=None, target=None):
            if name.split(".")[0] in self.BLOCKED:
                raise ModuleNotFoundError(f"No module named {name!r} (blocked by the test)",
                                          name=name)
            return None

    sys.meta_path.insert(0, _Blocker())
    for _name in _Blocker.BLOCKED:
        try:
            __import__(_name)
        except ImportError:
            pass
        else:
            raise SystemExit(f"{_name} is importable: the test proves nothing")
        assert _name not in sys.modules
""")

STANDALONE = textwrap.dedent("""
    import json, math, os
    sys.path.insert(0, {moddir!r})
    import numpy as np
    import quick_return as m

    assert "mechgen" not in sys.modules and "sympy" not in sys.modules
    out = {{"file": m.__file__}}
    p = np.array(m.PARAMETER_DEFAULTS, dtype=np.float64)
    idx = {{c: k for k, c in enumerate(m.COORDINATES)}}

    def solve(t, guess=None):
        q = np.array(m.GUESS, dtype=np.float64)
        for name, value in (guess or {{}}).items():
            q[idx[name]] = value
        info = np.zeros(4)
        status = m.solve_position(q, t, p, 1e-10, 1e-10, 50, 0, info)
        assert status == 0, status
        qd = np.empty(m.N_COORDS)
        assert m.solve_velocity(q, t, p, 0, qd) == 0
        qdd = np.empty(m.N_COORDS)
        assert m.solve_acceleration(q, qd, t, p, 0, qdd) == 0
        return q, qd, qdd

    for t in (0.0, 0.5, 0.85):
        q, _, _ = solve(t)
        out[f"X4@{{t}}"] = q[idx["X4"]]
        out[f"Th3@{{t}}"] = q[idx["Th3"]]
    q, _, _ = solve(0.85, {{"X4": 1.0}})
    out["X4@0.85/mode2"] = q[idx["X4"]]
    q, qd, qdd = solve(0.15)
    for name in ("Th3", "X4"):
        out[name + "d@0.15"] = qd[idx[name]]
        out[name + "dd@0.15"] = qdd[idx[name]]
    r = np.empty(m.N_EQS)
    m.phi(q, 0.15, p, r)
    out["residual@0.15"] = float(np.max(np.abs(r)))

    ts = np.linspace(0.0, 1.0, 21)
    N, n = ts.size, m.N_COORDS
    Q, QD, QDD = np.zeros((N, n)), np.zeros((N, n)), np.zeros((N, n))
    S, R = np.zeros((N, m.STATUS_COLUMNS), dtype=np.int16), np.zeros(m.REPORT_SIZE)
    done = m.sweep(ts, np.array(m.GUESS, dtype=np.float64), p, 2, 1e-10, 1e-10, 50, 0,
                   Q, QD, QDD, S, R)
    out["sweep_done"] = int(done)
    out["sweep_X4"] = Q[:, idx["X4"]].tolist()
    out["sweep_X4d_3"] = QD[3, idx["X4"]]

    assert "mechgen" not in sys.modules and "sympy" not in sys.modules
    out["modules_loaded"] = sorted(k for k in sys.modules if k.split(".")[0] in ("mechgen", "sympy"))
    print(json.dumps(out))
""")


def _close(a, b, digits=6):
    """Mech prints 6 significant digits."""
    import math
    return abs(a - b) <= 0.6 * 10 ** (math.floor(math.log10(abs(b))) - digits + 1)


def _run(script, tmp_path, cwd):
    path = tmp_path / "script.py"
    path.write_text(script)
    # -I: isolated mode (no PYTHONPATH, no user site, script dir only); cwd outside the repo
    proc = subprocess.run([sys.executable, "-I", str(path)], capture_output=True, text=True,
                          cwd=str(cwd), timeout=600)
    assert proc.returncode == 0, proc.stdout[-2000:] + proc.stderr[-4000:]
    return json.loads(proc.stdout.strip().splitlines()[-1])


def test_generated_module_runs_without_mechgen(tmp_path):
    """Copy generated/quick_return.py alone (with numba's cache of it, which is numba's, not
    mechgen's) to an empty folder and solve with it in a process where `import mechgen`
    raises ImportError: seed 001's numbers come out."""
    moddir = tmp_path / "ship"
    moddir.mkdir()
    shutil.copy2(os.path.join(GENERATED, "quick_return.py"), moddir / "quick_return.py")
    cache = glob.glob(os.path.join(GENERATED, "__pycache__", "quick_return.*.nb[ic]"))
    if cache:
        (moddir / "__pycache__").mkdir()
        for f in cache:
            shutil.copy2(f, moddir / "__pycache__" / os.path.basename(f))
    script = "import os, sys\n" + BLOCKER + STANDALONE.format(moddir=str(moddir))
    out = _run(script, tmp_path, cwd=tmp_path)
    assert os.path.dirname(out["file"]) == str(moddir)
    assert out["modules_loaded"] == []
    assert _close(out["X4@0.0"], 9.07905) and _close(out["Th3@0.0"], -0.54042)
    assert _close(out["X4@0.5"], -0.181877) and _close(out["Th3@0.5"], 0.54042)
    assert _close(out["X4@0.85"], 9.37314) and _close(out["Th3@0.85"], -0.600822)
    assert _close(out["X4@0.85/mode2"], 0.802632)
    assert _close(out["Th3d@0.15"], 2.27897) and _close(out["X4d@0.15"], -18.7395)
    assert _close(out["Th3dd@0.15"], 1.64018) and _close(out["X4dd@0.15"], -40.9024)
    assert out["residual@0.15"] < 1e-12
    assert out["sweep_done"] == 21
    x4 = out["sweep_X4"]
    assert _close(x4[0], 9.07905) and _close(x4[10], -0.181877) and _close(x4[20], 9.07905)
    assert _close(out["sweep_X4d_3"], -18.7395)      # t = 0.15


def test_blocker_really_blocks(tmp_path):
    """The blocker itself: without it mechgen imports in such a process, with it it cannot."""
    probe = textwrap.dedent("""
        import importlib.util, json
        print(json.dumps({"found": importlib.util.find_spec("mechgen") is not None}))
    """)
    out = _run("import os, sys\n" + probe, tmp_path, cwd=tmp_path)
    assert out["found"], "mechgen should be importable here without the blocker"
    blocked = textwrap.dedent("""
        import json
        try:
            import mechgen
        except ImportError as exc:
            print(json.dumps({"error": str(exc)}))
        else:
            print(json.dumps({"error": None}))
    """)
    # the blocker's own self-check would exit non-zero if mechgen were importable
    out = _run("import os, sys\n" + BLOCKER + blocked, tmp_path, cwd=tmp_path)
    assert out["error"] and "blocked" in out["error"]


RUNTIME_ONLY = textwrap.dedent("""
    import json, sys, warnings
    import mechgen
    import mechgen.runtime
    loaded = {{"import": "sympy" in sys.modules}}
    mech = mechgen.load({qr!r})
    s = mech.solve(0.15, level="acceleration")
    sw = mech.sweep(0.0, 1.0, 21, level="acceleration")
    values = [s["X4dd"], float(sw["X4d"][3]), float(sw["stroke_x"][0])]
    sw.to_csv({csv!r})
    mech.with_params(longitud=2.0).solve(0.3)
    slider = mechgen.load({slider!r})
    try:
        slider.solve(0.25)
    except (mechgen.ConvergenceError, mechgen.SingularError) as exc:
        values.append(str(exc)[:40])
    try:
        slider.sweep(0.0, 0.3, 31)
    except (mechgen.ConvergenceError, mechgen.SingularError) as exc:
        values.append(len(exc.sweep))
    loaded["solve"] = "sympy" in sys.modules
    loaded["sympy_modules"] = sorted(k for k in sys.modules if k.split(".")[0] == "sympy")[:5]
    loaded["values"] = values
    print(json.dumps(loaded, default=str))
""")


def test_runtime_never_imports_sympy(tmp_path):
    """import mechgen.runtime, load, solve, sweep, index, to_csv, with_params and failing
    solves (whose messages explain the failure) leave sympy unloaded."""
    script = RUNTIME_ONLY.format(qr=os.path.join(GENERATED, "quick_return.py"),
                                 slider=os.path.join(GENERATED, "quick_return_slider.py"),
                                 csv=str(tmp_path / "qr.csv"))
    path = tmp_path / "runtime_only.py"
    path.write_text(script)
    proc = subprocess.run([sys.executable, str(path)], capture_output=True, text=True,
                          cwd=str(tmp_path), timeout=600)
    assert proc.returncode == 0, proc.stderr[-4000:]
    out = json.loads(proc.stdout.strip().splitlines()[-1])
    assert out["import"] is False, "import mechgen.runtime loaded sympy"
    assert out["solve"] is False, f"solving loaded sympy: {out['sympy_modules']}"
    assert len(out["values"]) == 5, out["values"]      # both failures really happened
    assert (tmp_path / "qr.csv").is_file()
