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

The level is five modules, one per group of sections of the specification, and this one re-exports the others'
public names, so that the level's names stay in one place: the profiles and penetrations (the first item above,
§5.2-5.3) in :mod:`gearcalc.pins.contact_profiles`, the contact laws (§5.4) in :mod:`gearcalc.pins.contact_law`,
the equilibrium and kinematics at given crank angles (§5.1, §5.5) in :mod:`gearcalc.pins.contact_model`, one cycle
at one torque (losses, breakpoints, the cycle mean, metrics and backlash, §5.6-5.7, §6) in
:mod:`gearcalc.pins.contact_cycle`, and here the torque fixed point (§7), the modes, the equilibrium residual, the
crank bearing and the operating values (§4.9, §5.5, §8).

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

import math
from dataclasses import dataclass

import numpy as np

from ..quadrature import richardson_mean
from .contact_cycle import (ContactCycle, CycleGrid, CyclePeaks, backlash, contact_losses, cycle_peaks,
                            deflection_sized, engagement_metrics, free_play, mean_loss_ratio, pin_travel)
from .contact_interp import gk_interpolated, piece_guess, piece_keys
from .contact_law import HERTZ_EXPONENT, PALMGREN_COEFFICIENT, ContactLaw, contact_law, palmgren_line_constant
from .contact_model import EPS, ContactModel, Jam, NoEquilibrium, Solution
from .contact_profiles import (PROFILE_RULES, CircularProfile, Contacts, CycloidProfile, InadmissibleProfile, Pose,
                               circular_profile, cycloid_profile, full_tooth, tooth_centre_distance,
                               zero_backlash_tooth_circle)
from .contact_relinearise import nested_trapezoid_weights, piece_places, relinearised_cycle
from .contact_roots import BreakpointRoots, cycle_breakpoints
from .contact_settings import DEFAULT_SETTINGS, ContactSettings
from .cycle import disc_offsets, disc_sum_range, sum_over_discs
from .friction import PinFriction, peak_coefficient
from .geometry import MULTIPLIER, REDUCER, Cycloid
from .operating import SCALAR_OPS

__all__ = [
    # re-exported, the contact level's names in one place: the contact laws (:mod:`gearcalc.pins.contact_law`), the
    # profiles (:mod:`gearcalc.pins.contact_profiles`), the equilibrium (:mod:`gearcalc.pins.contact_model`) and the
    # cycle (:mod:`gearcalc.pins.contact_cycle`)
    "ContactLaw", "contact_law", "palmgren_line_constant", "PALMGREN_COEFFICIENT", "HERTZ_EXPONENT",
    "tooth_centre_distance", "zero_backlash_tooth_circle", "full_tooth", "Pose", "Contacts",
    "CircularProfile", "CycloidProfile", "InadmissibleProfile", "PROFILE_RULES", "circular_profile",
    "cycloid_profile",
    "ContactModel", "NoEquilibrium", "Jam", "Solution", "EPS",
    "contact_losses", "ContactCycle", "BreakpointRoots", "CycleGrid", "mean_loss_ratio", "relinearised_cycle",
    "cycle_breakpoints", "gk_interpolated", "piece_keys", "piece_guess", "engagement_metrics", "free_play", "backlash",
    "CyclePeaks", "cycle_peaks", "pin_travel", "deflection_sized", "ContactSettings", "DEFAULT_SETTINGS",
    # this module's: the torque fixed point and the modes
    "Unresolvable", "fixed_point_settled", "TorqueCycle", "ContactCase", "cycle_at_torque", "ModeCycles", "solve_modes",
    "mode_efficiencies", "equilibrium_residual", "CrankBearing", "crank_bearing", "effective_radius",
    "richardson_weights", "ContactOperating", "operating_values", "MULTIPLIER", "REDUCER",
]

# ============================================================ the torque fixed point (pins.md §7)

class Unresolvable(ValueError):
    """The contact level cannot resolve the geometry in floating point (non-finite forces or losses)."""


