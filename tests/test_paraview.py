"""The VTU/PVD files against ParaView's conventions (issue 25), read three ways: with meshio (through
femslide's reader, :func:`femslide.output.vtu.read`: meshio 5 cannot read VTK String arrays), with
VTK's own XML reader and with pyvista (both where installed, as ParaView reads them).

What is checked, each against an independent reference:

- the points are the reference configuration: the declared rod ends and body outline (1e-12 m);
- points + ``displacement`` is the deformed state, and VTK's vtkWarpVector (ParaView's Warp By Vector,
  scale 1) gives it once: the rod ends and body centroid of the result's JSON (1e-9 m);
- text field data are VTK String arrays (vtkStringArray), one string per name, no UInt8 byte arrays;
- global values under the dotted names of ``Result.flat`` and of the time history's columns, in the
  static file and in every frame of a series (1e-12 relative);
- mode shapes: one PVD whose timestep is the mode's number (ParaView steps through the modes as
  through time), each frame with its frequency, the static equilibrium as points and the mode as
  ``displacement``; the forces are the mode's linearised ones: a rod turning rigidly carries no
  bending moment, a point mass on a massless beam vibrates at sqrt(48 EI/(m L^3))/(2 pi) with the
  moment 12 EI w/L^2 at midspan and none at the supports (1e-6);
- the frames of a structure file's time series carry the joints, so that pictures draw the supports.
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

import femslide
import femslide.app.run
import femslide.app.structfile
from femslide.output.vtu import pvd_frames, read, text

ROOT = pathlib.Path(__file__).resolve().parents[1]
STRUCTURES = ROOT / "meshes" / "structures"


def cli(*args, cwd=ROOT):
    env = dict(os.environ, PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    p = subprocess.run([sys.executable, "-m", "femslide", *map(str, args)], capture_output=True, text=True,
                       cwd=cwd, env=env, timeout=300)
    assert p.returncode == 0, p.stderr
    return p.stdout


def frame_structure():
    """A portal frame: two columns welded to the ground, a deck welded on top, wind and gravity."""
    s = femslide.Structure(gravity=(0.0, -9.81))
    s.rod("left", start=(0, 0), end=(0, 3), EI=2e6)
    s.rod("right", start=(4, 0), end=(4, 3), EI=2e6, rhoA=12.0)
    s.body("deck", mass=500.0, centroid=(2.0, 3.25), outline=[(0, 3), (4, 3), (4, 3.5), (0, 3.5)])
    s.weld("A", a="left.start", b="ground")
    s.weld("B", a="right.start", b="ground")
    s.weld("L", a="left.end", b="deck")
    s.weld("R", a="right.end", b="deck")
    s.force("wind", on="deck", force=(8000.0, 0.0), at=(0, 3.5))
    return s


@pytest.fixture(scope="module")
def static_files(tmp_path_factory):
    out = tmp_path_factory.mktemp("static")
    f = out / "frame.toml"
    f.write_text(femslide.app.structfile.dumps(frame_structure()))
    res = json.loads(cli("solve", f, "--json", "--out", out / "res"))
    return res, out / "res" / "frame.vtu"


def _rod_nodes(m, rod):
    """The point ids of a rod's nodes in order (its elements are the first line cells of the file)."""
    mine = []
    for c, part, rods in zip(m.cells, m.cell_data["part"], m.cell_data["rod"]):
        if c.type == "line":
            sel = (np.asarray(part).ravel() == 0) & (np.asarray(rods).ravel() == rod)
            mine.append(c.data[sel])
    mine = np.concatenate(mine)
    return np.concatenate([mine[:, 0], mine[-1:, 1]])


def test_points_are_the_reference_and_displacement_leads_to_the_deformed_state(static_files):
    res, vtu = static_files
    m = read(str(vtu))
    assert "reference" in text(m.field_data, "points")
    P, U = m.points[:, :2], m.point_data["displacement"][:, :2]
    for k, (name, start, end) in enumerate((("left", (0, 0), (0, 3)), ("right", (4, 0), (4, 3)))):
        nodes = _rod_nodes(m, k)
        assert np.allclose(P[nodes[0]], start, atol=1e-12) and np.allclose(P[nodes[-1]], end, atol=1e-12)
        tip = res["rods"][name]["end"]
        assert np.allclose(P[nodes[-1]] + U[nodes[-1]], (end[0] + tip["u"], end[1] + tip["v"]), atol=1e-9)
    part = np.concatenate([np.asarray(p).ravel() for p in m.cell_data["part"]])
    deck = next(c.data[0] for c, p in zip(m.cells, m.cell_data["part"]) if c.type == "polygon")
    assert (part == 1).sum() == 1
    assert np.allclose(P[deck], [(0, 3), (4, 3), (4, 3.5), (0, 3.5)], atol=1e-12)
    # the deformed outline: the body moved rigidly to its result (centroid x, y and rotation)
    b = res["bodies"]["deck"]
    c, s_ = math.cos(b["rotation"]), math.sin(b["rotation"])
    r = P[deck] - (2.0, 3.25)
    expect = np.column_stack([b["x"] + c * r[:, 0] - s_ * r[:, 1], b["y"] + s_ * r[:, 0] + c * r[:, 1]])
    assert np.allclose(P[deck] + U[deck], expect, atol=1e-9)


