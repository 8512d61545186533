"""An animated GIF of a run: the two teeth meshing, deformation magnified, coloured by the
von Mises stress, with the contact-force trace beside them.

The view follows the teeth (each frame is filled by the two teeth), and the colour scale
is set by the fillets, not by the contact: the stress under a contact point is several
times the root's and would leave the root one flat colour. Elements above the scale
(under the contact) show its top colour, marked by the colour bar's arrow.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Callable

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import xarray as xr  # noqa: E402
from matplotlib.animation import FuncAnimation, PillowWriter  # noqa: E402
from matplotlib.collections import PolyCollection  # noqa: E402

from spurdyn.errors import InputError  # noqa: E402
from spurdyn.results.frames import ToothFrames, speeds_label, tooth_frames  # noqa: E402
from spurdyn.results.plots import draw_contact_force  # noqa: E402

# Outline of a Q8 element through its mid-side nodes: corner, mid, corner, ...
_OUTLINE = [0, 4, 1, 5, 2, 6, 3, 7]

#: The largest magnified elastic displacement, as a fraction of the tooth height.
AUTO_MAGNIFY_FRACTION = 0.08
#: Top of the colour scale, in the largest stress of the fillet elements over the run.
FILLET_SCALE = 1.5
#: Margin around the two teeth in each frame, as a fraction of the frame's larger side.
VIEW_PAD = 0.04


def fillet_elements(nodes: np.ndarray, elements: np.ndarray, outline: np.ndarray,
                    form_radius: float) -> np.ndarray:
    """Indices of the elements that touch an outline node below ``form_radius``: the fillets
    (and the root's corners), in the tooth's own frame."""
    low = outline[np.hypot(nodes[outline, 0], nodes[outline, 1]) < form_radius]
    return np.flatnonzero(np.isin(elements, low).any(axis=1))


def stress_scale(stress: list[list[np.ndarray]], fillets: list[np.ndarray]) -> float:
    """Top of the colour scale (the stresses' unit): :data:`FILLET_SCALE` times the largest
    fillet-element stress over all frames, or the largest stress of all if the fillets
    carry none (or no finite one)."""
    def top(select: Callable[[int], np.ndarray]) -> float:
        vals = [s[g][select(g)] for s in stress for g in (0, 1)]
        vals = [v[np.isfinite(v)] for v in vals]
        vals = [v for v in vals if v.size]
        return max((float(v.max()) for v in vals), default=0.0)

    fillet = top(lambda g: fillets[g])
    if fillet > 0.0:
        return FILLET_SCALE * fillet
    anywhere = top(lambda g: slice(None))
    return anywhere if anywhere > 0.0 else 1.0


def frame_view(polys: list[np.ndarray]) -> tuple[tuple[float, float], tuple[float, float]]:
    """``(xlim, ylim)`` around the finite points of one frame's teeth, padded."""
    pts = np.concatenate([p.reshape(-1, 2) for p in polys])
    pts = pts[np.isfinite(pts).all(axis=1)]
    if pts.size == 0:
        return (0.0, 1.0), (0.0, 1.0)
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    pad = VIEW_PAD * float((hi - lo).max())
    return (lo[0] - pad, hi[0] + pad), (lo[1] - pad, hi[1] + pad)


def auto_magnify(frames: ToothFrames) -> float:
    """A magnification that shows the largest elastic displacement as
    :data:`AUTO_MAGNIFY_FRACTION` of the tooth height (1 if the teeth do not deform)."""
    biggest = 0.0
    for k in range(frames.n_frames):
        for g in (0, 1):
            d = frames.elastic(g, k)
            if np.isfinite(d).all():
                biggest = max(biggest, float(np.hypot(d[:, 0], d[:, 1]).max()))
    gear = frames.case.pair.gear_a
    height = gear.tip_radius - gear.root_radius
    return AUTO_MAGNIFY_FRACTION * height / biggest if biggest > 0 else 1.0


def _frame_pictures(frames: ToothFrames, picks: np.ndarray, magnify: float,
                    progress: Callable[[int, int], None] | None
                    ) -> tuple[list[list[np.ndarray]], list[list[np.ndarray]]]:
    """The element outlines (mm) and von Mises stresses (MPa) of both teeth in each picked frame.

    Parameters
    ----------
    frames
        The run's tooth frames.
    picks
        The frames to draw.
    magnify
        Magnification of the elastic displacements.
    progress
        Called as ``progress(i, 2 * len(picks))`` before frame ``i``, if given.

    Returns
    -------
    polys, stress
        Per picked frame, per gear: the outlines ``(elements, 8, 2)`` and the stresses.
    """
    meshes = frames.meshes
    polys: list[list[np.ndarray]] = []
    stress: list[list[np.ndarray]] = []
    for i, k in enumerate(picks):
        if progress is not None:
            progress(i, 2 * len(picks))
        polys.append([frames.positions(g, k, magnify)[meshes[g].elements[:, _OUTLINE]] * 1e3
                      for g in (0, 1)])
        stress.append([frames.von_mises(g, k) / 1e6 for g in (0, 1)])
    return polys, stress


def _fillet_stress_scale(frames: ToothFrames, stress: list[list[np.ndarray]]) -> float:
    """Top of the colour scale (MPa) from the fillet elements of both teeth (:func:`stress_scale`).

    Parameters
    ----------
    frames
        The run's tooth frames (their meshes and gears).
    stress
        Per picked frame, per gear, the elements' stresses.

    Returns
    -------
    float
        The scale's top.
    """
    meshes = frames.meshes
    gears = (frames.case.pair.gear_a, frames.case.pair.gear_b)
    fillets = [fillet_elements(meshes[g].nodes, meshes[g].elements,
                               np.concatenate([meshes[g].right_side, meshes[g].left_side]),
                               gears[g].form_radius) for g in (0, 1)]
    return stress_scale(stress, fillets)


def _tooth_axes(fig: plt.Figure, ax_t: plt.Axes, polys: list[np.ndarray], stress: list[np.ndarray],
                vmax: float) -> tuple[list[PolyCollection], plt.Text]:
    """Draw the first frame's teeth on ``ax_t`` with a colour bar.

    Parameters
    ----------
    fig, ax_t
        The figure and its axes for the teeth.
    polys, stress
        The first frame's outlines and stresses, per gear.
    vmax
        Top of the colour scale.

    Returns
    -------
    coll, stamp
        The two gears' element collections and the axes' title (the time stamp).
    """
    coll = []
    for g in (0, 1):
        c = PolyCollection(polys[g], array=stress[g], cmap="viridis", clim=(0.0, vmax),
                           edgecolor="k", linewidth=0.2)
        ax_t.add_collection(c)
        coll.append(c)
    fig.colorbar(coll[0], ax=ax_t, label="von Mises stress (MPa)", shrink=0.8, extend="max")
    xlim, ylim = frame_view(polys)
    ax_t.set_xlim(*xlim)
    ax_t.set_ylim(*ylim)
    ax_t.set_aspect("equal", adjustable="datalim")
    ax_t.set_xlabel("x (mm)")
    ax_t.set_ylabel("y (mm)")
    return coll, ax_t.set_title("")


def _save_gif(fig: plt.Figure, anim: FuncAnimation, gif: Path, fps: int, n: int,
              progress: Callable[[int, int], None] | None) -> None:
    """Write the animation beside ``gif`` under a hidden name and rename it when whole.

    Parameters
    ----------
    fig
        The animation's figure, closed at the end (written or not).
    anim
        The animation.
    gif
        File to write.
    fps
        Frames per second.
    n
        The number of frames: ``progress(n + i, 2 n)`` reports frame ``i`` written.
    progress
        Called as the frames are written, if given.
    """
    tmp = gif.with_name(f".{gif.stem}.partial-{os.getpid()}{gif.suffix}")
    try:
        anim.save(tmp, writer=PillowWriter(fps=fps), progress_callback=None if progress is None
                  else (lambda i, total: progress(n + i, 2 * n)))
        tmp.replace(gif)
    finally:
        plt.close(fig)
        tmp.unlink(missing_ok=True)


def animate_run(ds: xr.Dataset, gif: str | Path, *, magnify: float | None = None,
                fps: int = 15, max_frames: int = 150,
                progress: Callable[[int, int], None] | None = None) -> Path:
    """Write an animated GIF of the tooth frames of a run.

    Parameters
    ----------
    ds
        The run (:func:`spurdyn.results.io.load_run`); it must hold tooth frames.
    gif
        File to write.
    magnify
        Magnification of the elastic displacements; default :func:`auto_magnify`.
    fps
        Frames per second of the GIF.
    max_frames
        At most this many frames, evenly picked from the run's.
    progress
        Called as ``progress(done, total)`` as the frames are prepared and drawn
        (``2 * total`` calls: stresses first, then the GIF).

    The GIF is written beside ``gif`` under a hidden name and renamed when whole, so an
    interrupted animation leaves no half GIF.
    """
    frames = tooth_frames(ds)
    if magnify is None:
        magnify = auto_magnify(frames)
    picks = np.unique(np.linspace(0, frames.n_frames - 1, min(max_frames, frames.n_frames))
                      .round().astype(int))

    # Stresses and outlines of every picked frame, and one colour scale for all.
    polys, stress = _frame_pictures(frames, picks, magnify, progress)
    vmax = _fillet_stress_scale(frames, stress)
    if not any(np.isfinite(p).all(axis=-1).any() for pair_ in polys for p in pair_):
        raise InputError("frame_u", "holds no finite displacements to draw")

    fig, (ax_t, ax_f) = plt.subplots(1, 2, figsize=(11, 5), dpi=90,
                                     gridspec_kw={"width_ratios": [1, 1.3]})
    coll, stamp = _tooth_axes(fig, ax_t, polys[0], stress[0], vmax)

    draw_contact_force(ax_f, [ds], legend=False)
    ax_f.set_title(f"{ds.attrs['case_name']}: {speeds_label(ds)}, displacements x {magnify:.3g}",
                   fontsize=9)
    cursor = ax_f.axvline(0.0, color="tab:red", lw=1.0)
    angle = ds["angle_deg"].values
    time = ds["time"].values
    fig.tight_layout()

    def draw(i: int) -> list:
        k = picks[i]
        for g in (0, 1):
            coll[g].set_verts(polys[i][g])
            coll[g].set_array(stress[i][g])
        xlim, ylim = frame_view(polys[i])     # the view follows the teeth
        ax_t.set_xlim(*xlim)
        ax_t.set_ylim(*ylim)
        a = float(np.interp(frames.time[k], time, angle)) if len(time) else 0.0
        cursor.set_xdata([a, a])
        stamp.set_text(f"t = {frames.time[k] * 1e6:.1f} us, A turned {a:.2f} deg")
        return [*coll, cursor, stamp]

    anim = FuncAnimation(fig, draw, frames=len(picks), blit=False)
    gif = Path(gif)
    n = len(picks)
    _save_gif(fig, anim, gif, fps, n, progress)
    if progress is not None:
        progress(2 * n, 2 * n)
    return gif
