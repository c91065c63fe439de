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
                  error_estimate=sol.error_estimate, notes=notes(sol))
    return Outcome(values, name, solution=sol)


def notes(sol) -> list[str]:
    """What an engineer must know about a converged equilibrium beyond its numbers: an output that the
    refinement could make accurate only to its round-off floor (femslide.analysis.static), a support resting
    on the ground (a pin, roller or slider) that pulls the structure down - it would lift off -, a
    structure reaching below the ground line of its supports (femslide.output.diagrams.notes, which
    the pictures draw in red)."""
    from femslide.output.diagrams import LiftOffWarning, frame_data
    from femslide.output.diagrams import notes as picture_notes
    found = picture_notes(frame_data(sol))
    return list(sol.notes or []) + [text + (" (a support resting on the ground cannot pull: it would lift off; "
                                            "the model holds it down)" if cls is LiftOffWarning else "")
                                    for cls, text in found]
