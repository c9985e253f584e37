"""Hertz line contact of two parallel cylinders (convex-convex or convex-concave).

Shared physics for every calculator with roller/pin contacts (``zstk`` now, the ``pins``
contact level later).  All functions are plain numpy expressions: they take floats or arrays
(broadcast against each other) and return the same.  Units: N, mm, MPa (= N/mm²).

Conventions
-----------
* A *signed* radius is positive for a convex surface and negative for a concave one (a roller
  inside a ring raceway has the raceway radius negative).
* ``reduced_radius`` R of the pair: 1/R = 1/R1 + 1/R2.
* ``contact_modulus`` E*: 1/E* = (1 - nu1²)/E1 + (1 - nu2²)/E2 (Johnson's E*, not E' = 2E*).

References
----------
K. L. Johnson, *Contact Mechanics*, Cambridge University Press, 1985, §4.2 (eqs. 4.43-4.45)
and §2.8 (subsurface stresses of a line contact).
"""
from __future__ import annotations

import numpy as np

TAU_MAX_RATIO = 0.30028310600077
"""Maximum subsurface (principal) shear stress of a line contact over its peak pressure.

Maximum over depth z of tau_1/p0 = t - t²/sqrt(1 + t²), t = z/b, on the axis of the contact
(Johnson 1985, §2.8, eq. 2.25 with the frictionless Hertz pressure); Johnson quotes 0.30.
"""
TAU_MAX_DEPTH_RATIO = 0.7861513777574233
"""Depth of the maximum subsurface (principal) shear below the centre of a line contact, over b: the exact
sqrt((sqrt(5) - 1)/2) = 0.786151377757423 (d tau_1/dt = 0 gives t^4 + t^2 = 1; then tau_1/p0 = t^5)."""
TRESCA_POISSON_CROSSOVER = 0.2422701946728895
"""Poisson's ratio below which the out-of-plane shear (sigma_z - sigma_y)/2 of a plane-strain line contact
exceeds the in-plane principal shear tau_1 (root of (1 - u) sqrt(1 - u^2)/2 = t^5, u(1 + u) = 2 nu)."""

ISO_ROLLER_CONSTANT = 35948.0
"""ISO/TS 16281 roller-raceway constant [N/mm^(10/9)]: Q = 35948 L^(8/9) delta^(10/9) for a steel roller's
two contacts in series (N, mm); the single-contact form multiplies it by 2^(10/9) (pins.md §5.4, zstk.md §5)."""
LINE_LOAD_EXPONENT = 10.0 / 9.0
"""Exponent of the line-contact load-deflection law F = c delta^(10/9)."""


def iso_roller_stiffness(length):
    r"""Load-deflection constant of a steel roller's two line contacts in series (ISO/TS 16281).

    .. math:: c_L = 35948\, l^{8/9} \quad [N/mm^{10/9}], \qquad Q = c_L \delta^{10/9}

    Parameters
    ----------
    length : float or array_like
        Roller working length l, [mm].

    Returns
    -------
    c_L : float or ndarray
        Load-deflection constant, [N/mm^(10/9)].

    Examples
    --------
    >>> round(float(iso_roller_stiffness(1.0)))
    35948

    References
    ----------
    .. [1] ISO/TS 16281:2008, Rolling bearings - Methods for calculating the modified reference rating life for
       universally loaded bearings, ISO, Geneva, 2008; docs/spec/zstk.md §5 item 4.
    """
    return ISO_ROLLER_CONSTANT * length ** (8.0 / 9.0)


def iso_contact_stiffness(face_width):
    r"""Load-deflection constant of one steel line contact (ISO/TS 16281 roller constant for one contact).

    .. math:: c = 35948 \cdot 2^{10/9}\, b^{8/9} \quad [N/mm^{10/9}], \qquad F = c\,\delta^{10/9}

    Parameters
    ----------
    face_width : float or array_like
        Contact length b, [mm].

    Returns
    -------
    c : float or ndarray
        Load-deflection constant, [N/mm^(10/9)].

    Examples
    --------
    >>> round(float(iso_contact_stiffness(1.0)))     # pins.md §5.4: about 7.77e4 b^(8/9)
    77652

    References
    ----------
    .. [1] ISO/TS 16281:2008, Rolling bearings - Methods for calculating the modified reference rating life for
       universally loaded bearings, ISO, Geneva, 2008 (the roller constant); docs/spec/pins.md §5.4.
    """
    return ISO_ROLLER_CONSTANT * 2.0 ** LINE_LOAD_EXPONENT * face_width ** (8.0 / 9.0)


