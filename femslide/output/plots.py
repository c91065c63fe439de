"""Pictures of engineering analyses (matplotlib, off-screen; nothing is drawn without matplotlib).

- ``envelope``: per rod, the bending moment M [N m] along the rod (arc length s [m] from its start) of
  every load combination, thin, and their envelope (the minimum and maximum at each s), shaded,
  with the governing extremes labelled;
- ``path``: a traced load path, the load factor against one output (its name and unit on the axis),
  limit points marked, full load dashed;
- ``buckling``: the rods of the base state (grey) and displaced along each buckling mode, one panel
  per mode with its load factor;
- :func:`ida_plot`: an incremental dynamic analysis (a dynamic sweep): the scale of the ground motion
  against the peak responses (the largest over rods, joints, storeys, bodies), one line per record;
- ``peaks``: a simulation's running peaks (the largest |value| so far of base moments, rod moments,
  slides, drifts, absolute accelerations) against time (``peaks_over_time.png`` of ``simulate --out``).

:func:`draw` draws a :class:`femslide.results.outcome.Figure` into a folder and returns its path.
"""
from __future__ import annotations

import os

import numpy as np


def _pyplot():
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return None
    return plt


def draw(fig, out_dir) -> str | None:
    """Draw ``fig`` (a Figure) into ``out_dir``; its path, or None without matplotlib."""
    plt = _pyplot()
    if plt is None:
        return None
    path = os.path.join(out_dir, fig.file)
    {"envelope": _envelope, "path": _path, "buckling": _buckling, "peaks": _peaks}[fig.kind](plt, fig.data, path)
    return path


