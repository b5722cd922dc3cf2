"""Compile the backend="cuda" kernels of a generated module to PTX without a GPU, and
report their registers and stack per thread (what occupancy they allow).

    pip install nvidia-cuda-nvcc-cu12          # NVVM, libdevice and ptxas, no driver needed
    CUDA_HOME=$(python -c "import nvidia.cuda_nvcc as m; print(list(m.__path__)[0])") \\
        python benchmarks/cuda_ptx_check.py [generated/quick_return.py] [--cc 90]
    ... python benchmarks/cuda_ptx_check.py generated/quick_return_forces.py --forces
        (the force tables' kernels, dynamic and static: mechgen.runtime.tables.cuda_forces)

numba compiles a device function for the current device; with no device this script
tells it one of compute capability --cc exists (a stand-in used here only, for typing).
The PTX is then assembled by ptxas (from the same wheel) when it is found; a PTX whose
version is newer than that ptxas is lowered to it (the instructions are the same).
"""
from __future__ import annotations

import argparse
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
import types

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, ROOT)

ARR = {"f1": "float64[::1]", "f2": "float64[:,::1]", "f3": "float64[:,:,::1]",
       "i1": "int64[::1]", "i2": "int64[:,::1]", "h3": "int16[:,:,::1]"}
COMMON = "float64, float64, int64, i1, int64, int64"      # tol, xtol, maxit, SL, nsl, nord
TAIL = "f3, f2, i2, i1, i1"                               # R, QS, FL, DONE, DSTATUS
SIGNATURES = {
    "_cu_fast_reduce": f"f1, f1, f2, int64, {COMMON}, {TAIL}",
    "_cu_careful_reduce": f"f1, f2, i1, int64, int64, {COMMON}, {TAIL}",
    "_cu_fast_table": f"f1, f1, f2, int64, {COMMON}, f3, f3, f3, h3, {TAIL}",
    "_cu_careful_table": f"f1, f2, i1, int64, int64, {COMMON}, f3, f3, f3, h3, {TAIL}",
    # ts, q0, P, tol, xtol, maxit, SL, nsl, nord, DRV, R, DONE, DSTATUS
    "_cu_forces_reduce": "f1, f1, f2, float64, float64, int64, i1, int64, int64, i2, f3, i1, i1",
}


def signature(text):
    return "void(" + ", ".join(ARR.get(a.strip(), a.strip()) for a in text.split(",")) + ")"


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("module", nargs="?", default=os.path.join(ROOT, "generated", "quick_return.py"))
    ap.add_argument("--cc", default="90", help="compute capability, e.g. 80 or 90")
    ap.add_argument("--kernels", default=None, help="(default: the four kinematic kernels, "
                    "or with --forces the force kernel)")
    ap.add_argument("--forces", action="store_true", help="the force kernel of a module with "
                    "FORCE_FUSED (mechgen.runtime.tables.cuda_forces)")
    args = ap.parse_args(argv)
    cc = (int(args.cc[:-1]), int(args.cc[-1]))
    import numba.cuda.dispatcher as dispatcher
    from numba import cuda
    dispatcher.get_current_device = lambda: types.SimpleNamespace(compute_capability=cc)

    import mechgen
    from mechgen.runtime.tables.cuda import STATUS_COLUMNS, numba_module
    from mechgen.runtime.tables.cuda_twin import build_twin
    mech = mechgen.load(args.module)
    if args.forces:
        from mechgen.runtime.tables import cuda_forces
        module = numba_module(mech)
        ns = cuda_forces.twin(module, cuda=cuda)
        made = [kernel for level, (_, kernel) in cuda_forces.KERNELS.items()
                if level in cuda_forces.fused_levels(module)]
        for kernel in made:         # every force kernel takes the same arguments
            SIGNATURES.setdefault(kernel, SIGNATURES["_cu_forces_reduce"])
        kernels = args.kernels or ",".join(made)
    else:
        ns = build_twin(numba_module(mech), cuda, STATUS_COLUMNS)
        kernels = args.kernels or ",".join(k for k in SIGNATURES if k != "_cu_forces_reduce")
    home = os.environ.get("CUDA_HOME", "")
    ptxas = shutil.which("ptxas") or (os.path.join(home, "bin", "ptxas") if home else None)
    for name in kernels.split(","):
        t0 = time.perf_counter()
        ptx, _ = cuda.compile_ptx(ns[name].py_func, signature(SIGNATURES[name]), cc=cc)
        line = f"{name}: PTX {len(ptx) / 1e3:.0f} kB in {time.perf_counter() - t0:.1f} s"
        if ptxas and os.path.exists(ptxas):
            with tempfile.TemporaryDirectory() as tmp:
                path = os.path.join(tmp, "k.ptx")
                have = subprocess.run([ptxas, "--version"], capture_output=True, text=True).stdout
                m = re.search(r"release (\d+)\.(\d+)", have)
                if m and int(m.group(1)) < 13:           # ptxas 12.x reads PTX up to 8.8
                    ptx = re.sub(r"^\.version 9\.\d+", ".version 8.8", ptx, flags=re.M)
                with open(path, "w") as fh:
                    fh.write(ptx)
                res = subprocess.run([ptxas, f"-arch=sm_{args.cc}", "-v", path, "-o",
                                      os.path.join(tmp, "k.cubin")], capture_output=True, text=True)
                info = [x for x in res.stderr.splitlines() if "registers" in x]
                line += "; " + (info[-1].split(":", 1)[-1].strip() if info else res.stderr[-300:])
        print(line, flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
