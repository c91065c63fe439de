"""A cache of Jacobian patterns, owned by whoever solves several models of one topology (the mesh
levels of a solve, the cases of a sweep).  No numpy at import: a sweep of spring-hinge scenes creates
one without loading the FE machinery."""
from __future__ import annotations


class PatternCache:
    """Dof layouts and Jacobian scatter patterns (femslide.model.discrete._Topology) by model topology,
    rod meshes by geometry, the frames, joints and loads of models by their structure's plan, and
    frozen structures by the values they were declared from but the rods' stiffness."""

    def __init__(self):
        self._topologies = {}
        self._meshes = {}
        self._frames = {}
        self._ids = {}
        self._structures = {}

    def structure(self, key, build):
        """A frozen structure kept by ``key`` (a scene and its values but the rods' stiffness: the
        cases of a sweep over EI derive theirs from it, femslide.model.frozen.Frozen.with_stiffness),
        built by ``build()`` once."""
        fs = self._structures.get(key)
        if fs is None:
            fs = self._structures[key] = build()
        return fs

    def key_id(self, key) -> int:
        """A small integer for a (large, hashable) key, the same for equal keys: the caches' lookups by
        it hash an int instead of the key's nested tuples (a model's plan key, at every model built)."""
        return self._ids.setdefault(key, len(self._ids))

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
