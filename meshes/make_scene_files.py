"""Regenerate meshes/<scene>.toml (every built-in scene with its defaults), meshes/<scene>.vtu (the
reference mesh of every FE statics scene, ``femslide mesh`` with its default n_elements) and
meshes/structures/<scene>.toml (every FE statics scene at its defaults as a structure file: the
declaration that femslide.scenes.paper makes of it, to copy and edit).

    python meshes/make_scene_files.py          # from the repository root

tests/test_scene_files.py checks that the committed files hold the current defaults.
"""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))

from femslide.app import meshfile
from femslide.app.scenefile import is_fe  # noqa: E402
from femslide.app.structfile import dumps  # noqa: E402
from femslide.scenes import paper  # noqa: E402
from femslide.scenes.catalog import SCENES  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
WHY = {"P0": "10 N, or 0 when ag or record is given", "record": "none"}


def fmt(x):
    """A float as TOML: 1e6 rather than 1000000.0."""
    x = float(x)
    if x != 0 and (abs(x) >= 1e5 or abs(x) < 1e-3):
        mant, ex = f"{x:.15e}".split("e")
        mant = mant.rstrip("0").rstrip(".")
        if float(f"{mant}e{int(ex)}") == x:
            return f"{mant}e{int(ex)}"
    return repr(x)


def main():
    for s in SCENES.values():
        lines = [f"# {s.name}: {s.model}",
                 f"# femslide {s.command} meshes/{s.name}.toml [--set NAME=VALUE]...  (parameters: SI units;",
                 "# --set overrides this file, this file overrides the built-in defaults)",
                 f'scene = "{s.name}"']
        if is_fe(s):
            lines.append(f'mesh = "{s.name}.vtu"  # reference mesh: its elements per rod set n_elements')
        lines += ["", "[parameters]"]
        for p in s.params.params():
            if p.name == "n_elements" and is_fe(s):
                continue
            if p.default is None:
                why = WHY.get(p.name, p.derived or "set by the scene")
                lines.append(f"# {p.name} = ...  (default: {why}) [{p.unit}] {p.meaning}")
                continue
            val = fmt(p.default) if p.kind == "float" else repr(p.default)
            lines.append(f"{p.name} = {val}  # [{p.unit}] {p.meaning}")
        with open(os.path.join(HERE, f"{s.name}.toml"), "w") as fh:
            fh.write("\n".join(lines) + "\n")
        if is_fe(s):
            meshfile.write(s.name, s.resolve({}), os.path.join(HERE, f"{s.name}.vtu"))
            header = (f"{s.name}: {s.model}\nThe built-in scene's declaration at its default parameters, as a "
                      f"structure file:\n  femslide solve meshes/structures/{s.name}.toml [--set NAME.FIELD=VALUE]...\n"
                      "SI units; rotations and moments counter-clockwise (the scene's phi is -(deck rotation)).")
            os.makedirs(os.path.join(HERE, "structures"), exist_ok=True)
            with open(os.path.join(HERE, "structures", f"{s.name}.toml"), "w") as fh:
                fh.write(dumps(paper.declare(s.name, s.resolve({})), header))


if __name__ == "__main__":
    main()
