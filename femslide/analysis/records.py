"""Ground-acceleration records in CSV form: the one reader of a record file (t [s], a [m/s^2]).
"""
from __future__ import annotations

import math
import os

from femslide.errors import BadInput

MAX_RECORD_ROWS = 1_000_000       # each row is a segment boundary of the exact oscillator (~20 us each: 20 s)
MAX_RECORD_BYTES = 64 * 2**20     # a 1e6-row CSV of full-precision numbers is ~40 MB


def read_record(path: str):
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
            raise BadInput(f"parameter record: {path!r} line {lineno}: non-finite value")
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
