"""Arc-length continuation: the equilibrium path through limit points, and the limit points themselves.

The equilibria of a model under loads lam f form a path z(s) = (y(s), lam(s)) in the space of the
unknowns and the load factor.  Load control (lam given) fails where lam(s) has a maximum (a limit
point, the snap of a shallow arch); displacement control fails where the controlled dof turns back
(snap-back).  Pseudo-arclength continuation (Keller; Riks and Crisfield in structural mechanics)
takes the arc length s as the parameter: from a point z_a with unit tangent t_a, the next point is
the equilibrium on the hyperplane

    t_a . W (z - z_a - ds t_a) = 0,

W the weights of the norm: 1 on the frame dofs (model units: lengths by Lref, rotations in rad), 0 on
the joint multipliers, 1 on lam.  The bordered Jacobian [[A, f], [t_a^T W]] stays regular at limit
points, so Newton (femslide.analysis.newton) converges through them.  The tangent at a point solves
[[A, f], [t_a^T W]] t = [0, 1] (oriented along the path); a sign change of its lam component is a
limit point.

Step control: the step grows when the corrector needs few iterations and is halved when it fails,
when the corrector moves far from the predictor (more than a third of the step) or when the tangent
turns by more than 0.35 rad: the path is resolved finely enough that no fold is stepped over.

:func:`trace` follows the path from the unloaded structure until lam reaches ``lam_end`` (the first
equilibrium at full load along the path) and locates every limit point on the way to about 1e-12 in
lam (regula falsi on the tangent's lam component between the two points that bracket it);
:func:`fold_on_mesh` locates a limit point on another mesh from a nearby state (for the mesh
refinement of femslide.analysis.limits).  Everything is in model units.
"""
from __future__ import annotations

import math

import numpy as np

from femslide.analysis.newton import newton
from femslide.errors import SolverFailure
from femslide.joints.holds import DofHold
from femslide.model.linalg import solve_linear
from femslide.records import dataclass, field

DENSE_LIMIT = 600      # unknowns: bordered systems assembled dense up to here, sparse above
MAX_TRANSLATION = 0.25  # model lengths: largest predicted translation of a step
MAX_ROTATION = 0.35     # rad: largest predicted rotation of a step
MAX_DLAM = 0.1          # largest predicted change of the load factor in a step
MAX_TURN = 0.35         # rad: largest angle between consecutive tangents
MAX_STEPS = 4000


@dataclass
class PathPoint:
    """An equilibrium on the path: load factor, state (model units) and the elements' committed
    chord rotations; ``kind`` "start", "point", "limit" (a maximum or minimum of lam), "end" (lam =
    lam_end)."""

    lam: float
    y: np.ndarray
    alpha: np.ndarray
    kind: str = "point"
    mode: np.ndarray | None = None   # a limit point: the path's tangent there (its null vector)


@dataclass
class Trace:
    """A traced path: ``points`` in path order (limit points and the end included), ``limits`` the
    limit points, ``bifurcations`` the load factors where the tangent's determinant changed sign
    without a limit point (the path crossed another branch), ``end`` the first point at lam_end (None
    if not reached), ``iterations`` the Newton iterations."""

    points: list = field(default_factory=list)
    limits: list = field(default_factory=list)
    bifurcations: list = field(default_factory=list)
    end: PathPoint | None = None
    iterations: int = 0


class _Bordered:
    """The equilibrium equations of a model with the load factor as the last unknown and one more
    equation c . (z - z_p) = 0 (the arc-length hyperplane): the interface newton() iterates on."""

    def __init__(self, model, c, zp):
        self.model, self.c, self.zp = model, c, zp
        self.n_q = model.n_q

    def rotation_dofs(self):
        return self.model.rotation_dofs()

    def system(self, z, elements, lam=None, control=None, jacobian=True, dense=False):
        m = self.model
        y, lam = z[:-1], float(z[-1])
        r, A, info = m.system(y, elements, lam, jacobian=jacobian, dense=jacobian and m.n <= DENSE_LIMIT)
        r = np.append(r, self.c @ (z - self.zp))
        if not jacobian:
            return r, None, info
        return r, _border(m, A, info["fl"], self.c), info


