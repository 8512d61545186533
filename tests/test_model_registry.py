"""Models that own their rules (issue 33, point 3): each entry of
:data:`spurdyn.simulators.MODELS` reads the settings declared for it beside each field of
:class:`~spurdyn.settings.RunSettings` and refuses the others in one line naming the key;
no module outside the registry asks a model's name what it can do; the default step, the
size estimate and the sweep's hash extras come from the entry."""

from __future__ import annotations

import ast
import math
from pathlib import Path

import pytest

from spurdyn.errors import InputError
from spurdyn.geometry.presets import paper_pair
from spurdyn.geometry.fault import Fault
from spurdyn.settings import (MODEL_NAMES, RPM, Bearing, RunSettings, TorqueHistory, setting_keys,
                              settings_read_by)
from spurdyn.simulators import DEFAULTS, MODELS

PACKAGE = Path(__file__).resolve().parents[1] / "src" / "spurdyn"
PAIR = paper_pair()
BASE = dict(speed_a=4000 * RPM, speed_b=4000 * RPM, torque=22.25)

#: A valid value other than the default for each setting (``method`` has one value only).
OTHER = {
    "nx": 3, "ny": 10, "grading": 2.0, "damping_ratio": 0.05, "name": "other",
    "dt": 1e-7, "angle": 0.1, "row_grading": 2.0, "n_spline": 33, "contact": "point",
    "save_every": 2, "tol_disp": 1e-11, "max_iter": 50, "accel_levels": 2,
    "integrator": "implicit", "frames_every": 7, "keep_theta_term": False, "backend": "numpy",
    "rho_inf": 0.5, "rayleigh_mass": 10.0, "rayleigh_stiffness": 1e-8, "cycles": 2,
    "max_cycles": 3, "teeth": 5, "start": "rest", "ramp_cycles": 2.0,
    "torque_history": TorqueHistory((0.0, 1.0), (1.0, 1.0)), "start_state": (0.0, 0.0),
    "stiffness": "sector", "bodies": "full", "back_flanks": True,
    "faults": (Fault("a", 1, "missing"),), "bearings": (Bearing(1e8, 1e3), None),
}
#: What a setting needs beside it (RunSettings refuses it alone).
COMPANIONS = {"max_cycles": {"cycles": 2}, "start": {"cycles": 2}, "torque_history": {"cycles": 2},
              "ramp_cycles": {"start": "rest", "cycles": 2}, "stiffness": {"cycles": 2}}
UNREAD = [(m, name) for m in MODEL_NAMES for name in MODELS[m].unread if name in OTHER]


def _given(name: str, value: object = None) -> RunSettings:
    change = {**COMPANIONS.get(name, {}), name: OTHER[name] if value is None else value}
    return RunSettings(**BASE, **change)


def test_every_setting_has_a_sample_and_the_registry_follows_the_names():
    assert tuple(MODELS) == MODEL_NAMES
    assert set(OTHER) | {"speed_a", "speed_b", "torque", "method"} == set(DEFAULTS)
    for m in MODEL_NAMES:
        reads = settings_read_by(m)
        assert MODELS[m].reads == reads and not set(reads) & set(MODELS[m].unread)
        assert {"speed_a", "speed_b", "torque"} <= set(reads)


@pytest.mark.parametrize("model,name", UNREAD, ids=[f"{m}-{n}" for m, n in UNREAD])
def test_each_model_refuses_what_it_does_not_read(model, name):
    """Given in Python (a value other than the default), and on the command line (the key
    in the labels): one refusal naming the key the user wrote."""
    entry = MODELS[model]
    value = OTHER[name]
    if entry.fixed.get(name) == value:          # what the model fixes is no refusal...
        entry.refuse(_given(name), None, PAIR)
        value = DEFAULTS[name]                  # ...another value given on the command line is
    else:
        with pytest.raises(InputError) as err:
            entry.refuse(_given(name), None, PAIR)
        # a setting that needs cycles beside it: the FE model names the cycles first
        assert err.value.field in (name, *COMPANIONS.get(name, {}))
        assert "\n" not in str(err.value)
    keys = setting_keys(name)
    if not keys:                                # no case key: only given in Python
        return
    flag = "--" + keys[0].split(".")[-1].replace("_", "-")      # a table of its own ("fault") too
    labels = {keys[0]: flag}
    with pytest.raises(InputError) as err:
        entry.refuse(_given(name, value), labels, PAIR)
    assert err.value.field in (flag, *(setting_keys(c)[0] for c in COMPANIONS.get(name, {}))), err.value
    # not given on the command line (a case file written for another model): no refusal,
    # unless the model refuses it wherever it comes from
    if name in entry.strict and value != DEFAULTS[name]:
        with pytest.raises(InputError):
            entry.refuse(_given(name, value), {}, PAIR)
    elif name not in COMPANIONS:
        entry.refuse(_given(name, value), {}, PAIR)


def test_a_sector_run_of_what_it_reads_only_is_taken():
    settings = RunSettings(**BASE, cycles=2, max_cycles=3, bodies="full", back_flanks=True,
                           backend="numpy", rho_inf=0.9, rayleigh_mass=0.0, damping_ratio=0.05,
                           nx=3, ny=10, grading=2.0, start="rest", ramp_cycles=1.5)
    MODELS["sector"].refuse(settings, None, PAIR)
    MODELS["sector"].refuse(settings.with_(integrator="implicit", contact="hertz"), None, PAIR)


