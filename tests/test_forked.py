"""The error estimate's check run beside the run (femslide.analysis.forked): the child's result, its
failures, and a simulate whose estimate is made in a child equal to one made after the run.  The
forking cases run in a fresh interpreter: a process with other threads (the test session's, after a
dask test) forks no child."""
from __future__ import annotations

import json
import os
import pathlib
import subprocess
import sys

import pytest

from femslide.analysis import forked

ROOT = pathlib.Path(__file__).resolve().parents[1]
needs_fork = pytest.mark.skipif(not forked.fork_possible(),
                                reason="not Linux or one CPU: the check run is made after the run")


def _fresh(code, timeout=300):
    """The last stdout line of ``code`` run in a fresh interpreter (at the repository root), as JSON."""
    env = dict(os.environ)
    env["PYTHONPATH"] = str(ROOT) + os.pathsep + env.get("PYTHONPATH", "")
    env.pop(forked.ENV, None)
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT, env=env,
                       timeout=timeout)
    assert r.returncode == 0, r.stderr
    return json.loads(r.stdout.strip().splitlines()[-1])


FAILURES = r'''
import json, os, signal, time
import numpy as np
from femslide.analysis import forked
from femslide.errors import SolverFailure
out = {}
big = np.arange(300000.0)   # (more than a pipe's buffer back)
r = forked.Forked.start(lambda: {"sum": float(big.sum()), "twice": 2.0 * big}).result()
out["value"] = r["sum"] == float(big.sum()) and bool(np.array_equal(r["twice"], 2.0 * big))
def fails():
    exc = SolverFailure("no convergence", [1.0, 0.5])
    exc.time_limit = True
    raise exc
try:
    forked.Forked.start(fails).result()
except SolverFailure as exc:
    out["failure"] = [exc.reason, exc.history, exc.time_limit]
def breaks():
    raise KeyError("x")
for name, fn, kw in (("error", breaks, {}), ("killed", lambda: os.kill(os.getpid(), signal.SIGKILL), {}),
                     ("silent", lambda: time.sleep(60), {"timeout": 0.5})):
    t0 = time.perf_counter()
    try:
        forked.Forked.start(fn).result(**kw)
    except forked.ChildLost as exc:
        out[name] = [str(exc), time.perf_counter() - t0]
h = forked.Forked.start(lambda: time.sleep(60))
pid, t0 = h.pid, time.perf_counter()
h.cancel()
out["cancel"] = time.perf_counter() - t0
try:
    os.kill(pid, 0)
    out["reaped"] = False
except ProcessLookupError:
    out["reaped"] = True
print(json.dumps(out))
'''


@needs_fork
def test_a_forked_computation_sends_its_value_and_its_failures():
    """The child's value comes back (a numpy array and a float, pickled, more than a pipe holds),
    computed on the parent's memory as it was at the fork; a SolverFailure comes back as one, with
    its reason, residual history and time_limit flag; another exception, a child killed before
    sending and one silent for longer than the timeout (stopped) are ChildLost (the caller then
    computes in its own process); cancel() stops and reaps a child that is still running."""
    out = _fresh(FAILURES)
    assert out["value"] is True
    assert out["failure"] == ["no convergence", [1.0, 0.5], True]
    assert "KeyError" in out["error"][0]
    assert "without its whole result" in out["killed"][0] and "without its whole result" in out["silent"][0]
    assert out["silent"][1] < 5.0 and out["cancel"] < 5.0 and out["reaped"] is True


def test_the_check_run_stays_in_the_process_when_asked_or_when_threads_run(monkeypatch):
    """FEMSLIDE_CHECK_RUN=serial: no child (start returns None, the caller computes); nor while
    another Python thread runs (a fork would copy its held locks without the thread)."""
    import threading
    stop = threading.Event()
    t = threading.Thread(target=stop.wait)
    t.start()
    try:
        assert not forked.parallel_allowed() and forked.Forked.start(lambda: 1) is None
    finally:
        stop.set()
        t.join()
    monkeypatch.setenv(forked.ENV, "serial")
    assert not forked.fork_possible() and not forked.parallel_allowed() and forked.Forked.start(lambda: 1) is None


SAME = r'''
import json, os, sys
import femslide
from femslide.analysis import forked
path, t_end = sys.argv[1], float(sys.argv[2])
got = []
plain = forked.Forked.result
def result(self, timeout=None):
    value = plain(self, timeout)
    got.append(sorted(value))
    return value
forked.Forked.result = result
out = {}
for mode in ("serial", "beside"):
    os.environ[forked.ENV] = mode
    r = femslide.simulate(path, t_end=t_end)
    acc = dict(r["accuracy"])
    acc.pop("check_time_s")
    out[mode] = [r["error_estimate"], acc, r["peaks"], r["steps"], r["events"]]
out["results"] = got
print(json.dumps(out))
'''


@needs_fork
@pytest.mark.parametrize("path, t_end", [("meshes/structures/beam-friction.toml", 1.5),
                                         ("meshes/structures/two-storey-frame.toml", 0.5)])
def test_an_estimate_made_beside_the_run_is_the_one_made_after_it(path, t_end):
    """simulate's check run in a forked child (its result received from the child: not redone in the
    process) gives the same error estimate and the same parts of it (steps, events, histories,
    peaks; all but its own time), bit for bit, as the check run made in the process after the run:
    a friction structure with events and a frame under ground motion; the run's own values are the
    same too."""
    out = _fresh(SAME.replace("sys.argv[1], float(sys.argv[2])", f"{path!r}, {t_end!r}"))
    assert out["results"] == [["H", "events", "peaks", "steps", "time_s"]]   # (the child's, once: beside)
    assert out["serial"][0] is not None and out["serial"][1]["check_steps"] > 0
    assert out["serial"] == out["beside"]