def _border(model, A, fl, c):
    """The bordered matrix [[A, f], [c^T]] (f = d r / d lam over the frame dofs), dense or sparse."""
    n = model.n
    if isinstance(A, np.ndarray):
        B = np.zeros((n + 1, n + 1))
        B[:n, :n] = A
        B[:model.n_q, n] = fl
        rows = getattr(model, "_motion_rows", None)
        if rows is not None and rows.size:   # a prescribed support motion: d g / d lam
            B[rows, n] = model._motion_vals
        B[n] = c
        return B
    import scipy.sparse as sp
    col = np.zeros((n, 1))
    col[:model.n_q, 0] = fl
    rows = getattr(model, "_motion_rows", None)
    if rows is not None and rows.size:
        col[rows, 0] = model._motion_vals
    return sp.bmat([[model.to_csc(A), sp.csc_matrix(col)], [sp.csc_matrix(c[None, :]), None]]).tocsc()


class Tracer:
    """Arc-length continuation on one model (see the module docstring)."""

    def __init__(self, model, lam_end=1.0, tol=1e-11):
        self.model, self.lam_end, self.tol = model, lam_end, tol
        n = model.n
        self.w = np.zeros(n + 1)
        self.w[:model.n_q] = 1.0
        self.w[n] = 1.0
        self.its = 0
        rot = np.zeros(model.n_q, bool)
        rot[model.rotation_dofs()] = True
        self.bound = np.where(rot, MAX_ROTATION, MAX_TRANSLATION)

    # -- pieces ------------------------------------------------------------------------------------------
    def tangent(self, z, es, t_prev):
        """(unit tangent at the converged state z, oriented along t_prev; sign of det A (dense models,
        else None)).  ``es`` committed at z (left so)."""
        m = self.model
        y, lam = z[:-1], float(z[-1])
        _, A, info = m.system(y, es, lam, dense=m.n <= DENSE_LIMIT)
        es.revert()
        sign = float(np.linalg.slogdet(A)[0]) if isinstance(A, np.ndarray) else None
        rhs = np.zeros(m.n + 1)
        rhs[-1] = 1.0
        t = solve_linear(_border(m, A, info["fl"], self.w * t_prev), rhs)
        return t / self.norm(t), sign

    def norm(self, v):
        return math.sqrt(float(np.sum(self.w * v * v)))

    def correct(self, z, es, t, ds, maxit=15):
        """(z_new, elements committed there, converged, iterations): the equilibrium on the
        hyperplane through z + ds t normal to W t; ``es`` (committed at z) unchanged."""
        zp = z + ds * t
        sysm = _Bordered(self.model, self.w * t, zp)
        e = es.copy()
        zn, info = newton(sysm, zp, e, tol=self.tol, maxit=maxit)
        self.its += info.iterations
        if not info.converged:
            return zn, None, False, info.iterations
        return zn, e.committed_trial(), True, info.iterations

    def step_bound(self, t):
        """The largest arc-length step whose prediction stays within the step bounds."""
        m = self.model
        g = max(float(np.max(np.abs(t[:m.n_q]) / self.bound)) if m.n_q else 0.0, abs(float(t[-1])) / MAX_DLAM)
        return 1.0 / g if g > 0 else math.inf

    # -- the path -----------------------------------------------------------------------------------------
    def start(self, y0=None, es0=None):
        """The unloaded start (z with lam = 0) and its tangent (towards increasing lam)."""
        m = self.model
        if y0 is None:
            y0, es0 = m.zero_state()
        z = np.append(y0, 0.0)
        t0 = np.zeros(m.n + 1)
        t0[-1] = 1.0
        t, sign = self.tangent(z, es0, t0)
        return z, es0, t, sign

    def trace(self, y0=None, es0=None, stop_at_limit=False, max_steps=MAX_STEPS):
        """Follow the path from the unloaded state until lam reaches lam_end (see :class:`Trace`);
        ``stop_at_limit``: stop at the first limit point (or bifurcation)."""
        z, es, t, sign = self.start(y0, es0)
        tr = Trace()
        tr.points.append(PathPoint(0.0, z[:-1].copy(), es.committed.copy(), "start"))
        ds = 0.25 * self.step_bound(t)
        ds_min = 1e-10 * ds
        for _ in range(max_steps):
            ds = min(ds, self.step_bound(t))
            zn, en, ok, nit = self.correct(z, es, t, ds)
            reason = "no convergence"
            if ok:
                dist = self.norm(zn - z - ds * t)
                if dist > ds / 3.0:
                    ok, reason = False, "the corrector moved far from the prediction"
            if ok:
                try:
                    tn, sign_n = self.tangent(zn, en, t)
                except (np.linalg.LinAlgError, RuntimeError, ValueError):
                    ok, reason = False, "singular bordered tangent"
            if ok and float(np.sum(self.w * tn * t)) < math.cos(MAX_TURN):
                ok, reason = False, "the tangent turned too far"
            if not ok:
                ds *= 0.5
                if ds < ds_min:
                    lam = float(z[-1])
                    raise _failed(f"arc-length continuation stalled at load factor {lam:.6g} ({reason})", tr)
                continue
            lam, lam_n = float(z[-1]), float(zn[-1])
            if t[-1] > 0 >= tn[-1] or t[-1] < 0 <= tn[-1]:
                lp, s_lp = self.fold(z, es, t, ds)
                if (lam - self.lam_end) * (lp.lam - self.lam_end) <= 0 and lp.lam != lam:
                    # the path reaches lam_end before this limit point (within the step)
                    zl = np.append(lp.y, lp.lam)
                    from femslide.model.state import ElementState
                    tr.end = self.at_end(z, es, t, s_lp, zl, ElementState(lp.alpha))
                    tr.points.append(tr.end)
                    tr.iterations = self.its
                    return tr
                tr.limits.append(lp)
                tr.points.append(lp)
                if stop_at_limit:
                    tr.iterations = self.its
                    return tr
            elif sign is not None and sign_n is not None and sign_n != sign:
                bp = self.bisect(z, es, t, ds, sign)
                tr.bifurcations.append(bp.lam)
                tr.points.append(bp)
                if stop_at_limit:
                    tr.iterations = self.its
                    return tr
            if (lam - self.lam_end) * (lam_n - self.lam_end) <= 0 and lam_n != lam:
                tr.end = self.at_end(z, es, t, ds, zn, en)
                tr.points.append(tr.end)
                tr.iterations = self.its
                return tr
            tr.points.append(PathPoint(lam_n, zn[:-1].copy(), en.committed.copy()))
            z, es, t, sign = zn, en, tn, sign_n
            ds = ds * (1.5 if nit <= 4 else 0.7 if nit >= 8 else 1.0)
        raise _failed(f"arc-length continuation did not reach load factor {self.lam_end:g} in {max_steps} steps "
                      f"(load factor {float(z[-1]):.6g} reached)", tr)

    def fold(self, z, es, t, ds):
        """(the limit point between z (its tangent t) and the point at arc step ds, its arc step
        from z): regula falsi (Illinois) on the lam component of the tangent along the arc from z."""
        fa, sa = float(t[-1]), 0.0
        fb, sb = None, ds
        best = None
        for _ in range(60):
            if fb is None:
                zb, eb, ok, _ = self.correct(z, es, t, sb)
                tb, _ = self.tangent(zb, eb, t)
                fb = float(tb[-1])
                best = (zb, eb, tb, sb)
            s = sb - fb * (sb - sa) / (fb - fa) if fb != fa else 0.5 * (sa + sb)
            if not (min(sa, sb) < s < max(sa, sb)):
                s = 0.5 * (sa + sb)
            zs, e_s, ok, _ = self.correct(z, es, t, s)
            if not ok:
                break
            ts, _ = self.tangent(zs, e_s, t)
            fs = float(ts[-1])
            best = (zs, e_s, ts, s)
            if abs(fs) <= 1e-12 or abs(sb - sa) <= 1e-13 * ds:
                break
            if (fs > 0) == (fa > 0):
                sa, fa = s, fs
                fb *= 0.5
            else:
                sb, fb = s, fs
                fa *= 0.5
        zs, e_s, ts, s = best
        return PathPoint(float(zs[-1]), zs[:-1].copy(), e_s.committed.copy(), "limit", ts[:self.model.n_q]), s

    def bisect(self, z, es, t, ds, sign):
        """The bifurcation between z (determinant sign ``sign``) and the point at arc step ds: bisection
        of the arc step on the sign of the tangent's determinant."""
        lo, hi = 0.0, ds
        best = None
        for _ in range(45):
            s = 0.5 * (lo + hi)
            zs, e_s, ok, _ = self.correct(z, es, t, s)
            if not ok:
                break
            _, sg = self.tangent(zs, e_s, t)
            best = (zs, e_s)
            if sg == sign:
                lo = s
            else:
                hi = s
            if hi - lo <= 1e-12 * ds:
                break
        if best is None:
            zs, e_s, _, _ = self.correct(z, es, t, ds)
            best = (zs, e_s)
        zs, e_s = best
        return PathPoint(float(zs[-1]), zs[:-1].copy(), e_s.committed.copy(), "bifurcation")

    def at_end(self, z, es, t, ds, zn, en):
        """The equilibrium at lam = lam_end between z and zn: Newton at that load from the linear
        interpolation, kept if it lies between them; else secant steps on the arc length."""
        m = self.model
        lam, lam_n = float(z[-1]), float(zn[-1])
        f = (self.lam_end - lam) / (lam_n - lam)
        start = z[:-1] + f * (zn[:-1] - z[:-1])
        e = es.copy()
        y, info = newton(m, start, e, lam=self.lam_end, tol=self.tol)
        self.its += info.iterations
        span = self.norm(zn - z)
        if info.converged and self.norm(np.append(y, self.lam_end) - np.append(start, self.lam_end)) <= span:
            return PathPoint(self.lam_end, y, e.committed_trial().committed.copy(), "end")
        sa, sb, fa, fb = 0.0, ds, lam - self.lam_end, lam_n - self.lam_end
        zs = zn
        for _ in range(60):
            s = sb - fb * (sb - sa) / (fb - fa)
            zs, e_s, ok, _ = self.correct(z, es, t, s)
            if not ok:
                raise SolverFailure(f"arc-length continuation: no equilibrium found at load factor "
                                    f"{self.lam_end:g} between {lam:.6g} and {lam_n:.6g}")
            fs = float(zs[-1]) - self.lam_end
            if abs(fs) <= 1e-13:
                break
            if (fs > 0) == (fa > 0):
                sa, fa = s, fs
            else:
                sb, fb = s, fs
        e2 = e_s.copy()
        y, info = newton(m, zs[:-1], e2, lam=self.lam_end, tol=self.tol)
        self.its += info.iterations
        if not info.converged:
            raise SolverFailure(f"arc-length continuation: the equilibrium at load factor {self.lam_end:g} did "
                                f"not converge ({info.reason})", info.history)
        return PathPoint(self.lam_end, y, e2.trial.copy(), "end")


