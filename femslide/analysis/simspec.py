"""The ``[simulate]`` table of a structure file, checked: :class:`Spec` and :func:`parse_spec` (every
key named in its error with its allowed range), :func:`parse_elements` (simulate and modes read it).
Keys (SI): ``t_end`` [s], ``tolerance`` (1e-12 .. 1e-2), ``damping`` {alpha [1/s], beta [s],
rotation {BODY: c [N m s/rad]}}, ``ground`` (femslide.analysis.excitation), ``initial`` {body,
rotation [rad], u [m]} or {joint, slide [m]}, ``elements``, ``error_estimate`` (true/false),
``max_time`` [s] (the user's wall-time limit; default none: SPEC 9.2).  The run itself is
femslide.analysis.simulate.
"""
from __future__ import annotations

import math

from femslide.analysis.excitation import Ground
from femslide.analysis.excitation import parse as parse_ground
from femslide.errors import BadInput
from femslide.records import dataclass

DEFAULT_ELEMENTS = 8
MAX_SAMPLES = 1e7   # rows of a sampled history at most (output_interval)
SIM_KEYS = ("t_end", "tolerance", "damping", "ground", "initial", "elements", "error_estimate", "max_time",
            "output_interval")


@dataclass
class Spec:
    t_end: float = 1.0
    tolerance: float = 1e-6
    alpha: float = 0.0
    beta: float = 0.0
    ground: Ground | None = None
    initial: dict | None = None
    elements: int = DEFAULT_ELEMENTS
    rotation_damping: dict | None = None   # {body name: c [N m s/rad]}: rotational dashpots
    turning: tuple = ()                   # bodies whose rotation rate's zeros are located (turning points)
    estimate: bool = True                 # a check run at CHECK_FACTOR * tolerance gives error_estimate
    #                                       (beside the run where it can: femslide.analysis.forked)
    max_time: float | None = None         # the user's wall-time limit [s] of the run (None: none)
    output_interval: float | None = None  # the history's rows at multiples of this [s] (None: every step)


def _num(where, x, lo, hi, lo_open=False):
    if isinstance(x, (str, bool)):   # one rule for every number of a file: text and true/false are not numbers
        raise BadInput(f"{where} = {x!r} is not a number; allowed: a number in [{lo:g}, {hi:g}] (without quotes)")
    try:
        v = float(x)
    except (TypeError, ValueError):
        raise BadInput(f"{where} = {x!r} is not a number; allowed: [{lo:g}, {hi:g}]") from None
    if not math.isfinite(v) or v < lo or v > hi or (lo_open and v == lo):
        raise BadInput(f"{where} = {x!r}; allowed: {'(' if lo_open else '['}{lo:g}, {hi:g}]")
    return v


