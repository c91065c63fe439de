"""The two sets of natural frequencies of a structure with friction joints (SPEC 9.4).

A friction joint is stuck or slips: small vibrations about the static state are those of the
structure with every friction joint **stuck** (its slide locked, femslide.analysis.stickslip's lock)
or of the **free** (frictionless) structure; a real motion passes between them.  Both sets are
computed about the same static state (model units inside, Hz out), the free one with its directions
free of any stiffness (a base on a frictionless slider without a spring) as zero frequencies
(femslide.analysis.modes, ``zero_ok``), not refused.
"""
from __future__ import annotations

import numpy as np

from femslide.analysis.modes import modes
from femslide.errors import SolverFailure


def frequency_sets(model, y, elements, fric_joints, counts, count, mechanism=False):
    """({"stuck": [...], "free": [...]} (Hz, ascending, the ``count`` lowest each), the free set's
    shapes, the stuck model, the stuck set's shapes) about the static state (y, elements) of
    ``model`` (the frictionless model; y in its units).  ``fric_joints``: the frozen joints with
    friction; ``counts``: the rods' element counts.  A set is empty when nothing can move in it (a
    block whose only joint is stuck).  ``mechanism``: the frictionless structure has no equilibrium of
    its own (its statics needed the friction joints stuck): its free directions, at most one per
    friction joint, are zero frequencies."""
    from femslide.analysis.stickslip import Friction
    from femslide.model.mass import Masses
    try:
        free, free_shapes = modes(model, y, elements, Masses(model), count, zero_ok=mechanism,
                                  max_free=len(fric_joints))
    except SolverFailure as exc:
        if "no motion" not in str(exc):
            raise
        free, free_shapes = np.zeros(0), np.zeros((0, model.n_q))
    fr = Friction(model, fric_joints, None, counts)
    m = fr.stuck_model()
    ys = np.concatenate([y[:model.n], np.zeros(m.n - model.n)])
    try:
        stuck, stuck_shapes = modes(m, ys, elements, Masses(m), count)
    except SolverFailure as exc:   # stuck, nothing can move: no frequencies
        if "no motion" not in str(exc):
            raise
        stuck, stuck_shapes = np.zeros(0), np.zeros((0, m.n_q))
    sets = {"stuck": [float(f) for f in stuck], "free": [float(f) for f in free]}
    return sets, free_shapes, m, stuck_shapes
