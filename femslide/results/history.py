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
    return float(_peaks(t, np.asarray(x, dtype=float)[:, None], candidates, breaks)[0])


def _peaks(t, X, candidates=16, breaks=()):
    """:func:`_peak` of every column of X (n samples, m columns) at once: (m,) peaks.  The
    candidates with five well-spaced samples (two on each side) of all columns are fitted together
    (:func:`_refine_many`), the others one by one (:func:`_refine`): the same polynomials to
    round-off."""
    X = np.asarray(X, dtype=float)
    n, m = X.shape
    best = X.max(axis=0) if n else np.full(m, -np.inf)
    if n < 3:
        return best
    br = np.asarray(breaks, dtype=float)
    cols, idx = [], []
    for j in range(m):
        x = X[:, j]
        inner = np.nonzero((x[1:-1] > x[:-2]) & (x[1:-1] >= x[2:]))[0] + 1
        cand = inner[np.argsort(-x[inner])][:candidates]
        if br.size and cand.size:
            lo, hi = t[np.maximum(cand - 2, 0)], t[np.minimum(cand + 2, n - 1)]
            cand = cand[~np.any((br[None, :] >= lo[:, None]) & (br[None, :] <= hi[:, None]), axis=1)]
        cols.append(np.full(cand.size, j))
        idx.append(cand)
    cols, idx = np.concatenate(cols), np.concatenate(idx)
    full = (idx >= 2) & (idx <= n - 3)
    rest = ~full
    if full.any():
        top, ok = _refine_many(t, X, idx[full], cols[full])
        np.maximum.at(best, cols[full][ok], top)
        rest[np.flatnonzero(full)[~ok]] = True
    for i, j in zip(idx[rest], cols[rest]):
        best[j] = max(best[j], _refine(t, X[:, j], int(i)))
    return best


def _refine_many(t, X, idx, cols):
    """:func:`_refine` of the interior local maxima ``idx`` (2 <= i <= n - 3: five samples each) of
    the columns ``cols`` of X at once: (peaks of the well-conditioned fits, mask of the candidates
    they belong to); a window whose samples crowd together (a spacing below 1e-3 of its
    half-width: polyfit's least squares there drops singular values) is left to :func:`_refine`."""
    win = idx[:, None] + np.arange(-2, 3)[None, :]
    tt = t[win] - t[idx][:, None]                      # (k, 5)
    scale = np.maximum(np.abs(tt[:, 0]), np.abs(tt[:, -1]))
    u = tt / scale[:, None]
    ok = np.all(np.diff(u, axis=1) > 1e-3, axis=1)
    if not ok.any():
        return np.zeros(0), ok
    u, xx, scale, i, j = u[ok], X[win[ok], cols[ok][:, None]], scale[ok], idx[ok], cols[ok]
    V = u[:, :, None] ** np.arange(5)[None, None, :]  # (k, 5, 5), ascending powers
    try:
        c = np.linalg.solve(V, xx[:, :, None])[:, :, 0]
    except np.linalg.LinAlgError:   # (a singular window: each left to polyfit)
        return np.zeros(0), np.zeros(idx.size, dtype=bool)
    a, b = (t[i - 1] - t[i]) / scale, (t[i + 1] - t[i]) / scale
    s = a[:, None] + (b - a)[:, None] * np.linspace(0.0, 1.0, 401)[None, :]   # (k, 401)
    val = c[:, 4:5]
    for p in (3, 2, 1, 0):                             # Horner
        val = val * s + c[:, p:p + 1]
    top = val.max(axis=1)
    xi = X[i, j]
    # a fit that overshoots far beyond the samples' spread is not trusted
    top = np.where(top - xi <= 0.5 * (xi - np.minimum(X[i - 1, j], X[i + 1, j])) + 1e-300, top, xi)
    return top, ok


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
