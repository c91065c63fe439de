"""femslide: planar structures on flexible support rods joined by sliding joints.

Declare a structure, solve it, read results by name (SI units; rotations and moments
counter-clockwise positive; reactions are forces of the ground on the structure)::

    import femslide
    s = femslide.Structure(gravity=(0.0, -9.81))
    s.rod("col", start=(0, 0), end=(0, 3), EI=2e6)
    s.body("deck", mass=500.0, centroid=(1.0, 3.5), outline=[(0, 3), (2, 3), (2, 4), (0, 4)])
    s.pin("base", a="col.start", b="ground")
    s.weld("top", a="col.end", b="deck")
    s.roller("right", a="deck", b="ground", at=(2.0, 3.0), axis=(0.0, 1.0))
    r = femslide.solve(s)
    r["reactions"]["base"]["Fy"], r["rods"]["col"]["M_max"], r.rod("col")["M"]

``femslide.solve`` also takes a structure file (TOML), a scene file or a built-in scene name with its
parameters: ``femslide.solve("beam-slider", EI=1e8)`` returns the scene's contract values (phi > 0
leaning towards B1, as in the paper).
"""
from __future__ import annotations

from .errors import BadInput, SolverFailure
from .structure import Structure, Table

__all__ = ["Structure", "Table", "solve", "simulate", "load", "list_scenes", "BadInput", "SolverFailure"]
__version__ = "0.2.0"


def list_scenes():
    """Names of the built-in scenes."""
    from .scenes import SCENES
    return list(SCENES)


def load(path: str) -> Structure:
    """The structure declared in a structure file (TOML), to inspect, change and solve."""
    from .structfile import load as _load
    return _load(path).structure


def _run(command, target, params):
    from .run import load_target, run_case
    from .structure import Frozen
    if isinstance(target, (Structure, Frozen)):
        if command != "solve":
            raise BadInput("simulate of declared structures is not available yet (FE dynamics)")
        from .structfile import apply
        s = target if isinstance(target, Structure) else None
        elements = params.pop("elements", None)
        if params:
            if s is None:
                raise BadInput("overrides need a Structure, not a frozen one")
            s, _ = apply(s, params)
        fs = s.freeze() if s is not None else target
        from .run import solve_structure
        import time
        t0 = time.perf_counter()
        res = solve_structure(fs, elements=elements)
        res["wall_time_s"] = time.perf_counter() - t0
        return res
    tgt = load_target(target)
    scene = tgt.scene
    if scene.command != command:
        raise BadInput(f"{target} is a '{scene.command}' scene")
    return run_case(scene, tgt.resolve(params))


def solve(target, **params):
    """Static equilibrium.  ``target``: a :class:`Structure`, a structure or scene file path, or a
    built-in scene name; keyword arguments override parameters (scenes: ``EI=1e8``; structures:
    ``**{"right.EI": 1e8}``, ``elements=32``).  Returns a dict-like :class:`femslide.run.Result`."""
    return _run("solve", target, dict(params))


def simulate(target, **params):
    """Dynamics.  ``target``: a :class:`Structure` or a structure file (FE dynamics: keyword arguments
    ``t_end``, ``tolerance``, ``damping``, ``ground``, ``initial``, ``elements`` as in a file's
    ``[simulate]`` table, and ``NAME.FIELD`` overrides), or a dynamic scene (a built-in name or a
    scene file) with its parameters.  Returns a dict-like :class:`femslide.run.Result`."""
    from .structure import Frozen
    if isinstance(target, (Structure, Frozen)) or (isinstance(target, str) and target.endswith(".toml")
                                                   and _is_structure_file(target)):
        from .simulation import run_api
        return run_api(target, dict(params))
    return _run("simulate", target, dict(params))


def _is_structure_file(path):
    from .structfile import is_structure_data, read_toml
    return is_structure_data(read_toml(path))
