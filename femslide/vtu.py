"""VTU output of static states (ParaView, pyvista): one file per state, VTU + PVD for series.

Everything written is in SI units (m, N, N m, rad), for any declared structure; this module only
reads the model and the state, and imports meshio, never pyvista.

Mesh of a static state (deformed configuration, z = 0):

- rods: one line cell per element (``part`` 0, ``rod`` = the rod's index in the declaration, in the
  order of the ``rods`` list of the sidecar);
- bodies with an outline of 3 or more points: one polygon cell through the outline's points, moved
  rigidly with the body (``part`` 1, ``body`` = the body's index);
- bodies with a 2-point outline (rigid rods, links): one line cell (``part`` 2);
- a body's links to its joint points that lie off its outline (e.g. a rigid rod that is part of the
  body and ends in a ground pin): one line cell from the nearest outline point (``part`` 2).

Point data (defined on every point):

- ``displacement`` (u, v, 0) [m]: displacement from the undeformed position;
- ``rotation`` [rad]: counter-clockwise; on body points the body's rotation;
- ``bending_moment`` [N m]: M = EI dtheta/ds at the rod nodes, s the arc length from the rod's
  ``start`` (M > 0 where the rod turns counter-clockwise as s grows), averaged over the two elements
  at an interior node; zero on body points;
- ``axial_force`` N [N] (tension > 0) and ``shear_force`` V [N] at the rod nodes: the part beyond a
  cut exerts on the part before it the force N t - V n and the moment M (t the rod's tangent, n = t
  turned by +90 degrees), so that dM/ds = V; zero on body points.

Cell data (one value per cell): ``axial_force`` and ``shear_force`` at the element's middle [N]
(NaN on bodies), ``part`` (0 rod element, 1 body polygon, 2 rigid link), ``rod`` (rod index or -1),
``body`` (body index or -1).

Field data (and the sidecar ``<name>.json``): the named results of this mesh (no extrapolation),
flattened as ``rods_NAME_M_max``, ``joints_NAME_Fx``, ..., the units and the conventions.
"""
from __future__ import annotations

import json
import math
import os
import xml.sax.saxutils as _sx

import numpy as np

PART_ROD, PART_BODY, PART_RIGID = 0, 1, 2
POINT_FIELDS = ("displacement", "rotation", "bending_moment", "axial_force", "shear_force")
CELL_FIELDS = ("axial_force", "shear_force", "part", "rod", "body")
CONVENTIONS = {
    "units": "SI (m, N, N m, rad)",
    "rotation": "counter-clockwise positive",
    "bending_moment": "M = EI dtheta/ds at the nodes, s from the rod's start",
    "forces": "at a cut the part beyond exerts N t - V n and the moment M on the part before; dM/ds = V",
    "axial_force": "N, tension positive",
    "part": "0 rod element, 1 body polygon, 2 rigid link (2-point outline)",
    "reactions": "forces and moments of the ground on the structure",
}


def mesh_data(model, y, alpha, arrays=None):
    """Deformed mesh of a static state in SI units.

    Returns (points (n, 3), cells [(type, connectivity)], point_data, cell_data) in meshio's layout
    (cell data: one array per cell block)."""
    from .results import rod_arrays
    L, F = model.Lref, model.Fref
    q = y[:model.n_q]
    arrays = rod_arrays(model, y, alpha) if arrays is None else arrays
    pts, disp, rotn, mom, Np, Vp = [], [], [], [], [], []
    blocks = []  # (type, conn, N, V, part, rod, body)
    n_pts = 0
    if model.elements is not None:
        es = model.elements
        qb, _ = model.element_forces(q, alpha)
        U = model.nodal(q)
        X = (model.X0 + U[:, :2]) * L
        pts.append(X)
        disp.append(U[:, :2] * L)
        rotn.append(U[:, 2])
        for rod in model.structure.rods:
            a = arrays[rod.name]
            mom.append(a["M"])
            Np.append(a["N"])
            Vp.append(a["V"])
        D = X[es.conn[:, 1]] - X[es.conn[:, 0]]
        Ln = np.hypot(D[:, 0], D[:, 1]) / L
        ne = es.size
        blocks.append(("line", es.conn, qb[:, 0] * F, (qb[:, 1] + qb[:, 2]) / Ln * F,
                       np.full(ne, PART_ROD), model.elem_rod.astype(int), np.full(ne, -1)))
        n_pts = model.n_nodes
    for i, b in enumerate(model.structure.bodies):
        if not b.outline:
            continue
        th = float(q[model.body_dof(b.name) + 2])
        P0 = np.asarray(b.outline, float)
        P = model.body_point(b.name, q, P0)
        k = len(P)
        pts.append(P)
        disp.append(P - P0)
        rotn.append(np.full(k, th))
        for lst in (mom, Np, Vp):
            lst.append(np.zeros(k))
        idx = np.arange(n_pts, n_pts + k)
        n_pts += k
        kind, part = ("polygon", PART_BODY) if k >= 3 else ("line", PART_RIGID)
        blocks.append((kind, idx[None, :], np.full(1, np.nan), np.full(1, np.nan), np.full(1, part),
                       np.full(1, -1), np.full(1, i)))
        for at in _off_outline_points(model.structure, b):
            j = int(np.argmin(np.hypot(*(P0 - at).T)))
            pa = model.body_point(b.name, q, at)
            pts.append(pa[None, :])
            disp.append((pa - at)[None, :])
            rotn.append(np.full(1, th))
            for lst in (mom, Np, Vp):
                lst.append(np.zeros(1))
            blocks.append(("line", np.array([[idx[j], n_pts]]), np.full(1, np.nan), np.full(1, np.nan),
                           np.full(1, PART_RIGID), np.full(1, -1), np.full(1, i)))
            n_pts += 1
    if not pts:
        pts, disp, rotn = [np.zeros((0, 2))], [np.zeros((0, 2))], [np.zeros(0)]
        mom = Np = Vp = [np.zeros(0)]
    P = np.concatenate(pts)
    points = np.column_stack([P, np.zeros(len(P))])
    dd = np.concatenate(disp)
    point_data = {"displacement": np.column_stack([dd, np.zeros(len(dd))]), "rotation": np.concatenate(rotn),
                  "bending_moment": np.concatenate(mom), "axial_force": np.concatenate(Np),
                  "shear_force": np.concatenate(Vp)}
    cells = [(bl[0], np.asarray(bl[1], dtype=np.int64)) for bl in blocks]
    cell_data = {"axial_force": [bl[2] for bl in blocks], "shear_force": [bl[3] for bl in blocks],
                 "part": [bl[4].astype(np.int32) for bl in blocks], "rod": [bl[5].astype(np.int32) for bl in blocks],
                 "body": [bl[6].astype(np.int32) for bl in blocks]}
    return points, cells, point_data, cell_data


