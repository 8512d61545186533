"""Issue 35: what a bare case file and a Python run get by default, and what they refuse.

The sector model by default (docs/sector.md, 6.10): options it does not take and damping out
of its range are refused in one line naming the key or flag, exit 2, nothing written.
"""

from __future__ import annotations

import math

import pytest

from cli_helpers import leftovers, run
from spurdyn.cli.main import main

from pathlib import Path

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "pinion_23_47.toml"


@pytest.mark.parametrize("argv, words", [
    (["--angle", "0.3"], "--angle: the sector model does not read it"),
    (["--dt", "1e-8"], "--dt: the sector model sets its own step"),
    (["--integrator", "rk4"], "--integrator: the sector model steps by generalized-alpha only"),
    (["--contact", "point"], "--contact: the sector model's contact is the Hertzian strip"),
    (["--damping", "1.0"], "--damping: must be a number from 0 to below 1"),
    (["--damping", "-0.1"], "--damping: must not be negative"),
])
def test_options_the_default_model_does_not_take_are_refused(tmp_path, capsys, argv, words):
    """A bare case file runs the sector model: what it does not read, or damping out of
    [0, 1), is refused in one line naming the flag, and nothing is written."""
    code, out, err = run(capsys, "run", EXAMPLE, "--out", tmp_path / "o", *argv)
    assert code == 2 and out == "" and err.count("\n") == 1, err
    assert f"spurdyn: error: {words}" in err, err
    assert "Traceback" not in err and leftovers(tmp_path) == []


@pytest.mark.parametrize("line, key", [("damping_ratio = 1.5", "run.damping_ratio"),
                                       ("damping_ratio = nan", "run.damping_ratio"),
                                       ("angle_deg = 10.0", "run.angle_deg")])
def test_a_case_files_keys_out_of_the_default_model_are_refused(tmp_path, capsys, line, key):
    path = tmp_path / "bad.toml"
    path.write_text(EXAMPLE.read_text() + line + "\n")
    assert main(["run", str(path), "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"spurdyn: error: {key}: ") and err.count("\n") == 1, err
    assert not (tmp_path / "o").exists()


@pytest.mark.slow
def test_the_python_api_runs_the_sector_model_by_default():
    """``spurdyn.simulate(pair, run_settings(...))`` with no model: the sector model's
    steady state, its cycles and mesh damper the defaults, settled."""
    import spurdyn
    from spurdyn.case import load_case
    from spurdyn.sector.rules import DEFAULT_CYCLES, MESH_DAMPING_RATIO

    pair = load_case(EXAMPLE).pair
    settings = spurdyn.run_settings(pair, 3000 * math.pi / 30, 50.0, nx=2, ny=8)
    result = spurdyn.simulate(pair, settings)
    assert result.info["model"] == "sector" and result.status == "complete"
    assert result.info["steady"]["cycles"] == DEFAULT_CYCLES and result.info["steady"]["settled"]
    assert (result.info["damping_ratio"], result.info["damping_ratio_source"]) == (MESH_DAMPING_RATIO,
                                                                                     "model default")
