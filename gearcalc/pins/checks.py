"""The validity rules of the ``pins`` calculator (pins.md §4.2, §5.4, §7, §9), each written once.

Pure functions over the values of one design or over arrays of designs and sweep points, in the physics'
names (no design keys): ``gearcalc check`` (one design, :func:`design_problems`), ``compute`` and ``batch``
(:func:`select_level`, :func:`ideal_over_budget`, :func:`contact_over_budget`) and a vectorised sweep
(:func:`points_pass`) all call them.  A rule answers with a mask or a rule name; the key and the message of
a rule name are :data:`gearcalc.pins.report.PROBLEMS`, the key of an argument name the adapter's mapping
(:mod:`gearcalc.kinds.pins`).

Imports no numpy at module level: the adapter imports this module at start-up (``gearcalc --help``).
"""
from __future__ import annotations

from dataclasses import dataclass

from .profiles import PROFILES, tooth_too_large
from .schema import (CONTACT_NODES_MAX, CONTACT_WORK_MAX, GROUP_PINS_MAX, GROUP_TOL_MIN, IDEAL_SWEEP_WORK_MAX,
                     IDEAL_WORK_MAX)

__all__ = ["friction_model", "modified", "select_level", "contact_law_problem", "Violations", "violations",
           "pin_circle_curtate", "tooth_too_large", "design_problems", "ideal_admissibility", "ideal_over_budget",
           "contact_passes", "contact_over_budget", "computed_alone", "points_pass"]


def friction_model(model, alias, default: str) -> tuple[str, bool]:
    """The friction model of a design (pins.md §4.9, §7) and whether its alias contradicts it.

    Parameters
    ----------
    model : str or None
        "consistent", "first-order" or None (not given).
    alias : bool or None
        The alias: true for "consistent", false for "first-order", None (not given).
    default : str
        The model when neither is given.

    Returns
    -------
    (name, contradiction)

    Examples
    --------
    >>> friction_model(None, None, "consistent"), friction_model("consistent", False, "consistent")
    (('consistent', False), ('first-order', True))
    """
    if alias is None:
        return model or default, False
    from_alias = "consistent" if alias else "first-order"
    return from_alias, model is not None and model != from_alias


def modified(equidistant_mod, radial_mod) -> bool:
    """Whether a cycloid carries a profile modification Delta R_b or Delta R_p [mm] (pins.md §5.2).

    >>> modified(0.0, 0.0), modified(0.01, 0.0)
    (False, True)
    """
    return equidistant_mod != 0.0 or radial_mod != 0.0


def select_level(model, tables, profile, is_modified: bool) -> tuple[str, str | None]:
    """The level a design runs and the rule (of :data:`gearcalc.pins.report.PROBLEMS`) a forced level breaks,
    else None (pins.md §3-5).

    Without ``model`` the cheapest level the design needs: "formula" without a gear, "contact" for a circular
    profile, a modified cycloid or a contact law, else "ideal".  A forced level: the formula level needs a
    per-pin load, the cycle levels a gear, the ideal level an unmodified cycloid.

    Parameters
    ----------
    model : str or None
        The forced level (``--model``).
    tables : set of str
        The design's tables among "gearing", "pin_load", "contact".
    profile : str or None
        A name of :data:`gearcalc.pins.profiles.PROFILES`, "cycloidal" or "circular" (None without a gear); the
        ideal level computes only those its entry marks ``ideal``.
    is_modified : bool
        A cycloid with a profile modification (:func:`modified`).

    Examples
    --------
    >>> select_level(None, {"pin_load"}, None, False), select_level(None, {"gearing"}, "cycloidal", False)
    (('formula', None), ('ideal', None))
    >>> select_level(None, {"gearing"}, "circular", False), select_level("ideal", {"gearing"}, "circular", False)
    (('contact', None), ('ideal', 'ideal_profile'))
    """
    entry = PROFILES.get(profile)
    has_g, contact_only = "gearing" in tables, entry is not None and not entry.ideal    # circular teeth
    if model is None:
        level = "contact" if contact_only or is_modified or "contact" in tables else "ideal"
        return level if has_g else "formula", None
    if model == "formula" and "pin_load" not in tables:
        return model, "need_pin_load"
    if model in ("ideal", "contact") and not has_g:
        return model, "need_gearing"
    if model == "ideal" and (contact_only or is_modified):
        return model, "ideal_profile" if contact_only else "ideal_mods"
    return model, None


