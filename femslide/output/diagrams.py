"""Engineering diagrams of a static state: M, V or N along every rod, drawn on the deformed structure.

``femslide.plot(result, diagram="M")`` draws with matplotlib (imported when called): the rods in their
deformed shape (displacements times ``magnify``; the undeformed shape in thin grey), the bodies as
their outline polygons, the supports by joint type, the guides of sliders along their axis, the
ground line, and for every rod the diagram as a filled polygon offset from the rod along its normal,
its extreme values labelled with units.  ``femslide show RESULT.vtu --diagram M`` draws the same
geometry with pyvista (:mod:`femslide.output.show` uses :func:`frame_data` and :func:`shapes` from here).

Sign conventions (SI units; x right, y up; along a rod s is the arc length from its ``start``,
t the tangent and n = t turned by +90 degrees, i.e. n points to the left when walking from start to
end; at a cut the part beyond exerts on the part before the force N t - V n and the moment M):

- **M** (bending moment, N m, M = EI dtheta/ds) is drawn on the **tension side**: a positive M at
  P - k M n, i.e. to the right of the walking direction.  Declaring the rod the other way round
  (start and end swapped) flips the sign of M at every point together with n, so the diagram stays
  on the same side in space, the side whose fibres are stretched (a cantilever under a downward tip
  load: above the rod, hogging; a simply supported beam under a downward load: below, sagging); only
  the signs of the labels change.
- **V** (shear force, N) and **N** (axial force, N, tension > 0) keep their values when the rod is
  declared the other way round (at a cut, the force -(N t - V n) that the part before exerts on the
  part beyond reads N t' - V n' with t' = -t, n' = -n).  They are drawn at P + k V n and P + k N n:
  positive values to the left of the walking direction, so swapping start and end moves their
  diagrams to the other side of the rod in space (the labels carry the signed values).

One scale k for all rods: by default the largest |value| is drawn at 15 % of the structure's size;
``scale`` gives k in m per unit of the diagram (m per N m for M, m per N for V and N).

Joints are drawn by the ``symbol`` of their kind (:mod:`femslide.joints.kind`), not by their type
name, so that a new kind of joint needs no drawing code: supports (joints whose part b is the
ground) are drawn on the side of the ground - "hinge" (a pin) as a triangle on a hatched line,
"roller" as a triangle on a line parallel to its guide, "clamp" (a weld) as a hatched wall,
"sleeve" (a slider) as a sleeve along its guide; between parts a hinge is a small circle, a roller
a disc on its guide, a sleeve a sleeve along it and a clamp nothing; any other symbol (or a type
this process does not know, read from a file) is a plain diamond marker.  Hinges, rollers and
sleeves on the ground are taken as resting on it: a reaction that pulls the structure towards the
ground (its component along the direction from the ground into the structure is negative: a real
support resting on the ground would lift off) is reported by a :class:`LiftOffWarning` and a red
note on the figure.  Clamps are taken as anchored, other symbols are not checked.  When all
supports stand on level ground, a structure that reaches more than 5 % of its size below their
level (the paper's structure falling over at a tiny EI; not a beam sagging between its supports) is
reported by a :class:`BelowGroundWarning` and a note: the model has no contact with the ground.
"""
from __future__ import annotations

import math
import os
import warnings

# numpy and matplotlib are imported inside the functions: `import femslide` (which exports plot) stays
# light for the command line's fast paths
from femslide.errors import BadInput
from femslide.joints.kinds import KINDS, name_of_code
from femslide.output.arrows import size_of

DIAGRAMS = {"M": ("bending_moment", "N m", "bending moment M"),
            "V": ("shear_force", "N", "shear force V"),
            "N": ("axial_force", "N", "axial force N")}
SIDE = {"M": -1.0, "V": 1.0, "N": 1.0}   # the diagram lies at P + SIDE * k * value * n
COLOURS = {"M": "tab:red", "V": "tab:green", "N": "tab:blue"}
SCALE_FRACTION = 0.15      # auto scale: the largest |value| is drawn this fraction of the structure's size
SYMBOL_FRACTION = 0.035    # supports: symbol size as a fraction of the structure's size
LIFT_OFF_RTOL = 1e-6       # a pull below this fraction of the largest reaction is round-off
BELOW_GROUND_FRACTION = 0.05   # a structure this far (fraction of its size) below its supports' level: a note
RESTING = ("hinge", "roller", "sleeve")   # the symbols of supports that rest on the ground (lift-off checked)