def line_pressure_constant(poisson):
    r"""The Hertz line-contact pressure constant for two bodies of one material [-].

    .. math:: C_H = \left(2\pi(1-\nu^2)\right)^{-1/2}, \qquad p_0 = C_H \sqrt{F E / (b \rho)}

    0.418 for nu = 0.3 (the constant of the seed paper 004's mass formula).

    Parameters
    ----------
    poisson : float or array_like
        Poisson's ratio nu, [-].

    Returns
    -------
    C_H : ndarray
        Pressure constant, [-].

    Examples
    --------
    >>> round(float(line_pressure_constant(0.3)), 3)
    0.418

    References
    ----------
    .. [1] K. L. Johnson, Contact Mechanics, Cambridge University Press, 1985, §4.2 (eq. 4.45 with
       E* = E/(2(1 - nu^2))); docs/spec/rows.md §6, §13.9.
    """
    return (2.0 * np.pi * (1.0 - np.asarray(poisson, float) ** 2)) ** -0.5


def contact_modulus(e1, nu1, e2, nu2):
    r"""Contact modulus E* of two elastic bodies [MPa].

    .. math:: \frac{1}{E^*} = \frac{1 - \nu_1^2}{E_1} + \frac{1 - \nu_2^2}{E_2}

    Parameters
    ----------
    e1, e2 : float or array_like
        Young's moduli of body 1 and body 2, [MPa].
    nu1, nu2 : float or array_like
        Poisson's ratios, [-].

    Returns
    -------
    E_star : float or ndarray
        Contact modulus, [MPa].

    Examples
    --------
    >>> round(float(contact_modulus(2.1e5, 0.3, 2.1e5, 0.3)), 3)
    115384.615

    References
    ----------
    .. [1] K. L. Johnson, Contact Mechanics, Cambridge University Press, 1985, §4.2 (eq. 4.23).
    """
    return 1.0 / ((1.0 - nu1 * nu1) / e1 + (1.0 - nu2 * nu2) / e2)


def paired_modulus(e1, nu1, e2, nu2):
    r"""The paper's material group, which equals E* [MPa].

    .. math:: \frac{E_1 E_2}{E_1 (1 - \nu_2^2) + E_2 (1 - \nu_1^2)} = E^*

    Written as in Merko et al., eq. (3)/(7), each modulus multiplying the *other* body's
    (1 - nu²).  Identical to :func:`contact_modulus` (kept to show and test the identity).

    Parameters
    ----------
    e1, e2 : float or array_like
        Young's moduli, [MPa].
    nu1, nu2 : float or array_like
        Poisson's ratios, [-].

    Returns
    -------
    group : float or ndarray
        The material group, [MPa].

    Examples
    --------
    >>> a, b = paired_modulus(2.1e5, 0.3, 1.1e5, 0.25), contact_modulus(2.1e5, 0.3, 1.1e5, 0.25)
    >>> bool(abs(a - b) <= 1e-12 * b)
    True

    References
    ----------
    .. [1] M. A. Merko, M. V. Mesnyankin, A. V. Kolotov, A. E. Mityaev, M. V. Savitskaya, A. M. Merko, S. A. Yurov,
       «Анализ нормальных напряжений на площадках контакта звеньев механизмов с ЗСТК при ведущем внутреннем кольце и
       вводе поправки по радиусу дорожки качения наружного кольца», Siberian Federal University, UDC 621.838.2 (seed
       file 003_2d1da402cb0b8488.txt; no journal or year given); eqs. (3), (7); docs/spec/zstk.md §2.
    """
    return e1 * e2 / (e1 * (1.0 - nu2 * nu2) + e2 * (1.0 - nu1 * nu1))


