"""Writing beside (spurdyn.results.beside): a forked child does one piece of the writing.

The work is done when the block ends, in the child or, when the child fails or is
killed, again in this process; an error of the block stops the child; without a child the
work runs after the block. A run folder is the same either way.
"""

from __future__ import annotations

import os
import signal
import sys
import threading
from pathlib import Path

import pytest

from spurdyn.case import preset_case
from spurdyn.results import beside as beside_module
from spurdyn.results.beside import beside
from spurdyn.results.io import write_run
from run_helpers import fake_simulate

#: Where beside() forks. Other tests may leave a thread behind (a tqdm monitor), which
#: turns the child off in this process; these tests turn it on again.
FORKS = hasattr(os, "fork") and sys.platform.startswith("linux")


@pytest.fixture
def forking(monkeypatch: pytest.MonkeyPatch) -> None:
    if not FORKS:
        pytest.skip("beside() forks only on Linux")
    monkeypatch.setattr(beside_module, "can_fork", lambda: True)


needs_fork = pytest.mark.usefixtures("forking")


def _writer(path: Path, fail_in_child: bool = False, kill_child: bool = False):
    parent = os.getpid()

    def work() -> None:
        in_child = os.getpid() != parent
        if in_child and kill_child:
            os.kill(os.getpid(), signal.SIGKILL)
        if in_child and fail_in_child:
            raise RuntimeError("only the child fails")
        path.write_text("child" if in_child else "parent")
    return work


@needs_fork
def test_the_work_is_done_in_a_child_and_finished_when_the_block_ends(tmp_path: Path) -> None:
    out = tmp_path / "picture.txt"
    with beside(_writer(out)):
        (tmp_path / "rest.txt").write_text("rest")
    assert out.read_text() == "child"
    assert (tmp_path / "rest.txt").read_text() == "rest"


@needs_fork
def test_a_child_that_fails_is_replaced_by_this_process(tmp_path: Path,
                                                        capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "picture.txt"
    with beside(_writer(out, fail_in_child=True)):
        pass
    assert out.read_text() == "parent"
    err = capsys.readouterr().err
    assert "only the child fails" in err and "written by this process instead" in err


@needs_fork
def test_a_killed_child_loses_nothing(tmp_path: Path) -> None:
    out = tmp_path / "picture.txt"
    with beside(_writer(out, kill_child=True)):
        pass
    assert out.read_text() == "parent"


@needs_fork
def test_an_error_of_the_work_is_raised_here(tmp_path: Path) -> None:
    def work() -> None:
        (tmp_path / "no such folder" / "picture.png").write_text("x")
    with pytest.raises(FileNotFoundError):
        with beside(work):
            pass


@needs_fork
def test_an_error_of_the_block_stops_the_child(tmp_path: Path,
                                               monkeypatch: pytest.MonkeyPatch) -> None:
    marker = tmp_path / "finished.txt"
    children: list[int] = []
    fork = beside_module.fork

    def recording_fork() -> int:
        pid = fork()
        if pid:
            children.append(pid)
        return pid
    monkeypatch.setattr(beside_module, "fork", recording_fork)

    def slow() -> None:
        signal.pause()    # until killed: the parent gives the folder up
        marker.write_text("finished")
    with pytest.raises(ValueError, match="writing failed"):
        with beside(slow):
            raise ValueError("writing failed")
    assert not marker.exists()
    assert len(children) == 1
    with pytest.raises(ChildProcessError):   # the child was reaped: nothing is left of it
        os.waitpid(children[0], os.WNOHANG)


def test_without_a_child_the_work_runs_after_the_block(tmp_path: Path,
                                                       monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(beside_module, "can_fork", lambda: False)
    order: list[str] = []
    with beside(lambda: order.append("work")):
        order.append("block")
    assert order == ["block", "work"]
    with pytest.raises(ValueError):
        with beside(lambda: order.append("never")):
            raise ValueError
    assert "never" not in order


def test_a_run_folder_is_the_same_with_and_without_a_child(tmp_path: Path,
                                                           monkeypatch: pytest.MonkeyPatch) -> None:
    case = preset_case("paper-fig9", {"run.angle_deg": 0.3}, check_step=False)
    result = fake_simulate(case.pair, case.run)
    for name, fork in (("forked", FORKS), ("here", False)):
        monkeypatch.setattr(beside_module, "can_fork", lambda fork=fork: fork)
        (tmp_path / name).mkdir()
        write_run(result, case, tmp_path / name)
    files = sorted(p.name for p in (tmp_path / "forked").iterdir())
    assert files == sorted(p.name for p in (tmp_path / "here").iterdir())
    assert "contact_force.png" in files
    for name in ("contact_force.png", "contact_force.csv", "summary.json"):
        assert (tmp_path / "forked" / name).read_bytes() == (tmp_path / "here" / name).read_bytes()


@needs_fork
def test_no_process_to_spare_and_the_work_is_done_here(tmp_path: Path,
                                                      monkeypatch: pytest.MonkeyPatch) -> None:
    def no_fork() -> int:
        raise BlockingIOError(11, "Resource temporarily unavailable")
    monkeypatch.setattr(beside_module, "fork", no_fork)
    out = tmp_path / "picture.txt"
    with beside(_writer(out)):
        assert not out.exists()
    assert out.read_text() == "parent"


def test_no_child_while_another_thread_runs() -> None:
    """A lock held by another thread would stay locked in a forked child."""
    from spurdyn.results.beside import can_fork

    release = threading.Event()
    other = threading.Thread(target=release.wait)
    other.start()
    try:
        assert not can_fork()
    finally:
        release.set()
        other.join()
