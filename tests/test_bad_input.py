"""Every bad gear-pair description is refused through the command line in one line.

Each case edits ``examples/paper_pair.toml`` (or writes a small file from scratch), runs
``spurdyn info FILE`` in-process and requires: exit status 2, nothing on stdout, and
exactly one line on stderr of the form ``spurdyn: error: <field>: <reason>``, where
``<field>`` is the key the user wrote (with its table) and ``<reason>`` says what is
wrong.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from spurdyn.cli.main import main

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
PAPER = (EXAMPLES / "paper_pair.toml").read_text()
MATERIAL_TABLE = "[gear_a.material]\nyoung = 210e9\npoisson = 0.3\ndensity = 7800.0\n"
PAIR_TABLE = '[pair]\ndriver = "a"                  # which gear drives\n'
MESH_TABLE = ("[mesh]\nnx = 4                        # Q8 elements across the tooth\n"
              "ny = 14                       # Q8 elements along the tooth\n")


def edit(old: str, new: str) -> str:
    """The paper's file with the first ``old`` replaced by ``new`` (``old`` must occur)."""
    assert old in PAPER, old
    return PAPER.replace(old, new, 1)


def gear(name: str, teeth: int, module: float, addendum: float, dedendum: float,
         alpha_deg: float = 20.0) -> str:
    """A gear table in the module / addendum / dedendum form."""
    return (f"[{name}]\nteeth = {teeth}\nmodule = {module}\naddendum = {addendum}\n"
            f"dedendum = {dedendum}\npressure_angle_deg = {alpha_deg}\nface_width = 0.01\n"
            f"disk_inertia = 1e-4\n")


