"""Implicit time integration of a declared structure: the constrained (index-3) equations of motion

    M(q) q'' + C q' + f(q) + G(q)^T mu = -M a_g(t) e,     g(q) = 0,

on the model's own assembly (:meth:`femslide.model.discrete.Model.system`: f the internal forces, springs and
dead loads, G the exact joint constraints) and solved by the statics' Newton loop
(:func:`femslide.analysis.newton.newton`) once per step.  Units: the model's (lengths by Lref, forces by Fref),
time in seconds.

Integrator: Radau IIA, 3 stages, order 5 (femslide.analysis.radau: the collocation equations of
the first-order form y = (q, v) with the multipliers, solved by Newton with the exact coupled-stage
matrix): the equations and the constraints hold exactly at every stage and at the step's end
(positions on the constraint manifold, no drift; massless dofs - rods with rhoA = 0, node
rotations - in static equilibrium at every stage), stiff modes (a massive rod's axial and high
bending modes) are put on their quasi-static response (L-stable), and the resolved motion is not
damped (a conservative structure keeps its energy to the tolerance).  Step size: adaptive, with
RADAU5's local error estimate of the positions (the embedded order-3 solution filtered through
[[K + lam C + lam^2 M, G^T], [G, 0]] at the step's start) over the dofs with mass, kept below
SAFETY = 0.5 times ``tolerance`` times the amplitude of the recent motion (the largest displacement
from the static state, remembered over about one period of the lowest mode; floor 1e-6 Lref): a
step with a larger error is repeated with a smaller h, the next step is h (0.9 / err)^(1/4)
(between 0.2 h and 2 h).  The estimate does not see a mode that the steps have damped (the integrator
is L-stable), so the vibration of the lowest modes is watched too: while one vibrates above 0.3 times
that budget, the steps keep its numerical damping over the run within 0.1 times it
(:func:`_mode_steps`), and so is each mode's share of the friction joints' forces (a vibration of
the normal force changes mu N; :func:`_mode_grip`).  Newton's residual is measured against the
motion's forces as well as the static ones.  Under a recorded ground motion the steps end on the
record's sample times, so that the input is smooth within every step.

Damping: Rayleigh, C = alpha M0 + beta K0 with M0 and K0 the mass matrix and the tangent at the
static state (constant; plus any rotational dashpots on bodies, simulate.py).  Energy balance:
kinetic + potential (strain, springs, dead loads including gravity) + dissipated - work of the
ground-motion inertia loads (integral of F_g . v); dissipated is the integral of the damping and
friction power (v.C v + mu N |s'|) plus the energy released by the jumps of massless parts at
friction events (``_requilibrate``); the integrals per step by the Radau quadrature on the step's
stages (exact for polynomials of degree 4); reported relative to the largest energy of the run.
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

from femslide.analysis.newton import newton
from femslide.analysis.radau import (
    C_RK,
    EPS,
    NEWTON_TOL,
    NEWTON_TOL_MAX,
    ORDER,
    SAFETY,
    START_STEP,
    RadauSystem,
    consistent_start,
    start_multipliers,
)
from femslide.model.linalg import Coo, Factorized, coo_mv
from femslide.model.state import ElementState, MotionState
from femslide.analysis.events import locate_step
from femslide.analysis.stickslip import SAME_INSTANT, _switch, start, switch_all
from femslide.errors import BadInput, SolverFailure

CHECK_FACTOR = 10.0    # the check run of an error estimate is at this multiple of the tolerance ...
ORDER_GLOBAL = 5.0     # ... and the global error ~ steps^-ORDER_GLOBAL (Radau IIA: order 5)
EVENT_STEPS = 50      # the step allowance of a run grows by this for each event
MODE_LIVE = 0.3       # a mode vibrating above this share of the error budget is resolved ...
MODE_SHARE = 0.1      # ... its numerical damping over the run kept within this share
N_FLOOR = 1e-6        # a friction joint's normal force below this share of the largest force scale carries nothing
F_MOTION_MIN = 1e-9  # floor of the motion's force scale (model units) that Newton's residual is measured against
REUSE = 0.1          # a step's Newton takes chord steps (its first matrix kept) while each cuts the residual 10x
MAX_STEPS = 2_000_000  # safety net (the a-priori work bound of femslide/analysis/simulate.py comes first)


@dataclass
class Integration:
    """Outcome of :func:`integrate`: the record rows of ``observe``, step counts and the energy
    balance."""

    rows: list = field(default_factory=list)
    steps: int = 0
    rejected: int = 0
    newton_iterations: int = 0
    energy_balance: float = 0.0
    energy: dict = field(default_factory=dict)
    crossings: list = field(default_factory=list)   # (index of the watched function, t) at its zeros
    notes: list = field(default_factory=list)       # what the run could not do as it usually does (result "notes")


def _dip(f0, f_stages, f1, calm):
    """Where (a fraction of the step) the event functions ``calm`` - positive at the step's start
    f0 and end f1 - dip below zero in between, by the cubic through their values at 0, the inner
    Radau stages (f_stages at C_RK[0], C_RK[1]) and 1: the earliest dip's minimum, or None."""
    x = np.array([0.0, C_RK[0], C_RK[1], 1.0])
    V = np.vander(x, 4)
    best = None
    for k in np.nonzero(calm)[0]:
        vals = np.array([f0[k], f_stages[0][k], f_stages[1][k], f1[k]])
        if vals.min() < 0.0:   # (an inner stage already below zero)
            xm = float(x[int(np.argmin(vals))])
        else:
            a, b, c, d = np.linalg.solve(V, vals)
            roots = np.roots([3.0 * a, 2.0 * b, c]) if abs(a) + abs(b) > 0.0 else np.zeros(0)
            xs = [float(r.real) for r in np.atleast_1d(roots) if abs(r.imag) < 1e-12 and 0.0 < r.real < 1.0]
            xs = [xi for xi in xs if ((a * xi + b) * xi + c) * xi + d < 0.0]
            if not xs:
                continue
            xm = min(xs)
        best = xm if best is None else min(best, xm)
    return best


