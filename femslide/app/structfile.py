"""Structure files: any planar structure declared in TOML (a file without a ``scene`` key).

    gravity = [0.0, -9.81]          # m/s^2 (default)

    [[rod]]                         # name, start, end, EI; optional EA, rhoA, elements
    name = "right"                  #   (or mesh = "frame.vtu", group = "rod:right": start, end and
    start = [2.0, 0.0]              #    elements from a meshio line group, straight, equally spaced)
    end = [2.0, 3.0]
    EI = 1e6                        # N m^2, or {s = [0.0, 3.0], value = [2e6, 1e6]}
                                    #   (or the section: E [Pa], I [m^4], A [m^2])

    [[body]]                        # name; optional mass, centroid, inertia, outline
    [[joint]]                       # name, type (pin|weld|slider|roller), a, b; optional at, axis,
                                    #   c, k, preload, mu, mu0, bearing, unilateral,
                                    #   restitution; with b = "ground" also
                                    #   kx, ky, kr (an elastic support)
    [[load]]                        # name, type (force|distributed), on; force, moment, at, case
    [[combination]]                 # name, factors = {dead = 1.35, wind = 1.5}
    [solve]                         # path = "principal" | "arc-length", theory = "nonlinear" |
                                    #   "linear", plot = "bodies.deck.rotation"

The fields and their meaning are those of the Python API (:mod:`femslide.model.structure`); every error
is bad input naming the file, the entry and the field.  Fields of a file can be overridden by name,
``NAME.FIELD=VALUE`` (``right.EI=1e8``, ``wind.force=[100, 0]``, ``gravity=[0, -9.81]``), which is how
``--set`` and sweeps (``--vary right.EI=1e4,1e6``) address them; ``elements=N`` fixes every rod's mesh
(also of rods that declare their own ``elements``; ``ROD.elements=M`` overrides it for one rod);
``solve.KEY=VALUE`` a key of the ``[solve]`` table (femslide.app.cases), ``ULS.factors={dead = 1.35}``
a combination's factors.
"""
from __future__ import annotations

import json
import math
import os

from femslide.errors import BadInput
from femslide.model.parts import MAX_ELEMENTS, SOLVER_FIELDS, Body, Joint, Load, Rod
from femslide.model.structure import Structure
from femslide.records import dataclass, field, fields

try:
    import tomllib
except ModuleNotFoundError:  # Python 3.10
    import tomli as tomllib

TABLES = {"rod": Rod, "body": Body, "joint": Joint, "load": Load}
TOP_KEYS = ("gravity", "description", "rod", "body", "joint", "load", "combination", "step", "solve", "simulate")
MESH_KEYS = ("mesh", "group")


def is_structure_data(data: dict) -> bool:
    return "scene" not in data


def read_toml(path: str, what: str = "file") -> dict:
    """The tables of a TOML file; every problem is bad input naming the file (``what`` says which
    kind of file it is).  A UTF-8 byte order mark (written by some Windows editors) is skipped."""
    if not os.path.isfile(path):
        raise BadInput(f"{what} {path} not found")
    try:
        with open(path, "rb") as fh:
            raw = fh.read()
    except OSError as exc:
        raise BadInput(f"{what} {path}: cannot be read ({exc.strerror})") from None
    try:
        return loads_toml(raw.decode("utf-8-sig"))
    except UnicodeDecodeError as exc:
        raise BadInput(f"{what} {path}: not UTF-8 text: {exc}") from None
    except BadInput as exc:
        raise BadInput(f"{what} {path}: {exc}") from None


def loads_toml(text: str) -> dict:
    """TOML text -> tables; malformed or too deeply nested text is bad input."""
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise BadInput(f"malformed TOML: {exc}") from None
    except RecursionError:   # arrays or tables nested thousands deep: the parser's stack
        raise BadInput("malformed TOML: arrays or tables nested too deeply; allowed: a structure or "
                       "scene file (a few levels of nesting)") from None


