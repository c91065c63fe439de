"""Scene parameters: declaration, parsing and validation in one place.

Every parameter a scene accepts is declared once in :data:`PARAMS` with its default, unit, allowed
range and meaning.  Scenes (see :mod:`femslide.scenes.catalog`) pick the names they use and may override
defaults.  Parsing a ``NAME=VALUE`` string and checking it against the range happens only here, so
the command line, scene files and the Python API give the same errors.

Nothing here imports numpy: the command-line core must start fast.
"""
from __future__ import annotations

import math

from femslide.errors import BadInput  # noqa: F401  (re-exported: parameters are where bad input is found)
from femslide.records import dataclass, field, replace


@dataclass(frozen=True)
class Param:
    """One scalar parameter.

    ``lo``/``hi`` bound the allowed range; ``lo_open``/``hi_open`` say whether the bound itself is
    excluded.  ``kind`` is ``"float"``, ``"int"`` or ``"path"``.  A ``default`` of ``None`` means the
    value is derived from other parameters (``derived`` says how) or chosen by the solver.
    """

    name: str
    default: float | int | str | None
    unit: str
    meaning: str
    lo: float = -math.inf
    hi: float = math.inf
    lo_open: bool = False
    hi_open: bool = False
    kind: str = "float"
    derived: str = ""

    def range_text(self) -> str:
        if self.kind == "path":
            return "a readable file path"
        lo = "(" if self.lo_open or self.lo == -math.inf else "["
        hi = ")" if self.hi_open or self.hi == math.inf else "]"
        fmt = (lambda v: "inf" if v == math.inf else "-inf" if v == -math.inf else f"{v:g}")
        what = "an integer" if self.kind == "int" else "a number"
        return f"{what} in {lo}{fmt(self.lo)}, {fmt(self.hi)}{hi}"

    def check(self, value):
        """Return ``value`` converted and range-checked; raise :class:`BadInput` otherwise."""
        if self.kind == "path":
            if not isinstance(value, str) or not value:
                raise BadInput(f"parameter {self.name}: expected {self.range_text()}, got {value!r}")
            return value
        if isinstance(value, bool):
            raise BadInput(f"parameter {self.name}: expected {self.range_text()}, got {value!r}")
        if isinstance(value, str):
            text = value.strip()
            try:
                value = float(text)
            except ValueError:
                raise BadInput(f"parameter {self.name}: {text!r} is not a number; "
                               f"allowed: {self.range_text()}") from None
        try:
            x = float(value)
        except (TypeError, ValueError):
            raise BadInput(f"parameter {self.name}: {value!r} is not a number; "
                           f"allowed: {self.range_text()}") from None
        except OverflowError:  # an int beyond the float range, e.g. 10**400
            raise BadInput(f"parameter {self.name}: the value is too large to be finite; "
                           f"allowed: {self.range_text()}") from None
        if not math.isfinite(x):
            raise BadInput(f"parameter {self.name}: {value!r} is not finite; "
                           f"allowed: {self.range_text()}")
        below = x < self.lo or (self.lo_open and x == self.lo)
        above = x > self.hi or (self.hi_open and x == self.hi)
        if below or above:
            raise BadInput(f"parameter {self.name} = {x:g} {self.unit} is out of range; "
                           f"allowed: {self.range_text()}")
        if self.kind == "int":
            if x != int(x):
                raise BadInput(f"parameter {self.name} = {x:g} is not an integer; "
                               f"allowed: {self.range_text()}")
            return int(x)
        return x


_INF = math.inf

