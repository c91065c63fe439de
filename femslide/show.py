"""Picture of a result: the deformed structure coloured by bending moment, with the body (pyvista).

``femslide show RESULT.vtu|RESULT.pvd [--frame K] [--screenshot out.png]``.  Reads what
:mod:`femslide.vtu` writes (cell data ``part``: 0 rod element, 1 body, 2 rigid rod; point data
``bending_moment`` and ``displacement``); any other VTU (e.g. a scene mesh from ``femslide mesh``)
is drawn plainly.  The undeformed configuration (points minus ``displacement``) is drawn thin and grey.

With a screenshot the rendering is off-screen: VTK's EGL window is chosen before pyvista is imported
(headless machines have no X server), so nothing here needs a display.
"""
from __future__ import annotations

import os
import xml.etree.ElementTree as ET

from .errors import BadInput

BACKGROUND = "white"
WINDOW = (900, 700)


def pvd_frames(path):
    """[(time, vtu path)] of a PVD collection, in file order."""
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


def _check_readable(vtu, given):
    """A corrupt or truncated VTU is bad input naming the file (VTK would only log errors and hand
    back an empty grid): it is parsed with meshio first."""
    from .meshfile import read_meshio
    what = "result file" if vtu == given else f"{given}: frame file"
    read_meshio(vtu, what)


def _import_pyvista(off_screen):
    if off_screen:
        os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")
    import pyvista
    if off_screen:
        pyvista.OFF_SCREEN = True
    return pyvista


def render(path, screenshot=None, frame=None, window_size=WINDOW):
    """Draw a result; save a PNG when ``screenshot`` is given (off-screen), else open a window.

    Returns a dict: ``file`` drawn, ``time`` (PVD frame) and, after a screenshot, ``rod_pixels``:
    (column, row) image positions of the rod nodes (row 0 at the top), for checks of the picture.
    """
    import numpy as np
    vtu, t = pick_file(path, frame)
    _check_readable(vtu, path)
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
        ref = grid.copy()
        ref.points = grid.points - np.asarray(grid.point_data["displacement"])
        ref_parts = ref.extract_cells(np.nonzero(part != 3)[0])
        ref_parts.points[:, 2] -= 2 * depth  # behind everything: the picture is flat, draw order by depth
        pl.add_mesh(ref_parts, style="wireframe", color=(0.72, 0.72, 0.72), line_width=1.5, lighting=False)

    rods = grid.extract_cells(np.nonzero(part == 0)[0])
    if rods.n_cells:
        if "bending_moment" in rods.point_data:
            M = np.asarray(rods.point_data["bending_moment"])
            lo, hi = float(M.min()), float(M.max())
            if hi - lo <= 1e-12 * max(abs(lo), abs(hi), 1.0):
                lo, hi = lo - max(abs(lo), 1.0) * 0.05, hi + max(abs(hi), 1.0) * 0.05
            pl.add_mesh(rods, scalars="bending_moment", cmap=_cmap(), clim=(lo, hi), line_width=7,
                        scalar_bar_args={"title": "M [N m]", "color": "black",
                                         "vertical": True, "position_x": 0.84, "position_y": 0.15,
                                         "height": 0.7, "width": 0.06, "fmt": "%.4g"},
                        lighting=False)
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

    pl.add_text(_title(vtu, grid, t), position="upper_left", font_size=10, color="black")
    pl.view_xy()
    pl.reset_camera()
    pl.camera.zoom(0.9)
    info = {"file": vtu, "time": t}
    if screenshot is None:
        pl.show()
        return info
    d = os.path.dirname(screenshot)
    if d:
        os.makedirs(d, exist_ok=True)
    pl.screenshot(screenshot)
    if rods.n_cells:
        info["rod_pixels"] = _to_pixels(pl, np.asarray(rods.points), window_size)
    pl.close()
    return info


def _cmap():
    try:
        import matplotlib  # noqa: F401  (pyvista's named colour maps come from matplotlib)
        return "viridis"
    except ImportError:
        return None


def _title(vtu, grid, t):
    name = os.path.splitext(os.path.basename(vtu))[0]
    parts = [name]
    if t is not None:
        parts.append(f"t = {t:.6g} s")
    fd = grid.field_data
    if "phi" in fd:
        parts.append(f"phi = {float(fd['phi'][0]):.6g} rad")
    if "M_max" in fd:
        parts.append(f"M_max = {float(fd['M_max'][0]):.6g} N m")
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
