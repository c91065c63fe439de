"""Quasi-static load histories with Coulomb friction in sliders and rollers (SPEC section 10).

A structure with ``[[step]]`` states is brought from one load state to the next by ramping every
load case's factor linearly, f(t) = f_prev + t (f_next - f_prev), t in [0, 1] along the step (the
first step starts from the unloaded structure).  Sliders and rollers with ``mu`` carry Coulomb friction,
rate-independent and path-dependent, exactly:

- a *stuck* joint has its slide locked by an extra constraint (femslide.joints.holds.SlideHold at
  the slide where it stuck); the constraint's multiplier lam is the friction force that holds it
  (the force along +s on part a is -lam).  It stays stuck while |lam| <= mu0 N, N the joint's normal
  force (femslide.joints.friction.FrictionJoint.normal: from its own multipliers, with its bearing);
- a *slipping* joint, in the direction sigma = +-1, carries the friction force -sigma mu N along its
  guide (a term of the equations with its exact Jacobian, N's dependence on the joint's multipliers
  included);
- the switches are found inside a step on its load parameter t: a stuck joint breaks away where
  |lam| reaches mu0 N (bisection on t to 1e-13; it then slips towards sign(lam) - with mu0 > mu the
  friction drops to mu N at once and the slide jumps to the equilibrium of the sliding friction, the
  quasi-static limit); a slipping joint sticks where its slide stops advancing in its direction
  (golden-section search of the extreme of sigma s(t)), and the joint is tested again at once in its
  new mode.  Each joint starts stuck at its reference slide.

Everything is solved on one fixed mesh (the rods' ``elements``, or ``elements`` given, else
``N_HISTORY`` elements per shortest rod); the history on the mesh with half the elements gives the
``error_estimate`` (the largest relative change of the step results, over 3: the O(h^2)
discretisation's Richardson estimate).

Units: the model's (femslide.model.discrete) inside; every step's result in SI, with each friction
joint's ``state`` ("stuck" / "slipping"), ``force`` [N] (the friction force on a along the guide's
+axis), ``normal`` [N] and ``slide`` [m].
"""
from __future__ import annotations

import math

import numpy as np

from femslide.analysis.newton import newton
from femslide.errors import SolverFailure
from femslide.joints.friction import FrictionJoint
from femslide.joints.holds import SlideHold
from femslide.results.static import extract

N_HISTORY = 16          # elements per shortest rod by default
SUBSTEPS = 4            # load increments per step (halved on a failed Newton)
T_TOL = 1e-13           # the switch's load parameter, absolute
GOLD = 0.5 * (math.sqrt(5.0) - 1.0)


class _Stage:
    """A model in given friction modes: newton's interface, with the slip forces of the slipping joints
    as extra terms of the model's equations (and, in first-order theory, the constant part of the locks'
    equations, which the linearised model leaves out)."""

    def __init__(self, model, slips, locks):
        self.model, self.slips, self.locks = model, slips, locks
        self.n_q = model.n_q
        self.n = model.n
        self._pos = {}
        self._lock_rows = np.array([self._row(h) for h, _ in locks], np.intp)
        if model.linear and locks:
            z = [np.zeros(h.dofs.size) for h, _ in locks]
            self._lock_g0 = np.array([float(h.eval(zz)[0][0]) for (h, _), zz in zip(locks, z)])

    def _row(self, hold):
        i = self.model.constraints.index(hold)
        return self.model.n_q + int(self.model.c_off[i])

    def rotation_dofs(self):
        return self.model.rotation_dofs()

    def system(self, y, elements, lam=1.0, control=None, jacobian=True):
        m = self.model
        extra = None
        if self.slips:
            rows, vals, pos, jv = [], [], [], []
            q = y[:m.n_q]
            for fj, sigma in self.slips:
                z = np.zeros(fj.dofs.size) if m.linear else q[fj.dofs]
                _, ds, Hs = fj.link.slide(z)
                N, dN = fj.normal(y)
                c = sigma * fj.mu
                rows.append(fj.dofs)
                vals.append(c * N * ds)
                if jacobian:
                    key = id(fj)
                    if key not in self._pos:
                        self._pos[key] = m.pattern_positions(fj.rows, fj.cols)
                    pos.append(self._pos[key])
                    H = np.zeros_like(Hs) if m.linear else c * N * Hs
                    jv.append(np.concatenate([H.ravel(), (c * np.outer(ds, dN)).ravel()]))
            extra = (np.concatenate(rows), np.concatenate(vals),
                     np.concatenate(pos) if jacobian else None, np.concatenate(jv) if jacobian else None)
        r, A, info = m.system(y, elements, lam, control, jacobian, extra=extra)
        if m.linear and self.locks:
            r[self._lock_rows] += self._lock_g0
        return r, A, info


