"""Envelopes of load combinations: the extremes over the combinations' results and which governs.

Each combination of a structure is solved as its own equilibrium (femslide.app.cases); its named
results are those of SPEC section 8.  The envelope (SI units, the results' own signs) holds

- ``rods``: {NAME: {``M_max``, ``N_max``, ``V_max``: the largest over the combinations, each with
  ``<key>_combination`` the combination that gives it}};
- ``reactions``: {NAME: {``Fx_min``, ``Fx_max``, ``Fy_min``, ``Fy_max``, ``M_min``, ``M_max``, each
  with ``<key>_combination``}} (forces of the ground on the structure);
- ``joints``: {NAME: {``slide_min``, ``slide_max``} for sliders and rollers, with their
  combinations};

and, for the diagrams, :func:`moment_envelope`: per rod the bending moment along the rod of every
combination and its minimum and maximum at every arc length.
"""
from __future__ import annotations

import numpy as np

from femslide.model.linalg import distinct


def envelope(results: dict) -> dict:
    """The envelope of ``results`` ({combination: section-8 result}, in declaration order)."""
    names = list(results)
    out = {"rods": {}, "reactions": {}, "joints": {}}
    if not names:
        return out
    first = results[names[0]]

    def extreme(get, pick):
        vals = [(get(results[c]), c) for c in names]
        v, c = pick(vals, key=lambda x: x[0])
        return v, c

    for rod in first["rods"]:
        d = {}
        for key in ("M_max", "N_max", "V_max"):
            v, c = extreme(lambda r, rod=rod, key=key: r["rods"][rod][key], max)
            d[key], d[f"{key}_combination"] = v, c
        out["rods"][rod] = d
    for sup in first["reactions"]:
        d = {}
        for key in ("Fx", "Fy", "M"):
            for end, pick in (("min", min), ("max", max)):
                v, c = extreme(lambda r, sup=sup, key=key: r["reactions"][sup][key], pick)
                d[f"{key}_{end}"], d[f"{key}_{end}_combination"] = v, c
        out["reactions"][sup] = d
    for j, jr in first["joints"].items():
        if "slide" not in jr:
            continue
        d = {}
        for end, pick in (("min", min), ("max", max)):
            v, c = extreme(lambda r, j=j: r["joints"][j]["slide"], pick)
            d[f"slide_{end}"], d[f"slide_{end}_combination"] = v, c
        out["joints"][j] = d
    return out


def moment_envelope(arrays: dict) -> dict:
    """Per rod, the bending moment of every combination on a common arc-length grid and its extremes.

    ``arrays``: {combination: {rod: {"s": ..., "M": ...}}} (the rods' node arrays of each
    combination's finest mesh, SI).  Returns {rod: {"s": grid [m], "M": {combination: M on the grid
    [N m]}, "M_min", "M_max": the extremes [N m]}}; meshes that differ are merged on the union of
    their nodes, M linear between nodes."""
    combos = list(arrays)
    out = {}
    if not combos:
        return out
    for rod in arrays[combos[0]]:
        grid = distinct(np.concatenate([np.asarray(arrays[c][rod]["s"], float) for c in combos]))
        Ms = {c: np.interp(grid, arrays[c][rod]["s"], arrays[c][rod]["M"]) for c in combos}
        stack = np.vstack(list(Ms.values()))
        out[rod] = {"s": grid, "M": Ms, "M_min": stack.min(axis=0), "M_max": stack.max(axis=0)}
    return out
