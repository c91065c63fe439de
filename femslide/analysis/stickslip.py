"""Coulomb friction joints and unilateral contacts in time: their modes, event location and switches.

:class:`Friction` holds the friction joints and the contacts (``unilateral`` sliders and rollers) of a
model (femslide.joints.friction: the Coulomb law and the gap of one joint) and their modes: a friction
mode (0 stuck, +-1 slipping, FREE when no friction acts: a frictionless contact, or a lifted one) and
whether a contact is lifted; a model per set of stuck joints (a stuck joint's slide is locked by an
exact constraint, femslide.joints.holds.SlideHold) and a step system per set of modes (a lifted
contact's multipliers are released: held at 0 instead of its equations, so that the layout stays);
the event functions, two per joint: the friction slot (slip velocity sigma s', or the static margin
mu0 N - |lam|) and the contact slot (the pressure -Q while in contact, the gap w . n while lifted);
and the events recorded.  The integrator locates an event inside a step
(femslide.analysis.events.locate_step); :func:`_switch` changes modes: :func:`_settle` (the stick
test on the consistent start's lock multiplier), :func:`_lift` (a contact that would pull lets go)
and :func:`_land` (a contact whose gap closes: an impact, :func:`_impact`).  At every change the
massless parts are re-solved for equilibrium in the new modes (:func:`_requilibrate`), the energy
their jump releases (and the kinetic energy an impact takes) counted as dissipated.
"""
from __future__ import annotations

import numpy as np

from femslide.analysis.radau import NEWTON_TOL, consistent_start, constraint_gradient
from femslide.errors import SolverFailure
from femslide.joints.friction import FrictionJoint
from femslide.joints.holds import SlideHold
from femslide.model.linalg import add_coo, complement, solve_linear
from femslide.model.state import ElementState, MotionState


SAME_INSTANT = 1e-9   # s (relative to max(1, t)): events this close are one instant (events are
                      # located to ~1e-12 s; two of them at one physical instant land within this)
FREE = 2              # the friction mode of a joint on which no friction acts (frictionless, or lifted)


