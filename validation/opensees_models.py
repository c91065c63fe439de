"""OpenSees (openseespy) models of femslide's scenes, for benchmarks and cross-checks.

Imported only where openseespy is wanted (it needs Debian's libblas3 and liblapack3).
"""
from __future__ import annotations

import math
import os
import time

from dynamic_references import OSCILLATION_F2


def opensees_slider(v, phi, n=32, steps=None, penalty=1e6):
    """beam-slider in OpenSees (nondimensional: lengths by a, forces by P), driven by displacement
    control of the body rotation to femslide's equilibrium phi; returns (seconds of the analysis,
    load factor at phi, M_max [N m], status, seconds of model building and analysis).

    OpenSees has no rotating prismatic joint, so the sliding clamp is a corotational beam from a body
    point C on the guide line to the rod top S that is stiff in bending (penalty x the rod's EI) and
    has almost no axial stiffness: its chord, and so S, stays on the guide line through C, S turns
    with the body, and the slide is free up to the penalty.  The rigid body (with the rigid left rod)
    is two stiff corotational beams from the ground pin A1 to C and to the centre of mass G.  The
    work is less than femslide's: OpenSees is told phi and only finds the load factor holding it.
    """
    import openseespy.opensees as ops
    a, P = v["a"], v["m"] * v["g"]
    l, b, d, L = v["l"] / a, v["b"] / a, v["d"] / a, (v.get("L") or v["l"]) / a
    EI, EA = v["EI"] / (P * a * a), v["EA"] / P
    stiff = penalty * max(EI, 1.0)
    t_build = time.perf_counter()
    ops.wipe()
    ops.logFile(os.devnull, "-noEcho")  # its failures are counted, not printed
    ops.model("basic", "-ndm", 2, "-ndf", 3)
    ops.node(1, 0.0, 0.0)                 # A1: the body's ground pin (body rotation = its dof 3)
    ops.node(2, 1.0 + d, l + b)           # G
    ops.node(3, 2.0, L + 1.0)             # C: body point on the guide line, above the rod top
    for i in range(n + 1):                # the flexible rod B1 -> S
        ops.node(10 + i, 2.0, L * i / n)
    ops.fix(1, 1, 1, 0)
    ops.fix(10, 1, 1, 0)
    ops.geomTransf("Corotational", 1)
    for i in range(n):
        ops.element("elasticBeamColumn", 100 + i, 10 + i, 11 + i, EA, 1.0, EI, 1)
    ops.element("elasticBeamColumn", 1, 1, 2, stiff * EA / max(EI, 1.0), 1.0, stiff, 1)   # rigid body
    ops.element("elasticBeamColumn", 2, 1, 3, stiff * EA / max(EI, 1.0), 1.0, stiff, 1)
    ops.element("elasticBeamColumn", 3, 3, 10 + n, 1e-6, 1.0, stiff, 1)                  # the clamp
    ops.timeSeries("Linear", 1)
    ops.pattern("Plain", 1, 1)
    ops.load(2, 0.0, -1.0, 0.0)
    ops.system("BandGeneral")
    ops.numberer("RCM")
    ops.constraints("Plain")
    ops.test("NormDispIncr", 1e-12, 50, 0)
    ops.algorithm("Newton")
    steps = steps or max(1, math.ceil(abs(phi) / 0.1))
    ops.integrator("DisplacementControl", 1, 3, -phi / steps)
    ops.analysis("Static")
    t0 = time.perf_counter()
    ok = ops.analyze(steps)
    dt = time.perf_counter() - t0
    dt_all = time.perf_counter() - t_build
    lam = ops.getLoadFactor(1)
    M = max(abs(ops.eleForce(100 + i)[2]) for i in range(n))
    M = max(M, abs(ops.eleForce(100 + n - 1)[5]))
    return dt, lam, M * P * a, ok, dt_all


PENALTY_CAP = 1e11   # the clamp's and the rigid offsets' bending stiffness, at most this many P a^2 (below)


