"""VTU output of static states (ParaView, pyvista): one file per state, VTU + PVD for series.

Everything written is in SI units (m, N, N m, rad), for any declared structure; this module only
reads the model and the state, and imports meshio, never pyvista.

Mesh of a state (z = 0), ParaView's convention: the points are the reference (undeformed)
configuration and the point data ``displacement`` leads to the deformed one, so that Warp By Vector
(scale 1) draws the deformed state once (field data ``points`` says so; mode shapes: the points are
the static equilibrium, femslide.output.files.mode_frame):

- rods: one line cell per element (``part`` 0, ``rod`` = the rod's index in the declaration, in the
  order of the ``rods`` list of the sidecar);
- bodies with an outline of 3 or more points: one polygon cell through the outline's points, moved
  rigidly with the body (``part`` 1, ``body`` = the body's index);
- bodies with a 2-point outline (rigid rods, links): one line cell (``part`` 2); a body without an
  outline: a vertex cell at its centroid (``part`` 1);
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

Cell data ``distributed_load`` (qx, qy, 0) [N/m]: the distributed load on a rod element, global
components (NaN on bodies); with it the moment inside an element is the parabola
M(xi) = (1 - xi) M_i + xi M_j - (q . n) L0^2 xi (1 - xi) / 2 (L0 the element's length, n the normal
of its deformed chord), which pictures use to draw the diagram exactly.

Field data (and the sidecar ``<name>.json``): the named results of this mesh (no extrapolation),
under the dotted names of :meth:`femslide.Result.flat` and of a time history's columns
(``rods.NAME.M_max``, ``reactions.NAME.Fx``, ...); text as VTK String arrays (ParaView and pyvista
show them as text; meshio 5 cannot read them, :func:`read` can): ``units`` (the unit of every
array), ``conventions``, ``points`` (what the points are), ``rod_names``, ``body_names``,
``joint_names`` and ``joint_type_names`` (one string per rod, body, joint, in declaration order);
one row per joint: ``joint_type`` (0 pin, 1 weld, 2 slider, 3 roller, -1 any
other registered kind: read the type from ``joint_type_names``), ``joint_ground`` (1: a support, b is
the ground), ``joint_position`` and ``joint_reference`` (x, y, 0) [m]: a's joint point now and in the reference
state, ``joint_axis`` (unit guide direction now, carried by b; zero for kinds without a guide),
``joint_force`` (Fx [N], Fy [N], M [N m]: what b exerts on a, springs included; for a support the
reaction of the ground), ``joint_inward`` (supports: unit vector from the ground into the structure:
across the guide of a slider or roller, along a rod clamped to the ground (a weld), else +y (-y when
the structure's centre lies clearly below the support: a hanging structure);
pictures draw the ground on the other side and call a reaction along -inward a lift-off).
Series frames add their time ``time`` [s] and the run's global values at that time.
"""
from __future__ import annotations

import json
import math
import os

import numpy as np

from femslide.errors import BadInput
from femslide.joints.kinds import kind_of

PART_ROD, PART_BODY, PART_RIGID = 0, 1, 2
REFERENCE_POINTS = ("reference: the points are the undeformed structure; points + displacement is the "
                    "deformed state (ParaView: Warp By Vector with displacement, scale 1)")
POINT_FIELDS = ("displacement", "rotation", "bending_moment", "axial_force", "shear_force")
CELL_FIELDS = ("axial_force", "shear_force", "distributed_load", "part", "rod", "body")
UNITS = ("displacement: m; rotation: rad; bending_moment: N m; axial_force: N; shear_force: N; "
         "distributed_load: N/m; joint_position, joint_reference: m; joint_force: N, N, N m (Fx, Fy, M); "
         "time: s; Lref: m; Fref: N; *.M, *M_max: N m; *.Fx, *.Fy, *.N_max, *.V_max: N; "
         "*.x, *.y, *.u, *.v, *.slide: m; *.theta, *.rotation, phi: rad")
CONVENTIONS_TEXT = ("SI units; x right, y up, z = 0; rotations and moments counter-clockwise positive; "
                    "along a rod s is the arc length from its start, t the tangent, n = t turned by +90 deg; "
                    "at a cut the part beyond exerts on the part before the force N t - V n and the moment M: "
                    "N > 0 tension, M = EI dtheta/ds (M > 0: the rod turns counter-clockwise as s grows, "
                    "the fibre on the -n side is in tension), dM/ds = V; joint forces: what part b exerts "
                    "on part a; reactions: forces of the ground on the structure")
