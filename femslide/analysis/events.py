"""Locating events: bracketing root finders that place an event just after it happens.
"""
from __future__ import annotations


def _root_up(f, lo, hi, flo, fhi, xtol=1e-14):
    """Root of f on [lo, hi] with f(lo) < 0 <= f(hi); Anderson-Bjorck regula falsi + bisection.

    Returns a point x with f(x) >= 0 and a point of the bracket no further than ``xtol``
    (relative to max(1, |x|)) below it, so the event is never placed before it happens.
    """
    tol = xtol * max(1.0, abs(hi))
    side = 0
    for _ in range(200):
        if hi - lo <= tol or fhi == 0.0:
            return hi
        x = hi - fhi * (hi - lo) / (fhi - flo)
        if not (lo < x < hi) or side == 2:  # safeguard: bisect
            x = 0.5 * (lo + hi)
            side = 0
        # keep steps away from the endpoints so both ends shrink
        w = hi - lo
        if x - lo < 0.5 * tol:
            x = lo + 0.5 * tol
        elif hi - x < 0.5 * tol:
            x = hi - 0.5 * tol
        fx = f(x)
        if fx >= 0.0:
            g = 1.0 - fx / fhi if fhi != 0 else 0.5
            hi, fhi = x, fx
            if side == -1:
                flo *= g if g > 0 else 0.5
            side = -1 if side != -1 else 2
        else:
            g = 1.0 - fx / flo
            lo, flo = x, fx
            if side == 1:
                fhi *= g if g > 0 else 0.5
            side = 1 if side != 1 else 2
        if hi - lo > 0.9 * w and side != 2:
            side = 2  # poor progress: bisect next
    return hi


def _first_up(fd, tau_max, h, from_zero=False):
    """First tau in (0, tau_max] where f(tau) reaches 0 from below, or None.

    ``fd(tau) -> (f, f')``.  ``f(0) <= 0``; with ``from_zero`` f(0) = 0 is a start (f < 0 just
    after 0), otherwise f(0) = 0 with f'(0) > 0 counts as an event at 0.  Samples every ``h``
    (<= 1/8 of the shortest period of f) and checks interior maxima between samples.
    """
    f = lambda x: fd(x)[0]  # noqa: E731
    dfun = lambda x: fd(x)[1]  # noqa: E731
    flo, dlo = fd(0.0)
    if not from_zero and (flo > 0.0 or (flo == 0.0 and dlo > 0.0)):
        return 0.0
    lo = 0.0
    while lo < tau_max:
        hi = lo + h
        if hi > tau_max:
            hi = tau_max
        fhi, dhi = fd(hi)
        if fhi >= 0.0:
            if flo >= 0.0:  # starting from f(0) = 0: find a point with f < 0 inside
                x = hi
                for _ in range(100):
                    x *= 0.5
                    fx = f(x)
                    if fx < 0.0:
                        break
                else:
                    return hi
                lo, flo = x, fx
            return _root_up(f, lo, hi, flo, fhi)
        if dlo > 0.0 and dhi <= 0.0 and flo < 0.0:  # interior maximum: did f touch 0?
            tm = _root_up(lambda x: -dfun(x), lo, hi, -dlo, -dhi)
            fm = f(tm)
            if fm >= 0.0:
                return _root_up(f, lo, tm, flo, fm)
        lo, flo, dlo = hi, fhi, dhi
    return None
