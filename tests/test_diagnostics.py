"""Gear diagnostics on synthetic signals with known answers (docs/diagnostics.md, section 6).

Spectrum: a sine's amplitude and frequency on and off bin; marks and the sideband energy
ratio of an amplitude-modulated mesh tone; the time-synchronous average: non-synchronous
noise falls as 1/sqrt(R) (a chi-square check), a tone between orders as McFadden's comb,
a waveform locked to a varying-speed shaft comes back within the spline's error bound;
indicators against closed forms; invariances by Hypothesis; refusals naming the argument.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.stats import chi2

from spurdyn.diagnostics import (crest_factor, difference_signal, fm0, fm4, kurtosis,
                                 mesh_marks, na4, na4_trend, order_amplitudes, read_at,
                                 read_marks, read_tone, regular_signal, residual_signal, rms,
                                 scalloping_loss, sideband_energy_ratio, spectrum,
                                 synchronous_average, window_response)
from spurdyn.errors import InputError

N_REC, DT = 4096, 1.0e-4                    # a record of 0.4096 s, bins of 2.44 Hz
DF = 1.0 / (N_REC * DT)
T = np.arange(N_REC) * DT
TEETH, POINTS = 23, 1024                    # the gear on the averaged shaft; points a turn
THETA = 2.0 * np.pi * np.arange(POINTS) / POINTS
HYPOTHESIS = settings(max_examples=40, deadline=None, derandomize=True)


def mesh(theta: np.ndarray) -> np.ndarray:
    """A healthy gear's average: two mesh harmonics and a shaft order (no noise)."""
    return (np.cos(TEETH * theta) + 0.4 * np.cos(2 * TEETH * theta + 0.5)
            + 0.3 * np.cos(theta + 0.2))


def tooth_pulse(theta: np.ndarray, height: float = 0.5) -> np.ndarray:
    """One tooth's pulse a revolution: a Gaussian a sixth of a tooth pitch wide at 1 rad."""
    width = 2.0 * np.pi / TEETH / 6.0
    wrapped = np.angle(np.exp(1j * (theta - 1.0)))
    return height * np.exp(-0.5 * (wrapped / width) ** 2)


# -- 1. the spectrum -----------------------------------------------------------------------

def test_hann_scalloping_bound_is_the_closed_form():
    """Hann's transform at d bins, relative to 0: sinc(d) / (1 - d^2); at half a bin 8/(3 pi)."""
    assert scalloping_loss("hann", N_REC) == pytest.approx(1.0 - 8.0 / (3.0 * math.pi), abs=1e-9)
    d = np.array([0.1, 0.25, 0.4])
    assert window_response("hann", N_REC, d) == pytest.approx(np.sinc(d) / (1 - d ** 2), rel=1e-6)


@pytest.mark.parametrize("window", ["hann", "flattop", "boxcar"])
def test_a_sine_on_a_bin_reads_its_amplitude_and_frequency(window):
    x = 1.7 * np.sin(2 * np.pi * 200 * DF * T + 0.3)
    spec = spectrum(x, DT, window)
    k = int(np.argmax(spec.amplitude))
    assert (k, spec.frequency[k]) == (200, pytest.approx(200 * DF, rel=1e-12))
    assert spec.amplitude[k] == pytest.approx(1.7, rel=1e-12)
    tone = read_tone(spec, 201 * DF)
    assert (tone.frequency, tone.amplitude) == (pytest.approx(200 * DF, rel=1e-9),
                                                pytest.approx(1.7, rel=1e-9))


@pytest.mark.parametrize("offset", [0.13, 0.25, 0.37, 0.5])
def test_a_sine_off_bin_reads_within_the_scalloping_bound_and_exactly_between_bins(offset):
    """The nearest bin reads A |W(d)|/W(0), within Hann's scalloping bound, but for the
    leak of the sine's mirror at -f (|W| at 300 + f / df bins); read between bins (read_tone)
    the amplitude and frequency come back to 1e-6 (asked: 1e-3)."""
    f = (300 + offset) * DF
    x = 0.8 * np.cos(2 * np.pi * f * T - 1.1)
    spec = spectrum(x, DT, "hann")
    nearest = spec.amplitude[300] / 0.8
    mirror = window_response("hann", N_REC, 300 + f / DF)[0]
    assert mirror < 1e-8
    assert 1.0 - scalloping_loss("hann", N_REC) - mirror <= nearest <= 1.0 + mirror
    assert nearest == pytest.approx(window_response("hann", N_REC, offset)[0], abs=mirror)
    tone = read_tone(spec, f)
    assert tone.amplitude == pytest.approx(0.8, rel=1e-6)
    assert tone.frequency == pytest.approx(f, rel=1e-6)


