"""A four-bar's defects decided by mechgen's own solver: its model built and swept.

The closed form (defects.py) reads the defects off the loop's geometry. This check asks the
compiled model instead, the way a user's sweep would meet them:

- the model (FourBar.model, the crank turning counter-clockwise) is started in pose 1's
  configuration and swept a whole turn of the crank each way, the solver keeping the
  branch; a lock (toggle) stops the sweep (the solver finds no configuration past it), and
  a point reached by a branch jump or through a singular configuration ends the stretch
  that counts (the motion beyond it is not the one pose 1 starts);
- pose j is *reached* where the sweep, at the crank angle of pose j, puts the coupler frame
  on pose j (to ``MATCH`` of the poses' size);
- each pose's assembly mode is the sign of det Φ_q (row-scaled) at its configuration: the
  solver's own branch indicator, which changes sign only through a singular configuration.

Then: *circuit* when a pose's mode differs from pose 1's; *branch* when a pose in pose 1's
mode is not reached either way (a toggle lies between); *order* when the poses reached are
not met in the given order while the crank turns one way.

One model is compiled per ``SolverCheck`` and every four-bar checked with it runs on
``mech.with_params`` (the four-bar's dimensions are the model's parameters) from its own
pose-1 configuration (``set_guess``): the module is built once."""
from __future__ import annotations

import math
import shutil
import tempfile
import weakref
from dataclasses import dataclass

import numpy as np

from ..errors import MechgenError
from ..protocol import OK
from ..runtime.analysis.singular import det_indicator
from .poses import place, spread

TWO_PI = 2 * math.pi
MATCH = 1e-7            # a sweep point on a pose: its frame within this (relative) of it
STEPS = 360             # sweep points per turn of the crank (the poses' angles added)
MAXIT = 12              # Newton iterations a sweep point may take (a lock fails fast)


@dataclass(frozen=True)
class Verdict:
    """What the solver found for a four-bar: ``defects`` (a frozenset drawn from {"circuit",
    "branch", "order"}), ``times`` (the model time at which the sweep from pose 1 reaches
    each pose, the crank turning counter-clockwise: negative where it is reached turning
    clockwise, NaN where it is not reached; a crank turning all the way round is taken
    the way that meets the poses in order), ``modes`` (each pose's sign of det Φ_q),
    ``stops`` (the last times, forward and backward, that the sweeps from pose 1 reached
    on its branch before a lock stopped them; None where one turned a whole turn) and
    ``full`` (the crank turns all the way round on pose 1's branch)."""
    defects: frozenset
    times: tuple
    modes: tuple
    stops: tuple
    full: bool


class SolverCheck:
    """Decides four-bars' defects with one compiled model. ``tier`` as for mechgen.load
    ("python": the module run as plain Python, no numba compile wait); ``outdir`` the
    folder the module is built in (a fresh temporary one by default); ``mech``: an
    already compiled model of FourBar.model(direction=1) to reuse instead."""

    def __init__(self, tier="python", outdir=None, mech=None, steps=STEPS):
        self.tier, self.outdir, self.mech = tier, outdir, mech
        self.steps = int(steps)

    def _built(self, fourbar):
        if self.mech is None:
            from ..bridge import compile_model
            outdir = self.outdir
            if outdir is None:          # ours: removed when this check is done with
                outdir = tempfile.mkdtemp(prefix="mechgen_synthesis_")
                weakref.finalize(self, shutil.rmtree, outdir, True)
            self.mech = compile_model(fourbar.model("fourbar_check", direction=1),
                                      outdir=outdir, tier=self.tier)
        return self.mech

    def __call__(self, fourbar) -> Verdict:
        """The Verdict on ``fourbar`` (a synthesis.FourBar)."""
        mech = self._built(fourbar)
        m = mech.with_params(**parameters(fourbar))
        configs = [configuration(fourbar, j) for j in range(len(fourbar.poses))]
        phis = np.array([c["Th2"] for c in configs])
        phi1 = phis[0]
        m.set_guess(configs[0], t=0.0)
        ahead = (phis - phi1) % TWO_PI
        behind = (phi1 - phis) % TWO_PI
        ahead[0] = behind[0] = 0.0
        fwd, stop_f = _branch(m, ahead, self.steps, 1)
        bwd, stop_b = _branch(m, behind, self.steps, -1)
        full = stop_f is None and stop_b is None
        size = spread(fourbar.poses) + max(fourbar.lengths)
        modes = tuple(_mode(m, configs[j], way * t)
                      for j, (way, t) in enumerate(zip(np.where(ahead <= behind, 1, -1),
                                                       np.minimum(ahead, behind))))
        defects = set()
        if len(set(modes)) > 1:
            defects.add("circuit")
        times = np.full(len(phis), np.nan)
        for j, pose in enumerate(fourbar.poses):
            on_f = _on_pose(fwd, ahead[j], pose, size)
            on_b = _on_pose(bwd, -behind[j], pose, size)
            if on_f:
                times[j] = ahead[j]
            elif on_b:
                times[j] = -behind[j]
            elif modes[j] == modes[0]:
                defects.add("branch")
        seen = ~np.isnan(times)
        if full:
            up = np.all(np.diff(ahead[seen]) > 0)
            down = np.all(np.diff(behind[seen]) > 0)
        else:
            up = np.all(np.diff(times[seen]) > 0)
            down = np.all(np.diff(times[seen]) < 0)
        if not up and not down:
            defects.add("order")
        if full and down and not up:        # met in order turning clockwise
            times = np.where(seen, -behind, np.nan)
        return Verdict(frozenset(defects), tuple(float(t) + 0.0 for t in times), modes,
                       (stop_f, stop_b), bool(full))


