"""The frozen structure: a declaration checked as a whole, immutable, every name resolved.

:meth:`Frozen.from_structure` (called by ``Structure.freeze()``) checks every field, resolves the
parts a joint or load names (``ROD.start``, ``ROD.end``, a body, ``"ground"``) to :class:`PointRef`,
fills in defaults (joint points, body centroids and inertias from their outlines) and checks that
every part is connected to the ground.  The solvers take only frozen structures; data derived by a
solver (its plan in model units) is cached in ``derived``.
"""
from __future__ import annotations

import math

from femslide.errors import BadInput
from femslide.joints.kinds import kind_of, listed
from femslide.model.parts import (
    DEAD,
    EA_PER_EI,
    GROUND,
    LOAD_TYPES,
    MAX_ELEMENTS,
    Body,
    Combination,
    Joint,
    Load,
    Rod,
    Table,
    _num,
    _stiffness,
    _vec,
    polygon_area_centroid_inertia,
)
from femslide.records import dataclass, field, replace


@dataclass(frozen=True)
class PointRef:
    """A joint or load point resolved: the part (``kind`` "rod_end", "body" or "ground"), its name
    and, for a rod end, which end (0 start, -1 end)."""

    kind: str
    name: str
    end: int = 0


@dataclass(frozen=True)
class Frozen:
    """A checked, immutable structure (SI units).  Built by :meth:`Structure.freeze`."""

    gravity: tuple
    rods: tuple
    bodies: tuple
    joints: tuple
    loads: tuple
    refs: dict = field(default_factory=dict)   # joint/load name -> (PointRef a, PointRef b or None)
    combinations: tuple = ()                   # Combination records, factors checked
    steps: tuple = ()                          # the load history's states ([[step]]), as Combination records
    derived: dict = field(default_factory=dict, compare=False, repr=False)  # data derived by solvers

    # -- lookup -------------------------------------------------------------------------------------
    def rod(self, name) -> Rod:
        return next(r for r in self.rods if r.name == name)

    def body(self, name) -> Body:
        return next(b for b in self.bodies if b.name == name)

    def point(self, ref: PointRef):
        """Reference position [m] of a rod end or a body's centroid."""
        if ref.kind == "rod_end":
            r = self.rod(ref.name)
            return r.start if ref.end == 0 else r.end
        if ref.kind == "body":
            return self.body(ref.name).centroid
        return None

    @property
    def length_scale(self) -> float:
        """Largest extent of the reference geometry [m] (the solver's length unit)."""
        pts = [p for r in self.rods for p in (r.start, r.end)]
        pts += [b.centroid for b in self.bodies]
        pts += [p for b in self.bodies for p in (b.outline or ())]
        pts += [j.at for j in self.joints if j.at is not None]
        xs, ys = [p[0] for p in pts], [p[1] for p in pts]
        ext = max(max(xs) - min(xs), max(ys) - min(ys)) if pts else 1.0
        return ext if ext > 0 else max((r.length for r in self.rods), default=1.0)

    @property
    def cases(self) -> tuple:
        """The load cases: "dead" (gravity's) first, then those of the loads in declaration order."""
        out = [DEAD]
        for ld in self.loads:
            if ld.case not in out:
                out.append(ld.case)
        return tuple(out)

    def weights(self):
        """Gravity force [N] of each body (x, y) and per unit length of each rod."""
        gx, gy = self.gravity
        return ({b.name: (b.mass * gx, b.mass * gy) for b in self.bodies},
                {r.name: (r.rhoA * gx, r.rhoA * gy) for r in self.rods})

    def with_stiffness(self, stiffness: dict) -> "Frozen":
        """The same structure with rods' stiffnesses replaced: ``stiffness`` {rod: (EI, EA)} [N m^2, N],
        each a positive number or a table {s, value} as a declaration gives them (EA None: EA_PER_EI
        times EI), checked as :meth:`from_structure` checks them.  Everything else, checked already,
        is shared: a sweep over the rods' stiffness freezes its structure once.  The solvers' data
        derived from this structure that does not depend on the stiffness is derived again from this
        one's (``derived["stiffness_of"]``: femslide.model.discrete keeps its plans' geometry, loads and
        joints and rescales only the rods' stiffness)."""
        unknown = set(stiffness) - {r.name for r in self.rods}
        if unknown:
            raise BadInput(f"rod {sorted(unknown)[0]}: no such rod; allowed: {', '.join(r.name for r in self.rods)}")
        rods = []
        for r in self.rods:
            if r.name in stiffness:
                EI, EA = stiffness[r.name]
                EI, EA = _section(f"rod {r.name}", replace(r, EI=EI, EA=EA), r.length)
                r = replace(r, EI=EI, EA=EA)
            rods.append(r)
        return replace(self, rods=tuple(rods), derived={"stiffness_of": self})

    # -- checking -----------------------------------------------------------------------------------
    @staticmethod
    def from_structure(s) -> "Frozen":
        """Check a :class:`femslide.model.structure.Structure` ``s`` and freeze it."""
        gravity = _vec("gravity", s.gravity)
        rods = []
        for r in s.rods.values():
            w = f"rod {r.name}"
            start, end = _vec(f"{w}: start", r.start), _vec(f"{w}: end", r.end)
            L = math.hypot(end[0] - start[0], end[1] - start[1])
            if not L > 0:
                raise BadInput(f"{w}: start and end coincide; a rod needs a positive length")
            EI, EA = _section(w, r, L)
            rhoA = _num(f"{w}: rhoA", r.rhoA, 0.0)
            n = r.elements
            if n is not None:
                if isinstance(n, bool) or not isinstance(n, (int, float)) or n != int(n) or not 1 <= n <= MAX_ELEMENTS:
                    raise BadInput(f"{w}: elements = {n!r}; allowed: an integer in [1, {MAX_ELEMENTS}] "
                                   f"(or absent: adaptive)")
                n = int(n)
            alpha = _num(f"{w}: alpha", getattr(r, "alpha", 0.0), 0.0, allowed="a number >= 0 [1/K]")
            depth = getattr(r, "depth", None)
            if depth is not None:
                depth = _num(f"{w}: depth", depth, 0.0, lo_open=True, allowed="a positive number [m]")
            rods.append(Rod(r.name, start, end, EI, EA, rhoA, n, alpha=alpha, depth=depth))
        # (the frozen rod keeps EI and EA only: E, I, A are folded into them)
        rodnames = {r.name for r in rods}
        bodies = []
        for b in s.bodies.values():
            w = f"body {b.name}"
            mass = _num(f"{w}: mass", b.mass, 0.0)
            outline = None
            area = 0.0
            c_out = None
            J_out = 0.0
            if b.outline is not None:
                try:
                    outline = tuple(_vec(f"{w}: outline point", p) for p in b.outline)
                except TypeError:
                    raise BadInput(f"{w}: outline must be a list of [x, y] points") from None
                if len(outline) < 2:
                    raise BadInput(f"{w}: outline needs at least 2 points")
                area, c_out, J_out = polygon_area_centroid_inertia(outline)
            if b.centroid is not None:
                centroid = _vec(f"{w}: centroid", b.centroid)
            elif c_out is not None:
                centroid = c_out
            elif outline is not None:
                centroid = (sum(p[0] for p in outline) / len(outline), sum(p[1] for p in outline) / len(outline))
            else:
                centroid = None  # placed at its first joint point below
            if b.inertia is not None:
                inertia = _num(f"{w}: inertia", b.inertia, 0.0)
            else:
                inertia = mass * J_out / area if area > 0 else 0.0
            bodies.append(Body(b.name, mass, centroid, inertia, outline))
        bodynames = {b.name for b in bodies}

        def resolve(what, text, allow_ground, allow_rod=False):
            if not isinstance(text, str):
                raise BadInput(f"{what} = {text!r}: expected a name")
            if text == GROUND:
                if allow_ground:
                    return PointRef("ground", GROUND)
                raise BadInput(f"{what} = {GROUND!r}: only b may be the ground")
            if text in bodynames:
                return PointRef("body", text)
            name, _, end = text.partition(".")
            if name in rodnames and end in ("start", "end"):
                return PointRef("rod_end", name, 0 if end == "start" else -1)
            if allow_rod and text in rodnames:
                return PointRef("rod", text)
            if name in rodnames:
                raise BadInput(f"{what} = {text!r}: a rod end is ROD.start or ROD.end")
            parts = sorted(rodnames | bodynames)
            raise BadInput(f"{what} = {text!r} names no body or rod end; parts: {', '.join(parts) or 'none'}")

        refs = {}
        # bodies without a centroid sit at their first joint point
        joints_in = list(s.joints.values())
        kinds = {}
        for j in joints_in:
            w = f"joint {j.name}"
            kinds[j.name] = kind_of(j.type, w)
            ra = resolve(f"{w}: a", j.a, allow_ground=False)
            rb = resolve(f"{w}: b", j.b, allow_ground=True)
            if ra == rb or (ra.kind == rb.kind == "body" and ra.name == rb.name):
                raise BadInput(f"{w}: a and b are the same part ({j.a})")
            refs[j.name] = (ra, rb)
        for i, b in enumerate(bodies):
            if b.centroid is None:
                for j in joints_in:
                    ra, rb = refs[j.name]
                    if b.name in (ra.name, rb.name) and j.at is not None:
                        bodies[i] = replace(b, centroid=_vec(f"joint {j.name}: at", j.at))
                        break
                else:
                    raise BadInput(f"body {b.name}: give its centroid (or an outline, or a joint with `at`)")
        frozen_b = {b.name: b for b in bodies}
        frozen_r = {r.name: r for r in rods}

        def pos(ref):
            if ref.kind == "rod_end":
                r = frozen_r[ref.name]
                return r.start if ref.end == 0 else r.end
            if ref.kind == "body":
                return frozen_b[ref.name].centroid
            return None

        def accepting(what):
            return listed(lambda k: what in k.accepts, plural=True)

        # the optional fields each kind takes (a kind with a guide needs its axis; a rod end a may
        # start anywhere on the guide line, every other rod end sits at the joint point)
        joints = []
        for j in joints_in:
            w = f"joint {j.name}"
            ra, rb = refs[j.name]
            kind = kinds[j.name]
            if j.at is not None:
                at = _vec(f"{w}: at", j.at)
            elif ra.kind == "rod_end":
                at = pos(ra)
            elif rb.kind == "rod_end":
                at = pos(rb)
            else:
                raise BadInput(f"{w}: give the joint point `at` (neither a nor b is a rod end)")
            scale = max(1.0, max(abs(v) for v in at))
            for ref, side in ((ra, "a"), (rb, "b")):
                if ref.kind == "rod_end" and math.dist(pos(ref), at) > 1e-9 * scale \
                        and (side == "b" or not kind.guide):
                    raise BadInput(f"{w}: at = {list(at)} is not the position of the rod end {side} = "
                                   f"{getattr(j, side)!r} {list(pos(ref))}")
            axis = None
            if kind.guide:
                if j.axis is None:
                    raise BadInput(f"{w}: a {j.type} needs its guide direction `axis`")
                axis = _vec(f"{w}: axis", j.axis, nonzero=True)
                na = math.hypot(*axis)
                axis = (axis[0] / na, axis[1] / na)
                if ra.kind == "rod_end":
                    pa = pos(ra)
                    off = (pa[0] - at[0]) * -axis[1] + (pa[1] - at[1]) * axis[0]
                    if abs(off) > 1e-9 * scale:
                        raise BadInput(f"{w}: the rod end {j.a} is {off:g} m off the guide line through at "
                                       f"along axis; it must start on the line")
            elif j.axis is not None:
                raise BadInput(f"{w}: axis is for {accepting('axis')}, not a {j.type}")
            c = _num(f"{w}: c", j.c, 0.0)
            if c and "c" not in kind.accepts:
                raise BadInput(f"{w}: a rotational spring c is for {accepting('c')}, not a {j.type}")
            k = _num(f"{w}: k", j.k, 0.0)
            pre = _num(f"{w}: preload", j.preload)
            if (k or pre) and "k" not in kind.accepts:
                raise BadInput(f"{w}: k and preload are for {accepting('k')}, not a {j.type}")
            mu = mu0 = bearing = None
            if j.mu is not None or j.mu0 is not None:
                if "mu" not in kind.accepts:
                    raise BadInput(f"{w}: friction (mu, mu0) is for {accepting('mu')}, not a {j.type}")
                mu = _num(f"{w}: mu", 0.0 if j.mu is None else j.mu, 0.0)
                mu0 = mu if j.mu0 is None else _num(f"{w}: mu0", j.mu0, 0.0)
                if mu0 < mu:
                    raise BadInput(f"{w}: mu0 = {mu0:g} < mu = {mu:g}; allowed: mu0 >= mu (static >= kinetic)")
            if j.bearing is not None:
                if "bearing" not in kind.accepts:
                    raise BadInput(f"{w}: bearing is for {accepting('bearing')}")
                bearing = _num(f"{w}: bearing", j.bearing, 0.0, lo_open=True)
            unilateral, restitution = _contact(w, j, kind, accepting)
            springs = _support_springs(w, j, kind, rb, axis, mu is not None)
            disp = rot = None
            if j.displacement is not None or j.rotation is not None:
                if rb.kind != "ground":
                    raise BadInput(f"{w}: displacement and rotation move a support: they need b = \"ground\"")
                if any(v is not None for v in springs):
                    raise BadInput(f"{w}: a prescribed support motion needs rigid constraints; drop kx, ky, kr")
                if j.displacement is not None:
                    disp = _vec(f"{w}: displacement", j.displacement)
                if j.rotation is not None:
                    if "kr" not in kind.springs:
                        raise BadInput(f"{w}: rotation is for a joint that holds the rotation (weld, slider), "
                                       f"not a {j.type}")
                    rot = _num(f"{w}: rotation", j.rotation, -math.pi, math.pi,
                               allowed="a rotation in [-pi, pi] rad")
            if unilateral and any(v is not None for v in springs):
                raise BadInput(f"{w}: a unilateral contact is rigid across its guide; drop kx, ky, kr")
            joints.append(Joint(j.name, j.type, j.a, j.b, at, axis, c, k, pre, mu, mu0, bearing, *springs,
                                displacement=disp, rotation=rot, unilateral=unilateral, restitution=restitution,
                                lifted=bool(j.lifted) and unilateral))

        loads = []
        for ld in s.loads.values():
            w = f"load {ld.name}"
            if ld.type not in LOAD_TYPES:
                raise BadInput(f"{w}: type {ld.type!r}; allowed: {', '.join(LOAD_TYPES)}")
            F = _vec(f"{w}: force", ld.force)
            if ld.type == "distributed":
                ref = resolve(f"{w}: on", ld.on, allow_ground=False, allow_rod=True)
                if ref.kind != "rod":
                    raise BadInput(f"{w}: a distributed load acts on a rod; on = {ld.on!r} is not a rod")
                if ld.moment or ld.at is not None or ld.s is not None:
                    raise BadInput(f"{w}: a distributed load has no moment, at or s")
                Fe = None if ld.force_end is None else _vec(f"{w}: force_end", ld.force_end)
                if ld.frame not in ("global", "rod"):
                    raise BadInput(f"{w}: frame = {ld.frame!r}; allowed: \"global\" (x, y components) or \"rod\" "
                                   f"(along the rod's tangent and normal)")
                loads.append(Load(ld.name, ld.type, ld.on, F, case=_case(w, ld.case), force_end=Fe, frame=ld.frame))
                refs[ld.name] = (ref, None)
                continue
            if ld.type == "thermal":
                ref = resolve(f"{w}: on", ld.on, allow_ground=False, allow_rod=True)
                if ref.kind != "rod":
                    raise BadInput(f"{w}: a thermal load acts on a rod; on = {ld.on!r} is not a rod")
                if ld.moment or ld.at is not None or tuple(ld.force) != (0.0, 0.0):
                    raise BadInput(f"{w}: a thermal load has only on, dT, dT_gradient and case")
                dT = _num(f"{w}: dT", ld.dT, allowed="a finite temperature change [K]")
                dTg = _num(f"{w}: dT_gradient", ld.dT_gradient, allowed="a finite temperature difference [K]")
                rod = next(r for r in rods if r.name == ref.name)
                if rod.alpha == 0.0 and (dT or dTg):
                    raise BadInput(f"{w}: rod {rod.name} has no thermal expansion coefficient; give the rod's "
                                   f"alpha [1/K] (a number > 0)")
                if dTg and rod.depth is None:
                    raise BadInput(f"{w}: dT_gradient needs the depth of rod {rod.name}; give the rod's depth [m] "
                                   f"(a positive number)")
                loads.append(Load(ld.name, ld.type, ld.on, case=_case(w, ld.case), dT=dT, dT_gradient=dTg))
                refs[ld.name] = (ref, None)
                continue
            if ld.force_end is not None or ld.frame != "global":
                raise BadInput(f"{w}: force_end and frame are for a distributed load, not a {ld.type} load")
            ref = resolve(f"{w}: on", ld.on, allow_ground=False, allow_rod=True)
            M = _num(f"{w}: moment", ld.moment)
            if ld.s is not None:
                if ref.kind != "rod":
                    raise BadInput(f"{w}: s places a force inside a rod; on = {ld.on!r} must name the rod")
                if ld.at is not None:
                    raise BadInput(f"{w}: give s (the arc length on the rod) or at, not both")
                rod = next(r for r in rods if r.name == ref.name)
                sv = _num(f"{w}: s", ld.s, 0.0, rod.length, allowed=f"an arc length in [0, {rod.length:g}] m "
                                                                      f"(the length of rod {rod.name})")
                if sv == 0.0 or sv == rod.length:   # at a rod end: the end's own load
                    ref = PointRef("rod_end", rod.name, 0 if sv == 0.0 else -1)
                    loads.append(Load(ld.name, ld.type, f"{rod.name}.{'start' if sv == 0.0 else 'end'}", F, M,
                                      pos(ref), _case(w, ld.case)))
                else:
                    loads.append(Load(ld.name, ld.type, ld.on, F, M, None, _case(w, ld.case), s=sv))
                refs[ld.name] = (ref, None)
                continue
            if ref.kind == "rod":
                raise BadInput(f"{w}: on = {ld.on!r} is a rod: give the arc length s of the point on it "
                               f"(or on = \"{ld.on}.start\" / \"{ld.on}.end\")")
            at = None
            if ld.at is not None:
                at = _vec(f"{w}: at", ld.at)
                if ref.kind == "rod_end" and math.dist(at, pos(ref)) > 1e-9 * max(1.0, *map(abs, at)):
                    raise BadInput(f"{w}: at = {list(at)} is not the position of the rod end {ld.on}")
            if at is None:
                at = pos(ref)
            loads.append(Load(ld.name, ld.type, ld.on, F, M, at, _case(w, ld.case)))
            refs[ld.name] = (ref, None)

        if not rods and not bodies:
            raise BadInput("the structure declares no rods and no bodies; allowed: at least one rod or "
                           "body, connected to the ground by a joint")
        cases = {DEAD} | {ld.case for ld in loads}
        combos = []
        for cb in getattr(s, "combinations", {}).values():
            w = f"combination {cb.name}"
            factors = []
            for case, f in cb.factors:
                if case not in cases:
                    raise BadInput(f"{w}: factors name the load case {case!r}, which no load has; cases: "
                                   f"{', '.join(sorted(cases))} (gravity is case {DEAD!r})")
                factors.append((case, _num(f"{w}: factor of {case}", f)))
            if not factors:
                raise BadInput(f"{w}: factors is empty; allowed: a table {{case = factor, ...}} naming at least "
                               f"one case")
            combos.append(Combination(cb.name, tuple(factors)))
        steps = []
        for i, st in enumerate(getattr(s, "steps", [])):
            w = f"step {st.name or i + 1}"
            factors = []
            for case, f in st.factors:
                if case not in cases:
                    raise BadInput(f"{w}: factors name the load case {case!r}, which no load has; cases: "
                                   f"{', '.join(sorted(cases))} (gravity is case {DEAD!r})")
                factors.append((case, _num(f"{w}: factor of {case}", f)))
            steps.append(Combination(st.name or f"step{i + 1}", tuple(factors)))
        if steps and combos:
            raise BadInput("a structure declares either [[step]] (a load history) or [[combination]] (separate "
                           "equilibria), not both")
        names = [st.name for st in steps]
        if len(set(names)) != len(names):
            raise BadInput(f"[[step]]: the name {next(n for n in names if names.count(n) > 1)!r} is used twice")

        fr = Frozen(gravity, tuple(rods), tuple(bodies), tuple(joints), tuple(loads), refs, tuple(combos),
                    tuple(steps))
        fr._check_connected()
        return fr

    def _check_connected(self):
        """Every part must be connected to the ground through joints (or it is bad input)."""
        parent = {}

        def find(x):
            while parent.setdefault(x, x) != x:
                x = parent[x]
            return x

        for j in self.joints:
            ra, rb = self.refs[j.name]
            parent[find(ra.name)] = find(rb.name)
        loose = [p.name for p in (*self.rods, *self.bodies) if find(p.name) != find(GROUND)]
        if loose:
            what = ", ".join(loose)
            raise BadInput(f"part(s) {what} not connected to the ground by any chain of joints; "
                           f"add a joint with b = \"ground\" (a support) or to a supported part")


