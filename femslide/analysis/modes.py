"""Natural frequencies and mode shapes of the linearised frictionless structure about a static state.

At a static equilibrium (q, mu) the small motions obey M x'' + K x + G^T l = 0, G x = 0, with K the
consistent tangent of the statics (elastic and geometric stiffness, joint Hessians weighted by their
multipliers, turning dead loads) and G the joints' gradient; friction is left out (sliders free).
With x = phi sin(omega t): K phi = omega^2 M phi on the null space of G.  M may be singular
(massless rods, rod rotations): those directions have infinite frequency and follow quasi-statically,
so the problem is solved for 1 / omega^2, which is finite:

- small models (up to DENSE_LIMIT dofs): the constraints are eliminated with a null-space basis Z of
  G and the dense symmetric problem (Z^T M Z) x = (1 / omega^2) (Z^T K Z) x is solved by LAPACK
  (the reduced K is positive definite at a stable equilibrium);
- larger models: the constrained compliance S (the q part of the saddle-point solve
  [[K, G^T], [G, 0]]^-1 [M x, 0]) is factorised once (sparse LU) and ARPACK finds the largest
  eigenvalues of S M, O(n) per iteration.

Frequencies in Hz, ascending; mode shapes over the frame dofs (model units), scaled to a largest
translation of 1.
"""
from __future__ import annotations

import math

import numpy as np
import scipy.sparse as sp

from femslide.errors import SolverFailure
from femslide.model.linalg import BandMatrix

DENSE_LIMIT = 600


def to_sparse(model, A):
    """The Jacobian of :meth:`Model.system` (dense, banded or sparse) as a scipy CSC matrix."""
    if isinstance(A, np.ndarray):
        return sp.csc_matrix(A)
    if isinstance(A, BandMatrix):
        rows, cols, size, band, _, _ = model._pattern(None)
        flat, idx = np.unique(band.flat, return_index=True)
        vals = A.ab.T.ravel()[flat]   # (ab is the Fortran-ordered band: flat indexes its transpose)
        return sp.csc_matrix((vals, (rows[idx], cols[idx])), shape=(size, size))
    return sp.csc_matrix(A)


def tangent(model, y, elements):
    """(K, G) of the static state (y, elements): sparse stiffness (n_q, n_q) and joint gradient
    (n_c, n_q)."""
    _, A, _ = model.system(y, elements, 1.0)
    elements.revert()
    S = to_sparse(model, A)
    n_q = model.n_q
    K = S[:n_q, :n_q]
    return (0.5 * (K + K.T)).tocsc(), S[n_q:, :n_q].tocsc(), S


def modes(model, y, elements, masses, count=6):
    """(frequencies_hz (k,), shapes (k, n_q)): the ``count`` lowest natural frequencies of the
    structure about the static state (y, elements).  Raises SolverFailure when the state is unstable
    (the reduced stiffness is not positive definite) or nothing has mass."""
    n_q = model.n_q
    Mr, Mc, Mv = masses.matrix(y[:n_q])
    M = sp.csc_matrix((Mv, (Mr, Mc)), shape=(n_q, n_q))
    if M.nnz == 0 or not np.any(Mv):
        raise SolverFailure("no natural frequencies: nothing in the structure has mass")
    K, G, S = tangent(model, y, elements)
    if n_q <= DENSE_LIMIT:
        from scipy.linalg import eigh, null_space
        Gd = G.toarray()
        Z = null_space(Gd) if Gd.shape[0] else np.eye(n_q)
        if Z.shape[1] == 0:
            raise SolverFailure("no natural frequencies: the joints leave the structure no motion")
        Kr = Z.T @ K.toarray() @ Z
        Mrd = Z.T @ M.toarray() @ Z
        Kr, Mrd = 0.5 * (Kr + Kr.T), 0.5 * (Mrd + Mrd.T)
        try:
            w, V = eigh(Mrd, Kr)
        except np.linalg.LinAlgError:
            raise SolverFailure("the static state is not stable (its reduced stiffness is not positive "
                                "definite): no natural frequencies") from None
        order = np.argsort(w)[::-1]
        w, V = w[order], V[:, order]
        keep = w > 1e-14 * max(w[0], 1e-300)
        w, V = w[keep][:count], V[:, keep][:, :count]
        shapes = (Z @ V).T
    else:
        import scipy.sparse.linalg as spla
        lu = spla.splu(S.tocsc(), permc_spec="COLAMD")
        n = S.shape[0]

        def op(x):
            b = np.zeros(n)
            b[:n_q] = M @ x
            return lu.solve(b)[:n_q]

        k = min(count, n_q - 2)
        L = spla.LinearOperator((n_q, n_q), matvec=op, dtype=float)
        w, V = spla.eigs(L, k=k, which="LM", tol=1e-12, maxiter=20 * n_q)
        w, V = w.real, V.real
        order = np.argsort(w)[::-1]
        w, V = w[order], V[:, order]
        keep = w > 0
        w, V = w[keep], V[:, keep]
        shapes = V.T
    if w.size == 0:
        raise SolverFailure("no natural frequencies found (massless structure or unstable static state)")
    freq = 1.0 / np.sqrt(w) / (2.0 * math.pi)
    for k in range(shapes.shape[0]):
        nod = shapes[k, : 3 * model.n_nodes].reshape(-1, 3)[:, :2]
        body = shapes[k, 3 * model.n_nodes:].reshape(-1, 3)[:, :2]
        big = max(float(np.abs(nod).max()) if nod.size else 0.0, float(np.abs(body).max()) if body.size else 0.0)
        if big == 0.0:
            big = float(np.abs(shapes[k]).max())
        i = int(np.argmax(np.abs(shapes[k])))
        shapes[k] *= np.sign(shapes[k][i]) / big
    return freq, shapes
