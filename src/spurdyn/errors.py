"""Errors raised for bad input, so the command line can explain them in one line."""

from __future__ import annotations


class InputError(ValueError):
    """A bad value in a user description (gear, pair, mesh, case, TOML file).

    Parameters
    ----------
    field
        Dotted name of the offending field as the user wrote it, e.g. ``gear_a.teeth``.
    reason
        What is wrong and, where possible, how to fix it.
    """

    def __init__(self, field: str, reason: str) -> None:
        self.field = field
        self.reason = reason
        super().__init__(f"{field}: {reason}")

    def prefixed(self, prefix: str) -> "InputError":
        """Return the same error with ``prefix.`` put in front of the field name."""
        return InputError(f"{prefix}.{self.field}" if prefix else self.field, self.reason)
