"""`femslide show`: off-screen rendering of a result to PNG, checked by its pixels (not blank; coloured
pixels where the rods are; the grey body).  Skipped only when this machine cannot make an off-screen
OpenGL context at all (asked of EGL directly); a pyvista/VTK that cannot render although EGL works
fails the tests."""
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
    return run_py(f"import sys\nfrom femslide.app.cli import main\nsys.exit(main({list(argv)!r}))")


# Can this machine make an off-screen OpenGL context at all?  Asked of EGL directly (ctypes, no VTK):
# a device display (or the default one), initialised, an OpenGL pbuffer config and a context.  Prints
# "OK ..." or the reason no context can be made.
EGL_PROBE = r"""
import ctypes, ctypes.util
def probe():
    name = ctypes.util.find_library("EGL") or "libEGL.so.1"
    try:
        egl = ctypes.CDLL(name)
    except OSError as exc:
        return f"no EGL library ({exc})"
    vp, ci = ctypes.c_void_p, ctypes.c_int
    egl.eglGetProcAddress.restype, egl.eglGetProcAddress.argtypes = vp, [ctypes.c_char_p]
    egl.eglGetDisplay.restype, egl.eglGetDisplay.argtypes = vp, [vp]
    egl.eglInitialize.argtypes = [vp, ctypes.POINTER(ci), ctypes.POINTER(ci)]
    egl.eglChooseConfig.argtypes = [vp, ctypes.POINTER(ci), ctypes.POINTER(vp), ci, ctypes.POINTER(ci)]
    egl.eglBindAPI.argtypes = [ctypes.c_uint]
    egl.eglCreateContext.restype, egl.eglCreateContext.argtypes = vp, [vp, vp, vp, ctypes.POINTER(ci)]
    displays = []
    q, g = egl.eglGetProcAddress(b"eglQueryDevicesEXT"), egl.eglGetProcAddress(b"eglGetPlatformDisplayEXT")
    if q and g:
        query = ctypes.CFUNCTYPE(ctypes.c_uint, ci, ctypes.POINTER(vp), ctypes.POINTER(ci))(q)
        get = ctypes.CFUNCTYPE(vp, ctypes.c_uint, vp, ctypes.POINTER(ci))(g)
        devs, n = (vp * 16)(), ci(0)
        if query(16, devs, ctypes.byref(n)):
            displays += [get(0x313F, devs[i], None) for i in range(n.value)]  # EGL_PLATFORM_DEVICE_EXT
    displays.append(egl.eglGetDisplay(None))
    why = "no EGL display"
    for dpy in filter(None, displays):
        major, minor = ci(), ci()
        if not egl.eglInitialize(dpy, ctypes.byref(major), ctypes.byref(minor)):
            why = f"eglInitialize failed (EGL error 0x{egl.eglGetError():x})"
            continue
        attrs = (ci * 5)(0x3033, 0x0001, 0x3040, 0x0008, 0x3038)  # PBUFFER surface, OPENGL renderable
        cfg, n = vp(), ci(0)
        if not egl.eglChooseConfig(dpy, attrs, ctypes.byref(cfg), 1, ctypes.byref(n)) or n.value < 1:
            why = "no EGL config for an off-screen OpenGL surface"
            continue
        if not egl.eglBindAPI(0x30A2):  # EGL_OPENGL_API
            why = "EGL cannot bind the OpenGL API"
            continue
        if egl.eglCreateContext(dpy, cfg, None, None):
            return f"OK EGL {major.value}.{minor.value}"
        why = f"eglCreateContext failed (EGL error 0x{egl.eglGetError():x})"
    return why
print(probe())
"""

VTK_PROBE = ("import os\nos.environ.setdefault('VTK_DEFAULT_OPENGL_WINDOW', 'vtkEGLRenderWindow')\n"
             "import pyvista as pv\npv.OFF_SCREEN = True\npl = pv.Plotter(off_screen=True, window_size=(64, 64))\n"
             "pl.add_mesh(pv.Line())\nimg = pl.screenshot(return_img=True)\nprint(img.shape)")


def no_context_reason():
    """None when EGL makes an off-screen OpenGL context on this machine, else why not."""
    r = run_py(EGL_PROBE, timeout=60)
    out = (r.stdout.strip().splitlines() or [f"the EGL probe crashed (exit {r.returncode}): {r.stderr[-300:]}"])[-1]
    return None if out.startswith("OK") else out


@pytest.fixture(scope="module")
def can_render():
    """Skip only when no off-screen OpenGL context can be made here at all (no EGL); fail when one can
    but the installed pyvista/VTK still cannot render (a VTK without EGL, an incompatible pyvista)."""
    r = run_py(VTK_PROBE)
    if r.returncode == 0:
        return
    why = no_context_reason()
    if why is not None:
        pytest.skip(f"no off-screen OpenGL context on this machine: {why}")
    tail = " | ".join(r.stderr.strip().splitlines()[-3:])
    pytest.fail(f"EGL makes an OpenGL context here, but pyvista/VTK cannot render off-screen (exit "
                f"{r.returncode}): {tail}; femslide needs pyvista>=0.45 with vtk>=9.4.2")


def test_egl_probe_tells_a_missing_library():
    """The probe reports a missing EGL as such (the skip reason), not as a crash."""
    code = EGL_PROBE.replace('ctypes.util.find_library("EGL") or "libEGL.so.1"', '"libEGL-missing.so.0"')
    assert code != EGL_PROBE
    r = run_py(code, timeout=60)
    assert r.returncode == 0 and r.stdout.strip().startswith("no EGL library"), r.stdout + r.stderr


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
    code = ("import json\nfrom femslide.output.show import render\n"
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
