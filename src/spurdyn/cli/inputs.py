"""What the commands' common inputs become: a CASE argument as a pair (with the options'
mesh), and a picture's target. Shared by ``cli.main`` and the commands beside it."""

from __future__ import annotations

import argparse
from dataclasses import replace
from pathlib import Path

from spurdyn.case.pair_tables import MeshedPair, pair_from_dict
from spurdyn.cli.options import parse_mesh
from spurdyn.errors import InputError
from spurdyn.geometry.presets import paper_pair


def resolve_pair(name: str) -> MeshedPair:
    """A pair by name (``paper`` or a preset such as ``paper-fig8``) or from a TOML file."""
    from spurdyn.case.presets import is_preset

    if name == "paper" or is_preset(name):
        return MeshedPair(pair=paper_pair(), name="paper")
    if not name.endswith(".toml") and not Path(name).exists():
        raise InputError("CASE", f"unknown case {name!r}; use 'paper', a preset "
                         "(see 'spurdyn cases') or a .toml file")
    from spurdyn.case.file import read_case_file

    return pair_from_dict(read_case_file(name), name=Path(name).stem)


def case_torque(name: str) -> float | None:
    """The driver's torque (N m) of a CASE argument: the paper's for ``paper`` and the
    presets, a file's ``[run]`` torque (``None`` without one), read and refused as
    ``spurdyn run`` reads and refuses it (:func:`~spurdyn.case.file.read_case_file`)."""
    from spurdyn.case.file import file_torque, read_case_file
    from spurdyn.case.presets import is_preset
    from spurdyn.geometry.presets import PAPER_TORQUE

    if name == "paper" or is_preset(name):
        return PAPER_TORQUE
    resolve_pair(name)                  # the file's tables first, in run's order
    return file_torque(read_case_file(name))


def _with_mesh(case: MeshedPair, mesh: tuple[int, int] | None,
               grading: float | None = None, row_grading: float | None = None) -> MeshedPair:
    nx, ny = (case.nx, case.ny) if mesh is None else mesh
    grading = case.grading if grading is None else grading
    row_grading = case.row_grading if row_grading is None else row_grading
    return replace(case, nx=nx, ny=ny, grading=grading, row_grading=row_grading)


def meshed_case(args: argparse.Namespace, faults: bool = False) -> MeshedPair:
    """The pair of ``info``, ``mesh`` and ``stiffness`` with the options' mesh, a bad mesh
    refused before any work (naming ``--grading`` or ``--row-grading`` when the option gave
    it); its ``[[fault]]`` tables refused unless the command reads ``faults``."""
    from spurdyn.case.file import refuse_faults
    from spurdyn.mesh.tooth import tooth_mesh

    row_grading = getattr(args, "row_grading", None)   # not an option of every command
    case = _with_mesh(resolve_pair(args.case), parse_mesh(args.mesh), args.grading, row_grading)
    if not faults:
        refuse_faults(case, f"`spurdyn {args.command}`" if hasattr(args, "command") else "this command")
    try:
        tooth_mesh(case.pair.gear_a, case.nx, case.ny, grading=case.grading,
                   row_grading=case.row_grading)
    except InputError as err:
        given = {"mesh.grading": args.grading, "mesh.row_grading": row_grading}
        if err.field in ("mesh.nx", "mesh.ny") and args.mesh is not None:
            raise InputError("--mesh", f"{err.field[5:]} {err.reason}") from None
        raise InputError(f"--{err.field[5:].replace('_', '-')}" if given.get(err.field) is not None
                         else err.field, err.reason) from None
    return case


def output_target(text: str, suffix: str, flag: str) -> Path:
    """The file an option names for writing, its suffix and folder checked before any work."""
    path = Path(text)
    if path.suffix.lower() != suffix:
        raise InputError(flag, f"must name a {suffix} file (got {text!r})")
    if not path.parent.exists():
        raise InputError(flag, f"folder {str(path.parent)!r} does not exist")
    return path


def png_target(text: str) -> Path:
    return output_target(text, ".png", "--png")


__all__ = ["case_torque", "meshed_case", "output_target", "png_target", "resolve_pair"]
