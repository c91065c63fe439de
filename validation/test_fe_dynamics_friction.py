"""Paper 003 examples 2 and 3 as structure files (FE dynamics with Coulomb friction in a ground slider)
against femslide.scenes.sdof's exact event-by-event solution (itself validated in
validation/test_friction_oscillator.py against closed forms and an independent integrator).

The structure files are meshes/structures/belt-ex2.toml (free decay, 13 half-swings) and
belt-ex3.toml (ex. 2 from rest, base-excited at theta = omega / 2), run at their tolerance 1e-9.
Tolerances: turning points (ends of slip: stick or reversal) within 1e-9 m and 1e-9 s.  Measured
(Radau IIA): ex. 2 2.5e-12 s and 1.1e-12 m over its 13 half-swings, ex. 3 7.6e-13 s, 4.5e-14 m;
energy balances 1.8e-11 and 2.2e-12.
Run:  pytest -q validation/test_fe_dynamics_friction.py   (slow: ~1 min)
"""
from __future__ import annotations

import numpy as np
import pytest

import femslide


def _turning(res):
    t, w = res.history["t"], res.history["joints.belt.slide"]
    out, prev = [], ""
    for e in res["events"]["belt"]:
        if e["t"] > 0 and (e["kind"] == "stick" or prev.startswith("slip")):
            out.append((e["t"], float(np.interp(e["t"], t, w))))
        prev = e["kind"]
    return out


@pytest.mark.slow
def test_example_2_free_decay():
    """13 half-swings, amplitudes 8 - 0.6 j cm, stop at -0.2 cm (t = 1.84405 s): every turning point
    within 1e-9 m and 1e-9 s of the exact solution; energy balance below 1e-9; the error estimate
    (at 1e-9: measured 3.4e-10) at most 1e-8."""
    res = femslide.simulate("meshes/structures/belt-ex2.toml")
    ref = femslide.simulate("sdof-decay")
    tp = _turning(res)
    ex = [(p["t"], p["w"]) for p in ref["turning_points"]]
    assert len(tp) == len(ex) == 13
    assert res["events"]["belt"][-1]["kind"] == "stick"
    for (t, w), (te, we) in zip(tp, ex):
        assert abs(w - we) < 1e-9 and abs(t - te) < 1e-9
    assert res["energy_balance"] < 1e-9
    assert res["error_estimate"] <= 1e-8


@pytest.mark.slow
def test_example_3_base_excitation():
    """Ex. 2 from rest under the base acceleration -(P0 / m) sin(omega t / 2) for 1.5 s, i.e. the force
    +P0 sin(omega t / 2) of paper 003's example 3 (stick, slip, stick phases): every turning point
    within 1e-9 m and 1e-9 s of sdof-harmonic at its defaults (the paper's example; before, the file
    had +P0 / m and was the mirror image, compared with the equally mirrored ag = P0 / m); energy
    balance (with the work of the base excitation) below 1e-9."""
    res = femslide.simulate("meshes/structures/belt-ex3.toml")
    ref = femslide.simulate("sdof-harmonic", t_end=1.5)
    tp = _turning(res)
    ex = [(p["t"], p["w"]) for p in ref["turning_points"]]
    assert len(tp) == len(ex) >= 4
    for (t, w), (te, we) in zip(tp, ex):
        assert abs(w - we) < 1e-9 and abs(t - te) < 1e-9
    assert any(e["kind"] == "stick" for e in res["events"]["belt"][1:])
    assert res["energy_balance"] < 1e-9


# the reduced 1-DOF model (validation/reduced_dynamics.py) at beam-friction's defaults: dynamic_references.py
from dynamic_references import FRICTION_F2 as BEAM_FRICTION_F2  # noqa: E402
from dynamic_references import FRICTION_JUMP as BEAM_FRICTION_JUMP  # noqa: E402
from dynamic_references import FRICTION_OMEGA as BEAM_FRICTION_OMEGA  # noqa: E402
from dynamic_references import FRICTION_SLIDE as BEAM_FRICTION_SLIDE  # noqa: E402
from dynamic_references import FRICTION_STICK as BEAM_FRICTION_STICK  # noqa: E402
from dynamic_references import FRICTION_WORK as BEAM_FRICTION_WORK  # noqa: E402


