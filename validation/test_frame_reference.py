"""Self-tests of the independent linear frame solver ``validation/frame_reference.py``.

Every case is compared with a textbook closed form (cited in each test) or with a unit-load integral
evaluated by scipy.integrate.quad, at 1e-10 relative; every case also checks global equilibrium of
the reactions against the applied loads (computed here from the inputs, not by the module).  Run:
    pytest -q validation/test_frame_reference.py
"""
from __future__ import annotations

import math
import pathlib
import sys

import numpy as np
import pytest
from scipy.integrate import quad

_HERE = pathlib.Path(__file__).resolve().parent
if str(_HERE) not in sys.path:
    sys.path.insert(0, str(_HERE))

import frame_reference as fr  # noqa: E402

RTOL = 1e-10


def close(a, b, scale=None, rtol=RTOL):
    scale = abs(b) if scale is None else scale
    assert abs(a - b) <= rtol * scale, (a, b, abs(a - b) / scale)


def check_equilibrium(frame, res, point_loads=(), dist=(), scale=1.0):
    """Sum of reactions + point loads [(x, y, Fx, Fy, M)] + member loads [(x1, y1, x2, y2, qx, qy)]."""
    Fx = Fy = Mz = 0.0
    items = [(*frame.nodes[n], *res.reaction(n)) for n in frame.supports] + list(point_loads)
    for (x1, y1, x2, y2, qx, qy) in dist:
        Lm = math.hypot(x2 - x1, y2 - y1)
        items.append((0.5 * (x1 + x2), 0.5 * (y1 + y2), qx * Lm, qy * Lm, 0.0))
    for (x, y, fx, fy, m) in items:
        Fx += fx
        Fy += fy
        Mz += m + x * fy - y * fx
    for r in (Fx, Fy, Mz):
        assert abs(r) <= RTOL * scale, (Fx, Fy, Mz)


def rot(a, v):
    c, s = math.cos(a), math.sin(a)
    return np.array([c * v[0] - s * v[1], s * v[0] + c * v[1]])


# -- cantilevers ------------------------------------------------------------------------------------

@pytest.mark.parametrize("angle", [0.0, math.radians(30), math.pi / 2, math.radians(200)])
@pytest.mark.parametrize("n_sub", [1, 4])
def test_cantilever_tip_load(angle, n_sub):
    """Tip force P transverse and axial force F (Gere & Timoshenko, Mechanics of Materials, table of
    cantilever deflections): v = P L^3 / 3EI, theta = P L^2 / 2EI, root moment P L, u = F L / EA."""
    L, EI, EA, P, F = 2.5, 3.0e4, 7.0e8, 120.0, -3.0e3
    tip = rot(angle, (L, 0.0))
    fm = fr.Frame().node("A", 0, 0).node("B", *tip)
    fm.beam("b", "A", "B", EI, EA, n_sub=n_sub).support("A", rz=True)
    load = rot(angle, (F, P))
    fm.load("B", *load)
    r = fm.solve()
    u, v, th = r.disp("B")
    d_loc = rot(-angle, (u, v))
    close(d_loc[1], P * L ** 3 / (3 * EI))
    close(d_loc[0], F * L / EA)
    close(th, P * L ** 2 / (2 * EI))
    N, V, M = r.member_forces("b", 0.0)
    close(M, P * L)               # M = EI theta' > 0: the rod turns counter-clockwise
    close(N, F)
    close(V, P)
    close(r.moment_max("b"), P * L)
    close(r.reaction("A")[2], -P * L)
    check_equilibrium(fm, r, [(*tip, *load, 0.0)], scale=P * L)
    # interior displacement: v(s) = P s^2 (3L - s) / 6EI
    s = 0.37 * L
    us = rot(-angle, r.member_disp("b", s)[:2])
    close(us[1], P * s ** 2 * (3 * L - s) / (6 * EI))


