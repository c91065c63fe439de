"""The state a simulation starts from: the statics it is released from, held at its ``initial`` values.

- :func:`stuck_statics`: the static state of a structure that is a mechanism without friction (a
  block on a ground slider without a spring) with its friction joints stuck (a stuck slider holds
  like a weld, a stuck roller like a pin); if every one stuck holds a freedom twice (a rigid block on
  two frictional contacts: the split of their horizontal forces is undetermined), as few of them
  stuck as hold the structure (the first k in declaration order).
- :func:`held_start`: the static state held at ``initial`` (a body's rotation and/or displacement, a
  slider's slide), walked there in small steps; joints named in ``drop`` left out (lifted contacts)
  and the slides of those in ``lock`` locked (contacts with friction, at rest).
- :func:`contact_start`: the held start of a structure with unilateral contacts: which contacts the
  held state lifts (a block tilted about one corner stands on that corner only) is found as the
  first feasible set - every contact kept presses (its normal force -Q >= 0), every contact left out
  has a gap >= 0 - among: those the static state lifted, none, then each one alone.

Units: the model's (lengths by Lref, forces by Fref); ``y`` laid out as the structure's own model
(every joint's multipliers, femslide.model.discrete.Model).
"""
from __future__ import annotations

import math

import numpy as np

from femslide.errors import BadInput, SolverFailure
from femslide.joints.holds import BodyHold, SlideHold
from femslide.joints.kinds import kind_of, listed
from femslide.records import replace

GAP_TOL = 1e-9     # a gap or a pressure below -GAP_TOL (model units) is infeasible


def stuck_statics(fs, exc):
    """Static solution of the structure with its friction joints stuck (each as its kind's ``stuck``
    kind: sliders as welds, rollers as pins, at the same points; see the module docstring);
    SolverFailure (the original reason ``exc``) if that fails too."""
    from femslide.analysis import static
    fric = [j.name for j in fs.joints if j.mu is not None]
    for k in [len(fric)] + list(range(1, len(fric))):
        stuck = set(fric[:k])
        joints = tuple(replace(j, type=kind_of(j.type).stuck, axis=None, k=0.0, preload=0.0, mu=None, mu0=None,
                               bearing=None, unilateral=False, restitution=None) if j.name in stuck else j
                       for j in fs.joints)
        try:
            return static.solve(replace(fs, joints=joints, derived={}))
        except (SolverFailure, BadInput):
            continue
    raise exc from None


def carry(m_from, y, m_to, n_to):
    """y of the model ``m_from`` in the layout of ``m_to`` (n_to unknowns): positions as they are,
    the multipliers of the joints both have by name, the rest 0."""
    z = np.zeros(n_to)
    n_q = m_from.n_q
    z[:n_q] = y[:n_q]
    have = {c.name: c for c in m_from.constraints if getattr(c, "joint_kind", None) is not None}
    for c in m_to.constraints:
        if getattr(c, "joint_kind", None) is not None and c.name in have and c.size:
            i, k = m_from.constraints.index(have[c.name]), m_to.constraints.index(c)
            z[n_q + m_to.c_off[k]:n_q + m_to.c_off[k + 1]] = y[n_q + m_from.c_off[i]:n_q + m_from.c_off[i + 1]]
    return z