class LiftOffWarning(UserWarning):
    """A support resting on the ground pulls the structure down (it would lift off)."""


class BelowGroundWarning(UserWarning):
    """A part of the structure lies below the ground line (the model has no contact with the ground)."""


# -- the data of a picture -----------------------------------------------------------------------------

def frame_data(source, magnify: float = 1.0, frame: int | None = None) -> dict:
    """Geometry and values of one static state, in SI units, for drawing.

    ``source``: a result of :func:`femslide.solve` that carries ``result.solution`` (declared
    structures, structure files, FE scenes), a :class:`femslide.analysis.static.Solution`, or the path of a
    ``.vtu`` written by femslide (or a ``.pvd`` series: frame ``frame``, default the last).
    ``magnify`` multiplies the displacements (1: the true deformed shape).

    Returns a dict: ``rods`` [{name, X (drawn nodes), X0 (undeformed), Xt (true deformed), M, V, N
    (nodal values), q (distributed load per element, N/m, global)}], ``bodies`` [{X, X0}] (outline
    polygons), ``links`` [{X, X0}] (rigid links: 2-point lines), ``joints`` [{name, type, ground,
    X (drawn), axis, force (Fx, Fy, M), inward}], ``loads`` [{name, X (drawn), X0, force (Fx, Fy,
    M)}] (point loads), ``values`` (scalar field data: time, phi, ...),
    ``name``.
    """
    if not (isinstance(magnify, (int, float)) and math.isfinite(magnify) and magnify >= 0):
        raise BadInput(f"magnify = {magnify!r}: allowed a number >= 0 (1: true displacements)")
    if isinstance(source, (str, os.PathLike)):
        return _from_file(os.fspath(source), magnify, frame)
    sol = getattr(source, "solution", None)
    if sol is None and hasattr(source, "level"):
        sol = source
    if sol is None:
        raise BadInput("plot: the result has no rods to draw (a spring-hinge or dynamic scene); "
                       "allowed: a result of femslide.solve for a declared structure, a structure file "
                       "or an FE scene, or a .vtu / .pvd file written by femslide")
    from femslide.output.vtu import describe, joint_data, load_data, mesh_data
    lv = sol.level
    points, cells, point_data, cell_data = mesh_data(lv.model, lv.y, lv.alpha, lv.arrays, lv.cuts)
    fd = {**describe(lv.model), **joint_data(lv.model, lv.y), **load_data(lv.model, lv.y)}
    name = getattr(source, "get", lambda *_: None)("name")
    return _from_mesh(points, cells, point_data, cell_data, fd, magnify, name)


def _from_file(path, magnify, frame):
    from femslide.output.vtu import read_meshio
    from femslide.output.vtu import pick_file
    vtu, t = pick_file(path, frame)
    m = read_meshio(vtu, "result file" if vtu == path else f"{path}: frame file")
    cells = [(c.type, c.data) for c in m.cells]
    name = os.path.splitext(os.path.basename(vtu))[0]
    out = _from_mesh(m.points, cells, m.point_data, m.cell_data, m.field_data, magnify, name, where=vtu)
    if t is not None:
        out["values"].setdefault("time", t)
    return out


def _text(fd, key):
    from femslide.output.vtu import text
    v = fd.get(key)
    if v is None:
        return None
    return v if isinstance(v, str) else text(fd, key)


