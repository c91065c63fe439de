"""`femslide simulate` of a declared structure: a structure file's ``[simulate]`` table run in time.

    [simulate]
    t_end = 10.0                                   # s
    tolerance = 1e-6                               # local error tolerance (relative), 1e-12 .. 1e-2
    damping = {alpha = 0.0, beta = 0.0}            # Rayleigh: C = alpha M + beta K0 [1/s, s]
    # (also rotation = {deck = 0.5}: a rotational dashpot c [N m s/rad] on a body's rotation)
    ground = {direction = [1.0, 0.0], amplitude = 1.0, frequency = 2.0}   # or {direction, record, scale}
    initial = {body = "deck", rotation = -0.01}    # or u = [dx, dy]; or {joint = "belt", slide = 0.07}
    elements = 8                                   # elements per rod without its own `elements`
    output_interval = 0.01                         # s: the history's rows at its multiples (default: every step)

The run: the static equilibrium under the loads (femslide.analysis.static, on the fixed mesh; a structure
that is a mechanism without friction - a block on a ground slider without a spring - starts from the
equilibrium with its friction joints stuck), held - if
``initial`` says so - at a body's rotation [rad] and/or centroid displacement u [m] (its component
along u is held, the rest of the structure in equilibrium: the body pulled along u) or at a slider's
slide [m] (an extra exact constraint, walked there in small steps), then released at rest and
integrated to ``t_end`` (femslide/analysis/transient.py: Radau IIA, adaptive step).  The lowest natural
frequencies of the frictionless structure about the static equilibrium (femslide/analysis/modes.py) are
reported as ``frequencies_hz`` (a direction free of stiffness, a base on a frictionless slider, as a
zero frequency); a structure with friction joints also reports ``frequency_sets`` {``stuck``: every
friction joint locked, ``free``: frictionless} (femslide/analysis/friction_modes.py).

Damping: Rayleigh C = alpha M0 + beta K0 (about the static state), plus rotational dashpots
(``damping.rotation``, :attr:`Spec.rotation_damping`): a body's moment -c theta' [N m] with c in
N m s/rad, i.e. c / (Fref Lref) [s] on the diagonal of C at the body's rotation dof (model units).

Result (SI): ``converged``, ``steps``, ``t_end``, ``energy_balance`` (kinetic + potential +
dissipated - work in, relative to the largest of them over the run), ``events`` (per friction joint:
[{t, kind}], kind "stick", "slip+" or "slip-", the first at t = 0 the joint's mode at the start;
femslide/joints/friction.py),
(contacts, ``unilateral`` sliders and rollers: "lift" and "land", femslide/analysis/stickslip.py),
``frequencies_hz``, ``peaks`` {``reactions``: {NAME: {Fx, Fy, M}} largest |value| over time,
``rods``: {NAME: {M_max}}, ``joints``: {NAME: {slide_min, slide_max[, gap_max]}}}, ``wall_time_s``; ``--out DIR``
writes ``history.csv`` (every reported quantity at every accepted step; friction joints also their
friction force on a along the axis), a PVD series of VTU frames (each frame's time and global values
as field data) and, with matplotlib, ``hysteresis_JOINT.png`` (friction force against slide).
History columns (SI): ``t``; ``reactions.NAME.Fx, Fy, M`` (forces of the ground on the structure);
``rods.NAME.M_max``; per slider and roller ``joints.NAME.slide`` and ``joints.NAME.normal`` (N: |transverse
force|, with a bearing the sum of its two contact forces' magnitudes, as friction takes it); per body
``bodies.NAME.x, y`` (centroid), ``rotation``, ``rotation_rate`` [rad/s] and ``rotation_accel``
[rad/s^2] (counter-clockwise positive, relative to the moving ground); per friction joint
``joints.NAME.friction``.  A friction event has two rows at its time: the state before the switch
(the left limit of the forces that jump there) and after it.

Long runs: a run is never refused for its length, only absurd inputs are bad input up front: a run
estimated (steps per period of the lowest mode at the tolerance, :func:`steps_per_period`, times a
measured cost per step) beyond ABSURD_WORK_S (24 h) of work, or t_end beyond MAX_PERIODS (1e6)
periods of the lowest mode; the step count is limited at run time only as a runaway's safety net
(RUNAWAY times the estimate).  No built-in wall-time limit: ``max_time`` [s] (``--max-time``, default
none) is the user's, beyond which the run stops cleanly (SolverFailure naming it), the history so far
kept on the exception (``exc.outcome``, written by ``--out``).
Sliders and rollers with ``mu`` carry Coulomb friction (femslide/joints/friction.py: exact stick, events
located in time); the static start ignores friction.

Error estimate (``error_estimate``, on by default): a check run from the same start at CHECK_FACTOR (10)
times the tolerance (:func:`_check_run`), compared with the run
(femslide.analysis.accuracy.estimate_error; promise_note says whether the estimate is within the promise
of the tolerance). It needs nothing of the run, so where a second CPU is there (Linux) it runs beside the run
in a forked process (femslide.analysis.forked; ``FEMSLIDE_CHECK_RUN=serial`` keeps it after the run):
the same values, bit for bit, for the CPU time of a check run and little wall time. A run that fails
stops its check run; a check run stopped by ``max_time`` stops the simulate as it would after the run.
"""
from __future__ import annotations

