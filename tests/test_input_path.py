"""Every command reads a case file as ``spurdyn run`` does, and bounds its work (docs/cli.md,
"Limits"): the same reader and messages for ``info``, ``mesh`` and ``stiffness``; files read
with a size limit; the elastic tooth's bound on every torque (a torque history's samples,
the quasi-static commands' ``--torque``); the option the user wrote named in a refusal.

The refusals come before any solver runs (the FE solver is the synthetic one where a run
would start), so the file takes seconds.
"""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path

import pytest

from cli_helpers import EXAMPLES, fake, here, run  # noqa: F401  (fixtures)

PAIR = (EXAMPLES / "paper_pair.toml").read_text()
#: The commands that read a case file's pair, as typed after the file.
PAIR_COMMANDS = (["info"], ["stiffness"], ["mesh", "--png", "m.png"])


def refused(capsys, folder: Path, *argv: object) -> str:
    """The one line of a refusal (exit 2, nothing on stdout, nothing written)."""
    before = sorted(p.name for p in folder.iterdir())
    code, out, err = run(capsys, *argv)
    assert code == 2 and out == "" and err.count("\n") == 1, (argv, code, err)
    assert err.startswith("spurdyn: error: ") and "Traceback" not in err, err
    assert sorted(p.name for p in folder.iterdir()) == before, argv
    return err


BAD_FILES = [
    ("gear_a = [\n", "is not valid TOML"),
    ("run = 3\n" + PAIR[:PAIR.index("[run]")], "run: must be a table"),
    (PAIR.replace("[run]", "[run]\nspeed = 3"), "run.speed: unknown key"),
    ("model = 4\n" + PAIR[:PAIR.index("[model]")], "model: must be a table"),
    ("[extra]\n" + PAIR, "extra: unknown key"),
]


@pytest.mark.parametrize("text, message", BAD_FILES)
@pytest.mark.parametrize("command", PAIR_COMMANDS + (["run"],), ids=lambda c: c[0])
def test_every_command_reads_a_case_file_as_run_does(fake, here, capsys, command, text, message):
    (here / "case.toml").write_text(text)
    err = refused(capsys, here, command[0], "case.toml", *command[1:])
    assert message in err, err


@pytest.mark.parametrize("command", PAIR_COMMANDS + (["run"],), ids=lambda c: c[0])
def test_a_missing_case_file_is_no_such_file(here, capsys, command):
    err = refused(capsys, here, command[0], "nowhere.toml", *command[1:])
    assert err.startswith("spurdyn: error: nowhere.toml: no such file"), err


def test_an_endless_torque_history_is_refused_by_its_size(fake, here, capsys):
    text = (EXAMPLES / "idle_rattle.toml").read_text()
    (here / "case.toml").write_text(text.replace('"idle_rattle_torque.csv"', '"/dev/zero"'))
    err = refused(capsys, here, "run", "case.toml")
    assert err.startswith("spurdyn: error: run.torque_history: '/dev/zero' holds more than 128 MiB")


def test_a_case_file_beyond_the_limit_is_refused(here, capsys, monkeypatch):
    from spurdyn.case import files

    monkeypatch.setattr(files, "MAX_FILE_BYTES", 1000)
    (here / "case.toml").write_text(PAIR + "#" * 1000 + "\n")
    err = refused(capsys, here, "info", "case.toml")
    assert "case.toml: holds more than" in err


def _history_case(folder: Path, column: str, value: float) -> Path:
    text = (EXAMPLES / "idle_rattle.toml").read_text()
    csv = ("time_s, driver_Nm, load_Nm\n0, 1, 1\n0.001, 1, 1\n0.002, 1, 1\n0.003, 1, 1\n"
           .replace("0.002, 1, 1", "0.002, 1e9, 1" if column == "driver" else "0.002, 1, 1e9"))
    (folder / "h.csv").write_text(csv)
    path = folder / "case.toml"
    path.write_text(text.replace('"idle_rattle_torque.csv"', '"h.csv"'))
    return path


@pytest.mark.parametrize("column", ["driver", "load"])
def test_a_torque_history_is_bounded_as_the_torque_is(fake, here, capsys, column):
    err = refused(capsys, here, "run", _history_case(here, column, 1e9))
    assert err.startswith(f"spurdyn: error: run.torque_history: its {column} torque at 0.002 s, "
                          f"1e+09 N m strains the {'driver' if column == 'driver' else 'driven'}'s "
                          "tooth by about"), err


@pytest.mark.parametrize("argv", [["stiffness", "paper"], ["info", "paper", "--contact", "hertz"]],
                         ids=["stiffness", "info"])
def test_quasi_static_commands_bound_the_torque_as_run_does(here, capsys, argv):
    err = refused(capsys, here, *argv, "--torque", "1e30")
    assert err.startswith("spurdyn: error: --torque: 1e+30 N m strains the driver's tooth"), err
    run_err = refused(capsys, here, "run", "paper-fig8", "--torque", "1e30")
    assert err == run_err


