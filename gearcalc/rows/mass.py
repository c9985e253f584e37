"""Relative mass M(i) of the multi-row planetary gear per output torque and the ratio that minimises it (rows.md §6).

Pure functions over floats and numpy arrays; M in kg/(kN·m), ρ in kg/m³, E and σ_HP in MPa.

References
----------
.. [1] The seed paper 004, cited in full in :mod:`gearcalc.rows`; docs/spec/rows.md (the
   section numbers "rows.md §x" refer to it).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .. import hertz
from ..roots import minimize_golden

__all__ = ["Mass", "mass_and_optimum", "mass_bracket", "relative_mass", "mass_optimum_closed_form"]


def mass_bracket(ratio, rows, planets_per_row, wall_ratio, sun_fill, planet_fill, cheek_ratio):
    r"""The paper's volume bracket {…} of the relative mass, in units of π d_a² b_w/4 [-].

    .. math::

        \{\dots\} = 8t\,(i - 1)^2 \left[\bar b\,(n + 1) + n + 0.25\right] + k_a \left[\bar b\,(n - 1) + n\right]
        + k_g\,n\,n_w \left(\tfrac12 i - 1\right)^2 + \bar b\,(n + 1) \left(\tfrac12 i\right)^2

    The terms: ring rim and housing, sun, the n n_w planets, the n + 1 cheeks.

    Parameters
    ----------
    ratio : float or array_like
        Ratio i, [-].
    rows : int
        Number of rows n, [-].
    planets_per_row : int
        Number of planets in a row n_w, [-].
    wall_ratio : float
        Wall thickness of the ring rim, housing and covers relative to the ring diameter t, [-].
    sun_fill : float
        Fill factor of the sun k_a, [-].
    planet_fill : float
        Fill factor of a planet k_g, [-].
    cheek_ratio : float
        Cheek ratio b̄ = b/b_w, [-].

    Returns
    -------
    bracket : ndarray
        The bracket, [-] (volumes in units of π d_a² b_w/4).

    Examples
    --------
    >>> float(mass_bracket(3.5, 2, 3, 0.06, 0.7, 1.0, 0.25))   # Fig. 5 set, n = 2, i = 3.5
    16.246875

    References
    ----------
    .. [1] Seed paper 004_971077b94d8d4426.txt, an OCR of a Russian journal paper on multi-row planetary gears (title,
       authors, journal and year not recoverable; its ref. [1]: F. I. Plekhanov, «Зубчатые планетарные передачи»); its
       relative-mass formula (the bracket); docs/spec/rows.md §6.
    """
    i = np.asarray(ratio, float)
    n, b = rows, cheek_ratio
    return (8.0 * wall_ratio * (i - 1.0) ** 2 * (b * (n + 1) + n + 0.25) + sun_fill * (b * (n - 1) + n)
            + planet_fill * n * planets_per_row * (0.5 * i - 1.0) ** 2 + b * (n + 1) * (0.5 * i) ** 2)


def relative_mass(ratio, rows, planets_per_row, wall_ratio=0.06, sun_fill=0.7, planet_fill=1.0, cheek_ratio=0.25,
                  allowable_contact=600.0, density=7800.0, youngs_modulus=2e5, poisson=0.3, efficiency=0.95,
                  unevenness=1.0, pressure_angle=math.radians(20.0)):
    r"""Relative mass M of the gear per output torque [kg/(kN·m)].

    .. math::

        M = 10^{-3}\,\frac{2\pi\,\rho\,K\,E\,\{\dots\}}{\eta\,(\sigma_{HP}/c_H)^2\,n\,n_w\,(i - 2)\sin 2\alpha_w},
        \qquad c_H = \left(2\pi\,(1 - \nu^2)\right)^{-1/2}

    with the bracket {…} of :func:`mass_bracket` (the OCR'd prefactor with its missing cos α_w restored;
    c_H = 0.418 for ν = 0.3).

    Parameters
    ----------
    ratio : float or array_like
        Ratio i (> 2), [-].
    rows : int
        Number of rows n, [-].
    planets_per_row : int
        Number of planets in a row n_w, [-].
    wall_ratio, sun_fill, planet_fill, cheek_ratio : float, optional
        t, k_a, k_g, b̄ of :func:`mass_bracket`, [-] (the paper's Fig. 5 set: 0.06, 0.7, 1.0, 0.25).
    allowable_contact : float, optional
        Allowable contact stress σ_HP, [MPa] (600).
    density : float, optional
        Density ρ, [kg/m³] (7800).
    youngs_modulus : float, optional
        Young's modulus E, [MPa] (2e5).
    poisson : float, optional
        Poisson's ratio ν, [-] (0.3).
    efficiency : float, optional
        Efficiency η, [-] (0.95).
    unevenness : float, optional
        Row unevenness factor K, [-] (1: equalised rows).
    pressure_angle : float, optional
        Working pressure angle α_w, [rad] (20°).

    Returns
    -------
    M : ndarray
        Relative mass, [kg/(kN·m)].

    Examples
    --------
    >>> round(float(relative_mass(3.5, 2, 3)), 3)   # bracket 16.246875 x prefactor 866.45 x 1e-3
    14.077

    References
    ----------
    .. [1] Seed paper 004_971077b94d8d4426.txt, an OCR of a Russian journal paper on multi-row planetary gears (title,
       authors, journal and year not recoverable; its ref. [1]: F. I. Plekhanov, «Зубчатые планетарные передачи»); its
       relative-mass formula, prefactor rederived; docs/spec/rows.md §6, §13.9.
    .. [2] K. L. Johnson, Contact Mechanics, Cambridge University Press, 1985, §5.6 (Hertz line contact: 0.418).
    """
    i = np.asarray(ratio, float)
    c_h = hertz.line_pressure_constant(poisson)
    pref = 2.0 * math.pi * density * unevenness * youngs_modulus / (
        efficiency * (allowable_contact / c_h) ** 2 * rows * planets_per_row * (i - 2.0) * np.sin(2.0 * pressure_angle))
    return 1e-3 * pref * mass_bracket(i, rows, planets_per_row, wall_ratio, sun_fill, planet_fill, cheek_ratio)


def mass_optimum_closed_form(rows, planets_per_row, wall_ratio, sun_fill, planet_fill, cheek_ratio):
    r"""Minimiser i* of M(i) for a constant K [-].

    .. math::

        i^* = 2 + \sqrt{C_0/A}, \qquad A = 8t\,L_h + \tfrac14 k_g\,n\,n_w + \tfrac14 \bar b\,(n + 1), \qquad
        C_0 = 8t\,L_h + k_a\,L_a + \bar b\,(n + 1),

        L_h = \bar b\,(n + 1) + n + 0.25, \qquad L_a = \bar b\,(n - 1) + n

    (with x = i - 2, M ∝ A x + B₀ + C₀/x).

    Parameters
    ----------
    rows : int
        Number of rows n, [-].
    planets_per_row : int
        Number of planets in a row n_w, [-].
    wall_ratio, sun_fill, planet_fill, cheek_ratio : float
        t, k_a, k_g, b̄ of :func:`mass_bracket`, [-].

    Returns
    -------
    i_opt : ndarray
        The optimum ratio, [-].

    Examples
    --------
    >>> round(float(mass_optimum_closed_form(2, 3, 0.06, 0.7, 1.0, 0.25)), 4)  # 2 + sqrt(3.765/3.1275)
    3.0972

    References
    ----------
    .. [1] Seed paper 004_971077b94d8d4426.txt, an OCR of a Russian journal paper on multi-row planetary gears (title,
       authors, journal and year not recoverable; its ref. [1]: F. I. Plekhanov, «Зубчатые планетарные передачи»); its
       optimum-ratio claim i = 3.5 (not reproduced); docs/spec/rows.md §6.
    """
    n, b, t = rows, cheek_ratio, wall_ratio
    L_h = b * (n + 1) + n + 0.25
    L_a = b * (n - 1) + n
    A = 8 * t * L_h + planet_fill * n * planets_per_row / 4.0 + b * (n + 1) / 4.0
    C0 = 8 * t * L_h + sun_fill * L_a + b * (n + 1)
    return 2.0 + np.sqrt(C0 / A)


@dataclass(frozen=True)
class Mass:
    """The relative mass at the ratio used and the optimum ratio (rows.md §6, §13.8); floats or arrays."""

    ratio: object
    """i at which M is reported: the given ratio, else ratio_opt"""
    relative_mass: object
    """M(i) [kg/(kN·m)]"""
    ratio_opt: object
    ratio_opt_err: object
    """max(half the final bracket, 3 sqrt(eps) ratio_opt)"""
    ratio_opt_on_bound: object
    relative_mass_min: object
    """M(ratio_opt) [kg/(kN·m)]"""


def mass_and_optimum(ratio, ratio_range, rtol, **params) -> Mass:
    r"""M at the given ratio and the ratio that minimises M, by golden section to ``rtol``.

    .. math:: i_{opt} = \arg\min_{i_{lo} \le i \le i_{hi}} M(i)

    K (``unevenness``) is held constant during the search; the search never assumes the paper's i = 3.5.

    Parameters
    ----------
    ratio : float or array_like or None
        Ratio i, [-], or None to report M at the optimum.
    ratio_range : tuple of (float or array_like)
        (i_lo, i_hi), [-].
    rtol : float
        Relative accuracy of the optimum ratio, [-].
    **params
        The keyword arguments of :func:`relative_mass` after ``ratio``.

    Returns
    -------
    mass : Mass
        The ratio used, M there [kg/(kN·m)], the optimum ratio, its error and whether it lies on a bound, and M there.

    Examples
    --------
    >>> m = mass_and_optimum(None, (2.2, 12.0), 1e-9, rows=2, planets_per_row=3)
    >>> abs(float(m.ratio_opt) - float(mass_optimum_closed_form(2, 3, 0.06, 0.7, 1.0, 0.25))) <= float(m.ratio_opt_err)
    True

    References
    ----------
    .. [1] Seed paper 004_971077b94d8d4426.txt, an OCR of a Russian journal paper on multi-row planetary gears (title,
       authors, journal and year not recoverable; its ref. [1]: F. I. Plekhanov, «Зубчатые планетарные передачи»); its
       relative-mass formula and optimum ratio; docs/spec/rows.md §6, §13.8.
    """
    lo, hi = ratio_range
    opt = minimize_golden(lambda i: relative_mass(i, **params), lo, hi, rtol=rtol)
    used = opt.x if ratio is None else ratio
    return Mass(used, relative_mass(used, **params), opt.x, opt.err, opt.on_bound, opt.fun)
