"""KHV pin gearing, level ``contact``: compliant quasi-static contact model (pins.md §5).

Pure physics over floats and numpy arrays (no I/O).  Units inside: N, mm, N·mm, rad; speeds are
given per unit crank speed (omega_H = 1 rad/s), because the quasi-static solution depends on the
crank angle only, so a speed here is in mm/s per rad/s and scales with omega_H.

This level is needed for the circular-arc satellite, which is not conjugate to the pins, and for
cycloids with clearance or profile modifications.  At each crank angle theta the crank fixes the
satellite centre O1 = e u(theta); the satellite rotation phi = phi_nom + tau (tau = transmission
error, phi_nom = -k theta/z1) is the one unknown:

* the penetration delta of every pin/tooth pair at a given tau: circle-circle for circular-arc
  teeth (§5.3), the signed distance to the design pin-centre curve for cycloids (§5.2, a
  safeguarded Newton search on the profile parameter, crest corners for k >= 2);
* forces from a line-contact law (Hertz after ISO/TS 16281, Palmgren, or linear), compression only
  (§5.4);
* tau from the moment equilibrium of the satellite, M(tau) = M_req, by the shared bracketed root
  finder (:func:`gearcalc.roots.find_root`), batched over crank angles (§5.5);
* the satellite's angular speed by implicit differentiation, the contact-point velocities, the pin
  spin and the per-contact losses (§5.6), reusing the loss functions of :mod:`gearcalc.pins`;
* the cycle mean of the loss ratio with :func:`gearcalc.quadrature.integrate_piecewise`, the
  breakpoints (contact entry/exit, spin reversals) located by
  :func:`gearcalc.quadrature.sign_change_breakpoints` (§6).

Why a separate module: the formula and ideal levels (:mod:`gearcalc.pins`) are closed-form
geometry evaluated pointwise; this level carries its own state (profiles, a contact law, a solved
pose per crank angle, a cycle cache) and is only imported when a design needs it.  It reuses
:class:`gearcalc.pins.Cycloid`, :func:`~gearcalc.pins.pin_centre_curve`,
:func:`~gearcalc.pins.crest_cutoff`, :func:`~gearcalc.pins.tooth_profile`,
:func:`~gearcalc.pins.pin_phase` and the loss/efficiency functions there.

Frames.  The satellite frame has its origin at O1 and turns with the satellite (pins.md §5.1):
pin j at X_j = Rot(-phi)(A_j - O1).  A contact has the unit normal n pointing from the pin centre
into the satellite; the pin pushes the satellite with F n along the line through X_j, so its moment
about O1 is F (X_j x n).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from . import pins
from . import hertz
from .arrays import unique_sorted
from .pins import MULTIPLIER, REDUCER, Cycloid
from .quadrature import QuadResult, geometric_breakpoints, integrate_piecewise, sign_change_breakpoints
from .roots import bisect, find_root, minimize_golden

# ============================================================ contact laws (pins.md §5.4)

PALMGREN_COEFFICIENT = 3.84e-5
"""Palmgren's line contact: delta = 3.84e-5 Q^0.9 / b^0.8 (mm, N) [Harris & Kotzalas]."""
HERTZ_EXPONENT = hertz.LINE_LOAD_EXPONENT


def palmgren_line_constant(face_width):
    """Palmgren's line contact solved for the force: F = c delta^(10/9), c = b^(8/9)/3.84e-5^(10/9).

    Examples
    --------
    >>> 1.03 < palmgren_line_constant(10.0) / hertz.iso_contact_stiffness(10.0) < 1.05   # pins.md: within ~4 %
    True
    """
    return face_width ** (8.0 / 9.0) / PALMGREN_COEFFICIENT ** HERTZ_EXPONENT


@dataclass(frozen=True)
class ContactLaw:
    """A compression-only contact law F = c max(delta, 0)^p (N, mm).

    name : "hertz", "palmgren" or "linear"; constant : c; exponent : p (10/9 or 1).

    Examples
    --------
    >>> law = ContactLaw("linear", 1e5, 1.0)
    >>> law.force(np.array([-1e-3, 2e-3])).tolist()
    [0.0, 200.0]
    """

    name: str
    constant: float
    exponent: float

    def force(self, delta):
        """F(delta) [N]; 0 for delta <= 0."""
        delta = np.asarray(delta, dtype=float)
        if self.exponent == 1.0:
            return self.constant * np.maximum(delta, 0.0)
        out = np.zeros(delta.shape)
        on = delta > 0.0                      # few pairs touch: the power only where they do
        out[on] = self.constant * delta[on] ** self.exponent
        return out

    def force_on(self, delta, active):
        """F on a fixed active set: the law's smooth extension on the ``active`` pairs (a linear law goes on
        linearly below delta = 0), 0 elsewhere.  Used for one-sided derivatives at contact entry/exit."""
        if self.exponent == 1.0:
            return np.where(active, self.constant * np.asarray(delta, dtype=float), 0.0)
        return np.where(active, self.force(delta), 0.0)

    def deflection(self, force):
        """delta(F) [mm], the inverse of :meth:`force` for F >= 0."""
        return (np.asarray(force, dtype=float) / self.constant) ** (1.0 / self.exponent)


def contact_law(name: str, face_width=None, stiffness=None) -> ContactLaw:
    """The law of a design: hertz/palmgren need the face width b [mm], linear the stiffness k_lin [N/mm].

    Examples
    --------
    >>> contact_law("linear", stiffness=2e5).constant
    200000.0
    """
    if name == "linear":
        return ContactLaw("linear", float(stiffness), 1.0)
    if name == "palmgren":
        return ContactLaw("palmgren", float(palmgren_line_constant(face_width)), HERTZ_EXPONENT)
    return ContactLaw("hertz", float(hertz.iso_contact_stiffness(face_width)), HERTZ_EXPONENT)


# ============================================================ circular-arc teeth (pins.md §5.3)

def _unit(a):
    return np.cos(a), np.sin(a)


def tooth_centre_distance(R_t, g: Cycloid, n_scan: int = 64):
    """D(R_t): least distance from the tooth centre T_0 = R_t u(pi/z1) to the nominal pin-centre curves [mm].

    Minimum over every family b and over the curve parameter beta within two tooth pitches of the
    tooth: a dense scan, then golden-section refinement between the neighbouring samples
    (vectorised over R_t).  D(0) = R_p - e (pins.md §5.3).

    Parameters
    ----------
    R_t : radius of the circle of tooth centres [mm] (array-like).
    g : the pin gear (z1, z2, e, R_p; R_b is not used).
    n_scan : samples per tooth pitch and family.

    Returns
    -------
    D [mm], the shape of R_t.

    Examples
    --------
    >>> g = Cycloid.from_pin_circle(20, 22, 3.9, 57.2, 2.75)
    >>> round(float(tooth_centre_distance(0.0, g)), 9)     # R_p - e
    53.3
    """
    shape = np.shape(R_t)
    R_t = np.atleast_1d(np.asarray(R_t, dtype=float)).ravel()
    chi = math.pi / g.z1
    pitch = 2.0 * math.pi / g.z1
    beta = chi + np.linspace(-2.0 * pitch, 2.0 * pitch, 4 * n_scan + 1)
    tx, ty = R_t * math.cos(chi), R_t * math.sin(chi)
    best = np.full(R_t.shape, np.inf)
    best_b = np.zeros(R_t.shape, dtype=np.int64)
    best_i = np.zeros(R_t.shape, dtype=np.int64)
    for b in range(g.k):  # a handful of families; vectorised over beta and R_t
        cx, cy = pins.pin_centre_curve(beta, b, g)
        d2 = (cx[None, :] - tx[:, None]) ** 2 + (cy[None, :] - ty[:, None]) ** 2
        i = np.argmin(d2, axis=1)
        v = d2[np.arange(R_t.size), i]
        better = v < best
        best = np.where(better, v, best)
        best_b = np.where(better, b, best_b)
        best_i = np.where(better, i, best_i)
    lo = beta[np.maximum(best_i - 1, 0)]
    hi = beta[np.minimum(best_i + 1, beta.size - 1)]

    def dist2(x):
        a = (g.z2 / g.k) * x - 2.0 * math.pi * best_b / g.k
        cx = g.R_p * np.cos(x) - g.e * np.cos(a)
        cy = g.R_p * np.sin(x) - g.e * np.sin(a)
        return (cx - tx) ** 2 + (cy - ty) ** 2

    res = minimize_golden(dist2, lo, hi, rtol=1e-13)
    return np.sqrt(np.minimum(res.fun, best)).reshape(shape)