CONVENTIONS = {
    "units": "SI (m, N, N m, rad)",
    "rotation": "counter-clockwise positive",
    "bending_moment": "M = EI dtheta/ds at the nodes, s from the rod's start",
    "forces": "at a cut the part beyond exerts N t - V n and the moment M on the part before; dM/ds = V",
    "axial_force": "N, tension positive",
    "part": "0 rod element, 1 body polygon, 2 rigid link (2-point outline)",
    "reactions": "forces and moments of the ground on the structure",
    "text": CONVENTIONS_TEXT,
}


def mesh_data(model, y, alpha, arrays=None, cuts=None):
    """Mesh of a static state in SI units: the reference points and the state's ``displacement``.

    Returns (points (n, 3), cells [(type, connectivity)], point_data, cell_data) in meshio's layout
    (cell data: one array per cell block); points + ``displacement`` is the deformed state.
    ``arrays``, ``cuts``: the state's rod arrays and
    ``end_moments(..., resultant=True)`` if already computed (a solution level has both)."""
    from femslide.results.static import end_moments, rod_arrays
    L, F = model.Lref, model.Fref
    q = y[:model.n_q]
    if cuts is None and model.elements is not None:
        cuts = end_moments(model, y, resultant=True)
    arrays = rod_arrays(model, y, alpha, cuts) if arrays is None else arrays
    pts, disp, rotn, mom, Np, Vp = [], [], [], [], [], []
    blocks = []  # (type, conn, N, V, part, rod, body)
    n_pts = 0
    if model.elements is not None:
        es = model.elements
        U = model.nodal(q)
        X = (model.X0 + U[:, :2]) * L
        pts.append(model.X0 * L)
        disp.append(U[:, :2] * L)
        rotn.append(U[:, 2])
        for rod in model.structure.rods:
            a = arrays[rod.name]
            mom.append(a["M"])
            Np.append(a["N"])
            Vp.append(a["V"])
        # cell values from the same equilibrium recovery as the point values (results.end_moments):
        # the cut force at the element's middle in its chord frame, N = G . t, V = -G . n
        G = cuts[1]
        D = X[es.conn[:, 1]] - X[es.conn[:, 0]]
        t = D / np.hypot(D[:, 0], D[:, 1])[:, None]
        Nc = (G[:, 0] * t[:, 0] + G[:, 1] * t[:, 1]) * F
        Vc = -(G[:, 1] * t[:, 0] - G[:, 0] * t[:, 1]) * F
        ne = es.size
        blocks.append(("line", es.conn, Nc, Vc,
                       np.full(ne, PART_ROD), model.elem_rod.astype(int), np.full(ne, -1),
                       np.asarray(model.elem_q, float).reshape(ne, 2) * (F / L)))
        n_pts = model.n_nodes
    for i, b in enumerate(model.structure.bodies):
        th = float(q[model.body_dof(b.name) + 2])
        P0 = np.asarray(b.outline or [b.centroid], float)   # (without an outline: its centroid, a vertex)
        P = model.body_point(b.name, q, P0)
        k = len(P)
        pts.append(P0)
        disp.append(P - P0)
        rotn.append(np.full(k, th))
        for lst in (mom, Np, Vp):
            lst.append(np.zeros(k))
        idx = np.arange(n_pts, n_pts + k)
        n_pts += k
        kind, part = ("polygon", PART_BODY) if k >= 3 else (("line", PART_RIGID) if k == 2 else ("vertex", PART_BODY))
        blocks.append((kind, idx[None, :], np.full(1, np.nan), np.full(1, np.nan), np.full(1, part),
                       np.full(1, -1), np.full(1, i), np.full((1, 2), np.nan)))
        for at, jname in (_off_outline_points(model.structure, b) if b.outline else ()):
            j = int(np.argmin(np.hypot(*(P0 - at).T)))
            if jname is None:
                pa, at0 = model.body_point(b.name, q, at), at
            else:
                # a rod end that slides in a guide of this body off its outline (the paper's
                # telescopic piece of a shortened rod): the link reaches the rod end's point now
                link = model.joint[jname]
                z = q[link.dofs]
                pa = link.point_a(z)[0] * L
                at0 = link.point_a(np.zeros_like(z))[0] * L
            pts.append(np.asarray(at0, float)[None, :])
            disp.append((pa - at0)[None, :])
            rotn.append(np.full(1, th))
            for lst in (mom, Np, Vp):
                lst.append(np.zeros(1))
            blocks.append(("line", np.array([[idx[j], n_pts]]), np.full(1, np.nan), np.full(1, np.nan),
                           np.full(1, PART_RIGID), np.full(1, -1), np.full(1, i), np.full((1, 2), np.nan)))
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
                 "body": [bl[6].astype(np.int32) for bl in blocks],
                 "distributed_load": [np.column_stack([bl[7], np.zeros(len(bl[7]))]) for bl in blocks]}
    return points, cells, point_data, cell_data


