"""Named results of a static state, in SI units: rods, bodies, joints and support reactions.

Conventions (counter-clockwise rotations and moments; forces in global x, y):

- rod arrays along the arc length s from the rod's ``start``: displacements (u, v), rotation theta,
  axial force N (tension > 0), shear force V and bending moment M = EI dtheta/ds (M > 0 where the rod
  turns counter-clockwise as s grows).  At a cut at s the part beyond the cut exerts on the part
  before it the force N t - V n and the moment +M (t the rod's tangent, n = t turned by +90 degrees);
  so dM/ds = V and, under a distributed load q per unit length, dN/ds = -q . t, dV/ds = -q . n;
- nodal values from equilibrium of the rod piece before the node (exact to the Newton residual,
  where the elements' own deformations, times a huge EA or EI, would carry round-off): the element
  end moments are those that balance the joint forces, springs and nodal loads on the nodes before
  them (in the deformed configuration), corrected by the fixed-end moments of a distributed load
  (exact for a linear beam); N and V are the force resultant G(s) of the same sums (statically
  G(s) = -(F_start + q s), F_start the joint forces and point loads on the rod's start node, q the
  distributed load; nodal inertia forces of a dynamic state included) projected on the nodal
  tangent.  ``M_max`` includes the interior extremum of the parabola a distributed load adds
  in an element;
- bodies: centroid position (x, y) now and rotation;
- joints: the force (Fx, Fy) and moment M that part b exerts on part a at the joint point (springs
  included), the slide (sliders, rollers: displacement of a's point along the axis from the
  reference) and the rotation of a relative to b (pins); a unilateral contact's gap (the distance
  of a's point from its guide on the +n side: 0 in contact, > 0 lifted off);
- reactions: the joints with the ground, as forces of the ground on the structure.

A model of first-order theory (``model.linear``, femslide.model.linear) has its results recovered
the same way on the reference geometry: equilibrium of the undeformed rod pieces, joint forces on
the reference gradients, springs linear in the displacements, slides and body positions to first
order.
"""
from __future__ import annotations

import math

import numpy as np

from femslide.joints.base import at_joint_point
from femslide.model.linalg import largest_abs, model_kernel


_GOLD = 0.5 * (math.sqrt(5.0) - 1.0)
SAMPLES = 16     # samples per element before the golden-section search of a maximum (module docstring)
GOLDEN_STEPS = 48
PEAK_CHUNK = 512  # elements sampled at once by _Inside.peak (bounds its temporaries on fine meshes)


