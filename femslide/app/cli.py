"""The command line: ``femslide COMMAND ...`` (``femslide --help``, ``femslide COMMAND --help``).

    femslide scenes [--json]
    femslide solve SCENE [--set NAME=VALUE]... [--json] [--out DIR]
    femslide simulate SCENE [--set NAME=VALUE]... [--json] [--out DIR] [--max-time S]
    femslide sweep SCENE --vary NAME=V1,V2,... [--vary ...] [--set NAME=VALUE]... [--json] [--out DIR]
                   [--jobs N] [--dask ADDRESS] [--resume] [--plot FILE]
    femslide modes FILE.toml [--count N] [--set NAME=VALUE]... [--json] [--out DIR]
    femslide buckling FILE.toml [--count N] [--about equilibrium|reference] [--combination NAME]
                      [--set NAME=VALUE]... [--json] [--out DIR]
    femslide mesh SCENE [--set NAME=VALUE]... [--out FILE]
    femslide show RESULT.vtu|RESULT.pvd [--frame K] [--screenshot FILE.png]
                  [--diagram M|V|N] [--scale K] [--magnify K] [--units N|kN] [--no-loads]
    femslide init SCENE [DIR]
    femslide --version

SCENE is a built-in scene name, a scene file (``*.toml`` with a ``scene`` key, see
femslide/app/scenefile.py) or a structure file (``*.toml`` declaring rods, bodies, joints and loads, see
femslide/app/structfile.py).

Exit status: 0 converged, 1 failed to converge (reason on stderr), 2 bad input (the message names
the parameter and its allowed range).  This module imports nothing heavy: the scene's runner pulls in
what that scene needs.
"""
from __future__ import annotations

import argparse
import json
import os
import sys

from femslide.app.result import clean as _clean
from femslide.app.result import fmt as _fmt
from femslide.app.run import load_target as _target
from femslide.app.run import run_case, start_up, started
from femslide.errors import BadInput, SolverFailure
from femslide.scenes.catalog import SCENES
from femslide.scenes.params import parse_assignments


def _columns() -> int:
    """The terminal's width as shutil.get_terminal_size finds it (COLUMNS, then the terminal of
    stdout, else 80), once per process: argparse asks for it at every argument it adds, importing
    shutil (and with it zlib, bz2, lzma) for it."""
    if not _WIDTH:
        try:
            cols = int(os.environ["COLUMNS"])
        except (KeyError, ValueError):
            cols = 0
        if cols <= 0:
            try:
                cols = os.get_terminal_size(sys.__stdout__.fileno()).columns
            except (AttributeError, ValueError, OSError):
                cols = 0
        _WIDTH.append(cols if cols > 0 else 80)
    return _WIDTH[0]


_WIDTH: list = []


class _Formatter(argparse.HelpFormatter):
    def __init__(self, prog, indent_increment=2, max_help_position=24, width=None):
        super().__init__(prog, indent_increment, max_help_position, _columns() - 2 if width is None else width)


class _Parser(argparse.ArgumentParser):
    def __init__(self, *args, **kwargs):
        kwargs.setdefault("formatter_class", _Formatter)
        super().__init__(*args, **kwargs)

    def error(self, message):  # argparse exits 2 too, but without a traceback and with our prefix
        self.print_usage(sys.stderr)
        raise BadInput(message)


SCENE_HELP = ("a built-in scene name (femslide scenes lists them), a scene file *.toml or a structure "
              "file *.toml")
SET_HELP = ("change a parameter: a scene's (EI=1e8) or a structure's field (right.EI=1e8, "
            "wind.force=[0,-500], elements=32); repeatable, overrides the file")
EPILOG = "Exit status: 0 converged, 1 failed to converge (reason on stderr), 2 bad input."


def _version() -> str:
    from femslide.version import __version__
    return __version__


class _VersionAction(argparse.Action):
    """``--version``: the version and which assembly runs (the compiled kernel or the numpy path),
    found out only when asked (it imports numpy)."""

    def __init__(self, option_strings, dest=argparse.SUPPRESS, default=argparse.SUPPRESS, help=None):
        super().__init__(option_strings=option_strings, dest=dest, default=default, nargs=0, help=help)

    def __call__(self, parser, namespace, values, option_string=None):
        from femslide.model.fast import status
        print(f"femslide {_version()}\n{status()}")
        parser.exit()


