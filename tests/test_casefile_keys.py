"""The case file's keys: the reference page, defaults that run, refusals that name the key."""

from __future__ import annotations

import copy
import json
import math
import re
from pathlib import Path

import pytest

from spurdyn.case.bearing_table import BEARING_TABLE_KEYS
from spurdyn.case.crack_table import CRACK_KEYS
from spurdyn.case.fault_tables import FAULT_KEYS
from spurdyn.cli.main import main
from spurdyn.cli.report import pair_info
from spurdyn.errors import InputError
from spurdyn.case import (BLANK_KEYS, GEAR_KEYS, MATERIAL_KEYS, MESH_KEYS, PAIR_KEYS,
                          RACK_KEYS, RUN_KEYS, TOP_KEYS, case_from_dict, load_case,
                          pair_from_dict)
from spurdyn.sector.rules import MESH_DAMPING_RATIO
from spurdyn.solvers.check import DT_FRACTION, run_settings

ROOT = Path(__file__).resolve().parents[1]
EXAMPLE = ROOT / "examples" / "pinion_23_47.toml"
SECTIONS = {"top": TOP_KEYS, "gear": GEAR_KEYS, "basic_rack": RACK_KEYS, "blank": BLANK_KEYS,
            "material": MATERIAL_KEYS, "pair": PAIR_KEYS, "mesh": MESH_KEYS, "run": RUN_KEYS,
            "fault": FAULT_KEYS, "crack": CRACK_KEYS, "bearing": set(BEARING_TABLE_KEYS)}


def _documented() -> dict[str, set[str]]:
    """Keys of each table of docs/casefile.md: first-column `key` cells after a marker."""
    found: dict[str, set[str]] = {}
    section = None
    for line in (ROOT / "docs" / "casefile.md").read_text().splitlines():
        marker = re.match(r"<!-- keys: (\w+) -->", line)
        if marker:
            section = marker.group(1)
            found[section] = set()
        elif line.startswith("#"):
            section = None
        elif section and (cell := re.match(r"\| `(\w+)` \|", line)):
            found[section].add(cell.group(1))
    return found


def test_the_reference_page_lists_every_key_of_the_parser():
    assert _documented() == SECTIONS


def test_the_readme_links_the_reference_page():
    assert "docs/casefile.md" in (ROOT / "README.md").read_text()


def _designer_pair() -> dict:
    gear = {"teeth": 23, "module": 0.002, "pressure_angle_deg": 25.0, "face_width": 0.02}
    return {"gear_a": dict(gear), "gear_b": {**gear, "teeth": 47},
            "run": {"speed_a_rpm": 3000.0, "torque": 50.0}}


def test_the_designer_pair_needs_nothing_else():
    case = case_from_dict(_designer_pair(), name="p")
    pair = case.pair
    assert pair.centre_distance == pytest.approx(0.070, rel=1e-15)
    assert case.run.speed_b == pytest.approx(case.run.speed_a * 23 / 47, rel=1e-15)
    info = pair_info(case.meshed_pair)
    stable = info["stable_dt_s"]
    assert case.run.dt == info["default_dt_s"]
    assert 0.7 * stable < case.run.dt <= DT_FRACTION * stable
    assert "solid disk" in info["disk_inertia_source"]["a"]
    # The API's defaults are the command line's (the step: the FE model's, which reads one).
    api = run_settings(pair, case.run.speed_a, 50.0, model="fe")
    assert api.speed_b == pytest.approx(case.run.speed_b, rel=1e-15)
    assert api.dt == case.run.dt


def test_an_explicit_dt_above_the_stable_step_is_still_refused():
    data = _designer_pair()
    data["run"]["dt"] = 3e-8
    with pytest.raises(InputError, match="above the stable RK4 step") as err:
        case_from_dict(data)
    assert err.value.field == "run.dt"


def test_shift_allowance_rack_and_blank_keys_are_read_and_reported():
    data = _designer_pair()
    data["gear_a"].update(profile_shift=0.3, thickness_allowance=40e-6, basic_rack="B",
                          blank={"bore_radius": 0.008})
    data["gear_b"].update(profile_shift=-0.1, basic_rack={"fillet_radius": 0.25})
    data["pair"] = {"centre_distance": 0.0705}
    info = pair_info(pair_from_dict(data))
    assert info["profile_shift"] == {"a": 0.3, "b": -0.1}
    assert info["basic_rack"] == {"a": "B", "b": "custom"}
    assert info["cutter_tip_radius_m"]["b"] == pytest.approx(0.25 * 0.002, rel=1e-15)
    assert info["backlash_normal_m"] > 0.0
    assert info["backlash_circumferential_m"] == pytest.approx(
        info["backlash_normal_m"] / math.cos(math.radians(info["working_pressure_angle_deg"])))
    assert "bore radius 8 mm" in info["disk_inertia_source"]["a"]