def held_start(fs, counts, L, F, y, elements, ini, drop=(), lock=(), full=None):
    """The static state (y, elements) held at the ``initial`` values (model units), walked there in
    small steps, with the joints ``drop`` left out and the slides of ``lock`` locked; y in the
    layout of the structure's own model ``full`` (built when not given)."""
    from femslide.analysis.newton import newton
    from femslide.model.discrete import Model
    full = full or Model(fs, counts, L, F)
    m = Model(fs, counts, L, F, finalize=False)
    if drop:
        m.constraints = [c for c in m.constraints if c.name not in drop]
    for n in lock:
        m.add_constraint(SlideHold(m.joint[n], float(m.joint[n].slide(y[:m.n_q][m.joint[n].dofs])[0]), f"lock {n}"))
    if "body" in ini:
        name = ini["body"]
        if name not in m.body_index:
            raise BadInput(f"[simulate] initial.body = {name!r}: no such body; bodies: "
                           f"{', '.join(m.body_index) or 'none'}")
        b = fs.body(name)
        d = m.body_dof(name)
        r = tuple(np.asarray(b.centroid, float) / L - m.body_X0[m.body_index[name]])
        what, target, e = [], [], (1.0, 0.0)
        if "u" in ini:
            size = math.hypot(*ini["u"])
            if size == 0.0:
                raise BadInput("[simulate] initial.u = [0, 0]: give a nonzero displacement (or leave it out)")
            e = (ini["u"][0] / size, ini["u"][1] / size)
            what.append("u")
            target.append(size / L)
        if "rotation" in ini:
            what.append("rot")
            target.append(ini["rotation"])
        hold = BodyHold(d, r, what, e)
    else:
        name = ini["joint"]
        j = next((j for j in fs.joints if j.name == name), None)
        if j is None or kind_of(j.type).free != "slide":
            raise BadInput(f"[simulate] initial.joint = {name!r}: not a "
                           f"{listed(lambda k: k.free == 'slide', last='or')} of the structure")
        hold = SlideHold(m.joint[name], np.zeros(1), "initial slide", origin=m.slide0[name])
        target = [ini["slide"] / L]
    m.add_constraint(hold)
    m.finalize()
    target = np.array(target)
    z = carry(full, y, m, m.n)
    start = hold.value(z[hold.dofs])
    steps = max(1, int(math.ceil(float(np.abs(target - start).max()) / 0.02)))
    es = elements.copy()
    k = 0
    frac = 0.0
    dfrac = 1.0 / steps
    while frac < 1.0:
        f1 = min(1.0, frac + dfrac)
        hold.target = start + f1 * (target - start)
        z1, info = newton(m, z, es)
        if not info.converged:
            es.revert()
            dfrac *= 0.5
            k += 1
            if k > 30:
                raise SolverFailure(f"the initial state (held at {ini}) could not be reached: {info.reason}")
            continue
        es.commit()
        z, frac = z1, f1
    return carry(m, z, full, full.n), es


def contact_start(fs, counts, L, F, model, y, elements, ini, first=()):
    """The held start of a structure with unilateral contacts (see the module docstring): (y,
    elements, names of the contacts lifted there), y in the layout of ``model`` (the structure's
    own); ``first``: the set tried first (the static state's lifted contacts).  SolverFailure naming
    the contacts when no set tried is feasible."""
    contacts = [j for j in fs.joints if j.unilateral]
    if not contacts:
        y0, e0 = held_start(fs, counts, L, F, y, elements, ini, full=model)
        return y0, e0, ()
    n_q = model.n_q
    tried = []
    tries = [tuple(first)] + [d for d in [()] + [(j.name,) for j in contacts] if d != tuple(first)]
    for drop in tries:
        lock = [j.name for j in contacts if j.name not in drop and j.mu is not None and j.mu0 > 0.0]
        try:
            y0, e0 = held_start(fs, counts, L, F, y, elements, ini, drop, lock, full=model)
        except SolverFailure as exc:
            tried.append(f"{', '.join(drop) or 'none'} lifted: {exc}")
            continue
        bad = []
        for j in contacts:
            link = model.joint[j.name]
            if j.name in drop:
                gap = link.gap(y0[:n_q][link.dofs])
                if gap < -GAP_TOL:
                    bad.append(f"{j.name} would sink {-gap * L:.3g} m into its guide")
            else:
                Q = float(model.multipliers(y0, link)[0])
                if Q > GAP_TOL:
                    bad.append(f"{j.name} would pull with {Q * F:.4g} N")
        if not bad:
            return y0, e0, tuple(drop)
        tried.append(f"{', '.join(drop) or 'none'} lifted: {'; '.join(bad)}")
    raise SolverFailure(f"simulate: no set of contacts holds the initial state {ini} (tried: {' | '.join(tried)})")
