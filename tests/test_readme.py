"""The commands the README and docs/cli.md show are commands spurdyn accepts.

Each ``spurdyn ...`` line of a code block is parsed by the real argument parser and its
CASE resolved (preset, group or file, from the repository root), without running it, so
a renamed preset or option cannot leave a user a tour that fails at the first step.
"""

from __future__ import annotations

import re
import shlex
from pathlib import Path

import pytest

from spurdyn.case import resolve_cases
from spurdyn.cli.main import build_parser, resolve_pair, run_overrides

ROOT = Path(__file__).resolve().parents[1]


def shown_commands(path: Path) -> list[str]:
    """The ``spurdyn`` command lines inside the fenced code blocks of ``path``."""
    lines, inside = [], False
    for line in path.read_text().splitlines():
        if line.startswith("```"):
            inside = not inside
            continue
        if inside and line.startswith("spurdyn "):
            lines.append(re.sub(r"\s+#.*$", "", line).strip())
    return lines


COMMANDS = shown_commands(ROOT / "README.md") + shown_commands(ROOT / "docs" / "cli.md")


def test_the_readme_shows_a_tour():
    names = {shlex.split(c)[1] for c in shown_commands(ROOT / "README.md")}
    assert {"info", "mesh", "cases", "run", "plot", "animate", "sweep"} <= names


@pytest.mark.parametrize("command", COMMANDS)
def test_shown_command_parses_and_its_case_resolves(command, monkeypatch):
    monkeypatch.chdir(ROOT)
    argv = shlex.split(command)[1:]
    if any("[" in a or "|" in a or a.isupper() for a in argv):
        pytest.skip("a synopsis, not a command")
    args = build_parser().parse_args(argv)   # SystemExit (a failure) if an option is wrong
    if args.command in ("info", "mesh"):
        resolve_pair(args.case)
    elif args.command == "run":
        overrides, labels = run_overrides(args)
        assert resolve_cases(args.case, overrides, labels)
    elif args.command == "sweep":
        assert resolve_cases(args.case, check_step=False)
