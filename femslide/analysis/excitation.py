"""Base excitation of the dynamics: a ground acceleration a_g(t) [m/s^2] along a fixed direction.

The one place where ground motion is read and evaluated: :class:`Record` (a sampled signal, linear
between its samples, zero outside them), the readers of record files (:func:`read_csv_record`,
:func:`read_at2`) and :class:`Ground` (harmonic and/or recorded acceleration along a direction) for
the FE dynamics; the exact one-mass oscillator (femslide.scenes.oscillator) takes its recorded
forcing from a :class:`Record` too.

Two kinds (the ``ground`` entry of a structure file's ``[simulate]`` table):

- harmonic: ``{direction = [1, 0], amplitude = 1.0, frequency = 2.0}``: a_g = amplitude sin(2 pi f t)
  [m/s^2, Hz];
- record: ``{direction = [0, 1], record = "elcentro.AT2", scale = 1.0}``: a PEER NGA ``.AT2`` file
  (accelerations in g; the 4th header line gives NPTS and DT, as ``NPTS= 4000, DT= .0050 SEC`` or the
  older ``4000  0.0050  NPTS, DT``) or a CSV file of two columns t [s], a [m/s^2]
  (a header line allowed), linearly interpolated, zero after its end; times scaled by nothing, the
  accelerations by ``scale``.

Any direction, vertical too.  The structure's dofs are measured relative to the moving ground, so the
base acceleration enters as the inertia load -m a_g on every mass (:mod:`femslide.model.mass`).
"""
from __future__ import annotations

import bisect
import math
import os
import re

from femslide.errors import BadInput

G_STANDARD = 9.80665  # m/s^2: PEER NGA records are in units of g
MAX_ROWS = 1_000_000
MAX_RECORD_ROWS = 1_000_000       # each row is a segment boundary of the exact oscillator (~20 us each: 20 s)
MAX_RECORD_BYTES = 64 * 2**20     # a 1e6-row CSV of full-precision numbers is ~40 MB
MAX_ACCEL = 1e6 * G_STANDARD      # m/s^2: no ground motion comes near 1e6 g; beyond, the inertia loads and
                                  # energies of the FE dynamics leave the float range (a 1e308 record: NaN)


class Record:
    """A sampled signal: ``values`` at ``times`` (strictly increasing lists of floats), linear between
    samples and zero outside them.  Pure Python (the exact oscillator must start without numpy)."""

    def __init__(self, times, values):
        self.times, self.values = list(times), list(values)

    def piece(self, t):
        """(p, q, t_next): the signal on [t, t_next) is p + q (s - t), until the next sample t_next
        (the piece that starts at t: zero from the last sample on)."""
        rt, rv = self.times, self.values
        i = bisect.bisect_right(rt, t) - 1
        if i < 0:
            return 0.0, 0.0, rt[0]
        if i >= len(rt) - 1:
            return 0.0, 0.0, math.inf
        q = (rv[i + 1] - rv[i]) / (rt[i + 1] - rt[i])
        return rv[i] + q * (t - rt[i]), q, rt[i + 1]

    def value(self, t):
        """The signal at t, continuous from the left at the last sample (the input at the end of a
        time step that ends there)."""
        rt = self.times
        if not rt[0] <= t <= rt[-1]:
            return 0.0
        if t == rt[-1]:
            return float(self.values[-1])
        return self.piece(t)[0]

    def eval_np(self, t):
        """The pieces that start at the times t (numpy array), as :meth:`piece`."""
        import numpy as np
        t = np.asarray(t, dtype=float)
        rt = np.asarray(self.times)
        inside = (t >= rt[0]) & (t < rt[-1])
        return np.where(inside, np.interp(t, rt, np.asarray(self.values)), 0.0)


