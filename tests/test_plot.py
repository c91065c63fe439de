"""Member diagrams: ``femslide.plot`` (matplotlib) and ``femslide show --diagram`` (pyvista).

Checked against independent references: the bending moment of statically determinate beams from
statics (closed forms), the sign convention (M drawn on the tension side), the labelled extremes
against the result's M_max, the lift-off warning of the paper's structure at EI = 10 N m^2, and the
global colour range of a .pvd series.  Render tests (pyvista) are skipped where no off-screen OpenGL
context can be made (the probe of tests/test_show.py).
"""
from __future__ import annotations

import json
import math
import os
import pathlib
import subprocess
import sys
import warnings

import numpy as np
import pytest

import femslide
from femslide.errors import BadInput
from femslide.output.diagrams import LiftOffWarning
from tests.test_show import can_render  # noqa: F401  (the fixture: skip only without an EGL context)

matplotlib = pytest.importorskip("matplotlib")
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[1]


def simple_beam(q=1000.0, L=6.0, elements=3):
    """Pinned at x = 0, on a roller (guide along x) at x = L, uniform load q N/m downwards; a very
    stiff beam, so that the linear closed form M(x) = q x (L - x) / 2 holds to ~1e-9."""
    s = femslide.Structure(gravity=(0.0, 0.0))
    s.rod("beam", start=(0.0, 0.0), end=(L, 0.0), EI=1e12, elements=elements)
    s.pin("A", a="beam.start", b="ground")
    s.roller("B", a="beam.end", b="ground", axis=(1.0, 0.0))
    s.distributed("q", on="beam", force=(0.0, -q))
    return s


def cantilever(P=-50.0, L=2.0, EI=1e4):
    s = femslide.Structure(gravity=(0.0, 0.0))
    s.rod("c", start=(0.0, 0.0), end=(L, 0.0), EI=EI, elements=8)
    s.weld("wall", a="c.start", b="ground")
    s.force("tip", on="c.end", force=(0.0, P))
    return s


def portal():
    s = femslide.Structure(gravity=(0.0, 0.0))
    s.rod("left", start=(0.0, 0.0), end=(0.0, 4.0), EI=8e6)
    s.rod("right", start=(6.0, 0.0), end=(6.0, 4.0), EI=8e6)
    s.rod("beam", start=(0.0, 4.0), end=(6.0, 4.0), EI=2e7)
    s.pin("A", a="left.start", b="ground")
    s.weld("D", a="right.start", b="ground")
    s.weld("B", a="left.end", b="beam.start")
    s.weld("C", a="right.end", b="beam.end")
    s.distributed("snow", on="beam", force=(0.0, -2000.0))
    s.force("wind", on="left.end", force=(1500.0, 0.0))
    return s


def draw(source, **kw):
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        ax = femslide.plot(source, **kw)
    return ax, [x for x in w if issubclass(x.category, LiftOffWarning)]


def test_simple_beam_parabola_between_nodes():
    """q L^2 / 8 at mid-span (closed form), with 3 elements: the midpoint lies inside the middle
    element, so the label is the parabola's interior extremum, not a nodal value (those are q L^2/9).
    Sagging: drawn below the beam (its tension side).  Tolerance 1e-6 relative."""
    q, L = 1000.0, 6.0
    r = femslide.solve(simple_beam(q, L))
    ax, lifts = draw(r, diagram="M")
    d = ax.femslide_diagram
    assert list(d["polygons"]) == ["beam"] and not lifts
    (v, text), = d["extremes"]["beam"]
    assert v == pytest.approx(q * L * L / 8, rel=1e-6)
    assert float(text.get_text().split()[0]) == pytest.approx(q * L * L / 8, rel=5e-4)   # 4 digits
    assert np.abs(r.rod("beam")["M"]).max() == pytest.approx(q * L * L / 9, rel=1e-6)
    xy = d["polygons"]["beam"].get_xy()
    assert xy[:, 1].max() <= 1e-6 and xy[:, 1].min() == pytest.approx(-d["scale"] * q * L * L / 8, rel=1e-6)
    # the automatic scale: the largest value drawn at 15 % of the structure's size (6 m)
    assert d["scale"] * q * L * L / 8 == pytest.approx(0.15 * 6.0, rel=1e-6)
    plt.close(ax.figure)


