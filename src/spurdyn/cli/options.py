"""Option parsing shared by the subcommands (below :mod:`spurdyn.cli.main` and
:mod:`spurdyn.cli.sweep`, which both import it); what each model refuses of them is its
registry entry's (:meth:`spurdyn.simulators.ModelEntry.refuse`)."""

from __future__ import annotations

import argparse

from spurdyn.errors import InputError
from spurdyn.settings import BODIES, INTEGRATORS, STARTS, STIFFNESSES

#: Options of the time integrator and damping that ``run`` and ``sweep`` share:
#: (dest, dotted case key, label).
DYNAMICS_OVERRIDES = (
    ("damping", "run.damping_ratio", "--damping"),
    ("integrator", "run.integrator", "--integrator"),
    ("rho_inf", "run.rho_inf", "--rho-inf"),
    ("rayleigh_ratio", "run.rayleigh_ratio", "--rayleigh-ratio"),
    ("rayleigh_hz", "run.rayleigh_hz", "--rayleigh-hz"),
    ("cycles", "run.cycles", "--cycles"),
    ("max_cycles", "run.max_cycles", "--max-cycles"),
    ("stiffness", "run.stiffness", "--stiffness"),
    ("bodies", "run.bodies", "--bodies"),
    ("back_flanks", "run.back_flanks", "--back-flanks"),
    ("teeth", "run.teeth", "--teeth"),
    ("start", "run.start", "--start"),
    ("ramp_cycles", "run.ramp_cycles", "--ramp-cycles"),
    ("torque_history", "run.torque_history", "--torque-history"),
    ("torque_history_periodic", "run.torque_history_periodic", "--torque-history-periodic"),
)


def _frequencies(text: str) -> list[float]:
    try:
        values = [float(v) for v in text.split(",")]
    except ValueError:
        values = []
    if len(values) != 2:
        raise argparse.ArgumentTypeError(f"must be two frequencies in Hz, F1,F2 (got {text!r})")
    return values


def _on_off(text: str) -> bool:
    if text not in ("on", "off"):
        raise argparse.ArgumentTypeError(f"must be on or off (got {text!r})")
    return text == "on"


def add_dynamics_options(p: argparse.ArgumentParser) -> None:
    """``--damping``, ``--integrator``, ``--rho-inf``, ``--rayleigh-ratio``, ``--rayleigh-hz``."""
    p.add_argument("--damping", type=float, metavar="Z",
                   help="damping ratio of the pair's torsional mode: a mesh damper acting in "
                        "contact (lumped model; FE with --integrator implicit; default 0)")
    p.add_argument("--integrator", metavar="|".join(INTEGRATORS),
                   help="time integrator of the FE model: rk4 (the paper's, its presets') or "
                        "implicit (generalized-alpha, a step of accuracy, damping; docs/implicit.md)")
    p.add_argument("--rho-inf", type=float, metavar="R",
                   help="implicit integrator's high-frequency spectral radius (0-1, default 0.8)")
    p.add_argument("--rayleigh-ratio", type=float, metavar="Z",
                   help="Rayleigh damping ratio of the teeth at the two --rayleigh-hz frequencies "
                        "(implicit integrator)")
    p.add_argument("--rayleigh-hz", type=_frequencies, metavar="F1,F2",
                   help="the two frequencies (Hz) at which the teeth have --rayleigh-ratio")
    p.add_argument("--cycles", type=int, metavar="N",
                   help="steady state: N mesh cycles under constant torques, settled figures "
                        "in the summary (lumped and sector models; docs/lumped.md, docs/sector.md)")
    p.add_argument("--max-cycles", type=int, metavar="M",
                   help="steady state: a run not settled after --cycles goes on, a cycle at a "
                        "time, until it settles or has run M (default 4 x --cycles; give "
                        "--max-cycles N to run exactly N)")
    p.add_argument("--bodies", metavar="|".join(BODIES),
                   help="the sector model's bodies: modal (their modes and the flanks' residual "
                        "flexibility, the default) or full (the whole FE bodies, the reference)")
    p.add_argument("--back-flanks", type=_on_off, metavar="on|off",
                   help="the sector model's back flanks as contacts too (backlash, rattle; "
                        "default: on where the pair has backlash; docs/sector.md)")
    p.add_argument("--teeth", type=int, metavar="K",
                   help="the sector model's teeth per gear (default: those the run meets and a "
                        "neighbour on each side; the gear's number of teeth: the whole gear)")
    p.add_argument("--start", metavar="|".join(STARTS),
                   help="how a run of mesh cycles starts: static (the loaded pair's static "
                        "equilibrium, the default) or rest (undeformed, the torques ramped up)")
    p.add_argument("--ramp-cycles", type=float, metavar="N",
                   help="mesh cycles of the torques' ramp of a run from rest (default 1)")
    p.add_argument("--torque-history", metavar="FILE",
                   help="the torques against time from a CSV file (columns time_s, driver_Nm "
                        "and optionally load_Nm; docs/casefile.md)")
    p.add_argument("--torque-history-periodic", type=_on_off, metavar="on|off",
                   help="repeat the torque history past its end (default off: a run longer "
                        "than the history is refused)")
    p.add_argument("--stiffness", metavar="|".join(STIFFNESSES),
                   help="the lumped model's mesh stiffness: tooth (the paper model's root-clamped "
                        "tooth pair, the default) or sector (the sector model's mesh cycle: teeth "
                        "on their rims; with --cycles; docs/sector.md)")


def parse_mesh(text: str | None) -> tuple[int, int] | None:
    """``"4x14"`` -> ``(4, 14)``; ``None`` stays ``None``.

    Raises
    ------
    InputError
        Naming ``--mesh`` when the text is not ``NXxNY``.
    """
    if text is None:
        return None
    try:
        nx, ny = (int(v) for v in text.lower().split("x"))
    except ValueError:
        raise InputError("--mesh", f"must look like NXxNY, e.g. 4x14 (got {text!r})") from None
    return nx, ny


__all__ = ["DYNAMICS_OVERRIDES", "add_dynamics_options", "parse_mesh"]