def _from_mesh(points, cells, point_data, cell_data, fd, magnify, name, where=None):
    import numpy as np
    from femslide.output.vtu import reference_points
    Pin = np.asarray(points, float)[:, :2]
    disp = np.asarray(point_data["displacement"], float)[:, :2] if "displacement" in point_data \
        else np.zeros_like(Pin)
    # the points are the reference configuration (files of earlier versions: the deformed one)
    P0 = Pin if reference_points(fd) else Pin - disp
    P = P0 + disp
    Pd = P0 + magnify * disp
    if "part" not in cell_data:
        raise BadInput(f"{where or name}: not a femslide result (no cell data 'part'); allowed: a .vtu written by "
                       f"femslide solve/simulate --out")
    rod_names = (_text(fd, "rod_names") or "").split("\n")
    rods, bodies, links = {}, [], []
    for k, (ctype, conn) in enumerate(cells):
        conn = np.asarray(conn)
        part = np.asarray(cell_data["part"][k]).ravel()
        rod = np.asarray(cell_data["rod"][k]).ravel() if "rod" in cell_data else np.zeros(len(conn), int)
        q = np.asarray(cell_data["distributed_load"][k], float)[:, :2] if "distributed_load" in cell_data \
            else np.zeros((len(conn), 2))
        for c in range(len(conn)):
            if part[c] == 0 and ctype == "line":
                rods.setdefault(int(rod[c]), []).append((conn[c], q[c]))
            elif part[c] == 1:
                bodies.append({"X": Pd[conn[c]], "X0": P0[conn[c]], "Xt": P[conn[c]]})
            elif part[c] == 2:
                links.append({"X": Pd[conn[c]], "X0": P0[conn[c]], "Xt": P[conn[c]]})
    out_rods = []
    pdat = {key: np.asarray(point_data[f], float) for key, (f, _, _) in DIAGRAMS.items() if f in point_data}
    for r in sorted(rods):
        els = rods[r]
        conn = np.array([e[0] for e in els])
        order = _chain(conn)
        if order is None:
            raise BadInput(f"{where or name}: the elements of rod {r} do not form one chain")
        nodes, qs = order
        qel = np.array([els[i][1] for i in qs])
        nm = rod_names[r] if r < len(rod_names) and rod_names[r] else f"rod {r}"
        d = {"name": nm, "X": Pd[nodes], "X0": P0[nodes], "Xt": P[nodes], "q": np.nan_to_num(qel)}
        for key in DIAGRAMS:
            d[key] = pdat[key][nodes] if key in pdat else np.zeros(len(nodes))
        out_rods.append(d)
    joints = []
    jn = (_text(fd, "joint_names") or "").split("\n")
    if "joint_type" in fd:
        jt = np.asarray(fd["joint_type"]).ravel().astype(int)
        gr = np.asarray(fd["joint_ground"]).ravel().astype(int)
        pos = np.asarray(fd["joint_position"], float).reshape(-1, 3)[:, :2]
        ref = np.asarray(fd["joint_reference"], float).reshape(-1, 3)[:, :2]
        ax = np.asarray(fd["joint_axis"], float).reshape(-1, 3)[:, :2]
        fo = np.asarray(fd["joint_force"], float).reshape(-1, 3)
        inw = np.asarray(fd["joint_inward"], float).reshape(-1, 3)[:, :2]
        tn = _text(fd, "joint_type_names")
        tn = tn.split("\n") if tn is not None else []   # files written before the type names: the codes
        for i in range(len(jt)):
            typ = tn[i] if i < len(tn) else (name_of_code(int(jt[i])) or f"type {jt[i]}")
            kind = KINDS.get(typ)
            joints.append({"name": jn[i] if i < len(jn) else f"joint {i}", "type": typ,
                           "symbol": kind.symbol if kind is not None else None, "ground": bool(gr[i]),
                           "X": ref[i] + magnify * (pos[i] - ref[i]), "X0": ref[i],
                           "axis": ax[i], "force": fo[i], "inward": inw[i]})
    loads = []
    if "load_force" in fd:
        ln = (_text(fd, "load_names") or "").split("\n")
        pos = np.asarray(fd["load_position"], float).reshape(-1, 3)[:, :2]
        ref = np.asarray(fd["load_reference"], float).reshape(-1, 3)[:, :2]
        fo = np.asarray(fd["load_force"], float).reshape(-1, 3)
        for i in range(len(fo)):
            loads.append({"name": ln[i] if i < len(ln) else f"load {i}", "X": ref[i] + magnify * (pos[i] - ref[i]),
                          "X0": ref[i], "force": fo[i]})
    values = {}
    for k, v in fd.items():
        a = np.asarray(v) if not isinstance(v, str) else None
        if a is not None and a.dtype.kind == "f" and a.size == 1:
            values[k] = float(a.ravel()[0])
    return {"name": name, "rods": out_rods, "bodies": bodies, "links": links, "joints": joints, "loads": loads,
            "values": values, "magnify": float(magnify)}


