"""KHV pin gearing, level ``contact``: the satellite's equilibrium at given crank angles (pins.md §5.1, §5.5, §5.6).

:class:`ContactModel` holds one design's gear, tooth profile, contact law, torque and mode: the candidate window of
the pins that can touch, the moment balance M(tau) = M_req over all crank angles at once by safeguarded Newton with
the analytic G_tau (warm-started from the solved neighbours, the shared bracketed root finder as the fallback), the
friction forces' directions iterated to a fixed point with friction in the balance (a crank angle where no rotation
balances the torque with them: :class:`Jam`), and the kinematics: d tau/d theta = -G_theta/G_tau, the contact-point
speeds.  :class:`~gearcalc.pins.contact_states.Solution` (the solved state per crank angle and contact, with the
helpers that take, put, merge and re-lay states) is :mod:`gearcalc.pins.contact_states`'s.  Pure physics over floats
and numpy arrays (N, mm, N·mm, rad; speeds per unit crank speed).  The cycle over these states is
:mod:`gearcalc.pins.contact_cycle`, the torque fixed point and the modes :mod:`gearcalc.pins.contact`, which
re-exports this module's public names.
"""
from __future__ import annotations

import math

import numpy as np

from ..roots import BracketError, find_root
from .contact_law import ContactLaw
from .contact_profiles import Contacts, Pose
from .contact_settings import DEFAULT_SETTINGS, ContactSettings
from .contact_states import Solution, filled, hermite, hermite_slope, put_states, relayout, sub_pose, take_states
from .forces import pin_phase
from .friction import PinFriction
from .geometry import REDUCER, Cycloid

__all__ = ["NoEquilibrium", "Jam", "Solution", "ContactModel", "EPS"]

EPS = float(np.finfo(float).eps)


class NoEquilibrium(ValueError):
    """No satellite rotation within +-pi/z1 balances the torque at some crank angle."""

    def __init__(self, theta):
        super().__init__("no contact can carry the torque")
        self.theta = theta


class Jam(NoEquilibrium):
    """With the friction forces in the moment balance, no positive contact force balances the torque at
    some crank angle although the frictionless balance has a solution: the mode jams (self-locks) there
    (pins.md §4.9, §5.5)."""


_CONTACT_FIELDS = ("delta", "nx", "ny", "arm", "xn", "switch", "branch", "wx", "wy")


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


class ContactModel:
    """The satellite of one design under one torque: pose, penetrations, moment, equilibrium, speeds.

    Parameters
    ----------
    g : the pin gear (actual pins: z1, z2, e, R_p, R_b).
    profile : a :class:`gearcalc.pins.profiles.ToothProfile` (:class:`CircularProfile`, :class:`CycloidProfile`).
    law : the contact law.
    torque_sat : T_sat, torque per satellite [N·mm], > 0.
    sigma : +1 reducer (M_req = -T_sat), -1 multiplier (M_req = +T_sat)  (pins.md §5.5).
    friction : None (frictionless forces, the first-order model) or (mu_eff, f, rolls): add the
        tangential friction forces to the moment balance (the friction-consistent model, §4.9, §5.5).
    settings : the numerical settings (:class:`gearcalc.pins.contact_settings.ContactSettings`; None: the
        defaults), ``self.settings``: the cycle functions of :mod:`gearcalc.pins.contact_cycle` read them there.

    Speed (pins.md §5.5-5.6): the equilibrium is solved at all crank angles at once by safeguarded
    Newton on G(tau) = M(tau) - M_req with the analytic G_tau (warm-started from the nearest solved
    angle, tau + d tau/d theta * d theta), falling back to the bracketed root finder; d tau/d theta =
    -G_theta/G_tau analytically; only the pins of a candidate window (those that can touch for
    |tau| <= 2 max |tau| of a first solve, :meth:`set_window`) are evaluated.
    """

    _refining = False
    """Solves for a breakpoint's refinement: stopped at ``settings.refine_newton_stop`` and ``refine_newton_small``."""

    def __init__(self, g: Cycloid, profile, law: ContactLaw, torque_sat: float, sigma: int, friction=None,
                 settings: ContactSettings | None = None):
        self.g, self.profile, self.law = g, profile, law
        self.settings = DEFAULT_SETTINGS if settings is None else settings
        self.torque_sat, self.sigma = float(torque_sat), sigma
        self.M_req = -self.torque_sat if sigma == REDUCER else self.torque_sat
        self.pins = np.arange(g.z2)[:, None]
        self.friction = None if friction is None else PinFriction(*friction)
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
        every other pair, widened by ``settings.window_margin`` scan spacings on each side (the scan's resolution in
        zeta).
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
            first = relayout(first, self.layout()[0])
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
            pad = self.settings.window_margin * g.period / n_scan
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
        <= 0 at tau: ``settings.window_margin``), nor the contacts of the window's pins that :attr:`sides` leaves out.

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
        lb, hb = ((filled(n, -np.inf), filled(n, np.inf)) if bracket is None
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
                stop = self.settings.refine_newton_stop if self._refining else self.settings.newton_stop
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
                    sub = sub_pose(sub, keep)
                    tr = None if tr is None else tr[..., keep]
                    idx, t, lb, hb = idx[keep], t[keep], lb[keep], hb[keep]
            else:
                tau[idx] = t               # the iterations ran out: not done, solved below
        failed |= ~done
        if failed.any() and bracket is not None:
            sub = sub_pose(pose, failed)
            tr = None if traction is None else traction[..., failed]
            tau[failed] = _bracket_root(lambda t: self.moment(sub, t, tr) - self.M_req, sub.theta, bracket[0][failed],
                                        bracket[1][failed], xtol)
        elif failed.any():
            tau[failed] = self._bracketed(sub_pose(pose, failed),
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
            pose_c = sub_pose(pose_c, keep)
            tr, ref_c = sub(traction, cols), None if ref is None else (sub(ref[0], cols), sub(ref[1], cols))
            tau, G, G_tau = part.tau[keep], part.residual[keep], part.g_tau[keep]
            with np.errstate(divide="ignore", invalid="ignore"):
                step = -G / G_tau
            if r == rounds or not ((G_tau < 0.0) & (np.abs(step) <= 0.5 * np.abs(tau))).all():
                break
            with np.errstate(divide="ignore", invalid="ignore"):
                part, need = self._kinematics(pose_c, tau + step, tr, ref_c, step=True)
            put_states(sol, part, cols)
        try:
            tau = self._solve(pose_c, tr, tau)
        except NoEquilibrium as exc:
            if traction is None:
                raise
            raise Jam(exc.theta) from None
        put_states(sol, self._kinematics(pose_c, tau, tr, ref_c), cols)
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
                old_g = filled(old[0].shape, np.nan)    # unknown there (inherited, mirrored): no Newton warm start
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
            herm = hermite(t, h, ta[a], dt[a], ta[b], dt[b])
            if slope:
                d_herm = hermite_slope(t, h, ta[a], dt[a], ta[b], dt[b])
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
            out = filled(lead + (C * R * n,), fill, a.dtype)
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
        the larger force (the rolling resistance), -f sign(v_t - omega_pin R_b) at the other one: the rule of
        :meth:`gearcalc.pins.friction.PinFriction.traction`.
        """
        return self.friction.traction(sol.force, sol.v_t)

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
                small = self.settings.refine_newton_small if self._refining else self.settings.newton_small
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
                _, gt, cs, fs, fps, As, _, _, _, _ = self._balance(sub_pose(pose, cols), tau[cols], sub_q, sub_ref)
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
            anew = self.solved_contacts(take_states(sol, ends))[0]
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
