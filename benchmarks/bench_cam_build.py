"""Cold builds of the cam examples: `python -m mechgen build EXAMPLE --force -o TMP` in a
fresh process each time (an empty output folder, no manifest), wall and CPU (user + sys)
seconds, interleaved rounds, the best and the median of each. With ``--baseline DIR`` (a
checkout of another mechgen, e.g. an export of main) the same builds run with that code
too, interleaved, so that both see the same load: on a shared machine other work only adds
time, so the best is the figure least disturbed by it, and the CPU time is less disturbed
than the wall time.

    python benchmarks/bench_cam_build.py                        # 5 rounds
    python benchmarks/bench_cam_build.py --rounds 3 --baseline /tmp/main_export
"""
from __future__ import annotations

import argparse
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
EXAMPLES = ["cam_cycloidal", "cam_roller_arm", "cam_eccentric"]


def build_once(code, example):
    """(wall, cpu) seconds of one cold build of examples/EXAMPLE.py with the mechgen at
    ``code``."""
    env = dict(os.environ, PYTHONPATH=code)
    with tempfile.TemporaryDirectory() as out:
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        t = time.perf_counter()
        subprocess.run([sys.executable, "-m", "mechgen", "build",
                        os.path.join(ROOT, "examples", f"{example}.py"), "--force", "-o", out],
                       cwd=code, env=env, check=True, capture_output=True)
        wall = time.perf_counter() - t
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return wall, (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--baseline", help="a checkout of another mechgen to time beside this one")
    ap.add_argument("--examples", default=",".join(EXAMPLES))
    args = ap.parse_args(argv)
    codes = [("this", ROOT)] + ([("baseline", os.path.abspath(args.baseline))]
                                if args.baseline else [])
    examples = [e for e in args.examples.split(",") if e]
    times = {(c, e): [] for c, _ in codes for e in examples}
    for r in range(args.rounds):
        for name, code in codes:
            for e in examples:
                times[name, e].append(build_once(code, e))
        print(f"round {r + 1} done (load {os.getloadavg()[0]:.1f})", file=sys.stderr)
    print(f"{'code':9s} {'example':16s} {'wall best':>9s} {'median':>7s} {'cpu best':>9s} "
          f"{'median':>7s}")
    for (name, e), runs in times.items():
        wall, cpu = [w for w, _ in runs], [c for _, c in runs]
        print(f"{name:9s} {e:16s} {min(wall):9.2f} {statistics.median(wall):7.2f} "
              f"{min(cpu):9.2f} {statistics.median(cpu):7.2f}")


if __name__ == "__main__":
    main()
