"""Adaptive mesh refinement of the statics: mesh levels, their interpolation and error estimates.

A :class:`Level` is the converged state on one mesh with its named results, computed when first
asked for.  :func:`prolong` starts a finer mesh from a coarser solution (cubic Hermite positions from
the nodes and their tangents, so the interpolated elements are stretched only by O(h^4)).  The
refinement (femslide.analysis.static.solve) compares the watched results of successive levels:
Richardson extrapolation of the O(h^2) corotational discretisation, relative errors on per-output
scales (:func:`_scales`), and the round-off scatter of the largest moment (:func:`_scatter`: Newton
reconverged from a slightly perturbed state) as a floor of the estimate.
"""
from __future__ import annotations

import math

import numpy as np

from femslide.elements import corotational
from femslide.model.discrete import Model
from femslide.model.state import ElementState
from femslide.model.linalg import largest_abs, model_kernel, solve_linear
from femslide.results.static import end_moments, extract, flatten, largest_moment, rod_arrays


def _prolongation_plan(mc: Model, mf: Model):
    """Per rod, the geometric part of :func:`prolong` (coarse element of every fine node, Hermite
    weights, coarse element of every fine element's midpoint), shared by all solves of one geometry."""
    plans = mf.mesh.prolongations
    key = id(mc.mesh)
    if key in plans and plans[key][0] is mc.mesh:
        return plans[key][1]
    out = []
    for r in range(len(mc.rod_nodes)):
        nc, nf = mc.rod_nodes[r], mf.rod_nodes[r]
        Xc, Xf = mc.X0[nc], mf.X0[nf]
        L = np.hypot(*(Xc[-1] - Xc[0]))
        sc = np.hypot(*(Xc - Xc[0]).T) / L
        sf = np.hypot(*(Xf - Xf[0]).T) / L
        k = np.minimum(np.maximum(np.searchsorted(sc, sf, side="right") - 1, 0), nc.size - 2)
        h = sc[k + 1] - sc[k]
        t = (sf - sc[k]) / h
        hL = (h * L)[:, None]
        H = (2 * t**3 - 3 * t**2 + 1, (t**3 - 2 * t**2 + t)[:, None] * hL, -2 * t**3 + 3 * t**2,
             (t**3 - t**2)[:, None] * hL)
        beta0 = np.arctan2(*(Xc[-1] - Xc[0])[::-1])
        ef = np.nonzero(mf.elem_rod == r)[0]
        ec = np.nonzero(mc.elem_rod == r)[0]
        kmid = np.minimum(np.maximum(np.searchsorted(sc, 0.5 * (sf[1:] + sf[:-1]), side="right") - 1, 0), ec.size - 1)
        out.append((nc, nf, Xc, Xf, k, t, H, beta0, ef, ec[kmid]))
    plans[key] = (mc.mesh, out)
    return out


def prolong(mc: Model, y, elements, mf: Model):
    """Interpolate a converged state onto a finer mesh of the same structure (a Newton start).

    Node positions are cubic Hermite in the arc length, with the nodal tangents, so that the
    interpolated elements are stretched only by O(h^4) (linear interpolation would shorten them by
    O(h^2) and, with EA/EI ~ 1e6, start Newton from enormous axial forces); rotations are linear.
    Body dofs and joint multipliers carry over (same bodies and joints).  Returns (y, elements) on
    the finer mesh (its chord rotations continued from the coarse elements' committed ones).
    """
    alpha = elements.committed
    yf = np.zeros(mf.n)
    af = np.zeros(mf.elements.size) if mf.elements is not None else np.zeros(0)
    kern = model_kernel(mf, "prolong") if mc.elements is not None and mf.elements is not None else None
    if kern is not None:   # the compiled kernel: the same arithmetic in one pass (the flattened plan)
        a, b, nf, t, H, bet, ia, ib, ef, ec = _flat_plan(mc, mf)
        kern(a, b, nf, t, H, bet, mc.X0, np.ascontiguousarray(y, float), mf.X0, yf, ia, ib, ef, ec,
             mc.elements.beta0, np.ascontiguousarray(alpha, float), mf.elements.beta0, af)
    else:
        _prolong_numpy(mc, y, alpha, mf, yf, af)
    yf[3 * mf.n_nodes:mf.n_q] = y[3 * mc.n_nodes:mc.n_q]
    yf[mf.n_q:] = y[mc.n_q:]
    return yf, ElementState(af)