def _distance_grid(g: Cycloid, step: float):
    """D(R_t) on a grid from 0 to R_p + e no coarser than ``step`` [mm] (the scan of pins.md §5.3)."""
    top = g.R_p + g.e
    n = int(min(max(64, math.ceil(top / step)), 20000))
    grid = np.linspace(0.0, top, n + 1)
    return grid, tooth_centre_distance(grid, g)


def _first_root(fun, grid, values, xtol):
    """First sign change (from > 0 to <= 0) of sampled values, refined by the bracketed root finder."""
    below = np.nonzero(values <= 0.0)[0]
    if below.size == 0 or below[0] == 0:
        return None
    i = int(below[0])
    if values[i] == 0.0:
        return float(grid[i])
    return float(find_root(fun, grid[i - 1], grid[i], xtol=xtol).root)


def zero_backlash_tooth_circle(g: Cycloid, tooth_radius: float, grid=None) -> float | None:
    """R_t for zero backlash: the smallest root of D(R_t) = R_b + rho_t, or None if there is none [mm].

    D(R_t) is scanned outward from 0 on a grid finer than (R_b + rho_t)/4 and the first sign change
    is refined by the bracketed root finder to 1e-13 R_p (pins.md §5.3; D is not monotone in
    general).  ``grid`` may pass a precomputed (R_t, D) scan.

    Examples
    --------
    >>> g = Cycloid.from_pin_circle(20, 22, 3.9, 57.2, 2.75)
    >>> R_t = zero_backlash_tooth_circle(g, 5.0)
    >>> round(float(tooth_centre_distance(R_t, g)), 9)      # = R_b + rho_t
    7.75
    """
    target = g.R_b + tooth_radius
    if target >= g.R_p - g.e:
        return None
    if grid is None or grid[0][1] - grid[0][0] > target / 4.0:
        grid = _distance_grid(g, target / 4.0)
    return _first_root(lambda r: tooth_centre_distance(r, g) - target, grid[0], grid[1] - target, 1e-13 * g.R_p)


def full_tooth(g: Cycloid) -> tuple[float, float] | None:
    """The "full" circular tooth: rho_t = R_t(rho_t) sin(pi/z1) (adjacent teeth tangent at the root).

    Solved as the first root of D(R_t) - R_b - R_t sin(pi/z1) on the outward scan (the same root as
    the nested definition of pins.md §5.3 when the zero-backlash root of that rho_t is the first
    crossing, which is checked).  Returns (rho_t, R_t) [mm], or None when no tooth fits.

    Examples
    --------
    >>> g = Cycloid.from_pin_circle(20, 22, 3.9, 57.2, 2.75)
    >>> rho, R_t = full_tooth(g)
    >>> bool(abs(rho - R_t * np.sin(np.pi / 20)) < 1e-9)
    True
    """
    s = math.sin(math.pi / g.z1)
    if g.R_b >= g.R_p - g.e:
        return None
    grid = _distance_grid(g, g.R_b / 4.0)
    R_t = _first_root(lambda r: tooth_centre_distance(r, g) - g.R_b - r * s, grid[0],
                      grid[1] - g.R_b - grid[0] * s, 1e-13 * g.R_p)
    if R_t is None:
        return None
    rho = R_t * s
    check = zero_backlash_tooth_circle(g, rho, grid)
    if check is None or abs(check - R_t) > 1e-9 * g.R_p:     # the nested definition: bisect on rho
        def h(r):
            r = np.asarray(r, dtype=float)
            out = np.array([x - (zero_backlash_tooth_circle(g, float(x), grid) or 0.0) * s for x in r.flat])
            return out.reshape(r.shape)

        upper = (g.R_p - g.e - g.R_b) * (1.0 - 1e-9)
        if h(upper) <= 0.0:
            return None
        rho = float(bisect(h, 0.0, upper, xtol=1e-11 * g.R_p).root)
        R_t = zero_backlash_tooth_circle(g, rho, grid)
        if R_t is None:
            return None
    return float(rho), float(R_t)


# ============================================================ profiles: penetrations (pins.md §5.2-5.3)

@dataclass
class Pose:
    """Nominal pose data at crank angles theta (tau = 0), shape (z2, n) per pin.

    theta [rad] (n,); x0, y0: X_j at tau = 0 in the satellite frame [mm]; beta0: curve parameter
    phi_j + k theta/z1 [rad]; psi: pin phase phi_j - theta wrapped to (-pi, pi] [rad]; aux: the
    profile's own precomputed data.
    """

    theta: np.ndarray
    x0: np.ndarray
    y0: np.ndarray
    beta0: np.ndarray
    psi: np.ndarray
    aux: dict = field(default_factory=dict)


@dataclass
class Contacts:
    """Pin/tooth pairs at a pose: arrays (c, z2, n), c contacts per pin.

    delta: penetration [mm]; nx, ny: unit normal from the pin centre into the satellite
    (satellite frame); arm: X_j x n, the moment arm of the normal about O1 [mm]; xn: X_j . n [mm];
    switch: (s, c, z2, n) quantities whose sign changes mark a change of the contact's geometry (a
    cycloidal pin passing from its flank to a crest corner, where the contact stiffness jumps), or None.
    """

    delta: np.ndarray
    nx: np.ndarray
    ny: np.ndarray
    arm: np.ndarray
    xn: np.ndarray
    switch: np.ndarray | None = None
    branch: np.ndarray | None = None


class CircularProfile:
    """Convex circular-arc teeth: z1 circles of radius rho_t centred at R_t u((2m+1) pi/z1) (pins.md §5.3).

    Each pin meets the two teeth adjacent to it in polar angle: c = 2 contacts per pin, with
    delta = R_b + rho_t - |X_j - T_m| and n = (T_m - X_j)/|T_m - X_j|.
    """

    contacts_per_pin = 2

    def __init__(self, g: Cycloid, tooth_radius: float, tooth_circle_radius: float):
        self.g, self.rho_t, self.R_t = g, float(tooth_radius), float(tooth_circle_radius)

    def prepare(self, pose: Pose) -> None:
        z1 = self.g.z1
        gam = np.arctan2(pose.y0, pose.x0)
        m = np.floor((gam * z1 / math.pi - 1.0) / 2.0)          # tooth with chi_m just below gamma
        chi = (2.0 * np.stack([m, m + 1.0]) + 1.0) * math.pi / z1
        pose.aux["tx"], pose.aux["ty"] = self.R_t * np.cos(chi), self.R_t * np.sin(chi)

    def contacts(self, pose: Pose, x, y, branch=None) -> Contacts:
        tx, ty = pose.aux["tx"], pose.aux["ty"]
        dx, dy = tx - x, ty - y
        dist = np.hypot(dx, dy)
        nx, ny = dx / dist, dy / dist
        return Contacts(self.g.R_b + self.rho_t - dist, nx, ny, x * ny - y * nx, x * nx + y * ny)


