"""KHV pin gearing, level ``contact``: one cycle of the contact model at one torque (pins.md §5.6, §5.7, §6, §8).

The per-contact losses (§5.6); the cycle's breakpoints (contact entries and exits, spin reversals, crest passages:
scanned, refined by Newton or secant steps, moved from pass to pass, §6); the cycle mean of the loss ratio by the
adaptive quadrature per smooth piece with its error (:func:`mean_loss_ratio`), and the torque fixed point's later
passes from the last pass's nodes (:func:`relinearised_cycle`, §6(6)); the cycle's metrics, peaks, free play and
backlash (§5.7, §8).  Pure physics over floats and numpy arrays, on the states of :mod:`gearcalc.pins.contact_model`;
:mod:`gearcalc.pins.contact` runs the torque fixed point and the modes over these cycles and re-exports the public
names.
"""
from __future__ import annotations

import dataclasses
import functools
import math
import warnings
from dataclasses import dataclass, field

import numpy as np

from ..arrays import unique_sorted
from ..quadrature import _KRONROD, QuadResult, geometric_breakpoints, integrate_adaptive
from ..roots import find_root
from .contact_model import ContactModel, NoEquilibrium
from .contact_settings import DEFAULT_SETTINGS
from .contact_states import (GEOMETRY_FIELDS, Solution, concat_states, distance_to, filled, hermite, hermite_slope,
                             merged, over_rows, relayout, same_rows, sorted_places, sub_pose, take_states)
from .cycle import disc_offsets, disc_sum_peak, sum_over_discs
from .friction import PinFriction
from .geometry import Cycloid

__all__ = ["contact_losses", "ContactCycle", "BreakpointRoots", "cycle_breakpoints", "CycleGrid", "mean_loss_ratio",
           "relinearised_cycle", "gk_interpolated", "piece_keys", "piece_guess", "engagement_metrics", "CyclePeaks",
           "cycle_peaks", "free_play", "backlash", "pin_travel", "deflection_sized"]


# ============================================================ losses (pins.md §5.6)

