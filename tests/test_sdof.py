"""Tests of the exact one-mass Coulomb-friction oscillator (femslide/scenes/sdof.py, SPEC section 5).

References are computed independently inside the tests (closed-form amplitude decrement of free
vibration with Coulomb friction).  SI units.
"""
from __future__ import annotations

import json
import math
import os
import subprocess
import sys

import numpy as np
import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
if ROOT not in sys.path:
    sys.path.insert(0, ROOT)

from femslide.scenes import sdof  # noqa: E402
from femslide.scenes.catalog import get  # noqa: E402


def run_scene(name, **given):
    scene = get(name)
    return sdof.run(scene.resolve(given))


def solution(name, **given):
    osc, w0, t_end = sdof.build(get(name).resolve(given))
    return osc.run(w0, t_end)


def decrement_reference(w0, k, m, mu, mu0, g):
    """Turning points of the free motion: w_j = (-1)^j sgn(w0) (|w0| - 2 j mu N/k) at j pi/omega, up
    to and including the first one inside the dead zone |w| <= mu0 N/k.  (The last bracket may be
    negative: the final half-swing then ends on the same side it started from.)"""
    N = m * g
    omega = math.sqrt(k / m)
    out, j = [], 0
    while True:
        j += 1
        a = abs(w0) - 2 * j * mu * N / k
        out.append((j * math.pi / omega, (-1) ** j * math.copysign(1.0, w0) * a))
        if k * abs(a) <= mu0 * N:
            return out


@pytest.mark.parametrize("name, data", [
    ("sdof-free", dict(w0=0.07, k=200.0, m=1.0, mu=0.2, mu0=0.24, g=9.81)),
    ("sdof-decay", dict(w0=0.08, k=1000.0, m=20 / 9.81, mu=0.15, mu0=0.18, g=9.81)),
])
def test_free_vibration_matches_decrement_formula(name, data):
    """Reference: exact decrement formula (w_j = (-1)^j (w0 - 2 j mu N/k), t_j = j pi/omega).
    Tolerance 1e-12 m and 1e-12 s on every turning point and on the stop."""
    res = run_scene(name)
    ref = decrement_reference(**data)
    tp = res["turning_points"]
    assert len(tp) == len(ref)
    for got, (t, w) in zip(tp, ref):
        assert abs(got["w"] - w) < 1e-12
        assert abs(got["t"] - t) < 1e-12
    assert res["stop"]["w"] == tp[-1]["w"] and res["stop"]["t"] == tp[-1]["t"]
    assert res["w_max"] == pytest.approx(data["w0"], abs=1e-15)


def test_paper_numbers_ex1_ex2():
    """Reference: SPEC section 5 table (printed to 4 digits): ex. 1 omega 14.142, T 0.4443 s,
    turning points -5.038, +3.076 cm, stop -1.114 cm after 3 half-swings; ex. 2 omega 22.147,
    T 0.28370 s, amplitudes 8 - 0.6 j cm, stop at -0.2 cm after 13 half-swings.  Tolerance: the
    printed digits."""
    r1 = run_scene("sdof-free")
    assert r1["omega"] == pytest.approx(14.142, abs=5e-4)
    assert r1["period"] == pytest.approx(0.4443, abs=5e-5)
    assert [round(p["w"] * 100, 3) for p in r1["turning_points"]] == [-5.038, 3.076, -1.114]
    r2 = run_scene("sdof-decay")
    assert r2["omega"] == pytest.approx(22.147, abs=5e-4)
    assert r2["period"] == pytest.approx(0.28370, abs=5e-6)
    amps = [abs(p["w"]) * 100 for p in r2["turning_points"]]
    assert len(amps) == 13
    assert amps == pytest.approx([8 - 0.6 * j for j in range(1, 14)], abs=1e-12)
    assert r2["stop"]["w"] == pytest.approx(-0.002, abs=1e-14)


@pytest.mark.parametrize("w0, mu, mu0", [(0.07, 0.2, 0.2), (0.0394, 0.2, 0.24), (-0.05, 0.1, 0.3),
                                        (0.0117, 0.2, 0.24)])
def test_stop_rule_first_turning_point_in_dead_zone(w0, mu, mu0):
    """Reference: decrement formula; the mass stops at the first turning point with
    k|w| <= mu0 N (or does not move when k|w0| <= mu0 N).  Tolerance 1e-12 m."""
    res = run_scene("sdof-free", w0=w0, mu=mu, mu0=mu0, t_end=5.0)
    N, k = 9.81, 200.0
    if k * abs(w0) <= mu0 * N:
        assert res["turning_points"] == [] and res["stop"] == {"t": 0.0, "w": w0}
        return
    ref = decrement_reference(w0, k, 1.0, mu, mu0, 9.81)
    assert len(res["turning_points"]) == len(ref)
    assert res["stop"]["w"] == pytest.approx(ref[-1][1], abs=1e-12)
    # every earlier turning point is outside the dead zone
    assert all(k * abs(p["w"]) > mu0 * N for p in res["turning_points"][:-1])


