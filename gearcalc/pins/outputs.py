"""KHV pin gearing, ideal level: the outputs of one operating point from the friction-consistent cycles.

Pure physics over floats and numpy arrays (no I/O, no design keys): the friction-consistent efficiencies
and shaft torques (pins.md §4.9), the per-pin peaks, and the outputs of pins.md §8 (crank torque,
crank-bearing force, Hertz contact stress, axle pressure), from the unit-torque cycle means and peaks of
:func:`gearcalc.pins.consistent_cycles`.  Units inside: N, mm, N·mm, rad/s; torques given and returned in
N·m; powers in W.  The functions that take ``xp`` run the same formulas on arrays over operating points
(:data:`gearcalc.pins.ARRAY_OPS`) or on the Python floats of one point (:data:`gearcalc.pins.SCALAR_OPS`):
the same numbers, bit for bit.

References
----------
.. [1] Prudnikov (seed 000), cited in full in :mod:`gearcalc.pins`, eqs. (3)-(7) and Figs 3-7 (the crank
   torque over the cycle).
.. [2] Blagojević et al. (friction forces in the satellite's balance) and [3] Johnson 1985, eq. (4.45) (Hertz
   line contact), cited in full in :mod:`gearcalc.pins`.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import hertz, units
from .consistent import consistent_cycles
from .cycle import crank_order, disc_offsets, sum_over_discs
from .efficiency import efficiency_multiplier, efficiency_reducer
from .friction import PinFriction, peak_coefficient
from .geometry import MULTIPLIER, REDUCER
from .operating import ARRAY_OPS, SCALAR_OPS, Gears, OperatingPoint, SatelliteLoad, efficiency_reducer_err
from .operating import shaft_torques

__all__ = ["STEEL_E_MPA", "STEEL_NU", "STEEL_E_STAR_MPA", "ConsistentEfficiencies", "consistent_efficiencies",
           "satellite_torque", "crank_torque", "contact_stress", "axle_pressure", "pin_loss_bound", "ConsistentPoint",
           "consistent_point", "consistent_outputs", "bearing_life", "CrankDetail", "crank_detail"]

STEEL_E_MPA, STEEL_NU = 2.1e5, 0.3
"""Steel pins and satellite: Young's modulus [MPa] and Poisson's ratio (the Hertz contact stress of pins.md §8;
the contact level's ``hertz`` law is steel too)."""
STEEL_E_STAR_MPA = hertz.contact_modulus(STEEL_E_MPA, STEEL_NU, STEEL_E_MPA, STEEL_NU)
"""E* of steel on steel, E/(2 (1 - nu^2)) = 115384.6 MPa (:func:`gearcalc.hertz.contact_modulus`)."""


# ------------------------------------------------------------------ efficiencies (pins.md §4.9)

@dataclass(frozen=True)
class ConsistentEfficiencies:
    """Both modes' friction-consistent efficiencies (:func:`consistent_efficiencies`); NaN: the mode self-locks.

    eta_vh, eta_vh_err : multiplier efficiency and its error [-]; eta_hv, eta_hv_err : the reducer's;
    locked_vh, locked_hv : the mode self-locks (jams, or eta_VH <= 0).
    """

    eta_vh: object
    eta_vh_err: object
    eta_hv: object
    eta_hv_err: object
    locked_vh: object
    locked_hv: object


def consistent_efficiencies(loss_ratio_reducer, loss_ratio_multiplier, err_reducer, err_multiplier, jam_reducer,
                            jam_multiplier, xp=ARRAY_OPS) -> ConsistentEfficiencies:
    r"""The efficiencies of both modes from their own friction-consistent loss ratios (pins.md §4.9).

    .. math::

        \eta_{HV} = \frac{1}{1 + \bar\lambda_{reducer}},\quad \eta_{VH} = 1 - \bar\lambda_{multiplier},\quad
        E_{HV} = \frac{E_{reducer}}{(1 + \bar\lambda_{reducer})^2},\quad E_{VH} = E_{multiplier}

    A mode self-locks where it jams (no positive normal-force solution at some crank angle) and, the
    multiplier, where eta_VH <= 0; its efficiency and error are then NaN.

    Parameters
    ----------
    loss_ratio_reducer, loss_ratio_multiplier : float or array_like
        lambda_bar of each mode [-] (NaN where it jams).
    err_reducer, err_multiplier : float or array_like
        their error estimates E [-].
    jam_reducer, jam_multiplier : bool or array_like of bool
        the mode jams.
    xp : :data:`gearcalc.pins.ARRAY_OPS` or :data:`gearcalc.pins.SCALAR_OPS`

    Returns
    -------
    ConsistentEfficiencies

    Examples
    --------
    >>> ce = consistent_efficiencies(0.25, 0.2, 1e-6, 1e-6, False, False, SCALAR_OPS)
    >>> ce.eta_hv, ce.eta_vh, ce.eta_hv_err
    (0.8, 0.8, 6.4e-07)
    >>> consistent_efficiencies(np.array([0.1]), np.array([1.2]), 0.0, 0.0, False, False).locked_vh.tolist()
    [True]

    References
    ----------
    pins.md §4.9 (efficiency from the cycle-mean powers, jam), §4.7; Blagojević et al. 2011 (model 2).
    """
    eta_vh0 = efficiency_multiplier(loss_ratio_multiplier)
    locked_vh = jam_multiplier | xp.logical_not(eta_vh0 > 0.0)
    locked_hv = jam_reducer
    return ConsistentEfficiencies(
        eta_vh=xp.where(locked_vh, xp.nan, eta_vh0), eta_vh_err=xp.where(locked_vh, xp.nan, err_multiplier),
        eta_hv=xp.where(locked_hv, xp.nan, efficiency_reducer(loss_ratio_reducer)),
        eta_hv_err=xp.where(locked_hv, xp.nan, efficiency_reducer_err(loss_ratio_reducer, err_reducer)),
        locked_vh=locked_vh, locked_hv=locked_hv)


# ------------------------------------------------------------------ the outputs of pins.md §8

def satellite_torque(torque_V, n_discs):
    r"""Torque on one satellite disc, T_sat = T_V/n_d [N·mm] from T_V [N·m] (pins.md §4.4, §12.7).

    .. math:: T_{sat} = \frac{10^3\,T_V}{n_d}

    Parameters
    ----------
    torque_V : float or array_like
        Output torque T_V, [N·m].
    n_discs : int or array_like
        Discs n_d, [-].

    Returns
    -------
    T_sat : float or ndarray
        Torque on one disc, [N·mm].

    Examples
    --------
    >>> satellite_torque(800.0, 2)
    400000.0

    References
    ----------
    pins.md §4.4 (forces from T_sat), §12.7 (several discs share T_V equally).
    """
    return units.nm_to_nmm(torque_V) / n_discs


def crank_torque(torque_sat, unit_crank_torque):
    r"""Crank torque T_H [N·m] from T_sat [N·mm] and the unit-torque crank torque T_H/T_sat [-] (pins.md §4.9).

    .. math::  T_H = \sigma e B_y = T_{sat} \hat T_H

    Parameters
    ----------
    torque_sat : float or array_like
        Torque on one satellite disc T_sat, [N·mm].
    unit_crank_torque : float or array_like
        T_H/T_sat, [-].

    Returns
    -------
    T_H : float or ndarray
        Crank torque, [N·m].

    Examples
    --------
    >>> crank_torque(400000.0, 0.05)     # 400 N·m on the satellite, T_H/T_sat = 1/20
    20.0

    References
    ----------
    pins.md §4.9 (T_H = O1 x B), §8 (crank_torque_mean_Nm, crank_torque_ripple_Nm); Prudnikov, Figs 3-7.
    """
    return torque_sat * unit_crank_torque / units.NMM_PER_NM


def contact_stress(torque_sat, unit_stress, face_width, e_star):
    r"""Peak Hertz pressure of the pin-tooth line contact, p0 [MPa] (pins.md §8; Johnson 1985, eq. 4.45).

    .. math::

        p_0 = \sqrt{\frac{F E^*}{\pi b R_{eff}}},\quad \frac{F}{R_{eff}} = T_{sat}\,\widehat{(F/R_{eff})},\quad
        R_{eff} = R_b (1 - R_b/\rho_c)

    Parameters
    ----------
    torque_sat : float or array_like
        T_sat [N·mm].
    unit_stress : float or array_like
        the largest F/(T_sat R_eff) over contacts and crank angles [1/mm^2]
        (:attr:`gearcalc.pins.ConsistentCycles.stress`).
    face_width : float or array_like
        b [mm] (NaN: not given; the result is then NaN).
    e_star : float
        contact modulus E* [MPa] (:func:`gearcalc.hertz.contact_modulus`).

    Returns
    -------
    p0 [MPa] (a numpy float or array).

    Examples
    --------
    >>> round(float(contact_stress(5000.0, 0.04, 10.0, 115384.6153846154)), 3)   # F/R = 200 N/mm: hertz
    857.066

    References
    ----------
    pins.md §8 (contact_stress_max_MPa); Johnson 1985, eq. (4.45); :func:`gearcalc.hertz.peak_pressure`.
    """
    return hertz.peak_pressure(torque_sat * unit_stress, face_width, 1.0, e_star) * 1.0


def axle_pressure(force, axle_radius, face_width):
    r"""Mean bushing-axle pressure of a rotating pin on the projected area, p = F/(2 r b) [MPa] (pins.md §8).

    .. math:: p = \frac{F}{2\,r\,b}

    Parameters
    ----------
    force : float or array_like
        the pin force F [N].
    axle_radius : float or array_like
        r [mm].
    face_width : float or array_like
        b [mm].

    Returns
    -------
    p : float or ndarray
        Mean pressure, [MPa].

    Examples
    --------
    >>> axle_pressure(1900.0, 0.95, 10.0)    # 1900 N on a 1.9 mm x 10 mm projected area
    100.0

    References
    ----------
    pins.md §8 (axle_pressure_max_MPa).
    """
    return force / (2.0 * axle_radius * face_width)


def pin_loss_bound(mu_eff, rolls, sliding_friction, force_max, speed_max, xp=ARRAY_OPS):
    r"""Upper bound of one pin's loss, eq. (7) with the peak force and the peak contact speed [W] (pins.md §8).

    .. math::  P \le \mu F_{max} v_{max} 10^{-3},\quad \mu = \mu_{eff} \text{ (rolling pins) else } f

    Parameters
    ----------
    mu_eff : float or array_like [-]; rolls : bool or array_like (the pins roll); sliding_friction : f [-].
    force_max : F_max [N]; speed_max : the peak contact speed (|omega_V| |rho - R_b|) [mm/s].
    xp : :data:`gearcalc.pins.ARRAY_OPS` or :data:`gearcalc.pins.SCALAR_OPS`

    Returns
    -------
    P : float or ndarray
        The bound, [W].

    Examples
    --------
    >>> pin_loss_bound(0.05, True, 0.1, 1000.0, 200.0, SCALAR_OPS)   # 0.05 x 1000 N x 0.2 m/s
    10.0

    References
    ----------
    Prudnikov, eq. (7); pins.md §8 (pin_loss_bound_W).
    """
    return peak_coefficient(mu_eff, rolls, sliding_friction, xp) * force_max * speed_max * 1e-3


@dataclass(frozen=True)
class ConsistentPoint:
    """The friction-consistent outputs of operating points (:func:`consistent_point`); NaN: undefined.

    Efficiencies (pins.md §4.9): eta_vh, eta_vh_err, eta_hv, eta_hv_err, efficiency, efficiency_err (the point's
    mode), self_locking, loss_ratio, loss_ratio_err (the point's mode) [-]; T_V, T_H, torque_in, torque_out
    [N·m]; loss_mean [W]; converged (bool), n_crank (int).  Peaks of the point's own mode: force_max [N],
    force_phase [deg], loss_max, loss_peak, loss_bound [W], loss_phase [deg].  pins.md §8: crank_torque_mean,
    crank_torque_ripple [N·m] (all discs; NaN for first-order points), bearing_force_max, bearing_force_mean [N]
    (one disc), contact_stress_max [MPa], axle_pressure_max [MPa] (NaN for fixed pins).  torque_scale: T_sat
    of the friction-consistent over the first-order efficiency [-].  torque_sat: T_sat [N·mm];
    bearing_pmean, bearing_pmean_err: the cycle mean of (|B|/T_sat)^p and its error
    (:class:`gearcalc.pins.ConsistentCycles`; :func:`bearing_life`).
    """

    eta_vh: object
    eta_vh_err: object
    eta_hv: object
    eta_hv_err: object
    efficiency: object
    efficiency_err: object
    self_locking: object
    loss_ratio: object
    loss_ratio_err: object
    T_V: object
    T_H: object
    torque_in: object
    torque_out: object
    loss_mean: object
    converged: object
    n_crank: object
    force_max: object
    force_phase: object
    loss_max: object
    loss_peak: object
    loss_phase: object
    loss_bound: object
    crank_torque_mean: object
    crank_torque_ripple: object
    bearing_force_max: object
    bearing_force_mean: object
    contact_stress_max: object
    axle_pressure_max: object
    torque_scale: object
    torque_sat: object = None
    bearing_pmean: object = None
    bearing_pmean_err: object = None


def consistent_point(c, consistent, gears: Gears, friction: PinFriction, op: OperatingPoint, load: SatelliteLoad,
                     rel_abs, xp=ARRAY_OPS) -> ConsistentPoint:
    r"""Efficiencies, torques, losses, peaks and the outputs of pins.md §8 of operating points (pins.md §4.9).

    Consistent points take everything from their friction-consistent unit cycles; first-order points get the outputs
    of §8 (bearing force, contact stress, axle pressure) from their friction-free forces at their own T_sat.

    .. math::

        T_{sat} = T_V/n_d,\quad F_{max} = T_{sat}\hat F,\quad P = \mu_{eff} T_{sat} |\omega_V| \hat P,\quad
        \bar P = \bar\lambda T_V |\omega_V|,\quad |B| = T_{sat} \hat B,\quad T_H = T_{sat} \hat T_H,\quad
        p_{axle} = \frac{F_{max}}{2 r b}

    Parameters
    ----------
    c : mapping
        the :class:`gearcalc.pins.ConsistentCycles` fields at the points (rows 0 reducer, 1 multiplier of loss_ratio,
        err, jammed, converged, n_crank; the peaks of the own mode): arrays, or one point's values (``.tolist()``).
    consistent : bool or array_like of bool
        the point uses the friction-consistent model (else first-order).
    gears, friction, op : :class:`gearcalc.pins.Gears`, :class:`gearcalc.pins.PinFriction`, :class:`OperatingPoint`
        z1, z2 (u = z1/k), n_d, rotating, r [mm], b [mm] (NaN: no stress, no axle pressure); mu_eff, f [-], rolls;
        T [N·m] (on V where ``torque_on_V``, else on H) and the mode.
    load : :class:`gearcalc.pins.SatelliteLoad`
        the first-order T_sat [N·mm] (:func:`gearcalc.pins.scale_unit_cycle`), |omega_V| [rad/s] (NaN: no powers).
    rel_abs : float or array_like
        the peak |rho - R_b| over the cycle [mm] (the contact speed per |omega_V|).
    xp : :data:`gearcalc.pins.ARRAY_OPS` or :data:`gearcalc.pins.SCALAR_OPS`

    Returns
    -------
    ConsistentPoint

    Examples
    --------
    >>> from gearcalc import pins
    >>> g = pins.geometry.as_arrays(pins.Cycloid.from_curtate_ratio(20, 22, 3.9, 0.75, 1.95))
    >>> cyc = pins.ideal_cycles(g, 1)
    >>> cc = pins.consistent_cycles(cyc, np.array([0]), np.array([0.1]), mode=pins.REDUCER)
    >>> c = {f: getattr(cc, f)[..., 0].tolist() for f in cc.__dataclass_fields__}
    >>> p = consistent_point(c, True, pins.Gears(20, 22, 3.9, 1.95, 0.75, np.nan, 1, False, 0.95, 10.0),
    ...                      pins.PinFriction(0.1, 0.1, False), pins.OperatingPoint(100.0, 1000.0, False, False),
    ...                      pins.SatelliteLoad(1.0, 10.0), 1.0, SCALAR_OPS)
    >>> round(p.crank_torque_mean, 4)          # the cycle mean of the crank torque is the torque on H (1e-8)
    100.0

    References
    ----------
    pins.md §4.9, §8; Prudnikov, eq. (7) and Figs 3-7; Blagojević et al. 2011 (model 2).
    """
    nan, multiplier, mu_eff, omega_V = xp.nan, op.multiplier, friction.mu_eff, load.omega_V
    lam_R, lam_M, err_R, err_M = c["loss_ratio"][0], c["loss_ratio"][1], c["err"][0], c["err"][1]
    jam_R, jam_M = c["jammed"][0], c["jammed"][1]
    ce = consistent_efficiencies(lam_R, lam_M, err_R, err_M, jam_R, jam_M, xp)
    T_V, T_H = shaft_torques(op.T, gears.z1 / gears.k, ce.eta_vh, ce.eta_hv, multiplier, op.torque_on_V, xp)
    Ts = xp.where(consistent, satellite_torque(T_V, gears.n_d), load.torque_sat)   # first-order: its own
    P = mu_eff * Ts * omega_V
    F = Ts * c["force"]
    lam = xp.where(multiplier, lam_M, lam_R)
    return ConsistentPoint(
        eta_vh=ce.eta_vh, eta_vh_err=ce.eta_vh_err, eta_hv=ce.eta_hv, eta_hv_err=ce.eta_hv_err,
        efficiency=xp.where(multiplier, ce.eta_vh, ce.eta_hv),
        efficiency_err=xp.where(multiplier, ce.eta_vh_err, ce.eta_hv_err),
        self_locking=xp.where(multiplier, ce.locked_vh, ce.locked_hv),
        loss_ratio=lam, loss_ratio_err=xp.where(multiplier, err_M, err_R),
        T_V=T_V, T_H=T_H, torque_in=xp.where(multiplier, T_V, T_H), torque_out=xp.where(multiplier, T_H, T_V),
        loss_mean=lam * T_V * omega_V,
        converged=xp.where(multiplier, c["converged"][1] | jam_M, c["converged"][0] | jam_R),
        n_crank=xp.maximum(c["n_crank"][0], c["n_crank"][1]),
        force_max=F, force_phase=xp.degrees(c["force_phase"]),
        loss_max=P * c["loss"], loss_peak=P * c["total"],
        loss_phase=xp.where(xp.isnan(P), nan, xp.degrees(c["loss_phase"])),
        loss_bound=pin_loss_bound(mu_eff, friction.rolls, friction.sliding, F, omega_V * rel_abs, xp),
        crank_torque_mean=xp.where(consistent, crank_torque(Ts, c["crank_mean"]), nan),
        crank_torque_ripple=xp.where(consistent, crank_torque(Ts, c["crank_max"] - c["crank_min"]), nan),
        bearing_force_max=Ts * c["bearing_max"], bearing_force_mean=Ts * c["bearing_mean"],
        contact_stress_max=contact_stress(Ts, c["stress"], gears.b, STEEL_E_STAR_MPA),
        axle_pressure_max=xp.where(gears.rotating, axle_pressure(F, gears.r, gears.b), nan),
        torque_scale=Ts / load.torque_sat, torque_sat=Ts, bearing_pmean=c["bearing_pmean"],
        bearing_pmean_err=c["bearing_pmean_err"])


def consistent_outputs(cyc, gi, consistent, gears: Gears, friction: PinFriction, op: OperatingPoint,
                       load: SatelliteLoad, tol: float = 1e-6):
    """:func:`consistent_point` of n operating points of solved gears (pins.md §4.9, §8), the admissible ones.

    Runs :func:`gearcalc.pins.consistent_cycles` for the points whose gear is admissible (its ``cyc.status`` 0)
    with their mu_eff (0 for first-order points: friction-free forces) and mode, then :func:`consistent_point`.
    One point (n = 1: scalars in, Python floats out, :data:`gearcalc.pins.SCALAR_OPS`) runs the same formulas
    as many (arrays over the points, NaN where a gear is inadmissible): the same numbers, bit for bit.

    Parameters
    ----------
    cyc : :class:`gearcalc.pins.IdealCycles`
    gi : ndarray of int, shape (n,)
        each point's gear in ``cyc``.
    consistent : ndarray of bool, shape (n,)
        the points of the friction-consistent model.
    gears, friction, op, load : :class:`gearcalc.pins.Gears`, :class:`gearcalc.pins.PinFriction`,
        :class:`gearcalc.pins.OperatingPoint`, :class:`gearcalc.pins.SatelliteLoad` (the first-order T_sat
        [N·mm] and |omega_V| [rad/s]): scalars or arrays (n,), as :func:`consistent_point` takes them; the gears'
        p is the crank bearing's life exponent [-].
    tol : relative accuracy target of the cycle means.

    Returns
    -------
    fields : ConsistentPoint or None
        None when no point is admissible; else arrays over the n points (NaN where inadmissible), or the one
        point's Python values.
    consistent : ndarray of bool, shape (n,)
        the admissible consistent points.

    Examples
    --------
    >>> from gearcalc import pins
    >>> g = pins.geometry.as_arrays(pins.Cycloid.from_curtate_ratio(20, 22, 3.9, 0.75, 1.95))
    >>> cyc = pins.ideal_cycles(g, np.array([1]))
    >>> gears, op = pins.Gears(20, 22, 3.9, 1.95, 0.75, np.nan), pins.OperatingPoint(100.0, np.nan, False, False)
    >>> p, cons = consistent_outputs(cyc, np.array([0]), np.array([True]), gears, pins.PinFriction(0.1, 0.1, False),
    ...                              op, pins.SatelliteLoad(1.0, 10.0))
    >>> round(p.efficiency, 5), round(p.crank_torque_mean, 4), p.contact_stress_max
    (0.86061, 100.0, nan)

    References
    ----------
    pins.md §4.9, §6 (the error estimate), §8.
    """
    n = len(consistent)
    if n == 1:
        return _consistent_output(cyc, gi, consistent, gears, friction, op, load, tol)
    nd_a = np.zeros(n, dtype=np.int64) + np.asarray(gears.n_d)
    good = np.asarray(cyc.status)[gi] == 0
    cons = np.asarray(consistent) & good
    if not good.any():
        return None, cons
    sel = np.flatnonzero(good)
    mult = np.broadcast_to(np.asarray(op.multiplier), (n,))[sel]
    mu_a = np.zeros(n) + np.asarray(friction.mu_eff, dtype=float)
    mu_c = np.where(cons[sel], mu_a[sel], 0.0)           # first-order points: friction-free forces
    cc = consistent_cycles(cyc, gi[sel], mu_c, nd_a[sel], tol, mode=np.where(mult, MULTIPLIER, REDUCER),
                           bearing_exponent=(np.zeros(n) + gears.p)[sel])
    c = {f: getattr(cc, f) for f in cc.__dataclass_fields__}

    def at(x, dtype=float):
        return (np.zeros(n, dtype=dtype) + np.asarray(x, dtype=dtype))[sel]

    def pick(x):            # the values themselves (at() turns -0.0 into 0.0)
        return np.broadcast_to(np.asarray(x), (n,))[sel]

    g = Gears(at(gears.z1, np.int64), at(gears.z2, np.int64), at(gears.e), at(gears.Rb), at(gears.K1), at(gears.Rp),
              nd_a[sel], at(gears.rotating, bool), at(gears.r), pick(gears.b), at(gears.p))
    pf = PinFriction(mu_a[sel], pick(friction.sliding), at(friction.rolls, bool))
    p = consistent_point(c, cons[sel], g, pf, OperatingPoint(at(op.T), at(op.n_H), mult, pick(op.torque_on_V)),
                         SatelliteLoad(at(load.torque_sat), at(load.omega_V)), np.asarray(cyc.rel_abs)[gi[sel]],
                         ARRAY_OPS)
    return _spread(p, n, sel), cons


def _spread(p: ConsistentPoint, n: int, sel) -> ConsistentPoint:
    """The fields of the points ``sel`` over all n points: NaN (floats) or 0 elsewhere."""
    full = {}
    for key, v in p.__dict__.items():
        v = np.asarray(v)
        arr = np.full(n, np.nan) if v.dtype.kind == "f" else np.zeros(n, dtype=v.dtype)
        arr[sel] = v
        full[key] = arr
    return ConsistentPoint(**full)


def _first(x, kind=float):
    """The first (or only) value of a scalar or an array, as a Python ``kind``."""
    return kind(np.asarray(x).reshape(-1)[0])


def _consistent_output(cyc, gi, consistent, gears: Gears, friction: PinFriction, op: OperatingPoint,
                       load: SatelliteLoad, tol: float):
    """:func:`consistent_outputs` of one point (n = 1): the same values, with Python scalars in between.

    The point's z1, z2, rotating, r, rolls, T and load are scalars; the other fields may be arrays of one value.
    """
    g0 = _first(gi, int)
    good = int(cyc.status[g0]) == 0
    cons = np.asarray(consistent) & good
    if not good:
        return None, cons
    cons0, mult = bool(cons[0]), _first(op.multiplier, bool)
    mu = float(np.asarray(friction.mu_eff, dtype=float).reshape(-1)[0])
    n_d = _first(gears.n_d, int)
    cc = consistent_cycles(cyc, gi, mu if cons0 else 0.0, n_d, tol, mode=MULTIPLIER if mult else REDUCER,
                           bearing_exponent=_first(gears.p))
    c = getattr(cc, "scalars", None)
    if c is None:
        c = {f: (getattr(cc, f)[..., 0].tolist()) for f in cc.__dataclass_fields__}
    g = Gears(int(gears.z1), int(gears.z2), gears.e, gears.Rb, gears.K1, gears.Rp, n_d, bool(gears.rotating),
              float(gears.r), _first(gears.b))
    p = consistent_point(c, cons0, g, PinFriction(mu, _first(friction.sliding), bool(friction.rolls)),
                         OperatingPoint(float(op.T), op.n_H, mult, _first(op.torque_on_V, bool)),
                         SatelliteLoad(float(load.torque_sat), float(load.omega_V)),
                         float(np.asarray(cyc.rel_abs)[g0]), SCALAR_OPS)
    return ConsistentPoint(**{key: (v.item() if hasattr(v, "item") else v) for key, v in p.__dict__.items()}), cons


def bearing_life(pmean, pmean_err, exponent, torque_sat, rating, crank_speed, xp=ARRAY_OPS):
    r"""The crank bearing's equivalent load and its basic rating life L10 (ISO 281), with their errors.

    The bearing-force history |B(theta)| of one disc's crank bearing over the cycle (pins.md §4.9, §8) gives the
    equivalent constant load P as its p-mean; the life in millions of revolutions and in hours at the crank
    speed n_H follow from the dynamic load rating C (ISO 281 basic rating life, 90 % reliability).  The error of
    the cycle mean (its quadrature error) is carried to P and L10_h to first order.

    .. math::

        P = T_{sat}\,\Big(\frac{1}{T}\int_0^T \hat B^p\,d\theta\Big)^{1/p}, \qquad
        L_{10} = \Big(\frac{C}{P}\Big)^p\ [10^6\ \mathrm{rev}], \qquad
        L_{10h} = \frac{10^6}{60\,n_H}\,L_{10}, \qquad
        \delta P = \frac{P}{p}\,\frac{\delta m}{m}, \qquad \delta L_{10h} = p\,L_{10h}\,\frac{\delta P}{P}

    Parameters
    ----------
    pmean : float or array_like
        m, the cycle mean of (|B|/T_sat)^p [mm^-p] (:class:`gearcalc.pins.ConsistentCycles` ``bearing_pmean``).
    pmean_err : float or array_like
        delta m, its quadrature error [mm^-p].
    exponent : float or array_like
        p, the life exponent [-]: 3 for ball bearings, 10/3 for roller bearings (ISO 281).
    torque_sat : float or array_like
        T_sat, the satellite torque of one disc [N·mm].
    rating : float or array_like
        C, the bearing's basic dynamic load rating [N] (NaN: not given; the lives are then NaN).
    crank_speed : float or array_like
        n_H, the crank speed [rpm] (NaN: not given; L10_h is then NaN).
    xp : :data:`gearcalc.pins.ARRAY_OPS` or :data:`gearcalc.pins.SCALAR_OPS`

    Returns
    -------
    P, P_err : equivalent load and its error [N]; L10_h, L10_h_err : life and its error [h].

    Examples
    --------
    A constant bearing force of 5 kN (m = 5^3 per unit T_sat, T_sat = 1000 N·mm, |B| = 5000 N), a ball bearing
    of C = 10 kN at 1000 rpm: L10 = 2^3 = 8 million revolutions, 8e6/60000 h.

    >>> P, dP, L, dL = bearing_life(125.0, 0.0, 3.0, 1000.0, 10000.0, 1000.0, SCALAR_OPS)
    >>> round(P, 9), round(L, 9), dL
    (5000.0, 133.333333333, 0.0)

    References
    ----------
    .. [1] ISO 281:2007, Rolling bearings -- Dynamic load ratings and rating life, eq. (1) and the
       mean load of a varying load (Annex, P_m = (integral of F^p dN / N)^(1/p)).
    .. [2] docs/spec/pins.md §8.2.
    """
    m, dm, p, Ts, C, n = (np.asarray(x, dtype=float) for x in (pmean, pmean_err, exponent, torque_sat, rating,
                                                                 crank_speed))
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        P = Ts * m ** (1.0 / p)
        P_err = P / p * dm / m
        L10_h = 1e6 / (60.0 * n) * (C / P) ** p
        L_err = p * L10_h * P_err / P
    out = (P, P_err, L10_h, L_err)
    return tuple(float(x) for x in out) if xp is SCALAR_OPS else out


# ------------------------------------------------------------------ the crank table of pins.md §8

@dataclass(frozen=True)
class CrankDetail:
    """The crank torque and crank-bearing force over a cycle grid, ordered by crank angle (:func:`crank_detail`).

    crank_torque [N·m] (all discs, along the power flow); bearing_force, bearing_radial (along the crank arm,
    outward), bearing_tangential [N] (one disc); bearing_angle [deg] (from the crank arm).
    """

    crank_torque: np.ndarray
    bearing_force: np.ndarray
    bearing_radial: np.ndarray
    bearing_tangential: np.ndarray
    bearing_angle: np.ndarray


def crank_detail(history, t, sigma: int, z2: int, torque_sat: float, n_discs: int = 1) -> CrankDetail:
    r"""Crank torque and crank-bearing force at the nodes of a cycle grid, ordered by crank angle (pins.md §8).

    .. math::

        T_H(\theta) = \sum_{discs} T_{sat} \hat T_H(\theta + \Delta_d),\quad B = T_{sat} \hat B,\quad
        |B| = \sqrt{B_x^2 + B_y^2},\quad \angle B = \operatorname{atan2}(B_y, B_x)

    Parameters
    ----------
    history : mapping
        :func:`gearcalc.pins.crank_history` at the nodes (crank = T_H/T_sat along the power flow, Bx, By per
        N·mm of T_sat).
    t : ndarray
        the nodes in the cycle variable (multiplier theta = T_p t, reducer theta = T_p (1 - t)).
    sigma : int
        +1 reducer, -1 multiplier.
    z2 : int
        pins.
    torque_sat : float
        T_sat [N·mm per disc].
    n_discs : int
        n_d: the crank torques of the discs, offset by 360/n_d degrees of crank, are summed (pins.md §12.7).

    Returns
    -------
    CrankDetail

    Examples
    --------
    >>> from gearcalc import pins
    >>> g = pins.Cycloid.from_curtate_ratio(21, 22, 3.9, 0.75, 1.95)
    >>> h = pins.crank_history(g, np.pi, np.array([0.2]), np.array([0.5]), 0.0, pins.REDUCER)
    >>> d = crank_detail(h, np.array([0.2]), pins.REDUCER, 22, 21000.0)
    >>> round(float(d.crank_torque[0]), 12)      # friction-free: T_H = T_sat/u = 1 N·m
    1.0

    References
    ----------
    pins.md §4.9 (crank-bearing force, crank torque), §8 (the detail table), §12.7 (several discs).
    """
    theta = t * 360.0 / z2 if sigma == MULTIPLIER else (1.0 - t) * 360.0 / z2
    order = crank_order(theta, sigma)                       # as gearcalc.pins.cycle_detail orders the nodes
    T_H = history["crank"] * torque_sat / units.NMM_PER_NM
    if n_discs > 1:
        T_H = sum_over_discs(t, T_H, disc_offsets(n_discs, z2), 1.0)
    Bx, By = history["Bx"] * torque_sat, history["By"] * torque_sat
    return CrankDetail(crank_torque=T_H[order], bearing_force=np.hypot(Bx, By)[order], bearing_radial=Bx[order],
                       bearing_tangential=By[order], bearing_angle=np.degrees(np.arctan2(By, Bx))[order])
