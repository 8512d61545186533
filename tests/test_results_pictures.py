"""The pictures a run leaves (the contact force's, the overlay, the GIF), its tooth frames
and ParaView files, and a run's root stress and ISO figures beside it, on synthetic results
shaped like the solver's (``run_helpers.fake_simulate``; split from test_results_io.py)."""

from __future__ import annotations

import xml.etree.ElementTree as ET

import meshio
import numpy as np
import pytest

from spurdyn.results.io import load_run, summarize, tooth_frames, write_run
from run_helpers import (  # noqa: F401 (short_case, run_dir: fixtures)
    PNG_MAGIC, run_dir, short_case,
)


# -- tooth frames, ParaView, GIF -------------------------------------------------------

def test_tooth_frames_recover_the_elastic_part(run_dir):
    d, _, _ = run_dir
    frames = tooth_frames(load_run(d))
    assert frames.n_frames >= 3
    # The first frame is the undeformed start: no elastic displacement, no stress.
    for g in (0, 1):
        assert np.abs(frames.elastic(g, 0)).max() < 1e-15
        assert frames.von_mises(g, 0).max() < 1e-3
    last = frames.n_frames - 1
    for g in (0, 1):
        e = frames.elastic(g, last)
        assert np.abs(e[:, 0]).max() == pytest.approx(2e-7, rel=1e-6)
        assert np.abs(e[:, 1]).max() < 1e-15
        assert frames.von_mises(g, last).max() > 1e3
        # Positions: the rigid rotation of the start, plus the elastic part.
        np.testing.assert_allclose(frames.positions(g, last, 1.0),
                                   frames.X0[g] + frames.u[g][last], atol=1e-15)


def test_vtu_series(run_dir):
    d, result, _ = run_dir
    root = ET.parse(d / "result.pvd").getroot()
    sets = root.findall("./Collection/DataSet")
    assert len(sets) == len(result.frame_time)
    assert float(sets[-1].get("timestep")) == pytest.approx(result.frame_time[-1])
    m = meshio.read(d / sets[-1].get("file"))
    assert m.cells[0].type == "quad8"
    assert {"displacement", "elastic_displacement"} <= set(m.point_data)
    assert {"von_mises", "gear"} <= set(m.cell_data)
    assert m.points.shape[1] == 3


@pytest.mark.slow
def test_animation_gif(tmp_path, run_dir):
    from spurdyn.results.animate import animate_run

    d, _, _ = run_dir
    gif = animate_run(load_run(d), tmp_path / "mesh.gif", max_frames=3, fps=5)
    assert gif.read_bytes()[:6] == b"GIF89a"


@pytest.fixture(scope="module")
def loaded_run(tmp_path_factory):
    """Fig. 8 through its first 9 degrees (the load is on), with a frame every 100 steps."""
    from spurdyn.case import resolve_cases
    from spurdyn.simulators import MODELS

    case = resolve_cases("paper-fig8", {"run.angle_deg": 9.0})[0]
    d = tmp_path_factory.mktemp("loaded")
    write_run(MODELS["fe"](case.pair, case.run), case, d)
    return load_run(d)


@pytest.mark.slow
def test_animation_scale_shows_the_fillet_and_the_view_follows_the_teeth(loaded_run):
    """The colour scale is set by the fillets (the contact's peak above it saturates), so
    the fillet elements spread over the scale instead of sitting in one flat colour; each
    frame's view is the box of that frame's teeth."""
    from spurdyn.results.animate import (FILLET_SCALE, _OUTLINE, fillet_elements, frame_view,
                                         stress_scale)
    from spurdyn.results.frames import tooth_frames

    frames = tooth_frames(loaded_run)
    meshes, pair = frames.meshes, frames.case.pair
    fillets = [fillet_elements(m.nodes, m.elements, np.concatenate([m.right_side, m.left_side]),
                               g.form_radius) for m, g in zip(meshes, (pair.gear_a, pair.gear_b))]
    for m, f in zip(meshes, fillets):     # both fillets, at the bottom of the tooth only
        assert 2 <= f.size < m.n_elements / 2
        assert np.hypot(*m.nodes[m.elements[f]].reshape(-1, 2).T).min() < pair.gear_a.form_radius
    stress = [[frames.von_mises(g, k) for g in (0, 1)] for k in range(frames.n_frames)]
    vmax = stress_scale(stress, fillets)
    peak_fillet = max(float(s[g][fillets[g]].max()) for s in stress for g in (0, 1))
    assert vmax == pytest.approx(FILLET_SCALE * peak_fillet)
    assert vmax < max(float(np.nanmax(s[g])) for s in stress for g in (0, 1))  # contact saturates
    k = int(np.argmax([max(s[0][fillets[0]].max(), s[1][fillets[1]].max()) for s in stress]))
    # the view of a frame holds its teeth and little more
    polys = [frames.positions(g, k)[meshes[g].elements[:, _OUTLINE]] for g in (0, 1)]
    (x0, x1), (y0, y1) = frame_view(polys)
    pts = np.concatenate([p.reshape(-1, 2) for p in polys])
    assert x0 < pts[:, 0].min() and pts[:, 0].max() < x1 and y0 < pts[:, 1].min() and pts[:, 1].max() < y1
    size = max(np.ptp(pts[:, 0]), np.ptp(pts[:, 1]))
    assert max(x1 - x0, y1 - y0) < 1.1 * size


