"""PointOnLines2, OriginLock2 and DirectedDistance1 in one small mechanism.

A crank turns about the origin (θ = ω T). A block's origin is held where the crank's axis
crosses the ground's vertical line x = h (point_on_lines): its height is h tan θ. A cover
is locked to the block's origin (origin_lock) and tilted so that its point P1, one unit
along its x axis, stands d(T) = k sin(2π T) above its origin (directed_distance, measured
along the global y): its angle is asin(k sin(2π T))."""
from mechgen import Model, T, pi, sin

m = Model("yoke")
h = m.param("h", 2.0)
k = m.param("k", 0.5)
omega = m.param("omega", pi / 4)
base = m.ground("base", points=[(0, 0), (h, 0), (h, 1)])
crank = m.body("crank", points=[(0, 0), (1, 0)], guess=(0, 0, 0.1))
block = m.body("block", points=[(0, 0), (0.4, 0)], guess=(2, 0.2, 0))
cover = m.body("cover", points=[(1, 0)], guess=(2, 0.2, 0.1))
m.revolute(base[1], crank[1])
m.rotation_lock(crank, omega * T, name="input")
m.point_on_lines(block[0], base.line(2, 3), crank.line(1, 2))
m.rotation_lock(block, 0)
m.origin_lock(cover, block)
m.directed_distance(cover[1], cover[0], (0, 1), k * sin(2 * pi * T), name="tilt")