def test_the_flat_top_window_reads_off_bin_within_its_own_bound():
    """The flat-top window's worst nearest-bin error, over offsets 0 .. 1/2 bin, bounds its
    reading of a sine anywhere between bins (about 1.1e-3 for SciPy's 'flattop'), but for
    the leak of the sine's mirror at -f (|W| at 150 + f / df bins)."""
    offsets = np.linspace(0.0, 0.5, 51)
    bound = np.max(np.abs(1.0 - window_response("flattop", N_REC, offsets)))
    assert 1.0e-3 < bound < 1.2e-3
    for d in (0.1, 0.3, 0.5):
        x = np.sin(2 * np.pi * (150 + d) * DF * T)
        mirror = window_response("flattop", N_REC, 150 + (150 + d))[0]
        assert abs(spectrum(x, DT, "flattop").amplitude[150] - 1.0) <= bound + mirror


# -- 2. marks and the sideband energy ratio ------------------------------------------------

def test_mesh_marks_table():
    marks = mesh_marks(f_a=25.0, f_b=10.0, z_a=20, harmonics=2, sidebands=3)
    assert len(marks) == 2 * (1 + 2 * 2 * 3)
    assert marks.frequency[marks.kind.index("mesh")] == 500.0
    rows = {(k, h, j): f for f, k, h, j in zip(marks.frequency, marks.kind, marks.harmonic, marks.order)}
    assert rows[("mesh", 2, 0)] == 1000.0
    assert rows[("sideband_a", 1, -3)] == 425.0 and rows[("sideband_b", 2, 2)] == 1020.0
    # a sideband at or below 0 Hz is left out
    low = mesh_marks(f_a=10.0, f_b=10.0, z_a=2, harmonics=1, sidebands=3)
    assert np.all(low.frequency > 0) and len(low) == 1 + 2 * (3 + 1)


def test_marks_read_their_lines_and_nan_beyond_the_band():
    fs, fm = 8 * DF, 160 * DF                # shaft on bin 8, mesh on bin 160 (z = 20)
    x = 2.0 * np.cos(2 * np.pi * fm * T) + 0.3 * np.cos(2 * np.pi * (fm + fs) * T)
    spec = spectrum(x, DT)
    marks = mesh_marks(fs, fs, 20, harmonics=1, sidebands=1)
    read = dict(zip(zip(marks.kind, marks.order), read_marks(spec, marks)))
    assert read[("mesh", 0)] == pytest.approx(2.0, rel=1e-12)
    assert read[("sideband_a", 1)] == pytest.approx(0.3, rel=1e-12)
    assert read[("sideband_a", -1)] == pytest.approx(0.0, abs=1e-12)
    # a line half a bin off is found by a window of one bin, not by the nearest bin alone
    assert read_at(spec, fm + 0.6 * DF, half_width=DF)[0] == pytest.approx(2.0, rel=1e-12)
    assert np.isnan(read_at(spec, 1.0 / DT)[0])


@pytest.mark.parametrize("depth", [0.0, 0.1, 0.5, 0.9])
def test_sideband_energy_ratio_of_amplitude_modulation(depth):
    """(1 + m cos(2 pi fs t)) A cos(2 pi fm t): each first sideband is m/2 of the carrier,
    the others 0, so SER = m (and 0 without modulation)."""
    fs, fm = 10 * DF, 400 * DF
    x = 1.3 * (1 + depth * np.cos(2 * np.pi * fs * T)) * np.cos(2 * np.pi * fm * T + 0.4)
    spec = spectrum(x, DT)
    upper, lower = read_at(spec, [fm + fs, fm - fs]) / read_at(spec, fm)[0]
    assert (upper, lower) == (pytest.approx(depth / 2, abs=1e-12),) * 2
    assert sideband_energy_ratio(spec, fm, fs) == pytest.approx(depth, abs=1e-12)
    assert sideband_energy_ratio(spec, fm, fs, sidebands=1) == pytest.approx(depth, abs=1e-12)


