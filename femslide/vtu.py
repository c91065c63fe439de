"""VTU output of FE states (ParaView, pyvista): one file per static state, VTU + PVD for series.

Everything written is in SI units (m, N, N m, rad): the model's nondimensional values are multiplied
back by the reference scales of :class:`~femslide.statics.Built` (lengths by ``Lref``, forces by
``Fref``, moments by ``Fref * Lref``).  This module only reads the model and the state; it imports
meshio, never pyvista.

Mesh of a static state (deformed configuration, z = 0):

- flexible rods: one line cell per element (``part`` 0, ``rod`` = the rod's index in the model);
- the rigid body ABCD (structure scenes): one polygon cell with its own four corner points (``part``
  1, ``rod`` -1);
- rigid rods that are part of the mechanism but not meshed (the left rod AA1 of beam-slider, the right
  rod of beam-fixed, the telescopic piece of beam-extra-mass): one line cell each (``part`` 2,
  ``rod`` -1), drawn for the picture only.

Point data (defined on every point):

- ``displacement`` (u, v, 0) [m]: displacement from the undeformed position;
- ``rotation`` [rad]: counter-clockwise; on body and rigid-rod points the body rotation Theta
  (the paper's phi is -Theta);
- ``bending_moment`` [N m]: the internal bending moment M = EI dtheta/ds, s the arc length from the
  rod's first node (the ground end for the built-in scenes): M > 0 when the rod turns
  counter-clockwise as s increases.  From an element's basic end moments (M1, M2), counter-clockwise
  on the element ends, M = -M1 at its start node and M = M2 at its end node; at an interior node the
  two neighbours' values (equal at equilibrium) are averaged.  Zero on body and rigid-rod points
  (not computed there).

Cell data (defined on every cell; NaN where not computed: body and rigid rods):

- ``axial_force`` N [N]: tension positive;
- ``shear_force`` V [N] = (M1 + M2)/Ln (Ln the current chord length) = dM/ds.  With t the unit chord
  vector (start to end node) and n = t turned by +90 degrees, the material before a cut (smaller s)
  exerts on the material after it the force -N t + V n and the moment -M; the material after the
  cut exerts N t - V n and +M on the material before;
- ``part`` (int): 0 rod element, 1 body, 2 rigid rod; ``rod`` (int): rod index or -1.

Field data (also in the sidecar ``<scene>.json``): ``phi`` [rad] (structures), ``M_max`` [N m]
(largest |bending moment| of *this* mesh: the adaptive solver reports a Richardson-extrapolated
value, the file shows its finest mesh), the reactions and, for cantilevers, the tip values.
"""
from __future__ import annotations

import json
import math
import os
import xml.sax.saxutils as _sx

import numpy as np

PART_ROD, PART_BODY, PART_RIGID = 0, 1, 2
POINT_FIELDS = ("displacement", "rotation", "bending_moment")
CELL_FIELDS = ("axial_force", "shear_force", "part", "rod")


# -- static state -> mesh arrays ----------------------------------------------------------------------

def nodal_moments(qb, conn, n_nodes):
    """Bending moment at every node from the elements' basic forces (N, M1, M2): -M1 at the start node,
    M2 at the end node, averaged over the elements meeting at a node (0 at nodes without elements)."""
    acc = np.zeros(n_nodes)
    cnt = np.zeros(n_nodes)
    np.add.at(acc, conn[:, 0], -qb[:, 1])
    np.add.at(acc, conn[:, 1], qb[:, 2])
    np.add.at(cnt, conn.ravel(), 1.0)
    return np.divide(acc, cnt, out=np.zeros(n_nodes), where=cnt > 0)


def _body_height(bt):
    """Full height AD/a of the body (nondimensional), from the build or from its weight term."""
    h = getattr(bt, "body_height", None)
    if h is not None:
        return float(h)
    from .loads import BodyWeight
    for t in bt.model.terms:
        if isinstance(t, BodyWeight):
            return 2.0 * float(t.r[1])  # G = A0 + (a + d, b): the body's half height is b
    return 1.0


