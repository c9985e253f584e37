"""KHV pin gearing, level ``contact``: the satellite's tooth profiles and the pin penetrations (pins.md §5.2-5.3).

Pure geometry over floats and numpy arrays (mm, rad), used by the contact model of :mod:`gearcalc.pins.contact`
(which re-exports these names):

* circular-arc teeth (§5.3): the least distance from a tooth centre to the pin-centre curves, the "full" tooth
  radius and the zero-backlash tooth circle (:func:`tooth_centre_distance`, :func:`full_tooth`,
  :func:`zero_backlash_tooth_circle`), and the profile's admissibility (:func:`circular_profile`);
* the penetration delta, the contact normal and its turning rate of every pin-tooth pair at a satellite rotation
  tau from the nominal pose (:class:`Pose`, :class:`Contacts`): circle-circle for circular-arc teeth
  (:class:`CircularProfile`), the signed distance to the design pin-centre curve for cycloids, with crest corners
  for k >= 2 (:class:`CycloidProfile`, :func:`cycloid_profile`).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..roots import bisect
from .forces import pin_phase
from .geometry import REDUCER, Cycloid, crest_cutoff, min_curvature_radius, pin_centre_curve, tooth_profile
from .profiles import tooth_too_large

__all__ = [
    "tooth_centre_distance", "zero_backlash_tooth_circle", "full_tooth",
    "Pose", "Contacts", "CircularProfile", "CycloidProfile", "InadmissibleProfile", "PROFILE_RULES",
    "circular_profile", "cycloid_profile", "circular_teeth", "cycloidal_profile",
]


def _unit(a):
    return np.cos(a), np.sin(a)


def tooth_centre_distance(R_t, g: Cycloid, n_scan: int = 64, with_slope: bool = False, max_newton: int = 50):
    r"""D(R_t): least distance from the tooth centre T_0 = R_t u(pi/z1) to the nominal pin-centre curves [mm].

    Minimum over every family b and over the curve parameter beta within two tooth pitches of the
    tooth: a dense scan, then golden-section refinement between the neighbouring samples
    (vectorised over R_t).  D(0) = R_p - e (pins.md §5.3).

    .. math:: D(R_t) = \min_{b,\ \beta} \left|c_b(\beta) - T_0\right|, \qquad T_0 = R_t\,u(\pi/z_1), \qquad
        \frac{dD}{dR_t} = -\frac{(c - T_0) \cdot u(\pi/z_1)}{D}

    Parameters
    ----------
    R_t : radius of the circle of tooth centres [mm] (array-like).
    g : the pin gear (z1, z2, e, R_p; R_b is not used).
    n_scan : samples per tooth pitch and family.
    max_newton : cap on the Newton iterations of the least distance (a scan only needs a few).

    Returns
    -------
    D [mm], the shape of R_t; with ``with_slope`` also dD/dR_t = -(c - T).u(pi/z1)/D [-] (the foot
    point is stationary: envelope theorem).

    Examples
    --------
    >>> g = Cycloid.from_pin_circle(20, 22, 3.9, 57.2, 2.75)
    >>> round(float(tooth_centre_distance(0.0, g)), 9)     # R_p - e
    53.3

    References
    ----------
    .. [1] B. Chen, T. Fang, C. Li, S. Wang, Gear geometry of cycloid drives, Science in China Series E:
       Technological Sciences 51, 2008 (the pin-centre curves c_b); docs/spec/pins.md §5.3.
    """
    shape = np.shape(R_t)
    R_t = np.atleast_1d(np.asarray(R_t, dtype=float)).ravel()
    chi = math.pi / g.z1
    pitch = 2.0 * math.pi / g.z1
    beta = chi + np.linspace(-2.0 * pitch, 2.0 * pitch, 4 * n_scan + 1)
    tx, ty = R_t * math.cos(chi), R_t * math.sin(chi)
    best, best_b, best_i = _nearest_sample(beta, tx, ty, g)
    lo = beta[np.maximum(best_i - 1, 0)]
    hi = beta[np.minimum(best_i + 1, beta.size - 1)]

    ze = g.z2 / g.k

    def curve(x):
        a = ze * x - 2.0 * math.pi * best_b / g.k
        ca, sa, cx_, sx_ = np.cos(a), np.sin(a), np.cos(x), np.sin(x)
        return (g.R_p * cx_ - g.e * ca - tx, g.R_p * sx_ - g.e * sa - ty, -g.R_p * sx_ + g.e * ze * sa,
                g.R_p * cx_ - g.e * ze * ca, -g.R_p * cx_ + g.e * ze * ze * ca, -g.R_p * sx_ + g.e * ze * ze * sa)

    # the least distance: safeguarded Newton on (c - T).c' = 0 between the neighbouring samples
    x = beta[best_i]
    for _ in range(max_newton):
        rx, ry, dx, dy, ddx, ddy = curve(x)
        h = rx * dx + ry * dy
        hp = dx * dx + dy * dy + rx * ddx + ry * ddy
        lo = np.where(h < 0.0, np.maximum(lo, x), lo)
        hi = np.where(h > 0.0, np.minimum(hi, x), hi)
        with np.errstate(divide="ignore", invalid="ignore"):
            new = x - h / hp
        new = np.where((hp > 0.0) & (new > lo) & (new < hi), new, 0.5 * (lo + hi))
        step = np.abs(new - x)
        x = new
        if np.all(step <= 1e-15 * (1.0 + np.abs(x))):
            break
    rx, ry = curve(x)[:2]
    D = np.sqrt(np.minimum(rx * rx + ry * ry, best))
    if with_slope:
        return D.reshape(shape), (-(rx * math.cos(chi) + ry * math.sin(chi)) / D).reshape(shape)
    return D.reshape(shape)


def _nearest_sample(beta, tx, ty, g: Cycloid):
    """(squared distance, family, sample) of the nearest sample of the pin-centre curves to each tooth centre.

    Over the families b and the samples ``beta``, from the tooth centres (tx, ty) (:func:`tooth_centre_distance`).
    """
    best = np.full(tx.shape, np.inf)
    best_b = np.zeros(tx.shape, dtype=np.int64)
    best_i = np.zeros(tx.shape, dtype=np.int64)
    for b in range(g.k):  # a handful of families; vectorised over beta and R_t
        cx, cy = pin_centre_curve(beta, b, g)
        d2 = (cx[None, :] - tx[:, None]) ** 2 + (cy[None, :] - ty[:, None]) ** 2
        i = np.argmin(d2, axis=1)
        v = d2[np.arange(tx.size), i]
        better = v < best
        best = np.where(better, v, best)
        best_b = np.where(better, b, best_b)
        best_i = np.where(better, i, best_i)
    return best, best_b, best_i


def _distance_grid(g: Cycloid, step: float):
    """D(R_t) on a grid from 0 to R_p + e no coarser than ``step`` [mm] (the scan of pins.md §5.3)."""
    top = g.R_p + g.e
    n = int(min(max(64, math.ceil(top / step)), 20000))
    grid = np.linspace(0.0, top, n + 1)
    return grid, tooth_centre_distance(grid, g, max_newton=6)     # signs only: the roots are refined


def _first_root(fun, grid, values, xtol):
    """First sign change (from > 0 to <= 0) of sampled values, refined by safeguarded Newton.

    ``fun(x)`` returns (value, slope) at a scalar x; a Newton step that leaves the bracket is replaced
    by bisection; stops when the step or the bracket is below ``xtol``.
    """
    below = np.nonzero(values <= 0.0)[0]
    if below.size == 0 or below[0] == 0:
        return None
    i = int(below[0])
    if values[i] == 0.0:
        return float(grid[i])
    lo, hi = float(grid[i - 1]), float(grid[i])
    flo, fhi = float(values[i - 1]), float(values[i])
    x = lo - flo * (hi - lo) / (fhi - flo)
    for _ in range(200):
        f, d = (float(v) for v in fun(x))
        if f == 0.0:
            return x
        if f > 0.0:
            lo = x
        else:
            hi = x
        new = x - f / d if d != 0.0 and math.isfinite(d) else 0.5 * (lo + hi)
        if not lo < new < hi:
            new = 0.5 * (lo + hi)
        if abs(new - x) <= xtol or hi - lo <= xtol:
            return new
        x = new
    return x


def zero_backlash_tooth_circle(g: Cycloid, tooth_radius: float, grid=None) -> float | None:
    r"""R_t for zero backlash: the smallest root of D(R_t) = R_b + rho_t, or None if there is none [mm].

    D(R_t) is scanned outward from 0 on a grid finer than (R_b + rho_t)/4 and the first sign change
    is refined by the bracketed root finder to 1e-13 R_p (pins.md §5.3; D is not monotone in
    general).  ``grid`` may pass a precomputed (R_t, D) scan.

    .. math:: D(R_t) = R_b + \rho_t \quad \text{(smallest root)}

    Parameters
    ----------
    g : Cycloid
        The gear.
    tooth_radius : float
        Circular tooth radius rho_t, [mm].
    grid : tuple of ndarray, optional
        A precomputed scan (R_t, D), [mm].

    Returns
    -------
    R_t : float or None
        Radius of the circle of tooth centres, [mm], or None.

    Examples
    --------
    >>> g = Cycloid.from_pin_circle(20, 22, 3.9, 57.2, 2.75)
    >>> R_t = zero_backlash_tooth_circle(g, 5.0)
    >>> round(float(tooth_centre_distance(R_t, g)), 9)      # = R_b + rho_t
    7.75

    References
    ----------
    .. [1] docs/spec/pins.md §5.3.
    """
    target = g.R_b + tooth_radius
    if tooth_too_large(g.R_b, tooth_radius, g.R_p, g.e):
        return None
    if grid is None or grid[0][1] - grid[0][0] > target / 4.0:
        grid = _distance_grid(g, target / 4.0)
    def fun(r):
        D, dD = tooth_centre_distance(r, g, with_slope=True)
        return D - target, dD

    return _first_root(fun, grid[0], grid[1] - target, 1e-13 * g.R_p)


_TOOTH_CACHE: dict = {}
"""full_tooth results by (z1, z2, e, R_p, R_b): a pure function of them, reused by repeated runs."""


def full_tooth(g: Cycloid) -> tuple[float, float] | None:  # noqa: D103 (the docstring of _full_tooth, below)
    key = (g.z1, g.z2, g.e, g.R_p, g.R_b)
    if key not in _TOOTH_CACHE:
        if len(_TOOTH_CACHE) > 256:
            _TOOTH_CACHE.clear()
        _TOOTH_CACHE[key] = _full_tooth(g)
    return _TOOTH_CACHE[key]


def _full_tooth(g: Cycloid) -> tuple[float, float] | None:
    r"""The "full" circular tooth: rho_t = R_t(rho_t) sin(pi/z1) (adjacent teeth tangent at the root).

    .. math:: D(R_t) - R_b - R_t \sin\frac{\pi}{z_1} = 0 \ \text{(first root)}, \qquad \rho_t = R_t \sin\frac{\pi}{z_1}

    Solved as the first root on the outward scan (the same root as the nested definition of pins.md §5.3 when the
    zero-backlash root of that rho_t is the first crossing, which is checked).

    Parameters
    ----------
    g : Cycloid
        The gear.

    Returns
    -------
    tooth : tuple of float or None
        (rho_t, R_t), [mm], or None when no tooth fits.

    Examples
    --------
    >>> g = Cycloid.from_pin_circle(20, 22, 3.9, 57.2, 2.75)
    >>> rho, R_t = full_tooth(g)
    >>> bool(abs(rho - R_t * np.sin(np.pi / 20)) < 1e-9)
    True

    References
    ----------
    .. [1] docs/spec/pins.md §5.3.
    """
    s = math.sin(math.pi / g.z1)
    if g.R_b >= g.R_p - g.e:
        return None
    grid = _distance_grid(g, g.R_b / 4.0)
    def fun(r):
        D, dD = tooth_centre_distance(r, g, with_slope=True)
        return D - g.R_b - r * s, dD - s

    R_t = _first_root(fun, grid[0], grid[1] - g.R_b - grid[0] * s, 1e-13 * g.R_p)
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


full_tooth.__doc__ = _full_tooth.__doc__


# ============================================================ profiles: penetrations (pins.md §5.2-5.3)

@dataclass
class Pose:
    """Nominal pose data at crank angles theta (tau = 0), shape (z2, n) per pin.

    theta [rad] (n,); x0, y0: X_j at tau = 0 in the satellite frame [mm]; beta0: curve parameter
    phi_j + k theta/z1 [rad]; psi: pin phase phi_j - theta wrapped to (-pi, pi] [rad], of the pins
    ``aux["idx"]`` among z2, computed when first read (the circular-arc teeth need it only for the candidate
    window, :meth:`ContactModel._nominal`); aux: the profile's own precomputed data.
    """

    theta: np.ndarray
    x0: np.ndarray
    y0: np.ndarray
    beta0: np.ndarray
    z2: int
    aux: dict = field(default_factory=dict)
    _psi: np.ndarray | None = None

    @property
    def psi(self) -> np.ndarray:
        """Pin phase phi_j - theta wrapped to (-pi, pi] [rad], computed when first read."""
        if self._psi is None:
            psi = pin_phase(self.aux["idx"], self.theta[None, :], self.z2, REDUCER)   # phi_j - theta in (0, 2 pi]
            self._psi = np.where(psi > math.pi, psi - 2.0 * math.pi, psi)
        return self._psi


@dataclass
class Contacts:
    """Pin/tooth pairs at a pose: arrays (c, z2, n), c contacts per pin.

    delta: penetration [mm]; nx, ny: unit normal from the pin centre into the satellite
    (satellite frame); arm: X_j x n, the moment arm of the normal about O1 [mm]; xn: X_j . n [mm];
    switch: (s, c, z2, n) quantities whose sign changes mark a change of the contact's geometry (a
    cycloidal pin passing from its flank to a crest corner, where the contact stiffness jumps), or None.
    wx, wy: the turning rate of the normal with the pin centre, dn = (wx dx + wy dy) (z x n) [1/mm]
    (-1/distance to the normal's centre of curvature: the tooth centre, a crest corner, or the
    design curve's centre of curvature seen from the pin centre); used by the analytic derivatives.
    psi_f: (z2, n) the foot point's phase on a cycloid's flank [rad], from which :meth:`CycloidProfile.switch`
    forms ``switch`` where a solution needs it (the balances of the Newton iteration do not), or None.
    """

    delta: np.ndarray
    nx: np.ndarray
    ny: np.ndarray
    arm: np.ndarray
    xn: np.ndarray
    switch: np.ndarray | None = None
    branch: np.ndarray | None = None
    wx: np.ndarray | None = None
    wy: np.ndarray | None = None
    psi_f: np.ndarray | None = None


class CircularProfile:
    """Convex circular-arc teeth: z1 circles of radius rho_t centred at R_t u((2m+1) pi/z1) (pins.md §5.3).

    Each pin meets the two teeth adjacent to it in polar angle: c = 2 contacts per pin, with
    delta = R_b + rho_t - |X_j - T_m| and n = (T_m - X_j)/|T_m - X_j|.  A
    :class:`gearcalc.pins.profiles.ToothProfile`.
    """

    contacts_per_pin = 2
    play_free = False
    """No free play by construction: set on the zero-backlash tooth circle (:func:`circular_teeth`)."""

    def __init__(self, g: Cycloid, tooth_radius: float, tooth_circle_radius: float):
        self.g, self.rho_t, self.R_t = g, float(tooth_radius), float(tooth_circle_radius)

    def switch(self, psi_f):
        """None: :meth:`contacts` returns no foot-point phases (a circle-circle contact has one geometry)."""
        return None

    def summary_fields(self) -> dict:
        """tooth_radius_mm and tooth_circle_radius_mm (pins.md §8)."""
        return {"tooth_radius_mm": self.rho_t, "tooth_circle_radius_mm": self.R_t}

    def prepare(self, pose: Pose, trig=None, sides=None) -> None:
        """The centres of the teeth each pin meets, (c, m, n).

        c = 0 the tooth just below the pin's polar angle, 1 the one above; ``sides`` (indices into them,
        optional): only these (:attr:`ContactModel.sides`).
        """
        z1 = self.g.z1
        gam = np.arctan2(pose.y0, pose.x0)
        m = np.floor((gam * z1 / math.pi - 1.0) / 2.0)          # tooth with chi_m just below gamma
        teeth = np.stack([m, m + 1.0]) if sides is None else m[None] + np.asarray(sides, dtype=float)[:, None, None]
        chi = (2.0 * teeth + 1.0) * math.pi / z1
        pose.aux["tx"], pose.aux["ty"] = self.R_t * np.cos(chi), self.R_t * np.sin(chi)

    def contacts(self, pose: Pose, x, y, branch=None) -> Contacts:
        """The pin-tooth pairs at satellite-frame pin centres (x, y) (:meth:`Profile.contacts`)."""
        tx, ty = pose.aux["tx"], pose.aux["ty"]
        dx, dy = tx - x, ty - y
        dist = np.hypot(dx, dy)
        nx, ny = dx / dist, dy / dist
        return Contacts(self.g.R_b + self.rho_t - dist, nx, ny, x * ny - y * nx, x * nx + y * ny,
                        wx=ny / dist, wy=-nx / dist)


_CURVE_KEYS = ("c1x", "c1y", "d1x", "d1y", "dd1x", "dd1y")
"""Pose keys of the design curve c_b, c_b', c_b'' at the last foot point (:meth:`CycloidProfile.contacts`)."""
_TRIG_KEYS = ("cb1", "sb1", "ca1", "sa1")
"""Pose keys of cos/sin of beta and of Z_e beta - 2 pi b/k at the last foot point."""
_START_KEYS = ("cb0", "sb0", "ca0", "sa0")
"""Pose keys of cos/sin of beta and of Z_e beta - 2 pi b/k at the nominal foot point beta0, when it is one
(:meth:`CycloidProfile.prepare`)."""