def fixed_point_settled(history, tol: float) -> bool:
    r"""Whether the torque fixed point has settled.

    The remaining error c |d_n|/(1 - c) of the last loss ratio, with the contraction c = |d_n/d_(n-1)| of the last
    two changes d, is below tol/10 of it.

    .. math:: \frac{c\,|d_n|}{1 - c} < \frac{\text{tol}}{10}\,|\lambda_n|, \qquad c = \left|\frac{d_n}{d_{n-1}}\right|,
        \quad d_n = \lambda_n - \lambda_{n-1}

    Parameters
    ----------
    history : list of float
        The loss ratio of each pass, [-].
    tol : float
        The relative tolerance, [-].

    Returns
    -------
    settled : bool
        True when the remaining error is below tol/10.

    Examples
    --------
    >>> fixed_point_settled([0.1, 0.11, 0.1101], 1e-3), fixed_point_settled([0.1, 0.2], 1e-6)
    (True, False)

    References
    ----------
    .. [1] docs/spec/pins.md §7 (the torque fixed point).
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


def reducer_stalls(history, torques, uT: float) -> bool:
    r"""Whether a reducer's torque fixed point has no positive T_V: the losses alone exceed the input (pins.md §7).

    With the loss L(T) = lambda(T) T of the last two passes (T_(n-1), T_n, in the units of ``uT`` = u T_H), the
    reducer's fixed point is T + L(T) = u T_H.  It stalls when L(T_n) >= u T_H at both passes and the straight line
    through the two (T, T + L) reaches u T_H at no positive T: a loss that does not vanish with the load (a
    preload: teeth that interfere with the pins), so the input cannot turn the drive.  For a loss convex in the
    torque (a preload plus a loss proportional to the load is linear) the line lies below T + L(T) for T below
    both passes, so no positive root is missed; the plain iteration would only halve T_V pass after pass.

    .. math:: T + L(T) = u\,T_H, \qquad L(T) = \lambda(T)\,T; \quad \text{stalls when } L(T_{n-1}), L(T_n) \ge u\,T_H
        \text{ and the secant through them has no root } T > 0

    Parameters
    ----------
    history : list of float
        The loss ratio of each pass, [-].
    torques : list of float
        T_V of each pass, in the units of ``uT``.
    uT : float
        u T_H, the input torque seen on V.

    Returns
    -------
    stalls : bool
        True when no positive T_V balances the losses.

    Examples
    --------
    >>> reducer_stalls([70.0, 7000.0], [1.0, 0.01], 10.0)      # L = 70 at both torques: 70 > u T_H = 10
    True
    >>> reducer_stalls([0.1, 0.1001], [9.0, 9.09], 10.0)       # an ordinary reducer, L ~ 0.9 << 10
    False

    References
    ----------
    .. [1] docs/spec/pins.md §7.
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
    r"""Whether the torque fixed point's passes stopped contracting.

    after four passes, the last change is not below half of the change two passes before (a converging secant
    iteration shrinks its changes far faster; a loss ratio that jumps with the torque, a contact that comes and
    goes, makes the passes wander; pins.md §7).

    .. math:: n \ge 4 \quad\text{and}\quad |d_n| \ge \tfrac12\,|d_{n-2}|, \qquad d_n = \lambda_n - \lambda_{n-1}

    Parameters
    ----------
    history : list of float
        The loss ratio of each pass, [-].

    Returns
    -------
    stalls : bool
        True when the passes wander.

    Examples
    --------
    >>> fixed_point_stalls([0.1303, 0.1295, 0.1193, 0.1224]), fixed_point_stalls([0.2, 0.21, 0.2101, 0.21010001])
    (True, False)

    References
    ----------
    .. [1] docs/spec/pins.md §7.
    """
    if len(history) < 4:
        return False
    d = [abs(b - a) for a, b in zip(history[:-1], history[1:])]
    return d[-1] >= 0.5 * d[-3] > 0.0


@dataclass(frozen=True)
class ContactCase:
    """One design's contact level at one operating point.

    The parameter object of :func:`cycle_at_torque` and :func:`solve_modes`.

    g : Cycloid, the pin gear; profile : a :class:`~gearcalc.pins.profiles.ToothProfile`; law : ContactLaw;
    n_discs : n_d, discs sharing the torque; friction : :class:`~gearcalc.pins.friction.PinFriction` (mu_eff, f,
    rolls) or that tuple; torque : T [N·m], on V when ``torque_on_V`` else on H.
    """

    g: Cycloid
    profile: object
    law: ContactLaw
    n_discs: int
    friction: PinFriction
    torque: float
    torque_on_V: bool

    def __post_init__(self):
        """Turn a plain (law, f) pair given as ``friction`` into a :class:`PinFriction`."""
        if not isinstance(self.friction, PinFriction):
            object.__setattr__(self, "friction", PinFriction(*self.friction))


