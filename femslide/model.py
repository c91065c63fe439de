"""Assembly of a planar model: flexible rods, one rigid body, joints and loads.

Unknowns y = [q, mu] (+ lam in displacement control): q holds the nodal dofs (u, v, theta) of every
rod node, then the body dofs (U, V, Theta); mu the constraint multipliers.  The equations are the
stationarity of the Lagrangian  U_rods(q) + lam V_loads(q) + sum mu_i g_i(q):

    R(q) + lam f(q) + G(q)^T mu = 0,    g(q) = 0,

solved by Newton with the consistent tangent [[K + lam K_V + sum mu_i H_i, G^T], [G, 0]].
In displacement control the body rotation is prescribed (Theta = Theta_c) and lam is unknown.

All quantities are whatever units the caller builds the model in; the statics driver builds it
nondimensional (lengths by a reference length, forces by a reference force).
"""
from __future__ import annotations

import numpy as np
from scipy.linalg.lapack import dgbsv as _gbsv
from scipy.linalg.lapack import dgesv as _gesv
from scipy.sparse.csgraph import reverse_cuthill_mckee
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from . import corotational
from .body import Body
from .forms import basic_stiffness

_ONE = np.ones(1)
DENSE_LIMIT = 100  # unknowns; above it a banded LU is faster when the band is narrow
SPARSE_LIMIT = 600  # unknowns; above it a wide-band system goes to sparse LU


class Banded:
    """A static sparsity pattern renumbered by reverse Cuthill-McKee and stored as a LAPACK band.

    Rod meshes give block-tridiagonal tangents; joints and the bordered control add a few entries
    near the rod ends.  After renumbering, the saddle-point system is solved by banded LU with
    partial pivoting (dgbsv) in O(n) per Newton iteration, without building a sparse matrix.
    """

    def __init__(self, rows, cols, size):
        pat = sp.coo_matrix((np.ones(rows.size), (rows, cols)), shape=(size, size)).tocsr()
        pat = pat + pat.T
        perm = reverse_cuthill_mckee(pat.tocsr(), symmetric_mode=True).astype(np.intp)
        inv = np.empty_like(perm)
        inv[perm] = np.arange(size)
        pr, pc = inv[rows], inv[cols]
        self.kl = int(max(0, (pr - pc).max()))
        self.ku = int(max(0, (pc - pr).max()))
        self.size = size
        self.perm = perm
        nrow = 2 * self.kl + self.ku + 1
        self.shape = (nrow, size)
        self.flat = (self.kl + self.ku + pr - pc) * size + pc

    def assemble(self, vals):
        ab = np.bincount(self.flat, weights=vals, minlength=self.shape[0] * self.size)
        return BandMatrix(self, ab.reshape(self.shape))


class BandMatrix:
    def __init__(self, pattern, ab):
        self.pattern, self.ab = pattern, ab

    def solve(self, b):
        p = self.pattern
        _, _, x, info = _gbsv(p.kl, p.ku, self.ab, b[p.perm], overwrite_ab=1, overwrite_b=1)
        if info != 0:
            raise np.linalg.LinAlgError(f"singular matrix (LAPACK gbsv info {info})")
        out = np.empty_like(x)
        out[p.perm] = x
        return out


_TOPOLOGIES: dict = {}  # dof layouts and Jacobian patterns by model topology


