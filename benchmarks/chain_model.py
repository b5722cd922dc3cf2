"""A scale family: a chain of N four-bar loops (3 bodies each, 9 coordinates per loop).

Loop k has ground pivots A_k = (3k, 0) and A_{k+1}; its crank turns about A_k, its rocker
about A_{k+1}; the crank of loop k+1 is welded to the rocker of loop k (a rotation lock),
so the first crank's driver moves the whole chain.
"""
from mechgen import Model, T, pi


def chain(n_loops: int, name: str | None = None) -> Model:
    m = Model(name or f"chain{n_loops}")
    omega = m.param("omega", 2 * pi)
    a, b, c, d = 0.8, 2.5, 2.0, 3.0
    ground = m.ground("ground", points=[(d * k, 0) for k in range(n_loops + 1)])
    previous_rocker = None
    for k in range(n_loops):
        crank = m.body(f"crank{k + 1}", points=[(0, 0), (a, 0)], guess=(d * k, 0, 1.0))
        coupler = m.body(f"coupler{k + 1}", points=[(0, 0), (b, 0)],
                         guess=(d * k + 0.4, 0.7, 0.5))
        rocker = m.body(f"rocker{k + 1}", points=[(0, 0), (c, 0)], guess=(d * (k + 1), 0, 1.8))
        m.revolute(ground[k + 1], crank[1])
        m.revolute(crank[2], coupler[1])
        m.revolute(ground[k + 2], rocker[1])
        m.revolute(coupler[2], rocker[2])
        if previous_rocker is None:
            m.rotation_lock(crank, pi / 3 + 0.25 * omega * T, name="driver")
        else:
            # the next crank is welded to this rocker at an offset that keeps it Grashof-like
            m.rotation_lock(crank, previous_rocker, -0.75, name=f"weld {k}")
        previous_rocker = rocker
    return m
