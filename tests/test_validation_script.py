"""The validation pages' generators, docs/validation: the report's pure helpers on synthetic
data, its run list and the relief gap (no solver runs); every generator imports and its
runner takes its options."""

import importlib
import math
import subprocess
import sys
from pathlib import Path
from types import ModuleType

import numpy as np
import pytest

DOCS = Path(__file__).resolve().parents[1] / "docs"


def _report_module(name: str) -> ModuleType:
    """``validation.report.<name>``, with ``docs/`` (where the package lives) on the path."""
    if str(DOCS) not in sys.path:
        sys.path.insert(0, str(DOCS))
    return importlib.import_module(f"validation.report.{name}")


@pytest.fixture(scope="module")
def mv() -> ModuleType:
    """The pure helpers, ``validation.report.helpers``."""
    return _report_module("helpers")


@pytest.fixture(scope="module")
def runs() -> ModuleType:
    """The run list and its cache keys, ``validation.report.runs``."""
    return _report_module("runs")


@pytest.fixture(scope="module")
def relief() -> ModuleType:
    """Section 5, ``validation.report.relief``."""
    return _report_module("relief")


def test_moving_average_keeps_constants_and_lines_and_removes_a_whole_period(mv):
    dt = 3e-8
    t = np.arange(2000) * dt
    avg, tc = mv.moving_average(t, np.full(t.size, 532.7))
    half = 5e-6 / dt                      # samples in half a window: only whole windows kept
    assert avg.size == tc.size == t.size - 2 * math.ceil(half)
    assert tc[0] >= t[0] + 5e-6 and tc[-1] <= t[-1] - 5e-6
    assert np.allclose(avg, 532.7)
    line = 3.0 + 1e6 * t
    avg, tc = mv.moving_average(t, line)
    assert np.allclose(avg, 3.0 + 1e6 * tc, rtol=1e-12)      # centred: no lag
    # a sine whose period is the window averages to zero
    wave = np.sin(2 * math.pi * t / 10e-6)
    avg, _ = mv.moving_average(t, wave)
    assert np.abs(avg).max() < 1e-5
    # a sine is scaled by |sinc|: 120 kHz (the teeth' mode) to 16 %, 7.3 kHz kept at 99 %
    for freq, gain in ((120e3, 0.156), (7.3e3, 0.991)):
        x = np.sin(2 * math.pi * freq * np.arange(20000) * dt)
        got = np.abs(mv.moving_average(np.arange(20000) * dt, x)[0]).max()
        assert got == pytest.approx(gain, abs=0.005)
        assert mv.window_gain(freq) == pytest.approx(gain, abs=0.001)
    with pytest.raises(ValueError):
        mv.moving_average(t[:10], line[:10])


def test_moving_average_is_spurdyns_own(mv):
    """The report compares runs on the average that makes ``spurdyn run``'s dynamic factor."""
    from spurdyn.results.headline import AVERAGING_WINDOW_S, moving_average

    assert mv.WINDOW == AVERAGING_WINDOW_S
    t = np.arange(3000) * 3e-8
    f = 500 + 80 * np.sin(2 * math.pi * 1e6 * t) + 100 * np.exp(-((t - 45e-6) / 10e-6) ** 2)
    avg, tc = mv.moving_average(t, f)
    own = moving_average(t, f)
    inner = (t >= tc[0]) & (t <= tc[-1])
    np.testing.assert_array_equal(avg, own[inner])
    assert avg.max() == own.max()


def test_dynamic_factor(mv):
    f = np.array([0.0, 100.0, 640.2, 500.0, np.nan])
    assert mv.dynamic_factor(f, 532.7) == pytest.approx(640.2 / 532.7)
    assert math.isnan(mv.dynamic_factor(np.zeros(5), 532.7))
    with pytest.raises(ValueError):
        mv.dynamic_factor(f, 0.0)


def test_zone_masks_split_the_engagement(mv):
    ts, t2 = math.radians(21.06), math.radians(8.2)
    a = np.linspace(0.0, ts, 1001)
    m = mv.zone_masks(a, t2, ts)
    parts = m["double_in"].astype(int) + m["single"].astype(int) + m["double_out"].astype(int)
    assert np.all(parts == 1)
    assert np.all(m["double"] == (m["double_in"] | m["double_out"]))
    assert a[m["single"]].min() >= t2 and a[m["single"]].max() <= ts - t2
    assert m["double_in"][0] and m["double_out"][-1]
    assert not mv.zone_masks(np.array([-0.1, ts + 0.1]), t2, ts)["double"].any()
    with pytest.raises(ValueError):
        mv.zone_masks(a, ts, ts)