def _chain(conn):
    """Node order of a chain of 2-node elements given in any order: (nodes, element order) or None."""
    import numpy as np
    n = len(conn)
    if n == 0:
        return None
    if n == 1 or np.all(conn[1:, 0] == conn[:-1, 1]):
        return np.concatenate([conn[:, 0], conn[-1:, 1]]), np.arange(n)
    nxt = {int(a): i for i, (a, _) in enumerate(conn)}
    ends = {int(b) for b in conn[:, 1]}
    starts = [i for i, (a, _) in enumerate(conn) if int(a) not in ends]
    if len(starts) != 1:
        return None
    i, nodes, els = starts[0], [int(conn[starts[0], 0])], []
    while i is not None and len(els) <= n:
        els.append(i)
        nodes.append(int(conn[i, 1]))
        i = nxt.get(int(conn[i, 1]))
    return (np.array(nodes), np.array(els)) if len(els) == n else None


# -- the diagram ---------------------------------------------------------------------------------------

def samples(rod, diagram):
    """(points on the drawn rod (k, 2), unit normals (k, 2), values (k,)) of one rod's diagram: the nodes,
    and for M under a distributed load the parabola inside each element (9 points and its extremum),
    with the zero crossings inserted (so that every piece between two samples has one sign)."""
    import numpy as np
    X, Xt, X0, v, q = rod["X"], rod["Xt"], rod["X0"], rod[diagram], rod["q"]
    pts, nrm, val = [], [], []
    for e in range(len(X) - 1):
        D = X[e + 1] - X[e]
        ln = math.hypot(*D) or 1.0
        n = np.array([-D[1], D[0]]) / ln
        xi = np.array([0.0, 1.0])
        vals = None
        if diagram == "M" and np.any(q[e] != 0):
            Dt = Xt[e + 1] - Xt[e]
            nt = np.array([-Dt[1], Dt[0]]) / (math.hypot(*Dt) or 1.0)
            qn = float(q[e] @ nt)
            L0 = math.hypot(*(X0[e + 1] - X0[e]))
            xi = np.linspace(0.0, 1.0, 9)
            if qn != 0:
                xs = 0.5 - (v[e + 1] - v[e]) / (qn * L0 * L0)
                if 0 < xs < 1:
                    xi = np.sort(np.append(xi, xs))
            vals = (1 - xi) * v[e] + xi * v[e + 1] - qn * L0 * L0 * xi * (1 - xi) / 2
        if vals is None:
            vals = (1 - xi) * v[e] + xi * v[e + 1]
        P = X[e][None, :] + xi[:, None] * D[None, :]
        # zero crossings
        Pl, Vl = [P[0]], [vals[0]]
        for i in range(1, len(xi)):
            a, b = vals[i - 1], vals[i]
            if a * b < 0:
                f = a / (a - b)
                Pl.append(P[i - 1] + f * (P[i] - P[i - 1]))
                Vl.append(0.0)
            Pl.append(P[i])
            Vl.append(b)
        pts += Pl
        val += Vl
        nrm += [n] * len(Pl)
    return np.array(pts), np.array(nrm), np.array(val)


def auto_scale(fr, diagram, size=None):
    """Diagram scale [m per unit]: the largest |value| over all rods drawn SCALE_FRACTION of the size."""
    import numpy as np
    vmax = max((float(np.abs(samples(r, diagram)[2]).max()) for r in fr["rods"]), default=0.0)
    size = size_of(fr) if size is None else size
    return SCALE_FRACTION * size / vmax if vmax > 0 else 0.0


