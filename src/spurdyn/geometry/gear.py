"""Descriptions of a spur gear and of a meshing pair, with their derived figures.

Descriptions are frozen dataclasses that check themselves when made; the figures gear
engineers quote (base pitch, contact ratio, angle of action, ...) are properties.
SI units throughout: m, rad, kg, N m.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np
from scipy.optimize import brentq

from spurdyn.errors import InputError
from spurdyn.fem.material import STEEL, Material
from spurdyn.geometry import involute as ivl
from spurdyn.geometry import relief as rlf

#: Default rack-cutter tip radius, as a fraction of the module: ISO 53 basic rack
#: profile A (dedendum 1.25 m, as the paper's gears) uses 0.38 m. It gives a generous
#: trochoid that meets the involute below the start of the active profile of ordinary
#: pairs (the paper gives no fillet; see docs/geometry.md).
DEFAULT_CUTTER_TIP_RADIUS = 0.38

#: Largest tilt (rad) a tip relief may give the flank: the largest slope of the depth
#: along the involute's arc length, ``k C_a r_b / ((L_a - L_s) L)`` with ``L = L_s``
#: (linear) or ``L_a`` (parabolic) (see ``docs/geometry.md``, section 7). A relief that
#: starts too close to the tip for its amount is refused.
MAX_RELIEF_TILT = 0.1

#: Largest tip relief as a fraction of the module (a second cap is a quarter of the tip
#: land of the unmodified tooth).
MAX_RELIEF_MODULES = 0.1

#: Default angle (from the root circle) at which the fillet is cut off and the sliver
#: beneath it counted as rigid disk; see ``docs/geometry.md``.
DEFAULT_FILLET_CUT_ANGLE = math.radians(45.0)


#: Plausibility bounds that catch lengths written in millimetres: the largest industrial
#: gears have modules of some 50 mm, and face widths of some tens of modules.
MAX_MODULE = 0.1
MAX_FACE_WIDTH_MODULES = 200.0


def _positive(name: str, value: float) -> None:
    if not isinstance(value, (int, float)) or isinstance(value, bool):
        raise InputError(name, f"must be a number (got {type(value).__name__})")
    if not math.isfinite(value) or value <= 0.0:
        raise InputError(name, f"must be a positive number (got {value!r})")


@dataclass(frozen=True)
class Gear:
    """A standard (unshifted) involute spur gear with its rigid disk.

    Parameters
    ----------
    teeth
        Number of teeth ``z``.
    module
        Module ``m`` (m); the pitch radius is ``m z / 2``.
    pressure_angle
        Pressure angle of the generating rack (rad).
    face_width
        Face width (m), the thickness of the plane-stress tooth.
    addendum, dedendum
        Radial heights of the tooth above and below the pitch circle (m).
    cutter_tip_radius
        Tip radius of the generating rack cutter (m); it shapes the trochoidal fillet.
    disk_inertia
        Moment of inertia ``J`` of the rigid disk about its axis (kg m^2).
    material
        Elastic constants and density of the tooth.
    tip_relief
        Tip relief amount ``C_a`` (m): material removed normal to the involute at the
        tip circle's roll angle. 0 (the default) leaves the flank a pure involute.
    tip_relief_start_roll
        Roll angle ``xi_s`` (rad) on the involute where the relief begins; it must lie
        between the form radius' roll angle and the tip's. Needed when ``tip_relief > 0``.
    tip_relief_shape
        ``"linear"`` (depth grows as ``(xi - xi_s)``) or ``"parabolic"`` (as its square);
        see :mod:`spurdyn.geometry.relief` and ``docs/geometry.md``, section 7.
    """

    teeth: int
    module: float
    pressure_angle: float
    face_width: float
    addendum: float
    dedendum: float
    cutter_tip_radius: float
    disk_inertia: float
    material: Material = field(default=STEEL)
    tip_relief: float = 0.0
    tip_relief_start_roll: float | None = None
    tip_relief_shape: str = "linear"

    def __post_init__(self) -> None:
        if not isinstance(self.teeth, int) or isinstance(self.teeth, bool):
            raise InputError("teeth", f"must be a whole number (got {self.teeth!r})")
        if self.teeth < 8:
            raise InputError("teeth", f"must be at least 8 (got {self.teeth})")
        for name in ("module", "pressure_angle", "face_width", "addendum", "dedendum",
                     "cutter_tip_radius", "disk_inertia"):
            _positive(name, getattr(self, name))
        if self.module > MAX_MODULE:
            raise InputError("module", f"{self.module:g} m is beyond any gear (at most "
                             f"{MAX_MODULE:g} m); lengths are in metres, not millimetres")
        if self.face_width > MAX_FACE_WIDTH_MODULES * self.module:
            raise InputError("face_width", f"{self.face_width:g} m is more than "
                             f"{MAX_FACE_WIDTH_MODULES:g} modules; lengths are in metres, "
                             "not millimetres")
        deg = math.degrees(self.pressure_angle)
        if not 12.0 <= deg <= 35.0:
            raise InputError("pressure_angle", f"must lie between 12 and 35 degrees (got {deg:.4g})")
        if self.addendum > 2.0 * self.module:
            raise InputError("addendum", "is more than twice the module; give a tip radius "
                             "closer to the pitch radius")
        if self.cutter_tip_radius >= self.dedendum or self._straight_depth <= 0.0:
            raise InputError("cutter_tip_radius", "is too large for the dedendum; "
                             "lower cutter_tip_radius or deepen the root")
        if self.root_radius <= 0.0:
            raise InputError("dedendum", "puts the root circle at or below the gear centre")
        if not isinstance(self.material, Material):
            raise InputError("material", "must be a Material")
        # The generating rack's tooth must still have a tip land at the dedendum depth.
        if math.pi * self.module / 4.0 - self.dedendum * math.tan(self.pressure_angle) <= 0.0:
            deepest = math.pi / 4.0 / math.tan(self.pressure_angle)
            raise InputError("dedendum", f"is too deep for the pressure angle: the generating "
                             f"rack's tooth comes to a point (dedendum must stay below "
                             f"{deepest:.3g} x module)")
        # The rounding must fit on the cutter tooth: its centre may not pass the
        # cutter tooth's centre line.
        x_c, _ = self.cutter_centre
        if x_c > math.pi * self.module / 2.0 + 1e-12:
            limit = (math.pi / 4 - self.dedendum / self.module * math.tan(self.pressure_angle)) \
                * math.cos(self.pressure_angle) / (1 - math.sin(self.pressure_angle))
            raise InputError("cutter_tip_radius", f"is too large for the cutter tooth "
                             f"(at most {limit:.3g} x module with this dedendum)")
        if self.undercut:
            raise InputError("teeth", f"{self.teeth} teeth are undercut by the cutter "
                             f"(need at least {self.min_teeth_without_undercut}); use more teeth")
        if float(self.thickness_at(self.tip_radius)) <= 0.0:
            raise InputError("addendum", "makes the tooth come to a point below the tip "
                             "circle; lower the tip radius")
        self._check_relief()

    def _check_relief(self) -> None:
        """Refuse a tip relief that is not a small, well-placed modification."""
        amount, start = self.tip_relief, self.tip_relief_start_roll
        if isinstance(amount, bool) or not isinstance(amount, (int, float)):
            raise InputError("tip_relief", f"must be a number (got {type(amount).__name__})")
        if not math.isfinite(amount) or amount < 0.0:
            raise InputError("tip_relief", f"must be zero or a positive number of metres "
                             f"(got {amount!r})")
        if not isinstance(self.tip_relief_shape, str) or self.tip_relief_shape not in rlf.RELIEF_SHAPES:
            raise InputError("tip_relief_shape", f"must be one of {', '.join(rlf.RELIEF_SHAPES)} "
                             f"(got {self.tip_relief_shape!r})")
        if start is None:
            if amount > 0.0:
                raise InputError("tip_relief_start_roll", "is missing: a tip relief needs the "
                                 "roll angle where it begins")
            return
        if isinstance(start, bool) or not isinstance(start, (int, float)) or not math.isfinite(start):
            raise InputError("tip_relief_start_roll", f"must be a finite number (got {start!r})")
        lo = float(self.roll_angle_at(self.form_radius))
        hi = float(self.roll_angle_at(self.tip_radius))
        if not lo - 1e-12 <= start < hi:
            raise InputError("tip_relief_start_roll", f"must lie on the involute, from the form "
                             f"radius' roll angle {math.degrees(lo):.4g} deg "
                             f"(r = {self.form_radius * 1e3:.5g} mm) up to below the tip's "
                             f"{math.degrees(hi):.4g} deg (r = {self.tip_radius * 1e3:.5g} mm); "
                             f"got {math.degrees(start):.4g} deg")
        cap = min(MAX_RELIEF_MODULES * self.module, float(self.thickness_at(self.tip_radius)) / 4.0)
        if amount > cap:
            raise InputError("tip_relief", f"{amount * 1e6:.4g} um is too large for this tooth "
                             f"(at most {cap * 1e6:.4g} um: 0.1 module and a quarter of the "
                             f"tip land)")
        if amount > 0.0:
            rb = self.base_radius
            length_s, length_a = start * rb, hi * rb
            k = rlf.RELIEF_SHAPES[self.tip_relief_shape]
            # Largest slope of the depth along the involute's arc length s (ds = L dL / r_b):
            # at the start for a linear relief, at the tip for a parabolic one.
            length = length_s if k == 1 else length_a
            tilt = k * amount * rb / ((length_a - length_s) * max(length, 1e-12 * rb))
            if tilt > MAX_RELIEF_TILT:
                raise InputError("tip_relief_start_roll", f"starts too close to the tip (or "
                                 f"the base circle) for a {amount * 1e6:.4g} um relief: it would "
                                 f"tilt the flank by up to {tilt:.3g} rad (at most "
                                 f"{MAX_RELIEF_TILT:g}); start lower or relieve less")
            if self.tip_thickness <= 0.0:  # pragma: no cover - the caps above prevent it
                raise InputError("tip_relief", "leaves no tip land")

    # -- constructors ------------------------------------------------------------------
    @classmethod
    def from_radii(
        cls,
        teeth: int,
        pitch_radius: float,
        tip_radius: float,
        root_radius: float,
        pressure_angle: float,
        face_width: float,
        disk_inertia: float,
        cutter_tip_radius: float | None = None,
        material: Material = STEEL,
        tip_relief: float = 0.0,
        tip_relief_start_roll: float | None = None,
        tip_relief_shape: str = "linear",
    ) -> "Gear":
        """Make a gear from its pitch, tip and root radii (as the paper gives them)."""
        _positive("pitch_radius", pitch_radius)
        _positive("tip_radius", tip_radius)
        _positive("root_radius", root_radius)
        if not isinstance(teeth, int) or isinstance(teeth, bool) or teeth <= 0:
            raise InputError("teeth", f"must be a positive whole number (got {teeth!r})")
        if tip_radius <= pitch_radius:
            raise InputError("tip_radius", f"must be above the pitch radius {pitch_radius:g} m")
        if root_radius >= pitch_radius:
            raise InputError("root_radius", f"must be below the pitch radius {pitch_radius:g} m")
        module = 2.0 * pitch_radius / teeth
        if cutter_tip_radius is None:
            cutter_tip_radius = DEFAULT_CUTTER_TIP_RADIUS * module
        return cls(teeth=teeth, module=module, pressure_angle=pressure_angle,
                   face_width=face_width, addendum=tip_radius - pitch_radius,
                   dedendum=pitch_radius - root_radius, cutter_tip_radius=cutter_tip_radius,
                   disk_inertia=disk_inertia, material=material, tip_relief=tip_relief,
                   tip_relief_start_roll=tip_relief_start_roll, tip_relief_shape=tip_relief_shape)

    # -- radii and pitches -------------------------------------------------------------
    @property
    def pitch_radius(self) -> float:
        return self.module * self.teeth / 2.0

    @property
    def base_radius(self) -> float:
        return self.pitch_radius * math.cos(self.pressure_angle)

    @property
    def tip_radius(self) -> float:
        return self.pitch_radius + self.addendum

    @property
    def root_radius(self) -> float:
        return self.pitch_radius - self.dedendum

    @property
    def base_pitch(self) -> float:
        return 2.0 * math.pi * self.base_radius / self.teeth

    @property
    def half_angle_base(self) -> float:
        """Polar half-angle of the tooth at the base circle, ``pi/(2z) + inv(alpha)``."""
        return math.pi / (2 * self.teeth) + float(ivl.inv(self.pressure_angle))

    def thickness_at(self, r: float | np.ndarray) -> np.ndarray:
        """Circular tooth thickness ``2 r psi(r)`` (m) on the circle of radius ``r``."""
        return 2.0 * np.asarray(r) * ivl.half_angle(r, self.base_radius, self.half_angle_base)

    @property
    def tip_thickness(self) -> float:
        """Tip land (m): the arc of the tip circle between the two flanks.

        With a tip relief this is the land of the *relieved* tooth, between the points
        where the relieved flanks meet the tip circle (narrower than the unmodified
        ``thickness_at(tip_radius)`` by about ``2 C_a / cos(alpha_a)``).
        """
        if self.tip_relief == 0.0:
            return float(self.thickness_at(self.tip_radius))
        corner = self.modified_flank_point(np.asarray(self.flank_end_radius))
        return 2.0 * self.tip_radius * float(np.arctan2(corner[0], corner[1]))

    # -- fillet ------------------------------------------------------------------------
    @cached_property
    def cutter_centre(self) -> tuple[float, float]:
        return ivl.cutter_tip_centre(self.module, self.pressure_angle, self.dedendum,
                                     self.cutter_tip_radius)

    @property
    def _straight_depth(self) -> float:
        """Depth below the pitch line of the lowest point of the cutter's straight flank."""
        return self.dedendum - self.cutter_tip_radius * (1.0 - math.sin(self.pressure_angle))

    @property
    def undercut(self) -> bool:
        """True if the cutter's straight flank reaches below the base circle (undercut)."""
        return self._straight_depth > self.pitch_radius * math.sin(self.pressure_angle) ** 2 + 1e-15

    @property
    def min_teeth_without_undercut(self) -> int:
        return math.ceil(2.0 * self._straight_depth / (self.module * math.sin(self.pressure_angle) ** 2) - 1e-9)

    @property
    def form_radius(self) -> float:
        """Radius where the fillet meets the involute (the true involute form radius)."""
        length = self.pitch_radius * math.sin(self.pressure_angle) \
            - self._straight_depth / math.sin(self.pressure_angle)
        return float(ivl.radius_at_roll(length, self.base_radius))

    def fillet_points(self, angle_from_root: np.ndarray) -> np.ndarray:
        """Right-fillet points at normal angles measured from the root circle (rad).

        The angle is that of the generating normal in the rack frame (0 at the root circle,
        ``fillet_end_angle`` at the involute); see ``docs/geometry.md``, section 3.2.
        """
        phi = ivl.fillet_phi_at_normal_angle(angle_from_root, self.pitch_radius, self.cutter_centre)
        return ivl.fillet_point(phi, self.pitch_radius, self.cutter_centre, self.cutter_tip_radius)

    @property
    def fillet_end_angle(self) -> float:
        """Normal angle (from the root circle) at which the fillet meets the involute."""
        return math.pi / 2.0 - self.pressure_angle

    def right_side_point(self, r: float, cut_angle: float = DEFAULT_FILLET_CUT_ANGLE) -> np.ndarray:
        """Point of the right tooth outline (fillet or flank) at radius ``r``.

        Above the form radius this is the (relieved) flank, ``modified_flank_point(r)``:
        ``r`` is then the radius of the *unmodified* involute point, and a relieved
        point lies up to ``C_a sin(alpha_r)`` lower. The relieved flank reaches the tip
        circle at ``r = flank_end_radius`` (the tip radius when there is no relief).
        """
        if r >= self.form_radius:
            if self.tip_relief == 0.0:
                return ivl.right_flank_point(r, self.base_radius, self.half_angle_base)
            return self.modified_flank_point(np.asarray(r))
        # The fillet's radius falls monotonically from the involute junction to the root.
        def gap(a: float) -> float:
            return float(np.hypot(*self.fillet_points(np.asarray(a)))) - r
        a = brentq(gap, 0.0, self.fillet_end_angle, xtol=1e-14)
        return self.fillet_points(np.asarray(a))

    # -- involute flank ----------------------------------------------------------------
    def flank_point(self, r: np.ndarray) -> np.ndarray:
        return ivl.right_flank_point(r, self.base_radius, self.half_angle_base)

    def flank_normal(self, r: np.ndarray) -> np.ndarray:
        return ivl.right_flank_normal(r, self.base_radius, self.half_angle_base)

    def roll_angle_at(self, r: float | np.ndarray) -> np.ndarray:
        """Roll angle (rad) of the involute point at radius ``r``: roll length / r_b."""
        return ivl.roll_length(r, self.base_radius) / self.base_radius

    def radius_at_roll_angle(self, roll: float | np.ndarray) -> np.ndarray:
        return ivl.radius_at_roll(np.asarray(roll) * self.base_radius, self.base_radius)

    # -- tip relief --------------------------------------------------------------------
    @property
    def has_tip_relief(self) -> bool:
        return self.tip_relief > 0.0

    def relief_depth(self, r: float | np.ndarray) -> np.ndarray:
        """Tip-relief depth (m) along the outward normal at the involute point of radius ``r``.

        Zero below the start of the relief (and everywhere on an unmodified gear),
        ``tip_relief`` at the tip radius; see :func:`spurdyn.geometry.relief.relief_depth`.
        """
        amount, start, exponent, tip = rlf.relief_params(self)
        return rlf.relief_depth(self.roll_angle_at(r), amount, start, tip, exponent)

    def modified_flank_point(self, r: float | np.ndarray) -> np.ndarray:
        """Points ``(..., 2)`` of the relieved right flank, gear frame.

        ``flank_point(r) - relief_depth(r) * flank_normal(r)``: the involute point of
        radius ``r`` moved into the tooth along its normal by the relief depth. Equal to
        ``flank_point(r)`` where there is no relief.
        """
        depth = self.relief_depth(r)
        return self.flank_point(r) - depth[..., None] * self.flank_normal(r)

    @cached_property
    def flank_end_radius(self) -> float:
        """Involute radius whose relieved point lies on the tip circle (m).

        The tip radius when there is no relief; with one, a few micrometres above it,
        since the relief moves the flank inwards (``docs/geometry.md``, section 7).
        """
        ra = self.tip_radius
        if self.tip_relief == 0.0:
            return ra

        def gap(r: float) -> float:
            return float(np.hypot(*self.modified_flank_point(np.asarray(r)))) - ra

        hi = ra + 2.0 * self.tip_relief
        while gap(hi) <= 0.0:  # pragma: no cover - 2 C_a always suffices within the caps
            hi += 2.0 * self.tip_relief
        return float(brentq(gap, ra, hi, xtol=1e-15, rtol=4 * np.finfo(float).eps))


