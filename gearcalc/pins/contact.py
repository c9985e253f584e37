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
* tau from the moment equilibrium of the satellite, M(tau) = M_req, at all crank angles at once by
  safeguarded Newton with the analytic G_tau, warm-started from the solved neighbours (cubic Hermite
  in tau and d tau/d theta), with the shared bracketed root finder (:func:`gearcalc.roots.find_root`)
  as the fallback (§5.5); with friction in the balance (the friction-consistent model, §4.9) the
  friction forces' directions are iterated to a fixed point, and a crank angle where no rotation
  balances the torque with them makes the mode jam (:class:`Jam`);
* only the pins of a candidate window, those that can touch, are evaluated (:meth:`ContactModel.set_window`);
* the satellite's angular speed d tau/d theta = -G_theta/G_tau analytically, the contact-point
  velocities, the pin spin and the per-contact losses (§5.6), reusing the loss functions of
  :mod:`gearcalc.pins`;
* the cycle mean of the loss ratio with :func:`gearcalc.quadrature.integrate_adaptive` (pieces doubled only
  where needed), the breakpoints (contact entry/exit, spin reversals, crest passages) scanned and refined
  by Newton (penetrations, with their slope along the solution) or secant steps (§6); a later pass of the
  torque fixed point, and the other mode, move the last pass's breakpoints instead of scanning again, and
  the quadrature's nodes confirm that no contact appeared or vanished (else the full scan);
* the torque fixed point (§7): a coarse loss ratio from the window's scan, then full passes (secant-Newton
  steps after the second) until the linearised remaining change of the loss ratio is below tol/10.

The profiles and penetrations (the first item) are in :mod:`gearcalc.pins.contact_profiles`, the contact laws (the
second) in :mod:`gearcalc.pins.contact_law`; both are re-exported here, so that the level's names stay in one place.

Why a module of its own: the formula and ideal levels (the other modules of :mod:`gearcalc.pins`) are
closed-form geometry evaluated pointwise; this level carries its own state (profiles, a contact law, a
solved pose per crank angle, a cycle cache) and is only imported when a design needs it.  It reuses
:class:`~gearcalc.pins.geometry.Cycloid`, :func:`~gearcalc.pins.geometry.pin_centre_curve`,
:func:`~gearcalc.pins.geometry.crest_cutoff`, :func:`~gearcalc.pins.geometry.tooth_profile`,
:func:`~gearcalc.pins.forces.pin_phase`, the loss functions of :mod:`gearcalc.pins.efficiency` and the
adaptive driver of :mod:`gearcalc.quadrature`.

Frames.  The satellite frame has its origin at O1 and turns with the satellite (pins.md §5.1):
pin j at X_j = Rot(-phi)(A_j - O1).  A contact has the unit normal n pointing from the pin centre
into the satellite; the pin pushes the satellite with F n along the line through X_j, so its moment
about O1 is F (X_j x n).
"""
from __future__ import annotations

import dataclasses
import functools
import math
import warnings
from dataclasses import dataclass, field

import numpy as np

from ..arrays import unique_sorted
from ..quadrature import _KRONROD, QuadResult, geometric_breakpoints, integrate_adaptive, richardson_mean
from ..roots import BracketError, find_root
from .contact_law import HERTZ_EXPONENT, PALMGREN_COEFFICIENT, ContactLaw, contact_law, palmgren_line_constant
from .contact_profiles import (PROFILE_RULES, CircularProfile, Contacts, CycloidProfile, InadmissibleProfile, Pose,
                               circular_profile, cycloid_profile, full_tooth, tooth_centre_distance,
                               zero_backlash_tooth_circle)
from .cycle import disc_offsets, disc_sum_peak, sum_over_discs
from .efficiency import contact_loss_power
from .forces import pin_phase
from .geometry import MULTIPLIER, REDUCER, Cycloid

__all__ = [
    # the contact laws (:mod:`gearcalc.pins.contact_law`) and the profiles (:mod:`gearcalc.pins.contact_profiles`),
    # re-exported: the contact level's names in one place
    "ContactLaw", "contact_law", "palmgren_line_constant", "PALMGREN_COEFFICIENT", "HERTZ_EXPONENT",
    "tooth_centre_distance", "zero_backlash_tooth_circle", "full_tooth", "Pose", "Contacts",
    "CircularProfile", "CycloidProfile", "InadmissibleProfile", "PROFILE_RULES", "circular_profile",
    "cycloid_profile",
    # this module's
    "ContactModel", "NoEquilibrium", "Jam", "Solution",
    "contact_losses", "mean_loss_ratio", "cycle_breakpoints", "engagement_metrics", "free_play",
    "backlash", "CyclePeaks", "cycle_peaks", "Unresolvable", "fixed_point_settled", "TorqueCycle", "cycle_at_torque",
    "ModeCycles", "solve_modes", "mode_efficiencies", "equilibrium_residual", "ContactOperating", "operating_values",
    "MULTIPLIER", "REDUCER",
]

EPS = float(np.finfo(float).eps)


# ============================================================ equilibrium (pins.md §5.1, §5.5)

class NoEquilibrium(ValueError):
    """No satellite rotation within +-pi/z1 balances the torque at some crank angle."""

    def __init__(self, theta):
        super().__init__("no contact can carry the torque")
        self.theta = theta


class Jam(NoEquilibrium):
    """With the friction forces in the moment balance, no positive contact force balances the torque at
    some crank angle although the frictionless balance has a solution: the mode jams (self-locks) there
    (pins.md §4.9, §5.5)."""


@dataclass
class Solution:
    """The solved contact state at crank angles theta (n,), per contact (c, z2, n).

    tau: transmission error phi - phi_nom [rad]; dtau: d tau/d theta [-]; residual: M - M_req [N·mm];
    delta [mm], force [N], v_t: tangential speed of the satellite at the contact per unit crank
    speed [mm/s per rad/s] (positive along z x n); phase: load-side phase of each pin [rad] (z2, n);
    zeta: pin phase measured along time, theta - phi_j wrapped to (-pi, pi] [rad] (z2, n);
    cand: (z2, n) the pins evaluated at each angle (the candidate window), None: all; the others cannot
    touch (delta = -inf, F = 0, v_t = 0 there);
    ddelta: (c, z2, n) d delta/d theta along the solution, n.dX/dtheta - (X x n) d tau/d theta [mm/rad]
    (the Newton slope of the contact entries and exits, :func:`cycle_breakpoints`);
    noise: (n,) the round-off floor of the residual [N·mm]: eps (R_p + e) sum |F'(delta) X x n|, the moment
    change of a round-off of the pin positions at every contact (the penetrations are differences of
    lengths ~R_p);
    g_tau: (n,) dG/dtau of the moment balance at the solution [N·mm/rad] (the warm start of another torque,
    :meth:`ContactModel.inherit`);
    nx, ny, wx, wy: (c, m, n) the contacts' normals and their turning rates (:class:`Contacts`) over the pins
    ``pins`` (m, n) the state was solved on (the candidate window, or all pins), at the solved rotation (within a
    last Newton step of it): kept for the crank bearing (:func:`crank_bearing`), None where not known;
    rows: (R,) the pins (sorted) that the per-pin arrays (delta, force, v_t, phase, zeta, switch, branch, cand,
    ddelta) hold, in that order: the pins the candidate window can hold over the period
    (:meth:`ContactModel.layout`); every other pin cannot touch anywhere on the cycle (R of z2 rows: the arrays
    of a u = 30 paper design are 6x smaller).  None: all z2 pins, in order;
    traction: (c, R, n) the friction forces per unit normal force the state was solved with (:meth:`ContactModel.
    traction` of the directions it settled on, or its piece's fixed ones), over the rows (0 where a pin is out of
    reach); None without friction in the balance.  At a piece end, or where no direction is consistent (the
    directions flip back and forth, :meth:`ContactModel._friction_fixed_point`), they can differ from the
    directions of the state's own sliding speeds: the crank bearing takes these (:func:`crank_bearing`).
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
    cand: np.ndarray | None = None
    ddelta: np.ndarray | None = None
    noise: np.ndarray | None = None
    g_tau: np.ndarray | None = None
    nx: np.ndarray | None = None
    ny: np.ndarray | None = None
    wx: np.ndarray | None = None
    wy: np.ndarray | None = None
    pins: np.ndarray | None = None
    rows: np.ndarray | None = None
    traction: np.ndarray | None = None

    def over_pins(self, z2: int) -> "Solution":
        """This state over all ``z2`` pins in order, to index its per-pin arrays by pin number: the rows scattered,
        every other pin out of reach (no contact; phases None where not held: :meth:`ContactModel.phases`)."""
        return _relayout(self, None, z2)


_GEOMETRY_FIELDS = ("nx", "ny", "wx", "wy", "pins")
"""The :class:`Solution` fields over the pins it was solved on (m, not its rows): never scattered to its rows."""

_PIN_FIELDS = ("delta", "force", "v_t", "phase", "zeta", "switch", "branch", "cand", "ddelta", "traction")
"""The :class:`Solution` fields over its ``rows`` (the pin axis second to last), with the values of a pin that is not
a candidate (out of reach: no contact)."""

_PIN_FILL = {"delta": -np.inf, "force": 0.0, "v_t": 0.0, "switch": np.nan, "branch": -1, "cand": False, "ddelta": 0.0,
             "traction": 0.0}

_CONTACT_FIELDS = ("delta", "nx", "ny", "arm", "xn", "switch", "branch", "wx", "wy")


def _filled(shape, value, dtype=float):
    """np.full without its Python wrapper (the scatters of every solve call it): an empty array filled in place."""
    out = np.empty(shape, dtype)
    out.fill(value)
    return out


def _with_cols(full, part, cols):
    """``full`` (..., n) with its columns ``cols`` replaced by ``part`` (a copy; None stays None)."""
    if full is None or part is None:
        return full
    out = np.array(full, dtype=np.result_type(full, part), copy=True)
    out[..., cols] = part
    return out


def _contact_index(profile, sides):
    """The contacts of each pin that a state holds, as an index (c, 1, 1) over the profile's c per pin (all of them
    when ``sides`` is None; :attr:`ContactModel.sides`)."""
    return (np.arange(profile.contacts_per_pin) if sides is None else np.asarray(sides))[:, None, None]


def _sub_pose(pose: Pose, sel) -> Pose:
    """The pose at the crank angles ``sel`` (a boolean mask or indices over the last axis)."""
    return Pose(pose.theta[sel], pose.x0[:, sel], pose.y0[:, sel], pose.beta0[:, sel], pose.z2,
                {k: v[..., sel] for k, v in pose.aux.items()}, None if pose._psi is None else pose._psi[:, sel])


def _distance_to(points, x):
    """The distance from each of ``x`` to the nearest of ``points`` (sorted, not empty).

    >>> _distance_to(np.array([0.0, 1.0]), np.array([-1.0, 0.25, 0.5, 3.0])).tolist()
    [1.0, 0.25, 0.5, 2.0]
    """
    k = np.minimum(np.maximum(points.searchsorted(x), 1), points.size)
    return np.minimum(np.abs(x - points[k - 1]), np.abs(x - points[np.minimum(k, points.size - 1)]))


def _hermite(t, h, fa, da, fb, db):
    """The cubic Hermite interpolant at t = (x - x_a)/h in [0, 1] of values f and slopes d at x_a and x_a + h."""
    t2, t3 = t * t, t * t * t
    return ((2 * t3 - 3 * t2 + 1) * fa + (t3 - 2 * t2 + t) * h * da + (-2 * t3 + 3 * t2) * fb + (t3 - t2) * h * db)


def _hermite_slope(t, h, fa, da, fb, db):
    """The derivative d/dx of :func:`_hermite` at t = (x - x_a)/h.

    >>> bool(abs(_hermite_slope(0.3, 2.0, 1.0, -0.5, 4.0, 2.0)
    ...          - (_hermite(0.3 + 1e-7, 2.0, 1.0, -0.5, 4.0, 2.0) - _hermite(0.3 - 1e-7, 2.0, 1.0, -0.5, 4.0, 2.0))
    ...          / 4e-7) < 1e-8)
    True
    """
    t2 = t * t
    return (6.0 * t2 - 6.0 * t) * (fa - fb) / h + (3.0 * t2 - 4.0 * t + 1.0) * da + (3.0 * t2 - 2.0 * t) * db


def _doubling_bracket(G, n: int, h0: float, limit: float):
    """Brackets of the roots of a decreasing G(tau) (n,) about tau = 0, by doubling a step from h0 on the side of
    sign(G(0)) up to ``limit``: (a, b, open), open where no sign change lies within +-limit."""
    G0 = G(np.zeros(n))
    direction = np.where(G0 > 0.0, 1.0, -1.0)            # G decreasing: root on the side of sign(G0)
    lo, hi = np.zeros(n), np.zeros(n)
    h = h0
    open_ = G0 != 0.0
    prev = np.zeros(n)
    while open_.any():
        step = min(h, limit)
        Gs = G(direction * step)
        found = open_ & (np.sign(Gs) != np.sign(G0))
        lo = np.where(found, prev, lo)
        hi = np.where(found, direction * step, hi)
        open_ &= ~found
        prev = np.where(open_, direction * step, prev)
        if step >= limit:
            break
        h *= 2.0
    return np.minimum(lo, hi), np.maximum(lo, hi), open_


def _bracket_root(G, theta, a, b, xtol: float):
    """The roots of the moment balance G on the brackets [a, b] at crank angles theta (by
    :func:`gearcalc.roots.find_root`); :class:`NoEquilibrium` at the angles whose ends no longer hold a sign change:
    for a rotation far beyond a deflection the contact geometry depends on the search's path (a cycloidal pin's foot
    point can jump to another flank between evaluations), so a bracket found by one search need not hold for the
    next (pins.md §5.5, §7)."""
    try:
        return find_root(G, a, b, xtol=xtol, rtol=0.0).root
    except BracketError as exc:
        raise NoEquilibrium(np.asarray(theta)[exc.mask]) from None


def _window_range(tau) -> tuple[float, float]:
    """The candidate window's range of tau from a scan's: each end twice as far from 0, or half as near when the
    range does not reach 0 (:meth:`ContactModel.set_window`)."""
    lo, hi = float(np.min(tau)), float(np.max(tau))
    return (2.0 * lo if lo < 0.0 else 0.5 * lo), (2.0 * hi if hi > 0.0 else 0.5 * hi)


WINDOW_MARGIN = 2
"""The candidate window's margin in time phase beyond the outermost pairs that can touch, in spacings of its scan
(:meth:`ContactModel.set_window`): the scan's n_scan crank angles over all z2 pins sample the time phase zeta on a
grid of T_p/n_scan (the contact geometry of a pin depends on zeta alone), so a pin between the last sample that can
touch and the first that cannot lies within one spacing; two for safety.  (It was one pin pitch T_p, n_scan = 64
spacings: two pins more per angle than needed.)  The pins next to the window are checked on each cycle's final grid
(:meth:`ContactModel.window_holds`)."""

NEWTON_SMALL = 1e-8
"""A warm start's Newton step s is taken without a new balance (:meth:`ContactModel._kinematics` with ``step``) when
|s| <= 1e-8 |tau| (quadratic convergence: the error is then ~s^2/tau <= 1e-16 |tau|, and the geometry, kept at the
start, moves by (R_p + e) s ~ 1e-10 mm, far below the deflections' resolution)."""

REFINE_NEWTON_STOP, REFINE_NEWTON_SMALL = 1e-11, 1e-12
""":data:`NEWTON_STOP` and :data:`NEWTON_SMALL` of the solves that refine a scanned penetration's sign change from the
smooth side (:func:`_scan_roots`, :attr:`ContactModel._refining`): a root is taken from one such state's value and
slope, so the penetration must hold to well below 1e-12 T_p times its slope (with the product's stops, a state next to a
Hertz contact's entry warm-started from the scan came out ~1e-10 mm off; measured 2026-11-27).  An iteration or two
more per refinement call (2-3 crank angles)."""

NEWTON_STOP = 1e-6
"""The satellite rotation's Newton iteration (:meth:`ContactModel._solve`) stops after a step |s| <= 1e-6 |tau|: its
error is then C s^2 with C = |G_tautau tau/(2 G_tau)|, measured 0.05-3 on the paper designs (the ratio of successive
relative steps), so <= ~3e-12 |tau|, the resolution of tau itself (a deflection of ~1e-3 mm out of positions of
~60 mm held to 1e-14 mm: ~1e-11); the kinematics then evaluate the geometry at the stepped tau.  (1e-8 took one
balance more per solve, whose step was that round-off, 3e-12 to 1e-13.)"""


