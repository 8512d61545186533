"""Section 7 of the report: the dynamic factor against speed, as
``docs/validation/sweep.py`` last wrote it."""

from __future__ import annotations

from .settings import SWEEP_FRAGMENT


def section_sweep() -> str:
    """The dynamic-factor curves, as ``docs/validation/sweep.py`` last wrote them."""
    if not SWEEP_FRAGMENT.exists():
        raise SystemExit(f"{SWEEP_FRAGMENT} is missing: run "
                         "python docs/validation validation_sweep first")
    lines = SWEEP_FRAGMENT.read_text(encoding="utf-8").splitlines()
    body = [ln for ln in lines if not ln.startswith("<!--")]
    # its "## Dynamic factor ..." heading becomes section 7 of this page
    body = [f"## 7. {ln[3:]}\n\n![dynamic factor against speed](figures/dynamic_factor_sweep.png)"
            if ln.startswith("## ") else ln for ln in body]
    return ("\n" + "\n".join(body) + "\n\n*Section 7 is written by `docs/validation/sweep.py` "
            "from two `spurdyn sweep` runs and copied here; `docs/validation validation --sweep` "
            "runs that script first.*\n")

