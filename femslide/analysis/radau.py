"""One step of Radau IIA (3 stages, order 5) on the constrained equations of motion.

The equations of femslide.analysis.transient, first order in y = (q, v) with the multipliers mu::

    q' = v,    M(q) v' + F(t, q, v, mu) = 0,    g(q) = 0,

F the model's forces (femslide.model.discrete.Model.system: elements, springs, loads, the joints'
G^T mu), the damping C v, the centripetal and ground-acceleration inertia terms of the bodies
(femslide.model.mass) and friction's slip forces; M may be singular (massless dofs - rods with
rhoA = 0, node rotations - follow the masses quasi-statically: their rows are statics).  Units are
the model's (lengths by Lref, forces by Fref), time in seconds.

Collocation at the Radau points c = ((4 - sqrt 6)/10, (4 + sqrt 6)/10, 1) (Hairer & Wanner, Solving
ODEs II, IV.8; RADAU5): with the stage increments Z_i = (Q_i - q_n, V_i - v_n) and W = A^-1 of the
Butcher matrix, the stage derivatives are (W Z)_i / h, and the step solves for every stage i

    (W ZQ)_i - h V_i = 0,    M(Q_i) (W ZV)_i / h + F(t_i, Q_i, V_i, mu_i) = 0,    g(Q_i) = 0.

The step's end is the third stage (stiffly accurate: L-stable, stiff components - a massive rod's
axial and high bending modes - are put on their quasi-static response at every step, where
generalized-alpha only damps them).  Order 5 in the positions (2s - 1) of an ODE and of the
positions of index-3 constraints; the velocities and multipliers of constraints between massive
parts converge at lower order (Hairer & Wanner VII.4).

The stage equations are solved by the one Newton loop (femslide.analysis.newton) with the simplified
Newton matrix of RADAU5, frozen at the step's start: with T^-1 W T = diag(mu_r, [[a, b], [-b, a]]) the
3-stage linear system decouples into one real and one complex system of the model's size,

    [[K + lam (C + D_v) + lam^2 M, G^T], [G, 0]],   lam = mu_r / h  and  (a - i b) / h,

(K, G the model's tangent, D_v the centripetal velocity terms), each factorised once per step.
The local error estimate is RADAU5's (the embedded order-3 formula filtered through the real
system); the dense output is the collocation polynomial of degree 3 (events are located on it);
the energy integrals use the Radau quadrature (exact for degree 4).
"""
from __future__ import annotations

import math

import numpy as np
import scipy.sparse as sp

from femslide.analysis.generalized_alpha import State, add_coo
from femslide.model.linalg import BandMatrix, Factorized
from femslide.model.state import ElementState

S6 = math.sqrt(6.0)
C_RK = np.array([(4.0 - S6) / 10.0, (4.0 + S6) / 10.0, 1.0])
A_RK = np.array([[(88.0 - 7.0 * S6) / 360.0, (296.0 - 169.0 * S6) / 1800.0, (-2.0 + 3.0 * S6) / 225.0],
                 [(296.0 + 169.0 * S6) / 1800.0, (88.0 + 7.0 * S6) / 360.0, (-2.0 - 3.0 * S6) / 225.0],
                 [(16.0 - S6) / 36.0, (16.0 + S6) / 36.0, 1.0 / 9.0]])
W_RK = np.linalg.inv(A_RK)
B_RK = A_RK[2].copy()             # quadrature weights at the stages (stiffly accurate)
E_RK = np.array([-13.0 - 7.0 * S6, -13.0 + 7.0 * S6, -1.0]) / 3.0   # RADAU5's error combination
MU_REAL = 3.0 + 3.0 ** (2.0 / 3.0) - 3.0 ** (1.0 / 3.0)
MU_COMPLEX = (3.0 + 0.5 * (3.0 ** (1.0 / 3.0) - 3.0 ** (2.0 / 3.0))
              - 0.5j * (3.0 ** (5.0 / 6.0) + 3.0 ** (7.0 / 6.0)))
T_RK = np.array([[0.09443876248897524, -0.14125529502095421, 0.03002919410514742],
                 [0.25021312296533332, 0.20412935229379994, -0.38294211275726192],
                 [1.0, 1.0, 0.0]])
TI_RK = np.linalg.inv(T_RK)
# the collocation polynomial through 0 and the stages: y(t_n + x h) = y_n + Z^T P [x, x^2, x^3]
P_RK = np.array([[13.0 / 3.0 + 7.0 * S6 / 3.0, -23.0 / 3.0 - 22.0 * S6 / 3.0, 10.0 / 3.0 + 5.0 * S6],
                 [13.0 / 3.0 - 7.0 * S6 / 3.0, -23.0 / 3.0 + 22.0 * S6 / 3.0, 10.0 / 3.0 - 5.0 * S6],
                 [1.0 / 3.0, -8.0 / 3.0, 10.0 / 3.0]])
