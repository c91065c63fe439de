"""Self-tests of the large-rotation elastica references ``validation/elastica_reference.py``.

* published large-deflection values (Bisshopp & Drucker 1945 / Mattiasson 1981, 4-5 digits) and the
  elliptic-integral closed form (to 1e-10) for the tip-loaded cantilever, up to P L^2 / EI = 100;
* the end-moment circle (exact), also extensible and inclined;
* the small-load limit against the independent linear frame solver ``frame_reference`` (relative
  difference O(load): checked to scale by 10 when the load does);
* exact extensible cases (straight rod under an axial tip force / axial distributed load);
* the sliding-clamp rod: the locked inextensible cases (statics), its linear limit (two springs in
  series along the guide), and the large-rotation solution checked against ``inclined_cantilever``
  (the same rod seen as a cantilever clamped at the top and loaded at its base by the pin force);
* global equilibrium of every solution.
Run:  pytest -q validation/test_elastica_reference.py
"""
from __future__ import annotations

import math
import pathlib
import sys

import numpy as np
import pytest

_HERE = pathlib.Path(__file__).resolve().parent
if str(_HERE) not in sys.path:
    sys.path.insert(0, str(_HERE))

import elastica_reference as er  # noqa: E402
import frame_reference as fr  # noqa: E402

TOL = 1e-10   # shooting vs closed forms (integration rtol 1e-12, Newton 1e-13)


def rot(a, v):
    c, s = math.cos(a), math.sin(a)
    return np.array([c * v[0] - s * v[1], s * v[0] + c * v[1]])


def check_cantilever_statics(r, F, M, q, L, EI):
    """Clamp reaction balances the loads; the integrated moment balance closes."""
    assert r["reaction"][0] == pytest.approx(-(F[0] + q[0] * L), abs=1e-14 * (abs(F[0]) + abs(q[0]) * L + 1))
    assert r["reaction"][1] == pytest.approx(-(F[1] + q[1] * L), abs=1e-14 * (abs(F[1]) + abs(q[1]) * L + 1))
    assert abs(r["equilibrium"]) <= 1e-11 * EI / L
    assert abs(r["root_angle_residual"]) <= 1e-9


# -- tip-loaded cantilever: published values and the elliptic closed form ---------------------------

def test_bisshopp_drucker_published():
    """P L^2 / EI = 1: v/L = 0.30172, u/L = -0.05643, tip rotation 0.46135 (Mattiasson 1981, table;
    Bisshopp & Drucker 1945)."""
    L, EI = 1.7, 2.3e3
    P = EI / L ** 2
    r = er.inclined_cantilever(L, EI, 0.0, 0.0, P)
    assert r["disp"][1] / L == pytest.approx(0.30172, abs=5e-6)
    assert r["disp"][0] / L == pytest.approx(-0.05643, abs=5e-6)
    assert r["rotation"] == pytest.approx(0.46135, abs=5e-6)
    assert r["M_max"] == pytest.approx(P * r["tip"][0], rel=1e-12)   # at the root: P x_tip
    assert r["s_M_max"] == 0.0
    check_cantilever_statics(r, (0.0, P), 0.0, (0.0, 0.0), L, EI)
    e = er.tip_load_elliptic(L, EI, P)
    assert e["disp"][1] / L == pytest.approx(0.30172, abs=5e-6)


@pytest.mark.parametrize("alpha", [0.3, 1.0, 3.0, 10.0, 100.0])
def test_tip_load_vs_elliptic(alpha):
    """Shooting against the Bisshopp-Drucker elliptic integrals, 1e-10 L and 1e-10 rad; the
    continuation stays on the principal branch (tip angle below pi/2) up to alpha = 100."""
    L, EI = 2.0, 7.0e3
    P = -alpha * EI / L ** 2          # downward
    r = er.inclined_cantilever(L, EI, 0.0, 0.0, P)
    e = er.tip_load_elliptic(L, EI, P)
    assert abs(r["tip"][0] - e["tip"][0]) <= TOL * L
    assert abs(r["tip"][1] - e["tip"][1]) <= TOL * L
    assert abs(r["rotation"] - e["rotation"]) <= TOL
    assert -math.pi / 2 < r["rotation"] < 0
    check_cantilever_statics(r, (0.0, P), 0.0, (0.0, 0.0), L, EI)