def _off_outline_points(fs, body):
    """Joint points of the body that are neither an outline vertex nor inside its outline polygon:
    [(reference point, name of a slider or roller whose rod end a slides in a guide of this body, or
    None)]."""
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
        guide = (kind_of(j.type).guide and rb.kind == "body" and rb.name == body.name
                 and ra.kind == "rod_end")
        if guide:
            out.append((at, j.name))
        elif not any(np.allclose(at, o) for o, _ in out):
            out.append((at, None))
    return out


def joint_data(model, y) -> dict:
    """Field data of the joints of a state (SI units; see the module docstring)."""
    fs = model.structure
    L, F = model.Lref, model.Fref
    q = y[:model.n_q]
    U = model.nodal(q) if model.n_nodes else np.zeros((0, 3))
    n = len(fs.joints)
    pos, ref, axis, force, inward = (np.zeros((n, 3)) for _ in range(5))
    types, ground = np.zeros(n, np.int32), np.zeros(n, np.int32)
    geo = [p for r in fs.rods for p in (r.start, r.end)] + [p for b in fs.bodies for p in (b.outline or ())]
    geo += [b.centroid for b in fs.bodies if b.centroid is not None]
    centre = np.mean(np.asarray(geo, float), axis=0) if geo else np.zeros(2)
    from femslide.results.static import joint_forces
    for i, j in enumerate(fs.joints):
        ra, rb = fs.refs[j.name]
        link = model.joint[j.name]
        z = q[link.dofs]
        pos[i, :2] = link.point_a(z)[0] * L
        ref[i, :2] = link.point_a(np.zeros_like(z))[0] * L
        types[i] = link.joint_kind.code
        try:
            fx, fy, m = joint_forces(model, y, j.name)
            force[i] = (fx * F, fy * F, m * F * L)
        except (ValueError, IndexError):
            force[i] = np.nan
        thb = 0.0
        if rb.kind == "body":
            thb = float(q[model.body_dof(rb.name) + 2])
        elif rb.kind == "rod_end":
            thb = float(U[model.node(rb.name, rb.end), 2])
        if j.axis is not None:
            c, s_ = np.cos(thb), np.sin(thb)
            axis[i, :2] = (c * j.axis[0] - s_ * j.axis[1], s_ * j.axis[0] + c * j.axis[1])
        if rb.kind == "ground":
            ground[i] = 1
            d = centre - ref[i, :2]
            if j.axis is not None:
                w = np.array([-j.axis[1], j.axis[0]])
                sgn = np.sign(w @ d) or (np.sign(w[1]) or np.sign(w[0]))
                inward[i, :2] = sgn * w
            elif ra.kind == "rod_end" and link.joint_kind.symbol == "clamp":   # drawn across the rod
                r = fs.rod(ra.name)
                t = np.subtract(r.end, r.start) / r.length
                inward[i, :2] = t if ra.end == 0 else -t
            else:   # the ground below the structure (above it when the structure hangs from the support)
                inward[i, 1] = -1.0 if d[1] < -0.1 * abs(d[0]) else 1.0
    return {"joint_names": [j.name for j in fs.joints],
            "joint_type_names": [j.type for j in fs.joints], "joint_type": types, "joint_ground": ground,
            "joint_position": pos, "joint_reference": ref, "joint_axis": axis, "joint_force": force,
            "joint_inward": inward}