def diagram_geometry(fr, diagram, scale=None):
    """Per rod: {name, base (k, 2), offset (k, 2), value (k,), extremes [(value, base point, offset
    point)]} and the scale used.  Extremes: the largest |value| of the rod and the extreme of the other
    sign when it is at least 1e-3 of it (values exactly as computed, not rounded)."""
    import numpy as np
    if diagram not in DIAGRAMS:
        raise BadInput(f"diagram = {diagram!r}: allowed 'M', 'V' or 'N'")
    if scale is None:
        k = auto_scale(fr, diagram)
    else:
        if not (isinstance(scale, (int, float)) and math.isfinite(scale) and scale > 0):
            raise BadInput(f"scale = {scale!r}: allowed a number > 0 (m per {DIAGRAMS[diagram][1]})")
        k = float(scale)
    out = []
    for r in fr["rods"]:
        P, n, v = samples(r, diagram)
        Off = P + SIDE[diagram] * k * v[:, None] * n
        ext = []
        if v.size:
            i = int(np.argmax(np.abs(v)))
            ext.append((float(v[i]), P[i], Off[i]))
            other = v * np.sign(v[i]) if v[i] != 0 else v
            j = int(np.argmin(other))
            if other[j] < 0 and abs(v[j]) >= 1e-3 * abs(v[i]):
                ext.append((float(v[j]), P[j], Off[j]))
        out.append({"name": r["name"], "base": P, "offset": Off, "value": v, "extremes": ext})
    return out, k


def fmt_value(v, unit):
    return f"{v:.4g} {unit}"


# -- supports, guides, ground --------------------------------------------------------------------------

def shapes(fr, h=None):
    """Primitives of the supports, guides and ground line: [(kind, points (k, 2), style)] with kind
    'line' (open polyline), 'poly' (closed filled polygon) or 'dash' (dash-dot guide axis); style
    'support', 'ground', 'guide'.  ``h``: symbol size [m] (default SYMBOL_FRACTION of the size)."""
    import numpy as np
    size = size_of(fr)
    h = SYMBOL_FRACTION * size if h is None else h
    out = []
    resting = []
    for j in fr["joints"]:
        p = np.asarray(j["X"], float)
        ax = np.asarray(j["axis"], float)
        sym = j.get("symbol")
        if j["ground"]:
            up = np.asarray(j["inward"], float)
            if not np.any(up):
                up = np.array([0.0, 1.0])
            side = np.array([up[1], -up[0]])
            if sym in ("hinge", "roller"):
                base = p - 1.2 * h * up
                tri = np.array([p, base + 0.7 * h * side, base - 0.7 * h * side])
                out.append(("poly", tri, "support"))
                g = base - (0.35 * h * up if sym == "roller" else 0.0)
                if sym == "roller":
                    out.append(("line", np.array([base + 0.9 * h * side, base - 0.9 * h * side]), "support"))
                out += _hatched(g, side, -up, 1.1 * h)
                resting.append((j, g))
            elif sym == "clamp":
                out += _hatched(p, side, -up, 1.4 * h, thick=True)
                resting.append((j, p))
            elif sym == "sleeve":   # on the ground: along the guide, hatched on the ground side
                e = ax / (np.hypot(*ax) or 1.0)
                for s_ in (1.0, -1.0):
                    out.append(("line", np.array([p - 1.6 * h * e + 0.45 * h * s_ * up,
                                                  p + 1.6 * h * e + 0.45 * h * s_ * up]), "support"))
                out.append(("dash", np.array([p - 3.5 * h * e, p + 3.5 * h * e]), "guide"))
                g = p - 0.45 * h * up
                out += _hatched(g, e, -up, 1.6 * h)[1:]
                resting.append((j, g))
            else:   # a symbol without a drawing: a plain marker (not resting on the ground)
                out.append(("poly", _diamond(p, 0.4 * h), "support"))
        elif sym == "sleeve":   # the guide carried by part b: a sleeve along its axis
            e = ax / (np.hypot(*ax) or 1.0)
            w = np.array([-e[1], e[0]])
            for s_ in (1.0, -1.0):
                out.append(("line", np.array([p - 1.5 * h * e + 0.35 * h * s_ * w,
                                              p + 1.5 * h * e + 0.35 * h * s_ * w]), "guide"))
            out.append(("dash", np.array([p - 3.0 * h * e, p + 3.0 * h * e]), "guide"))
        elif sym == "roller":
            e = ax / (np.hypot(*ax) or 1.0)
            out.append(("dash", np.array([p - 3.0 * h * e, p + 3.0 * h * e]), "guide"))
            out.append(("poly", _circle(p, 0.3 * h), "support"))
        elif sym == "hinge":
            out.append(("line", _circle(p, 0.25 * h, closed=True), "support"))
        elif sym != "clamp":
            out.append(("poly", _diamond(p, 0.3 * h), "support"))
    # the ground line: through the supports resting on the ground with the ground below (inward +y)
    low = [g[1] for j, g in resting if j["inward"][1] > 0.99]
    level = [j["X0"][1] for j, g in resting if j["inward"][1] > 0.99]
    if low and len(low) == len(resting) and max(level) - min(level) <= 1e-9 * size:
        xs = np.concatenate([r["X"][:, 0] for r in fr["rods"]] + [b["X"][:, 0] for b in fr["bodies"]]
                            + [np.array([j["X"][0] for j in fr["joints"]])])
        y0 = min(low)
        out.append(("line", np.array([[xs.min() - 0.1 * size, y0], [xs.max() + 0.1 * size, y0]]), "ground"))
    return out


