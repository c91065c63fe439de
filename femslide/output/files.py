"""The files of a run: everything an :class:`femslide.results.outcome.Outcome` holds, written out.

:func:`write` is the one writer the application calls (``--out DIR``, ``Result.write``):

- a converged static solution: ``NAME.vtu`` and its sidecar ``NAME.json`` (femslide.output.vtu);
- tables: CSV files (``history.csv``, ...), one header line ``name [unit],...``;
- frames of a motion: ``NAME_0000.vtu``, ... and ``NAME.pvd`` (each frame with its time and the
  run's global values at that time as field data; cut forces from the elements, since a state of a
  motion is no static equilibrium);
- mode shapes: ``NAME_modeK.vtu``, the structure displaced along mode K (largest translation 5 % of
  the structure's size, in model units), with its frequency as field data;
- hysteresis loops: ``hysteresis_JOINT.png`` (friction force against slide; nothing without
  matplotlib);
- more static solutions (load combinations): ``NAME_<key>.vtu`` and their sidecar JSON each;
- figures (femslide.output.plots: a moment envelope, a traced load path): PNG files (nothing without
  matplotlib).
"""
from __future__ import annotations

import os

import numpy as np

from femslide.results.outcome import Outcome
from femslide.results.static import element_cuts


def write(outcome: Outcome, out_dir: str) -> list[str]:
    """Write the outcome's files into ``out_dir`` (created if needed); returns their paths."""
    from femslide.output.vtu import write_static
    os.makedirs(out_dir, exist_ok=True)
    files = []
    if outcome.solution is not None:
        files += write_static(outcome.solution, out_dir, outcome.name, extra=outcome.static_values)
    for table in outcome.get_tables():
        files.append(write_table(table, out_dir))
    if outcome.frames is not None and outcome.frames.states:
        files += write_frames(outcome.frames, out_dir, outcome.name)
    if outcome.modes is not None:
        files += write_modes(outcome.modes, out_dir, outcome.name)
    if outcome.loops:
        files += write_loops(outcome.loops, out_dir, outcome.name)
    if outcome.buckling is not None:
        files += write_buckling(outcome.buckling, out_dir, outcome.name)
    for key, sol in outcome.solutions.items():
        files += write_static(sol, out_dir, f"{outcome.name}_{key}")
    if outcome.figures:
        from femslide.output.plots import draw
        files += [p for p in (draw(fig, out_dir) for fig in outcome.figures) if p]
    return files


def write_table(table, out_dir) -> str:
    """One CSV file of a :class:`femslide.results.outcome.Table`; returns its path."""
    path = os.path.join(out_dir, table.file)
    cols = [np.asarray(c) for c in table.columns]
    if any(c.dtype == object for c in cols):   # text columns (names) among numbers: keep each as it is
        cols = [c.astype(object) for c in cols]
    data = np.column_stack(cols) if cols else np.zeros((0, 0))
    np.savetxt(path, data, delimiter=",", header=",".join(table.header), fmt=table.fmt, comments="")
    return path


def write_frames(frames, out_dir, name) -> list[str]:
    """The PVD series of a motion's states (femslide.output.vtu.write_series): every frame with the
    names of the rods and bodies, the joints' field data at its state (femslide.output.vtu.joint_data)
    and the frame's own values (which win over those: e.g. a run's own ``units`` text)."""
    from femslide.output.vtu import describe, joint_data, mesh_data, write_series
    model = frames.model
    names = describe(model)

    def series():
        for t, y, alpha, values in frames.states:
            points, cells, pdata, cdata = mesh_data(model, y, alpha, cuts=element_cuts(model, y, alpha))
            yield t, points, cells, pdata, cdata, {**names, **joint_data(model, y), **values}
    return write_series(series(), out_dir, name)


def write_modes(modes, out_dir, name) -> list[str]:
    """One VTU per mode shape (see the module docstring)."""
    from femslide.output.vtu import _write_vtu, mesh_data
    model, y = modes.model, modes.y
    files = []
    for k, (f, phi) in enumerate(zip(modes.frequencies, modes.shapes)):
        yk = y.copy()
        yk[:model.n_q] += 0.05 * phi
        _, alpha_k = model.element_forces(yk[:model.n_q], modes.alpha)
        points, cells, pdata, cdata = mesh_data(model, yk, alpha_k, cuts=element_cuts(model, yk, alpha_k))
        path = os.path.join(out_dir, f"{name}_mode{k + 1}.vtu")
        _write_vtu(path, points, cells, pdata, cdata, {"mode": k + 1, "frequency_hz": float(f)})
        files.append(path)
    return files


def write_buckling(modes, out_dir, name) -> list[str]:
    """The buckling mode shapes as a PVD series ``NAME_buckling.pvd`` of VTU frames, the mode number as
    its time: the state displaced along each mode (largest translation 5 % of the structure's size),
    with its load factor as field data ``load_factor`` and ``mode``."""
    from femslide.output.vtu import describe, joint_data, mesh_data, write_series
    model, y = modes.model, modes.y
    names = describe(model)

    def series():
        for k, (lam, phi) in enumerate(zip(modes.load_factors, modes.shapes)):
            yk = y.copy()
            yk[:model.n_q] += 0.05 * phi
            _, alpha_k = model.element_forces(yk[:model.n_q], modes.alpha)
            points, cells, pdata, cdata = mesh_data(model, yk, alpha_k, cuts=element_cuts(model, yk, alpha_k))
            yield (k + 1, points, cells, pdata, cdata,
                   {**names, **joint_data(model, y), "mode": k + 1, "load_factor": float(lam)})
    return write_series(series(), out_dir, f"{name}_buckling")


def write_loops(loops, out_dir, name) -> list[str]:
    """A PNG per friction joint: friction force against slide (nothing without matplotlib)."""
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return []
    files = []
    for lp in loops:
        fig, ax = plt.subplots(figsize=(5, 4))
        ax.plot(lp.slide, lp.force, lw=0.8)
        ax.set_xlabel(f"slide of {lp.joint} [m]")
        ax.set_ylabel("friction force on a along the axis [N]")
        ax.set_title(f"{name}: {lp.joint}")
        ax.grid(True, alpha=0.3)
        fig.tight_layout()
        path = os.path.join(out_dir, f"hysteresis_{lp.joint}.png")
        fig.savefig(path, dpi=100)
        plt.close(fig)
        files.append(path)
    return files