def contact_losses(sol: Solution, R_b: float, mu_eff: float, sliding_friction: float, rolls: bool):
    """Per-contact loss per unit crank speed and the pin spin (pins.md §5.6, §4.6): the rolling-pin rule of
    :meth:`gearcalc.pins.friction.PinFriction.losses`.

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
    return PinFriction(mu_eff, sliding_friction, rolls).losses(sol.force, sol.v_t, R_b)


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
    densest scan (``settings.scan_max`` intervals; not scanned denser where the satellite turns beyond a deflection,
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
        switch, relative = PinFriction.sign_components(force, v_t, loaded)
        parts.append(switch.reshape(-1, n))
        parts.append(relative.reshape(-1, n))
    values = np.concatenate(parts)
    slopes.append(filled((values.shape[0] - slopes[0].shape[0], n), np.nan))
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
        x0, steps = _smooth_side_start(x, v, dv, comp, idx, xtol, Tp, model.settings.smooth_start_curvature_margin)

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
        stops = RootStops(xtol, jump_xtol=1e-3 * tol * Tp, step_tol=model.settings.root_step * Tp,
                          sections=model.settings.sections)
        roots = _refine_sign_changes(h, (x[idx], x[idx + 1], v[comp, idx], v[comp, idx + 1]), stops, x0=x0,
                                     bent_above=True, step_tols=steps)
    else:
        roots = np.empty(0)
    order = roots.argsort(kind="stable")
    return BreakpointRoots(roots[order], (comp < n_delta)[order], not checked, state.seen)




def _smooth_side_start(x, v, dv, comp, idx, xtol: float, Tp: float, margin: float):
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
    C s^2 = ``margin`` ``xtol`` (``settings.smooth_start_curvature_margin``: ~1e-7 T_p, against
    ``settings.root_step`` = 1e-9 T_p), and
    the first point, half of it short of the cubic's root, is one step from the root: one call (pins.md §6).

    ``x`` (m + 1,): the scan's crank angles; ``v``, ``dv`` (c, m + 1): the components and their slopes there (NaN:
    unknown); ``comp``, ``idx``: the sign changes, between x[idx] and x[idx + 1] of component comp; ``xtol``: the
    breakpoints' tolerance; ``Tp``: the period.  Returns (first points, step tolerances), NaN where not taken.

    Examples
    --------
    >>> x = np.linspace(0.0, 1.0, 5)
    >>> f = lambda t: np.sin(3.0 * t) - 0.8                # one root at arcsin(0.8)/3 = 0.30910
    >>> v, dv = f(x)[None], (3.0 * np.cos(3.0 * x))[None]
    >>> start, step = _smooth_side_start(x, v, dv, np.array([0]), np.array([1]), 1e-12, 1.0, 1e-2)
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
            r = r - hermite(t, H, fo, so, fn, sn) / hermite_slope(t, H, fo, so, fn, sn)
        # the cubic's curvature at its root, |p''/2p'|, at least 1/T_p
        t = (r - xo) / H
        dp = hermite_slope(t, H, fo, so, fn, sn)
        d2p = ((12.0 * t - 6.0) * (fo - fn) / H + (6.0 * t - 4.0) * so + (6.0 * t - 2.0) * sn) / H
        C = np.maximum(np.abs(d2p / (2.0 * dp)), 1.0 / Tp)
        step = np.sqrt(margin * xtol / C)
        # the far end's penetration, bent by the contact's own force, lies below the cubic's (the smooth extension:
        # the state without that force, which turns the satellite farther): else the bracket holds other sign changes
        # (a crest corner, another root) and the scan's linear start is kept
        f_far = v[comp, np.where(lower, idx + 1, idx)]
        t = (x[np.where(lower, idx + 1, idx)] - xo) / H
        p_far = hermite(t, H, fo, so, fn, sn)
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

    stops = RootStops(xtol, jump_xtol=jtol, step_tol=model.settings.root_step * Tp, sections=model.settings.sections)
    roots = _refine_sign_changes(h, tuple(np.concatenate(u) for u in (lo, hi, flo, fhi)), stops, bent_above=True)
    # one root found from two overlapping brackets: the same component within the refinement's tolerance
    order = np.lexsort((roots, comp))
    comp, roots = comp[order], roots[order]
    dup = np.concatenate(([False], (comp[1:] == comp[:-1]) & (np.diff(roots) <= 2.0 * jtol + 4.0 * xtol)))
    comp, roots = comp[~dup], roots[~dup]
    if roots.size != r0.size:
        return None
    order = roots.argsort(kind="stable")
    return BreakpointRoots(roots[order], (comp < n_delta)[order], False, state.seen)




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
                extra.append(geometric_breakpoints(edges[i], edges[i - 1], width,
                                                   ratio=model.settings.hertz_grading_ratio))
            if i + 1 < edges.size:
                extra.append(geometric_breakpoints(edges[i], edges[i + 1], width,
                                                   ratio=model.settings.hertz_grading_ratio))
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




@dataclass(frozen=True)
class RootStops:
    """Where :func:`_refine_sign_changes` stops (its parameter object): ``xtol`` the location tolerance of a root;
    ``jump_xtol`` (default ``xtol``) of a jump; ``step_tol`` (default ``xtol``) a Newton or secant step below which a
    bracket stops at the stepped point; ``maxiter`` calls at most; a bracket that Newton or the secant cannot narrow
    is cut into ``sections`` parts per call (``settings.sections``)."""

    xtol: float
    jump_xtol: float | None = None
    step_tol: float | None = None
    maxiter: int = 100
    sections: int = DEFAULT_SETTINGS.sections


def _refine_sign_changes(h, brackets, stops: RootStops, x0=None, bent_above: bool = False, step_tols=None):
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
    >>> brackets = ([0.0, 0.0], [1.0, 1.0], [-0.3, -1.0], [0.7, 1.0])      # a, b, h(a), h(b)
    >>> r = _refine_sign_changes(f, brackets, RootStops(1e-12, jump_xtol=1e-9))
    >>> bool(abs(r[0] - 0.3) < 1e-12), bool(abs(r[1] - 0.7) < 1e-9)
    (True, True)
    """
    a, b, fa, fb = brackets
    xtol, jump_xtol, step_tol, maxiter, sections = (stops.xtol, stops.jump_xtol, stops.step_tol, stops.maxiter,
                                                    stops.sections)
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




