r"""KHV pin gearing, level ``contact``: a torque pass of the fixed point from the last pass's nodes (pins.md §6(6), §7).

:func:`relinearised_cycle` solves the last pass's final grid at the new torque (every stride-th node of each piece
and its ends, :func:`_strided`; the others moved by the change, :func:`_moved`), adds the change's trapezoid
(:func:`nested_trapezoid_weights`) to the last pass's mean and bounds the strips the breakpoints move through
(:func:`_strips`, :func:`_strip_sides`).  Pure physics over the states of :mod:`gearcalc.pins.contact_model`.

The method.  Every node keeps its crank angle and its piece's sets and is solved at the new torque from the Newton
step tau + dM/G_tau (:meth:`ContactModel.state`, mostly one balance per node).  On each piece the state is then the
smooth extension of the new torque's over the old piece, so

.. math::

    \bar\lambda_2 = \frac{\bar\lambda_1 s_1 + \frac{1}{T_p}\sum_i w_i (L_2 - L_1)_i}{s_2}

(L the nodes' loss per unit crank speed, w_i the final grid's trapezoid weights per piece, s the loss ratio's scale
T_sat k/z1), exact but for the strips between each breakpoint's old place r and its new one: there the other side's
state holds.  A breakpoint moves by d = |c/c'| (c the sign-changing component at the new torque at r, c' its slope,
else a secant to the next node: a Newton step, :func:`_breakpoint_moves`), taken as D = 1.25 d
(``settings.relinearise_margin``); the integrand's two sides differ over the strip by at most the jump J at r plus
each side's change, which grows like t^p from r: read off the nearest node at least D out (Delta at distance t_n;
the graded pieces next to a Hertz entry have one close by), scaled by min(1, D/t_n)^p and integrated over the strip
(1/(1 + p)); p = 1 for the linear law, 1/9 for the Hertz law (its singular speeds, (theta - theta_0)^(1/9)).  Under
a power law a contact entry or exit alone (:func:`_strip_sides`) counts nothing where its zero moved into the
touching side (the states there are the other side's exactly); where it moved out of it, the other side's states
miss the touching pin's share of the speeds, an error that grows from 0 at the new zero like t^p to e_r at the old
place (the touching side's loss minus the other's, both solved at the new torque): its integral e_r d/(1 + p) is
added to the value, and (1.25^(1 + p) - 1) of it (a zero up to 25 % farther) is the strip's term instead.  That
bound,

.. math::

    E_s = \frac{1}{T_p s_2}\sum_b D_b \Big(J_b + \sum_{\pm} \frac{\Delta_\pm \min(1, D_b/t_\pm)^p}{1 + p}\Big),

is added to the quadrature's error (rescaled by s_1/s_2); the difference's own quadrature error is ~tol of a change
of ~1e-7 lambda_bar.  Measured on the paper designs: the loss ratio within 0.28 of the full pass's stated error of
it; E_s 0.4-1.1 of tol lambda_bar at the torque steps of their second passes (3e-6 to 2e-5); with the strips
integrated (2026-11-27) every pass is taken, within 0.48 of the stated errors of a full pass at 1/100 of the
tolerance (0.19 on random designs, 0.52 before).

No pass (None: a full pass is needed) when the cycle has no final-grid record (a Gauss-Kronrod rule), a node has no
equilibrium with its sets or non-finite values, a node farther than D from every breakpoint has a component with the
other sign than its piece (:func:`~gearcalc.pins.contact_roots.pieces_hold`: a contact appears or leaves; with the
floor of the cycle's own check, ``settings.hold_floor`` where its roots are the full scan's), the window's tau range
does not hold or its pins are not the last pass's (:meth:`ContactModel.layout`: a window recomputed for a wider tau
range, :func:`_over_rows`), a breakpoint's component is not found, or the quadrature's error and E_s exceed
``settings.relinearise_share`` of tol lambda_bar (a breakpoint that moves far, or a loss that jumps there: rolling
pins' lead switch, flipping friction forces).
"""
from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from .contact_cycle import ContactCycle, contact_losses
from .contact_model import ContactModel, NoEquilibrium
from .contact_roots import cycle_components, pieces_hold
from .contact_states import GEOMETRY_FIELDS, Solution, over_rows, relayout, same_rows, sub_pose, take_states

