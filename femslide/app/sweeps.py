"""Parameter sweeps: one solve per value, in process, in a process pool or on a Dask cluster.

Every case is solved *cold*, from the scene's own start, exactly as ``femslide solve`` solves it.  A
sweep used to continue each case from the previous solution (warm start); measured on beam-slider
(EI = 1e4 ... 1e10) the warm and cold solutions agree only to ~3e-10 relative (both are converged to
the solver's tolerance, not to the last bit), so a parallel sweep, which cannot warm start, would not
reproduce an in-process one.  Solving cold everywhere makes the rows independent of how and in what
order the cases run (the results of a sweep are the same whichever way it runs), and a
sweep row equals the ``solve`` of that case; it also costs nothing here (cold solves were faster).

A failed case is reported in its row (``converged`` false, ``reason``) and the sweep goes on.  With
``--out DIR`` the rows stream to ``DIR/sweep.jsonl`` as they finish (each line the row plus
``case``, ``case_dir``, ``scene``, ``varied``, ``fixed`` (the parameters given), ``params`` (all
values), ``version``, ``status``), so an interrupted
sweep keeps what finished; rerunning with the same ``--out`` (or ``--resume``) skips the cases
already there (matched by femslide version, scene and the full set of parameter values).  Rows whose
run crashed (``status`` "error": a lost worker, an internal error) are run again; converged and
failed rows are not (failures are deterministic).

A folder holds the rows of one sweep only: the same femslide version, scene, varied parameter and
fixed (``--set``) parameters; the varied values may differ (a resumed sweep may add values).  A
folder with another sweep's rows is bad input (exit 2, before any case runs): its rows and case
folders would mix with this sweep's.  Case folders ``case_NNN`` are numbered on from the largest
number already in the folder (rows or folders), so a case's files are never overwritten and every
row's ``case_dir`` and ``files`` name the files of that row's own run.

On Dask (``--dask local``: a LocalCluster of ``--jobs`` worker processes, or one per case up to the CPU
count; ``--dask tcp://host:port``: a running scheduler and its workers) the workers may run in another
folder or on another machine sharing the file system: the case folders, path parameters (``record``)
and structure files are made absolute against the caller's working folder before submitting, and the
rows name their files as an in-process run does.
"""
from __future__ import annotations

import json
import os
import sys

from femslide.errors import BadInput, SolverFailure

JSONL = "sweep.jsonl"
EXTRA = ("case", "case_dir", "scene", "varied", "fixed", "params", "version", "status")  # jsonl-only keys
CASE_DIR = "case_{:03d}"


def is_dynamic(values) -> bool:
    """Whether a structure file's case is a simulation: a ``simulate.KEY`` among its values."""
    return any(isinstance(k, str) and k.startswith("simulate.") for k in values)


def for_case(scene, values):
    """The target a case runs: a structure file's `simulate` when a ``simulate.KEY`` is given."""
    if is_dynamic(values) and hasattr(scene, "for_simulate") and getattr(scene, "command", "") != "simulate":
        return scene.for_simulate()
    return scene


def dynamic_row(res: dict) -> dict:
    """A simulate result as a sweep row: the friction events as counts (``events``: {joint: number of
    events after the start}) instead of their lists; the peaks, error_estimate and the rest kept."""
    ev = res.get("events")
    if isinstance(ev, dict) and all(isinstance(v, list) for v in ev.values()):
        res = {**res, "events": {j: sum(1 for e in v if isinstance(e, dict) and e.get("t", 0.0) > 0.0)
                                 for j, v in ev.items()}}
    res.pop("turning_points", None)
    return res