class ContactModel:
    """The satellite of one design under one torque: pose, penetrations, moment, equilibrium, speeds.

    Parameters
    ----------
    g : the pin gear (actual pins: z1, z2, e, R_p, R_b).
    profile : :class:`CircularProfile` or :class:`CycloidProfile`.
    law : the contact law.
    torque_sat : T_sat, torque per satellite [N·mm], > 0.
    sigma : +1 reducer (M_req = -T_sat), -1 multiplier (M_req = +T_sat)  (pins.md §5.5).
    friction : None (frictionless forces, the first-order model) or (mu_eff, f, rolls): add the
        tangential friction forces to the moment balance (the friction-consistent model, §4.9, §5.5).

    Speed (pins.md §5.5-5.6): the equilibrium is solved at all crank angles at once by safeguarded
    Newton on G(tau) = M(tau) - M_req with the analytic G_tau (warm-started from the nearest solved
    angle, tau + d tau/d theta * d theta), falling back to the bracketed root finder; d tau/d theta =
    -G_theta/G_tau analytically; only the pins of a candidate window (those that can touch for
    |tau| <= 2 max |tau| of a first solve, :meth:`set_window`) are evaluated.
    """

    _refining = False
    """Solves for a breakpoint's refinement: stopped at :data:`REFINE_NEWTON_STOP` and :data:`REFINE_NEWTON_SMALL`."""

    def __init__(self, g: Cycloid, profile, law: ContactLaw, torque_sat: float, sigma: int, friction=None):
        self.g, self.profile, self.law = g, profile, law
        self.torque_sat, self.sigma = float(torque_sat), sigma
        self.M_req = -self.torque_sat if sigma == REDUCER else self.torque_sat
        self.pins = np.arange(g.z2)[:, None]
        self.friction = friction
        self.diff_step = 1e-6
        self.window = None            # (z_lo, z_hi, m, tau_bound): candidate pins by time phase, or None: all
        self._sides = None            # (window, sides): :attr:`sides` while that window is the model's
        self.clearance = None         # (theta, tau, clearance, (candidates, sides)) of the last final grid's check
        self.last_pose = None         # the pose of the last state (its foot points start the next torque's)
        self._memo = {0: None, 1: None}   # solved (theta, tau, dtau) for warm starts: 0 frictionless, 1 final
        self._gtau = {0: None, 1: None}   # dG/dtau at the memo's angles (None: unknown)
        self.roots = None             # the located sign changes of its last cycle (:func:`mean_loss_ratio`)
        self._layout = None           # (window, rows, pos) of :meth:`layout`
        self._nominal_cache = {}      # n_scan -> :meth:`_nominal` (shared with the models that inherit or mirror)
        self.scan_n = 0               # the densest full scan a cycle of this design needed (:func:`mean_loss_ratio`)

    # -- geometry -------------------------------------------------------------------------------
    def pose(self, theta, idx=None, sides=None) -> Pose:
        """Nominal satellite-frame pin positions at crank angles theta (tau = 0); ``idx`` (m, n): only
        these pins (default: all, shape (z2, n)); ``sides``: only these of each pin's contacts (default: all;
        :attr:`sides`)."""
        g = self.g
        theta = np.atleast_1d(np.asarray(theta, dtype=float))
        sel = self.pins if idx is None else idx
        beta0 = 2.0 * math.pi * sel / g.z2 + (g.k / g.z1) * theta[None, :]
        a = (g.z2 / g.z1) * theta[None, :]
        trig = (np.cos(beta0), np.sin(beta0), np.cos(a), np.sin(a))
        x0 = g.R_p * trig[0] - g.e * trig[2]
        y0 = g.R_p * trig[1] - g.e * trig[3]
        p = Pose(theta, x0, y0, beta0 if beta0.shape == x0.shape else np.broadcast_to(beta0, x0.shape), g.z2)
        p.aux["idx"] = sel if np.shape(sel) == x0.shape else np.broadcast_to(sel, x0.shape)
        self.profile.prepare(p, trig, sides)
        return p

    def candidates(self, theta):
        """Pin indices (m, n) of the candidate window at crank angles theta, or None (all pins).

        Pin j has the time phase zeta_j = theta - 2 pi j/z2 (mod 2 pi); the window holds the m
        consecutive pins from the first with zeta_j <= z_hi, which covers [z_lo, z_hi]."""
        if self.window is None:
            return None
        _, z_hi, m, _ = self.window
        z2 = self.g.z2
        j0 = np.mod(np.ceil((np.asarray(theta, dtype=float) - z_hi) / self.g.period).astype(np.int64), z2)
        j = j0[None, :] + np.arange(m)[:, None]       # in [0, 2 z2): wrapped by a subtraction, not an integer modulo
        return j - z2 * (j >= z2)

    @property
    def sides(self):
        """The contacts of each pin that the states evaluate (indices into the profile's c per pin), or None (all):
        with a candidate window, those that can touch for its range of tau (:meth:`_window_for`; circular teeth: the
        tooth on the side the torque presses the pins against, the other one cannot touch at that rotation).  The
        states' arrays hold every contact all the same (:meth:`_full`: the others out of reach)."""
        s = self._sides
        return s[1] if s is not None and self.window is not None and s[0] == self.window else None

    def set_window(self, n_scan: int = 64):
        """The candidate window: the time phases zeta of the pins that can touch (pins.md §5.5, speed).

        The balance with the penetrations linearised about the nominal pose (:meth:`_linearised_tau`, all pins,
        ``n_scan`` crank angles of one period) gives tau; the window allows tau in [tau_lo, tau_hi], each end of
        that range twice as far from 0 (or half as near when the range does not reach 0); the scan is then solved
        on the window's pins from those starts, and kept when its tau stay in [tau_lo, tau_hi] (else, or where the
        linearised balance has no root, the scan is solved over all pins by doubling and Newton, and the window
        taken from its range).  Since d delta/d tau = -(X x n) and
        |d^2 delta/d tau^2| <= |X| <= R_p + e, a pair with

            max over tau in {tau_lo, tau_hi} of delta(0) - (X x n) tau + (R_p + e) tau^2/2 <= 0

        (1 % and 1e-12 R_p of margin) cannot touch there.  The window is the shortest arc of zeta holding
        every other pair, widened by :data:`WINDOW_MARGIN` scan spacings on each side (the scan's resolution in zeta).
        :func:`mean_loss_ratio` checks the tau range on the final grid.  Returns the scan's solution
        (all pins' phases), which also seeds the warm starts."""
        g = self.g
        theta = np.arange(n_scan) * (g.period / n_scan)
        if getattr(self, "_mirrored", False) and self.window is not None:
            guess = None
            if self.friction is not None:
                # with friction, the mirrored states are the other mode's: its friction moment turns the satellite
                # the other way, tau_other = tau_0 + d against tau = tau_0 - d + O(f^2) (tau_0 frictionless): start
                # from 2 tau_0 - tau_other, the frictionless scan's mirror at these very angles
                g0, g1 = self._guess(theta, 0, slope=True), self._guess(theta, 1, slope=True)
                if g0 is not None and g1 is not None and self._memo[0] is not self._memo[1]:
                    guess = (2.0 * g0[0] - g1[0], 2.0 * g0[1] - g1[1])
            sol = self.state(theta, guess=guess)       # the other mode's window, mirrored: the scan only
            if self.friction is not None:
                # the mirrored warm starts hold the other mode's friction forces (tau off by O(f)): the scan's own
                # solutions replace them
                self._memo[1], self._gtau[1] = None, None
                self._remember(1, sol)
            return sol
        self.window = None
        # the doubling starts near the rotation at which one pin at R_p would carry the torque, /8 (5-10 pins share it)
        R = g.R_p + g.e
        h0 = float(self.law.deflection(self.torque_sat / R)) / R / 8.0
        h0 = h0 if math.isfinite(h0) and h0 > 1e-9 else 1e-9
        with np.errstate(all="ignore"):
            est = self._linearised_tau(n_scan, h0)
        first, start = None, None
        if est is not None and np.isfinite(est).all():
            # the window from the linearised balance's range; the scan solved on its pins only, kept when its tau
            # stay in the window's range (else every pin, below)
            self._window_for(*_window_range(est), n_scan)
            idx = self.candidates(theta)
            sides = self.sides
            sub = self.pose(theta, idx, sides)
            with np.errstate(divide="ignore", invalid="ignore"):
                try:
                    part = self._kinematics(sub, self._solve(sub, None, est), None)
                except NoEquilibrium:
                    part = None
            if part is not None and self.window_holds(part.tau) and np.isfinite(part.dtau).all():
                first = self._full(part, idx, sides)
                start = (sub, part)
        if first is None:
            self.window = None
            pose = self.pose(theta)
            tau = self._bracketed(pose, None, 1e-15, h0, newton=True)
            with np.errstate(divide="ignore", invalid="ignore"):
                first = self._kinematics(pose, tau, None)
            self._window_for(*_window_range(tau), n_scan)
            first = _relayout(first, self.layout()[0])
        if np.isfinite(first.dtau).all():
            self._remember(0, first)   # the frictionless solution warm-starts the scan below
        if self.friction is None and np.isfinite(first.dtau).all():
            # the frictionless scan is the state over all pins (the window's pins the same, the others untouched)
            first.phase, first.zeta = self.phases(theta, first.rows)
            return first
        # and the warm-start memory for the cycle; the friction directions from the frictionless scan on the window's
        # pins (its pose and solution, not solved again)
        return self.state(theta, scan=start if np.isfinite(first.dtau).all() else None)

    def _nominal(self, n_scan: int = 64):
        """(psi, delta, arm) of every pin at the nominal pose (tau = 0) on ``n_scan`` crank angles of one period
        (:class:`Pose`, :class:`Contacts`): the window's and the linearised balance's data (:meth:`_window_for`,
        :meth:`_linearised_tau`).  They depend on the design only (not on the torque or the mode): computed once
        and shared with the models that inherit or mirror this one."""
        nom = self._nominal_cache.get(n_scan)
        if nom is None:
            pose = self.pose(np.arange(n_scan) * (self.g.period / n_scan))
            ct = self.contacts(pose, np.zeros(n_scan))
            nom = self._nominal_cache[n_scan] = (pose.psi, ct.delta, ct.arm)
        return nom

    def _window_for(self, t_lo: float, t_hi: float, n_scan: int = 64) -> None:
        """Set the candidate window to the pins that can touch for tau in [t_lo, t_hi] (see :meth:`set_window`;
        None when every pin can).  The pin set depends on the tau range: a window taken over from another
        torque or mode (:meth:`inherit`, :meth:`mirror`) with its tau range scaled must be recomputed for the
        scaled range, else pins that touch only at the larger |tau| are left out (and the range check of
        :func:`mean_loss_ratio` still passes)."""
        g = self.g
        self.window = None
        psi, delta, arm = self._nominal(n_scan)
        R = g.R_p + g.e
        # delta(tau) <= delta(0) - (X x n) tau + (R_p + e) tau^2/2: convex in tau, largest at an end
        reach = np.maximum(-arm * t_lo + 0.5 * R * t_lo * t_lo, -arm * t_hi + 0.5 * R * t_hi * t_hi)
        touch_c = delta + reach + 0.01 * np.abs(reach) + 1e-12 * g.R_p > 0.0
        touch = touch_c.any(axis=0)
        z = np.sort(-psi[touch])
        if z.size:
            gaps = np.diff(np.concatenate((z, [z[0] + 2.0 * math.pi])))
            i = int(np.argmax(gaps))
            z_lo, z_hi = (z[0], z[-1]) if i == z.size - 1 else (z[i + 1], z[i] + 2.0 * math.pi)
            pad = WINDOW_MARGIN * g.period / n_scan
            z_lo, z_hi = z_lo - pad, z_hi + pad
            m = int(math.floor((z_hi - z_lo) / g.period)) + 2
            if m < g.z2:
                self.window = (float(z_lo), float(z_hi), m, (t_lo, t_hi))
                # the contacts of a pin that can touch at all (circular teeth: one of the two, by the torque's sense)
                can = touch_c.any(axis=(1, 2))
                self._sides = (self.window, np.flatnonzero(can)) if can.any() and not can.all() else None

    def period_pins(self):
        """The pins the candidate window can hold at crank angles in [0, T_p] (sorted), or None (every pin): the
        rows of the states' per-pin arrays (:meth:`layout`).

        The window's first pin j0(theta) does not decrease with theta and grows by one over a period, so the
        pins of its two ends hold every one in between."""
        if self.window is None:
            return None
        rows = np.union1d(*self.candidates(np.array([0.0, self.g.period])).T)
        return None if rows.size >= self.g.z2 else rows

    def layout(self):
        """(rows, pos): the pins the per-pin arrays of this model's states hold (:attr:`Solution.rows`: the candidate
        window's over one period, :meth:`period_pins`; None: all z2), and each pin's row there (z2,), -1 for a pin
        they do not hold.  Fixed while the window is (a cycle's states share it)."""
        if self._layout is None or self._layout[0] != self.window:
            rows = self.period_pins()
            pos = np.arange(self.g.z2)
            if rows is not None:
                pos = np.full(self.g.z2, -1)
                pos[rows] = np.arange(rows.size)
            self._layout = (self.window, rows, pos)
        return self._layout[1], self._layout[2]

    def window_holds(self, tau, theta=None, prev: "ContactModel | None" = None) -> bool:
        """Whether the solved tau stay in the range the candidate window allows (or there is no window) and, with
        their crank angles ``theta``, the pins next to the window on either side do not touch there (penetration
        <= 0 at tau: :data:`WINDOW_MARGIN`), nor the contacts of the window's pins that :attr:`sides` leaves out.

        The smallest clearance -delta of those pairs is kept (:attr:`clearance`).  ``prev``: a model checked at the
        same crank angles with the same candidate pins and sides (the torque pass before): where its clearance c exceeds
        (R_p + e)(d + d^2/2), d = max |tau - tau_prev|, no pair can have closed it (|d delta/d tau| = |X x n| <=
        R_p + e, |d^2 delta/d tau^2| <= R_p + e) and nothing is evaluated."""
        self.clearance = None
        if self.window is None:
            return True
        t_lo, t_hi = self.window[3]
        if not ((tau >= t_lo) & (tau <= t_hi)).all():
            return False
        if theta is None or tau.size == 0:
            return True
        idx, sides = self.candidates(theta), self.sides
        key = (idx, None if sides is None else tuple(sides.tolist()))       # the pairs the states evaluate
        last = None if prev is None else prev.clearance
        if (last is not None and last[0].shape == theta.shape and np.array_equal(last[0], theta)
                and last[3][1] == key[1] and np.array_equal(last[3][0], idx)):
            d = float(np.abs(tau - last[1]).max())
            bound = (self.g.R_p + self.g.e) * (d + 0.5 * d * d)
            if bound < last[2]:
                self.clearance = (theta, tau, last[2] - bound, key)
                return True
        if sides is None:
            pins = np.stack((idx[0] - 1, idx[-1] + 1))
        else:
            # and the contacts of the window's pins that the states leave out (:attr:`sides`)
            pins = np.concatenate(((idx[0] - 1)[None], idx, (idx[-1] + 1)[None]))
        with np.errstate(all="ignore"):
            delta = self.contacts(self.pose(theta, np.mod(pins, self.g.z2)), tau).delta
        if sides is not None:
            delta = delta.copy()
            delta[sides[:, None], np.arange(1, pins.shape[0] - 1)[None, :]] = -np.inf
        c = float(-delta.max())
        if not c >= 0.0:
            return False
        self.clearance = (theta, tau, c, key)
        return True

    def mirror(self, other: "ContactModel") -> None:
        """Start from the solved other mode of the same design: its window and warm starts mirrored.

        Without friction in the balance the reducer is the multiplier run backwards (pins.md §4.8(5),
        §5.7): tau_R(-theta) = -tau_M(theta), so the time phases zeta, the tau range and tau change
        sign and d tau/d theta keeps it; scaled by the torque ratio like :meth:`inherit`.  With friction
        this is a warm start only (the window's tau range is checked on the final grid)."""
        r = (self.torque_sat / other.torque_sat) ** (1.0 / self.law.exponent)
        self._nominal_cache, self.scan_n = other._nominal_cache, other.scan_n      # the same design
        if other.window is not None:
            z_lo, z_hi, m, (t_lo, t_hi) = other.window
            self.window = (-z_hi, -z_lo, m, (-t_hi * r, -t_lo * r))
            # the mirror swaps each pin's two teeth (the one below its polar angle and the one above)
            sides = other.sides
            self._sides = None if sides is None else (self.window,
                                                      np.sort(self.profile.contacts_per_pin - 1 - sides))
            if r > 1.0:                   # a wider tau range: its pins recomputed (:meth:`_window_for`)
                with np.errstate(all="ignore"):
                    self._window_for(-t_hi * r, -t_lo * r)
        Tp = self.g.period
        for key, memo in other._memo.items():
            if memo is not None:
                th = np.mod(-memo[0], Tp)
                order = th.argsort(kind="stable")
                self._memo[key] = (th[order], -memo[1][order] * r, memo[2][order] * r)
        if self.friction is not None and self._memo[1] is None:
            self._memo[1] = self._memo[0]
        self._gtau = {0: None, 1: None}
        self._mirrored = True

    def inherit(self, prev: "ContactModel") -> None:
        """Start from the candidate window and the solved angles of the same design at another torque.

        tau scales about as the deflection, (T/T_prev)^(1/p) for the law F ~ delta^p: the warm starts
        and the window's tau range are scaled by it (the range is checked on the final grid)."""
        r = (self.torque_sat / prev.torque_sat) ** (1.0 / self.law.exponent)
        self._nominal_cache, self.scan_n = prev._nominal_cache, prev.scan_n        # the same design
        if prev.window is not None:
            z_lo, z_hi, m, (t_lo, t_hi) = prev.window
            self.window = (z_lo, z_hi, m, (t_lo * r, t_hi * r))
            self._sides = None if prev.sides is None else (self.window, prev.sides)
            if r > 1.0:                   # a wider tau range: its pins recomputed (:meth:`_window_for`)
                with np.errstate(all="ignore"):
                    self._window_for(t_lo * r, t_hi * r)
        dM = self.M_req - prev.M_req
        for key, memo in prev._memo.items():
            if memo is not None:
                tau = memo[1] * r
                gt = prev._gtau[key]
                if gt is not None and gt.shape == tau.shape:
                    # the Newton step of the new torque from the solution of the old one: tau + dM/G_tau (its error
                    # is second order in the torque change), where G_tau < 0 and the step within 10x the scaling's
                    with np.errstate(divide="ignore", invalid="ignore"):
                        newton = memo[1] + dM / gt
                    ok = (gt < 0.0) & np.isfinite(newton) & (np.abs(newton - memo[1]) <= 10.0 * np.abs(tau - memo[1]))
                    tau = np.where(ok, newton, tau)
                    # G_tau at the new torque differs by O(dM): good for the next pass's Newton step
                    self._gtau[key] = gt
                self._memo[key] = (memo[0], tau, memo[2] * r)

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
            return (F * ct.arm).sum(axis=(0, 1))
        return (F * (ct.arm + traction * (ct.xn + self.g.R_b))).sum(axis=(0, 1))

    def _balance(self, pose: Pose, tau, traction=None, ref=None):
        r"""G = M - M_req and its analytic derivative G_tau, with the contact data (pins.md §5.5).

        With the moment arm A = X x n + q (X.n + R_b) of a pair, dn = (w . dX)(z x n) and
        dX/dtau = (y, -x):

        .. math::

            G_\tau = \sum -F'(\delta)\,(X\times n)\,A + F\,(1 + w\cdot X_\tau)(X\cdot n - q\,X\times n)

        Returns (G, G_tau, ct, F, Fp, A, q, x, y, G_geo), G_geo the part of G_tau at fixed deflections."""
        c, s = np.cos(tau), np.sin(tau)
        x = c * pose.x0 + s * pose.y0
        y = -s * pose.x0 + c * pose.y0
        if ref is None:
            ct = self.profile.contacts(pose, x, y)
            F, Fp = self.law.force_stiffness(ct.delta)
        else:
            ct = self.profile.contacts(pose, x, y, ref[1])
            F, Fp = self.law.force_stiffness(ct.delta, ref[0])
        q = 0.0 if traction is None else traction
        A = ct.arm if traction is None else ct.arm + q * (ct.xn + self.g.R_b)
        G, G_tau, G_geo = self._moment_slope(ct, F, Fp, A, q, x, y)
        return G, G_tau, ct, F, Fp, A, q, x, y, G_geo

    def _moment_slope(self, ct: Contacts, F, Fp, A, q, x, y):
        """(G, G_tau, G_geo) of :meth:`_balance` from the contact data; G_geo: the part of G_tau from the turning
        geometry at fixed deflections, sum F (1 + w.X_tau)(X.n - q X x n)."""
        G = (F * A).sum(axis=(0, 1)) - self.M_req
        one = 1.0 + (ct.wx * y - ct.wy * x)
        G_geo = (F * one * (ct.xn - q * ct.arm)).sum(axis=(0, 1))
        return G, (-Fp * ct.arm * A).sum(axis=(0, 1)) + G_geo, G_geo

    # -- equilibrium ------------------------------------------------------------------------------
    def solve(self, theta, xtol: float = 1e-15, traction=None, pose=None):
        """tau at crank angles theta from M(tau) = M_req: bracket by doubling from 1e-9 rad, then Chandrupatla.

        M does not increase with tau for deflection-sized rotations; the solver relies only on the
        sign change (pins.md §5.5).  Raises :class:`NoEquilibrium` when no sign change exists within
        +-pi/z1.  Returns (pose, tau, residual).
        """
        pose = self.pose(theta) if pose is None else pose
        tau = self._bracketed(pose, traction, xtol)
        return pose, tau, self.moment(pose, tau, traction) - self.M_req

    def _bracketed(self, pose: Pose, traction=None, xtol: float = 1e-15, h0: float = 1e-9, newton: bool = False):
        a, b, open_ = _doubling_bracket(lambda t: self.moment(pose, t, traction) - self.M_req, pose.theta.size, h0,
                                        math.pi / self.g.z1)
        if np.any(open_):
            raise NoEquilibrium(pose.theta[open_])
        if not newton:
            return _bracket_root(lambda t: self.moment(pose, t, traction) - self.M_req, pose.theta, a, b, xtol)
        return self._solve(pose, traction, 0.5 * (a + b), xtol, bracket=(a, b))

    def _linearised_tau(self, n_scan: int, h0: float):
        r"""tau balancing the torque with the penetrations linearised about the nominal pose (no friction), or None
        where that balance has no root within +-pi/z1: a start for the first scan's Newton (:meth:`set_window`).

        With d delta/d tau = -(X x n) (:meth:`set_window`), the balance sum F(delta_0 - (X x n) tau) (X x n) = M_req
        needs only the contacts at tau = 0: bracketed by doubling from h0 and narrowed to 1e-6 of the bracket.
        Its error is that of the linearisation, |d^2 delta/d tau^2| tau^2/2 <= (R_p + e) tau^2/2, ~1e-3 of tau at
        deflection-sized rotations: Newton on the true balance then needs about three rounds.  On the ``n_scan``
        crank angles of :meth:`_nominal`."""
        n = n_scan
        _, d0, arm = self._nominal(n_scan)

        def G(t):
            return (self.law.force(d0 - arm * t) * arm).sum(axis=(0, 1)) - self.M_req

        a, b, open_ = _doubling_bracket(G, n, h0, math.pi / self.g.z1)
        if open_.any():
            return None
        return find_root(G, a, b, xtol=1e-3 * float(np.abs(np.concatenate((a, b))).max()), rtol=0.0).root

    def _solve(self, pose: Pose, traction=None, guess=None, xtol: float = 1e-15, maxiter: int = 40, bracket=None):
        """tau from G(tau) = 0 at every crank angle of ``pose``: safeguarded Newton from ``guess``.

        The analytic G_tau (:meth:`_balance`); a step that leaves the bracket of sign changes met so far
        is replaced by bisection; stops at |d tau| <= xtol (pins.md §5.5).  Angles without a guess, or
        where Newton cannot proceed (G_tau >= 0 with one side unbracketed, no convergence), are solved
        by the bracketed root finder (:meth:`solve`)."""
        n = pose.theta.size
        if guess is None:
            return self._bracketed(pose, traction, xtol)
        tau = np.array(guess, dtype=float)
        # the iterate t and the bracket [lb, hb] of the sign changes met so far, over the angles still iterating (idx):
        # only these are evaluated; an angle's tau and flags are written when it stops
        t = tau.copy()
        lb, hb = ((_filled(n, -np.inf), _filled(n, np.inf)) if bracket is None
                  else (bracket[0].copy(), bracket[1].copy()))
        done = np.zeros(n, dtype=bool)
        failed = np.zeros(n, dtype=bool)
        idx = np.arange(n)
        sub, tr = pose, traction
        with np.errstate(divide="ignore", invalid="ignore"):
            for _ in range(maxiter):
                G, G_tau = self._balance(sub, t, tr)[:2]
                lb = np.where(G > 0.0, np.maximum(lb, t), lb)
                hb = np.where(G < 0.0, np.minimum(hb, t), hb)
                step = -G / G_tau
                newton = t + step
                neg = G_tau < 0.0
                ok = np.isfinite(newton) & neg & (newton > lb) & (newton < hb)
                both = np.isfinite(lb) & np.isfinite(hb)
                # quadratic convergence: after a step |s| <= 1e-6 |tau| the error is ~C s^2 <= ~3e-12 |tau|;
                # a step below the spacing of floats (not inside the open bracket) leaves tau as it is
                at = np.abs(step)
                xt = np.maximum(4.0 * np.spacing(np.abs(t)), 1e-3 * xtol)
                stop = REFINE_NEWTON_STOP if self._refining else NEWTON_STOP
                conv = ((G == 0.0) | (neg & (at <= xt)) | (ok & (at <= stop * np.abs(t)))
                        | (both & (hb - lb <= xt)))
                fail = ~(ok | both | conv)
                act = ~fail & (G != 0.0)
                t = np.where(act & ok, newton, np.where(act & ~conv & both, 0.5 * (lb + hb), t))
                stop = conv | fail
                if stop.all():
                    tau[idx], failed[idx], done[idx] = t, fail, conv & ~fail
                    break
                if stop.any():         # go on with the angles not yet solved (a sub-pose keeps its foot points)
                    fin = idx[stop]
                    tau[fin], failed[fin], done[fin] = t[stop], fail[stop], conv[stop] & ~fail[stop]
                    keep = ~stop
                    sub = _sub_pose(sub, keep)
                    tr = None if tr is None else tr[..., keep]
                    idx, t, lb, hb = idx[keep], t[keep], lb[keep], hb[keep]
            else:
                tau[idx] = t               # the iterations ran out: not done, solved below
        failed |= ~done
        if failed.any() and bracket is not None:
            sub = _sub_pose(pose, failed)
            tr = None if traction is None else traction[..., failed]
            tau[failed] = _bracket_root(lambda t: self.moment(sub, t, tr) - self.M_req, sub.theta, bracket[0][failed],
                                        bracket[1][failed], xtol)
        elif failed.any():
            tau[failed] = self._bracketed(_sub_pose(pose, failed),
                                          None if traction is None else traction[..., failed], xtol)
        return tau

    def state(self, theta, ref=None, phases: bool = True, guess=None, scan=None, reuse=None) -> Solution:
        """The solved state at crank angles theta: tau, d tau/d theta, forces, tangential speeds.

        ``ref`` = (active, branch) (c, z2, n), optional: the active set and contact branches of the
        piece of the cycle each theta belongs to; the derivative d tau/d theta is then the one-sided
        limit from inside that piece (at a piece end, where a contact enters or changes branch, the
        derivative would straddle a jump of the contact stiffness).
        With ``friction``, the tangential forces take their directions from the previous solution and
        the equilibrium is re-solved until the directions no longer change (a fixed point, at most 8
        passes; pins.md §5.5); when no rotation balances the torque with them, :class:`Jam`.
        ``phases = False`` leaves phase and zeta None (the cycle adds them once, :meth:`phases`).
        ``guess`` (n,), optional: warm starts of tau (NaN: none), e.g. from the solved neighbours in the same piece
        (:func:`piece_guess`); the others from the solved angles around (:meth:`_guess`).
        ``scan`` = (pose, solution), optional, with friction: the frictionless equilibrium at theta on the candidate
        pins (:meth:`set_window`'s scan), from which the friction directions are iterated (instead of solving it).
        ``reuse`` (:class:`Pose`), optional: a pose of the same crank angles and candidate pins solved at another torque
        (:attr:`last_pose` of the pass before, :func:`relinearised_cycle`): taken instead of a new one, its foot points
        the warm start of this torque's (one Newton step instead of a fresh search from the nominal ones).
        """
        theta = np.atleast_1d(np.asarray(theta, dtype=float))
        idx, sides = self.candidates(theta), self.sides
        if scan is not None:
            pose = scan[0]
        elif reuse is not None and reuse.theta.shape == theta.shape and np.array_equal(reuse.theta, theta) \
                and np.array_equal(reuse.aux["idx"], self.pins if idx is None else idx):
            pose = reuse
        else:
            pose = self.pose(theta, idx, sides)
        self.last_pose = pose
        fixed = None if ref is None or len(ref) < 3 else ref[2]
        if ref is not None and idx is not None:
            # the sets are over the rows of this model's layout (a cycle's states): the candidates' rows there (and
            # the contacts the states evaluate, :attr:`sides`)
            at, cols = self.layout()[1][idx], np.arange(theta.size)[None, :]
            if (at < 0).any():
                raise ValueError("piece sets over the layout's rows hold no pins outside one period's window")
            cs = _contact_index(self.profile, sides)

            def cut(a):
                return None if a is None else a[cs, at[None], cols[None]]

            ref = (cut(ref[0]), cut(ref[1]))
            fixed = cut(fixed)
        elif ref is not None:
            ref = ref[:2]
        given = guess

        def start(key):
            memo = self._guess(theta, key)
            if given is None:
                return memo
            return given if memo is None else np.where(np.isfinite(given), given, memo)

        if self.friction is None:
            guess = start(0)
            sol = self._warm(pose, guess, None, ref) if ref is not None else None
            if sol is None:
                sol = self._kinematics(pose, self._solve(pose, None, guess), None, ref)
        elif fixed is not None:
            # the piece's own sliding directions (set at its midpoint, like its active set): the friction
            # forces jump only at the piece ends
            tau = start(1)
            sol = None
            if tau is None:
                tau = self._solve(pose, None, self._guess(theta, 0))
            else:
                sol = self._warm(pose, tau, fixed, ref)
            if sol is None:
                sol = self._friction_solve(pose, fixed, tau, ref)
        else:
            sol = self._friction_fixed_point(theta, pose, ref, None if scan is None else scan[1], given)
        self._remember(1 if self.friction is not None else 0, sol)
        sol = self._full(sol, idx, sides)
        if phases:
            sol.phase, sol.zeta = self.phases(theta, sol.rows)
        return sol

    def _warm(self, pose: Pose, guess, traction, ref, rounds: int = 2) -> "Solution | None":
        """The state from the warm start ``guess`` by Newton steps, each with one balance (:meth:`_kinematics` with
        ``step``: the last step, one :meth:`_solve` would stop after, moves the state without a new balance); an angle
        whose start is farther takes a full Newton step (G_tau < 0, |s| <= |tau|/2) and is evaluated again, at most
        ``rounds`` times; the others are solved by :meth:`_solve` from there.  None without a guess.  At the
        quadrature's nodes the cubic Hermite warm start between solved neighbours (:func:`piece_guess`) is usually
        that close: one balance per node instead of two or more (pins.md §5.5)."""
        if guess is None:
            return None
        with np.errstate(divide="ignore", invalid="ignore"):
            sol, need = self._kinematics(pose, guess, traction, ref, step=True)
        cols = np.arange(sol.theta.size)

        def sub(arr, c):
            return arr[..., c] if isinstance(arr, np.ndarray) else arr

        part, pose_c = sol, pose
        for r in range(rounds + 1):
            if not need.any():
                return sol
            keep = np.flatnonzero(need)
            cols = cols[keep]
            pose_c = _sub_pose(pose_c, keep)
            tr, ref_c = sub(traction, cols), None if ref is None else (sub(ref[0], cols), sub(ref[1], cols))
            tau, G, G_tau = part.tau[keep], part.residual[keep], part.g_tau[keep]
            with np.errstate(divide="ignore", invalid="ignore"):
                step = -G / G_tau
            if r == rounds or not ((G_tau < 0.0) & (np.abs(step) <= 0.5 * np.abs(tau))).all():
                break
            with np.errstate(divide="ignore", invalid="ignore"):
                part, need = self._kinematics(pose_c, tau + step, tr, ref_c, step=True)
            _put(sol, part, cols)
        try:
            tau = self._solve(pose_c, tr, tau)
        except NoEquilibrium as exc:
            if traction is None:
                raise
            raise Jam(exc.theta) from None
        _put(sol, self._kinematics(pose_c, tau, tr, ref_c), cols)
        return sol

    def _friction_solve(self, pose: Pose, traction, tau, ref) -> Solution:
        """The equilibrium with the friction forces ``traction`` from the start ``tau``; :class:`Jam` when
        no rotation balances the torque with them."""
        try:
            tau = self._solve(pose, traction, tau)
        except NoEquilibrium as exc:
            raise Jam(exc.theta) from None
        return self._kinematics(pose, tau, traction, ref)

    def _friction_fixed_point(self, theta, pose: Pose, ref, start: "Solution | None" = None,
                              guess=None) -> Solution:
        """The friction forces' directions iterated to a fixed point (at most 8 passes; pins.md §5.5).

        The first directions come from the kinematics at the warm start of an earlier friction solution,
        or, without one (or where that start leaves a contact set without stiffness), from the
        frictionless equilibrium (``start``: already solved on ``pose``).  ``guess`` = (tau, d tau/d theta) (n,) or
        tau, optional: the warm start instead of the memory's (NaN: the memory's).  The first directions are those of
        the sliding speeds at the warm start with its interpolated d tau/d theta (:meth:`_sliding_at`: no balance)."""
        sol = start
        if start is None:
            memo = self._guess(theta, 1, slope=True)
            if guess is not None and not isinstance(guess, tuple):
                guess = (np.asarray(guess, dtype=float), np.full(np.shape(guess), np.nan) if memo is None else memo[1])
            if guess is not None and memo is not None:
                guess = (np.where(np.isfinite(guess[0]), guess[0], memo[0]),
                         np.where(np.isfinite(guess[1]), guess[1], memo[1]))
            elif guess is None:
                guess = memo
            if guess is not None:
                with np.errstate(divide="ignore", invalid="ignore"):
                    sol = self._sliding_at(pose, *guess)
                if not np.isfinite(sol.v_t).all():
                    sol = None
        if sol is None:
            sol = self._kinematics(pose, self._solve(pose, None, self._guess(theta, 0)), None, ref)
            self._remember(0, sol)
        traction = None
        back = None                  # (traction, solution) of the pass before the last
        passes = 8
        for it in range(passes):
            new = self.traction(sol)
            if traction is not None and np.array_equal(new, traction):
                break
            if back is not None and np.array_equal(new, back[0]):
                # a cycle of two (the directions flip back and forth where no direction is consistent, at a
                # jump of the sliding speed): the remaining passes repeat the last two, so the directions of
                # the last pass's parity are those of the full count; one more solve from their solution
                trac, start = back if (passes - 1 - it) % 2 == 0 else (traction, sol)
                sol = self._friction_solve(pose, trac, start.tau, ref)
                break
            back = None if traction is None else (traction, sol)
            traction = new
            sol = self._friction_solve(pose, traction, sol.tau, ref)
        return sol

    def phases(self, theta, rows=None):
        """(phase, zeta) of the pins ``rows`` (None: all) at crank angles theta (R, n): the load-side phase of the
        mode and the time phase theta - phi_j wrapped to [-pi, pi) [rad]."""
        g = self.g
        th = np.atleast_1d(np.asarray(theta, dtype=float))[None, :]
        pins = self.pins if rows is None else rows[:, None]
        psi = pin_phase(pins, th, g.z2, REDUCER)
        zeta = -np.where(psi > math.pi, psi - 2.0 * math.pi, psi)
        return pin_phase(pins, th, g.z2, self.sigma), zeta

    def _remember(self, key, sol: Solution) -> None:
        old, old_g = self._memo[key], self._gtau[key]
        th, ta, dt, gt = sol.theta, sol.tau, sol.dtau, sol.g_tau
        if old is not None:
            # an angle solved again replaces its older state (one inherited from another torque, or from a solve
            # with other sets): a warm start between a new state and an old one at the next angle would carry the old
            # one's error (~1e-3 of tau after a torque pass of lambda_bar ~ 0.1)
            if th.size:
                # the old angles within 1e-12 T_p of a new one: the stretches [x - eps, x + eps] of the sorted memory
                eps = 1e-12 * self.g.period
                lo = old[0].searchsorted(th - eps, side="left")
                hi = old[0].searchsorted(th + eps, side="right")
                if (hi > lo).any():
                    cover = np.zeros(old[0].size + 1, dtype=np.int64)
                    np.add.at(cover, lo, 1)
                    np.add.at(cover, hi, -1)
                    keep = np.cumsum(cover[:-1]) == 0
                    old = tuple(o[keep] for o in old)
                    old_g = None if old_g is None else old_g[keep]
            th, ta, dt = (np.concatenate((o, v)) for o, v in zip(old, (th, ta, dt)))
            if gt is not None and old_g is None:
                old_g = _filled(old[0].shape, np.nan)    # unknown there (inherited, mirrored): no Newton warm start
            gt = None if old_g is None or gt is None else np.concatenate((old_g, gt))
        order = th.argsort(kind="stable")
        self._memo[key] = (th[order], ta[order], dt[order])
        self._gtau[key] = None if gt is None else gt[order]

    def _guess(self, theta, key, slope: bool = False):
        """tau at theta from the solved angles around it: the cubic Hermite interpolant of tau and
        d tau/d theta between the two neighbours (the tangent line of the nearer one where they coincide
        or lie on one side only), or None when nothing is solved yet.  ``slope``: (tau, d tau/d theta) of that
        interpolant."""
        memo = self._memo[key] if key == 0 or self.friction is not None else None
        if memo is None:
            return None
        th, ta, dt = memo
        if th.size == 1:
            line = ta[0] + dt[0] * (theta - th[0])
            return (line, dt[0] + 0.0 * line) if slope else line
        j = np.minimum(np.maximum(th.searchsorted(theta, side="right"), 1), th.size - 1)
        a, b = j - 1, j
        near = np.where(np.abs(theta - th[a]) <= np.abs(th[b] - theta), a, b)
        line = ta[near] + dt[near] * (theta - th[near])
        h = th[b] - th[a]
        inside = (h > 0.0) & (theta >= th[a]) & (theta <= th[b])
        with np.errstate(divide="ignore", invalid="ignore"):
            t = np.where(inside, (theta - th[a]) / h, 0.0)
            herm = _hermite(t, h, ta[a], dt[a], ta[b], dt[b])
            if slope:
                d_herm = _hermite_slope(t, h, ta[a], dt[a], ta[b], dt[b])
                return np.where(inside, herm, line), np.where(inside, d_herm, dt[near])
        return np.where(inside, herm, line)

    def _sliding_at(self, pose: Pose, tau, dtau):
        """The contacts' forces and sliding speeds v_t at the rotations ``tau`` with the turning rate d tau/d theta
        ``dtau`` given (a warm start's interpolant, :meth:`_guess`), without an equilibrium: the first friction
        directions of :meth:`_friction_fixed_point` (:meth:`traction` reads ``force`` and ``v_t``), as
        :meth:`_kinematics` gives them but for its own d tau/d theta (v_t = O1'.n + (d tau/d theta - k/z1)(C.n),
        pins.md §5.6).  Returns a :class:`Solution` holding tau, d tau/d theta, the forces and v_t."""
        g = self.g
        ct = self.contacts(pose, tau)
        ang = (g.z2 / g.z1) * pose.theta - tau
        v_t = self._tangential_speed(np.cos(ang), np.sin(ang), ct, dtau)
        return Solution(pose.theta, tau, dtau, None, ct.delta, self.law.force(ct.delta), v_t, None, None)

    def _tangential_speed(self, ca, sa, ct: Contacts, dtau):
        """The sliding speed v_t of every contact per unit crank speed [mm/rad] (pins.md §5.6): with omega_H = 1,
        v = z x O1' + w1 z x (C - O1) and v_t = v.(z x n) = O1'.n + w1 (C.n), O1' = e u(theta - phi), C = X + R_b n
        in the satellite axes and w1 = d tau/d theta - k/z1; ``ca``, ``sa``: cos and sin of z2 theta/z1 - tau."""
        g = self.g
        return g.e * (ca * ct.nx + sa * ct.ny) + (-(g.k / g.z1) + dtau) * (ct.xn + g.R_b)

    def _full(self, sol: Solution, idx, sides=None) -> Solution:
        """The solution over the rows of :meth:`layout`: the candidates' values scattered, the others untouched by
        contact (a state at crank angles outside [0, T_p] whose candidates the layout does not hold: over the union
        of both); solved on some contacts of each pin only (``sides``, :attr:`sides`): over all of them, the others
        out of reach like the pins out of the window (their normals and turning rates over the candidates 0: they
        carry no force)."""
        if idx is None:
            return sol
        rows, pos = self.layout()
        if rows is not None and (pos[idx] < 0).any():
            rows = np.union1d(rows, idx)
            pos = np.full(self.g.z2, -1)
            pos[rows] = np.arange(rows.size)
        n = sol.theta.size
        R = self.g.z2 if rows is None else rows.size
        at, cols = pos[idx], np.arange(n)[None, :]

        C, cs = self.profile.contacts_per_pin, _contact_index(self.profile, sides)

        # the places of the states' (c, m, n) entries in the rows' (C, R, n), flat: one index for every field
        flat = ((cs * R + at[None]) * n + cols[None]).ravel()

        def scatter(a, fill):
            if a is None:
                return None
            lead = a.shape[:-3]
            out = _filled(lead + (C * R * n,), fill, a.dtype)
            out[..., flat] = a.reshape(lead + (-1,))
            return out.reshape(lead + (C, R, n))

        def every(a):
            # the geometry over the candidates (c, m, n): the contacts left out get 0 (no force, no moment)
            if a is None or sides is None:
                return a
            out = np.zeros(a.shape[:-3] + (C,) + a.shape[-2:], dtype=a.dtype)
            out[..., sides, :, :] = a
            return out

        cand = np.zeros((R, n), dtype=bool)
        cand[at, cols] = True
        return Solution(sol.theta, sol.tau, sol.dtau, sol.residual, scatter(sol.delta, -np.inf),
                        scatter(sol.force, 0.0), scatter(sol.v_t, 0.0), None, None,
                        scatter(sol.switch, np.nan), scatter(sol.branch, -1), cand, scatter(sol.ddelta, 0.0),
                        sol.noise, sol.g_tau, every(sol.nx), every(sol.ny), every(sol.wx), every(sol.wy), sol.pins,
                        rows, scatter(sol.traction, 0.0))

    def reference(self, theta):
        """(active, branch, traction) of the solved state at theta: the fixed sets of the pieces with these
        midpoints (traction: the friction forces' directions with friction in the balance, else None)."""
        sol = self.state(theta, phases=False)
        return sol.force > 0.0, sol.branch, None if self.friction is None else self.traction(sol)

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

    def _kinematics(self, pose: Pose, tau, traction, ref=None, step: bool = False):
        r"""Forces, d tau/d theta and the contact speeds at the solved tau (pins.md §5.6).

        d tau/d theta = -G_theta/G_tau, both analytic (on the piece's active set and branches ``ref``);
        at fixed tau, dX/dtheta = -Rot(-phi) O1' + (k/z1)(-y, x), so with V = dX/dtheta

        .. math::

            G_\theta = \sum F'(\delta)(n\cdot V) A + F\left[V\times n + (w\cdot V)(X\cdot n)
                       + q\,(n\cdot V - (w\cdot V)(X\times n))\right]

        ``step``: ``tau`` is a warm start; where its Newton step s = -G/G_tau is one that :meth:`_solve` would take
        and stop after (G_tau < 0, |s| <= 1e-8 |tau|) and the arms' turn moves the moment by |G_geo s| <= 1e-11
        |M_req| at most, the state is moved by it: tau + s, delta - (X x n) s (exact to O((R_p + e) s^2) ~ 1e-22 mm,
        d delta/d tau = -(X x n)), the forces and slopes anew from those deflections, the residual with the arms'
        turn G_geo s added; the geometry (normals, arms, positions) stays at ``tau`` (its change, (R_p + e) s ~ 1e-10
        mm, is far below the deflections' resolution).  Returns (Solution, need): ``need`` marks the angles whose
        warm start was farther (they need :meth:`_solve`).
        """
        g = self.g
        th = pose.theta
        G, G_tau, ct, F, Fp, A, q, x, y, G_geo = self._balance(pose, tau, traction)
        need = None
        if step:
            with np.errstate(divide="ignore", invalid="ignore"):
                s = -G / G_tau
                small = REFINE_NEWTON_SMALL if self._refining else NEWTON_SMALL
                take = ((G_tau < 0.0) & np.isfinite(s) & (np.abs(s) <= small * np.abs(tau))
                        & (np.abs(G_geo * s) <= 1e-3 * small * abs(self.M_req)))
            need = ~take
            if take.any():
                s = np.where(take, s, 0.0)
                tau = tau + s
                ct.delta = ct.delta - ct.arm * s
                F, Fp = self.law.force_stiffness(ct.delta)
                G, G_tau, _ = self._moment_slope(ct, F, Fp, A, q, x, y)
                G = G + G_geo * s       # the moment at tau + s to first order in s: the arms' turn added
        G_tau0 = G_tau
        cr, F_r, Fp_r, A_r = ct, F, Fp, A
        if ref is not None:
            # the piece's sets differ from the solution's own only at some angles (a piece end, a contact at
            # delta = 0): the one-sided derivatives are evaluated there alone, the others are the same
            other = (ref[0] != (F > 0.0)).any(axis=(0, 1))
            if ref[1] is not None:
                other |= (ref[1] != ct.branch).any(axis=(0, 1))
            if other.any():
                cols = np.flatnonzero(other)
                sub_ref = (ref[0][..., cols], None if ref[1] is None else ref[1][..., cols])
                sub_q = traction[..., cols] if isinstance(traction, np.ndarray) else traction
                _, gt, cs, fs, fps, As, _, _, _, _ = self._balance(_sub_pose(pose, cols), tau[cols], sub_q, sub_ref)
                G_tau = G_tau.copy()
                G_tau[cols] = gt
                cr = Contacts(*(_with_cols(getattr(ct, k), getattr(cs, k), cols) for k in _CONTACT_FIELDS))
                F_r, Fp_r, A_r = (_with_cols(a, b, cols) for a, b in ((F, fs), (Fp, fps), (A, As)))
        kz = g.k / g.z1
        ang = (g.z2 / g.z1) * th - tau
        ca, sa = np.cos(ang), np.sin(ang)
        vx = g.e * sa - kz * y
        vy = -g.e * ca + kz * x
        dd = cr.nx * vx + cr.ny * vy
        om = cr.wx * vx + cr.wy * vy
        d_arm = vx * cr.ny - vy * cr.nx + om * cr.xn
        d_xn = dd - om * cr.arm
        G_th = (Fp_r * dd * A_r + F_r * (d_arm + q * d_xn)).sum(axis=(0, 1))
        dtau = -G_th / G_tau
        v_t = self._tangential_speed(ca, sa, ct, dtau)
        ddelta = (dd if cr is ct else ct.nx * vx + ct.ny * vy) - ct.arm * dtau
        noise = EPS * (g.R_p + g.e) * np.abs(Fp * ct.arm).sum(axis=(0, 1))
        switch = ct.switch if ct.psi_f is None else self.profile.switch(ct.psi_f)
        # the friction forces solved with, per contact (a copy: the caller's array stays its own)
        solved_q = None if traction is None else np.array(np.broadcast_to(traction, F.shape), dtype=float)
        sol = Solution(th, tau, dtau, G, ct.delta, F, v_t, None, None, switch, ct.branch, None, ddelta, noise,
                       G_tau0, ct.nx, ct.ny, ct.wx, ct.wy, pose.aux["idx"], traction=solved_q)
        return (sol, need) if step else sol

    def _picker(self, theta, rows=None):
        """(idx, pick): the candidate pins (m, n) at crank angles theta (all pins when there is no window) and the
        candidates' columns of an array over the pins ``rows`` (a state's :attr:`Solution.rows`; None: all z2),
        (c, R, n) -> (c, m, n) (scalars and None unchanged)."""
        idx = self.candidates(theta)
        if idx is None:
            idx = np.broadcast_to(self.pins, (self.g.z2, np.size(theta)))
        cols = np.arange(np.size(theta))[None, :]
        at = idx
        if rows is not None:
            at = np.minimum(np.maximum(rows.searchsorted(idx), 0), rows.size - 1)
            if not np.array_equal(rows[at], idx):
                raise ValueError("the state's rows do not hold every candidate pin")

        def pick(a):
            return a if a is None or np.ndim(a) == 0 else a[:, at, cols]

        return idx, pick

    def solved_contacts(self, sol: Solution):
        """The contacts of a solved state (theta, tau, branches) over the candidate pins, and ``pick``: the
        candidates' columns of an array over its rows (c, R, n) -> (c, m, n) (scalars and None unchanged)."""
        idx, pick = self._picker(sol.theta, sol.rows)
        return self.contacts(self.pose(sol.theta, idx), sol.tau, pick(sol.branch)), pick

    def kept_contacts(self, sol: Solution):
        """:meth:`solved_contacts` from the normals the solution kept (:class:`Solution`: nx, ny, wx, wy over its
        ``pins``) when they are over this model's candidate pins at every angle; else evaluated anew.

        At a piece end (a crank angle held twice, one-sided) they are evaluated anew all the same: where a
        cycloidal pin passes to a crest corner its foot point on the design curve jumps there, and the kept one
        may be the other side's (the profile's corner, whose curvature radius is 0); anew, from the nominal foot
        point, with the state's branch."""
        if sol.pins is None or sol.nx is None:
            return self.solved_contacts(sol)
        theta = sol.theta
        idx, pick = self._picker(theta, sol.rows)
        if sol.pins.shape != idx.shape or not np.array_equal(sol.pins, idx):
            return self.solved_contacts(sol)
        nx, ny, wx, wy = sol.nx, sol.ny, sol.wx, sol.wy
        twice = np.concatenate(([False], theta[1:] == theta[:-1]))
        ends = np.flatnonzero(twice | np.concatenate((twice[1:], [False])))
        if ends.size:
            anew = self.solved_contacts(_take(sol, ends))[0]
            nx, ny, wx, wy = (_with_cols(a, getattr(anew, k), ends) for a, k in ((nx, "nx"), (ny, "ny"),
                                                                                   (wx, "wx"), (wy, "wy")))
        ct = Contacts(pick(sol.delta), nx, ny, None, None, wx=wx, wy=wy)
        ct.branch = pick(sol.branch)
        return ct, pick

    def bearing_force(self, sol: Solution, traction=None, ct=None, pick=None):
        """Force B of the crank bearing on the satellite (crank-frame axes turned by phi) [N], (2, n).

        Satellite equilibrium: B = -sum (F n + q F (z x n)) (the coupling gives a pure torque); ``ct``, ``pick``: the
        state's :meth:`solved_contacts`, when known."""
        if ct is None:
            ct, pick = self.solved_contacts(sol)
        F, q = pick(sol.force), 0.0 if traction is None else pick(traction)
        return -(F * (ct.nx - q * ct.ny)).sum(axis=(0, 1)), -(F * (ct.ny + q * ct.nx)).sum(axis=(0, 1))


