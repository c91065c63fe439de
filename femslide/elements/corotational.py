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

import numpy as np

from femslide.records import dataclass


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
# the 7 varying parameters in the order evaluate computes them: X00, X01, X11, rho1 s/Ln, rho2 s/Ln,
# rho1 c/Ln, rho2 c/Ln (w = (s, -c): the last two enter with the opposite sign)
_K_MAP7 = np.ascontiguousarray(_K_MAP[[0, 1, 2, 3, 5, 4, 6]] * np.array([1, 1, 1, 1, 1, -1, -1.0])[:, None])
_EPS = float(np.finfo(float).eps)
_DERIVED = frozenset(("k00", "kA", "kB", "kappa", "rho", "k_noise_eps", "k00_2_eps", "K_bend"))
_SIGN = np.array([[1.0], [-1.0]])


@dataclass
class ElementSet:
    """Static element data: connectivity (n, 2) into the node list, initial chord vectors D0 (n, 2),
    lengths L0 (n,), initial chord angles beta0 (n,), basic stiffness kb (n, 3, 3).

    The per-element constants of :func:`evaluate` (stiffness entries, their combinations and the
    constant bending part of the tangent) are derived once here, stacked as rows (k, n) so that one
    numpy call treats both ends or both components of every element."""

    conn: np.ndarray
    D0: np.ndarray
    L0: np.ndarray
    beta0: np.ndarray
    kb: np.ndarray
    xmax: float = 1.0  # largest |initial coordinate|: sets the round-off of the chord angles

    def __post_init__(self):
        self.i, self.j = self.conn[:, 0].copy(), self.conn[:, 1].copy()
        # flat indices of (u1, v1, u2, v2, theta1, theta2) of every element in U.ravel(): (6, n)
        self.gather = (3 * self.conn[:, [0, 0, 1, 1, 0, 1]] + np.array([0, 1, 0, 1, 2, 2])).T.copy()
        self.D0T = self.D0.T.copy()                       # (2, n): D0x, D0y
        self.inv_L0 = 1.0 / self.L0

    def with_stiffness(self, kb: np.ndarray) -> "ElementSet":
        """The same elements with the basic stiffness kb (n, 3, 3): the geometric data are shared."""
        new = object.__new__(ElementSet)
        new.__dict__.update({k: v for k, v in self.__dict__.items() if k not in _DERIVED})
        new.kb = kb
        return new

    def __getattr__(self, name):
        # the stiffness constants of the numpy evaluation, derived when first used (a model assembled by
        # the compiled kernel, femslide.model.fast, never needs them)
        if name in _DERIVED:
            self._stiffness()
            return self.__dict__[name]
        raise AttributeError(f"{type(self).__name__!r} object has no attribute {name!r}")

    def _stiffness(self):
        S = self.kb.reshape(-1, 9).T.copy()   # (9, n): k00 k01 k02 k10 k11 k12 k20 k21 k22
        self.k00 = S[0]
        self.kA = S[4::3]                     # (k11, k21): M = kA t1 + kB t2
        self.kB = S[5::3]                     # (k12, k22)
        self.kappa = S[4] + S[5] + S[7] + S[8]
        self.rho = self.kA + self.kB          # (2, n): rho1, rho2 (row sums)
        # the round-off estimate's coefficients, times eps (a power of 2: exact)
        self.k_noise_eps = _EPS * (S[4] + np.abs(S[5]))
        self.k00_2_eps = _EPS * (2.0 * S[0])
        self.K_bend = Kb = np.zeros((S.shape[1], 36))     # entries (2, 2), (2, 5), (5, 2), (5, 5)
        Kb[:, 14], Kb[:, 17], Kb[:, 32], Kb[:, 35] = S[4], S[5], S[7], S[8]

    @property
    def size(self):
        return self.L0.size