@pytest.mark.parametrize("n_sub", [1, 3])
def test_cantilever_uniform_load(n_sub):
    """Uniform q (Gere & Timoshenko): tip v = q L^4 / 8EI, tip rotation q L^3 / 6EI, root moment
    q L^2 / 2, M(s) = q (L - s)^2 / 2 (sign: hogging for a downward load)."""
    L, EI, EA, q = 3.0, 2.0e4, 1e9, -400.0
    fm = fr.Frame().node("A", 0, 0).node("B", L, 0)
    fm.beam("b", "A", "B", EI, EA, n_sub=n_sub).support("A", rz=True)
    fm.distributed("b", qy=q)
    r = fm.solve()
    _, v, th = r.disp("B")
    close(v, q * L ** 4 / (8 * EI))
    close(th, q * L ** 3 / (6 * EI))
    close(r.moment_max("b"), abs(q) * L ** 2 / 2)
    for s in (0.0, 0.4, 1.7, L):
        close(r.member_forces("b", s)[2], q * (L - s) ** 2 / 2, scale=abs(q) * L ** 2)
    close(r.reaction("A")[2], -q * L ** 2 / 2)
    check_equilibrium(fm, r, dist=[(0, 0, L, 0, 0.0, q)], scale=abs(q) * L ** 2)


@pytest.mark.parametrize("n_sub", [1, 2])
def test_simply_supported_uniform(n_sub):
    """Simply supported, uniform q: midspan deflection 5 q L^4 / 384 EI, M_max = q L^2 / 8 at L/2,
    reactions q L / 2, end rotations q L^3 / 24 EI (Gere & Timoshenko)."""
    L, EI, EA, q = 4.0, 5.0e4, 1e9, -300.0
    fm = fr.Frame().node("A", 0, 0).node("B", L, 0)
    fm.beam("b", "A", "B", EI, EA, n_sub=n_sub)
    fm.support("A").support_roller("B", (1.0, 0.0)).distributed("b", qy=q)
    r = fm.solve()
    close(r.member_disp("b", L / 2)[1], 5 * q * L ** 4 / (384 * EI))
    Mmax, at = r.moment_max("b", where=True)
    close(Mmax, abs(q) * L ** 2 / 8)
    close(at, L / 2)
    close(r.member_forces("b", L / 2)[2], -q * L ** 2 / 8)     # sagging: M > 0
    close(r.disp("A")[2], q * L ** 3 / (24 * EI))
    close(r.reaction("A")[1], -q * L / 2)
    close(r.reaction("B")[1], -q * L / 2)
    assert r.reaction("B")[0] == 0.0
    check_equilibrium(fm, r, dist=[(0, 0, L, 0, 0.0, q)], scale=abs(q) * L ** 2)


# -- tapered members --------------------------------------------------------------------------------

def _EI_lin(EI0, EI1, L):
    return lambda s: EI0 + (EI1 - EI0) * s / L


def _quad(f, L):
    return quad(f, 0.0, L, epsabs=0.0, epsrel=1e-13, limit=200)[0]


@pytest.mark.parametrize("ratio", [0.15, 0.7, 1.05, 3.0, 40.0])
def test_tapered_cantilever(ratio):
    """EI linear from EI0 at the clamp to ratio EI0 at the tip.  Unit-load theorem:
    tip load P: v = int P (L-s)^2 / EI, theta = int P (L-s) / EI; uniform q: v = int q (L-s)^3 / 2EI,
    theta = int q (L-s)^2 / 2EI (each by scipy quad).  Interior deflection by the same theorem."""
    L, EI0, EA, P, q = 2.0, 1.0e4, 1e9, 50.0, 80.0
    EI = _EI_lin(EI0, ratio * EI0, L)
    for n_sub in (1, 5):
        fm = fr.Frame().node("A", 0, 0).node("B", L, 0)
        fm.beam("b", "A", "B", EI0, EA, n_sub=n_sub, EI_end=ratio * EI0).support("A", rz=True)
        fm.load("B", Fy=P).distributed("b", qy=q)
        r = fm.solve()
        _, v, th = r.disp("B")
        v_ref = _quad(lambda s: (P * (L - s) + q * (L - s) ** 2 / 2) * (L - s) / EI(s), L)
        th_ref = _quad(lambda s: (P * (L - s) + q * (L - s) ** 2 / 2) / EI(s), L)
        close(v, v_ref)
        close(th, th_ref)
        a = 0.6 * L   # deflection at a: unit load at a, moment (a - s) for s < a
        va = _quad(lambda s, a=a: (P * (L - s) + q * (L - s) ** 2 / 2) * max(a - s, 0.0) / EI(s), a)
        close(r.member_disp("b", a)[1], va)
        close(r.member_disp("b", L)[1], v)      # interior formula closes on the node
        check_equilibrium(fm, r, [(L, 0, 0, P, 0)], [(0, 0, L, 0, 0, q)], scale=(P + q * L) * L)


