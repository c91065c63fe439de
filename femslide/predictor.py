"""Newton start of a structure scene: its spring-hinge mechanism, deformed, at a given body rotation.

The equivalent spring-hinge model (femslide.hinge) gives the body rotation phi of the equilibrium to
within a few per mille for EI >= 1e2 N m^2 (and within tens of per cent at EI = 1e1).  From phi alone
this module builds a state of the FE model that satisfies its joints up to O(h^2) and has no axial
strain, so that Newton, started there, needs only a few iterations:

- body: turned by Theta = -phi; its position follows from the ground pin of a rigid rod (body pin),
  or from the welded flexible rod, whose chord keeps its length and turns so that the body's guide
  point stays on the rigid rod's guide line, or, with a flexible rod in the clamp instead, so that
  the two rods share the kinematic misfit equally: opposite top angles against their chords (the
  bending energy of two equal rods is least so; the misfit itself does not depend on the turn);
- flexible rods (pinned at the ground node, top welded or in a sliding clamp that locks the top
  rotation to the body's): the chord runs from the ground node to the top, which is the weld point,
  or the point of the guide line at the rod's chord length from the ground node; the shape is the
  linear beam under a top moment with zero moment at the pin: the tangent turns from the chord by
  t(xi) = t_top (3 xi^2 - 1) / 2 (xi = s/L), so the top tangent matches the body's rotation and the
  chord is kept; elements are laid end to end with their initial lengths.
Multipliers start at zero (the equations are linear in them).  Angles are counter-clockwise; the
rods are vertical in the undeformed state, as in every structure scene.
"""
from __future__ import annotations

import math

import numpy as np

from .joints import BodyPin, GuideLine, SlidingClamp, Weld


def _top_joint(model, node):
    for c in model.constraints:
        if isinstance(c, (Weld, SlidingClamp)) and c.node == node:
            return c
    return None


def _chord(L, t_top):
    """Chord of a rod of length L bent by the tangent angles t_top (3 xi^2 - 1) / 2 (to O(t^4))."""
    return L * (1.0 - t_top * t_top / 10.0)


def _clamp_top(clamp, ref, nrm, e, base, chord):
    """The point of the clamp's guide line (body reference point at ``ref``, normal ``nrm``, direction
    ``e``) at distance ``chord`` from ``base``, up the guide; None if the line is out of reach."""
    c0 = ref + clamp.r[0] * nrm - base
    ce = c0 @ e
    disc = ce * ce - c0 @ c0 + chord * chord
    if disc < 0.0:
        return None
    return base + c0 + (-ce + math.sqrt(disc)) * e


def _bent_top(joint, ref, R, nrm, e, base, L, beta0, th):
    """(top, beta, t_top) of a rod of length L pinned at ``base`` (initial chord angle beta0) whose
    top is welded to the body or held in its clamp (body reference point at ``ref``, rotation th):
    the top point, the chord angle and the top tangent's angle against the chord; the clamped top is
    where the guide line meets the bent rod's chord.  None if the guide line is out of reach."""
    chord = L
    for _ in range(4):
        if isinstance(joint, Weld):
            top = ref + R @ joint.r
        else:
            top = _clamp_top(joint, ref, nrm, e, base, chord)
            if top is None:
                return None
        beta = math.atan2(top[1] - base[1], top[0] - base[0])
        t_top = math.remainder(th - (beta - beta0), 2.0 * math.pi)
        new = _chord(L, t_top)
        if abs(new - chord) <= 1e-15 * L:
            break
        chord = new
    return top, beta, t_top


def mechanism_state(bt, phi):
    """(y, alpha): a start state of the built structure ``bt`` at body rotation phi [rad] (phi >= 0
    towards the side the load pushes), or None if the geometry admits none (guide line out of reach)."""
    m = bt.model
    th = -bt.phi_dir * phi
    ct, st = math.cos(th), math.sin(th)
    R = np.array([[ct, -st], [st, ct]])
    nrm = np.array([ct, st])    # body's (1, 0): normal of its guide lines
    e = np.array([-st, ct])     # body's (0, 1): guide direction
    A0 = m.body.A0
    rods = range(len(m.rods))
    tops = {k: _top_joint(m, m.node(k, -1)) for k in rods}
    welded = [k for k in rods if isinstance(tops[k], Weld)]
    if isinstance(bt.pin_A1, BodyPin):
        U = bt.pin_A1.ground - A0 - R @ bt.pin_A1.r
    elif welded:
        k = welded[0]
        w = tops[k]
        base = m.X0[m.node(k, 0)]
        Lw = float(np.hypot(*(w.X0 - base)))

        def pose(psi):  # psi: clockwise chord angle of the welded rod from the vertical
            top = base + _chord(Lw, th + psi) * np.array([math.sin(psi), math.cos(psi)])
            return top - A0 - R @ w.r

        if isinstance(bt.guide, GuideLine):
            # the body's guide point stays on the guide line through the rigid rod's ground pin:
            # chord sin(psi + Theta) + (base - ground).n + r_guide_x - r_weld_x = 0
            g = bt.guide
            psi = -th
            for _ in range(50):  # a contraction: the chord depends on psi only through t^2 / 10
                rhs = -((base - g.ground) @ nrm + g.r[0] - w.r[0]) / _chord(Lw, th + psi)
                if abs(rhs) > 1.0:
                    return None
                psi, old = math.asin(rhs) - th, psi
                if abs(psi - old) <= 1e-15:
                    break
            U = pose(psi)
        else:
            others = [j for j in rods if isinstance(tops[j], SlidingClamp)]
            if not others:
                return None
            j = others[0]
            base_j = m.X0[m.node(j, 0)]
            L_j = float(np.hypot(*(m.X0[m.node(j, -1)] - base_j)))

            def mismatch(psi):  # sum of the top angles (tangent against chord) of the two rods
                bent = _bent_top(tops[j], A0 + pose(psi), R, nrm, e, base_j, L_j, math.pi / 2, th)
                return math.nan if bent is None else bent[2] + (th + psi)

            # secant from the rigid turn with the body (psi = -Theta)
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
            U = pose(p1)
    else:
        return None
    y, alpha = m.zero_state()
    Uq = m.nodal(y[:m.n_q])
    for k in rods:
        joint = tops[k]
        nodes = m.rod_nodes[k]
        X = m.X0[nodes]
        base = X[0]
        L = float(np.hypot(*(X[-1] - X[0])))
        xi = np.hypot(*(X - base).T) / L
        beta0 = math.atan2(X[-1, 1] - X[0, 1], X[-1, 0] - X[0, 0])
        bent = _bent_top(joint, A0 + U, R, nrm, e, base, L, beta0, th) if joint is not None else None
        if bent is None:
            return None
        _, beta, t_top = bent
        # tangent angle relative to the chord: t(xi) = t_top (3 xi^2 - 1) / 2; mean over an element
        xa, xb = xi[:-1], xi[1:]
        t_el = 0.5 * t_top * (xa * xa + xa * xb + xb * xb - 1.0)
        gam = beta + t_el
        seg = np.diff(xi) * L
        P = np.vstack([base, base + np.cumsum(seg[:, None] * np.column_stack([np.cos(gam), np.sin(gam)]),
                                              axis=0)])
        Uq[nodes, :2] = P - X
        Uq[nodes, 2] = (beta - beta0) + 0.5 * t_top * (3.0 * xi * xi - 1.0)
        alpha[m.elem_rod == k] = gam - m.elements.beta0[m.elem_rod == k]
    b0 = m.body.dof0
    y[b0:b0 + 2], y[b0 + 2] = U, th
    return y, alpha