class CycloidProfile:
    """Cycloidal teeth cut on the design curve: R_p + Delta R_p, equidistant R_b + Delta R_b (pins.md §5.2).

    delta_j = -d_j - Delta R_b, d_j the signed distance (positive outside) from X_j to the design
    pin-centre curve c_b of the pin's family, found by a safeguarded Newton search on beta at the
    nominal pose and updated by Newton steps for each tau; for k >= 2 a pin whose foot point lies
    beyond its tooth-space segment (|psi| > psi*) faces the crest corner instead.
    A :class:`gearcalc.pins.profiles.ToothProfile`.
    """

    contacts_per_pin = 1

    def __init__(self, g: Cycloid, radial_mod: float = 0.0, equidistant_mod: float = 0.0):
        self.g = g
        self.play_free = equidistant_mod == 0.0 and radial_mod == 0.0   # the paper's cycloid: no free play
        self.dRb = float(equidistant_mod)
        Rp = g.R_p + radial_mod
        k = g.k
        self.design = Cycloid(g.z1, g.z2, g.e, Rp, g.R_b + equidistant_mod, (k * Rp - g.e * g.z2) / (k * Rp))
        self.psi_star = crest_cutoff(self.design)
        self.crests = g.k >= 2
        self._corner_table = None

    def summary_fields(self) -> dict:
        """None of its own (pins.md §8: the tooth fields are the circular profile's)."""
        return {}

    def _trig(self, beta, fam):
        """Cosine and sine of beta and of a = Z_e beta - 2 pi b/k."""
        d = self.design
        a = (d.z2 / d.k) * beta - 2.0 * math.pi * fam / d.k
        return np.cos(beta), np.sin(beta), np.cos(a), np.sin(a)

    def _turned(self, trig, s, beta, fam):
        """:meth:`_trig` at beta (= the old beta + s) from its values at the old beta.

        The angle sums with cos and sin of the small angles s and Z_e s by their Taylor series, exact to
        round-off while |Z_e s| <= 1e-3 (the terms left out are below 1e-19 of the kept ones; to the third order
        while |Z_e s| <= 1e-5, below 1e-21 then); otherwise evaluated anew.

        Examples
        --------
        >>> from gearcalc.pins import Cycloid
        >>> p = CycloidProfile(Cycloid.from_curtate_ratio(30, 31, 3.9, 0.75, 1.95))
        >>> beta, fam = np.array([0.3, 2.0, 5.1]), np.zeros(3, dtype=np.int64)
        >>> s = np.array([3e-8, -2e-7, 1e-5])               # the last one by the fifth-order series
        >>> cb, sb, ca, sa = p._trig(beta, fam)
        >>> t = 31.0 * s                                    # Z_e s; the angle sums with exact cos and sin of s, t
        >>> exact = (cb * np.cos(s) - sb * np.sin(s), sb * np.cos(s) + cb * np.sin(s),
        ...          ca * np.cos(t) - sa * np.sin(t), sa * np.cos(t) + ca * np.sin(t))
        >>> turned = p._turned((cb, sb, ca, sa), s, beta + s, fam)
        >>> bool(np.max(np.abs(np.array(turned) - np.array(exact))) <= 4.0 * np.finfo(float).eps)
        True
        """
        ze = self.design.z2 / self.design.k
        t = ze * s
        largest = np.abs(t).max(initial=0.0)
        if not largest <= 1e-3:
            return self._trig(beta, fam)
        cb, sb, ca, sa = trig
        s2, t2 = s * s, t * t
        if largest <= 1e-5:
            # the last step of a converged foot point (below 1e-7 rad): two terms each, the next ones below 1e-21
            c1, s1 = 1.0 - 0.5 * s2, s * (1.0 - s2 / 6.0)
            c2, s2_ = 1.0 - 0.5 * t2, t * (1.0 - t2 / 6.0)
        else:
            c1, s1 = 1.0 - 0.5 * s2 + s2 * s2 / 24.0, s * (1.0 - s2 / 6.0 + s2 * s2 / 120.0)
            c2, s2_ = 1.0 - 0.5 * t2 + t2 * t2 / 24.0, t * (1.0 - t2 / 6.0 + t2 * t2 / 120.0)
        return cb * c1 - sb * s1, sb * c1 + cb * s1, ca * c2 - sa * s2_, sa * c2 + ca * s2_

    def _curve_of(self, trig):
        """c_b, c_b', c_b'' of the design curve [mm, mm/rad, mm/rad^2] from :meth:`_trig`."""
        d = self.design
        ze = d.z2 / d.k
        cb, sb, ca, sa = trig
        return (d.R_p * cb - d.e * ca, d.R_p * sb - d.e * sa,
                -d.R_p * sb + d.e * ze * sa, d.R_p * cb - d.e * ze * ca,
                -d.R_p * cb + d.e * ze * ze * ca, -d.R_p * sb + d.e * ze * ze * sa)

    def _curve(self, beta, fam):
        """c_b, c_b', c_b'' of the design curve [mm, mm/rad, mm/rad^2]."""
        return self._curve_of(self._trig(beta, fam))

    def _newton(self, beta, fam, x, y, steps, tol=None):
        """Newton steps on the foot point.

        ``steps`` of them, or with ``tol`` until the largest step is below it (at most ``steps``).
        """
        return self._newton_trig(beta, fam, x, y, steps, tol)[0]

    def _newton_trig(self, beta, fam, x, y, steps, tol=None, start=None):
        """:meth:`_newton`, also returning the last step.

        :meth:`_newton`, also returning :meth:`_trig` at the beta before the last step and that step (signed,
        the change of beta).  ``start``: :meth:`_trig` at the first beta, when known.

        The first step is Halley's, s = (g/g')/(1 - s_N g''/(2 g')) with the Newton step s_N = g/g' and
        g'' = 3 c'.c'' + (c - X).c''' (Newton's where |s_N g''/(2 g')| > 1/2): from the nominal foot point, a
        rotation's ~2e-4 rad away, Newton leaves ~1e-6 rad and a third step was needed before one below 1e-7 rad
        (``tol``); Halley's error is cubic in the step, so the second one is below it.
        """
        trig, change = None, None
        d = self.design
        e3 = d.e * (d.z2 / d.k) ** 3
        for i in range(steps):
            # after the first step, cos/sin by the angle sums from the last ones (:meth:`_turned`: exact to round-off
            # for a step |Z_e s| <= 1e-3, else evaluated anew)
            if i == 0:
                trig = self._trig(beta, fam) if start is None else start
            else:
                trig = self._turned(trig, change, beta, fam)
            cx, cy, dx, dy, ddx, ddy = self._curve_of(trig)
            rx, ry = cx - x, cy - y
            gval = rx * dx + ry * dy
            gder = dx * dx + dy * dy + rx * ddx + ry * ddy
            step = gval / gder
            if i == 0:
                cb, sb, ca, sa = trig
                g2 = 3.0 * (dx * ddx + dy * ddy) + rx * (d.R_p * sb - e3 * sa) + ry * (e3 * ca - d.R_p * cb)
                ratio = 0.5 * step * g2 / gder
                step = np.where(np.abs(ratio) <= 0.5, step / (1.0 - ratio), step)
            beta = beta - step
            change = -step
            if tol is not None and not np.abs(step).max(initial=0.0) > tol:
                break
        return beta, trig, change

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
        trig, last = None, None                        # cos/sin at each element's last beta (:meth:`_turned`)
        for _ in range(maxiter):
            bt, fa = beta[act], fam_all[act]
            if trig is None:
                tr = self._trig(bt, fa)
                trig, last = [t.copy() for t in tr], b0.copy()
            else:
                tr = self._turned(tuple(t[act] for t in trig), bt - last[act], bt, fa)
                for t, v in zip(trig, tr):
                    t[act] = v
                last[act] = bt
            cx, cy, dx, dy, ddx, ddy = self._curve_of(tr)
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

    def prepare(self, pose: Pose, trig=None, sides=None) -> None:
        """The pins' families and their foot points on the design curve at the nominal pose.

        ``sides``: one contact per pin, nothing to choose (:attr:`ContactModel.sides`).

        ``trig``, optional: cos and sin of beta0 and of the crank-arm angle a = z2 theta/z1 of the pose, which are
        those of :meth:`_trig` at beta0 (Z_e beta0 - 2 pi b/k = a + 2 pi floor(j/k)).  Without a radial
        modification the nominal pin centre lies on the design curve, so its foot point is beta0 itself, and the
        Newton steps of :meth:`contacts` start from these values (no new cos/sin).
        """
        k, idx = self.g.k, pose.aux["idx"]
        # the family j mod k (a bitwise and for k a power of two: an integer modulo over every pair costs 4x as much)
        fam = idx & (k - 1) if k & (k - 1) == 0 else np.mod(idx, k)
        if fam.shape != pose.x0.shape:
            fam = fam * np.ones_like(pose.x0, dtype=np.int64)
        pose.aux["fam"] = fam
        if trig is not None and self.design.R_p == self.g.R_p:
            pose.aux["beta"] = pose.beta0
            pose.aux.update(zip(_START_KEYS, trig))          # (m, n) and (1, n): they broadcast where used
        else:
            # only the start of the Newton steps of :meth:`contacts` at the turned positions (which iterate until a
            # step below 1e-7 rad has been applied): 1e-7 here too (quadratic convergence: the error is then ~1e-14 rad)
            pose.aux["beta"] = self.foot_point(pose.beta0, fam, pose.x0, pose.y0, tol=1e-7)

    def switch(self, psi_f):
        """The crest components (2, 1, z2, n) of :attr:`Contacts.switch` from the foot points' flank phases psi_f.

        psi* - psi_f and psi_f + psi* (a pin passes to the crest corner where one changes sign).
        """
        out = np.empty((2, 1) + psi_f.shape)
        np.subtract(self.psi_star, psi_f, out=out[0, 0])
        np.add(psi_f, self.psi_star, out=out[1, 0])
        return out

    def _crest_corners(self, pose: Pose, at, corner):
        """The crest corners of the tooth spaces that the pins at the flat indices ``at`` face.

        The crest corners of the tooth spaces that the pins at the flat indices ``at`` of the pose's (m, n)
        arrays face, ``corner`` 0 (psi = +psi*) or 1 (-psi*) for each, x and y [mm] (only where a pin faces a
        crest: 7-15 % of the pairs on the paper's k = 2 cycloids, :meth:`contacts`).

        On the tooth profile they lie at beta0 + psi/z_d -+ psi*/z_d = B_j - 2 pi k w/z1 -+ psi*/z_d, with
        B_j = 2 pi j (1 + k/z1)/z2 and w the turns by which psi = phi_j - theta was wrapped (theta cancels); a shift
        of beta by -2 pi k w/z1 turns the profile by that angle (z2 = z1 + k), so the corners are the pin's two
        corners at w = 0 (a table over the pins), turned by -2 pi k w/z1 (a table over the teeth): every turned corner
        is tabulated once (2 z2 z1 entries), a pair's corner is looked up.
        """
        g = self.g
        z1, z2, k = g.z1, g.z2, g.k
        if self._corner_table is None:
            j = np.arange(z2)
            B = 2.0 * math.pi * j * (1.0 + k / z1) / z2
            dz = self.psi_star * k / z1
            cx, cy = tooth_profile(np.stack([B - dz, B + dz]), np.mod(j, k)[None], self.design)
            r = 2.0 * math.pi * np.arange(z1) / z1
            ca, sa = np.cos(r), -np.sin(r)       # the turn by -2 pi k w/z1 of every corner: (2, z2, z1) tables
            px, py = cx[:, :, None], cy[:, :, None]
            self._corner_table = ((ca * px - sa * py).ravel(), (sa * px + ca * py).ravel())
        tx, ty = self._corner_table
        idx = pose.aux["idx"].ravel()[at]
        theta = pose.theta[at % pose.theta.size]
        w = np.rint((2.0 * math.pi * idx / z2 - theta - pose.psi.ravel()[at]) / (2.0 * math.pi)).astype(np.int64)
        place = (corner * z2 + idx) * z1 + np.mod(k * w, z1)
        return tx[place], ty[place]

    def contacts(self, pose: Pose, x, y, branch=None) -> Contacts:
        """``branch`` (z2, n), optional, forces the flank (-1) or a crest corner (0: +psi*, 1: -psi*)."""
        fam = pose.aux["fam"]
        # Newton from the foot point of the last call on this pose (usually one step) or the nominal one
        # (~1e-3 rad away), until a step below 1e-7 rad has been applied: Newton's error after it is
        # ~(c''/c') 1e-14 rad, and the distance is stationary in beta (its error is second order in that)
        if "beta1" in pose.aux:
            # the first Newton step from the last call's foot point uses the curve kept from that call
            cx, cy, dx, dy, ddx, ddy = (pose.aux[k] for k in _CURVE_KEYS)
            rx, ry = cx - x, cy - y
            step = (rx * dx + ry * dy) / (dx * dx + dy * dy + rx * ddx + ry * ddy)
            beta = pose.aux["beta1"] - step
            trig, change = tuple(pose.aux[k] for k in _TRIG_KEYS), -step
            if np.abs(step).max(initial=0.0) > 1e-7:
                beta, trig, change = self._newton_trig(beta, fam, x, y, 7, 1e-7)
        else:
            start = tuple(pose.aux[k] for k in _START_KEYS) if _START_KEYS[0] in pose.aux else None
            beta, trig, change = self._newton_trig(pose.aux["beta"], fam, x, y, 8, 1e-7, start)
        # the curve at the foot point: the last step is below 1e-7 rad, so cos/sin follow from the last ones by
        # the angle sums (:meth:`_turned`, no new cos/sin)
        trig = self._turned(trig, change, beta, fam)
        cur = self._curve_of(trig)
        pose.aux["beta1"] = beta
        pose.aux.update(zip(_CURVE_KEYS, cur))
        pose.aux.update(zip(_TRIG_KEYS, trig))
        cx, cy, dx, dy, ddx, ddy = cur
        t2 = dx * dx + dy * dy
        t = np.sqrt(t2)
        nx, ny = -dy / t, dx / t                          # inward normal (the outward one is (c'_y, -c'_x))
        d_out = -((x - cx) * nx + (y - cy) * ny)
        delta = -d_out - self.dRb
        # dn = (d beta* c'x c''/|c'|^2) (z x n), d beta* = (c'.dX)/g', g' = |c'|^2 + (c - X).c''
        kap = (dx * ddy - dy * ddx) / (t2 * (t2 + (cx - x) * ddx + (cy - y) * ddy))
        wx, wy = dx * kap, dy * kap
        psi_f = None
        if self.crests:
            zd = self.g.z1 / self.g.k
            psi_f = pose.psi - zd * (beta - pose.beta0)
            side = np.where(psi_f > self.psi_star, 0, np.where(psi_f < -self.psi_star, 1, -1))
            if branch is not None:
                side = np.asarray(branch)[0]
            at = np.flatnonzero(side >= 0)            # the pairs facing a crest corner (a few)
            if at.size:
                gx, gy = self._crest_corners(pose, at, side.ravel()[at])
                ex, ey = gx - x.ravel()[at], gy - y.ravel()[at]
                r = np.hypot(ex, ey)
                ux, uy = ex / r, ey / r
                # (delta, nx, ny, wx, wy are this call's own arrays)
                delta.flat[at] = self.g.R_b - r
                nx.flat[at], ny.flat[at] = ux, uy
                wx.flat[at], wy.flat[at] = uy / r, -ux / r
        ct = Contacts(delta[None], nx[None], ny[None], (x * ny - y * nx)[None], (x * nx + y * ny)[None], None,
                      wx=wx[None], wy=wy[None], psi_f=psi_f)
        ct.branch = side[None] if self.crests else None
        return ct


