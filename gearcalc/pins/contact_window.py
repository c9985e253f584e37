"""KHV pin gearing, level ``contact``: the candidate window of a contact model (pins.md §5.5).

:class:`CandidateWindow` is the part of :class:`~gearcalc.pins.contact_model.ContactModel` that chooses which pins (and
which of each pin's contacts) a solve evaluates: the shortest arc of time phase holding every pair that can touch for
rotations within twice a first scan's, widened by ``settings.window_margin`` scan spacings, checked on each cycle's
final grid, and carried to the model of the next torque (:meth:`~CandidateWindow.inherit`) or of the other mode
(:meth:`~CandidateWindow.mirror`).  Its methods read and write the model's parts
(:mod:`gearcalc.pins.contact_parts`).
"""
from __future__ import annotations


import math

import numpy as np

from .contact_parts import NoEquilibrium
from .contact_states import relayout

__all__ = ["CandidateWindow"]


def _window_range(tau) -> tuple[float, float]:
    """The candidate window's range of tau from a scan's: each end twice as far from 0, or half as near when the
    range does not reach 0 (:meth:`CandidateWindow.set_window`)."""
    lo, hi = float(np.min(tau)), float(np.max(tau))
    return (2.0 * lo if lo < 0.0 else 0.5 * lo), (2.0 * hi if hi > 0.0 else 0.5 * hi)


class CandidateWindow:
    """The candidate window of a :class:`~gearcalc.pins.contact_model.ContactModel` (a part of its class)."""

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

    def window_holds(self, tau, theta=None, prev: "CandidateWindow | None" = None) -> bool:
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

    def mirror(self, other: "CandidateWindow") -> None:
        """Start from the solved other mode of the same design: its window and warm starts mirrored.

        Without friction in the balance the reducer is the multiplier run backwards (pins.md §4.8(5),
        §5.7): tau_R(-theta) = -tau_M(theta), so the time phases zeta, the tau range and tau change
        sign and d tau/d theta keeps it; scaled by the torque ratio like :meth:`inherit`.  With friction
        this is a warm start only (the window's tau range is checked on the final grid)."""
        r = (self.torque_sat / other.torque_sat) ** (1.0 / self.law.exponent)
        self.caches, self.scan_n = other.caches, other.scan_n      # the same design
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

    def inherit(self, prev: "CandidateWindow") -> None:
        """Start from the candidate window and the solved angles of the same design at another torque.

        tau scales about as the deflection, (T/T_prev)^(1/p) for the law F ~ delta^p: the warm starts
        and the window's tau range are scaled by it (the range is checked on the final grid)."""
        r = (self.torque_sat / prev.torque_sat) ** (1.0 / self.law.exponent)
        self.caches, self.scan_n = prev.caches, prev.scan_n        # the same design
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
