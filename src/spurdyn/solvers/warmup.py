"""Whether the compiled solver still has to be compiled (a first run, an empty cache), and
for about how long.

The command says so before it starts a run, with nothing else to show while Numba
compiles. It looks at Numba's on-disk cache index of the kernel the run calls (the paper's
RK4 loop for the point or the distributed contact, or the implicit step); when that cannot
be read it says nothing rather than something untrue.
"""

from __future__ import annotations

from typing import Any

from spurdyn.settings import RunSettings

#: Seconds a first run spends compiling on this project's 2-core machine (load average
#: 1-4, where the same compile varies by a quarter; docs/performance.md, "The first
#: run's compile"), by integrator and contact, measured with
#: benchmarks/bench_fig8_compile.py; the implicit step with the strip not measured,
#: :data:`UNMEASURED`.
COMPILE_SECONDS: dict[tuple[str, str], float] = {
    ("rk4", "point"): 30.0,
    ("rk4", "hertz"): 35.0,
    ("implicit", "point"): 40.0,
}
UNMEASURED = 60.0


def _kernel(integrator: str) -> Any:
    """The compiled function a run of ``integrator`` calls first (its dispatcher)."""
    if integrator == "implicit":
        from spurdyn.solvers.implicit import step_compiled as implicit

        return implicit.step
    from spurdyn.solvers.paper import step_compiled

    return step_compiled.advance


def _ours(signature: tuple[Any, ...], integrator: str, contact: str) -> bool:
    """Whether a compiled signature is the one a run calls: the paper's loop and the
    implicit step have one for the point contact (their ``strip`` argument None) and one for
    the strip."""
    strip = signature[2] if integrator == "implicit" else signature[3]
    return (str(strip) == "none") == (contact != "hertz")


def needs_compiling(settings: RunSettings | None = None) -> bool:
    """True when neither this process nor the on-disk cache holds the compiled kernel of
    a run of ``settings`` (the paper's RK4 with the point contact when None)."""
    integrator, contact = ("rk4", "point") if settings is None else (settings.integrator,
                                                                      settings.contact)
    kernel = _kernel(integrator)
    if any(_ours(sig, integrator, contact) for sig in kernel.overloads):  # in this process
        return False
    try:
        index = kernel._cache._cache_file._load_index()  # Numba's cache index (private)
        keys = [key[0] for key in index]
    except Exception:  # noqa: BLE001 - another Numba version: say nothing
        return False
    return not any(_ours(sig, integrator, contact) for sig in keys)


def compile_seconds(settings: RunSettings) -> float:
    """About how long a first run of ``settings`` compiles (seconds, this machine)."""
    return COMPILE_SECONDS.get((settings.integrator, settings.contact), UNMEASURED)


__all__ = ["COMPILE_SECONDS", "UNMEASURED", "compile_seconds", "needs_compiling"]
