"""The pictures of a steady-state run of several tooth pairs (issue 35, point 5): the last
mesh cycle's pair forces beside the quasi-static ones, the transmission error and its mesh
harmonics, each tooth's root stress, and mesh.png's title and legend; on synthetic runs
shaped like the sector model's, whose figures are known."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
import xarray as xr

from spurdyn.result import Result
from spurdyn.results.cycle_plot import (
    HARMONICS, _te_spectra, harmonic_amplitudes, mesh_cycle_figure, transmission_error_figure,
)
from spurdyn.results.io import result_to_dataset, write_run
from spurdyn.results.mesh_plot import mesh_figure, plot_pair_pictures
from spurdyn.results.teeth_stress_plot import teeth_stress_figure
from spurdyn.solvers.steady import cycle_figures, steady_record
from run_helpers import PNG_MAGIC, short_case  # noqa: F401 (short_case: a fixture)

Z = 23
PITCH = 2.0 * math.pi / Z
PER = 64             # samples a mesh cycle
PERIOD = 1e-3        # s
START = 0.25         # driver's roll at the start of the path (rad)
LENGTH = 1.5 * PITCH  # the path's roll span: contact ratio 1.5
TE_AMPS = (1e-6, 0.0, 0.3e-6)   # the dynamic TE's harmonics 1..3 (m)


def tooth_force(s):
    """A tooth's quasi-static force along its path (roll ``s`` from its start): half the
    load where two pairs share it, all of it in the single-contact zone."""
    s = np.asarray(s, float)
    single = (s > 0.5 * PITCH) & (s < PITCH)
    return np.where((s >= 0) & (s <= LENGTH), np.where(single, 1000.0, 500.0), 0.0)


def sector_like(cycles_done: int, *, asked: int = 5, settled: bool | None = None,
                static: bool = True, te: bool = True) -> Result:
    """A run of ``cycles_done`` mesh cycles at constant speed: each tooth's force its
    quasi-static one with a ripple, the TE of :data:`TE_AMPS` about 5 um."""
    n = cycles_done * PER + 1
    t = np.arange(n) * (PERIOD / PER)
    phase = t / PERIOD
    theta_a = PITCH * phase
    teeth = np.arange(-cycles_done, 2)
    s = theta_a[:, None] + teeth[None, :] * PITCH
    force = tooth_force(s) * (1.0 + 0.1 * np.sin(2 * math.pi * 4 * phase))[:, None]
    roll = np.where((s >= -0.05) & (s <= LENGTH + 0.05), START + s, np.nan)
    dyn_te = 5e-6 + sum(a * np.cos(2 * math.pi * (h + 1) * phase) for h, a in enumerate(TE_AMPS))
    mesh = force.sum(axis=1)
    fig = cycle_figures(t, mesh, dyn_te, PER, asked, max(asked, cycles_done))
    steady = steady_record(fig, PERIOD, 1000.0, 1e8)
    if settled is not None:
        steady["settled"] = settled
    info = {"model": "sector", "n_dof": 100, "damping_ratio": 0.05, "pair_teeth": teeth.tolist(),
            "driver": "a", "steady": steady, "damping_ratio_source": "model default",
            # what every sector run's record holds beside (docs/summary.md)
            "start": "static", "torque_history": None, "back_flanks": False, "backlash_normal_m": 0.0,
            "rayleigh": [0.0, 1e-7], "rayleigh_default": True}
    if static:
        rolls = START + PITCH * np.arange(21) / 20
        pairs = np.column_stack([tooth_force(rolls - START + j * PITCH) for j in (0, 1)])
        pairs[-1] = (1000.0, 0.0)   # the last position: the end of the cycle before the next pair enters
        info["static_cycle"] = {
            "roll": rolls, "force": pairs,
            "transmission_error": 5e-6 + 1e-6 * np.cos(2 * math.pi * np.arange(21) / 20)}
    z = np.zeros((n, 2))
    return Result(time=t, angle=theta_a, contact_force=force.max(axis=1), gap=np.zeros(n),
                  roll=z, theta=np.column_stack([theta_a, theta_a * 0.5]), omega=z, torque=z,
                  residual=np.zeros((n, 3)), iterations=np.zeros((n, 3), dtype=np.int64),
                  corner=np.zeros(n, dtype=np.int8), frame_time=np.zeros(0), frame_theta=np.zeros((0, 2)),
                  frame_u=np.zeros((0, 0)), steps=n - 1, info=info, pair_force=force, pair_roll=roll,
                  transmission_error=dyn_te if te else None)


def legend_entries(fig) -> int:
    return sum(len(ax.get_legend().get_texts()) for ax in fig.axes if ax.get_legend() is not None)


def test_harmonic_amplitudes_of_a_known_signal():
    cycles, per = 3, 50
    u = np.arange(cycles * per) / per          # in periods
    x = (2.0 + 1.5 * np.cos(2 * math.pi * u) + 0.4 * np.sin(2 * math.pi * 3 * u + 0.7)
         + 0.25 * np.cos(2 * math.pi * 7 * u - 1.0)
         + 0.5 * np.cos(2 * math.pi * u / cycles))   # a subharmonic: not a mesh harmonic
    np.testing.assert_allclose(harmonic_amplitudes(x, cycles, 8),
                               [1.5, 0, 0.4, 0, 0, 0, 0.25, 0], atol=1e-12)
    # at and above the Nyquist frequency there is no figure, not a zero
    amps = harmonic_amplitudes(np.cos(2 * math.pi * np.arange(8) / 8), 1, 6)
    assert amps[0] == pytest.approx(1.0) and np.isnan(amps[3:]).all() and np.isfinite(amps[:3]).all()


def test_the_static_cycle_reaches_the_dataset(short_case):
    ds = result_to_dataset(sector_like(5), short_case)
    assert ds["static_pair_force"].dims == ("cycle_position", "static_pair")
    assert ds["static_pair_force"].attrs["units"] == "N" and ds["static_transmission_error"].attrs["units"] == "m"
    np.testing.assert_allclose(ds["cycle_roll_deg"].values[[0, -1]], np.degrees([START, START + PITCH]))
    # the pairs share the load: the static pair forces sum to it at every position
    np.testing.assert_allclose(ds["static_pair_force"].sum("static_pair"), 1000.0)
    assert "static_cycle" not in json.loads(ds.attrs["info"])      # arrays in variables, not JSON
    assert "static_pair_force" not in result_to_dataset(sector_like(5, static=False), short_case)


def test_the_spectrum_of_the_run_is_its_tes_harmonics(short_case):
    ds = result_to_dataset(sector_like(8, asked=8), short_case)
    dyn, static, cycles, positions = _te_spectra(ds)
    assert cycles == 2 and positions == 20          # the settled window: the last 8 // 4 cycles
    np.testing.assert_allclose(dyn[:3], TE_AMPS, atol=1e-15)
    np.testing.assert_allclose(dyn[3:], 0.0, atol=1e-15)
    assert static[0] == pytest.approx(1e-6) and np.isnan(static[positions // 4:]).all()
    assert dyn.size == static.size == HARMONICS


@pytest.mark.parametrize("done, settled, words, absent", [
    (5, None, ["last of 5 mesh cycles done", "settled (change < 0.1 %"], "NOT"),
    (20, False, ["last of 20 mesh cycles done", "NOT settled", "limit of 20 cycles"], "last of 5"),
])
def test_the_titles_say_the_cycles_done_and_whether_settled(short_case, done, settled, words, absent):
    ds = result_to_dataset(sector_like(done, settled=settled), short_case)
    for fig in (mesh_figure(ds), mesh_cycle_figure(ds), transmission_error_figure(ds)):
        title = fig.axes[0].get_title().replace("\n", " ")
        for w in words + ["damping ratio 0.05", f"{json.loads(ds.attrs['case'])['run']['torque']:g} N m"]:
            assert w in title
        assert absent not in title


def test_the_legends_stay_short_and_the_teeth_are_numbered(short_case):
    ds = result_to_dataset(sector_like(24), short_case)
    assert ds.sizes["pair"] == 26
    fig = mesh_cycle_figure(ds)
    assert legend_entries(fig) <= 8 and legend_entries(mesh_figure(ds)) <= 8
    loaded = ds["pair"].values[ds["pair_force"].values[-PER - 1:].max(axis=0) > 0]
    texts = {t.get_text() for t in fig.axes[0].texts}
    assert texts == {f"tooth {k}" for k in loaded} and len(loaded) == 3
    numbers = {t.get_text() for t in mesh_figure(ds).axes[0].texts}
    assert numbers == {str(k) for k in ds["pair"].values}


def stress_dataset(ds: xr.Dataset, turns: float) -> xr.Dataset:
    """``ds`` with each tooth's root stress over ``turns`` of gear A (synthetic pulses)."""
    t = np.linspace(0.0, ds["time"].values[-1], 200)
    teeth = np.arange(Z)
    turn = 2 * math.pi * turns * t / t[-1]
    apart = (turn[:, None] - teeth[None, :] * PITCH + math.pi) % (2 * math.pi) - math.pi
    pulse = np.exp(-(apart / 0.05) ** 2) * 300e6       # tooth k loaded at k pitches, each turn
    out = ds.assign(theta_a=("time", 2 * math.pi * turns * ds["time"].values / t[-1]))
    out = out.assign_coords(stress_time=("stress_time", t), tooth_a=("tooth_a", teeth),
                            tooth_b=("tooth_b", -teeth))
    return out.assign(root_stress_a=(("stress_time", "tooth_a"), pulse),
                      root_stress_b=(("stress_time", "tooth_b"), 0.9 * pulse),
                      root_stress_compressive_a=(("stress_time", "tooth_a"), -0.5 * pulse),
                      root_stress_compressive_b=(("stress_time", "tooth_b"), -0.4 * pulse))