import math
import time

import numpy as np

from femslide.analysis.accuracy import check_trust, estimate_error, promise_note
from femslide.analysis.forked import ChildLost, Forked
from femslide.errors import BadInput, SolverFailure
from femslide.joints.kinds import kind_of
from femslide.model.linalg import Coo
from femslide.records import replace
from femslide.results.outcome import Figure, Frames, Loop, ModeShapes, Outcome, Table
from femslide.results.history import _peaks
from femslide.results.seismic import drift_columns, drifts, residuals, running_peaks, storey_pairs
from femslide.analysis.workload import (  # noqa: F401  (check_work and steps_per_period: also imported from here)
    ABSURD_WORK_S, MAX_PERIODS, check_release, check_work, steps_per_period)
from femslide.analysis.start import contact_start, stuck_statics as _stuck_statics
from femslide.analysis.simspec import (  # noqa: F401  (the [simulate] table's parsing: also imported from here)
    DEFAULT_ELEMENTS, SIM_KEYS, Spec, parse_elements, parse_spec)

MODES = 6
FRAMES = 200                 # at most this many VTU frames in --out


def _has_friction(j):
    """Whether joint j has friction: a mu, and mu0 > 0 (mu0 = 0 is an ordinary slider or roller)."""
    return j.mu is not None and j.mu0 > 0.0


def _model_like(fs, m):
    """The model of ``fs`` on the mesh and in the units of the model ``m``."""
    from femslide.model.discrete import Model
    counts = {r.name: r.elements for r in fs.rods}
    return Model(fs, counts, m.Lref, m.Fref)


def _fixed_mesh(fs, n):
    """The frozen structure with every rod's mesh fixed (``n`` elements unless the rod has its own)."""
    rods = tuple(r if r.elements else replace(r, elements=n) for r in fs.rods)
    return replace(fs, rods=rods, derived={})


def rayleigh_damping(model, masses, y, elements, alpha, beta):
    """C = alpha M + beta K0 (femslide.model.linalg.Coo, model units): the mass matrix and the symmetric
    part of the static tangent's stiffness block at the static state (y, elements) (K0 = (K + K^T) / 2:
    elements, springs, the joints' Hessians weighted by their multipliers, turning loads)."""
    n_q = model.n_q
    r, c, v = masses.matrix(y[:n_q])
    C = Coo(r, c, alpha * v, n_q)   # (each entry scaled, then the duplicates summed)
    if beta:
        _, (r, c, v), _ = model.system(y, elements, 1.0, None, True, dense="coo")
        elements.revert()
        k = (r < n_q) & (c < n_q)
        K = Coo(r[k], c[k], v[k], n_q)   # (its duplicates summed first, as scipy did: the same C bit for bit)
        C = C + (0.5 * beta) * (K + K.T)
    return C


def rotation_dampers(model, dampers, C=None):
    """C (femslide.model.linalg.Coo or scipy sparse, model units, or None) plus a rotational dashpot on
    each named body's rotation dof: ``dampers`` {body: c [N m s/rad]}, entered as c / (Fref Lref) [s] (a
    moment -c theta'); a Coo."""
    rows, vals = [], []
    for name, c in dampers.items():
        if name not in model.body_index:
            raise BadInput(f"[simulate] damping.rotation.{name}: no such body; bodies: "
                           f"{', '.join(model.body_index) or 'none'}")
        rows.append(model.body_dof(name) + 2)
        vals.append(float(c) / (model.Fref * model.Lref))
    D = Coo(rows, rows, vals, model.n_q)
    return D if C is None else D + C


BESIDE_SHARE = 0.95    # of the progress bar for the run when its check run runs beside it


def _check_run(spec, run_at, new_friction, peaks_of, T1, progress=None):
    """The check run of the error estimate (see the module docstring): the integration at
    CHECK_FACTOR times the tolerance from the run's start, as what
    femslide.analysis.accuracy.estimate_error compares -
    {"steps", "H" (its history), "events", "peaks", "time_s"} - or {"failed": the reason's first
    line} when it fails; the user's time limit (``max_time``) raises.  It needs nothing of the run
    it checks: simulate runs it beside the run where it can (femslide.analysis.forked)."""
    from femslide.analysis.transient import CHECK_FACTOR
    t0 = time.perf_counter()
    fr_c = new_friction()
    if fr_c is not None:   # (its contacts come to rest and rebound as the run's, and its touches of a
        # breakaway bound are the run's: the same thresholds)
        fr_c.tolerance = spec.tolerance
        fr_c.resolution = 0.1 * spec.tolerance * T1
    try:
        run_c, Hc = run_at(CHECK_FACTOR * spec.tolerance, fr_c, False, progress)
    except SolverFailure as exc:
        if getattr(exc, "time_limit", False):   # the user's max_time: the run stops (simulate)
            raise
        return {"failed": str(exc).splitlines()[0]}
    return {"steps": run_c.steps, "H": Hc, "events": fr_c.events if fr_c is not None else {},
            "peaks": peaks_of(Hc, fr_c), "time_s": time.perf_counter() - t0}


