"""Exact references of the structure files of issue 22 (the accuracy of the FE dynamics), built from the
files' own parameters by validation/linear_dynamics.py and validation/friction_events.py (numpy and
scipy; femslide's solvers are not used, only tomllib reads the same TOML file).

Each builder returns a :class:`Reference`: ``histories`` {history column of femslide: function of
time (vectorised) giving the exact value [SI]}, ``peaks`` {dotted key of femslide's ``peaks``:
exact largest |value| over the run}, ``events`` (friction cases: [(t, kind)]), ``frequencies_hz``
(the linear model's, to check against ``femslide modes``), ``T1`` [s] (longest natural period of
the structure as it starts: stuck friction joints locked), and ``notes``.

Displacement columns are compared as displacements: ``bodies.NAME.x`` here is the centroid's
displacement along x (femslide reports the position; the script subtracts the reference
position, see ``offsets``).

* :func:`two_storey_frame` - meshes/structures/two-storey-frame.toml: full linear frame (floors with
  their three dofs, massless columns as exact beam elements, EA finite), undamped modal superposition
  in closed form.  The shear-building model (storey stiffness 2 x 12 EI/h^3) is its EA -> infinity
  limit (:func:`shear_building_frequencies`).
* :func:`cantilever_tip_mass` - meshes/structures/cantilever-tip-mass.toml: the same discretisation as
  femslide (32 equal Euler-Bernoulli elements, nodal masses rhoA L_e / 2 on the translations, no rotary
  inertia at the nodes, the tip body's mass and inertia on the tip node), the massless rotations
  condensed statically; modal superposition in closed form.
* :func:`two_mass_friction` - meshes/structures/two-mass-friction.toml: two blocks, the lower on a
  ground slider with a spring and Coulomb friction, the upper on a frictionless slider with a spring
  on the lower one: all rotations and vertical motions are locked, so the FE model is exactly this
  linear 2-dof system with N = (m1 + m2) g; event-driven exact solution.
* :func:`base_isolated_frame` - meshes/structures/base-isolated-frame.toml: the frame's linearisation
  about its static state under gravity (the columns' axial force enters as the geometric stiffness
  of the corotational elements, same mesh as femslide's), the base on the ground slider with
  N = total weight; event-driven exact solution under the synthetic record.
"""
from __future__ import annotations

import math
import os
import tomllib
from dataclasses import dataclass, field

import numpy as np

from friction_events import FrictionSystem, Ground
from linear_dynamics import LinearStructure, modal_harmonic, modal_harmonic_damped, modes, peak_abs

HERE = os.path.dirname(os.path.abspath(__file__))
STRUCTURES = os.path.join(os.path.dirname(HERE), "meshes", "structures")


@dataclass
class Reference:
    name: str
    path: str
    t_end: float
    histories: dict
    peaks: dict
    frequencies_hz: np.ndarray
    T1: float
    offsets: dict = field(default_factory=dict)
    events: list | None = None
    notes: str = ""
    extra: dict = field(default_factory=dict)


def history_errors(history, ref, columns=None):
    """{column: the largest |femslide - reference| at femslide's history times over the reference's
    largest |value| there} of a femslide ``history`` (columns -> arrays, "t" the times [s]) against a
    :class:`Reference`: the reference's ``offsets`` (a position's static place) taken off femslide's
    value first; every column the reference has, or those of ``columns``."""
    t = history["t"]
    out = {}
    for c, f in ref.histories.items():
        if columns is None or c in columns:
            xr = f(t)
            out[c] = float(np.abs(history[c] - ref.offsets.get(c, 0.0) - xr).max() / np.abs(xr).max())
    return out


def without_zero_duration_pairs(events):
    """An event list [(t, kind)] without the pairs (stick, slip) at one instant (within 1e-9 s): an
    event-driven reference's own record of a grazing stop that breaks away at once (femslide lists
    neither)."""
    out = []
    for t, k in events:
        if out and k.startswith("slip") and out[-1][1] == "stick" and abs(out[-1][0] - t) <= 1e-9:
            out.pop()
            continue
        out.append((t, k))
    return out


