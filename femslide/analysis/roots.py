"""Scalar root finding in pure Python (no numpy: the spring-hinge scenes must start fast).

:func:`first_crossing` finds the *first* sign change of ``g`` away from 0 along a direction: the
equilibrium reached by ramping the load from zero is the first root of dPi/dphi met when phi grows
from 0 (the load-deflection curve is followed from the origin).
"""
from __future__ import annotations


class NoRoot(RuntimeError):
    """No sign change was found where one was expected."""


def brent(f, a: float, b: float, fa: float | None = None, fb: float | None = None,
          xtol: float = 0.0, rtol: float = 4e-16, maxiter: int = 200) -> tuple[float, int]:
    """Brent's method on a bracket [a, b] with f(a) f(b) <= 0.  Returns (root, evaluations)."""
    fa = f(a) if fa is None else fa
    fb = f(b) if fb is None else fb
    if fa == 0.0:
        return a, 0
    if fb == 0.0:
        return b, 0
    if (fa > 0) == (fb > 0):
        raise NoRoot(f"no sign change on [{a:g}, {b:g}]")
    c, fc = a, fa
    d = e = b - a
    for it in range(1, maxiter + 1):
        if (fb > 0) == (fc > 0):
            c, fc = a, fa
            d = e = b - a
        if abs(fc) < abs(fb):
            a, b, c = b, c, b
            fa, fb, fc = fb, fc, fb
        tol = 2.0 * rtol * abs(b) + 0.5 * xtol
        m = 0.5 * (c - b)
        if abs(m) <= tol or fb == 0.0:
            return b, it
        if abs(e) >= tol and abs(fa) > abs(fb):
            s = fb / fa
            if a == c:
                p, q = 2.0 * m * s, 1.0 - s
            else:
                q_, r = fa / fc, fb / fc
                p = s * (2.0 * m * q_ * (q_ - r) - (b - a) * (r - 1.0))
                q = (q_ - 1.0) * (r - 1.0) * (s - 1.0)
            if p > 0:
                q = -q
            else:
                p = -p
            if 2.0 * p < min(3.0 * m * q - abs(tol * q), abs(e * q)):
                e, d = d, p / q
            else:
                d = e = m
        else:
            d = e = m
        a, fa = b, fb
        b += d if abs(d) > tol else (tol if m > 0 else -tol)
        fb = f(b)
    raise NoRoot(f"Brent did not converge in {maxiter} iterations")


def first_crossing(g, x_start: float, x_max: float, grow: float = 1.3) -> tuple[float, int]:
    """First x in (0, x_max] where g changes sign from negative to non-negative.

    ``g(0) < 0`` is assumed; the scan starts at ``x_start`` (well below the root) and grows
    geometrically.  Raises :class:`NoRoot` when g stays negative up to ``x_max``.
    """
    lo, glo = 0.0, -1.0
    x = min(x_start, x_max)
    n = 0
    while True:
        gx = g(x)
        n += 1
        if gx >= 0.0:
            root, k = brent(g, lo, x, fa=None if lo == 0.0 else glo, fb=gx)
            return root, n + k
        if x >= x_max:
            raise NoRoot(f"no equilibrium found up to {x_max:g}")
        lo, glo = x, gx
        x = min(x * grow, x_max)