class Ground:
    """a_g(t) e: ``direction`` e (unit (2,)), ``accel(t)`` [m/s^2] (scalar) = amplitude
    sin(2 pi frequency t) + record(t) (either or both); ``times`` the record's sample times (numpy,
    None without a record) and ``dt`` their smallest interval."""

    def __init__(self, direction, amplitude=0.0, frequency=0.0, record: Record | None = None):
        import numpy as np
        e = np.asarray(direction, float)
        self.direction = e / np.hypot(*e)
        self.amplitude, self.frequency = float(amplitude), float(frequency)
        self.harmonic = self.amplitude != 0.0 and self.frequency > 0.0
        self.record = record
        self.times = None if record is None else np.asarray(record.times, float)
        self.dt = float(np.min(np.diff(self.times))) if self.times is not None and self.times.size > 1 else None
        self._vcum = None   # the record's velocity at its samples (computed when first asked for)

    def accel(self, t: float) -> float:
        a = self.amplitude * math.sin(2.0 * math.pi * self.frequency * t) if self.harmonic else 0.0
        return a + self.record.value(t) if self.record is not None else a

    def velocity(self, t: float) -> float:
        """The ground's velocity [m/s] along the direction at t, from rest at t = 0: exact for the
        harmonic part (amplitude (1 - cos(2 pi f t)) / (2 pi f)) and for the record, linear between
        its samples (trapezoids, plus the quadratic within the current sample interval)."""
        v = 0.0
        if self.harmonic:
            w = 2.0 * math.pi * self.frequency
            v = self.amplitude * (1.0 - math.cos(w * t)) / w
        if self.record is not None and t > self.record.times[0]:
            if self._vcum is None:
                rt, rv = self.record.times, self.record.values
                cum = [0.0]
                for k in range(1, len(rt)):
                    cum.append(cum[-1] + 0.5 * (rv[k] + rv[k - 1]) * (rt[k] - rt[k - 1]))
                self._vcum = cum
            rt = self.record.times
            i = min(bisect.bisect_right(rt, t) - 1, len(rt) - 1)
            if i >= len(rt) - 1:
                v += self._vcum[-1]
            else:
                p, q, _ = self.record.piece(rt[i])
                d = t - rt[i]
                v += self._vcum[i] + p * d + 0.5 * q * d * d
        return v


def at2_header(line: str):
    """(NPTS, DT [s]) of the 4th header line of a PEER .AT2 file, either form: the NGA-West2 one
    ``NPTS=  4000, DT=   .0050 SEC`` or the older ``4000   0.0050   NPTS, DT`` (the numbers first,
    labelled after them); None if the line is neither."""
    head = line.upper()
    m_n = re.search(r"NPTS\s*=\s*([0-9]+)", head)
    m_dt = re.search(r"DT\s*=\s*([0-9.Ee+-]+)", head)
    if m_n and m_dt:
        n, dt = m_n.group(1), m_dt.group(1)
    else:
        m = re.match(r"\s*([0-9]+)[\s,]+([0-9.Ee+-]+)[\s,]+NPTS\s*,?\s*DT\b", head)
        if not m:
            return None
        n, dt = m.group(1), m.group(2)
    try:
        return int(n), float(dt)
    except ValueError:
        return None


