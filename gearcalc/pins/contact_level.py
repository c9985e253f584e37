"""KHV pin gearing, level ``contact`` of one design: profile, friction, both modes, peaks, play (pins.md §5).

The orchestration of :mod:`gearcalc.pins.contact` for one design: the satellite profile
(:func:`satellite_profile`), the friction regime of its operating point (:func:`contact_friction`) and the
solve of the modes with their efficiencies, peaks, engagement metrics, backlash, losses and detail
(:func:`contact_level`).  Values in, in the units of :mod:`gearcalc.pins.contact`; no design keys: the adapter
:mod:`gearcalc.kinds.pins` maps them, and the exceptions of :mod:`gearcalc.pins.contact` (an inadmissible
profile, no equilibrium, a geometry below floating-point resolution) reach it unchanged for its messages.

References
----------
.. [1] The paper (Prudnikov, seed 000), cited in full in :mod:`gearcalc.pins`; docs/spec/pins.md §5.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .. import units
from . import contact as pc
from .checks import pin_circle_curtate
from .contact_settings import DEFAULT_SETTINGS, ContactSettings
from .detail import contact_detail
from .friction import AtCrankSpeed, PinFriction, friction_regime
from .geometry import Cycloid
from .operating import ARRAY_OPS
from .profiles import ProfileParams, make_profile

__all__ = ["contact_rule", "gear", "satellite_profile", "contact_friction", "backlash_deg", "ContactLevel",
           "ContactDesign", "contact_level"]


def contact_rule(tol: float, settings: ContactSettings | None = None) -> str:
    r"""The cycle mean's quadrature rule at the contact level for a tolerance (pins.md §6).

    ``settings.rule`` where given (an explicit rule whatever the tolerance); else the composite trapezoid per smooth
    piece at tol >= 3e-7 (``settings.gk_below``; the default 1e-6 included), the
    Gauss-Kronrod pair ``"gk7"`` (3-point Gauss, 7-point Kronrod, with the piece ends solved and each piece's
    interpolated states on the final grid, :func:`~gearcalc.pins.contact.gk_interpolated`) below.  Measured
    2026-11-27 on the eight paper designs, CPU time of both modes: at 1e-6 the trapezoid takes 0.55-1.0x gk7's time
    (each solve's fixed numpy overhead outweighs gk7's 2-3x fewer angles); at 1e-7 gk7 takes 0.77x the trapezoid's
    in all (1.34 s against 1.73 s), at 1e-8 0.49x; at 1e-8 it meets the tolerance where the trapezoid reaches its
    cap of 2^12 intervals on 3 designs, at 1e-9 on the three designs tried (0.13-0.45 s against 0.24-0.54 s).

    .. math:: \text{rule} = \text{"trapezoid"} \ (\text{tol} \ge 3 \cdot 10^{-7}), \qquad
        \text{"gk7"} \ \text{otherwise}

    Parameters
    ----------
    tol : float
        Relative accuracy target, [-].
    settings : ContactSettings, optional
        The contact level's settings (``rule``, ``gk_below``; None: :data:`DEFAULT_SETTINGS`).

    Returns
    -------
    rule : str
        "trapezoid" or "gk7".

    Examples
    --------
    >>> contact_rule(1e-6), contact_rule(1e-9), contact_rule(1e-6, ContactSettings(rule="gk15"))
    ('trapezoid', 'gk7', 'gk15')

    References
    ----------
    .. [1] A. S. Kronrod, Nodes and Weights of Quadrature Formulas, Consultants Bureau, New York, 1965;
       docs/spec/pins.md §6.
    """
    s = DEFAULT_SETTINGS if settings is None else settings
    if s.rule is not None:
        return s.rule
    return "gk7" if tol < s.gk_below else "trapezoid"


def gear(z1: int, z2: int, e: float, Rp, K1, Rb: float):
    r"""(the gear, R_p [mm]) from whichever of R_p and K1 is given (the other None; pins.md §4.1, §7).

    :class:`~gearcalc.pins.geometry.Cycloid` with 1 - K1 from :func:`gearcalc.pins.checks.pin_circle_curtate`.

    .. math:: R_p = \frac{e\,z_2}{k\,K_1} \ \text{(K1 given)}, \qquad K_1 = \frac{e\,z_2}{k\,R_p} \ \text{(R_p given)}

    Parameters
    ----------
    z1, z2 : int
        Teeth and pins, [-].
    e : float
        Eccentricity, [mm].
    Rp : float or None
        Pin circle radius, [mm].
    K1 : float or None
        Curtate ratio, [-].
    Rb : float
        Pin radius, [mm].

    Returns
    -------
    g : Cycloid
        The gear.
    Rp : float
        Pin circle radius, [mm].

    Examples
    --------
    >>> g, Rp = gear(20, 22, 3.9, None, 0.75, 1.95)
    >>> round(Rp, 9), g.R_b
    (57.2, 1.95)

    References
    ----------
    .. [1] docs/spec/pins.md §4.1, §7.
    """
    Rp, _, omk = pin_circle_curtate(z1, z2, e, Rp, K1)
    return Cycloid(z1, z2, float(e), float(Rp), float(Rb), float(omk)), Rp


def satellite_profile(g, profile: str, tooth_radius, tooth_circle_radius, radial_mod: float,
                      equidistant_mod: float):
    """The satellite profile of the contact level (pins.md §5.2-5.3) and whether circular teeth overlap.

    Parameters
    ----------
    g : Cycloid
        The gear.
    profile : str
        The profile's name in :data:`gearcalc.pins.profiles.PROFILES`: "circular" (circular-arc teeth,
        :func:`~gearcalc.pins.contact.circular_profile`), "cycloidal" (the (modified) cycloid,
        :func:`~gearcalc.pins.contact.cycloid_profile`); ValueError for an unknown name.
    tooth_radius : float or "full"
        rho_t [mm]; "full": adjacent teeth tangent at the root.
    tooth_circle_radius : float or "zero_backlash"
        R_t [mm]; "zero_backlash": the teeth just touch the pins' nominal paths.
    radial_mod, equidistant_mod : float
        Delta R_p, Delta R_b of a cycloid [mm].

    Returns
    -------
    (profile, overlap)

    Raises
    ------
    gearcalc.pins.contact.InadmissibleProfile

    Examples
    --------
    >>> g = Cycloid.from_curtate_ratio(21, 22, 3.9, 0.75, 1.95)
    >>> p, overlap = satellite_profile(g, "circular", 5.0, "zero_backlash", 0.0, 0.0)
    >>> type(p).__name__, round(p.R_t, 2), overlap   # circular_profile's example
    ('CircularProfile', 111.35, False)

    References
    ----------
    .. [1] A. P. Prudnikov, «Потери мощности в контакте цевок и зубьев планетарной передачи типа K-H-V» (Power losses in
       pins and teeth contact area of KHV-type planetary gearing), Машиностроение (seed file 000_fe288dec6e7c72f0.txt);
       its circular-arc teeth; docs/spec/pins.md §5.2, §5.3, §7.
    """
    return make_profile(profile, g, ProfileParams(tooth_radius, tooth_circle_radius, radial_mod, equidistant_mod))


def contact_friction(rotating: bool, Rb: float, r, sliding: float, rolling: float, axle: float):
    r"""(mu_eff, rolls, rolling condition) of one operating point as arrays of one (pins.md §4.5-4.6).

    :func:`~gearcalc.pins.friction.friction_regime`; the condition is None for fixed pins.

    .. math:: \mu_{eff} = (f_c r + f_k)/R_b \text{ where } f R_b \ge f_c r + f_k, \text{ else } f

    Parameters
    ----------
    rotating : bool
        Rotating pins.
    Rb, r : float
        Pin and axle radii, [mm].
    sliding : float
        Sliding friction f, [-].
    rolling : float
        Rolling friction f_k, [mm].
    axle : float
        Axle friction f_c, [-].

    Returns
    -------
    mu_eff : ndarray
        Effective coefficient, [-], shape (1,).
    rolls : ndarray of bool
        The pins roll, shape (1,).
    condition : ndarray of bool or None
        The rolling condition (None for fixed pins).

    Examples
    --------
    >>> mu, rolls, ok = contact_friction(True, 1.95, 0.95, 0.1, 0.01, 0.1)
    >>> round(float(mu[0]), 12), bool(rolls[0]), bool(ok[0])
    (0.053846153846, True, True)

    References
    ----------
    .. [1] A. P. Prudnikov, «Потери мощности в контакте цевок и зубьев планетарной передачи типа K-H-V» (Power losses in
       pins and teeth contact area of KHV-type planetary gearing), Машиностроение (seed file 000_fe288dec6e7c72f0.txt);
       docs/spec/pins.md §4.5-4.6.
    """
    f = np.array([sliding], dtype=float)
    if not rotating:
        return f, np.zeros(f.shape, dtype=bool), None
    mu, ok = friction_regime(np.ones(1, dtype=bool), np.full(1, float(Rb)), np.full(1, float(r)), f,
                             np.array([rolling], dtype=float), np.array([axle], dtype=float), ARRAY_OPS)
    return mu, ok, ok


def backlash_deg(model, play_free: bool) -> float:
    r"""The satellite's play at no load [deg] (pins.md §5.3).

    0 where the profile has none by construction (an unmodified cycloid, the zero-backlash tooth circle), else
    :func:`gearcalc.pins.contact.backlash`.

    .. math:: \Delta\varphi = \frac{180}{\pi} \min_\theta \left(\tau_+(\theta) - \tau_-(\theta)\right)

    Parameters
    ----------
    model : ContactModel
        The contact model (its profile and gear).
    play_free : bool
        The profile has no play by construction.

    Returns
    -------
    backlash : float
        The play, [deg].

    Examples
    --------
    >>> from gearcalc.pins.contact import MULTIPLIER, Cycloid, ContactModel, contact_law
    >>> g = Cycloid.from_curtate_ratio(21, 22, 3.9, 0.75, 1.95)
    >>> p, _ = satellite_profile(g, "circular", 5.0, 110.0, 0.0, 0.0)   # R_t below the zero-backlash 111.35 mm
    >>> round(backlash_deg(ContactModel(g, p, contact_law("linear", stiffness=1e5), 1e4, MULTIPLIER), False), 3)
    6.286

    References
    ----------
    .. [1] docs/spec/pins.md §5.3, §8.
    """
    return 0.0 if play_free else math.degrees(pc.backlash(model))


@dataclass
class ContactLevel:
    """The contact level of one design (:func:`contact_level`).

    modes : :class:`~gearcalc.pins.contact.ModeCycles`; residual, balanced : the largest moment-balance
    residual relative to the torque and whether it is within its limit (the rest is None when not);
    consistent : whether the friction forces entered the balance; rolling_ok : the rolling condition (array of
    one; None for fixed pins); et_multiplier, et_reducer, locked : :func:`~gearcalc.pins.contact.mode_efficiencies`;
    peaks, metrics : :func:`~gearcalc.pins.contact.cycle_peaks`, :func:`~gearcalc.pins.contact.engagement_metrics`;
    backlash [deg]; operating : :func:`~gearcalc.pins.contact.operating_values` (None without a crank speed);
    detail : the detail tables (None unless asked); torsion : (summary, tables) of
    :func:`~gearcalc.pins.stiffness.torsion_outputs` (None unless asked); crank :
    :class:`~gearcalc.pins.contact.CrankBearing` (crank torque, crank-bearing force, contact stress factor of the
    requested mode).
    """

    modes: object
    residual: float
    balanced: bool
    consistent: bool
    rolling_ok: object
    et_multiplier: object = None
    et_reducer: object = None
    locked: dict | None = None
    peaks: object = None
    metrics: dict | None = None
    backlash: float | None = None
    operating: object = None
    detail: dict | None = None
    crank: object = None
    torsion: tuple | None = None


@dataclass(frozen=True)
class ContactDesign:
    """One design at the contact level (the parameter object of :func:`contact_level`).

    The gear ``g``, its ``profile`` (:func:`satellite_profile`), contact ``law``, ``n_discs`` discs, ``rotating``
    pins on axles of radius ``axle_radius`` [mm] (None: fixed pins); ``bearing_stiffness`` k_b, the radial stiffness
    of one disc's crank bearing [N/µm], in series in the torsion outputs (None: rigid).
    """

    g: Cycloid
    profile: object
    law: object
    n_discs: int
    rotating: bool
    axle_radius: float | None
    bearing_stiffness: float | None = None


def contact_level(design: ContactDesign, point: dict, friction_model: str, tol: float, play_free: bool,
                  detail: bool = False, settings: ContactSettings | None = None, torsion: bool = False) -> ContactLevel:
    r"""The compliant contact level (pins.md §5) of one design at one operating point.

    The satellite rotation is solved at every crank angle (:func:`~gearcalc.pins.contact.solve_modes`); the cycle
    mean of the loss ratio uses the shared quadrature with contact entry/exit and spin reversals as breakpoints.
    With the torque given on H the torque on V is iterated to the fixed point T_V = u T_H/eta (multiplier) or
    eta u T_H (reducer) (pins.md §7).  The friction model "consistent" (pins.md §4.9, §5.5) puts the friction forces
    into the moment balance and solves each mode with its own forces (a mode that jams self-locks), unless there is
    no friction at all; "first-order" solves the requested mode with frictionless forces (§4.7).

    .. math:: \eta_{HV} = \frac{1}{1 + \bar\lambda}, \qquad \eta_{VH} = 1 - \bar\lambda

    Parameters
    ----------
    design : ContactDesign
        The gear, satellite profile, contact law, discs, pins (rotating, on axles of radius r [mm]), crank bearing.
    point : dict
        The operating point (:data:`gearcalc.pins.columns.OPERATING`): sliding f, rolling f_k [mm], axle f_c,
        mode ("multiplier" or "reducer"), shaft ("H" or "V") of torque T [N·m], speed n_H [rpm] (None: none).
    friction_model, tol : str, float
        "consistent" or "first-order"; the relative accuracy target.
    play_free, detail : bool
        The profile has no play by construction (:func:`backlash_deg`); build the detail tables (pins.md §8).
    settings : ContactSettings or None
        The numerical settings, the cycle mean's rule among them (:func:`contact_rule`; None: the defaults).
    torsion : bool
        Also the torsional stiffness, lost motion, hysteresis and transmission error with the crank held
        (:func:`~gearcalc.pins.stiffness.torsion_outputs`; pins.md §5.8), T_r the torque on V (u T on H), the crank
        bearing's stiffness ``design.bearing_stiffness`` in series.

    Examples
    --------
    The paper's cycloidal u = 10 design with fixed pins, multiplier, T_H = 100 N·m (pins.md §10), Hertz contacts
    (0.87363 at the rigid ideal level):

    >>> g = Cycloid.from_curtate_ratio(20, 22, 3.9, 0.75, 1.95)
    >>> prof, _ = satellite_profile(g, "cycloidal", "full", "zero_backlash", 0.0, 0.0)
    >>> design = ContactDesign(g, prof, pc.contact_law("hertz", face_width=10.0), 1, False, None)
    >>> point = dict(sliding=0.1, rolling=None, axle=None, mode="multiplier", shaft="H", torque=100.0, speed=None)
    >>> et = contact_level(design, point, "consistent", 1e-5, True).et_multiplier
    >>> round(float(et.efficiency[0]), 3), round(float(et.T_V[0] * et.eta_vh[0]), 6)   # eta T_V = u T_H = 1000 N·m
    (0.874, 1000.0)

    Returns
    -------
    ContactLevel
        The modes, their efficiencies and the requested mode's outputs.

    Raises
    ------
    gearcalc.pins.contact.NoEquilibrium, gearcalc.pins.contact.Jam, gearcalc.pins.contact.Unresolvable

    References
    ----------
    .. [1] A. P. Prudnikov, «Потери мощности в контакте цевок и зубьев планетарной передачи типа K-H-V», Машиностроение
       (seed file 000_fe288dec6e7c72f0.txt); docs/spec/pins.md §4.7, §4.9, §5, §7, §10.
    """
    g, n_discs = design.g, design.n_discs
    mu_a, rolls_a, rolling_ok = contact_friction(design.rotating, g.R_b, design.axle_radius, point["sliding"],
                                                 point["rolling"], point["axle"])
    mu, rolls, f = float(mu_a[0]), bool(rolls_a[0]), float(point["sliding"])
    law = _speed_law(point)
    consistent = friction_model == "consistent" and not (mu == 0.0 and f == 0.0 and law is None)
    torque, multiplier, on_V = point["torque"], point["mode"] == "multiplier", point["shaft"] == "V"
    case = pc.ContactCase(g, design.profile, design.law, n_discs, PinFriction(mu, f, rolls, law), torque, on_V)
    modes = pc.solve_modes(case, multiplier, consistent, tol=tol, rule=contact_rule(tol, settings), settings=settings)
    residual, excess = pc.equilibrium_residual(modes.runs.values(), tol)
    if not excess <= 1.0:
        return ContactLevel(modes, residual, False, consistent, rolling_ok)
    et_m, et_r, locked = pc.mode_efficiencies(modes, consistent, np.array([torque], dtype=float), g.ratio,
                                              np.array([multiplier]), np.array([on_V]))
    outs = _requested_outputs(design, point, modes, consistent, (mu, f, rolls, law), play_free, detail)
    # the twist with the crank held is quasi-static: a speed law's coefficient at zero speed (pins.md §4.10, §5.8)
    fr = (PinFriction(mu, f, rolls) if law is None else PinFriction(mu, float(law.coefficient(0.0)), rolls)) \
        if consistent else None
    tor = _torsion(design, fr, settings, torque if on_V else torque * g.ratio, outs[2]) if torsion else None
    return ContactLevel(modes, residual, True, consistent, rolling_ok, et_m, et_r, locked, *outs, tor)


def _speed_law(point: dict):
    """The sliding contacts' speed-dependent law of an operating point, at the contact level's speeds.

    ``point["law"]`` (m/s) read at the crank speed ``point["speed"]`` [rpm] (pins.md §4.10, §5.6); None: Coulomb.
    """
    law = point.get("law")
    if law is None or law.constant:
        return None
    return AtCrankSpeed(law, units.rpm_to_rad_s(point["speed"]))


def _torsion(design: ContactDesign, friction, settings, torque_V: float, play: float) -> tuple:
    """(summary, tables) of the torsion outputs with the crank held (:func:`contact_level`, pins.md §5.8).

    :func:`~gearcalc.pins.stiffness.torsion_outputs` of a reducer at unit torque with the friction forces of
    ``friction`` in the balance (None: none) at ``torque_V`` [N·m] on V, the crank bearing's stiffness in series.
    """
    from .stiffness import torsion_outputs

    held = pc.ContactModel(design.g, design.profile, design.law, 1.0, pc.REDUCER, friction, settings)
    k_b = design.bearing_stiffness
    return torsion_outputs(held, torque_V, design.n_discs, play, bearing_stiffness=None if k_b is None else 1e3 * k_b)


def _requested_outputs(design: ContactDesign, point: dict, modes, consistent: bool, friction: tuple, play_free: bool,
                       detail: bool) -> tuple:
    """(peaks, metrics, backlash, operating, detail, crank) of the requested mode's cycle (:func:`contact_level`).

    The crank torque, bearing force and contact stress come from the requested mode's own forces (friction in the
    balance unless first-order or jammed: then the friction-free forces, and no crank-torque history, pins.md §8).
    ``friction``: (mu_eff, f, rolls, law).
    """
    g, n_discs, (mu, f, rolls, law) = design.g, design.n_discs, friction
    multiplier = point["mode"] == "multiplier"
    tc = modes.requested
    w_H = units.rpm_to_rad_s(point["speed"]) if point["speed"] is not None else None
    cyc = tc.cycle
    pk = pc.cycle_peaks(cyc, g, n_discs, rolls)
    metrics = pc.engagement_metrics(cyc.sol, cyc.spin if rolls else np.zeros(cyc.sol.force.shape[1:]))
    play = backlash_deg(tc.model, play_free)
    f_peak = f if law is None else float(np.max(law.coefficient(cyc.slide[cyc.sol.force > 0.0]), initial=0.0))
    ov = pc.operating_values(pk, g, tc.loss_ratio, tc.torque_V, w_H, mu, f_peak, rolls) if w_H is not None else None
    own = consistent and multiplier not in modes.jams
    # the friction forces each state was solved with (at a piece end they can differ from its own sliding's)
    crank = pc.crank_bearing(tc.model, cyc.sol, cyc.sol.traction if own else None, n_discs,
                             None if cyc.nodes is None else cyc.nodes[1])
    tables = contact_detail(g, cyc.sol, cyc, tc.torque_V, w_H, n_discs, crank, own) if detail else None
    return pk, metrics, play, ov, tables, crank