def solve_case(scene_name: str, values: dict, out_dir: str | None = None, cache=None):
    """Solve one case cold; return (row without the varied parameter, status).

    Status: "converged", "failed" (did not converge), "bad-input" (the run rejected the values) or
    "error" (an internal error).  Runs in worker processes: imports are local, results are plain
    JSON-safe data.  ``scene_name``: a built-in scene or a scene or structure file's path; ``cache``:
    Jacobian patterns shared by the cases solved in this process.  A structure file's case with a
    ``simulate.KEY`` is simulated (:func:`dynamic_row`); a simulation stopped half way (max_time)
    keeps its peaks so far and ``t_reached`` in the failed row.
    """
    from femslide.app.result import clean
    from femslide.app.run import load_target, run_case
    scene = for_case(load_target(scene_name).scene, values)
    try:
        res = run_case(scene, {**values, "_cache": cache} if cache is not None and not is_dynamic(values)
                       else values, out=out_dir, quiet=True)  # the sweep has its own bar
    except SolverFailure as exc:
        part = getattr(exc, "result", None)
        keep = {k: part[k] for k in ("t_reached", "peaks", "events") if k in part} if part else {}
        return dynamic_row(clean({"converged": False, "reason": exc.reason, **keep})), "failed"
    except BadInput as exc:
        return {"converged": False, "reason": f"bad input: {exc}"}, "bad-input"
    except Exception as exc:  # keep the sweep going; the row says what happened
        return {"converged": False, "reason": f"internal error: {type(exc).__name__}: {exc}"}, "error"
    res = clean(res)
    if is_dynamic(values):
        res = dynamic_row(res)
    return res, "converged" if res.get("converged", True) else "failed"


def _version():
    from femslide.version import __version__
    return __version__


def _key(scene_name, values, version=None):
    """Resume key of a case: femslide version, scene and every parameter value."""
    return json.dumps([version or _version(), scene_name, {k: values[k] for k in sorted(values)}],
                      sort_keys=True)


def _fixed(target, base, varied):
    """The sweep's fixed parameters as given (scene file [parameters], then --set), each converted to
    its canonical value (``EI=1e6`` and ``EI=1000000`` are the same sweep).  Derived and default values
    are not listed: they follow from these and the varied value."""
    params = getattr(target.scene, "params", None)
    given = {**(getattr(target, "params", None) or {}), **base}
    skip = set(varied) if isinstance(varied, (list, tuple)) else {varied}
    if params is None:  # a structure file: NAME.FIELD overrides, canonical as its resolve makes them
        from femslide.app.structfile import parse_value
        fixed = {k: parse_value(v) for k, v in given.items() if k not in skip}
    else:
        table = {p.name: p for p in params.params()}
        fixed = {k: table[k].check(v) for k, v in given.items() if k not in skip and k in table}
    if getattr(target, "mesh_path", None):
        fixed["mesh file"] = os.path.abspath(target.mesh_path)
    return fixed


def _identity(version, scene_name, varied, fixed):
    """What makes rows belong to one sweep: version, scene, varied name and the fixed parameters."""
    return json.dumps([version, scene_name, varied, {k: fixed[k] for k in sorted(fixed)}], sort_keys=True)


def _records(path):
    """The readable records of a jsonl file (a line cut by an interrupt is skipped)."""
    recs = []
    if not os.path.isfile(path):
        return recs
    try:
        fh = open(path, encoding="utf-8")
    except OSError as exc:
        raise BadInput(f"--out: cannot read {path} ({exc.strerror or exc})") from None
    with fh:
        try:
            for line in fh:
                try:
                    rec = json.loads(line)
                except json.JSONDecodeError:
                    continue
                if isinstance(rec, dict):
                    recs.append(rec)
        except UnicodeDecodeError:
            raise BadInput(f"--out: {path} is not a femslide sweep file (not UTF-8 text); "
                           f"allowed: a folder of one sweep, or a new one") from None
    return recs


def _check_same_sweep(out, recs, scene_name, varied, base_values, resume):
    """BadInput unless every record of the folder belongs to this sweep (see the module docstring)."""
    want = _identity(_version(), scene_name, varied, base_values)
    for rec in recs:
        params = rec.get("fixed")
        ok = (isinstance(params, dict) and rec.get("varied") == varied
              and _identity(rec.get("version"), rec.get("scene"), varied, params) == want)
        if ok:
            continue
        what = []
        if rec.get("version") != _version():
            what.append(f"femslide {rec.get('version') or '(unknown version)'}, this is {_version()}")
        if rec.get("scene") != scene_name:
            what.append(f"scene {rec.get('scene')}, not {scene_name}")
        if rec.get("varied") != varied:
            what.append(f"varied {rec.get('varied') or '(unknown)'}, not {varied}")
        if isinstance(params, dict) and not what:
            diff = sorted(k for k in set(params) | set(base_values) if k != varied
                          and params.get(k) != base_values.get(k))
            show = (lambda d, k: f"{d[k]!r}" if k in d else "default")  # noqa: E731
            what.append("other fixed parameters: " + ", ".join(
                f"{k} = {show(params, k)} there, {show(base_values, k)} here" for k in diff[:4]))
        how = "--resume continues a sweep only with its own scene and parameters; " if resume else ""
        raise BadInput(f"--out {out}: the folder holds the rows of another sweep (case "
                       f"{rec.get('case')}: {'; '.join(what) or 'unreadable record'}); {how}allowed: a new "
                       f"folder, or the folder of this same sweep")