def read_at2(path: str):
    """(t [s], a [m/s^2]) (lists) of a PEER NGA .AT2 record: 4 header lines, the 4th giving NPTS and
    DT in either form (:func:`at2_header`), then the accelerations in g, any number per line.  A
    value that is not a finite number is bad input naming the file and line."""
    try:
        with open(path) as fh:
            lines = fh.read().splitlines()
    except (OSError, UnicodeDecodeError) as exc:
        raise BadInput(f"ground record {path}: cannot be read ({exc})") from None
    if len(lines) < 5:
        raise BadInput(f"ground record {path}: an .AT2 file needs 4 header lines and data")
    found = at2_header(lines[3])
    if found is None:
        raise BadInput(f"ground record {path} line 4: {lines[3].strip()[:60]!r}; allowed: 'NPTS= n, DT= dt SEC' "
                       f"or 'n  dt  NPTS, DT' (PEER NGA format)")
    n, dt = found
    if not 1 <= n <= MAX_ROWS or not dt > 0:
        raise BadInput(f"ground record {path}: NPTS = {n}, DT = {dt:g}; allowed: 1 <= NPTS <= {MAX_ROWS}, DT > 0")
    vals = []
    for lineno, ln in enumerate(lines[4:], 5):
        for x in ln.replace(",", " ").split():
            try:
                v = float(x)
            except ValueError:
                raise BadInput(f"ground record {path} line {lineno}: {x[:30]!r} is not a number") from None
            if not math.isfinite(v):
                raise BadInput(f"ground record {path} line {lineno}: {x[:30]!r}; allowed: finite accelerations "
                               f"[g]") from None
            vals.append(v)
    if len(vals) < n:
        raise BadInput(f"ground record {path}: NPTS = {n} but only {len(vals)} values")
    return [k * dt for k in range(n)], [x * G_STANDARD for x in vals[:n]]


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
        if isinstance(d, str) or any(isinstance(c, (str, bool)) for c in d):
            raise ValueError
        e = [float(d[0]), float(d[1])]
        if len(d) != 2 or not all(map(math.isfinite, e)) or e == [0.0, 0.0]:
            raise ValueError
    except (TypeError, ValueError, IndexError):
        raise BadInput(f"{where}.direction = {d!r}; allowed: a nonzero vector [x, y]") from None

    def num(key, default, lo=-math.inf, lo_open=False):
        x = spec.get(key, default)
        if isinstance(x, (str, bool)):
            raise BadInput(f"{where}.{key} = {x!r} is not a number; allowed: a number (without quotes)")
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
        t, a = read_at2(path) if path.upper().endswith(".AT2") else read_csv_record(path)
        scale = num("scale", 1.0)
        peak = max(abs(x) for x in a) * abs(scale)
        if not peak <= MAX_ACCEL:
            i = max(range(len(a)), key=lambda k: abs(a[k]))
            raise BadInput(f"{where}.record: {path} reaches |a| = {peak:.3g} m/s^2 (scale {scale:g}) at t = "
                           f"{t[i]:g} s; allowed: |a| <= {MAX_ACCEL:.3g} m/s^2 (1e6 g)")
        return Ground(e, record=Record(t, [x * scale for x in a]))
    if "scale" in spec:
        raise BadInput(f"{where}.scale is for records; a harmonic ground motion has amplitude and frequency")
    amplitude = num("amplitude", 1.0)
    if abs(amplitude) > MAX_ACCEL:
        raise BadInput(f"{where}.amplitude = {amplitude:g} m/s^2; allowed: |amplitude| <= {MAX_ACCEL:.3g} m/s^2 "
                       f"(1e6 g)")
    return Ground(e, amplitude=amplitude, frequency=num("frequency", 2.0, 0.0, lo_open=True))