@pytest.mark.slow
def test_beam_friction_twin_with_a_massless_slide():
    """meshes/structures/beam-friction.toml (friction in the sliding clamp between the massless rod's
    end and the deck, mu0 > mu: the slide jumps at every breakaway) against the reduced model of the
    scene beam-friction.  At tolerance 1e-6 (measured in brackets, Radau IIA): the same sequence of
    stick and slip events; every end of slip within 2e-5 s of the reduced model's turning point
    (5.7e-6 s); peak |F2| within 1e-4 (3.7e-5); slide range within 1e-5 m (2.9e-6); the lowest
    frequency equals the reduced model's small-oscillation omega / 2 pi within 1e-8 (1.7e-9); energy
    balance, jump losses included, below 1e-6 (7.6e-8); the energy dissipated by friction, the jumps
    included, and the work of the ground motion within 5e-4 of the reduced model's (1.6e-4, 1.1e-4);
    the energy released by the slide's jumps within 1e-3 of the reduced model's (2.3e-4).  (What is
    left at these levels is the difference of the models - the FE rod stretches - not the
    integration's: the run's own error estimate is 5.9e-7.)"""
    res = femslide.simulate("meshes/structures/beam-friction.toml")
    ev = res["events"]["clamp"]
    kinds = [e["kind"] for e in ev]
    assert kinds == ["stick", "slip-", "stick", "slip+", "stick", "slip-", "stick", "slip+", "stick", "slip-"]
    sticks = [e["t"] for e in ev if e["kind"] == "stick" and e["t"] > 0]
    assert len(sticks) == len(BEAM_FRICTION_STICK)
    for t, te in zip(sticks, BEAM_FRICTION_STICK):
        assert abs(t - te) < 2e-5
    assert res["peaks"]["reactions"]["B1"]["Fx"] == pytest.approx(BEAM_FRICTION_F2, rel=1e-4)
    j = res["peaks"]["joints"]["clamp"]
    assert abs(j["slide_min"] - BEAM_FRICTION_SLIDE[0]) < 1e-5 and abs(j["slide_max"] - BEAM_FRICTION_SLIDE[1]) < 1e-5
    assert res["frequencies_hz"][0] == pytest.approx(BEAM_FRICTION_OMEGA / (2 * np.pi), rel=1e-8)
    assert res["energy_balance"] < 1e-6
    assert res["energy"]["dissipated"] == pytest.approx(BEAM_FRICTION_WORK[0], rel=5e-4)
    assert res["energy"]["work_in"] == pytest.approx(BEAM_FRICTION_WORK[1], rel=5e-4)
    assert res["energy"]["jump_loss"] == pytest.approx(BEAM_FRICTION_JUMP, rel=1e-3)
    # the slide is exactly at rest while stuck: no drift between a stick and the next breakaway
    t, s = res.history["t"], res.history["joints.clamp.slide"]
    for a, b in zip(ev[2::2], ev[3::2]):
        inside = (t > a["t"] + 1e-9) & (t < b["t"] - 1e-9)
        if inside.sum() > 1:
            assert np.ptp(s[inside]) < 1e-12


