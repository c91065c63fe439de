"""A declared structure's own runs, as outcomes: its statics (SPEC section 8).

The structure file targets (femslide.app.structfile) and the Python API (``femslide.solve`` of a
Structure) run a frozen structure's statics here; its dynamics and modes are
femslide.analysis.simulate's ``simulate`` and ``natural_modes``.
"""
from __future__ import annotations

from femslide.results.outcome import Outcome


def statics(fs, elements=None, name="structure", cache=None) -> Outcome:
    """Static equilibrium of a frozen structure: the section 8 values, with the solution behind them
    (its VTU on request).  ``elements``: a fixed mesh for every rod; ``cache``: patterns shared with
    other solves of one topology (a sweep)."""
    from femslide.analysis import static
    sol = static.solve(fs, elements=elements, cache=cache)
    res = sol.result
    values = dict(converged=True, M_max=res["M_max"], bodies=res["bodies"], rods=res["rods"],
                  joints=res["joints"], reactions=res["reactions"], iterations=sol.iterations,
                  error_estimate=sol.error_estimate)
    return Outcome(values, name, solution=sol)
