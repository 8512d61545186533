"""The headline: the dynamic factor is the 10-us-averaged force's (spurdyn.results.headline).

The average itself (generated histories, steps of unequal length, the ends, a spike), the
figures of ``summary.json``, the command's line and the run's picture built on it, and a
run stopped early, which has no dynamic factor anywhere.
"""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from matplotlib.figure import Figure

from spurdyn.case import preset_case
from spurdyn.cli.run import report_line
from spurdyn.result import Result
from spurdyn.results.headline import (AVERAGING_WINDOW_S, averaged_peak, headline,
                                      moving_average, window_means)
from spurdyn.results.io import result_to_dataset, summarize
from spurdyn.results.plots import draw_contact_force

W = AVERAGING_WINDOW_S
DT = 3e-8
SETTINGS = settings(max_examples=60, deadline=None, derandomize=True)


def _times(draw: st.DrawFn, n_min: int = 2, n_max: int = 60, span_min: float = 0.0
           ) -> np.ndarray:
    """Strictly increasing sample times with steps of unequal length (0.1..2 us)."""
    steps = draw(st.lists(st.floats(1e-7, 2e-6), min_size=n_min - 1, max_size=n_max - 1))
    t = np.concatenate([[0.0], np.cumsum(steps)])
    if t[-1] < span_min:  # stretch to the span asked for
        t = t * (span_min / t[-1]) if t[-1] > 0 else np.linspace(0.0, span_min, t.size)
    return t


