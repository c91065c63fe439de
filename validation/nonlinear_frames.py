"""Rigid bodies on massless corotational columns, in time, with Coulomb friction under one body: an
independent nonlinear reference for femslide's FE dynamics (numpy and scipy only; nothing from
femslide).

Why: the linear references (linear_dynamics.py, friction_events.py) are exact for the linearised
structure, but a frame's geometric nonlinearity shows at first order in the drift ratio in some
outputs - the column moments and the support forces carry the overturning axial forces times the
chord rotations - and, under a friction support, at second order times omega^2 h / g in the
normal force (the deck rises and falls by the columns' bowing, ~ 0.6 u^2 / h, and its vertical
inertia loads the support).  At the drifts of a base-isolated frame (~2e-3) that is ~1e-3: far
above the tolerances to be checked.  This module solves the same nonlinear model femslide solves,
in another way.

Model (SI units, x right, y up, rotations counter-clockwise):

* bodies: mass m at the centroid, rotary inertia J about it; coordinates (x, y, theta) of the
  centroid's displacement and the rotation, relative to the moving ground; a body on a ground slider
  along x has y and theta locked (its vertical reaction is the slider's normal force);
* columns: massless rods of ``n`` equal corotational Euler-Bernoulli elements (Crisfield, Non-linear
  FE analysis of solids and structures, vol. 1, sec. 7.3, written out here: chord length l and
  rotation alpha from the end nodes; basic deformations l - L0, theta_1 - alpha, theta_2 - alpha;
  basic forces N = EA (l - L0) / L0, M1 = EI (4 th1 + 2 th2) / L0, M2 = EI (2 th1 + 4 th2) / L0;
  internal forces B^T (N, M1, M2); tangent B^T D B + (N / l) z z^T + (M1 + M2) / l^2 (r z^T + z r^T)),
  welded at both ends to a body point (exact rigid-body kinematics, any rotation) or to the ground;
  their inner nodes are in static equilibrium at every instant (Newton, all columns of one element
  count at once, from the last solution moved by its linear sensitivity to the ends, to a
  correction <= 1e-10: the remaining error is round-off).  The deformations are formed from the
  displacement differences Dl of the element's ends, never from positions: l - L0 = (2 D0 . Dl +
  Dl . Dl) / (l + L0), alpha = atan2(D0 x Dl, L0^2 + D0 . Dl), a body point's displacement with
  cos - 1 = -2 sin^2(theta / 2) - from positions the axial force would carry a round-off of EA eps
  (3e-7 N here), a noise the step control of a tight run chases (5289 steps for 0.1 s, against 47);
* equations of motion of the bodies, by virtual work: M q'' = Q(q) - M r a_g(t) - (0, m g, 0) + F,
  Q the columns' forces on the bodies, F the friction force on the sliding body (stuck: F holds
  x'' = 0, as long as |F| <= mu0 N; slipping in the direction sigma: F = -sigma mu N), N = m_b g -
  Q_y of that body (its vertical reaction);
* integration: scipy's DOP853 between the record's samples (the input is linear in each interval;
  each piece starts with the last step size) and the friction events, which solve_ivp locates on
  its dense output (stick: mu0 N -+ F_req = 0; slip: the sliding velocity = 0), then the stick test
  on the located state as in friction_events.py.  The work of the ground's inertia loads and of
  friction is integrated with the motion.  At rtol 1e-10 (atol 1e-12) the 20 s record of
  base-isolated-frame.toml takes 250 s CPU (23913 steps, 0.4 ms per force evaluation) and agrees
  with rtol 1e-12 (395 s) to < 7e-10 of every history's largest value.  The explicit method is the
  cheaper one at this accuracy: the problem is not stiff at rtol 1e-10 (the stiffest mode, the deck's
  rocking on the columns' axial stiffness, 188 Hz, has to be followed anyway: the friction events
  excite it and it carries ~10 N of the normal force); solve_ivp's Radau took 3x the steps and 1.8x
  the CPU over 0.5 s at the same rtol, with an energy balance of 7e-10 against 2e-14.

The run starts from the static equilibrium under gravity (bodies and inner nodes by Newton, the slide
held), at rest, the friction support stuck.  The energy balance (kinetic + strain + gravity against
the work of the ground's inertia loads and of friction) is :meth:`Run.energy_balance`, the mechanical
energy :meth:`Frames.energy`.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy.integrate import solve_ivp


@dataclass
class Body:
    name: str
    m: float
    J: float
    c: np.ndarray              # reference centroid [m]
    locked: tuple = ()         # indices among (0, 1, 2) = (x, y, theta) held at 0


@dataclass
class Column:
    name: str
    a: str | None              # body name at the start (None: the ground)
    b: str | None              # body name at the end
    X0: np.ndarray             # start point [m]
    X1: np.ndarray             # end point [m]
    EI: float
    EA: float
    n: int


class _Group:
    """The columns of one element count n, as arrays (C columns): reference element vectors D0
    (C, n, 2), element length L0, EI, EA (C, 1), the ends' body indices (nb = the ground) and their
    offsets from the body centroids (C, 2), and the inner nodes' last solution (C, n - 1, 3)."""

    def __init__(self, cols, bi, bodies):
        nb = len(bodies)
        self.cols = cols
        self.n = n = cols[0].n
        self.L0 = np.array([[np.linalg.norm(c.X1 - c.X0) / n] for c in cols])
        self.D0 = np.array([[(c.X1 - c.X0) / n] * n for c in cols])
        self.EI = np.array([[c.EI] for c in cols], float)
        self.EA = np.array([[c.EA] for c in cols], float)
        self.ia = np.array([bi[c.a] if c.a is not None else nb for c in cols])
        self.ib = np.array([bi[c.b] if c.b is not None else nb for c in cols])
        cen = [b.c for b in bodies] + [np.zeros(2)]
        self.ra = np.array([c.X0 - cen[i] if c.a is not None else np.zeros(2) for c, i in zip(cols, self.ia)])
        self.rb = np.array([c.X1 - cen[i] if c.b is not None else np.zeros(2) for c, i in zip(cols, self.ib)])
        self.nodes = np.zeros((len(cols), n - 1, 3))
        self.S = self.ends = None          # the nodes' linear sensitivity to the ends, at the ends


