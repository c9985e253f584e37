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
from typing import NamedTuple

from ..calculator import Check
from .profiles import PROFILES, tooth_too_large
from .schema import (CONTACT_NODES_MAX, CONTACT_WORK_MAX, GROUP_PINS_MAX, GROUP_TOL_MIN, IDEAL_SWEEP_WORK_MAX,
                     IDEAL_WORK_MAX)

__all__ = ["CHECKS", "friction_model", "modified", "select_level", "level_cause",
           "contact_law_problem", "GearGiven", "PinLoadGiven", "Violations", "violations",
           "pin_circle_curtate", "tooth_too_large", "design_problems", "ideal_admissibility", "ideal_over_budget",
           "contact_passes", "contact_over_budget", "contact_pins_max", "computed_alone", "points_pass",
           "RollingValues", "SatelliteTurn", "satellite_turn"]


def friction_model(model, alias, default: str) -> tuple[str, bool]:
    r"""The friction model of a design (pins.md §4.9, §7) and whether its alias contradicts it.

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

    .. math:: \text{name} = \text{model, else (alias ? "consistent" : "first-order"), else default}

    Examples
    --------
    >>> friction_model(None, None, "consistent"), friction_model("consistent", False, "consistent")
    (('consistent', False), ('first-order', True))

    References
    ----------
    .. [1] docs/spec/pins.md §4.9, §7.
    """
    if alias is None:
        return model or default, False
    from_alias = "consistent" if alias else "first-order"
    return from_alias, model is not None and model != from_alias


def modified(equidistant_mod, radial_mod) -> bool:
    r"""Whether a cycloid carries a profile modification Delta R_b or Delta R_p [mm] (pins.md §5.2).

    .. math:: \Delta R_b \ne 0 \ \lor\ \Delta R_p \ne 0

    Parameters
    ----------
    equidistant_mod : float
        Equidistant modification Delta R_b, [mm].
    radial_mod : float
        Radial modification Delta R_p, [mm].

    Returns
    -------
    modified : bool
        True for a modified cycloid.

    Examples
    --------
    >>> modified(0.0, 0.0), modified(0.01, 0.0)
    (False, True)

    References
    ----------
    .. [1] docs/spec/pins.md §5.2.
    """
    return equidistant_mod != 0.0 or radial_mod != 0.0


def select_level(model, tables, profile, is_modified: bool) -> tuple[str, str | None]:
    """The level a design runs and the rule a forced level breaks.

    The level a design runs and the rule (of :data:`gearcalc.pins.report.PROBLEMS`) a forced level breaks, else None
    (pins.md §3-5).

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

    Returns
    -------
    level : str
        "formula", "ideal" or "contact".
    rule : str or None
        The rule a forced level breaks, else None.

    Examples
    --------
    >>> select_level(None, {"pin_load"}, None, False), select_level(None, {"gearing"}, "cycloidal", False)
    (('formula', None), ('ideal', None))
    >>> select_level(None, {"gearing"}, "circular", False), select_level("ideal", {"gearing"}, "circular", False)
    (('contact', None), ('ideal', 'ideal_profile'))

    References
    ----------
    .. [1] docs/spec/pins.md §3-5, §7.
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


CHECKS = (Check("self_locking", "the requested mode self-locks"),
          Check("rolling", "f R_b < f_c r + f_k: the bushings cannot turn"),
          Check("contact_stress", "contact_stress_max > allowable_stress"))
"""The pins design checks (pins.md §8): their margins, the summary fields margin_<name>, are
:mod:`gearcalc.pins.margins`'."""

def level_cause(model, tables, profile, is_modified: bool) -> str:
    """Why a design runs at the level :func:`select_level` gives it.

    A cause of :data:`gearcalc.pins.report.LEVEL_REASONS` (the summary's ``model_reason`` in words).

    Parameters
    ----------
    model : str or None
        The level forced by the caller, else None.
    tables : set of str
        The design's tables among "gearing", "pin_load", "load" and "contact" (the last where it names a
        contact law).
    profile : str or None
        The tooth profile's name.
    is_modified : bool
        A modified cycloid (equidistant or radial modification).

    Returns
    -------
    cause : str
        "forced", "pin_load" (no gear), "circular", "modified", "contact_law" or "cycloid".

    Examples
    --------
    >>> level_cause(None, {"gearing", "load"}, "cycloidal", False), level_cause("contact", {"gearing"}, None, False)
    ('cycloid', 'forced')

    References
    ----------
    .. [1] gearcalc specification docs/spec/pins.md §7 (design keys: the level each table calls for), §8.
    """
    if model is not None:
        return "forced"
    if "gearing" not in tables:
        return "pin_load"
    if profile == "circular":
        return "circular"
    if is_modified:
        return "modified"
    if "contact" in tables:
        return "contact_law"
    return "cycloid"


