"""Design tables: a sweep over time for every design (``design``), where they run
(``backends``: threads over ``chunks`` of designs, ``dask_backend``, the GPU in
runtime/gpu), per-design reductions and statuses (``reduce``), exact extremes
(``refine``) and dimensional synthesis on top of them (``synthesis``: mech.optimize)."""
