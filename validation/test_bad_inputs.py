"""Regression tests of issue 25: the last bad inputs and false failures found by trying femslide as a
new user would.  Each case misbehaved before the fix (noted per test): an internal error, a wrong
exit status, a silently ignored setting or a misleading reason.

Each test runs the command line (``femslide.app.cli.main`` in process, or ``python -m femslide`` in a
subprocess where the process itself matters) or the Python API, and checks the exit status (0
converged, 1 failed with a reason, 2 bad input naming the parameter or file), the message, and -
where a run converges - the answer against an independent reference (stated per test).
"""
from __future__ import annotations

import contextlib
import io
import os
import pathlib
import subprocess
import sys

import pytest

import femslide
import femslide.app.run
import femslide.app.structfile
from femslide.app.cli import main

HERE = pathlib.Path(__file__).resolve().parent
ROOT = HERE.parent
STRUCTURES = ROOT / "meshes" / "structures"


def cli(*argv):
    """``femslide.app.cli.main`` in process: (exit status, stdout, stderr)."""
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main([str(a) for a in argv])
    return code, out.getvalue(), err.getvalue()


def run(*args, timeout=120, cwd=ROOT):
    """``python -m femslide ARGS`` in a subprocess: (exit status, stdout, stderr)."""
    env = dict(os.environ, PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    env.pop("FEMSLIDE_DEBUG", None)
    p = subprocess.run([sys.executable, "-m", "femslide", *map(str, args)], capture_output=True, text=True,
                       cwd=cwd, env=env, timeout=timeout)
    return p.returncode, p.stdout, p.stderr


def clean(err, *names):
    """One femslide message naming ``names``: no traceback, no internal error, no numpy warning."""
    assert "Traceback" not in err and "internal error" not in err, err
    assert "Warning" not in err, err
    for n in names:
        assert n in err, (n, err)


# -- the Python API's target ------------------------------------------------------------------------------
# Before: femslide.solve(123) raised AttributeError, femslide.solve(femslide.Structure()) ValueError.

@pytest.mark.parametrize("target", [123, None, "", 1.5, ["frame.toml"]])
@pytest.mark.parametrize("func", [femslide.solve, femslide.simulate])
def test_api_target_of_the_wrong_type_is_bad_input(func, target):
    with pytest.raises(femslide.BadInput, match="target .*allowed: a femslide.Structure"):
        func(target)


def test_empty_structure_is_bad_input():
    with pytest.raises(femslide.BadInput, match="no rods and no bodies"):
        femslide.solve(femslide.Structure())


# -- TOML files -------------------------------------------------------------------------------------------
# Before: nesting 5000 deep was a RecursionError (internal error); a file starting with a UTF-8 byte
# order mark was called a "scene file" with "malformed TOML" at line 1.

@pytest.mark.parametrize("text", ["x = " + "[" * 5000 + "]" * 5000, "x = " + "{a = " * 5000 + "1" + "}" * 5000])
def test_deeply_nested_toml_is_bad_input(tmp_path, text):
    f = tmp_path / "deep.toml"
    f.write_text(text + "\n")
    code, out, err = cli("solve", f, "--json")
    assert code == 2, err
    clean(err, str(f), "nested too deeply")


def test_deeply_nested_set_value_is_bad_input():
    code, out, err = cli("solve", STRUCTURES / "beam-slider.toml", "--set", "wind.force=" + "[" * 3000 + "]" * 3000)
    assert code == 2, err
    clean(err)


def test_structure_file_with_a_byte_order_mark_solves_as_without(tmp_path):
    """Reference: the same file without the mark (the same bytes after it): identical results."""
    src = (STRUCTURES / "beam-slider.toml").read_bytes()
    f = tmp_path / "bom.toml"
    f.write_bytes(b"\xef\xbb\xbf" + src)
    with_bom = femslide.solve(str(f))
    plain = femslide.solve(str(STRUCTURES / "beam-slider.toml"))
    assert with_bom["M_max"] == plain["M_max"]
    assert femslide.load(str(f)).rods.keys() == femslide.load(str(STRUCTURES / "beam-slider.toml")).rods.keys()


# -- near-zero rods ---------------------------------------------------------------------------------------
# Before: a rod 1e-12 m long on a 3 m column asked for 3e12 elements per level (MemoryError, 43.7 TiB:
# "internal error"); 2 mm read as a mechanism.

def _column_with_stub(tmp_path, stub, EA=None):
    f = tmp_path / "stub.toml"
    f.write_text(f"""
[[rod]]
name = "col"
start = [0.0, 0.0]
end = [0.0, 3.0]
EI = 1e6
[[rod]]
name = "stub"
start = [0.0, 3.0]
end = [{stub!r}, 3.0]
EI = 1e6
{'' if EA is None else f'EA = {EA!r}'}
[[joint]]
name = "A"
type = "weld"
a = "col.start"
b = "ground"
[[joint]]
name = "W"
type = "weld"
a = "stub.start"
b = "col.end"
[[load]]
name = "P"
type = "force"
on = "stub.end"
force = [1000.0, -1000.0]
""")
    return f


@pytest.mark.parametrize("stub", [1e-12, 1e-6, 2e-3])
def test_near_zero_rod_is_bad_input(tmp_path, stub):
    code, out, err = cli("solve", _column_with_stub(tmp_path, stub), "--json")
    assert code == 2, err
    clean(err, "rod stub", "length", "allowed: a rod of at least 0.003 m")


def test_short_rod_at_the_limit_solves(tmp_path):
    """A 3 mm stub (1e-3 of the structure's size) on a 3 m column solves.  Reference: moment
    equilibrium of the whole structure about the support A, exact for any deformation: M_A = -(x_P F_y
    - y_P F_x), P the stub's end where the load acts (its deformed position from the result); 1e-9
    relative."""
    r = femslide.solve(str(_column_with_stub(tmp_path, 3e-3)))
    tip = r["rods"]["stub"]["end"]
    xP, yP = 3e-3 + tip["u"], 3.0 + tip["v"]
    M_exact = -(xP * -1000.0 - yP * 1000.0)
    assert abs(r["reactions"]["A"]["M"] - M_exact) <= 1e-9 * abs(M_exact)
    assert r["error_estimate"] <= 1e-6


def test_stiffness_contrast_is_named_in_the_mechanism_message(tmp_path):
    """EA = 1e15 N on a 1 cm stub: its axial stiffness is ~1e13 times the column's bending stiffness;
    before, the failure read as a free part only."""
    code, out, err = cli("solve", _column_with_stub(tmp_path, 1e-2, EA=1e15))
    assert code == 1, err
    clean(err, "beyond double precision", "rigid body or a weld")


# -- redundant joints --------------------------------------------------------------------------------------
# Before: "load stepping stalled at load factor 0: a limit point or a bifurcation (singular matrix)".

def _frame(*joints):
    s = femslide.Structure()
    s.rod("col", start=(0, 0), end=(0, 3), EI=1e6)
    s.body("deck", mass=100.0, centroid=(1, 3.5), outline=[(0, 3), (2, 3), (2, 4), (0, 4)])
    s.weld("top", a="col.end", b="deck")
    for kind, name, a, kw in joints:
        getattr(s, kind)(name, a=a, b="ground", **kw)
    return s


@pytest.mark.parametrize("joints, named", [
    ([("weld", "W1", "col.start", {}), ("weld", "W2", "col.start", {})], "W1, W2"),
    ([("pin", "A", "col.start", {}), ("roller", "R", "col.start", {"axis": (1, 0)})], "A, R"),
    ([("weld", "A", "col.start", {}), ("pin", "P", "col.start", {})], "A, P"),
    ([("weld", "A", "col.start", {}), ("slider", "S1", "deck", {"at": (2, 3), "axis": (0, 1)}),
      ("slider", "S2", "deck", {"at": (2, 3.5), "axis": (0, 1)})], "S1, S2"),
])
def test_redundant_joints_are_named(joints, named):
    with pytest.raises(femslide.BadInput, match=f"joints {named} hold the same freedom more than once"):
        femslide.solve(_frame(*joints))


def test_redundant_welds_exit_2_on_the_command_line(tmp_path):
    f = tmp_path / "welds.toml"
    f.write_text(femslide.app.structfile.dumps(_frame(("weld", "W1", "col.start", {}),
                                                      ("weld", "W2", "col.start", {}))))
    code, out, err = cli("solve", f)
    assert code == 2, err
    clean(err, "W1, W2", "undetermined")


def test_two_rollers_on_a_welded_frame_are_not_redundant():
    """Two parallel rollers on the deck of a frame welded at its base hold the deck's x and rotation
    (two independent equations): statically indeterminate, not redundant.  Reference: the deck's
    weight goes down the column (the rollers are vertical guides: no vertical force), so the base
    reaction is (.., 100 g, ..) to 1e-9 and the column carries no moment beyond round-off."""
    r = femslide.solve(_frame(("weld", "A", "col.start", {}),
                              ("roller", "R1", "deck", {"at": (2, 3), "axis": (0, 1)}),
                              ("roller", "R2", "deck", {"at": (2, 3.5), "axis": (0, 1)})))
    assert abs(r["reactions"]["A"]["Fy"] - 100.0 * 9.81) <= 1e-9 * 981.0
    assert r["rods"]["col"]["M_max"] <= 1e-6


# -- ground records in a structure file -------------------------------------------------------------------
# Before: an .AT2 with NaN and a CSV record of 1e308 ran into exit 1 with a numpy warning and a source
# line on stderr (the scene path already said exit 2).

def _at2(path, bad=None):
    import numpy as np
    t = np.arange(0.0, 2.0, 0.01)
    g = 0.1 * np.sin(2 * np.pi * t)
    rows = ["  ".join(f"{x: .7E}" for x in g[i:i + 5]) for i in range(0, g.size, 5)]
    if bad is not None:
        rows[7] = rows[7].replace(rows[7].split()[2], bad)
    path.write_text(f"PEER NGA\nsynthetic\nACCELERATION IN G\nNPTS= {t.size}, DT= 0.0100 SEC\n"
                    + "\n".join(rows) + "\n")
    return path


@pytest.mark.parametrize("bad", ["NaN", "inf", "-Infinity"])
def test_at2_record_with_nan_or_inf_is_bad_input_naming_the_line(tmp_path, bad):
    rec = _at2(tmp_path / "rec.AT2", bad)
    code, out, err = run("simulate", STRUCTURES / "beam-oscillation.toml", "--quiet", "--set", "simulate.t_end=0.5",
                         "--set", f'simulate.ground={{direction = [1, 0], record = "{rec}"}}')
    assert code == 2, err
    clean(err, str(rec), "line 12", "allowed: finite")


@pytest.mark.parametrize("ground, named", [
    ('{direction = [1, 0], record = "REC"}', "reaches |a| = 1e+308"),
    ('{direction = [1, 0], record = "REC", scale = 1e300}', "scale 1e+300"),
    ("{direction = [1, 0], amplitude = 1e308, frequency = 1.0}", "amplitude = 1e+308"),
])
def test_overflowing_ground_motion_is_bad_input(tmp_path, ground, named):
    rec = tmp_path / "huge.csv"
    rec.write_text("t,a\n0,1e308\n1,-1e308\n2,1e308\n" if "scale" not in ground else "t,a\n0,1\n1,-1\n2,1\n")
    code, out, err = run("simulate", STRUCTURES / "beam-oscillation.toml", "--quiet", "--set", "simulate.t_end=0.5",
                         "--set", "simulate.ground=" + ground.replace("REC", str(rec)))
    assert code == 2, err
    clean(err, named, "allowed: |a")


# -- two sweeps into one --out ----------------------------------------------------------------------------
# Before: both exited 0, every case row was written twice and the same case folders by both.

def test_second_sweep_into_the_same_out_is_refused_while_the_first_runs(tmp_path):
    import time

    from femslide.app.sweeps import LOCK, _lock
    out = tmp_path / "sw"
    env = dict(os.environ, PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    first = subprocess.Popen([sys.executable, "-m", "femslide", "sweep", "sdof-harmonic", "--vary",
                              "t_end=20000,20001", "--out", str(out), "--quiet"], cwd=ROOT, env=env,
                             stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        for _ in range(600):   # until the first sweep holds the lock (its pid in the lock file)
            if (out / LOCK).exists() and (out / LOCK).read_text().strip() == str(first.pid):
                break
            time.sleep(0.05)
        else:
            pytest.fail("the first sweep did not start")
        assert first.poll() is None
        code, text, err = cli("sweep", "sdof-harmonic", "--vary", "t_end=20000,20001", "--out", out, "--quiet")
        assert code == 2, err
        clean(err, f"--out {out}", f"another sweep (process {first.pid})", "one sweep at a time")
        assert not (out / "sweep.jsonl").exists() or (out / "sweep.jsonl").read_text().count("\n") <= 2
    finally:
        first.kill()
        first.wait()
    _lock(str(out)).close()   # a sweep that died leaves no stale lock: the next one goes on


# -- what the output says ---------------------------------------------------------------------------------
# Before: the paper's near-mechanism under 800 N of wind swayed 22.6 degrees with support A1 pulled down
# by 2091 N, reported as plain `converged` (only `femslide show` printed the lift-off); the text output
# had no units and `files: [2 entries]` hid the paths written.

def _paper_under_wind():
    s = femslide.Structure(gravity=(0.0, -9.81))
    s.rod("left", start=(0, 0), end=(0, 3), EI=2e6)
    s.rod("right", start=(2, 0), end=(2, 3), EI=2e6, rhoA=12.0)
    s.body("deck", mass=500.0, centroid=(1.0, 3.5), outline=[(0, 3), (2, 3), (2, 4), (0, 4)])
    s.pin("A1", a="left.start", b="ground")
    s.pin("B1", a="right.start", b="ground")
    s.weld("A", a="left.end", b="deck")
    s.slider("clamp", a="right.end", b="deck", axis=(0, 1))
    s.force("wind", on="deck", force=(800.0, 0.0), at=(0, 4))
    return s


def test_lift_off_is_a_note_of_the_solve_output(tmp_path):
    """The note's force is the reaction's vertical component (the pin rests on level ground: inward
    +y), 1e-12 relative."""
    r = femslide.solve(_paper_under_wind())
    Fy = r["reactions"]["A1"]["Fy"]
    assert Fy < -2000.0
    assert len(r["notes"]) == 1 and r["notes"][0].startswith(f"lift-off at A1: the ground pulls with {-Fy:.4g} N")
    f = tmp_path / "paper.toml"
    f.write_text(femslide.app.structfile.dumps(_paper_under_wind()))
    code, out, err = cli("solve", f, "--out", tmp_path / "out")
    assert code == 0, err
    assert "note: lift-off at A1" in out
    # every path written, one a line; values with their units
    assert f"file: {tmp_path / 'out' / 'paper.vtu'}" in out and f"file: {tmp_path / 'out' / 'paper.json'}" in out
    assert "entries]" not in out
    assert "reactions.A1: Fx=" in out and " N, Fy=" in out and " N m" in out and "rotation=" in out and " rad" in out
    assert "M_max: " in out.replace("  ", " ") and "wall_time_s:" in out


def test_a_portal_frame_under_roof_load_and_wind_has_no_notes():
    s = femslide.Structure(gravity=(0.0, -9.81))
    s.rod("left", start=(0, 0), end=(0, 4), EI=1.2e7)
    s.rod("right", start=(6, 0), end=(6, 4), EI=1.2e7)
    s.rod("beam", start=(0, 4), end=(6, 4), EI=4e7, rhoA=60.0)
    s.weld("A", a="left.start", b="ground")
    s.weld("B", a="right.start", b="ground")
    s.weld("corner", a="beam.start", b="left.end")
    s.slider("bearing", a="right.end", b="beam.end", axis=(1, 0))
    s.distributed("roof", on="beam", force=(0.0, -8000.0))
    s.force("wind", on="left.end", force=(6000.0, 0.0))
    assert femslide.solve(s)["notes"] == []


# -- belt-ex3.toml is paper 003's example 3, not its mirror image --------------------------------------------
# Before: the ground amplitude +4.905 m/s^2 gave the force -P0 sin(theta t).

def test_belt_ex3_moves_as_the_papers_example_3():
    """Reference: femslide simulate sdof-harmonic (paper 003 ex. 3, the exact event-by-event solution):
    its first turning point w = +0.0124628 m at t = 0.2021157 s; the structure file at tolerance 1e-7:
    the first slip positive and the largest slide within 1e-6 m of it."""
    ref = femslide.simulate("sdof-harmonic", t_end=0.25)["turning_points"][0]
    assert ref["w"] > 0
    r = femslide.simulate(str(STRUCTURES / "belt-ex3.toml"), t_end=0.25, tolerance=1e-7)
    slips = [e["kind"] for e in r["events"]["belt"] if e["kind"].startswith("slip")]
    assert slips[0] == "slip+"
    assert abs(r["peaks"]["joints"]["belt"]["slide_max"] - ref["w"]) <= 1e-6


# -- one rule for numbers --------------------------------------------------------------------------------
# Before: EI = "2e6" was accepted while elements = "8" was rejected.

@pytest.mark.parametrize("field, value", [("right.EI", '"2e6"'), ("right.elements", '"8"'), ("clamp.k", '"100"'),
                                          ("deck.mass", '"1"'), ("right.rhoA", "true"), ("simulate.t_end", '"3"')])
def test_a_number_written_as_text_is_bad_input(tmp_path, field, value):
    src = (STRUCTURES / "beam-oscillation.toml").read_text()
    name, key = field.split(".")
    if name == "simulate":
        src = src.replace("[simulate]\n", f"[simulate]\n{key} = {value}\n").replace("t_end = 3.0\n", "")
    else:
        table = {"right": '"right"', "clamp": '"clamp"', "deck": '"deck"'}[name]
        src = src.replace(f"name = {table}\n", f"name = {table}\n{key} = {value}\n", 1)
        src = "\n".join(ln for ln in src.splitlines() if not (ln.startswith(f"{key} = ") and value not in ln)) + "\n"
    f = tmp_path / "s.toml"
    f.write_text(src)
    code, out, err = cli("simulate" if name == "simulate" else "solve", f, "--quiet")
    assert code == 2, err
    clean(err, key)
    assert "not a number" in err or "allowed: an integer" in err


def test_numbers_from_the_command_line_are_still_numbers():
    """--set values are parsed (right.EI=2e6 is the number 2e6): the same answer as in the file."""
    a = femslide.solve(str(STRUCTURES / "beam-slider.toml"), **{"right.EI": "2e6"})
    b = femslide.solve(str(STRUCTURES / "beam-slider.toml"), **{"right.EI": 2e6})
    assert a["M_max"] == b["M_max"]


# -- --set elements=N is every rod's mesh ---------------------------------------------------------------------
# Before: it was silently ignored by modes and simulate for rods that declare their own `elements`.

def test_set_elements_applies_to_rods_with_their_own_mesh():
    """beam-oscillation.toml declares right.elements = 8.  Reference for the effect: the first
    frequency converges like h^2 (README), so 4 and 32 elements differ."""
    f = str(STRUCTURES / "beam-oscillation.toml")
    for n in (4, 32):
        code, out, err = cli("modes", f, "--set", f"elements={n}", "--json", "--quiet")
        assert code == 0, err
        assert '"elements": {"right": %d}' % n in out
    code, out, err = cli("modes", f, "--set", "elements=32", "--set", "right.elements=16", "--json", "--quiet")
    assert '"elements": {"right": 16}' in out        # a rod named explicitly keeps its own
    a = femslide.app.run.run_case(femslide.app.structfile.load(f).for_modes(), {"elements": 4})
    b = femslide.app.run.run_case(femslide.app.structfile.load(f).for_modes(), {"elements": 32})
    assert a["frequencies_hz"][0] != b["frequencies_hz"][0]
    code, out, err = cli("simulate", f, "--set", "elements=4", "--set", "simulate.t_end=0.02", "--json", "--quiet")
    assert code == 0, err
    assert '"elements": {"right": 4}' in out


# -- a release that only the stiffest parts can follow ------------------------------------------------------
# Before: initial = {body = "deck", rotation = -0.01} on a frame welded at its bases and to its deck ran
# 110 s and failed (Newton at t = 0.045 s, step 3.4e-13 s).

WELDED_FRAME = """
gravity = [0.0, -9.81]
[[rod]]
name = "left"
start = [0.0, 0.0]
end = [0.0, 3.0]
EI = 2e6
[[rod]]
name = "right"
start = [2.0, 0.0]
end = [2.0, 3.0]
EI = 2e6
rhoA = 12.0
[[body]]
name = "deck"
mass = 500.0
centroid = [1.0, 3.5]
outline = [[0.0, 3.0], [2.0, 3.0], [2.0, 4.0], [0.0, 4.0]]
[[joint]]
name = "A1"
type = "weld"
a = "left.start"
b = "ground"
[[joint]]
name = "B1"
type = "weld"
a = "right.start"
b = "ground"
[[joint]]
name = "A"
type = "weld"
a = "left.end"
b = "deck"
[[joint]]
name = "B"
type = "weld"
a = "right.end"
b = "deck"
[simulate]
t_end = 3.0
initial = {body = "deck", rotation = -0.01}
"""


def test_release_too_fast_to_follow_is_bad_input_at_once(tmp_path):
    """The deck, held turned on columns welded to it, rocks on the columns' axial stiffness (EA =
    1e6 EI): closed form sqrt(2 EA a^2 / (l J)) / (2 pi) = 12.7 kHz (a = 1 m each side, l = 3 m, J =
    m (2^2 + 1^2) / 12 the deck's inertia); the message's frequency within 5 % (the columns' bending
    and mass).  Exit 2 naming initial, within seconds, for t_end = 40 s (~26 h of work at 12.7 kHz;
    issue 24: only runs estimated beyond 24 h are refused)."""
    import re
    import time
    f = tmp_path / "frame.toml"
    f.write_text(WELDED_FRAME)
    t0 = time.perf_counter()
    code, out, err = cli("simulate", f, "--set", "simulate.t_end=40", "--quiet")
    assert time.perf_counter() - t0 < 30
    assert code == 2, err
    clean(err, "initial", "a displacement u of a body")
    got = float(re.search(r"a mode of ([0-9.e+]+) Hz", err).group(1))
    J = 500.0 * (2.0 ** 2 + 1.0 ** 2) / 12.0
    ref = (2 * 2e12 * 1.0 ** 2 / (3.0 * J)) ** 0.5 / (2 * 3.141592653589793)
    assert abs(got / ref - 1) < 0.05
