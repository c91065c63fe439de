"""The paper's section 5.2 structure in time: the scenes beam-oscillation and beam-friction on the FE
transient (femslide.analysis.simulate).

The structure is ``beam-extra-mass`` (femslide.scenes.paper.declare) at dm = 0: the deck (mass m,
pinned to the ground at A1 through the rigid left rod), the flexible right rod (n_elements
corotational beams, massless, pinned at B1) in the sliding clamp ``clamp`` with the slider spring k
preloaded by -m g (a + d)/(2a) (phi = 0 is the equilibrium of an inextensible rod), and - only in
beam-oscillation - the rigid telescopic piece (m1, l2) welded to the rod's top.  beam-friction has
m1 = 0 (no piece) and Coulomb friction mu, mu0 in the clamp (N = |transverse clamp force|,
femslide.joints.friction).  The same declarations as meshes/structures/beam-oscillation.toml and
beam-friction.toml.

The run (femslide.analysis.simulate.Spec): the static equilibrium, the deck held at rotation -phi0
(phi > 0 is clockwise, leaning towards B1; the deck's rotation is counter-clockwise positive; phi0 = 0
is held too: the vertical state, the equilibrium of an inextensible rod - beam-friction's extensible
default rod, EA = 1e6 N, has its equilibrium at phi = 4.8e-6 rad, as the reduced model had), released
at rest and integrated to t_end at ``tolerance``; a viscous damping c_v [N m s/rad] on phi is a
rotational dashpot on the deck (Spec.rotation_damping); beam-friction's ground acceleration is
ag sin(theta t) along x [m/s^2] (plus the CSV ``record``), theta = theta_ratio * omega with omega
[rad/s] the lowest natural frequency of the frictionless structure (femslide.analysis.simulate.
natural_modes: the same statics and modes simulate reports as ``frequencies_hz``).

The result keeps the scenes' contract (SPEC section 7) and adds simulate's: ``turning_points`` (every
instant after t = 0 where phi' returns to zero: events of the integration, located on the steps'
own solution to ~1e-12 s (femslide.analysis.simulate's ``turning``); w = phi there), ``w_max``
(largest |phi|, phi0 included), ``steady_amplitude``,
``F2_max`` (= ``peaks.reactions.B1.Fx``, refined between steps), ``energy_balance``,
``frequencies_hz``, ``events``, ``peaks``, ``omega`` and (forced) ``theta``; a run whose energy
balance is worse than ENERGY_LIMIT fails (SolverFailure, exit 1) unless its energies are all at the
round-off level.  The history (SI):
``t`` [s], ``phi`` [rad], ``phi_dot`` [rad/s], ``slide`` [m] (of the clamp, from the static state's
reference), ``stuck`` (1 stuck, 0 sliding or free), ``F_ax`` [N] (the friction force along the guide
that holds or resists the slide: the force on the deck along +axis, 0 without friction), ``N`` [N]
(|transverse clamp force|), ``F1``, ``N1``, ``F2``, ``N2`` [N] (forces of the ground on the structure
at A1 and B1, global x and y), one row per accepted step.
"""
from __future__ import annotations

import math

import numpy as np

from femslide.analysis.excitation import Ground, Record, read_csv_record
from femslide.analysis.simulate import Spec, natural_modes, simulate
from femslide.analysis.stickslip import SAME_INSTANT
from femslide.errors import BadInput, SolverFailure
from femslide.results.outcome import Frames, Outcome, Table
from femslide.scenes import hinge
from femslide.scenes.paper import declare

MAX_ELEMENTS = 512          # as a structure file's [simulate] elements
STEADY_FACTOR = 10.0        # two forcing periods repeat when their extremes agree to this * tolerance
ENERGY_LIMIT = 0.1          # a run whose energy balance is worse fails (exit 1): measured 2.3e-2 at the
                            # loosest tolerance 1e-2; mu = mu0 = 5 jams the massless slide (forces of 1e5 N,
                            # energy balance 1.0) where neither the FE transient nor the reduced model copes;
ENERGY_FLOOR = 1e-9         # ... unless every energy is below this times m g a (a run so short that they
                            # are at the round-off level of the potential energy, ~1e-12 m g a: t_end = 1e-6 s)
COLUMNS = ("t", "phi", "phi_dot", "slide", "stuck", "F_ax", "N", "F1", "N1", "F2", "N2")
CSV = (("t", "t [s]"), ("phi", "phi [rad]"), ("phi_dot", "phi_dot [rad/s]"), ("F2", "F2 [N]"),
       ("slide", "slide [m]"), ("stuck", "stuck (1 stuck; 0 sliding or free)"),
       ("F_ax", "F_ax [N] (friction force along the guide on the deck; 0 without friction)"),
       ("N", "N [N] (|transverse clamp force|)"), ("F1", "F1 [N]"), ("N1", "N1 [N]"), ("N2", "N2 [N]"))
