"""The pin: a's point stays on b's point, the rotations are free (a hinge; w = 0, 2 equations).

Its multipliers are minus its force on a (mu = -(Fx, Fy)); a rotational spring ``c`` [N m/rad] may
act on theta_a - theta_b, reported as the joint's ``rotation`` [rad].
"""
from __future__ import annotations

from femslide.joints.kind import JointKind, coincide


class Pin(JointKind):
    name = "pin"
    size = 2
    accepts = frozenset(("c",))
    free = "rotation"
    linear = True
    pivot = True
    symbol = "hinge"
    code = 0
    springs = {"kx": 0, "ky": 1}

    def equations(self, link, z):
        w = link.w(z)
        g, G, hess = [], [], []
        coincide(link, w, g, G, hess)
        return g, G, hess
