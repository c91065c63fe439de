"""Displacement control: the principal branch of a near-mechanism, one controlled dof at a time.

The structures of femslide are mechanisms to first order in the rigid limit: the tangent at phi = 0 is
singular and the potential quartic in phi (SPEC section 4), so load control from the undeformed state
fails or lands on the wrong branch.  :func:`principal_branch` therefore controls one dof (for the
paper's structures the body rotation phi): for a prescribed phi the system is well posed and the
load factor lam(phi) that holds it is an unknown.  Starting at phi = 0 (lam = 0) and moving phi
towards the side the load pushes, the principal equilibrium is the first phi with lam(phi) = 1 -
exactly the state reached by ramping the loads from zero.  A final Newton solve with lam = 1 and phi
free confirms it (quadratic convergence, residual history reported).  A maximum of lam before 1 is a
limit point: the run fails and says at which load factor.

The path following starts from a given state when there is one (the deformed spring-hinge mechanism
at the spring-hinge rotation, or a coarser mesh's solution) and falls back to the march from the
undeformed state when the load factor that holds that state's rotation is far from 1.
"""
from __future__ import annotations

import math

import numpy as np

from femslide.analysis.newton import newton
from femslide.joints.holds import DofHold
from femslide.model.state import ElementState
from femslide.errors import SolverFailure
from femslide.model.linalg import solve_linear
from femslide.records import dataclass


@dataclass
class Branch:
    y: np.ndarray
    elements: ElementState   # committed at y
    iterations: int
    history: list


def principal_branch(model, theta_dof, sign=-1.0, phi_guess=None, y0=None, elements0=None,
                     phi_max=math.pi, tol=1e-11):
    """Principal equilibrium at lam = 1 by control of one dof: its value is ``sign * phi`` and phi
    grows from 0 (for the paper's structures the body rotation, sign = -1: phi = -Theta).

    A maximum of the load factor before lam = 1 (d lam / d phi <= 0 at 0 < lam < 1) is a limit
    point: the path of ramped loads ends there, and SolverFailure says so and at which load factor.

    ``phi_guess`` (magnitude) is a first estimate (e.g. the equivalent spring-hinge model); ``y0``,
    ``elements0`` a state to start from (the deformed spring-hinge mechanism at phi_guess, or the
    interpolated solution of a coarser mesh), used only if the load factor that holds its rotation
    is between 0.25 and 2 and the path from it succeeds: otherwise the path starts from the
    undeformed state.
    Raises :class:`SolverFailure` with the residual history when it does not converge.
    """
    total_it = 0
    hist_all = []

    def controlled(phi, z0, es, maxit=40):
        """The state with phi prescribed, from z0 (committed into ``es``), or None."""
        nonlocal total_it
        z, info = newton(model, z0, es, control=DofHold(theta_dof, sign * phi), tol=tol, maxit=maxit)
        total_it += info.iterations
        hist_all.extend(info.history)
        if not info.converged:
            es.revert()
            return None
        es.commit()
        return z

    def tangent(z, es):
        """d z / d phi along the controlled path (its last entry is d lam / d phi)."""
        _, A, _ = model.system(z, es, control=DofHold(theta_dof, 0.0))
        es.revert()
        rhs = np.zeros(z.size)
        rhs[-1] = sign
        return solve_linear(A, rhs)

    def follow(y, elements, phi, lam, trial):
        """The path from the state (y, elements) with phi prescribed; ``trial``: give up early
        (raise) if the load factor holding that state's rotation is far from 1."""
        nonlocal total_it
        es = elements.copy()
        z_c = np.concatenate([y, [lam]])
        pred = z_c.copy()
        # start with the body already at the prescribed rotation: at the undeformed state the load
        # factor can be undetermined (a + d = 0: the weight has no moment about A1, a singular Jacobian)
        pred[theta_dof] = sign * phi
        phi_lo, phi_hi = 0.0, None
        last = None   # the last accepted point marching forward: (phi, z, d z / d phi)
        for _ in range(200):
            # a good start converges in a few iterations: do not spend long on a poor one
            committed = es.committed
            out = controlled(phi, pred, es, maxit=12 if trial else 40)
            if trial:
                trial = False
                if out is None or not 0.25 <= out[-1] <= 2.0:
                    raise SolverFailure("poor start: load factor far from 1", hist_all)
            if out is not None and last is not None and phi_hi is None and _jumped(model, last, phi, out):
                # a step that lands far from its tangent's prediction has jumped past a limit point (a
                # fold of the path between the two points): refuse it, as a failed step
                es.committed = es.trial = committed
                out = None
            if out is None:
                if phi - phi_lo <= 1e-12 * max(phi, 1e-300):
                    raise SolverFailure(f"path following stalled at {phi:.6g} of the controlled dof", hist_all,
                                        critical=True)
                phi = phi_lo + 0.5 * (phi - phi_lo)
                pred = z_c
                continue
            z = z_c = out
            lam = z[-1]
            if abs(lam - 1.0) <= 1e-13:
                break
            if abs(lam - 1.0) <= 1e-2:
                # close to full load: release phi; keep the result only if it stays on this branch
                y_f, info_f = newton(model, z[:model.n], es, lam=1.0, tol=tol)
                total_it += info_f.iterations
                if info_f.converged and abs(abs(y_f[theta_dof]) - phi) <= 0.05 * phi \
                        and np.sign(y_f[theta_dof]) == sign:
                    return Branch(y_f, es.commit(), total_it, info_f.history)
                es.revert()
            dz = tangent(z, es)
            slope = dz[-1]
            if phi_hi is None and lam <= 1.0:
                last = (phi, z, dz)
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
                                        f"value on the principal branch", hist_all, critical=True)
                else:
                    new = phi + min(0.1, phi)  # not yet loaded (lam <= 0): keep marching
                if phi_hi is not None and not new < phi_hi:
                    new = 0.5 * (phi + phi_hi)
                if new >= phi_max:
                    raise SolverFailure(f"no equilibrium on the principal branch up to {phi_max:g} of the "
                                        f"controlled dof (rad or model lengths)",
                                        hist_all, critical=True)
            if abs(new - phi) <= 1e-15 * phi:
                break
            pred = z + dz * (new - phi) if abs(new - phi) < 0.1 else z.copy()
            phi = new
        else:
            raise SolverFailure("path following did not reach the full load in 200 steps", hist_all, critical=True)
        y, info = newton(model, z_c[:model.n], es, lam=1.0, tol=tol)
        total_it += info.iterations
        if not info.converged:
            raise SolverFailure(f"final Newton solve at full load: {info.reason}", info.history)
        return Branch(y, es.commit(), total_it, info.history)

    if y0 is not None:
        try:
            return follow(y0, elements0, abs(y0[theta_dof]) or phi_guess or 0.01, 1.0, trial=True)
        except SolverFailure:
            pass  # a poor or failing start: the march from the undeformed state decides
    y, a = model.zero_state()
    return follow(y, a, min(phi_guess, 0.1) if phi_guess else 0.01, 0.0, trial=False)


def _jumped(model, last, phi, z):
    """Whether the controlled state z at phi left the neighbourhood of the tangent prediction from the
    last accepted point (its frame dofs off by more than the predicted increment itself): a step over
    a fold of the path (a limit point and the snap after it) lands on another branch, O(1) away,
    while a step along a smooth path is off by its curvature, small against the increment."""
    phi0, z0, dz0 = last
    n_q = model.n_q
    inc = dz0[:n_q] * (phi - phi0)
    return float(np.abs(z[:n_q] - z0[:n_q] - inc).max()) > max(float(np.abs(inc).max()), 1e-12)
