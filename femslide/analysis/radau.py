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
axial and high bending modes - are put on their quasi-static response at every step; the resolved
motion is damped only at order 5: the energy of a conservative structure is kept to the tolerance).
Order 5 in the positions (2s - 1) of an ODE and of the positions of index-3 constraints; the
velocities and multipliers of constraints between massive parts converge at lower order (Hairer & Wanner VII.4).

The stage equations are solved by the one Newton loop (femslide.analysis.newton) with the exact
Newton matrix of the three coupled stages: with the velocity corrections eliminated,
dv_i = ((W dq)_i + r_i) / h, the unknowns are (dq_i, dmu_i) and stage i's rows are

    K_i dq_i + (1/h) C_i (W dq)_i + (1/h^2) M_i (W^2 dq)_i + G_i^T dmu_i = ...,   G_i dq_i = ...,

(K_i, G_i the model's tangent at stage i, C_i the damping and the centripetal velocity terms, M_i
the mass matrix), a matrix of 3 (n_q + n_c) unknowns stored dense, banded or sparse as the model's
Jacobians are.  (RADAU5's simplified Newton, a single matrix frozen at the step's start and
decoupled into one real and one complex system, does not converge on nearly inextensible rods:
the frozen axial stiffness EA of a rod that turns within the step swamps its bending stiffness.)
One exception: the step's first matrix, at the predicted stages, carries in its geometric part
(N zz^T / L of each element) the rods' axial forces at the step's start instead of the predicted
ones (the bending moments' geometric term keeps the predicted stages' moments).  The prediction
stretches a nearly inextensible rod by an error near round-off that EA turns into axial forces up
to 1e4 times the structure's (section 5.2, EA = 1e12 N); in the geometric stiffness they made the
chord steps that follow contract only 5x per step, and most steps assembled a second matrix.  With
the start's forces (exact kinematics, the step's correct axial directions) the chord steps
converge: section 5.2 at tolerance 1e-5 takes 347 Newton iterations for its 101 steps instead of
533.  The residual is always the exact one, so the step's solution is unchanged to
Newton's tolerance.
The local error estimate is RADAU5's (the embedded order-3 formula filtered through
[[K + lam C + lam^2 M, G^T], [G, 0]] at the step's start, lam = mu_r / h); the dense output is the
collocation polynomial of degree 3; the energy integrals use the Radau quadrature (exact for
polynomials of degree 4).
"""
from __future__ import annotations

import math

import numpy as np

from femslide.analysis.newton import newton
from femslide.errors import SolverFailure
from femslide.model.discrete import Model
from femslide.model.linalg import Assembler, Coo, Factorized, complement, coo_mv, kernel_function, member
from femslide.model.state import ElementState, MotionState

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
W2_RK = W_RK @ W_RK
W_FLAT = np.ascontiguousarray(W_RK).ravel()   # (the kernel's w)
# the collocation polynomial through 0 and the stages: y(t_n + x h) = y_n + Z^T P [x, x^2, x^3]
P_RK = np.array([[13.0 / 3.0 + 7.0 * S6 / 3.0, -23.0 / 3.0 - 22.0 * S6 / 3.0, 10.0 / 3.0 + 5.0 * S6],
                 [13.0 / 3.0 - 7.0 * S6 / 3.0, -23.0 / 3.0 + 22.0 * S6 / 3.0, 10.0 / 3.0 - 5.0 * S6],
                 [1.0 / 3.0, -8.0 / 3.0, 10.0 / 3.0]])
EPS = float(np.finfo(float).eps)
ORDER = 4          # the local error estimate is O(h^4): steps follow err^(-1/4)
NEWTON_TOL = 1e-10     # Newton's tolerance at tight tolerances (and for the consistent starts) ...
NEWTON_TOL_MAX = 1e-8  # ... and at loose ones: 1e-3 * tolerance in between
SAFETY = 0.5           # the local error estimate is held below SAFETY * tolerance
START_STEP = 1e-2      # the tiny step of a consistent (re)start, relative to the step size


def constraint_gradient(coo, n_q, n_c, released=()):
    """The constraints' gradient G (n_c, n_q), dense, from a model Jacobian's COO entries (rows,
    cols, vals) (:meth:`femslide.model.discrete.Model.system` with ``dense="coo"``: the constraint
    rows lie beyond n_q), the ``released`` rows (lifted contacts, pooled locks) zero."""
    rows, cols, vals = coo
    G = np.zeros((n_c, n_q))
    sel = (rows >= n_q) & (rows < n_q + n_c) & (cols < n_q)
    np.add.at(G, (rows[sel] - n_q, cols[sel]), vals[sel])
    G[np.asarray(released, dtype=np.intp)] = 0.0
    return G


def _w_times(Z):
    """W Z for the three stages' rows Z (3, m), W = A^-1: row i is W_i0 Z_0 + W_i1 Z_1 + W_i2 Z_2 summed in
    that order, as the kernel sums it (numpy's matmul may fuse or reorder the products)."""
    W = W_RK
    return (W[:, 0:1] * Z[0] + W[:, 1:2] * Z[1]) + W[:, 2:3] * Z[2]


class CoupledMatrix:
    """The exact Newton matrix of the three coupled stages (see the module docstring), factorised:
    ``solve(r)`` maps a residual of the stacked stages to the Newton correction of the stacked
    unknowns (femslide.model.linalg.solve_linear dispatches to it).  ``mass`` and ``vel`` (3, nnz):
    the stages' mass matrices and centripetal velocity terms in the masses' COO order
    (femslide.model.mass.Masses.inertia_parts)."""

    def __init__(self, sysm, A, mass, vel):
        self.s, self.A, self.mass, self.vel = sysm, A, mass, vel
        self.fact = None

    def solve(self, r):
        """The Newton correction for the stacked residual r (factorising at the first call: a
        singular matrix raises there, where Newton reports it)."""
        s = self.s
        nq, nc, h = s.nq, s.nc, s.h
        if self.fact is None:
            self.fact = Factorized(self.A, overwrite=True)   # (A is this matrix's alone)
            self.A = None
            Cv = self.vel if s.Cvals is None else np.concatenate([self.vel, s._Cvals3], axis=1)
            self.Mv, self.Cv = self.mass.ravel(), Cv.ravel()
        n, m3 = nq + nc, 3 * nq
        kern = self.fact.kern
        if s._coupled_solve is not None and kern is not None and r.flags.c_contiguous and r.dtype == np.float64:
            # all of the below in one kernel call, with the factors of the kernel's LU
            out = np.empty(r.size)
            lu, piv, kl, ku = kern
            s._coupled_solve(r, h, W_FLAT, s._Cr, s._Cc, self.Cv, s._Mr, s._Mc, self.Mv, lu, piv, kl, ku,
                             None if kl < 0 else self.fact.pattern.perm, self.fact.rs, self.fact.cs, out)
            return out
        Rq = r[m3:2 * m3]
        WRq = _w_times(Rq.reshape(3, nq)).ravel()
        # the stages' C (W dq) / h and M (W^2 dq) / h^2 with (W dq)_i eliminated, all stages in one
        # bincount each (the entries of a row in the same order as stage by stage), or one kernel call
        if s._coupled_rhs is not None and r.flags.c_contiguous and r.dtype == np.float64:
            rhs = np.empty(3 * n)
            s._coupled_rhs(r, WRq, h, s._Cr, s._Cc, self.Cv, s._Mr, s._Mc, self.Mv, nq, rhs)
        else:
            cp = np.bincount(s._Cr, weights=self.Cv * Rq[s._Cc], minlength=m3)
            mp = np.bincount(s._Mr, weights=self.Mv * WRq[s._Mc], minlength=m3)
            rhs = np.empty((3, n))
            rhs[:, :nq] = (r[:m3] + cp / h + mp / (h * h)).reshape(3, nq)
            rhs[:, nq:] = r[2 * m3:].reshape(3, nc)
            rhs = rhs.ravel()
        x = self.fact.solve(rhs).reshape(3, n)
        out = np.empty(r.size)
        dQ = x[:, :nq]
        out[:m3] = dQ.ravel()
        out[m3:2 * m3] = ((_w_times(dQ) - Rq.reshape(3, nq)) / h).ravel()
        out[2 * m3:] = x[:, nq:].ravel()
        return out


class RadauSystem:
    """The stage equations of one Radau IIA step in the interface femslide.analysis.newton.newton
    expects (``n_q``: the stacked force rows, ``rotation_dofs``, ``system``); unknowns
    Y = [ZQ (3 n_q), ZV (3 n_q), mu (3 n_c)], residual rows [forces, h x kinematics, constraints].
    The friction and lock models of femslide.analysis.stickslip build one per set of friction
    modes."""

    order = ORDER

    def __init__(self, model, masses, C, ground, extra=None, released=None):
        self.model, self.masses, self.C, self.ground = model, masses, C, ground
        # multipliers of lifted contacts (indices among the model's n_c): their rows hold mu = 0
        # instead of the joint's equations (the layout stays; femslide.analysis.stickslip)
        self.released = np.asarray(released if released is not None else [], dtype=np.intp)
        self._rel_pos = None
        self.nq, self.nc = model.n_q, model.n_c
        self.n_q = 3 * self.nq
        self.n = 6 * self.nq + 3 * self.nc
        self.extra = extra or []
        C = Coo.of(C)   # (the damping matrix: a Coo, or scipy's sparse matrix)
        self.C = C
        self.Crows, self.Ccols, self.Cvals = (C.row, C.col, C.data) if C is not None else (None, None, None)
        # the three stages' mass and damping entries stacked (rows and columns offset by the stage):
        # CoupledMatrix.solve's products for all stages at once
        ir, ic = masses.coo_rows, masses.coo_cols
        off = (np.arange(3) * self.nq)[:, None]
        self._Mr, self._Mc = (ir[None, :] + off).ravel(), (ic[None, :] + off).ravel()
        if C is not None:
            ir, ic = np.concatenate([ir, self.Crows]), np.concatenate([ic, self.Ccols])
            self._Cvals3 = np.tile(self.Cvals, (3, 1))
        self._Cr, self._Cc = (ir[None, :] + off).ravel(), (ic[None, :] + off).ravel()
        rot = model.rotation_dofs()
        self._rot = np.concatenate([i * self.nq + rot for i in range(3)]).astype(np.intp)
        self.m_max = float(max(np.abs(masses.matrix(np.zeros(model.n_q))[2]).max(initial=0.0), 0.0))
        self.roundoff_floor = True
        self.previous = None   # the last accepted step's collocation polynomial (the next predictor)
        self.big = None        # the coupled matrix's pattern (built at the first Jacobian)
        self._error_pattern = None   # ... and the error estimate's matrix's
        self._n_first = None   # the axial forces of the step's first matrix (prepare)
        self._coupled = kernel_function("coupled")   # the kernel's writer of the coupled matrix, or None
        self._coupled_rhs = kernel_function("coupled_rhs")   # ... and of CoupledMatrix.solve's right-hand side
        self._coupled_solve = kernel_function("coupled_solve")   # ... or of all of CoupledMatrix.solve
        self._stages = kernel_function("stages")   # the stage states from the unknowns ...
        self._stage_rows = kernel_function("stage_rows")   # ... and the stacked residual from the stages'
        self._error_rhs = kernel_function("error_rhs")   # ... and the error estimate's right-hand side
        # a model assembled by the kernel without Python-evaluated pieces: its Assembler is called directly
        # (not a model whose system is another's: the linearised model's equations are its own)
        pack = getattr(model, "_pack", None)
        self._direct = (self._stages is not None and pack is not None and not pack.python
                        and not self.released.size and type(model).system is Model.system)

    def rotation_dofs(self):
        return self._rot

    def model_system(self, y, elements, jacobian=True, n_geometric=None):
        """The model's residual and COO Jacobian at y (:meth:`femslide.model.discrete.Model.system`,
        ``dense="coo"``; ``n_geometric`` its argument, or None) with the released rows (lifted
        contacts) replaced by mu = 0: residual mu, Jacobian row the unit entry on mu (appended; the
        pattern stays static)."""
        r, coo, info = self.model.system(y, elements, 1.0, None, jacobian, dense="coo", n_geometric=n_geometric)
        rel = self.released
        if not rel.size:
            return r, coo, info
        nq = self.nq
        r[nq + rel] = y[nq + rel]
        if coo is None:
            return r, coo, info
        rows, cols, vals = coo
        if self._rel_pos is None or self._rel_pos[0] is not rows:
            self._rel_pos = (rows, np.nonzero(member(rows, nq + rel))[0])
        vals = vals.copy()
        vals[self._rel_pos[1]] = 0.0
        d = nq + rel
        return r, (np.concatenate([rows, d]), np.concatenate([cols, d]),
                   np.concatenate([vals, np.ones(rel.size)])), info

    def _stage_models(self, Ys, jacobian, n_geometric=None):
        """The model at the three stages Ys (3, n): (residuals (3, n), Jacobian values (3, nnz) in its
        pattern's order or None, {"fmax": the largest, "noise": the last stage's}, the pattern's rows and
        columns), each stage's chord rotations its trial ones: the kernel's Assembler called as
        femslide.model.fast.system calls it (Model.system's wrappers were most of a stage's cost).  For a
        model assembled by the kernel without Python-evaluated pieces and without lifted contacts.
        ``n_geometric``: Model.system's."""
        m = self.model
        kern = m._assembler()
        rows, cols = m._topo.pattern(None)[:2]
        R = np.empty((3, m.n))
        vals = np.empty((3, rows.size)) if jacobian else None
        ne = self.elements[0].committed.size
        alpha = np.empty((3, ne))
        fmax = noise = 0.0
        for i in range(3):
            f, noise = kern.assemble(Ys[i], self.elements[i].committed, alpha[i], 1.0, -1, 0.0, R[i], None, None,
                                     None if vals is None else vals[i], None, None, None, None, None, None, None,
                                     True, n_geometric)
            self.elements[i].trial = alpha[i]
            fmax = max(fmax, f)
        if m._motion_rows.size:   # (Model.system's prescribed motions, at load factor 1)
            R[:, m._motion_rows] += 1.0 * m._motion_vals
        return R, vals, {"fmax": fmax, "noise": 4.0 * noise if jacobian and ne else 0.0}, rows, cols

    def release_dense(self, r, A, y):
        """The released rows of a dense residual r and Jacobian A (the model's) set to mu = 0."""
        if self.released.size:
            k = self.nq + self.released
            r[k] = y[k]
            A[k, :] = 0.0
            A[k, k] = 1.0
        return r, A

    def _pattern(self, model_coo, extra_coo):
        """The coupled matrix's pattern from the model's Jacobian pattern, the inertia's, the damping's
        and the friction terms' (all static)."""
        nq, n = self.nq, self.nq + self.nc
        ir, ic = self.masses.coo_rows, self.masses.coo_cols
        rows, cols = [], []
        for i in range(3):
            o = i * n
            rows += [model_coo[0] + o, ir + o] + [e[0] + o for e in extra_coo]
            cols += [model_coo[1] + o, ic + o] + [e[1] + o for e in extra_coo]
        for i in range(3):
            for j in range(3):
                rows.append(ir + i * n)
                cols.append(ic + j * n)
                if self.Crows is not None:
                    rows.append(self.Crows + i * n)
                    cols.append(self.Ccols + j * n)
        del nq
        # (stored as a band up to a width of half its size: three stages of a small model, 126 unknowns
        # with a band of 29 + 29, factorise in 0.6 of the dense matrix's time)
        self.big = Assembler(np.concatenate(rows).astype(np.intp), np.concatenate(cols).astype(np.intp), 3 * n,
                             band_share=0.5)

    # -- the step ---------------------------------------------------------------------------------
    def prepare(self, s: MotionState, h: float):
        """Set the step from state s with step h (the ground motion at the stages, the error
        estimate's matrix at the step's start)."""
        m, nq = self.model, self.nq
        self.s, self.h = s, h
        self.t = s.t + C_RK * h
        self.qn, self.mun = s.y[:nq], s.y[nq:]
        # (the kernel's stage functions take C-ordered float arrays; the numpy path any)
        self._flat = all(a.flags.c_contiguous and a.dtype == np.float64 for a in (self.qn, s.v, s.acc))
        if self.ground is not None:
            e = self.ground.direction / m.Lref
            # the ground's acceleration at the stages (Masses.inertia_parts' ground)
            self._ag3 = np.array([self.ground.accel(t) * e for t in self.t], float).reshape(3, 2)
        else:
            self._ag3 = None
        self.elements = [ElementState(s.alpha) for _ in range(3)]
        self._error_matrix = None
        # the coupling blocks' weights (W^2)_ij / h^2 and W_ij / h, and the damping's blocks W_ij / h C
        w1 = (W_RK / h)[:, :, None]
        self._weights = ((W2_RK / (h * h))[:, :, None], w1, None if self.Cvals is None else w1 * self.Cvals)
        vmax = float(np.abs(s.v).max(initial=0.0))
        self.noise_in = EPS * 30.0 * self.m_max * vmax / h   # round-off of M (W ZV)/h (|W| ~ 30)
        # the rods' axial forces at the step's start, for the geometric part of the step's first Newton
        # matrix (the module docstring; a model whose system is its own - the linear theory's - has none)
        self._n_first = None
        if m.elements is not None and type(m).system is Model.system:
            self._n_first = np.ascontiguousarray(m.element_forces(self.qn, s.alpha)[0][:, 0])

    def _error_system(self):
        """[[K + lam C_v + lam^2 M, G^T], [G, 0]] at the step's start, lam = mu_r / h, factorised,
        with M and C_v (COO) for the right-hand side: what RADAU5's error estimate solves."""
        if self._error_matrix is None:
            s, h = self.s, self.h
            _, coo, _ = self.model_system(s.y, ElementState(s.alpha))
            lam = MU_REAL / h
            rows, cols = self.masses.coo_rows, self.masses.coo_cols
            _, base, vm, vd = self.masses.inertia_parts(self.qn[None, :], s.v[None, :], s.acc[None, :],
                                                        None if self.ground is None else self._ag3[:1])
            base, vm, vd = base[0], vm[0], vd[0]
            ex = [e(s.y, s.v, 0.0)[1] for e in self.extra]
            parts = [coo, (rows, cols, base + lam * vd + lam * lam * vm)] + ex
            Cr, Cc, Cvals = rows, cols, vd
            if self.Crows is not None:
                parts.append((self.Crows, self.Ccols, lam * self.Cvals))
                Cr, Cc, Cvals = (np.concatenate([rows, self.Crows]), np.concatenate([cols, self.Ccols]),
                                 np.concatenate([vd, self.Cvals]))
            if self._error_pattern is None:   # (static: the model's, the masses', the friction terms')
                rows_e, cols_e = (np.concatenate([p[i] for p in parts]).astype(np.intp) for i in (0, 1))
                self._error_pattern = Assembler(rows_e, cols_e, self.nq + self.nc)
            A = self._error_pattern.assemble(np.concatenate([p[2] for p in parts]))
            self._error_matrix = (Factorized(A, overwrite=True), (rows, cols, vm), (Cr, Cc, Cvals), lam)
        return self._error_matrix

    def predictor(self):
        """The start of Newton: the previous step's collocation polynomial continued (when it ended
        where this step starts, in the same layout, and this step is at most 4 times as long: a
        cubic extrapolated further is no prediction), else a Taylor start from the step's start."""
        s, h, nq, ny = self.s, self.h, self.nq, self.s.y.size
        p = self.previous
        if p is not None and p[0] + p[1] == s.t and p[3].size == ny + nq and h <= 4.0 * p[1]:
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
        """The stacked stage residual at Y (and, with ``jacobian``, the coupled Newton matrix);
        ``elements.trial`` becomes the step's end (the third stage's chord rotations)."""
        nq, nc, h = self.nq, self.nc, self.h
        m3 = 3 * nq
        kern = self._stages is not None and self._flat and Y.flags.c_contiguous and Y.dtype == np.float64
        if kern:   # (the same arithmetic as the numpy lines below)
            Q, Ys, V, ACC = np.empty((3, nq)), np.empty((3, nq + nc)), np.empty((3, nq)), np.empty((3, nq))
            self._stages(Y, self.qn, self.s.v, W_FLAT, h, Q, Ys, V, ACC)
        else:
            ZQ, ZV = Y[:m3].reshape(3, nq), Y[m3:2 * m3].reshape(3, nq)
            Q = self.qn + ZQ
            Ys = np.empty((3, nq + nc))      # the stages' model unknowns (q, mu), one row each
            Ys[:, :nq] = Q
            Ys[:, nq:] = Y[2 * m3:].reshape(3, nc)
            V = self.s.v + ZV
            ACC = _w_times(ZV) / h
        # the inertia of the three stages in one call, its derivative in parts linear in the
        # coefficients of the accelerations and velocities
        F, base, mass, vel = self.masses.inertia_parts(Q, V, ACC, self._ag3)
        r = np.empty(self.n)
        fmax = 0.0
        vals, parts, more = [], [], []
        ng = self._n_first if jacobian else None
        if jacobian:
            self._n_first = None   # (the step's later matrices are exact)
        direct = self._stage_models(Ys, jacobian, ng) if self._direct and kern else None
        for i in range(3):
            y = Ys[i]
            if direct is not None:
                R, jv, info, prow, pcol = direct
                ri, coo = R[i], (prow, pcol, None if jv is None else jv[i])
            else:
                ri, coo, info = self.model_system(y, self.elements[i], jacobian, ng)
            parts.append(ri)
            ex_coo = []
            for ex in self.extra:
                fe, ce = ex(y, V[i], 0.0)
                more.append((i, fe))
                ex_coo.append(ce)
            fmax = max(fmax, info["fmax"])
            if jacobian:
                if self.big is None:
                    self._pattern(coo, ex_coo)
                vals += [coo[2], base[i]] + [np.ascontiguousarray(ce[2], float) for ce in ex_coo]
        # the stacked residual: forces (the model's + inertia, then damping and the friction terms), h x
        # the kinematics W ZQ - h V, the constraints
        Rv = r[:m3].reshape(3, nq)
        if kern and self._stage_rows is not None:
            self._stage_rows(parts, F, Y, V, W_FLAT, h, r)
        else:
            Rm = r[2 * m3:].reshape(3, nc)
            for i, ri in enumerate(parts):
                np.add(ri[:nq], F[i], out=Rv[i])
                Rm[i] = ri[nq:]
            np.subtract(_w_times(Y[:m3].reshape(3, nq)), h * V, out=r[m3:2 * m3].reshape(3, nq))
        if self.C is not None:
            for i in range(3):
                Rv[i] += self.C @ V[i]
        for i, fe in more:
            Rv[i] += fe
        elements.trial = self.elements[2].trial
        noise = float(info["noise"]) if jacobian else 0.0
        if self.roundoff_floor and self.noise_in > 1e-6 * (1.0 + fmax):
            noise += self.noise_in
        out = {"fmax": fmax, "noise": noise, "lam": 1.0}
        if not jacobian:
            return r, None, out
        # the coupling blocks (i, j): (W^2)_ij / h^2 M_i + W_ij / h (C_v,i + C), in _pattern's order
        w2, w1, Cblocks = self._weights
        kern = self._coupled
        target = self.big.target() if kern is not None else None
        if target is not None:   # the kernel writes the values into the matrix's storage (the same sums)
            kern(target[0], target[1], vals, mass, vel, w2, w1, Cblocks)
            return r, CoupledMatrix(self, target[2], mass, vel), out
        k = mass.shape[1]
        blocks = np.empty((3, 3, k + (0 if Cblocks is None else Cblocks.shape[2])))
        Mb = np.multiply(w2, mass[:, None, :], out=blocks[:, :, :k])
        Mb += w1 * vel[:, None, :]
        if Cblocks is not None:
            blocks[:, :, k:] = Cblocks
        vals.append(blocks.ravel())
        A = self.big.assemble(np.concatenate(vals))
        return r, CoupledMatrix(self, A, mass, vel), out

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
        h, nq = self.h, self.nq
        fact, Mp, Cp, lam = self._error_system()
        if self._error_rhs is not None and self._flat and Y.flags.c_contiguous and Y.dtype == np.float64:
            rq, b = np.empty(nq), np.empty(nq + self.nc)   # (the same arithmetic as the lines below)
            self._error_rhs(Y, E_RK, h, self.s.acc, self.s.v, lam, *Mp, *Cp, b, rq)
        else:
            Z = Y[:6 * nq].reshape(2, 3, nq)
            ZEq, ZEv = ((E_RK[0] * Z[:, 0] + E_RK[1] * Z[:, 1]) + E_RK[2] * Z[:, 2]) / h   # (E ZQ, E ZV) / h
            rq = self.s.v + ZEq
            b = np.zeros(nq + self.nc)
            b[:nq] = (coo_mv(*Mp, self.s.acc + ZEv, nq) + coo_mv(*Cp, rq, nq)) + lam * coo_mv(*Mp, rq, nq)
        eq = fact.solve(b)[:nq]
        return eq, lam * eq - rq

    def dense(self, Y):
        """The collocation polynomial of the step: a function t -> (y, v, acc) on [t_n, t_n + h]
        (acc the derivative of the velocities' polynomial)."""
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
            return y, v0 + Zv @ X, Zv @ np.array([1.0, 2.0 * x, 3.0 * x * x]) / h
        return at

    def remember(self, Y):
        """Keep the accepted step's collocation polynomial for the next step's predictor."""
        ZQ, ZV, MU = self.split(Y)
        Z = np.concatenate([ZQ, MU - self.mun, ZV], axis=1)   # increments of [q, mu, v] at the stages
        Zc = (Z.T @ P_RK).T                                     # (3, n): coefficients of x, x^2, x^3
        self.previous = (self.s.t, self.h, Zc, np.concatenate([self.s.y, self.s.v]))

    def work(self, Y, loss_power=None):
        """(work of the ground motion, energy dissipated) over the step: the Radau quadrature of
        their powers at the stages (exact for polynomials of degree 4); the ground's power is the
        inertia load of its acceleration at the stages (femslide.model.mass.Masses.ground_power),
        ``loss_power(y, v)`` the dissipated power at a state (None: nothing dissipates)."""
        ZQ, ZV, MU = self.split(Y)
        Q, V = self.qn + ZQ, self.s.v + ZV
        W = D = 0.0
        if self._ag3 is not None:
            W = float(B_RK @ self.masses.ground_power(Q, V, self._ag3))
        if loss_power is not None:
            for i, b in enumerate(B_RK):
                D += b * loss_power(np.concatenate([Q[i], MU[i]]), V[i])
        return W * self.h, D * self.h


def consistent_start(sysm: RadauSystem, s: MotionState, h_s: float) -> MotionState:
    """The state s with consistent accelerations and multipliers: one tiny step h_s from q'' = 0
    gives q''(h_s) = q''(0) + O(h_s), massless dofs included (they follow the masses
    quasi-statically), and the multipliers that hold the released structure (a dof held by a
    constraint gets q'' = 0 and its multiplier the force that holds it: the stick test of
    femslide.analysis.stickslip reads it).  The positions are kept; h_s grows 4x per failure.
    (A Richardson pair h_s, 2 h_s is no better: stiff modes the tiny step half resolves - a mass on
    a nearly inextensible rod - differ between the two and the combination doubles them.)"""
    z = np.zeros_like(s.v)
    s = MotionState(s.t, s.y, s.v, z, s.elements)
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
            acc, y0[sysm.nq:] = start_multipliers(sysm, s, acc.copy(), y[sysm.nq:])
            sysm.previous = None
            return MotionState(s.t, y0, s.v, acc, s.elements)
        h_s *= 4.0
    raise SolverFailure("simulate: no consistent initial acceleration (Newton failed on the start step)",
                        info.history)


def start_multipliers(sysm: RadauSystem, s: MotionState, acc, mu_step):
    """(accelerations, multipliers) at the start s that satisfy its equations of motion exactly: the
    massive dofs' accelerations a_M and the multipliers mu from the least-squares solution of

        M[:, M] a_M + G^T mu = -(F + M[:, m] a_m),     G[:, M] a_M = -(gamma + G[:, m] a_m)

    (M the mass matrix, F the forces at s - elements, springs, loads, damping, friction, the inertia
    terms of the velocities and of the ground's acceleration -, G the constraints' gradient, gamma
    = d(G)/dt v their curvature along the velocities, by a central difference of the constraints'
    values) with the massless dofs' accelerations a_m from the tiny start step.  The start step's
    own accelerations and multipliers carry Newton's tolerance on the constrained positions divided
    by its step squared: 3e-3 of a block's weight in its slider's reaction at tolerance 1e-9.
    Returns the step's own (acc, mu_step) if the solve fails."""
    m, nq, nc = sysm.model, sysm.nq, sysm.nc
    heavy = sysm.masses.massive_dofs()
    if heavy.size < nq:
        # massless dofs (rods without rhoA, node rotations): their accelerations follow the masses'
        # through the constraints and their own statics' time derivatives, which this solve does not
        # hold; the step's accelerations are kept (corrected alone, the massive ones made a massless
        # slide's reversal in beam-friction a continued slip)
        return acc, mu_step
    q, v = s.y[:nq], s.v
    es = ElementState(s.alpha)
    r, (rows, cols, vals), _ = sysm.model_system(np.concatenate([q, np.zeros(nc)]), es)
    ag = sysm.ground.accel(s.t) * sysm.ground.direction / m.Lref if sysm.ground is not None else None
    F = r[:nq] + sysm.masses.inertia(q, v, np.zeros(nq), 0.0, 0.0, ag)[0]
    if sysm.C is not None:
        F = F + sysm.C @ v
    for ex in sysm.extra:
        F = F + ex(np.concatenate([q, mu_step]), v, 0.0)[0]
    gamma = np.zeros(nc)
    vmax = float(np.abs(v).max(initial=0.0))
    if nc and vmax > 0.0:
        eps = 1e-4 / vmax
        g = [m.system(np.concatenate([q + k * eps * v, np.zeros(nc)]), ElementState(s.alpha), 1.0, None,
                      False)[0][nq:] for k in (-1.0, 1.0)]
        gamma = (g[0] - 2.0 * r[nq:] + g[1]) / (eps * eps)
        gamma[sysm.released] = 0.0
    light = complement(nq, heavy)
    M = sysm.masses.dense(q)
    G = constraint_gradient((rows, cols, vals), nq, nc)
    GT = np.zeros((nq, nc))
    sel = (rows < nq) & (cols >= nq)
    np.add.at(GT, (rows[sel], cols[sel] - nq), vals[sel])
    GT[:, sysm.released] = 0.0   # (a lifted contact's multiplier is 0)
    A = np.block([[M[:, heavy], GT], [G[:, heavy], np.zeros((nc, nc))]])
    b = -np.concatenate([F + M[:, light] @ acc[light], gamma + G[:, light] @ acc[light]])
    try:
        x = np.linalg.lstsq(A, b, rcond=None)[0]
    except np.linalg.LinAlgError:
        return acc, mu_step
    if not np.all(np.isfinite(x)):
        return acc, mu_step
    out = acc.copy()
    out[heavy] = x[:heavy.size]
    return out, x[heavy.size:]
