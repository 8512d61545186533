"""The compiled-code gate (spurdyn.jit): its disk cache is keyed on every source the
compiled modules read, found by a quick scan of their import lines."""

from __future__ import annotations

import ast

from spurdyn import jit


def _parsed(source: str) -> set[str]:
    """The spurdyn names a source imports, read by parsing it (the slow, sure way)."""
    names: list[str] = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            names += [node.module] + [f"{node.module}.{a.name}" for a in node.names]
        elif isinstance(node, ast.Import):
            names += [a.name for a in node.names]
    return {n for n in names if n.split(".")[0] == "spurdyn"}


def test_the_scan_finds_every_import_a_parse_finds() -> None:
    """In every source file: a name missed would leave a file out of the cache key."""
    for path in sorted(jit.PACKAGE.rglob("*.py")):
        source = path.read_text()
        missed = _parsed(source) - set(jit.imported_modules(source))
        assert not missed, f"{path.name}: {sorted(missed)}"


def test_the_scan_reads_every_form_of_import() -> None:
    source = '''
import os, spurdyn.geometry.gear as g  # a comment
from spurdyn.contact.constants import (EDGE,  # why
    FLANK as F,
)
def f():
    from spurdyn.solvers.layout import H
'''
    assert set(jit.imported_modules(source)) == {
        "spurdyn.geometry.gear", "spurdyn.contact.constants", "spurdyn.contact.constants.EDGE",
        "spurdyn.contact.constants.FLANK", "spurdyn.solvers.layout", "spurdyn.solvers.layout.H"}


def test_the_key_covers_the_compiled_modules_and_what_they_import() -> None:
    names = {p.relative_to(jit.PACKAGE).as_posix() for p in jit.compiled_sources()}
    assert {"jit.py", "solvers/paper/step_compiled.py", "contact/search_compiled.py",
            "contact/constants.py", "solvers/layout.py"} <= names
    assert "cli/main.py" not in names    # editing the command line keeps the cache
