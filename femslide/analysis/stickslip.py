"""Coulomb friction joints in time: their stick/slip modes, event location and mode switches.

:class:`Friction` holds the friction joints of a model (femslide.joints.friction: the Coulomb law of
one joint) and their modes (0 stuck, +-1 slipping), a model per set of stuck joints (a stuck joint's
slide is locked by an exact constraint, femslide.joints.holds.SlideHold) and its step system, the
event functions (slip velocity, static margin mu0 N - |lam|) and the events recorded; the
integrator locates an event inside a step (femslide.analysis.events.locate_step); :func:`_switch`
and :func:`_settle` change modes (the stick test on the consistent start's lock multiplier); at
every change the massless parts are re-solved for equilibrium in the new modes (:func:`_requilibrate`),
the energy their jump releases counted as dissipated.
"""
from __future__ import annotations

import numpy as np

from femslide.analysis.radau import NEWTON_TOL, consistent_start
from femslide.errors import SolverFailure
from femslide.joints.friction import FrictionJoint
from femslide.joints.holds import SlideHold
from femslide.model.linalg import add_coo, solve_linear
from femslide.model.state import MotionState


SAME_INSTANT = 1e-9   # s (relative to max(1, t)): events this close are one instant (events are
                      # located to ~1e-12 s; two of them at one physical instant land within this)


class Friction:
    """The friction joints of a model and their modes (0 stuck, +-1 slipping), the step systems of
    each set of stuck joints, the event functions and the mode switches."""

    def __init__(self, model, joints, make_system, counts):
        from femslide.model.discrete import Model
        from femslide.model.patterns import PatternCache
        self.base = model
        self.joints = [FrictionJoint(model, j) for j in joints]
        self.make_system = make_system      # (model, extras) -> a step system (femslide.analysis.radau)
        self.counts = counts
        self._Model, self._cache = Model, PatternCache()
        self._models = {(): model}
        self.mode = [0] * len(self.joints)
        self.stick_at = [0.0] * len(self.joints)
        self.events = {fj.name: [] for fj in self.joints}
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
        return self._model(tuple(range(len(self.joints))))

    def system(self):
        """The step system of the current modes (lock targets set)."""
        stuck = self.stuck()
        key = tuple(self.mode)
        sysm = self._systems.get(key)
        if sysm is None:
            m = self._model(stuck)
            extras = [fj.slip(mo) for fj, mo in zip(self.joints, self.mode) if mo != 0]
            sysm = self._systems[key] = self.make_system(m, extras)
        m = sysm.model
        for lock, i in zip(getattr(m, "locks", []), stuck):
            lock.target = self.stick_at[i]
        return sysm

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
        """Record joint i's new mode at t; a repeat of the joint's last event at the same instant
        (within SAME_INSTANT: the stick test may confirm a slip direction twice, or two events located
        to the locator's tolerance may coincide) is not recorded."""
        ev = self.events[self.joints[i].name]
        if not ev or ev[-1]["kind"] != kind or abs(ev[-1]["t"] - t) > SAME_INSTANT * max(1.0, abs(t)):
            ev.append({"t": t, "kind": kind})

    def phi(self, y, v):
        """Event functions (positive while the mode holds): sigma s' when slipping, mu0 N - |lam|
        when stuck."""
        q = y[:self.base.n_q]
        out = []
        for i, (fj, mo) in enumerate(zip(self.joints, self.mode)):
            if mo != 0:
                out.append(mo * fj.slide_rate(q, v)[1])
            else:
                out.append(self.holding(i, y))
        return np.array(out)

    def started_slip(self, i, t):
        """Whether joint i started to slip at t (its last event, within SAME_INSTANT, and it is
        slipping)."""
        ev = self.events[self.joints[i].name]
        return self.mode[i] != 0 and bool(ev) and abs(ev[-1]["t"] - t) <= SAME_INSTANT * max(1.0, abs(t))

    def holding(self, i, y):
        """Stuck joint i's margin mu0 N - |lam|: >= 0 while static friction holds."""
        N, _ = self.joints[i].normal(y)
        return self.joints[i].mu0 * N - abs(self.lock_multiplier(y, i))

    def power(self, y, v):
        """Friction power dissipated (model units), sum of mu N |s'| over the slipping joints."""
        q = y[:self.base.n_q]
        P = 0.0
        for fj, mo in zip(self.joints, self.mode):
            if mo != 0:
                N, _ = fj.normal(y)
                P += fj.mu * N * abs(fj.slide_rate(q, v)[1])
        return P

    def coefficient(self, name, y):
        """The friction force coefficient c of joint ``name`` (force -c along +s on a)."""
        for i, (fj, mo) in enumerate(zip(self.joints, self.mode)):
            if fj.name == name:
                if mo == 0:
                    return self.lock_multiplier(y, i)
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
        light = np.setdiff1d(np.arange(n_q), heavy).astype(np.intp)
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
        for ex in sysm.extra:
            fe, coo = ex(y, None, 0.0)
            r[:m.n_q] += fe
            if jacobian:
                A = add_coo(A, coo)
        if sysm.Csr is not None:
            r[:m.n_q] += sysm.Csr @ self.v
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


def _restart(fr, s: MotionState, old_stuck, h_s):
    """The state s (laid out for the stuck joints ``old_stuck``) carried into the current modes'
    layout (lock multipliers kept, new ones 0), its massless parts re-solved
    (:func:`_requilibrate`) and its accelerations made consistent: (state, step system, energy
    released by jumps of massless parts)."""
    s = MotionState(s.t, fr.convert(s.y, old_stuck, fr.stuck()), s.v, s.acc, s.elements)
    sysm = fr.system()
    s, released = _requilibrate(sysm, s)
    return consistent_start(sysm, s, h_s), sysm, released


def _switch(fr, s: MotionState, i, h_s):
    """The mode change of friction joint i at the state s: a slipping joint at rest takes the stick
    test (:func:`_settle`); a stuck one breaks away towards its net force (sign of its lock
    multiplier).  Returns the state in the new modes' layout with consistent accelerations, the
    step system and the energy released by jumps of massless parts (:func:`_requilibrate`)."""
    if fr.mode[i] != 0:
        return _settle(fr, s, h_s, [i], fr.stuck())
    old = fr.stuck()
    lam = fr.lock_multiplier(s.y, i)
    fr.mode[i] = 1 if lam > 0 else -1
    fr.event(i, s.t, "slip+" if lam > 0 else "slip-")
    return _restart(fr, s, old, h_s)


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
