"""A straight flexible rod and its mesh of 2-node beam elements (data only).

The rod runs from ``start`` to ``end`` [m]; ``EI`` [N m^2] and ``EA`` [N] are numbers or vectorised
callables of the arc length s [m] measured from ``start``.  Nodes are numbered from ``start``.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Rod:
    name: str
    start: tuple
    end: tuple
    n: int
    EI: object
    EA: object

    @property
    def length(self):
        return float(np.hypot(self.end[0] - self.start[0], self.end[1] - self.start[1]))

    def nodes(self):
        """Initial node positions (n + 1, 2) and their arc lengths (n + 1,)."""
        t = np.linspace(0.0, 1.0, self.n + 1)
        X = np.outer(1 - t, self.start) + np.outer(t, self.end)
        return X, t * self.length
