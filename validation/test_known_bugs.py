"""Regression tests for wrong answers once found by validation/stability.py (now fixed).

Each test asserts the correct behaviour against an exact reference.
"""
from __future__ import annotations

import math

import pytest

import femslide
from femslide.scenes import sdof


def test_frictionless_harmonic_turning_points_are_not_duplicated():
    """sdof-harmonic with mu = mu0 = 0, from rest, theta = omega/2 (defaults otherwise).

    Reference (closed form): w = B (sin(th t) - r sin(om t)), v = B th (cos(th t) - cos(om t)), which
    vanishes exactly at t = 2 pi j/(om + th) and t = 2 pi j/(om - th); where both coincide
    (th t = 2 pi j) v only touches zero - one instant, not two.  Over the default 30 s: 158 instants.
    Tolerance: the count exactly, and the times within 1e-6 s (a touching zero, a double root of v,
    is located only to ~sqrt(eps) relative).
    Was: femslide simulate sdof-harmonic --set mu=0 --set mu0=0 --json gave 210 turning points."""
    r = femslide.simulate("sdof-harmonic", mu=0.0, mu0=0.0)
    om, th, t_end = r["omega"], r["theta"], r["t_end"]
    zs = sorted(2 * math.pi * j / fr for fr in (om + th, om - th)
                for j in range(1, int(t_end * fr / (2 * math.pi)) + 2) if 2 * math.pi * j / fr <= t_end)
    exact = [z for i, z in enumerate(zs) if i == 0 or z - zs[i - 1] > 1e-9]
    got = [p["t"] for p in r["turning_points"]]
    assert len(got) == len(exact), (len(got), len(exact))
    assert max(abs(a - b) for a, b in zip(got, exact)) <= 1e-6


def test_dynamics_on_a_mesh_above_the_dense_limit():
    """beam-oscillation with 64 elements (more unknowns than model.DENSE_LIMIT, where statics solves
    banded) crashed when the banded Jacobian reached the dynamics' dense LU (of the reduced model, then
    femslide's dynamics).  Reference: the reduced 1-DOF model (validation/reduced_dynamics.py) on the
    same 64-element mesh: the largest |F2| over 0.3 s within 1e-6 (measured 1.5e-9 on the FE transient)."""
    from reduced_dynamics import run_oscillation

    from femslide.scenes.catalog import get
    fine = femslide.simulate("beam-oscillation", n_elements=64, t_end=0.3)
    ref = run_oscillation(get("beam-oscillation").resolve({"n_elements": 64, "t_end": 0.3}))
    assert fine["converged"]
    assert abs(fine["F2_max"] / ref["F2_max"] - 1.0) <= 1e-6


@pytest.mark.parametrize("c_v,t_end", [(100.0, 30.0), (60.0, 100.0)])
def test_overdamped_oscillator_does_not_overflow(c_v, t_end):
    """sdof-free heavily over-damped (c_v = 100, 60 N s/m; sigma up to 50/s) over 30..100 s: cosh and
    sinh of the over-damped solution overflowed (OverflowError, or a nan energy balance) before
    e^{-sigma t} could damp them.  Reference: scipy DOP853 with event switching at rtol 1e-12
    (validation/sdof_reference.py): the final position within 1e-9 m; energy balance finite."""
    import sdof_reference as ref

    from femslide.scenes.catalog import get
    v = get("sdof-free").resolve({"c_v": c_v, "t_end": t_end})
    res = femslide.simulate("sdof-free", c_v=c_v, t_end=t_end)
    assert res["converged"] and math.isfinite(res["energy_balance"])
    osc, w0, _ = sdof.build(v)
    w_end = float(osc.run(w0, t_end).eval([t_end])[0][0])
    iv = ref.ivp_simulate(v["m"], v["k"], c_v, v["mu"], v["mu0"], v["g"], v["w0"], t_end=t_end)
    assert abs(w_end - float(ref.ivp_eval(iv, t_end)[0])) <= 1e-9
