"""Scene files (meshes/*.toml) and scene meshes (femslide mesh): every built-in scene has a file holding
its defaults; a file solves like the built-in name on the file's mesh; precedence defaults < file <
--set; a mesh fixes n_elements and must match the geometry; bad files exit 2 with a clear message."""
from __future__ import annotations

import contextlib
import io
import json
import os
import pathlib
import shutil
import subprocess
import sys

import pytest

from femslide.app.cli import main
from femslide.app.scenefile import is_fe, load
from femslide.scenes.catalog import SCENES

ROOT = pathlib.Path(__file__).resolve().parents[1]
MESHES = ROOT / "meshes"
FE = [s for s in SCENES.values() if is_fe(s)]


def cli(*argv):
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(list(argv))
    return code, out.getvalue(), err.getvalue()


def numbers(res):
    """The result's numbers (no timing, no file list)."""
    return {k: v for k, v in res.items() if k not in ("wall_time_s", "import_time_s", "files")}


@pytest.mark.parametrize("name", list(SCENES))
def test_every_builtin_scene_has_a_scene_file_with_its_defaults(name):
    sf = load(str(MESHES / f"{name}.toml"))
    scene = SCENES[name]
    assert sf.scene is scene
    got, want = sf.resolve({}), scene.resolve({})
    if is_fe(scene):
        assert sf.mesh is not None and got["n_elements"] == sf.mesh_n
        got.pop("n_elements"), want.pop("n_elements")
    else:
        assert sf.mesh is None
    assert got == want


@pytest.mark.parametrize("scene", [s.name for s in FE])
def test_committed_meshes_are_what_femslide_mesh_writes(scene, tmp_path):
    import meshio
    import numpy as np
    out = tmp_path / f"{scene}.vtu"
    code, _, err = cli("mesh", scene, "--out", str(out))
    assert code == 0, err
    a, b = meshio.read(MESHES / f"{scene}.vtu"), meshio.read(out)
    assert np.array_equal(a.points, b.points)
    assert [c.type for c in a.cells] == [c.type for c in b.cells]
    assert sorted(a.cell_data) == sorted(b.cell_data)
    assert any(k.startswith("rod:") for k in a.cell_data)


def test_scene_file_solves_like_the_builtin_on_its_mesh():
    code, out, err = cli("solve", str(MESHES / "beam-slider.toml"), "--json")
    assert code == 0, err
    n = load(str(MESHES / "beam-slider.toml")).mesh_n
    code2, out2, _ = cli("solve", "beam-slider", "--set", f"n_elements={n}", "--json")
    a, b = json.loads(out), json.loads(out2)
    assert set(a) == set(b)
    assert numbers(a) == numbers(b)
    # and it is close to the adaptive built-in (the mesh is fine enough)
    _, out3, _ = cli("solve", "beam-slider", "--json")
    assert abs(a["M_max"] / json.loads(out3)["M_max"] - 1) < 1e-6


def test_precedence_defaults_file_set(tmp_path):
    f = tmp_path / "s.toml"
    shutil.copy(MESHES / "beam-slider.vtu", tmp_path / "m.vtu")
    f.write_text('scene = "beam-slider"\nmesh = "m.vtu"\n[parameters]\nEI = 1e8\nd = 0.1\n')
    _, out, _ = cli("solve", str(f), "--json")
    _, ref, _ = cli("solve", "beam-slider", "--set", "EI=1e8", "--set", "d=0.1", "--set", "n_elements=64", "--json")
    assert numbers(json.loads(out)) == numbers(json.loads(ref))
    # --set beats the file, and --set n_elements beats the mesh
    _, out, _ = cli("solve", str(f), "--set", "d=0.3", "--set", "n_elements=8", "--json")
    _, ref, _ = cli("solve", "beam-slider", "--set", "EI=1e8", "--set", "d=0.3", "--set", "n_elements=8", "--json")
    assert numbers(json.loads(out)) == numbers(json.loads(ref))


def test_simulate_scene_file():
    code, out, err = cli("simulate", str(MESHES / "sdof-free.toml"), "--json")
    assert code == 0, err
    _, ref, _ = cli("simulate", "sdof-free", "--json")
    assert numbers(json.loads(out)) == numbers(json.loads(ref))


