"""ISO 6336-5:2016 allowable stress numbers ``sigma_Hlim`` and ``sigma_Flim`` from a material class.

Within each material class, quality grade and hardness range ISO 6336-5 gives the
allowable stress numbers (its figures 1 to 14) as straight lines of the surface hardness
``x`` (HBW or HV, as the class is measured): ``sigma = A x + B`` (clause 5.5, Table 1).
:data:`LINES` holds ``A`` (MPa per hardness unit), ``B`` (MPa) and the range of ``x`` for
the subset of classes supported here; :func:`allowable_stresses` reads them.

The numbers, the subset, the sources and what was cross-checked are in
``docs/iso6336.md``, section 10. Errors name the bare key (``material_class``, ``grade``,
``hardness_hv``/``hardness_hbw``); the case file prefixes where the table came from.
"""

from __future__ import annotations

from dataclasses import dataclass

from spurdyn.errors import InputError

#: ISO 6336-5's material quality grades: modest (ML), normal (MQ), high (ME) demands.
GRADES = ("ML", "MQ", "ME")
#: 1 MPa in Pa: the table is written in ISO's N/mm^2.
MPA = 1e6


@dataclass(frozen=True)
class Line:
    """One straight line ``sigma = slope x + intercept`` (MPa) for ``low <= x <= high``."""

    slope: float
    intercept: float
    low: float
    high: float

    def at(self, hardness: float) -> float:
        """The stress number (MPa) at ``hardness``."""
        return self.slope * hardness + self.intercept


@dataclass(frozen=True)
class MaterialClass:
    """A material class of ISO 6336-5: its name, hardness scale and lines per grade.

    ``contact`` and ``bending`` map a grade to its line of ``sigma_Hlim`` and
    ``sigma_Flim``; ``running_in`` is ISO 6336-1's material group for the running-in
    allowance ``y_alpha`` (:mod:`spurdyn.iso6336.transverse`).
    """

    name: str
    scale: str
    contact: dict[str, Line]
    bending: dict[str, Line]
    running_in: str

    def hardness_range(self, grade: str) -> tuple[float, float]:
        """The hardnesses where both lines of ``grade`` hold (their overlap)."""
        h, f = self.contact[grade], self.bending[grade]
        return max(h.low, f.low), min(h.high, f.high)


def _same(line: Line) -> dict[str, Line]:
    return {g: line for g in GRADES}


def _lq(ml_mq: Line, me: Line) -> dict[str, Line]:
    """ML and MQ share one line in most of the cast and normalized classes."""
    return {"ML": ml_mq, "MQ": ml_mq, "ME": me}


#: The supported classes, by ISO 6336-5's symbol (``V`` split by its two figures).
LINES: dict[str, MaterialClass] = {c.name: c for c in (
    MaterialClass("St", "HBW",  # normalized low carbon wrought steel
                  _lq(Line(1.000, 190, 110, 210), Line(1.520, 250, 110, 210)),
                  _lq(Line(0.455, 69, 110, 210), Line(0.386, 147, 110, 210)), "steel"),
    MaterialClass("GGG", "HBW",  # nodular (spheroidal graphite) cast iron
                  _lq(Line(1.434, 211, 175, 300), Line(1.500, 250, 200, 300)),
                  _lq(Line(0.350, 119, 175, 300), Line(0.380, 134, 200, 300)), "cast_iron"),
    MaterialClass("GG", "HBW",  # grey cast iron
                  _lq(Line(1.033, 132, 150, 240), Line(1.465, 122, 175, 275)),
                  _lq(Line(0.256, 8, 150, 240), Line(0.200, 53, 175, 275)), "cast_iron"),
    MaterialClass("V_carbon", "HV",  # through-hardened wrought carbon steel
                  {"ML": Line(0.963, 283, 135, 210), "MQ": Line(0.925, 360, 135, 210),
                   "ME": Line(0.838, 432, 135, 210)},
                  {"ML": Line(0.250, 108, 115, 215), "MQ": Line(0.240, 163, 115, 215),
                   "ME": Line(0.283, 202, 115, 215)}, "steel"),
    MaterialClass("V_alloy", "HV",  # through-hardened wrought alloy steel
                  {"ML": Line(1.313, 188, 200, 360), "MQ": Line(1.313, 373, 200, 360),
                   "ME": Line(2.213, 260, 200, 390)},
                  {"ML": Line(0.423, 104, 200, 360), "MQ": Line(0.425, 187, 200, 360),
                   "ME": Line(0.358, 231, 200, 390)}, "steel"),
    MaterialClass("Eh", "HV",  # case-hardened (carburized) wrought steel
                  {"ML": Line(0.0, 1300, 600, 800), "MQ": Line(0.0, 1500, 660, 800),
                   "ME": Line(0.0, 1650, 660, 800)},
                  {"ML": Line(0.0, 312, 600, 800), "MQ": Line(0.0, 425, 660, 800),
                   "ME": Line(0.0, 525, 660, 800)}, "surface_hardened"),
    MaterialClass("IF", "HV",  # flame or induction hardened
                  {"ML": Line(0.740, 602, 485, 615), "MQ": Line(0.541, 882, 500, 615),
                   "ME": Line(0.505, 1013, 500, 615)},
                  {"ML": Line(0.305, 76, 485, 615), "MQ": Line(0.138, 290, 500, 570),
                   "ME": Line(0.271, 237, 500, 615)}, "surface_hardened"),
    MaterialClass("NT", "HV",  # nitriding steel, nitrided
                  {"ML": Line(0.0, 1125, 650, 900), "MQ": Line(0.0, 1250, 650, 900),
                   "ME": Line(0.0, 1450, 650, 900)},
                  {"ML": Line(0.0, 270, 650, 900), "MQ": Line(0.0, 420, 650, 900),
                   "ME": Line(0.0, 468, 650, 900)}, "surface_hardened"),
    MaterialClass("NV", "HV",  # through-hardening steel, nitrided
                  {"ML": Line(0.0, 788, 450, 650), "MQ": Line(0.0, 998, 450, 650),
                   "ME": Line(0.0, 1217, 450, 650)},
                  {"ML": Line(0.0, 258, 450, 650), "MQ": Line(0.0, 363, 450, 650),
                   "ME": Line(0.0, 432, 450, 650)}, "surface_hardened"),
)}