# ============================================================ losses (pins.md §5.6)

def contact_losses(sol: Solution, R_b: float, mu_eff: float, sliding_friction: float, rolls: bool):
    """Per-contact loss per unit crank speed and the pin spin (pins.md §5.6, §4.6).

    Fixed pins: every loaded contact slides at |v_t| with mu_eff = f.  Rolling pins: the contact with
    the larger force sets the spin omega_pin = v_t/R_b and loses mu_rot F |v_t|; another loaded
    contact on the same pin slides at |v_t - omega_pin R_b| with f.

    Returns
    -------
    loss : mu F |v| per contact [N·mm/s per rad/s] (c, R, n) (times 1e-3 omega_H gives W);
    spin : omega_pin per unit crank speed [-] (R, n) (0 for fixed pins and unloaded pins);
    slide : sliding speed per contact [mm/s per rad/s] (c, R, n);
    over the state's rows (:attr:`Solution.rows`: R pins; every other pin carries no force).
    """
    F, v = sol.force, sol.v_t
    if not rolls:
        slide = np.abs(v)
        return contact_loss_power(F, slide, mu_eff) * 1e3, np.zeros(F.shape[1:]), slide
    lead = np.argmax(F, axis=0)
    v_lead = np.take_along_axis(v, lead[None], axis=0)[0]
    loaded = (F > 0.0).any(axis=0)
    spin = np.where(loaded, v_lead / R_b, 0.0)
    is_lead = np.arange(F.shape[0])[:, None, None] == lead[None]
    slide = np.where(is_lead, 0.0, np.abs(v - v_lead[None]))
    loss = np.where(is_lead, mu_eff * F * np.abs(v), sliding_friction * F * slide)
    return loss, spin, slide


# ============================================================ the cycle (pins.md §5.6, §6)