def load_data(model, y) -> dict:
    """Field data of the point loads (dead loads of type force, SI units): ``load_names``,
    ``load_position`` and ``load_reference`` (x, y, 0) [m] (the point of application now and in the
    reference state) and ``load_force`` (Fx [N], Fy [N], M [N m]); empty without point loads (the
    distributed loads are the cell data ``distributed_load``)."""
    fs = model.structure
    L = model.Lref
    q = y[:model.n_q]
    names, pos, ref, force = [], [], [], []
    for ld in fs.loads:
        if ld.type != "force":
            continue
        r, _ = fs.refs[ld.name]
        if r.kind == "rod":     # inside a rod: its node at the arc length s
            nd = model.node_at(r.name, ld.s)
            at0 = model.X0[nd] * L
            at = (model.X0[nd] + model.nodal(q)[nd, :2]) * L
        else:
            at0 = np.asarray(ld.at, float)
        if r.kind == "body":
            at = model.body_point(r.name, q, at0)
        elif r.kind == "rod_end":
            nd = model.node(r.name, r.end)
            at = (model.X0[nd] + model.nodal(q)[nd, :2]) * L
        names.append(ld.name)
        pos.append((at[0], at[1], 0.0))
        ref.append((at0[0], at0[1], 0.0))
        force.append((ld.force[0], ld.force[1], ld.moment))
    if not names:
        return {}
    return {"load_names": names, "load_position": np.array(pos), "load_reference": np.array(ref),
            "load_force": np.array(force)}


def describe(model) -> dict:
    """Text field data of every VTU: units, conventions, names of the rods and bodies."""
    fs = model.structure
    return {"units": UNITS, "conventions": CONVENTIONS_TEXT, "points": REFERENCE_POINTS,
            "rod_names": [r.name for r in fs.rods], "body_names": [b.name for b in fs.bodies]}


def text(field_data, name, default=None):
    """A text field of a VTU read back, as one string (the entries of a list joined by new lines):
    from :func:`read` (str or list of str), from pyvista (an array of str) or from a file of an
    earlier femslide (UTF-8 bytes in a UInt8 array)."""
    if name not in field_data:
        return default
    v = field_data[name]
    if isinstance(v, str):
        return v
    a = np.asarray(v).ravel()
    if a.dtype.kind in "USO":
        return "\n".join(str(x) for x in a)
    return bytes(a.astype(np.uint8).tolist()).decode("utf-8")


def reference_points(field_data) -> bool:
    """True if a VTU's points are its reference (undeformed) configuration and ``displacement`` leads
    to the deformed one (every file of this femslide); False for files of femslide <= 0.x that stored
    the deformed points (then points - displacement is the reference)."""
    return "points" in field_data


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


def _flat_numbers(obj):
    """{'reactions': {'A1': {'Fx': 1}}} -> {'reactions.A1.Fx': 1.0} for the numeric leaves: the dotted
    names of a result's :meth:`~femslide.app.result.Result.flat` and of a time history's columns."""
    from femslide.results.outcome import dotted
    return {k: float(v) for k, v in dotted(obj).items()
            if isinstance(v, (int, float, np.floating, np.integer)) and not isinstance(v, bool)}


