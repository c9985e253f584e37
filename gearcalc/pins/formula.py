"""KHV pin gearing, level ``formula``: the paper's maximum friction loss per pin (pins.md §3).

The per-pin rolling and axle friction forces and powers of the paper's eqs. (3)-(7), and the loss of a
fixed (sliding) pin, over floats and numpy arrays.  Units: N, mm, rpm, W.

References
----------
.. [1] The paper (Prudnikov, seed 000), cited in full in :mod:`gearcalc.pins`; docs/spec/pins.md §3.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .. import units

__all__ = ["PAPER_PI", "pin_angular_speed", "rolling_friction_force", "axle_friction_force", "friction_power",
           "FormulaLosses", "formula_losses", "fixed_pin_formula_loss"]

PAPER_PI = 3.14
"""The value of pi the paper computed with (pins.md §3)."""


def pin_angular_speed(pin_speed_rpm, paper_pi: bool = False):
    r"""Pin spin omega = pi n/30 [rad/s], optionally with the paper's pi = 3.14.

    Parameters
    ----------
    pin_speed_rpm : n_pin [rpm].
    paper_pi : use pi = 3.14 as the paper did.

    .. math:: \omega = \frac{\pi\,n_{pin}}{30} \quad (\pi \to 3.14 \text{ with paper\_pi})

    Returns
    -------
    omega : float or ndarray
        Pin angular speed, [rad/s].

    Examples
    --------
    >>> round(pin_angular_speed(30.0, paper_pi=True), 12)
    3.14
    >>> pin_angular_speed(np.array([30.0, 30.0]), np.array([True, False])).round(4).tolist()
    [3.14, 3.1416]

    References
    ----------
    .. [1] A. P. Prudnikov, «Потери мощности в контакте цевок и зубьев планетарной передачи типа K-H-V» (Power losses in
       pins and teeth contact area of KHV-type planetary gearing), Машиностроение (seed file 000_fe288dec6e7c72f0.txt);
       eqs. (5)-(6) (π = 3.14 in its printed values); docs/spec/pins.md §3.
    """
    omega = units.rpm_to_rad_s(pin_speed_rpm)
    if np.ndim(paper_pi):                       # per element
        return np.where(paper_pi, omega * (PAPER_PI / math.pi), omega)
    return omega * (PAPER_PI / math.pi) if paper_pi else omega


def rolling_friction_force(normal_force, rolling_coefficient, bushing_radius):
    r"""Rolling-resistance force between tooth and bushing, F_tr1 = f_k F_n / R  (paper eq. 3).

    .. math:: F_{tr1} = \frac{f_k\,F_n}{R}

    Parameters
    ----------
    normal_force : F_n [N].
    rolling_coefficient : f_k [mm].
    bushing_radius : R = R_b [mm].

    Returns
    -------
    F_tr1 [N].

    Examples
    --------
    >>> round(rolling_friction_force(1920.0, 0.01, 1.95), 2)   # paper: 9.85 N
    9.85

    References
    ----------
    .. [1] A. P. Prudnikov, «Потери мощности в контакте цевок и зубьев планетарной передачи типа K-H-V» (Power losses in
       pins and teeth contact area of KHV-type planetary gearing), Машиностроение (seed file 000_fe288dec6e7c72f0.txt);
       eq. (3); docs/spec/pins.md §3.
    """
    return rolling_coefficient * normal_force / bushing_radius


def axle_friction_force(normal_force, axle_friction):
    r"""Sliding friction between bushing and axle, F_tr2 = f_c F_n  (paper eq. 4).

    .. math:: F_{tr2} = f_c\,F_n

    Parameters
    ----------
    normal_force : F_n [N] (the axle reaction equals it).
    axle_friction : f_c [-].

    Returns
    -------
    F_tr2 [N].

    Examples
    --------
    >>> axle_friction_force(1920.0, 0.1)   # paper: 192 N
    192.0

    References
    ----------
    .. [1] A. P. Prudnikov, «Потери мощности в контакте цевок и зубьев планетарной передачи типа K-H-V» (Power losses in
       pins and teeth contact area of KHV-type planetary gearing), Машиностроение (seed file 000_fe288dec6e7c72f0.txt);
       eq. (4); docs/spec/pins.md §3.
    """
    return axle_friction * normal_force


def friction_power(force, angular_speed, radius):
    r"""Power of a friction force acting at a radius of a spinning part, P = F omega R 1e-3  (eqs. 5, 6).

    .. math:: P = F\,\omega\,R \cdot 10^{-3}

    Parameters
    ----------
    force : friction force [N].
    angular_speed : spin [rad/s].
    radius : lever of the force about the spin axis [mm].

    Returns
    -------
    P [W].

    Examples
    --------
    >>> friction_power(10.0, 2.0, 3.0)
    0.06

    References
    ----------
    .. [1] A. P. Prudnikov, «Потери мощности в контакте цевок и зубьев планетарной передачи типа K-H-V» (Power losses in
       pins and teeth contact area of KHV-type planetary gearing), Машиностроение (seed file 000_fe288dec6e7c72f0.txt);
       eqs. (5), (6); docs/spec/pins.md §3.
    """
    return force * angular_speed * radius * 1e-3


@dataclass(frozen=True)
class FormulaLosses:
    """Per-pin maximum losses of the paper (eqs. 3-7): forces [N], powers [W] (floats or arrays).

    ``P_tr_fixed`` is the fixed-pin variant (:func:`fixed_pin_formula_loss`), None unless the sliding
    friction was given.
    """

    F_tr1: float
    F_tr2: float
    P_tr1: float
    P_tr2: float
    P_tr: float
    P_tr_fixed: float | None = None


def formula_losses(normal_force, pin_speed_rpm, bushing_radius, axle_radius, rolling_coefficient,
                   axle_friction, paper_pi=False, sliding_friction=None) -> FormulaLosses:
    r"""The paper's maximum friction loss on one rotating pin, eqs. (3)-(7).

    .. math::

        F_{tr1} = \frac{f_k F_n}{R},\quad F_{tr2} = f_c F_n,\quad
        P_{tr1} = F_{tr1}\,\omega R\,10^{-3},\quad P_{tr2} = F_{tr2}\,\omega r\,10^{-3},\quad
        P_{tr} = P_{tr1} + P_{tr2},\quad \omega = \frac{\pi n_{pin}}{30}

    Parameters
    ----------
    normal_force : float or array_like
        F_n, peak normal force on one pin [N].
    pin_speed_rpm : float or array_like
        n_pin, bushing speed [rpm].
    bushing_radius : float or array_like
        R, outer radius of the bushing [mm].
    axle_radius : float or array_like
        r, radius of the axle [mm].
    rolling_coefficient : float or array_like
        f_k, rolling friction between tooth and bushing [mm].
    axle_friction : float or array_like
        f_c, sliding friction between bushing and axle [-].
    paper_pi : bool or array_like of bool
        compute with pi = 3.14 (reproduces the paper's printed digits), per element for an array.
    sliding_friction : float or array_like, optional
        f, tooth-pin sliding friction [-]: also gives ``P_tr_fixed``, the fixed-pin loss
        f F_n omega R 1e-3 [W] (pins.md §3).

    Returns
    -------
    FormulaLosses
        F_tr1, F_tr2 [N]; P_tr1, P_tr2, P_tr, P_tr_fixed [W]; floats or arrays (NaN in, NaN out).

    Examples
    --------
    >>> round(formula_losses(1920, 14, 1.95, 0.95, 0.01, 0.1, paper_pi=True).P_tr, 3)  # paper 0.295 W
    0.295
    >>> formula_losses(np.array([1920.0, 960.0]), 14, 1.95, 0.95, 0.01, 0.1, paper_pi=True).P_tr.round(4).tolist()
    [0.2954, 0.1477]

    References
    ----------
    .. [1] Prudnikov (seed 000), cited in full in :mod:`gearcalc.pins`, eqs. (3)-(7); pins.md §3.
    """
    omega = pin_angular_speed(pin_speed_rpm, paper_pi)
    f1 = rolling_friction_force(normal_force, rolling_coefficient, bushing_radius)
    f2 = axle_friction_force(normal_force, axle_friction)
    p1 = friction_power(f1, omega, bushing_radius)
    p2 = friction_power(f2, omega, axle_radius)
    fixed = None if sliding_friction is None else friction_power(sliding_friction * normal_force, omega,
                                                                 bushing_radius)
    return FormulaLosses(f1, f2, p1, p2, p1 + p2, fixed)


def fixed_pin_formula_loss(normal_force, pin_speed_rpm, bushing_radius, sliding_friction, paper_pi=False):
    r"""Fixed-pin variant of eq. (7): P = f F_n v_s 1e-3 with v_s = (pi n_eq/30) R  (pins.md §3).

    .. math:: P_{tr,fix} = f\,F_n\,v_s \cdot 10^{-3}, \qquad v_s = \frac{\pi\,n_{eq}}{30}\,R

    Parameters
    ----------
    normal_force : F_n [N].
    pin_speed_rpm : n_eq, the speed the pin would turn at if it rolled [rpm].
    bushing_radius : R [mm].
    sliding_friction : f [-].
    paper_pi : pi = 3.14.

    Returns
    -------
    P_tr,fix [W].

    Examples
    --------
    >>> round(fixed_pin_formula_loss(1920, 14, 1.95, 0.1, paper_pi=True), 4)
    0.5486

    References
    ----------
    .. [1] A. P. Prudnikov, «Потери мощности в контакте цевок и зубьев планетарной передачи типа K-H-V» (Power losses in
       pins and teeth contact area of KHV-type planetary gearing), Машиностроение (seed file 000_fe288dec6e7c72f0.txt);
       eq. (7) (the rotating-pin form); docs/spec/pins.md §3 (the fixed-pin variant, derived).
    """
    return friction_power(sliding_friction * normal_force, pin_angular_speed(pin_speed_rpm, paper_pi),
                          bushing_radius)