def _hatched(c, along, away, half, thick=False):
    """A line through c along ``along`` (half-length ``half``) hatched on the side ``away``."""
    import numpy as np
    along = np.asarray(along, float)
    away = np.asarray(away, float)
    out = [("line", np.array([c - half * along, c + half * along]), "wall" if thick else "support")]
    for t in np.linspace(-half, half, 6):
        a = c + t * along
        out.append(("line", np.array([a, a + 0.45 * half * (away - 0.7 * along)]), "hatch"))
    return out


def _diamond(c, r):
    """The plain marker of a joint whose symbol has no drawing: a diamond of half-diagonal r."""
    import numpy as np
    return np.array([[c[0] + r, c[1]], [c[0], c[1] + r], [c[0] - r, c[1]], [c[0], c[1] - r]])


def _circle(c, r, closed=False, n=16):
    import numpy as np
    t = np.linspace(0, 2 * np.pi, n + 1 if closed else n, endpoint=closed)
    return np.column_stack([c[0] + r * np.cos(t), c[1] + r * np.sin(t)])


def lift_off(fr):
    """[(support name, reaction component along the inward direction [N])] of the supports resting on
    the ground (symbols RESTING: pins, rollers, sliders) that pull the structure towards the ground."""
    import numpy as np
    sup = [j for j in fr["joints"] if j["ground"]]
    big = max((float(np.hypot(*j["force"][:2])) for j in sup if np.all(np.isfinite(j["force"]))), default=0.0)
    out = []
    for j in sup:
        if j.get("symbol") not in RESTING or not np.all(np.isfinite(j["force"])):
            continue
        r = float(np.asarray(j["force"][:2]) @ np.asarray(j["inward"]))
        if r < -LIFT_OFF_RTOL * big:
            out.append((j["name"], r))
    return out


def ground_level(fr):
    """y [m] of the ground when every support rests on level ground (pins, rollers, sliders and welds
    with the ground below them, all at one height), else None."""
    sup = [j for j in fr["joints"] if j["ground"]]
    if not sup or any(j["inward"][1] < 0.99 for j in sup):
        return None
    ys = [float(j["X0"][1]) for j in sup]
    return ys[0] if max(ys) - min(ys) <= 1e-9 * size_of(fr) else None


def below_ground(fr):
    """How far [m] the deformed structure (true displacements) reaches below the level of its supports
    on level ground, when that is more than BELOW_GROUND_FRACTION of the structure's size (a beam
    sagging between its supports is not meant), else 0."""
    import numpy as np
    y0 = ground_level(fr)
    pts = [r["Xt"] for r in fr["rods"]] + [b["Xt"] for b in fr["bodies"] + fr["links"]]
    if y0 is None or not pts:
        return 0.0
    depth = y0 - float(np.concatenate(pts)[:, 1].min())
    return depth if depth > BELOW_GROUND_FRACTION * size_of(fr) else 0.0


def notes(fr):
    """[(warning class, one-line note)] of a picture: lift-off at supports, parts below the ground."""
    out = [(LiftOffWarning, f"lift-off at {n}: the ground pulls with {-r:.4g} N") for n, r in lift_off(fr)]
    d = below_ground(fr)
    if d:
        out.append((BelowGroundWarning, f"the structure reaches {d:.4g} m below the ground line of its supports "
                                        f"(no contact in the model)"))
    return out


def warn_notes(found, stacklevel=3):
    """Issue the Python warnings of :func:`notes` (the lift-off one with its full explanation)."""
    for cls, text in found:
        if cls is LiftOffWarning:
            text += " (a support resting on the ground cannot pull; it would lift off)"
        warnings.warn(text, cls, stacklevel=stacklevel)