@dataclass
class ContactCycle:
    """The contact level's cycle solution of one design at one torque.

    loss_ratio, loss_ratio_err : the cycle mean of lambda and its error (trapezoid: Richardson value and
    |Q_2N - Q_N|; Gauss-Kronrod: K and |K - G|); converged : the quadrature's; n_crank : the solved crank angles;
    quad : the QuadResult;
    sol : the states on the final grid, sorted by theta (piece ends twice, one-sided; a Gauss-Kronrod rule: every
    evaluated node, the bisected pieces' own included, both ends of every piece of the breakpoints, and the
    interpolated states of :func:`gk_interpolated`);
    breakpoints : the located breakpoints in theta [rad]; roots : the located sign changes
    (:class:`BreakpointRoots`), which a later pass of the same design starts from;
    friction : (R_b, mu_eff, f, rolls, scale) of :func:`contact_losses` and the loss ratio's scale;
    held : every node lies on its piece's side of every sign change (:func:`_pieces_hold`); False: not even on the
    densest scan (``SCAN_MAX`` intervals; not scanned denser where the satellite turns beyond a deflection,
    :func:`deflection_sized`), and the loss ratio is not known to its error (pins.md §6);
    nodes : (sets, mids, ref_sols, rows) of the trapezoid's final grid, for the next torque pass from the same nodes
    (:func:`relinearised_cycle`): each node's piece sets (active, branch, traction), its piece's midpoint, the states
    that fixed the pieces' sets and the pins the sets are over (:attr:`Solution.rows`; None: a Gauss-Kronrod rule).
    loss, spin, slide : per node (:func:`contact_losses`); lam : lambda per node: computed on first use (only the
    cycle the outputs come from needs them).
    """

    loss_ratio: float
    loss_ratio_err: float
    converged: bool
    n_crank: int
    quad: QuadResult
    sol: Solution
    breakpoints: np.ndarray
    roots: "BreakpointRoots | None" = None
    friction: tuple = ()
    nodes: "tuple | None" = field(default=None, repr=False, compare=False)
    held: bool = True

    @functools.cached_property
    def _losses(self):
        R_b, mu_eff, f, rolls, scale = self.friction
        loss, spin, slide = contact_losses(self.sol, R_b, mu_eff, f, rolls)
        return loss, spin, slide, loss.sum(axis=(0, 1)) / scale

    loss = property(lambda self: self._losses[0])
    spin = property(lambda self: self._losses[1])
    slide = property(lambda self: self._losses[2])
    lam = property(lambda self: self._losses[3])


def _take(sol: Solution, sel) -> Solution:
    """The states of ``sol`` at the crank angles ``sel`` (an index or slice over the last axis)."""
    n = sol.theta.size
    return Solution(**{f.name: (v[..., sel] if isinstance(v, np.ndarray) and v.shape[-1:] == (n,) and f.name != "rows"
                                else v)
                       for f in dataclasses.fields(sol) for v in (getattr(sol, f.name),)})


def _put(sol: Solution, part: Solution, sel) -> None:
    """The states of ``part`` written into ``sol`` at the crank angles ``sel`` (in place; theta is not written)."""
    n = sol.theta.size
    for f in dataclasses.fields(sol):
        a = getattr(sol, f.name)
        if isinstance(a, np.ndarray) and a.shape[-1:] == (n,) and f.name not in ("theta", "pins", "rows"):
            a[..., sel] = getattr(part, f.name)


def _sorted_places(thetas: list) -> list:
    """Where the crank angles of each part land when all are sorted together (stable: ties keep the parts' order); one
    part already sorted (the quadrature's nodes solved in one call): all of it in place (a slice)."""
    if len(thetas) == 1 and not (thetas[0][1:] < thetas[0][:-1]).any():
        return [slice(None)]
    theta = np.concatenate(thetas)
    place = np.empty(theta.size, dtype=np.int64)
    place[theta.argsort(kind="stable")] = np.arange(theta.size)
    bounds = np.cumsum([0] + [t.size for t in thetas])
    return [place[a:b] for a, b in zip(bounds[:-1], bounds[1:])]


def _merged(arrays: list, places: list, axis: int):
    """The arrays written at their ``places`` (:func:`_sorted_places`) along ``axis``, the last one: the sorted
    concatenation in one pass."""
    a0 = arrays[0]
    shape = list(a0.shape)
    shape[axis] = sum(a.shape[axis] for a in arrays)
    out = np.empty(shape, dtype=np.result_type(*arrays))
    lead = (slice(None),) * axis
    for a, p in zip(arrays, places):
        out[lead + (p,)] = a
    return out


def _concat(parts: list[Solution]) -> Solution:
    """The states of ``parts`` together, sorted by theta (stable), over their rows (over the union of them where the
    parts' rows differ, :func:`_relayout`)."""
    rows = parts[0].rows
    if not all(_same_rows(p.rows, rows) for p in parts):
        full = [p for p in parts if p.rows is None]
        rows = None if full else functools.reduce(np.union1d, [p.rows for p in parts])
        z2 = full[0].force.shape[-2] if full else None
        parts = [_relayout(p, rows, z2) for p in parts]
    places = _sorted_places([p.theta for p in parts])
    theta = _merged([p.theta for p in parts], places, 0)

    def cat(name, axis):
        if any(getattr(p, name) is None for p in parts):
            return None
        return _merged([getattr(p, name) for p in parts], places, axis)

    geometry = [None] * len(_GEOMETRY_FIELDS)
    if all(p.pins is not None for p in parts) and len({p.pins.shape[0] for p in parts}) == 1:
        geometry = [cat(name, getattr(parts[0], name).ndim - 1) for name in _GEOMETRY_FIELDS]

    return Solution(theta, cat("tau", 0), cat("dtau", 0), cat("residual", 0), cat("delta", 2),
                    cat("force", 2), cat("v_t", 2), cat("phase", 1), cat("zeta", 1),
                    None if parts[0].switch is None else cat("switch", 3),
                    None if parts[0].branch is None else cat("branch", 2),
                    None if any(p.cand is None for p in parts) else cat("cand", 1), cat("ddelta", 2),
                    cat("noise", 0), cat("g_tau", 0), *geometry, rows,
                    None if parts[0].traction is None else cat("traction", 2))


def _same_rows(a, b) -> bool:
    """Whether two :attr:`Solution.rows` are the same pins."""
    return (a is None and b is None) or (a is not None and b is not None and np.array_equal(a, b))


def _relayout(sol: Solution, rows, z2: int | None = None) -> Solution:
    """``sol`` over the pins ``rows`` (sorted; None: all ``z2``): each per-pin array's rows of these pins, a pin that
    ``sol`` does not hold with the values of a pin out of reach (no contact; :data:`_PIN_FILL`; phases then None, to
    be computed, :meth:`ContactModel.phases`)."""
    if _same_rows(sol.rows, rows):
        return sol
    n_src = sol.force.shape[-2]
    src = np.arange(n_src) if sol.rows is None else sol.rows
    dst = np.arange(z2) if rows is None else rows
    held = np.isin(dst, src).all()
    out = {}
    for name in _PIN_FIELDS:
        a = getattr(sol, name)
        if name == "cand" and a is None and not held:
            a = np.ones((n_src, sol.theta.size), dtype=bool)
        if a is None or (name in ("phase", "zeta") and not held):
            out[name] = None
        else:
            out[name] = _over_rows(a, src, dst, _PIN_FILL.get(name))
    return dataclasses.replace(sol, rows=rows, **out)


def _over_rows(a, src, dst, fill):
    """``a`` (..., len(src), n) over the pins ``src`` (sorted) as (..., len(dst), n) over the pins ``dst`` (sorted): a
    pin that ``a`` does not hold gets ``fill``."""
    at = np.minimum(np.maximum(src.searchsorted(dst), 0), src.size - 1)
    have = src[at] == dst
    if have.all():
        return a[..., at, :]
    b = _filled(a.shape[:-2] + (dst.size, a.shape[-1]), fill, a.dtype)
    b[..., have, :] = a[..., at[have], :]
    return b


def _components(s: Solution, rolls: bool):
    """The sign-change components of the cycle at the solved states ``s`` (pins.md §6): (values, slopes, n_delta),
    values and slopes (c, n) over the crank angles of ``s``; the slope is known for the penetrations only (NaN
    else), which come first (n_delta rows).  A component that is NaN at a crank angle has no sign there.  Over the
    state's rows (:attr:`Solution.rows`; the other pins are never candidates over the period: no contact, no sign):
    the states of one cycle share them."""
    n = s.theta.size
    force, v_t, cand = s.force, s.v_t, s.cand
    delta = s.delta
    delta = delta if cand is None else np.where(cand, delta, np.nan)   # NaN: no sign change
    loaded = force > 0.0
    parts = [delta.reshape(-1, n), np.where(loaded, v_t, 0.0).reshape(-1, n)]
    slopes = [s.ddelta.reshape(-1, n)]
    if s.switch is not None:      # not masked: a pin can reach the crest and leave it in one scan step
        parts.append(s.switch.reshape(-1, n))
    if rolls and force.shape[0] == 2:
        lead = (force[1] > force[0]).astype(np.intp)          # np.argmax over the two contacts (ties: the first)
        v_lead = np.where(lead == 1, v_t[1], v_t[0])[None]
        other = loaded & (np.arange(2)[:, None, None] != lead[None])
        parts.append(np.where(loaded.all(axis=0), force[0] - force[1], np.nan).reshape(-1, n))
        parts.append(np.where(other, v_t - v_lead, np.nan).reshape(-1, n))
    values = np.concatenate(parts)
    slopes.append(_filled((values.shape[0] - slopes[0].shape[0], n), np.nan))
    return values, np.concatenate(slopes), slopes[0].shape[0]


@dataclass
class BreakpointRoots:
    """The located sign changes of one cycle (:func:`cycle_breakpoints`): roots [rad] and whether each is a contact
    entry or exit (a penetration's), sorted by root; ``scanned``: located by the full scan and taken as it is (False:
    a coarse scan or moved roots, which the quadrature's nodes must confirm, :func:`mean_loss_ratio`)."""

    roots: np.ndarray
    contact: np.ndarray
    scanned: bool = True
    seen: list = field(default_factory=list, repr=False, compare=False)   # the states solved to find them


def _breakpoint_state(model: ContactModel):
    """A one-entry cache of the solved states of the last crank angles (the refinement evaluates the same ones
    for the values and the slopes)."""
    memo: dict = {}

    def state(x):
        key = (x.size, x.tobytes())
        if key not in memo:
            memo.clear()
            memo[key] = model.state(x, phases=False)
            state.seen.append(memo[key])
        return memo[key]

    state.seen = []          # every state solved, for the pieces' sets (:func:`_interior_states`)
    return state


def _scan_roots(model: ContactModel, n_scan: int, tol: float, rolls: bool, checked: bool = False) -> BreakpointRoots:
    """Every sign change of the components on an ``n_scan`` grid of one period, refined (:func:`cycle_breakpoints`);
    ``checked``: a coarse scan whose result the quadrature's nodes must confirm (:func:`mean_loss_ratio`)."""
    Tp = model.g.period
    state = _breakpoint_state(model)
    xtol = 1e-12 * Tp
    x = np.linspace(0.0, Tp, n_scan + 1)
    v, dv, n_delta = _components(state(x), rolls)
    sgn = np.sign(v)
    comp, idx = np.nonzero(sgn[:, :-1] * sgn[:, 1:] < 0)
    if comp.size:
        x0, steps = _smooth_side_start(x, v, dv, comp, idx, xtol, Tp)

        first = [True]

        def h(t, k):
            # the first call's solves tight (its points from the smooth side are taken as they are, below); later
            # ones are the product's
            model._refining, first[0] = first[0] and np.isfinite(x0).any(), False
            try:
                val, slope, _ = _components(state(t), rolls)
            finally:
                model._refining = False
            i = np.arange(k.size)
            return val[comp[k], i], slope[comp[k], i]

        # a jump (not a root) needs its place only to 1e-3 tol T_p: the integrand's error from it is below
        # 1e-3 tol times the jump of lambda over lambda_bar
        roots = _refine_sign_changes(h, x[idx], x[idx + 1], v[comp, idx], v[comp, idx + 1], xtol,
                                     jump_xtol=1e-3 * tol * Tp, step_tol=ROOT_STEP * Tp, x0=x0, bent_above=True,
                                     step_tols=steps)
    else:
        roots = np.empty(0)
    order = roots.argsort(kind="stable")
    return BreakpointRoots(roots[order], (comp < n_delta)[order], not checked, state.seen)


SMOOTH_START_CURVATURE_MARGIN = 1e-2
"""A refinement step from the smooth side of a scanned penetration's sign change (:func:`_smooth_side_start`) stops its
bracket when Newton's error after it, C s^2 (C = |f''/2f'|, the larger of the scan cubic's at its root and 1/T_p), is
below this fraction of the breakpoints' tolerance (1e-12 T_p): the curvature may be 100x the estimate."""


def _smooth_side_start(x, v, dv, comp, idx, xtol: float, Tp: float):
    """First points and step tolerances of the refinement of the scan's sign changes (:func:`_refine_sign_changes`):
    for a penetration (its slope known), the root of the cubic Hermite interpolant of the two scan points below zero
    next to the sign change (value and slope each), extrapolated over the bracket, and backed off into the side below
    zero by half the step tolerance; NaN (the scan's linear interpolation, the global step tolerance) where the slope
    is unknown, the next point out is not below zero too, another component changes sign on the way or in the
    bracket, or the far end lies above the cubic (below).

    Below zero the pin is clear of its tooth and the state is smooth in theta; above, the contact's force bends the
    penetration ((theta - theta0)^(10/9) under the Hertz law), so the linear interpolation across the root and Newton
    from the point above zero land 1e-5-1e-4 T_p off, and the refinement took three calls.  The cubic's root is
    O(h^4) off (1e-10-1e-9 T_p on the paper designs); a Newton step of s from a point below zero leaves C s^2, C =
    |f''/2f'| (from the cubic at its root, at least 1/T_p), so the bracket's step tolerance is the s with
    C s^2 = :data:`SMOOTH_START_CURVATURE_MARGIN` ``xtol`` (~1e-7 T_p, against :data:`ROOT_STEP` = 1e-9 T_p), and
    the first point, half of it short of the cubic's root, is one step from the root: one call (pins.md §6).

    ``x`` (m + 1,): the scan's crank angles; ``v``, ``dv`` (c, m + 1): the components and their slopes there (NaN:
    unknown); ``comp``, ``idx``: the sign changes, between x[idx] and x[idx + 1] of component comp; ``xtol``: the
    breakpoints' tolerance; ``Tp``: the period.  Returns (first points, step tolerances), NaN where not taken.

    Examples
    --------
    >>> x = np.linspace(0.0, 1.0, 5)
    >>> f = lambda t: np.sin(3.0 * t) - 0.8                # one root at arcsin(0.8)/3 = 0.30910
    >>> v, dv = f(x)[None], (3.0 * np.cos(3.0 * x))[None]
    >>> start, step = _smooth_side_start(x, v, dv, np.array([0]), np.array([1]), 1e-12, 1.0)
    >>> bool(abs(start[0] - np.arcsin(0.8) / 3.0) < 2e-3 < abs(x[1] - v[0, 1] * 0.25 / (v[0, 2] - v[0, 1]) - 0.30910))
    True
    """
    m = x.size - 1
    lower = v[comp, idx] < 0.0                      # the side below zero: idx (else idx + 1)
    n = np.where(lower, idx, idx + 1)               # its scan point next to the root
    o = np.where(lower, idx - 1, idx + 2)           # and the next one out
    ok = (o >= 0) & (o <= m)
    o = np.clip(o, 0, m)
    fn, sn, fo, so = v[comp, n], dv[comp, n], v[comp, o], dv[comp, o]
    # no sign change of any component between o and n (a kink of the state there), nor of another one in the bracket
    a, b = np.minimum(n, o), np.maximum(n, o)
    sg = np.sign(v)
    clean = ~np.any(sg[:, a] * sg[:, b] < 0.0, axis=0) & (np.sum(sg[:, idx] * sg[:, idx + 1] < 0.0, axis=0) == 1)
    ok &= clean & (fo < 0.0) & np.isfinite(sn) & np.isfinite(so) & np.isfinite(fo)
    xn, xo = x[n], x[o]
    H = xn - xo                                    # signed: toward the root
    with np.errstate(divide="ignore", invalid="ignore"):
        r = xn - fn / sn                             # Newton from the nearer point, then Newton on the cubic
        for _ in range(3):
            t = (r - xo) / H
            r = r - _hermite(t, H, fo, so, fn, sn) / _hermite_slope(t, H, fo, so, fn, sn)
        # the cubic's curvature at its root, |p''/2p'|, at least 1/T_p
        t = (r - xo) / H
        dp = _hermite_slope(t, H, fo, so, fn, sn)
        d2p = ((12.0 * t - 6.0) * (fo - fn) / H + (6.0 * t - 4.0) * so + (6.0 * t - 2.0) * sn) / H
        C = np.maximum(np.abs(d2p / (2.0 * dp)), 1.0 / Tp)
        step = np.sqrt(SMOOTH_START_CURVATURE_MARGIN * xtol / C)
        # the far end's penetration, bent by the contact's own force, lies below the cubic's (the smooth extension:
        # the state without that force, which turns the satellite farther): else the bracket holds other sign changes
        # (a crest corner, another root) and the scan's linear start is kept
        f_far = v[comp, np.where(lower, idx + 1, idx)]
        t = (x[np.where(lower, idx + 1, idx)] - xo) / H
        p_far = _hermite(t, H, fo, so, fn, sn)
        ok &= (f_far > 0.0) & (f_far <= 1.25 * p_far) & np.isfinite(step) & np.isfinite(r)
    return np.where(ok, r - 0.5 * step * np.sign(H), np.nan), np.where(ok, step, np.nan)


def _incremental_roots(model: ContactModel, prior: BreakpointRoots, width: float, tol: float,
                       rolls: bool, max_width: float | None = None) -> BreakpointRoots | None:
    """The roots of ``prior`` (the same design's cycle at a nearby torque) moved to this
    model: each is bracketed by +-``width`` (widened 4x, up to ``max_width``, where its bracket holds no sign change),
    and the components' sign changes between the bracket ends refined as in :func:`_scan_roots` (one root found in
    two overlapping brackets counted once).  None (the full scan is needed) unless every bracket holds a sign change
    and their number is the prior's: a root that left its widest bracket, or a pair that appeared or vanished in
    it.  Changes elsewhere are caught on the quadrature's nodes (:func:`mean_loss_ratio`)."""
    Tp = model.g.period
    if prior.roots.size == 0:
        return BreakpointRoots(np.empty(0), np.zeros(0, dtype=bool), False)
    max_width = width if max_width is None else max(max_width, width)
    state = _breakpoint_state(model)
    r0 = prior.roots
    w = np.full(r0.size, float(width))
    todo = np.arange(r0.size)
    comps, lo, hi, flo, fhi = [], [], [], [], []
    n_delta = 0
    while todo.size:
        a = np.maximum(r0[todo] - w[todo], 0.0)
        b = np.minimum(r0[todo] + w[todo], Tp)
        v, _, n_delta = _components(state(np.concatenate((a, b))), rolls)
        va, vb = v[:, :todo.size], v[:, todo.size:]
        comp, idx = np.nonzero(np.sign(va) * np.sign(vb) < 0)
        comps.append(comp)
        lo.append(a[idx]), hi.append(b[idx]), flo.append(va[comp, idx]), fhi.append(vb[comp, idx])
        missing = np.setdiff1d(np.arange(todo.size), idx)
        todo = todo[missing]
        if todo.size and (w[todo] >= max_width).any():
            return None
        w[todo] = np.minimum(4.0 * w[todo], max_width)
    comp = np.concatenate(comps)
    if comp.size < r0.size:
        return None
    xtol = 1e-12 * Tp
    jtol = 1e-3 * tol * Tp

    def h(t, k):
        val, slope, _ = _components(state(t), rolls)
        i = np.arange(k.size)
        return val[comp[k], i], slope[comp[k], i]

    roots = _refine_sign_changes(h, np.concatenate(lo), np.concatenate(hi), np.concatenate(flo), np.concatenate(fhi),
                                 xtol, jump_xtol=jtol, step_tol=ROOT_STEP * Tp, bent_above=True)
    # one root found from two overlapping brackets: the same component within the refinement's tolerance
    order = np.lexsort((roots, comp))
    comp, roots = comp[order], roots[order]
    dup = np.concatenate(([False], (comp[1:] == comp[:-1]) & (np.diff(roots) <= 2.0 * jtol + 4.0 * xtol)))
    comp, roots = comp[~dup], roots[~dup]
    if roots.size != r0.size:
        return None
    order = roots.argsort(kind="stable")
    return BreakpointRoots(roots[order], (comp < n_delta)[order], False, state.seen)


HERTZ_GRADING_RATIO = 0.25
"""The geometric ratio of the grading toward both sides of a contact entry or exit under the Hertz law (:func:`_edges`,
:func:`cycle_breakpoints`): each graded piece is 1/ratio times longer than the next one nearer the entry."""


def _edges(model: ContactModel, found: BreakpointRoots, tol: float) -> np.ndarray:
    """The piece ends from the located roots: the period's ends, the roots, and the geometric gradings
    (:func:`cycle_breakpoints`)."""
    Tp = model.g.period
    xtol = 1e-12 * Tp
    contact_bp = found.roots[found.contact]      # the contact entries and exits (a penetration changes sign)
    edges = _merge(np.concatenate(([0.0, Tp], found.roots)), 4.0 * xtol)
    extra = []
    if model.law.exponent != 1.0 and contact_bp.size:
        width = 4.0 * Tp * (0.01 * tol) ** 0.9
        for x0 in _merge(contact_bp, 4.0 * xtol):
            i = int(np.argmin(np.abs(edges - x0)))
            if i > 0:
                extra.append(geometric_breakpoints(edges[i], edges[i - 1], width, ratio=HERTZ_GRADING_RATIO))
            if i + 1 < edges.size:
                extra.append(geometric_breakpoints(edges[i], edges[i + 1], width, ratio=HERTZ_GRADING_RATIO))
    if model.g.one_minus_K1 < 0.01:
        extra.append(geometric_breakpoints(0.0, Tp, model.g.one_minus_K1 * Tp * model.g.z2 / (2.0 * math.pi)))
    return _merge(np.concatenate([edges, *extra]), 4.0 * xtol)


