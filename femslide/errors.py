"""The two ways a run can fail, mapped to the exit statuses of the command-line contract."""
from __future__ import annotations


class BadInput(ValueError):
    """Invalid user input; the message names the parameter and what is allowed (exit status 2)."""


class SolverFailure(RuntimeError):
    """A solve or simulation that did not converge (exit status 1).

    ``reason`` says why in one line; ``history`` holds the residual norms (or other per-iteration
    diagnostics) of the failed attempt so that a caller can see how it failed; ``critical`` is true
    when the load path ended at a limit point or bifurcation (the statics then locate it).
    """

    def __init__(self, reason: str, history=None, critical=False):
        super().__init__(reason)
        self.reason = reason
        self.history = list(history or [])
        self.critical = critical

    def __str__(self):
        if not self.history:
            return self.reason
        tail = ", ".join(f"{h:.3e}" if isinstance(h, float) else str(h) for h in self.history[-12:])
        return f"{self.reason} (last residuals: {tail})"
