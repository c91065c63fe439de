"""Static equilibrium of a frozen structure on its principal branch, with adaptive mesh refinement.

The answer is the equilibrium reached by ramping all loads together from zero (the principal
branch).  How the path is followed is chosen from the undeformed structure under full load, on the
coarsest mesh (femslide.analysis.paths.choose_path):

- stable there (the reduced tangent, with the initial stresses of the loads, is positive definite on
  the unloaded structure's first-order mechanisms, or there are none): load control, in load steps
  whose predicted increments stay bounded, each checked against its tangent prediction and for
  stability; the steps shrink towards a limit point, where the run exits 1 with its load factor
  (femslide.analysis.paths);
- not stable (a near-mechanism such as the paper's structure, whose undeformed tangent is singular
  in the rigid limit, or a structure that must deform to carry its loads): displacement control of
  the dof that moves most in the softest mode (a body rotation when one takes part), marching in the
  direction in which the loads do work (:func:`femslide.analysis.continuation.principal_branch`); a maximum of the
  load factor before full load is a limit point (exit 1);
- singular with and without the loads' initial stresses: a mechanism (exit 1 naming the free part
  and direction).
The equilibrium reached must be stable: on the coarsest mesh, a negative eigenvalue of the reduced
tangent at full load means the path crossed a bifurcation (exit 1).

Accuracy (femslide.analysis.refine: levels, interpolation between meshes, error estimates): with no
fixed mesh the rods are refined by doubling (2, 4, 8, ... elements per rod, times
each rod's length over the shortest rod's) and the named results are Richardson-extrapolated from the
two finest meshes (the corotational discretisation error is O(h^2)).  Refinement stops when every
watched result is estimated accurate to ``TARGET``; or when the first two meshes already agree to
TARGET/10 (the finer mesh's raw values are reported); or when the level-to-level changes stop
shrinking like h^2 *and* are down at the round-off level of the model (the raw finest values are
reported).  ``error_estimate`` is the estimated relative error of the largest rod moment, and at
least its round-off scatter (Newton reconverged from a slightly perturbed state).  A rod with a
fixed number of elements is not refined; when every rod is fixed the estimate compares the mesh with
one of half as many elements.  Meshes finer than 16 elements per rod start from the
Hermite-interpolated solution of the coarser mesh.

Everything inside is nondimensional: lengths by ``Lref`` (the structure's extent) and forces by
``Fref`` (the total applied load), so that EI/(P L^2) from 1 to 1e12 needs no tuning.
"""
from __future__ import annotations

import math

import numpy as np

from femslide.analysis import redundancy
from femslide.analysis.paths import N_START, Path, check_stable, choose_path, solve_level
from femslide.analysis.refine import (
    Level,
    _extrapolate_all,
    _force_like,
    _force_noise,
    _roundoff_scatter,
    _scale_list,
    _units,
    default_watch,
    prolong,
)
from femslide.errors import BadInput, SolverFailure
from femslide.model.discrete import Model, PatternCache
from femslide.model.frozen import Frozen
from femslide.records import dataclass
from femslide.results.static import unflatten

TARGET = 1e-7     # estimated relative error the adaptive refinement aims for (10x below 1e-6)
N_MAX = 4096
MULT_MAX = 64     # the most elements per level on a long rod for one on the shortest adaptive rod
N_DIRECT = 16     # meshes finer than this start from the interpolated solution of the coarser one
ROUNDOFF_LIMIT = 1e-3  # relative round-off scatter of the largest moment above which a result is refused




def scales(fs: Frozen):
    """(Lref [m], Fref [N]): the structure's extent and its total applied load (sum of magnitudes;
    without loads, EI/L^2 of the stiffest rod)."""
    L = fs.length_scale
    body_w, rod_w = fs.weights()
    F = sum(math.hypot(*w) for w in body_w.values())
    F += sum(math.hypot(*rod_w[r.name]) * r.length for r in fs.rods)
    for ld in fs.loads:
        if ld.type == "distributed":
            F += math.hypot(*ld.force) * fs.rod(ld.on).length
        elif ld.type == "thermal":   # the moment a gradient locks in, the bending force of dT, over L
            r = fs.rod(ld.on)
            EI = r.EI if isinstance(r.EI, float) else r.EI.max
            F += EI * r.alpha * (abs(ld.dT) / L + (abs(ld.dT_gradient) / r.depth if ld.dT_gradient else 0.0)) / L
        else:
            F += math.hypot(*ld.force) + abs(ld.moment) / L
    F += sum(abs(j.preload) for j in fs.joints)
    if F == 0.0:
        EI = [r.EI if isinstance(r.EI, float) else r.EI.max for r in fs.rods]
        F = max(EI, default=1.0) / (L * L)
    return L, F