class CycloidProfile:
    """Cycloidal teeth cut on the design curve: R_p + Delta R_p, equidistant R_b + Delta R_b (pins.md §5.2).

    delta_j = -d_j - Delta R_b, d_j the signed distance (positive outside) from X_j to the design
    pin-centre curve c_b of the pin's family, found by a safeguarded Newton search on beta at the
    nominal pose and updated by Newton steps for each tau; for k >= 2 a pin whose foot point lies
    beyond its tooth-space segment (|psi| > psi*) faces the crest corner instead.
    """

    contacts_per_pin = 1

    def __init__(self, g: Cycloid, radial_mod: float = 0.0, equidistant_mod: float = 0.0):
        self.g = g
        self.dRb = float(equidistant_mod)
        Rp = g.R_p + radial_mod
        k = g.k
        self.design = Cycloid(g.z1, g.z2, g.e, Rp, g.R_b + equidistant_mod, (k * Rp - g.e * g.z2) / (k * Rp))
        self.psi_star = pins.crest_cutoff(self.design)
        self.crests = g.k >= 2

    def _curve(self, beta, fam):
        """c_b, c_b', c_b'' of the design curve [mm, mm/rad, mm/rad^2]."""
        d = self.design
        ze = d.z2 / d.k
        a = ze * beta - 2.0 * math.pi * fam / d.k
        cb, sb, ca, sa = np.cos(beta), np.sin(beta), np.cos(a), np.sin(a)
        return (d.R_p * cb - d.e * ca, d.R_p * sb - d.e * sa,
                -d.R_p * sb + d.e * ze * sa, d.R_p * cb - d.e * ze * ca,
                -d.R_p * cb + d.e * ze * ze * ca, -d.R_p * sb + d.e * ze * ze * sa)

    def _newton(self, beta, fam, x, y, steps):
        for _ in range(steps):
            cx, cy, dx, dy, ddx, ddy = self._curve(beta, fam)
            rx, ry = cx - x, cy - y
            gval = rx * dx + ry * dy
            gder = dx * dx + dy * dy + rx * ddx + ry * ddy
            beta = beta - gval / gder
        return beta

    def foot_point(self, beta0, fam, x, y, tol: float = 1e-14, maxiter: int = 60):
        """Foot point beta* of X on c_b: root of g(beta) = (c_b - X).c_b' in beta0 +- pi k/(2 z1).

        Safeguarded Newton: a Newton step that leaves the bracket is replaced by bisection; stops at
        |d beta| < tol (pins.md §5.2).  Vectorised over pins and crank angles.
        """
        half = math.pi * self.g.k / (2.0 * self.g.z1)
        shape = np.shape(beta0)
        b0 = np.asarray(beta0, dtype=float).ravel()
        fam_all, x_all, y_all = (np.broadcast_to(a, shape).ravel() for a in (fam, x, y))
        beta, lo, hi = b0.copy(), b0 - half, b0 + half
        act = np.arange(b0.size)                       # iterate only the elements not yet converged
        for _ in range(maxiter):
            bt, fa = beta[act], fam_all[act]
            cx, cy, dx, dy, ddx, ddy = self._curve(bt, fa)
            rx, ry = cx - x_all[act], cy - y_all[act]
            gval = rx * dx + ry * dy
            gder = dx * dx + dy * dy + rx * ddx + ry * ddy
            lo_a = np.where(gval < 0.0, bt, lo[act])       # g < 0 before the foot point, > 0 after
            hi_a = np.where(gval > 0.0, bt, hi[act])
            lo[act], hi[act] = lo_a, hi_a
            with np.errstate(divide="ignore", invalid="ignore"):
                step = -gval / gder
            new = bt + step
            done = (gder > 0.0) & (np.abs(step) < tol)         # converged: keep the last Newton step
            bad = ~done & (~np.isfinite(new) | (new <= lo_a) | (new >= hi_a) | (gder <= 0.0))
            new = np.where(bad, 0.5 * (lo_a + hi_a), new)
            done |= np.abs(new - bt) < tol
            beta[act] = new
            act = act[~done]
            if act.size == 0:
                break
        return beta.reshape(shape)

    def prepare(self, pose: Pose) -> None:
        fam = np.mod(np.arange(self.g.z2), self.g.k)[:, None] * np.ones_like(pose.x0, dtype=np.int64)
        pose.aux["fam"] = fam
        pose.aux["beta"] = self.foot_point(pose.beta0, fam, pose.x0, pose.y0)
        if self.crests:
            zd = self.g.z1 / self.g.k
            ends = np.stack([pose.beta0 - (self.psi_star - pose.psi) / zd,    # psi = +psi*
                             pose.beta0 + (pose.psi + self.psi_star) / zd])   # psi = -psi*
            gx, gy = pins.tooth_profile(ends, fam[None], self.design)
            pose.aux["crest_x"], pose.aux["crest_y"] = gx, gy

    def contacts(self, pose: Pose, x, y, branch=None) -> Contacts:
        """``branch`` (z2, n), optional, forces the flank (-1) or a crest corner (0: +psi*, 1: -psi*)."""
        fam = pose.aux["fam"]
        beta = self._newton(pose.aux["beta"], fam, x, y, 2)   # from ~1e-3 rad: 1e-12 rad after two steps
        cx, cy, dx, dy, _, _ = self._curve(beta, fam)
        t = np.hypot(dx, dy)
        nx, ny = -dy / t, dx / t                          # inward normal (the outward one is (c'_y, -c'_x))
        d_out = -((x - cx) * nx + (y - cy) * ny)
        delta = -d_out - self.dRb
        switch = None
        if self.crests:
            zd = self.g.z1 / self.g.k
            psi_f = pose.psi - zd * (beta - pose.beta0)
            switch = np.stack([self.psi_star - psi_f, psi_f + self.psi_star])[:, None]
            side = np.where(psi_f > self.psi_star, 0, np.where(psi_f < -self.psi_star, 1, -1))
            if branch is not None:
                side = np.asarray(branch)[0]
            crest = side >= 0
            if np.any(crest):
                s = np.maximum(side, 0)
                gx = np.take_along_axis(pose.aux["crest_x"], s[None], axis=0)[0]
                gy = np.take_along_axis(pose.aux["crest_y"], s[None], axis=0)[0]
                ex, ey = gx - x, gy - y
                r = np.hypot(ex, ey)
                delta = np.where(crest, self.g.R_b - r, delta)
                nx = np.where(crest, ex / r, nx)
                ny = np.where(crest, ey / r, ny)
        ct = Contacts(delta[None], nx[None], ny[None], (x * ny - y * nx)[None], (x * nx + y * ny)[None], switch)
        ct.branch = side[None] if self.crests else None
        return ct


