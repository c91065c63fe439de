"""The result of a run, as users get it from the Python API: :class:`Result`.

A dict holding the JSON object of the contract (what ``solve --json`` / ``simulate --json`` print)
plus arrays along rods, the time history and files on request; :func:`dotted`, :func:`clean` and
:func:`fmt` turn results into table rows, JSON and text.
"""
from __future__ import annotations

import json
import math
import os
from typing import TYPE_CHECKING

from femslide.errors import BadInput
from femslide.results.outcome import dotted  # noqa: F401  (the one flattener; app.result.dotted)

if TYPE_CHECKING:
    import pandas

    from femslide.analysis.static import Solution


ROD_COLUMNS = ("s", "x", "y", "u", "v", "theta", "N", "V", "M")
UNITS = {"s": "m", "x": "m", "y": "m", "u": "m", "v": "m", "theta": "rad", "N": "N", "V": "N", "M": "N m"}


class Result(dict):
    """The result of a run: a dict of named values, plus arrays, a time history and files.

    As a dict it is the JSON object that ``femslide solve --json`` / ``simulate --json`` print (SI
    units): ``r["M_max"]``, ``r["reactions"]["B1"]["Fx"]``, ``r["rods"]["right"]["M_max"]`` (declared
    structures).  Moments and rotations are counter-clockwise positive, reactions are forces of the
    ground on the structure; the built-in paper scenes report ``phi`` > 0 when the body leans towards
    B1 (clockwise), as in the paper.  Private keys (starting with ``_``) never appear.

    Beyond the dict:

    - FE statics (a declared structure, a structure file, the ``beam-*`` and ``cantilever-*``
      scenes): :meth:`rod` (arrays along a rod), :meth:`joint`, :meth:`body` (values by name, also
      for the scenes, whose dict holds only the paper's values), :meth:`parts`;
    - simulations: :attr:`history`, the time history as arrays;
    - every result: :meth:`flat` (dotted names to scalars), :meth:`to_dataframe`, :meth:`write`.

    Attributes
    ----------
    solution : femslide.analysis.static.Solution or None
        The converged static solution behind an FE statics result (None otherwise): its finest mesh
        ``solution.level`` (model, state, raw per-rod arrays) and how the load path was followed.
    """

    _outcome = None
    _history = None

    @classmethod
    def of(cls, outcome) -> "Result":
        """The result of a run's :class:`femslide.results.outcome.Outcome` (or of a plain dict of
        values: the spring-hinge scenes)."""
        from femslide.results.outcome import Outcome
        if not isinstance(outcome, Outcome):
            outcome = Outcome(dict(outcome))
        res = cls({k: v for k, v in outcome.values.items() if not str(k).startswith("_")})
        res._outcome = outcome
        return res

    @property
    def solution(self) -> Solution | None:
        return self._outcome.solution if self._outcome is not None else None

    def combination(self, name: str) -> "Result":
        """The result of one load combination (structures with combinations): the values of
        ``self["combinations"][name]`` with its solution behind them (:meth:`rod`, :meth:`write`...).

        Raises
        ------
        femslide.BadInput
            An unknown combination, or a result without combinations.
        """
        from femslide.results.outcome import Outcome
        combos = self.get("combinations")
        if not isinstance(combos, dict) or name not in combos:
            raise BadInput(f"no combination named {name!r}; combinations: "
                           f"{', '.join(combos) if isinstance(combos, dict) else '(none)'}")
        sol = self._outcome.solutions.get(name) if self._outcome is not None else None
        base = self._outcome.name if self._outcome is not None else "structure"
        return Result.of(Outcome(dict(combos[name]), f"{base}_{name}", solution=sol))

    # -- FE statics: values by name --------------------------------------------------------------
    def _named(self) -> dict:
        """The section-8 values (bodies, rods, joints, reactions) of an FE statics result."""
        if self.solution is None:
            raise BadInput("this result has no rods, joints or bodies by name (only FE statics results "
                           "have them: declared structures, structure files and the beam-*/cantilever-* "
                           "scenes); its values are the dict's keys: " + ", ".join(map(str, self)))
        return self.solution.result

    def parts(self) -> dict:
        """Names of the rods, bodies and joints of an FE statics result.

        Returns
        -------
        dict
            ``{"rods": [...], "bodies": [...], "joints": [...]}``, in declaration order.  The paper
            scenes name theirs too: beam-slider has the rod ``right``, the body ``deck`` and the
            joints ``A1``, ``B1`` (ground pins) and ``clamp`` (the sliding clamp).

        Raises
        ------
        femslide.BadInput
            When the result is not an FE statics result (spring-hinge model, simulation).
        """
        named = self._named()
        return {k: list(named[k]) for k in ("rods", "bodies", "joints")}

    def rod(self, name: str) -> dict:
        """Arrays along a rod, at its nodes, from its ``start`` to its ``end`` (SI units).

        Parameters
        ----------
        name : str
            The rod's name (see :meth:`parts`).

        Returns
        -------
        dict
            numpy arrays ``s`` (arc length from ``start`` in the undeformed rod [m]), ``x``, ``y``
            (deformed node positions [m]), ``u``, ``v`` (displacements [m], global), ``theta``
            (rotation [rad], counter-clockwise), ``N`` (axial force [N], tension > 0), ``V`` (shear
            force [N]) and ``M`` (bending moment [N m], M = EI dtheta/ds, dM/ds = V); and the floats
            ``M_max``, ``N_max``, ``V_max`` (largest absolute values along the rod, M_max including
            element-interior extrema).  At a cut at s the part beyond exerts on the part before the
            force N t - V n and the moment M (t the tangent, n = t turned by +90 degrees).  These
            are the raw values on the finest mesh; the dict's scalar values may be extrapolated
            from the two finest meshes and so differ from them by about ``r["error_estimate"]``.
            The arrays are copies: changing them changes nothing in the result.

        Raises
        ------
        femslide.BadInput
            An unknown rod name, or a result without rods.
        """
        self._named()  # BadInput without rods
        arrays = self.solution.level.arrays
        if name not in arrays:
            raise BadInput(f"no rod named {name!r}; rods: {', '.join(arrays) or '(none)'}")
        return {k: (v.copy() if hasattr(v, "copy") else v) for k, v in arrays[name].items()}

    def joint(self, name: str) -> dict:
        """Force, moment and motion of a joint (SI units).

        Parameters
        ----------
        name : str
            The joint's name (see :meth:`parts`).

        Returns
        -------
        dict
            ``Fx``, ``Fy`` [N] and ``M`` [N m]: the force and moment that part b exerts on part a at
            the joint point (global components, springs included); sliders and rollers add ``slide``
            [m] (displacement of a along the axis), pins add ``rotation`` [rad] (a relative to b).
            For a joint with the ground (b = ``"ground"``) this is the reaction: the force of the
            ground on the structure.

        Raises
        ------
        femslide.BadInput
            An unknown joint name, or a result without joints.
        """
        joints = self._named()["joints"]
        if name not in joints:
            raise BadInput(f"no joint named {name!r}; joints: {', '.join(joints) or '(none)'}")
        return dict(joints[name])

    def body(self, name: str) -> dict:
        """Position of a rigid body now: ``x``, ``y`` of its centroid [m] and its ``rotation`` [rad].

        Parameters
        ----------
        name : str
            The body's name (see :meth:`parts`).

        Raises
        ------
        femslide.BadInput
            An unknown body name, or a result without bodies.
        """
        bodies = self._named()["bodies"]
        if name not in bodies:
            raise BadInput(f"no body named {name!r}; bodies: {', '.join(bodies) or '(none)'}")
        return dict(bodies[name])

    # -- simulations -----------------------------------------------------------------------------
    @property
    def history(self) -> dict | None:
        """The time history of a simulation as numpy arrays of equal length, or None (statics).

        Always ``t`` [s] first, then every reported quantity, sampled as the ``history.csv`` that
        :meth:`write` writes (the exact oscillator: uniformly, 64 samples per shortest period, plus
        the events; the FE dynamics: every accepted step of the integrator):

        - one-mass oscillator (``sdof-*``): ``w`` [m] (displacement relative to the base), ``v``
          [m/s], ``state`` (+1/-1 sliding direction, 0 stuck), ``F`` [N] (applied force), ``f`` [N]
          (friction force in m w'' + c_v w' + k w + f = F: mu N sgn(w') while sliding, F - k w while
          stuck; the force of friction on the mass is -f);
        - structure scenes (``beam-oscillation``, ``beam-friction``): ``phi`` [rad] (> 0 leaning
          towards B1), ``phi_dot`` [rad/s], ``slide`` [m], ``stuck`` (1 stuck, 0 sliding or free),
          ``F_ax`` [N] (force along the guide), ``N`` [N] (magnitude of the transverse clamp force),
          ``F1``, ``N1`` and ``F2``, ``N2`` [N] (forces of the ground at A1 and B1, global x and y);
        - structure files and declared structures: the columns of simulate's history
          (femslide.analysis.simulate: ``reactions.NAME.Fx``, ..., ``bodies.NAME.rotation_rate``, ...).

        Computed from the stored solution when first asked for, then kept.
        """
        if self._history is None and self._outcome is not None:
            h = self._outcome.get_history()
            if h is not None:
                self._history = {k: h[k] for k in ["t"] + [k for k in h if k != "t"]}
        return self._history

    # -- tables and files ------------------------------------------------------------------------
    def flat(self) -> dict:
        """The scalar values of the result under dotted names, as a sweep's row holds them.

        Returns
        -------
        dict
            ``{"M_max": ..., "reactions.B1.Fx": ..., "rods.right.start.u": ...}``: nested dicts
            flattened with dots, numpy numbers as floats, NaN and inf as None; lists (turning
            points, files) are left out.
        """
        return dotted(clean(self))

    def to_dataframe(self) -> pandas.DataFrame:
        """The result as a :class:`pandas.DataFrame`.

        - FE statics (a result with rods): one row per rod node, columns ``rod`` (its name),
          ``node`` (0 at the rod's start), then ``s``, ``x``, ``y``, ``u``, ``v``, ``theta``, ``N``,
          ``V``, ``M`` as in :meth:`rod`;
        - simulations: one row per time sample, the columns of :attr:`history` (``t`` first);
        - anything else (the spring-hinge models): one row of :meth:`flat`.

        The units of the columns are in ``df.attrs["units"]``.
        """
        import numpy as np
        import pandas as pd
        if self.solution is not None and self.solution.level.arrays:
            parts = []
            for name, a in self.solution.level.arrays.items():
                n = len(a["s"])
                cols = {"rod": np.full(n, name, dtype=object), "node": np.arange(n)}
                cols.update({k: np.asarray(a[k], float) for k in ROD_COLUMNS})
                parts.append(pd.DataFrame(cols))
            df = pd.concat(parts, ignore_index=True)
            df.attrs["units"] = {"node": "-", **UNITS}
            return df
        h = self.history
        if h is not None:
            df = pd.DataFrame(h)
            df.attrs["units"] = {k: HISTORY_UNITS.get(k, "-") for k in h}
            return df
        return pd.DataFrame([self.flat()])

    def write(self, out_dir: str) -> list:
        """Write the run's files into the folder ``out_dir`` (created if needed).

        FE statics: a VTU file of the deformed structure (rods with u, v, theta, N, V, M; bodies as
        polygons) and its sidecar JSON; simulations: ``history.csv`` (and, for the structure scenes,
        a PVD series of VTU frames); every result: ``result.json``, the dict as JSON (with the list
        of files under ``"files"``).

        Parameters
        ----------
        out_dir : str or os.PathLike
            The folder.

        Returns
        -------
        list of str
            The paths written, ``result.json`` last.

        Raises
        ------
        femslide.BadInput
            When ``out_dir`` cannot be written.
        """
        from femslide.app.outputs import check_out_dir
        out_dir = os.fspath(out_dir)
        check_out_dir(out_dir, "out_dir")
        from femslide.output.files import write
        files = write(self._outcome, out_dir) if self._outcome is not None else []
        path = os.path.join(out_dir, "result.json")
        with open(path, "w") as fh:
            json.dump(clean({**self, "files": files}), fh, indent=1)
        return files + [path]


