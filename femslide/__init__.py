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

import os
from collections.abc import Iterable
from typing import TYPE_CHECKING, Any, Union

from femslide.app.result import Result
from femslide.errors import BadInput, SolverFailure
from femslide.version import __version__  # noqa: F401  (femslide.__version__)
from femslide.model.parts import Table
from femslide.model.structure import Structure

if TYPE_CHECKING:
    import pandas

    from femslide.model.frozen import Frozen

#: what solve and sweep take: a Structure, a structure or scene file path, or a built-in scene name
Target = Union[Structure, "Frozen", str, os.PathLike]

__all__ = ["Structure", "Table", "solve", "simulate", "sweep", "buckling", "load", "list_scenes", "plot", "Result",
           "BadInput", "SolverFailure"]


def list_scenes() -> list[str]:
    """Names of the built-in scenes (``femslide scenes`` lists their parameters and defaults).

    Returns
    -------
    list of str
        ``["hinge-slider", ..., "beam-slider", ..., "sdof-harmonic", ...]``.
    """
    from femslide.scenes.catalog import SCENES
    return list(SCENES)


def load(path: str) -> Structure:
    """The structure declared in a structure file (TOML), to inspect, change and solve.

    Parameters
    ----------
    path : str
        A structure file: ``[[rod]]``, ``[[body]]``, ``[[joint]]``, ``[[load]]`` tables and
        ``gravity`` (a file without a ``scene`` key).

    Returns
    -------
    Structure
        A new, mutable declaration; ``femslide.solve(s)`` solves it.

    Raises
    ------
    BadInput
        A missing or malformed file; the message names the file, the entry and the field.
    """
    from femslide.app.structfile import load as _load
    return _load(path).structure


def _check_target(command, target):
    """BadInput unless ``target`` is something :func:`solve` / :func:`simulate` can run."""
    from femslide.model.frozen import Frozen
    if isinstance(target, (Structure, Frozen, os.PathLike)) or (isinstance(target, str) and target):
        return
    raise BadInput(f"{command}: target {target!r} ({type(target).__name__}); allowed: a femslide.Structure, "
                   f"a structure or scene file path, or a built-in scene name (femslide.list_scenes())")


def _run(command, target, params):
    from femslide.app.run import load_target, run_case
    from femslide.model.frozen import Frozen
    _check_target(command, target)
    if isinstance(target, (Structure, Frozen)):   # solve (simulate takes structures in app.api.run_api)
        from femslide.app.structfile import apply
        s = target if isinstance(target, Structure) else None
        elements = params.pop("elements", None)
        options = {k: params.pop(k) for k in ("path", "theory", "plot") if k in params}
        options.update({k.split(".", 1)[1]: params.pop(k) for k in list(params) if k.startswith("solve.")})
        if params:
            if s is None:
                raise BadInput("overrides need a Structure, not a frozen one")
            s, _ = apply(s, params)
        fs = s.freeze() if s is not None else target
        import time
        t_imp = time.perf_counter()
        from femslide.analysis import static  # noqa: F401  (timed apart: import_time_s)
        from femslide.model.linalg import load_lapack
        load_lapack()
        from femslide.app.cases import statics
        from femslide.app.result import Result
        t0 = time.perf_counter()
        res = Result.of(statics(fs, elements=elements, options=options))
        res["wall_time_s"] = time.perf_counter() - t0
        res["import_time_s"] = t0 - t_imp
        return res
    import os
    tgt = load_target(os.fspath(target) if isinstance(target, os.PathLike) else target)
    scene = tgt.scene
    if scene.command != command:
        raise BadInput(f"{target} is a '{scene.command}' scene")
    if command == "solve" and getattr(scene, "solve_options", None):   # a structure file: solve options
        for k in ("path", "theory", "plot"):
            if k in params:
                params[f"solve.{k}"] = params.pop(k)
    return run_case(scene, tgt.resolve(params))