COMMANDS = ("scenes", "solve", "simulate", "sweep", "modes", "buckling", "mesh", "show", "init")
RUNS = ("solve", "simulate", "sweep", "modes", "buckling")   # the commands that run cases (run_case)


def _build_parser(only: str | None = None) -> argparse.ArgumentParser:
    """The command line's parser; ``only``: just that command's subparser (a run of one command
    needs no other; ``femslide --help`` builds them all)."""

    def want(name):
        return only is None or only == name

    p = _Parser(prog="femslide", description="Planar structures on flexible rods with sliding joints: "
                "exact spring-hinge models, corotational beam FE statics and dry-friction dynamics. "
                "SI units throughout.", epilog=EPILOG)
    p.add_argument("--version", action=_VersionAction,
                   help="print the femslide version and which assembly runs (compiled kernel or numpy), and exit")
    sub = p.add_subparsers(dest="cmd", required=True, parser_class=_Parser, metavar="COMMAND",
                           help="one of the commands below; `femslide COMMAND --help` describes it")
    if want("scenes"):
        _scenes_parser(sub)
    _solve_parsers(sub, want)
    if want("modes"):
        _modes_parser(sub)
    if want("buckling"):
        _buckling_parser(sub)
    if want("mesh"):
        _mesh_parser(sub)
    if want("show"):
        _show_parser(sub)
    if want("init"):
        _init_parser(sub)
    return p


def _scenes_parser(sub):
    sc = sub.add_parser("scenes", help="list the built-in scenes, their parameters and defaults",
                        description="List the built-in scenes: their command (solve or simulate), model, "
                        "and every parameter with its default, unit and allowed range.")
    sc.add_argument("--json", action="store_true", help="print the list as JSON")


def _solve_parsers(sub, want):
    about = {
        "solve": ("static equilibrium of a scene or structure",
                  "Static equilibrium on the principal branch (all loads ramped from zero), with the mesh "
                  "refined until the named results are accurate to about 1e-7. Prints the named results "
                  "(reactions, joint forces, rod moments, error_estimate)."),
        "simulate": ("time history of a dynamic scene or a structure file",
                     "Time history of a dynamic scene (the dry-friction oscillator or the reduced "
                     "structure dynamics: turning points, stop, amplitudes) or of a structure file with a "
                     "[simulate] table (FE dynamics: peaks of the reactions, rod moments and slides, friction "
                     "events, natural frequencies; --set simulate.KEY=VALUE overrides the table)."),
        "sweep": ("solve a scene for several values of one parameter",
                  "Solve a scene once per value of one parameter, each case from the scene's own start "
                  "(rows equal `femslide solve` of that case), in process, in N processes or on Dask. "
                  "A failed case is reported in its row and the sweep goes on."),
    }
    for name, (short, long) in about.items():
        if not want(name):
            continue
        s = sub.add_parser(name, help=short, description=long, epilog=EPILOG)
        s.add_argument("scene", metavar="SCENE", help=SCENE_HELP)
        s.add_argument("--set", action="append", default=[], metavar="NAME=VALUE", help=SET_HELP)
        s.add_argument("--json", action="store_true",
                       help="print one JSON object on stdout instead of text" if name != "sweep" else
                       "print the rows on stdout as a JSON list of solve objects instead of text")
        s.add_argument("--out", metavar="DIR",
                       help="write VTU files, sidecar JSON and result.json into DIR" if name != "sweep" else
                       "stream rows to DIR/sweep.jsonl and write each case's files to DIR/case_NNN; "
                       "rerunning with the same DIR skips the cases already done")
        s.add_argument("--quiet", action="store_true", help="no progress bar (it is drawn on a terminal only)")
        if name == "solve":
            s.add_argument("--path", choices=("principal", "arc-length"),
                           help="principal: the equilibrium reached by ramping the loads (exit 1 at a limit "
                           "point, named with its load factor); arc-length: follow the path through limit "
                           "points to the first equilibrium at full load (structure files; also "
                           "--set solve.path=...)")
            s.add_argument("--theory", choices=("nonlinear", "linear"),
                           help="nonlinear: exact large rotations (default); linear: first-order theory, "
                           "equilibrium on the undeformed structure (structure files)")
        if name == "simulate":
            s.add_argument("--max-time", metavar="S", type=float,
                           help="stop the run after S seconds of wall time (exit 1, the reason named, the history "
                           "so far written with --out); default: no limit (also --set simulate.max_time=S)")
        if name == "sweep":
            s.add_argument("--vary", required=True, action="append", metavar="NAME=V1,V2,...",
                           help="the varied parameter and its values (commas inside [...] belong to a value); "
                           "repeatable: every combination (e.g. --vary simulate.ground.record=a.AT2,b.csv --vary "
                           "simulate.ground.scale=0.5,1,2: an incremental dynamic analysis of a record suite)")
            s.add_argument("--jobs", type=int, default=None, metavar="N",
                           help="solve the cases in N processes; with --dask local: N worker processes "
                           "(default: in this process; --dask local alone: one worker per case, at most the "
                           "CPU count and 8)")
            s.add_argument("--dask", metavar="ADDRESS",
                           help="run the cases on Dask: 'local' (a LocalCluster) or tcp://host:port (a running "
                           "scheduler whose workers have femslide installed); needs femslide[dask]")
            s.add_argument("--resume", action="store_true",
                           help="skip the cases already in DIR/sweep.jsonl (rerunning with the same --out does too)")
            s.add_argument("--plot", metavar="FILE",
                           help="draw M_max against the varied parameter into FILE (.png, .pdf, .svg; matplotlib)")


