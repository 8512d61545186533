"""Root stress along the fillets (spurdyn.model.root) of a quasi-statically loaded tooth."""

import math

import numpy as np
import pytest

from spurdyn.geometry.presets import PAPER_TORQUE, paper_pair
from spurdyn.model.root import fillet_nodes, peaks, root_surface
from spurdyn.model.stiffness import ToothCompliance
from spurdyn.model.tooth import build_tooth

PAIR = paper_pair()
GEAR = PAIR.gear_a


def _loaded(nx, ny, grading):
    """Tooth A clamped at its root under ISO's load: the static normal force at the outer
    point of single contact, on its right flank."""
    tooth = build_tooth(GEAR, nx, ny, grading)
    comp = ToothCompliance(tooth, "right")
    roll = max(PAIR.single_contact_roll_a)
    f_n = PAPER_TORQUE / GEAR.pitch_radius / math.cos(GEAR.pressure_angle)
    f = comp.load_vector(GEAR.base_radius * math.hypot(1.0, roll)) * f_n
    u = np.zeros_like(f)
    u[comp._free] = comp._lu.solve(f[comp._free])
    surface = root_surface(tooth.mesh, GEAR.form_radius, GEAR.material)
    return surface, surface.stress(u), u


def test_fillet_nodes_are_the_outline_below_the_form_radius():
    mesh = build_tooth(GEAR, 6, 20).mesh
    nodes, side = fillet_nodes(mesh, GEAR.form_radius)
    for k, outline in enumerate((mesh.right_side, mesh.left_side)):
        mine = nodes[side == k]
        np.testing.assert_array_equal(mine, outline[:mine.size])     # from the root upward
        r = np.hypot(*mesh.nodes[outline].T)
        assert r[mine.size - 1] < GEAR.form_radius <= r[mine.size]


def test_loaded_fillet_pulls_and_the_other_presses_and_stress_is_linear():
    surface, stress, u = _loaded(6, 20, 1.0)
    right, left = stress[surface.side == 0], stress[surface.side == 1]
    assert right.max() > 0.0 > left.min()
    assert right.max() > abs(right.min()) and abs(left.min()) > left.max()
    np.testing.assert_allclose(surface.stress(2.5 * u), 2.5 * stress, rtol=1e-12)
    np.testing.assert_allclose(surface.stress(np.stack([u, -u])), [stress, -stress], rtol=1e-12)


def test_peak_root_stress_converges_with_the_mesh():
    """Issue 17: the quasi-static peak root stress of the paper's pair changes by less than
    3 % between the two finest meshes (graded toward the outlines)."""
    peak = {}
    for nx, ny in ((12, 40), (16, 56)):
        surface, stress, _ = _loaded(nx, ny, 6.0)
        hi, r_hi, lo, _ = peaks(stress[None], surface.radius)
        peak[nx] = hi[0]
        # not at the clamped bottom corner: in the fillet above it
        assert surface.radius.min() < r_hi[0] < GEAR.form_radius
    assert abs(peak[12] / peak[16] - 1.0) < 0.03


def test_peaks_skip_missing_rows():
    s = np.array([[1.0, 3.0, -2.0], [np.nan, np.nan, np.nan]])
    hi, r_hi, lo, r_lo = peaks(s, np.array([10.0, 11.0, 12.0]))
    np.testing.assert_array_equal(hi[:1], [3.0]) and np.testing.assert_array_equal(r_hi[:1], [11.0])
    np.testing.assert_array_equal(lo[:1], [-2.0]) and np.testing.assert_array_equal(r_lo[:1], [12.0])
    assert np.isnan(hi[1]) and np.isnan(r_lo[1])


def test_peaks_of_finite_rows_are_the_masked_paths():
    """Every row finite (a run's kept samples) takes the path without masks: the same
    numbers as the rows among one without a finite value (the masked path), and the
    largest and smallest by hand."""
    rng = np.random.default_rng(5)
    s, r = rng.standard_normal((300, 22)), np.linspace(0.03, 0.035, 22)
    fast = peaks(s, r)
    masked = peaks(np.vstack([s, np.full((1, 22), np.nan)]), r)
    for a, b in zip(fast, masked):
        assert a.shape == (300,)
        np.testing.assert_array_equal(a, b[:300])
    np.testing.assert_array_equal(fast[0], s.max(axis=1))
    np.testing.assert_array_equal(fast[3], r[s.argmin(axis=1)])


def _case_with_allowables(flim=430e6, hlim=1500e6):
    from spurdyn.case import case_from_dict

    gear = {"teeth": 25, "module": 0.003, "pressure_angle_deg": 20.0, "face_width": 0.03,
            "material": {"young": 210e9, "poisson": 0.3, "density": 7800.0}}
    if flim is not None:
        gear["material"]["sigma_flim"] = flim
    if hlim is not None:
        gear["material"]["sigma_hlim"] = hlim
    data = {"gear_a": gear, "gear_b": {**gear, "teeth": 50},
            "run": {"speed_a_rpm": 3000.0, "torque": 150.0}}
    return case_from_dict(data, check_step=False)


def test_safety_factors_from_the_model_peaks_and_from_iso():
    from spurdyn.iso6336.rating import dynamic_factor_at, iso_pair, rate
    from spurdyn.results.stress import safety_figures

    case = _case_with_allowables()
    s = safety_figures(case, [2e8, 1e8], 1.2e9)
    # model: S_F = sigma_Flim Y_ST / peak, S_H = sigma_Hlim / peak pressure (ISO 6336-2/-3, cl. 5)
    assert s["safety_root_model"] == pytest.approx([2 * 430e6 / 2e8, 2 * 430e6 / 1e8])
    assert s["safety_contact_model"] == pytest.approx([1500e6 / 1.2e9] * 2)
    rating = rate(iso_pair(case.pair), 150.0)
    k_v = dynamic_factor_at(rating, case.run.speed_a)
    assert s["iso6336_k_v"] == pytest.approx(k_v) and k_v > 1.0
    assert s["safety_root_iso"] == pytest.approx([860e6 / (f * k_v) for f in rating.sigma_f0])
    assert s["safety_contact_iso"][0] == pytest.approx(
        1500e6 / (rating.z_b * rating.sigma_h0 * math.sqrt(k_v)))
    # a gear without allowables gets none; a case without any, no safety figures at all
    only_f = safety_figures(_case_with_allowables(hlim=None), [2e8, 1e8], None)
    assert only_f["safety_contact_model"] == [None, None] and only_f["safety_root_model"][0] > 0
    assert safety_figures(_case_with_allowables(None, None), [2e8, 1e8], 1e9) == {}


def test_allowables_are_kept_in_the_stored_case_and_a_value_in_mpa_is_refused():
    from spurdyn.case import case_from_dict, case_to_dict
    from spurdyn.errors import InputError

    case = _case_with_allowables()
    again = case_from_dict(case_to_dict(case), check_step=False)
    assert again.pair.gear_a.material.sigma_flim == 430e6
    assert again.pair.gear_b.material.sigma_hlim == 1500e6
    with pytest.raises(InputError, match=r"gear_a.material.sigma_flim: .*in MPa is refused"):
        _case_with_allowables(flim=430.0)
