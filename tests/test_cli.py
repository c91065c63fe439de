"""The command-line contract of SPEC section 7, exercised as a user does: ``python -m femslide ...`` in
a subprocess, checking stdout, stderr and the exit status (0 converged, 1 failed to converge with the
reason on stderr, 2 bad input naming the parameter).  Timing is not tested here (see
validation/bench_cli.py).
"""
from __future__ import annotations

import json
import math
import os
import pathlib
import re
import subprocess
import sys

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[1]
HINGE_SCENES = {
    "hinge-slider": {"a", "b", "d", "l", "m", "g", "l1", "c"},
    "hinge-fixed": {"a", "b", "d", "l", "m", "g", "c"},
    "hinge-spring": {"a", "b", "d", "l", "m", "g", "l1", "c", "k"},
    "hinge-extra-mass": {"a", "b", "d", "l", "m", "g", "l1", "c", "k", "dm", "m1", "l2"},
}
SOLVE_KEYS = {"import_time_s", "converged", "phi", "psi", "slide", "T", "M_max", "reactions", "iterations",
              "error_estimate", "wall_time_s"}
HEAVY = {"numpy", "scipy", "skfem", "pyvista", "meshio", "matplotlib"}


def run(*args, timeout=60):
    env = dict(os.environ)
    env["PYTHONPATH"] = str(ROOT) + os.pathsep + env.get("PYTHONPATH", "")
    env.pop("FEMSLIDE_DEBUG", None)
    return subprocess.run([sys.executable, "-m", "femslide", *args], capture_output=True, text=True,
                          cwd=ROOT, env=env, timeout=timeout)


def test_scenes_lists_the_hinge_scenes_with_parameters():
    r = run("scenes")
    assert r.returncode == 0, r.stderr
    text = r.stdout
    for name, params in HINGE_SCENES.items():
        assert name in text
        # the block of this scene: from its name to the next blank line
        block = text[text.index(name):].split("\n\n", 1)[0]
        listed = {line.split()[0] for line in block.splitlines()[1:] if line.strip()}
        assert params <= listed, (name, params - listed)
    # defaults of section 1 are shown
    block = text[text.index("hinge-slider"):].split("\n\n", 1)[0]
    assert any(line.split()[:2] == ["l1", "1.5"] for line in block.splitlines())
    assert any(line.split()[:2] == ["g", "9.81"] for line in block.splitlines())


def test_scenes_json():
    r = run("scenes", "--json")
    assert r.returncode == 0, r.stderr
    scenes = {s["name"]: s for s in json.loads(r.stdout)}
    for name, params in HINGE_SCENES.items():
        got = {p["name"]: p for p in scenes[name]["params"]}
        assert set(got) == params
        assert scenes[name]["command"] == "solve"
    assert {p["name"]: p["default"] for p in scenes["hinge-extra-mass"]["params"]}["m1"] == 0.1


@pytest.mark.parametrize("scene", list(HINGE_SCENES))
def test_solve_json_keys(scene):
    r = run("solve", scene, "--json")
    assert r.returncode == 0, r.stderr
    res = json.loads(r.stdout)
    assert set(res) == SOLVE_KEYS
    assert res["converged"] is True
    assert set(res["reactions"]) == {"A1", "B1"}
    for support in ("A1", "B1"):
        assert set(res["reactions"][support]) == {"Fx", "Fy"}
        assert all(isinstance(v, float) and math.isfinite(v) for v in res["reactions"][support].values())
    assert res["M_max"] == abs(res["T"])
    assert isinstance(res["iterations"], int)
    assert res["wall_time_s"] >= 0
    # global statics in the JSON itself: F1 + F2 = 0, N1 + N2 = weight (section 1)
    R = res["reactions"]
    assert R["A1"]["Fx"] + R["B1"]["Fx"] == pytest.approx(0.0, abs=1e-9 * abs(R["B1"]["Fx"]) + 1e-12)
    weight = 9.81 * (1.0 + (1e-3 + 0.1 if scene == "hinge-extra-mass" else 0.0))
    assert R["A1"]["Fy"] + R["B1"]["Fy"] == pytest.approx(weight, rel=1e-12)


def test_solve_text_output_and_set():
    r = run("solve", "hinge-slider", "--set", "c=1e8", "--set", "d=0.1")
    assert r.returncode == 0, r.stderr
    assert "phi" in r.stdout and "M_max" in r.stdout
    a = json.loads(run("solve", "hinge-slider", "--set", "c=1e8", "--set", "d=0.1", "--json").stdout)
    b = json.loads(run("solve", "hinge-slider", "--json").stdout)
    assert a["phi"] != b["phi"] and a["M_max"] > b["M_max"]   # --set took effect (c up, M_max up)


