"""The history of a model's corotational elements: committed and trial chord rotations.

A corotational element's chord angle is tracked incrementally: its rotation alpha [rad] from the
undeformed chord is continued from a reference, the last converged state, so that an element may
turn past pi (codes that wrap the angle with atan2 fail there).  :class:`ElementState` holds that
history as OpenSees' coordinate transformations do: every evaluation of the model
(femslide.model.discrete.Model.system) computes the *trial* rotations of its state from the
*committed* ones; a solver commits the trial of a converged state (:meth:`commit`) and reverts a
failed one (:meth:`revert`).  Several trials may start from one committed state (a time step tried
with several sizes, a load step halved): each reads the same reference.
"""
from __future__ import annotations

import numpy as np

from femslide.records import dataclass


class ElementState:
    """Chord rotations [rad] of a model's elements: ``committed`` (the reference of every
    evaluation) and ``trial`` (those of the latest evaluation), arrays of one value per element."""

    __slots__ = ("committed", "trial")

    def __init__(self, alpha):
        self.committed = alpha
        self.trial = alpha

    @classmethod
    def zero(cls, n: int) -> "ElementState":
        """The undeformed elements (n of them)."""
        return cls(np.zeros(n))

    def commit(self) -> "ElementState":
        """Take the trial rotations as the new reference; returns self."""
        self.committed = self.trial
        return self

    def revert(self) -> "ElementState":
        """Drop the trial rotations (back to the reference); returns self."""
        self.trial = self.committed
        return self

    def copy(self) -> "ElementState":
        """An independent state with the same committed and trial rotations."""
        new = ElementState(self.committed)
        new.trial = self.trial
        return new

    def committed_trial(self) -> "ElementState":
        """A new state whose reference is this one's trial (the next step's start), this one
        unchanged."""
        return ElementState(self.trial)

    def __repr__(self):
        return f"ElementState({self.committed.size} elements)"


@dataclass
class MotionState:
    """A state of motion at time t [s] (model units): y = [q, mu] (positions and multipliers),
    velocities v and accelerations acc (q'') of the positions, and the elements' history
    (:class:`ElementState`, committed at this state: the reference of the steps tried from it)."""

    t: float
    y: np.ndarray
    v: np.ndarray
    acc: np.ndarray
    elements: ElementState

    @property
    def alpha(self) -> np.ndarray:
        """The committed chord rotations [rad]."""
        return self.elements.committed
