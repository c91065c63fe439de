"""The Python API's entry points that are not plain scene runs: ``femslide.simulate`` of a structure.
"""
from __future__ import annotations

import os

from femslide.analysis import transient  # noqa: F401  (sets the BLAS threads before numpy is imported)
from femslide.analysis.simulate import SIM_KEYS, parse_spec, simulate
from femslide.errors import BadInput


def run_api(target, params: dict):
    """``femslide.simulate`` of a Structure, a Frozen structure or a structure file: keyword
    arguments named like the [simulate] keys (t_end, tolerance, damping, ground, initial, elements;
    also as ``**{"simulate.tolerance": 1e-7}``, the command line's form) set or override them;
    ``NAME.FIELD`` ones change the structure (a Structure or a file)."""
    from femslide.app.result import Result
    from femslide.app.structfile import apply, load
    from femslide.model.frozen import Frozen
    from femslide.model.structure import Structure
    table, base = {}, "."
    if isinstance(target, str):
        sf = load(target)
        table = dict(sf.simulate_table or {})
        base = os.path.dirname(os.path.abspath(target))
        target, name = sf.structure, sf.name
    else:
        name = "structure"
    # [simulate] keys, bare or in the command line's --set form simulate.KEY
    sim = {k[len("simulate."):]: params.pop(k) for k in list(params) if k.startswith("simulate.")}
    both = sorted(set(sim) & set(params) & set(SIM_KEYS))
    if both:
        raise BadInput(f"simulate: {both[0]} given both as {both[0]} and as simulate.{both[0]}; allowed: one of them")
    sim.update({k: params.pop(k) for k in list(params) if k in SIM_KEYS})
    table.update(sim)
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
    raw = simulate(fs, spec, name=name)
    res = Result({k: v for k, v in raw.items() if not k.startswith("_")})
    res._writer = raw["_write"]
    res._history_source = raw["_history"]
    return res
