"""A declared structure's own runs, as outcomes: its statics (SPEC sections 8 and 10).

The structure file targets (femslide.app.structfile) and the Python API (``femslide.solve`` of a
Structure) run a frozen structure's statics here: the principal equilibrium, or each load
combination with their envelope, in exact or first-order theory, by the principal branch or by
arc-length continuation through limit points.  Its dynamics and modes are femslide.analysis.simulate's
``simulate`` and ``natural_modes``, its buckling femslide.analysis.buckling.

Solve options (``[solve]`` table of a structure file, ``--path``/``--theory`` or ``--set solve.KEY=``
on the command line, keyword arguments of ``femslide.solve``): ``path`` "principal" (default) or
"arc-length", ``theory`` "nonlinear" (default) or "linear", ``plot`` the output drawn against the load
factor in ``path.png`` of an arc-length solve (a dotted name of the path's outputs, e.g.
"bodies.head.rotation"; default: the displacement or rotation that changes most).
"""
from __future__ import annotations

import math

from femslide.errors import BadInput, SolverFailure
from femslide.results.outcome import Figure, Outcome, Table

PATHS = ("principal", "arc-length")
THEORIES = ("nonlinear", "linear")
SOLVE_KEYS = ("path", "theory", "plot")


def solve_options(options: dict | None, where: str = "[solve]") -> dict:
    """The solve options checked, with their defaults (module docstring); BadInput naming the key."""
    opts = dict(options or {})
    unknown = sorted(set(opts) - set(SOLVE_KEYS))
    if unknown:
        raise BadInput(f"{where}: unknown key {unknown[0]!r}; allowed: {', '.join(SOLVE_KEYS)}")
    path = opts.get("path", "principal")
    if path not in PATHS:
        raise BadInput(f"{where}: path = {path!r}; allowed: {', '.join(PATHS)}")
    theory = opts.get("theory", "nonlinear")
    if theory not in THEORIES:
        raise BadInput(f"{where}: theory = {theory!r}; allowed: {', '.join(THEORIES)}")
    if path == "arc-length" and theory == "linear":
        raise BadInput(f"{where}: path = 'arc-length' needs theory = 'nonlinear' (a linear path has no limit points)")
    plot = opts.get("plot")
    if plot is not None and (not isinstance(plot, str) or not plot):
        raise BadInput(f"{where}: plot = {plot!r}; allowed: the dotted name of an output, e.g. 'bodies.deck.rotation'")
    return {"path": path, "theory": theory, "plot": plot}


def _values(sol) -> dict:
    res = sol.result
    out = dict(converged=True, M_max=res["M_max"], bodies=res["bodies"], rods=res["rods"],
               joints=res["joints"], reactions=res["reactions"], iterations=sol.iterations,
               error_estimate=sol.error_estimate, notes=notes(sol))
    if sol.lifted is not None:   # a structure with unilateral contacts: those released (they would pull)
        out["lifted"] = list(sol.lifted)
    return out


def notes(sol) -> list[str]:
    """What an engineer must know about a converged equilibrium beyond its numbers: an output that the
    refinement could make accurate only to its round-off floor (femslide.analysis.static), a support resting
    on the ground (a pin, roller or slider) that pulls the structure down - it would lift off -, a
    structure reaching below the ground line of its supports (femslide.output.diagrams.notes, which
    the pictures draw in red)."""
    from femslide.output.diagrams import LiftOffWarning, frame_data
    from femslide.output.diagrams import notes as picture_notes
    found = picture_notes(frame_data(sol))
    return list(sol.notes or []) + [text + (" (a support resting on the ground cannot pull: it would lift off; "
                                            "the model holds it down; declare it unilateral = true to let it "
                                            "lift)" if cls is LiftOffWarning else "")
                                    for cls, text in found]


def _solve(fs, elements, cache, opts, factors=None):
    from femslide.analysis import static
    from femslide.analysis.paths import Path
    path = Path("arc-length") if opts["path"] == "arc-length" else None
    return static.solve(fs, elements=elements, cache=cache, factors=factors, theory=opts["theory"], path=path)


