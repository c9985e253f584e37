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
    """The paper's volume bracket {…} of the relative mass (rows.md §6), in units of π d_a² b_w / 4.

    ``8t(i-1)²[b̄(n+1)+n+0.25] + k_a[b̄(n-1)+n] + k_g n n_w (0.5i-1)² + b̄(n+1)(0.5i)²``

    Examples
    --------
    >>> float(mass_bracket(3.5, 2, 3, 0.06, 0.7, 1.0, 0.25))   # Fig. 5 set, n = 2, i = 3.5
    16.246875

    References
    ----------
    .. [1] Seed paper 004_971077b94d8d4426.txt (multi-row planetary gears; title, authors and journal not
       recoverable), its relative-mass formula (the bracket); gearcalc specification docs/spec/rows.md §6.
    """
    i = np.asarray(ratio, float)
    n, b = rows, cheek_ratio
    return (8.0 * wall_ratio * (i - 1.0) ** 2 * (b * (n + 1) + n + 0.25) + sun_fill * (b * (n - 1) + n)
            + planet_fill * n * planets_per_row * (0.5 * i - 1.0) ** 2 + b * (n + 1) * (0.5 * i) ** 2)


def relative_mass(ratio, rows, planets_per_row, wall_ratio=0.06, sun_fill=0.7, planet_fill=1.0, cheek_ratio=0.25,
                  allowable_contact=600.0, density=7800.0, youngs_modulus=2e5, poisson=0.3, efficiency=0.95,
                  unevenness=1.0, pressure_angle=math.radians(20.0)):
    """Relative mass M of the gear per output torque [kg/(kN·m)] (rows.md §6).

    ``M = 2π ρ K E {…} / [η (σ_HP/c_H)² n n_w (i-2) sin 2α_w] × 1e-3``, ``c_H = (2π(1-ν²))^(-1/2)``
    (the OCR'd prefactor with its missing cos α_w restored; ρ in kg/m³, E and σ_HP in MPa).

    Examples
    --------
    >>> round(float(relative_mass(3.5, 2, 3)), 3)   # bracket 16.246875 x prefactor 866.45 x 1e-3
    14.077

    References
    ----------
    .. [1] Seed paper 004_971077b94d8d4426.txt (multi-row planetary gears; title, authors and journal not
       recoverable), its relative-mass formula, prefactor rederived; K. L. Johnson, Contact Mechanics, 1985 (0.418);
       gearcalc specification docs/spec/rows.md §6, §13.9.
    """
    i = np.asarray(ratio, float)
    c_h = hertz.line_pressure_constant(poisson)
    pref = 2.0 * math.pi * density * unevenness * youngs_modulus / (
        efficiency * (allowable_contact / c_h) ** 2 * rows * planets_per_row * (i - 2.0) * np.sin(2.0 * pressure_angle))
    return 1e-3 * pref * mass_bracket(i, rows, planets_per_row, wall_ratio, sun_fill, planet_fill, cheek_ratio)


def mass_optimum_closed_form(rows, planets_per_row, wall_ratio, sun_fill, planet_fill, cheek_ratio):
    """Minimiser of M(i) for constant K: ``i* = 2 + sqrt(C₀/A)`` (rows.md §6, x = i - 2).

    Examples
    --------
    >>> round(float(mass_optimum_closed_form(2, 3, 0.06, 0.7, 1.0, 0.25)), 4)  # 2 + sqrt(3.765/3.1275)
    3.0972

    References
    ----------
    .. [1] Seed paper 004_971077b94d8d4426.txt (multi-row planetary gears; title, authors and journal not
       recoverable), its optimum-ratio claim i = 3.5 (not reproduced); gearcalc specification docs/spec/rows.md §6.
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
    """M at the given ratio and the ratio that minimises M, by golden section to ``rtol`` (rows.md §6).

    K (``unevenness``) is held constant during the search; the search never assumes the paper's i = 3.5.

    Parameters
    ----------
    ratio : i [-], or None to report M at the optimum
    ratio_range : (i_lo, i_hi), each a float or an array [-]
    rtol : relative accuracy of the optimum ratio
    **params : the keyword arguments of :func:`relative_mass` after ``ratio``

    Examples
    --------
    >>> m = mass_and_optimum(None, (2.2, 12.0), 1e-9, rows=2, planets_per_row=3)
    >>> abs(float(m.ratio_opt) - float(mass_optimum_closed_form(2, 3, 0.06, 0.7, 1.0, 0.25))) <= float(m.ratio_opt_err)
    True

    References
    ----------
    .. [1] Seed paper 004_971077b94d8d4426.txt (multi-row planetary gears; title, authors and journal not
       recoverable), its relative-mass formula and optimum ratio; gearcalc specification docs/spec/rows.md §6,
       §13.8.
    """
    lo, hi = ratio_range
    opt = minimize_golden(lambda i: relative_mass(i, **params), lo, hi, rtol=rtol)
    used = opt.x if ratio is None else ratio
    return Mass(used, relative_mass(used, **params), opt.x, opt.err, opt.on_bound, opt.fun)