def write_static(sol, out_dir, name, extra=None) -> list[str]:
    """Write ``out_dir/<name>.vtu`` (the finest mesh's deformed state, SI units) and the sidecar
    ``out_dir/<name>.json`` (that mesh's named results, conventions, ``extra`` values such as a
    scene's section 7 results); return the two paths."""
    lv = sol.level
    model = lv.model
    points, cells, point_data, cell_data = mesh_data(model, lv.y, lv.alpha, lv.arrays, lv.cuts)
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
    fd.update(describe(model))
    fd.update(joint_data(model, lv.y))
    fd.update(load_data(model, lv.y))
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
    write it) holding scalar values such as phi and M_max (Float64), arrays (rows x components,
    Float64 or Int32) and text: a str or a list of str as a VTK String array (what VTK's own
    vtkXMLWriter writes for a vtkStringArray: each string's bytes, signed, each ended by a 0; ParaView
    and pyvista show it as text; meshio 5 cannot read it, :func:`read` can)."""
    import meshio
    if not any(len(c[1]) for c in cells):
        # nothing to draw as cells (bodies without an outline and no rods): the points as vertices
        # and the field data (meshio can neither write cell data without cells nor read a VTU
        # without cells)
        import numpy as np
        cells = [("vertex", np.arange(len(points)).reshape(-1, 1))] if len(points) else []
        cell_data = {}
    meshio.Mesh(points, cells, point_data=point_data, cell_data=cell_data).write(path, file_format="vtu")
    if not field_data:
        return
    arrays = "".join(_field_array(k, v) for k, v in field_data.items())
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


def _quoteattr(text: str) -> str:
    """``text`` as a quoted XML attribute value: xml.sax.saxutils.quoteattr's result, without that
    module's import (it imports urllib.request, http, email and ssl: ~50 ms and a few MB in a run
    that writes no file)."""
    text = text.replace("&", "&amp;").replace(">", "&gt;").replace("<", "&lt;")
    text = text.replace("\n", "&#10;").replace("\r", "&#13;").replace("\t", "&#9;")
    if '"' not in text:
        return f'"{text}"'
    if "'" not in text:
        return f"'{text}'"
    return '"%s"' % text.replace('"', "&quot;")


def _field_array(name, v):
    """One <DataArray> of the <FieldData> block ('' for a non-finite scalar)."""
    qn = _quoteattr(str(name))
    if isinstance(v, str) or (isinstance(v, (list, tuple)) and all(isinstance(x, str) for x in v) and v):
        items = [v] if isinstance(v, str) else list(v)
        codes = []
        for x in items:   # VTK writes the bytes as signed chars
            codes += [c - 256 if c > 127 else c for c in x.encode("utf-8")] + [0]
        return (f'<Array type="String" Name={qn} NumberOfTuples="{len(items)}" format="ascii">'
                f'{" ".join(map(str, codes))}</Array>\n')
    if isinstance(v, (list, tuple)) and not v:
        return ""
    a = np.asarray(v)
    if a.ndim == 0:
        x = float(a)
        return (f'<DataArray type="Float64" Name={qn} NumberOfTuples="1" format="ascii">{x!r}</DataArray>\n'
                if math.isfinite(x) else "")
    a = a.reshape(len(a), -1)
    if a.shape[0] == 0:
        return ""
    integer = np.issubdtype(a.dtype, np.integer)
    kind = "Int32" if integer else "Float64"
    body = " ".join(str(int(x)) if integer else repr(float(x)) for x in a.ravel())
    return (f'<DataArray type="{kind}" Name={qn} NumberOfTuples="{a.shape[0]}" '
            f'NumberOfComponents="{a.shape[1]}" format="ascii">{body}</DataArray>\n')


def write_series(frames, out_dir, name, field_data=None) -> list[str]:
    """Write one VTU per frame (``<name>_0000.vtu``, ...) and the index ``<name>.pvd``.

    ``frames``: iterable of (time [s], points (n, 2 or 3), cells, point_data, cell_data) in meshio's
    layout (cells: [(type, connectivity)], cell data one array per cell block).  Line and polygon
    cells may be mixed (meshio's XDMF writer cannot, hence VTU + PVD).  ``field_data``: optional
    values written into every frame (see :func:`_write_vtu`); a frame may carry a sixth item, its own
    field data (e.g. the global values at its time).  Every frame gets its ``time`` [s], ``units`` and
    ``conventions``.  Returns the paths written, the .pvd last.
    """
    os.makedirs(out_dir, exist_ok=True)
    files, entries = [], []
    for k, frame in enumerate(frames):
        t, points, cells, point_data, cell_data = frame[:5]
        fd = {"units": UNITS, "conventions": CONVENTIONS_TEXT, "time": float(t), **(field_data or {}),
              **(frame[5] if len(frame) > 5 and frame[5] else {})}
        points = np.asarray(points, float)
        if points.ndim == 2 and points.shape[1] == 2:
            points = np.column_stack([points, np.zeros(len(points))])
        fname = f"{name}_{k:04d}.vtu"
        path = os.path.join(out_dir, fname)
        _write_vtu(path, points, cells, point_data or {}, cell_data or {}, fd)
        files.append(path)
        entries.append((float(t), fname))
    files.append(write_pvd(os.path.join(out_dir, f"{name}.pvd"), entries))
    return files


def write_pvd(path, entries) -> str:
    """A PVD collection: [(timestep, file name relative to the PVD)] in order; returns its path.
    ParaView steps through the files by their timestep (a time, or a mode's number)."""
    with open(path, "w") as fh:
        fh.write('<?xml version="1.0"?>\n'
                 '<VTKFile type="Collection" version="0.1" byte_order="LittleEndian">\n<Collection>\n')
        for t, fname in entries:
            fh.write(f'<DataSet timestep="{t!r}" group="" part="0" file={_quoteattr(fname)}/>\n')
        fh.write("</Collection>\n</VTKFile>\n")
    return path


# -- reading back what is written here ------------------------------------------------------------------

def pvd_frames(path):
    """[(time, vtu path)] of a PVD collection, in file order."""
    import xml.etree.ElementTree as ET
    try:
        root = ET.parse(path).getroot()
    except (ET.ParseError, OSError) as exc:
        raise BadInput(f"{path}: not a readable PVD file: {exc}") from None
    base = os.path.dirname(os.path.abspath(path))
    out = []
    for ds in root.iter("DataSet"):
        f = ds.get("file")
        if f:
            out.append((float(ds.get("timestep", "nan")), os.path.join(base, f)))
    if not out:
        raise BadInput(f"{path}: the PVD collection lists no data sets")
    return out


def pick_file(path, frame=None):
    """The VTU to draw: ``path`` itself, or frame ``frame`` (default: the last) of a PVD."""
    if not os.path.isfile(path):
        raise BadInput(f"result file {path} not found")
    ext = os.path.splitext(path)[1].lower()
    if ext == ".pvd":
        frames = pvd_frames(path)
        k = len(frames) - 1 if frame is None else frame
        if not -len(frames) <= k < len(frames):
            raise BadInput(f"--frame {frame}: {path} has {len(frames)} frames; allowed 0 ... {len(frames) - 1}")
        t, f = frames[k]
        if not os.path.isfile(f):
            raise BadInput(f"{path}: frame {k} file {f} not found")
        return f, t
    if frame is not None:
        raise BadInput("--frame applies to a .pvd series only")
    if ext != ".vtu":
        raise BadInput(f"{path}: expected a .vtu or .pvd file")
    return path, None


def read(path: str):
    """A VTU written by femslide as a ``meshio.Mesh`` whose text field data are Python strings (a
    list of str for a list; see :func:`text`).  meshio 5 cannot read VTK String arrays (meshio issue
    1370): they are taken out of the XML here and the rest is read by meshio."""
    return read_meshio(path, "result file")


def _strings(path):
    """(text of the file without its String arrays or None when it has none, {name: str or [str]})."""
    with open(path, "rb") as fh:
        raw = fh.read()
    if b'type="String"' not in raw:
        return None, {}
    import xml.etree.ElementTree as ET
    root = ET.fromstring(raw)
    found = {}
    for parent in root.iter():
        for c in list(parent):
            if c.get("type") == "String":
                codes = [int(x) % 256 for x in (c.text or "").split()]
                items = bytes(codes).split(b"\0")[:int(c.get("NumberOfTuples", "1"))]
                items = [b.decode("utf-8") for b in items]
                found[c.get("Name")] = items[0] if len(items) == 1 and c.get("Name") in SINGLE_TEXT else items
                parent.remove(c)
    return ET.tostring(root, encoding="unicode"), found


SINGLE_TEXT = ("units", "conventions", "points")   # text fields of one string; the others are lists


def read_meshio(path: str, what: str = "mesh file"):
    """meshio.read(path) (String arrays read by :func:`read`'s rules), or BadInput naming the file.
    meshio reports some unreadable files by printing a line and calling sys.exit(1) (meshio 5: a
    corrupt .vtu), which is caught here too."""
    import contextlib
    import io
    import tempfile
    import xml.etree.ElementTree as ET

    import meshio
    err = io.StringIO()
    try:
        strings = {}
        if path.lower().endswith(".vtu"):
            try:
                stripped, strings = _strings(path)
            except (ET.ParseError, UnicodeDecodeError, ValueError):
                stripped = None   # meshio says what is wrong with it
            if stripped is not None:
                with tempfile.TemporaryDirectory() as tmp:
                    tmp_path = os.path.join(tmp, "stripped.vtu")
                    with open(tmp_path, "w", encoding="utf-8") as fh:
                        fh.write(stripped)
                    with contextlib.redirect_stdout(err), contextlib.redirect_stderr(err):
                        mesh = meshio.read(tmp_path)
                mesh.field_data.update(strings)
                return mesh
        with contextlib.redirect_stdout(err), contextlib.redirect_stderr(err):
            return meshio.read(path)
    except (Exception, SystemExit) as exc:
        detail = err.getvalue().strip().splitlines()
        why = (str(exc) if not isinstance(exc, SystemExit) else "") or (detail[-1] if detail else "")
        why = why.replace("Error: ", "")
        raise BadInput(f"{what} {path}: cannot be read ({why or type(exc).__name__}); allowed: a "
                       f"readable mesh file in a meshio format (.vtu, .msh, .xdmf, ...)") from None
