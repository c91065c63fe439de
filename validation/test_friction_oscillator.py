"""Paper 003 examples 1-3 (SPEC section 5) against independent references.

References (``validation/sdof_reference.py``, no femslide code):
* closed-form amplitude decrement of free vibration with Coulomb friction (ex. 1, 2);
* Den Hartog's (1931) exact stop-free steady state (derived in sdof_reference.den_hartog from the
  half-period symmetry w(t + pi/theta) = -w(t)), used only where its motion is verified stop-free;
* a scipy solve_ivp (DOP853, rtol 1e-12, atol 1e-15) integrator with event switching for the ratios
  with stops, for viscous damping, and for a base-acceleration record;
* the resonance energy argument: at theta = omega, once the turning points sit at the zeros of the
  force, each cycle adds exactly (pi P0 - 4 mu N)/k to the amplitude.
Every test states its tolerance; the accuracy target of femslide is 1e-8 m / 1e-8 s.
Run:  pytest -q validation/test_friction_oscillator.py
"""
from __future__ import annotations

import math
import pathlib
import sys

import numpy as np
import pytest

_HERE = pathlib.Path(__file__).resolve().parent
for _p in (str(_HERE.parent), str(_HERE)):
    if _p not in sys.path:
        sys.path.insert(0, _p)

import sdof_reference as ref  # noqa: E402

from femslide.scenes import sdof  # noqa: E402
from femslide.scenes.catalog import get  # noqa: E402

M2, K2, N2, MU2, MU02, P0 = 20 / 9.81, 1000.0, 20.0, 0.15, 0.18, 10.0
OMEGA2 = math.sqrt(K2 / M2)
STOP_FREE = (0.6, 0.7, 0.8, 0.9, 0.95)
WITH_STOPS = (0.1, 0.2, 0.3, 0.4, 0.5)


def run(name, **given):
    return sdof.run(get(name).resolve(given))


def solution(name, **given):
    osc, w0, t_end = sdof.build(get(name).resolve(given))
    return osc.run(w0, t_end)


@pytest.mark.parametrize("name, data", [
    ("sdof-free", (0.07, 200.0, 1.0, 0.2, 0.24, 9.81)),
    ("sdof-decay", (0.08, K2, M2, MU2, MU02, N2 / M2)),
])
def test_free_examples_against_decrement(name, data):
    """Ex. 1, 2 vs the exact decrement formula; tolerance 1e-8 m and 1e-8 s (achieved ~1e-16)."""
    w0, k, m, mu, mu0, g = data
    exact = ref.decrement_turning_points(w0, k, m, mu, mu0, m * g)
    res = run(name)
    got = [(p["t"], p["w"]) for p in res["turning_points"]]
    assert len(got) == len(exact)
    err_w = max(abs(a[1] - b[1]) for a, b in zip(got, exact))
    err_t = max(abs(a[0] - b[0]) for a, b in zip(got, exact))
    assert err_w < 1e-8 and err_t < 1e-8
    assert (res["stop"]["t"], res["stop"]["w"]) == got[-1]


def test_den_hartog_applicability():
    """Den Hartog's stop-free solution exists and is stop-free (one-signed velocity per half-cycle,
    net force r^2 k X > mu0 N at the turning points) exactly for the ratios 0.6 .. 0.95 of the grid
    0.1 .. 0.95; femslide's runs agree: after the initial stick there is no stop for those ratios and
    there are stops for 0.1 .. 0.5.  (Exact classification, no tolerance.)"""
    for r in STOP_FREE:
        assert ref.den_hartog_is_stop_free(r, P0, K2, M2, MU2 * N2, MU02 * N2)
        sol = solution("sdof-harmonic", theta_ratio=r, t_end=10.0)
        assert sum(1 for s in sol.segs if s[7] == 0) == 1  # only the start from rest
    for r in WITH_STOPS:
        assert not ref.den_hartog_is_stop_free(r, P0, K2, M2, MU2 * N2, MU02 * N2)
        sol = solution("sdof-harmonic", theta_ratio=r, t_end=10.0)
        assert sum(1 for s in sol.segs[5:] if s[7] == 0) > 3


@pytest.mark.parametrize("r, t_end", [(0.6, 30.0), (0.7, 30.0), (0.8, 30.0), (0.9, 100.0),
                                      (0.95, 300.0)])
