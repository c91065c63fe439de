"""A computation run beside the caller in a forked child process (Linux), its result sent back.

``Forked.start(fn)`` forks; the child runs ``fn()`` on a copy of the caller's memory (copy on write:
nothing is pickled on the way in) and sends its result, pickled, through a pipe; ``result()`` waits
for it.  The time history's error estimate uses it for its check run, which needs nothing of the
run it checks (the same start, another tolerance): on a machine with a second core the estimate
costs the run's wall time almost nothing (femslide.analysis.simulate).  The CPU time is the same as
one after the other, and so are the results, bit for bit (the child computes what the caller would
have computed).

``start`` returns None - the caller computes ``fn()`` itself - where a child would not help or is not
safe: not Linux (macOS forbids fork after its system frameworks started threads, Windows has no
fork), one usable CPU, other Python threads running (a dask worker, an application's threads: a
child would inherit their locks, held), or ``FEMSLIDE_CHECK_RUN=serial`` in the environment (a
sweep's worker processes set it: they already use the CPUs).  A child that dies without sending
(killed, out of memory), or sends nothing for ``timeout`` seconds (it is then stopped), is reported
by ``result()`` as ChildLost, and the caller computes ``fn()`` itself.  A SolverFailure of the child
is raised again by ``result()`` with its reason, residual history and ``time_limit`` flag; any other
exception as RuntimeError naming it.
"""
from __future__ import annotations

import os
import pickle
import signal
import sys

from femslide.errors import SolverFailure

ENV = "FEMSLIDE_CHECK_RUN"   # "serial": never fork


class ChildLost(RuntimeError):
    """The child process ended without sending its result."""


def parallel_allowed() -> bool:
    """Whether a computation may run in a forked child here (see the module docstring)."""
    if os.environ.get(ENV, "").strip().lower() == "serial":
        return False
    if not sys.platform.startswith("linux") or not hasattr(os, "fork"):
        return False
    import threading
    if threading.active_count() > 1:   # (a fork copies only the calling thread: another's locks could hang it)
        return False
    try:
        cpus = len(os.sched_getaffinity(0))
    except (AttributeError, OSError):
        cpus = os.cpu_count() or 1
    return cpus >= 2


class Forked:
    """A running child (``start``) and the way to its result."""

    def __init__(self, pid, fd):
        self.pid, self.fd = pid, fd

    @classmethod
    def start(cls, fn):
        """Run ``fn()`` in a forked child; None where that is not allowed or the fork fails."""
        if not parallel_allowed():
            return None
        sys.stdout.flush()
        sys.stderr.flush()
        try:
            r, w = os.pipe()
        except OSError:
            return None
        try:
            pid = os.fork()
        except OSError:
            os.close(r)
            os.close(w)
            return None
        if pid == 0:   # the child: compute, send, and leave without the parent's exit handlers
            code = 0
            try:
                os.close(r)
                try:
                    out = ("ok", fn())
                except SolverFailure as exc:
                    out = ("failure", exc.reason, list(exc.history), bool(getattr(exc, "time_limit", False)))
                except BaseException as exc:  # noqa: BLE001 - reported to the parent by name
                    out = ("error", f"{type(exc).__name__}: {exc}")
                data = pickle.dumps(out, protocol=pickle.HIGHEST_PROTOCOL)
                view = memoryview(data)
                while view:
                    view = view[os.write(w, view):]
            except BaseException:  # noqa: BLE001 - the parent sees a lost child
                code = 1
            finally:
                os._exit(code)
        os.close(w)
        return cls(pid, r)

    def result(self, timeout=None):
        """The child's value (waiting for it, at most ``timeout`` seconds without a byte from it: then
        it is stopped); its SolverFailure raised again; ChildLost when it ended or was stopped without
        sending all of it."""
        import select
        chunks, status = [], None
        try:
            while True:
                if timeout is not None and not select.select([self.fd], [], [], timeout)[0]:
                    chunks = []   # (silent too long: a child stuck is stopped, its part dropped)
                    os.kill(self.pid, signal.SIGKILL)
                    break
                b = os.read(self.fd, 1 << 20)
                if not b:
                    break
                chunks.append(b)
        finally:
            os.close(self.fd)
            self.fd = None
            _, status = os.waitpid(self.pid, 0)
        if not chunks or status != 0:
            raise ChildLost(f"the check run's process ended without its result (wait status {status})")
        out = pickle.loads(b"".join(chunks))
        if out[0] == "ok":
            return out[1]
        if out[0] == "failure":
            exc = SolverFailure(out[1], out[2])
            exc.time_limit = out[3]
            raise exc
        raise RuntimeError(f"the check run failed in its process: {out[1]}")

    def cancel(self):
        """Stop the child (the caller no longer needs its result)."""
        if self.fd is None:
            return
        try:
            os.kill(self.pid, signal.SIGKILL)
        except OSError:
            pass
        os.close(self.fd)
        self.fd = None
        try:
            os.waitpid(self.pid, 0)
        except OSError:
            pass
