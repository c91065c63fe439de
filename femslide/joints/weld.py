"""The weld: a's point and rotation stay those of b (w = 0, theta_a - theta_b = 0: 3 equations).

Its multipliers are minus its force and moment on a (mu = -(Fx, Fy, M), the moment about a's point).
"""
from __future__ import annotations

from femslide.joints.kind import JointKind, coincide, same_rotation


class Weld(JointKind):
    name = "weld"
    size = 3
    linear = True
    symbol = "clamp"
    code = 1
    springs = {"kx": 0, "ky": 1, "kr": 2}

    def equations(self, link, z):
        w = link.w(z)
        g, G, hess = [], [], []
        coincide(link, w, g, G, hess)
        same_rotation(link, w, g, G)
        return g, G, hess
