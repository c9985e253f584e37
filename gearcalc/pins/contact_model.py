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
from .contact_profiles import Pose
from .contact_settings import DEFAULT_SETTINGS, ContactSettings
from .contact_kinematics import ContactKinematics
from .contact_memory import WarmStarts
from .contact_parts import EPS, ContactCaches, ContactSetup, Jam, ModelParts, NoEquilibrium, SolverState
from .contact_states import (Solution, contact_index, filled, put_states, sub_pose)
from .contact_window import CandidateWindow
from .forces import pin_phase
from .geometry import REDUCER, Cycloid

__all__ = ["NoEquilibrium", "Jam", "Solution", "ContactModel", "EPS"]

COEFFICIENT_STOP = 1e-12
"""A speed law's coefficients are settled at a state when a pass changes none by more than this share of the largest
(pins.md §4.10: 1e-6 of the efficiencies' usual tolerance; an equilibrium is met to tol/100)."""

def _doubling_bracket(G, n: int, h0: float, limit: float):
    """Brackets of the roots of a decreasing G(tau) about tau = 0.

    Brackets of the roots of a decreasing G(tau) (n,) about tau = 0, by doubling a step from h0 on the side of
    sign(G(0)) up to ``limit``: (a, b, open), open where no sign change lies within +-limit.
    """
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
    """The roots of the moment balance G on the brackets [a, b] at crank angles theta.

    The roots of the moment balance G on the brackets [a, b] at crank angles theta (by
    :func:`gearcalc.roots.find_root`); :class:`NoEquilibrium` at the angles whose ends no longer hold a sign change:
    for a rotation far beyond a deflection the contact geometry depends on the search's path (a cycloidal pin's foot
    point can jump to another flank between evaluations), so a bracket found by one search need not hold for the
    next (pins.md §5.5, §7).
    """
    try:
        return find_root(G, a, b, xtol=xtol, rtol=0.0).root
    except BracketError as exc:
        raise NoEquilibrium(np.asarray(theta)[exc.mask]) from None


def _window_range(tau) -> tuple[float, float]:
    """The candidate window's range of tau from a scan's.

    Each end twice as far from 0, or half as near when the range does not reach 0 (:meth:`ContactModel.set_window`).
    """
    lo, hi = float(np.min(tau)), float(np.max(tau))
    return (2.0 * lo if lo < 0.0 else 0.5 * lo), (2.0 * hi if hi > 0.0 else 0.5 * hi)


