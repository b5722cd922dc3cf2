"""Closed forms of the committed example mechanisms, written out here independently of
mechgen (mpmath, at any precision): the reference values of the tests that check mechgen's
numbers. Coordinates in the models' order [X2, Y2, Th2, X3, Y3, Th3, X4, Y4, Th4]."""
import math

import mpmath as mp
import numpy as np


def quick_return(t, longitud=3, velocidad=None, anguloI=0, side=1):
    """examples/quick_return.py (seed 001, crank-driven) at T = t: the crank pin
    P = (L cos θ, 5 + L sin θ), θ = velocidad·T + anguloI, about the pivot (0, 5); the lever
    (colisa) about the origin through P, its end 9 P/|P|; the slider on y = 10 at 5 from
    the lever's end, on the side of larger x (side=1: the seed's assembly mode) or of
    smaller x (side=-1: the other)."""
    velocidad = 2 * mp.pi if velocidad is None else velocidad
    th = velocidad * t + anguloI
    px, py = longitud * mp.cos(th), 5 + longitud * mp.sin(th)
    r = mp.hypot(px, py)
    x4 = 9 * px / r + side * mp.sqrt(25 - (10 - 9 * py / r) ** 2)
    return [0, 5, th, 0, 0, mp.atan2(-px, py), x4, 10, 0]


def quick_return_torque(t, bodies, g=9.807, cut=0.0, longitud=3):
    """The crank torque of the crank-driven quick-return (quick_return, θ = 2πT + 0) by the
    power balance τ θ̇ = d/dt (kinetic + potential energy) − P_cut, differentiated by
    mpmath. ``bodies``: {"manivela" | "colisa" | "deslizadera": (mass, inertia about the
    centroid, centroid in local axes)} (the crank's origin at its pivot (0, 5), the
    lever's at the origin, the slider's at its pin on y = 10); gravity g along −y;
    ``cut``: a force (cut, 0) on the slider's pin while it moves back (ẋ4 < 0)."""
    def frames(u):
        q = quick_return(u, longitud)
        return {"manivela": (q[0], q[1], q[2]), "colisa": (q[3], q[4], q[5]),
                "deslizadera": (q[6], q[7], q[8])}

    def centroid(u, name, k):
        x, y, th = frames(u)[name]
        c = bodies[name][2]
        return (x + mp.cos(th) * c[0] - mp.sin(th) * c[1],
                y + mp.sin(th) * c[0] + mp.cos(th) * c[1], th)[k]

    def energy(u):
        kinetic = potential = 0
        for name, (mass, inertia, _) in bodies.items():
            vx, vy, w = (mp.diff(lambda v: centroid(v, name, k), u) for k in range(3))
            kinetic += 0.5 * mass * (vx ** 2 + vy ** 2) + 0.5 * inertia * w ** 2
            potential += mass * g * centroid(u, name, 1)
        return kinetic + potential

    with mp.workdps(30):
        tt = mp.mpf(t)
        x4d = mp.diff(lambda v: quick_return(v, longitud)[6], tt)
        cutting = cut * x4d if x4d < 0 else 0
        return float((mp.diff(energy, tt) - cutting) / (2 * mp.pi))


def motion(fn, t, dps=30):
    """q, q̇, q̈ (float arrays) of a closed form fn(t) at t, differentiated by mpmath."""
    with mp.workdps(dps):
        tt = mp.mpf(t)
        n = len(fn(tt))
        parts = [lambda u, k=k: fn(u)[k] for k in range(n)]
        return tuple(np.array([float(mp.diff(f, tt, order)) for f in parts])
                     for order in (0, 1, 2))


def slider_driven_configurations(t, centro=4.13931, amplitud=5.40447, longitud=3.0):
    """Every configuration of examples/quick_return_slider.py at T = t, as (Th2, Th3, X4)
    with the angles in (−π, π]: the slider at X4 = centro + amplitud sin 2πT on y = 10;
    the lever's end E = 9 (−sin φ, cos φ) lies 5 from it, so
    18 X4 sin φ − 180 cos φ = −156 − X4² (two φ at most); the crank pin, on the lever's
    line at s (−sin φ, cos φ), lies L from the pivot (0, 5): s² − 10 s cos φ + 25 − L² = 0
    (two s at most)."""
    x4 = centro + amplitud * math.sin(2 * math.pi * t)
    a, b, c = 18 * x4, -180.0, -156.0 - x4 ** 2
    R, beta = math.hypot(a, b), math.atan2(b, a)         # a sin φ + b cos φ = R sin(φ + β)
    if abs(c / R) > 1:
        return []
    out = []
    for phi in {math.remainder(math.asin(c / R) - beta, 2 * math.pi),
                math.remainder(math.pi - math.asin(c / R) - beta, 2 * math.pi)}:
        disc = 25 * math.cos(phi) ** 2 - (25 - longitud ** 2)
        if disc < 0:
            continue                                     # the crank cannot reach the line
        for s in {5 * math.cos(phi) + math.sqrt(disc), 5 * math.cos(phi) - math.sqrt(disc)}:
            px, py = -s * math.sin(phi), s * math.cos(phi)
            out.append((math.atan2(py - 5, px), phi, x4))
    return sorted(out)
