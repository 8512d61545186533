"""The paper's Fig. 7 torque schedule (spurdyn.model.loading)."""

import math
from dataclasses import replace

import numpy as np
import pytest

from spurdyn.geometry import paper_pair
from spurdyn.geometry.pair import GearPair
from spurdyn.geometry.presets import PAPER_TORQUE, paper_gear
from spurdyn.model.loading import (
    gear_angles,
    gear_torques,
    torque_amplitudes,
    torque_fraction,
    torque_schedule,
)

TS, T2 = math.radians(21.06), math.radians(8.20)


def unequal_pair(driver: str = "a") -> GearPair:
    g = paper_gear()
    return GearPair(gear_a=g, gear_b=replace(g, teeth=40, disk_inertia=8.0e-4), driver=driver)


def test_schedule_key_values():
    phi = np.array([-0.1, 0.0, T2 / 2, T2, TS / 2, TS - T2, TS - T2 / 4, TS, TS + 0.1])
    want = np.array([0.0, 0.0, 0.5, 1.0, 1.0, 1.0, 0.25, 0.0, 0.0])
    assert torque_schedule(phi, TS, T2) == pytest.approx(want, abs=1e-15)


def test_schedule_is_continuous_bounded_and_piecewise_linear():
    phi = np.linspace(-0.05, TS + 0.05, 200_001)
    f = torque_schedule(phi, TS, T2)
    assert f.min() == 0.0 and f.max() == 1.0
    step = phi[1] - phi[0]
    # Lipschitz with constant 1 / theta_2: no jumps anywhere.
    assert np.abs(np.diff(f)).max() <= step / T2 * (1 + 1e-9)
    # Slopes are only +1/theta_2, 0, -1/theta_2.
    slopes = np.diff(f) / step * T2
    off = ~np.isclose(slopes, -1.0, atol=1e-6) & ~np.isclose(slopes, 0.0, atol=1e-6) \
        & ~np.isclose(slopes, 1.0, atol=1e-6)
    assert off.sum() <= 4  # only the intervals holding the four kinks


def test_schedule_vectorised_and_scalar_path_agree():
    phi = np.random.default_rng(1).uniform(-0.1, TS + 0.1, (7, 9))
    f = torque_schedule(phi, TS, T2)
    assert f.shape == (7, 9)
    assert np.array_equal(f, np.vectorize(lambda x: torque_fraction(x, TS, T2))(phi))
    assert np.ndim(torque_schedule(0.1, TS, T2)) == 0


def test_triangle_when_double_contact_exceeds_half_the_action():
    f = torque_schedule(np.array([0.5, 1.0, 1.5]), 2.0, 1.5)
    assert f == pytest.approx([1 / 3, 2 / 3, 1 / 3])


def test_bad_angles_rejected():
    with pytest.raises(ValueError):
        torque_schedule(0.1, TS, 0.0)
    with pytest.raises(ValueError):
        torque_schedule(0.1, -1.0, T2)


def test_gear_angles_of_the_paper_pair():
    p = paper_pair()
    (tsa, t2a), (tsb, t2b) = gear_angles(p)
    assert math.degrees(tsa) == pytest.approx(21.06, abs=0.005)
    assert math.degrees(t2a) == pytest.approx(8.20, abs=0.005)
    assert (tsa, t2a) == pytest.approx((p.theta_s, p.theta_2), rel=1e-14)
    assert (tsb, t2b) == pytest.approx((tsa, t2a), rel=1e-14)


def test_gear_angles_of_an_unequal_pair_share_the_line_of_action():
    p = unequal_pair()
    (tsa, t2a), (tsb, t2b) = gear_angles(p)
    ra, rb = p.gear_a.base_radius, p.gear_b.base_radius
    assert tsb * rb == pytest.approx(tsa * ra, rel=1e-14)
    # The double-contact length path - p_b is the same on both gears.
    assert t2b * rb == pytest.approx(t2a * ra, rel=1e-12)
    assert t2b == pytest.approx(tsb - 2 * math.pi / 40, rel=1e-14)


@pytest.mark.parametrize("driver", ["a", "b"])
def test_torque_signs_and_static_balance(driver):
    p = unequal_pair(driver)
    ra, rb = p.gear_a.base_radius, p.gear_b.base_radius
    (tsa, t2a), (tsb, t2b) = gear_angles(p)
    phi_a = np.linspace(0.0, tsa, 101)
    phi_b = phi_a * ra / rb  # rigid kinematics: equal pitch-line motion
    tau_a, tau_b = gear_torques(p, PAPER_TORQUE, phi_a, phi_b)
    amp_a, amp_b = torque_amplitudes(p, PAPER_TORQUE)
    if driver == "a":
        assert amp_a == PAPER_TORQUE and amp_b == pytest.approx(-PAPER_TORQUE * rb / ra)
        assert np.all(tau_a >= 0) and np.all(tau_b <= 0)
    else:
        assert amp_b == PAPER_TORQUE and amp_a == pytest.approx(-PAPER_TORQUE * ra / rb)
        assert np.all(tau_b >= 0) and np.all(tau_a <= 0)
    # Both torques balance through one tooth force along the line of action.
    assert tau_a / ra + tau_b / rb == pytest.approx(np.zeros_like(phi_a), abs=1e-9)
    assert tau_a == pytest.approx(amp_a * torque_schedule(phi_a, tsa, t2a), rel=1e-14)
    assert tau_b == pytest.approx(amp_b * torque_schedule(phi_b, tsb, t2b), rel=1e-14)


def test_gear_torques_broadcast():
    p = paper_pair()
    tau_a, tau_b = gear_torques(p, 1.0, np.linspace(0, 0.3, 5), 0.1)
    assert tau_a.shape == tau_b.shape == (5,)
    assert np.all(tau_b == tau_b[0])
