"""Joints as exact constraints g(z) = 0 (Lagrange multipliers), and the springs joints carry.

Every part of a model moves as a *frame* with three dofs (u, v, theta): a rod node (its
displacement and rotation) or a rigid body (the displacement of its centroid and its rotation); the
ground is a frame without dofs.  A point fixed to a frame at reference offset r from the frame's
origin X sits at X + (u, v) + R(theta) r.  A joint connects a point of part a to a point of part b
(both at the joint point ``at`` in the reference configuration); with w = p_a - p_b and the guide
direction e = R(theta_b) e0 carried by b, n = e turned by +90 degrees, the built-in kinds
(:mod:`femslide.joints.kinds`; one module each) are:

- ``pin``:    w = 0                                   (2 equations)
- ``weld``:   w = 0, theta_a - theta_b = 0            (3)
- ``slider``: w . n = 0, theta_a - theta_b = 0        (2; the slide s = w . e is free)
- ``roller``: w . n = 0                               (1)

A :class:`Link` is one joint of a model: its carriers, its dofs and the kinematics (w with its
derivatives, the guide, the slide, the relative rotation) that its kind's equations
(:meth:`femslide.joints.kind.JointKind.equations`) are written with.  Each constraint returns its
values g (m,), gradient G (m, k) and Hessians over its k <= 6 dofs (a's then b's), or, given the
multipliers mu, the weighted Hessian sum_i mu_i H_i that the Newton tangent needs.  The kinematics
are scalar ``math``: a joint has a handful of numbers, and numpy's per-call cost would dominate.
Sign of the multipliers: the equations are stationarity of U + V + mu . g, so the generalised force
of the joint on a is -G_a^T mu: a pin's force on a is -mu, a slider's transverse force on a is
-mu_1 n and its moment -mu_2.
"""
from __future__ import annotations

import math

import numpy as np

from femslide.joints.kind import JointKind
from femslide.joints.kinds import kind_of
from femslide.records import dataclass


@dataclass(frozen=True)
class Carrier:
    """One side of a joint: the frame's first dof (None for the ground), the frame origin X and the
    offset r of the joint point from it, in the reference configuration (model units)."""

    dof0: int | None
    X: tuple
    r: tuple

    @property
    def dofs(self):
        return np.arange(self.dof0, self.dof0 + 3) if self.dof0 is not None else np.zeros(0, np.intp)


def _point(z, i, c: Carrier):
    """(px, py, Rx, Ry, theta) of the carrier's joint point; Rr = R(theta) r."""
    rx, ry = c.r
    if i is None:
        return c.X[0] + rx, c.X[1] + ry, 0.0, 0.0, 0.0
    t = z[i + 2]
    if rx == 0.0 and ry == 0.0:   # a rod node: no lever
        return c.X[0] + z[i], c.X[1] + z[i + 1], 0.0, 0.0, t
    co, si = math.cos(t), math.sin(t)
    Rx, Ry = co * rx - si * ry, si * rx + co * ry
    return c.X[0] + z[i] + Rx, c.X[1] + z[i + 1] + Ry, Rx, Ry, t


