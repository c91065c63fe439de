"""Large rotations of declared structures against independent elastica shooting (issue 11).

Reference: validation/elastica_reference.py (scipy solve_ivp DOP853 at rtol 1e-12 and Newton on
the shooting unknowns, continued in load from zero; it does not import femslide), with the rods'
axial stiffness EA passed to it, so that both solve the same extensible elastica.  Tolerance:
1e-6 relative to the largest value of a kind (displacements by the rod length, rotations by 1 rad,
forces by the load, moments by the load times the length), on top of femslide's own estimate.

* an inclined cantilever (along 0.7 rad) under an inclined dead tip force and a tip moment,
  P L^2/EI = 4, rotations ~1.3 rad;
* a heavy inclined cantilever under its own weight, q L^3/EI = 6;
* a rod pinned to the ground with its top in a sliding clamp on an inclined ground guide (a slider
  with b = "ground": top on the guide line, top rotation locked), pushed along and across the guide.
"""
from __future__ import annotations

import math

import pytest

import femslide
from femslide.model.structure import Structure

elastica = pytest.importorskip("elastica_reference")

TOL = 1e-6


def test_the_reference_on_known_solutions():
    """The oracle itself: the tip-loaded cantilever at P L^2/EI = 1 against the elliptic-integral
    solution (Bisshopp-Drucker; v/L = 0.30172, u/L = -0.05643, rotation 0.4611 rad, Mattiasson
    1981) and the end-moment circle (exact), 1e-9."""
    r = elastica.inclined_cantilever(1.0, 1.0, 0.0, 0.0, 1.0)
    e = elastica.tip_load_elliptic(1.0, 1.0, 1.0)
    assert r["disp"][0] == pytest.approx(e["disp"][0], rel=1e-9)
    assert r["disp"][1] == pytest.approx(e["disp"][1], rel=1e-9)
    assert r["rotation"] == pytest.approx(e["rotation"], rel=1e-9)
    assert (round(e["disp"][1], 5), round(e["disp"][0], 5), round(e["rotation"], 4)) == (0.30172, -0.05643, 0.4614)
    c = elastica.inclined_cantilever(1.0, 1.0, 0.0, 0.0, 0.0, M=2 * math.pi)
    assert abs(c["disp"][0] + 1.0) < 1e-9 and abs(c["disp"][1]) < 1e-9
    assert c["rotation"] == pytest.approx(2 * math.pi, rel=1e-12)


def close(got, ref, scale, what=""):
    assert abs(got - ref) <= TOL * abs(scale), (what, got, ref, scale)


@pytest.mark.parametrize("load", [(1.5, -3.5, 1.0), (-2.0, 1.0, -2.5)])
def test_inclined_cantilever_tip_force_and_moment(load):
    L, EI, EA, ang = 2.0, 3.0e4, 3.0e9, 0.7
    fx, fy, m = load
    F = EI / L ** 2
    Fx, Fy, M = fx * F, fy * F, m * F * L
    s = Structure(gravity=(0.0, 0.0))
    s.rod("c", (0.0, 0.0), (L * math.cos(ang), L * math.sin(ang)), EI=EI, EA=EA)
    s.weld("root", "c.start", "ground")
    s.force("tip", "c.end", force=(Fx, Fy), moment=M)
    r = femslide.solve(s)
    ref = elastica.inclined_cantilever(L, EI, ang, Fx, Fy, M=M, EA=EA)
    tip = r["rods"]["c"]["end"]
    close(tip["u"], ref["disp"][0], L, "u")
    close(tip["v"], ref["disp"][1], L, "v")
    close(tip["theta"], ref["rotation"], 1.0, "theta")
    P = math.hypot(Fx, Fy) + abs(M) / L
    R = r["reactions"]["root"]
    close(R["Fx"], ref["reaction"][0], P, "Fx")
    close(R["Fy"], ref["reaction"][1], P, "Fy")
    close(R["M"], ref["reaction"][2], P * L, "M")
    close(r["rods"]["c"]["M_max"], ref["M_max"], P * L, "M_max")


def test_heavy_inclined_cantilever():
    L, EI, EA, ang, g = 1.5, 2.0e3, 2.0e9, -0.4, 9.81
    rhoA = 6.0 * EI / L ** 3 / g
    s = Structure(gravity=(0.0, -g))
    s.rod("c", (0.0, 0.0), (L * math.cos(ang), L * math.sin(ang)), EI=EI, EA=EA, rhoA=rhoA)
    s.weld("root", "c.start", "ground")
    r = femslide.solve(s)
    ref = elastica.inclined_cantilever(L, EI, ang, 0.0, 0.0, q=(0.0, -rhoA * g), EA=EA)
    tip = r["rods"]["c"]["end"]
    close(tip["u"], ref["disp"][0], L, "u")
    close(tip["v"], ref["disp"][1], L, "v")
    close(tip["theta"], ref["rotation"], 1.0, "theta")
    W = rhoA * g * L
    close(r["reactions"]["root"]["M"], ref["reaction"][2], W * L, "M")
    close(r["rods"]["c"]["M_max"], ref["M_max"], W * L, "M_max")


@pytest.mark.parametrize("guide,force", [(1.2, (-1.5, -0.8)), (2.2, (0.9, -2.0))])
def test_pinned_rod_in_an_inclined_ground_slider(guide, force):
    L, EI, EA, ang = 1.0, 1.0e3, 1.0e7, math.pi / 2
    F = (force[0] * EI / L ** 2, force[1] * EI / L ** 2)
    g = (math.cos(guide), math.sin(guide))
    s = Structure(gravity=(0.0, 0.0))
    s.rod("r", (0.0, 0.0), (0.0, L), EI=EI, EA=EA)
    s.pin("base", "r.start", "ground")
    s.slider("guide", "r.end", "ground", axis=g)
    s.force("push", "r.end", force=F)
    res = femslide.solve(s)
    ref = elastica.pinned_slider_rod(L, EI, ang, guide, F, EA=EA)
    P = math.hypot(*F)
    close(res["joints"]["guide"]["slide"], ref["slide"], L, "slide")
    close(res["rods"]["r"]["end"]["theta"], 0.0, 1.0, "top rotation")
    close(res["rods"]["r"]["start"]["theta"], ref["base_rotation"], 1.0, "base rotation")
    close(res["reactions"]["base"]["Fx"], ref["base_reaction"][0], P, "base Fx")
    close(res["reactions"]["base"]["Fy"], ref["base_reaction"][1], P, "base Fy")
    close(res["reactions"]["guide"]["M"], ref["clamp_moment"], P * L, "clamp M")
    close(res["rods"]["r"]["M_max"], ref["M_max"], P * L, "M_max")