@pytest.mark.slow
def test_a_run_keeps_its_root_stress_and_iso_beside_it(loaded_run):
    from spurdyn.iso6336.rating import iso_pair, rate
    from spurdyn.results.frames import case_from_run

    ds = loaded_run
    assert ds["root_stress"].dims == ("frame", "gear") and ds["root_stress"].attrs["units"] == "Pa"
    hi = ds["root_stress"].values
    # the loaded fillet's stress follows the contact force of the frame (quasi-static run)
    force = np.interp(ds["frame_time"].values, ds["time"].values, ds["contact_force"].values)
    assert np.corrcoef(force, hi[:, 0])[0, 1] > 0.95
    assert np.all(ds["root_stress_compressive"].values <= hi)
    s = summarize(ds)
    assert s["root_stress_max_Pa"][0] == pytest.approx(float(np.nanmax(hi[:, 0])))
    case = case_from_run(ds)
    iso = rate(iso_pair(case.pair), case.run.torque)
    assert s["iso6336_sigma_F0_Pa"] == pytest.approx(list(iso.sigma_f0))
    assert s["iso6336_sigma_H0_Pa"] == pytest.approx(iso.sigma_h0)
    pos = s["root_stress_max_position_m"][0]
    assert case.pair.gear_a.root_radius < pos < case.pair.gear_a.form_radius


def test_stress_scale_without_fillet_stress_falls_back_to_the_largest():
    from spurdyn.results.animate import stress_scale

    zero = [np.zeros(4), np.zeros(4)]
    hot = [np.array([0.0, 0.0, 0.0, 7.0]), np.array([np.nan, 0.0, 2.0, 0.0])]
    fillets = [np.array([0, 1]), np.array([0, 1])]
    assert stress_scale([zero, hot], fillets) == 7.0
    assert stress_scale([zero], fillets) == 1.0


def test_overlay_picture(tmp_path, run_dir):
    from spurdyn.results.plots import plot_contact_force

    d, _, _ = run_dir
    png = plot_contact_force([load_run(d), load_run(d)], tmp_path / "two.png")
    assert png.read_bytes()[:8] == PNG_MAGIC


def test_picture_as_drawn_the_plain_way(tmp_path, run_dir):
    """The quicker layout (no layout engine left for savefig to run again; one run's
    legend, inside the axes, left out of it) gives the same picture, to the byte, as
    ``Figure.tight_layout`` with everything in the layout."""
    from matplotlib.figure import Figure

    from spurdyn.results import plots

    d, _, _ = run_dir
    runs = [load_run(d)]
    quick = plots.plot_contact_force(runs, tmp_path / "quick.png", title="t").read_bytes()
    fig = Figure(figsize=(8, 4.8), dpi=120)
    ax = fig.subplots()
    plots.draw_contact_force(ax, runs)
    ax.set_title("t", fontsize=10)
    fig.tight_layout()
    fig.savefig(tmp_path / "plain.png")
    assert (tmp_path / "plain.png").read_bytes() == quick


def test_prefetch_draws_a_picture_of_the_run_kind_and_leaves_nothing(tmp_path, monkeypatch):
    """The writers' warm-up (spurdyn.results.prefetch, a thread during the run) writes a
    NetCDF file and a picture like the run's, in a folder of its own that it removes."""
    import tempfile

    from spurdyn.results import prefetch

    monkeypatch.setattr(tempfile, "tempdir", str(tmp_path))
    prefetch.load()
    assert list(tmp_path.iterdir()) == []


@pytest.mark.slow
def test_the_elastic_part_of_all_frames_at_once_is_each_frames(loaded_run):
    from spurdyn.results.frames import tooth_frames

    frames = tooth_frames(loaded_run)
    for g in (0, 1):
        every = frames.elastic_all(g)
        for k in (0, frames.n_frames // 2, frames.n_frames - 1):
            # a difference of positions ~0.05 m: round-off of a few 1e-17 m either way
            np.testing.assert_allclose(every[k], frames.elastic(g, k), rtol=0, atol=1e-16)


def test_prefetch_shortens_the_switch_interval_while_it_loads_and_restores_it(monkeypatch):
    """While the writers load (a thread holding the GIL), the time loop's thread takes the GIL
    back within :data:`prefetch.SWITCH_INTERVAL`; Python's own interval comes back after."""
    import sys
    import threading

    from spurdyn.results import prefetch

    seen: list[float] = []
    go = threading.Event()

    def load() -> None:
        go.wait(10)
        seen.append(sys.getswitchinterval())

    monkeypatch.setattr(prefetch, "load", load)
    default = sys.getswitchinterval()
    try:
        thread = prefetch.start()
        during = sys.getswitchinterval()
        go.set()
        prefetch.wait(thread)
        # Python keeps the interval in whole microseconds
        assert during == seen[0] == pytest.approx(prefetch.SWITCH_INTERVAL, rel=1e-6)
        assert during < default
        assert sys.getswitchinterval() == default
    finally:
        sys.setswitchinterval(default)


def test_overlapping_prefetches_restore_pythons_interval_whichever_ends_first(monkeypatch):
    """Two loads at once (a run that never reached ``wait`` before the next): the first to
    end must not put back the second's shortened interval as the default, nor the second the
    first's; Python's own comes back when the last ends."""
    import sys
    import threading

    from spurdyn.results import prefetch

    gates = [threading.Event(), threading.Event()]
    calls = iter(gates)

    def load() -> None:
        next(calls).wait(10)

    monkeypatch.setattr(prefetch, "load", load)
    default = sys.getswitchinterval()
    try:
        first, second = prefetch.start(), prefetch.start()
        gates[0].set()
        prefetch.wait(first)
        assert sys.getswitchinterval() == pytest.approx(prefetch.SWITCH_INTERVAL, rel=1e-6)
        gates[1].set()
        prefetch.wait(second)
        assert sys.getswitchinterval() == default
    finally:
        sys.setswitchinterval(default)
