"""Loads as potential-energy terms, scaled by the load factor lam while the load is ramped.

Each term acts on a few model dofs and returns (energy, gradient, Hessian, d gradient / d lam).
Gravity acts in -y: the potential of a weight W [N] at height y is W y.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .body import Body
from .joints import node_dofs


@dataclass
class BodyWeight:
    """Weight W [N] at the body point with local offset r."""

    body: Body
    r: np.ndarray
    W: float
    name: str = "weight"

    @property
    def dofs(self):
        return self.body.dofs

    def eval(self, z, lam=1.0):
        _, py, Rx, Ry = self.body.place(z.tolist(), self.r)
        W = self.W
        g0 = np.array([0.0, W, W * Rx])
        H = np.zeros((3, 3))
        H[2, 2] = -lam * W * Ry
        return lam * W * py, lam * g0, H, g0


@dataclass
class RigidPieceWeight:
    """Weight W [N] of a rigid piece attached to rod node ``node`` and turning with the body:
    its centre sits at the node plus h along the body's guide direction e = R(Theta) (0, 1)."""

    node: int
    X0: np.ndarray
    body: Body
    h: float
    W: float
    name: str = "piece weight"

    @property
    def dofs(self):
        return np.concatenate([node_dofs(self.node), self.body.dofs])

    def eval(self, z, lam=1.0):
        th = z[5]
        y = self.X0[1] + z[1] + self.h * np.cos(th)
        g0 = np.zeros(6)
        g0[1], g0[5] = self.W, -self.W * self.h * np.sin(th)
        H = np.zeros((6, 6))
        H[5, 5] = -lam * self.W * self.h * np.cos(th)
        return lam * self.W * y, lam * g0, H, g0


@dataclass
class NodeLoad:
    """Dead force (Fx, Fy) [N] and moment Mz [N m] (counter-clockwise) on a rod node."""

    node: int
    F: np.ndarray  # (Fx, Fy, Mz)
    name: str = "nodal load"

    @property
    def dofs(self):
        return node_dofs(self.node)

    def eval(self, z, lam=1.0):
        g0 = -np.asarray(self.F, float)
        return lam * (g0 @ z), lam * g0, np.zeros((3, 3)), g0