class Friction:
    """The friction joints and contacts of a model and their modes (friction: 0 stuck, +-1 slipping,
    FREE; contacts: lifted or not), the step systems of each set of modes, the event functions and
    the mode switches.  ``lifted``: the names of the contacts lifted at the start."""

    def __init__(self, model, joints, make_system, counts, lifted=()):
        from femslide.model.discrete import Model
        from femslide.model.patterns import PatternCache
        self.base = model
        self.joints = [FrictionJoint(model, j) for j in joints]
        self.make_system = make_system      # (model, extras, released) -> a step system (femslide.analysis.radau)
        self.counts = counts
        self._Model, self._cache = Model, PatternCache()
        self._models = {(): model}
        self.lifted = [fj.unilateral and fj.name in lifted for fj in self.joints]
        self.mode = [0 if fj.friction and not up else FREE for fj, up in zip(self.joints, self.lifted)]
        self.stick_at = [0.0] * len(self.joints)
        self.events = {fj.name: [] for fj in self.joints}
        self.last = [None] * len(self.joints)   # (t, kind) of each joint's last switch
        self.size = 2 * len(self.joints)    # event slots: 2 i friction, 2 i + 1 contact
        self.v_landing = [0.0] * len(self.joints)   # the largest approach speed of each contact's landings
        self.tolerance = 0.0                # the run's tolerance: a rebound below it (relative) is plastic
        self.resolution = 0.0               # [s] the resolution of event times (set by the integration)
        self.touches = []                   # touches of the breakaway bound not listed as events (event)
        self.pooled = {}                    # {stuck joint whose lock is redundant: the joint carrying it}
        self._systems = {}

    # -- models and systems ------------------------------------------------------------------------
    def stuck(self):
        return tuple(i for i, m in enumerate(self.mode) if m == 0)

    def _model(self, stuck):
        m = self._models.get(stuck)
        if m is None:
            b = self.base
            m = self._Model(b.structure, self.counts, b.Lref, b.Fref, self._cache, finalize=False)
            m.locks = []
            for i in stuck:
                fj = self.joints[i]
                lock = SlideHold(m.joint[fj.name], 0.0, f"lock {fj.name}")
                m.add_constraint(lock)
                m.locks.append(lock)
            m.finalize()
            self._models[stuck] = m
        return m

    def stuck_model(self):
        """The model with every friction joint stuck."""
        return self._model(tuple(i for i, fj in enumerate(self.joints) if fj.friction))

    def released(self):
        """The multiplier indices (among n_c) of the lifted contacts."""
        n_q = self.base.n_q
        rows = [fj.mu_idx - n_q for fj, up in zip(self.joints, self.lifted) if up]
        return np.concatenate(rows).astype(np.intp) if rows else np.zeros(0, np.intp)

    def system(self, y=None):
        """The step system of the current modes (lock targets set).  With the state ``y`` (in the
        current modes' layout) the locks that hold nothing the others do not - two stuck contacts
        under one rigid body - are found first (:meth:`_pool`)."""
        stuck = self.stuck()
        if y is not None:
            self._pool(y)
        else:   # (the pooling of the last state, while its joints are still stuck)
            self.pooled = {j: c for j, c in self.pooled.items() if j in stuck and (c is None or c in stuck)}
        key = (tuple(self.mode), tuple(self.lifted), tuple(sorted(self.pooled)))
        sysm = self._systems.get(key)
        if sysm is None:
            m = self._model(stuck)
            extras = [fj.slip(mo) for fj, mo in zip(self.joints, self.mode) if mo in (1, -1)]
            rel = self.released()
            if self.pooled:   # (a pooled joint's lock is released: its share is carried by another)
                rel = np.concatenate([rel, [self.base.n_c + stuck.index(j) for j in sorted(self.pooled)]])
            sysm = self._systems[key] = self.make_system(m, extras, rel.astype(np.intp))
        m = sysm.model
        for lock, i in zip(getattr(m, "locks", []), stuck):
            lock.target = self.stick_at[i]
        return sysm

    def _pool(self, y):
        """Which stuck locks are redundant at y: a lock whose constraint gradient is a combination
        of the others' (the joints' own equations and the locks before it: a rigid block standing
        on two stuck contacts has four equations for three freedoms).  Such a lock is released and
        its joint pooled with the kept lock that carries most of it: the split of the friction
        force between them is undetermined (rigid-body statics), the kept one carries it all and
        holds while it is within the sum of their static friction (mu0 N) - the pooled joints slide
        together.  A lock that the joints' own equations make redundant holds nothing (carrier
        None).  Sets ``self.pooled`` {pooled joint: carrying joint or None}."""
        self.pooled = {}
        stuck = self.stuck()
        if len(stuck) < 2:
            return
        m = self._model(stuck)
        n_q, nc0 = self.base.n_q, self.base.n_c
        # (the lock targets of the current modes: the gradient does not depend on them)
        _, coo, _ = m.system(y, ElementState.zero(m.elements.size if m.elements is not None else 0),
                             1.0, None, True, dense="coo")
        G = constraint_gradient(coo, n_q, m.n_c, self.released())
        keep = set(_independent_rows(G).tolist())
        for k, j in enumerate(stuck):
            if nc0 + k in keep:
                continue
            kept = [nc0 + kk for kk in range(len(stuck)) if nc0 + kk in keep]
            if not kept:   # (the joints' own equations already fix its slide: friction has nothing to hold)
                self.pooled[j] = None
                continue
            A = G[sorted(keep)].T
            coef = np.linalg.lstsq(A, G[nc0 + k], rcond=None)[0]
            share = {row: abs(c) for row, c in zip(sorted(keep), coef) if row in kept}
            self.pooled[j] = stuck[max(share, key=share.get) - nc0]

    def lock_multiplier(self, y, i):
        """Multiplier of joint i's lock in y of the current modes."""
        stuck = self.stuck()
        k = stuck.index(i)
        return float(y[self.base.n + k])

    def convert(self, y, old_stuck, new_stuck):
        """y of the modes ``old_stuck`` -> y of ``new_stuck`` (lock multipliers kept, new ones 0)."""
        n = self.base.n
        vals = dict(zip(old_stuck, y[n:]))
        return np.concatenate([y[:n], [vals.get(i, 0.0) for i in new_stuck]])

    # -- events -------------------------------------------------------------------------------------
    def event(self, i, t, kind):
        """Record joint i's new mode at t; a repeat of the joint's last event is not recorded (the
        stick test may confirm a slip direction twice: at one instant, or a hair after a slip's start
        whose velocity moved the wrong way by round-off).  A stuck joint that slips and sticks again
        within the resolution of event times (``resolution`` [s]: the shortest step the event
        locator takes) only touched its breakaway bound: neither is recorded (a margin mu0 N - |T|
        that grazes zero, which an error below the tolerance decides; as a stop that breaks away at
        once records neither); they are kept in ``touches`` [(joint index, t of the slip, t of the
        stick)] for what counts switches (the step allowance, the chatter guard, the peaks' breaks)."""
        ev = self.events[self.joints[i].name]
        self.last[i] = (t, kind)   # (the joint's last switch, recorded or not: fresh)
        if (kind == "stick" and len(ev) > 1 and ev[-1]["kind"].startswith("slip") and ev[-2]["kind"] == "stick"
                and t - ev[-1]["t"] <= 1.5 * max(self.resolution, SAME_INSTANT * max(1.0, abs(t)))):
            self.touches.append((i, ev.pop()["t"], t))
            return
        if not ev or ev[-1]["kind"] != kind:   # (a repeat: the joint re-tested into the mode it was in)
            ev.append({"t": t, "kind": kind})

    def phi(self, y, v):
        """Event functions, two per joint (positive while the mode holds): sigma s' when slipping,
        mu0 N - |lam| when stuck (1 when free); a contact's pressure -Q, or its gap while lifted (1
        for a two-sided joint)."""
        q = y[:self.base.n_q]
        out = np.ones(self.size)
        for i, (fj, mo) in enumerate(zip(self.joints, self.mode)):
            if mo in (1, -1):
                out[2 * i] = mo * fj.slide_rate(q, v)[1]
            elif mo == 0:
                out[2 * i] = self.holding(i, y)
            if fj.unilateral:
                out[2 * i + 1] = fj.gap(q)[0] if self.lifted[i] else fj.pressure(y)
        return out

    def fresh(self, k, t):
        """Whether event slot k changed its joint's mode at t (its last event, within SAME_INSTANT):
        the friction slot of a joint that has just started to slip, the contact slot of one that has
        just lifted or landed (a function just located at zero is not late at that instant)."""
        i, what = divmod(k, 2)
        last = self.last[i]
        if last is None or abs(last[0] - t) > SAME_INSTANT * max(1.0, abs(t)):
            return False
        if what == 0:
            return self.mode[i] in (1, -1)
        return last[1] in ("lift", "land")

    def flight_step(self, s, fresh):
        """The longest step [s] that resolves the flights just begun at the state s (``fresh``: the
        event slots that changed modes at s.t): a contact that rebounded with the normal velocity
        v > 0 and falls back with the normal acceleration a < 0 lands after 2 v / |a|; a step of a
        quarter of that finds the landing (a whole flight inside one step would be missed)."""
        out = np.inf
        n_q = self.base.n_q
        q = s.y[:n_q]
        for i, fj in enumerate(self.joints):
            if not (fj.unilateral and self.lifted[i] and fresh[2 * i + 1]):
                continue
            v, a = fj.gap_rates(q, s.v, s.acc)
            if v <= 0.0:
                continue
            if a < 0.0:
                out = min(out, 0.5 * v / -a)
        return out

    def holding(self, i, y):
        """Stuck joint i's margin mu0 N - |lam|: >= 0 while static friction holds (with the joints
        pooled with it, :meth:`_pool`: the sum of their mu0 N; a pooled joint itself: 1)."""
        if i in self.pooled:
            return 1.0
        N, _ = self.joints[i].normal(y)
        margin = self.joints[i].mu0 * N
        for j, c in self.pooled.items():
            if c == i:
                margin += self.joints[j].mu0 * self.joints[j].normal(y)[0]
        return margin - abs(self.lock_multiplier(y, i))

    def power(self, y, v):
        """Friction power dissipated (model units), sum of mu N |s'| over the slipping joints."""
        q = y[:self.base.n_q]
        P = 0.0
        for fj, mo in zip(self.joints, self.mode):
            if mo in (1, -1):
                N, _ = fj.normal(y)
                P += fj.mu * N * abs(fj.slide_rate(q, v)[1])
        return P

    def coefficient(self, name, y):
        """The friction force coefficient c of joint ``name`` (force -c along +s on a)."""
        for i, (fj, mo) in enumerate(zip(self.joints, self.mode)):
            if fj.name == name:
                if mo == 0:
                    return self.lock_multiplier(y, i)
                if mo in (1, -1):
                    return mo * fj.mu * fj.normal(y)[0]
        return 0.0


