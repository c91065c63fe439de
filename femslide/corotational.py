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
_K_MAP7 = np.ascontiguousarray(_K_MAP[:7])
_EPS = float(np.finfo(float).eps)


@dataclass
class ElementSet:
    """Static element data: connectivity (n, 2) into the node list, initial chord vectors D0 (n, 2),
    lengths L0 (n,), initial chord angles beta0 (n,), basic stiffness kb (n, 3, 3).

    The per-element constants of :func:`evaluate` (stiffness entries, their combinations and the
    constant bending part of the tangent) are derived once here."""

    conn: np.ndarray
    D0: np.ndarray
    L0: np.ndarray
    beta0: np.ndarray
    kb: np.ndarray
    xmax: float = 1.0  # largest |initial coordinate|: sets the round-off of the chord angles

    def __post_init__(self):
        kb = self.kb
        self.i, self.j = self.conn[:, 0].copy(), self.conn[:, 1].copy()
        self.D0x, self.D0y = self.D0[:, 0].copy(), self.D0[:, 1].copy()
        self.k00, self.k11, self.k12 = kb[:, 0, 0].copy(), kb[:, 1, 1].copy(), kb[:, 1, 2].copy()
        self.k21, self.k22 = kb[:, 2, 1].copy(), kb[:, 2, 2].copy()
        self.kappa = self.k11 + self.k12 + self.k21 + self.k22
        self.rho1, self.rho2 = self.k11 + self.k12, self.k21 + self.k22
        self.k_noise = self.k11 + np.abs(self.k12)
        self.k00_2 = 2.0 * self.k00
        self.inv_L0 = 1.0 / self.L0
        self.K_bend = np.stack([self.k11, self.k12, self.k21, self.k22], axis=1) @ _K_MAP[7:]

    @property
    def size(self):
        return self.L0.size


def _kinematics(es: ElementSet, U: np.ndarray, alpha_ref: np.ndarray):
    """Displacement differences dx, dy, deformed chord components Dx, Dy and length Ln, stretch
    u_bar [m], chord rotation alpha (continued from ``alpha_ref``) and the end rotations relative to
    the chord t1, t2 [rad] of every element (the one place they are computed)."""
    Ui, Uj = U[es.i], U[es.j]
    d = Uj - Ui
    dx, dy = d[:, 0], d[:, 1]
    Dx, Dy = es.D0x + dx, es.D0y + dy
    Ln = np.hypot(Dx, Dy)
    u_bar = ((es.D0x + Dx) * dx + (es.D0y + Dy) * dy) / (Ln + es.L0)
    b_ref = es.beta0 + alpha_ref
    cr, sr = np.cos(b_ref), np.sin(b_ref)
    alpha = alpha_ref + np.arctan2(cr * Dy - sr * Dx, cr * Dx + sr * Dy)
    return dx, dy, Dx, Dy, Ln, u_bar, alpha, Ui[:, 2] - alpha, Uj[:, 2] - alpha


def basic_deformations(es: ElementSet, U: np.ndarray, alpha_ref: np.ndarray):
    """Displacement differences dU (n, 2), chord length Ln, stretch u_bar [m], chord rotation alpha and
    the end rotations relative to the chord t1, t2 [rad] of every element."""
    dx, dy, _, _, Ln, u_bar, alpha, t1, t2 = _kinematics(es, U, alpha_ref)
    return np.column_stack([dx, dy]), Ln, u_bar, alpha, t1, t2


def strain_energy(es: ElementSet, U: np.ndarray, alpha_ref: np.ndarray) -> float:
    """Elastic energy of all elements, sum of 1/2 (k00 u_bar^2 + [t1 t2] kb [t1 t2]^T) [model units]:
    the energy whose gradient is the internal force of :func:`evaluate`."""
    _, _, u_bar, _, t1, t2 = basic_deformations(es, U, alpha_ref)
    kb = es.kb
    e = (kb[:, 0, 0] * u_bar ** 2 + kb[:, 1, 1] * t1 ** 2 + (kb[:, 1, 2] + kb[:, 2, 1]) * t1 * t2
         + kb[:, 2, 2] * t2 ** 2)
    return 0.5 * float(np.sum(e))