def _failed(reason, trace):
    """A SolverFailure carrying the path traced so far (``exc.trace``): nothing is lost."""
    exc = SolverFailure(reason)
    exc.trace = trace
    return exc


def fold_on_mesh(model, y, alpha, lam, dof, tol=1e-11):
    """A limit point of ``model`` near the state y at load factor lam (interpolated from another
    mesh's limit point): the maximum (or minimum) of the load factor along the path with the dof
    ``dof`` prescribed (one that moves in the limit point's null vector), found by secant steps on
    d lam / d u.  Returns a PathPoint, or None when the controlled solves fail."""
    from femslide.model.state import ElementState
    es = ElementState(alpha.copy())
    u = float(y[dof])
    z = np.append(y, lam)

    def solve(u, z):
        e = es.copy()
        zz, info = newton(model, z, e, control=DofHold(dof, u), tol=tol)
        if not info.converged:
            return None
        e.commit()
        _, A, _ = model.system(zz, e, control=DofHold(dof, 0.0))
        e.revert()
        rhs = np.zeros(zz.size)
        rhs[-1] = 1.0
        return zz, e, float(solve_linear(A, rhs)[-1])

    out = solve(u, z)
    if out is None:
        return None
    z0, e0, g0 = out
    # lam(u) near its extremum: a parabola; probe at a small offset from the curvature scale
    scale = max(abs(u), 1e-3)
    u1 = u + 1e-3 * scale
    out = solve(u1, z0)
    if out is None:
        return None
    z1, e1, g1 = out
    u0 = u
    for _ in range(40):
        if g1 == g0:
            break
        u2 = u1 - g1 * (u1 - u0) / (g1 - g0)
        out = solve(u2, z1)
        if out is None:
            return None
        u0, z0, g0 = u1, z1, g1
        u1, (z1, e1, g1) = u2, out
        if abs(u1 - u0) <= 1e-12 * scale:
            break
    return PathPoint(float(z1[-1]), z1[:-1].copy(), e1.committed.copy(), "limit")