FRAME_UNITS = ("phi: rad (deck rotation, > 0 leaning towards B1); phi_dot: rad/s; F1, N1 / F2, N2: N "
               "(horizontal, vertical force of the ground at A1 / B1); slide: m; stuck: 1 stuck, 0 sliding "
               "or free; F_ax: N (friction force along the guide); N: N (|transverse clamp force|)")


def structure(v: dict, friction: bool):
    """The frozen declaration of the scene from validated parameters ``v`` (SI)."""
    s = declare("beam-extra-mass", {**v, "dm": 0.0, **({"m1": 0.0, "l2": 1.0} if friction else {})})
    if friction:
        s.set("clamp.mu", v["mu"])
        s.set("clamp.mu0", v["mu0"])
    return s.freeze()


def check(v: dict, friction: bool):
    """Bad input (exit 2) naming the parameter: k <= k_crit, too many elements."""
    kc = hinge.k_crit(**{**v, "l1": v["L"], **({"m1": 0.0, "l2": 1.0} if friction else {})})
    if not v["k"] > kc:
        raise BadInput(f"parameter k = {v['k']:g} N/m is not above k_crit = {kc:.6g} N/m: the vertical "
                       f"state is unstable; allowed: k > {kc:.6g}")
    if v["n_elements"] > MAX_ELEMENTS:
        raise BadInput(f"parameter n_elements = {v['n_elements']} is too large for the dynamic scenes; "
                       f"allowed: 1 <= n_elements <= {MAX_ELEMENTS}")


def spec(v: dict, fs, friction: bool):
    """(Spec, omega [rad/s], theta [rad/s] or None) of the run."""
    n = v["n_elements"]
    sp = Spec(t_end=v["t_end"], tolerance=v["tolerance"], elements=n,
              initial={"body": "deck", "rotation": -v["phi0"]},
              rotation_damping={"deck": v["c_v"]} if v["c_v"] else None, turning=("deck",))
    omega = theta = None
    if friction:
        omega = 2 * math.pi * natural_modes(fs, 1, n).values["frequencies_hz"][0]
        theta = v["theta_ratio"] * omega
        record = Record(*read_csv_record(v["record"])) if v.get("record") else None
        if v["ag"] or record is not None:
            sp.ground = Ground((1.0, 0.0), v["ag"], theta / (2 * math.pi), record=record)
    return sp, omega, theta


def run(v: dict, friction: bool, progress=None) -> Outcome:
    """The scene beam-oscillation (``friction`` False) or beam-friction from validated parameters."""
    check(v, friction)
    fs = structure(v, friction)
    sp, omega, theta = spec(v, fs, friction)
    name = "beam-friction" if friction else "beam-oscillation"
    out = simulate(fs, sp, name, progress)
    res, fe = out.values, out.get_history()
    scale = max(abs(x) for x in res["energy"].values())
    if not res["energy_balance"] <= ENERGY_LIMIT and not scale < ENERGY_FLOOR * v["m"] * v["g"] * v["a"]:
        raise SolverFailure(f"the energy balance is off by {res['energy_balance']:.3g} of the largest energy "
                            f"(more than {ENERGY_LIMIT:g}): the motion cannot be trusted")
    if omega is None:
        omega = 2 * math.pi * res["frequencies_hz"][0]
    h = history(fe, res["events"].get("clamp", []))
    T, phi = h["t"], h["phi"]
    tps = []
    for tp in res["turning_points"]["deck"]:   # (located zeros of phi'; two within SAME_INSTANT are one)
        if tp["t"] > 0.0 and not (tps and tp["t"] - tps[-1][0] <= SAME_INSTANT * max(1.0, tp["t"])):
            tps.append((tp["t"], -tp["rotation"]))
    forced = sp.ground is not None
    amp, reason = steady(sp.ground, theta, tps, T, phi, v["tolerance"])
    values = {
        "converged": True,
        "turning_points": [{"t": t, "w": w} for t, w in tps],
        "stop": None,
        "w_max": float(max([abs(v["phi0"]), float(np.abs(phi).max())] + [abs(w) for _, w in tps])),
        "steady_amplitude": amp,
        **({"steady_reason": reason} if amp is None else {}),
        "steps": res["steps"],
        "F2_max": res["peaks"]["reactions"]["B1"]["Fx"],
        "energy_balance": res["energy_balance"],
        "error_estimate": res.get("error_estimate"),
        "accuracy": res.get("accuracy"),
        **({"notes": res["notes"]} if res.get("notes") else {}),
        "energy": res["energy"],
        "frequencies_hz": res["frequencies_hz"],
        "frequencies_of": res["frequencies_of"],
        **({"events": res["events"]} if friction else {}),
        "peaks": res["peaks"],
        "w_is": "phi [rad], the deck rotation (positive leaning towards B1)",
        "omega": omega,
        "omega_is": "lowest natural frequency of the frictionless structure [rad/s] (slide free, spring k)",
        "theta": theta if forced else None,
        "period_linear": 2 * math.pi / omega,
        "rejected_steps": res["rejected_steps"],
        "newton_iterations": res["newton_iterations"],
        "n_elements": v["n_elements"],
        "tolerance": v["tolerance"],
        "t_end": v["t_end"],
        "integration_time_s": res["integration_time_s"],
    }
    if friction:
        values.update(stuck_stats(h, res["events"].get("clamp", []), v["t_end"], v["mu0"]))
    frames = out.frames
    if frames is not None:
        row = {float(t): i for i, t in enumerate(T)}
        frames = Frames(frames.model, [(t, y, a, {**vals, **frame_values(h, row[float(t)])})
                                       for t, y, a, vals in frames.states])
    table = Table("history.csv", [head for _, head in CSV], [h[k] for k, _ in CSV],
                  ["%.17g"] * 5 + ["%d"] + ["%.17g"] * 5)
    return Outcome(values, name, history=h, tables=[table], frames=frames, loops=out.loops)


