"""What seismic engineers read from a simulation: inter-storey drifts, residual slides and drifts,
running peaks (SPEC 9.3, issue 24).  Plain post-processing of a simulation's history (SI units):

- storeys: two bodies (or a body and the ground) joined by a rod - a rod end held by a joint to one
  and its other end to the other (directly: a joint between the rod end and the body or the
  ground) - are consecutive storeys; the pair is named ``UPPER-LOWER`` (the body with the higher
  centroid first; ``ground`` last);
- the drift of a pair: the displacement of the upper centroid relative to the lower one, from the
  static start: ``drifts.PAIR.dx``, ``drifts.PAIR.dy`` [m] (global axes);
- residuals: the slides of sliders and rollers and the drifts at the end of the record;
- running peaks: the largest |value| up to each time of a set of columns.

The absolute velocities and accelerations of the bodies (``bodies.NAME.vx, vy, ax, ay``: relative
motion plus the ground's) are computed where the motion is (femslide.analysis.simulate).
"""
from __future__ import annotations

import numpy as np


def storey_pairs(fs) -> list:
    """[(upper, lower)] of the frozen structure ``fs``: bodies (or a body and "ground") joined by a rod
    (module docstring), each pair once, in the order of the rods."""
    bodies = {b.name: b for b in fs.bodies}
    ends = {}   # (rod, "start"/"end") -> the body or "ground" a joint holds it to
    for j in fs.joints:
        for x, other in ((j.a, j.b), (j.b, j.a)):
            if isinstance(x, str) and "." in x and (other in bodies or other == "ground"):
                rod, end = x.rsplit(".", 1)
                ends[(rod, end)] = other
    pairs = []
    for r in fs.rods:
        a, b = ends.get((r.name, "start")), ends.get((r.name, "end"))
        if a is None or b is None or a == b or (a == "ground" and b == "ground"):
            continue

        def height(n):
            return -np.inf if n == "ground" else float(bodies[n].centroid[1])
        up, low = (a, b) if height(a) >= height(b) else (b, a)
        if (up, low) not in pairs:
            pairs.append((up, low))
    return pairs


def drift_columns(pairs) -> list:
    """The history columns of the drifts of ``pairs``."""
    return [f"drifts.{u}-{lo}.{k}" for u, lo in pairs for k in ("dx", "dy")]


def drifts(H, col, pairs) -> np.ndarray:
    """The drift columns (n rows, 2 per pair) from a history H whose columns ``col`` (name -> index)
    hold the bodies' centroids ``bodies.NAME.x, y``: the upper centroid's displacement from the first
    row relative to the lower one's (the ground's is zero)."""
    out = np.zeros((H.shape[0], 2 * len(pairs)))
    for k, (up, low) in enumerate(pairs):
        for c, axis in enumerate(("x", "y")):
            u = H[:, col[f"bodies.{up}.{axis}"]] - H[0, col[f"bodies.{up}.{axis}"]] if H.shape[0] else H[:, 0]
            if low != "ground":
                u = u - (H[:, col[f"bodies.{low}.{axis}"]] - H[0, col[f"bodies.{low}.{axis}"]])
            out[:, 2 * k + c] = u
    return out


def residuals(H, cols) -> dict:
    """{"slides": {JOINT: slide [m] at the end}, "drifts": {PAIR: {dx, dy} [m] at the end}} from the
    last row of a history (signed; the slide from the static start)."""
    last = H[-1] if H.shape[0] else np.zeros(len(cols))
    res = {"slides": {}, "drifts": {}}
    for i, c in enumerate(cols):
        if c.startswith("joints.") and c.endswith(".slide"):
            res["slides"][c[len("joints."):-len(".slide")]] = float(last[i])
        elif c.startswith("drifts."):
            pair, k = c[len("drifts."):].rsplit(".", 1)
            res["drifts"].setdefault(pair, {})[k] = float(last[i])
    return res


PEAK_GROUPS = (("base moments M [N m]", lambda c: c.startswith("reactions.") and c.endswith(".M")),
               ("rod moments M_max [N m]", lambda c: c.startswith("rods.") and c.endswith(".M_max")),
               ("slides [m]", lambda c: c.startswith("joints.") and c.endswith(".slide")),
               ("inter-storey drifts [m]", lambda c: c.startswith("drifts.")),
               ("absolute accelerations [m/s^2]", lambda c: c.startswith("bodies.") and c.endswith((".ax", ".ay"))))


def running_peaks(H, cols) -> dict:
    """{group title: {column: running max |value| (array)}} of the groups of :data:`PEAK_GROUPS`
    present in the history (slides and drifts from their start)."""
    out = {}
    for title, pick in PEAK_GROUPS:
        g = {}
        for i, c in enumerate(cols):
            if i and pick(c) and H.shape[0]:
                x = H[:, i] - (H[0, i] if c.endswith((".slide", ".dx", ".dy")) else 0.0)
                g[c] = np.maximum.accumulate(np.abs(x))
        if g:
            out[title] = g
    return out