def opensees_slider_equilibrium(v, n=32, penalty=1e6, cap=PENALTY_CAP, tol=1e-12, first=1e-3, largest=0.1,
                                clock=time.perf_counter):
    """beam-slider in OpenSees as a user would solve it without femslide's answer: the same model as
    :func:`opensees_slider` (penalty clamp, rigid body as stiff corotational beams, ``n`` elements,
    nondimensional), but OpenSees finds the equilibrium at full load itself.

    The structure is a near-mechanism (its undeformed tangent is singular in the rigid limit), so load
    control from the undeformed state cannot start; the body rotation is driven instead
    (DisplacementControl of A1's rotation, towards B1): steps of ``first`` rad, doubled while the
    load factor lam stays well below 1 and aimed at lam = 1.02 by the power law lam ~ phi^p fitted to
    the last two steps (at most ``largest`` rad), a failed step halved; once lam passes 1, secant
    steps on the rotation (still under displacement control, which keeps the near-mechanism well
    posed) to |lam - 1| <= 1e-10.  Newton with NormDispIncr ``tol`` (50 iterations), BandGeneral with
    RCM numbering.

    The clamp and the rigid offsets are stiff in bending, ``penalty`` x the rod's EI, but at most
    ``cap`` (in P a^2): beyond that the load factor, which balances the penalty forces, is lost to
    round-off (measured on the 9-value EI sweep: a cap of 1e12 fails at EI = 1e7 N m^2, 1e13 at
    1e10), and the penalty's own error (its compliance against the rod's, ~EI / cap) grows at stiff
    rods: M_max is then only as accurate as that (``bench_cli.py`` prints it against femslide's).
    The guide point C sits 4 a above the rod's top so that the clamp beam keeps its length positive
    while the rod slides up to 1.5 a (EI = 1e2 N m^2).

    Returns a dict: ``status`` (0 = every analysis converged), ``phi`` (rad, clockwise), ``lam`` (the load
    factor reached), ``M_max`` [N m] (largest |end moment| of the rod's elements), ``steps``,
    ``newton_iterations``, ``analysis_s`` (``clock``, perf_counter by default, around the analysis: the
    stepping and the secant, not the model building) and ``all_s`` (building and analysis)."""
    import openseespy.opensees as ops
    a, P = v["a"], v["m"] * v["g"]
    l, b, d, L = v["l"] / a, v["b"] / a, v["d"] / a, (v.get("L") or v["l"]) / a
    EI, EA = v["EI"] / (P * a * a), v["EA"] / P
    stiff = min(penalty * max(EI, 1.0), cap)
    t_build = time.perf_counter()
    ops.wipe()
    ops.logFile(os.devnull, "-noEcho")
    ops.model("basic", "-ndm", 2, "-ndf", 3)
    ops.node(1, 0.0, 0.0)                 # A1: the body's ground pin (body rotation = its dof 3)
    ops.node(2, 1.0 + d, l + b)           # G
    ops.node(3, 2.0, L + 4.0)             # C: body point on the guide line, above the rod top
    for i in range(n + 1):
        ops.node(10 + i, 2.0, L * i / n)
    ops.fix(1, 1, 1, 0)
    ops.fix(10, 1, 1, 0)
    ops.geomTransf("Corotational", 1)
    for i in range(n):
        ops.element("elasticBeamColumn", 100 + i, 10 + i, 11 + i, EA, 1.0, EI, 1)
    ops.element("elasticBeamColumn", 1, 1, 2, stiff * EA / max(EI, 1.0), 1.0, stiff, 1)   # rigid body
    ops.element("elasticBeamColumn", 2, 1, 3, stiff * EA / max(EI, 1.0), 1.0, stiff, 1)
    ops.element("elasticBeamColumn", 3, 3, 10 + n, 1e-6, 1.0, stiff, 1)                  # the clamp
    ops.timeSeries("Linear", 1)
    ops.pattern("Plain", 1, 1)
    ops.load(2, 0.0, -1.0, 0.0)
    ops.system("BandGeneral")
    ops.numberer("RCM")
    ops.constraints("Plain")
    ops.test("NormDispIncr", tol, 50, 0)
    ops.algorithm("Newton")
    t0 = clock()

    def step(dphi):
        ops.integrator("DisplacementControl", 1, 3, -dphi)
        ops.analysis("Static")
        return ops.analyze(1), ops.testIter()

    dphi, lam, phi = first, 0.0, 0.0
    phi_prev = lam_prev = 0.0
    steps = its = 0
    status = 0
    while lam < 1.0:
        ok, k = step(dphi)
        steps, its = steps + 1, its + k
        if ok != 0:
            dphi *= 0.5
            if dphi < 1e-9:
                status = ok
                break
            continue
        phi_prev, lam_prev = phi, lam
        phi, lam = -ops.nodeDisp(1, 3), ops.getLoadFactor(1)
        need = largest
        if lam_prev > 0.0 and lam > lam_prev:   # lam ~ phi^p: aim at 1.02
            p = max(math.log(lam / lam_prev) / math.log(phi / phi_prev), 1.0)
            need = phi * ((1.02 / lam) ** (1.0 / p) - 1.0)
        dphi = min(2.0 * dphi, max(need, 1e-9), largest)
    for _ in range(30):
        if status or abs(lam - 1.0) <= 1e-10:
            break
        dstep = (1.0 - lam) * (phi - phi_prev) / (lam - lam_prev)
        ok, k = step(dstep)
        steps, its = steps + 1, its + k
        if ok != 0:
            status = ok
            break
        phi_prev, lam_prev = phi, lam
        phi, lam = -ops.nodeDisp(1, 3), ops.getLoadFactor(1)
    dt = clock() - t0
    M = max(abs(ops.eleForce(100 + i)[2]) for i in range(n))
    M = max(M, abs(ops.eleForce(100 + n - 1)[5]))
    return {"status": int(status), "phi": phi, "lam": lam, "M_max": M * P * a, "steps": steps,
            "newton_iterations": its, "analysis_s": dt, "all_s": time.perf_counter() - t_build}