def contact_law_problem(law: str, face_width, stiffness):
    """The rule a contact law's missing constant breaks (pins.md §5.4, §7): the Hertz and Palmgren laws need
    the face width b [mm], the linear law its stiffness k_lin [N/mm]; else None.

    >>> contact_law_problem("hertz", None, None), contact_law_problem("linear", None, 1e5)
    ('face_width', None)

    A name that is not a law (:data:`LAW_NEEDS`, the names of :data:`gearcalc.pins.contact_law.CONTACT_LAWS`) is a
    ValueError listing the known ones.
    """
    try:
        need = LAW_NEEDS[law]
    except (KeyError, TypeError):
        raise ValueError(f"unknown contact law {law!r}; known: {', '.join(LAW_NEEDS)}") from None
    return need if {"face_width": face_width, "stiffness": stiffness}[need] is None else None


LAW_NEEDS = {"hertz": "face_width", "palmgren": "face_width", "linear": "stiffness"}
"""The constant each contact law needs (pins.md §5.4): the rule broken when it is missing.  Kept here, without numpy,
for ``gearcalc check``; a test checks its names are those of :data:`gearcalc.pins.contact_law.CONTACT_LAWS`."""


@dataclass(frozen=True)
class Violations:
    """The cross-key rules over designs or points (:func:`violations`): boolean arrays of shape (n,).

    pin_load_axle : r >= R of the per-pin load; no_sliding : f missing; one_circle : both or neither of
    R_p and K1; no_axle : rotating pins without an axle radius; geometry :
    :class:`~gearcalc.pins.geometry.GeometryViolations`.
    """

    pin_load_axle: object
    no_sliding: object
    one_circle: object
    no_axle: object
    geometry: object


def violations(z1, z2, e, Rp, K1, Rb, r, rotating, profile, sliding, load_pin_radius, load_axle_radius) -> Violations:
    r"""The cross-key rules of n designs or sweep points (pins.md §7, §9), as arrays.

    .. math:: r < R\ \text{(per-pin load)},\quad f\ \text{given},\quad R_p \oplus K_1,\quad
              r\ \text{given for rotating pins}

    with the gear's rules of :func:`~gearcalc.pins.geometry.geometry_violations` (k >= 1, K1 < 1, no
    overlapping pins, r < R_b).

    Parameters
    ----------
    z1, z2 : list of int or None
        Teeth and pins per point (None: no gear).
    e, Rp, K1, Rb, r : list of float or None
        Eccentricity, pin circle, curtate ratio, pin and axle radii [mm] (None: not given).
    rotating : list of bool; profile : list of str
        Rotating pins; "cycloidal" or "circular".
    sliding : list of float or None
        f (None: not given).
    load_pin_radius, load_axle_radius : list of float or None
        R and r of the per-pin load [mm] (pins.md §3).

    Returns
    -------
    Violations

    Examples
    --------
    >>> v = violations([20], [22], [3.9], [None], [0.75], [1.95], [None], [True], ["cycloidal"], [None],
    ...                [1.95], [2.0])
    >>> v.pin_load_axle.tolist(), v.no_sliding.tolist(), v.one_circle.tolist(), v.no_axle.tolist()
    ([True], [True], [False], [True])
    """
    import numpy as np

    from .operating import floats
    from .geometry import geometry_violations

    K1g, Rpg, r_ = floats(K1), floats(Rp), floats(r)
    rot = np.array([bool(v) for v in rotating])
    has_g = all(v is not None for v in z1 + z2)
    geometry = geometry_violations(z1 if has_g else 0, z2 if has_g else 0, floats(e), Rpg, K1g, floats(Rb), r_, rot,
                                   np.array([p == "cycloidal" for p in profile]))
    with np.errstate(invalid="ignore"):
        return Violations(pin_load_axle=floats(load_axle_radius) >= floats(load_pin_radius),
                          no_sliding=np.array([v is None for v in sliding]),
                          one_circle=np.isnan(K1g) == np.isnan(Rpg), no_axle=rot & np.isnan(r_), geometry=geometry)


def pin_circle_curtate(z1: int, z2: int, e: float, Rp, K1):
    """(R_p [mm], K1, 1 - K1) of one gear from whichever of R_p and K1 is given (the other None): K1 as given,
    else e z2/(k R_p) (:func:`~gearcalc.pins.operating.pin_circle`, pins.md §4.1, §7).

    >>> pin_circle_curtate(20, 22, 3.9, None, 0.75)
    (57.199999999999996, 0.75, 0.25)
    """
    import math

    import numpy as np

    from .operating import SCALAR_OPS, pin_circle

    with np.errstate(all="ignore"):  # float64 scalars: a K1 so large that k*K1 overflows gives R_p = 0, no exception
        Rp, omk = pin_circle(z1, z2, np.float64(e), math.nan if Rp is None else Rp, math.nan if K1 is None else K1,
                             SCALAR_OPS)
    return float(Rp), (e * z2 / ((z2 - z1) * Rp) if K1 is None else K1), float(omk)


