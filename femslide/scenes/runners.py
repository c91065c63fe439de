"""Runners of the spring-hinge scenes: validated parameters in, contract JSON object out."""
from __future__ import annotations

from femslide.scenes import hinge


def hinge_slider(v):
    return hinge.solve_slider(**v)


def hinge_fixed(v):
    return hinge.solve_fixed(**v)


hinge_spring = hinge_slider  # section 4: the slider model with its spring k


def hinge_extra_mass(v):
    return hinge.solve_extra_mass(**v)
