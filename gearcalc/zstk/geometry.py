"""Geometry of the ZSTK (spec zstk.md §3.1): roller radius, centre distance, normals, reduced radii.

Pure functions over floats and numpy arrays (units mm, radians).  Frame: O_H = (0, 0), O_B = (e, 0);
+x points to the narrowest point of the annular gap (theta = 0); angles grow counter-clockwise.

References
----------
The seed paper by Merko et al. (seed 003), cited in full in :mod:`gearcalc.zstk`; docs/spec/zstk.md.
"""
from __future__ import annotations

__all__ = ['SCHEME_PARITY', 'INTEGER_TOL', 'broadcast', 'take', 'single', 'wrap_angle', 'remainder_360',
           'roller_radius', 'extreme_roller_radii', 'centre_distance', 'normal_angle_offset', 'reduced_radii']

import numpy as np


SCHEME_PARITY = {"A": 0, "B": 1, "C": 1, "D": 0}
"""N mod 2 of each symmetric scheme (spec §4.2)."""
INTEGER_TOL = 1e-9
"""|N* - round(N*)| below this makes N* an integer (spec §11.5)."""

# ----------------------------------------------------------------------------- helpers
def broadcast(a, shape):
    """``np.broadcast_to`` that returns an array already of the shape unchanged (cheap on hot paths).

    >>> broadcast(2.0, (3,)).tolist()
    [2.0, 2.0, 2.0]
    """
    a = np.asarray(a)
    return a if a.shape == shape else np.broadcast_to(a, shape)


def take(obj, idx):
    """A dataclass of arrays over designs (Chain, Materials) restricted to the designs ``idx``.

    >>> from gearcalc.zstk import close_chains
    >>> take(close_chains(np.array([100.0, 90.0]), 50.0, 6.0, 6.0, np.array([8, 8])), [1]).outer_radius.shape
    (1,)
    """
    import dataclasses

    return type(obj)(*(np.asarray(getattr(obj, f.name))[idx] for f in dataclasses.fields(obj)))


def single(obj):
    """A dataclass of arrays of shape (1,) (Chain, Materials) as one design with Python scalars.

    >>> from gearcalc.zstk import close_chains
    >>> single(close_chains(np.array([100.0]), 50.0, 6.0, 6.0, np.array([8]))).n
    8
    """
    import dataclasses

    vals = []
    for f in dataclasses.fields(obj):
        v = np.asarray(getattr(obj, f.name)).reshape(-1)[0]
        vals.append(v.item() if hasattr(v, "item") else v)
    return type(obj)(*vals)


def remainder_360(x):
    """math.remainder(x, 360) element-wise, exactly: x - 360 k, k the integer nearest to x/360 (ties even) [deg].

    >>> remainder_360(np.array([540.0, -190.0, 90.0])).tolist()
    [-180.0, 170.0, 90.0]
    >>> import math
    >>> remainder_360(np.array([1.3266152821258527e+39, 1e300, 900.0])).tolist() == [
    ...     math.remainder(v, 360.0) for v in (1.3266152821258527e+39, 1e300, 900.0)]
    True
    """
    x = np.fmod(x, 720.0)  # exact for any float, and keeps the parity of the ties: |x| < 720 below
    r = x - 360.0 * np.round(x / 360.0)  # exact: |r| <= 180 and 360 k is a multiple of 8
    r = np.where(r > 180.0, r - 360.0, r)  # x/360 rounded onto a tie: the nearest k is the other one
    return np.where(r < -180.0, r + 360.0, r)


def wrap_angle(angle):
    """Angle wrapped to (-pi, pi] [rad].

    >>> float(wrap_angle(np.pi)), float(wrap_angle(-np.pi)), round(float(wrap_angle(3 * np.pi / 2)), 12)
    (3.141592653589793, 3.141592653589793, -1.570796326795)
    """
    return np.pi - np.mod(np.pi - np.asarray(angle, dtype=float), 2.0 * np.pi)


# ----------------------------------------------------------------------------- §3.1 geometry
def roller_radius(theta, outer_radius, inner_radius, eccentricity):
    """Radius of the roller tangent to both raceways whose centre lies at polar angle theta.

    .. math:: r(\\theta) = \\frac{(D - e)(S - e) + 4 R_H e \\sin^2(\\theta/2)}{2[(S - e) + 2 e \\sin^2(\\theta/2)]},
              \\quad S = R_H + R_B,\\ D = R_H - R_B

    r(theta) = [(D - e)(S - e) + 4 R_H e sin²(theta/2)] / [2((S - e) + 2 e sin²(theta/2))],
    with S = R_H + R_B and D = R_H - R_B; every term is non-negative (no cancellation).

    Parameters
    ----------
    theta : polar angle of the roller centre about O_H, from the narrowest point [rad].
    outer_radius, inner_radius : R_H, R_B [mm].
    eccentricity : e [mm].

    Returns
    -------
    r [mm]; r(0) = (D - e)/2 and r(pi) = (D + e)/2.

    Examples
    --------
    >>> float(roller_radius(0.0, 100.0, 50.0, 6.0)), float(roller_radius(np.pi, 100.0, 50.0, 6.0))
    (22.0, 28.0)

    References
    ----------
    derived (the paper gives r_i only as data); docs/spec/zstk.md §3.1 (centre locus: the ellipse with foci O_H, O_B
    and major axis S).
    """
    s, d = outer_radius + inner_radius, outer_radius - inner_radius
    h2 = np.sin(0.5 * np.asarray(theta, dtype=float)) ** 2
    e = eccentricity
    return ((d - e) * (s - e) + 4.0 * outer_radius * e * h2) / (2.0 * ((s - e) + 2.0 * e * h2))