def _ends(qe, idx, r0):
    """Rod-end dofs (u, v, theta) (..., C, 3) of the points at the offsets r0 (C, 2) from the
    centroids of the bodies idx (C,) for the body dofs qe (..., nb + 1, 3) (the last row: the ground,
    zero), and d(end)/d(body dofs) (..., C, 3, 3).  The displacement of the offset, (R - I) r0, is
    formed with cos - 1 = -2 sin^2(theta / 2): no cancellation for small rotations."""
    x, y, th = qe[..., idx, 0], qe[..., idx, 1], qe[..., idx, 2]
    s, cm1 = np.sin(th), -2.0 * np.sin(0.5 * th) ** 2
    u = np.stack([x + cm1 * r0[:, 0] - s * r0[:, 1], y + s * r0[:, 0] + cm1 * r0[:, 1], th], axis=-1)
    rx, ry = r0[:, 0] + u[..., 0] - x, r0[:, 1] + u[..., 1] - y
    J = np.zeros(u.shape + (3,))
    J[..., 0, 0] = J[..., 1, 1] = J[..., 2, 2] = 1.0
    J[..., 0, 2], J[..., 1, 2] = -ry, rx
    return u, J


def _elements(g, U, tangent=True):
    """Internal forces f (..., C, n, 6) [N, N m] of the corotational elements of the group g for the
    node dofs U (..., C, n + 1, 3), their tangents K (..., C, n, 6, 6) (None without ``tangent``),
    basic forces (N, M1, M2) (..., C, n, 3) and strain energies (..., C, n) [J].  The chord's
    stretch and rotation are formed from the displacement differences Dl (no cancellation of the
    positions): l - L0 = (2 D0 . Dl + Dl . Dl) / (l + L0), alpha = atan2(D0 x Dl, L0^2 + D0 . Dl)."""
    D0, L0, EI, EA = g.D0, g.L0, g.EI, g.EA
    Dl = U[..., 1:, :2] - U[..., :-1, :2]
    d = D0 + Dl
    l = np.hypot(d[..., 0], d[..., 1])
    c, s = d[..., 0] / l, d[..., 1] / l
    dot = D0[..., 0] * Dl[..., 0] + D0[..., 1] * Dl[..., 1]
    alpha = np.arctan2(D0[..., 0] * Dl[..., 1] - D0[..., 1] * Dl[..., 0], L0 * L0 + dot)
    stretch = (2.0 * dot + (Dl * Dl).sum(axis=-1)) / (l + L0)
    th1, th2 = U[..., :-1, 2] - alpha, U[..., 1:, 2] - alpha
    Nf = EA * stretch / L0
    M1 = EI * (4.0 * th1 + 2.0 * th2) / L0
    M2 = EI * (2.0 * th1 + 4.0 * th2) / L0
    zero = np.zeros_like(c)
    z = np.stack([s, -c, zero, -s, c, zero], axis=-1)
    r = np.stack([-c, -s, zero, c, s, zero], axis=-1)
    zl = z / l[..., None]
    B = np.stack([r, -zl, -zl], axis=-2)
    B[..., 1, 2] += 1.0
    B[..., 2, 5] += 1.0
    basic = np.stack([Nf, M1, M2], axis=-1)
    f = np.einsum("...ki,...k->...i", B, basic)
    energy = 0.5 * Nf * stretch + 0.5 * (M1 * th1 + M2 * th2)
    if not tangent:
        return f, None, basic, energy
    k = EI / L0
    Dm = np.zeros(L0.shape + (3, 3))
    Dm[..., 0, 0] = (EA / L0)
    Dm[..., 1, 1] = Dm[..., 2, 2] = 4.0 * k
    Dm[..., 1, 2] = Dm[..., 2, 1] = 2.0 * k
    K = np.swapaxes(B, -1, -2) @ (Dm @ B)
    K += (Nf / l)[..., None, None] * (z[..., :, None] * z[..., None, :])
    rz = r[..., :, None] * z[..., None, :]
    K += ((M1 + M2) / (l * l))[..., None, None] * (rz + np.swapaxes(rz, -1, -2))
    return f, K, basic, energy