def test_rotation_invariance():
    """The same loaded cantilever turned by 2.1 rad: positions and forces turn, rotations and
    moments do not (1e-11)."""
    L, EI, a = 1.3, 900.0, 2.1
    F, M, q = np.array([150.0, -420.0]), 250.0, np.array([-80.0, 120.0])
    r0 = er.inclined_cantilever(L, EI, 0.0, *F, M=M, q=q)
    r1 = er.inclined_cantilever(L, EI, a, *rot(a, F), M=M, q=rot(a, q))
    np.testing.assert_allclose(r1["disp"], rot(a, r0["disp"]), atol=1e-11 * L)
    assert r1["rotation"] == pytest.approx(r0["rotation"], abs=1e-11)
    assert r1["reaction"][2] == pytest.approx(r0["reaction"][2], abs=1e-11 * EI / L)
    assert r1["M_max"] == pytest.approx(r0["M_max"], rel=1e-11)


# -- end moment: the circle ---------------------------------------------------------------------------

@pytest.mark.parametrize("m_ratio,angle,EA", [(1.0, 0.0, None), (1.0, 0.9, None), (0.5, -0.4, None),
                                              (1.0, 0.3, 5e5), (0.37, 0.0, None)])
def test_end_moment_circle(m_ratio, angle, EA):
    """Tip moment M = m_ratio 2 pi EI / L: circular arc (exact).  m_ratio = 1: the rod closes into a
    circle, tip back at the root, rotation 2 pi.  With EA: no axial force, no stretch."""
    L, EI = 1.5, 400.0
    M = m_ratio * 2 * math.pi * EI / L
    r = er.inclined_cantilever(L, EI, angle, 0.0, 0.0, M=M, EA=EA)
    c = er.end_moment_circle(L, EI, M, angle)
    np.testing.assert_allclose(r["tip"], c["tip"], rtol=0, atol=TOL * L)
    assert r["rotation"] == pytest.approx(c["rotation"], abs=TOL)
    assert r["M_max"] == pytest.approx(abs(M), rel=1e-12)
    assert r["reaction"][2] == pytest.approx(-M, rel=1e-12)
    if m_ratio == 1.0:
        assert math.hypot(*r["tip"]) <= TOL * L
        assert r["rotation"] == pytest.approx(2 * math.pi, abs=TOL)
    check_cantilever_statics(r, (0.0, 0.0), M, (0.0, 0.0), L, EI)


# -- small loads: the linear frame solver ---------------------------------------------------------------

def _linear_cantilever(L, EI, EA, angle, F, M, q):
    fm = fr.Frame().node("A", 0, 0).node("B", L * math.cos(angle), L * math.sin(angle))
    fm.beam("b", "A", "B", EI, EA).support("A", rz=True).load("B", F[0], F[1], M)
    fm.distributed("b", *q)
    return fm.solve()


@pytest.mark.parametrize("EA", [None, 2e6])
def test_small_load_limit_vs_linear(EA):
    """Inclined cantilever with tip force, tip moment and a distributed load, scaled by lf: the
    elastica tends to linear theory with a relative difference O(lf) (second-order effects: the
    load acting on the displaced rod).  Checked: difference < 0.1 lf (relative) and it shrinks
    tenfold (within 5 %) when lf does."""
    L, EI, angle = 2.0, 5.0e3, 0.7
    F0, M0, q0 = np.array([30.0, -80.0]), 40.0, np.array([5.0, -60.0])
    errs = []
    for lf in (1e-3, 1e-4):
        F, M, q = F0 * lf, M0 * lf, q0 * lf
        r = er.inclined_cantilever(L, EI, angle, *F, M=M, q=q, EA=EA)
        lin = _linear_cantilever(L, EI, 1e8 * EI / L ** 2 if EA is None else EA, angle, F, M, q)
        u, v, th = lin.disp("B")
        scale = math.hypot(u, v)
        e = max(math.hypot(r["disp"][0] - u, r["disp"][1] - v) / scale,
                abs(r["rotation"] - th) / abs(th),
                abs(r["reaction"][2] - lin.reaction("A")[2]) / abs(lin.reaction("A")[2]),
                abs(r["M_max"] - lin.moment_max("b")) / lin.moment_max("b"))
        errs.append(e)
        assert e < 0.1 * lf
        check_cantilever_statics(r, F, M, q, L, EI)
    assert 9.5 < errs[0] / errs[1] < 10.5