def test_cantilever_hogging_is_drawn_above():
    """A downward tip load P: M(s) = P (x_tip - x(s)) from statics of the part beyond the cut
    (exact also for large deflections), negative (hogging) and drawn above the rod, on its tension
    side; the label equals the root moment to 1e-9 relative."""
    P, L = -50.0, 2.0
    r = femslide.solve(cantilever(P, L))
    a = r.rod("c")
    M0 = P * (a["x"][-1] - a["x"][0])
    assert M0 < 0
    ax, lifts = draw(r, diagram="M")
    (v, _), = ax.femslide_diagram["extremes"]["c"]
    assert v == pytest.approx(M0, rel=1e-9) and not lifts
    xy = ax.femslide_diagram["polygons"]["c"].get_xy()[:-1]   # matplotlib closes the polygon
    n = len(xy) // 2
    base, off = xy[:n], xy[n:][::-1]
    assert np.all(off[:, 1] >= base[:, 1] - 1e-12)          # above the rod
    assert math.dist(off[0], base[0]) == pytest.approx(-ax.femslide_diagram["scale"] * M0, rel=1e-9)
    plt.close(ax.figure)


@pytest.mark.parametrize("diagram,key", [("M", "M_max"), ("V", "V_max"), ("N", "N_max")])
def test_portal_frame_one_polygon_per_rod_and_extremes(diagram, key):
    """Every rod gets one diagram polygon; the largest |label| of each rod equals the result's
    M_max / V_max / N_max of that rod to 4 digits (the label text) and to 1e-6 (its value)."""
    r = femslide.solve(portal())
    ax, lifts = draw(r, diagram=diagram, magnify=20.0)
    d = ax.femslide_diagram
    assert sorted(d["polygons"]) == ["beam", "left", "right"]
    gids = [p.get_gid() for p in ax.patches if (p.get_gid() or "").startswith("diagram:")]
    assert sorted(gids) == ["diagram:beam", "diagram:left", "diagram:right"]
    for name, ext in d["extremes"].items():
        big = max(ext, key=lambda e: abs(e[0]))
        assert abs(big[0]) == pytest.approx(r["rods"][name][key], rel=1e-6)
        assert abs(float(big[1].get_text().split()[0])) == pytest.approx(r["rods"][name][key], rel=5e-4)
        assert big[1].get_text().endswith("N m" if diagram == "M" else " N")
    assert ax.get_xlabel() == "x [m]" and ax.get_ylabel() == "y [m]"
    assert not lifts     # the pin A carries the frame's weight upwards
    plt.close(ax.figure)


def test_from_a_vtu_file_same_diagram(tmp_path):
    r = femslide.solve(portal())
    files = r.write(str(tmp_path))
    vtu = next(f for f in files if f.endswith(".vtu"))
    ax1, _ = draw(r, diagram="M")
    ax2, _ = draw(vtu, diagram="M")
    for name, ext in ax1.femslide_diagram["extremes"].items():
        e2 = ax2.femslide_diagram["extremes"][name]
        assert [v for v, _ in ext] == pytest.approx([v for v, _ in e2], rel=1e-12)
    assert ax1.femslide_diagram["scale"] == pytest.approx(ax2.femslide_diagram["scale"], rel=1e-12)
    plt.close("all")


