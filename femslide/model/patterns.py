"""A cache of Jacobian patterns, owned by whoever solves several models of one topology (the mesh
levels of a solve, the cases of a sweep).  No numpy at import: a sweep of spring-hinge scenes creates
one without loading the FE machinery."""
from __future__ import annotations


LIMIT = 256   # entries kept per kind: a sweep over a geometry builds a model per case


class _Lru:
    """A map bounded to ``limit`` entries: the least recently used is dropped first (a rebuild later
    costs what the first build cost; nothing is ever served for another key)."""

    __slots__ = ("_d", "limit")

    def __init__(self, limit):
        self._d, self.limit = {}, limit

    def get(self, key):
        d = self._d
        value = d.pop(key, None)   # (re-inserted: the most recently used last)
        if value is not None:
            d[key] = value
        return value

    def put(self, key, value):
        d = self._d
        d[key] = value
        if len(d) > self.limit:
            del d[next(iter(d))]
        return value

    def get_or_build(self, key, build):
        """The value of ``key``, made by ``build()`` and kept if absent."""
        value = self.get(key)
        return value if value is not None else self.put(key, build())

    def __len__(self):
        return len(self._d)


class PatternCache:
    """Dof layouts and Jacobian scatter patterns (femslide.model.discrete._Topology) by model topology,
    rod meshes by geometry, the frames, joints and loads of models by their structure's plan, and
    frozen structures by the values they were declared from but the rods' stiffness; each kind bounded
    to ``limit`` entries, the least recently used dropped (a long sweep over geometry keeps its memory)."""

    def __init__(self, limit: int = LIMIT):
        self._topologies = _Lru(limit)
        self._meshes = _Lru(limit)
        self._frames = _Lru(limit)
        self._ids = _Lru(limit)
        self._next_id = 0
        self._structures = _Lru(limit)

    def structure(self, key, build):
        """A frozen structure kept by ``key`` (a scene and its values but the rods' stiffness: the
        cases of a sweep over EI derive theirs from it, femslide.model.frozen.Frozen.with_stiffness),
        built by ``build()`` once."""
        return self._structures.get_or_build(key, build)

    def key_id(self, key) -> int:
        """A small integer for a (large, hashable) key, the same for equal keys while it is kept: the
        caches' lookups by it hash an int instead of the key's nested tuples (a model's plan key, at every
        model built).  Never reused: a key dropped and seen again gets a new one (its entries are rebuilt)."""
        i = self._ids.get(key)
        if i is None:
            i = self._ids.put(key, self._next_id)
            self._next_id += 1
        return i

    def mesh(self, key, build):
        """The rod meshes of a geometry and element counts (femslide.model.discrete._Mesh), built once."""
        return self._meshes.get_or_build(key, build)

    def frames(self, key, model=None):
        """A finalized model (femslide.model.discrete.Model) whose frames, joints, terms and loads the models of
        this key (plan and element counts) share, or None; with ``model``: keep it for the key (unless one is)."""
        held = self._frames.get(key)
        if held is None and model is not None:
            held = self._frames.put(key, model)
        return held

    def topology(self, key, build):
        """The dof layout and Jacobian patterns (femslide.model.discrete._Topology) of a model topology
        ``key``, built by ``build()`` once."""
        return self._topologies.get_or_build(key, build)
