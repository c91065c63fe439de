"""What a time history's result says of its accuracy, and whether it can be trusted.

- :func:`estimate_error`: the error estimate of a run (``error_estimate`` and ``accuracy``) from a
  check run at CHECK_FACTOR (10) times the tolerance (femslide.analysis.simulate runs both): the
  check run's differences from the run - histories, peaks, friction event times -, divided by
  (steps / check steps)^5 - 1 (the check run's error over the run's, less one, for an integrator of
  order 5; kept between 0.3 and 10^(5/4) - 1: where vibrations that the steps damp make the error,
  it shrinks more slowly than that and the estimate can be several times low).  A history's
  difference is relative to its largest value, or to FLOOR of the largest of its unit when that is
  larger (a quantity the motion hardly changes is not judged by its own round-off);
  velocities and accelerations are estimated apart (``accuracy.derivatives``).
- :func:`promise_note`: ``accuracy.within_promise`` - whether the estimate is at most PROMISE (3)
  times the tolerance, what ``tolerance`` promises - and the note of a run whose estimate is not.
- :func:`check_trust`: the failure (exit 1) of a run that completed but cannot be trusted: an energy
  balance far beyond its tolerance, stick/slip chatter.

Units: the result's (SI); the estimates are relative.
"""
from __future__ import annotations

import math

import numpy as np

from femslide.errors import SolverFailure

UNIT = {"Fx": "N", "Fy": "N", "normal": "N", "friction": "N", "M": "N m", "M_max": "N m", "x": "m", "y": "m",
        "gap": "m", "slide": "m", "rotation": "rad", "rotation_rate": "rad/s", "rotation_accel": "rad/s^2",
        "vx": "m/s", "vy": "m/s", "ax": "m/s^2", "ay": "m/s^2", "dx": "m", "dy": "m"}
FLOOR = 1e-2   # a change below this fraction of the motion's size in its unit is not judged relative to itself
# velocities and accelerations: estimated apart from the headline error_estimate
DERIVATIVES = ("rotation_rate", "rotation_accel", "vx", "vy", "ax", "ay")


ENERGY_TRUST = 1e4     # a run whose energy balance exceeds max(ENERGY_TRUST tolerance, ENERGY_FLOOR) fails
ENERGY_FLOOR = 1e-2
ENERGY_MAX = 0.1       # ... and never beyond this (a relative balance saturates near 1)
PROMISE = 3.0          # tolerance promises every history and peak within this multiple of it
CHATTER_SHARE = 0.5    # a run with friction events on more than this share of its steps (and over
CHATTER_EVENTS = 100   # CHATTER_EVENTS events) fails: stick/slip chatter, not a motion


def check_trust(res, tolerance, unit=0.0, touches=0):
    """SolverFailure (exit 1, the reason named) for a run that completed but cannot be trusted: an
    energy balance far beyond what the tolerance allows (Radau IIA keeps it near the tolerance: 1e-7
    at 1e-6 on section 5.2, 2e-6 at 1e-3 on the base-isolated frame; a run that chattered between
    stick and slip or took a wrong breakaway read 1e-2 .. 1), or friction events on most steps.
    ``unit`` [J]: the model's energy unit (its forces times its length); a run whose energies are all
    below 1e-9 of it (t_end = 1e-6 s) has a balance of round-off and is not judged by it.
    ``touches``: switches not listed as events (a stuck joint's slip and stick within the
    resolution of event times, femslide.analysis.stickslip.Friction.event), counted as events."""
    E = res["energy_balance"]
    scale = max((abs(x) for x in res.get("energy", {}).values()), default=0.0)
    # (the balance is relative to the largest energy: it saturates near 1, whatever the tolerance)
    allowed = min(max(ENERGY_TRUST * tolerance, ENERGY_FLOOR), ENERGY_MAX)
    if not E <= allowed and not scale < 1e-9 * unit:
        raise SolverFailure(f"simulate: the energy balance {E:.3g} (kinetic + potential + dissipated - work "
                            f"in, relative) is far beyond what tolerance {tolerance:g} allows (at most "
                            f"{allowed:g}): the motion cannot be trusted; try a tighter tolerance")
    # friction's stick/slip events (a contact's lifts and landings may pile up for real: a rocking
    # block's impacts accumulate in finite time)
    events = sum(max(sum(e["kind"] not in ("lift", "land") for e in v) - 1, 0) for v in res["events"].values())
    events += touches
    if events > CHATTER_EVENTS and events > CHATTER_SHARE * res["steps"]:
        raise SolverFailure(f"simulate: {events} friction events in {res['steps']} steps: the stick/slip "
                            f"modes chatter; try a tighter tolerance")