# the stiffness range in which the solver is verified (validation/STABILITY.md: beyond it round-off of
# the stiff terms outgrows the answers while the estimates do not notice)
KAPPA_MAX = 1e15     # EI / (F L^2): bending stiffness against the loads
EA_RATIO_MAX = 1e14  # EA L^2 / EI (L: the model length unit)
MIN_LENGTH = 1e-3    # a rod's length against the structure's size: a 3 mm rod on a 3 m column solves,
                     # 2 mm reads as a mechanism (its stiffness 1e12 times the column's), 1e-12 m asked for
                     # 1e12 elements


def check_stiffness_range(fs: Frozen, L: float, F: float):
    """Bad input (naming the rod and the field) outside the verified stiffness range."""
    for r in fs.rods:
        if r.length < MIN_LENGTH * L:
            raise BadInput(f"rod {r.name}: length {r.length:g} m is below {MIN_LENGTH:g} of the structure's "
                           f"size {L:g} m; allowed: a rod of at least {MIN_LENGTH * L:g} m (a shorter piece is "
                           f"rigid against the rest beyond double precision: make it part of a body or a joint)")
        EI = max(r.EI.value) if not isinstance(r.EI, float) else r.EI
        EA = max(r.EA.value) if not isinstance(r.EA, float) else r.EA
        EImin = min(r.EI.value) if not isinstance(r.EI, float) else r.EI
        if not math.isfinite(EA):
            raise BadInput(f"rod {r.name}: EA = {EA:g} N is not finite (the default EA is 1e6 m^-2 * EI); give EA")
        if EI / (F * L * L) > KAPPA_MAX:
            raise BadInput(f"rod {r.name}: EI = {EI:g} N m^2 is more than {KAPPA_MAX:g} times the loads' scale "
                           f"F L^2 = {F * L * L:g} N m^2; allowed: EI <= {KAPPA_MAX * F * L * L:g} N m^2 "
                           f"for these loads")
        if EA * L * L / EImin > EA_RATIO_MAX:
            raise BadInput(f"rod {r.name}: EA L^2 / EI = {EA * L * L / EImin:g} exceeds {EA_RATIO_MAX:g} (L = {L:g} m, "
                           f"the structure's size); allowed: EA <= {EA_RATIO_MAX * EImin / (L * L):g} N")


THEORIES = ("nonlinear", "linear")
ARC_FIRST = 8     # elements per shortest rod of the mesh an arc-length path is traced on


def model_class(theory: str):
    """The discrete model of a theory: "nonlinear" (exact, corotational) or "linear" (first order)."""
    if theory == "linear":
        from femslide.model.linear import LinearModel
        return LinearModel
    if theory != "nonlinear":
        raise BadInput(f"theory = {theory!r}; allowed: {', '.join(THEORIES)}")
    return Model


@dataclass
class Solution:
    """A converged static solution.

    ``result``: the named results of SPEC section 8 (SI units), Richardson-extrapolated from the two
    finest meshes when the mesh was refined (``coarse`` is then the second finest level; None when the
    finest mesh's raw values are reported); ``watched``: the watched values, likewise;
    ``error_estimate``: relative, of the largest rod moment (None for a single fixed element);
    ``level``: the finest mesh (``model``, ``y``, ``elements`` (``alpha`` their committed chord
    rotations), ``arrays``: its raw per-rod arrays);
    ``path``: how the equilibrium was reached; an arc-length solve also has the ``trace`` of the
    path on the first mesh (femslide.analysis.arclength.Trace) and its refined ``critical`` points
    (femslide.analysis.limits.Critical) with the ``meshes`` they were refined on."""

    error_estimate: float | None
    iterations: int
    level: Level
    coarse: Level | None
    path: Path
    watched: np.ndarray
    raw_values: bool = False
    _result: dict | None = None
    notes: list = None      # what the user must know about its accuracy (an output at its round-off floor)
    trace: object = None
    critical: list | None = None
    lifted: list | None = None   # unilateral contacts released (they would pull; femslide.analysis.contacts)

    @property
    def model(self):
        return self.level.model

    @property
    def result(self) -> dict:
        if self._result is None:
            fs = self.model.structure
            if self.coarse is None:
                self._result = self.level.res
            else:
                self._result = unflatten(self.level.res, _extrapolate_all(self.coarse, self.level, fs), fs)
        return self._result


