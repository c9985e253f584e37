r"""KHV pin gearing, level ``ideal``: a speed-dependent sliding law over the cycle (pins.md §4.10).

The ideal level scales a unit loss ratio by one coefficient (§4.6).  With a law mu(v) (``friction.law``: a table or
the Stribeck curve, :mod:`gearcalc.pins.friction`) every contact slides at its own speed v_i = |omega_V| |rho_i - R_b|
(fixed pins), and the loss is the cycle mean of sum_i mu(v_i) F_i v_i: it equals the unit loss ratio times the
power-weighted mean coefficient

.. math:: \bar\mu = \frac{\langle \sum_i \mu(v_i)\,F_i\,v_i \rangle}{\langle \sum_i F_i\,v_i \rangle}

(friction-free forces F_i = T_sat |l_i|/S).  The first-order model with mu = mu-bar is then exact; the
friction-consistent model (§4.9) runs with mu-bar as its constant coefficient (an approximation: the friction
changes the forces by O(mu), so the weights by O(mu) too).  Units mm, rad/s, m/s.
"""
from __future__ import annotations

import math

import numpy as np

from .friction import friction_law

__all__ = ["power_weighted_coefficient", "NODES", "sliding_law", "satellite_speed"]

NODES = 2048
"""Crank angles (midpoints) over one tooth period of the power-weighted mean."""


def power_weighted_coefficient(law, g, psi_star: float, omega_V: float, nodes: int = NODES) -> float:
    r"""The power-weighted mean sliding coefficient of a gear's teeth over the cycle, fixed pins [-].

    .. math:: \bar\mu = \frac{\sum_n \sum_i \mu(|\omega_V| |\rho_i - R_b|)\,|l_i|\,|\rho_i - R_b| / S_n}
        {\sum_n \sum_i |l_i|\,|\rho_i - R_b| / S_n}, \qquad S_n = \sum_i l_i^2

    Parameters
    ----------
    law : FrictionLaw
        The sliding law, speeds in m/s.
    g : Cycloid
        The gear.
    psi_star : float
        End of the loaded arc, [rad].
    omega_V : float
        Satellite angular speed, [rad/s].
    nodes : int, optional
        Crank angles over one tooth period (the midpoint rule).

    Returns
    -------
    mu_bar : float
        [-].

    Examples
    --------
    >>> from gearcalc.pins.friction import TableLaw
    >>> from gearcalc.pins.geometry import Cycloid, crest_cutoff
    >>> g = Cycloid.from_curtate_ratio(20, 22, 3.9, 0.75, 1.95)
    >>> round(power_weighted_coefficient(TableLaw((0.0, 1.0), (0.1, 0.1)), g, crest_cutoff(g), 10.0), 12)
    0.1

    References
    ----------
    .. [1] docs/spec/pins.md §4.6 (the loss ratio), §4.10 (the speed-dependent law).
    """
    from .geometry import as_arrays
    from .ideal import contacts_geo, GearTable

    G = GearTable.of(as_arrays(g), np.array([psi_star]))
    t = (np.arange(nodes) + 0.5) / nodes
    _, lev, rho, _, _ = contacts_geo(t, t, None, G, int(g.z2))
    rel = np.abs(rho - float(g.R_b))
    wgt = lev * rel / (lev * lev).sum(axis=0)
    mu = law.coefficient(abs(omega_V) * rel * 1e-3)
    return float((mu * wgt).sum() / wgt.sum())


def sliding_law(a: dict):
    r"""The design's sliding law (``friction.law``, pins.md §4.10) from its values by argument name.

    The names are those of :data:`gearcalc.pins.output_keys.LAW_ARGS` (f_law, f_v, f_mu, f_s, f_c, f_vs, f_delta,
    f_kv); a table's coefficient is interpolated over the speed, Stribeck's curve is (with the defaults delta = 2,
    k_v = 0)

    .. math:: \mu(v) = \mu_c + (\mu_s - \mu_c)\,e^{-(v/v_s)^\delta} + k_v\,v

    Parameters
    ----------
    a : dict
        The design's law values by argument name (None: not given).

    Returns
    -------
    law : FrictionLaw or None
        The law (:func:`gearcalc.pins.friction.friction_law`); None for Coulomb's law (friction.sliding).

    Examples
    --------
    >>> float(sliding_law({"f_law": "table", "f_v": [0.0, 1.0], "f_mu": [0.1, 0.05]}).coefficient(0.5))
    0.07500000000000001
    >>> sliding_law({"f_law": None}) is None
    True

    References
    ----------
    .. [1] docs/spec/pins.md §4.10 (the speed-dependent law), §7 (friction.law and its keys).
    """
    name = a.get("f_law") or "coulomb"
    if name == "table":
        return friction_law("table", speed_m_s=tuple(a["f_v"]), mu=tuple(a["f_mu"]))
    if name == "stribeck":
        delta = 2.0 if a.get("f_delta") is None else a["f_delta"]
        k_v = 0.0 if a.get("f_kv") is None else a["f_kv"]
        return friction_law("stribeck", mu_s=a["f_s"], mu_c=a["f_c"], v_s=a["f_vs"], delta=delta, k_v=k_v)
    return None


def satellite_speed(z1, z2, speed_rpm):
    r"""The satellite's speed |omega_V| from the crank speed n_H (pins.md §2) [rad/s].

    .. math:: |\omega_V| = \frac{\pi n_H}{30}\,\frac{z_2 - z_1}{z_1}

    Parameters
    ----------
    z1, z2 : int
        Satellite teeth and pins, [-].
    speed_rpm : float
        Crank speed n_H, [rpm].

    Returns
    -------
    omega_V : float
        [rad/s].

    Examples
    --------
    >>> round(satellite_speed(20, 22, 1000.0), 12)        # 1000 rpm, u = 10
    10.471975511966

    References
    ----------
    .. [1] docs/spec/pins.md §2 (omega_V = -omega_H k/z1), §4.5.
    """
    return speed_rpm * math.pi / 30.0 * (z2 - z1) / z1
