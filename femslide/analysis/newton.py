"""Newton's method on a model: the one nonlinear solver of the statics and of every time step.

``newton(model, y, elements, ...)`` iterates on any object with the model's interface (``n_q``,
``rotation_dofs()``, ``system(y, elements, lam, control, jacobian)``): the discrete model itself
(statics, load or displacement control) or a time step's stage equations (femslide.analysis.radau).
Its evaluations are trials of the elements' history (femslide.model.state.ElementState): on return
the trial rotations are those of the returned state, and the caller commits them (a converged
state it keeps) or reverts them.

Convergence: force residual below ``tol`` (1 + largest internal nodal force) and constraint residual
below ``tol`` (model units are nondimensional: lengths by a, forces by P); a caller whose forces of
interest are smaller than that (a time step: the motion's forces, not the static ones) gives their
scale ``fscale``, and the force residual is measured against the smaller of the two.  A stiff model
(EA/P up to 1e15) cannot reach ``tol``: its force residual is then accepted below the estimated
round-off bound of the element forces, but only when it is there both before and after a Newton step (so a residual
that merely dips under a loose bound is not taken for convergence), or after 4 steps there.  A
caller may ask (``reuse``) for chord steps: the last matrix kept while each residual is cut by
``reuse`` or more (a time step's first matrix often carries it to convergence: a residual
evaluation without the matrix, its assembly and its LU costs a third of a full iteration), assembled
afresh where the contraction is slower.  Steps
that would turn a rotation by more than ``max_rot`` are scaled down (a trust region for the exact but
strongly nonlinear corotational kinematics).  Never raises: the caller reads ``info.converged`` and
the residual history.
"""
from __future__ import annotations

import math

import numpy as np

from femslide.model.linalg import norms, solve_linear
from femslide.records import dataclass, field


@dataclass
class NewtonInfo:
    converged: bool
    iterations: int
    history: list = field(default_factory=list)
    reason: str = ""


def newton(model, y, elements, lam=1.0, control=None, tol=1e-11, maxit=40, max_rot=0.5, fscale=None,
           reuse=None):
    """Newton iterations from y (modified copy returned).  Never raises: check ``info.converged``.

    Steps whose largest rotation increment exceeds ``max_rot`` [rad] are scaled down (a trust
    region for the corotational kinematics, which are exact but strongly nonlinear).  ``fscale``
    (model units, or None): the force residual is relative to min(1 + largest internal force,
    fscale).  ``reuse`` (a factor < 1, or None): chord steps (the module docstring).
    """
    y = y.copy()
    n_q = model.n_q
    rot = model.rotation_dofs()
    hist = []
    prev = best = math.inf
    finfo = None
    stalled = floor_its = 0
    floor_step = False
    last = None   # the last matrix (reuse's chord steps)
    for it in range(1, maxit + 1):
        # after a step from a residual <= 1e-7, quadratic convergence predicts a converged state:
        # check the residual alone first, and assemble the Jacobian only if it is needed after all
        # (and so with ``reuse``, where the last matrix may do)
        r, A, info = model.system(y, elements, lam, control, jacobian=not (prev <= 1e-7 or last is not None))
        # relative to the internal forces, floored at the round-off level of the element forces
        # (estimated with the Jacobian; a residual-only evaluation keeps the last estimate)
        rq, res_g, _ = norms(r, n_q)
        res_f = rq / _denominator(info, fscale)
        if A is not None:
            finfo = info   # the round-off floor of this state, estimated when first needed
        res = max(res_f, res_g)
        hist.append(res)
        if A is not None and control is None and isinstance(A, np.ndarray):
            model.last_tangent = A   # for a stability check of the solution (solve_linear keeps A)
        if not math.isfinite(res):
            return y, NewtonInfo(False, it, hist, "residual is not finite")
        # converged: below tol, or below the (worst-case) round-off bound, under which the residual
        # no longer measures the error, both before and after a Newton step
        if res_g <= tol and (res_f <= tol or (floor_step and res_f <= _floor(finfo, fscale))):
            return y, NewtonInfo(True, it - 1, hist, "" if res_f <= tol else "at round-off level")
        if A is None and last is not None and res <= reuse * prev:
            A = last   # a chord step
        elif A is None:
            r, A, info = model.system(y, elements, lam, control)
            finfo = info
            if control is None and isinstance(A, np.ndarray):
                model.last_tangent = A
        at_floor = res_g <= tol and res_f <= _floor(finfo, fscale)
        floor_its = floor_its + 1 if at_floor else 0
        # stagnation at the round-off level of a stiff model: no progress for 4 iterations
        stalled = stalled + 1 if res > 0.5 * best else 0
        best = min(best, res)
        if stalled >= 4 and best <= 1e-7:
            return y, NewtonInfo(True, it - 1, hist, "stagnated at round-off level")
        if reuse is not None:
            last = A
        try:
            step = solve_linear(A, r)   # the Newton step is -step
        except (np.linalg.LinAlgError, RuntimeError, ValueError) as exc:
            return y, NewtonInfo(False, it, hist, f"singular tangent ({exc})")
        sq, sc, big = norms(step, n_q, rot)
        if not (math.isfinite(sq) and math.isfinite(sc)):   # (a NaN propagates through the norms)
            return y, NewtonInfo(False, it, hist, "singular tangent (non-finite step)")
        if big > max_rot:
            step *= max_rot / big
            sq *= max_rot / big
        y -= step
        floor_step = at_floor
        if floor_its >= 4:
            r, _, info = model.system(y, elements, lam, control, jacobian=False)
            hist.append(float(np.abs(r[:n_q]).max()) / _denominator(info, fscale))
            return y, NewtonInfo(True, it, hist, "at round-off level")
        # round-off floor: a step at the level of machine precision cannot improve further
        if res <= 1e3 * tol and res >= 0.5 * prev and sq <= 1e-14 * (1.0 + norms(y, n_q)[0]):
            r, _, info = model.system(y, elements, lam, control, jacobian=False)
            hist.append(float(np.abs(r).max()))
            return y, NewtonInfo(True, it, hist)
        prev = res
    return y, NewtonInfo(False, maxit, hist, f"no convergence in {maxit} iterations")


def _denominator(info, fscale):
    """What the force residual is measured against: 1 + the largest internal force, or ``fscale``
    when that is smaller."""
    d = 1.0 + info["fmax"]
    return d if fscale is None else min(d, fscale)


def _floor(info, fscale=None):
    """The relative round-off floor of the force residual (the model's estimate, computed when read)."""
    return info["noise"] / _denominator(info, fscale)