@dataclass(frozen=True)
class CycleGrid:
    """The crank-angle grids of a cycle mean (:func:`mean_loss_ratio`, pins.md §6): its parameter object.

    n_max : cap on crank-angle intervals (2^12, pins.md §6); n_start : first-level intervals per period; n_scan :
    intervals of the full breakpoint scan; n_min : the least intervals of a piece at the first level
    (:func:`integrate_adaptive`); coarse_scan : without a prior, scan on this many intervals instead of ``n_scan``,
    with the check of the nodes (and the full scan where it fails; the nodes must then be at least as dense as the
    full scan: ``n_start`` >= n_scan/4 with two doublings); at_once : the first level's doublings solved with it in
    one call (:func:`integrate_adaptive`); prefilter : the candidate window (False: every pin at every angle).
    """

    n_max: int = 2 ** 12
    n_start: int = 128
    n_scan: int = 256
    n_min: int = 2
    coarse_scan: int | None = None
    at_once: int = 0
    prefilter: bool = True


def mean_loss_ratio(model: ContactModel, friction, tol: float = 1e-6, grid: CycleGrid | None = None,
                    n_initial=None, rule: str = "trapezoid", prior: "BreakpointRoots | None" = None,
                    prior_width: float = 1e-2) -> ContactCycle:
    """Cycle mean of lambda(theta) = sum P_j/(T_sat omega_H k/z1) over one period, with an honest error (the
    quadrature's, :func:`~gearcalc.quadrature.piece_errors`, at least ``settings.inner_share`` tol |lambda_bar|).

    Every node is an equilibrium solve; the solved states of all nodes are kept (the final grid) for
    the summary and the detail tables (pins.md §5.6, §6).

    Parameters
    ----------
    model : the contact model (design and torque).
    friction : :class:`~gearcalc.pins.friction.PinFriction` or its tuple (mu_eff, f, rolls): mu_eff f (fixed pins or
        pins that cannot roll) or mu_rot (rolling pins), f for the second contact of a rolling pin [-], the pins
        roll.
    tol : relative accuracy target.
    grid : the crank-angle grids (:class:`CycleGrid`; None: its defaults).
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
    ``grid.coarse_scan`` checks a coarse scan the same way (:class:`CycleGrid`); ``grid.at_once`` solves the first
    level's doublings in one call, as with ``n_initial`` from the last pass, whose final grid the first call then
    solves at once.
    """
    grid = CycleGrid() if grid is None else grid
    friction = friction if isinstance(friction, PinFriction) else PinFriction(*friction)
    mu_eff, sliding_friction, rolls = friction.mu_eff, friction.sliding, friction.rolls
    n_max, n_start, n_scan, n_min = grid.n_max, grid.n_start, grid.n_scan, grid.n_min
    coarse_scan, at_once, prefilter = grid.coarse_scan, grid.at_once, grid.prefilter
    full = dataclasses.replace(grid, coarse_scan=None, at_once=0)      # a recomputation's grid
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
            col, known = _interior_states(found, new, g.period, model.settings.interior_margin)
            parts = []
            if (col >= 0).any():
                rs = take_states(known, col[col >= 0])
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
        found = _incremental_roots(model, prior, prior_width * g.period, tol, rolls,
                                   model.settings.prior_width_max * g.period)
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
    solved = concat_states(cache)
    dense = gk_interpolated(solved, q, rule, model.settings.dense_per_period) if rule != "trapezoid" else None
    # the check of the moved or coarse roots covers the interpolated states too: as dense as the trapezoid's nodes
    # (every third interpolated state: 341 per period, as dense as the trapezoid's nodes, pins.md §6)
    checked = (cache, mids) if dense is None else (cache + [take_states(dense[0], slice(None, None, 3))],
                                                   mids + [dense[1][::3]])
    # the moved or coarse roots: every sign; the full scan's: a sliding speed that dithers about 0 (below 1e-3 of its
    # largest) where the friction forces flip does not count (its losses are as small)
    held = _pieces_hold(checked, ref_sols, edges, rolls, tol, g.period,
                        floor=model.settings.hold_floor if found.scanned else 0.0)
    if not held and not found.scanned:
        # a sign change the moved roots do not hold: the full scan (pins.md §6)
        return mean_loss_ratio(model, friction, tol, full, n_initial, rule)
    if not held and n_scan < model.settings.scan_max and deflection_sized(solved.tau, g, model.settings.travel_max):
        # nor the full scan's: a contact or a sliding direction that changes twice between its angles, a 4x denser
        # one (pins.md §6), also for the later passes of this design; not where the satellite turns beyond a
        # deflection (:func:`deflection_sized`): that cycle is flagged whatever the scan (its balance can have several
        # solutions, pins.md §7), and at its cap of angles each denser scan cost seconds a pass
        model.scan_n = 4 * n_scan
        return mean_loss_ratio(model, friction, tol, dataclasses.replace(full, n_scan=4 * n_scan), n_initial, rule)
    n_solved = solved.theta.size
    sol = solved if dense is None else concat_states([solved, dense[0]])
    sol.phase, sol.zeta = model.phases(sol.theta, sol.rows)
    if not model.window_holds(sol.tau, sol.theta):
        model.window = None        # the window's tau bound does not hold: every pin, every angle
        return mean_loss_ratio(model, friction, tol, dataclasses.replace(full, prefilter=False), n_initial, rule, None,
                               prior_width)
    model.roots = found
    nodes = None
    if dense is None:
        # the nodes' piece sets and midpoints in the final grid's order (:func:`concat_states`), for the next torque
        # pass from these nodes (:func:`relinearised_cycle`)
        places = sorted_places([c.theta for c in cache])

        def cat(parts):
            return None if parts[0] is None else merged(parts, places, parts[0].ndim - 1)

        nodes = ((cat([t[0] for t in sets]), cat([t[1] for t in sets]), cat([t[2] for t in sets])),
                 cat(mids), ref_sols, rows)
    # the states' equilibria are met to 1/100 of the tolerance (:func:`equilibrium_residual`): no error below that
    err = max(float(q.err[0]), model.settings.inner_share * tol * abs(float(q.value[0])))
    return ContactCycle(float(q.value[0]), err, q.converged, n_solved, q, sol, edges, found,
                        (g.R_b, mu_eff, sliding_friction, rolls, scale), nodes, held)




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
    (``settings.relinearise_margin``); the integrand's two sides differ over the strip by at most the jump J at r plus
    each
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
    ``cyc``'s own check, ``settings.hold_floor`` where its roots are the full scan's), the window's tau range
    does not hold or its pins are not the last pass's (:meth:`ContactModel.layout`: a window recomputed for a wider
    tau range), a breakpoint's component is not found, or the quadrature's error and E_s exceed
    ``settings.relinearise_share`` of tol lambda_bar (a breakpoint that moves far, or a loss that jumps there: rolling
    pins'
    lead switch, flipping friction forces).

    Examples
    --------
    >>> from gearcalc.pins.contact import MULTIPLIER, REDUCER, CycloidProfile, contact_law
    >>> g = Cycloid.from_curtate_ratio(21, 22, 3.9, 0.75, 1.95)
    >>> law = contact_law("linear", stiffness=1e5)
    >>> a = ContactModel(g, CycloidProfile(g, 0.0, 0.0), law, 1e4, MULTIPLIER)
    >>> first = mean_loss_ratio(a, (0.1, 0.1, False), tol=1e-5)
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
    if not same_rows(rows2, rows):
        # the window recomputed for a wider tau range (:meth:`ContactModel.inherit`): the last pass's states and sets
        # over this model's rows (a pin they do not hold: out of reach at every node, inactive); a pin left out must
        # carry no force in them (the window's bound: it cannot touch at this torque either)
        src, dst = (np.arange(g.z2) if r is None else r for r in (rows, rows2))
        if (sol1.force[:, ~np.isin(src, dst)] > 0.0).any():
            return None
        sets = tuple(None if a is None else over_rows(a, src, dst, fill) for a, fill in zip(sets, (False, -1, 0.0)))
        ref_sols = [relayout(r, rows2, g.z2) for r in ref_sols]
        sol1, rows = relayout(sol1, rows2, g.z2), rows2
    Tp, x = g.period, cyc.sol.theta
    scale2 = model.torque_sat * g.k / g.z1
    # the final grid piece by piece (a piece end is a node of each of its two pieces); pieces follow each other in
    # theta, so the order by (piece, theta) is sorted in theta too
    edges = cyc.breakpoints
    p = np.minimum(np.maximum(edges.searchsorted(node_mid) - 1, 0), edges.size - 2)
    order = np.lexsort((x, p))
    xs, ps = x[order], p[order]
    keep, lo_s, hi_s, t_s = _strided(xs, ps, model.settings.relinearise_stride if stride is None else stride)
    kept = order[keep]                        # the nodes solved at the new torque (both ends of every piece)
    with np.errstate(divide="ignore", invalid="ignore"):
        step = (model.M_req - prev.M_req) / sol1.g_tau[kept]
        guess = np.where((sol1.g_tau[kept] < 0.0) & np.isfinite(step), sol1.tau[kept] + step, np.nan)
        try:
            # the last pass's pose of its nodes (solved in one call, in this order), at the kept ones: its foot points
            # start this torque's
            last, same_sides = prev.last_pose, (prev.sides is None) == (model.sides is None) and (
                prev.sides is None or np.array_equal(prev.sides, model.sides))
            reuse = sub_pose(last, kept) if last is not None and same_sides and last.theta.shape == x.shape \
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
    w, w2 = nested_trapezoid_weights(xs[keep], pk)
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
        v1 = _components(take_states(sol1, nb), rolls)[0]
        v2n = _components(take_states(s2, nb), rolls)[0]
        v2, dv2, n_delta = _components(take_states(s2, ends), rolls)
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
        move = model.settings.relinearise_margin * d
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
                    contact_losses(take_states(s2, ends), R_b, mu_eff, f, rolls)[0].sum(axis=(0, 1))
                e_r = np.where(left == 1.0, l2[:m] - l2[m:], l2[m:] - l2[:m])     # touching minus the other
                grown = np.where(grows, e_r * d / (1.0 + p_exp), 0.0)
                strip = np.where(grows, (model.settings.relinearise_margin ** (1.0 + p_exp) - 1.0) * np.abs(grown),
                                 strip)
                lam2 += float(grown.sum()) / Tp / scale2
        if not (np.isfinite(strip).all() and math.isfinite(lam2)):
            return None
        E_s = float(strip.sum()) / Tp / scale2
    if not (E_q + E_s <= model.settings.relinearise_share * tol * abs(lam2)
            and _pieces_hold(([s2], [node_mid]), ref_sols, edges, rolls, tol, Tp, away=(r, width),
                             floor=model.settings.hold_floor if cyc.roots.scanned else 0.0)):
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


