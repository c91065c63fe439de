"""VTU output (femslide/output/vtu.py), exercised as a user does: ``python -m femslide solve SCENE --out DIR`` in
a subprocess, then the file read back with pyvista.  Checks the mesh layout (one line cell per element,
a polygon for the body), the arrays and their SI units, the deformed geometry, the sign conventions of
the moment and the forces (against statics), and the VTU + PVD series writer.  The files hold the
reference points and the ``displacement`` (ParaView's convention); the geometric checks here move the
points to the deformed state first.
"""
from __future__ import annotations

import json
import math
import os
import pathlib
import subprocess
import sys

import numpy as np
import pytest

ROOT = pathlib.Path(__file__).resolve().parents[1]
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))
VTK_LINE, VTK_POLYGON = 3, 7
POINT_ARRAYS = ("displacement", "rotation", "bending_moment")
CELL_ARRAYS = ("axial_force", "shear_force", "part", "rod")


def solve(scene, out, *sets):
    env = dict(os.environ)
    env["PYTHONPATH"] = str(ROOT) + os.pathsep + env.get("PYTHONPATH", "")
    args = [sys.executable, "-m", "femslide", "solve", scene, "--json", "--out", str(out)]
    for s in sets:
        args += ["--set", s]
    r = subprocess.run(args, capture_output=True, text=True, cwd=ROOT, env=env, timeout=120)
    assert r.returncode == 0, r.stderr
    res = json.loads(r.stdout)
    path = out / f"{scene}.vtu"
    assert path.is_file()
    saved = json.loads((out / "result.json").read_text())
    assert str(path) in saved["files"]
    return res, path


def read(path):
    """The VTU with pyvista, its points moved to the deformed state: the file holds the reference
    points and the displacement (ParaView's convention: Warp By Vector draws the deformed state)."""
    pv = pytest.importorskip("pyvista")
    g = pv.read(str(path))
    assert "reference" in str(g.field_data["points"][0])
    g.points = g.points + g.point_data["displacement"]
    return g


def read_meshio(path):
    """The VTU with femslide's reader (meshio underneath; meshio 5 alone cannot read the text arrays),
    its points moved to the deformed state."""
    from femslide.output.vtu import read as read_vtu
    m = read_vtu(str(path))
    m.points = m.points + m.point_data["displacement"]
    return m


def check_layout(g, n_elements, body):
    for name in POINT_ARRAYS:
        assert name in g.point_data, name
    for name in CELL_ARRAYS:
        assert name in g.cell_data, name
    disp = np.asarray(g.point_data["displacement"])
    assert disp.shape == (g.n_points, 3) and np.all(disp[:, 2] == 0)
    for name in ("rotation", "bending_moment"):
        assert g.point_data[name].shape == (g.n_points,)
        assert np.all(np.isfinite(g.point_data[name]))
    part = np.asarray(g.cell_data["part"])
    types = np.asarray(g.celltypes)
    rods = part == 0
    assert rods.sum() == n_elements
    assert np.all(types[rods] == VTK_LINE)
    assert np.all(np.isfinite(g.cell_data["axial_force"][rods]))
    assert np.all(np.isfinite(g.cell_data["shear_force"][rods]))
    poly = np.nonzero(types == VTK_POLYGON)[0]
    if body:
        assert poly.size == 1 and part[poly[0]] == 1 and g.get_cell(poly[0]).n_points == 4
    else:
        assert poly.size == 0 and np.all(rods)
    return poly


def rod_points(g, rod):
    """Deformed nodes of one rod, in node order."""
    ids = [c for c in range(g.n_cells) if g.cell_data["part"][c] == 0 and g.cell_data["rod"][c] == rod]
    conn = np.array([g.get_cell(c).point_ids for c in ids])
    order = np.concatenate([conn[:, 0], conn[-1:, 1]])
    return g.points[order, :2], order