class _Light:
    """The equations of the massless ("light") dofs of a step system's model with the massive dofs
    held and the velocities ``v`` held: static forces, friction slip forces and the Rayleigh damping
    forces C v (as in the step's equations), on the rows and columns of the light dofs and of the
    constraint rows that involve them.  With the masses held, constraints may be redundant (a rod end
    welded to a massive piece and also in the slider of a massive deck): the light positions are
    still determined, the split of the multipliers is not.  The redundant rows are dropped up front
    (:func:`_independent_rows` on the constraint gradients, which are O(1) in model units), so the
    system solved is regular (LU) whatever the rod's stiffness."""

    def __init__(self, sysm, y, elements, v, heavy):
        self.sysm, self.model, self.v = sysm, sysm.model, v
        self.elements = elements.copy()   # the trials of this solve
        n_q = self.model.n_q
        light = complement(n_q, heavy)
        self.first = self.full(y)
        A = self.first[1]
        G = A[n_q:, light]
        rows = np.nonzero(np.abs(G).max(axis=1) > 0.0)[0] if light.size else np.zeros(0, np.intp)
        rows = rows[_independent_rows(G[rows])]
        self.cols = np.concatenate([light, n_q + rows]).astype(np.intp)
        self.heavy, self.n_q = heavy, light.size

    def full(self, y, jacobian=True):
        """The whole model's residual (static, slip and damping forces) and its dense Jacobian."""
        m, sysm = self.model, self.sysm
        r, A, info = m.system(y, self.elements, 1.0, None, jacobian, dense=True)
        if jacobian:
            sysm.release_dense(r, A, y)   # (a lifted contact's multipliers held at 0)
        elif sysm.released.size:
            r[m.n_q + sysm.released] = y[m.n_q + sysm.released]
        for ex in sysm.extra:
            fe, coo = ex(y, None, 0.0)
            r[:m.n_q] += fe
            if jacobian:
                A = add_coo(A, coo)
        if sysm.C is not None:
            r[:m.n_q] += sysm.C @ self.v
        return r, A, info

    def solve(self, y, maxit=30):
        """Newton on the light unknowns from y: (y, its elements' history, residual history);
        SolverFailure when it does not converge."""
        c, n_q = self.cols, self.n_q
        y = y.copy()
        hist = []
        r, A, info = self.first
        for _ in range(maxit):
            rc = r[c]
            floor = 4.0 * info["noise"] / (1.0 + info["fmax"])
            res_f = float(np.abs(rc[:n_q]).max(initial=0.0)) / (1.0 + info["fmax"])
            res_g = float(np.abs(rc[n_q:]).max(initial=0.0))
            hist.append(max(res_f, res_g))
            if res_g <= NEWTON_TOL and (res_f <= NEWTON_TOL or (len(hist) > 1 and res_f <= floor)):
                self.first = (r, A, info)
                return y, self.elements.committed_trial(), hist
            if len(hist) > 4 and hist[-1] <= 1e-7 and hist[-1] > 0.5 * min(hist[-4:-1]):
                self.first = (r, A, info)
                return y, self.elements.committed_trial(), hist   # stagnated at round-off (as newton)
            y[c] -= solve_linear(np.ascontiguousarray(A[np.ix_(c, c)]), rc)
            r, A, info = self.full(y)
        raise SolverFailure("simulate: the massless parts find no equilibrium in the new friction modes", hist)

    def rates(self, v_heavy):
        """Velocities of the light dofs (and multiplier rates) for the massive dofs' velocities at the
        state :meth:`solve` returned: the time derivative of the light equations (the damping
        forces' own rate, which needs accelerations, left out)."""
        A, c = self.first[1], self.cols
        return solve_linear(np.ascontiguousarray(A[np.ix_(c, c)]), -A[np.ix_(c, self.heavy)] @ v_heavy)


