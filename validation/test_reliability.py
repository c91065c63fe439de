"""Regression tests of issue 12: never exit 0 with a wrong, NaN or unconverged answer; bounded time
and memory; output paths checked before any work; unreadable inputs named.

Each test runs the command line as a user does (``python -m femslide ...`` in a subprocess, or
``femslide.cli.main`` in process where that is enough) and checks the exit status (0 converged, 1
failed with a reason, 2 bad input naming the parameter or file), the message, and - where a run
converges - the answer against an independent reference.  Every case here misbehaved before the
fix (noted per test).
"""
from __future__ import annotations

import contextlib
import io
import json
import math
import os
import pathlib
import subprocess
import sys
import time

import pytest

HERE = pathlib.Path(__file__).resolve().parent
ROOT = HERE.parent
for _p in (str(ROOT), str(HERE)):
    if _p not in sys.path:
        sys.path.insert(0, _p)

from femslide.cli import main  # noqa: E402


def run(*args, timeout=120):
    """``python -m femslide ARGS``: (exit status, stdout, stderr, wall time)."""
    env = dict(os.environ)
    env["PYTHONPATH"] = str(ROOT) + os.pathsep + env.get("PYTHONPATH", "")
    env.pop("FEMSLIDE_DEBUG", None)
    t0 = time.perf_counter()
    p = subprocess.run([sys.executable, "-m", "femslide", *args], capture_output=True, text=True,
                       cwd=ROOT, env=env, timeout=timeout)
    return p.returncode, p.stdout, p.stderr, time.perf_counter() - t0


def cli(*argv):
    """``femslide.cli.main`` in process: (exit status, stdout, stderr)."""
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main([str(a) for a in argv])
    return code, out.getvalue(), err.getvalue()


def clean_error(code, err, *names):
    """Exit 2 or 1 with one femslide message naming ``names``; no traceback, no internal error."""
    assert "Traceback" not in err and "internal error" not in err, err
    assert "RuntimeWarning" not in err, err
    for n in names:
        assert n in err, (n, err)


# -- output paths: checked before any work ---------------------------------------------------------------
# Before: the whole solve or sweep ran, then "internal error" (exit 1).

SLOW_SWEEP = ("sweep", "sdof-harmonic", "--vary", "t_end=20000,20001", "--quiet")


@pytest.mark.parametrize("make, args, option", [
    (lambda d: (d / "afile").write_text("x") and d / "afile", ("simulate", "sdof-harmonic", "--set", "t_end=20000"), "--out"),
    (lambda d: d / "afile" / "sub", ("simulate", "sdof-harmonic", "--set", "t_end=20000"), "--out"),
    (lambda d: "/proc/femslide-out", ("solve", "beam-slider"), "--out"),
    (lambda d: "/proc/femslide-out", SLOW_SWEEP, "--out"),
])
def test_out_path_is_checked_before_the_work(tmp_path, make, args, option):
    (tmp_path / "afile").write_text("x")
    path = make(tmp_path)
    code, out, err, dt = run(*args, option, str(path))
    assert code == 2, err
    clean_error(code, err, option, str(path))
    assert dt < 10  # rejected at once: the run itself takes longer


@pytest.mark.parametrize("plot", ["x.xyz", "/proc/femslide/x.png"])
def test_plot_path_is_checked_before_the_sweep(tmp_path, plot):
    path = plot if plot.startswith("/") else str(tmp_path / plot)
    code, out, err, dt = run(*SLOW_SWEEP, "--plot", path)
    assert code == 2
    clean_error(code, err, "--plot", path)
    assert dt < 10


def test_screenshot_path_and_corrupt_vtu(tmp_path):
    bad = tmp_path / "corrupt.vtu"
    bad.write_text("<VTKFile> this is not a VTU")
    code, _, err, _ = run("show", str(bad), "--screenshot", str(tmp_path / "x.png"))
    assert code == 2
    clean_error(code, err, str(bad))
    good = tmp_path / "res"
    assert run("solve", "beam-slider", "--set", "n_elements=4", "--out", str(good))[0] == 0
    vtu = next(good.glob("*.vtu"))
    code, _, err, _ = run("show", str(vtu), "--screenshot", "/proc/femslide/x.png")
    assert code == 2
    clean_error(code, err, "--screenshot", "/proc/femslide/x.png")


