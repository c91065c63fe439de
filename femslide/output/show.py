"""Picture of a result: the deformed structure coloured by bending moment, with the body (pyvista).

``femslide show RESULT.vtu|RESULT.pvd [--frame K] [--screenshot out.png]``.  Reads what
:mod:`femslide.output.vtu` writes (cell data ``part``: 0 rod element, 1 body, 2 rigid rod; point data
``bending_moment`` and ``displacement``: the points are the reference configuration, points +
``displacement`` the deformed one); any other VTU (e.g. a scene mesh from ``femslide mesh``) is drawn
plainly.  The undeformed configuration is drawn thin and grey.

``--magnify K`` multiplies the displacements (the undeformed shape stays as it is).  The colour range
is the same for every frame of a .pvd series (computed over all its frames); a field that is
constant to round-off (e.g. the moment of cantilever-moment) is drawn in one colour with its value
written out instead of a colour bar of noise ticks.  Supports, slider guides and the ground line are
drawn from the joints the VTU carries (field data written by :mod:`femslide.output.vtu`).

``--diagram M|V|N [--scale K]`` draws the member diagrams of :func:`femslide.plot` instead (same
geometry, conventions and scale rule: M on the tension side, V and N positive to the left of the
rod's direction from start to end; by default the largest |value| over the series is drawn at 15 %
of the structure's size; ``--scale`` in m per N m or m per N), coloured by value, extremes labelled,
and a red note when a support resting on the ground pulls the structure down (lift-off).

With a screenshot the rendering is off-screen: VTK's EGL window is chosen before pyvista is imported
(headless machines have no X server), so nothing here needs a display.
"""
from __future__ import annotations

import math
import os

from femslide.errors import BadInput
from femslide.output.vtu import pick_file, pvd_frames

BACKGROUND = "white"
WINDOW = (900, 700)


def _check_readable(vtu, given):
    """A corrupt or truncated VTU is bad input naming the file (VTK would only log errors and hand
    back an empty grid): it is parsed with meshio first."""
    from femslide.output.vtu import read_meshio
    what = "result file" if vtu == given else f"{given}: frame file"
    read_meshio(vtu, what)


VIEW_MISSING = ("femslide show draws with pyvista and VTK, which are not installed; install them with "
                "pip install 'femslide[view]' (the result files themselves are plain VTU/PVD: ParaView opens "
                "them too)")


def need_pyvista():
    """BadInput naming the extra to install when pyvista (with VTK) is missing."""
    import importlib.util
    if importlib.util.find_spec("pyvista") is None or importlib.util.find_spec("vtkmodules") is None:
        raise BadInput(VIEW_MISSING)


def _import_pyvista(off_screen):
    need_pyvista()
    if off_screen:
        os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")
    import pyvista
    if off_screen:
        pyvista.OFF_SCREEN = True
    return pyvista


CONSTANT_RTOL = 1e-6   # a colour range narrower than this (relative) is round-off: one value


def series_files(path):
    """The VTU files of a result: every frame of a .pvd, or the .vtu itself."""
    if os.path.splitext(path)[1].lower() == ".pvd" and os.path.isfile(path):
        return [f for _, f in pvd_frames(path) if os.path.isfile(f)]
    return [path]


def value_range(path, diagram=None):
    """(lo, hi) of the coloured quantity over all frames of a series (bending moment of the rods, or
    the diagram's values including the parabolas of distributed loads); None without rods."""
    import numpy as np

    from femslide.output.vtu import read_meshio
    from femslide.output.diagrams import frame_data, samples
    lo, hi = math.inf, -math.inf
    for f in series_files(path):
        if diagram is None:
            m = read_meshio(f, f"{path}: frame file")
            if "bending_moment" not in m.point_data or "part" not in m.cell_data:
                continue
            ids = [c for blk, part in zip(m.cells, m.cell_data["part"]) for c in
                   np.asarray(blk.data)[np.asarray(part).ravel() == 0].ravel()]
            v = np.asarray(m.point_data["bending_moment"])[np.unique(np.asarray(ids, int))]
        else:
            fr = frame_data(f)
            v = np.concatenate([samples(r, diagram)[2] for r in fr["rods"]] or [np.zeros(0)])
        if v.size:
            lo, hi = min(lo, float(v.min())), max(hi, float(v.max()))
    if lo > hi:
        return None
    big = max(abs(lo), abs(hi))
    # an end that is zero to round-off (a free rod end) is zero: no 7.6e-13 tick
    lo = 0.0 if abs(lo) <= 1e-9 * big else lo
    hi = 0.0 if abs(hi) <= 1e-9 * big else hi
    return lo, hi


