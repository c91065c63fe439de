"""One-mass Coulomb-friction oscillator integrated exactly, event by event (SPEC section 5).

Model (SI units: m [kg], k [N/m], c_v [N s/m], forces [N], w [m], t [s])::

    m w'' + c_v w' + k w + f = F(t),      N = m g,
    F(t) = P0 sin(theta t) - m ag sin(theta t) - m a_rec(t),     theta = theta_ratio * omega,

``w`` is the displacement of the mass relative to its base (positive along the guide), ``F`` the
applied force (for base excitation the inertia force -m z0'' of the moving frame) and ``f`` the
friction force on the mass, opposite to the relative velocity:

* sliding (w' != 0): f = mu N sgn(w');
* at rest (w' = 0): the mass sticks while |F - k w| <= mu0 N (mu0 >= mu, the static coefficient);
  otherwise it starts to slide in the direction of the net force F - k w.

While stuck the velocity is exactly 0 and the position constant (no regularised sign function).
Between events the equation is linear with a constant friction force and a forcing that is a sine
plus a linear function of time (the record is interpolated linearly), so each segment is solved in
closed form: homogeneous part (under-, critically or over-damped) plus the exact particular
solution.  For c_v = 0 the harmonic response is written in a form that stays exact and stable at and
near resonance (theta = omega).  Events are found on the closed form:

* sliding -> velocity zero: analytically (atan2) for unforced under-damped segments, otherwise by a
  scan in sub-steps of 1/8 of the shortest period (with a check of interior extrema, so that a zero
  touched between two samples is not missed) and a bracketing root finder to ~1e-14 s;
* stuck -> breakaway, the first time |F(t) - k w| exceeds mu0 N: analytically for a harmonic force,
  exactly per record interval for a record, by scan + root for both together.

The record acceleration is zero outside its time range.  Energy balance, dense histories and
per-period amplitudes are evaluated afterwards, vectorised, from the stored closed forms.
"""
from __future__ import annotations

import bisect
import math

import numpy as np

from femslide.analysis.excitation import Record, read_csv_record
from femslide.errors import BadInput, SolverFailure
from femslide.results.outcome import Outcome
from femslide.scenes.oscillator import Forcing, Oscillator
from femslide.scenes.oscillator_solution import E_MAX, TWO_PI
from femslide.scenes.params import floor_g

# Bounded work (issue 12).  The run follows the motion period by period: closed-form segments
# between events, located by a scan of 8 samples per shortest period.  Measured on the 2-core
# development machine under load: 150-210 us per period of the shortest time scale for the solve,
# energy balance and summary of a forced run (the slowest kind: 2 events and 16 scan samples per
# period; unforced runs need one closed form per half-swing), and as much again for --out (history
# and JSON).  A run may follow at most MAX_PERIODS such periods: about US_PER_PERIOD * MAX_PERIODS
# = 20 s of solving (40 s with --out) and under 1 GiB, inside the 2 minutes and 4 GiB of the
# contract with room to spare.
US_PER_PERIOD = 200
MAX_PERIODS = 100_000
ENERGY_TOL = 1e-6       # a run whose energy balance is worse than this fails (exit 1)


def build(values: dict) -> tuple[Oscillator, float, float]:
    """Oscillator, w0 and t_end from validated scene parameters (see module docstring)."""
    m, k = values["m"], values["k"]
    if not k > 0:
        raise BadInput(f"parameter k = {k:g} N/m: the one-mass oscillator needs a spring; "
                       f"allowed: k > 0")
    omega = math.sqrt(k / m)
    ag = values.get("ag") or 0.0
    rec = values.get("record")
    P0 = values.get("P0", 0.0)
    if P0 is None:  # default of sdof-harmonic: 10 N unless a base excitation is given
        P0 = 0.0 if (ag or rec) else 10.0
    theta = values.get("theta_ratio", 1.0) * omega
    A = P0 - m * ag
    rec_F = record = None
    if rec:
        rec_t, acc = read_csv_record(rec)
        rec_F = [-m * a for a in acc]
        record = Record(rec_t, rec_F)
    forcing = Forcing(A, theta if A else 0.0, record)
    _check_finite(values, m=m, k=k, omega=omega, theta=theta, A=A, sigma=values.get("c_v", 0.0) / (2 * m),
                  N=m * values["g"], fk=values["mu"] * m * values["g"], fs=values["mu0"] * m * values["g"],
                  rec_F=rec_F, rec=rec)
    osc = Oscillator(m, k, values.get("c_v", 0.0), values["mu"], values["mu0"], values["g"], forcing)
    w0, t_end = float(values.get("w0", 0.0)), float(values["t_end"])
    check_bounds(osc, w0, t_end, values)
    return osc, w0, t_end


