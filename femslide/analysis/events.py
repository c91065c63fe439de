"""Locating events: the one bracketing root finder, and the scans that find the first event.

An event is where a function of time (or of a load or rotation) crosses zero: a friction joint's
slip velocity or static margin between two time steps, a velocity zero or a breakaway of the exact
one-mass oscillator, the first equilibrium of a spring-hinge model along its rotation.  All of them
are located by :func:`root_up` on a bracket [lo, hi] with f(lo) < 0 <= f(hi) (Brent's method).  It
returns the end of the final bracket on the f >= 0 side, so an event is never placed before it
happens (the state there is already past it).

:func:`first_up` and :func:`first_crossing` find the bracket of the *first* event by scanning.
Pure Python: the spring-hinge scenes and the exact oscillator start without numpy.
"""
from __future__ import annotations


class NoRoot(RuntimeError):
    """No sign change was found where one was expected."""


def root_up(f, lo, hi, flo, fhi, xtol=1e-14, rtol=0.0, maxiter=200, count=False):
    """Root of f on [lo, hi] with f(lo) < 0 <= f(hi): a point x with f(x) >= 0 and a point of the
    bracket no further than 2 rtol |x| + xtol max(1, |x|)/2 below it, by Brent's method (inverse
    quadratic interpolation, secant and bisection; superlinear on smooth functions, never slower
    than bisection).  ``f(x)`` may return None where it cannot be evaluated (a time step that does
    not converge): the trial moves to the middle of the bracket, at most 3 times; then the bracket so
    far is returned.  With ``count``: (x, number of evaluations of f)."""
    a, fa, b, fb = lo, flo, hi, fhi   # b: the best estimate, c: the other end of the bracket
    n = 0
    r2, hx = 2.0 * rtol, 0.5 * xtol
    if fb == 0.0:
        return (b, n) if count else b
    c, fc = a, fa
    d = e = b - a
    for _ in range(maxiter):
        if (fb > 0) == (fc > 0) and fb != 0.0:
            c, fc = a, fa
            d = e = b - a
        if abs(fc) < abs(fb):
            a, b, c = b, c, b
            fa, fb, fc = fb, fc, fb
        ab = abs(b)
        tol = r2 * ab + (hx * ab if ab > 1.0 else hx)
        m = 0.5 * (c - b)
        if abs(m) <= tol or fb == 0.0:
            break
        if abs(e) >= tol and abs(fa) > abs(fb):
            q_ = fb / fa
            if a == c:
                p, q = 2.0 * m * q_, 1.0 - q_
            else:
                qa, r = fa / fc, fb / fc
                p = q_ * (2.0 * m * qa * (qa - r) - (b - a) * (r - 1.0))
                q = (qa - 1.0) * (r - 1.0) * (q_ - 1.0)
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
        x = b + (d if abs(d) > tol else (tol if m > 0 else -tol))
        fx = f(x)
        n += 1
        if fx is None:
            for _ in range(3):
                x = 0.5 * (b + c)
                fx = f(x)
                n += 1
                if fx is not None:
                    break
            else:
                break
        b, fb = x, fx
    # the end of the final bracket on the f >= 0 side
    x = b if fb >= 0.0 else c
    return (x, n) if count else x