def statics(fs, elements=None, name="structure", cache=None, options=None) -> Outcome:
    """Static equilibrium of a frozen structure: the section 8 values, with the solution behind them
    (its VTU on request); with combinations declared, each combination and their envelope
    (section 10).  ``elements``: a fixed mesh for every rod; ``cache``: patterns shared with other
    solves of one topology (a sweep); ``options``: the solve options (module docstring)."""
    opts = solve_options(options)
    if fs.steps:
        from femslide.app.steps import history
        return history(fs, elements, name, cache, opts)
    if fs.combinations:
        return _combinations(fs, elements, name, cache, opts)
    sol = _solve(fs, elements, cache, opts)
    values = _values(sol)
    out = Outcome(values, name, solution=sol)
    if opts["theory"] == "linear":
        values["theory"] = "linear"
    if opts["path"] == "arc-length":
        _arc_length_outputs(out, sol, opts)
    return out


# -- load combinations ------------------------------------------------------------------------------------
def _combinations(fs, elements, name, cache, opts) -> Outcome:
    """Every combination solved as its own equilibrium (sharing the meshes' patterns); a failed one
    is reported with its reason and the others are kept."""
    from femslide.model.discrete import PatternCache
    from femslide.results.envelope import envelope, moment_envelope
    cache = cache or PatternCache()
    combos, sols, reasons = {}, {}, {}
    its = 0
    for cb in fs.combinations:
        try:
            sol = _solve(fs, elements, cache, opts, factors=cb.factor_dict())
        except SolverFailure as exc:
            combos[cb.name] = {"converged": False, "reason": exc.reason, "factors": cb.factor_dict()}
            reasons[cb.name] = exc.reason
            continue
        v = _values(sol)
        v["factors"] = cb.factor_dict()
        its += sol.iterations
        combos[cb.name] = v
        sols[cb.name] = sol
    ok = {c: combos[c] for c in sols}
    errs = [v["error_estimate"] for v in ok.values() if v["error_estimate"] is not None]
    values = {"converged": not reasons, "combinations": combos, "envelope": envelope(ok),
              "iterations": its, "error_estimate": max(errs) if errs else None}
    if opts["theory"] == "linear":
        values["theory"] = "linear"
    if reasons:
        values["reason"] = "; ".join(f"combination {c}: {r}" for c, r in reasons.items())
    out = Outcome(values, name, solutions=sols)
    if sols:
        env = moment_envelope({c: _samples(s) for c, s in sols.items()})
        out.tables = lambda: _combination_tables(fs, ok, env)
        out.figures.append(Figure("envelope_M.png", "envelope", {"rods": env, "title":
                                  f"{name}: bending moment of the load combinations and their envelope"}))
    return out


def _samples(sol):
    """The bending moment along every rod of a solution's finest mesh, inside the elements too."""
    from femslide.results.static import moment_samples
    lv = sol.level
    return {rod: {"s": s, "M": M} for rod, (s, M) in moment_samples(lv.model, lv.y, lv.alpha, cuts=lv.cuts).items()}


def _combination_tables(fs, ok, env):
    """``combinations.csv`` (one row per combination: its factors and every scalar result) and
    ``envelope_M.csv`` (per rod and arc length: M of every combination, their minimum and maximum)."""
    import numpy as np

    from femslide.app.result import dotted
    names = list(ok)
    flat = {c: dotted({k: v for k, v in ok[c].items() if k != "converged"}) for c in names}
    keys = [k for k in flat[names[0]] if all(isinstance(flat[c].get(k), (int, float)) for c in names)]
    header = ["combination"] + [f"{k} [{_unit(k)}]" for k in keys]
    cols = [np.array(names, object)] + [np.array([float(flat[c][k]) for c in names], object) for k in keys]
    t1 = Table("combinations.csv", header, cols, ["%s"] + ["%.17g"] * len(keys))
    rows = []
    for rod, e in env.items():
        for i, s in enumerate(e["s"]):
            rows.append([rod, s, e["M_min"][i], e["M_max"][i]] + [e["M"][c][i] for c in names])
    header2 = ["rod", "s [m]", "M_min [N m]", "M_max [N m]"] + [f"M {c} [N m]" for c in names]
    cols2 = [np.array([r[k] for r in rows], object) for k in range(len(header2))]
    t2 = Table("envelope_M.csv", header2, cols2, ["%s"] + ["%.17g"] * (len(header2) - 1))
    return [t1, t2]


_UNITS = {"M": "N m", "M_max": "N m", "N_max": "N", "V_max": "N", "Fx": "N", "Fy": "N", "u": "m", "v": "m",
          "x": "m", "y": "m", "slide": "m", "theta": "rad", "rotation": "rad", "iterations": "-",
          "error_estimate": "-", "load_factor": "-"}


