"""Implicit time integration of a declared structure: the constrained (index-3) equations of motion

    M(q) q'' + C q' + f(q) + G(q)^T mu = -M a_g(t) e,     g(q) = 0,

on the model's own assembly (:meth:`femslide.model.Model.system`: f the internal forces, springs and
dead loads, G the exact joint constraints) and solved by the statics' Newton loop
(:func:`femslide.newton.newton`) once per step.  Units: the model's (lengths by Lref, forces by Fref),
time in seconds.

Integrator: generalized-alpha for constrained mechanical systems (Arnold & Bruls 2007; the
Chung-Hulbert parameters of spectral radius ``RHO_INF`` at infinite frequency): the equations hold
exactly at t_{n+1} (positions on the constraint manifold, no drift; massless dofs - rods with
rhoA = 0, node rotations - in static equilibrium at every step), with an acceleration-like variable a,

    q_{n+1} = q_n + h v_n + h^2 ((1/2 - beta) a_n + beta a_{n+1}),
    v_{n+1} = v_n + h ((1 - gamma) a_n + gamma a_{n+1}),
    (1 - alpha_m) a_{n+1} + alpha_m a_n = (1 - alpha_f) q''_{n+1} + alpha_f q''_n.

Second order in q, v and the multipliers.  Newton's unknowns are q_{n+1} and mu_{n+1}; the iteration
matrix is [[M beta' + C gamma' + K, G^T], [G, 0]] with beta' = (1 - alpha_m)/((1 - alpha_f) beta h^2),
gamma' = gamma / (beta h), plus the derivatives of a body's inertia when its frame origin is not its
centroid (femslide/mass.py).  Step size: adaptive, with the local error estimate of the positions
e = c3 h^2 (a_{n+1} - a_n), c3 = (alpha_m - alpha_f)/2 + beta - 1/6 (Taylor expansion of the
position update), filtered through the step's iteration matrix S as RADAU5 filters its estimate,
e_f = S^-1 (M c_acc + C c_vel) e (the effect of a position error at the step's start on the step's
solution: unchanged in the modes the step resolves, omega h << 1, and ~1/(omega h)^2 in stiff modes
the step does not resolve and rho_inf damps - a massive rod's axial and high bending modes, whose
raw estimate is noise that rejected half the steps), over the dofs with mass, kept below
SAFETY = 0.5 times ``tolerance`` times the amplitude of the recent motion (the largest
displacement from the static state, remembered over about one period of the lowest mode; floor
1e-6 Lref): a step with a larger error is repeated with a smaller h, the next step is
h (0.9 / err)^(1/3) (between 0.2 h and 2 h).  Under a recorded ground motion the steps end on the
record's sample times, so that the input is linear within every step.

Damping: Rayleigh, C = alpha M0 + beta K0 with M0 and K0 the mass matrix and the tangent at the
static state (constant).  Energy balance: kinetic + potential (strain, springs, dead loads including
gravity) + dissipated - work of the ground-motion inertia loads (integral of F_g . v); dissipated is
the integral of the damping and friction power (v.C v + mu N |s'|) plus the energy released by the
jumps of massless parts at friction events (``_requilibrate``); the integrals per step by 3-point
Gauss on the cubic Hermite interpolant of the step (:func:`_step_work`); reported relative to the
largest energy of the run.
"""
from __future__ import annotations

import math
import os
import time
from dataclasses import dataclass, field

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")  # small LUs: threads only cost (see dynamics.py)

import numpy as np  # noqa: E402
import scipy.sparse as sp  # noqa: E402

from .errors import BadInput, SolverFailure  # noqa: E402
from .model import BandMatrix, solve_linear  # noqa: E402
from .newton import newton  # noqa: E402

EPS = float(np.finfo(float).eps)
RHO_INF = 0.9          # spectral radius at infinite frequency (a little numerical damping of the
                       # highest modes, needed by the multipliers of index-3 constraints)
NEWTON_TOL = 1e-10     # Newton's tolerance at tight tolerances (and for the consistent starts) ...
NEWTON_TOL_MAX = 1e-8  # ... and at loose ones: 1e-3 * tolerance in between
SAFETY = 0.5           # the local error estimate is held below SAFETY * tolerance
START_STEP = 1e-2      # the tiny step of a consistent (re)start, relative to the step size: its
                       # q'' is O(START_STEP) off, and shorter ones lose digits to round-off