# The paper's section 5.2 structure, as meshes/structures/beam-oscillation.toml declares it (SI units).
OSCILLATION = {
    "EI": 1e6, "EA": 1e12, "n": 8,        # flexible right rod B1 = (2, 0) -> S = (2, 1.5), massless
    "B1": (2.0, 0.0), "S": (2.0, 1.5),
    "m": 1.0, "I": 0.4166666666666667, "G": (1.2, 3.5),   # deck (with the rigid left rod), pinned at A1
    "C": (2.0, 3.0),                      # the guide's point on the deck (corner B of the deck)
    "m1": 0.1, "I1": 0.03333333333333333, "P": (2.0, 2.5),   # the piece welded to S
    "k": 100.0, "preload": -5.886,        # slider spring [N/m] and its force on S at zero slide [N]
    "g": 9.81,
}
F2_REDUCED = OSCILLATION_F2   # N, max |F2| of the reduced 1-DOF model (validation/reduced_dynamics.py)


def _peak3(t, y):
    """(t, y) of the vertex of the parabola through the largest sample of y and its two neighbours (any
    spacing); the sample itself when it is an end sample or the vertex falls outside the neighbours."""
    i = int(y.argmax())
    if not 0 < i < y.size - 1:
        return float(t[i]), float(y[i])
    h0, h1 = t[i] - t[i - 1], t[i + 1] - t[i]
    d0, d1 = (y[i] - y[i - 1]) / h0, (y[i + 1] - y[i]) / h1
    c2 = (d1 - d0) / (h0 + h1)                # y = y_i + c1 (t - t_i) + c2 (t - t_i)^2
    if c2 >= 0.0:
        return float(t[i]), float(y[i])
    c1 = d0 + c2 * h0
    x = -c1 / (2.0 * c2)
    if not -h0 <= x <= h1:
        return float(t[i]), float(y[i])
    return float(t[i] + x), float(y[i] - c1 * c1 / (4.0 * c2))


