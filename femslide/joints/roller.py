"""The roller: a's point stays on the guide line through ``at`` along ``axis`` carried by b; the
rotations are free (w . n = 0: 1 equation).

The slide s = w . e [m] is free as for the slider (spring ``k``, ``preload``, friction ``mu``/``mu0``
with the normal force N = |Q|).  The multiplier Q is the transverse force: the force on a is -Q n.
Stuck by friction it is a pin.
"""
from __future__ import annotations

from femslide.joints.kind import JointKind, on_guide


class Roller(JointKind):
    name = "roller"
    size = 1
    accepts = frozenset(("axis", "k", "preload", "mu", "mu0", "unilateral", "restitution"))
    free = "slide"
    stuck = "pin"
    symbol = "roller"
    code = 3
    springs = {"kn": 0}

    def equations(self, link, z):
        w = link.w(z)
        g, G, hess = [], [], []
        on_guide(link, w, g, G, hess)
        return g, G, hess