def test_text_field_data_are_string_arrays_and_values_have_dotted_names(static_files):
    res, vtu = static_files
    m = read(str(vtu))
    fd = m.field_data
    assert isinstance(fd["units"], str) and "bending_moment: N m" in fd["units"]
    assert fd["joint_names"] == ["A", "B", "L", "R"] and fd["rod_names"] == ["left", "right"]
    assert fd["body_names"] == ["deck"] and fd["joint_type_names"] == ["weld"] * 4
    flat = femslide.Result(res).flat()
    for key in ("reactions.A.Fx", "reactions.B.M", "rods.left.M_max", "joints.R.Fy", "bodies.deck.rotation"):
        assert float(np.ravel(fd[key])[0]) == pytest.approx(flat[key], rel=1e-6, abs=1e-9), key
    assert not any("_" in k and k.startswith(("reactions", "rods_", "joints_")) for k in fd)
    raw = vtu.read_text()
    assert 'type="UInt8" Name="units"' not in raw and '<Array type="String" Name="units"' in raw


def test_vtk_reads_the_strings_and_warp_by_vector_deforms_once(static_files):
    """VTK's own XML reader (what ParaView uses) and its vtkWarpVector (ParaView's Warp By Vector)."""
    vtk = pytest.importorskip("vtk")
    res, vtu = static_files
    r = vtk.vtkXMLUnstructuredGridReader()
    r.SetFileName(str(vtu))
    r.Update()
    g = r.GetOutput()
    fd = g.GetFieldData()
    names = fd.GetAbstractArray("joint_names")
    assert names.IsA("vtkStringArray")
    assert [names.GetValue(i) for i in range(names.GetNumberOfValues())] == ["A", "B", "L", "R"]
    units = fd.GetAbstractArray("units")
    assert units.IsA("vtkStringArray") and "N m" in units.GetValue(0)
    assert fd.GetArray("reactions.A.Fx").GetValue(0) == pytest.approx(res["reactions"]["A"]["Fx"], rel=1e-6)
    g.GetPointData().SetActiveVectors("displacement")
    warp = vtk.vtkWarpVector()
    warp.SetInputData(g)
    warp.SetScaleFactor(1.0)
    warp.Update()
    from vtk.util.numpy_support import vtk_to_numpy
    W = vtk_to_numpy(warp.GetOutput().GetPoints().GetData())[:, :2]
    P = vtk_to_numpy(g.GetPoints().GetData())[:, :2]
    U = vtk_to_numpy(g.GetPointData().GetArray("displacement"))[:, :2]
    assert np.allclose(W, P + U, atol=1e-12)
    m = read(str(vtu))
    tip = res["rods"]["right"]["end"]
    top = _rod_nodes(m, 1)[-1]
    assert np.allclose(W[top], (4.0 + tip["u"], 3.0 + tip["v"]), atol=1e-9)


def test_pyvista_reads_the_strings(static_files):
    pv = pytest.importorskip("pyvista")
    res, vtu = static_files
    g = pv.read(str(vtu))
    assert list(g.field_data["joint_names"]) == ["A", "B", "L", "R"]
    assert "N m" in str(g.field_data["units"][0])


# -- modes ----------------------------------------------------------------------------------------------

def mass_on_a_beam(L=4.0, m=50.0, EI=2e5, EA=2e9):
    """A massless simply supported beam (pin, roller along x) of two rods welded to a point mass at
    midspan (no rotary inertia); no gravity, so that the modes are about the straight beam."""
    s = femslide.Structure(gravity=(0.0, 0.0))
    s.rod("left", start=(0, 0), end=(L / 2, 0), EI=EI, EA=EA, elements=8)
    s.rod("right", start=(L / 2, 0), end=(L, 0), EI=EI, EA=EA, elements=8)
    s.body("mass", mass=m, centroid=(L / 2, 0), inertia=0.0)
    s.weld("wl", a="left.end", b="mass")
    s.weld("wr", a="right.start", b="mass")
    s.pin("A", a="left.start", b="ground")
    s.roller("B", a="right.end", b="ground", axis=(1.0, 0.0))
    return s