def contact_law_problem(law: str, face_width, stiffness):
    r"""The rule a contact law's missing constant breaks (pins.md §5.4, §7).

    The Hertz and Palmgren laws need the face width b [mm], the linear law its stiffness k_lin [N/mm]; else None.

    .. math:: b \ \text{given (hertz, palmgren)}, \qquad k_{lin} \ \text{given (linear)}

    Parameters
    ----------
    law : str
        The contact law's name.
    face_width : float or None
        Contact length b, [mm].
    stiffness : float or None
        Linear stiffness k_lin, [N/mm].

    Returns
    -------
    rule : str or None
        The missing key's rule, else None.

    Examples
    --------
    >>> contact_law_problem("hertz", None, None), contact_law_problem("linear", None, 1e5)
    ('face_width', None)

    A name that is not a law (:data:`LAW_NEEDS`, the names of :data:`gearcalc.pins.contact_law.CONTACT_LAWS`) is a
    ValueError listing the known ones.

    References
    ----------
    .. [1] docs/spec/pins.md §5.4, §7.
    """
    try:
        need = LAW_NEEDS[law]
    except (KeyError, TypeError):
        raise ValueError(f"unknown contact law {law!r}; known: {', '.join(LAW_NEEDS)}") from None
    return need if {"face_width": face_width, "stiffness": stiffness}[need] is None else None


LAW_NEEDS = {"hertz": "face_width", "palmgren": "face_width", "linear": "stiffness"}
"""The constant each contact law needs (pins.md §5.4): the rule broken when it is missing.  Kept here, without numpy,
for ``gearcalc check``; a test checks its names are those of :data:`gearcalc.pins.contact_law.CONTACT_LAWS`."""


class GearGiven(NamedTuple):
    """A pin gear's keys as a design gives them, in the physics' names (pins.md §3, §7).

    Each field holds one design's value (:func:`design_problems`) or a list of the values of n designs or sweep
    points (:func:`violations`, :func:`points_pass`); None where the key is not given.

    Attributes
    ----------
    z1, z2 : int or None
        Satellite teeth and pins, [-] (None: no gear).
    e : float or None
        Eccentricity, [mm].
    Rp : float or None
        Pin circle radius R_p, [mm] (None: K1 given instead).
    K1 : float or None
        Curtate ratio, [-] (None: R_p given instead).
    Rb : float or None
        Pin (bushing) radius R_b, [mm].
    r : float or None
        Axle radius of rotating pins, [mm].
    rotating : bool
        Rotating pins (bushings on axles).
    profile : str
        The satellite's profile, "cycloidal" or "circular".
    """

    z1: object
    z2: object
    e: object
    Rp: object
    K1: object
    Rb: object
    r: object
    rotating: object
    profile: object


class PinLoadGiven(NamedTuple):
    """The radii of the per-pin load ``[pin_load]`` (pins.md §3), one design's or lists over points (None: absent).

    Attributes
    ----------
    pin_radius : float or None
        Bushing radius R, [mm].
    axle_radius : float or None
        Axle radius r, [mm].
    """

    pin_radius: object
    axle_radius: object


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


