"""The rigid gap evaluated over arrays of rolls (issue 34): the vectorised corner, relief and
slope against the scalar :func:`~spurdyn.sector.system.rigid_gap` and against the scalar
formula of ``math`` the code had before, at rolls across the path's ends, the reliefs'
starts and off the path; and the gap table against them at its own points."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from spurdyn.geometry.gear import Gear
from spurdyn.geometry.pair import GearPair
from spurdyn.geometry.presets import nasa_like_relief, paper_pair
from spurdyn.sector.statics import driving_pair
from spurdyn.sector.system import REACH, SLOPE_STEP, gap_table, rigid_gap, rigid_gaps

#: Round-off allowed against the scalar formula of ``math``: the gap (m; NumPy's arctan2
#: differs from libm's by an ulp, 5e-17 m on the driven gear's flank), the radii (relative)
#: and the slope (m/rad: the gap's round-off over the difference's step).
GAP_ABS, RADIUS_REL, SLOPE_ABS = 1e-15, 1e-12, 1e-15 / SLOPE_STEP


def _pairs() -> dict[str, GearPair]:
    """The paper's pair, with the NASA-like tip relief on both gears, and a 19/53 pair of
    module 4 with a parabolic relief on the wheel only."""
    pair = paper_pair()
    relieved = dataclasses.replace(pair, gear_a=nasa_like_relief(pair.gear_a, pair.gear_b),
                                   gear_b=nasa_like_relief(pair.gear_b, pair.gear_a))
    pinion = Gear.standard(19, 0.004, 20.0, 0.03, disk_inertia=1e-3)
    wheel = nasa_like_relief(Gear.standard(53, 0.004, 20.0, 0.03, disk_inertia=2e-2), pinion,
                             amount=15e-6, shape="parabolic")
    return {"paper": pair, "relieved": relieved,
            "19/53": GearPair(gear_a=pinion, gear_b=wheel, driver="a")}


PAIRS = _pairs()


def _reference(dp: GearPair, rho: float) -> tuple[float, float, float]:
    """``(g, r_a, r_b)``: the corner's gap and the reliefs at one roll, written out in
    ``math`` as the scalar code had it before issue 34 (docs/sector.md, 6.2; it agrees with
    that code to 6e-17 m, the order of a few operations)."""
    ga, gb = dp.gear_a, dp.gear_b
    ra, rb, length = ga.base_radius, gb.base_radius, dp.line_of_centres_length

    def gap_to_flank(s_tip, rho_c, oc, rbc, phi_c, ox, oy, rbf, rho_f, phi_f):
        phi = phi_c + (s_tip - rho_c)
        x = oc[0] + rbc * math.cos(phi) + rbc * s_tip * math.sin(phi) - ox
        y = oc[1] + rbc * math.sin(phi) - rbc * s_tip * math.cos(phi) - oy
        d = math.sqrt(max(x * x + y * y - rbf * rbf, 0.0))
        s = rho_f + (math.atan2(y, x) + math.atan2(d, rbf) - phi_f + math.pi) % (2 * math.pi) - math.pi
        return d - rbf * s, rbf * math.sqrt(1.0 + s * s)

    rho_b = (length - ra * rho) / rb
    if rho < dp.start_roll_a:
        s_tip = math.sqrt(gb.tip_radius**2 - rb * rb) / rb
        g, r_a = gap_to_flank(s_tip, rho_b, (length, rb), rb, -math.pi / 2, 0.0, -ra, ra, rho, math.pi / 2)
        r_b = gb.tip_radius
    elif rho > dp.end_roll_a:
        s_tip = math.sqrt(ga.tip_radius**2 - ra * ra) / ra
        g, r_b = gap_to_flank(s_tip, rho, (0.0, -ra), ra, math.pi / 2, length, rb, rb, rho_b, -math.pi / 2)
        r_a = ga.tip_radius
    else:
        g, r_a, r_b = 0.0, ra * math.hypot(1.0, rho), rb * math.hypot(1.0, rho_b)
    return g + float(ga.relief_depth(r_a)) + float(gb.relief_depth(r_b)), r_a, r_b


def _reference_gap(dp: GearPair, rho: float, side: int) -> tuple[float, float, float, float]:
    """``(g, slope, r_a, r_b)`` of :func:`_reference` with the slope's difference of ``side``."""
    g, r_a, r_b = _reference(dp, rho)
    hi = _reference(dp, rho + SLOPE_STEP)[0] if side >= 0 else g
    lo = _reference(dp, rho - SLOPE_STEP)[0] if side <= 0 else g
    return g, (hi - lo) / ((2 if side == 0 else 1) * SLOPE_STEP), r_a, r_b


