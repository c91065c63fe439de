"""Peaks of sampled time histories, refined between the samples.
"""
from __future__ import annotations

import numpy as np



def _peak(t, x, candidates=16, breaks=()):
    """Largest value of the sampled x(t): the largest sample, or the peak of the interpolating
    polynomial through a local maximum of the samples and its neighbours (up to two on each side:
    degree 4, exact to O(h^5) for a smooth peak) maximised between the neighbouring samples, for the
    ``candidates`` largest local maxima (a sharp peak between coarse steps can leave its samples
    below an end value, e.g. the held start); the samples are the integrator's steps.  A flat run
    of equal samples is one candidate (its first sample); no polynomial is fitted across one of the
    times ``breaks`` (friction events, where a history may jump: a fit there would overshoot)."""
    x = np.asarray(x, dtype=float)
    best = float(x.max())
    if x.size < 3:
        return best
    inner = np.nonzero((x[1:-1] > x[:-2]) & (x[1:-1] >= x[2:]))[0] + 1
    br = np.asarray(breaks, dtype=float)
    for i in inner[np.argsort(-x[inner])][:candidates]:
        lo, hi = t[max(0, i - 2)], t[min(x.size - 1, i + 2)]
        if br.size and np.any((br >= lo) & (br <= hi)):
            continue
        best = max(best, _refine(t, x, int(i)))
    return best


def _refine(t, x, i):
    """The interpolated peak about the local maximum sample i (see :func:`_peak`), or x[i]."""
    lo, hi = max(0, i - 2), min(x.size, i + 3)
    tt, xx = t[lo:hi] - t[i], x[lo:hi]
    scale = max(abs(tt[0]), abs(tt[-1]))
    try:
        c = np.polyfit(tt / scale, xx, hi - lo - 1)
    except (np.linalg.LinAlgError, ValueError):
        return float(x[i])
    s = np.linspace(t[i - 1] - t[i], t[i + 1] - t[i], 401) / scale
    best = float(np.polyval(c, s).max())
    # a fit that overshoots far beyond the samples' spread is not trusted
    return best if best - x[i] <= 0.5 * (x[i] - min(x[i - 1], x[i + 1])) + 1e-300 else float(x[i])
