"""What the pictures write on a structure besides its diagrams: load and reaction arrows, the moment
in every sliding bearing, the unit of the numbers (N or kN) and even colour-bar ticks.

Used by :func:`femslide.plot` (matplotlib) and ``femslide show`` (pyvista) alike, from the frame data
of :func:`femslide.output.diagrams.frame_data`:

- loads: an arrow per point load (force [N] on a body or a rod end, at its point of application in
  the drawn configuration) pointing at its point, its name and value written at its tail; a
  distributed load (cell data ``distributed_load``, N/m) as a row of arrows along its rod with one
  label; the moment of a point load in the label;
- reactions: an arrow per support, the force of the ground on the structure, pointing at the support,
  labelled with its components and its moment;
- the moment in every sliding bearing (a joint drawn as a sleeve: a slider, whose guide transmits a
  moment): ``NAME: M = ...`` at the joint, the moment part b exerts on part a (what the paper's users
  study);
- ``units="kN"`` writes forces in kN, moments in kN m and distributed loads in kN/m (default "N").

All arrows have one length (ARROW_FRACTION of the structure's size): the label carries the value.
"""
from __future__ import annotations

import math

ARROW_FRACTION = 0.12     # length of an arrow, as a fraction of the structure's size
UNITS = {"N": 1.0, "kN": 1e-3}


def check_units(units: str) -> float:
    """The factor from N to ``units`` ("N" or "kN"), else BadInput."""
    from femslide.errors import BadInput
    if units not in UNITS:
        raise BadInput(f"units = {units!r}; allowed: N (N, N m, N/m) or kN (kN, kN m, kN/m)")
    return UNITS[units]


def unit_label(unit: str, units: str = "N") -> str:
    """A force unit ("N", "N m", "N/m") in ``units``: "kN", "kN m", "kN/m"."""
    return unit.replace("N", units, 1) if unit.startswith("N") else unit


def value_text(v: float, unit: str, units: str = "N") -> str:
    """``v`` [N, N m or N/m] written in ``units`` with 4 significant digits and the unit."""
    f = check_units(units)
    x = v * f
    return f"{x:.4g} {unit_label(unit, units)}"


def nice_ticks(lo: float, hi: float, n: int = 5) -> list[float]:
    """Round tick values inside [lo, hi]: steps of 1, 2 or 5 times a power of ten, about ``n`` of
    them (the colour bar of 1.2e+04, 1.37e+04, ... becomes 12000, 14000, ...)."""
    if not (math.isfinite(lo) and math.isfinite(hi)) or hi <= lo:
        return [lo]
    raw = (hi - lo) / max(n - 1, 1) / 1.6   # at least about n - 1 ticks inside the range
    p = 10.0 ** math.floor(math.log10(raw))
    step = next(m * p for m in (1.0, 2.0, 2.5, 5.0, 10.0) if m * p >= raw)
    first = math.ceil(lo / step - 1e-9) * step
    ticks = []
    t = first
    while t <= hi * (1 + 1e-12) + 1e-12 * abs(step):
        ticks.append(0.0 if abs(t) < 1e-9 * step else float(f"{t:.12g}"))
        t += step
    return ticks


def arrows(fr, units: str = "N", size: float | None = None):
    """Arrows of the loads and reactions of a frame (see the module docstring): a list of dicts
    ``{"kind": "load" | "distributed" | "reaction", "tail", "head"`` (drawn points [m]), ``"label"``
    (or None for the unlabelled arrows of a distributed load)}."""
    import numpy as np

    size = size_of(fr) if size is None else size
    ell = ARROW_FRACTION * size
    out = []

    def arrow(kind, head, f, label):
        f = np.asarray(f, float)[:2]
        n = float(np.hypot(*f))
        if n == 0.0:
            return
        head = np.asarray(head, float)
        out.append({"kind": kind, "tail": head - ell * f / n, "head": head, "label": label})

    for ld in fr.get("loads", []):
        fx, fy, m = ld["force"]
        text = f"{ld['name']}: {value_text(math.hypot(fx, fy), 'N', units)}"
        if m:
            text += f", M = {value_text(m, 'N m', units)}"
        if fx or fy:
            arrow("load", ld["X"], (fx, fy), text)
        elif m:
            out.append({"kind": "load", "tail": np.asarray(ld["X"], float), "head": np.asarray(ld["X"], float),
                        "label": text})
    for r in fr["rods"]:
        q = np.asarray(r.get("q", np.zeros((0, 2))), float)
        if not q.size or not np.any(q):
            continue
        X = np.asarray(r["X"], float)
        # one arrow at every k-th node of the loaded elements, the one nearest the middle labelled
        k = max(1, (len(X) - 1) // 6)
        qmax = q[np.argmax(np.hypot(q[:, 0], q[:, 1]))]
        stations = [i for i in range(0, len(X), k) if np.any(q[min(i, len(q) - 1)])]
        mid = min(stations, key=lambda i: abs(i - (len(X) - 1) / 2))
        for i in stations:
            label = f"{r['name']}: q = {value_text(float(np.hypot(*qmax)), 'N/m', units)}" if i == mid else None
            arrow("distributed", X[i], q[min(i, len(q) - 1)], label)
    for j in fr["joints"]:
        if not j["ground"] or not np.all(np.isfinite(j["force"])):
            continue
        fx, fy, m = j["force"]
        text = f"{j['name']}: Fx = {value_text(fx, 'N', units)}, Fy = {value_text(fy, 'N', units)}"
        if m:
            text += f", M = {value_text(m, 'N m', units)}"
        if fx or fy:
            arrow("reaction", j["X"], (fx, fy), text)
    return out


def bearing_labels(fr, units: str = "N"):
    """[(point [m], text)]: the moment transmitted by every sliding bearing (a joint drawn as a
    sleeve), ``NAME: M = ...``."""
    import numpy as np
    out = []
    for j in fr["joints"]:
        if j.get("symbol") == "sleeve" and np.all(np.isfinite(j["force"])):
            text = f"{j['name']}: M = {value_text(float(j['force'][2]), 'N m', units)}"
            out.append((np.asarray(j["X"], float), text))
    return out


def size_of(fr) -> float:
    """Largest extent [m] of the drawn structure (undeformed and drawn shapes)."""
    import numpy as np
    pts = [r[k] for r in fr["rods"] for k in ("X", "X0")] + [b[k] for b in fr["bodies"] + fr["links"]
                                                              for k in ("X", "X0")]
    pts += [np.array([j["X0"]]) for j in fr["joints"]]
    if not pts:
        return 1.0
    P = np.concatenate(pts)
    return float(np.ptp(P, axis=0).max()) or 1.0