class _Inside:
    """The continuous solution inside every element of a state (model units), from the equilibrium
    cuts at its nodes:

    - the cut force G(xi) = G_i - int_0^xi q (xi in [0, 1] along the element, q linear between its
      values at the element's ends), G_i the force just past node i (the middle force of
      :func:`end_moments` plus the element's consistent start share of its distributed load);
    - the element's axis: the chord plus the cubic Hermite deflection w(xi) = l (t1 xi (1 - xi)^2 -
      t2 xi^2 (1 - xi)) of its end rotations t1, t2 relative to the chord (exact theory; zero in
      first-order theory, whose equilibrium is written on the undeformed rod), its tangent turned by
      w'(xi) / l from the chord;
    - the moment M(xi) = (1 - xi) Ms + xi Me - m_q(xi) + N w(xi): the end moments from equilibrium,
      the simply supported moment of the distributed load m_q (linear load: l^2 / 6 (p1 xi (1 - xi)
      (2 - xi) + p2 xi (1 - xi) (1 + xi)), p the load's normal component) and the moment of the axial
      force on the deflection (N = G . t: a compressed element's moment grows where it bows out);
    - N(xi) = G(xi) . t(xi), V(xi) = -G(xi) . n(xi).

    Peaks of |M|, |N|, |V| inside an element (a column's moment a few millimetres from its root
    inside a long first element) are found in closed form for M (a cubic in xi: the roots of M') and
    by sampling and a golden-section search for N and V, so ``M_max`` and its position ``s_M_max``
    are those of the continuous solution, not of the nodes."""

    def __init__(self, model, y, alpha, cuts, lam, moment_only=False):
        """``moment_only``: only what :meth:`moment` and :meth:`moment_peak` need (not the cut
        force G, nor N and V), which without distributed loads is the end moments and the chords."""
        es = model.elements
        q = y[:model.n_q]
        U = model.nodal(q)
        lin = model.linear
        Xe = model.X0 if lin else model.X0 + U[:, :2]
        qb, Gmid = cuts
        D = Xe[es.conn[:, 1]] - Xe[es.conn[:, 0]]
        Ln = np.hypot(D[:, 0], D[:, 1])
        self.t = t = D / Ln[:, None]
        L0 = self.L0 = es.L0
        if moment_only and not model.rods_loaded:
            self.p1 = self.p2 = np.zeros(es.size)
            self.Ms, self.Me = -qb[:, 0], qb[:, 1]
        else:
            self.n = nrm = np.column_stack([-t[:, 1], t[:, 0]])
            q1 = model.elem_q1 if lam == 1.0 else lam * model.elem_q1
            q2 = model.elem_q2 if lam == 1.0 else lam * model.elem_q2
            self.q1, self.dq = q1, q2 - q1
            p1 = np.einsum("ij,ij->i", q1, nrm)
            p2 = np.einsum("ij,ij->i", q2, nrm)
            a1 = np.einsum("ij,ij->i", q1, t)
            dp, da = p2 - p1, np.einsum("ij,ij->i", q2, t) - a1
            self.p1, self.p2 = p1, p2
            # the consistent end moments and start force of the element's load (femslide.elements.loads)
            LL = L0 * L0
            self.Ms = -qb[:, 0] + (LL * p1 / 12.0 + LL * dp / 30.0)
            self.Me = qb[:, 1] + (LL * p1 / 12.0 + LL * dp / 20.0)
            self.G0 = Gmid + 0.5 * L0[:, None] * q1 + L0[:, None] * ((da / 6.0)[:, None] * t +
                                                                    (0.15 * dp)[:, None] * nrm)
        if lin:
            self.t1 = self.t2 = np.zeros(es.size)
        else:
            # the chord's rotation now, continued from the elements' committed one (``alpha``: past pi)
            ref = es.beta0 + (0.0 if alpha is None else alpha)
            chord = ref + np.arctan2(np.cos(ref) * D[:, 1] - np.sin(ref) * D[:, 0],
                                     np.cos(ref) * D[:, 0] + np.sin(ref) * D[:, 1]) - es.beta0
            self.t1 = U[es.i, 2] - chord
            self.t2 = U[es.j, 2] - chord
        self.Ln = Ln
        self.Nm = np.einsum("ij,ij->i", Gmid, t)

    def G(self, e, xi):
        L0 = self.L0[e]
        return self.G0[e] - L0[:, None] * (self.q1[e] * xi[:, None] + self.dq[e] * (0.5 * xi * xi)[:, None])

    def moment(self, e, xi):
        Ms, Me, L0 = self.Ms[e], self.Me[e], self.L0[e]
        w = self.Ln[e] * (self.t1[e] * xi * (1 - xi) ** 2 - self.t2[e] * xi * xi * (1 - xi))
        mq = L0 * L0 / 6.0 * (self.p1[e] * xi * (1 - xi) * (2 - xi) + self.p2[e] * xi * (1 - xi) * (1 + xi))
        return (1 - xi) * Ms + xi * Me - mq + self.Nm[e] * w

    def moment_peak(self, e=None):
        """(value, xi) of the largest |M| inside each element e (None: every element), in closed
        form: M(xi) of :meth:`moment` is a cubic in xi (linear end moments, the cubic m_q, N times
        the cubic deflection), so its extrema on [0, 1] are the ends and the real roots of the
        quadratic M'(xi) (the same values as :meth:`peak`'s search, to round-off, at a fraction of
        its cost)."""
        if e is None:
            Ms, Me, L0, p1, p2 = self.Ms, self.Me, self.L0, self.p1, self.p2
            W, t1, t2 = self.Nm * self.Ln, self.t1, self.t2
        else:
            Ms, Me, L0, p1, p2 = self.Ms[e], self.Me[e], self.L0[e], self.p1[e], self.p2[e]
            W, t1, t2 = self.Nm[e] * self.Ln[e], self.t1[e], self.t2[e]
        c = L0 * L0 / 6.0
        # M(xi) = Ms + a1 xi + a2 xi^2 + a3 xi^3
        a1 = (Me - Ms) - c * (2.0 * p1 + p2) + W * t1
        a2 = 3.0 * c * p1 - W * (2.0 * t1 + t2)
        a3 = W * (t1 + t2) - c * (p1 - p2)
        A, B = 3.0 * a3, 2.0 * a2                  # M'(xi) = A xi^2 + B xi + a1
        disc = B * B - 4.0 * A * a1
        q = -0.5 * (B + np.copysign(np.sqrt(np.maximum(disc, 0.0)), B))
        # the stable pair of roots q / A and a1 / q (a zero A or q: no root there)
        r1 = np.divide(q, A, out=np.zeros_like(q), where=A != 0.0)
        r2 = np.divide(a1, q, out=np.zeros_like(q), where=q != 0.0)
        out = disc < 0.0
        r1[out | (r1 <= 0.0) | (r1 >= 1.0)] = 0.0
        r2[out | (r2 <= 0.0) | (r2 >= 1.0)] = 0.0
        ne = Ms.size
        X = np.empty((4, ne))
        X[0], X[1], X[2], X[3] = 0.0, 1.0, r1, r2
        V = np.empty((4, ne))
        V[0], V[1] = Ms, Me                        # the ends exactly
        V[2:] = Ms + X[2:] * (a1 + X[2:] * (a2 + X[2:] * a3))
        k = np.argmax(np.abs(V), axis=0)
        idx = np.arange(ne)
        return V[k, idx], X[k, idx]

    def _frame(self, e, xi):
        phi = self.t1[e] * (1 - xi) * (1 - 3 * xi) - self.t2[e] * xi * (2 - 3 * xi)
        c, s = np.cos(phi), np.sin(phi)
        t, n = self.t[e], self.n[e]
        tt = t * c[:, None] + n * s[:, None]
        return tt, np.column_stack([-tt[:, 1], tt[:, 0]])

    def axial(self, e, xi):
        tt, _ = self._frame(e, xi)
        return np.einsum("ij,ij->i", self.G(e, xi), tt)

    def shear(self, e, xi):
        _, nn = self._frame(e, xi)
        return -np.einsum("ij,ij->i", self.G(e, xi), nn)

    def peak(self, f, e):
        """(value, xi) of the largest |f| inside each element e (signed value at its position)."""
        ne = e.size
        xs = np.linspace(0.0, 1.0, SAMPLES + 1)
        # the samples of at most PEAK_CHUNK elements at a time: the same values, with the temporaries
        # of a fine mesh bounded (17 samples of 4096 elements were ~10 MB of arrays at once)
        k = np.empty(ne, np.intp)
        best = np.empty(ne)
        for lo in range(0, ne, PEAK_CHUNK):
            ec = e[lo:lo + PEAK_CHUNK]
            v = np.abs(f(np.repeat(ec, xs.size), np.tile(xs, ec.size))).reshape(ec.size, xs.size)
            kc = k[lo:lo + ec.size] = np.argmax(v, axis=1)
            best[lo:lo + ec.size] = v[np.arange(ec.size), kc]
        h = 1.0 / SAMPLES
        a = np.clip(xs[k] - h, 0.0, 1.0)
        b = np.clip(xs[k] + h, 0.0, 1.0)
        c = b - _GOLD * (b - a)
        d = a + _GOLD * (b - a)
        fc, fd = np.abs(f(e, c)), np.abs(f(e, d))
        for _ in range(GOLDEN_STEPS):
            left = fc >= fd                     # the maximum lies in [a, d]
            b = np.where(left, d, b)
            a = np.where(left, a, c)
            c2 = b - _GOLD * (b - a)
            d2 = a + _GOLD * (b - a)
            c, d = np.where(left, c2, d), np.where(left, c, d2)
            fnew = np.abs(f(e, np.where(left, c, d)))
            fc, fd = np.where(left, fnew, fd), np.where(left, fc, fnew)
        xi = 0.5 * (a + b)
        # never below the best sample (the nodes' values included)
        fx = f(e, xi)
        use = np.abs(fx) >= best
        xi = np.where(use, xi, xs[k])
        return np.where(use, fx, f(e, xs[k])), xi