def is_constant(lo, hi):
    return hi - lo <= CONSTANT_RTOL * max(abs(lo), abs(hi)) or hi - lo <= 1e-300


def render(path, screenshot=None, frame=None, window_size=WINDOW, diagram=None, scale=None, magnify=1.0,
           units="N", loads=True):
    """Draw a result; save a PNG when ``screenshot`` is given (off-screen), else open a window.

    ``diagram``: None (rods coloured by bending moment) or "M", "V", "N" (member diagrams, see
    :func:`femslide.plot`); ``scale``: diagram scale [m per N m or m per N], default automatic;
    ``magnify``: factor on the displacements; ``units``: "N" or "kN" for every number written (the
    colour bar's ticks are round values in these units); ``loads``: draw the load and reaction arrows
    (femslide.output.arrows; the moment in every sliding bearing is written at it either way).

    Returns a dict: ``file`` drawn, ``time`` (PVD frame), ``clim`` (colour range), ``scale``
    (diagram), ``lift_off`` and, after a screenshot, ``rod_pixels``: (column, row) image positions of
    the rod nodes (row 0 at the top), for checks of the picture.
    """
    import numpy as np
    if diagram is not None and diagram not in ("M", "V", "N"):
        raise BadInput(f"--diagram {diagram}: allowed M, V or N")
    if scale is not None and diagram is None:
        raise BadInput("--scale applies to --diagram M|V|N only")
    if scale is not None and not (math.isfinite(scale) and scale > 0):
        raise BadInput(f"--scale {scale:g}: allowed a number > 0 (m per N m for M, m per N for V, N)")
    if not (math.isfinite(magnify) and magnify >= 0):
        raise BadInput(f"--magnify {magnify:g}: allowed a number >= 0 (1: true displacements)")
    from femslide.output.arrows import check_units
    check_units(units)
    need_pyvista()   # before any work: the message names the extra to install
    vtu, t = pick_file(path, frame)
    _check_readable(vtu, path)
    if diagram is not None:
        return _render_diagram(path, vtu, t, screenshot, window_size, diagram, scale, magnify, units, loads)
    pv = _import_pyvista(screenshot is not None)
    grid = pv.read(vtu)
    if grid.n_points == 0 or grid.n_cells == 0:
        raise BadInput(f"result file {vtu}: holds no points or cells; allowed: a .vtu written by "
                       f"femslide (or any VTU mesh with cells)")
    part = grid.cell_data["part"] if "part" in grid.cell_data else None
    types = np.asarray(grid.celltypes)
    if part is None:  # a plain mesh: lines as rods, polygons as the body, vertices as supports
        part = np.where(np.isin(types, (3, 4)), 0, np.where(np.isin(types, (7, 9)), 1, 3))
    part = np.asarray(part)
    pl = pv.Plotter(off_screen=screenshot is not None, window_size=list(window_size))
    pl.set_background(BACKGROUND)
    pl.enable_parallel_projection()
    depth = 1e-3 * float(np.ptp(np.asarray(grid.points)[:, :2], axis=0).max() or 1.0)

    if "displacement" in grid.point_data:
        disp = np.asarray(grid.point_data["displacement"])
        ref = grid.copy()
        if "points" not in grid.field_data:   # a file of an earlier version: deformed points
            ref.points = grid.points - disp
        grid.points = ref.points + magnify * disp
        ref_parts = ref.extract_cells(np.nonzero(part != 3)[0])
        ref_parts.points[:, 2] -= 2 * depth  # behind everything: the picture is flat, draw order by depth
        pl.add_mesh(ref_parts, style="wireframe", color=(0.72, 0.72, 0.72), line_width=1.5, lighting=False)

    rods = grid.extract_cells(np.nonzero(part == 0)[0])
    clim = None
    if rods.n_cells:
        if "bending_moment" in rods.point_data:
            from femslide.output.arrows import UNITS, unit_label
            f = UNITS[units]
            rng = value_range(path)   # over all frames of a series
            M = np.asarray(rods.point_data["bending_moment"])
            lo, hi = rng if rng else (float(M.min()), float(M.max()))
            clim = (lo, hi)
            if is_constant(lo, hi):
                v = 0.5 * (lo + hi)
                pl.add_mesh(rods, color=_colour_of(0.5), line_width=7, lighting=False)
                pl.add_text(f"M = {v * f:.6g} {unit_label('N m', units)}\n(constant)", position="lower_right",
                            font_size=11, color="black")
            else:
                rods.point_data["M_shown"] = M * f
                pl.add_mesh(rods, scalars="M_shown", cmap=_cmap(), clim=(lo * f, hi * f), line_width=7,
                            scalar_bar_args={"title": f"M [{unit_label('N m', units)}]", "color": "black",
                                             "vertical": True, "position_x": 0.84, "position_y": 0.15,
                                             "height": 0.7, "width": 0.06, "fmt": "%.4g"},
                            lighting=False)
                _round_ticks(pl, lo * f, hi * f)
        else:
            pl.add_mesh(rods, color="steelblue", line_width=7, lighting=False)
    body = grid.extract_cells(np.nonzero(part == 1)[0])
    if body.n_cells:
        body.points[:, 2] -= depth  # behind the rods (a rod's top slides into the guide inside the body)
        pl.add_mesh(body, color=(0.80, 0.80, 0.80), show_edges=True, edge_color="black", line_width=2,
                    lighting=False)  # a flat picture: exact colours
    rigid = grid.extract_cells(np.nonzero(part == 2)[0])
    if rigid.n_cells:
        pl.add_mesh(rigid, color=(0.35, 0.35, 0.35), line_width=5, lighting=False)
    verts = grid.extract_cells(np.nonzero(part == 3)[0])
    if verts.n_cells:
        pl.add_mesh(verts, color="black", point_size=12, render_points_as_spheres=False,
                    lighting=False)
    lifts = []
    if "joint_type" in grid.field_data:
        from femslide.output.diagrams import frame_data
        fr = frame_data(vtu, magnify=magnify)
        _add_shapes(pv, pl, fr, depth)
        _add_arrows(pv, pl, fr, depth, units, loads and "mode" not in grid.field_data)
        lifts = _notes(pl, fr)

    pl.add_text(_title(vtu, grid, t, magnify, units), position="upper_left", font_size=10, color="black")
    return _finish(pl, screenshot, window_size, {"file": vtu, "time": t, "clim": clim, "lift_off": lifts},
                   np.asarray(rods.points) if rods.n_cells else None)