class _Joint:
    """A friction joint's mode along the history: stuck at ``lock`` (its absolute slide, model units)
    or slipping in direction ``sigma``."""

    def __init__(self, joint):
        self.joint = joint
        self.name = joint.name
        self.stuck = True
        self.lock = None        # set from the reference slide when first built
        self.sigma = 0.0


class History:
    """The load history of a frozen structure on one mesh (module docstring)."""

    def __init__(self, fs, counts, Lref, Fref, cache, make):
        self.fs, self.counts, self.L, self.F, self.cache, self.make = fs, counts, Lref, Fref, cache, make
        self.joints = [_Joint(j) for j in fs.joints if j.mu is not None and j.mu0 is not None and j.mu0 > 0]
        self.events = []
        self.iterations = 0
        self.failure = None     # the reason a step failed (the steps before it are kept)
        self.trace = {jt.name: [] for jt in self.joints}   # (slide [m], friction force [N]) along the history

    # -- models ------------------------------------------------------------------------------------------
    def _stage(self, factors):
        """The model at these load factors in the joints' current modes, with its FrictionJoints."""
        m = self.make(self.fs, self.counts, self.L, self.F, self.cache, finalize=False, factors=factors)
        locks = []
        for jt in self.joints:
            if jt.stuck:
                link = m.joint[jt.name]
                if jt.lock is None:
                    jt.lock = float(link.slide(np.zeros(link.k))[0])
                h = SlideHold(link, jt.lock, name=f"lock {jt.name}")
                m.add_constraint(h)
                locks.append((h, jt))
        m.finalize()
        fjs = {jt.name: FrictionJoint(m, jt.joint) for jt in self.joints}
        slips = [(fjs[jt.name], jt.sigma) for jt in self.joints if not jt.stuck]
        return _Stage(m, slips, locks), fjs

    def _carry(self, y, old, new):
        """A state of the stage ``old`` laid out for ``new``: frame dofs and the joints' multipliers kept
        (the locks come after the joints), a lock's multiplier kept if the joint was locked before,
        else 0 (Newton finds it: the locks are linear in their multipliers)."""
        yn = np.zeros(new.n)
        k = min(old.model.n_q + _joint_mults(old.model), new.model.n_q + _joint_mults(new.model))
        yn[:k] = y[:k]
        for h, jt in new.locks:
            row = new._row(h)
            if any(jt is j for _, j in old.locks):
                oh = next(h2 for h2, j in old.locks if j is jt)
                yn[row] = y[old._row(oh)]
        return yn

    def _solve(self, factors, y, es, prev_stage=None):
        """Equilibrium at ``factors`` in the current modes from the state (y, es): (stage, y, es, fjs);
        raises SolverFailure when Newton fails."""
        stage, fjs = self._stage(factors)
        if prev_stage is not None:
            y = self._carry(y, prev_stage, stage)
        e = es.copy()
        yn, info = newton(stage, y, e, lam=1.0)
        self.iterations += info.iterations
        if not info.converged:
            raise SolverFailure(f"no equilibrium in the load history ({info.reason})", info.history)
        return stage, yn, e.committed_trial(), fjs

    # -- friction tests ----------------------------------------------------------------------------------
    def _lock_force(self, stage, y, jt):
        h = next(h for h, j in stage.locks if j is jt)
        return float(y[stage._row(h)])

    def _slide(self, stage, y, fj):
        z = y[:stage.n_q][fj.dofs]
        if stage.model.linear:
            s0, ds, _ = fj.link.slide(np.zeros(z.size))
            return float(s0 + ds @ z)
        return float(fj.link.slide(z)[0])

    def _excess(self, stage, y, fjs, jt):
        """|lam| - mu0 N of a stuck joint (> 0: it breaks away), in model units."""
        N, _ = fjs[jt.name].normal(y)
        return abs(self._lock_force(stage, y, jt)) - jt.joint.mu0 * N

    # -- the history -------------------------------------------------------------------------------------
    def run(self):
        """Every step's state: a list of (name, factors, model, y, alpha, friction) (model units); a step
        that fails ends the list, its reason in ``self.failure``."""
        y = None
        es = None
        prev = {}
        stage = None
        out = []
        for st in self.fs.steps:
            target = st.factor_dict()
            cases = set(prev) | set(target)
            f0 = {c: prev.get(c, 0.0) for c in cases}
            df = {c: target.get(c, 0.0) - f0[c] for c in cases}

            def factors(t, f0=f0, df=df):
                return {c: f0[c] + t * df[c] for c in f0}
            if y is None:
                stage, _ = self._stage(factors(0.0))
                y, es = stage.model.zero_state()
            try:
                stage, y, es = self._step(factors, stage, y, es, st.name)
            except SolverFailure as exc:
                modes = ", ".join(f"{jt.name} {'stuck' if jt.stuck else 'slipping'}" for jt in self.joints)
                self.failure = (f"step {st.name}: {exc.reason}" + (f" (friction joints: {modes}; a structure "
                                "whose slipping joints leave a free motion is a mechanism)" if modes else ""))
                break
            fjs = {jt.name: FrictionJoint(stage.model, jt.joint) for jt in self.joints}
            out.append((st.name, target, stage, y, es.committed.copy(), self._report(stage, y, fjs)))
            prev = target
        return out

    def _step(self, factors, stage, y, es, name):
        t, dt = 0.0, 1.0 / SUBSTEPS
        stage, y, es, fjs = self._solve(factors(0.0), y, es, stage)
        halvings = 0
        while t < 1.0 - 1e-15:
            t1 = min(1.0, t + dt)
            try:
                st1, y1, es1, fj1 = self._solve(factors(t1), y, es, stage)
            except SolverFailure:
                halvings += 1
                if halvings > 30:
                    raise
                dt *= 0.5
                continue
            ev = self._first_event(factors, stage, y, es, fjs, st1, y1, fj1, t, t1)
            if ev is None:
                stage, y, es, fjs, t = st1, y1, es1, fj1, t1
                self._record(stage, y, fjs)
                continue
            te, jt, kind, (ste, ye, ese, fje), direction = ev
            # the state at the switch, then the joint in its new mode (and any joint that is then
            # out of its law switched too, at the same load)
            stage, y, es, fjs, t = ste, ye, ese, fje, te
            self._record(stage, y, fjs)
            self._switch(jt, kind, stage, y, fjs, name, te, direction)
            stage, y, es, fjs = self._settle(factors(te), stage, y, es, name, te)
            self._record(stage, y, fjs)
        return stage, y, es

    def _settle(self, factors, stage, y, es, name, t):
        """Re-solve in the new modes at the same load until every joint obeys its law there."""
        for _ in range(4 * len(self.joints) + 4):
            stage, y, es, fjs = self._solve(factors, y, es, stage)
            bad = None
            for jt in self.joints:
                if jt.stuck and self._excess(stage, y, fjs, jt) > 1e-12 * self._scale(stage, y, fjs):
                    bad = (jt, "slip")
                    break
            if bad is None:
                return stage, y, es, fjs
            self._switch(bad[0], bad[1], stage, y, fjs, name, t)
        raise SolverFailure(f"friction joints keep switching at step {name}, load parameter {t:.6g}")

    def _scale(self, stage, y, fjs):
        return max([1e-300] + [abs(fjs[jt.name].normal(y)[0]) * jt.joint.mu0 for jt in self.joints])

    def _switch(self, jt, kind, stage, y, fjs, name, t, direction=None):
        """Switch a joint's mode at the state (stage, y); a breakaway's ``direction`` is the sign of
        the lock force just past the switch (the state at the switch itself may carry it only to
        round-off: a joint that slips from the first load on)."""
        if kind == "slip":
            lam = self._lock_force(stage, y, jt) if direction is None else direction
            jt.stuck, jt.sigma = False, (1.0 if lam > 0 else -1.0)
            kind = "slip+" if jt.sigma > 0 else "slip-"
        else:
            jt.stuck, jt.lock, jt.sigma = True, self._slide(stage, y, fjs[jt.name]), 0.0
        self.events.append({"step": name, "load_parameter": t, "joint": jt.name, "kind": kind})

    def _first_event(self, factors, st0, y0, es0, fj0, st1, y1, fj1, t0, t1):
        """The earliest switch in (t0, t1], or None: (t, joint, "slip" | "stick", state at t, the lock
        force at t1 for a breakaway: its direction)."""
        scale = self._scale(st1, y1, fj1)
        best = None
        for jt in self.joints:
            if jt.stuck:
                if self._excess(st1, y1, fj1, jt) <= 1e-12 * scale:
                    continue

                def g(t, jt=jt):
                    s = self._solve(factors(t), y0, es0, st0)
                    return self._excess(s[0], s[1], s[3], jt), s
                te, state = _bisect(g, t0, t1)
                kind = "slip"
                direction = self._lock_force(st1, y1, jt)
            else:
                fj_a, fj_b = fj0[jt.name], fj1[jt.name]
                s_a, s_b = self._slide(st0, y0, fj_a), self._slide(st1, y1, fj_b)
                if jt.sigma * (s_b - s_a) >= -1e-13 * (abs(s_a) + abs(s_b) + 1e-300):
                    continue

                def h(t, jt=jt):
                    s = self._solve(factors(t), y0, es0, st0)
                    return jt.sigma * self._slide(s[0], s[1], s[3][jt.name]), s
                te, state = _golden_max(h, t0, t1)
                kind, direction = "stick", None
            if best is None or te < best[0]:
                best = (te, jt, kind, state, direction)
        return best

    def _record(self, stage, y, fjs):
        for name, v in self._report(stage, y, fjs).items():
            self.trace[name].append((v["slide"], v["force"]))

    def _report(self, stage, y, fjs):
        """Each friction joint's state, force, normal force and slide (SI)."""
        out = {}
        F, L = self.F, self.L
        for jt in self.joints:
            fj = fjs[jt.name]
            N, _ = fj.normal(y)
            if jt.stuck:
                force = -self._lock_force(stage, y, jt)
            else:
                force = -jt.sigma * jt.joint.mu * N
            s = self._slide(stage, y, fj) - stage.model.slide0[jt.name]
            out[jt.name] = {"state": "stuck" if jt.stuck else "slipping", "force": force * F, "normal": N * F,
                            "slide": s * L}
        return out


