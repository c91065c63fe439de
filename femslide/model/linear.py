"""First-order (geometrically linear) theory: the discrete model linearised about the reference state.

``[solve] theory = "linear"`` solves the problem of hand calculations and linear frame codes: small
displacements, equilibrium written on the undeformed structure.  :class:`LinearModel` is the
:class:`femslide.model.discrete.Model` of the same structure with its equations replaced by their
linearisation at the reference state (y = 0, no stresses, no loads):

    A0 y + lam f = 0,

A0 the Jacobian there - the rods' elastic stiffness (the corotational tangent at zero stress is the
linear beam's), the springs', the joints' gradients G0 (their curvature enters only with
multipliers, which are zero there) - and f the dead loads.  Nothing of the geometric stiffness (axial
forces, joint forces, loads turning with bodies) is left: a linear structure's results are linear in
its loads, so that combinations superpose exactly.  Newton converges in one step.

Results come from the same recovery as the exact theory's (femslide.results.static), on the
reference geometry: cut forces from the equilibrium of the undeformed rod pieces, joint forces from
the multipliers on the reference gradients, spring forces linear in the displacements; displacements
and rotations are reported as computed (and drawn on the deformed shape).
"""
from __future__ import annotations

import numpy as np

from femslide.elements import corotational
from femslide.model.discrete import Model, _Info


class LinearModel(Model):
    """The linearised model (module docstring); same constructor as :class:`Model`."""

    linear = True
    theory = "linear"
    _OWN = Model._OWN | {"_lin"}

    # -- the constant parts ---------------------------------------------------------------------------
    def _parts(self, control=None):
        """(sparse Jacobian at the reference for this control (csc), d r / d lam over the frame dofs,
        the elements' reference tangents (n, 6, 6), their dof indices (n, 6)), built once."""
        lin = self.__dict__.setdefault("_lin", {})
        key = None if control is None else int(control.dof)
        if key not in lin:
            z0, es0 = self._reference(control)
            r, A, info = Model.system(self, z0, es0, 0.0, control)
            S = self.to_csc(A, control)
            if "elements" not in lin:
                lin["elements"] = _element_tangents(self)
                lin["fl"] = np.array(info["fl"])
                # a thermal load's share of fl: the elements' free forces at the reference, -B0^T S_T
                lin["fl_T"] = np.zeros(self.n_q)
                if self.free_T is not None:
                    _, ed = lin["elements"]
                    F = corotational.free_nodal(self.elements, np.zeros(self.n_q), np.zeros(self.elements.size),
                                                self.free_T)
                    lin["fl_T"] = -np.bincount(ed.T.ravel(), weights=F.ravel(), minlength=self.n_q)
            lin[key] = S
        return lin[key], lin["fl"], lin["elements"]

    def _reference(self, control=None):
        """The reference state (zero, with a zero load factor when it is an unknown)."""
        z0, es0 = Model.zero_state(self)
        if control is not None:
            z0 = np.zeros(self.n + 1)
        return z0, es0

    def element_forces_linear(self, q, lam=1.0):
        """Generalised forces (n_q) of the rod elements, linear in q (model units), with their free
        (thermal) forces at load factor ``lam``."""
        _, _, (K, ed) = self._parts()
        if K is None:
            return np.zeros(self.n_q)
        d = q[ed]
        F = np.einsum("eij,ej->ei", K, d)
        out = np.bincount(ed.ravel(), weights=F.ravel(), minlength=self.n_q)
        if self.free_T is not None:
            out += lam * self.__dict__["_lin"]["fl_T"]
        return out

    # -- the model's interface ------------------------------------------------------------------------
    def system(self, y, elements, lam=1.0, control=None, jacobian=True, dense=False, extra=None, n_geometric=None):
        """Residual and Jacobian of the linear equations (same interface and storage as
        :meth:`Model.system`; the Jacobian is the same at every state but for the caller's ``extra``
        terms, added as there; it carries no state's axial forces, so ``n_geometric`` must be None)."""
        if n_geometric is not None:
            raise ValueError("LinearModel.system: the linear theory's tangent takes no n_geometric")
        S, fl, _ = self._parts(control)
        r = S @ y
        n_q = self.n_q
        if control is None:
            r[:n_q] += lam * fl
        else:
            lam = y[-1]
            r[-1] -= control.target
        if self._motion_rows.size:   # prescribed support motion
            r[self._motion_rows] += lam * self._motion_vals
        if extra is not None and extra[0] is not None:
            np.add.at(r, extra[0], extra[1])
        info = _Info(lam=lam)
        fe = self.element_forces_linear(y[:n_q], lam)
        info["fmax"] = float(np.abs(fe).max()) if fe.size else 0.0
        info["noise"] = 0.0
        info["fl"] = fl
        elements.trial = elements.committed
        if not jacobian:
            return r, None, info
        z0, es0 = self._reference(control)
        jx = None if extra is None or extra[2] is None else (None, None, extra[2], extra[3])
        _, A, _ = Model.system(self, z0, es0, 0.0, control, True, dense, extra=jx)
        return r, A, info

    def applied(self, y, lam=1.0):
        """The generalised forces of everything but the rod elements - loads, springs, joint
        multipliers on the reference gradients - linear in y (see :meth:`Model.applied`)."""
        S, fl, _ = self._parts()
        n_q = self.n_q
        return (S @ y)[:n_q] + lam * fl - self.element_forces_linear(y[:n_q], lam)

    def element_forces(self, q, alpha_ref):
        """Basic forces (N, M1, M2) of every element, linear in q, and the chord rotations."""
        es = self.elements
        if es is None:
            return np.zeros((0, 3)), np.zeros(0)
        U = self.nodal(q)
        d = U[es.j, :2] - U[es.i, :2]
        c, s = np.cos(es.beta0), np.sin(es.beta0)
        u_bar = c * d[:, 0] + s * d[:, 1]
        alpha = (-s * d[:, 0] + c * d[:, 1]) / es.L0
        t = np.column_stack([U[es.i, 2] - alpha, U[es.j, 2] - alpha])
        kb = es.kb
        N = kb[:, 0, 0] * u_bar
        M = np.einsum("eij,ej->ei", kb[:, 1:, 1:], t)
        out = np.column_stack([N, M])
        if self.free_T is not None:   # the free (thermal) forces at full load
            out -= self.free_T.T
        return out, alpha


def _element_tangents(model):
    """(K (n, 6, 6), dof indices (n, 6)) of the elements at the reference state, or (None, None)."""
    es = model.elements
    if es is None:
        return None, None
    U0 = np.zeros((model.n_nodes, 3))
    _, K, _, _, _ = corotational.evaluate(es, U0, np.zeros(es.size))
    c = es.conn
    ed = np.concatenate([3 * c[:, :1] + np.arange(3), 3 * c[:, 1:] + np.arange(3)], axis=1)
    return K, ed
