"""The difference of two runs of one motion: histories, peaks and event times.

Two runs of the same structure at two tolerances give two sampled histories on different time
grids (each run samples at its own steps).  :func:`history_difference` interpolates the denser run
(``a``) onto the other's sample times (``b``) and returns, per column, the largest difference
relative to the column's largest value in ``a``.  Interpolation is local (Lagrange through up to
six neighbouring samples, error ~(omega h)^6 / 720 of a smooth history) and never across a break
(a friction event, where forces jump); sample times within a window about an event of either run
are left out (between the two runs' times of one event, one is before it and one after), and
samples the runs share (record sample times, the start and the end) are compared directly.

:func:`peak_difference` compares nested peak tables ({group: {name: {key: value}}}) relative to each
value; :func:`event_difference` matches event lists joint by joint, in order.
"""
from __future__ import annotations

import numpy as np

from femslide.model.linalg import distinct, member

POINTS = 6   # samples per local interpolation (degree 5)


def _lagrange(ts, t):
    """Weights of the Lagrange interpolant through the times ``ts`` at t: w_j = prod over m != j of
    (t - ts_m) / (ts_j - ts_m), all j in one array operation (the factor m = j set to 1)."""
    R = np.divide(t - ts[None, :], ts[:, None] - ts[None, :], out=np.ones((ts.size, ts.size)),
                  where=~np.eye(ts.size, dtype=bool))
    return R.prod(axis=1)


def interpolate(ta, Xa, tb, breaks=(), kinks=()):
    """The rows of Xa (samples at the increasing times ta) at the times tb: local Lagrange
    interpolation within the segments between ``breaks`` (a row at a break time belongs to the
    segment after it, unless another row at that time follows it: then it is the left limit and
    belongs to the segment before) and ``kinks`` (times where the history is continuous but not
    smooth - a recorded ground motion's samples, between which it is linear -: a row at a kink
    belongs to both segments); NaN where a segment has no sample."""
    ta = np.asarray(ta, dtype=float)
    Xa = np.asarray(Xa, dtype=float)
    kk = np.asarray(list(kinks), dtype=float)
    dup = np.nonzero(ta[:-1] == ta[1:])[0]
    # (two rows at one time are a switch - its left limit and the state after -: a break, listed or not)
    br = distinct(np.concatenate([np.asarray(list(breaks), dtype=float), ta[dup], kk]))
    is_kink = member(br, kk)
    seg_a = np.searchsorted(br, ta, side="right")     # segment index of every sample
    # a row followed by another at the same time is a left limit (the state before an event's
    # switch): it belongs to the segment before
    seg_a[dup] = np.searchsorted(br, ta[dup], side="left")
    out = np.full((len(tb), Xa.shape[1]), np.nan)
    for i, t in enumerate(tb):
        k = int(np.searchsorted(br, t, side="right"))
        idx = np.nonzero(seg_a == k)[0]
        if k < br.size and is_kink[k] and not np.any(ta[idx] == br[k]):
            # (the row at the segment's closing kink, too - unless the segment has a row at that time:
            # the left limit of an event there)
            at = np.nonzero((ta == br[k]) & (seg_a == k + 1))[0]
            idx = distinct(np.concatenate([idx, at[:1]]))
        if idx.size == 0:
            continue
        j = int(np.searchsorted(ta[idx], t))
        if j < idx.size and abs(ta[idx[j]] - t) <= 1e-12 * max(1.0, abs(t)):
            out[i] = Xa[idx[j]]
            continue
        lo = max(0, min(j - POINTS // 2, idx.size - POINTS))
        sel = idx[lo:lo + POINTS]
        scale = max(abs(ta[sel[-1]] - ta[sel[0]]), 1e-300)
        w = _lagrange((ta[sel] - t) / scale, 0.0)
        out[i] = w @ Xa[sel]
    return out


def history_difference(ta, Xa, tb, Xb, breaks=(), windows=(), offsets=None, floors=None, kinks=()):
    """Per column, max |Xb - Xa(tb)| / scale over the samples of b outside the ``windows``
    [(t0, t1)], the scale being max |Xa - offset| of the column and at least its ``floors`` entry
    (the size of a change that matters for that quantity: a body's vertical position that moves by
    1e-9 m while the others sway by 0.1 m is not judged by its own round-off).  ``offsets`` (per
    column, default 0) are subtracted for the scale only (positions are measured from their start).
    A column whose scale is zero gives 0.  ``kinks``: see :func:`interpolate`."""
    tb = np.asarray(tb, dtype=float)
    keep = np.ones(tb.size, dtype=bool)
    for t0, t1 in windows:
        keep &= ~((tb >= t0) & (tb <= t1))
    Xi = interpolate(ta, Xa, tb[keep], breaks, kinks)
    D = np.abs(np.asarray(Xb, dtype=float)[keep] - Xi)
    off = np.zeros(Xa.shape[1]) if offsets is None else np.asarray(offsets, dtype=float)
    scale = np.abs(np.asarray(Xa, dtype=float) - off).max(axis=0) if len(Xa) else np.zeros(Xa.shape[1])
    if floors is not None:
        scale = np.maximum(scale, np.asarray(floors, dtype=float))
    with np.errstate(invalid="ignore", divide="ignore"):
        rel = np.where(scale > 0.0, np.nanmax(np.where(np.isnan(D), 0.0, D), axis=0, initial=0.0) / scale, 0.0)
    return rel


def leaves(tree, path=()):
    """(path tuple, value) of every leaf of a nested dict."""
    if isinstance(tree, dict):
        for k, v in tree.items():
            yield from leaves(v, path + (k,))
    else:
        yield path, tree


def peak_difference(pa, pb, floors=None):
    """{dotted key: |b - a| / max(|a|, floor)} of two peak tables of the same shape (``floors``
    {dotted key: smallest scale}, default none; 0 where the scale is 0 and b equals a)."""
    flat_b = dict(leaves(pb))
    floors = floors or {}
    out = {}
    for path, a in leaves(pa):
        b = flat_b.get(path)
        if b is None:
            continue
        key = ".".join(path)
        d = abs(float(b) - float(a))
        scale = max(abs(float(a)), floors.get(key, 0.0))
        out[key] = d / scale if scale else (0.0 if d == 0.0 else float("inf"))
    return out


def event_difference(ea, eb):
    """(agree, largest |t_b - t_a| [s]) of two event tables {joint: [{t, kind}]}: agree when every
    joint has the same kinds in the same order."""
    agree, dt = True, 0.0
    for name, la in ea.items():
        lb = eb.get(name, [])
        if [e["kind"] for e in la] != [e["kind"] for e in lb]:
            agree = False
            continue
        for a, b in zip(la, lb):
            dt = max(dt, abs(a["t"] - b["t"]))
    return agree, dt