def _modes_parser(sub):
    mo = sub.add_parser("modes", help="natural frequencies and mode shapes of a structure file",
                        description="Natural frequencies [Hz] and mode shapes (VTU with --out) of a structure "
                        "file: the lowest eigenvalues of the linearised frictionless structure about its static "
                        "equilibrium (rod mass rhoA lumped at the nodes, bodies' mass and inertia).",
                        epilog=EPILOG)
    mo.add_argument("scene", metavar="FILE.toml", help="a structure file")
    mo.add_argument("--set", action="append", default=[], metavar="NAME=VALUE",
                    help="change a field of the file, e.g. right.EI=1e8, or elements=N (every rod's mesh)")
    mo.add_argument("--count", type=int, default=6, help="how many of the lowest frequencies (default 6)")
    mo.add_argument("--json", action="store_true", help="print the result as one JSON object")
    mo.add_argument("--out", metavar="DIR", help="write one VTU per mode shape and result.json here")
    mo.add_argument("--quiet", action="store_true", help="no progress bar")


def _buckling_parser(sub):
    bu = sub.add_parser("buckling", help="linear buckling load factors and mode shapes of a structure file",
                        description="The lowest load factors at which the structure under its loads loses "
                        "stability (linear buckling: the tangent's elastic and geometric parts about the "
                        "loaded equilibrium, or about the reference state with --about reference), refined "
                        "with the mesh, with the mode shapes (VTU files and a PVD series with --out).",
                        epilog=EPILOG)
    bu.add_argument("scene", metavar="FILE.toml", help="a structure file")
    bu.add_argument("--set", action="append", default=[], metavar="NAME=VALUE",
                    help="change a field of the file, e.g. right.EI=1e8, or elements=N (a fixed mesh)")
    bu.add_argument("--count", type=int, default=4, help="how many of the lowest load factors (default 4)")
    bu.add_argument("--about", choices=("equilibrium", "reference"), default="equilibrium",
                    help="the state whose stresses are scaled: the equilibrium under the loads (default) or "
                    "the reference state with the stresses of first-order theory (classic linear buckling)")
    bu.add_argument("--combination", metavar="NAME", help="the loads of this load combination (default: every "
                    "load as declared)")
    bu.add_argument("--json", action="store_true", help="print the result as one JSON object")
    bu.add_argument("--out", metavar="DIR", help="write the mode shapes (VTU, PVD) and result.json here")
    bu.add_argument("--quiet", action="store_true", help="no progress bar")


def _mesh_parser(sub):
    m = sub.add_parser("mesh", help="write the reference mesh of an FE scene (meshio format by extension)",
                       description="Write the reference mesh of a built-in FE statics scene: the undeformed "
                       "rods as line cells in named groups (rod:NAME), supports, rigid rods and the body.")
    m.add_argument("scene", metavar="SCENE", help="an FE statics scene: a built-in name or a scene file *.toml")
    m.add_argument("--set", action="append", default=[], metavar="NAME=VALUE",
                   help="change a parameter (n_elements=N sets the elements per rod; default 64); repeatable")
    m.add_argument("--out", metavar="FILE", help="the mesh file, format by extension (default: SCENE.vtu)")


