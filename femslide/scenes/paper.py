"""The paper's FE structures and the classic cantilevers as declarations (built-in static scenes).

Each scene is a :class:`~femslide.model.structure.Structure` declared from the scene parameters (SPEC
sections 1 and 3: ground hinges A1 = (0, 0) and B1 = (2a, 0), the body ``deck`` (rectangle 2a x 2b
on top of the rods, centre of mass offset by d), the rods ``left`` and ``right`` flexible or rigid,
the sliding clamp ``clamp`` at the right rod's top), solved by :func:`femslide.analysis.static.solve` with
what the paper's structure needs: the deck rotation as the controlled dof, started from the deformed
spring-hinge mechanism at the spring-hinge rotation (femslide.scenes.predictor), in the model units a and
P = m g; the refinement watches the values of the SPEC section 7 contract.

Results (section 7): ``phi`` = -(deck rotation) (clockwise positive, towards B1), ``slide`` of the
clamp, ``M_max`` the largest |bending moment| in the flexible rods, ``reactions`` A1 and B1 (Fx, Fy:
forces of the ground on the structure); cantilevers: ``tip`` {u, v, theta}.
"""
from __future__ import annotations

import math

from femslide.analysis import static
from femslide.analysis.paths import Control, Path
from femslide.results.outcome import Outcome
from femslide.errors import BadInput, SolverFailure
from femslide.model.structure import Structure
from femslide.results.static import joint_forces
from femslide.scenes import hinge
from femslide.scenes.predictor import mechanism_state

STRUCTURES = ("beam-slider", "beam-fixed", "beam-both", "beam-spring", "beam-extra-mass")
CANTILEVERS = ("cantilever-moment", "cantilever-load")
GUESS_KIND = {"beam-slider": "slider", "beam-fixed": "fixed", "beam-both": "both", "beam-spring": "spring"}


def declare(scene: str, v: dict) -> Structure:
    """The scene's structure in SI units from validated scene parameters ``v``."""
    if scene in CANTILEVERS:
        return _cantilever(scene, v)
    a, b, d, l, m, g = (v[k] for k in ("a", "b", "d", "l", "m", "g"))
    EI, EA = v["EI"], v["EA"]
    left_flex = scene in ("beam-fixed", "beam-both")
    right_flex = scene != "beam-fixed"
    L = (v.get("L") or l) if right_flex else l
    mass = m + v["dm"] if scene == "beam-extra-mass" else m
    s = Structure(gravity=(0.0, -g))
    outline = [(0.0, l), (2 * a, l), (2 * a, l + 2 * b), (0.0, l + 2 * b)]
    # (a rigid left rod AA1 is part of the deck, welded at A, pinned to the ground at A1: pictures
    # draw it as the deck's link from its outline to that joint)
    s.body("deck", mass=mass, centroid=(a + d, l + b), inertia=m * ((2 * a) ** 2 + (2 * b) ** 2) / 12.0,
           outline=outline)
    if left_flex:
        s.rod("left", (0.0, 0.0), (0.0, l), EI=EI, EA=EA)
        s.pin("A1", "left.start", "ground")
        s.weld("A", "left.end", "deck")
    else:
        s.pin("A1", "deck", "ground", at=(0.0, 0.0))
    if right_flex:
        s.rod("right", (2 * a, 0.0), (2 * a, L), EI=EI, EA=EA)
        s.pin("B1", "right.start", "ground")
        k, pre = 0.0, 0.0
        if scene == "beam-spring":
            k = v["k"]
        elif scene == "beam-extra-mass":
            # preloaded so that phi = 0 is the equilibrium at dm = 0: the spring pushes the rod end
            # down the guide with F_el = P (a + d) / (2a) (SPEC section 2, 5.1)
            k, pre = v["k"], -m * g * (a + d) / (2 * a)
        s.slider("clamp", "right.end", "deck", axis=(0.0, 1.0), k=k, preload=pre)
        if scene == "beam-extra-mass" and v["m1"] > 0:
            l2 = v["l2"]
            s.body("piece", mass=v["m1"], centroid=(2 * a, L + 0.5 * l2), inertia=v["m1"] * l2 * l2 / 12.0,
                   outline=[(2 * a, L), (2 * a, L + l2)])
            s.weld("piece_weld", "piece", "right.end")
    else:
        s.body("right", centroid=(2 * a, 0.5 * l), outline=[(2 * a, 0.0), (2 * a, l)])
        s.pin("B1", "right", "ground", at=(2 * a, 0.0))
        s.slider("clamp", "right", "deck", axis=(0.0, 1.0), at=(2 * a, l))
    return s


