"""Second-order jets (value, first and second time derivative) on numpy arrays: the
closed forms of tests/random_families.py are written once with these, and give
positions, velocities and accelerations exactly (to rounding) by the chain rule, without
sympy's differentiation of nested circle intersections (minutes for a six-bar) and
without mechgen's equations."""
import numpy as np


class Jet:
    """f, f', f'' at the same times (numpy arrays or floats)."""
    __slots__ = ("v", "d", "dd")
    __array_ufunc__ = None          # numpy scalars and arrays defer to the jet

    def __init__(self, v, d=0.0, dd=0.0):
        self.v, self.d, self.dd = v, d, dd

    def __add__(self, o):
        if isinstance(o, Jet):
            return Jet(self.v + o.v, self.d + o.d, self.dd + o.dd)
        return Jet(self.v + o, self.d, self.dd)

    __radd__ = __add__

    def __neg__(self):
        return Jet(-self.v, -self.d, -self.dd)

    def __sub__(self, o):
        return self + (-o)

    def __rsub__(self, o):
        return (-self) + o

    def __mul__(self, o):
        if isinstance(o, Jet):
            return Jet(self.v * o.v, self.d * o.v + self.v * o.d,
                       self.dd * o.v + 2 * self.d * o.d + self.v * o.dd)
        return Jet(self.v * o, self.d * o, self.dd * o)

    __rmul__ = __mul__

    def _recip(self):
        v = self.v
        return Jet(1 / v, -self.d / v ** 2, -self.dd / v ** 2 + 2 * self.d ** 2 / v ** 3)

    def __truediv__(self, o):
        if isinstance(o, Jet):
            return self * o._recip()
        return Jet(self.v / o, self.d / o, self.dd / o)

    def __rtruediv__(self, o):
        return self._recip() * o

    def __pow__(self, n):
        if n != 2:
            raise ValueError("jets: only squares")
        return self * self


def _chain(u, f, f1, f2):
    """g(u) from g, g', g'' evaluated at u's value."""
    if not isinstance(u, Jet):
        return f
    return Jet(f, f1 * u.d, f2 * u.d ** 2 + f1 * u.dd)


def sqrt(u):
    v = u.v if isinstance(u, Jet) else u
    with np.errstate(invalid="ignore", divide="ignore"):
        r = np.sqrt(v)
        return _chain(u, r, 0.5 / r, -0.25 / (r * v))


def sin(u):
    v = u.v if isinstance(u, Jet) else u
    s, c = np.sin(v), np.cos(v)
    return _chain(u, s, c, -s)


def cos(u):
    v = u.v if isinstance(u, Jet) else u
    s, c = np.sin(v), np.cos(v)
    return _chain(u, c, -s, -c)


def asin(u):
    v = u.v if isinstance(u, Jet) else u
    with np.errstate(invalid="ignore", divide="ignore"):
        w = 1 - v * v
        return _chain(u, np.arcsin(v), 1 / np.sqrt(w), v / (w * np.sqrt(w)))


def atan2(y, x):
    """The angle of (x, y): θ' = (x y' − y x')/(x² + y²), θ'' its derivative."""
    if not isinstance(y, Jet):
        y = Jet(y)
    if not isinstance(x, Jet):
        x = Jet(x)
    D = x.v ** 2 + y.v ** 2
    N = x.v * y.d - y.v * x.d
    N1 = x.v * y.dd - y.v * x.dd
    D1 = 2 * (x.v * x.d + y.v * y.d)
    return Jet(np.arctan2(y.v, x.v), N / D, (N1 * D - N * D1) / D ** 2)