def cycle_breakpoints(model: ContactModel, n_scan: int = 256, tol: float = 1e-6, rolls: bool = False,
                      roots: bool = False):
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
    * K1 > 0.99: the geometric grading toward entry of the ideal level;
    * rolling pins (``rolls``) with two loaded contacts on one pin: where the two forces are equal (the
      contact that sets the spin changes) and where the other contact's sliding speed v_t - omega_pin R_b
      changes sign (its friction force flips): the loss, and with friction in the balance the forces, jump
      or kink there (pins.md §5.6).

    The scan's sign changes are refined by safeguarded Newton (the penetrations, with the slope
    d delta/d theta of the solution) or secant steps (the others) to 1e-12 T_p.  ``roots``: also return the
    located sign changes (:class:`BreakpointRoots`, for the incremental location of a later pass).
    """
    found = _scan_roots(model, n_scan, tol, rolls)
    edges = _edges(model, found, tol)
    return (edges, found) if roots else edges


SECTIONS = 8
"""A bracket that Newton or the secant cannot narrow (a step outside it: a jump, or a root far from linear) is cut into
SECTIONS equal parts at once (SECTIONS - 1 points in one call): 8x narrower per call instead of bisection's 2x, at
about the cost of one point (a call's cost is mostly its fixed overhead; :func:`_refine_sign_changes`)."""


def _refine_sign_changes(h, a, b, fa, fb, xtol: float, maxiter: int = 100, jump_xtol: float | None = None,
                         step_tol: float | None = None, sections: int = SECTIONS, x0=None, bent_above: bool = False,
                         step_tols=None):
    """Sign changes of a vectorised h on the brackets [a, b]: safeguarded Newton where ``h`` gives a
    slope, secant otherwise, and where a step leaves the bracket the bracket cut into ``sections`` equal parts by
    as many points minus one in the next call (pins.md §6: breakpoints to 1e-12 T_p).  ``h(x, k)`` returns (values,
    slopes) of the brackets ``k`` (indices, repeated for several points of one bracket) at x, a slope NaN where
    unknown; only the brackets not yet done are evaluated.  Stops bracket by bracket when the step or the bracket is
    below ``xtol`` or h is exactly 0.

    A bracket whose end values stay 100x above what the scan's slope |fb - fa|/(b - a) allows over the
    shrunken bracket (after shrinking it 1000x) holds a jump, not a root (e.g. the tangential speed
    where the friction forces flip): it is narrowed only to ``jump_xtol`` (default ``xtol``).  A cut bracket is cut
    again while its end values stay 4x above that (a jump, or a root whose slope is far from the scan's), else
    Newton or the secant take over from the part with the sign change.

    ``x0`` (optional): first points to evaluate, e.g. a root extrapolated from the smooth side
    (:func:`_smooth_side_start`), taken where finite and within a quarter of the bracket of the scan's linear
    interpolation (else that: farther, the bracket may hold three sign changes, and the start would pick another one
    than the linear one, which the other passes and modes of the cycle pick).

    ``bent_above``: a value above zero that comes with a slope is a penetration's, bent there by the contact's own
    force, so Newton from it converges linearly (its error ~1/30 of the step under the Hertz law, not ~s^2): such a
    step stops the bracket only below 30 ``xtol``; otherwise the stepped point, just below zero, is evaluated, and the
    step from there stops it.  ``step_tols`` (optional, per bracket): a larger step tolerance where finite (one whose
    Newton error is known to be small from the bracket's curvature, :func:`_smooth_side_start`).

    ``step_tol`` (default ``xtol``): a bracket also stops after a Newton or secant step below it, at the stepped
    point: Newton's error after a step s is ~(h''/2h') s^2, the secant's ~s^1.6, so a step of 1e-9 T_p leaves
    ~1e-15 T_p, below ``xtol`` = 1e-12 T_p, one evaluation sooner than a step below ``xtol`` would.

    Examples
    --------
    A root of a smooth function (Newton) and a jump (cut into 8 parts per call, to ``jump_xtol``):

    >>> f = lambda x, k: (np.where(k == 0, x - 0.3, np.where(x < 0.7, -1.0, 1.0)), np.where(k == 0, 1.0, np.nan))
    >>> r = _refine_sign_changes(f, [0.0, 0.0], [1.0, 1.0], [-0.3, -1.0], [0.7, 1.0], 1e-12, jump_xtol=1e-9)
    >>> bool(abs(r[0] - 0.3) < 1e-12), bool(abs(r[1] - 0.7) < 1e-9)
    (True, True)
    """
    step_tol = xtol if step_tol is None else max(step_tol, xtol)
    lo, hi = np.array(a, dtype=float), np.array(b, dtype=float)
    flo, fhi = np.array(fa, dtype=float), np.array(fb, dtype=float)
    w0 = hi - lo
    slope0 = np.abs(fhi - flo) / np.where(w0 > 0.0, w0, 1.0)
    jtol = xtol if jump_xtol is None else max(xtol, jump_xtol)
    with np.errstate(divide="ignore", invalid="ignore"):
        x = lo - flo * (hi - lo) / (fhi - flo)                # the scan's linear interpolation
    x = np.where(np.isfinite(x) & (x > lo) & (x < hi), x, 0.5 * (lo + hi))
    stols = None if step_tols is None else np.where(np.isfinite(step_tols), np.maximum(step_tols, step_tol), step_tol)
    if x0 is not None:
        # far from the linear interpolation (a quarter of the bracket) the bracket holds more than one sign change, or
        # the cubic does not describe it: the linear start then
        x0 = np.asarray(x0, dtype=float)
        x = np.where(np.isfinite(x0) & (x0 > lo) & (x0 < hi) & (np.abs(x0 - x) <= 0.25 * (hi - lo)), x0, x)
    xp, fp = np.where(np.abs(flo) < np.abs(fhi), lo, hi), np.where(np.abs(flo) < np.abs(fhi), flo, fhi)
    cut = np.zeros(x.size, dtype=bool)              # cut into sections at the next call (else one point: x)
    frac = np.arange(1, sections) / sections
    act = np.arange(x.size)
    for _ in range(maxiter):
        if act.size == 0:
            break
        one, many = act[~cut[act]], act[cut[act]]
        grid = lo[many, None] + (hi - lo)[many, None] * frac[None, :]
        fv, sv = h(np.concatenate((x[one], grid.ravel())), np.concatenate((one, np.repeat(many, frac.size))))
        done = np.zeros(0, dtype=np.int64)
        if one.size:
            xa = x[one]
            f, slope = fv[:one.size], sv[:one.size]
            lb, hh, fl, fh = lo[one], hi[one], flo[one], fhi[one]
            left = np.sign(f) == np.sign(fl)
            lb, fl = np.where(left, xa, lb), np.where(left, f, fl)
            hh, fh = np.where(~left, xa, hh), np.where(~left, f, fh)
            with np.errstate(divide="ignore", invalid="ignore"):
                d = np.where(np.isfinite(slope) & (slope != 0.0), slope, (f - fp[one]) / (xa - xp[one]))
                new = xa - f / d
            bad = ~np.isfinite(new) | (new <= lb) | (new >= hh)
            new = np.where(bad, 0.5 * (lb + hh), new)
            width = hh - lb
            jump = (width <= 1e-3 * w0[one]) & (np.minimum(np.abs(fl), np.abs(fh)) > 100.0 * slope0[one] * width)
            small = np.abs(new - xa) <= (step_tol if step_tols is None else stols[one])
            if bent_above:
                small = np.where((f > 0.0) & np.isfinite(slope), np.abs(new - xa) <= 30.0 * xtol, small)
            conv = ((f == 0.0) | (~bad & small) | (width <= 2.0 * xtol)
                    | (jump & (width <= 2.0 * jtol)))
            closed = conv & ((width <= 2.0 * xtol) | (jump & (width <= 2.0 * jtol)))
            lo[one], hi[one], flo[one], fhi[one] = lb, hh, fl, fh
            xp[one], fp[one] = xa, f
            x[one] = np.where(f == 0.0, xa, np.where(closed, 0.5 * (lb + hh), new))
            cut[one] = bad                          # a step outside the bracket: cut it at the next call
            done = one[conv]
        if many.size:
            # the part of each cut bracket with the sign change (a zero value: the root there)
            fg = fv[one.size:].reshape(many.size, frac.size)
            X = np.column_stack((lo[many], grid, hi[many]))
            F = np.column_stack((flo[many], fg, fhi[many]))
            j = np.argmax(np.sign(F[:, :-1]) * np.sign(F[:, 1:]) <= 0.0, axis=1)
            r = np.arange(many.size)
            lb, hh, fl, fh = X[r, j], X[r, j + 1], F[r, j], F[r, j + 1]
            width = hh - lb
            big = np.minimum(np.abs(fl), np.abs(fh))
            jump = (width <= 1e-3 * w0[many]) & (big > 100.0 * slope0[many] * width)
            zero = (fl == 0.0) | (fh == 0.0)
            conv = zero | (width <= 2.0 * xtol) | (jump & (width <= 2.0 * jtol))
            lo[many], hi[many], flo[many], fhi[many] = lb, hh, fl, fh
            with np.errstate(divide="ignore", invalid="ignore"):
                sec = lb - fl * width / (fh - fl)
            sec = np.where(np.isfinite(sec) & (sec > lb) & (sec < hh), sec, 0.5 * (lb + hh))
            x[many] = np.where(fl == 0.0, lb, np.where(fh == 0.0, hh, np.where(conv, 0.5 * (lb + hh), sec)))
            near = np.abs(fl) < np.abs(fh)
            xp[many], fp[many] = np.where(near, lb, hh), np.where(near, fl, fh)
            cut[many] = big > 4.0 * slope0[many] * width        # still far from linear there: cut again
            done = np.concatenate((done, many[conv]))
        act = np.setdiff1d(act, done, assume_unique=True)
    return x


ROOT_STEP = 1e-9
"""A breakpoint's refinement stops after a Newton or secant step below ROOT_STEP T_p, at the stepped point (its error
then ~1e-15 T_p, :func:`_refine_sign_changes`; pins.md §6)."""


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


HOLD_FLOOR = 1e-3
"""A full scan's cycle holds when no node contradicts its piece by more than HOLD_FLOOR of the component's largest
|value| (:func:`_pieces_hold`): the dither of a sliding speed about 0 where the friction forces flip stays below
3e-4 on the band designs; the contradictions of the random sample's failing designs were 3.7e-3 to 0.3."""

SCAN_MAX = 4096
"""The densest scan of a cycle's sign changes (:func:`mean_loss_ratio`): 256 intervals, then 4x denser while the
quadrature's nodes contradict their pieces, up to this many; then the cycle is reported as not held."""

DENSE_PER_PERIOD = 1024
"""Interpolated crank angles per period on the contact level's final grid with a Gauss-Kronrod rule
(:func:`gk_interpolated`), shared out over the bisected pieces in proportion to their length (at least 2 each): as
dense as the composite trapezoid's final grid at tol 1e-6 (pins.md §6)."""


def _lagrange_matrix(nodes, points):
    """The Lagrange basis of ``nodes`` at ``points``: L (len(points), len(nodes)), sum_k L[j, k] f(nodes[k]) is the
    interpolating polynomial at points[j] (barycentric weights; exact for polynomials of degree < len(nodes)).

    >>> t = np.array([-1.0, 0.0, 1.0]); bool(np.allclose(_lagrange_matrix(t, np.array([0.5])) @ t**2, 0.25))
    True
    """
    d = nodes[:, None] - nodes[None, :]
    np.fill_diagonal(d, 1.0)
    w = 1.0 / np.prod(d, axis=1)
    diff = points[:, None] - nodes[None, :]
    exact = diff == 0.0
    diff[exact] = 1.0
    L = w[None, :] / diff
    L /= L.sum(axis=1, keepdims=True)
    rows = exact.any(axis=1)
    L[rows] = exact[rows].astype(float)
    return L


def gk_interpolated(sol: Solution, q: QuadResult, rule: str, per_period: int):
    r"""States between the nodes of a Gauss-Kronrod cycle, by the interpolating polynomial of each bisected piece.

    A piece of the final grid [a, b] holds m Kronrod nodes x_k = c + h t_k (c, h its centre and half-width; 7 for
    ``"gk7"``, 15 for ``"gk15"``) on which the state is analytic (no contact enters, leaves or changes branch
    inside a piece, pins.md §5.6); its smooth fields (tau, d tau/d theta, forces, penetrations, speeds) at J
    points c + h s_j, s_j = -1 + (2j + 1)/J inside [t_0, t_(m-1)], J in proportion to the piece's length
    (``per_period`` per period, at least 2), are

    .. math::  f(c + h s_j) \approx \sum_k L_k(s_j) f(x_k)

    (degree m - 1; forces clipped at 0, a penetration -inf where a pin is not a candidate at some node; the
    active set, branch and candidates those of the piece; residual 0: not solved).  They serve the peaks, the
    loaded interval, the detail and the check of the breakpoints (:func:`_pieces_hold`), never the mean (pins.md
    §6, §8).  Returns (the interpolated :class:`Solution`, sorted by theta; each point's piece midpoint), or None
    when the nodes are not found on ``sol``.
    """
    t = _KRONROD[rule][0]
    m = t.size
    a, b = q.edges[:-1], q.edges[1:]
    c, h = 0.5 * (a + b), 0.5 * (b - a)
    x = c[:, None] + h[:, None] * t[None, :]                    # as the quadrature evaluated them
    k_all = np.minimum(np.maximum(sol.theta.searchsorted(x.ravel()), 0), sol.theta.size - 1)
    if not np.array_equal(sol.theta[k_all], x.ravel()):
        return None
    k_all = k_all.reshape(a.size, m)
    mid_all = q.mid if q.mid is not None else c
    span = float(q.edges[-1] - q.edges[0])
    counts = np.maximum(2, np.ceil(per_period * (b - a) / span).astype(np.int64)) if span > 0 else np.full(a.size, 2)
    # every point: its piece p and its s = -1 + (2j + 1)/J_p, the pieces in order (theta sorted)
    piece = np.repeat(np.arange(a.size), counts)
    j = np.arange(piece.size) - np.repeat(np.cumsum(counts) - counts, counts)
    s = -1.0 + (2.0 * j + 1.0) / counts[piece]
    keep = (s > t[0]) & (s < t[-1])
    piece, s = piece[keep], s[keep]
    if not piece.size:
        return None
    W = _lagrange_matrix(t, s)                                   # (n, m), one row per point
    K = k_all[piece]                                             # (n, m) node indices into sol
    theta = c[piece] + h[piece] * s

    z2, n = sol.force.shape[-2], theta.size                     # z2: the state's rows
    # the pins that are candidates at some node of a point's piece (all pins without a window): the others cannot
    # touch there and keep the values of a pin out of reach (-inf, 0, NaN), as the solved states do
    cand = np.ones((z2, n), dtype=bool) if sol.cand is None else sol.cand[:, K].any(axis=-1)
    pj, pi = np.nonzero(cand)
    Kp, Wp = K[pi], W[pi]                                        # (pairs, m)

    def interp(arr):                                             # fields per crank angle only
        return None if arr is None else np.einsum("...nm,nm->...n", arr[..., K], W)

    def interp_pins(arr, fill):                                  # fields per pin (..., z2, n_solved)
        if arr is None:
            return None
        out = np.full(arr.shape[:-2] + (z2, n), fill, dtype=float)
        out[..., pj, pi] = np.einsum("...pm,pm->...p", arr[..., pj[:, None], Kp], Wp)
        return out

    def per_piece(arr, how):                                     # one value per piece (its nodes'), per point
        return None if arr is None else how(arr[..., K])

    finite = np.isfinite(sol.delta)
    delta = np.where(per_piece(finite, lambda v: v.all(axis=-1)), interp_pins(np.where(finite, sol.delta, 0.0), 0.0),
                     -np.inf)
    out = Solution(theta, interp(sol.tau), interp(sol.dtau), np.zeros(n), delta,
                   np.maximum(interp_pins(sol.force, 0.0), 0.0), interp_pins(sol.v_t, 0.0), None, None,
                   interp_pins(sol.switch, np.nan), per_piece(sol.branch, lambda v: v[..., 0]),
                   None if sol.cand is None else cand, interp_pins(sol.ddelta, 0.0),
                   per_piece(sol.noise, lambda v: v.max(axis=-1)), interp(sol.g_tau), rows=sol.rows,
                   traction=per_piece(sol.traction, lambda v: v[..., 0]))
    return out, mid_all[piece]


INNER_SHARE = 1e-2
"""The inner tolerances' share of the target (pins.md §6, error propagation): the equilibria are met to 1/100 of
``tol`` (:func:`equilibrium_residual`), so a cycle mean's stated error is never below INNER_SHARE tol |lambda_bar|
(the Richardson estimate of a very smooth cycle can be far smaller: 6e-12 relative on a stiff linear law)."""


def mean_loss_ratio(model: ContactModel, mu_eff: float, sliding_friction: float, rolls: bool,
                    tol: float = 1e-6, n_max: int = 2 ** 12, n_start: int = 128, n_scan: int = 256,
                    prefilter: bool = True, n_initial=None, rule: str = "trapezoid",
                    prior: "BreakpointRoots | None" = None, prior_width: float = 1e-2, n_min: int = 2,
                    coarse_scan: int | None = None, at_once: int = 0) -> ContactCycle:
    """Cycle mean of lambda(theta) = sum P_j/(T_sat omega_H k/z1) over one period, with an honest error (the
    quadrature's, :func:`~gearcalc.quadrature.piece_errors`, at least :data:`INNER_SHARE` tol |lambda_bar|).

    Every node is an equilibrium solve; the solved states of all nodes are kept (the final grid) for
    the summary and the detail tables (pins.md §5.6, §6).

    Parameters
    ----------
    model : the contact model (design and torque).
    mu_eff : f (fixed pins or pins that cannot roll) or mu_rot (rolling pins) [-].
    sliding_friction : f, for the second contact of a rolling pin [-].
    rolls : the pins roll.
    tol : relative accuracy target; n_max : cap on crank-angle intervals (2^12, pins.md §6).
    n_initial : first-level intervals per piece (:func:`integrate_adaptive`), used when the breakpoints
        give that many pieces.
    rule : the quadrature rule of :func:`integrate_adaptive`: ``"trapezoid"`` (pins.md §6), or opt-in a
        Gauss-Kronrod pair per piece (``"gk7"``, ``"gk15"``: gk7 2-4x fewer crank angles at tol 1e-6; the peaks
        are then taken over its nodes, which hold no piece ends).
    prior : the located sign changes of the same design's cycle at a nearby torque
        (:attr:`ContactCycle.roots`): the breakpoints are then moved from them by Newton within +-``prior_width`` T_p
        (:func:`_incremental_roots`) instead of the full scan, and every node of the quadrature is checked to lie
        on its piece's side of every sign change (its components' signs those of the piece's midpoint, away from
        the piece ends); when the roots cannot be moved, or a node fails that check (a contact appeared or
        vanished between the passes), the cycle is recomputed with the full scan.
    coarse_scan : without ``prior``, scan on this many intervals instead of ``n_scan``, with the same check of the
        nodes (and the same recomputation with the full scan); the nodes must then be at least as dense as the full
        scan (``n_start`` >= n_scan/4 with two doublings), so the check is at least as strict as the full scan.
    n_min : the least intervals of a piece at the first level (:func:`integrate_adaptive`).
    at_once : the first level's doublings solved with it in one call (:func:`integrate_adaptive`), as with
        ``n_initial`` from the last pass, whose final grid the first call then solves at once.
    """
    g = model.g
    scale = model.torque_sat * g.k / g.z1
    cache: list[Solution] = []
    mids: list[np.ndarray] = []
    refs: dict = {}
    ref_sols: list[Solution] = []
    sets: list[tuple] = []          # each node's piece sets (active, branch, traction), as ``cache``

    solved = [np.empty(0), np.empty(0), np.empty(0)]     # piece keys, tau, d tau/d theta of the nodes solved so far

    def integrand(x, mid):
        um, inv = np.unique(mid, return_inverse=True)
        new = np.array([m for m in um if m not in refs])
        if new.size:
            # the pieces' fixed sets (:meth:`ContactModel.reference`), from a state solved in the stretch between the
            # sign changes around the piece while they were located, else at the midpoint; kept for the check below
            col, known = _interior_states(found, new, g.period)
            parts = []
            if (col >= 0).any():
                rs = _take(known, col[col >= 0])
                rs.theta = new[col >= 0]            # the piece's reference, told by its midpoint
                parts.append(rs)
            if (col < 0).any():
                parts.append(model.state(new[col < 0], phases=False))
            for rs in parts:
                ref_sols.append(rs)
                active, branch = rs.force > 0.0, rs.branch
                traction = None if model.friction is None else model.traction(rs)
                for i, m in enumerate(rs.theta):
                    refs[m] = (active[..., i], None if branch is None else branch[..., i],
                               None if traction is None else traction[..., i])
        active = np.stack([refs[m][0] for m in um], axis=-1)[..., inv]
        branch = None if refs[um[0]][1] is None else np.stack([refs[m][1] for m in um], axis=-1)[..., inv]
        traction = None if refs[um[0]][2] is None else np.stack([refs[m][2] for m in um], axis=-1)[..., inv]
        key = piece_keys(edges, x, mid)
        s = model.state(x, (active, branch, traction), phases=False, guess=piece_guess(*solved, key, x, edges))
        order = (k_all := np.concatenate((solved[0], key))).argsort(kind="stable")
        solved[:] = [k_all[order], np.concatenate((solved[1], s.tau))[order],
                     np.concatenate((solved[2], s.dtau))[order]]
        cache.append(s)
        mids.append(np.asarray(mid, dtype=float))
        sets.append((active, branch, traction))
        loss, _, _ = contact_losses(s, g.R_b, mu_eff, sliding_friction, rolls)
        return loss.sum(axis=(0, 1)) / scale / g.period

    if model.window is None and prefilter:
        model.set_window()
    rows = model.layout()[0]             # the window is fixed for this cycle (a failing one recomputes it)
    found = None
    if prior is not None:
        found = _incremental_roots(model, prior, prior_width * g.period, tol, rolls, PRIOR_WIDTH_MAX * g.period)
    elif coarse_scan is not None and coarse_scan < n_scan:
        found = _scan_roots(model, coarse_scan, tol, rolls, checked=True)
    if found is None:
        # as dense as the last pass's full scan had to be (its nodes held only there; pins.md §6)
        n_scan = max(n_scan, model.scan_n)
        found = _scan_roots(model, n_scan, tol, rolls)
    edges = _edges(model, found, tol)
    q = integrate_adaptive(integrand, edges, tol=tol, n_max=n_max, n_start=n_start, n_initial=n_initial, rule=rule,
                           n_min=n_min, at_once=at_once)
    if rule != "trapezoid":
        # a Gauss-Kronrod rule evaluates no piece end: the one-sided states at both ends of every piece join the
        # final grid for the peaks, the loaded interval and the detail (they do not enter the mean; pins.md §6)
        u = unique_sorted(np.asarray(edges, dtype=float))
        lo, hi = u[:-1], u[1:]
        lo, hi = lo[hi > lo], hi[hi > lo]
        mid = 0.5 * (lo + hi)                    # the pieces' midpoints, as the quadrature tells them
        integrand(np.column_stack((lo, hi)).ravel(), np.repeat(mid, 2))     # in time order: ..., b_p, a_(p+1), ...
    solved = _concat(cache)
    dense = gk_interpolated(solved, q, rule, DENSE_PER_PERIOD) if rule != "trapezoid" else None
    # the check of the moved or coarse roots covers the interpolated states too: as dense as the trapezoid's nodes
    # (every third interpolated state: 341 per period, as dense as the trapezoid's nodes, pins.md §6)
    checked = (cache, mids) if dense is None else (cache + [_take(dense[0], slice(None, None, 3))],
                                                   mids + [dense[1][::3]])
    # the moved or coarse roots: every sign; the full scan's: a sliding speed that dithers about 0 (below 1e-3 of its
    # largest) where the friction forces flip does not count (its losses are as small)
    held = _pieces_hold(*checked, ref_sols, edges, rolls, tol, g.period, floor=HOLD_FLOOR if found.scanned else 0.0)
    if not held and not found.scanned:
        # a sign change the moved roots do not hold: the full scan (pins.md §6)
        return mean_loss_ratio(model, mu_eff, sliding_friction, rolls, tol, n_max, n_start, n_scan, prefilter,
                               n_initial, rule, n_min=n_min)
    if not held and n_scan < SCAN_MAX and deflection_sized(solved.tau, g):
        # nor the full scan's: a contact or a sliding direction that changes twice between its angles, a 4x denser
        # one (pins.md §6), also for the later passes of this design; not where the satellite turns beyond a
        # deflection (:func:`deflection_sized`): that cycle is flagged whatever the scan (its balance can have several
        # solutions, pins.md §7), and at its cap of angles each denser scan cost seconds a pass
        model.scan_n = 4 * n_scan
        return mean_loss_ratio(model, mu_eff, sliding_friction, rolls, tol, n_max, n_start, 4 * n_scan, prefilter,
                               n_initial, rule, n_min=n_min)
    n_solved = solved.theta.size
    sol = solved if dense is None else _concat([solved, dense[0]])
    sol.phase, sol.zeta = model.phases(sol.theta, sol.rows)
    if not model.window_holds(sol.tau, sol.theta):
        model.window = None        # the window's tau bound does not hold: every pin, every angle
        return mean_loss_ratio(model, mu_eff, sliding_friction, rolls, tol, n_max, n_start, n_scan, False, n_initial,
                               rule, None, prior_width, n_min)
    model.roots = found
    nodes = None
    if dense is None:
        # the nodes' piece sets and midpoints in the final grid's order (:func:`_concat`), for the next torque pass
        # from these nodes (:func:`relinearised_cycle`)
        places = _sorted_places([c.theta for c in cache])

        def cat(parts):
            return None if parts[0] is None else _merged(parts, places, parts[0].ndim - 1)

        nodes = ((cat([t[0] for t in sets]), cat([t[1] for t in sets]), cat([t[2] for t in sets])),
                 cat(mids), ref_sols, rows)
    # the states' equilibria are met to 1/100 of the tolerance (:func:`equilibrium_residual`): no error below that
    err = max(float(q.err[0]), INNER_SHARE * tol * abs(float(q.value[0])))
    return ContactCycle(float(q.value[0]), err, q.converged, n_solved, q, sol, edges, found,
                        (g.R_b, mu_eff, sliding_friction, rolls, scale), nodes, held)


RELINEARISE_MARGIN = 1.25
"""A breakpoint's move to the next torque, taken as this many times its Newton step (:func:`relinearised_cycle`; the
step's own error is second order in a move of ~1e-6 T_p)."""
RELINEARISE_STRIDE = 8
"""The pass from the last pass's nodes solves every RELINEARISE_STRIDE-th node of each piece and its ends
(:func:`relinearised_cycle`, :func:`_strided`); the nodes between are interpolated."""
RELINEARISE_SHARE = 0.9
"""The largest share of the tolerance (tol lambda_bar) that the quadrature's error and the strips the breakpoints move
through may hold together in a torque pass from the last pass's nodes (:func:`relinearised_cycle`); more: a full
pass."""


def relinearised_cycle(model: ContactModel, cyc: ContactCycle, prev: ContactModel, tol: float,
                       stride: int | None = None) -> "ContactCycle | None":
    r"""The cycle at the torque of ``model`` from the final grid of ``cyc`` (solved with ``prev``, a torque a few 1e-5
    away): the next pass of the torque fixed point without locating the breakpoints again (pins.md §6(6), §7).

    Every node keeps its crank angle and its piece's sets and is solved at the new torque from the Newton step
    tau + dM/G_tau (:meth:`ContactModel.state`, mostly one balance per node).  On each piece the state is then the
    smooth extension of the new torque's over the old piece, so

    .. math::

        \bar\lambda_2 = \frac{\bar\lambda_1 s_1 + \frac{1}{T_p}\sum_i w_i (L_2 - L_1)_i}{s_2}

    (L the nodes' loss per unit crank speed, w_i the final grid's trapezoid weights per piece, s the loss ratio's
    scale T_sat k/z1), exact but for the strips between each breakpoint's old place r and its new one: there the
    other side's state holds.  A breakpoint moves by d = |c/c'| (c the sign-changing component at the new torque
    at r, c' its slope, else a secant to the next node: a Newton step), taken as D = 1.25 d
    (``RELINEARISE_MARGIN``); the integrand's two sides differ over the strip by at most the jump J at r plus each
    side's change, which grows like t^p from r: read off the nearest node at least D out (Delta at distance
    t_n; the graded pieces next to a Hertz entry have one close by), scaled by min(1, D/t_n)^p and integrated
    over the strip (1/(1 + p)); p = 1 for the linear law, 1/9 for the Hertz law (its singular speeds,
    (theta - theta_0)^(1/9)).  Under a power law a contact entry or exit alone (:func:`_strip_sides`) counts nothing
    where its zero moved into the touching side (the states there are the other side's exactly); where it moved out
    of it, the other side's states miss the touching pin's share of the speeds, an error that grows from 0 at the
    new zero like t^p to e_r at the old place (the touching side's loss minus the other's, both solved at the new
    torque): its integral e_r d/(1 + p) is added to the value, and (1.25^(1 + p) - 1) of it (a zero up to 25 %
    farther) is the strip's term instead.  That bound,

    .. math::

        E_s = \frac{1}{T_p s_2}\sum_b D_b \Big(J_b + \sum_{\pm} \frac{\Delta_\pm \min(1, D_b/t_\pm)^p}{1 + p}\Big),

    is added to the quadrature's error (rescaled by s_1/s_2); the difference's own quadrature error is ~tol of a
    change of ~1e-7 lambda_bar.  Measured on the paper designs: the loss ratio within 0.28 of the full pass's
    stated error of it; E_s 0.4-1.1 of tol lambda_bar at the torque steps of their second passes (3e-6 to 2e-5);
    with the strips integrated (2026-11-27) every pass is taken, within 0.48 of the stated errors of a full pass at
    1/100 of the tolerance (0.19 on random designs, 0.52 before).

    None (a full pass is needed) when ``cyc`` has no final-grid record (a Gauss-Kronrod rule), a node has no
    equilibrium with its sets or non-finite values, a node farther than D from every breakpoint has a component
    with the other sign than its piece (:func:`_pieces_hold`: a contact appears or leaves; with the floor of
    ``cyc``'s own check, :data:`HOLD_FLOOR` where its roots are the full scan's), the window's tau range
    does not hold or its pins are not the last pass's (:meth:`ContactModel.layout`: a window recomputed for a wider
    tau range), a breakpoint's component is not found, or the quadrature's error and E_s exceed
    ``RELINEARISE_SHARE`` of tol lambda_bar (a breakpoint that moves far, or a loss that jumps there: rolling pins'
    lead switch, flipping friction forces).

    Examples
    --------
    >>> g = Cycloid.from_curtate_ratio(21, 22, 3.9, 0.75, 1.95)
    >>> law = contact_law("linear", stiffness=1e5)
    >>> a = ContactModel(g, CycloidProfile(g, 0.0, 0.0), law, 1e4, MULTIPLIER)
    >>> first = mean_loss_ratio(a, 0.1, 0.1, False, tol=1e-5)
    >>> b = ContactModel(g, CycloidProfile(g, 0.0, 0.0), law, 1e4 * (1.0 + 1e-6), MULTIPLIER)
    >>> b.inherit(a)
    >>> lite = relinearised_cycle(b, first, a, 1e-5)
    >>> lite is not None and abs(lite.loss_ratio - first.loss_ratio) < 1e-5 * first.loss_ratio
    True

    References
    ----------
    .. [1] pins.md §6 (the torque fixed point's passes), §7.
    """
    if cyc.nodes is None or cyc.roots is None:
        return None
    sets, node_mid, ref_sols, rows = cyc.nodes
    R_b, mu_eff, f, rolls, scale1 = cyc.friction
    g, sol1 = model.g, cyc.sol
    rows2 = model.layout()[0]
    if not _same_rows(rows2, rows):
        # the window recomputed for a wider tau range (:meth:`ContactModel.inherit`): the last pass's states and sets
        # over this model's rows (a pin they do not hold: out of reach at every node, inactive); a pin left out must
        # carry no force in them (the window's bound: it cannot touch at this torque either)
        src, dst = (np.arange(g.z2) if r is None else r for r in (rows, rows2))
        if (sol1.force[:, ~np.isin(src, dst)] > 0.0).any():
            return None
        sets = tuple(None if a is None else _over_rows(a, src, dst, fill) for a, fill in zip(sets, (False, -1, 0.0)))
        ref_sols = [_relayout(r, rows2, g.z2) for r in ref_sols]
        sol1, rows = _relayout(sol1, rows2, g.z2), rows2
    Tp, x = g.period, cyc.sol.theta
    scale2 = model.torque_sat * g.k / g.z1
    # the final grid piece by piece (a piece end is a node of each of its two pieces); pieces follow each other in
    # theta, so the order by (piece, theta) is sorted in theta too
    edges = cyc.breakpoints
    p = np.minimum(np.maximum(edges.searchsorted(node_mid) - 1, 0), edges.size - 2)
    order = np.lexsort((x, p))
    xs, ps = x[order], p[order]
    keep, lo_s, hi_s, t_s = _strided(xs, ps, RELINEARISE_STRIDE if stride is None else stride)
    kept = order[keep]                        # the nodes solved at the new torque (both ends of every piece)
    with np.errstate(divide="ignore", invalid="ignore"):
        step = (model.M_req - prev.M_req) / sol1.g_tau[kept]
        guess = np.where((sol1.g_tau[kept] < 0.0) & np.isfinite(step), sol1.tau[kept] + step, np.nan)
        try:
            # the last pass's pose of its nodes (solved in one call, in this order), at the kept ones: its foot points
            # start this torque's
            last, same_sides = prev.last_pose, (prev.sides is None) == (model.sides is None) and (
                prev.sides is None or np.array_equal(prev.sides, model.sides))
            reuse = _sub_pose(last, kept) if last is not None and same_sides and last.theta.shape == x.shape \
                and np.array_equal(last.theta, x) else None
            s2k = model.state(x[kept], tuple(None if a is None else a[..., kept] for a in sets), phases=False,
                              guess=guess, reuse=reuse)
        except NoEquilibrium:
            return None
        L1 = contact_losses(sol1, R_b, mu_eff, f, rolls)[0].sum(axis=(0, 1))
        L2 = contact_losses(s2k, R_b, mu_eff, f, rolls)[0].sum(axis=(0, 1))
    if not (np.isfinite(L2).all() and np.isfinite(s2k.force).all() and np.isfinite(s2k.v_t).all()):
        return None
    # the change's trapezoid over the solved nodes of each piece, and over every other one of them (its error)
    dL, pk = L2 - L1[kept], ps[keep]
    w, w2 = _nested_trapezoid_weights(xs[keep], pk)
    change = np.bincount(pk, weights=w * dL, minlength=edges.size)
    E_d = float(np.abs(change - np.bincount(pk, weights=w2 * dL, minlength=edges.size)).sum()) / Tp / scale2
    lam2 = (cyc.loss_ratio * scale1 + float(change.sum()) / Tp) / scale2
    E_q = cyc.loss_ratio_err * scale1 / scale2 + E_d
    # the nodes between: the first pass's states moved by the change, linear between the solved nodes around
    place = np.cumsum(keep) - 1                   # each kept node's place in ``kept`` (xs order)
    lo_n, hi_n, t_n = (np.empty_like(a) for a in (lo_s, hi_s, t_s))
    lo_n[order], hi_n[order], t_n[order] = place[lo_s], place[hi_s], t_s
    s2 = _moved(sol1, s2k, kept, lo_n, hi_n, t_n)
    if not model.window_holds(s2.tau, s2.theta, prev):
        return None
    l1 = L1[order]
    r = cyc.roots.roots
    E_s, width = 0.0, 0.0
    if r.size:
        n = x.size
        a_end = np.minimum(np.maximum(xs.searchsorted(r), 0), n - 1)      # the two one-sided nodes at each breakpoint
        b_end = np.minimum(a_end + 1, n - 1)
        if not ((np.abs(xs[a_end] - r) <= 8e-12 * Tp) & (xs[b_end] == xs[a_end])).all():
            return None
        # the components that change sign at each breakpoint (between its neighbouring nodes, first torque), and
        # how far their zero moved: a Newton step from the one-sided nodes at the new torque (secant: no slope)
        nb = order[np.minimum(np.maximum(np.concatenate((a_end - 1, b_end + 1)), 0), n - 1)]
        ends = order[np.concatenate((a_end, b_end))]
        v1 = _components(_take(sol1, nb), rolls)[0]
        v2n = _components(_take(s2, nb), rolls)[0]
        v2, dv2, n_delta = _components(_take(s2, ends), rolls)
        m = r.size
        flips = (np.sign(v1[:, :m]) * np.sign(v1[:, m:]) < 0.0)
        flips = np.concatenate((flips, flips), axis=1)
        with np.errstate(divide="ignore", invalid="ignore"):
            secant = (v2n - v2) / (x[nb] - x[ends])[None, :]
            slope = np.where(np.isfinite(dv2) & (dv2 != 0.0), dv2, secant)
            step = np.where(flips, -v2 / slope, 0.0)          # the zero's signed move, from either side
        d = np.maximum(np.abs(step[:, :m]), np.abs(step[:, m:])).max(axis=0)
        if not ((flips.any(axis=0)).all() and np.isfinite(d).all()):
            return None
        move = RELINEARISE_MARGIN * d
        width = float(move.max())
        p_exp = 1.0 if model.law.exponent == 1.0 else model.law.exponent - 1.0
        lo = np.minimum(np.maximum(xs.searchsorted(r - move, side="right") - 1, 0), n - 1)
        hi = np.minimum(np.maximum(xs.searchsorted(r + move, side="left"), 0), n - 1)
        left, right = _strip_sides(flips[:, :m], step, v1[:, :m], n_delta, model.law.exponent != 1.0)
        with np.errstate(divide="ignore", invalid="ignore"):
            side = (left * np.abs(l1[lo] - l1[a_end]) * np.minimum(1.0, move / (r - xs[lo])) ** p_exp
                    + right * np.abs(l1[hi] - l1[b_end]) * np.minimum(1.0, move / (xs[hi] - r)) ** p_exp)
            side = side / (1.0 + p_exp)
            strip = move * (np.abs(l1[a_end] - l1[b_end]) + np.where(move > 0.0, side, 0.0))
            grows = left != right               # an entry or exit alone whose zero moved out of the touching side
            if grows.any():
                # that strip integrated, not bounded: the integrand's error there (the touching pin's share of the
                # speeds, missing) grows from 0 at the new zero like t^p to e_r at the old place, where both sides'
                # states are solved at the new torque: its integral e_r d/(1 + p) joins the value, and what a zero
                # up to 25 % farther would add, (1.25^(1 + p) - 1) of it, the error
                both = np.concatenate((a_end, b_end))          # piece ends: solved nodes, their losses in L2
                l2 = L2[place[both]] if keep[both].all() else \
                    contact_losses(_take(s2, ends), R_b, mu_eff, f, rolls)[0].sum(axis=(0, 1))
                e_r = np.where(left == 1.0, l2[:m] - l2[m:], l2[m:] - l2[:m])     # touching minus the other
                grown = np.where(grows, e_r * d / (1.0 + p_exp), 0.0)
                strip = np.where(grows, (RELINEARISE_MARGIN ** (1.0 + p_exp) - 1.0) * np.abs(grown), strip)
                lam2 += float(grown.sum()) / Tp / scale2
        if not (np.isfinite(strip).all() and math.isfinite(lam2)):
            return None
        E_s = float(strip.sum()) / Tp / scale2
    if not (E_q + E_s <= RELINEARISE_SHARE * tol * abs(lam2)
            and _pieces_hold([s2], [node_mid], ref_sols, edges, rolls, tol, Tp, away=(r, width),
                             floor=HOLD_FLOOR if cyc.roots.scanned else 0.0)):
        return None
    # functions of theta and the mode only
    s2.phase, s2.zeta = (sol1.phase, sol1.zeta) if sol1.phase is not None else model.phases(s2.theta, s2.rows)
    model.roots = cyc.roots
    return ContactCycle(float(lam2), E_q + E_s, cyc.converged, cyc.n_crank, cyc.quad, s2, edges, cyc.roots,
                        (R_b, mu_eff, f, rolls, scale2), (sets, node_mid, ref_sols, rows))


def _strip_sides(flips, step, v_left, n_delta: int, power_law: bool):
    r"""(left, right): 1 where a side's change counts in the bound of a breakpoint's strip (:func:`relinearised_cycle`),
    0 where it does not, per breakpoint (m,).

    A node's forces are its own equilibrium's; its piece's sets enter only the one-sided derivatives (d tau/d theta,
    so the sliding speeds).  A contact entry or exit alone (one sign-changing component, a penetration, both sides'
    Newton steps of its zero the same way) under a power law F = c max(delta, 0)^p (p > 1), whose extension below
    delta = 0 has force and stiffness 0 (:meth:`ContactLaw.force_on`): where the zero moved into the touching side,
    that side's nodes in the strip hold the pin at delta < 0, exactly the other side's state: both 0; where it moved
    the other way, the other side's nodes miss the touching pin's stiffness, whose share of the speeds grows from 0
    at the new zero (like t^(p - 1)): 1 on the touching side only (:func:`relinearised_cycle` then integrates that
    strip instead of bounding it).  Every other breakpoint (a linear law, whose extension goes on linearly; a
    sliding direction; several components; steps of opposite signs): both.

    ``flips`` (c, m): the components that change sign at each breakpoint; ``step`` (c, 2m): their zeros' signed
    Newton steps from the left and the right one-sided node; ``v_left`` (c, m): their values left of it (the first
    pass's); ``n_delta``: the penetrations come first (:func:`_components`).

    An entry moving earlier (only the touching right side counts), an exit moving later (the left side), an entry
    moving later (into the touching side: neither), a sliding direction (both):

    >>> flips = np.array([[True, False, True, False], [False, True, False, False], [False, False, False, True]])
    >>> step = np.array([[-1e-6, 0.0, 1e-6, 0.0, -2e-6, 0.0, 2e-6, 0.0], [0.0, 1e-6, 0.0, 0.0, 0.0, 1e-6, 0.0, 0.0],
    ...                  [0.0, 0.0, 0.0, 1e-6, 0.0, 0.0, 0.0, 1e-6]])
    >>> v_left = np.array([[-1e-4, 0.0, -1e-4, 0.0], [0.0, 1e-4, 0.0, 0.0], [0.0, 0.0, 0.0, 0.5]])
    >>> [a.tolist() for a in _strip_sides(flips, step, v_left, 2, True)]
    [[0.0, 1.0, 0.0, 1.0], [1.0, 0.0, 0.0, 1.0]]
    """
    m = flips.shape[1]
    if not power_law:
        return np.ones(m), np.ones(m)
    k = np.argmax(flips, axis=0)
    cols = np.arange(m)
    sa, sb = step[k, cols], step[k, m + cols]
    alone = (flips.sum(axis=0) == 1) & (k < n_delta) & (np.sign(sa) == np.sign(sb)) & (sa != 0.0)
    touch_left = v_left[k, cols] > 0.0                     # the pin touches left of the zero: an exit
    into = np.where(touch_left, sa < 0.0, sa > 0.0)        # the zero moved into the touching side
    left = np.where(alone, np.where(into, 0.0, touch_left.astype(float)), 1.0)
    right = np.where(alone, np.where(into, 0.0, (~touch_left).astype(float)), 1.0)
    return left, right


def _piece_places(ps):
    """Of nodes sorted by piece (``ps`` their pieces): each run's first position ``start`` and node count ``count``,
    and per node its run ``piece`` and its place ``j`` in it (0 at the piece's first node)."""
    start = np.flatnonzero(np.concatenate(([True], ps[1:] != ps[:-1])))
    count = np.diff(np.append(start, ps.size))
    piece = np.repeat(np.arange(start.size), count)
    return start, count, piece, np.arange(ps.size) - start[piece]


def _strided(xs, ps, stride: int):
    """Every ``stride``-th node of each piece and both its ends (nodes sorted by piece, then theta; ``ps`` their
    pieces): a piece of M intervals takes the largest of stride, stride/2, ... (powers of 2 down to 1) that leaves it
    at least 4 intervals.  Returns (keep, lo, hi, t): the kept nodes, and for every node the kept nodes around it in
    its piece (positions) and its place between them, (x - x_lo)/(x_hi - x_lo) (0 at a kept node)."""
    start, count, piece, j = _piece_places(ps)
    k = np.ones(start.size, dtype=np.int64)
    s = 2
    while s <= stride:
        k = np.where(count - 1 >= 4 * s, s, k)
        s *= 2
    kk, M = k[piece], (count - 1)[piece]
    keep = (j % kk == 0) | (j == M)
    left = j - j % kk
    lo = start[piece] + left
    hi = start[piece] + np.minimum(left + kk, M)
    with np.errstate(divide="ignore", invalid="ignore"):
        t = np.where(keep | (xs[hi] == xs[lo]), 0.0, (xs - xs[lo]) / (xs[hi] - xs[lo]))
    return keep, lo, np.where(keep, lo, hi), t


def _trapezoid_weights(xs, ps):
    """The composite trapezoid's weights of nodes sorted by piece, then theta (``ps`` their pieces), piece by
    piece."""
    h = np.where(ps[1:] == ps[:-1], np.diff(xs), 0.0)
    w = np.zeros(xs.size)
    w[:-1] += 0.5 * h
    w[1:] += 0.5 * h
    return w


def _nested_trapezoid_weights(xs, ps):
    """The composite trapezoid's weights of nodes sorted by piece, then theta (``ps`` their pieces), piece by piece,
    over all nodes and over every other node of each piece (its ends kept): (w, w_half), the levels N and N/2 of a
    piece of N intervals (an odd N: the half level's last interval is the one that is left)."""
    _, count, piece, j = _piece_places(ps)
    half = (j % 2 == 0) | (j == count[piece] - 1)
    w_half = np.zeros(xs.size)
    w_half[half] = _trapezoid_weights(xs[half], ps[half])
    return _trapezoid_weights(xs, ps), w_half


def _moved(sol: Solution, part: Solution, kept, lo, hi, t) -> Solution:
    """``sol`` with the states ``part`` at its crank angles ``kept`` and, at the others, moved by the change
    part - sol interpolated linearly between the kept nodes around each (``lo``, ``hi``: their places in ``kept``;
    weight ``t`` on ``hi``); the sets (branch, candidates, the friction forces' directions), the phases, the residual
    and the contact geometry (nx, ny, wx, wy) stay those of ``sol`` there (not solved at the new torque), forces are
    clipped at 0, a value that is not finite (a pin out of reach) is left as it is (:func:`relinearised_cycle`; both
    over the same rows)."""
    n = sol.theta.size
    rest = np.ones(n, dtype=bool)
    rest[kept] = False
    rest = np.flatnonzero(rest)
    lo, hi, t = lo[rest], hi[rest], t[rest]
    # a pin that is not a candidate at a node keeps its fill values there (0 force and speed, -inf penetration)
    cand = None if sol.cand is None else sol.cand[:, rest]
    out = {}
    # the contact geometry (over the pins each state was solved on, not all pins): the solved nodes' own, the first
    # pass's between (the normals turn with the rotation's change: ~1e-7 relative in the crank-bearing force; not
    # interpolated: a piece end's kept geometry may be the other side's where a cycloidal pin passes to a crest
    # corner, :meth:`ContactModel.kept_contacts`); dropped when the two passes were solved on different pins
    same = (sol.pins is not None and part.pins is not None and sol.pins.shape[0] == part.pins.shape[0]
            and np.array_equal(sol.pins[:, kept], part.pins))
    moving: dict = {}
    for fl in dataclasses.fields(sol):
        a = getattr(sol, fl.name)
        geometry = fl.name in _GEOMETRY_FIELDS
        if geometry and not same:
            out[fl.name] = None
            continue
        if (fl.name in ("theta", "phase", "zeta", "branch", "cand", "rows") or not isinstance(a, np.ndarray)
                or a.shape[-1:] != (n,)):
            out[fl.name] = a
            continue
        b = np.asarray(getattr(part, fl.name))
        if fl.name in ("residual", "traction") or geometry or not rest.size:
            new = a.copy()
            new[..., kept] = b
            out[fl.name] = new
            continue
        moving.setdefault((a.shape, b.shape), []).append((fl.name, a, b))
    # the fields of one shape moved together (one set of array operations for the penetrations, forces, speeds and
    # their slopes, one for tau, d tau/d theta and the rest over the crank angles)
    for group in moving.values():
        names = [f for f, _, _ in group]
        ai = np.stack([a for _, a, _ in group])
        bi = np.stack([b for _, _, b in group])
        with np.errstate(invalid="ignore"):
            d = bi - ai[..., kept]
        d = np.where(np.isfinite(d), d, 0.0)
        old = ai[..., rest]
        dl = d[..., lo]
        v = old + dl + t * (d[..., hi] - dl)
        if "force" in names:
            f = names.index("force")
            v[f] = np.maximum(v[f], 0.0)
        ok = np.isfinite(old)
        if ai.ndim >= 3 and cand is not None:
            ok &= cand
        ai[..., rest] = np.where(ok, v, old)
        ai[..., kept] = bi
        out.update(zip(names, ai))
    return Solution(**out)


INTERIOR_MARGIN = 1e-6
"""A state stands for a piece's sets when it lies farther than INTERIOR_MARGIN T_p from every located sign change
(1000x a jump's location tolerance at --tol 1e-6, :func:`_interior_states`)."""


def _interior_states(found: BreakpointRoots, mids, period: float):
    """For the pieces with midpoints ``mids``: the column of a state solved while the sign changes ``found`` were
    located (``found.seen``) that lies in the same stretch between two of them as the midpoint, farther than
    ``INTERIOR_MARGIN`` T_p from both (the nearest such to the midpoint), else -1; and those states concatenated.
    The components keep their signs over the stretch, so that state has the piece's active set, branches and
    friction directions, as its midpoint's would (pins.md §6; a sign change the located ones missed is caught on the
    nodes, :func:`_pieces_hold`)."""
    seen = [s for s in found.seen if s.theta.size]
    if not seen:
        return np.full(mids.size, -1), None
    known = _concat(seen)
    th = known.theta
    r = found.roots
    margin = INTERIOR_MARGIN * period
    k = r.searchsorted(mids)
    lo = np.where(k > 0, r[np.maximum(k - 1, 0)], -np.inf)[:, None]
    hi = np.where(k < r.size, r[np.minimum(k, r.size - 1)], np.inf)[:, None]
    inside = (th[None, :] > lo + margin) & (th[None, :] < hi - margin)
    dist = np.where(inside, np.abs(th[None, :] - mids[:, None]), np.inf)
    col = np.argmin(dist, axis=1)
    return np.where(np.isfinite(dist[np.arange(mids.size), col]), col, -1), known


def piece_keys(edges, x, mid):
    """The nodes' places 2 p + (x - a_p)/(b_p - a_p) in [2 p, 2 p + 1], p the piece of the midpoint ``mid`` (edges
    sorted): the keys of two pieces never meet, so the piece ends are told apart from their neighbours'."""
    p = np.minimum(np.maximum(edges.searchsorted(mid) - 1, 0), edges.size - 2)
    a, b = edges[p], edges[p + 1]
    with np.errstate(divide="ignore", invalid="ignore"):
        t = np.where(b > a, (x - a) / (b - a), 0.5)
    return 2.0 * p + np.minimum(np.maximum(t, 0.0), 1.0)


def piece_guess(keys, tau, dtau, key, x, edges):
    """Warm starts of tau at the nodes ``key`` (:func:`piece_keys`) from the solved nodes of the same piece around
    each (keys sorted): the cubic Hermite interpolant of tau and d tau/d theta (one-sided at the piece's ends, from
    inside it), error O(h^4) in their spacing h; NaN where the piece has no solved node on either side (then the
    model's own warm start, :meth:`ContactModel.state`).  None when nothing is solved yet."""
    if keys.size < 2:
        return None
    j = np.minimum(np.maximum(keys.searchsorted(key), 1), keys.size - 1)
    a, b = j - 1, j
    p = np.floor(key * 0.5)
    same = (np.floor(keys[a] * 0.5) == p) & (np.floor(keys[b] * 0.5) == p)
    p = np.minimum(np.maximum(p.astype(np.int64), 0), edges.size - 2)
    L = edges[p + 1] - edges[p]
    xa, xb = edges[p] + (keys[a] - 2.0 * p) * L, edges[p] + (keys[b] - 2.0 * p) * L
    h = xb - xa
    with np.errstate(divide="ignore", invalid="ignore"):
        herm = _hermite((x - xa) / h, h, tau[a], dtau[a], tau[b], dtau[b])
    return np.where(same & (h > 0.0) & np.isfinite(herm), herm, np.nan)


def _pieces_hold(cache, mids, ref_sols, edges, rolls: bool, tol: float, period: float, away=None,
                 floor: float = 0.0) -> bool:
    """Whether every evaluated node lies on its piece's side of every sign change: no component has the
    opposite sign of the piece's midpoint at a node farther than 2e-3 tol T_p from the piece's ends (where a
    located jump may lie within 1e-3 tol T_p of its place, :func:`_scan_roots`).  A stricter test than the full
    scan's (the nodes are denser than its 256 intervals), used for the incrementally moved breakpoints.
    ``away`` = (points, width): nor at a node within ``width`` of a point (sorted; the strips a breakpoint may have
    moved through since the nodes were placed, :func:`relinearised_cycle`).  ``floor``: a contradiction counts only
    where the node's value and the piece's both exceed ``floor`` times the component's largest |value| over the nodes
    (a sliding speed that dithers about 0 where the friction forces flip, with friction in the balance)."""
    rm = np.concatenate([r.theta for r in ref_sols])
    rv = np.concatenate([_components(r, rolls)[0] for r in ref_sols], axis=1)
    if floor > 0.0:
        with np.errstate(invalid="ignore"), warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)          # a component without a sign anywhere: NaN
            big = floor * np.nanmax(np.abs(np.concatenate([_components(c, rolls)[0] for c in cache], axis=1)),
                                    axis=1)
        big = np.where(np.isfinite(big), big, 0.0)[:, None]
        rv = np.where(np.abs(rv) > big, rv, np.nan)
    rpos, rneg = rv > 0.0, rv < 0.0             # NaN: neither (no sign)
    order = rm.argsort()
    excl = 2e-3 * tol * period + 8e-12 * period
    for c, mid in zip(cache, mids):
        x = c.theta
        piece = np.minimum(np.maximum(edges.searchsorted(mid) - 1, 0), edges.size - 2)
        inner = (x - edges[piece] > excl) & (edges[piece + 1] - x > excl)
        if away is not None and away[0].size:
            inner &= _distance_to(away[0], x) > away[1]
        if not inner.any():
            continue
        v = _components(c, rolls)[0][:, inner]
        if v.shape[0] != rv.shape[0]:
            return False
        if floor > 0.0:
            v = np.where(np.abs(v) > big, v, np.nan)
        col = order[rm[order].searchsorted(mid[inner])]
        if (((v > 0.0) & rneg[:, col]) | ((v < 0.0) & rpos[:, col])).any():
            return False
    return True


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
    order = z.argsort(kind="stable")
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
    # a reversal is a change between spins above round-off and the friction-induced dither at a reversal
    # with friction in the balance (the spin jumps through 0 where the friction forces flip): |spin| below
    # 1e-3 of its peak does not count
    sg = np.sign(np.where(np.abs(ww) > 1e-3 * wmax, ww, 0.0))
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
        F1, phF = disc_sum_peak(sol.phase[loaded], F_pin[loaded], n_discs)
        P1, phP = disc_sum_peak(sol.phase[loaded], loss_pin[loaded], n_discs)
        t = sol.theta / g.period
        tot = float(sum_over_discs(t, loss_pin.sum(axis=0), disc_offsets(n_discs, g.z2), 1.0).max())
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