def test_interior_moment_extremum():
    """Self-weight w (down) and an upward tip force P = 0.6 w L: in linear theory
    M(x) = P x - w x^2 / 2 (x = L - s) has its extremum P^2 / (2w) = 0.18 w L^2 at x = P / w,
    larger than the root moment 0.1 w L^2.  Small loads: the event-located extremum agrees to
    O(load) in value and place."""
    L, EI, w = 3.0, 1.0e4, 2.0
    P = 0.6 * w * L
    r = er.inclined_cantilever(L, EI, 0.0, 0.0, P, q=(0.0, -w))
    assert r["M_max"] == pytest.approx(P ** 2 / (2 * w), rel=1e-3)
    assert r["s_M_max"] == pytest.approx(L - P / w, abs=1e-3 * L)
    assert -r["reaction"][2] == pytest.approx(P * L - w * L ** 2 / 2, rel=1e-2)
    check_cantilever_statics(r, (0.0, P), 0.0, (0.0, -w), L, EI)


# -- extensible exact cases ------------------------------------------------------------------------------

@pytest.mark.parametrize("angle", [0.0, 1.1])
def test_extensible_axial(angle):
    """Axial tip force F and axial distributed load q_t on an inclined rod: it stays straight,
    N(s) = F + q_t (L - s), tip displacement F L / EA + q_t L^2 / (2 EA) along the axis (exact)."""
    L, EI, EA, Fa, qa = 2.5, 1.0e3, 4.0e5, 2.0e4, -3.0e3
    t0 = np.array([math.cos(angle), math.sin(angle)])
    r = er.inclined_cantilever(L, EI, angle, *(Fa * t0), q=qa * t0, EA=EA)
    assert r["disp_axial"] == pytest.approx(Fa * L / EA + qa * L ** 2 / (2 * EA), rel=1e-11)
    assert abs(r["disp_transverse"]) <= 1e-14 * L
    assert abs(r["rotation"]) <= 1e-14


def test_inextensible_limit():
    """EA -> inf: the extensible solution tends to the inextensible one like 1 / EA."""
    L, EI = 1.0, 1.0
    F = (0.8, 2.5)
    r0 = er.inclined_cantilever(L, EI, 0.2, *F)
    d = []
    for EA in (1e6, 1e8):
        r = er.inclined_cantilever(L, EI, 0.2, *F, EA=EA)
        d.append(np.hypot(*(np.array(r["tip"]) - r0["tip"])))
    assert d[0] < 10 * math.hypot(*F) / 1e6
    assert 90 < d[0] / d[1] < 110


# -- the sliding-clamp rod -------------------------------------------------------------------------------

def test_slider_inextensible_locked():
    """Inextensible rod, guide tilted from the rod: below buckling the rod stays straight and the
    top does not slide; the clamp's transverse force makes n parallel to the rod with n . g = F . g,
    so the base pin force is -(F . g) / (t0 . g) t0 (statics)."""
    L, EI, a, g = 1.2, 800.0, 1.3, 1.9
    F = np.array([300.0, -900.0])
    r = er.pinned_slider_rod(L, EI, a, g, F)
    t0 = np.array([math.cos(a), math.sin(a)])
    gv = np.array([math.cos(g), math.sin(g)])
    assert abs(r["slide"]) <= 1e-13 * L
    assert abs(r["base_rotation"]) <= 1e-13
    np.testing.assert_allclose(r["base_reaction"], -(F @ gv) / (t0 @ gv) * t0, rtol=1e-12)
    assert abs(r["clamp_moment"]) <= 1e-12 * np.hypot(*F) * L
    with pytest.raises(ValueError):
        er.pinned_slider_rod(L, EI, math.pi / 2, 0.0, F)     # guide across the rod: locked


@pytest.mark.parametrize("a,g,EA,order", [(math.pi / 2, math.pi / 2 + 0.3, 1e6, 1), (1.2, 2.0, 1e4, 1),
                                          (1.2, 2.0, 1e6, 1), (math.pi / 2, 0.0, 1e4, 2)])
