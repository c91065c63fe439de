"""Running one case, whatever it is: a built-in scene, a scene file, a structure file or a declared
structure.  The command line, sweeps and the Python API all run cases through here.

A runner returns an :class:`femslide.results.outcome.Outcome` (plain data: the contract's values,
the static solution, the time history, what its files hold); a run returns it as a :class:`Result`:
a dict holding the JSON object of the contract (the keys ``solve --json`` / ``simulate --json``
print) plus, for FE statics, the solution (``result.solution``) with per-rod arrays and values by
name, for simulations the time history, and its files written on request (femslide.output.files).
"""
from __future__ import annotations

import gc
import time

from femslide.app.result import Result
from femslide.errors import SolverFailure

_COLLECTOR_OFF: list = []   # the command line's start-up, until the first case's machinery is imported


def start_up():
    """The command line's start-up (femslide.app.cli.main, as a process of its own): the cyclic
    garbage collector is off until the machinery of the first case is imported (:func:`started`).
    The imports - femslide, numpy, the FE modules - make only objects that live as long as the
    process, which the collector would scan again and again: 40 young and 4 older collections,
    ~8 ms of a 9-case sweep's ~200 ms process, for nothing."""
    gc.disable()
    _COLLECTOR_OFF.append(True)


def started():
    """End of the start-up: what the imports made is frozen (``gc.freeze``: never scanned again)
    and the collector is switched back on for the run itself (a no-op unless :func:`start_up`
    switched it off)."""
    if _COLLECTOR_OFF:
        _COLLECTOR_OFF.clear()
        gc.freeze()
        gc.enable()



def run_case(scene, values, out=None, quiet=False) -> Result:
    """Run a scene (built-in, scene file or structure file) with validated ``values``; the result has
    ``wall_time_s`` (the run itself) and ``import_time_s`` (importing the machinery it needs, the
    first time in a process; 0 afterwards); with ``out`` its files and result.json are written
    there, also when the run stops half way (SolverFailure carrying ``outcome``: a simulation's history
    so far; ``exc.result`` then holds it and ``exc.files`` the files written).  ``quiet`` switches off progress bars."""
    t_imp = time.perf_counter()
    prepare = getattr(scene, "prepare", None)
    if prepare is not None:
        prepare()
    started()
    t0 = time.perf_counter()
    bar = None
    if getattr(scene, "kind", "") == "fe-dynamics":   # a bar over simulated time (a no-op unless a terminal)
        from femslide.app.progress import TimeProgress
        bar = TimeProgress(values["t_end"], f"simulate {scene.name}", quiet or bool(values.get("_quiet")))
        values = {**values, "_progress": bar.at}
    try:
        outcome = scene.run({**values, "_quiet": True} if quiet else values)
    except SolverFailure as exc:
        # a run stopped half way (a simulation at its max_time, or failing): what it computed is kept
        # on the exception (``exc.outcome``) and written with ``out``; ``exc.files`` names the files
        part = getattr(exc, "outcome", None)
        if part is not None:
            exc.result = Result.of(part)
            if out:
                exc.files = exc.result.write(out)[:-1]
        raise
    finally:
        if bar is not None:
            bar.close()
    wall = time.perf_counter() - t0
    res = Result.of(outcome)
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