@dataclass(frozen=True)
class GearPair:
    """Two meshing gears, A and B, on a given centre distance.

    Parameters
    ----------
    gear_a, gear_b
        The two gears.
    centre_distance
        Centre distance (m); ``None`` takes the standard one, the sum of pitch radii.
    driver
        ``"a"`` or ``"b"``: which gear drives.
    """

    gear_a: Gear
    gear_b: Gear
    centre_distance: float | None = None
    driver: str = "a"

    def __post_init__(self) -> None:
        if self.centre_distance is None:
            object.__setattr__(self, "centre_distance",
                               self.gear_a.pitch_radius + self.gear_b.pitch_radius)
        _positive("centre_distance", self.centre_distance)
        if self.driver not in ("a", "b"):
            raise InputError("driver", f"must be 'a' or 'b' (got {self.driver!r})")
        if not math.isclose(self.gear_a.module, self.gear_b.module, rel_tol=1e-9):
            raise InputError("gear_b.module", "differs from gear_a's; meshing gears need one module")
        if not math.isclose(self.gear_a.pressure_angle, self.gear_b.pressure_angle, rel_tol=1e-9):
            raise InputError("gear_b.pressure_angle", "differs from gear_a's")
        rb = self.gear_a.base_radius + self.gear_b.base_radius
        if self.centre_distance <= rb:
            raise InputError("centre_distance", f"must exceed the sum of base radii {rb:g} m")
        if self.centre_distance <= self.gear_a.tip_radius + self.gear_b.root_radius or \
                self.centre_distance <= self.gear_b.tip_radius + self.gear_a.root_radius:
            raise InputError("centre_distance", "is too small: a tip would hit the other gear's root")
        if self.path_of_contact <= 0.0:
            raise InputError("centre_distance", "is too large: the tip circles do not reach "
                             "across the line of action, so the gears never touch")
        if self.contact_ratio < 1.0:
            raise InputError("centre_distance", f"gives a contact ratio {self.contact_ratio:.3f} "
                             "below 1; the pair would not mesh continuously")
        for name, gear, start in (("gear_a", self.gear_a, self.start_roll_a),
                                  ("gear_b", self.gear_b, self.start_roll_b)):
            if start * gear.base_radius < float(ivl.roll_length(gear.form_radius, gear.base_radius)) - 1e-12:
                raise InputError(f"{name}.cutter_tip_radius", "the mating tip reaches below the "
                                 "involute into the fillet (interference); use a smaller cutter "
                                 "tip radius or a shorter mating addendum")

    # -- line of action ----------------------------------------------------------------
    @property
    def working_pressure_angle(self) -> float:
        return math.acos((self.gear_a.base_radius + self.gear_b.base_radius) / self.centre_distance)

    @property
    def line_of_centres_length(self) -> float:
        """Length of the common tangent of the base circles, ``a sin(alpha_w)``."""
        return self.centre_distance * math.sin(self.working_pressure_angle)

    @property
    def tip_roll_length_a(self) -> float:
        return float(ivl.roll_length(self.gear_a.tip_radius, self.gear_a.base_radius))

    @property
    def tip_roll_length_b(self) -> float:
        return float(ivl.roll_length(self.gear_b.tip_radius, self.gear_b.base_radius))

    @property
    def path_of_contact(self) -> float:
        """Length of the path of contact along the line of action (m)."""
        return self.tip_roll_length_a + self.tip_roll_length_b - self.line_of_centres_length

    @property
    def contact_ratio(self) -> float:
        return self.path_of_contact / self.gear_a.base_pitch

    # Roll lengths on A along the line of action, measured from A's base tangent point:
    # contact runs from B's tip (start, low on A) to A's tip (end) when A drives.
    @property
    def start_roll_length_a(self) -> float:
        return self.line_of_centres_length - self.tip_roll_length_b

    @property
    def end_roll_length_a(self) -> float:
        return self.tip_roll_length_a

    @property
    def start_roll_a(self) -> float:
        """Roll angle of A at the start of its active profile (rad)."""
        return self.start_roll_length_a / self.gear_a.base_radius

    @property
    def start_roll_b(self) -> float:
        """Roll angle of B at the start of its active profile (rad)."""
        return (self.line_of_centres_length - self.tip_roll_length_a) / self.gear_b.base_radius

    @property
    def pitch_roll_a(self) -> float:
        return math.tan(self.working_pressure_angle)

    @property
    def end_roll_a(self) -> float:
        return self.end_roll_length_a / self.gear_a.base_radius

    @property
    def theta_s(self) -> float:
        """Angle of action of gear A: the rotation over the whole contact (rad)."""
        return self.path_of_contact / self.gear_a.base_radius

    @property
    def theta_2(self) -> float:
        """Double-contact angle of gear A at each end of the engagement (rad)."""
        return self.theta_s - 2.0 * math.pi / self.gear_a.teeth

    @property
    def single_contact_angle(self) -> float:
        return self.theta_s - 2.0 * self.theta_2

    @property
    def single_contact_roll_a(self) -> tuple[float, float]:
        """Roll angles of A where single-tooth contact begins and ends (rad)."""
        return self.start_roll_a + self.theta_2, self.end_roll_a - self.theta_2

    def roll_b_from_roll_a(self, roll_a: float | np.ndarray) -> np.ndarray:
        """Roll angle on B of the contact point whose roll angle on A is ``roll_a``."""
        return (self.line_of_centres_length - np.asarray(roll_a) * self.gear_a.base_radius) \
            / self.gear_b.base_radius