def _kinematics(es: ElementSet, x: np.ndarray, alpha_ref: np.ndarray):
    """Nodal values Z (6, n) (rows u1, v1, u2, v2, theta1, theta2), displacement differences d (2, n),
    deformed chord D (2, n) and its length Ln, stretch u_bar [m], chord rotation alpha (continued
    from ``alpha_ref``) and the end rotations relative to the chord t (2, n) [rad] of every element
    (the one place they are computed); ``x`` = U.ravel(), the nodal (u, v, theta) node after node."""
    Z = x[es.gather]
    d = Z[2:4] - Z[0:2]
    D = es.D0T + d
    Ln = np.hypot(D[0], D[1])
    e = (es.D0T + D) * d
    u_bar = (e[0] + e[1]) / (Ln + es.L0)
    b_ref = es.beta0 + alpha_ref
    Dc, Ds = np.cos(b_ref) * D, np.sin(b_ref) * D
    alpha = alpha_ref + np.arctan2(Dc[1] - Ds[0], Dc[0] + Ds[1])
    return Z, d, D, Ln, u_bar, alpha, Z[4:6] - alpha


def _basic(es: ElementSet, u_bar, t, free):
    """The basic forces (N, M1, M2) (3, n) from the stretch and the end rotations relative to the chord:
    N = k00 u_bar, (M1, M2) = kb t, minus the free forces ``free`` (3, n) of a thermal load (or None)."""
    NM = np.empty((3, u_bar.size))
    np.multiply(es.k00, u_bar, out=NM[0])
    np.add(es.kA * t[0], es.kB * t[1], out=NM[1:])
    if free is not None:
        NM -= free
    return NM


def basic_forces(es: ElementSet, x: np.ndarray, alpha_ref: np.ndarray, free=None):
    """The basic forces (N, M1, M2) (3, n) and the chord rotations alpha (n,) of every element: what
    :func:`element_terms` gives as NM, without the nodal forces and tangents (a history's rows);
    ``x`` and ``free`` as there."""
    _, _, _, _, u_bar, alpha, t = _kinematics(es, x, alpha_ref)
    return _basic(es, u_bar, t, free), alpha


def basic_deformations(es: ElementSet, U: np.ndarray, alpha_ref: np.ndarray):
    """Displacement differences dU (n, 2), chord length Ln, stretch u_bar [m], chord rotation alpha and
    the end rotations relative to the chord t1, t2 [rad] of every element."""
    _, d, _, Ln, u_bar, alpha, t = _kinematics(es, U.reshape(-1), alpha_ref)
    return d.T.copy(), Ln, u_bar, alpha, t[0], t[1]


def strain_energy(es: ElementSet, U: np.ndarray, alpha_ref: np.ndarray, free=None) -> float:
    """Elastic energy of all elements, sum of 1/2 (k00 u_bar^2 + [t1 t2] kb [t1 t2]^T) [model units]:
    the energy whose gradient is the internal force of :func:`evaluate`.  ``free`` (3, n): the
    elements' free basic forces (a thermal load, :func:`free_forces`): the energy then is
    1/2 (e - e_T)^T kb (e - e_T) up to a constant, i.e. minus e . (N_T, M1_T, M2_T)."""
    _, _, u_bar, _, t1, t2 = basic_deformations(es, U, alpha_ref)
    kb = es.kb
    e = (kb[:, 0, 0] * u_bar ** 2 + kb[:, 1, 1] * t1 ** 2 + (kb[:, 1, 2] + kb[:, 2, 1]) * t1 * t2
         + kb[:, 2, 2] * t2 ** 2)
    out = 0.5 * float(np.sum(e))
    if free is not None:
        out -= float(np.sum(free[0] * u_bar + free[1] * t1 + free[2] * t2))
    return out


def free_forces(es: ElementSet, strain, curvature) -> np.ndarray:
    """The basic forces (3, n) that hold every element at its free (thermal) deformation: the free
    strain ``strain`` (n,) [-] (alpha dT) stretches an element by strain L0, the free curvature
    ``curvature`` (n,) [1/length] (-alpha dT_gradient / depth) turns its ends by -+ curvature L0 / 2
    relative to the chord (a circular arc), e_T = (strain L0, -kappa L0 / 2, kappa L0 / 2) and
    S_T = kb e_T.  The element's forces are then N = k00 (u_bar - strain L0) and
    (M1, M2) = kb ((t1, t2) - e_T[1:]): M(s) = EI (dtheta/ds - kappa_T) (:func:`element_terms` takes
    S_T as ``free``)."""
    L0 = es.L0
    h = 0.5 * np.asarray(curvature, float) * L0
    kb = es.kb
    S = np.empty((3, L0.size))
    S[0] = kb[:, 0, 0] * np.asarray(strain, float) * L0
    S[1] = (kb[:, 1, 2] - kb[:, 1, 1]) * h
    S[2] = (kb[:, 2, 2] - kb[:, 2, 1]) * h
    return S


