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
    """Sliding speed at a contact on a fixed pin, v = |omega_V| |rho - R_b| [mm/s]  (pins.md §4.5).

    Examples
    --------
    >>> float(sliding_speed(10.0, 2.0, -3.0))
    24.0
    """
    return np.abs(omega_V) * np.abs(np.asarray(rho) - bushing_radius)


def pin_spin(rho, bushing_radius, omega_V):
    """Signed spin of a rolling pin, omega_pin = -omega_V (rho - R_b)/R_b [rad/s]  (pins.md §4.5).

    Examples
    --------
    >>> float(pin_spin(10.0, 2.0, -3.0))
    12.0
    """
    return -omega_V * (np.asarray(rho) - bushing_radius) / bushing_radius


def efficiency_multiplier(loss_ratio_mean):
    """Multiplier (V -> H) efficiency eta_VH = 1 - lambda_bar; <= 0 means self-locking  (pins.md §4.7).

    Examples
    --------
    >>> efficiency_multiplier(0.25)
    0.75
    """
    return 1.0 - loss_ratio_mean


def efficiency_reducer(loss_ratio_mean):
    """Reducer (H -> V) efficiency eta_HV = 1/(1 + lambda_bar)  (pins.md §4.7).

    Examples
    --------
    >>> efficiency_reducer(0.25)
    0.8
    """
    return 1.0 / (1.0 + loss_ratio_mean)


def willis_efficiencies(loss_ratio_mean, z1: int, z2: int):
    """Willis cross-check: (eta0, eta_VH^W, eta_HV^W) with psi0 = lambda_bar k/z2, eta0 = 1 - psi0.

    eta_VH^W = (z2 eta0 - z1)/k (identical to 1 - lambda_bar); eta_HV^W = k eta0/(z2 - z1 eta0)
    (pins.md §4.7).

    Examples
    --------
    >>> [round(x, 12) for x in willis_efficiencies(0.2, 20, 22)]
    [0.981818181818, 0.8, 0.830769230769]
    """
    k = z2 - z1
    eta0 = 1.0 - loss_ratio_mean * k / z2
    return eta0, (z2 * eta0 - z1) / k, k * eta0 / (z2 - z1 * eta0)