#: the keys of a joint's results, in order (those its kind has)
JOINT_KEYS = ("Fx", "Fy", "M", "slide", "rotation", "gap")

def rod_arrays(model, y, alpha, cuts=None, lam=1.0):
    """Per rod (by name): node arrays s, x, y, u, v, theta, N, V, M (SI) and the largest |M|, |N|, |V|
    along the rod including the inside of elements (``M_max``, ``N_max``, ``V_max``, at arc lengths
    ``s_M_max``, ``s_N_max``, ``s_V_max`` [m]; :class:`_Inside`).  ``cuts``: ``end_moments(model, y,
    resultant=True)`` of this state if already computed; ``lam``: the load factor of the state (an
    equilibrium on a load path; 1 = full load)."""
    L, F = model.Lref, model.Fref
    q = y[:model.n_q]
    U = model.nodal(q)
    out = {}
    if model.elements is None:
        return out
    es = model.elements
    X = model.X0 + U[:, :2]
    Xe = model.X0 if model.linear else X   # the geometry equilibrium is written on
    cuts = end_moments(model, y, Xe, resultant=True, lam=lam) if cuts is None else cuts
    ins = _Inside(model, y, alpha, cuts, lam)
    L0 = es.L0
    fs = model.structure
    for k, rod in enumerate(fs.rods):
        nodes = model.rod_nodes[k]
        el = np.nonzero(model.elem_rod == k)[0]
        ang = rod.angle + (0.0 if model.linear else U[nodes, 2])
        tn = np.column_stack([np.cos(ang), np.sin(ang)])
        nn = np.column_stack([-tn[:, 1], tn[:, 0]])
        M = np.zeros(nodes.size)
        M[:-1] += ins.Ms[el]
        M[1:] += ins.Me[el]
        M[1:-1] *= 0.5      # an interior node: the mean of its two elements (equal at equilibrium)
        s = np.concatenate([[0.0], np.cumsum(L0[el])])
        G = np.vstack([ins.G0[el], ins.G(el[-1:], np.ones(1))])
        N = np.einsum("ij,ij->i", G, tn)
        V = -np.einsum("ij,ij->i", G, nn)
        row = {"s": s * L, "x": X[nodes, 0] * L, "y": X[nodes, 1] * L,
               "u": U[nodes, 0] * L, "v": U[nodes, 1] * L, "theta": U[nodes, 2].copy(),
               "N": N * F, "V": V * F, "M": M * F * L}
        for key, fun, unit, nodal in (("M", None, F * L, M), ("N", ins.axial, F, N), ("V", ins.shear, F, V)):
            val, xi = ins.moment_peak(el) if fun is None else ins.peak(fun, el)
            cand = np.abs(np.concatenate([nodal, val]))
            pos = np.concatenate([s, s[:-1] + xi * L0[el]])
            top = float(cand.max())
            # the first position where the largest value is reached (to round-off: a constant V or N)
            row[f"{key}_max"] = top * unit
            row[f"s_{key}_max"] = float(pos[cand >= top * (1.0 - 1e-9)].min()) * L
        out[rod.name] = row
    return out


