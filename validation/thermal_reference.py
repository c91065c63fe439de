"""Closed forms of thermal loads on straight rods (independent of femslide: math only).

Units SI; rotations and moments counter-clockwise positive; N > 0 in tension; the bending moment
M = EI (dtheta/ds - kappa_T) with the free curvature kappa_T = -alpha dT_gradient / depth (a rod
bends away from its hotter face; dT_gradient is the temperature of the +n face minus the -n face,
n = the rod's tangent turned by +90 degrees), the axial force N = EA (stretch - alpha dT).

* A rod welded (or pinned) at both ends under a uniform dT cannot lengthen: N = -EA alpha dT
  (compression when heated), no moment (below buckling).
* Pinned at one end, on a roller along its axis at the other: free to lengthen by alpha dT L, N = 0.
* A cantilever under dT_gradient takes its free curvature: a circular arc of curvature kappa_T, exact
  at any rotation: tip rotation kappa_T L, tip displacement (sin(kappa L)/kappa - L,
  (1 - cos(kappa L))/kappa) along and across the axis; M = 0.
* Welded at both ends under dT_gradient: no motion, M = -EI kappa_T = +EI alpha dT_gradient / depth
  constant, no axial or shear force.
"""
from __future__ import annotations

import math


def kappa_T(alpha, dT_gradient, depth):
    """Free curvature [1/m] of a temperature gradient."""
    return -alpha * dT_gradient / depth


def welded_uniform_N(EA, alpha, dT):
    """Axial force [N] of a rod held at both ends under a uniform change dT."""
    return -EA * alpha * dT


def roller_slide(alpha, dT, L):
    """Slide [m] of the roller end of a pinned-roller rod under dT."""
    return alpha * dT * L


def cantilever_gradient_tip(alpha, dT_gradient, depth, L):
    """(u, v, theta) of the free tip of a cantilever along +x under a gradient: the circular arc."""
    k = kappa_T(alpha, dT_gradient, depth)
    th = k * L
    if abs(th) < 1e-8:
        return 0.0, 0.5 * k * L * L, th
    return math.sin(th) / k - L, (1.0 - math.cos(th)) / k, th


def welded_gradient_M(EI, alpha, dT_gradient, depth):
    """Bending moment [N m] (constant) of a rod welded at both ends under a gradient."""
    return -EI * kappa_T(alpha, dT_gradient, depth)
