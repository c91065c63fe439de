"""Coulomb friction in sliders and rollers for the FE dynamics (exact stick, events located in time).

A joint with ``mu`` (kinetic) and ``mu0`` >= mu (static) resists its slide s (the displacement of a's
point along the guide carried by b; femslide/joints/base.py) by a friction force along the guide:

- normal force N from the joint's own multipliers, by its kind
  (:meth:`femslide.joints.kind.JointKind.normal_force`): a slider carries its transverse force Q
  (first multiplier) and its moment M (second); with ``bearing = h`` the guide's two bearings h
  apart take the contact forces Q/2 + M/h and Q/2 - M/h and N = |Q/2 + M/h| + |Q/2 - M/h|; without a
  bearing (and for a roller) N = |Q|.  N is evaluated implicitly, at the end of every step, with the
  multipliers of that step;
- stuck: the slide is locked exactly by an extra constraint s(q) = s_stick (velocity exactly zero,
  no drift, no chattering); its multiplier lam is the friction force that holds it (the force along
  +s on a is -lam).  Stuck while |lam| <= mu0 N;
- slip in the direction sigma = +-1: the friction force -sigma mu N along the guide (on a, and its
  reaction on b): the generalised force -sigma mu N ds/dq with its Jacobian (N's derivatives with
  respect to the joint's multipliers lie in the joint's own Jacobian block);
- events, located in time by the Illinois method on the step size (each trial a step of the
  integrator from the last accepted state, so the event lies on the step's own solution): slip ends
  when sigma s' reaches 0; there the stick test is made (the lock multiplier of the consistent
  start, |lam| <= mu0 N) and the joint sticks ("stick") or slips on in the direction of the net force
  ("slip+" / "slip-"); a stuck joint breaks away when |lam| reaches mu0 N, towards sign(lam).  At
  every event the massless dofs (rods with rhoA = 0) are re-solved for their equilibrium in the new
  modes with the massive dofs held, their velocities made consistent with the massive ones, and the
  integrator restarts with consistent accelerations (the friction force jumps).  A massless slide
  that breaks away with mu0 > mu therefore jumps at once to the position where the forces on it equal
  the sliding friction and stops there: the quasi-static limit of a vanishing slide mass with the
  jump's energy lost on the way (a small slide mass on a spring would overshoot before it sticks);
  the potential energy released counts as dissipated (femslide/analysis/transient.py, ``_requilibrate``).
- a joint with mu0 = 0 has no friction at all: femslide/analysis/simulate.py treats it as an ordinary slider
  or roller.

The structure's model gets one extra constraint per stuck joint: a model per set of stuck joints,
built when first needed (the lock multipliers come after the joints', so the joints' layout stays).
Energy: friction dissipates mu N |s'| (integrated with the others in femslide/analysis/transient.py).
"""
from __future__ import annotations

import numpy as np

from femslide.joints.base import at_joint_point


class FrictionJoint:
    """One friction joint of a model: the slide, the normal force and the slip force."""

    def __init__(self, model, joint):
        self.name = joint.name
        self.link = model.joint[joint.name]
        self.dofs = self.link.dofs
        self.link_nq = model.n_q
        i = model.constraints.index(self.link)
        o = model.n_q + int(model.c_off[i])
        self.mu_idx = np.arange(o, o + self.link.size, dtype=np.intp)
        self.mu = float(joint.mu) if joint.mu is not None else 0.0
        self.mu0 = float(joint.mu0) if joint.mu0 is not None else 0.0
        self.friction = self.mu0 > 0.0                    # (mu0 = 0: no friction at all)
        self.unilateral = bool(getattr(joint, "unilateral", False))
        self.restitution = float(getattr(joint, "restitution", None) or 0.0)
        self.h = joint.bearing / model.Lref if joint.bearing else None
        self.kind = self.link.joint_kind
        # COO pattern of the slip force: (dofs x dofs) and (dofs x joint multipliers)
        d, m = self.dofs, self.mu_idx
        self.rows = np.concatenate([np.repeat(d, d.size), np.repeat(d, m.size)])
        self.cols = np.concatenate([np.tile(d, d.size), np.tile(m, d.size)])

    def normal(self, y):
        """N (model units) and dN / d(joint multipliers)."""
        N, dN = self.kind.normal_force(y[self.mu_idx].tolist(), self.h)
        return N, np.array(dN)

    def gap(self, q):
        """(gap, its gradient over the joint's dofs) of a contact: w . n, a's point's distance from
        the guide line on its +n side (the kind's first equation, model units)."""
        g, G, _ = self.link._parts(q[self.dofs].tolist())
        return float(g[0]), np.array(G[0])

    def gap_rates(self, q, v, acc):
        """(gap', gap'') of a contact at positions q, velocities v and accelerations acc: G v and
        G acc + v^T H v, with the gradient G and the Hessian H of its first equation."""
        _, G, hess = self.link._parts(q[self.dofs].tolist())
        vd, ad = v[self.dofs], acc[self.dofs]
        g1 = float(np.dot(G[0], vd))
        g2 = float(np.dot(G[0], ad)) + sum(val * vd[i] * vd[j] for e, i, j, val in hess if e == 0)
        return g1, g2

    def pressure(self, y):
        """A contact's normal force -Q (model units): >= 0 while it presses (the force -Q n on a)."""
        return -float(y[self.mu_idx[0]])

    def slide_rate(self, q, v):
        """(s, s') of the joint (s from its absolute value along the guide, model units)."""
        z = q[self.dofs]
        s, ds, _ = self.link.slide(z)
        return float(s), float(ds @ v[self.dofs])

    def slip(self, sigma):
        """The slip force as an ``extra`` term of a :class:`femslide.analysis.radau.RadauSystem`."""
        def term(y, v1, c_vel):
            q = y[:self.link_nq]
            s, ds, Hs = self.link.slide(q[self.dofs])
            N, dN = self.normal(y)
            c = sigma * self.mu
            f = np.zeros(self.link_nq)
            f[self.dofs] = c * N * ds
            vals = np.concatenate([(c * N * Hs).ravel(), (c * np.outer(ds, dN)).ravel()])
            return f, (self.rows, self.cols, vals)
        return term


def joint_friction_force(link, c, q):
    """(Fx, Fy, M) (model units) of a friction force of coefficient c along the guide on part a at
    the joint point: the generalised force -c ds/dq on a's dofs, its moment taken about the joint
    point (:func:`femslide.results.static.at_joint_point`)."""
    if link.ia is None:
        return 0.0, 0.0, 0.0
    z = q[link.dofs]
    _, ds, _ = link.slide(z)
    f = (-c * ds[link.ia:link.ia + 3]).tolist()
    return at_joint_point(link, z.tolist(), f)