def test_lift_off_warning_beam_slider_ei10():
    """At EI = 10 N m^2 the paper's structure falls over (phi = 1.84 rad) and the ground pulls A1
    down (Fy < 0): a warning and a red note name A1."""
    r = femslide.solve("beam-slider", EI=10.0)
    assert r["reactions"]["A1"]["Fy"] < 0
    ax, lifts = draw(r, diagram="M")
    assert len(lifts) == 1 and "A1" in str(lifts[0].message)
    assert ax.femslide_diagram["lift_off"][0][0] == "A1"
    # the finest mesh's value; the result's reaction is extrapolated (they differ by ~1e-6)
    assert ax.femslide_diagram["lift_off"][0][1] == pytest.approx(r["reactions"]["A1"]["Fy"], rel=1e-4)
    assert any("lift-off at A1" in t.get_text() and t.get_color() == "red" for t in ax.texts)
    # the deck passes below the ground line y = 0 (the model has no contact): said too
    low = min(float(np.min(b["Xt"][:, 1])) for b in femslide_frame(r)["bodies"])
    assert low < 0 and ax.femslide_diagram["below_ground"] == pytest.approx(-low, rel=1e-12)
    assert any("below the ground" in t.get_text() for t in ax.texts)
    plt.close(ax.figure)


def femslide_frame(r):
    from femslide.output.diagrams import frame_data
    return frame_data(r)


def test_no_notes_for_a_structure_standing_on_the_ground():
    """The simple beam (pin and roller at y = 0, the ground drawn below both) and the portal frame: no
    lift-off and nothing below the ground."""
    from femslide.output.diagrams import BelowGroundWarning, frame_data, ground_level
    for s in (simple_beam(), portal()):
        r = femslide.solve(s)
        fr = frame_data(r)
        assert ground_level(fr) == 0.0
        assert all(j["inward"].tolist() == [0.0, 1.0] for j in fr["joints"] if j["ground"])
        with warnings.catch_warnings():
            warnings.simplefilter("error", LiftOffWarning)
            warnings.simplefilter("error", BelowGroundWarning)
            ax = femslide.plot(r)
        assert ax.femslide_diagram["below_ground"] == 0.0 and not ax.femslide_diagram["lift_off"]
        plt.close(ax.figure)


def test_bad_input():
    r = femslide.solve(cantilever())
    for kw, word in (({"diagram": "T"}, "diagram"), ({"scale": -1.0}, "scale"),
                     ({"magnify": float("nan")}, "magnify")):
        with pytest.raises(BadInput, match=word):
            femslide.plot(r, **kw)
    with pytest.raises(BadInput, match="no rods"):
        femslide.plot(femslide.solve("hinge-slider"))
    with pytest.raises(BadInput, match="not found"):
        femslide.plot("missing.vtu")
    plt.close("all")


# -- femslide show --diagram (pyvista) -----------------------------------------------------------------