class Meshes:
    """The meshes of a solve: ``meshes(n)`` is the model with n elements per (shortest adaptive) rod
    - each rod n times its length over the shortest adaptive rod's, a rod with its own ``elements``
    (or every rod, given ``elements``) fixed - in the solve's theory, units and load factors."""

    def __init__(self, fs, elements, theory, Lref, Fref, cache, factors):
        self.fs, self.Lref, self.Fref, self.cache, self.factors = fs, Lref, Fref, cache, factors
        self.make = model_class(theory)
        rods = fs.rods
        self.uniform = elements is not None
        self.fixed = {} if self.uniform else {r.name: r.elements for r in rods if r.elements}
        adaptive = [r for r in rods if r.name not in self.fixed]
        self.adaptive = bool(adaptive) and not self.uniform
        self.n_fixed = elements
        hmin = min((r.length for r in adaptive), default=1.0)
        # elements of about one length on every rod, up to MULT_MAX times as many on a long rod as on the
        # shortest (a rod 1e-12 of the others' length would otherwise ask for 1e12 elements per level)
        self.mult = {r.name: (1 if self.uniform else min(MULT_MAX, max(1, round(r.length / hmin))))
                     for r in adaptive}
        self.first = elements if self.uniform else (N_START if adaptive else 1)

    def counts(self, n):
        return {r.name: self.fixed.get(r.name) or n * self.mult[r.name] for r in self.fs.rods}

    def __call__(self, n, counts=None):
        return self.make(self.fs, counts or self.counts(n), self.Lref, self.Fref, self.cache, factors=self.factors)


def solve(fs: Frozen, elements: int | None = None, watch=None, path: Path | None = None,
          Lref=None, Fref=None, cache: PatternCache | None = None, target=TARGET, factors: dict | None = None,
          theory: str = "nonlinear") -> Solution:
    """Principal equilibrium of a frozen structure with adaptive refinement (module docstring).

    ``elements``: a fixed number of elements for every rod (overrides the rods' own); ``watch``:
    ``watch(level, structure) -> (values, kinds)``, the results whose accuracy decides the
    refinement (first: the moment the error estimate is about; default: every named result);
    ``path``: how to reach the equilibrium (default: :func:`choose_path` on the coarsest mesh;
    ``Path("arc-length")``: arc-length continuation through limit points, femslide.analysis.arclength);
    ``Lref``, ``Fref``: the model units (default: :func:`scales`); ``cache``: patterns shared with
    other solves of the same topology (a sweep); ``factors``: {load case: factor} (a combination;
    None: every load as declared); ``theory``: "nonlinear" (exact large rotations) or "linear"
    (first order, femslide.model.linear).

    A principal branch that ends before full load fails (SolverFailure) naming its first critical
    point - a limit point located on the refined meshes (femslide.analysis.limits) or a
    bifurcation - and its load factor.

    A structure with unilateral contacts (sliders, rollers with ``unilateral``): a contact that would
    pull is released (femslide.analysis.contacts; the solution's ``lifted`` names them).
    """
    if any(j.unilateral for j in fs.joints):
        from femslide.analysis.contacts import with_contacts
        return with_contacts(fs, lambda f: _solve_set(f, elements, watch, path, Lref, Fref, cache, target, factors,
                                                      theory))
    return _solve_set(fs, elements, watch, path, Lref, Fref, cache, target, factors, theory)


