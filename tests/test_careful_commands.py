"""The last gaps of "every command as careful as run" (docs/cli.md, "Limits"): an error of
the system named for what failed, a sweep's point count bounded by what planning holds a
point, a frozen scheduler given up on, the sector model's whole bodies bounded by their
time, and the FE model at a torque too small to load its teeth."""

from __future__ import annotations

import errno
from pathlib import Path

import pytest

from cli_helpers import EXAMPLES, fake, here, run  # noqa: F401  (fixtures)
from spurdyn.cli import main as cli_main


# -- what failed: a read is not a write -----------------------------------------------

@pytest.mark.parametrize("code, words", [(errno.ENOENT, "No such file or directory"),
                                         (errno.EACCES, "Permission denied"),
                                         (errno.EISDIR, "Is a directory")])
def test_an_error_reading_an_input_names_it_without_cannot_be_written(here, capsys,
                                                                      monkeypatch, code, words):
    def reads(args):
        raise OSError(code, words, "/data/gears/torque.csv")

    monkeypatch.setattr(cli_main, "cmd_info", reads)
    code_, out, err = run(capsys, "info", "paper")
    assert code_ == 2 and out == "" and err.count("\n") == 1
    assert err == f"spurdyn: error: /data/gears/torque.csv: {words}\n", err


def test_an_error_writing_under_out_still_says_cannot_be_written(here, capsys, monkeypatch):
    def writes(args):
        raise OSError(errno.ENOSPC, "No space left on device", str(here / "res" / "result.nc"))

    monkeypatch.setattr(cli_main, "cmd_run", writes)
    code, out, err = run(capsys, "run", "paper-fig8", "--out", here / "res")
    assert code == 2 and "res/result.nc: cannot be written (No space left on device)" in err


@pytest.mark.parametrize("command", (["info"], ["stiffness"], ["run"]), ids=lambda c: c[0])
def test_a_folder_given_as_case_file_is_said_to_be_a_folder(here, capsys, command):
    (here / "case.toml").mkdir()
    code, out, err = run(capsys, command[0], "case.toml", *command[1:])
    assert code == 2 and err == "spurdyn: error: case.toml: is a folder, not a file\n", err