def _mode_guard(modal, masses, q_static, heavy, fr=None, y_static=None, elements=None):
    """(omega (k,), P (k, n_q), reach (k,), decay (k,), grip, note) for :func:`_mode_steps`: the modal
    coordinates of an acceleration are P @ acc (P = phi^T M / phi^T M phi: the modes are
    M-orthogonal), reach the largest entry of a shape on the dofs with mass, decay = zeta omega
    [1/s], grip the friction forces a unit of each mode carries (:func:`_mode_grip`: (joints, G) or
    None), note why that watch is off where the structure has friction joints (or None); None
    without modes.  ``modal``: (omega, shapes, zeta[, stuck]), stuck whether the
    shapes are those of the structure with its friction joints stuck."""
    if modal is None:
        return None
    om, Phi, zeta = (np.asarray(x, float) for x in modal[:3])
    if Phi.ndim != 2 or Phi.shape != (om.size, q_static.size) or not (om > 0.0).any():
        return None
    keep = om > 0.0
    om, Phi, zeta = om[keep], Phi[keep], zeta[keep]
    r, c, v = masses.matrix(q_static)
    MPhi = np.array([coo_mv(r, c, v, phi, q_static.size) for phi in Phi])
    mm = np.einsum("kn,kn->k", MPhi, Phi)
    grip = note = None
    if fr is not None and y_static is not None:
        grip = _mode_grip(fr, bool(modal[3]) if len(modal) > 3 else False, y_static, elements, om, MPhi)
        if isinstance(grip, str):
            grip, note = None, grip
    return om, MPhi / mm[:, None], np.abs(Phi[:, heavy]).max(axis=1), zeta * om, grip, note