def _noise(es, Z, d, t, alpha, inv):
    """Round-off level of every element's basic forces (see :func:`element_terms`)."""
    ad = np.abs(d)
    dmag = np.maximum(ad[0], ad[1])
    umag = float(np.abs(Z[0:4]).max())   # largest displacement component of the elements' nodes
    at = np.abs(t)
    ang = at[0] + at[1] + np.abs(alpha) + (2.0 * (es.xmax + umag)) * es.inv_L0
    return (es.k00_2_eps * (umag + dmag) * (1.0 + dmag * es.inv_L0)
            + es.k_noise_eps * ang * (1.0 + 2.0 * inv))


def force_noise(es: ElementSet, U: np.ndarray, alpha_ref: np.ndarray) -> np.ndarray:
    """The round-off level of every element's forces (the estimate :func:`evaluate` returns with the
    tangent), without the forces."""
    Z, d, _, Ln, _, alpha, t = _kinematics(es, U.reshape(-1), alpha_ref)
    return _noise(es, Z, d, t, alpha, 1.0 / Ln)


def evaluate(es: ElementSet, U: np.ndarray, alpha_ref: np.ndarray, tangent: bool = True, free=None):
    """Internal forces (n, 6), tangents (n, 6, 6) or None, basic forces (n, 3), alpha (n,) and,
    with the tangent, the round-off level of each element's forces (n,).

    ``U`` (n_nodes, 3) holds the nodal (u, v, theta).  (:func:`element_terms` is the same evaluation
    in the layout the assembly uses; ``free`` as there.)
    """
    F, K, NM, alpha, noise = element_terms(es, U.reshape(-1), alpha_ref, tangent, free)
    if not tangent:
        return F.T, None, NM.T, alpha
    return F.T, K.reshape(-1, 6, 6), NM.T, alpha, noise()


def element_terms(es: ElementSet, x: np.ndarray, alpha_ref: np.ndarray, tangent: bool = True, free=None,
                  n_geometric=None):
    """:func:`evaluate` in the layout of the model's assembly: ``x`` holds the nodal (u, v, theta)
    node after node (U.ravel(), or the model's dof vector, which starts with them).

    Returns internal forces F (6, n) (rows: the dofs u1, v1, theta1, u2, v2, theta2), tangents (n, 36) or
    None, basic forces (N, M1, M2) (3, n), alpha (n,) and, with the tangent, a function that returns
    the round-off level of each element's forces (n,) (else None): computed only if asked for, from
    copies of this state's kinematics.

    ``free``: None, or the free basic forces (3, n) of a thermal load (:func:`free_forces`, times the
    load factor) subtracted from the elastic ones: N = k00 u_bar - N_T, M = kb t - M_T.  The tangent
    keeps its form (its geometric part carries these total forces).

    ``n_geometric``: None, or axial forces (n,) that the tangent's geometric part carries instead of
    the elements' own N (the forces stay the elements'): a time step's first Newton matrix takes those
    of the step's start, where the predicted state's stretch of a nearly inextensible rod would put
    its error times EA into the geometric stiffness (femslide.analysis.radau).

    Written for few numpy calls: with a handful of elements the cost is the number of calls, not
    their size; quantities of both ends or both components share one call as rows of (2, n) arrays.
    """
    Z, d, D, Ln, u_bar, alpha, t = _kinematics(es, x, alpha_ref)
    n = u_bar.size
    NM = _basic(es, u_bar, t, free)
    N, M = NM[0], NM[1:]
    inv = 1.0 / Ln
    p = D * inv                # (c, s): cos and sin of the chord angle beta = beta0 + alpha
    # With p = (c, s), w = (s, -c): d Ln/d d = r = (-p, 0, p, 0), d beta/d d = (w, 0, -w, 0)/Ln.
    # f = N r - (M1 + M2) z/Ln + M1 e3 + M2 e6: (fu, fv) = -(N p + m w) at node 1, + at node 2
    m = (M[0] + M[1]) * inv
    F = np.empty((6, n))
    np.add(N * p, (m * p[::-1]) * _SIGN, out=F[3:5])
    np.negative(F[3:5], out=F[0:2])
    F[2::3] = M
    if not tangent:
        return F, None, NM, alpha, None
    # round-off floor of the basic forces: u_bar and the angles carry absolute errors ~ eps times
    # the displacement and rotation magnitudes; EA/L amplifies the first (EA/EI up to 1e12 m^-2);
    # the chord angle carries eps |x| / L0 (node coordinates rounded), which EI/L0 turns into moment
    # noise and 1/Ln into shear noise in the nodal forces.  u_j - u_i is rounded to eps |u| (the
    # displacement magnitude), and u_bar ~ D0 . dU / L0
    def noise():
        return _noise(es, Z, d, t, alpha, inv)
    # K = B^T kb B + N z z^T/Ln + (M1 + M2)/Ln^2 (r z^T + z r^T) has the translational block
    # [[X, -X], [-X, X]] with X = k00 p p^T + (kappa + N Ln)/Ln^2 w w^T - m/Ln (p w^T + w p^T),
    # translation-rotation columns -+ rho_a w/Ln (rho_a: row sums of the bending block) and the
    # bending block itself: 11 numbers per element mapped to the 36 entries by a constant matrix
    # (the 4 of the bending block are constant: es.K_bend).
    if n_geometric is not None:
        n_geometric = np.asarray(n_geometric, dtype=float)
        if n_geometric.shape != (n,):
            raise ValueError(f"n_geometric: {n} axial forces expected, got shape {n_geometric.shape}")
    a_ww = (es.kappa + (N if n_geometric is None else n_geometric) * Ln) * inv * inv
    b_pw = m * inv
    pp = p * p                 # (cc, ss)
    cs = p[0] * p[1]
    b2 = 2.0 * b_pw * cs
    k00 = es.k00
    P = np.empty((7, n))
    # X00 = k00 cc + a_ww ss - b2, X11 = k00 ss + a_ww cc + b2
    np.add(k00 * pp + a_ww * pp[::-1], b2 * _SIGN[::-1], out=P[0:3:2])
    np.add((k00 - a_ww) * cs, b_pw * (pp[0] - pp[1]), out=P[1])
    r = es.rho * inv           # (rho1, rho2) / Ln
    np.multiply(r, p[1], out=P[3:5])
    np.multiply(r, p[0], out=P[5:7])
    K = P.T @ _K_MAP7
    K += es.K_bend
    return F, K, NM, alpha, noise