__all__ = ["relinearised_cycle", "piece_places", "nested_trapezoid_weights"]


def relinearised_cycle(model: ContactModel, cyc: ContactCycle, prev: ContactModel, tol: float,
                       stride: int | None = None) -> "ContactCycle | None":
    r"""The cycle at the torque of ``model`` from the final grid of ``cyc`` (solved with ``prev``, a torque nearby).

    The next pass of the torque fixed point without locating the breakpoints again (pins.md §6(6), §7; the method and
    its error bound in this module's documentation).  Every node keeps its crank angle and its piece's sets; every
    stride-th node of each piece and its ends are solved at the new torque from the Newton step tau + dM/G_tau
    (:func:`_solve_kept`), the others moved by the change (:func:`_moved`); the mean is the last one plus the change's
    trapezoid, its error the last one's plus the change's own and the strips' bound E_s (:func:`_strips`):

    .. math::

        \bar\lambda_2 = \frac{\bar\lambda_1 s_1 + \frac{1}{T_p}\sum_i w_i (L_2 - L_1)_i}{s_2}

    None (a full pass is needed) where the method does not hold (the cases in this module's documentation).

    Parameters
    ----------
    model, prev : ContactModel
        The model at the new torque (its window inherited, :meth:`ContactModel.inherit`); the one ``cyc`` was solved
        with.
    cyc : ContactCycle
        The cycle at the torque of ``prev``.
    tol : float
        Relative accuracy target, [-].
    stride : int, optional
        Every stride-th node of each piece is solved anew, the others moved by the change interpolated.

    Returns
    -------
    cycle : ContactCycle or None
        The cycle at the new torque, or None when a piece's sets do not hold (recompute in full).

    Examples
    --------
    >>> from gearcalc.pins.contact import MULTIPLIER, Cycloid, CycloidProfile, contact_law, mean_loss_ratio
    >>> g = Cycloid.from_curtate_ratio(21, 22, 3.9, 0.75, 1.95)
    >>> law, prof = contact_law("linear", stiffness=1e5), CycloidProfile(g, 0.0, 0.0)
    >>> a, b = ContactModel(g, prof, law, 1e4, MULTIPLIER), ContactModel(g, prof, law, 1e4 * (1 + 1e-6), MULTIPLIER)
    >>> first = mean_loss_ratio(a, (0.1, 0.1, False), tol=1e-5)
    >>> b.inherit(a)
    >>> lite = relinearised_cycle(b, first, a, 1e-5)
    >>> lite is not None and abs(lite.loss_ratio - first.loss_ratio) < 1e-5 * first.loss_ratio
    True

    References
    ----------
    .. [1] pins.md §6 (the torque fixed point's passes), §7.
    """
    on_rows = None if cyc.nodes is None or cyc.roots is None else _over_rows(model, cyc)
    gp = None if on_rows is None else _pass_grid(model, cyc, on_rows[4], on_rows[1], stride)
    s2k = None if gp is None else _solve_kept(model, prev, cyc, on_rows[0], gp)
    if s2k is None:
        return None
    (sets, node_mid, ref_sols, rows, sol1), (R_b, mu_eff, f, rolls, scale1, *law) = on_rows, cyc.friction
    g, Tp, edges = model.g, model.g.period, cyc.breakpoints
    scale2 = model.torque_sat * g.k / g.z1
    # the change's trapezoid over the solved nodes of each piece, and over every other one of them (its error)
    dL, pk = gp.L2 - gp.L1[gp.kept], gp.ps[gp.keep]
    w, w2 = nested_trapezoid_weights(gp.xs[gp.keep], pk)
    change = np.bincount(pk, weights=w * dL, minlength=edges.size)
    E_d = float(np.abs(change - np.bincount(pk, weights=w2 * dL, minlength=edges.size)).sum()) / Tp / scale2
    lam2 = (cyc.loss_ratio * scale1 + float(change.sum()) / Tp) / scale2
    E_q = cyc.loss_ratio_err * scale1 / scale2 + E_d
    gp.s2 = _moved(sol1, s2k, gp.kept, *gp.between())
    if not model.window_holds(gp.s2.tau, gp.s2.theta, prev):
        return None
    E_s, width, lam2 = _strips(model, cyc, gp, lam2, scale2) or (math.inf, 0.0, lam2)     # None: no pass
    s2 = gp.s2
    if not (E_q + E_s <= model.settings.relinearise_share * tol * abs(lam2)
            and pieces_hold(([s2], [node_mid]), ref_sols, edges, rolls, tol, Tp, away=(cyc.roots.roots, width),
                            floor=model.settings.hold_floor if cyc.roots.scanned else 0.0)):
        return None
    # functions of theta and the mode only
    s2.phase, s2.zeta = (sol1.phase, sol1.zeta) if sol1.phase is not None else model.phases(s2.theta, s2.rows)
    model.roots = cyc.roots
    return ContactCycle(float(lam2), E_q + E_s, cyc.converged, cyc.n_crank, cyc.quad, s2, edges, cyc.roots,
                        (R_b, mu_eff, f, rolls, scale2, *law), (sets, node_mid, ref_sols, rows))