def _mode_grip(fr, stuck, y_static, elements, om, MPhi):
    """(joints, G (j, k)): the friction joints (mu0 > 0) and the friction forces that a unit of each mode's
    coordinate carries there (model units), the largest of |N_k| and, stuck, of the lock's force
    over mu0, |T_k| / mu0 (the margin mu0 N - |T|), weighed by (omega_1 / omega_k)^2; None without
    such joints; where the tangent is singular (locks that pool: their split is undetermined) the
    watch of these forces is off, and a sentence says so (the run's note).  A mode's constraint
    forces lam_k are its multipliers, [[K, G^T], [G, 0]] [phi_k, lam_k] = [omega_k^2 M phi_k, 0]
    (the tangent at the start's state ``y_static``, in the layout of the modes' model: with every
    friction joint stuck or none).  A vibration that the steps damp changes the friction force mu N,
    or the margin of a stuck joint, by its share: the deck of a base-isolated frame rings at 109 and
    188 Hz after each friction event by nanometres, beside a slide of centimetres, but by 1e-4 of
    the normal force.  The weight: a friction force that vibrates at omega_k moves the masses by its
    amplitude over m omega_k^2, (omega_1 / omega_k)^2 of what the same force does at the lowest
    frequency (a stiff rod's axial mode at 395 kHz under a clamp carries 1e-4 of its normal force,
    and moves nothing)."""
    base = fr.base
    model = fr.stuck_model() if stuck else base
    every = tuple(i for i, fj in enumerate(fr.joints) if fj.friction)   # (stuck_model's locks, in order)
    y = fr.convert(y_static, fr.stuck(), every) if stuck else y_static[:model.n].copy()
    # (the tangent as the model stores it: dense, banded or sparse; the trial rotations are a copy's)
    _, S, _ = model.system(y, ElementState(elements.committed.copy()), 1.0)
    n_q = base.n_q
    rhs = np.zeros((model.n, om.size))
    rhs[:n_q] = (MPhi * (om * om)[:, None]).T
    state = "stuck" if stuck else "free"

    def off(why):
        return (f"the steps do not watch the friction forces of the vibrating modes: {why}; the steps follow "
                f"the modes' displacements only")
    try:
        fact = Factorized(S, overwrite=True)   # (a zero pivot: LinAlgError)
    except np.linalg.LinAlgError:
        return off(f"the tangent with the friction joints {state} is singular (locks that share one load)")
    lam = np.column_stack([fact.solve(b) for b in rhs.T])[n_q:]   # (k columns of constraint forces)
    locks = every if stuck else ()
    joints, rows = [], []
    for i, fj in enumerate(fr.joints):
        if not fj.friction:
            continue
        _, dN = fj.normal(y_static)
        share = np.abs(dN @ lam[fj.mu_idx - n_q])
        if i in locks:   # (the margin mu0 N - |T|: the lock's force against mu0 N)
            share = np.maximum(share, np.abs(lam[base.n_c + locks.index(i)]) / fj.mu0)
        joints.append(fj)
        rows.append(share * (om.min() / om) ** 2)
    G = np.array(rows)
    if not joints:
        return None
    if not np.isfinite(G).all():
        return off(f"with the friction joints {state} they came out non-finite")
    return joints, G


def _mode_steps(vib, omega, decay, budget, t_end):
    """The largest step [s] that resolves every mode vibrating above MODE_LIVE ``budget`` (model
    units; a mode below may be damped away: it costs less than that): Radau IIA damps a mode by
    (omega h)^6 / 7200 of its amplitude per step (its stability function on the imaginary axis, to
    2 % for omega h <= 1), so over T / h steps a mode of amplitude A loses A T omega^6 h^5 / 7200,
    kept below MODE_SHARE budget; T is the run's t_end, or the mode's own decay time
    1 / (zeta omega) when its damping makes it shorter; inf when no mode vibrates so."""
    live = vib > MODE_LIVE * budget
    if not live.any():
        return math.inf
    T = np.minimum(t_end, 1.0 / np.maximum(decay[live], 1e-300))
    return float(((7200.0 * MODE_SHARE * budget / (T * vib[live] * omega[live] ** 6)) ** 0.2).min())


