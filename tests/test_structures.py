"""Declared structures as a user meets them: the Python API, structure files on the command line
(SPEC section 8: keys of `solve --json`, --out, sweeps over NAME.FIELD) and bad input (exit 2 naming
the object and the field)."""
from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import femslide
from femslide.errors import BadInput
from femslide.model.structure import Structure

ROOT = Path(__file__).resolve().parents[1]
STRUCTURES = ROOT / "meshes" / "structures"

FRAME = """
description = "a column with a deck on a roller"
gravity = [0.0, -9.81]

[[rod]]
name = "col"
start = [0.0, 0.0]
end = [0.0, 3.0]
EI = 2e6
rhoA = 5.0

[[body]]
name = "deck"
mass = 200.0
centroid = [1.0, 3.25]
outline = [[0.0, 3.0], [2.0, 3.0], [2.0, 3.5], [0.0, 3.5]]

[[joint]]
name = "base"
type = "weld"
a = "col.start"
b = "ground"

[[joint]]
name = "top"
type = "pin"
a = "col.end"
b = "deck"

[[joint]]
name = "prop"
type = "roller"
a = "deck"
b = "ground"
at = [2.0, 3.0]
axis = [1.0, 0.0]

[[load]]
name = "wind"
type = "force"
on = "deck"
at = [0.0, 3.5]
force = [500.0, 0.0]
"""


def cli(*args, cwd=ROOT):
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    return subprocess.run([sys.executable, "-m", "femslide", *map(str, args)], capture_output=True, text=True,
                          cwd=cwd, env=env, timeout=300)


@pytest.fixture
def frame_file(tmp_path):
    p = tmp_path / "frame.toml"
    p.write_text(FRAME)
    return p


def test_solve_structure_file_json_keys(frame_file):
    r = cli("solve", frame_file, "--json")
    assert r.returncode == 0, r.stderr
    res = json.loads(r.stdout)
    assert {"converged", "iterations", "error_estimate", "wall_time_s", "bodies", "rods", "joints",
            "reactions"} <= set(res)
    assert res["converged"] is True and res["error_estimate"] <= 1e-6
    assert set(res["bodies"]["deck"]) == {"x", "y", "rotation"}
    assert set(res["rods"]["col"]) == {"M_max", "N_max", "V_max", "s_M_max", "s_N_max", "s_V_max", "start", "end"}
    assert set(res["rods"]["col"]["end"]) == {"u", "v", "theta"}
    assert set(res["joints"]["prop"]) == {"Fx", "Fy", "M", "slide"}
    assert set(res["joints"]["top"]) == {"Fx", "Fy", "M", "rotation"}
    assert set(res["reactions"]) == {"base", "prop"}
    # global equilibrium of the reactions with the loads (gravity on the deck and the column, wind)
    W = 200.0 * 9.81 + 5.0 * 3.0 * 9.81
    Fx = sum(R["Fx"] for R in res["reactions"].values()) + 500.0
    Fy = sum(R["Fy"] for R in res["reactions"].values()) - W
    assert abs(Fx) <= 1e-8 * W and abs(Fy) <= 1e-8 * W


def test_structure_file_out_writes_every_rod_and_body(frame_file, tmp_path):
    out = tmp_path / "out"
    r = cli("solve", frame_file, "--out", out)
    assert r.returncode == 0, r.stderr
    from femslide.output.vtu import read   # meshio underneath (meshio alone cannot read text arrays)
    mesh = read(str(out / "frame.vtu"))
    part = np.concatenate(mesh.cell_data["part"])
    assert (part == 0).sum() >= 2 and (part == 1).sum() == 1   # the column's elements, the deck polygon
    res = json.loads((out / "result.json").read_text())
    assert res["converged"] and "frame.vtu" in " ".join(res["files"])
    side = json.loads((out / "frame.json").read_text())
    assert side["rods"] == ["col"] and side["bodies"] == ["deck"]


def test_set_and_sweep_by_field(frame_file):
    r1 = json.loads(cli("solve", frame_file, "--json", "--set", "col.EI=4e6").stdout)
    r2 = json.loads(cli("solve", frame_file, "--json").stdout)
    assert r1["rods"]["col"]["end"]["u"] == pytest.approx(r2["rods"]["col"]["end"]["u"] / 2, rel=1e-3)
    r = cli("sweep", frame_file, "--vary", "wind.force=[0,0],[500,0]", "--json")
    assert r.returncode == 0, r.stderr
    rows = json.loads(r.stdout)
    assert rows[0]["reactions"]["base"]["Fx"] + rows[0]["reactions"]["prop"]["Fx"] == pytest.approx(0, abs=1e-6)
    assert rows[1]["reactions"]["base"]["Fx"] + rows[1]["reactions"]["prop"]["Fx"] == pytest.approx(-500, rel=1e-9)
    r = cli("sweep", frame_file, "--vary", "col.EI=1e6,4e6", "--json")
    assert r.returncode == 0, r.stderr
    rows = json.loads(r.stdout)
    assert [row["col.EI"] for row in rows] == [1e6, 4e6]
    assert rows[1]["rods"]["col"]["M_max"] > 0