def free_play(model: ContactModel, theta, limit: float | None = None, sides=(-1.0, 1.0)):
    """Angular free play of the unloaded satellite at crank angles theta: (tau_minus, tau_plus) [rad] (``sides``:
    only these of the two directions, in this order, -1.0 for tau_minus and 1.0 for tau_plus).

    tau_plus > 0 (tau_minus < 0) is the rotation from nominal at which the first pair touches, the root of
    max_j delta_j(tau) = 0; 0 where a pair already touches or interferes at nominal; +-``limit`` (default pi/z1)
    where none touches within it.  Each side starts from the least rotation at which a pair's convex bound
    delta_j(0) - (X x n)_j tau + (R_p + e) tau^2/2 reaches 0 (the bound of :meth:`ContactModel.set_window`, from
    |d^2 delta/d tau^2| <= |X| for a fixed normal: close below the first touch), doubled from there until a pair
    touches (once or twice), then the root to 1e-15 rad (:func:`gearcalc.roots.find_root`); where the start already
    touches (a profile's curvature turns the normal), the root is found in [0, start].  Before 2026-11-27 the
    doubling started at 1e-12 rad: ~30 more contact evaluations per side, the same roots to 1e-15 rad.  The
    backlash is min over theta of tau_plus - tau_minus (:func:`backlash`).
    """
    pose = model.pose(theta)
    n = pose.theta.size
    limit = limit or math.pi / model.g.z1
    R = model.g.R_p + model.g.e

    def hmax(t, p=pose):
        return np.max(model.contacts(p, t).delta, axis=(0, 1))

    ct0 = model.contacts(pose, np.zeros(n))
    h0 = np.max(ct0.delta, axis=(0, 1))
    out = []
    for direction in sides:
        # pair j's bound delta0 - a t + R t^2/2 (a = direction (X x n), t = |tau|) first reaches 0 at
        # t_j = (a + S)/R = -2 delta0/(S - a), S = sqrt(a^2 - 2 R delta0) > |a| (delta0 < 0), the form without
        # cancellation for the sign of a
        a = direction * ct0.arm
        with np.errstate(invalid="ignore", divide="ignore"):
            S = np.sqrt(a * a - 2.0 * R * ct0.delta)
            t_j = np.where(ct0.delta < 0.0, np.where(a >= 0.0, (a + S) / R, -2.0 * ct0.delta / (S - a)), 0.0)
        start = np.minimum(np.maximum(np.min(np.where(np.isfinite(t_j), t_j, limit), axis=(0, 1)), 1e-15), limit)
        lo, hi = np.zeros(n), np.zeros(n)
        open_ = h0 < 0.0
        prev = np.zeros(n)                     # a touch at the start: the root lies in [0, start]
        t = start.copy()
        while np.any(open_):
            idx = np.flatnonzero(open_)
            found = hmax(direction * t[idx], _sub_pose(pose, idx)) >= 0.0
            lo[idx] = np.where(found, prev[idx], lo[idx])
            hi[idx] = np.where(found, t[idx], hi[idx])
            done = found | (t[idx] >= limit)
            prev[idx] = np.where(found, prev[idx], t[idx])
            open_[idx[done]] = False
            t[idx] = np.where(done, t[idx], np.minimum(2.0 * t[idx], limit))
        miss = (h0 < 0.0) & (hi == 0.0)                  # no pair touches within the limit
        good = (h0 < 0.0) & ~miss
        root = np.zeros(n)
        if np.any(good):
            idx = np.flatnonzero(good)
            sub = _sub_pose(pose, idx)
            res = find_root(lambda x, sub=sub, d=direction: hmax(d * x, sub), lo[idx], hi[idx], xtol=1e-15)
            root[idx] = res.root
        root = np.where(miss, limit, root)
        out.append(direction * root)
    return tuple(out)