def parse(data: dict, path: str = "<structure>") -> Structure:
    """A :class:`~femslide.model.structure.Structure` from the tables of a structure file."""
    base = os.path.dirname(os.path.abspath(path))
    unknown = [k for k in data if k not in TOP_KEYS]
    if unknown:
        raise BadInput(f"structure file {path}: unknown key {unknown[0]!r}; allowed: {', '.join(TOP_KEYS)} "
                       f"(a scene file needs a `scene` key)")
    s = Structure(**({"gravity": data["gravity"]} if "gravity" in data else {}))
    for kind, cls in TABLES.items():
        entries = data.get(kind, [])
        if not isinstance(entries, list) or not all(isinstance(e, dict) for e in entries):
            raise BadInput(f"structure file {path}: {kind} must be an array of tables ([[{kind}]])")
        allowed = [f.name for f in fields(cls) if f.name not in SOLVER_FIELDS] \
            + (list(MESH_KEYS) if kind == "rod" else [])
        for i, e in enumerate(entries):
            where = f"structure file {path}: [[{kind}]] #{i + 1}"
            if "name" not in e:
                raise BadInput(f"{where}: missing `name`")
            where = f"structure file {path}: {kind} {e['name']!r}"
            bad = [k for k in e if k not in allowed]
            if bad:
                raise BadInput(f"{where}: unknown field {bad[0]!r}; allowed: {', '.join(allowed)}")
            e = dict(e)
            try:
                if kind == "rod":
                    if "mesh" in e:
                        e.update(_rod_from_mesh(e, base, where))
                    missing = [k for k in ("start", "end") if k not in e]
                    if "EI" not in e and not ("E" in e and "I" in e):
                        missing.append("EI")
                    if missing:
                        raise BadInput(f"missing field {missing[0]!r}")
                    s.rod(**e)
                elif kind == "body":
                    s.body(**e)
                elif kind == "joint":
                    missing = [k for k in ("type", "a", "b") if k not in e]
                    if missing:
                        raise BadInput(f"missing field {missing[0]!r}")
                    s.joint(**e)
                else:
                    missing = [k for k in ("type", "on") if k not in e]
                    if missing:
                        raise BadInput(f"missing field {missing[0]!r}")
                    typ = e.pop("type")
                    if typ == "force":
                        s.force(**e)
                    elif typ == "distributed":
                        if set(e) - {"name", "on", "force", "case", "force_end", "frame"}:
                            raise BadInput("a distributed load has only name, on, force, force_end, frame and case")
                        s.distributed(**e)
                    elif typ == "thermal":
                        if set(e) - {"name", "on", "dT", "dT_gradient", "case"}:
                            raise BadInput("a thermal load has only name, on, dT, dT_gradient and case")
                        s.thermal(**e)
                    else:
                        raise BadInput(f"type {typ!r}; allowed: force, distributed, thermal")
            except BadInput as exc:
                raise BadInput(f"{where}: {exc}") from None
            except TypeError as exc:
                raise BadInput(f"{where}: {exc}") from None
    combos = data.get("combination", [])
    if not isinstance(combos, list) or not all(isinstance(e, dict) for e in combos):
        raise BadInput(f"structure file {path}: combination must be an array of tables ([[combination]])")
    for i, e in enumerate(combos):
        if "name" not in e:
            raise BadInput(f"structure file {path}: [[combination]] #{i + 1}: missing `name`")
        bad = [k for k in e if k not in ("name", "factors")]
        if bad or "factors" not in e:
            raise BadInput(f"structure file {path}: combination {e['name']!r}: "
                           + (f"unknown field {bad[0]!r}" if bad else "missing field 'factors'")
                           + "; allowed: name, factors")
        try:
            s.combination(e["name"], e["factors"])
        except BadInput as exc:
            raise BadInput(f"structure file {path}: combination {e['name']!r}: {exc}") from None
    steps = data.get("step", [])
    if not isinstance(steps, list) or not all(isinstance(e, dict) for e in steps):
        raise BadInput(f"structure file {path}: step must be an array of tables ([[step]])")
    for i, e in enumerate(steps):
        bad = [k for k in e if k not in ("name", "factors")]
        if bad or "factors" not in e:
            raise BadInput(f"structure file {path}: [[step]] #{i + 1}: "
                           + (f"unknown field {bad[0]!r}" if bad else "missing field 'factors'")
                           + "; allowed: name, factors")
        try:
            s.step(e["factors"], e.get("name"))
        except BadInput as exc:
            raise BadInput(f"structure file {path}: [[step]] #{i + 1}: {exc}") from None
    if "solve" in data and not isinstance(data["solve"], dict):
        raise BadInput(f"structure file {path}: solve must be a table ([solve])")
    return s


