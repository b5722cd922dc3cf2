"""Every Python block of the user guide and the getting-started page runs as printed: the
blocks of a page in order, in one fresh interpreter, from the top of the repository (where
the pages say to run them), in the plain-Python tier (nothing waits for numba) but where
a page's design tables ask for the compiled one. A block that is only a fragment says so
with ``<!-- not run: why -->`` on the line before it; a ``__main__`` guard's body (a
script's part that starts worker processes) is not run."""
import os
import subprocess
import sys

import pytest

from docs_pages import ROOT, guide_pages, page, python_blocks

# pages whose tables are too large for the plain-Python tier: the compiled one, whose
# cache the other tests fill for the repository's generated/ modules
COMPILED = {"guide/design.md"}
RUNNER = ("import sys\n"
          "path = sys.argv[1]\n"
          "code = compile(open(path, encoding='utf-8').read(), path, 'exec')\n"
          "exec(code, {'__name__': 'guide_page'})\n")


@pytest.mark.slow
@pytest.mark.parametrize("name", guide_pages())
def test_the_page_runs_as_printed(name, tmp_path):
    blocks = python_blocks(page(name))
    assert blocks, f"docs/{name} has no Python block to run"
    script = tmp_path / (os.path.basename(name)[:-3].replace("-", "_") + ".py")
    script.write_text("\n\n".join(blocks), encoding="utf-8")
    env = dict(os.environ, MPLBACKEND="Agg", MECHGEN_CACHE=str(tmp_path / "cache"),
               MECHGEN_TIER="auto" if name in COMPILED else "python")
    env["PYTHONPATH"] = ROOT + os.pathsep + env.get("PYTHONPATH", "")
    got = subprocess.run([sys.executable, "-c", RUNNER, str(script)], cwd=ROOT, env=env,
                         capture_output=True, text=True, timeout=900)
    assert got.returncode == 0, f"docs/{name}:\n{got.stderr[-3000:]}"


def test_a_fragment_says_why_it_is_not_run():
    for name in guide_pages():
        text = page(name)
        every, runnable = python_blocks(text, runnable=False), python_blocks(text)
        skipped = len(every) - len(runnable)
        assert text.count("<!-- not run: ") == skipped, \
            f"docs/{name}: a 'not run' mark that is not right above a python block"