def simulate(fs, spec: Spec, name="structure", progress=None) -> Outcome:
    """Run the dynamics of a frozen structure (see the module docstring): the outcome's values are
    the JSON object, its history {column: array} (``t`` first, then the columns of history.csv), its
    tables history.csv, its frames the states for the VTU series and its loops the friction joints'
    hysteresis."""
    from femslide.analysis import static
    from femslide.analysis.modes import modes
    from femslide.analysis.refine import moment_watch
    from femslide.analysis.transient import integrate
    from femslide.model.mass import Masses
    from femslide.results.static import joint_forces

    t_wall = time.perf_counter()
    fs = _fixed_mesh(fs, spec.elements)
    frequencies_of = "frictionless structure"
    lifted_static = ()
    try:
        # (only the state is used: the static error estimate watches the largest moment alone)
        sol = static.solve(fs, watch=moment_watch)
        model, y_s, e_s = sol.level.model, sol.level.y, sol.level.elements
        if sol.lifted:   # contacts the statics released: the dynamics' model has every joint (it releases them)
            from femslide.analysis.start import carry
            full = _model_like(fs, model)
            model, y_s, lifted_static = full, carry(model, y_s, full, full.n), tuple(sol.lifted)
    except SolverFailure as exc:
        if not any(j.mu is not None for j in fs.joints):
            raise
        # frictionless, the structure has no equilibrium of its own (a block on a ground slider
        # without a spring): at rest its friction joints are stuck - solve the statics so
        # (a stuck slider holds like a weld, a stuck roller like a pin) and start from there.  A
        # joint declared with mu0 = 0 is held so too for the start only (at rest, released at t = 0)
        sol = _stuck_statics(fs, exc)
        model = _model_like(fs, sol.level.model)
        y_s = np.zeros(model.n)
        y_s[:model.n_q] = sol.level.y[:model.n_q]
        e_s = sol.level.elements
        frequencies_of = "frictionless structure (it has no equilibrium of its own: about the static state " \
                         "with its friction joints stuck; a free direction is a zero frequency)"
    L, F = model.Lref, model.Fref
    masses = Masses(model)
    if masses.massive_dofs().size == 0:
        raise BadInput("simulate: nothing in the structure has mass (give a body a mass or a rod a rhoA)")
    counts = {r.name: r.elements for r in fs.rods}
    sets = None
    if any(_has_friction(j) for j in fs.joints):   # both sets, stuck and free (SPEC 9.4)
        from femslide.analysis.friction_modes import frequency_sets
        sets, shapes, _, stuck_shapes = frequency_sets(
            model, y_s, e_s, [j for j in fs.joints if _has_friction(j)], counts, MODES,
            mechanism=frequencies_of != "frictionless structure")
        freq = np.array(sets["free"])
    elif frequencies_of == "frictionless structure":
        try:
            freq, shapes = modes(model, y_s, e_s, masses, MODES)
        except SolverFailure as exc:
            # while its contacts hold, a structure may have no motion at all (a bar on a pin and a
            # contact): it moves only lifted off
            if not any(j.unilateral for j in fs.joints) or "no motion" not in str(exc):
                raise
            freq, shapes = np.zeros(0), np.zeros((0, model.n_q))
    else:   # frictionless sliders held for the start only: their free directions are zero frequencies
        freq, shapes = modes(model, y_s, e_s, masses, MODES, zero_ok=True,
                              max_free=sum(j.mu is not None for j in fs.joints))
    # the modes that keep vibrations resolved: of the structure as declared (stuck False) or with its
    # friction joints stuck (True)
    omega, phi, stuck = 2.0 * math.pi * np.asarray(freq, float), shapes, False
    # the frequencies that set the steps: the free structure's positive ones (a free direction's zero
    # sets none); the stuck ones for a structure without an equilibrium of its own (it starts stuck)
    f_pos = [float(f) for f in freq if f > 0]
    if sets and (frequencies_of != "frictionless structure" or not f_pos):
        f_pos = sets["stuck"] or f_pos
        if sets["stuck"]:
            omega, phi, stuck = 2.0 * math.pi * np.asarray(sets["stuck"], float), stuck_shapes, True
    # their damping ratios under the Rayleigh damping, alpha / (2 omega) + beta omega / 2 (for the steps)
    om_ = np.where(omega > 0, omega, 1.0)
    modal = (omega, phi, np.where(omega > 0, spec.alpha / (2.0 * om_) + spec.beta * om_ / 2.0, 0.0), stuck)
    C = None
    if spec.alpha or spec.beta:
        C = rayleigh_damping(model, masses, y_s, e_s, spec.alpha, spec.beta)
    if spec.rotation_damping and any(spec.rotation_damping.values()):
        C = rotation_dampers(model, spec.rotation_damping, C)
    f_ref = [f_pos[0], f_pos[-1]] if len(f_pos) else [1.0 / spec.t_end] * 2
    # joints with mu0 = 0 have no friction at all (the stick/slip direction of a massless slide is
    # then undetermined): they are frictionless sliders and rollers
    fric_joints = [j for j in fs.joints if _has_friction(j)]
    # the joints with modes: friction (stick/slip) and contacts (lift/land)
    mode_joints = [j for j in fs.joints if _has_friction(j) or j.unilateral]
    y0, e0, lifted0 = (y_s, e_s, lifted_static) if spec.initial is None else \
        contact_start(fs, counts, L, F, model, y_s, e_s, spec.initial, lifted_static)

    def new_friction():
        """The friction joints' and contacts' modes and step systems, fresh for a run (or None)."""
        if not mode_joints:
            return None
        from femslide.analysis.radau import RadauSystem
        from femslide.analysis.stickslip import Friction
        return Friction(model, mode_joints, lambda m, extras, rel: RadauSystem(m, masses, C, spec.ground, extras, rel),
                        counts, lifted=lifted0)
    fr = new_friction()
    if fr is not None and sets:
        # stuck phases may be much stiffer (a massless rod clamped in its guide must stretch):
        # the run-time step allowance follows the highest frequency of either
        f_ref[1] = max(f_ref[1], max(sets["stuck"], default=0.0))
    check_work(spec, f_ref[0], model.n_q, f_ref[1])
    deadline = None if spec.max_time is None else t_wall + spec.max_time
    if spec.initial is not None:   # the released motion may be much faster than the lowest mode
        f_ref[1] = max(f_ref[1], check_release(spec, model, masses, y_s, e_s, y0, f_ref[0]))
    max_steps, _ = check_work(spec, f_ref[0], model.n_q, f_ref[1])
    fric_names = {j.name for j in fric_joints}
    contacts = [j.name for j in fs.joints if j.unilateral]   # their gap [m]: 0 in contact, > 0 lifted

    def forces(y, n, fr):
        fx, fy, m = joint_forces(model, y, n)
        if n in fric_names:
            from femslide.joints.friction import joint_friction_force
            gx, gy, gm = joint_friction_force(model.joint[n], fr.coefficient(n, y), y[:model.n_q])
            fx, fy, m = fx + gx, fy + gy, m + gm
        return fx, fy, m

    reac = [j.name for j in fs.joints if j.b == "ground"]
    slides = [j.name for j in fs.joints if kind_of(j.type).free == "slide"]
    rods = [r.name for r in fs.rods]
    bodies = [b.name for b in fs.bodies]
    cols = ["t"] + [f"reactions.{n}.{k}" for n in reac for k in ("Fx", "Fy", "M")] \
        + [f"rods.{n}.M_max" for n in rods] + [f"joints.{n}.{k}" for n in slides for k in ("slide", "normal")] \
        + [f"bodies.{n}.{k}" for n in bodies for k in ("x", "y", "rotation", "rotation_rate", "rotation_accel")] \
        + [f"joints.{n}.friction" for n in sorted(fric_names)] \
        + [f"joints.{n}.gap" for n in contacts] \
        + [f"bodies.{n}.{k}" for n in bodies for k in ("vx", "vy", "ax", "ay")]
    pairs = storey_pairs(fs)
    cols += drift_columns(pairs)   # (computed from the bodies' centroids after the run)
    n_raw = len(cols) - 2 * len(pairs)
    # each body's dof, frame origin X [m] and centroid relative to it [m] (Model.body_point's formula,
    # without its per-call lookups), and that lever in model units (the centroid's velocity), as floats
    body_at = []
    for n in bodies:
        X0 = model.body_X0[model.body_index[n]]
        c, X = np.asarray(fs.body(n).centroid, float), X0 * L
        r, cr = c - X, c / L - X0
        body_at.append((model.body_dof(n), float(X[0]), float(X[1]), float(r[0]), float(r[1]),
                        float(cr[0]), float(cr[1])))
    bearing = {j.name: (kind_of(j.type), j.bearing / L if j.bearing else None) for j in fs.joints}
    frames, frames_rows = [], []   # (t, row index, y, alpha) every t_end / FRAMES
    next_frame = [0.0]

    rod_elements = [np.nonzero(model.elem_rod == k)[0] for k in range(len(rods))] if rods else []

    def observe(t, y, alpha, v, acc, fr=None, record=True):
        """A history row (SI) of the state; with ``record`` the VTU frames are kept too."""
        row = [t]
        for n in reac:
            fx, fy, m = forces(y, n, fr)
            row += [fx * F, fy * F, m * F * L]
        if rods:
            qb, _ = model.element_forces(y[:model.n_q], alpha)
            Mabs = np.abs(qb[:, 1:]).max(axis=1) if qb.size else np.zeros(0)
            for e in rod_elements:
                row.append(float(Mabs[e].max()) * F * L if e.size else 0.0)
        q = y[:model.n_q]
        for n in slides:
            link = model.joint[n]
            row.append((link.slide_value(q[link.dofs]) - model.slide0[n]) * L)
            kind, h = bearing[n]
            row.append(kind.normal_force(model.multipliers(y, link).tolist(), h)[0] * F)
        for d, X0, X1, r0, r1, _, _ in body_at:
            th = float(q[d + 2])
            c, s_ = math.cos(th), math.sin(th)
            row += [X0 + float(q[d]) * L + c * r0 - s_ * r1, X1 + float(q[d + 1]) * L + s_ * r0 + c * r1, th,
                    float(v[d + 2]), float(acc[d + 2])]
        for n in sorted(fric_names):   # friction force on a along +axis [N]
            row.append(-fr.coefficient(n, y) * F)
        for n in contacts:
            link = model.joint[n]
            row.append(link.gap(q[link.dofs]) * L)
        if bodies:   # absolute velocity and acceleration of the centroids: relative motion + the ground's
            vg = ag = 0.0
            if spec.ground is not None:
                vg, ag = spec.ground.velocity(t), spec.ground.accel(t)
            e = spec.ground.direction if spec.ground is not None else (0.0, 0.0)
            for d, *_, r0, r1 in body_at:
                c, s_ = math.cos(q[d + 2]), math.sin(q[d + 2])
                Rr = (c * r0 - s_ * r1, s_ * r0 + c * r1)
                w, al = v[d + 2], acc[d + 2]
                row += [(v[d] - w * Rr[1]) * L + vg * e[0], (v[d + 1] + w * Rr[0]) * L + vg * e[1],
                        (acc[d] - al * Rr[1] - w * w * Rr[0]) * L + ag * e[0],
                        (acc[d + 1] + al * Rr[0] - w * w * Rr[1]) * L + ag * e[1]]
        if record and (t >= next_frame[0] or t >= spec.t_end * (1 - 1e-12)):
            frames.append((t, len(frames_rows), y.copy(), alpha.copy()))
            next_frame[0] = t + spec.t_end / FRAMES
        if record:
            frames_rows.append(None)
        return row

    h_max = spec.t_end / 20.0
    if spec.ground is not None and spec.ground.harmonic:
        h_max = min(h_max, 0.05 / spec.ground.frequency)
    for b in spec.turning:
        if b not in model.body_index:
            raise BadInput(f"turning points of {b!r}: no such body; bodies: {', '.join(model.body_index) or 'none'}")
    rates = [model.body_dof(b) + 2 for b in spec.turning]
    watch = [(lambda y, v, d=d: float(v[d])) for d in rates]

    def run_at(tol, fr, record, progress):
        """The integration at tolerance tol with the friction modes fr: (run, history array); the
        largest step (t_end / 20, 1/20 of a harmonic ground motion's period) scales as the steps
        the tolerance sets, (tol / tolerance)^(1/4), up to a record's sample interval."""
        kept = []   # the rows so far: on a failure (max_time reached) the exception carries them

        def obs(t, y, alpha, v, acc):
            row = observe(t, y, alpha, v, acc, fr, record)
            kept.append(row)
            return row
        hm = h_max * (tol / spec.tolerance) ** 0.25
        if spec.ground is not None and spec.ground.times is not None and spec.ground.dt:
            hm = min(hm, spec.ground.dt)
        left = None if deadline is None else max(deadline - time.perf_counter(), 1e-9)
        try:
            run = integrate(model, masses, y0, e0, spec.t_end, tol, C=C, ground=spec.ground,
                            observe=obs, h0=0.02 / f_ref[0] * spec.tolerance ** 0.25, h_max=hm,
                            max_steps=max_steps, wall_limit=left, progress=progress, q_ref=y_s, friction=fr,
                            period=1.0 / f_ref[0], watch=watch, sample=spec.output_interval, modal=modal)
        except SolverFailure as err:
            exc = err
            if deadline is not None and time.perf_counter() >= deadline:
                t_at = kept[-1][0] if kept else 0.0
                exc = SolverFailure(f"simulate: stopped at t = {t_at:.6g} s of t_end = {spec.t_end:g} s: the time "
                                    f"limit max_time = {spec.max_time:g} s was reached"
                                    f"{'' if record else ' in the check run of the error estimate'}")
                exc.time_limit = True
            exc.rows = kept
            raise exc from None
        H = with_drifts(np.array(run.rows))
        if not np.all(np.isfinite(H)):
            raise SolverFailure("simulate: the history holds NaN or inf values")
        return run, H

    def with_drifts(H):
        """The history rows (n_raw columns) with the drift columns appended."""
        if H.ndim != 2 or H.shape[1] != n_raw:
            return H
        return np.hstack([H, drifts(H, col, pairs)]) if pairs else H

    col = {c: i for i, c in enumerate(cols)}

    def peaks_of(H, fr):
        T = H[:, 0]
        brk = [e["t"] for evs in (fr.events.values() if fr is not None else ()) for e in evs if e["t"] > 0.0]
        brk = sorted(brk + [t for _, t0, t1 in (fr.touches if fr is not None else ()) for t in (t0, t1)])   # (jumps)
        # (group, name, key, sign, series): every peak's series, refined together (_peaks)
        want = []
        for n in reac:
            want += [("reactions", n, k, 1.0, np.abs(H[:, col[f"reactions.{n}.{k}"]])) for k in ("Fx", "Fy", "M")]
        for n in rods:
            want.append(("rods", n, "M_max", 1.0, H[:, col[f"rods.{n}.M_max"]]))
        for n in slides:
            s = H[:, col[f"joints.{n}.slide"]]
            want += [("joints", n, "slide_min", -1.0, -s), ("joints", n, "slide_max", 1.0, s)]
        for n in contacts:   # the largest lift-off
            want.append(("joints", n, "gap_max", 1.0, H[:, col[f"joints.{n}.gap"]]))
        for n in bodies:   # absolute velocities and accelerations of the centroids
            want += [("bodies", n, k, 1.0, np.abs(H[:, col[f"bodies.{n}.{k}"]])) for k in ("vx", "vy", "ax", "ay")]
        for up, low in pairs:
            pair = f"{up}-{low}"
            want += [("drifts", pair, k, 1.0, np.abs(H[:, col[f"drifts.{pair}.{k}"]])) for k in ("dx", "dy")]
        peaks = {"reactions": {}, "rods": {}, "joints": {}, "bodies": {}, "drifts": {}}
        if not want:
            return peaks
        vals = _peaks(T, np.column_stack([w[4] for w in want]), breaks=brk)
        for (group, n, k, sign, _), v in zip(want, vals):
            peaks[group].setdefault(n, {})[k] = sign * float(v)
        return peaks

    def outcome(res, H):
        """The Outcome of the history H (a run's, or the part computed before a failure)."""
        history = {c: H[:, i] for i, c in enumerate(cols)}   # t first
        res["residual"] = residuals(H, cols)
        res["wall_time_s"] = time.perf_counter() - t_wall
        figs = [Figure("peaks_over_time.png", "peaks", {"t": H[:, 0], "groups": running_peaks(H, cols),
                                                        "name": name})]
        return Outcome(res, name, history=history, tables=[Table("history.csv", cols, list(H.T))], figures=figs,
                       frames=Frames(model, [(t, y, a, {c: H[i, j] for j, c in enumerate(cols) if j > 0})
                                             for t, i, y, a in frames if i < H.shape[0]]),
                       loops=[Loop(n, history[f"joints.{n}.slide"], history[f"joints.{n}.friction"])
                              for n in sorted(fric_names)])

    def stopped(exc, res=None, H=None):
        """The failure with the outcome of what was computed (``exc.outcome``): the run's own history
        (its rows so far, or all of them when the check run failed), converged false and the reason."""
        if H is None:
            rows = getattr(exc, "rows", None) or []
            H = with_drifts(np.array(rows)) if rows else np.zeros((0, len(cols)))
            H = H[np.all(np.isfinite(H), axis=1)] if H.size else H
        if H.shape[0]:
            part = {"t_reached": float(H[-1, 0]), "t_end": spec.t_end,
                    "frequencies_hz": [float(f) for f in freq], "frequencies_of": frequencies_of,
                    **({"frequency_sets": sets} if sets else {}),
                    **(res or {"events": fr.events if fr is not None else {}, "peaks": peaks_of(H, fr)})}
            part.update(converged=False, reason=exc.reason)
            exc.outcome = outcome(part, H)
        return exc

    # the error estimate's check run: beside the run in a forked process where a second CPU is there
    # (femslide.analysis.forked; the same values as after it, bit for bit), else after it
    T1 = 1.0 / f_ref[0]
    beside = None
    try:   # (a child whose result is not read - the run failed, an interrupt - is stopped)
        if spec.estimate:
            beside = Forked.start(lambda: _check_run(spec, run_at, new_friction, peaks_of, T1))
        # the progress bar (simulated time, with the time left) covers the run and a check run after it,
        # which takes about CHECK_FACTOR^(-1/5) of its steps (steps ~ tolerance^(-1/5)); a check run
        # beside the run ends about with it: the bar reaches t_end when its result is in
        from femslide.analysis.transient import CHECK_FACTOR
        share = (1.0 / (1.0 + CHECK_FACTOR ** -0.2) if beside is None else BESIDE_SHARE) if spec.estimate else 1.0
        t_int = time.perf_counter()
        try:
            run, H = run_at(spec.tolerance, fr, True, (lambda t: progress(share * t)) if progress else None)
        except SolverFailure as exc:
            raise stopped(exc) from None
        t_int = time.perf_counter() - t_int
        peaks = peaks_of(H, fr)
        res = {"converged": True, "steps": run.steps, "rejected_steps": run.rejected,
               "newton_iterations": run.newton_iterations, "t_end": spec.t_end,
               "energy_balance": run.energy_balance, "energy": run.energy,
               "events": fr.events if fr is not None else {},
               "frequencies_hz": [float(f) for f in freq], "frequencies_of": frequencies_of,
               **({"frequency_sets": sets} if sets else {}), "peaks": peaks,
               "elements": {r.name: r.elements for r in fs.rods}, "integration_time_s": t_int}
        if run.notes:
            res["notes"] = list(run.notes)
        check_trust(res, spec.tolerance, model.Fref * model.Lref, 2 * len(fr.touches) if fr is not None else 0)
        if spec.estimate:
            try:
                check = None
                if beside is not None:
                    try:   # (a check run takes about 0.6 of the run: silent for 20 runs' time, it is stuck)
                        check = beside.result(timeout=max(60.0, 20.0 * t_int))
                        if progress:
                            progress(spec.t_end)
                    except ChildLost:   # (killed, out of memory, stuck, failed otherwise: made here)
                        check = None
                if check is None:
                    after = (lambda t: progress(share * spec.t_end + (1.0 - share) * t)) if progress else None
                    check = _check_run(spec, run_at, new_friction, peaks_of, T1, after)
                res.update(estimate_error(spec, check, H, res, cols, T1, model.Lref))
                note = promise_note(res, spec.tolerance)
                if note:
                    res.setdefault("notes", []).append(note)
            except SolverFailure as exc:   # only the user's time limit ends the check run so (module docstring)
                raise stopped(exc, {**res, "t_reached": spec.t_end}, H) from None
        else:   # (skipped: the key is there, null)
            res["error_estimate"] = None
    finally:
        if beside is not None:
            beside.cancel()   # (nothing once its result was read)
    if spec.turning:   # the located zeros of the bodies' rotation rates (rows of the history)
        T = H[:, 0]
        res["turning_points"] = {
            b: [{"t": t, "rotation": float(H[int(np.searchsorted(T, t)), col[f"bodies.{b}.rotation"]])}
                for k, t in run.crossings if spec.turning[k] == b] for b in spec.turning}
    return outcome(res, H)