class Link:
    """A joint between carriers a and b (see the module docstring): ``kind`` a registered type name
    or a :class:`JointKind`; ``axis`` the guide direction e0 (unit, reference configuration) of a
    kind with a guide.  ``link.kind`` is the type name, ``link.joint_kind`` the kind."""

    def __init__(self, name: str, kind: str | JointKind, a: Carrier, b: Carrier, axis=None, keep=None):
        jk = kind if isinstance(kind, JointKind) else kind_of(kind, f"joint {name}")
        self.name, self.kind, self.joint_kind, self.a, self.b = name, jk.name, jk, a, b
        # the kind's equations this link holds exactly (an elastic support turns the others into
        # springs, ElasticSupport); None: all of them
        self.keep = None if keep is None or tuple(keep) == tuple(range(jk.size)) else tuple(keep)
        self.size = jk.size if self.keep is None else len(self.keep)
        self.ia = 0 if a.dof0 is not None else None
        self.ib = (3 if a.dof0 is not None else 0) if b.dof0 is not None else None
        self.dofs = np.array([c.dof0 + i for c in (a, b) if c.dof0 is not None for i in range(3)], np.intp)
        self.k = self.dofs.size
        # a lever: the joint point is off the frame's origin of a part that turns (not the ground)
        self.lever_a = a.dof0 is not None and a.r != (0.0, 0.0)
        self.lever_b = b.dof0 is not None and b.r != (0.0, 0.0)
        self.e0 = tuple(axis) if axis is not None else (0.0, 1.0)
        self.n0 = (-self.e0[1], self.e0[0])
        # e.g. a pin or weld between rod nodes and the ground: constant gradient, no Hessian
        self.linear = jk.linear and not self.lever_a and not self.lever_b
        self._lin = None

    # -- kinematics ----------------------------------------------------------------------------------
    def w(self, z):
        """(wx, wy, dw, d2w, theta_a, theta_b) at the joint's dofs ``z`` (a list): w = p_a - p_b,
        its gradient dw = [(dof, dwx, dwy)], its second derivatives d2w = [(dof, d2wx, d2wy)] (only
        theta-theta of a carrier with a lever) and the two rotations (0 for the ground)."""
        ia, ib = self.ia, self.ib
        ax, ay, Rax, Ray, tha = _point(z, ia, self.a)
        bx, by, Rbx, Rby, thb = _point(z, ib, self.b)
        dw, d2w = [], []
        if ia is not None:
            dw += [(ia, 1.0, 0.0), (ia + 1, 0.0, 1.0)]
            if self.lever_a:
                dw.append((ia + 2, -Ray, Rax))
                d2w.append((ia + 2, -Rax, -Ray))
        if ib is not None:
            dw += [(ib, -1.0, 0.0), (ib + 1, 0.0, -1.0)]
            if self.lever_b:
                dw.append((ib + 2, Rby, -Rbx))
                d2w.append((ib + 2, Rbx, Rby))
        return ax - bx, ay - by, dw, d2w, tha, thb

    def guide(self, thb):
        """(ex, ey, nx, ny): the guide direction e and its normal n carried by b at b's rotation
        ``thb`` (constant for the ground)."""
        co, si = math.cos(thb), math.sin(thb)
        ex, ey = self.e0
        nx, ny = self.n0
        return co * ex - si * ey, si * ex + co * ey, co * nx - si * ny, si * nx + co * ny

    def _parts(self, z):
        """(g, G, hess) of the joint's kind at ``z`` (a list; :meth:`JointKind.equations`), the
        equations it holds exactly (``keep``) only."""
        g, G, hess = self.joint_kind.equations(self, z)
        if self.keep is None:
            return g, G, hess
        new = {old: i for i, old in enumerate(self.keep)}
        return ([g[i] for i in self.keep], [G[i] for i in self.keep],
                [(new[i], a, b, v) for i, a, b, v in hess if i in new])

    def _linear(self):
        """The constant parts of a linear joint (g = G z + g(0), no Hessian) as Python floats, built
        once: the nonzeros of G's rows, g(0) and the Jacobian entries of :meth:`assemble`."""
        if self._lin is None:
            k = self.k
            g0, G, _ = self._parts([0.0] * k)
            nz = [[(j, c) for j, c in enumerate(row) if c] for row in G]
            flat = [c for row in G for c in row]
            self._lin = (nz, g0, [0.0] * (k * k) + flat + flat)
        return self._lin

    def eval(self, z, mu=None):
        """g, G and the Hessians (m, k, k), or with ``mu`` the weighted Hessian (k, k) (the reference
        form: the model assembles through :meth:`assemble`, the tests compare the two)."""
        g, G, hess = self._parts(z.tolist())
        k = self.k
        if mu is None:
            H = np.zeros((len(g), k, k))
            for i, a, b, v in hess:
                H[i, a, b] += v
            return np.array(g), np.array(G), H
        mu = mu.tolist()
        Hmu = [0.0] * (k * k)
        for i, a, b, v in hess:
            Hmu[a * k + b] += mu[i] * v
        return np.array(g), np.array(G), np.array(Hmu).reshape(k, k)

    def assemble(self, z, mu, rv, jv):
        """The joint's share of the model's equations, as Python floats (``z``: its dofs' values,
        ``mu``: its multipliers, lists): appends the generalised forces mu . G (k, the residual
        rows of its dofs) and the equations g (m) to ``rv`` and, unless ``jv`` is None, the
        Jacobian entries in the model's pattern order to ``jv``: sum_i mu_i H_i (k x k), G (m x k)
        and G again (the transposed block).  The same numbers as :meth:`eval`."""
        k = self.k
        if self.linear:
            nz, g0, const = self._linear()
            f = [0.0] * k
            g = []
            for i, row in enumerate(nz):
                mi, gi = mu[i], 0.0
                for j, c in row:
                    f[j] += mi * c
                    gi += c * z[j]
                g.append(gi + g0[i])
            rv += f
            rv += g
            if jv is not None:
                jv += const
            return
        g, G, hess = self._parts(z)
        f = [0.0] * k
        for mi, row in zip(mu, G):
            for j in range(k):
                f[j] += mi * row[j]
        rv += f
        rv += g
        if jv is not None:
            Hmu = [0.0] * (k * k)
            for i, a, b, v in hess:
                Hmu[a * k + b] += mu[i] * v
            jv += Hmu
            for row in G:
                jv += row
            for row in G:
                jv += row

    # -- joint quantities ------------------------------------------------------------------------------
    def gap(self, z):
        """A contact's gap w . n (model units): the kind's first equation (:func:`on_guide`) at the
        joint dofs z, also when the statics released the joint (``keep`` empty)."""
        return float(self.joint_kind.equations(self, z.tolist())[0][0])

    def slide(self, z):
        """Slide s = w . e (model units), its gradient and Hessian over the joint dofs (kinds with a guide).
        The reference slide (0 when a starts at ``at``) is subtracted by the caller."""
        s, ds, H = self._slide(z.tolist())
        return s, np.array(ds), np.array(H).reshape(self.k, self.k)

    def slide_value(self, z) -> float:
        """The slide s of :meth:`slide` alone (model units; ``z`` the joint dofs' values, an array): the
        same arithmetic without the gradient and Hessian."""
        z = z.tolist()
        ax, ay, _, _, _ = _point(z, self.ia, self.a)
        bx, by, _, _, thb = _point(z, self.ib, self.b)
        ex, ey, _, _ = self.guide(thb)
        return (ax - bx) * ex + (ay - by) * ey

    def _slide(self, z):
        """:meth:`slide` as Python floats: s, ds (k), H (k x k, row-major); ``z`` a list."""
        k, ib = self.k, self.ib
        wx, wy, dw, d2w, _, thb = self.w(z)
        ex, ey, nx, ny = self.guide(thb)
        ds = [0.0] * k
        H = [0.0] * (k * k)
        for i, dx, dy in dw:
            ds[i] += dx * ex + dy * ey
        for i, hx, hy in d2w:
            H[i * k + i] += hx * ex + hy * ey
        if ib is not None:
            j = ib + 2
            ds[j] += wx * nx + wy * ny               # de/dthb = n
            for i, dx, dy in dw:
                v = dx * nx + dy * ny
                H[i * k + j] += v
                H[j * k + i] += v
            H[j * k + j] -= wx * ex + wy * ey        # d2e/dthb2 = -e
        return wx * ex + wy * ey, ds, H

    def rotation(self, z):
        """theta_a - theta_b [rad] and its gradient over the joint dofs."""
        t, d = self._rotation(z.tolist())
        return t, np.array(d)

    def _rotation(self, z):
        """:meth:`rotation` as Python floats; ``z`` a list."""
        d = [0.0] * self.k
        t = 0.0
        if self.ia is not None:
            t += z[self.ia + 2]
            d[self.ia + 2] = 1.0
        if self.ib is not None:
            t -= z[self.ib + 2]
            d[self.ib + 2] = -1.0
        return t, d

    def lever(self, z):
        """The lever (Rx, Ry) of a's joint point about a's frame origin, Python floats (``z`` a list)."""
        return _point(z, self.ia, self.a)[2:4]

    def point_a(self, z):
        """Position of a's joint point (model units) and the lever of a's forces about a's frame."""
        px, py, Rx, Ry, _ = _point(z.tolist(), self.ia, self.a)
        return np.array([px, py]), np.array([Rx, Ry])