def _independent_rows(G, rtol=1e-9):
    """Indices of a maximal set of linearly independent rows of G (in order; a row is dropped when
    its part orthogonal to the rows kept is below rtol times its norm)."""
    keep, basis = [], []
    for i, g in enumerate(G):
        n0 = float(np.linalg.norm(g))
        if n0 == 0.0:
            continue
        r = g.copy()
        for _ in range(2):                       # Gram-Schmidt, twice for round-off
            for b in basis:
                r -= (b @ r) * b
        nr = float(np.linalg.norm(r))
        if nr > rtol * n0:
            keep.append(i)
            basis.append(r / nr)
    return np.array(keep, dtype=np.intp)


def _requilibrate(sysm, s: MotionState):
    """The massless dofs at a change of the friction modes: solved for their equilibrium in the new
    modes with the massive dofs (and the velocities) held where they are, and their velocities made
    consistent with the massive ones (the time derivative of that equilibrium).  This is the
    quasi-static limit of a vanishing slide mass with the jump's energy lost on the way: a massless
    slide that breaks away with mu0 > mu moves at once to the position where its spring and elastic
    forces equal the sliding friction (and stops there, with no overshoot).  Returns the state and
    the potential energy the jump releases (model units; dissipated)."""
    heavy = sysm.masses.massive_dofs()
    if heavy.size == sysm.model.n_q:
        return s, 0.0
    light = _Light(sysm, s.y, s.elements, s.v, heavy)
    y, elements, _ = light.solve(s.y)
    released = sysm.model.potential(s.y, s.alpha) - sysm.model.potential(y, elements.committed)
    rate = light.rates(s.v[heavy])
    v = s.v.copy()
    v[light.cols[:light.n_q]] = rate[:light.n_q]
    return MotionState(s.t, y, v, s.acc, elements), released


