"""One step of generalized-alpha on the constrained equations of motion, and a consistent start.

:class:`StepSystem` is the model's equations plus the inertia, damping, friction and ground terms of
one step, in the interface Newton expects; :class:`State` is the integrator's state at a time;
:func:`_consistent_start` gives the accelerations and multipliers at rest (Arnold & Bruls 2007);
:func:`_step_work` integrates the powers of the ground motion and of the losses over a step.  The
scheme, its parameters and the error estimate are described in femslide.analysis.transient.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from femslide.analysis.newton import newton
from femslide.errors import SolverFailure
from femslide.model.linalg import BandMatrix, solve_linear
from femslide.model.state import ElementState

EPS = float(np.finfo(float).eps)
RHO_INF = 0.9          # spectral radius at infinite frequency (a little numerical damping of the
                       # highest modes, needed by the multipliers of index-3 constraints)
NEWTON_TOL = 1e-10     # Newton's tolerance at tight tolerances (and for the consistent starts) ...
NEWTON_TOL_MAX = 1e-8  # ... and at loose ones: 1e-3 * tolerance in between
SAFETY = 0.5           # the local error estimate is held below SAFETY * tolerance
START_STEP = 1e-2      # the tiny step of a consistent (re)start, relative to the step size: its
                       # q'' is O(START_STEP) off, and shorter ones lose digits to round-off


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
    acceleration-like variable a, and the elements' history (femslide.model.state.ElementState,
    committed at this state: the reference of the steps tried from it)."""

    t: float
    y: np.ndarray
    v: np.ndarray
    acc: np.ndarray
    a: np.ndarray
    elements: ElementState

    @property
    def alpha(self) -> np.ndarray:
        """The committed chord rotations [rad]."""
        return self.elements.committed


class StepSystem:
    """The model's equations with the inertia, damping and ground terms of one step, in the interface
    :func:`femslide.analysis.newton.newton` expects (``n_q``, ``rotation_dofs``, ``system``)."""

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

    def system(self, y, elements, lam=1.0, control=None, jacobian=True, dense=False):
        r, A, info = self.model.system(y, elements, 1.0, None, jacobian)
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
    if hasattr(sysm, "end"):   # a Radau step system: its own tiny step
        return _consistent_radau(sysm, State(s.t, s.y, s.v, z, z.copy(), s.elements), h_s)
    s = State(s.t, s.y, s.v, z, z.copy(), s.elements)
    for _ in range(8):
        sysm.prepare(s, h_s)
        sysm.roundoff_floor = False
        try:
            y, info = newton(sysm, sysm.predictor(), s.elements, tol=NEWTON_TOL, maxit=20)
        finally:
            sysm.roundoff_floor = True
            s.elements.revert()   # (the positions stay: only the accelerations and multipliers are taken)
        if info.converged:
            _, _, acc = sysm.kinematics(y[:sysm.n_q])
            y0 = s.y.copy()
            y0[sysm.n_q:] = y[sysm.n_q:]
            return State(s.t, y0, s.v, acc.copy(), acc.copy(), s.elements)
        h_s *= 4.0
    raise SolverFailure("simulate: no consistent initial acceleration (Newton failed on the start step)",
                        info.history)


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


def _consistent_radau(sysm, s: State, h_s: float) -> State:
    """The consistent start of :func:`_consistent_start` by a tiny Radau step (femslide.analysis.radau)."""
    for _ in range(8):
        sysm.prepare(s, h_s)
        sysm.roundoff_floor = False
        try:
            Y, info = newton(sysm, sysm.predictor(), s.elements, tol=NEWTON_TOL, maxit=20)
        finally:
            sysm.roundoff_floor = True
            s.elements.revert()
        if info.converged:
            y, _, acc = sysm.end(Y)
            y0 = s.y.copy()
            y0[sysm.nq:] = y[sysm.nq:]
            sysm.previous = None
            return State(s.t, y0, s.v, acc.copy(), acc.copy(), s.elements)
        h_s *= 4.0
    raise SolverFailure("simulate: no consistent initial acceleration (Newton failed on the start step)",
                        info.history)