# -- matplotlib ----------------------------------------------------------------------------------------

def plot(result, diagram: str = "M", ax=None, scale: float | None = None, magnify: float = 1.0,
         frame: int | None = None, labels: bool = True, title: str | None = None, units: str = "N",
         loads: bool = True):
    """Draw the M, V or N diagram of every rod on the deformed structure (matplotlib); return the Axes.

    ``result``: a result of :func:`femslide.solve` with rods (declared structure, structure file, FE
    scene) or a ``.vtu`` / ``.pvd`` file written by femslide (``frame``: which frame of a .pvd,
    default the last).  ``diagram``: "M" (bending moment, N m, drawn on the tension side: a positive M
    to the right of the rod's direction from start to end), "V" (shear force, N) or "N" (axial force,
    N, tension > 0), both positive to the left of the rod's direction.  ``scale``: m of drawing per
    unit of the diagram (m per N m, m per N); default: the largest absolute value drawn at 15 % of the
    structure's size, the same scale for every rod.  ``magnify``: factor on the displacements (the
    undeformed shape is drawn in thin grey).  ``ax``: an Axes to draw into (default: a new figure).
    ``units``: "N" (N, N m, N/m) or "kN" (kN, kN m, kN/m) for every number written.  ``loads``: draw
    the load and reaction arrows with their values (femslide.output.arrows); the moment in every
    sliding bearing is written at the bearing.

    The Axes gets an attribute ``femslide_diagram``: {``polygons``: {rod: Polygon}, ``extremes``:
    {rod: [(value, Text)]}, ``scale``, ``lift_off``: [(support, reaction along the inward
    direction, N)], ``below_ground``: m, ``arrows``: [(kind, Annotation)], ``bearings``: [Text]}.
    A support resting on the ground that pulls the structure
    down adds a red note on the figure and a :class:`LiftOffWarning`; a structure reaching below the
    level ground of its supports a note and a :class:`BelowGroundWarning`.
    """
    import numpy as np

    from femslide.output.arrows import arrows as load_arrows
    from femslide.output.arrows import bearing_labels, check_units, unit_label, value_text
    check_units(units)
    try:
        import matplotlib
    except ImportError:  # pragma: no cover - depends on the installation
        raise ImportError("femslide.plot needs matplotlib: pip install matplotlib (or femslide[plot])") from None
    if ax is None:
        import matplotlib.pyplot as plt
        _, ax = plt.subplots(figsize=(7.5, 6.5))
    from matplotlib.patches import Polygon
    fr = frame_data(result, magnify=magnify, frame=frame)
    geo, k = diagram_geometry(fr, diagram, scale)
    unit, what = DIAGRAMS[diagram][1], DIAGRAMS[diagram][2]
    size = size_of(fr)
    grey = (0.72, 0.72, 0.72)
    for b in fr["bodies"]:
        ax.add_patch(Polygon(b["X0"], closed=True, fill=False, ec=grey, lw=0.8, zorder=1))
        ax.add_patch(Polygon(b["X"], closed=True, fc=(0.86, 0.86, 0.86), ec="black", lw=1.2, zorder=2))
    for ln in fr["links"]:
        ax.plot(*ln["X0"].T, color=grey, lw=0.8, zorder=1)
        ax.plot(*ln["X"].T, color=(0.3, 0.3, 0.3), lw=3, zorder=3, solid_capstyle="round")
    for r in fr["rods"]:
        ax.plot(*r["X0"].T, color=grey, lw=0.8, zorder=1)
    polys, exts = {}, {}
    colour = COLOURS[diagram]
    for g in geo:
        poly = Polygon(np.concatenate([g["base"], g["offset"][::-1]]), closed=True, fc=colour, alpha=0.3,
                       ec=colour, lw=1.0, zorder=4)
        poly.set_gid(f"diagram:{g['name']}")
        ax.add_patch(poly)
        polys[g["name"]] = poly
        # stations: thin lines from the rod to the diagram at the nodes (opsvis style)
        sel = np.linspace(0, len(g["base"]) - 1, min(len(g["base"]), 25)).round().astype(int)
        for i in sel:
            ax.plot([g["base"][i, 0], g["offset"][i, 0]], [g["base"][i, 1], g["offset"][i, 1]], color=colour,
                    lw=0.5, alpha=0.6, zorder=4)
        exts[g["name"]] = []
        for v, P, Q in g["extremes"]:
            if not labels:
                continue
            d = Q - P
            nd = math.hypot(*d)
            off = d / nd * 0.02 * size if nd > 0 else np.zeros(2)
            t = ax.annotate(value_text(v, unit, units), xy=Q, xytext=Q + off, fontsize=8, color="black",
                            ha="left" if off[0] >= 0 else "right", va="bottom" if off[1] >= 0 else "top",
                            zorder=7, bbox={"boxstyle": "round,pad=0.15", "fc": "white", "ec": colour,
                                  "lw": 0.5, "alpha": 0.85})
            exts[g["name"]].append((v, t))
            ax.update_datalim(np.array([Q + 4 * off]))   # room for the label
    for r in fr["rods"]:
        ax.plot(*r["X"].T, color="black", lw=2.0, zorder=5, solid_capstyle="round")
    for kind, P, style in shapes(fr):
        c = {"guide": (0.15, 0.15, 0.5), "ground": (0.35, 0.25, 0.15)}.get(style, "black")
        lw = {"hatch": 0.7, "wall": 2.5, "ground": 1.2}.get(style, 1.3)
        if kind == "poly":
            ax.add_patch(Polygon(P, closed=True, fc="white", ec="black", lw=1.3, zorder=6))
        elif kind == "dash":
            ax.plot(*P.T, color=c, lw=0.8, ls="-.", zorder=6)
        else:
            ax.plot(*P.T, color=c, lw=lw, zorder=6 if style != "ground" else 0)
    drawn = []
    if loads:
        colours = {"load": "darkred", "distributed": "darkred", "reaction": "darkgreen"}
        for a in load_arrows(fr, units):
            c = colours[a["kind"]]
            an = ax.annotate("", xy=a["head"], xytext=a["tail"], zorder=7,
                             arrowprops={"arrowstyle": "-|>", "color": c, "lw": 1.3, "shrinkA": 0, "shrinkB": 0})
            drawn.append((a["kind"], an))
            if a["label"]:
                ax.annotate(a["label"], xy=a["tail"], fontsize=7.5, color=c, ha="center", va="center", zorder=8,
                            bbox={"boxstyle": "round,pad=0.15", "fc": "white", "ec": c, "lw": 0.5, "alpha": 0.85})
            ax.update_datalim(np.array([a["tail"], a["head"]]))
    bearings = []
    for P, text in bearing_labels(fr, units):
        bearings.append(ax.annotate(text, xy=P, xytext=(8, -14), textcoords="offset points", fontsize=8,
                                    color=(0.15, 0.15, 0.5), zorder=8,
                                    bbox={"boxstyle": "round,pad=0.15", "fc": "white", "ec": (0.15, 0.15, 0.5),
                                          "lw": 0.6, "alpha": 0.9}))
    lifts = lift_off(fr)
    found = notes(fr)
    if found:
        warn_notes(found)
        ax.text(0.01, 0.99, "\n".join(t for _, t in found), transform=ax.transAxes, color="red", fontsize=9,
                va="top", ha="left", zorder=8, bbox={"fc": "white", "ec": "red", "alpha": 0.9})
    ax.set_aspect("equal", adjustable="datalim")
    ax.autoscale_view()
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    side = "tension side" if diagram == "M" else "positive to the left of start -> end"
    mag = f", displacements x {magnify:g}" if magnify != 1 else ""
    shown = unit_label(unit, units)
    ax.set_title(title if title is not None else
                 f"{fr['name'] + ': ' if fr['name'] else ''}{what} [{shown}] ({side}; "
                 f"scale {k / check_units(units):.3g} m/{shown}{mag})", fontsize=9)
    ax.grid(True, lw=0.3, alpha=0.5)
    ax.femslide_diagram = {"polygons": polys, "extremes": exts, "scale": k, "lift_off": lifts,
                           "below_ground": below_ground(fr), "matplotlib": matplotlib.__version__,
                           "arrows": drawn, "bearings": bearings}
    return ax