def free_nodal(es: ElementSet, x: np.ndarray, alpha_ref: np.ndarray, free) -> np.ndarray:
    """The nodal forces (6, n) (rows as :func:`element_terms`' F) of the basic forces ``free`` (3, n)
    alone at the state ``x``: B^T free, the derivative of the elements' forces by a factor that
    scales their free basic forces (minus this is d F / d lam of a ramped thermal load)."""
    _, _, D, Ln, _, _, _ = _kinematics(es, x, alpha_ref)
    inv = 1.0 / Ln
    p = D * inv
    m = (free[1] + free[2]) * inv
    F = np.empty((6, Ln.size))
    np.add(free[0] * p, (m * p[::-1]) * _SIGN, out=F[3:5])
    np.negative(F[3:5], out=F[0:2])
    F[2::3] = free[1:]
    return F


def geometric_terms(es: ElementSet, x: np.ndarray, alpha_ref: np.ndarray, NM: np.ndarray) -> np.ndarray:
    """The geometric (stress) part (n, 36) of the elements' tangents at the nodal state ``x`` (as
    :func:`element_terms`) carrying the basic forces ``NM`` (3, n) = (N, M1, M2): the terms of the
    tangent that scale with the forces, N z z^T / Ln + (M1 + M2) / Ln^2 (r z^T + z r^T), without the
    material part B^T kb B.  With the element's own forces, element tangent = material + this; with
    other forces (those of a linear solution at the reference state) it is the initial-stress matrix
    of linear buckling."""
    _, _, D, Ln, _, _, _ = _kinematics(es, x, alpha_ref)
    n = Ln.size
    inv = 1.0 / Ln
    p = D * inv
    a_ww = NM[0] * inv
    b_pw = (NM[1] + NM[2]) * inv * inv
    pp = p * p
    cs = p[0] * p[1]
    b2 = 2.0 * b_pw * cs
    P = np.zeros((7, n))
    np.add(a_ww * pp[::-1], b2 * _SIGN[::-1], out=P[0:3:2])
    np.add(-a_ww * cs, b_pw * (pp[0] - pp[1]), out=P[1])
    return P.T @ _K_MAP7
