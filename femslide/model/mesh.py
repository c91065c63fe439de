"""The meshes of a structure's rods (geometry only, model units): nodes along every rod, with a node at
every point of a load inside a rod (:func:`rod_fractions`), and the elements' reference chords.
Shared through the PatternCache by the models of one geometry (the cases of a sweep over
stiffnesses)."""
from __future__ import annotations

import numpy as np

from femslide.elements import corotational


def rod_fractions(breaks, n):
    """Node positions (arc length over the rod's length, from 0 to 1) of a rod meshed with about n
    elements that has nodes at the fractions ``breaks`` (sorted, inside (0, 1): the points of loads
    inside the rod): each piece between breaks gets ceil(n times its share of the length) equal
    elements (at least one), so halving n's elements halves every piece's; without breaks n equal
    elements."""
    if not breaks:
        return np.arange(n + 1) / n
    edges = [0.0, *breaks, 1.0]
    parts = []
    for a, b in zip(edges[:-1], edges[1:]):
        k = max(1, int(np.ceil(n * (b - a) - 1e-9)))
        parts.append(a + (b - a) * (np.arange(k) / k))
    parts.append([1.0])
    return np.concatenate(parts)


class _Mesh:
    """The meshes of a structure's rods for given element counts (geometry only, model units): shared
    through the PatternCache by the models of one geometry (the cases of a sweep over stiffnesses).
    ``counts``: the element counts asked for; ``self.counts`` those made (a rod with loads inside gets
    at least one element per piece between them)."""

    def __init__(self, plan, counts):
        Xs, conn, rod_of, self.rod_nodes, self.rod_elements, s0 = [], [], [], [], [], []
        self.counts = ()
        off = eoff = 0
        self.rod_t = []
        for k, (rp, n) in enumerate(zip(plan.rods, counts)):
            t = rod_fractions(rp.breaks, n)
            n = t.size - 1
            self.rod_t.append(t)
            X = np.empty((n + 1, 2))
            X[:, 0] = rp.S[0] + t * (rp.E[0] - rp.S[0])
            X[:, 1] = rp.S[1] + t * (rp.E[1] - rp.S[1])
            Xs.append(X)
            c = np.empty((n, 2), np.intp)
            c[:, 0] = np.arange(off, off + n)
            c[:, 1] = c[:, 0] + 1
            conn.append(c)
            rod_of.append(np.full(n, k))
            s0.append(t[:-1] * rp.length)
            self.counts += (n,)
            self.rod_nodes.append(np.arange(off, off + n + 1))
            self.rod_elements.append(np.arange(eoff, eoff + n))
            off += n + 1
            eoff += n
        self.n_nodes = off
        self.prolongations = {}   # interpolation plans from coarser meshes (static.prolong)
        self.derived = {}         # data of higher layers that depends on the mesh alone (a Newton start's geometry)
        self.X0 = np.concatenate(Xs) if Xs else np.zeros((0, 2))
        # the first node of each node's rod (rods are numbered node block by node block)
        self.node_first = np.repeat([r[0] for r in self.rod_nodes], [r.size for r in self.rod_nodes]) \
            if self.rod_nodes else np.zeros(0, np.intp)
        self.conn = None
        if conn:
            self.conn = np.concatenate(conn)
            self.D0 = self.X0[self.conn[:, 1]] - self.X0[self.conn[:, 0]]
            self.L0 = np.hypot(self.D0[:, 0], self.D0[:, 1])
            self.beta0 = np.arctan2(self.D0[:, 1], self.D0[:, 0])
            self.elem_rod = np.concatenate(rod_of)
            self.s0 = np.concatenate(s0)
            self.xmax = float(np.abs(self.X0).max())
        self._elements = None

    def element_set(self):
        """The elements' geometric data (corotational.ElementSet without stiffness), built once."""
        if self._elements is None:
            self._elements = corotational.ElementSet(self.conn, self.D0, self.L0, self.beta0,
                                                     np.zeros((self.L0.size, 3, 3)), self.xmax)
        return self._elements