def _flat_plan(mc: Model, mf: Model):
    """:func:`_prolongation_plan` over all rods at once, as the kernel's ``prolong`` takes it: per fine
    node its coarse element's end nodes, its node, parameter, Hermite weights (4, n) and rod chord
    angle; per fine element its two nodes and the coarse element at its middle (kept with the plan)."""
    plans = mf.mesh.prolongations
    key = ("flat", id(mc.mesh))
    if key in plans and plans[key][0] is mc.mesh:
        return plans[key][1]
    parts = _prolongation_plan(mc, mf)
    cat = np.concatenate
    flat = (cat([nc[k] for nc, nf, Xc, Xf, k, t, H, beta0, ef, ecm in parts]).astype(np.int64),
            cat([nc[k + 1] for nc, nf, Xc, Xf, k, t, H, beta0, ef, ecm in parts]).astype(np.int64),
            cat([nf for nc, nf, *_ in parts]).astype(np.int64),
            cat([p[5] for p in parts]).astype(float),
            np.ascontiguousarray(np.stack([cat([np.broadcast_to(p[6][i].reshape(-1), p[5].shape) for p in parts])
                                           for i in range(4)]), float),
            cat([np.full(p[5].size, p[7]) for p in parts]).astype(float),
            cat([p[1][:-1] for p in parts]).astype(np.int64), cat([p[1][1:] for p in parts]).astype(np.int64),
            cat([p[8] for p in parts]).astype(np.int64), cat([p[9] for p in parts]).astype(np.int64))
    plans[key] = (mc.mesh, flat)
    return flat


def _prolong_numpy(mc, y, alpha, mf, yf, af):
    """The numpy path of :func:`prolong` (the kernel's oracle): yf's nodal part and af in place."""
    Uc = mc.nodal(y[:mc.n_q])
    Uf = mf.nodal(yf[:mf.n_q])
    for nc, nf, Xc, Xf, k, t, H, beta0, ef, ecm in _prolongation_plan(mc, mf):
        P = Xc + Uc[nc, :2]
        ang = beta0 + Uc[nc, 2]
        T = np.column_stack([np.cos(ang), np.sin(ang)])
        pos = H[0][:, None] * P[k] + H[1] * T[k] + H[2][:, None] * P[k + 1] + H[3] * T[k + 1]
        Uf[nf, :2] = pos - Xf
        Uf[nf, 2] = (1 - t) * Uc[nc[k], 2] + t * Uc[nc[k + 1], 2]
        D = np.diff(Xf + Uf[nf, :2], axis=0)
        ref = mc.elements.beta0[ecm] + alpha[ecm]
        cr, sr = np.cos(ref), np.sin(ref)
        beta = ref + np.arctan2(cr * D[:, 1] - sr * D[:, 0], cr * D[:, 0] + sr * D[:, 1])
        af[ef] = beta - mf.elements.beta0[ef]
    yf[: 3 * mf.n_nodes] = Uf.ravel()


class Level:
    """The converged state on one mesh: ``y`` and its ``elements`` (committed); its named results
    (``res``) and rod arrays are computed when first asked for."""

    def __init__(self, n, model, y, elements):
        self.n, self.model, self.y, self.elements = n, model, y, elements
        self._arrays = self._res = self._watched = self._noise = self._scatter = self._cuts = None

    @property
    def alpha(self):
        """The committed chord rotations of the elements [rad]."""
        return self.elements.committed

    @property
    def cuts(self):
        """The elements' end moments and middle cut forces from equilibrium
        (:func:`femslide.results.static.end_moments` with ``resultant``)."""
        if self._cuts is None:
            self._cuts = end_moments(self.model, self.y, resultant=True)
        return self._cuts

    @property
    def arrays(self):
        if self._arrays is None:
            self._arrays = rod_arrays(self.model, self.y, self.alpha, self.cuts)
        return self._arrays

    def watched(self, watch):
        """(values, kinds) of ``watch(level, structure)`` on this level, computed once (the
        refinement's and the runner's are the same)."""
        if self._watched is None:
            v, kinds = watch(self, self.model.structure)
            self._watched = (np.asarray(v, float), list(kinds))
        return self._watched

    def largest_moment(self) -> float:
        """Largest |bending moment| [N m] over all rods."""
        return largest_moment(self.model, self.y, self.alpha, self.cuts)

    @property
    def res(self):
        if self._res is None:
            self._res = extract(self.model, self.y, self.alpha, self.arrays)
        return self._res


