"""A generated module file to the tier that answers: ``loader`` (the file, its stamp,
format and version), ``caches`` (numba's cache checked before it loads), ``plain`` and
``plain_linalg`` (the module run as plain Python at once), ``warm`` and ``warmup`` (the
compiled module's entry points called once in a background process), ``tiers`` (which
tier answers, the switch to compiled code)."""