@dataclass
class RotationalSpring:
    """Spiral spring c [model units] of a pin: energy (c/2) (theta_a - theta_b)^2."""

    link: Link
    c: float
    name: str = "spring"

    @property
    def dofs(self):
        return self.link.dofs

    def eval(self, z, lam=1.0):
        t, d = self.link.rotation(z)
        return 0.5 * self.c * t * t, self.c * t * d, self.c * np.outer(d, d), np.zeros(d.size)

    def energy(self, z, lam=1.0):
        """:meth:`eval`'s energy alone (the same arithmetic)."""
        t, _ = self.link._rotation(z.tolist())
        return 0.5 * self.c * t * t

    def assemble(self, z, lam, rv, jv, fv):
        """:meth:`eval` as Python floats for the model's assembly (``z`` a list): appends the
        generalised force to ``rv``, the Hessian (k x k) to ``jv`` (unless None) and d/d lam of the
        force to ``fv``."""
        t, d = self.link._rotation(z)
        ct, c = self.c * t, self.c
        rv += [ct * x for x in d]
        if jv is not None:
            jv += [c * (x * w) for x in d for w in d]
        fv += [0.0] * len(d)

    def stress_hessian(self, z, lam=1.0, linear=None):
        """A linear spring on a linear coordinate: no stress part."""
        return np.zeros((self.link.k, self.link.k))


