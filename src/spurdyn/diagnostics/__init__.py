"""Gear diagnostics: spectra, spectral marks, time-synchronous averages and condition
indicators of a signal sampled at a fixed time step (NumPy and SciPy only).

What the dynamic models will feed it: a hub's angular acceleration, the mesh force or a
bearing force over several revolutions of a gear with a fault. The definitions, choices
and checks are in ``docs/diagnostics.md``; :mod:`spurdyn.results.vibration` reads it for a
sector run's summary.
"""

from spurdyn.diagnostics.indicators import (crest_factor, fm0, fm4, kurtosis, na4, na4_trend,
                                            rms)
from spurdyn.diagnostics.marks import (KINDS, Marks, mesh_marks, read_at, read_marks,
                                       sideband_energy_ratio)
from spurdyn.diagnostics.spectrum import (Spectrum, Tone, read_tone, scalloping_loss, spectrum,
                                          window_response)
from spurdyn.diagnostics.tsa import (SHAFT_ORDERS, SynchronousAverage, difference_signal,
                                     mesh_orders, order_amplitudes, order_sideband_energy_ratio,
                                     regular_signal, residual_signal, synchronous_average)

__all__ = ["KINDS", "SHAFT_ORDERS", "Marks", "Spectrum", "SynchronousAverage", "Tone",
           "crest_factor", "difference_signal", "fm0", "fm4", "kurtosis", "mesh_marks",
           "mesh_orders", "na4", "na4_trend", "order_amplitudes", "order_sideband_energy_ratio", "read_at", "read_marks",
           "read_tone", "regular_signal", "residual_signal", "rms", "scalloping_loss",
           "sideband_energy_ratio", "spectrum", "synchronous_average", "window_response"]
