"""Scene files: a built-in scene, its parameters and (FE scenes) its mesh, in TOML.

    # meshes/beam-slider.toml
    scene = "beam-slider"          # the model: a built-in scene name
    mesh = "beam-slider.vtu"       # optional, FE scenes only; relative to this file
    description = "..."            # optional, free text

    [parameters]                   # optional; any of the scene's parameters (SI units)
    EI = 1e6

Precedence: the scene's defaults < the file's [parameters] < ``--set``.  With a mesh, its element
count per flexible rod sets ``n_elements`` unless ``--set n_elements`` is given, and its geometry must
agree with the parameters (see :mod:`femslide.app.meshfile`).  A relative ``record`` path is taken
relative to the file.  Errors are :class:`~femslide.errors.BadInput` naming the file.

Only the stdlib is imported here (tomllib, or tomli on Python 3.10); meshio and numpy are imported
when a mesh is read.
"""
from __future__ import annotations

import os

from femslide.errors import BadInput
from femslide.records import dataclass
from femslide.scenes.catalog import Scene
from femslide.scenes.catalog import get as get_scene


def _toml():
    """tomllib (tomli on Python 3.10), imported when a file is read (a built-in scene needs none)."""
    try:
        import tomllib
    except ModuleNotFoundError:  # Python 3.10
        import tomli as tomllib
    return tomllib


KEYS = ("scene", "mesh", "description", "parameters")


def is_scene_file(name: str) -> bool:
    return name.lower().endswith(".toml")


def is_fe(scene: Scene) -> bool:
    """Scenes whose mesh a file can fix: the FE statics scenes (runners in femslide.scenes.paper)."""
    return getattr(scene, "kind", "") == "fe-statics"


def no_mesh_reason(scene) -> str:
    if getattr(scene, "spec", None):   # a structure file: its rods may name meshes themselves
        return (f"{scene.name} is a structure file: its rods declare their meshes (elements, or mesh and "
                f"group); `femslide mesh` writes the reference meshes of the built-in FE scenes")
    if "n_elements" in scene.params.names:  # FE dynamics: built by femslide/scenes/beam_dynamics.py
        return (f"scene {scene.name}: mesh files are read for the FE statics scenes only; "
                f"set n_elements instead")
    return f"scene {scene.name} builds no beams, so it takes no mesh"


@dataclass
class SceneFile:
    path: str
    scene: Scene
    params: dict
    mesh_path: str | None = None
    mesh: object = None  # femslide.app.meshfile.MeshFile

    @property
    def mesh_n(self):
        if self.mesh is None:
            return None
        rods = [g[4:] for g in self.mesh.groups if g.startswith("rod:")]
        return self.mesh.n_elements(rods[0]) if rods else None

    def resolve(self, given: dict) -> dict:
        """File parameters overridden by ``given``; n_elements from the mesh; geometry checked."""
        merged = {**self.params, **given}
        n = self.mesh_n
        if n is not None and "n_elements" not in given:
            if "n_elements" in self.params and _as_int(self.params["n_elements"]) != n:
                raise BadInput(f"scene file {self.path}: [parameters] n_elements = "
                               f"{self.params['n_elements']} but the mesh {self.mesh_path} has {n} "
                               f"elements per rod; remove one of them")
            merged["n_elements"] = n
        values = self.scene.resolve(merged)
        if self.mesh is not None:
            from femslide.app.meshfile import check
            check(self.mesh, self.scene.name, values)
        return values


def _as_int(x):
    try:
        return int(float(x))
    except (TypeError, ValueError):
        return x


def load(path: str):
    """Read and check a scene file (and its mesh), or a structure file (no ``scene`` key:
    :mod:`femslide.app.structfile`)."""
    from femslide.app.structfile import read_toml
    data = read_toml(path, "file")   # a scene file or a structure file: which one is known once read
    if "scene" not in data and any(k in data for k in ("rod", "body", "joint", "load", "gravity", "simulate")):
        from femslide.app import structfile
        return structfile.load(path, data)
    unknown = [k for k in data if k not in KEYS]
    if unknown:
        raise BadInput(f"scene file {path}: unknown key {unknown[0]!r}; allowed: {', '.join(KEYS)} "
                       f"(scene parameters go in the [parameters] table)")
    if "scene" not in data:
        raise BadInput(f"scene file {path}: missing key 'scene' (a built-in scene name), and no "
                       f"[[rod]], [[body]], [[joint]] or [[load]] tables of a structure file")
    if not isinstance(data["scene"], str):
        raise BadInput(f"scene file {path}: 'scene' must be a string (a built-in scene name)")
    try:
        scene = get_scene(data["scene"])
    except BadInput as exc:
        raise BadInput(f"scene file {path}: {exc}") from None
    params = data.get("parameters", {})
    if not isinstance(params, dict):
        raise BadInput(f"scene file {path}: 'parameters' must be a table ([parameters])")
    for k, v in params.items():
        if isinstance(v, (dict, list)):
            raise BadInput(f"scene file {path}: parameter {k} must be a number or a string")
    base = os.path.dirname(os.path.abspath(path))
    params = dict(params)
    if isinstance(params.get("record"), str) and not os.path.isabs(params["record"]):
        params["record"] = os.path.join(base, params["record"])
    try:  # names and values checked now, before any mesh is read
        scene.resolve({k: v for k, v in params.items()})
    except BadInput as exc:
        raise BadInput(f"scene file {path}: {exc}") from None
    sf = SceneFile(path, scene, params)
    if "mesh" in data:
        if not isinstance(data["mesh"], str) or not data["mesh"]:
            raise BadInput(f"scene file {path}: 'mesh' must be a file name")
        if not is_fe(scene):
            raise BadInput(f"scene file {path}: {no_mesh_reason(scene)}; remove the 'mesh' key")
        from femslide.app import meshfile
        sf.mesh_path = os.path.join(base, data["mesh"])
        try:
            sf.mesh = meshfile.read(sf.mesh_path)
        except BadInput as exc:
            raise BadInput(f"scene file {path}: {exc}") from None
        # groups and geometry against the file's own parameters (each run checks its values again)
        try:
            sf.resolve({})
        except BadInput as exc:
            raise BadInput(f"scene file {path}: {exc}") from None
    return sf