# ============================================================ equilibrium (pins.md §5.1, §5.5)

class NoEquilibrium(ValueError):
    """No satellite rotation within +-pi/z1 balances the torque at some crank angle."""

    def __init__(self, theta):
        super().__init__("no contact can carry the torque")
        self.theta = theta


@dataclass
class Solution:
    """The solved contact state at crank angles theta (n,), per contact (c, z2, n).

    tau: transmission error phi - phi_nom [rad]; dtau: d tau/d theta [-]; residual: M - M_req [N·mm];
    delta [mm], force [N], v_t: tangential speed of the satellite at the contact per unit crank
    speed [mm/s per rad/s] (positive along z x n); phase: load-side phase of each pin [rad] (z2, n);
    zeta: pin phase measured along time, theta - phi_j wrapped to (-pi, pi] [rad] (z2, n).
    """

    theta: np.ndarray
    tau: np.ndarray
    dtau: np.ndarray
    residual: np.ndarray
    delta: np.ndarray
    force: np.ndarray
    v_t: np.ndarray
    phase: np.ndarray
    zeta: np.ndarray
    switch: np.ndarray | None = None
    branch: np.ndarray | None = None


class ContactModel:
    """The satellite of one design under one torque: pose, penetrations, moment, equilibrium, speeds.

    Parameters
    ----------
    g : the pin gear (actual pins: z1, z2, e, R_p, R_b).
    profile : :class:`CircularProfile` or :class:`CycloidProfile`.
    law : the contact law.
    torque_sat : T_sat, torque per satellite [N·mm], > 0.
    sigma : +1 reducer (M_req = -T_sat), -1 multiplier (M_req = +T_sat)  (pins.md §5.5).
    friction : None (frictionless forces, the default) or (mu_eff, f, rolls): add the tangential
        friction forces to the moment balance (option ``contact.friction_in_equilibrium``, §5.5).
    """

    def __init__(self, g: Cycloid, profile, law: ContactLaw, torque_sat: float, sigma: int, friction=None):
        self.g, self.profile, self.law = g, profile, law
        self.torque_sat, self.sigma = float(torque_sat), sigma
        self.M_req = -self.torque_sat if sigma == REDUCER else self.torque_sat
        self.pins = np.arange(g.z2)[:, None]
        self.friction = friction
        self.diff_step = 1e-6

    # -- geometry -------------------------------------------------------------------------------
    def pose(self, theta) -> Pose:
        """Nominal satellite-frame pin positions at crank angles theta (tau = 0)."""
        g = self.g
        theta = np.atleast_1d(np.asarray(theta, dtype=float))
        beta0 = 2.0 * math.pi * self.pins / g.z2 + (g.k / g.z1) * theta[None, :]
        a = (g.z2 / g.z1) * theta[None, :]
        x0 = g.R_p * np.cos(beta0) - g.e * np.cos(a)
        y0 = g.R_p * np.sin(beta0) - g.e * np.sin(a)
        psi = pins.pin_phase(self.pins, theta[None, :], g.z2, REDUCER)   # phi_j - theta in (0, 2 pi]
        psi = np.where(psi > math.pi, psi - 2.0 * math.pi, psi)
        p = Pose(theta, x0, y0, beta0, psi)
        self.profile.prepare(p)
        return p

    def contacts(self, pose: Pose, tau, branch=None) -> Contacts:
        """Penetrations and normals with the satellite turned by tau from nominal (tau shape (n,))."""
        c, s = np.cos(tau), np.sin(tau)
        x = c * pose.x0 + s * pose.y0
        y = -s * pose.x0 + c * pose.y0
        return self.profile.contacts(pose, x, y, branch)

    def moment(self, pose: Pose, tau, traction=None, ref=None):
        """M(tau): total moment of the contact forces about O1, counter-clockwise positive [N·mm], (n,).

        ``traction`` (c, z2, n), optional: signed tangential force per unit normal force, +q meaning a
        force q F along +(z x n) on the satellite; its moment is q F (C . n), C = X + R_b n.
        ``ref`` = (active, branch), optional: evaluate on a fixed active set and contact branch (the
        smooth extension of one piece of the cycle, for one-sided derivatives at its ends).
        """
        if ref is None:
            ct = self.contacts(pose, tau)
            F = self.law.force(ct.delta)
        else:
            ct = self.contacts(pose, tau, ref[1])
            F = self.law.force_on(ct.delta, ref[0])
        if traction is None:
            return np.sum(F * ct.arm, axis=(0, 1))
        return np.sum(F * (ct.arm + traction * (ct.xn + self.g.R_b)), axis=(0, 1))

    # -- equilibrium ------------------------------------------------------------------------------
    def solve(self, theta, xtol: float = 1e-15, traction=None, pose=None):
        """tau at crank angles theta from M(tau) = M_req: bracket by doubling from 1e-9 rad, then Chandrupatla.

        M does not increase with tau for deflection-sized rotations; the solver relies only on the
        sign change (pins.md §5.5).  Raises :class:`NoEquilibrium` when no sign change exists within
        +-pi/z1.  Returns (pose, tau, residual).
        """
        pose = self.pose(theta) if pose is None else pose
        n = pose.theta.size
        G0 = self.moment(pose, np.zeros(n), traction) - self.M_req
        direction = np.where(G0 > 0.0, 1.0, -1.0)            # G decreasing: root on the side of sign(G0)
        lo, hi = np.zeros(n), np.zeros(n)
        h = 1e-9
        open_ = G0 != 0.0
        limit = math.pi / self.g.z1
        prev = np.zeros(n)
        while np.any(open_):
            step = min(h, limit)
            Gs = self.moment(pose, direction * step, traction) - self.M_req
            found = open_ & (np.sign(Gs) != np.sign(G0))
            lo = np.where(found, prev, lo)
            hi = np.where(found, direction * step, hi)
            open_ &= ~found
            prev = np.where(open_, direction * step, prev)
            if step >= limit and np.any(open_):
                raise NoEquilibrium(pose.theta[open_])
            h *= 2.0
        a, b = np.minimum(lo, hi), np.maximum(lo, hi)
        res = find_root(lambda t: self.moment(pose, t, traction) - self.M_req, a, b, xtol=xtol, rtol=0.0)
        tau = res.root
        return pose, tau, self.moment(pose, tau, traction) - self.M_req

    def state(self, theta, ref=None) -> Solution:
        """The solved state at crank angles theta: tau, d tau/d theta, forces, tangential speeds.

        ``ref`` = (active, branch) (c, z2, n), optional: the active set and contact branches of the
        piece of the cycle each theta belongs to; the derivative d tau/d theta is then the one-sided
        limit from inside that piece (at a piece end, where a contact enters or changes branch, the
        central difference would straddle a jump of the contact stiffness).
        With ``friction``, the tangential forces take their directions from the previous solution and
        the equilibrium is re-solved until the directions no longer change (a fixed point, at most 8
        passes; pins.md §5.5).
        """
        pose, tau, residual = self.solve(theta)
        sol = self._kinematics(pose, tau, residual, None, ref)
        if self.friction is None:
            return sol
        traction = None
        for _ in range(8):
            new = self.traction(sol)
            if traction is not None and np.array_equal(new, traction):
                break
            traction = new
            _, tau, residual = self.solve(theta, traction=traction, pose=pose)
            sol = self._kinematics(pose, tau, residual, traction, ref)
        return sol

    def reference(self, theta):
        """(active, branch) of the solved state at theta: the fixed sets of the pieces with these midpoints."""
        sol = self.state(theta)
        return sol.force > 0.0, sol.branch

    def traction(self, sol: Solution):
        """Tangential force per unit normal force against the sliding (pins.md §5.5, §5.6).

        Fixed pins: -f sign(v_t) at every contact.  Rolling pins: -mu_rot sign(v_t) at the contact with
        the larger force (the rolling resistance), -f sign(v_t - omega_pin R_b) at the other one.
        """
        mu_eff, f, rolls = self.friction
        v = sol.v_t
        if not rolls:
            return -f * np.sign(v)
        lead = np.argmax(sol.force, axis=0)
        v_lead = np.take_along_axis(v, lead[None], axis=0)
        is_lead = np.arange(v.shape[0])[:, None, None] == lead[None]
        return np.where(is_lead, -mu_eff * np.sign(v), -f * np.sign(v - v_lead))

    def _kinematics(self, pose: Pose, tau, residual, traction, ref=None) -> Solution:
        g = self.g
        th = pose.theta
        # d tau/d theta = -G_theta/G_tau by central differences (pins.md §5.6), at fixed tau
        h = self.diff_step * g.period
        p_plus, p_minus = self.pose(th + h), self.pose(th - h)
        G_th = (self.moment(p_plus, tau, traction, ref) - self.moment(p_minus, tau, traction, ref)) / (2.0 * h)
        h_tau = h * g.k / g.z1
        G_tau = (self.moment(pose, tau + h_tau, traction, ref)
                 - self.moment(pose, tau - h_tau, traction, ref)) / (2.0 * h_tau)
        dtau = -G_th / G_tau
        ct = self.contacts(pose, tau)
        force = self.law.force(ct.delta)
        # contact velocity (omega_H = 1): v = z x O1 + w1 z x (C - O1); v_t = v.(z x n)
        #   = O1'.n + w1 (C.n), O1' = e u(theta - phi) and C = X + R_b n in the satellite axes
        w1 = -g.k / g.z1 + dtau
        ang = (g.z2 / g.z1) * th - tau
        o_n = g.e * (np.cos(ang) * ct.nx + np.sin(ang) * ct.ny)
        v_t = o_n + w1 * (ct.xn + g.R_b)
        phase = pins.pin_phase(self.pins, th[None, :], g.z2, self.sigma)
        zeta = -pose.psi
        return Solution(th, tau, dtau, residual, ct.delta, force, v_t, phase, zeta, ct.switch, ct.branch)

    def bearing_force(self, sol: Solution, traction=None):
        """Force B of the crank bearing on the satellite (crank-frame axes turned by phi) [N], (2, n).

        Satellite equilibrium: B = -sum (F n + q F (z x n)) (the coupling gives a pure torque).
        """
        pose = self.pose(sol.theta)
        ct = self.contacts(pose, sol.tau)
        q = 0.0 if traction is None else traction
        fx = sol.force * (ct.nx - q * ct.ny)
        fy = sol.force * (ct.ny + q * ct.nx)
        return -np.sum(fx, axis=(0, 1)), -np.sum(fy, axis=(0, 1))


