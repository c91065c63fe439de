"""A cache of Jacobian patterns, owned by whoever solves several models of one topology (the mesh
levels of a solve, the cases of a sweep).  No numpy at import: a sweep of spring-hinge scenes creates
one without loading the FE machinery."""
from __future__ import annotations


class PatternCache:
    """Dof layouts and Jacobian scatter patterns (femslide.model._Topology) by model topology."""

    def __init__(self):
        self._topologies = {}

    def topology(self, model, con_dofs, term_dofs, lin_dofs):
        key = (model.n_q, model.elements.conn.tobytes() if model.elements is not None else b"",
               tuple((c.size, d.tobytes()) for c, d in zip(model.constraints, con_dofs)),
               tuple(d.tobytes() for d in term_dofs), lin_dofs.tobytes())
        topo = self._topologies.get(key)
        if topo is None:
            from .model import _Topology
            topo = self._topologies[key] = _Topology(model, con_dofs, term_dofs, lin_dofs)
        return topo
