"""KHV planetary pin (lantern) gearing: per-pin friction losses and the efficiency they cause.

Pure physics over floats and numpy arrays (no I/O).  Units inside: N, mm, N·mm, rad, rad/s; a
power F [N]·v [mm/s]·1e-3 is in W.  Symbols follow ``pins.md`` (the spec):

* level ``formula``: the paper's per-pin maximum loss, eqs. (3)-(7) (Prudnikov, seed 000);
* level ``ideal``: the quasi-static rigid conjugate model of a cycloidal satellite (pins.md §4):
  profile and admissibility, crest cut-off psi*, lever arms, forces from equilibrium, sliding
  speeds, pin spin, losses, loss ratio over one crank-angle period, efficiency in both modes: first-order
  (friction-free forces, §4.6-4.7) and friction-consistent (friction in the satellite's balance, each mode
  solved on its own, jams, crank torque and crank-bearing force; §4.9, :func:`consistent_cycles`).

The compliant ``contact`` level (pins.md §5) is :mod:`gearcalc.pins_contact`; it reuses :class:`Cycloid`,
:func:`pin_centre_curve`, :func:`tooth_profile`, :func:`crest_cutoff`, :func:`pin_phase`, the loss and
efficiency functions and :mod:`gearcalc.quadrature`.

Conventions: crank speed omega_H > 0 (counter-clockwise); satellite (V) speed
omega_V = -omega_H k/z1; pin i sits at phi_i = 2 pi i/z2; its phase psi_i = phi_i - theta;
sigma = +1 (reducer) or -1 (multiplier); load-side phase psi~ = (sigma psi) mod 2 pi.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from dataclasses import field as dataclass_field

import numpy as np

from . import units
from .arrays import unique_sorted
from .quadrature import QuadResult, geometric_breakpoints, integrate_pieces

PAPER_PI = 3.14
"""The value of pi the paper computed with (pins.md §3)."""

REDUCER, MULTIPLIER = 1, -1
"""sigma: +1 reducer (H drives V), -1 multiplier (V drives H)."""


# ============================================================ level "formula" (pins.md §3)

def pin_angular_speed(pin_speed_rpm, paper_pi: bool = False):
    """Pin spin omega = pi n/30 [rad/s], optionally with the paper's pi = 3.14.

    Parameters
    ----------
    pin_speed_rpm : n_pin [rpm].
    paper_pi : use pi = 3.14 as the paper did.

    Examples
    --------
    >>> round(pin_angular_speed(30.0, paper_pi=True), 12)
    3.14
    >>> pin_angular_speed(np.array([30.0, 30.0]), np.array([True, False])).round(4).tolist()
    [3.14, 3.1416]
    """
    omega = units.rpm_to_rad_s(pin_speed_rpm)
    if np.ndim(paper_pi):                       # per element
        return np.where(paper_pi, omega * (PAPER_PI / math.pi), omega)
    return omega * (PAPER_PI / math.pi) if paper_pi else omega


def rolling_friction_force(normal_force, rolling_coefficient, bushing_radius):
    """Rolling-resistance force between tooth and bushing, F_tr1 = f_k F_n / R  (paper eq. 3).

    Parameters
    ----------
    normal_force : F_n [N].
    rolling_coefficient : f_k [mm].
    bushing_radius : R = R_b [mm].

    Returns
    -------
    F_tr1 [N].

    Examples
    --------
    >>> round(rolling_friction_force(1920.0, 0.01, 1.95), 2)   # paper: 9.85 N
    9.85
    """
    return rolling_coefficient * normal_force / bushing_radius


def axle_friction_force(normal_force, axle_friction):
    """Sliding friction between bushing and axle, F_tr2 = f_c F_n  (paper eq. 4).

    Parameters
    ----------
    normal_force : F_n [N] (the axle reaction equals it).
    axle_friction : f_c [-].

    Returns
    -------
    F_tr2 [N].

    Examples
    --------
    >>> axle_friction_force(1920.0, 0.1)   # paper: 192 N
    192.0
    """
    return axle_friction * normal_force


def friction_power(force, angular_speed, radius):
    """Power of a friction force acting at a radius of a spinning part, P = F omega R 1e-3  (eqs. 5, 6).

    Parameters
    ----------
    force : friction force [N].
    angular_speed : spin [rad/s].
    radius : lever of the force about the spin axis [mm].

    Returns
    -------
    P [W].

    Examples
    --------
    >>> friction_power(10.0, 2.0, 3.0)
    0.06
    """
    return force * angular_speed * radius * 1e-3


@dataclass(frozen=True)
class FormulaLosses:
    """Per-pin maximum losses of the paper (eqs. 3-7): forces [N], powers [W] (floats or arrays).

    ``P_tr_fixed`` is the fixed-pin variant (:func:`fixed_pin_formula_loss`), None unless the sliding
    friction was given."""

    F_tr1: float
    F_tr2: float
    P_tr1: float
    P_tr2: float
    P_tr: float
    P_tr_fixed: float | None = None


def formula_losses(normal_force, pin_speed_rpm, bushing_radius, axle_radius, rolling_coefficient,
                   axle_friction, paper_pi=False, sliding_friction=None) -> FormulaLosses:
    r"""The paper's maximum friction loss on one rotating pin, eqs. (3)-(7).

    .. math::

        F_{tr1} = \frac{f_k F_n}{R},\quad F_{tr2} = f_c F_n,\quad
        P_{tr1} = F_{tr1}\,\omega R\,10^{-3},\quad P_{tr2} = F_{tr2}\,\omega r\,10^{-3},\quad
        P_{tr} = P_{tr1} + P_{tr2},\quad \omega = \frac{\pi n_{pin}}{30}

    Parameters
    ----------
    normal_force : float or array_like
        F_n, peak normal force on one pin [N].
    pin_speed_rpm : float or array_like
        n_pin, bushing speed [rpm].
    bushing_radius : float or array_like
        R, outer radius of the bushing [mm].
    axle_radius : float or array_like
        r, radius of the axle [mm].
    rolling_coefficient : float or array_like
        f_k, rolling friction between tooth and bushing [mm].
    axle_friction : float or array_like
        f_c, sliding friction between bushing and axle [-].
    paper_pi : bool or array_like of bool
        compute with pi = 3.14 (reproduces the paper's printed digits), per element for an array.
    sliding_friction : float or array_like, optional
        f, tooth-pin sliding friction [-]: also gives ``P_tr_fixed``, the fixed-pin loss
        f F_n omega R 1e-3 [W] (pins.md §3).

    Returns
    -------
    FormulaLosses
        F_tr1, F_tr2 [N]; P_tr1, P_tr2, P_tr, P_tr_fixed [W]; floats or arrays (NaN in, NaN out).

    Examples
    --------
    >>> round(formula_losses(1920, 14, 1.95, 0.95, 0.01, 0.1, paper_pi=True).P_tr, 3)  # paper 0.295 W
    0.295
    >>> formula_losses(np.array([1920.0, 960.0]), 14, 1.95, 0.95, 0.01, 0.1, paper_pi=True).P_tr.round(4).tolist()
    [0.2954, 0.1477]

    References
    ----------
    .. [1] A. P. Prudnikov, "Power losses in pins and teeth contact area of KHV-type planetary
       gearing", *Mashinostroenie* (seed 000), eqs. (3)-(7); pins.md §3.
    """
    omega = pin_angular_speed(pin_speed_rpm, paper_pi)
    f1 = rolling_friction_force(normal_force, rolling_coefficient, bushing_radius)
    f2 = axle_friction_force(normal_force, axle_friction)
    p1 = friction_power(f1, omega, bushing_radius)
    p2 = friction_power(f2, omega, axle_radius)
    fixed = None if sliding_friction is None else friction_power(sliding_friction * normal_force, omega,
                                                                 bushing_radius)
    return FormulaLosses(f1, f2, p1, p2, p1 + p2, fixed)


def fixed_pin_formula_loss(normal_force, pin_speed_rpm, bushing_radius, sliding_friction, paper_pi=False):
    """Fixed-pin variant of eq. (7): P = f F_n v_s 1e-3 with v_s = (pi n_eq/30) R  (pins.md §3).

    Parameters
    ----------
    normal_force : F_n [N].
    pin_speed_rpm : n_eq, the speed the pin would turn at if it rolled [rpm].
    bushing_radius : R [mm].
    sliding_friction : f [-].
    paper_pi : pi = 3.14.

    Returns
    -------
    P_tr,fix [W].

    Examples
    --------
    >>> round(fixed_pin_formula_loss(1920, 14, 1.95, 0.1, paper_pi=True), 4)
    0.5486
    """
    return friction_power(sliding_friction * normal_force, pin_angular_speed(pin_speed_rpm, paper_pi),
                          bushing_radius)


# ============================================================ level "ideal": geometry (pins.md §4.1-4.3)

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
        k = z2 - z1
        return cls(z1, z2, float(e), float(R_p), float(R_b), (k * R_p - e * z2) / (k * R_p))

    @classmethod
    def from_curtate_ratio(cls, z1, z2, e, K1, R_b):
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
    R_p [mm], K1 [-] and the overlap limit R_p sin(pi/z2) [mm] they were decided on."""

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


def geometry_violations(z1, z2, eccentricity, pin_circle_radius, curtate_ratio, pin_radius, axle_radius=np.nan,
                        rotating=False, cycloidal=True) -> GeometryViolations:
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
    axle_radius : float or array_like
        r [mm] (NaN: none).
    rotating : bool or array_like of bool
        rotating pins (bushings on axles).
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
    .. [1] A. P. Prudnikov, "Power losses in pins and teeth contact area of KHV-type planetary gearing",
       *Mashinostroenie* (seed 000); pins.md §4.2, §7, §9.
    """
    z1 = np.atleast_1d(np.asarray(z1, dtype=np.int64))
    z2 = np.atleast_1d(np.asarray(z2, dtype=np.int64))
    e, Rb, r = (np.atleast_1d(np.asarray(x, dtype=float)) for x in (eccentricity, pin_radius, axle_radius))
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
            overlap=Rb >= limit, axle=np.asarray(rotating) & (r >= Rb), pin_circle_radius=Rp, curtate_ratio=K1,
            overlap_limit=limit)


def s_factor(psi, K1, one_minus_K1):
    """s(psi) = sqrt((1 - K1)^2 + 4 K1 sin^2(psi/2)) = |A - P|/R_p, cancellation-free (pins.md §4.2).

    Parameters
    ----------
    psi : pin phase [rad].
    K1 : curtate ratio [-].
    one_minus_K1 : 1 - K1, given separately [-].

    Examples
    --------
    >>> round(float(s_factor(np.pi, 0.75, 0.25)), 12)
    1.75
    """
    sh = np.sin(0.5 * np.asarray(psi, dtype=float))
    return np.sqrt(one_minus_K1 * one_minus_K1 + 4.0 * K1 * sh * sh)


def pitch_distance(psi, g: Cycloid):
    """rho(psi) = |A - P| = R_p s(psi): pin centre to pitch point [mm]  (pins.md §4.2).

    Examples
    --------
    >>> g = Cycloid.from_curtate_ratio(20, 22, 3.9, 0.75, 1.95)
    >>> round(float(pitch_distance(0.0, g)), 12)   # R_p (1 - K1)
    14.3
    """
    return g.R_p * s_factor(psi, g.K1, g.one_minus_K1)


def lever_arm(psi, g: Cycloid):
    """Signed lever arm of the normal through P about O1, l = r_p1 sin(psi)/s(psi) [mm]  (pins.md §4.4).

    Examples
    --------
    >>> g = Cycloid.from_curtate_ratio(20, 22, 3.9, 0.75, 1.95)
    >>> round(float(lever_arm(np.pi / 2, g)), 9)   # 39 / sqrt(1 + 0.75^2)
    31.2
    """
    psi = np.asarray(psi, dtype=float)
    return g.r_p1 * np.sin(psi) / s_factor(psi, g.K1, g.one_minus_K1)


def contact_point(psi, g: Cycloid):
    """Contact point C = A - R_b (A - P)/rho in the crank frame (O1 = (e, 0), P = (r_p2, 0)) [mm].

    Returns
    -------
    (C_x, C_y) [mm].

    Examples
    --------
    >>> g = Cycloid.from_curtate_ratio(20, 22, 3.9, 0.75, 1.95)
    >>> [round(float(c), 9) for c in contact_point(np.pi, g)]
    [-55.25, 0.0]
    """
    psi = np.asarray(psi, dtype=float)
    rho = pitch_distance(psi, g)
    sh = np.sin(0.5 * psi)
    dx = g.R_p * (g.one_minus_K1 - 2.0 * sh * sh)       # R_p cos(psi) - r_p2, cancellation-free
    dy = g.R_p * np.sin(psi)
    return g.R_p * np.cos(psi) - g.R_b * dx / rho, dy - g.R_b * dy / rho


def contact_angle_offset(psi, g: Cycloid):
    """epsilon(psi): polar angle of the contact point on the satellite from its tooth-space axis [rad].

    epsilon = atan2(C_y, C_x - e) - (z2/z1) psi; a pin leaves its flank at epsilon = -pi/z1
    (pins.md §4.3).

    Examples
    --------
    >>> g = Cycloid.from_curtate_ratio(21, 22, 3.9, 0.75, 1.95)   # k = 1: the crest is at psi = pi
    >>> abs(round(float(contact_angle_offset(np.pi, g)) + np.pi / 21, 12))
    0.0
    """
    cx, cy = contact_point(psi, g)
    return np.arctan2(cy, cx - g.e) - (g.z2 / g.z1) * np.asarray(psi, dtype=float)


def crest_cutoff(g: Cycloid) -> float:
    """End of the loaded arc psi* [rad]: pi for k = 1, else the first root of epsilon(psi) = -pi/z1.

    One gear of :func:`crest_cutoffs` (pins.md §4.3, §12.11).

    Examples
    --------
    >>> g = Cycloid.from_curtate_ratio(20, 22, 3.9, 0.75, 1.95)
    >>> 0 < crest_cutoff(g) < np.pi
    True
    """
    if g.k == 1:
        return math.pi
    return float(crest_cutoffs(_as_arrays(g))[0])


def _as_arrays(g: Cycloid) -> Cycloid:
    """The same gear with every field a one-element array (for the functions vectorised over gears)."""
    return Cycloid(*(np.atleast_1d(v) for v in (g.z1, g.z2, g.e, g.R_p, g.R_b, g.one_minus_K1)))


def crest_cutoffs(g: Cycloid, n_scan: int = 512, n_refine: int = 128, stages: int = 2) -> np.ndarray:
    """psi* of many gears at once [rad]: pi where k = 1, else the first root of h = epsilon + pi/z1.

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
    the ideal level's time per design.

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

    def col(v):
        v = np.asarray(v)[rows]
        return float(v[0]) if one else v[:, None]

    z1, z2, e, R_p, R_b, omk = (col(v) for v in (g.z1, g.z2, g.e, g.R_p, g.R_b, g.one_minus_K1))
    A, B = omk * omk, 4.0 * (e * z2 / ((z2 - z1) * R_p))      # (1 - K1)^2 and 4 K1 (K1 as Cycloid.K1)
    q0, e0, zr, offset = R_b / R_p, e / R_p, z2 / z1, math.pi / z1

    def h(psi):
        """epsilon(psi) + pi/z1 in half-angle form (contact_angle_offset scaled by 1/R_p; two sines)."""
        half = 0.5 * psi
        sh, ch = np.sin(half), np.cos(half)
        u = 2.0 * sh * sh                                        # 1 - cos psi
        q = q0 / np.sqrt(A + B * (0.5 * u))                      # R_b/rho
        cx = (1.0 - u) - q * (omk - u) - e0                      # (C_x - e)/R_p
        cy = (2.0 * sh * ch) * (1.0 - q)                          # C_y/R_p
        return np.arctan2(cy, cx) - zr * psi + offset

    if one:
        out[rows] = _first_root_of_scan(h, offset, n_scan, n_refine, stages)
        return out
    m = rows.size
    r = np.arange(m)
    lo, hi = np.zeros(m), np.full(m, math.pi)
    h_lo, h_hi = (np.zeros((m, 1)) + offset).reshape(m), np.zeros(m)     # h(0) = pi/z1
    found = np.ones(m, dtype=bool)
    n = n_scan
    for stage in range(stages + 1):
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
    out[rows] = np.where(found, np.clip(root, lo, hi), math.pi)
    return out


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
    """Phase psi_0 where rho(psi_0) = R_b (the pin's spin reverses), or None when R_b <= R_p (1 - K1).

    One gear of :func:`spin_reversal_phases` (pins.md §4.5, §6).

    Examples
    --------
    >>> g = Cycloid.from_curtate_ratio(20, 22, 3.9, 0.75, 1.95)
    >>> spin_reversal_phase(g) is None
    True
    """
    psi_0 = float(spin_reversal_phases(_as_arrays(g))[0])
    return None if math.isnan(psi_0) else psi_0


def spin_reversal_phases(g: Cycloid) -> np.ndarray:
    """Spin-reversal phases psi_0 of many gears (NaN where R_b <= R_p (1 - K1): none) [rad].

    sin(psi_0/2) = sqrt(((R_b/R_p)^2 - (1 - K1)^2)/(4 K1))  (pins.md §4.5, §6).

    Examples
    --------
    >>> g = Cycloid.from_curtate_ratio(21, 22, 1.0, 0.999, 0.1)
    >>> p = float(spin_reversal_phases(_as_arrays(g))[0])
    >>> round(float(pitch_distance(p, g)), 12)     # rho(psi_0) = R_b
    0.1
    """
    q = np.asarray(g.R_b) / np.asarray(g.R_p)
    omk = np.asarray(g.one_minus_K1)
    arg = (q * q - omk ** 2) / (4.0 * g.K1)
    ok = (arg > 0.0) & (arg < 1.0)
    return np.where(ok, 2.0 * np.arcsin(np.sqrt(np.where(ok, arg, 0.0))), np.nan)


def curvature_radius(psi, g: Cycloid):
    """Radius of curvature of the pin-centre curve, rho_c = R_p s^3/D  (pins.md §4.2) [mm].

    D = 1 + K1^2 Z_e - K1 (1 + Z_e) cos(psi), Z_e = z2/k; D > 0 on the convex part.  Returns
    the signed value (negative on the concave part).

    Examples
    --------
    >>> g = Cycloid.from_curtate_ratio(20, 22, 3.9, 0.75, 1.95)
    >>> round(float(curvature_radius(np.pi, g)), 6)     # 57.2 * 1.75**3 / 16.1875
    18.937838
    """
    psi = np.asarray(psi, dtype=float)
    K1, Ze = g.K1, g.z2 / g.k
    D = 1.0 + K1 * K1 * Ze - K1 * (1.0 + Ze) * np.cos(psi)
    s = s_factor(psi, K1, g.one_minus_K1)
    with np.errstate(divide="ignore"):
        return g.R_p * s ** 3 / D


def min_curvature_radius(g: Cycloid, psi_star, n_scan=None):
    """Least radius of curvature of the convex part of the pin-centre curve over 0 <= psi <= psi* [mm].

    Closed form.  With c = cos(psi), s^2 = A - B c and D = p - q c, where A = 1 + K1^2, B = 2 K1,
    p = 1 + K1^2 Z_e and q = K1 (1 + Z_e), so rho_c = R_p (A - B c)^(3/2)/(p - q c), and

        d rho_c/dc = R_p (A - B c)^(1/2) (q A - 3 B p/2 + B q c/2)/(p - q c)^2,

    whose bracket is linear and increasing in c: rho_c has a single minimum, at
    c* = 3 p/q - A/K1.  On the convex part (D > 0, i.e. c < p/q) of the loaded range
    c in [cos psi*, 1] the least value is therefore at c* clipped to that range; it is evaluated
    at psi = arccos(c) with the cancellation-free :func:`curvature_radius` (the clipped ends are
    psi* and 0 exactly).  inf where no part of the range is convex.  The profile has no loops
    (undercut) when R_b < this value (pins.md §4.2).  Works element-wise on gears of arrays.

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
    """Pin-centre curve of family b in the satellite frame, c_b(beta) = R_p u(beta) - e u(Z_e beta - 2 pi b/k) [mm].

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
    """
    beta = np.asarray(beta, dtype=float)
    ze = g.z2 / g.k
    a = ze * beta - 2.0 * math.pi * family / g.k
    return g.R_p * np.cos(beta) - g.e * np.cos(a), g.R_p * np.sin(beta) - g.e * np.sin(a)


def tooth_profile(beta, family: int, g: Cycloid):
    """Tooth profile Gamma_b(beta) = c_b - R_b (c_b - p_b)/|c_b - p_b|, p_b = r_p1 u(Z_e beta - 2 pi b/k) [mm].

    Examples
    --------
    >>> g = Cycloid.from_curtate_ratio(20, 22, 3.9, 0.75, 1.95)
    >>> [round(float(c), 9) for c in tooth_profile(0.0, 0, g)]   # R_p - e - R_b
    [51.35, 0.0]
    """
    cx, cy = pin_centre_curve(beta, family, g)
    a = (g.z2 / g.k) * np.asarray(beta, dtype=float) - 2.0 * math.pi * family / g.k
    px, py = g.r_p1 * np.cos(a), g.r_p1 * np.sin(a)
    d = np.hypot(cx - px, cy - py)
    return cx - g.R_b * (cx - px) / d, cy - g.R_b * (cy - py) / d


# ============================================================ pin phases and the loaded set (§4.1, §4.3)

def pin_phase(pin, theta, z2: int, sigma: int = REDUCER):
    """Load-side phase psi~ = (sigma (phi_i - theta)) mod 2 pi, in exact integer phase arithmetic [rad].

    theta = T_p (m + tau) with m an integer and 0 <= tau < 1; psi = pi ((2 ((i - m) mod z2) - 2 tau)/z2),
    dividing before multiplying by pi, so that pins exactly at 0 or pi stay exact (pins.md §4.1).

    Parameters
    ----------
    pin : pin index i (array-like of int).
    theta : crank angle [rad].
    z2 : number of pins.
    sigma : +1 reducer, -1 multiplier.

    Examples
    --------
    >>> float(pin_phase(25, 0.0, 50))  # exactly pi, although 2 pi/50 * 25 need not be
    3.141592653589793
    """
    pin = np.asarray(pin)
    t = np.asarray(theta, dtype=float) * (z2 / (2.0 * math.pi))
    m = np.floor(t)
    tau = t - m
    m = m.astype(np.int64)
    if sigma == REDUCER:
        j = np.mod(pin - m, z2)
        j = np.where((j == 0) & (tau > 0), z2, j)
        return math.pi * ((2.0 * j - 2.0 * tau) / z2)
    j = np.mod(m - pin, z2)
    return math.pi * ((2.0 * j + 2.0 * tau) / z2)


def lever_sum(theta, g: Cycloid, psi_star: float, sigma: int = REDUCER):
    """S(theta) = sum over the loaded pins of l_i^2 [mm^2], pointwise in theta (pins.md §4.4).

    Examples
    --------
    >>> g = Cycloid.from_curtate_ratio(21, 22, 3.9, 0.75, 1.95)
    >>> bool(lever_sum(0.1, g, np.pi) > 0)
    True
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
    """Pin normal forces F_i = T_sat |l_i|/S(theta) (zero off the loaded set) [N]  (pins.md §4.4).

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
    """
    psi, loaded = _pointwise_phases(theta, g, psi_star, sigma)
    lev = np.abs(lever_arm(psi, g))
    S = np.sum(np.where(loaded, lev * lev, 0.0), axis=0)
    return np.where(loaded, torque_sat * lev / S, 0.0)


def loss_ratio(theta, g: Cycloid, psi_star: float, mu_eff: float, sigma: int = REDUCER):
    """Instantaneous loss ratio lambda(theta) = mu_eff sum |l_i| |rho_i - R_b| / sum l_i^2  (pins.md §4.6).

    Pointwise in theta (membership 0 < psi~ < psi* decided at theta itself); the cycle integration
    uses :func:`cycle_loss_ratio` instead, which evaluates piece ends as one-sided limits.

    Examples
    --------
    >>> g = Cycloid.from_curtate_ratio(21, 22, 3.9, 0.75, 1.95)
    >>> a = loss_ratio([0.1], g, np.pi, 0.1, REDUCER); b = loss_ratio([-0.1], g, np.pi, 0.1, MULTIPLIER)
    >>> bool(abs(a[0] - b[0]) < 1e-13)
    True
    """
    psi, loaded = _pointwise_phases(theta, g, psi_star, sigma)
    lev = np.abs(lever_arm(psi, g))
    S = np.sum(np.where(loaded, lev * lev, 0.0), axis=0)
    num = np.sum(np.where(loaded, lev * np.abs(pitch_distance(psi, g) - g.R_b), 0.0), axis=0)
    return mu_eff * num / S


def full_circle_lever_sum(theta, z2: int, K1: float):
    """Closed form of sum over all pins of (l_i/r_p1)^2 (pins.md §4.8, identity 2).

    z2/2 - (z2 (1 - K1^2)/(2 K1^2)) Re[q/(1 - q)], q = K1^z2 exp(i z2 theta).

    Examples
    --------
    >>> round(float(full_circle_lever_sum(0.0, 1000, 0.5)), 9)
    500.0
    """
    q = K1 ** z2 * np.exp(1j * z2 * np.asarray(theta, dtype=float))
    return z2 / 2.0 - (z2 * (1.0 - K1 * K1) / (2.0 * K1 * K1)) * np.real(q / (1.0 - q))


# ============================================================ losses, rolling, efficiency (§4.5-4.7)

def rolling_condition(sliding_friction, bushing_radius, axle_friction, axle_radius, rolling_coefficient) -> bool:
    """Whether contact friction can drive the bushing: f R_b >= f_c r + f_k  (pins.md §4.5).

    Examples
    --------
    >>> rolling_condition(0.1, 1.95, 0.1, 0.95, 0.01)
    True
    """
    return sliding_friction * bushing_radius >= axle_friction * axle_radius + rolling_coefficient


def rotating_loss_coefficient(axle_friction, axle_radius, rolling_coefficient, bushing_radius):
    """Equivalent friction coefficient of a rolling bushing, mu_rot = (f_c r + f_k)/R_b  (pins.md §4.6).

    Examples
    --------
    >>> round(rotating_loss_coefficient(0.1, 0.95, 0.01, 1.95), 12)
    0.053846153846
    """
    return (axle_friction * axle_radius + rolling_coefficient) / bushing_radius


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


def contact_loss_power(force, speed, mu_eff):
    """Loss at one contact, P = mu_eff F v 1e-3 [W] (F [N], v [mm/s])  (pins.md §4.6).

    Examples
    --------
    >>> float(contact_loss_power(100.0, 1000.0, 0.1))
    10.0
    """
    return mu_eff * np.asarray(force) * np.asarray(speed) * 1e-3


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


# ============================================================ operating points (pins.md §4.5-4.7)
#
# The friction regime and the mapping from loss ratios to efficiencies and torques, for one operating
# point (floats) or many (arrays).  They take ``xp``: :data:`ARRAY_OPS` (numpy, arrays over points) or
# :data:`SCALAR_OPS` (one point, numpy float64 scalars).  Scalar float64 operations round exactly as the
# element operations on arrays do, and overflow or divide by zero to inf or NaN as they do, so one design
# computed on scalars equals the same design in a batch, bit for bit, without the cost of numpy calls on
# arrays of one element.

class _ScalarOps:
    """The few numpy functions of the operating-point formulas, for one point of scalars."""

    nan = math.nan

    @staticmethod
    def where(cond, a, b):
        return a if cond else b

    @staticmethod
    def maximum(a, b):
        return a if a != a or a >= b else b          # as np.maximum: NaN propagates

    abs = staticmethod(abs)

    @staticmethod
    def isnan(x) -> bool:
        return x != x

    @staticmethod
    def logical_not(x) -> bool:
        return not x

    @staticmethod
    def degrees(x):
        return x * (180.0 / math.pi)                 # as numpy's rad2deg

    @staticmethod
    def as_int(x) -> int:
        return int(x)


class _ArrayOps:
    """numpy for the formulas that take ``xp`` (see :class:`_ScalarOps`), over arrays of points."""

    def __getattr__(self, name):
        return getattr(np, name)

    @staticmethod
    def as_int(x):
        return np.asarray(x).astype(np.int64)


SCALAR_OPS = _ScalarOps()
"""``xp`` for one operating point of scalars."""
ARRAY_OPS = _ArrayOps()
"""``xp`` for arrays over operating points (numpy)."""


def pin_circle(z1, z2, eccentricity, pin_circle_radius, curtate_ratio, xp=ARRAY_OPS):
    r"""The pin-centre circle radius R_p and 1 - K1 from whichever of R_p and K1 is given (pins.md §4.1, §7).

    .. math::

        K_1 = \frac{e z_2}{k R_p}:\quad R_p = \frac{e z_2}{k K_1},\quad 1 - K_1 = \frac{k R_p - e z_2}{k R_p}

    (1 - K1 from R_p without the cancellation of 1 - e z2/(k R_p); as :meth:`Cycloid.from_pin_circle` and
    :meth:`Cycloid.from_curtate_ratio`.)

    Parameters
    ----------
    z1, z2 : int or array_like of int
        satellite teeth and pins (k = z2 - z1 >= 1).
    eccentricity : float or array_like
        e [mm].
    pin_circle_radius : float or array_like
        R_p [mm], NaN where K1 is given.
    curtate_ratio : float or array_like
        K1 [-], NaN where R_p is given (it wins where both are).
    xp : :data:`ARRAY_OPS` or :data:`SCALAR_OPS`

    Returns
    -------
    R_p [mm], 1 - K1 [-].

    Examples
    --------
    >>> pin_circle(20, 22, 3.9, math.nan, 0.75, SCALAR_OPS)       # R_p = 3.9 x 22/(2 x 0.75)
    (57.199999999999996, 0.25)
    >>> [round(float(v[0]), 12) for v in pin_circle(np.array([20]), np.array([22]), 3.9, np.array([57.2]),
    ...                                             np.array([np.nan]))]
    [57.2, 0.25]

    References
    ----------
    pins.md §4.1 (K1 = e z2/(k R_p)), §7 (give R_p or K1).
    """
    k = z2 - z1
    use_K1 = xp.logical_not(xp.isnan(curtate_ratio))
    R_p = xp.where(use_K1, eccentricity * z2 / (k * curtate_ratio), pin_circle_radius)
    one_minus_K1 = xp.where(use_K1, 1.0 - curtate_ratio, (k * R_p - eccentricity * z2) / (k * R_p))
    return R_p, one_minus_K1


def friction_regime(rotating, bushing_radius, axle_radius, sliding_friction, rolling_coefficient, axle_friction,
                    xp=ARRAY_OPS):
    r"""Effective friction coefficient and whether the pins roll, per operating point (pins.md §4.5-4.6).

    .. math::

        \mu_{eff} = \begin{cases} \mu_{rot} = (f_c r + f_k)/R_b & \text{rotating and } f R_b \ge f_c r + f_k \\
        f & \text{otherwise (fixed pins, or bushings that cannot turn: they slide)} \end{cases}

    Parameters
    ----------
    rotating : bool or array_like of bool
        whether the pins carry rotating bushings.
    bushing_radius : float or array_like
        R_b [mm].
    axle_radius : float or array_like
        r [mm]; NaN (absent) for fixed pins.
    sliding_friction : float or array_like
        f, tooth-pin sliding friction [-].
    rolling_coefficient : float or array_like
        f_k [mm].
    axle_friction : float or array_like
        f_c [-].
    xp : :data:`ARRAY_OPS` or :data:`SCALAR_OPS`

    Returns
    -------
    mu_eff : float or ndarray
        [-].
    rolls : bool or ndarray of bool
        rotating pins whose rolling condition holds (false for fixed pins).

    Examples
    --------
    >>> mu, rolls = friction_regime(True, 1.95, 0.95, 0.1, 0.01, 0.1, SCALAR_OPS)
    >>> round(mu, 12), bool(rolls)
    (0.053846153846, True)
    >>> friction_regime(np.array([True, False]), 1.95, np.array([0.95, np.nan]), 0.1, 0.01, 0.1)[0].tolist()
    [0.05384615384615384, 0.1]

    References
    ----------
    .. [1] A. P. Prudnikov, "Power losses in pins and teeth contact area of KHV-type planetary gearing",
       *Mashinostroenie* (seed 000); pins.md §4.5-4.6.
    """
    rolls = rotating & rolling_condition(sliding_friction, bushing_radius, axle_friction, axle_radius,
                                         rolling_coefficient)          # NaN r (fixed pins) compares False
    mu = xp.where(rolls, rotating_loss_coefficient(axle_friction, axle_radius, rolling_coefficient, bushing_radius),
                  sliding_friction)
    return mu, rolls


def efficiency_reducer_err(loss_ratio_mean, loss_ratio_err):
    r"""Error of the reducer efficiency from that of the loss ratio, E_HV = E/(1 + lambda_bar)^2  (pins.md §4.7).

    The first-order propagation of E through eta_HV = 1/(1 + lambda_bar) (|d eta_HV/d lambda_bar| E).

    Parameters
    ----------
    loss_ratio_mean : float or array_like
        lambda_bar [-].
    loss_ratio_err : float or array_like
        E, the error estimate of lambda_bar [-].

    Returns
    -------
    E_HV [-].

    Examples
    --------
    >>> efficiency_reducer_err(0.25, 1e-6)   # 1e-6/1.5625
    6.4e-07

    References
    ----------
    pins.md §4.7 (the efficiencies), §6 (the error estimate).
    """
    return loss_ratio_err / ((1.0 + loss_ratio_mean) * (1.0 + loss_ratio_mean))


def shaft_torques(torque, ratio, eta_vh, eta_hv, multiplier, torque_on_V, xp=ARRAY_OPS):
    r"""Shaft torques T_V (satellite output) and T_H (crank) from the torque given on one of them (pins.md §4.7).

    Input power = output power + loss, with the efficiency of the mode:

    .. math::

        \text{multiplier: } T_V = \frac{u T_H}{\eta_{VH}},\qquad
        \text{reducer: } T_V = \eta_{HV} u T_H,\qquad u = z_1/k

    Parameters
    ----------
    torque : float or array_like
        the torque given, on V when ``torque_on_V`` else on H [N·m].
    ratio : float or array_like
        u = z1/k [-].
    eta_vh, eta_hv : float or array_like
        the multiplier and reducer efficiencies [-] (NaN: the mode self-locks).
    multiplier : bool or array_like of bool
        multiplier mode (V drives H), else reducer.
    torque_on_V : bool or array_like of bool
        the torque is given on V, else on H.
    xp : :data:`ARRAY_OPS` or :data:`SCALAR_OPS`

    Returns
    -------
    T_V, T_H : float or ndarray
        [N·m] (the unit of ``torque``); NaN where the efficiency they need is.

    Examples
    --------
    >>> shaft_torques(100.0, 10.0, 0.75, 0.8, False, False, SCALAR_OPS)   # reducer: T_V = 0.8 x 10 x 100
    (800.0, 100.0)
    >>> shaft_torques(100.0, 10.0, 0.75, 0.8, True, False, SCALAR_OPS)[0]  # multiplier: 10 x 100/0.75
    1333.3333333333333

    References
    ----------
    .. [1] A. P. Prudnikov, "Power losses in pins and teeth contact area of KHV-type planetary gearing",
       *Mashinostroenie* (seed 000); pins.md §4.7, §4.9 (the friction-consistent efficiencies).
    """
    T = torque
    T_V = xp.where(torque_on_V, T, xp.where(multiplier, ratio * T / eta_vh, eta_hv * ratio * T))
    T_H = xp.where(torque_on_V, xp.where(multiplier, eta_vh * T / ratio, T / (eta_hv * ratio)), T)
    return T_V, T_H


@dataclass(frozen=True)
class EfficiencyTorques:
    """Efficiencies, self-locking and shaft torques per operating point (:func:`efficiency_torques`).

    NaN marks an undefined value (no multiplier efficiency when it self-locks, no T_V when it self-locks
    with the torque given on H).  Torques in the unit of the torque given (N·m in the product)."""

    locked: object
    eta_vh: object
    eta_vh_err: object
    eta_hv: object
    eta_hv_err: object
    efficiency: object
    efficiency_err: object
    self_locking: object
    T_V: object
    T_H: object
    torque_in: object
    torque_out: object


def efficiency_torques(loss_ratio_mean, loss_ratio_err, torque, ratio, multiplier, torque_on_V,
                       xp=ARRAY_OPS) -> EfficiencyTorques:
    r"""Efficiencies, self-locking and shaft torques from the cycle-mean loss ratio (pins.md §4.7).

    .. math::

        \eta_{VH} = 1 - \bar\lambda,\quad \eta_{HV} = \frac{1}{1 + \bar\lambda},\quad
        T_V = \frac{u T_H}{\eta_{VH}}\ \text{(multiplier)},\quad T_V = \eta_{HV} u T_H\ \text{(reducer)}

    The drive self-locks in the multiplier mode when lambda_bar >= 1.  Error of eta_HV:
    E/(1 + lambda_bar)^2; of eta_VH: E.

    Parameters
    ----------
    loss_ratio_mean : float or array_like
        lambda_bar [-].
    loss_ratio_err : float or array_like
        E, its error estimate [-].
    torque : float or array_like
        the torque given, on V when ``torque_on_V`` else on H [N·m].
    ratio : float or array_like
        u = z1/k [-].
    multiplier : bool or array_like of bool
        multiplier mode (V drives H), else reducer.
    torque_on_V : bool or array_like of bool
        the torque is given on the satellite shaft V, else on the crank H.
    xp : :data:`ARRAY_OPS` or :data:`SCALAR_OPS`

    Returns
    -------
    EfficiencyTorques

    Examples
    --------
    >>> et = efficiency_torques(0.25, 1e-9, 100.0, 10.0, False, False, SCALAR_OPS)
    >>> et.efficiency, et.T_V
    (0.8, 800.0)
    >>> et = efficiency_torques(np.array([0.25, 1.5]), 0.0, 100.0, 10.0, True, True)
    >>> et.self_locking.tolist(), et.efficiency.tolist()
    ([False, True], [0.75, nan])

    References
    ----------
    .. [1] A. P. Prudnikov, "Power losses in pins and teeth contact area of KHV-type planetary gearing",
       *Mashinostroenie* (seed 000); pins.md §4.7.
    """
    lam, E = loss_ratio_mean, loss_ratio_err
    locked = lam >= 1.0
    eta_vh = xp.where(locked, xp.nan, efficiency_multiplier(lam))
    eta_hv = efficiency_reducer(lam)
    eta_hv_err = efficiency_reducer_err(lam, E)
    T_V, T_H = shaft_torques(torque, ratio, eta_vh, eta_hv, multiplier, torque_on_V, xp)   # NaN: no warning
    return EfficiencyTorques(
        locked=locked, eta_vh=eta_vh, eta_vh_err=xp.where(locked, xp.nan, E), eta_hv=eta_hv,
        eta_hv_err=eta_hv_err, efficiency=xp.where(multiplier, eta_vh, eta_hv),
        efficiency_err=xp.where(multiplier, xp.where(locked, xp.nan, E), eta_hv_err),
        self_locking=locked & multiplier, T_V=T_V, T_H=T_H,
        torque_in=xp.where(multiplier, T_V, T_H), torque_out=xp.where(multiplier, T_H, T_V))


@dataclass(frozen=True)
class ScaledCycle:
    """The ideal level's unit cycle scaled to operating points (:func:`scale_unit_cycle`); NaN: undefined.

    torque_sat [N·mm per disc]; omega_V, |omega_V| [rad/s]; loss_mean, loss_peak, loss_max (one pin),
    loss_bound [W]; force_max [N]; force_phase, loss_phase [deg] (NaN where the force or loss is);
    spin_abs_max, spin_min, spin_max [rpm] (0 for pins that do not roll); spin_reversals (int);
    sliding_speed_max [m/s] (0 for rolling pins)."""

    torque_sat: object
    omega_V: object
    loss_mean: object
    loss_peak: object
    loss_max: object
    loss_bound: object
    force_max: object
    force_phase: object
    loss_phase: object
    spin_abs_max: object
    spin_min: object
    spin_max: object
    spin_reversals: object
    sliding_speed_max: object


def scale_unit_cycle(unit, loss_ratio_mean, mu_eff, rolls, sliding_friction, torque_V, n_discs, crank_speed_rpm,
                     z1, k, pin_radius, xp=ARRAY_OPS) -> ScaledCycle:
    r"""Scale the ideal level's unit cycle (unit torque, speed and friction) to operating points (pins.md §4.4-4.8).

    The rigid solution does not depend on the torque, the speed or the friction coefficient (pins.md
    §4.8 identity 8): forces scale with T_sat, speeds with omega_V, losses with mu_eff T_sat omega_V.

    .. math::

        T_{sat} = \frac{T_V}{n_d},\quad |\omega_V| = \omega_H \frac{k}{z_1},\quad
        F_{max} = T_{sat} \hat F,\quad P = \mu_{eff} T_{sat} |\omega_V| \hat P,\quad
        \bar P = \bar\lambda T_V |\omega_V|

    Parameters
    ----------
    unit : object
        the unit cycle per point (fields of :class:`IdealCycles`: force, total, loss, rel_min, rel_max,
        rel_abs, psi_0, psi_star [rad], force_phase, loss_phase [rad]).
    loss_ratio_mean : float or array_like
        lambda_bar = mu_eff x the unit loss ratio [-].
    mu_eff : float or array_like
        [-]; rolls : bool or array_like, the pins roll; sliding_friction : f [-].
    torque_V : float or array_like
        T_V [N·m] (:func:`efficiency_torques`).
    n_discs : int or array_like
        n_d.
    crank_speed_rpm : float or array_like
        n_H [rpm] (NaN: not given; the losses and speeds are then NaN).
    z1, k : int or array_like
        teeth of the satellite, tooth difference.
    pin_radius : float or array_like
        R_b [mm].
    xp : :data:`ARRAY_OPS` or :data:`SCALAR_OPS`

    Returns
    -------
    ScaledCycle

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> u = SimpleNamespace(force=0.01, total=0.02, loss=0.005, rel_min=-1.0, rel_max=2.0, rel_abs=2.0,
    ...                     psi_0=np.nan, psi_star=3.0, force_phase=1.0, loss_phase=1.5)
    >>> sc = scale_unit_cycle(u, 0.05, 0.1, False, 0.1, 100.0, 1, 1000.0, 20, 1, 2.0, SCALAR_OPS)
    >>> sc.force_max, sc.spin_abs_max
    (1000.0, 0.0)

    References
    ----------
    .. [1] A. P. Prudnikov, "Power losses in pins and teeth contact area of KHV-type planetary gearing",
       *Mashinostroenie* (seed 000); pins.md §4.4-4.8.
    """
    T_sat = units.nm_to_nmm(torque_V) / n_discs                            # N·mm per disc
    w_V = units.rpm_to_rad_s(crank_speed_rpm) * k / z1                      # |omega_V| [rad/s]
    F_max = T_sat * unit.force                                              # N
    spin_rpm = units.rad_s_to_rpm(w_V) / pin_radius                         # rpm per mm of rho - R_b
    v_max = w_V * unit.rel_abs                                              # mm/s
    zero = 0.0 * w_V
    P = mu_eff * T_sat * w_V
    return ScaledCycle(
        torque_sat=T_sat, omega_V=w_V, loss_mean=loss_ratio_mean * torque_V * w_V, loss_peak=P * unit.total,
        loss_max=P * unit.loss, loss_bound=xp.where(rolls, mu_eff, sliding_friction) * F_max * v_max * 1e-3,
        force_max=F_max, force_phase=xp.where(xp.isnan(F_max), xp.nan, xp.degrees(unit.force_phase)),
        loss_phase=xp.where(xp.isnan(P), xp.nan, xp.degrees(unit.loss_phase)),
        spin_abs_max=xp.where(rolls, spin_rpm * xp.maximum(xp.abs(unit.rel_min), xp.abs(unit.rel_max)), zero),
        spin_min=xp.where(rolls, spin_rpm * unit.rel_min, zero),
        spin_max=xp.where(rolls, spin_rpm * unit.rel_max, zero),
        spin_reversals=xp.as_int(rolls & (unit.psi_0 < unit.psi_star)),   # NaN (no reversal) compares False
        sliding_speed_max=xp.where(rolls, zero, v_max / units.MM_PER_M))


# ============================================================ cycle model (pins.md §4.6, §6)
#
# Over one period the load-side phases of the pins are psi_j(t) = 2 pi (j + t)/z2, j = 0 .. z2-1,
# t in [0, 1] (t = theta/T_p in the multiplier; t = 1 - theta/T_p in the reducer, by the mirror
# relation of §4.8 identity 5).  The loaded pins are a prefix j < J(t) with J = ceil(c - t),
# c = psi* z2/(2 pi); membership is decided at the piece midpoint.

def _loaded_count(t_mid, c):
    return np.ceil(c - np.asarray(t_mid, dtype=float)).astype(np.int64)


def cycle_breakpoints(g: Cycloid, psi_star: float, psi_0: float | None) -> np.ndarray:
    """Breakpoints of the cycle integrand in t = theta/T_p in [0, 1]  (pins.md §6, §12.12).

    0 and 1 (entry at psi~ = 0), the exit frac(psi* z2/2 pi), the spin reversal
    frac(psi_0 z2/2 pi) when psi_0 < psi*, and two geometric gradings:

    * K1 > 0.99: toward the entry t = 0 over the whole period, down to a quarter of the boundary
      layer width (1 - K1) z2/(2 pi); the layer's tail (1 - K1)^2/psi^2 is algebraic, so the grading
      must not stop at the first breakpoint;
    * a piece where a single pin carries the load (psi* barely above 2 pi/z2): lambda ~ 1/psi there,
      so toward that piece's start, down to its own distance from the entry.

    Examples
    --------
    >>> g = Cycloid.from_curtate_ratio(21, 22, 3.9, 0.75, 1.95)   # k = 1, z2 even: exit at t = 0
    >>> cycle_breakpoints(g, np.pi, None).tolist()
    [0.0, 1.0]
    """
    c = _exit_count(g, psi_star)
    pts = [0.0, 1.0, c - math.floor(c)]
    if psi_0 is not None and psi_0 < psi_star:
        c0 = psi_0 * g.z2 / (2.0 * math.pi)
        pts.append(c0 - math.floor(c0))
    pts = unique_sorted(np.array(pts))
    extra = []
    if g.one_minus_K1 < 0.01:
        extra.append(geometric_breakpoints(0.0, 1.0, g.one_minus_K1 * g.z2 / (2.0 * math.pi)))
    a, b = pts[:-1], pts[1:]
    for lo, hi in zip(a[_loaded_count(0.5 * (a + b), c) == 1], b[_loaded_count(0.5 * (a + b), c) == 1]):
        if lo > 0.0:
            extra.append(geometric_breakpoints(lo, hi, lo))
    return unique_sorted(np.concatenate([pts, *extra]))


def _exit_count(g, psi_star):
    """c = psi* z2/(2 pi), exact for k = 1."""
    return g.z2 / 2.0 if g.k == 1 else psi_star * g.z2 / (2.0 * math.pi)


@dataclass
class CycleState:
    """The loaded contacts at nodes t (one disc): rows j = 0 .. J_max-1 (load-side order).

    phase [rad], loaded (bool), lever |l| [mm], rho [mm], S = sum l^2 [mm^2] per node.
    """

    t: np.ndarray
    phase: np.ndarray
    loaded: np.ndarray
    lever: np.ndarray
    rho: np.ndarray
    S: np.ndarray


def cycle_state(t, t_mid, g: Cycloid, psi_star: float) -> CycleState:
    """Loaded-pin geometry at nodes t of pieces with midpoints t_mid (one-sided at piece ends).

    Examples
    --------
    >>> g = Cycloid.from_curtate_ratio(21, 22, 3.9, 0.75, 1.95)
    >>> st = cycle_state(np.array([0.0, 1.0]), np.array([0.5, 0.5]), g, np.pi)
    >>> st.loaded.sum(axis=0).tolist()    # k = 1: half the pins
    [11, 11]
    """
    t = np.asarray(t, dtype=float)
    c = _exit_count(g, psi_star)
    J = _loaded_count(t_mid, c)
    jmax = math.ceil(c) + 1
    j = np.arange(jmax)[:, None]
    phase = math.pi * ((2.0 * j + 2.0 * t[None, :]) / g.z2)
    loaded = j < J[None, :]
    lev = np.where(loaded, np.abs(lever_arm(phase, g)), 0.0)
    rho = pitch_distance(phase, g)
    S = np.sum(lev * lev, axis=0)
    return CycleState(t, phase, loaded, lev, rho, S)


def cycle_loss_ratio(t, t_mid, g: Cycloid, psi_star: float, mu_eff: float):
    """lambda at nodes t of the cycle (one-sided at piece ends)  (pins.md §4.6).

    Examples
    --------
    >>> g = Cycloid.from_curtate_ratio(21, 22, 3.9, 0.75, 1.95)
    >>> a = cycle_loss_ratio(np.array([0.3]), np.array([0.5]), g, np.pi, 0.1)
    >>> b = loss_ratio([0.3 * 2 * np.pi / 22], g, np.pi, 0.1, MULTIPLIER)
    >>> bool(abs(a[0] - b[0]) < 1e-13)
    True
    """
    return state_loss_ratio(cycle_state(t, t_mid, g, psi_star), g, mu_eff)


def state_loss_ratio(st: CycleState, g: Cycloid, mu_eff, n_discs: int = 1):
    r"""lambda at the nodes of a :class:`CycleState`, averaged over n_d discs (pins.md §4.6, §12.7).

    .. math::

        \lambda(t) = \mu_{eff} \frac{\sum_i |l_i| |\rho_i - R_b|}{\sum_i l_i^2},\qquad
        \lambda_{n_d}(t) = \frac{1}{n_d} \sum_{d=0}^{n_d-1} \lambda(t + \Delta_d)

    with the disc offsets Delta_d of :func:`disc_offsets` (one period = 1 in t).

    Parameters
    ----------
    st : CycleState
        the loaded contacts at nodes t (one disc).
    g : Cycloid
    mu_eff : float
        effective friction coefficient [-].
    n_discs : int
        n_d, discs in phase-shifted sets.

    Returns
    -------
    ndarray
        lambda at the nodes [-].

    Examples
    --------
    >>> g = Cycloid.from_curtate_ratio(21, 22, 3.9, 0.75, 1.95)
    >>> st = cycle_state(np.array([0.3]), np.array([0.5]), g, np.pi)
    >>> bool(state_loss_ratio(st, g, 0.1)[0] == cycle_loss_ratio(np.array([0.3]), np.array([0.5]), g, np.pi, 0.1)[0])
    True

    References
    ----------
    .. [1] A. P. Prudnikov, "Power losses in pins and teeth contact area of KHV-type planetary gearing",
       *Mashinostroenie* (seed 000); pins.md §4.6, §12.7.
    """
    lam = mu_eff * np.sum(st.lever * np.abs(st.rho - g.R_b), axis=0) / st.S
    if n_discs > 1:   # all discs: the mean of the discs' shifted histories (pins.md §12.7)
        lam = sum_over_discs(st.t, lam, disc_offsets(n_discs, g.z2), 1.0) / n_discs
    return lam


@dataclass(frozen=True)
class CycleDetail:
    """The ideal level's cycle at the nodes of its final grid (:func:`cycle_detail`), crank angle ascending.

    Per node: theta [deg], loss_ratio (all discs) [-], loss (all discs) [W] or None, loaded (pins of the
    first disc).  Per loaded contact of the first disc (row-major by node, then pin): contact_theta [deg],
    pin (index of the fixed ring), phase [deg], force [N] or None, sliding_speed [m/s] or None,
    pin_speed [rpm] or None, contact_loss [W] or None.  None: the torque or the crank speed is not known."""

    theta: np.ndarray
    loss_ratio: np.ndarray
    loss: np.ndarray | None
    loaded: np.ndarray
    contact_theta: np.ndarray
    pin: np.ndarray
    phase: np.ndarray
    force: np.ndarray | None
    sliding_speed: np.ndarray | None
    pin_speed: np.ndarray | None
    contact_loss: np.ndarray | None


def cycle_detail(g: Cycloid, sigma: int, st: CycleState, mu_eff: float, torque_sat, omega_V, rolls: bool,
                 n_discs: int = 1, denominator=None) -> CycleDetail:
    r"""Loss ratio, forces, speeds and losses at the nodes of the ideal level's cycle (pins.md §4.4-4.6, §8).

    The cycle variable t maps to crank angle theta = T_p t (multiplier; pin i = -j mod z2) or
    theta = T_p (1 - t) (reducer; pin i = j + 1 mod z2), by the mirror relation of pins.md §4.8.

    .. math::

        F_j = T_{sat} \frac{|l_j|}{\sum_i l_i^2},\quad v_j = |\omega_V| |\rho_j - R_b|,\quad
        \omega_{pin} = -\omega_V \frac{\rho_j - R_b}{R_b},\quad P_j = \mu_{eff} F_j v_j 10^{-3}

    Parameters
    ----------
    g : Cycloid
    sigma : int
        +1 reducer, -1 multiplier.
    st : CycleState
        the loaded contacts at the nodes t (:func:`cycle_state`).
    mu_eff : float
        [-].
    torque_sat : float or None
        T_sat per disc [N·mm] (None: unknown, e.g. self-locking with the torque on H).
    omega_V : float or None
        signed satellite speed [rad/s] (None: no crank speed).
    rolls : bool
        the pins roll.
    n_discs : int
        n_d.
    denominator : ndarray, optional
        D per node, F_j = T_sat |l_j|/D (the friction-consistent model, pins.md §4.9, :func:`crank_history`);
        default S = sum l^2 (friction-free forces, §4.4).

    Returns
    -------
    CycleDetail

    Examples
    --------
    >>> g = Cycloid.from_curtate_ratio(21, 22, 3.9, 0.75, 1.95)
    >>> st = cycle_state(np.array([0.0, 0.5, 1.0]), np.array([0.5, 0.5, 0.5]), g, np.pi)
    >>> d = cycle_detail(g, REDUCER, st, 0.1, 1000.0, -1.0, False)
    >>> d.theta.tolist() == sorted(d.theta.tolist()), bool(np.all(d.force >= 0)), d.loaded.tolist()  # k = 1: half
    (True, True, [11, 11, 11])

    References
    ----------
    .. [1] A. P. Prudnikov, "Power losses in pins and teeth contact area of KHV-type planetary gearing",
       *Mashinostroenie* (seed 000); pins.md §4.4-4.6, §8.
    """
    t = st.t
    Tp_deg = 360.0 / g.z2
    if denominator is not None:     # friction-consistent forces (pins.md §4.9)
        st = CycleState(st.t, st.phase, st.loaded, st.lever, st.rho, np.asarray(denominator, dtype=float))
    lam = state_loss_ratio(st, g, mu_eff, n_discs)
    if sigma == MULTIPLIER:      # theta = T_p t, pin i = -j mod z2
        theta, pin_shift, pin_sign = t * Tp_deg, 0, -1
    else:                        # theta = T_p (1 - t), pin i = j + 1 mod z2
        theta, pin_shift, pin_sign = (1.0 - t) * Tp_deg, 1, 1
    order = np.argsort(theta, kind="stable")
    have_P = torque_sat is not None and omega_V is not None
    loaded = st.loaded[:, order]
    jj, nn = np.nonzero(loaded.T)[1], order[np.nonzero(loaded.T)[0]]      # row-major by node, then pin
    F = torque_sat * st.lever[jj, nn] / st.S[nn] if torque_sat is not None else None
    v = sliding_speed(st.rho[jj, nn], g.R_b, omega_V) if omega_V is not None else None
    if omega_V is not None:
        spin = units.rad_s_to_rpm(pin_spin(st.rho[jj, nn], g.R_b, omega_V)) if rolls else np.zeros(jj.size)
        slide = np.zeros(jj.size) if rolls else v / units.MM_PER_M
    else:
        spin = slide = None
    return CycleDetail(
        theta=theta[order], loss_ratio=lam[order],
        loss=(lam * (n_discs * torque_sat * abs(omega_V) * 1e-3))[order] if have_P else None,
        loaded=st.loaded.sum(axis=0)[order], contact_theta=theta[nn], pin=(pin_sign * jj + pin_shift) % g.z2,
        phase=np.degrees(st.phase[jj, nn]), force=F, sliding_speed=slide, pin_speed=spin,
        contact_loss=contact_loss_power(F, v, mu_eff) if have_P else None)


@dataclass
class CycleIntegral:
    """Cycle mean of the loss ratio: value (Richardson), err (|Q_2N - Q_N|), and the quadrature."""

    loss_ratio: float
    loss_ratio_err: float
    converged: bool
    n_crank: int
    quad: QuadResult | None


def mean_loss_ratio(g: Cycloid, psi_star: float, psi_0: float | None, mu_eff: float, tol: float = 1e-6,
                    n_max: int = 2 ** 20, n_start: int = 16, n_initial=None) -> CycleIntegral:
    """Cycle mean lambda_bar = (1/T_p) integral of lambda over one period, with an honest error.

    Piecewise trapezoid between the breakpoints of :func:`cycle_pieces` (those of
    :func:`cycle_breakpoints`), doubled to ``tol`` (pins.md §6), with the integrator and integrand
    of :func:`ideal_cycles` (one gear).  mu_eff = 0 short-circuits to exactly 0 with error 0.

    Parameters
    ----------
    g : the gear; psi_star : end of the loaded arc [rad]; psi_0 : spin reversal phase or None [rad].
    mu_eff : f (fixed pins) or mu_rot (rolling pins) [-].
    tol : relative accuracy target.
    n_max : cap on crank-angle intervals per period.
    n_start : intervals of the first level.
    n_initial : intervals per piece of the first level (see :func:`~gearcalc.quadrature.integrate_pieces`).

    Returns
    -------
    CycleIntegral

    Examples
    --------
    >>> g = Cycloid.from_curtate_ratio(20, 22, 3.9, 0.75, 1.95)
    >>> r = mean_loss_ratio(g, crest_cutoff(g), None, 0.1)
    >>> bool(r.converged and r.loss_ratio_err < 1e-6 * r.loss_ratio)
    True
    """
    if mu_eff == 0.0:
        return CycleIntegral(0.0, 0.0, True, 0, None)
    ga = _as_arrays(g)
    ps = np.array([psi_star], dtype=float)
    a, b, owner = cycle_pieces(ga, ps, np.array([np.nan if psi_0 is None else psi_0]))
    unit = _unit_loss_ratio(_GearTable.of(ga, ps), owner)
    q = integrate_pieces(lambda x, mid, piece: mu_eff * unit(x, mid, piece), a, b, owner, 1, tol=tol,
                         n_max=n_max, n_start=n_start, n_initial=n_initial, first_levels=first_levels(tol))
    quad = QuadResult(value=q.value, err=q.err, trapezoid=q.trapezoid, n=int(q.n[0]), converged=bool(q.converged[0]),
                      levels=int(q.levels[0]), edges=np.concatenate((a, b[-1:])), n_piece=q.n_piece)
    return CycleIntegral(float(q.value[0]), float(q.err[0]), bool(q.converged[0]), int(q.n[0]), quad)


def disc_offsets(n_discs: int, z2: int) -> np.ndarray:
    """Shifts in t = theta/T_p of the discs' cycles, frac(d z2/n_d), d = 0 .. n_d-1  (pins.md §12.7).

    Examples
    --------
    >>> disc_offsets(2, 22).tolist()
    [0.0, 0.0]
    """
    d = np.arange(n_discs)
    return np.mod(d * z2, n_discs) / n_discs


def sum_over_discs(x, values, shifts, period, origin: float = 0.0, zero_outside: bool = False):
    """Sum over discs of a sampled periodic history, sum_d v(x + shift_d), by linear interpolation.

    Parameters
    ----------
    x : sample points, non-decreasing (repeated points hold one-sided limits).
    values : samples at x.
    shifts : the discs' shifts (0 for the first) [unit of x].
    period : the period of v [unit of x]; points are wrapped into [origin, origin + period).
    origin : start of the wrapped range.
    zero_outside : v = 0 outside [x[0], x[-1]] (a pin's history off its loaded arc).

    Returns
    -------
    The summed history at x.  Linear interpolation: error O(h^2) in the sample spacing h.

    Examples
    --------
    >>> sum_over_discs(np.array([0.0, 0.5, 1.0]), np.array([0.0, 1.0, 0.0]), [0.0, 0.5], 1.0).tolist()
    [1.0, 1.0, 1.0]
    """
    x = np.asarray(x, dtype=float)
    values = np.asarray(values, dtype=float)
    total = np.zeros_like(values)
    fill = 0.0 if zero_outside else None
    for s in shifts:  # a handful of discs: loop over discs, vectorised over samples
        y = np.mod(x + s - origin, period) + origin
        total += np.interp(y, x, values, left=fill, right=fill)
    return total


def disc_sum_peak(phase, values, n_d: int):
    """Peak over the cycle and the pins of a per-contact quantity summed over n_d discs, and its phase.

    The discs are 2 pi/n_d apart: a pin's history at phase psi is sum_d v(psi - 2 pi d/n_d) (pins.md
    §12.7), interpolated linearly between the samples (error O(h^2)).

    Parameters
    ----------
    phase : load-side phases of the loaded contacts of the first disc [rad], shape (n,).
    values : the quantity at those contacts, shape (n,).
    n_d : number of discs.

    Returns
    -------
    (peak, phase of the peak [rad]).

    Examples
    --------
    >>> disc_sum_peak(np.array([0.0, 1.0, 2.0]), np.array([0.0, 1.0, 0.0]), 1)
    (1.0, 1.0)
    """
    x, val = np.asarray(phase, dtype=float), np.asarray(values, dtype=float)
    order = np.argsort(x, kind="stable")
    x, val = x[order], val[order]
    shifts = -2.0 * np.pi * np.arange(n_d) / n_d
    pts = unique_sorted(np.concatenate([np.mod(x - s, 2.0 * np.pi) for s in shifts]))
    tot = np.zeros_like(pts)
    for s in shifts:  # a handful of discs; vectorised over the samples
        tot += np.interp(np.mod(pts + s, 2.0 * np.pi), x, val, left=0.0, right=0.0)
    i = int(np.argmax(tot))
    return float(tot[i]), float(pts[i])


# ============================================================ the ideal level vectorised over gears (§4, §6)
#
# The functions below solve the cycle model of many gears at once: numpy over gears, pins, crank
# angles.  Inside, a crank-angle node of gear o carries its J = ceil(c_o - t_mid) loaded contacts
# as consecutive *entries* of flat arrays (one per loaded pin and node), and sums over a node's
# contacts are np.bincount over the node index: sequential in contact order, so a gear's numbers do
# not depend on the gears computed with it (a batch equals one design at a time, bit for bit).

@dataclass
class _GearTable:
    """Per-gear constants of the cycle integrand, arrays of shape (m,), the gears sorted by z2."""

    z2: np.ndarray
    K1: np.ndarray
    omk: np.ndarray
    R_p: np.ndarray
    R_b: np.ndarray
    r_p1: np.ndarray
    c: np.ndarray
    omk2: np.ndarray = None
    """(1 - K1)^2, as a product of arrays (a numpy scalar's ``** 2`` calls pow(), which is not always the
    correctly rounded square: one gear alone would then differ from the same gear in a batch)."""
    Ze: np.ndarray = None
    """Z_e = z2/k (the curvature of the pin-centre curve, pins.md §4.2; the contact stress needs it)."""
    trig: dict = dataclass_field(default_factory=dict)
    """Per z2: (j, sin, cos) of the rows' half phases pi j/z2 (:func:`_contacts`), computed once."""

    def __post_init__(self):
        if self.omk2 is None:
            self.omk2 = self.omk * self.omk

    @classmethod
    def of(cls, g: Cycloid, psi_star):
        z1, z2 = np.asarray(g.z1), np.asarray(g.z2)
        k = z2 - z1
        e, R_p = np.asarray(g.e, dtype=float), np.asarray(g.R_p, dtype=float)
        c = np.where(k == 1, z2 / 2.0, np.asarray(psi_star) * z2 / (2.0 * math.pi))
        return cls(z2, e * z2 / (k * R_p), np.asarray(g.one_minus_K1, dtype=float), R_p,
                   np.asarray(g.R_b, dtype=float), e * z1 / k, c, Ze=z2 / k)

    def rows(self, z2: int, n: int):
        """(j, sin(pi j/z2), cos(pi j/z2)) for the rows j = 0 .. n-1, as columns (cached per z2; the values
        do not depend on how many rows were computed)."""
        have = self.trig.get(z2)
        if have is None or have[0].shape[0] < n:
            j = np.arange(max(n, int(np.ceil(self.c.max())) + 1))[:, None]
            half = math.pi * (j / z2)
            have = self.trig[z2] = (j, np.sin(half), np.cos(half))
        j, sa, ca = have
        return j[:n], sa[:n], ca[:n]

    def take(self, name: str, idx):
        """Field ``name`` at gear indices ``idx`` (a scalar when there is one gear: same values, fewer gathers)."""
        arr = getattr(self, name)
        return arr[0] if arr.size == 1 else arr[idx]

    def blocks(self, gi):
        """(slice, z2) of the runs of nodes whose gears have the same number of pins (gears sorted by z2)."""
        if self.z2.size == 1:
            return [(slice(None), int(self.z2[0]))]
        z = self.z2[gi]
        cuts = np.flatnonzero(z[1:] != z[:-1]) + 1
        edges = [0, *cuts.tolist(), z.size]
        return [(slice(lo, hi), int(z[lo])) for lo, hi in zip(edges[:-1], edges[1:]) if hi > lo]


FINAL_BLOCK_CELLS = 4_000_000
"""Nodes x contact rows of the final grid evaluated at once (about 32 MB an array): a batch of gears at a
tight --tol is evaluated a few gears at a time (cut at gear boundaries, so the numbers do not change)."""


def _bounded_blocks(blocks, gi, starts, rows: int):
    """The (slice, z2) blocks cut at gear boundaries into runs of at most FINAL_BLOCK_CELLS nodes x rows
    (a gear larger than that alone).  ``starts``: first node of each gear."""
    limit = max(1, FINAL_BLOCK_CELLS // max(rows, 1))
    for sl, zz in blocks:
        lo, hi = sl.start or 0, gi.size if sl.stop is None else sl.stop
        if hi - lo <= limit:
            yield sl, zz
            continue
        ends = [*starts[np.unique(gi[lo:hi])][1:].tolist(), hi]    # where each gear of the block ends
        a = prev = lo
        for end in ends:
            if end - a > limit and prev > a:
                yield slice(a, prev), zz
                a = prev
            prev = end
        yield slice(a, hi), zz


def _colsum(a):
    """Sums over the rows (axis 0) in row order, so that a column's sum does not depend on the padding
    rows (zeros) or on the other columns.  numpy reduces a C-ordered array over its outer axis row by
    row (sequentially) when there are several columns; a single column is a contiguous reduction, which
    numpy sums pairwise, so that case takes the (sequential) cumulative sum."""
    return a.sum(axis=0) if a.shape[1] > 1 else np.cumsum(a, axis=0)[-1]


def _contacts(x, mid, gi, G: _GearTable, z2: int, with_phase: bool = False):
    """Loaded contacts at nodes x (pieces with midpoints mid) of gears gi that all have z2 pins.

    Arrays of shape (rows j, nodes), j in load-side order; the rows beyond a node's J loaded contacts
    are padding (lever 0).  Returns J (loaded contacts per node), loaded, phase psi~ [rad] (or None),
    lever |l| [mm] and rho [mm].  Membership: j < J = ceil(c - mid) (pins.md §6, one-sided at piece
    ends); psi~ = 2 pi (j + t)/z2 (pins.md §4.1).  The half phase is a + b with a = pi j/z2 per row and
    b = pi t/z2 per node, so sin and cos of psi~/2 follow from the rows' and nodes' sines by the
    addition theorem (products instead of sines per contact: the trigonometric functions dominated
    the cost), and sin psi~ = 2 sin(psi~/2) cos(psi~/2); s and the lever arm then take the
    cancellation-free forms of :func:`s_factor` and :func:`lever_arm`.
    """
    J, j, loaded, lev, rho, _, _ = _contact_rows(x, mid, gi, G, z2)
    phase = 2.0 * math.pi * ((j + x) / z2) if with_phase else None
    return J, loaded, phase, lev, rho


def _contact_rows(x, mid, gi, G: _GearTable, z2: int):
    """The computation of :func:`_contacts`: J, row index j, loaded, lever |l| [mm], rho [mm], sin(psi~/2), s."""
    J = np.ceil(G.take("c", gi) - mid).astype(np.int64)
    j, sa, ca = G.rows(z2, int(J.max()))
    b = math.pi * (x / z2)
    sb, cb = np.sin(b), np.cos(b)
    sh = sa * cb + ca * sb                       # sin(psi/2)
    ch = ca * cb - sa * sb                       # cos(psi/2)
    loaded = j < J
    s = np.sqrt(G.take("omk2", gi) + 4.0 * G.take("K1", gi) * (sh * sh))
    lev = np.where(loaded, np.abs(G.take("r_p1", gi) * (2.0 * sh * ch) / s), 0.0)
    rho = G.take("R_p", gi) * s
    return J, j, loaded, lev, rho, sh, s


def _contacts_geo(x, mid, gi, G: _GearTable, z2: int):
    """:func:`_contacts` with the half-phase sine and s(psi) that the friction-consistent sums need.

    Returns J, lever |l| [mm], rho [mm], sin(psi~/2) and s (rows j, nodes); lever and rho by the very
    operations of :func:`_contacts` (the same numbers, bit for bit)."""
    J, _, _, lev, rho, sh, s = _contact_rows(x, mid, gi, G, z2)
    return J, lev, rho, sh, s


NODE_ROWS = ("N", "S", "rUx", "Sx", "Uy", "lever_max", "lever_row", "loss_max", "loss_row", "stress_max")
"""The rows of :func:`_node_sums`: what the friction-consistent model (pins.md §4.9) needs per node."""


def _node_sums(J, lev, rho, sh, s, G: _GearTable, gi):
    r"""Sums over a node's loaded contacts that do not depend on the friction (pins.md §4.9), rows :data:`NODE_ROWS`.

    In the crank frame (O1 = (e, 0), P = (r_p2, 0)) contact i has the unit normal
    n_i = (A_i - P)/rho_i = ((1 - K1 - 2 sin^2(psi/2))/s, sin(psi)/s) towards the pin centre, the lever
    |l_i| = r_p1 |sin psi|/s, rel_i = rho_i - R_b and sg_i = sign(rel_i) (the satellite slides along
    -sg_i z x n_i, since omega_V < 0).  Per node:

    .. math::

        N = \sum |l| |rel|,\ S = \sum l^2,\ r_{p1} U_x = -r_{p1} \sum sg\,|l| n_x,\
        S_x = \sum |l| n_x,\ U_y = -\sum sg\,l^2/r_{p1}

    then Q = N - r_p1 U_x, D_reducer = S - mu Q, D_multiplier = S + mu Q (:func:`consistent_node_values`).
    Also the largest |l| and |l| |rel| of a contact with their rows (the force and loss peaks), and the
    largest |l|/R_eff, R_eff = R_b (1 - R_b/rho_c) the reduced radius of pin and tooth (the contact stress;
    rho_c = R_p s^3/D_c of :func:`curvature_radius`, signed: the formula holds on both the convex and the
    concave part of the profile).  Padding rows (lever 0) add nothing."""
    rb = G.take("R_b", gi)
    r_p1 = G.take("r_p1", gi)
    rel = rho - rb
    sg = np.sign(rel)
    nx = (G.take("omk", gi) - 2.0 * (sh * sh)) / s
    lev2 = lev * lev
    K1, Ze = G.take("K1", gi), G.take("Ze", gi)
    Dc = 1.0 + K1 * K1 * Ze - K1 * (1.0 + Ze) * (1.0 - 2.0 * (sh * sh))
    r_eff = rb * (1.0 - rb * Dc / (G.take("R_p", gi) * (s * s * s)))
    out = np.empty((len(NODE_ROWS), J.size))
    out[0] = _colsum(lev * np.abs(rel))
    out[1] = _colsum(lev2)
    out[2] = -r_p1 * _colsum(sg * lev * nx)
    out[3] = _colsum(lev * nx)
    out[4] = -_colsum(sg * lev2) / r_p1
    rf = lev.argmax(axis=0)
    cols = np.arange(J.size)
    out[5], out[6] = lev[rf, cols], rf
    pl = lev * np.abs(rel)
    rp = pl.argmax(axis=0)
    out[7], out[8] = pl[rp, cols], rp
    out[9] = (lev / r_eff).max(axis=0)
    return out


GRID_ROWS = ("loss_ratio", "force", "loss", "total", "rel_first", "rel_last", "loaded")
"""The rows of :func:`_grid_rows`."""


def _grid_rows(J, lev, rel):
    """The integrand lambda/mu_eff and what the peaks need at each node, one gear (rows :data:`GRID_ROWS`).

    Per node, from its contacts (J loaded, lever arms |l|, rel = rho - R_b; pins.md §4.4-4.6, unit
    scalings): lambda/mu_eff, the largest force F/T_sat and the largest loss P/(T_sat |omega_V|) of a
    contact, the total loss, rho - R_b at the first and the last loaded contact, and J.  The same
    operations as the vectorised code for many gears (:func:`ideal_cycles`)."""
    S = _colsum(lev * lev)
    arel = np.abs(rel)
    out = np.empty((len(GRID_ROWS), J.size))
    out[0] = _colsum(lev * arel) / S
    force = lev / S
    loss = force * arel * 1e-3                     # contact_loss_power(force, |rho - R_b|, 1)
    force.max(axis=0, out=out[1])
    loss.max(axis=0, out=out[2])
    out[3] = _colsum(loss)
    out[4], out[5], out[6] = rel[0], rel[J - 1, np.arange(J.size)], J
    return out


def _unit_loss_ratio(G: _GearTable, piece_owner, grid_rows: bool = False):
    """The integrand lambda(t)/mu_eff of the cycle mean, for :func:`~gearcalc.quadrature.integrate_pieces`.

    With ``grid_rows`` (one gear), the rows of :func:`_grid_rows` follow it, which the quadrature carries
    to its final grid (the peaks need them there)."""
    if grid_rows:
        z2, R_b = int(G.z2[0]), G.R_b[0]

        def f_rows(x, mid, piece):
            J, lev, rho, sh, s = _contacts_geo(x, mid, None, G, z2)
            return np.concatenate((_grid_rows(J, lev, rho - R_b), _node_sums(J, lev, rho, sh, s, G, None)))
        return f_rows

    def f(x, mid, piece):
        gi = piece_owner[piece]
        out = np.empty(x.size)
        for sl, z2 in G.blocks(gi):
            g = gi[sl]
            _, _, _, lev, rho = _contacts(x[sl], mid[sl], g, G, z2)
            out[sl] = _colsum(lev * np.abs(rho - G.take("R_b", g))) / _colsum(lev * lev)
        return out
    return f


FIRST_LEVELS_MAX = 6
"""Most doublings of the first round (1024 intervals at n_start = 16): see :func:`first_levels`."""


def first_levels(tol: float) -> int:
    """Doublings evaluated in the first round of the cycle quadrature (speed only, never a result).

    A typical gear needs E ~ 3e-5 4^-L at level L, so L = 1 + ceil(log_4(3e-5/tol)), at least 2, and at
    most :data:`FIRST_LEVELS_MAX`: a round costs about as much as evaluating a few hundred nodes, so
    small levels are best guessed in one round, while beyond it a wrong guess costs a whole level (twice
    the nodes before it) and the next round's prediction from the observed rate of convergence
    (:func:`~gearcalc.quadrature.integrate_pieces`) is the better guess (the paper designs at tol = 1e-9
    need 8 or 9 levels).

    Examples
    --------
    >>> [first_levels(t) for t in (1e-3, 1e-6, 1e-9)]
    [2, 4, 6]
    """
    return min(FIRST_LEVELS_MAX, max(2, 1 + math.ceil(math.log(3e-5 / tol, 4))))


def _one_gear_pieces(z1: int, z2: int, psi_star: float, psi_0: float, one_minus_K1: float):
    """:func:`cycle_pieces` of one gear on Python floats (the same operations), or None when the gear needs
    a geometric grading (the vectorised code then calls :func:`cycle_breakpoints`)."""
    c = z2 / 2.0 if z2 - z1 == 1 else psi_star * z2 / (2.0 * math.pi)
    pts = [0.0, 1.0, c - math.floor(c)]
    if psi_0 < psi_star:                                    # False for NaN (no spin reversal)
        c0 = psi_0 * z2 / (2.0 * math.pi)
        pts.append(c0 - math.floor(c0))
    pts.sort()
    a, b = [], []
    for lo, hi in zip(pts[:-1], pts[1:]):
        if hi > lo:
            if lo > 0.0 and math.ceil(c - 0.5 * (lo + hi)) == 1:
                return None                                  # a single pin carries the load: graded
            a.append(lo)
            b.append(hi)
    if one_minus_K1 < 0.01:
        return None                                          # K1 > 0.99: graded
    return np.array(a), np.array(b), np.zeros(len(a), dtype=np.int64)


def cycle_pieces(g: Cycloid, psi_star, psi_0):
    """Smooth pieces of the cycle integrand of many gears in t = theta/T_p: (a, b, owner), gear by gear.

    The breakpoints are those of :func:`cycle_breakpoints`: 0, 1, the exit frac(psi* z2/2 pi) and the
    spin reversal frac(psi_0 z2/2 pi) when psi_0 < psi*, computed for all gears at once; a gear that
    needs a geometric grading (K1 > 0.99, or a piece where a single pin carries the load) gets
    :func:`cycle_breakpoints` itself.

    Parameters
    ----------
    g : gears with array fields, shape (m,).
    psi_star : psi* per gear [rad]; psi_0 : spin reversal phase per gear, NaN where none [rad].

    Examples
    --------
    >>> g = _as_arrays(Cycloid.from_curtate_ratio(20, 22, 3.9, 0.75, 1.95))
    >>> a, b, owner = cycle_pieces(g, crest_cutoffs(g), np.array([np.nan]))
    >>> a.size, float(a[0]), float(b[-1]), owner.tolist()
    (2, 0.0, 1.0, [0, 0])
    """
    z1, z2 = np.asarray(g.z1), np.asarray(g.z2)
    psi_star, psi_0 = np.asarray(psi_star, dtype=float), np.asarray(psi_0, dtype=float)
    m = z2.size
    if m == 1:
        one = _one_gear_pieces(int(z1.flat[0]), int(z2.flat[0]), float(psi_star.flat[0]), float(psi_0.flat[0]),
                               float(np.asarray(g.one_minus_K1).flat[0]))
        if one is not None:
            return one
    c = np.where(z2 - z1 == 1, z2 / 2.0, psi_star * z2 / (2.0 * math.pi))
    c0 = psi_0 * z2 / (2.0 * math.pi)
    with np.errstate(invalid="ignore"):
        f0 = np.where(psi_0 < psi_star, c0 - np.floor(c0), np.nan)
    pts = np.stack([np.zeros(m), np.ones(m), c - np.floor(c), f0], axis=1)
    pts.sort(axis=1)                                   # NaN (no spin reversal) last
    a, b = pts[:, :-1], pts[:, 1:]
    with np.errstate(invalid="ignore"):
        valid = b > a
        single = valid & (np.ceil(c[:, None] - 0.5 * (a + b)) == 1) & (a > 0.0)
    graded = (np.asarray(g.one_minus_K1) < 0.01) | np.any(single, axis=1)
    valid &= ~graded[:, None]
    owner = np.repeat(np.arange(m), valid.sum(axis=1))
    a, b = a[valid], b[valid]
    if np.any(graded):
        parts_a, parts_b, parts_o = [a], [b], [owner]
        for i in np.flatnonzero(graded):   # the rare graded gears, one by one
            gi = Cycloid(int(z1[i]), int(z2[i]), float(np.asarray(g.e)[i]), float(np.asarray(g.R_p)[i]),
                         float(np.asarray(g.R_b)[i]), float(np.asarray(g.one_minus_K1)[i]))
            bp = cycle_breakpoints(gi, float(psi_star[i]), None if np.isnan(psi_0[i]) else float(psi_0[i]))
            parts_a.append(bp[:-1])
            parts_b.append(bp[1:])
            parts_o.append(np.full(bp.size - 1, i))
        a, b, owner = np.concatenate(parts_a), np.concatenate(parts_b), np.concatenate(parts_o)
        order = np.argsort(owner, kind="stable")
        a, b, owner = a[order], b[order], owner[order]
    return a, b, owner


TOO_FEW_TEETH, UNDERCUT = 1, 2
"""Status codes of :class:`IdealCycles`: psi* <= 2 pi/z2 (pins.md §12.10); R_b >= min rho_c (§4.2)."""
TOO_COSTLY = 3
"""Status code: the sums over n_d discs (pins.md §12.7) on the final grid would exceed DISC_SAMPLES_MAX or
DISC_WORK_MAX (their size follows from n_d and the crank-angle grid that --tol needs, known only after the
quadrature); the gear's peaks are then not computed."""
DISC_SAMPLES_MAX = 10_000_000
"""n_d x loaded samples of one gear's disc sums: the merged phase grid and its sums, ~5 arrays of 8 bytes a
sample (~0.4 GB)."""
DISC_WORK_MAX = 200_000_000
"""n_d^2 x loaded samples of one gear's disc sums (n_d interpolations over n_d x samples points, ~45 ns each:
~10 s).  100 pins x 64 discs at --tol 1e-9 are 2.5e8 (11 s); at 1e-12, 8e9 (9.5 minutes)."""


@dataclass
class IdealCycles:
    """The ideal level's cycle solution of many gears in unit scalings (mu = 1, T_sat = 1 N·mm, |omega_V| = 1).

    Arrays over gears, shape (m,):

    psi_star, psi_0 : end of the loaded arc and spin-reversal phase (NaN: none) [rad];
    rho_c_min : least radius of curvature of the pin-centre curve over the loaded arc [mm];
    status : 0 (admissible), TOO_FEW_TEETH, UNDERCUT or TOO_COSTLY; the fields below are NaN where status != 0;
    loss_ratio, loss_ratio_err, converged, n_crank : the cycle mean of lambda at mu = 1, its error
        |Q_2N - Q_N| and the quadrature's acceptance and intervals (pins.md §6);
    force, force_phase : max over the cycle and the pins of F/T_sat (summed over the discs) [1/mm] and
        the load-side phase where it occurs [rad];
    loss, loss_phase : the same for P/(mu T_sat |omega_V|) [W per (N·mm·rad/s)];
    total : max over the cycle of the summed losses of all discs, per the same unit;
    rel_min, rel_max, rel_abs : extremes of rho - R_b and of |rho - R_b| over the loaded contacts [mm];
    loaded_min, loaded_max : pins carrying load (per disc).

    grid_t, grid_mid, grid_gear : the final crank-angle grid (t = theta/T_p) of every admissible gear,
    gear by gear (:meth:`grid`).
    """

    psi_star: np.ndarray
    psi_0: np.ndarray
    rho_c_min: np.ndarray
    status: np.ndarray
    loss_ratio: np.ndarray
    loss_ratio_err: np.ndarray
    converged: np.ndarray
    n_crank: np.ndarray
    force: np.ndarray
    force_phase: np.ndarray
    loss: np.ndarray
    loss_phase: np.ndarray
    total: np.ndarray
    rel_min: np.ndarray
    rel_max: np.ndarray
    rel_abs: np.ndarray
    loaded_min: np.ndarray
    loaded_max: np.ndarray
    grid_t: np.ndarray
    grid_mid: np.ndarray
    grid_gear: np.ndarray
    grid_sums: np.ndarray | None = None
    """The friction-independent node sums of :func:`_node_sums` on the final grid, rows :data:`NODE_ROWS`."""
    grid_weights: np.ndarray | None = None
    """Trapezoid weights of the final grid's nodes at its level L and at L-1, L-2 (every 2nd, 4th node),
    shape (3, nodes): a gear's weights of one level sum to 1 (the cycle mean over t = theta/T_p)."""
    table: object = None
    """The admissible gears' constants (:class:`_GearTable`, in their solve order ``solved``) and their pieces."""
    solved: np.ndarray | None = None
    pieces: tuple | None = None

    def grid(self, i: int):
        """(t, t_mid) of gear i's final grid (piece ends twice: the one-sided limits)."""
        at = np.flatnonzero(self.grid_gear == i)      # one contiguous run (the gears are not in index order)
        return self.grid_t[at], self.grid_mid[at]


REFINE_SAMPLES = 32
"""Samples of a peak's bracket (two grid intervals) before its parabolic vertex (:func:`ideal_cycles`)."""


def _peak_values(u, mid, gi, row, kind, G: _GearTable):
    """A peak candidate's quantity at crank angles u: kind 0 the force of contact ``row``, 1 its loss,
    2 the total loss of the node; with the load-side phase of contact ``row`` [rad].  The points are
    ordered by gear."""
    val, ph = np.empty(u.size), np.empty(u.size)
    for sl, z2 in G.blocks(gi):
        g = gi[sl]
        _, _, phase, lev, rho = _contacts(u[sl], mid[sl], g, G, z2, with_phase=True)
        force = lev / _colsum(lev * lev)
        loss = force * np.abs(rho - G.take("R_b", g)) * 1e-3          # contact_loss_power(force, |rho - R_b|, 1)
        col = np.arange(force.shape[1])
        r = row[sl]
        k = kind[sl]
        val[sl] = np.where(k == 0, force[r, col], np.where(k == 1, loss[r, col], _colsum(loss)))
        ph[sl] = phase[r, col]
    return val, ph


_REFINE_FRACTIONS = np.arange(REFINE_SAMPLES + 1) / REFINE_SAMPLES
_REFINE_FRACTIONS.setflags(write=False)


def _one_gear_peaks(t, tmid, piece, G: _GearTable, rows, refine: bool = True) -> dict:
    """The final-grid extremes and the refined peaks of :func:`ideal_cycles` for one gear with one disc.

    ``rows``: the rows of :func:`_grid_rows` after the first (the quadrature carried them) at the final grid
    (t, tmid, piece).  The same maxima (first occurrence: the first node holding the grid maximum, then the
    first contact of that node holding it) and the same parabolic refinement as the vectorised code for
    many gears, operation for operation, so that one design equals the same design in a batch bit for bit.
    The contact of a peak's node is found with the refining samples (one evaluation: the node's values are
    those the quadrature met, bit for bit); the bookkeeping of the three peaks (force, loss, total loss)
    runs on Python floats.  Returns the IdealCycles fields rel_min, rel_max, rel_abs, loaded_min,
    loaded_max, force, force_phase, loss, loss_phase and total of the gear.
    """
    z2 = int(G.z2[0])
    force, loss, tot, first, final, J = rows[:len(GRID_ROWS) - 1]
    # rho grows with the phase on [0, pi] (pins.md §4.2): rho - R_b is least at a node's first loaded
    # contact and largest at its last
    res = {"rel_min": first.min(), "rel_max": final.max(), "rel_abs": np.maximum(np.abs(first), np.abs(final)).max(),
           "loaded_min": J.min(), "loaded_max": J.max()}
    if not refine:              # the friction-free peaks are not wanted (friction-consistent model, pins.md §4.9)
        return res
    # grid maxima: the first node holding the maximum (its contact below)
    nds = [int(np.argmax(vals)) for vals in (force, loss, tot)]
    # each refined inside the grid intervals around its node, within the node's piece (one-sided ends)
    last = t.size - 1
    lo, hi = [], []
    for nd in nds:
        lo.append(t[nd - 1] if nd > 0 and piece[nd - 1] == piece[nd] else t[nd])
        hi.append(t[nd + 1] if nd < last and piece[nd + 1] == piece[nd] else t[nd])
    lo, hi = np.array(lo), np.array(hi)
    M = REFINE_SAMPLES
    n = M + 1
    u = lo[:, None] + (hi - lo)[:, None] * _REFINE_FRACTIONS                  # (3, M + 1)
    # the samples, and the force and loss peaks' grid nodes (for their contacts), in one evaluation
    x = np.concatenate((u.ravel(), t[nds[:2]]))
    mid = np.concatenate((np.repeat(tmid[nds], n), tmid[nds[:2]]))
    _, _, _, lev, rho = _contacts(x, mid, None, G, z2)
    F = lev / _colsum(lev * lev)
    P = F * np.abs(rho - G.R_b[0]) * 1e-3
    row_f, row_p = int(np.argmax(F[:, 3 * n])), int(np.argmax(P[:, 3 * n + 1]))
    contact = (row_f, row_p, 0)
    vals = (F[row_f, :n], P[row_p, n:2 * n], _colsum(P)[2 * n:3 * n])
    best = [force[nds[0]], loss[nds[1]], tot[nds[2]]]
    at = [t[nd] for nd in nds]                      # crank angle of the best value met so far
    xv = []
    for k in range(3):
        v, uk = vals[k], u[k]
        bi = int(np.argmax(v))
        bm = min(max(bi, 1), M - 1)
        f0, fm, fp = v[bm], v[bm - 1], v[bm + 1]
        den = fp - 2.0 * f0 + fm
        if 0 < bi < M and den < 0.0:
            xk = uk[bm] - 0.5 * (uk[bm + 1] - uk[bm]) * (fp - fm) / den
            xv.append(min(max(xk, uk[bm - 1]), uk[bm + 1]))
        else:
            xv.append(uk[bi])
        if v[bi] > best[k]:
            best[k], at[k] = v[bi], uk[bi]
    # the parabolas' vertices
    _, _, _, lev, rho = _contacts(np.array(xv), tmid[nds], None, G, z2)
    F = lev / _colsum(lev * lev)
    P = F * np.abs(rho - G.R_b[0]) * 1e-3
    vv = (F[row_f, 0], P[row_p, 1], _colsum(P)[2])
    for k, key in enumerate(("force", "loss", "total")):
        if vv[k] > best[k]:
            best[k], at[k] = vv[k], xv[k]
        res[key] = best[k]
        if key != "total":       # the load-side phase of the peak's contact, as _contacts computes it
            res[key + "_phase"] = 2.0 * math.pi * ((contact[k] + at[k]) / z2)
    return res


def admissibility(g: Cycloid):
    """(status, psi*, min rho_c) of many cycloidal gears (arrays of shape (m,)): status 0, TOO_FEW_TEETH
    (psi* <= 2 pi/z2, pins.md §12.10) or UNDERCUT (R_b >= min rho_c over the loaded arc, §4.2).  The ideal
    level's checks, also run by ``gearcalc check`` (gearcalc.kinds.pins.admissibility_problem)."""
    z2 = np.atleast_1d(g.z2)
    psi_star = crest_cutoffs(g)
    status = np.where(psi_star <= 2.0 * math.pi / z2, TOO_FEW_TEETH, 0)
    rho_c = np.atleast_1d(min_curvature_radius(g, psi_star))
    status = np.where((status == 0) & (np.asarray(g.R_b) >= rho_c), UNDERCUT, status)
    return status, psi_star, rho_c


def ideal_cycles(g: Cycloid, n_discs, tol: float = 1e-6, n_max: int = 2 ** 20, n_start: int = 16,
                 first_order_peaks: bool = True) -> IdealCycles:
    """Solve the ideal level (pins.md §4, §6) of many cycloidal gears at once, in unit scalings.

    For every gear: psi* (:func:`crest_cutoffs`), the admissibility checks (pins.md §4.2, §12.10),
    the spin reversal, the cycle mean of the loss ratio at mu = 1 (:func:`cycle_pieces` and the
    piecewise trapezoid of :func:`~gearcalc.quadrature.integrate_pieces`, all gears together), and on
    the final grid the peaks of the pin force, the pin loss and the total loss.  Each peak starts at
    its largest grid value; for one disc it is refined inside the two grid intervals around that node
    (the same piece only: piece ends stay one-sided) by ``REFINE_SAMPLES`` samples and the vertex of
    the parabola through the best sample and its neighbours, keeping the largest value met (the peak
    is a maximum of values actually evaluated, never an extrapolation).  With n_d > 1 discs the
    discs' histories are summed per pin and per crank angle (pins.md §12.7, :func:`disc_sum_peak`).

    A gear's numbers do not depend on the gears solved with it: the gears are processed in groups of
    equal z2 as (contact, node) arrays whose sums over contacts run in contact order (:func:`_colsum`),
    and the quadrature accumulates per gear (:func:`~gearcalc.quadrature.integrate_pieces`); so a batch
    gives, bit for bit, what each design gives alone.  One gear with one disc (a design computed alone)
    takes a shorter path to the same numbers: the integrand also returns what the peaks need per node
    (:func:`_grid_rows`), which the quadrature carries to its final grid, so the grid is not evaluated
    again, and :func:`_one_gear_peaks` refines the peaks with scalar bookkeeping.

    Parameters
    ----------
    g : gears whose fields are arrays of shape (m,).
    n_discs : discs per gear, shape (m,) (or a scalar).
    tol : relative accuracy target of the cycle mean.
    n_max : cap on crank-angle intervals per period; n_start : intervals of the first level.
    first_order_peaks : False: one gear with one disc whose friction-free peaks (force, loss, total and
        their phases) are not needed (they stay NaN): the friction-consistent model has its own
        (:func:`consistent_cycles`).

    Returns
    -------
    IdealCycles

    Examples
    --------
    >>> g = _as_arrays(Cycloid.from_curtate_ratio(20, 22, 3.9, 0.75, 1.95))
    >>> r = ideal_cycles(g, 1)
    >>> bool(r.status[0] == 0 and r.converged[0] and r.loss_ratio_err[0] <= 1e-6 * r.loss_ratio[0])
    True

    References
    ----------
    pins.md §4.2-4.6, §6, §12.1, §12.7, §12.10-12.12.
    """
    z2 = np.atleast_1d(g.z2)
    m = z2.size
    n_discs = np.zeros(m, dtype=np.int64) + n_discs
    status, psi_star, rho_c = admissibility(g)
    psi_0 = spin_reversal_phases(g)
    nan = np.full(m, np.nan)
    out = {k: nan.copy() for k in ("loss_ratio", "loss_ratio_err", "force", "force_phase", "loss", "loss_phase",
                                   "total", "rel_min", "rel_max", "rel_abs")}
    out.update(converged=np.zeros(m, dtype=bool), n_crank=np.zeros(m, dtype=np.int64),
               loaded_min=np.zeros(m, dtype=np.int64), loaded_max=np.zeros(m, dtype=np.int64))
    ok = np.flatnonzero(status == 0)
    if ok.size > 1:                                   # groups of equal z2 (then of similar loaded counts)
        ok = ok[np.lexsort((psi_star[ok], z2[ok]))]
    if ok.size == 0:
        empty = np.zeros(0)
        return IdealCycles(psi_star, psi_0, rho_c, status, grid_t=empty, grid_mid=empty,
                           grid_gear=np.zeros(0, dtype=np.int64), **out)
    gk = Cycloid(*(np.atleast_1d(v)[ok] for v in (g.z1, g.z2, g.e, g.R_p, g.R_b, g.one_minus_K1)))
    G = _GearTable.of(gk, psi_star[ok])
    n_ok = ok.size

    # the cycle mean of lambda at mu = 1, all gears together (pins.md §4.6, §6)
    a, b, owner = cycle_pieces(gk, psi_star[ok], psi_0[ok])
    jmax = int(np.ceil(G.c.max())) + 1
    alone = n_ok == 1 and n_discs[ok[0]] == 1      # one design: the same numbers, fewer array operations
    # chunks of about 2^14 contacts (at least 1024 nodes): the integrand's (contact, node) arrays then stay
    # in the cache; twice as fast per node as arrays of 2^20 at tol = 1e-9 (speed only: nodes are independent)
    q = integrate_pieces(_unit_loss_ratio(G, owner, grid_rows=alone), a, b, owner, n_ok, tol=tol, n_max=n_max,
                         n_start=n_start, first_levels=first_levels(tol), chunk=max(1024, 2 ** 14 // jmax))
    out["loss_ratio"][ok], out["loss_ratio_err"][ok] = q.value, q.err
    out["converged"][ok], out["n_crank"][ok] = q.converged, q.n

    # the final grid: loaded contacts, forces and losses (pins.md §4.4-4.6), per group of equal z2
    t, tmid, piece = q.grid()
    extra = dict(table=G, solved=ok, pieces=(a, b, owner))
    if alone:                                        # the grid's values came with the quadrature
        for key, value in _one_gear_peaks(t, tmid, piece, G, q.carried, first_order_peaks).items():
            out[key][ok[0]] = value
        return IdealCycles(psi_star, psi_0, rho_c, status, grid_t=t, grid_mid=tmid,
                           grid_gear=np.zeros(t.size, dtype=np.int64) + ok[0],
                           grid_sums=q.carried[len(GRID_ROWS) - 1:], grid_weights=_grid_weights(t, piece),
                           **extra, **out)
    gi = owner[piece]
    multi = n_discs[ok] > 1
    if multi.any():   # disc sums too large for the grid --tol needed: refused before any array is built
        bound = np.bincount(gi, minlength=n_ok) * (np.ceil(G.c).astype(np.int64) + 1) * n_discs[ok]
        costly = multi & ((bound > DISC_SAMPLES_MAX) | (bound * n_discs[ok] > DISC_WORK_MAX))
        if costly.any():
            status[ok[costly]] = TOO_COSTLY
            keep = ~costly[gi]
            t, tmid, piece, gi = t[keep], tmid[keep], piece[keep], gi[keep]
    gears = np.arange(n_ok)
    starts = np.searchsorted(gi, gears)                 # first node of each gear
    sums = np.empty((len(NODE_ROWS), t.size))
    one = n_discs[ok] == 1
    picks = np.zeros((3, n_ok), dtype=np.int64), np.zeros((3, n_ok), dtype=np.int64), np.zeros((3, n_ok))
    grid_phase = np.zeros((3, n_ok))
    for sl, zz in (_bounded_blocks(G.blocks(gi), gi, starts, jmax) if gi.size else ()):
        lo = sl.start or 0
        gb = gi[sl]
        J, loaded, _, lev, rho = _contacts(t[sl], tmid[sl], gb, G, zz)
        _, _, _, sh_, s_ = _contacts_geo(t[sl], tmid[sl], gb, G, zz)
        sums[:, sl] = _node_sums(J, lev, rho, sh_, s_, G, gb)
        force = lev / _colsum(lev * lev)
        rel = rho - G.take("R_b", gb)
        loss = force * np.abs(rel) * 1e-3              # contact_loss_power(force, |rho - R_b|, 1)
        tot = _colsum(loss)
        here = gb[np.flatnonzero(np.diff(gb, prepend=-1))]      # gears of the block (sorted), and their first nodes
        seg = starts[here] - lo
        oo = ok[here]
        cols = np.arange(J.size)
        # rho grows with the phase on [0, pi] (pins.md §4.2), so along a node's loaded contacts
        # rho - R_b is least at the first and largest at the last
        first, final = rel[0], rel[J - 1, cols]
        out["rel_min"][oo] = np.minimum.reduceat(first, seg)
        out["rel_max"][oo] = np.maximum.reduceat(final, seg)
        out["rel_abs"][oo] = np.maximum.reduceat(np.maximum(np.abs(first), np.abs(final)), seg)
        out["loaded_min"][oo] = np.minimum.reduceat(J, seg)
        out["loaded_max"][oo] = np.maximum.reduceat(J, seg)
        where = np.searchsorted(here, gb) if here.size > 1 else None
        for kind, vals in enumerate((force, loss, None)):
            if vals is None:
                node_row, node_val = np.zeros(J.size, dtype=np.int64), tot
            else:
                node_row = vals.argmax(axis=0)
                node_val = vals[node_row, cols]
            if here.size == 1:                               # grid maximum per gear, first occurrence
                nd = np.atleast_1d(np.argmax(node_val))
                best = node_val[nd]
            else:
                best = np.maximum.reduceat(node_val, seg)
                hit = np.flatnonzero(node_val == best[where])
                nd = hit[np.searchsorted(gb[hit], here)]
            picks[0][kind, here] = nd + lo
            picks[1][kind, here] = node_row[nd]
            picks[2][kind, here] = best
            grid_phase[kind, here] = 2.0 * math.pi * ((node_row[nd] + t[sl][nd]) / zz)    # as _contacts
        for i in here[~one[here]]:                       # several discs (pins.md §12.7): one by one
            n_d = int(n_discs[ok[i]])
            c0, c1 = starts[i] - lo, (starts[i + 1] if i + 1 < n_ok else t.size) - lo
            ld = loaded[:, c0:c1]
            samples = int(np.count_nonzero(ld))
            if n_d * samples > DISC_SAMPLES_MAX or n_d * n_d * samples > DISC_WORK_MAX:
                status[ok[i]] = TOO_COSTLY               # refused: the caller names gearing.discs and --tol
                continue
            ph = 2.0 * math.pi * ((np.arange(loaded.shape[0])[:, None] + t[sl][c0:c1]) / zz)
            out["force"][ok[i]], out["force_phase"][ok[i]] = disc_sum_peak(ph[ld], force[:, c0:c1][ld], n_d)
            out["loss"][ok[i]], out["loss_phase"][ok[i]] = disc_sum_peak(ph[ld], loss[:, c0:c1][ld], n_d)
            tt = t[lo + c0:lo + c1]
            out["total"][ok[i]] = float(sum_over_discs(tt, tot[c0:c1], disc_offsets(n_d, zz), 1.0).max())

    # peaks of one-disc gears: refined around the grid maxima (see the docstring)
    sel = np.flatnonzero(one)
    if sel.size:
        K, M = 3 * sel.size, REFINE_SAMPLES
        gsel = np.repeat(sel, 3)                                   # gear-major: groups stay contiguous
        kind = np.tile(np.arange(3), sel.size)
        nd, row = picks[0][kind, gsel], picks[1][kind, gsel]
        grid_best, grid_ph = picks[2][kind, gsel], grid_phase[kind, gsel]
        last = t.size - 1
        same_prev = (nd > 0) & (piece[np.maximum(nd - 1, 0)] == piece[nd])
        same_next = (nd < last) & (piece[np.minimum(nd + 1, last)] == piece[nd])
        lo = np.where(same_prev, t[np.maximum(nd - 1, 0)], t[nd])
        hi = np.where(same_next, t[np.minimum(nd + 1, last)], t[nd])
        u = lo[:, None] + (hi - lo)[:, None] * (np.arange(M + 1) / M)
        vals, phs = _peak_values(u.ravel(), np.repeat(tmid[nd], M + 1), np.repeat(gsel, M + 1),
                                 np.repeat(row, M + 1), np.repeat(kind, M + 1), G)
        vals, phs = vals.reshape(K, M + 1), phs.reshape(K, M + 1)
        r = np.arange(K)
        bi = np.argmax(vals, axis=1)
        bm = np.minimum(np.maximum(bi, 1), M - 1)
        f0, fm, fp = vals[r, bm], vals[r, bm - 1], vals[r, bm + 1]
        den = fp - 2.0 * f0 + fm
        interior = (bi > 0) & (bi < M) & (den < 0.0)
        xv = u[r, bm] - 0.5 * (u[r, bm + 1] - u[r, bm]) * (fp - fm) / np.where(interior, den, -1.0)
        xv = np.where(interior, np.minimum(np.maximum(xv, u[r, bm - 1]), u[r, bm + 1]), u[r, bi])
        vv, phv = _peak_values(xv, tmid[nd], gsel, row, kind, G)
        best, best_ph = grid_best, grid_ph
        better = vals[r, bi] > best
        best, best_ph = np.where(better, vals[r, bi], best), np.where(better, phs[r, bi], best_ph)
        better = vv > best
        best, best_ph = np.where(better, vv, best), np.where(better, phv, best_ph)
        best, best_ph = best.reshape(-1, 3), best_ph.reshape(-1, 3)
        okk = ok[sel]
        out["force"][okk], out["force_phase"][okk] = best[:, 0], best_ph[:, 0]
        out["loss"][okk], out["loss_phase"][okk] = best[:, 1], best_ph[:, 1]
        out["total"][okk] = best[:, 2]
    return IdealCycles(psi_star, psi_0, rho_c, status, grid_t=t, grid_mid=tmid, grid_gear=ok[gi], grid_sums=sums,
                       grid_weights=_grid_weights(t, piece), **extra, **out)


def _grid_weights(t, piece):
    """Trapezoid weights of a final grid's nodes (piece by piece, ends on every piece) at its level L and at
    L-1 and L-2 (every 2nd and 4th node of each piece; a final level has at least 4 intervals a piece,
    pins.md §6, §12.6), shape (3, nodes)."""
    w = np.zeros((3, t.size))
    if t.size == 0:
        return w
    new_piece = np.empty(t.size, dtype=bool)
    new_piece[0] = True
    np.not_equal(piece[1:], piece[:-1], out=new_piece[1:])
    start = np.flatnonzero(new_piece)
    count = np.concatenate((start[1:], [t.size])) - start
    run = np.repeat(np.arange(start.size), count)
    k = np.arange(t.size) - start[run]
    n = (count - 1)[run]
    h = ((t[start + count - 1] - t[start]) / (count - 1))[run]
    end = np.where((k == 0) | (k == n), 0.5, 1.0)
    w[0] = h * end
    w[1] = np.where(k % 2 == 0, 2.0 * h * end, 0.0)
    w[2] = np.where(k % 4 == 0, 4.0 * h * end, 0.0)
    return w


def consistent_node_values(sums, mu, sigma: int):
    r"""Friction-consistent forces, loss ratio and crank-bearing load at cycle nodes (pins.md §4.9), unit torque.

    From the friction-free node sums of :func:`_node_sums` (rows :data:`NODE_ROWS`) and mu = mu_eff.  The
    friction forces mu F_i act against the sliding; the moment balance of the satellite about O1 with
    F_i = c |l_i| gives

    .. math::

        c = \frac{T_{sat}}{D_\sigma},\quad D_{reducer} = S - \mu Q,\quad D_{multiplier} = S + \mu Q,\quad
        Q = N - r_{p1} U_x,\quad \lambda = \frac{P_{loss}}{T_{sat} |\omega_V|} = \frac{\mu N}{D_\sigma}

    and the crank-bearing force on the satellite B = -sum of the pin forces, in the crank frame (x along
    the crank arm O1):

    .. math::

        B_x = c (S_x \mp \mu U_y),\quad B_y = c (\pm S + \mu r_{p1} U_x)/r_{p1}\quad (\text{upper sign: reducer})

    and the crank torque T_H = O1 x B = e B_y (the torque the crank's shaft applies).  ``crank`` is the
    crank torque along the power flow, sigma T_H (the input torque of a reducer, the output torque of a
    multiplier).  A node with D <= 0 jams (no positive normal-force solution).

    Parameters
    ----------
    sums : ndarray, shape (len(NODE_ROWS), n)
        node sums of :func:`_node_sums` [mm^2, mm] (N, S, r_p1 U_x, S_x, U_y, ...).
    mu : float or ndarray, shape (n,)
        mu_eff [-].
    sigma : int
        +1 reducer, -1 multiplier.

    Returns
    -------
    dict of arrays (n,): D [mm^2], lam [-], c = F/(T_sat |l|) [1/mm^2], Bx, By = B/T_sat [1/mm], and
    jam (D <= 0).

    Examples
    --------
    >>> sums = np.array([[1.0], [4.0], [0.5], [0.1], [-0.2]] + [[0.0]] * 5)   # N, S, r_p1 U_x, S_x, U_y
    >>> v = consistent_node_values(sums, 0.1, REDUCER)
    >>> float(v["D"][0]), float(v["lam"][0])     # S - mu Q, Q = N - r_p1 U_x = 0.5
    (3.95, 0.02531645569620253)

    References
    ----------
    pins.md §4.9 [derived; checked against an independent model]; Blagojević et al. 2012 (model 2).
    """
    N, S, Q = sums[0], sums[1], sums[0] - sums[2]
    D = S - sigma * mu * Q
    with np.errstate(divide="ignore", invalid="ignore"):
        lam = mu * N / D
        c = 1.0 / D
    return {"D": D, "lam": lam, "c": c, "jam": ~(D > 0.0)}


@dataclass
class ConsistentCycles:
    """The friction-consistent model (pins.md §4.9) per operating point and mode, in unit scalings.

    Arrays of shape (2, P) (row 0 the reducer, row 1 the multiplier): loss_ratio, err, converged, jammed,
    n_crank; the others, of shape (P,), are those of each point's own mode (``mode``).

    loss_ratio, err, converged : cycle mean of lambda_sigma = P_loss/(T_sat |omega_V|), its error
        |Q_2N - Q_N| and the acceptance (pins.md §6); NaN where the mode jams;
    jammed : some crank angle has no positive normal-force solution (D <= 0);
    n_crank : crank-angle intervals of the grid the value comes from;
    force, force_phase : largest F/T_sat of a contact [1/mm] and its load-side phase [rad];
    loss, loss_phase : largest P/(mu T_sat |omega_V|) of a contact and its phase [rad]; total : largest summed
        one over the cycle;
    stress : largest F/(T_sat R_eff) [1/mm^2] (the Hertz peak pressure is sqrt(E* T_sat stress/(pi b)));
    bearing_max, bearing_mean : largest and mean |B|/T_sat of one disc's crank bearing [1/mm];
    crank_mean, crank_min, crank_max : crank torque along the power flow over T_sat, summed over the discs [-].
    The peaks are the largest values at the nodes of the final grid (error O(h^2)).
    """

    loss_ratio: np.ndarray
    err: np.ndarray
    converged: np.ndarray
    jammed: np.ndarray
    n_crank: np.ndarray
    force: np.ndarray
    force_phase: np.ndarray
    loss: np.ndarray
    loss_phase: np.ndarray
    total: np.ndarray
    stress: np.ndarray
    bearing_max: np.ndarray
    bearing_mean: np.ndarray
    crank_mean: np.ndarray
    crank_min: np.ndarray
    crank_max: np.ndarray


CONSISTENT_CHUNK_NODES = 2 ** 18
"""Points x final-grid nodes of the friction-consistent evaluation done at once (~20 arrays of 8 bytes a node:
~40 MB); a larger sweep is evaluated a chunk of points at a time (the same numbers: points are independent)."""
REFINE_BLOCK = 2 ** 20
"""(friction, mode) pairs x new nodes of the refining doublings evaluated at once (memory)."""
CONSISTENT_N_MAX = 2 ** 16
"""Cap of the refining quadrature of the friction-consistent model (intervals per period): near the jam limit
lambda has a pole beside the cycle and converges slowly; the value is then reported with its error."""


def _point_nodes(cyc: IdealCycles, gear):
    """Flat indices of the final-grid nodes of each point's gear, the point of each, and the counts."""
    gg = cyc.grid_gear
    if gear.size == 1 and cyc.solved.size == 1 and gg.size and gear[0] == cyc.solved[0]:   # one design
        return np.arange(gg.size), np.zeros(gg.size, dtype=np.int64), np.array([gg.size])
    order_start = np.flatnonzero(np.diff(gg, prepend=-1) != 0) if gg.size else np.zeros(0, dtype=np.int64)
    first = np.full(cyc.status.size, -1, dtype=np.int64)
    cnt = np.zeros(cyc.status.size, dtype=np.int64)
    if gg.size:
        runs = np.diff(np.append(order_start, gg.size))
        first[gg[order_start]] = order_start
        cnt[gg[order_start]] = runs
    counts = cnt[gear]
    pt = np.repeat(np.arange(gear.size), counts)
    starts = np.cumsum(counts) - counts
    idx = np.arange(int(counts.sum())) - starts[pt] + first[gear][pt]
    return idx, pt, counts


def consistent_cycles(cyc: IdealCycles, gear, mu, n_discs=1, tol: float = 1e-6, mode=None,
                      chunk_nodes: int = CONSISTENT_CHUNK_NODES) -> ConsistentCycles:
    """The friction-consistent efficiency model (pins.md §4.9) of operating points, both modes.

    Every point has a solved gear (``gear``: its index in the gears of ``cyc``, which must be admissible)
    and an effective friction mu_eff.  The friction-free node sums that :func:`ideal_cycles` keeps on its
    final grid give, at any friction, the friction-consistent loss ratio at every node
    (:func:`consistent_node_values`); its cycle mean follows from the same trapezoid rule on the same
    pieces, at the final level L and at L-1 and L-2 (every 2nd and 4th node): Richardson value
    Q_L + (Q_L - Q_{L-1})/3, error E = |Q_L - Q_{L-1}|, accepted when E <= max(tol |Q|, 1e-14) on the two
    last doublings (pins.md §6).  Where that is not accepted (friction near the jam limit), the doubling
    continues from the final grid, evaluating only the new nodes (:func:`_refine_consistent`), up to
    :data:`CONSISTENT_N_MAX`.  A mode jams where D <= 0 at some node.

    Parameters
    ----------
    cyc : IdealCycles
    gear : ndarray of int, shape (P,)
    mu : ndarray, shape (P,)
    n_discs : int or ndarray (P,)
    tol : relative accuracy target.
    mode : int or ndarray (P,), optional
        sigma of each point (+1 reducer, -1 multiplier; default multiplier): the mode whose forces, peaks,
        crank-bearing force and crank torque are computed (the cycle means are computed for both).
    chunk_nodes : int
        points x nodes evaluated at once (memory); more are evaluated a chunk of points at a time.

    Returns
    -------
    ConsistentCycles

    Examples
    --------
    >>> g = _as_arrays(Cycloid.from_curtate_ratio(10, 11, 1.95, 0.75, 1.755))   # pins.md §4.9 reference
    >>> cc = consistent_cycles(ideal_cycles(g, 1), np.array([0]), np.array([0.1]))
    >>> round(1.0 / (1.0 + float(cc.loss_ratio[0, 0])), 5), round(1.0 - float(cc.loss_ratio[1, 0]), 5)
    (0.83078, 0.84594)

    References
    ----------
    pins.md §4.9, §6.
    """
    gear = np.atleast_1d(np.asarray(gear, dtype=np.int64))
    P = gear.size
    mu = np.zeros(P) + mu
    n_d = np.zeros(P, dtype=np.int64) + n_discs
    sig = np.zeros(P, dtype=np.int64) + (MULTIPLIER if mode is None else mode)
    per_gear = np.bincount(cyc.grid_gear, minlength=cyc.status.size) if cyc.grid_gear.size else \
        np.zeros(cyc.status.size, dtype=np.int64)
    nodes = per_gear[gear]
    if P > 1 and int(nodes.sum()) > chunk_nodes:   # many points (a sweep): a chunk of points at a time
        chunk = np.cumsum(nodes) // chunk_nodes        # non-decreasing chunk number per point
        cuts = [0, *(np.flatnonzero(np.diff(chunk)) + 1).tolist(), P]
        parts = [consistent_cycles(cyc, gear[a:b], mu[a:b], n_d[a:b], tol, sig[a:b], chunk_nodes=1 << 62)
                 for a, b in zip(cuts[:-1], cuts[1:])]
        return ConsistentCycles(**{f: np.concatenate([getattr(q, f) for q in parts], axis=-1)
                                   for f in ConsistentCycles.__dataclass_fields__})
    idx, pt, counts = _point_nodes(cyc, gear)
    if P == 1 and idx.size == cyc.grid_t.size:           # one point on the whole grid: no gathers
        idx = slice(None)
        sums, w, t = cyc.grid_sums, cyc.grid_weights, cyc.grid_t
    else:
        sums, w, t = cyc.grid_sums[:, idx], cyc.grid_weights[:, idx], cyc.grid_t[idx]
    G = cyc.table
    if cyc.solved.size == 1:
        slot = np.zeros(P, dtype=np.int64)
    else:
        where = np.zeros(cyc.status.size, dtype=np.int64)
        where[cyc.solved] = np.arange(cyc.solved.size)  # a gear's row of the table (solved in z2 order)
        slot = where[gear]
    r_p1 = G.r_p1[slot]
    z2 = G.z2[slot]
    mu_n = mu[pt]
    block = np.full((15, P), np.nan)                    # one allocation for every field (rows as views)
    names = ("force", "force_phase", "loss", "loss_phase", "total", "stress", "bearing_max", "bearing_mean",
             "crank_mean", "crank_min", "crank_max")
    res = {"loss_ratio": block[0:2], "err": block[2:4]}
    res.update({k: block[4 + r] for r, k in enumerate(names)})
    conv = np.zeros((2, P), dtype=bool)
    jam = np.zeros((2, P), dtype=bool)
    n_crank = np.zeros((2, P), dtype=np.int64) + cyc.n_crank[gear]
    seg = np.cumsum(counts) - counts
    nonempty = counts > 0
    segs = seg[nonempty]
    cols = np.flatnonzero(nonempty)
    N, S, Q = sums[0], sums[1], sums[0] - sums[2]
    # the cycle means of both modes at once: rows 0 reducer (sigma = +1), 1 multiplier (sigma = -1)
    muQ = mu_n * Q
    D2 = np.stack((S - muQ, S + muQ))
    bad = ~(D2 > 0.0)
    any_bad = bool(bad.any())
    if any_bad:
        jam[:] = np.bincount(np.concatenate((pt, pt + P)), bad.ravel(), minlength=2 * P).reshape(2, P) > 0
        with np.errstate(divide="ignore", invalid="ignore"):
            lam2 = np.where(bad, 0.0, (mu_n * N) / D2)
    else:
        lam2 = (mu_n * N) / D2
    lam_m = (lam2[0], lam2[1])
    # the three levels' trapezoid sums of both modes in one (sequential, per bin) bincount
    pt6 = np.concatenate([pt + r * P for r in range(6)])
    q = np.bincount(pt6, (w[None, :, :] * lam2[:, None, :]).ravel(), minlength=6 * P).reshape(2, 3, P)
    E1, E0 = np.abs(q[:, 0] - q[:, 1]), np.abs(q[:, 1] - q[:, 2])
    ok = (E1 <= np.maximum(tol * np.abs(q[:, 0]), 1e-14)) & (E0 <= np.maximum(tol * np.abs(q[:, 1]), 1e-14))
    res["loss_ratio"][:] = np.where(jam, np.nan, q[:, 0] + (q[:, 0] - q[:, 1]) / 3.0)
    res["err"][:] = np.where(jam, np.nan, E1)
    conv[:] = ok & ~jam
    # forces, peaks, crank bearing and crank torque of each point's own mode
    sg = sig[pt]
    D = S - (sg * mu_n) * Q
    with np.errstate(divide="ignore", invalid="ignore"):
        c = np.where(D > 0.0, 1.0 / D, np.nan)
    F = sums[5] * c
    Bx = c * (sums[3] - sg * mu_n * sums[4])
    By = c * (sg * S + mu_n * sums[2]) / r_p1[pt]
    Bm = np.hypot(Bx, By)
    crank = sg * (r_p1[pt] / _ratio_of(G, slot)[pt]) * By   # sigma e B_y, e = r_p1/u
    Pl = sums[7] * c * 1e-3
    if segs.size:
        stacked = np.stack((F, Pl, N * c * 1e-3, sums[9] * c, Bm, crank))
        # the maxima are exact (no rounding): one point reduces its whole grid
        peak = np.fmax.reduce(stacked, axis=1)[:, None] if P == 1 else np.fmax.reduceat(stacked, segs, axis=1)
        for r, key in enumerate(("force", "loss", "total", "stress", "bearing_max", "crank_max")):
            res[key][cols] = peak[r]
        res["crank_min"][cols] = np.fmin.reduce(crank) if P == 1 else np.fmin.reduceat(crank, segs)
        for key, arr, row in (("force", F, 6), ("loss", Pl, 8)):     # the load-side phase of the peak's contact
            hit = np.flatnonzero(arr == res[key][pt])                 # (the first node holding the maximum)
            if hit.size:
                ph = pt[hit]
                first = np.ones(hit.size, dtype=bool)
                first[1:] = ph[1:] != ph[:-1]
                h, pts = hit[first], ph[first]
                res[key + "_phase"][pts] = 2.0 * math.pi * ((sums[row, h] + t[h]) / z2[pts])
    finite = np.isfinite(c)
    if not finite.all():
        Bm, crank_m = np.where(finite, Bm, 0.0), np.where(finite, crank, 0.0)
    else:
        crank_m = crank
    means = np.bincount(np.concatenate((pt, pt + P)), np.concatenate((w[0] * Bm, w[0] * crank_m)), minlength=2 * P)
    res["bearing_mean"], res["crank_mean"] = means[:P], means[P:] * n_d
    for i in np.flatnonzero(n_d > 1):          # the discs' torques summed (pins.md §12.7): a handful of points
        sl = slice(seg[i], seg[i] + counts[i])
        tot_c = sum_over_discs(t[sl], crank[sl], disc_offsets(int(n_d[i]), int(z2[i])), 1.0)
        if np.isnan(tot_c).all():              # the mode jams at every node: no crank torque (and no warning)
            res["crank_max"][i] = res["crank_min"][i] = np.nan
        else:
            res["crank_max"][i], res["crank_min"][i] = np.nanmax(tot_c), np.nanmin(tot_c)
    own_jam = np.where(sig == REDUCER, jam[0], jam[1])
    if own_jam.any():
        for key in ("force", "force_phase", "loss", "loss_phase", "total", "stress", "bearing_max", "bearing_mean",
                    "crank_mean", "crank_min", "crank_max"):
            res[key] = np.where(own_jam, np.nan, res[key])
    # continue the doubling where the final grid does not meet the tolerance (friction near the jam limit)
    redo_m, redo_p = np.nonzero(~conv & ~jam & (mu > 0.0)[None, :])
    mids = cyc.grid_mid[idx]
    us = slot[redo_p]
    for gs in (() if not us.size else [us[0]] if (us == us[0]).all() else np.unique(us)):   # per gear: its points
        # and modes together
        pick = np.flatnonzero(slot[redo_p] == gs)
        mm, pp = redo_m[pick], redo_p[pick]
        i0 = pp[0]
        sl = slice(seg[i0], seg[i0] + counts[i0])       # the gear's final grid (the same for all its points)
        lam0 = np.stack([lam_m[m][seg[i]:seg[i] + counts[i]] for m, i in zip(mm.tolist(), pp.tolist())])
        val, err, cv, nn, jm = _refine_consistent(cyc, int(gs), t[sl], mids[sl], w[:, sl], mu[pp],
                                                  np.where(mm == 0, REDUCER, MULTIPLIER), lam0, tol)
        res["loss_ratio"][mm, pp] = np.where(jm, np.nan, val)
        res["err"][mm, pp] = np.where(jm, np.nan, err)
        conv[mm, pp], n_crank[mm, pp] = cv, nn
        jam[mm, pp] |= jm
    zero = mu == 0.0                                   # f = f_k = f_c = 0: lambda = 0 exactly (pins.md §9)
    res["loss_ratio"][:, zero], res["err"][:, zero] = 0.0, 0.0
    conv[:, zero] = True
    return ConsistentCycles(converged=conv, jammed=jam, n_crank=n_crank, **res)


def _ratio_of(G: _GearTable, slot):
    """u = z1/k of the gears at ``slot`` of the table (Z_e - 1 = z1/k)."""
    return G.Ze[slot] - 1.0


def _refine_consistent(cyc: IdealCycles, slot: int, t, t_mid, w, mu, sigma, lam, tol: float):
    """Continue the doubling of the cycle quadrature (pins.md §6) of the friction-consistent lambda beyond the
    final grid of the first-order solve, for several (friction, mode) pairs of one gear at once, evaluating
    only the new nodes (their friction-free sums once for all pairs), until the rule accepts each pair
    (E <= max(tol |Q|, 1e-14) on two successive doublings) or :data:`CONSISTENT_N_MAX`.

    ``t, t_mid, w``: the gear's final grid (nodes piece by piece) and its trapezoid weights at levels L, L-1;
    ``mu, sigma``: per pair, shape (K,); ``lam``: lambda at the grid's nodes, shape (K, nodes).  Returns
    arrays over the pairs: Richardson value, E, accepted, intervals, jammed (D <= 0 at a new node)."""
    G = cyc.table
    z2 = int(G.z2[slot])
    new_piece = np.empty(t.size, dtype=bool)
    new_piece[0] = True
    np.not_equal(t_mid[1:], t_mid[:-1], out=new_piece[1:])
    start = np.flatnonzero(new_piece)
    count = np.concatenate((start[1:], [t.size])) - start
    a, b, n = t[start], t[start + count - 1], count - 1
    q_prev, q = (lam * w[1]).sum(axis=1), (lam * w[0]).sum(axis=1)
    ok_prev = np.abs(q - q_prev) <= np.maximum(tol * np.abs(q), 1e-14)   # the final grid's last doubling
    K = q.size
    value, err = np.full(K, np.nan), np.full(K, np.nan)
    conv, jam = np.zeros(K, dtype=bool), np.zeros(K, dtype=bool)
    n_out = np.zeros(K, dtype=np.int64)
    active = np.ones(K, dtype=bool)
    if G.z2.size == 1:               # one gear (a design alone): its table, with the rows' sines already cached
        G1 = G
    else:
        G1 = _GearTable(G.z2[slot:slot + 1], G.K1[slot:slot + 1], G.omk[slot:slot + 1], G.R_p[slot:slot + 1],
                        G.R_b[slot:slot + 1], G.r_p1[slot:slot + 1], G.c[slot:slot + 1], Ze=G.Ze[slot:slot + 1])
    mids = 0.5 * (a + b)
    while active.any():
        if 2 * int(n.sum()) > CONSISTENT_N_MAX:        # the cap: the best value and its error
            value[active] = q[active] + (q[active] - q_prev[active]) / 3.0
            err[active] = np.abs(q[active] - q_prev[active])
            n_out[active] = int(n.sum())
            break
        piece = np.repeat(np.arange(a.size), n)
        j = np.arange(int(n.sum())) - np.repeat(np.cumsum(n) - n, n)
        x = a[piece] + (b - a)[piece] * ((2 * j + 1) / (2 * n[piece]))
        J, lev, rho, sh, s = _contacts_geo(x, mids[piece], None, G1, z2)
        rel = rho - G1.R_b[0]
        nx = (G1.omk[0] - 2.0 * (sh * sh)) / s
        Nn = _colsum(lev * np.abs(rel))
        Sn = _colsum(lev * lev)
        Qn = Nn + G1.r_p1[0] * _colsum(np.sign(rel) * lev * nx)
        hp = ((b - a) / (2 * n))[piece]
        q_new = 0.5 * q
        act = np.flatnonzero(active)
        step = max(1, REFINE_BLOCK // max(x.size, 1))
        for c0 in range(0, act.size, step):             # (pairs, new nodes) blocks of bounded size
            kk = act[c0:c0 + step]
            D = Sn[None, :] - (sigma[kk] * mu[kk])[:, None] * Qn[None, :]
            bad = ~(D > 0.0).all(axis=1)
            jam[kk[bad]] = True
            n_out[kk[bad]] = 2 * int(n.sum())
            active[kk[bad]] = False
            with np.errstate(divide="ignore", invalid="ignore"):
                f = mu[kk][:, None] * Nn[None, :] / D
            q_new[kk] += (f * hp).sum(axis=1)             # row by row: a pair's sum does not depend on the others
        n = 2 * n
        ok = np.abs(q_new - q) <= np.maximum(tol * np.abs(q_new), 1e-14)
        done = active & ok & ok_prev
        value[done] = q_new[done] + (q_new[done] - q[done]) / 3.0
        err[done] = np.abs(q_new[done] - q[done])
        conv |= done
        n_out[done] = int(n.sum())
        active &= ~done
        q_prev, q, ok_prev = q, q_new, ok
    return value, err, conv, n_out, jam


def crank_history(g: Cycloid, psi_star: float, t, t_mid, mu_eff: float, sigma: int, consistent: bool = True):
    r"""Per node of a cycle grid: the force denominator D, the crank-bearing force and the crank torque, unit T_sat.

    The friction-consistent model of pins.md §4.9 (:func:`consistent_node_values`); with ``consistent``
    false the forces are the friction-free ones of §4.4 (D = S; the bearing force then has no friction
    part either).  t = theta/T_p in the cycle variable of :func:`cycle_state` (multiplier theta = T_p t,
    reducer theta = T_p (1 - t)).

    Returns
    -------
    dict of arrays over the nodes: D [mm^2] (F_i = T_sat |l_i|/D), lam [-], Bx, By (crank frame, x along
    the crank arm; per N·mm of T_sat) [1/mm], crank (the crank torque along the power flow over T_sat,
    sigma e B_y) [-], jam (D <= 0).

    Examples
    --------
    >>> g = Cycloid.from_curtate_ratio(21, 22, 3.9, 0.75, 1.95)
    >>> h = crank_history(g, np.pi, np.array([0.2]), np.array([0.5]), 0.0, REDUCER)
    >>> round(float(h["crank"][0]) * 21, 12)           # friction-free: T_H = T_sat/u
    1.0

    References
    ----------
    pins.md §4.9 (crank-bearing force, crank torque), §8 (the detail table).
    """
    G = _GearTable.of(_as_arrays(g), np.array([psi_star]))
    t = np.asarray(t, dtype=float)
    J, lev, rho, sh, s = _contacts_geo(t, np.asarray(t_mid, dtype=float), None, G, int(g.z2))
    sums = _node_sums(J, lev, rho, sh, s, G, None)
    v = consistent_node_values(sums, mu_eff if consistent else 0.0, sigma)
    mu = mu_eff if consistent else 0.0
    Bx = v["c"] * (sums[3] - sigma * mu * sums[4])
    By = v["c"] * (sigma * sums[1] + mu * sums[2]) / g.r_p1
    lam = mu_eff * sums[0] / v["D"]
    return {"D": v["D"], "lam": lam, "Bx": Bx, "By": By, "crank": sigma * g.e * By, "jam": v["jam"]}
