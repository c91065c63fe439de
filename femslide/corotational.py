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


@dataclass
class ElementSet:
    """Static element data: connectivity (n, 2) into the node list, initial chord vectors D0 (n, 2),
    lengths L0 (n,), initial chord angles beta0 (n,), basic stiffness kb (n, 3, 3)."""

    conn: np.ndarray
    D0: np.ndarray
    L0: np.ndarray
    beta0: np.ndarray
    kb: np.ndarray

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


def evaluate(es: ElementSet, U: np.ndarray, alpha_ref: np.ndarray, tangent: bool = True):
    """Internal forces (n, 6), tangents (n, 6, 6) or None, basic forces (n, 3), alpha (n,) and,
    with the tangent, the round-off level of each element's forces (n,).

    ``U`` (n_nodes, 3) holds the nodal (u, v, theta).
    """
    i, j = es.conn[:, 0], es.conn[:, 1]
    dU = U[j, :2] - U[i, :2]
    D = es.D0 + dU
    Ln = np.hypot(D[:, 0], D[:, 1])
    u_bar = (2.0 * np.einsum("ij,ij->i", es.D0, dU) + np.einsum("ij,ij->i", dU, dU)) / (Ln + es.L0)
    alpha = chord_rotation(es, U, alpha_ref)
    beta = es.beta0 + alpha
    c, s = np.cos(beta), np.sin(beta)
    t1 = U[i, 2] - alpha
    t2 = U[j, 2] - alpha
    q = np.einsum("nij,nj->ni", es.kb, np.stack([u_bar, t1, t2], axis=1))
    N, M1, M2 = q[:, 0], q[:, 1], q[:, 2]
    n = es.size
    zero = np.zeros(n)
    r = np.stack([-c, -s, zero, c, s, zero], axis=1)
    z = np.stack([s, -c, zero, -s, c, zero], axis=1)
    B = np.empty((n, 3, 6))
    B[:, 0] = r
    B[:, 1] = -z / Ln[:, None]
    B[:, 2] = B[:, 1]
    B[:, 1, 2] += 1.0
    B[:, 2, 5] += 1.0
    f = np.einsum("nki,nk->ni", B, q)
    if not tangent:
        return f, None, q, alpha
    # round-off floor of the basic forces: u_bar and the angles carry absolute errors ~ eps times
    # the displacement and rotation magnitudes; EA/L amplifies the first (EA/EI up to 1e12 m^-2)
    eps = np.finfo(float).eps
    dmag = np.abs(dU).max(axis=1)
    noise = eps * (es.kb[:, 0, 0] * dmag * (1.0 + dmag / es.L0)
                   + (es.kb[:, 1, 1] + np.abs(es.kb[:, 1, 2])) * (np.abs(t1) + np.abs(t2) + np.abs(alpha)))
    K = np.einsum("nki,nkl,nlj->nij", B, es.kb, B)
    K += (N / Ln)[:, None, None] * z[:, :, None] * z[:, None, :]
    rz = r[:, :, None] * z[:, None, :]
    K += ((M1 + M2) / Ln ** 2)[:, None, None] * (rz + rz.transpose(0, 2, 1))
    return f, K, q, alpha, noise