class InadmissibleProfile(ValueError):
    """A satellite profile the contact level cannot run (pins.md §5.2-5.3, §9).

    ``reason`` names the rule (one of :data:`PROFILE_RULES`), ``values`` the numbers a message needs.
    """

    def __init__(self, reason: str, **values):
        super().__init__(reason)
        self.reason, self.values = reason, values


PROFILE_RULES = ("no_full_tooth", "tooth_too_large", "no_zero_backlash", "interference", "design_curve",
                 "modification", "too_few_teeth", "undercut")
"""The rules of :func:`circular_profile` and :func:`cycloid_profile`, in the order they are tried."""


def circular_profile(g: Cycloid, tooth_radius=None, tooth_circle_radius=None):
    r"""The circular-arc satellite of the contact level with its admissibility rules (pins.md §5.3, §9).

    rho_t = ``tooth_radius`` (None: the full tooth, adjacent teeth tangent at the root: rho_t = R_t sin(pi/z1),
    or :func:`full_tooth` when R_t is not given either); R_t = ``tooth_circle_radius`` (None: the zero-backlash
    circle of :func:`zero_backlash_tooth_circle`).  A tooth must fit, :math:`R_b + \rho_t < R_p - e`, and a given
    R_t must not make the teeth interfere with the pins' nominal paths.

    .. math:: \rho_t = R_t \sin\frac{\pi}{z_1} \ \text{(full tooth)}, \qquad D(R_t) = R_b + \rho_t \
        \text{(zero backlash)}, \qquad R_b + \rho_t < R_p - e

    Parameters
    ----------
    g : Cycloid
        The gear (its R_p, e, R_b, z1) [mm].
    tooth_radius, tooth_circle_radius : float or None
        rho_t, R_t [mm].

    Returns
    -------
    profile : CircularProfile
    overlap : bool
        Whether rho_t exceeds the full tooth R_t sin(pi/z1), so adjacent tooth circles overlap.

    Raises
    ------
    InadmissibleProfile
        ``no_full_tooth``, ``tooth_too_large``, ``no_zero_backlash``, ``interference``.

    Examples
    --------
    >>> g = Cycloid.from_curtate_ratio(21, 22, 3.9, 0.75, 1.95)
    >>> prof, overlap = circular_profile(g, 5.0)      # zero backlash: the teeth just touch the pins' paths
    >>> round(prof.R_t, 2), round(float(tooth_centre_distance(prof.R_t, g)), 9), overlap   # R_b + rho_t = 6.95
    (111.35, 6.95, False)

    References
    ----------
    .. [1] pins.md §5.3 (circular-arc teeth), §9 (hard cases).
    """
    Rp, Rb, e, z1 = g.R_p, g.R_b, g.e, g.z1
    rho_t, R_t = tooth_radius, tooth_circle_radius
    explicit_R_t = R_t is not None
    if rho_t is None:
        if R_t is not None:
            s = math.sin(math.pi / z1)
            rho_t = R_t * s        # adjacent teeth tangent at the root on the given circle
        else:
            full = full_tooth(g)
            if full is None:
                raise InadmissibleProfile("no_full_tooth", R_b=Rb, limit=Rp - e)
            rho_t, R_t = full
    if tooth_too_large(Rb, rho_t, Rp, e):
        raise InadmissibleProfile("tooth_too_large", rho_t=rho_t, sum=Rb + rho_t, limit=Rp - e)
    if not explicit_R_t and R_t is None:
        R_t = zero_backlash_tooth_circle(g, rho_t)
        if R_t is None:
            raise InadmissibleProfile("no_zero_backlash", rho_t=rho_t, sum=Rb + rho_t)
    elif explicit_R_t:
        D = float(tooth_centre_distance(R_t, g))
        if D < Rb + rho_t - 1e-12 * Rp:
            raise InadmissibleProfile("interference", R_t=R_t, depth=Rb + rho_t - D, distance=D, sum=Rb + rho_t)
    overlap = rho_t > R_t * math.sin(math.pi / z1) * (1.0 + 1e-12)
    return CircularProfile(g, rho_t, R_t), overlap