def moment_samples(model, y, alpha, k=8, cuts=None, lam=1.0):
    """Per rod: the bending moment [N m] at k points inside every element and at the nodes, on the
    continuous solution (:class:`_Inside`, as :func:`rod_arrays`): {rod: (s [m], M [N m])}, for
    diagrams that show interior extrema."""
    if model.elements is None:
        return {}
    L, F = model.Lref, model.Fref
    es = model.elements
    X = model.X0 if model.linear else model.X0 + model.nodal(y[:model.n_q])[:, :2]
    cuts = end_moments(model, y, X, resultant=True, lam=lam) if cuts is None else cuts
    ins = _Inside(model, y, alpha, cuts, lam)
    L0 = es.L0
    xi = np.linspace(0.0, 1.0, k + 2)[:-1]
    out = {}
    for r, rod in enumerate(model.structure.rods):
        el = np.nonzero(model.elem_rod == r)[0]
        s0 = np.concatenate([[0.0], np.cumsum(L0[el])])
        M = ins.moment(np.repeat(el, xi.size), np.tile(xi, el.size)).reshape(el.size, xi.size)
        s = s0[:-1, None] + xi * L0[el, None]
        out[rod.name] = (np.append(s.ravel(), s0[-1]) * L, np.append(M.ravel(), ins.Me[el[-1]]) * F * L)
    return out


