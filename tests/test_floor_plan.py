"""The floor plan (docs/architecture.md): floors that stack, and room for what comes.

- Every module imports only modules of its own floor or of lower floors; upward imports
  are allowed only inside functions of a package facade (``__init__.py``), which import
  lazily. No circle of imports between modules, lazy ones included.
- Today's pair built through the interfaces later models extend (gear bodies carrying a
  tuple of teeth, a tuple of contact pairs, a registry of steppers by integrator) is the
  pair :func:`~spurdyn.model.system.build_system` builds, and steps identically.
"""

from __future__ import annotations

import ast
import math
from pathlib import Path

import numpy as np
import pytest

from spurdyn.errors import InputError
from spurdyn.geometry.placement import mesh_angles, to_world_a, to_world_b
from spurdyn.geometry.presets import PAPER_TORQUE, paper_pair
from spurdyn.mesh.tooth import tooth_mesh
from spurdyn.model.system import (
    SENSE, FlankPair, assemble_system, build_system, gear_body, tooth_body,
)
from spurdyn.settings import RPM, RunSettings
from spurdyn.solvers.layout import CP, HISTORY, NCOL, H, HistoryRow
from spurdyn.solvers.paper.dynamics_numpy import torques
from spurdyn.solvers.loop import STEPPERS, make_stepper

PACKAGE = Path(__file__).resolve().parents[1] / "src" / "spurdyn"

#: The floors, lowest first. A top-level module is its own floor; a package's modules share it.
FLOORS = (
    ("errors", "version", "result", "jit", "linking", "signals", "lazy", "store", "history"),
    ("diagnostics",),
    ("fem",),
    ("geometry",),
    ("iso6336",),
    ("energy",),
    ("mesh",),
    ("fracture",),
    ("settings",),
    ("model",),
    ("contact",),
    ("sector",),
    ("solvers",),
    ("lumped",),
    ("case",),
    ("results",),
    ("simulators",),
    ("sweep",),
    ("cli",),
    ("__init__", "__main__"),
)
LEVEL = {name: i for i, names in enumerate(FLOORS) for name in names}


def _unit(path: Path) -> str:
    """The floor name of a source file: its top-level package or module."""
    rel = path.relative_to(PACKAGE)
    return rel.parts[0] if len(rel.parts) > 1 else rel.stem


def _imports(path: Path) -> list[tuple[str, bool]]:
    """``(spurdyn module imported, at top level?)`` for every absolute import in ``path``
    (relative ones are refused by :func:`test_imports_are_absolute`)."""
    tree = ast.parse(path.read_text())
    top = {id(n) for n in tree.body}
    # imports inside ``if TYPE_CHECKING:`` blocks are for annotations only
    typing_only = set()
    for node in tree.body:
        if isinstance(node, ast.If) and "TYPE_CHECKING" in ast.unparse(node.test):
            typing_only |= {id(n) for n in ast.walk(node)}
    out = []
    for node in ast.walk(tree):
        if id(node) in typing_only:
            continue
        names = []
        if isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            # ``from spurdyn.geometry import involute`` imports the submodule
            subs = [f"{node.module}.{a.name}" for a in node.names]
            names = [n for n in subs if _is_module(n)] or [node.module]
        elif isinstance(node, ast.Import):
            names = [a.name for a in node.names]
        for name in names:
            if name == "spurdyn" or name.startswith("spurdyn."):
                out.append((name, id(node) in top))
    return out


def _is_module(name: str) -> bool:
    base = PACKAGE.joinpath(*name.split(".")[1:])
    return base.with_suffix(".py").is_file() or (base / "__init__.py").is_file()


def _sources() -> list[Path]:
    return sorted(PACKAGE.rglob("*.py"))


def test_every_module_is_on_a_floor():
    assert sorted({_unit(p) for p in _sources()} - set(LEVEL)) == []


@pytest.mark.parametrize("path", _sources(), ids=lambda p: str(p.relative_to(PACKAGE)))
def test_imports_point_down(path):
    here = _unit(path)
    facade = path.name == "__init__.py"
    for name, at_top in _imports(path):
        parts = name.split(".")
        there = parts[1] if len(parts) > 1 else "__init__"
        if LEVEL[there] == LEVEL[here]:
            continue                      # its own package or floor (circles: the next test)
        if not at_top and facade:
            continue                      # a lazy facade may reach up
        assert LEVEL[there] < LEVEL[here], (
            f"{path.relative_to(PACKAGE)} imports {name} ({'top level' if at_top else 'in a function'}),"
            f" floor {there} is not below {here}")


def test_imports_are_absolute():
    """No relative import (``from . import x``) anywhere: the floor tests above read only
    absolute ones, so a relative import would pass them unseen."""
    relative = [f"{path.relative_to(PACKAGE)}:{node.lineno}: {ast.unparse(node)}"
                for path in _sources() for node in ast.walk(ast.parse(path.read_text()))
                if isinstance(node, ast.ImportFrom) and node.level > 0]
    assert relative == [], "relative imports: " + "; ".join(relative)