def _show_parser(sub):
    sh = sub.add_parser("show", help="draw a result (.vtu, or a frame of a .pvd) with pyvista",
                        description="Draw a result file with pyvista: the deformed rods coloured by their "
                        "bending moment, the bodies and the undeformed configuration. Opens a window, or "
                        "renders off-screen with --screenshot (EGL: no X server needed).")
    sh.add_argument("result", metavar="RESULT", help="a .vtu file, or a .pvd series written by --out")
    sh.add_argument("--frame", type=int, metavar="K", help="frame K of a .pvd series (default: the last)")
    sh.add_argument("--screenshot", metavar="FILE.png", help="render off-screen to this image instead of a window")
    sh.add_argument("--diagram", choices=("M", "V", "N"),
                    help="member diagrams on the deformed structure: M bending moment [N m] on the "
                         "tension side, V shear force or N axial force [N] (positive to the left of "
                         "the rod from start to end); extremes labelled, supports and guides drawn")
    sh.add_argument("--scale", type=float, metavar="K",
                    help="diagram scale in m per N m (M) or m per N (V, N); default: the largest "
                         "|value| of the series drawn at 15%% of the structure's size")
    sh.add_argument("--magnify", type=float, default=1.0, metavar="K",
                    help="multiply the displacements by K (default 1; the undeformed shape is drawn grey)")
    sh.add_argument("--units", choices=("N", "kN"), default="N",
                    help="forces in N or kN, moments in N m or kN m (colour bar, labels, arrows; default N)")
    sh.add_argument("--no-loads", action="store_true",
                    help="leave out the load and reaction arrows (drawn with their values by default)")


def _init_parser(sub):
    it = sub.add_parser("init", help="copy a scene's template file (and its mesh) to edit",
                        description="Copy the template of a built-in scene into DIR: its scene file NAME.toml "
                        "and the reference mesh it names, or with structures/NAME the scene declared as a "
                        "structure file. Existing files are never overwritten.")
    it.add_argument("scene", metavar="SCENE",
                    help="a built-in scene name (beam-slider) or structures/NAME (the FE scene as a structure file)")
    it.add_argument("dir", metavar="DIR", nargs="?", default=".",
                    help="folder to copy into (created if missing; default: the current folder)")


def _print_scenes(as_json: bool):
    if as_json:
        out = []
        for s in SCENES.values():
            out.append({"name": s.name, "command": s.command, "model": s.model,
                        "params": [{"name": p.name, "default": p.default, "unit": p.unit,
                                    "allowed": p.range_text(), "meaning": p.meaning,
                                    **({"derived": p.derived} if p.derived else {})}
                                   for p in s.params.params()]})
        print(json.dumps(out, indent=1))
        return
    for s in SCENES.values():
        print(f"{s.name}  ({s.command})  {s.model}")
        for p in s.params.params():
            default = p.derived if p.default is None and p.derived else _fmt(p.default)
            print(f"    {p.name:<12} {default:>12} {p.unit:<8} {p.range_text():<28} {p.meaning}")
        print()


def _print_result(res: dict):
    """One line per value with its SI unit; named objects (rods, joints, ...) one line each with their
    values; the files written and the notes one per line."""
    from femslide.app.result import unit_of
    from femslide.results.outcome import dotted

    def with_unit(path, x):
        u = unit_of(path) if isinstance(x, (int, float)) and not isinstance(x, bool) else ""
        return f"{_fmt(x)} {u}" if u else _fmt(x)

    def flat(d, path):
        return [f"{k}={with_unit(path + '.' + k, x)}" for k, x in dotted(d).items()]

    for key, val in res.items():
        if key in ("files", "notes") and isinstance(val, list):
            for item in val:
                print(f"{key[:-1]:>24}: {item}")
        elif isinstance(val, dict) and val and all(isinstance(x, dict) for x in val.values()):
            for name, obj in val.items():
                print(f"{key + '.' + name:>24}: {', '.join(flat(obj, key + '.' + name))}")
        elif isinstance(val, dict):
            if val:
                print(f"{key:>24}: {', '.join(flat(val, key))}")
        elif isinstance(val, list) and len(val) <= 20 and all(isinstance(x, (int, float)) for x in val):
            u = unit_of(key)
            print(f"{key:>24}: {', '.join(_fmt(x) for x in val)}" + (f" {u}" if u else ""))
        elif isinstance(val, list):
            print(f"{key:>24}: [{len(val)} entries]")
        else:
            print(f"{key:>24}: {with_unit(key, val)}")


