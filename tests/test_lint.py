"""The tree is clean under ruff with the project's configuration (pyproject.toml [tool.ruff]: pycodestyle
errors and warnings, pyflakes, bugbear; line length 120).  Skipped only when ruff is not installed
(it is in the ``test`` extra)."""
from __future__ import annotations

import pathlib
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[1]


def _ruff():
    """The ruff command of this environment (the module of the ruff package, or None)."""
    try:
        from ruff.__main__ import find_ruff_bin
    except ImportError:
        return None
    try:
        return [find_ruff_bin()]
    except FileNotFoundError:
        return None


def test_ruff_check_finds_nothing():
    cmd = _ruff()
    if cmd is None:
        pytest.skip("ruff is not installed (pip install -e '.[test]')")
    r = subprocess.run([*cmd, "check", "--no-cache", "--output-format", "concise", "."], cwd=ROOT,
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, f"ruff check found problems:\n{r.stdout}{r.stderr}"


def test_ruff_is_configured_for_this_tree():
    """The configuration the check uses is the project's (a finding in a scratch file is reported), so
    the test above cannot pass by checking nothing."""
    cmd = _ruff()
    if cmd is None:
        pytest.skip("ruff is not installed (pip install -e '.[test]')")
    code = "import os\n\n\ndef f(values):\n    x = 1\n    return values\n"
    r = subprocess.run([*cmd, "check", "--no-cache", "--output-format", "concise", "--stdin-filename",
                        str(ROOT / "femslide" / "_lint_probe.py"), "-"], cwd=ROOT, input=code,
                       capture_output=True, text=True, timeout=60)
    assert r.returncode == 1 and "F401" in r.stdout and "F841" in r.stdout, r.stdout + r.stderr