def test_stop_is_null_when_t_end_before_the_stop():
    """Reference: ex. 1 stops at 3 pi/omega = 0.666 s; with t_end = 0.5 s there is no stop yet."""
    res = run_scene("sdof-free", t_end=0.5)
    assert res["stop"] is None and len(res["turning_points"]) == 2


def test_zero_drift_while_stuck():
    """Reference: true sticking.  Over every stuck interval the velocity is exactly 0.0 and the
    position bit-identical to the turning point (tolerance 0), free and forced runs alike."""
    for name, given in [("sdof-free", {}), ("sdof-harmonic", {"theta_ratio": 0.1, "t_end": 10.0})]:
        sol = solution(name, **given)
        stuck = [s for s in sol.segs if s[7] == 0]
        assert stuck
        for s in stuck:
            t = np.linspace(s[0], s[1], 50)
            w, v, st = sol.eval(t, np.full(t.size, sol.segs.index(s)))
            assert np.all(v == 0.0) and np.all(st == 0)
            assert np.all(w == w[0])
        # stuck segments begin at a turning point (or t = 0) with that position
        tps = dict(sol.turning)
        for s in stuck:
            if s[0] > 0:
                assert tps[s[0]] == s[4]


@pytest.mark.parametrize("name, given", [
    ("sdof-free", {}), ("sdof-decay", {}), ("sdof-harmonic", {}),
    ("sdof-harmonic", {"theta_ratio": 1.0}), ("sdof-harmonic", {"theta_ratio": 0.1}),
    ("sdof-free", {"c_v": 3.0}), ("sdof-harmonic", {"c_v": 5.0, "theta_ratio": 0.9}),
    ("sdof-free", {"c_v": 2 * math.sqrt(200.0)}), ("sdof-free", {"c_v": 60.0, "t_end": 1.0}),
    ("sdof-harmonic", {"ag": 3.0, "theta_ratio": 0.7, "t_end": 5.0}),
])
def test_energy_balance(name, given):
    """Reference: energy conservation E + friction work + viscous work - input work = E(0).
    Tolerance 1e-10 relative (to E(0), or to the largest E when E(0) = 0)."""
    res = run_scene(name, **given)
    assert res["energy_balance"] < 1e-10


def test_base_acceleration_is_an_inertia_force():
    """Reference: symmetry.  From rest at w = 0, base acceleration ag sin(theta t) acts as the force
    -m ag sin(theta t), so its turning points are those of P0 = m ag mirrored (w -> -w).
    Tolerance 1e-13 m, 1e-12 s."""
    m = 20 / 9.81
    a = run_scene("sdof-harmonic", ag=4.0, t_end=5.0)
    b = run_scene("sdof-harmonic", P0=m * 4.0, t_end=5.0)
    assert len(a["turning_points"]) == len(b["turning_points"]) > 5
    for p, q in zip(a["turning_points"], b["turning_points"]):
        assert p["w"] == pytest.approx(-q["w"], abs=1e-13)
        assert p["t"] == pytest.approx(q["t"], abs=1e-12)


def test_record_constant_acceleration_is_a_shifted_free_vibration(tmp_path):
    """Reference: a record of constant base acceleration a0 gives the constant force -m a0, i.e.
    free vibration about w_s = -m a0/k: from rest at w0 = 0 the first turning point is
    2 (w_s - sgn * mu N/k) away, at t = pi/omega.  Tolerance 1e-12 m, 1e-12 s."""
    path = tmp_path / "rec.csv"
    path.write_text("time,acc\n0,-5\n2.5,-5\n5,-5\n")
    m, k, N = 20 / 9.81, 1000.0, 20.0
    res = run_scene("sdof-harmonic", record=str(path), t_end=2.0)
    ws = m * 5.0 / k
    first = res["turning_points"][0]
    assert first["t"] == pytest.approx(math.pi / math.sqrt(k / m), abs=1e-12)
    assert first["w"] == pytest.approx(2 * (ws - 0.15 * N / k), abs=1e-12)
    assert res["steady_amplitude"] is None and "record" in res["steady_reason"]