def _over_rows(model: ContactModel, cyc: ContactCycle):
    """(sets, node midpoints, reference states, rows, states) of ``cyc``'s final grid over ``model``'s rows.

    The window recomputed for a wider tau range (:meth:`ContactModel.inherit`): the last pass's states and sets over
    this model's rows (a pin they do not hold: out of reach at every node, inactive); a pin left out must carry no
    force in them (the window's bound: it cannot touch at this torque either), else None.
    """
    sets, node_mid, ref_sols, rows = cyc.nodes
    g, sol1 = model.g, cyc.sol
    rows2 = model.layout()[0]
    if not same_rows(rows2, rows):
        src, dst = (np.arange(g.z2) if r is None else r for r in (rows, rows2))
        if (sol1.force[:, ~np.isin(src, dst)] > 0.0).any():
            return None
        sets = tuple(None if a is None else over_rows(a, src, dst, fill) for a, fill in zip(sets, (False, -1, 0.0)))
        ref_sols = [relayout(r, rows2, g.z2) for r in ref_sols]
        sol1, rows = relayout(sol1, rows2, g.z2), rows2
    return sets, node_mid, ref_sols, rows, sol1


@dataclass
class _PassGrid:
    """The last pass's final grid piece by piece, and what the new torque's pass solves of it (:func:`_pass_grid`).

    ``x``, ``sol1``: the nodes' crank angles and the last pass's states over this model's rows; ``order``: the nodes
    in (piece, theta) order (sorted in theta too: pieces follow each other), ``xs``, ``ps`` their crank angles and
    pieces; ``keep`` (in that order), ``kept`` (in the grid's): the nodes solved anew; ``lo``,
    ``hi``, ``t``: the kept nodes around each node and its place between them (:func:`_strided`); ``L1`` the losses
    per unit crank speed of every node at the last torque, ``L2`` of the kept ones at the new; ``s2`` the new
    torque's states (set by :func:`relinearised_cycle`).
    """

    x: np.ndarray
    sol1: Solution
    order: np.ndarray
    xs: np.ndarray
    ps: np.ndarray
    keep: np.ndarray
    kept: np.ndarray
    lo: np.ndarray
    hi: np.ndarray
    t: np.ndarray
    L1: np.ndarray | None = None
    L2: np.ndarray | None = None
    s2: Solution | None = None

    def between(self):
        """(lo, hi, t) per node in the grid's order, lo and hi as places in ``kept`` (:func:`_moved`)."""
        place = np.cumsum(self.keep) - 1                   # each kept node's place in ``kept`` (xs order)
        lo_n, hi_n, t_n = (np.empty_like(a) for a in (self.lo, self.hi, self.t))
        lo_n[self.order], hi_n[self.order], t_n[self.order] = place[self.lo], place[self.hi], self.t
        return lo_n, hi_n, t_n


