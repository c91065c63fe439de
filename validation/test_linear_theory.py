"""First-order theory, elastic supports and sections, against an independent linear frame solver and
closed forms; load combinations against separate solves with the loads scaled by hand.

References and tolerances:

* ``theory = "linear"`` on portal frames (pinned or clamped bases, a lateral load, a uniform load on
  the beam, self-weight, an inclined member) with realistic loads - sways of centimetres, where the
  exact theory differs by 1e-3 - against validation/frame_reference.py (direct stiffness with exact
  elements, independent of femslide): reactions, member moments (M_max with the interior extremum),
  end displacements and rotations, to 1e-9 relative to the largest of each kind;
* a cantilever on a rotational spring kr at its clamp under a tip load P (linear theory): tip
  deflection P L^3/(3 EI) + P L^2 / kr, tip rotation P L^2/(2 EI) + P L / kr, root moment P L, to
  1e-9; with springs kx, ky at the support under a tip force (H, -P): u = H/kx + H L/EA,
  v = -(P/ky + P L^3/(3 EI) + P L^2/kr) (1e-9); a simply supported beam whose roller is an elastic
  spring ky: the midspan deflection 5 q L^4/(384 EI) + q L/(4 ky) (superposition of the beam's and
  the rigid rotation about the pin, 1e-9);
* a rod given by E, I, A gives the results of the rod given by EI = E I, EA = E A exactly;
* load combinations on a linear frame equal separate solves of the structure with each case's loads
  (and gravity, case "dead") scaled by hand, to 1e-9; the envelope equals the max/min over the
  combinations exactly; in exact theory on a fixed mesh (same discrete equations) to 1e-9 too;
* linearity: doubling every load doubles every result of first-order theory (1e-12).
"""
from __future__ import annotations

import math

import numpy as np
import pytest
from frame_reference import Frame

import femslide
from femslide.model.structure import Structure

TOL = 1e-9


def close(got, ref, scale, tol=TOL):
    assert abs(got - ref) <= tol * abs(scale), (got, ref, scale, abs(got - ref) / abs(scale))


def _portal(H, qb, base, rhoA=0.0, lean=0.0):
    h, L, EIc, EIb, EA = 4.0, 6.0, 4.8e6, 1.2e7, 1.1e9
    g = (0.0, -9.81)
    s = Structure(gravity=g)
    top_left = (lean, h)
    s.rod("left", (0.0, 0.0), top_left, EI=EIc, EA=EA, rhoA=rhoA)
    s.rod("right", (L, 0.0), (L, h), EI=EIc, EA=EA, rhoA=rhoA)
    s.rod("beam", top_left, (L, h), EI=EIb, EA=EA, rhoA=rhoA)
    sup = s.weld if base == "clamped" else s.pin
    sup("A", "left.start", "ground")
    sup("D", "right.start", "ground")
    s.weld("B", "left.end", "beam.start")
    s.weld("C", "right.end", "beam.end")
    s.force("H", "left.end", force=(H, 0.0))
    s.distributed("q", "beam", force=(0.0, -qb))
    f = Frame().node("A", 0, 0).node("B", *top_left).node("C", L, h).node("D", L, 0)
    f.beam("left", "A", "B", EIc, EA).beam("beam", "B", "C", EIb, EA).beam("right", "D", "C", EIc, EA)
    rz = base == "clamped"
    f.support("A", rz=rz).support("D", rz=rz).load("B", Fx=H).distributed("beam", qy=-qb)
    for m in ("left", "right", "beam"):
        if rhoA:
            f.self_weight(m, rhoA, g)
    return s, f.solve()


@pytest.mark.parametrize("H,qb,base,rhoA,lean", [(60e3, 0.0, "pinned", 0.0, 0.0),
                                                  (0.0, 25e3, "pinned", 0.0, 0.0),
                                                  (40e3, 20e3, "clamped", 80.0, 0.0),
                                                  (30e3, 15e3, "pinned", 0.0, 0.8)])