@dataclass
class SlideSpring:
    """Linear spring k along a slider or roller: energy (k/2) s^2 - lam F0 s, with s the slide from
    the reference position; the preload F0 pushes a along +axis and is ramped with the loads."""

    link: Link
    k: float
    F0: float = 0.0
    s0: float = 0.0
    name: str = "spring"

    @property
    def dofs(self):
        return self.link.dofs

    def eval(self, z, lam=1.0):
        s, ds, Hs = self.link.slide(z)
        s -= self.s0
        f = self.k * s - lam * self.F0
        return (0.5 * self.k * s * s - lam * self.F0 * s, f * ds, self.k * np.outer(ds, ds) + f * Hs,
                -self.F0 * ds)

    def energy(self, z, lam=1.0):
        """:meth:`eval`'s energy alone (the same arithmetic)."""
        s = self.link.slide_value(z)
        s -= self.s0
        return 0.5 * self.k * s * s - lam * self.F0 * s

    def assemble(self, z, lam, rv, jv, fv):
        """:meth:`eval` as Python floats for the model's assembly (see RotationalSpring.assemble)."""
        s, ds, Hs = self.link._slide(z)
        s -= self.s0
        k = self.k
        f = k * s - lam * self.F0
        rv += [f * x for x in ds]
        if jv is not None:
            n = len(ds)
            jv += [k * (ds[i] * ds[j]) + f * Hs[i * n + j] for i in range(n) for j in range(n)]
        fv += [-self.F0 * x for x in ds]

    def stress_hessian(self, z, lam=1.0, linear=None):
        """The spring force times the slide's curvature, f Hs (the guide turning with b), at ``z``;
        ``linear``: the joint's displacements of a first-order state, the force then linear in them
        and the curvature at the reference."""
        if linear is None:
            s, _, Hs = self.link.slide(np.asarray(z, float))
            f = self.k * (s - self.s0) - lam * self.F0
        else:
            s0, ds, Hs = self.link.slide(np.zeros(self.link.k))
            f = self.k * (s0 - self.s0 + float(ds @ linear)) - lam * self.F0
        return f * Hs


