"""How much work a simulation is, before it runs: the steps the lowest natural frequency and the
tolerance need, the bound on absurd runs and the check of a held start's release (SPEC 9.2).

Long runs are not refused: a run is bad input only when it is estimated beyond ABSURD_WORK_S (24 h)
of work (steps per period of the lowest mode at the tolerance, :func:`steps_per_period`, times a
measured cost per step) or t_end is beyond MAX_PERIODS (1e6) periods of the lowest mode.  The step
count allowed at run time is RUNAWAY times the estimate, a runaway's safety net.  Model units inside
(femslide.model.discrete); frequencies in Hz, times in s.
"""
from __future__ import annotations

import math

import numpy as np

from femslide.errors import BadInput

ABSURD_WORK_S = 86400.0     # a run estimated beyond this much work [s] is bad input (24 h)
MAX_PERIODS = 1e6           # ... and t_end beyond this many periods of the lowest mode
RUNAWAY = 10                # the step count limit: this many times the estimate (a runaway's safety net)
STEP_SECONDS = 1.2e-3       # measured cost of one step (2-3 Newton iterations) of a small model ...
STEP_SECONDS_PER_DOF = 1e-5  # ... plus this per frame dof (2-core development machine, one BLAS thread)
RADAU_C4 = 0.015   # RADAU5's estimate on a harmonic motion ~ RADAU_C4 (omega h)^4 amplitude (measured 0.0075-0.015 on
                   # section 5.2 at tolerance 1e-9 .. 1e-3: 15 .. 390 steps per period)


def steps_per_period(tolerance: float) -> float:
    """Steps per period of a harmonic motion at the error control's step h = (SAFETY tol / c4)^(1/4) / w
    (RADAU5's estimate ~ c4 (w h)^4 amp; c4 measured on harmonic motions), with 1.5 for rejected
    steps and the control's margin."""
    from femslide.analysis.radau import ORDER, SAFETY
    return 2 * math.pi * (RADAU_C4 / (SAFETY * tolerance)) ** (1.0 / ORDER) * 1.5


def check_work(spec, f1: float, n_q: int, f_top=None):
    """Bad input (naming t_end and the usable range) only for absurd runs: estimated beyond
    ABSURD_WORK_S of work by the steps its lowest frequency f1 (or a harmonic ground motion, or a
    record's samples) needs, or t_end beyond MAX_PERIODS periods of f1.  Returns (the step count
    allowed at run time: RUNAWAY times the steps of the highest computed frequency f_top, whose modes
    a release may excite, a runaway's safety net; the estimated work [s])."""
    per_period = steps_per_period(spec.tolerance)
    f_forced = spec.ground.frequency if spec.ground is not None and spec.ground.harmonic else 0.0
    periods = spec.t_end * max(f1, f_forced)
    steps = periods * per_period
    if spec.ground is not None and spec.ground.times is not None and spec.ground.dt:
        steps = max(steps, min(spec.t_end, float(spec.ground.times[-1])) / spec.ground.dt)
    cost = STEP_SECONDS + STEP_SECONDS_PER_DOF * n_q
    if steps * cost > ABSURD_WORK_S:
        t_max = spec.t_end * ABSURD_WORK_S / (steps * cost)
        raise BadInput(f"[simulate] t_end = {spec.t_end:g} s: about {steps:.3g} steps of ~{cost * 1e3:.2g} ms "
                       f"({per_period:.0f} per period of the lowest mode, {1 / f1:.4g} s, at tolerance "
                       f"{spec.tolerance:g}) would take ~{steps * cost / 3600:.3g} h; allowed: t_end <= {t_max:.4g} s "
                       f"(24 h of work; a looser tolerance allows more)")
    if spec.t_end * f1 > MAX_PERIODS:
        raise BadInput(f"[simulate] t_end = {spec.t_end:g} s is {spec.t_end * f1:.3g} periods of the lowest mode "
                       f"({1 / f1:.4g} s); allowed: t_end <= {MAX_PERIODS / f1:.4g} s ({MAX_PERIODS:.0e} periods)")
    work = steps * cost
    if f_top:
        steps = max(steps, steps * f_top / max(f1, 1e-300))
    return int(RUNAWAY * max(steps, 1000)) + 1000, work


