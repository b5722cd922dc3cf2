"""Design tables on an NVIDIA GPU (``backend="cuda"``): ``cuda`` (the kernels' dispatch,
the tables that keep every point or reduce them), ``cuda_twin`` (the generated module's
functions translated into numba.cuda device code, its kernels cached on disk),
``cuda_forces`` (force tables whose driver efforts are reduced in the kernel). numba.cuda
is imported only when a CUDA table is asked for; see docs/cuda.md."""
