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
