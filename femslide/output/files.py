"""The files of a run: everything an :class:`femslide.results.outcome.Outcome` holds, written out.

:func:`write` is the one writer the application calls (``--out DIR``, ``Result.write``):

- a converged static solution: ``NAME.vtu`` and its sidecar ``NAME.json`` (femslide.output.vtu);
- tables: CSV files (``history.csv``, ...), one header line ``name [unit],...``;
- frames of a motion: ``NAME_0000.vtu``, ... and ``NAME.pvd`` (each frame with its time and the
  run's global values at that time as field data; cut forces from the elements, since a state of a
  motion is no static equilibrium);
- mode shapes: ``NAME_modeK.vtu`` and ``NAME_modes.pvd`` (timestep = the mode's number): the static
  equilibrium and the mode as ``displacement`` (largest translation 5 % of the structure's size), its
  linearised forces, the frequency as field data (:func:`mode_frame`);
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
    from femslide.output.vtu import describe, joint_data, load_data, mesh_data, write_series
    model = frames.model
    names = describe(model)

    def series():
        for t, y, alpha, values in frames.states:
            points, cells, pdata, cdata = mesh_data(model, y, alpha, cuts=element_cuts(model, y, alpha))
            yield t, points, cells, pdata, cdata, {**names, **joint_data(model, y), **load_data(model, y), **values}
    return write_series(series(), out_dir, name)


MODE_AMPLITUDE = 0.05   # a mode shape's largest translation, as a fraction of the structure's size
MODE_STEP = 1e-3        # model units: the difference step that linearises a mode's forces


def mode_multipliers(model, y, alpha, phi, frequency_hz):
    """The joints' multiplier rates of a mode: the small motion q = y + phi sin(omega t) is held by
    multipliers lam + dlam sin(omega t) with G^T dlam = omega^2 M phi - K phi (K, G the tangent and
    the joints' gradient at the static state); least squares (redundant joints are refused before)."""
    from femslide.analysis.modes import tangent
    from femslide.model.mass import Masses
    import scipy.sparse as sp
    if not model.n_c:
        return np.zeros(0)
    n_q = model.n_q
    K, G, _ = tangent(model, y, alpha_state(model, alpha))
    Mr, Mc, Mv = Masses(model).matrix(y[:n_q])
    M = sp.csc_matrix((Mv, (Mr, Mc)), shape=(n_q, n_q))
    w2 = (2.0 * np.pi * frequency_hz) ** 2
    rhs = w2 * (M @ phi) - K @ phi
    dlam, *_ = np.linalg.lstsq(G.toarray().T, rhs, rcond=None)
    return dlam


def alpha_state(model, alpha):
    """An element history at the committed chord rotations ``alpha`` (what Model.system takes)."""
    from femslide.model.state import ElementState
    return ElementState(np.array(alpha, float))


def mode_frame(model, y, alpha, phi, frequency_hz, amplitude=MODE_AMPLITUDE):
    """One mode shape as a VTU frame about the static state (y, alpha): (points, cells, point_data,
    cell_data, joint field data) in SI units.

    The points are the static equilibrium (the state the structure vibrates about); ``displacement``
    is the mode, scaled to a largest translation of ``amplitude`` times the structure's size; every
    other point, cell and joint value is the mode's linearised increment for that displacement (the
    static values not included): the derivative along the mode (multipliers by
    :func:`mode_multipliers`), by central differences of steps h and h/2 extrapolated (Richardson,
    error O(h^4)), so that a rigid motion carries no force - the second-order stretch and the
    third-order chord angle of a rotating rod drop out - and a pin carries no moment."""
    from femslide.output.vtu import joint_data, mesh_data
    n_q = model.n_q
    dy = np.concatenate([phi, mode_multipliers(model, y, alpha, phi, frequency_hz)])

    def state(eps):
        ye = y + eps * dy
        _, ae = model.element_forces(ye[:n_q], alpha)
        pts, cells, pd, cd = mesh_data(model, ye, ae, cuts=element_cuts(model, ye, ae))
        jd = joint_data(model, ye)
        flat = {**{("p", k): v for k, v in pd.items()},
                **{("c", k): np.concatenate([np.atleast_1d(b) for b in v]) for k, v in cd.items()
                   if k in ("axial_force", "shear_force")},
                **{("j", k): jd[k] for k in ("joint_position", "joint_force")}}
        return pts, cells, pd, cd, jd, flat

    def rate(h):
        plus, minus = state(h)[5], state(-h)[5]
        return {k: (plus[k] - minus[k]) / (2.0 * h) for k in plus}

    h = MODE_STEP
    p0, cells, pd0, cd0, jd0, _ = state(0.0)
    r1, r2 = rate(h), rate(0.5 * h)
    d = {k: amplitude * (4.0 * r2[k] - r1[k]) / 3.0 for k in r1}
    points = p0.copy()
    points[:, :2] += pd0["displacement"][:, :2]   # the static equilibrium
    pdata = {k: d[("p", k)] for k in pd0}
    sizes = [len(np.atleast_1d(b)) for b in cd0["axial_force"]]
    cdata = {}
    for k, blocks in cd0.items():
        if ("c", k) in d:
            cdata[k] = np.split(d[("c", k)], np.cumsum(sizes)[:-1])
        else:
            cdata[k] = blocks
    jd = dict(jd0)
    jd["joint_reference"] = jd0["joint_position"]
    jd["joint_position"] = jd0["joint_position"] + d[("j", "joint_position")]
    jd["joint_force"] = d[("j", "joint_force")]
    return points, cells, pdata, cdata, jd


def write_modes(modes, out_dir, name) -> list[str]:
    """One VTU per mode shape (``NAME_modeK.vtu``, :func:`mode_frame`) and ``NAME_modes.pvd``, whose
    timestep is the mode's number: ParaView steps through the modes as through time (and Warp By
    Vector with ``displacement`` draws each).  Returns the paths, the .pvd last."""
    from femslide.output.vtu import CONVENTIONS_TEXT, _write_vtu, describe, write_pvd
    model, y = modes.model, modes.y
    files, entries = [], []
    names = describe(model)
    for k, (f, phi) in enumerate(zip(modes.frequencies, modes.shapes)):
        points, cells, pdata, cdata, jd = mode_frame(model, y, modes.alpha, phi, f)
        fname = f"{name}_mode{k + 1}.vtu"
        path = os.path.join(out_dir, fname)
        fd = {**names, **jd, "points": MODE_POINTS, "conventions": CONVENTIONS_TEXT + MODE_CONVENTIONS,
              "mode": k + 1, "frequency_hz": float(f), "period_s": float(1.0 / f) if f > 0 else float("inf"),
              "time": float(k + 1)}
        _write_vtu(path, points, cells, pdata, cdata, fd)
        files.append(path)
        entries.append((float(k + 1), fname))
    if entries:
        files.append(write_pvd(os.path.join(out_dir, f"{name}_modes.pvd"), entries))
    return files


MODE_POINTS = ("equilibrium: the points are the static equilibrium the modes are about; points + "
               "displacement is the structure displaced along the mode (ParaView: Warp By Vector)")
MODE_CONVENTIONS = ("; mode shapes: displacement scaled to a largest translation of 5 % of the structure's "
                    "size, forces, moments and joint forces the linearised increments of that displacement "
                    "(the static ones not included); time = the mode's number")


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