BACKLASH_ZOOM = 33
"""Crank angles of each zoom of :func:`backlash`'s search for the least play (each shrinks the bracket 16x)."""


def backlash(model: ContactModel, n_scan: int = 129) -> float:
    r"""The satellite's angular play at no load, both flanks [rad] (pins.md §5.3).

    .. math::

        j = \min_\theta |\tau_-(\theta)| + \min_\theta \tau_+(\theta)

    For each flank, the least rotation over the cycle from the nominal position to the first contact
    (:func:`free_play`), summed over the two flanks: 0 for an unmodified cycloid and for the
    zero-backlash tooth circle (it touches the pins' paths), positive with clearance.  Sampled on
    ``n_scan`` crank angles of one period; each least value is then refined by zooming: ``BACKLASH_ZOOM`` angles
    across the two scan intervals around the least sample, the two intervals around the least of those next (each
    zoom one vectorised :func:`free_play` of that flank), until the least sample's neighbours exceed it by at most
    1e-12 of it (the play is a minimum over the pins of smooth functions of theta: the least value in the bracket
    then lies within that of the sample) or the bracket is below 1e-9 T_p.

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
    scan = free_play(model, theta)
    total = 0.0
    for side, direction in ((0, -1.0), (1, 1.0)):
        x, p = theta, np.abs(scan[side])
        best = float(p.min())
        while True:
            i = int(np.argmin(p))
            j, k = max(i - 1, 0), min(i + 1, x.size - 1)
            if not (x[k] - x[j] > 1e-9 * Tp and max(p[j], p[k]) - p[i] > 1e-12 * p[i] + 1e-18):
                break
            x = np.linspace(x[j], x[k], BACKLASH_ZOOM)
            p = np.abs(free_play(model, x, sides=(direction,))[0])
            best = min(best, float(p.min()))
        total += best
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
    loss_ratio, loss_ratio_err : lambda_bar and its error, the quadrature's plus the fixed point's remaining change
        (exactly 0 without friction);
    history : the loss ratios of the passes; settled : False when the passes ran out unsettled;
    locked : the mode self-locks on the way (no T_V balances T_H): a multiplier whose loss ratio reached 1, or a
        reducer that stalls (:func:`reducer_stalls`; ``stalled``).
    """

    cycle: ContactCycle
    model: ContactModel
    torque_V: float
    loss_ratio: float
    loss_ratio_err: float
    history: list
    settled: bool
    locked: bool = False
    stalled: bool = False


TRAVEL_MAX = 0.25
"""The largest travel of a pin centre relative to the satellite's nominal pose, as a share of the pin radius, that
the contact level's results are trusted for (:func:`pin_travel`; pins.md §7 "Several equilibria")."""


def pin_travel(tau, g: Cycloid) -> float:
    r"""The largest travel of a pin centre relative to the satellite's nominal (rigid conjugate) pose under the load,
    as a share of the pin radius: :math:`\max|\tau| (R_p + e)/R_b` [-] (pins.md §7).

    The contact model holds the satellite's rotation tau to be deflection-sized; a pin centre that moves by a good
    part of its radius (a profile with large free play, on few teeth) meets its tooth far from its nominal place,
    and the moment balance there can have several solutions: above :data:`TRAVEL_MAX` (0.25) the random sample's
    designs disagreed with the crank angles solved one by one by up to 10 %, below it (0.004-0.23, the paper designs
    0.004-0.042) they agreed to the reference's own error.

    Examples
    --------
    >>> g = Cycloid.from_curtate_ratio(21, 22, 3.9, 0.75, 1.95)
    >>> round(pin_travel(np.array([1e-3, -2e-3]), g) * g.R_b / (g.R_p + g.e), 12)
    0.002
    """
    return float(np.max(np.abs(tau))) * (g.R_p + g.e) / g.R_b


def deflection_sized(tau, g: Cycloid) -> bool:
    """Whether the satellite's rotation ``tau`` [rad] under the load is deflection-sized: :func:`pin_travel` at most
    :data:`TRAVEL_MAX` (else the contact level's results are flagged, pins.md §7).

    >>> g = Cycloid.from_curtate_ratio(21, 22, 3.9, 0.75, 1.95)
    >>> deflection_sized(np.array([1e-3]), g), deflection_sized(np.array([0.1]), g)
    (True, False)
    """
    return pin_travel(tau, g) <= TRAVEL_MAX


def reducer_stalls(history, torques, uT: float) -> bool:
    r"""Whether a reducer's torque fixed point has no positive T_V: the losses alone exceed the input (pins.md §7).

    With the loss L(T) = lambda(T) T of the last two passes (T_(n-1), T_n, in the units of ``uT`` = u T_H), the
    reducer's fixed point is T + L(T) = u T_H.  It stalls when L(T_n) >= u T_H at both passes and the straight line
    through the two (T, T + L) reaches u T_H at no positive T: a loss that does not vanish with the load (a
    preload: teeth that interfere with the pins), so the input cannot turn the drive.  For a loss convex in the
    torque (a preload plus a loss proportional to the load is linear) the line lies below T + L(T) for T below
    both passes, so no positive root is missed; the plain iteration would only halve T_V pass after pass.

    Examples
    --------
    >>> reducer_stalls([70.0, 7000.0], [1.0, 0.01], 10.0)      # L = 70 at both torques: 70 > u T_H = 10
    True
    >>> reducer_stalls([0.1, 0.1001], [9.0, 9.09], 10.0)       # an ordinary reducer, L ~ 0.9 << 10
    False
    """
    if len(history) < 2 or torques[-1] == torques[-2]:
        return False
    L1, L0 = history[-1] * torques[-1], history[-2] * torques[-2]
    if not (L1 >= uT and L0 >= uT):
        return False
    s = (L1 - L0) / (torques[-1] - torques[-2])
    if not (1.0 + s > 0.0):
        return False
    return (uT - L1 + s * torques[-1]) / (1.0 + s) <= 0.0


def _fixed_point_step(history, torques, uT: float, a: float):
    r"""The remaining change of the loss ratio to the torque fixed point, and the next T_V (pins.md §6(6), §7).

    The fixed point is phi(T) = T (1 + a lambda(T)) - u T_H = 0 (a = -1 multiplier, +1 reducer).  With the slope
    s = d lambda/d T from the last two passes (a secant), phi'(T) = 1 + a lambda + a s T, and the linearised
    remaining change of lambda is :math:`|s\,\phi(T_n)/\phi'(T_n)|` (never negative); the next T is the
    secant-Newton step T_n - phi/phi' (within a factor 2 of the plain step u T_H/(1 + a lambda_n)).  Without
    a slope (one pass, or equal torques), or where phi' <= 0 (no contraction: the plain iteration moves away
    from the fixed point, or there is none), the remainder is unknown (inf) and the next T is the plain step
    (None).  Near a fixed point the plain iteration's contraction is c = |s T/(1 + a lambda)| < 1 and
    phi' = (1 + a lambda)(1 - c sign) > 0.

    Examples
    --------
    >>> r, T = _fixed_point_step([0.1, 0.11], [10.0, 11.0], 10.0, 1.0)     # lambda = 0.1 + 0.01 (T - 10)
    >>> T_star = (-1.0 + math.sqrt(1.0 + 0.04 * 10.0)) / 0.02              # T (1.0 + 0.01 T) = 10
    >>> bool(abs(T - T_star) < 0.05), bool(r >= 0.0)
    (True, True)
    """
    lam, T_n = history[-1], torques[-1]
    plain = uT / (1.0 + a * lam)
    if len(history) < 2 or torques[-1] == torques[-2] or not (1.0 + a * lam > 0.0):
        return math.inf, None
    s = (history[-1] - history[-2]) / (torques[-1] - torques[-2])
    phi = T_n * (1.0 + a * lam) - uT
    dphi = 1.0 + a * lam + a * s * T_n
    if not (dphi > 0.0 and math.isfinite(s)):
        return math.inf, None
    step = T_n - phi / dphi
    return abs(s * phi / dphi), min(max(step, 0.5 * plain), 2.0 * plain)


def fixed_point_stalls(history) -> bool:
    """Whether the torque fixed point's passes stopped contracting: after four passes, the last change is not below
    half of the change two passes before (a converging secant iteration shrinks its changes far faster; a loss ratio
    that jumps with the torque, a contact that comes and goes, makes the passes wander; pins.md §7).

    Examples
    --------
    >>> fixed_point_stalls([0.1303, 0.1295, 0.1193, 0.1224]), fixed_point_stalls([0.2, 0.21, 0.2101, 0.21010001])
    (True, False)
    """
    if len(history) < 4:
        return False
    d = [abs(b - a) for a, b in zip(history[:-1], history[1:])]
    return d[-1] >= 0.5 * d[-3] > 0.0


CYCLE_N_START = 64
"""First-level crank-angle intervals of the cycle mean per period (:func:`mean_loss_ratio` in :func:`cycle_at_torque`):
with two doublings at least 256 per period, rounded up per piece, so nodes at most T_p/256 apart: as dense as the
full breakpoint scan (the least that keeps the coarse scan's check sound).  128 until 2026-11-27, when the pieces'
Richardson estimate (:func:`~gearcalc.quadrature.piece_errors`) let the first call's 256 intervals meet tol 1e-6 on
most designs: 469-483 solved angles per pass on the paper designs instead of 700-1040 (pins.md §6)."""
CYCLE_N_MIN = 1
"""First-level intervals of a piece at least (the tiny pieces of a geometric grading)."""
CYCLE_MOVE_ROOTS = True
"""Whether a later full pass of the torque fixed point moves the last pass's breakpoints (else it scans)."""
CYCLE_RELINEARISE = True
"""The passes of the torque fixed point after a full one from its nodes (:func:`relinearised_cycle`) where their
error bound allows; False: full passes only (a reference for the tests)."""
CYCLE_AT_ONCE = 2
"""Doublings solved with the first level in one call (:func:`integrate_adaptive`): the first pass's first level and
both doublings every piece gets; a later pass's first level is a quarter of the last pass's final counts, so that
grid at once."""
CYCLE_COARSE_SCAN = 64
"""Intervals of the first breakpoint scan of a design, checked on the quadrature's nodes (:func:`mean_loss_ratio`)."""
PRIOR_WIDTH_PASS = 1.0
"""First half-width of the bracket that moves a breakpoint to the next pass of the torque fixed point, in periods per
unit relative change of the torque (a grazing contact entry of the circular-arc paper designs moves by 0.2 T_p per
unit relative torque change)."""
PRIOR_WIDTH_MAX = 0.125
"""The widest bracket of a moved breakpoint, in periods."""