def _case(what, case):
    """A load case name: a non-empty string."""
    if not isinstance(case, str) or not case.strip():
        raise BadInput(f"{what}: case = {case!r}; allowed: a non-empty name (default {DEAD!r})")
    return case


def _section(w, r, L):
    """(EI, EA) of a declared rod: given, or from its section E, I, A (EI = E I, EA = E A)."""
    section = (r.E, r.I, r.A)
    if any(v is not None for v in section):
        if r.EI is not None or (r.EA is not None and r.A is not None):
            raise BadInput(f"{w}: give EI (and EA) or the section E, I (and A), not both")
        if r.E is None or r.I is None:
            raise BadInput(f"{w}: a section needs E [Pa] and I [m^4] (and optionally A [m^2]); missing "
                           f"{'E' if r.E is None else 'I'}")
        E = _num(f"{w}: E", r.E, 0.0, lo_open=True, allowed="a positive number [Pa]")
        EI = E * _num(f"{w}: I", r.I, 0.0, lo_open=True, allowed="a positive number [m^4]")
        if r.A is not None:
            EA = E * _num(f"{w}: A", r.A, 0.0, lo_open=True, allowed="a positive number [m^2]")
        elif r.EA is not None:
            EA = _stiffness(f"{w}: EA", r.EA, L)
        else:
            EA = EA_PER_EI * EI
        return EI, EA
    if r.EI is None:
        raise BadInput(f"{w}: missing EI [N m^2] (or the section E, I, A)")
    EI = _stiffness(f"{w}: EI", r.EI, L)
    if r.EA is None:
        EA = EI.scaled(EA_PER_EI) if isinstance(EI, Table) else EA_PER_EI * EI
    else:
        EA = _stiffness(f"{w}: EA", r.EA, L)
    return EI, EA


