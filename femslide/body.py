"""Rigid body kinematics: a body point's position and its first and second derivatives.

Body dofs (U, V, Theta): displacement [m] of the reference point from its initial position ``A0``
and rotation [rad], counter-clockwise positive (the paper's phi is -Theta).  A body-fixed point with
local offset r (its initial position minus A0) sits at A0 + (U, V) + R(Theta) r.
"""
from __future__ import annotations

from dataclasses import dataclass
import math

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

    def place(self, zb, r):
        """Scalars (x, y, Rr_x, Rr_y): position of the body point with offset r and R(Theta) r
        (d/dTheta of the position is (-Rr_y, Rr_x), d2/dTheta2 is -Rr).  ``math`` only: the joints
        call it in every Newton iteration."""
        c, s = math.cos(zb[2]), math.sin(zb[2])
        rx, ry = r
        Rx, Ry = c * rx - s * ry, s * rx + c * ry
        return self.A0[0] + zb[0] + Rx, self.A0[1] + zb[1] + Ry, Rx, Ry

    def point(self, zb, r):
        """Position of the body point with offset r, d/dTheta and d2/dTheta2 of it (arrays)."""
        px, py, Rx, Ry = self.place(zb, r)
        return np.array([px, py]), np.array([-Ry, Rx]), np.array([-Rx, -Ry])