def _rod_from_mesh(e, base, where):
    """start, end and elements of a rod from a line group of a meshio mesh (straight, equally spaced)."""
    import numpy as np

    from femslide.app.meshfile import read, rod_nodes
    mesh = e.pop("mesh")
    group = e.pop("group", f"rod:{e['name']}")
    for k in ("start", "end", "elements"):
        if k in e:
            raise BadInput(f"`{k}` comes from the mesh; remove it or the mesh")
    path = mesh if os.path.isabs(mesh) else os.path.join(base, mesh)
    mf = read(path)
    if group not in mf.groups:
        raise BadInput(f"mesh {path} has no group {group!r}; groups: {', '.join(sorted(mf.groups)) or 'none'}")
    X = rod_nodes(mf, group)
    n = len(X) - 1
    t = np.linspace(0.0, 1.0, n + 1)[:, None]
    off = float(np.abs((1 - t) * X[0] + t * X[-1] - X).max())
    if off > 1e-6 * max(1.0, float(np.abs(X).max())):
        raise BadInput(f"mesh {path} group {group}: nodes not equally spaced on a straight line (off by "
                       f"{off:.3g} m); femslide meshes rods uniformly")
    return {"start": tuple(map(float, X[0])), "end": tuple(map(float, X[-1])), "elements": n}


def parse_value(text):
    """A --set value: a number, or a list or table written as in the file (TOML: ``[0, -500]``,
    ``{alpha = 0.0, beta = 1e-3}``) or as JSON, else the string itself."""
    if not isinstance(text, str):
        return text
    t = text.strip()
    try:
        x = float(t)
        return x if math.isfinite(x) or t.lower() in ("inf", "-inf", "nan") else x
    except ValueError:
        pass
    try:
        return json.loads(t)
    except ValueError:
        pass
    except RecursionError:
        raise BadInput(f"value {t[:40]!r}...: nested too deeply; allowed: a number, a list or a table") from None
    if t[:1] and t[0] in "[{":
        try:
            doc = loads_toml("v = " + t)
            if list(doc) == ["v"]:
                return doc["v"]
        except BadInput as exc:
            if "too deeply" in str(exc):
                raise BadInput(f"value {t[:40]!r}...: nested too deeply; allowed: a number, a list or a "
                               f"table") from None
    return t


def apply(structure: Structure, overrides: dict) -> tuple[Structure, int | None]:
    """A copy of the structure with ``NAME.FIELD`` overrides applied, and the global ``elements``."""
    s = structure.copy()
    elements = None
    for name, value in overrides.items():
        value = parse_value(value)
        if name == "elements":
            if isinstance(value, bool) or not isinstance(value, (int, float)) or value != int(value) \
                    or not 1 <= value <= MAX_ELEMENTS:
                raise BadInput(f"elements = {value!r}: allowed: an integer in [1, {MAX_ELEMENTS}] (every rod's mesh)")
            elements = int(value)
            continue
        if name == "gravity" or "." in name:
            s.set(name, tuple(value) if isinstance(value, list) else value)
            continue
        raise BadInput(f"{name}: a structure file's values are named NAME.FIELD (e.g. right.EI), gravity or "
                       f"elements")
    if elements is not None:   # every rod's mesh, also of rods that declare their own (but not of a
        for rod in s.rods:     # rod whose elements are overridden by name too: ROD.elements)
            if f"{rod}.elements" not in overrides:
                s.set(f"{rod}.elements", elements)
    return s, elements


