"""Ready-made runs (presets) and how a CASE argument turns into cases to run.

The presets are the paper's four examples (Lee & Jang, section 4, Fig. 8-11): the paper's
pair (:func:`spurdyn.geometry.presets.paper_pair`, gear A driving), the torque
``tau_0 = 22.25 N m``, the step ``dt = 3e-8 s`` and the whole angle of action
``theta_s``. In the rattling cases (Fig. 10-11) gear B, the driven gear, starts 1 % faster
than the speed that meshes with A: the paper says only that B starts faster, and the
presets keep the paper's driver (A), so the driven gear runs ahead of the mesh and the
teeth separate first. At 20,000 rpm B then escapes for the whole engagement (no contact
at all; the lumped model agrees). The ``-bdrive`` presets take the other reading: B, the
faster gear, drives and strikes first. ``paper-all`` is the group of the four.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any, Mapping

from spurdyn.case.file import Case, case_from_pair, load_case
from spurdyn.case.pair_tables import MeshedPair
from spurdyn.errors import InputError
from spurdyn.geometry.pair import GearPair
from spurdyn.geometry.presets import PAPER_TORQUE, paper_pair
from spurdyn.settings import PAPER_DT, PAPER_MODEL


@dataclass(frozen=True)
class Preset:
    """A ready-made run: speeds (rpm) of the paper's pair and what it shows."""

    name: str
    speed_a_rpm: float
    speed_b_rpm: float
    description: str
    torque: float = PAPER_TORQUE
    dt: float = PAPER_DT
    driver: str = "a"

    def run_table(self) -> dict[str, Any]:
        """The preset's ``[run]`` table (TOML units)."""
        return {"speed_a_rpm": self.speed_a_rpm, "speed_b_rpm": self.speed_b_rpm,
                "torque": self.torque, "dt": self.dt, "contact": "point"}

    def line(self) -> str:
        """One line for ``spurdyn cases``."""
        return (f"{self.name:<18} {self.speed_a_rpm:>6,.0f}/{self.speed_b_rpm:,.0f} rpm, "
                f"{self.torque:g} N m, dt {self.dt:g} s, whole theta_s: {self.description}")


PRESETS: dict[str, Preset] = {p.name: p for p in (
    Preset("paper-fig8", 4000.0, 4000.0,
           "contact force at 4,000 rpm (the paper compares it with NASA TM-105326)"),
    Preset("paper-fig9", 20000.0, 20000.0, "contact force at 20,000 rpm"),
    Preset("paper-fig10", 4000.0, 4040.0,
           "B (driven) starts 1 % fast at 4,000 rpm: separation, then repeated impacts (rattling)"),
    Preset("paper-fig11", 20000.0, 20200.0,
           "B (driven) starts 1 % fast at 20,000 rpm: B runs away, no contact within theta_s"),
    Preset("paper-fig10-bdrive", 4000.0, 4040.0,
           "as paper-fig10 with B driving: the faster driver strikes first, repeated impacts",
           driver="b"),
    Preset("paper-fig11-bdrive", 20000.0, 20200.0,
           "as paper-fig11 with B driving: one long impact with chatter", driver="b"),
)}

#: Names that stand for several presets.
GROUPS: dict[str, tuple[str, ...]] = {
    "paper-all": ("paper-fig8", "paper-fig9", "paper-fig10", "paper-fig11")}


def preset_lines() -> list[str]:
    """What ``spurdyn cases`` prints: one line per preset and group."""
    lines = [p.line() for p in PRESETS.values()]
    lines += [f"{name:<18} the {len(members)} paper cases, one after the other "
              f"(--jobs N: side by side)" for name, members in GROUPS.items()]
    return lines


def is_preset(name: str) -> bool:
    """Whether ``name`` is a preset or a group of presets."""
    return name in PRESETS or name in GROUPS


def preset_case(name: str, overrides: Mapping[str, Any] | None = None,
                labels: Mapping[str, str] | None = None, check_step: bool = True) -> Case:
    """The :class:`Case` of one preset, with command-line ``overrides`` applied."""
    if name not in PRESETS:
        raise InputError("CASE", f"unknown preset {name!r}; see 'spurdyn cases'")
    preset = PRESETS[name]
    pair = paper_pair()
    if preset.driver != "a":
        pair = GearPair(gear_a=pair.gear_a, gear_b=pair.gear_b, driver=preset.driver)
    table = preset.run_table()
    if (overrides or {}).get("run.integrator") == "implicit" and "run.dt" not in (overrides or {}):
        del table["dt"]      # the paper's step is RK4's; the implicit one takes its own default
    case = case_from_pair(MeshedPair(pair=pair, name=name), table, name,
                          overrides, labels, description=preset.description,
                          check_step=check_step)
    # the paper's cases run the paper's model; their table is the preset's, not the user's
    return replace(case, model=PAPER_MODEL, written=frozenset())


def resolve_cases(spec: str, overrides: Mapping[str, Any] | None = None,
                  labels: Mapping[str, str] | None = None,
                  check_step: bool = True) -> list[Case]:
    """Turn a CASE argument (preset, group or TOML file) into the cases to run.

    Raises
    ------
    InputError
        For an unknown name or any bad value (see :func:`spurdyn.case.file.case_from_pair`).
    """
    if spec in GROUPS:
        return [preset_case(n, overrides, labels, check_step) for n in GROUPS[spec]]
    if spec in PRESETS:
        return [preset_case(spec, overrides, labels, check_step)]
    if not spec.endswith(".toml") and not Path(spec).exists():
        names = ", ".join([*PRESETS, *GROUPS])
        raise InputError("CASE", f"unknown case {spec!r}; use a preset ({names}) or a .toml file")
    return [load_case(spec, overrides, labels, check_step)]
