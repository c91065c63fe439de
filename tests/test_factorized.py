"""model.linalg.Factorized: the LU kept for several solves (Radau's coupled stages, modes, buckling),
dense and banded, real and complex, on the compiled kernel and on LAPACK.

Reference: a badly scaled system A = D1 B D2 (B well conditioned, D1 and D2 diagonal powers of 2
over 2^-20 .. 2^20, as a time step's matrix holds M / h^2 beside O(1) constraint rows), whose
solution x = D2^-1 B^-1 D1^-1 b is computed from B alone: D2 x within 1e-12 of D2 times it, relative
to its largest component (the accuracy of the equilibrated system, whatever the scales; without
the equilibration the band LU misses it by orders of magnitude)."""
from __future__ import annotations

import numpy as np
import pytest

from femslide.model.linalg import Assembler, Factorized, kernel_enabled, kernel_forced

RNG = np.random.default_rng(7)


def _scaled(n, band=None, complex_=False):
    B = RNG.standard_normal((n, n)) + 4.0 * np.sqrt(n) * np.eye(n)
    if complex_:
        B = B + 1j * RNG.standard_normal((n, n))
    if band is not None:
        i, j = np.indices((n, n))
        B[np.abs(i - j) > band] = 0.0
    d1 = np.exp2(RNG.integers(-20, 21, n).astype(float))
    d2 = np.exp2(RNG.integers(-20, 21, n).astype(float))
    return B, d1, d2


def _check(A, B, d1, d2, b, x, exact):
    assert np.abs(d2 * (x - exact)).max() <= 1e-12 * np.abs(d2 * exact).max()


@pytest.mark.parametrize("kernel", [True, False])
@pytest.mark.parametrize("complex_", [False, True])
def test_dense_badly_scaled(kernel, complex_):
    if kernel and not kernel_enabled():
        pytest.skip("the compiled kernel is not built")
    n = 40
    B, d1, d2 = _scaled(n, complex_=complex_)
    A = d1[:, None] * B * d2[None, :]
    b = RNG.standard_normal(n)
    exact = np.linalg.solve(B, b / d1) / d2
    with kernel_forced(kernel):
        x = Factorized(A).solve(b)
    _check(A, B, d1, d2, b, x, exact)


@pytest.mark.parametrize("kernel", [True, False])
def test_band_badly_scaled(kernel):
    if kernel and not kernel_enabled():
        pytest.skip("the compiled kernel is not built")
    n, w = 120, 2
    B, d1, d2 = _scaled(n, band=w)
    A = d1[:, None] * B * d2[None, :]
    rows, cols = np.nonzero(np.abs(np.subtract.outer(np.arange(n), np.arange(n))) <= w)
    asm = Assembler(rows, cols, n, dense_limit=10)
    b = RNG.standard_normal(n)
    exact = np.linalg.solve(B, b / d1) / d2
    with kernel_forced(kernel):
        M = asm.assemble(A[rows, cols])
        assert type(M).__name__ == "BandMatrix"
        x = Factorized(M).solve(b)
    _check(A, B, d1, d2, b, x, exact)


def test_singular_is_a_linalg_error():
    A = np.ones((5, 5))
    for kernel in ([True, False] if kernel_enabled() else [False]):
        with kernel_forced(kernel), pytest.raises(np.linalg.LinAlgError):
            Factorized(A)