def _check_finite(values, **q):
    """Derived quantities (omega, forces, rates) must be finite floats: an overflow here (e.g.
    m ag with ag = 1e308, or a record acceleration times m) is bad input naming its parameters."""
    names = {"omega": ("k, m", "omega = sqrt(k/m)", "k/m < 1e308 s^-2"),
             "theta": ("theta_ratio, k, m", "theta = theta_ratio sqrt(k/m)", "theta_ratio sqrt(k/m) < 1e308 rad/s"),
             "A": ("P0, ag, m", "the force amplitude |P0 - m ag|", "|P0 - m ag| < 1e308 N"),
             "sigma": ("c_v, m", "sigma = c_v/(2m)", "c_v/(2m) < 1e308 s^-1"),
             "N": ("m, g", "N = m g", "m g < 1e308 N"),
             "fk": ("mu, m, g", "the friction force mu m g", "mu m g < 1e308 N"),
             "fs": ("mu0, m, g", "the static friction limit mu0 m g", "mu0 m g < 1e308 N")}
    for key, (params, what, allowed) in names.items():
        x = q.get(key)
        if x is not None and not math.isfinite(x):
            raise BadInput(f"parameters {params}: {what} overflows the floating-point range; "
                           f"allowed: {allowed}")
    rec_F = q.get("rec_F")
    if rec_F is not None and not all(math.isfinite(f) for f in rec_F):
        raise BadInput(f"parameter record: m a(t) overflows for the accelerations in {q['rec']!r} "
                       f"(m = {q['m']:g} kg); allowed: |a| * m < 1e308 N")


def _impulse(osc, t_end):
    """Upper bound of int_0^t_end |F| dt [N s] (harmonic amplitude times t_end plus the record's
    piecewise-linear |force| integrated over [0, t_end])."""
    F = osc.F
    imp = abs(F.A) * t_end if F.harmonic else 0.0
    if F.has_record:
        if not hasattr(F, "_imp_cum"):   # cumulative bound at the nodes (t_end is bisected on)
            rt, rF = np.asarray(F.record.times), np.abs(np.asarray(F.record.values))
            piece = np.maximum(rF[:-1], rF[1:])
            lo, hi = np.maximum(rt[:-1], 0.0), np.maximum(rt[1:], 0.0)
            F._imp_cum = (hi, piece, np.concatenate([[0.0], np.cumsum(piece * (hi - lo))]))
        hi, piece, cum = F._imp_cum
        j = int(np.searchsorted(hi, t_end, side="left"))   # pieces 0 .. j-1 end before t_end
        imp += float(cum[j])
        if j < piece.size:
            start = hi[j - 1] if j > 0 else max(F.record.times[0], 0.0)
            imp += float(piece[j]) * max(0.0, t_end - start)
    return imp


def energy_bound(osc, w0, t_end):
    """log of an upper bound of the oscillator's energy up to t_end [log J]: friction and damping only
    take energy out, and d sqrt(E)/dt <= |F| / sqrt(2 m), so sqrt(E) <= sqrt(E0) + int |F| dt / sqrt(2m).
    Logarithms, so that the bound itself cannot overflow.  Returns (log E_bound, log sqrt(E0) part,
    log forcing part)."""
    lo = -math.inf
    e0 = math.log(0.5 * osc.k) / 2 + math.log(abs(w0)) if w0 else lo     # log sqrt(E0)
    imp = _impulse(osc, t_end)
    ef = math.log(imp) - 0.5 * math.log(2 * osc.m) if imp > 0 else lo   # log of the forcing part
    big = max(e0, ef)
    if big == lo:
        return lo, e0, ef
    return 2 * (big + math.log1p(math.exp(min(e0, ef) - big))), e0, ef


def work_periods(osc, w0, t_end):
    """A-priori bound of the shortest periods the run has to follow up to t_end, and that period.

    Forced stretches (harmonic: all of [0, t_end]; a record: its span) are followed period by
    period.  Unforced, the motion stops or creeps: critically or over-damped a single closed-form
    segment; under-damped with kinetic friction mu N > 0 each half-swing lowers the amplitude by at
    least 2 mu N/k (energy: friction and damping only remove energy), so at most A k/(2 mu N) + 1
    half-swings for an amplitude bound A; with damping alone the amplitude reaches the dead zone
    mu0 N/k after ln(A k/(mu0 N))/(sigma T/2) half-swings."""
    F = osc.F
    om = max(osc.omega, F.theta) if F.harmonic else osc.omega
    T = TWO_PI / om
    if F.harmonic:
        return t_end / T, T
    span = min(t_end, F.record.times[-1]) if F.has_record else 0.0
    n_nodes = bisect.bisect_right(F.record.times, t_end) if F.has_record else 0
    P = span / T + n_nodes / 4.0          # a record node costs about a quarter period's work
    tail = t_end - span
    if tail <= 0:
        return P, T
    if osc.kind != 0:
        return P + 1.0, T
    logE = energy_bound(osc, w0, t_end)[0]
    A = math.exp(0.5 * (logE - math.log(0.5 * osc.k))) if logE > -700 else 0.0   # amplitude bound
    Td = TWO_PI / osc.wd
    half = tail / (Td / 2)
    if osc.fk > 0:
        half = min(half, A * osc.k / (2 * osc.fk) + 1)
    if osc.fs > 0 and osc.sigma > 0 and A * osc.k > osc.fs:
        half = min(half, math.log(A * osc.k / osc.fs) / (osc.sigma * Td / 2) + 1)
    if A * osc.k <= osc.fs and not F.has_record:
        half = 0.0                            # held by static friction from the start
    return P + half * (Td / 2) / T, T


