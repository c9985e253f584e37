"""The output mechanism's and the drag's design keys and their cross-key rule (pins.md §4.10).

Imports no numpy: ``gearcalc check`` and the adapter read it at start-up.
"""
from __future__ import annotations

import math

__all__ = ["OUTPUT_ARGS", "output_problem"]

OUTPUT_ARGS = {"w_mech": "output.mechanism", "w_holes": "output.holes", "w_radius": "output.hole_circle_radius_mm",
               "w_pin": "output.pin_radius_mm", "w_friction": "output.friction", "drag": "load.drag_torque_Nm"}
"""Argument name -> design key of the output mechanism and the drag (in gearcalc.kinds.pins.KEYS)."""


def output_problem(a: dict, level: str, Rp=None):
    r"""(key, message) of the first problem of the output mechanism's and the drag's keys, else None.

    .. math:: 2 R_w \sin(\pi/n_w) > 2 (r_w + e), \qquad R_w + r_w + e < R_p - R_b - e

    (the holes do not overlap and stay inside the satellite's root circle; the contact level takes neither the
    mechanism nor a drag.)

    Parameters
    ----------
    a : dict
        The design's values by argument name (:data:`OUTPUT_ARGS`, ``e`` and ``Rb`` [mm]; None: absent).
    level : str
        The level that runs.
    Rp : float, optional
        The pin-circle radius R_p, [mm] (None: the fit inside the satellite is not checked).

    Returns
    -------
    problem : tuple of (str, str) or None
        The design key and the message.

    Examples
    --------
    >>> output_problem({"w_mech": "pins_in_holes", "w_holes": 8, "w_radius": 35.0, "w_pin": 6.0, "e": 3.9,
    ...                 "Rb": 1.95}, "ideal", 57.2) is None
    True
    >>> output_problem({"w_mech": "pins_in_holes", "w_holes": 8, "w_radius": None, "w_pin": 6.0}, "ideal")[0]
    'output.hole_circle_radius_mm'

    References
    ----------
    .. [1] docs/spec/pins.md §4.10, §7.
    """
    mech = a.get("w_mech") or "ideal"
    drag = a.get("drag") or 0.0
    if level == "contact" and (mech != "ideal" or drag > 0.0):
        key = "output.mechanism" if mech != "ideal" else "load.drag_torque_Nm"
        return key, ("the contact level transmits pure torque at the output and has no drag (pins.md §4.10): use "
                     "the ideal level (a cycloidal profile without modifications or [contact] law) or leave it out")
    if mech == "ideal":
        return None
    for name, what in (("w_holes", "n_w, the number of holes"), ("w_radius", "R_w, the holes' circle radius"),
                       ("w_pin", "r_w, the output pins' radius")):
        if a.get(name) is None:
            return OUTPUT_ARGS[name], f"missing: {what}, required with output.mechanism = \"pins_in_holes\""
    n_w, R_w, r_w, e = a["w_holes"], a["w_radius"], a["w_pin"], a["e"]
    r_h = r_w + e
    if not 2.0 * R_w * math.sin(math.pi / n_w) > 2.0 * r_h:
        return OUTPUT_ARGS["w_radius"], (f"= {R_w:.6g} mm: {n_w} holes of radius r_w + e = {r_h:.6g} mm overlap on "
                                         "this circle (need 2 R_w sin(pi/n_w) > 2 (r_w + e))")
    if Rp is not None and a.get("Rb") is not None and not R_w + r_h < Rp - a["Rb"] - e:
        return OUTPUT_ARGS["w_radius"], (f"= {R_w:.6g} mm: the holes (radius r_w + e = {r_h:.6g} mm) reach past the "
                                         f"satellite's root circle R_p - R_b - e = {Rp - a['Rb'] - e:.6g} mm")
    return None