BAD = [
    ("hinge-slider", "c=-1", "c"),
    ("hinge-slider", "a=0", "a"),
    ("hinge-slider", "l=nan", "l"),
    ("hinge-slider", "c=abc", "c"),
    ("hinge-slider", "c=inf", "c"),
    ("hinge-slider", "c=-inf", "c"),
    ("hinge-slider", "c=1e400", "c"),
    ("hinge-slider", "bogus=1", "bogus"),
    ("hinge-slider", "l1=4", "l1"),
    ("hinge-spring", "k=-5", "k"),
    ("hinge-fixed", "l1=1", "l1"),           # not a parameter of section 3
    ("hinge-extra-mass", "k=9", "k"),        # below k_crit = 9.197 N/m
    ("hinge-extra-mass", "k=9.19", "k"),
    ("hinge-extra-mass", "dm=-0.1", "dm"),
]


@pytest.mark.parametrize("scene,assignment,name", BAD, ids=[f"{s}-{a}" for s, a, _ in BAD])
def test_bad_input_exits_2_naming_the_parameter(scene, assignment, name):
    r = run("solve", scene, "--set", assignment, "--json")
    assert r.returncode == 2, (r.stdout, r.stderr)
    assert "Traceback" not in r.stderr
    assert r.stdout == ""
    err = r.stderr
    assert name in err and ("allowed" in err), err
    # the parameter is named as a word, not as part of another one
    assert f"parameter {name}" in err or f"'{name}'" in err, err


def test_k_crit_message_gives_the_bound():
    r = run("solve", "hinge-extra-mass", "--set", "k=9", "--json")
    assert r.returncode == 2
    # k_crit = [m g (l+b) + m1 g (l1 + l2/2)] / (4 a^2) = 9.19688 N/m must be stated
    numbers = [float(x) for x in re.findall(r"\d+\.\d+", r.stderr)]
    assert any(abs(x - 9.196875) < 1e-3 for x in numbers), r.stderr
    # just above it is accepted
    ok = run("solve", "hinge-extra-mass", "--set", "k=9.2", "--json")
    assert ok.returncode == 0, ok.stderr


@pytest.mark.parametrize("args", [
    ("solve", "no-such-scene"),
    ("solve",),
    ("frobnicate",),
    ("solve", "hinge-slider", "--set", "c"),
    ("sweep", "hinge-slider", "--vary", "c=1e4,abc", "--json"),
    ("sweep", "hinge-slider", "--vary", "c=", "--json"),
    ("sweep", "hinge-slider", "--vary", "c=1e4", "--set", "c=1e5", "--json"),
], ids=lambda a: " ".join(a))
def test_other_bad_input_exits_2(args):
    r = run(*args)
    assert r.returncode == 2, (r.stdout, r.stderr)
    assert "Traceback" not in r.stderr
    assert r.stderr.strip()
    if "no-such-scene" in args:
        assert "no-such-scene" in r.stderr and "hinge-slider" in r.stderr


def test_sweep_json_is_a_list_of_solve_objects():
    r = run("sweep", "hinge-slider", "--vary", "c=1e4,1e6,1e8", "--json")
    assert r.returncode == 0, r.stderr
    rows = json.loads(r.stdout)
    assert isinstance(rows, list) and len(rows) == 3
    assert [row["c"] for row in rows] == [1e4, 1e6, 1e8]
    for row in rows:
        assert SOLVE_KEYS <= set(row) and row["converged"] is True
    m = [row["M_max"] for row in rows]
    assert m[0] < m[1] < m[2]          # M_max grows with c (like c^(1/3))
    single = json.loads(run("solve", "hinge-slider", "--set", "c=1e6", "--json").stdout)
    assert rows[1]["phi"] == single["phi"] and rows[1]["T"] == single["T"]


def test_failing_solve_exits_1_with_reason():
    """hinge-fixed with c = 1 has no equilibrium on the principal branch (the hinge geometry locks
    at phi = 1.318 rad before the spring can hold the weight)."""
    r = run("solve", "hinge-fixed", "--set", "c=1", "--json")
    assert r.returncode == 1, (r.stdout, r.stderr)
    assert "Traceback" not in r.stderr
    assert "equilibrium" in r.stderr
    res = json.loads(r.stdout)
    assert res["converged"] is False
    assert res.get("reason")
    # without --json: same status, reason on stderr
    r = run("solve", "hinge-fixed", "--set", "c=1")
    assert r.returncode == 1 and "equilibrium" in r.stderr and "Traceback" not in r.stderr


def test_sweep_with_a_failing_case_exits_1_and_keeps_the_others():
    r = run("sweep", "hinge-fixed", "--vary", "c=1,1e6", "--json")
    assert r.returncode == 1
    rows = json.loads(r.stdout)
    assert [row["converged"] for row in rows] == [False, True]
    assert "Traceback" not in r.stderr and "c=1" in r.stderr


