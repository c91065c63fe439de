"""Loads as potential-energy terms, scaled by the load factor lam while the loads are ramped.

Dead forces and moments on a frame's origin (a rod node, a body's centroid) have a linear
potential: the model adds them to one constant load vector (no Hessian, no Jacobian entries).  A
force applied at a body point away from the centroid turns with the body: it is a term with a
Hessian (:class:`PointForce`).  Distributed loads on rods are turned into nodal loads by
:func:`distributed_nodal_loads`.
"""
from __future__ import annotations

import math

import numpy as np

from femslide.records import dataclass


@dataclass
class PointForce:
    """Dead force F (2,) and moment M on a body point at reference offset r from the body's centroid
    (model units); dofs = the body's (u, v, theta).  Potential -lam [F . (u + R r - r) + M theta]."""

    dofs: np.ndarray
    r: tuple
    F: tuple
    M: float = 0.0
    name: str = "force"

    def _arm(self, z):
        """(t, Rx, Ry): the body's rotation at z and its arm r turned by it."""
        t = float(z[2])
        c, s = math.cos(t), math.sin(t)
        rx, ry = self.r
        return t, c * rx - s * ry, s * rx + c * ry

    def eval(self, z, lam=1.0):
        t, Rx, Ry = self._arm(z)
        rx, ry = self.r
        Fx, Fy = self.F
        E = -(Fx * (z[0] + Rx - rx) + Fy * (z[1] + Ry - ry) + self.M * t)
        g0 = np.array([-Fx, -Fy, -(Fx * -Ry + Fy * Rx) - self.M])
        H = np.zeros((3, 3))
        H[2, 2] = lam * (Fx * Rx + Fy * Ry)
        return lam * E, lam * g0, H, g0

    def energy(self, z, lam=1.0):
        """:meth:`eval`'s energy alone (the same arithmetic)."""
        t, Rx, Ry = self._arm(z)
        rx, ry = self.r
        Fx, Fy = self.F
        return lam * -(Fx * (z[0] + Rx - rx) + Fy * (z[1] + Ry - ry) + self.M * t)

    def assemble(self, z, lam, rv, jv, fv):
        """:meth:`eval` as Python floats for the model's assembly (``z`` a list): appends the
        generalised force to ``rv``, the Hessian (3 x 3) to ``jv`` (unless None) and d/d lam of the
        force to ``fv``."""
        t = z[2]
        c, s = math.cos(t), math.sin(t)
        rx, ry = self.r
        Rx, Ry = c * rx - s * ry, s * rx + c * ry
        Fx, Fy = self.F
        g0 = [-Fx, -Fy, -(Fx * -Ry + Fy * Rx) - self.M]
        rv += [lam * x for x in g0]
        if jv is not None:
            jv += [0.0] * 8
            jv.append(lam * (Fx * Rx + Fy * Ry))
        fv += g0

    def stress_hessian(self, z, lam=1.0, linear=None):
        """The Hessian's part that scales with the load (all of it: a load turning with its body),
        at ``z`` (``linear``: at the reference, z = 0)."""
        H = np.zeros((3, 3))
        t = 0.0 if linear is not None else float(z[2])
        c, s = math.cos(t), math.sin(t)
        rx, ry = self.r
        H[2, 2] = lam * (self.F[0] * (c * rx - s * ry) + self.F[1] * (s * rx + c * ry))
        return H


def distributed_nodal_loads(X, q, q_end=None):
    """Nodal loads (n_nodes, 3) = (Fx, Fy, Mz) of a dead load per unit reference length on a rod meshed
    with the nodes X (n_nodes, 2): q (2,) [global components] at the rod's start, varying linearly in
    the arc length to ``q_end`` at its end (default q: uniform).  Each element passes its consistent
    loads to its nodes - exact for a linear beam: the load's component along the element's reference
    tangent by linear shape functions, L (2 a1 + a2) / 6 and L (a1 + 2 a2) / 6, the normal one by the
    cubic Hermite ones, L (7 p1 + 3 p2) / 20, L (3 p1 + 7 p2) / 20 and the end moments
    +L^2 (3 p1 + 2 p2) / 60, -L^2 (2 p1 + 3 p2) / 60 (uniform: q L / 2 each and +-q_perp L^2 / 12)."""
    D = np.diff(X, axis=0)
    L = np.hypot(D[:, 0], D[:, 1])
    q = np.asarray(q, float)
    nrm = np.column_stack([-D[:, 1], D[:, 0]]) / L[:, None]
    qp = nrm @ q
    out = np.zeros((X.shape[0], 3))
    if q_end is None or np.array_equal(np.asarray(q_end, float), q):
        half = 0.5 * L[:, None] * q[None, :]
        out[:-1, :2] += half
        out[1:, :2] += half
        out[:-1, 2] += qp * L * L / 12.0
        out[1:, 2] -= qp * L * L / 12.0
        return out
    s = np.concatenate([[0.0], np.cumsum(L)])
    f = (s / s[-1])[:, None]
    qn = q[None, :] + f * (np.asarray(q_end, float) - q)[None, :]     # the load at the nodes
    q1, q2 = qn[:-1], qn[1:]
    tan = D / L[:, None]
    a1, a2 = np.einsum("ij,ij->i", q1, tan), np.einsum("ij,ij->i", q2, tan)
    p1, p2 = np.einsum("ij,ij->i", q1, nrm), np.einsum("ij,ij->i", q2, nrm)
    F1 = (L * (2 * a1 + a2) / 6.0)[:, None] * tan + (L * (7 * p1 + 3 * p2) / 20.0)[:, None] * nrm
    F2 = (L * (a1 + 2 * a2) / 6.0)[:, None] * tan + (L * (3 * p1 + 7 * p2) / 20.0)[:, None] * nrm
    out[:-1, :2] += F1
    out[1:, :2] += F2
    out[:-1, 2] += L * L * (3 * p1 + 2 * p2) / 60.0
    out[1:, 2] -= L * L * (2 * p1 + 3 * p2) / 60.0
    return out