def violations(gear: GearGiven, sliding, pin_load: PinLoadGiven) -> Violations:
    r"""The cross-key rules of n designs or sweep points (pins.md §7, §9), as arrays.

    .. math:: r < R\ \text{(per-pin load)},\quad f\ \text{given},\quad R_p \oplus K_1,\quad
              r\ \text{given for rotating pins}

    with the gear's rules of :func:`~gearcalc.pins.geometry.geometry_violations` (k >= 1, K1 < 1, no
    overlapping pins, r < R_b).

    Parameters
    ----------
    gear : GearGiven
        The gear per point, lists of n values (None: not given; z1, z2 None: no gear).
    sliding : list of float or None
        f (None: not given).
    pin_load : PinLoadGiven
        R and r of the per-pin load per point [mm] (pins.md §3), lists of n values.

    Returns
    -------
    Violations

    Examples
    --------
    >>> gear = GearGiven([20], [22], [3.9], [None], [0.75], [1.95], [None], [True], ["cycloidal"])
    >>> v = violations(gear, [None], PinLoadGiven([1.95], [2.0]))
    >>> v.pin_load_axle.tolist(), v.no_sliding.tolist(), v.one_circle.tolist(), v.no_axle.tolist()
    ([True], [True], [False], [True])

    References
    ----------
    .. [1] A. P. Prudnikov, «Потери мощности в контакте цевок и зубьев планетарной передачи типа K-H-V» (Power losses in
       pins and teeth contact area of KHV-type planetary gearing), Машиностроение (seed file 000_fe288dec6e7c72f0.txt);
       docs/spec/pins.md §3, §4.2, §7, §9.
    """
    import numpy as np

    from .operating import floats
    from .geometry import PinMounting, geometry_violations

    K1g, Rpg, r_ = floats(gear.K1), floats(gear.Rp), floats(gear.r)
    rot = np.array([bool(v) for v in gear.rotating])
    has_g = all(v is not None for v in gear.z1 + gear.z2)
    geometry = geometry_violations(gear.z1 if has_g else 0, gear.z2 if has_g else 0, floats(gear.e), Rpg, K1g,
                                   floats(gear.Rb), PinMounting(r_, rot),
                                   np.array([p == "cycloidal" for p in gear.profile]))
    with np.errstate(invalid="ignore"):
        return Violations(pin_load_axle=floats(pin_load.axle_radius) >= floats(pin_load.pin_radius),
                          no_sliding=np.array([v is None for v in sliding]),
                          one_circle=np.isnan(K1g) == np.isnan(Rpg), no_axle=rot & np.isnan(r_), geometry=geometry)


def pin_circle_curtate(z1: int, z2: int, e: float, Rp, K1):
    r"""(R_p [mm], K1, 1 - K1) of one gear from whichever of R_p and K1 is given (the other None).

    K1 as given, else e z2/(k R_p) (:func:`~gearcalc.pins.operating.pin_circle`, pins.md §4.1, §7).

    .. math:: K_1 = \frac{e\,z_2}{k\,R_p}, \qquad R_p = \frac{e\,z_2}{k\,K_1}, \qquad k = z_2 - z_1

    Parameters
    ----------
    z1, z2 : int
        Teeth and pins, [-].
    e : float
        Eccentricity, [mm].
    Rp : float or None
        Pin circle radius R_p, [mm], or None.
    K1 : float or None
        Curtate ratio, [-], or None.

    Returns
    -------
    Rp, K1, one_minus_K1 : float
        R_p [mm], K1 [-] and 1 - K1 [-].

    Examples
    --------
    >>> pin_circle_curtate(20, 22, 3.9, None, 0.75)
    (57.199999999999996, 0.75, 0.25)

    References
    ----------
    .. [1] docs/spec/pins.md §4.1, §7.
    """
    import math

    import numpy as np

    from .operating import SCALAR_OPS, pin_circle

    with np.errstate(all="ignore"):  # float64 scalars: a K1 so large that k*K1 overflows gives R_p = 0, no exception
        Rp, omk = pin_circle(z1, z2, np.float64(e), math.nan if Rp is None else Rp, math.nan if K1 is None else K1,
                             SCALAR_OPS)
    return float(Rp), (e * z2 / ((z2 - z1) * Rp) if K1 is None else K1), float(omk)