def solve(target: Target, **params: Any) -> Result:
    """Static equilibrium on the principal branch (all loads ramped together from zero).

    Parameters
    ----------
    target : Structure, str or os.PathLike
        A :class:`Structure`, a structure file (TOML), a scene file, or a built-in scene name
        (``"beam-slider"``; :func:`list_scenes`).
    **params
        Overrides.  Scenes: their parameters (``EI=1e8``, SI units).  Structures and structure
        files: fields by name, ``**{"right.EI": 1e8, "wind.force": [0, -500]}``, ``gravity``,
        ``elements=32`` (a fixed mesh for every rod instead of adaptive refinement), and the solve
        options ``path="arc-length"`` (through limit points; default "principal"), ``theory="linear"``
        (first order; default "nonlinear"), ``plot="bodies.deck.rotation"`` (the output of an
        arc-length path's picture).

    Returns
    -------
    Result
        A dict of named values (SI units): for declared structures ``converged``, ``M_max``,
        ``bodies``, ``rods``, ``joints``, ``reactions``, ``iterations``, ``error_estimate``,
        ``wall_time_s`` (with load combinations: ``combinations`` {name: those values} and their
        ``envelope``, :meth:`Result.combination`; with ``path="arc-length"``: ``limit_points``,
        ``path``, ``stable``); for scenes the keys of ``femslide solve SCENE --json``.  FE results
        also give arrays along the rods (:meth:`Result.rod`) and a table (:meth:`Result.to_dataframe`).

    Raises
    ------
    BadInput
        An unknown name, a value out of range, a structure that is not connected to the ground.
    SolverFailure
        The load path ends at a limit point before full load, or the structure is a mechanism.
    """
    return _run("solve", target, dict(params))


def simulate(target: Target, **params: Any) -> Result:
    """Motion in time of a dynamic scene or of a declared structure (FE dynamics).

    Parameters
    ----------
    target : str, os.PathLike or Structure
        A built-in dynamic scene (``sdof-free``, ``sdof-decay``, ``sdof-harmonic``,
        ``beam-oscillation``, ``beam-friction``) or a scene file of one; or a :class:`Structure` or
        a structure file (the FE dynamics of any declared structure: its ``[simulate]`` table).
    **params
        A scene's parameters (``t_end=5.0``, ``mu=0.2``, SI units); for a structure the keys of a
        ``[simulate]`` table (``t_end``, ``tolerance``, ``damping``, ``ground``, ``initial``,
        ``elements``) and ``NAME.FIELD`` overrides of the declaration.

    Returns
    -------
    Result
        The keys of ``femslide simulate SCENE --json`` (scenes: ``turning_points``, ``stop``,
        ``w_max``, ``steady_amplitude``, ``steps``, ``energy_balance``, ``wall_time_s``...;
        structures: ``steps``, ``energy_balance``, ``events``, ``frequencies_hz``, ``peaks``...) and
        the time history, :attr:`Result.history`.

    Raises
    ------
    BadInput
        An unknown parameter or a value out of range (also a run whose work would exceed the
        bounds; the message gives the usable range).
    SolverFailure
        The integration failed (scenes: or its energy balance is worse than 1e-6).
    """
    from femslide.model.frozen import Frozen
    _check_target("simulate", target)
    data = _structure_data(str(target)) if isinstance(target, (str, os.PathLike)) else None
    if isinstance(target, (Structure, Frozen)) or data is not None:
        from femslide.app.api import run_api
        return run_api(target if not isinstance(target, os.PathLike) else str(target), dict(params), data=data)
    return _run("simulate", target, dict(params))


def buckling(target: Target, count: int = 4, about: str = "equilibrium", combination: str | None = None,
             **params: Any) -> Result:
    """Linear buckling: the lowest load factors at which the structure under its loads loses stability.

    Parameters
    ----------
    target : Structure or str
        A :class:`Structure` or a structure file.
    count : int, default 4
        How many of the lowest positive load factors.
    about : {"equilibrium", "reference"}
        The state whose stresses are scaled: the equilibrium under the loads (default; its
        deformation and the loads' stiffness included) or the reference state with the stresses of
        first-order theory (classic linear buckling).
    combination : str, optional
        The loads of this load combination (default: every load as declared).
    **params
        ``NAME.FIELD`` overrides and ``elements=N`` (a fixed mesh), as for :func:`solve`.

    Returns
    -------
    Result
        ``load_factors`` (ascending; times the loads they are the critical loads), their
        ``error_estimates`` (relative, from the mesh refinement), ``error_estimate`` (the largest),
        ``about``, ``elements``; :meth:`Result.write` writes the mode shapes (a PVD series, the
        mode number as its time) and ``buckling_modes.png``.

    Raises
    ------
    BadInput
        Not a structure, an unknown combination, ``about`` or a field out of range.
    SolverFailure
        The equilibrium under the loads cannot be reached (about the equilibrium).
    """
    from femslide.analysis.buckling import buckling as _buckling
    from femslide.app.structfile import apply, load as _load
    from femslide.model.frozen import Frozen
    if isinstance(target, (str, os.PathLike)):
        sf = _load(os.fspath(target))
        target, name = sf.structure, sf.name
    else:
        name = "structure"
    if isinstance(target, Frozen):
        if params:
            raise BadInput("overrides need a Structure, not a frozen one")
        fs, elements = target, None
    elif isinstance(target, Structure):
        s, elements = apply(target, params)
        fs = s.freeze()
    else:
        raise BadInput(f"buckling: {target!r} is not a Structure or a structure file")
    if isinstance(count, bool) or not isinstance(count, int) or not 1 <= count <= 50:
        raise BadInput(f"buckling: count = {count!r}; allowed: an integer in [1, 50]")
    return Result.of(_buckling(fs, count=count, about=about, elements=elements, combination=combination, name=name))