@pytest.mark.parametrize("scene,n_rods", [("beam-slider", 1), ("beam-both", 2)])
def test_structure_vtu(tmp_path, scene, n_rods):
    n = 16
    res, path = solve(scene, tmp_path, f"n_elements={n}")
    g = read(path)
    poly = check_layout(g, n * n_rods, body=True)
    M = np.asarray(g.point_data["bending_moment"])
    assert abs(np.abs(M).max() - res["M_max"]) <= 1e-6 * res["M_max"]
    assert abs(float(g.field_data["phi"][0]) - res["phi"]) <= 1e-9 * abs(res["phi"])
    side = json.loads((tmp_path / f"{scene}.json").read_text())
    assert side["reactions"]["A1"]["Fx"] == pytest.approx(res["reactions"]["A1"]["Fx"], rel=1e-9)
    # body rectangle ABCD (a = 1, b = 0.5: 2 m x 1 m), turned by -phi clockwise-positive
    P = g.points[g.get_cell(poly[0]).point_ids, :2]
    A, B, C, D = P
    assert np.linalg.norm(B - A) == pytest.approx(2.0, rel=1e-12)
    assert np.linalg.norm(D - A) == pytest.approx(1.0, rel=1e-12)
    assert np.allclose(C - B, D - A, atol=1e-12)
    assert math.atan2(-(B - A)[1], (B - A)[0]) == pytest.approx(res["phi"], rel=1e-9)
    e = (D - A) / np.linalg.norm(D - A)
    n_ab = (B - A) / 2.0
    # right rod: pinned at B1 = (2, 0); its top node on the guide line through B along the body axis
    X, _ = rod_points(g, n_rods - 1)
    assert np.allclose(X[0], [2.0, 0.0], atol=1e-12)
    assert abs((X[-1] - B) @ n_ab) < 1e-9
    assert (X[-1] - B) @ e == pytest.approx(res["slide"], rel=1e-9)
    if n_rods == 2:  # left rod pinned at A1 = (0, 0), welded to the body at A
        X, _ = rod_points(g, 0)
        assert np.allclose(X[0], [0.0, 0.0], atol=1e-12)
        assert np.allclose(X[-1], A, atol=1e-9)


def test_adaptive_run_writes_its_finest_mesh(tmp_path):
    res, path = solve("beam-slider", tmp_path)
    g = read(path)
    side = json.loads((tmp_path / "beam-slider.json").read_text())
    M = np.abs(g.point_data["bending_moment"]).max()
    assert M == pytest.approx(side["M_max"], rel=1e-12)
    assert (g.cell_data["part"] == 0).sum() == side["n_elements"]
    # the JSON value is extrapolated; the finest mesh is within its O(h^2) discretisation error
    assert M == pytest.approx(res["M_max"], rel=1e-4)


def test_cantilever_moment_rolls_into_a_half_circle(tmp_path):
    n = 64
    res, path = solve("cantilever-moment", tmp_path, f"n_elements={n}", "m_ratio=0.5")
    g = read(path)
    check_layout(g, n, body=False)
    X, order = rod_points(g, 0)
    assert np.allclose(X[-1], [0.0, 2.0 / math.pi], atol=1e-3)
    # constant internal moment = the applied end moment pi EI/L (counter-clockwise: M = EI dtheta/ds > 0)
    M = np.asarray(g.point_data["bending_moment"])
    assert np.allclose(M, math.pi, rtol=1e-9)
    assert abs(np.abs(M).max() - res["M_max"]) <= 1e-6 * res["M_max"]
    rot = np.asarray(g.point_data["rotation"])[order]
    assert rot[-1] == pytest.approx(math.pi, rel=1e-6)
    assert np.allclose(g.point_data["displacement"][order[-1], :2], [res["tip"]["u"], res["tip"]["v"]], rtol=1e-9)