@pytest.mark.parametrize("command", ["info", "stiffness"])
def test_a_case_files_torque_is_named_as_its_key(here, capsys, command):
    (here / "case.toml").write_text(PAIR.replace("[run]", "[run]\ntorque = 1e9"))
    err = refused(capsys, here, command, "case.toml")
    assert err.startswith("spurdyn: error: run.torque: 1e+09 N m strains"), err


@pytest.mark.parametrize("command", PAIR_COMMANDS, ids=lambda c: c[0])
def test_a_mesh_option_is_named_as_written(here, capsys, command):
    err = refused(capsys, here, command[0], "paper", *command[1:], "--mesh", "1000x1000")
    assert err.startswith("spurdyn: error: --mesh: nx must be"), err


@pytest.mark.parametrize("rpm", ["1000:1e308:1e-300", "0:1e308:1e302", "1000:1e6:1"])
def test_a_sweep_of_too_many_points_is_refused_by_its_count(here, capsys, rpm):
    from spurdyn.sweep.spec import MAX_POINTS

    err = refused(capsys, here, "sweep", "paper-fig8", "--rpm", rpm, "--model", "lumped",
                  "--out", here / "o")
    assert err.startswith("spurdyn: error: --rpm: ") and f"values; at most {MAX_POINTS:,}" in err, err


@pytest.mark.parametrize("ratio, hz, key", [
    (1e308, [5000, 50000], "run.rayleigh_ratio"),
    (0.05, [1e308, 1e308], "run.rayleigh_hz"),
    (0.05, [1e-300, 1e308], "run.rayleigh_hz"),
])
def test_rayleigh_damping_beyond_numbers_names_the_key_written(fake, here, capsys, ratio, hz, key):
    from test_properties import case_file

    path = case_file(here, {"rayleigh_ratio": ratio, "rayleigh_hz": hz, "integrator": "implicit"})
    err = refused(capsys, here, "run", path, "--out", here / "o")
    assert err.startswith(f"spurdyn: error: {key}: gives Rayleigh coefficients beyond"), err


@pytest.mark.parametrize("rack, key", [
    ("basic_rack = {addendum = 1.0, dedendum = 0.9}", "gear_a.basic_rack.dedendum"),
    ("dedendum = 0.003", "gear_a.dedendum"),
    ("addendum = 0.0045", "gear_a.addendum"),
])
@pytest.mark.parametrize("command", PAIR_COMMANDS + (["run"],), ids=lambda c: c[0])
def test_a_tip_on_the_mating_root_names_the_height_written(fake, here, capsys, rack, key, command):
    text = PAIR.replace("tip_radius = 0.047625", "").replace("root_radius = 0.04048", "")
    (here / "case.toml").write_text(text.replace("[gear_a.material]", f"{rack}\n[gear_a.material]"))
    err = refused(capsys, here, command[0], "case.toml", *command[1:])
    assert err.startswith(f"spurdyn: error: {key}: leaves no clearance"), err


def test_a_tip_on_the_root_at_a_given_centre_distance_names_it(here, capsys):
    (here / "case.toml").write_text(PAIR.replace("# centre_distance = 0.0889",
                                                 "centre_distance = 0.0885"))
    err = refused(capsys, here, "info", "case.toml")
    assert err.startswith("spurdyn: error: pair.centre_distance: "), err


@pytest.mark.parametrize("argv, key", [
    (["--model", "sector", "--speed-a", "1", "--cycles", "1"], "--speed-a"),
    (["--model", "sector", "--cycles", "10000", "--max-cycles", "10000", "--mesh", "2x8"],
     "--max-cycles"),
    (["--model", "sector", "--cycles", "3000"], "--cycles"),
    (["--model", "lumped", "--cycles", "1000", "--speed-a", "100"], "--cycles"),
    (["--model", "lumped", "--cycles", "5", "--speed-a", "10"], "--speed-a"),
])
def test_steady_states_are_bounded_by_their_own_steps(fake, here, capsys, argv, key):
    err = refused(capsys, here, "run", "paper-fig8", *argv)
    assert err.startswith(f"spurdyn: error: {key}: paper-fig8 would take "), err
    assert "give --allow-large" in err


