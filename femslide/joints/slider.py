"""The slider (a sliding clamp, a prismatic joint): a's point stays on the guide line through ``at``
along ``axis`` carried by b, and a turns with b (w . n = 0, theta_a - theta_b = 0: 2 equations).

The slide s = w . e [m] along the guide is free (reported from the reference position; a spring
``k`` with ``preload`` and Coulomb friction ``mu``/``mu0`` act on it).  The multipliers are the
transverse force Q and the moment M: the force on a is -Q n, its moment -M.  Stuck by friction it
is a weld.  With ``bearing = h`` friction's normal force is that of the guide's two bearings h apart,
which carry Q/2 + M/h and Q/2 - M/h: N = |Q/2 + M/h| + |Q/2 - M/h|; without one N = |Q|.
"""
from __future__ import annotations

import math

from femslide.joints.kind import JointKind, on_guide, same_rotation


class Slider(JointKind):
    name = "slider"
    size = 2
    accepts = frozenset(("axis", "k", "preload", "mu", "mu0", "unilateral", "restitution", "bearing"))
    free = "slide"
    stuck = "weld"
    symbol = "sleeve"
    code = 2
    springs = {"kn": 0, "kr": 1}

    def equations(self, link, z):
        w = link.w(z)
        g, G, hess = [], [], []
        on_guide(link, w, g, G, hess)
        same_rotation(link, w, g, G)
        return g, G, hess

    def normal_force(self, mu, h):
        if not h:
            return super().normal_force(mu, h)
        Q, M = mu[0], mu[1]
        c1, c2 = 0.5 * Q + M / h, 0.5 * Q - M / h
        s1, s2 = math.copysign(1.0, c1), math.copysign(1.0, c2)
        return abs(c1) + abs(c2), [0.5 * (s1 + s2), (s1 - s2) / h]
