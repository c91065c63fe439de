"""Packaging: one source of the version, the license, the scene templates and py.typed in the wheel, the
templates found through the installed package (importlib.resources), not the repository layout.

The wheel test builds a real wheel (``pip wheel --no-deps`` of a copy of this tree, ~10 s) and reads its
file list and metadata; it skips only when pip cannot fetch the build backend (no network)."""
from __future__ import annotations

import pathlib
import shutil
import subprocess
import sys
import zipfile

import pytest

import femslide

ROOT = pathlib.Path(__file__).resolve().parents[1]

try:
    import tomllib
except ModuleNotFoundError:  # Python 3.10
    import tomli as tomllib


def pyproject():
    return tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))


def template_files():
    """The scene templates of the source tree, relative to meshes/: *.toml and *.vtu, also in subfolders."""
    base = ROOT / "meshes"
    return sorted(str(p.relative_to(base)).replace("\\", "/") for p in base.rglob("*")
                  if p.suffix in (".toml", ".vtu") and "__pycache__" not in p.parts)


def test_version_has_one_source():
    """pyproject.toml takes the version from femslide/version.py, which femslide.__version__ is (no
    second copy to drift: it once said 0.1.0 while the package said 0.2.0)."""
    project = pyproject()["project"]
    assert "version" not in project and "version" in project["dynamic"]
    assert pyproject()["tool"]["setuptools"]["dynamic"]["version"] == {"attr": "femslide.version.__version__"}
    assert femslide.__version__ == "0.2.0"


def test_license_file_and_spdx_field():
    project = pyproject()["project"]
    assert project["license"] == "MIT" and project["license-files"] == ["LICENSE"]
    text = (ROOT / "LICENSE").read_text(encoding="utf-8")
    assert text.startswith("MIT License") and "femslide developers" in text
    requires = pyproject()["build-system"]["requires"]
    assert any(r.replace(" ", "").startswith("setuptools>=") and
               tuple(int(x) for x in r.split(">=")[1].split(".")[:1]) >= (77,) for r in requires), requires


def test_templates_come_from_the_package_and_match_the_tree():
    """femslide.app.scenefile.templates() (importlib.resources on femslide.meshes) holds every template of
    meshes/, and init's names cover every scene file and structure file.  (In a checkout the package
    is this tree's meshes/, so the bytes are compared in the wheel, below.)"""
    from femslide.app import scenefile
    root = scenefile.templates()
    for rel in template_files():
        node = root
        for part in rel.split("/"):
            node = node / part
        assert node.is_file(), rel
    names = set(scenefile.template_names())
    want = {rel[:-5] for rel in template_files() if rel.endswith(".toml")}
    assert names == want
    from femslide.scenes.catalog import SCENES
    assert set(SCENES) <= names  # every built-in scene has a template


def test_package_data_covers_every_template():
    """Every template file is matched by [tool.setuptools] packages / package-data (the wheel of 0.2.0
    left meshes/ out)."""
    import fnmatch
    st = pyproject()["tool"]["setuptools"]
    data = st["package-data"]
    dirs = {pkg: st["package-dir"].get(pkg) for pkg in st["packages"]}
    assert dirs["femslide.meshes"] == "meshes"
    assert "py.typed" in data["femslide"] and (ROOT / "femslide" / "py.typed").is_file()
    for rel in template_files():
        folder, name = rel.rsplit("/", 1) if "/" in rel else ("", rel)
        pkg = "femslide.meshes" + ("." + folder.replace("/", ".") if folder else "")
        assert pkg in st["packages"], f"meshes/{rel}: package {pkg} is not listed"
        assert any(fnmatch.fnmatch(name, pat) for pat in data.get(pkg, [])), f"meshes/{rel} not in package-data"


def test_manifest_ships_the_tests():
    text = (ROOT / "MANIFEST.in").read_text(encoding="utf-8").split()
    for what in ("tests", "validation", "meshes"):
        assert what in text


def test_wheel_holds_templates_license_and_py_typed(tmp_path):
    """A wheel built from this tree holds every template under femslide/meshes (byte for byte), py.typed, the LICENSE
    and the metadata: version = femslide.__version__, License-Expression MIT; and the compiled assembly kernel
    (femslide/model/_assembly, built from its C source by the wheel's own build: the copy leaves the in-place
    build out), so the wheel is platform-specific."""
    src = tmp_path / "src"
    shutil.copytree(ROOT, src, ignore=shutil.ignore_patterns(
        ".git", "build", "dist", "*.egg-info", ".ci-venv", ".venv", "__pycache__", ".pytest_cache",
        ".hypothesis", ".ruff_cache", "out", "*.so", "*.pyd"))
    r = subprocess.run([sys.executable, "-m", "pip", "wheel", "--no-deps", "-q", "-w", str(tmp_path / "dist"),
                        str(src)], capture_output=True, text=True, timeout=300)
    if r.returncode != 0 and ("No matching distribution" in r.stderr or "Could not find a version" in r.stderr):
        pytest.skip(f"pip cannot fetch the build backend here: {r.stderr.strip().splitlines()[-1]}")
    assert r.returncode == 0, r.stderr
    (whl,) = (tmp_path / "dist").glob("femslide-*.whl")
    with zipfile.ZipFile(whl) as z:
        names = set(z.namelist())
        meta_name = next(n for n in names if n.endswith(".dist-info/METADATA"))
        meta = z.read(meta_name).decode()
        for rel in template_files():   # every template, byte for byte as in the tree
            assert f"femslide/meshes/{rel}" in names, rel
            assert z.read(f"femslide/meshes/{rel}") == (ROOT / "meshes" / rel).read_bytes(), rel
    assert "femslide/py.typed" in names
    assert any(n.endswith(".dist-info/licenses/LICENSE") for n in names)
    assert f"\nVersion: {femslide.__version__}\n" in meta
    assert "\nLicense-Expression: MIT\n" in meta
    assert not any(n.startswith(("tests/", "validation/", "meshes/")) for n in names)
    ext = [n for n in names if n.startswith("femslide/model/_assembly") and n.endswith((".so", ".pyd"))]
    assert len(ext) == 1, sorted(n for n in names if "_assembly" in n)
    assert not whl.name.endswith("-none-any.whl"), whl.name


def _public_callables():
    """The public API: femslide's exported functions, and the public methods of Structure, Table and
    Result (with Structure.__init__)."""
    import inspect

    from femslide.app.result import Result
    out = [(f"femslide.{n}", getattr(femslide, n)) for n in ("solve", "simulate", "sweep", "load", "list_scenes")]
    for cls in (femslide.Structure, femslide.Table, Result):
        for name, obj in vars(cls).items():
            if inspect.isfunction(obj) and (not name.startswith("_") or name in ("__init__", "__call__")):
                out.append((f"{cls.__name__}.{name}", obj))
            elif isinstance(obj, property) and not name.startswith("_"):
                out.append((f"{cls.__name__}.{name}", obj.fget))
    return out


def test_public_api_has_type_hints():
    """Every parameter and the return value of the public API are annotated (py.typed promises it)."""
    import inspect
    missing = []
    calls = _public_callables()
    assert len(calls) > 20
    for qual, fn in calls:
        sig = inspect.signature(fn)
        for p in sig.parameters.values():
            if p.name in ("self", "cls"):
                continue
            if p.annotation is inspect.Parameter.empty:
                missing.append(f"{qual}({p.name})")
        if sig.return_annotation is inspect.Signature.empty:
            missing.append(f"{qual} -> ?")
    assert not missing, missing
