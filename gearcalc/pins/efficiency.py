"""KHV pin gearing: rolling condition, sliding speeds, pin spin, losses and efficiency (pins.md §4.5-4.7).

Pure functions over floats and numpy arrays: whether the pins roll, the rotating-pin loss coefficient,
the sliding speed and pin spin at a contact, a contact's loss power, and the efficiencies from a cycle's
mean loss ratio (reducer, multiplier, Willis).  Units N, mm, rad/s, W.

References
----------
.. [1] The paper (Prudnikov, seed 000), cited in full in :mod:`gearcalc.pins`; docs/spec/pins.md §4.5-4.7.
"""
from __future__ import annotations

import numpy as np

from .friction import contact_loss_power, rolling_condition, rotating_loss_coefficient


__all__ = ["rolling_condition", "rotating_loss_coefficient", "sliding_speed", "pin_spin", "contact_loss_power",
           "efficiency_multiplier", "efficiency_reducer", "willis_efficiencies"]


def sliding_speed(rho, bushing_radius, omega_V):
    r"""Sliding speed at a contact on a fixed pin [mm/s].

    .. math:: v = |\omega_V|\,|\rho - R_b|

    Parameters
    ----------
    rho : float or array_like
        Pin centre to pitch point ρ, [mm].
    bushing_radius : float
        Pin (bushing) radius R_b, [mm].
    omega_V : float
        Satellite (output) angular speed ω_V, [rad/s].

    Returns
    -------
    v : ndarray
        Sliding speed, [mm/s].

    Examples
    --------
    >>> float(sliding_speed(10.0, 2.0, -3.0))
    24.0

    References
    ----------
    .. [1] docs/spec/pins.md §4.5 (derived: the contact point lies on the line from the pin centre to P).
    """
    return np.abs(omega_V) * np.abs(np.asarray(rho) - bushing_radius)


def pin_spin(rho, bushing_radius, omega_V):
    r"""Signed spin of a pin that rolls without slip [rad/s].

    .. math:: \omega_{pin} = -\omega_V\,\frac{\rho - R_b}{R_b}

    Parameters
    ----------
    rho : float or array_like
        Pin centre to pitch point ρ, [mm].
    bushing_radius : float
        Pin (bushing) radius R_b, [mm].
    omega_V : float
        Satellite (output) angular speed ω_V, [rad/s].

    Returns
    -------
    omega_pin : ndarray
        Pin spin, [rad/s].

    Examples
    --------
    >>> float(pin_spin(10.0, 2.0, -3.0))
    12.0

    References
    ----------
    .. [1] docs/spec/pins.md §4.5 (derived).
    """
    return -omega_V * (np.asarray(rho) - bushing_radius) / bushing_radius


def efficiency_multiplier(loss_ratio_mean):
    r"""Multiplier (V -> H) efficiency; <= 0 means self-locking [-].

    .. math:: \eta_{VH} = 1 - \bar\lambda

    Parameters
    ----------
    loss_ratio_mean : float or array_like
        Cycle-mean loss ratio λ̄, [-].

    Returns
    -------
    eta_VH : float or ndarray
        Efficiency, [-].

    Examples
    --------
    >>> efficiency_multiplier(0.25)
    0.75

    References
    ----------
    .. [1] docs/spec/pins.md §4.7 (derived).
    """
    return 1.0 - loss_ratio_mean


def efficiency_reducer(loss_ratio_mean):
    r"""Reducer (H -> V) efficiency [-].

    .. math:: \eta_{HV} = \frac{1}{1 + \bar\lambda}

    Parameters
    ----------
    loss_ratio_mean : float or array_like
        Cycle-mean loss ratio λ̄, [-].

    Returns
    -------
    eta_HV : float or ndarray
        Efficiency, [-].

    Examples
    --------
    >>> efficiency_reducer(0.25)
    0.8

    References
    ----------
    .. [1] docs/spec/pins.md §4.7 (derived).
    """
    return 1.0 / (1.0 + loss_ratio_mean)


def willis_efficiencies(loss_ratio_mean, z1: int, z2: int):
    r"""Willis cross-check of the efficiencies from the basic (fixed-carrier) efficiency [-].

    .. math:: \psi_0 = \bar\lambda\,\frac{k}{z_2}, \quad \eta_0 = 1 - \psi_0, \qquad
        \eta^W_{VH} = \frac{z_2\,\eta_0 - z_1}{k} = 1 - \bar\lambda, \qquad
        \eta^W_{HV} = \frac{k\,\eta_0}{z_2 - z_1\,\eta_0}

    Parameters
    ----------
    loss_ratio_mean : float
        Cycle-mean loss ratio λ̄, [-].
    z1 : int
        Satellite teeth, [-].
    z2 : int
        Pins, [-].

    Returns
    -------
    eta0, eta_VH, eta_HV : float
        Basic efficiency and the Willis efficiencies of the multiplier and the reducer, [-].

    Examples
    --------
    >>> [round(x, 12) for x in willis_efficiencies(0.2, 20, 22)]
    [0.981818181818, 0.8, 0.830769230769]

    References
    ----------
    .. [1] R. Willis, Principles of Mechanism, 2nd ed., Longmans, Green, and Co., London, 1870 (the fixed-carrier
       train); docs/spec/pins.md §4.7.
    """
    k = z2 - z1
    eta0 = 1.0 - loss_ratio_mean * k / z2
    return eta0, (z2 * eta0 - z1) / k, k * eta0 / (z2 - z1 * eta0)