def stress_coefficient(e1, nu1, e2, nu2):
    r"""The paper's coefficient k, so that sigma = k sqrt(F/(l rho)) [sqrt(MPa)].

    .. math:: k = \sqrt{\frac{E^*}{\pi}} = \sqrt{\frac{E_1 E_2}{\pi\,[E_1 (1 - \nu_2^2) + E_2 (1 - \nu_1^2)]}}

    Parameters
    ----------
    e1, e2 : float or array_like
        Young's moduli, [MPa].
    nu1, nu2 : float or array_like
        Poisson's ratios, [-].

    Returns
    -------
    k : ndarray
        Stress coefficient, [sqrt(MPa)].

    Examples
    --------
    >>> round(float(stress_coefficient(2.1e5, 0.3, 2.1e5, 0.3)), 3)
    191.646

    References
    ----------
    .. [1] M. A. Merko, M. V. Mesnyankin, A. V. Kolotov, A. E. Mityaev, M. V. Savitskaya, A. M. Merko, S. A. Yurov,
       «Анализ нормальных напряжений на площадках контакта звеньев механизмов с ЗСТК при ведущем внутреннем кольце и
       вводе поправки по радиусу дорожки качения наружного кольца», Siberian Federal University, UDC 621.838.2 (seed
       file 003_2d1da402cb0b8488.txt; no journal or year given); eq. (7); docs/spec/zstk.md §2.
    """
    return np.sqrt(paired_modulus(e1, nu1, e2, nu2) / np.pi)


def reduced_radius(radius1, radius2):
    r"""Reduced radius of curvature R of two parallel cylinders [mm].

    .. math:: \frac{1}{R} = \frac{1}{R_1} + \frac{1}{R_2}, \qquad R = \frac{R_1 R_2}{R_1 + R_2}

    Use a negative radius for a concave surface.  For a roller r in a ring of radius R_H the
    result r R_H/(R_H - r) loses accuracy when the contact is nearly conformal; a caller that
    knows R_H - r exactly should form the ratio itself (see :func:`gearcalc.zstk.reduced_radii`).

    Parameters
    ----------
    radius1, radius2 : float or array_like
        Signed radii, [mm] (> 0 convex, < 0 concave).

    Returns
    -------
    R : float or ndarray
        Reduced radius, [mm].

    Examples
    --------
    >>> float(reduced_radius(10.0, 50.0)), float(reduced_radius(10.0, -50.0))
    (8.333333333333334, 12.5)

    References
    ----------
    .. [1] K. L. Johnson, Contact Mechanics, Cambridge University Press, 1985, §4.2 (two cylinders' relative curvature).
    """
    return radius1 * radius2 / (radius1 + radius2)


def peak_pressure(force, length, radius, e_star):
    r"""Hertz peak pressure p0 of a line contact [MPa].

    .. math:: p_0 = \sqrt{\frac{P' E^*}{\pi R}}, \qquad P' = \frac{F}{l}

    Equal to the paper's sigma of eq. (3) with E* from eq. (7).

    Parameters
    ----------
    force : float or array_like
        Normal force F (>= 0), [N].
    length : float or array_like
        Contact length l, [mm].
    radius : float or array_like
        Reduced radius R, [mm].
    e_star : float or array_like
        Contact modulus E*, [MPa].

    Returns
    -------
    p0 : ndarray
        Peak pressure, [MPa].

    Examples
    --------
    >>> round(float(peak_pressure(1000.0, 10.0, 5.0, 115384.6153846154)), 3)
    857.066

    References
    ----------
    .. [1] K. L. Johnson, Contact Mechanics, Cambridge University Press, 1985, §4.2 (eq. 4.45).
    .. [2] M. A. Merko, M. V. Mesnyankin, A. V. Kolotov, A. E. Mityaev, M. V. Savitskaya, A. M. Merko, S. A. Yurov,
       «Анализ нормальных напряжений на площадках контакта звеньев механизмов с ЗСТК при ведущем внутреннем кольце и
       вводе поправки по радиусу дорожки качения наружного кольца», Siberian Federal University, UDC 621.838.2 (seed
       file 003_2d1da402cb0b8488.txt; no journal or year given); eqs. (3), (6), (7).
    """
    return np.sqrt(force * e_star / (np.pi * length * radius))


def semi_width(force, length, radius, e_star):
    r"""Semi-width b of a Hertz line contact [mm].

    .. math:: b = \sqrt{\frac{4 P' R}{\pi E^*}} = \frac{2 P'}{\pi p_0}, \qquad P' = \frac{F}{l}

    Parameters
    ----------
    force : float or array_like
        Normal force F, [N].
    length : float or array_like
        Contact length l, [mm].
    radius : float or array_like
        Reduced radius R, [mm].
    e_star : float or array_like
        Contact modulus E*, [MPa].

    Returns
    -------
    b : ndarray
        Semi-width, [mm].

    Examples
    --------
    >>> round(float(semi_width(1000.0, 10.0, 5.0, 115384.6153846154)), 6)
    0.074279

    References
    ----------
    .. [1] K. L. Johnson, Contact Mechanics, Cambridge University Press, 1985, §4.2 (eq. 4.43).
    """
    return np.sqrt(4.0 * force * radius / (np.pi * length * e_star))