def read(name):
    path = os.path.join(STRUCTURES, name if name.endswith(".toml") else name + ".toml")
    with open(path, "rb") as f:
        return path, tomllib.load(f)


def _by_name(items, name):
    for it in items:
        if it["name"] == name:
            return it
    raise KeyError(name)


def _body_maps(S, name):
    return S.dofs(f"{name}.u", f"{name}.v", f"{name}.th")


def _harmonic(d):
    g = d["simulate"]["ground"]
    assert tuple(g["direction"]) == (1.0, 0.0)
    return float(g["amplitude"]), 2 * math.pi * float(g["frequency"])


CHUNK = 20000   # samples per evaluation of a modal history


def _modal_reference(name, path, d, S, cols, offsets, T1_from=None, forces=(), ground_terms=None, damping=None,
                     peaks=True):
    """Histories and peaks of the outputs ``cols`` {column: row (n,)} under the file's harmonic
    ground motion by modal superposition.  ``damping`` (alpha, beta) of Rayleigh damping (C = alpha M
    + beta K on the model's coordinates, K the linear stiffness): modal damping ratios, and the
    columns ``forces`` (element end forces, rows of K) carry their damping part beta (row @ q').
    ``ground_terms`` {column: c}: c a_g(t) added (the inertia of a support node's own lumped mass,
    which moves with the ground: it is carried by the support).  ``peaks``: False leaves ``peaks``
    empty (they take a fine grid over every mode: about a minute and gigabytes on the mast)."""
    rows = np.array(list(cols.values()))
    Mr, Cr, Kr, fmap, keep, R = S.reduced(rows)
    assert np.abs(Cr).max() == 0.0
    fg = S.ground_load()[keep]
    md = modes(Mr, Kr, fg)
    A, W = _harmonic(d)
    t_end = float(d["simulate"]["t_end"])
    alpha, beta = damping or (0.0, 0.0)
    zeta = alpha / (2 * md.omega) + beta * md.omega / 2 if (alpha or beta) else None
    ground_terms = ground_terms or {}
    hist = {}

    def one(t, k, c):
        t = np.asarray(t, float)
        if t.size > CHUNK:   # (in chunks: memory ~ modes x samples)
            return np.concatenate([one(t[i:i + CHUNK], k, c) for i in range(0, t.size, CHUNK)])
        if alpha or beta:
            x = modal_harmonic_damped(md, A, W, t, R[k:k + 1], zeta)[0]
            if c in forces:
                x = x + beta * modal_harmonic_damped(md, A, W, t, R[k:k + 1], zeta, 1)[0]
        else:
            x = modal_harmonic(md, A, W, t, R[k:k + 1])[0]
        return x + ground_terms.get(c, 0.0) * A * np.sin(W * t)

    for k, c in enumerate(cols):
        hist[c] = (lambda t, k=k, c=c: one(t, k, c))
    dt = 2 * math.pi / max(W, md.omega[md.omega < 1e4 * md.omega[md.omega > 0].min()].max()) / 40
    peaks = {c: peak_abs(hist[c], 0.0, t_end, dt) for c in cols} if peaks else {}
    T1 = 2 * math.pi / md.omega[md.omega > 0].min()
    return Reference(name, path, t_end, hist, peaks, md.frequencies_hz, T1, offsets,
                     extra={"modal": md, "rows": R, "A": A, "W": W})


# -- a) the two-storey frame ---------------------------------------------------------------------------

