"""Joints as exact constraints g(z) = 0 (Lagrange multipliers), and the slider spring.

Every constraint acts on a few model dofs and returns its values g (m,), gradient G (m, k) and
Hessians H (m, k, k) over those dofs.  The multiplier mu of a constraint is the generalised force it
exerts *on the constraint's first participant taken with a minus sign*: the support reaction of a pin
is -mu, the clamp's transverse force on the rod end is -mu_1 n and its moment -mu_2.

Joints (SPEC section 3):
- :class:`NodePin`: a rod node pinned to the ground (u = v = 0); optionally clamped (theta = 0).
- :class:`BodyPin`: a body point pinned to the ground (a rigid rod AA1 is part of the body).
- :class:`Weld`: a rod end welded to the body (same position and rotation).
- :class:`SlidingClamp`: prismatic joint; the rod node S stays on the body-fixed guide line and
  turns with the body; the slide s along the line is free.  s > 0 when the rod end advances along
  the guide direction e (up the guide in the vertical state).
- :class:`GuideLine`: a rigid rod pinned at a ground point and held by a sliding clamp: the body's
  guide point stays on the line through the ground point along the guide direction.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .body import Body


def node_dofs(node):
    return np.arange(3 * node, 3 * node + 3)


@dataclass
class NodePin:
    node: int
    clamp: bool = False
    name: str = "pin"

    @property
    def dofs(self):
        return node_dofs(self.node)[: 3 if self.clamp else 2]

    @property
    def size(self):
        return 3 if self.clamp else 2

    def eval(self, z):
        m = self.size
        return z.copy(), np.eye(m), np.zeros((m, m, m))


@dataclass
class BodyPin:
    body: Body
    r: np.ndarray      # body-local offset of the pinned point
    ground: np.ndarray  # ground point [m]
    name: str = "pin"
    size: int = 2

    @property
    def dofs(self):
        return self.body.dofs

    def eval(self, z):
        p, dp, d2p = self.body.point(z, self.r)
        G = np.zeros((2, 3))
        G[:, :2] = np.eye(2)
        G[:, 2] = dp
        H = np.zeros((2, 3, 3))
        H[:, 2, 2] = d2p
        return p - self.ground, G, H


@dataclass
class Weld:
    node: int
    X0: np.ndarray  # initial node position
    body: Body
    r: np.ndarray   # body-local offset of the weld point
    name: str = "weld"
    size: int = 3

    @property
    def dofs(self):
        return np.concatenate([node_dofs(self.node), self.body.dofs])

    def eval(self, z):
        p, dp, d2p = self.body.point(z[3:], self.r)
        g = np.array([self.X0[0] + z[0] - p[0], self.X0[1] + z[1] - p[1], z[2] - z[5]])
        G = np.zeros((3, 6))
        G[0, 0] = G[1, 1] = G[2, 2] = 1.0
        G[0, 3] = G[1, 4] = G[2, 5] = -1.0
        G[:2, 5] = -dp
        H = np.zeros((3, 6, 6))
        H[:2, 5, 5] = -d2p
        return g, G, H


@dataclass
class SlidingClamp:
    """Rod node S on the body-fixed line through body point r along body direction (0, 1)."""

    node: int
    X0: np.ndarray
    body: Body
    r: np.ndarray
    name: str = "clamp"
    size: int = 2

    @property
    def dofs(self):
        return np.concatenate([node_dofs(self.node), self.body.dofs])

    def _rel(self, z):
        # w = p_S - A0 - U_b (so that g1 = w.n - r_x, s = w.e - r_y)
        return self.X0 + z[:2] - self.body.A0 - z[3:5]

    def eval(self, z):
        th = z[5]
        n = np.array([np.cos(th), np.sin(th)])
        e = np.array([-np.sin(th), np.cos(th)])
        w = self._rel(z)
        g = np.array([w @ n - self.r[0], z[2] - th])
        G = np.zeros((2, 6))
        G[0, :2] = n
        G[0, 3:5] = -n
        G[0, 5] = w @ e
        G[1, 2], G[1, 5] = 1.0, -1.0
        H = np.zeros((2, 6, 6))
        H[0, 5, 5] = -(w @ n)
        H[0, :2, 5] = H[0, 5, :2] = e
        H[0, 3:5, 5] = H[0, 5, 3:5] = -e
        return g, G, H

    def slide(self, z):
        """Slide s [m], its gradient and Hessian over the joint dofs."""
        th = z[5]
        n = np.array([np.cos(th), np.sin(th)])
        e = np.array([-np.sin(th), np.cos(th)])
        w = self._rel(z)
        s = w @ e - self.r[1]
        ds = np.zeros(6)
        ds[:2], ds[3:5], ds[5] = e, -e, -(w @ n)
        H = np.zeros((6, 6))
        H[5, 5] = -(w @ e)
        H[:2, 5] = H[5, :2] = -n
        H[3:5, 5] = H[5, 3:5] = n
        return s, ds, H


@dataclass
class GuideLine:
    body: Body
    r: np.ndarray       # body-local offset of the guide point B
    ground: np.ndarray  # ground pin of the rigid rod, B1
    name: str = "guide"
    size: int = 1

    @property
    def dofs(self):
        return self.body.dofs

    def eval(self, z):
        th = z[2]
        n = np.array([np.cos(th), np.sin(th)])
        e = np.array([-np.sin(th), np.cos(th)])
        w = self.body.A0 + z[:2] - self.ground
        g = np.array([w @ n + self.r[0]])
        G = np.zeros((1, 3))
        G[0, :2], G[0, 2] = n, w @ e
        H = np.zeros((1, 3, 3))
        H[0, 2, 2] = -(w @ n)
        H[0, :2, 2] = H[0, 2, :2] = e
        return g, G, H

    def slide(self, z):
        """Advance of the rigid rod past the guide point along e: s = l_rod - (B - B1).e."""
        p, _, _ = self.body.point(z, self.r)
        th = z[2]
        e = np.array([-np.sin(th), np.cos(th)])
        p0 = self.body.A0 + self.r
        return (p0 - self.ground) @ np.array([0.0, 1.0]) - (p - self.ground) @ e


@dataclass
class SliderSpring:
    """Linear spring k [N/m] along a sliding clamp, energy (k/2) s^2 + F0 s (F0: preload [N]).

    The preload is a load (scaled with gravity while the load is ramped); k is a stiffness.
    """

    clamp: SlidingClamp
    k: float
    F0: float = 0.0
    name: str = "spring"

    @property
    def dofs(self):
        return self.clamp.dofs

    def eval(self, z, lam=1.0):
        s, ds, Hs = self.clamp.slide(z)
        f = self.k * s + lam * self.F0
        return 0.5 * self.k * s * s + lam * self.F0 * s, f * ds, self.k * np.outer(ds, ds) + f * Hs, self.F0 * ds