MODES_TARGET = 2e-7    # estimated relative error the refinement of `femslide modes` aims for (below 1e-6)
MODES_N_MAX = 1024     # elements per massive rod at most


def _modes_on(fs, n, count):
    """(model, y, elements, masses, freq, shapes, stuck) with every rod without its own mesh in n
    elements; a structure with friction joints: freq the free (frictionless) set, a direction free
    of stiffness a zero frequency, and ``stuck`` the set with every friction joint locked
    (femslide.analysis.friction_modes; None without friction joints).  One without an equilibrium
    of its own when frictionless (a base on a slider without a spring) is taken about its static
    state with the friction joints stuck."""
    from femslide.analysis import static
    from femslide.analysis.modes import modes
    from femslide.analysis.refine import moment_watch
    from femslide.model.mass import Masses
    fs = _fixed_mesh(fs, n)
    fric = [j for j in fs.joints if _has_friction(j)]
    mechanism = False
    try:
        sol = static.solve(fs, watch=moment_watch)   # (only the state is used)
        model, y, elements = sol.level.model, sol.level.y, sol.level.elements
    except SolverFailure as exc:
        if not fric:
            raise
        mechanism = True
        sol = _stuck_statics(fs, exc)
        model = _model_like(fs, sol.level.model)
        y = np.zeros(model.n)
        y[:model.n_q] = sol.level.y[:model.n_q]
        elements = sol.level.elements
    masses = Masses(model)
    if masses.massive_dofs().size == 0:
        raise BadInput("modes: nothing in the structure has mass (give a body a mass or a rod a rhoA)")
    stuck = None
    if fric:
        from femslide.analysis.friction_modes import frequency_sets
        sets, shapes, _, _ = frequency_sets(model, y, elements, fric, {r.name: r.elements for r in fs.rods}, count,
                                            mechanism=mechanism)
        freq, stuck = sets["free"], np.asarray(sets["stuck"], dtype=float)
    else:
        freq, shapes = modes(model, y, elements, masses, count)
    return model, y, elements, masses, np.asarray(freq, dtype=float), shapes, stuck


