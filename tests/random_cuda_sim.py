"""Run by tests/test_random_mechanisms.py in a subprocess with NUMBA_ENABLE_CUDASIM=1:
tiny design tables of random four-bars (tests/random_families.py) on numba's CUDA
simulator (backend="cuda"), one per level, printed as one JSON line (times, designs,
points, statuses) for the parent to judge against the closed form."""
import json
import warnings

import numpy as np

import random_checks as rc
from random_families import FOURBAR


def main():
    rng = np.random.default_rng(5)
    runs = []
    for level, variant in zip(rc.LEVELS, ("nearmiss", "grashof", "lockwin")):
        spec = rc.draw_spec(FOURBAR, rng, variant=variant, level=level, method="auto")
        spec.n = int(rng.integers(7, 12))
        spec.t1 = FOURBAR.period(spec.params)
        p = spec.params
        vals = {"w": [p["w"], 1.3 * p["w"]], "b": [p["b"], p["b"] * (1 + 1e-3)]}
        q0 = FOURBAR.exact(p, spec.sigma, np.array([0.0]), 0)[0][0]
        mech = FOURBAR.mech().with_params(**p)
        designs = [dict(p, w=w, b=b) for w, b in zip(vals["w"], vals["b"])]
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                tab = mech.sweep(0.0, spec.t1, spec.n, params=vals, grid=False, guess=q0,
                                 level=level, backend="cuda", on_fail="ignore")
        except rc.REFUSALS:
            runs.append({"spec": str(spec), "refused": True})
            continue
        sws = [tab.sweep(d) for d in range(len(designs))]
        n = len(tab.t)

        def full(get):
            if get(sws[0]) is None:
                return None
            out = np.full((len(sws), n, len(FOURBAR.coords)), np.nan)
            for d, sw in enumerate(sws):
                out[d, :len(sw)] = get(sw)
            return out.tolist()
        status = np.zeros((len(sws), n), dtype=int)
        for d, sw in enumerate(sws):
            status[d, :len(sw)] = sw.status
        runs.append({"spec": str(spec), "designs": designs, "t": tab.t.tolist(),
                     "done": [int(x) for x in tab.done], "status": status.tolist(),
                     "Q": full(lambda s: s.Q), "QD": full(lambda s: s.QD),
                     "QDD": full(lambda s: s.QDD)})
    print(json.dumps(runs))


if __name__ == "__main__":
    main()
