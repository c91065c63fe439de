"""femslide: planar structures on flexible support rods joined by sliding joints.

Python API (the command line is a thin layer over it)::

    import femslide
    res = femslide.solve("hinge-slider", c=1e8)      # dict, the JSON object of ``femslide solve``
    res["M_max"], res["reactions"]["B1"]["Fx"]

Units are SI throughout; sign conventions are those of SPEC section 1 (phi > 0 leaning towards B1,
reactions are forces of the ground on the structure).
"""
from __future__ import annotations

from .errors import BadInput, SolverFailure

__all__ = ["solve", "simulate", "list_scenes", "BadInput", "SolverFailure"]
__version__ = "0.1.0"


def list_scenes():
    """Names of the built-in scenes."""
    from .scenes import SCENES
    return list(SCENES)


def _run(command, scene, params):
    from .cli import run_one
    from .scenes import get
    s = get(scene)
    if s.command != command:
        raise BadInput(f"scene {scene} is a '{s.command}' scene")
    return run_one(s, s.resolve(params))


def solve(scene: str, **params) -> dict:
    """Solve a static scene; keyword arguments are scene parameters (SI units)."""
    return _run("solve", scene, params)


def simulate(scene: str, **params) -> dict:
    """Run a dynamic scene; keyword arguments are scene parameters (SI units)."""
    return _run("simulate", scene, params)