# (edited file, field named, words of the reason)
CASES = [
    # -- zero or negative sizes ------------------------------------------------------
    pytest.param(edit("pitch_radius = 0.04445", "pitch_radius = -0.04445"),
                 "gear_a.pitch_radius", "must be a positive number", id="pitch_radius<0"),
    pytest.param(edit("pitch_radius = 0.04445", "pitch_radius = 0.0"),
                 "gear_a.pitch_radius", "must be a positive number", id="pitch_radius=0"),
    pytest.param(edit("pitch_radius = 0.04445", "pitch_radius = inf"),
                 "gear_a.pitch_radius", "must be a positive number", id="pitch_radius=inf"),
    pytest.param(edit("pitch_radius = 0.04445        # or: module = 0.003175", "module = -0.003175"),
                 "gear_a.module", "must be a positive number", id="module<0"),
    pytest.param(edit("pitch_radius = 0.04445        # or: module = 0.003175", "module = 0"),
                 "gear_a.module", "must be a positive number", id="module=0"),
    pytest.param(edit("tip_radius = 0.047625         # or: addendum = 0.003175", "addendum = -0.003"),
                 "gear_a.addendum", "must be a positive number", id="addendum<0"),
    pytest.param(edit("tip_radius = 0.047625         # or: addendum = 0.003175", "addendum = 0"),
                 "gear_a.addendum", "must be a positive number", id="addendum=0"),
    pytest.param(edit("root_radius = 0.04048         # or: dedendum = 0.00397", "dedendum = -0.004"),
                 "gear_a.dedendum", "must be a positive number", id="dedendum<0"),
    pytest.param(edit("root_radius = 0.04048         # or: dedendum = 0.00397", "dedendum = 0"),
                 "gear_a.dedendum", "must be a positive number", id="dedendum=0"),
    pytest.param(edit("root_radius = 0.04048         # or: dedendum = 0.00397", "dedendum = 0.05"),
                 "gear_a.dedendum", "root circle at or below the gear centre", id="dedendum>r_p"),
    pytest.param(edit("tip_radius = 0.047625", "tip_radius = -0.047625"),
                 "gear_a.tip_radius", "must be above the pitch radius", id="tip_radius<0"),
    pytest.param(edit("tip_radius = 0.047625", "tip_radius = 0"),
                 "gear_a.tip_radius", "must be above the pitch radius", id="tip_radius=0"),
    pytest.param(edit("tip_radius = 0.047625", "tip_radius = nan"),
                 "gear_a.tip_radius", "", id="tip_radius=nan"),
    pytest.param(edit("root_radius = 0.04048", "root_radius = -0.04048"),
                 "gear_a.root_radius", "", id="root_radius<0"),
    pytest.param(edit("root_radius = 0.04048", "root_radius = 0"),
                 "gear_a.root_radius", "", id="root_radius=0"),
    pytest.param(edit("root_radius = 0.04048", "root_radius = nan"),
                 "gear_a.root_radius", "", id="root_radius=nan"),
    # -- lengths written in millimetres -------------------------------------------
    pytest.param(PAPER.replace("pitch_radius = 0.04445", "pitch_radius = 44.45")
                 .replace("tip_radius = 0.047625", "tip_radius = 47.625")
                 .replace("root_radius = 0.04048", "root_radius = 40.48")
                 .replace("face_width = 0.00635", "face_width = 6.35"),
                 "gear_a.pitch_radius", "lengths are in metres", id="radii-mm"),
    pytest.param(PAIR_TABLE + gear("gear_a", 28, 3.175, 3.175, 3.97) + MATERIAL_TABLE,
                 "gear_a.module", "lengths are in metres", id="module-mm"),
    pytest.param(edit("face_width = 0.00635", "face_width = 6.35"),
                 "gear_a.face_width", "lengths are in metres", id="face_width-mm"),
    pytest.param(edit("face_width = 0.00635", "face_width = -0.00635"),
                 "gear_a.face_width", "must be a positive number", id="face_width<0"),
    pytest.param(edit("face_width = 0.00635", "face_width = 0"),
                 "gear_a.face_width", "must be a positive number", id="face_width=0"),
    pytest.param(edit("face_width = 0.00635", "face_width = nan"),
                 "gear_a.face_width", "must be a positive number", id="face_width=nan"),
    pytest.param(edit("disk_inertia = 2.965e-4", "disk_inertia = 0"),
                 "gear_a.disk_inertia", "must be a positive number", id="disk_inertia=0"),
    pytest.param(edit("disk_inertia = 2.965e-4", "disk_inertia = -2.965e-4"),
                 "gear_a.disk_inertia", "must be a positive number", id="disk_inertia<0"),
    pytest.param(edit("# cutter_tip_radius = 0.0012065", "cutter_tip_radius = 0"),
                 "gear_a.cutter_tip_radius", "must be a positive number", id="cutter_tip=0"),
    pytest.param(edit("# cutter_tip_radius = 0.0012065", "cutter_tip_radius = -0.001"),
                 "gear_a.cutter_tip_radius", "must be a positive number", id="cutter_tip<0"),
    pytest.param(edit("# cutter_tip_radius = 0.0012065", "cutter_tip_radius = 0.0025"),
                 "gear_a.cutter_tip_radius", "too large", id="cutter_tip-too-large"),
    pytest.param(edit("young = 210e9", "young = 0"),
                 "gear_a.material.young", "must be > 0", id="young=0"),
    pytest.param(edit("young = 210e9", "young = -210e9"),
                 "gear_a.material.young", "must be > 0", id="young<0"),
    pytest.param(edit("young = 210e9", "young = inf"),
                 "gear_a.material.young", "must be finite", id="young=inf"),
    pytest.param(edit("density = 7800.0", "density = 0"),
                 "gear_a.material.density", "must be > 0", id="density=0"),
    pytest.param(edit("density = 7800.0", "density = -7800.0"),
                 "gear_a.material.density", "must be > 0", id="density<0"),
    pytest.param(edit("poisson = 0.3", "poisson = 0.5"),
                 "gear_a.material.poisson", "must be in (-1, 0.5)", id="poisson=0.5"),
    pytest.param(edit("poisson = 0.3", "poisson = -1.0"),
                 "gear_a.material.poisson", "must be in (-1, 0.5)", id="poisson=-1"),
    pytest.param(edit("# centre_distance = 0.0889", "centre_distance = -0.0889"),
                 "pair.centre_distance", "must be a positive number", id="centre<0"),
    pytest.param(edit("# centre_distance = 0.0889", "centre_distance = 0.0"),
                 "pair.centre_distance", "", id="centre=0"),
    pytest.param(edit("nx = 4 ", "nx = 0 "), "mesh.nx", "from 1 to 64", id="nx=0"),
    pytest.param(edit("ny = 14", "ny = -14"), "mesh.ny", "from 2 to 256", id="ny<0"),
    pytest.param(edit("ny = 14", "ny = 14\ngrading = 0.5"), "mesh.grading", "from 1 (even) to 50",
                 id="grading<1"),
    pytest.param(edit("ny = 14", "ny = 14\ngrading = 80"), "mesh.grading", "from 1 (even) to 50",
                 id="grading>50"),
    pytest.param(edit("ny = 14", 'ny = 14\ngrading = "fine"'), "mesh.grading", "must be a number",
                 id="grading-text"),
    pytest.param(edit("ny = 14", "ny = 14\nrow_grading = 0.5"), "mesh.row_grading",
                 "from 1 (even rows) to 1000", id="row_grading<1"),
    pytest.param(edit("ny = 14", 'ny = 14\nrow_grading = "x"'), "mesh.row_grading",
                 "must be a number", id="row_grading-text"),
    pytest.param(edit("ny = 14", "ny = 14\nrow_grading = true"), "mesh.row_grading",
                 "must be a number", id="row_grading-bool"),
    pytest.param(edit("ny = 14", "ny = 14\nrow_grading = 1e9"), "mesh.row_grading",
                 "from 1 (even rows) to 1000", id="row_grading>1000"),
    # -- tip radius not above root radius ----------------------------------------------
    pytest.param(edit("tip_radius = 0.047625", "tip_radius = 0.0400"),
                 "gear_a.tip_radius", "must be above", id="tip<root"),
    pytest.param(edit("tip_radius = 0.047625", "tip_radius = 0.04048"),
                 "gear_a.tip_radius", "must be above", id="tip=root"),
    pytest.param(edit("root_radius = 0.04048", "root_radius = 0.0480"),
                 "gear_a.root_radius", "must be below the pitch radius", id="root>tip"),
    pytest.param(edit("tip_radius = 0.047625", "tip_radius = 0.060"),
                 "gear_a.tip_radius", "", id="tip-far-above-pitch"),
    # -- too few teeth -------------------------------------------------------------------
    pytest.param(edit("teeth = 28", "teeth = 0"), "gear_a.teeth", "positive whole number",
                 id="teeth=0"),
    pytest.param(edit("teeth = 28", "teeth = -28"), "gear_a.teeth", "positive whole number",
                 id="teeth<0"),
    pytest.param(edit("teeth = 28", "teeth = 7"), "gear_a.teeth", "at least 8", id="teeth=7"),
    pytest.param(gear("gear_a", 14, 0.003175, 0.003175, 0.00397),
                 "gear_a.teeth", "undercut", id="teeth-undercut"),
    pytest.param(gear("gear_a", 17, 0.003, 0.003, 0.00375),
                 "gear_a.teeth", "need at least 18", id="teeth=17-undercut"),
    # -- pressure angle out of range -------------------------------------------------------
    pytest.param(edit("pressure_angle_deg = 20.0", "pressure_angle_deg = 0.0"),
                 "gear_a.pressure_angle_deg", "between 12 and 35", id="alpha=0"),
    pytest.param(edit("pressure_angle_deg = 20.0", "pressure_angle_deg = -20.0"),
                 "gear_a.pressure_angle_deg", "between 12 and 35", id="alpha<0"),
    pytest.param(edit("pressure_angle_deg = 20.0", "pressure_angle_deg = 11.9"),
                 "gear_a.pressure_angle_deg", "between 12 and 35", id="alpha=11.9"),
    pytest.param(edit("pressure_angle_deg = 20.0", "pressure_angle_deg = 35.1"),
                 "gear_a.pressure_angle_deg", "between 12 and 35", id="alpha=35.1"),
    pytest.param(edit("pressure_angle_deg = 20.0", "pressure_angle_deg = 90.0"),
                 "gear_a.pressure_angle_deg", "between 12 and 35", id="alpha=90"),
    pytest.param(edit("pressure_angle_deg = 20.0", "pressure_angle_deg = nan"),
                 "gear_a.pressure_angle_deg", "between 12 and 35", id="alpha=nan"),
    pytest.param(gear("gear_a", 30, 0.003, 0.003, 0.00375, 35.0),
                 "gear_a.dedendum", "comes to a point", id="alpha=35-pointed-rack"),
    pytest.param(gear("gear_a", 28, 0.003, 0.003, 0.00375)
                 + gear("gear_b", 28, 0.003, 0.003, 0.00375, 22.0).replace(
                     "disk_inertia", "cutter_tip_radius = 0.0006\ndisk_inertia"),
                 "gear_b.pressure_angle_deg", "differs", id="alpha-mismatch"),
    # -- unknown keys ----------------------------------------------------------------------
    pytest.param(edit("[gear_a]", 'title = "paper"\n\n[gear_a]'),
                 "title", "unknown key", id="unknown-top-key"),
    pytest.param(edit("[mesh]", "[meshing]"), "meshing", "unknown key", id="unknown-table"),
    pytest.param(edit("disk_inertia = 2.965e-4", 'disk_inertia = 2.965e-4\ncolour = "red"'),
                 "gear_a.colour", "unknown key", id="unknown-gear-key"),
    pytest.param(edit("pressure_angle_deg = 20.0", "pressure_angle = 20.0"),
                 "gear_a.pressure_angle", "unknown key", id="unknown-gear-key-no-unit"),
    pytest.param(edit("density = 7800.0", "density = 7800.0\nyield = 1e9"),
                 "gear_a.material.yield", "unknown key", id="unknown-material-key"),
    pytest.param(PAPER + "\n" + gear("gear_b", 28, 0.003175, 0.003175, 0.00397)
                 + "helix_angle_deg = 0.0\n",
                 "gear_b.helix_angle_deg", "unknown key", id="unknown-gear_b-key"),
    pytest.param(edit('driver = "a"', 'driver = "a"\nratio = 1.0'),
                 "pair.ratio", "unknown key", id="unknown-pair-key"),
    pytest.param(edit("ny = 14", "ny = 14\nnz = 3"), "mesh.nz", "unknown key",
                 id="unknown-mesh-key"),
    # -- wrong types -------------------------------------------------------------------------
    pytest.param(edit("teeth = 28", 'teeth = "28"'), "gear_a.teeth", "whole number",
                 id="teeth-string"),
    pytest.param(edit("teeth = 28", "teeth = 28.0"), "gear_a.teeth", "whole number",
                 id="teeth-float"),
    pytest.param(edit("teeth = 28", "teeth = true"), "gear_a.teeth", "whole number",
                 id="teeth-bool"),
    pytest.param(edit("pitch_radius = 0.04445", 'pitch_radius = "big"'),
                 "gear_a.pitch_radius", "must be a number", id="pitch_radius-string"),
    pytest.param(edit("tip_radius = 0.047625", "tip_radius = [0.047625]"),
                 "gear_a.tip_radius", "must be a number", id="tip_radius-array"),
    pytest.param(edit("pressure_angle_deg = 20.0", 'pressure_angle_deg = "20"'),
                 "gear_a.pressure_angle_deg", "must be a number", id="alpha-string"),
    pytest.param(edit("face_width = 0.00635", "face_width = true"),
                 "gear_a.face_width", "must be a number", id="face_width-bool"),
    pytest.param(edit("disk_inertia = 2.965e-4", 'disk_inertia = "heavy"'),
                 "gear_a.disk_inertia", "must be a number", id="disk_inertia-string"),
    pytest.param(edit("# cutter_tip_radius = 0.0012065", 'cutter_tip_radius = "fine"'),
                 "gear_a.cutter_tip_radius", "must be a number", id="cutter_tip-string"),
    pytest.param(edit("face_width = 0.00635\n", ""),
                 "gear_a.face_width", "is missing", id="face_width-missing"),
    pytest.param(edit("young = 210e9", 'young = "steel"'),
                 "gear_a.material.young", "must be a number", id="young-string"),
    pytest.param(edit("poisson = 0.3", "poisson = false"),
                 "gear_a.material.poisson", "must be a number", id="poisson-bool"),
    pytest.param(edit(MATERIAL_TABLE, "").replace("disk_inertia = 2.965e-4",
                                                  'disk_inertia = 2.965e-4\nmaterial = "steel"'),
                 "gear_a.material", "must be a table", id="material-string"),
    pytest.param("gear_a = 3\n", "gear_a", "must be a table", id="gear_a-number"),
    pytest.param(edit(PAIR_TABLE, "").replace("[gear_a]", 'pair = "a"\n\n[gear_a]'),
                 "pair", "must be a table", id="pair-string"),
    pytest.param(edit(MESH_TABLE, "").replace("[gear_a]", "mesh = 4\n\n[gear_a]"),
                 "mesh", "must be a table", id="mesh-number"),
    pytest.param(edit('driver = "a"', "driver = 1"), "pair.driver", "must be 'a' or 'b'",
                 id="driver-number"),
    pytest.param(edit('driver = "a"', 'driver = "c"'), "pair.driver", "must be 'a' or 'b'",
                 id="driver-unknown"),
    pytest.param(edit("# centre_distance = 0.0889", 'centre_distance = "standard"'),
                 "pair.centre_distance", "must be a number", id="centre-string"),
    pytest.param(edit("nx = 4 ", "nx = 4.5 "), "mesh.nx", "whole number", id="nx-float"),
    pytest.param(edit("ny = 14", 'ny = "14"'), "mesh.ny", "whole number", id="ny-string"),
    # -- missing or conflicting keys -------------------------------------------------------
    pytest.param("", "gear_a", "missing", id="empty-file"),
    pytest.param(edit("teeth = 28\n", ""), "gear_a.teeth", "is missing", id="teeth-missing"),
    pytest.param(edit("pitch_radius = 0.04445        # or: module = 0.003175",
                      "pitch_radius = 0.04445\nmodule = 0.003175"),
                 "gear_a.pitch_radius", "not both", id="module-and-pitch_radius"),
    pytest.param(edit("poisson = 0.3\n", ""), "gear_a.material.poisson", "is missing",
                 id="poisson-missing"),
    # -- a pair whose geometry cannot mesh ------------------------------------------------------
    pytest.param(gear("gear_a", 18, 0.003, 0.003, 0.00375)
                 + gear("gear_b", 100, 0.003, 0.0036, 0.00375),
                 "gear_a.cutter_tip_radius", "interference", id="interference"),
    pytest.param(gear("gear_a", 28, 0.003, 0.003, 0.00375)
                 + gear("gear_b", 28, 0.0031, 0.003, 0.00375),
                 "gear_b.module", "differs", id="module-mismatch"),
    pytest.param(edit("# centre_distance = 0.0889", "centre_distance = 0.080"),
                 "pair.centre_distance", "must exceed the sum of base radii", id="centre-small"),
    pytest.param(edit("# centre_distance = 0.0889", "centre_distance = 0.0925"),
                 "pair.centre_distance", "contact ratio", id="centre-ratio<1"),
    pytest.param(edit("# centre_distance = 0.0889", "centre_distance = 0.1"),
                 "pair.centre_distance", "never touch", id="centre-apart"),
    # -- not TOML at all -------------------------------------------------------------------------
    pytest.param(edit("teeth = 28", "teeth = [28"), None, "is not valid TOML", id="not-toml"),
]