def read_csv_record(path: str):
    """Read a base-acceleration record: CSV with columns t [s], a [m/s^2].

    One header line (non-numeric first field) and blank or ``#`` comment lines are allowed; times
    must be finite and strictly increasing, at least two rows.  Returns ``(times, accelerations)``
    as lists of floats.  Raises :class:`BadInput` naming ``record`` otherwise.
    """
    allowed = "a readable CSV text file with columns t [s], a [m/s^2]"
    try:
        size = os.path.getsize(path)
        if size > MAX_RECORD_BYTES:
            raise BadInput(f"parameter record: {path!r} is {size / 2**20:.0f} MiB; allowed: {allowed} "
                           f"of at most {MAX_RECORD_BYTES // 2**20} MiB and {MAX_RECORD_ROWS} rows")
        with open(path, newline="", encoding="utf-8") as fh:
            text = fh.read()
    except OSError as exc:
        raise BadInput(f"parameter record: cannot read {path!r} ({exc.strerror or exc}); "
                       f"allowed: {allowed}") from None
    except (UnicodeDecodeError, ValueError) as exc:
        raise BadInput(f"parameter record: {path!r} is not text ({exc}); allowed: {allowed}") from None
    ts, acc = [], []
    seen_data = False
    for lineno, line in enumerate(text.splitlines(), 1):
        s = line.strip()
        if not s or s.startswith("#"):
            continue
        parts = [p.strip() for p in s.replace(";", ",").split(",")]
        if len(parts) == 1:
            parts = s.split()
        try:
            if len(parts) < 2:
                raise ValueError
            t, a = float(parts[0]), float(parts[1])
        except ValueError:
            if not seen_data and not ts:
                seen_data = True  # the header line
                continue
            raise BadInput(f"parameter record: {path!r} line {lineno}: expected two numbers "
                           f"'t, a', got {s[:60]!r}") from None
        seen_data = True
        if not (math.isfinite(t) and math.isfinite(a)):
            raise BadInput(f"parameter record: {path!r} line {lineno}: {s[:60]!r} is not finite; allowed: "
                           f"finite numbers t [s], a [m/s^2]")
        if ts and not t > ts[-1]:
            raise BadInput(f"parameter record: {path!r} line {lineno}: times must be strictly "
                           f"increasing (t = {t:g} s after {ts[-1]:g} s)")
        ts.append(t)
        acc.append(a)
        if len(ts) > MAX_RECORD_ROWS:
            raise BadInput(f"parameter record: {path!r} has more than {MAX_RECORD_ROWS} data rows; "
                           f"allowed: at most {MAX_RECORD_ROWS} rows (each is a segment of the exact "
                           f"solution; resample the record)")
    if len(ts) < 2:
        raise BadInput(f"parameter record: {path!r} has {len(ts)} data rows; "
                       f"allowed: a CSV file with at least two rows 't, a'")
    return ts, acc


def synthetic_record(duration: float = 20.0, dt: float = 0.01, pga: float = 3.0, f_g: float = 2.5,
                     zeta_g: float = 0.6, rise: float = 2.0, strong: float = 8.0, decay: float = 0.25,
                     seed: int = 0):
    """A synthetic ground acceleration (not a recorded earthquake): white noise through the
    Kanai-Tajimi filter (a ground layer of frequency ``f_g`` [Hz] and damping ratio ``zeta_g``:
    a_g = 2 zeta_g w_g x' + w_g^2 x with x'' + 2 zeta_g w_g x' + w_g^2 x = -w(t), integrated exactly
    for piecewise-constant noise), times the Jennings-Housner-Tsai envelope (t/rise)^2 up to
    ``rise`` [s], 1 up to ``rise + strong``, exp(-decay (t - rise - strong)) after, ending at zero,
    scaled to the peak ground acceleration ``pga`` [m/s^2].  ``seed`` selects the noise.  Returns
    (t [s], a [m/s^2]) numpy arrays, n = round(duration / dt) + 1 samples."""
    import numpy as np
    from scipy.linalg import expm
    n = int(round(duration / dt)) + 1
    t = np.arange(n) * dt
    w = np.random.default_rng(seed).standard_normal(n)
    wg = 2.0 * math.pi * f_g
    A = np.array([[0.0, 1.0], [-wg * wg, -2.0 * zeta_g * wg]])
    E = expm(A * dt)
    Bd = np.linalg.solve(A, (E - np.eye(2)) @ np.array([0.0, -1.0]))   # exact for a constant input
    x = np.zeros(2)
    a = np.zeros(n)
    for k in range(n):                   # (a filter: one 2x2 product per sample)
        a[k] = 2.0 * zeta_g * wg * x[1] + wg * wg * x[0]
        x = E @ x + Bd * w[k]
    env = np.where(t < rise, (t / rise) ** 2, np.where(t < rise + strong, 1.0, np.exp(-decay * (t - rise - strong))))
    a *= env
    a -= np.linspace(0.0, 1.0, n) * a[-1]   # ends at zero
    a[0] = 0.0
    peak = np.abs(a).max()
    return t, a * (pga / peak if peak > 0 else 0.0)


def write_csv_record(path: str, t, a) -> str:
    """Write a record as CSV (header ``t,a``; t [s], a [m/s^2]) that :func:`read_csv_record` reads."""
    with open(path, "w") as fh:
        fh.write("t,a\n")
        fh.writelines(f"{float(x)!r},{float(y)!r}\n" for x, y in zip(t, a))
    return path