MAX_STEPS = 2_000_000  # safety net (the a-priori work bound of femslide/simulation.py comes first)


def parameters(rho_inf=RHO_INF):
    """(alpha_m, alpha_f, gamma, beta) of Chung & Hulbert for the spectral radius rho_inf."""
    am = (2.0 * rho_inf - 1.0) / (rho_inf + 1.0)
    af = rho_inf / (rho_inf + 1.0)
    gamma = 0.5 + af - am
    beta = 0.25 * (gamma + 0.5) ** 2
    return am, af, gamma, beta


def error_constant(rho_inf=RHO_INF):
    """c3 of the local position error c3 h^2 (a_{n+1} - a_n) (Taylor expansion of the update)."""
    am, af, gamma, beta = parameters(rho_inf)
    return abs(0.5 * (am - af) + beta - 1.0 / 6.0)


def add_coo(A, *parts):
    """A + the COO entries ``parts`` = (rows, cols, vals), ... (which must lie in the Jacobian's
    pattern), for A dense, banded or sparse (one sparse sum for all parts)."""
    if isinstance(A, np.ndarray):
        for rows, cols, vals in parts:
            np.add.at(A, (rows, cols), vals)
        return A
    if isinstance(A, BandMatrix):
        p = A.pattern
        for rows, cols, vals in parts:
            pr, pc = p.inv[rows], p.inv[cols]
            np.add.at(A.ab, (p.kl + p.ku + pr - pc, pc), vals)
        return A
    rows, cols, vals = (np.concatenate(x) for x in zip(*parts))
    return (A + sp.csc_matrix((vals, (rows, cols)), shape=A.shape)).tocsc()


@dataclass
class State:
    """The integrator's state at t: y = [q, mu], velocities v, accelerations acc (q''), the
    acceleration-like variable a, chord rotations alpha (the corotational reference)."""

    t: float
    y: np.ndarray
    v: np.ndarray
    acc: np.ndarray
    a: np.ndarray
    alpha: np.ndarray


