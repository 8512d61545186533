"""The figures of docs/diagnostics.md: the windows' reading errors, the average's noise and
resampling errors, and the indicators of a synthetic gearbox record, healthy and faulty.

Usage::

    python scripts/diagnostics_figures.py        # print the page's tables (markdown), ~2 s

Every signal is synthetic with a known answer; the seeds are fixed.
"""

from __future__ import annotations

import math

import numpy as np

from spurdyn.diagnostics import (crest_factor, fm0, fm4, kurtosis, na4_trend, read_tone, rms,
                                 scalloping_loss, sideband_energy_ratio, spectrum,
                                 synchronous_average, window_response)

Z_A, Z_B = 23, 31                 # teeth of the gear on shaft A (averaged) and of its mate
F_A = 50.0                        # shaft A's mean speed (Hz)
SAMPLES_PER_TURN = 256
POINTS = 512


def windows() -> None:
    """Nearest-bin and between-bin reading errors of a unit sine, by window and offset."""
    n, dt = 4096, 1e-4
    df, t = 1.0 / (n * dt), np.arange(n) * 1e-4
    print("| window | scalloping loss at 1/2 bin | worst nearest-bin error, 0..1/2 bin |"
          " read_tone amplitude error (worst of d = 0.13, 0.25, 0.37, 0.5) | frequency error |")
    print("|---|---|---|---|---|")
    for window in ("boxcar", "hann", "flattop"):
        worst = np.max(np.abs(1 - window_response(window, n, np.linspace(0, 0.5, 51))))
        amp = freq = 0.0
        for d in (0.13, 0.25, 0.37, 0.5):
            f = (300 + d) * df
            tone = read_tone(spectrum(np.cos(2 * np.pi * f * t - 1.1), dt, window), f)
            amp, freq = max(amp, abs(tone.amplitude - 1)), max(freq, abs(tone.frequency / f - 1))
        print(f"| {window} | {scalloping_loss(window, n):.4g} | {worst:.4g} | {amp:.2g} | {freq:.2g} |")


def angle_history(revolutions: float, swing: float, dt: float) -> tuple[np.ndarray, np.ndarray]:
    """Shaft A's angle: mean speed F_A, the speed swinging +-swing at 3.1 Hz."""
    w0, wm = 2 * np.pi * F_A, 2 * np.pi * 3.1
    t = np.arange(int(revolutions / (F_A * dt))) * dt
    return t, w0 * t + swing * w0 / wm * (1 - np.cos(wm * t))


def gearbox(theta_a: np.ndarray, fault: float, seed: int, noise: float = 0.3) -> np.ndarray:
    """A gearbox record: two mesh harmonics, shaft A's order 1, gear B's once-a-turn (order
    23/31 of A, not synchronous), Gaussian noise, and ``fault`` times one tooth's pulse on A."""
    theta_b = theta_a * Z_A / Z_B
    width = 2 * np.pi / Z_A / 6
    pulse = np.exp(-0.5 * (np.angle(np.exp(1j * (theta_a - 1.0))) / width) ** 2)
    rng = np.random.default_rng(seed)
    return (np.cos(Z_A * theta_a) + 0.4 * np.cos(2 * Z_A * theta_a + 0.5)
            + 0.2 * np.cos(theta_a + 0.3) + 0.3 * np.cos(theta_b) + fault * pulse
            + noise * rng.normal(size=theta_a.size))


def indicators() -> None:
    """The indicators of the average of 40 turns at +-5 % speed, as the fault grows."""
    dt = 1.0 / (F_A * SAMPLES_PER_TURN)
    t, theta = angle_history(40.2, 0.05, dt)
    averages, rows = [], []
    for seed, fault in enumerate((0.0, 0.0, 0.25, 0.5, 1.0)):
        x = gearbox(theta, fault, seed)
        avg = synchronous_average(x, theta, POINTS)
        averages.append(avg.signal)
        y = avg.signal
        rows.append((fault, avg.revolutions, rms(x), kurtosis(x), rms(y), kurtosis(y),
                     crest_factor(y), fm0(y, Z_A), fm4(y, Z_A)))
    trend = na4_trend(averages, Z_A)
    print("| pulse height | turns averaged | record RMS | record kurtosis | TSA RMS | "
          "TSA kurtosis | TSA crest | FM0 | FM4 | NA4 (records so far) |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for row, n4 in zip(rows, trend):
        f, r, *vals = row
        print(f"| {f} | {r} | " + " | ".join(f"{v:.3f}" for v in vals) + f" | {n4:.3f} |")


def sideband_ratio() -> None:
    """SER of the record's spectrum at constant speed, and of amplitude modulation."""
    dt = 1.0 / (F_A * SAMPLES_PER_TURN)
    t, theta = angle_history(160, 0.0, dt)     # 160 turns: bins of F_A / 160
    spec_h = spectrum(gearbox(theta, 0.0, 11), dt)
    spec_f = spectrum(gearbox(theta, 1.0, 12), dt)
    f_mesh = Z_A * F_A
    print("| record | SER (6 sidebands of f_A around f_m) | SER (1 sideband) |")
    print("|---|---|---|")
    for name, spec in (("healthy", spec_h), ("pulse 1.0", spec_f)):
        print(f"| {name} | {sideband_energy_ratio(spec, f_mesh, F_A):.4f} | "
              f"{sideband_energy_ratio(spec, f_mesh, F_A, sidebands=1):.4f} |")
    m = 0.3
    am = (1 + m * np.cos(2 * np.pi * F_A * t)) * np.cos(2 * np.pi * f_mesh * t)
    print(f"| AM depth {m}, no noise | {sideband_energy_ratio(spectrum(am, dt), f_mesh, F_A):.6f} | "
          f"{sideband_energy_ratio(spectrum(am, dt), f_mesh, F_A, sidebands=1):.6f} |")


def main() -> None:
    print("## windows\n")
    windows()
    print(f"\nHann's closed form 1 - 8/(3 pi) = {1 - 8 / (3 * math.pi):.6f}\n")
    print("## indicators, 40 turns at +-5 % speed\n")
    indicators()
    print("\n## sideband energy ratio\n")
    sideband_ratio()


if __name__ == "__main__":
    main()