def test_portal_frame_linear_theory(H, qb, base, rhoA, lean):
    """theory = "linear" equals the direct-stiffness solution (1e-9) at loads where the exact
    theory's results differ by ~1e-3 (checked: the sway is centimetres)."""
    s, fr = _portal(H, qb, base, rhoA, lean)
    r = femslide.solve(s, theory="linear")
    assert r["theory"] == "linear"
    Fs = max(abs(H), abs(qb) * 6.0, 1.0)
    Ms = max(fr.moment_max(m) for m in ("left", "right", "beam"))
    for j in ("A", "D"):
        Fx, Fy, M = fr.reaction(j)
        close(r["reactions"][j]["Fx"], Fx, Fs)
        close(r["reactions"][j]["Fy"], Fy, Fs)
        close(r["reactions"][j]["M"], M, Ms)
    for m in ("left", "right", "beam"):
        close(r["rods"][m]["M_max"], fr.moment_max(m), Ms)
    Us = max(abs(x) for node in ("B", "C") for x in fr.disp(node)[:2])
    Ts = max(abs(fr.disp(node)[2]) for node in ("B", "C"))
    for rod, node in (("left", "B"), ("right", "C")):
        u, v, th = fr.disp(node)
        close(r["rods"][rod]["end"]["u"], u, Us)
        close(r["rods"][rod]["end"]["v"], v, Us)
        close(r["rods"][rod]["end"]["theta"], th, Ts)
    assert Us > 1e-4   # realistic loads: the exact theory differs by about Us / h
    exact = femslide.solve(s)
    assert abs(exact["rods"]["beam"]["M_max"] - r["rods"]["beam"]["M_max"]) > 1e-6 * Ms


def test_linear_results_are_linear_in_the_loads():
    """Doubling every load (gravity too) doubles every result of first-order theory (1e-12)."""
    s1, _ = _portal(40e3, 20e3, "clamped", 80.0)
    s2, _ = _portal(80e3, 40e3, "clamped", 80.0)
    s2.gravity = (0.0, -2 * 9.81)
    a = femslide.solve(s1, theory="linear").flat()
    b = femslide.solve(s2, theory="linear").flat()
    for k, v in a.items():
        if ".s_" in k:   # the positions of the maxima do not change
            assert b[k] == pytest.approx(v, rel=1e-6, abs=1e-9), k
        elif k.startswith(("rods.", "reactions.", "M_max")) and isinstance(v, float):
            assert b[k] == pytest.approx(2 * v, rel=1e-12, abs=1e-12 * abs(a["M_max"])), k


def _cantilever(L=2.5, EI=3e5, EA=4e9, **springs):
    s = Structure(gravity=(0.0, 0.0))
    s.rod("c", (0.0, 0.0), (L, 0.0), EI=EI, EA=EA)
    s.weld("root", "c.start", "ground", **springs)
    return s


def test_cantilever_on_a_rotational_spring():
    """Tip deflection P L^3/(3 EI) + P L^2/kr and rotation P L^2/(2 EI) + P L/kr (1e-9)."""
    L, EI, P, kr = 2.5, 3e5, 4e3, 2e6
    s = _cantilever(L, EI, kr=kr)
    s.force("P", "c.end", force=(0.0, -P))
    r = femslide.solve(s, theory="linear")
    v = -(P * L**3 / (3 * EI) + P * L**2 / kr)
    th = -(P * L**2 / (2 * EI) + P * L / kr)
    close(r["rods"]["c"]["end"]["v"], v, v)
    close(r["rods"]["c"]["end"]["theta"], th, th)
    close(r["rods"]["c"]["start"]["theta"], -P * L / kr, th)
    close(r["reactions"]["root"]["M"], P * L, P * L)
    close(r["reactions"]["root"]["Fy"], P, P)
    close(r["rods"]["c"]["M_max"], P * L, P * L)


def test_cantilever_on_three_springs():
    """Springs kx, ky, kr at the support under a tip force (H, -P): u = H/kx + H L/EA,
    v = -(P/ky + P L^3/(3 EI) + P L^2/kr) (1e-9); the reactions are the springs' forces."""
    L, EI, EA, P, H = 2.5, 3e5, 4e9, 4e3, 1.5e3
    kx, ky, kr = 7e6, 5e6, 2e6
    s = _cantilever(L, EI, EA, kx=kx, ky=ky, kr=kr)
    s.force("P", "c.end", force=(H, -P))
    r = femslide.solve(s, theory="linear")
    u = H / kx + H * L / EA
    v = -(P / ky + P * L**3 / (3 * EI) + P * L**2 / kr)
    close(r["rods"]["c"]["end"]["u"], u, u)
    close(r["rods"]["c"]["end"]["v"], v, v)
    close(r["rods"]["c"]["start"]["u"], H / kx, u)
    close(r["rods"]["c"]["start"]["v"], -P / ky, v)
    R = r["reactions"]["root"]
    close(R["Fx"], -H, P)
    close(R["Fy"], P, P)
    close(R["M"], P * L, P * L)