def promise_note(res, tolerance):
    """Set ``accuracy["within_promise"]`` (whether ``error_estimate`` is at most PROMISE times the
    tolerance, what ``tolerance`` promises) and return the sentence for the result's notes when it is
    not, else None: a run is not silently less accurate than asked.  Nothing without an estimate
    (error_estimate off, or its check run failed).

    Where the error comes from vibrations that the steps damp (modes too fast for the steps that
    carry a share of a reaction: a 32-element massive cantilever's clamp, a base-isolated frame's
    deck on stiff columns), it shrinks only slowly as the tolerance is tightened, and the estimate -
    which assumes the integrator's order 5 between the run and its check run - can itself be several
    times low (the cantilever's clamp shear over 0.3 s at tolerance 1e-5: 2.9e-4 off a run at 1e-9,
    its own estimate 3.4e-5)."""
    est, acc = res.get("error_estimate"), res.get("accuracy")
    if est is None or acc is None:
        return None
    ok = bool(est <= PROMISE * tolerance)
    acc["within_promise"] = ok
    if ok:
        return None
    peak = acc.get("peaks", 0.0) > acc.get("histories", 0.0)
    worst = acc.get("worst_peak") if peak else acc.get("worst_history")
    what = f"{'peak' if peak else 'history'} {worst}" if worst else ("a peak" if peak else "a history")
    return (f"error_estimate {est:.2g} is above {PROMISE:g} x tolerance {tolerance:g} (worst: {what}): by its "
            f"error estimate this run is less accurate than asked. Where the error comes from vibrations too "
            f"fast for the steps, which the integrator damps, it shrinks only slowly with the tolerance and "
            f"error_estimate can itself be several times low")


def peak_floors(peaks):
    """{dotted key: FLOOR times the largest peak of its unit} (a reaction that the motion hardly
    loads - the axial reaction of a mast shaken sideways without gravity - is not judged by its own
    round-off)."""
    from femslide.results.compare import leaves
    flat = {".".join(path): (UNIT.get(path[-1], "m" if path[-1].startswith("slide") else path[-1]), abs(float(v)))
            for path, v in leaves(peaks)}
    big = {}
    for u, v in flat.values():
        big[u] = max(big.get(u, 0.0), v)
    return {k: FLOOR * big[u] for k, (u, v) in flat.items()}


def floors(H, cols, offsets, size, T1):
    """Per history column, the smallest scale its error is measured against (FLOOR of the largest
    amplitude of the columns of its unit; rotations FLOOR of the largest displacement over the
    structure's ``size`` [m], their rates and accelerations that times 2 pi / T1 and its square):
    a quantity the motion hardly changes (a body's rotation in a sway without rocking) is not judged
    by its own round-off."""
    amp = np.abs(H - np.asarray(offsets)).max(axis=0) if len(H) else np.zeros(len(cols))
    unit = [UNIT.get(c.rsplit(".", 1)[-1]) for c in cols]
    big = {u: max((a for a, v in zip(amp, unit) if v == u), default=0.0) for u in set(unit)}
    w = 2.0 * math.pi / T1
    big["rad"] = max(big.get("rad", 0.0), big.get("m", 0.0) / size)
    big["rad/s"] = max(big.get("rad/s", 0.0), big["rad"] * w)
    big["rad/s^2"] = max(big.get("rad/s^2", 0.0), big["rad"] * w * w)
    return [FLOOR * big[u] if u is not None else 0.0 for u in unit]