def cycle_at_torque(case: ContactCase, multiplier: bool, friction_in_equilibrium: bool = False, tol: float = 1e-6,
                    passes: int = 8, seed: "ContactModel | None" = None, rule: str = "trapezoid",
                    settings: ContactSettings | None = None) -> TorqueCycle:
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
    case : ContactCase
        the gear, profile, law, discs, friction (mu_eff, f, rolls) and the torque T [N·m], on V or on H.
    multiplier : bool
        multiplier (V drives H) or reducer mode.
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
    >>> case = ContactCase(g, CycloidProfile(g, 0.0, 0.0), contact_law("linear", stiffness=1e5), 1, (0.1, 0.1, False),
    ...                    10.0, False)
    >>> tc = cycle_at_torque(case, False, tol=1e-4)
    >>> tc.settled, 0.0 < tc.loss_ratio < 1.0
    (True, True)

    References
    ----------
    .. [1] pins.md §4.7, §5.5, §7 (torque_shaft).
    """
    return _TorquePasses(case, multiplier, friction_in_equilibrium, tol, seed, rule, settings).iterate(passes)


class _TorquePasses:
    """The passes of the torque fixed point of one design in one mode (:func:`cycle_at_torque`).

    Its set-up (the case, mode, friction in the balance, tolerance, quadrature rule, settings and the cycle mean's
    grid) and the model and cycle of each pass.
    """

    def __init__(self, case: ContactCase, multiplier: bool, friction_in_equilibrium: bool, tol: float,
                 seed: "ContactModel | None", rule: str, settings: ContactSettings | None):
        from .. import units

        self.case, self.multiplier, self.tol, self.seed, self.rule = case, multiplier, tol, seed, rule
        self.nm_to_nmm = units.nm_to_nmm
        self.st = st = DEFAULT_SETTINGS if settings is None else settings
        self.sigma = MULTIPLIER if multiplier else REDUCER
        self.friction = case.friction if friction_in_equilibrium else None
        self.grid = CycleGrid(n_start=st.cycle_n_start, n_min=st.cycle_n_min, coarse_scan=st.cycle_coarse_scan,
                              at_once=st.cycle_at_once)

    def coarse(self, model, sol):
        """lambda_bar from the window scan's uniform crank angles (no breakpoints): a coarse value."""
        g, fr = self.case.g, self.case.friction
        loss = contact_losses(sol, g.R_b, fr.mu_eff, fr.sliding, fr.rolls, fr.law)[0]
        return float(np.mean(loss.sum(axis=(0, 1)))) / (model.torque_sat * g.k / g.z1)

    def make(self, T_V):
        c = self.case
        return ContactModel(c.g, c.profile, c.law, self.nm_to_nmm(T_V) / c.n_discs, self.sigma, self.friction, self.st)

    def settles(self, remainder, history, cyc):
        """The fixed point's stop.

        The remaining change below tol/10 of lambda, or lambda no longer changing, or, when the cycle mean
        itself did not converge (its quadrature at the cap of its angles: the tolerance is not met whatever the
        torque), below that mean's own error (more passes would refine what that error swamps).
        """
        tol = self.tol
        return (remainder <= max(0.1 * tol * abs(history[-1]), 1e-15) or fixed_point_settled(history[-2:], tol)
                or (not cyc.converged and remainder <= cyc.loss_ratio_err))

    def run(self, T_V, prev, window_only=False, n_initial=None):
        """A full pass at T_V.

        Its model (from the last pass's, or the other mode's seed, mirrored) and cycle mean (``window_only``:
        the coarse value of the window scan instead).
        """
        st, seed = self.st, self.seed
        model = self.make(T_V)
        if prev is not None:
            model.inherit(prev)
        elif seed is not None and seed.sigma != self.sigma:
            model.mirror(seed)
        # the breakpoints moved from the last pass's (a nearby torque); a mode's first full pass scans (the other
        # mode's, mirrored, took three calls to move where the coarse scan takes one, pins.md §6)
        prior, width = None, 0.0
        if st.cycle_move_roots and prev is not None and prev.roots is not None:
            # a root moves up to 0.2 T_p per unit relative torque change (a grazing entry): a bracket of |dT/T| T_p,
            # widened where it holds no sign change (:func:`_incremental_roots`)
            prior = prev.roots
            width = max(st.prior_width_pass * abs(model.torque_sat / prev.torque_sat - 1.0), 1e-10)
        try:
            with np.errstate(all="ignore"):       # non-finite values are caught below, never printed
                if window_only:
                    out = self.coarse(model, model.set_window())
                    model.roots = None        # the first full pass scans (above)
                    return model, out
                return model, mean_loss_ratio(model, self.case.friction, self.tol, self.grid, n_initial=n_initial,
                                              rule=self.rule, prior=prior, prior_width=width)
        except NoEquilibrium as exc:
            exc.torque_V = T_V
            raise

    def iterate(self, passes: int) -> TorqueCycle:
        """The fixed point's passes (at most ``passes``; :func:`cycle_at_torque`)."""
        case, multiplier, tol, rule = self.case, self.multiplier, self.tol, self.rule
        g, torque_on_V, fr = case.g, case.torque_on_V, case.friction
        T = float(case.torque)
        lam, cyc, model, T_V, history, torques = 0.0, None, None, None, [], []
        remainder = 0.0
        settled = True
        frictionless = fr.mu_eff == 0.0 and fr.sliding == 0.0
        prev = None
        if not torque_on_V and not frictionless:
            # a coarse loss ratio from the candidate-window scan (uniform angles, no breakpoints) starts the
            # fixed point close to it: two or three full passes then settle it
            prev, lam = self.run(g.ratio * T, None, window_only=True)
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
                # a pass from the last full pass's nodes, its breakpoints not moved (:func:`relinearised_cycle`);
                # refused (a contact comes or goes, a breakpoint moves too far for the tolerance): a full pass, the
                # next base
                lite_model = self.make(T_V)
                lite_model.inherit(model)
                lite = relinearised_cycle(lite_model, base[0], base[1], tol)
                base = None if lite is None else base
                if lite is not None:
                    model, cyc = lite_model, lite
            if lite is None:
                # the next pass starts its quadrature from a quarter of this one's final counts per piece (the torque
                # changes little between passes: two doublings then usually suffice)
                model, cyc = self.run(T_V, prev,
                                      n_initial=None if cyc is None or rule != "trapezoid" else cyc.quad.n_piece // 4)
                prev = model
                if self.st.cycle_relinearise and cyc.nodes is not None:
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
                # lambda(T_V) jumps (a contact comes and goes with the torque): no contraction, so the secant's
                # remainder (which a wandering history can make small by chance) says nothing: not settled, whatever
                settled = False
                break
            if self.settles(remainder, history, cyc):
                break
        else:
            settled = False
        E = _fixed_point_error(cyc, history, remainder, (locked and not stalled) or not settled)
        if self.friction is not None:
            from .contact_choice import friction_choice_error

            E += friction_choice_error(model, cyc)     # the friction directions' discrete choice (pins.md §6)
        if frictionless:
            lam, E = 0.0, 0.0
        return TorqueCycle(cyc, model, T_V, lam, E, history, settled, locked, stalled)


def _fixed_point_error(cyc, history, remainder: float, unsettled: bool) -> float:
    """The torque cycle's error.

    The quadrature's plus the fixed point's remaining change.  ``unsettled``: the passes ran out or stalled, or the
    multiplier locked on the way (a stalled reducer has no fixed point: its loss ratio is the last pass's, with that
    pass's quadrature error): the remainder is not known to be small; the spread of all passes (the last change at
    least) is in the error (never less): a loss ratio that jumps with the torque takes any of those values near the
    torques the passes tried.
    """
    if unsettled:
        spread = max(history) - min(history) if len(history) >= 3 else 0.0
        remainder = max(remainder if math.isfinite(remainder) else 0.0, spread,
                        abs(history[-1] - history[-2]) if len(history) >= 2 else 0.0)
    return cyc.loss_ratio_err + (remainder if math.isfinite(remainder) else 0.0)


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


def solve_modes(case: ContactCase, multiplier: bool, consistent: bool, tol: float = 1e-6, rule: str = "trapezoid",
                settings: ContactSettings | None = None) -> ModeCycles:
    """The contact cycle of each mode at the torque fixed point (pins.md §4.9, §5.5, §7).

    The contact cycle of each mode with its own forces (friction-consistent model), or of the requested mode with
    frictionless forces (first-order), at the torque fixed point (pins.md §4.9, §5.5, §7).

    With ``consistent`` both modes are solved with the friction forces in the moment balance, the other mode
    starting from the requested one's solution; a mode that jams (:class:`Jam`) is recorded in ``jams``, and
    when it is the requested mode, its cycle is the frictionless balance's (forces, speeds and peaks).
    :class:`NoEquilibrium` (other than a jam) and :class:`Unresolvable` propagate.

    Parameters are those of :func:`cycle_at_torque`; ``multiplier``: the requested mode; ``rule``: the cycle
    mean's quadrature rule (:func:`mean_loss_ratio`).

    Parameters
    ----------
    case : ContactCase
        The gear, profile, law, discs, friction and torque [N·m].
    multiplier : bool
        The requested mode.
    consistent : bool
        The friction-consistent model (both modes, friction in the balance); else first-order.
    tol : float, optional
        Relative accuracy target, [-].
    rule : str, optional
        The cycle mean's quadrature rule.
    settings : ContactSettings, optional
        The contact level's settings.

    Returns
    -------
    ModeCycles

    Examples
    --------
    >>> g = Cycloid.from_curtate_ratio(21, 22, 3.9, 0.75, 1.95)
    >>> case = ContactCase(g, CycloidProfile(g, 0.0, 0.0), contact_law("linear", stiffness=1e5), 1, (0.1, 0.1, False),
    ...                    10.0, True)
    >>> modes = solve_modes(case, True, True, tol=1e-4)
    >>> {m: round(t.loss_ratio, 4) for m, t in modes.runs.items()}, modes.jams   # multiplier True, reducer False
    ({True: 0.1536, False: 0.2028}, {})

    References
    ----------
    .. [1] pins.md §4.9 (each mode solved on its own, jams), §5.5, §7 (the torque fixed point).
    """
    def run(mult: bool, in_equilibrium: bool, seed=None):
        return cycle_at_torque(case, mult, in_equilibrium, tol=tol, seed=seed, rule=rule, settings=settings)

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
    r"""The largest equilibrium residual of the cycles' moment balances and its ratio to the limit.

    The largest equilibrium residual of the cycles' moment balances relative to the torque, and its largest ratio to
    the limit: 1/100 of ``tol`` (inner tolerances 100x tighter, pins.md §6), or 100x the round-off floor of the
    penetrations (stiff contacts: deflections of 1e-7 mm on R_p); above 1 the balance is not met (pins.md §5.5).
    ``runs``: :class:`TorqueCycle` objects.

    .. math:: r = \max \frac{|M - M_{req}|}{T_{sat}}, \qquad
        \text{excess} = \max \frac{r}{\max(\text{tol}/100,\ 100\,\varepsilon_M / T_{sat})}

    (ε_M the round-off floor of the residual, :attr:`Solution.noise`).

    Parameters
    ----------
    runs : iterable of TorqueCycle
        The solved cycles.
    tol : float
        Relative accuracy target, [-].

    Returns
    -------
    residual : float
        The largest residual relative to the torque, [-].
    excess : float
        Its largest ratio to the limit, [-] (above 1: the balance is not met).

    Examples
    --------
    >>> g = Cycloid.from_curtate_ratio(21, 22, 3.9, 0.75, 1.95)
    >>> case = ContactCase(g, CycloidProfile(g, 0.0, 0.0), contact_law("linear", stiffness=1e5), 1, (0.1, 0.1, False),
    ...                    10.0, True)
    >>> residual, excess = equilibrium_residual(solve_modes(case, True, True, tol=1e-4).runs.values(), 1e-4)
    >>> residual < 1e-12, excess < 1.0
    (True, True)

    References
    ----------
    .. [1] docs/spec/pins.md §5.5, §6.
    """
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
    crest_loaded : a loaded contact sits on a crest corner (a sharp edge: no Hertz stress there);
    mean_weights, trapezoid_weights : the cycle mean's weights over the final grid (the Richardson-corrected ones
    and the plain trapezoid's, each summing to 1; the mean of any history v is sum(w v)), or None (pins.md §8.2).
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
    mean_weights: np.ndarray | None = None
    trapezoid_weights: np.ndarray | None = None


def effective_radius(R_b, delta, inv_D):
    r"""Reduced radius of the pin-tooth contact, R_eff [mm], from the normal's turning rate (pins.md §8).

    The normal at a contact turns about the tooth's centre of curvature, at the signed distance D = 1/inv_D from
    the pin centre (inv_D = w x n of :class:`Contacts`; D > 0 when the tooth is convex there); the tooth's radius
    of curvature is rho = D - R_b + delta (circular teeth: rho_t; a cycloid cut with the equidistant R_b + Delta
    R_b on a curve of curvature radius rho_c: rho_c - R_b - Delta R_b; a crest corner: 0), and

    .. math::

        \frac{1}{R_{eff}} = \frac{1}{R_b} + \frac{1}{\rho},\qquad
        R_{eff} = R_b\,\frac{1 - (R_b - \delta)\,inv_D}{1 + \delta\,inv_D}

    (the ideal level's R_b (1 - R_b/rho_c) when delta = Delta R_b = 0; a flat tooth, inv_D = 0: R_b).

    Parameters
    ----------
    R_b : float
        pin radius [mm].
    delta : array_like
        penetration [mm].
    inv_D : array_like
        1/D [1/mm].

    Returns
    -------
    R_eff : ndarray
        Reduced radius of the contact, [mm].

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
    r"""Richardson-corrected weights of the cycle mean over a trapezoid's final grid.

    Weights w of the cycle mean sum w_i v_i / (theta_n - theta_0) over a trapezoid's final grid,
    Richardson-corrected piece by piece (pins.md §6, §8): per piece of 2N uniform intervals, T_2N + (T_2N - T_N)/3,
    T_N over every other node (Simpson's rule on the piece).  ``theta`` sorted (piece ends twice, one-sided),
    ``pieces`` each node's piece key (its midpoint, :attr:`ContactCycle.nodes`).  None when a piece has an odd count
    of intervals (not the nested grid of :func:`~gearcalc.quadrature.integrate_adaptive`): the plain trapezoid then.

    .. math:: \bar v = \frac{\sum_i w_i v_i}{\theta_n - \theta_0}, \qquad
        R_{2N} = T_{2N} + \frac{T_{2N} - T_N}{3} \ \text{per piece}

    Parameters
    ----------
    theta : ndarray
        Nodes sorted, piece ends twice (one-sided), [rad].
    pieces : ndarray
        Each node's piece key (its midpoint), [rad].

    Returns
    -------
    w : ndarray or None
        The weights, [rad]; None when a piece has an odd count of intervals.

    Examples
    --------
    Two pieces of 4 and 2 intervals; the cubic x^3 is integrated exactly (Simpson):

    >>> x = np.array([0.0, 0.25, 0.5, 0.75, 1.0, 1.0, 1.5, 2.0])
    >>> w = richardson_weights(x, np.array([0.5] * 5 + [1.5] * 3))
    >>> round(float(np.sum(w * x ** 3)), 12)
    4.0

    References
    ----------
    .. [1] W. Romberg, Vereinfachte numerische Integration, Det Kongelige Norske Videnskabers Selskab
       Forhandlinger 28 (7), 1955; docs/spec/pins.md §6, §8.
    """
    order = np.lexsort((theta, pieces))
    xs, ps = theta[order], pieces[order]
    if np.any((piece_places(ps)[1] - 1) % 2 != 0):
        return None
    out = np.empty(xs.size)
    out[order] = richardson_mean(*nested_trapezoid_weights(xs, ps))
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

    .. math:: B = -\sum_i F_i\,(n_i + q_i\,z \times n_i), \qquad T_H = \sigma\,e\,B_t, \qquad
        \text{stress factor} = \max \frac{F}{R_{eff}}

    Returns
    -------
    CrankBearing

    Examples
    --------
    Friction-free forces: the crank torque's mean is T_sat/u (u = z1/k = 21):

    >>> from gearcalc.pins import contact_cycle as cc
    >>> g = Cycloid.from_curtate_ratio(21, 22, 3.9, 0.75, 1.95)
    >>> model = ContactModel(g, CycloidProfile(g, 0.0, 0.0), contact_law("linear", stiffness=1e5), 1e4, MULTIPLIER)
    >>> cb = crank_bearing(model, cc.mean_loss_ratio(model, (0.1, 0.1, False), tol=1e-5).sol, None, 1)
    >>> round(cb.crank_torque_mean * 1e3 * 21 / 1e4, 9)
    1.0

    References
    ----------
    pins.md §4.9 (B = -sum pin forces, T_H = O1 x B), §8 (crank_torque_*, bearing_force_*, contact_stress_max_MPa,
    the detail's bearing columns), §12.7 (discs); Prudnikov, Figs 3-7 (the driving torque over time).
    """
    g = model.g
    theta, tau = sol.theta, sol.tau
    ct, pick = model.kept_contacts(sol)
    Bx, By = model.bearing_force(sol, traction, ct, pick)
    ang = (g.z2 / g.z1) * theta - tau
    ca, sa = np.cos(ang), np.sin(ang)
    B_r, B_t = Bx * ca + By * sa, -Bx * sa + By * ca
    T_H, lo, hi = _crank_torque(model, theta, B_t, n_discs)
    B = np.hypot(B_r, B_t)
    span = theta[-1] - theta[0]
    w = None if pieces is None or span <= 0.0 else richardson_weights(theta, np.asarray(pieces, dtype=float))

    def mean(v):
        if span <= 0.0:
            return float(v[0])
        if w is not None:
            return float((w * v).sum() / span)
        return float((0.5 * (v[1:] + v[:-1]) * np.diff(theta)).sum() / span)

    stress, crest = _flank_stress(g, sol, ct, pick)
    w_mean = w_trap = None
    if span > 0.0:                  # the means' weights, for the bearing's p-mean (pins.md §8.2)
        h = np.diff(theta) / span
        w_trap = np.zeros(theta.size)
        w_trap[:-1] += 0.5 * h
        w_trap[1:] += 0.5 * h
        w_mean = w_trap if w is None else w / span
    return CrankBearing(T_H, B_r, B_t, B, np.degrees(np.arctan2(B_t, B_r)), mean(T_H), hi - lo,
                        float(B.max()), mean(B), stress, crest, w_mean, w_trap)


def _crank_torque(model: "ContactModel", theta, B_t, n_discs: int):
    """(T_H [N·m] per crank angle, its least and largest value): sigma e B_t, summed over the discs.

    With n_d > 1 discs the range comes from both one-sided limits at every disc's jump (pins.md §12.7).
    """
    g = model.g
    T_H = model.sigma * g.e * B_t / 1e3                 # N·mm -> N·m, one disc
    if n_discs > 1:   # the ripple from both one-sided limits at every disc's jump (pins.md §12.7)
        lo, hi = disc_sum_range(theta / g.period, T_H, disc_offsets(n_discs, g.z2), 1.0)
        T_H = sum_over_discs(theta / g.period, T_H, disc_offsets(n_discs, g.z2), 1.0)
    else:
        lo, hi = float(T_H.min()), float(T_H.max())
    return T_H, lo, hi


def _flank_stress(g, sol: Solution, ct, pick):
    """(the largest F/R_eff of a loaded flank contact (NaN: none), whether a loaded contact is on a crest corner)."""
    F = pick(sol.force)
    loaded = F > 0.0
    crest = np.zeros(F.shape, dtype=bool) if ct.branch is None else (ct.branch >= 0) & loaded
    flank = loaded & ~crest
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = F / effective_radius(g.R_b, pick(sol.delta), ct.wx * ct.ny - ct.wy * ct.nx)
    return (float(np.max(ratio[flank])) if np.any(flank) else math.nan), bool(np.any(crest))


@dataclass
class ContactOperating:
    """Losses and speeds of a contact cycle at a crank speed (:func:`operating_values`).

    loss_mean, loss_peak, loss_max, loss_bound [W]; loss_phase [deg]; spin_abs_max, spin_min, spin_max [rpm];
    sliding_speed_max [m/s].
    """

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
    r"""The mean and peak losses and the speeds of a contact cycle at crank speed omega_H.

    The mean and peak losses and the pin and sliding speeds of a contact cycle at crank speed omega_H (pins.md §4.6,
    §5.6, §8): the cycle's quantities are per unit crank speed, so they scale with omega_H.

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

    Examples
    --------
    >>> from gearcalc.pins import contact_cycle as cc
    >>> g = Cycloid.from_curtate_ratio(21, 22, 3.9, 0.75, 1.95)
    >>> model = ContactModel(g, CycloidProfile(g, 0.0, 0.0), contact_law("linear", stiffness=1e5), 1e4, MULTIPLIER)
    >>> cyc = cc.mean_loss_ratio(model, (0.1, 0.1, False), tol=1e-5)
    >>> op = operating_values(cc.cycle_peaks(cyc, g, 1, False), g, cyc.loss_ratio, 10.0, 100.0, 0.1, 0.1, False)
    >>> bool(abs(op.loss_mean - cyc.loss_ratio * 10.0 * 100.0 / 21) < 1e-12)   # lambda_bar T_V omega_H k/z1
    True

    References
    ----------
    .. [1] pins.md §4.6 (losses), §5.6, §8 (loss_mean_W, loss_peak_W, pin_loss_bound_W, speeds).
    """
    from .. import units

    Pw = omega_H * 1e-3                                                   # W per (N·mm/s per rad/s)
    rpm = units.rad_s_to_rpm(omega_H)
    coeff = peak_coefficient(mu_eff, rolls, sliding_friction, SCALAR_OPS)
    return ContactOperating(
        loss_mean=loss_ratio * torque_V * (omega_H * g.k / g.z1), loss_peak=pk.total * Pw, loss_max=pk.loss * Pw,
        loss_phase=math.degrees(pk.loss_phase), loss_bound=coeff * pk.force * pk.contact_speed * Pw,
        spin_abs_max=pk.spin_abs * rpm if rolls else 0.0, spin_min=pk.spin_min * rpm if rolls else 0.0,
        spin_max=pk.spin_max * rpm if rolls else 0.0,
        sliding_speed_max=(pk.slide if rolls else pk.contact_speed) * omega_H / units.MM_PER_M)


def mode_efficiencies(modes: ModeCycles, consistent: bool, torque, ratio: float, multiplier, torque_on_V):
    r"""The efficiencies and shaft torques of both modes from the contact cycles (pins.md §4.7, §4.9).

    Friction-consistent: each mode from its own loss ratio (a jammed mode self-locks); first-order: both from
    the requested mode's.  ``torque``, ``multiplier``, ``torque_on_V``: arrays of one operating point, as
    :func:`~gearcalc.pins.operating.efficiency_torques` takes them.

    .. math:: \eta_{VH} = 1 - \bar\lambda_{VH}, \qquad \eta_{HV} = \frac{1}{1 + \bar\lambda_{HV}}

    Parameters
    ----------
    modes : ModeCycles
        :func:`solve_modes` of the operating point.
    consistent : bool
        The friction-consistent model.
    torque : ndarray
        The torque T, [N·m], shape (1,).
    ratio : float
        The ratio u = z1/k, [-].
    multiplier, torque_on_V : ndarray of bool
        The mode and the shaft of the torque, shape (1,).

    Returns
    -------
    et_multiplier, et_reducer : EfficiencyTorques
        Of the multiplier's and the reducer's loss ratio.
    locked : dict
        {multiplier (bool): whether that mode self-locks}.

    Examples
    --------
    >>> g = Cycloid.from_curtate_ratio(21, 22, 3.9, 0.75, 1.95)
    >>> case = ContactCase(g, CycloidProfile(g, 0.0, 0.0), contact_law("linear", stiffness=1e5), 1, (0.1, 0.1, False),
    ...                    10.0, True)
    >>> modes = solve_modes(case, True, True, tol=1e-4)
    >>> et_m, et_r, locked = mode_efficiencies(modes, True, np.array([10.0]), g.ratio, np.array([True]),
    ...                                        np.array([True]))
    >>> round(float(et_m.eta_vh[0]), 4), round(float(et_r.eta_hv[0]), 4)   # 1 - 0.1536, 1/(1 + 0.2028)
    (0.8464, 0.8314)

    References
    ----------
    .. [1] docs/spec/pins.md §4.7, §4.9.
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