def test_the_existing_refusals_keep_their_words():
    with pytest.raises(InputError, match="sets its own step of accuracy") as err:
        MODELS["sector"].refuse(_given("dt"), {"run.dt": "--dt"}, PAIR)
    assert err.value.field == "--dt"
    with pytest.raises(InputError, match="the paper's RK4 is undamped") as err:
        MODELS["fe"].refuse(RunSettings(**BASE, damping_ratio=0.05), {"run.damping_ratio": "--damping"})
    assert err.value.field == "--damping"
    with pytest.raises(InputError, match="the paper's RK4 is undamped") as err:
        MODELS["fe"](PAIR, RunSettings(**BASE, rayleigh_stiffness=1e-8))   # through the registry
    assert err.value.field == "run.rayleigh_stiffness"


def _model_names_asked(path: Path) -> list[str]:
    """``model == "..."``-like comparisons in a source file (a name or attribute ``model``
    against a string or a tuple of strings)."""
    def is_model(node: ast.AST) -> bool:
        return (isinstance(node, ast.Name) and node.id == "model") or \
               (isinstance(node, ast.Attribute) and node.attr == "model")

    def is_name(node: ast.AST) -> bool:
        return (isinstance(node, ast.Constant) and isinstance(node.value, str)) or \
               (isinstance(node, (ast.Tuple, ast.List, ast.Set)) and all(map(is_name, node.elts)))

    found = []
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Compare):
            sides = [node.left, *node.comparators]
            if any(map(is_model, sides)) and any(map(is_name, sides)):
                found.append(f"{path.relative_to(PACKAGE)}:{node.lineno}: {ast.unparse(node)}")
    return found


def test_no_model_name_is_asked_outside_the_registry():
    found = [hit for path in sorted(PACKAGE.rglob("*.py")) if path.name != "simulators.py"
             or path.parent != PACKAGE for hit in _model_names_asked(path)]
    assert found == []
    text = "\n".join(p.read_text() for p in PACKAGE.rglob("*.py") if p != PACKAGE / "simulators.py")
    assert 'model == "' not in text and 'model != "' not in text


def test_the_default_step_comes_from_the_entry(tmp_path):
    from spurdyn.case import resolve_cases
    from spurdyn.solvers.check import default_dt, stable_step
    from spurdyn.model.system import system_for

    examples = PACKAGE.parents[1] / "examples"
    overrides: dict[str, object] = {}       # a file that gives no dt
    case = resolve_cases(str(examples / "pinion_23_47.toml"), overrides, {})[0]
    assert case.run.dt == MODELS["fe"].default_step(case.run, case.pair)
    system = system_for(case.pair, case.run.nx, case.run.ny, case.run.n_spline, case.run.grading,
                        case.run.row_grading)
    assert case.run.dt == default_dt(stable_step(system))
    implicit = resolve_cases(str(examples / "pinion_23_47.toml"),
                             {**overrides, "run.integrator": "implicit"}, {})[0]
    assert implicit.run.dt == MODELS["fe"].default_step(implicit.run, implicit.pair) != case.run.dt
    # the sector model's own: a whole number of steps per mesh cycle, whatever dt says
    run = RunSettings(**BASE, cycles=1)
    h = MODELS["sector"].default_step(run, PAIR)
    period = 2.0 * math.pi / (PAIR.gear_a.teeth * run.speed_a)
    assert period / h == pytest.approx(round(period / h), abs=1e-9)
    assert MODELS["sector"].default_step(run.with_(dt=1e-5), PAIR) == h


def test_the_size_and_the_hash_extras_are_the_entries():
    from types import SimpleNamespace

    run = RunSettings(**BASE, cycles=2)
    case = SimpleNamespace(pair=PAIR, run=run, name="c")
    sector = MODELS["sector"].size(case)
    assert sector == MODELS["sector"].size(SimpleNamespace(pair=PAIR, run=run.with_(dt=1e-9), name="c"))
    assert sector.sampling == "cycles" and sector.steps_capped and sector.frame_bytes == 0
    fe = MODELS["fe"].size(SimpleNamespace(pair=PAIR, run=RunSettings(**BASE), name="c"))
    assert fe.steps_capped and fe.frame_bytes > 0
    assert "sector_revision" in MODELS["sector"].hash_extras(run)
    assert MODELS["lumped"].hash_extras(run) == MODELS["fe"].hash_extras(run) == {"cycles_limit": run.cycles_limit}


@pytest.mark.slow
def test_a_sector_run_through_the_api_takes_no_dt():
    import spurdyn
    from spurdyn.solvers.check import run_settings

    s = run_settings(PAIR, 20000 * RPM, 22.25, cycles=1, max_cycles=1, damping_ratio=0.05,
                     backend="numpy", nx=2, ny=8, model="sector")
    assert s.dt == DEFAULTS["dt"]
    with pytest.raises(InputError) as err:
        spurdyn.simulate(PAIR, s.with_(dt=1e-6), model="sector")
    assert err.value.field == "dt"
    result = spurdyn.simulate(PAIR, s, model="sector")
    steps = result.time[1:] - result.time[:-1]
    assert steps.mean() == pytest.approx(MODELS["sector"].default_step(s, PAIR), rel=1e-12)