@st.composite
def histories(draw: st.DrawFn, span_min: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    t = _times(draw, span_min=span_min)
    f = np.array(draw(st.lists(st.floats(0.0, 5000.0), min_size=t.size, max_size=t.size)))
    return t, f


def _result(case, t: np.ndarray, force: np.ndarray, status: str = "complete",
            reason: str = "") -> Result:
    """A run of ``case`` with the history ``(t, force)``, A turning at its speed."""
    n = t.size
    angle = case.run.speed_a * t
    pair = np.column_stack
    return Result(time=t, angle=angle, contact_force=force, gap=np.where(force > 0, -1e-9, 1e-7),
                  roll=pair([angle, angle]), theta=pair([angle, angle]),
                  omega=np.full((n, 2), case.run.speed_a), torque=np.full((n, 2), case.run.torque),
                  residual=np.zeros((n, 3)), iterations=np.zeros((n, 3), np.int64),
                  corner=np.zeros(n, np.int8), frame_time=np.zeros(0),
                  frame_theta=np.zeros((0, 2)), frame_u=np.zeros((0, 0)), status=status,
                  reason=reason, steps=n - 1, wall_s=0.1,
                  # the FE model's Hertz strip (a fixed half-width will do here)
                  contact_half_width=np.full(n, 1e-5), contact_pressure_max=force / 1e-7)


@pytest.fixture(scope="module")
def case():
    """paper-fig8 over 0.6 deg (25 us at 4,000 rpm)."""
    return preset_case("paper-fig8", {"run.angle_deg": 0.6, "run.frames_every": 0},
                       check_step=False)


def smooth_force(t: np.ndarray, static: float) -> np.ndarray:
    """A force like a run's: a ramp with a slow swing (7.5 kHz)."""
    return static * (0.8 + 0.2 * t / t[-1]) * (1.0 + 0.15 * np.sin(2 * math.pi * 7.5e3 * t))


# -- the average ---------------------------------------------------------------------------

@pytest.mark.slow
@SETTINGS
@given(data=st.data())
def test_moving_average_of_a_line_is_the_line_at_the_window_centre(data):
    t = _times(data.draw, span_min=data.draw(st.floats(0.0, 3 * W)))
    a, b = data.draw(st.floats(-1e3, 1e3)), data.draw(st.floats(-1e8, 1e8))
    centre, mean, keep = window_means(t, a + b * t)
    assert keep.all()
    scale = abs(a) + abs(b) * t[-1] + 1.0
    np.testing.assert_allclose(mean, a + b * centre, rtol=0, atol=1e-9 * scale)
    # centred: no lag, and the centre moves inside the record only at its ends
    half = 0.5 * min(W, t[-1] - t[0])
    inner = (t >= t[0] + half) & (t <= t[-1] - half)
    assert np.array_equal(centre[inner], t[inner])
    assert np.all(centre >= centre[0]) and np.all(centre <= centre[-1])
    assert centre[0] == pytest.approx(t[0] + half) and centre[-1] == pytest.approx(t[-1] - half)


@SETTINGS
@given(history=histories(), data=st.data())
def test_steps_of_unequal_length_weigh_by_their_time(history, data):
    """Samples added on the straight line between two samples change no average (a mean
    of samples would be pulled towards the densely sampled stretch)."""
    t, f = history
    i = data.draw(st.integers(0, t.size - 2))
    k = data.draw(st.integers(1, 20))
    x = np.linspace(t[i], t[i + 1], k + 2)[1:-1]
    t2 = np.insert(t, i + 1, x)
    f2 = np.insert(f, i + 1, np.interp(x, t, f))
    before = moving_average(t, f)
    after = moving_average(t2, f2)
    old = np.ones(t2.size, bool)
    old[i + 1:i + 1 + k] = False
    np.testing.assert_allclose(after[old], before, rtol=1e-9, atol=1e-9 * (1 + f.max()))


@SETTINGS
@given(history=histories())
def test_the_average_lies_within_the_samples_and_below_the_raw_peak(history):
    t, f = history
    avg = moving_average(t, f)
    assert avg.shape == f.shape
    assert (avg >= f.min() - 1e-9 * (1 + f.max())).all()
    assert (avg <= f.max() + 1e-9 * (1 + f.max())).all()
    peak, centre = averaged_peak(t, f)
    assert peak == avg.max() and t[0] <= centre <= t[-1]


@SETTINGS
@given(history=histories(span_min=1.5 * W), data=st.data())
def test_a_one_sample_spike_moves_the_average_by_its_area_only(history, data):
    """A spike on one sample (anywhere, the ends included) changes every window mean by at
    most its area over the window: height x step / window."""
    t, f = history
    i = data.draw(st.integers(0, t.size - 1))
    height = data.draw(st.floats(1e3, 1e6))
    spiked = f.copy()
    spiked[i] += height
    step = max(t[i] - t[max(i - 1, 0)], t[min(i + 1, t.size - 1)] - t[i])
    change = moving_average(t, spiked) - moving_average(t, f)
    assert (change >= -1e-9 * height).all()
    assert change.max() <= height * step / W * (1 + 1e-9)


def test_ends_hold_the_first_and_last_whole_window():
    t = np.arange(0.0, 40e-6, DT)
    f = np.zeros(t.size)
    f[0] = 1000.0                                          # a spike on the very first sample
    avg = moving_average(t, f)
    whole = 0.5 * 1000.0 * DT / W                          # its triangle over one window
    near = t <= t[0] + 0.5 * W
    assert avg[near] == pytest.approx(np.full(near.sum(), whole), rel=1e-9)
    assert avg[~near].max() < whole and avg[-1] == 0.0


def test_a_record_shorter_than_the_window_is_one_window():
    t = np.array([0.0, 1e-6, 4e-6])
    f = np.array([0.0, 30.0, 0.0])
    avg = moving_average(t, f)
    assert avg == pytest.approx(np.full(3, 0.5 * 30.0 * 4e-6 / 4e-6))
    assert moving_average(t[:1], f[:1]).tolist() == [0.0]
    assert moving_average(t[:0], f[:0]).size == 0


def test_non_finite_samples_are_left_out():
    t = np.arange(0.0, 30e-6, DT)
    f = 500.0 + 100.0 * np.sin(2 * math.pi * 20e3 * t)
    holed = f.copy()
    holed[[5, 300, 600]] = [np.nan, np.inf, np.nan]
    avg = moving_average(t, holed)
    assert np.isnan(avg[[5, 300, 600]]).all()
    keep = np.isfinite(holed)
    np.testing.assert_array_equal(avg[keep], moving_average(t[keep], f[keep]))


@pytest.mark.parametrize("freq, kept", [(7.5e3, 0.991), (120e3, 0.156)])
def test_the_window_keeps_the_pair_mode_and_takes_out_the_tooth_ripple(freq, kept):
    """What :data:`AVERAGING_WINDOW_S` says of itself: |sinc(pi f w)| of a sinusoid."""
    t = np.arange(0.0, 400e-6, DT)
    got = np.abs(moving_average(t, np.sin(2 * math.pi * freq * t))).max()
    assert got == pytest.approx(kept, abs=0.003)
    assert abs(math.sin(math.pi * freq * W) / (math.pi * freq * W)) == pytest.approx(kept, abs=0.001)


@pytest.mark.parametrize("t, f, window, message", [
    ([0.0, 1e-6, 1e-6], [1.0, 2.0, 3.0], W, "increase strictly"),
    ([0.0, 2e-6, 1e-6], [1.0, 2.0, 3.0], W, "increase strictly"),
    ([0.0, 1e-6], [1.0], W, "equal length"),
    ([0.0, 1e-6], [1.0, 2.0], 0.0, "positive"),
    ([0.0, 1e-6], [1.0, 2.0], float("nan"), "positive"),
])
def test_refusals(t, f, window, message):
    with pytest.raises(ValueError, match=message):
        moving_average(np.array(t), np.array(f), window)


# -- the headline figures --------------------------------------------------------------------

def test_a_spike_makes_the_raw_factor_not_the_headline(case):
    """One sample of 5 kN on a 530 N force: the raw factor jumps, the headline barely moves
    (the whole test fails if summary.json's dynamic_factor were the raw peak's)."""
    t = np.arange(0.0, 100e-6, DT)
    static = case.static_force
    smooth = smooth_force(t, static)
    spiked = smooth.copy()
    spiked[t.size // 2] = 5000.0
    plain = summarize(result_to_dataset(_result(case, t, smooth), case))
    spike = summarize(result_to_dataset(_result(case, t, spiked), case))
    assert spike["peak_force_raw_N"] == 5000.0
    assert spike["dynamic_factor_raw"] == pytest.approx(5000.0 / static)
    assert plain["dynamic_factor_raw"] == pytest.approx(smooth.max() / static)
    assert spike["dynamic_factor"] - plain["dynamic_factor"] <= 5000.0 * DT / W / static
    assert spike["dynamic_factor"] < 1.2 < spike["dynamic_factor_raw"] / 7
    assert spike["peak_force_N"] == pytest.approx(np.max(moving_average(t, spiked)))
    assert "averaged over a centred 10-us" in spike["dynamic_factor_note"]
    # the command's line says the averaged figures and gives the raw peak only beside them
    line = report_line({**spike, "separations": 0})
    assert f"= {spike['dynamic_factor']:.3f} x static" in line and "raw 5,000.0 N" in line
    assert f"{5000.0 / static:.3f}" not in line


def test_angle_of_the_averaged_peak_is_its_window_centre(case):
    t = np.arange(0.0, 100e-6, DT)
    f = 600.0 * np.exp(-(((t - 60e-6) / 15e-6) ** 2))
    s = summarize(result_to_dataset(_result(case, t, f), case))
    deg_per_s = math.degrees(case.run.speed_a)
    assert s["peak_angle_deg"] == pytest.approx(60e-6 * deg_per_s, abs=DT * deg_per_s)
    assert s["peak_angle_raw_deg"] == pytest.approx(60e-6 * deg_per_s, abs=DT * deg_per_s)


def test_no_contact_has_no_factor(case):
    t = np.arange(0.0, 20e-6, DT)
    s = summarize(result_to_dataset(_result(case, t, np.zeros(t.size)), case))
    assert s["peak_force_N"] is s["peak_force_raw_N"] is s["dynamic_factor"] is None
    assert s["dynamic_factor_raw"] is None and "never touched" in s["dynamic_factor_note"]
    assert "no contact" in report_line({**s, "separations": 0})


def test_zero_torque_has_no_factor():
    h = headline([0.0, 1e-6], [0.0, 0.1], [0.0, 3.0], 0.0, complete=True)
    assert h.peak_force == 1.5 and h.dynamic_factor is None and "zero torque" in h.note


# -- a run stopped early ---------------------------------------------------------------------

def test_an_incomplete_run_reports_no_factor_anywhere(case, tmp_path):
    t = np.arange(0.0, 30e-6, DT)
    f = smooth_force(t, case.static_force)
    f[-1] = 9e4                                     # the step that stopped it
    reason = "step 999: the displacement stage did not converge in 500 iterations"
    ds = result_to_dataset(_result(case, t, f, "incomplete", reason), case)
    s = summarize(ds)
    assert s["status"] == "incomplete"
    assert s["dynamic_factor"] is None and s["dynamic_factor_raw"] is None
    assert s["dynamic_factor_note"].startswith("none: the run stopped early")
    assert reason in s["dynamic_factor_note"]
    assert s["peak_force_raw_N"] == 9e4          # a fact of the part computed, not a headline
    line = report_line(s)
    assert "incomplete" in line and "stopped early: no dynamic factor" in line
    assert "x static" not in line and "peak" not in line
    assert f"{s['angle_deg']:.3f} of {s['angle_target_deg']:.3f} deg" in line
    # the picture: no factor in its legend, the run marked incomplete
    fig = Figure()
    ax = fig.subplots()
    draw_contact_force(ax, [ds])
    texts = [x.get_text() for x in ax.get_legend().get_texts()]
    assert any("stopped early: no dynamic factor" in x for x in texts)
    assert not any("x static" in x for x in texts)
    assert any("[incomplete]" in x for x in texts)


def test_a_complete_run_has_its_factor_in_the_picture(case):
    t = np.arange(0.0, 60e-6, DT)
    ds = result_to_dataset(_result(case, t, smooth_force(t, case.static_force)), case)
    s = summarize(ds)
    fig = Figure()
    ax = fig.subplots()
    draw_contact_force(ax, [ds])
    texts = [x.get_text() for x in ax.get_legend().get_texts()]
    assert f"peak of the average {s['peak_force_N']:,.1f} N = {s['dynamic_factor']:.3f} x static" \
        in texts
    averaged = [ln for ln in ax.get_lines() if ln.get_label() == "10-µs average"]
    assert len(averaged) == 1
    np.testing.assert_allclose(averaged[0].get_ydata(), moving_average(t, ds["contact_force"].values))


@pytest.mark.parametrize("doc", ["README.md", "docs/cli.md"])
def test_the_line_the_docs_quote_is_the_line_the_command_prints(doc):
    text = (Path(__file__).resolve().parents[1] / doc).read_text()
    line = next(ln for ln in text.splitlines() if ln.startswith("paper-fig8: complete"))
    m = re.fullmatch(r"paper-fig8: complete, ([\d,]+) steps in ([\d.]+) s, peak ([\d,.]+) N = "
                     r"([\d.]+) x static \(10-us average; raw ([\d,.]+) N\), (\d+) separation\(s\) "
                     r"-> (\S+)", line)
    assert m, line
    num = lambda s: float(s.replace(",", ""))  # noqa: E731
    summary = {"case": "paper-fig8", "status": "complete", "steps": int(num(m[1])),
               "wall_s": num(m[2]), "peak_force_N": num(m[3]), "dynamic_factor": num(m[4]),
               "peak_force_raw_N": num(m[5]), "separations": int(m[6]),
               "averaging_window_s": AVERAGING_WINDOW_S}
    assert f"{report_line(summary)} -> {m[7]}" == line
    assert num(m[4]) == pytest.approx(num(m[3]) / 532.7, abs=6e-4)   # the factor is the average's