class _Topology:
    """Dof layout of a finalized model and the scatter patterns of its Jacobian (static)."""

    def __init__(self, model, con_dofs, term_dofs):
        n_q = model.n_q
        sizes = [c.size for c in model.constraints]
        self.c_off = np.concatenate([[0], np.cumsum(sizes)]).astype(int)
        self.n_c = int(self.c_off[-1])
        self.n = n_q + self.n_c
        rows, cols = [], []
        self.edofs = self.ebinT = None
        if model.elements is not None:
            c = model.elements.conn
            ed = np.concatenate([3 * c[:, :1] + np.arange(3), 3 * c[:, 1:] + np.arange(3)], axis=1)
            self.edofs = ed
            self.ebinT = ed.T.ravel()  # matches the (6, n_elements) layout of the element forces
            rows.append(np.repeat(ed, 6, axis=1).ravel())
            cols.append(np.tile(ed, (1, 6)).ravel())
        for d in term_dofs:
            rows.append(np.repeat(d, d.size))
            cols.append(np.tile(d, d.size))
        for i, d in enumerate(con_dofs):
            o, m = n_q + self.c_off[i], sizes[i]
            rows += [np.repeat(d, d.size), np.repeat(np.arange(o, o + m), d.size), np.tile(d, m)]
            cols += [np.tile(d, d.size), np.tile(d, m), np.repeat(np.arange(o, o + m), d.size)]
        self.rows = np.concatenate(rows).astype(np.intp)
        self.cols = np.concatenate(cols).astype(np.intp)
        self.con_mu = [slice(self.c_off[i], self.c_off[i + 1]) for i in range(len(sizes))]
        self.con_rows = [slice(n_q + self.c_off[i], n_q + self.c_off[i + 1]) for i in range(len(sizes))]
        # loads act on few dofs: d r / d lam is sparse with a static pattern
        self.load_dofs = (np.unique(np.concatenate(term_dofs)) if term_dofs else np.zeros(0, np.intp))
        self.patterns = {}

    def pattern(self, control):
        key = None if control is None else int(control)
        if key in self.patterns:
            return self.patterns[key]
        if control is None:
            rows, cols, size = self.rows, self.cols, self.n
        else:
            j = self.n
            ld = self.load_dofs
            rows = np.concatenate([self.rows, [j], ld])
            cols = np.concatenate([self.cols, [key], np.full(ld.size, j)])
            size = self.n + 1
        # storage: dense (band None) for small systems, banded when the renumbered band is narrow,
        # else dense up to SPARSE_LIMIT unknowns and sparse above
        band, sparse = None, False
        if size > DENSE_LIMIT:
            band = Banded(rows, cols, size)
            if band.kl + band.ku >= size // 4:
                band, sparse = None, size > SPARSE_LIMIT
        flat = rows * size + cols if band is None and not sparse else None
        self.patterns[key] = (rows, cols, size, band, sparse, flat)
        return self.patterns[key]