def test_cantilever_load_force_signs_and_units(tmp_path):
    # L = 2 m, EI = 5 N m^2, tip load P = 3 EI/L^2 = 3.75 N up: SI scaling and the sign conventions
    L, EI, p = 2.0, 5.0, 3.0
    P = p * EI / L ** 2
    n = 16
    res, path = solve("cantilever-load", tmp_path, f"n_elements={n}", f"L={L}", f"EI={EI}", f"p_ratio={p}")
    g = read(path)
    check_layout(g, n, body=False)
    X, order = rod_points(g, 0)
    assert np.allclose(X[0], [0.0, 0.0]) and X[-1, 0] == pytest.approx(L + res["tip"]["u"], rel=1e-9)
    # material before a cut exerts -N t + V n on the material after it: minus the tip load
    for c in range(g.n_cells):
        i, j = g.get_cell(c).point_ids
        t = g.points[j, :2] - g.points[i, :2]
        t /= np.linalg.norm(t)
        nrm = np.array([-t[1], t[0]])
        F = -g.cell_data["axial_force"][c] * t + g.cell_data["shear_force"][c] * nrm
        assert np.allclose(F, [0.0, -P], atol=1e-8 * P)
    # M = P (x_tip - x) >= 0 at every node (the rod curls counter-clockwise)
    M = np.asarray(g.point_data["bending_moment"])[order]
    assert np.allclose(M, P * (X[-1, 0] - X[:, 0]), atol=1e-8 * P * L)


def test_series_round_trips_through_pvd(tmp_path):
    pv = pytest.importorskip("pyvista")
    from femslide.output.vtu import write_series
    times = [0.0, 0.5, 1.25]
    frames = []
    for t in times:
        pts = np.array([[0, 0], [0, 1], [0, 2], [0, 2], [2, 2], [2, 3], [0, 3]], float) + [t, 0]
        cells = [("line", np.array([[0, 1], [1, 2]])), ("polygon", np.array([[3, 4, 5, 6]]))]
        pdata = {"rotation": np.full(7, t), "displacement": np.tile([t, 0.0, 0.0], (7, 1))}
        cdata = {"part": [np.array([0, 0]), np.array([1])], "shear_force": [np.array([t, t]), np.array([np.nan])]}
        frames.append((t, pts, cells, pdata, cdata))
    files = write_series(frames, str(tmp_path), "run")
    assert len(files) == 4 and files[-1].endswith("run.pvd")
    reader = pv.get_reader(str(tmp_path / "run.pvd"))
    assert list(reader.time_values) == times
    for k, t in enumerate(times):
        reader.set_active_time_point(k)
        block = reader.read()[0]
        assert block.n_cells == 3 and list(block.celltypes) == [VTK_LINE, VTK_LINE, VTK_POLYGON]
        assert np.allclose(block.points[:, 0].min(), t)
        assert np.allclose(block.point_data["rotation"], t)
        assert np.allclose(block.cell_data["shear_force"][:2], t)


# -- self-describing output: field data read back with meshio ---------------------------------------------

def test_static_vtu_field_data_units_conventions_joints(tmp_path):
    """Units, conventions and names as text; the joints' types, positions, axes and forces as arrays;
    checked against the sidecar (this mesh's results) and the geometry of the deck."""
    from femslide.output.vtu import text
    res, path = solve("beam-slider", tmp_path, "n_elements=16")
    m = read_meshio(path)
    fd = m.field_data
    units, conv = text(fd, "units"), text(fd, "conventions")
    for word in ("displacement: m", "bending_moment: N m", "axial_force: N", "rotation: rad"):
        assert word in units
    for word in ("x right, y up", "counter-clockwise positive", "N > 0 tension", "M = EI dtheta/ds"):
        assert word in conv
    assert text(fd, "rod_names").split("\n") == ["right"] and text(fd, "body_names") == "deck"
    names = text(fd, "joint_names").split("\n")
    assert names == ["A1", "B1", "clamp"]
    assert fd["joint_type"].ravel().tolist() == [0, 0, 2] and fd["joint_ground"].ravel().tolist() == [1, 1, 0]
    assert text(fd, "joint_type_names").split("\n") == ["pin", "pin", "slider"]
    side = json.loads((tmp_path / "beam-slider.json").read_text())["results_of_this_mesh"]
    F = fd["joint_force"]
    for i, n in enumerate(names):
        j = side["joints"][n]
        assert F[i].tolist() == pytest.approx([j["Fx"], j["Fy"], j["M"]], rel=1e-12, abs=1e-12 * res["M_max"])
    phi = res["phi"]
    assert fd["joint_axis"][2, :2] == pytest.approx([math.sin(phi), math.cos(phi)], abs=1e-12)
    assert fd["joint_inward"][:2, :2].tolist() == [[0.0, 1.0], [0.0, 1.0]]
    assert fd["joint_reference"][:2, :2].tolist() == [[0.0, 0.0], [2.0, 0.0]]
    # the clamp's joint point is the rod's top node
    top = m.points[np.concatenate([c.data for c in m.cells if c.type == "line"])[15, 1], :2]
    assert fd["joint_position"][2, :2] == pytest.approx(top, abs=1e-12)
    assert "distributed_load" in m.cell_data


