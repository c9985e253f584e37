"""Units: the one place where design-file units meet the SI-like internal units.

Design files and outputs use the units engineers write on drawings (mm, N, N·m, MPa, rpm,
degrees).  The calculators work in N, mm, N·mm, MPa (= N/mm²), rad and rad/s.  Every
conversion goes through the constants and functions here; field names carry their unit as
a suffix, and :func:`unit_of` reads it back for table headers.
"""
from __future__ import annotations

import math

NMM_PER_NM = 1000.0
"""N·mm in one N·m."""
RAD_PER_DEG = math.pi / 180.0
RAD_S_PER_RPM = 2.0 * math.pi / 60.0
MM_PER_M = 1000.0
UM_PER_MM = 1000.0
MRAD_PER_RAD = 1000.0

# The ranges gearcalc accepts for inputs of these kinds (the schema's bounds). They are far outside any
# machine (a micrometre-scale mechanism to a kilometre-scale one) and keep every result a finite double:
# forces, stresses and powers built from them stay below ~1e300 instead of overflowing to inf.
MIN_LENGTH_MM, MAX_LENGTH_MM = 1e-6, 1e6
MAX_FORCE_N = 1e15
MAX_TORQUE_NM = 1e15
MAX_SPEED_RPM = 1e9
MAX_FRICTION = 10.0
"""Friction coefficients (dimensionless): dry metal pairs stay below about 1."""
MAX_TEETH = 10_000
"""Pins and satellite teeth of a pin gear (pins z1, z2).  Drives use 10 to a few hundred; the bound keeps
every integer exact in floating point (far below 2^53, where z2 - z1 would round to 0) and bounds the ideal
level's arrays, which grow as z2 times the crank samples (10 000 pins: < 0.6 GB, < 6 s at any --tol)."""

# Longest suffix first, so that "_N_per_mm" wins over "_mm".
_SUFFIXES = (
    ("_kg_per_kNm", "kg/(kN·m)"),
    ("_N_per_mm", "N/mm"),
    ("_kg_m3", "kg/m³"),
    ("_arcsec", "arcsec"),
    ("_mrad", "mrad"),
    ("_m_s", "m/s"),
    ("_MPa", "MPa"),
    ("_rpm", "rpm"),
    ("_deg", "°"),
    ("_pct", "%"),
    ("_Nm", "N·m"),
    ("_mm", "mm"),
    ("_um", "µm"),
    ("_ms", "ms"),
    ("_W", "W"),
    ("_N", "N"),
)


def unit_of(name: str) -> str:
    """The unit a field name carries in its suffix ('' for dimensionless).

    >>> unit_of("sigma_max_MPa"), unit_of("w_mean_N_per_mm"), unit_of("K")
    ('MPa', 'N/mm', '')
    """
    for suffix, unit in _SUFFIXES:
        if name.endswith(suffix):
            return unit
    return ""


def split_unit(name: str) -> tuple[str, str]:
    """(name without unit suffix, unit).

    >>> split_unit("roller_gap_mm")
    ('roller_gap', 'mm')
    """
    for suffix, unit in _SUFFIXES:
        if name.endswith(suffix):
            return name[: -len(suffix)], unit
    return name, ""


def nm_to_nmm(torque_nm):
    """Torque from N·m (design files) to N·mm (inside)."""
    return torque_nm * NMM_PER_NM


def deg_to_rad(angle_deg):
    return angle_deg * RAD_PER_DEG


def rad_to_deg(angle_rad):
    return angle_rad / RAD_PER_DEG


def rpm_to_rad_s(speed_rpm):
    return speed_rpm * RAD_S_PER_RPM


def rad_s_to_rpm(speed_rad_s):
    return speed_rad_s / RAD_S_PER_RPM