def piece_places(ps):
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
    start, count, piece, j = piece_places(ps)
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


def nested_trapezoid_weights(xs, ps):
    """The composite trapezoid's weights of nodes sorted by piece, then theta (``ps`` their pieces), piece by piece,
    over all nodes and over every other node of each piece (its ends kept): (w, w_half), the levels N and N/2 of a
    piece of N intervals (an odd N: the half level's last interval is the one that is left)."""
    _, count, piece, j = piece_places(ps)
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
        geometry = fl.name in GEOMETRY_FIELDS
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




def _interior_states(found: BreakpointRoots, mids, period: float, margin: float):
    """For the pieces with midpoints ``mids``: the column of a state solved while the sign changes ``found`` were
    located (``found.seen``) that lies in the same stretch between two of them as the midpoint, farther than
    ``settings.interior_margin`` T_p from both (the nearest such to the midpoint), else -1; and those states
    concatenated.
    The components keep their signs over the stretch, so that state has the piece's active set, branches and
    friction directions, as its midpoint's would (pins.md §6; a sign change the located ones missed is caught on the
    nodes, :func:`_pieces_hold`)."""
    seen = [s for s in found.seen if s.theta.size]
    if not seen:
        return np.full(mids.size, -1), None
    known = concat_states(seen)
    th = known.theta
    r = found.roots
    margin = margin * period
    k = r.searchsorted(mids)
    if r.size:
        lo = np.where(k > 0, r[np.maximum(k - 1, 0)], -np.inf)[:, None]
        hi = np.where(k < r.size, r[np.minimum(k, r.size - 1)], np.inf)[:, None]
    else:  # no sign change located (e.g. a torque so small the contacts never change sets): one stretch
        lo, hi = np.full((mids.size, 1), -np.inf), np.full((mids.size, 1), np.inf)
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
        herm = hermite((x - xa) / h, h, tau[a], dtau[a], tau[b], dtau[b])
    return np.where(same & (h > 0.0) & np.isfinite(herm), herm, np.nan)


