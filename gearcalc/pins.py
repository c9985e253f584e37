"""KHV planetary pin (lantern) gearing: per-pin friction losses and the efficiency they cause.

Pure physics over floats and numpy arrays (no I/O).  Units inside: N, mm, N·mm, rad, rad/s; a
power F [N]·v [mm/s]·1e-3 is in W.  Symbols follow ``pins.md`` (the spec):

* level ``formula``: the paper's per-pin maximum loss, eqs. (3)-(7) (Prudnikov, seed 000);
* level ``ideal``: the quasi-static rigid conjugate model of a cycloidal satellite (pins.md §4):
  profile and admissibility, crest cut-off psi*, lever arms, forces from equilibrium, sliding
  speeds, pin spin, losses, loss ratio over one crank-angle period, efficiency in both modes.

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

import numpy as np

from . import units
from .quadrature import QuadResult, geometric_breakpoints, integrate_piecewise
from .roots import find_root, minimize_golden

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
    """
    omega = units.rpm_to_rad_s(pin_speed_rpm)
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
    """Per-pin maximum losses of the paper (eqs. 3-7): forces [N], powers [W]."""

    F_tr1: float
    F_tr2: float
    P_tr1: float
    P_tr2: float
    P_tr: float


def formula_losses(normal_force, pin_speed_rpm, bushing_radius, axle_radius, rolling_coefficient,
                   axle_friction, paper_pi: bool = False) -> FormulaLosses:
    """The paper's maximum friction loss on one rotating pin, eqs. (3)-(7).

    F_tr1 = f_k F_n/R, F_tr2 = f_c F_n, P_tr1 = F_tr1 omega R 1e-3, P_tr2 = F_tr2 omega r 1e-3,
    P_tr = P_tr1 + P_tr2, with omega = pi n_pin/30.

    Parameters
    ----------
    normal_force : F_n [N].
    pin_speed_rpm : n_pin [rpm].
    bushing_radius : R [mm].
    axle_radius : r [mm].
    rolling_coefficient : f_k [mm].
    axle_friction : f_c [-].
    paper_pi : compute with pi = 3.14 (reproduces the paper's printed digits).

    Returns
    -------
    FormulaLosses

    Examples
    --------
    >>> round(formula_losses(1920, 14, 1.95, 0.95, 0.01, 0.1, paper_pi=True).P_tr, 3)  # paper 0.295 W
    0.295

    References
    ----------
    Prudnikov (seed 000), eqs. (3)-(7); pins.md §3.
    """
    omega = pin_angular_speed(pin_speed_rpm, paper_pi)
    f1 = rolling_friction_force(normal_force, rolling_coefficient, bushing_radius)
    f2 = axle_friction_force(normal_force, axle_friction)
    p1 = friction_power(f1, omega, bushing_radius)
    p2 = friction_power(f2, omega, axle_radius)
    return FormulaLosses(f1, f2, p1, p2, p1 + p2)


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


def crest_cutoff(g: Cycloid, n_scan: int = 1024) -> float:
    """End of the loaded arc psi* [rad]: pi for k = 1, else the first root of epsilon(psi) = -pi/z1.

    The function epsilon + pi/z1 is scanned on (0, pi] and its first sign change refined by the
    bracketed root finder (Chandrupatla) to 1e-15 rad (pins.md §4.3, §12.11).

    Examples
    --------
    >>> g = Cycloid.from_curtate_ratio(20, 22, 3.9, 0.75, 1.95)
    >>> 0 < crest_cutoff(g) < np.pi
    True
    """
    if g.k == 1:
        return math.pi
    psi = np.linspace(0.0, math.pi, n_scan + 1)[1:]
    h = contact_angle_offset(psi, g) + math.pi / g.z1
    first = int(np.argmax(h <= 0.0))
    if h[first] == 0.0:
        return float(psi[first])
    lo = psi[first - 1] if first > 0 else 0.0
    res = find_root(lambda x: contact_angle_offset(x, g) + math.pi / g.z1, lo, psi[first], xtol=1e-15)
    return float(res.root)