HISTORY_UNITS = {"t": "s", "w": "m", "v": "m/s", "state": "-", "F": "N", "f": "N", "phi": "rad",
                 "phi_dot": "rad/s", "slide": "m", "stuck": "-", "F_ax": "N", "N": "N", "F1": "N",
                 "N1": "N", "F2": "N", "N2": "N"}


def clean(obj):
    """JSON-safe copy: numpy scalars to float, non-finite floats to null, private keys dropped."""
    t = type(obj)
    if t is float:   # (the common leaf first: a result is mostly floats)
        return obj if math.isfinite(obj) else None
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


VALUE_UNITS = {"N m": ("M_max", "M", "T", "M_min"),
         "N": ("Fx", "Fy", "N_max", "V_max", "F2_max", "normal", "friction", "F_ax", "F1", "F2", "N1", "N2",
               "Fx_min", "Fx_max", "Fy_min", "Fy_max", "force"),
         "m": ("x", "y", "u", "v", "slide", "slide_min", "slide_max", "gap", "gap_max", "s_M_max", "s_N_max",
               "s_V_max"),
         "rad": ("theta", "rotation", "phi", "psi", "phi0"),
         "rad/s": ("rotation_rate", "omega", "phi_dot"),
         "s": ("wall_time_s", "import_time_s", "integration_time_s", "t_end", "t", "period", "periods_s",
               "stuck_time"),
         "Hz": ("frequencies_hz",),
         "J": ("kinetic", "potential", "dissipated", "work_in", "jump_loss")}
_UNIT_OF = {k: u for u, keys in VALUE_UNITS.items() for k in keys}


def unit_of(path: str) -> str:
    """The SI unit of a value of a result by its dotted name (``reactions.A1.Fx`` -> "N"), "" for
    counts, flags and relative values (error_estimate, energy_balance) and where a key means different
    things (``w`` is a length of the one-mass oscillator, an angle of the structure scenes)."""
    parts = path.split(".")
    if parts == ["theta"]:   # the one-mass oscillator's forcing frequency (theta t)
        return "rad/s"
    if parts[-1] in ("stop", "turning_points"):
        return ""
    return _UNIT_OF.get(parts[-1], "")


def fmt(v):
    """A value as the plain-text output prints it."""
    if isinstance(v, float):
        return f"{v:.10g}"
    if v is None:
        return "-"
    return str(v)
