"""``python docs/validation PAGE [OPTIONS]``: write one validation page (see the package)."""

from __future__ import annotations

import sys
from importlib import import_module
from pathlib import Path
from typing import Sequence

DOCS = Path(__file__).resolve().parent.parent
if str(DOCS) not in sys.path:       # run as a folder: the package lives in docs/
    sys.path.insert(0, str(DOCS))


def main(argv: Sequence[str] | None = None) -> int:
    """Run the generator of the page named first in ``argv`` with the rest of it.

    Parameters
    ----------
    argv : sequence of str, optional
        ``PAGE [OPTIONS]`` (``sys.argv[1:]`` by default); without a page, or with
        ``-h``/``--help``, the pages are listed.

    Returns
    -------
    int
        The exit status: the generator's, or 2 for an unknown page.
    """
    from validation import PAGES

    args = list(sys.argv[1:] if argv is None else argv)
    if not args or args[0] in ("-h", "--help"):
        print("usage: python docs/validation PAGE [OPTIONS]  (PAGE --help: its options)\n\npages:")
        for page, module in PAGES.items():
            print(f"  {page:<28} docs/validation/{module.split('.')[0]}")
        return 0
    page = args[0].removesuffix(".md")
    if page not in PAGES:
        print(f"unknown page {args[0]!r}; one of: {', '.join(PAGES)}", file=sys.stderr)
        return 2
    return import_module(f"validation.{PAGES[page]}").main(args[1:]) or 0


if __name__ == "__main__":
    sys.exit(main())
