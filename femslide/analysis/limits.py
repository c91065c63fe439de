"""Critical points of the load path, located on the discrete model and refined with the mesh.

A limit point (a maximum or minimum of the load factor along the path of equilibria) and a
bifurcation (the tangent singular while the load factor still grows) end the principal branch.
:func:`critical_points` traces the path by arc-length continuation (femslide.analysis.arclength) on
the coarsest mesh and locates each critical point there to about 1e-12 in load factor; each limit
point is then followed onto finer meshes (2, 4, 8 ... times as many elements: the finer model's
extremum of the load factor with the limit point's dominant dof prescribed, started from the
interpolated coarser state) and its load factor Richardson-extrapolated from the two finest meshes
(the corotational discretisation error is O(h^2)), until the estimate of its error is below
``target``.  A bifurcation is located by bisection of the arc step on the sign of the tangent's
determinant, on every traced mesh.

:func:`explain` turns a failed principal-branch solve (femslide.analysis.static) into the failure
that names the first critical point and its load factor; :func:`limit_points` gives the refined limit
points of an arc-length solve.  Model units inside; load factors are dimensionless.
"""
from __future__ import annotations

import math

import numpy as np

from femslide.analysis.arclength import PathPoint, Tracer, fold_on_mesh
from femslide.analysis.paths import _mode_part
from femslide.analysis.refine import prolong
from femslide.errors import SolverFailure
from femslide.model.state import ElementState
from femslide.records import dataclass

TARGET = 1e-8     # estimated relative error of a limit point's load factor that ends the refinement
N_MAX = 1024      # elements per (shortest) rod: the finest mesh a limit point is followed onto


@dataclass
class Critical:
    """A critical point: ``kind`` "maximum", "minimum" (limit points) or "bifurcation"; its load
    factor ``lam`` (extrapolated), the estimate of its error ``error`` (absolute, in load factor;
    None on a fixed mesh), the mesh it was last located on (``model``, elements per shortest rod
    ``n``) and the state there (``point``, a PathPoint)."""

    kind: str
    lam: float
    error: float | None
    n: int
    model: object
    point: PathPoint


def critical_points(meshes, lam_end=1.0, first_only=False, target=TARGET, trace=None, max_steps=None):
    """The critical points of the path up to lam_end, refined (module docstring).

    ``meshes``: ``meshes(n) -> model`` with n elements per shortest rod, with ``meshes.first`` (the
    coarsest n) and ``meshes.adaptive`` (False: the mesh is fixed, nothing is refined); ``trace``: a
    Trace of the first mesh already computed.  Returns (critical points in path order, the trace of
    the first mesh)."""
    if trace is not None and getattr(trace, "model", None) is not None:
        n0, m0 = trace.n, trace.model
    else:
        n0 = meshes.first
        m0 = meshes(n0)
    if trace is None:
        trace = Tracer(m0, lam_end).trace(stop_at_limit=first_only, **({"max_steps": max_steps} if max_steps else {}))
    out = []
    for i, p in enumerate(trace.points):
        if p.kind == "limit":
            kind = "maximum" if _is_max(trace.points, i) else "minimum"
            out.append(_refine(meshes, n0, m0, p, kind, target))
        elif p.kind == "bifurcation":
            out.append(Critical("bifurcation", p.lam, None, n0, m0, p))
        if out and first_only:
            break
    return out, trace


def _is_max(points, i):
    """Whether the limit point points[i] is a maximum of the load factor (its neighbours lower)."""
    before = next((p.lam for p in reversed(points[:i]) if p.kind != "bifurcation"), None)
    return before is None or before <= points[i].lam


def _refine(meshes, n0, m0, p, kind, target):
    """A limit point followed onto finer meshes and extrapolated (module docstring)."""
    if not meshes.adaptive:
        return Critical(kind, p.lam, None, n0, m0, p)
    ctrl = _mode_part(m0, p.mode) if p.mode is not None else None
    lams = [p.lam]
    model, point, n = m0, p, n0
    ext, err = p.lam, None
    exts = []
    while 2 * n <= N_MAX and ctrl is not None:
        fine = meshes(2 * n)
        y, es = prolong(model, point.y, ElementState(point.alpha), fine)
        q = fold_on_mesh(fine, y, es.committed, point.lam, ctrl.dof(fine))
        if q is None or abs(q.lam - point.lam) > 0.2 * abs(point.lam) + 1e-12:
            break
        model, point, n = fine, q, 2 * n
        lams.append(q.lam)
        exts.append((4.0 * lams[-1] - lams[-2]) / 3.0)
        raw = abs(lams[-1] - lams[-2]) / 3.0
        err = raw if len(exts) < 2 else min(raw, abs(exts[-1] - exts[-2]) / 15.0 + 1e-15)
        ext = exts[-1]
        if len(exts) >= 2 and err <= target * max(abs(ext), 1e-300):
            break
        if len(exts) == 1 and raw <= 0.1 * target * max(abs(ext), 1e-300):
            ext = lams[-1]
            break
    return Critical(kind, ext, err, n, model, point)


BEYOND = 1.5   # the path is traced on the first mesh up to this load factor to find the critical point


def explain(meshes, exc: SolverFailure) -> SolverFailure:
    """The failure of a principal-branch solve restated with its first critical point (a limit
    point or a bifurcation, located and refined), or ``exc`` itself when there is none below full
    load or the path cannot be traced.  The first mesh is traced a little beyond full load
    (``BEYOND``): its limit point may lie above full load while the finer meshes' lies below."""
    try:
        found, trace = critical_points(meshes, BEYOND, first_only=True, max_steps=1000)
    except (SolverFailure, np.linalg.LinAlgError, ValueError, RuntimeError):
        return exc
    if not found or found[0].lam > 1.0 + 10.0 * (found[0].error or 0.0):
        return exc
    c = found[0]
    if c.kind == "bifurcation":
        ne = c.model.elements.size if c.model.elements is not None else 0
        msg = (f"bifurcation at load factor {c.lam:.7g} (located on the {ne}-element mesh): the tangent "
               f"stiffness turns singular while the load still grows; another branch crosses the principal "
               f"one there and the loads cannot be ramped to full value on it")
    else:
        est = "" if c.error is None else f" (estimated error {c.error:.1g})"
        msg = (f"limit point at load factor {c.lam:.7g}{est}: the load factor reaches its maximum there and "
               f"the loads cannot be ramped to full value on the principal branch (it would snap to another "
               f"equilibrium; `[solve] path = \"arc-length\"` follows the path through it)")
    new = SolverFailure(msg, exc.history)
    new.critical = c
    return new


def limit_points(meshes, trace, lam_end=1.0, target=TARGET):
    """The refined limit points (and bifurcations) of a traced path (an arc-length solve)."""
    found, _ = critical_points(meshes, lam_end, trace=trace, target=target)
    return found


def relative_error(c: Critical) -> float | None:
    """The relative error estimate of a critical point's load factor."""
    if c.error is None:
        return None
    return c.error / max(abs(c.lam), 1e-300) if math.isfinite(c.error) else None
