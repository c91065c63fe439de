"""Unilateral contacts in statics: a contact that would pull is released (SPEC 9.4).

A slider or roller declared ``unilateral`` holds a's point on the +n side of its guide (n = the
axis turned by +90 degrees) only while it presses: its first multiplier Q (the force -Q n on a)
must be <= 0.  :func:`with_contacts` finds the contacts in contact at the solved state by an active
set: solve with every contact holding; release the one that pulls hardest (the structure's frozen
joint marked ``lifted``: it keeps its place in the results with zero force and its spring along the
guide, but holds nothing); solve again; a released contact whose point would sink below its guide
(gap w . n < 0) holds again; until every contact kept presses and every released one has a gap >= 0.
The contact state is that of the full load (decided on the solved equilibrium, not along the load
path).  A structure that does not hold without its lifted contacts fails, naming them.
"""
from __future__ import annotations


from femslide.errors import SolverFailure
from femslide.records import replace

PULL_TOL = 1e-9    # a contact pulls when Q exceeds this fraction of the largest multiplier
GAP_TOL = 1e-12    # a released contact sinks when its gap is below -GAP_TOL (model lengths)


def contacts_of(fs):
    """The names of the unilateral contacts of a frozen structure."""
    return [j.name for j in fs.joints if j.unilateral]


def lifted_as(fs, lifted):
    """The frozen structure with the contacts ``lifted`` (names) released and every other one
    holding."""
    return replace(fs, joints=tuple(replace(j, lifted=j.name in lifted) if j.unilateral else j for j in fs.joints),
                   derived={})


def gap(model, name, y):
    """The gap w . n [model lengths] of contact ``name`` at y (also when it is released)."""
    link = model.joint[name]
    return link.gap(y[:model.n_q][link.dofs])


def with_contacts(fs, solve_one):
    """The static solution (``solve_one(frozen structure)``, femslide.analysis.static) with every
    unilateral contact either pressing or released with a gap >= 0 (module docstring).  The
    solution's ``lifted`` lists the released contacts and its ``notes`` say so."""
    names = contacts_of(fs)
    lifted = {j.name for j in fs.joints if j.unilateral and j.lifted}
    seen = set()
    for _ in range(2 * len(names) + 2):
        key = frozenset(lifted)
        if key in seen:
            break
        seen.add(key)
        try:
            sol = solve_one(lifted_as(fs, lifted))
        except SolverFailure as exc:
            if not lifted:
                raise
            raise SolverFailure(f"statics: without the contact(s) {', '.join(sorted(lifted))} (lifted: they would "
                                f"pull) the structure does not hold: {exc}", getattr(exc, "history", None)) from None
        m, y = sol.level.model, sol.level.y
        mult = y[m.n_q:m.n]
        scale = float(abs(mult).max()) if mult.size else 0.0
        pulls = [(float(m.multipliers(y, m.joint[n])[0]), n) for n in names if n not in lifted]
        pulls = [(Q, n) for Q, n in pulls if Q > PULL_TOL * scale]
        sinks = [(gap(m, n, y), n) for n in lifted]
        sinks = [(g, n) for g, n in sinks if g < -GAP_TOL]
        if not pulls and not sinks:
            sol.lifted = sorted(lifted)
            if lifted:
                sol.notes = list(sol.notes or []) + [
                    f"contact {n} lifted off: it would pull, so it holds nothing (gap {gap(m, n, y) * m.Lref:.4g} m)"
                    for n in sorted(lifted)]
            return sol
        if pulls:
            lifted.add(max(pulls)[1])
        else:
            lifted.discard(min(sinks)[1])
    raise SolverFailure(f"statics: no consistent set of contacts found among {', '.join(names)} (each contact "
                        f"kept would pull, or each released would sink)")