def _finish(pl, screenshot, window_size, info, rod_points):
    pl.view_xy()
    pl.reset_camera()
    pl.camera.zoom(0.9)
    if screenshot is None:
        pl.show()
        return info
    d = os.path.dirname(screenshot)
    if d:
        os.makedirs(d, exist_ok=True)
    pl.screenshot(screenshot)
    if rod_points is not None and len(rod_points):
        info["rod_pixels"] = _to_pixels(pl, rod_points, window_size)
    pl.close()
    return info


def _polyline(pv, P, z=0.0):
    import numpy as np
    pts = np.column_stack([P, np.full(len(P), z)])
    return pv.lines_from_points(pts)


def _polygon(pv, P, z=0.0):
    import numpy as np
    pts = np.column_stack([P, np.full(len(P), z)])
    return pv.PolyData(pts, faces=np.concatenate([[len(P)], np.arange(len(P))]))


def _add_shapes(pv, pl, fr, depth):
    """Supports, guides and the ground line (femslide.output.diagrams.shapes) in front of the picture."""
    colours = {"guide": (0.15, 0.15, 0.5), "ground": (0.35, 0.25, 0.15)}
    widths = {"hatch": 1.5, "wall": 5, "ground": 2}
    from femslide.output.diagrams import shapes
    for kind, P, style in shapes(fr):
        if kind == "poly":
            pl.add_mesh(_polygon(pv, P, 3 * depth), color="white", lighting=False)
            pl.add_mesh(_polyline(pv, list(P) + [P[0]], 4 * depth), color="black", line_width=2, lighting=False)
        else:
            pl.add_mesh(_polyline(pv, P, 3 * depth), color=colours.get(style, "black"),
                        line_width=widths.get(style, 2.5), lighting=False)


def _round_ticks(pl, lo, hi):
    """The colour bar's labels at round values (1, 2, 2.5 or 5 times a power of ten) instead of five
    evenly spaced ones between the range's ends (1.2e+04, 1.37e+04, ...)."""
    from femslide.output.arrows import nice_ticks
    bar = getattr(pl, "scalar_bar", None)
    if bar is None or not hasattr(bar, "SetUseCustomLabels"):
        return
    import vtk
    ticks = vtk.vtkDoubleArray()
    for t in nice_ticks(lo, hi):
        ticks.InsertNextValue(t)
    bar.SetUseCustomLabels(True)
    bar.SetCustomLabels(ticks)
    bar.SetLabelFormat("%.6g")