@pytest.mark.parametrize("ratio", [0.25, 4.0])
def test_tapered_propped_cantilever_uniform(ratio):
    """Statically indeterminate: clamp at s = 0, roller at s = L, uniform q, EI linear.  Force method
    with the prop force X as redundant: X = -int q (L-s)^3 / (2 EI) / int (L-s)^2 / EI (quad).  Tests
    the exact fixed-end forces of a tapered element (one element, n_sub = 1)."""
    L, EI0, EA, q = 3.0, 2.0e4, 1e9, -150.0
    EI = _EI_lin(EI0, ratio * EI0, L)
    X = -_quad(lambda s: q * (L - s) ** 3 / 2 / EI(s), L) / _quad(lambda s: (L - s) ** 2 / EI(s), L)
    fm = fr.Frame().node("A", 0, 0).node("B", L, 0)
    fm.beam("b", "A", "B", EI0, EA, EI_end=ratio * EI0).support("A", rz=True)
    fm.support_roller("B", (1, 0)).distributed("b", qy=q)
    r = fm.solve()
    close(r.reaction("B")[1], X)
    close(r.reaction("A")[2], -(q * L ** 2 / 2 + X * L))
    # the parabola's interior extremum: shear zero at s* = L + X / q
    s_star = L + X / q
    Mmax = r.moment_max("b")
    M_star = X * (L - s_star) + q * (L - s_star) ** 2 / 2
    close(max(abs(M_star), abs(q * L ** 2 / 2 + X * L)), Mmax)
    check_equilibrium(fm, r, dist=[(0, 0, L, 0, 0, q)], scale=abs(q) * L ** 2)


def test_tapered_axial():
    """EA linear: tip displacement under an axial load F: int F / EA ds = F L ln(r) / (EA0 (r - 1));
    under a uniform axial load q_t: int q (L - s) / EA ds."""
    L, EA0, r_, F, qt = 1.5, 2.0e8, 0.3, 4.0e4, 1.0e4
    EA = _EI_lin(EA0, r_ * EA0, L)
    fm = fr.Frame().node("A", 0, 0).node("B", 0, L)
    fm.beam("b", "A", "B", 1e4, EA0, EA_end=r_ * EA0).support("A", rz=True)
    fm.load("B", Fy=F).distributed("b", qy=qt)
    res = fm.solve()
    close(res.disp("B")[1], F * L * math.log(r_) / (EA0 * (r_ - 1)) + _quad(lambda s: qt * (L - s) / EA(s), L))
    close(res.member_forces("b", 0.5)[0], F + qt * (L - 0.5))


# -- frames -----------------------------------------------------------------------------------------

@pytest.mark.parametrize("EA_b", [2.0e6, 1.0e10])
def test_portal_pinned_lateral(EA_b):
    """Pinned-base portal, welded corners, lateral H at the top of the left column:
    ``portal_pinned_lateral`` (force method, derivation in its docstring, beam axial strain
    included).  Classical limit (axially rigid beam, e.g. Kleinlogel's frame formulas / Hibbeler):
    A_x = D_x = -H/2, A_y = -D_y = -H h / L, corner moments H h / 2; the deviation from it is
    (L / EA_b) / d11 relative (2.6e-7 at EA_b = 1e10 here)."""
    H, h, L, EIc, EIb = 1.0e3, 3.0, 5.0, 2.0e4, 4.5e4
    fm = fr.Frame()
    for n, x, y in (("A", 0, 0), ("B", 0, h), ("C", L, h), ("D", L, 0)):
        fm.node(n, x, y)
    fm.beam("AB", "A", "B", EIc, 3e8).beam("BC", "B", "C", EIb, EA_b).beam("DC", "D", "C", EIc, 3e8)
    fm.support("A").support("D").load("B", Fx=H)
    r = fm.solve()
    ref = fr.portal_pinned_lateral(H, h, L, EIc, EIb, EA_b)
    close(r.reaction("A")[0], ref["Ax"], scale=H)
    close(r.reaction("D")[0], ref["Dx"], scale=H)
    close(r.reaction("A")[1], ref["Ay"])
    close(r.reaction("D")[1], ref["Dy"])
    close(r.member_forces("AB", h)[2], ref["MB"], scale=H * h)
    close(r.member_forces("DC", h)[2], ref["MC"], scale=H * h)
    close(r.moment_max("BC"), max(abs(ref["MB"]), abs(ref["MC"])), scale=H * h)
    close(ref["Dy"], H * h / L)
    lim = fr.portal_pinned_lateral(H, h, L, EIc, EIb, math.inf)
    assert lim["Ax"] == lim["Dx"] == -H / 2
    close(lim["MB"], H * h / 2)
    close(lim["MC"], H * h / 2)
    dev = (L / EA_b) / (2 * h ** 3 / (3 * EIc) + h ** 2 * L / EIb)
    assert abs(r.reaction("A")[0] + H / 2) <= 1.01 * dev * H / 2
    check_equilibrium(fm, r, [(0, h, H, 0, 0)], scale=H * h)


