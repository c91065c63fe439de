"""Element-local ("basic") matrices of the Euler-Bernoulli beam from scikit-fem forms.

Each element is integrated on its own local coordinate s in [0, L_e] (a 1-D mesh of disjoint
intervals, one per element), so a rod whose EI(s) or EA(s) varies along its length costs nothing
extra and the Hermite matrices keep full accuracy on very fine meshes.

The basic deformations of an element are (u_bar, theta1_bar, theta2_bar): axial stretch [m] and the
end rotations relative to the chord [rad].  The basic stiffness is

    k_b = [[int EA/L^2 ds, 0, 0], [0, int EI N1'' N1'' ds, int EI N1'' N2'' ds], [0, ..., ...]]

with N1, N2 the Hermite shape functions of the end slopes; for constant EI, EA this is the classic
EA/L and EI/L [[4, 2], [2, 4]].
"""
from __future__ import annotations

import numpy as np


def element_stiffness(L0, s0, EI, EA):
    """Basic stiffness (n, 3, 3) of beam elements of lengths L0 [m] starting at arc lengths s0 [m]: the
    closed form EA/L, EI/L [[4, 2], [2, 4]] for constant EI [N m^2] and EA [N] (numbers), scikit-fem
    forms (:func:`basic_stiffness`) where either varies along the rod (a callable of s, a table)."""
    if callable(EI) or callable(EA):
        return basic_stiffness(L0, s0, EI, EA)
    n = L0.size
    kb = np.zeros((n, 9))   # (the flat rows: k00 .. k22)
    kb[:, 0] = EA / L0
    kb[:, 4] = kb[:, 8] = 4.0 * EI / L0
    kb[:, 5] = kb[:, 7] = 2.0 * EI / L0
    return kb.reshape(n, 3, 3)


def basic_stiffness(L0, s0, EI, EA):
    """Basic stiffness matrices, shape (n_elements, 3, 3), by scikit-fem quadrature.

    ``L0``: element lengths [m]; ``s0``: arc length of each element's first node [m];
    ``EI``, ``EA``: callables of the arc length s [m] returning N m^2 and N (vectorised), or numbers.
    (The model uses the closed form for constant EI and EA: :func:`element_stiffness`.)
    """
    return _assemble(np.asarray(L0, float), np.asarray(s0, float), EI, EA)


def _assemble(L0, s0, EI, EA):
    from skfem import Basis, BilinearForm, ElementLineHermite, ElementLineP1, MeshLine, asm
    from skfem.helpers import dd, grad

    L0 = np.asarray(L0, dtype=float)
    n = L0.size
    p = np.zeros(2 * n)
    p[1::2] = L0
    t = np.vstack([np.arange(0, 2 * n, 2), np.arange(1, 2 * n, 2)])
    mesh = MeshLine(p[None, :], t)

    def field(fun, basis):
        s_local = basis.mapping.F(basis.X)[0]  # (n, nqp) local coordinate of quadrature points
        s = s0[:, None] + s_local
        return np.broadcast_to(np.asarray(fun(s) if callable(fun) else fun, dtype=float), s.shape)

    @BilinearForm
    def bending(u, v, w):
        return w.EI * dd(u)[0, 0] * dd(v)[0, 0]

    @BilinearForm
    def axial(u, v, w):
        return w.EA * grad(u)[0] * grad(v)[0]

    # one element object per basis: skfem elements cache mesh data
    bh = Basis(mesh, ElementLineHermite())
    b1 = Basis(mesh, ElementLineP1())
    Kb = asm(bending, bh, EI=field(EI, bh)).tocsr()
    Ka = asm(axial, b1, EA=field(EA, b1)).tocsr()
    slope = bh.element_dofs[[1, 3]]  # Hermite dofs: value, slope at node 1; value, slope at node 2
    kb = np.zeros((n, 3, 3))
    for i in range(2):
        for j in range(2):
            kb[:, 1 + i, 1 + j] = np.asarray(Kb[slope[i], slope[j]]).ravel()
    ends = b1.element_dofs
    kb[:, 0, 0] = np.asarray(Ka[ends[0], ends[0]]).ravel()
    return kb
