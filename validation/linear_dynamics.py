"""Exact linear dynamics of small planar structures: an independent reference for femslide's FE dynamics
(validation only; numpy and scipy, nothing from femslide).

A :class:`LinearStructure` is the linearisation of a planar structure about a (prestressed) static
state, written in generalised coordinates q (n,) chosen by hand for each case, so that every joint is
built into the coordinates (a weld ties a rod end to a body point, a slider on the ground leaves a body
one coordinate, ...) instead of being a constraint:

* the physical dofs of a rod node or of a body (u, v, theta: displacements [m] along global x, y,
  rotation [rad] counter-clockwise) are linear maps of q, (3, n) matrices: a body's own coordinates,
  a point of a body at the offset r = (rx, ry) from its centroid (:meth:`point`:
  u = u_b - theta ry, v = v_b + theta rx, theta = theta_b), a free node's three coordinates, or the
  ground (zero);
* a beam element (Euler-Bernoulli, length L, EI and EA constant) between two such maps adds
  T^T (k_e + k_g) T to the stiffness, with k_e the standard exact 6 x 6 frame element and
  k_g = (N / L) z z^T the geometric stiffness of the axial force N [N, tension > 0] of the static
  state acting on the chord's rotation (z the chord's transverse direction on both ends).  That is
  the linearisation of a corotational element whose local beam is linear (Crisfield, Non-linear FE
  analysis of solids and structures, vol. 1, sec. 7.3: the tangent B^T D B + z z^T N / l
  + (r z^T + z r^T)(M1 + M2) / l^2, whose last term vanishes where the static end moments do);
* a mass m [kg] with a rotary inertia J [kg m^2] on a map adds T^T diag(m, m, J) T; a spring k [N/m]
  on a coordinate combination c adds k c c^T;
* the base acceleration a_g(t) along a unit direction d enters, as in femslide (coordinates relative
  to the moving ground), as the generalised force f_g a_g(t), f_g = -sum T^T diag(m, m, J) (d, 0).

Coordinates without inertia (rotations of massless rods' nodes, massless rods' nodes) are condensed
statically: q_c = -K_cc^-1 K_cm q_m (exact: they carry no inertia and no load).  The remaining system
M q'' + C q' + K q = f_g a_g(t) (+ a friction force, friction_events.py) is solved exactly:

* :func:`modal_harmonic`: undamped modal superposition of the response to a_g = A sin(W t) from rest,
  in closed form per mode, transient included:
  eta_j = Gamma_j A (sin W t - (W / w_j) sin w_j t) / (w_j^2 - W^2), Gamma_j = phi_j . f_g
  (mass-normalised modes); a rigid-body mode (w_j = 0) gives Gamma_j A (t / W - sin W t / W^2);
* friction_events.py: the piecewise-linear motion with Coulomb friction by the matrix exponential.

Outputs are linear functionals of q (rows, :meth:`output`): displacements of bodies and nodes, the end
forces of beam elements and so the reactions of the supports (forces of the ground on the structure)
and the bending moments M = EI dtheta/ds at the element ends (femslide's sign: M(0) = -M1 at an
element's start, M(L) = +M2 at its end, M1, M2 the end moments acting on the element,
counter-clockwise positive).  Units: SI throughout.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import scipy.linalg as sla


def frame_element(X1, X2, EI, EA, N=0.0, ln=None):
    """Global 6 x 6 tangent stiffness of a straight Euler-Bernoulli element from X1 to X2 (dofs u1, v1,
    th1, u2, v2, th2) about a state where it carries the axial force N [N] (tension > 0) and no end
    moments, its chord of length ``ln`` (default: |X2 - X1|, the unstressed length L0) along X2 - X1:

        K = B^T D B + (N / ln) z z^T,   D = [[EA / L0, 0, 0], [0, 4 EI / L0, 2 EI / L0], [0, 2 EI / L0, 4 EI / L0]],

    B the rows of the basic deformations (stretch, th1 - beta, th2 - beta; beta the chord rotation,
    d beta = z . d / ln, z = (s, -c, 0, -s, c, 0)).  With ln = L0 and N = 0, B^T D B is the exact
    elastic frame element.  Returns (K, T, L0) with T the 6 x 6 rotation to the local axes (t along the
    element, n = t turned by +90 degrees)."""
    d = np.asarray(X2, float) - np.asarray(X1, float)
    L = float(math.hypot(*d))
    ln = L if ln is None else float(ln)
    c, s = d / L
    z = np.array([s, -c, 0.0, -s, c, 0.0])
    B = np.array([[-c, -s, 0.0, c, s, 0.0],
                  [0, 0, 1.0, 0, 0, 0] - z / ln,
                  [0, 0, 0, 0, 0, 1.0] - z / ln])
    D = np.array([[EA / L, 0, 0], [0, 4 * EI / L, 2 * EI / L], [0, 2 * EI / L, 4 * EI / L]])
    K = B.T @ D @ B + (N / ln) * np.outer(z, z)
    R = np.array([[c, s, 0], [-s, c, 0], [0, 0, 1.0]])
    T = np.zeros((6, 6))
    T[:3, :3] = T[3:, 3:] = R
    return K, T, L


@dataclass
class Beam:
    name: str
    T: np.ndarray          # (6, n): element dofs from q
    K: np.ndarray          # (6, 6) global stiffness (elastic + geometric)
    Rot: np.ndarray        # (6, 6) to local axes
    L: float
    EI: float
    ends: tuple            # names of its end nodes (for reactions)


@dataclass
class LinearStructure:
    """A linearised planar structure in the generalised coordinates ``names`` (see the module
    docstring).  Build it with :meth:`body`, :meth:`point`, :meth:`beam`, :meth:`mass`,
    :meth:`spring`; read it with :meth:`output`, :meth:`reduced`."""

    names: list
    K: np.ndarray = None
    M: np.ndarray = None
    C: np.ndarray = None
    beams: list = field(default_factory=list)
    masses: list = field(default_factory=list)

    def __post_init__(self):
        n = len(self.names)
        self.names = list(self.names)
        self.K = np.zeros((n, n))
        self.M = np.zeros((n, n))
        self.C = np.zeros((n, n))

    @property
    def n(self):
        return len(self.names)

    # -- kinematic maps ---------------------------------------------------------------------------
    def coord(self, name):
        """Row (n,) selecting the coordinate ``name``."""
        r = np.zeros(self.n)
        r[self.names.index(name)] = 1.0
        return r

    def zero(self):
        return np.zeros(self.n)

    def dofs(self, u=None, v=None, th=None):
        """(3, n) map of a node or body whose u, v, theta are the named coordinates (None: held at 0)."""
        return np.array([self.coord(x) if x else self.zero() for x in (u, v, th)])

    def ground(self):
        return np.zeros((3, self.n))

    @staticmethod
    def point(body, r):
        """(3, n) map of the point at the offset r = (rx, ry) [m] from the reference point of the body
        whose map is ``body`` (small rotations)."""
        u, v, th = body
        return np.array([u - r[1] * th, v + r[0] * th, th])

    # -- members -------------------------------------------------------------------------------------
    def beam(self, name, A, B, XA, XB, EI, EA, N=0.0, ends=("", "")):
        """A beam element between the maps A and B at the reference points XA, XB [m]; N the static
        axial force [N] (tension > 0), its chord then L0 (1 + N / EA) long.  Returns its index."""
        L0 = math.dist(XA, XB)
        K, Rot, L = frame_element(XA, XB, EI, EA, N, ln=L0 * (1.0 + N / EA))
        T = np.vstack([A, B])
        self.K += T.T @ K @ T
        self.beams.append(Beam(name, T, K, Rot, L, EI, tuple(ends)))
        return len(self.beams) - 1

    def chain(self, name, A, B, XA, XB, EI, EA, n_el, N=0.0, prefix=None):
        """A rod of ``n_el`` equal elements from the map A to the map B (XA, XB its ends [m]); its
        n_el - 1 inner nodes get new coordinates PREFIX.i.u/v/th (added to ``names``, grown in place).
        The first element's start is end "start", the last's end "end"."""
        prefix = prefix or name
        new = [f"{prefix}.{i}.{c}" for i in range(1, n_el) for c in ("u", "v", "th")]
        self._grow(new)
        A = np.hstack([A, np.zeros((3, self.n - A.shape[1]))])
        B = np.hstack([B, np.zeros((3, self.n - B.shape[1]))])
        XA, XB = np.asarray(XA, float), np.asarray(XB, float)
        maps = [A] + [self.dofs(f"{prefix}.{i}.u", f"{prefix}.{i}.v", f"{prefix}.{i}.th") for i in range(1, n_el)] + [B]
        X = [XA + (XB - XA) * i / n_el for i in range(n_el + 1)]
        out = []
        for i in range(n_el):
            ends = ("start" if i == 0 else "", "end" if i == n_el - 1 else "")
            out.append(self.beam(f"{name}[{i}]", maps[i], maps[i + 1], X[i], X[i + 1], EI, EA, N, ends))
        return out

    def _grow(self, new):
        k = len(new)
        if not k:
            return
        n0 = self.n
        self.names += new
        for attr in ("K", "M", "C"):
            A = getattr(self, attr)
            B = np.zeros((n0 + k, n0 + k))
            B[:n0, :n0] = A
            setattr(self, attr, B)
        for b in self.beams:
            b.T = np.hstack([b.T, np.zeros((6, k))])
        self.masses = [(np.hstack([T, np.zeros((3, k))]), m, J) for T, m, J in self.masses]

    def mass(self, T, m, J=0.0):
        """A mass m [kg] (and rotary inertia J [kg m^2]) moving with the map T (3, n)."""
        T = np.hstack([T, np.zeros((3, self.n - T.shape[1]))])
        D = np.diag([m, m, J])
        self.M += T.T @ D @ T
        self.masses.append((T, m, J))

    def spring(self, c, k):
        """A spring of stiffness k [N/m or N m/rad] on the coordinate combination c (n,)."""
        c = np.concatenate([c, np.zeros(self.n - c.size)])
        self.K += k * np.outer(c, c)

    def ground_load(self, direction=(1.0, 0.0)):
        """f_g (n,): the generalised force of a unit base acceleration along ``direction`` (the
        inertia loads -m a_g d on every mass)."""
        d = np.array([direction[0], direction[1], 0.0])
        f = np.zeros(self.n)
        for T, m, J in self.masses:
            f -= T.T @ (np.array([m, m, J]) * d)
        return f

    # -- outputs ---------------------------------------------------------------------------------------
    def output(self, what, *args):
        """Row (n,) of a linear output: ``("coord", name)``; ``("map", T, k)`` component k of a map;
        ``("beam_force", index, k)`` the global end force component k (0..5: Fx1, Fy1, M1, Fx2, Fy2,
        M2) acting on the element; ``("moment", index, end)`` the bending moment M = EI dtheta/ds at
        the element's start (0) or end (1)."""
        if what == "coord":
            return self.coord(args[0])
        if what == "map":
            T, k = args
            return np.concatenate([T[k], np.zeros(self.n - T.shape[1])])
        b = self.beams[args[0]]
        F = b.K @ b.T                       # (6, n) global end forces on the element
        if what == "beam_force":
            return F[args[1]]
        if what == "moment":
            loc = b.Rot @ F                 # local end forces (the moments are unchanged)
            return -loc[2] if args[1] == 0 else loc[5]
        raise ValueError(what)

    def reaction(self, indices_and_ends):
        """Rows (3, n) of the force (Fx, Fy, M) of the ground on the structure at a support: the sum of
        the end forces on the elements listed as (beam index, 0 | 1) that end there."""
        R = np.zeros((3, self.n))
        for i, e in indices_and_ends:
            b = self.beams[i]
            R += (b.K @ b.T)[3 * e:3 * e + 3]
        return R

    # -- condensation ----------------------------------------------------------------------------------
    def reduced(self, rows=None, tol=0.0):
        """The system on the coordinates with inertia: (Mr, Cr, Kr, fmap, keep) with fmap (n, m) the map
        q = fmap q_m (massless coordinates condensed statically) and keep their indices; ``rows``
        (k, n) of outputs become rows @ fmap."""
        diag = np.diag(self.M)
        keep = np.nonzero(diag > tol)[0]
        drop = np.nonzero(diag <= tol)[0]
        if (np.abs(self.M[np.ix_(drop, drop)]).max(initial=0.0) > 0
                or np.abs(self.M[np.ix_(keep, drop)]).max(initial=0.0) > 0):
            raise ValueError("a condensed coordinate carries inertia")
        fmap = np.zeros((self.n, keep.size))
        fmap[keep, np.arange(keep.size)] = 1.0
        if drop.size:
            Kcc = self.K[np.ix_(drop, drop)]
            Kcm = self.K[np.ix_(drop, keep)]
            fmap[drop] = -np.linalg.solve(Kcc, Kcm)
        Kr = fmap.T @ self.K @ fmap
        Kr = 0.5 * (Kr + Kr.T)
        Mr = self.M[np.ix_(keep, keep)]
        Cr = fmap.T @ self.C @ fmap
        out = (Mr, Cr, Kr, fmap, keep)
        if rows is not None:
            return out + (np.atleast_2d(rows) @ fmap,)
        return out