def max_subsurface_shear(p0):
    r"""Maximum subsurface principal shear stress of a line contact [MPa].

    .. math:: \tau_{max} = 0.30028\,p_0 \quad \text{at depth } z = 0.78615\,b

    (:data:`TAU_MAX_RATIO`, :data:`TAU_MAX_DEPTH_RATIO`).

    Parameters
    ----------
    p0 : float or array_like
        Peak pressure, [MPa].

    Returns
    -------
    tau_max : float or ndarray
        Maximum principal shear, [MPa].

    Examples
    --------
    >>> round(float(max_subsurface_shear(1000.0)), 1)
    300.3

    References
    ----------
    .. [1] K. L. Johnson, Contact Mechanics, Cambridge University Press, 1985, §2.8 and Fig. 4.6
       (tau_1 = 0.30 p0 at z = 0.78 b).
    """
    return TAU_MAX_RATIO * p0


def tresca_shear_ratio(poisson):
    r"""Maximum (Tresca) shear stress of a plane-strain line contact over p0, and its depth over b.

    Along the axis of the contact (Johnson 1985, eqs. 4.47-4.48, t = z/b, s = sqrt(1 + t²)) the
    principal stresses are sigma_z = -p0/s, sigma_x = -p0((1 + 2t²)/s - 2t) and, in plane strain,
    sigma_y = nu(sigma_x + sigma_z); sigma_z is the most compressive.  The largest shear is the larger
    of two maxima over depth:

    .. math:: \tau_1 = \tfrac12(\sigma_x - \sigma_z) = p_0 (t - t^2/s): \quad \max = t_1^5\,p_0 = 0.30028\,p_0
              \text{ at } t_1 = \sqrt{(\sqrt5 - 1)/2} = 0.78615

    .. math:: \tau_y = \tfrac12(\sigma_y - \sigma_z) = \tfrac{p_0}2 (1/s - 2\nu(s - t)): \quad
              \max = \tfrac12 (1 - u)\sqrt{1 - u^2}\,p_0 \text{ at } t = u/\sqrt{1 - u^2},\;
              u = \tfrac12(\sqrt{1 + 8\nu} - 1)

    (d tau_y/dt = 0 with u = t/s gives u(1 + u) = 2 nu).  tau_y governs for nu <
    :data:`TRESCA_POISSON_CROSSOVER` = 0.24227: 0.330 p0 at nu = 0.2, 0.408 p0 at 0.1; above it the
    result is :data:`TAU_MAX_RATIO` and :data:`TAU_MAX_DEPTH_RATIO` exactly.

    Parameters
    ----------
    poisson : float or array_like
        Poisson's ratio nu of the body in which the stress is wanted [-], 0 <= nu < 0.5.

    Returns
    -------
    (tau_max/p0 [-], depth/b [-]), arrays of the shape of ``poisson``.

    Examples
    --------
    >>> [round(float(x), 4) for x in tresca_shear_ratio(0.2)]
    [0.3302, 0.3217]
    >>> [float(x) for x in tresca_shear_ratio(0.3)] == [TAU_MAX_RATIO, TAU_MAX_DEPTH_RATIO]
    True

    References
    ----------
    K. L. Johnson, Contact Mechanics, 1985, §2.8 (stresses along the axis, eq. 2.25) and §4.2 (plane strain
    sigma_y = nu(sigma_x + sigma_z)); zstk.md §2.
    """
    nu = np.asarray(poisson, dtype=float)
    u = 0.5 * (np.sqrt(1.0 + 8.0 * nu) - 1.0)
    root = np.sqrt(1.0 - u * u)
    tau_y = 0.5 * (1.0 - u) * root
    out_of_plane = tau_y > TAU_MAX_RATIO
    return np.where(out_of_plane, tau_y, TAU_MAX_RATIO), np.where(out_of_plane, u / root, TAU_MAX_DEPTH_RATIO)
