"""`femslide show`: off-screen rendering of a result to PNG, checked by its pixels (not blank; coloured
pixels where the rods are; the grey body).  Skipped when this machine cannot make an off-screen OpenGL
context (no EGL)."""
from __future__ import annotations

import json
import os
import pathlib
import shutil
import subprocess
import sys

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[1]
pytestmark = pytest.mark.render


def run_py(code, timeout=120):
    env = {**os.environ, "PYTHONPATH": str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", "")}
    return subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT, env=env,
                          timeout=timeout)


def femslide(*argv):
    return run_py(f"import sys\nfrom femslide.cli import main\nsys.exit(main({list(argv)!r}))")


@pytest.fixture(scope="module")
def can_render():
    probe = ("import os\nos.environ.setdefault('VTK_DEFAULT_OPENGL_WINDOW', 'vtkEGLRenderWindow')\n"
             "import pyvista as pv\npv.OFF_SCREEN = True\npl = pv.Plotter(off_screen=True, window_size=(64, 64))\n"
             "pl.add_mesh(pv.Line())\nimg = pl.screenshot(return_img=True)\nprint(img.shape)")
    r = run_py(probe)
    if r.returncode != 0:
        pytest.skip(f"no off-screen rendering here: {r.stderr.strip().splitlines()[-1:]}")


@pytest.fixture(scope="module")
def result(tmp_path_factory):
    d = tmp_path_factory.mktemp("res")
    r = femslide("solve", "beam-slider", "--set", "EI=1e3", "--out", str(d))
    assert r.returncode == 0, r.stderr
    return d / "beam-slider.vtu"


def read_png(path):
    import numpy as np
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkIOImage import vtkPNGReader
    rd = vtkPNGReader()
    rd.SetFileName(str(path))
    rd.Update()
    img = rd.GetOutput()
    w, h, _ = img.GetDimensions()
    a = vtk_to_numpy(img.GetPointData().GetScalars()).reshape(h, w, -1)[:, :, :3]
    return np.flipud(a).astype(int)  # row 0 at the top


def test_show_renders_the_deformed_rods_coloured_by_moment(can_render, result, tmp_path):
    import numpy as np
    png = tmp_path / "shot.png"
    code = ("import json\nfrom femslide.show import render\n"
            f"info = render({str(result)!r}, screenshot={str(png)!r})\n"
            "print(json.dumps(info['rod_pixels'].tolist()))")
    r = run_py(code)
    assert r.returncode == 0, r.stderr
    pix = np.array(json.loads(r.stdout.strip().splitlines()[-1]))
    img = read_png(png)
    H, W, _ = img.shape
    background = img[0, -1]  # a corner
    assert (background == 255).all()  # white
    differs = (np.abs(img - background).sum(axis=2) > 30)
    assert differs.mean() > 0.02  # not blank
    sat = img.max(axis=2) - img.min(axis=2) > 60  # coloured (colour map), not grey or white
    hits = 0
    for x, y in pix:
        i, j = int(round(y)), int(round(x))
        assert 0 <= i < H and 0 <= j < W
        hits += sat[max(i - 3, 0):i + 4, max(j - 3, 0):j + 4].any()
    assert hits >= 0.9 * len(pix), (hits, len(pix))
    grey = (np.abs(img - 204).max(axis=2) <= 12)  # the body's light grey
    assert grey.sum() > 2000


def test_show_cli_vtu_pvd_and_errors(can_render, result, tmp_path):
    png = tmp_path / "a.png"
    r = femslide("show", str(result), "--screenshot", str(png))
    assert r.returncode == 0, r.stderr
    assert png.read_bytes()[:4] == b"\x89PNG"
    # a two-frame series of copies: the last frame by default, --frame K, a bad K exits 2
    for k in range(2):
        shutil.copy(result, tmp_path / f"s_{k:04d}.vtu")
    (tmp_path / "s.pvd").write_text(
        '<?xml version="1.0"?>\n<VTKFile type="Collection" version="0.1"><Collection>\n'
        '<DataSet timestep="0" file="s_0000.vtu"/>\n<DataSet timestep="0.5" file="s_0001.vtu"/>\n'
        "</Collection></VTKFile>\n")
    for extra in ([], ["--frame", "0"]):
        out = tmp_path / f"p{len(extra)}.png"
        r = femslide("show", str(tmp_path / "s.pvd"), "--screenshot", str(out), *extra)
        assert r.returncode == 0, r.stderr
        assert out.stat().st_size > 1000
    r = femslide("show", str(tmp_path / "s.pvd"), "--frame", "5", "--screenshot", str(tmp_path / "x.png"))
    assert r.returncode == 2 and "2 frames" in r.stderr
    r = femslide("show", str(tmp_path / "missing.vtu"), "--screenshot", str(tmp_path / "x.png"))
    assert r.returncode == 2 and "not found" in r.stderr


def test_show_a_scene_mesh(can_render, tmp_path):
    png = tmp_path / "mesh.png"
    r = femslide("show", str(ROOT / "meshes" / "beam-both.vtu"), "--screenshot", str(png))
    assert r.returncode == 0, r.stderr
    img = read_png(png)
    assert (img.sum(axis=2) < 600).mean() > 0.005