#: The parameter vocabulary of SPEC section 7.  Scene-specific defaults live in the scene registry.
PARAMS: dict[str, Param] = {p.name: p for p in [
    Param("a", 1.0, "m", "half-width of the body: AB = 2a, ground hinges at x = 0 and x = 2a", 0, _INF, lo_open=True),
    Param("b", 0.5, "m", "half-height of the body: AD = 2b", 0, _INF),
    Param("d", 0.2, "m", "offset of the centre of mass G from the centre of AB, along AB (towards B)", -_INF, _INF),
    Param("l", 3.0, "m", "length of the support rods", 0, _INF, lo_open=True),
    Param("l1", 1.5, "m", "height of the spring hinge on the rod (sections 2, 4, 5); l1 <= l", 0, _INF, lo_open=True),
    Param("m", 1.0, "kg", "mass of the rigid body (or of the oscillator)", 0, _INF, lo_open=True),
    Param("g", 9.81, "m/s^2", "gravitational acceleration (acts in -y)", 0, _INF, lo_open=True),
    Param("c", 1e6, "N m/rad", "stiffness of the spiral spring in the rod hinge", 0, _INF, lo_open=True),
    Param("k", 100.0, "N/m", "linear spring: between rod and guide (structures) or of the oscillator", 0, _INF),
    Param("dm", 0.0, "kg", "extra mass added to the body (section 5.1)", 0, _INF),
    Param("m1", 0.1, "kg", "mass of the telescopic rod piece B3B2 (section 5)", 0, _INF),
    Param("l2", 2.0, "m", "length of the telescopic rod piece B3B2 (section 5)", 0, _INF, lo_open=True),
    Param("EI", 1e6, "N m^2", "bending stiffness of the flexible rods", 0, _INF, lo_open=True),
    Param("EA", None, "N", "axial stiffness of the flexible rods", 0, _INF, lo_open=True,
          derived="1e6 m^-2 * EI"),
    Param("n_elements", None, "-", "elements per flexible rod (default: chosen adaptively to reach 1e-7)",
          1, 16384, kind="int", derived="adaptive"),
    Param("mu", 0.0, "-", "kinetic Coulomb friction coefficient", 0, _INF),
    Param("mu0", None, "-", "static Coulomb friction coefficient, mu0 >= mu", 0, _INF, derived="mu"),
    Param("c_v", 0.0, "N s/m", "viscous damping coefficient (sdof scenes: on w; beam-oscillation, beam-friction: "
          "on phi, a rotational dashpot on the deck, in N m s/rad)", 0, _INF),
    Param("w0", 0.0, "m", "initial displacement of the oscillator", -_INF, _INF),
    Param("phi0", 0.01, "rad", "initial tilt of the body (clockwise, towards B1), held and released at rest; "
          "0 is the vertical state, the equilibrium with an inextensible rod", -1.5, 1.5),
    Param("P0", 0.0, "N", "amplitude of the harmonic force P0 sin(theta t)", 0, _INF),
    Param("theta_ratio", 0.5, "-", "forcing frequency over natural frequency, theta/omega", 0, _INF, lo_open=True),
    Param("ag", 0.0, "m/s^2", "amplitude of the harmonic base acceleration", 0, _INF),
    Param("record", None, "-", "CSV file of base acceleration: columns t [s], a [m/s^2]", kind="path"),
    Param("t_end", 5.0, "s", "end time of the simulation", 0, 1e7, lo_open=True),
    Param("tolerance", 1e-6, "-", "local error tolerance of the FE transient (relative to the motion's "
          "amplitude; as a structure file's [simulate] tolerance)", 1e-12, 1e-2),
    Param("L", 1.0, "m", "length of the cantilever; free length of a flexible sliding rod (default l)",
          0, _INF, lo_open=True, derived="l"),
    Param("m_ratio", 0.5, "-", "end moment over 2 pi EI/L (1 rolls the cantilever into a full circle)", -10, 10),
    Param("p_ratio", 1.0, "-", "transverse tip load over EI/L^2", -1000, 1000),
]}


@dataclass(frozen=True)
class ParamSet:
    """The parameters one scene accepts, with scene-specific defaults and cross-parameter rules.

    ``rules`` are callables ``rule(values) -> str | None`` returning an error message naming the
    parameters involved, or ``None`` when the combination is allowed.  ``units`` overrides a
    parameter's unit in this scene (c_v is N m s/rad on a rotation).
    """

    names: tuple[str, ...]
    defaults: dict = field(default_factory=dict)
    rules: tuple = ()
    units: dict = field(default_factory=dict)

    def params(self) -> list[Param]:
        out = []
        for n in self.names:
            p = PARAMS[n]
            if n in self.defaults:
                p = replace(p, default=self.defaults[n])
            if n in self.units:
                p = replace(p, unit=self.units[n])
            out.append(p)
        return out

    def resolve(self, given: dict, scene: str = "") -> dict:
        """Defaults merged with ``given`` (strings or numbers), every value checked.

        Unknown names, bad values and broken cross-parameter rules raise :class:`BadInput`.
        """
        table = {p.name: p for p in self.params()}
        values = {}
        for name, raw in given.items():
            if name not in table:
                where = f" of scene {scene}" if scene else ""
                raise BadInput(f"unknown parameter {name!r}{where}; allowed: {', '.join(self.names)}")
            values[name] = table[name].check(raw)
        for p in table.values():
            if p.name not in values:
                values[p.name] = p.default
        if "EA" in values and values["EA"] is None:
            values["EA"] = 1e6 * values["EI"]
        if "mu0" in values and values["mu0"] is None:
            values["mu0"] = values.get("mu", 0.0)
        for rule in self.rules + ((rule_fe_ranges,) if "EI" in values else ()):
            msg = rule(values)
            if msg:
                raise BadInput(msg)
        return values


def floor_g(x: float, digits: int = 6) -> str:
    """x rounded *down* to ``digits`` significant digits, as %g: an upper bound a user can copy from a
    message and pass back (rounding to nearest may land just above the bound)."""
    if not math.isfinite(x) or x <= 0:
        return f"{x:g}"
    e = math.floor(math.log10(x)) - digits + 1
    y = math.floor(x / 10.0 ** e) * 10.0 ** e
    while y > x:  # the power of ten itself rounded
        y = math.nextafter(y, 0.0)
    return f"{y:.{digits}g}"