# ---------------------------------------------------------------- units written in a value (loader hints)
# Only the loader's hints use this block: a design file holds bare numbers in the unit of the key's name,
# and a value written with a unit ("10 kN" on a key in N) gets the number in the key's unit proposed.
# Each quantity: unit word -> size in the quantity's first unit. Words are matched exactly, after removing
# spaces and the product signs (·, ⋅, *, .), then case-insensitively for the spelled-out words only.
_PI = math.pi
_UNIT_SIZES = {
    "length": {"mm": 1.0, "m": 1e3, "cm": 10.0, "dm": 100.0, "km": 1e6, "µm": 1e-3, "μm": 1e-3, "um": 1e-3,
               "nm": 1e-6, "in": 25.4, "inch": 25.4, "inches": 25.4, "ft": 304.8, "feet": 304.8, "foot": 304.8},
    "force": {"N": 1.0, "kN": 1e3, "MN": 1e6, "mN": 1e-3, "lbf": 4.4482216152605, "kgf": 9.80665},
    "torque": {"Nm": 1.0, "kNm": 1e3, "MNm": 1e6, "Nmm": 1e-3, "kNmm": 1.0, "Ncm": 1e-2,
               "lbfft": 1.3558179483314004, "lbfin": 0.1129848290276167},
    "stress": {"MPa": 1.0, "Pa": 1e-6, "kPa": 1e-3, "GPa": 1e3, "N/mm²": 1.0, "N/mm2": 1.0, "N/mm^2": 1.0,
               "N/m²": 1e-6, "N/m2": 1e-6, "bar": 0.1, "psi": 0.006894757293168361, "ksi": 6.894757293168361},
    "speed": {"rpm": 1.0, "rev/min": 1.0, "r/min": 1.0, "1/min": 1.0, "min⁻¹": 1.0, "min-1": 1.0,
              "rev/s": 60.0, "rps": 60.0, "rad/s": 30.0 / _PI},
    "angle": {"°": 1.0, "deg": 1.0, "degree": 1.0, "degrees": 1.0, "rad": 180.0 / _PI, "radian": 180.0 / _PI,
              "radians": 180.0 / _PI, "mrad": 0.18 / _PI, "arcmin": 1.0 / 60.0, "′": 1.0 / 60.0,
              "arcsec": 1.0 / 3600.0, "″": 1.0 / 3600.0},
    "velocity": {"m/s": 1.0, "mm/s": 1e-3, "cm/s": 1e-2, "km/h": 1.0 / 3.6},
    "power": {"W": 1.0, "kW": 1e3, "MW": 1e6, "mW": 1e-3},
    "time": {"ms": 1.0, "s": 1e3, "µs": 1e-3, "μs": 1e-3, "us": 1e-3, "min": 6e4},
    "percent": {"%": 1.0, "pct": 1.0, "percent": 1.0},
    "stiffness": {"N/mm": 1.0, "kN/mm": 1e3, "N/m": 1e-3, "kN/m": 1.0, "N/µm": 1e3, "N/μm": 1e3, "N/um": 1e3},
    "density": {"kg/m³": 1.0, "kg/m3": 1.0, "kg/m^3": 1.0, "g/cm³": 1e3, "g/cm3": 1e3, "kg/dm³": 1e3},
    "mass per torque": {"kg/(kNm)": 1.0, "kg/kNm": 1.0},
}
_SPELLED = {w for sizes in _UNIT_SIZES.values() for w in sizes if len(w) > 2 and w.isalpha() and w.islower()}


def _unit_word(text: str) -> str:
    return "".join(c for c in text.strip() if c not in " \t·⋅*.")


def _unit_size(text: str) -> tuple[str, float] | None:
    word = _unit_word(text)
    for quantity, sizes in _UNIT_SIZES.items():
        if word in sizes:
            return quantity, sizes[word]
    if word.lower() in _SPELLED:
        return _unit_size(word.lower())
    return None


def convert_hint(value: float, unit_text: str, key_unit: str) -> float | None:
    """``value`` given in ``unit_text`` expressed in ``key_unit`` (a key's unit, as :func:`unit_of` gives it);
    ``None`` when either unit is unknown or they measure different quantities.

    >>> convert_hint(10, "kN", "N"), convert_hint(0.25, "in", "mm"), convert_hint(2, "kN·m", "N·m")
    (10000.0, 6.35, 2000.0)
    """
    given, target = _unit_size(unit_text), _unit_size(key_unit)
    if given is None or target is None or given[0] != target[0]:
        return None
    if given[1] == target[1]:
        return float(value)
    return value * given[1] / target[1]


def same_unit(unit_text: str, key_unit: str) -> bool:
    """True when the unit written is the key's own unit (e.g. "deg" for °)."""
    given, target = _unit_size(unit_text), _unit_size(key_unit)
    return given is not None and given == target