class StepSystem:
    """The model's equations with the inertia, damping and ground terms of one step, in the interface
    :func:`femslide.newton.newton` expects (``n_q``, ``rotation_dofs``, ``system``)."""

    def __init__(self, model, masses, C, ground, extra=None):
        self.model, self.masses, self.C, self.ground = model, masses, C, ground
        self.n_q, self.n = model.n_q, model.n
        self.Crows, self.Ccols, self.Cvals = (C.row, C.col, C.data) if C is not None else (None, None, None)
        self.Csr = C.tocsr() if C is not None else None
        self.extra = extra or []   # callables (y, v, c_vel) -> (f, (rows, cols, vals)) (friction)
        self.params = parameters()
        self.roundoff_floor = True   # off in the consistent starts (their tiny step is solved fully)
        self.m_max = float(max(np.abs(masses.matrix(np.zeros(model.n_q))[2]).max(initial=0.0), 0.0))

    def rotation_dofs(self):
        return self.model.rotation_dofs()

    def prepare(self, s: State, h: float):
        """Set the step from state s with step h."""
        am, af, gamma, beta = self.params
        self.s, self.h, self.t1 = s, h, s.t + h
        self.qn = s.y[:self.n_q]
        self.base = self.qn + h * s.v + h * h * (0.5 - beta) * s.a
        self.c_a = 1.0 / (beta * h * h)       # d a_{n+1} / d q_{n+1}
        self.c_acc = (1.0 - am) / (1.0 - af) * self.c_a
        self.c_vel = gamma * h * self.c_a
        self.noise_in = EPS * self.c_acc * self.m_max * (float(np.abs(self.qn).max()) + float(np.abs(self.base).max()))
        ag = self.ground.accel(self.t1) if self.ground is not None else 0.0
        # m/s^2 -> model lengths / s^2
        self.ag_vec = None if self.ground is None else ag * self.ground.direction / self.model.Lref

    def kinematics(self, q):
        """(a, v, acc) at t_{n+1} for the trial positions q."""
        am, af, gamma, beta = self.params
        s, h = self.s, self.h
        a1 = (q - self.base) * self.c_a
        v1 = s.v + h * ((1.0 - gamma) * s.a + gamma * a1)
        acc1 = ((1.0 - am) * a1 + am * s.a - af * s.acc) / (1.0 - af)
        return a1, v1, acc1

    def predictor(self):
        """Start of Newton: q'' as at t_n."""
        am, af, gamma, beta = self.params
        s, h = self.s, self.h
        a1 = (s.acc - am * s.a) / (1.0 - am)
        y = s.y.copy()
        y[:self.n_q] = self.base + h * h * beta * a1
        return y

    def system(self, y, alpha_ref, lam=1.0, control=None, jacobian=True, dense=False):
        r, A, info = self.model.system(y, alpha_ref, 1.0, None, jacobian)
        q = y[:self.n_q]
        _, v1, acc1 = self.kinematics(q)
        f, coo = self.masses.inertia(q, v1, acc1, self.c_acc, self.c_vel, self.ag_vec)
        coos = [coo]   # the Jacobian's extra entries (one sparse sum for all)
        r[:self.n_q] += f
        if self.Csr is not None:
            r[:self.n_q] += self.Csr @ v1
            coos.append((self.Crows, self.Ccols, self.c_vel * self.Cvals))
        for ex in self.extra:
            fe, coo = ex(y, v1, self.c_vel)
            r[:self.n_q] += fe
            coos.append(coo)
        # round-off of the inertia term: q'' ~ (q - base) / (beta h^2) resolves q only to eps |q|;
        # when that level is above 1e-6 of the forces (steps far shorter than the motion's time
        # scale) Newton accepts a residual at this level, as for the element forces' round-off
        # (with |q| from the step's start: it moves by a step's increment, irrelevant at this level)
        if self.roundoff_floor and self.noise_in > 1e-6 * (1.0 + info["fmax"]):
            info["noise"] = info["noise"] + self.noise_in
        if jacobian:
            A = add_coo(A, *coos)
            self.last_matrix = A   # the iteration matrix of the latest Jacobian (the error filter's)
        return r, A, info

    def filtered_error(self, e):
        """The local error estimate e (n_q,) filtered through the iteration matrix S of the step (the
        last Jacobian of its Newton iteration), S^-1 (M c_acc + C c_vel) e: how a position error at
        the step's start moves the step's solution.  Components in modes with omega h << 1 pass
        unchanged, stiff ones (omega h >> 1: unresolved by design, damped by rho_inf) are attenuated
        by ~ 1/(omega h)^2, creeping modes of heavy damping pass while the step resolves them, and the
        result is tangent to the constraints (Hairer & Wanner, Solving ODEs II, IV.8: the estimate
        of RADAU5)."""
        r, c, v = self.masses.matrix(self.qn)
        rhs = np.bincount(r, weights=v * e[c] * self.c_acc, minlength=self.n)
        if self.Csr is not None:
            rhs[:self.n_q] += self.c_vel * (self.Csr @ e)
        return solve_linear(self.last_matrix, rhs)[:self.n_q]


def _consistent_start(sysm, s: State, h_s: float) -> State:
    """The state at rest with consistent accelerations and multipliers: one tiny step h_s from
    a = q'' = 0 gives q''(h_s) = q''(0) + O(h_s), massless dofs included (they follow the masses
    quasi-statically), and the multipliers that hold the released structure (Arnold & Bruls start
    the integrator with a_0 = q''_0; a start with a_0 = 0 leaves a non-decaying jump in a that the
    error estimate would see at every step)."""
    # from a = q'' = 0: a dof held by a constraint then gets q'' = 0 and its multiplier the force
    # that holds it (the stick test needs that), the free massive dofs get the q'' the equations give
    z = np.zeros_like(s.v)
    s = State(s.t, s.y, s.v, z, z.copy(), s.alpha)
    for _ in range(8):
        sysm.prepare(s, h_s)
        sysm.roundoff_floor = False
        try:
            y, info = newton(sysm, sysm.predictor(), s.alpha, tol=NEWTON_TOL, maxit=20)
        finally:
            sysm.roundoff_floor = True
        if info.converged:
            _, _, acc = sysm.kinematics(y[:sysm.n_q])
            y0 = s.y.copy()
            y0[sysm.n_q:] = y[sysm.n_q:]
            return State(s.t, y0, s.v, acc.copy(), acc.copy(), s.alpha)
        h_s *= 4.0
    raise SolverFailure("simulate: no consistent initial acceleration (Newton failed on the start step)",
                        info.history)