# ============================================================ losses (pins.md §5.6)

def contact_losses(sol: Solution, R_b: float, mu_eff: float, sliding_friction: float, rolls: bool):
    """Per-contact loss per unit crank speed and the pin spin (pins.md §5.6, §4.6).

    Fixed pins: every loaded contact slides at |v_t| with mu_eff = f.  Rolling pins: the contact with
    the larger force sets the spin omega_pin = v_t/R_b and loses mu_rot F |v_t|; another loaded
    contact on the same pin slides at |v_t - omega_pin R_b| with f.

    Returns
    -------
    loss : mu F |v| per contact [N·mm/s per rad/s] (c, z2, n) (times 1e-3 omega_H gives W);
    spin : omega_pin per unit crank speed [-] (z2, n) (0 for fixed pins and unloaded pins);
    slide : sliding speed per contact [mm/s per rad/s] (c, z2, n).
    """
    F, v = sol.force, sol.v_t
    if not rolls:
        slide = np.abs(v)
        return pins.contact_loss_power(F, slide, mu_eff) * 1e3, np.zeros(F.shape[1:]), slide
    lead = np.argmax(F, axis=0)
    v_lead = np.take_along_axis(v, lead[None], axis=0)[0]
    loaded = np.any(F > 0.0, axis=0)
    spin = np.where(loaded, v_lead / R_b, 0.0)
    is_lead = np.arange(F.shape[0])[:, None, None] == lead[None]
    slide = np.where(is_lead, 0.0, np.abs(v - v_lead[None]))
    loss = np.where(is_lead, mu_eff * F * np.abs(v), sliding_friction * F * slide)
    return loss, spin, slide


# ============================================================ the cycle (pins.md §5.6, §6)

@dataclass
class ContactCycle:
    """The contact level's cycle solution of one design at one torque.

    loss_ratio, loss_ratio_err : Richardson value and |Q_2N - Q_N| of the cycle mean of lambda;
    converged, n_crank : the quadrature's; quad : the QuadResult;
    sol : the solved states on the final grid, sorted by theta (piece ends twice);
    loss, spin, slide : per node (see :func:`contact_losses`); lam : lambda per node;
    breakpoints : the located breakpoints in theta [rad].
    """

    loss_ratio: float
    loss_ratio_err: float
    converged: bool
    n_crank: int
    quad: QuadResult
    sol: Solution
    loss: np.ndarray
    spin: np.ndarray
    slide: np.ndarray
    lam: np.ndarray
    breakpoints: np.ndarray


def _concat(parts: list[Solution]) -> Solution:
    theta = np.concatenate([p.theta for p in parts])
    order = np.argsort(theta, kind="stable")

    def cat(name, axis):
        return np.take(np.concatenate([getattr(p, name) for p in parts], axis=axis), order, axis=axis)

    return Solution(theta[order], cat("tau", 0), cat("dtau", 0), cat("residual", 0), cat("delta", 2),
                    cat("force", 2), cat("v_t", 2), cat("phase", 1), cat("zeta", 1),
                    None if parts[0].switch is None else cat("switch", 3),
                    None if parts[0].branch is None else cat("branch", 2))


