"""Mesh files of the FE scenes: the reference (undeformed) discretisation, written and checked.

A scene mesh is any meshio-readable file (VTU is what ``femslide mesh`` writes; Gmsh ``.msh`` or XDMF
with physical names work too) in SI units (m), z = 0, holding named groups:

- ``rod:<name>``: the line cells (2-node elements) of one flexible rod, e.g. ``rod:right`` for the
  sliding rod of beam-slider, ``rod:left`` for the welded rod of beam-fixed, ``rod:cantilever``;
- ``rigid:<name>``: one line cell for a rigid rod of the mechanism (not meshed by the solver; drawn);
- ``support:<name>``: a vertex cell at a ground support: ``support:A1``, ``support:B1`` (ground
  hinges), ``support:clamp`` (the cantilever's clamped end);
- ``body``: the rigid body ABCD as one polygon cell (structure scenes).

A group is either a meshio cell set of that name (Gmsh physical names arrive so) or an integer cell
data array of that name, nonzero on the group's cells (what ``femslide mesh`` writes: VTU keeps cell
data, not cell sets).

What a mesh fixes, and what it does not: femslide's scene declarations (femslide/scenes/paper.py) make straight
rods with equally spaced nodes, one element count for all flexible rods.  A scene file's mesh is
*checked* against them (groups present, rods straight with equal elements, end points where the
scene's parameters a, l, L put them) and its element count sets ``n_elements``; the solver then
builds that same discretisation.  A mesh that the builders cannot reproduce (graded or curved rods,
different counts per rod) is rejected with a clear message instead of being approximated: this is
not a general mesh-driven model builder.
"""
from __future__ import annotations

import os

from femslide.errors import BadInput
from femslide.records import dataclass, field

DEFAULT_N = 64  # elements per flexible rod that ``femslide mesh`` writes without --set n_elements
GROUP_PREFIXES = ("rod:", "rigid:", "support:")
MAX_MESH_BYTES = 128 * 2**20  # larger files are not read (memory): n_elements <= 100000 needs ~20 MiB
REL_TOL = 1e-6  # geometry tolerance, relative to the structure's size (hand-written files round)


# -- the scene's reference geometry (from the solver's own builders) ------------------------------------

@dataclass
class Geometry:
    """Reference geometry of an FE scene in SI units."""

    rods: dict                 # flexible rod name -> (nodes (n+1, 2)), start = ground end
    rigid: dict = field(default_factory=dict)      # rigid rod name -> (2, 2) end points
    supports: dict = field(default_factory=dict)   # support name -> (x, y)
    body: object = None        # (4, 2) corners A, B, C, D or None

    @property
    def size(self):
        import numpy as np
        pts = [np.atleast_2d(p) for p in (*self.rods.values(), *self.rigid.values())]
        if self.body is not None:
            pts.append(self.body)
        return float(max(np.abs(np.concatenate(pts)).max(), 1e-300))


def geometry(scene: str, values: dict, n: int) -> Geometry:
    """The reference geometry the solver builds for ``scene`` with validated ``values`` and ``n``
    elements per flexible rod (the declarations of femslide.scenes.paper)."""
    import numpy as np

    from femslide.scenes.paper import CANTILEVERS, STRUCTURES, declare
    if scene not in STRUCTURES + CANTILEVERS:
        raise BadInput(f"scene {scene} builds no beams: it has no mesh")
    t = np.linspace(0.0, 1.0, n + 1)[:, None]
    rods = {r.name: (1 - t) * np.asarray(r.start) + t * np.asarray(r.end)
            for r in declare(scene, values).rods.values()}
    if scene in CANTILEVERS:
        return Geometry(rods, supports={"clamp": rods["cantilever"][0]})
    a, l, b = values["a"], values["l"], values["b"]
    g = Geometry(rods, supports={"A1": np.array([0.0, 0.0]), "B1": np.array([2 * a, 0.0])})
    if "left" not in rods:
        g.rigid["left"] = np.array([[0.0, 0.0], [0.0, l]])
    if "right" not in rods:
        g.rigid["right"] = np.array([[2 * a, 0.0], [2 * a, l]])
    g.body = np.array([[0.0, l], [2 * a, l], [2 * a, l + 2 * b], [0.0, l + 2 * b]])
    return g


