"""Design tables: a sweep over time for every design (``design``), where they run
(``backends``: threads over ``chunks`` of designs, ``dask_backend``, the GPU: ``cuda``,
the kernels' dispatch and tables, ``cuda_twin``, the generated module's functions as
numba.cuda device code, ``cuda_forces``, force tables reduced in the kernel; numba.cuda
is imported only when a CUDA table is asked for, see docs/cuda.md), per-design reductions and statuses (``reduce``), exact extremes
(``refine``) and dimensional synthesis on top of them (``synthesis``: mech.optimize)."""
