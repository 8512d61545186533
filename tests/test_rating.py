"""Issue 35 (3): ISO 6336-5 material classes, ISO's safety chain with K_alpha, the command's line.

Hand figures: ``docs/iso6336_hand/chain_ii.bc`` (``docs/iso6336.md``, sections 10 and 11).
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest

from cli_helpers import fake, here, run  # noqa: F401  (pytest fixtures)
from spurdyn.case import case_from_dict, case_to_dict, load_case
from spurdyn.cli.run import safety_phrase
from spurdyn.errors import InputError
from spurdyn.iso6336.__main__ import example_pair
from spurdyn.iso6336.chain import safety_chain
from spurdyn.iso6336.materials import GRADES, LINES, allowable_stresses
from spurdyn.iso6336.rating import rate
from spurdyn.iso6336.transverse import running_in_allowance, transverse_factors
from spurdyn.results.stress import safety_figures

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "pinion_23_47.toml"
MPA = 1e6


# -- ISO 6336-5 lines ------------------------------------------------------------------

@pytest.mark.parametrize("grade, hlim, flim", [("ML", 1300, 312), ("MQ", 1500, 425),
                                               ("ME", 1650, 525)])
def test_case_hardened_steel_has_the_published_numbers_over_its_range(grade, hlim, flim):
    low, high = LINES["Eh"].hardness_range(grade)
    for hv in (low, 700.0, high):
        assert allowable_stresses("Eh", grade, hv) == pytest.approx((hlim * MPA, flim * MPA))


@pytest.mark.parametrize("name, grade, hardness, hlim, flim", [
    ("V_alloy", "MQ", 360.0, 1.313 * 360 + 373, 0.425 * 360 + 187),   # top of the MQ line
    ("V_alloy", "ME", 390.0, 2.213 * 390 + 260, 0.358 * 390 + 231),
    ("St", "MQ", 110.0, 300.0, 119.05),                                # foot of St
    ("NT", "MQ", 650.0, 1250.0, 420.0), ("NV", "ME", 650.0, 1217.0, 432.0),
    ("IF", "MQ", 570.0, 0.541 * 570 + 882, 368.66),                   # where ISO's bending line turns flat (369)
    ("GG", "ML", 150.0, 286.95, 46.4),                                 # the weakest material of the table
])
def test_lines_at_their_ends(name, grade, hardness, hlim, flim):
    assert allowable_stresses(name, grade, hardness) == pytest.approx((hlim * MPA, flim * MPA))


@pytest.mark.parametrize("name", list(LINES))
def test_better_quality_never_lowers_a_number_and_harder_never_weakens(name):
    cls = LINES[name]
    low = max(cls.hardness_range(g)[0] for g in GRADES)
    high = min(cls.hardness_range(g)[1] for g in GRADES)
    for x in (low, 0.5 * (low + high), high):
        h = [cls.contact[g].at(x) for g in GRADES]
        f = [cls.bending[g].at(x) for g in GRADES]
        assert h == sorted(h) and f == sorted(f), (name, x)
    for g in GRADES:
        assert cls.contact[g].slope >= 0.0 and cls.bending[g].slope >= 0.0


def test_hardness_just_outside_the_range_is_refused_with_the_range():
    with pytest.raises(InputError, match=r"^hardness_hv: 659 HV is outside .* 660 to 800 HV"):
        allowable_stresses("Eh", "MQ", 659.0)
    with pytest.raises(InputError, match=r"^hardness_hbw: .*110 to 210 HBW"):
        allowable_stresses("St", "ME", 211.0)
    with pytest.raises(InputError, match=r"^material_class: unknown .*'Ehh'"):
        allowable_stresses("Ehh", "MQ", 700.0)
    with pytest.raises(InputError, match=r"^grade: must be one of ML, MQ, ME"):
        allowable_stresses("Eh", "mq", 700.0)


# -- K_alpha ---------------------------------------------------------------------------

def test_perfect_gears_have_unit_transverse_factors():
    for eps in (1.2, 1.6, 1.99, 2.3):
        z = math.sqrt((4.0 - eps) / 3.0)
        assert transverse_factors(2e10, 0.0, 0.0, 2e5, eps, z) == (1.0, 1.0)


def test_transverse_factors_are_held_between_one_and_their_limits():
    eps = 1.5
    z = math.sqrt((4.0 - eps) / 3.0)
    k_h, k_f = transverse_factors(2e10, 100e-6, 0.0, 1e5, eps, z)    # q = 20
    assert k_h == pytest.approx(1.0 / z**2) and k_f == pytest.approx(eps / (0.25 * eps + 0.75))
    assert k_h < k_f    # for spur gears 1/Z_eps^2 = 3/(4 - eps) lies below eps/(0.25 eps + 0.75)


def test_the_two_branches_meet_at_contact_ratio_two():
    for q_dev in (30e-6, 50e-6):      # q = 0.6 and 1: K = 1.14 and 1.3, inside the limits
        below = transverse_factors(2e10, q_dev, 0.0, 1e6, 2.0, 0.5)
        above = transverse_factors(2e10, q_dev, 0.0, 1e6, 2.0 + 1e-12, 0.5)
        assert below == pytest.approx(above, rel=1e-9) and below[1] > 1.0


def test_running_in_allowance_limits():
    assert running_in_allowance("surface_hardened", 20e-6, 1500e6, 3.0) == pytest.approx(1.5e-6)
    assert running_in_allowance("surface_hardened", 100e-6, 1500e6, 3.0) == pytest.approx(3e-6)
    # steel: 160/sigma_Hlim f_pb, capped at the value of f_pb = 40 um above 10 m/s
    assert running_in_allowance("steel", 20e-6, 800e6, 3.0) == pytest.approx(4e-6)
    assert running_in_allowance("steel", 60e-6, 800e6, 12.0) == pytest.approx(8e-6)
    assert running_in_allowance("cast_iron", 100e-6, 0.0, 7.0) == pytest.approx(22e-6)


# -- the chain, by hand (docs/iso6336_hand/chain_ii.bc) ----------------------------------

def _chain_ii(f_pb: float):
    rating = rate(example_pair(), 100.0)
    speed = 3000.0 * math.pi / 30.0
    return rating, safety_chain(rating, speed, (1500e6, 1500e6), (425e6, 425e6), pitch_speed=7.2,
                                groups=("surface_hardened",) * 2, pitch_deviation=f_pb)


def test_chain_matches_hand_for_perfect_gears():
    _, c = _chain_ii(0.0)
    assert (c.k_halpha, c.k_falpha, c.y_alpha) == (1.0, 1.0, 0.0)
    assert c.k_v == pytest.approx(1.029340, rel=1e-6)
    assert c.s_h == pytest.approx((1.318906, 1.388879), rel=1e-6)
    assert c.s_f == pytest.approx((2.851784, 2.973994), rel=1e-6)


def test_chain_matches_hand_with_a_base_pitch_deviation():
    _, c = _chain_ii(20e-6)
    assert c.y_alpha == pytest.approx(1.5e-6)
    assert c.k_v == pytest.approx(1.079452, rel=1e-6)
    assert (c.k_halpha, c.k_falpha) == pytest.approx((1.125410, 1.125410), rel=1e-6)
    assert c.s_h[0] == pytest.approx(1.214049, rel=1e-6)
    assert c.s_f[0] == pytest.approx(2.416359, rel=1e-6)
    _, c30 = _chain_ii(30e-6)   # raw K = 1.339: both limits hold
    assert (c30.k_halpha, c30.k_falpha) == pytest.approx((1.191225, 1.322375), rel=1e-6)


# -- the case file, summary.json and the command's line ---------------------------------

def test_a_material_class_is_read_kept_and_rated_both_ways():
    case = load_case(EXAMPLE)
    mat = case.pair.gear_a.material
    assert (mat.sigma_hlim, mat.sigma_flim, mat.iso_class) == (1500e6, 425e6, ("Eh", "MQ", 700.0))
    again = case_from_dict(case_to_dict(case), check_step=False)
    assert again.pair.gear_b.material == case.pair.gear_b.material
    assert case_to_dict(case)["gear_a"]["material"]["material_class"] == "Eh"
    s = safety_figures(case, [300e6, 200e6], 1.2e9)
    r = s["rating_iso"]
    assert s["safety_root_iso"] == r["S_F"] and s["safety_contact_iso"] == r["S_H"]
    assert r["S_F"][1] == pytest.approx(r["sigma_FG_Pa"][1] / r["sigma_F_Pa"][1])
    assert r["sigma_F_Pa"][0] == pytest.approx(r["sigma_F0_Pa"][0] * r["K_v"] * r["K_Falpha"])
    assert r["allowables"] == ["ISO 6336-5 Eh MQ 700 HV"] * 2
    assert s["safety_root_model"] == pytest.approx([850e6 / 300e6, 850e6 / 200e6])
    assert json.loads(json.dumps(s)) == s


def test_safety_phrase_names_each_gear_below_one_and_nothing_else():
    summary = {"safety_root_iso": [1.2, 0.834], "safety_root_model": [0.95, None],
               "safety_contact_iso": [1.0, 1.3], "safety_contact_model": [None, None]}
    assert safety_phrase(summary) == ", S_F below 1: gear B 0.834 (ISO), gear A 0.95 (model)"
    assert safety_phrase({}) == "" and safety_phrase({"safety_root_iso": [2.0, 3.0]}) == ""


def test_run_line_names_a_gear_below_one(fake, here, capsys):  # noqa: F811
    case = here / "hot.toml"
    case.write_text(EXAMPLE.read_text().replace("torque = 50.0", "torque = 400.0"))
    code, out, err = run(capsys, "run", case, "--model", "fe", "--angle", "0.3")
    assert code == 0, err
    assert "S_F below 1: gear A 0." in out and "(ISO)" in out and "S_H below 1: gear A" in out
    summary = json.loads((here / "out" / "hot" / "summary.json").read_text())
    assert summary["rating_iso"]["S_F"][0] < 1.0


BAD = [
    ("hardness_hv = 700", "hardness_hv = 500", "gear_a.material.hardness_hv: 500 HV is outside"),
    ("hardness_hv = 700", "hardness_hbw = 700", "gear_a.material.hardness_hbw: class Eh"),
    ('material_class = "Eh"', 'material_class = "Eh2"', "gear_a.material.material_class: unknown"),
    ('grade = "MQ"', 'grade = "MX"', "gear_a.material.grade: must be one of"),
    ("hardness_hv = 700", "hardness_hv = 700\nsigma_hlim = 1500e6",
     "gear_a.material.sigma_hlim: give either"),
    ('material_class = "Eh"         # ISO 6336-5: sigma_Hlim 1500 MPa, sigma_Flim 425 MPa\n'
     'grade = "MQ"\nhardness_hv = 700', "sigma_hlim = 1500.0",
     "gear_a.material.sigma_hlim: 1500 Pa is outside"),
]


@pytest.mark.parametrize("old, new, message", BAD)
def test_bad_strength_refused_in_one_line_nothing_written(fake, here, capsys, old, new,  # noqa: F811
                                                          message):
    text = EXAMPLE.read_text()
    assert old in text
    bad = here / "bad.toml"
    bad.write_text(text.replace(old, new, 1))
    code, out, err = run(capsys, "run", bad)
    assert code == 2 and out == ""
    assert err.startswith("spurdyn: error: ") and err.count("\n") == 1
    assert message in err, err
    assert [p.name for p in here.iterdir()] == ["bad.toml"]
