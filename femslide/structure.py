"""Declaring a planar structure: rods, rigid bodies, joints and loads (the model layer's front end).

A :class:`Structure` is a plain, mutable declaration: every object has a unique name, coordinates
are global and in the reference (undeformed) configuration, units are SI (m, kg, s, N, N m, rad).
Rotations and moments are counter-clockwise positive.  :meth:`Structure.freeze` checks the whole
declaration and returns a :class:`Frozen` structure: immutable, with every name resolved to the
part it denotes; the solvers take only frozen structures.

    s = Structure(gravity=(0.0, -9.81))
    s.rod("col", start=(0, 0), end=(0, 3), EI=1e6)
    s.body("deck", mass=100.0, centroid=(1.0, 3.5), outline=[(0, 3), (2, 3), (2, 4), (0, 4)])
    s.pin("base", a="col.start", b="ground")
    s.weld("top", a="col.end", b="deck")
    s.force("wind", on="deck", force=(50.0, 0.0))
    frozen = s.freeze()

Parts and points:

- a rod is a flexible corotational Euler-Bernoulli beam from ``start`` to ``end``; its ends are the
  points ``"ROD.start"`` and ``"ROD.end"``.  ``EI`` [N m^2] and ``EA`` [N] are numbers or
  :class:`Table` (piecewise linear in the arc length s [m] from ``start``); EA defaults to
  1e6 m^-2 * EI (a nearly inextensible rod); ``rhoA`` [kg/m] gives self-weight (and mass in
  dynamics); ``elements`` fixes the mesh (absent: adaptive refinement with an error estimate);
- a body is rigid: ``mass`` [kg] at ``centroid``, ``inertia`` [kg m^2] about it, ``outline`` a
  polygon (pictures; default inertia of a uniform plate); a massless body is a rigid link;
- a joint connects part ``a`` (a rod end or a body) to part ``b`` (a rod end, a body or
  ``"ground"``) at the point ``at`` (default: the position of the rod end a, or of the rod end b);
  ``pin`` keeps the points together (rotational spring ``c`` [N m/rad] optional), ``weld`` the
  points and rotations, ``slider`` keeps a's point on the line through ``at`` along ``axis``
  (carried by b) and a's rotation equal to b's, ``roller`` the line only.  Sliders and rollers may
  carry a spring ``k`` [N/m] along the axis with a ``preload`` [N] (> 0 pushes a along +axis) and,
  in dynamics, Coulomb friction ``mu``/``mu0`` with bearings ``bearing`` [m] apart;
- loads: gravity (vector, on bodies and rod mass), ``force`` (a force [N] and moment [N m] on a body
  at ``at`` or on a rod end) and ``distributed`` (force per unit reference length [N/m], global
  components, on a whole rod).  All loads are dead loads, applied together with gravity.
"""
from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field, fields, replace
from typing import TYPE_CHECKING, Any, Union

from .errors import BadInput

if TYPE_CHECKING:
    import numpy as np

    from .static import Solution

#: a point or vector (x, y) in SI units: m for points, N for forces
Vec = Sequence[float]
#: a rod property along the arc length: a number or a Table
Field = Union[float, "Table"]

GROUND = "ground"
JOINT_TYPES = ("pin", "weld", "slider", "roller")
LOAD_TYPES = ("force", "distributed")
EA_PER_EI = 1e6  # m^-2: default EA/EI, a nearly inextensible rod (SPEC section 3)
MAX_ELEMENTS = 16384  # per rod: beyond it round-off of the stiff axial terms outgrows the discretisation error


# -- declarations ---------------------------------------------------------------------------------

@dataclass(frozen=True)
class Table:
    """A piecewise-linear function of the arc length: ``value[i]`` at ``s[i]`` [m] (s increasing).

    Used for a rod's EI or EA varying along it, e.g. ``Table(s=(0.0, 3.0), value=(3e6, 1e6))``; in a
    structure file ``{s = [0.0, 3.0], value = [3e6, 1e6]}``.  Calling it interpolates linearly.
    """

    s: tuple
    value: tuple

    def __call__(self, s: float | np.ndarray) -> float | np.ndarray:
        import numpy as np
        return np.interp(s, self.s, self.value)

    def scaled(self, factor: float) -> Table:
        return Table(self.s, tuple(v * factor for v in self.value))

    @property
    def min(self) -> float:
        return min(self.value)

    @property
    def max(self) -> float:
        return max(self.value)