def end_moments(model, y, X=None, resultant=False, lam=1.0):
    """End moments (n_elements, 2) [model units] of every element, in the sign of the elements' basic
    forces (M1 at the start node, M2 at the end; a beam's M(s) is -M1 at its start, +M2 at its end),
    from the equilibrium of the rod piece up to the element: at node i of a rod the element starting
    there balances the generalised forces g_j (loads, springs, joints: :meth:`Model.applied`) on the
    nodes j <= i,

        M1_i = -sum_{j<=i} [g_j^M + (x_j - x_i) x g_j^F],   M2_i = -M1_i - (x_i - x_{i+1}) x F1_i,

    with F1_i = -sum_{j<=i} g_j^F (x the current node positions, a x b = a_x b_y - a_y b_x).  Equal to
    the elements' own moments at equilibrium, but with the round-off of the forces instead of that of
    EI times a curvature from nearly equal rotations.

    With ``resultant``: also the force (n_elements, 2) that the part beyond each element's middle
    exerts on the part before it (G = N t - V n of the module docstring), sum_{j<=i} g_j^F: at the
    middle because node i carries half of element i's share of a distributed load."""
    if model.elements is None:
        return (np.zeros((0, 2)), np.zeros((0, 2))) if resultant else np.zeros((0, 2))
    if X is None:
        X = model.X0 if model.linear else model.X0 + model.nodal(y[:model.n_q])[:, :2]
    g = model.applied(y, lam)[:3 * model.n_nodes].reshape(-1, 3)
    first = model.node_first
    es = model.elements
    kern = model_kernel(model, "cuts")
    if kern is not None:   # the compiled kernel: the same arithmetic in one call
        M, G = np.empty((es.size, 2)), np.empty((es.size, 2))
        # (the kernel takes 8-byte indices: np.repeat of Python ints gives int32 on Windows with numpy 1)
        kern(np.ascontiguousarray(X, float), np.ascontiguousarray(g), np.asarray(first, np.int64),
             np.asarray(es.i, np.int64), np.asarray(es.j, np.int64), M, G)
        return (M, G) if resultant else M
    Xr = X - X[first]
    rows = g.copy()      # forces and moments about each rod's start node
    rows[:, 2] += Xr[:, 0] * g[:, 1] - Xr[:, 1] * g[:, 0]
    C = rows.cumsum(axis=0)
    C -= C[first] - rows[first]            # sums over each rod's own nodes only
    Ci, Xi = C[es.i], Xr[es.i]
    d = Xi - Xr[es.j]
    M = np.empty((es.size, 2))
    M[:, 0] = Xi[:, 0] * Ci[:, 1] - Xi[:, 1] * Ci[:, 0] - Ci[:, 2]
    M[:, 1] = d[:, 0] * Ci[:, 1] - d[:, 1] * Ci[:, 0] - M[:, 0]
    return (M, Ci[:, :2].copy()) if resultant else M


