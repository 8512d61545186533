"""Entry point of the ``spurdyn`` command: ``info``, ``mesh``, ``run``, ``sweep``,
``stiffness``, ``cases``, ``plot`` and ``animate``.

Every refusal is one line on stderr, ``spurdyn: error: <field>: <reason>``, with exit
status 2 and nothing written. ``spurdyn run`` exits with 1 when a run stopped early
(its results so far are kept, marked incomplete).
"""

from __future__ import annotations

import argparse
import json
import math
import sys
from dataclasses import replace
from pathlib import Path
from typing import Any, NoReturn, Sequence

from spurdyn.case.pair_tables import MeshedPair
from spurdyn.cli.inputs import meshed_case, png_target, resolve_pair
from spurdyn.cli.options import DYNAMICS_OVERRIDES, add_dynamics_options, parse_mesh
from spurdyn.errors import InputError
from spurdyn.simulators import MODELS
from spurdyn.settings import BACKENDS, CONTACTS, DEFAULT_MODEL, METHODS

EXIT_BAD_INPUT = 2
#: Exit status when stdout was closed by the reader (128 + SIGPIPE).
EXIT_BROKEN_PIPE = 141


class _Parser(argparse.ArgumentParser):
    """An argument parser whose refusals are one line, like every other refusal."""

    def error(self, message: str) -> NoReturn:
        self.exit(EXIT_BAD_INPUT, f"spurdyn: error: {message} (see {self.prog} --help)\n")


def _info_contact(args: argparse.Namespace, case: MeshedPair) -> tuple[str, float | None]:
    """The contact model ``info`` reports the stiffness of, and the force its strip carries.

    The paper's pair defaults to its point contact, a file to the distributed contact
    under the file's ``[run]`` torque (or ``--torque``); a file without a torque to the
    point contact, unless ``--contact hertz`` asks for the strip (then a torque is needed)."""
    from spurdyn.case.presets import is_preset
    from spurdyn.cli.inputs import case_torque
    from spurdyn.model.loading import static_force
    from spurdyn.solvers.limits import check_torque

    paper = args.case == "paper" or is_preset(args.case)
    contact = args.contact or ("point" if paper else "hertz")
    if contact not in CONTACTS:
        raise InputError("--contact", f"must be one of {', '.join(CONTACTS)} (got {contact!r})")
    torque, field = args.torque, "--torque"
    if torque is None:
        torque, field = case_torque(args.case), "run.torque"
    elif not (math.isfinite(torque) and torque >= 0.0):
        raise InputError("--torque", f"must be a torque in N m, zero or positive (got {torque!r})")
    if torque is not None:
        check_torque(case.pair, torque, field)     # as run refuses it
    known = torque is not None and torque > 0
    if contact == "point" or (not known and args.contact is None):
        return "point", None     # a pair without a load: the strip has no width to report
    if not known:
        raise InputError("--torque", "the Hertzian strip's stiffness depends on the load: give "
                         "the driver's torque (N m) with --torque, or --contact point")
    return contact, static_force(case.pair, float(torque))


def cmd_info(args: argparse.Namespace) -> int:
    from spurdyn.cli.report import format_info, pair_info

    case = meshed_case(args, faults=True)       # shown: the tooth, the kind, the size
    contact, force = _info_contact(args, case)
    info = pair_info(case, contact, force)
    print(json.dumps(info, indent=2) if args.json else format_info(info))
    return 0


def cmd_mesh(args: argparse.Namespace) -> int:
    from spurdyn.results.pictures import draw_mesh_position

    case = meshed_case(args)
    png = png_target(args.png)
    draw_mesh_position(case, png)
    print(f"wrote {png}")
    return 0


#: ``spurdyn run`` options that override a case: (dest, dotted case key, label).
RUN_OVERRIDES = (
    ("dt", "run.dt", "--dt"),
    ("speed_a", "run.speed_a_rpm", "--speed-a"),
    ("speed_b", "run.speed_b_rpm", "--speed-b"),
    ("torque", "run.torque", "--torque"),
    ("angle", "run.angle_deg", "--angle"),
    ("save_every", "run.save_every", "--save-every"),
    ("frames_every", "run.frames_every", "--frames-every"),
    ("method", "run.method", "--method"),
    ("backend", "run.backend", "--backend"),
    ("contact", "run.contact", "--contact"),
    ("grading", "mesh.grading", "--grading"),
    ("row_grading", "mesh.row_grading", "--row-grading"),
)


