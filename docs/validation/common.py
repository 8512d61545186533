"""What the page generators share: where the pages live, how a page and its figures are
written, a run timed, the impacts of a contact force matched between two runs, and a
markdown table."""

from __future__ import annotations

import json
import time
from pathlib import Path
from typing import Any, Callable, Sequence, TypeVar

import numpy as np

#: ``docs/``: the pages, their figures and their stores live beside this package.
DOCS = Path(__file__).resolve().parent.parent
ROOT = DOCS.parent
FIGURES = DOCS / "figures"
#: The runner, ``python docs/validation PAGE`` (this package's ``__main__.py``).
RUNNER = DOCS / "validation"
#: Force (N) below which the teeth count as apart, for the impact times.
APART = 1e-9

T = TypeVar("T")


def timed(run: Callable[..., T], *args: Any, **kwargs: Any) -> tuple[T, float]:
    """``run(*args, **kwargs)`` and its wall time.

    Parameters
    ----------
    run : callable
        What to run (a simulation, a part of a page).
    *args, **kwargs
        Its arguments.

    Returns
    -------
    result, seconds : tuple
        What it returned, and the wall time it took (s).
    """
    t0 = time.perf_counter()
    out = run(*args, **kwargs)
    return out, time.perf_counter() - t0


def write_page(page: Path, text: str, echo: bool = True) -> None:
    """Write a page (UTF-8) and print it, or only its path.

    Parameters
    ----------
    page : Path
        The markdown page.
    text : str
        Its text.
    echo : bool
        Print the whole text (True) or ``wrote <page>``.
    """
    page.write_text(text, encoding="utf-8")
    print(text if echo else f"wrote {page}")


def load_figures(store: Path) -> dict[str, Any]:
    """The figures a page keeps in its JSON store (``{}`` before the first run).

    Parameters
    ----------
    store : Path
        The store, ``docs/<page>.json``.

    Returns
    -------
    dict
        Its figures, so that one part can be measured again and the others kept.
    """
    return json.loads(store.read_text()) if store.exists() else {}


def save_figures(store: Path, figures: dict[str, Any]) -> None:
    """Keep a page's figures in its JSON store (floats of NumPy as plain floats).

    Parameters
    ----------
    store : Path
        The store, ``docs/<page>.json``.
    figures : dict
        The figures.
    """
    store.write_text(json.dumps(figures, indent=1, default=float) + "\n")


def touches(t: np.ndarray, f: np.ndarray) -> list[tuple[float, float, float]]:
    """The contacts made after a separation.

    A contact starts where the force rises from zero (above :data:`APART`) and lasts until
    it is zero again. The start's touch is not one: the teeth start just touching, and a run
    whose force at ``t = 0`` is zero (to round-off) and positive after its first step has
    not struck.

    Parameters
    ----------
    t, f : ndarray
        The times (s) and the contact force (N).

    Returns
    -------
    list of tuple
        ``(time, duration, peak force)`` of each contact.
    """
    on = f > APART
    out = []
    for i in np.flatnonzero(on[1:] & ~on[:-1]) + 1:
        if i == 1:
            continue
        off = np.flatnonzero(~on[i:])
        j = i + off[0] if off.size else t.size
        out.append((float(t[i]), float(t[j - 1] - t[i]), float(f[i:j].max())))
    return out


def match_impacts(ref: list[tuple[float, float, float]], imp: list[tuple[float, float, float]]
                  ) -> tuple[list[float], list[tuple[float, float, float]]]:
    """RK4's impacts against the implicit run's touches (both from :func:`touches`).

    Each RK4 impact, in time order, takes the nearest implicit touch after those already
    taken; an extra touch between the two belongs to the contact it is nearer in time: to
    the end of the previous one taken (a bounce as the teeth part, listed only) or to this
    one (the teeth striking early, then bouncing off), in which case the shift is that of
    the early touch. Matching by index, as before, compared unrelated impacts as soon as
    one run bounced once more: Fig. 9's 3.99 us at the old default step was RK4's second
    impact against the implicit run's 13-N touch at 9.5 us, 1 us after it had parted in
    what RK4 keeps as one first contact.

    Parameters
    ----------
    ref, imp : list of tuple
        RK4's impacts and the implicit run's touches, ``(time, duration, peak force)``.

    Returns
    -------
    shifts : list of float
        Implicit minus RK4 for each RK4 impact (s; NaN where the implicit run has no
        touch left).
    extra : list of tuple
        The implicit touches no RK4 impact took (extra bounces).
    """
    shifts, taken, last, end = [], set(), -1, 0.0
    for ta, _, _ in ref:
        free = [(abs(tb - ta), k) for k, (tb, _, _) in enumerate(imp) if k > last]
        if not free:
            shifts.append(float("nan"))
            continue
        k = min(free)[1]
        early = [j for j in range(last + 1, k) if imp[j][0] - end > imp[k][0] - imp[j][0]]
        shifts.append(imp[early[0] if early else k][0] - ta)
        taken.add(k)
        last, end = k, imp[k][0] + imp[k][1]
    return shifts, [c for k, c in enumerate(imp) if k not in taken]


def table(header: Sequence[str], rows: Sequence[Sequence[Any]]) -> str:
    """A markdown table.

    Parameters
    ----------
    header : sequence of str
        The column titles.
    rows : sequence of sequences
        The cells, row by row (each turned into text by ``str``).

    Returns
    -------
    str
        The table's lines.
    """
    lines = ["| " + " | ".join(header) + " |", "| " + " | ".join("---" for _ in header) + " |"]
    lines += ["| " + " | ".join(str(c) for c in r) + " |" for r in rows]
    return "\n".join(lines)