def run(*argv, timeout=120):
    env = {**os.environ, "PYTHONPATH": str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", "")}
    return subprocess.run([sys.executable, "-m", "femslide", *argv], capture_output=True, text=True,
                          cwd=ROOT, env=env, timeout=timeout)


@pytest.fixture(scope="module")
def friction_series(tmp_path_factory):
    d = tmp_path_factory.mktemp("bf")
    r = run("simulate", "beam-friction", "--set", "t_end=0.6", "--quiet", "--out", str(d))
    assert r.returncode == 0, r.stderr
    return d / "beam-friction.pvd"


def test_pvd_colour_range_is_global(friction_series):
    """The colour range of a series is min/max over all its frames (read here with meshio, through
    femslide's reader for the text arrays)."""
    from femslide.output.show import value_range
    from femslide.output.vtu import pvd_frames
    from femslide.output.vtu import read as meshio_read
    lo, hi = math.inf, -math.inf
    for _, f in pvd_frames(str(friction_series)):
        m = meshio_read(f)
        part = np.concatenate([np.asarray(p).ravel() for p in m.cell_data["part"]])
        conn = np.concatenate([c.data for c in m.cells if c.type == "line"])[:(part == 0).sum()]
        M = m.point_data["bending_moment"][np.unique(conn)]
        lo, hi = min(lo, M.min()), max(hi, M.max())
    got = value_range(str(friction_series))
    assert got[1] == pytest.approx(hi, rel=1e-12) and got[0] == pytest.approx(lo, abs=1e-9 * hi)
    last = meshio_read(pvd_frames(str(friction_series))[-1][1])
    assert np.ptp(last.point_data["bending_moment"]) < hi - lo   # one frame alone spans less


def test_constant_field_is_one_value(tmp_path):
    from femslide.output.show import is_constant, value_range
    r = run("solve", "cantilever-moment", "--out", str(tmp_path))
    assert r.returncode == 0, r.stderr
    lo, hi = value_range(str(tmp_path / "cantilever-moment.vtu"))
    assert lo == pytest.approx(math.pi, rel=1e-9) and is_constant(lo, hi)
    assert not is_constant(0.0, 1.0) and not is_constant(3.0, 3.1)


@pytest.mark.render
@pytest.mark.usefixtures("can_render")
def test_show_diagram_screenshot(tmp_path, friction_series):
    from tests.test_show import read_png
    r = run("solve", "beam-slider", "--set", "EI=10", "--out", str(tmp_path))
    assert r.returncode == 0, r.stderr
    for diagram in ("M",):   # V and N share the geometry code (checked above with matplotlib)
        png = tmp_path / f"{diagram}.png"
        r = run("show", str(tmp_path / "beam-slider.vtu"), "--diagram", diagram, "--magnify", "2",
                "--screenshot", str(png))
        assert r.returncode == 0, r.stderr
        assert "lift-off at A1" in r.stderr       # the warning, on stderr
        img = read_png(png)
        assert (np.abs(img - 255).sum(axis=2) > 30).mean() > 0.02        # not blank
        assert ((img[:, :, 0] > 200) & (img[:, :, 1] < 60) & (img[:, :, 2] < 60)).sum() > 50   # red note
    png = tmp_path / "series.png"
    r = run("show", str(friction_series), "--diagram", "M", "--scale", "0.05", "--magnify", "50",
            "--screenshot", str(png))
    assert r.returncode == 0, r.stderr
    assert png.stat().st_size > 1000
    r = run("show", str(friction_series), "--diagram", "Q", "--screenshot", str(tmp_path / "x.png"))
    assert r.returncode == 2
    r = run("show", str(friction_series), "--diagram", "M", "--scale", "-1", "--screenshot", str(tmp_path / "x.png"))
    assert r.returncode == 2 and "--scale" in r.stderr


def test_magnify_scales_the_displacements():
    """Drawn points = undeformed + K (deformed - undeformed), for rods, bodies and joints."""
    from femslide.output.diagrams import frame_data
    r = femslide.solve("beam-slider", EI=1e5)
    f1, f10 = frame_data(r), frame_data(r, magnify=10.0)
    for a, b in zip(f1["rods"] + f1["bodies"] + f1["links"], f10["rods"] + f10["bodies"] + f10["links"]):
        assert np.allclose(b["X"], a["X0"] + 10.0 * (a["X"] - a["X0"]), rtol=0, atol=1e-12)
    for a, b in zip(f1["joints"], f10["joints"]):
        assert np.allclose(b["X"], a["X0"] + 10.0 * (a["X"] - a["X0"]), rtol=0, atol=1e-12)


@pytest.mark.render
@pytest.mark.usefixtures("can_render")
def test_show_series_colour_range_is_global(friction_series):
    """The colour range that show uses for a frame of a series is the range over all frames."""
    from femslide.output.show import value_range
    from tests.test_show import run_py
    code = ("import json\nfrom femslide.output.show import render\n"
            f"info = render({str(friction_series)!r}, frame=0, screenshot={str(friction_series.parent / 'f0.png')!r})\n"
            "print(json.dumps(info['clim']))")
    r = run_py(code)
    assert r.returncode == 0, r.stderr
    clim = json.loads(r.stdout.strip().splitlines()[-1])
    assert clim == pytest.approx(list(value_range(str(friction_series))), rel=1e-12)
    from femslide.output.vtu import pvd_frames, read
    M0 = read(pvd_frames(str(friction_series))[0][1]).point_data["bending_moment"]
    assert np.ptp(M0) < 0.9 * (clim[1] - clim[0])   # not frame 0's own range
