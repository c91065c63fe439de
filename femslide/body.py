"""Rigid body kinematics: a body point's position and its first and second derivatives.

Body dofs (U, V, Theta): displacement [m] of the reference point from its initial position ``A0``
and rotation [rad], counter-clockwise positive (the paper's phi is -Theta).  A body-fixed point with
local offset r (its initial position minus A0) sits at A0 + (U, V) + R(Theta) r.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np


def rot(theta):
    c, s = np.cos(theta), np.sin(theta)
    return np.array([[c, -s], [s, c]])


@dataclass(frozen=True)
class Body:
    """A rigid body: reference point ``A0`` [m] and the index of its first dof in the model."""

    A0: np.ndarray
    dof0: int = -1

    @property
    def dofs(self):
        return np.arange(self.dof0, self.dof0 + 3)

    def point(self, zb, r):
        """Position of the body point with offset r, d/dTheta and d2/dTheta2 of it."""
        R = rot(zb[2])
        Rr = R @ np.asarray(r, float)
        dRr = np.array([-Rr[1], Rr[0]])
        return self.A0 + zb[:2] + Rr, dRr, -Rr
