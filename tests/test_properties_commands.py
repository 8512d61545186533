"""Every command that takes a case file holds to what ``run`` holds to (Hypothesis).

``run``, ``sweep``, ``info``, ``mesh`` and ``stiffness`` are each driven with generated bad
case files (text that is not TOML, a table that is not one, an unknown key, a gear key with
a value beyond its meaning) and bad options (a mesh, a grading, a torque), and each answers
with exit status 2 and one line naming the key or option written, no traceback and nothing
written. The FE solver is the synthetic one (``test_properties.fake``); a refusal comes
before any solver, cluster or picture. Example counts are bounded to keep the suite's budget.
"""

from __future__ import annotations

import tempfile
import tomllib
from pathlib import Path
from typing import Any

from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from test_properties import EXAMPLE, NOT_A_NUMBER, _floats, _refused, fake, toml_value  # noqa: F401

SETTINGS = settings(max_examples=30, deadline=None, derandomize=True,
                    suppress_health_check=[HealthCheck.function_scoped_fixture,
                                           HealthCheck.too_slow])

#: Each command after its CASE: what it needs beside it (its output in the folder).
COMMANDS: dict[str, list[str]] = {
    "run": ["--out", "o", "--quiet"],
    "sweep": ["--rpm", "4000", "--model", "lumped", "--out", "o", "--quiet"],
    "info": [],
    "mesh": ["--png", "m.png"],
    "stiffness": ["--png", "s.png"],
}
COMMAND = st.sampled_from(sorted(COMMANDS))

#: Per gear key: values beyond its meaning (the paper's pair, module 3.175 mm).
BAD_GEAR: dict[str, st.SearchStrategy[Any]] = {
    "teeth": st.one_of(NOT_A_NUMBER, st.integers(-(2**63), 0), st.integers(1001, 2**63 - 1),
                       _floats(-1e9, 1e9).filter(lambda v: v != int(v))),
    "pitch_radius": st.one_of(NOT_A_NUMBER, _floats(-1e308, 0.0), _floats(2.0, 1e308)),
    "pressure_angle_deg": st.one_of(NOT_A_NUMBER, _floats(-1e308, 11.9), _floats(35.1, 1e308)),
    "face_width": st.one_of(NOT_A_NUMBER, _floats(-1e308, 0.0), _floats(0.7, 1e308)),
    "disk_inertia": st.one_of(NOT_A_NUMBER, _floats(-1e308, 0.0), _floats(1e-300, 1e-8),
                              _floats(1e3, 1e308)),
    "tip_radius": st.one_of(NOT_A_NUMBER, _floats(-1e308, 0.0444), _floats(0.06, 1e308)),
}

#: The top-level entries of a case file replaced by something that is not their table.
NOT_A_TABLE = st.one_of(st.integers(), st.text(max_size=5), st.booleans(),
                        st.lists(st.integers(-3, 3), max_size=2))


def _with_gear_value(key: str, value: Any) -> str:
    lines = EXAMPLE.read_text().splitlines()
    start = lines.index("[gear_a]")
    end = lines.index("[gear_a.material]")
    body = [ln for ln in lines[start + 1:end] if ln.split("=", 1)[0].strip() != key]
    return "\n".join(lines[:start + 1] + [f"{key} = {toml_value(value)}"] + body
                     + lines[end:]) + "\n"


def _with_top(key: str, value: Any) -> str:
    """The example with ``key = value`` at its top, its own ``[key]`` table (if any) left out."""
    text = EXAMPLE.read_text()
    kept, skip = [], False
    for line in text.splitlines():
        if line.startswith("["):
            skip = line.strip("[] ").split(".")[0] == key
        if not skip:
            kept.append(line)
    return f"{key} = {toml_value(value)}\n" + "\n".join(kept) + "\n"


def _drive(capsys, command: str, text: str, name: str, options: list[str] = ()) -> None:
    """Run ``command`` on a case file holding ``text``; it must be refused naming ``name``."""
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        path = folder / "case.toml"
        path.write_text(text, encoding="utf-8")
        argv = [command, path, *options,
                *[str(folder / a) if a in ("o", "m.png", "s.png") else a for a in COMMANDS[command]]]
        _refused(capsys, folder, argv, name)