def _add_arrows(pv, pl, fr, depth, units, loads):
    """Load and reaction arrows (``loads``) and the moment of every sliding bearing, with their values
    (femslide.output.arrows)."""
    import numpy as np

    from femslide.output.arrows import arrows, bearing_labels
    colours = {"load": (0.55, 0.0, 0.0), "distributed": (0.55, 0.0, 0.0), "reaction": (0.0, 0.4, 0.0)}
    pts, texts = [], []
    for a in (arrows(fr, units) if loads else []):
        d = a["head"] - a["tail"]
        n = float(np.hypot(*d))
        if n > 0:
            pl.add_mesh(pv.Arrow(start=(*a["tail"], 5 * depth), direction=(*d, 0.0), scale=n, tip_length=0.25,
                                 tip_radius=0.06, shaft_radius=0.015), color=colours[a["kind"]], lighting=False)
        if a["label"]:
            pts.append([*a["tail"], 6 * depth])
            texts.append(a["label"])
    for P, text in bearing_labels(fr, units):
        pts.append([*P, 6 * depth])
        texts.append(text)
    if pts:
        pl.add_point_labels(np.array(pts), texts, font_size=11, point_size=1, shape_opacity=0.6,
                            always_visible=True, text_color="black")


def _notes(pl, fr):
    """Red notes (and Python warnings) for lift-off and parts below the ground; returns the lift-offs."""
    from femslide.output.diagrams import lift_off, notes, warn_notes
    found = notes(fr)
    if found:
        warn_notes(found, stacklevel=4)
        pl.add_text("\n".join(t for _, t in found), position="lower_left", font_size=11, color="red")
    return lift_off(fr)