def _load_done(recs):
    """Rows of a previous run of this sweep: key -> (row, status, case, case_dir)."""
    done = {}
    for rec in recs:
        if "params" not in rec or "scene" not in rec or rec.get("status") == "error":
            continue
        row = {k: v for k, v in rec.items() if k not in EXTRA}
        status = rec.get("status") or ("converged" if row.get("converged") else "failed")
        done[_key(rec["scene"], rec["params"], rec.get("version"))] = (row, status)
    return done


def _next_case(out, recs):
    """First case number above every number used in the folder (records and case_NNN folders)."""
    used = [r["case"] for r in recs if isinstance(r.get("case"), int)]
    try:
        names = os.listdir(out)
    except OSError:
        names = []
    for nm in names:
        if nm.startswith("case_") and nm[5:].isdigit():
            used.append(int(nm[5:]))
    return max(used, default=-1) + 1


def _open_stream(path):
    """Append to the jsonl file; a line cut by an interrupt is closed first."""
    if os.path.isfile(path) and os.path.getsize(path) > 0:
        with open(path, "rb") as fh:
            fh.seek(-1, os.SEEK_END)
            last = fh.read(1)
        if last != b"\n":
            with open(path, "a") as fh:
                fh.write("\n")
    return open(path, "a")


# -- executors: each yields (case index, row, status) as cases finish ------------------------------------

_CACHE: dict = {}   # the PatternCache of the last in-process sweep, by scene (one kept)


def run_serial(scene_name, cases, todo, out_dirs):
    """Cases one after the other in this process, sharing one PatternCache: the meshes, Jacobian
    patterns and joints of one geometry are built once for all cases (a sweep over stiffnesses
    builds each mesh's model once) and kept for the next sweep of the same scene in this process."""
    from femslide.model.patterns import PatternCache
    cache = _CACHE.get(scene_name)
    if cache is None:
        _CACHE.clear()
        cache = _CACHE[scene_name] = PatternCache()
    for i in todo:
        row, status = solve_case(scene_name, cases[i], out_dirs[i], cache)
        yield i, row, status


def _serial_check_runs():
    """A pool worker's initializer (module level: spawn and forkserver pickle it): time histories
    make their check runs after their runs (femslide.analysis.forked), the workers already fill the
    CPUs."""
    from femslide.analysis.forked import ENV
    os.environ[ENV] = "serial"


def run_pool(scene_name, cases, todo, out_dirs, jobs):
    from concurrent.futures import ProcessPoolExecutor, as_completed

    # (the workers fill the CPUs: a time history's check run is made after its run, in the worker)
    with ProcessPoolExecutor(max_workers=jobs, initializer=_serial_check_runs) as pool:
        futs = {pool.submit(solve_case, scene_name, cases[i], out_dirs[i]): i for i in todo}
        try:
            for fut in as_completed(futs):
                i = futs[fut]
                try:
                    row, status = fut.result()
                except Exception as exc:  # a worker died (BrokenProcessPool, ...)
                    row, status = {"converged": False, "reason": f"worker error: {type(exc).__name__}: {exc}"}, "error"
                yield i, row, status
        except BaseException:
            pool.shutdown(wait=False, cancel_futures=True)
            raise


def dask_client(address: str, workers: int | None = None):
    """A dask.distributed Client: ``local`` starts a LocalCluster (one thread per worker process),
    ``tcp://host:port`` connects to a running scheduler.  BadInput if dask is missing or the
    scheduler cannot be reached."""
    try:
        from dask.distributed import Client, LocalCluster
    except ImportError:
        raise BadInput("--dask needs dask.distributed: pip install 'femslide[dask]'") from None
    import logging
    if address == "local":
        n = workers or min(os.cpu_count() or 1, 8)
        cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True,
                               dashboard_address=None, silence_logs=logging.ERROR)
        return Client(cluster), cluster
    if "://" not in address:
        raise BadInput(f"--dask expects 'local' or a scheduler address such as tcp://host:8786, got {address!r}")
    try:
        return Client(address, timeout="15s"), None
    except (OSError, TimeoutError) as exc:
        raise BadInput(f"--dask {address}: cannot reach the Dask scheduler: {exc}") from None


