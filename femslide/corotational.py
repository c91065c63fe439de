"""2-node corotational Euler-Bernoulli beam, vectorised over all elements of a model.

Nodal dofs per element d = (u1, v1, theta1, u2, v2, theta2): displacements [m] in global x, y and
rotations [rad], counter-clockwise positive.  The element is a linear beam in a frame that follows
the chord (basic deformations u_bar, theta1_bar, theta2_bar; basic forces N [N], M1, M2 [N m], N > 0
in tension, M counter-clockwise on the element end); this module alone knows about large rotations
and adds the geometric stiffness (Crisfield, Non-linear FE analysis of solids and structures, vol. 1,
sec. 7.3).

The chord rotation alpha = beta - beta0 is tracked incrementally from a reference (the last
converged state): alpha = alpha_ref + atan2(cross, dot) of the reference and current chords, so an
element may turn past pi (the classic failure of codes that wrap beta with atan2).
The stretch is computed as (Ln^2 - L0^2)/(Ln + L0) from displacement differences, so that very stiff
axial springs (EA/EI up to 1e12 m^-2) do not amplify round-off in the node coordinates.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np


def _k_map():
    """Constant 11 x 36 map from the element parameters of :func:`evaluate` to its 6 x 6 tangent."""
    C = np.zeros((11, 6, 6))
    X = {(0, 0): 0, (0, 1): 1, (1, 0): 1, (1, 1): 2}
    for (i, j), k in X.items():
        for a, sa in ((0, 1.0), (3, -1.0)):
            for b, sb in ((0, 1.0), (3, -1.0)):
                C[k, a + i, b + j] += sa * sb
    # translation-rotation: K[t, 2] = -rho1 w_t/Ln at node 1, + at node 2 (and symmetric)
    for k0, col in ((3, 2), (5, 5)):
        for comp in range(2):
            k = k0 + comp
            C[k, comp, col] -= 1.0
            C[k, 3 + comp, col] += 1.0
            C[k, col, comp] -= 1.0
            C[k, col, 3 + comp] += 1.0
    C[7, 2, 2] = C[8, 2, 5] = C[9, 5, 2] = C[10, 5, 5] = 1.0
    return C.reshape(11, 36)


_K_MAP = _k_map()


@dataclass
class ElementSet:
    """Static element data: connectivity (n, 2) into the node list, initial chord vectors D0 (n, 2),
    lengths L0 (n,), initial chord angles beta0 (n,), basic stiffness kb (n, 3, 3)."""

    conn: np.ndarray
    D0: np.ndarray
    L0: np.ndarray
    beta0: np.ndarray
    kb: np.ndarray
    xmax: float = 1.0  # largest |initial coordinate|: sets the round-off of the chord angles

    @property
    def size(self):
        return self.L0.size


def chord_rotation(es: ElementSet, U: np.ndarray, alpha_ref: np.ndarray) -> np.ndarray:
    """Chord rotation alpha [rad] of every element, continued from ``alpha_ref``."""
    i, j = es.conn[:, 0], es.conn[:, 1]
    D = es.D0 + U[j, :2] - U[i, :2]
    b_ref = es.beta0 + alpha_ref
    cr, sr = np.cos(b_ref), np.sin(b_ref)
    return alpha_ref + np.arctan2(cr * D[:, 1] - sr * D[:, 0], cr * D[:, 0] + sr * D[:, 1])


def basic_deformations(es: ElementSet, U: np.ndarray, alpha_ref: np.ndarray):
    """Displacement differences dU (n, 2), chord length Ln, stretch u_bar [m], chord rotation alpha and
    the end rotations relative to the chord t1, t2 [rad] of every element."""
    i, j = es.conn[:, 0], es.conn[:, 1]
    dU = U[j, :2] - U[i, :2]
    D = es.D0 + dU
    Ln = np.hypot(D[:, 0], D[:, 1])
    dx, dy = dU[:, 0], dU[:, 1]
    u_bar = ((2.0 * es.D0[:, 0] + dx) * dx + (2.0 * es.D0[:, 1] + dy) * dy) / (Ln + es.L0)
    alpha = chord_rotation(es, U, alpha_ref)
    return dU, Ln, u_bar, alpha, U[i, 2] - alpha, U[j, 2] - alpha


def strain_energy(es: ElementSet, U: np.ndarray, alpha_ref: np.ndarray) -> float:
    """Elastic energy of all elements, sum of 1/2 (k00 u_bar^2 + [t1 t2] kb [t1 t2]^T) [model units]:
    the energy whose gradient is the internal force of :func:`evaluate`."""
    _, _, u_bar, _, t1, t2 = basic_deformations(es, U, alpha_ref)
    kb = es.kb
    e = (kb[:, 0, 0] * u_bar ** 2 + kb[:, 1, 1] * t1 ** 2 + (kb[:, 1, 2] + kb[:, 2, 1]) * t1 * t2
         + kb[:, 2, 2] * t2 ** 2)
    return 0.5 * float(np.sum(e))


def evaluate(es: ElementSet, U: np.ndarray, alpha_ref: np.ndarray, tangent: bool = True):
    """Internal forces (n, 6), tangents (n, 6, 6) or None, basic forces (n, 3), alpha (n,) and,
    with the tangent, the round-off level of each element's forces (n,).

    ``U`` (n_nodes, 3) holds the nodal (u, v, theta).
    """
    dU, Ln, u_bar, alpha, t1, t2 = basic_deformations(es, U, alpha_ref)
    beta = es.beta0 + alpha
    c, s = np.cos(beta), np.sin(beta)
    kb = es.kb
    k00, k11, k12, k21, k22 = kb[:, 0, 0], kb[:, 1, 1], kb[:, 1, 2], kb[:, 2, 1], kb[:, 2, 2]
    N = k00 * u_bar
    M1 = k11 * t1 + k12 * t2
    M2 = k21 * t1 + k22 * t2
    q = np.column_stack([N, M1, M2])
    n = es.size
    # With p = (c, s), w = (s, -c): d Ln/d d = r = (-p, 0, p, 0), d beta/d d = (w, 0, -w, 0)/Ln.
    # f = N r - (M1 + M2) z/Ln + M1 e3 + M2 e6
    m = (M1 + M2) / Ln
    fu = -(N * c + m * s)
    fv = -(N * s - m * c)
    f = np.empty((n, 6))
    f[:, 0], f[:, 1], f[:, 2], f[:, 3], f[:, 4], f[:, 5] = fu, fv, M1, -fu, -fv, M2
    if not tangent:
        return f, None, q, alpha
    # round-off floor of the basic forces: u_bar and the angles carry absolute errors ~ eps times
    # the displacement and rotation magnitudes; EA/L amplifies the first (EA/EI up to 1e12 m^-2);
    # the chord angle carries eps |x| / L0 (node coordinates rounded), which EI/L0 turns into moment
    # noise and 1/Ln into shear noise in the nodal forces
    eps = np.finfo(float).eps
    dmag = np.abs(dU).max(axis=1)
    xmag = es.xmax + np.abs(U[:, :2]).max()
    ang = np.abs(t1) + np.abs(t2) + np.abs(alpha) + 2.0 * xmag / es.L0
    # u_j - u_i is rounded to eps |u| (the displacement magnitude), and u_bar ~ D0 . dU / L0
    umag = np.abs(U[:, :2]).max()
    noise = eps * (2.0 * k00 * (umag + dmag) * (1.0 + dmag / es.L0)
                   + (k11 + np.abs(k12)) * ang * (1.0 + 2.0 / Ln))
    # K = B^T kb B + N z z^T/Ln + (M1 + M2)/Ln^2 (r z^T + z r^T) has the translational block
    # [[X, -X], [-X, X]] with X = k00 p p^T + (kappa + N Ln)/Ln^2 w w^T - m/Ln (p w^T + w p^T),
    # translation-rotation columns -+ rho_a w/Ln (rho_a: row sums of the bending block) and the
    # bending block itself: 11 numbers per element mapped to the 36 entries by a constant matrix.
    kappa = k11 + k12 + k21 + k22
    a_ww = (kappa + N * Ln) / Ln ** 2
    b_pw = m / Ln
    P = np.empty((n, 11))
    P[:, 0] = k00 * c * c + a_ww * s * s - 2.0 * b_pw * c * s
    P[:, 1] = k00 * c * s - a_ww * s * c - b_pw * (c * (-c) + s * s)
    P[:, 2] = k00 * s * s + a_ww * c * c + 2.0 * b_pw * s * c
    r1, r2 = (k11 + k12) / Ln, (k21 + k22) / Ln
    P[:, 3], P[:, 4], P[:, 5], P[:, 6] = r1 * s, -r1 * c, r2 * s, -r2 * c
    P[:, 7], P[:, 8], P[:, 9], P[:, 10] = k11, k12, k21, k22
    K = (P @ _K_MAP).reshape(n, 6, 6)
    return f, K, q, alpha, noise