def history(fe: dict, events: list) -> dict:
    """The scene's history (see the module docstring) from the FE history ``fe`` and the clamp's
    friction events (none without friction)."""
    T = fe["t"]
    stuck = np.zeros(T.size, dtype=int)
    if events:
        te = np.array([e["t"] for e in events])
        k = np.searchsorted(te, T, side="right") - 1   # the event that set each row's mode
        kinds = np.array([e["kind"] == "stick" for e in events])
        stuck = np.where(k >= 0, kinds[np.maximum(k, 0)], False).astype(int)
    F_ax = -fe["joints.clamp.friction"] if "joints.clamp.friction" in fe else np.zeros(T.size)
    return {"t": T, "phi": -fe["bodies.deck.rotation"], "phi_dot": -fe["bodies.deck.rotation_rate"],
            "slide": fe["joints.clamp.slide"], "stuck": stuck, "F_ax": F_ax, "N": fe["joints.clamp.normal"],
            "F1": fe["reactions.A1.Fx"], "N1": fe["reactions.A1.Fy"],
            "F2": fe["reactions.B1.Fx"], "N2": fe["reactions.B1.Fy"]}


def frame_values(h: dict, i: int) -> dict:
    """The scene's global values at history row i, as a VTU frame's field data (with their units)."""
    from femslide.output.vtu import UNITS
    return {**{k: float(h[k][i]) for k in COLUMNS if k != "t"}, "units": UNITS + "; " + FRAME_UNITS}


def steady(ground, theta, tps, T, phi, tolerance):
    """(amplitude, None) of the last forcing period, half the range of phi over it (samples and turning
    points), when its largest and smallest phi repeat those of the period before to STEADY_FACTOR *
    tolerance relative to the amplitude; else (None, the reason)."""
    if ground is None:
        return None, "unforced run (no steady forced response)"
    if ground.record is not None:
        return None, "record excitation is not periodic"
    if not ground.harmonic:
        return None, "unforced run (no steady forced response)"
    Tf = 2 * math.pi / theta
    n = int(math.floor(T[-1] / Tf))
    if n < 2:
        return None, "fewer than two complete forcing periods before t_end"
    pts = np.vstack([np.column_stack([T, phi])] + ([np.array(tps)] if tps else []))

    def ext(k):
        sel = pts[(pts[:, 0] >= k * Tf) & (pts[:, 0] <= (k + 1) * Tf), 1]
        return sel.max(), sel.min()
    a1, b1 = ext(n - 2)
    a2, b2 = ext(n - 1)
    amp = 0.5 * (a2 - b2)
    diff = max(abs(a2 - a1), abs(b2 - b1))
    if diff > STEADY_FACTOR * tolerance * max(amp, 1e-300):
        return None, (f"not steady by t_end: the last two forcing periods differ by {diff:.3g} rad "
                      f"(> {STEADY_FACTOR:g} tolerance of the amplitude); increase t_end")
    return float(amp), None


def stuck_stats(h: dict, events: list, t_end: float, mu0: float) -> dict:
    """Friction diagnostics: ``stick_slip_switches`` (events after t = 0), ``stuck_time`` [s],
    ``stuck_slide_drift`` [m] (largest change of the slide within a stuck phase: the lock is exact),
    ``stuck_force_ratio_max`` (largest |F_ax| / (mu0 N) while stuck; <= 1 by Coulomb's law)."""
    te = [e["t"] for e in events] + [t_end]
    stuck_time = sum(te[i + 1] - te[i] for i, e in enumerate(events) if e["kind"] == "stick")
    drift, ratio = 0.0, None
    T, s, st = h["t"], h["slide"], h["stuck"]
    for i, e in enumerate(events):
        if e["kind"] != "stick":
            continue
        sel = (T >= te[i]) & (T < te[i + 1]) & (st == 1)
        if sel.any():
            drift = max(drift, float(np.abs(s[sel] - s[sel][0]).max()))
    sel = st == 1
    if sel.any() and mu0 > 0:
        N = h["N"][sel]
        ratio = float(np.max(np.abs(h["F_ax"][sel]) / np.where(N > 0, mu0 * N, np.inf)))
    return {"stick_slip_switches": max(0, len(events) - 1), "stuck_time": stuck_time,
            "stuck_slide_drift": drift, "stuck_force_ratio_max": ratio}
