"""What the pictures write besides the diagrams (issue 25): load and reaction arrows with their values,
the moment at every sliding bearing, kN units and round colour-bar ticks.

The reference of every number written is the result's own JSON value of the same quantity (the
picture must show what the solve computed: 4 significant digits), and the geometry of an arrow is
checked against the load's direction and point of application (the deformed point of the declared
load, 1e-12 m).
"""
from __future__ import annotations

import math
import os
import pathlib
import subprocess
import sys

import numpy as np
import pytest

import femslide
import femslide.app.structfile
from femslide.output.arrows import arrows, bearing_labels, nice_ticks, value_text
from femslide.output.diagrams import frame_data

ROOT = pathlib.Path(__file__).resolve().parents[1]


def portal():
    """A portal frame: fixed bases, a rigid left corner, the beam in a sliding clamp on the right
    column, a roof load and wind."""
    s = femslide.Structure(gravity=(0.0, -9.81))
    s.rod("left", start=(0, 0), end=(0, 4), EI=1.2e7)
    s.rod("right", start=(6, 0), end=(6, 4), EI=1.2e7)
    s.rod("beam", start=(0, 4), end=(6, 4), EI=4e7)
    s.weld("A", a="left.start", b="ground")
    s.weld("B", a="right.start", b="ground")
    s.weld("corner", a="beam.start", b="left.end")
    s.slider("bearing", a="right.end", b="beam.end", axis=(1, 0))
    s.distributed("roof", on="beam", force=(0.0, -8000.0))
    s.force("wind", on="left.end", force=(6000.0, 0.0))
    return s


@pytest.fixture(scope="module")
def solved():
    return femslide.solve(portal())


def test_nice_ticks_are_round_and_inside():
    assert nice_ticks(-18.19, 38.9) == [-10.0, 0.0, 10.0, 20.0, 30.0]
    assert nice_ticks(12000.0, 15800.0) == [12000.0, 13000.0, 14000.0, 15000.0]
    assert nice_ticks(0.0, 1.0) == [0.0, 0.2, 0.4, 0.6, 0.8, 1.0]


def test_arrows_of_loads_and_reactions(solved):
    fr = frame_data(solved)
    got = arrows(fr, units="kN")
    kinds = [a["kind"] for a in got]
    assert kinds.count("reaction") == 2 and kinds.count("load") == 1 and kinds.count("distributed") >= 3
    wind = next(a for a in got if a["kind"] == "load")
    tip = solved["rods"]["left"]["end"]
    assert np.allclose(wind["head"], (0.0 + tip["u"], 4.0 + tip["v"]), atol=1e-12)   # at the deformed point
    d = wind["head"] - wind["tail"]
    assert d[0] > 0 and abs(d[1]) < 1e-12 * abs(d[0])                                 # along the wind
    assert wind["label"] == "wind: 6 kN"
    A = solved["reactions"]["A"]
    ra = next(a for a in got if a["kind"] == "reaction" and a["label"].startswith("A:"))
    assert ra["label"] == (f"A: Fx = {A['Fx'] / 1e3:.4g} kN, Fy = {A['Fy'] / 1e3:.4g} kN, "
                           f"M = {A['M'] / 1e3:.4g} kN m")
    d = ra["head"] - ra["tail"]
    assert math.atan2(d[1], d[0]) == pytest.approx(math.atan2(A["Fy"], A["Fx"]), abs=1e-9)  # (finest mesh: raw)
    roof = [a for a in got if a["kind"] == "distributed" and a["label"]]
    assert len(roof) == 1 and roof[0]["label"] == "beam: q = 8 kN/m"


def test_the_moment_in_the_sliding_bearing_is_written(solved):
    """The moment the sliding clamp transmits (what the users of this project study)."""
    (P, text), = bearing_labels(frame_data(solved), units="kN")
    assert text == f"bearing: M = {solved['joints']['bearing']['M'] / 1e3:.4g} kN m"
    assert abs(solved["joints"]["bearing"]["M"]) > 1e3


def test_plot_writes_kilonewtons(solved):
    pytest.importorskip("matplotlib")
    import matplotlib
    matplotlib.use("Agg")
    ax = femslide.plot(solved, "M", units="kN")
    info = ax.femslide_diagram
    assert len(info["arrows"]) >= 6 and len(info["bearings"]) == 1
    texts = [t.get_text() for t in ax.texts]
    assert value_text(solved["rods"]["beam"]["M_max"], "N m", "kN") in " ".join(texts)
    assert "[kN m]" in ax.get_title()
    with pytest.raises(femslide.BadInput, match="units"):
        femslide.plot(solved, "M", units="MN")


def test_show_with_units_and_arrows_renders(tmp_path):
    """`femslide show --units kN` (and --diagram M): off-screen pictures are written (skipped without
    an OpenGL context, as the render tests)."""
    pytest.importorskip("pyvista")
    env = dict(os.environ, PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    f = tmp_path / "portal.toml"
    f.write_text(femslide.app.structfile.dumps(portal()))
    p = subprocess.run([sys.executable, "-m", "femslide", "solve", str(f), "--out", str(tmp_path / "o"), "--quiet"],
                       capture_output=True, text=True, env=env, timeout=200)
    assert p.returncode == 0, p.stderr
    for extra in ([], ["--diagram", "M"]):
        png = tmp_path / f"p{len(extra)}.png"
        p = subprocess.run([sys.executable, "-m", "femslide", "show", str(tmp_path / "o" / "portal.vtu"), "--units",
                            "kN", "--screenshot", str(png), *extra], capture_output=True, text=True, env=env,
                           timeout=200)
        if p.returncode != 0 and ("EGL" in p.stderr or "OpenGL" in p.stderr or "display" in p.stderr.lower()):
            pytest.skip("no off-screen OpenGL context here")
        assert p.returncode == 0, p.stderr
        assert png.stat().st_size > 1000