def test_dynamic_frames_carry_time_and_global_values(tmp_path):
    """Every frame of a simulate series: its time (= the .pvd timestep), phi, F2, slide ... (= the
    history.csv row at that time), units; the telescopic guide link reaches the rod's top end."""
    from femslide.output.vtu import pvd_frames, text
    env = {**os.environ, "PYTHONPATH": str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", "")}
    r = subprocess.run([sys.executable, "-m", "femslide", "simulate", "beam-friction", "--set", "t_end=0.4",
                        "--quiet", "--out", str(tmp_path)], capture_output=True, text=True, cwd=ROOT, env=env,
                       timeout=120)
    assert r.returncode == 0, r.stderr
    H = np.loadtxt(tmp_path / "history.csv", delimiter=",", skiprows=1)
    frames = pvd_frames(str(tmp_path / "beam-friction.pvd"))
    assert len(frames) >= 10
    for t, f in frames:
        m = read_meshio(f)
        fd = m.field_data
        assert float(fd["time"][0]) == t
        row = H[np.argmin(np.abs(H[:, 0] - t))]
        assert row[0] == pytest.approx(t, abs=1e-12)
        for key, col in (("phi", 1), ("phi_dot", 2), ("F2", 3), ("slide", 4), ("F_ax", 6), ("N", 7)):
            assert float(fd[key][0]) == pytest.approx(row[col], rel=1e-12, abs=1e-300), key
        assert "phi: rad" in text(fd, "units") and "F2" in text(fd, "units")
        # the reaction at B1 in the joints' forces is the frame's F2 (horizontal reaction at B1)
        names = text(fd, "joint_names").split("\n")
        assert float(fd["joint_force"][names.index("B1"), 0]) == pytest.approx(float(fd["F2"][0]), rel=1e-9,
                                                                                  abs=1e-12)
        # the rod (L = 1.5 m) ends below the deck (l = 3 m): a rigid link runs from the deck to its top node
        part = [np.asarray(p).ravel() for p in m.cell_data["part"]]
        rods = np.concatenate([c.data[p == 0] for c, p in zip(m.cells, part) if c.type == "line"])
        links = np.concatenate([c.data[p == 2] for c, p in zip(m.cells, part) if c.type == "line"])
        top = m.points[rods[-1, 1], :2]
        ends = m.points[links.ravel(), :2]
        assert np.min(np.hypot(*(ends - top).T)) <= 1e-12


def test_a_body_without_an_outline_is_a_vertex(tmp_path):
    """A block without an outline on a ground slider (no rods): solve --out and simulate --out write
    VTU files with its centroid as a vertex cell (before: meshio failed, 'need at least one array to
    concatenate', and the run ended as an internal error)."""
    import femslide
    from femslide.output.vtu import read
    s = femslide.Structure(gravity=(0.0, -9.81))
    s.body("block", mass=2.0, centroid=(0.0, 0.1), inertia=0.01)
    s.slider("belt", "block", "ground", at=(0.0, 0.1), axis=(1.0, 0.0), k=1000.0)
    r = femslide.solve(s)
    r.write(tmp_path / "s")
    (vtu,) = (tmp_path / "s").glob("*.vtu")
    m = read(str(vtu))
    assert m.cells[0].type == "vertex" and m.points.shape == (1, 3)
    assert np.allclose(m.points[0, :2], (0.0, 0.1))
