"""Declared structures in the linear regime against closed forms and an independent linear frame solver.

The loads are small (rotations <= ~1e-7 rad), so that the geometric nonlinearity of femslide's
corotational model (relative effects of the order of the rotations) stays below 1e-7; the
references are linear theory.  EA is
finite in both femslide and the frame solver (validation/frame_reference.py: direct stiffness with
exact elements, independent of femslide).  Tolerance: 1e-6 relative (each quantity against the
largest of its kind in the case), on top of femslide's own error estimate (<= 1e-7).

* tapered cantilever, EI linear from EI0 to EI1, tip load P: tip deflection = int_0^L P (L-s)^2/EI(s) ds
  and tip rotation int_0^L P (L-s)/EI(s) ds (scipy quad), root moment P L; and the frame solver;
* cantilever under its own weight (rhoA g): tip deflection q L^4/(8 EI), tip rotation q L^3/(6 EI),
  root moment q L^2/2, root shear q L;
* simply supported beam (pin + roller) under a uniform load: midspan deflection 5 q L^4/(384 EI),
  end rotations q L^3/(24 EI), M_max = q L^2/8 at midspan, reactions q L/2;
* pinned-base portal frame with welded corners under a lateral load at the beam level and a uniform
  load on the beam: base reactions, corner moments, member M_max, sway: the frame solver;
* an inclined propped cantilever (clamped, the far end on a roller along an inclined axis) under a
  uniform load: reactions, end rotation: the frame solver.
"""
from __future__ import annotations

import math

import numpy as np
import pytest
from frame_reference import Frame
from scipy.integrate import quad

import femslide
from femslide.model.structure import Structure

TOL = 1e-6


def close(got, ref, scale):
    assert abs(got - ref) <= TOL * abs(scale), (got, ref, scale)


@pytest.mark.parametrize("EI0,EI1", [(2e6, 1e6), (1e6, 4e6)])
def test_tapered_cantilever(EI0, EI1):
    L, P = 2.5, 0.01
    EA = 1e12
    s = Structure(gravity=(0.0, 0.0))
    s.rod("c", (0.0, 0.0), (L, 0.0), EI={"s": [0.0, L], "value": [EI0, EI1]}, EA=EA)
    s.weld("root", "c.start", "ground")
    s.force("P", "c.end", force=(0.0, -P))
    r = femslide.solve(s)

    def EI(x):
        return EI0 + (EI1 - EI0) * x / L

    v_ref = -quad(lambda x: P * (L - x) ** 2 / EI(x), 0.0, L, epsabs=0, epsrel=1e-13)[0]
    th_ref = -quad(lambda x: P * (L - x) / EI(x), 0.0, L, epsabs=0, epsrel=1e-13)[0]
    tip = r["rods"]["c"]["end"]
    close(tip["v"], v_ref, v_ref)
    close(tip["theta"], th_ref, th_ref)
    close(r["rods"]["c"]["M_max"], P * L, P * L)
    close(r["reactions"]["root"]["M"], P * L, P * L)      # the ground holds the moment -(-P) L
    # the independent frame solver (exact element for linear EI)
    f = Frame().node(1, 0.0, 0.0).node(2, L, 0.0).beam("c", 1, 2, EI0, EA, EI_end=EI1)
    f.support(1, rz=True).load(2, Fy=-P)
    fr = f.solve()
    u, v, th = fr.disp(2)
    close(tip["v"], v, v)
    close(tip["theta"], th, th)


def test_self_weight_cantilever():
    L, EI, rhoA, g = 3.0, 5e6, 0.02, 9.81
    q = rhoA * g
    s = Structure(gravity=(0.0, -g))
    s.rod("c", (0.0, 0.0), (L, 0.0), EI=EI, EA=1e12, rhoA=rhoA)
    s.weld("root", "c.start", "ground")
    r = femslide.solve(s)
    tip = r["rods"]["c"]["end"]
    close(tip["v"], -q * L ** 4 / (8 * EI), q * L ** 4 / (8 * EI))
    close(tip["theta"], -q * L ** 3 / (6 * EI), q * L ** 3 / (6 * EI))
    close(r["rods"]["c"]["M_max"], q * L * L / 2, q * L * L / 2)
    close(r["rods"]["c"]["V_max"], q * L, q * L)
    R = r["reactions"]["root"]
    close(R["Fy"], q * L, q * L)
    close(R["M"], q * L * L / 2, q * L * L / 2)
    # along the rod: M(s) = -q (L - s)^2 / 2 (hogging), from the finest mesh's nodal values
    a = r.rod("c")
    M_ref = -q * (L - a["s"]) ** 2 / 2
    assert np.abs(a["M"] - M_ref).max() <= TOL * q * L * L / 2 + 1e-7 * q * L * L