def cycloid_profile(g: Cycloid, radial_mod: float = 0.0, equidistant_mod: float = 0.0) -> CycloidProfile:
    r"""The (modified) cycloidal satellite of the contact level with its admissibility rules (pins.md §5.2, §9).

    The design curve is the pin-centre curve of pin circle R_p + Delta R_p and pin radius R_b + Delta R_b: its
    curtate ratio :math:`K_1 = e z_2/(k (R_p + \Delta R_p))` must be < 1, :math:`R_b + \Delta R_b > 0`, the
    loaded arc psi* must exceed the pin pitch 2 pi/z2, and R_b + Delta R_b must stay below the least radius of
    curvature of the design curve over the loaded arc (no undercut).

    .. math:: K_1 = \frac{e\,z_2}{k\,(R_p + \Delta R_p)} < 1, \quad R_b + \Delta R_b > 0,
        \quad \psi^* > \frac{2\pi}{z_2}, \quad R_b + \Delta R_b < \min_{0 \le \psi \le \psi^*} \rho_c(\psi)

    Parameters
    ----------
    g : Cycloid
        The gear [mm].
    radial_mod, equidistant_mod : float
        Delta R_p, Delta R_b [mm].

    Returns
    -------
    CycloidProfile

    Raises
    ------
    InadmissibleProfile
        ``design_curve``, ``modification``, ``too_few_teeth``, ``undercut``.

    Examples
    --------
    >>> g = Cycloid.from_curtate_ratio(20, 22, 3.9, 0.75, 1.95)
    >>> round(cycloid_profile(g, 0.0, 0.01).design.R_b, 2)
    1.96

    References
    ----------
    .. [1] pins.md §5.2 (cycloidal profile, modifications), §4.2 (undercut), §9.
    """
    Rp, Rb, e, z2, k = g.R_p, g.R_b, g.e, g.z2, g.k
    dRp, dRb = radial_mod, equidistant_mod
    Rpd = Rp + dRp
    if Rpd <= 0.0 or e * z2 >= k * Rpd:
        raise InadmissibleProfile("design_curve", K1=e * z2 / (k * Rpd) if Rpd > 0 else math.inf)
    if Rb + dRb <= 0.0:
        raise InadmissibleProfile("modification", R_b=Rb + dRb)
    prof = CycloidProfile(g, dRp, dRb)
    if prof.psi_star <= g.period:
        raise InadmissibleProfile("too_few_teeth", psi_star=prof.psi_star)
    rho_c = min_curvature_radius(prof.design, prof.psi_star)
    if prof.design.R_b >= rho_c:
        raise InadmissibleProfile("undercut", R_b=prof.design.R_b, rho_c=rho_c)
    return prof


