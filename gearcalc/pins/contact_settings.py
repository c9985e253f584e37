"""KHV pin gearing, level ``contact``: the numerical settings of the contact level in one immutable object (issue 35).

:class:`ContactSettings` holds every tunable that steers the contact level's numerics (the equilibrium's Newton stops,
the breakpoints' refinement, the quadrature's grids, the torque fixed point's passes); each field's documentation
says what it controls and why it has its value.  The contact level's functions take a ``settings`` argument (None:
:data:`DEFAULT_SETTINGS`), and :class:`~gearcalc.pins.contact_model.ContactModel` carries the one its cycle was
solved with (``model.settings``): a test that needs other values passes
``dataclasses.replace(DEFAULT_SETTINGS, ...)`` instead of patching module constants.  The results of the shipped
designs are those of :data:`DEFAULT_SETTINGS`; ``gearcalc accuracy`` checks them.
"""
from __future__ import annotations

from dataclasses import dataclass

__all__ = ["ContactSettings", "DEFAULT_SETTINGS"]


@dataclass(frozen=True)
class ContactSettings:
    """The contact level's numerical settings (immutable; :data:`DEFAULT_SETTINGS` are the shipped ones).

    Every field is documented below; the names are the former module constants' in lower case
    (``NEWTON_STOP`` -> ``newton_stop``).
    """

    # -- the equilibrium at given crank angles (:mod:`gearcalc.pins.contact_model`)
    window_margin: int = 2
    """The candidate window's margin in time phase beyond the outermost pairs that can touch, in spacings of its scan
    (:meth:`ContactModel.set_window`): the scan's n_scan crank angles over all z2 pins sample the time phase zeta on
    a grid of T_p/n_scan (the contact geometry of a pin depends on zeta alone), so a pin between the last sample
    that can touch and the first that cannot lies within one spacing; two for safety.  (It was one pin pitch T_p,
    n_scan = 64 spacings: two pins more per angle than needed.)  The pins next to the window are checked on each
    cycle's final grid (:meth:`ContactModel.window_holds`)."""
    newton_small: float = 1e-8
    """A warm start's Newton step s is taken without a new balance (:meth:`ContactModel._kinematics` with ``step``)
    when |s| <= 1e-8 |tau| (quadratic convergence: the error is then ~s^2/tau <= 1e-16 |tau|, and the geometry, kept
    at the start, moves by (R_p + e) s ~ 1e-10 mm, far below the deflections' resolution)."""
    newton_stop: float = 1e-6
    """The satellite rotation's Newton iteration (:meth:`ContactModel._solve`) stops after a step |s| <= 1e-6 |tau|:
    its error is then C s^2 with C = |G_tautau tau/(2 G_tau)|, measured 0.05-3 on the paper designs (the ratio of
    successive relative steps), so <= ~3e-12 |tau|, the resolution of tau itself (a deflection of ~1e-3 mm out of
    positions of ~60 mm held to 1e-14 mm: ~1e-11); the kinematics then evaluate the geometry at the stepped tau.
    (1e-8 took one balance more per solve, whose step was that round-off, 3e-12 to 1e-13.)"""
    refine_newton_stop: float = 1e-11
    """``newton_stop`` and ``newton_small`` of the solves that refine a scanned penetration's sign change from the
    smooth side (:func:`_scan_roots`, :attr:`ContactModel._refining`): a root is taken from one such state's value and
    slope, so the penetration must hold to well below 1e-12 T_p times its slope (with the product's stops, a state
    next to a Hertz contact's entry warm-started from the scan came out ~1e-10 mm off; measured 2026-11-27).  An
    iteration or two more per refinement call (2-3 crank angles)."""
    refine_newton_small: float = 1e-12
    """See ``refine_newton_stop``: the ``newton_small`` of the refining solves."""

    # -- one cycle: breakpoints (:mod:`gearcalc.pins.contact_roots`), quadrature, backlash
    # (:mod:`gearcalc.pins.contact_cycle`), passes from the nodes (:mod:`gearcalc.pins.contact_relinearise`)
    smooth_start_curvature_margin: float = 1e-2
    """A refinement step from the smooth side of a scanned penetration's sign change (:func:`_smooth_side_start`) stops
    its bracket when Newton's error after it, C s^2 (C = |f''/2f'|, the larger of the scan cubic's at its root and
    1/T_p), is below this fraction of the breakpoints' tolerance (1e-12 T_p): the curvature may be 100x the
    estimate."""
    hertz_grading_ratio: float = 0.25
    """The geometric ratio of the grading toward both sides of a contact entry or exit under the Hertz law
    (:func:`_edges`, :func:`cycle_breakpoints`): each graded piece is 1/ratio times longer than the next one nearer
    the entry."""
    sections: int = 8
    """A bracket that Newton or the secant cannot narrow (a step outside it: a jump, or a root far from linear) is cut
    into sections equal parts at once (sections - 1 points in one call): 8x narrower per call instead of bisection's
    2x, at about the cost of one point (a call's cost is mostly its fixed overhead; :func:`_refine_sign_changes`)."""
    root_step: float = 1e-9
    """A breakpoint's refinement stops after a Newton or secant step below root_step T_p, at the stepped point (its
    error then ~1e-15 T_p, :func:`_refine_sign_changes`; pins.md §6)."""
    hold_floor: float = 1e-3
    """A full scan's cycle holds when no node contradicts its piece by more than hold_floor of the component's largest
    |value| (:func:`~gearcalc.pins.contact_roots.pieces_hold`): the dither of a sliding speed about 0 where the
    friction forces flip stays below 3e-4 on the band designs; the contradictions of the random sample's failing
    designs were 3.7e-3 to 0.3."""
    scan_max: int = 4096
    """The densest scan of a cycle's sign changes (:func:`mean_loss_ratio`): 256 intervals, then 4x denser while the
    quadrature's nodes contradict their pieces, up to this many; then the cycle is reported as not held."""
    dense_per_period: int = 1024
    """Interpolated crank angles per period on the contact level's final grid with a Gauss-Kronrod rule
    (:func:`gk_interpolated`), shared out over the bisected pieces in proportion to their length (at least 2 each):
    as dense as the composite trapezoid's final grid at tol 1e-6 (pins.md §6)."""
    inner_share: float = 1e-2
    """The inner tolerances' share of the target (pins.md §6, error propagation): the equilibria are met to 1/100 of
    ``tol`` (:func:`equilibrium_residual`), so a cycle mean's stated error is never below inner_share tol
    |lambda_bar| (the Richardson estimate of a very smooth cycle can be far smaller: 6e-12 relative on a stiff
    linear law)."""
    relinearise_margin: float = 1.25
    """A breakpoint's move to the next torque, taken as this many times its Newton step (:func:`relinearised_cycle`;
    the step's own error is second order in a move of ~1e-6 T_p)."""
    relinearise_stride: int = 8
    """The pass from the last pass's nodes solves every relinearise_stride-th node of each piece and its ends
    (:func:`relinearised_cycle`, :func:`_strided`); the nodes between are interpolated."""
    relinearise_share: float = 0.9
    """The largest share of the tolerance (tol lambda_bar) that the quadrature's error and the strips the breakpoints
    move through may hold together in a torque pass from the last pass's nodes (:func:`relinearised_cycle`); more: a
    full pass."""
    interior_margin: float = 1e-6
    """A state stands for a piece's sets when it lies farther than interior_margin T_p from every located sign change
    (1000x a jump's location tolerance at --tol 1e-6, :func:`_interior_states`)."""
    prior_width_max: float = 0.125
    """The widest bracket of a moved breakpoint, in periods."""
    backlash_zoom: int = 33
    """Crank angles of each zoom of :func:`backlash`'s search for the least play (each shrinks the bracket 16x)."""
    travel_max: float = 0.25
    """The largest travel of a pin centre relative to the satellite's nominal pose, as a share of the pin radius, that
    the contact level's results are trusted for (:func:`pin_travel`; pins.md §7 "Several equilibria")."""

    # -- the torque fixed point (:mod:`gearcalc.pins.contact`)
    cycle_n_start: int = 64
    """First-level crank-angle intervals of the cycle mean per period (:func:`mean_loss_ratio` in
    :func:`cycle_at_torque`): with two doublings at least 256 per period, rounded up per piece, so nodes at most
    T_p/256 apart: as dense as the full breakpoint scan (the least that keeps the coarse scan's check sound).  128
    until 2026-11-27, when the pieces' Richardson estimate (:func:`~gearcalc.quadrature.piece_errors`) let the first
    call's 256 intervals meet tol 1e-6 on most designs: 469-483 solved angles per pass on the paper designs instead
    of 700-1040 (pins.md §6)."""
    cycle_n_min: int = 1
    """First-level intervals of a piece at least (the tiny pieces of a geometric grading)."""
    cycle_move_roots: bool = True
    """Whether a later full pass of the torque fixed point moves the last pass's breakpoints (else it scans)."""
    cycle_relinearise: bool = True
    """The passes of the torque fixed point after a full one from its nodes (:func:`relinearised_cycle`) where their
    error bound allows; False: full passes only (a reference for the tests)."""
    cycle_at_once: int = 2
    """Doublings solved with the first level in one call (:func:`integrate_adaptive`): the first pass's first level and
    both doublings every piece gets; a later pass's first level is a quarter of the last pass's final counts, so
    that grid at once."""
    cycle_coarse_scan: int = 64
    """Intervals of the first breakpoint scan of a design, checked on the quadrature's nodes
    (:func:`mean_loss_ratio`)."""
    prior_width_pass: float = 1.0
    """First half-width of the bracket that moves a breakpoint to the next pass of the torque fixed point, in periods
    per unit relative change of the torque (a grazing contact entry of the circular-arc paper designs moves by 0.2
    T_p per unit relative torque change)."""

    # -- the level (:mod:`gearcalc.pins.contact_level`)
    gk_below: float = 3e-7
    """Below this --tol the contact level's cycle mean uses the Gauss-Kronrod pair ``"gk7"``, above it the composite
    trapezoid (:func:`contact_rule`)."""
    rule: str | None = None
    """The cycle mean's quadrature rule whatever the --tol (``"trapezoid"``, ``"gk7"``, ``"gk15"``,
    :func:`contact_rule`); None: by ``gk_below``.  ``gearcalc accuracy`` checks the contact level against itself with
    a rule no tolerance of its report uses (``HIGH_RULE_CONTACT``), passed here instead of patching a module."""


DEFAULT_SETTINGS = ContactSettings()
"""The shipped settings: every design, batch, sweep and ``gearcalc accuracy`` run with them."""