def two_storey_frame(file="two-storey-frame.toml"):
    """Exact response of meshes/structures/two-storey-frame.toml (module docstring).  Coordinates: the
    floors' centroid displacements and rotations; each column one exact element (massless prismatic
    members under end loads only: the cubic is exact, so femslide's inner nodes add nothing in the
    linear limit).  Outputs: floor displacements along x, base shear Fx and moment M of the ground
    on the columns at A and B."""
    path, d = read(file)
    assert d["gravity"] == [0.0, 0.0]
    S = LinearStructure(["floor1.u", "floor1.v", "floor1.th", "floor2.u", "floor2.v", "floor2.th"])
    bodies = {b["name"]: b for b in d["body"]}
    maps = {}
    for name, b in bodies.items():
        maps[name] = _body_maps(S, name)
        S.mass(maps[name], b["mass"], b["inertia"])
    joints = d["joint"]

    def end_map(rod, end):
        """The map of a rod end welded to a floor or the ground."""
        j = next(j for j in joints if j["a"] == f"{rod['name']}.{end}")
        X = rod[end]
        if j["b"] == "ground":
            return S.ground(), X, j["name"]
        c = bodies[j["b"]]["centroid"]
        return S.point(maps[j["b"]], (X[0] - c[0], X[1] - c[1])), X, None

    beams = {}
    supports = {}
    for rod in d["rod"]:
        assert rod.get("rhoA", 0.0) == 0.0
        A, XA, ga = end_map(rod, "start")
        B, XB, gb = end_map(rod, "end")
        i = S.beam(rod["name"], A, B, XA, XB, float(rod["EI"]), float(rod["EA"]))
        beams[rod["name"]] = i
        if ga:
            supports[ga] = (i, 0)
        if gb:
            supports[gb] = (i, 1)
    cols = {}
    offsets = {}
    for name in bodies:
        cols[f"bodies.{name}.x"] = S.output("map", maps[name], 0)
        offsets[f"bodies.{name}.x"] = bodies[name]["centroid"][0]
    for jn, (i, e) in supports.items():
        R = S.reaction([(i, e)])
        cols[f"reactions.{jn}.Fx"] = R[0]
        cols[f"reactions.{jn}.M"] = R[2]
    ref = _modal_reference("two-storey-frame", path, d, S, cols, offsets)
    return ref


def shear_building_frequencies(file="two-storey-frame.toml"):
    """[Hz] of the EA -> infinity limit: floors that do not rotate, storey stiffness 2 x 12 EI / h^3."""
    _, d = read(file)
    m1, m2 = (b["mass"] for b in d["body"])
    rods = {r["name"]: r for r in d["rod"]}
    k = []
    for pair in (("c1L", "c1R"), ("c2L", "c2R")):
        k.append(sum(12 * float(rods[p]["EI"]) / (rods[p]["end"][1] - rods[p]["start"][1]) ** 3 for p in pair))
    K = np.array([[k[0] + k[1], -k[1]], [-k[1], k[1]]])
    M = np.diag([m1, m2])
    w2 = np.linalg.eigvalsh(np.linalg.solve(np.sqrt(M), np.linalg.solve(np.sqrt(M), K).T))
    return np.sqrt(np.sort(w2)) / (2 * math.pi)


# -- b) the cantilever with a tip mass ---------------------------------------------------------------------

