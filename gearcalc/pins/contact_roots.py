"""KHV pin gearing, level ``contact``: the cycle's breakpoints, its sign changes located and refined (pins.md §6).

The components whose sign changes end the cycle integrand's smooth pieces (:func:`cycle_components`: penetrations,
tangential speeds at loaded contacts, crest passages, rolling pins' lead switches); their sign changes scanned on one
period and refined by safeguarded Newton or secant steps to 1e-12 T_p (:func:`_refine_sign_changes`, from the smooth
side of a penetration where it can, :func:`_smooth_side_start`), or moved from the last pass's roots
(:func:`_incremental_roots`); the piece ends with their geometric gradings (:func:`cycle_breakpoints`,
:func:`locate_breakpoints`); and the check that the quadrature's nodes lie on their pieces' sides of every sign change
(:func:`pieces_hold`).  Pure physics over the states of :mod:`gearcalc.pins.contact_model`; the cycle mean over the
pieces is :mod:`gearcalc.pins.contact_cycle`'s.
"""
from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field

import numpy as np

from ..arrays import unique_sorted
from ..quadrature import geometric_breakpoints
from .contact_model import ContactModel
from .contact_settings import DEFAULT_SETTINGS
from .contact_states import Solution, distance_to, filled, hermite, hermite_slope
from .friction import PinFriction

__all__ = ["cycle_components", "BreakpointRoots", "RootStops", "cycle_breakpoints", "locate_breakpoints",
           "pieces_hold"]


def cycle_components(s: Solution, rolls: bool):
    r"""The sign-change components of the cycle at the solved states ``s`` (pins.md §6).

    Their sign changes end the cycle integrand's smooth pieces: the penetrations delta_j of the candidate pins (a
    contact enters or leaves), the tangential speeds v_t at loaded contacts (a spin reversal), the distances from a
    flank's end where the profile has crests (a crest passage), and for rolling pins with two contacts the lead
    switch and the other contact's relative sliding (:meth:`PinFriction.sign_components`).  A component that is NaN
    at a crank angle has no sign there.  Over the state's rows (:attr:`Solution.rows`; the other pins are never
    candidates over the period: no contact, no sign): the states of one cycle share them.

    .. math:: c = \big(\delta_j,\ v_{t,j} [F_j > 0],\ s_j,\ \ldots\big), \qquad
        c'_\delta = \frac{d\delta_j}{d\theta}

    Parameters
    ----------
    s : Solution
        Solved states of one cycle.
    rolls : bool
        The pins roll.

    Returns
    -------
    values, slopes : ndarray
        (c, n) over the crank angles of ``s``; the slopes known for the penetrations only (NaN else).
    n_delta : int
        The penetrations' rows, which come first.

    Examples
    --------
    >>> from gearcalc.pins.contact import MULTIPLIER, ContactModel, Cycloid, CycloidProfile, contact_law
    >>> g = Cycloid.from_curtate_ratio(21, 22, 3.9, 0.75, 1.95)
    >>> model = ContactModel(g, CycloidProfile(g, 0.0, 0.0), contact_law("linear", stiffness=1e5), 1e4, MULTIPLIER)
    >>> v, dv, n_delta = cycle_components(model.state(np.array([0.0, 0.1]), phases=False), False)
    >>> v.shape[1], bool(np.isnan(dv[n_delta:]).all()), n_delta > 0
    (2, True, True)

    References
    ----------
    .. [1] docs/spec/pins.md §5.6, §6.
    """
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
    """The located sign changes of one cycle (:func:`cycle_breakpoints`).

    roots [rad] and whether each is a contact entry or exit (a penetration's), sorted by root; ``scanned``: located
    by the full scan and taken as it is (False: a coarse scan or moved roots, which the quadrature's nodes must
    confirm, :func:`mean_loss_ratio`).
    """

    roots: np.ndarray
    contact: np.ndarray
    scanned: bool = True
    seen: list = field(default_factory=list, repr=False, compare=False)   # the states solved to find them


def _breakpoint_state(model: ContactModel):
    """A one-entry cache of the solved states of the last crank angles.

    A one-entry cache of the solved states of the last crank angles (the refinement evaluates the same ones for the
    values and the slopes).
    """
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


