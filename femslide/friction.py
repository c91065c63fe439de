"""Coulomb friction in sliders and rollers for the FE dynamics (exact stick, events located in time).

A joint with ``mu`` (kinetic) and ``mu0`` >= mu (static) resists its slide s (the displacement of a's
point along the guide carried by b; femslide/joints.py) by a friction force along the guide:

- normal force N from the joint's own multipliers: a slider carries its transverse force Q (first
  multiplier) and its moment M (second); with ``bearing = h`` the guide's two bearings h apart take
  the contact forces Q/2 + M/h and Q/2 - M/h and N = |Q/2 + M/h| + |Q/2 - M/h|; without a bearing
  (and for a roller) N = |Q|.  N is evaluated implicitly, at the end of every step, with the
  multipliers of that step;
- stuck: the slide is locked exactly by an extra constraint s(q) = s_stick (velocity exactly zero,
  no drift, no chattering); its multiplier lam is the friction force that holds it (the force along
  +s on a is -lam).  Stuck while |lam| <= mu0 N;
- slip in the direction sigma = +-1: the friction force -sigma mu N along the guide (on a, and its
  reaction on b): the generalised force -sigma mu N ds/dq with its Jacobian (N's derivatives with
  respect to the joint's multipliers lie in the joint's own Jacobian block);
- events, located in time by the Illinois method on the step size (each trial a step of the
  integrator from the last accepted state, so the event lies on the step's own solution): slip ends
  when sigma s' reaches 0; there the stick test is made (the lock multiplier of the consistent
  start, |lam| <= mu0 N) and the joint sticks ("stick") or slips on in the direction of the net force
  ("slip+" / "slip-"); a stuck joint breaks away when |lam| reaches mu0 N, towards sign(lam).  At
  every event the massless dofs (rods with rhoA = 0) are re-solved for their equilibrium in the new
  modes with the massive dofs held, their velocities made consistent with the massive ones, and the
  integrator restarts with consistent accelerations (the friction force jumps).  A massless slide
  that breaks away with mu0 > mu therefore jumps at once to the position where the forces on it equal
  the sliding friction and stops there: the quasi-static limit of a vanishing slide mass with the
  jump's energy lost on the way (a small slide mass on a spring would overshoot before it sticks);
  the potential energy released counts as dissipated (femslide/transient.py, ``_requilibrate``).
- a joint with mu0 = 0 has no friction at all: femslide/simulation.py treats it as an ordinary slider
  or roller.

The structure's model gets one extra constraint per stuck joint: a model per set of stuck joints,
built when first needed (the lock multipliers come after the joints', so the joints' layout stays).
Energy: friction dissipates mu N |s'| (integrated with the others in femslide/transient.py).
"""
from __future__ import annotations

import math

import numpy as np

from .results import at_joint_point


class SlideLock:
    """Exact constraint s(q) - origin - target = 0 on a slider's or roller's slide s (joints.py
    protocol): a stuck friction joint (origin 0, target the slide where it stuck) and the held
    start of a simulation (origin the reference slide, target walked to the initial one)."""

    size = 1

    def __init__(self, link, target=0.0, name="lock", origin=0.0):
        self.link, self.target, self.name, self.origin = link, target, name, origin
        self.dofs = link.dofs

    def value(self, z):
        """The held quantity s - origin (array of one)."""
        return np.array([self.link.slide(z)[0] - self.origin])

    def eval(self, z, mu=None):
        s, ds, H = self.link.slide(z)
        g = np.array([s - self.origin]) - self.target
        if mu is not None:
            return g, ds[None, :], mu[0] * H
        return g, ds[None, :], H[None]


class FrictionJoint:
    """One friction joint of a model: the slide, the normal force and the slip force."""

    def __init__(self, model, joint):
        self.name = joint.name
        self.link = model.joint[joint.name]
        self.dofs = self.link.dofs
        self.link_nq = model.n_q
        i = model.constraints.index(self.link)
        o = model.n_q + int(model.c_off[i])
        self.mu_idx = np.arange(o, o + self.link.size, dtype=np.intp)
        self.mu, self.mu0 = float(joint.mu), float(joint.mu0)
        self.h = joint.bearing / model.Lref if joint.bearing else None
        self.slider = joint.type == "slider"
        # COO pattern of the slip force: (dofs x dofs) and (dofs x joint multipliers)
        d, m = self.dofs, self.mu_idx
        self.rows = np.concatenate([np.repeat(d, d.size), np.repeat(d, m.size)])
        self.cols = np.concatenate([np.tile(d, d.size), np.tile(m, d.size)])

    def normal(self, y):
        """N (model units) and dN / d(joint multipliers)."""
        m = y[self.mu_idx]
        Q = float(m[0])
        if self.slider and self.h:
            M = float(m[1])
            c1, c2 = 0.5 * Q + M / self.h, 0.5 * Q - M / self.h
            s1, s2 = math.copysign(1.0, c1), math.copysign(1.0, c2)
            return abs(c1) + abs(c2), np.array([0.5 * (s1 + s2), (s1 - s2) / self.h])
        dN = np.zeros(self.mu_idx.size)
        dN[0] = math.copysign(1.0, Q)
        return abs(Q), dN

    def slide_rate(self, q, v):
        """(s, s') of the joint (s from its absolute value along the guide, model units)."""
        z = q[self.dofs]
        s, ds, _ = self.link.slide(z)
        return float(s), float(ds @ v[self.dofs])

    def slip(self, sigma):
        """The slip force as an ``extra`` term of a :class:`femslide.transient.StepSystem`."""
        def term(y, v1, c_vel):
            q = y[:self.link_nq]
            s, ds, Hs = self.link.slide(q[self.dofs])
            N, dN = self.normal(y)
            c = sigma * self.mu
            f = np.zeros(self.link_nq)
            f[self.dofs] = c * N * ds
            vals = np.concatenate([(c * N * Hs).ravel(), (c * np.outer(ds, dN)).ravel()])
            return f, (self.rows, self.cols, vals)
        return term


def joint_friction_force(link, c, q):
    """(Fx, Fy, M) (model units) of a friction force of coefficient c along the guide on part a at
    the joint point: the generalised force -c ds/dq on a's dofs, its moment taken about the joint
    point (:func:`femslide.results.at_joint_point`)."""
    if link.ia is None:
        return 0.0, 0.0, 0.0
    z = q[link.dofs]
    _, ds, _ = link.slide(z)
    f = (-c * ds[link.ia:link.ia + 3]).tolist()
    return at_joint_point(link, z.tolist(), f)


class Friction:
    """The friction joints of a model and their modes (0 stuck, +-1 slipping), the step systems of
    each set of stuck joints, the event functions and the mode switches."""

    def __init__(self, model, joints, make_system, counts):
        from .model import Model
        from .patterns import PatternCache
        self.base = model
        self.joints = [FrictionJoint(model, j) for j in joints]
        self.make_system = make_system      # (model, extras) -> StepSystem
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
                lock = SlideLock(m.joint[fj.name], 0.0, f"lock {fj.name}")
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
        """Record joint i's new mode at t (a repeat of the joint's last event is not recorded: the
        stick test may confirm a slip direction twice at one instant)."""
        ev = self.events[self.joints[i].name]
        if not ev or ev[-1] != {"t": t, "kind": kind}:
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
        """Whether joint i started to slip at t (its last event, and it is slipping)."""
        ev = self.events[self.joints[i].name]
        return self.mode[i] != 0 and bool(ev) and ev[-1]["t"] == t

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