def _not_toml(text: str) -> bool:
    try:
        tomllib.loads(text)
    except (tomllib.TOMLDecodeError, UnicodeError):
        return True
    return False


@SETTINGS
@given(command=COMMAND, text=st.text(st.characters(blacklist_categories=("Cs",)),
                                       max_size=40).filter(_not_toml))
def test_text_that_is_not_toml_names_the_file(fake, capsys, command, text):
    _drive(capsys, command, text, "case.toml: is not valid TOML")


@SETTINGS
@given(command=COMMAND, key=st.sampled_from(["run", "model", "gear_a", "pair", "mesh"]),
       value=NOT_A_TABLE)
def test_an_entry_that_is_not_a_table_is_named(fake, capsys, command, key, value):
    _drive(capsys, command, _with_top(key, value), f"error: {key}")


def _known(where: str) -> set[str]:
    """The keys a table of a case file may hold ("" the top level)."""
    from spurdyn.case import GEAR_KEYS, MESH_KEYS, PAIR_KEYS, RUN_KEYS, TOP_KEYS

    return {"": TOP_KEYS, "gear_a": GEAR_KEYS, "pair": PAIR_KEYS, "mesh": MESH_KEYS,
            "run": RUN_KEYS, "model": {"kind"}}[where]


@SETTINGS
@given(command=COMMAND, name=st.from_regex(r"[a-z][a-z_]{0,11}", fullmatch=True),
       where=st.sampled_from(["", "gear_a", "pair", "mesh", "run", "model"]))
def test_an_unknown_key_is_named(fake, capsys, command, name, where):
    assume(name not in _known(where))
    text = EXAMPLE.read_text()
    text = (f"{name} = 1\n" + text if where == "" else
            text.replace(f"[{where}]\n", f"[{where}]\n{name} = 1\n", 1))
    _drive(capsys, command, text, f"error: {where + '.' if where else ''}{name}: unknown key")


@SETTINGS
@given(data=st.data(), command=COMMAND, key=st.sampled_from(sorted(BAD_GEAR)))
def test_a_gear_value_beyond_its_meaning_is_named(fake, capsys, data, command, key):
    value = data.draw(BAD_GEAR[key], label=key)
    _drive(capsys, command, _with_gear_value(key, value), f"error: gear_a.{key}: ")


#: Options of the commands that read a pair, with values beyond their meaning.
BAD_OPTIONS: dict[str, st.SearchStrategy[str]] = {
    "--mesh": st.one_of(st.text(max_size=6).filter(lambda s: "x" not in s.lower()),
                        st.tuples(st.integers(65, 10**6), st.integers(1, 40)).map(
                            lambda t: f"{t[0]}x{t[1]}"),
                        st.tuples(st.integers(1, 8), st.integers(257, 10**6)).map(
                            lambda t: f"{t[0]}x{t[1]}")),
    "--grading": st.one_of(_floats(-1e308, 1.0 - 1e-9), _floats(1e3, 1e308),
                           st.sampled_from(["nan", "inf", "x"])),
}
#: Options of the commands that load the pair with a torque.
BAD_TORQUES = st.one_of(_floats(1e5, 1e308), st.sampled_from(["nan", "inf", "-1", "x"]))


@SETTINGS
@given(data=st.data(), command=COMMAND, flag=st.sampled_from(sorted(BAD_OPTIONS)))
def test_a_bad_option_is_named(fake, capsys, data, command, flag):
    value = data.draw(BAD_OPTIONS[flag], label=flag)
    _drive(capsys, command, EXAMPLE.read_text(), flag, [f"{flag}={value}"])


@SETTINGS
@given(command=st.sampled_from(["run", "info", "stiffness"]), value=BAD_TORQUES)
def test_a_torque_beyond_the_elastic_tooth_is_named(fake, capsys, command, value):
    text = value if isinstance(value, str) else repr(value)
    options = [f"--torque={text}"] + (["--contact", "hertz"] if command == "info" else [])
    _drive(capsys, command, EXAMPLE.read_text(), "--torque", options)
