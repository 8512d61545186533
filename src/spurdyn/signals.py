"""Stop signals for the whole command: Ctrl-C (SIGINT) and SIGTERM handled alike.

SIGTERM is what ``timeout``, batch schedulers and ``docker stop`` send; it is treated as
Ctrl-C so that a stopped run keeps what it has computed. One process-wide
:class:`Interrupts` record counts the stop signals; how a signal acts depends on where
the command is:

- *at work* (:meth:`Interrupts.installed`, the default): the signal raises
  ``KeyboardInterrupt`` where the program is;
- *in a solver* (:meth:`Interrupts.checkpoints`): until the solver's first progress
  report the signal raises at once (it may be compiling for a minute); from then on it
  is only counted, and :meth:`Interrupts.checkpoint` (called by the progress callback,
  inside the solver's loop) raises it. The solver catches it there and returns the run
  so far, so a signal that lands after the loop has ended can no longer discard a
  finished result;
- *writing* (:meth:`Interrupts.held`): the signal is only counted; whoever held it looks
  at :attr:`Interrupts.count` afterwards.

Nothing here imports the rest of spurdyn.
"""

from __future__ import annotations

import signal
from contextlib import contextmanager
from typing import Any, Iterator

#: The stop signals and their names.
STOP_SIGNALS = {signal.SIGINT: "Ctrl-C", signal.SIGTERM: "SIGTERM"}

#: Exit status of a command stopped by a signal before it kept any result: 128 + signal.
EXIT_SIGINT, EXIT_SIGTERM = 128 + signal.SIGINT, 128 + signal.SIGTERM

_WORK, _START, _LOOP, _HELD = "work", "start", "loop", "held"


class Interrupts:
    """Process-wide count of stop signals and the rule for acting on them."""

    count = 0
    last: int | None = None
    mode = _WORK

    @classmethod
    def reset(cls) -> None:
        cls.count, cls.last, cls.mode = 0, None, _WORK

    @classmethod
    def handler(cls, signum: int, frame: Any) -> None:
        cls.count += 1
        cls.last = signum
        if cls.mode in (_WORK, _START):
            raise KeyboardInterrupt

    @classmethod
    def name(cls) -> str:
        """``"Ctrl-C"`` or ``"SIGTERM"``: the last stop signal (``"Ctrl-C"`` if none)."""
        return STOP_SIGNALS.get(cls.last, "Ctrl-C")  # type: ignore[arg-type]

    @classmethod
    def stopped(cls) -> str:
        """``"interrupted"`` (Ctrl-C) or ``"interrupted by SIGTERM"``."""
        return "interrupted by SIGTERM" if cls.last == signal.SIGTERM else "interrupted"

    @classmethod
    def exit_status(cls) -> int:
        """128 + the last stop signal (130 for Ctrl-C, 143 for SIGTERM)."""
        return EXIT_SIGTERM if cls.last == signal.SIGTERM else EXIT_SIGINT

    @classmethod
    @contextmanager
    def installed(cls) -> Iterator[None]:
        """Handle SIGINT and SIGTERM in this block (outside the main thread: no change)."""
        with _handled(STOP_SIGNALS, cls.handler):
            yield

    @classmethod
    @contextmanager
    def _mode(cls, mode: str) -> Iterator[None]:
        before = cls.mode
        cls.mode = mode
        try:
            yield
        finally:
            cls.mode = before

    @classmethod
    def checkpoints(cls) -> Any:
        """After the first :meth:`checkpoint` in this block, signals are counted and
        raised only at checkpoints."""
        return cls._mode(_START)

    @classmethod
    def held(cls) -> Any:
        """Signals are counted, never raised, in this block (files being written)."""
        return cls._mode(_HELD)

    @classmethod
    def checkpoint(cls) -> None:
        """Raise ``KeyboardInterrupt`` if a stop signal came (in a solver loop)."""
        if cls.mode == _START:
            cls.mode = _LOOP
        if cls.count and cls.mode == _LOOP:
            raise KeyboardInterrupt


def install_in_worker() -> None:
    """For a worker process: handle both stop signals, starting afresh."""
    Interrupts.reset()
    for s in STOP_SIGNALS:
        signal.signal(s, Interrupts.handler)


def ignore_interrupts() -> None:
    """Ignore Ctrl-C for good in this process (outside the main thread: no change).

    For worker processes whose client stops the work and closes them.
    """
    try:
        signal.signal(signal.SIGINT, signal.SIG_IGN)
    except ValueError:
        pass


@contextmanager
def ignored(signums: tuple[int, ...] = (signal.SIGINT,)) -> Iterator[None]:
    """Ignore ``signums`` in this block (processes spawned in it inherit that).

    SIGINT only by default: the pool that spawns workers ends them with SIGTERM.
    """
    with _handled(signums, signal.SIG_IGN):
        yield


@contextmanager
def _handled(signums: tuple[int, ...], handler: Any) -> Iterator[None]:
    """``handler`` for ``signums`` in this block, the old handlers restored after it
    (outside the main thread, where signals cannot be set: no change)."""
    try:
        old = {s: signal.signal(s, handler) for s in signums}
    except ValueError:
        yield
        return
    try:
        yield
    finally:
        for s, h in old.items():
            signal.signal(s, h)


__all__ = ["EXIT_SIGINT", "EXIT_SIGTERM", "Interrupts", "STOP_SIGNALS", "ignore_interrupts",
           "ignored", "install_in_worker"]
