"""Redundant joints: constraints that hold the same freedom twice.

Two welds of one rod end to the ground, a pin and a roller at the same point of a body, two sliders
along one guide: the joints' equations are linearly dependent, so their multipliers - how the
reaction splits between them - are undetermined and the Newton matrix [[K, G^T], [G, 0]] is
singular from the first iteration.  Before, such a structure ran into "load stepping stalled at load
factor 0: a limit point or a bifurcation"; it is bad input, named here before any solve.

:func:`check` looks at the joints' gradient G at the undeformed state (model units, one row per joint
equation).  The joints are taken in declaration order; a joint whose rows do not raise the rank of the
rows before it is redundant with the joints that the left null vector c (c^T G = 0) involves.
"""
from __future__ import annotations

import numpy as np

from femslide.errors import BadInput
from femslide.model.linalg import distinct

RANK_TOL = 1e-9   # relative to the largest singular value: rows dependent to 1e-9 are redundant


def _rows(model):
    """(names, G): each joint equation's joint name and the gradient rows at the undeformed state,
    restricted to the dofs the joints touch."""
    y, _ = model.zero_state()
    q = y[:model.n_q]
    # (linalg.distinct: np.unique's result without its import of numpy.ma)
    dofs = distinct(np.concatenate([c.dofs for c in model.constraints] + [np.zeros(0, np.intp)]))
    col = {int(d): i for i, d in enumerate(dofs)}
    names, rows = [], []
    for c in model.constraints:
        _, Gc, _ = c.eval(q[c.dofs])
        Gc = np.atleast_2d(Gc)
        block = np.zeros((Gc.shape[0], dofs.size))
        for j, d in enumerate(c.dofs):
            block[:, col[int(d)]] = Gc[:, j]
        rows.append(block)
        names += [c.name] * Gc.shape[0]
    return names, (np.vstack(rows) if rows else np.zeros((0, dofs.size)))


def _rank(G, scale):
    if G.shape[0] == 0:
        return 0
    s = np.linalg.svd(G, compute_uv=False)
    return int(np.sum(s > RANK_TOL * scale))


def redundant(model) -> list[str] | None:
    """The names of a set of joints whose equations are dependent (the first such set in declaration
    order), or None when the joints are independent."""
    names, G = _rows(model)
    if G.shape[0] == 0:
        return None
    scale = float(np.linalg.svd(G, compute_uv=False)[0])
    if scale == 0.0 or _rank(G, scale) == G.shape[0]:
        return None
    order = list(dict.fromkeys(names))
    sel = np.zeros(len(names), bool)
    rank = 0
    for name in order:
        mine = np.array([n == name for n in names])
        trial = sel | mine
        r = _rank(G[trial], scale)
        if r < rank + int(mine.sum()):
            # the left null vectors of these rows: which joints' equations combine to zero
            U, s, _ = np.linalg.svd(G[trial], full_matrices=True)
            C = U[:, int(np.sum(s > RANK_TOL * scale)):]
            w = np.abs(C).max(axis=1)
            idx = np.nonzero(trial)[0][w > 1e-6 * w.max()]
            return list(dict.fromkeys(names[i] for i in idx))
        sel, rank = trial, r
    return None


def check(model):
    """BadInput naming the redundant joints, if any (see the module docstring)."""
    names = redundant(model)
    if names:
        ground = [n for n in names if model.structure.refs.get(n, (None, None))[1] is not None
                  and model.structure.refs[n][1].kind == "ground"]
        what = "the reactions' split between them" if len(ground) == len(names) else "their forces' split"
        raise BadInput(f"joints {', '.join(names)} hold the same freedom more than once (redundant "
                       f"constraints): {what} is undetermined; allowed: each freedom held by one joint - "
                       f"remove one of them, or change its type (e.g. a pin instead of a weld)")
