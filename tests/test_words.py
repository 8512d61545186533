"""Texts users read say what they mean without pointing at issue numbers.

The project's issues are internal: a user cannot look up "issue 15". The README, every
page of docs/ and the help of ``spurdyn`` and each of its subcommands (built in process by
the real parser) must name what they mean instead.
"""

from __future__ import annotations

import argparse
import re
from pathlib import Path

import pytest

from spurdyn.cli.main import build_parser

ROOT = Path(__file__).resolve().parents[1]
#: "issue 15", "issues 15, 16", "Issue #6", "issue-19": a pointer to an issue number.
ISSUE_NUMBER = re.compile(r"\bissues?[ -]?#?\d", re.IGNORECASE)
PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]


def pointers(text: str) -> list[str]:
    """The lines of ``text`` that point at an issue number."""
    return [line.strip() for line in text.splitlines() if ISSUE_NUMBER.search(line)]


def helps(parser: argparse.ArgumentParser, prog: str = "spurdyn") -> dict[str, str]:
    """The ``--help`` text of ``parser`` and of every subcommand below it, by command."""
    out = {prog: parser.format_help()}
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for name, sub in action.choices.items():
                out.update(helps(sub, f"{prog} {name}"))
    return out


def test_the_pattern_finds_what_it_should():
    found = pointers("the sector model (issue 15)\nIssues 15, 16 ask\nsee issue #6\n"
                     "the issue-19 rule\nan issue of the journal, 12 teeth\n")
    assert len(found) == 4


@pytest.mark.parametrize("page", PAGES, ids=lambda p: str(p.relative_to(ROOT)))
def test_pages_name_no_issue_number(page):
    assert pointers(page.read_text()) == []


def test_help_names_no_issue_number():
    texts = helps(build_parser())
    assert len(texts) > 5  # spurdyn and its subcommands
    found = {cmd: pointers(text) for cmd, text in texts.items() if pointers(text)}
    assert found == {}