def _locate(attempt, fr, phi0, cross, h, cand, max_iter=60):
    """The step size at which the first event function of the crossing joints reaches zero (Illinois
    on h in (0, h], each trial a step from the same state); returns (h_event, candidate)."""
    def Phi(c):
        return float(np.min(np.where(cross, fr.phi(c[0], c[3]), np.inf)))

    lo, f_lo = 0.0, float(np.min(phi0[cross]))
    hi, f_hi = h, Phi(cand)
    best = (hi, cand)
    side = 0
    for _ in range(max_iter):
        if hi - lo <= 1e-14 * max(1.0, h) * 100 or f_hi == 0.0:
            break
        x = hi - f_hi * (hi - lo) / (f_hi - f_lo) if f_hi != f_lo else 0.5 * (lo + hi)
        if not lo < x < hi:
            x = 0.5 * (lo + hi)
        c, _ = attempt(x)
        if c is None:
            x = 0.5 * (lo + hi)
            c, _ = attempt(x)
            if c is None:
                break
        fx = Phi(c)
        if fx < 0.0:
            hi, f_hi, best = x, fx, (x, c)
            if side == -1:
                f_lo *= 0.5
            side = -1
        else:
            lo, f_lo = x, fx
            best_lo = (x, c)
            if side == 1:
                f_hi *= 0.5
            side = 1
            if fx == 0.0:
                return best_lo
        if abs(fx) <= 1e-15 * (1.0 + abs(f_lo)):
            return (x, c)
    return best


class _Light:
    """The equations of the massless ("light") dofs of a step system's model with the massive dofs
    held and the velocities ``v`` held: static forces, friction slip forces and the Rayleigh damping
    forces C v (as in the step's equations), on the rows and columns of the light dofs and of the
    constraint rows that involve them.  With the masses held, constraints may be redundant (a rod end
    welded to a massive piece and also in the slider of a massive deck): the light positions are
    still determined, the split of the multipliers is not.  The redundant rows are dropped up front
    (:func:`_independent_rows` on the constraint gradients, which are O(1) in model units), so the
    system solved is regular (LU) whatever the rod's stiffness."""

    def __init__(self, sysm, y, alpha, v, heavy):
        self.sysm, self.model, self.v = sysm, sysm.model, v
        n_q = self.model.n_q
        light = np.setdiff1d(np.arange(n_q), heavy).astype(np.intp)
        self.first = self.full(y, alpha)
        A = self.first[1]
        G = A[n_q:, light]
        rows = np.nonzero(np.abs(G).max(axis=1) > 0.0)[0] if light.size else np.zeros(0, np.intp)
        rows = rows[_independent_rows(G[rows])]
        self.cols = np.concatenate([light, n_q + rows]).astype(np.intp)
        self.heavy, self.n_q = heavy, light.size

    def full(self, y, alpha_ref, jacobian=True):
        """The whole model's residual (static, slip and damping forces) and its dense Jacobian."""
        m, sysm = self.model, self.sysm
        r, A, info = m.system(y, alpha_ref, 1.0, None, jacobian, dense=True)
        for ex in sysm.extra:
            fe, coo = ex(y, None, 0.0)
            r[:m.n_q] += fe
            if jacobian:
                A = add_coo(A, coo)
        if sysm.Csr is not None:
            r[:m.n_q] += sysm.Csr @ self.v
        return r, A, info

    def solve(self, y, alpha, maxit=30):
        """Newton on the light unknowns from y: (y, alpha, residual history); SolverFailure when it
        does not converge."""
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
                return y, info["alpha"], hist
            if len(hist) > 4 and hist[-1] <= 1e-7 and hist[-1] > 0.5 * min(hist[-4:-1]):
                self.first = (r, A, info)
                return y, info["alpha"], hist   # stagnated at the round-off level (as newton.newton)
            y[c] -= solve_linear(np.ascontiguousarray(A[np.ix_(c, c)]), rc)
            r, A, info = self.full(y, alpha)
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


def _requilibrate(sysm, s: State):
    """The massless dofs at a change of the friction modes: solved for their equilibrium in the new
    modes with the massive dofs (and the velocities) held where they are, and their velocities made
    consistent with the massive ones (the time derivative of that equilibrium).  This is the
    quasi-static limit of a vanishing slide mass with the jump's energy lost on the way: a massless
    slide that breaks away with mu0 > mu moves at once to the position where its spring and elastic
    forces equal the sliding friction (and stops there, with no overshoot).  Returns the state and
    the potential energy the jump releases (model units; dissipated)."""
    heavy = sysm.masses.massive_dofs()
    if heavy.size == sysm.n_q:
        return s, 0.0
    light = _Light(sysm, s.y, s.alpha, s.v, heavy)
    y, alpha, _ = light.solve(s.y, s.alpha)
    released = sysm.model.potential(s.y, s.alpha) - sysm.model.potential(y, alpha)
    rate = light.rates(s.v[heavy])
    v = s.v.copy()
    v[light.cols[:light.n_q]] = rate[:light.n_q]
    return State(s.t, y, v, s.acc, s.a, alpha), released


