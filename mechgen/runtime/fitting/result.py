"""What ``mech.fit`` returns (docs/reference/sensitivities.md): the design chosen, how close it
passes the targets, when, and what the search cost."""
from __future__ import annotations

import numpy as np


class FitResult:
    """A fitted design.

    ``params``: {name: value} of every parameter chosen; ``error``: the RMS distance of
    the point from the targets; ``times``: the k times at which the point passes them
    under the model's own drivers (the given ones with prescribed timing); ``positions``:
    the point there, (k, 2); ``mechanism``: the mechanism with the fitted parameters, its
    guess the configuration at the earliest of ``times`` (its solves and sweeps stay on
    the assembly mode that passes the targets); ``evaluations``: designs evaluated (each
    design of the global stage's tables, and each Levenberg–Marquardt evaluation: one
    design solved, with its derivatives, at the k times); ``designs``: those of the global
    stage alone; ``starts``: the candidates refined by least squares; ``seconds``: wall
    time; ``timing``: "free" or "prescribed"; ``message``: how the search ended."""

    def __init__(self, **fields):
        self.__dict__.update(fields)

    def __repr__(self):
        values = ", ".join(f"{k}={v:.10g}" for k, v in self.params.items())
        return (f"<FitResult {values}: RMS error {self.error:.3g} over "
                f"{len(self.times)} targets ({self.timing} timing), {self.evaluations} "
                f"evaluations in {self.seconds:.2f} s>")

    @property
    def residuals(self) -> np.ndarray:
        """The point minus the targets at ``times``: (k, 2)."""
        return self.positions - self.targets
