"""The error estimate's check run beside the run (femslide.analysis.forked): the child's result, its
failures, and a simulate whose estimate is made in a child equal to one made after the run."""
from __future__ import annotations

import os
import signal

import numpy as np
import pytest

import femslide
from femslide.analysis import forked
from femslide.errors import SolverFailure

needs_fork = pytest.mark.skipif(not forked.parallel_allowed(),
                                reason="no second CPU or not Linux: the check run is made after the run")


@needs_fork
def test_a_forked_computation_sends_its_value_and_its_failures():
    """The child's value comes back (a numpy array and a dict, pickled), computed on the parent's
    memory as it was at the fork; a SolverFailure comes back as one, with its reason, residual
    history and time_limit flag; another exception as RuntimeError naming it; a child killed before
    sending is ChildLost, and so is one silent for longer than the timeout (stopped); cancel() stops
    a child that is still running."""
    big = np.arange(300000.0)   # (more than a pipe's buffer back)
    h = forked.Forked.start(lambda: {"sum": float(big.sum()), "twice": 2.0 * big})
    out = h.result()
    assert out["sum"] == float(big.sum()) and np.array_equal(out["twice"], 2.0 * big)

    def fails():
        exc = SolverFailure("no convergence", [1.0, 0.5])
        exc.time_limit = True
        raise exc
    with pytest.raises(SolverFailure) as info:
        forked.Forked.start(fails).result()
    assert info.value.reason == "no convergence" and info.value.history == [1.0, 0.5] and info.value.time_limit

    def breaks():
        raise KeyError("x")
    with pytest.raises(RuntimeError, match="KeyError"):
        forked.Forked.start(breaks).result()
    with pytest.raises(forked.ChildLost):
        forked.Forked.start(lambda: os.kill(os.getpid(), signal.SIGKILL)).result()
    import time
    h = forked.Forked.start(lambda: time.sleep(60))
    t0 = time.perf_counter()
    h.cancel()
    assert time.perf_counter() - t0 < 5.0
    # a child silent for longer than the timeout is stopped: ChildLost (the caller computes itself)
    t0 = time.perf_counter()
    with pytest.raises(forked.ChildLost):
        forked.Forked.start(lambda: time.sleep(60)).result(timeout=0.5)
    assert time.perf_counter() - t0 < 5.0


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
    assert not forked.parallel_allowed() and forked.Forked.start(lambda: 1) is None


@needs_fork
@pytest.mark.parametrize("path, t_end", [("meshes/structures/beam-friction.toml", 1.5),
                                         ("meshes/structures/two-storey-frame.toml", 0.5)])
def test_an_estimate_made_beside_the_run_is_the_one_made_after_it(monkeypatch, path, t_end):
    """simulate's check run in a forked child gives the same error estimate and the same parts of it
    (steps, events, histories, peaks; all but its own time), bit for bit, as the check run made in
    the process after the run: a friction structure with events and a frame under ground motion;
    the run's own values are the same too."""
    out, started = {}, []
    plain = forked.Forked.start.__func__

    def start(cls, fn):
        h = plain(cls, fn)
        started.append(h is not None)
        return h
    monkeypatch.setattr(forked.Forked, "start", classmethod(start))
    for mode in ("serial", "beside"):
        monkeypatch.setenv(forked.ENV, mode)
        r = femslide.simulate(path, t_end=t_end)
        acc = dict(r["accuracy"])
        acc.pop("check_time_s")
        out[mode] = (r["error_estimate"], acc, r["peaks"], r["steps"], r["events"])
    assert started == [False, True]   # (after the run, then beside it)
    assert out["serial"][0] is not None and out["serial"][1]["check_steps"] > 0
    assert out["serial"] == out["beside"]