# the units of the history columns (by the last part of their names)
RELEASE_SHARE = 0.1   # a mode that carries this fraction of the start's displacement sets the step size


def release_frequency(model, masses, y_s, e_s, y0):
    """(f [Hz], share): the fastest mode that carries at least RELEASE_SHARE of the displacement of the
    held start y0 from the static equilibrium y_s (the massive dofs' largest displacement), with that
    share; None for models above the dense size (modes.DENSE_LIMIT).  The held displacement is split
    into the modes of the frictionless structure about y_s (dense, every mode); modes with a smaller
    share (the telescopic piece's 410 kHz axial vibration in section 5.2: 0.25 %) are damped out by the
    integrator within a few steps and cost nothing."""
    from femslide.analysis.modes import DENSE_LIMIT, dense_tangent
    from femslide.model.linalg import eigh, null_space
    n_q = model.n_q
    heavy = masses.massive_dofs()
    dq = y0[:n_q] - y_s[:n_q]
    A = float(np.abs(dq[heavy]).max()) if heavy.size else 0.0
    if n_q > DENSE_LIMIT or A == 0.0:
        return None
    K, Gd = dense_tangent(model, y_s, e_s)
    M = masses.dense(y_s[:n_q])
    Z = null_space(Gd) if Gd.shape[0] else np.eye(n_q)
    if Z.shape[1] == 0:   # no motion while every joint holds (a bar on a pin and a contact)
        return None
    Kr, Mr = Z.T @ K @ Z, Z.T @ M @ Z
    try:
        w, V = eigh(0.5 * (Mr + Mr.T), 0.5 * (Kr + Kr.T))   # w = 1 / omega^2, V^T Kr V = I
    except np.linalg.LinAlgError:
        return None
    keep = w > 1e-14 * max(float(w.max()), 1e-300)
    w, V = w[keep], V[:, keep]
    b = V.T @ (Kr @ np.linalg.lstsq(Z, dq, rcond=None)[0])     # the modes' amplitudes
    shares = np.abs((Z @ (V * b))[heavy]).max(axis=0) / A
    big = np.nonzero(shares >= RELEASE_SHARE)[0]
    if big.size == 0:
        return None
    k = big[np.argmin(w[big])]
    return 1.0 / math.sqrt(w[k]) / (2.0 * math.pi), float(shares[k])


def check_release(spec, model, masses, y_s, e_s, y0, f1):
    """Bad input (naming ``initial``) when the motion released from the held start is too fast to
    follow for t_end within ABSURD_WORK_S (24 h) of work: e.g. a deck held at a rotation on columns welded to it
    and to the ground, which only their axial stiffness lets turn (before: 110 s of steps of 1e-7 s,
    then a failure).  Returns that frequency [Hz] (0 when it cannot be computed: a large model)."""
    found = release_frequency(model, masses, y_s, e_s, y0)
    if found is None:
        return 0.0
    f, share = found
    steps = spec.t_end * f * steps_per_period(spec.tolerance)
    cost = STEP_SECONDS + STEP_SECONDS_PER_DOF * model.n_q
    if steps * cost > ABSURD_WORK_S:
        t_max = spec.t_end * ABSURD_WORK_S / (steps * cost)
        raise BadInput(f"[simulate] initial = {spec.initial}: released there, the structure moves in a mode of "
                       f"{f:.4g} Hz ({share:.0%} of the start's displacement; its lowest mode has {f1:.4g} Hz): "
                       f"holding it there strains its stiffest parts (e.g. the axial stiffness of rods welded "
                       f"to it), and following that motion for t_end = {spec.t_end:g} s at tolerance "
                       f"{spec.tolerance:g} takes about {steps:.2g} steps (~{steps * cost / 3600:.3g} h); allowed: "
                       f"an initial state its soft modes reach (a displacement u of a body, a slide), or "
                       f"t_end <= {t_max:.3g} s")
    return f
