"""`spurdyn info` and `spurdyn mesh`, and their refusals of bad input."""

import json
import subprocess
import sys
from pathlib import Path

import pytest

from spurdyn.cli.main import main

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"

PAPER_TOML = (EXAMPLES / "paper_pair.toml").read_text()


def run(capsys, *argv):
    code = main(list(argv))
    out = capsys.readouterr()
    return code, out.out, out.err


def test_info_paper_json(capsys):
    code, out, err = run(capsys, "info", "paper", "--json")
    assert code == 0 and err == ""
    info = json.loads(out)
    assert round(info["contact_ratio"], 3) == 1.638
    assert round(info["theta_s_deg"], 2) == 21.06
    assert round(info["theta_2_deg"], 2) == 8.20
    assert round(info["base_radius_m"]["a"] * 1e3, 2) == 41.77
    assert info["tooth_mass_kg"]["a"] == pytest.approx(info["tooth_mass_kg"]["b"])
    assert 1.0e-3 < info["tooth_mass_kg"]["a"] < 2.5e-3
    assert info["n_dof"]["a"] == 2 * info["mesh"]["nodes"]["a"] + 1
    assert info["stable_dt_s"] >= 3e-8 and info["paper_dt_stable"]
    assert 8e7 < info["pair_stiffness_pitch_N_per_m"] < 2.4e8


def test_info_toml_equals_preset(capsys):
    _, out_toml, _ = run(capsys, "info", str(EXAMPLES / "paper_pair.toml"), "--json")
    _, out_preset, _ = run(capsys, "info", "paper", "--json")
    a, b = json.loads(out_toml), json.loads(out_preset)
    for key in ("contact_ratio", "theta_s_deg", "stable_dt_s", "pair_stiffness_pitch_N_per_m"):
        assert a[key] == pytest.approx(b[key], rel=1e-9)


def test_info_text_and_finer_mesh_reports_unstable_paper_step(capsys):
    code, out, _ = run(capsys, "info", "paper", "--mesh", "8x28")
    assert code == 0
    assert "NOT stable" in out


def test_info_different_gears(capsys):
    code, out, _ = run(capsys, "info", str(EXAMPLES / "pinion_gear.toml"), "--json")
    info = json.loads(out)
    assert code == 0 and info["teeth"] == {"a": 20, "b": 40}


def test_mesh_picture(tmp_path, capsys):
    png = tmp_path / "mesh.png"
    code, _, _ = run(capsys, "mesh", "paper", "--png", str(png))
    assert code == 0 and png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


BAD_TOML = [
    ("teeth = 28", "teeth = 4", "gear_a.teeth"),
    ("teeth = 28", "teeth = \"many\"", "gear_a.teeth"),
    ("face_width = 0.00635", "face_width = -0.00635", "gear_a.face_width"),
    ("face_width = 0.00635", "face_width = 0", "gear_a.face_width"),
    ("tip_radius = 0.047625", "tip_radius = 0.040", "gear_a.tip_radius"),
    ("root_radius = 0.04048", "root_radius = 0.05", "gear_a.root_radius"),
    ("pressure_angle_deg = 20.0", "pressure_angle_deg = 60.0", "gear_a.pressure_angle_deg"),
    ("disk_inertia = 2.965e-4", "disk_inertia = \"heavy\"", "gear_a.disk_inertia"),
    ("disk_inertia = 2.965e-4", "disk_inertia = 2.965e-4\ncolour = \"red\"", "gear_a.colour"),
    ("young = 210e9", "young = -1.0", "gear_a.material"),
    ("poisson = 0.3", "poisson = 0.7", "gear_a.material"),
    ("nx = 4 ", "nx = 0 ", "mesh.nx"),
    ("driver = \"a\"", "driver = \"c\"", "pair.driver"),
    ("[mesh]", "[meshing]", "meshing"),
    ("teeth = 28", "teeth = [28", "not valid TOML"),
]


@pytest.mark.parametrize("old, new, expected", BAD_TOML)
def test_bad_toml_one_line_exit_2(tmp_path, capsys, old, new, expected):
    assert old in PAPER_TOML
    bad = tmp_path / "bad.toml"
    bad.write_text(PAPER_TOML.replace(old, new, 1))
    code, out, err = run(capsys, "info", str(bad))
    assert code == 2 and out == ""
    assert expected in err
    assert err.count("\n") == 1 and err.startswith("spurdyn: error: ")


def test_undercut_pinion_refused(tmp_path, capsys):
    bad = tmp_path / "undercut.toml"
    bad.write_text((EXAMPLES / "pinion_gear.toml").read_text().replace("teeth = 20", "teeth = 12", 1))
    code, _, err = run(capsys, "info", str(bad))
    assert code == 2 and "gear_a.teeth" in err and "undercut" in err


@pytest.mark.parametrize("argv, expected", [
    (["info", "no-such-case"], "unknown case"),
    (["info", "missing.toml"], "no such file"),
    (["info", "paper", "--mesh", "4by14"], "--mesh"),
    (["mesh", "paper", "--png", "/no/such/dir/x.png"], "--png"),
    (["mesh", "paper", "--png", "x.jpg"], "--png"),
])
def test_bad_arguments(capsys, argv, expected):
    code, out, err = run(capsys, *argv)
    assert code == 2 and expected in err and err.count("\n") == 1


def test_console_script_refuses_without_traceback(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text(PAPER_TOML.replace("teeth = 28", "teeth = -3", 1))
    proc = subprocess.run([sys.executable, "-m", "spurdyn.cli.main", "info", str(bad)],
                          capture_output=True, text=True)
    assert proc.returncode == 2
    assert "Traceback" not in proc.stderr and proc.stderr.count("\n") == 1
    assert "gear_a.teeth" in proc.stderr
    proc = subprocess.run([sys.executable, "-m", "spurdyn.cli.main", "info"], capture_output=True, text=True)
    assert proc.returncode == 2 and proc.stderr.count("\n") == 1