# -- modal superposition ------------------------------------------------------------------------------------

@dataclass
class Modal:
    """Mass-normalised modes of (M, K): omega [rad/s] (ascending), Phi (m, m), and the participation
    Gamma_j = phi_j . f_g of the base acceleration."""

    omega: np.ndarray
    Phi: np.ndarray
    Gamma: np.ndarray

    @property
    def frequencies_hz(self):
        return self.omega / (2 * math.pi)


def modes(M, K, f_g, rigid_tol=1e-13):
    """:class:`Modal` of the undamped system; eigenvalues below rigid_tol * max are rigid-body (0)."""
    w2, Phi = sla.eigh(K, M)
    w2 = np.where(w2 < rigid_tol * w2.max(), 0.0, w2)
    return Modal(np.sqrt(w2), Phi, Phi.T @ f_g)


def modal_harmonic(md: Modal, A, W, t, rows, derivative=0):
    """Outputs rows (k, m) @ q(t) (derivative 0, 1 or 2 in time) of the undamped response to
    a_g = A sin(W t) [m/s^2, rad/s] from rest at t = 0, exactly, by modes (transient included).
    Returns (k, len(t))."""
    t = np.atleast_1d(np.asarray(t, float))[None, :]
    w = md.omega[:, None]
    G = (md.Gamma * A)[:, None]
    rigid = w[:, 0] == 0.0
    if np.any(np.abs(md.omega - W) < 1e-6 * W):
        raise ValueError("the forcing is at resonance with a mode; choose another frequency")
    ws = np.where(rigid[:, None], 1.0, w)
    den = np.where(rigid[:, None], 1.0, ws ** 2 - W ** 2)
    if derivative == 0:
        el = (np.sin(W * t) - (W / ws) * np.sin(ws * t)) / den
        rb = t / W - np.sin(W * t) / W ** 2
    elif derivative == 1:
        el = (W * np.cos(W * t) - W * np.cos(ws * t)) / den
        rb = (1.0 - np.cos(W * t)) / W
    else:
        el = (-W * W * np.sin(W * t) + W * ws * np.sin(ws * t)) / den
        rb = np.sin(W * t) + 0.0 * t
    eta = G * np.where(rigid[:, None], rb, el)
    return np.atleast_2d(rows) @ md.Phi @ eta