def _pieces_hold(nodes, ref_sols, edges, rolls: bool, tol: float, period: float, away=None,
                 floor: float = 0.0) -> bool:
    """Whether every evaluated node lies on its piece's side of every sign change: no component has the
    opposite sign of the piece's midpoint at a node farther than 2e-3 tol T_p from the piece's ends (where a
    located jump may lie within 1e-3 tol T_p of its place, :func:`_scan_roots`).  A stricter test than the full
    scan's (the nodes are denser than its 256 intervals), used for the incrementally moved breakpoints.
    ``away`` = (points, width): nor at a node within ``width`` of a point (sorted; the strips a breakpoint may have
    moved through since the nodes were placed, :func:`relinearised_cycle`).  ``floor``: a contradiction counts only
    where the node's value and the piece's both exceed ``floor`` times the component's largest |value| over the nodes
    (a sliding speed that dithers about 0 where the friction forces flip, with friction in the balance).  ``nodes``:
    (cache, mids), the nodes' states and their pieces' midpoints."""
    cache, mids = nodes
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
            inner &= distance_to(away[0], x) > away[1]
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


# the moved breakpoints' widest bracket (a tunable of the torque fixed point, pins.md §7)


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
    >>> from gearcalc.pins.contact import MULTIPLIER, REDUCER, CycloidProfile, contact_law
    >>> g = Cycloid.from_curtate_ratio(21, 22, 3.9, 0.75, 1.95)
    >>> m = ContactModel(g, CycloidProfile(g, 0.0, 0.0), contact_law("linear", stiffness=1e5), 1e4, REDUCER)
    >>> pk = cycle_peaks(mean_loss_ratio(m, (0.1, 0.1, False), tol=1e-4), g, 1, False)
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
            found = hmax(direction * t[idx], sub_pose(pose, idx)) >= 0.0
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
            sub = sub_pose(pose, idx)
            res = find_root(lambda x, sub=sub, d=direction: hmax(d * x, sub), lo[idx], hi[idx], xtol=1e-15)
            root[idx] = res.root
        root = np.where(miss, limit, root)
        out.append(direction * root)
    return tuple(out)




