"""KHV pin gearing, level ``ideal``: pin phases, the loaded set and the pin forces (pins.md §4.1, §4.3, §4.4).

The phase of each pin at a crank angle, which pins carry load, the lever-arm sum, the friction-free pin
forces from the satellite's moment balance and the instantaneous loss ratio.  Units N, mm, rad.

References
----------
.. [1] The paper (Prudnikov, seed 000), cited in full in :mod:`gearcalc.pins`; docs/spec/pins.md §4.3-4.4.
"""
from __future__ import annotations

import math

import numpy as np

from .geometry import Cycloid, lever_arm, pitch_distance, REDUCER

__all__ = ["pin_phase", "lever_sum", "pin_forces", "loss_ratio", "full_circle_lever_sum"]


def pin_phase(pin, theta, z2: int, sigma: int = REDUCER):
    r"""Load-side phase psi~ = (sigma (phi_i - theta)) mod 2 pi, in exact integer phase arithmetic [rad].

    theta = T_p (m + tau) with m an integer and 0 <= tau < 1; psi = pi ((2 ((i - m) mod z2) - 2 tau)/z2),
    dividing before multiplying by pi, so that pins exactly at 0 or pi stay exact (pins.md §4.1).

    Parameters
    ----------
    pin : pin index i (array-like of int).
    theta : crank angle [rad].
    z2 : number of pins.
    sigma : +1 reducer, -1 multiplier.

    .. math:: \tilde\psi_i = \sigma\,(\varphi_i - \theta) \bmod 2\pi
        = \pi\,\frac{2\,((i - m) \bmod z_2) - 2\tau}{z_2}, \qquad \theta = T_p\,(m + \tau),\ T_p = \frac{2\pi}{z_2}

    (the reducer's form; the multiplier's has m - i and + 2 tau).

    Returns
    -------
    psi : ndarray
        Load-side phase in (0, 2 pi], [rad].

    Examples
    --------
    >>> float(pin_phase(25, 0.0, 50))  # exactly pi, although 2 pi/50 * 25 need not be
    3.141592653589793

    References
    ----------
    .. [1] A. P. Prudnikov, «Потери мощности в контакте цевок и зубьев планетарной передачи типа K-H-V» (Power losses in
       pins and teeth contact area of KHV-type planetary gearing), Машиностроение (seed file 000_fe288dec6e7c72f0.txt);
       docs/spec/pins.md §4.1.
    """
    pin = np.asarray(pin)
    if pin.size and (pin.min() < 0 or pin.max() >= z2):
        pin = np.mod(pin, z2)
    t = np.asarray(theta, dtype=float) * (z2 / (2.0 * math.pi))
    m = np.floor(t)
    tau = t - m
    m = np.mod(m.astype(np.int64), z2)
    # (pin - m) mod z2 with both in [0, z2): the difference, plus z2 where negative (an integer modulo over every pin
    # and crank angle costs 4x as much)
    d = pin - m if sigma == REDUCER else m - pin
    j = d + z2 * (d < 0)
    if sigma == REDUCER:
        j = np.where((j == 0) & (tau > 0), z2, j)
        return math.pi * ((2.0 * j - 2.0 * tau) / z2)
    return math.pi * ((2.0 * j + 2.0 * tau) / z2)


def lever_sum(theta, g: Cycloid, psi_star: float, sigma: int = REDUCER):
    r"""S(theta) = sum over the loaded pins of l_i^2 [mm^2], pointwise in theta (pins.md §4.4).

    .. math:: S(\theta) = \sum_{j \in L(\theta)} l_j^2, \qquad L = \{j : 0 < \tilde\psi_j < \psi^*\}

    Parameters
    ----------
    theta : float or array_like
        Crank angles, [rad], shape (n,).
    g : Cycloid
        The gear.
    psi_star : float
        End of the loaded arc, [rad].
    sigma : int, optional
        +1 reducer, -1 multiplier.

    Returns
    -------
    S : ndarray
        The sum, [mm²], shape (n,).

    Examples
    --------
    >>> g = Cycloid.from_curtate_ratio(21, 22, 3.9, 0.75, 1.95)
    >>> bool(lever_sum(0.1, g, np.pi) > 0)
    True

    References
    ----------
    .. [1] S. K. Malhotra, M. A. Parameswaran, Analysis of a cycloid speed reducer, Mechanism and Machine Theory
       18(6):491-499, 1983; docs/spec/pins.md §4.4.
    """
    psi, loaded = _pointwise_phases(theta, g, psi_star, sigma)
    lev = lever_arm(psi, g)
    return np.sum(np.where(loaded, lev * lev, 0.0), axis=0)


def _pointwise_phases(theta, g, psi_star, sigma):
    theta = np.atleast_1d(np.asarray(theta, dtype=float))
    pins = np.arange(g.z2)[:, None]
    psi = pin_phase(pins, theta[None, :], g.z2, sigma)
    loaded = (psi > 0.0) & (psi < psi_star)
    return psi, loaded