def _pass_grid(model: ContactModel, cyc: ContactCycle, sol1: Solution, node_mid, stride) -> _PassGrid:
    """The final grid of ``cyc`` piece by piece (a piece end is a node of each of its two pieces), strided."""
    x, edges = cyc.sol.theta, cyc.breakpoints
    p = np.minimum(np.maximum(edges.searchsorted(node_mid) - 1, 0), edges.size - 2)
    order = np.lexsort((x, p))
    xs, ps = x[order], p[order]
    keep, lo_s, hi_s, t_s = _strided(xs, ps, model.settings.relinearise_stride if stride is None else stride)
    return _PassGrid(x, sol1, order, xs, ps, keep, order[keep], lo_s, hi_s, t_s)


def _solve_kept(model: ContactModel, prev: ContactModel, cyc: ContactCycle, sets, gp: _PassGrid):
    """The kept nodes' states at the new torque, from the Newton step tau + dM/G_tau; their losses into ``gp``.

    Started from the last pass's pose of its nodes (its foot points) where it was solved on the same nodes and
    sides.  None where a node has no equilibrium with its sets or a non-finite force, speed or loss.
    """
    x, kept, sol1 = gp.x, gp.kept, gp.sol1
    R_b, mu_eff, f, rolls, _, *law = cyc.friction
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
        gp.L1 = contact_losses(sol1, R_b, mu_eff, f, rolls, *law)[0].sum(axis=(0, 1))
        gp.L2 = contact_losses(s2k, R_b, mu_eff, f, rolls, *law)[0].sum(axis=(0, 1))
    if not (np.isfinite(gp.L2).all() and np.isfinite(s2k.force).all() and np.isfinite(s2k.v_t).all()):
        return None
    return s2k


def _breakpoint_moves(model: ContactModel, r, gp: _PassGrid, rolls: bool):
    """How far each breakpoint ``r`` moved: its components' Newton steps from its one-sided nodes at the new torque.

    The components that change sign at each breakpoint (between its neighbouring nodes, first torque), and a Newton
    step of their zero from either one-sided node (secant to the next node where there is no slope).  Returns
    (a_end, b_end, ends, flips, step, v_left, n_delta, d): the one-sided nodes (``xs`` places; grid places of both),
    the flipping components (c, m), their steps (c, 2m), values left (first torque), the penetrations' count, and
    each breakpoint's move; None where the nodes at a breakpoint or a flipping component are not found.
    """
    xs, order, s2, sol1, x, Tp = gp.xs, gp.order, gp.s2, gp.sol1, gp.x, model.g.period
    n = xs.size
    a_end = np.minimum(np.maximum(xs.searchsorted(r), 0), n - 1)      # the two one-sided nodes at each breakpoint
    b_end = np.minimum(a_end + 1, n - 1)
    if not ((np.abs(xs[a_end] - r) <= 8e-12 * Tp) & (xs[b_end] == xs[a_end])).all():
        return None
    nb = order[np.minimum(np.maximum(np.concatenate((a_end - 1, b_end + 1)), 0), n - 1)]
    ends = order[np.concatenate((a_end, b_end))]
    v1 = cycle_components(take_states(sol1, nb), rolls)[0]
    v2n = cycle_components(take_states(s2, nb), rolls)[0]
    v2, dv2, n_delta = cycle_components(take_states(s2, ends), rolls)
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
    return a_end, b_end, ends, flips[:, :m], step, v1[:, :m], n_delta, d