def cycle_at_torque(g: Cycloid, profile, law: ContactLaw, torque: float, torque_on_V: bool, multiplier: bool,
                    n_discs: int, mu_eff: float, sliding_friction: float, rolls: bool,
                    friction_in_equilibrium: bool = False, tol: float = 1e-6, passes: int = 8,
                    seed: "ContactModel | None" = None, rule: str = "trapezoid") -> TorqueCycle:
    r"""The contact cycle under the torque given on V, or on H through the torque fixed point (pins.md §4.7, §7).

    The loss ratio depends (weakly) on the torque, so with the torque given on H the torque on V is
    iterated to the fixed point

    .. math::

        T_V = \frac{u T_H}{1 - \bar\lambda(T_V)}\ \text{(multiplier)},\qquad
        T_V = \frac{u T_H}{1 + \bar\lambda(T_V)}\ \text{(reducer)}

    (at most ``passes``; one pass when the torque is on V).  The iteration starts from a coarse loss ratio
    of the candidate window's scan (64 uniform crank angles at T_V = u T_H); the second pass is the plain
    step, the later ones secant-Newton steps on phi(T_V) = T_V (1 -+ lambda) - u T_H with the slope of the
    last two passes (:func:`_fixed_point_step`).  A pass after a full one starts from that one's nodes, its
    breakpoints not moved (:func:`relinearised_cycle`), and so does each later pass while they are taken; one
    refused (a contact that comes or goes, a breakpoint that moves too far for the tolerance) is a full pass, the
    base of the next.  It stops when the linearised remaining change of lambda,
    |s phi/phi'| (never negative), is below tol/10 of lambda, or lambda did not change
    (:func:`fixed_point_settled`); that remaining change is added to the error.  When the passes run out
    (``settled`` False) or a multiplier self-locks on the way (lambda_bar >= 1: it keeps the last solution,
    ``locked``), the error holds at least the last change.  A reducer whose losses alone exceed the input at two
    passes, with no positive T_V on the line through them (:func:`reducer_stalls`: a preload), self-locks too
    (``locked`` and ``stalled``) instead of halving T_V pass after pass.

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
    seed : ContactModel, optional
        the solved other mode of the same design: its candidate window and warm starts, mirrored
        (:meth:`ContactModel.mirror`), replace the first bracketed solve.
    tol : float
        relative accuracy of the cycle mean and of the fixed point.
    rule : str
        the cycle mean's quadrature rule (:func:`mean_loss_ratio`; default the trapezoid of pins.md §6).

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
    from .. import units

    sigma = MULTIPLIER if multiplier else REDUCER
    friction = (mu_eff, sliding_friction, rolls) if friction_in_equilibrium else None
    T = float(torque)
    lam, cyc, model, T_V, history, torques = 0.0, None, None, None, [], []
    remainder = 0.0
    settled = True
    frictionless = mu_eff == 0.0 and sliding_friction == 0.0

    def coarse(model, sol):
        """lambda_bar from the window scan's uniform crank angles (no breakpoints): a coarse value."""
        loss = contact_losses(sol, g.R_b, mu_eff, sliding_friction, rolls)[0]
        return float(np.mean(loss.sum(axis=(0, 1)))) / (model.torque_sat * g.k / g.z1)

    def make(T_V):
        return ContactModel(g, profile, law, units.nm_to_nmm(T_V) / n_discs, sigma, friction)

    def settles(remainder, history, cyc):
        """The fixed point's stop: the remaining change below tol/10 of lambda, or lambda no longer changing, or, when
        the cycle mean itself did not converge (its quadrature at the cap of its angles: the tolerance is not met
        whatever the torque), below that mean's own error (more passes would refine what that error swamps)."""
        return (remainder <= max(0.1 * tol * abs(history[-1]), 1e-15) or fixed_point_settled(history[-2:], tol)
                or (not cyc.converged and remainder <= cyc.loss_ratio_err))

    def run(T_V, prev, window_only=False, n_initial=None):
        model = make(T_V)
        if prev is not None:
            model.inherit(prev)
        elif seed is not None and seed.sigma != sigma:
            model.mirror(seed)
        # the breakpoints moved from the last pass's (a nearby torque); a mode's first full pass scans (the other
        # mode's, mirrored, took three calls to move where the coarse scan takes one, pins.md §6)
        prior, width = None, 0.0
        if CYCLE_MOVE_ROOTS and prev is not None and prev.roots is not None:
            # a root moves up to 0.2 T_p per unit relative torque change (a grazing entry): a bracket of |dT/T| T_p,
            # widened where it holds no sign change (:func:`_incremental_roots`)
            prior = prev.roots
            width = max(PRIOR_WIDTH_PASS * abs(model.torque_sat / prev.torque_sat - 1.0), 1e-10)
        try:
            with np.errstate(all="ignore"):       # non-finite values are caught below, never printed
                if window_only:
                    out = coarse(model, model.set_window())
                    model.roots = None        # the first full pass scans (above)
                    return model, out
                return model, mean_loss_ratio(model, mu_eff, sliding_friction, rolls, tol=tol, n_initial=n_initial,
                                              rule=rule, prior=prior, prior_width=width, n_start=CYCLE_N_START,
                                              n_min=CYCLE_N_MIN, coarse_scan=CYCLE_COARSE_SCAN,
                                              at_once=CYCLE_AT_ONCE)
        except NoEquilibrium as exc:
            exc.torque_V = T_V
            raise

    prev = None
    if not torque_on_V and not frictionless:
        # a coarse loss ratio from the candidate-window scan (uniform angles, no breakpoints) starts the
        # fixed point close to it: two or three full passes then settle it
        prev, lam = run(g.ratio * T, None, window_only=True)
        if not (np.isfinite(lam) and lam < 1.0):
            lam = 0.0
    a = -1.0 if multiplier else 1.0          # the fixed point phi(T_V) = T_V (1 + a lambda(T_V)) - u T_H = 0
    uT = g.ratio * T
    locked = stalled = False
    T_next = None
    base = None         # (cycle, model) of the last full pass, whose nodes the next pass starts from
    for _ in range(passes):
        if torque_on_V:
            T_V = T
        elif multiplier and lam >= 1.0:
            locked = True                  # self-locking: no T_V balances T_H; keep the last solution
            break
        else:
            T_V = T_next if T_next is not None else uT / (1.0 + a * lam)
        lite = None
        if base is not None:
            # a pass from the last full pass's nodes, its breakpoints not moved (:func:`relinearised_cycle`); refused
            # (a contact comes or goes, a breakpoint moves too far for the tolerance): a full pass, the next base
            lite_model = make(T_V)
            lite_model.inherit(model)
            lite = relinearised_cycle(lite_model, base[0], base[1], tol)
            base = None if lite is None else base
            if lite is not None:
                model, cyc = lite_model, lite
        if lite is None:
            # the next pass starts its quadrature from a quarter of this one's final counts per piece (the torque
            # changes little between passes: two doublings then usually suffice)
            model, cyc = run(T_V, prev,
                             n_initial=None if cyc is None or rule != "trapezoid" else cyc.quad.n_piece // 4)
            prev = model
            if CYCLE_RELINEARISE and cyc.nodes is not None:
                base = (cyc, model)
        finite = np.all(np.isfinite(cyc.sol.force)) and np.all(np.isfinite(cyc.sol.v_t))   # forces and speeds
        if not (np.isfinite(cyc.loss_ratio) and finite):
            raise Unresolvable("non-finite contact forces or losses")
        history.append(cyc.loss_ratio)
        torques.append(T_V)
        lam = cyc.loss_ratio
        if torque_on_V or frictionless:
            remainder = 0.0
            break
        if not multiplier and reducer_stalls(history, torques, uT):
            locked = stalled = True        # the losses at no load exceed the input: keep the last solution
            break
        remainder, T_next = _fixed_point_step(history, torques, uT, a)
        if fixed_point_stalls(history):
            # lambda(T_V) jumps (a contact comes and goes with the torque): no contraction, so the secant's remainder
            # (which a wandering history can make small by chance) says nothing: not settled, whatever it is
            settled = False
            break
        if settles(remainder, history, cyc):
            break
    else:
        settled = False
    if (locked and not stalled) or not settled:
        # the passes ran out or stalled, or the multiplier locked on the way (a stalled reducer has no fixed point:
        # its loss ratio is the last pass's, with that pass's quadrature error): the remainder is not known to be
        # small; the spread of all passes (the last change at least) is in the error (never less): a loss ratio that
        # jumps with the torque takes any of those values near the torques the passes tried
        spread = max(history) - min(history) if len(history) >= 3 else 0.0
        remainder = max(remainder if math.isfinite(remainder) else 0.0, spread,
                        abs(history[-1] - history[-2]) if len(history) >= 2 else 0.0)
    # the error: the quadrature's plus the fixed point's remaining change
    E = cyc.loss_ratio_err + (remainder if math.isfinite(remainder) else 0.0)
    if frictionless:
        lam, E = 0.0, 0.0
    return TorqueCycle(cyc, model, T_V, lam, E, history, settled, locked, stalled)




# ============================================================ modes, residual, speeds, powers (pins.md §4.9, §5.5, §8)

@dataclass
class ModeCycles:
    """The torque cycles of the modes a design needs (:func:`solve_modes`).

    runs : {multiplier (bool): :class:`TorqueCycle`}; jams : {multiplier: the :class:`Jam` of a mode that jams
    with the friction forces in the balance}; requested : the requested mode's cycle (its frictionless
    balance when it jams).
    """

    runs: dict
    jams: dict
    requested: TorqueCycle


def solve_modes(g: Cycloid, profile, law: ContactLaw, torque: float, torque_on_V: bool, multiplier: bool,
                n_discs: int, mu_eff: float, sliding_friction: float, rolls: bool, consistent: bool,
                tol: float = 1e-6, rule: str = "trapezoid") -> ModeCycles:
    """The contact cycle of each mode with its own forces (friction-consistent model), or of the requested
    mode with frictionless forces (first-order), at the torque fixed point (pins.md §4.9, §5.5, §7).

    With ``consistent`` both modes are solved with the friction forces in the moment balance, the other mode
    starting from the requested one's solution; a mode that jams (:class:`Jam`) is recorded in ``jams``, and
    when it is the requested mode, its cycle is the frictionless balance's (forces, speeds and peaks).
    :class:`NoEquilibrium` (other than a jam) and :class:`Unresolvable` propagate.

    Parameters are those of :func:`cycle_at_torque`; ``multiplier``: the requested mode; ``rule``: the cycle
    mean's quadrature rule (:func:`mean_loss_ratio`).

    Returns
    -------
    ModeCycles

    References
    ----------
    .. [1] pins.md §4.9 (each mode solved on its own, jams), §5.5, §7 (the torque fixed point).
    """
    def run(mult: bool, in_equilibrium: bool, seed=None):
        return cycle_at_torque(g, profile, law, torque, torque_on_V, mult, n_discs, mu_eff, sliding_friction, rolls,
                               in_equilibrium, tol=tol, seed=seed, rule=rule)

    jams, runs = {}, {}
    for mult in ((multiplier, not multiplier) if consistent else (multiplier,)):
        seed = runs[multiplier].model if mult != multiplier and multiplier in runs else None
        try:
            runs[mult] = run(mult, consistent, seed)       # the other mode starts from the first one, mirrored
        except Jam as exc:
            jams[mult] = exc
    if multiplier in jams:
        runs[multiplier] = run(multiplier, False)
    return ModeCycles(runs, jams, runs[multiplier])


def equilibrium_residual(runs, tol: float) -> tuple[float, float]:
    """The largest equilibrium residual of the cycles' moment balances relative to the torque, and its largest
    ratio to the limit: 1/100 of ``tol`` (inner tolerances 100x tighter, pins.md §6), or 100x the round-off floor
    of the penetrations (stiff contacts: deflections of 1e-7 mm on R_p); above 1 the balance is not met
    (pins.md §5.5).  ``runs``: :class:`TorqueCycle` objects."""
    residual, excess = 0.0, 0.0
    for t in runs:
        r = np.abs(t.cycle.sol.residual) / t.model.torque_sat
        limit = np.maximum(0.01 * tol, 100.0 * t.cycle.sol.noise / t.model.torque_sat)
        residual, excess = max(residual, float(r.max())), max(excess, float(np.max(r / limit)))
    return residual, excess


@dataclass(frozen=True)
class CrankBearing:
    """The crank torque, the crank-bearing force and the contact stress of a contact cycle (:func:`crank_bearing`).

    crank_torque : T_H over the final grid, all discs summed, along the power flow [N·m] (n,);
    bearing_radial, bearing_tangential : B along the crank arm (outward) and across it, one disc [N] (n,);
    bearing_force, bearing_angle : |B| [N] and its direction from the crank arm [deg] (n,);
    crank_torque_mean, crank_torque_ripple : cycle mean and peak-to-peak of ``crank_torque`` [N·m];
    bearing_force_max, bearing_force_mean : peak and cycle mean of |B| [N];
    stress_factor : the largest F/R_eff over the loaded flank contacts [N/mm] (NaN: none);
    crest_loaded : a loaded contact sits on a crest corner (a sharp edge: no Hertz stress there).
    """

    crank_torque: np.ndarray
    bearing_radial: np.ndarray
    bearing_tangential: np.ndarray
    bearing_force: np.ndarray
    bearing_angle: np.ndarray
    crank_torque_mean: float
    crank_torque_ripple: float
    bearing_force_max: float
    bearing_force_mean: float
    stress_factor: float
    crest_loaded: bool


def effective_radius(R_b, delta, inv_D):
    r"""Reduced radius of the pin-tooth contact, R_eff [mm], from the normal's turning rate (pins.md §8).

    The normal at a contact turns about the tooth's centre of curvature, at the signed distance D = 1/inv_D from
    the pin centre (inv_D = w x n of :class:`Contacts`; D > 0 when the tooth is convex there); the tooth's radius
    of curvature is rho = D - R_b + delta (circular teeth: rho_t; a cycloid cut with the equidistant R_b + Delta
    R_b on a curve of curvature radius rho_c: rho_c - R_b - Delta R_b; a crest corner: 0), and

    .. math::

        rac{1}{R_{eff}} = rac{1}{R_b} + rac{1}{
ho},\qquad
        R_{eff} = R_b\,rac{1 - (R_b - \delta)\,inv_D}{1 + \delta\,inv_D}

    (the ideal level's R_b (1 - R_b/rho_c) when delta = Delta R_b = 0; a flat tooth, inv_D = 0: R_b).

    Parameters
    ----------
    R_b : float
        pin radius [mm].
    delta : array_like
        penetration [mm].
    inv_D : array_like
        1/D [1/mm].

    Examples
    --------
    >>> float(effective_radius(2.0, 0.0, 1.0 / (2.0 + 6.0)))    # pin 2 mm on a convex 6 mm tooth: 2*6/8
    1.5

    References
    ----------
    pins.md §8 (contact_stress_max_MPa); Johnson 1985, eq. (4.45).
    """
    return R_b * (1.0 - (R_b - delta) * inv_D) / (1.0 + delta * inv_D)


def richardson_weights(theta, pieces):
    r"""Weights w of the cycle mean sum w_i v_i / (theta_n - theta_0) over a trapezoid's final grid,
    Richardson-corrected piece by piece (pins.md §6, §8): per piece of 2N uniform intervals, T_2N + (T_2N - T_N)/3,
    T_N over every other node (Simpson's rule on the piece).  ``theta`` sorted (piece ends twice, one-sided),
    ``pieces`` each node's piece key (its midpoint, :attr:`ContactCycle.nodes`).  None when a piece has an odd count
    of intervals (not the nested grid of :func:`~gearcalc.quadrature.integrate_adaptive`): the plain trapezoid then.

    Examples
    --------
    Two pieces of 4 and 2 intervals; the cubic x^3 is integrated exactly (Simpson):

    >>> x = np.array([0.0, 0.25, 0.5, 0.75, 1.0, 1.0, 1.5, 2.0])
    >>> w = richardson_weights(x, np.array([0.5] * 5 + [1.5] * 3))
    >>> round(float(np.sum(w * x ** 3)), 12)
    4.0
    """
    order = np.lexsort((theta, pieces))
    xs, ps = theta[order], pieces[order]
    if np.any((_piece_places(ps)[1] - 1) % 2 != 0):
        return None
    out = np.empty(xs.size)
    out[order] = richardson_mean(*_nested_trapezoid_weights(xs, ps))
    return out


def crank_bearing(model: "ContactModel", sol: Solution, traction, n_discs: int, pieces=None) -> CrankBearing:
    r"""Crank torque, crank-bearing force and Hertz stress factor over a solved contact cycle (pins.md §4.9, §8).

    The crank bearing holds the satellite against the pins: B = -sum_i F_i (n_i + q_i z x n_i) (the friction
    forces q_i F_i, ``traction``, when they are in the moment balance; None: friction-free forces), in the axes of
    the crank arm u = (cos(z2 theta/z1 - tau), sin(...)) of the satellite frame, from the contacts evaluated once
    over the final grid.  The crank torque along the power flow is T_H = sigma e B_t (sigma +1 reducer, -1
    multiplier; the ideal level's sigma e B_y), summed over the discs (histories 2 pi/n_d of crank apart,
    :func:`gearcalc.pins.sum_over_discs`); its cycle mean equals the torque on H to the quadrature error.  Means are
    trapezoids over the final grid, O(h^2) in its spacing, Richardson-corrected piece by piece when ``pieces`` (each
    node's piece key, :attr:`ContactCycle.nodes`) is given (:func:`richardson_weights`, O(h^4) on smooth pieces).
    The stress factor is the largest F/R_eff (:func:`effective_radius`) of a loaded flank contact; a loaded contact
    on a crest corner is flagged instead.

    Parameters
    ----------
    model : ContactModel
        the cycle's model (its mode, gear and candidate window).
    sol : Solution
        the solved cycle over one period, sorted by theta, piece ends included.
    traction : ndarray or None
        friction forces per unit normal force, those the states were solved with (:attr:`Solution.traction`), or
        None (friction-free forces).
    n_discs : int
        n_d.
    pieces : ndarray, optional
        each node's piece key (the trapezoid's final grid, :attr:`ContactCycle.nodes`): Richardson-corrected means.

    Returns
    -------
    CrankBearing

    References
    ----------
    pins.md §4.9 (B = -sum pin forces, T_H = O1 x B), §8 (crank_torque_*, bearing_force_*, contact_stress_max_MPa,
    the detail's bearing columns), §12.7 (discs); Prudnikov, Figs 3-7 (the driving torque over time).
    """
    g = model.g
    theta, tau = sol.theta, sol.tau
    ct, pick = model.kept_contacts(sol)
    Bx, By = model.bearing_force(sol, traction, ct, pick)
    F = pick(sol.force)
    ang = (g.z2 / g.z1) * theta - tau
    ca, sa = np.cos(ang), np.sin(ang)
    B_r, B_t = Bx * ca + By * sa, -Bx * sa + By * ca
    T_H = model.sigma * g.e * B_t / 1e3                 # N·mm -> N·m, one disc
    if n_discs > 1:
        T_H = sum_over_discs(theta / g.period, T_H, disc_offsets(n_discs, g.z2), 1.0)
    B = np.hypot(B_r, B_t)
    span = theta[-1] - theta[0]

    w = None if pieces is None or span <= 0.0 else richardson_weights(theta, np.asarray(pieces, dtype=float))

    def mean(v):
        if span <= 0.0:
            return float(v[0])
        if w is not None:
            return float((w * v).sum() / span)
        return float((0.5 * (v[1:] + v[:-1]) * np.diff(theta)).sum() / span)

    loaded = F > 0.0
    crest = np.zeros(F.shape, dtype=bool) if ct.branch is None else (ct.branch >= 0) & loaded
    flank = loaded & ~crest
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = F / effective_radius(g.R_b, pick(sol.delta), ct.wx * ct.ny - ct.wy * ct.nx)
    stress = float(np.max(ratio[flank])) if np.any(flank) else math.nan
    return CrankBearing(T_H, B_r, B_t, B, np.degrees(np.arctan2(B_t, B_r)), mean(T_H), float(T_H.max() - T_H.min()),
                        float(B.max()), mean(B), stress, bool(np.any(crest)))


@dataclass
class ContactOperating:
    """Losses and speeds of a contact cycle at a crank speed (:func:`operating_values`): loss_mean, loss_peak,
    loss_max, loss_bound [W]; loss_phase [deg]; spin_abs_max, spin_min, spin_max [rpm]; sliding_speed_max
    [m/s]."""

    loss_mean: float
    loss_peak: float
    loss_max: float
    loss_phase: float
    loss_bound: float
    spin_abs_max: float
    spin_min: float
    spin_max: float
    sliding_speed_max: float


def operating_values(pk: CyclePeaks, g: Cycloid, loss_ratio: float, torque_V: float, omega_H: float,
                     mu_eff: float, sliding_friction: float, rolls: bool) -> ContactOperating:
    r"""The mean and peak losses and the pin and sliding speeds of a contact cycle at crank speed omega_H
    (pins.md §4.6, §5.6, §8): the cycle's quantities are per unit crank speed, so they scale with omega_H.

    .. math:: P_{mean} = \bar\lambda\,T_V\,\omega_H k/z_1, \qquad
              P_{bound} = \mu\,F_{max}\,v_{max}\,\omega_H

    Parameters
    ----------
    pk : CyclePeaks
        :func:`cycle_peaks` of the cycle.
    g : Cycloid
    loss_ratio : float
        lambda_bar [-].
    torque_V : float
        T_V [N·m].
    omega_H : float
        Crank speed [rad/s].
    mu_eff, sliding_friction : float
        mu_rot (rolling pins) and f [-]; the bound uses mu_eff where the pins roll, else f.
    rolls : bool

    Returns
    -------
    ContactOperating

    References
    ----------
    .. [1] pins.md §4.6 (losses), §5.6, §8 (loss_mean_W, loss_peak_W, pin_loss_bound_W, speeds).
    """
    from .. import units

    Pw = omega_H * 1e-3                                                   # W per (N·mm/s per rad/s)
    rpm = units.rad_s_to_rpm(omega_H)
    coeff = mu_eff if rolls else sliding_friction
    return ContactOperating(
        loss_mean=loss_ratio * torque_V * (omega_H * g.k / g.z1), loss_peak=pk.total * Pw, loss_max=pk.loss * Pw,
        loss_phase=math.degrees(pk.loss_phase), loss_bound=coeff * pk.force * pk.contact_speed * Pw,
        spin_abs_max=pk.spin_abs * rpm if rolls else 0.0, spin_min=pk.spin_min * rpm if rolls else 0.0,
        spin_max=pk.spin_max * rpm if rolls else 0.0,
        sliding_speed_max=(pk.slide if rolls else pk.contact_speed) * omega_H / units.MM_PER_M)


def mode_efficiencies(modes: ModeCycles, consistent: bool, torque, ratio: float, multiplier, torque_on_V):
    """The efficiencies and shaft torques of both modes from the contact cycles (pins.md §4.7, §4.9).

    Friction-consistent: each mode from its own loss ratio (a jammed mode self-locks); first-order: both from
    the requested mode's.  ``torque``, ``multiplier``, ``torque_on_V``: arrays of one operating point, as
    :func:`~gearcalc.pins.operating.efficiency_torques` takes them.

    Returns
    -------
    et_multiplier, et_reducer : EfficiencyTorques
        Of the multiplier's and the reducer's loss ratio.
    locked : dict
        {multiplier (bool): whether that mode self-locks}.
    """
    from .operating import efficiency_torques

    runs, jams, tc = modes.runs, modes.jams, modes.requested
    lam, E = tc.loss_ratio, tc.loss_ratio_err
    lam_mode = {m: (runs[m].loss_ratio, runs[m].loss_ratio_err) for m in runs if m not in jams}
    if not consistent:
        lam_mode = {True: (lam, E), False: (lam, E)}
    et_m = efficiency_torques(np.array([lam_mode.get(True, (np.inf, np.nan))[0]]),
                              np.array([lam_mode.get(True, (np.inf, np.nan))[1]]), torque, ratio, multiplier,
                              torque_on_V)
    et_r = efficiency_torques(np.array([lam_mode.get(False, (0.0, np.nan))[0]]),
                              np.array([lam_mode.get(False, (0.0, np.nan))[1]]), torque, ratio, multiplier,
                              torque_on_V)
    stalled = runs[False].stalled if False in runs and False not in jams else False
    return et_m, et_r, {True: bool(et_m.locked[0]) or True in jams, False: False in jams or stalled}