@dataclass(frozen=True)
class Rod:
    name: str
    start: tuple
    end: tuple
    EI: object
    EA: object = None
    rhoA: float = 0.0
    elements: int | None = None

    @property
    def length(self) -> float:
        return math.hypot(self.end[0] - self.start[0], self.end[1] - self.start[1])

    @property
    def angle(self) -> float:
        """Direction of the undeformed rod from +x [rad]."""
        return math.atan2(self.end[1] - self.start[1], self.end[0] - self.start[0])


@dataclass(frozen=True)
class Body:
    name: str
    mass: float = 0.0
    centroid: tuple | None = None
    inertia: float | None = None
    outline: tuple | None = None


@dataclass(frozen=True)
class Joint:
    name: str
    type: str
    a: str
    b: str
    at: tuple | None = None
    axis: tuple | None = None
    c: float = 0.0
    k: float = 0.0
    preload: float = 0.0
    mu: float | None = None
    mu0: float | None = None
    bearing: float | None = None


@dataclass(frozen=True)
class Load:
    name: str
    type: str
    on: str
    force: tuple = (0.0, 0.0)
    moment: float = 0.0
    at: tuple | None = None


_JOINT_FIELDS = frozenset(f.name for f in fields(Joint))


# -- checking helpers -----------------------------------------------------------------------------

def _num(what, x, lo=-math.inf, hi=math.inf, lo_open=False, allowed=None):
    """A finite float in the range, else BadInput naming ``what``."""
    if type(x) is float or type(x) is int:   # the common case, checked without the general path
        v = float(x)
        if math.isfinite(v) and (lo < v or (v == lo and not lo_open)) and v <= hi:
            return v
    if isinstance(x, bool):
        x = "bool"
    try:
        v = float(x)
    except (TypeError, ValueError, OverflowError):
        raise BadInput(f"{what}: {x!r} is not a number; allowed: {allowed or _range(lo, hi, lo_open)}") from None
    if not math.isfinite(v) or v < lo or v > hi or (lo_open and v == lo):
        raise BadInput(f"{what} = {x!r} is out of range; allowed: {allowed or _range(lo, hi, lo_open)}")
    return v


def _range(lo, hi, lo_open):
    a = "(" if lo_open or lo == -math.inf else "["
    b = ")" if hi == math.inf else "]"
    return f"a finite number in {a}{lo:g}, {hi:g}{b}"


def _vec(what, x, nonzero=False):
    try:
        items = list(x)
    except TypeError:
        raise BadInput(f"{what}: expected two numbers [x, y], got {x!r}") from None
    if len(items) != 2:
        raise BadInput(f"{what}: expected two numbers [x, y], got {x!r}")
    v = (_num(what, items[0]), _num(what, items[1]))
    if nonzero and v == (0.0, 0.0):
        raise BadInput(f"{what} = [0, 0] is a zero vector; allowed: a nonzero direction [x, y]")
    return v


def _stiffness(what, x, length):
    """A positive number or a table {s, value} covering [0, length]."""
    if isinstance(x, Table):
        x = {"s": x.s, "value": x.value}
    if isinstance(x, dict):
        unknown = set(x) - {"s", "value"}
        if unknown or "s" not in x or "value" not in x:
            raise BadInput(f"{what}: a table needs exactly the keys s and value (got {sorted(x)})")
        try:
            s = [_num(f"{what}.s", v) for v in x["s"]]
            val = [_num(f"{what}.value", v, 0.0, lo_open=True) for v in x["value"]]
        except TypeError:
            raise BadInput(f"{what}: s and value must be lists of numbers") from None
        if len(s) != len(val) or len(s) < 2:
            raise BadInput(f"{what}: s and value must be lists of the same length >= 2")
        if any(b <= a for a, b in zip(s, s[1:])):
            raise BadInput(f"{what}.s must increase strictly")
        tol = 1e-9 * length
        if s[0] > tol or s[-1] < length - tol:
            raise BadInput(f"{what}.s = [{s[0]:g} .. {s[-1]:g}] must cover the rod's arc length [0, {length:g}] m")
        return Table(tuple(s), tuple(val))
    return _num(what, x, 0.0, lo_open=True, allowed="a positive number or a table {s = [...], value = [...]}")


