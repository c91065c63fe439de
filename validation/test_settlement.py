"""Prescribed support motion (SPEC section 10) against closed forms (validation/beam_formulas.py).

References and tolerances:

* a propped cantilever (clamped at x = 0, its prop a roller along x at x = L) whose prop settles by
  delta: prop force 3 EI delta / L^3, clamp moment 3 EI delta / L^2 (1e-9 in first-order theory;
  1e-5 in the exact theory with delta / L = 1e-4, where the rotation's second-order terms are
  ~(delta / L)^2), the prop's end moved by exactly delta;
* a rod welded at both ends whose first support turns by phi (first-order theory): end moments
  4 EI phi / L and 2 EI phi / L (1e-9);
* the motion is of load case "dead": a combination with dead = 0.5 halves it (1e-9, linear theory);
* a motion on a joint that is not with the ground, or a rotation on a pin, is bad input.
"""
from __future__ import annotations

import beam_formulas as bf
import pytest

import femslide
from femslide.errors import BadInput
from femslide.model.structure import Structure

L, EI = 4.0, 2e6


def propped(delta, dx=0.0):
    s = Structure(gravity=(0.0, 0.0))
    s.rod("p", (0.0, 0.0), (L, 0.0), EI=EI)
    s.weld("A", "p.start", "ground")
    s.joint("B", "roller", "p.end", "ground", axis=(1.0, 0.0), displacement=(dx, delta))
    return s


@pytest.mark.parametrize("theory,delta,tol", [("linear", -0.02, 1e-9), ("nonlinear", -4e-4, 1e-5)])
def test_settled_prop(theory, delta, tol):
    r = femslide.solve(propped(delta, dx=0.001), theory=theory)
    ref = bf.propped_settlement(L, EI, delta)
    # the clamp holds the rod end against the prop: the ground's moment on the rod's start is
    # -M(0) = -3 EI delta / L^2 (M = EI v'', v = delta (3 x^2 L - x^3) / (2 L^3))
    assert abs(r["reactions"]["A"]["M"] + ref["M_root"]) <= tol * abs(ref["M_root"])
    assert abs(r["reactions"]["B"]["Fy"] - ref["R_prop"]) <= tol * abs(ref["R_prop"])
    assert abs(r["rods"]["p"]["end"]["v"] - delta) <= 1e-12 * abs(delta)
    assert abs(r["rods"]["p"]["M_max"] - abs(ref["M_root"])) <= tol * abs(ref["M_root"])


def test_rotated_weld():
    phi = 0.003
    s = Structure(gravity=(0.0, 0.0))
    s.rod("p", (0.0, 0.0), (L, 0.0), EI=EI)
    s.weld("A", "p.start", "ground", rotation=phi)
    s.weld("B", "p.end", "ground")
    r = femslide.solve(s, theory="linear")
    assert abs(r["reactions"]["A"]["M"] - 4 * EI * phi / L) <= 1e-9 * 4 * EI * phi / L
    assert abs(r["reactions"]["B"]["M"] - 2 * EI * phi / L) <= 1e-9 * 4 * EI * phi / L
    assert abs(r["rods"]["p"]["start"]["theta"] - phi) <= 1e-12


def test_motion_is_case_dead():
    s = propped(-0.02)
    s.force("w", "p.end", force=(1.0, 0.0), case="wind")   # a second case to combine
    s.combination("full", {"dead": 1.0, "wind": 0.0})
    s.combination("half", {"dead": 0.5, "wind": 0.0})
    r = femslide.solve(s, theory="linear")
    full, half = r.combination("full")["reactions"]["B"]["Fy"], r.combination("half")["reactions"]["B"]["Fy"]
    assert abs(full - bf.propped_settlement(L, EI, -0.02)["R_prop"]) <= 1e-9 * abs(full)
    assert abs(half - 0.5 * full) <= 1e-9 * abs(full)


def test_bad_motion():
    s = Structure(gravity=(0.0, 0.0))
    s.rod("p", (0.0, 0.0), (L, 0.0), EI=EI)
    s.rod("q", (L, 0.0), (2 * L, 0.0), EI=EI)
    s.weld("A", "p.start", "ground")
    s.pin("B", "p.end", "q.start", displacement=(0.0, 0.01))
    s.pin("C", "q.end", "ground")
    with pytest.raises(BadInput, match="ground"):
        s.freeze()
    s.joints["B"] = s.joints["B"].__class__("B", "pin", "p.end", "q.start")
    s.joints["C"] = s.joints["C"].__class__("C", "pin", "q.end", "ground", rotation=0.1)
    with pytest.raises(BadInput, match="rotation"):
        s.freeze()
