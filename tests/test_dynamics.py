"""Tests of the structure dynamics (femslide/scenes/beam_dynamics.py): beam-oscillation and beam-friction.

References computed independently here: the linearised stiffness K_eff = dM/dphi of the static
structure under a small dead moment on the body (femslide.analysis.newton on the plain beam-extra-mass model,
no lock constraint, no sensitivities) and the rotary inertia M(0) from rigid-body kinematics.
"""
from __future__ import annotations

import csv
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

from femslide.scenes.catalog import get  # noqa: E402

KEYS = {"converged", "turning_points", "stop", "w_max", "steady_amplitude", "steps", "F2_max",
        "energy_balance", "wall_time_s"}


def cli(*args, timeout=120):
    env = dict(os.environ, PYTHONPATH=ROOT)
    return subprocess.run([sys.executable, "-m", "femslide", *args], capture_output=True, text=True,
                          cwd=ROOT, env=env, timeout=timeout)


@pytest.fixture(scope="module")
def oscillation(tmp_path_factory):
    out = tmp_path_factory.mktemp("osc")
    r = cli("simulate", "beam-oscillation", "--json", "--quiet", "--out", str(out), "--set", "t_end=1.2")
    assert r.returncode == 0, r.stderr
    return json.loads(r.stdout), out


def test_oscillation_json_keys(oscillation):
    res, _ = oscillation
    assert KEYS <= set(res)
    assert res["converged"] is True and res["stop"] is None and res["steady_amplitude"] is None
    assert res["F2_max"] > 0 and res["w_max"] == pytest.approx(0.01, rel=1e-9)
    assert all(set(tp) == {"t", "w"} for tp in res["turning_points"])
    assert len(res["turning_points"]) >= 2


def test_frictionless_energy_balance(oscillation):
    """Kinetic + potential (strain + weights + spring of the static state) is conserved to 1e-8."""
    res, _ = oscillation
    assert res["energy_balance"] <= 1e-8
    assert res["energy_balance_turning_points"] <= 1e-8
    # d'Alembert check: with the inertia loads the rotation lock carries no moment
    assert res["dalembert_residual"] <= 1e-8


def test_out_writes_pvd_series_readable_by_pyvista(oscillation):
    import pyvista as pv
    _, out = oscillation
    vtus = sorted(f for f in os.listdir(out) if f.startswith("beam-oscillation_") and f.endswith(".vtu"))
    assert len(vtus) >= 10
    assert os.path.exists(out / "beam-oscillation.pvd")
    mesh = pv.read(str(out / vtus[len(vtus) // 2]))
    assert mesh.n_points > 0 and "bending_moment" in mesh.point_data and "axial_force" in mesh.cell_data
    with open(out / "history.csv") as fh:
        rows = list(csv.reader(fh))
    assert rows[0][:6] == ["t [s]", "phi [rad]", "phi_dot [rad/s]", "F2 [N]", "slide [m]",
                           "stuck (1 stuck; 0 sliding or free)"]
    assert len(rows) > 20


def static_stiffness(v, n, h=1e-4):
    """K_eff [N m/rad] = -d(moment)/d(phi) by central differences of two static solves under +-h P a
    (the declared beam-extra-mass structure at dm = 0 with a moment on the deck, n elements)."""
    from femslide.analysis import static
    from femslide.scenes import paper
    P, a = v["m"] * v["g"], v["a"]
    phis = []
    for sgn in (1.0, -1.0):
        s = paper.declare("beam-extra-mass", {**v, "dm": 0.0})
        s.force("M", "deck", moment=sgn * h * P * a)
        sol = static.solve(s.freeze(), elements=n, Lref=a, Fref=P)
        phis.append(-sol.result["bodies"]["deck"]["rotation"])
    # a counter-clockwise moment +h turns the body by Theta > 0, i.e. phi < 0
    return 2 * h * P * a / (phis[1] - phis[0])


def test_small_amplitude_period_matches_linearised_frequency():
    """Period from the turning points at phi0 = 1e-4 vs 2 pi sqrt(M/K_eff); K_eff from the statics,
    M = J_A1 + m1 ((L + l2/2)^2 + l2^2/12) (at phi = 0 the top of the vertical inextensible rod moves
    horizontally, so the piece translates horizontally with speed (L + l2/2) phi').  The quartic
    hardening shifts the frequency by ~ c (a/L)^2 phi0^2 / K ~ 3e-5 here: tolerance 2e-4."""
    from femslide.scenes import beam_dynamics as dynamics
    v = get("beam-oscillation").resolve({"phi0": 1e-4, "t_end": 1.4})
    res = dynamics.run_oscillation(v)
    K = static_stiffness(v, v["n_elements"])
    a, b, d, l, m = v["a"], v["b"], v["d"], v["l"], v["m"]
    J = m * ((2 * a) ** 2 + (2 * b) ** 2) / 12 + m * ((a + d) ** 2 + (l + b) ** 2)
    J += v["m1"] * ((v["L"] + v["l2"] / 2) ** 2 + v["l2"] ** 2 / 12)
    T_ref = 2 * math.pi * math.sqrt(J / K)
    tp = res["turning_points"]
    T = 2 * (tp[1]["t"] - tp[0]["t"])
    assert abs(T - T_ref) / T_ref < 2e-4
    assert res["K_eff"] == pytest.approx(K, rel=1e-5)
    assert res["energy_balance"] <= 1e-7  # tiny amplitude: the round-off floor of the statics shows


@pytest.fixture(scope="module")
def friction(tmp_path_factory):
    out = tmp_path_factory.mktemp("fric")
    r = cli("simulate", "beam-friction", "--json", "--quiet", "--out", str(out), "--set", "t_end=1.3")
    assert r.returncode == 0, r.stderr
    return json.loads(r.stdout), out


def test_friction_zero_drift_while_stuck(friction):
    res, out = friction
    assert KEYS <= set(res)
    assert res["stick_slip_switches"] >= 2 and res["stuck_time"] > 0
    # the lock is an exact constraint: the slide of stuck samples equals the stuck value to round-off
    # of the slide's evaluation (~1e-17 m; a creeping penalty or regularised friction drifts by far more)
    assert res["stuck_slide_drift"] <= 1e-15
    H = np.loadtxt(out / "history.csv", delimiter=",", skiprows=1)
    stuck = H[:, 5] == 1
    assert stuck.any()
    # in each run of stuck samples the slide is constant to the last bit, except where a slip phase
    # too short to hold a sample separates two stuck phases (at most one change per stick event)
    runs = np.split(np.arange(len(H)), np.flatnonzero(np.diff(stuck.astype(int))) + 1)
    changes = sum(np.count_nonzero(np.diff(H[r, 4])) for r in runs if stuck[r[0]])
    assert changes <= res["stick_slip_switches"] // 2
    assert res["energy_balance"] <= 1e-7
    assert res["friction_work"] > 0 and res["jump_loss"] >= 0


@pytest.mark.parametrize("scene, setting", [
    ("beam-friction", "mu0=0.1"),          # mu0 < mu (default mu = 0.2)
    ("beam-friction", "mu=-0.1"),
    ("beam-friction", "t_end=0"),
    ("beam-oscillation", "t_end=-1"),
    ("beam-oscillation", "k=9"),           # k <= k_crit = 9.19 N/m
    ("beam-friction", "k=5"),
])
def test_bad_input_exits_2(scene, setting):
    r = cli("simulate", scene, "--set", setting)
    assert r.returncode == 2, r.stderr
    assert setting.split("=")[0] in r.stderr