def spin_reversal_phase(g: Cycloid) -> float | None:
    """Phase psi_0 where rho(psi_0) = R_b (the pin's spin reverses), or None when R_b <= R_p (1 - K1).

    sin(psi_0/2) = sqrt(((R_b/R_p)^2 - (1 - K1)^2)/(4 K1))  (pins.md §4.5, §6).

    Examples
    --------
    >>> g = Cycloid.from_curtate_ratio(20, 22, 3.9, 0.75, 1.95)
    >>> spin_reversal_phase(g) is None
    True
    """
    q = g.R_b / g.R_p
    arg = (q * q - g.one_minus_K1 ** 2) / (4.0 * g.K1)
    if arg <= 0.0 or arg >= 1.0:
        return None
    return 2.0 * math.asin(math.sqrt(arg))


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


def min_curvature_radius(g: Cycloid, psi_star: float, n_scan: int = 2048) -> float:
    """Least radius of curvature of the convex part of the pin-centre curve over 0 <= psi <= psi* [mm].

    Scan, then golden-section refinement around the smallest sample; inf if no part is convex.
    The profile has no loops (undercut) when R_b < this value (pins.md §4.2).

    Examples
    --------
    >>> g = Cycloid.from_curtate_ratio(21, 22, 3.9, 0.75, 1.95)
    >>> round(min_curvature_radius(g, np.pi), 3) <= round(float(curvature_radius(np.pi, g)), 3)
    True
    """
    psi = np.linspace(0.0, psi_star, n_scan + 1)
    rc = curvature_radius(psi, g)
    rc = np.where(rc > 0, rc, np.inf)
    i = int(np.argmin(rc))
    if not np.isfinite(rc[i]):
        return math.inf
    lo, hi = psi[max(i - 1, 0)], psi[min(i + 1, n_scan)]

    def fun(x):
        r = curvature_radius(x, g)
        return np.where(r > 0, r, np.inf)

    res = minimize_golden(fun, lo, hi, rtol=1e-10)
    return float(min(res.fun, rc[i]))


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
    pts = np.unique(np.array(pts))
    extra = []
    if g.one_minus_K1 < 0.01:
        extra.append(geometric_breakpoints(0.0, 1.0, g.one_minus_K1 * g.z2 / (2.0 * math.pi)))
    a, b = pts[:-1], pts[1:]
    for lo, hi in zip(a[_loaded_count(0.5 * (a + b), c) == 1], b[_loaded_count(0.5 * (a + b), c) == 1]):
        if lo > 0.0:
            extra.append(geometric_breakpoints(lo, hi, lo))
    return np.unique(np.concatenate([pts, *extra]))


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
    st = cycle_state(t, t_mid, g, psi_star)
    num = np.sum(st.lever * np.abs(st.rho - g.R_b), axis=0)
    return mu_eff * num / st.S


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

    Piecewise trapezoid between the breakpoints of :func:`cycle_breakpoints`, doubled to
    ``tol`` (pins.md §6).  mu_eff = 0 short-circuits to exactly 0 with error 0.

    Parameters
    ----------
    g : the gear; psi_star : end of the loaded arc [rad]; psi_0 : spin reversal phase or None [rad].
    mu_eff : f (fixed pins) or mu_rot (rolling pins) [-].
    tol : relative accuracy target.
    n_max : cap on crank-angle intervals per period.
    n_start : intervals of the first level.
    n_initial : intervals per piece of the first level (see :func:`~gearcalc.quadrature.integrate_piecewise`).

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
    bp = cycle_breakpoints(g, psi_star, psi_0)
    q = integrate_piecewise(lambda t, m: cycle_loss_ratio(t, m, g, psi_star, mu_eff), bp, tol=tol,
                            n_max=n_max, n_start=n_start, n_initial=n_initial)
    return CycleIntegral(float(q.value[0]), float(q.err[0]), q.converged, q.n, q)


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