# ============================================================ the registered factories (gearcalc.pins.profiles)

def circular_teeth(g: Cycloid, params) -> tuple[CircularProfile, bool]:
    r"""The factory of the profile "circular" (:data:`gearcalc.pins.profiles.PROFILES`).

    :func:`circular_profile` from a design's values (``params``: :class:`gearcalc.pins.profiles.ProfileParams`;
    "full" and "zero_backlash" as None), marked play-free on the zero-backlash tooth circle.

    .. math:: \rho_t = R_t \sin\frac{\pi}{z_1} \ \text{("full")}, \qquad
        D(R_t) = R_b + \rho_t \ \text{("zero\_backlash")}

    Parameters
    ----------
    g : Cycloid
        The gear.
    params : ProfileParams
        The design's tooth radius rho_t and tooth circle R_t, [mm], or "full" and "zero_backlash".

    Returns
    -------
    profile : CircularProfile
        The profile.
    overlap : bool
        Whether adjacent tooth circles overlap.

    Examples
    --------
    >>> from gearcalc.pins.profiles import ProfileParams
    >>> g = Cycloid.from_curtate_ratio(21, 22, 3.9, 0.75, 1.95)
    >>> p, overlap = circular_teeth(g, ProfileParams(tooth_radius=5.0))
    >>> round(p.R_t, 2), overlap, p.play_free
    (111.35, False, True)

    References
    ----------
    .. [1] docs/spec/pins.md §5.3, §7.
    """
    prof, overlap = circular_profile(g, None if params.tooth_radius == "full" else params.tooth_radius,
                                     None if params.tooth_circle_radius == "zero_backlash"
                                     else params.tooth_circle_radius)
    prof.play_free = params.tooth_circle_radius == "zero_backlash"
    return prof, overlap


