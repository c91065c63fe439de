"""Thermal loads (SPEC section 10) against the closed forms of validation/thermal_reference.py.

References and tolerances (relative, 1e-6 unless said):

* welded at both ends, uniform dT: N = -EA alpha dT all along, reactions +-EA alpha dT, no moment
  (|M| <= 1e-9 EA alpha dT L), ends unmoved;
* pinned + roller along the axis, uniform dT: the roller slides alpha dT L, N = 0 (|N| <= 1e-9 of
  EA alpha dT);
* cantilever under dT_gradient: tip rotation -alpha dT_gradient L / depth, M = 0; at large rotation
  (kappa L = 1 rad) the exact circular arc's tip position (1e-6 of L: adaptive mesh);
* welded at both ends under dT_gradient: M = +EI alpha dT_gradient / depth all along, no motion;
* the same with first-order theory (``theory = "linear"``) and a rod turned by 30 degrees (the
  load is in the rod's own frame);
* the compiled kernel and the numpy path agree (1e-12) on a thermal model, and a case factor of
  -1 reverses the answer (linearity of the first three cases).
"""
from __future__ import annotations

import math

import numpy as np
import pytest
import thermal_reference as ref

import femslide
from femslide.model.structure import Structure

L, EI, EA, ALPHA, DEPTH = 2.0, 1.0e4, 1.0e8, 1.2e-5, 0.3
TOL = 1e-6


def rod_structure(end_joint, load, angle=0.0, n=None):
    c, s = math.cos(angle), math.sin(angle)
    st = Structure(gravity=(0.0, 0.0))
    st.rod("r", (0.0, 0.0), (L * c, L * s), EI=EI, EA=EA, alpha=ALPHA, depth=DEPTH, elements=n)
    st.weld("A", "r.start", "ground") if end_joint != "roller" else st.pin("A", "r.start", "ground")
    if end_joint == "weld":
        st.weld("B", "r.end", "ground")
    elif end_joint == "roller":
        st.roller("B", "r.end", "ground", axis=(c, s))
    st.thermal("T", "r", **load)
    return st


@pytest.mark.parametrize("theory", ["nonlinear", "linear"])
@pytest.mark.parametrize("angle", [0.0, math.pi / 6])
def test_welded_uniform(theory, angle):
    dT = 40.0
    r = femslide.solve(rod_structure("weld", {"dT": dT}, angle), theory=theory)
    N = ref.welded_uniform_N(EA, ALPHA, dT)
    a = r.rod("r")
    assert np.allclose(a["N"], N, rtol=TOL, atol=0), a["N"]
    assert np.abs(a["M"]).max() <= 1e-9 * abs(N) * L
    assert abs(r["rods"]["r"]["N_max"] - abs(N)) <= TOL * abs(N)
    # the ground pushes the heated rod's ends inwards: at the end B along -t
    assert math.hypot(r["reactions"]["B"]["Fx"] - N * math.cos(angle),
                      r["reactions"]["B"]["Fy"] - N * math.sin(angle)) <= TOL * abs(N)
    assert np.abs(a["u"]).max() <= 1e-12 and np.abs(a["v"]).max() <= 1e-12


@pytest.mark.parametrize("theory", ["nonlinear", "linear"])
def test_pinned_roller_slides(theory):
    dT = -25.0
    r = femslide.solve(rod_structure("roller", {"dT": dT}, math.pi / 6), theory=theory)
    slide = ref.roller_slide(ALPHA, dT, L)
    assert abs(r["joints"]["B"]["slide"] - slide) <= TOL * abs(slide)
    assert r["rods"]["r"]["N_max"] <= 1e-9 * EA * ALPHA * abs(dT)


@pytest.mark.parametrize("theory", ["nonlinear", "linear"])
def test_cantilever_gradient(theory):
    dTg = 15.0
    r = femslide.solve(rod_structure("free", {"dT_gradient": dTg}), theory=theory)
    _, _, th = ref.cantilever_gradient_tip(ALPHA, dTg, DEPTH, L)
    assert abs(r["rods"]["r"]["end"]["theta"] - th) <= TOL * abs(th)
    assert abs(th - (-ALPHA * dTg * L / DEPTH)) <= 1e-15
    assert r["rods"]["r"]["M_max"] <= 1e-9 * EI * abs(th) / L


def test_cantilever_gradient_large_rotation():
    """kappa L = -1 rad: the tip on the exact circular arc (the corotational element at large
    rotation; adaptive mesh: 1e-6 of L)."""
    dTg = DEPTH / (ALPHA * L)     # kappa_T L = -1
    r = femslide.solve(rod_structure("free", {"dT_gradient": dTg}))
    u, v, th = ref.cantilever_gradient_tip(ALPHA, dTg, DEPTH, L)
    end = r["rods"]["r"]["end"]
    assert abs(end["theta"] - th) <= TOL
    assert math.hypot(end["u"] - u, end["v"] - v) <= TOL * L, (end, u, v)
    assert r["rods"]["r"]["M_max"] <= 1e-6 * EI / L