def _bisect(g, a, b):
    """The root of g on [a, b] (g(a) <= 0 < g(b)) to T_TOL: (t, the state there, on the side g <= 0
    rounded to the root)."""
    state = None
    while b - a > T_TOL:
        m = 0.5 * (a + b)
        fm, s = g(m)
        if fm > 0:
            b = m
        else:
            a, state = m, s
    if state is None:
        _, state = g(a)
    return a, state


def _golden_max(h, a, b):
    """The t in [a, b] of the largest h(t) (unimodal) to T_TOL: (t, the state there)."""
    c, d = b - GOLD * (b - a), a + GOLD * (b - a)
    fc, sc = h(c)
    fd, sd = h(d)
    while b - a > 1e-10:
        if fc >= fd:
            b, d, fd, sd = d, c, fc, sc
            c = b - GOLD * (b - a)
            fc, sc = h(c)
        else:
            a, c, fc, sc = c, d, fd, sd
            d = a + GOLD * (b - a)
            fd, sd = h(d)
    fa, sa = h(a)
    best = max(((fa, a, sa), (fc, c, sc), (fd, d, sd)), key=lambda x: x[0])
    return best[1], best[2]


def _joint_mults(model):
    """The number of the joints' multipliers (the constraints before any lock)."""
    n = 0
    for c in model.constraints:
        if isinstance(c, SlideHold):
            break
        n += c.size
    return n


def run_history(fs, counts, Lref, Fref, cache, make):
    """(steps, history) of :class:`History` on the mesh ``counts``: steps as (name, factors, values,
    model, y, alpha) with the section-8 values in SI plus ``friction``; ``history`` the History (its
    ``events``, ``iterations`` and ``trace``)."""
    h = History(fs, counts, Lref, Fref, cache, make)
    raw = h.run()
    steps = []
    for name, factors, stage, y, alpha, fric in raw:
        res = extract(stage.model, y, alpha)
        steps.append((name, factors, {**res, "friction": fric}, stage.model, y, alpha))
    return steps, h