def _extrapolated(f, f_c):
    """Richardson's (4 f - f_c) / 3 of two meshes' frequencies (their common count)."""
    k = min(len(f), len(f_c))
    return (4.0 * f[:k] - f_c[:k]) / 3.0


def natural_modes(fs, count=MODES, elements=None, name="structure"):
    """`femslide modes`: the ``count`` lowest natural frequencies [Hz] of the frictionless structure
    about its static equilibrium, with the mode shapes to write as VTU files
    (femslide.output.files.write_modes) and ``error_estimate``.  A structure with friction joints
    also gets ``frequency_sets`` {``stuck``: every friction joint locked, ``free``: frictionless, as
    ``frequencies_hz``} (SPEC 9.4); a direction free of any stiffness is a zero frequency (period
    None), not a refusal.

    ``elements`` fixes the mesh of the rods without their own `elements`.  Without it, a structure
    whose rods carry mass is solved on meshes of 8, 16, 32, ... elements per rod: the lumped masses
    (no rotary inertia) make the frequencies converge like h^2, and Richardson's extrapolation of two
    meshes, (4 f_2n - f_n) / 3, like h^4; its estimated error is the change of the extrapolation from
    the previous pair over 15 (the h^4 term's ratio), and the refinement stops when that is below
    MODES_TARGET for every mode, or when it grows again (the round-off of fine meshes' eigenproblem):
    a cantilever's f4 is 5.5e-2 off at 8 elements, 1.0e-7 after extrapolating 64 and 128 (estimate
    1.1e-7).  The shapes are the finest mesh's.  Rods without mass are exact in the static condensation up to their
    element's cubic: their mesh stays at DEFAULT_ELEMENTS."""
    t0 = time.perf_counter()
    massive = any(r.rhoA for r in fs.rods if not r.elements)
    notes = []
    if elements is not None or not massive:
        n = elements or DEFAULT_ELEMENTS
        model, y, es, masses, freq, shapes, stuck = _modes_on(fs, n, count)
        estimate = None
    else:
        n = DEFAULT_ELEMENTS
        level = _modes_on(fs, n, count)
        prev, prev_ext, best = level, None, None
        while 2 * n <= MODES_N_MAX:
            n *= 2
            level = _modes_on(fs, n, count)
            f, f_c = level[4], prev[4]
            k = min(len(f), len(f_c))
            ext = _extrapolated(f, f_c)
            if prev_ext is not None:
                k = min(k, len(prev_ext))
                # the extrapolation's error falls like h^4: its change from the previous pair is 15x it
                # (a zero frequency - a direction free of stiffness - is exact)
                nz = np.abs(ext[:k]) > 0.0
                est = float(np.max(np.abs(ext[:k] - prev_ext[:k])[nz] / np.abs(ext[:k])[nz])) / 15.0 \
                    if nz.any() else 0.0
                if best is not None and est > best[0]:
                    # the estimate grows again: the round-off of the fine meshes' eigenproblem (a
                    # cantilever's EA L_e^2 / EI beyond 1e8 at 256 elements); the previous level stands
                    notes.append(f"the frequencies' refinement stopped at the round-off floor of the "
                                 f"finer meshes: estimated accurate to {best[0]:.2g} (relative)")
                    break
                stuck_ext = None if level[6] is None else np.concatenate(
                    [_extrapolated(level[6], prev[6]), level[6][min(len(level[6]), len(prev[6])):]])
                best = (est, np.concatenate([ext[:k], f[k:]]), level, n, stuck_ext)
                if est <= MODES_TARGET:
                    break
            prev, prev_ext = level, ext
        if best is None:
            model, y, es, masses, freq, shapes, stuck = level
            estimate = None
        else:
            estimate, freq, (model, y, es, masses, _, shapes, _), n, stuck = best
            if estimate > MODES_TARGET and not notes:
                notes.append(f"the frequencies are estimated accurate to {estimate:.2g} (relative) at {n} "
                             f"elements per rod, the most the refinement uses")
    res = {"converged": True, "frequencies_hz": [float(f) for f in freq],
           "periods_s": [float(1.0 / f) if f > 0 else None for f in freq],
           **({"frequency_sets": {"stuck": [float(f) for f in stuck], "free": [float(f) for f in freq]}}
              if stuck is not None else {}),
           "elements": {r.name: r.elements or n for r in fs.rods}, "error_estimate": estimate}
    if len(freq) < count:   # fewer motions with mass than asked for: say so rather than pad or hide it
        notes.append(f"{len(freq)} of the {count} modes asked for: the structure has no more motions "
                     f"with mass (its massless parts - rods with rhoA = 0, rotations of bodies without "
                     f"inertia - follow the masses quasi-statically)")
    if stuck is not None:
        notes.append("frequencies_hz and the mode shapes: the frictionless (free) structure; frequency_sets.stuck: "
                     "every friction joint locked" + ("; a zero frequency is a direction free of stiffness"
                                                      if 0.0 in list(freq) else ""))
    if notes:
        res["notes"] = notes
    res["wall_time_s"] = time.perf_counter() - t0
    return Outcome(res, name, modes=ModeShapes(model, y, es.committed, list(freq), shapes))