def cycloidal_profile(g: Cycloid, params) -> tuple[CycloidProfile, bool]:
    r"""The factory of the profile "cycloidal" (:data:`gearcalc.pins.profiles.PROFILES`).

    The factory of the profile "cycloidal" (:data:`gearcalc.pins.profiles.PROFILES`): :func:`cycloid_profile` with
    the design's modifications; no overlap.

    .. math:: c_b(\beta) \ \text{of } R_p + \Delta R_p, \quad \text{pin radius } R_b + \Delta R_b

    Parameters
    ----------
    g : Cycloid
        The gear.
    params : ProfileParams
        The design's modifications Delta R_p and Delta R_b, [mm].

    Returns
    -------
    profile : CycloidProfile
        The profile.
    overlap : bool
        Always False.

    Examples
    --------
    >>> from gearcalc.pins.profiles import ProfileParams
    >>> p, overlap = cycloidal_profile(Cycloid.from_curtate_ratio(20, 22, 3.9, 0.75, 1.95),
    ...                                ProfileParams(equidistant_mod=0.01))
    >>> round(p.design.R_b, 2), overlap
    (1.96, False)

    References
    ----------
    .. [1] docs/spec/pins.md §5.2, §7.
    """
    return cycloid_profile(g, params.radial_mod, params.equidistant_mod), False