def test_out_dir_writes_result_json(tmp_path):
    r = run("solve", "hinge-spring", "--json", "--out", str(tmp_path / "o"))
    assert r.returncode == 0, r.stderr
    saved = json.loads((tmp_path / "o" / "result.json").read_text())
    printed = json.loads(r.stdout)
    assert saved["phi"] == printed["phi"] and saved["reactions"] == printed["reactions"]


_IMPORT_PROBE = r"""
import contextlib, io, json, sys
from femslide.app.cli import main
buf = io.StringIO()
codes = []
with contextlib.redirect_stdout(buf):
    for argv in ARGVS:
        codes.append(main(argv))
print(json.dumps({"codes": codes, "modules": sorted(sys.modules)}))
"""


def _imports_of(argvs, timeout=60):
    """(exit codes, modules loaded) of running the command lines ``argvs`` in one fresh interpreter."""
    env = dict(os.environ)
    env["PYTHONPATH"] = str(ROOT) + os.pathsep + env.get("PYTHONPATH", "")
    code = _IMPORT_PROBE.replace("ARGVS", repr(argvs))
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT, env=env,
                       timeout=timeout)
    assert r.returncode == 0, r.stderr
    out = json.loads(r.stdout.strip().splitlines()[-1])
    return out["codes"], out["modules"]


def test_cli_core_imports_nothing_heavy_for_hinge_scenes():
    """A spring-hinge solve (and listing the scenes) must not import numpy, scipy, skfem, pyvista,
    meshio or matplotlib: the command-line core has to start fast."""
    argvs = [["scenes"], ["scenes", "--json"]] + [["solve", s, "--json"] for s in HINGE_SCENES] \
        + [["sweep", "hinge-slider", "--vary", "c=1e4,1e6", "--json"]]
    codes, modules = _imports_of(argvs)
    assert codes == [0] * len(argvs)
    heavy = sorted(m for m in modules if m.split(".")[0] in HEAVY)
    assert not heavy, heavy


def test_a_structure_solve_without_files_imports_no_writer_machinery():
    """A structure file solved with --json (no --out: no file written) imports neither meshio nor
    pyvista nor the standard library's XML and network stack (xml.sax.saxutils brings urllib.request,
    http, email and ssl: ~50 ms of start-up and ~6 MB of peak memory, for a quoted attribute that
    femslide.output.vtu now writes itself) nor numpy.ma (np.unique imports it: ~17 ms with bytecode,
    ~3 MB); its notes (lift-off, below ground) are still computed."""
    codes, modules = _imports_of([["solve", str(ROOT / "meshes" / "structures" / "two-storey-frame.toml"),
                                   "--json"]], timeout=120)
    assert codes == [0]
    # the notes ran (through femslide.output.vtu's mesh data), and the redundancy check
    assert {"femslide.output.diagrams", "femslide.output.vtu", "femslide.analysis.redundancy"} <= set(modules)
    loaded = sorted(m for m in modules if m.split(".")[0] in ("meshio", "pyvista", "xml", "http", "email", "ssl",
                                                              "matplotlib")
                    or m in ("urllib.request", "numpy.ma"))
    assert not loaded, loaded


@pytest.mark.parametrize("name, extra", [("beam-oscillation", []), ("beam-friction", []),
                                         ("two-storey-frame", ["--set", "simulate.damping.alpha=0.4",
                                                               "--set", "simulate.damping.beta=0.002"])])
def test_a_simulate_imports_no_scipy_modules(name, extra):
    """The time history of section 5.2's structure (no damping, no friction: its static start, modes,
    release check, integration and error estimate) loads LAPACK's compiled wrappers alone, no scipy
    package module (scipy.sparse and scipy.linalg cost ~0.2 s of a 0.6 s run and 27 MB of its peak
    memory, with bytecode: their import chain brings numpy.f2py and numpy.testing) and not numpy.ma;
    its natural frequencies, found with them, are still reported.  So does a structure with a friction
    joint (beam-friction: its stick/slip modes, and the mode watch's friction forces, whose stuck
    tangent is factorised by the model's own dense or band LU, not SuperLU), and a structure under
    Rayleigh damping (the two-storey frame: C = alpha M + beta K0 is a femslide.model.linalg.Coo)."""
    codes, modules = _imports_of([["simulate", str(ROOT / "meshes" / "structures" / f"{name}.toml"),
                                   "--json", "--set", "simulate.t_end=0.3", *extra]], timeout=300)
    assert codes == [0]
    assert {"femslide.analysis.modes", "femslide.analysis.workload", "femslide.results.compare"} <= set(modules)
    if name == "beam-friction":
        assert "femslide.analysis.stickslip" in modules
    loaded = sorted(m for m in modules if (m.split(".")[0] == "scipy" and m != "scipy.linalg._flapack")
                    or m.split(".")[0:2] in (["numpy", "ma"], ["numpy", "f2py"]))
    assert not loaded, loaded