def _path_names(scene_name):
    """Names of the parameters that are file paths (``record``) of a scene; none for structure files,
    whose mesh paths are resolved when the file is read."""
    from femslide.scenes.catalog import SCENES
    scene = SCENES.get(scene_name)
    if scene is None:
        return ()
    return tuple(p.name for p in scene.params.params() if p.kind == "path")


def absolute_case(scene_name, values, out_dir):
    """A case as a worker in another folder (or on another machine with the same file system) needs it:
    the scene or structure file, every path parameter and the case folder made absolute against this
    process's working directory.  Returns (scene_name, values, out_dir)."""
    if scene_name.lower().endswith(".toml"):
        scene_name = os.path.abspath(scene_name)
    paths = _path_names(scene_name)
    values = {k: os.path.abspath(v) if k in paths and isinstance(v, str) else v for k, v in values.items()}
    return scene_name, values, (os.path.abspath(out_dir) if out_dir else out_dir)


def _relative_files(row, abs_dir, out_dir):
    """The row's ``files`` named as an in-process run names them (below ``out_dir`` as given), so that
    rows are the same whichever way the sweep runs."""
    files = row.get("files")
    if not out_dir or not isinstance(files, list) or abs_dir == out_dir:
        return row
    out = []
    for f in files:
        if isinstance(f, str) and os.path.dirname(f) == abs_dir:
            f = os.path.join(out_dir, os.path.basename(f))
        out.append(f)
    return {**row, "files": out}


def _run_dask(scene_name, cases, todo, out_dirs, address, workers):
    """Cases on a Dask cluster; ``workers``: worker processes of a LocalCluster (``address`` 'local'),
    at most one per case.  Relative paths are made absolute before submitting (a worker's working
    directory is not this process's)."""
    from dask.distributed import as_completed
    if address == "local":  # never more workers than cases; by default at most the CPU count (and 8)
        workers = min(workers or min(os.cpu_count() or 1, 8), len(todo))
    client, cluster = dask_client(address, workers if address == "local" else None)
    try:
        futs, index, abs_dirs = [], {}, {}
        for i in todo:
            name_i, values_i, abs_dirs[i] = absolute_case(scene_name, cases[i], out_dirs[i])
            f = client.submit(solve_case, name_i, values_i, abs_dirs[i], pure=False)
            futs.append(f)
            index[f.key] = i
        for fut in as_completed(futs):
            i = index[fut.key]
            try:
                row, status = fut.result()
            except Exception as exc:  # lost worker, serialisation trouble
                row, status = {"converged": False, "reason": f"worker error: {type(exc).__name__}: {exc}"}, "error"
            yield i, _relative_files(row, abs_dirs[i], out_dirs[i]), status
    finally:
        client.close()
        if cluster is not None:
            cluster.close()


# -- the sweep -------------------------------------------------------------------------------------------

LOCK = "sweep.lock"


def _lock(out):
    """An exclusive lock on ``out/sweep.lock`` for the whole sweep (released when its file closes, also
    when the process dies): a second sweep started into the same folder is bad input, instead of both
    writing every row twice and the same case folders."""
    fh = open(os.path.join(out, LOCK), "a+")
    try:
        try:
            import fcntl
            fcntl.flock(fh.fileno(), fcntl.LOCK_EX | fcntl.LOCK_NB)
        except ImportError:   # Windows
            import msvcrt
            fh.seek(0)
            msvcrt.locking(fh.fileno(), msvcrt.LK_NBLCK, 1)
    except OSError:
        fh.seek(0)
        who = fh.read().strip()
        fh.close()
        raise BadInput(f"--out {out}: another sweep{f' (process {who})' if who else ''} is writing into this "
                       f"folder; allowed: one sweep at a time per --out folder (wait for it to finish, then "
                       f"rerun to add to it, or choose another --out)") from None
    fh.seek(0)
    fh.truncate()
    fh.write(str(os.getpid()))
    fh.flush()
    return fh


