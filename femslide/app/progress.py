"""Progress bars for long runs (sweeps, simulations): a tqdm bar with an ETA, or a no-op.

    from femslide.progress import progress
    with progress(n_steps, "simulate", quiet) as bar:
        for ...:
            bar.update(1)

The bar is on stderr and only when stderr is a terminal: piped or redirected runs, ``--quiet`` and
environments without tqdm get the no-op, so stdout (``--json``) is never touched.  Lines that must
appear while a bar is shown go through ``bar.write(text)`` (printed to stdout above the bar).
tqdm is imported only when a bar is actually shown.
"""
from __future__ import annotations

import sys


class NoBar:
    """The interface of the tqdm bar that femslide uses, doing nothing (``write`` still prints)."""

    n = 0

    def update(self, n=1):
        self.n += n

    def set_postfix_str(self, s="", refresh=True):
        pass

    def write(self, text, file=None):
        print(text, file=file or sys.stdout, flush=True)

    def close(self):
        pass

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
        return False


class _Bar:
    """A tqdm bar whose ``write`` goes to stdout by default (tqdm's own default)."""

    def __init__(self, bar, tqdm_cls):
        self._bar, self._cls = bar, tqdm_cls

    def __getattr__(self, name):
        return getattr(self._bar, name)

    def write(self, text, file=None):
        self._cls.write(text, file=file or sys.stdout)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self._bar.close()
        return False


def progress(total, desc="", quiet=False, unit="it"):
    """A progress bar over ``total`` units (ETA shown), or :class:`NoBar` when ``quiet``, when
    stderr is not a terminal, or when tqdm is not installed."""
    try:
        tty = sys.stderr.isatty()
    except (AttributeError, ValueError):
        tty = False
    if quiet or not tty:
        return NoBar()
    try:
        from tqdm import tqdm
    except ImportError:
        return NoBar()
    return _Bar(tqdm(total=total, desc=desc, unit=unit, file=sys.stderr, dynamic_ncols=True,
                     leave=False), tqdm)


class TimeProgress:
    """A progress bar over simulated time: ``at(t)`` moves it to t of ``t_end`` (in 1000 steps, with
    the time left shown); ``close()`` ends it.  Quiet as :func:`progress` is."""

    def __init__(self, t_end, desc, quiet=False):
        self.bar = progress(1000, desc, quiet, unit="\u2030")
        self.t_end, self.done = t_end, 0

    def at(self, t):
        k = int(min(1000, 1000 * t / self.t_end))
        if k > self.done:
            self.bar.update(k - self.done)
            self.done = k

    def close(self):
        self.bar.close()