def polygon_area_centroid_inertia(outline):
    """Area, centroid and polar second moment of area about the centroid of a simple polygon."""
    A = cx = cy = Ixx = Iyy = 0.0
    n = len(outline)
    for i in range(n):
        x0, y0 = outline[i]
        x1, y1 = outline[(i + 1) % n]
        cr = x0 * y1 - x1 * y0
        A += cr
        cx += (x0 + x1) * cr
        cy += (y0 + y1) * cr
        Ixx += (y0 * y0 + y0 * y1 + y1 * y1) * cr
        Iyy += (x0 * x0 + x0 * x1 + x1 * x1) * cr
    A *= 0.5
    if A == 0.0:
        return 0.0, None, 0.0
    cx, cy = cx / (6 * A), cy / (6 * A)
    J = (Ixx + Iyy) / 12.0  # about the origin, signed with A
    J_c = J - A * (cx * cx + cy * cy)
    return abs(A), (cx, cy), abs(J_c)


# -- the declaration ------------------------------------------------------------------------------

class Structure:
    """A planar structure being declared: rods, rigid bodies, joints and loads (mutable).

    Every object has a unique name (a non-empty string without ``.``, not ``"ground"``);
    coordinates are global, in the reference (undeformed) configuration; units are SI (m, kg, s,
    N, N m, rad); rotations and moments are counter-clockwise positive.  Nothing is checked until
    :meth:`freeze` (which :func:`femslide.solve` calls): then an unknown name, a zero axis, a part
    connected to nothing or a value out of range raises :class:`femslide.BadInput` naming the
    object and the field.

    Parameters
    ----------
    gravity : (float, float), default (0.0, -9.81)
        Gravitational acceleration [m/s^2]; acts on bodies and on the rods' mass per length.

    Examples
    --------
    >>> s = femslide.Structure(gravity=(0.0, -9.81))
    >>> s.rod("col", start=(0, 0), end=(0, 3), EI=2e6)
    >>> s.body("deck", mass=500.0, centroid=(1.0, 3.5), outline=[(0, 3), (2, 3), (2, 4), (0, 4)])
    >>> s.pin("base", a="col.start", b="ground")
    >>> s.weld("top", a="col.end", b="deck")
    >>> s.roller("right", a="deck", b="ground", at=(2.0, 3.0), axis=(0.0, 1.0))
    >>> r = femslide.solve(s)
    """

    def __init__(self, gravity: Vec = (0.0, -9.81)) -> None:
        self.gravity = gravity
        self.rods: dict[str, Rod] = {}
        self.bodies: dict[str, Body] = {}
        self.joints: dict[str, Joint] = {}
        self.loads: dict[str, Load] = {}

    # -- declaring ----------------------------------------------------------------------------------
    def _name(self, name):
        if not isinstance(name, str) or not name or "." in name or name == GROUND:
            raise BadInput(f"name {name!r}: a non-empty string without '.', not {GROUND!r}")
        for kind in (self.rods, self.bodies, self.joints, self.loads):
            if name in kind:
                raise BadInput(f"name {name!r} is used twice; every rod, body, joint and load needs its own name")
        return name

    def rod(self, name: str, start: Vec, end: Vec, EI: Field, EA: Field | None = None, rhoA: Field = 0.0,
            elements: int | None = None) -> Rod:
        """Declare a flexible rod: a mesh of corotational Euler-Bernoulli beams from ``start`` to ``end``.

        Parameters
        ----------
        name : str
            Its name; its ends are the points ``"NAME.start"`` and ``"NAME.end"``.
        start, end : (float, float)
            End points [m].
        EI : float or Table
            Bending stiffness [N m^2], > 0: a number or a :class:`Table` piecewise linear in the
            arc length s [m] from ``start`` (covering the whole rod).
        EA : float or Table, optional
            Axial stiffness [N]; default 1e6 m^-2 * EI (a nearly inextensible rod).
        rhoA : float, default 0
            Mass per unit length [kg/m]: self-weight (and mass in dynamics).
        elements : int, optional
            A fixed number of elements; absent: the mesh is refined until the results are
            accurate to about 1e-7 and the result reports its ``error_estimate``.
        """
        r = Rod(self._name(name), tuple(start), tuple(end), EI, EA, rhoA, elements)
        self.rods[name] = r
        return r

    def body(self, name: str, mass: float = 0.0, centroid: Vec | None = None, inertia: float | None = None,
             outline: Sequence[Vec] | None = None) -> Body:
        """Declare a rigid body.

        Parameters
        ----------
        name : str
            Its name, used as a part of joints (``a="deck"``) and loads (``on="deck"``).
        mass : float, default 0
            Mass [kg] at the centroid; 0 makes a massless rigid link.
        centroid : (float, float), optional
            Centre of mass in the reference configuration [m]; default: the outline's centroid,
            else the point ``at`` of its first joint.
        inertia : float, optional
            Rotary inertia about the centroid [kg m^2]; default: a uniform plate of the outline.
        outline : list of (float, float), optional
            A polygon [m], for pictures and the default inertia.
        """
        b = Body(self._name(name), mass, None if centroid is None else tuple(centroid), inertia,
                 None if outline is None else tuple(tuple(p) for p in outline))
        self.bodies[name] = b
        return b

    def joint(self, name: str, type: str, a: str, b: str, **options: Any) -> Joint:
        """Declare a joint of any ``type``; :meth:`pin`, :meth:`weld`, :meth:`slider` and
        :meth:`roller` are the same with their options named.

        Parameters
        ----------
        name : str
            Its name.
        type : str
            ``"pin"``, ``"weld"``, ``"slider"`` or ``"roller"``.
        a : str
            Part a: a rod end (``"ROD.start"``, ``"ROD.end"``) or a body.
        b : str
            Part b: a rod end, a body, or ``"ground"`` (then the joint is a support and its force
            is reported as a reaction).
        **options
            ``at``, ``axis``, ``c``, ``k``, ``preload``, ``mu``, ``mu0``, ``bearing`` as in the
            methods of each type.
        """
        unknown = set(options) - _JOINT_FIELDS
        if unknown:
            raise BadInput(f"joint {name}: unknown option(s) {', '.join(sorted(unknown))}")
        j = Joint(self._name(name), type, a, b, **{k: (tuple(v) if isinstance(v, (list, tuple)) else v)
                                                   for k, v in options.items()})
        self.joints[name] = j
        return j

    def pin(self, name: str, a: str, b: str, at: Vec | None = None, c: float = 0.0) -> Joint:
        """A pin: a's point and b's point stay together; rotations are free relative to each other.

        Parameters
        ----------
        name, a, b : str
            Its name and parts (see :meth:`joint`).
        at : (float, float), optional
            The joint point [m]; default: the position of the rod end a (or of the rod end b).
        c : float, default 0
            A rotational spring [N m/rad] between a and b (a spring hinge).
        """
        return self.joint(name, "pin", a, b, at=at, c=c)

    def weld(self, name: str, a: str, b: str, at: Vec | None = None) -> Joint:
        """A weld: a's point and rotation stay those of b.

        Parameters
        ----------
        name, a, b : str
            Its name and parts (see :meth:`joint`).
        at : (float, float), optional
            The joint point [m]; default: the position of the rod end a (or of the rod end b).
        """
        return self.joint(name, "weld", a, b, at=at)

    def slider(self, name: str, a: str, b: str, axis: Vec, at: Vec | None = None, k: float = 0.0,
               preload: float = 0.0, mu: float | None = None, mu0: float | None = None,
               bearing: float | None = None) -> Joint:
        """A slider (a sliding clamp, a prismatic joint): a's point stays on the line through ``at``
        along ``axis``, carried by b, and a's rotation equals b's; the slide along the line is free.

        Parameters
        ----------
        name, a, b : str
            Its name and parts (see :meth:`joint`); the guide is fixed to b.
        axis : (float, float)
            Direction of the guide in the reference configuration (nonzero; its length is ignored).
        at : (float, float), optional
            A point of the guide [m]; default: the position of the rod end a (or of the rod end b).
        k : float, default 0
            A linear spring along the guide [N/m].
        preload : float, default 0
            The spring's force at the reference position [N]; > 0 pushes a along +axis.
        mu, mu0 : float, optional
            Coulomb friction along the guide (kinetic, static >= kinetic; default mu0 = mu), for the
            dynamics; the statics treat sliders as frictionless.
        bearing : float, optional
            Distance [m] between the guide's two bearings, for friction's normal force.
        """
        return self.joint(name, "slider", a, b, at=at, axis=axis, k=k, preload=preload, mu=mu, mu0=mu0,
                          bearing=bearing)

    def roller(self, name: str, a: str, b: str, axis: Vec, at: Vec | None = None, k: float = 0.0,
               preload: float = 0.0, mu: float | None = None, mu0: float | None = None) -> Joint:
        """A roller: a's point stays on the line through ``at`` along ``axis``, carried by b; the
        rotation is free.

        Parameters
        ----------
        name, a, b : str
            Its name and parts (see :meth:`joint`).
        axis : (float, float)
            Direction of the line (nonzero).
        at : (float, float), optional
            A point of the line [m]; default: the position of the rod end a (or of the rod end b).
        k, preload, mu, mu0 : float, optional
            Spring, preload and friction along the line, as for :meth:`slider`.
        """
        return self.joint(name, "roller", a, b, at=at, axis=axis, k=k, preload=preload, mu=mu, mu0=mu0)

    def force(self, name: str, on: str, force: Vec = (0.0, 0.0), moment: float = 0.0,
              at: Vec | None = None) -> Load:
        """A dead force (and moment) on a body or a rod end, applied together with gravity.

        Parameters
        ----------
        name : str
            Its name.
        on : str
            A body or a rod end (``"ROD.start"``, ``"ROD.end"``).
        force : (float, float), default (0, 0)
            Force [N], global components.
        moment : float, default 0
            Moment [N m], counter-clockwise positive.
        at : (float, float), optional
            Point of application [m] on a body; default: its centroid (or the rod end).
        """
        ld = Load(self._name(name), "force", on, tuple(force), moment, None if at is None else tuple(at))
        self.loads[name] = ld
        return ld

    def distributed(self, name: str, on: str, force: Vec) -> Load:
        """A dead load distributed uniformly along a whole rod.

        Parameters
        ----------
        name : str
            Its name.
        on : str
            The rod's name.
        force : (float, float)
            Force per unit reference length [N/m], global components.
        """
        ld = Load(self._name(name), "distributed", on, tuple(force))
        self.loads[name] = ld
        return ld

    def set(self, path: str, value: Any) -> None:
        """Change one declared field by its dotted name.

        Parameters
        ----------
        path : str
            ``"NAME.FIELD"`` (``"right.EI"``, ``"wind.force"``, ``"clamp.k"``) or ``"gravity"``.
        value
            The new value (checked by :meth:`freeze`).

        Raises
        ------
        femslide.BadInput
            No part of that name, or no such field.
        """
        if path == "gravity":
            self.gravity = value
            return
        name, _, fld = path.partition(".")
        for kind in (self.rods, self.bodies, self.joints, self.loads):
            if name in kind:
                obj = kind[name]
                names = {f.name for f in fields(obj)} - {"name"}
                if fld not in names:
                    raise BadInput(f"{path}: {name} has no field {fld!r}; fields: {', '.join(sorted(names))}")
                kind[name] = replace(obj, **{fld: value})
                return
        raise BadInput(f"{path}: no rod, body, joint or load is named {name!r}")

    def copy(self) -> Structure:
        """An independent copy of the declaration (the declared objects themselves are immutable)."""
        s = Structure(self.gravity)
        s.rods, s.bodies, s.joints, s.loads = dict(self.rods), dict(self.bodies), dict(self.joints), dict(self.loads)
        return s

    def freeze(self) -> Frozen:
        """Check the whole declaration and return it frozen: immutable, every name resolved.

        Raises
        ------
        femslide.BadInput
            An unknown name, a zero axis, a part connected to nothing or a value out of range;
            the message names the object and the field.
        """
        return Frozen.from_structure(self)

    def solve(self, **options: Any) -> Solution:
        """Static equilibrium (see :func:`femslide.static.solve`)."""
        from .static import solve
        return solve(self.freeze(), **options)


