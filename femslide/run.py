"""Running one case, whatever it is: a built-in scene, a scene file, a structure file or a declared
structure.  The command line, sweeps and the Python API all run cases through here.

A run returns a :class:`Result`: a dict holding the JSON object of the contract (SPEC sections 7 and
8) plus, for FE statics, the solution (``result.solution``) whose arrays and files can be asked for.
"""
from __future__ import annotations

import json
import math
import os
import time

from .errors import BadInput


class Result(dict):
    """The JSON object of a run (``r["M_max"]``, ``r["rods"]["right"]["M_max"]``...), with, for FE
    statics, ``solution`` (a :class:`femslide.static.Solution`) and per-rod arrays by name."""

    solution = None
    _writer = None

    def rod(self, name: str) -> dict:
        """Arrays along the rod (SI): s, x, y, u, v, theta, N, V, M (finest mesh, raw values)."""
        if self.solution is None:
            raise BadInput("this result has no rods")
        arrays = self.solution.level.arrays
        if name not in arrays:
            raise BadInput(f"no rod named {name!r}; rods: {', '.join(arrays)}")
        return arrays[name]

    def write(self, out_dir: str) -> list[str]:
        """Write the run's files (VTU, sidecar JSON, result.json) into ``out_dir``; returns the paths."""
        os.makedirs(out_dir, exist_ok=True)
        files = self._writer(out_dir) if self._writer else []
        path = os.path.join(out_dir, "result.json")
        with open(path, "w") as fh:
            json.dump(clean({**self, "files": files}), fh, indent=1)
        return files + [path]


def clean(obj):
    """JSON-safe copy: numpy scalars to float, non-finite floats to null, private keys dropped."""
    if isinstance(obj, dict):
        return {k: clean(v) for k, v in obj.items() if not str(k).startswith("_")}
    if isinstance(obj, (list, tuple)):
        return [clean(v) for v in obj]
    if isinstance(obj, bool) or obj is None or isinstance(obj, str):
        return obj
    if isinstance(obj, int):
        return obj
    try:
        x = float(obj)
    except (TypeError, ValueError):
        return str(obj)
    return x if math.isfinite(x) else None


def fmt(v):
    """A value as the plain-text output prints it."""
    if isinstance(v, float):
        return f"{v:.10g}"
    if v is None:
        return "-"
    return str(v)


def solve_structure(fs, elements=None, name="structure", cache=None) -> Result:
    """Static equilibrium of a frozen structure: the section 8 result."""
    from . import static
    sol = static.solve(fs, elements=elements, cache=cache)
    res = sol.result
    out = Result(converged=True, M_max=res["M_max"], bodies=res["bodies"], rods=res["rods"],
                 joints=res["joints"], reactions=res["reactions"], iterations=sol.iterations,
                 error_estimate=sol.error_estimate)
    out.solution = sol

    def write(d):
        from .vtu import write_static
        return write_static(sol, d, name)

    out._writer = write
    return out


def run_case(scene, values, out=None, quiet=False) -> Result:
    """Run a scene (built-in, scene file or structure file) with validated ``values``; the result has
    ``wall_time_s``; with ``out`` its files and result.json are written there.  ``quiet`` switches
    off progress bars."""
    t0 = time.perf_counter()
    raw = scene.run({**values, "_quiet": True} if quiet else values)
    wall = time.perf_counter() - t0
    if isinstance(raw, Result):
        res = raw
    else:
        res = Result({k: v for k, v in raw.items() if not k.startswith("_")})
        res._writer = raw.get("_write")
        res.solution = raw.get("_solution")
    res["wall_time_s"] = wall
    if out:
        res["files"] = res.write(out)[:-1]
    return res


def load_target(name: str):
    """A built-in scene name, a scene file or a structure file -> a target with ``scene`` (name,
    command, run) and ``resolve(given) -> values``."""
    from .scenefile import target
    return target(name)