def _off_outline_points(fs, body):
    """Joint points of the body that are neither an outline vertex nor inside its outline polygon."""
    P = np.asarray(body.outline, float)
    out = []
    for j in fs.joints:
        ra, rb = fs.refs[j.name]
        if body.name not in (ra.name if ra.kind == "body" else None, rb.name if rb.kind == "body" else None):
            continue
        at = np.asarray(j.at, float)
        scale = max(1.0, float(np.abs(P).max()))
        if np.hypot(*(P - at).T).min() <= 1e-9 * scale or (len(P) >= 3 and _inside(P, at)):
            continue
        if not any(np.allclose(at, o) for o in out):
            out.append(at)
    return out


def _inside(P, p):
    """Point in polygon (even-odd rule; points on an edge count as inside)."""
    x, y = p
    inside = False
    n = len(P)
    for i in range(n):
        (x0, y0), (x1, y1) = P[i], P[(i + 1) % n]
        cross = (x1 - x0) * (y - y0) - (y1 - y0) * (x - x0)
        if abs(cross) <= 1e-12 * (1 + abs(x) + abs(y)) and min(x0, x1) - 1e-12 <= x <= max(x0, x1) + 1e-12 \
                and min(y0, y1) - 1e-12 <= y <= max(y0, y1) + 1e-12:
            return True
        if (y0 > y) != (y1 > y) and x < x0 + (y - y0) * (x1 - x0) / (y1 - y0):
            inside = not inside
    return inside


def _flat_numbers(obj, prefix=""):
    """{'reactions': {'A1': {'Fx': 1}}} -> {'reactions_A1_Fx': 1.0} for the numeric leaves."""
    out = {}
    if isinstance(obj, dict):
        for k, v in obj.items():
            out.update(_flat_numbers(v, f"{prefix}{k}_"))
    elif isinstance(obj, (int, float, np.floating)) and not isinstance(obj, bool):
        out[prefix[:-1]] = float(obj)
    return out


def write_static(sol, out_dir, name, extra=None) -> list[str]:
    """Write ``out_dir/<name>.vtu`` (the finest mesh's deformed state, SI units) and the sidecar
    ``out_dir/<name>.json`` (that mesh's named results, conventions, ``extra`` values such as a
    scene's section 7 results); return the two paths."""
    lv = sol.level
    model = lv.model
    points, cells, point_data, cell_data = mesh_data(model, lv.y, lv.alpha, lv.arrays)
    res = lv.res
    summary = {"name": name, "units": CONVENTIONS["units"], "Lref": model.Lref, "Fref": model.Fref,
               "n_elements": int(model.elements.size) if model.elements is not None else 0,
               "rod_elements": {r.name: int(n.size - 1) for r, n in zip(model.structure.rods, model.rod_nodes)},
               "rods": [r.name for r in model.structure.rods], "bodies": [b.name for b in model.structure.bodies],
               "results_of_this_mesh": res, "conventions": CONVENTIONS}
    if extra:
        summary.update(extra)
    fd = {"Lref": model.Lref, "Fref": model.Fref}
    fd.update(_flat_numbers({k: res[k] for k in ("M_max", "rods", "bodies", "joints", "reactions")}))
    if extra:
        fd.update(_flat_numbers(extra))
    os.makedirs(out_dir, exist_ok=True)
    path = os.path.join(out_dir, f"{name}.vtu")
    _write_vtu(path, points, cells, point_data, cell_data, fd)
    side = os.path.join(out_dir, f"{name}.json")
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