def test_steady_amplitude_vs_den_hartog(r, t_end):
    """Stop-free ratios: femslide's steady_amplitude vs Den Hartog's exact X; tolerance 1e-8 m
    (achieved ~1e-15 m).  Near resonance the transient decays slowly, hence the longer runs."""
    res = run("sdof-harmonic", theta_ratio=r, t_end=t_end)
    X = ref.den_hartog(r, P0, K2, MU2 * N2)
    assert res["steady_amplitude"] is not None, res.get("steady_reason")
    assert abs(res["steady_amplitude"] - X) < 1e-8


@pytest.mark.parametrize("r", WITH_STOPS)
def test_amplitude_with_stops_vs_solve_ivp(r):
    """Ratios with stops (Den Hartog does not apply): turning points and the last forcing period's
    amplitude vs the independent solve_ivp event-switching integrator (DOP853, rtol 1e-12);
    tolerance 1e-8 m and 1e-8 s (achieved ~1e-13)."""
    t_end = 12.0
    sol = solution("sdof-harmonic", theta_ratio=r, t_end=t_end)
    iv = ref.ivp_simulate(M2, K2, 0.0, MU2, MU02, N2 / M2, 0.0, A=P0, theta=r * OMEGA2, t_end=t_end)
    assert len(sol.turning) == len(iv.turning)
    d = np.abs(np.array(sol.turning) - np.array(iv.turning)).max(axis=0)
    assert d[0] < 1e-8 and d[1] < 1e-8
    wmax, wmin = sol.period_amplitudes()
    amp_ref, _, _ = ref.period_amplitudes(iv.turning, lambda t: ref.ivp_eval(iv, t), r * OMEGA2, t_end)
    assert abs(0.5 * (wmax[-1] - wmin[-1]) - amp_ref[-1]) < 1e-8


def test_amplitudes_rise_with_theta():
    """SPEC section 5 / errata: the steady amplitude rises with theta (the paper's 'decrease' is
    wrong).  Exact results: strictly increasing over the stop-free range 0.6 .. 0.95 and from 0.3
    upwards; overall 0.95 gives > 10x the amplitude at 0.1.  Below 0.3 the stick-slip pattern changes
    (e.g. 0.25 and 0.3 lie below 0.2), so the rise is not monotone there (reported, not hidden)."""
    ratios = (0.1, 0.2, 0.25, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 0.95)
    amps = []
    for r in ratios:
        sol = solution("sdof-harmonic", theta_ratio=r, t_end=300.0 if r == 0.95 else 40.0)
        wmax, wmin = sol.period_amplitudes()
        amps.append(0.5 * (wmax[-1] - wmin[-1]))
    amps = np.array(amps)
    i3 = ratios.index(0.3)
    assert np.all(np.diff(amps[i3:]) > 0)
    assert amps[-1] > 10 * amps[0]
    assert amps[ratios.index(0.25)] < amps[ratios.index(0.2)]  # the non-monotone dip is real


def test_formula6_is_approximate():
    """The paper's formula (6) (equivalent linearisation) vs Den Hartog's exact X on the stop-free
    ratios: it underestimates by 0.4 % .. 6 % (relative errors asserted to lie in [-7 %, -0.1 %]:
    the formula is an approximation, not an exact result).  Printed with -s."""
    errs = {}
    for r in STOP_FREE:
        X = ref.den_hartog(r, P0, K2, MU2 * N2)
        errs[r] = ref.formula6(r, P0, K2, MU2 * N2) / X - 1.0
    print("\nformula (6) relative error vs Den Hartog: "
          + ", ".join(f"r={r}: {e:+.3%}" for r, e in errs.items()))
    assert all(-0.07 < e < -0.001 for e in errs.values())


def test_resonance_growth_exact_phase():
    """theta = omega starting at w0 = -5 cm (turning point at a zero of the force): every half-cycle
    adds (pi P0/2 - 2 mu N)/k exactly (Duhamel integral over pi/omega); tolerance 1e-6 relative on
    the growth per cycle (pi P0 - 4 mu N)/k, 1e-8 m on each turning point, 1e-8 s on the times."""
    res = run("sdof-harmonic", theta_ratio=1.0, w0=-0.05, t_end=3.0)
    grow = (math.pi * P0 - 4 * MU2 * N2) / K2
    tp = res["turning_points"]
    for j, p in enumerate(tp, 1):
        assert abs(abs(p["w"]) - (0.05 + j * grow / 2)) < 1e-8
        assert abs(p["t"] - j * math.pi / OMEGA2) < 1e-8
    per_cycle = abs(tp[-1]["w"]) - abs(tp[-3]["w"])
    assert abs(per_cycle / grow - 1) < 1e-6