def test_beam_on_an_elastic_support():
    """Pin at one end, a roller whose vertical constraint is a spring ky at the other, uniform load
    q: midspan deflection 5 q L^4/(384 EI) + q L/(4 ky), the spring force q L/2 (1e-9)."""
    L, EI, q, ky = 6.0, 8e6, 12e3, 4e6
    s = Structure(gravity=(0.0, 0.0))
    s.rod("b", (0.0, 0.0), (L, 0.0), EI=EI, EA=1e10)
    s.pin("A", "b.start", "ground")
    s.roller("B", "b.end", "ground", axis=(1.0, 0.0), ky=ky)
    s.distributed("q", "b", force=(0.0, -q))
    r = femslide.solve(s, theory="linear")
    a = r.rod("b")
    k = int(np.argmin(np.abs(a["s"] - L / 2)))
    assert a["s"][k] == pytest.approx(L / 2)
    mid = -(5 * q * L**4 / (384 * EI) + q * L / (4 * ky))
    close(a["v"][k], mid, mid)
    close(r["rods"]["b"]["end"]["v"], -q * L / (2 * ky), mid)
    close(r["reactions"]["B"]["Fy"], q * L / 2, q * L)
    close(r["rods"]["b"]["M_max"], q * L**2 / 8, q * L**2 / 8)


def test_section_E_I_A_equals_EI_EA():
    """A rod given by E, I, A has exactly the results of the rod given by EI = E I, EA = E A."""
    E, I, A = 210e9, 8.36e-5, 5.38e-3
    out = []
    for kw in (dict(E=E, I=I, A=A), dict(EI=E * I, EA=E * A)):
        s = Structure(gravity=(0.0, 0.0))
        s.rod("c", (0.0, 0.0), (0.0, 3.0), **kw)
        s.weld("root", "c.start", "ground")
        s.force("P", "c.end", force=(2e4, -3e5))
        out.append(femslide.solve(s).flat())
    for k, v in out[0].items():
        if isinstance(v, float) and not k.endswith("_time_s"):
            assert out[1][k] == v, k


def _frame_with_cases(combos=True):
    s, _ = _portal(0.0, 0.0, "pinned", rhoA=80.0)
    del s.loads["H"], s.loads["q"]
    s.distributed("snow", "beam", force=(0.0, -9e3), case="snow")
    s.force("wind", "left.end", force=(25e3, 0.0), case="wind")
    s.force("crane", "right.end", force=(0.0, -40e3), moment=5e3, case="crane")
    if combos:
        s.combination("ULS-snow", {"dead": 1.35, "snow": 1.5, "wind": 0.9})
        s.combination("ULS-wind", {"dead": 1.0, "wind": 1.5, "crane": 1.05})
        s.combination("SLS", {"dead": 1.0, "snow": 1.0, "crane": 1.0})
    return s


def _scaled_by_hand(factors):
    s = _frame_with_cases(combos=False)
    f = {"dead": 0.0, **factors}
    s.gravity = (0.0, -9.81 * f["dead"])
    for name, ld in list(s.loads.items()):
        k = f.get(ld.case, 0.0)
        s.set(f"{name}.force", (k * ld.force[0], k * ld.force[1]))
        if ld.type == "force":
            s.set(f"{name}.moment", k * ld.moment)
    return s