def test_json_keys_and_cli(tmp_path):
    """Contract (SPEC section 7): simulate --json prints the keys; --out writes the history."""
    out = subprocess.run([sys.executable, "-m", "femslide", "simulate", "sdof-free", "--json",
                          "--out", str(tmp_path)], capture_output=True, text=True, cwd=ROOT)
    assert out.returncode == 0, out.stderr
    res = json.loads(out.stdout)
    for key in ("converged", "turning_points", "stop", "w_max", "steady_amplitude", "steps",
                "energy_balance", "t_end", "omega", "period", "wall_time_s", "steady_reason"):
        assert key in res
    assert res["converged"] is True
    assert set(res["turning_points"][0]) == {"t", "w"}
    assert res["steps"] == 4
    hist = np.loadtxt(tmp_path / "history.csv", delimiter=",", skiprows=1)
    assert hist.shape[1] == 4 and hist[-1, 0] == pytest.approx(2.0)
    # the event instants are in the history and the stuck tail has v = 0
    for p in res["turning_points"]:
        assert np.min(np.abs(hist[:, 0] - p["t"])) < 1e-12
    tail = hist[hist[:, 0] > res["stop"]["t"] + 1e-9]
    assert np.all(tail[:, 2] == 0) and np.all(tail[:, 1] == res["stop"]["w"])
    assert {os.path.basename(f) for f in res["files"]} == {"history.csv", "turning_points.csv"}


@pytest.mark.parametrize("args", [
    ["sdof-free", "--set", "mu0=0.1"], ["sdof-free", "--set", "mu=-0.1"],
    ["sdof-free", "--set", "m=0"], ["sdof-decay", "--set", "t_end=0"],
    ["sdof-decay", "--set", "k=0"], ["sdof-harmonic", "--set", "theta_ratio=0"],
    ["sdof-harmonic", "--set", "record=/nonexistent/rec.csv"],
])
def test_bad_input_exit_2(args):
    """Contract: bad input exits with status 2 and names the parameter."""
    out = subprocess.run([sys.executable, "-m", "femslide", "simulate", *args],
                         capture_output=True, text=True, cwd=ROOT)
    assert out.returncode == 2, out.stderr
    name = args[-1].split("=")[0]
    assert name in out.stderr


@pytest.mark.parametrize("text, what", [
    ("t,a\n0,1\n0,2\n", "increasing"), ("t,a\n0,1\n1,x\n", "two numbers"),
    ("t,a\n0,1\n", "rows"), ("", "rows"), ("t,a\n0,1\n1,nan\n", "not finite"),
    ("t,a\n1,1\n0.5,2\n", "increasing"),
])
def test_malformed_record_exit_2(tmp_path, text, what):
    """Contract: a malformed record is bad input (exit 2) and the message names `record`."""
    path = tmp_path / "rec.csv"
    path.write_text(text)
    out = subprocess.run([sys.executable, "-m", "femslide", "simulate", "sdof-harmonic", "--set",
                          f"record={path}"], capture_output=True, text=True, cwd=ROOT)
    assert out.returncode == 2
    assert "record" in out.stderr and what in out.stderr


def test_record_accepts_header_comments_and_whitespace(tmp_path):
    """The record reader takes an optional header, '#' comments, blank lines, ',' ';' or blanks."""
    path = tmp_path / "r.csv"
    path.write_text("# quake\n t [s] , a [m/s^2]\n0, 0\n\n0.5; 1\n1.0 0.5\n")
    from femslide.analysis.excitation import read_csv_record
    t, a = read_csv_record(str(path))
    assert t == [0.0, 0.5, 1.0] and a == [0.0, 1.0, 0.5]


def test_no_heavy_imports():
    """One-mass scenes must not import scikit-fem, meshio or pyvista."""
    code = ("import sys, femslide.app.cli as c; c.main(['simulate','sdof-harmonic','--json']); "
            "print([m for m in ('skfem','meshio','pyvista') if m in sys.modules])")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT)
    assert out.stdout.strip().splitlines()[-1] == "[]"


def test_resonance_runs_and_reports_no_steady_state():
    """theta = omega (exact resonance) works: the amplitude grows, steady_amplitude is null with a
    reason."""
    res = run_scene("sdof-harmonic", theta_ratio=1.0, t_end=5.0)
    assert res["steady_amplitude"] is None and "resonance" in res["steady_reason"]
    assert res["energy_balance"] < 1e-10


def test_steady_amplitude_reported():
    """A forced run that settles reports steady_amplitude (two forcing periods agree to 1e-10 m)."""
    res = run_scene("sdof-harmonic", theta_ratio=0.8)
    assert res["steady_amplitude"] == pytest.approx(0.0262610487572, abs=1e-12)
    assert res["steady_since_t"] < 30.0
