"""Regenerate the validation report ``docs/validation.md`` and its figures.

Run from the repository root::

    .venv/bin/python docs/make_validation.py [--rerun | --runs-only | --sweep]

The code is the package ``docs/validation_report/`` (its docstring says what is where).
"""

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))  # docs/, where the package lives

from validation_report.report import main  # noqa: E402

if __name__ == "__main__":
    sys.exit(main())