def _switch(fr, s: MotionState, k, h_s):
    """The mode change of event slot k (2 i: joint i's friction, 2 i + 1: its contact) at the state
    s: a slipping joint at rest takes the stick test (:func:`_settle`); a stuck one breaks away
    towards its net force (sign of its lock multiplier); a contact lifts (:func:`_lift`) or lands
    (:func:`_land`).  Returns the state in the new modes' layout with consistent accelerations, the
    step system and the energy released by jumps of massless parts and taken by impacts."""
    i, what = divmod(int(k), 2)
    if what == 1:
        return _land(fr, s, i, h_s) if fr.lifted[i] else _lift(fr, s, i, h_s)
    if fr.mode[i] != 0:
        return _settle(fr, s, h_s, [i], fr.stuck())
    old = fr.stuck()
    lam = fr.lock_multiplier(s.y, i)
    fr.mode[i] = 1 if lam > 0 else -1
    fr.event(i, s.t, "slip+" if lam > 0 else "slip-")
    return _restart(fr, s, old, h_s)


def switch_all(fr, s: MotionState, slots, h_s):
    """The mode changes of the event ``slots`` due at one instant: the slipping joints that come to
    rest together take one stick test (:func:`_settle`: a rigid block on two contacts stops as one;
    tested in turn, the first would carry the other's sliding friction too and slip on), then each
    other slot in turn if its mode still fails in the state the switches before left (a landing that
    comes to rest on both corners leaves the other corner pressing, not lifting).  Returns (state,
    step system, energy released)."""
    rest = [k // 2 for k in slots if k % 2 == 0 and fr.mode[k // 2] in (1, -1)]
    released, sysm, done = 0.0, None, False
    if len(rest) > 1:
        s, sysm, released = _settle(fr, s, h_s, rest, fr.stuck())
        slots = [k for k in slots if k // 2 not in rest or k % 2]
        done = True
    for k in slots:
        if done and fr.phi(s.y, s.v)[k] >= 0.0:
            continue
        s, sysm, more = _switch(fr, s, k, h_s)
        released += more
        done = True
    return s, sysm, released


def start(fr, s: MotionState, h_s):
    """The modes at the start of a run: the contacts lifted at the start (event "lift" at t), then
    the stick test of every friction joint in contact (:func:`_settle`)."""
    for i, up in enumerate(fr.lifted):
        if up:
            fr.event(i, s.t, "lift")
    pending = [i for i, fj in enumerate(fr.joints) if fj.friction and not fr.lifted[i]]
    return _settle(fr, s, h_s, pending, ())


def _settle(fr, s: MotionState, h_s, pending, old_stuck):
    """Stick test of the joints ``pending`` (at rest along their guides, or all joints at t = 0):
    each is locked where it is, the consistent start gives its lock multiplier lam, and it stays
    stuck if |lam| <= mu0 N, else slips towards sign(lam).  Returns the state (with the new modes'
    layout), the step system and the energy released by jumps of massless parts."""
    n_q = fr.base.n_q
    q = s.y[:n_q]
    v = s.v.copy()
    for i in pending:
        fj = fr.joints[i]
        fr.mode[i] = 0
        sl, ds, _ = fj.link.slide(q[fj.dofs])
        fr.stick_at[i] = float(sl)
        rate = float(ds @ v[fj.dofs])
        v[fj.dofs] -= ds * rate / float(ds @ ds)     # exactly at rest along the guide
    s, sysm, released = _restart(fr, MotionState(s.t, s.y, v, s.acc, s.elements), old_stuck, h_s)
    slip = []
    for i in pending:
        lam = fr.lock_multiplier(s.y, i)
        if fr.holding(i, s.y) >= 0.0:
            fr.event(i, s.t, "stick")
        else:
            slip.append((i, 1 if lam > 0 else -1))
    if slip:
        old = fr.stuck()
        for i, sg in slip:
            fr.mode[i] = sg
            fr.event(i, s.t, "slip+" if sg > 0 else "slip-")
        s, sysm, more = _restart(fr, s, old, h_s)
        released += more
    return s, sysm, released


def _lift(fr, s: MotionState, i, h_s):
    """Contact i lets go (its pressure reached zero): released (its multipliers 0), no friction acts
    on it while it flies (a stuck joint's lock goes)."""
    old = fr.stuck()
    fr.lifted[i] = True
    fr.mode[i] = FREE
    fr.event(i, s.t, "lift")
    y = s.y.copy()
    y[fr.joints[i].mu_idx] = 0.0
    return _restart(fr, MotionState(s.t, y, s.v, s.acc, s.elements), old, h_s)


def _land(fr, s: MotionState, i, h_s):
    """Contact i lands (its gap closed): an impact (:func:`_impact`: plastic, or with the joint's
    restitution a rebound), then - in contact - the stick test of its friction.  Returns (state,
    step system, energy dissipated: the kinetic energy the impact takes and the jumps of massless
    parts)."""
    fj = fr.joints[i]
    # the velocities before: on the constraints of the modes before (the integrator holds the
    # positions' constraints exactly, their velocities to its error), projected in the mass metric
    before = fr.system()
    v, _ = _kkt(fr, before, s.y, s.alpha, s.v, np.zeros(before.model.n_c))
    s = MotionState(s.t, s.y, _heavy(s.v, v, before.masses.massive_dofs()), s.acc, s.elements)
    fr.lifted[i] = False
    fr.event(i, s.t, "land")
    old = fr.stuck()
    if fj.friction:
        fr.mode[i] = 0
        fr.stick_at[i] = float(fj.link.slide(s.y[:fr.base.n_q][fj.dofs])[0])
    s = MotionState(s.t, fr.convert(s.y, old, fr.stuck()), s.v, s.acc, s.elements)
    s = _onto_constraints(fr.system(), s)
    s, lost, bounce = _impact(fr, s, i)
    if bounce:   # it flies on: released again at once
        old2 = fr.stuck()
        fr.lifted[i] = True
        fr.mode[i] = FREE
        fr.event(i, s.t, "lift")
        y = s.y.copy()
        y[fj.mu_idx] = 0.0
        s = MotionState(s.t, fr.convert(y, old2, fr.stuck()), s.v, s.acc, s.elements)
    s, sysm, released = _restart(fr, s, fr.stuck(), h_s)
    released += lost
    if fj.friction and fr.mode[i] == 0 and fr.holding(i, s.y) < 0.0:
        return _with(_settle(fr, s, h_s, [i], fr.stuck()), released)
    return s, sysm, released


def _with(out, energy):
    s, sysm, released = out
    return s, sysm, released + energy


def _impact(fr, s: MotionState, i):
    """The velocity jump of contact i's landing: with the modes' constraints G (the lifted contacts
    released) and the impulses Lam of their multipliers,

        M (v+ - v-) + G^T Lam + sum_slipping c N(Lam) ds = 0,    G v+ = b,

    b = 0 but on the landing joint's normal row, -e (its normal velocity before), e its restitution
    (0: plastic); friction impulses of the slipping joints with their slip coefficient c = sigma mu.
    A contact whose impulse would pull (Lam_Q > 0) lets go (event "lift": its impulse 0, it
    separates), a stuck joint whose lock impulse exceeds mu0 N(Lam) slips in its direction: the
    solve is repeated in the new modes (the active set of the impact).  Massless dofs carry no
    impulse (their velocities follow the masses', :func:`_requilibrate`).  Least squares: redundant
    constraints (a block on two pinned corners) leave the split of their impulses free.
    Returns (state in the final modes' layout with v+, kinetic energy lost, whether contact i
    rebounds and flies on)."""
    fj = fr.joints[i]
    n_q = fr.base.n_q
    q, v = s.y[:n_q], s.v
    y = s.y
    for _ in range(2 * len(fr.joints) + 2):
        sysm = fr.system()
        nc = sysm.model.n_c
        b = np.zeros(nc)
        row = int(fj.mu_idx[0] - n_q)
        vn = float(fj.gap(q)[1] @ v[fj.dofs])           # the approach velocity (< 0)
        fr.v_landing[i] = max(fr.v_landing[i], abs(vn))
        # a landing below the tolerance of the joint's fastest one comes to rest: the contacts stay
        # (a rocking block's impacts accumulate in finite time, their speeds falling geometrically)
        rest = abs(vn) <= max(fr.tolerance, 1e-12) * fr.v_landing[i]
        e = fj.restitution
        bounce = e > 0.0 and e * abs(vn) > max(fr.tolerance, 1e-12) * fr.v_landing[i]
        if bounce:
            b[row] = -e * vn
        v_new, lam = _kkt(fr, sysm, y, s.alpha, v, b)
        for _ in range(3):   # the normal impulses' signs of the slipping joints, made consistent
            v2, lam2 = _kkt(fr, sysm, y, s.alpha, v, b, lam)
            same = np.allclose(lam2, lam, rtol=1e-12, atol=1e-300)
            v_new, lam = v2, lam2
            if same:
                break
        # the active set: a contact pulled by its impulse lets go; a stuck joint whose lock impulse
        # exceeds static friction slips
        scale = float(np.abs(lam).max(initial=0.0))
        pull = [(lam[int(c.mu_idx[0] - n_q)], k) for k, c in enumerate(fr.joints)
                if c.unilateral and not fr.lifted[k] and k != i]
        pull = [(p, k) for p, k in pull if p > 1e-9 * scale and not rest]
        stuck = fr.stuck()
        slips = []
        for k in stuck:
            c = fr.joints[k]
            N, _ = c.kind.normal_force((lam[c.mu_idx - n_q]).tolist(), c.h)
            L = float(lam[nc - len(stuck) + stuck.index(k)])
            if abs(L) > c.mu0 * N + 1e-9 * scale:
                slips.append((abs(L) - c.mu0 * N, k, 1 if L > 0 else -1))
        if not pull and not slips:
            break
        old = fr.stuck()
        if pull:
            k = max(pull)[1]
            fr.lifted[k] = True
            fr.mode[k] = FREE
            fr.event(k, s.t, "lift")
            y = y.copy()
            y[fr.joints[k].mu_idx] = 0.0
        else:
            _, k, sg = max(slips)
            fr.mode[k] = sg
            fr.event(k, s.t, "slip+" if sg > 0 else "slip-")
        y = fr.convert(y, old, fr.stuck())
    else:
        raise SolverFailure(f"simulate: the impact of {fj.name}'s landing at t = {s.t:.9g} s finds no "
                            f"consistent set of contacts and friction modes")
    v_out = _heavy(v, v_new, sysm.masses.massive_dofs())
    lost = sysm.masses.kinetic(q, v) - sysm.masses.kinetic(q, v_out)
    return MotionState(s.t, y, v_out, s.acc, s.elements), lost, bounce


def _onto_constraints(sysm, s: MotionState, iters=6):
    """The state s with its positions on the constraints of the step system's modes: the smallest
    correction in the mass metric (M dq + G^T a = 0, G dq = -g, Newton on g).  A landing is located
    to the resolution of event times (t_same): its contact's gap is then a few times its approach
    velocity times that, which the next step would close with impulsive forces (a rocking block
    coming to rest on both corners read multipliers of 100 times its weight and lifted a corner)."""
    m = sysm.model
    n_q, nc = m.n_q, m.n_c
    y = s.y.copy()
    M = sysm.masses.dense(y[:n_q])
    for _ in range(iters):
        r, coo, _ = sysm.model_system(y, ElementState(s.alpha))
        g = r[n_q:n_q + nc].copy()
        g[sysm.released] = 0.0
        if float(np.abs(g).max(initial=0.0)) <= 1e-14:
            break
        G = constraint_gradient(coo, n_q, nc, sysm.released)
        A = np.block([[M, G.T], [G, np.zeros((nc, nc))]])
        x = np.linalg.lstsq(A, np.concatenate([np.zeros(n_q), -g]), rcond=None)[0]
        if not np.all(np.isfinite(x)):
            break
        y[:n_q] += x[:n_q]
    return MotionState(s.t, y, s.v, s.acc, s.elements)


def _heavy(v, v_new, heavy):
    """v with the massive dofs' velocities of v_new (the massless ones follow, _requilibrate)."""
    out = v.copy()
    out[heavy] = v_new[heavy]
    return out


def _kkt(fr, sysm, y, alpha, v, b, impulses=None):
    """The impulse problem of the step system ``sysm``'s modes at y (model units): (v+, Lam) from

        M (v+ - v) + G^T Lam + sum_slipping c N(Lam) ds = 0,    G v+ = b

    (G the constraints' gradient with the lifted contacts' rows released, c = sigma mu the slip
    coefficient of each slipping joint in contact; N's sign pattern from the joints' ``impulses``, a
    previous solve's Lam, else from their multipliers in y), by least squares (redundant constraints
    leave the split of their impulses free; massless dofs carry none)."""
    m = sysm.model
    n_q, nc = m.n_q, m.n_c
    q = y[:n_q]
    G = constraint_gradient(sysm.model_system(y, ElementState(alpha))[1], n_q, nc, sysm.released)
    M = sysm.masses.dense(q)
    B = G.T.copy()
    for k, (c, mo) in enumerate(zip(fr.joints, fr.mode)):   # friction impulses of the slipping joints
        if mo in (1, -1) and not fr.lifted[k]:
            _, ds, _ = c.link.slide(q[c.dofs])
            mu_c = y[c.mu_idx] if impulses is None else impulses[c.mu_idx - n_q]
            if c.unilateral and impulses is None:
                mu_c = np.minimum(mu_c, -1e-300)    # (a contact presses: Q < 0)
            _, dN = c.kind.normal_force(mu_c.tolist(), c.h)
            B[np.ix_(c.dofs, c.mu_idx - n_q)] += mo * c.mu * np.outer(ds, np.array(dN))
    A = np.block([[M, B], [G, np.zeros((nc, nc))]])
    x = np.linalg.lstsq(A, np.concatenate([M @ v, b]), rcond=None)[0]
    if not np.all(np.isfinite(x)):
        raise SolverFailure("simulate: the impulse problem of a contact's landing has no solution")
    return x[:n_q], x[n_q:]


def _restart(fr, s: MotionState, old_stuck, h_s):
    """The state s (laid out for the stuck joints ``old_stuck``) carried into the current modes'
    layout (lock multipliers kept, new ones 0), its massless parts re-solved
    (:func:`_requilibrate`) and its accelerations made consistent: (state, step system, energy
    released by jumps of massless parts)."""
    s = MotionState(s.t, fr.convert(s.y, old_stuck, fr.stuck()), s.v, s.acc, s.elements)
    sysm = fr.system(s.y)
    s, released = _requilibrate(sysm, s)
    try:
        return consistent_start(sysm, s, h_s), sysm, released
    except SolverFailure as exc:
        modes = ", ".join(f"{fj.name} {'lifted' if up else _MODE_NAMES[mo]}"
                          for fj, mo, up in zip(fr.joints, fr.mode, fr.lifted))
        raise SolverFailure(f"{exc.reason} at t = {s.t:.9g} s, in the modes {modes} (a rigid body nearly at rest on "
                            f"contacts that slide - low friction - may find no consistent motion)",
                            getattr(exc, "history", None)) from None


_MODE_NAMES = {0: "stuck", 1: "slipping +", -1: "slipping -", FREE: "frictionless"}
