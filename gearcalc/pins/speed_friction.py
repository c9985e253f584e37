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

__all__ = ["power_weighted_coefficient", "NODES"]

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


def _law_of(a: dict):
    """The design's :class:`~gearcalc.pins.friction.FrictionLaw` from its values by argument name.

    (:data:`gearcalc.pins.output_keys.LAW_ARGS`); None for Coulomb's law (friction.sliding).
    """
    name = a.get("f_law") or "coulomb"
    if name == "table":
        return friction_law("table", speed_m_s=tuple(a["f_v"]), mu=tuple(a["f_mu"]))
    if name == "stribeck":
        delta = 2.0 if a.get("f_delta") is None else a["f_delta"]
        k_v = 0.0 if a.get("f_kv") is None else a["f_kv"]
        return friction_law("stribeck", mu_s=a["f_s"], mu_c=a["f_c"], v_s=a["f_vs"], delta=delta, k_v=k_v)
    return None


def _omega_V(z1, z2, speed_rpm):
    return speed_rpm * math.pi / 30.0 * (z2 - z1) / z1