EPS = float(np.finfo(float).eps)
ORDER = 4          # the local error estimate is O(h^4): steps follow err^(-1/4)


def _complex_copy(A):
    if isinstance(A, BandMatrix):
        return BandMatrix(A.pattern, A.ab.astype(complex))
    if isinstance(A, np.ndarray):
        return A.astype(complex)
    return A.astype(complex).tocsc()


def _real_copy(A):
    if isinstance(A, BandMatrix):
        return BandMatrix(A.pattern, A.ab.copy())
    return A.copy()


class RadauMatrix:
    """The simplified Newton matrix of the stage equations, as factorised real and complex blocks:
    ``solve(r)`` maps a residual of the stacked stages to the Newton correction of the stacked
    unknowns (femslide.model.linalg.solve_linear dispatches to it)."""

    def __init__(self, sysm, real, complex_):
        self.s, self.real, self.complex = sysm, real, complex_

    def _block(self, fact, lam, rv, rq, rm):
        s = self.s
        top = rv + s.Cv @ rq + lam * (s.M @ rq)
        x = fact.solve(np.concatenate([top, rm]))
        dq = x[:s.nq]
        return dq, lam * dq - rq, x[s.nq:]

    def solve(self, r):
        s = self.s
        nq, nc, h = s.nq, s.nc, s.h
        Rv = r[:3 * nq].reshape(3, nq)
        Rq = r[3 * nq:6 * nq].reshape(3, nq)
        Rm = r[6 * nq:].reshape(3, nc)
        Tv, Tq, Tm = TI_RK @ Rv, (TI_RK @ Rq) / h, TI_RK @ Rm
        q0, v0, m0 = self._block(self.real, MU_REAL / h, Tv[0], Tq[0], Tm[0])
        qc, vc, mc = self._block(self.complex, MU_COMPLEX / h, Tv[1] + 1j * Tv[2], Tq[1] + 1j * Tq[2],
                                 Tm[1] + 1j * Tm[2])
        dQ = T_RK @ np.array([q0, qc.real, qc.imag])
        dV = T_RK @ np.array([v0, vc.real, vc.imag])
        dM = T_RK @ np.array([m0, mc.real, mc.imag])
        return np.concatenate([dQ.ravel(), dV.ravel(), dM.ravel()])

    def error(self, rv, rq, rm):
        """The real system's solution for the right-hand side (rv, rq, rm) (the error estimate)."""
        return self._block(self.real, MU_REAL / self.s.h, rv, rq, rm)


class CoupledMatrix:
    """The exact Newton matrix of the three coupled stages, eliminated to (dq_i, dmu_i) (size
    3 (n_q + n_c)), factorised: ``solve(r)`` maps a stacked residual to the Newton correction."""

    def __init__(self, sysm, A):
        self.s = sysm
        self.fact = Factorized(A)

    def solve(self, r):
        s = self.s
        nq, nc, h = s.nq, s.nc, s.h
        n = nq + nc
        Rv = r[:3 * nq].reshape(3, nq)
        Rq = r[3 * nq:6 * nq].reshape(3, nq)
        Rm = r[6 * nq:].reshape(3, nc)
        WRq = W_RK @ Rq
        rhs = np.empty(3 * n)
        for i in range(3):
            rhs[i * n:i * n + nq] = Rv[i] + s.Cv_i[i] @ Rq[i] / h + s.M_i[i] @ WRq[i] / (h * h)
            rhs[i * n + nq:(i + 1) * n] = Rm[i]
        x = self.fact.solve(rhs).reshape(3, n)
        dQ, dM = x[:, :nq], x[:, nq:]
        dV = (W_RK @ dQ - Rq) / h
        return np.concatenate([dQ.ravel(), dV.ravel(), dM.ravel()])