def _cantilever(scene, v):
    L, EI = v["L"], v["EI"]
    s = Structure(gravity=(0.0, 0.0))
    s.rod("cantilever", (0.0, 0.0), (L, 0.0), EI=EI, EA=v["EA"])
    s.weld("clamp", "cantilever.start", "ground")
    if scene == "cantilever-moment":
        s.force("tip", "cantilever.end", moment=v["m_ratio"] * 2 * math.pi * EI / L)
    else:
        s.force("tip", "cantilever.end", force=(0.0, v["p_ratio"] * EI / L ** 2))
    return s


# -- how the paper's structures are solved -------------------------------------------------------------

def spring_hinge_phi(v, kind):
    """phi [rad] of the equivalent spring-hinge model (start of the path following)."""
    try:
        if kind == "fixed":
            c = 3.0 * v["EI"] / (4.0 * v["l"])
            return abs(hinge.solve_fixed(**{**v, "c": c})["phi"])
        L = v.get("L") or v["l"]
        c = 3.0 * v["EI"] / L
        if kind == "both":
            # both rods bend by about the same angle: two such springs in series (phi 2^(1/3) larger,
            # which the FE solution approaches as EI grows: 1.175 at EI = 1e2, 1.260 at 1e10)
            c *= 0.5
        k = v.get("k", 0.0) if kind == "spring" else 0.0
        return abs(hinge.solve_slider(**{**v, "c": c, "l1": L, "k": k})["phi"])
    except SolverFailure:
        return 0.05


def _start_level(phi_guess):
    """Elements per rod of the first adaptive mesh: more for large rotations, which need fine meshes
    anyway (EI = 1e2 N m^2, phi ~ 1.2 rad: 64 elements), so that no level is spent on coarse meshes
    far from the asymptotic O(h^2) regime."""
    if phi_guess is None or phi_guess < 0.3:
        return static.N_START
    return 4 if phi_guess < 1.0 else 8


def path(scene: str, v: dict) -> static.Path:
    if scene == "cantilever-moment":
        return Path("load", load_steps=max(1, math.ceil(abs(v["m_ratio"]) * 8)))
    if scene == "cantilever-load":
        return Path("load", load_steps=max(1, math.ceil(abs(v["p_ratio"]) / 2)))
    if scene == "beam-extra-mass":
        # the preloaded spring (k > k_crit) makes the vertical state stable: not a mechanism, so
        # plain load stepping from the undeformed state follows the principal branch
        return Path("load")
    kind = GUESS_KIND[scene]
    guess = spring_hinge_phi(v, kind)
    phi_dir = 1.0 if (v["a"] + v["d"]) >= 0 else -1.0
    return Path("control", Control("body", "deck", 2), sign=-phi_dir, guess=guess,
                       start=lambda model, phi: mechanism_state(model, -phi_dir * phi),
                       first_n=_start_level(guess) if kind != "both" else static.N_START)