# -- the frozen, checked structure ----------------------------------------------------------------

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

    def weights(self):
        """Gravity force [N] of each body (x, y) and per unit length of each rod."""
        gx, gy = self.gravity
        return ({b.name: (b.mass * gx, b.mass * gy) for b in self.bodies},
                {r.name: (r.rhoA * gx, r.rhoA * gy) for r in self.rods})

    # -- checking -----------------------------------------------------------------------------------
    @staticmethod
    def from_structure(s: Structure) -> "Frozen":
        gravity = _vec("gravity", s.gravity)
        rods = []
        for r in s.rods.values():
            w = f"rod {r.name}"
            start, end = _vec(f"{w}: start", r.start), _vec(f"{w}: end", r.end)
            L = math.hypot(end[0] - start[0], end[1] - start[1])
            if not L > 0:
                raise BadInput(f"{w}: start and end coincide; a rod needs a positive length")
            EI = _stiffness(f"{w}: EI", r.EI, L)
            if r.EA is None:
                EA = EI.scaled(EA_PER_EI) if isinstance(EI, Table) else EA_PER_EI * EI
            else:
                EA = _stiffness(f"{w}: EA", r.EA, L)
            rhoA = _num(f"{w}: rhoA", r.rhoA, 0.0)
            n = r.elements
            if n is not None:
                if isinstance(n, bool) or not isinstance(n, (int, float)) or n != int(n) or not 1 <= n <= MAX_ELEMENTS:
                    raise BadInput(f"{w}: elements = {n!r}; allowed: an integer in [1, {MAX_ELEMENTS}] "
                                   f"(or absent: adaptive)")
                n = int(n)
            rods.append(Rod(r.name, start, end, EI, EA, rhoA, n))
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
        for j in joints_in:
            w = f"joint {j.name}"
            if j.type not in JOINT_TYPES:
                raise BadInput(f"{w}: type {j.type!r}; allowed: {', '.join(JOINT_TYPES)}")
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

        joints = []
        for j in joints_in:
            w = f"joint {j.name}"
            ra, rb = refs[j.name]
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
                        and (side == "b" or j.type in ("pin", "weld")):
                    raise BadInput(f"{w}: at = {list(at)} is not the position of the rod end {side} = "
                                   f"{getattr(j, side)!r} {list(pos(ref))}")
            axis = None
            if j.type in ("slider", "roller"):
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
                raise BadInput(f"{w}: axis is for sliders and rollers, not a {j.type}")
            c = _num(f"{w}: c", j.c, 0.0)
            if c and j.type != "pin":
                raise BadInput(f"{w}: a rotational spring c is for pins, not a {j.type}")
            k = _num(f"{w}: k", j.k, 0.0)
            pre = _num(f"{w}: preload", j.preload)
            if (k or pre) and j.type not in ("slider", "roller"):
                raise BadInput(f"{w}: k and preload are for sliders and rollers, not a {j.type}")
            mu = mu0 = bearing = None
            if j.mu is not None or j.mu0 is not None:
                if j.type not in ("slider", "roller"):
                    raise BadInput(f"{w}: friction (mu, mu0) is for sliders and rollers, not a {j.type}")
                mu = _num(f"{w}: mu", 0.0 if j.mu is None else j.mu, 0.0)
                mu0 = mu if j.mu0 is None else _num(f"{w}: mu0", j.mu0, 0.0)
                if mu0 < mu:
                    raise BadInput(f"{w}: mu0 = {mu0:g} < mu = {mu:g}; allowed: mu0 >= mu (static >= kinetic)")
            if j.bearing is not None:
                if j.type != "slider":
                    raise BadInput(f"{w}: bearing is for sliders")
                bearing = _num(f"{w}: bearing", j.bearing, 0.0, lo_open=True)
            joints.append(Joint(j.name, j.type, j.a, j.b, at, axis, c, k, pre, mu, mu0, bearing))

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
                if ld.moment or ld.at is not None:
                    raise BadInput(f"{w}: a distributed load has no moment or at")
                loads.append(Load(ld.name, ld.type, ld.on, F))
                refs[ld.name] = (ref, None)
                continue
            ref = resolve(f"{w}: on", ld.on, allow_ground=False)
            M = _num(f"{w}: moment", ld.moment)
            at = None
            if ld.at is not None:
                at = _vec(f"{w}: at", ld.at)
                if ref.kind == "rod_end" and math.dist(at, pos(ref)) > 1e-9 * max(1.0, *map(abs, at)):
                    raise BadInput(f"{w}: at = {list(at)} is not the position of the rod end {ld.on}")
            if at is None:
                at = pos(ref)
            loads.append(Load(ld.name, ld.type, ld.on, F, M, at))
            refs[ld.name] = (ref, None)

        fr = Frozen(gravity, tuple(rods), tuple(bodies), tuple(joints), tuple(loads), refs)
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
