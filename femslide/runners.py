"""Runners of the spring-hinge scenes: validated parameters in, contract JSON object out."""
from __future__ import annotations

from . import hinge


def hinge_slider(v, warm=None):
    return hinge.solve_slider(**v), None


def hinge_fixed(v, warm=None):
    return hinge.solve_fixed(**v), None


def hinge_spring(v, warm=None):
    return hinge.solve_slider(**v), None


def hinge_extra_mass(v, warm=None):
    return hinge.solve_extra_mass(**v), None
