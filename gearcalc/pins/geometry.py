"""KHV pin gearing, level ``ideal``: the cycloidal satellite's geometry (pins.md §4.1-4.3).

The gear (:class:`Cycloid`), the rules its dimensions must satisfy (:func:`geometry_violations`), the
pitch distance and lever arm of a pin, the contact point, the crest cut-off psi* where the loaded arc
ends, the spin-reversal phase, the profile's curvature, the pin-centre curve and the tooth profile.
Pure functions over floats and numpy arrays; units mm, rad.

Conventions: crank speed omega_H > 0 (counter-clockwise); satellite (V) speed omega_V = -omega_H k/z1;
pin i sits at phi_i = 2 pi i/z2; its phase psi_i = phi_i - theta; sigma = +1 (reducer) or -1
(multiplier); load-side phase psi~ = (sigma psi) mod 2 pi.

References
----------
.. [1] The paper (Prudnikov, seed 000), cited in full in :mod:`gearcalc.pins`; docs/spec/pins.md §4.1-4.3.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np


__all__ = ["REDUCER", "MULTIPLIER", "Cycloid", "GeometryViolations", "geometry_violations", "s_factor",
           "pitch_distance", "lever_arm", "contact_point", "contact_angle_offset", "crest_cutoff", "crest_cutoffs",
           "spin_reversal_phase", "spin_reversal_phases", "curvature_radius", "min_curvature_radius",
           "pin_centre_curve", "tooth_profile", "PinMounting"]

REDUCER, MULTIPLIER = 1, -1
"""sigma: +1 reducer (H drives V), -1 multiplier (V drives H)."""


@dataclass(frozen=True)
class Cycloid:
    """A cycloidal KHV pin gear: z1 teeth, z2 pins on R_p, eccentricity e, pin radius R_b.

    ``one_minus_K1`` (1 - K1) is kept separately so that s(psi) stays free of cancellation when
    K1 -> 1.  Build with :meth:`from_pin_circle` or :meth:`from_curtate_ratio`.

    Examples
    --------
    >>> g = Cycloid.from_curtate_ratio(20, 22, 3.9, 0.75, 1.95)
    >>> round(g.R_p, 6), g.k, round(g.r_p1, 6)
    (57.2, 2, 39.0)
    """

    z1: int
    z2: int
    e: float
    R_p: float
    R_b: float
    one_minus_K1: float

    @classmethod
    def from_pin_circle(cls, z1, z2, e, R_p, R_b):
        """The gear from its pin circle radius R_p [mm], with 1 - K1 = (k R_p - e z2)/(k R_p)."""
        k = z2 - z1
        return cls(z1, z2, float(e), float(R_p), float(R_b), (k * R_p - e * z2) / (k * R_p))

    @classmethod
    def from_curtate_ratio(cls, z1, z2, e, K1, R_b):
        """The gear from its curtate ratio K1, with R_p = e z2/(k K1) [mm]."""
        k = z2 - z1
        return cls(z1, z2, float(e), e * z2 / (k * K1), float(R_b), 1.0 - K1)

    @property
    def k(self) -> int:
        """Tooth difference k = z2 - z1."""
        return self.z2 - self.z1

    @property
    def K1(self) -> float:
        """Curtate ratio K1 = e z2/(k R_p)."""
        return self.e * self.z2 / (self.k * self.R_p)

    @property
    def r_p1(self) -> float:
        """Satellite pitch radius e z1/k [mm]."""
        return self.e * self.z1 / self.k

    @property
    def r_p2(self) -> float:
        """Ring pitch radius e z2/k [mm]."""
        return self.e * self.z2 / self.k

    @property
    def ratio(self) -> float:
        """Speed ratio u = z1/k = |omega_H/omega_V|."""
        return self.z1 / self.k

    @property
    def period(self) -> float:
        """Integration period T_p = 2 pi/z2 of crank angle [rad]."""
        return 2.0 * math.pi / self.z2


@dataclass(frozen=True)
class GeometryViolations:
    """Which gears break a geometric rule of pins.md §4.2, §7, §9 (:func:`geometry_violations`).

    Boolean masks: teeth (z2 <= z1), overflow (R_p = e z2/(k K1) not finite), curtate (K1 >= 1 for a
    cycloid), overlap (R_b >= R_p sin(pi/z2)), axle (rotating pins with r >= R_b); and the pin circle
    R_p [mm], K1 [-] and the overlap limit R_p sin(pi/z2) [mm] they were decided on.
    """

    teeth: np.ndarray
    overflow: np.ndarray
    curtate: np.ndarray
    overlap: np.ndarray
    axle: np.ndarray
    pin_circle_radius: np.ndarray
    curtate_ratio: np.ndarray
    overlap_limit: np.ndarray

    def any(self) -> np.ndarray:
        """Masks of gears that break any rule."""
        return self.teeth | self.overflow | self.curtate | self.overlap | self.axle


class PinMounting(NamedTuple):
    """How the pins are held (pins.md §3, §7): fixed, or rotating bushings on axles of radius r.

    Attributes
    ----------
    axle_radius : float or array_like
        r [mm] (NaN: none given).
    rotating : bool or array_like of bool
        Rotating pins (bushings on axles).

    Examples
    --------
    >>> PinMounting(0.95, True).rotating
    True
    """

    axle_radius: object = np.nan
    rotating: object = False


FIXED_PINS = PinMounting()
"""Fixed pins without an axle (:class:`PinMounting`'s defaults)."""


def geometry_violations(z1, z2, eccentricity, pin_circle_radius, curtate_ratio, pin_radius,
                        mounting: PinMounting = FIXED_PINS, cycloidal=True) -> GeometryViolations:
    r"""The geometric validity rules of a pin gear, over arrays of gears (pins.md §4.2, §7, §9).

    .. math::

        k = z_2 - z_1 \ge 1,\quad K_1 = \frac{e z_2}{k R_p} < 1\ \text{(cycloid)},\quad
        R_b < R_p \sin\frac{\pi}{z_2},\quad r < R_b\ \text{(rotating pins)}

    One of R_p and K1 is given (the other NaN).  The one rule set of ``gearcalc check``, of a computed
    design and of a vectorised sweep.  The admissibility of the ideal level (psi* beyond the pin pitch,
    no undercut) is :func:`admissibility`.

    Parameters
    ----------
    z1, z2 : int or array_like of int
        teeth of the satellite, pins of the ring.
    eccentricity : float or array_like
        e [mm].
    pin_circle_radius : float or array_like
        R_p [mm], NaN where K1 is given.
    curtate_ratio : float or array_like
        K1 [-], NaN where R_p is given.
    pin_radius : float or array_like
        R_b [mm].
    mounting : PinMounting
        the pins' axle radius r [mm] (NaN: none) and whether they rotate (bushings on axles); fixed pins by default.
    cycloidal : bool or array_like of bool
        cycloidal satellite profile (K1 < 1 applies to it only).

    Returns
    -------
    GeometryViolations
        masks of shape (n,).

    Examples
    --------
    >>> v = geometry_violations([21, 21, 22], [22, 22, 22], 3.9, np.nan, [0.75, 1.2, 0.75], 1.95)
    >>> v.teeth.tolist(), v.curtate.tolist(), v.any().tolist()
    ([False, False, True], [False, True, False], [False, True, True])

    References
    ----------
    .. [1] Prudnikov (seed 000), cited in full in :mod:`gearcalc.pins`; pins.md §4.2, §7, §9.
    """
    z1 = np.atleast_1d(np.asarray(z1, dtype=np.int64))
    z2 = np.atleast_1d(np.asarray(z2, dtype=np.int64))
    e, Rb, r = (np.atleast_1d(np.asarray(x, dtype=float)) for x in (eccentricity, pin_radius,
                                                                     mounting.axle_radius))
    K1g, Rpg = (np.atleast_1d(np.asarray(x, dtype=float)) for x in (curtate_ratio, pin_circle_radius))
    with np.errstate(all="ignore"):
        k = z2 - z1
        useK = ~np.isnan(K1g)
        Rp = np.where(useK, e * z2 / (k * np.where(useK, K1g, 1.0)), Rpg)
        K1 = np.where(useK, K1g, e * z2 / (k * Rp))
        zs, inv = np.unique(z2, return_inverse=True)
        sines = np.array([math.sin(math.pi / int(z)) if z > 0 else math.nan for z in zs])
        limit = Rp * sines[inv.reshape(-1)]
        return GeometryViolations(
            teeth=z2 <= z1, overflow=useK & ~np.isfinite(Rp), curtate=np.asarray(cycloidal) & (K1 >= 1.0),
            overlap=Rb >= limit, axle=np.asarray(mounting.rotating) & (r >= Rb), pin_circle_radius=Rp,
            curtate_ratio=K1, overlap_limit=limit)


def s_factor(psi, K1, one_minus_K1):
    r"""s(psi) = sqrt((1 - K1)^2 + 4 K1 sin^2(psi/2)) = |A - P|/R_p, cancellation-free (pins.md §4.2).

    Parameters
    ----------
    psi : pin phase [rad].
    K1 : curtate ratio [-].
    one_minus_K1 : 1 - K1, given separately [-].

    .. math:: s(\psi) = \sqrt{(1 - K_1)^2 + 4 K_1 \sin^2(\psi/2)} = \sqrt{1 + K_1^2 - 2 K_1 \cos\psi}
        = \frac{|A - P|}{R_p}

    Returns
    -------
    s : ndarray
        The factor, [-].

    Examples
    --------
    >>> round(float(s_factor(np.pi, 0.75, 0.25)), 12)
    1.75

    References
    ----------
    .. [1] A. P. Prudnikov, «Потери мощности в контакте цевок и зубьев планетарной передачи типа K-H-V» (Power losses in
       pins and teeth contact area of KHV-type planetary gearing), Машиностроение (seed file 000_fe288dec6e7c72f0.txt);
       docs/spec/pins.md §4.2.
    """
    sh = np.sin(0.5 * np.asarray(psi, dtype=float))
    return np.sqrt(one_minus_K1 * one_minus_K1 + 4.0 * K1 * sh * sh)


def pitch_distance(psi, g: Cycloid):
    r"""rho(psi) = |A - P| = R_p s(psi): pin centre to pitch point [mm]  (pins.md §4.2).

    .. math:: \rho(\psi) = |A - P| = R_p\,s(\psi)

    Parameters
    ----------
    psi : float or array_like
        Pin phase, [rad].
    g : Cycloid
        The gear.

    Returns
    -------
    rho : ndarray
        Pin centre to pitch point, [mm].

    Examples
    --------
    >>> g = Cycloid.from_curtate_ratio(20, 22, 3.9, 0.75, 1.95)
    >>> round(float(pitch_distance(0.0, g)), 12)   # R_p (1 - K1)
    14.3

    References
    ----------
    .. [1] A. P. Prudnikov, «Потери мощности в контакте цевок и зубьев планетарной передачи типа K-H-V» (Power losses in
       pins and teeth contact area of KHV-type planetary gearing), Машиностроение (seed file 000_fe288dec6e7c72f0.txt);
       docs/spec/pins.md §4.2.
    """
    return g.R_p * s_factor(psi, g.K1, g.one_minus_K1)


def lever_arm(psi, g: Cycloid):
    r"""Signed lever arm of the normal through P about O1, l = r_p1 sin(psi)/s(psi) [mm]  (pins.md §4.4).

    .. math:: l = \frac{r_{p1} \sin\psi}{s(\psi)}

    Parameters
    ----------
    psi : float or array_like
        Pin phase, [rad].
    g : Cycloid
        The gear.

    Returns
    -------
    l : ndarray
        Signed lever arm, [mm].

    Examples
    --------
    >>> g = Cycloid.from_curtate_ratio(20, 22, 3.9, 0.75, 1.95)
    >>> round(float(lever_arm(np.pi / 2, g)), 9)   # 39 / sqrt(1 + 0.75^2)
    31.2

    References
    ----------
    .. [1] S. K. Malhotra, M. A. Parameswaran, Analysis of a cycloid speed reducer, Mechanism and Machine Theory
       18(6):491-499, 1983 (k = 1); docs/spec/pins.md §4.4 (general k, derived).
    """
    psi = np.asarray(psi, dtype=float)
    return g.r_p1 * np.sin(psi) / s_factor(psi, g.K1, g.one_minus_K1)


def contact_point(psi, g: Cycloid):
    r"""Contact point C = A - R_b (A - P)/rho in the crank frame (O1 = (e, 0), P = (r_p2, 0)) [mm].

    .. math:: C = A - R_b\,\frac{A - P}{\rho}, \qquad A = R_p\,(\cos\psi, \sin\psi), \quad P = (r_{p2}, 0)

    Parameters
    ----------
    psi : float or array_like
        Pin phase, [rad].
    g : Cycloid
        The gear.

    Returns
    -------
    (C_x, C_y) [mm].

    Examples
    --------
    >>> g = Cycloid.from_curtate_ratio(20, 22, 3.9, 0.75, 1.95)
    >>> [round(float(c), 9) for c in contact_point(np.pi, g)]
    [-55.25, 0.0]

    References
    ----------
    .. [1] A. P. Prudnikov, «Потери мощности в контакте цевок и зубьев планетарной передачи типа K-H-V» (Power losses in
       pins and teeth contact area of KHV-type planetary gearing), Машиностроение (seed file 000_fe288dec6e7c72f0.txt);
       docs/spec/pins.md §4.2.
    """
    psi = np.asarray(psi, dtype=float)
    rho = pitch_distance(psi, g)
    sh = np.sin(0.5 * psi)
    dx = g.R_p * (g.one_minus_K1 - 2.0 * sh * sh)       # R_p cos(psi) - r_p2, cancellation-free
    dy = g.R_p * np.sin(psi)
    return g.R_p * np.cos(psi) - g.R_b * dx / rho, dy - g.R_b * dy / rho


def contact_angle_offset(psi, g: Cycloid):
    r"""epsilon(psi): polar angle of the contact point on the satellite from its tooth-space axis [rad].

    epsilon = atan2(C_y, C_x - e) - (z2/z1) psi; a pin leaves its flank at epsilon = -pi/z1
    (pins.md §4.3).

    .. math:: \varepsilon(\psi) = \operatorname{atan2}(C_y,\ C_x - e) - \frac{z_2}{z_1}\,\psi

    Parameters
    ----------
    psi : float or array_like
        Pin phase, [rad].
    g : Cycloid
        The gear.

    Returns
    -------
    epsilon : ndarray
        Polar angle of the contact point from the tooth-space axis, [rad].

    Examples
    --------
    >>> g = Cycloid.from_curtate_ratio(21, 22, 3.9, 0.75, 1.95)   # k = 1: the crest is at psi = pi
    >>> abs(round(float(contact_angle_offset(np.pi, g)) + np.pi / 21, 12))
    0.0

    References
    ----------
    .. [1] A. P. Prudnikov, «Потери мощности в контакте цевок и зубьев планетарной передачи типа K-H-V» (Power losses in
       pins and teeth contact area of KHV-type planetary gearing), Машиностроение (seed file 000_fe288dec6e7c72f0.txt);
       docs/spec/pins.md §4.3.
    """
    cx, cy = contact_point(psi, g)
    return np.arctan2(cy, cx - g.e) - (g.z2 / g.z1) * np.asarray(psi, dtype=float)


def crest_cutoff(g: Cycloid) -> float:
    r"""End of the loaded arc psi* [rad]: pi for k = 1, else the first root of epsilon(psi) = -pi/z1.

    One gear of :func:`crest_cutoffs` (pins.md §4.3, §12.11).

    .. math:: \psi^* = \pi \ (k = 1), \qquad \varepsilon(\psi^*) = -\frac{\pi}{z_1} \ \text{(first root, } k \ge 2)

    Parameters
    ----------
    g : Cycloid
        The gear.

    Returns
    -------
    psi_star : float
        End of the loaded arc, [rad].

    Examples
    --------
    >>> g = Cycloid.from_curtate_ratio(20, 22, 3.9, 0.75, 1.95)
    >>> 0 < crest_cutoff(g) < np.pi
    True

    References
    ----------
    .. [1] A. P. Prudnikov, «Потери мощности в контакте цевок и зубьев планетарной передачи типа K-H-V» (Power losses in
       pins and teeth contact area of KHV-type planetary gearing), Машиностроение (seed file 000_fe288dec6e7c72f0.txt);
       docs/spec/pins.md §4.3, §12.11.
    """
    if g.k == 1:
        return math.pi
    return float(crest_cutoffs(as_arrays(g))[0])


def as_arrays(g: Cycloid) -> Cycloid:
    r"""The same gear with every field a one-element array (for the functions vectorised over gears).

    .. math:: \text{every field } v \mapsto \text{atleast\_1d}(v)

    Parameters
    ----------
    g : Cycloid
        A gear with scalar fields.

    Returns
    -------
    g1 : Cycloid
        The same gear, every field an array of shape (1,).

    Examples
    --------
    >>> as_arrays(Cycloid.from_curtate_ratio(20, 22, 3.9, 0.75, 1.95)).z2.tolist()
    [22]

    References
    ----------
    .. [1] docs/spec/pins.md §4.2 (the gear's fields).
    """
    return Cycloid(*(np.atleast_1d(v) for v in (g.z1, g.z2, g.e, g.R_p, g.R_b, g.one_minus_K1)))


_as_arrays = as_arrays          # its former name (issue 35 made it public): for code written against that one


def crest_cutoffs(g: Cycloid, n_scan: int = 512, n_refine: int = 128, stages: int = 2) -> np.ndarray:
    r"""psi* of many gears at once [rad]: pi where k = 1, else the first root of h = epsilon + pi/z1.

    h(psi) = epsilon(psi) + pi/z1 is positive at psi = 0 (epsilon(0) = 0).  It is scanned on
    ``n_scan`` points of (0, pi], and its first sign change located; the bracketing cell is scanned
    again on ``n_refine`` points, ``stages`` times (each scan keeps the *first* sign change, so a
    non-monotone epsilon cannot send the search to a later root, pins.md §12.11).  The root is then
    the inverse quadratic interpolation through the two ends of the last cell and the next scan
    point; the cell is pi/(n_scan n_refine^stages) = 3.7e-7 rad wide by default, so the
    interpolation error (of the order of the cube of the width times the ratio of the third to the
    first derivative of h) lies below the round-off of psi*.  Every scan is one vectorised
    evaluation over all the gears (h in the half-angle form of :func:`contact_angle_offset`, two
    sines per point); this costs 3 evaluations where the bracketed root finder of
    :mod:`gearcalc.roots` needs 5-8 iterations of about 40 array operations each, which dominated
    the ideal level's time per design.  The first scan's points (0, pi] and their trigonometry are the
    same for every gear and are computed once (:func:`_first_scan`; the same numbers).

    .. math:: h(\psi) = \varepsilon(\psi) + \frac{\pi}{z_1}, \qquad \psi^* = \min\{\psi \in (0, \pi] : h(\psi) \le 0\}
        \ (k \ge 2), \qquad \psi^* = \pi \ (k = 1)

    Parameters
    ----------
    g : gears whose fields are arrays of one shape (m,) (see :class:`Cycloid`).
    n_scan, n_refine, stages : scan points of the first and of the refining scans, and their number.

    Returns
    -------
    psi* [rad], shape (m,).

    Examples
    --------
    >>> g = Cycloid(np.array([20, 21]), np.array([22, 22]), np.array([3.9, 3.9]),
    ...             np.array([57.2, 114.4]), np.array([1.95, 1.95]), np.array([0.25, 0.25]))
    >>> r = crest_cutoffs(g)
    >>> bool(0 < r[0] < np.pi), bool(r[1] == np.pi)
    (True, True)

    References
    ----------
    pins.md §4.3 (the crest cut-off) and §12.11 (first sign change of a scan).
    """
    k = np.asarray(g.z2) - np.asarray(g.z1)
    out = np.full(k.shape, math.pi)
    rows = np.flatnonzero(k >= 2)
    if rows.size == 0:
        return out
    one = rows.size == 1           # one gear: Python floats (fewer and cheaper array operations)
    h, offset = _crest_offset_function(g, rows, one)
    if one:
        out[rows] = _first_root_of_scan(h, offset, n_scan, n_refine, stages)
        return out
    root, found = _first_roots_of_scans(h, offset, rows.size, n_scan, n_refine, stages)
    out[rows] = np.where(found, root, math.pi)
    return out


def _crest_offset_function(g: Cycloid, rows, one: bool):
    """(h, pi/z1): h(psi, trig=None) = epsilon(psi) + pi/z1 of the gears ``rows`` (:func:`crest_cutoffs`).

    ``one``: a single gear, its fields as Python floats; else columns (m, 1) against psi (m, n).
    """
    def col(v):
        v = np.asarray(v)[rows]
        return float(v[0]) if one else v[:, None]

    z1, z2, e, R_p, R_b, omk = (col(v) for v in (g.z1, g.z2, g.e, g.R_p, g.R_b, g.one_minus_K1))
    A, B = omk * omk, 4.0 * (e * z2 / ((z2 - z1) * R_p))      # (1 - K1)^2 and 4 K1 (K1 as Cycloid.K1)
    q0, e0, zr, offset = R_b / R_p, e / R_p, z2 / z1, math.pi / z1

    def h(psi, trig=None):
        """epsilon(psi) + pi/z1 in half-angle form (contact_angle_offset scaled by 1/R_p; two sines); ``trig``.

        The gear-independent u = 1 - cos psi, sin psi, u/2 and 1 - u when known (:func:`_first_scan`).
        """
        if trig is None:
            u, w = _half_angle_terms(psi)                        # 1 - cos psi, sin psi
            hu, cu = 0.5 * u, 1.0 - u
        else:
            u, w, hu, cu = trig
        q = q0 / np.sqrt(A + B * hu)                             # R_b/rho
        cx = cu - q * (omk - u) - e0                             # (C_x - e)/R_p
        cy = w * (1.0 - q)                                       # C_y/R_p
        return np.arctan2(cy, cx) - zr * psi + offset

    return h, offset


def _first_roots_of_scans(h, offset: float, m: int, n_scan: int, n_refine: int, stages: int):
    """(psi*, found) of m gears at once: the first sign change of h's scans, then inverse quadratic interpolation.

    The vectorised form of :func:`_first_root_of_scan` (:func:`crest_cutoffs`); found: h has a sign change on
    (0, pi].
    """
    r = np.arange(m)
    lo, hi = np.zeros(m), np.full(m, math.pi)
    h_lo, h_hi = (np.zeros((m, 1)) + offset).reshape(m), np.zeros(m)     # h(0) = pi/z1
    found = np.ones(m, dtype=bool)
    n = n_scan
    for stage in range(stages + 1):
        if stage == 0:              # the first scan's points and their trigonometry are those of every gear
            x0, *trig = _first_scan(n)
            x = np.broadcast_to(x0, (m, n))
            hx = h(x, trig)
        else:
            x = lo[:, None] + (hi - lo)[:, None] * (np.arange(1, n + 1) / n)
            hx = h(x)
        neg = hx <= 0.0
        first = np.argmax(neg, axis=1)
        if stage == 0:
            found = neg[r, first]          # no sign change on (0, pi]: psi* = pi (not for an admissible k >= 2)
        prev = np.maximum(first - 1, 0)
        lo, h_lo = np.where(first > 0, x[r, prev], lo), np.where(first > 0, hx[r, prev], h_lo)
        hi, h_hi = x[r, first], hx[r, first]
        n = n_refine
    # inverse quadratic interpolation through lo, hi and the next scan point (error ~ width^3),
    # falling back to the secant if it leaves the bracket
    k3 = np.where(first + 1 < n, first + 1, first - 2)
    x3, h3 = x[r, k3], hx[r, k3]
    with np.errstate(divide="ignore", invalid="ignore"):
        iqi = (lo * (h_hi * h3) / ((h_lo - h_hi) * (h_lo - h3)) + hi * (h_lo * h3) / ((h_hi - h_lo) * (h_hi - h3))
               + x3 * (h_lo * h_hi) / ((h3 - h_lo) * (h3 - h_hi)))
        sec = lo + (hi - lo) * (h_lo / (h_lo - h_hi))
    root = np.where(h_hi == 0.0, hi, np.where((iqi >= lo) & (iqi <= hi), iqi, sec))
    return np.clip(root, lo, hi), found


def _half_angle_terms(psi):
    """(1 - cos psi, sin psi) = (2 sin^2(psi/2), 2 sin(psi/2) cos(psi/2)), the cancellation-free half-angle forms."""
    half = 0.5 * psi
    sh, ch = np.sin(half), np.cos(half)
    t2 = 2.0 * sh
    return t2 * sh, t2 * ch


_FIRST_SCANS: dict[int, tuple] = {}


def _first_scan(n: int):
    """The first scan of :func:`crest_cutoffs` on (0, pi], the same for every gear.

    Its points lo + (hi - lo) (k/n) with lo = 0, hi = pi, their :func:`_half_angle_terms` u = 1 - cos psi and sin
    psi, and u/2 and 1 - u (cached: read-only).
    """
    have = _FIRST_SCANS.get(n)
    if have is None:
        x = 0.0 + (math.pi - 0.0) * _scan_fractions(n)
        u, w = _half_angle_terms(x)
        have = (x, u, w, 0.5 * u, 1.0 - u)
        for a in have:
            a.setflags(write=False)
        _FIRST_SCANS[n] = have
    return have


_SCAN_FRACTIONS: dict[int, np.ndarray] = {}


def _scan_fractions(n: int) -> np.ndarray:
    """(1, 2, ..., n)/n, the scan points of a cell as fractions of its width (cached: read-only)."""
    frac = _SCAN_FRACTIONS.get(n)
    if frac is None:
        frac = np.arange(1, n + 1) / n
        frac.setflags(write=False)
        _SCAN_FRACTIONS[n] = frac
    return frac


def _first_root_of_scan(h, h0: float, n_scan: int, n_refine: int, stages: int) -> float:
    """The search of :func:`crest_cutoffs` for one gear, on Python floats between the scans.

    The same scan points, first sign changes and interpolation, operation for operation, as the
    vectorised search over many gears (so a design alone equals the same design in a batch): the
    bookkeeping between the scans is done on Python floats, which round as numpy's float64 does.
    A division by zero in the interpolation (NaN or inf in the vectorised search) takes the secant,
    as there.
    """
    lo, hi, h_lo = 0.0, math.pi, h0
    n = n_scan
    for stage in range(stages + 1):
        if stage == 0:              # lo = 0, hi = pi: the points and trigonometry of every gear (cached)
            x, *trig = _first_scan(n)
            hx = h(x, trig)
        else:
            x = lo + (hi - lo) * _scan_fractions(n)
            hx = h(x)
        first = int(np.argmax(hx <= 0.0))
        if stage == 0 and not hx[first] <= 0.0:
            return math.pi                  # no sign change on (0, pi]: psi* = pi (not for an admissible k >= 2)
        if first > 0:
            lo, h_lo = float(x[first - 1]), float(hx[first - 1])
        hi, h_hi = float(x[first]), float(hx[first])
        n = n_refine
    k3 = first + 1 if first + 1 < n else first - 2
    x3, h3 = float(x[k3]), float(hx[k3])
    if h_hi == 0.0:
        return hi
    try:
        sec = lo + (hi - lo) * (h_lo / (h_lo - h_hi))
    except ZeroDivisionError:
        sec = math.nan
    try:
        iqi = (lo * (h_hi * h3) / ((h_lo - h_hi) * (h_lo - h3)) + hi * (h_lo * h3) / ((h_hi - h_lo) * (h_hi - h3))
               + x3 * (h_lo * h_hi) / ((h3 - h_lo) * (h3 - h_hi)))
    except ZeroDivisionError:
        iqi = math.nan
    root = iqi if lo <= iqi <= hi else sec
    return min(max(root, lo), hi)           # np.clip (NaN stays NaN there too)


def spin_reversal_phase(g: Cycloid) -> float | None:
    r"""Phase psi_0 where rho(psi_0) = R_b (the pin's spin reverses), or None when R_b <= R_p (1 - K1).

    One gear of :func:`spin_reversal_phases` (pins.md §4.5, §6).

    .. math:: \rho(\psi_0) = R_b, \qquad \sin\frac{\psi_0}{2} = \sqrt{\frac{(R_b/R_p)^2 - (1 - K_1)^2}{4 K_1}}

    Parameters
    ----------
    g : Cycloid
        The gear.

    Returns
    -------
    psi_0 : float or None
        The phase, [rad], or None.

    Examples
    --------
    >>> g = Cycloid.from_curtate_ratio(20, 22, 3.9, 0.75, 1.95)
    >>> spin_reversal_phase(g) is None
    True

    References
    ----------
    .. [1] A. P. Prudnikov, «Потери мощности в контакте цевок и зубьев планетарной передачи типа K-H-V» (Power losses in
       pins and teeth contact area of KHV-type planetary gearing), Машиностроение (seed file 000_fe288dec6e7c72f0.txt);
       docs/spec/pins.md §4.5, §6.
    """
    psi_0 = float(spin_reversal_phases(as_arrays(g))[0])
    return None if math.isnan(psi_0) else psi_0


def spin_reversal_phases(g: Cycloid) -> np.ndarray:
    r"""Spin-reversal phases psi_0 of many gears (NaN where R_b <= R_p (1 - K1): none) [rad].

    sin(psi_0/2) = sqrt(((R_b/R_p)^2 - (1 - K1)^2)/(4 K1))  (pins.md §4.5, §6).

    .. math:: \sin\frac{\psi_0}{2} = \sqrt{\frac{(R_b/R_p)^2 - (1 - K_1)^2}{4 K_1}}

    Parameters
    ----------
    g : Cycloid
        Gears whose fields are arrays of one shape (m,).

    Returns
    -------
    psi_0 : ndarray
        The phases, [rad], shape (m,); NaN where there is none.

    Examples
    --------
    >>> g = Cycloid.from_curtate_ratio(21, 22, 1.0, 0.999, 0.1)
    >>> p = float(spin_reversal_phases(as_arrays(g))[0])
    >>> round(float(pitch_distance(p, g)), 12)     # rho(psi_0) = R_b
    0.1

    References
    ----------
    .. [1] A. P. Prudnikov, «Потери мощности в контакте цевок и зубьев планетарной передачи типа K-H-V» (Power losses in
       pins and teeth contact area of KHV-type planetary gearing), Машиностроение (seed file 000_fe288dec6e7c72f0.txt);
       docs/spec/pins.md §4.5, §6.
    """
    q = np.asarray(g.R_b) / np.asarray(g.R_p)
    omk = np.asarray(g.one_minus_K1)
    arg = (q * q - omk ** 2) / (4.0 * g.K1)
    ok = (arg > 0.0) & (arg < 1.0)
    return np.where(ok, 2.0 * np.arcsin(np.sqrt(np.where(ok, arg, 0.0))), np.nan)


def curvature_radius(psi, g: Cycloid):
    r"""Radius of curvature of the pin-centre curve, rho_c = R_p s^3/D  (pins.md §4.2) [mm].

    D = 1 + K1^2 Z_e - K1 (1 + Z_e) cos(psi), Z_e = z2/k; D > 0 on the convex part.  Returns
    the signed value (negative on the concave part).

    .. math:: \rho_c = \frac{R_p\,s^3}{D}, \qquad D = 1 + K_1^2 Z_e - K_1\,(1 + Z_e) \cos\psi, \quad Z_e = \frac{z_2}{k}

    Parameters
    ----------
    psi : float or array_like
        Pin phase, [rad].
    g : Cycloid
        The gear.

    Returns
    -------
    rho_c : ndarray
        Signed radius of curvature, [mm] (negative on the concave part).

    Examples
    --------
    >>> g = Cycloid.from_curtate_ratio(20, 22, 3.9, 0.75, 1.95)
    >>> round(float(curvature_radius(np.pi, g)), 6)     # 57.2 * 1.75**3 / 16.1875
    18.937838

    References
    ----------
    .. [1] A. P. Prudnikov, «Потери мощности в контакте цевок и зубьев планетарной передачи типа K-H-V» (Power losses in
       pins and teeth contact area of KHV-type planetary gearing), Машиностроение (seed file 000_fe288dec6e7c72f0.txt);
       docs/spec/pins.md §4.2 (admissibility, derived).
    """
    psi = np.asarray(psi, dtype=float)
    K1, Ze = g.K1, g.z2 / g.k
    D = 1.0 + K1 * K1 * Ze - K1 * (1.0 + Ze) * np.cos(psi)
    s = s_factor(psi, K1, g.one_minus_K1)
    with np.errstate(divide="ignore"):
        return g.R_p * s ** 3 / D


def min_curvature_radius(g: Cycloid, psi_star, n_scan=None):
    r"""Least radius of curvature of the convex part of the pin-centre curve over 0 <= psi <= psi* [mm].

    Closed form.  With c = cos(psi), s^2 = A - B c and D = p - q c, where A = 1 + K1^2, B = 2 K1,
    p = 1 + K1^2 Z_e and q = K1 (1 + Z_e), so rho_c = R_p (A - B c)^(3/2)/(p - q c), and

        d rho_c/dc = R_p (A - B c)^(1/2) (q A - 3 B p/2 + B q c/2)/(p - q c)^2,

    whose bracket is linear and increasing in c: rho_c has a single minimum, at
    c* = 3 p/q - A/K1.  On the convex part (D > 0, i.e. c < p/q) of the loaded range
    c in [cos psi*, 1] the least value is therefore at c* clipped to that range; it is evaluated
    at psi = arccos(c) with the cancellation-free :func:`curvature_radius` (the clipped ends are
    psi* and 0 exactly).  inf where no part of the range is convex.  The profile has no loops
    (undercut) when R_b < this value (pins.md §4.2).  Works element-wise on gears of arrays.

    .. math:: \rho_c = \frac{R_p\,(A - B c)^{3/2}}{p - q c}, \qquad c^* = \frac{3 p}{q} - \frac{A}{K_1}, \qquad
        \min \rho_c = \rho_c\big(\operatorname{clip}(c^*,\ \cos\psi^*,\ 1)\big)

    Parameters
    ----------
    g : the gear (fields scalars or arrays of one shape).
    psi_star : end of the loaded arc [rad] (scalar or array of that shape).
    n_scan : ignored (the minimum was once found by a scan; kept for callers).

    Returns
    -------
    min rho_c [mm] (a float for a scalar gear, else an array).

    Examples
    --------
    >>> g = Cycloid.from_curtate_ratio(21, 22, 3.9, 0.75, 1.95)
    >>> round(min_curvature_radius(g, np.pi), 3) <= round(float(curvature_radius(np.pi, g)), 3)
    True

    References
    ----------
    .. [1] A. P. Prudnikov, «Потери мощности в контакте цевок и зубьев планетарной передачи типа K-H-V» (Power losses in
       pins and teeth contact area of KHV-type planetary gearing), Машиностроение (seed file 000_fe288dec6e7c72f0.txt);
       docs/spec/pins.md §4.2 (admissibility, derived).
    """
    K1, Ze = g.K1, np.asarray(g.z2) / np.asarray(g.k)
    psi_star = np.asarray(psi_star, dtype=float)
    A = 1.0 + K1 * K1                              # s^2 = A - B c with B = 2 K1
    p, q = 1.0 + K1 * K1 * Ze, K1 * (1.0 + Ze)
    c_lo, c_hi = np.cos(psi_star), np.minimum(1.0, p / q)
    c_star = 3.0 * p / q - A / K1
    convex = c_lo < p / q
    at_end = c_star <= c_lo
    at_zero = (c_star >= 1.0) & (c_hi >= 1.0)
    c = np.clip(c_star, c_lo, c_hi)
    psi = np.where(at_end, psi_star, np.where(at_zero, 0.0, np.arccos(np.clip(c, -1.0, 1.0))))
    rc = curvature_radius(psi, g)
    rc = np.where(convex & (rc > 0), rc, np.inf)
    return float(rc) if rc.ndim == 0 else rc


def pin_centre_curve(beta, family: int, g: Cycloid):
    r"""Pin-centre curve of family b in the satellite frame, c_b(beta) = R_p u(beta) - e u(Z_e beta - 2 pi b/k) [mm].

    .. math:: c_b(\beta) = R_p\,u(\beta) - e\,u\!\left(Z_e \beta - \frac{2\pi b}{k}\right), \qquad
        u(x) = (\cos x, \sin x), \quad Z_e = \frac{z_2}{k}

    Parameters
    ----------
    beta : curve parameter (= phi_i + k theta/z1) [rad].
    family : b = i mod k.
    g : the gear.

    Returns
    -------
    (x, y) [mm]  (Chen et al. 2008 eqs. (10)-(11), counter-clockwise form; pins.md §4.2).

    Examples
    --------
    >>> g = Cycloid.from_curtate_ratio(20, 22, 3.9, 0.75, 1.95)
    >>> [round(float(c), 9) for c in pin_centre_curve(0.0, 0, g)]   # R_p - e
    [53.3, 0.0]

    References
    ----------
    .. [1] B. Chen, T. Fang, C. Li, S. Wang, Gear geometry of cycloid drives, Science in China Series E:
       Technological Sciences 51, 2008, eqs. (10)-(11) (counter-clockwise form); docs/spec/pins.md §4.2.
    """
    beta = np.asarray(beta, dtype=float)
    ze = g.z2 / g.k
    a = ze * beta - 2.0 * math.pi * family / g.k
    return g.R_p * np.cos(beta) - g.e * np.cos(a), g.R_p * np.sin(beta) - g.e * np.sin(a)


def tooth_profile(beta, family: int, g: Cycloid):
    r"""Tooth profile Gamma_b(beta) = c_b - R_b (c_b - p_b)/|c_b - p_b|, p_b = r_p1 u(Z_e beta - 2 pi b/k) [mm].

    .. math:: \Gamma_b(\beta) = c_b - R_b\,\frac{c_b - p_b}{|c_b - p_b|}, \qquad
        p_b = r_{p1}\,u\!\left(Z_e \beta - \frac{2\pi b}{k}\right)

    Parameters
    ----------
    beta : float or array_like
        Curve parameter (= phi_i + k theta/z1), [rad].
    family : int
        b = i mod k.
    g : Cycloid
        The gear.

    Returns
    -------
    x, y : ndarray
        The profile point in the satellite frame, [mm].

    Examples
    --------
    >>> g = Cycloid.from_curtate_ratio(20, 22, 3.9, 0.75, 1.95)
    >>> [round(float(c), 9) for c in tooth_profile(0.0, 0, g)]   # R_p - e - R_b
    [51.35, 0.0]

    References
    ----------
    .. [1] B. Chen, T. Fang, C. Li, S. Wang, Gear geometry of cycloid drives, Science in China Series E:
       Technological Sciences 51, 2008, eqs. (10)-(11); docs/spec/pins.md §4.2.
    """
    cx, cy = pin_centre_curve(beta, family, g)
    a = (g.z2 / g.k) * np.asarray(beta, dtype=float) - 2.0 * math.pi * family / g.k
    px, py = g.r_p1 * np.cos(a), g.r_p1 * np.sin(a)
    d = np.hypot(cx - px, cy - py)
    return cx - g.R_b * (cx - px) / d, cy - g.R_b * (cy - py) / d