@pytest.mark.parametrize("where, key, value, field, words", [
    ("gear_a", "teeth", 100000, "gear_a.teeth", "at most 1000"),
    ("gear_b", "pressure_angle_deg", 20.0, "gear_b.pressure_angle_deg", "differs"),
    ("gear_a", "profile_shift", 3.0, "gear_a.profile_shift", "-2 to 2"),
    ("gear_a", "profile_shift", 1.0, "gear_a.profile_shift", "at most 0.939"),
    ("gear_a", "profile_shift", 1.5, "gear_a.profile_shift", "root circle"),
    ("gear_a", "basic_rack", "E", "gear_a.basic_rack", "ISO 53"),
    ("gear_a", "basic_rack", "A", "gear_a.basic_rack", "too large for the cutter tooth"),
    ("gear_a", "blank", {"bore_radius": 0.05}, "gear_a.blank.bore_radius", "root radius"),
    ("gear_a", "material", {"young": 210000.0, "poisson": 0.3, "density": 7800.0},
     "gear_a.material.young", "not MPa"),
    ("gear_a", "material", {"young": 210e15, "poisson": 0.3, "density": 7800.0},
     "gear_a.material.young", "outside any gear material"),
    ("gear_a", "material", {"young": 210e9, "poisson": 0.3, "density": 7.8},
     "gear_a.material.density", "g/cm^3"),
    ("pair", "centre_distance", 0.0699, "pair.centre_distance", "overlap"),
    ("run", "speed_a_rpm", 5e6, "run.speed_a_rpm", "bursting"),
])
def test_refusals_name_the_key_written(where, key, value, field, words):
    data = _designer_pair()
    data.setdefault(where, {})[key] = value
    if key == "tip_radius":
        data[where].pop("addendum", None)
    with pytest.raises(InputError) as err:
        case_from_dict(copy.deepcopy(data), check_step=False)
    assert err.value.field == field
    assert words in err.value.reason


@pytest.mark.slow
def test_the_23_47_example_runs_at_first_try(tmp_path, capsys):
    text = EXAMPLE.read_text()
    # Only teeth, module, pressure angle, face width, material (its ISO 6336-5 class too),
    # speed and torque.
    keys = set(re.findall(r"^(\w+)\s*=", text, flags=re.M))
    assert keys == {"teeth", "module", "pressure_angle_deg", "face_width", "young", "poisson",
                    "density", "material_class", "grade", "hardness_hv", "speed_a_rpm", "torque"}
    assert load_case(EXAMPLE).run.dt > 0.0
    code = main(["run", str(EXAMPLE), "--out", str(tmp_path / "out"), "--quiet"])
    assert code == 0
    assert (tmp_path / "out" / "result.nc").exists()
    # by default the sector model, damped so that it settles, and saying whose damping it was
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert summary["model"] == "sector" and summary["settled"]
    assert summary["mesh_damping"] == {"ratio": MESH_DAMPING_RATIO, "source": "model default"}
    assert all(s > 1.0 for s in summary["safety_root_iso"] + summary["safety_contact_iso"])


def test_a_shifted_backlashed_pair_runs(tmp_path):
    data = (EXAMPLE.read_text()
            .replace("face_width = 0.020            # m",
                     "face_width = 0.020            # m\nprofile_shift = 0.35\n"
                     "thickness_allowance = 40e-6\nbasic_rack = \"B\"")
            .replace("[run]", "[pair]\ncentre_distance = 0.0708\n\n[run]"))
    path = tmp_path / "shifted.toml"
    path.write_text(data)
    case = load_case(path)
    assert case.pair.gear_a.profile_shift == 0.35 and case.pair.backlash_normal > 40e-6
    assert main(["run", str(path), "--model", "fe", "--angle", "0.3", "--out", str(tmp_path / "out"),
                 "--quiet"]) == 0


def test_a_stored_case_rebuilds_the_same_shifted_pair():
    from spurdyn.case import case_to_dict

    data = _designer_pair()
    data["gear_b"]["basic_rack"] = {"dedendum": 1.3, "fillet_radius": 0.2}
    data["gear_a"].update(profile_shift=0.25, thickness_allowance=20e-6, basic_rack="C",
                          blank={"bore_radius": 0.006, "hub_radius": 0.01, "rim_radius": 0.018,
                                 "web_width": 0.008})
    case = case_from_dict(data, name="p")
    again = case_from_dict(case_to_dict(case), name="p")
    assert again.pair == case.pair and again.run == case.run