def cycle_breakpoints(model: ContactModel, n_scan: int = 256, tol: float = 1e-6) -> np.ndarray:
    """Breakpoints in [0, T_p] of the contact level's cycle integrand (pins.md §6, §12.9, §12.12).

    * the ends 0 and T_p;
    * every sign change of a penetration (a contact enters or leaves), of the tangential speed at
      a loaded contact (a spin reversal) and, for cycloids with k >= 2, of the distance of a loaded
      contact from its flank's end (it passes to the crest corner), located on an ``n_scan`` grid and
      refined by bisection to 1e-12 T_p;
    * with the Hertz law (F ~ delta^(10/9)), a geometric grading toward both sides of every entry
      and exit: there dF/d delta ~ delta^(1/9), so the satellite's speed (through d tau/d theta) has
      an algebraic singularity (theta - theta_0)^(1/9) that plain doubling resolves only to order
      1.1; the grading stops at a width where that term is below tol/100 of the integrand;
    * K1 > 0.99: the geometric grading toward entry of the ideal level.
    """
    Tp = model.g.period
    memo: dict = {}

    def state(x):
        key = (x.size, x.tobytes())
        if key not in memo:
            memo.clear()
            memo[key] = model.state(x)
        return memo[key]

    def components(x):
        s = state(x)
        parts = [s.delta.reshape(-1, x.size), np.where(s.force > 0.0, s.v_t, 0.0).reshape(-1, x.size)]
        if s.switch is not None:      # not masked: a pin can reach the crest and leave it in one scan step
            parts.append(s.switch.reshape(-1, x.size))
        return np.concatenate(parts)

    xtol = 1e-12 * Tp
    found = sign_change_breakpoints(components, 0.0, Tp, n_scan, xtol=xtol)   # one vectorised bisection
    # which scan intervals hold a change of a penetration (the contact entries and exits)
    x = np.linspace(0.0, Tp, n_scan + 1)
    c = state(x).delta.reshape(-1, x.size)
    sg = np.sign(c)
    entry = np.any(sg[:, :-1] * sg[:, 1:] < 0, axis=0)
    contact_bp = found[entry[np.clip(np.searchsorted(x, found) - 1, 0, n_scan - 1)]]
    edges = _merge(np.concatenate(([0.0, Tp], found)), 4.0 * xtol)
    extra = []
    if model.law.exponent != 1.0 and contact_bp.size:
        width = 4.0 * Tp * (0.01 * tol) ** 0.9
        for x0 in _merge(contact_bp, 4.0 * xtol):
            i = int(np.argmin(np.abs(edges - x0)))
            if i > 0:
                extra.append(geometric_breakpoints(edges[i], edges[i - 1], width, ratio=0.25))
            if i + 1 < edges.size:
                extra.append(geometric_breakpoints(edges[i], edges[i + 1], width, ratio=0.25))
    if model.g.one_minus_K1 < 0.01:
        extra.append(geometric_breakpoints(0.0, Tp, model.g.one_minus_K1 * Tp * model.g.z2 / (2.0 * math.pi)))
    return _merge(np.concatenate([edges, *extra]), 4.0 * xtol)


def _merge(points, gap):
    """Sorted unique points with neighbours closer than ``gap`` merged (the ends of the range kept)."""
    x = unique_sorted(points)
    if x.size <= 2:
        return x
    keep = np.concatenate(([True], np.diff(x) > gap))
    out = x[keep]
    if out[-1] != x[-1]:
        out[-1] = x[-1]
    return out


def mean_loss_ratio(model: ContactModel, mu_eff: float, sliding_friction: float, rolls: bool,
                    tol: float = 1e-6, n_max: int = 2 ** 12, n_start: int = 128, n_scan: int = 256) -> ContactCycle:
    """Cycle mean of lambda(theta) = sum P_j/(T_sat omega_H k/z1) over one period, with an honest error.

    Every node is an equilibrium solve; the solved states of all nodes are kept (the final grid) for
    the summary and the detail tables (pins.md §5.6, §6).

    Parameters
    ----------
    model : the contact model (design and torque).
    mu_eff : f (fixed pins or pins that cannot roll) or mu_rot (rolling pins) [-].
    sliding_friction : f, for the second contact of a rolling pin [-].
    rolls : the pins roll.
    tol : relative accuracy target; n_max : cap on crank-angle intervals (2^12, pins.md §6).
    """
    g = model.g
    scale = model.torque_sat * g.k / g.z1
    cache: list[Solution] = []
    refs: dict = {}

    def integrand(x, mid):
        um, inv = np.unique(mid, return_inverse=True)
        new = np.array([m for m in um if m not in refs])
        if new.size:
            active, branch = model.reference(new)
            for i, m in enumerate(new):
                refs[m] = (active[..., i], None if branch is None else branch[..., i])
        active = np.stack([refs[m][0] for m in um], axis=-1)[..., inv]
        branch = None if refs[um[0]][1] is None else np.stack([refs[m][1] for m in um], axis=-1)[..., inv]
        s = model.state(x, (active, branch))
        cache.append(s)
        loss, _, _ = contact_losses(s, g.R_b, mu_eff, sliding_friction, rolls)
        return loss.sum(axis=(0, 1)) / scale / g.period

    edges = cycle_breakpoints(model, n_scan, tol)
    q = integrate_piecewise(integrand, edges, tol=tol, n_max=n_max, n_start=n_start)
    sol = _concat(cache)
    loss, spin, slide = contact_losses(sol, g.R_b, mu_eff, sliding_friction, rolls)
    lam = loss.sum(axis=(0, 1)) / scale
    return ContactCycle(float(q.value[0]), float(q.err[0]), q.converged, q.n, q, sol, loss, spin, slide, lam,
                        edges)


# ============================================================ cycle metrics (pins.md §5.7, §8)

def engagement_metrics(sol: Solution, spin, low: float = 0.1):
    """The paper's circular-profile metrics from one period of all pins (pins.md §5.7(b)).

    All pins' samples together cover one full engagement (a pin's history has period 2 pi, the pins
    are T_p apart).  They are ordered by zeta = theta - phi_j (time order).  The loaded interval is the
    longest run of consecutive samples with a loaded contact.

    Returns
    -------
    dict: exit_entry_force_ratio (max F in the second half of the loaded interval / max in the first),
    spin_reversals (sign changes of the spin in the interval), low_spin_fraction (share of the interval
    with |spin| < low max|spin|; None when the pins do not spin), loaded_from, loaded_to (zeta ends) [rad].
    """
    F = sol.force.max(axis=0).ravel()
    z = sol.zeta.ravel()
    w = spin.ravel()
    order = np.argsort(z, kind="stable")
    z, F, w = z[order], F[order], w[order]
    on = F > 0.0
    if not np.any(on):
        return {"exit_entry_force_ratio": None, "spin_reversals": 0, "low_spin_fraction": None,
                "loaded_from": None, "loaded_to": None}
    # longest run of loaded samples
    idx = np.nonzero(on)[0]
    splits = np.nonzero(np.diff(idx) > 1)[0]
    starts = np.concatenate(([idx[0]], idx[splits + 1]))
    ends = np.concatenate((idx[splits], [idx[-1]]))
    r = int(np.argmax(z[ends] - z[starts]))
    a, b = int(starts[r]), int(ends[r])
    zz, FF, ww = z[a:b + 1], F[a:b + 1], w[a:b + 1]
    half = 0.5 * (zz[0] + zz[-1])
    first, second = FF[zz <= half], FF[zz >= half]
    ratio = float(second.max() / first.max()) if first.size and first.max() > 0 else None
    wmax = float(np.abs(ww).max())
    if wmax == 0.0:
        return {"exit_entry_force_ratio": ratio, "spin_reversals": 0, "low_spin_fraction": None,
                "loaded_from": float(zz[0]), "loaded_to": float(zz[-1])}
    sg = np.sign(ww)
    sg = sg[sg != 0]
    reversals = int(np.count_nonzero(sg[1:] != sg[:-1]))
    # share of the interval (by zeta length) where |spin| < low * max: trapezoid weights
    lowmask = (np.abs(ww) < low * wmax).astype(float)
    dz = np.diff(zz)
    span = zz[-1] - zz[0]
    frac = float(np.sum(0.5 * (lowmask[1:] + lowmask[:-1]) * dz) / span) if span > 0 else 0.0
    return {"exit_entry_force_ratio": ratio, "spin_reversals": reversals, "low_spin_fraction": frac,
            "loaded_from": float(zz[0]), "loaded_to": float(zz[-1])}