def cantilever_tip_mass(file="cantilever-tip-mass.toml", damping=None, peaks=True):
    """Exact response of the discretised mast of meshes/structures/cantilever-tip-mass.toml (module
    docstring): coordinates u, v, theta of every node above the foot (the top node is the tip body's
    centroid), femslide's lumped masses, the node rotations condensed (no inertia).  Outputs: tip
    displacement along x, tip rotation, root shear Fx and moment M (ground on the mast); the root
    shear includes the foot node's own lumped mass rhoA L_e / 2 times the ground acceleration (the
    foot moves with the ground, and the weld carries its inertia).  ``damping``: (alpha, beta) of
    Rayleigh damping (None: the file's ``simulate.damping``, or none)."""
    path, d = read(file)
    if damping is None:
        dm = d["simulate"].get("damping", {})
        damping = (float(dm.get("alpha", 0.0)), float(dm.get("beta", 0.0)))
    assert d["gravity"] == [0.0, 0.0]
    (rod,) = d["rod"]
    (tip,) = d["body"]
    assert list(tip["centroid"]) == list(rod["end"])
    n_el = int(rod["elements"])
    S = LinearStructure(["tip.u", "tip.v", "tip.th"])
    T_tip = _body_maps(S, "tip")
    els = S.chain("mast", S.ground(), T_tip, rod["start"], rod["end"], float(rod["EI"]), float(rod["EA"]), n_el)
    Le = math.dist(rod["start"], rod["end"]) / n_el
    m_node = float(rod["rhoA"]) * Le
    for i in range(1, n_el):
        S.mass(S.dofs(f"mast.{i}.u", f"mast.{i}.v", None), m_node)
    S.mass(_body_maps(S, "tip"), m_node / 2 + float(tip["mass"]), float(tip["inertia"]))
    cols = {"bodies.tip.x": S.output("coord", "tip.u"), "bodies.tip.rotation": S.output("coord", "tip.th")}
    R = S.reaction([(els[0], 0)])
    cols["reactions.root.Fx"] = R[0]
    cols["reactions.root.M"] = R[2]
    return _modal_reference("cantilever-tip-mass", path, d, S, cols, {"bodies.tip.x": tip["centroid"][0]},
                            forces=("reactions.root.Fx", "reactions.root.M"),
                            ground_terms={"reactions.root.Fx": m_node / 2}, damping=damping, peaks=peaks)


def euler_bernoulli_tip_mass(file="cantilever-tip-mass.toml", count=4):
    """[Hz] of the continuous Euler-Bernoulli cantilever with a tip mass M_t and tip rotary inertia
    J_t (the limit of the mesh): roots of the frequency equation of w'''' = beta^4 w with
    w(0) = w'(0) = 0 and the tip body's equations of motion EI w''(L) = J_t omega^2 w'(L),
    EI w'''(L) = -M_t omega^2 w(L)."""
    from scipy.optimize import brentq
    _, d = read(file)
    (rod,) = d["rod"]
    (tip,) = d["body"]
    L = math.dist(rod["start"], rod["end"])
    EI, m = float(rod["EI"]), float(rod["rhoA"])
    Mt, Jt = float(tip["mass"]), float(tip["inertia"])

    def det(bL):
        b = bL / L
        w2 = EI * b ** 4 / m
        # w = A (cosh - cos) + B (sinh - sin) in b x: the 2 x 2 system at x = L
        ch, c, sh, s = math.cosh(bL), math.cos(bL), math.sinh(bL), math.sin(bL)
        w_A, w_B = ch - c, sh - s
        d1_A, d1_B = b * (sh + s), b * (ch - c)
        d2_A, d2_B = b * b * (ch + c), b * b * (sh + s)
        d3_A, d3_B = b ** 3 * (sh - s), b ** 3 * (ch + c)
        r1 = (EI * d2_A - Jt * w2 * d1_A, EI * d2_B - Jt * w2 * d1_B)
        r2 = (EI * d3_A + Mt * w2 * w_A, EI * d3_B + Mt * w2 * w_B)
        return (r1[0] * r2[1] - r1[1] * r2[0]) / ch ** 2
    roots = []
    grid = np.linspace(1e-3, 4 * count + 4, 40000)
    vals = [det(g) for g in grid]
    for a, b, fa, fb in zip(grid[:-1], grid[1:], vals[:-1], vals[1:]):
        if fa * fb < 0:
            roots.append(brentq(det, a, b, xtol=1e-15))
            if len(roots) == count:
                break
    return np.array([(r / L) ** 2 * math.sqrt(EI / m) / (2 * math.pi) for r in roots])


# -- c) friction: two masses ------------------------------------------------------------------------------

def _ground_of(d, base_dir):
    g = d["simulate"]["ground"]
    assert tuple(g["direction"]) == (1.0, 0.0)
    if "record" in g:
        times, values = read_record(os.path.join(base_dir, g["record"]))
        return Ground(times=times, values=values, scale=float(g.get("scale", 1.0)),
                      amplitude=float(g.get("amplitude", 0.0)), frequency=float(g.get("frequency", 0.0)))
    return Ground(amplitude=float(g["amplitude"]), frequency=float(g["frequency"]))