def _solve_set(fs, elements, watch, path, Lref, Fref, cache, target, factors, theory):
    """:func:`solve` with the contacts' states as the structure says."""
    if Lref is None or Fref is None:
        L0, F0 = scales(fs)
        Lref, Fref = Lref or L0, Fref or F0
    check_stiffness_range(fs, Lref, Fref)
    cache = cache or PatternCache()
    meshes = Meshes(fs, elements, theory, Lref, Fref, cache, factors)
    if theory == "linear":
        path = Path("linear")
    elif path is not None and path.kind == "arc-length":
        # its own trace, on a first mesh fine enough for the reported path (8 elements per rod)
        path = Path("arc-length", first_n=ARC_FIRST)
    try:
        sol = _solve(fs, meshes, watch or default_watch, path, target, theory)
    except SolverFailure as exc:
        if theory == "linear" or not getattr(exc, "critical", False):
            raise
        from femslide.analysis.limits import explain
        raise explain(meshes, exc) from None
    if sol.path.kind == "arc-length":
        from femslide.analysis.limits import limit_points
        sol.trace = sol.path.trace
        sol.critical = limit_points(meshes, sol.trace)
    return sol


def _solve(fs, meshes, watch, path, target, theory) -> Solution:
    """:func:`solve` on the meshes of ``meshes`` (the refinement itself)."""
    Lref, Fref, cache, factors = meshes.Lref, meshes.Fref, meshes.cache, meshes.factors
    make = meshes.make
    rods = fs.rods
    uniform = meshes.uniform
    fixed = meshes.fixed
    adaptive = [r for r in rods if r.name not in fixed]
    counts = meshes.counts
    elements = meshes.n_fixed
    cache_lv: dict[int, Level] = {}
    its = [0]
    state = {"path": path}

    def level(n: int) -> Level:
        """The solution with n elements per (shortest adaptive) rod; meshes finer than N_DIRECT, or
        whose coarser mesh is solved already, start from the interpolated coarser solution."""
        if n in cache_lv:
            return cache_lv[n]
        start = None
        c = level((n + 1) // 2) if adaptive and n > 1 and (n > N_DIRECT or (n + 1) // 2 in cache_lv) else None
        model = make(fs, counts(n), Lref, Fref, cache, factors=factors)
        if c is not None:
            start = prolong(c.model, c.y, c.elements, model)
        if state["path"] is None:
            # on the coarsest mesh: the mechanisms and the loads' work on them do not depend on the
            # mesh, and a fine mesh of a stiff rod (EA L^2/EI ~ 1e9, 64 elements) spreads the
            # tangent's eigenvalues beyond what the round-off test for a null space can separate
            cn = {r.name: min(int(c), N_START) for r, c in zip(rods, counts(n).values())}
            coarse = model if cn == counts(n) else make(fs, cn, Lref, Fref, cache, factors=factors)
            redundancy.check(coarse)
            state["path"] = choose_path(coarse)
        y, es, k = solve_level(model, state["path"], start)
        tr = state["path"].trace
        if tr is not None and getattr(tr, "n", None) is None:
            tr.n = n   # the mesh the path was traced on
        if not cache_lv and state["path"].kind not in ("linear", "arc-length"):
            check_stable(model, y, es)
        its[0] += k
        cache_lv[n] = lv = Level(n, model, y, es)
        # meshes coarser than the next coarser one are used up (started this one): drop them, so that
        # a fine solve holds two levels, not the whole hierarchy
        for k in [k for k in cache_lv if k < (n + 1) // 2]:
            del cache_lv[k]
        return lv

    def fixed_counts(d):
        return {r.name: max(1, fixed[r.name] // d) for r in rods}

    def fixed_level(d: int) -> Level:
        """The solution on the fixed meshes with every rod's count divided by d; finer than N_DIRECT
        elements on some rod: started from the interpolated solution of the meshes divided by 2 d."""
        key = ("fixed", d)
        if key in cache_lv:
            return cache_lv[key]
        cn = fixed_counts(d)
        c = None
        dc = 2 * d if d == 1 else 4 * d     # the half meshes (the error estimate's), then quarters
        if max(cn.values(), default=0) > N_DIRECT and fixed_counts(dc) != cn:
            c = fixed_level(dc)
        model = make(fs, cn, Lref, Fref, cache, factors=factors)
        start = prolong(c.model, c.y, c.elements, model) if c is not None else None
        if state["path"] is None:
            cp = {r.name: min(int(k), N_START) for r, k in zip(rods, cn.values())}
            coarse = model if cp == cn else make(fs, cp, Lref, Fref, cache, factors=factors)
            redundancy.check(coarse)
            state["path"] = choose_path(coarse)
        y, es, k = solve_level(model, state["path"], start)
        if not cache_lv:
            check_stable(model, y, es)
        its[0] += k
        cache_lv[key] = lv = Level(d, model, y, es)
        for k in [k for k in cache_lv if k[1] > dc]:   # the coarser levels than the next are used up
            del cache_lv[k]
        return lv

    def values(lv):
        return lv.watched(watch)

    raw_values = False
    notes = []
    if uniform:
        fine = level(elements)
        coarse, err = None, None
        if elements >= 2:
            f1, _ = values(level(elements // 2))
            f2, _ = values(fine)
            ratio = (elements / (elements // 2)) ** 2
            err = abs(f2[0] - f1[0]) / (ratio - 1.0) / max(abs(f2[0]), 1e-300)
    elif not adaptive:
        # a fixed mesh finer than N_DIRECT elements per rod is reached through coarser ones (every rod's
        # count halved), each started from the interpolated coarser solution, as the adaptive levels
        # are: O(10) Newton iterations per mesh instead of a load path on the fine mesh
        fine = fixed_level(1)
        coarse, err = None, (0.0 if not rods else None)
        half = fixed_counts(2)
        if rods and all(fixed[r.name] // 2 >= 1 for r in rods):
            f1, kinds = values(fixed_level(2))
            f2, _ = values(fine)
            r0 = rods[0].name
            ratio = (fixed[r0] / half[r0]) ** 2
            # relative to the largest moment, but not below the round-off level of the element forces:
            # a moment that is zero but for round-off (a rod that takes its free thermal curvature)
            # has no relative error to speak of
            zero = 10.0 * _force_noise(fine) * float(_units(kinds[:1], Lref, Fref)[0])
            change = abs(f2[0] - f1[0])
            err = 0.0 if change <= zero and abs(f2[0]) <= zero else \
                change / (ratio - 1.0) / max(abs(f2[0]), zero, 1e-300)
    else:
        p0 = path.first_n if path is not None else N_START
        n = p0
        ext = []
        prev_raw = None
        history = []     # the extrapolated estimates of every level
        fine = level(n)
        units = None
        while True:
            coarse, fine = fine, level(2 * n)
            f1, kinds = values(coarse)
            f2, _ = values(fine)
            # a handful of values: Python floats (the same IEEE arithmetic as numpy's elementwise, without
            # its per-call cost on tiny arrays); the units and which outputs are force-like once per kinds
            if units is None or kinds != units[0]:
                units = (kinds, _units(kinds, Lref, Fref).tolist(), _force_like(kinds).tolist())
            u, fl = units[1], units[2]
            f1, f2 = f1.tolist(), f2.tolist()
            ext.append([(4.0 * b - a) / 3.0 for a, b in zip(f1, f2)])
            scale = _scale_list([e / x for e, x in zip(ext[-1], u)], kinds)
            change = [abs(b - a) / x for a, b, x in zip(f1, f2, u)]
            raw = [c / sc for c, sc in zip(change, scale)]
            if len(ext) >= 2:
                errs = [abs(a - b) / x / 15.0 / sc for a, b, x, sc in zip(ext[-1], ext[-2], u, scale)]
                err = float(min(errs[0], raw[0] / 3.0))
            else:
                errs = [r / 3.0 * 10.0 for r in raw]  # one level only: no estimate of the extrapolated error yet
                err = float(raw[0] / 3.0)
            # an output is settled when its estimate meets the target, when it does not change, or
            # (forces and moments that are zero but for round-off, e.g. the shear of a rod in pure
            # bending) when its change is within the round-off level of the element forces
            settled = [e <= target or r <= 1e-13 for e, r in zip(errs, raw)]
            small = [not st and f and abs(b) / x < sc for st, f, b, x, sc in zip(settled, fl, f2, u, scale)]
            if any(small):   # below their group's floor
                zero = 10.0 * _force_noise(fine)
                settled = [st or (sm and abs(b) / x <= zero and c <= zero)
                           for st, sm, b, x, c in zip(settled, small, f2, u, change)]
            if (len(ext) >= 2 or all(r <= 1e-13 for r in raw)) and all(settled):
                break
            # the first two meshes already agree to 3e-8: the finer one is accurate to its O(h^2)
            # estimate raw / 3 <= target / 10; reported as it is (not extrapolated)
            if len(ext) == 1 and all(r / 3.0 <= 0.1 * target or st for r, st in zip(raw, settled)):
                raw_values = True
                break
            # the changes must shrink like h^2 (x 1/4); outputs whose changes stop shrinking *at the
            # round-off level* of the stiff model only gain noise from refining: when all unsettled
            # outputs are such, stop and report the finest level's raw values.  (On coarse meshes
            # changes can stall far above round-off: then keep refining.)
            if prev_raw is not None:
                if all(st or r > 0.6 * p for st, r, p in zip(settled, raw, prev_raw)):   # settled or stalled
                    noise = 1e3 * max(_roundoff_scatter(fine), 1e-13)
                    if all(st or r <= noise for st, r in zip(settled, raw)):
                        err = float(max(raw[0], prev_raw[0]))
                        raw_values = True
                        break
            prev_raw = raw
            if len(ext) >= 2:
                history.append(errs)
                floor = _estimate_floor(history, settled, 2 * n)
                if floor is not None and floor[1] <= FLOOR_LIMIT:
                    # the unsettled outputs' extrapolated estimates stopped shrinking, and are small: their
                    # round-off floor (forces that hang on a huge EA between rods, say); refining further
                    # only adds noise.  (Larger stalled estimates are not yet asymptotic: refine on.)
                    k, est = floor
                    name = _output_name(watch, fine, fs, k)
                    notes.append(f"{name} is determined only to about {est:.1g} (relative; the target "
                                 f"{target:g} is met by the other results): its estimate stopped shrinking at "
                                 f"{2 * n} elements per rod, the round-off floor of the stiff terms")
                    break
            if 2 * n >= N_MAX:
                k = int(np.argmax(np.where(settled, 0.0, errs)))
                name = _output_name(watch, fine, fs, k)
                raise SolverFailure(f"the mesh refinement reached {2 * n} elements per rod without meeting "
                                    f"the error target {target:g}: {name} is estimated accurate to "
                                    f"{float(errs[k]):.3g}; fix a mesh with `elements` to accept a coarser answer")
            n *= 2
        if raw_values:
            coarse = None
    if err is not None:
        scatter = _roundoff_scatter(fine)
        err = max(err, scatter)
        if scatter > ROUNDOFF_LIMIT:
            n_el = fine.model.elements.size if fine.model.elements is not None else 0
            raise SolverFailure(f"round-off dominates the answer: the largest rod moment of the {n_el}-element "
                                f"mesh is determined only to {scatter:.2g} (relative) by the stiff axial terms "
                                f"(EA/EI of the rods, element length); use fewer elements (or the adaptive default)")
    watched = values(fine)[0] if coarse is None else (4.0 * values(fine)[0] - values(coarse)[0]) / 3.0
    return Solution(err, its[0], fine, coarse, state["path"], watched, raw_values, notes=notes)


FLOOR_LIMIT = 1e-4   # a stalled estimate below this is a round-off floor (reported); above, refinement goes on
FLOOR_FROM = 64      # elements per rod from which a stalled estimate counts as a round-off floor


def _estimate_floor(history, settled, n):
    """``history``: the estimates (arrays or lists) of every level; ``settled``: the outputs settled now
    (booleans).  (output, estimate) when every unsettled output's extrapolated error estimate has stopped
    shrinking - neither of the last two levels brought it below half its value of the level before
    them - on meshes of at least FLOOR_FROM elements per rod; else None.  (A discretisation error
    shrinks by 4 to 16 a level; round-off does not.)"""
    if n < FLOOR_FROM or len(history) < 3 or all(settled):
        return None
    H, settled = np.array(history), np.asarray(settled)
    before = H[-3]
    stuck = (H[-1] > 0.5 * before) & (H[-2] > 0.5 * before)
    if not np.all(settled | stuck):
        return None
    # at the floor the extrapolated values scatter by the change itself, not by 1/15 of it (the factor
    # of an h^4 convergence): the estimate is the scatter
    est = np.where(settled, 0.0, 15.0 * np.maximum(H[-1], H[-2]))
    k = int(np.argmax(est))
    return k, float(est[k])


def _output_name(watch, level, fs, k):
    """The dotted name of watched output k (default watch), else 'watched result k'."""
    from femslide.analysis.refine import default_watch
    if watch is default_watch:
        from femslide.results.static import flatten_names
        names = flatten_names(level.res, fs)
        if k < len(names):
            return names[k]
    return f"watched result {k}"
