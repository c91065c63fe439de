"""Masses of a discretised structure for the dynamics (built only when a dynamic run asks for them).

Units are the model's (:mod:`femslide.model.discrete`): lengths by ``Lref`` [m], forces by ``Fref`` [N],
time in seconds; a mass m [kg] becomes m Lref / Fref and a rotary inertia J [kg m^2] becomes
J / (Fref Lref), so that (model mass) x (model acceleration) is a model force.

Rods: the mass per length rhoA [kg/m] is lumped at the nodes, each element passing rhoA L_e / 2 to
each of its two nodes (row-sum lumping of the consistent translational mass; for a uniform mesh the
same as HRZ lumping of the translations).  The nodes get **no rotary inertia**: Euler-Bernoulli theory
has none, the lumped translational masses already carry the rod's whole mass and first moment of mass,
and massless rotations leave no spurious high frequencies (~ sqrt(EI / (rhoA h^4))) for the
integrator to resolve.  The rotations are then algebraic unknowns that follow the translations
quasi-statically (the iteration matrix stays regular because the stiffness is).  Lumping is second
order: the natural frequencies of a uniform rod converge like h^2 (validation: cantilever modes).
rhoA = 0 (the paper's massless rods) is allowed: such rods follow the masses quasi-statically.

Bodies: mass m at the centroid C and inertia J about C, with the exact rigid-body kinematics when
the body's frame origin O (its first ground pin, else the centroid) is not C: with
rho = R(theta) (C0 - O0) the lever from O to C now, the centroid moves with
a_C = u'' + theta'' rho_perp - theta'^2 rho (rho_perp = rho turned by +90 degrees), and the
generalised inertia force on (u, v, theta) is (m a_C, J theta'' + m rho_perp . a_C): the body's mass
matrix M(theta) = [[m, 0, -m rho_y], [0, m, m rho_x], [-m rho_y, m rho_x, J + m |rho|^2]] plus the
centripetal term.  A body with m = 0 (a rigid link) has no inertia.
"""
from __future__ import annotations

import math

import numpy as np

from femslide.model.linalg import distinct, kernel_function