def test_three_hinged_portal():
    """Pin in the middle of the beam: statically determinate, A_x = D_x = -H/2 whatever the
    stiffnesses (moment of the right half about the crown pin), A_y = -D_y = -H h / L; the moment
    vanishes at the pin."""
    H, h, L = 800.0, 2.5, 6.0
    fm = fr.Frame()
    for n, x, y in (("A", 0, 0), ("B", 0, h), ("E", L / 2, h), ("C", L, h), ("D", L, 0)):
        fm.node(n, x, y)
    fm.beam("AB", "A", "B", 1e4, 1e8).beam("BE", "B", "E", 3e4, 2e8)
    fm.beam("EC", "E", "C", 7e3, 5e8).beam("DC", "D", "C", 2e4, 1e8)
    fm.pin("E").support("A").support("D").load("B", Fx=H)
    r = fm.solve()
    close(r.reaction("A")[0], -H / 2)
    close(r.reaction("D")[0], -H / 2)
    close(r.reaction("D")[1], H * h / L)
    assert abs(r.member_forces("BE", L / 2)[2]) <= RTOL * H * h
    assert math.isnan(r.disp("E")[2])
    check_equilibrium(fm, r, [(0, h, H, 0, 0)], scale=H * h)


@pytest.mark.parametrize("n_sub", [1, 3])
def test_pinned_cantilevers(n_sub):
    """Two cantilevers (clamped at x = 0 and x = L1 + L2) joined by a pin, force P at the pin: equal
    tip deflections share P as P1 / P2 = (EI1 / L1^3) / (EI2 / L2^3); each end rotation is the
    cantilever's P_i L_i^2 / 2EI_i (opposite signs)."""
    L1, L2, EI1, EI2, P = 2.0, 3.0, 1.0e4, 4.0e4, -900.0
    k1, k2 = 3 * EI1 / L1 ** 3, 3 * EI2 / L2 ** 3
    P1, P2 = P * k1 / (k1 + k2), P * k2 / (k1 + k2)
    fm = fr.Frame().node("A", 0, 0).node("E", L1, 0).node("C", L1 + L2, 0)
    fm.beam("l", "A", "E", EI1, 1e9, n_sub=n_sub).beam("r", "E", "C", EI2, 1e9, n_sub=n_sub)
    fm.hinge("l", "E").support("A", rz=True).support("C", rz=True).load("E", Fy=P)
    r = fm.solve()
    close(r.disp("E")[1], P1 * L1 ** 3 / (3 * EI1))
    close(r.reaction("A")[1], -P1)
    close(r.reaction("C")[1], -P2)
    close(r.end_rotation("l", "E"), P1 * L1 ** 2 / (2 * EI1))
    close(r.end_rotation("r", "E"), -P2 * L2 ** 2 / (2 * EI2))
    check_equilibrium(fm, r, [(L1, 0, 0, P, 0)], scale=abs(P) * (L1 + L2))