def _solve(args, command):
    tgt = _target(args.scene)
    scene = tgt.scene
    if command == "simulate" and getattr(scene, "spec", None):
        tgt = scene = scene.for_simulate()   # a structure file (target and scene): its [simulate] table
    if scene.command != command:
        raise BadInput(f"scene {scene.name} is a '{scene.command}' scene; run: femslide {scene.command} {args.scene}")
    given = parse_assignments(args.set)
    if getattr(args, "max_time", None) is not None:
        if not hasattr(scene, "simulate_table"):
            raise BadInput(f"--max-time is for structure files (a [simulate] table); {args.scene} is a scene")
        given["simulate.max_time"] = args.max_time
    for opt in ("path", "theory"):
        if getattr(args, opt, None) is not None:
            if not getattr(scene, "solve_options", None):
                raise BadInput(f"--{opt} is for structure files (rods, bodies, joints); {args.scene} is a scene")
            given[f"solve.{opt}"] = getattr(args, opt)
    values = tgt.resolve(given)
    try:
        res = run_case(scene, values, out=args.out, quiet=args.quiet)
    except SolverFailure as exc:
        part = getattr(exc, "result", None)   # a simulation stopped half way: what it computed
        extra = {k: part[k] for k in ("t_reached", "t_end", "peaks", "events") if k in part} if part else {}
        if getattr(exc, "files", None):
            extra["files"] = exc.files
        if args.json:
            print(json.dumps(_clean({"converged": False, "reason": exc.reason, **_critical(exc), **extra,
                                     "history": exc.history})))
        what = "stopped" if getattr(exc, "time_limit", False) else "failed to converge"
        print(f"femslide: {scene.name} {what}: {exc}", file=sys.stderr)
        if extra.get("files") and not args.json:
            print(f"femslide: what was computed up to t = {extra.get('t_reached', 0.0):g} s is written: "
                  f"{', '.join(extra['files'][:3])}{' ...' if len(extra['files']) > 3 else ''}", file=sys.stderr)
        return 1
    if args.json:
        print(json.dumps(_clean(res)))
    else:
        _print_result(_clean(res))
    if not res.get("converged", True) and res.get("reason"):
        print(f"femslide: {scene.name}: {res['reason']}", file=sys.stderr)
    return 0 if res.get("converged", True) else 1


def _critical(exc) -> dict:
    """The critical point a failed statics named (femslide.analysis.limits), for the JSON."""
    c = getattr(exc, "critical", None)
    if c is None or isinstance(c, bool):
        return {}
    rel = None if c.error is None else c.error / max(abs(c.lam), 1e-300)
    return {"limit_point": {"kind": c.kind, "load_factor": c.lam, "error_estimate": rel}}


def _parse_vary(text):
    if "=" not in text:
        raise BadInput(f"--vary expects NAME=V1,V2,..., got {text!r}")
    name, vals = text.split("=", 1)
    # commas inside brackets belong to a value: --vary wind.force=[0,0],[500,0]
    items, depth, cur = [], 0, ""
    for ch in vals:
        depth += ch in "[{"
        depth -= ch in "]}"
        if ch == "," and depth == 0:
            items.append(cur)
            cur = ""
        else:
            cur += ch
    items = [v.strip() for v in items + [cur] if v.strip()]
    if not items:
        raise BadInput(f"--vary {name}: no values given")
    return name.strip(), items


def _sweep(args):
    from femslide.app.sweeps import run_sweep
    pairs = [_parse_vary(v) for v in args.vary]
    name, items = (pairs[0] if len(pairs) == 1 else ([p[0] for p in pairs], [p[1] for p in pairs]))
    return run_sweep(_target(args.scene), name, items, parse_assignments(args.set), as_json=args.json,
                     out=args.out, jobs=args.jobs, dask=args.dask, resume=args.resume, plot=args.plot,
                     quiet=args.quiet)


def _structure_command(args, command, count_max):
    """(scene, values) of `femslide modes|buckling FILE`: the file's scene for the command, checked
    (a structure file; --count in [1, count_max]), with its --set values resolved."""
    tgt = _target(args.scene)
    if not getattr(tgt.scene, "spec", None) or not hasattr(tgt.scene, f"for_{command}"):
        raise BadInput(f"{args.scene}: `femslide {command}` takes a structure file (rods, bodies, joints)")
    if not 1 <= args.count <= count_max:
        raise BadInput(f"--count = {args.count}; allowed: an integer in [1, {count_max}]")
    scene = getattr(tgt.scene, f"for_{command}")()
    return scene, scene.resolve(parse_assignments(args.set))