def _restart(fr, s: State, old_stuck, h_s):
    """The state s (laid out for the stuck joints ``old_stuck``) carried into the current modes'
    layout (lock multipliers kept, new ones 0), its massless parts re-solved
    (:func:`_requilibrate`) and its accelerations made consistent: (state, step system, energy
    released by jumps of massless parts)."""
    s = State(s.t, fr.convert(s.y, old_stuck, fr.stuck()), s.v, s.acc, s.a, s.alpha)
    sysm = fr.system()
    s, released = _requilibrate(sysm, s)
    return _consistent_start(sysm, s, h_s), sysm, released


def _switch(fr, s: State, i, h_s):
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


def _settle(fr, s: State, h_s, pending, old_stuck):
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
    s, sysm, released = _restart(fr, State(s.t, s.y, v, s.acc, s.a, s.alpha), old_stuck, h_s)
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


# 3-point Gauss-Legendre on [0, 1]: exact for polynomials of degree 5
_GAUSS_T = 0.5 + 0.5 * math.sqrt(0.6) * np.array([-1.0, 0.0, 1.0])
_GAUSS_W = np.array([5.0, 8.0, 5.0]) / 18.0


def _step_work(s: State, y1, v1, h, ground_power, loss_power, n_q):
    """The work of the ground-motion loads and the energy dissipated by damping and friction over
    the step from s to (y1, v1) at t + h: their powers integrated by 3-point Gauss on the cubic
    Hermite interpolant of the positions (from the positions and velocities at both ends; velocities
    its derivative, O(h^3)) and the multipliers interpolated linearly; in the step's friction modes.
    (The trapezoidal rule on the end powers overstated the energy error of friction and forced runs
    about twice.)"""
    q0, qe, v0 = s.y[:n_q], y1[:n_q], s.v
    dq = qe - q0
    W = D = 0.0
    for tau, w in zip(_GAUSS_T, _GAUSS_W):
        t2, t3 = tau * tau, tau * tau * tau
        q = q0 + (3.0 * t2 - 2.0 * t3) * dq + h * ((t3 - 2.0 * t2 + tau) * v0 + (t3 - t2) * v1)
        v = (6.0 * tau - 6.0 * t2) / h * dq + (3.0 * t2 - 4.0 * tau + 1.0) * v0 + (3.0 * t2 - 2.0 * tau) * v1
        y = (1.0 - tau) * s.y + tau * y1
        y[:n_q] = q
        W += w * ground_power(q, v, s.t + tau * h)
        D += w * loss_power(y, v)
    return W * h, D * h


@dataclass
class Integration:
    """Outcome of :func:`integrate`: the record rows of ``observe``, step counts and the energy
    balance."""

    rows: list = field(default_factory=list)
    steps: int = 0
    rejected: int = 0
    newton_iterations: int = 0
    energy_balance: float = 0.0
    energy: dict = field(default_factory=dict)