def _unit(key: str) -> str:
    return _UNITS.get(key.rsplit(".", 1)[-1], "-")


# -- arc-length outputs --------------------------------------------------------------------------------------
def _arc_length_outputs(out: Outcome, sol, opts):
    """``limit_points``, ``path``, ``stable`` of an arc-length solve; path.csv and path.png."""
    import numpy as np

    from femslide.analysis.paths import is_stable
    from femslide.app.result import dotted
    from femslide.results.static import extract
    values = out.values
    tr = sol.trace
    model = tr.model
    lv = sol.level
    end = tr.end
    from femslide.model.state import ElementState
    # (on the traced mesh: the finest may be too large for the dense eigenvalue test)
    values["stable"] = is_stable(model, end.y, ElementState(end.alpha.copy())) if lv.model.n > 600 \
        else is_stable(lv.model, lv.y, lv.elements)
    lps = []
    for c in sol.critical or []:
        p = c.point
        res = extract(c.model, p.y, p.alpha, lam=p.lam)
        err = None if c.error is None else c.error / max(abs(c.lam), 1e-300)
        lps.append({"kind": c.kind, "load_factor": c.lam, "error_estimate": err,
                    "elements": {r.name: int(n.size - 1) for r, n in zip(c.model.structure.rods, c.model.rod_nodes)},
                    **{k: res[k] for k in ("bodies", "rods", "joints", "reactions")}})
    values["limit_points"] = lps
    pts = []
    for p in tr.points:
        res = extract(model, p.y, p.alpha, lam=p.lam)
        pts.append({"load_factor": p.lam, "kind": p.kind, **{k: res[k] for k in ("M_max", "bodies", "rods", "joints",
                                                                                  "reactions")}})
    values["path"] = pts
    values["path_elements"] = {r.name: int(n.size - 1) for r, n in zip(model.structure.rods, model.rod_nodes)}
    flat = [dotted({k: v for k, v in p.items() if k != "kind"}) for p in pts]
    keys = list(flat[0])
    header = [f"{k} [{_unit(k)}]" for k in keys] + ["kind"]
    cols = [np.array([float(f[k]) for f in flat], object) for k in keys] + [np.array([p["kind"] for p in pts], object)]
    out.tables = [Table("path.csv", header, cols, ["%.17g"] * len(keys) + ["%s"])]
    name = opts.get("plot") or _most_changing(flat, model)
    if name not in keys:
        raise BadInput(f"[solve] plot = {name!r}: no such output of the path; outputs: {', '.join(keys[1:])}")
    refined = iter([c.lam for c in sol.critical or [] if c.kind != "bifurcation"])
    lim = [(f[name], next(refined, f["load_factor"])) for f, p in zip(flat, pts) if p["kind"] == "limit"]
    lim_at = [f["load_factor"] for f, p in zip(flat, pts) if p["kind"] == "limit"]
    end = next(((f[name], f["load_factor"]) for f, p in zip(flat, pts) if p["kind"] == "end"), None)
    out.figures.append(Figure("path.png", "path", {
        "x": [f[name] for f in flat], "lam": [f["load_factor"] for f in flat], "label": f"{name} [{_unit(name)}]",
        "limits": lim, "limits_at": lim_at, "end": end,
        "title": f"{out.name}: load path (arc length, {values['path_elements']} elements)"}))
    values["path_plot"] = name


def _most_changing(flat, model):
    """The displacement or rotation output of the path that changes most (lengths in units of the
    structure's size, rotations in rad): of the bodies if there are any, else of the joints, else
    of the rods' ends."""
    keys = list(flat[0])
    for group in ("bodies.", "joints.", "rods."):
        if any(k.startswith(group) and k.rsplit(".", 1)[-1] in ("x", "y", "u", "v", "slide", "rotation", "theta")
               for k in keys):
            keys = [k for k in keys if k.startswith(group)]
            break
    best, name = -1.0, "load_factor"
    for k in keys:
        last = k.rsplit(".", 1)[-1]
        if last in ("x", "y", "u", "v", "slide"):
            scale = model.Lref
        elif last in ("rotation", "theta"):
            scale = 1.0
        else:
            continue
        vals = [f[k] for f in flat]
        change = (max(vals) - min(vals)) / scale
        if math.isfinite(change) and change > best:
            best, name = change, k
    return name