def mesh_data(bt, y, alpha):
    """Deformed mesh of a static state in SI units.

    Returns (points (n, 3), cells [(type, connectivity)], point_data, cell_data, field_data) in
    meshio's layout (cell data: one array per cell block).
    """
    from .body import rot
    m = bt.model
    Lr, Fr = bt.Lref, bt.Fref
    q = y[:m.n_q]
    U = m.nodal(q)
    pts, disp, rotn, mom = [], [], [], []
    blocks = []  # (type, conn, axial, shear, part, rod)

    if m.elements is not None:
        es = m.elements
        qb, _ = m.element_forces(q, alpha)
        X = m.X0 + U[:, :2]
        D = X[es.conn[:, 1]] - X[es.conn[:, 0]]
        Ln = np.hypot(D[:, 0], D[:, 1])
        pts.append(X)
        disp.append(U[:, :2])
        rotn.append(U[:, 2])
        mom.append(nodal_moments(qb, es.conn, m.n_nodes) * Fr * Lr)
        ne = es.size
        blocks.append(("line", es.conn, qb[:, 0] * Fr, (qb[:, 1] + qb[:, 2]) / Ln * Fr,
                       np.full(ne, PART_ROD), m.elem_rod.astype(int)))
        n_pts = m.n_nodes
    else:
        n_pts = 0

    def add_points(P, P0, theta):
        nonlocal n_pts
        P, P0 = np.atleast_2d(P), np.atleast_2d(P0)
        pts.append(P)
        disp.append(P - P0)
        rotn.append(np.full(len(P), theta))
        mom.append(np.zeros(len(P)))
        idx = np.arange(n_pts, n_pts + len(P))
        n_pts += len(P)
        return idx

    def add_rigid(P, P0, theta):
        idx = add_points(P, P0, theta)
        blocks.append(("line", idx[None, :], np.full(1, np.nan), np.full(1, np.nan),
                       np.full(1, PART_RIGID), np.full(1, -1)))

    body = m.body
    field = {"Lref": Lr, "Fref": Fr}
    if body is not None:
        zb = q[body.dof0:body.dof0 + 3]
        th = float(zb[2])
        R = rot(th)
        e = R @ np.array([0.0, 1.0])

        def bpoint(r):
            return body.A0 + zb[:2] + R @ np.asarray(r, float)

        h = _body_height(bt)
        corners = np.array([[0.0, 0.0], [2.0, 0.0], [2.0, h], [0.0, h]])
        P = np.array([bpoint(r) for r in corners])
        idx = add_points(P, body.A0 + corners, th)
        blocks.append(("polygon", idx[None, :], np.full(1, np.nan), np.full(1, np.nan),
                       np.full(1, PART_BODY), np.full(1, -1)))
        # rigid rods (not meshed), for the picture
        from .joints import BodyPin, GuideLine
        from .loads import RigidPieceWeight
        for c in m.constraints:
            if isinstance(c, BodyPin):       # rigid rod from the pinned body point to A
                r = np.asarray(c.r, float)
                add_rigid(np.array([bpoint(r), bpoint((0.0, 0.0))]),
                          np.array([body.A0 + r, body.A0]), th)
            elif isinstance(c, GuideLine):   # rigid rod from its ground pin along the guide
                g = np.asarray(c.ground, float)
                Lrod = float((body.A0 + c.r - g)[1])
                add_rigid(np.array([g, g + Lrod * e]), np.array([g, g + (0.0, Lrod)]), th)
        for t in m.terms:
            if isinstance(t, RigidPieceWeight):  # telescopic piece above a rod node, along the guide
                p = t.X0 + U[t.node, :2]
                add_rigid(np.array([p, p + 2.0 * t.h * e]), np.array([t.X0, t.X0 + (0.0, 2.0 * t.h)]), th)
        field["phi"] = -th

    P = np.concatenate(pts) * Lr
    points = np.column_stack([P, np.zeros(len(P))])
    d = np.concatenate(disp) * Lr
    point_data = {"displacement": np.column_stack([d, np.zeros(len(d))]),
                  "rotation": np.concatenate(rotn),
                  "bending_moment": np.concatenate(mom)}
    cells = [(b[0], np.asarray(b[1], dtype=np.int64)) for b in blocks]
    cell_data = {"axial_force": [b[2] for b in blocks], "shear_force": [b[3] for b in blocks],
                 "part": [b[4].astype(np.int32) for b in blocks], "rod": [b[5].astype(np.int32) for b in blocks]}
    rm = point_data["bending_moment"]
    field["M_max"] = float(np.abs(rm).max()) if rm.size else 0.0
    return points, cells, point_data, cell_data, field


def _summary(bt, y, alpha, scene, field):
    """Sidecar values: the contract's result values for this state (its own mesh, no extrapolation)."""
    from .statics import extract
    res = extract(bt, y, alpha)
    m = bt.model
    out = {"scene": scene, "units": "SI (m, N, N m, rad)", "Lref": bt.Lref, "Fref": bt.Fref,
           "n_elements": int(m.elements.size) if m.elements is not None else 0,
           "rods": [r.name for r in m.rods],
           "M_max": field["M_max"], "M_max_elements": res["M_max"]}
    for k in ("phi", "slide", "reactions", "tip"):
        if k in res:
            out[k] = res[k]
    out["conventions"] = {
        "bending_moment": "M = EI dtheta/ds at the nodes (-M1 at an element's start, M2 at its end)",
        "shear_force": "V = (M1 + M2)/Ln = dM/ds; material before a cut exerts -N t + V n on the material after",
        "axial_force": "N, tension positive",
        "part": "0 rod element, 1 rigid body, 2 rigid rod (not meshed)"}
    return out