@dataclass
class StructureFile:
    """A structure file as a command-line target (duck-types a scene: ``name``, ``command``,
    ``resolve``, ``run``)."""

    path: str
    structure: Structure
    description: str = ""
    command: str = "solve"
    _frozen_ok: dict = field(default_factory=dict)
    simulate_table: dict | None = None   # the file's [simulate] table (femslide/analysis/simulate.py)
    solve_table: dict | None = None      # the file's [solve] table (femslide/app/cases.py)

    def _sim_elements(self, default):
        """The [simulate] table's elements (checked as simulate checks them), else ``default``."""
        from femslide.analysis.simulate import parse_elements
        n = parse_elements(self.simulate_table, f"structure file {self.path}: [simulate]")
        return default if n is None else n

    def for_modes(self) -> "StructureFile":
        """The same file as a `modes` target."""
        return StructureFile(self.path, self.structure, self.description, "modes",
                             simulate_table=self.simulate_table, solve_table=self.solve_table)

    def for_simulate(self) -> "StructureFile":
        """The same file as a `simulate` target (its [simulate] table is checked by :meth:`resolve`)."""
        return StructureFile(self.path, self.structure, self.description, "simulate",
                             simulate_table=self.simulate_table, solve_table=self.solve_table)

    def for_buckling(self) -> "StructureFile":
        """The same file as a `buckling` target."""
        return StructureFile(self.path, self.structure, self.description, "buckling",
                             simulate_table=self.simulate_table, solve_table=self.solve_table)

    @property
    def name(self):
        return os.path.splitext(os.path.basename(self.path))[0]

    @property
    def scene(self):
        return self

    @property
    def spec(self):
        """What a worker process loads the target from: the file's absolute path."""
        return os.path.abspath(self.path)

    @property
    def model(self):
        return self.description or f"structure file {self.path}"

    def resolve(self, given: dict) -> dict:
        """Overrides checked now (applied to a copy and frozen), before any run.  A `simulate`
        target also takes ``simulate.KEY=VALUE`` (a key of the [simulate] table)."""
        values = {k: parse_value(v) for k, v in given.items()}
        s, _ = apply(self.structure, {k: v for k, v in values.items() if not k.startswith(("simulate.", "solve."))})
        try:
            s.freeze()
        except BadInput as exc:
            raise BadInput(f"structure file {self.path}: {exc}") from None
        if self.command == "simulate":
            values = record_paths(values)
            self._spec(values)
        elif any(k.startswith("simulate.") for k in values):
            raise BadInput(f"{next(k for k in values if k.startswith('simulate.'))}: [simulate] keys are for "
                           f"`femslide simulate`")
        if self.command == "solve":
            self.solve_options(values)
        elif any(k.startswith("solve.") for k in values):
            raise BadInput(f"{next(k for k in values if k.startswith('solve.'))}: [solve] keys are for "
                           f"`femslide solve`")
        return values

    def solve_options(self, values) -> dict:
        """The [solve] table with the ``solve.KEY`` overrides, checked (femslide.app.cases)."""
        from femslide.app.cases import solve_options
        table = dict(self.solve_table or {})
        table.update({k.split(".", 1)[1]: v for k, v in values.items() if k.startswith("solve.")})
        return solve_options(table, f"structure file {self.path}: [solve]")

    def _spec(self, values):
        """The [simulate] table with the ``simulate.KEY`` overrides (``simulate.ground.scale``: a key
        of a table in it), checked."""
        from femslide.analysis.simulate import parse_spec
        table = simulate_table(self.simulate_table, values)
        return parse_spec(table if (self.simulate_table is not None or table) else None,
                          os.path.dirname(os.path.abspath(self.path)), f"structure file {self.path}: [simulate]")

    def prepare(self):
        """Import the FE statics (timed apart from the solve, as ``import_time_s``)."""
        from femslide.analysis import static  # noqa: F401
        from femslide.model.linalg import load_lapack
        load_lapack()
        if self.command in ("simulate", "modes"):
            from femslide.analysis import simulate as simulation  # noqa: F401

    def run(self, values: dict) -> dict:
        if self.command == "buckling":
            from femslide.analysis.buckling import buckling
            s, elements = apply(self.structure, {k: v for k, v in values.items() if not k.startswith("_")})
            return buckling(s.freeze(), count=values.get("_count") or 4, about=values.get("_about", "equilibrium"),
                            elements=elements, combination=values.get("_combination"), name=self.name)
        if self.command == "modes":
            from femslide.analysis.simulate import MODES, natural_modes
            s, elements = apply(self.structure, {k: v for k, v in values.items() if not k.startswith("_")})
            return natural_modes(s.freeze(), values.get("_count") or MODES,
                                 elements or self._sim_elements(None), name=self.name)
        if self.command == "simulate":
            from femslide.analysis.simulate import simulate
            s, elements = apply(self.structure, {k: v for k, v in values.items()
                                                 if not k.startswith(("_", "simulate."))})
            spec = self._spec(values)
            if elements is not None:
                spec.elements = elements
            from femslide.app.progress import TimeProgress
            bar = TimeProgress(spec.t_end, f"simulate {self.name}", bool(values.get("_quiet")))
            try:
                return simulate(s.freeze(), spec, name=self.name, progress=bar.at)
            finally:
                bar.close()
        from femslide.app.cases import statics
        s, elements = apply(self.structure, {k: v for k, v in values.items() if not k.startswith(("_", "solve."))})
        return statics(s.freeze(), elements=elements, name=self.name, cache=values.get("_cache"),
                       options=self.solve_options(values))