@pytest.mark.parametrize("edit,needle", [
    (("b = \"deck\"", "b = \"desk\""), "desk"),                       # an unknown part
    (("axis = [1.0, 0.0]", "axis = [0.0, 0.0]"), "zero vector"),      # a zero axis
    (("EI = 2e6", "EI = -1"), "EI"),                                  # a negative stiffness
    (("type = \"roller\"", "type = \"hinge\""), "hinge"),            # an unknown joint type
    (("name = \"prop\"", "name = \"top\""), "used twice"),            # a duplicate name
    (("mass = 200.0", "mass = 200.0\ncolour = \"red\""), "colour"),   # an unknown field
])
def test_bad_structure_files_exit_2_naming_the_field(tmp_path, edit, needle):
    p = tmp_path / "bad.toml"
    p.write_text(FRAME.replace(*edit, 1))
    r = cli("solve", p, "--json")
    assert r.returncode == 2, (r.returncode, r.stderr)
    assert needle in r.stderr and "Traceback" not in r.stderr


def test_disconnected_part_is_bad_input():
    s = Structure()
    s.rod("a", (0, 0), (1, 0), EI=1.0)
    s.rod("b", (2, 0), (3, 0), EI=1.0)
    s.weld("w", "a.start", "ground")
    with pytest.raises(BadInput, match="b not connected to the ground"):
        s.freeze()


def test_mechanism_exits_1_naming_the_part(tmp_path):
    p = tmp_path / "cart.toml"
    p.write_text('[[body]]\nname = "cart"\nmass = 1.0\ncentroid = [0.0, -0.5]\n'
                 '[[joint]]\nname = "track"\ntype = "roller"\na = "cart"\nb = "ground"\nat = [0.0, 0.0]\n'
                 'axis = [1.0, 0.0]\n')
    r = cli("solve", p)
    assert r.returncode == 1 and "mechanism" in r.stderr and "cart" in r.stderr


@pytest.mark.parametrize("EA", [1e12, 1e13])
def test_stiff_rod_with_its_own_fine_mesh_is_no_mechanism(EA):
    """A welded cantilever (EI = 1e4, L = 3, EA L^2/EI = 9e8 .. 9e9) with ``elements = 64`` in its
    declaration: before, the path choice ran on the 64-element mesh, whose tangent's eigenvalues span
    more than the round-off test for a null space can separate, and the run failed as a "mechanism".
    Reference: exact statics of the deformed rod, root moment = P (L + u_tip) (1e-9)."""
    s = Structure(gravity=(0.0, 0.0))
    s.rod("c", (0.0, 0.0), (3.0, 0.0), EI=1e4, EA=EA, elements=64)
    s.weld("root", "c.start", "ground")
    s.force("tip", "c.end", force=(0.0, -100.0))
    r = femslide.solve(s)
    x_tip = 3.0 + r["rods"]["c"]["end"]["u"]
    assert r.rod("c")["M"][0] == pytest.approx(-100.0 * x_tip, rel=1e-9)
    assert r["reactions"]["root"]["M"] == pytest.approx(100.0 * x_tip, rel=1e-9)


def test_python_api_result_arrays_and_overrides():
    s = Structure(gravity=(0.0, 0.0))
    s.rod("c", (0.0, 0.0), (2.0, 0.0), EI=1e4)
    s.weld("root", "c.start", "ground")
    s.force("tip", "c.end", force=(0.0, -1.0))
    r = femslide.solve(s)
    a = r.rod("c")
    assert set(a) >= {"s", "x", "y", "u", "v", "theta", "N", "V", "M"}
    assert a["s"][0] == 0.0 and a["s"][-1] == pytest.approx(2.0)
    assert a["M"][0] == pytest.approx(-2.0, rel=1e-6)          # hogging at the root: M = EI dtheta/ds < 0
    stiffer = femslide.solve(s, **{"c.EI": 2e4})
    assert stiffer["rods"]["c"]["end"]["v"] == pytest.approx(r["rods"]["c"]["end"]["v"] / 2, rel=1e-4)
    fixed = femslide.solve(s, elements=4)
    assert fixed.solution.model.elements.size == 4


@pytest.mark.parametrize("name", sorted(p.stem for p in STRUCTURES.glob("*.toml")))
def test_shipped_structure_files_load(name):
    s = femslide.load(str(STRUCTURES / f"{name}.toml"))
    fs = s.freeze()
    assert fs.rods or fs.bodies   # (the dynamic examples belt-ex*.toml are a block on a ground slider)


def test_rod_from_a_mesh_group(tmp_path):
    """A rod's geometry and element count from a meshio line group (femslide mesh writes one)."""
    r = cli("mesh", "beam-slider", "--set", "n_elements=16", "--out", tmp_path / "bs.vtu")
    assert r.returncode == 0, r.stderr
    text = (STRUCTURES / "beam-slider.toml").read_text()
    text = text.replace("start = [2.0, 0.0]\nend = [2.0, 3.0]\n", 'mesh = "bs.vtu"\ngroup = "rod:right"\n')
    (tmp_path / "s.toml").write_text(text)
    res = femslide.solve(str(tmp_path / "s.toml"))
    assert res.solution.model.elements.size == 16
    ref = femslide.solve("beam-slider", n_elements=16)
    assert res["M_max"] == pytest.approx(ref["M_max"], rel=1e-10)
    bad = text.replace('group = "rod:right"', 'group = "rod:nope"')
    (tmp_path / "bad.toml").write_text(bad)
    r = cli("solve", tmp_path / "bad.toml")
    assert r.returncode == 2 and "rod:nope" in r.stderr