def _assemble(f, K, n):
    """Node forces (..., C, 3 (n + 1)) and the tangent (..., C, 3 (n + 1), 3 (n + 1)) of a chain."""
    R = np.zeros(f.shape[:-2] + (3 * (n + 1),))
    Kg = None if K is None else np.zeros(K.shape[:-3] + (3 * (n + 1), 3 * (n + 1)))
    for e in range(n):
        R[..., 3 * e:3 * e + 6] += f[..., e, :]
        if K is not None:
            Kg[..., 3 * e:3 * e + 6, 3 * e:3 * e + 6] += K[..., e, :, :]
    return R, Kg


class Frames:
    """The structure: ``bodies``, ``columns``, gravity g [m/s^2] (downwards), and an optional ground
    slider with friction (``slider`` = body name, mu, mu0) along x; ``ground`` the base motion
    (friction_events.Ground: accel(t) [m/s^2] along x, rec_piece(t) its linear pieces)."""

    def __init__(self, bodies, columns, g=9.81, slider=None, mu=0.0, mu0=0.0, ground=None):
        self.bodies = list(bodies)
        self.bi = {b.name: i for i, b in enumerate(self.bodies)}
        self.columns = list(columns)
        self.g = float(g)
        self.slider, self.mu, self.mu0 = slider, float(mu), float(mu0)
        self.ground = ground
        self.free = [3 * i + k for i, b in enumerate(self.bodies) for k in range(3) if k not in b.locked]
        self.Mdiag = np.concatenate([[b.m, b.m, b.J] for b in self.bodies])
        by_n = {}
        for c in self.columns:
            by_n.setdefault(int(c.n), []).append(c)
        self.groups = [_Group(cs, self.bi, self.bodies) for cs in by_n.values()]
        self.newton_solves = 0          # column solves (one per force evaluation)
        self.newton_iterations = 0

    # -- the columns, condensed --------------------------------------------------------------------------
    def _solve(self, q, store=True, full=True, tol=1e-10, maxit=40):
        """The columns at the body dofs q (..., 3 nb) (any leading batch shape): their inner nodes by
        Newton, until the correction is <= tol (translations over the element length, rotations in
        rad; the error after it is ~ 25 tol^2, 25 ~ EA L0^2 / (24 EI) the columns' nonlinearity:
        round-off).  An unbatched q starts from the last solution moved by its linear sensitivity
        to the ends, S = -K_ii^-1 K_ie (so the first correction is of second order in the step) and,
        with ``store``, stores the solution back.  ``full``: the forces are evaluated at the
        converged nodes; else the ends' forces are the last evaluation's plus K_ei du (the same to
        O(du^2)).  Returns Q (..., 3 nb) the columns' generalised forces on the bodies [N, N m],
        {column name: basic forces (..., n, 3) (N, M1, M2) per element}, strain energy (...,) [J]
        (these two of the last Newton evaluation without ``full``)."""
        q = np.asarray(q, float)
        batch = q.shape[:-1]
        nb = len(self.bodies)
        qe = np.concatenate([q.reshape(batch + (nb, 3)), np.zeros(batch + (1, 3))], axis=-2)
        Qe = np.zeros(batch + (nb + 1, 3))
        basics, E = {}, np.zeros(batch)
        for g in self.groups:
            n, C = g.n, len(g.cols)
            ua, Ja = _ends(qe, g.ia, g.ra)
            ub, Jb = _ends(qe, g.ib, g.rb)
            U = np.empty(batch + (C, n + 1, 3))
            U[..., 0, :], U[..., n, :], U[..., 1:n, :] = ua, ub, g.nodes
            ends_now = np.concatenate([ua, ub], axis=-1)
            if not batch and g.S is not None:
                U[:, 1:n, :] += (g.S @ (ends_now - g.ends)[:, :, None]).reshape(C, n - 1, 3)
            inner = slice(3, 3 * n)
            ends = np.r_[0:3, 3 * n:3 * n + 3]
            du = None
            for _ in range(maxit if n > 1 else 0):
                f, K, basic, en = _elements(g, U)
                R, Kg = _assemble(f, K, n)
                rhs = np.concatenate([-R[..., inner, None], Kg[..., inner, :][..., ends]], axis=-1)
                X = np.linalg.solve(Kg[..., inner, inner], rhs)
                du = X[..., 0]
                U[..., 1:n, :] += du.reshape(batch + (C, n - 1, 3))
                self.newton_iterations += 1
                d3 = du.reshape(batch + (C, n - 1, 3))
                size = max(float((np.abs(d3[..., :2]) / g.L0[:, :, None]).max()), float(np.abs(d3[..., 2]).max()))
                if size <= tol:
                    break
            else:
                if n > 1:
                    raise RuntimeError(f"columns {[c.name for c in g.cols]}: Newton did not converge ({size:.3g})")
            if full or du is None:
                f, _, basic, en = _elements(g, U, tangent=False)
                R, _ = _assemble(f, None, n)
                Rend = R[..., ends]
            else:
                Rend = R[..., ends] + (Kg[..., ends, :][..., inner] @ du[..., None])[..., 0]
            if store and not batch:
                g.nodes = U[:, 1:n, :].copy()
                if du is not None:
                    g.S, g.ends = -X[..., 1:], ends_now
            Fa = -np.einsum("...cji,...cj->...ci", Ja, Rend[..., :3])
            Fb = -np.einsum("...cji,...cj->...ci", Jb, Rend[..., 3:])
            for k in range(C):
                Qe[..., g.ia[k], :] += Fa[..., k, :]
                Qe[..., g.ib[k], :] += Fb[..., k, :]
                basics[g.cols[k].name] = basic[..., k, :, :]
            E = E + en.sum(axis=(-1, -2))
        self.newton_solves += 1
        return Qe[..., :nb, :].reshape(batch + (3 * nb,)), basics, E

    def forces(self, q):
        """Q (3 nb,): the columns' generalised forces on the bodies at the body dofs q (all 3 nb)."""
        return self._solve(q, full=False)[0]

    def details(self, q):
        """{column: basic forces (n, 3) = (N, M1, M2) per element [N, N m]}, strain energy [J], and Q
        (for q (3 nb,); a batch q (..., 3 nb) gives batched arrays, the stored nodes untouched)."""
        Q, basic, E = self._solve(q)
        return basic, E, Q

    def moments_max(self, q):
        """{column: largest |M| over its element ends [N m]} at the body dofs q (..., 3 nb)."""
        basic = self._solve(q)[1]
        return {name: np.abs(b[..., 1:]).max(axis=(-1, -2)) for name, b in basic.items()}

    # -- statics ------------------------------------------------------------------------------------------
    def static(self, tol=1e-13):
        """Equilibrium under gravity (body dofs with the free ones solved by Newton with a
        finite-difference tangent of Q; the friction slider's slide held at 0: stuck), stored as
        the start; returns q."""
        q = np.zeros(3 * len(self.bodies))
        W = np.concatenate([[0.0, -b.m * self.g, 0.0] for b in self.bodies])
        held = 3 * self.bi[self.slider] if self.slider else None
        fr = [k for k in self.free if k != held]
        for _ in range(50):
            r = (self.forces(q) + W)[fr]
            Kf = self._tangent(q, fr=fr)
            dq = np.linalg.solve(Kf, r)
            q[fr] += dq
            if np.abs(dq).max() < tol * max(1e-6, np.abs(q).max()):
                break
        self.forces(q)
        self.q_static = q.copy()
        return q

    def _tangent(self, q, h=1e-7, fr=None):
        """-dQ/dq on the free dofs (or those of ``fr``) by central differences (the columns
        re-solved)."""
        fr = self.free if fr is None else fr
        saved = [(g.nodes.copy(), g.S, g.ends) for g in self.groups]
        dq = np.zeros((2 * len(fr), q.size))
        for j, k in enumerate(fr):
            dq[2 * j, k], dq[2 * j + 1, k] = h, -h
        Q = self._solve(q[None, :] + dq)[0][:, fr]
        for g, s in zip(self.groups, saved):
            g.nodes, g.S, g.ends = s
        return -(Q[0::2] - Q[1::2]).T / (2 * h)

    def frequencies(self, held=True):
        """Natural frequencies [Hz] of the motion linearised about the static state (:meth:`static`
        first), the friction slider's slide held (``held``: stuck) or free; a rigid-body mode of a
        free slide shows as 0."""
        ib = 3 * self.bi[self.slider] if self.slider else None
        fr = [k for k in self.free if not (held and k == ib)]
        K = self._tangent(self.q_static, fr=fr)
        m = self.Mdiag[fr]
        w2 = np.linalg.eigvalsh(K / np.sqrt(np.outer(m, m)))
        return np.sqrt(np.abs(w2)) / (2 * np.pi)

    # -- dynamics -------------------------------------------------------------------------------------------
    def normal(self, Q):
        """Normal force [N] of the ground slider on its body: its weight minus the columns' pull."""
        i = self.bi[self.slider]
        return self.bodies[i].m * self.g - Q[..., 3 * i + 1]

    def energy(self, q, v):
        """Mechanical energy [J] at the body dofs q, velocities v (..., 3 nb) relative to the ground:
        kinetic (relative motion) + the columns' strain energy + gravity (m g y of the centroids)."""
        q, v = np.asarray(q, float), np.asarray(v, float)
        E = self._solve(q, store=False)[2]
        kin = 0.5 * (self.Mdiag * v * v).sum(axis=-1)
        grav = self.g * (self.Mdiag[1::3] * q[..., 1::3]).sum(axis=-1)
        return kin + E + grav

    def run(self, t_end, rtol=1e-12, atol=1e-14, method="DOP853", log=None):
        """Integrate from the static state at rest over [0, t_end] [s]; returns a :class:`Run`
        (events, dense pieces, the work of the ground's inertia loads and of friction).  ``rtol``,
        ``atol`` [m, rad, m/s, rad/s] of solve_ivp's local error control (``method``: DOP853, or an
        implicit Radau/BDF with solve_ivp's finite-difference Jacobian); the work integrals carry
        atol = 1e4 atol [J].  ``log(t)``: called at every piece."""
        q0 = self.static()
        nb = len(self.bodies)
        fr = np.array(self.free)
        ib = 3 * self.bi[self.slider] if self.slider else None
        Mf = self.Mdiag[fr]
        rx = np.concatenate([[1.0, 0.0, 0.0] for _ in self.bodies])[fr]
        Wf = np.concatenate([[0.0, -b.m * self.g, 0.0] for b in self.bodies])[fr]
        jb = int(np.nonzero(fr == ib)[0][0]) if self.slider else None
        run = Run(self)
        mode = 0 if self.slider else None
        run.events.append((0.0, "stick" if self.slider else "free"))
        t, q, v = 0.0, q0.copy(), np.zeros(3 * nb)
        work = np.zeros(2)                   # (ground inertia loads, friction) [J]
        cache = {}

        def active(mode):
            """Indices (into fr) of the dofs integrated in this mode."""
            if mode == 0:
                return np.array([j for j, k in enumerate(fr) if k != ib])
            return np.arange(fr.size)

        def unpack(y, act, qbase, vbase):
            qq, vv = qbase.copy(), vbase.copy()
            qq[fr[act]] = y[:act.size]
            vv[fr[act]] = y[act.size:2 * act.size]
            return qq, vv

        def accel(tt, qq, mode):
            """(accelerations of the free dofs, the force that keeps the slide at rest, N): the
            velocities do not enter (no damping); cached for the event functions."""
            key = (float(tt), mode, qq.tobytes())
            if key in cache:
                return cache[key]
            Q = self.forces(qq)
            ag = float(self.ground.accel(tt))
            rhs = Q[fr] + Wf - Mf * rx * ag
            F_req, N = 0.0, 0.0
            if self.slider:
                N = float(self.normal(Q))
                F_req = -rhs[jb]
                if mode:
                    rhs[jb] += -mode * self.mu * N
                else:
                    rhs[jb] = 0.0
            if len(cache) > 8:
                cache.clear()
            cache[key] = out = (rhs / Mf, F_req, N, ag)
            return out

        h_last = None
        while t < t_end - 1e-14:
            act = active(mode)
            na = act.size
            _, _, t_next = self.ground.rec_piece(t)
            t1 = min(t_next, t_end)
            qbase, vbase = q.copy(), v.copy()
            y0 = np.concatenate([q[fr[act]], v[fr[act]], work])
            mx = (Mf * rx)[act]

            def rhs(tt, y, act=act, mode=mode, qbase=qbase, vbase=vbase, na=na, mx=mx):
                qq, vv = unpack(y, act, qbase, vbase)
                a, _, N, ag = accel(tt, qq, mode)
                vel = y[na:2 * na]
                p_ground = -ag * float(mx @ vel)
                p_fric = -mode * self.mu * N * vv[ib] if mode else 0.0
                return np.concatenate([vel, a[act], [p_ground, p_fric]])

            events = []
            if self.slider:
                if mode == 0:
                    def g_plus(tt, y, act=act, qbase=qbase, vbase=vbase):
                        qq, _ = unpack(y, act, qbase, vbase)
                        _, F, N, _ = accel(tt, qq, 0)
                        return self.mu0 * N - F

                    def g_minus(tt, y, act=act, qbase=qbase, vbase=vbase):
                        qq, _ = unpack(y, act, qbase, vbase)
                        _, F, N, _ = accel(tt, qq, 0)
                        return self.mu0 * N + F
                    events = [g_plus, g_minus]
                else:
                    jv = na + int(np.nonzero(fr[act] == ib)[0][0])

                    def g_vel(tt, y, jv=jv, mode=mode):
                        return mode * y[jv]
                    events = [g_vel]
                for e in events:
                    e.terminal, e.direction = True, -1
            at = np.full(y0.size, float(atol))
            at[-2:] = 1e4 * atol
            opts = {"first_step": min(h_last, t1 - t)} if h_last else {}
            sol = solve_ivp(rhs, (t, t1), y0, method=method, rtol=rtol, atol=at, dense_output=True,
                            events=events or None, **opts)
            if sol.status < 0:
                raise RuntimeError(sol.message)
            run.nfev += sol.nfev
            run.steps += sol.t.size - 1
            if sol.t.size >= 3:
                h_last = float(np.diff(sol.t)[-2:].max())
            elif sol.t.size == 2 and not h_last:
                h_last = float(sol.t[1] - sol.t[0])
            te = t1
            hit = sol.status == 1
            if hit:
                k = next(i for i, x in enumerate(sol.t_events) if len(x))
                te = float(sol.t_events[k][0])
                if te - t < 1e-12 * max(1.0, t):
                    raise RuntimeError(f"a friction event at the start of a piece, t = {t}")
            run.pieces.append((t, te, sol.sol, act, qbase.copy(), vbase.copy(), mode))
            yend = sol.sol(te)
            q, v = unpack(yend, act, qbase, vbase)
            work = yend[-2:].copy()
            t = te
            if hit:
                if mode != 0:
                    v[ib] = 0.0
                _, F, N, _ = accel(t, q, 0)
                if mode == 0:
                    mode = -int(np.sign(F))
                elif abs(F) <= self.mu0 * N:
                    mode = 0
                else:
                    mode = -int(np.sign(F))
                run.events.append((t, {0: "stick", 1: "slip+", -1: "slip-"}[mode]))
            if log is not None:
                log(t)
        run.q_end, run.v_end, run.work_end = q, v, work
        return run