def pin_forces(theta, g: Cycloid, psi_star: float, torque_sat, sigma: int = REDUCER):
    r"""Pin normal forces F_i = T_sat |l_i|/S(theta) (zero off the loaded set) [N]  (pins.md §4.4).

    .. math:: F_i = \frac{T_{sat}\,|l_i|}{S(\theta)} \ (i \in L), \qquad F_i = 0 \ \text{otherwise}

    Parameters
    ----------
    theta : crank angles [rad], shape (n,).
    g : the gear; psi_star : end of the loaded arc [rad].
    torque_sat : torque per satellite T_sat [N·mm].
    sigma : +1 reducer, -1 multiplier.

    Returns
    -------
    F : shape (z2, n) [N]; pin i in row i.

    Examples
    --------
    >>> g = Cycloid.from_curtate_ratio(21, 22, 3.9, 0.75, 1.95)
    >>> F = pin_forces([0.05], g, np.pi, 1000.0)
    >>> psi = pin_phase(np.arange(22)[:, None], 0.05, 22)
    >>> round(float(np.sum(F * np.abs(lever_arm(psi, g)))), 9)    # equilibrium: T_sat
    1000.0

    References
    ----------
    .. [1] S. K. Malhotra, M. A. Parameswaran, Analysis of a cycloid speed reducer, Mechanism and Machine Theory
       18(6):491-499, 1983 (F_i proportional to |l_i|); docs/spec/pins.md §4.4.
    """
    psi, loaded = _pointwise_phases(theta, g, psi_star, sigma)
    lev = np.abs(lever_arm(psi, g))
    S = np.sum(np.where(loaded, lev * lev, 0.0), axis=0)
    return np.where(loaded, torque_sat * lev / S, 0.0)


def loss_ratio(theta, g: Cycloid, psi_star: float, mu_eff: float, sigma: int = REDUCER):
    r"""Instantaneous loss ratio lambda(theta) = mu_eff sum |l_i| |rho_i - R_b| / sum l_i^2  (pins.md §4.6).

    Pointwise in theta (membership 0 < psi~ < psi* decided at theta itself); the cycle integration
    uses :func:`cycle_loss_ratio` instead, which evaluates piece ends as one-sided limits.

    .. math:: \lambda(\theta) = \mu_{eff}\,\frac{\sum_{i \in L} |l_i|\,|\rho_i - R_b|}{\sum_{i \in L} l_i^2}

    Parameters
    ----------
    theta : float or array_like
        Crank angles, [rad], shape (n,).
    g : Cycloid
        The gear.
    psi_star : float
        End of the loaded arc, [rad].
    mu_eff : float
        Effective friction coefficient, [-].
    sigma : int, optional
        +1 reducer, -1 multiplier.

    Returns
    -------
    lam : ndarray
        Loss ratio, [-], shape (n,).

    Examples
    --------
    >>> from gearcalc.pins import MULTIPLIER
    >>> g = Cycloid.from_curtate_ratio(21, 22, 3.9, 0.75, 1.95)
    >>> a = loss_ratio([0.1], g, np.pi, 0.1, REDUCER); b = loss_ratio([-0.1], g, np.pi, 0.1, MULTIPLIER)
    >>> bool(abs(a[0] - b[0]) < 1e-13)
    True

    References
    ----------
    .. [1] A. P. Prudnikov, «Потери мощности в контакте цевок и зубьев планетарной передачи типа K-H-V» (Power losses in
       pins and teeth contact area of KHV-type planetary gearing), Машиностроение (seed file 000_fe288dec6e7c72f0.txt);
       docs/spec/pins.md §4.6.
    """
    psi, loaded = _pointwise_phases(theta, g, psi_star, sigma)
    lev = np.abs(lever_arm(psi, g))
    S = np.sum(np.where(loaded, lev * lev, 0.0), axis=0)
    num = np.sum(np.where(loaded, lev * np.abs(pitch_distance(psi, g) - g.R_b), 0.0), axis=0)
    return mu_eff * num / S


def full_circle_lever_sum(theta, z2: int, K1: float):
    r"""Closed form of sum over all pins of (l_i/r_p1)^2 (pins.md §4.8, identity 2).

    z2/2 - (z2 (1 - K1^2)/(2 K1^2)) Re[q/(1 - q)], q = K1^z2 exp(i z2 theta).

    .. math:: \sum_{i=0}^{z_2 - 1} \left(\frac{l_i}{r_{p1}}\right)^2
        = \frac{z_2}{2} - \frac{z_2\,(1 - K_1^2)}{2 K_1^2}\,\operatorname{Re}\frac{q}{1 - q}, \qquad
        q = K_1^{z_2}\,e^{i z_2 \theta}

    Parameters
    ----------
    theta : float or array_like
        Crank angle, [rad].
    z2 : int
        Number of pins, [-].
    K1 : float
        Curtate ratio, [-].

    Returns
    -------
    sum : ndarray
        The dimensionless sum, [-].

    Examples
    --------
    >>> round(float(full_circle_lever_sum(0.0, 1000, 0.5)), 9)
    500.0

    References
    ----------
    .. [1] docs/spec/pins.md §4.8, identity 2 (derived).
    """
    q = K1 ** z2 * np.exp(1j * z2 * np.asarray(theta, dtype=float))
    return z2 / 2.0 - (z2 * (1.0 - K1 * K1) / (2.0 * K1 * K1)) * np.real(q / (1.0 - q))