@dataclass
class ElasticSupport:
    """The springs of an elastic support: equations of its link's kind (``springs``: (index,
    stiffness) pairs, model units) turned into the energies (k/2) g_i(z)^2 - a pin's w_x = 0 into a
    spring kx along x, a weld's rotation into kr, a guide's w . n = 0 into a spring across it.  Their
    generalised force is k g_i G_i, as a multiplier k g_i would give; the stresses of the springs
    (k g_i times the equations' curvature) are its geometric part (:meth:`stress_hessian`)."""

    link: Link
    springs: tuple
    name: str = "support"

    @property
    def dofs(self):
        return self.link.dofs

    def _terms(self, z):
        g, G, hess = self.link.joint_kind.equations(self.link, z)
        return [(i, k, g[i], G[i]) for i, k in self.springs], hess

    def eval(self, z, lam=1.0):
        rv, jv, fv = [], [], []
        self.assemble(z.tolist(), lam, rv, jv, fv)
        n = len(rv)
        force = np.array(rv)
        E = 0.0
        for _, k, gi, _ in self._terms(z.tolist())[0]:
            E += 0.5 * k * gi * gi
        return E, force, np.array(jv).reshape(n, n), np.zeros(n)

    def energy(self, z, lam=1.0):
        """:meth:`eval`'s energy alone (the same arithmetic)."""
        E = 0.0
        for _, k, gi, _ in self._terms(z.tolist())[0]:
            E += 0.5 * k * gi * gi
        return E

    def assemble(self, z, lam, rv, jv, fv):
        """:meth:`eval` as Python floats for the model's assembly (see RotationalSpring.assemble)."""
        n = self.link.k
        terms, hess = self._terms(z)
        f = [0.0] * n
        H = [0.0] * (n * n) if jv is not None else None
        for i, k, gi, Gi in terms:
            kg = k * gi
            for a in range(n):
                f[a] += kg * Gi[a]
            if H is not None:
                for a in range(n):
                    ka = k * Gi[a]
                    if ka:
                        for b in range(n):
                            H[a * n + b] += ka * Gi[b]
                for e, a, b, v in hess:
                    if e == i:
                        H[a * n + b] += kg * v
        rv += f
        if jv is not None:
            jv += H
        fv += [0.0] * n

    def stress_hessian(self, z, lam=1.0, linear=None):
        """The springs' stress part of the Hessian, sum_i k g_i H_i (k x k); ``linear``: the
        displacements of a first-order state (g_i linear in them, H_i at the reference)."""
        n = self.link.k
        H = np.zeros((n, n))
        if linear is None:
            terms, hess = self._terms(list(map(float, z)))
        else:
            terms, hess = self._terms([0.0] * n)
            terms = [(i, k, gi + float(np.dot(Gi, linear)), Gi) for i, k, gi, Gi in terms]
        for i, k, gi, _ in terms:
            for e, a, b, v in hess:
                if e == i:
                    H[a, b] += k * gi * v
        return H


def at_joint_point(link, z, f):
    """(Fx, Fy, M) at the joint point of a force f = (fx, fy, m) on part a's frame (``z`` the joint's
    dofs as a list): the frame moment about a's origin includes the moment of the force about it."""
    Rx, Ry = link.lever(z)
    return f[0], f[1], f[2] - (Rx * f[1] - Ry * f[0])
