"""KHV pin gearing: one operating point or many, from loss ratios to efficiencies and torques (pins.md §4.5-4.7).

The points' inputs as parameter objects (:class:`Gears`, :class:`FrictionCoefficients`, :class:`OperatingPoint`,
:class:`SatelliteLoad`), the pin circle, the friction regime, the efficiencies with their error, the shaft torques
and the scaling of a unit-torque cycle to an operating point, for floats (:data:`SCALAR_OPS`) and arrays over
points (:data:`ARRAY_OPS`) alike, bit for bit.  Units N, mm, N·mm, rad/s; torques in N·m; powers in W.

References
----------
.. [1] The paper (Prudnikov, seed 000), cited in full in :mod:`gearcalc.pins`; docs/spec/pins.md §4.5-4.7.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from .. import units
from .efficiency import efficiency_multiplier, efficiency_reducer
from .friction import PinFriction, friction_regime, peak_coefficient

__all__ = ["floats", "SCALAR_OPS", "ARRAY_OPS", "Gears", "FrictionCoefficients", "OperatingPoint", "SatelliteLoad",
           "pin_circle", "friction_regime", "efficiency_reducer_err", "shaft_torques", "EfficiencyTorques",
           "efficiency_torques", "ScaledCycle", "scale_unit_cycle"]


def floats(vals):
    r"""A float array from a list of numbers and None (NaN).

    A column of design values (:mod:`gearcalc.pins.columns`, :mod:`gearcalc.pins.checks`).

    .. math:: x_i = \text{float}(v_i), \qquad x_i = \text{NaN} \ \text{where } v_i \text{ is None}

    Parameters
    ----------
    vals : list
        Numbers and None.

    Returns
    -------
    x : ndarray
        Floats, NaN for None.

    Examples
    --------
    >>> floats([1, None]).tolist()
    [1.0, nan]

    References
    ----------
    .. [1] docs/spec/pins.md §7 (absent design values).
    """
    return np.array([np.nan if v is None else v for v in vals], dtype=float)


# The friction regime and the mapping from loss ratios to efficiencies and torques, for one operating
# point (floats) or many (arrays).  They take ``xp``: :data:`ARRAY_OPS` (numpy, arrays over points) or
# :data:`SCALAR_OPS` (one point, numpy float64 scalars).  Scalar float64 operations round exactly as the
# element operations on arrays do, and overflow or divide by zero to inf or NaN as they do, so one design
# computed on scalars equals the same design in a batch, bit for bit, without the cost of numpy calls on
# arrays of one element.

class _ScalarOps:
    """The few numpy functions of the operating-point formulas, for one point of scalars."""

    nan = math.nan

    @staticmethod
    def where(cond, a, b):
        return a if cond else b

    @staticmethod
    def maximum(a, b):
        return a if a != a or a >= b else b          # as np.maximum: NaN propagates

    abs = staticmethod(abs)

    @staticmethod
    def isnan(x) -> bool:
        return x != x

    @staticmethod
    def logical_not(x) -> bool:
        return not x

    @staticmethod
    def degrees(x):
        return x * (180.0 / math.pi)                 # as numpy's rad2deg

    @staticmethod
    def as_int(x) -> int:
        return int(x)


class _ArrayOps:
    """numpy for the formulas that take ``xp`` (see :class:`_ScalarOps`), over arrays of points."""

    def __getattr__(self, name):
        return getattr(np, name)

    @staticmethod
    def as_int(x):
        return np.asarray(x).astype(np.int64)


SCALAR_OPS = _ScalarOps()
"""``xp`` for one operating point of scalars."""
ARRAY_OPS = _ArrayOps()
"""``xp`` for arrays over operating points (numpy)."""


# The inputs of the ideal level's points (pins.md §2, §7), each field a scalar of one point or an array over the
# points (:func:`gearcalc.pins.points.ideal_points`); the friction regime of a point (mu_eff, f, rolls) is a
# :class:`~gearcalc.pins.friction.PinFriction` (:func:`friction_regime`).

class Gears(NamedTuple):
    """The gears of operating points (pins.md §2, §7): scalars of one point, or arrays over the points.

    z1, z2 : satellite teeth, pins [-] (k = z2 - z1, :attr:`k`); e : eccentricity [mm]; Rb : pin (bushing) outer
    radius R_b [mm]; K1 : curtate ratio [-] and Rp : pin-centre circle radius R_p [mm], the one not given NaN
    (:func:`pin_circle`); n_d : discs [-]; rotating : the pins carry bushings on axles; r : axle radius [mm] (NaN:
    none); b : face width [mm] (NaN: not given); p : the crank bearing's life exponent [-] (ISO 281, pins.md §8.2).

    Examples
    --------
    >>> Gears(20, 22, 3.9, 1.95, 0.75, math.nan).k
    2
    """

    z1: object
    z2: object
    e: object
    Rb: object
    K1: object
    Rp: object
    n_d: object = 1
    rotating: object = False
    r: object = math.nan
    b: object = math.nan
    p: object = 10.0 / 3.0

    @property
    def k(self):
        """The tooth difference k = z2 - z1 [-]."""
        return self.z2 - self.z1


class FrictionCoefficients(NamedTuple):
    """The friction coefficients of operating points (pins.md §2, §7 ``[friction]``): scalars or arrays.

    f : pin-tooth sliding friction [-]; f_k : rolling-friction coefficient [mm]; f_c : bushing-axle sliding friction
    [-] (f_k and f_c NaN: not given, fixed pins).
    """

    f: object
    f_k: object
    f_c: object


class OperatingPoint(NamedTuple):
    """The load and speed of operating points (pins.md §2, §7 ``[load]``): scalars of one point, or arrays.

    T : the torque given [N·m], on the satellite shaft V where ``torque_on_V``, else on the crank H; n_H : crank
    speed [rpm] (NaN: not given); multiplier : the mode (V drives H), else reducer; torque_on_V : the shaft of T.
    """

    T: object
    n_H: object
    multiplier: object
    torque_on_V: object


class SatelliteLoad(NamedTuple):
    """The torque and speed of one satellite disc (pins.md §2, §4.4-4.5): scalars of one point, or arrays.

    torque_sat : T_sat = T_V/n_d, the torque on one disc [N·mm] (None in the detail tables: not known);
    omega_V : the satellite's speed [rad/s] (NaN or None: no crank speed; |omega_V| in the summary's scaling,
    signed in the detail tables).
    """

    torque_sat: object
    omega_V: object


def pin_circle(z1, z2, eccentricity, pin_circle_radius, curtate_ratio, xp=ARRAY_OPS):
    r"""The pin-centre circle radius R_p and 1 - K1 from whichever of R_p and K1 is given (pins.md §4.1, §7).

    .. math::

        K_1 = \frac{e z_2}{k R_p}:\quad R_p = \frac{e z_2}{k K_1},\quad 1 - K_1 = \frac{k R_p - e z_2}{k R_p}

    (1 - K1 from R_p without the cancellation of 1 - e z2/(k R_p); as :meth:`Cycloid.from_pin_circle` and
    :meth:`Cycloid.from_curtate_ratio`.)

    Parameters
    ----------
    z1, z2 : int or array_like of int
        satellite teeth and pins (k = z2 - z1 >= 1).
    eccentricity : float or array_like
        e [mm].
    pin_circle_radius : float or array_like
        R_p [mm], NaN where K1 is given.
    curtate_ratio : float or array_like
        K1 [-], NaN where R_p is given (it wins where both are).
    xp : :data:`ARRAY_OPS` or :data:`SCALAR_OPS`

    Returns
    -------
    R_p [mm], 1 - K1 [-].

    Examples
    --------
    >>> pin_circle(20, 22, 3.9, math.nan, 0.75, SCALAR_OPS)       # R_p = 3.9 x 22/(2 x 0.75)
    (57.199999999999996, 0.25)
    >>> [round(float(v[0]), 12) for v in pin_circle(np.array([20]), np.array([22]), 3.9, np.array([57.2]),
    ...                                             np.array([np.nan]))]
    [57.2, 0.25]

    References
    ----------
    pins.md §4.1 (K1 = e z2/(k R_p)), §7 (give R_p or K1).
    """
    k = z2 - z1
    use_K1 = xp.logical_not(xp.isnan(curtate_ratio))
    R_p = xp.where(use_K1, eccentricity * z2 / (k * curtate_ratio), pin_circle_radius)
    one_minus_K1 = xp.where(use_K1, 1.0 - curtate_ratio, (k * R_p - eccentricity * z2) / (k * R_p))
    return R_p, one_minus_K1


def efficiency_reducer_err(loss_ratio_mean, loss_ratio_err):
    r"""Error of the reducer efficiency from that of the loss ratio, E_HV = E/(1 + lambda_bar)^2  (pins.md §4.7).

    The first-order propagation of E through eta_HV = 1/(1 + lambda_bar) (|d eta_HV/d lambda_bar| E).

    .. math:: E_{HV} = \left|\frac{d\eta_{HV}}{d\bar\lambda}\right| E = \frac{E}{(1 + \bar\lambda)^2}

    Parameters
    ----------
    loss_ratio_mean : float or array_like
        lambda_bar [-].
    loss_ratio_err : float or array_like
        E, the error estimate of lambda_bar [-].

    Returns
    -------
    E_HV [-].

    Examples
    --------
    >>> efficiency_reducer_err(0.25, 1e-6)   # 1e-6/1.5625
    6.4e-07

    References
    ----------
    pins.md §4.7 (the efficiencies), §6 (the error estimate).
    """
    return loss_ratio_err / ((1.0 + loss_ratio_mean) * (1.0 + loss_ratio_mean))


def shaft_torques(torque, ratio, eta_vh, eta_hv, multiplier, torque_on_V, xp=ARRAY_OPS):
    r"""Shaft torques T_V (satellite output) and T_H (crank) from the torque given on one of them (pins.md §4.7).

    Input power = output power + loss, with the efficiency of the mode:

    .. math::

        \text{multiplier: } T_V = \frac{u T_H}{\eta_{VH}},\qquad
        \text{reducer: } T_V = \eta_{HV} u T_H,\qquad u = z_1/k

    Parameters
    ----------
    torque : float or array_like
        the torque given, on V when ``torque_on_V`` else on H [N·m].
    ratio : float or array_like
        u = z1/k [-].
    eta_vh, eta_hv : float or array_like
        the multiplier and reducer efficiencies [-] (NaN: the mode self-locks).
    multiplier : bool or array_like of bool
        multiplier mode (V drives H), else reducer.
    torque_on_V : bool or array_like of bool
        the torque is given on V, else on H.
    xp : :data:`ARRAY_OPS` or :data:`SCALAR_OPS`

    Returns
    -------
    T_V, T_H : float or ndarray
        [N·m] (the unit of ``torque``); NaN where the efficiency they need is.

    Examples
    --------
    >>> shaft_torques(100.0, 10.0, 0.75, 0.8, False, False, SCALAR_OPS)   # reducer: T_V = 0.8 x 10 x 100
    (800.0, 100.0)
    >>> shaft_torques(100.0, 10.0, 0.75, 0.8, True, False, SCALAR_OPS)[0]  # multiplier: 10 x 100/0.75
    1333.3333333333333

    References
    ----------
    .. [1] Prudnikov (seed 000), cited in full in :mod:`gearcalc.pins`; pins.md §4.7, §4.9 (the
       friction-consistent efficiencies).
    """
    T = torque
    # both branches of where are evaluated and may divide by an efficiency 0 (a jammed mode's lambda_bar = inf
    # gives eta_HV = 0): an inf discarded, or the torques of a self-locked mode (not reported); never a numpy
    # warning (the product shows none, --debug aside)
    with np.errstate(divide="ignore", invalid="ignore"):
        T_V = xp.where(torque_on_V, T, xp.where(multiplier, ratio * T / eta_vh, eta_hv * ratio * T))
        T_H = xp.where(torque_on_V, xp.where(multiplier, eta_vh * T / ratio, T / (eta_hv * ratio)), T)
    return T_V, T_H


@dataclass(frozen=True)
class EfficiencyTorques:
    """Efficiencies, self-locking and shaft torques per operating point (:func:`efficiency_torques`).

    NaN marks an undefined value (no multiplier efficiency when it self-locks, no T_V when it self-locks
    with the torque given on H).  Torques in the unit of the torque given (N·m in the product).
    """

    locked: object
    eta_vh: object
    eta_vh_err: object
    eta_hv: object
    eta_hv_err: object
    efficiency: object
    efficiency_err: object
    self_locking: object
    T_V: object
    T_H: object
    torque_in: object
    torque_out: object


def efficiency_torques(loss_ratio_mean, loss_ratio_err, torque, ratio, multiplier, torque_on_V,
                       xp=ARRAY_OPS) -> EfficiencyTorques:
    r"""Efficiencies, self-locking and shaft torques from the cycle-mean loss ratio (pins.md §4.7).

    .. math::

        \eta_{VH} = 1 - \bar\lambda,\quad \eta_{HV} = \frac{1}{1 + \bar\lambda},\quad
        T_V = \frac{u T_H}{\eta_{VH}}\ \text{(multiplier)},\quad T_V = \eta_{HV} u T_H\ \text{(reducer)}

    The drive self-locks in the multiplier mode when lambda_bar >= 1.  Error of eta_HV:
    E/(1 + lambda_bar)^2; of eta_VH: E.

    Parameters
    ----------
    loss_ratio_mean : float or array_like
        lambda_bar [-].
    loss_ratio_err : float or array_like
        E, its error estimate [-].
    torque : float or array_like
        the torque given, on V when ``torque_on_V`` else on H [N·m].
    ratio : float or array_like
        u = z1/k [-].
    multiplier : bool or array_like of bool
        multiplier mode (V drives H), else reducer.
    torque_on_V : bool or array_like of bool
        the torque is given on the satellite shaft V, else on the crank H.
    xp : :data:`ARRAY_OPS` or :data:`SCALAR_OPS`

    Returns
    -------
    EfficiencyTorques

    Examples
    --------
    >>> et = efficiency_torques(0.25, 1e-9, 100.0, 10.0, False, False, SCALAR_OPS)
    >>> et.efficiency, et.T_V
    (0.8, 800.0)
    >>> et = efficiency_torques(np.array([0.25, 1.5]), 0.0, 100.0, 10.0, True, True)
    >>> et.self_locking.tolist(), et.efficiency.tolist()
    ([False, True], [0.75, nan])

    References
    ----------
    .. [1] Prudnikov (seed 000), cited in full in :mod:`gearcalc.pins`; pins.md §4.7.
    """
    lam, E = loss_ratio_mean, loss_ratio_err
    locked = lam >= 1.0
    eta_vh = xp.where(locked, xp.nan, efficiency_multiplier(lam))
    eta_hv = efficiency_reducer(lam)
    eta_hv_err = efficiency_reducer_err(lam, E)
    T_V, T_H = shaft_torques(torque, ratio, eta_vh, eta_hv, multiplier, torque_on_V, xp)   # NaN: no warning
    return EfficiencyTorques(
        locked=locked, eta_vh=eta_vh, eta_vh_err=xp.where(locked, xp.nan, E), eta_hv=eta_hv,
        eta_hv_err=eta_hv_err, efficiency=xp.where(multiplier, eta_vh, eta_hv),
        efficiency_err=xp.where(multiplier, xp.where(locked, xp.nan, E), eta_hv_err),
        self_locking=locked & multiplier, T_V=T_V, T_H=T_H,
        torque_in=xp.where(multiplier, T_V, T_H), torque_out=xp.where(multiplier, T_H, T_V))


@dataclass(frozen=True)
class ScaledCycle:
    """The ideal level's unit cycle scaled to operating points (:func:`scale_unit_cycle`); NaN: undefined.

    torque_sat [N·mm per disc]; omega_V, |omega_V| [rad/s]; loss_mean, loss_peak, loss_max (one pin),
    loss_bound [W]; force_max [N]; force_phase, loss_phase [deg] (NaN where the force or loss is);
    spin_abs_max, spin_min, spin_max [rpm] (0 for pins that do not roll); spin_reversals (int);
    sliding_speed_max [m/s] (0 for rolling pins).
    """

    torque_sat: object
    omega_V: object
    loss_mean: object
    loss_peak: object
    loss_max: object
    loss_bound: object
    force_max: object
    force_phase: object
    loss_phase: object
    spin_abs_max: object
    spin_min: object
    spin_max: object
    spin_reversals: object
    sliding_speed_max: object


def scale_unit_cycle(unit, loss_ratio_mean, friction: PinFriction, torque_V, crank_speed_rpm, gears: Gears,
                     xp=ARRAY_OPS) -> ScaledCycle:
    r"""Scale the ideal level's unit cycle (unit torque, speed and friction) to operating points (pins.md §4.4-4.8).

    The rigid solution does not depend on the torque, the speed or the friction coefficient (pins.md
    §4.8 identity 8): forces scale with T_sat, speeds with omega_V, losses with mu_eff T_sat omega_V.

    .. math::

        T_{sat} = \frac{T_V}{n_d},\quad |\omega_V| = \omega_H \frac{k}{z_1},\quad
        F_{max} = T_{sat} \hat F,\quad P = \mu_{eff} T_{sat} |\omega_V| \hat P,\quad
        \bar P = \bar\lambda T_V |\omega_V|

    Parameters
    ----------
    unit : object
        the unit cycle per point (fields of :class:`IdealCycles`: force, total, loss, rel_min, rel_max,
        rel_abs, psi_0, psi_star [rad], force_phase, loss_phase [rad]).
    loss_ratio_mean : float or array_like
        lambda_bar = mu_eff x the unit loss ratio [-].
    friction : :class:`~gearcalc.pins.friction.PinFriction`
        mu_eff [-], f [-] and whether the pins roll (:func:`friction_regime`), per point.
    torque_V : float or array_like
        T_V [N·m] (:func:`efficiency_torques`).
    crank_speed_rpm : float or array_like
        n_H [rpm] (NaN: not given; the losses and speeds are then NaN).
    gears : Gears
        the points' gears: z1, z2 (k = z2 - z1), n_d and R_b [mm] are used.
    xp : :data:`ARRAY_OPS` or :data:`SCALAR_OPS`

    Returns
    -------
    ScaledCycle

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> u = SimpleNamespace(force=0.01, total=0.02, loss=0.005, rel_min=-1.0, rel_max=2.0, rel_abs=2.0,
    ...                     psi_0=np.nan, psi_star=3.0, force_phase=1.0, loss_phase=1.5)
    >>> sc = scale_unit_cycle(u, 0.05, PinFriction(0.1, 0.1, False), 100.0, 1000.0, Gears(20, 21, 1.0, 2.0, 0.5,
    ...                       math.nan), SCALAR_OPS)
    >>> sc.force_max, sc.spin_abs_max
    (1000.0, 0.0)

    References
    ----------
    .. [1] Prudnikov (seed 000), cited in full in :mod:`gearcalc.pins`; pins.md §4.4-4.8.
    """
    mu_eff, rolls = friction.mu_eff, friction.rolls
    T_sat = units.nm_to_nmm(torque_V) / gears.n_d                          # N·mm per disc
    w_V = units.rpm_to_rad_s(crank_speed_rpm) * gears.k / gears.z1          # |omega_V| [rad/s]
    F_max = T_sat * unit.force                                              # N
    spin_rpm = units.rad_s_to_rpm(w_V) / gears.Rb                           # rpm per mm of rho - R_b
    v_max = w_V * unit.rel_abs                                              # mm/s
    zero = 0.0 * w_V
    P = mu_eff * T_sat * w_V
    return ScaledCycle(
        torque_sat=T_sat, omega_V=w_V, loss_mean=loss_ratio_mean * torque_V * w_V, loss_peak=P * unit.total,
        loss_max=P * unit.loss, loss_bound=peak_coefficient(mu_eff, rolls, friction.sliding, xp) * F_max * v_max * 1e-3,
        force_max=F_max, force_phase=xp.where(xp.isnan(F_max), xp.nan, xp.degrees(unit.force_phase)),
        loss_phase=xp.where(xp.isnan(P), xp.nan, xp.degrees(unit.loss_phase)),
        spin_abs_max=xp.where(rolls, spin_rpm * xp.maximum(xp.abs(unit.rel_min), xp.abs(unit.rel_max)), zero),
        spin_min=xp.where(rolls, spin_rpm * unit.rel_min, zero),
        spin_max=xp.where(rolls, spin_rpm * unit.rel_max, zero),
        spin_reversals=xp.as_int(rolls & (unit.psi_0 < unit.psi_star)),   # NaN (no reversal) compares False
        sliding_speed_max=xp.where(rolls, zero, v_max / units.MM_PER_M))