def _flat_numbers(obj, prefix=""):
    """{'reactions': {'A1': {'Fx': 1}}} -> {'reactions_A1_Fx': 1.0} for the numeric leaves."""
    out = {}
    if isinstance(obj, dict):
        for k, v in obj.items():
            out.update(_flat_numbers(v, f"{prefix}{k}_"))
    elif isinstance(obj, (int, float, np.floating)) and not isinstance(obj, bool):
        out[prefix[:-1]] = float(obj)
    return out


def write_static(bt, y, alpha, out_dir, scene) -> list[str]:
    """Write ``out_dir/<scene>.vtu`` (deformed mesh, SI units) and the sidecar ``out_dir/<scene>.json``;
    return the two paths."""
    points, cells, point_data, cell_data, field = mesh_data(bt, y, alpha)
    summary = _summary(bt, y, alpha, scene, field)
    fd = {"M_max": field["M_max"], "Lref": bt.Lref, "Fref": bt.Fref}
    for k in ("phi", "slide", "reactions", "tip"):
        if k in summary:
            fd.update(_flat_numbers({k: summary[k]}))
    os.makedirs(out_dir, exist_ok=True)
    path = os.path.join(out_dir, f"{scene}.vtu")
    _write_vtu(path, points, cells, point_data, cell_data, fd)
    side = os.path.join(out_dir, f"{scene}.json")
    with open(side, "w") as fh:
        json.dump(_json_safe(summary), fh, indent=1)
    return [path, side]


def _json_safe(obj):
    if isinstance(obj, dict):
        return {k: _json_safe(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_json_safe(v) for v in obj]
    if isinstance(obj, (str, bool)) or obj is None:
        return obj
    if isinstance(obj, (int, np.integer)):
        return int(obj)
    x = float(obj)
    return x if math.isfinite(x) else None


# -- writing --------------------------------------------------------------------------------------------

def _write_vtu(path, points, cells, point_data, cell_data, field_data=None):
    """meshio's VTU writer, plus a <FieldData> block (meshio 5 reads field data from VTU but does not
    write it) holding scalar values such as phi and M_max."""
    import meshio
    meshio.Mesh(points, cells, point_data=point_data, cell_data=cell_data).write(path, file_format="vtu")
    if not field_data:
        return
    arrays = "".join(
        f'<DataArray type="Float64" Name={_sx.quoteattr(str(k))} NumberOfTuples="1" format="ascii">'
        f"{float(v)!r}</DataArray>\n" for k, v in field_data.items() if math.isfinite(float(v)))
    with open(path) as fh:
        text = fh.read()
    tag = "<UnstructuredGrid>"
    i = text.find(tag)
    if i < 0:  # unexpected layout: leave the file as meshio wrote it
        return
    i += len(tag)
    text = text[:i] + "\n<FieldData>\n" + arrays + "</FieldData>" + text[i:]
    with open(path, "w") as fh:
        fh.write(text)


def write_series(frames, out_dir, name, field_data=None) -> list[str]:
    """Write one VTU per frame (``<name>_0000.vtu``, ...) and the index ``<name>.pvd``.

    ``frames``: iterable of (time [s], points (n, 2 or 3), cells, point_data, cell_data) in meshio's
    layout (cells: [(type, connectivity)], cell data one array per cell block).  Line and polygon
    cells may be mixed (meshio's XDMF writer cannot, hence VTU + PVD).  ``field_data``: optional
    scalars written into every frame.  Returns the paths written, the .pvd last.
    """
    os.makedirs(out_dir, exist_ok=True)
    files, entries = [], []
    for k, (t, points, cells, point_data, cell_data) in enumerate(frames):
        points = np.asarray(points, float)
        if points.ndim == 2 and points.shape[1] == 2:
            points = np.column_stack([points, np.zeros(len(points))])
        fname = f"{name}_{k:04d}.vtu"
        path = os.path.join(out_dir, fname)
        _write_vtu(path, points, cells, point_data or {}, cell_data or {}, field_data)
        files.append(path)
        entries.append((float(t), fname))
    pvd = os.path.join(out_dir, f"{name}.pvd")
    with open(pvd, "w") as fh:
        fh.write('<?xml version="1.0"?>\n'
                 '<VTKFile type="Collection" version="0.1" byte_order="LittleEndian">\n<Collection>\n')
        for t, fname in entries:
            fh.write(f'<DataSet timestep="{t!r}" group="" part="0" file={_sx.quoteattr(fname)}/>\n')
        fh.write("</Collection>\n</VTKFile>\n")
    files.append(pvd)
    return files