def _envelope(plt, data, path):
    """data: {"rods": moment_envelope(...) result, "title": str}."""
    rods = data["rods"]
    n = max(len(rods), 1)
    fig, axes = plt.subplots(n, 1, figsize=(7, 2.6 * n + 0.6), squeeze=False)
    for ax, (rod, env) in zip(axes[:, 0], rods.items()):
        s = env["s"]
        ax.fill_between(s, env["M_min"], env["M_max"], color="tab:blue", alpha=0.18, lw=0,
                        label="envelope")
        for k, (combo, M) in enumerate(env["M"].items()):
            ax.plot(s, M, lw=0.9, label=combo, color=f"C{k % 10}")
        ax.plot(s, env["M_max"], color="k", lw=1.4)
        ax.plot(s, env["M_min"], color="k", lw=1.4)
        for arr, va in ((env["M_max"], "bottom"), (env["M_min"], "top")):
            i = int(np.argmax(np.abs(arr)))
            ax.annotate(f"{arr[i]:.4g}", (s[i], arr[i]), fontsize=8, ha="center", va=va)
        ax.axhline(0.0, color="0.6", lw=0.6)
        ax.set_ylabel(f"M of {rod} [N m]")
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=7, loc="best")
    axes[-1, 0].set_xlabel("s: arc length from the rod's start [m]")
    axes[0, 0].set_title(data.get("title", "bending moment envelope of the load combinations"))
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _path(plt, data, path):
    """data: {"x": output values, "lam": load factors, "label": the output's name and unit,
    "limits": [(x, refined lam)], "limits_at": the limit points' load factors on the traced path,
    "end": (x, lam) or None, "title": str}."""
    fig, ax = plt.subplots(figsize=(6, 4.2))
    ax.plot(data["x"], data["lam"], "-", lw=1.3, color="tab:blue", marker=".", ms=3)
    at = data.get("limits_at") or [lam for _, lam in data.get("limits", [])]
    for (x, lam), lam_path in zip(data.get("limits", []), at):
        ax.plot([x], [lam_path], "o", color="tab:red", ms=6)
        ax.annotate(f"limit {lam:.7g}", (x, lam_path), textcoords="offset points", xytext=(6, 4), fontsize=8)
    end = data.get("end")
    if end is not None:
        ax.plot([end[0]], [end[1]], "s", color="k", ms=5)
    ax.axhline(1.0, color="0.5", lw=0.8, ls="--")
    ax.set_xlabel(data["label"])
    ax.set_ylabel("load factor")
    ax.set_title(data.get("title", "load path"))
    ax.grid(True, alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _buckling(plt, data, path):
    """data: {"base": [rod node positions], "modes": [{"load_factor", "rods": [...]}], "title"}."""
    modes = data["modes"]
    n = len(modes)
    fig, axes = plt.subplots(1, n, figsize=(2.8 * n + 0.6, 4.0), squeeze=False)
    for ax, m in zip(axes[0], modes):
        for rod in data["base"]:
            p = np.asarray(rod)
            ax.plot(p[:, 0], p[:, 1], color="0.7", lw=1.0)
        for rod in m["rods"]:
            p = np.asarray(rod)
            ax.plot(p[:, 0], p[:, 1], color="tab:red", lw=1.6)
        ax.set_title(f"load factor {m['load_factor']:.6g}", fontsize=9)
        ax.set_aspect("equal", adjustable="datalim")
        ax.axis("off")
    fig.suptitle(data.get("title", "buckling modes"), fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _peaks(plt, data, path):
    """A simulation's running peaks: one panel per group (base moments, rod moments, slides, drifts,
    absolute accelerations), the largest |value| so far of each quantity against time."""
    groups = data["groups"]
    n = max(len(groups), 1)
    fig, axes = plt.subplots(n, 1, figsize=(7, 2.2 * n + 0.8), squeeze=False, sharex=True)
    for ax, (title, lines) in zip(axes[:, 0], groups.items()):
        for k, (c, y) in enumerate(lines.items()):
            ax.plot(data["t"], y, lw=1.0, color=f"C{k % 10}", label=c)
        ax.set_ylabel(title, fontsize=8)
        ax.grid(True, alpha=0.3)
        if len(lines) <= 8:
            ax.legend(loc="lower right", fontsize=6)
    axes[-1, 0].set_xlabel("t [s]")
    fig.suptitle(f"{data.get('name', '')}: peaks so far (largest |value| up to t)", fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


# the response quantities of an IDA curve: (title, unit, the flattened peak keys that count)
IDA_GROUPS = (("bending moment M_max", "N m", lambda k: k.startswith("peaks.rods.") and k.endswith(".M_max")),
              ("|slide|", "m", lambda k: k.startswith("peaks.joints.") and k.endswith((".slide_min", ".slide_max"))),
              ("inter-storey drift", "m", lambda k: k.startswith("peaks.drifts.")),
              ("absolute acceleration", "m/s^2",
               lambda k: k.startswith("peaks.bodies.") and k.endswith((".ax", ".ay"))),
              ("base moment", "N m", lambda k: k.startswith("peaks.reactions.") and k.endswith(".M")))


def _flat(row):
    from femslide.results.outcome import dotted
    return {k: v for k, v in dotted(row).items() if isinstance(v, (int, float)) and not isinstance(v, bool)}


def ida_plot(path, scene, names, cases, rows):
    """An IDA curve (PNG, PDF, SVG by extension): per response group (:data:`IDA_GROUPS`) a panel of
    the scale (``simulate.ground.scale``, else the first numeric varied parameter) against the
    group's largest peak |value| [SI], one line per value of the other varied parameters (a record
    suite: one line per record); cases that did not converge are left out (crosses at their
    peaks so far).  Returns the path, or None without matplotlib."""
    plt = _pyplot()
    if plt is None:
        return None
    x_name = "simulate.ground.scale" if "simulate.ground.scale" in names else next(
        (n for n in names if all(isinstance(c.get(n), (int, float)) for c in cases)), names[0])
    others = [n for n in names if n != x_name]
    flats = [_flat(r or {}) for r in rows]
    groups = [(t, u, f) for t, u, f in IDA_GROUPS if any(f(k) for fl in flats for k in fl)]
    if not groups:
        groups = [("peak", "-", lambda k: k.startswith("peaks."))]
    fig, axes = plt.subplots(1, len(groups), figsize=(3.6 * len(groups) + 0.8, 4.2), squeeze=False)
    lines = {}
    for c, r, fl in zip(cases, rows, flats):
        label = ", ".join(os.path.basename(str(c.get(n))) for n in others) or scene
        lines.setdefault(label, []).append((c.get(x_name), bool(r and r.get("converged")), fl))
    for ax, (title, unit, pick) in zip(axes[0], groups):
        for k, (label, pts) in enumerate(lines.items()):
            pts = sorted((p for p in pts if isinstance(p[0], (int, float))), key=lambda p: p[0])
            ok = [(max((abs(v) for kk, v in fl.items() if pick(kk)), default=np.nan), x) for x, good, fl in pts if good]
            bad = [(max((abs(v) for kk, v in fl.items() if pick(kk)), default=np.nan), x) for x, good, fl in pts
                   if not good]
            if ok:
                ax.plot([p[0] for p in ok], [p[1] for p in ok], "o-", color=f"C{k % 10}", ms=4, label=label)
            if bad:
                ax.plot([p[0] for p in bad], [p[1] for p in bad], "x", color=f"C{k % 10}", ms=7)
        ax.set_xlabel(f"peak {title} [{unit}]")
        ax.set_ylabel(x_name)
        ax.grid(True, alpha=0.3)
    axes[0][0].legend(loc="best", fontsize=7)
    fig.suptitle(f"femslide sweep {scene}: incremental dynamic analysis")
    fig.tight_layout()
    d = os.path.dirname(path)
    if d:
        os.makedirs(d, exist_ok=True)
    fig.savefig(path, dpi=100)
    plt.close(fig)
    return path

