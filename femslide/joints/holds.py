"""Holds: exact constraints that keep one quantity of the structure at a target value.

A hold adds equations g(z) = value(z) - target = 0 over a few dofs z of the model, with their
gradient G and Hessians (the constraint protocol of femslide.joints.base.Link: ``size``, ``dofs``,
``eval(z, mu)``), and Lagrange multipliers that are the generalised forces holding it (model units):

- :class:`DofHold`: one dof of the model (the controlled dof of displacement control, where the
  load factor is the extra unknown instead of a multiplier; femslide.analysis.continuation);
- :class:`SlideHold`: the slide of a slider or roller (a stuck friction joint; a simulation's start
  held at a given slide);
- :class:`BodyHold`: a body's rotation [rad] and/or the displacement of its centroid along a
  direction (a simulation's start held at a given tilt or offset).

``target`` may be changed between solves (walking a hold to its value, a joint stuck elsewhere).
"""
from __future__ import annotations

import math

import numpy as np


class Hold:
    """Base of the holds: :meth:`eval` from the subclass's :meth:`parts`, the value, its gradient
    (size, k) and Hessians (size, k, k) over the hold's dofs ``z``."""

    size = 1
    dofs: np.ndarray
    target = 0.0
    name = "hold"

    def parts(self, z):
        raise NotImplementedError

    def value(self, z):
        """The held quantities at z (array of ``size``)."""
        return self.parts(z)[0]

    def eval(self, z, mu=None):
        """g = value - target, G and the Hessians (size, k, k), or with the multipliers ``mu`` their
        weighted sum (k, k)."""
        v, G, H = self.parts(z)
        g = v - self.target
        if mu is not None:
            return g, G, np.einsum("i,ijk->jk", np.atleast_1d(mu), H)
        return g, G, H


class DofHold(Hold):
    """One dof of the model held at ``target`` (model units)."""

    def __init__(self, dof: int, target: float = 0.0, name="control"):
        self.dof, self.target, self.name = int(dof), float(target), name
        self.dofs = np.array([self.dof], np.intp)

    def parts(self, z):
        return np.array([float(z[0])]), np.ones((1, 1)), np.zeros((1, 1, 1))


class SlideHold(Hold):
    """The slide s of a slider's or roller's link (femslide.joints.base.Link.slide) held at
    ``origin + target``: a stuck friction joint (origin 0, target the slide where it stuck) and the
    held start of a simulation (origin the reference slide, target walked to the initial one)."""

    def __init__(self, link, target=0.0, name="lock", origin=0.0):
        self.link, self.target, self.name, self.origin = link, target, name, origin
        self.dofs = link.dofs

    def parts(self, z):
        s, ds, H = self.link.slide(z)
        return np.array([s - self.origin]), ds[None, :], H[None]

    def eval(self, z, mu=None):   # (one equation: no einsum)
        s, ds, H = self.link.slide(z)
        g = np.array([s - self.origin]) - self.target
        if mu is not None:
            return g, ds[None, :], mu[0] * H
        return g, ds[None, :], H[None]


class BodyHold(Hold):
    """A body's centroid displacement along a direction e (its component along e, model lengths)
    and/or its rotation [rad] held; ``d`` the body's first dof, ``r`` the centroid's offset from
    the body's frame origin (model lengths), ``what`` a list of "u" (along e) and "rot"."""

    def __init__(self, d, r, what, e=(1.0, 0.0), name="body hold"):
        self.d, self.r, self.what, self.e, self.name = d, r, what, e, name
        self.size = len(what)
        self.dofs = np.arange(d, d + 3, dtype=np.intp)
        self.target = np.zeros(self.size)

    def parts(self, z):
        c, s = math.cos(z[2]), math.sin(z[2])
        rx, ry = self.r
        Rx, Ry = c * rx - s * ry, s * rx + c * ry
        ex, ey = self.e
        vals = {"u": (z[0] + Rx - rx) * ex + (z[1] + Ry - ry) * ey, "rot": z[2]}
        rows = {"u": [ex, ey, -Ry * ex + Rx * ey], "rot": [0.0, 0.0, 1.0]}
        hrow = {"u": -Rx * ex - Ry * ey, "rot": 0.0}
        H = np.zeros((self.size, 3, 3))
        for i, w in enumerate(self.what):
            H[i, 2, 2] = hrow[w]
        return np.array([vals[w] for w in self.what]), np.array([rows[w] for w in self.what]), H
