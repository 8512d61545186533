"""Rows graded along the tooth (``mesh.row_grading``, :func:`spurdyn.mesh.tooth.row_radii`; issue 14)."""

import numpy as np
import pytest

from spurdyn.errors import InputError
from spurdyn.fem.assembly import jacobian_determinants
from spurdyn.geometry.presets import paper_pair
from spurdyn.mesh.tooth import row_radii, tooth_mesh
from spurdyn.model.system import system_for


def test_row_grading_one_is_the_even_mesh():
    gear = paper_pair().gear_a
    r, n_f = row_radii(0.041, 0.042, 0.047, 14)
    assert n_f == 0 and np.array_equal(r, 0.041 + np.linspace(0.0, 1.0, 29) * (0.047 - 0.041))
    even, same = tooth_mesh(gear, 4, 14), tooth_mesh(gear, 4, 14, row_grading=1.0)
    assert np.array_equal(even.nodes, same.nodes) and same.fillet_rows == 0


@pytest.mark.parametrize("nx, ny", [(4, 14), (12, 40), (16, 56)])
@pytest.mark.parametrize("row_grading", [2.0, 4.0, 1000.0])
def test_graded_rows_are_even_on_each_stretch(nx, ny, row_grading):
    gear = paper_pair().gear_a
    mesh = tooth_mesh(gear, nx, ny, grading=6.0, row_grading=row_grading)
    assert np.all(jacobian_determinants(mesh.nodes, mesh.elements) > 0.0)
    n_f = mesh.fillet_rows
    assert 1 <= n_f <= ny - 1
    radii = np.hypot(*mesh.nodes[mesh.right_side].T)
    corners = radii[::2]
    assert corners[n_f] == pytest.approx(gear.form_radius, abs=1e-12)
    fillet, flank = np.diff(corners[:n_f + 1]), np.diff(corners[n_f:])
    np.testing.assert_allclose(fillet, fillet[0], rtol=1e-9)
    np.testing.assert_allclose(flank, flank[0], rtol=1e-9)
    assert fillet[0] > flank[0]


def test_flank_law_holds_over_the_flank_rows():
    """The flank coordinate stays linear in radius over the flank rows: the exact involute
    at each corner t = k >= fillet_rows is the outline node there."""
    pair = paper_pair()
    system = system_for(pair, 12, 40, 61, 6.0, 4.0)
    for gb in system.gears:
        f, mesh = gb.teeth[0].flank, gb.teeth[0].mesh
        assert f.t0 == pytest.approx(mesh.fillet_rows, abs=1e-9)
        for k in range(mesh.fillet_rows, mesh.ny + 1):
            np.testing.assert_allclose(f.exact(float(k)), f.side_Y[2 * k], atol=1e-12)


def test_row_grading_out_of_range():
    with pytest.raises(InputError, match="row_grading"):
        tooth_mesh(paper_pair().gear_a, 4, 14, row_grading=0.5)


# -- the key: settings, case file, command line, models ------------------------------------

import dataclasses  # noqa: E402
import json  # noqa: E402
from pathlib import Path  # noqa: E402

from spurdyn.case import case_from_dict, case_to_dict, load_case  # noqa: E402
from spurdyn.cli.main import main  # noqa: E402
from spurdyn.settings import RunSettings  # noqa: E402

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
FIG8 = (EXAMPLES / "paper_fig8.toml").read_text()


def _fig8_with(tmp_path, mesh_line: str) -> Path:
    """The Fig. 8 example with ``mesh_line`` added to its ``[mesh]`` table."""
    assert "[mesh]\n" in FIG8
    path = tmp_path / "fig8_rows.toml"
    path.write_text(FIG8.replace("[mesh]\n", f"[mesh]\n{mesh_line}\n", 1))
    return path


@pytest.mark.parametrize("bad", [0.5, "x", True, 1e9, float("nan"), 0.0])
def test_run_settings_refuse_a_bad_row_grading(bad):
    with pytest.raises(InputError) as err:
        RunSettings(speed_a=100.0, speed_b=100.0, torque=1.0, row_grading=bad)
    assert err.value.field == "row_grading"


def test_the_default_is_one_and_is_not_written_back():
    case = load_case(EXAMPLES / "paper_fig8.toml", check_step=False)
    assert case.run.row_grading == 1.0 and case.meshed_pair.row_grading == 1.0
    assert "row_grading" not in case_to_dict(case)["mesh"]   # stored cases and sweep hashes as before