@pytest.mark.parametrize("deg", [0.0, 25.0, -60.0])
def test_inclined_roller(deg):
    """Pinned at A, roller at B rolling along d = (cos a, sin a): the reaction at B is normal to d;
    with a vertical load P at midspan, moments about A give its y component P/2, so
    R_B = (P/2) nrm / nrm_y and A takes the rest (statics)."""
    L, P = 4.0, -1.0e3
    a = math.radians(deg)
    nrm = np.array([-math.sin(a), math.cos(a)])
    fm = fr.Frame().node("A", 0, 0).node("M", L / 2, 0).node("B", L, 0)
    fm.beam("l", "A", "M", 2e4, 3e8).beam("r", "M", "B", 2e4, 3e8)
    fm.support("A").support_roller("B", (math.cos(a), math.sin(a))).load("M", Fy=P)
    r = fm.solve()
    RB = -P / 2 * nrm / nrm[1]
    close(r.reaction("B")[0], RB[0], scale=abs(P))
    close(r.reaction("B")[1], RB[1], scale=abs(P))
    uB = np.array(r.disp("B")[:2])
    assert abs(uB @ nrm) <= 1e-14 * np.hypot(*uB) + 1e-300
    check_equilibrium(fm, r, [(L / 2, 0, 0, P, 0)], scale=abs(P) * L)


def test_self_weight_inclined_and_consistency():
    """Self-weight on an inclined clamped member equals the same distributed load; the resultants
    obey dM/ds = -V and dN/ds = -q_t (finite differences of the exact parabola: exact to round-off);
    a sliding clamp (roller with rz) at the top: the top moves only along its guide."""
    L, ang, rhoA = 3.0, math.radians(50), 12.0
    tip = rot(ang, (L, 0))
    fm = fr.Frame().node("A", 0, 0).node("B", *tip)
    fm.beam("b", "A", "B", 1.5e4, 4e8, n_sub=3).support("A", rz=True).self_weight("b", rhoA)
    fm2 = fr.Frame().node("A", 0, 0).node("B", *tip)
    fm2.beam("b", "A", "B", 1.5e4, 4e8, n_sub=3).support("A", rz=True).distributed("b", 0.0, -9.81 * rhoA)
    r, r2 = fm.solve(), fm2.solve()
    assert r.disp("B") == r2.disp("B")
    qt = -9.81 * rhoA * math.sin(ang)
    for s in (0.3, 1.4, 2.2):
        h = 1e-3
        Np, _, Mp = r.member_forces("b", s + h)
        Nm, _, Mm = r.member_forces("b", s - h)
        V = r.member_forces("b", s)[1]
        close((Mp - Mm) / (2 * h), -V, scale=rhoA * 9.81 * L, rtol=1e-8)
        close((Np - Nm) / (2 * h), -qt, scale=rhoA * 9.81, rtol=1e-8)
    check_equilibrium(fm, r, dist=[(0, 0, *tip, 0, -9.81 * rhoA)], scale=rhoA * 9.81 * L * L)
    # sliding clamp at the top, guide at 20 deg
    g = (math.cos(0.35), math.sin(0.35))
    fm.support_roller("B", g, rz=True).load("B", 300.0, 100.0)
    r = fm.solve()
    u = np.array(r.disp("B")[:2])
    assert abs(u[0] * g[1] - u[1] * g[0]) <= 1e-14 * np.hypot(*u)
    assert r.disp("B")[2] == 0.0
    check_equilibrium(fm, r, [(*tip, 300.0, 100.0, 0)], [(0, 0, *tip, 0, -9.81 * rhoA)],
                      scale=rhoA * 9.81 * L * L + 300 * L)


def test_mechanism_and_bad_moment():
    fm = fr.Frame().node("A", 0, 0).node("B", 1, 0).beam("b", "A", "B", 1e4, 1e8).support("A")
    fm.load("B", Fy=1.0)
    with pytest.raises(np.linalg.LinAlgError):
        fm.solve()
    fm = fr.Frame().node("A", 0, 0).node("B", 1, 0).node("C", 2, 0)
    fm.beam("l", "A", "B", 1e4, 1e8).beam("r", "B", "C", 1e4, 1e8).pin("B")
    fm.support("A", rz=True).support("C", rz=True).load("B", Mz=5.0)
    with pytest.raises(ValueError):
        fm.solve()