def _strips(model: ContactModel, cyc: ContactCycle, gp: _PassGrid, lam2: float, scale2: float):
    """(E_s, the widest strip, lambda_bar): the bound of the strips the breakpoints moved through, and the value.

    Each strip of width D = ``settings.relinearise_margin`` d about a breakpoint (:func:`_breakpoint_moves`) counts
    the jump of the loss there plus each side's change, read off the nearest node at least D out, scaled by
    min(1, D/t)^p and integrated (1/(1 + p)); an entry or exit alone under a power law whose zero moved out of the
    touching side (:func:`_strip_sides`) is integrated instead: e_r d/(1 + p) joins the value, (1.25^(1 + p) - 1)
    of it the bound (the module's documentation).  None where a term or the value is not finite.
    """
    r, Tp, xs, l1 = cyc.roots.roots, model.g.period, gp.xs, gp.L1[gp.order]
    R_b, mu_eff, f, rolls, _, *law = cyc.friction
    if not r.size:
        return 0.0, 0.0, lam2
    moves = _breakpoint_moves(model, r, gp, rolls)
    if moves is None:
        return None
    a_end, b_end, ends, flips, step, v_left, n_delta, d = moves
    n, m = xs.size, r.size
    move = model.settings.relinearise_margin * d
    p_exp = 1.0 if model.law.exponent == 1.0 else model.law.exponent - 1.0
    lo = np.minimum(np.maximum(xs.searchsorted(r - move, side="right") - 1, 0), n - 1)
    hi = np.minimum(np.maximum(xs.searchsorted(r + move, side="left"), 0), n - 1)
    left, right = _strip_sides(flips, step, v_left, n_delta, model.law.exponent != 1.0)
    with np.errstate(divide="ignore", invalid="ignore"):
        side = (left * np.abs(l1[lo] - l1[a_end]) * np.minimum(1.0, move / (r - xs[lo])) ** p_exp
                + right * np.abs(l1[hi] - l1[b_end]) * np.minimum(1.0, move / (xs[hi] - r)) ** p_exp)
        side = side / (1.0 + p_exp)
        strip = move * (np.abs(l1[a_end] - l1[b_end]) + np.where(move > 0.0, side, 0.0))
        grows = left != right               # an entry or exit alone whose zero moved out of the touching side
        if grows.any():
            # the integrand's error there grows from 0 at the new zero like t^p to e_r at the old place, where both
            # sides' states are solved at the new torque (the touching side's loss minus the other's)
            both = np.concatenate((a_end, b_end))          # piece ends: solved nodes, their losses in L2
            place = np.cumsum(gp.keep) - 1
            l2 = gp.L2[place[both]] if gp.keep[both].all() else \
                contact_losses(take_states(gp.s2, ends), R_b, mu_eff, f, rolls, *law)[0].sum(axis=(0, 1))
            e_r = np.where(left == 1.0, l2[:m] - l2[m:], l2[m:] - l2[:m])     # touching minus the other
            grown = np.where(grows, e_r * d / (1.0 + p_exp), 0.0)
            strip = np.where(grows, (model.settings.relinearise_margin ** (1.0 + p_exp) - 1.0) * np.abs(grown), strip)
            lam2 += float(grown.sum()) / Tp / scale2
    if not (np.isfinite(strip).all() and math.isfinite(lam2)):
        return None
    return float(strip.sum()) / Tp / scale2, float(move.max()), lam2