def element_cuts(model, y, alpha):
    """The (end moments, middle force) pair of :func:`end_moments` (``resultant=True``) taken from the
    elements' own basic forces instead of the equilibrium of the rod pieces: for a state that is not
    a static equilibrium of :meth:`Model.applied` - a time step of the dynamics (inertia, damping and
    friction forces act besides it), a displaced mode shape - where the equilibrium recovery would
    miss those forces.  M from the basic end moments, G = N t - V n at the element middle with N the
    basic axial force and V = (M1 + M2) / l the element shear (l the current chord)."""
    if model.elements is None:
        return np.zeros((0, 2)), np.zeros((0, 2))
    qb, _ = model.element_forces(y[:model.n_q], alpha)
    es = model.elements
    X = model.X0 if model.linear else model.X0 + model.nodal(y[:model.n_q])[:, :2]
    D = X[es.conn[:, 1]] - X[es.conn[:, 0]]
    ln = np.hypot(D[:, 0], D[:, 1])
    t = D / ln[:, None]
    V = (qb[:, 1] + qb[:, 2]) / ln
    G = qb[:, :1] * t - V[:, None] * np.column_stack([-t[:, 1], t[:, 0]])
    return qb[:, 1:].copy(), G


def largest_moment(model, y, alpha, cuts=None) -> float:
    """Largest |bending moment| [N m] over all rods (cheap when no rod carries a distributed load).
    ``cuts``: ``end_moments(model, y, resultant=True)`` of this state if already computed."""
    if model.elements is None:
        return 0.0
    if cuts is None:
        cuts = end_moments(model, y, resultant=True)
    if model.rods_loaded:   # interior peaks: the continuous solution's
        ins = _Inside(model, y, alpha, cuts, 1.0, moment_only=True)
        val, _ = ins.moment_peak()
        return max(float(np.abs(val).max()), float(np.abs(cuts[0]).max())) * model.Fref * model.Lref
    top = largest_abs(cuts[0])
    if not model.linear:
        top = max(top, _largest_inside(model, y, alpha, cuts))
    return top * model.Fref * model.Lref


def _largest_inside(model, y, alpha, cuts) -> float:
    """max |M| [model units] at the interior extrema of the elements' moments without distributed
    loads: M(xi) = (1 - xi) Ms + xi Me + N w(xi) (:class:`_Inside`), a cubic whose derivative
    a1 + 2 a2 xi + 3 a3 xi^2 has a1 = Me - Ms + W t1, a2 = -W (2 t1 + t2), a3 = W (t1 + t2) with
    W = N l; the ends are the end moments themselves.  (The closed form of
    :meth:`_Inside.moment_peak` with fewer array operations: it runs on every refinement level.)"""
    es = model.elements
    U = model.nodal(y[:model.n_q])
    X = model.X0 + U[:, :2]
    qb, Gmid = cuts
    kern = model_kernel(model, "inside")
    if kern is not None:   # the compiled kernel: the same arithmetic in one pass over the elements
        return kern(X, np.ascontiguousarray(U), es.i, es.j, es.beta0, alpha, np.ascontiguousarray(qb),
                    np.ascontiguousarray(Gmid))
    i, j = es.i, es.j
    Dx = X[j, 0] - X[i, 0]
    Dy = X[j, 1] - X[i, 1]
    ref = es.beta0 if alpha is None else es.beta0 + alpha
    cr, sr = np.cos(ref), np.sin(ref)
    chord = ref + np.arctan2(cr * Dy - sr * Dx, cr * Dx + sr * Dy) - es.beta0
    t1 = U[i, 2] - chord
    t2 = U[j, 2] - chord
    W = Gmid[:, 0] * Dx + Gmid[:, 1] * Dy        # N l (N = G . t)
    Ms = -qb[:, 0]
    a1 = (qb[:, 1] - Ms) + W * t1
    a2 = -W * (2.0 * t1 + t2)
    a3 = W * (t1 + t2)
    A, B = 3.0 * a3, 2.0 * a2                      # M'(xi) = A xi^2 + B xi + a1
    disc = B * B - 4.0 * A * a1
    q = -0.5 * (B + np.copysign(np.sqrt(np.maximum(disc, 0.0)), B))
    r = np.zeros((2, Ms.size))                     # the stable pair of roots q / A, a1 / q
    np.divide(q, A, out=r[0], where=A != 0.0)
    np.divide(a1, q, out=r[1], where=q != 0.0)
    r[(r <= 0.0) | (r >= 1.0) | (disc < 0.0)] = 0.0   # (xi = 0: the start, Ms)
    return float(np.abs(Ms + r * (a1 + r * (a2 + r * a3))).max())


