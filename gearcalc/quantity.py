"""Quantities written in design values (``torque_Nm = "2 kN*m"``): converted to the key's unit with pint.

The loader (:func:`gearcalc.design.check_value`) calls :func:`convert` only for a string on a numeric key whose
name carries a unit and whose text starts with a number; pint is imported then, and only then (``gearcalc --help``
and a design of bare numbers never import it).  pint is a dependency of gearcalc; without it, the loader falls back
to proposing the bare number (:func:`gearcalc.design._string_hint`).
"""
from __future__ import annotations

import math
import re

# The pint spelling of each unit a key's name carries (gearcalc.units.unit_of).
_PINT_UNIT = {
    "mm": "mm", "N": "N", "N·m": "N*m", "MPa": "MPa", "rpm": "rpm", "°": "degree", "N/mm": "N/mm",
    "kg/m³": "kg/m**3", "µm": "um", "ms": "ms", "W": "W", "m/s": "m/s", "%": "percent", "mrad": "mrad",
    "arcsec": "arcsec", "kg/(kN·m)": "kg/(kN*m)",
}

_REGISTRY = None


def _registry():
    global _REGISTRY
    if _REGISTRY is None:
        import pint

        _REGISTRY = pint.UnitRegistry()
    return _REGISTRY


def _what(units) -> str:
    """The quantity a pint unit measures, in words ("a torque")."""
    ureg = _registry()
    dim = ureg.get_dimensionality(units)
    radians = dict(ureg.get_root_units(units)[1]._units).get("radian", 0)
    names = {
        "[length]": "a length", "[mass] * [length] / [time] ** 2": "a force",
        "[mass] * [length] ** 2 / [time] ** 2": "a torque", "[mass] / [length] / [time] ** 2": "a stress",
        "[mass] / [time] ** 2": "a stiffness (force per length)", "[mass] / [length] ** 3": "a density",
        "1 / [time]": "a speed of rotation" if radians == 1 else "a frequency",
        "[time]": "a time", "[length] / [time]": "a velocity", "[mass] * [length] ** 2 / [time] ** 3": "a power",
        "[mass]": "a mass", "[time] ** 2 / [length] ** 2": "a mass per torque",
    }
    text = str(dim)
    if text == "dimensionless":
        return "an angle" if radians == 1 else "a dimensionless number"
    return names.get(text, f"of dimension {text}")


_POWER_OF_A_NUMBER = re.compile(r"[0-9)]\s*(?:\*\*|\^)")
_LONG_NUMBER = re.compile(r"[0-9]{3}")


def _plain_unit(text: str) -> bool:
    """Whether a unit text is safe to hand to pint, whose parser computes numbers: no power of a number or of a
    parenthesised group (``2**2**2**2**2**2**2`` would take forever), no number of more than two digits."""
    return len(text) <= 64 and not _POWER_OF_A_NUMBER.search(text) and not _LONG_NUMBER.search(text)


def convert(number: float, unit_text: str, key_unit: str) -> tuple[float | None, str | None]:
    """``number unit_text`` in ``key_unit`` (a key's unit, :func:`gearcalc.units.unit_of`): (value, None); or
    (None, why) when pint knows the unit but it measures another quantity than the key; or (None, None) when
    the text is not a unit pint knows (the caller keeps its hint) or pint is not installed.

    >>> convert(2, "kN*m", "N·m")
    (2000.0, None)
    >>> convert(2, "kN*m", "mm")
    (None, 'kN*m is a torque, this key is a length (mm)')
    """
    target_text = _PINT_UNIT.get(key_unit)
    if target_text is None or not _plain_unit(unit_text):
        return None, None
    try:
        ureg = _registry()
    except ImportError:
        return None, None
    try:
        unit = ureg.parse_units(unit_text.strip())
        target = ureg.parse_units(target_text)
    except Exception:  # noqa: BLE001 - pint raises several types for text that is not a unit
        return None, None
    if unit.dimensionless and str(unit) == "dimensionless":  # no unit at all ("2 *")
        return None, None
    given, wanted = _what(unit), _what(target)
    if given == "a frequency" and wanted == "a speed of rotation":  # 1/min, Hz: revolutions per unit of time
        unit, given = unit * ureg.revolution, wanted
    if given != wanted:
        return None, f"{unit_text.strip()} is {given}, this key is {wanted} ({key_unit})"
    try:
        value = float(ureg.Quantity(number, unit).to(target).magnitude)
    except (OverflowError, ValueError, ZeroDivisionError):
        return None, None
    return (value, None) if math.isfinite(value) else (None, None)