def watch(scene):
    """The section 7 values whose accuracy decides the refinement (M_max first), computed from the
    level's state without the full set of named results."""
    if scene in CANTILEVERS:
        def w(lv, fs):
            m = lv.model
            tip = m.nodal(lv.y[:m.n_q])[m.node("cantilever", -1)]
            return ([lv.largest_moment(), tip[0] * m.Lref, tip[1] * m.Lref, float(tip[2])],
                    ["moment", "length", "length", "angle"])
        return w

    def w(lv, fs):
        m, y = lv.model, lv.y
        F = m.Fref
        clamp = m.joint["clamp"]
        # the slide alone (Link.slide_value: not its gradient and Hessian)
        s = (clamp.slide_value(y[clamp.dofs]) - m.slide0["clamp"]) * m.Lref
        A = joint_forces(m, y, "A1")
        B = joint_forces(m, y, "B1")
        return ([lv.largest_moment(), -float(y[m.body_dof("deck") + 2]), s,
                 A[0] * F, A[1] * F, B[0] * F, B[1] * F],
                ["moment", "angle", "length", "force", "force", "force", "force"])
    return w


def contract(scene: str, watched) -> dict:
    """The section 7 values from the watched values of a paper scene (see :func:`watch`)."""
    w = [float(x) for x in watched]
    if scene in CANTILEVERS:
        return {"M_max": w[0], "tip": {"u": w[1], "v": w[2], "theta": w[3]}}
    return {"M_max": w[0], "phi": w[1], "slide": w[2],
            "reactions": {"A1": {"Fx": w[3], "Fy": w[4]}, "B1": {"Fx": w[5], "Fy": w[6]}}}


def units(scene: str, v: dict):
    """(Lref, Fref) of the scene: a and P = m g (cantilevers: L and EI/L^2)."""
    if scene in CANTILEVERS:
        return v["L"], v["EI"] / v["L"] ** 2
    return v["a"], v["m"] * v["g"]


def check(scene: str, v: dict):
    if scene == "beam-extra-mass":
        kc = hinge.k_crit(**{**v, "l1": v["L"]})
        if not v["k"] > kc:
            raise BadInput(f"parameter k = {v['k']:g} N/m is not above k_crit = {kc:.6g} N/m: the vertical "
                           f"state is unstable even at dm = 0; allowed: k > {kc:.6g}")


def frozen(scene: str, v: dict, cache=None):
    """The scene's frozen structure.  With a ``cache`` (the cases of a sweep) a paper structure, whose
    rods' EI and EA enter its declaration nowhere else, is declared and frozen once per set of the
    other values and takes each case's EI and EA through Frozen.with_stiffness (the same structure
    as freezing it anew, without checking again what did not change)."""
    if cache is None or scene not in STRUCTURES:
        return declare(scene, v).freeze()
    try:
        key = (scene, tuple(sorted((k, x) for k, x in v.items() if k not in ("EI", "EA") and not k.startswith("_"))))
        hash(key)
    except TypeError:    # a value that is not hashable: no reuse
        return declare(scene, v).freeze()
    base = cache.structure(key, lambda: declare(scene, v).freeze())
    return base.with_stiffness({r.name: (v["EI"], v["EA"]) for r in base.rods})


def solve_scene(scene: str, v: dict, cache=None) -> static.Solution:
    """Solve a built-in FE statics scene from scratch (validated parameters ``v``, SI)."""
    check(scene, v)
    fs = frozen(scene, v, cache)
    Lref, Fref = units(scene, v)
    return static.solve(fs, elements=v.get("n_elements"), watch=watch(scene), path=path(scene, v),
                        Lref=Lref, Fref=Fref, cache=cache)


def run(scene: str, v: dict) -> Outcome:
    """The scene's runner: the section 7 result, with the solution behind it (its VTU carries the
    contract's values of the finest mesh)."""
    sol = solve_scene(scene, v, cache=v.get("_cache"))
    out = {"converged": True, **contract(scene, sol.watched), "iterations": sol.iterations,
           "error_estimate": sol.error_estimate}
    lv = sol.level
    return Outcome(out, scene, solution=sol,
                   static_values=contract(scene, lv.watched(watch(scene))[0]))