def read_record(path):
    """(times [s], accelerations [m/s^2]) of a CSV record t, a (one header line allowed)."""
    data = np.genfromtxt(path, delimiter=",", skip_header=1)
    return data[:, 0].copy(), data[:, 1].copy()


def _friction_reference(name, path, d, S, slide, N, joint, cols, offsets, h, overrides=None):
    """Event-driven reference of the linear structure S with friction on the coordinate ``slide``."""
    j = _by_name(d["joint"], joint)
    o = overrides or {}
    mu = float(o.get("mu", j["mu"]))
    mu0 = float(o.get("mu0", j.get("mu0", mu)))
    rows = np.array(list(cols.values()))
    Mr, Cr, Kr, fmap, keep, R = S.reduced(rows)
    ib = int(np.nonzero(keep == S.names.index(slide))[0][0])
    ground = _ground_of(d, os.path.dirname(path))
    if "scale" in o:
        ground.scale = float(o["scale"])
    fg = S.ground_load()[keep]
    t_end = float(o.get("t_end", d["simulate"]["t_end"]))
    sys_ = FrictionSystem(Mr, Cr, Kr, fg, ib, N, mu, mu0, ground)
    sol = sys_.solve(t_end, h)
    hist = {}
    for k, c in enumerate(cols):
        hist[c] = (lambda t, k=k: R[k] @ sol.state(t)[0])
    # natural periods: stuck (slide locked) and free (frictionless)
    o_ = np.array([i for i in range(keep.size) if i != ib])
    w_stuck = np.sqrt(np.abs(np.linalg.eigvals(np.linalg.solve(Mr[np.ix_(o_, o_)], Kr[np.ix_(o_, o_)]))))
    w_free = np.sqrt(np.abs(np.linalg.eigvals(np.linalg.solve(Mr, Kr))))
    w_free = np.sort(w_free[w_free > 1e-6 * w_free.max()])
    T1 = 2 * math.pi / min(w_stuck.min(), w_free.min() if w_free.size else np.inf)
    # peaks: the dense state on a grid of 1/64 of the shortest period that the ground motion and the
    # friction excite noticeably (the stiff vertical and rocking modes carry < 1e-9 of the motion),
    # plus the event times, refined by a bounded search about the largest sample
    w_dom = [w for w in np.concatenate([w_stuck, w_free]) if w < 200.0] or [1.0]
    dt = min(h, 2 * math.pi / max(w_dom) / 64, 1e-3)
    grid = np.unique(np.concatenate([np.linspace(0.0, t_end, int(math.ceil(t_end / dt)) + 1),
                                     [t for t, _ in sol.events]]))
    Xg = sol.state(grid)[0]
    peaks = {c: peak_abs(hist[c], 0.0, t_end, dt, samples=(grid, R[k] @ Xg)) for k, c in enumerate(cols)}
    ref = Reference(name, path, t_end, hist, peaks, np.sort(w_stuck) / (2 * math.pi), T1, offsets,
                    events=sol.events, extra={"solution": sol, "system": sys_, "rows": R, "keep": keep,
                                              "grid": grid, "grid_state": Xg,
                                              "free_hz": w_free / (2 * math.pi), "N": N, "mu": mu, "mu0": mu0})
    t_ev = [t for t, _ in sol.events]
    slide_row = R[list(cols).index(f"joints.{joint}.slide")]
    ref.extra["residual_slide"] = float(slide_row @ sol.state([t_end])[0][:, 0])
    ref.extra["event_times"] = t_ev
    return ref