def check_bounds(osc, w0, t_end, values):
    """BadInput unless the run's energies stay within E_MAX and its work within MAX_PERIODS."""
    logE, e0, ef = energy_bound(osc, w0, t_end)
    if logE > math.log(E_MAX):
        half_log = 0.5 * math.log(E_MAX)
        if e0 >= ef:
            wmax = math.exp(half_log - 0.5 * math.log(0.5 * osc.k))
            raise BadInput(f"parameter w0 = {w0:g} m: the initial energy k w0^2/2 = 10^{e0 * 2 / math.log(10):.0f} J "
                           f"is beyond the range the solver computes in (energies up to {E_MAX:g} J); "
                           f"allowed: |w0| <= {wmax:.6g} m for k = {osc.k:g} N/m")
        lim = math.exp(half_log + 0.5 * math.log(2 * osc.m))    # max impulse [N s]
        F = osc.F
        if F.harmonic and abs(F.A) * t_end >= _impulse(osc, t_end) - abs(F.A) * t_end:
            name = "P0" if abs(values.get("P0") or 0.0) >= osc.m * abs(values.get("ag") or 0.0) else "ag"
            val = values.get(name) or 0.0
            raise BadInput(f"parameter {name} = {val:g}: the force amplitude |P0 - m ag| = {abs(F.A):g} N can "
                           f"put up to 10^{ef * 2 / math.log(10):.0f} J into the oscillator by t_end = {t_end:g} s, "
                           f"beyond the range the solver computes in (energies up to {E_MAX:g} J); allowed: "
                           f"|P0 - m ag| <= {lim / t_end:.6g} N for t_end = {t_end:g} s and m = {osc.m:g} kg")
        raise BadInput(f"parameter record: the record's force m a(t) can put up to 10^{ef * 2 / math.log(10):.0f} J "
                       f"into the oscillator by t_end = {t_end:g} s, beyond the range the solver computes in "
                       f"(energies up to {E_MAX:g} J); allowed: int |a| dt <= {lim / osc.m:.6g} m/s over the record")
    P, T = work_periods(osc, w0, t_end)
    if P > MAX_PERIODS:
        lo, hi = 0.0, t_end                    # the largest t_end within MAX_PERIODS (P grows with t)
        for _ in range(60):
            mid = 0.5 * (lo + hi)
            if work_periods(osc, w0, mid)[0] <= MAX_PERIODS:
                lo = mid
            else:
                hi = mid
        what = "forcing period" if osc.F.harmonic and osc.F.theta > osc.omega else "natural period"
        raise BadInput(f"parameter t_end = {t_end:g} s: the run would follow {P:.3g} periods of its "
                       f"shortest time scale ({what} {T:.4g} s); the exact solver takes about "
                       f"{US_PER_PERIOD} us per period and a run may follow at most {MAX_PERIODS:g} "
                       f"(about {MAX_PERIODS * US_PER_PERIOD * 1e-6:.0f} s); allowed: t_end <= {floor_g(lo)} s "
                       f"for these parameters")


def run(values: dict) -> Outcome:
    """Simulate one scene; returns the contract result dict.  SolverFailure (exit 1) when the
    result is not finite or the energy balance is worse than ENERGY_TOL."""
    osc, w0, t_end = build(values)
    try:
        return _run(osc, w0, t_end)
    except (OverflowError, ZeroDivisionError, FloatingPointError, MemoryError) as exc:
        raise SolverFailure(f"floating-point failure in the exact solution ({type(exc).__name__}: {exc}); "
                            f"the parameters are outside the range this solver computes in") from None


def _run(osc, w0, t_end):
    sol = osc.run(w0, t_end)
    amp, reason, t_steady = sol.steady()
    res = {
        "converged": True,
        "turning_points": [{"t": t, "w": w} for t, w in sol.turning],
        "stop": sol.stop(),
        "w_max": sol.w_max(),
        "steady_amplitude": amp,
    }
    if amp is None:
        res["steady_reason"] = reason
    else:
        res["steady_since_t"] = t_steady
    res.update({
        "steps": len(sol.segs),
        "energy_balance": sol.energy_balance(),
        "t_end": t_end,
        "omega": osc.omega,
        "period": TWO_PI / osc.omega,
        "theta": osc.F.theta if osc.F.harmonic else None,
    })
    bad = [key for key in ("w_max", "energy_balance") if not math.isfinite(res[key])]
    if bad or not all(math.isfinite(t) and math.isfinite(w) for t, w in sol.turning):
        raise SolverFailure(f"the solution is not finite ({', '.join(bad) or 'turning points'}): "
                            f"the parameters are outside the range this solver computes in")
    if res["energy_balance"] > ENERGY_TOL:
        raise SolverFailure(f"energy balance {res['energy_balance']:.3g} is worse than the tolerance "
                            f"{ENERGY_TOL:g} (relative to the largest energy)")
    # the history is computed when first asked for (the API's Result.history, --out)
    return Outcome(res, "sdof", history=sol.history, tables=sol.tables)