class Masses:
    """The masses of a :class:`femslide.model.discrete.Model` (model units, see the module docstring)."""

    SCALAR_BODIES = 8   # up to this many bodies, inertia() loops in Python; above, numpy over bodies

    def __init__(self, model):
        fs = model.structure
        L, F = model.Lref, model.Fref
        self.unit_m = L / F            # kg -> model mass
        self.unit_J = 1.0 / (F * L)    # kg m^2 -> model rotary inertia
        self.n_q = model.n_q
        node_m = np.zeros(model.n_nodes)
        if model.elements is not None:
            L0 = model.elements.L0 * L  # element lengths [m]
            rhoA = np.array([r.rhoA for r in fs.rods], float)[model.elem_rod]
            half = 0.5 * rhoA * L0
            np.add.at(node_m, model.elements.conn[:, 0], half)
            np.add.at(node_m, model.elements.conn[:, 1], half)
        self.node_m = node_m * self.unit_m
        heavy = np.nonzero(self.node_m > 0)[0]
        self.node_dofs = np.concatenate([3 * heavy, 3 * heavy + 1]).astype(np.intp)
        self.node_vals = np.concatenate([self.node_m[heavy], self.node_m[heavy]])
        bodies = [b for b in fs.bodies if b.mass > 0 or (b.inertia or 0.0) > 0]
        self.body_d = np.array([model.body_dof(b.name) for b in bodies], np.intp)
        self.body_m = np.array([b.mass for b in bodies], float) * self.unit_m
        self.body_J = np.array([b.inertia or 0.0 for b in bodies], float) * self.unit_J
        self.body_r = np.array([np.asarray(b.centroid, float) / L - model.body_X0[model.body_index[b.name]]
                                for b in bodies], float).reshape(-1, 2)
        # the 3 x 3 blocks of the bodies in COO order (row-major per body)
        d = self.body_d[:, None] + np.arange(3)[None, :]
        self.block_rows = np.repeat(d, 3, axis=1).ravel()
        self.block_cols = np.tile(d, (1, 3)).ravel()
        self._body_list = [(int(d), float(m), float(J), (float(r[0]), float(r[1])))
                           for d, m, J, r in zip(self.body_d, self.body_m, self.body_J, self.body_r)]
        # the compiled kernel's inertia (femslide.model._assembly.inertia), if it is used when the masses
        # are built (they keep it, as a model keeps its assembly), and its inputs: dofs as int64, per body
        # m, J, rho0
        self._kern = kernel_function("inertia")
        self._kern_dofs = (self.node_dofs.astype(np.int64), self.body_d.astype(np.int64),
                           np.ascontiguousarray(np.column_stack([self.body_m, self.body_J, self.body_r]).reshape(-1)))
        self.coo_rows = np.concatenate([self.node_dofs, self.block_rows])
        self.coo_cols = np.concatenate([self.node_dofs, self.block_cols])
        self.total_mass = float(node_m.sum() + sum(b.mass for b in bodies))  # kg

    # -- which dofs carry inertia ------------------------------------------------------------------
    def massive_dofs(self):
        """Dofs with inertia (lumped node translations, body dofs with mass or inertia)."""
        b = [self.body_d[:, None] + np.arange(3)[None, :]] if self.body_d.size else []
        return distinct(np.concatenate([self.node_dofs, *[x.ravel() for x in b]])).astype(np.intp)

    # -- body kinematics -----------------------------------------------------------------------------
    def _rho(self, q):
        """The bodies' levers from frame origin to centroid, rotated: (px, py, theta) at q (n_q,), or
        (k, bodies) each at k states q (k, n_q)."""
        th = q[..., self.body_d + 2]
        c, s = np.cos(th), np.sin(th)
        rx, ry = self.body_r[:, 0], self.body_r[:, 1]
        return c * rx - s * ry, s * rx + c * ry, th

    def _blocks(self, q):
        """Body mass matrices M(theta) (nb, 3, 3)."""
        m, J = self.body_m, self.body_J
        px, py, _ = self._rho(q)
        B = np.zeros((m.size, 3, 3))
        B[:, 0, 0] = B[:, 1, 1] = m
        B[:, 0, 2] = B[:, 2, 0] = -m * py
        B[:, 1, 2] = B[:, 2, 1] = m * px
        B[:, 2, 2] = J + m * (px * px + py * py)
        return B

    def matrix(self, q):
        """The mass matrix at q as COO (rows, cols, values)."""
        return self.coo_rows, self.coo_cols, np.concatenate([self.node_vals, self._blocks(q).ravel()])

    def dense(self, q):
        M = np.zeros((self.n_q, self.n_q))
        r, c, v = self.matrix(q)
        np.add.at(M, (r, c), v)
        return M

    def inertia(self, q, v, acc, c_acc=0.0, c_vel=0.0, ground=None):
        """Generalised inertia force f (n_q,) at positions q, velocities v, accelerations acc, minus
        the inertia load of a base acceleration ``ground`` (a (2,) vector, model units, or None), and
        its derivative with respect to q along a step in which acc and v change by ``c_acc`` and
        ``c_vel`` times the change of q: COO (rows, cols, values) (rows and cols are fixed arrays)."""
        f = np.zeros(self.n_q)
        nd = self.node_dofs
        if nd.size:
            f[nd] = self.node_vals * acc[nd]
            if ground is not None:
                k = nd.size // 2
                f[nd[:k]] += self.node_vals[:k] * ground[0]
                f[nd[k:]] += self.node_vals[k:] * ground[1]
        if not self.body_d.size:
            return f, (self.coo_rows, self.coo_cols, c_acc * self.node_vals)
        if self.body_d.size <= self.SCALAR_BODIES:   # a few bodies: scalar arithmetic is faster than numpy's calls
            vals = [c_acc * self.node_vals]
            gx, gy = (float(ground[0]), float(ground[1])) if ground is not None else (0.0, 0.0)
            for d, m, J, (rx, ry) in self._body_list:
                th = float(q[d + 2])
                c, s_ = math.cos(th), math.sin(th)
                px, py = c * rx - s_ * ry, s_ * rx + c * ry
                ux, uy, tdd = float(acc[d]) + gx, float(acc[d + 1]) + gy, float(acc[d + 2])
                td = float(v[d + 2])
                td2 = td * td
                ax = ux - tdd * py - td2 * px
                ay = uy + tdd * px - td2 * py
                f[d:d + 3] += (m * ax, m * ay, J * tdd + m * (px * ay - py * ax))
                mc = c_acc * m
                vals.append(np.array([
                    mc, 0.0, -mc * py + m * (-2.0 * c_vel * td * px - tdd * px + td2 * py),
                    0.0, mc, mc * px + m * (-2.0 * c_vel * td * py - tdd * py - td2 * px),
                    -mc * py, mc * px, c_acc * (J + m * (px * px + py * py)) - m * (px * ux + py * uy)]))
            return f, (self.coo_rows, self.coo_cols, np.concatenate(vals))
        d = self.body_d
        m, J = self.body_m, self.body_J
        px, py, _ = self._rho(q)
        ux, uy, tdd = acc[d], acc[d + 1], acc[d + 2]
        td = v[d + 2]
        td2 = td * td
        if ground is not None:
            ux = ux + ground[0]
            uy = uy + ground[1]
        # a_C (+ the base acceleration: the inertia load -m a_g moved to the left-hand side)
        ax = ux - tdd * py - td2 * px
        ay = uy + tdd * px - td2 * py
        f[d] += m * ax
        f[d + 1] += m * ay
        f[d + 2] += J * tdd + m * (px * ay - py * ax)
        B = np.empty((m.size, 9))
        mc = c_acc * m
        B[:, 0] = B[:, 4] = mc
        B[:, 1] = B[:, 3] = 0.0
        B[:, 6] = -mc * py
        B[:, 7] = mc * px
        # d/dtheta' (centripetal) and d/dtheta (the lever turns) in the theta column
        B[:, 2] = -mc * py + m * (-2.0 * c_vel * td * px - tdd * px + td2 * py)
        B[:, 5] = mc * px + m * (-2.0 * c_vel * td * py - tdd * py - td2 * px)
        B[:, 8] = c_acc * (J + m * (px * px + py * py)) - m * (px * ux + py * uy)
        return f, (self.coo_rows, self.coo_cols, np.concatenate([c_acc * self.node_vals, B.ravel()]))

    def inertia_parts(self, Q, V, ACC, ground=None):
        """:meth:`inertia` at k states at once (the rows of Q, V, ACC, each (k, n_q); ``ground`` None
        or k base accelerations (2,), model units), its derivative split by its linear dependence on
        c_acc and c_vel: returns (F (k, n_q), base, mass, vel), each of the last three (k, nnz) values
        in the order of (``coo_rows``, ``coo_cols``), such that inertia(q, v, acc, c_acc, c_vel)'s
        derivative is base + c_acc mass + c_vel vel (mass: the mass matrix M(q); vel: the centripetal
        terms' velocity part).  One call per Newton iteration of a time step instead of three per
        stage and part.  The parts are rounded as the difference of inertia() at c_acc = 1 (c_vel = 1)
        and at 0 rounds them (the mass matrix's lever column (-m rho_y, m rho_x, J + m |rho|^2) to
        within an ulp of the base terms), so that a time step's Newton matrices, and with them its
        converged iterates, are bitwise those of the separate calls (the exact parts instead moved
        section 5.2's histories by up to 9e-8 relative: Newton stops within its tolerance, and where
        within it depends on the matrix's last bits)."""
        k = Q.shape[0]
        nd, nv = self.node_dofs, self.node_vals
        nn, nnz = nv.size, self.coo_rows.size
        g = None if ground is None or ground[0] is None else np.asarray(ground, float).reshape(k, 2)
        kern = self._kern
        if kern is not None and nnz:   # the same arithmetic in C (bodies: libm's cos and sin, as math's)
            F, base, mass, vel = np.empty((k, self.n_q)), np.empty((k, nnz)), np.empty((k, nnz)), np.empty((k, nnz))
            kd, bd, bdat = self._kern_dofs
            kern(np.ascontiguousarray(Q, float), np.ascontiguousarray(V, float), np.ascontiguousarray(ACC, float),
                 g, kd, nv, bd, bdat, F, base, mass, vel)
            return F, base, mass, vel
        F = np.zeros((k, self.n_q))
        if nd.size:
            F[:, nd] = nv * ACC[:, nd]
            if g is not None:
                h = nd.size // 2
                F[:, nd[:h]] += nv[:h] * g[:, :1]
                F[:, nd[h:]] += nv[h:] * g[:, 1:]
        base = np.zeros((k, nnz))
        vel = np.zeros((k, nnz))
        mass = np.empty((k, nnz))
        mass[:, :nn] = nv
        if not self.body_d.size:
            return F, base, mass, vel
        if self.body_d.size <= self.SCALAR_BODIES:   # scalar arithmetic: faster than numpy's calls
            for s in range(k):
                q, v, acc, Fs, bs, ms, vs = Q[s], V[s], ACC[s], F[s], base[s], mass[s], vel[s]
                gx, gy = (float(g[s, 0]), float(g[s, 1])) if g is not None else (0.0, 0.0)
                o = nn
                for d, m, J, (rx, ry) in self._body_list:
                    th = float(q[d + 2])
                    c, s_ = math.cos(th), math.sin(th)
                    px, py = c * rx - s_ * ry, s_ * rx + c * ry
                    ux, uy, tdd = float(acc[d]) + gx, float(acc[d + 1]) + gy, float(acc[d + 2])
                    td = float(v[d + 2])
                    td2 = td * td
                    ax = ux - tdd * py - td2 * px
                    ay = uy + tdd * px - td2 * py
                    Fs[d:d + 3] += (m * ax, m * ay, J * tdd + m * (px * ay - py * ax))
                    b2, b5 = m * (td2 * py - tdd * px), m * (-(tdd * py) - td2 * px)
                    b8 = -(m * (px * ux + py * uy))
                    bs[o + 2], bs[o + 5], bs[o + 8] = b2, b5, b8
                    ms[o:o + 9] = (m, 0.0, (-m * py + b2) - b2, 0.0, m, (m * px + b5) - b5, -m * py, m * px,
                                   (J + m * (px * px + py * py) + b8) - b8)
                    vs[o + 2] = m * (-2.0 * td * px - tdd * px + td2 * py) - b2
                    vs[o + 5] = m * (-2.0 * td * py - tdd * py - td2 * px) - b5
                    o += 9
            return F, base, mass, vel
        d = self.body_d
        m, J = self.body_m, self.body_J
        th = Q[:, d + 2]
        c, s_ = np.cos(th), np.sin(th)
        rx, ry = self.body_r[:, 0], self.body_r[:, 1]
        px, py = c * rx - s_ * ry, s_ * rx + c * ry
        ux, uy, tdd = ACC[:, d], ACC[:, d + 1], ACC[:, d + 2]
        td = V[:, d + 2]
        td2 = td * td
        if g is not None:
            ux = ux + g[:, :1]
            uy = uy + g[:, 1:]
        ax = ux - tdd * py - td2 * px
        ay = uy + tdd * px - td2 * py
        F[:, d] += m * ax
        F[:, d + 1] += m * ay
        F[:, d + 2] += J * tdd + m * (px * ay - py * ax)
        nb = d.size
        B = base[:, nn:].reshape(k, nb, 9)
        b2, b5 = m * (td2 * py - tdd * px), m * (-(tdd * py) - td2 * px)
        b8 = -(m * (px * ux + py * uy))
        B[:, :, 2], B[:, :, 5], B[:, :, 8] = b2, b5, b8
        Mb = mass[:, nn:].reshape(k, nb, 9)
        Mb[:, :, 0] = Mb[:, :, 4] = m
        Mb[:, :, 1] = Mb[:, :, 3] = 0.0
        Mb[:, :, 2] = (-m * py + b2) - b2
        Mb[:, :, 5] = (m * px + b5) - b5
        Mb[:, :, 6] = -m * py
        Mb[:, :, 7] = m * px
        Mb[:, :, 8] = (J + m * (px * px + py * py) + b8) - b8
        Vb = vel[:, nn:].reshape(k, nb, 9)
        Vb[:, :, 2] = m * (-2.0 * td * px - tdd * px + td2 * py) - b2
        Vb[:, :, 5] = m * (-2.0 * td * py - tdd * py - td2 * px) - b5
        return F, base, mass, vel

    def kinetic(self, q, v):
        """Kinetic energy (model units: Fref Lref)."""
        nd = self.node_dofs
        T = 0.5 * float(np.dot(self.node_vals, v[nd] ** 2)) if nd.size else 0.0
        if 0 < self.body_d.size <= self.SCALAR_BODIES:   # (a few bodies: scalar arithmetic)
            Tb = 0.0
            for d, m, J, (rx, ry) in self._body_list:
                th = float(q[d + 2])
                c, s = math.cos(th), math.sin(th)
                td = float(v[d + 2])
                vx, vy = float(v[d]) - td * (s * rx + c * ry), float(v[d + 1]) + td * (c * rx - s * ry)
                Tb += m * (vx * vx + vy * vy) + J * td * td
            return T + 0.5 * Tb
        if self.body_d.size:
            d = self.body_d
            px, py, _ = self._rho(q)
            td = v[d + 2]
            vx, vy = v[d] - td * py, v[d + 1] + td * px
            T += 0.5 * float(np.sum(self.body_m * (vx * vx + vy * vy) + self.body_J * td * td))
        return T

    def ground_power(self, Q, V, G):
        """The power of the base acceleration's inertia load at k states: ``ground_load(Q[i], G[i]) .
        V[i]`` for the positions and velocities Q, V (k, n_q) and ground accelerations G (k, 2), as a
        (k,) array (model units)."""
        nd = self.node_dofs
        k = nd.size // 2
        P = -(V[:, nd[:k]] @ self.node_vals[:k]) * G[:, 0] - (V[:, nd[k:]] @ self.node_vals[k:]) * G[:, 1]
        if self.body_d.size:
            d, m = self.body_d, self.body_m
            px, py, _ = self._rho(Q)   # (k, bodies)
            gx, gy = G[:, :1], G[:, 1:]
            P -= (m * (V[:, d] * gx + V[:, d + 1] * gy + (px * gy - py * gx) * V[:, d + 2])).sum(axis=1)
        return P

    def ground_load(self, q, ground):
        """Generalised inertia load (n_q,) of the base acceleration ``ground`` (2,) (model units):
        -m a_g on every mass, with its moment about a body's frame origin."""
        f = np.zeros(self.n_q)
        nd = self.node_dofs
        k = nd.size // 2
        f[nd[:k]] -= self.node_vals[:k] * ground[0]
        f[nd[k:]] -= self.node_vals[k:] * ground[1]
        if self.body_d.size:
            d = self.body_d
            px, py, _ = self._rho(q)
            f[d] -= self.body_m * ground[0]
            f[d + 1] -= self.body_m * ground[1]
            f[d + 2] -= self.body_m * (-py * ground[0] + px * ground[1])
        return f
