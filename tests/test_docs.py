"""The documentation (docs/: user guide and API reference from the docstrings) builds with Sphinx
without a single warning, and its API page documents the public API."""
from __future__ import annotations

import os
import pathlib
import subprocess
import sys

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[1]


def test_docs_build_without_warnings(tmp_path):
    pytest.importorskip("sphinx")
    out = tmp_path / "html"
    env = {**os.environ, "PYTHONPATH": str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", "")}
    r = subprocess.run([sys.executable, "-m", "sphinx", "-W", "--keep-going", "-q", "-b", "html",
                        "-d", str(tmp_path / "doctrees"), str(ROOT / "docs"), str(out)],
                       capture_output=True, text=True, cwd=tmp_path, env=env, timeout=300)
    assert r.returncode == 0, (r.stdout + r.stderr)[-4000:]
    api = (out / "api.html").read_text(encoding="utf-8")
    for name in ("femslide.Structure", "femslide.solve", "femslide.simulate", "femslide.sweep",
                 "femslide.load", "femslide.Result", "to_dataframe", "history", "femslide.plot",
                 "femslide.output.vtu.read"):
        assert f'id="{name}' in api or name in api, name
    for page in ("index.html", "guide.html", "examples.html"):
        assert (out / page).is_file()
    # the examples page shows the pictures its scripts write (issue 25: it had none)
    examples = (out / "examples.html").read_text(encoding="utf-8")
    for png in ("example-ei-sweep.png", "example-hysteresis.png", "example-frame-M.png"):
        assert png in examples and (out / "_images" / png).is_file(), png