@pytest.mark.slow
def test_beam_friction_with_a_trace_of_friction():
    """mu = mu0 = 1e-6 on the massless slide (it used to chatter at the first reversal of the slide,
    where its velocity follows the deck and changes sign at round-off level): the run ends, and its
    peak |F2| and slide range equal the frictionless run's within 1e-4 (measured 9e-6, 5e-6)."""
    f = "meshes/structures/beam-friction.toml"
    trace = femslide.simulate(f, **{"clamp.mu": 1e-6, "clamp.mu0": 1e-6})
    free = femslide.simulate(f, **{"clamp.mu": 0.0, "clamp.mu0": 0.0})
    assert trace["peaks"]["reactions"]["B1"]["Fx"] == pytest.approx(free["peaks"]["reactions"]["B1"]["Fx"], rel=1e-4)
    for k in ("slide_min", "slide_max"):
        assert trace["peaks"]["joints"]["clamp"][k] == pytest.approx(free["peaks"]["joints"]["clamp"][k], rel=1e-4)
    assert len(trace["events"]["clamp"]) >= 3


@pytest.mark.slow
def test_belt_under_a_recorded_ground_motion(tmp_path):
    """Paper 003 ex. 2's block on its frictional ground slider under a recorded base acceleration
    (CSV, two decaying sines sampled every 0.01 s, linear between samples) against femslide.scenes.sdof's
    exact event-by-event solution with the same record (sdof-harmonic, record=..., P0 = 0): every
    end of slip within 5e-6 s and 5e-7 m at tolerance 1e-7 (measured 1.2e-6 s, 1.1e-7 m; 2.4e-6 s and
    1.7e-7 m before the steps landed on the record's samples, whose kinks they smoothed over).  Every
    sample time of the record is a step."""
    t = np.arange(0.0, 1.0001, 0.01)
    a = 4.0 * np.sin(2 * np.pi * 1.7 * t) * np.exp(-0.3 * t) + 1.5 * np.sin(2 * np.pi * 5.3 * t + 0.4)
    rec = tmp_path / "rec.csv"
    np.savetxt(rec, np.column_stack([t, a]), delimiter=",", header="t,a", comments="")
    text = open("meshes/structures/belt-ex2.toml").read()
    text = text[:text.index("[simulate]")] + ('[simulate]\nt_end = 1.0\ntolerance = 1e-7\n'
                                              'ground = {direction = [1.0, 0.0], record = "rec.csv"}\n')
    (tmp_path / "belt-rec.toml").write_text(text)
    res = femslide.simulate(str(tmp_path / "belt-rec.toml"))
    ref = femslide.simulate("sdof-harmonic", record=str(rec), P0=0.0, w0=0.0, ag=0.0, t_end=1.0)
    tp = _turning(res)
    ex = [(p["t"], p["w"]) for p in ref["turning_points"]]
    assert len(tp) == len(ex) >= 5
    for (tt, w), (te, we) in zip(tp, ex):
        assert abs(tt - te) < 5e-6 and abs(w - we) < 5e-7
    assert np.isin(t[(t > 0.0) & (t < 1.0)], res.history["t"]).all()


@pytest.mark.slow
def test_jumps_close_the_energy_balance():
    """A soft massless rod (EA = 1e3 N) with mu = 0.05, mu0 = 0.5 in beam-friction.toml: its slide jumps
    far at each breakaway (jump_loss 2.2e-4 J, 1.7 % of the dissipated energy).  The energy balance,
    which counts the jumps' released energy as dissipated, closes below 3e-4 (measured 7.0e-5; with
    the potential taken before the jump it read 1.2e-3); with Rayleigh damping beta = 0.01 s, which
    the massless parts' re-solve must include, below 3e-4 as well (6.0e-5; it read 7e-3)."""
    f = "meshes/structures/beam-friction.toml"
    kw = {"right.EA": 1e3, "clamp.mu": 0.05, "clamp.mu0": 0.5}
    res = femslide.simulate(f, t_end=1.3, **kw)
    assert res["energy"]["jump_loss"] > 1e-2 * res["energy"]["dissipated"]
    assert res["energy_balance"] < 3e-4
    damped = femslide.simulate(f, t_end=1.3, damping={"alpha": 0.0, "beta": 0.01}, **kw)
    assert damped["energy_balance"] < 3e-4