def integrate(model, masses, y0, elements0, t_end, tolerance, C=None, ground=None, observe=None,
              h0=None, h_max=None, max_steps=MAX_STEPS, wall_limit=None, progress=None, q_ref=None,
              friction=None, period=None, watch=(), sample=None, modal=None):
    """Integrate from rest at the state (y0, elements0) (model units; the elements' history
    committed there) to ``t_end`` [s].

    ``C``: damping matrix (femslide.model.linalg.Coo or a scipy sparse matrix, model units) or None; ``ground``: a
    :class:`femslide.analysis.excitation.Ground` or None; ``observe(t, y, alpha, v, acc)`` -> a row recorded at
    every accepted step (t = 0 included; acc = q''); ``h0``: first step [s]; ``h_max``: largest step; ``q_ref``: the
    static equilibrium (default: the start), from which the displacements that scale the error are
    measured; ``friction``: a :class:`femslide.analysis.stickslip.Friction` (stick/slip modes and events) or
    None; ``period`` [s]: the time over which the error scale (the motion's amplitude) is
    remembered (default: the whole run); ``watch``: functions g(y, v) (model units) whose sign
    changes are located as events: the step ends there, and ``crossings`` lists (index, t).
    ``wall_limit`` [s]: the user's limit on the wall time of this integration (None: none).
    ``sample`` [s]: record the rows at the multiples of this interval (inside a step from its
    collocation polynomial: positions and multipliers to the integrator's order, velocities and
    accelerations to lower orders), at t_end and at every event (the rows before and after it),
    instead of at every step (None).  ``modal``: (omega [rad/s] (k,), shapes (k, n_q), zeta (k,)[, stuck]) of
    the lowest natural modes about the static state and their damping ratios (stuck: the shapes are
    those of the structure with its friction joints stuck), or None: a mode that vibrates above the
    tolerance keeps the steps short enough for it (:func:`_mode_steps`, :func:`_mode_grip`).
    Raises SolverFailure when a step cannot be completed
    (Newton fails at the smallest step)
    or the step count (a runaway's safety net) or the wall-time limit runs out."""
    n_q = model.n_q
    heavy = masses.massive_dofs()
    if heavy.size == 0:
        raise BadInput("simulate: nothing in the structure has mass (give bodies a mass or rods a rhoA)")
    zero = np.zeros(n_q)
    s = MotionState(0.0, y0.copy(), zero.copy(), zero.copy(), elements0.copy())
    q_static = (y0[:n_q] if q_ref is None else q_ref[:n_q]).copy()
    amp = max(1e-6, float(np.abs(y0[heavy] - q_static[heavy]).max()))
    amp_all = amp
    h = h0 or 1e-3 * t_end
    h_max = h_max or t_end
    h_min = 1e-12 * max(t_end, 1.0)
    stops = None
    if ground is not None and ground.times is not None:
        stops = ground.times[(ground.times > 0.0) & (ground.times < t_end)]
    out = Integration()
    V0 = model.potential(y0, elements0.committed)
    T0 = masses.kinetic(y0[:n_q], s.v)
    D = W = 0.0
    J = 0.0            # of D: the energy released by jumps of massless parts at friction events
    Emax = 0.0
    bal = 0.0
    Cm = Coo.of(C)   # (C @ v)
    fr = friction
    # Newton's residual well below the step's error budget: relative to the internal forces and to
    # the motion's forces (the largest mass times the largest acceleration, the ground's included,
    # remembered over a period as the amplitude is): a force residual that is small beside the
    # static forces may still be large beside the motion's (a mast's tip at 1e-6 was 8x off)
    newton_tol = min(NEWTON_TOL_MAX, max(NEWTON_TOL, 1e-3 * tolerance))
    motion_share = max(1.0, 1e-3 * tolerance / newton_tol)   # (against the motion: 1e-3 tolerance, uncapped)
    m_max = float(np.abs(masses.matrix(zero)[2]).max(initial=0.0))
    g_len = 0.0 if ground is None else float(np.linalg.norm(ground.direction)) / model.Lref

    def motion_force(t, acc):
        a = float(np.abs(acc[heavy]).max(initial=0.0))
        if ground is not None:
            a += abs(float(ground.accel(t))) * g_len
        return m_max * a

    def loss_power(y, v):
        P = float(v @ (Cm @ v)) if Cm is not None else 0.0
        return P + (fr.power(y, v) if fr is not None else 0.0)

    def attempt(sysm, s, h):
        """One step of size h from s: (y, alpha, v, acc, Y) at its end (Y: the step's Newton
        unknowns, its stages) or None, and Newton's info."""
        sysm.prepare(s, h)
        Y, info = newton(sysm, sysm.predictor(), s.elements, tol=newton_tol, maxit=12,
                         fscale=f_motion * motion_share, reuse=REUSE)
        alpha1 = s.elements.trial
        s.elements.revert()   # (every trial starts from the state's committed history)
        out.newton_iterations += info.iterations
        if not info.converged:
            return None, info
        y, v1, acc1 = sysm.end(Y)
        return (y, alpha1, v1, acc1, Y), info

    h_s = START_STEP * h
    if fr is None:
        sysm = RadauSystem(model, masses, Cm, ground)
        s = consistent_start(sysm, s, h_s)
    else:
        if not fr.tolerance:
            fr.tolerance = tolerance
        if not fr.resolution:   # (t_same's, for the events' record; a check run keeps its run's)
            fr.resolution = 0.1 * tolerance * (period or 0.0)
        s, sysm, released = start(fr, s, h_s)
        D += released
        J += released
    f_motion = max(motion_force(s.t, s.acc), F_MOTION_MIN)
    k_sample = 1   # the next sample is at k_sample * sample
    guard = _mode_guard(modal, masses, q_static, heavy, fr, s.y, s.elements)   # (s: the start's multipliers)
    if guard is not None:
        om, Pm, reach, decay, grip, note = guard   # (Pm @ acc: the modal accelerations)
        if note:
            out.notes.append(note)
        vib = np.zeros(om.size)   # the modes' vibration amplitudes [model units]
        if grip is not None:
            # ... and the friction forces they carry (joints, modes), against the normal forces' largest
            # |value| so far (a history's error is relative to its largest value)
            vib_f = np.zeros(grip[1].shape)
            n_top = np.array([abs(fj.normal(s.y)[0]) for fj in grip[0]])
    if observe:
        out.rows.append(observe(0.0, s.y, s.alpha, s.v, s.acc))
    watch = list(watch)
    wvals = np.array([g(s.y, s.v) for g in watch])
    wscale = np.abs(wvals)
    wsign = np.where(wvals != 0.0, np.sign(wvals), 0.0)
    t0 = time.perf_counter()
    switches, t_switch = 0, None
    fresh = [False] * (fr.size if fr is not None else 0)

    def t_same(t):
        """The resolution of event times [s]: events closer than this are one instant (1e-9 s,
        relative to t, and 1/100 of the promised accuracy of event times, 10 tolerance times the
        lowest mode's period)."""
        return max(SAME_INSTANT * max(1.0, abs(t)), 0.1 * tolerance * (period or 0.0))
    ph_of = None   # the state the event functions ph were evaluated at
    while s.t < t_end * (1 - 1e-14):
        # (each event - a friction switch, a lift, a landing - brings its own restart and located steps)
        n_ev = sum(len(v) for v in fr.events.values()) + 2 * len(fr.touches) if fr is not None else 0
        if out.steps + out.rejected >= max_steps + EVENT_STEPS * n_ev:
            raise SolverFailure(f"simulate: the step count limit {max_steps + EVENT_STEPS * n_ev} ({max_steps} and "
                                f"{EVENT_STEPS} per event, {n_ev} events) was reached at t = {s.t:.6g} s "
                                f"(tolerance too tight, the motion too fast for this t_end, or events piling up)")
        if wall_limit and time.perf_counter() - t0 > wall_limit:
            raise SolverFailure(f"simulate: stopped at t = {s.t:.6g} s of t_end = {t_end:g} s: the wall-time "
                                f"limit of {wall_limit:g} s was reached")
        h = min(h, h_max, t_end - s.t)
        if h < t_end - s.t < 1.5 * h:
            # two even steps to the end rather than one and a sliver (a very short step's
            # accelerations and multipliers carry the step's velocity error divided by its length)
            h = 0.5 * (t_end - s.t)
        t_stop = None
        if stops is not None:
            # a step ends on the record's next sample (the input is linear within a step: a kink of
            # the record inside a step was smoothed over, and its work not what the steps applied)
            # (a sample within 1e-9 h_max ahead counts as reached: an event may end a step there)
            k = int(np.searchsorted(stops, s.t + 1e-9 * h_max, side="right"))
            if k < stops.size:
                gap = float(stops[k] - s.t)
                # (gap carries the round-off of t: a step capped at the record's dt may fall short of
                # it by ulps, which must not count as a sliver)
                if h >= gap - 1e-9 * gap - 16.0 * EPS * max(1.0, abs(s.t)):
                    h, t_stop = gap, float(stops[k])
                elif h > 0.5 * gap:
                    h = 0.5 * gap   # two even steps rather than one and a sliver
        if fr is not None:
            # a joint whose mode no longer holds at the start of a step (two events at one instant):
            # switch it now
            if ph_of is not s:
                ph, ph_of = fr.phi(s.y, s.v), s
            # (a joint that has just started to slip is not late at that instant: a massless slide's
            # velocity follows the masses, and at a reversal it may still carry the old sign by a
            # hair; if it really moves the other way, the next step's start finds it late)
            fresh = [fr.fresh(k, s.t) for k in range(ph.size)]
            if any(fresh):
                # a slip just begun starts at velocity 0, a contact just lifted at gap 0: neither is
                # late, and a reversal or a landing within the step crosses from there (a slip that
                # reversed within its first step was switched late, at the step's end, as a
                # zero-duration stick); a rebound's flight is resolved by the steps
                ph = np.where(fresh, np.maximum(ph, 0.0), ph)
                if any(fresh[1::2]):
                    h = min(h, fr.flight_step(s, fresh))
            late = [i for i in np.nonzero(ph < -1e-10)[0] if not fresh[i]]
            if late:
                switches = switches + 1 if s.t == t_switch else 1
                t_switch = s.t
                if switches > 2 * len(fr.joints) + 2:
                    raise SolverFailure(f"simulate: the friction joints' stick/slip modes do not settle at "
                                        f"t = {s.t:.9g} s")
                s, sysm, released = _switch(fr, s, int(late[0]), START_STEP * h)
                D += released
                J += released
                continue
        cand, info = attempt(sysm, s, h)
        if cand is None:
            out.rejected += 1
            if h <= h_min:
                raise SolverFailure(f"simulate: Newton failed at t = {s.t:.6g} s with the smallest step "
                                    f"{h:.3g} s: {info.reason}", info.history)
            h *= 0.25
            continue
        y, alpha1, v1, acc1, Y = cand
        q = y[:n_q]
        est = np.abs(sysm.error(Y)[0][heavy])
        disp = float(np.abs(q[heavy] - q_static[heavy]).max())
        err = float(est.max()) / (SAFETY * tolerance * max(amp, disp, 1e-3 * amp_all)) if est.size else 0.0
        if err > 1.0 and h > h_min:
            out.rejected += 1
            h *= max(0.2, 0.9 * err ** (-1.0 / ORDER))
            continue
        h_next = h * min(2.0, max(0.2, 0.9 * max(err, 1e-12) ** (-1.0 / ORDER)))
        # events: a friction joint's mode stops holding (its event function turns negative), a
        # watched quantity changes sign; the step is cut at the first, located on the step's own
        # solution (femslide.analysis.events.locate_step)
        nf = fr.size if fr is not None else 0
        ws, started = wsign, np.zeros(len(watch), dtype=bool)
        if watch and not wsign.all():
            # a watched quantity at zero at the step's start (a start from rest, a zero just located)
            # takes the sign it moves towards, from its rate along the start's motion: its zero
            # within the step is found (beam-friction's first turning point, 2e-4 s after the
            # release, falls on a friction event and was lost to round-off)
            eps = 1e-6 * h
            y_ = s.y.copy()
            y_[:n_q] += eps * s.v
            dg = np.array([g(y_, s.v + eps * s.acc) for g in watch]) - wvals
            ws = np.where(wsign != 0.0, wsign, np.sign(dg))
            started = (wsign == 0.0) & (ws != 0.0)
        ev0 = np.concatenate([ph if fr is not None else np.zeros(0), ws * wvals])

        def event_values(y_, v_, ws=ws):
            f = fr.phi(y_, v_) if fr is not None else np.zeros(0)
            return np.concatenate([f, ws * np.array([g(y_, v_) for g in watch])]) if watch else f
        def with_mu(c, hh, sy=sysm, t0=s.t):
            """y of a trial step's end c (of length hh) with its multipliers solved exactly where every
            dof has mass (femslide.analysis.radau.start_multipliers), else its own."""
            if heavy.size < n_q:
                return c[0]
            st = MotionState(t0 + hh, c[0], c[2], c[3], ElementState(c[1]))
            return np.concatenate([c[0][:n_q], start_multipliers(sy, st, c[3].copy(), c[0][n_q:])[1]])

        ev1 = at = event_values(y, v1)
        cross = (ev1 < 0.0) & (ev0 >= 0.0)
        if nf and not cross[:nf].any():
            # a mode that stops holding and holds again within the step (a grazing breakaway, a
            # slip of a few ms inside a longer step): the cubic through its event function at the
            # step's start, inner stages and end dips below zero; the step is cut at the dip and
            # the first crossing located inside it
            calm = (ev0[:nf] > 0.0) & ~np.array(fresh, dtype=bool)
            x_dip = _dip(ev0[:nf], [fr.phi(y_i, v_i) for _, y_i, v_i in sysm.stages(Y)[:2]], ev1[:nf], calm)
            if x_dip is not None:
                cand_i, _ = attempt(sysm, s, x_dip * h)
                e_i = event_values(with_mu(cand_i, x_dip * h), cand_i[2]) if cand_i is not None else None
                if e_i is not None and (e_i[:nf][calm] < 0.0).any():
                    h, cand = x_dip * h, cand_i
                    y, alpha1, v1, acc1, Y = cand
                    q = y[:n_q]
                    ev1 = at = e_i
                    cross = (ev1 < 0.0) & (ev0 >= 0.0)
                else:
                    sysm.prepare(s, h)   # (back on the step)
        if watch:
            cross[nf:] &= ws != 0.0
        crossed, due = [], []
        if cross.any():
            # an event function that reaches zero within the resolution of event times (t_same: a
            # turning point just after another, a slide that stops just after the deck turns) crosses
            # at the step's start: placed there, without re-steps shorter than t_same, whose
            # massless parts' velocities are Newton's residual over the step (a slip just begun
            # starts at zero and is located inside the step)
            tau = np.where(cross, ev0 / np.maximum(ev0 - ev1, 1e-300) * h, np.inf)
            early = cross & (tau <= t_same(s.t))
            early[:nf] &= (ev0[:nf] > 0.0) & ~np.array(fresh, dtype=bool) if nf else False
            early[nf:] &= ~started   # (its zero at the start is where it comes from, not a crossing)
            for k in np.nonzero(early[nf:])[0]:
                if not any(kk == k and abs(tt - s.t) <= t_same(s.t) for kk, tt in out.crossings[-len(watch):]):
                    out.crossings.append((int(k), s.t))
                wsign[k] = 0.0
            now = [int(i) for i in np.nonzero(early[:nf])[0]]
            if now:
                switches = switches + 1 if s.t == t_switch else 1
                t_switch = s.t
                if switches > 2 * len(fr.joints) + 2:
                    raise SolverFailure(f"simulate: the friction joints' stick/slip modes do not settle at "
                                        f"t = {s.t:.9g} s")
                s, sysm, released = _switch(fr, s, now[0], START_STEP * h)
                D += released
                J += released
                continue
            cross &= ~early
        if cross.any():
            # each trial is a step from s (the event lies on the step's own positions and
            # velocities); where every dof has mass its multipliers - the friction's forces, a
            # contact's pressure - are solved exactly at the trial's end (start_multipliers): a
            # short trial's own carry its velocity error over its length (a 1e-6 velocity error
            # over a 1e-4 s trial step turned a rocking block's friction force around and broke its
            # corner away)
            trial_h = [h]

            def attempt_at(hh, sy=sysm, st=s, th=trial_h):
                th[0] = hh
                return attempt(sy, st, hh)[0]
            f_at = (lambda c, cr=cross, th=trial_h: float(np.min(np.where(cr, event_values(with_mu(c, th[0]), c[2]),
                                                                          np.inf))))
            h_ev, cand = locate_step(attempt_at, f_at, float(np.min(ev0[cross])), h, cand, x_min=t_same(s.t))
            y, alpha1, v1, acc1, Y = cand
            y = with_mu(cand, h_ev)
            sysm.prepare(s, h_ev)   # (the step system back on the located step: its last trial may be another)
            q = y[:n_q]
            at = event_values(y, v1)
            # the first event, and every other that reaches zero at the same instant (within t_same
            # by its rate over the step): a slide that stops as the deck turns is both a friction
            # event and a turning point, whichever is located first
            rate = np.maximum((ev0 - at) / h_ev, 1e-300)
            now = cross & (at <= t_same(s.t + h_ev) * rate)
            now[int(np.argmin(np.where(cross, at, np.inf)))] = True
            due = [int(i) for i in np.nonzero(now)[0] if i < nf]
            crossed = [int(i) - nf for i in np.nonzero(now)[0] if i >= nf]
            h_next = max(h, 10 * h_ev) if h_ev < 0.1 * h else h
            h = h_ev
        disp = float(np.abs(q[heavy] - q_static[heavy]).max())
        amp_all = max(amp_all, disp)
        # the amplitude of the recent motion (a decaying memory of one period): a decaying or
        # growing motion keeps its relative accuracy
        amp = max(disp, amp * math.exp(-h / period) if period else amp, 1e-6)
        f_motion = max(motion_force(s.t + h, acc1), f_motion * math.exp(-h / period) if period else f_motion,
                       F_MOTION_MIN)
        t1 = t_stop if (t_stop is not None and not cross.any()) else s.t + h
        on_grid = False
        if sample and observe:
            # the samples inside the step, from its collocation polynomial (the elements' chord
            # rotations of its end: they only unwrap angles); one at the step's end is its own row
            at_t = None
            while k_sample * sample < t1 - 1e-9 * sample:
                tk = k_sample * sample
                at_t = at_t or sysm.dense(Y)
                yk, vk, ak = at_t(tk)
                out.rows.append(observe(tk, yk, alpha1, vk, ak))
                k_sample += 1
            on_grid = abs(t1 - k_sample * sample) <= 1e-9 * sample
            if on_grid:
                k_sample += 1
        if ground is not None or Cm is not None or fr is not None:   # (else no work, no loss)
            dW, dD = sysm.work(Y, loss_power if Cm is not None or fr is not None else None)
            W += dW
            D += dD
        sysm.remember(Y)
        s = MotionState(t1, y, v1, acc1, ElementState(alpha1))
        for k in crossed:
            out.crossings.append((k, t1))
        if watch:
            wvals = np.array([g(s.y, s.v) for g in watch])
            wscale = np.maximum(wscale, np.abs(wvals))
            # (a quantity just located at zero carries no sign until it moves away)
            wsign = np.where(np.abs(wvals) > 1e-9 * wscale, np.sign(wvals), 0.0)
        if fr is not None and not due:
            ph, ph_of = at[:nf], s   # (evaluated at this state's (y, v1) above)
        out.steps += 1
        if due and observe:
            # the state before the switch, at the event's instant (its left limit: the friction force
            # and the reactions jump there, and the largest of them is often just before the jump);
            # the row after the switch follows at the same time
            # (accelerations and multipliers solved exactly at that state when every dof has mass:
            # the located step may be short, and its own carry its velocity error over its length)
            acc_l, mu_l = start_multipliers(sysm, s, s.acc.copy(), s.y[n_q:])
            s = MotionState(t1, np.concatenate([s.y[:n_q], mu_l]), s.v, acc_l, s.elements)
            out.rows.append(observe(t1, s.y, s.alpha, s.v, s.acc))
        elif due:   # (the switches read the lock multipliers of the state: exact where every dof has mass)
            acc_l, mu_l = start_multipliers(sysm, s, s.acc.copy(), s.y[n_q:])
            s = MotionState(t1, np.concatenate([s.y[:n_q], mu_l]), s.v, acc_l, s.elements)
        if due:   # (several joints may change modes at one instant: femslide.analysis.stickslip.switch_all)
            s, sysm, released = switch_all(fr, s, due, START_STEP * h_next)
            D += released
            J += released
        T = masses.kinetic(s.y[:n_q], s.v)         # (after a switch: the state it left)
        V = model.potential(s.y, s.alpha) - V0
        Emax = max(Emax, abs(T), abs(V), abs(D), abs(W))
        bal = max(bal, abs(T + V + D - W - T0))
        if observe and (not sample or on_grid or due or t1 >= t_end * (1 - 1e-14)):
            out.rows.append(observe(t1, s.y, s.alpha, s.v, s.acc))
        if progress:
            progress(t1)
        if guard is not None:
            # a mode that vibrates above the tolerance (excited by an event: a friction switch
            # rings the deck of a base-isolated frame at 109 and 188 Hz) is resolved: the steps
            # keep its numerical damping over the run below the error budget
            # (the amplitude from the modal acceleration over omega^2: a forced, quasi-static response
            # at a frequency W counts only (W / omega)^2 of its size, a free vibration in full)
            q_mode = np.abs(Pm @ s.acc) / (om * om)
            fade = math.exp(-h / period) if period else 1.0
            vib = np.maximum(q_mode * reach, vib * fade)
            h_next = min(h_next, _mode_steps(vib, om, decay, tolerance * max(amp, disp, 1e-3 * amp_all), t_end))
            if grip is not None:
                # ... and by the share of the friction forces it carries (_mode_grip): a slide follows
                # mu N, a breakaway mu0 N; the deck's vibration is nanometres beside a slide that grows
                # with the record, but its share of N does not shrink
                n_top = np.maximum(n_top, [abs(fj.normal(s.y)[0]) for fj in grip[0]])
                vib_f = np.maximum(q_mode * grip[1], vib_f * fade)   # (joints, modes) [model units]
                # (a joint whose normal force stays at round-off beside the others' and the motion's
                # carries no friction worth resolving)
                floor = N_FLOOR * max(float(n_top.max()), f_motion)
                share = (vib_f * np.where(n_top > floor, 1.0 / np.maximum(n_top, 1e-300), 0.0)[:, None]).max(axis=0)
                h_next = min(h_next, _mode_steps(share, om, decay, tolerance, t_end))
        h = h_next
    out.energy_balance = bal / Emax if Emax > 0 else 0.0
    out.energy = {"kinetic": masses.kinetic(s.y[:n_q], s.v) * model.Fref * model.Lref,
                  "potential": (model.potential(s.y, s.alpha) - V0) * model.Fref * model.Lref,
                  "dissipated": D * model.Fref * model.Lref, "work_in": W * model.Fref * model.Lref,
                  "jump_loss": J * model.Fref * model.Lref}
    return out
