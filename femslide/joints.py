"""Joints as exact constraints g(z) = 0 (Lagrange multipliers), and the slider spring.

Every constraint acts on a few model dofs and returns its values g (m,), gradient G (m, k) and
Hessians H (m, k, k) over those dofs, or, given the multipliers mu, the weighted Hessian
sum_i mu_i H_i (k, k) that the Newton tangent needs.  The kinematics are scalar ``math``: a joint has a
handful of numbers, and numpy's per-call cost would dominate.  The multiplier mu of a constraint is
the generalised force it exerts *on the constraint's first participant taken with a minus sign*: the
support reaction of a pin is -mu, the clamp's transverse force on the rod end is -mu_1 n and its
moment -mu_2.

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
import math

import numpy as np

from .body import Body


def node_dofs(node):
    return np.arange(3 * node, 3 * node + 3)


class _Joint:
    """g, G and the Hessians from ``_parts(z) -> (g, G, hess)`` (lists; hess: (i, a, b, value) for
    the nonzero entries H_i[a, b])."""

    def eval(self, z, mu=None):
        g, G, hess = self._parts(z.tolist())
        G = np.array(G)
        k = G.shape[1]
        if mu is None:
            H = np.zeros((len(g), k, k))
            for i, a, b, v in hess:
                H[i, a, b] += v
            return np.array(g), G, H
        mu = mu.tolist()
        Hmu = np.zeros((k, k))
        for i, a, b, v in hess:
            Hmu[a, b] += mu[i] * v
        return np.array(g), G, Hmu


def _guide_frame(theta, wx, wy):
    """cos and sin of the body rotation and the components of w along the body's guide normal
    n = (cos Th, sin Th) and guide direction e = (-sin Th, cos Th)."""
    c, s = math.cos(theta), math.sin(theta)
    return c, s, wx * c + wy * s, -wx * s + wy * c


@dataclass
class NodePin(_Joint):
    node: int
    clamp: bool = False
    name: str = "pin"

    @property
    def dofs(self):
        return node_dofs(self.node)[: 3 if self.clamp else 2]

    @property
    def size(self):
        return 3 if self.clamp else 2

    def _parts(self, z):
        m = self.size
        return z, np.eye(m), ()


@dataclass
class BodyPin(_Joint):
    body: Body
    r: np.ndarray      # body-local offset of the pinned point
    ground: np.ndarray  # ground point [m]
    name: str = "pin"
    size: int = 2

    @property
    def dofs(self):
        return self.body.dofs

    def _parts(self, z):
        px, py, Rx, Ry = self.body.place(z, self.r)
        g = [px - self.ground[0], py - self.ground[1]]
        G = [[1.0, 0.0, -Ry], [0.0, 1.0, Rx]]
        return g, G, ((0, 2, 2, -Rx), (1, 2, 2, -Ry))


@dataclass
class Weld(_Joint):
    node: int
    X0: np.ndarray  # initial node position
    body: Body
    r: np.ndarray   # body-local offset of the weld point
    name: str = "weld"
    size: int = 3

    @property
    def dofs(self):
        return np.concatenate([node_dofs(self.node), self.body.dofs])

    def _parts(self, z):
        px, py, Rx, Ry = self.body.place(z[3:], self.r)
        g = [self.X0[0] + z[0] - px, self.X0[1] + z[1] - py, z[2] - z[5]]
        G = [[1.0, 0.0, 0.0, -1.0, 0.0, Ry],
             [0.0, 1.0, 0.0, 0.0, -1.0, -Rx],
             [0.0, 0.0, 1.0, 0.0, 0.0, -1.0]]
        return g, G, ((0, 5, 5, Rx), (1, 5, 5, Ry))


@dataclass
class SlidingClamp(_Joint):
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

    def _frame(self, z):
        """:func:`_guide_frame` of w = p_S - A0 - U_b (so that g1 = w.n - r_x, s = w.e - r_y)."""
        return _guide_frame(z[5], self.X0[0] + z[0] - self.body.A0[0] - z[3],
                            self.X0[1] + z[1] - self.body.A0[1] - z[4])

    def _parts(self, z):
        c, s, wn, we = self._frame(z)
        g = [wn - self.r[0], z[2] - z[5]]
        G = [[c, s, 0.0, -c, -s, we], [0.0, 0.0, 1.0, 0.0, 0.0, -1.0]]
        hess = ((0, 5, 5, -wn), (0, 0, 5, -s), (0, 5, 0, -s), (0, 1, 5, c), (0, 5, 1, c),
                (0, 3, 5, s), (0, 5, 3, s), (0, 4, 5, -c), (0, 5, 4, -c))
        return g, G, hess

    def slide(self, z):
        """Slide s [m], its gradient and Hessian over the joint dofs."""
        c, s, wn, we = self._frame(z.tolist())
        ds = np.array([-s, c, 0.0, s, -c, -wn])
        H = np.zeros((6, 6))
        H[5, 5] = -we
        H[0, 5] = H[5, 0] = -c
        H[1, 5] = H[5, 1] = -s
        H[3, 5] = H[5, 3] = c
        H[4, 5] = H[5, 4] = s
        return we - self.r[1], ds, H


@dataclass
class GuideLine(_Joint):
    body: Body
    r: np.ndarray       # body-local offset of the guide point B
    ground: np.ndarray  # ground pin of the rigid rod, B1
    name: str = "guide"
    size: int = 1

    @property
    def dofs(self):
        return self.body.dofs

    def _frame(self, z):
        """:func:`_guide_frame` of w = A0 + U_b - B1 (so that (B - B1).n = w.n + r_x and
        (B - B1).e = w.e + r_y)."""
        return _guide_frame(z[2], self.body.A0[0] + z[0] - self.ground[0],
                            self.body.A0[1] + z[1] - self.ground[1])

    def _parts(self, z):
        c, s, wn, we = self._frame(z)
        hess = ((0, 2, 2, -wn), (0, 0, 2, -s), (0, 2, 0, -s), (0, 1, 2, c), (0, 2, 1, c))
        return [wn + self.r[0]], [[c, s, we]], hess

    def slide(self, z):
        """Advance of the rigid rod past the guide point along e: s = l_rod - (B - B1).e."""
        _, _, _, we = self._frame(z.tolist())
        return (self.body.A0[1] + self.r[1] - self.ground[1]) - (we + self.r[1])


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