def _render_diagram(path, vtu, t, screenshot, window_size, diagram, scale, magnify, units="N", loads=True):
    """The member diagrams of femslide.plot, drawn with pyvista; one colour range and (automatic)
    scale for all frames of a series."""
    import numpy as np

    from femslide.output.diagrams import DIAGRAMS, SCALE_FRACTION, diagram_geometry, frame_data, size_of
    fr = frame_data(vtu, magnify=magnify)
    if not fr["rods"]:
        raise BadInput(f"result file {vtu}: has no rods for a --diagram; allowed: a .vtu written by "
                       f"femslide solve/simulate --out of a structure with rods")
    rng = value_range(path, diagram)
    lo, hi = rng if rng else (0.0, 0.0)
    vmax = max(abs(lo), abs(hi))
    k = scale if scale is not None else (SCALE_FRACTION * size_of(fr) / vmax if vmax > 0 else 1.0)
    geo, k = diagram_geometry(fr, diagram, k)
    from femslide.output.arrows import UNITS, unit_label, value_text
    f = UNITS[units]
    unit = unit_label(DIAGRAMS[diagram][1], units)
    pv = _import_pyvista(screenshot is not None)
    pl = pv.Plotter(off_screen=screenshot is not None, window_size=list(window_size))
    pl.set_background(BACKGROUND)
    pl.enable_parallel_projection()
    size = size_of(fr)
    depth = 1e-3 * size
    grey = (0.72, 0.72, 0.72)
    for r in fr["rods"]:
        pl.add_mesh(_polyline(pv, r["X0"], -2 * depth), color=grey, line_width=1.5, lighting=False)
    for b in fr["bodies"]:
        pl.add_mesh(_polyline(pv, list(b["X0"]) + [b["X0"][0]], -2 * depth), color=grey, line_width=1.5,
                    lighting=False)
        pl.add_mesh(_polygon(pv, b["X"], -depth), color=(0.86, 0.86, 0.86), lighting=False)
        pl.add_mesh(_polyline(pv, list(b["X"]) + [b["X"][0]], -depth), color="black", line_width=2,
                    lighting=False)
    for ln in fr["links"]:
        pl.add_mesh(_polyline(pv, ln["X0"], -2 * depth), color=grey, line_width=1.5, lighting=False)
        pl.add_mesh(_polyline(pv, ln["X"], 0.5 * depth), color=(0.3, 0.3, 0.3), line_width=5, lighting=False)
    # the diagrams: one quad per piece between samples, coloured by the value
    pts, faces, vals = [], [], []
    n0 = 0
    for g in geo:
        B, Q, v = g["base"], g["offset"], g["value"]
        m = len(B)
        pts += [np.column_stack([B, np.zeros(m)]), np.column_stack([Q, np.zeros(m)])]
        vals += [v, v]
        i = np.arange(m - 1)
        faces.append(np.column_stack([np.full(m - 1, 4), n0 + i, n0 + i + 1, n0 + m + i + 1, n0 + m + i]).ravel())
        n0 += 2 * m
    mesh = pv.PolyData(np.concatenate(pts), faces=np.concatenate(faces))
    mesh.point_data[diagram] = np.concatenate(vals) * f
    const = is_constant(lo, hi)
    if const:
        pl.add_mesh(mesh, color=_colour_of(0.5), opacity=0.6, lighting=False)
        pl.add_text(f"{diagram} = {0.5 * (lo + hi) * f:.6g} {unit}\n(constant)", position="lower_right",
                    font_size=11, color="black")
    else:
        pl.add_mesh(mesh, scalars=diagram, cmap=_cmap(), clim=(lo * f, hi * f), opacity=0.75, lighting=False,
                    scalar_bar_args={"title": f"{diagram} [{unit}]", "color": "black", "vertical": True,
                                     "position_x": 0.86, "position_y": 0.15, "height": 0.7, "width": 0.05,
                                     "fmt": "%.4g"})
        _round_ticks(pl, lo * f, hi * f)
    for g in geo:
        pl.add_mesh(_polyline(pv, g["offset"], 0.2 * depth), color="black", line_width=1, lighting=False)
    for r in fr["rods"]:
        pl.add_mesh(_polyline(pv, r["X"], depth), color="black", line_width=4, lighting=False)
    _add_shapes(pv, pl, fr, depth)
    _add_arrows(pv, pl, fr, depth, units, loads)
    lp, lt = [], []
    for g in geo:
        for v, _P, Q in g["extremes"]:
            lp.append([Q[0], Q[1], 5 * depth])
            lt.append(value_text(v, DIAGRAMS[diagram][1], units))
    if lp:
        pl.add_point_labels(np.array(lp), lt, font_size=13, point_size=1, shape_opacity=0.6,
                            always_visible=True, text_color="black")
    lifts = _notes(pl, fr)
    fd = fr["values"]
    title = [os.path.splitext(os.path.basename(vtu))[0], f"{DIAGRAMS[diagram][2]} [{unit}]"]
    if t is not None:
        title.append(f"t = {t:.6g} s")
    if "phi" in fd:
        title.append(f"phi = {fd['phi']:.6g} rad")
    title.append(f"scale {k / f:.3g} m/{unit}" + ("  M on the tension side" if diagram == "M" else ""))
    if magnify != 1.0:
        title.append(f"displacements x {magnify:g}")
    pl.add_text("   ".join(title[:4]) + "\n" + "   ".join(title[4:]), position="upper_left", font_size=10,
                color="black")
    rod_pts = np.concatenate([np.column_stack([r["X"], np.zeros(len(r["X"]))]) for r in fr["rods"]])
    return _finish(pl, screenshot, window_size, {"file": vtu, "time": t, "clim": (lo, hi), "scale": k,
                                                 "lift_off": lifts}, rod_pts)


def _colour_of(x):
    """The colour map's colour at x in [0, 1] (a single-valued field)."""
    try:
        from matplotlib import colormaps
        return tuple(colormaps[_cmap() or "viridis"](x)[:3])
    except (ImportError, KeyError):  # no matplotlib: pyvista's default
        return "steelblue"


def _cmap():
    try:
        import matplotlib  # noqa: F401  (pyvista's named colour maps come from matplotlib)
        return "viridis"
    except ImportError:
        return None


def _title(vtu, grid, t, magnify=1.0, units="N"):
    name = os.path.splitext(os.path.basename(vtu))[0]
    parts = [name]
    if t is not None:
        parts.append(f"t = {t:.6g} s")
    if magnify != 1.0:
        parts.append(f"displacements x {magnify:g}")
    fd = grid.field_data
    if "phi" in fd:
        parts.append(f"phi = {float(fd['phi'][0]):.6g} rad")
    if "M_max" in fd:
        from femslide.output.arrows import value_text
        parts.append(f"M_max = {value_text(float(fd['M_max'][0]), 'N m', units)}")
    return "   ".join(parts)


def _to_pixels(pl, pts, window_size):
    """Image (column, row) of world points, row 0 at the top of the screenshot."""
    import numpy as np
    import vtk
    coord = vtk.vtkCoordinate()
    coord.SetCoordinateSystemToWorld()
    W, H = pl.window_size
    out = []
    for p in pts:
        coord.SetValue(*map(float, p))
        x, y = coord.GetComputedDoubleDisplayValue(pl.renderer)
        out.append((x, H - 1 - y))
    return np.array(out)