@dataclass(frozen=True)
class CyclePeaks:
    """Peaks of one contact cycle over the pins and crank angles, all discs (:func:`cycle_peaks`).

    force, force_phase : peak pin force [N] and its load-side phase [rad];
    loss, loss_phase : peak loss of one pin [N·mm/s per rad/s of crank speed] and its phase [rad];
    total : peak loss of all pins [N·mm/s per rad/s];
    contact_speed : largest |v_t| at a loaded contact; slide : largest sliding speed at a loaded contact
        [mm/s per rad/s];
    spin_min, spin_max, spin_abs : signed least, largest and largest |spin| of a loaded rolling pin
        [rad/s per rad/s] (0 for pins that do not roll);
    loaded_min, loaded_max : least and most loaded pins; psi_star : largest loaded phase [rad] (None: none).
    """

    force: float
    force_phase: float
    loss: float
    loss_phase: float
    total: float
    contact_speed: float
    slide: float
    spin_min: float
    spin_max: float
    spin_abs: float
    loaded_min: int
    loaded_max: int
    psi_star: float | None


def cycle_peaks(cyc: ContactCycle, g: Cycloid, n_discs: int, rolls: bool) -> CyclePeaks:
    r"""Peak force, loss and speeds of a contact cycle (pins.md §5.6, §8, §12.7).

    With n_d > 1 discs the per-pin histories are summed over the discs, 2 pi/n_d apart
    (:func:`gearcalc.pins.disc_sum_peak`, :func:`gearcalc.pins.sum_over_discs`):

    .. math::

        F_{max} = \max_{\psi} \sum_{d=0}^{n_d-1} F(\psi - 2\pi d/n_d)

    Parameters
    ----------
    cyc : ContactCycle
        the solved cycle (:func:`mean_loss_ratio`).
    g : Cycloid
        the pin gear.
    n_discs : int
        n_d.
    rolls : bool
        the pins roll.

    Returns
    -------
    CyclePeaks

    Examples
    --------
    >>> g = Cycloid.from_curtate_ratio(21, 22, 3.9, 0.75, 1.95)
    >>> m = ContactModel(g, CycloidProfile(g, 0.0, 0.0), contact_law("linear", stiffness=1e5), 1e4, REDUCER)
    >>> pk = cycle_peaks(mean_loss_ratio(m, 0.1, 0.1, False, tol=1e-4), g, 1, False)
    >>> pk.force > 0.0, pk.spin_abs
    (True, 0.0)

    References
    ----------
    .. [1] pins.md §5.6 (losses), §8 (output), §12.7 (discs).
    """
    sol = cyc.sol
    loaded_c = sol.force > 0.0
    loaded = loaded_c.any(axis=0)
    F_pin = sol.force.max(axis=0)
    loss_pin = cyc.loss.sum(axis=0)
    if n_discs == 1:
        i = np.unravel_index(int(np.argmax(F_pin)), F_pin.shape)
        F1, phF = float(F_pin[i]), float(sol.phase[i])
        i = np.unravel_index(int(np.argmax(loss_pin)), loss_pin.shape)
        P1, phP = float(loss_pin[i]), float(sol.phase[i])
        tot = float(loss_pin.sum(axis=0).max())
    else:
        F1, phF = pins.disc_sum_peak(sol.phase[loaded], F_pin[loaded], n_discs)
        P1, phP = pins.disc_sum_peak(sol.phase[loaded], loss_pin[loaded], n_discs)
        t = sol.theta / g.period
        tot = float(pins.sum_over_discs(t, loss_pin.sum(axis=0), pins.disc_offsets(n_discs, g.z2), 1.0).max())
    vt_load = np.abs(sol.v_t[loaded_c]) if loaded_c.any() else np.zeros(1)
    spin_load = cyc.spin[loaded] if rolls else np.zeros(1)
    slide_load = cyc.slide[loaded_c] if loaded_c.any() else np.zeros(1)
    counts = loaded.sum(axis=0)
    observed = sol.phase[loaded]
    return CyclePeaks(
        force=F1, force_phase=phF, loss=P1, loss_phase=phP, total=tot, contact_speed=float(vt_load.max()),
        slide=float(slide_load.max()), spin_min=float(spin_load.min()) if rolls else 0.0,
        spin_max=float(spin_load.max()) if rolls else 0.0,
        spin_abs=float(np.abs(spin_load).max()) if rolls else 0.0, loaded_min=int(counts.min()),
        loaded_max=int(counts.max()), psi_star=float(observed.max()) if observed.size else None)


def free_play(model: ContactModel, theta, limit: float | None = None):
    """Angular free play of the unloaded satellite at crank angles theta: (tau_minus, tau_plus) [rad].

    tau_plus > 0 (tau_minus < 0) is the rotation from nominal at which the first pair touches, the
    root of max_j delta_j(tau) = 0 bracketed by doubling from 1e-12 rad; 0 where a pair already touches
    or interferes at nominal.  The backlash is min over theta of tau_plus - tau_minus.
    """
    pose = model.pose(theta)
    n = pose.theta.size
    limit = limit or math.pi / model.g.z1

    def hmax(t):
        return np.max(model.contacts(pose, t).delta, axis=(0, 1))

    h0 = hmax(np.zeros(n))
    out = []
    for direction in (-1.0, 1.0):
        lo, hi = np.zeros(n), np.zeros(n)
        open_ = h0 < 0.0
        prev = np.zeros(n)
        h = 1e-12
        while np.any(open_) and h <= 2 * limit:
            step = direction * min(h, limit)
            v = hmax(np.full(n, step))
            found = open_ & (v >= 0.0)
            lo, hi = np.where(found, prev, lo), np.where(found, step, hi)
            open_ &= ~found
            prev = np.where(open_, step, prev)
            h *= 2.0
        hi = np.where(open_, direction * limit, hi)
        good = (h0 < 0.0) & ~open_
        root = np.zeros(n)
        if np.any(good):
            a, b = np.minimum(lo, hi)[good], np.maximum(lo, hi)[good]
            sub = Pose(pose.theta[good], pose.x0[:, good], pose.y0[:, good], pose.beta0[:, good],
                       pose.psi[:, good], {k: v[..., good] for k, v in pose.aux.items()})
            res = find_root(lambda t, sub=sub: np.max(model.contacts(sub, t).delta, axis=(0, 1)), a, b, xtol=1e-15)
            root[good] = res.root
        root = np.where(open_, direction * limit, root)
        out.append(root)
    return out[0], out[1]