def test_resonance_growth_from_rest():
    """theta = omega from rest at w = 0 (ex. 3 data, mu = 0.15 < pi P0/(4 N) = 0.39): after the
    start-up the growth per cycle is (pi P0 - 4 mu N)/k; tolerance 1e-6 relative (achieved ~1e-11)."""
    res = run("sdof-harmonic", theta_ratio=1.0, t_end=30.0)
    grow = (math.pi * P0 - 4 * MU2 * N2) / K2
    w = np.array([abs(p["w"]) for p in res["turning_points"]])
    assert abs((w[-1] - w[-3]) / grow - 1) < 1e-6
    assert res["steady_amplitude"] is None


@pytest.mark.parametrize("c_v, r", [(3.0, 0.0), (5.0, 0.7), (2 * math.sqrt(K2 * M2), 0.0),
                                    (150.0, 0.0), (5.0, 1.0)])
def test_viscous_damping_vs_solve_ivp(c_v, r):
    """c_v > 0 (under-, critically, over-damped; free and forced, resonance with damping): turning
    points vs solve_ivp (DOP853, rtol 1e-12); tolerance 1e-8 m, 1e-8 s; and the value at t_end."""
    given = dict(c_v=c_v, t_end=4.0, w0=0.08)
    if r:
        given.update(theta_ratio=r, P0=P0)
    else:
        given.update(P0=0.0)
    sol = solution("sdof-harmonic", **given)
    iv = ref.ivp_simulate(M2, K2, c_v, MU2, MU02, N2 / M2, 0.08, A=P0 if r else 0.0,
                          theta=r * OMEGA2, t_end=4.0)
    if c_v == 2 * math.sqrt(K2 * M2):
        # critically damped from rest: v = -sigma^2 x0 t exp(-sigma t) never vanishes for t > 0,
        # the mass creeps to mu N/k without a turning point; solve_ivp reports a spurious v = 0
        # event once |v| is at round-off level, at the same position
        assert sol.turning == [] and sol.stop() is None
        assert all(abs(w - MU2 * N2 / K2) < 1e-8 for _, w in iv.turning)
    else:
        assert len(sol.turning) == len(iv.turning)
        if sol.turning:
            d = np.abs(np.array(sol.turning) - np.array(iv.turning)).max(axis=0)
            assert d[0] < 1e-8 and d[1] < 1e-8
    tt = np.linspace(0.0, 4.0, 41)
    assert np.max(np.abs(sol.eval(tt)[0] - ref.ivp_eval(iv, tt))) < 1e-8


def test_base_record_vs_solve_ivp(tmp_path):
    """Base-acceleration record (piecewise linear, 401 nodes, decaying 2 Hz shaking of 4 m/s^2):
    turning points vs solve_ivp split at the record nodes; tolerance 1e-8 m, 1e-8 s; the stop after
    the shaking has died out agrees too."""
    t = np.linspace(0.0, 4.0, 401)
    a = 4.0 * np.sin(2 * math.pi * 2.0 * t) * np.exp(-0.5 * t)
    path = tmp_path / "quake.csv"
    np.savetxt(path, np.column_stack([t, a]), delimiter=",", header="t,a", comments="")
    res = run("sdof-harmonic", record=str(path), t_end=6.0)
    iv = ref.ivp_simulate(M2, K2, 0.0, MU2, MU02, N2 / M2, 0.0, t_end=6.0, rec=(t, -M2 * a))
    got = np.array([[p["t"], p["w"]] for p in res["turning_points"]])
    assert len(got) == len(iv.turning) > 4
    d = np.abs(got - np.array(iv.turning)).max(axis=0)
    assert d[0] < 1e-8 and d[1] < 1e-8
    assert res["stop"] is not None and abs(res["stop"]["w"] - iv.turning[-1][1]) < 1e-8
    assert res["energy_balance"] < 1e-10