@pytest.mark.parametrize("angle", [0.0, 0.6])
def test_simply_supported_uniform_load(angle):
    """A beam along ``angle``, pinned at its start, on a roller along its axis at its end, under a
    uniform load perpendicular to it."""
    L, EI, q0 = 4.0, 3e6, 0.5
    c, sn = math.cos(angle), math.sin(angle)
    t, n = (c, sn), (-sn, c)
    s = Structure(gravity=(0.0, 0.0))
    s.rod("b", (0.0, 0.0), (L * c, L * sn), EI=EI, EA=1e12)
    s.pin("left", "b.start", "ground")
    s.roller("right", "b.end", "ground", axis=t)
    s.distributed("q", "b", force=(-q0 * n[0], -q0 * n[1]))
    r = femslide.solve(s)
    rod = r["rods"]["b"]
    close(rod["M_max"], q0 * L * L / 8, q0 * L * L / 8)
    close(rod["start"]["theta"], -q0 * L ** 3 / (24 * EI), q0 * L ** 3 / (24 * EI))
    close(rod["end"]["theta"], q0 * L ** 3 / (24 * EI), q0 * L ** 3 / (24 * EI))
    for j in ("left", "right"):
        R = r["reactions"][j]
        close(R["Fx"] * n[0] + R["Fy"] * n[1], q0 * L / 2, q0 * L / 2)
    a = r.rod("b")
    mid = int(np.argmin(np.abs(a["s"] - L / 2)))
    assert a["s"][mid] == pytest.approx(L / 2)
    w_mid = a["u"][mid] * n[0] + a["v"][mid] * n[1]
    close(w_mid, -5 * q0 * L ** 4 / (384 * EI), 5 * q0 * L ** 4 / (384 * EI))
    close(a["M"][mid], q0 * L * L / 8, q0 * L * L / 8)


def _portal(H, qb, EIc, EIb, EA, h, L):
    s = Structure(gravity=(0.0, 0.0))
    s.rod("left", (0.0, 0.0), (0.0, h), EI=EIc, EA=EA)
    s.rod("right", (L, 0.0), (L, h), EI=EIc, EA=EA)
    s.rod("beam", (0.0, h), (L, h), EI=EIb, EA=EA)
    s.pin("A", "left.start", "ground")
    s.pin("D", "right.start", "ground")
    s.weld("B", "left.end", "beam.start")
    s.weld("C", "right.end", "beam.end")
    s.force("H", "left.end", force=(H, 0.0))
    s.distributed("q", "beam", force=(0.0, -qb))
    f = Frame().node("A", 0, 0).node("B", 0, h).node("C", L, h).node("D", L, 0)
    f.beam("left", "A", "B", EIc, EA).beam("beam", "B", "C", EIb, EA).beam("right", "D", "C", EIc, EA)
    f.support("A").support("D").load("B", Fx=H).distributed("beam", qy=-qb)
    return s, f.solve()


@pytest.mark.parametrize("H,qb", [(0.01, 0.0), (0.0, 0.008), (0.006, 0.004)])
def test_portal_frame(H, qb):
    h, L, EIc, EIb, EA = 3.0, 5.0, 4e6, 8e6, 1e11
    s, fr = _portal(H, qb, EIc, EIb, EA, h, L)
    r = femslide.solve(s)
    Fs = max(H, qb * L)
    for j in ("A", "D"):
        Fx, Fy, _ = fr.reaction(j)
        close(r["reactions"][j]["Fx"], Fx, Fs)
        close(r["reactions"][j]["Fy"], Fy, Fs)
    Ms = max(abs(fr.moment_max(m)) for m in ("left", "right", "beam"))
    for m in ("left", "right", "beam"):
        close(r["rods"][m]["M_max"], fr.moment_max(m), Ms)
    # displacements against the largest of the frame (the beam's midspan or the sway)
    mid = fr.member_disp("beam", L / 2)
    Us = max(abs(x) for x in (*fr.disp("B")[:2], *fr.disp("C")[:2], *mid[:2]))
    Ts = max(abs(fr.disp("B")[2]), abs(fr.disp("C")[2]))
    for rod, node in (("left", "B"), ("right", "C")):
        u, v, th = fr.disp(node)
        close(r["rods"][rod]["end"]["u"], u, Us)
        close(r["rods"][rod]["end"]["v"], v, Us)
        close(r["rods"][rod]["end"]["theta"], th, Ts)
    a = r.rod("beam")
    k = int(np.argmin(np.abs(a["s"] - L / 2)))
    close(a["v"][k], mid[1], Us)


def test_inclined_propped_cantilever():
    """Clamped at the origin, the far end on a roller along (1, 1)/sqrt(2), under self-weight-like
    load: the roller's reaction normal to its axis, the clamp's reactions, the end rotation."""
    L, EI, EA, q = 3.0, 2e6, 1e10, 0.003
    ang = math.radians(25.0)
    end = (L * math.cos(ang), L * math.sin(ang))
    d = (1 / math.sqrt(2), 1 / math.sqrt(2))
    s = Structure(gravity=(0.0, 0.0))
    s.rod("b", (0.0, 0.0), end, EI=EI, EA=EA)
    s.weld("clamp", "b.start", "ground")
    s.roller("prop", "b.end", "ground", axis=d)
    s.distributed("q", "b", force=(0.0, -q))
    r = femslide.solve(s)
    f = Frame().node(1, 0, 0).node(2, *end).beam("b", 1, 2, EI, EA).support(1, rz=True)
    f.support_roller(2, d).distributed("b", qy=-q)
    fr = f.solve()
    Fs = q * L
    for j, node in (("clamp", 1), ("prop", 2)):
        Fx, Fy, M = fr.reaction(node)
        close(r["reactions"][j]["Fx"], Fx, Fs)
        close(r["reactions"][j]["Fy"], Fy, Fs)
        close(r["reactions"][j]["M"], M, Fs * L)
    close(r["rods"]["b"]["end"]["theta"], fr.disp(2)[2], fr.disp(2)[2])
    close(r["rods"]["b"]["M_max"], fr.moment_max("b"), fr.moment_max("b"))