def test_femslide_mesh_sets_the_element_count(tmp_path):
    out = tmp_path / "m.vtu"
    assert cli("mesh", "beam-both", "--set", "n_elements=10", "--out", str(out))[0] == 0
    f = tmp_path / "s.toml"
    f.write_text('scene = "beam-both"\nmesh = "m.vtu"\n')
    sf = load(str(f))
    assert sf.mesh_n == 10 and sf.resolve({})["n_elements"] == 10
    assert set(sf.mesh.groups) >= {"rod:left", "rod:right", "support:A1", "support:B1", "body"}
    code, _, err = cli("mesh", "hinge-slider")
    assert code == 2 and "takes no mesh" in err


BAD = {
    "unknown key": ('scene = "beam-slider"\nsolver = "fast"\n', "unknown key 'solver'"),
    "unknown scene": ('scene = "beam-slide"\n', "unknown scene 'beam-slide'"),
    "missing mesh": ('scene = "beam-slider"\nmesh = "nowhere.vtu"\n', "nowhere.vtu not found"),
    "mesh without the group": ('scene = "beam-slider"\nmesh = "fixed.vtu"\n', "group 'rod:right'"),
    "malformed": ('scene = "beam-slider\n', "malformed TOML"),
    "unknown parameter": ('scene = "beam-slider"\n[parameters]\nEJ = 1\n', "unknown parameter 'EJ'"),
    "bad value": ('scene = "beam-slider"\n[parameters]\nEI = -1\n', "parameter EI"),
    "mesh for a hinge scene": ('scene = "hinge-slider"\nmesh = "fixed.vtu"\n', "takes no mesh"),
    "geometry": ('scene = "beam-slider"\nmesh = "slider.vtu"\n[parameters]\nl = 4.0\n', "rod:right runs from"),
    "n_elements conflict": ('scene = "beam-slider"\nmesh = "slider.vtu"\n[parameters]\nn_elements = 8\n',
                            "n_elements"),
}


@pytest.mark.parametrize("case", list(BAD))
def test_bad_scene_files_exit_2(case, tmp_path):
    text, msg = BAD[case]
    shutil.copy(MESHES / "beam-fixed.vtu", tmp_path / "fixed.vtu")
    shutil.copy(MESHES / "beam-slider.vtu", tmp_path / "slider.vtu")
    f = tmp_path / "s.toml"
    f.write_text(text)
    code, out, err = cli("solve", str(f), "--json")
    assert code == 2, (out, err)
    assert msg in err and str(f) in err
    assert "Traceback" not in err


def test_set_that_contradicts_the_mesh_is_an_error():
    code, _, err = cli("solve", str(MESHES / "beam-slider.toml"), "--set", "a=1.5")
    assert code == 2 and "rod:right runs from" in err and "a, l, L" in err


def test_non_uniform_mesh_is_rejected(tmp_path):
    import meshio
    m = meshio.read(MESHES / "beam-slider.vtu")
    m.points[1, 1] += 0.01  # second node of the right rod moved along the rod
    m.write(tmp_path / "m.vtu")
    f = tmp_path / "s.toml"
    f.write_text('scene = "beam-slider"\nmesh = "m.vtu"\n')
    code, _, err = cli("solve", str(f))
    assert code == 2 and "equally spaced" in err


def test_hinge_scene_file_imports_nothing_heavy():
    code = ("import sys, io, contextlib\nfrom femslide.app.cli import main\n"
            "with contextlib.redirect_stdout(io.StringIO()):\n"
            f"    rc = main(['solve', {str(MESHES / 'hinge-slider.toml')!r}, '--json'])\n"
            "heavy = [m for m in sys.modules if m.split('.')[0] in ('numpy', 'scipy', 'meshio', 'pyvista')]\n"
            "print(rc, heavy)")
    env = {**os.environ, "PYTHONPATH": str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", "")}
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, timeout=60)
    assert r.stdout.strip() == "0 []", r.stdout + r.stderr
