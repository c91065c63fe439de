"""A computation run beside the caller in a forked child process (Linux), its result sent back.

``Forked.start(fn)`` forks; the child runs ``fn()`` on a copy of the caller's memory (copy on write:
nothing is pickled on the way in) and sends its result, pickled, through a pipe; ``result()`` waits
for it.  The time history's error estimate uses it for its check run, which needs nothing of the
run it checks (the same start, another tolerance): on a machine with a second core the estimate
adds little to the run's wall time (femslide.analysis.simulate; section 5.2: 0.104 s against 0.087 s
without the estimate and 0.147 s with the check run after the run).  The CPU time is the same as
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
exception of the child is ChildLost too (the caller's own computation then raises it with its type).
The child dies with its parent (Linux's parent-death signal), ignores the terminal's interrupt (the
parent stops it) and writes nothing to the parent's terminal (its standard streams are /dev/null).
"""
from __future__ import annotations

import os
import pickle
import signal
import struct
import sys

from femslide.errors import SolverFailure

ENV = "FEMSLIDE_CHECK_RUN"   # "serial": never fork


class ChildLost(RuntimeError):
    """The child process ended without sending its result."""


def fork_possible() -> bool:
    """Whether this machine and environment allow a forked child at all: Linux, two usable CPUs,
    FEMSLIDE_CHECK_RUN not "serial"."""
    if os.environ.get(ENV, "").strip().lower() == "serial":
        return False
    if not sys.platform.startswith("linux") or not hasattr(os, "fork"):
        return False
    try:
        cpus = len(os.sched_getaffinity(0))
    except (AttributeError, OSError):
        cpus = os.cpu_count() or 1
    return cpus >= 2


def parallel_allowed() -> bool:
    """Whether a computation may run in a forked child now (see the module docstring): as
    :func:`fork_possible`, and no other Python thread running (a fork copies only the calling
    thread: another's locks, held, could hang the child)."""
    if not fork_possible():
        return False
    import threading
    return threading.active_count() == 1


class Forked:
    """A running child (``start``) and the way to its result."""

    def __init__(self, pid, fd):
        self.pid, self.fd = pid, fd

    @classmethod
    def start(cls, fn):
        """Run ``fn()`` in a forked child; None where that is not allowed or the fork fails."""
        if not parallel_allowed():
            return None
        for stream in (sys.stdout, sys.stderr):   # (what is buffered is written once, by the parent)
            try:
                stream.flush()
            except Exception:  # noqa: BLE001 - a closed or missing stream: nothing to flush
                pass
        parent = os.getpid()
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
            code = 1
            try:
                signal.signal(signal.SIGINT, signal.SIG_IGN)   # (the parent stops it)
                _die_with(parent)
                os.close(r)
                null = os.open(os.devnull, os.O_RDWR)
                for fd in (0, 1, 2):
                    os.dup2(null, fd)
                try:
                    out = ("ok", fn())
                except SolverFailure as exc:
                    out = ("failure", exc.reason, list(exc.history), bool(getattr(exc, "time_limit", False)))
                except BaseException as exc:  # noqa: BLE001 - the parent computes it again, and raises it
                    out = ("error", f"{type(exc).__name__}: {exc}")
                data = pickle.dumps(out, protocol=pickle.HIGHEST_PROTOCOL)
                view = memoryview(struct.pack("<Q", len(data)) + data)
                while view:
                    view = view[os.write(w, view):]
                code = 0
            except BaseException:  # noqa: BLE001 - the parent sees a lost child
                code = 1
            finally:
                os._exit(code)
        os.close(w)
        return cls(pid, r)

    def result(self, timeout=None):
        """The child's value (waiting for it, at most ``timeout`` seconds without a byte from it: then
        it is stopped); its SolverFailure raised again; ChildLost when it ended, failed otherwise or
        was stopped without sending all of its result."""
        import selectors
        chunks, size, complete = [], 0, False
        try:
            with selectors.DefaultSelector() as sel:
                sel.register(self.fd, selectors.EVENT_READ)
                while True:
                    if timeout is not None and not sel.select(timeout):
                        break   # (silent too long: a child stuck is stopped below)
                    b = os.read(self.fd, 1 << 20)
                    if not b:
                        break
                    chunks.append(b)
                    size += len(b)
            data = b"".join(chunks)
            complete = size >= 8 and size == 8 + struct.unpack("<Q", data[:8])[0]
        finally:
            self._reap(kill=not complete)
        if not complete:
            raise ChildLost("the check run's process ended without its whole result")
        try:
            out = pickle.loads(data[8:])
        except Exception as exc:  # noqa: BLE001 - a result that does not load: computed again by the caller
            raise ChildLost(f"the check run's result did not load ({type(exc).__name__}: {exc})") from None
        if out[0] == "ok":
            return out[1]
        if out[0] == "failure":
            exc = SolverFailure(out[1], out[2])
            exc.time_limit = out[3]
            raise exc
        raise ChildLost(f"the check run failed in its process ({out[1]})")

    def cancel(self):
        """Stop the child (the caller no longer needs its result); nothing once its result was read."""
        if self.fd is not None:
            self._reap(kill=True)

    def _reap(self, kill):
        """Close the pipe and wait for the child (stopped first with ``kill``)."""
        if kill:
            try:
                os.kill(self.pid, signal.SIGKILL)
            except OSError:
                pass
        try:
            os.waitpid(self.pid, 0)
        except (ChildProcessError, InterruptedError):   # (reaped elsewhere: SIGCHLD ignored)
            pass
        finally:
            fd, self.fd = self.fd, None
            if fd is not None:
                os.close(fd)


def _die_with(parent):
    """Make the calling child process die with its parent (Linux's PR_SET_PDEATHSIG), or exit now if
    the parent is gone already."""
    try:
        import ctypes
        libc = ctypes.CDLL(None, use_errno=True)
        libc.prctl(1, signal.SIGKILL, 0, 0, 0)   # (1: PR_SET_PDEATHSIG)
    except Exception:  # noqa: BLE001 - without it an orphan finishes its check run and exits
        pass
    if os.getppid() != parent:
        os._exit(1)
