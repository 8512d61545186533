"""Entry point of the ``spurdyn`` command.

Every refusal is one line on stderr, ``spurdyn: error: <field>: <reason>``, with exit
status 2 and nothing written.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import NoReturn, Sequence

from spurdyn.casefile import PairCase, load_pair
from spurdyn.errors import InputError
from spurdyn.geometry.presets import paper_pair

EXIT_BAD_INPUT = 2


class _Parser(argparse.ArgumentParser):
    """An argument parser whose refusals are one line, like every other refusal."""

    def error(self, message: str) -> NoReturn:
        self.exit(EXIT_BAD_INPUT, f"{self.prog}: error: {message} (see {self.prog} --help)\n")


def resolve_pair(name: str) -> PairCase:
    """A pair by preset name (``paper``) or from a TOML file."""
    if name == "paper" or name.startswith("paper-"):
        return PairCase(pair=paper_pair(), name="paper")
    if not name.endswith(".toml") and not Path(name).exists():
        raise InputError("CASE", f"unknown case {name!r}; use 'paper' or a .toml file")
    return load_pair(name)


def _parse_mesh(text: str | None) -> tuple[int, int] | None:
    if text is None:
        return None
    try:
        nx, ny = (int(v) for v in text.lower().split("x"))
    except ValueError:
        raise InputError("--mesh", f"must look like NXxNY, e.g. 4x14 (got {text!r})") from None
    return nx, ny


def _with_mesh(case: PairCase, mesh: tuple[int, int] | None) -> PairCase:
    if mesh is None:
        return case
    return PairCase(pair=case.pair, nx=mesh[0], ny=mesh[1], name=case.name)


def cmd_info(args: argparse.Namespace) -> int:
    from spurdyn.cli.report import format_info, pair_info
    from spurdyn.mesh.tooth import tooth_mesh

    case = _with_mesh(resolve_pair(args.case), _parse_mesh(args.mesh))
    tooth_mesh(case.pair.gear_a, case.nx, case.ny)  # refuse a bad mesh before any work
    info = pair_info(case)
    print(json.dumps(info, indent=2) if args.json else format_info(info))
    return 0


def cmd_mesh(args: argparse.Namespace) -> int:
    from spurdyn.results.pictures import draw_mesh_position

    case = _with_mesh(resolve_pair(args.case), _parse_mesh(args.mesh))
    png = Path(args.png)
    if png.suffix.lower() != ".png":
        raise InputError("--png", f"must name a .png file (got {args.png!r})")
    if not png.parent.exists():
        raise InputError("--png", f"folder {str(png.parent)!r} does not exist")
    draw_mesh_position(case, png)
    print(f"wrote {png}")
    return 0


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="spurdyn", description="Dynamic contact analysis of spur gears "
                     "(Lee & Jang): rigid disks, elastic Q8 teeth, exact contact.")
    parser.add_argument("--version", action="version", version="spurdyn 0.1.0")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)

    info = sub.add_parser("info", help="derived geometry, mesh, stable time step and stiffness")
    info.add_argument("case", metavar="CASE", help="'paper' or a TOML file describing a pair")
    info.add_argument("--json", action="store_true", help="print one JSON object")
    info.add_argument("--mesh", metavar="NXxNY", help="elements across x along the tooth")
    info.set_defaults(func=cmd_info)

    mesh = sub.add_parser("mesh", help="draw the two teeth and their meshes in mesh position")
    mesh.add_argument("case", metavar="CASE", help="'paper' or a TOML file describing a pair")
    mesh.add_argument("--png", required=True, metavar="FILE", help="picture to write")
    mesh.add_argument("--mesh", metavar="NXxNY", help="elements across x along the tooth")
    mesh.set_defaults(func=cmd_mesh)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; return the exit status."""
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return int(args.func(args))
    except InputError as err:
        print(f"spurdyn: error: {err}", file=sys.stderr)
        return EXIT_BAD_INPUT


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
