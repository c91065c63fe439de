"""A cache of Jacobian patterns, owned by whoever solves several models of one topology (the mesh
levels of a solve, the cases of a sweep).  No numpy at import: a sweep of spring-hinge scenes creates
one without loading the FE machinery."""
from __future__ import annotations


class PatternCache:
    """Dof layouts and Jacobian scatter patterns (femslide.model.discrete._Topology) by model topology,
    rod meshes by geometry, and the frames, joints and loads of models by their structure's plan."""

    def __init__(self):
        self._topologies = {}
        self._meshes = {}
        self._frames = {}

    def mesh(self, key, build):
        """The rod meshes of a geometry and element counts (femslide.model.discrete._Mesh), built once."""
        m = self._meshes.get(key)
        if m is None:
            m = self._meshes[key] = build()
        return m

    def frames(self, key, model=None):
        """A finalized model (femslide.model.discrete.Model) whose frames, joints, terms and loads the models of
        this key (plan and element counts) share, or None; with ``model``: keep it for the key."""
        if model is not None:
            self._frames.setdefault(key, model)
        return self._frames.get(key)

    def topology(self, key, build):
        """The dof layout and Jacobian patterns (femslide.model.discrete._Topology) of a model topology
        ``key``, built by ``build()`` once."""
        topo = self._topologies.get(key)
        if topo is None:
            topo = self._topologies[key] = build()
        return topo