def test_version_prints_the_package_version():
    """`femslide --version` prints `femslide X.Y.Z` (femslide.__version__, the one source of the
    version: pyproject.toml reads it) and, on a second line, which assembly runs (the compiled kernel,
    or numpy and LAPACK when it is not built or FEMSLIDE_KERNEL=numpy switches it off); exits 0."""
    import femslide
    from femslide.model import fast
    r = run("--version")
    assert r.returncode == 0, r.stderr
    first, second = r.stdout.strip().splitlines()
    assert first == f"femslide {femslide.__version__}"
    assert re.fullmatch(r"\d+\.\d+\.\d+", femslide.__version__)
    assert second == fast.status() and second.startswith("assembly: ")
    assert ("compiled kernel (" in second) == fast.available()


def _walk(parser, path=("femslide",)):
    """(command path, action) for every action of the parser and its subcommands."""
    import argparse
    for action in parser._actions:
        yield path, action
        if isinstance(action, argparse._SubParsersAction):
            for name, sub in action.choices.items():
                yield from _walk(sub, path + (name,))


def test_every_command_and_option_has_help():
    """Every option, positional argument and command of the parser has a help text, and every
    command a description (shown by `femslide COMMAND --help`)."""
    import argparse

    from femslide.app.cli import _build_parser
    parser = _build_parser()
    missing, commands = [], 0
    for path, action in _walk(parser):
        name = "/".join(action.option_strings) or action.dest
        if not (action.help or "").strip() or action.help == argparse.SUPPRESS:
            missing.append(f"{' '.join(path)} {name}")
        if isinstance(action, argparse._SubParsersAction):
            helps = {a.dest: a.help for a in action._choices_actions}
            for cmd, sub in action.choices.items():
                commands += 1
                if not (helps.get(cmd) or "").strip():
                    missing.append(f"{' '.join(path)} {cmd} (command)")
                if not (sub.description or "").strip():
                    missing.append(f"{' '.join(path)} {cmd} (description)")
    assert commands >= 7  # scenes solve simulate sweep mesh show init
    assert not missing, missing
    r = run("sweep", "--help")
    assert r.returncode == 0 and "--dask" in r.stdout and "LocalCluster" in r.stdout


def test_init_copies_a_scene_template_and_its_mesh(tmp_path):
    """`femslide init beam-slider DIR` writes the scene file and the mesh it names, which then load
    and check as a scene file; a second init refuses to overwrite (exit 2 naming the file, the files
    unchanged); structures/NAME copies the structure file; an unknown name lists the names."""
    from femslide.app import scenefile, structfile
    d = tmp_path / "new"
    r = run("init", "beam-slider", str(d))
    assert r.returncode == 0, r.stderr
    assert sorted(p.name for p in d.iterdir()) == ["beam-slider.toml", "beam-slider.vtu"]
    sf = scenefile.load(str(d / "beam-slider.toml"))
    assert sf.scene.name == "beam-slider" and sf.mesh is not None and sf.mesh_n > 0
    before = (d / "beam-slider.toml").read_bytes()
    (d / "beam-slider.toml").write_text("# mine\n")
    r = run("init", "beam-slider", str(d))
    assert r.returncode == 2 and "beam-slider.toml exists" in r.stderr
    assert (d / "beam-slider.toml").read_text() == "# mine\n"
    assert before.startswith(b"# beam-slider")
    r = run("init", "structures/beam-both", str(d))
    assert r.returncode == 0, r.stderr
    assert structfile.load(str(d / "beam-both.toml")).structure.rods
    r = run("init", "hinge-slider", str(d / "beam-slider.vtu"))
    assert r.returncode == 2 and "is a file" in r.stderr
    r = run("init", "no-such-scene", str(d))
    assert r.returncode == 2 and "no-such-scene" in r.stderr and "structures/beam-slider" in r.stderr \
        and "hinge-slider" in r.stderr


def test_init_default_folder_is_the_current_one(tmp_path):
    env = dict(os.environ)
    env["PYTHONPATH"] = str(ROOT) + os.pathsep + env.get("PYTHONPATH", "")
    r = subprocess.run([sys.executable, "-m", "femslide", "init", "sdof-free"], capture_output=True,
                       text=True, cwd=tmp_path, env=env, timeout=60)
    assert r.returncode == 0, r.stderr
    assert [p.name for p in tmp_path.iterdir()] == ["sdof-free.toml"]  # no mesh: a dynamic scene