def test_kernel_equilibration_and_dense_solve_equal_their_references():
    """The kernel's equilibration (``equilibrate``: powers of 2 from the rows' and columns' largest
    magnitudes) gives the numpy path's scales and scaled matrix bitwise (tolerance 0) on random dense
    and band matrices with zeros, NaN, inf and subnormal entries; the kernel's dense solve (forward
    substitution four rows at a time) equals the row-at-a-time substitution written out in Python
    bitwise (each row's terms in the same order)."""
    from femslide.model import linalg
    if not kernel_enabled():
        pytest.skip("the compiled kernel is not built")
    rng = np.random.default_rng(11)
    for trial in range(300):
        n = int(rng.integers(1, 40))
        if trial % 2:
            kl = ku = None
            A = rng.standard_normal((n, n))
        else:
            kl, ku = int(rng.integers(0, 6)), int(rng.integers(0, 6))
            A = rng.standard_normal((n, 2 * kl + ku + 1))
        A *= 10.0 ** rng.integers(-8, 8, A.shape)
        A[rng.random(A.shape) < 0.3] = 0.0
        special = [np.nan, np.inf, -np.inf, 1e-310][trial % 4]
        if trial % 3 == 0:
            A[rng.random(A.shape) < 0.05] = special
        M1, M2 = A.copy(), A.copy()
        with np.errstate(all="ignore"):
            with kernel_forced(False):
                r1 = linalg._equilibrate(M1, kl, ku)
            r2 = linalg._equilibrate(M2, kl, ku)
        for a, b in zip(r1 + (M1,), r2 + (M2,)):
            assert np.array_equal(a, b, equal_nan=True)
    for n in (1, 3, 4, 5, 17, 40):
        lu = np.ascontiguousarray(rng.standard_normal((n, n)) + n * np.eye(n))
        piv = np.empty(n, np.intp)
        assert linalg._kernel.factor(lu, piv, n, -1, 0) == 0
        b = rng.standard_normal(n)
        x = b.copy()
        linalg._kernel.solve(lu, piv, x, -1, 0)
        y = b.copy()
        for k in range(n):
            y[k], y[piv[k]] = y[piv[k]], y[k]
        for i in range(1, n):
            s = y[i]
            for j in range(i):
                s -= lu[i, j] * y[j]
            y[i] = s
        for i in range(n - 1, -1, -1):
            s = y[i]
            for j in range(i + 1, n):
                s -= lu[i, j] * y[j]
            y[i] = s / lu[i, i]
        assert np.array_equal(x, y)


def test_kernel_dense_lu_skipping_zeros_equals_the_textbook_loops():
    """The kernel's dense LU (``factor``), which skips the zero entries of sparse matrices (a time
    step's coupled matrix is 6 % nonzero) and finds each pivot while eliminating the previous
    column, gives the factors and pivots of the textbook partial-pivoting loops written out here
    (the first of the largest |A[i, k]|, l = A[i, k] / pivot as A[i, k] (1 / pivot), row i -=
    l row k) bitwise (tolerance 0; the sign of a zero aside), on random sparse and dense matrices,
    some with a zero column (info = its index + 1)."""
    from femslide.model import linalg
    if not kernel_enabled():
        pytest.skip("the compiled kernel is not built")
    rng = np.random.default_rng(23)
    for trial in range(150):
        n = int(rng.integers(1, 60))
        A = rng.standard_normal((n, n)) * (rng.random((n, n)) < rng.uniform(0.03, 1.0))
        A *= 10.0 ** rng.integers(-6, 6, (n, 1))
        if trial % 5 == 0:
            A[:, rng.integers(0, n)] = 0.0
        ref, piv_ref, info_ref = A.copy(), np.zeros(n, np.intp), 0
        for k in range(n):
            col = np.abs(ref[k:, k])
            p = k + int(np.argmax(col))   # (argmax: the first of the largest)
            piv_ref[k] = p
            if ref[p, k] == 0.0:
                info_ref = info_ref or k + 1
                continue
            ref[[k, p]] = ref[[p, k]]
            inv = 1.0 / ref[k, k]
            for i in range(k + 1, n):
                lf = ref[i, k] * inv
                ref[i, k] = lf
                if lf != 0.0:
                    ref[i, k + 1:] -= lf * ref[k, k + 1:]
        lu = A.copy()
        piv = np.empty(n, np.intp)
        info = linalg._kernel.factor(lu, piv, n, -1, 0)
        assert info == info_ref
        assert np.array_equal(piv, piv_ref)
        assert np.array_equal(lu, ref)