def _noise(es, U, dx, dy, t1, t2, alpha, inv):
    dmag = np.maximum(np.abs(dx), np.abs(dy))
    umag = float(np.abs(U[:, :2]).max())
    ang = np.abs(t1) + np.abs(t2) + np.abs(alpha) + (2.0 * (es.xmax + umag)) * es.inv_L0
    return _EPS * (es.k00_2 * (umag + dmag) * (1.0 + dmag * es.inv_L0)
                   + es.k_noise * ang * (1.0 + 2.0 * inv))


def force_noise(es: ElementSet, U: np.ndarray, alpha_ref: np.ndarray) -> np.ndarray:
    """The round-off level of every element's forces (the estimate :func:`evaluate` returns with the
    tangent), without the forces."""
    dx, dy, _, _, Ln, _, alpha, t1, t2 = _kinematics(es, U, alpha_ref)
    return _noise(es, U, dx, dy, t1, t2, alpha, 1.0 / Ln)


def evaluate(es: ElementSet, U: np.ndarray, alpha_ref: np.ndarray, tangent: bool = True):
    """Internal forces (n, 6), tangents (n, 6, 6) or None, basic forces (n, 3), alpha (n,) and,
    with the tangent, the round-off level of each element's forces (n,).

    ``U`` (n_nodes, 3) holds the nodal (u, v, theta).  Written for few numpy calls: with a handful of
    elements the cost is the number of calls, not their size.
    """
    dx, dy, Dx, Dy, Ln, u_bar, alpha, t1, t2 = _kinematics(es, U, alpha_ref)
    N = es.k00 * u_bar
    M1 = es.k11 * t1 + es.k12 * t2
    M2 = es.k21 * t1 + es.k22 * t2
    inv = 1.0 / Ln
    c, s = Dx * inv, Dy * inv  # cos and sin of the chord angle beta = beta0 + alpha
    # With p = (c, s), w = (s, -c): d Ln/d d = r = (-p, 0, p, 0), d beta/d d = (w, 0, -w, 0)/Ln.
    # f = N r - (M1 + M2) z/Ln + M1 e3 + M2 e6
    m = (M1 + M2) * inv
    fu = -(N * c + m * s)
    fv = m * c - N * s
    # np.array of a list and a transposed view: a third of the cost of np.stack for few elements
    f = np.array([fu, fv, M1, -fu, -fv, M2]).T
    q = np.array([N, M1, M2]).T
    if not tangent:
        return f, None, q, alpha
    # round-off floor of the basic forces: u_bar and the angles carry absolute errors ~ eps times
    # the displacement and rotation magnitudes; EA/L amplifies the first (EA/EI up to 1e12 m^-2);
    # the chord angle carries eps |x| / L0 (node coordinates rounded), which EI/L0 turns into moment
    # noise and 1/Ln into shear noise in the nodal forces.  u_j - u_i is rounded to eps |u| (the
    # displacement magnitude), and u_bar ~ D0 . dU / L0
    noise = _noise(es, U, dx, dy, t1, t2, alpha, inv)
    # K = B^T kb B + N z z^T/Ln + (M1 + M2)/Ln^2 (r z^T + z r^T) has the translational block
    # [[X, -X], [-X, X]] with X = k00 p p^T + (kappa + N Ln)/Ln^2 w w^T - m/Ln (p w^T + w p^T),
    # translation-rotation columns -+ rho_a w/Ln (rho_a: row sums of the bending block) and the
    # bending block itself: 11 numbers per element mapped to the 36 entries by a constant matrix
    # (the 4 of the bending block are constant: es.K_bend).
    a_ww = (es.kappa + N * Ln) * inv * inv
    b_pw = m * inv
    cc, cs, ss = c * c, c * s, s * s
    b2 = 2.0 * b_pw * cs
    r1, r2 = es.rho1 * inv, es.rho2 * inv
    k00 = es.k00
    P = np.array([k00 * cc + a_ww * ss - b2, (k00 - a_ww) * cs + b_pw * (cc - ss),
                  k00 * ss + a_ww * cc + b2, r1 * s, -r1 * c, r2 * s, -r2 * c])
    K = (P.T @ _K_MAP7 + es.K_bend).reshape(-1, 6, 6)
    return f, K, q, alpha, noise