def run_overrides(args: argparse.Namespace) -> tuple[dict[str, object], dict[str, str]]:
    """The case values given on the command line, and how to name them in refusals."""
    overrides: dict[str, object] = {}
    labels: dict[str, str] = {}
    for dest, key, label in RUN_OVERRIDES + DYNAMICS_OVERRIDES:
        value = getattr(args, dest)
        if value is not None:
            overrides[key] = value
            labels[key] = label
    mesh = parse_mesh(args.mesh)
    if mesh is not None:
        overrides["mesh.nx"], overrides["mesh.ny"] = mesh
        labels["mesh.nx"] = labels["mesh.ny"] = "--mesh"
    if getattr(args, "fault", None):     # beside the case's [[fault]] tables
        overrides["fault"] = tuple(args.fault)
        labels["fault"] = "--fault"
    return overrides, labels


def model_of(cases: Any, flag: str | None) -> str:
    """The model to run: ``--model``, else the one the cases' files ask for (``[model]
    kind``, :data:`~spurdyn.settings.DEFAULT_MODEL` without one; the presets' the FE model)."""
    if flag is not None:
        return flag
    kinds = sorted({case.model for case in cases})
    if len(kinds) > 1:
        raise InputError("--model", f"the cases ask for different models ({', '.join(kinds)}); "
                         "give --model to run them with one")
    return kinds[0] if kinds else DEFAULT_MODEL


def cmd_run(args: argparse.Namespace) -> int:
    from spurdyn.case.presets import resolve_cases
    from spurdyn.cli import run as runner

    if args.jobs < 1:
        raise InputError("--jobs", f"must be a whole number >= 1 (got {args.jobs})")
    overrides, labels = run_overrides(args)
    cases = resolve_cases(args.case, overrides, labels)
    model = model_of(cases, args.model)
    entry = MODELS[model]
    cases = [replace(case, run=entry.with_defaults(case.run)) for case in cases]
    if args.vtu:  # a ParaView series is made of tooth frames: refuse a run that keeps none
        if not entry.keeps_frames:
            raise InputError("--vtu", f"draws the FE teeth; the {model} model has none "
                             "(leave out --vtu or use --model fe)")
        for case in cases:
            if case.run.frames_every < 1:
                raise InputError("--vtu", f"needs tooth frames, but {case.name} keeps none "
                                 "(frames_every = 0); give --frames-every M with M >= 1")
            if case.pair.driver == "b":
                raise InputError("--vtu", f"needs tooth frames, but {case.name} is driven by "
                                 "gear B, whose runs keep none; leave out --vtu")
    for case in cases:   # not ignored in silence: the options, and the keys its file wrote
        entry.refuse(case.run, case.labels(labels), case.pair)
    if not args.allow_large:
        from spurdyn.solvers.limits import check_size

        for case in cases:
            check_size(case, labels, entry.size(case))
    simulate = runner.load_simulate(model)
    plans = runner.plan_runs(cases, args.out, args.force, vtu=args.vtu)
    return runner.run_plans(plans, simulate, jobs=args.jobs, progress=not args.quiet,
                            quiet=args.quiet)


def cmd_cases(args: argparse.Namespace) -> int:
    from spurdyn.case.presets import preset_lines

    print("\n".join(preset_lines()))
    return 0


def cmd_plot(args: argparse.Namespace) -> int:
    from spurdyn.results.io import load_run
    from spurdyn.results.plots import plot_contact_force

    runs = [load_run(d) for d in args.dirs]
    if args.stress:
        from spurdyn.results.stress_plot import plot_stress_history

        if len(runs) != 1:
            raise InputError("--stress", "draws one run: give one run folder")
        png = png_target(args.png or "stress_history.png")
        plot_stress_history(runs[0], png)
    else:
        png = png_target(args.png or "contact_force_overlay.png")
        plot_contact_force(runs, png)
    print(f"wrote {png}")
    return 0