def integrate(model, masses, y0, alpha0, t_end, tolerance, C=None, ground=None, observe=None,
              h0=None, h_max=None, max_steps=MAX_STEPS, wall_limit=None, progress=None, q_ref=None,
              friction=None, period=None):
    """Integrate from rest at the state (y0, alpha0) (model units) to ``t_end`` [s].

    ``C``: Rayleigh damping matrix (scipy COO, model units) or None; ``ground``: a
    :class:`femslide.ground.Ground` or None; ``observe(t, y, alpha, v)`` -> a row recorded at every
    accepted step (t = 0 included); ``h0``: first step [s]; ``h_max``: largest step; ``q_ref``: the
    static equilibrium (default: the start), from which the displacements that scale the error are
    measured; ``friction``: a :class:`femslide.friction.Friction` (stick/slip modes and events) or
    None; ``period`` [s]: the time over which the error scale (the motion's amplitude) is
    remembered (default: the whole run).  Raises SolverFailure when a step cannot be completed
    (Newton fails at the smallest step)
    or the step count or wall time runs out."""
    c3 = error_constant()
    n_q = model.n_q
    heavy = masses.massive_dofs()
    if heavy.size == 0:
        raise BadInput("simulate: nothing in the structure has mass (give bodies a mass or rods a rhoA)")
    zero = np.zeros(n_q)
    s = State(0.0, y0.copy(), zero.copy(), zero.copy(), zero.copy(), alpha0.copy())
    q_static = (y0[:n_q] if q_ref is None else q_ref[:n_q]).copy()
    amp = max(1e-6, float(np.abs(y0[heavy] - q_static[heavy]).max()))
    amp_all = amp
    h = h0 or 1e-3 * t_end
    h_max = h_max or t_end
    h_min = 1e-12 * max(t_end, 1.0)
    stops = None
    if ground is not None and ground.times is not None:
        stops = ground.times[(ground.times > 0.0) & (ground.times < t_end)]
    out = Integration()
    V0 = model.potential(y0, alpha0)
    T0 = masses.kinetic(y0[:n_q], s.v)
    D = W = 0.0
    J = 0.0            # of D: the energy released by jumps of massless parts at friction events
    Emax = 0.0
    bal = 0.0
    Csr = C.tocsr() if C is not None else None
    fr = friction
    # Newton's residual (relative to the internal forces) well below the step's error budget
    newton_tol = min(NEWTON_TOL_MAX, max(NEWTON_TOL, 1e-3 * tolerance))

    def ground_power(q, v, t):
        if ground is None:
            return 0.0
        g = ground.accel(t) * ground.direction / model.Lref
        return float(np.dot(masses.ground_load(q, g), v))

    def loss_power(y, v):
        P = float(v @ (Csr @ v)) if Csr is not None else 0.0
        return P + (fr.power(y, v) if fr is not None else 0.0)

    def attempt(sysm, s, h):
        sysm.prepare(s, h)
        y, info = newton(sysm, sysm.predictor(), s.alpha, tol=newton_tol, maxit=12)
        out.newton_iterations += info.iterations
        if not info.converged:
            return None, info
        a1, v1, acc1 = sysm.kinematics(y[:n_q])
        return (y, info.alpha, a1, v1, acc1), info

    h_s = START_STEP * h
    if fr is None:
        sysm = StepSystem(model, masses, C, ground)
        s = _consistent_start(sysm, s, h_s)
    else:
        s, sysm, released = _settle(fr, s, h_s, list(range(len(fr.joints))), ())
        D += released
        J += released
    if observe:
        out.rows.append(observe(0.0, s.y, s.alpha, s.v))
    t0 = time.perf_counter()
    switches, t_switch = 0, None
    ph_of = None   # the state the event functions ph were evaluated at
    while s.t < t_end * (1 - 1e-14):
        if out.steps + out.rejected >= max_steps:
            raise SolverFailure(f"simulate: the step count limit {max_steps} was reached at t = {s.t:.6g} s "
                                f"(tolerance too tight or the motion too fast for this t_end)")
        if wall_limit and time.perf_counter() - t0 > wall_limit:
            raise SolverFailure(f"simulate: the wall-time limit {wall_limit:g} s was reached at t = {s.t:.6g} s")
        h = min(h, h_max, t_end - s.t)
        t_stop = None
        if stops is not None:
            # a step ends on the record's next sample (the input is linear within a step: a kink of
            # the record inside a step was smoothed over, and its work not what the steps applied)
            # (a sample within 1e-9 h_max ahead counts as reached: an event may end a step there)
            k = int(np.searchsorted(stops, s.t + 1e-9 * h_max, side="right"))
            if k < stops.size:
                gap = float(stops[k] - s.t)
                # (gap carries the round-off of t: a step capped at the record's dt may fall short of
                # it by ulps, which must not count as a sliver)
                if h >= gap - 1e-9 * gap - 16.0 * EPS * max(1.0, abs(s.t)):
                    h, t_stop = gap, float(stops[k])
                elif h > 0.5 * gap:
                    h = 0.5 * gap   # two even steps rather than one and a sliver
        if fr is not None:
            # a joint whose mode no longer holds at the start of a step (two events at one instant):
            # switch it now
            if ph_of is not s:
                ph, ph_of = fr.phi(s.y, s.v), s
            # (a joint that has just started to slip is not late at that instant: a massless slide's
            # velocity follows the masses, and at a reversal it may still carry the old sign by a
            # hair; if it really moves the other way, the next step's start finds it late)
            fresh = [fr.started_slip(i, s.t) for i in range(ph.size)]
            late = [i for i in np.nonzero(ph < -1e-10)[0] if not fresh[i]]
            if late:
                switches = switches + 1 if s.t == t_switch else 1
                t_switch = s.t
                if switches > 2 * len(fr.joints) + 2:
                    raise SolverFailure(f"simulate: the friction joints' stick/slip modes do not settle at "
                                        f"t = {s.t:.9g} s")
                s, sysm, released = _switch(fr, s, int(late[0]), START_STEP * h)
                D += released
                J += released
                continue
        cand, info = attempt(sysm, s, h)
        if cand is None:
            out.rejected += 1
            if h <= h_min:
                raise SolverFailure(f"simulate: Newton failed at t = {s.t:.6g} s with the smallest step "
                                    f"{h:.3g} s: {info.reason}", info.history)
            h *= 0.25
            continue
        y, alpha1, a1, v1, acc1 = cand
        q = y[:n_q]
        e = np.zeros(n_q)   # (the massless dofs' a is no estimate of anything: left out)
        e[heavy] = c3 * h * h * (a1[heavy] - s.a[heavy])
        est = np.abs(sysm.filtered_error(e)[heavy])
        disp = float(np.abs(q[heavy] - q_static[heavy]).max())
        err = float(est.max()) / (SAFETY * tolerance * max(amp, disp, 1e-3 * amp_all)) if est.size else 0.0
        if err > 1.0 and h > h_min:
            out.rejected += 1
            h *= max(0.2, 0.9 * err ** (-1.0 / 3.0))
            continue
        event = None
        h_next = h * min(2.0, max(0.2, 0.9 * max(err, 1e-12) ** (-1.0 / 3.0)))
        if fr is not None:
            phi0, phi1 = ph, fr.phi(y, v1)   # (ph: the modes' event functions at s, above)
            cross = (phi1 < 0.0) & (phi0 >= 0.0)
            if cross.any():
                h_ev, cand = _locate(lambda hh, sy=sysm, st=s: attempt(sy, st, hh), fr, phi0, cross, h, cand)
                y, alpha1, a1, v1, acc1 = cand
                q = y[:n_q]
                event = int(np.argmin(np.where(cross, fr.phi(y, v1), np.inf)))
                h_next = max(h, 10 * h_ev) if h_ev < 0.1 * h else h
                h = h_ev
        disp = float(np.abs(q[heavy] - q_static[heavy]).max())
        amp_all = max(amp_all, disp)
        # the amplitude of the recent motion (a decaying memory of one period): a decaying or
        # growing motion keeps its relative accuracy
        amp = max(disp, amp * math.exp(-h / period) if period else amp, 1e-6)
        t1 = t_stop if (t_stop is not None and event is None) else s.t + h
        if ground is not None or Csr is not None or fr is not None:   # (else no work, no loss)
            dW, dD = _step_work(s, y, v1, h, ground_power, loss_power, n_q)
            W += dW
            D += dD
        s = State(t1, y, v1, acc1, a1, alpha1)
        if fr is not None and event is None:
            ph, ph_of = phi1, s   # (evaluated at this state's (y, v1) above)
        out.steps += 1
        if event is not None:
            s, sysm, released = _switch(fr, s, event, START_STEP * h_next)
            D += released
            J += released
        T = masses.kinetic(s.y[:n_q], s.v)         # (after a switch: the state it left)
        V = model.potential(s.y, s.alpha) - V0
        Emax = max(Emax, abs(T), abs(V), abs(D), abs(W))
        bal = max(bal, abs(T + V + D - W - T0))
        if observe:
            out.rows.append(observe(t1, s.y, s.alpha, s.v))
        if progress:
            progress(t1)
        h = h_next
    out.energy_balance = bal / Emax if Emax > 0 else 0.0
    out.energy = {"kinetic": masses.kinetic(s.y[:n_q], s.v) * model.Fref * model.Lref,
                  "potential": (model.potential(s.y, s.alpha) - V0) * model.Fref * model.Lref,
                  "dissipated": D * model.Fref * model.Lref, "work_in": W * model.Fref * model.Lref,
                  "jump_loss": J * model.Fref * model.Lref}
    return out