def test_scene_file_with_a_corrupt_mesh_names_the_file(tmp_path):
    """Before: exit 1 with meshio's bare 'Couldn't read file' (meshio calls sys.exit)."""
    (tmp_path / "bad.vtu").write_text("garbage")
    scene = tmp_path / "s.toml"
    scene.write_text('scene = "beam-slider"\nmesh = "bad.vtu"\n')
    code, _, err, _ = run("solve", str(scene))
    assert code == 2
    clean_error(code, err, "bad.vtu", str(scene))


# -- sweeps: one sweep per folder, case files never overwritten --------------------------------------------

def test_second_sweep_with_other_parameters_is_refused(tmp_path):
    """Before: the second sweep restarted at case 0 and overwrote the first sweep's case files."""
    code, out, err = cli("sweep", "beam-slider", "--vary", "EI=1e6,1e8", "--set", "n_elements=4",
                         "--json", "--quiet", "--out", tmp_path)
    assert code == 0, err
    first = json.loads(out)
    before = {p: p.read_bytes() for p in tmp_path.rglob("*") if p.is_file()}
    for extra in (("--set", "n_elements=8"), ("--set", "n_elements=4", "--set", "d=0.1")):
        for resume in ((), ("--resume",)):
            code, out, err = cli("sweep", "beam-slider", "--vary", "EI=1e6,1e8", *extra, "--json",
                                 "--quiet", "--out", tmp_path, *resume)
            assert code == 2 and "another sweep" in err and str(tmp_path) in err, err
    other_scene = cli("sweep", "beam-fixed", "--vary", "EI=1e6", "--set", "n_elements=4", "--quiet",
                      "--out", tmp_path)
    assert other_scene[0] == 2 and "scene beam-slider, not beam-fixed" in other_scene[2]
    after = {p: p.read_bytes() for p in tmp_path.rglob("*") if p.is_file()}
    assert after == before  # nothing written, nothing overwritten
    # the same sweep with one more value: resumed; the new case gets a new folder, rows point at
    # their own files
    code, out, err = cli("sweep", "beam-slider", "--vary", "EI=1e7,1e6,1e8", "--set", "n_elements=4",
                         "--json", "--quiet", "--out", tmp_path, "--resume")
    assert code == 0, err
    rows = json.loads(out)
    assert rows[1] == first[0] and rows[2] == first[1]
    recs = [json.loads(x) for x in (tmp_path / "sweep.jsonl").read_text().splitlines()]
    assert [r["case"] for r in recs] == [0, 1, 2] and recs[2]["params"]["EI"] == 1e7
    assert all(r["version"] and r["varied"] == "EI" for r in recs)
    for r in recs:
        assert all(f"case_{r['case']:03d}" in f for f in r["files"]), r["files"]
    after2 = {p: p.read_bytes() for p in tmp_path.rglob("*") if p.is_file() and "case_002" not in str(p)}
    assert {p: b for p, b in after2.items() if p.name != "sweep.jsonl"} == \
        {p: b for p, b in before.items() if p.name != "sweep.jsonl"}


def test_resume_key_includes_the_version(tmp_path):
    code, out, err = cli("sweep", "hinge-slider", "--vary", "c=1e6,1e7", "--json", "--quiet", "--out", tmp_path)
    assert code == 0
    path = tmp_path / "sweep.jsonl"
    recs = [json.loads(x) for x in path.read_text().splitlines()]
    path.write_text("".join(json.dumps({**r, "version": "0.0.1"}) + "\n" for r in recs))
    code, out, err = cli("sweep", "hinge-slider", "--vary", "c=1e6,1e7", "--json", "--quiet", "--out",
                         tmp_path, "--resume")
    assert code == 2 and "femslide 0.0.1" in err
