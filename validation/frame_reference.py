"""Independent linear 2-D frame solver (direct stiffness method), a reference for femslide.

This module does not import femslide; it uses numpy only and is written from scratch so that it can
serve as an oracle for femslide's small-load (linear) limit.

Units and signs
---------------
SI units throughout (m, N, N m, N/m, N m^2).  Global axes: x right, y up.  Rotations and moments
are counter-clockwise positive.  Nodal displacements are (u, v, theta).

Members are Euler-Bernoulli beams with axial stiffness (3 dof per node: u, v, theta), no shear
deformation, linear (first-order) theory: equilibrium is written in the undeformed geometry.

Element formulation (exact for linearly varying EI and EA)
----------------------------------------------------------
Each (sub-)element of length L is treated by the flexibility method in its local axes (t along the
member from its first to its second node, n = t turned by +90 deg).  With the first end clamped, the
displacement (u2, v2, theta2) of the second end under end forces (N2, V2, M2) is F (N2, V2, M2) with

    F = [[int 1/EA, 0, 0], [0, int (L-s)^2/EI, int (L-s)/EI], [0, int (L-s)/EI, int 1/EI]],

integrals over 0 <= s <= L.  For EI(s) linear in s these integrals have the closed form
int_0^1 eta^k / (1 + beta eta) d eta = J_k(beta) (``_J``: a power series for |beta| <= 0.9, the
logarithmic closed form otherwise), so the element stiffness K = B^T F^-1 B, B = [-Gamma, I]
(Gamma carries a rigid motion of end 1 to end 2) is exact, not an approximation.  ``n_sub`` therefore
only adds output stations; it does not change the nodal results (checked in the tests).

Uniform distributed loads (qx, qy per unit length of member, global components, e.g. self-weight
rhoA g) are turned into exact fixed-end forces by the same flexibility integrals (end-2 displacement
of the clamped-free element under the load, cancelled by F^-1), so nodal displacements, reactions
and member forces are exact for uniform loads, also on tapered members.

Stress resultants along a member (``member_forces``): at arc length s from the member's first node,
N, V, M are the force and moment that the part of the member beyond s (towards n2) exerts on the part
before s, in local axes: N along t (tension positive), V along n, M counter-clockwise.  With this
convention M = EI d theta / ds (positive when the member turns counter-clockwise as s increases:
sagging of a left-to-right beam), dM/ds = -V, dV/ds = -q_n, dN/ds = -q_t.

Supports, pins and the solution
-------------------------------
Supports are kinematic constraints built into a basis Z of the admissible displacements (u = Z w),
no penalty and no Lagrange multiplier: a fixed dof is dropped, a roller's translation is u = w d
(d its rolling direction).  K_red = Z^T K Z is scaled by its diagonal and solved by numpy.linalg.solve;
a condition number above ``COND_MAX`` is reported as a mechanism (so model a "rigid" member with EA or EI
at most ~1e10 times the others' scale, not 1e20).  Reactions are the residual R = K u - f at the
supported nodes (force and moment of the support on the structure),
projected on the constrained directions.  An internal pin (``hinge``) gives the member end its own
rotation dof; a node whose rotation is connected to no member (all member ends at it pinned) has no
rotation dof (``disp`` returns nan for its theta).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

__all__ = ["Frame", "FrameResult", "portal_pinned_lateral"]

COND_MAX = 1e15   # condition number (after diagonal scaling) above which solve() reports a mechanism


# -- exact integrals of s^k / (linear function) --------------------------------------------------------

def _J(k: int, beta: float) -> float:
    """J_k(beta) = int_0^1 eta^k / (1 + beta eta) d eta, beta > -1, k = 0..3, to ~1e-15 relative.

    |beta| <= 0.9: the series sum_n (-beta)^n / (n + k + 1), summed smallest term first.  Otherwise
    with t = 1 + beta eta:  J_k = beta^-(k+1) int_1^(1+beta) (t - 1)^k / t dt
    = beta^-(k+1) [(-1)^k ln(1 + beta) + sum_{j=1..k} C(k, j) (-1)^(k-j) ((1 + beta)^j - 1) / j]."""
    if beta <= -1.0:
        raise ValueError("EI and EA must stay positive along a member")
    if beta == 0.0:
        return 1.0 / (k + 1)
    if abs(beta) <= 0.9:
        nterms = math.ceil(math.log(1e-18) / math.log(abs(beta))) + 2 if abs(beta) > 1e-300 else 1
        n = np.arange(nterms - 1, -1, -1, dtype=float)
        return float(np.sum((-beta) ** n / (n + k + 1)))
    lp = math.log1p(beta)
    acc = (-1.0) ** k * lp
    for j in range(1, k + 1):
        acc += math.comb(k, j) * (-1.0) ** (k - j) * math.expm1(j * lp) / j
    return acc / beta ** (k + 1)


def _int_pow_over_linear(k: int, s: float, f0: float, f1: float, L: float) -> float:
    """int_0^s t^k / f(t) dt for f(t) = f0 + (f1 - f0) t / L (exact)."""
    if s == 0.0:
        return 0.0
    return s ** (k + 1) / f0 * _J(k, (f1 / f0 - 1.0) * s / L)


# -- the element --------------------------------------------------------------------------------------

@dataclass
class _Element:
    member: str
    s0: float            # arc length of its first node along the member
    L: float
    c: float             # direction cosines of t
    s: float
    EI1: float
    EI2: float
    EA1: float
    EA2: float
    qt: float            # distributed load, local components, per unit length
    qn: float
    dofs: list           # 6 global dof indices (u1, v1, th1, u2, v2, th2)
    k_loc: np.ndarray = field(default=None, repr=False)
    f_fix: np.ndarray = field(default=None, repr=False)   # forces of the nodes on the clamped element

    def build(self):
        L = self.L
        # integrals of (L - s)^k / EI and (L - s)^k / EA: substitute eta = 1 - s / L, base at end 2
        bI = self.EI1 / self.EI2 - 1.0
        G = [L ** (k + 1) / self.EI2 * _J(k, bI) for k in range(4)]
        bA = self.EA1 / self.EA2 - 1.0
        H = [L ** (k + 1) / self.EA2 * _J(k, bA) for k in range(2)]
        det = G[2] * G[0] - G[1] ** 2
        K22 = np.array([[1.0 / H[0], 0.0, 0.0],
                        [0.0, G[0] / det, -G[1] / det],
                        [0.0, -G[1] / det, G[2] / det]])
        Gam = np.array([[1.0, 0.0, 0.0], [0.0, 1.0, L], [0.0, 0.0, 1.0]])
        B = np.hstack([-Gam, np.eye(3)])
        self.k_loc = B.T @ K22 @ B
        # end-2 displacement of the element clamped at end 1 under the uniform load
        d0 = np.array([self.qt * H[1], 0.5 * self.qn * G[3], 0.5 * self.qn * G[2]])
        f2 = -K22 @ d0
        f1 = np.array([-f2[0] - self.qt * L,
                       -f2[1] - self.qn * L,
                       -f2[2] - L * f2[1] - 0.5 * self.qn * L ** 2])
        self.f_fix = np.concatenate([f1, f2])

    def T(self) -> np.ndarray:
        c, s = self.c, self.s
        R = np.array([[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]])
        T = np.zeros((6, 6))
        T[:3, :3] = R
        T[3:, 3:] = R
        return T


# -- model ----------------------------------------------------------------------------------------------

@dataclass
class _Member:
    n1: str
    n2: str
    EI: float
    EA: float
    n_sub: int
    EI_end: float
    EA_end: float
    q: np.ndarray
    hinged: set


class Frame:
    """A planar linear frame.  Build it with ``node``, ``beam``, supports, pins and loads, then
    ``solve()``.  Names are any hashable values."""

    def __init__(self):
        self.nodes: dict = {}
        self.members: dict = {}
        self.supports: dict = {}
        self.loads: dict = {}

    # geometry and members
    def node(self, name, x: float, y: float):
        """Node at (x, y) [m]."""
        if name in self.nodes:
            raise ValueError(f"node {name!r} exists")
        self.nodes[name] = np.array([float(x), float(y)])
        return self

    def beam(self, name, n1, n2, EI: float, EA: float, n_sub: int = 1,
             EI_end: float | None = None, EA_end: float | None = None):
        """Member from node n1 to n2, bending stiffness EI [N m^2], axial stiffness EA [N].

        ``EI_end`` / ``EA_end``: value at n2 (linear variation from n1, exact element); ``n_sub``
        sub-elements (extra output stations only: the element is exact)."""
        if name in self.members:
            raise ValueError(f"member {name!r} exists")
        for n in (n1, n2):
            if n not in self.nodes:
                raise KeyError(f"unknown node {n!r}")
        EI_end = EI if EI_end is None else EI_end
        EA_end = EA if EA_end is None else EA_end
        if min(EI, EA, EI_end, EA_end) <= 0:
            raise ValueError("EI and EA must be positive")
        if int(n_sub) < 1:
            raise ValueError("n_sub >= 1")
        self.members[name] = _Member(n1, n2, float(EI), float(EA), int(n_sub), float(EI_end),
                                     float(EA_end), np.zeros(2), set())
        return self

    # pins
    def hinge(self, beam, node):
        """Internal pin: the end of member ``beam`` at ``node`` gets its own rotation (it shares the
        node's translation but transmits no moment to it)."""
        m = self.members[beam]
        if node not in (m.n1, m.n2):
            raise ValueError(f"member {beam!r} does not end at node {node!r}")
        m.hinged.add(node)
        return self

    def pin(self, node):
        """Pin every member end at ``node`` (the members turn independently about it)."""
        for m in self.members.values():
            if node in (m.n1, m.n2):
                m.hinged.add(node)
        return self

    # supports
    def support(self, node, ux: bool = True, uy: bool = True, rz: bool = False):
        """Fix the chosen dofs of ``node`` (default: a pin).  ``rz=True`` with both translations: a clamp."""
        self.supports[node] = ("fix", bool(ux), bool(uy), bool(rz))
        return self

    def support_roller(self, node, direction, rz: bool = False):
        """Roller: ``node`` may move only along ``direction`` (any nonzero 2-vector); rotation free
        unless ``rz`` (then a sliding clamp).  The reaction is normal to ``direction``."""
        d = np.asarray(direction, float)
        d = d / np.hypot(*d)
        self.supports[node] = ("roller", d, bool(rz))
        return self

    # loads
    def load(self, node, Fx: float = 0.0, Fy: float = 0.0, Mz: float = 0.0):
        """Point force [N] and moment [N m] on ``node`` (accumulates)."""
        self.loads.setdefault(node, np.zeros(3))
        self.loads[node] += (Fx, Fy, Mz)
        return self

    def distributed(self, beam, qx: float = 0.0, qy: float = 0.0):
        """Uniform load [N/m] per unit member length, global components (accumulates)."""
        self.members[beam].q += (qx, qy)
        return self

    def self_weight(self, beam, rhoA: float, g=(0.0, -9.81)):
        """Self-weight: rhoA [kg/m] times g [m/s^2] per unit length."""
        return self.distributed(beam, rhoA * g[0], rhoA * g[1])

    # -- solution -----------------------------------------------------------------------------------
    def solve(self) -> FrameResult:
        names = list(self.nodes)
        index = {n: i for i, n in enumerate(names)}
        coords = [self.nodes[n] for n in names]
        rot_used = np.zeros(len(names), bool)

        # pass 1: interior nodes of subdivided members (3 dofs each, numbered after the named nodes)
        member_nodes = {}
        for mname, m in self.members.items():
            p1, p2 = self.nodes[m.n1], self.nodes[m.n2]
            if float(np.hypot(*(p2 - p1))) == 0.0:
                raise ValueError(f"member {mname!r} has zero length")
            ids = [index[m.n1]]
            for k in range(1, m.n_sub):
                coords.append(p1 + (p2 - p1) * k / m.n_sub)
                rot_used = np.append(rot_used, True)
                ids.append(len(coords) - 1)
            ids.append(index[m.n2])
            member_nodes[mname] = ids
        ndof = 3 * len(coords)

        # pass 2: pinned member ends (one rotation dof each, after all node dofs) and the elements
        elements, stations = [], {}
        for mname, m in self.members.items():
            p1, p2 = self.nodes[m.n1], self.nodes[m.n2]
            Lm = float(np.hypot(*(p2 - p1)))
            c, s = (p2 - p1) / Lm
            node_ids = member_nodes[mname]
            extra = {}
            for end in sorted(m.hinged, key=lambda n: n != m.n1):   # own rotation dof for a pinned end
                extra[end] = ndof
                ndof += 1
            qt = m.q[0] * c + m.q[1] * s
            qn = -m.q[0] * s + m.q[1] * c
            els = []
            for k in range(m.n_sub):
                a, b = node_ids[k], node_ids[k + 1]
                xa, xb = k / m.n_sub, (k + 1) / m.n_sub
                th_a, th_b = 3 * a + 2, 3 * b + 2
                if k == 0 and m.n1 in extra:
                    th_a = extra[m.n1]
                else:
                    rot_used[a] = True
                if k == m.n_sub - 1 and m.n2 in extra:
                    th_b = extra[m.n2]
                else:
                    rot_used[b] = True
                e = _Element(mname, xa * Lm, Lm / m.n_sub, c, s,
                             m.EI + (m.EI_end - m.EI) * xa, m.EI + (m.EI_end - m.EI) * xb,
                             m.EA + (m.EA_end - m.EA) * xa, m.EA + (m.EA_end - m.EA) * xb,
                             qt, qn, [3 * a, 3 * a + 1, th_a, 3 * b, 3 * b + 1, th_b])
                e.build()
                els.append(e)
                elements.append(e)
            stations[mname] = (Lm, els, extra)

        K = np.zeros((ndof, ndof))
        f = np.zeros(ndof)
        for e in elements:
            T = e.T()
            ke = T.T @ e.k_loc @ T
            ix = np.ix_(e.dofs, e.dofs)
            K[ix] += ke
            f[e.dofs] -= T.T @ e.f_fix
        for n, F in self.loads.items():
            i = index[n]
            f[3 * i:3 * i + 3] += F
            if F[2] != 0.0 and not rot_used[i] and not self._rz_fixed(n):
                raise ValueError(f"moment on node {n!r}, which no member end resists (all pinned)")

        # basis of admissible displacements
        cols = []
        def unit(i, vec=None):
            z = np.zeros(ndof)
            if vec is None:
                z[i] = 1.0
            else:
                z[i:i + 2] = vec
            cols.append(z)
        for i in range(len(coords)):
            name = names[i] if i < len(names) else None
            sup = self.supports.get(name) if name is not None else None
            if sup is None:
                unit(3 * i)
                unit(3 * i + 1)
                rz = False
            elif sup[0] == "fix":
                _, ux, uy, rz = sup
                if not ux:
                    unit(3 * i)
                if not uy:
                    unit(3 * i + 1)
            else:
                _, d, rz = sup
                unit(3 * i, d)
            if rot_used[i] and not rz:
                unit(3 * i + 2)
        for i in range(3 * len(coords), ndof):
            unit(i)
        Z = np.array(cols).T if cols else np.zeros((ndof, 0))
        Kr = Z.T @ K @ Z
        if Kr.size:
            # symmetric diagonal scaling (translations and rotations have different units)
            dg = np.sqrt(np.abs(np.diag(Kr)))
            if np.any(dg == 0.0):
                raise np.linalg.LinAlgError("the frame is a mechanism (a free dof has no stiffness)")
            Ks = Kr / np.outer(dg, dg)
            if np.linalg.cond(Ks) > COND_MAX:
                raise np.linalg.LinAlgError("the frame is a mechanism (singular stiffness)")
            w = np.linalg.solve(Ks, (Z.T @ f) / dg) / dg
        else:
            w = np.zeros(0)
        u = Z @ w
        R = K @ u - f
        return FrameResult(self, index, u, R, stations, rot_used)

    def _rz_fixed(self, n):
        sup = self.supports.get(n)
        return sup is not None and sup[-1] is True


class FrameResult:
    """Solution of a ``Frame``: nodal displacements, reactions and member stress resultants."""

    def __init__(self, frame, index, u, R, stations, rot_used):
        self.frame, self._index, self._u, self._R = frame, index, u, R
        self._stations, self._rot_used = stations, rot_used

    def disp(self, node):
        """(u [m], v [m], theta [rad]) of a named node; theta is nan at a node whose member ends are
        all pinned (use ``end_rotation``)."""
        i = self._index[node]
        th = self._u[3 * i + 2] if self._rot_used[i] else math.nan
        return float(self._u[3 * i]), float(self._u[3 * i + 1]), float(th)

    def end_rotation(self, beam, node):
        """Rotation [rad] of the end of member ``beam`` at ``node`` (differs from the node's if pinned)."""
        els = self._stations[beam][1]
        m = self.frame.members[beam]
        e = els[0] if node == m.n1 else els[-1]
        return float(self._u[e.dofs[2] if node == m.n1 else e.dofs[5]])

    def reaction(self, node):
        """(Fx [N], Fy [N], M [N m]): force and moment of the support on the structure at ``node``
        (components along free directions are exactly 0)."""
        sup = self.frame.supports.get(node)
        if sup is None:
            raise KeyError(f"node {node!r} has no support")
        i = self._index[node]
        Fx, Fy, Mz = self._R[3 * i:3 * i + 3]
        if sup[0] == "fix":
            _, ux, uy, rz = sup
            Fx, Fy = (Fx if ux else 0.0), (Fy if uy else 0.0)
        else:
            _, d, rz = sup
            nrm = np.array([-d[1], d[0]])
            Fx, Fy = nrm * (nrm @ (Fx, Fy))
        Mz = Mz if rz else 0.0
        return float(Fx), float(Fy), float(Mz)

    # -- along a member -------------------------------------------------------------------------------
    def _locate(self, beam, s):
        Lm, els, _ = self._stations[beam]
        if not -1e-12 * Lm <= s <= Lm * (1 + 1e-12):
            raise ValueError(f"s = {s} outside [0, {Lm}]")
        k = min(int(s / els[0].L), len(els) - 1)
        e = els[max(k, 0)]
        return e, s - e.s0

    def _end_forces(self, e):
        T = e.T()
        return e.k_loc @ (T @ self._u[e.dofs]) + e.f_fix   # local forces of the nodes on the element

    def member_forces(self, beam, s: float):
        """(N [N], V [N], M [N m]) at arc length s [m] from the member's n1: resultants of the part
        beyond s on the part before s in local axes (N tension positive, M = EI dtheta/ds)."""
        e, x = self._locate(beam, s)
        f1 = self._end_forces(e)[:3]
        N = -f1[0] - e.qt * x
        V = -f1[1] - e.qn * x
        M = -f1[2] + x * f1[1] + 0.5 * e.qn * x * x
        return float(N), float(V), float(M)

    def member_disp(self, beam, s: float):
        """Global (u, v, theta) of the member's axis at arc length s (exact for uniform loads and
        linear EI, EA: theta = theta1 + int M/EI, deflection = int theta, axial = int N/EA)."""
        e, x = self._locate(beam, s)
        T = e.T()
        d = T @ self._u[e.dofs]
        f1 = self._end_forces(e)[:3]
        A, B, C = -f1[2], f1[1], 0.5 * e.qn          # M(x) = A + B x + C x^2
        I = [_int_pow_over_linear(k, x, e.EI1, e.EI2, e.L) for k in range(4)]
        th = d[2] + A * I[0] + B * I[1] + C * I[2]
        w = d[1] + d[2] * x + x * (A * I[0] + B * I[1] + C * I[2]) - (A * I[1] + B * I[2] + C * I[3])
        IA = [_int_pow_over_linear(k, x, e.EA1, e.EA2, e.L) for k in range(2)]
        ut = d[0] - f1[0] * IA[0] - e.qt * IA[1]
        return float(e.c * ut - e.s * w), float(e.s * ut + e.c * w), float(th)

    def moment_max(self, beam, where: bool = False):
        """max |M| [N m] along the member (ends of every sub-element and the vertex of the load
        parabola); with ``where`` also the arc length where it occurs."""
        best, at = -1.0, 0.0
        for e in self._stations[beam][1]:
            f1 = self._end_forces(e)[:3]
            A, B, C = -f1[2], f1[1], 0.5 * e.qn
            xs = [0.0, e.L]
            if C != 0.0 and 0.0 < -B / (2 * C) < e.L:
                xs.append(-B / (2 * C))
            for x in xs:
                val = abs(A + B * x + C * x * x)
                if val > best:
                    best, at = val, e.s0 + x
        return (float(best), float(at)) if where else float(best)

    def equilibrium_residual(self, about=(0.0, 0.0)):
        """(sum Fx, sum Fy, sum M about ``about``) of all reactions and applied loads (should be ~0)."""
        fr = self.frame
        Fx = Fy = Mz = 0.0
        def add(p, F, M=0.0):
            nonlocal Fx, Fy, Mz
            Fx += F[0]
            Fy += F[1]
            Mz += M + (p[0] - about[0]) * F[1] - (p[1] - about[1]) * F[0]
        for n in fr.supports:
            r = self.reaction(n)
            add(fr.nodes[n], r[:2], r[2])
        for n, F in fr.loads.items():
            add(fr.nodes[n], F[:2], F[2])
        for m in fr.members.values():
            p1, p2 = fr.nodes[m.n1], fr.nodes[m.n2]
            Lm = float(np.hypot(*(p2 - p1)))
            add(0.5 * (p1 + p2), m.q * Lm)
        return Fx, Fy, Mz


def portal_pinned_lateral(H: float, h: float, L: float, EI_c: float, EI_b: float,
                          EA_b: float = math.inf):
    """Closed form: pinned-base portal frame, welded corners, horizontal load H at the top of the
    left column.  Feet A = (0, 0), D = (L, 0); corners B = (0, h), C = (L, h).

    Force method (unit-load theorem, e.g. Hibbeler, Structural Analysis, force method chapter), the
    horizontal reaction at D as redundant X (primary structure: roller at D).  Bending and the beam's
    axial strain enter (the columns' axial forces have no part in the redundant's unit state):

        d10 = H h^3 / (3 EI_c) + H h^2 L / (2 EI_b),
        d11 = 2 h^3 / (3 EI_c) + h^2 L / EI_b + L / EA_b,     D_x = -d10 / d11,  A_x = -H - D_x,
        A_y = -H h / L, D_y = H h / L (moments about a foot, exact),
        corner moments (M = EI dtheta/ds along A->B and D->C): M_B = -A_x h, M_C = -D_x h.

    For EA_b -> inf: A_x = D_x = -H/2 (the classical antisymmetry result) and |M_B| = |M_C| = H h / 2.
    Returns a dict with Ax, Ay, Dx, Dy (forces of the ground on the frame), MB, MC."""
    d10 = H * h ** 3 / (3 * EI_c) + H * h ** 2 * L / (2 * EI_b)
    d11 = 2 * h ** 3 / (3 * EI_c) + h ** 2 * L / EI_b + L / EA_b
    Dx = -d10 / d11
    Ax = -H - Dx
    return dict(Ax=Ax, Ay=-H * h / L, Dx=Dx, Dy=H * h / L, MB=-Ax * h, MC=-Dx * h)
