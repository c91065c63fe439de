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

A mechanism (``zero_ok``: a base on a frictionless slider without a spring) has directions free of
any stiffness: the reduced K is singular (an eigenvalue below FREE = 1e-12 of the largest).  The
dense path then splits them off (:func:`_mechanism_modes`): each free direction with mass is a zero
frequency, the rest is solved on the complement with the free part following (its mass condensed
in), for 1 / omega^2 as the stable path is; an unstable state (a negative eigenvalue) is still a
SolverFailure.
"""
from __future__ import annotations

import math

import numpy as np

from femslide.errors import SolverFailure
from femslide.model.linalg import eigh, load_lapack, null_space, one_blas_thread

DENSE_LIMIT = 600


def dense_tangent(model, y, elements):
    """(K, G) of the static state (y, elements) as :func:`tangent` gives them, dense (the modes of
    models up to DENSE_LIMIT dofs: no scipy.sparse)."""
    _, A, _ = model.system(y, elements, 1.0, dense=True)
    elements.revert()
    n_q = model.n_q
    K = A[:n_q, :n_q]
    return 0.5 * (K + K.T), A[n_q:, :n_q].copy()


def tangent(model, y, elements):
    """(K, G) of the static state (y, elements): sparse stiffness (n_q, n_q) and joint gradient
    (n_c, n_q)."""
    _, A, _ = model.system(y, elements, 1.0)
    elements.revert()
    S = model.to_csc(A)
    n_q = model.n_q
    K = S[:n_q, :n_q]
    return (0.5 * (K + K.T)).tocsc(), S[n_q:, :n_q].tocsc(), S


def modes(model, y, elements, masses, count=6, zero_ok=False, max_free=None):
    """(frequencies_hz (k,), shapes (k, n_q)): :func:`_modes`, with OpenBLAS on one thread
    (femslide.model.linalg.one_blas_thread: its dense problems are small)."""
    if model.n_q <= DENSE_LIMIT:
        load_lapack(always=True)   # (loaded first: its OpenBLAS is set too)
    with one_blas_thread():
        return _modes(model, y, elements, masses, count, zero_ok, max_free)


def _modes(model, y, elements, masses, count=6, zero_ok=False, max_free=None):
    """(frequencies_hz (k,), shapes (k, n_q)): the ``count`` lowest natural frequencies of the
    structure about the static state (y, elements).  Raises SolverFailure when the state is unstable
    (the reduced stiffness is not positive definite; with ``zero_ok`` only when it is indefinite: a
    direction free of stiffness is a zero frequency, module docstring; at most ``max_free`` of them,
    the number of joints released, when given) or nothing has mass.  ``zero_ok`` is for a state known
    to be a mechanism (its statics needed the friction joints stuck): a stable state's softest modes
    may be 1e-12 of its stiffest and are solved by the stable path."""
    n_q = model.n_q
    Mr, Mc, Mv = masses.matrix(y[:n_q])
    if not np.any(Mv):
        raise SolverFailure("no natural frequencies: nothing in the structure has mass")
    if n_q <= DENSE_LIMIT:
        K, Gd = dense_tangent(model, y, elements)
        Z = null_space(Gd) if Gd.shape[0] else np.eye(n_q)
        if Z.shape[1] == 0:
            raise SolverFailure("no natural frequencies: the joints leave the structure no motion")
        Kr = Z.T @ K @ Z
        Mrd = Z.T @ masses.dense(y[:n_q]) @ Z
        Kr, Mrd = 0.5 * (Kr + Kr.T), 0.5 * (Mrd + Mrd.T)
        if zero_ok:   # (a singular Kr may still pass the Cholesky factorisation by round-off)
            kw, kV = eigh(Kr)
            if kw.min() <= FREE * max(float(np.abs(kw).max()), 1e-300):
                return _mechanism_modes(model, Z, kw, kV, Mrd, count, max_free)
        try:
            w, V = eigh(Mrd, Kr)
        except np.linalg.LinAlgError:
            if not zero_ok:
                raise SolverFailure("the static state is not stable (its reduced stiffness is not positive "
                                    "definite): no natural frequencies") from None
            # (Kr's eigenvalues all above FREE but its Cholesky factorisation failed by round-off: the
            # mechanism path, with no direction split off, solves it from those eigenvalues)
            return _mechanism_modes(model, Z, kw, kV, Mrd, count, max_free)
        order = np.argsort(w)[::-1]
        w, V = w[order], V[:, order]
        keep = w > 1e-14 * max(w[0], 1e-300)
        w, V = w[keep][:count], V[:, keep][:, :count]
        shapes = (Z @ V).T
    else:
        import scipy.sparse as sp
        import scipy.sparse.linalg as spla
        M = sp.csc_matrix((Mv, (Mr, Mc)), shape=(n_q, n_q))
        _, _, S = tangent(model, y, elements)
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
    return freq, _normalised(model, shapes)


def _normalised(model, shapes):
    """Mode shapes scaled to a largest translation of 1, the largest entry positive."""
    for k in range(shapes.shape[0]):
        nod = shapes[k, : 3 * model.n_nodes].reshape(-1, 3)[:, :2]
        body = shapes[k, 3 * model.n_nodes:].reshape(-1, 3)[:, :2]
        big = max(float(np.abs(nod).max()) if nod.size else 0.0, float(np.abs(body).max()) if body.size else 0.0)
        if big == 0.0:
            big = float(np.abs(shapes[k]).max())
        i = int(np.argmax(np.abs(shapes[k])))
        shapes[k] *= np.sign(shapes[k][i]) / big
    return shapes


FREE = 1e-12   # a direction whose stiffness (an eigenvalue of the reduced K) is below this fraction of the
               # largest is free of stiffness (round-off is ~1e-16; real soft modes are far above 1e-12)


def _mechanism_modes(model, Z, kw, kV, Mr, count, max_free=None):
    """The modes of a structure with directions free of stiffness (dense; module docstring).
    ``kw``, ``kV``: the eigenpairs of the reduced K.  The free directions N (kw <= FREE max) are
    zero frequencies (those with mass; shapes N a with (N^T M N) a = mu a); the others are the
    motions x = W b + N a with W^T K W b = omega^2 M* b, M* = W^T M W - W^T M N (N^T M N)^+ N^T M W
    (the free part a = -(N^T M N)^+ N^T M W b follows, carrying no force), solved for 1 / omega^2 as
    the stable path is.  SolverFailure when K has a negative eigenvalue (an unstable state)."""
    scale = max(float(np.abs(kw).max()), 1e-300)
    if kw.min() < -FREE * scale:
        raise SolverFailure("the static state is not stable (its reduced stiffness has a negative "
                            "eigenvalue): no natural frequencies")
    free = kw <= FREE * scale
    if max_free is not None:   # (eigh: kw ascending)
        free[max_free:] = False
    N, W = kV[:, free], kV[:, ~free]
    Mnn, Mnw = N.T @ Mr @ N, N.T @ Mr @ W
    Mnn_pinv = np.linalg.pinv(0.5 * (Mnn + Mnn.T), rcond=1e-12, hermitian=True)
    mu, U = eigh(0.5 * (Mnn + Mnn.T))
    heavy = mu > 1e-12 * max(float(np.abs(mu).max(initial=0.0)), 1e-300)   # (none when no direction is free)
    zero_shapes = (N @ U[:, heavy]).T                    # the free directions with mass: zero frequencies
    freq, shapes = np.zeros(int(heavy.sum())), zero_shapes
    if W.shape[1]:
        Meff = W.T @ Mr @ W - Mnw.T @ Mnn_pinv @ Mnw
        w, V = eigh(0.5 * (Meff + Meff.T), np.diag(kw[~free]))   # w = 1 / omega^2
        order = np.argsort(w)[::-1]
        w, V = w[order], V[:, order]
        keep = w > 1e-14 * max(float(w[0]), 1e-300)
        w, V = w[keep], V[:, keep]
        x = W @ V - N @ (Mnn_pinv @ (Mnw @ V))
        freq = np.concatenate([freq, 1.0 / np.sqrt(w) / (2.0 * math.pi)])
        shapes = np.vstack([zero_shapes, x.T]) if zero_shapes.size else x.T
    if freq.size == 0:
        raise SolverFailure("no natural frequencies found (massless structure)")
    freq, shapes = freq[:count], shapes[:count]
    return freq, _normalised(model, (Z @ shapes.T).T)