def _strip_sides(flips, step, v_left, n_delta: int, power_law: bool):
    r"""(left, right): whether each side's change counts in the bound of a breakpoint's strip.

    1 where a side's change counts in the bound of a breakpoint's strip (:func:`relinearised_cycle`), 0 where it
    does not, per breakpoint (m,).

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
    pass's); ``n_delta``: the penetrations come first (:func:`cycle_components`).

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
    r"""Of nodes sorted by piece (``ps`` their pieces).

    Each run's first position ``start`` and node count ``count``, and per node its run ``piece`` and its place ``j``
    in it (0 at the piece's first node).

    .. math:: j = k - \text{start}_{\text{piece}(k)}

    Parameters
    ----------
    ps : ndarray
        Each node's piece key, sorted by piece.

    Returns
    -------
    start, count, piece, j : ndarray of int
        Each run's first position and node count; each node's run and place in it.

    Examples
    --------
    >>> [a.tolist() for a in piece_places(np.array([0.5, 0.5, 0.5, 1.5, 1.5]))]
    [[0, 3], [3, 2], [0, 0, 0, 1, 1], [0, 1, 2, 0, 1]]

    References
    ----------
    .. [1] docs/spec/pins.md §6.
    """
    start = np.flatnonzero(np.concatenate(([True], ps[1:] != ps[:-1])))
    count = np.diff(np.append(start, ps.size))
    piece = np.repeat(np.arange(start.size), count)
    return start, count, piece, np.arange(ps.size) - start[piece]


def _strided(xs, ps, stride: int):
    """Every ``stride``-th node of each piece and both its ends.

    Every ``stride``-th node of each piece and both its ends (nodes sorted by piece, then theta; ``ps`` their
    pieces): a piece of M intervals takes the largest of stride, stride/2, ... (powers of 2 down to 1) that leaves
    it at least 4 intervals.  Returns (keep, lo, hi, t): the kept nodes, and for every node the kept nodes around it
    in its piece (positions) and its place between them, (x - x_lo)/(x_hi - x_lo) (0 at a kept node).
    """
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
    """The composite trapezoid's weights of nodes sorted by piece, then theta (``ps`` their pieces), piece by piece."""
    h = np.where(ps[1:] == ps[:-1], np.diff(xs), 0.0)
    w = np.zeros(xs.size)
    w[:-1] += 0.5 * h
    w[1:] += 0.5 * h
    return w


def nested_trapezoid_weights(xs, ps):
    r"""The composite trapezoid's weights at the levels N and N/2 of each piece.

    The composite trapezoid's weights of nodes sorted by piece, then theta (``ps`` their pieces), piece by piece,
    over all nodes and over every other node of each piece (its ends kept): (w, w_half), the levels N and N/2 of a
    piece of N intervals (an odd N: the half level's last interval is the one that is left).

    .. math:: w_k = \tfrac12 (h_{k-1} + h_k) \ \text{within a piece (level N)}, \qquad
        w_{1/2} \ \text{likewise over every other node (level N/2)}

    Parameters
    ----------
    xs : ndarray
        Nodes sorted by piece, then theta, [rad].
    ps : ndarray
        Their piece keys.

    Returns
    -------
    w, w_half : ndarray
        The weights at the levels N and N/2, [rad] (0 at the nodes the half level does not hold).

    Examples
    --------
    >>> w, w_half = nested_trapezoid_weights(np.array([0.0, 0.5, 1.0, 1.0, 2.0]), np.array([0.5, 0.5, 0.5, 1.5, 1.5]))
    >>> w.tolist(), w_half.tolist()
    ([0.25, 0.5, 0.25, 0.5, 0.5], [0.5, 0.0, 0.5, 0.5, 0.5])

    References
    ----------
    .. [1] docs/spec/pins.md §6, §8.
    """
    _, count, piece, j = piece_places(ps)
    half = (j % 2 == 0) | (j == count[piece] - 1)
    w_half = np.zeros(xs.size)
    w_half[half] = _trapezoid_weights(xs[half], ps[half])
    return _trapezoid_weights(xs, ps), w_half


def _moved(sol: Solution, part: Solution, kept, lo, hi, t) -> Solution:
    """``sol`` with the states ``part`` at the kept nodes, relinearised at the others.

    ``sol`` with the states ``part`` at its crank angles ``kept`` and, at the others, moved by the change part - sol
    interpolated linearly between the kept nodes around each (``lo``, ``hi``: their places in ``kept``; weight ``t``
    on ``hi``); the sets (branch, candidates, the friction forces' directions), the phases, the residual and the
    contact geometry (nx, ny, wx, wy) stay those of ``sol`` there (not solved at the new torque), forces are clipped
    at 0, a value that is not finite (a pin out of reach) is left as it is (:func:`relinearised_cycle`; both over
    the same rows).
    """
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
