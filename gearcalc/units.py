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