def cmd_animate(args: argparse.Namespace) -> int:
    from spurdyn.results.io import load_run, tooth_frames

    gif = Path(args.gif)
    if gif.suffix.lower() != ".gif":
        raise InputError("--gif", f"must name a .gif file (got {args.gif!r})")
    if not gif.parent.exists():
        raise InputError("--gif", f"folder {str(gif.parent)!r} does not exist")
    if args.magnify is not None and not (args.magnify > 0 and args.magnify < float("inf")):
        raise InputError("--magnify", f"must be a positive number (got {args.magnify})")
    if args.fps < 1:
        raise InputError("--fps", f"must be a whole number >= 1 (got {args.fps})")
    if args.max_frames < 1:
        raise InputError("--max-frames", f"must be a whole number >= 1 (got {args.max_frames})")
    ds = load_run(args.dir)
    tooth_frames(ds)  # refuse a run without frames before drawing anything
    from spurdyn.results.animate import animate_run

    bar = _StepsBar(f"animating {gif.name}", quiet=args.quiet)
    try:
        animate_run(ds, gif, magnify=args.magnify, fps=args.fps, max_frames=args.max_frames,
                    progress=bar)
    finally:
        bar.close()
    print(f"wrote {gif}")
    return 0


class _StepsBar:
    """A tqdm bar of ``done/total`` on a terminal; one line at the start elsewhere."""

    def __init__(self, label: str, quiet: bool = False, stream: object = None) -> None:
        self.stream = sys.stderr if stream is None else stream
        self.label, self.quiet, self.bar, self.said = label, quiet, None, False
        self.tty = bool(getattr(self.stream, "isatty", lambda: False)())

    def __call__(self, done: int, total: int) -> None:
        if self.quiet:
            return
        if not self.tty:
            if not self.said:
                print(f"spurdyn: {self.label} ({total // 2} frames)...", file=self.stream,
                      flush=True)
                self.said = True
            return
        if self.bar is None:
            from tqdm import tqdm

            self.bar = tqdm(total=total, desc=self.label, unit="step", file=self.stream,
                            dynamic_ncols=True, leave=False)
        self.bar.update(done - self.bar.n)

    def close(self) -> None:
        if self.bar is not None:
            self.bar.close()
            self.bar = None