@dataclass
class Run:
    frames: Frames
    events: list = field(default_factory=list)
    pieces: list = field(default_factory=list)     # (t0, t1, dense, active, qbase, vbase, mode)
    nfev: int = 0
    steps: int = 0

    def state(self, t, work=False):
        """(q, v) (3 nb, len(t)) at the times t, from the dense outputs (the method's interpolant:
        DOP853's is of order 7); with ``work`` also the work of the ground's inertia loads and of
        friction (2, len(t)) [J]."""
        t = np.atleast_1d(np.asarray(t, float))
        fr = np.array(self.frames.free)
        nb = len(self.frames.bodies)
        Q = np.zeros((3 * nb, t.size))
        V = np.zeros((3 * nb, t.size))
        W = np.zeros((2, t.size))
        starts = np.array([p[0] for p in self.pieces])
        idx = np.clip(np.searchsorted(starts, t, side="right") - 1, 0, len(self.pieces) - 1)
        for k in np.unique(idx):
            sel = np.nonzero(idx == k)[0]
            t0, t1, dense, act, qb, vb, mode = self.pieces[k]
            Y = dense(np.clip(t[sel], t0, t1))
            Q[:, sel] = qb[:, None]
            V[:, sel] = vb[:, None]
            Q[fr[act][:, None], sel[None, :]] = Y[:act.size]
            V[fr[act][:, None], sel[None, :]] = Y[act.size:2 * act.size]
            W[:, sel] = Y[-2:]
        return (Q, V, W) if work else (Q, V)

    def energy_balance(self, t):
        """(E(t) - E(0) - W_ground(t) - W_friction(t)) / max(|W_ground|, E(t) - E(0)) over the times t
        (the mechanical energy from :meth:`Frames.energy`): zero for the exact motion."""
        t = np.atleast_1d(np.asarray(t, float))
        Q, V, W = self.state(t, work=True)
        fr = self.frames
        E = fr.energy(Q.T, V.T)
        E0 = fr.energy(fr.q_static, np.zeros_like(fr.q_static))
        res = E - E0 - W.sum(axis=0)
        scale = max(float(np.abs(W[0]).max()), float(np.abs(E - E0).max()), 1e-300)
        return res / scale