@pytest.mark.parametrize("depth", [0.0, 0.3, 0.9])
def test_sideband_energy_ratio_on_the_averages_orders_has_no_leakage(depth):
    """The same modulation over one revolution of a 20-tooth gear: on the average's orders
    SER = m exactly, where a spectrum of that one revolution, its bins a shaft frequency
    apart, reads the mesh tone's leakage into the sidebands (Hann: half the tone each side)."""
    from spurdyn.diagnostics import order_sideband_energy_ratio

    n, z = 512, 20
    theta = 2 * np.pi * np.arange(n) / n
    x = 1.3 * (1 + depth * np.cos(theta)) * np.cos(z * theta + 0.4)
    assert order_sideband_energy_ratio(x, z) == pytest.approx(depth, abs=1e-12)
    spec = spectrum(x, 1.0 / n)                         # one revolution a second: shaft on bin 1
    assert abs(sideband_energy_ratio(spec, z, 1.0, sidebands=1) - depth) > 0.3
    assert np.isnan(order_sideband_energy_ratio(x[:64], 30))     # the sidebands beyond its orders


# -- 3. the time-synchronous average -------------------------------------------------------

@pytest.mark.parametrize("revolutions", [16, 64])
def test_tsa_removes_non_synchronous_noise_as_one_over_root_r(revolutions):
    """White noise of variance s^2 sampled on the average's grid: each point of the average
    carries noise of variance s^2/R, so R sum(e^2)/s^2 is chi-square with N degrees of
    freedom; it lies inside the two-sided 1e-6 quantiles (fixed seed)."""
    n, sigma = 128, 0.7
    theta = 2 * np.pi * np.arange(n * revolutions + 1) / n
    x = mesh(theta) + np.random.default_rng(revolutions).normal(0.0, sigma, theta.size)
    avg = synchronous_average(x, theta, n)
    assert avg.revolutions == revolutions
    statistic = revolutions * np.sum((avg.signal - mesh(avg.angle)) ** 2) / sigma ** 2
    assert chi2.ppf(1e-6, n) < statistic < chi2.ppf(1 - 1e-6, n)


def test_tsa_passes_a_tone_between_orders_as_mcfaddens_comb():
    """A tone at shaft order q + d averaged over R turns keeps |sin(pi R d)/(R sin(pi d))|."""
    n, revolutions, order = 64, 10, 5.3
    theta = 2 * np.pi * np.arange(n * revolutions + 1) / n
    avg = synchronous_average(np.cos(order * theta + 0.7), theta, n)
    basis = np.column_stack([np.cos(order * avg.angle), np.sin(order * avg.angle)])
    amplitude = np.hypot(*np.linalg.lstsq(basis, avg.signal, rcond=None)[0])
    d = order - 5
    assert amplitude == pytest.approx(abs(math.sin(math.pi * revolutions * d)
                                          / (revolutions * math.sin(math.pi * d))), rel=1e-9)


def test_tsa_of_a_waveform_locked_to_a_varying_speed_shaft():
    """x = g(theta(t)) with the speed swinging +-30 % (7.3 Hz, not synchronous), sampled
    uniformly in time: the average recovers g within the complete cubic spline's bound
    5/384 h^4 max|g''''| (Hall & Meyer 1976), h the largest angle step; averaging
    as if the speed were constant does not."""
    f0 = 50.0
    w0, wm = 2 * np.pi * f0, 2 * np.pi * 7.3
    dt = 1.0 / (f0 * 200)                                # 200 samples a turn on average
    t = np.arange(int(20 / (f0 * dt))) * dt - 0.3 / f0
    theta = w0 * t + 0.3 * w0 / wm * (1 - np.cos(wm * t))
    orders = ((1, 1.0, 0.2), (5, 0.5, 1.0), (17, 0.3, -0.4))

    def g(th):
        return sum(a * np.cos(q * th + p) for q, a, p in orders)

    avg = synchronous_average(g(theta), theta, 256)
    h = np.max(np.diff(theta))
    bound = 5.0 / 384.0 * h ** 4 * sum(a * q ** 4 for q, a, _ in orders)
    error = np.max(np.abs(avg.signal - g(avg.angle)))
    assert avg.revolutions == 19 and bound < 1e-3
    assert error <= bound
    constant = synchronous_average(g(theta), w0 * t, 256)     # the speed taken as constant
    assert np.max(np.abs(constant.signal - g(constant.angle))) > 100 * bound