def two_mass_friction(file="two-mass-friction.toml", h=2e-3, **overrides):
    """Exact event-driven motion of meshes/structures/two-mass-friction.toml (module docstring).
    Coordinates: the blocks' displacements along x (rotations and vertical motions are locked by the
    sliders exactly, also in femslide's nonlinear model).  ``overrides``: mu, mu0, scale, t_end (for
    the limiting cases)."""
    path, d = read(file)
    g = -float(d["gravity"][1])
    base, top = (_by_name(d["body"], n) for n in ("base", "top"))
    belt, upper = (_by_name(d["joint"], n) for n in ("belt", "upper"))
    S = LinearStructure(["base.u", "top.u"])
    S.mass(S.dofs("base.u"), base["mass"])
    S.mass(S.dofs("top.u"), top["mass"])
    S.spring(S.coord("base.u"), float(belt["k"]))
    S.spring(S.coord("top.u") - S.coord("base.u"), float(upper["k"]))
    N = (base["mass"] + top["mass"]) * g
    cols = {"joints.belt.slide": S.coord("base.u"), "joints.upper.slide": S.coord("top.u") - S.coord("base.u"),
            "bodies.top.x": S.coord("top.u")}
    return _friction_reference("two-mass-friction", path, d, S, "base.u", N, "belt", cols,
                               {"bodies.top.x": top["centroid"][0]}, h, overrides)


# -- c) friction: the base-isolated frame -------------------------------------------------------------------

def base_isolated_frame(file="base-isolated-frame.toml", h=2e-3, **overrides):
    """Exact event-driven motion of meshes/structures/base-isolated-frame.toml linearised about its
    static state (module docstring).  Coordinates: the base's slide, the deck's u, v, theta and the
    columns' inner nodes (condensed: massless); each column's elements carry the static axial force
    -m_deck g / 2 (symmetric structure: no static end moments), so their tangent has the geometric
    stiffness of that force.  N = (m_base + m_deck) g (the deck's vertical inertia is of second order
    in the motion: it is neglected here, see the notes).  ``overrides``: mu, mu0, scale, t_end."""
    path, d = read(file)
    g = -float(d["gravity"][1])
    base, deck = (_by_name(d["body"], n) for n in ("base", "deck"))
    S = LinearStructure(["base.u", "deck.u", "deck.v", "deck.th"])
    B = S.dofs("base.u", None, None)
    D = _body_maps(S, "deck")
    S.mass(B, base["mass"])
    S.mass(D, deck["mass"], deck["inertia"])
    P = deck["mass"] * g / 2.0
    els = {}
    for rod in d["rod"]:
        assert rod.get("rhoA", 0.0) == 0.0
        cb, cd = base["centroid"], deck["centroid"]
        A_ = S.point(B, (rod["start"][0] - cb[0], rod["start"][1] - cb[1]))
        B_ = S.point(D, (rod["end"][0] - cd[0], rod["end"][1] - cd[1]))
        els[rod["name"]] = S.chain(rod["name"], A_, B_, rod["start"], rod["end"], float(rod["EI"]),
                                   float(rod["EA"]), int(rod["elements"]), N=-P)
    N = (base["mass"] + deck["mass"]) * g
    cols = {"joints.iso.slide": S.coord("base.u"), "bodies.deck.x": S.coord("deck.u")}
    moments = {}
    for name, ii in els.items():
        moments[name] = np.array([S.output("moment", i, e) for i in ii for e in (0, 1)])
        cols[f"rods.{name}.M_base"] = moments[name][0]
    ref = _friction_reference("base-isolated-frame", path, d, S, "base.u", N, "iso", cols,
                              {"bodies.deck.x": deck["centroid"][0]}, h, overrides)
    # rods' M_max: the largest |M| over the element ends of the rod (femslide's rods.NAME.M_max)
    sol = ref.extra["solution"]
    fmap = S.reduced()[3]
    for name, Mrows in moments.items():
        Rm = Mrows @ fmap
        ref.histories[f"rods.{name}.M_max"] = (lambda t, Rm=Rm: np.abs(Rm @ sol.state(t)[0]).max(axis=0))
        ref.peaks[f"rods.{name}.M_max"] = peak_abs(
            ref.histories[f"rods.{name}.M_max"], 0.0, ref.t_end, 0,
            samples=(ref.extra["grid"], np.abs(Rm @ ref.extra["grid_state"]).max(axis=0)))
    return ref