@pytest.mark.parametrize("theory", ["nonlinear", "linear"])
def test_welded_gradient(theory):
    dTg = -12.0
    r = femslide.solve(rod_structure("weld", {"dT_gradient": dTg}, math.pi / 6), theory=theory)
    M = ref.welded_gradient_M(EI, ALPHA, dTg, DEPTH)
    a = r.rod("r")
    assert np.allclose(a["M"], M, rtol=TOL, atol=0), (a["M"], M)
    assert np.abs(a["u"]).max() <= 1e-12 and np.abs(a["theta"]).max() <= 1e-12
    assert r["rods"]["r"]["N_max"] <= 1e-9 * abs(M) / L
    assert abs(r["reactions"]["B"]["M"] - M) <= TOL * abs(M)
    assert abs(r["reactions"]["A"]["M"] + M) <= TOL * abs(M)


def test_case_factor_reverses():
    st = rod_structure("roller", {"dT": 30.0, "case": "summer"})
    st.combination("winter", {"summer": -1.0})
    r = femslide.solve(st)
    w = r.combination("winter")
    assert abs(w["joints"]["B"]["slide"] + ref.roller_slide(ALPHA, 30.0, L)) <= TOL * ALPHA * 30 * L


def test_dynamics_carry_the_thermal_state():
    """In time (simulate): a cantilever with a tip mass under a temperature gradient starts from its
    bent static state (tip rotation -alpha dT_gradient L / depth, 1e-9) and, shaken at its base, moves
    about it as the unheated cantilever moves about the straight one: the thermal curvature is free of
    stress, so the peak root moment and the peak tip slide agree with the unheated run's to the
    geometric effect of the 1.6 mrad pre-rotation (1e-3 relative), both with error estimates below
    1e-3."""
    dTg = 20.0

    def run(grad):
        s = Structure(gravity=(0.0, 0.0))
        s.rod("r", (0.0, 0.0), (L, 0.0), EI=EI, EA=EA, rhoA=5.0, alpha=ALPHA, depth=DEPTH, elements=8)
        s.weld("A", "r.start", "ground")
        s.body("m", mass=10.0, centroid=(L, 0.0), inertia=0.1)
        s.weld("tip", "r.end", "m")
        if grad:
            s.thermal("T", "r", dT_gradient=dTg)
        static = femslide.solve(s)
        dyn = femslide.simulate(s, t_end=0.5, tolerance=1e-6,
                                ground={"direction": [0.0, 1.0], "amplitude": 1.0, "frequency": 2.0})
        return static, dyn
    (_, d0), (s1, d1) = run(False), run(True)
    assert abs(s1["rods"]["r"]["end"]["theta"] + ALPHA * dTg * L / DEPTH) <= 1e-9
    assert d0["converged"] and d1["converged"] and max(d0["error_estimate"], d1["error_estimate"]) < 1e-3
    m0, m1 = d0["peaks"]["rods"]["r"]["M_max"], d1["peaks"]["rods"]["r"]["M_max"]
    assert abs(m1 - m0) <= 1e-3 * m0, (m0, m1)


@pytest.mark.parametrize("about", ["reference", "equilibrium"])
def test_thermal_buckling_of_a_restrained_rod(about):
    """A rod pinned at both ends (axially restrained) and heated by dT buckles when its thermal
    compression EA alpha dT reaches the Euler load pi^2 EI / L^2: the lowest load factor is
    pi^2 EI / (EA alpha L^2 dT) (1e-6, converging with the mesh), about the reference and about the
    heated equilibrium (whose thermal stresses are the geometric stiffness: before, they were left
    out of it and the factor came out as 1e16)."""
    dT = 10.0
    s = Structure(gravity=(0.0, 0.0))
    s.rod("c", (0.0, 0.0), (4.0, 0.0), EI=1e5, EA=1e9, alpha=ALPHA)
    s.pin("A", "c.start", "ground")
    s.pin("B", "c.end", "ground")
    s.thermal("T", "c", dT=dT)
    r = femslide.buckling(s, about=about)
    ref = math.pi ** 2 * 1e5 / (1e9 * ALPHA * 16.0 * dT)
    assert abs(r["load_factors"][0] - ref) <= TOL * ref, (r["load_factors"][0], ref)


def test_estimate_of_a_moment_free_rod_on_a_fixed_mesh():
    """A cantilever that takes its free thermal curvature has no moment but round-off: the fixed
    mesh's error_estimate (of M_max) is at that round-off, not the relative change of two round-off
    values (it read 2479 on 16 elements)."""
    r = femslide.solve(rod_structure("free", {"dT_gradient": 15.0}, n=16))
    assert r["rods"]["r"]["M_max"] <= 1e-9 * EI * ALPHA * 15.0 / DEPTH
    assert r["error_estimate"] <= 1e-9
