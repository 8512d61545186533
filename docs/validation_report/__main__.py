"""``python -m validation_report [--rerun|--runs-only|--sweep]``, run from ``docs/``."""

import sys

from .report import main

sys.exit(main())