def test_a_case_file_key_reaches_the_run_and_comes_back(tmp_path):
    case = load_case(_fig8_with(tmp_path, "row_grading = 4"), check_step=False)
    assert case.run.row_grading == 4.0 and case.meshed_pair.row_grading == 4.0
    data = case_to_dict(case)
    assert data["mesh"]["row_grading"] == 4.0
    again = case_from_dict(data, name=case.name, check_step=False)
    assert again.run == dataclasses.replace(case.run, name=again.run.name)


def _info(capsys, *argv):
    code = main(["info", *argv, "--json"])
    out = capsys.readouterr()
    assert code == 0, out.err
    return json.loads(out.out)


def test_info_with_graded_rows_differs_and_a_file_says_the_same(tmp_path, capsys):
    even = _info(capsys, "paper-fig8")
    rows = _info(capsys, "paper-fig8", "--row-grading", "4")
    assert even["mesh"]["row_grading"] == 1.0 and even["mesh"]["fillet_rows"] == {"a": 0, "b": 0}
    assert rows["mesh"]["row_grading"] == 4.0 and rows["mesh"]["fillet_rows"] == {"a": 1, "b": 1}
    assert rows["mesh"]["nodes"] == even["mesh"]["nodes"]            # the same elements, moved
    assert rows["pair_stiffness_pitch_N_per_m"] != even["pair_stiffness_pitch_N_per_m"]
    assert rows["stable_dt_s"] != even["stable_dt_s"]
    text = main(["info", "paper-fig8", "--row-grading", "4"])
    assert text == 0 and "fillet rows 4 times as tall as flank rows" in capsys.readouterr().out
    from_file = _info(capsys, str(_fig8_with(tmp_path, "row_grading = 4")), "--contact", "point")
    assert from_file["pair_stiffness_pitch_N_per_m"] == pytest.approx(
        rows["pair_stiffness_pitch_N_per_m"], rel=1e-9)


@pytest.mark.parametrize("argv, field", [
    (["info", "paper-fig8", "--row-grading", "0.5"], "--row-grading"),
    (["info", "paper-fig8", "--row-grading", "1e9"], "--row-grading"),
    (["run", "paper-fig8", "--row-grading", "0.5"], "--row-grading"),
    (["run", "paper-fig8", "--model", "sector", "--cycles", "1", "--row-grading", "4"],
     "--row-grading"),
    (["run", "paper-fig8", "--model", "lumped", "--cycles", "2", "--stiffness", "sector",
      "--row-grading", "4"], "--row-grading"),
])
def test_a_bad_or_refused_row_grading_is_one_line(tmp_path, capsys, monkeypatch, argv, field):
    monkeypatch.chdir(tmp_path)
    code = main(argv)
    out, err = capsys.readouterr()
    assert code == 2 and out == "" and err.count("\n") == 1, err
    assert err.startswith(f"spurdyn: error: {field}: "), err
    assert not any(tmp_path.iterdir())          # nothing written


def test_the_sector_model_refuses_graded_rows(tmp_path, capsys):
    from spurdyn.simulators import MODELS, sector_cycle

    settings = RunSettings(speed_a=400.0, speed_b=400.0, torque=22.25, cycles=1, row_grading=4.0,
                           integrator="implicit")
    for call in (lambda: MODELS["sector"](paper_pair(), settings),
                 lambda: sector_cycle(paper_pair(), settings)):
        with pytest.raises(InputError, match="rows even in radius") as err:
            call()
        assert err.value.field == "mesh.row_grading"
    code = main(["stiffness", str(_fig8_with(tmp_path, "row_grading = 4"))])
    out, err = capsys.readouterr()
    assert code == 2 and err.startswith("spurdyn: error: mesh.row_grading: "), err


def test_the_lumped_model_takes_the_graded_tooth(tmp_path):
    from spurdyn.simulators import tooth_table

    base = RunSettings(speed_a=400.0, speed_b=400.0, torque=22.25, contact="point")
    even, rows = tooth_table(paper_pair(), base), tooth_table(paper_pair(),
                                                              dataclasses.replace(base, row_grading=4.0))
    pitch = paper_pair().pitch_roll_a
    assert even is not rows and not np.isclose(even.scalar(pitch), rows.scalar(pitch), rtol=1e-6)
