"""Sweeps: identical rows whichever way they run (in process, --jobs, --dask), a failed case reported in
its row, streaming to DIR/sweep.jsonl and resuming, --plot, and the progress helper."""
from __future__ import annotations

import contextlib
import importlib
import io
import json
import os
import pathlib
import subprocess
import sys

import pytest

from femslide.app.cli import main

ROOT = pathlib.Path(__file__).resolve().parents[1]
VARY = "EI=1e4,1e6,1e8,1e10"


def cli(*argv):
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(list(argv))
    return code, out.getvalue(), err.getvalue()


def run(*argv, code_prefix="", timeout=120):
    env = {**os.environ, "PYTHONPATH": str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", "")}
    if code_prefix:
        cmd = [sys.executable, "-c",
               code_prefix + f"\nfrom femslide.app.cli import main\nsys.exit(main({list(argv)!r}))"]
    else:
        cmd = [sys.executable, "-m", "femslide", *argv]
    return subprocess.run(cmd, capture_output=True, text=True, cwd=ROOT, env=env, timeout=timeout)


def flat(obj, prefix=""):
    out = {}
    for k, v in obj.items():
        if isinstance(v, dict):
            out.update(flat(v, f"{prefix}{k}."))
        elif k not in ("wall_time_s", "import_time_s", "files", "status"):   # (status: sweep rows only)
            out[prefix + k] = v
    return out


def assert_same_rows(a, b, rtol=1e-12):
    assert len(a) == len(b)
    for x, y in zip(a, b):
        fx, fy = flat(x), flat(y)
        assert fx.keys() == fy.keys()
        for k in fx:
            if isinstance(fx[k], float) and k != "error_estimate":
                assert abs(fx[k] - fy[k]) <= rtol * max(abs(fx[k]), abs(fy[k]), 1e-300), (k, fx[k], fy[k])
            elif k != "error_estimate":
                assert fx[k] == fy[k], k


@pytest.fixture(scope="module")
def in_process_rows():
    code, out, err = cli("sweep", "beam-slider", "--vary", VARY, "--json")
    assert code == 0, err
    rows = json.loads(out)
    assert [r["EI"] for r in rows] == [1e4, 1e6, 1e8, 1e10] and all(r["converged"] for r in rows)
    return rows


def test_sweep_row_equals_the_solve_of_that_case(in_process_rows):
    """Cases are solved cold, so a row is exactly `femslide solve` of its parameters."""
    code, out, _ = cli("solve", "beam-slider", "--set", "EI=1e8", "--json")
    assert code == 0
    one = {"EI": 1e8, **json.loads(out)}
    assert_same_rows([in_process_rows[2]], [one], rtol=0.0)


def test_jobs_equals_in_process(in_process_rows):
    r = run("sweep", "beam-slider", "--vary", VARY, "--json", "--jobs", "2")
    assert r.returncode == 0, r.stderr
    assert_same_rows(in_process_rows, json.loads(r.stdout))


@pytest.mark.dask
def test_dask_local_equals_in_process(in_process_rows):
    pytest.importorskip("dask.distributed")
    r = run("sweep", "beam-slider", "--vary", VARY, "--json", "--dask", "local")
    assert r.returncode == 0, r.stderr
    assert_same_rows(in_process_rows, json.loads(r.stdout))


@pytest.mark.dask
def test_dask_scheduler_address(in_process_rows):
    dd = pytest.importorskip("dask.distributed")
    with dd.LocalCluster(n_workers=1, threads_per_worker=1, processes=False, protocol="tcp",
                       dashboard_address=None) as cluster:
        r = run("sweep", "beam-slider", "--vary", "EI=1e4,1e6", "--json", "--dask", cluster.scheduler_address)
    assert r.returncode == 0, r.stderr
    assert_same_rows(in_process_rows[:2], json.loads(r.stdout))


def test_dask_missing_is_bad_input():
    r = run("sweep", "hinge-slider", "--vary", "c=1e4,1e6", "--dask", "local",
            code_prefix="import sys; sys.modules['dask'] = None")
    assert r.returncode == 2 and "femslide[dask]" in r.stderr


def test_failed_case_is_reported_in_its_row_and_the_sweep_goes_on(tmp_path):
    code, out, err = cli("sweep", "beam-extra-mass", "--vary", "k=1,100", "--json", "--out", str(tmp_path))
    rows = json.loads(out)
    assert [r["k"] for r in rows] == [1.0, 100.0]
    assert rows[0]["converged"] is False and "k_crit" in rows[0]["reason"]
    assert rows[1]["converged"] is True
    assert code == 2 and "k=1 failed" in err
    lines = (tmp_path / "sweep.jsonl").read_text().splitlines()
    assert len(lines) == 2


def test_jsonl_stream_and_resume(tmp_path):
    code, out, _ = cli("sweep", "hinge-slider", "--vary", "c=1e4,1e6", "--json", "--out", str(tmp_path))
    assert code == 0
    first = json.loads(out)
    path = tmp_path / "sweep.jsonl"
    recs = [json.loads(x) for x in path.read_text().splitlines()]
    assert [r["c"] for r in recs] == [1e4, 1e6]
    assert all(r["scene"] == "hinge-slider" and r["params"]["c"] == r["c"] and r["status"] == "converged"
               for r in recs)
    # an interrupted write leaves half a line: it is ignored and closed before appending
    with open(path, "a") as fh:
        fh.write('{"c": 1e8, "conv')
    code, out, _ = cli("sweep", "hinge-slider", "--vary", "c=1e4,1e6,1e8", "--json", "--out", str(tmp_path),
                       "--resume")
    assert code == 0
    rows = json.loads(out)
    assert rows[:2] == first  # taken from the file, wall times included
    lines = path.read_text().splitlines()
    assert len(lines) == 4 and json.loads(lines[-1])["c"] == 1e8
    # a different --set is another sweep: not mixed into this folder (bad input, nothing run)
    code, out, err = cli("sweep", "hinge-slider", "--vary", "c=1e4", "--set", "d=0.1", "--json", "--out", str(tmp_path))
    assert code == 2 and "another sweep" in err and "d = default there, 0.1 here" in err
    assert len(path.read_text().splitlines()) == 4


def test_resumed_rows_keep_their_status(tmp_path):
    """A bad-input case (k below k_crit) exits 2; resuming the same sweep from its jsonl must too
    (the stored status was once dropped and re-guessed as a failure, exit 1)."""
    args = ("sweep", "hinge-extra-mass", "--vary", "k=9,100", "--json", "--out", str(tmp_path))
    assert cli(*args)[0] == 2
    assert cli(*args, "--resume")[0] == 2


def test_resume_needs_out():
    code, _, err = cli("sweep", "hinge-slider", "--vary", "c=1e4", "--resume")
    assert code == 2 and "--out" in err


def test_bad_jobs():
    assert cli("sweep", "hinge-slider", "--vary", "c=1e4", "--jobs", "0")[0] == 2
    code, _, err = cli("sweep", "hinge-slider", "--vary", "c=1e4", "--jobs", "2", "--dask", "tcp://127.0.0.1:1")
    assert code == 2 and "--jobs" in err and "--dask local" in err  # a scheduler has its own workers


@pytest.mark.dask
def test_dask_local_jobs_sets_the_workers(monkeypatch):
    """`--dask local --jobs N`: a LocalCluster of N worker processes (N = 2 for 3 cases), rows as in
    process."""
    pytest.importorskip("dask.distributed")
    sweep = importlib.import_module("femslide.app.sweeps")
    seen = []
    real = sweep.dask_client

    def spy(address, workers=None):
        client, cluster = real(address, workers)
        seen.append((address, workers, len(cluster.workers)))
        return client, cluster

    monkeypatch.setattr(sweep, "dask_client", spy)
    args = ("sweep", "hinge-slider", "--vary", "c=1e4,1e5,1e6", "--json")
    code, out, err = cli(*args, "--dask", "local", "--jobs", "2")
    assert code == 0, err
    assert seen == [("local", 2, 2)]
    seen.clear()
    code, out1, err = cli(*args, "--dask", "local", "--jobs", "1")  # one worker when asked for one
    assert code == 0, err
    assert seen == [("local", 1, 1)]
    seen.clear()
    many = ",".join(f"{c:g}" for c in [1e4 * 1.5 ** i for i in range(12)])
    code, _, err = cli("sweep", "hinge-slider", "--vary", f"c={many}", "--json", "--dask", "local")
    assert code == 0, err
    n = min(os.cpu_count() or 1, 8)
    assert seen == [("local", n, n)]  # without --jobs: at most the CPU count, not one per case (12)
    code0, out0, _ = cli(*args)
    assert code0 == 0
    assert_same_rows(json.loads(out0), json.loads(out))


@pytest.mark.dask
def test_dask_relative_paths_are_made_absolute(tmp_path, monkeypatch):
    """Workers whose working folder is not the caller's (as on other machines) still write each case
    into the relative --out given here and read a relative `record` file: both are made absolute
    before submitting.  The workers of this cluster chdir to another folder."""
    dd = pytest.importorskip("dask.distributed")
    import numpy as np
    from distributed.diagnostics.plugin import WorkerPlugin

    elsewhere = tmp_path / "elsewhere"
    here = tmp_path / "here"
    elsewhere.mkdir()
    here.mkdir()
    t = np.linspace(0.0, 2.0, 201)
    np.savetxt(here / "rec.csv", np.c_[t, 5.0 * np.sin(3.0 * t)], delimiter=",", header="t,a", comments="")

    class Chdir(WorkerPlugin):
        def setup(self, worker):
            os.chdir(elsewhere)

    monkeypatch.chdir(here)
    args = ("sweep", "sdof-harmonic", "--set", "record=rec.csv", "--set", "t_end=2", "--vary", "mu=0.1,0.15",
            "--json", "--out", "rel")
    with dd.LocalCluster(n_workers=1, threads_per_worker=1, processes=True, dashboard_address=None) as cluster, \
            dd.Client(cluster) as client:
        register = getattr(client, "register_plugin", None) or client.register_worker_plugin
        register(Chdir())
        assert client.run(os.getcwd) == {a: str(elsewhere) for a in client.scheduler_info()["workers"]}
        code, out, err = cli(*args, "--dask", cluster.scheduler_address)
    assert code == 0, err
    rows = json.loads(out)
    assert all(r["converged"] for r in rows) and any(r["w_max"] > 0 for r in rows)  # the record moved it
    assert sorted(os.listdir(here / "rel")) == ["case_000", "case_001", "sweep.jsonl", "sweep.lock"]
    assert (here / "rel" / "case_000" / "result.json").is_file()
    assert not list(elsewhere.iterdir())
    rec = [json.loads(line) for line in (here / "rel" / "sweep.jsonl").read_text().splitlines()]
    assert [r["params"]["record"] for r in rec] == ["rec.csv", "rec.csv"]  # the sweep's identity unchanged
    (here / "rel2").mkdir()
    code, out2, err = cli(*args[:-1], "rel2")  # in process: the same rows
    assert code == 0, err
    assert_same_rows(rows, json.loads(out2))


def test_absolute_case_makes_paths_absolute(tmp_path, monkeypatch):
    from femslide.app.sweeps import absolute_case
    monkeypatch.chdir(tmp_path)
    name, values, out = absolute_case("sdof-harmonic", {"record": "a/rec.csv", "mu": 0.1}, "o/case_000")
    assert name == "sdof-harmonic" and values == {"record": str(tmp_path / "a" / "rec.csv"), "mu": 0.1}
    assert out == str(tmp_path / "o" / "case_000")
    name, values, out = absolute_case("frame.toml", {"right.EI": 1e6}, None)
    assert name == str(tmp_path / "frame.toml") and values == {"right.EI": 1e6} and out is None


def test_structure_file_sweep_with_out(tmp_path):
    """A structure file swept with --out streams its rows (it once failed: a structure file has no
    scene parameter table)."""
    src = ROOT / "meshes" / "structures" / "cantilever-load.toml"
    code, out, err = cli("sweep", str(src), "--vary", "cantilever.EI=1,2", "--set", "elements=4", "--json",
                         "--out", str(tmp_path / "o"))
    assert code == 0, err
    rec = [json.loads(line) for line in (tmp_path / "o" / "sweep.jsonl").read_text().splitlines()]
    assert [r["params"]["cantilever.EI"] for r in rec] == [1, 2] and rec[0]["fixed"] == {"elements": 4}


def test_plot(tmp_path):
    pytest.importorskip("matplotlib")
    png = tmp_path / "ei.png"
    code, out, err = cli("sweep", "beam-fixed", "--vary", "EI=1e6,1e8", "--plot", str(png), "--json")
    assert code == 0, err
    assert json.loads(out)  # stdout is still the JSON list
    data = png.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 10_000
    png2 = tmp_path / "c.png"
    assert cli("sweep", "hinge-slider", "--vary", "c=1e4,1e6", "--plot", str(png2))[0] == 0
    assert png2.stat().st_size > 10_000


def test_plot_asymptote_is_spec_section_3():
    """The plotted asymptote is femslide.scenes.series.M_max_asymptote, which the FE M_max approaches."""
    from femslide.scenes.series import M_max_asymptote
    code, out, _ = cli("sweep", "beam-slider", "--vary", "EI=1e10", "--json")
    row = json.loads(out)[0]
    p = dict(a=1.0, b=0.5, d=0.2, l=3.0, m=1.0, g=9.81)
    assert abs(row["M_max"] / M_max_asymptote(2, 1e10, **p) - 1) < 1e-3


def test_progress_helper(monkeypatch):
    from femslide.app import progress as pg
    assert isinstance(pg.progress(5, "x", quiet=True), pg.NoBar)
    assert isinstance(pg.progress(5, "x"), pg.NoBar)  # pytest's stderr is not a terminal

    class Tty(io.StringIO):
        def isatty(self):
            return True

    pytest.importorskip("tqdm")
    monkeypatch.setattr(sys, "stderr", Tty())
    bar = pg.progress(3, "x")
    assert not isinstance(bar, pg.NoBar)
    with bar:
        bar.update(3)
    assert "0/3" in sys.stderr.getvalue()  # the bar was drawn (it clears itself when done)
    assert isinstance(pg.progress(3, "x", quiet=True), pg.NoBar)


@pytest.mark.parametrize("scene", ["beam-slider", "beam-both"])
def test_a_case_frozen_from_the_sweeps_structure_equals_freezing_it_anew(scene):
    """A sweep freezes a paper structure once per set of values but EI and EA and derives each case's
    through Frozen.with_stiffness: equal to freezing the case's declaration (every field), its plan in
    model units that of a fresh freeze (the rods' EI and EA rescaled, the rest shared), the case's
    solution the same; a stiffness out of range is BadInput naming the rod and the field."""
    from femslide.errors import BadInput
    from femslide.model.discrete import _plan
    from femslide.model.patterns import PatternCache
    from femslide.scenes import paper
    from femslide.scenes.catalog import SCENES
    cache = PatternCache()
    base = SCENES[scene].resolve({"EI": 1e5})
    paper.frozen(scene, base, cache)
    v = SCENES[scene].resolve({"EI": 3e7})
    fs, fresh = paper.frozen(scene, v, cache), paper.declare(scene, v).freeze()
    assert fs == fresh and fs.derived["stiffness_of"] is not None
    assert [r.EI for r in fs.rods] == [3e7] * len(fs.rods) and [r.EA for r in fs.rods] == [3e13] * len(fs.rods)
    L, F = paper.units(scene, v)
    a, b = _plan(fs, L, F), _plan(fresh, L, F)
    assert a.key == b.key
    for ra, rb in zip(a.rods, b.rods):
        assert (ra.EI, ra.EA) == (rb.EI, rb.EA) and ra.EI == 3e7 / (F * L * L)
    sa = paper.solve_scene(scene, v, cache)
    sb = paper.solve_scene(scene, v)
    assert list(sa.watched) == list(sb.watched) and sa.error_estimate == sb.error_estimate
    with pytest.raises(BadInput, match="rod right: EI"):
        fs.with_stiffness({"right": (-1.0, None)})
    with pytest.raises(BadInput, match="rod nosuch"):
        fs.with_stiffness({"nosuch": (1.0, None)})



def test_the_pattern_cache_is_bounded_and_never_serves_another_key():
    """PatternCache keeps at most ``limit`` entries of each kind, the least recently used dropped; a
    dropped key is rebuilt (its id is new, never an id another key had), a recent one is not; and a
    sweep over a geometry with a cache of 2 entries gives the cases' solutions of fresh solves (the
    cache of a long sweep over geometry kept every model before)."""
    from femslide.model.patterns import PatternCache
    from femslide.scenes import paper
    from femslide.scenes.catalog import SCENES
    cache = PatternCache(limit=3)
    ids = [cache.key_id(("k", i)) for i in range(5)]
    assert ids == [0, 1, 2, 3, 4] and len(cache._ids) == 3
    assert cache.key_id(("k", 4)) == 4 and cache.key_id(("k", 0)) == 5   # (0 was dropped: a new id)
    built = []

    def build(i):
        built.append(i)
        return ("mesh", i)
    for i in (0, 1, 2, 0, 3, 0, 1):
        assert cache.mesh(i, lambda i=i: build(i)) == ("mesh", i)
    assert built == [0, 1, 2, 3, 1] and len(cache._meshes) == 3   # (0 kept by its use, 1 dropped by 3)
    cache = PatternCache(limit=2)
    first = set()
    for d in (0.1, 0.2, 0.3, 0.1, 0.25):
        v = SCENES["beam-slider"].resolve({"d": d, "EI": 1e4})
        got, fresh = paper.solve_scene("beam-slider", v, cache), paper.solve_scene("beam-slider", v)
        assert list(got.watched) == list(fresh.watched) and got.error_estimate == fresh.error_estimate
        first.add(float(got.watched[0]))
    assert len(first) == 4   # (four geometries, four answers)
    assert max(len(cache._frames), len(cache._meshes), len(cache._topologies), len(cache._structures)) <= 2