def _rolls(dp: GearPair, reach: float) -> np.ndarray:
    """Rolls across the path and beyond it, on and beside its ends and the reliefs' starts."""
    marks = [dp.start_roll_a, dp.end_roll_a]
    ga, gb = dp.gear_a, dp.gear_b
    if ga.has_tip_relief:
        marks.append(ga.tip_relief_start_roll)
    if gb.has_tip_relief:       # B's relief start on the driver's roll
        marks.append((dp.line_of_centres_length - gb.tip_relief_start_roll * gb.base_radius)
                     / ga.base_radius)
    near = [m + d for m in marks for d in (0.0, -1e-12, 1e-12, -0.5 * SLOPE_STEP, 0.5 * SLOPE_STEP,
                                           -3e-6, 3e-6, -1e-3, 1e-3)]
    rng = np.random.default_rng(34)
    spread = rng.uniform(dp.start_roll_a - reach, dp.end_roll_a + reach, 150)
    far = [dp.start_roll_a - reach, dp.end_roll_a + reach, dp.start_roll_a - 2 * reach]
    return np.array([*near, *spread, *far])


@pytest.mark.parametrize("name", sorted(PAIRS))
def test_the_vectorised_rigid_gap_is_the_scalar_one(name):
    """:func:`rigid_gaps` over an array of rolls and each of the three differences equals
    :func:`rigid_gap` roll by roll, and the scalar formula of ``math`` to round-off."""
    dp = driving_pair(PAIRS[name])
    rho = _rolls(dp, REACH * 2.0 * math.pi / dp.gear_a.teeth)
    for side in (-1, 0, 1):
        got = np.array(rigid_gaps(dp, rho, side))
        scalar = np.array([rigid_gap(dp, float(x), side) for x in rho]).T
        np.testing.assert_allclose(got, scalar, rtol=1e-12, atol=0.0)
        ref = np.array([_reference_gap(dp, float(x), side) for x in rho]).T
        np.testing.assert_allclose(got[0], ref[0], rtol=0.0, atol=GAP_ABS)
        np.testing.assert_allclose(got[1], ref[1], rtol=0.0, atol=SLOPE_ABS)
        np.testing.assert_allclose(got[2:], ref[2:], rtol=RADIUS_REL, atol=0.0)
    assert got[0][rho > dp.end_roll_a + 1e-4].min() > 0.0     # the corners stand off


@pytest.mark.parametrize("name", sorted(PAIRS))
def test_the_gap_table_is_the_rigid_gap_at_its_points(name):
    """At its points the table holds :func:`rigid_gap` with the slope from inside each
    segment: one-sided at the table's ends and at the breaks (two points, the left one's
    slope from the left, the right one's from the right), central elsewhere."""
    dp = driving_pair(PAIRS[name])
    reach = REACH * 2.0 * math.pi / dp.gear_a.teeth
    table = gap_table(dp, reach)
    rho = table.rho
    assert rho[0] == dp.start_roll_a - reach and rho[-1] == dp.end_roll_a + reach
    assert np.all(np.diff(rho) >= 0.0)
    side = np.zeros(rho.size, dtype=int)
    side[0], side[-1] = 1, -1
    twin = np.flatnonzero(rho[1:] == rho[:-1])
    side[twin], side[twin + 1] = -1, 1
    assert {dp.start_roll_a, dp.end_roll_a} <= set(rho[twin])
    assert twin.size == 2 + sum(g.has_tip_relief for g in (dp.gear_a, dp.gear_b))
    pick = np.unique(np.concatenate([np.arange(0, rho.size, 7), twin, twin + 1, [rho.size - 1]]))
    for i in pick:
        want = rigid_gap(dp, float(rho[i]), int(side[i]))
        got = (table.gap[i], table.slope[i], table.r_a[i], table.r_b[i])
        assert got == pytest.approx(want, rel=1e-12, abs=0.0)
        ref = _reference_gap(dp, float(rho[i]), int(side[i]))
        assert got[0] == pytest.approx(ref[0], rel=0.0, abs=GAP_ABS)
        assert got[1] == pytest.approx(ref[1], rel=0.0, abs=SLOPE_ABS)
        assert got[2:] == pytest.approx(ref[2:], rel=RADIUS_REL, abs=0.0)
