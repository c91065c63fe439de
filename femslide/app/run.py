"""Running one case, whatever it is: a built-in scene, a scene file, a structure file or a declared
structure.  The command line, sweeps and the Python API all run cases through here.

A run returns a :class:`Result`: a dict holding the JSON object of the contract (the keys ``solve
--json`` / ``simulate --json`` print) plus, for FE statics, the solution (``result.solution``) with
per-rod arrays and values by name, for simulations the time history, and files on request.  A scene
runner hands these over in private keys of its dict, which never reach the result's keys:
``_write`` (the writer of its files), ``_solution`` (a static solution) and ``_history`` (the time
history: a dict of arrays, or a callable returning one when asked for).

:func:`sweep_table` is ``femslide.sweep``: a table of cases run by the command line's sweep
executors (femslide/app/sweeps.py).
"""
from __future__ import annotations

import os
import time
from typing import TYPE_CHECKING

from femslide.app.result import Result, dotted
from femslide.errors import BadInput

if TYPE_CHECKING:
    pass


def solve_structure(fs, elements=None, name="structure", cache=None) -> Result:
    """Static equilibrium of a frozen structure: the section 8 result."""
    from femslide.analysis import static
    sol = static.solve(fs, elements=elements, cache=cache)
    res = sol.result
    out = Result(converged=True, M_max=res["M_max"], bodies=res["bodies"], rods=res["rods"],
                 joints=res["joints"], reactions=res["reactions"], iterations=sol.iterations,
                 error_estimate=sol.error_estimate)
    out.solution = sol

    def write(d):
        from femslide.output.vtu import write_static
        return write_static(sol, d, name)

    out._writer = write
    return out


def run_case(scene, values, out=None, quiet=False) -> Result:
    """Run a scene (built-in, scene file or structure file) with validated ``values``; the result has
    ``wall_time_s`` (the run itself) and ``import_time_s`` (importing the machinery it needs, the
    first time in a process; 0 afterwards); with ``out`` its files and result.json are written
    there.  ``quiet`` switches off progress bars."""
    t_imp = time.perf_counter()
    prepare = getattr(scene, "prepare", None)
    if prepare is not None:
        prepare()
    t0 = time.perf_counter()
    raw = scene.run({**values, "_quiet": True} if quiet else values)
    wall = time.perf_counter() - t0
    if isinstance(raw, Result):
        res = raw
    else:
        res = Result({k: v for k, v in raw.items() if not k.startswith("_")})
        res._writer = raw.get("_write")
        res.solution = raw.get("_solution")
        res._history_source = raw.get("_history")
    res["wall_time_s"] = wall
    res["import_time_s"] = t0 - t_imp
    if out:
        res["files"] = res.write(out)[:-1]
    return res


def load_target(name: str):
    """A built-in scene name, a scene file or a structure file -> a target with ``scene`` (name,
    command, run) and ``resolve(given) -> values``."""
    from femslide.app.scenefile import target
    return target(name)


def _values_of(name, values):
    """The list of values of a varied parameter; BadInput unless a non-empty sequence."""
    if isinstance(values, (str, bytes, dict)) or not hasattr(values, "__iter__"):
        raise BadInput(f"sweep: {name} = {values!r} is not a list of values; allowed: a non-empty list, "
                       f"tuple, range or array (a constant goes into fixed=)")
    items = [v.tolist() if hasattr(v, "tolist") else v for v in values]   # numpy scalars, 0-d arrays too
    if not items:
        raise BadInput(f"sweep: {name} has no values; allowed: a non-empty list of values")
    return items


def sweep_table(target, varied: dict, fixed: dict | None = None, jobs: int = 1, quiet: bool = False):
    """``femslide.sweep``: run every combination of the varied values; one DataFrame row per case.

    Columns: the varied names, ``converged``, ``status`` ("converged"; "failed": the solver gave up,
    ``reason`` says why; "bad-input": the case's values were rejected when it ran, e.g. a work bound
    that depends on the solution; "error": an internal error), ``reason``, then every scalar result
    under dotted names.  Values that can be checked before running are checked for every case first
    (BadInput, nothing run).

    Every case is solved from scratch exactly as ``femslide solve``/``simulate`` solves it alone,
    through the command line's sweep executors (femslide/app/sweeps.py): in this process, or in a pool of
    ``jobs`` processes.  A declared :class:`~femslide.Structure` is written to a temporary structure
    file first, so that worker processes can load it.
    """
    import itertools
    import tempfile

    import pandas as pd

    from femslide.app.progress import progress
    from femslide.app.sweeps import run_pool, run_serial
    from femslide.model.frozen import Frozen
    from femslide.model.structure import Structure

    if not varied:
        raise BadInput("sweep: no varied parameter; give one or more as name=[values...], e.g. EI=[1e4, 1e6]")
    fixed = dict(fixed or {})
    both = sorted(set(fixed) & set(varied))
    if both:
        raise BadInput(f"sweep: {', '.join(both)} both fixed and varied; allowed: each name in one of them")
    if isinstance(jobs, bool) or not isinstance(jobs, int) or jobs < 1:
        raise BadInput(f"sweep: jobs = {jobs!r}; allowed: an integer >= 1")
    lists = {name: _values_of(name, v) for name, v in varied.items()}
    names = list(lists)
    with tempfile.TemporaryDirectory(prefix="femslide-sweep-") as tmp:
        if isinstance(target, Frozen):
            raise BadInput("sweep: a frozen structure cannot be changed; pass the Structure itself")
        if isinstance(target, Structure):
            from femslide.app.structfile import dumps
            spec = os.path.join(tmp, "structure.toml")
            with open(spec, "w") as fh:
                fh.write(dumps(target))
            label = "structure"
        elif isinstance(target, (str, os.PathLike)):
            spec = os.fspath(target)
            label = spec
        else:
            raise BadInput(f"sweep: target {target!r}; allowed: a built-in scene name, a scene or structure "
                           f"file path, or a femslide.Structure")
        tgt = load_target(spec)
        spec = getattr(tgt.scene, "spec", spec)
        if os.path.isfile(spec):
            spec = os.path.abspath(spec)  # workers may start elsewhere
        combos = [dict(zip(names, c)) for c in itertools.product(*(lists[n] for n in names))]
        cases = [tgt.resolve({**fixed, **c}) for c in combos]  # every case checked before any run
        n = len(cases)
        rows: list = [None] * n
        out_dirs: list = [None] * n
        bar = progress(n, f"sweep {label}", quiet, unit="case")
        try:
            if jobs > 1 and n > 1:
                runs = run_pool(spec, cases, range(n), out_dirs, min(jobs, n))
            else:
                runs = run_serial(spec, cases, range(n), out_dirs)
            for i, row, status in runs:
                rows[i] = {**{nm: cases[i].get(nm, combos[i][nm]) for nm in names},
                           "converged": bool(row.get("converged", True)), "status": status,
                           "reason": row.get("reason"),
                           **dotted({k: v for k, v in row.items() if k not in ("converged", "reason")})}
                bar.update(1)
        finally:
            bar.close()
    df = pd.DataFrame(rows)
    df.attrs.update({"target": label, "varied": names, "fixed": fixed})
    return df