def _contact(w, j, kind, accepting):
    """(unilateral, restitution) of joint j checked: ``unilateral`` true or false (a contact, SPEC
    9.4), ``restitution`` a number in [0, 1] and only with unilateral (default 0: a plastic landing)."""
    uni = j.unilateral
    if uni is None:
        uni = False
    if not isinstance(uni, bool):
        raise BadInput(f"{w}: unilateral = {uni!r}; allowed: true or false")
    if uni and "unilateral" not in kind.accepts:
        raise BadInput(f"{w}: unilateral is for {accepting('unilateral')}, not a {j.type}")
    e = None
    if j.restitution is not None:
        if not uni:
            raise BadInput(f"{w}: restitution is for a unilateral contact; add unilateral = true")
        e = _num(f"{w}: restitution", j.restitution, 0.0, 1.0, allowed="a number in [0, 1] (0: plastic landing)")
    return uni, (e if uni else None)


def _support_springs(w, j, kind, rb, axis, friction):
    """(kx, ky, kr) of a joint, checked: positive, on a joint with the ground, each in a direction
    the kind constrains (``kind.springs``: a guide's constraint across it is x for a guide along y
    and y for a guide along x)."""
    given = {n: getattr(j, n) for n in ("kx", "ky", "kr") if getattr(j, n) is not None}
    if not given:
        return None, None, None
    if rb.kind != "ground":
        raise BadInput(f"{w}: {', '.join(given)} make an elastic support: only for a joint with b = \"ground\"")
    if friction:
        raise BadInput(f"{w}: an elastic support ({', '.join(given)}) cannot carry friction (mu); give one or "
                       f"the other")
    out = {}
    for n, v in given.items():
        out[n] = _num(f"{w}: {n}", v, 0.0, lo_open=True,
                      allowed=f"a positive spring stiffness [{'N m/rad' if n == 'kr' else 'N/m'}] (absent: rigid)")
        if _spring_equation(kind, n, axis) is None:
            ok = [m for m in ("kx", "ky", "kr") if _spring_equation(kind, m, axis) is not None]
            raise BadInput(f"{w}: a {j.type} {'with this guide ' if axis else ''}has no rigid constraint that "
                           f"{n} could replace; allowed here: {', '.join(ok) or 'none'}")
    return out.get("kx"), out.get("ky"), out.get("kr")


def _spring_equation(kind, name, axis):
    """The index of the kind's equation that the spring ``name`` (kx, ky, kr) replaces, or None."""
    if name in kind.springs:
        return kind.springs[name]
    if "kn" in kind.springs and axis is not None and name in ("kx", "ky"):
        along = 1 if name == "kx" else 0   # kx: the guide along y (its normal along x)
        if abs(axis[1 - along]) <= 1e-12:
            return kind.springs["kn"]
    return None


def support_springs(joint, kind):
    """((equation index, stiffness, rotational), ...) of a frozen joint's elastic support springs:
    stiffness in N/m (kx, ky) or N m/rad (kr, rotational True)."""
    out = []
    for n in ("kx", "ky", "kr"):
        v = getattr(joint, n)
        if v is not None:
            out.append((_spring_equation(kind, n, joint.axis), v, n == "kr"))
    return tuple(out)