def test_a_shaft_turning_backwards_averages_along_its_rotation():
    theta = -2 * np.pi * np.arange(64 * 3 + 1) / 64
    avg = synchronous_average(np.cos(3 * theta) + np.sin(2 * theta), theta, 64)
    assert avg.revolutions == 3
    assert avg.signal == pytest.approx(np.cos(3 * avg.angle) - np.sin(2 * avg.angle), abs=1e-12)


def test_regular_residual_and_difference_signals_split_the_orders():
    side = 0.2 * np.cos((TEETH + 1) * THETA)          # a first-order sideband
    other = 0.1 * np.cos(7 * THETA)                   # an order neither mesh nor shaft 1-2
    y = mesh(THETA) + side + other + 0.05
    assert regular_signal(y, TEETH) == pytest.approx(mesh(THETA) + 0.05, abs=1e-12)
    assert residual_signal(y, TEETH) == pytest.approx(side + other, abs=1e-12)
    assert difference_signal(y, TEETH) == pytest.approx(other, abs=1e-12)
    a = order_amplitudes(y)
    assert (a[0], a[1], a[TEETH], a[2 * TEETH]) == pytest.approx((0.05, 0.3, 1.0, 0.4), rel=1e-12)


# -- 4. indicators ---------------------------------------------------------------------------

def test_sine_rms_kurtosis_crest_factor():
    """Ten whole periods, 64 samples each (the peaks sampled): A/sqrt(2), 3/2, sqrt(2)."""
    x = 2.5 * np.sin(2 * np.pi * np.arange(640) / 64)
    assert rms(x) == pytest.approx(2.5 / math.sqrt(2), rel=1e-12)
    assert kurtosis(x) == pytest.approx(1.5, rel=1e-12)
    assert crest_factor(x) == pytest.approx(math.sqrt(2), rel=1e-12)


def test_gaussian_kurtosis_is_three_within_its_sampling_error():
    """The sample kurtosis of n Gaussian values has standard error sqrt(24/n): 5 of them."""
    n = 20_000
    x = np.random.default_rng(7).normal(3.0, 2.0, n)
    assert abs(kurtosis(x) - 3.0) < 5 * math.sqrt(24 / n)


def test_fm0_closed_forms():
    """cos(z t) + a cos(2 z t), a <= 1/4: peak 1 + a at 0, trough a - 1 at pi/z, so
    FM0 = 2/(1 + a); a pure mesh tone (a = 0) gives 2, whatever its offset."""
    n = 2 * TEETH * 24                           # peaks and troughs on the grid
    th = 2 * np.pi * np.arange(n) / n
    for a in (0.0, 0.1, 0.25):
        y = 4.0 + np.cos(TEETH * th) + a * np.cos(2 * TEETH * th)
        assert fm0(y, TEETH) == pytest.approx(2.0 / (1.0 + a), rel=1e-12)
    assert math.isnan(fm0(np.cos(5 * th), TEETH))          # no mesh harmonic but rounding


def test_fm4_healthy_is_three_and_a_tooth_pulse_raises_it():
    """Mesh harmonics plus Gaussian noise: the difference signal is Gaussian, FM4 = 3 within
    5 standard errors sqrt(24/N). One tooth's pulse a revolution: FM4 above 10."""
    noise = 0.05 * np.random.default_rng(3).normal(size=POINTS)
    healthy = fm4(mesh(THETA) + noise, TEETH)
    assert abs(healthy - 3.0) < 5 * math.sqrt(24 / POINTS)
    assert fm4(mesh(THETA) + noise + tooth_pulse(THETA), TEETH) > 10.0
    assert math.isnan(fm4(mesh(THETA), TEETH))        # nothing left but rounding


def test_na4_single_record_is_the_residuals_kurtosis():
    y = mesh(THETA) + tooth_pulse(THETA) + 0.02 * np.random.default_rng(5).normal(size=POINTS)
    assert na4(y, TEETH) == pytest.approx(kurtosis(residual_signal(y, TEETH)), rel=1e-12)
    assert na4([y], TEETH) == na4(y, TEETH)