def _structure_data(path):
    """The tables of the structure file ``path`` (read once: the run parses them), None for anything else
    (a scene name, a scene file)."""
    if not path.endswith(".toml"):
        return None
    from femslide.app.structfile import is_structure_data, read_toml
    data = read_toml(path)
    return data if is_structure_data(data) else None


def sweep(target: Target, *, fixed: dict[str, Any] | None = None, jobs: int = 1, quiet: bool = False,
          dask: str | None = None, **varied: Iterable[Any]) -> pandas.DataFrame:
    """Solve (or simulate) every combination of parameter values; one table row per case.

    Parameters
    ----------
    target : str, os.PathLike or Structure
        A built-in scene name (``"beam-slider"``), a scene or structure file, or a
        :class:`Structure`.
    fixed : dict, optional
        Parameters kept constant in every case (as keyword arguments of :func:`solve`).
    jobs : int, default 1
        Number of worker processes; 1 runs the cases one after the other in this process.  The
        rows are the same either way: every case is solved from scratch, as :func:`solve` solves
        it alone.
    quiet : bool, default False
        Switch off the progress bar (shown on stderr only when it is a terminal).
    dask : str, optional
        Run the cases on Dask: ``"local"`` (a LocalCluster of ``jobs`` worker processes, or one per
        case up to the CPU count) or a scheduler address ``"tcp://host:8786"``; needs
        ``pip install 'femslide[dask]'``.
    **varied : list of values
        The varied parameters, each with a list (tuple, range, numpy array) of values: scene
        parameters (``EI=[1e4, 1e6]``) or structure fields (``**{"right.EI": [1e4, 1e6]}``; a vector
        field takes a list of vectors), or keys of a structure's ``[simulate]`` table
        (``**{"simulate.ground.scale": [0.5, 1, 2], "simulate.ground.record": ["a.AT2", "b.csv"]}``:
        every case is then simulated; also with a ``simulate.KEY`` in ``fixed``).  Several varied
        parameters give the full grid (``itertools.product``, the first name varying slowest).

    Returns
    -------
    pandas.DataFrame
        One row per case in grid order: the varied parameters, ``converged`` (bool), ``status``
        ("converged", "failed", "bad-input" - values rejected only when the case ran, such as a
        work bound that depends on the solution - or "error"), ``reason`` (why a case failed,
        else None), then every scalar value of the result under dotted names
        (``M_max``, ``reactions.B1.Fx``, ``rods.right.M_max``, ``wall_time_s``...; see
        :meth:`Result.flat`; NaN where a case has no value).  A simulation's row: one column per
        flattened peak (``peaks.reactions.A1.Fx``), ``events.JOINT`` (the friction events' count),
        ``error_estimate``.  A case that fails does not stop the
        sweep: its row says why.  ``df.attrs`` holds ``target``, ``varied`` and ``fixed``.

    Raises
    ------
    BadInput
        An unknown parameter, a value out of range (every case is checked before any runs), or a
        varied parameter without a list of values.

    Examples
    --------
    >>> df = femslide.sweep("beam-slider", EI=[1e4, 1e6, 1e8])          # doctest: +SKIP
    >>> df[["EI", "M_max", "reactions.B1.Fx"]]                           # doctest: +SKIP
    """
    from femslide.app.api import sweep_table
    return sweep_table(target, varied, fixed=fixed, jobs=jobs, quiet=quiet, dask=dask)


def __getattr__(name: str):
    """``femslide.plot`` (member diagrams, femslide/output/diagrams.py) is imported on first use, so that
    ``import femslide`` and the command line stay light."""
    if name == "plot":
        from femslide.output.diagrams import plot
        return plot
    raise AttributeError(f"module 'femslide' has no attribute {name!r}")