def _add_run_parser(sub: argparse._SubParsersAction) -> None:
    run = sub.add_parser(
        "run", help="run a case and leave result.nc, CSV, picture and summary in a folder",
        description="Run a dynamic contact analysis. CASE is a preset (see 'spurdyn cases') "
        "or a TOML case file; the options override the case. Ctrl-C and SIGTERM stop a run "
        "and keep what it computed. Exit status: 0 complete, 1 incomplete (results so far "
        "kept), 2 bad input (nothing written), 130/143 stopped by Ctrl-C/SIGTERM before "
        "any result (nothing written).")
    run.add_argument("case", metavar="CASE", help="preset name or TOML case file")
    run.add_argument("--out", metavar="DIR", help="output folder (default out/<case name>; "
                     "for a group, the parent of one folder per case)")
    run.add_argument("--force", action="store_true", help="replace an existing output folder")
    run.add_argument("--allow-large", action="store_true",
                     help="run even beyond 2,000,000 steps or 1 GiB of results per case")
    run.add_argument("--dt", type=float, metavar="S", help="time step (s)")
    run.add_argument("--speed-a", type=float, metavar="RPM", help="initial speed of gear A (rpm); B keeps the case's ratio unless --speed-b is given")
    run.add_argument("--speed-b", type=float, metavar="RPM", help="initial speed of gear B (rpm)")
    run.add_argument("--torque", type=float, metavar="NM", help="external torque on the driver (N m)")
    run.add_argument("--fault", action="append", metavar="SPEC",
                     help="a fault beside the case's [[fault]] tables, the keys of one, e.g. "
                     "gear=a,tooth=5,kind=crack,depth=1e-3 or gear=a,tooth=5,kind=chip,height=1e-3,"
                     "width=5e-4; kinds missing, spall, crack, chip (the sector model; docs/faults.md)")
    run.add_argument("--angle", type=float, metavar="DEG",
                     help="rotation of A to simulate (deg; default the whole angle of action)")
    run.add_argument("--mesh", metavar="NXxNY", help="Q8 elements across x along each tooth")
    add_dynamics_options(run)
    run.add_argument("--grading", type=float, metavar="G", help="how much thinner the outline columns of each tooth mesh are than the middle ones (default 1: even; e.g. 6 to resolve a contact strip)")
    run.add_argument("--row-grading", type=float, metavar="G", help="how much taller the fillet rows of each tooth mesh are than its flank rows (default 1: rows even in radius; e.g. 4 to resolve a contact strip along the flank; FE and lumped models)")
    run.add_argument("--save-every", type=int, metavar="K", help="keep every K-th step")
    run.add_argument("--frames-every", type=int, metavar="M",
                     help="keep the tooth displacements every M-th step (0: none)")
    run.add_argument("--method", metavar="|".join(METHODS), help="constraint iteration")
    run.add_argument("--backend", metavar="|".join(BACKENDS), help="solver backend")
    run.add_argument("--contact", metavar="|".join(CONTACTS),
                     help="contact model: hertz (the force over the Hertzian strip; case "
                          "files' default) or point (the paper's; its presets')")
    run.add_argument("--model", choices=tuple(MODELS), metavar="|".join(MODELS),
                     help="fe: the paper's FE contact model (the default, or the case file's "
                     "[model] kind); lumped: two disks and "
                     "a mesh spring (docs/lumped.md); sector: elastic teeth on elastic rims under "
                     "constant torques over --cycles N mesh cycles (docs/sector.md)")
    run.add_argument("--vtu", action="store_true", help="also write a ParaView time series")
    run.add_argument("--jobs", type=int, default=1, metavar="N",
                     help="run the cases of a group side by side on N processes")
    run.add_argument("--quiet", action="store_true", help="no progress bar, no report line")
    run.set_defaults(func=cmd_run)


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="spurdyn", description="Dynamic contact analysis of spur gears "
                     "(Lee & Jang): rigid disks, elastic Q8 teeth, exact contact.")
    parser.add_argument("--version", action="version", version="spurdyn 0.1.0")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)

    info = sub.add_parser("info", help="derived geometry, mesh, stable time step and stiffness")
    info.add_argument("case", metavar="CASE", help="'paper' or a TOML file describing a pair")
    info.add_argument("--json", action="store_true", help="print one JSON object")
    info.add_argument("--mesh", metavar="NXxNY", help="elements across x along the tooth")
    info.add_argument("--grading", type=float, metavar="G", help="how much thinner the outline columns of each tooth mesh are than the middle ones (default 1: even; e.g. 6 to resolve a contact strip)")
    info.add_argument("--row-grading", type=float, metavar="G", help="how much taller the fillet rows of each tooth mesh are than its flank rows (default 1: rows even in radius; e.g. 4 to resolve a contact strip along the flank; FE and lumped models)")
    info.add_argument("--contact", metavar="|".join(CONTACTS),
                      help="the contact model whose stiffness to report (default: point for the "
                           "paper's pair, hertz for a file)")
    info.add_argument("--torque", type=float, metavar="NM",
                      help="the driver's torque the Hertzian strip carries (default: the file's)")
    info.set_defaults(func=cmd_info)

    mesh = sub.add_parser("mesh", help="draw the two teeth and their meshes in mesh position")
    mesh.add_argument("case", metavar="CASE", help="'paper' or a TOML file describing a pair")
    mesh.add_argument("--png", required=True, metavar="FILE", help="picture to write")
    mesh.add_argument("--mesh", metavar="NXxNY", help="elements across x along the tooth")
    mesh.add_argument("--grading", type=float, metavar="G", help="how much thinner the outline columns of each tooth mesh are than the middle ones (default 1: even; e.g. 6 to resolve a contact strip)")
    mesh.add_argument("--row-grading", type=float, metavar="G", help="how much taller the fillet rows of each tooth mesh are than its flank rows (default 1: rows even in radius; e.g. 4 to resolve a contact strip along the flank; FE and lumped models)")
    mesh.set_defaults(func=cmd_mesh)

    _add_run_parser(sub)
    from spurdyn.cli.sweep import add_sweep_parser

    add_sweep_parser(sub)
    from spurdyn.cli.stiffness import add_stiffness_parser

    add_stiffness_parser(sub)
    from spurdyn.cli.crack import add_crack_parser

    add_crack_parser(sub)
    from spurdyn.cli.cache import add_cache_parser

    add_cache_parser(sub)
    from spurdyn.cli.design import add_report_parser

    add_report_parser(sub)

    cases = sub.add_parser("cases", help="list the ready-made cases (presets)")
    cases.set_defaults(func=cmd_cases)

    plot = sub.add_parser("plot", help="overlay the contact force of one or more runs, or "
                                       "draw one run's stresses (--stress)")
    plot.add_argument("dirs", nargs="+", metavar="DIR", help="run folders")
    plot.add_argument("--png", metavar="FILE",
                      help="picture to write (default contact_force_overlay.png, or "
                           "stress_history.png with --stress)")
    plot.add_argument("--stress", action="store_true",
                      help="the root stress of each tooth and the contact pressure against "
                           "the rotation, ISO 6336's nominal stresses dashed")
    plot.set_defaults(func=cmd_plot)

    anim = sub.add_parser("animate", help="animated GIF of the teeth meshing, stress-coloured")
    anim.add_argument("dir", metavar="DIR", help="run folder (with tooth frames)")
    anim.add_argument("--gif", required=True, metavar="FILE", help="GIF to write")
    anim.add_argument("--magnify", type=float, metavar="X",
                      help="magnification of the elastic displacements (default: automatic)")
    anim.add_argument("--fps", type=int, default=15, help="frames per second (default 15)")
    anim.add_argument("--max-frames", type=int, default=150, metavar="K",
                      help="at most K frames, evenly picked (default 150)")
    anim.add_argument("--quiet", action="store_true", help="no progress")
    anim.set_defaults(func=cmd_animate)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; return the exit status.

    Ctrl-C and SIGTERM stop any subcommand (:mod:`spurdyn.signals`); ``run`` and
    ``sweep`` keep what was computed. Output to a closed pipe (``spurdyn info | head``)
    ends the command quietly with status 141 (128 + SIGPIPE), as a shell tool would.
    """
    from spurdyn.signals import Interrupts

    parser = build_parser()
    try:
        args = parser.parse_args(argv)
    except SystemExit as done:  # --help, --version, or a refusal already printed
        return done.code if isinstance(done.code, int) else EXIT_BAD_INPUT
    with Interrupts.installed():
        Interrupts.reset()
        try:
            code = int(args.func(args))
            sys.stdout.flush()  # a closed pipe shows here, not at exit
            return code
        except InputError as err:
            print(f"spurdyn: error: {err}", file=sys.stderr)
            return EXIT_BAD_INPUT
        except KeyboardInterrupt:
            print(f"spurdyn: interrupted by {Interrupts.name()}", file=sys.stderr)
            return Interrupts.exit_status()
        except BrokenPipeError:
            _silence_stdout()
            return EXIT_BROKEN_PIPE
        except OSError as err:  # a file or folder the system refused to read or write
            print(f"spurdyn: error: {os_error_line(err, args)}", file=sys.stderr)
            return EXIT_BAD_INPUT


#: The options naming what a command writes (a path under one of them was being written).
OUTPUT_OPTIONS = ("out", "png", "gif")


def os_error_line(err: OSError, args: argparse.Namespace) -> str:
    """``path: what failed`` for an ``OSError`` no command turned into a refusal.

    The error does not say whether its path was read or written (a missing input file and
    a missing output folder are both ``ENOENT``): a path at or under an output the command
    was given (:data:`OUTPUT_OPTIONS`) "cannot be written"; any other, an input, a cache,
    is named with the system's words alone.
    """
    if err.filename is None:
        return f"{type(err).__name__}: {err.strerror or err}"
    path = Path(str(err.filename)).absolute()
    given = {n: getattr(args, n) for n in OUTPUT_OPTIONS if hasattr(args, n)}
    if given.get("out", "") is None:      # run, sweep and report write under out/ by default
        given["out"] = "out"
    outputs = [Path(str(v)).absolute() for v in given.values() if v is not None]
    if any(path == o or o in path.parents for o in outputs):
        return f"{err.filename}: cannot be written ({err.strerror or err})"
    return f"{err.filename}: {err.strerror or type(err).__name__}"


def _silence_stdout() -> None:
    """Point stdout at /dev/null so that flushing it at exit raises nothing."""
    import os

    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
    except (OSError, ValueError):
        pass


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