def test_na4_normalises_by_the_running_mean_variance():
    """Records c_j r: NA4_M = K(r) c_M^4 / (mean_{j<=M} c_j^2)^2."""
    r = mesh(THETA) + tooth_pulse(THETA) + 0.02 * np.random.default_rng(6).normal(size=POINTS)
    c = np.array([1.0, 1.5, 3.0])
    k = kurtosis(residual_signal(r, TEETH))
    expected = k * c ** 4 / (np.cumsum(c ** 2) / np.arange(1, 4)) ** 2
    assert na4_trend([cj * r for cj in c], TEETH) == pytest.approx(expected, rel=1e-12)


# -- 5. invariances ----------------------------------------------------------------------------

def faulty(seed: int) -> np.ndarray:
    return (mesh(THETA) + tooth_pulse(THETA)
            + 0.03 * np.random.default_rng(seed).normal(size=POINTS))


def indicators(y: np.ndarray) -> np.ndarray:
    return np.array([kurtosis(y), crest_factor(y), fm0(y, TEETH), fm4(y, TEETH),
                     na4([0.5 * y, y], TEETH)])


@HYPOTHESIS
@given(scale=st.floats(1e-3, 1e3) | st.floats(-1e3, -1e-3), seed=st.integers(0, 3))
def test_indicators_do_not_depend_on_the_scale(scale, seed):
    y = faulty(seed)
    assert indicators(scale * y) == pytest.approx(indicators(y), rel=1e-9)


@HYPOTHESIS
@given(delay=st.integers(0, POINTS - 1), start=st.integers(0, POINTS - 1))
def test_a_shift_in_time_leaves_the_average_indicators_unchanged(delay, start):
    """The record of a uniformly turning shaft (N samples a turn), its signal delayed by
    ``delay`` samples and started ``start`` samples later: its average is the same one
    turned, and its indicators are the same."""
    theta = 2 * np.pi * np.arange(6 * POINTS) / POINTS
    base = mesh(theta) + tooth_pulse(theta)
    shifted_angle = theta - 2 * np.pi * delay / POINTS
    moved = mesh(shifted_angle) + tooth_pulse(shifted_angle)
    ref = synchronous_average(base, theta, POINTS).signal
    avg = synchronous_average(moved[start:], theta[start:], POINTS).signal
    assert avg == pytest.approx(np.roll(ref, delay), abs=1e-12)
    assert indicators(avg) == pytest.approx(indicators(ref), rel=1e-9)


# -- 6. refusals ------------------------------------------------------------------------------

def refused(key: str, call, *args, **kwargs) -> InputError:
    with pytest.raises(InputError) as err:
        call(*args, **kwargs)
    assert err.value.field == key, err.value
    return err.value


def test_bad_inputs_are_refused_naming_the_argument():
    theta = np.linspace(0.1, 0.1 + 1.5 * 2 * np.pi, 300)      # 1.5 turns, no whole one
    err = refused("angle", synchronous_average, np.ones(300), theta, 64)
    assert "no whole one" in err.reason
    refused("angle", synchronous_average, np.ones(300), np.r_[theta[:150], theta[:150]], 64)
    refused("angle", synchronous_average, np.ones(300), theta[:200], 64)
    refused("points", synchronous_average, np.ones(300), 10 * theta, 2)
    refused("signal", synchronous_average, np.r_[np.ones(299), np.nan], 10 * theta, 64)
    refused("dt", spectrum, np.ones(16), 0.0)
    refused("window", spectrum, np.ones(16), 1e-3, "no-such-window")
    refused("signal", spectrum, np.ones((4, 4)), 1e-3)
    refused("teeth", fm4, np.ones(64), 40)
    refused("teeth", fm0, np.ones(64), 0)
    refused("records", na4, [np.ones(64), np.ones(32)], 5)
    refused("records", na4, [], 5)
    refused("records", na4, 3.0, 5)
    refused("z_a", mesh_marks, 10.0, 5.0, 0)
    refused("f_b", mesh_marks, 10.0, -5.0, 20)
    refused("sidebands", sideband_energy_ratio, spectrum(np.ones(64), 1e-3), 400.0, 100.0)
    refused("near", read_tone, spectrum(np.ones(64), 1e-3), 5000.0)