class ContactModel(ModelParts, CandidateWindow, ContactKinematics, WarmStarts):
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

    Its parts (:mod:`gearcalc.pins.contact_parts`): ``setup`` (immutable: the arguments above), ``solver`` (what the
    solves change) and ``caches`` (shared by the models of one design), under the former attribute names
    (:class:`~gearcalc.pins.contact_parts.ModelParts`); its candidate window
    (:class:`~gearcalc.pins.contact_window.CandidateWindow`), geometry, moment and speeds
    (:class:`~gearcalc.pins.contact_kinematics.ContactKinematics`) and the memory of solved angles its warm starts
    interpolate (:class:`~gearcalc.pins.contact_memory.WarmStarts`) are written in their own modules.

    Speed (pins.md §5.5-5.6): the equilibrium is solved at all crank angles at once by safeguarded
    Newton on G(tau) = M(tau) - M_req with the analytic G_tau (warm-started from the nearest solved
    angle, tau + d tau/d theta * d theta), falling back to the bracketed root finder; d tau/d theta =
    -G_theta/G_tau analytically; only the pins of a candidate window (those that can touch for
    |tau| <= 2 max |tau| of a first solve, :meth:`set_window`) are evaluated.
    """

    def __init__(self, g: Cycloid, profile, law: ContactLaw, torque_sat: float, sigma: int, friction=None,
                 settings: ContactSettings | None = None):
        self.setup = ContactSetup(g, profile, law, torque_sat, sigma, friction,
                                  DEFAULT_SETTINGS if settings is None else settings)
        self.solver = SolverState()       # what the solves change (window, warm starts, located sign changes, ...)
        self.caches = ContactCaches()     # shared with the models that inherit or mirror this one
















    # -- equilibrium ------------------------------------------------------------------------------
    def solve(self, theta, xtol: float = 1e-15, traction=None, pose=None):
        """The rotation tau at crank angles theta from M(tau) = M_req.

        Bracket by doubling from 1e-9 rad, then Chandrupatla.

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
        r"""The rotation tau balancing the torque with the penetrations linearised about the nominal pose.

        tau balancing the torque with the penetrations linearised about the nominal pose (no friction), or None
        where that balance has no root within +-pi/z1: a start for the first scan's Newton (:meth:`set_window`).

        With d delta/d tau = -(X x n) (:meth:`set_window`), the balance sum F(delta_0 - (X x n) tau) (X x n) = M_req
        needs only the contacts at tau = 0: bracketed by doubling from h0 and narrowed to 1e-6 of the bracket.
        Its error is that of the linearisation, |d^2 delta/d tau^2| tau^2/2 <= (R_p + e) tau^2/2, ~1e-3 of tau at
        deflection-sized rotations: Newton on the true balance then needs about three rounds.  On the ``n_scan``
        crank angles of :meth:`_nominal`.
        """
        n = n_scan
        _, d0, arm = self._nominal(n_scan)

        def G(t):
            return (self.law.force(d0 - arm * t) * arm).sum(axis=(0, 1)) - self.M_req

        a, b, open_ = _doubling_bracket(G, n, h0, math.pi / self.g.z1)
        if open_.any():
            return None
        return find_root(G, a, b, xtol=1e-3 * float(np.abs(np.concatenate((a, b))).max()), rtol=0.0).root

    def _solve(self, pose: Pose, traction=None, guess=None, xtol: float = 1e-15, maxiter: int = 40, bracket=None):
        """The rotation tau from G(tau) = 0 at every crank angle of ``pose``: safeguarded Newton from ``guess``.

        The analytic G_tau (:meth:`_balance`); a step that leaves the bracket of sign changes met so far
        is replaced by bisection; stops at |d tau| <= xtol (pins.md §5.5).  Angles without a guess, or
        where Newton cannot proceed (G_tau >= 0 with one side unbracketed, no convergence), are solved
        by the bracketed root finder (:meth:`solve`).
        """
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
            cs = contact_index(self.profile, sides)

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
            if self.friction.varies:
                sol = self._coefficient_fixed_point(pose, fixed, sol, ref)
        else:
            sol = self._friction_fixed_point(theta, pose, ref, None if scan is None else scan[1], given)
        self._remember(1 if self.friction is not None else 0, sol)
        sol = self._full(sol, idx, sides)
        if phases:
            sol.phase, sol.zeta = self.phases(theta, sol.rows)
        return sol

    def _warm(self, pose: Pose, guess, traction, ref, rounds: int = 2) -> "Solution | None":
        """The state from the warm start ``guess`` by Newton steps, each with one balance.

        The state from the warm start ``guess`` by Newton steps, each with one balance (:meth:`_kinematics` with
        ``step``: the last step, one :meth:`_solve` would stop after, moves the state without a new balance); an
        angle whose start is farther takes a full Newton step (G_tau < 0, |s| <= |tau|/2) and is evaluated
        again, at most ``rounds`` times; the others are solved by :meth:`_solve` from there.  None without a
        guess.  At the quadrature's nodes the cubic Hermite warm start between solved neighbours
        (:func:`piece_guess`) is usually that close: one balance per node instead of two or more (pins.md §5.5).
        """
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
        """The equilibrium with the friction forces ``traction`` from the start ``tau``.

        :class:`Jam` when no rotation balances the torque with them.
        """
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
        the sliding speeds at the warm start with its interpolated d tau/d theta (:meth:`_sliding_at`: no balance).
        """
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
            if traction is not None and (np.array_equal(new, traction) or self._coefficients_settled(new, traction)):
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

    def _coefficients_settled(self, new, old) -> bool:
        """A speed law's coefficients (same directions) changed by at most COEFFICIENT_STOP of the largest: settled."""
        if not self.friction.varies or not np.array_equal(np.sign(new), np.sign(old)):
            return False
        change = float(np.max(np.abs(new - old), initial=0.0))
        return change <= COEFFICIENT_STOP * float(np.max(np.abs(new), initial=0.0))

    def _coefficient_fixed_point(self, pose: Pose, fixed, sol: Solution, ref) -> Solution:
        """A speed law with a piece's directions ``fixed``: its coefficients iterated with the state.

        The coefficients at the state's own sliding speeds and forces, to a fixed point (at most 8 passes; pins.md
        §4.10, §5.5).
        """
        traction = np.broadcast_to(fixed, sol.force.shape) if sol.traction is None else sol.traction
        for _ in range(8):
            new = self.friction.along(fixed, sol.force, sol.v_t)
            if self._coefficients_settled(new, traction):
                break
            traction = new
            sol = self._friction_solve(pose, traction, sol.tau, ref)
        return sol

    def phases(self, theta, rows=None):
        """(phase, zeta) of the pins ``rows`` (None: all) at crank angles theta (R, n).

        The load-side phase of the mode and the time phase theta - phi_j wrapped to [-pi, pi) [rad].
        """
        g = self.g
        th = np.atleast_1d(np.asarray(theta, dtype=float))[None, :]
        pins = self.pins if rows is None else rows[:, None]
        psi = pin_phase(pins, th, g.z2, REDUCER)
        zeta = -np.where(psi > math.pi, psi - 2.0 * math.pi, psi)
        return pin_phase(pins, th, g.z2, self.sigma), zeta