def estimate_error(spec, check, H, res, cols, T1, size):
    """The error estimate of a run (see the module docstring) from its check run ``check``
    (femslide.analysis.simulate._check_run): the differences of the check run's histories, peaks and event times from
    the run's, divided by (steps / check steps)^ORDER_GLOBAL - 1 (the check run's error over the
    run's, less one).  Returns the result keys ``error_estimate`` (the largest relative estimate of
    histories and peaks, or None when the check run failed) and ``accuracy`` (the parts)."""
    from femslide.analysis.radau import ORDER
    from femslide.analysis.transient import CHECK_FACTOR, ORDER_GLOBAL
    from femslide.results.compare import event_difference, history_difference, peak_difference
    tol_c = CHECK_FACTOR * spec.tolerance
    if "failed" in check:
        return {"error_estimate": None, "accuracy": {"check_tolerance": tol_c, "check_failed": check["failed"]}}
    Hc = check["H"]
    # the check run's error is (steps / check steps)^ORDER_GLOBAL times the run's; the steps grow at
    # most as the tolerance^(-1/ORDER) (the local estimate's order) when the step control follows the
    # accuracy: steps beyond that (a 32-element cantilever at 1e-5 took 6.2 times the check run's
    # steps) buy no more than that, and the estimate is not divided by more (it was 36 times low)
    ratio_max = CHECK_FACTOR ** (ORDER_GLOBAL / ORDER) - 1.0
    ratio = min(max((res["steps"] / max(check["steps"], 1)) ** ORDER_GLOBAL - 1.0, 0.3), ratio_max)
    ev, ev_c = res["events"], check["events"]
    agree, dt = event_difference(ev, ev_c)
    times = [e["t"] for evs in ev.values() for e in evs if e["t"] > 0.0]
    if agree:
        windows = [(min(a["t"], b["t"]) - 1e-12, max(a["t"], b["t"]) + 1e-12)
                   for n in ev for a, b in zip(ev[n], ev_c[n]) if a["t"] > 0.0]
    else:
        times_c = [e["t"] for evs in ev_c.values() for e in evs if e["t"] > 0.0]
        windows = [(t - 1e-12, t + 1e-12) for t in times + times_c]
    # positions from their start (the scale of a moving body is its motion, not its place)
    offsets = [H[0, i] if c.endswith((".x", ".y")) else 0.0 for i, c in enumerate(cols)]
    # a recorded ground motion is linear between its samples: the histories have kinks there
    kinks = () if spec.ground is None or spec.ground.times is None else spec.ground.times
    hist = history_difference(H[:, 0], H[:, 1:], Hc[:, 0], Hc[:, 1:], times, windows, offsets[1:],
                              floors(H, cols, offsets, size, T1)[1:], kinks=kinks) / ratio
    pk = peak_difference(res["peaks"], check["peaks"], peak_floors(res["peaks"]))
    # a rod's largest moment is a maximum over its nodes: its history has kinks where the maximum
    # moves from one node to another, which no interpolation follows; it is judged by its peak
    hist[[c.endswith(".M_max") for c in cols[1:]]] = 0.0
    # velocities and accelerations carry the modes too fast for the step (a piece's 410 kHz axial
    # vibration on its rod), which the integrator puts on their quasi-static response: estimated
    # apart, not in the headline estimate of the displacements, forces and moments
    is_acc = np.array([c.rsplit(".", 1)[-1] in DERIVATIVES for c in cols[1:]], dtype=bool)
    h_acc = float(hist[is_acc].max()) if is_acc.any() else 0.0
    worst_a = cols[1 + int(np.flatnonzero(is_acc)[np.argmax(hist[is_acc])])] if h_acc > 0 else None
    hist[is_acc] = 0.0
    p_acc = {k: v for k, v in pk.items() if k.rsplit(".", 1)[-1] in DERIVATIVES}
    pk = {k: v for k, v in pk.items() if k not in p_acc}
    worst_h = int(np.argmax(hist)) if hist.size else None
    e_h = float(hist.max()) if hist.size else 0.0
    e_p = max(pk.values(), default=0.0) / ratio
    worst_p = max(pk, key=pk.get) if pk and e_p > 0 else None
    acc = {"check_tolerance": tol_c, "check_steps": check["steps"], "check_time_s": check["time_s"],
           "histories": e_h, "worst_history": cols[1 + worst_h] if worst_h is not None and e_h > 0 else None,
           "peaks": e_p, "worst_peak": worst_p,
           "derivatives": max(h_acc, max(p_acc.values(), default=0.0) / ratio),
           "worst_derivative": worst_a, "events_agree": agree,
           "event_times_s": dt / ratio if agree else None, "check_events": sum(len(v) for v in ev_c.values()),
           "energy_balance": res["energy_balance"]}
    return {"error_estimate": max(e_h, e_p), "accuracy": acc}

