"""The output mechanism's and the drag's design keys and their cross-key rule (pins.md §4.10).

Imports no numpy: ``gearcalc check`` and the adapter read it at start-up.
"""
from __future__ import annotations

import math

__all__ = ["OUTPUT_ARGS", "LAW_ARGS", "output_problem", "law_problem"]

OUTPUT_ARGS = {"w_mech": "output.mechanism", "w_holes": "output.holes", "w_radius": "output.hole_circle_radius_mm",
               "w_pin": "output.pin_radius_mm", "w_friction": "output.friction", "drag": "load.drag_torque_Nm"}
"""Argument name -> design key of the output mechanism and the drag (in gearcalc.kinds.pins.KEYS)."""

LAW_ARGS = {"f_law": "friction.law", "f_v": "friction.table_speed_m_s", "f_mu": "friction.table_mu",
            "f_s": "friction.stribeck_static", "f_c": "friction.stribeck_coulomb",
            "f_vs": "friction.stribeck_speed_m_s",
            "f_delta": "friction.stribeck_exponent", "f_kv": "friction.stribeck_viscous_s_per_m"}
"""Argument name -> design key of the teeth's sliding law (in gearcalc.kinds.pins.KEYS)."""


def output_problem(a: dict, level: str, Rp=None):
    r"""(key, message) of the first problem of the output mechanism's and the drag's keys, else None.

    .. math:: 2 R_w \sin(\pi/n_w) > 2 (r_w + e), \qquad R_w + r_w + e < R_p - R_b - e

    (the holes do not overlap and stay inside the satellite's root circle; a reducer driven on H needs more
    torque than the crank's drag.)  The same rules at the ideal and the contact level.

    Parameters
    ----------
    a : dict
        The design's values by argument name (:data:`OUTPUT_ARGS`, ``e`` and ``Rb`` [mm], ``mode``, ``shaft``,
        ``torque`` [N·m]; None: absent).
    level : str
        The level that runs (the rules are the same at "ideal" and "contact").
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
    if drag > 0.0 and a.get("mode") == "reducer" and a.get("shaft") == "H" and (a.get("torque") or 0.0) <= drag:
        return OUTPUT_ARGS["drag"], (f"= {drag:.6g} N·m: the crank's drag takes all of the reducer's input torque "
                                     f"load.torque_Nm = {a.get('torque') or 0.0:.6g} N·m (nothing reaches the teeth)")
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


def law_problem(a: dict, level: str):
    r"""(key, message) of the first problem of the teeth's sliding law's keys, else None (pins.md §4.10).

    .. math:: 0 \le v_1 < v_2 < \dots < v_m, \qquad m \ge 2

    (a table's speeds; the Stribeck law needs mu_s, mu_c and v_s; any law but coulomb needs the ideal or the contact
    level, fixed pins and a crank speed.)

    Parameters
    ----------
    a : dict
        The design's values by argument name (:data:`LAW_ARGS`, ``rotating``, ``speed``; None: absent).
    level : str
        The level that runs.

    Returns
    -------
    problem : tuple of (str, str) or None
        The design key and the message.

    Examples
    --------
    >>> law_problem({"f_law": "table", "f_v": [0.0, 1.0], "f_mu": [0.1], "rotating": False, "speed": 1000.0},
    ...             "ideal")[0]
    'friction.table_mu'

    References
    ----------
    .. [1] docs/spec/pins.md §4.10, §7.
    """
    law = a.get("f_law") or "coulomb"
    if law == "coulomb":
        return None
    if level not in ("ideal", "contact"):
        return "friction.law", (f'= "{law}": only the ideal and contact levels take a speed-dependent law (pins.md '
                                f"§4.10); the {level} level uses friction.sliding")
    if a.get("rotating"):
        return "friction.law", f'= "{law}": for fixed pins only (rotating pins roll; pins.md §4.10)'
    if a.get("speed") is None:
        return "load.crank_speed_rpm", f'missing: friction.law = "{law}" needs the crank speed (sliding speeds)'
    if law == "table":
        v, mu = a.get("f_v"), a.get("f_mu")
        if v is None or mu is None:
            key = "friction.table_speed_m_s" if v is None else "friction.table_mu"
            return key, 'missing: required with friction.law = "table"'
        if len(v) < 2:
            return "friction.table_speed_m_s", "needs at least 2 speeds"
        if len(mu) != len(v):
            return "friction.table_mu", f"has {len(mu)} values: must have as many as table_speed_m_s ({len(v)})"
        if any(b <= a_ for a_, b in zip(v, v[1:])):
            return "friction.table_speed_m_s", "must increase strictly"
        return None
    for name, what in (("f_s", "stribeck_static"), ("f_c", "stribeck_coulomb"), ("f_vs", "stribeck_speed_m_s")):
        if a.get(name) is None:
            return f"friction.{what}", 'missing: required with friction.law = "stribeck"'
    return None