class Model:
    """Rods are meshed at construction; joints and loads are added, then :meth:`finalize`."""

    def __init__(self, rods, body_A0=None):
        self.rods = list(rods)
        Xs, conn, rod_of = [], [], []
        self.rod_nodes = []
        off = 0
        kbs = []
        for k, rod in enumerate(self.rods):
            X, s = rod.nodes()
            n = rod.n
            Xs.append(X)
            c = off + np.stack([np.arange(n), np.arange(1, n + 1)], axis=1)
            conn.append(c)
            L0 = np.diff(s)
            kbs.append(basic_stiffness(L0, s[:-1], rod.EI, rod.EA))
            rod_of.append(np.full(n, k))
            self.rod_nodes.append(np.arange(off, off + n + 1))
            off += n + 1
        self.X0 = np.concatenate(Xs) if Xs else np.zeros((0, 2))
        self.n_nodes = off
        if conn:
            conn = np.concatenate(conn)
            D0 = self.X0[conn[:, 1]] - self.X0[conn[:, 0]]
            self.elements = corotational.ElementSet(
                conn, D0, np.hypot(D0[:, 0], D0[:, 1]), np.arctan2(D0[:, 1], D0[:, 0]),
                np.concatenate(kbs), float(np.abs(self.X0).max()))
            self.elem_rod = np.concatenate(rod_of)
        else:
            self.elements = None
        self.body = Body(np.asarray(body_A0, float), 3 * off) if body_A0 is not None else None
        self.n_q = 3 * off + (3 if self.body is not None else 0)
        self.constraints = []
        self.terms = []

    # -- building -------------------------------------------------------------------------------
    def node(self, rod: int, i: int) -> int:
        """Model index of node i (negative counts from the end) of rod number ``rod``."""
        return int(self.rod_nodes[rod][i])

    def add_constraint(self, c):
        self.constraints.append(c)
        return c

    def add_term(self, t):
        self.terms.append(t)
        return t

    def finalize(self):
        """Fix the dof layout and the scatter pattern of the Jacobian (static; shared by every model
        of the same topology: the levels of a mesh refinement and the cases of a sweep)."""
        con_dofs = [c.dofs for c in self.constraints]
        term_dofs = [t.dofs for t in self.terms]
        key = (self.n_q, self.elements.conn.tobytes() if self.elements is not None else b"",
               tuple((c.size, d.tobytes()) for c, d in zip(self.constraints, con_dofs)),
               tuple(d.tobytes() for d in term_dofs))
        topo = _TOPOLOGIES.get(key)
        if topo is None:
            topo = _Topology(self, con_dofs, term_dofs)
            if len(_TOPOLOGIES) > 64:
                _TOPOLOGIES.clear()
            _TOPOLOGIES[key] = topo
        self._topo = topo
        self.c_off, self.n_c, self.n = topo.c_off, topo.n_c, topo.n
        self.edofs, self._ebinT, self._load_dofs = topo.edofs, topo.ebinT, topo.load_dofs
        self._term_dofs, self._con_dofs = term_dofs, con_dofs
        self._con_mu, self._con_rows = topo.con_mu, topo.con_rows
        return self

    def _pattern(self, control):
        """Static index arrays (rows, cols), size, banded pattern or None, sparse flag, and the dense
        scatter index (cached per topology)."""
        return self._topo.pattern(control)

    def rotation_dofs(self):
        """Indices of the rotational dofs (node and body rotations) among the unknowns (cached)."""
        if getattr(self, "_rot", None) is None:
            rot = list(range(2, 3 * self.n_nodes, 3))
            if self.body is not None:
                rot.append(self.body.dof0 + 2)
            self._rot = np.array(rot, dtype=np.intp)
        return self._rot

    def zero_state(self):
        ne = self.elements.size if self.elements is not None else 0
        return np.zeros(self.n), np.zeros(ne)

    # -- evaluation ------------------------------------------------------------------------------
    def nodal(self, q):
        return q[: 3 * self.n_nodes].reshape(-1, 3)

    def element_forces(self, q, alpha_ref):
        """Basic forces (N, M1, M2) of every element and the chord rotations alpha."""
        if self.elements is None:
            return np.zeros((0, 3)), np.zeros(0)
        _, _, qb, alpha = corotational.evaluate(self.elements, self.nodal(q), alpha_ref, tangent=False)
        return qb, alpha

    def system(self, y, alpha_ref, lam=1.0, control=None, jacobian=True, dense=False):
        """Residual and Jacobian of the equations at y.

        ``control``: None (load ``lam`` given) or (dof, value): the dof is prescribed, lam is the
        last unknown y[-1].  Returns (r, A, info) with A dense, banded or sparse CSC
        (:func:`solve_linear` solves any of them; ``dense=True`` asks for a dense array whatever
        the size), or None with ``jacobian=False`` (then info["noise"] is not estimated either).
        """
        n_q, n_c = self.n_q, self.n_c
        q, mu = y[:n_q], y[n_q:n_q + n_c]
        if control is not None:
            lam = y[-1]
        size = self.n + (1 if control is not None else 0)
        r = np.zeros(size)
        fl = np.zeros(n_q)
        vals = []
        fmax = noise = 0.0
        alpha = alpha_ref
        if self.elements is not None:
            out = corotational.evaluate(self.elements, self.nodal(q), alpha_ref, tangent=jacobian)
            f, K, alpha = out[0], out[1], out[3]
            fT = f.T  # (6, n_elements): contiguous as evaluate builds it
            r[:n_q] += np.bincount(self._ebinT, weights=fT.ravel(), minlength=n_q)
            fmax = float(np.abs(fT).max())
            if jacobian:
                vals.append(K.ravel())
                noise = 4.0 * float(out[4].max())
        for t, d in zip(self.terms, self._term_dofs):
            _, gt, Ht, g0 = t.eval(q[d], lam)
            r[d] += gt
            fl[d] += g0
            vals.append(Ht.ravel())
        for c, d, ci, gi in zip(self.constraints, self._con_dofs, self._con_mu, self._con_rows):
            mi = mu[ci]
            g, G, Hmu = c.eval(q[d], mi)
            r[d] += mi @ G
            r[gi] = g
            Gr = G.ravel()
            vals += [Hmu.ravel(), Gr, Gr]
        info = {"fl": fl, "fmax": fmax, "noise": noise, "lam": lam, "alpha": alpha}
        if control is not None:
            dof, value = control
            r[-1] = q[dof] - value
            vals += [_ONE, fl[self._load_dofs]]
        if not jacobian:
            return r, None, info
        rows, cols, size, band, sparse, flat = self._pattern(None if control is None else control[0])
        vals = np.concatenate(vals)
        if band is not None and not dense:
            A = band.assemble(vals)
        elif sparse and not dense:
            A = sp.csc_matrix((vals, (rows, cols)), shape=(size, size))
        else:
            flat = rows * size + cols if flat is None else flat
            A = np.bincount(flat, weights=vals, minlength=size * size).reshape(size, size)
        return r, A, info


def solve_linear(A, b):
    """Solve A x = b for the dense or sparse Jacobian of :meth:`Model.system`."""
    if isinstance(A, BandMatrix):
        return A.solve(b)
    if isinstance(A, np.ndarray):
        lu, piv, x, info = _gesv(A, b, overwrite_a=1, overwrite_b=0)
        if info != 0:
            raise np.linalg.LinAlgError(f"singular matrix (LAPACK gesv info {info})")
        return x
    return spla.splu(A, permc_spec="COLAMD").solve(b)
