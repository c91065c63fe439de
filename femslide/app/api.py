"""The Python API behind ``femslide.solve``, ``femslide.simulate`` and ``femslide.sweep``.

:func:`solve_api` and :func:`run_api` run a declared structure (or a structure file) with overrides;
:func:`sweep_table` is ``femslide.sweep``: a table of cases run by the command line's sweep
executors (femslide/app/sweeps.py).  Scenes and files run through femslide.app.run.
"""
from __future__ import annotations

import os

from femslide.errors import BadInput


def run_api(target, params: dict, data: dict | None = None):
    """``femslide.simulate`` of a Structure, a Frozen structure or a structure file: keyword
    arguments named like the [simulate] keys (t_end, tolerance, damping, ground, initial, elements;
    also as ``**{"simulate.tolerance": 1e-7}``, the command line's form) set or override them;
    ``NAME.FIELD`` ones change the structure (a Structure or a file); ``data``: the file's tables
    if the caller has read them."""
    from femslide.analysis.simulate import SIM_KEYS, parse_spec, simulate
    from femslide.app.result import Result
    from femslide.app.structfile import apply, load
    from femslide.model.frozen import Frozen
    from femslide.model.structure import Structure
    table, base = {}, "."
    if isinstance(target, str):
        sf = load(target, data)
        table = dict(sf.simulate_table or {})
        base = os.path.dirname(os.path.abspath(target))
        target, name = sf.structure, sf.name
    else:
        name = "structure"
    # [simulate] keys, bare or in the command line's --set form simulate.KEY
    from femslide.app.structfile import record_paths, simulate_table
    sim = {k: params.pop(k) for k in list(params) if k.startswith("simulate.")}
    both = sorted({k.split(".")[1] for k in sim} & set(params) & set(SIM_KEYS))
    if both:
        raise BadInput(f"simulate: {both[0]} given both as {both[0]} and as simulate.{both[0]}; allowed: one of them")
    sim.update({f"simulate.{k}": params.pop(k) for k in list(params) if k in SIM_KEYS})
    table = simulate_table(table, record_paths(sim))
    if isinstance(target, Structure):
        s, elements = apply(target, params)
        fs = s.freeze()
    elif isinstance(target, Frozen):
        if params:
            raise BadInput("overrides of fields need a Structure, not a frozen one")
        fs, elements = target, None
    else:
        raise BadInput(f"simulate: {target!r} is not a Structure or a structure file")
    spec = parse_spec(table, base)
    if elements is not None:
        spec.elements = elements
    return Result.of(simulate(fs, spec, name=name))


def _values_of(name, values):
    """The list of values of a varied parameter; BadInput unless a non-empty sequence."""
    if isinstance(values, (str, bytes, dict)) or not hasattr(values, "__iter__"):
        raise BadInput(f"sweep: {name} = {values!r} is not a list of values; allowed: a non-empty list, "
                       f"tuple, range or array (a constant goes into fixed=)")
    items = [v.tolist() if hasattr(v, "tolist") else v for v in values]   # numpy scalars, 0-d arrays too
    if not items:
        raise BadInput(f"sweep: {name} has no values; allowed: a non-empty list of values")
    return items


def sweep_table(target, varied: dict, fixed: dict | None = None, jobs: int = 1, quiet: bool = False,
                dask: str | None = None):
    """``femslide.sweep``: run every combination of the varied values; one DataFrame row per case.

    Columns: the varied names, ``converged``, ``status`` ("converged"; "failed": the solver gave up,
    ``reason`` says why; "bad-input": the case's values were rejected when it ran, e.g. a work bound
    that depends on the solution; "error": an internal error), ``reason``, then every scalar result
    under dotted names.  Values that can be checked before running are checked for every case first
    (BadInput, nothing run).

    Every case is solved from scratch exactly as ``femslide solve``/``simulate`` solves it alone,
    through the command line's sweep executors (femslide/app/sweeps.py): in this process, in a pool of
    ``jobs`` processes, or on Dask (``dask`` "local" or a scheduler address; BadInput naming
    ``pip install 'femslide[dask]'`` without dask.distributed).  A structure file or Structure with a
    ``simulate.KEY`` among the varied or fixed values is simulated in every case: its rows hold the
    peaks (one column per flattened peak, ``peaks.reactions.A1.Fx``), the friction events' counts
    (``events.JOINT``), ``error_estimate`` and ``status``.  A declared :class:`~femslide.Structure` is
    written to a temporary structure file first, so that worker processes can load it.
    """
    import itertools
    import tempfile

    import pandas as pd

    from femslide.app.progress import progress
    from femslide.app.result import dotted
    from femslide.app.run import load_target
    from femslide.app.sweeps import _run_dask, is_dynamic, run_pool, run_serial
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
    if dask is not None:
        if not isinstance(dask, str) or not (dask == "local" or "://" in dask):
            raise BadInput(f"sweep: dask = {dask!r}; allowed: 'local' or a scheduler address tcp://host:port")
        try:
            import dask.distributed as _dd  # noqa: F401  (binds _dd only, not the name 'dask')
        except ImportError:
            raise BadInput("sweep: dask needs dask.distributed: pip install 'femslide[dask]'") from None
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
        if is_dynamic({**fixed, **varied}) and hasattr(tgt.scene, "for_simulate"):
            tgt = tgt.scene.for_simulate()
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
            if dask is not None:
                runs = _run_dask(spec, cases, list(range(n)), out_dirs, dask, jobs if jobs > 1 else None)
            elif jobs > 1 and n > 1:
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