# -- writing --------------------------------------------------------------------------------------------

def to_meshio(geo: Geometry):
    """A meshio.Mesh of the geometry: line cells (rod elements, then rigid rods), vertex cells
    (supports), one polygon (body); one int32 cell-data mask per group."""
    import meshio
    import numpy as np
    pts, lines, groups_line = [], [], []
    off = 0
    for name, X in geo.rods.items():
        k = len(X)
        pts.append(X)
        lines.append(off + np.stack([np.arange(k - 1), np.arange(1, k)], axis=1))
        groups_line += [f"rod:{name}"] * (k - 1)
        off += k
    for name, X in geo.rigid.items():
        pts.append(X)
        lines.append(np.array([[off, off + 1]]))
        groups_line.append(f"rigid:{name}")
        off += 2
    verts, groups_vert = [], []
    for name, p in geo.supports.items():
        pts.append(np.atleast_2d(p))
        verts.append([off])
        groups_vert.append(f"support:{name}")
        off += 1
    blocks = [("line", np.concatenate(lines)), ("vertex", np.array(verts))]
    block_groups = [groups_line, groups_vert]
    if geo.body is not None:
        pts.append(geo.body)
        blocks.append(("polygon", np.arange(off, off + 4)[None, :]))
        block_groups.append(["body"])
        off += 4
    P = np.concatenate(pts)
    points = np.column_stack([P, np.zeros(len(P))])
    names = list(dict.fromkeys(g for bg in block_groups for g in bg))
    cell_data = {nm: [np.array([g == nm for g in bg], dtype=np.int32) for bg in block_groups]
                 for nm in names}
    return meshio.Mesh(points, [(t, c.astype(np.int64)) for t, c in blocks], cell_data=cell_data)


def write(scene: str, values: dict, path: str, n: int | None = None) -> str:
    """Write the reference mesh of ``scene`` to ``path`` (format from the extension); return it."""
    n = int(n or values.get("n_elements") or DEFAULT_N)
    mesh = to_meshio(geometry(scene, values, n))
    d = os.path.dirname(path)
    if d:
        os.makedirs(d, exist_ok=True)
    try:
        mesh.write(path)
    except Exception as exc:  # meshio: unknown extension or a format that cannot hold these cells
        raise BadInput(f"cannot write mesh {path}: {exc}") from None
    return path


# -- reading and checking --------------------------------------------------------------------------------

@dataclass
class MeshFile:
    """The groups of a mesh file: name -> list of (cell type, connectivity (k, nodes)) and its points."""

    path: str
    points: object
    groups: dict

    def lines(self, name):
        import numpy as np
        conn = [c for t, c in self.groups.get(name, []) if t == "line"]
        return np.concatenate(conn) if conn else np.zeros((0, 2), int)

    def n_elements(self, rod):
        return len(self.lines(f"rod:{rod}"))


def read(path: str) -> MeshFile:
    """Read a mesh file with meshio and collect its named groups; BadInput when it cannot be used."""
    import numpy as np
    if not os.path.isfile(path):
        raise BadInput(f"mesh file {path} not found")
    size = os.path.getsize(path)
    if size > MAX_MESH_BYTES:
        raise BadInput(f"mesh file {path}: {size / 2**20:.0f} MiB; allowed: at most "
                       f"{MAX_MESH_BYTES // 2**20} MiB (a mesh within n_elements <= 100000 per rod needs "
                       f"far less)")
    from femslide.output.vtu import read_meshio
    mesh = read_meshio(path, "mesh file")
    if not any(b.type == "line" for b in mesh.cells):
        raise BadInput(f"mesh file {path} has no line cells (the rods' elements)")
    groups: dict = {}
    for name, per_block in (mesh.cell_sets or {}).items():
        for b, idx in zip(mesh.cells, per_block):
            if idx is not None and len(idx):
                groups.setdefault(name, []).append((b.type, np.asarray(b.data)[np.asarray(idx, int)]))
    for name, per_block in (mesh.cell_data or {}).items():
        if not (name == "body" or name.startswith(GROUP_PREFIXES)):
            continue
        for b, mask in zip(mesh.cells, per_block):
            sel = np.asarray(mask).reshape(len(b.data), -1)[:, 0] != 0
            if sel.any():
                groups.setdefault(name, []).append((b.type, np.asarray(b.data)[sel]))
    return MeshFile(path, np.asarray(mesh.points, float), groups)