def backlash(model: ContactModel, n_scan: int = 129) -> float:
    r"""The satellite's angular play at no load, both flanks [rad] (pins.md §5.3).

    .. math::

        j = \min_\theta |\tau_-(\theta)| + \min_\theta \tau_+(\theta)

    For each flank, the least rotation over the cycle from the nominal position to the first contact
    (:func:`free_play`), summed over the two flanks: 0 for an unmodified cycloid and for the
    zero-backlash tooth circle (it touches the pins' paths), positive with clearance.  Sampled on
    ``n_scan`` crank angles of one period, each least value refined by golden-section search
    (:func:`gearcalc.roots.minimize_golden`) between the neighbouring angles.

    Parameters
    ----------
    model : ContactModel
        the satellite (its torque is not used).
    n_scan : int
        crank angles of the scan over one period T_p = 2 pi/z2.

    Returns
    -------
    float
        backlash [rad].

    Examples
    --------
    >>> g = Cycloid.from_curtate_ratio(21, 22, 3.9, 0.75, 1.95)
    >>> m = ContactModel(g, CycloidProfile(g, 0.0, 0.05), contact_law("linear", stiffness=1e5), 1e3, REDUCER)
    >>> bool(backlash(m) > 0.0)
    True

    References
    ----------
    .. [1] pins.md §5.3 (backlash_deg), §8.
    """
    Tp = model.g.period
    theta = np.linspace(0.0, Tp, n_scan)
    total = 0.0
    for side in (0, 1):
        def play(x, side=side):
            pair = free_play(model, np.atleast_1d(x))
            return np.reshape(np.abs(pair[side]), np.shape(x))

        p = play(theta)
        i = int(np.argmin(p))
        a, b = theta[max(i - 1, 0)], theta[min(i + 1, theta.size - 1)]
        res = minimize_golden(play, a, b, rtol=1e-9)
        total += min(float(res.fun), float(p[i]))
    return total


# ============================================================ the torque fixed point (pins.md §7)

class Unresolvable(ValueError):
    """The contact level cannot resolve the geometry in floating point (non-finite forces or losses)."""


def fixed_point_settled(history, tol: float) -> bool:
    """Whether the torque fixed point has settled: the remaining error c |d_n|/(1 - c) of the last loss
    ratio, with the contraction c = |d_n/d_(n-1)| of the last two changes d, is below tol/10 of it.

    Examples
    --------
    >>> fixed_point_settled([0.1, 0.11, 0.1101], 1e-3), fixed_point_settled([0.1, 0.2], 1e-6)
    (True, False)
    """
    if len(history) < 2:
        return False
    d1 = abs(history[-1] - history[-2])
    if d1 <= 1e-15 + 1e-3 * tol * abs(history[-1]):
        return True
    if len(history) < 3:
        return False
    c = d1 / max(abs(history[-2] - history[-3]), 1e-300)
    return c < 0.5 and c * d1 / (1.0 - c) <= 0.1 * tol * abs(history[-1])


@dataclass
class TorqueCycle:
    """The contact cycle at the torque fixed point (:func:`cycle_at_torque`).

    cycle : the last :class:`ContactCycle`; model : its :class:`ContactModel`; torque_V : T_V [N·m];
    loss_ratio, loss_ratio_err : lambda_bar and its error (exactly 0 without friction);
    history : the loss ratios of the passes; settled : False when the passes ran out unsettled.
    """

    cycle: ContactCycle
    model: ContactModel
    torque_V: float
    loss_ratio: float
    loss_ratio_err: float
    history: list
    settled: bool


def cycle_at_torque(g: Cycloid, profile, law: ContactLaw, torque: float, torque_on_V: bool, multiplier: bool,
                    n_discs: int, mu_eff: float, sliding_friction: float, rolls: bool,
                    friction_in_equilibrium: bool = False, tol: float = 1e-6, passes: int = 8) -> TorqueCycle:
    r"""The contact cycle under the torque given on V, or on H through the torque fixed point (pins.md §4.7, §7).

    The loss ratio depends (weakly) on the torque, so with the torque given on H the torque on V is
    iterated to the fixed point

    .. math::

        T_V = \frac{u T_H}{1 - \bar\lambda(T_V)}\ \text{(multiplier)},\qquad
        T_V = \frac{u T_H}{1 + \bar\lambda(T_V)}\ \text{(reducer)}

    until :func:`fixed_point_settled` (at most ``passes``; one pass when the torque is on V).  A
    multiplier that self-locks (lambda_bar >= 1) keeps the last solution.

    Parameters
    ----------
    g : Cycloid
        the pin gear.
    profile : CircularProfile or CycloidProfile
    law : ContactLaw
    torque : float
        T, on V when ``torque_on_V`` else on H [N·m].
    torque_on_V, multiplier : bool
        where the torque is given; multiplier (V drives H) or reducer mode.
    n_discs : int
        n_d, discs sharing the torque.
    mu_eff, sliding_friction : float
        mu_eff and f [-]; rolls : bool, the pins roll.
    friction_in_equilibrium : bool
        add the friction forces to the moment balance (pins.md §5.5).
    tol : float
        relative accuracy of the cycle mean and of the fixed point.

    Returns
    -------
    TorqueCycle

    Raises
    ------
    NoEquilibrium
        no satellite rotation balances the torque; its ``torque_V`` is the T_V tried [N·m].
    Unresolvable
        non-finite forces or losses (deflections below the round-off of the pin positions).

    Examples
    --------
    >>> g = Cycloid.from_curtate_ratio(21, 22, 3.9, 0.75, 1.95)
    >>> tc = cycle_at_torque(g, CycloidProfile(g, 0.0, 0.0), contact_law("linear", stiffness=1e5), 10.0, False,
    ...                      False, 1, 0.1, 0.1, False, tol=1e-4)
    >>> tc.settled, 0.0 < tc.loss_ratio < 1.0
    (True, True)

    References
    ----------
    .. [1] pins.md §4.7, §5.5, §7 (torque_shaft).
    """
    from . import units

    sigma = MULTIPLIER if multiplier else REDUCER
    friction = (mu_eff, sliding_friction, rolls) if friction_in_equilibrium else None
    T = float(torque)
    lam, cyc, model, T_V, history = 0.0, None, None, None, []
    settled = True
    for _ in range(passes):
        if torque_on_V:
            T_V = T
        elif multiplier:
            if lam >= 1.0:
                break                      # self-locking: no T_V balances T_H; keep the last solution
            T_V = g.ratio * T / (1.0 - lam)
        else:
            T_V = g.ratio * T / (1.0 + lam)
        model = ContactModel(g, profile, law, units.nm_to_nmm(T_V) / n_discs, sigma, friction)
        try:
            with np.errstate(all="ignore"):       # non-finite values are caught below, never printed
                cyc = mean_loss_ratio(model, mu_eff, sliding_friction, rolls, tol=tol)
        except NoEquilibrium as exc:
            exc.torque_V = T_V
            raise
        if not (np.isfinite(cyc.loss_ratio) and np.all(np.isfinite(cyc.sol.force)) and np.all(np.isfinite(cyc.lam))):
            raise Unresolvable("non-finite contact forces or losses")
        history.append(cyc.loss_ratio)
        lam = cyc.loss_ratio
        if torque_on_V or fixed_point_settled(history, tol):
            break
    else:
        settled = False
    E = cyc.loss_ratio_err
    if mu_eff == 0.0 and sliding_friction == 0.0:
        lam, E = 0.0, 0.0
    return TorqueCycle(cyc, model, T_V, lam, E, history, settled)


__all__ = [
    "ContactLaw", "contact_law", "palmgren_line_constant",
    "tooth_centre_distance", "zero_backlash_tooth_circle", "full_tooth",
    "CircularProfile", "CycloidProfile", "ContactModel", "NoEquilibrium", "Solution",
    "contact_losses", "mean_loss_ratio", "cycle_breakpoints", "engagement_metrics", "free_play",
    "backlash", "CyclePeaks", "cycle_peaks", "Unresolvable", "fixed_point_settled", "TorqueCycle", "cycle_at_torque",
    "MULTIPLIER", "REDUCER",
]
