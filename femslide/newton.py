"""Newton's method on a model, and the path following that keeps it on the principal branch.

The structures of femslide are mechanisms to first order in the rigid limit: the tangent at phi = 0 is
singular and the potential quartic in phi (SPEC section 4), so load control from the undeformed state
fails or lands on the wrong branch.  :func:`principal_branch` therefore controls the body rotation
phi: for a prescribed phi the system is well posed and the load factor lam(phi) that holds it is an
unknown.  Starting at phi = 0 (lam = 0) and moving phi towards the side the load pushes, the
principal equilibrium is the first phi with lam(phi) = 1 — exactly the state reached by ramping
gravity from zero.  A final Newton solve with lam = 1 and phi free confirms it (quadratic convergence,
residual history reported).

Convergence: force residual below ``tol`` (1 + largest internal nodal force) and constraint residual
below ``tol`` (model units are nondimensional: lengths by a, forces by P).  A stiff model (EA/P up to
1e15) cannot reach ``tol``: its force residual is then accepted below the estimated round-off bound
of the element forces, but only when it is there both before and after a Newton step (so a residual
that merely dips under a loose bound is not taken for convergence), or after 4 steps there.

The path following starts from a given state when there is one (the deformed spring-hinge mechanism
at the spring-hinge rotation, or a coarser mesh's solution) and falls back to the march from the
undeformed state when the load factor that holds that state's rotation is far from 1.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .errors import SolverFailure
from .model import solve_linear


@dataclass
class NewtonInfo:
    converged: bool
    iterations: int
    history: list = field(default_factory=list)
    reason: str = ""
    alpha: np.ndarray = None  # chord rotations at the returned state (the next reference)


def newton(model, y, alpha_ref, lam=1.0, control=None, tol=1e-11, maxit=40, max_rot=0.5):
    """Newton iterations from y (modified copy returned).  Never raises: check ``info.converged``.

    Steps whose largest rotation increment exceeds ``max_rot`` [rad] are scaled down (a trust
    region for the corotational kinematics, which are exact but strongly nonlinear).
    """
    y = y.copy()
    n_q = model.n_q
    rot = model.rotation_dofs()
    hist = []
    prev = best = math.inf
    finfo = None
    stalled = floor_its = 0
    floor_step = False
    for it in range(1, maxit + 1):
        # after a step from a residual <= 1e-7, quadratic convergence predicts a converged state:
        # check the residual alone first, and assemble the Jacobian only if it is needed after all
        r, A, info = model.system(y, alpha_ref, lam, control, jacobian=not prev <= 1e-7)
        # relative to the internal forces, floored at the round-off level of the element forces
        # (estimated with the Jacobian; a residual-only evaluation keeps the last estimate)
        ar = np.abs(r)
        res_f = float(ar[:n_q].max()) / (1.0 + info["fmax"])
        res_g = float(ar[n_q:].max()) if r.size > n_q else 0.0
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
        if res_g <= tol and (res_f <= tol or (floor_step and res_f <= _floor(finfo))):
            return y, NewtonInfo(True, it - 1, hist, "" if res_f <= tol else "at round-off level",
                                 alpha=info["alpha"])
        if A is None:
            r, A, info = model.system(y, alpha_ref, lam, control)
            finfo = info
            if control is None and isinstance(A, np.ndarray):
                model.last_tangent = A
        at_floor = res_g <= tol and res_f <= _floor(finfo)
        floor_its = floor_its + 1 if at_floor else 0
        # stagnation at the round-off level of a stiff model: no progress for 4 iterations
        stalled = stalled + 1 if res > 0.5 * best else 0
        best = min(best, res)
        if stalled >= 4 and best <= 1e-7:
            return y, NewtonInfo(True, it - 1, hist, "stagnated at round-off level", alpha=info["alpha"])
        try:
            dy = -solve_linear(A, r)
        except (np.linalg.LinAlgError, RuntimeError, ValueError) as exc:
            return y, NewtonInfo(False, it, hist, f"singular tangent ({exc})")
        ady = np.abs(dy)
        if not math.isfinite(ady.max()):   # (a NaN propagates through max)
            return y, NewtonInfo(False, it, hist, "singular tangent (non-finite step)")
        big = ady[rot].max() if rot.size else 0.0
        if big > max_rot:
            dy *= max_rot / big
            ady *= max_rot / big
        y += dy
        floor_step = at_floor
        if floor_its >= 4:
            r, _, info = model.system(y, alpha_ref, lam, control, jacobian=False)
            hist.append(float(np.abs(r[:n_q]).max()) / (1.0 + info["fmax"]))
            return y, NewtonInfo(True, it, hist, "at round-off level", alpha=info["alpha"])
        # round-off floor: a step at the level of machine precision cannot improve further
        if res <= 1e3 * tol and res >= 0.5 * prev and \
                ady[:n_q].max() <= 1e-14 * (1.0 + np.abs(y[:n_q]).max()):
            r, _, info = model.system(y, alpha_ref, lam, control, jacobian=False)
            hist.append(float(np.abs(r).max()))
            return y, NewtonInfo(True, it, hist, alpha=info["alpha"])
        prev = res
    return y, NewtonInfo(False, maxit, hist, f"no convergence in {maxit} iterations")


def _floor(info):
    """The relative round-off floor of the force residual (the model's estimate, computed when read)."""
    return info["noise"] / (1.0 + info["fmax"])


@dataclass
class Branch:
    y: np.ndarray
    alpha: np.ndarray
    iterations: int
    history: list


def principal_branch(model, theta_dof, sign=-1.0, phi_guess=None, y0=None, alpha0=None,
                     phi_max=math.pi, tol=1e-11):
    """Principal equilibrium at lam = 1 by control of one dof: its value is ``sign * phi`` and phi
    grows from 0 (for the paper's structures the body rotation, sign = -1: phi = -Theta).

    A maximum of the load factor before lam = 1 (d lam / d phi <= 0 at 0 < lam < 1) is a limit
    point: the path of ramped loads ends there, and SolverFailure says so and at which load factor.

    ``phi_guess`` (magnitude) is a first estimate (e.g. the equivalent spring-hinge model); ``y0``,
    ``alpha0`` a state to start from (the deformed spring-hinge mechanism at phi_guess, or the
    interpolated solution of a coarser mesh), used only if the load factor that holds its rotation
    is between 0.25 and 2 and the path from it succeeds: otherwise the path starts from the
    undeformed state.
    Raises :class:`SolverFailure` with the residual history when it does not converge.
    """
    total_it = 0
    hist_all = []

    def controlled(phi, z0, a0, maxit=40):
        nonlocal total_it
        z, info = newton(model, z0, a0, control=(theta_dof, sign * phi), tol=tol, maxit=maxit)
        total_it += info.iterations
        hist_all.extend(info.history)
        if not info.converged:
            return None
        return z, info.alpha

    def tangent(z, a):
        """d z / d phi along the controlled path (its last entry is d lam / d phi)."""
        _, A, _ = model.system(z, a, control=(theta_dof, 0.0))
        rhs = np.zeros(z.size)
        rhs[-1] = sign
        return solve_linear(A, rhs)

    def follow(y, a, phi, lam, trial):
        """The path from the state (y, a) with phi prescribed; ``trial``: give up early (raise) if
        the load factor holding that state's rotation is far from 1."""
        nonlocal total_it
        z_c, a_c = np.concatenate([y, [lam]]), a.copy()
        pred = z_c.copy()
        # start with the body already at the prescribed rotation: at the undeformed state the load
        # factor can be undetermined (a + d = 0: the weight has no moment about A1, a singular Jacobian)
        pred[theta_dof] = sign * phi
        phi_lo, phi_hi = 0.0, None
        for _ in range(200):
            # a good start converges in a few iterations: do not spend long on a poor one
            out = controlled(phi, pred, a_c, maxit=12 if trial else 40)
            if trial:
                trial = False
                if out is None or not 0.25 <= out[0][-1] <= 2.0:
                    raise SolverFailure("poor start: load factor far from 1", hist_all)
            if out is None:
                if phi - phi_lo <= 1e-12 * max(phi, 1e-300):
                    raise SolverFailure(f"path following stalled at {phi:.6g} of the controlled dof", hist_all)
                phi = phi_lo + 0.5 * (phi - phi_lo)
                pred = z_c
                continue
            z, a = out
            lam = z[-1]
            z_c, a_c = z, a
            if abs(lam - 1.0) <= 1e-13:
                break
            if abs(lam - 1.0) <= 1e-2:
                # close to full load: release phi; keep the result only if it stays on this branch
                y_f, info_f = newton(model, z[:model.n], a, lam=1.0, tol=tol)
                total_it += info_f.iterations
                if info_f.converged and abs(abs(y_f[theta_dof]) - phi) <= 0.05 * phi \
                        and np.sign(y_f[theta_dof]) == sign:
                    return Branch(y_f, info_f.alpha, total_it, info_f.history)
            dz = tangent(z, a)
            slope = dz[-1]
            if lam > 1.0:
                phi_hi = phi
                new = phi - (lam - 1.0) / slope if slope > 0 else 0.5 * (phi + phi_lo)
                if not phi_lo < new < phi:
                    new = 0.5 * (phi + phi_lo)
            else:
                phi_lo = phi
                if slope > 0 and lam > 0:
                    # Newton in log-log: lam ~ phi^p near the rigid limit (p = 3 for a quartic potential)
                    p = max(slope * phi / lam, 0.5)
                    new = min(phi * lam ** (-1.0 / p), 2.0 * phi, phi + 0.35)
                elif lam > 0.05 and slope <= 0:
                    raise SolverFailure(f"limit point: the load factor reaches its maximum {lam:.6g} < 1 at "
                                        f"{phi:.6g} of the controlled dof; the loads cannot be ramped to full "
                                        f"value on the principal branch", hist_all)
                else:
                    new = phi + min(0.1, phi)  # not yet loaded (lam <= 0): keep marching
                if phi_hi is not None and not new < phi_hi:
                    new = 0.5 * (phi + phi_hi)
                if new >= phi_max:
                    raise SolverFailure(f"no equilibrium on the principal branch up to {phi_max:g} of the "
                                        f"controlled dof (rad or model lengths)",
                                        hist_all)
            if abs(new - phi) <= 1e-15 * phi:
                break
            pred = z + dz * (new - phi) if abs(new - phi) < 0.1 else z.copy()
            phi = new
        else:
            raise SolverFailure("path following did not reach the full load in 200 steps", hist_all)
        y, info = newton(model, z_c[:model.n], a_c, lam=1.0, tol=tol)
        total_it += info.iterations
        if not info.converged:
            raise SolverFailure(f"final Newton solve at full load: {info.reason}", info.history)
        return Branch(y, info.alpha, total_it, info.history)

    if y0 is not None:
        try:
            return follow(y0, alpha0, abs(y0[theta_dof]) or phi_guess or 0.01, 1.0, trial=True)
        except SolverFailure:
            pass  # a poor or failing start: the march from the undeformed state decides
    y, a = model.zero_state()
    return follow(y, a, min(phi_guess, 0.1) if phi_guess else 0.01, 0.0, trial=False)