@pytest.mark.parametrize("text, field, reason", CASES)
def test_bad_description_refused_in_one_line(tmp_path, capsys, text, field, reason):
    path = tmp_path / "bad.toml"
    path.write_text(text)
    code = main(["info", str(path)])
    out, err = capsys.readouterr()
    assert code == 2
    assert out == ""
    assert err.endswith("\n") and err.count("\n") == 1, err
    assert "Traceback" not in err
    # `<field>: <reason>`, the field exactly as written (not doubled, not a derived name).
    where = str(path) if field is None else field
    assert err.startswith(f"spurdyn: error: {where}: "), err
    assert reason in err, err
    assert len(err.strip()) > len(f"spurdyn: error: {where}: ") + 5  # a reason is given


def test_every_example_is_accepted(capsys):
    """The refusals above are not a blanket refusal: the shipped examples pass."""
    for path in sorted(EXAMPLES.glob("*.toml")):
        assert main(["info", str(path)]) == 0, path
        assert capsys.readouterr().err == ""


@pytest.mark.parametrize("old, new, field", [
    ("young = 210e9", "young = -1.0", "gear_a.material.young"),
    ("teeth = 28", "teeth = 7", "gear_a.teeth"),
])
def test_console_refusal_has_no_traceback(tmp_path, old, new, field):
    """The same refusal from a real process: status 2, one line, no traceback."""
    path = tmp_path / "bad.toml"
    path.write_text(edit(old, new))
    proc = subprocess.run([sys.executable, "-m", "spurdyn.cli.main", "info", str(path)],
                          capture_output=True, text=True, timeout=60)
    assert proc.returncode == 2 and proc.stdout == ""
    assert proc.stderr.count("\n") == 1 and "Traceback" not in proc.stderr
    assert proc.stderr.startswith(f"spurdyn: error: {field}: ")