def test_contact_episodes(mv):
    t = np.arange(12) * 1e-6
    angle = t * 400.0
    f = np.array([0, 5, 9, 0, 0, 1, 7, 3, 0, 0, 2, 4.0])
    eps = mv.contact_episodes(t, angle, f)
    assert len(eps) == 3
    assert (eps[0]["t_on"], eps[0]["t_off"], eps[0]["peak"]) == (t[1], t[2], 9.0)
    assert eps[1]["angle_peak"] == angle[6] and not eps[1]["open_end"]
    assert eps[2]["open_end"] and eps[2]["t_off"] == t[-1]
    assert mv.contact_episodes(t, angle, np.zeros(12)) == []
    first = mv.contact_episodes(t, angle, np.r_[1.0, f[1:]])[0]
    assert first["t_on"] == 0.0


def test_common_grid_and_rms(mv):
    ta = np.linspace(0.0, 1.0, 11)
    tb = np.linspace(0.2, 1.4, 7)
    grid, (a, b) = mv.on_common_grid([(ta, 2 * ta), (tb, 2 * tb + 1)], 0.1)
    assert grid[0] == pytest.approx(0.2) and grid[-1] == pytest.approx(1.0)
    assert np.allclose(b - a, 1.0)
    assert mv.rms(b - a) == pytest.approx(1.0)
    assert mv.rms(np.array([3.0, -3.0])) == 3.0
    with pytest.raises(ValueError):
        mv.on_common_grid([(ta, ta), (ta + 2.0, ta)], 0.1)


def test_frequency_estimators_find_a_short_sinusoid(mv):
    rng = np.random.default_rng(1)
    t = np.arange(0.0, 775e-6, 1.5e-7)
    f0 = 7310.0
    x = 60 * np.sin(2 * math.pi * f0 * t + 0.4) + 5e5 * t + 530 + rng.normal(0, 3, t.size)
    f, amp = mv.dominant_frequency(t, x, 2e3, 30e3, n=400)
    assert f == pytest.approx(f0, rel=3e-3) and amp == pytest.approx(60, rel=0.05)
    fz, n = mv.zero_crossing_frequency(t, 60 * np.sin(2 * math.pi * f0 * t + 0.4))
    assert fz == pytest.approx(f0, rel=5e-3) and n >= 10
    assert math.isnan(mv.zero_crossing_frequency(t[:10], np.ones(10))[0])
    ts = np.arange(0.0, 190e-6, 3e-8)
    fp, ap = mv.spectrum_peak(ts, 4 * np.sin(2 * math.pi * 120e3 * ts), 20e3)
    assert fp == pytest.approx(120e3, rel=0.01) and ap == pytest.approx(4, rel=0.1)


def test_least_squares_spectrum_of_two_tones(mv):
    """On a record of ~6 periods of the main tone (an FFT bin is 1.3 kHz there), the
    least-squares spectrum gives each tone's amplitude at its frequency, little where
    there is none, and nothing for a mean and a linear trend."""
    t = np.arange(0.0, 775e-6, 1.5e-7)
    x = 50 * np.cos(2 * math.pi * 7300 * t) + 10 * np.sin(2 * math.pi * 15000 * t) + 3e5 * t + 500
    f = np.array([7300.0, 15000.0, 22000.0])
    amp = mv.ls_spectrum(t, x, f)
    assert amp[0] == pytest.approx(50, rel=0.05) and amp[1] == pytest.approx(10, rel=0.2)
    assert amp[2] < 2.0
    assert mv.ls_spectrum(t, 3e5 * t + 500, f).max() < 1e-6


def test_first_crossing_and_formatting(mv):
    x = np.array([0.0, 1.0, 2.0, 3.0])
    assert mv.first_crossing(x, np.array([0.0, 2.0, 4.0, 6.0]), 3.0) == pytest.approx(1.5)
    assert math.isnan(mv.first_crossing(x, x, 10.0))
    assert mv.first_crossing(x, x, -1.0) == 0.0
    assert mv.pct(0.0215) == "+2.1 %" and mv.upct(0.5, 0) == "50 %"
    assert mv.sci(1.5e-7, 1) == "1.5 × 10⁻⁷" and mv.sci(9.99e3, 1) == "1.0 × 10⁴"
    assert mv.n0(29251) == "29,251"
    assert mv.table(["a", "b"], [[1, 2]]).splitlines() == ["| a | b |", "| --- | --- |", "| 1 | 2 |"]
    assert mv.relative(1.1, 1.0) == pytest.approx(0.1)


