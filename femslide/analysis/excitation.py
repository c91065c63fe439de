"""Base excitation of the dynamics: a ground acceleration a_g(t) [m/s^2] along a fixed direction.

Two kinds (the ``ground`` entry of a structure file's ``[simulate]`` table):

- harmonic: ``{direction = [1, 0], amplitude = 1.0, frequency = 2.0}``: a_g = amplitude sin(2 pi f t)
  [m/s^2, Hz];
- record: ``{direction = [0, 1], record = "elcentro.AT2", scale = 1.0}``: a PEER NGA ``.AT2`` file
  (accelerations in g, a header line with NPTS and DT) or a CSV file of two columns t [s], a [m/s^2]
  (a header line allowed), linearly interpolated, zero after its end; times scaled by nothing, the
  accelerations by ``scale``.

Any direction, vertical too.  The structure's dofs are measured relative to the moving ground, so the
base acceleration enters as the inertia load -m a_g on every mass (:mod:`femslide.model.mass`).
"""
from __future__ import annotations

import math
import os
import re

import numpy as np

from femslide.errors import BadInput

G_STANDARD = 9.80665  # m/s^2: PEER NGA records are in units of g
MAX_ROWS = 1_000_000


class Ground:
    """a_g(t) e: ``direction`` e (unit (2,)), ``accel(t)`` [m/s^2] (scalar), ``dt`` the record's
    sampling interval (None for harmonic)."""

    def __init__(self, direction, amplitude=0.0, frequency=0.0, times=None, values=None):
        e = np.asarray(direction, float)
        self.direction = e / np.hypot(*e)
        self.amplitude, self.frequency = float(amplitude), float(frequency)
        self.times, self.values = times, values
        self.dt = None if times is None else float(np.min(np.diff(times))) if times.size > 1 else None

    def accel(self, t: float) -> float:
        if self.times is None:
            return self.amplitude * math.sin(2.0 * math.pi * self.frequency * t)
        return float(np.interp(t, self.times, self.values, left=0.0, right=0.0))


def read_at2(path: str):
    """(t [s], a [m/s^2]) of a PEER NGA .AT2 record (4 header lines; the 4th gives NPTS and DT)."""
    try:
        with open(path) as fh:
            lines = fh.read().splitlines()
    except (OSError, UnicodeDecodeError) as exc:
        raise BadInput(f"ground record {path}: cannot be read ({exc})") from None
    if len(lines) < 5:
        raise BadInput(f"ground record {path}: an .AT2 file needs 4 header lines and data")
    head = lines[3].upper()
    m_n = re.search(r"NPTS\s*=\s*([0-9]+)", head)
    m_dt = re.search(r"DT\s*=\s*([0-9.Ee+-]+)", head)
    if not m_n or not m_dt:
        raise BadInput(f"ground record {path}: the 4th line must give NPTS = n and DT = dt (PEER NGA format)")
    n, dt = int(m_n.group(1)), float(m_dt.group(1))
    if not 1 <= n <= MAX_ROWS or not dt > 0:
        raise BadInput(f"ground record {path}: NPTS = {n}, DT = {dt:g}; allowed: 1 <= NPTS <= {MAX_ROWS}, DT > 0")
    try:
        vals = np.array([float(x) for ln in lines[4:] for x in ln.replace(",", " ").split()])
    except ValueError:
        raise BadInput(f"ground record {path}: non-numeric data after the header") from None
    if vals.size < n:
        raise BadInput(f"ground record {path}: NPTS = {n} but only {vals.size} values")
    a = vals[:n] * G_STANDARD
    return np.arange(n) * dt, a


def read_csv(path: str):
    """(t [s], a [m/s^2]) of a CSV record: columns t, a (a header line, blank and # comment lines
    allowed), read by :func:`femslide.analysis.records.read_record`, the project's one CSV record reader."""
    from femslide.analysis.records import read_record
    t, a = read_record(path)
    return np.asarray(t, float), np.asarray(a, float)


def parse(spec, base_dir: str = ".", where: str = "simulate.ground") -> Ground | None:
    """A :class:`Ground` from the ``ground`` table (see the module docstring), or None."""
    if spec is None:
        return None
    if not isinstance(spec, dict):
        raise BadInput(f"{where}: expected a table {{direction, amplitude, frequency}} or {{direction, record, scale}}")
    allowed = {"direction", "amplitude", "frequency", "record", "scale"}
    bad = sorted(set(spec) - allowed)
    if bad:
        raise BadInput(f"{where}: unknown key {bad[0]!r}; allowed: {', '.join(sorted(allowed))}")
    d = spec.get("direction", [1.0, 0.0])
    try:
        e = [float(d[0]), float(d[1])]
        if len(d) != 2 or not all(map(math.isfinite, e)) or e == [0.0, 0.0]:
            raise ValueError
    except (TypeError, ValueError, IndexError):
        raise BadInput(f"{where}.direction = {d!r}; allowed: a nonzero vector [x, y]") from None

    def num(key, default, lo=-math.inf, lo_open=False):
        x = spec.get(key, default)
        try:
            v = float(x)
        except (TypeError, ValueError):
            raise BadInput(f"{where}.{key} = {x!r} is not a number") from None
        if not math.isfinite(v) or v < lo or (lo_open and v == lo):
            raise BadInput(f"{where}.{key} = {x!r}; allowed: a finite number {'>' if lo_open else '>='} {lo:g}")
        return v

    if "record" in spec:
        if "amplitude" in spec or "frequency" in spec:
            raise BadInput(f"{where}: give either a record (with scale) or amplitude and frequency, not both")
        path = spec["record"]
        if not isinstance(path, str):
            raise BadInput(f"{where}.record: a file name")
        path = path if os.path.isabs(path) else os.path.join(base_dir, path)
        if not os.path.isfile(path):
            raise BadInput(f"{where}.record: file {path} not found")
        t, a = read_at2(path) if path.upper().endswith(".AT2") else read_csv(path)
        return Ground(e, times=t, values=a * num("scale", 1.0))
    if "scale" in spec:
        raise BadInput(f"{where}.scale is for records; a harmonic ground motion has amplitude and frequency")
    return Ground(e, amplitude=num("amplitude", 1.0), frequency=num("frequency", 2.0, 0.0, lo_open=True))