def rod_nodes(mf: MeshFile, name: str):
    """Node coordinates (k+1, 2) of a rod group ordered along the rod; BadInput if not a simple chain."""
    import numpy as np
    conn = mf.lines(name)
    ids, counts = np.unique(conn, return_counts=True)
    ends = ids[counts == 1]
    if len(ends) != 2 or counts.max() > 2 or len(ids) != len(conn) + 1:
        raise BadInput(f"mesh file {mf.path}: group {name} is not a single chain of line cells "
                       f"({len(conn)} cells, {len(ids)} nodes)")
    nxt = {}
    for i, j in conn:
        nxt.setdefault(int(i), []).append(int(j))
        nxt.setdefault(int(j), []).append(int(i))
    order, prev = [int(ends[0])], None
    while len(order) < len(ids):
        cur = order[-1]
        step = [k for k in nxt[cur] if k != prev]
        prev = cur
        order.append(step[0])
    return mf.points[order, :2]


def check(mf: MeshFile, scene: str, values: dict) -> None:
    """Check a read mesh against the scene's reference geometry for ``values`` (with the mesh's own
    element count).  Raises BadInput naming the group and the parameter that disagree."""
    import numpy as np

    from femslide.scenes.paper import CANTILEVERS, STRUCTURES
    if scene not in STRUCTURES + CANTILEVERS:
        raise BadInput(f"scene {scene} builds no beams: a mesh file does not apply")
    # the rods the scene needs (names only): a cheap build with one element
    rod_names = list(geometry(scene, values, 1).rods)
    counts = {}
    for r in rod_names:
        if f"rod:{r}" not in mf.groups or not len(mf.lines(f"rod:{r}")):
            found = ", ".join(sorted(mf.groups)) or "none"
            raise BadInput(f"mesh file {mf.path}: no line cells in group 'rod:{r}' (the scene {scene} "
                           f"needs its flexible {r} rod); groups found: {found}")
        counts[r] = mf.n_elements(r)
    if len(set(counts.values())) > 1:
        raise BadInput(f"mesh file {mf.path}: the flexible rods have different element counts {counts}; "
                       f"femslide meshes every flexible rod with the same n_elements")
    n = next(iter(counts.values()))
    geo = geometry(scene, values, n)
    tol = REL_TOL * geo.size
    params = "L" if scene.startswith("cantilever") else "a, l, L" if "L" in values else "a, l"
    for r, X in geo.rods.items():
        got = rod_nodes(mf, f"rod:{r}")
        if np.linalg.norm(got[0] - X[0]) > np.linalg.norm(got[-1] - X[0]):
            got = got[::-1]
        end_err = max(np.linalg.norm(got[0] - X[0]), np.linalg.norm(got[-1] - X[-1]))
        if end_err > tol:
            raise BadInput(f"mesh file {mf.path}: rod:{r} runs from {_pt(got[0])} to {_pt(got[-1])} m, "
                           f"but the scene parameters ({params}) put it from {_pt(X[0])} to {_pt(X[-1])} m")
        off = float(np.abs(got - X).max())
        if off > tol:
            raise BadInput(f"mesh file {mf.path}: the nodes of rod:{r} are not equally spaced on a straight "
                           f"line (off by {off:.3g} m); femslide builds uniform rods, so the mesh cannot "
                           f"be reproduced")
    for s, p in geo.supports.items():
        grp = mf.groups.get(f"support:{s}")
        if grp:
            ids = np.unique(np.concatenate([c.ravel() for _, c in grp]))
            err = float(np.abs(mf.points[ids, :2] - p).max())
            if err > tol:
                raise BadInput(f"mesh file {mf.path}: support:{s} is at {_pt(mf.points[ids[0], :2])} m, "
                               f"the scene (parameter a) puts it at {_pt(p)} m")


def _pt(p):
    return f"({p[0]:.6g}, {p[1]:.6g})"