def design_problems(bad: Violations, tables: set, z1, z2, e, Rp, K1, Rb, r, rotating, profile, tooth_radius,
                    tooth_circle_radius, is_modified, load_pin_radius, load_axle_radius) -> list:
    """The cross-key problems of one design (pins.md §5.3, §7, §9) in the order ``gearcalc check`` reports
    them: (severity "error" or "warn", rule of :data:`gearcalc.pins.report.PROBLEMS` or the name of a
    warning, the numbers of its message).  ``bad``: :func:`violations` of the design (arrays of one);
    ``tables``: the design's tables among "gearing", "pin_load", "load"; ``Rp``, ``K1``: as given (None: not).
    The list ends early without a gear (the gear's rules and the level's do not apply) and at a curtate ratio
    that overflows R_p (the rules after it cannot be evaluated): ``gearcalc check`` stops there too.

    >>> bad = violations([20], [22], [3.9], [None], [0.75], [9.0], [None], [False], ["cycloidal"], [0.1],
    ...                  [None], [None])
    >>> [(s, rule) for s, rule, _ in design_problems(bad, {"gearing", "load"}, 20, 22, 3.9, None, 0.75, 9.0, None,
    ...                                               False, "cycloidal", "full", "zero_backlash", False, None, None)]
    [('error', 'overlap')]
    """
    if not tables & {"gearing", "pin_load"}:
        return [("error", "no_tables", {})]
    out = []
    if "pin_load" in tables and bad.pin_load_axle[0]:
        out.append(("error", "pin_load_axle", {"r": load_axle_radius, "R": load_pin_radius}))
    if "gearing" not in tables:
        return out
    if "load" not in tables:
        out.append(("error", "no_load", {}))
    if bad.no_sliding[0]:
        out.append(("error", "no_sliding", {}))
    geo = bad.geometry
    ok_teeth = not geo.teeth[0]
    if not ok_teeth:
        out.append(("error", "teeth", {"z1": z1, "z2": z2}))
    if bad.one_circle[0]:
        out.append(("error", "one_circle", {"given": "both" if Rp is not None else "neither"}))
    elif ok_teeth:
        Rp_, K1_, _ = pin_circle_curtate(z1, z2, e, Rp, K1)
        k = z2 - z1
        if geo.overflow[0]:        # e.g. K1 = 5e-324: R_p = inf (was exit 70)
            out.append(("error", "overflow", {"K1": K1_, "e": e, "ratio": z2 / k}))
            return out
        if geo.curtate[0]:
            out.append(("error", "curtate_K1", {"K1": K1_}) if K1 is not None else
                       ("error", "curtate_Rp", {"Rp": Rp_, "K1": K1_, "limit": e * z2 / k, "e": e}))
        if geo.overlap[0]:         # R_b >= R_p sin(pi/z2) (geometry_violations)
            out.append(("error", "overlap", {"Rb": Rb, "limit": float(geo.overlap_limit[0]), "Rp": Rp_, "z2": z2}))
    if rotating:
        if bad.no_axle[0]:
            out.append(("error", "no_axle", {}))
        elif geo.axle[0]:
            out.append(("error", "axle", {"r": r, "Rb": Rb}))
    circular = profile == "circular"
    if circular and ok_teeth and tooth_radius != "full" and (Rp is None) != (K1 is None):
        Rp_, _, _ = pin_circle_curtate(z1, z2, e, Rp, K1)
        if tooth_too_large(Rb, tooth_radius, Rp_, e):
            out.append(("error", "tooth_too_large", {"rho_t": tooth_radius, "sum": Rb + tooth_radius,
                                                     "limit": Rp_ - e}))
    if not circular:
        for name, value in (("tooth_radius", tooth_radius), ("tooth_circle_radius", tooth_circle_radius)):
            if value not in ("full", "zero_backlash"):
                out.append(("warn", "circular_only", {"name": name}))
    elif is_modified:
        out.append(("warn", "cycloid_mods_ignored", {}))
    return out