@pytest.mark.parametrize("model", ["sector", "lumped"])
def test_a_steady_states_size_counts_its_cycles(model):
    from spurdyn.case.presets import resolve_cases
    from spurdyn.lumped.steady import samples_per_cycle
    from spurdyn.sector.rules import steps_per_cycle
    from spurdyn.simulators import MODELS
    from spurdyn.solvers.limits import MAX_STEPS

    entry = MODELS[model]
    (case,) = resolve_cases("paper-fig8", {"run.cycles": 7, "run.max_cycles": 9}, {})
    case = replace(case, run=entry.with_defaults(case.run))
    size = entry.size(case)
    period = 2 * math.pi / (case.pair.gear_a.teeth * case.run.speed_a)
    per_cycle = (steps_per_cycle(case.run.speed_a, case.pair.gear_a.teeth) if model == "sector"
                 else samples_per_cycle(period))
    assert size.steps == 9 * per_cycle < MAX_STEPS and size.steps_capped


def test_a_sweeps_slowest_speed_is_bounded(here, capsys):
    err = refused(capsys, here, "sweep", "paper-fig8", "--model", "sector", "--rpm", "1,2",
                  "--cycles", "1", "--out", here / "o")
    assert err.startswith("spurdyn: error: --rpm: paper-fig8@1rpm"), err


@pytest.mark.parametrize("argv, key", [
    (["--model", "lumped", "--cycles", "5", "--angle", "5"], "--angle: is one engagement's"),
    (["--model", "sector", "--angle", "5"], "--angle: the sector model does not read it"),
])
def test_an_angle_a_steady_state_would_not_read_is_refused(fake, here, capsys, argv, key):
    err = refused(capsys, here, "run", "paper-fig8", *argv, "--out", here / "o")
    assert err.startswith(f"spurdyn: error: {key}"), err


def test_a_case_files_angle_beside_cycles_is_refused_by_its_key(fake, here, capsys):
    # the designer's file (no key the lumped model does not read: those are refused first)
    example = Path(__file__).resolve().parents[1] / "examples" / "pinion_23_47.toml"
    path = here / "p.toml"
    path.write_text(example.read_text() + "angle_deg = 5.0\ncycles = 5\n")
    err = refused(capsys, here, "run", path, "--model", "lumped", "--out", here / "o")
    assert err.startswith("spurdyn: error: run.angle_deg: is one engagement's"), err


@pytest.mark.parametrize("torque, message", [
    ("0", "--torque: must be above zero for the sector model"),
    ("1e-9", "--torque: 1e-09 N m deflects the teeth by less than the rounding"),
])
def test_a_sector_run_without_a_load_is_refused(fake, here, capsys, torque, message):
    err = refused(capsys, here, "run", "paper-fig8", "--model", "sector", "--torque", torque)
    assert err.startswith(f"spurdyn: error: {message}"), err


def test_an_unloaded_steady_state_says_so_without_warnings(here, capsys):
    import json
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        code, _, err = run(capsys, "run", "paper-fig8", "--model", "lumped", "--torque", "0",
                           "--cycles", "2", "--out", here / "o", "--quiet")
    assert code == 0 and err == "", err
    summary = json.loads((here / "o" / "summary.json").read_text())
    assert summary["status"] == "complete" and summary["dynamic_factor"] is None
    assert summary["dynamic_factor_note"] == "none: no quasi-static force (zero torque)"


@pytest.mark.parametrize("inertia", ["1e300", "1e-12"])
@pytest.mark.parametrize("command", PAIR_COMMANDS + (["run"],), ids=lambda c: c[0])
def test_a_disk_inertia_beyond_any_gear_is_refused(fake, here, capsys, inertia, command):
    (here / "case.toml").write_text(PAIR.replace("disk_inertia = 2.965e-4",
                                                 f"disk_inertia = {inertia}"))
    err = refused(capsys, here, command[0], "case.toml", *command[1:])
    assert err.startswith(f"spurdyn: error: gear_a.disk_inertia: {float(inertia):g} kg m^2 is "), err


def test_the_inertia_bounds_are_the_solid_disks():
    from spurdyn.errors import InputError
    from spurdyn.geometry.blank import INERTIA_RATIOS
    from spurdyn.geometry.presets import paper_pair

    gear = paper_pair().gear_a
    solid = replace(gear, disk_inertia=None, blank=None).disk_inertia   # the default blank's
    low, high = INERTIA_RATIOS
    for j in (low * solid * 1.001, high * solid * 0.999):
        assert replace(gear, disk_inertia=j).disk_inertia == j
    for j in (low * solid * 0.999, high * solid * 1.001):
        with pytest.raises(InputError) as err:
            replace(gear, disk_inertia=j)
        assert err.value.field == "disk_inertia"


@pytest.mark.parametrize("model", ["sector", "lumped"])
def test_a_torque_historys_size_is_its_cycles(model):
    from spurdyn.case import load_case
    from spurdyn.simulators import MODELS

    case = load_case(EXAMPLES / "idle_rattle.toml")      # 9 cycles under a history
    size = MODELS[model].size(case)
    assert size.steps_capped and size.steps % case.run.cycles == 0
    assert size.steps == case.run.cycles * MODELS[model].size(
        replace(case, run=case.run.with_(cycles=1))).steps