def defects_by_solver(fourbar, check=None, tier="python", outdir=None) -> frozenset:
    """The defects of ``fourbar`` as mechgen's solver meets them (see SolverCheck): a
    frozenset drawn from {"circuit", "branch", "order"}. ``check``: a SolverCheck to reuse
    (its compiled model) across many four-bars."""
    check = check or SolverCheck(tier=tier, outdir=outdir)
    return check(fourbar).defects


def parameters(fourbar) -> dict:
    """The model parameters (FourBar.model's) of this four-bar."""
    O2, O4 = fourbar.input.fixed, fourbar.output.fixed
    uA, uB = fourbar.input.moving, fourbar.output.moving
    a, _, c, _ = fourbar.lengths
    return dict(x_O2=O2[0], y_O2=O2[1], x_O4=O4[0], y_O4=O4[1], a=a, c=c, x_A=uA[0],
                y_A=uA[1], x_B=uB[0], y_B=uB[1], phi0=float(fourbar.phis[0]))


def configuration(fourbar, j) -> dict:
    """The model's coordinates (X2 .. Th4) with the coupler frame at pose j (0-based)."""
    pose = fourbar.poses[j]
    O2, O4 = np.asarray(fourbar.input.fixed), np.asarray(fourbar.output.fixed)
    A = place(pose, fourbar.input.moving)
    B = place(pose, fourbar.output.moving)
    return dict(X2=O2[0], Y2=O2[1], Th2=math.atan2(A[1] - O2[1], A[0] - O2[0]),
                X3=pose[0], Y3=pose[1], Th3=pose[2],
                X4=O4[0], Y4=O4[1], Th4=math.atan2(B[1] - O4[1], B[0] - O4[0]))


def _branch(m, travel, steps, way):
    """The sweep from pose 1 over a whole turn of the crank in direction ``way``, at a grid
    with the poses' travels added: (times, frames (n, 3)) of the stretch on pose 1's branch
    and the last time it reached there before it stopped (None: the whole turn)."""
    grid = np.union1d(np.linspace(0.0, TWO_PI, steps + 1), travel)
    ts = way * grid
    try:
        sw = m.sweep(None, None, None, times=ts, maxit=MAXIT)
    except MechgenError as exc:
        sw = getattr(exc, "sweep", None)
        if sw is None:
            return (np.zeros(0), np.zeros((0, 3))), 0.0
    t = np.asarray(sw.t)
    good = np.asarray(sw.status) == OK
    keep = len(t) if np.all(good) else int(np.argmin(good))
    stop = None
    if keep < len(ts):
        stop = float(t[keep - 1]) if keep else 0.0
    frames = np.column_stack([sw["X3"], sw["Y3"], sw["Th3"]])[:keep]
    return (t[:keep], frames), stop


def _on_pose(branch, t, pose, size) -> bool:
    """Whether the branch's point at time t (one of its grid's) puts the frame on pose."""
    ts, frames = branch
    k = np.nonzero(np.abs(ts - t) <= 1e-12 * (1 + abs(t)))[0]
    if k.size == 0:
        return False
    x, y, th = frames[k[0]]
    return bool(math.hypot(x - pose[0], y - pose[1]) <= MATCH * size
                and abs(math.remainder(th - pose[2], TWO_PI)) <= MATCH)


def _mode(m, config, t) -> int:
    """The sign of det Φ_q at the configuration (the crank's driver read at time t)."""
    q = np.array([config[name] for name in m.coordinates], dtype=float)
    return int(np.sign(det_indicator(m, q, t)))