def backlash(model: ContactModel, n_scan: int = 129) -> float:
    r"""The satellite's angular play at no load, both flanks [rad] (pins.md §5.3).

    .. math::

        j = \min_\theta |\tau_-(\theta)| + \min_\theta \tau_+(\theta)

    For each flank, the least rotation over the cycle from the nominal position to the first contact
    (:func:`free_play`), summed over the two flanks: 0 for an unmodified cycloid and for the
    zero-backlash tooth circle (it touches the pins' paths), positive with clearance.  Sampled on
    ``n_scan`` crank angles of one period; each least value is then refined by zooming: ``settings.backlash_zoom``
    angles
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
    >>> from gearcalc.pins.contact import MULTIPLIER, REDUCER, CycloidProfile, contact_law
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
            x = np.linspace(x[j], x[k], model.settings.backlash_zoom)
            p = np.abs(free_play(model, x, sides=(direction,))[0])
            best = min(best, float(p.min()))
        total += best
    return total


# ============================================================ deflection-sized rotations (pins.md §7)



def pin_travel(tau, g: Cycloid) -> float:
    r"""The largest travel of a pin centre relative to the satellite's nominal (rigid conjugate) pose under the load,
    as a share of the pin radius: :math:`\max|\tau| (R_p + e)/R_b` [-] (pins.md §7).

    The contact model holds the satellite's rotation tau to be deflection-sized; a pin centre that moves by a good
    part of its radius (a profile with large free play, on few teeth) meets its tooth far from its nominal place,
    and the moment balance there can have several solutions: above ``settings.travel_max`` (0.25) the random sample's
    designs disagreed with the crank angles solved one by one by up to 10 %, below it (0.004-0.23, the paper designs
    0.004-0.042) they agreed to the reference's own error.

    Examples
    --------
    >>> g = Cycloid.from_curtate_ratio(21, 22, 3.9, 0.75, 1.95)
    >>> round(pin_travel(np.array([1e-3, -2e-3]), g) * g.R_b / (g.R_p + g.e), 12)
    0.002
    """
    return float(np.max(np.abs(tau))) * (g.R_p + g.e) / g.R_b


def deflection_sized(tau, g: Cycloid, travel_max: float = DEFAULT_SETTINGS.travel_max) -> bool:
    """Whether the satellite's rotation ``tau`` [rad] under the load is deflection-sized: :func:`pin_travel` at most
    ``settings.travel_max`` (else the contact level's results are flagged, pins.md §7).

    >>> g = Cycloid.from_curtate_ratio(21, 22, 3.9, 0.75, 1.95)
    >>> deflection_sized(np.array([1e-3]), g), deflection_sized(np.array([0.1]), g)
    (True, False)
    """
    return pin_travel(tau, g) <= travel_max