def test_run_specs_are_distinct_and_their_digest_follows_the_settings(runs):
    specs = runs.specs()
    names = [s.name for s in specs]
    assert len(set(names)) == len(names)
    assert {"fig8", "fig9", "fig10", "fig11", "fig10_b", "qs1000", "relief_20um"} <= set(names)
    s = runs.Spec("x", "fe", 4000, 4000)
    assert s.digest() == runs.Spec("x", "fe", 4000, 4000).digest()
    assert s.digest() != runs.Spec("x", "fe", 4000, 4000, n_spline=121).digest()
    assert all(sp.kind in ("fe", "lumped", "balance") for sp in specs)


def test_relief_gap_is_the_relief_at_the_ends_and_zero_in_between(relief):
    from spurdyn.geometry.presets import paper_pair

    pair = paper_pair()
    phi = np.array([0.0, pair.theta_2 * 0.5, pair.theta_2 + 1e-4, pair.theta_s / 2,
                    pair.theta_s - pair.theta_2 - 1e-4, pair.theta_s])
    gap = relief.relief_gap(pair, 20e-6, phi)
    assert gap[0] == pytest.approx(20e-6, rel=1e-6) and gap[-1] == pytest.approx(20e-6, rel=1e-6)
    assert gap[1] == pytest.approx(10e-6, rel=0.02)
    assert np.all(gap[2:5] == 0.0)


@pytest.fixture(scope="module")
def common() -> ModuleType:
    """What the page generators share, ``validation.common``."""
    if str(DOCS) not in sys.path:
        sys.path.insert(0, str(DOCS))
    return importlib.import_module("validation.common")


def test_touches_and_their_matching_between_two_runs(common):
    t = np.arange(10.0)
    f = np.array([1.0, 0, 0, 5, 7, 0, 0, 2, 0, 0])      # the start's contact is not a touch
    assert common.touches(t, f) == [(3.0, 1.0, 7.0), (7.0, 0.0, 2.0)]
    ref = [(3.0, 1.0, 7.0), (7.0, 0.0, 2.0)]
    shifts, extra = common.match_impacts(ref, [(3.5, 1.0, 6.0), (5.0, 0.1, 1.0), (7.25, 0.0, 2.0)])
    assert shifts == [0.5, 0.25] and extra == [(5.0, 0.1, 1.0)]
    shifts, extra = common.match_impacts(ref, [(3.0, 1.0, 7.0)])
    assert shifts[0] == 0.0 and math.isnan(shifts[1]) and extra == []


def test_figures_kept_and_read_back_and_a_run_timed(common, tmp_path):
    store = tmp_path / "page.json"
    assert common.load_figures(store) == {}
    common.save_figures(store, {"a": np.float64(1.5), "b": [1, 2]})
    assert common.load_figures(store) == {"a": 1.5, "b": [1, 2]}
    out, wall = common.timed(sum, [1, 2, 3])
    assert out == 6 and wall >= 0.0


def _runner(*args: str) -> subprocess.CompletedProcess[str]:
    """``python docs/validation ARGS``, the one runner of the pages."""
    return subprocess.run([sys.executable, str(DOCS / "validation"), *args],
                          capture_output=True, text=True, timeout=300)


def test_the_runner_lists_the_pages_and_refuses_an_unknown_one():
    out = _runner()
    assert out.returncode == 0, out.stderr
    for page in ("validation", "contact_validation", "sector_rk4_validation", "validation_sweep"):
        assert page in out.stdout
    assert _runner("no_such_page").returncode == 2


def test_the_report_still_takes_its_options():
    out = _runner("validation", "--help")
    assert out.returncode == 0, out.stderr
    for option in ("--rerun", "--runs-only", "--sweep"):
        assert option in out.stdout


@pytest.mark.parametrize("page", ["contact_validation", "implicit_validation", "sector_validation",
                                  "sector_dynamics_validation", "sector_rk4_validation",
                                  "stress_validation", "validation_sweep", "stiffness", "fracture"])
def test_every_generator_imports_and_shows_its_options(page):
    """Each page's generator imports (its spurdyn names among them) and answers ``--help``
    without running anything."""
    out = _runner(page, "--help")
    assert out.returncode == 0, out.stderr
    assert out.stdout.startswith(f"usage: docs/validation {page}")
