"""Newton start of the paper's structures: the spring-hinge mechanism, deformed, at a body rotation.

The equivalent spring-hinge model (femslide.scenes.hinge) gives the body rotation phi of the equilibrium to
within a few per mille for EI >= 1e2 N m^2 (and within tens of per cent at EI = 1e1).  From phi alone
this module builds a state of the FE model that satisfies its joints up to O(h^2) and has no axial
strain, so that Newton, started there, needs only a few iterations.  It knows the paper's structure
by its declared names (femslide.scenes.paper): the body ``deck`` (pinned at A1 when the left rod is rigid:
then the rod is part of it); the flexible left rod ``left`` welded to it at ``A``; the right support ``right``
(a rigid body pinned at B1, or a flexible rod pinned at B1) held by the sliding clamp ``clamp``; the
optional telescopic piece ``piece`` welded to the right rod's top.

- deck: turned by Theta; its position follows from the rigid left rod's ground pin, or from the
  welded flexible left rod, whose chord keeps its length and turns so that the clamp's guide point
  stays on the rigid right rod's guide line, or, with a flexible rod in the clamp instead, so that
  the two rods share the kinematic misfit equally (opposite top angles against their chords);
- flexible rods (pinned at the ground node, top welded or in the clamp that locks the top rotation
  to the deck's): the chord runs from the ground node to the top, which is the weld point or the
  point of the guide line at the rod's chord length from the ground node; the shape is the linear
  beam under a top moment with zero moment at the pin: the tangent turns from the chord by
  t(xi) = t_top (3 xi^2 - 1) / 2 (xi = s/L); elements are laid end to end with their lengths;
- rigid bodies turn with the deck about their ground pins; the piece sits on the rod's top.
Multipliers start at zero (the equations are linear in them).  Angles are counter-clockwise.
"""
from __future__ import annotations

import math

import numpy as np


def _chord(L, t_top):
    """Chord of a rod of length L bent by the tangent angles t_top (3 xi^2 - 1) / 2 (to O(t^4))."""
    return L * (1.0 - t_top * t_top / 10.0)


# points and vectors are (x, y) tuples of floats: a handful of them, where numpy's per-call cost would
# dominate (the predictor runs once per solve)

def _line_top(point, e, base, chord):
    """The point of the line through ``point`` along ``e`` at distance ``chord`` from ``base``, on the
    +e side; None if the line is out of reach."""
    cx, cy = point[0] - base[0], point[1] - base[1]
    ce = cx * e[0] + cy * e[1]
    disc = ce * ce - (cx * cx + cy * cy) + chord * chord
    if disc < 0.0:
        return None
    f = -ce + math.sqrt(disc)
    return (base[0] + cx + f * e[0], base[1] + cy + f * e[1])


def _bent_top(weld_point, line_point, e, base, L, beta0, th):
    """(top, beta, t_top) of a rod of length L pinned at ``base`` (initial chord angle beta0) whose top
    is welded at ``weld_point`` or, if that is None, held in the clamp whose guide line passes through
    ``line_point`` along ``e`` (the top turns with the deck, rotation th): the top point, the chord
    angle and the top tangent's angle against the chord.  None if the guide line is out of reach."""
    chord = L
    for _ in range(4):
        top = weld_point if weld_point is not None else _line_top(line_point, e, base, chord)
        if top is None:
            return None
        beta = math.atan2(top[1] - base[1], top[0] - base[0])
        t_top = math.remainder(th - (beta - beta0), 2.0 * math.pi)
        new = _chord(L, t_top)
        if abs(new - chord) <= 1e-15 * L:
            break
        chord = new
    return top, beta, t_top


def _rod_geometry(model, k):
    """What :func:`mechanism_state` needs of rod k's mesh, computed once per mesh (kept with it): its
    nodes and their positions, the base node, chord length and angle, the shape's polynomials in
    xi = s/L at the elements (xa^2 + xa xb + xb^2 - 1) and nodes (3 xi^2 - 1), the elements' lengths
    along the chord, and the rod's elements with their reference angles."""
    key = ("mechanism_state", k)
    geo = model.mesh.derived.get(key)
    if geo is None:
        nodes = model.rod_nodes[k]
        X = model.X0[nodes]
        base = (float(X[0, 0]), float(X[0, 1]))
        Lr = math.hypot(X[-1, 0] - base[0], X[-1, 1] - base[1])
        xi = np.hypot(X[:, 0] - base[0], X[:, 1] - base[1]) / Lr
        beta0 = math.atan2(X[-1, 1] - base[1], X[-1, 0] - base[0])
        xa, xb = xi[:-1], xi[1:]
        el = np.nonzero(model.elem_rod == k)[0]
        geo = model.mesh.derived[key] = (nodes, X, base, Lr, beta0, xa * xa + xa * xb + xb * xb - 1.0,
                                         np.diff(xi) * Lr, 3.0 * xi * xi - 1.0, el, model.elements.beta0[el])
    return geo


