"""Sensitivities over a design table: each design's points (whatever backend solved them:
threads, Dask, CUDA) go through the sensitivity module's compiled pass on this host, with
the design's own parameters, so that a table's derivatives are those of its designs'
single sweeps."""
from __future__ import annotations

import numpy as np

from ...protocol import LEVEL
from .companion import companion
from .solve import Sensitivities, parameter_columns


class TableSensitivities:
    """Per design d and point k: ``full[order][d, k]`` (coordinates × parameters), NaN past
    the points the design solved and where Φ_q had lost rank (``singular[d, k]``)."""

    def __init__(self, params, columns, full, singular):
        self.params, self.columns, self.full, self.singular = params, columns, full, singular

    def design(self, d, k) -> Sensitivities:
        """Design d's first k points as a sweep's Sensitivities."""
        return Sensitivities(self.params, self.columns,
                             tuple(None if D is None else D[d, :k] for D in self.full),
                             self.singular[d, :k])


def of_table(mech, tab, which) -> TableSensitivities:
    """The sensitivities of every design of ``tab`` (a DesignTable that kept its points)."""
    names, cols = parameter_columns(mech, which)
    comp, blocks = companion(mech)
    if not blocks.square:
        raise ValueError(f"sensitivities of a design table need a square build of "
                         f"'{mech.name}' (it has redundant equations): sweep the designs")
    level = LEVEL[tab.level]
    D, N, n, npar = len(tab), len(tab.t), mech.n, len(mech.parameter_names)
    full = [np.full((D, N, n, npar), np.nan) if order <= level else None for order in range(3)]
    singular = np.zeros((D, N), dtype=bool)
    one = np.zeros((1, n, npar))
    zero = np.zeros((1, n))
    status = np.zeros(N, dtype=np.int64)
    for d in range(D):
        k = int(tab.done[d])
        if not k:
            continue
        Q = np.ascontiguousarray(tab.Q[d, :k])
        QD = np.ascontiguousarray(tab.QD[d, :k]) if level >= 1 else zero
        QDD = np.ascontiguousarray(tab.QDD[d, :k]) if level >= 2 else zero
        parts = [full[o][d, :k] if full[o] is not None else one for o in range(3)]
        comp.sensitivities_rows(np.ascontiguousarray(tab.t[:k]), Q, QD, QDD,
                                np.ascontiguousarray(tab.P[d]), level, blocks.brow,
                                blocks.bvar, blocks.bstart, cols, *parts, status[:k])
        singular[d, :k] = status[:k] != 0
    return TableSensitivities(names, cols, tuple(full), singular)