def parse_assignments(items) -> dict:
    """``["EI=1e8", "d=0.1"]`` -> ``{"EI": "1e8", "d": "0.1"}`` (values checked later)."""
    out = {}
    for item in items or ():
        if "=" not in item:
            raise BadInput(f"--set expects NAME=VALUE, got {item!r}")
        name, value = item.split("=", 1)
        name = name.strip()
        if not name:
            raise BadInput(f"--set expects NAME=VALUE, got {item!r}")
        out[name] = value.strip()
    return out


# Cross-parameter rules shared by several scenes -------------------------------------------------

def rule_mu0_ge_mu(v):
    if v["mu0"] < v["mu"]:
        return (f"parameter mu0 = {v['mu0']:g} is below mu = {v['mu']:g}; "
                f"allowed: mu0 >= mu (static friction is at least kinetic friction)")
    return None


def rule_l1_le_l(v):
    """Sections 2 and 4: the hinge may sit at the guide entrance (l1 = l, the FE-equivalent case)."""
    if not v["l1"] <= v["l"]:
        return (f"parameter l1 = {v['l1']:g} m must lie on the rod: allowed 0 < l1 <= l = {v['l']:g} m")
    return None


def rule_l1_lt_l(v):
    if not v["l1"] < v["l"]:
        return (f"parameter l1 = {v['l1']:g} m must lie on the rod: allowed 0 < l1 < l = {v['l']:g} m")
    return None


# The FE models' verified ranges ------------------------------------------------------------------
# Measured with the global statics of beam-slider/-fixed/-both (sum of forces and moment about A1
# within 1e-9 P, validation/STABILITY.md) and the cantilever against the elastica: EI/(P a^2) up to
# 1e15 (at 1e16 the moment balance is off by 4e-6 while the error estimate says 1e-4), EA a^2/EI up to
# 1e13 (at 1e15 off by 8e-6 with an estimate of 6e-8: silently wrong), EA/P up to 1e21 (the general
# model of session 3 closes the global statics at EA/P = 1e17 only to 2e-9 P a: validation/STABILITY.md
# flags it; the default EA = 1e6 EI at EI/(P a^2) = 1e12 needs EA/P ~ 1e18); the
# cantilever's EA L^2/EI up to 1e14 (1e16 stalls).  Beyond them the answers are not trustworthy or
# the arithmetic overflows (EI = 1e308: NaN and numpy warnings), so they are bad input.  EA a^2/EI
# >= 1: a rod is slender (EA L^2/EI = (L/r)^2, r its radius of gyration).
KAPPA_MAX, EA_RATIO_MAX, EA_P_MAX, EA_CANT_MAX = 1e15, 1e13, 1e21, 1e14


def rule_fe_ranges(v):
    EI, EA = v["EI"], v.get("EA")
    if EA is not None and not math.isfinite(EA):
        return (f"parameter EA: the default 1e6 m^-2 * EI = {EA:g} N overflows for EI = {EI:g} N m^2; "
                f"allowed: EA < 1e308 N (set EA, or a smaller EI)")
    if "a" not in v:  # cantilevers: lengths and forces by L and EI/L^2; only EA L^2/EI matters
        r = EA * v["L"] ** 2 / EI
        if not 1.0 <= r <= EA_CANT_MAX:
            return (f"parameter EA = {EA:g} N: EA L^2/EI = {r:.3g} is outside the range the FE model is "
                    f"verified for; allowed: {EI / v['L'] ** 2:.6g} <= EA <= {EA_CANT_MAX * EI / v['L'] ** 2:.6g} N "
                    f"here (1 <= EA L^2/EI <= {EA_CANT_MAX:g})")
        return None
    P, a = v["m"] * v["g"], v["a"]
    if not (math.isfinite(P) and P > 0 and math.isfinite(a * a) and a * a > 0):
        return (f"parameters m, g, a: the load m g = {P:g} N and a^2 = {a * a:g} m^2 must be positive and "
                f"finite; allowed: m g and a^2 between 1e-300 and 1e300")
    kappa = EI / (P * a * a)
    if not kappa <= KAPPA_MAX:
        return (f"parameter EI = {EI:g} N m^2: EI/(m g a^2) = {kappa:.3g} is outside the range the FE statics "
                f"is verified for; allowed: EI <= {KAPPA_MAX * P * a * a:.6g} N m^2 here "
                f"(EI/(m g a^2) <= {KAPPA_MAX:g})")
    r = EA * a * a / EI
    if not 1.0 <= r <= EA_RATIO_MAX:
        return (f"parameter EA = {EA:g} N: EA a^2/EI = {r:.3g} is outside the range the FE model is verified "
                f"for; allowed: {EI / (a * a):.6g} <= EA <= {EA_RATIO_MAX * EI / (a * a):.6g} N here "
                f"(1 <= EA a^2/EI <= {EA_RATIO_MAX:g})")
    if not EA / P <= EA_P_MAX:
        return (f"parameter EA = {EA:g} N: EA/(m g) = {EA / P:.3g} is outside the range the FE model is "
                f"verified for; allowed: EA <= {EA_P_MAX * P:.6g} N here (EA/(m g) <= {EA_P_MAX:g})")
    return None