class RadauSystem:
    """The stage equations of one Radau IIA step in the interface femslide.analysis.newton.newton
    expects (``n_q``: the stacked force rows, ``rotation_dofs``, ``system``); unknowns
    Y = [ZQ (3 n_q), ZV (3 n_q), mu (3 n_c)], residual rows [forces, h x kinematics, constraints]."""

    order = ORDER

    def __init__(self, model, masses, C, ground, extra=None):
        self.model, self.masses, self.C, self.ground = model, masses, C, ground
        self.nq, self.nc = model.n_q, model.n_c
        self.n_q = 3 * self.nq
        self.n = 6 * self.nq + 3 * self.nc
        self.extra = extra or []
        self.Csr = C.tocsr() if C is not None else None
        self.Crows, self.Ccols, self.Cvals = (C.row, C.col, C.data) if C is not None else (None, None, None)
        rot = model.rotation_dofs()
        self._rot = np.concatenate([i * self.nq + rot for i in range(3)]).astype(np.intp)
        self.m_max = float(max(np.abs(masses.matrix(np.zeros(model.n_q))[2]).max(initial=0.0), 0.0))
        self.roundoff_floor = True
        self.exact = True      # the exact Newton matrix of the coupled stages (else RADAU5's simplified one)
        self.previous = None   # the last accepted step's dense output (start, h, polynomials)

    def rotation_dofs(self):
        return self._rot

    # -- the step ---------------------------------------------------------------------------------
    def prepare(self, s: State, h: float):
        """Set the step from state s with step h: the frozen Jacobian, factorised."""
        m, nq = self.model, self.nq
        self.s, self.h = s, h
        self.t = s.t + C_RK * h
        self.qn, self.mun = s.y[:nq], s.y[nq:]
        if self.ground is not None:
            e = self.ground.direction / m.Lref
            self.ag = [self.ground.accel(t) * e for t in self.t]
        else:
            self.ag = [None, None, None]
        es = ElementState(s.alpha)
        _, A0, info = m.system(s.y, es, 1.0, None, True)
        self.noise0 = float(info["noise"])
        # the inertia's parts at the step's start: M, the velocity derivative D_v (centripetal), the
        # position derivative D_q
        rows, cols, base = self.masses.inertia(self.qn, s.v, s.acc, 0.0, 0.0, self.ag[0])[1]
        vm = self.masses.inertia(self.qn, s.v, s.acc, 1.0, 0.0, self.ag[0])[1][2] - base
        vd = self.masses.inertia(self.qn, s.v, s.acc, 0.0, 1.0, self.ag[0])[1][2] - base
        self.M = sp.csr_matrix((vm, (rows, cols)), shape=(nq, nq))
        Cv = sp.csr_matrix((vd, (rows, cols)), shape=(nq, nq))
        if self.Csr is not None:
            Cv = Cv + self.Csr
        self.Cv = Cv.tocsr()
        fr = [ex(s.y, s.v, 0.0)[1] for ex in self.extra]
        parts = []
        for lam, A in ((MU_REAL / h, _real_copy(A0)), (MU_COMPLEX / h, _complex_copy(A0))):
            coos = [(rows, cols, base + lam * vd + lam * lam * vm)] + fr
            if self.Crows is not None:
                coos.append((self.Crows, self.Ccols, lam * self.Cvals))
            parts.append(Factorized(add_coo(A, *coos)))
        self.matrix = RadauMatrix(self, *parts)
        self.elements = [ElementState(s.alpha) for _ in range(3)]
        vmax = float(np.abs(s.v).max(initial=0.0))
        self.noise_in = EPS * 30.0 * self.m_max * vmax / h   # round-off of M (W ZV)/h (|W| ~ 30)

    def predictor(self):
        """The start of Newton: the previous step's collocation polynomial continued (when it ended
        where this step starts, in the same layout), else a Taylor start from the step's start."""
        s, h, nq, ny = self.s, self.h, self.nq, self.s.y.size
        p = self.previous
        if p is not None and p[0] + p[1] == s.t and p[3].size == ny + nq:
            t0, h0, Zc, base = p
            x = (self.t - t0) / h0
            Yp = base[None, :] + np.column_stack([x, x * x, x * x * x]) @ Zc   # (3, n_y + n_q)
            ZQ, MU, ZV = Yp[:, :nq] - s.y[:nq], Yp[:, nq:ny], Yp[:, ny:] - s.v
        else:
            c = C_RK[:, None] * h
            ZQ = c * s.v + 0.5 * c * c * s.acc
            ZV = c * s.acc
            MU = np.tile(self.mun, (3, 1))
        return np.concatenate([ZQ.ravel(), ZV.ravel(), MU.ravel()])

    def split(self, Y):
        nq, nc = self.nq, self.nc
        return Y[:3 * nq].reshape(3, nq), Y[3 * nq:6 * nq].reshape(3, nq), Y[6 * nq:].reshape(3, nc)

    def system(self, Y, elements, lam=1.0, control=None, jacobian=True, dense=False):
        m, nq, h = self.model, self.nq, self.h
        ZQ, ZV, MU = self.split(Y)
        Q = self.qn + ZQ
        V = self.s.v + ZV
        ACC = (W_RK @ ZV) / h
        Rv = np.empty((3, nq))
        Rm = np.empty((3, self.nc))
        fmax = noise = 0.0
        exact = jacobian and self.exact
        if exact:
            n = nq + self.nc
            big = np.zeros((3 * n, 3 * n))
            W2 = W_RK @ W_RK
            self.M_i, self.Cv_i = [], []
        for i in range(3):
            y = np.concatenate([Q[i], MU[i]])
            r, Ai, info = m.system(y, self.elements[i], 1.0, None, exact, dense=True)
            f, (ir, ic, base) = self.masses.inertia(Q[i], V[i], ACC[i], 0.0, 0.0, self.ag[i])
            if exact:
                vm = self.masses.inertia(Q[i], V[i], ACC[i], 1.0, 0.0, self.ag[i])[1][2] - base
                vd = self.masses.inertia(Q[i], V[i], ACC[i], 0.0, 1.0, self.ag[i])[1][2] - base
                Mi = sp.csr_matrix((vm, (ir, ic)), shape=(nq, nq))
                Ci = sp.csr_matrix((vd, (ir, ic)), shape=(nq, nq))
                if self.Csr is not None:
                    Ci = (Ci + self.Csr).tocsr()
                self.M_i.append(Mi)
                self.Cv_i.append(Ci)
                big[i * n:(i + 1) * n, i * n:(i + 1) * n] += Ai
                np.add.at(big, (i * n + ir, i * n + ic), base)
                Md, Cd = Mi.toarray(), Ci.toarray()
                for j in range(3):
                    big[i * n:i * n + nq, j * n:j * n + nq] += (W2[i, j] / (h * h)) * Md + (W_RK[i, j] / h) * Cd
                for ex in self.extra:
                    er, ec, ev = ex(y, V[i], 0.0)[1]
                    np.add.at(big, (i * n + er, i * n + ec), ev)
            rv = r[:nq] + f
            if self.Csr is not None:
                rv += self.Csr @ V[i]
            for ex in self.extra:
                rv += ex(y, V[i], 0.0)[0]
            Rv[i] = rv
            Rm[i] = r[nq:]
            fmax = max(fmax, info["fmax"])
        elements.trial = self.elements[2].trial
        Rq = W_RK @ ZQ - h * V
        r = np.concatenate([Rv.ravel(), Rq.ravel(), Rm.ravel()])
        noise = self.noise0
        if self.roundoff_floor and self.noise_in > 1e-6 * (1.0 + fmax):
            noise += self.noise_in
        info = {"fmax": fmax, "noise": noise, "lam": 1.0}
        if exact:
            return r, CoupledMatrix(self, big), info
        return r, (self.matrix if jacobian else None), info

    # -- what a converged step gives ------------------------------------------------------------
    def end(self, Y):
        """(y, v, acc) at the step's end (the third stage)."""
        ZQ, ZV, MU = self.split(Y)
        return (np.concatenate([self.qn + ZQ[2], MU[2]]), self.s.v + ZV[2], (W_RK[2] @ ZV) / self.h)

    def stages(self, Y):
        """[(t_i, y_i, v_i)] of the three stages."""
        ZQ, ZV, MU = self.split(Y)
        return [(self.t[i], np.concatenate([self.qn + ZQ[i], MU[i]]), self.s.v + ZV[i]) for i in range(3)]

    def error(self, Y):
        """RADAU5's local error estimate of the positions and velocities (n_q each): the embedded
        order-3 solution's difference filtered through the real system."""
        ZQ, ZV, _ = self.split(Y)
        h = self.h
        ZEq, ZEv = (E_RK @ ZQ) / h, (E_RK @ ZV) / h
        eq, ev, _ = self.matrix.error(self.M @ (self.s.acc + ZEv), self.s.v + ZEq, np.zeros(self.nc))
        return eq, ev

    def dense(self, Y):
        """The collocation polynomial of the step: a function t -> (y, v) on [t_n, t_n + h]."""
        ZQ, ZV, MU = self.split(Y)
        s, h = self.s, self.h
        Zq, Zv, Zm = ZQ.T @ P_RK, ZV.T @ P_RK, (MU - self.mun).T @ P_RK
        y0, v0 = s.y, s.v
        nq = self.nq

        def at(t):
            x = (t - s.t) / h
            X = np.array([x, x * x, x * x * x])
            y = y0.copy()
            y[:nq] += Zq @ X
            y[nq:] += Zm @ X
            return y, v0 + Zv @ X
        return at

    def remember(self, Y):
        """Keep the accepted step's collocation polynomial for the next step's predictor."""
        ZQ, ZV, MU = self.split(Y)
        Z = np.concatenate([ZQ, MU - self.mun, ZV], axis=1)   # increments of [q, mu, v] at the stages
        Zc = (Z.T @ P_RK).T                                     # (3, n): coefficients of x, x^2, x^3
        self.previous = (self.s.t, self.h, Zc, np.concatenate([self.s.y, self.s.v]))

    def work(self, Y, ground_power, loss_power):
        """(work of the ground motion, energy dissipated) over the step: the Radau quadrature of
        their powers at the stages (exact for polynomials of degree 4)."""
        W = D = 0.0
        for b, (t, y, v) in zip(B_RK, self.stages(Y)):
            W += b * ground_power(y[:self.nq], v, t)
            D += b * loss_power(y, v)
        return W * self.h, D * self.h