def test_no_circles_between_modules():
    """No cycle in the graph of imports between modules, lazy ones included (a package
    facade's lazy imports aside)."""
    def module(path: Path) -> str:
        rel = path.relative_to(PACKAGE).with_suffix("")
        parts = ["spurdyn", *rel.parts]
        return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)

    modules = {module(p): p for p in _sources()}
    graph = {m: sorted({n for n, top in _imports(p)
                        if n in modules and n != m and (top or p.name != "__init__.py")})
             for m, p in modules.items()}
    state: dict[str, int] = {}
    stack: list[str] = []

    def visit(m: str) -> None:
        state[m] = 1
        stack.append(m)
        for n in graph[m]:
            if state.get(n) == 1:
                cycle = stack[stack.index(n):] + [n]
                raise AssertionError("import circle: " + " -> ".join(cycle))
            if n not in state:
                visit(n)
        stack.pop()
        state[m] = 2

    for m in graph:
        if m not in state:
            visit(m)


# -- room for what comes ------------------------------------------------------------------

@pytest.fixture(scope="module")
def today():
    """The paper's pair, built by ``build_system`` and built through the interfaces."""
    pair = paper_pair()
    settings = RunSettings(speed_a=4000 * RPM, speed_b=4000 * RPM, torque=PAPER_TORQUE)
    built = build_system(pair, settings)
    theta_a, theta_b = mesh_angles(pair, pair.start_roll_a)
    ca, cb = np.zeros(2), np.array([0.0, pair.centre_distance])
    meshes = (tooth_mesh(pair.gear_a, settings.nx, settings.ny),
              tooth_mesh(pair.gear_b, settings.nx, settings.ny))
    tooth_a = tooth_body(pair.gear_a, meshes[0], to_world_a(meshes[0].nodes, theta_a), ca,
                         -theta_a, settings.n_spline)
    tooth_b = tooth_body(pair.gear_b, meshes[1], to_world_b(meshes[1].nodes, theta_b,
                                                            pair.centre_distance),
                         cb, math.pi + theta_b, settings.n_spline)
    gears = (gear_body(pair.gear_a, (tooth_a,), ca, float(SENSE[0])),
             gear_body(pair.gear_b, (tooth_b,), cb, float(SENSE[1])))
    by_parts = assemble_system(pair, gears, (theta_a, theta_b), contacts=(FlankPair(0, 0, "drive"),))
    return pair, settings, built, by_parts


def test_todays_pair_through_the_interfaces_is_the_built_pair(today):
    _, _, built, by_parts = today
    assert by_parts.offsets == built.offsets and by_parts.n_x == built.n_x
    assert len(by_parts.gears[0].teeth) == len(by_parts.contacts) == 1
    for g in range(2):
        a, b = built.gears[g], by_parts.gears[g]
        assert (a.sense, a.inertia, a.base_radius) == (b.sense, b.inertia, b.base_radius)
        ta, tb = a.tooth, b.tooth
        assert np.array_equal(ta.X, tb.X) and np.array_equal(ta.mass, tb.mass)
        assert (ta.stiffness != tb.stiffness).nnz == 0
        assert np.array_equal(ta.flank.data_delta, tb.flank.data_delta)
    fa, fb = by_parts.flanks(by_parts.contacts[0])
    assert fa is by_parts.gears[0].tooth.flank and fb is by_parts.gears[1].tooth.flank


@pytest.mark.parametrize("backend, steps", [("numba", 200), ("numpy", 5)])
def test_steppers_iterate_the_described_system_identically(today, backend, steps):
    """Every registered stepper runs the system described through the interfaces with the
    very same steps (to the last bit) as the built one."""
    pair, settings, built, by_parts = today
    settings = settings.with_(backend=backend)
    assert (settings.integrator, backend) in STEPPERS
    rows = []
    for system in (built, by_parts):
        stepper = make_stepper(system, settings)
        out = np.empty((steps + 1, NCOL))
        done, written, reason = stepper.advance(steps, math.inf, 1, out, 0, [])
        assert (done, written, reason) == (steps, steps, "")
        rows.append(out[:written])
    assert np.array_equal(rows[0], rows[1])


def test_the_paper_method_constrains_one_tooth_pair(today):
    """A gear of two teeth and a second contact pair are data the system carries; the paper's
    one-tooth method says it cannot run them instead of running something else."""
    pair, settings, built, _ = today
    two = gear_body(pair.gear_a, (built.gears[0].tooth, built.gears[0].tooth),
                    built.gears[0].centre, built.gears[0].sense)
    assert two.n_u == 2 * built.gears[0].n_u
    assert np.array_equal(two.mass, np.concatenate([built.gears[0].mass] * 2))
    with pytest.raises(ValueError, match="reads exactly one"):
        two.flank
    doubled = assemble_system(pair, built.gears, built.theta0, contacts=(FlankPair(), FlankPair()))
    assert doubled.n_x == built.n_x + 1
    with pytest.raises(ValueError, match="constrains one flank pair"):
        make_stepper(doubled, settings)


