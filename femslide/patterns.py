"""A cache of Jacobian patterns, owned by whoever solves several models of one topology (the mesh
levels of a solve, the cases of a sweep).  No numpy at import: a sweep of spring-hinge scenes creates
one without loading the FE machinery."""
from __future__ import annotations


class PatternCache:
    """Dof layouts and Jacobian scatter patterns (femslide.model._Topology) by model topology,
    and rod meshes by geometry."""

    def __init__(self):
        self._topologies = {}
        self._meshes = {}

    def mesh(self, key, build):
        """The rod meshes of a geometry and element counts (femslide.model._Mesh), built once."""
        m = self._meshes.get(key)
        if m is None:
            m = self._meshes[key] = build()
        return m

    def topology(self, model, con_dofs, term_dofs, lin_dofs):
        key = (model.n_q, model.elements.conn.tobytes() if model.elements is not None else b"",
               tuple((c.size, d.tobytes()) for c, d in zip(model.constraints, con_dofs)),
               tuple(d.tobytes() for d in term_dofs), lin_dofs.tobytes())
        topo = self._topologies.get(key)
        if topo is None:
            from .model import _Topology
            topo = self._topologies[key] = _Topology(model, con_dofs, term_dofs, lin_dofs)
        return topo
