"""Loads as potential-energy terms, scaled by the load factor lam while the loads are ramped.

Dead forces and moments on a frame's origin (a rod node, a body's centroid) have a linear
potential: the model adds them to one constant load vector (no Hessian, no Jacobian entries).  A
force applied at a body point away from the centroid turns with the body: it is a term with a
Hessian (:class:`PointForce`).  Distributed loads on rods are turned into nodal loads by
:func:`distributed_nodal_loads`.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np


@dataclass
class PointForce:
    """Dead force F (2,) and moment M on a body point at reference offset r from the body's centroid
    (model units); dofs = the body's (u, v, theta).  Potential -lam [F . (u + R r - r) + M theta]."""

    dofs: np.ndarray
    r: tuple
    F: tuple
    M: float = 0.0
    name: str = "force"

    def eval(self, z, lam=1.0):
        t = float(z[2])
        c, s = math.cos(t), math.sin(t)
        rx, ry = self.r
        Rx, Ry = c * rx - s * ry, s * rx + c * ry
        Fx, Fy = self.F
        E = -(Fx * (z[0] + Rx - rx) + Fy * (z[1] + Ry - ry) + self.M * t)
        g0 = np.array([-Fx, -Fy, -(Fx * -Ry + Fy * Rx) - self.M])
        H = np.zeros((3, 3))
        H[2, 2] = lam * (Fx * Rx + Fy * Ry)
        return lam * E, lam * g0, H, g0

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


def distributed_nodal_loads(X, q):
    """Nodal loads (n_nodes, 3) = (Fx, Fy, Mz) of a dead load q (2,) per unit reference length on a
    rod meshed with the nodes X (n_nodes, 2): each element passes q L/2 to each node and the
    consistent end moments +-q_perp L^2/12 (q_perp: component along the element's reference normal),
    exact for a linear beam; interior end moments cancel for a uniform load and mesh."""
    D = np.diff(X, axis=0)
    L = np.hypot(D[:, 0], D[:, 1])
    nrm = np.column_stack([-D[:, 1], D[:, 0]]) / L[:, None]
    qp = nrm @ np.asarray(q, float)
    out = np.zeros((X.shape[0], 3))
    half = 0.5 * L[:, None] * np.asarray(q, float)[None, :]
    out[:-1, :2] += half
    out[1:, :2] += half
    out[:-1, 2] += qp * L * L / 12.0
    out[1:, 2] -= qp * L * L / 12.0
    return out