def parse_spec(table, base_dir=".", where="[simulate]") -> Spec:
    """A :class:`Spec` from a structure file's ``[simulate]`` table (see the module docstring)."""
    if table is None:
        raise BadInput(f"{where}: a structure file needs a [simulate] table (t_end, tolerance, ...) to be simulated")
    if not isinstance(table, dict):
        raise BadInput(f"{where}: must be a table")
    bad = sorted(set(table) - set(SIM_KEYS))
    if bad:
        raise BadInput(f"{where}: unknown key {bad[0]!r}; allowed: {', '.join(SIM_KEYS)}")
    sp_ = Spec()
    sp_.t_end = _num(f"{where} t_end", table.get("t_end", 1.0), 0.0, 1e7, lo_open=True)
    sp_.tolerance = _num(f"{where} tolerance", table.get("tolerance", 1e-6), 1e-12, 1e-2)
    damp = table.get("damping", {}) or {}
    if not isinstance(damp, dict) or set(damp) - {"alpha", "beta", "rotation"}:
        raise BadInput(f"{where} damping: a table {{alpha = ..., beta = ...}} (Rayleigh, C = alpha M + beta K) "
                       f"and/or rotation = {{BODY = c}} (rotational dashpots, N m s/rad)")
    sp_.alpha = _num(f"{where} damping.alpha", damp.get("alpha", 0.0), 0.0, 1e6)
    sp_.beta = _num(f"{where} damping.beta", damp.get("beta", 0.0), 0.0, 1e3)
    rot = damp.get("rotation")
    if rot is not None:
        if not isinstance(rot, dict):
            raise BadInput(f"{where} damping.rotation: a table {{BODY = c}} (c in N m s/rad)")
        sp_.rotation_damping = {str(k): _num(f"{where} damping.rotation.{k}", c, 0.0, 1e12) for k, c in rot.items()}
    sp_.ground = parse_ground(table.get("ground"), base_dir, f"{where} ground")
    ini = table.get("initial")
    if ini is not None:
        if not isinstance(ini, dict):
            raise BadInput(f"{where} initial: a table {{body, rotation, u}} or {{joint, slide}}")
        if "body" in ini:
            bad = sorted(set(ini) - {"body", "rotation", "u"})
            if bad or not ({"rotation", "u"} & set(ini)):
                raise BadInput(f"{where} initial: a body's hold needs rotation [rad] and/or u = [dx, dy] [m] "
                               f"(and nothing else{'; got ' + bad[0] if bad else ''})")
            ini = dict(ini)
            if "rotation" in ini:
                ini["rotation"] = _num(f"{where} initial.rotation", ini["rotation"], -math.pi, math.pi)
            if "u" in ini:
                u = ini["u"]
                if not isinstance(u, (list, tuple)) or len(u) != 2:
                    raise BadInput(f"{where} initial.u = {u!r}; allowed: [dx, dy] in m")
                ini["u"] = [_num(f"{where} initial.u", x, -1e6, 1e6) for x in u]
        elif "joint" in ini:
            if set(ini) != {"joint", "slide"}:
                raise BadInput(f"{where} initial: a joint's hold is {{joint = NAME, slide = VALUE [m]}}")
            ini = {"joint": ini["joint"], "slide": _num(f"{where} initial.slide", ini["slide"], -1e6, 1e6)}
        else:
            raise BadInput(f"{where} initial: name a body (rotation, u) or a slider/roller joint (slide)")
    sp_.initial = ini
    est = table.get("error_estimate", True)
    if not isinstance(est, bool):
        raise BadInput(f"{where} error_estimate = {est!r}; allowed: true (a check run at 10 x tolerance, "
                       f"about +60 % work) or false")
    sp_.estimate = est
    if table.get("max_time") is not None:
        sp_.max_time = _num(f"{where} max_time", table["max_time"], 0.0, 1e9, lo_open=True)
    if table.get("output_interval") is not None:
        sp_.output_interval = _num(f"{where} output_interval", table["output_interval"], 0.0, sp_.t_end,
                                   lo_open=True)
        if sp_.t_end / sp_.output_interval > MAX_SAMPLES:
            raise BadInput(f"{where} output_interval = {sp_.output_interval:g} s gives more than {MAX_SAMPLES:g} "
                           f"rows over t_end = {sp_.t_end:g} s; allowed: [{sp_.t_end / MAX_SAMPLES:g}, "
                           f"{sp_.t_end:g}] s")
    n = parse_elements(table, where)
    if n is not None:
        sp_.elements = n
    return sp_


def parse_elements(table, where="[simulate]"):
    """The table's ``elements`` (elements per rod without its own mesh): an integer in [1, 512], or
    None when absent; BadInput naming it otherwise (simulate and modes read it)."""
    if not isinstance(table, dict) or "elements" not in table:
        return None
    n = table["elements"]
    if isinstance(n, bool) or not isinstance(n, (int, float)) or n != int(n) or not 1 <= n <= 512:
        raise BadInput(f"{where} elements = {n!r}; allowed: an integer in [1, 512]")
    return int(n)