def default_watch(level, structure):
    """Every named result is watched (values, kinds): see :func:`femslide.results.static.flatten`."""
    return flatten(level.res, structure)


def moment_watch(level, structure):
    """The largest |bending moment| alone is watched (values, kinds): what a fixed mesh's error
    estimate is about (:func:`femslide.analysis.static.solve`), without extracting every named
    result on each level (a run that needs only the equilibrium state: the dynamics' static start)."""
    return [level.largest_moment()], ["moment"]


GROUPS = (("moment",), ("length", "angle"), ("force",))
GROUP_OF = {k: i for i, g in enumerate(GROUPS) for k in g}   # each kind's index in GROUPS


def _units(kinds, L, F):
    u = {"moment": F * L, "force": F, "length": L, "angle": 1.0}
    return np.array([u[k] for k in kinds])


def _scales(vals, kinds):
    """Per-output scales for relative errors: |value|, floored at 1e-3 of its group's largest and at
    1e-10 in model units: changes below that are round-off, not discretisation error."""
    return np.array(_scale_list(vals.tolist(), kinds))


def _scale_list(vals, kinds):
    """:func:`_scales` of a list of floats, as a list (a handful of values: Python floats)."""
    group = [GROUP_OF[k] for k in kinds]
    a = [abs(v) for v in vals]
    top = [0.0] * len(GROUPS)
    for x, g in zip(a, group):
        top[g] = max(top[g], x)
    return [max(x, 1e-3 * top[g], 1e-10) for x, g in zip(a, group)]


def _force_like(kinds):
    return np.array([k in ("force", "moment") for k in kinds])


def _force_noise(lv: Level) -> float:
    """Round-off level of the element forces of a level (model units), from the model's estimate."""
    if lv._noise is None:
        m = lv.model
        if m.elements is None:
            lv._noise = 0.0
        elif not m.linear and getattr(m, "_pack", None) is not None:
            # the compiled assembly estimates the same (bit for bit, tests/test_kernel.py) in one call
            lv._noise = float(m.system(lv.y, lv.elements.copy(), 1.0)[2]["noise"])
        else:
            lv._noise = 4.0 * float(corotational.force_noise(m.elements, m.nodal(lv.y[:m.n_q]), lv.alpha).max())
    return lv._noise


def _roundoff_scatter(lv: Level) -> float:
    """The round-off scatter of a level's largest rod moment (computed once per level)."""
    if lv._scatter is None:
        lv._scatter = _scatter(lv)
    return lv._scatter


def _scatter(lv: Level) -> float:
    """Relative change of the largest rod moment when Newton reconverges from the solution perturbed
    by 1e-13 (relative, alternating signs): how well round-off lets the equilibrium be determined.

    Two full Newton steps: the first is taken from a residual dominated by the perturbation (1e-13
    is far above eps) and leaves its square times the model's nonlinearity, which with stiff rods
    (EA L^2/EI ~ 1e12, fine meshes) can still be ~1e-8; the second, from a residual near round-off,
    is the last step of a solve.  (A perturbation of 1e-10 needs three steps there and a chord step
    with the solve's last tangent leaves it at 1e-5.)
    """
    m = lv.model
    if m.elements is None:
        return 0.0
    y = lv.y.copy()
    q = y[:m.n_q]
    a = np.abs(q)
    p = np.maximum(a, 1e-6 * largest_abs(a))
    p *= 1e-13
    p[1::2] *= -1.0     # (alternating signs: the same numbers as 1e-13 * (+-1) * p)
    q += p
    es = lv.elements.copy()
    try:
        for _ in range(2):
            r, A, _ = m.system(y, es, 1.0)
            y -= solve_linear(A, r)
    except (np.linalg.LinAlgError, RuntimeError, ValueError):
        return 0.0
    if not math.isfinite(largest_abs(y)):   # (a NaN or an infinity anywhere)
        return 0.0
    M0 = largest_abs(lv.cuts[0])
    M1 = largest_abs(end_moments(m, y))
    # relative to the moment, or to 1e-6 of the loads' moment scale (model unit) when the rods carry
    # (almost) none: the noise of a zero moment is no relative error of anything
    return float(abs(M1 - M0) / max(M0, 1e-6))


def _extrapolate_all(coarse: Level, fine: Level, fs):
    f1, _ = flatten(coarse.res, fs)
    f2, _ = flatten(fine.res, fs)
    return (4.0 * f2 - f1) / 3.0
