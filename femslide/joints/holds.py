"""Holds: exact constraints that keep one quantity of the structure at a target value.

A hold adds equations g(z) = value(z) - target = 0 over a few dofs z of the model, with their
gradient and Hessian (the protocol of femslide.joints.base.Link: ``size``, ``dofs``, ``eval``), and
Lagrange multipliers that are the generalised forces holding it:

- :class:`SlideLock`: the slide of a slider or roller (a stuck friction joint; a simulation's start
  held at a given slide);
- :class:`BodyHold`: a body's rotation and/or the displacement of its centroid along a direction (a
  simulation's start held at a given tilt or offset).
"""
from __future__ import annotations

import math

import numpy as np


class SlideLock:
    """Exact constraint s(q) - origin - target = 0 on a slider's or roller's slide s (joints.py
    protocol): a stuck friction joint (origin 0, target the slide where it stuck) and the held
    start of a simulation (origin the reference slide, target walked to the initial one)."""

    size = 1

    def __init__(self, link, target=0.0, name="lock", origin=0.0):
        self.link, self.target, self.name, self.origin = link, target, name, origin
        self.dofs = link.dofs

    def value(self, z):
        """The held quantity s - origin (array of one)."""
        return np.array([self.link.slide(z)[0] - self.origin])

    def eval(self, z, mu=None):
        s, ds, H = self.link.slide(z)
        g = np.array([s - self.origin]) - self.target
        if mu is not None:
            return g, ds[None, :], mu[0] * H
        return g, ds[None, :], H[None]


class BodyHold:
    """Exact constraint holding a body's centroid displacement along a direction e (its component
    along e) and/or its rotation (joints.py protocol); ``what``: list of "u" (along e), "rot"."""

    def __init__(self, d, r, what, e=(1.0, 0.0)):
        self.d, self.r, self.what, self.e = d, r, what, e
        self.size = len(what)
        self.dofs = np.arange(d, d + 3, dtype=np.intp)
        self.target = np.zeros(self.size)

    def value(self, z):
        c, s = math.cos(z[2]), math.sin(z[2])
        rx, ry = self.r
        dx, dy = z[0] + c * rx - s * ry - rx, z[1] + s * rx + c * ry - ry
        vals = {"u": dx * self.e[0] + dy * self.e[1], "rot": z[2]}
        return np.array([vals[w] for w in self.what])

    def eval(self, z, mu=None):
        c, s = math.cos(z[2]), math.sin(z[2])
        rx, ry = self.r
        Rx, Ry = c * rx - s * ry, s * rx + c * ry
        ex, ey = self.e
        rows = {"u": [ex, ey, -Ry * ex + Rx * ey], "rot": [0.0, 0.0, 1.0]}
        hrow = {"u": -Rx * ex - Ry * ey, "rot": 0.0}
        g = self.value(z) - self.target
        G = np.array([rows[w] for w in self.what])
        H = np.zeros((self.size, 3, 3))
        for i, w in enumerate(self.what):
            H[i, 2, 2] = hrow[w]
        if mu is not None:
            return g, G, np.einsum("i,ijk->jk", mu, H)
        return g, G, H