def test_slider_linear_limit(a, g, EA, order):
    """Small loads: two springs in series along the guide (module docstring):
    slide = (F . g) / (EA/L cos^2 b + 3EI/L^3 sin^2 b); base rotation V L^2 / 2EI and clamp moment
    -V L with V = n . n0 the shear.  Relative difference O(load^order), shrinking 10^order-fold
    with it.  (a, g) = (pi/2, 0): guide across the rod, the slide is bending only while it stays
    well below sqrt(EI / EA) L; the correction (string stiffening) is even in the load: order 2."""
    L, EI = 1.0, 1.0
    t0 = np.array([math.cos(a), math.sin(a)])
    n0 = np.array([-t0[1], t0[0]])
    gv = np.array([math.cos(g), math.sin(g)])
    b = g - a
    k = EA / L * math.cos(b) ** 2 + 3 * EI / L ** 3 * math.sin(b) ** 2
    errs = []
    lfs = (1e-5, 1e-6) if abs(math.cos(b)) < 1e-12 else (1e-3, 1e-4)
    for lf in lfs:
        F = np.array([3.0, -5.0]) * lf
        r = er.pinned_slider_rod(L, EI, a, g, F, EA=EA)
        slide = F @ gv / k
        n = -np.array(r["base_reaction"])
        V = n @ n0
        e = max(abs(r["slide"] - slide) / abs(slide),
                abs(r["base_rotation"] - V * L ** 2 / (2 * EI)) / abs(V * L ** 2 / (2 * EI)),
                abs(r["clamp_moment"] + V * L) / abs(V * L))
        errs.append(e)
        assert abs(r["guide_offset"]) <= 1e-12 * L and abs(r["top_rotation"]) <= 1e-9
        # statics of the rod: pin + F + clamp force = 0; moments about the base
        np.testing.assert_allclose(np.array(r["base_reaction"]) + F + r["clamp_force"], 0.0,
                                   atol=1e-14 * np.hypot(*F))
        tip = np.array(r["tip"])
        Ft = F + r["clamp_force"]
        assert abs(tip[0] * Ft[1] - tip[1] * Ft[0] + r["clamp_moment"]) <= 1e-12 * np.hypot(*F) * L
    assert errs[0] < 0.2
    assert 0.9 * 10 ** order < errs[0] / errs[1] < 1.1 * 10 ** order


@pytest.mark.parametrize("a,g,F,EA,guess", [
    (math.pi / 2, math.pi / 2 + 0.3, (3.0, 2.0), 1e2, False),     # rod in tension
    (1.2, 2.0, (2.0, 3.0), 50.0, False),
    (math.pi / 2, 0.0, (3.0, -2.0), 1e2, False),                  # guide across the rod
    (math.pi / 2, math.pi / 2 + 0.3, (3.0, -2.0), 1e2, True),     # compression above pi^2/4
])
def test_slider_large_rotation_vs_cantilever(a, g, F, EA, guess):
    """Large rotations (EA / (EI/L^2) = 50-100, slides ~0.03-0.3 L): the slider's rod is the
    cantilever clamped at its top (angle + pi) and loaded at its free end (the base) by the pin
    force; ``inclined_cantilever`` with that load must bring the free end to the origin and give
    the same clamp moment, rotation and M_max (a different shooting formulation: 1e-9).  When that
    pin force compresses the cantilever above its buckling load pi^2 EI / 4L^2 the slider's state is
    not the cantilever's principal branch: it is reached from ``rotation_guess``."""
    L, EI = 1.0, 1.0
    r = er.pinned_slider_rod(L, EI, a, g, F, EA=EA)
    assert abs(r["slide"]) > 0.01 * L
    tip = np.array(r["tip"])
    c = er.inclined_cantilever(L, EI, a + math.pi, *r["base_reaction"], EA=EA,
                               rotation_guess=r["base_rotation"] if guess else None)
    if guess:
        assert -r["axial_force_base"] > math.pi ** 2 / 4 * EI / L ** 2
    np.testing.assert_allclose(tip + np.array(c["tip"]), 0.0, atol=1e-9 * L)
    assert c["reaction"][2] == pytest.approx(r["clamp_moment"], abs=1e-9 * EI / L)
    assert c["rotation"] == pytest.approx(r["base_rotation"], abs=1e-9)
    assert c["M_max"] == pytest.approx(r["M_max"], abs=1e-9 * EI / L)
    assert r["M_max"] >= abs(r["clamp_moment"]) - 1e-15
    gv = np.array([math.cos(g), math.sin(g)])
    assert (-np.array(r["base_reaction"])) @ gv == pytest.approx(np.array(F) @ gv, rel=1e-12)