def target(name: str):
    """A built-in scene name or a scene file path -> an object with ``scene`` and ``resolve(given)``."""
    if is_scene_file(name):
        return load(name)
    scene = get_scene(name)
    return _Builtin(scene)


@dataclass
class _Builtin:
    scene: Scene

    def resolve(self, given: dict) -> dict:
        return self.scene.resolve(given)


# -- templates shipped with femslide (the package femslide.meshes) -----------------------------------------

def templates():
    """The folder of scene templates installed with femslide: every built-in scene as a scene file
    ``NAME.toml`` (FE statics scenes with their reference mesh ``NAME.vtu``) and the FE scenes as
    structure files ``structures/NAME.toml``.  An importlib.resources Traversable (a folder of the
    installed package, wheel or editable); a source checkout run without installing falls back to
    the package's source folder."""
    from importlib import resources
    try:
        return resources.files("femslide.meshes")
    except ModuleNotFoundError:  # `python -m femslide` in a checkout that was never pip-installed
        import pathlib
        src = pathlib.Path(__file__).resolve().parent.parent / "meshes"
        if (src / "__init__.py").is_file():
            return src
        raise BadInput("the scene templates (package femslide.meshes) are not installed; reinstall "
                       "femslide (pip install femslide)") from None


def template_names() -> list:
    """Names ``femslide init`` accepts: scene files NAME, structure files structures/NAME."""
    root = templates()
    names = sorted(e.name[:-5] for e in root.iterdir() if e.name.endswith(".toml"))
    sub = root / "structures"
    if sub.is_dir():
        names += sorted("structures/" + e.name[:-5] for e in sub.iterdir() if e.name.endswith(".toml"))
    return names


def _template_files(name: str):
    """(source Traversable, file name) pairs of a template: the TOML and, for a scene file, the mesh
    it names."""
    root = templates()
    key = name[:-5] if name.lower().endswith(".toml") else name
    key = key.replace("\\", "/")
    if key not in template_names():
        raise BadInput(f"init: no scene template {name!r}; allowed: {', '.join(template_names())}")
    if key.startswith("structures/"):
        base = key.split("/", 1)[1]
        return [(root / "structures" / f"{base}.toml", f"{base}.toml")]
    src = root / f"{key}.toml"
    files = [(src, f"{key}.toml")]
    data = _toml().loads(src.read_text(encoding="utf-8"))
    mesh = data.get("mesh")
    if isinstance(mesh, str) and mesh:
        files.append((root / mesh, os.path.basename(mesh)))
    return files


def copy_template(name: str, folder: str = ".") -> list:
    """Copy the template of scene ``name`` into ``folder`` (created if missing) and return the paths
    written.  No existing file is overwritten: BadInput naming it, and nothing is copied."""
    files = _template_files(name)
    if os.path.exists(folder) and not os.path.isdir(folder):
        raise BadInput(f"init: {folder} is a file; allowed: a folder (existing or new)")
    dests = [os.path.join(folder, fname) for _, fname in files]
    for d in dests:
        if os.path.lexists(d):
            raise BadInput(f"init: {d} exists; allowed: a folder without {', '.join(fname for _, fname in files)} "
                           f"(remove it or give another DIR)")
    try:
        os.makedirs(folder, exist_ok=True)
        for (src, _), d in zip(files, dests):
            with open(d, "xb") as fh:  # exclusive: never overwrite, even in a race
                fh.write(src.read_bytes())
    except FileExistsError as exc:
        raise BadInput(f"init: {exc.filename} exists; nothing overwritten") from None
    except OSError as exc:
        raise BadInput(f"init: cannot write into {folder} ({exc.strerror or exc}); allowed: a "
                       f"writable folder") from None
    return dests
