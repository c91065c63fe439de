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
  their inner nodes are in static equilibrium at every instant (Newton to machine precision from the
  last solution);
* equations of motion of the bodies, by virtual work: M q'' = Q(q) - M r a_g(t) - (0, m g, 0) + F,
  Q the columns' forces on the bodies, F the friction force on the sliding body (stuck: F holds
  x'' = 0, as long as |F| <= mu0 N; slipping in the direction sigma: F = -sigma mu N), N = m_b g -
  Q_y of that body (its vertical reaction);
* integration: scipy's DOP853 (rtol 1e-12 by default) between the record's samples (the input is
  linear in each interval) and the friction events, which solve_ivp locates on its dense output
  (stick: mu0 N -+ F_req = 0; slip: the sliding velocity = 0), then the stick test on the located
  state as in friction_events.py.

The run starts from the static equilibrium under gravity (bodies and inner nodes by Newton), at rest,
the friction support stuck.  The energy balance (kinetic + strain + gravity - work of the ground
inertia loads + friction dissipation) is checked by :meth:`Frames.energy`.
"""
from __future__ import annotations

import math
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
    nodes: np.ndarray = None   # inner node states (n - 1, 3): displacement u, v and rotation


class Frames:
    """The structure: ``bodies``, ``columns``, gravity g [m/s^2] (downwards), and an optional ground
    slider with friction (``slider`` = body name, mu, mu0) along x."""

    def __init__(self, bodies, columns, g=9.81, slider=None, mu=0.0, mu0=0.0, ground=None):
        self.bodies = list(bodies)
        self.bi = {b.name: i for i, b in enumerate(self.bodies)}
        self.columns = list(columns)
        self.g = float(g)
        self.slider, self.mu, self.mu0 = slider, float(mu), float(mu0)
        self.ground = ground               # friction_events.Ground-like: accel(t), rec_piece
        nb = len(self.bodies)
        self.free = [3 * i + k for i, b in enumerate(self.bodies) for k in range(3) if k not in b.locked]
        self.Mdiag = np.concatenate([[b.m, b.m, b.J] for b in self.bodies])
        for c in self.columns:
            c.nodes = np.zeros((c.n - 1, 3))
            c.L0 = float(np.linalg.norm(c.X1 - c.X0)) / c.n
            c.beta0 = math.atan2(*(c.X1 - c.X0)[::-1])
            c.Xref = np.array([c.X0 + (c.X1 - c.X0) * k / c.n for k in range(c.n + 1)])
        self.q_all = np.zeros(3 * nb)
        self.newton_solves = 0

    # -- kinematics of the column ends ---------------------------------------------------------------
    def _end(self, body, X, q):
        """(node dofs (u, v, theta), d(node)/d(body dofs) (3, 3)) of the rod end at the reference
        point X welded to ``body`` (None: ground) for the body dofs q (3 per body)."""
        if body is None:
            return np.zeros(3), None
        i = self.bi[body]
        x, y, th = q[3 * i:3 * i + 3]
        r0 = X - self.bodies[i].c
        c, s = math.cos(th), math.sin(th)
        rx, ry = c * r0[0] - s * r0[1], s * r0[0] + c * r0[1]
        u = np.array([x + rx - r0[0], y + ry - r0[1], th])
        J = np.array([[1.0, 0.0, -ry], [0.0, 1.0, rx], [0.0, 0.0, 1.0]])
        return u, J

    # -- one corotational element ----------------------------------------------------------------------
    @staticmethod
    def _element(Xi, Xj, ui, uj, L0, beta0, EI, EA, tangent=True):
        d = (Xj + uj[:2]) - (Xi + ui[:2])
        l = math.hypot(d[0], d[1])
        c, s = d[0] / l, d[1] / l
        beta = math.atan2(d[1], d[0])
        alpha = (beta - beta0 + math.pi) % (2 * math.pi) - math.pi
        stretch = (l * l - L0 * L0) / (l + L0)
        th1, th2 = ui[2] - alpha, uj[2] - alpha
        Nf = EA * stretch / L0
        M1 = EI * (4 * th1 + 2 * th2) / L0
        M2 = EI * (2 * th1 + 4 * th2) / L0
        z = np.array([s, -c, 0.0, -s, c, 0.0])
        r = np.array([-c, -s, 0.0, c, s, 0.0])
        B = np.array([r, -z / l, -z / l])
        B[1, 2] += 1.0
        B[2, 5] += 1.0
        f = B.T @ np.array([Nf, M1, M2])
        if not tangent:
            return f, None, (Nf, M1, M2)
        D = np.array([[EA / L0, 0, 0], [0, 4 * EI / L0, 2 * EI / L0], [0, 2 * EI / L0, 4 * EI / L0]])
        K = B.T @ D @ B + (Nf / l) * np.outer(z, z) + (M1 + M2) / (l * l) * (np.outer(r, z) + np.outer(z, r))
        return f, K, (Nf, M1, M2)

    def _column(self, col, q, tol=1e-13, maxit=30):
        """Solve the inner nodes of ``col`` for the body dofs q; returns (forces on the bodies' dofs
        (3 nb,), element basic forces [(N, M1, M2)], strain energy)."""
        ua, Ja = self._end(col.a, col.X0, q)
        ub, Jb = self._end(col.b, col.X1, q)
        n = col.n
        X = col.Xref
        U = np.vstack([ua, col.nodes, ub])
        prev = math.inf
        for it in range(maxit):
            if n == 1:
                break
            R = np.zeros((n + 1) * 3)
            K = np.zeros(((n + 1) * 3, (n + 1) * 3))
            for e in range(n):
                f, k, _ = self._element(X[e], X[e + 1], U[e], U[e + 1], col.L0, col.beta0, col.EI, col.EA)
                R[3 * e:3 * e + 6] += f
                K[3 * e:3 * e + 6, 3 * e:3 * e + 6] += k
            inner = slice(3, 3 * n)
            du = np.linalg.solve(K[inner, inner], -R[inner])
            U[1:n] += du.reshape(-1, 3)
            # size of the correction: translations by the element length, rotations as they are
            size = max(float(np.abs(du[0::3]).max()) / col.L0, float(np.abs(du[1::3]).max()) / col.L0,
                       float(np.abs(du[2::3]).max()))
            if size <= tol * 1e-3 or (it >= 2 and size >= 0.5 * prev):
                break                  # converged, or stalled at round-off
            prev = size
        else:
            raise RuntimeError(f"column {col.name}: Newton did not converge")
        col.nodes = U[1:n].copy()
        self.newton_solves += 1
        # final forces and energy at the converged state
        R = np.zeros((n + 1) * 3)
        basic, energy = [], 0.0
        for e in range(n):
            f, _, bf = self._element(X[e], X[e + 1], U[e], U[e + 1], col.L0, col.beta0, col.EI, col.EA, tangent=False)
            R[3 * e:3 * e + 6] += f
            basic.append(bf)
            Nf, M1, M2 = bf
            th = np.linalg.solve(np.array([[4, 2], [2, 4.0]]) * col.EI / col.L0, [M1, M2])
            energy += 0.5 * Nf * Nf * col.L0 / col.EA + 0.5 * (M1 * th[0] + M2 * th[1])
        Q = np.zeros(3 * len(self.bodies))
        if col.a is not None:
            i = self.bi[col.a]
            Q[3 * i:3 * i + 3] -= Ja.T @ R[:3]
        if col.b is not None:
            i = self.bi[col.b]
            Q[3 * i:3 * i + 3] -= Jb.T @ R[-3:]
        return Q, basic, energy

    def forces(self, q):
        """Q (3 nb,): the columns' generalised forces on the bodies at the body dofs q (all 3 nb)."""
        Q = np.zeros(3 * len(self.bodies))
        for col in self.columns:
            Q += self._column(col, q)[0]
        return Q

    def details(self, q):
        """{column: [(N, M1, M2) per element]}, strain energy, and Q."""
        out, E, Q = {}, 0.0, np.zeros(3 * len(self.bodies))
        for col in self.columns:
            Qc, basic, e = self._column(col, q)
            out[col.name], E, Q = basic, E + e, Q + Qc
        return out, E, Q

    # -- statics ------------------------------------------------------------------------------------------
    def static(self, tol=1e-13):
        """Equilibrium under gravity (body dofs with the free ones solved by Newton with a
        finite-difference tangent of Q), stored as the start; returns q."""
        q = np.zeros(3 * len(self.bodies))
        W = np.concatenate([[0.0, -b.m * self.g, 0.0] for b in self.bodies])
        fr = self.free
        for _ in range(50):
            r = (self.forces(q) + W)[fr]
            Kf = self._tangent(q)
            dq = np.linalg.solve(Kf, r)
            q[fr] += dq
            if np.abs(dq).max() < tol * max(1e-6, np.abs(q).max()):
                break
        self.q_static = q.copy()
        return q

    def _tangent(self, q, h=1e-7):
        """-dQ/dq on the free dofs by central differences (the columns re-solved)."""
        fr = self.free
        K = np.zeros((len(fr), len(fr)))
        saved = [c.nodes.copy() for c in self.columns]
        for j, k in enumerate(fr):
            dq = np.zeros_like(q)
            dq[k] = h
            Qp = self.forces(q + dq)[fr]
            Qm = self.forces(q - dq)[fr]
            K[:, j] = -(Qp - Qm) / (2 * h)
            for c, s in zip(self.columns, saved):
                c.nodes = s.copy()
        return K

    # -- dynamics -------------------------------------------------------------------------------------------
    def normal(self, Q):
        """Normal force [N] of the ground slider on its body: its weight minus the columns' pull."""
        i = self.bi[self.slider]
        return self.bodies[i].m * self.g - Q[3 * i + 1]

    def run(self, t_end, rtol=1e-12, atol=1e-14, sample=1e-3):
        """Integrate from the static state at rest; returns a :class:`Run` (events, samples)."""
        q0 = self.static()
        nb = len(self.bodies)
        fr = np.array(self.free)
        ib = 3 * self.bi[self.slider] if self.slider else None
        Mf = self.Mdiag[fr]
        rx = np.concatenate([[1.0, 0.0, 0.0] for _ in self.bodies])[fr]
        Wf = np.concatenate([[0.0, -b.m * self.g, 0.0] for b in self.bodies])[fr]
        run = Run(self)
        mode = 0 if self.slider else None
        run.events.append((0.0, "stick" if self.slider else "free"))
        t, q, v = 0.0, q0.copy(), np.zeros(3 * nb)

        def active(mode):
            """Indices (into fr) of the dofs integrated in this mode."""
            if mode == 0:
                return np.array([j for j, k in enumerate(fr) if k != ib])
            return np.arange(fr.size)

        def unpack(y, act, qbase, vbase):
            qq, vv = qbase.copy(), vbase.copy()
            qq[fr[act]] = y[:act.size]
            vv[fr[act]] = y[act.size:]
            return qq, vv

        def accel(tt, qq, vv, mode):
            Q = self.forces(qq)
            ag = float(self.ground.accel(tt))
            rhs = Q[fr] + Wf - Mf * rx * ag
            F_req, N = 0.0, 0.0
            if self.slider:
                N = self.normal(Q)
                jb = int(np.nonzero(fr == ib)[0][0])
                F_req = -rhs[jb]             # the force that keeps the slide at rest
                if mode:
                    rhs[jb] += -mode * self.mu * N
                else:
                    rhs[jb] = 0.0
            return rhs / Mf, F_req, N

        while t < t_end - 1e-14:
            act = active(mode)
            a_, q_, t_next = self.ground.rec_piece(t)
            t1 = min(t_next, t_end)
            qbase, vbase = q.copy(), v.copy()
            y0 = np.concatenate([q[fr[act]], v[fr[act]]])

            def rhs(tt, y, act=act, mode=mode, qbase=qbase, vbase=vbase):
                qq, vv = unpack(y, act, qbase, vbase)
                a, _, _ = accel(tt, qq, vv, mode)
                return np.concatenate([y[act.size:], a[act]])

            events = []
            if self.slider:
                if mode == 0:
                    def g_plus(tt, y, act=act, qbase=qbase, vbase=vbase):
                        qq, vv = unpack(y, act, qbase, vbase)
                        _, F, N = accel(tt, qq, vv, 0)
                        return self.mu0 * N - F

                    def g_minus(tt, y, act=act, qbase=qbase, vbase=vbase):
                        qq, vv = unpack(y, act, qbase, vbase)
                        _, F, N = accel(tt, qq, vv, 0)
                        return self.mu0 * N + F
                    events = [g_plus, g_minus]
                else:
                    jv = act.size + int(np.nonzero(fr[act] == ib)[0][0])

                    def g_vel(tt, y, jv=jv, mode=mode):
                        return mode * y[jv]
                    events = [g_vel]
                for e in events:
                    e.terminal, e.direction = True, -1
            sol = solve_ivp(rhs, (t, t1), y0, method="DOP853", rtol=rtol, atol=atol, dense_output=True,
                            events=events or None)
            if sol.status < 0:
                raise RuntimeError(sol.message)
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
            t = te
            if hit:
                if mode != 0:
                    v[ib] = 0.0
                _, F, N = accel(t, q, np.where(np.arange(v.size) == ib, 0.0, v), 0)
                if mode == 0:
                    mode = -int(np.sign(F))
                elif abs(F) <= self.mu0 * N:
                    mode = 0
                else:
                    mode = -int(np.sign(F))
                run.events.append((t, {0: "stick", 1: "slip+", -1: "slip-"}[mode]))
        run.q_end, run.v_end = q, v
        return run


@dataclass
class Run:
    frames: Frames
    events: list = field(default_factory=list)
    pieces: list = field(default_factory=list)     # (t0, t1, dense, active, qbase, vbase, mode)

    def state(self, t):
        """(q, v) (3 nb, len(t)) at the times t, from the dense outputs (DOP853's 7th-order
        interpolant)."""
        t = np.atleast_1d(np.asarray(t, float))
        fr = np.array(self.frames.free)
        nb = len(self.frames.bodies)
        Q = np.zeros((3 * nb, t.size))
        V = np.zeros((3 * nb, t.size))
        starts = np.array([p[0] for p in self.pieces])
        idx = np.clip(np.searchsorted(starts, t, side="right") - 1, 0, len(self.pieces) - 1)
        for k in np.unique(idx):
            sel = np.nonzero(idx == k)[0]
            t0, t1, dense, act, qb, vb, mode = self.pieces[k]
            Y = dense(np.clip(t[sel], t0, t1))
            Q[:, sel] = qb[:, None]
            V[:, sel] = vb[:, None]
            Q[fr[act][:, None], sel[None, :]] = Y[:act.size]
            V[fr[act][:, None], sel[None, :]] = Y[act.size:]
        return Q, V