def opensees_oscillation(dt=1e-3, t_end=3.0, rotation=-0.01, penalty=1e9, axial=1e15, start_step=1e-6,
                         tol=1e-12, hold_steps=10, history=True, data=None, integrator=("Newmark", 0.5, 0.25)):
    """The section 5.2 structure (meshes/structures/beam-oscillation.toml) as an OpenSees (openseespy)
    Newmark transient: held statically at the deck rotation ``rotation`` [rad, counter-clockwise], released
    at rest at t = 0, run to ``t_end`` [s] with the constant step ``dt`` [s].

    Model (SI units, 2D, 3 dofs per node, every element ``elasticBeamColumn`` with ``geomTransf
    Corotational`` unless said otherwise, so that all rotations are exact, not linearised):

    * right rod: ``n`` = 8 elements B1 = (2, 0) -> S = (2, 1.5), EI = 1e6 N m^2, EA = 1e12 N, massless;
      B1 pinned (ux = uy = 0).
    * deck (one rigid body with the left rod): pinned at A1 = (0, 0); two stiff beams from A1 to the
      centre of mass G = (1.2, 3.5) and to the guide point C = (2, 3).  G carries the deck's mass
      (1 kg in x and y) and its rotary inertia about G (0.41667 kg m^2) and its weight.
    * the piece: a stiff beam S -> P = (2, 2.5) (the weld), P carries 0.1 kg, 0.03333 kg m^2 about P and
      its weight.
    * the sliding clamp (a prismatic joint whose guide turns with the deck): a beam C -> S stiff in
      bending (EI = ``penalty`` x the rod's EI) with almost no axial stiffness (EA = 1e-6 N).  Its end
      rotations equal its chord's rotation up to the penalty, so S stays on the line through C along
      the deck's axis and turns with the deck, at any rotation; the slide along the guide is free.
    * the slider spring: a ``corotTruss`` C -> S (force along the chord, i.e. along the guide) of axial
      stiffness k = 100 N/m (E A / L = k) with ``InitStressMaterial`` giving the preload: at zero slide
      it pushes S along -y with 5.886 N (femslide's ``preload = -5.886``: > 0 pushes the rod end along
      +axis), so that the vertical state is the equilibrium under gravity (g = 9.81 m/s^2).
    * rigid offsets (deck beams, weld): stiff corotational ``elasticBeamColumn``s, EI = ``penalty`` x
      1e6 N m^2 (default 1e15) and EA = ``axial`` N (default 1e15).  Not ``rigidLink``: OpenSees' rigid
      link is a linear (small-rotation) constraint, but the answer here is second order in the
      rotation (the rod's bending comes from the guide's misfit ~ rotation^2 ~ 1e-4 m); a hold with
      ``rigidLink beam`` for the deck stopped converging at -0.004 rad (measured).  Effect of the
      stiffnesses on max |F2| at dt = 1e-3 (refined peak, against the default): penalty 1e7 2.6e-6,
      1e8 1e-7, 1e10 7e-10; axial 1e14 or 1e16 below 2e-8 (validation/bench_fe_dynamics.py, table 4b).
      Lumping the deck's inertia at A1 instead (I_G + m |G - A1|^2, exact for a pinned rigid body)
      changes max |F2| by 5e-8 (measured).

    Analysis: gravity with the preload in one load step (the vertical state is its equilibrium), then
    displacement control of the deck rotation (node G, dof 3) in ``hold_steps`` steps against a moment
    on the deck: the holding moment is the load factor.  Release: that pattern is removed; Newmark
    average acceleration (gamma = 1/2, beta = 1/4), Newton, BandGeneral with RCM numbering,
    NormDispIncr ``tol`` [m] (at most 50 iterations).  OpenSees starts a transient with the
    accelerations of the static state (zero), not those of the released structure.  With
    ``start_step`` > 0 [s] the transient begins with one step of that size, whose Newmark equilibrium
    gives the initial accelerations (its velocity error, start_step x acceleration / 2, is negligible);
    ``start_step = None`` keeps OpenSees' zero start, which costs 9e-6 relative in max |F2| at
    dt = 1e-3 and 1.6e-4 at 4e-3 (an O(dt^2) loss of energy in the first step).  Then round(t_end / dt)
    steps of dt (the run ends at t_end + start_step).

    F2 is the horizontal ground reaction at B1 (force of the ground on the structure, +x), read each
    step as the first rod element's force at B1 (equal to ``nodeReaction``: B1 is massless and
    unloaded).  Returns a dict: ``F2_max`` (max |F2| over the samples, N), ``F2_peak`` and ``t_peak``
    (the top sample refined by the parabola through it and its neighbours, as femslide refines its own
    peaks), ``status`` (0 = every step converged; the run stops at the first failure), ``steps``,
    ``newton_iterations``, ``analysis_s`` (perf_counter around the transient analyze loop only: the
    steps and the read of F2), ``build_s`` (model building and the static hold), ``hold_moment`` [N m],
    ``F2_start`` (F2 of the held state), and with ``history`` the arrays ``t``, ``F2``, ``rotation``
    (deck) and ``slide`` (S along the guide relative to the deck, m).
    """
    import numpy as np
    import openseespy.opensees as ops
    v = dict(OSCILLATION, **(data or {}))
    n, L = int(v["n"]), v["S"][1] - v["B1"][1]
    EIs = penalty * v["EI"]
    t_build = time.perf_counter()
    ops.wipe()
    ops.logFile(os.devnull, "-noEcho")
    ops.model("basic", "-ndm", 2, "-ndf", 3)
    A1, G, C, P, R0 = 1, 2, 3, 4, 10          # nodes; the rod is R0 .. R0 + n, S = R0 + n
    S = R0 + n
    ops.node(A1, 0.0, 0.0)
    ops.node(G, *v["G"])
    ops.node(C, *v["C"])
    ops.node(P, *v["P"])
    for i in range(n + 1):
        ops.node(R0 + i, v["B1"][0] + (v["S"][0] - v["B1"][0]) * i / n, v["B1"][1] + L * i / n)
    ops.fix(A1, 1, 1, 0)
    ops.fix(R0, 1, 1, 0)
    ops.geomTransf("Corotational", 1)
    for i in range(n):
        ops.element("elasticBeamColumn", 100 + i, R0 + i, R0 + i + 1, v["EA"], 1.0, v["EI"], 1)
    ops.element("elasticBeamColumn", 1, A1, G, axial, 1.0, EIs, 1)      # deck: rigid offsets
    ops.element("elasticBeamColumn", 2, A1, C, axial, 1.0, EIs, 1)
    ops.element("elasticBeamColumn", 3, C, S, 1e-6, 1.0, EIs, 1)       # the clamp
    ops.element("elasticBeamColumn", 4, S, P, axial, 1.0, EIs, 1)       # the piece's weld
    Lc = math.dist(v["C"], v["S"])
    ops.uniaxialMaterial("Elastic", 2, v["k"] * Lc)                     # E A / Lc = k with A = 1
    ops.uniaxialMaterial("InitStressMaterial", 1, 2, v["preload"])      # compression pushes S off C
    ops.element("corotTruss", 5, C, S, 1.0, 1)
    ops.mass(G, v["m"], v["m"], v["I"])
    ops.mass(P, v["m1"], v["m1"], v["I1"])
    ops.timeSeries("Constant", 1)
    ops.pattern("Plain", 1, 1)
    ops.load(G, 0.0, -v["m"] * v["g"], 0.0)
    ops.load(P, 0.0, -v["m1"] * v["g"], 0.0)
    ops.system("BandGeneral")
    ops.numberer("RCM")
    ops.constraints("Plain")
    ops.test("NormDispIncr", tol, 50, 0)
    ops.algorithm("Newton")
    ops.integrator("LoadControl", 1.0)
    ops.analysis("Static")
    status = ops.analyze(1)
    ops.loadConst("-time", 0.0)
    ops.timeSeries("Linear", 2)
    ops.pattern("Plain", 2, 2)
    ops.load(G, 0.0, 0.0, 1.0)                                          # the holding moment
    ops.integrator("DisplacementControl", G, 3, rotation / hold_steps)
    status = status or ops.analyze(hold_steps)
    hold_moment = ops.getLoadFactor(2)
    ops.remove("loadPattern", 2)
    ops.wipeAnalysis()
    ops.setTime(0.0)
    ops.system("BandGeneral")
    ops.numberer("RCM")
    ops.constraints("Plain")
    ops.test("NormDispIncr", tol, 50, 0)
    ops.algorithm("Newton")
    ops.integrator(*integrator)   # (``integrator``: OpenSees' arguments, e.g. ("HHT", 0.9))
    ops.analysis("Transient")
    build_s = time.perf_counter() - t_build

    steps = int(round(t_end / dt))
    first = 1 if start_step else 0
    F2 = np.full(steps + first + 1, np.nan)
    t = np.zeros(steps + first + 1)
    rot = np.full_like(F2, np.nan)
    slide = np.full_like(F2, np.nan)
    xc, xs = np.array(v["C"]), np.array(v["S"])

    def sample(j):
        F2[j] = ops.eleForce(100)[0]
        t[j] = ops.getTime()
        if history:
            rot[j] = ops.nodeDisp(G, 3)
            c, s = xc + ops.nodeDisp(C)[:2], xs + ops.nodeDisp(S)[:2]
            slide[j] = Lc - math.hypot(*(c - s))
    sample(0)
    F2_start = float(F2[0])
    iters = 0
    t0 = time.perf_counter()
    if not status:
        for j in range(1, steps + first + 1):
            ok = ops.analyze(1, start_step if j <= first else dt)
            iters += ops.testIter()
            if ok:
                status = ok
                break
            sample(j)
    analysis_s = time.perf_counter() - t0
    ops.wipe()
    good = ~np.isnan(F2)
    absF = np.abs(F2[good])
    t_peak, F2_peak = _peak3(t[good], absF)
    out = {"F2_max": float(absF.max()), "F2_peak": F2_peak, "t_peak": t_peak, "status": int(status),
           "steps": steps, "newton_iterations": iters, "analysis_s": analysis_s, "build_s": build_s,
           "hold_moment": hold_moment, "F2_start": F2_start, "dt": dt, "penalty": penalty}
    if history:
        out.update(t=t[good], F2=F2[good], rotation=rot[good], slide=slide[good])
    return out