def test_mode_shapes_are_one_pvd_with_the_mode_number_as_time(tmp_path):
    """A point mass m at the middle of a massless simply supported beam: f1 = sqrt(48 EI / (m L^3)) /
    (2 pi) (the beam's static stiffness under a central load, exact for the cubic elements; measured
    2e-13), the mode's moment 12 EI w / L^2 at midspan (w the central deflection) and zero at the pin
    and the roller (1e-9 of it); the axial mode sqrt(EA / (m L / 2)) / (2 pi) (the left rod holds the
    mass along x); the mode's reactions m omega^2 w / 2 each; 1e-9 relative."""
    L, m_, EI, EA = 4.0, 50.0, 2e5, 2e9
    f = tmp_path / "beam.toml"
    f.write_text(femslide.app.structfile.dumps(mass_on_a_beam(L, m_, EI, EA)))
    res = json.loads(cli("modes", f, "--count", "4", "--json", "--out", tmp_path / "out"))
    freq = res["frequencies_hz"]
    # the mass's x and y are the only motions with mass (its rotation and the rods are massless): two
    # modes, and the output says so
    assert len(freq) == 2 and any("2 of the 4" in n for n in res["notes"])
    assert freq[0] == pytest.approx(math.sqrt(48 * EI / (m_ * L ** 3)) / (2 * math.pi), rel=1e-9)
    assert freq[1] == pytest.approx(math.sqrt(EA / (L / 2) / m_) / (2 * math.pi), rel=1e-9)
    pvd = tmp_path / "out" / "beam_modes.pvd"
    frames = pvd_frames(str(pvd))
    assert [t for t, _ in frames] == [1.0, 2.0]
    for k, (_t, vtu) in enumerate(frames):
        mm = read(vtu)
        fd = mm.field_data
        assert float(fd["mode"][0]) == k + 1 and float(fd["frequency_hz"][0]) == pytest.approx(freq[k], rel=1e-12)
        assert "equilibrium" in text(fd, "points")
        U = mm.point_data["displacement"][:, :2]
        assert np.abs(U).max() == pytest.approx(0.05 * L, rel=1e-9)   # 5 % of the structure's size
    m1 = read(frames[0][1])
    left, right = _rod_nodes(m1, 0), _rod_nodes(m1, 1)
    M = m1.point_data["bending_moment"]
    w = m1.point_data["displacement"][left[-1], 1]
    M_mid = 12 * EI * w / L ** 2
    assert abs(M[left[-1]]) == pytest.approx(abs(M_mid), rel=1e-9)
    assert abs(M[left[0]]) <= 1e-9 * abs(M_mid) and abs(M[right[-1]]) <= 1e-9 * abs(M_mid)
    # the linearised reactions of the mode: half the mass's inertia force m omega^2 w each
    names = m1.field_data["joint_names"]
    Fy = m1.field_data["joint_force"][:, 1]
    inertia = m_ * (2 * math.pi * freq[0]) ** 2 * abs(w)
    assert abs(Fy[names.index("A")]) == pytest.approx(inertia / 2, rel=1e-9)
    assert abs(Fy[names.index("B")]) == pytest.approx(inertia / 2, rel=1e-9)
    pv = pytest.importorskip("pyvista")
    reader = pv.get_reader(str(pvd))
    assert list(reader.time_values) == [1.0, 2.0]


def test_mode_of_a_rigidly_rotating_rod_has_no_moment_at_its_pin(tmp_path):
    """beam-oscillation.toml, mode 1: the deck turns about A1 and the right rod, pinned at B1 and held
    across the deck's guide, turns rigidly with it (the guide point moves by (-1.5, 2) theta: the rod
    rotation theta equals the deck's).  Before, the mode's VTU showed M = +-5440 N m, at the pin too.
    Reference: zero, to 1e-8 of EI w / l^2 (the moment of a rod bent by the mode's displacement w;
    measured 5e-10); the axial force is the inertia of the mode (16.0 N, nonzero)."""
    out = tmp_path / "out"
    cli("modes", STRUCTURES / "beam-oscillation.toml", "--json", "--out", out)
    m = read(str(out / "beam-oscillation_mode1.vtu"))
    nodes = _rod_nodes(m, 0)
    M = m.point_data["bending_moment"][nodes]
    w = np.abs(m.point_data["displacement"]).max()
    assert np.abs(M).max() <= 1e-8 * 1e6 * w / 1.5 ** 2
    assert np.abs(m.point_data["axial_force"][nodes]).min() > 1.0