def _scan_roots(model: ContactModel, n_scan: int, tol: float, rolls: bool, checked: bool = False,
                smooth: bool = True) -> BreakpointRoots:
    """Every sign change of the components on an ``n_scan`` grid of one period, refined (:func:`cycle_breakpoints`).

    ``checked``: a coarse scan whose result the quadrature's nodes must confirm (:func:`mean_loss_ratio`).
    ``smooth``: the refinement starts from the smooth side where it can (:func:`_smooth_side_start`); False: from the
    scan's linear interpolation only (the reference the smooth start is measured against).
    """
    Tp = model.g.period
    state = _breakpoint_state(model)
    xtol = 1e-12 * Tp
    x = np.linspace(0.0, Tp, n_scan + 1)
    v, dv, n_delta = cycle_components(state(x), rolls)
    sgn = np.sign(v)
    comp, idx = np.nonzero(sgn[:, :-1] * sgn[:, 1:] < 0)
    if comp.size:
        x0, steps = (_smooth_side_start(x, v, dv, comp, idx, xtol, Tp, model.settings.smooth_start_curvature_margin)
                     if smooth else (np.full(comp.size, np.nan),) * 2)

        first = [True]

        def h(t, k):
            # the first call's solves tight (its points from the smooth side are taken as they are, below); later
            # ones are the product's
            model._refining, first[0] = first[0] and np.isfinite(x0).any(), False
            try:
                val, slope, _ = cycle_components(state(t), rolls)
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
    """First points and step tolerances of the refinement of the scan's sign changes (:func:`_refine_sign_changes`).

    for a penetration (its slope known), the root of the cubic Hermite interpolant of the two scan points below zero
    next to the sign change (value and slope each), extrapolated over the bracket, and backed off into the side
    below zero by half the step tolerance; NaN (the scan's linear interpolation, the global step tolerance) where
    the slope is unknown, the next point out is not below zero too, another component changes sign on the way or in
    the bracket, or the far end lies above the cubic (below).

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
    """The roots of ``prior`` (the same design's cycle at a nearby torque) moved to this model.

    Each is bracketed by +-``width`` (widened 4x, up to ``max_width``, where its bracket holds no sign change), and
    the components' sign changes between the bracket ends refined as in :func:`_scan_roots` (one root found in two
    overlapping brackets counted once).  None (the full scan is needed) unless every bracket holds a sign change and
    their number is the prior's: a root that left its widest bracket, or a pair that appeared or vanished in it.
    Changes elsewhere are caught on the quadrature's nodes (:func:`mean_loss_ratio`).
    """
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
        v, _, n_delta = cycle_components(state(np.concatenate((a, b))), rolls)
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
        val, slope, _ = cycle_components(state(t), rolls)
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
    """The piece ends from the located roots.

    The period's ends, the roots, and the geometric gradings (:func:`cycle_breakpoints`).
    """
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
    r"""Breakpoints in [0, T_p] of the contact level's cycle integrand (pins.md §6, §12.9, §12.12).

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

    .. math:: \{0,\ T_p\} \cup \{\theta : \delta_j(\theta) = 0\} \cup \{\theta : v_{t,j}(\theta) = 0,\ F_j > 0\}
        \cup \text{gradings}, \qquad T_p = \frac{2\pi}{z_2}

    Parameters
    ----------
    model : ContactModel
        The contact model.
    n_scan : int, optional
        Scan intervals per period.
    tol : float, optional
        Relative accuracy target, [-].
    rolls : bool, optional
        The pins roll.
    roots : bool, optional
        Also return the located sign changes.

    Returns
    -------
    breakpoints : ndarray
        Sorted, in [0, T_p], [rad]; with ``roots`` also the :class:`BreakpointRoots`.

    Examples
    --------
    >>> from gearcalc.pins.contact import MULTIPLIER, Cycloid, CycloidProfile, contact_law
    >>> g = Cycloid.from_curtate_ratio(21, 22, 3.9, 0.75, 1.95)
    >>> model = ContactModel(g, CycloidProfile(g, 0.0, 0.0), contact_law("linear", stiffness=1e5), 1e4, MULTIPLIER)
    >>> bp = cycle_breakpoints(model)
    >>> float(bp[0]), bool(bp[-1] == 2 * np.pi / 22)   # from 0 to the pin period T_p
    (0.0, True)

    References
    ----------
    .. [1] docs/spec/pins.md §6, §12.9, §12.12.
    """
    found = _scan_roots(model, n_scan, tol, rolls)
    edges = _edges(model, found, tol)
    return (edges, found) if roots else edges


def locate_breakpoints(model: ContactModel, n_scan: int, tol: float, rolls: bool, coarse_scan: int | None = None,
                       prior: BreakpointRoots | None = None, prior_width: float = 1e-2):
    r"""The sign changes and piece ends of a cycle: moved from a prior, from a coarse scan, or from the full scan.

    With ``prior`` (the located sign changes of the same design's cycle at a nearby torque) the roots are moved by
    Newton within +-``prior_width`` T_p (widened up to ``settings.prior_width_max`` T_p, :func:`_incremental_roots`);
    else, with ``coarse_scan`` below ``n_scan``, scanned on that many intervals.  Both are taken unconfirmed
    (``scanned`` False): the quadrature's nodes must then lie on their pieces' sides of every sign change
    (:func:`pieces_hold`), else the cycle is recomputed with the full scan (pins.md §6).  Where neither applies or
    the roots cannot be moved, the full scan on ``max(n_scan, model.scan_n)`` intervals (as dense as the last pass's
    had to be).  The piece ends are the period's ends, the roots and the gradings of :func:`cycle_breakpoints`.

    .. math:: \{0,\ T_p\} \cup \{\theta_r\} \cup \text{gradings}, \qquad
        \theta_r^{(2)} = \theta_r^{(1)} - c(\theta_r^{(1)})/c'(\theta_r^{(1)}) \ \text{(moved, Newton)}

    Parameters
    ----------
    model : ContactModel
        The contact model (design and torque).
    n_scan : int
        Intervals of the full scan per period.
    tol : float
        Relative accuracy target, [-].
    rolls : bool
        The pins roll.
    coarse_scan : int, optional
        Intervals of a coarse scan to try first (None: none).
    prior : BreakpointRoots, optional
        The located sign changes of a nearby torque's cycle.
    prior_width : float, optional
        The first half-width of a moved root's bracket, [periods].

    Returns
    -------
    found : BreakpointRoots
        The located sign changes.
    edges : ndarray
        The piece ends, sorted, [rad].
    n_scan : int
        The full scan's intervals (``n_scan`` unless it ran denser).

    Examples
    --------
    >>> from gearcalc.pins.contact import MULTIPLIER, CycloidProfile, Cycloid, contact_law
    >>> g = Cycloid.from_curtate_ratio(21, 22, 3.9, 0.75, 1.95)
    >>> model = ContactModel(g, CycloidProfile(g, 0.0, 0.0), contact_law("linear", stiffness=1e5), 1e4, MULTIPLIER)
    >>> found, edges, n = locate_breakpoints(model, 256, 1e-6, False)
    >>> found.scanned, n, float(edges[0]), bool(edges[-1] == g.period), found.roots.size > 0
    (True, 256, 0.0, True, True)

    References
    ----------
    .. [1] docs/spec/pins.md §6, §7.
    """
    Tp = model.g.period
    found = None
    if prior is not None:
        found = _incremental_roots(model, prior, prior_width * Tp, tol, rolls, model.settings.prior_width_max * Tp)
    elif coarse_scan is not None and coarse_scan < n_scan:
        found = _scan_roots(model, coarse_scan, tol, rolls, checked=True)
    if found is None:
        # as dense as the last pass's full scan had to be (its nodes held only there; pins.md §6)
        n_scan = max(n_scan, model.scan_n)
        found = _scan_roots(model, n_scan, tol, rolls)
    return found, _edges(model, found, tol), n_scan


@dataclass(frozen=True)
class RootStops:
    """Where :func:`_refine_sign_changes` stops (its parameter object).

    ``xtol`` the location tolerance of a root; ``jump_xtol`` (default ``xtol``) of a jump; ``step_tol`` (default
    ``xtol``) a Newton or secant step below which a bracket stops at the stepped point; ``maxiter`` calls at most; a
    bracket that Newton or the secant cannot narrow is cut into ``sections`` parts per call (``settings.sections``).
    """

    xtol: float
    jump_xtol: float | None = None
    step_tol: float | None = None
    maxiter: int = 100
    sections: int = DEFAULT_SETTINGS.sections


def _refine_sign_changes(h, brackets, stops: RootStops, x0=None, bent_above: bool = False, step_tols=None):
    """Sign changes of a vectorised h on the brackets [a, b].

    safeguarded Newton where ``h`` gives a slope, secant otherwise, and where a step leaves the bracket the bracket
    cut into ``sections`` equal parts by as many points minus one in the next call (pins.md §6: breakpoints to 1e-12
    T_p).  ``h(x, k)`` returns (values, slopes) of the brackets ``k`` (indices, repeated for several points of one
    bracket) at x, a slope NaN where unknown; only the brackets not yet done are evaluated.  Stops bracket by
    bracket when the step or the bracket is below ``xtol`` or h is exactly 0.

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
    B = _Brackets.start(brackets, stops, x0, step_tols)
    frac = np.arange(1, stops.sections) / stops.sections
    act = np.arange(B.x.size)
    for _ in range(stops.maxiter):
        if act.size == 0:
            break
        one, many = act[~B.cut[act]], act[B.cut[act]]
        grid = B.lo[many, None] + (B.hi - B.lo)[many, None] * frac[None, :]
        fv, sv = h(np.concatenate((B.x[one], grid.ravel())), np.concatenate((one, np.repeat(many, frac.size))))
        done = np.zeros(0, dtype=np.int64)
        if one.size:
            done = B.step(one, fv[:one.size], sv[:one.size], bent_above)
        if many.size:
            done = np.concatenate((done, B.section(many, grid, fv[one.size:].reshape(many.size, frac.size))))
        act = np.setdiff1d(act, done, assume_unique=True)
    return B.x


@dataclass
class _Brackets:
    """The brackets of :func:`_refine_sign_changes` as they narrow (arrays over the brackets, updated in place).

    ``lo``, ``hi``, ``flo``, ``fhi``: the ends and their values; ``x``: each bracket's next point (its root when
    done); ``xp``, ``fp``: its last point and value (the secant's); ``cut``: cut into sections at the next call;
    ``w0``, ``slope0``: the first width and the scan's slope |fb - fa|/(b - a) (a jump's test); ``xtol``, ``jtol``,
    ``step_tol``, ``stols``: the tolerances of a root, a jump, a step (``stols``: per bracket, or None).
    """

    lo: np.ndarray
    hi: np.ndarray
    flo: np.ndarray
    fhi: np.ndarray
    x: np.ndarray
    xp: np.ndarray
    fp: np.ndarray
    cut: np.ndarray
    w0: np.ndarray
    slope0: np.ndarray
    xtol: float
    jtol: float
    step_tol: float
    stols: np.ndarray | None

    @classmethod
    def start(cls, brackets, stops: RootStops, x0, step_tols) -> "_Brackets":
        """The brackets at the scan's linear interpolation, or at ``x0`` where it is near it (a quarter bracket)."""
        a, b, fa, fb = brackets
        xtol = stops.xtol
        step_tol = xtol if stops.step_tol is None else max(stops.step_tol, xtol)
        lo, hi = np.array(a, dtype=float), np.array(b, dtype=float)
        flo, fhi = np.array(fa, dtype=float), np.array(fb, dtype=float)
        w0 = hi - lo
        slope0 = np.abs(fhi - flo) / np.where(w0 > 0.0, w0, 1.0)
        jtol = xtol if stops.jump_xtol is None else max(xtol, stops.jump_xtol)
        with np.errstate(divide="ignore", invalid="ignore"):
            x = lo - flo * (hi - lo) / (fhi - flo)                # the scan's linear interpolation
        x = np.where(np.isfinite(x) & (x > lo) & (x < hi), x, 0.5 * (lo + hi))
        stols = None if step_tols is None else np.where(np.isfinite(step_tols), np.maximum(step_tols, step_tol),
                                                         step_tol)
        if x0 is not None:
            # far from the linear interpolation (a quarter of the bracket) the bracket holds more than one sign change,
            # or the cubic does not describe it: the linear start then
            x0 = np.asarray(x0, dtype=float)
            x = np.where(np.isfinite(x0) & (x0 > lo) & (x0 < hi) & (np.abs(x0 - x) <= 0.25 * (hi - lo)), x0, x)
        near = np.abs(flo) < np.abs(fhi)
        return cls(lo, hi, flo, fhi, x, np.where(near, lo, hi), np.where(near, flo, fhi), np.zeros(x.size, dtype=bool),
                   w0, slope0, xtol, jtol, step_tol, stols)

    def step(self, one, f, slope, bent_above: bool):
        """The brackets ``one`` evaluated at ``x`` (values ``f``, slopes): narrowed, a Newton or secant step next.

        A step outside the bracket: cut it at the next call.  Returns the brackets done.
        """
        xa, xtol, jtol = self.x[one], self.xtol, self.jtol
        lb, hh, fl, fh = self.lo[one], self.hi[one], self.flo[one], self.fhi[one]
        left = np.sign(f) == np.sign(fl)
        lb, fl = np.where(left, xa, lb), np.where(left, f, fl)
        hh, fh = np.where(~left, xa, hh), np.where(~left, f, fh)
        with np.errstate(divide="ignore", invalid="ignore"):
            d = np.where(np.isfinite(slope) & (slope != 0.0), slope, (f - self.fp[one]) / (xa - self.xp[one]))
            new = xa - f / d
        bad = ~np.isfinite(new) | (new <= lb) | (new >= hh)
        new = np.where(bad, 0.5 * (lb + hh), new)
        width = hh - lb
        jump = (width <= 1e-3 * self.w0[one]) & (np.minimum(np.abs(fl), np.abs(fh)) > 100.0 * self.slope0[one] * width)
        small = np.abs(new - xa) <= (self.step_tol if self.stols is None else self.stols[one])
        if bent_above:
            small = np.where((f > 0.0) & np.isfinite(slope), np.abs(new - xa) <= 30.0 * xtol, small)
        conv = ((f == 0.0) | (~bad & small) | (width <= 2.0 * xtol)
                | (jump & (width <= 2.0 * jtol)))
        closed = conv & ((width <= 2.0 * xtol) | (jump & (width <= 2.0 * jtol)))
        self.lo[one], self.hi[one], self.flo[one], self.fhi[one] = lb, hh, fl, fh
        self.xp[one], self.fp[one] = xa, f
        self.x[one] = np.where(f == 0.0, xa, np.where(closed, 0.5 * (lb + hh), new))
        self.cut[one] = bad                          # a step outside the bracket: cut it at the next call
        return one[conv]

    def section(self, many, grid, fg):
        """The cut brackets ``many`` evaluated at their ``grid`` (values ``fg``): the part with the sign change.

        A zero value: the root there.  Cut again while the end values stay 4x above the scan's slope (a jump, or a
        root far from linear), else the secant next.  Returns the brackets done.
        """
        xtol, jtol = self.xtol, self.jtol
        X = np.column_stack((self.lo[many], grid, self.hi[many]))
        F = np.column_stack((self.flo[many], fg, self.fhi[many]))
        j = np.argmax(np.sign(F[:, :-1]) * np.sign(F[:, 1:]) <= 0.0, axis=1)
        r = np.arange(many.size)
        lb, hh, fl, fh = X[r, j], X[r, j + 1], F[r, j], F[r, j + 1]
        width = hh - lb
        big = np.minimum(np.abs(fl), np.abs(fh))
        jump = (width <= 1e-3 * self.w0[many]) & (big > 100.0 * self.slope0[many] * width)
        zero = (fl == 0.0) | (fh == 0.0)
        conv = zero | (width <= 2.0 * xtol) | (jump & (width <= 2.0 * jtol))
        self.lo[many], self.hi[many], self.flo[many], self.fhi[many] = lb, hh, fl, fh
        with np.errstate(divide="ignore", invalid="ignore"):
            sec = lb - fl * width / (fh - fl)
        sec = np.where(np.isfinite(sec) & (sec > lb) & (sec < hh), sec, 0.5 * (lb + hh))
        self.x[many] = np.where(fl == 0.0, lb, np.where(fh == 0.0, hh, np.where(conv, 0.5 * (lb + hh), sec)))
        near = np.abs(fl) < np.abs(fh)
        self.xp[many], self.fp[many] = np.where(near, lb, hh), np.where(near, fl, fh)
        self.cut[many] = big > 4.0 * self.slope0[many] * width        # still far from linear there: cut again
        return many[conv]


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


def pieces_hold(nodes, ref_sols, edges, rolls: bool, tol: float, period: float, away=None,
                 floor: float = 0.0) -> bool:
    r"""Whether every evaluated node lies on its piece's side of every sign change (pins.md §6).

    No component has the opposite sign of the piece's midpoint at a node farther than 2e-3 tol T_p from the piece's
    ends (where a located jump may lie within 1e-3 tol T_p of its place, :func:`_scan_roots`): stricter than the
    full scan (the nodes are denser than its intervals), it confirms moved or coarsely scanned breakpoints.
    ``away`` = (points, width): nor at a node within ``width`` of a point (sorted; the strips a breakpoint may have
    moved through since the nodes were placed, :func:`relinearised_cycle`).  ``floor``: a contradiction counts only
    where the node's value and the piece's both exceed ``floor`` times the component's largest |value| over the
    nodes (a sliding speed that dithers about 0 where the friction forces flip, with friction in the balance).

    .. math:: \operatorname{sign} c_k(x) \ne -\operatorname{sign} c_k(m_p) \quad \text{for every node } x
        \text{ of piece } p,\ |x - a_p|, |b_p - x| > 2\cdot 10^{-3}\,\text{tol}\,T_p

    Parameters
    ----------
    nodes : tuple
        (cache, mids): the nodes' states (a list of :class:`Solution`) and their pieces' midpoints [rad].
    ref_sols : list of Solution
        The states that fixed the pieces' sets, told by their pieces' midpoints (``theta``).
    edges : ndarray
        The piece ends, sorted, [rad].
    rolls : bool
        The pins roll.
    tol, period : float
        Relative accuracy target, [-]; T_p, [rad].
    away : tuple, optional
        (points, width): also exclude the nodes within ``width`` of a point, [rad].
    floor : float, optional
        The share of a component's largest |value| below which a contradiction does not count, [-].

    Returns
    -------
    held : bool
        No node contradicts its piece.

    Examples
    --------
    >>> from gearcalc.pins.contact import MULTIPLIER, ContactModel, Cycloid, CycloidProfile, contact_law
    >>> g = Cycloid.from_curtate_ratio(21, 22, 3.9, 0.75, 1.95)
    >>> model = ContactModel(g, CycloidProfile(g, 0.0, 0.0), contact_law("linear", stiffness=1e5), 1e4, MULTIPLIER)
    >>> edges = cycle_breakpoints(model); mids = 0.5 * (edges[:-1] + edges[1:]); ref = model.state(mids, phases=False)
    >>> pieces_hold(([ref], [mids]), [ref], edges, False, 1e-6, g.period)      # the midpoints hold themselves
    True

    References
    ----------
    .. [1] docs/spec/pins.md §6.
    """
    cache, mids = nodes
    rm = np.concatenate([r.theta for r in ref_sols])
    rv = np.concatenate([cycle_components(r, rolls)[0] for r in ref_sols], axis=1)
    if floor > 0.0:
        with np.errstate(invalid="ignore"), warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)          # a component without a sign anywhere: NaN
            big = floor * np.nanmax(np.abs(np.concatenate([cycle_components(c, rolls)[0] for c in cache], axis=1)),
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
        v = cycle_components(c, rolls)[0][:, inner]
        if v.shape[0] != rv.shape[0]:
            return False
        if floor > 0.0:
            v = np.where(np.abs(v) > big, v, np.nan)
        col = order[rm[order].searchsorted(mid[inner])]
        if (((v > 0.0) & rneg[:, col]) | ((v < 0.0) & rpos[:, col])).any():
            return False
    return True