@pytest.mark.parametrize("theory,elements", [("linear", None), ("nonlinear", 8)])
def test_combinations_equal_separate_solves(theory, elements):
    """Each combination equals the structure with its cases' loads scaled by hand (1e-9 relative to
    the largest value of its kind); the envelope is the max/min over the combinations (exact)."""
    s = _frame_with_cases()
    kw = {"theory": theory} if elements is None else {"theory": theory, "elements": elements}
    r = femslide.solve(s, **kw)
    assert r["converged"] and set(r["combinations"]) == {"ULS-snow", "ULS-wind", "SLS"}
    for name, c in s.combinations.items():
        ref = femslide.solve(_scaled_by_hand(dict(c.factors)), **kw)
        got = r["combinations"][name]
        assert got["factors"] == dict(c.factors)
        Ms = ref["M_max"]
        Fs = max(abs(v) for R in ref["reactions"].values() for v in (R["Fx"], R["Fy"]))
        for rod in ("left", "right", "beam"):
            for key in ("M_max",):
                close(got["rods"][rod][key], ref["rods"][rod][key], Ms)
            for key in ("N_max", "V_max"):
                close(got["rods"][rod][key], ref["rods"][rod][key], Fs)
            Us = max(abs(ref["rods"][x]["end"][c_]) for x in ("left", "right") for c_ in ("u", "v"))
            for c_ in ("u", "v"):
                close(got["rods"][rod]["end"][c_], ref["rods"][rod]["end"][c_], Us)
        for j in ("A", "D"):
            for key in ("Fx", "Fy"):
                close(got["reactions"][j][key], ref["reactions"][j][key], Fs)
    env = r["envelope"]
    ok = r["combinations"]
    for rod in ("left", "right", "beam"):
        for key in ("M_max", "N_max", "V_max"):
            best = max(ok, key=lambda c: ok[c]["rods"][rod][key])
            assert env["rods"][rod][key] == ok[best]["rods"][rod][key]
            assert env["rods"][rod][f"{key}_combination"] == best
    for j in ("A", "D"):
        for key in ("Fx", "Fy", "M"):
            vals = [ok[c]["reactions"][j][key] for c in ok]
            assert env["reactions"][j][f"{key}_min"] == min(vals)
            assert env["reactions"][j][f"{key}_max"] == max(vals)


def test_combination_result_by_name():
    """Result.combination(name) is that combination's result with its rods' arrays behind it."""
    r = femslide.solve(_frame_with_cases(), theory="linear")
    c = r.combination("SLS")
    assert c["M_max"] == r["combinations"]["SLS"]["M_max"]
    assert max(abs(c.rod("beam")["M"])) <= c["rods"]["beam"]["M_max"] * (1 + 1e-12)
    with pytest.raises(femslide.BadInput, match="no combination named"):
        r.combination("ULS")


def test_combination_factors_not_named_are_zero():
    """A case a combination does not name has factor 0: {"wind": 1} is the wind alone (no gravity)."""
    s = _frame_with_cases()
    s.combinations.clear()
    s.combination("wind-only", {"wind": 1.0})
    r = femslide.solve(s, theory="linear")["combinations"]["wind-only"]
    H = 25e3
    close(r["reactions"]["A"]["Fx"] + r["reactions"]["D"]["Fx"], -H, H)
    close(r["reactions"]["A"]["Fy"] + r["reactions"]["D"]["Fy"], 0.0, H)
    assert math.isfinite(r["M_max"])


@pytest.mark.parametrize("elements", [8, 64])
def test_linear_theory_on_banded_meshes(elements):
    """First-order theory on meshes whose Jacobian is stored banded (above 100 unknowns): an inclined
    cantilever under a tip force (P across, H along) against the closed forms P L^3/(3 EI) across and
    H L/EA along (exact for the linear elements), 1e-9.  Regression (review of the merges of issues
    23 and 27): the linear model read the Fortran-ordered band in C order and its solve failed
    ("the linear system could not be solved") on every mesh of more than ~30 elements."""
    L, EI, EA, P, H = 3.0, 2.1e6, 1.05e9, 2e4, 5e4
    c, s_ = 0.6, 0.8
    s = Structure(gravity=(0.0, 0.0))
    s.rod("c", (0.0, 0.0), (L * c, L * s_), EI=EI, EA=EA, elements=elements)
    s.weld("root", "c.start", "ground")
    # P across the rod (its normal turned +90 degrees), H along it
    s.force("tip", "c.end", force=(H * c - P * s_, H * s_ + P * c))
    r = femslide.solve(s, theory="linear")
    w, u = P * L**3 / (3 * EI), H * L / EA
    end = r["rods"]["c"]["end"]
    close(end["u"], u * c - w * s_, w)
    close(end["v"], u * s_ + w * c, w)
    close(end["theta"], P * L**2 / (2 * EI), P * L**2 / (2 * EI))