def test_second_mode_of_beam_oscillation_is_the_pieces_axial_vibration():
    """The 410935 Hz mode is real: the telescopic piece (0.1 kg) on the massless right rod (EA = 1e12 N,
    1.5 m) in the direction of the guide; closed form sqrt(EA / (L m)) / (2 pi) = 410936 Hz (the deck's
    coupling changes it by 3e-6)."""
    r = femslide.app.run.run_case(femslide.app.structfile.load(str(STRUCTURES / "beam-oscillation.toml")).for_modes(),
                                  {"_count": 4})
    f2 = math.sqrt(1e12 / (1.5 * 0.1)) / (2 * math.pi)
    assert r["frequencies_hz"][1] == pytest.approx(f2, rel=1e-5)


# -- time series ----------------------------------------------------------------------------------------

def test_time_series_frames_carry_the_joints_and_reference_points(tmp_path):
    from femslide.output.diagrams import frame_data, shapes
    out = tmp_path / "out"
    cli("simulate", STRUCTURES / "beam-oscillation.toml", "--set", "simulate.t_end=0.2", "--quiet", "--out", out)
    frames = pvd_frames(str(out / "beam-oscillation.pvd"))
    H = np.loadtxt(out / "history.csv", delimiter=",", skiprows=1)
    cols = (out / "history.csv").read_text().splitlines()[0].split(",")
    col = {c.split(" [")[0]: i for i, c in enumerate(cols)}
    for t, vtu in frames[:: max(1, len(frames) // 5)]:
        m = read(vtu)
        fd = m.field_data
        assert fd["joint_names"] == ["A1", "B1", "clamp", "piece_weld"]
        assert "reference" in text(fd, "points")
        row = H[np.argmin(np.abs(H[:, 0] - t))]
        assert float(fd["reactions.B1.Fx"][0]) == pytest.approx(row[col["reactions.B1.Fx"]], rel=1e-12)
        nodes = _rod_nodes(m, 0)
        assert np.allclose(m.points[nodes[0], :2], (2.0, 0.0), atol=1e-12)   # B1, the reference
        fr = frame_data(vtu)
        assert len(fr["joints"]) == 4 and any(j["ground"] for j in fr["joints"])
        assert len(shapes(fr)) >= 2   # the supports and the ground line are drawn


# -- a light install ------------------------------------------------------------------------------------

def test_pyvista_and_vtk_are_an_optional_extra():
    """The base install writes every file with meshio; pyvista and VTK (566 MB) come with femslide[view]
    (and with femslide[test], so that the render tests run)."""
    try:
        import tomllib
    except ModuleNotFoundError:  # Python 3.10
        import tomli as tomllib
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    base = " ".join(project["dependencies"])
    assert "pyvista" not in base and "vtk" not in base
    extras = project["optional-dependencies"]
    for extra in ("view", "test"):
        assert any(r.startswith("pyvista") for r in extras[extra]) and any(r.startswith("vtk") for r in extras[extra])


BLOCK = """
import sys
class Block:
    def find_spec(self, name, path=None, target=None):
        if name.split('.')[0] in ('pyvista', 'vtk', 'vtkmodules'):
            raise ModuleNotFoundError(name)
sys.meta_path.insert(0, Block())
import importlib.util
_orig = importlib.util.find_spec
importlib.util.find_spec = lambda n, *a: None if n.split('.')[0] in ('pyvista', 'vtk', 'vtkmodules') else _orig(n, *a)
from femslide.app.cli import main
sys.exit(main(sys.argv[1:]))
"""


def test_show_without_pyvista_names_the_extra_and_solve_still_writes_files(tmp_path):
    """With pyvista and VTK unimportable (as after `pip install femslide`): solve --out writes its VTU
    (meshio), show exits 2 naming femslide[view] (before anything is read)."""
    env = dict(os.environ, PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    out = tmp_path / "out"
    p = subprocess.run([sys.executable, "-c", BLOCK, "solve", "beam-slider", "--out", str(out)], capture_output=True,
                       text=True, cwd=ROOT, env=env, timeout=120)
    assert p.returncode == 0, p.stderr
    assert (out / "beam-slider.vtu").is_file()
    p = subprocess.run([sys.executable, "-c", BLOCK, "show", str(out / "beam-slider.vtu"), "--screenshot",
                        str(tmp_path / "x.png")], capture_output=True, text=True, cwd=ROOT, env=env, timeout=120)
    assert p.returncode == 2, p.stderr
    assert "pip install 'femslide[view]'" in p.stderr and "Traceback" not in p.stderr
    assert not (tmp_path / "x.png").exists()