def test_an_unknown_integrator_is_refused_naming_it():
    with pytest.raises(InputError) as err:
        RunSettings(speed_a=1.0, speed_b=1.0, torque=1.0, integrator="euler")
    assert err.value.field == "integrator"


# -- the history row, declared once ----------------------------------------------------------

def _history_row_calls() -> dict[str, list[ast.Call]]:
    """``{module: [HistoryRow(...) calls]}`` over the package (the modules that build one)."""
    found: dict[str, list[ast.Call]] = {}
    for path in _sources():
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.Call) and ast.unparse(node.func).endswith("HistoryRow"):
                found.setdefault(str(path.relative_to(PACKAGE).as_posix()), []).append(node)
    return found


def test_every_history_writer_builds_the_one_declared_row():
    """The history's columns are declared once (``layout.HISTORY``); ``HistoryRow`` is that
    declaration, its field order the column order. Each writer (the compiled ``write_row``
    and the NumPy steppers' ``row``) builds one naming every column, so a column added to
    the declaration and not written fails here (and in the writer, where the constructor
    misses it); no module writes a row column by column any more."""
    assert HistoryRow._fields == HISTORY and len(HistoryRow._fields) == NCOL
    assert tuple(H) == tuple(range(NCOL)) and H._fields == HISTORY
    calls = _history_row_calls()
    assert {"solvers/paper/step_compiled.py", "solvers/paper/stepper_numpy.py"} <= set(calls)
    assert any(m.startswith("solvers/implicit/") for m in calls)
    for module, nodes in calls.items():
        for node in nodes:
            names = [k.arg for k in node.keywords]
            assert not node.args and sorted(names) == sorted(HISTORY), (
                f"{module}:{node.lineno} builds a HistoryRow of {names}, not of HISTORY")
    by_column = [f"{path.relative_to(PACKAGE)}:{node.lineno}" for path in _sources()
                 for node in ast.walk(ast.parse(path.read_text()))
                 if isinstance(node, ast.Subscript) and isinstance(node.ctx, ast.Store)
                 and isinstance(node.slice, ast.Attribute) and ast.unparse(node.slice.value) == "H"]
    assert by_column == [], "rows written column by column: " + "; ".join(by_column)


def _contact_columns(stepper) -> dict[str, float]:
    """The contact columns of a stepper's state, wherever the stepper keeps them."""
    if hasattr(stepper, "contact_columns"):
        values = stepper.contact_columns()
    elif hasattr(stepper.state, "cpar"):
        cp = stepper.state.cpar
        values = (cp[CP.s], cp[CP.alpha], cp[CP.beta], cp[CP.mode], cp[CP.half_width])
    else:
        c = stepper.state.contact
        values = (c.s, c.alpha, c.beta, c.mode, c.half_width)
    return dict(zip(("s", "alpha", "beta", "mode", "half_width"), values))


@pytest.mark.slow
@pytest.mark.parametrize("integrator, backend", sorted(STEPPERS))
def test_every_history_writer_fills_each_column_with_its_own_value(integrator, backend):
    """Every registered stepper's history rows, written by its writer, hold column by
    column (by name) what its state says: the value of each column is told apart from the
    others (distributed contact under load, so none of the state's columns is 0 by chance),
    and none is left unwritten (the rows start as NaN)."""
    pair = paper_pair()
    settings = RunSettings(speed_a=4000 * RPM, speed_b=4000 * RPM, torque=PAPER_TORQUE,
                           contact="hertz", backend=backend, integrator=integrator)
    if integrator == "implicit":
        settings = settings.with_(dt=6.6e-7)
    system = build_system(pair, settings)
    stepper = make_stepper(system, settings)
    steps = 3
    out = np.full((steps + 1, NCOL), np.nan)
    assert stepper.advance(steps, math.inf, 1, out, 0, []) == (steps, steps, "")
    assert not np.isnan(out[:steps]).any()
    assert np.array_equal(out[steps - 1], stepper.row())
    res, its = stepper.residual, stepper.iterations
    tau = torques(system, settings.torque, stepper.theta)
    expected = dict(
        t=stepper.t, theta_a=stepper.theta[0], theta_b=stepper.theta[1],
        omega_a=stepper.omega[0], omega_b=stepper.omega[1], tau_a=tau[0], tau_b=tau[1],
        p=stepper.x[-1], res1=res[0], it1=its[0], **_contact_columns(stepper),
        # the implicit scheme has no velocity or acceleration stage: those columns are 0
        **(dict(res2=0.0, res3=0.0, it2=0, it3=0) if integrator == "implicit" else
           dict(res2=res[1], res3=res[2], it2=its[1], it3=its[2])))
    assert set(expected) == set(HISTORY)
    row = dict(zip(HISTORY, out[steps - 1]))
    assert row == pytest.approx(expected, rel=0, abs=0)
    # the columns the state sets tell each other apart (mode and the iteration counts may
    # coincide, the displacement stage's residual is the error of the gap the constraint
    # holds, and the implicit scheme's unused columns are 0)
    told = [v for k, v in expected.items()
            if k not in ("mode", "it1", "it2", "it3", "res1", "res2", "res3")]
    assert len(set(told)) == len(told), expected
