"""Option parsing shared by the subcommands (below :mod:`spurdyn.cli.main` and
:mod:`spurdyn.cli.sweep`, which both import it)."""

from __future__ import annotations

from spurdyn.errors import InputError


def parse_mesh(text: str | None) -> tuple[int, int] | None:
    """``"4x14"`` -> ``(4, 14)``; ``None`` stays ``None``.

    Raises
    ------
    InputError
        Naming ``--mesh`` when the text is not ``NXxNY``.
    """
    if text is None:
        return None
    try:
        nx, ny = (int(v) for v in text.lower().split("x"))
    except ValueError:
        raise InputError("--mesh", f"must look like NXxNY, e.g. 4x14 (got {text!r})") from None
    return nx, ny


__all__ = ["parse_mesh"]