def base_isolated_frame_nonlinear(file="base-isolated-frame.toml", rtol=1e-12, atol=1e-14, method="DOP853",
                                  log=None, peaks=True, **overrides):
    """The same structure solved without linearisation (validation/nonlinear_frames.py: the bodies'
    exact kinematics, corotational columns of the file's mesh, the normal force from the columns'
    forces on the base).  Returns a :class:`Reference`: histories of the slide, the deck's x and the
    columns' largest |M| over their element ends, the event list, peaks on a 1 ms grid refined
    (``peaks``), ``extra``: frames, run, residual_slide.  ``rtol``, ``atol``, ``method``: the
    integration's (nonlinear_frames.Frames.run); ``overrides``: mu, mu0, scale, t_end."""
    from nonlinear_frames import Body, Column, Frames
    path, d = read(file)
    g = -float(d["gravity"][1])
    bodies = [Body(b["name"], float(b["mass"]), float(b["inertia"]), np.array(b["centroid"], float),
                   locked=(1, 2) if b["name"] == "base" else ()) for b in d["body"]]
    welds = {j["a"]: j["b"] for j in d["joint"] if j["type"] == "weld"}
    cols = [Column(r["name"], welds[f"{r['name']}.start"], welds[f"{r['name']}.end"], np.array(r["start"], float),
                   np.array(r["end"], float), float(r["EI"]), float(r["EA"]), int(r["elements"])) for r in d["rod"]]
    iso = _by_name(d["joint"], "iso")
    o = overrides
    ground = _ground_of(d, os.path.dirname(path))
    if "scale" in o:
        ground.scale = float(o["scale"])
    fr = Frames(bodies, cols, g=g, slider="base", mu=float(o.get("mu", iso["mu"])),
                mu0=float(o.get("mu0", iso.get("mu0", iso["mu"]))), ground=ground)
    t_end = float(o.get("t_end", d["simulate"]["t_end"]))
    run = fr.run(t_end, rtol=rtol, atol=atol, method=method, log=log)
    hist = nonlinear_histories(fr, run)
    pk = {}
    if peaks:
        grid = np.unique(np.concatenate([np.arange(0.0, t_end, 1e-3), [t_end], [t for t, _ in run.events]]))
        pk = {k: peak_abs(f, 0.0, t_end, 0, samples=(grid, f(grid))) for k, f in hist.items()}
    ref = Reference("base-isolated-frame (nonlinear)", path, t_end, hist, pk, np.array([]), float("nan"),
                    {"bodies.deck.x": float(d["body"][[b["name"] for b in d["body"]].index("deck")]["centroid"][0])},
                    events=run.events,
                    extra={"residual_slide": float(hist["joints.iso.slide"]([t_end])[0]), "frames": fr,
                           "run": run})
    return ref


def nonlinear_histories(fr, run, slider="base", deck="deck", joint="iso"):
    """{femslide history column: function of time (vectorised)} of a nonlinear_frames run: the slide
    (the slider body's x from its static place) [m], the deck's x displacement [m] (femslide reports
    the position: add the centroid's x, ``Reference.offsets``), each column's largest |M| over its
    element ends [N m]."""
    ib, idk = 3 * fr.bi[slider], 3 * fr.bi[deck]
    q_s = fr.q_static

    def slide(t):
        return run.state(t)[0][ib] - q_s[ib]

    def deck_x(t):
        return run.state(t)[0][idk] - q_s[idk]

    def mmax(name):
        def f(t):
            return fr.moments_max(run.state(t)[0].T)[name]
        return f
    hist = {f"joints.{joint}.slide": slide, f"bodies.{deck}.x": deck_x}
    for c in fr.columns:
        hist[f"rods.{c.name}.M_max"] = mmax(c.name)
    return hist
