"""Property-based tests of the case file and the command line (Hypothesis).

Generated bad values for every ``[run]`` key and every ``spurdyn run`` option are each
answered with exit status 2 and one line naming the key or option, no traceback and
nothing written; generated valid small cases run. The FE solver is replaced by the
synthetic one of ``run_helpers.py`` (the run layer is what is tested); the lumped
model runs for real. Example counts are bounded to keep the suite's budget.
"""

from __future__ import annotations

import json
import math
import tempfile
from pathlib import Path
from typing import Any

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from spurdyn.case import RUN_KEYS
from spurdyn.cli import run as runner
from spurdyn.cli.main import main
from spurdyn.simulators import MODELS as MODEL_ENTRIES
from run_helpers import fake_simulate

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "paper_fig8.toml"
SETTINGS = settings(max_examples=40, deadline=None, derandomize=True,
                    suppress_health_check=[HealthCheck.function_scoped_fixture,
                                           HealthCheck.too_slow])


def toml_value(value: Any) -> str:
    """``value`` written as TOML."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        if math.isnan(value):
            return "nan"
        if math.isinf(value):
            return "inf" if value > 0 else "-inf"
        return repr(value)
    if isinstance(value, int):
        return str(value)
    if isinstance(value, str):  # TOML escapes: JSON's, but no surrogate pairs and no raw DEL
        return json.dumps(value, ensure_ascii=False).replace("\x7f", "\\u007f")
    if isinstance(value, list):
        return "[" + ", ".join(toml_value(v) for v in value) + "]"
    raise TypeError(value)


def case_file(folder: Path, run: dict[str, Any], name: str = "paper_fig8",
              drop: frozenset[str] = frozenset()) -> Path:
    """The Fig. 8 example with some ``[run]`` keys replaced or added, those of ``drop``
    left out."""
    lines = EXAMPLE.read_text().splitlines()
    start = lines.index("[run]")
    table = lines[:start + 1]
    for line in lines[start + 1:]:
        key = line.split("=", 1)[0].strip()
        if key and not key.startswith("#") and (key in run or key in drop):
            continue
        table.append(line)
    table += [f"{json.dumps(k)} = {toml_value(v)}" for k, v in run.items()]
    path = folder / f"{name}.toml"
    path.write_text("\n".join(table) + "\n")
    return path


# -- bad values ----------------------------------------------------------------------------

NOT_A_NUMBER = st.one_of(st.text(max_size=6), st.booleans(),
                         st.lists(st.integers(-3, 3), max_size=2))
NOT_FINITE = st.sampled_from([math.nan, math.inf, -math.inf])
NOT_POSITIVE = st.one_of(st.floats(max_value=0.0, allow_nan=False, allow_infinity=False),
                         st.integers(-(2**63), 0))
NOT_WHOLE = st.one_of(NOT_A_NUMBER, st.floats(allow_nan=False, allow_infinity=False))
INT64 = 2**63 - 1


def _floats(lo: float, hi: float) -> st.SearchStrategy[float]:
    return st.floats(min_value=lo, max_value=hi, allow_nan=False, allow_infinity=False)


#: Per ``[run]`` key: values that must be refused (limits for the Fig. 8 pair: theta_s =
#: 21.06 deg, 29,250 steps of 3e-8 s at 4,000 rpm, module 3.175 mm, centre 88.9 mm).
BAD: dict[str, st.SearchStrategy[Any]] = {
    "speed_a_rpm": st.one_of(NOT_A_NUMBER, NOT_FINITE, NOT_POSITIVE,
                             _floats(1.2e6, 1e308), _floats(1e-300, 50.0)),
    "speed_b_rpm": st.one_of(NOT_A_NUMBER, NOT_FINITE, NOT_POSITIVE, _floats(2e6, 1e308)),
    "torque": st.one_of(NOT_A_NUMBER, NOT_FINITE, _floats(-1e308, -1e-300),
                        _floats(1e5, 1e308)),
    "dt": st.one_of(NOT_A_NUMBER, NOT_FINITE, NOT_POSITIVE, _floats(1e-6, 1e308),
                    _floats(1e-300, 1e-14)),
    "angle_deg": st.one_of(NOT_A_NUMBER, NOT_FINITE, NOT_POSITIVE, _floats(21.6, 1e308),
                           _floats(1e-300, 1e-4)),
    "n_spline": st.one_of(NOT_WHOLE, st.integers(-(2**63), 7), st.integers(8194, INT64)),
    "tol_disp": st.one_of(NOT_A_NUMBER, NOT_FINITE, NOT_POSITIVE, _floats(4e-9, 1e308),
                          _floats(1e-300, 1e-15)),
    "max_iter": st.one_of(NOT_WHOLE, st.integers(-(2**63), 0), st.integers(100_001, INT64)),
    "accel_levels": st.one_of(NOT_WHOLE, st.integers(-(2**63), 0), st.integers(11, INT64)),
    "method": st.one_of(st.text(max_size=8).filter(lambda s: s not in ("paper", "pinned")),
                        st.integers(), st.booleans()),
    "backend": st.one_of(st.text(max_size=8).filter(lambda s: s not in ("numba", "numpy")),
                         st.integers(), st.booleans()),
    "contact": st.one_of(st.text(max_size=8).filter(lambda s: s not in ("point", "hertz")),
                         st.integers(), st.booleans()),
    "save_every": st.one_of(NOT_WHOLE, st.integers(-(2**63), 0), st.integers(10_000, INT64)),
    "frames_every": st.one_of(NOT_WHOLE, st.integers(-(2**63), -1)),
    "keep_theta_term": st.one_of(st.integers(), st.text(max_size=5), st.floats()),
    "back_flanks": st.one_of(st.integers(), st.text(max_size=5), st.floats()),
    "damping_ratio": st.one_of(NOT_A_NUMBER, NOT_FINITE, _floats(-1e308, -1e-300),
                               _floats(1.0, 1e308)),
    "integrator": st.one_of(st.text(max_size=8).filter(lambda s: s not in ("rk4", "implicit")),
                            st.integers(), st.booleans()),
    "rho_inf": st.one_of(NOT_A_NUMBER, NOT_FINITE, _floats(-1e308, -1e-300),
                         _floats(1.0 + 1e-9, 1e308)),
    "rayleigh_mass": st.one_of(NOT_A_NUMBER, NOT_FINITE, _floats(-1e308, -1e-300)),
    "rayleigh_stiffness": st.one_of(NOT_A_NUMBER, NOT_FINITE, _floats(-1e308, -1e-300)),
    # alone, without its frequencies, any ratio is refused; so are frequencies without one
    "rayleigh_ratio": st.one_of(NOT_A_NUMBER, NOT_FINITE, _floats(-1e308, 1e308)),
    "rayleigh_hz": st.one_of(st.integers(), st.text(max_size=5),
                             st.lists(_floats(-1e6, 1e6), max_size=3)),
    "cycles": st.one_of(NOT_WHOLE, st.integers(-(2**63), 0), st.integers(10_001, INT64)),
    # without cycles any bound is refused (it bounds a steady-state run)
    "max_cycles": st.one_of(NOT_WHOLE, st.integers(-(2**63), INT64)),
    # without cycles even "sector" is refused (it is a mesh cycle)
    "stiffness": st.one_of(st.text(max_size=8).filter(lambda s: s != "tooth"), st.integers(),
                           st.booleans()),
    "bodies": st.one_of(st.text(max_size=8).filter(lambda s: s not in ("modal", "full")),
                        st.integers(), st.booleans()),
    # the FE model (the example's) refuses any teeth; without cycles any start but the static
    # one, any ramp (it needs a start from rest) and any history are refused, as a bad value
    # or for want of cycles; a name is no file in an empty folder
    "teeth": st.one_of(NOT_WHOLE, st.integers(-(2**63), INT64)),
    "start": st.one_of(st.text(max_size=8).filter(lambda s: s != "static"), st.integers(), st.booleans()),
    "ramp_cycles": st.one_of(NOT_A_NUMBER, NOT_FINITE, _floats(-1e308, 1e308)),
    "torque_history": st.one_of(st.text(max_size=8), st.integers(), st.floats(), st.booleans()),
    "torque_history_periodic": st.one_of(st.booleans(), st.integers(), st.text(max_size=5)),
}


def test_every_run_key_has_bad_values():
    assert set(BAD) == RUN_KEYS


@pytest.fixture
def fake(monkeypatch):
    def simulate(pair, case, progress=None):
        return fake_simulate(pair, case, progress)

    monkeypatch.setattr(runner, "load_simulate",
                        lambda model="fe": simulate if model == "fe" else runner.MODELS[model])


def _refused(capsys, folder: Path, argv: list[str], name: str) -> None:
    before = sorted(p.name for p in folder.iterdir())
    code = main([str(a) for a in argv])
    out = capsys.readouterr()
    assert code == 2, (argv, out.err)
    assert out.out == "" and out.err.count("\n") == 1 and "Traceback" not in out.err
    assert out.err.startswith("spurdyn: error: ") and name in out.err, (argv, out.err)
    assert sorted(p.name for p in folder.iterdir()) == before  # nothing written


@pytest.mark.slow
@SETTINGS
@given(data=st.data(), key=st.sampled_from(sorted(RUN_KEYS)))
def test_bad_run_values_are_refused_by_key(fake, capsys, data, key):
    value = data.draw(BAD[key], label=key)
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        path = case_file(folder, {key: value})
        _refused(capsys, folder, ["run", path, "--out", folder / "o", "--quiet"],
                 f"error: run.{key}: ")


@settings(max_examples=10, deadline=None, derandomize=True,
          suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(name=st.from_regex(r"[a-z][a-z_]{0,11}", fullmatch=True).filter(
    lambda k: k not in RUN_KEYS))
def test_unknown_run_keys_are_refused_by_key(fake, capsys, name):
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        path = case_file(folder, {name: 1})
        _refused(capsys, folder, ["run", path, "--out", folder / "o"],
                 f"error: run.{name}: unknown key")


def _text(strategy: st.SearchStrategy[Any]) -> st.SearchStrategy[str]:
    return strategy.map(lambda v: repr(v) if isinstance(v, float) else str(v))


#: Per ``spurdyn run`` option: values (as typed) that must be refused.
BAD_FLAGS: dict[str, st.SearchStrategy[str]] = {
    "--dt": _text(st.one_of(st.text(max_size=5).filter(lambda s: not _is_float(s)),
                            NOT_FINITE, NOT_POSITIVE, _floats(1e-6, 1e308),
                            _floats(1e-300, 1e-14))),
    "--speed-a": _text(st.one_of(NOT_FINITE, NOT_POSITIVE, _floats(1.2e6, 1e308),
                                 _floats(1e-300, 50.0))),
    "--speed-b": _text(st.one_of(NOT_FINITE, NOT_POSITIVE, _floats(2e6, 1e308))),
    "--torque": _text(st.one_of(NOT_FINITE, _floats(-1e308, -1e-300), _floats(1e5, 1e308))),
    "--angle": _text(st.one_of(NOT_FINITE, NOT_POSITIVE, _floats(21.6, 1e308))),
    "--save-every": _text(st.one_of(st.integers(-(2**70), 0), st.integers(10_000, 2**70),
                                    _floats(0.5, 1e9))),
    "--frames-every": _text(st.one_of(st.integers(-(2**70), -1), _floats(0.5, 1e9))),
    "--method": st.text(min_size=1, max_size=8).filter(lambda s: s not in ("paper", "pinned")),
    "--backend": st.text(min_size=1, max_size=8).filter(lambda s: s not in ("numba", "numpy")),
    "--mesh": st.one_of(st.text(max_size=6).filter(lambda s: "x" not in s.lower()),
                        st.tuples(st.integers(65, 10**6), st.integers(1, 40)).map(
                            lambda t: f"{t[0]}x{t[1]}"),
                        st.tuples(st.integers(-5, 0), st.integers(1, 40)).map(
                            lambda t: f"{t[0]}x{t[1]}")),
    "--jobs": _text(st.one_of(st.integers(-(2**40), 0), st.text(min_size=1, max_size=4).filter(
        lambda s: not s.strip().lstrip("+-").isdigit()))),
    "--row-grading": st.one_of(st.sampled_from(["0.5", "x", "true", "1e9"]),
                               _text(st.one_of(NOT_FINITE, _floats(-1e308, 1.0 - 1e-9),
                                               _floats(1000.0 + 1e-6, 1e308)))),
}


def _is_float(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


@SETTINGS
@given(data=st.data(), flag=st.sampled_from(sorted(BAD_FLAGS)))
def test_bad_options_are_refused_by_name(fake, capsys, data, flag):
    value = data.draw(BAD_FLAGS[flag], label=flag)
    case = "paper-all" if flag == "--jobs" else "paper-fig8"
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        _refused(capsys, folder, ["run", case, f"{flag}={value}", "--out", folder / "o"], flag)


# -- valid small cases -------------------------------------------------------------------

@pytest.mark.slow
@settings(max_examples=8, deadline=None, derandomize=True,
          suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow])
# valid torques: none (an unloaded run) or one whose deflection is above the rounding of
# positions (1.1e-7 N m on the paper's pair: smaller ones are refused, tests/test_careful_commands.py)
@given(speed=_floats(3000.0, 20000.0), torque=st.one_of(st.just(0.0), _floats(1e-3, 40.0)),
       angle=_floats(0.2, 1.0), save_every=st.integers(1, 3), frames_every=st.integers(0, 20),
       method=st.sampled_from(["paper"]), model=st.sampled_from(["fe", "lumped"]))
def test_valid_small_cases_run(fake, capsys, speed, torque, angle, save_every, frames_every,
                               method, model):
    # a file's keys its model does not read are refused by name: the example's FE keys
    # are left out of the lumped model's file
    unread = frozenset(MODEL_ENTRIES[model].unread)
    run = {k: v for k, v in {"speed_a_rpm": speed, "torque": torque, "angle_deg": angle,
                             "save_every": save_every, "frames_every": frames_every,
                             "method": method}.items() if k not in unread}
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        path = case_file(folder, run, drop=unread)
        code = main(["run", str(path), "--model", model, "--out", str(folder / "o"), "--quiet"])
        out = capsys.readouterr()
        assert code == 0, out.err
        summary = json.loads((folder / "o" / "summary.json").read_text())
        assert summary["status"] == "complete" and summary["samples"] >= 3
        assert sorted(p.name for p in folder.iterdir()) == ["o", "paper_fig8.toml"]


#: Per ``spurdyn sweep`` option: values (as typed) that must be refused before any
#: cluster is started.
BAD_SWEEP_FLAGS: dict[str, st.SearchStrategy[str]] = {
    "--rpm": st.one_of(
        st.text(max_size=6).filter(lambda s: not _is_float(s) and ":" not in s and "," not in s),
        _text(st.one_of(NOT_FINITE, NOT_POSITIVE, _floats(1.2e6, 1e308), _floats(1e-300, 50.0))),
        st.tuples(_floats(3000, 5000), _floats(1e-9, 1e-3)).map(
            lambda t: f"{t[0]!r}:{t[0] + 1e5!r}:{t[1]!r}")),   # far more than 10,000 points
    "--torque": _text(st.one_of(NOT_FINITE, _floats(-1e308, -1e-300), _floats(1e5, 1e308))),
    "--dt": _text(st.one_of(NOT_FINITE, NOT_POSITIVE, _floats(1e-6, 1e308))),
    "--jobs": _text(st.integers(-(2**40), 0)),
    "--row-grading": st.sampled_from(["0.5", "x", "true", "1e9", "nan"]),
    "--scheduler": st.text(max_size=12).filter(lambda s: not s.startswith(("tcp://", "tls://"))),
}


@settings(max_examples=20, deadline=None, derandomize=True,
          suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(data=st.data(), flag=st.sampled_from(sorted(BAD_SWEEP_FLAGS)))
def test_bad_sweep_options_are_refused_by_name(capsys, data, flag):
    value = data.draw(BAD_SWEEP_FLAGS[flag], label=flag)
    rpm = [] if flag == "--rpm" else ["--rpm", "4000,6000"]
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        _refused(capsys, folder, ["sweep", "paper-fig8", f"{flag}={value}", *rpm,
                                  "--out", folder / "o", "--model", "lumped"], flag)