def run_sweep(target, name, items, base, *, as_json=False, out=None, jobs=None, dask=None,
              resume=False, plot=None, quiet=False):
    """Run a sweep from the command line; returns the exit status (0 all converged, 1 a case failed,
    2 a case was rejected as bad input).  ``name``, ``items``: the varied parameter and its values, or
    lists of them (several ``--vary``: every combination, the first varying slowest).  ``jobs``:
    processes (None: in process), or with ``dask`` 'local' the LocalCluster's worker processes (None:
    one per case, at most the CPU count and 8).  A structure file swept with a ``simulate.KEY`` (varied
    or set) is simulated in every case (SPEC 9.3)."""
    import itertools
    names = list(name) if isinstance(name, (list, tuple)) else [name]
    lists = list(items) if isinstance(name, (list, tuple)) else [items]
    name = ",".join(names)   # the sweep's varied parameters, as its rows name them
    if len(set(names)) < len(names):
        raise BadInput(f"--vary {name}: a parameter varied twice; allowed: each name once")
    if is_dynamic({**base, **dict.fromkeys(names)}) and hasattr(target.scene, "for_simulate"):
        target = target.scene.for_simulate()
    scene = target.scene
    spec = getattr(scene, "spec", scene.name)  # what a worker process loads the case from
    both = [n for n in names if n in base]
    if both:
        raise BadInput(f"parameter {both[0]} is both set and varied")
    if jobs is not None and jobs < 1:
        raise BadInput(f"--jobs {jobs}: allowed: an integer >= 1")
    if dask and dask != "local" and jobs is not None:
        raise BadInput(f"--jobs {jobs} with --dask {dask}: a running scheduler has its own workers; --jobs "
                       f"sets the worker processes of --dask local only (allowed here: no --jobs)")
    if resume and not out:
        raise BadInput("--resume needs --out DIR (the sweep.jsonl of the earlier run)")
    combos = [dict(zip(names, c)) for c in itertools.product(*lists)]
    cases = [target.resolve({**base, **c}) for c in combos]  # all checked before any run
    if plot:
        try:
            import matplotlib  # noqa: F401
        except ImportError:
            raise BadInput("--plot needs matplotlib: pip install 'femslide[plot]'") from None
    if dask:
        try:
            import dask.distributed as _dd  # noqa: F401  (binds _dd only, not the name 'dask')
        except ImportError:
            raise BadInput("--dask needs dask.distributed: pip install 'femslide[dask]'") from None

    n = len(cases)
    out_dirs: list = [None] * n
    case_no: list = [None] * n
    rows: list = [None] * n
    statuses: list = [None] * n
    stream = None
    lock = None
    if out:
        os.makedirs(out, exist_ok=True)
        lock = _lock(out)
        path = os.path.join(out, JSONL)
        recs = _records(path)
        fixed = _fixed(target, base, names)
        _check_same_sweep(out, recs, scene.name, name, fixed, resume)
        done = _load_done(recs)
        for i, v in enumerate(cases):
            prev = done.get(_key(scene.name, v))
            if prev is not None:
                rows[i], statuses[i] = prev
        nxt = _next_case(out, recs)
        for i in range(n):
            if rows[i] is None:  # a new number and folder: earlier cases' files are never overwritten
                case_no[i] = nxt
                out_dirs[i] = os.path.join(out, CASE_DIR.format(nxt))
                nxt += 1
        stream = _open_stream(path)
    todo = [i for i in range(n) if rows[i] is None]

    from femslide.app.progress import progress
    from femslide.app.run import started
    bar = progress(len(todo), f"sweep {scene.name}", quiet, unit="case")
    try:
        if not as_json:
            for i in range(n):
                if rows[i] is not None:
                    bar.write(_row_text(names, rows[i]) + f"  (from {JSONL})")
        if not todo:
            runs = iter(())
        elif dask:
            started()   # (the cases run in other processes: this one imports no machinery)
            runs = _run_dask(spec, cases, todo, out_dirs, dask, jobs)
        elif jobs is not None and jobs > 1 and len(todo) > 1:
            started()
            runs = run_pool(spec, cases, todo, out_dirs, min(jobs, len(todo)))
        else:
            runs = run_serial(spec, cases, todo, out_dirs)
        for i, row, status in runs:
            values = cases[i]
            row = {**{n: values[n] for n in names}, **row}
            rows[i], statuses[i] = row, status
            if stream:
                rec = {**row, "case": case_no[i], "case_dir": os.path.basename(out_dirs[i]),
                       "scene": scene.name, "varied": name, "fixed": fixed, "params": values,
                       "version": _version(),
                       "status": status}
                stream.write(json.dumps(rec) + "\n")
                stream.flush()
            if status != "converged":
                from femslide.app.result import fmt
                print(f"femslide: {scene.name} {' '.join(f'{n}={fmt(values[n])}' for n in names)} failed: "
                      f"{row.get('reason')}",
                      file=sys.stderr)
            if not as_json:
                bar.write(_row_text(names, row))
            bar.update(1)
    finally:
        bar.close()
        if stream:
            stream.close()
        if lock is not None:
            lock.close()   # (closing the file releases the lock)
    if as_json:   # every row with its status (also rows read back from sweep.jsonl)
        print(json.dumps([{**r, "status": st} if r is not None else r for r, st in zip(rows, statuses)]))
    if plot:
        if is_dynamic(cases[0]):
            from femslide.output.plots import ida_plot
            ida_plot(plot, scene.name, names, cases, rows)
        else:
            plot_sweep(plot, scene.name, names[0], cases, rows)
        if not as_json:
            print(f"plot: {plot}")
    if "bad-input" in statuses:
        return 2
    return 0 if all(s == "converged" for s in statuses) else 1