@pytest.mark.parametrize("argv", [["info", "paper", "--grading", "0.9"],
                                  ["mesh", "paper", "--png", "x.png", "--grading", "60"],
                                  ["run", "paper-fig8", "--grading", "0.5"]])
def test_a_bad_grading_option_is_named(tmp_path, capsys, monkeypatch, argv):
    monkeypatch.chdir(tmp_path)
    code = main(argv)
    out, err = capsys.readouterr()
    assert code == 2 and out == "" and err.count("\n") == 1, err
    assert err.startswith("spurdyn: error: --grading: must be a number from 1 (even) to 50"), err
    assert not any(tmp_path.iterdir())          # nothing half-written


@pytest.mark.parametrize("argv", [["info", "paper", "--row-grading", "0.9"],
                                  ["mesh", "paper", "--png", "x.png", "--row-grading", "2000"],
                                  ["run", "paper-fig8", "--row-grading", "0.5"]])
def test_a_bad_row_grading_option_is_named(tmp_path, capsys, monkeypatch, argv):
    monkeypatch.chdir(tmp_path)
    code = main(argv)
    out, err = capsys.readouterr()
    assert code == 2 and out == "" and err.count("\n") == 1, err
    assert err.startswith("spurdyn: error: --row-grading: must be a number from 1 (even rows) "
                          "to 1000"), err
    assert not any(tmp_path.iterdir())          # nothing half-written