def opensees_massive_cantilever(n=32, dt=1e-3, t_end=3.0, EI=10.0, EA=1e7, rhoA=1.0, L=1.0, amplitude=1.0,
                                frequency=1.0, tol=1e-12, axis=(1.0, 0.0), direction=(0.0, 1.0), tip_mass=0.0,
                                tip_inertia=0.0, transf="Corotational", integrator=("Newmark", 0.5, 0.25),
                                history=False, eigen=0, reactions=False):
    """validation/massive-cantilever.toml (defaults) or meshes/structures/cantilever-tip-mass.toml
    (``axis=(0, 1)``, ``direction=(1, 0)``, ``tip_mass``, ``tip_inertia``) in OpenSees: a cantilever of
    ``n`` equal ``elasticBeamColumn`` elements (EI [N m^2], EA [N], geometric transformation
    ``transf``: "Corotational" or "Linear") of length ``L`` [m] along the unit vector ``axis``, clamped
    at the origin; rhoA L / n [kg] lumped at the inner nodes and half of it at the free end
    (translations only, no rotary inertia at the nodes, as femslide lumps:
    femslide/model/mass.py), plus a tip body whose centroid is the free end: ``tip_mass`` [kg] on its
    translations and ``tip_inertia`` [kg m^2] on its rotation.  The base is shaken by the acceleration
    a_g = amplitude sin(2 pi frequency t) [m/s^2, Hz] along the unit vector ``direction``, applied as the
    inertia loads -m_i a_g(t) on the lumped translational masses (relative coordinates, as femslide:
    the same equations as a ``UniformExcitation`` pattern, whose command does not return in openseespy
    3.7.1.2 here, measured again for issue 22; a ``Trig`` time series on a ``Plain`` pattern, exact at
    every step's end), from rest (a_g(0) = 0: OpenSees' zero initial accelerations are exact).
    Transient: ``integrator`` (OpenSees' arguments: ("Newmark", 0.5, 0.25) average acceleration,
    ("HHT", 0.9), ...), Newton, NormDispIncr ``tol`` [m] (at most 50 iterations), BandGeneral with RCM,
    ``round(t_end / dt)`` constant steps ``dt`` [s].

    Returns a dict: ``status`` (0 = every step converged; the run stops at the first failure),
    ``steps``, ``newton_iterations``, ``analysis_s`` (perf_counter around the analyze loop: the steps and
    the read of the free end's displacement), ``tip_v_max`` [m] (largest |displacement| of the free end
    relative to the base, along the rod's normal (-axis_y, axis_x)), ``all_s`` (with the model
    building); with ``eigen`` > 0 the first ``eigen`` natural frequencies ``frequencies_hz`` [Hz] of the
    model before the transient (``eigen -fullGenLapack``: the mass matrix is singular on the massless
    rotations); with ``history`` the arrays ``t`` [s] and ``tip_u``, ``tip_v`` [m] (the free end's
    displacement relative to the base along x and y) at t = 0 and at every step's end; with
    ``reactions`` (which implies ``history``) also ``reaction`` (steps + 1, 3): the clamp's reaction (Fx, Fy [N],
    M [N m], global axes, OpenSees' ``nodeReaction`` after ``reactions``: the force of the support on
    the rod) at the same times."""
    import numpy as np
    import openseespy.opensees as ops
    history = history or reactions
    t_build = time.perf_counter()
    ops.wipe()
    ops.logFile(os.devnull, "-noEcho")
    ops.model("basic", "-ndm", 2, "-ndf", 3)
    ax, ay = axis
    for i in range(n + 1):
        ops.node(i + 1, ax * L * i / n, ay * L * i / n)
    ops.fix(1, 1, 1, 1)
    ops.geomTransf(transf, 1)
    for i in range(n):
        ops.element("elasticBeamColumn", i + 1, i + 1, i + 2, EA, 1.0, EI, 1)
    m = rhoA * L / n
    masses = [m if i < n else 0.5 * m + tip_mass for i in range(1, n + 1)]
    for i, mi in zip(range(1, n + 1), masses):
        ops.mass(i + 1, mi, mi, tip_inertia if i == n else 0.0)
    freq = None
    if eigen:
        lam = np.array(ops.eigen("-fullGenLapack", eigen), float)
        freq = np.sqrt(lam) / (2 * math.pi)
    ops.timeSeries("Trig", 1, 0.0, 1e9, 1.0 / frequency, "-factor", amplitude)
    ops.pattern("Plain", 1, 1)
    dx, dy = direction
    for i, mi in zip(range(1, n + 1), masses):
        ops.load(i + 1, -mi * dx, -mi * dy, 0.0)
    ops.system("BandGeneral")
    ops.numberer("RCM")
    ops.constraints("Plain")
    ops.test("NormDispIncr", tol, 50, 0)
    ops.algorithm("Newton")
    ops.integrator(*integrator)
    ops.analysis("Transient")
    steps = int(round(t_end / dt))
    iters, vmax, status = 0, 0.0, 0
    t = np.zeros(steps + 1)
    tip = np.zeros((steps + 1, 2))
    reac = np.zeros((steps + 1, 3))
    k = 0
    t0 = time.perf_counter()
    for k in range(1, steps + 1):
        status = ops.analyze(1, dt)
        if status:
            k -= 1
            break
        iters += ops.testIter()
        u = ops.nodeDisp(n + 1)
        vmax = max(vmax, abs(-ay * u[0] + ax * u[1]))
        if history:
            t[k], tip[k] = ops.getTime(), u[:2]
            if reactions:
                ops.reactions()
                reac[k] = ops.nodeReaction(1)[:3]
    dt_an = time.perf_counter() - t0
    ops.wipe()
    out = {"status": int(status), "steps": steps, "newton_iterations": iters, "analysis_s": dt_an,
           "tip_v_max": vmax, "all_s": time.perf_counter() - t_build}
    if freq is not None:
        out["frequencies_hz"] = freq
    if history:
        out.update(t=t[:k + 1], tip_u=tip[:k + 1, 0], tip_v=tip[:k + 1, 1])
        if reactions:
            out["reaction"] = reac[:k + 1]
    return out
