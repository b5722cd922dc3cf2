"""The user guide's analysis snippet (docs/guide/analysis.md) runs as printed (from the
top of the repository, in a fresh interpreter), and mechgen.compile writes where the guide
says and keeps its module (and
numba's cache beside it) when nothing changed."""
import glob
import os
import shutil
import subprocess
import sys

import mechgen
from mechgen.bridge import cache_folder
from conftest import GENERATED, ROOT, example_model
from docs_pages import python_blocks, section


def test_analysis_snippet_runs_as_printed(tmp_path):
    code = python_blocks(section("guide/analysis.md",
                                 "Everything seed 001 does after SolveMech"))[0]
    assert code.lstrip().startswith("import mechgen")
    assert 'mechgen.load_model("examples/quick_return.py")' in code
    # print what the snippet's bare expressions show in a notebook, to check the numbers
    probe = code + "\nprint('distance', mech.evaluate(distance(manivela[1], deslizadera[2]), s))" \
                   "\nprint('modes', len(mech.assemblies(0.85)))\n"
    # the cache folder seeded with the committed module and numba's cache of it (copies
    # keep their time stamps): compile finds the same text, keeps it, and numba reuses
    # what other tests compiled; the snippet runs as a user's second run would
    cache = tmp_path / "cache"
    (cache / "__pycache__").mkdir(parents=True)
    shutil.copy2(os.path.join(GENERATED, "quick_return.py"), cache)
    for f in glob.glob(os.path.join(GENERATED, "__pycache__", "quick_return.*.nb[ic]")):
        shutil.copy2(f, cache / "__pycache__")
    env = dict(os.environ, MECHGEN_CACHE=str(cache), MPLBACKEND="Agg")
    env["PYTHONPATH"] = ROOT + os.pathsep + env.get("PYTHONPATH", "")
    got = subprocess.run([sys.executable, "-c", probe], cwd=ROOT, env=env, capture_output=True,
                         text=True, timeout=600)
    assert got.returncode == 0, got.stderr[-3000:]
    lines = got.stdout.splitlines()
    assert [ln.split()[0] for ln in lines[:2]] == ["min", "max"]
    lo, hi = (float(ln.split()[2]) for ln in lines[:2])
    assert abs(lo + 1.2575370) < 1e-6 and abs(hi - 9.5424630) < 1e-6
    assert abs(float(lines[2].split()[1]) - 11.0022) < 5e-5     # the seed's Distance at .1
    assert lines[3] == "modes 2"
    # compile wrote where $MECHGEN_CACHE says
    assert (tmp_path / "cache" / "quick_return.py").is_file()


def test_compile_writes_to_the_cache_and_keeps_an_unchanged_module(tmp_path, monkeypatch):
    monkeypatch.setenv("MECHGEN_CACHE", str(tmp_path / "c"))
    assert cache_folder() == str(tmp_path / "c")
    monkeypatch.delenv("MECHGEN_CACHE")
    assert cache_folder() == os.path.join(os.path.expanduser("~"), ".cache", "mechgen")

    model = example_model("fourbar")
    model.name = "fourbar_cache_test"
    outdir = str(tmp_path / "out")
    path = os.path.join(outdir, "fourbar_cache_test.py")
    mechgen.compile(model, outdir=outdir, level="position")
    stamp = os.stat(path).st_mtime_ns
    os.utime(path, ns=(stamp - 10**9, stamp - 10**9))     # a second older, to see a rewrite
    mech = mechgen.compile(model, outdir=outdir, level="position")
    assert os.stat(path).st_mtime_ns == stamp - 10**9      # same text: not rewritten
    assert mech.model is model
    mechgen.compile(model, outdir=outdir, level="velocity")
    assert os.stat(path).st_mtime_ns != stamp - 10**9      # other text: rewritten