def _row_text(names, res):
    from femslide.app.result import fmt as _fmt
    keys = [k for k in ("phi", "M_max", "slide", "iterations", "t_reached", "error_estimate", "wall_time_s")
            if k in res]
    return ("  ".join(f"{n}={_fmt(res[n]):>12}" for n in names) + f"  converged={res.get('converged')}  "
            + "  ".join(f"{k}={_fmt(res[k])}" for k in keys))


# -- plot --------------------------------------------------------------------------------------------------

ASYMPTOTE_SCENES = ("beam-slider", "beam-fixed")


def plot_sweep(path, scene, name, cases, rows):
    """M_max against the varied parameter (PNG, PDF, SVG by extension); log-log for EI sweeps, with
    the beam-equivalent asymptotes of M_max (1 and 2 terms: (3 EI/(4a))^(1/3) (P(a+d))^(2/3) + P (l+b) L/(3a),
    femslide.scenes.series.M_max_asymptote) for beam-slider and beam-fixed."""
    import matplotlib
    matplotlib.use("Agg", force=False)
    import numpy as np
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    pts = sorted((c[name], r["M_max"]) for c, r in zip(cases, rows)
                 if r and r.get("converged") and r.get("M_max") is not None)
    bad = [c[name] for c, r in zip(cases, rows) if not (r and r.get("converged"))]
    fig = Figure(figsize=(6.4, 4.6), dpi=100)
    FigureCanvasAgg(fig)
    ax = fig.add_subplot()
    x = np.array([p[0] for p in pts], float)
    y = np.array([p[1] for p in pts], float)
    ax.plot(x, y, "o-", color="C0", label=f"{scene}: M_max")
    loglog = name == "EI" and (x > 0).all() and (y > 0).all() and x.size > 0
    if loglog:
        ax.set_xscale("log")
        ax.set_yscale("log")
    if name == "EI" and scene in ASYMPTOTE_SCENES and x.size:
        from femslide.scenes.series import M_max_asymptote
        v = cases[0]
        L_r = (v.get("L") or v["l"]) if scene == "beam-slider" else v["l"]
        xs = np.geomspace(x.min(), x.max(), 200) if x.min() > 0 else np.linspace(x.min(), x.max(), 200)
        p = {k: v[k] for k in ("a", "b", "d", "l", "m", "g")}
        for nt, style in ((1, "--"), (2, ":")):
            ax.plot(xs, [M_max_asymptote(nt, e, L_r=L_r, **p) for e in xs], style, color="C1" if nt == 1 else "C2",
                    label=f"asymptote, {nt} term{'s' if nt > 1 else ''}")
    for xb in bad:
        ax.axvline(xb, color="C3", lw=0.8, alpha=0.6)
    if bad:
        ax.plot([], [], color="C3", lw=0.8, label="not converged")
    from femslide.scenes.params import PARAMS
    unit = PARAMS[name].unit if name in PARAMS else ""
    ax.set_xlabel(f"{name} [{unit}]" if unit and unit != "-" else name)
    ax.set_ylabel("M_max [N m]")
    ax.set_title(f"femslide sweep {scene} --vary {name}")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(loc="best", fontsize=8)
    fig.tight_layout()
    d = os.path.dirname(path)
    if d:
        os.makedirs(d, exist_ok=True)
    fig.savefig(path)
    return path