def simulate_table(table: dict | None, values: dict) -> dict:
    """A copy of a [simulate] table with the ``simulate.KEY`` overrides of ``values`` applied; a dotted
    key sets a key of a table in it (``simulate.ground.scale = 2`` keeps the ground's record and
    direction), creating the table if needed."""
    import copy
    out = copy.deepcopy(dict(table or {}))
    for k, v in values.items():
        if not k.startswith("simulate."):
            continue
        path = k.split(".")[1:]
        node = out
        for i, part in enumerate(path[:-1]):
            sub = node.get(part)
            if not isinstance(sub, dict):
                if sub is not None:
                    raise BadInput(f"{k}: simulate.{'.'.join(path[:i + 1])} is {sub!r}, not a table")
                sub = node[part] = {}
            node = sub
        node[path[-1]] = v
    return out


def record_paths(values: dict) -> dict:
    """Overrides naming a ground record (``simulate.ground.record``, or ``record`` in a
    ``simulate.ground`` table) made absolute when the file exists relative to the current folder (as a
    command line's paths are read); otherwise they stay relative to the structure file's folder (as
    the file's own ``record`` is read)."""
    def fix(p):
        return os.path.abspath(p) if isinstance(p, str) and not os.path.isabs(p) and os.path.isfile(p) else p
    out = dict(values)
    if "simulate.ground.record" in out:
        out["simulate.ground.record"] = fix(out["simulate.ground.record"])
    g = out.get("simulate.ground")
    if isinstance(g, dict) and "record" in g:
        out["simulate.ground"] = {**g, "record": fix(g["record"])}
    return out


def _toml_value(x):
    from femslide.model.parts import Table
    if isinstance(x, Table):
        return f"{{s = {_toml_value(list(x.s))}, value = {_toml_value(list(x.value))}}}"
    if isinstance(x, bool):
        return "true" if x else "false"
    if isinstance(x, str):
        return json.dumps(x)
    if isinstance(x, int):
        return str(x)
    if isinstance(x, float):
        return repr(x) if math.isfinite(x) else ("inf" if x > 0 else "-inf" if x < 0 else "nan")
    if isinstance(x, dict):
        return "{" + ", ".join(f"{k} = {_toml_value(v)}" for k, v in x.items()) + "}"
    return "[" + ", ".join(_toml_value(v) for v in x) + "]"


def dumps(structure: Structure, header: str = "") -> str:
    """A structure file (TOML) declaring ``structure``; fields at their defaults are left out."""
    lines = [f"# {h}" if h else "#" for h in header.splitlines()] if header else []
    lines.append(f"gravity = {_toml_value([float(g) for g in structure.gravity])}")
    for kind, objs in (("rod", structure.rods), ("body", structure.bodies), ("joint", structure.joints),
                       ("load", structure.loads), ("combination", getattr(structure, "combinations", {}))):
        cls = TABLES.get(kind)
        if cls is None:   # combinations: name and the factors as a table
            for obj in objs.values():
                lines += ["", f"[[{kind}]]", f"name = {_toml_value(obj.name)}",
                          f"factors = {_toml_value(dict(obj.factors))}"]
            continue
        defaults = {f.name: f.default for f in fields(cls)}
        for obj in objs.values():
            lines += ["", f"[[{kind}]]"]
            for f in fields(cls):
                v = getattr(obj, f.name)
                if v is None or (f.name not in ("name", "type") and v == defaults.get(f.name)):
                    continue
                lines.append(f"{f.name} = {_toml_value(v)}")
    for st in getattr(structure, "steps", []):   # the load history, in order
        lines += ["", "[[step]]"] + ([f"name = {_toml_value(st.name)}"] if st.name else [])
        lines.append(f"factors = {_toml_value(dict(st.factors))}")
    return "\n".join(lines) + "\n"


def load(path: str, data: dict | None = None) -> StructureFile:
    data = read_toml(path) if data is None else data
    desc = data.get("description", "")
    s = parse(data, path)
    try:
        s.freeze()
    except BadInput as exc:
        raise BadInput(f"structure file {path}: {exc}") from None
    sf = StructureFile(path, s, desc if isinstance(desc, str) else "", simulate_table=data.get("simulate"),
                       solve_table=data.get("solve"))
    sf.solve_options({})   # the [solve] table checked now
    return sf