def _emit(res, args) -> int:
    """Print a result as JSON or text; exit status 0."""
    if args.json:
        print(json.dumps(_clean(res)))
    else:
        _print_result(_clean(res))
    return 0


def _modes(args):
    scene, values = _structure_command(args, "modes", 100)
    return _emit(run_case(scene, {**values, "_count": args.count}, out=args.out, quiet=args.quiet), args)


def _buckling(args):
    scene, values = _structure_command(args, "buckling", 50)
    if args.combination is not None:
        names = [c.name for c in scene.structure.combinations.values()]
        if args.combination not in names:
            raise BadInput(f"--combination {args.combination}: no such combination; combinations: "
                           f"{', '.join(names) or 'none'}")
    res = run_case(scene, {**values, "_count": args.count, "_about": args.about, "_combination": args.combination},
                   out=args.out, quiet=args.quiet)
    return _emit(res, args)


def _mesh(args):
    from femslide.app.scenefile import is_fe, no_mesh_reason
    tgt = _target(args.scene)
    scene = tgt.scene
    if not is_fe(scene):
        raise BadInput(no_mesh_reason(scene))
    values = tgt.resolve(parse_assignments(args.set))
    from femslide.app import meshfile
    path = meshfile.write(scene.name, values, args.out or f"{scene.name}.vtu")
    print(path)
    return 0


def _show(args):
    import warnings

    from femslide.output.show import render
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        info = render(args.result, screenshot=args.screenshot, frame=args.frame, diagram=args.diagram,
                      scale=args.scale, magnify=args.magnify, units=args.units, loads=not args.no_loads)
    for w in caught:   # the picture's notes (lift-off, below ground) as plain messages
        print(f"femslide: note: {w.message}", file=sys.stderr)
    if args.screenshot:
        print(args.screenshot)
    return 0 if info else 1


def _init(args):
    from femslide.app.scenefile import copy_template
    for path in copy_template(args.scene, args.dir):
        print(path)
    return 0


def _check_outputs(args):
    """Output paths (--out, --plot, --screenshot) writable, before any work (femslide/app/outputs.py)."""
    from femslide.app.outputs import check
    check(args)


def main(argv=None) -> int:
    # The solvers factorise many small matrices; multithreaded OpenBLAS only costs there (up to 11x on
    # a busy 2-core machine).  One BLAS thread unless the user chose otherwise: effective because the
    # command line imports no numpy before this point.
    os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
    try:
        try:
            if argv is None and len(sys.argv) > 1 and sys.argv[1] in RUNS:
                start_up()   # a process of its own: no garbage collection during the imports
            argv = sys.argv[1:] if argv is None else list(argv)
            args = _build_parser(argv[0] if argv and argv[0] in COMMANDS else None).parse_args(argv)
        except SystemExit as exc:  # --help, --version: printed, exit status 0
            return exc.code if isinstance(exc.code, int) else 0
        _check_outputs(args)
        if args.cmd == "scenes":
            _print_scenes(args.json)
            return 0
        if args.cmd in ("solve", "simulate"):
            return _solve(args, args.cmd)
        if args.cmd == "mesh":
            return _mesh(args)
        if args.cmd == "modes":
            return _modes(args)
        if args.cmd == "buckling":
            return _buckling(args)
        if args.cmd == "show":
            return _show(args)
        if args.cmd == "init":
            return _init(args)
        return _sweep(args)
    except BadInput as exc:
        print(f"femslide: error: {exc}", file=sys.stderr)
        return 2
    except SolverFailure as exc:
        print(f"femslide: failed: {exc}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        print("femslide: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:  # output piped into a command that stopped reading (| head)
        try:
            sys.stdout = open(os.devnull, "w")
        except OSError:
            pass
        return 0
    except Exception as exc:  # an internal error: say so plainly; FEMSLIDE_DEBUG=1 shows the traceback
        if os.environ.get("FEMSLIDE_DEBUG"):
            raise
        print(f"femslide: internal error: {type(exc).__name__}: {exc} "
              f"(set FEMSLIDE_DEBUG=1 for the traceback)", file=sys.stderr)
        return 1
    finally:
        started()


if __name__ == "__main__":
    sys.exit(main())