def extreme_roller_radii(outer_radius, inner_radius, eccentricity):
    """The smallest and the largest roller radius, at the narrowest and the widest point of the gap.

    .. math:: r_{min} = r(0) = \\frac{R_H - R_B - e}{2}, \\qquad r_{max} = r(\\pi) = \\frac{R_H - R_B + e}{2}

    Parameters
    ----------
    outer_radius, inner_radius : float or array_like
        R_H, R_B [mm].
    eccentricity : float or array_like
        e [mm].

    Returns
    -------
    (r_min, r_max) [mm]; r_min <= 0 when e >= R_H - R_B (no valid mechanism).

    Examples
    --------
    >>> extreme_roller_radii(100.0, 50.0, 6.0) == (roller_radius(0.0, 100.0, 50.0, 6.0), 28.0)
    True

    References
    ----------
    docs/spec/zstk.md §3.1 (the extremes of r(theta)), §3.3 (e < R_H - R_B; |s| < r_min).
    """
    return (outer_radius - inner_radius - eccentricity) / 2, (outer_radius - inner_radius + eccentricity) / 2


def centre_distance(theta, outer_radius, inner_radius, eccentricity):
    """Distance h = |O_H P| of the roller centre from the outer-ring centre.

    .. math:: h(\\theta) = \\frac{S^2 - e^2}{2 (S - e \\cos\\theta)} = R_H - r(\\theta)

    h(theta) = (S² - e²) / (2 (S - e cos theta)) = R_H - r(theta).

    Parameters
    ----------
    theta [rad]; outer_radius, inner_radius, eccentricity [mm].

    Returns
    -------
    h [mm]

    Examples
    --------
    >>> float(centre_distance(0.0, 100.0, 50.0, 6.0))
    78.0

    References
    ----------
    derived; docs/spec/zstk.md §3.1.
    """
    s, e = outer_radius + inner_radius, eccentricity
    return (s - e) * (s + e) / (2.0 * (s - e * np.cos(theta)))


def normal_angle_offset(theta, outer_radius, inner_radius, eccentricity):
    """Signed angle beta_s from the outer normal n_H to the inner normal n_B (counter-clockwise).

    .. math:: \\beta_s = \\operatorname{atan2}(e \\sin\\theta,\\ h - e \\cos\\theta), \\quad \\sin\\beta = e
              |\\sin\\theta| / (R_B + r)

    beta_s = atan2(e sin theta, h - e cos theta); |beta_s| = beta = angle O_B P O_H, and the
    polar angle of n_B = (P - O_B)/|P - O_B| is theta + beta_s.

    Parameters
    ----------
    theta [rad]; outer_radius, inner_radius, eccentricity [mm].

    Returns
    -------
    beta_s [rad], in (-pi/2, pi/2) for a valid design (e < S/sqrt 2).

    Examples
    --------
    >>> float(normal_angle_offset(0.0, 100.0, 50.0, 6.0)), float(normal_angle_offset(np.pi, 100.0, 50.0, 0.0))
    (0.0, 0.0)

    References
    ----------
    derived; docs/spec/zstk.md §3.1 (the angle beta_i of the paper's load transfer F_iH = F_iB cos beta_i, §5).
    """
    h = centre_distance(theta, outer_radius, inner_radius, eccentricity)
    return np.arctan2(eccentricity * np.sin(theta), h - eccentricity * np.cos(theta))


def reduced_radii(roller_r, centre_dist, inner_radius, outer_radius):
    """Reduced radii of the inner and outer contact of each roller (the paper's eqs. 4, 5).

    .. math:: \\rho_B = \\frac{r R_B}{R_B + r}, \\qquad \\rho_H = \\frac{r R_H}{R_H - r} = \\frac{r R_H}{h}

    rho_B = r R_B/(R_B + r) (convex on convex);  rho_H = r R_H/(R_H - r) = r R_H/h (convex in
    concave), formed with h so that no R_H - r is subtracted.

    Parameters
    ----------
    roller_r : r [mm]; centre_dist : h = R_H - r [mm]; inner_radius, outer_radius : R_B, R_H [mm].

    Returns
    -------
    (rho_B, rho_H) [mm]

    Examples
    --------
    >>> [round(float(x), 6) for x in reduced_radii(22.0, 78.0, 50.0, 100.0)]
    [15.277778, 28.205128]

    References
    ----------
    Merko M.A. et al., «Анализ нормальных напряжений на площадках контакта звеньев механизмов с ЗСТК ...» (seed
    003_2d1da402cb0b8488.txt; no journal given; see :mod:`gearcalc.zstk`), eqs. (4) and (5); docs/spec/zstk.md §2.
    """
    return (roller_r * inner_radius / (inner_radius + roller_r),
            roller_r * outer_radius / centre_dist)