def mechanism_state(model, theta):
    """(y, elements): a start state of a paper structure's model at deck rotation ``theta`` [rad,
    counter-clockwise] (its chord rotations committed), or None if the geometry admits none (guide
    line out of reach)."""
    fs = model.structure
    th = float(theta)
    ct, st = math.cos(th), math.sin(th)

    def rot(v):   # R(th) v
        return (ct * v[0] - st * v[1], st * v[0] + ct * v[1])

    def add(*vs):
        return (sum(v[0] for v in vs), sum(v[1] for v in vs))

    def sub(a, b):
        return (a[0] - b[0], a[1] - b[1])

    nrm = (ct, st)      # deck's (1, 0): normal of the guide
    e = (-st, ct)       # deck's (0, 1): guide direction
    L = model.Lref
    pt = {j.name: (j.at[0] / L, j.at[1] / L) for j in fs.joints}
    Xd = tuple(model.body_X0[model.body_index["deck"]].tolist())
    A1, B0, B1 = pt["A1"], pt["clamp"], pt["B1"]
    A0 = pt["A"] if "A" in pt else A1  # the weld point of a flexible left rod
    left_rod = "left" in model.rod_index
    right_rod = "right" in model.rod_index

    def deck_at(A_new):
        """Deck centroid displacement with the weld point A at A_new."""
        return sub(add(A_new, rot(sub(Xd, A0))), Xd)

    def node(rod, i):
        X = model.X0[model.node(rod, i)]
        return tuple(X[:2].tolist())

    if not left_rod:           # a rigid left rod is part of the deck, pinned at A1
        Ud = sub(add(A1, rot(sub(Xd, A1))), Xd)
    else:
        base = node("left", 0)
        Lw = math.hypot(A0[0] - base[0], A0[1] - base[1])

        def weld_top(psi):  # psi: clockwise chord angle of the left rod from the vertical
            c = _chord(Lw, th + psi)
            return (base[0] + c * math.sin(psi), base[1] + c * math.cos(psi))

        if not right_rod:
            # the guide point B stays on the line through B1 along e:
            # chord sin(psi + Theta) + (base - B1) . n + (B - A)_x = 0
            psi = -th
            for _ in range(50):  # a contraction: the chord depends on psi only through t^2 / 10
                rhs = -((base[0] - B1[0]) * nrm[0] + (base[1] - B1[1]) * nrm[1] + (B0[0] - A0[0])) \
                    / _chord(Lw, th + psi)
                if abs(rhs) > 1.0:
                    return None
                psi, old = math.asin(rhs) - th, psi
                if abs(psi - old) <= 1e-15:
                    break
            Ud = deck_at(weld_top(psi))
        else:
            base_j = node("right", 0)
            top_j = node("right", -1)
            L_j = math.hypot(top_j[0] - base_j[0], top_j[1] - base_j[1])

            def mismatch(psi):  # sum of the top angles (tangent against chord) of the two rods
                A_new = weld_top(psi)
                B_new = add(A_new, rot(sub(B0, A0)))
                bent = _bent_top(None, B_new, e, base_j, L_j, math.pi / 2, th)
                return math.nan if bent is None else bent[2] + (th + psi)

            p0, p1 = -th, -th + 1e-3 * (1.0 + abs(th))
            f0, f1 = mismatch(p0), mismatch(p1)
            for _ in range(20):
                if not (math.isfinite(f0) and math.isfinite(f1)) or f1 == f0:
                    break
                p0, p1, f0 = p1, p1 - f1 * (p1 - p0) / (f1 - f0), f1
                f1 = mismatch(p1)
                if abs(p1 - p0) <= 1e-12:
                    break
            if not math.isfinite(f1):
                return None
            Ud = deck_at(weld_top(p1))
    y, elements = model.zero_state()
    alpha = elements.committed
    Uq = model.nodal(y[:model.n_q])
    A_new = add(Xd, Ud, rot(sub(A0, Xd)))
    B_new = add(Xd, Ud, rot(sub(B0, Xd)))
    for k, name in enumerate(r.name for r in fs.rods):
        nodes, X, base, Lr, beta0, xq, seg, xn, el, beta0_el = _rod_geometry(model, k)
        bent = _bent_top(A_new if name == "left" else None, B_new, e, base, Lr, beta0, th)
        if bent is None:
            return None
        _, beta, t_top = bent
        t_el = 0.5 * t_top * xq
        gam = beta + t_el
        P = np.empty_like(X)
        P[0] = base
        P[1:, 0] = base[0] + (seg * np.cos(gam)).cumsum()   # (the method: no dispatch wrapper)
        P[1:, 1] = base[1] + (seg * np.sin(gam)).cumsum()
        Uq[nodes, :2] = P - X
        Uq[nodes, 2] = (beta - beta0) + 0.5 * t_top * xn
        alpha[el] = gam - beta0_el
    for b in fs.bodies:
        d = model.body_dof(b.name)
        Xb = tuple(model.body_X0[model.body_index[b.name]].tolist())
        if b.name == "deck":
            U = Ud
        elif b.name == "right":     # the rigid right rod turns with the deck about its ground pin
            U = sub(add(B1, rot(sub(Xb, B1))), Xb)
        else:                                 # the piece, welded to the right rod's top node
            top = model.node("right", -1)
            Xt = (float(model.X0[top, 0] + Uq[top, 0]), float(model.X0[top, 1] + Uq[top, 1]))
            X0t = (float(model.X0[top, 0]), float(model.X0[top, 1]))
            U = sub(add(Xt, rot(sub(Xb, X0t))), Xb)
        y[d:d + 2], y[d + 2] = U, th
    return y, elements