def design_problems(bad: Violations, tables: set, gear: GearGiven, pin_load: PinLoadGiven, tooth_radius,
                    tooth_circle_radius, is_modified: bool) -> list:
    """The cross-key problems of one design (pins.md §5.3, §7, §9) in the order ``gearcalc check`` reports them.

    (severity "error" or "warn", rule of :data:`gearcalc.pins.report.PROBLEMS` or the name of a warning, the numbers
    of its message).  The list ends early without a gear (the gear's rules and the level's do not apply) and at a
    curtate ratio that overflows R_p (the rules after it cannot be evaluated): ``gearcalc check`` stops there too.
    The steps: the tables (:func:`_table_problems`), the gear (:func:`_gear_problems`), its pins' axles
    (:func:`_axle_problems`), its profile (:func:`_profile_problems`).

    Parameters
    ----------
    bad : Violations
        :func:`violations` of the design (arrays of one).
    tables : set of str
        The design's tables among "gearing", "pin_load", "load".
    gear : GearGiven
        The design's gear, one value per field, as given (R_p, K1: None where not given).
    pin_load : PinLoadGiven
        R and r of the per-pin load, [mm].
    tooth_radius, tooth_circle_radius : float or str
        rho_t and R_t [mm], or "full" and "zero_backlash".
    is_modified : bool
        A modified cycloid.

    Returns
    -------
    problems : list of tuple
        (severity, rule, numbers of its message).

    Examples
    --------
    >>> one = GearGiven(20, 22, 3.9, None, 0.75, 9.0, None, False, "cycloidal")
    >>> points = GearGiven(*([v] for v in one))
    >>> bad = violations(points, [0.1], PinLoadGiven([None], [None]))
    >>> [(s, rule) for s, rule, _ in design_problems(bad, {"gearing", "load"}, one, PinLoadGiven(None, None),
    ...                                               "full", "zero_backlash", False)]
    [('error', 'overlap')]

    References
    ----------
    .. [1] docs/spec/pins.md §5.3, §7, §9.
    """
    if not tables & {"gearing", "pin_load"}:
        return [("error", "no_tables", {})]
    out = _table_problems(bad, tables, pin_load)
    if "gearing" not in tables:
        return out
    gear_out, stop = _gear_problems(bad, gear)
    out.extend(gear_out)
    if stop:
        return out
    out.extend(_axle_problems(bad, gear))
    out.extend(_profile_problems(bad, gear, tooth_radius, tooth_circle_radius, is_modified))
    return out


def _table_problems(bad: Violations, tables: set, pin_load: PinLoadGiven) -> list:
    """The problems of one design's tables (:func:`design_problems`'s first step, pins.md §3, §7).

    The per-pin load's axle; with [gearing], [load] and friction.sliding missing.
    """
    out = []
    if "pin_load" in tables and bad.pin_load_axle[0]:
        out.append(("error", "pin_load_axle", {"r": pin_load.axle_radius, "R": pin_load.pin_radius}))
    if "gearing" not in tables:
        return out
    if "load" not in tables:
        out.append(("error", "no_load", {}))
    if bad.no_sliding[0]:
        out.append(("error", "no_sliding", {}))
    return out


def _gear_problems(bad: Violations, gear: GearGiven) -> tuple[list, bool]:
    """(problems, stop) of one design's gear (pins.md §4.1, §7, §9).

    k >= 1, one of R_p and K1, R_p finite (else ``stop``: the rules after it cannot be evaluated), K1 < 1, no
    overlapping pins.
    """
    geo, out = bad.geometry, []
    z1, z2, e, Rp, K1 = gear.z1, gear.z2, gear.e, gear.Rp, gear.K1
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
            return out, True
        if geo.curtate[0]:
            out.append(("error", "curtate_K1", {"K1": K1_}) if K1 is not None else
                       ("error", "curtate_Rp", {"Rp": Rp_, "K1": K1_, "limit": e * z2 / k, "e": e}))
        if geo.overlap[0]:         # R_b >= R_p sin(pi/z2) (geometry_violations)
            out.append(("error", "overlap", {"Rb": gear.Rb, "limit": float(geo.overlap_limit[0]), "Rp": Rp_,
                                             "z2": z2}))
    return out, False


def _axle_problems(bad: Violations, gear: GearGiven) -> list:
    """The problems of one design's rotating pins (pins.md §7): an axle radius given, and r < R_b."""
    if not gear.rotating:
        return []
    if bad.no_axle[0]:
        return [("error", "no_axle", {})]
    return [("error", "axle", {"r": gear.r, "Rb": gear.Rb})] if bad.geometry.axle[0] else []