def test_the_root_stress_picture_says_what_it_covers(short_case):
    ds = result_to_dataset(sector_like(5), short_case)
    assert teeth_stress_figure(ds) is None                      # no stress variables: no picture
    part = teeth_stress_figure(stress_dataset(ds, 0.5)).axes[0].get_title().replace("\n", " ")
    assert "180 deg of A's revolution" in part
    fig = teeth_stress_figure(stress_dataset(ds, 1.5))
    assert "the last revolution of A" in fig.axes[0].get_title().replace("\n", " ")
    assert {t.get_text() for t in fig.axes[0].texts} == {str(k) for k in range(Z)}
    assert "MPa" in fig.axes[0].get_ylabel() and len(fig.legends[0].get_texts()) == 2


def test_absent_variables_draw_nothing_and_do_not_fail(tmp_path, short_case):
    ds = result_to_dataset(sector_like(5, static=False, te=False), short_case)
    assert transmission_error_figure(ds) is None
    drawn = plot_pair_pictures(ds, tmp_path)
    assert sorted(p.name for p in drawn) == ["mesh.png", "mesh_cycle.png"]
    # no whole mesh cycle, or no steady-state record: no cycle pictures
    short = result_to_dataset(sector_like(5), short_case).isel(time=slice(0, PER // 2))
    assert mesh_cycle_figure(short.assign_attrs(info="{}")) is None
    assert transmission_error_figure(short.assign_attrs(info="{}")) is None


def test_write_run_draws_a_sector_runs_pictures(tmp_path, short_case):
    write_run(sector_like(5), short_case, tmp_path)
    for name in ("contact_force.png", "mesh.png", "mesh_cycle.png", "transmission_error.png"):
        assert (tmp_path / name).read_bytes()[:8] == PNG_MAGIC
    assert not (tmp_path / "root_stress.png").exists()


def test_a_sector_runs_pictures_split_between_the_child_and_here_are_those_drawn_here(tmp_path, short_case,
                                                                                      monkeypatch):
    """:func:`write_run` draws a run of several pairs' pictures in two parts, one in the
    forked child, one itself after the files: the same files, byte for byte, as all drawn
    in this process; and ``plot_pair_pictures`` draws each part alone."""
    from spurdyn.results import beside as beside_module

    result = sector_like(5)
    for name, fork in (("split", beside_module.can_fork()), ("here", False)):
        monkeypatch.setattr(beside_module, "can_fork", lambda fork=fork: fork)
        (tmp_path / name).mkdir()
        write_run(result, short_case, tmp_path / name)
    files = sorted(p.name for p in (tmp_path / "here").iterdir())
    assert files == sorted(p.name for p in (tmp_path / "split").iterdir())
    pictures = [f for f in files if f.endswith(".png")]
    assert len(pictures) == 4
    for f in pictures:
        assert (tmp_path / "split" / f).read_bytes() == (tmp_path / "here" / f).read_bytes()
    ds = result_to_dataset(result, short_case)
    parts = []
    for part in (0, 1):
        (tmp_path / str(part)).mkdir()
        parts.append({p.name for p in plot_pair_pictures(ds, tmp_path / str(part), part)})
        assert {p.name for p in (tmp_path / str(part)).iterdir()} == parts[-1]
    assert parts == [{"mesh_cycle.png"}, {"mesh.png", "transmission_error.png"}]   # no stress: none drawn
