"""Where a gear pair's spectrum has its lines: mesh harmonics and their shaft sidebands.

Gear A turns at ``f_a``, gear B at ``f_b`` (Hz); with ``z_a`` teeth on A the mesh frequency
is ``f_m = z_a f_a`` (``= z_b f_b``). A fault on a gear modulates the mesh at that gear's
shaft frequency, so lines appear at ``k f_m +- j f_a`` and ``k f_m +- j f_b``. The sideband
energy ratio (SER) sums the sideband amplitudes around a mesh harmonic over the harmonic's
amplitude. ``docs/diagnostics.md``, sections 2 and 5.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from spurdyn.diagnostics.checks import count, positive
from spurdyn.diagnostics.spectrum import Spectrum
from spurdyn.errors import InputError

#: The kinds of mark: a mesh harmonic, a sideband spaced by gear A's or gear B's shaft.
KINDS = ("mesh", "sideband_a", "sideband_b")


@dataclass(frozen=True)
class Marks:
    """A table of spectral marks, one row per mark.

    Attributes
    ----------
    frequency
        Where the mark is (Hz).
    kind
        One of :data:`KINDS` per row.
    harmonic
        ``k``: the mesh harmonic the mark belongs to (1 = the mesh frequency).
    order
        ``j``: signed sideband order (``-J .. J``), 0 for the harmonic itself.
    """

    frequency: NDArray[np.float64]
    kind: tuple[str, ...]
    harmonic: NDArray[np.int64]
    order: NDArray[np.int64]

    def __len__(self) -> int:
        return int(self.frequency.size)


def mesh_marks(f_a: float, f_b: float, z_a: int, harmonics: int = 3,
               sidebands: int = 3) -> Marks:
    """Mesh harmonics ``k f_m`` and sidebands ``k f_m +- j f_a``, ``k f_m +- j f_b``.

    Parameters
    ----------
    f_a, f_b
        Shaft frequencies of gears A and B (Hz).
    z_a
        Teeth on gear A (``f_m = z_a f_a``).
    harmonics
        ``K``: mesh harmonics ``k = 1 .. K``.
    sidebands
        ``J``: sideband orders ``j = 1 .. J`` on each side (0: harmonics only).

    Returns
    -------
    Marks
        Rows by harmonic, then shaft A's sidebands, then B's, each from ``-J`` to ``J``;
        a sideband at or below 0 Hz is left out.
    """
    fa, fb = positive(f_a, "f_a"), positive(f_b, "f_b")
    f_mesh = count(z_a, "z_a", 1) * fa
    K, J = count(harmonics, "harmonics", 1), count(sidebands, "sidebands", 0)
    rows: list[tuple[float, str, int, int]] = []
    orders = [j for j in range(-J, J + 1) if j != 0]
    for k in range(1, K + 1):
        rows.append((k * f_mesh, "mesh", k, 0))
        for kind, f_shaft in (("sideband_a", fa), ("sideband_b", fb)):
            rows += [(k * f_mesh + j * f_shaft, kind, k, j) for j in orders
                     if k * f_mesh + j * f_shaft > 0.0]
    f, kind, k, j = zip(*rows)
    return Marks(np.array(f), tuple(kind), np.array(k, dtype=np.int64),
                 np.array(j, dtype=np.int64))


def read_at(spec: Spectrum, frequency: ArrayLike, half_width: float = 0.0) -> NDArray[np.float64]:
    """Amplitudes of ``spec`` at ``frequency`` (Hz): the nearest bin, or the largest bin
    within ``+- half_width`` (Hz) if that is > 0. NaN above the spectrum's last bin or
    below 0 Hz (not read, not zero)."""
    f = np.atleast_1d(np.asarray(frequency, dtype=np.float64))
    if half_width < 0.0 or not np.isfinite(half_width):
        raise InputError("half_width", f"must be finite and >= 0 Hz, got {half_width!r}")
    df, last = spec.resolution, spec.frequency[-1]
    out = np.full(f.shape, np.nan)
    for i, fi in enumerate(f):
        if not (0.0 <= fi <= last + 0.5 * df):
            continue
        if half_width < 0.5 * df:
            out[i] = spec.amplitude[int(np.rint(fi / df))]
        else:
            lo = max(0, int(np.ceil((fi - half_width) / df)))
            hi = min(spec.amplitude.size - 1, int(np.floor((fi + half_width) / df)))
            out[i] = spec.amplitude[lo:hi + 1].max()
    return out


def read_marks(spec: Spectrum, marks: Marks, half_width: float = 0.0) -> NDArray[np.float64]:
    """The amplitude of ``spec`` at each of ``marks`` (:func:`read_at`), in the marks' order."""
    return read_at(spec, marks.frequency, half_width)


def sideband_energy_ratio(spec: Spectrum, f_mesh: float, f_shaft: float, sidebands: int = 6,
                          harmonic: int = 1, half_width: float = 0.0) -> float:
    """Sideband energy ratio around mesh harmonic ``k``:
    ``SER = sum_{j=1..J} (A(k f_m + j f_s) + A(k f_m - j f_s)) / A(k f_m)``.

    Six sidebands a side by default, as Hanna et al. (2011) define it. Amplitude
    modulation of depth ``m`` at ``f_s`` puts ``m/2`` of the carrier on each first
    sideband, so ``SER = m``.

    Parameters
    ----------
    spec
        The spectrum.
    f_mesh, f_shaft
        Mesh frequency and the shaft frequency the sidebands are spaced by (Hz).
    sidebands
        ``J``, sidebands counted on each side.
    harmonic
        ``k``, the mesh harmonic (1: the mesh frequency).
    half_width
        Reading band (:func:`read_at`); 0 reads the nearest bin.

    Returns
    -------
    float
        The ratio; NaN where the harmonic reads 0.
    """
    fm, fs = positive(f_mesh, "f_mesh"), positive(f_shaft, "f_shaft")
    J, k = count(sidebands, "sidebands", 1), count(harmonic, "harmonic", 1)
    centre = k * fm
    if centre - J * fs <= 0.0 or centre + J * fs > spec.frequency[-1]:
        raise InputError("sidebands", f"{J} sidebands of {fs} Hz around {centre} Hz reach "
                                      f"outside 0 .. {spec.frequency[-1]} Hz: ask for fewer, "
                                      "or sample finer")
    j = np.arange(1, J + 1)
    a = read_at(spec, np.concatenate([[centre], centre + j * fs, centre - j * fs]), half_width)
    return float(np.sum(a[1:]) / a[0]) if a[0] > 0.0 else float("nan")