def _profile_problems(bad: Violations, gear: GearGiven, tooth_radius, tooth_circle_radius, is_modified) -> list:
    """The problems of one design's profile (pins.md §5.3).

    A circular tooth that fits (R_b + rho_t < R_p - e); the warnings of the keys of the other profile.
    """
    out, circular = [], gear.profile == "circular"
    z1, z2, e, Rp, K1, Rb = gear.z1, gear.z2, gear.e, gear.Rp, gear.K1, gear.Rb
    if circular and not bad.geometry.teeth[0] and tooth_radius != "full" and (Rp is None) != (K1 is None):
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
    r"""(status, psi* [rad], min rho_c [mm], K1) of one gear at the ideal level (pins.md §4.2, §12.10).

    :func:`~gearcalc.pins.ideal.admissibility`, the rule the ideal level's solve applies to every gear; ``Rp``,
    ``K1`` as given (None: not), K1 = e z2/(k R_p) as that level computes it.

    .. math:: \psi^* > \frac{2\pi}{z_2} \ \text{(enough teeth)}, \qquad R_b < \min_{0 \le \psi \le \psi^*} \rho_c(\psi)
        \ \text{(no undercut)}, \qquad K_1 = \frac{e\,z_2}{k\,R_p}

    Parameters
    ----------
    z1, z2 : int
        Teeth and pins, [-].
    e : float
        Eccentricity, [mm].
    Rp : float or None
        Pin circle radius, [mm], or None.
    K1 : float or None
        Curtate ratio, [-], or None.
    Rb : float
        Pin radius, [mm].

    Returns
    -------
    status : int
        0, TOO_FEW_TEETH or UNDERCUT.
    psi_star : float
        End of the loaded arc, [rad].
    rho_c : float
        Least radius of curvature, [mm].
    K1 : float
        Curtate ratio, [-].

    Examples
    --------
    >>> status, psi_star, rho_c, K1 = ideal_admissibility(20, 22, 3.9, None, 0.75, 1.95)
    >>> status, round(K1, 12)
    (0, 0.75)

    References
    ----------
    .. [1] docs/spec/pins.md §4.2, §12.10.
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
    r"""Whether the ideal level's cost z2 n_d exceeds :data:`~gearcalc.pins.schema.IDEAL_WORK_MAX` (pins.md §9).

    scalars or arrays.

    .. math:: z_2\,n_d > W_{ideal} = 200\,000

    Parameters
    ----------
    z2 : int or array_like
        Pins, [-].
    n_discs : int or array_like
        Discs n_d, [-].

    Returns
    -------
    over : bool or ndarray of bool
        True over the budget.

    Examples
    --------
    >>> ideal_over_budget(10_000, 20), ideal_over_budget(10_000, 21)
    (False, True)

    References
    ----------
    .. [1] docs/spec/pins.md §9.
    """
    return z2 * n_discs > IDEAL_WORK_MAX


def contact_passes(torque_on_V: bool) -> int:
    r"""Passes of the contact level's torque fixed point: 1 with the torque on V, 3 on H.

    .. math:: n_{passes} = 1 \ \text{(torque on V)}, \qquad n_{passes} = 3 \ \text{(torque on H)}

    Parameters
    ----------
    torque_on_V : bool
        The design's torque is given on the output shaft V.

    Returns
    -------
    passes : int
        The passes budgeted.

    Examples
    --------
    >>> contact_passes(True), contact_passes(False)
    (1, 3)

    References
    ----------
    .. [1] docs/spec/pins.md §7, §9.
    """
    return 1 if torque_on_V else 3


def contact_over_budget(z2: int, torque_on_V: bool) -> bool:
    r"""Whether the contact level's work exceeds its limit (pins.md §9).

    Whether the contact level's z2 x CONTACT_NODES_MAX x passes pin-contact solves exceed
    :data:`~gearcalc.pins.schema.CONTACT_WORK_MAX` (pins.md §9).

    .. math:: z_2 \cdot N_{nodes} \cdot n_{passes} > W_{contact}, \qquad N_{nodes} = 4352,\ W_{contact} = 1.5 \cdot 10^6

    Parameters
    ----------
    z2 : int
        Pins, [-].
    torque_on_V : bool
        The torque is given on V (one pass) rather than on H (three).

    Returns
    -------
    over : bool
        True over the budget.

    Examples
    --------
    >>> contact_over_budget(114, False), contact_over_budget(115, False), contact_over_budget(344, True)
    (False, True, False)

    References
    ----------
    .. [1] docs/spec/pins.md §7, §9.
    """
    return z2 > contact_pins_max(torque_on_V)   # z2 N p > W for whole pins: the bound of the message, once


def contact_pins_max(torque_on_V: bool) -> int:
    r"""The most pins the contact level's budget allows (pins.md §9): the bound :func:`contact_over_budget` applies.

    .. math:: z_{2,max} = \left\lfloor \frac{W_{contact}}{N_{nodes}\,n_{passes}} \right\rfloor

    Parameters
    ----------
    torque_on_V : bool
        The torque is given on V (one pass) rather than on H (three).

    Returns
    -------
    z2_max : int
        Pins, [-].

    Examples
    --------
    >>> contact_pins_max(False), contact_pins_max(True)
    (114, 344)

    References
    ----------
    .. [1] docs/spec/pins.md §7, §9.
    """
    return CONTACT_WORK_MAX // (CONTACT_NODES_MAX * contact_passes(torque_on_V))


def computed_alone(z2: int, n_discs: int, tol: float) -> bool:
    r"""Whether a batch computes an ideal-level design alone rather than in a group (memory, pins.md §6).

    more pin-discs than :data:`~gearcalc.pins.schema.GROUP_PINS_MAX`, or a --tol below
    :data:`~gearcalc.pins.schema.GROUP_TOL_MIN`.

    .. math:: z_2\,n_d > 200 \quad\lor\quad \text{tol} < 10^{-9}

    Parameters
    ----------
    z2 : int
        Pins, [-].
    n_discs : int
        Discs n_d, [-].
    tol : float
        The relative tolerance (--tol), [-].

    Returns
    -------
    alone : bool
        True when the design is computed alone.

    Examples
    --------
    >>> computed_alone(22, 1, 1e-6), computed_alone(22, 10, 1e-6), computed_alone(22, 1, 1e-12)
    (False, True, True)

    References
    ----------
    .. [1] docs/spec/pins.md §6.
    """
    return tol < GROUP_TOL_MIN or z2 * n_discs > GROUP_PINS_MAX


def points_pass(bad: Violations, formula: bool, has_pin_load: bool, gear: GearGiven, n_d) -> bool:
    """Whether every point of a vectorised sweep passes the rules its varied keys can break.

    The rules of :func:`design_problems` as arrays (the per-pin load's axle; at the ideal level f given, k >= 1,
    one of R_p and K1, the gear's geometry, the axle) and the cost budgets: :func:`ideal_over_budget` per point,
    and :data:`~gearcalc.pins.schema.IDEAL_SWEEP_WORK_MAX` pin-discs over the distinct geometries (solved together;
    a larger grid runs point by point, bounded memory).

    Parameters
    ----------
    bad : Violations
        :func:`violations` of the points.
    formula : bool
        The sweep runs the formula level.
    has_pin_load : bool
        The design has a per-pin load.
    gear : GearGiven
        The gear per point, lists of n values (None: not given).
    n_d : list of int
        Discs per point, [-].

    Returns
    -------
    ok : bool
        True when every point passes.

    Examples
    --------
    >>> gear = GearGiven([20, 20], [22, 22], [3.9, 3.9], [None, None], [0.75, 0.75], [1.95, 9.0], [None, None],
    ...                  [False, False], ["cycloidal"] * 2)
    >>> bad = violations(gear, [0.1, 0.1], PinLoadGiven([None, None], [None, None]))
    >>> points_pass(bad, False, False, gear, [1, 1])   # the second point's pins overlap
    False

    References
    ----------
    .. [1] docs/spec/pins.md §7, §9.
    """
    import numpy as np

    from .operating import floats

    if has_pin_load and np.any(bad.pin_load_axle):
        return False
    if formula:
        return True
    if np.any(bad.no_sliding) or np.any(bad.geometry.teeth) or np.any(bad.one_circle):
        return False
    z1, z2, n_d = (np.array(v, dtype=np.int64) for v in (gear.z1, gear.z2, n_d))
    if np.any(ideal_over_budget(z2, n_d)):         # reported point by point
        return False
    key = np.nan_to_num(np.stack([z1, z2, n_d, floats(gear.e), floats(gear.Rb), floats(gear.K1), floats(gear.Rp)],
                                 axis=1).astype(float), nan=-1.0)
    geometries = np.unique(key, axis=0)         # each distinct geometry is solved once
    if float((geometries[:, 1] * geometries[:, 2]).sum()) > IDEAL_SWEEP_WORK_MAX:
        return False
    return not (np.any(bad.geometry.any()) or np.any(bad.no_axle))


class RollingValues(NamedTuple):
    r"""One design's values in the rolling condition of rotating pins, f R_b >= f_c r + f_k (pins.md §4.5).

    :func:`gearcalc.pins.friction.rolling_condition` decides it; :meth:`sides` gives its two sides for the message
    of a design that fails it.

    Attributes
    ----------
    sliding : float
        Tooth-pin sliding friction f, [-].
    pin_radius : float
        Bushing radius R_b, [mm].
    axle_friction : float
        Bushing-axle friction f_c, [-].
    axle_radius : float or None
        Axle radius r, [mm] (None: not given).
    rolling : float
        Rolling friction f_k, [mm].

    Examples
    --------
    >>> [round(x, 12) for x in RollingValues(0.1, 1.95, 0.1, 0.95, 5.0).sides()]
    [0.195, 5.095]
    """

    sliding: float
    pin_radius: float
    axle_friction: float
    axle_radius: object
    rolling: float

    def sides(self) -> tuple[float, float]:
        r"""(f R_b, f_c r + f_k) [mm]: the moment arms that drive and that resist the bushing.

        .. math:: f\,R_b \ \ge\ f_c\,r + f_k
        """
        return self.sliding * self.pin_radius, self.axle_friction * self.axle_radius + self.rolling


class SatelliteTurn(NamedTuple):
    """How far the satellite turns under the load in one mode's contact cycle (pins.md §6-7, §8).

    Attributes
    ----------
    turn_max : float
        The largest rotation max |tau|, [rad].
    turn_range : float
        The transmission error peak to peak, max tau - min tau, [rad].
    travel : float
        The largest pin-centre travel over the pin radius (:func:`gearcalc.pins.contact_cycle.pin_travel`), [-].
    travel_max : float
        The largest travel the contact level's results are trusted for (``ContactSettings.travel_max``), [-].
    sized : bool
        A deflection-sized rotation (:func:`gearcalc.pins.contact_cycle.deflection_sized`): travel <= travel_max.
    """

    turn_max: float
    turn_range: float
    travel: float
    travel_max: float
    sized: bool


def satellite_turn(cycle) -> SatelliteTurn:
    r"""The satellite's rotation under the load in one mode's contact cycle and whether it is a deflection.

    The rule of pins.md §7 ("Several equilibria"): a pin centre that travels more than ``travel_max`` of its radius
    meets its tooth far from its nominal place; the loss ratio is then not known to the stated error.

    .. math:: \frac{\max|\tau|\,(R_p + e)}{R_b} \le \text{travel}_{max}

    Parameters
    ----------
    cycle : gearcalc.pins.contact.TorqueCycle
        One mode's cycle at its torque (its model's gear and settings, its solved rotations tau [rad]).

    Returns
    -------
    SatelliteTurn

    Examples
    --------
    >>> from types import SimpleNamespace as NS
    >>> import numpy as np
    >>> from gearcalc.pins.geometry import Cycloid
    >>> from gearcalc.pins.contact import DEFAULT_SETTINGS
    >>> g = Cycloid.from_curtate_ratio(20, 22, 3.9, 0.75, 1.95)
    >>> tc = NS(cycle=NS(sol=NS(tau=np.array([1e-3, -2e-3]))), model=NS(g=g, settings=DEFAULT_SETTINGS))
    >>> turn = satellite_turn(tc)
    >>> turn.turn_max, round(turn.turn_range, 12), turn.sized
    (0.002, 0.003, True)

    References
    ----------
    .. [1] docs/spec/pins.md §6-7, §8.
    """
    from .contact_cycle import deflection_sized, pin_travel    # the contact level ran: loaded

    tau, g, travel_max = cycle.cycle.sol.tau, cycle.model.g, cycle.model.settings.travel_max
    return SatelliteTurn(turn_max=float(abs(tau).max()), turn_range=float(tau.max() - tau.min()),
                         travel=pin_travel(tau, g), travel_max=travel_max, sized=deflection_sized(tau, g, travel_max))