def ideal_admissibility(z1: int, z2: int, e: float, Rp, K1, Rb: float):
    """(status, psi* [rad], min rho_c [mm], K1) of one gear at the ideal level (pins.md §4.2, §12.10):
    :func:`~gearcalc.pins.ideal.admissibility`, the rule the ideal level's solve applies to every gear; ``Rp``,
    ``K1`` as given (None: not), K1 = e z2/(k R_p) as that level computes it.

    >>> status, psi_star, rho_c, K1 = ideal_admissibility(20, 22, 3.9, None, 0.75, 1.95)
    >>> status, round(K1, 12)
    (0, 0.75)
    """
    import numpy as np

    from .geometry import Cycloid
    from .ideal import admissibility

    Rp, _, omk = pin_circle_curtate(z1, z2, e, Rp, K1)
    status, psi_star, rho_c = admissibility(Cycloid(np.array([z1]), np.array([z2]), np.array([float(e)]),
                                                    np.array([float(Rp)]), np.array([float(Rb)]),
                                                    np.array([float(omk)])))
    return int(status[0]), float(psi_star[0]), float(rho_c[0]), e * z2 / ((z2 - z1) * Rp)


def ideal_over_budget(z2, n_discs):
    """Whether the ideal level's cost z2 n_d exceeds :data:`~gearcalc.pins.schema.IDEAL_WORK_MAX` (pins.md §9);
    scalars or arrays.

    >>> ideal_over_budget(10_000, 20), ideal_over_budget(10_000, 21)
    (False, True)
    """
    return z2 * n_discs > IDEAL_WORK_MAX


def contact_passes(torque_on_V: bool) -> int:
    """Passes of the contact level's torque fixed point: 1 with the torque on V, 3 on H (pins.md §7)."""
    return 1 if torque_on_V else 3


def contact_over_budget(z2: int, torque_on_V: bool) -> bool:
    """Whether the contact level's z2 x CONTACT_NODES_MAX x passes pin-contact solves exceed
    :data:`~gearcalc.pins.schema.CONTACT_WORK_MAX` (pins.md §9).

    >>> contact_over_budget(114, False), contact_over_budget(115, False), contact_over_budget(344, True)
    (False, True, False)
    """
    return z2 * CONTACT_NODES_MAX * contact_passes(torque_on_V) > CONTACT_WORK_MAX


def computed_alone(z2: int, n_discs: int, tol: float) -> bool:
    """Whether a batch computes an ideal-level design alone rather than in a group (memory, pins.md §6): more
    pin-discs than :data:`~gearcalc.pins.schema.GROUP_PINS_MAX`, or a --tol below
    :data:`~gearcalc.pins.schema.GROUP_TOL_MIN`.

    >>> computed_alone(22, 1, 1e-6), computed_alone(22, 10, 1e-6), computed_alone(22, 1, 1e-12)
    (False, True, True)
    """
    return tol < GROUP_TOL_MIN or z2 * n_discs > GROUP_PINS_MAX


def points_pass(bad: Violations, formula: bool, has_pin_load: bool, z1, z2, n_d, e, Rb, K1, Rp) -> bool:
    """Whether every point of a vectorised sweep passes the rules its varied keys can break (pins.md §7, §9).

    ``bad``: :func:`violations` of the points; ``formula``: the sweep runs the formula level; the gear as lists
    per point (None: not given).  The rules of :func:`design_problems` as arrays (the per-pin load's axle; at
    the ideal level f given, k >= 1, one of R_p and K1, the gear's geometry, the axle) and the cost budgets:
    :func:`ideal_over_budget` per point, and :data:`~gearcalc.pins.schema.IDEAL_SWEEP_WORK_MAX` pin-discs over
    the distinct geometries (solved together; a larger grid runs point by point, bounded memory).
    """
    import numpy as np

    from .operating import floats

    if has_pin_load and np.any(bad.pin_load_axle):
        return False
    if formula:
        return True
    if np.any(bad.no_sliding) or np.any(bad.geometry.teeth) or np.any(bad.one_circle):
        return False
    z1, z2, n_d = (np.array(v, dtype=np.int64) for v in (z1, z2, n_d))
    if np.any(ideal_over_budget(z2, n_d)):         # reported point by point
        return False
    key = np.nan_to_num(np.stack([z1, z2, n_d, floats(e), floats(Rb), floats(K1), floats(Rp)], axis=1).astype(float),
                        nan=-1.0)
    geometries = np.unique(key, axis=0)         # each distinct geometry is solved once
    if float((geometries[:, 1] * geometries[:, 2]).sum()) > IDEAL_SWEEP_WORK_MAX:
        return False
    return not (np.any(bad.geometry.any()) or np.any(bad.no_axle))