def modal_harmonic_damped(md: Modal, A, W, t, rows, zeta, derivative=0):
    """As :func:`modal_harmonic` with modal damping ratios ``zeta`` (m,) (Rayleigh C = alpha M +
    beta K: zeta_j = alpha / (2 omega_j) + beta omega_j / 2): every mode's response to
    p sin(W t) from rest, eta'' + 2 zeta w eta' + w^2 eta = p sin(W t), in closed form (the forced
    part plus the free part through the roots r1, r2 = -zeta w +- sqrt(zeta^2 - 1) w, complex for
    an under-damped mode; every mode elastic).  Derivative 0 or 1.  Returns (k, len(t))."""
    if derivative not in (0, 1):
        raise ValueError("derivative 0 or 1")
    if np.any(md.omega == 0.0):
        raise ValueError("a rigid-body mode: use modal_harmonic")
    t = np.atleast_1d(np.asarray(t, float))[None, :]
    w, z = md.omega[:, None], np.asarray(zeta, float)[:, None]
    p = (md.Gamma * A)[:, None]
    den = (w ** 2 - W ** 2) ** 2 + (2 * z * w * W) ** 2
    a, b = p * (w ** 2 - W ** 2) / den, -p * 2 * z * w * W / den   # forced part a sin + b cos
    root = np.sqrt((z * w) ** 2 - w ** 2 + 0j)
    r1, r2 = -z * w + root, -z * w - root
    c2 = (-a * W + r1 * b) / (r2 - r1)       # free part c1 e^(r1 t) + c2 e^(r2 t): eta(0) = eta'(0) = 0
    c1 = -b - c2
    if derivative == 0:
        eta = a * np.sin(W * t) + b * np.cos(W * t) + (c1 * np.exp(r1 * t) + c2 * np.exp(r2 * t)).real
    else:
        eta = (a * W * np.cos(W * t) - b * W * np.sin(W * t)
               + (c1 * r1 * np.exp(r1 * t) + c2 * r2 * np.exp(r2 * t)).real)
    return np.atleast_2d(rows) @ md.Phi @ eta


def peak_abs(f, t0, t1, dt, samples=None):
    """max |f(t)| over [t0, t1] (f vectorised): the largest sample on a grid of spacing <= dt (or the
    given ``samples`` = (t, f(t)) on any grid), refined by a bounded scalar search between its
    neighbours (Brent's bounded method to 1e-13 s)."""
    from scipy.optimize import minimize_scalar
    if samples is None:
        n = int(math.ceil((t1 - t0) / dt))
        t = np.linspace(t0, t1, n + 1)
        y = np.abs(f(t))
    else:
        t, y = samples[0], np.abs(samples[1])
    i = int(np.argmax(y))
    best = float(y[i])
    if 0 < i < t.size - 1:
        r = minimize_scalar(lambda s: -abs(float(f(np.array([s]))[0])), bounds=(t[i - 1], t[i + 1]),
                            method="bounded", options={"xatol": 1e-13})
        best = max(best, -float(r.fun))
    return best