def joint_forces(model, y, name, lam=1.0):
    """(Fx, Fy, M) [model units] that b exerts on a at the joint point, springs (and the springs of
    an elastic support) included; ``lam`` the load factor of the state (a preload is ramped)."""
    link = model.joint[name]
    if link.ia is None:   # a is the ground: not allowed by the declaration layer
        raise ValueError(f"joint {name}: part a has no dofs")
    zq = y[link.dofs]
    z = [0.0] * zq.size if model.linear else zq.tolist()   # first order: the reference geometry
    gen = [0.0] * link.k   # the joint's generalised forces mu . G on its dofs (then its equations g)
    if link.size:
        gen = []
        link.assemble(z, model.multipliers(y, link).tolist(), gen, None)
    f = [-gen[i] for i in range(link.ia, link.ia + 3)]
    for spring in (model.spring.get(name), model.supports.get(name)):
        if spring is None:
            continue
        fs, jv, fv = [], ([] if model.linear else None), []
        spring.assemble(z, 0.0 if model.linear else lam, fs, jv, fv)
        if model.linear:   # the spring's force linear in the displacements: H0 z + f0 (preload)
            fs = (np.array(jv).reshape(link.k, link.k) @ zq + lam * np.array(fv)).tolist()
        f = [f[j] - fs[i] for j, i in enumerate(range(link.ia, link.ia + 3))]
    return at_joint_point(link, z, f)


def extract(model, y, alpha, arrays=None, lam=1.0) -> dict:
    """The named results of SPEC section 8 (SI units) of a converged state (at load factor ``lam``)."""
    L, F = model.Lref, model.Fref
    q = y[:model.n_q]
    arrays = rod_arrays(model, y, alpha, lam=lam) if arrays is None else arrays
    rods = {}
    for rod in model.structure.rods:
        a = arrays[rod.name]
        rods[rod.name] = {"M_max": a["M_max"], "N_max": a["N_max"], "V_max": a["V_max"],
                          "s_M_max": a["s_M_max"], "s_N_max": a["s_N_max"], "s_V_max": a["s_V_max"],
                          "start": {"u": float(a["u"][0]), "v": float(a["v"][0]), "theta": float(a["theta"][0])},
                          "end": {"u": float(a["u"][-1]), "v": float(a["v"][-1]), "theta": float(a["theta"][-1])}}
    bodies = {}
    for b in model.structure.bodies:
        d = model.body_dof(b.name)
        if model.linear:   # to first order: the origin's displacement plus theta x (centroid - origin)
            X = model.body_X0[model.body_index[b.name]] * L
            th = float(q[d + 2])
            x = b.centroid[0] + q[d] * L - th * (b.centroid[1] - X[1])
            y_ = b.centroid[1] + q[d + 1] * L + th * (b.centroid[0] - X[0])
        else:
            x, y_ = model.body_point(b.name, q, b.centroid)
        bodies[b.name] = {"x": float(x), "y": float(y_), "rotation": float(q[d + 2])}
    joints, reactions = {}, {}
    for j in model.structure.joints:
        fx, fy, m = joint_forces(model, y, j.name, lam)
        out = {"Fx": fx * F, "Fy": fy * F, "M": m * F * L}
        link = model.joint[j.name]
        free = link.joint_kind.free   # the joint's free coordinate, if its kind reports one
        if free == "slide" and model.linear:   # to first order: the gradient at the reference
            s0, ds, _ = link.slide(np.zeros(link.k))
            out["slide"] = (float(s0) + float(ds @ q[link.dofs]) - model.slide0[j.name]) * L
        elif free == "slide":
            out["slide"] = (float(link.slide(q[link.dofs])[0]) - model.slide0[j.name]) * L
        elif free == "rotation":
            out["rotation"] = float(link.rotation(q[link.dofs])[0])
        if j.unilateral:   # a contact's gap: a's point's distance from the guide on its +n side
            out["gap"] = link.gap(q[link.dofs]) * L
        joints[j.name] = out
        if j.b == "ground":
            reactions[j.name] = {"Fx": out["Fx"], "Fy": out["Fy"], "M": out["M"]}
    M_all = max((r["M_max"] for r in rods.values()), default=0.0)
    return {"M_max": M_all, "bodies": bodies, "rods": rods, "joints": joints, "reactions": reactions}


