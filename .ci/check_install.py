"""Check an installed femslide (a wheel's test, run by cibuildwheel's test-command and by .ci/wheels).

    python .ci/check_install.py --expect compiled|numpy|any

Run with the interpreter of the environment to check, from any directory (FEMSLIDE_KERNEL is ignored:
the install's own choice is checked).  It runs the installed
command line, as a user would, from an empty temporary directory (so the installed package is imported,
not a source tree):

- ``femslide --version``: prints the version and which assembly runs; with ``--expect compiled`` it must
  be the compiled kernel (a wheel whose optional extension failed to build would otherwise pass
  silently), with ``--expect numpy`` the numpy path;
- ``femslide solve beam-slider --json``: it must converge; its M_max (N m) is printed;
- the same solve on the numpy path (``FEMSLIDE_KERNEL=numpy``), femslide's test oracle for the kernel:
  the two M_max must agree to 1e-9 (relative; they agree to ~1e-13 on x86_64 Linux).

Prints four lines: the version, the assembly, ``M_max`` (repr; the run's own assembly) and ``module`` (where
femslide was imported from), and exits 1
on any failure.  Standard library only.
"""
from __future__ import annotations

import argparse
import json
import os
import pathlib
import subprocess
import sys
import tempfile


def femslide_command() -> list[str]:
    """The installed console script next to this interpreter (``bin/femslide`` or
    ``Scripts/femslide.exe``), else ``python -m femslide`` with this interpreter (not a ``femslide``
    found on PATH: that may belong to another install)."""
    here = pathlib.Path(sys.executable).parent
    for name in ("femslide", "femslide.exe"):
        if (here / name).is_file():
            return [str(here / name)]
    return [sys.executable, "-m", "femslide"]


def run(cmd: list[str], cwd: str, env: dict | None = None) -> str:
    r = subprocess.run(cmd, cwd=cwd, env=env, capture_output=True, text=True, timeout=600)
    if r.returncode != 0:
        sys.exit(f"{' '.join(cmd)} failed (exit {r.returncode}):\n{r.stdout}\n{r.stderr}")
    return r.stdout


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--expect", choices=("compiled", "numpy", "any"), default="any",
                        help="which assembly the installed femslide must run")
    args = parser.parse_args()
    cmd = femslide_command()
    env = {k: v for k, v in os.environ.items() if k != "FEMSLIDE_KERNEL"}   # the install's own choice
    with tempfile.TemporaryDirectory() as cwd:
        version = run(cmd + ["--version"], cwd, env).strip().splitlines()
        if len(version) != 2 or not version[1].startswith("assembly: "):
            sys.exit(f"femslide --version printed {version}, not the version and the assembly")
        compiled = "compiled kernel" in version[1] and "not available" not in version[1]
        if args.expect == "compiled" and not compiled:
            sys.exit(f"the compiled kernel was expected: {version[1]}")
        if args.expect == "numpy" and compiled:
            sys.exit(f"the numpy path was expected: {version[1]}")
        out = json.loads(run(cmd + ["solve", "beam-slider", "--json"], cwd, env))
        ref = json.loads(run(cmd + ["solve", "beam-slider", "--json"], cwd, dict(env, FEMSLIDE_KERNEL="numpy")))
        module = run([sys.executable, "-c", "import femslide; print(femslide.__file__)"], cwd, env).strip()
    print(version[0])
    print(version[1])
    print(f"M_max {out['M_max']!r}")
    print(f"module {module}")
    if not (out.get("converged") and ref.get("converged")):
        sys.exit(f"beam-slider did not converge: {out.get('converged')}, numpy path {ref.get('converged')}")
    rel = abs(out["M_max"] - ref["M_max"]) / abs(ref["M_max"])
    print(f"M_max on the numpy path {ref['M_max']!r}: relative difference {rel:.2e} (<= 1e-9)", file=sys.stderr)
    if rel > 1e-9:
        sys.exit(f"M_max {out['M_max']!r} differs from the numpy path's {ref['M_max']!r} by {rel:.2e} > 1e-9")


if __name__ == "__main__":
    main()