#: Plausible allowable stress numbers (Pa) of a metal gear, by case-file key: ISO 6336-5's
#: lines span sigma_Hlim 287 MPa (grey iron, ML, 150 HBW) to 1650 MPa (case-hardened, ME)
#: and sigma_Flim 46 to 525 MPa; the bounds leave room around them and catch a value in
#: MPa or a sigma_FE given as sigma_Flim's double where it does not fit.
PLAUSIBLE = {"sigma_hlim": (100e6, 2500e6), "sigma_flim": (30e6, 1000e6),
             "sigma_fe": (60e6, 2000e6)}

#: The case file's key for each hardness scale.
HARDNESS_KEYS = {"HV": "hardness_hv", "HBW": "hardness_hbw"}


def material_class(name: object) -> MaterialClass:
    """The class called ``name``, or an :class:`InputError` on ``material_class`` listing them."""
    if not isinstance(name, str) or name not in LINES:
        raise InputError("material_class", f"unknown ISO 6336-5 class {name!r}; supported: "
                         f"{', '.join(LINES)} (or give sigma_hlim and sigma_flim in Pa)")
    return LINES[name]


def check_allowable(key: str, value: float) -> None:
    """Refuse an allowable stress number ``value`` (Pa) of case-file ``key`` outside
    :data:`PLAUSIBLE`, naming the key."""
    low, high = PLAUSIBLE[key]
    if not low <= value <= high:
        raise InputError(key, f"{value:g} Pa is outside any ISO 6336-5 gear material "
                         f"({low:g} to {high:g} Pa); it is in Pa (a value in MPa is refused)")


def allowable_stresses(name: str, grade: str, hardness: float) -> tuple[float, float]:
    """``(sigma_Hlim, sigma_Flim)`` in Pa of class ``name``, quality ``grade``, ``hardness``.

    Parameters
    ----------
    name
        ISO 6336-5 class symbol, a key of :data:`LINES`.
    grade
        ``"ML"``, ``"MQ"`` or ``"ME"``.
    hardness
        Surface hardness in the class's scale (``MaterialClass.scale``: HV or HBW).

    Raises
    ------
    InputError
        On ``material_class``, ``grade`` or the hardness key (``hardness_hv`` /
        ``hardness_hbw``) when unknown or out of the class's range, with the range.
    """
    cls = material_class(name)
    if grade not in GRADES:
        raise InputError("grade", f"must be one of {', '.join(GRADES)} (ISO 6336-5 quality; "
                         f"got {grade!r})")
    key = HARDNESS_KEYS[cls.scale]
    if isinstance(hardness, bool) or not isinstance(hardness, (int, float)):
        raise InputError(key, f"must be a number (got {hardness!r})")
    low, high = cls.hardness_range(grade)
    if not low <= hardness <= high:
        raise InputError(key, f"{hardness:g} {cls.scale} is outside ISO 6336-5's range for "
                         f"{name} {grade}, {low:g} to {high:g} {cls.scale}; give sigma_hlim "
                         "and sigma_flim instead for other materials")
    return cls.contact[grade].at(hardness) * MPA, cls.bending[grade].at(hardness) * MPA


__all__ = ["GRADES", "HARDNESS_KEYS", "LINES", "Line", "MaterialClass", "PLAUSIBLE",
           "allowable_stresses", "check_allowable", "material_class"]
