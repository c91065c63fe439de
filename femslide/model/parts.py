"""The parts of a declared structure: rods, rigid bodies, joints, loads and their field checks.

Plain immutable records (SI units, global reference coordinates) that :class:`femslide.model.structure.Structure`
collects and :class:`femslide.model.frozen.Frozen` checks; :class:`Table` is a rod property varying
piecewise linearly along the arc length.  The ``_num``, ``_vec`` and ``_stiffness`` helpers check one
field each and raise :class:`femslide.errors.BadInput` naming the object, the field and the allowed
range.
"""
from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TYPE_CHECKING, Union

from femslide.errors import BadInput
from femslide.records import dataclass, fields

if TYPE_CHECKING:
    import numpy as np



GROUND = "ground"
LOAD_TYPES = ("force", "distributed", "thermal")
EA_PER_EI = 1e6  # m^-2: default EA/EI, a nearly inextensible rod (SPEC section 3)
MAX_ELEMENTS = 16384  # per rod: beyond it round-off of the stiff axial terms outgrows the discretisation error


#: a point or vector (x, y) in SI units: m for points, N for forces
Vec = Sequence[float]


#: a rod property along the arc length: a number or a Table
Field = Union[float, "Table"]


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
    """A flexible rod as declared: EI [N m^2] and EA [N], or the section's E [Pa], I [m^4] and A
    [m^2] instead (EI = E I, EA = E A; the frozen rod holds EI and EA only)."""

    name: str
    start: tuple
    end: tuple
    EI: object = None
    EA: object = None
    rhoA: float = 0.0
    elements: int | None = None
    E: float | None = None
    I: float | None = None  # noqa: E741 - the second moment of area, as engineers write it
    A: float | None = None
    alpha: float = 0.0          # 1/K: thermal expansion coefficient
    depth: float | None = None  # m: section depth (for a temperature gradient)

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
    """A joint as declared: ``type`` names a registered kind (:mod:`femslide.joints.kinds`), which
    says what it holds and which of the optional fields (axis, c, k, preload, mu, mu0, bearing) it
    takes.  A joint with the ground may carry elastic springs ``kx``, ``ky`` [N/m] and ``kr``
    [N m/rad] instead of its rigid constraints in those directions (an elastic support).  A slider or
    roller with ``unilateral`` is a contact: it holds a's point on the +n side of the guide (n = the
    axis turned by +90 degrees) only while it presses, lifts off when it would pull and lands again
    when its gap closes (``restitution``: the landing's coefficient, 0 = plastic, the default)."""

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
    kx: float | None = None
    ky: float | None = None
    kr: float | None = None
    displacement: tuple | None = None   # with the ground: prescribed support motion [m] (settlement)
    rotation: float | None = None       # with the ground (weld, slider): prescribed support rotation [rad]
    unilateral: bool = False            # slider, roller: a contact (holds only while it presses; uplift)
    restitution: float | None = None    # with unilateral: Newton's coefficient of a landing (0 plastic .. 1)
    lifted: bool = False                # a unilateral contact the statics released (set by the solver, not declared)


#: the load case of gravity and of loads declared without one
DEAD = "dead"


@dataclass(frozen=True)
class Load:
    """A load as declared; ``case`` names its load case (default "dead", the case of gravity).
    A thermal load (``type = "thermal"``, on a rod) has a uniform temperature change ``dT`` [K] and a
    gradient ``dT_gradient`` [K] (the +n face minus the -n face).  A force on a rod (``on`` = the rod)
    acts at the arc length ``s`` [m]; a distributed load varies linearly from ``force`` to
    ``force_end`` and its components are global or, with ``frame = "rod"``, along the rod's
    reference tangent and normal."""

    name: str
    type: str
    on: str
    force: tuple = (0.0, 0.0)
    moment: float = 0.0
    at: tuple | None = None
    case: str = DEAD
    dT: float = 0.0
    dT_gradient: float = 0.0
    s: float | None = None             # force on a rod: arc length [m] from the rod's start
    force_end: tuple | None = None     # distributed: the load at the rod's end (linear in s between)
    frame: str = "global"              # distributed: "global" or "rod" (along the reference tangent, normal)


@dataclass(frozen=True)
class Combination:
    """A load combination: a factor per load case (``factors``: (case, factor) pairs; cases not
    named have factor 0), solved as its own equilibrium."""

    name: str
    factors: tuple = ()

    def factor_dict(self) -> dict:
        return dict(self.factors)


#: fields a solver sets on a frozen structure (not declarations)
SOLVER_FIELDS = frozenset(("lifted",))
_JOINT_FIELDS = frozenset(f.name for f in fields(Joint)) - SOLVER_FIELDS


def _num(what, x, lo=-math.inf, hi=math.inf, lo_open=False, allowed=None):
    """A finite float in the range, else BadInput naming ``what``."""
    if type(x) is float or type(x) is int:   # the common case, checked without the general path
        v = float(x)
        if math.isfinite(v) and (lo < v or (v == lo and not lo_open)) and v <= hi:
            return v
    if isinstance(x, (str, bytes, bool)):   # one rule for every number: text is not a number ("2e6" as "8")
        raise BadInput(f"{what}: {x!r} is {'true/false' if isinstance(x, bool) else 'text'}, not a number; allowed: "
                       f"{allowed or _range(lo, hi, lo_open)} (a number, written without quotes)")
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
