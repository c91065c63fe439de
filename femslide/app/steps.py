"""A structure's load history (``[[step]]``, SPEC section 10) as an outcome.

Every step's result (the section-8 values in SI and each friction joint's ``state``, ``force``,
``normal`` and ``slide``), the friction events (``step``, ``load_parameter`` t in [0, 1] along the
step, ``joint``, ``kind`` "slip+" | "slip-" | "stick") and an ``error_estimate``: the history solved
again on meshes with half the elements (adaptive rods), the largest relative change of the watched
step results and of the friction forces and slides, over 3 (the O(h^2) discretisation's Richardson
estimate); None when every rod's mesh is fixed.  Files: ``steps.csv`` (one row per step) and a
hysteresis plot per friction joint (slide against friction force along the history).
"""
from __future__ import annotations

import numpy as np

from femslide.errors import SolverFailure
from femslide.results.outcome import Loop, Outcome, Table


def history(fs, elements, name, cache, opts) -> Outcome:
    from femslide.analysis import static
    from femslide.analysis.history import N_HISTORY, run_history
    from femslide.model.patterns import PatternCache
    L, F = static.scales(fs)
    static.check_stiffness_range(fs, L, F)
    cache = cache or PatternCache()
    meshes = static.Meshes(fs, elements, opts["theory"], L, F, cache, None)
    n = elements or N_HISTORY
    steps, h = run_history(fs, meshes.counts(n), L, F, cache, meshes.make)
    its = h.iterations
    estimate = None
    if not steps:
        raise SolverFailure(h.failure or "the load history has no step")
    if meshes.adaptive and n >= 2 and h.failure is None:
        try:
            coarse, hc = run_history(fs, meshes.counts(n // 2), L, F, cache, meshes.make)
            its += hc.iterations
            estimate = _estimate(fs, steps, coarse)
        except SolverFailure:
            estimate = None
    out_steps = []
    for sname, factors, res, _, _, _ in steps:
        out_steps.append({"name": sname, "factors": factors, "converged": True, **res})
    last = out_steps[-1]
    values = {"converged": h.failure is None, "M_max": last["M_max"], "bodies": last["bodies"], "rods": last["rods"],
              "joints": last["joints"], "reactions": last["reactions"], "friction": last["friction"],
              "steps": out_steps, "events": h.events, "iterations": its, "error_estimate": estimate,
              "elements": {r.name: int(c) for r, c in zip(fs.rods, meshes.counts(n).values())}}
    if h.failure is not None:   # the steps before the failed one are kept (exit 1)
        values["reason"] = h.failure
    if opts["theory"] == "linear":
        values["theory"] = "linear"
    out = Outcome(values, name)
    out.tables = lambda: [_table(out_steps)]
    out.loops = [Loop(j, np.array([p[0] for p in pts]), np.array([p[1] for p in pts])) for j, pts in h.trace.items()
                 if pts]
    return out


def _watched(fs, res):
    from femslide.results.static import flatten
    vals, kinds = flatten(res, fs)
    extra = []
    for v in res["friction"].values():
        extra += [(v["force"], "force"), (v["slide"], "length")]
    return np.concatenate([vals, [e[0] for e in extra]]), list(kinds) + [e[1] for e in extra]


def _estimate(fs, fine, coarse):
    from femslide.analysis.refine import _scales, _units
    worst = 0.0
    for a, b in zip(fine, coarse):
        va, kinds = _watched(fs, a[2])
        vb, _ = _watched(fs, b[2])
        m = a[3]
        sc = _scales(va / _units(kinds, m.Lref, m.Fref), kinds) * _units(kinds, m.Lref, m.Fref)
        worst = max(worst, float(np.max(np.abs(va - vb) / sc)) / 3.0)
    return worst


def _table(steps):
    from femslide.app.result import dotted, unit_of
    flat = [dotted({k: v for k, v in s.items() if k not in ("converged", "name")}) for s in steps]
    keys = [k for k in flat[0] if all(isinstance(f.get(k), (int, float)) and not isinstance(f.get(k), bool)
                                      for f in flat)]
    header = ["step"] + [f"{k} [{unit_of(k) or '-'}]" for k in keys]
    cols = [np.array([s["name"] for s in steps], object)] + [np.array([float(f[k]) for f in flat], object)
                                                            for k in keys]
    return Table("steps.csv", header, cols, ["%s"] + ["%.17g"] * len(keys))