# -- flat views for the adaptive refinement ------------------------------------------------------------
KIND_OF = {"M_max": "moment", "M": "moment", "N_max": "force", "V_max": "force", "Fx": "force", "Fy": "force",
           "u": "length", "v": "length", "slide": "length", "gap": "length", "x": "length", "y": "length",
           "theta": "angle", "rotation": "angle"}


def flatten(res: dict, structure):
    """(values, kinds) of every named number of a section-8 result in a fixed order; body positions
    enter as displacements (x - x0), so that relative changes measure the motion."""
    vals, kinds = [res["M_max"]], ["moment"]
    for r in structure.rods:
        d = res["rods"][r.name]
        for key in ("M_max", "N_max", "V_max"):
            vals.append(d[key])
            kinds.append(KIND_OF[key])
        for end in ("start", "end"):
            for key in ("u", "v", "theta"):
                vals.append(d[end][key])
                kinds.append(KIND_OF[key])
    for b in structure.bodies:
        d = res["bodies"][b.name]
        vals += [d["x"] - b.centroid[0], d["y"] - b.centroid[1], d["rotation"]]
        kinds += ["length", "length", "angle"]
    for j in structure.joints:
        d = res["joints"][j.name]
        for key in JOINT_KEYS:
            if key in d:
                vals.append(d[key])
                kinds.append(KIND_OF[key])
    return np.array(vals, float), kinds


def flatten_names(res: dict, structure) -> list[str]:
    """The dotted names of the values of :func:`flatten`, in its order (``rods.c0.M_max``,
    ``joints.T2.Fy``, ...)."""
    names = ["M_max"]
    for r in structure.rods:
        names += [f"rods.{r.name}.{k}" for k in ("M_max", "N_max", "V_max")]
        names += [f"rods.{r.name}.{end}.{k}" for end in ("start", "end") for k in ("u", "v", "theta")]
    for b in structure.bodies:
        names += [f"bodies.{b.name}.{k}" for k in ("x", "y", "rotation")]
    for j in structure.joints:
        names += [f"joints.{j.name}.{k}" for k in JOINT_KEYS if k in res["joints"][j.name]]
    return names


def unflatten(template: dict, vals, structure) -> dict:
    """The inverse of :func:`flatten` on a result of the same structure."""
    it = iter(np.asarray(vals, float).tolist())
    out = {"M_max": next(it), "bodies": {}, "rods": {}, "joints": {}, "reactions": {}}
    for r in structure.rods:
        d = {k: next(it) for k in ("M_max", "N_max", "V_max")}
        tr = template["rods"][r.name]
        d.update({k: tr[k] for k in ("s_M_max", "s_N_max", "s_V_max") if k in tr})   # positions: the finest mesh's
        for end in ("start", "end"):
            d[end] = {k: next(it) for k in ("u", "v", "theta")}
        out["rods"][r.name] = d
    for b in structure.bodies:
        dx, dy, rot = next(it), next(it), next(it)
        out["bodies"][b.name] = {"x": b.centroid[0] + dx, "y": b.centroid[1] + dy, "rotation": rot}
    for j in structure.joints:
        tj = template["joints"][j.name]
        d = {k: next(it) for k in JOINT_KEYS if k in tj}
        out["joints"][j.name] = d
        if j.b == "ground":
            out["reactions"][j.name] = {k: d[k] for k in ("Fx", "Fy", "M")}
    return out