def first_up(fd, tau_max, h, from_zero=False):
    """First tau in (0, tau_max] where f(tau) reaches 0 from below, or None.

    ``fd(tau) -> (f, f')``.  ``f(0) <= 0``; with ``from_zero`` f(0) = 0 is a start (f < 0 just
    after 0), otherwise f(0) = 0 with f'(0) > 0 counts as an event at 0.  Samples every ``h``
    (<= 1/8 of the shortest period of f) and checks interior maxima between samples, so that a zero
    touched between two samples is not missed.
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
            return root_up(f, lo, hi, flo, fhi)
        if dlo > 0.0 and dhi <= 0.0 and flo < 0.0:  # interior maximum: did f touch 0?
            tm = root_up(lambda x: -dfun(x), lo, hi, -dlo, -dhi)
            fm = f(tm)
            if fm >= 0.0:
                return root_up(f, lo, tm, flo, fm)
            # a zero touched (a double root): the maximum is zero to round-off, whose sign at the
            # located maximum is chance
            if fm >= -1e-12 * max(abs(flo), abs(fhi)):
                return tm
        lo, flo, dlo = hi, fhi, dhi
    return None


def first_crossing(g, x_start: float, x_max: float, grow: float = 1.3, rtol: float = 4e-16) -> tuple[float, int]:
    """First x in (0, x_max] where g changes sign from negative to non-negative, and the number of
    evaluations of g.

    ``g(0) < 0`` is assumed; the scan starts at ``x_start`` (well below the root) and grows
    geometrically; the root is located to ``rtol`` (relative).  Raises :class:`NoRoot` when g stays
    negative up to ``x_max``.
    """
    lo, glo = 0.0, None
    x = min(x_start, x_max)
    n = 0
    while True:
        gx = g(x)
        n += 1
        if gx >= 0.0:
            if glo is None:
                glo = g(lo)
                n += 1
            root, k = root_up(g, lo, x, glo, gx, xtol=0.0, rtol=rtol, count=True)
            return root, n + k
        if x >= x_max:
            raise NoRoot(f"no equilibrium found up to {x_max:g}")
        lo, glo = x, gx
        x = min(x * grow, x_max)


def locate_step(attempt, f, f0, h, cand, max_iter=60, x_min=0.0):
    """The step size in (0, h] at which an event function f of a time step's end reaches zero from
    above, each trial a step from the same state (``attempt(x)`` -> candidate or None), so that the
    event lies on the step's own solution; ``f0`` >= 0 its value at the start, ``cand`` the step of
    size h (f(cand) < 0).  Returns (h_event, candidate): the trial at or just past the event.

    A function that is zero at the start (a slip just begun from rest) gives no secant: the step is
    halved until a trial has not crossed yet, so that the event lies inside the step, never at its
    start.  No trial is shorter than ``x_min`` (the resolution of event times: shorter steps carry
    the round-off of their own stage equations); an event before it is placed at x_min.  A trial of
    x_min is made only where the event may lie that near the start: f0 is zero, or the secant through
    the step's ends crosses within 4 x_min (a trial of 2.5e-8 s on a structure with massless parts
    gave a friction margin of -2 for a true +3e-4 N, and the event was placed 1.6e-4 s early)."""
    tried = {h: cand}

    def trial(x):
        x = max(x, x_min)   # (never shorter than the resolution)
        c = attempt(x)
        if c is None:
            return None
        tried[x] = c
        return -f(c)
    lo, g_lo, hi, g_hi = 0.0, -f0, h, -f(cand)
    if h <= x_min:   # (no trial shorter than the resolution: the event is at the step's end)
        return h, cand
    near = f0 <= 0.0 or g_hi <= 0.0 or f0 / (f0 + g_hi) * h <= 4.0 * x_min   # (the secant's crossing)
    if 0.0 < x_min < h and near:
        g = trial(x_min)
        if g is not None:
            if g >= 0.0:
                return x_min, tried[x_min]
            lo, g_lo = x_min, g
    for _ in range(max_iter):
        if g_lo < 0.0:
            break
        x = 0.5 * (lo + hi)
        if x < x_min:
            return hi, tried[hi]
        gx = trial(x)
        if gx is None:
            break
        if gx < 0.0:
            lo, g_lo = x, gx
        else:
            hi, g_hi = x, gx
    x = root_up(trial, lo, hi, min(g_lo, -1e-300), g_hi, xtol=1e-12, maxiter=max_iter)
    if x not in tried:   # (the bracket's end never tried - its start: the nearest trial past it)
        x = min((k for k in tried if k >= x), default=h)
    return x, tried[x]
