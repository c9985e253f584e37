"""KHV pin gearing, level ``contact``: one cycle of the contact model at one torque (pins.md §5.6, §5.7, §6, §8).

The per-contact losses (§5.6); the cycle's breakpoints (contact entries and exits, spin reversals, crest passages:
scanned, refined by Newton or secant steps, moved from pass to pass, §6); the cycle mean of the loss ratio by the
adaptive quadrature per smooth piece with its error (:func:`mean_loss_ratio`; the breakpoints are
:mod:`gearcalc.pins.contact_roots`', the torque fixed point's later passes from the last pass's nodes
:mod:`gearcalc.pins.contact_relinearise`', §6(6)); the cycle's metrics, peaks, free play and backlash (§5.7, §8).
Pure physics over floats and numpy arrays, on the states of :mod:`gearcalc.pins.contact_model`;
:mod:`gearcalc.pins.contact` runs the torque fixed point and the modes over these cycles and re-exports the public
names.
"""
from __future__ import annotations

import dataclasses
import functools
import math
from dataclasses import dataclass, field

import numpy as np

from ..arrays import unique_sorted
from ..quadrature import QuadResult, integrate_adaptive
from ..roots import find_root
from .contact_interp import gk_interpolated, piece_guess, piece_keys
from .contact_model import ContactModel
from .contact_roots import BreakpointRoots, locate_breakpoints, pieces_hold
from .contact_settings import DEFAULT_SETTINGS
from .contact_states import Solution, concat_states, merged, sorted_places, sub_pose, take_states
from .cycle import disc_offsets, disc_sum_peak, sum_over_discs
from .friction import PinFriction
from .geometry import Cycloid

__all__ = ["contact_losses", "ContactCycle", "CycleGrid", "mean_loss_ratio", "engagement_metrics", "CyclePeaks",
           "cycle_peaks", "free_play", "backlash", "pin_travel", "deflection_sized"]


# ============================================================ losses (pins.md §5.6)

def contact_losses(sol: Solution, R_b: float, mu_eff: float, sliding_friction: float, rolls: bool, law=None):
    r"""Per-contact loss per unit crank speed and the pin spin (pins.md §5.6, §4.6).

    The rolling-pin rule of :meth:`gearcalc.pins.friction.PinFriction.losses`.

    Fixed pins: every loaded contact slides at |v_t| with mu_eff = f.  Rolling pins: the contact with
    the larger force sets the spin omega_pin = v_t/R_b and loses mu_rot F |v_t|; another loaded
    contact on the same pin slides at |v_t - omega_pin R_b| with f.

    .. math:: P = \mu F |v_t| \ \text{(fixed pins)}; \qquad \omega_{pin} = \frac{v_{t,lead}}{R_b}, \quad
        P_{lead} = \mu_{rot} F |v_t|, \quad P_{other} = f F |v_t - \omega_{pin} R_b| \ \text{(rolling pins)}

    Parameters
    ----------
    sol : Solution
        The solved states.
    R_b : float
        Pin radius, [mm].
    mu_eff : float
        Effective coefficient (mu_rot for rolling pins, else f), [-].
    sliding_friction : float
        Sliding friction f, [-].
    rolls : bool
        The pins roll.
    law : FrictionLaw, optional
        The sliding contacts' law at speeds per rad/s of crank speed (:class:`~gearcalc.pins.friction.AtCrankSpeed`;
        None: Coulomb with f).

    Returns
    -------
    loss : mu F |v| per contact [N·mm/s per rad/s] (c, R, n) (times 1e-3 omega_H gives W);
    spin : omega_pin per unit crank speed [-] (R, n) (0 for fixed pins and unloaded pins);
    slide : sliding speed per contact [mm/s per rad/s] (c, R, n);
    over the state's rows (:attr:`Solution.rows`: R pins; every other pin carries no force).

    Examples
    --------
    >>> from gearcalc.pins.contact import MULTIPLIER, CycloidProfile, contact_law
    >>> g = Cycloid.from_curtate_ratio(21, 22, 3.9, 0.75, 1.95)
    >>> model = ContactModel(g, CycloidProfile(g, 0.0, 0.0), contact_law("linear", stiffness=1e5), 1e4, MULTIPLIER)
    >>> sol = mean_loss_ratio(model, (0.1, 0.1, False), tol=1e-5).sol
    >>> loss, spin, slide = contact_losses(sol, g.R_b, 0.1, 0.1, False)   # fixed pins: mu F |v_t|, no spin
    >>> bool(np.allclose(loss, 0.1 * sol.force * np.abs(sol.v_t))), bool(np.all(spin == 0.0))
    (True, True)

    References
    ----------
    .. [1] docs/spec/pins.md §4.6, §5.6.
    """
    return PinFriction(mu_eff, sliding_friction, rolls, law).losses(sol.force, sol.v_t, R_b)


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
    friction : (R_b, mu_eff, f, rolls, scale, law) of :func:`contact_losses` and the loss ratio's scale;
    held : every node lies on its piece's side of every sign change (:func:`pieces_hold`); False: not even on the
    densest scan (``settings.scan_max`` intervals; not scanned denser where the satellite turns beyond a deflection,
    :func:`deflection_sized`), and the loss ratio is not known to its error (pins.md §6);
    nodes : (sets, mids, ref_sols, rows) of the trapezoid's final grid, for the next torque pass from the same nodes
    (:func:`~gearcalc.pins.contact_relinearise.relinearised_cycle`):
    each node's piece sets (active, branch, traction), its piece's midpoint, the states
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
        R_b, mu_eff, f, rolls, scale, *law = self.friction
        loss, spin, slide = contact_losses(self.sol, R_b, mu_eff, f, rolls, *law)
        return loss, spin, slide, loss.sum(axis=(0, 1)) / scale

    loss = property(lambda self: self._losses[0])
    spin = property(lambda self: self._losses[1])
    slide = property(lambda self: self._losses[2])
    lam = property(lambda self: self._losses[3])


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


def _interior_states(found: BreakpointRoots, mids, period: float, margin: float):
    """For the pieces with midpoints ``mids``.

    The column of a state solved while the sign changes ``found`` were located (``found.seen``) that lies in the
    same stretch between two of them as the midpoint, farther than ``settings.interior_margin`` T_p from both (the
    nearest such to the midpoint), else -1; and those states concatenated. The components keep their signs over the
    stretch, so that state has the piece's active set, branches and friction directions, as its midpoint's would
    (pins.md §6; a sign change the located ones missed is caught on the nodes, :func:`pieces_hold`).
    """
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


class _NodeLog:
    """The cycle mean's integrand (:func:`mean_loss_ratio`) and its record of the solved nodes.

    Called as ``log(x, mid)`` by :func:`~gearcalc.quadrature.integrate_adaptive`: the nodes ``x`` of the pieces with
    midpoints ``mid`` are solved with their pieces' fixed sets (:meth:`ContactModel.reference`: from a state solved
    in the stretch between the sign changes around the piece while they were located, else at the midpoint,
    :func:`_interior_states`) and warm-started from the solved nodes of the same piece (:func:`piece_guess`); returns
    lambda/T_p per node.  Kept: ``cache`` (the states per call), ``mids`` (their pieces' midpoints), ``sets`` (their
    piece sets (active, branch, traction)), ``ref_sols`` (the states that fixed the pieces' sets, for
    :func:`pieces_hold`).
    """

    def __init__(self, model: ContactModel, friction: PinFriction, found: BreakpointRoots, edges):
        g = model.g
        self.model, self.friction, self.found, self.edges = model, friction, found, edges
        self.scale = model.torque_sat * g.k / g.z1
        self.cache: list[Solution] = []
        self.mids: list[np.ndarray] = []
        self.refs: dict = {}
        self.ref_sols: list[Solution] = []
        self.sets: list[tuple] = []          # each node's piece sets (active, branch, traction), as ``cache``
        self.solved = [np.empty(0), np.empty(0), np.empty(0)]   # piece keys, tau, d tau/d theta of the nodes so far

    def _reference(self, new):
        """The fixed sets of the pieces with the new midpoints ``new`` into ``refs`` (their states: ``ref_sols``)."""
        model = self.model
        col, known = _interior_states(self.found, new, model.g.period, model.settings.interior_margin)
        parts = []
        if (col >= 0).any():
            rs = take_states(known, col[col >= 0])
            rs.theta = new[col >= 0]            # the piece's reference, told by its midpoint
            parts.append(rs)
        if (col < 0).any():
            parts.append(model.state(new[col < 0], phases=False))
        for rs in parts:
            self.ref_sols.append(rs)
            active, branch = rs.force > 0.0, rs.branch
            traction = None if model.friction is None else model.traction(rs)
            for i, m in enumerate(rs.theta):
                self.refs[m] = (active[..., i], None if branch is None else branch[..., i],
                                None if traction is None else traction[..., i])

    def __call__(self, x, mid):
        model, refs, solved, g, fr = self.model, self.refs, self.solved, self.model.g, self.friction
        um, inv = np.unique(mid, return_inverse=True)
        new = np.array([m for m in um if m not in refs])
        if new.size:
            self._reference(new)
        active = np.stack([refs[m][0] for m in um], axis=-1)[..., inv]
        branch = None if refs[um[0]][1] is None else np.stack([refs[m][1] for m in um], axis=-1)[..., inv]
        traction = None if refs[um[0]][2] is None else np.stack([refs[m][2] for m in um], axis=-1)[..., inv]
        key = piece_keys(self.edges, x, mid)
        s = model.state(x, (active, branch, traction), phases=False, guess=piece_guess(*solved, key, x, self.edges))
        order = (k_all := np.concatenate((solved[0], key))).argsort(kind="stable")
        solved[:] = [k_all[order], np.concatenate((solved[1], s.tau))[order],
                     np.concatenate((solved[2], s.dtau))[order]]
        self.cache.append(s)
        self.mids.append(np.asarray(mid, dtype=float))
        self.sets.append((active, branch, traction))
        loss, _, _ = contact_losses(s, g.R_b, fr.mu_eff, fr.sliding, fr.rolls, fr.law)
        return loss.sum(axis=(0, 1)) / self.scale / g.period

    def piece_ends(self):
        """A Gauss-Kronrod rule evaluates no piece end: the one-sided states at both ends of every piece.

        They join the final grid for the peaks, the loaded interval and the detail (not the mean; pins.md §6).
        """
        u = unique_sorted(np.asarray(self.edges, dtype=float))
        lo, hi = u[:-1], u[1:]
        lo, hi = lo[hi > lo], hi[hi > lo]
        mid = 0.5 * (lo + hi)                    # the pieces' midpoints, as the quadrature tells them
        self(np.column_stack((lo, hi)).ravel(), np.repeat(mid, 2))     # in time order: ..., b_p, a_(p+1), ...

    def hold(self, dense, rolls: bool, tol: float) -> bool:
        """Whether the nodes (and every third interpolated state of ``dense``) lie on their pieces' sides.

        :func:`pieces_hold` over the nodes, and with a Gauss-Kronrod rule every third of its interpolated states (341
        per period, as dense as the trapezoid's nodes, pins.md §6); the moved or coarse roots: every sign; the full
        scan's: a sliding speed that dithers about 0 (below ``settings.hold_floor`` of its largest) where the friction
        forces flip does not count (its losses are as small).
        """
        cache, mids = self.cache, self.mids
        checked = (cache, mids) if dense is None else (cache + [take_states(dense[0], slice(None, None, 3))],
                                                       mids + [dense[1][::3]])
        return pieces_hold(checked, self.ref_sols, self.edges, rolls, tol, self.model.g.period,
                           floor=self.model.settings.hold_floor if self.found.scanned else 0.0)

    def record(self, rows):
        """(sets, mids, ref_sols, rows) of the nodes in the final grid's order (:func:`concat_states`).

        For the next torque pass from these nodes (:func:`~gearcalc.pins.contact_relinearise.relinearised_cycle`).
        """
        places = sorted_places([c.theta for c in self.cache])

        def cat(parts):
            return None if parts[0] is None else merged(parts, places, parts[0].ndim - 1)

        sets = self.sets
        return ((cat([t[0] for t in sets]), cat([t[1] for t in sets]), cat([t[2] for t in sets])),
                cat(self.mids), self.ref_sols, rows)


def mean_loss_ratio(model: ContactModel, friction, tol: float = 1e-6, grid: CycleGrid | None = None,
                    n_initial=None, rule: str = "trapezoid", prior: "BreakpointRoots | None" = None,
                    prior_width: float = 1e-2) -> ContactCycle:
    r"""Cycle mean of lambda(theta) = sum P_j/(T_sat omega_H k/z1) over one period, with an honest error.

    The error: the quadrature's (:func:`~gearcalc.quadrature.piece_errors`), at least ``settings.inner_share`` tol
    |lambda_bar|.  The pieces' ends: :func:`locate_breakpoints` (a full scan, a coarse one, or moved from ``prior``);
    every node is an equilibrium solve (:class:`_NodeLog`), kept (the final grid) for the summary and the detail
    (pins.md §5.6, §6).  A node that contradicts its piece's sets (:func:`pieces_hold`): the cycle again with the full
    scan (moved or coarse roots) or a 4x denser one (up to ``settings.scan_max``).

    .. math:: \bar\lambda = \frac{1}{T_p} \int_0^{T_p} \lambda(\theta)\,d\theta, \qquad
        \lambda(\theta) = \frac{\sum_j P_j(\theta)}{T_{sat}\,\omega_H\,k/z_1}

    Parameters
    ----------
    model, friction : the contact model (design, torque); a :class:`~gearcalc.pins.friction.PinFriction` or tuple.
    tol, grid : relative accuracy target; the crank-angle grids (:class:`CycleGrid`; None: its defaults).
    n_initial : first-level intervals per piece (:func:`integrate_adaptive`) where the breakpoints give that many.
    rule : ``"trapezoid"`` (pins.md §6), or opt-in a Gauss-Kronrod pair per piece (``"gk7"``, ``"gk15"``).
    prior, prior_width : the located sign changes of the same design's cycle at a nearby torque
        (:attr:`ContactCycle.roots`), moved within +-``prior_width`` T_p (:func:`locate_breakpoints`).

    Returns
    -------
    cycle : ContactCycle
        The cycle mean and its error, the solved states on the final grid, the breakpoints and the losses.

    Examples
    --------
    Stiff contacts reproduce the rigid ideal level (pins.md §5.7; 0.174820 at the ideal level):

    >>> from gearcalc.pins.contact import MULTIPLIER, CycloidProfile, contact_law
    >>> g = Cycloid.from_curtate_ratio(21, 22, 3.9, 0.75, 1.95)
    >>> model = ContactModel(g, CycloidProfile(g, 0.0, 0.0), contact_law("linear", stiffness=1e9), 1e4, MULTIPLIER)
    >>> c = mean_loss_ratio(model, (0.1, 0.1, False), tol=1e-6)
    >>> c.converged, round(c.loss_ratio, 6)
    (True, 0.17482)

    References
    ----------
    .. [1] A. P. Prudnikov, «Потери мощности в контакте цевок и зубьев планетарной передачи типа K-H-V», Машиностроение
       (seed file 000_fe288dec6e7c72f0.txt); docs/spec/pins.md §5.6, §6.
    """
    grid = CycleGrid() if grid is None else grid
    friction = friction if isinstance(friction, PinFriction) else PinFriction(*friction)
    full = dataclasses.replace(grid, coarse_scan=None, at_once=0)      # a recomputation's grid
    g = model.g
    if model.window is None and grid.prefilter:
        model.set_window()
    rows = model.layout()[0]             # the window is fixed for this cycle (a failing one recomputes it)
    found, edges, n_scan = locate_breakpoints(model, grid.n_scan, tol, friction.rolls, grid.coarse_scan, prior,
                                              prior_width)
    log = _NodeLog(model, friction, found, edges)
    q = integrate_adaptive(log, edges, tol=tol, n_max=grid.n_max, n_start=grid.n_start, n_initial=n_initial,
                           rule=rule, n_min=grid.n_min, at_once=grid.at_once)
    if rule != "trapezoid":
        log.piece_ends()
    solved = concat_states(log.cache)
    dense = gk_interpolated(solved, q, rule, model.settings.dense_per_period) if rule != "trapezoid" else None
    held = log.hold(dense, friction.rolls, tol)
    if not held and not found.scanned:
        # a sign change the moved roots do not hold: the full scan (pins.md §6)
        return mean_loss_ratio(model, friction, tol, full, n_initial, rule)
    if not held and n_scan < model.settings.scan_max and deflection_sized(solved.tau, g, model.settings.travel_max):
        # nor the full scan's: 4x denser (pins.md §6), also for later passes; not beyond a deflection (flagged)
        model.scan_n = 4 * n_scan
        return mean_loss_ratio(model, friction, tol, dataclasses.replace(full, n_scan=4 * n_scan), n_initial, rule)
    sol = solved if dense is None else concat_states([solved, dense[0]])
    sol.phase, sol.zeta = model.phases(sol.theta, sol.rows)
    if not model.window_holds(sol.tau, sol.theta):
        model.window = None        # the window's tau bound does not hold: every pin, every angle
        return mean_loss_ratio(model, friction, tol, dataclasses.replace(full, prefilter=False), n_initial, rule, None,
                               prior_width)
    model.roots = found
    # the states' equilibria are met to 1/100 of the tolerance (:func:`equilibrium_residual`): no error below that
    err = max(float(q.err[0]), model.settings.inner_share * tol * abs(float(q.value[0])))
    return ContactCycle(float(q.value[0]), err, q.converged, solved.theta.size, q, sol, edges, found,
                        (g.R_b, friction.mu_eff, friction.sliding, friction.rolls, log.scale, friction.law),
                        log.record(rows) if dense is None else None, held)


# ============================================================ cycle metrics (pins.md §5.7, §8)

def engagement_metrics(sol: Solution, spin, low: float = 0.1):
    r"""The paper's circular-profile metrics from one period of all pins (pins.md §5.7(b)).

    All pins' samples together cover one full engagement (a pin's history has period 2 pi, the pins
    are T_p apart).  They are ordered by zeta = theta - phi_j (time order).  The loaded interval is the
    longest run of consecutive samples with a loaded contact.

    .. math:: \frac{\max_{second\ half} F}{\max_{first\ half} F}, \qquad \zeta = \theta - \varphi_j

    Parameters
    ----------
    sol : Solution
        The states over one period.
    spin : ndarray
        Pin spin per unit crank speed, [-] (:func:`contact_losses`).
    low : float, optional
        The share of max |spin| below which the spin is low, [-].

    Returns
    -------
    dict: exit_entry_force_ratio (max F in the second half of the loaded interval / max in the first),
    spin_reversals (sign changes of the spin in the interval), low_spin_fraction (share of the interval
    with |spin| < low max|spin|; None when the pins do not spin), loaded_from, loaded_to (zeta ends) [rad].

    Examples
    --------
    >>> from gearcalc.pins.contact import MULTIPLIER, CycloidProfile, contact_law
    >>> g = Cycloid.from_curtate_ratio(21, 22, 3.9, 0.75, 1.95)
    >>> model = ContactModel(g, CycloidProfile(g, 0.0, 0.0), contact_law("linear", stiffness=1e5), 1e4, MULTIPLIER)
    >>> sol = mean_loss_ratio(model, (0.1, 0.1, False), tol=1e-5).sol
    >>> m = engagement_metrics(sol, contact_losses(sol, g.R_b, 0.1, 0.1, False)[1])
    >>> m["spin_reversals"], m["low_spin_fraction"], round(m["loaded_to"] - m["loaded_from"], 3)   # k = 1: about pi
    (0, None, 3.142)

    References
    ----------
    .. [1] A. P. Prudnikov, «Потери мощности в контакте цевок и зубьев планетарной передачи типа K-H-V» (Power losses in
       pins and teeth contact area of KHV-type planetary gearing), Машиностроение (seed file 000_fe288dec6e7c72f0.txt);
       its circular-profile findings; docs/spec/pins.md §5.7(b).
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
    r"""Angular free play of the unloaded satellite at crank angles theta.

    (tau_minus, tau_plus) [rad] (``sides``: only these of the two directions, in this order, -1.0 for tau_minus and
    1.0 for tau_plus).

    tau_plus > 0 (tau_minus < 0) is the rotation from nominal at which the first pair touches, the root of
    max_j delta_j(tau) = 0; 0 where a pair already touches or interferes at nominal; +-``limit`` (default pi/z1)
    where none touches within it.  Each side starts from the least rotation at which a pair's convex bound
    delta_j(0) - (X x n)_j tau + (R_p + e) tau^2/2 reaches 0 (the bound of :meth:`ContactModel.set_window`, from
    |d^2 delta/d tau^2| <= |X| for a fixed normal: close below the first touch), doubled from there until a pair
    touches (once or twice), then the root to 1e-15 rad (:func:`gearcalc.roots.find_root`); where the start already
    touches (a profile's curvature turns the normal), the root is found in [0, start].  Before 2026-11-27 the
    doubling started at 1e-12 rad: ~30 more contact evaluations per side, the same roots to 1e-15 rad.  The
    backlash is min over theta of tau_plus - tau_minus (:func:`backlash`).

    .. math:: \tau_+ = \min\{\tau > 0 : \max_j \delta_j(\tau) = 0\}, \qquad
        \tau_- = \max\{\tau < 0 : \max_j \delta_j(\tau) = 0\}

    Parameters
    ----------
    model : ContactModel
        The contact model (its profile and gear).
    theta : ndarray
        Crank angles, [rad].
    limit : float, optional
        The largest rotation searched, [rad] (default pi/z1).
    sides : tuple of float, optional
        Only these directions (-1.0, 1.0).

    Returns
    -------
    tau_minus, tau_plus : ndarray
        The free play each way, [rad].

    Examples
    --------
    >>> from gearcalc.pins.contact import MULTIPLIER, CycloidProfile, contact_law
    >>> g = Cycloid.from_curtate_ratio(21, 22, 3.9, 0.75, 1.95)
    >>> model = ContactModel(g, CycloidProfile(g, 0.0, 0.0), contact_law("linear", stiffness=1e5), 1e4, MULTIPLIER)
    >>> [abs(float(t[0])) for t in free_play(model, np.array([0.1]))]   # an unmodified cycloid: no play
    [0.0, 0.0]

    References
    ----------
    .. [1] docs/spec/pins.md §5.3 (backlash), §8.
    """
    pose = model.pose(theta)
    limit = limit or math.pi / model.g.z1
    ct0 = model.contacts(pose, np.zeros(pose.theta.size))
    return tuple(direction * _first_touch(model, pose, ct0, direction, limit) for direction in sides)


def _first_touch(model: ContactModel, pose, ct0, direction: float, limit: float):
    """|tau| of the first touch in ``direction`` at the crank angles of ``pose`` (:func:`free_play`).

    ``ct0``: the contacts at nominal.  Doubled from the convex bound's start until a pair touches, then the root.
    """
    n = pose.theta.size
    R = model.g.R_p + model.g.e

    def hmax(t, p=pose):
        return np.max(model.contacts(p, t).delta, axis=(0, 1))

    h0 = np.max(ct0.delta, axis=(0, 1))
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
    return np.where(miss, limit, root)


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
    r"""The largest travel of a pin centre under the load, as a share of the pin radius.

    The largest travel of a pin centre relative to the satellite's nominal (rigid conjugate) pose under the load, as
    a share of the pin radius: :math:`\max|\tau| (R_p + e)/R_b` [-] (pins.md §7).

    The contact model holds the satellite's rotation tau to be deflection-sized; a pin centre that moves by a good
    part of its radius (a profile with large free play, on few teeth) meets its tooth far from its nominal place,
    and the moment balance there can have several solutions: above ``settings.travel_max`` (0.25) the random sample's
    designs disagreed with the crank angles solved one by one by up to 10 %, below it (0.004-0.23, the paper designs
    0.004-0.042) they agreed to the reference's own error.

    .. math:: \frac{\max|\tau|\,(R_p + e)}{R_b}

    Parameters
    ----------
    tau : ndarray
        The satellite's rotations under the load, [rad].
    g : Cycloid
        The gear.

    Returns
    -------
    travel : float
        The largest travel over the pin radius, [-].

    Examples
    --------
    >>> g = Cycloid.from_curtate_ratio(21, 22, 3.9, 0.75, 1.95)
    >>> round(pin_travel(np.array([1e-3, -2e-3]), g) * g.R_b / (g.R_p + g.e), 12)
    0.002

    References
    ----------
    .. [1] docs/spec/pins.md §7.
    """
    return float(np.max(np.abs(tau))) * (g.R_p + g.e) / g.R_b


def deflection_sized(tau, g: Cycloid, travel_max: float = DEFAULT_SETTINGS.travel_max) -> bool:
    r"""Whether the satellite's rotation ``tau`` [rad] under the load is deflection-sized.

    :func:`pin_travel` at most ``settings.travel_max`` (else the contact level's results are flagged, pins.md §7).

    .. math:: \frac{\max|\tau|\,(R_p + e)}{R_b} \le \text{travel\_max}

    Parameters
    ----------
    tau : ndarray
        The satellite's rotations under the load, [rad].
    g : Cycloid
        The gear.
    travel_max : float, optional
        The largest travel over the pin radius, [-] (default 0.25).

    Returns
    -------
    sized : bool
        True when the rotation is deflection-sized.

    Examples
    --------
    >>> g = Cycloid.from_curtate_ratio(21, 22, 3.9, 0.75, 1.95)
    >>> deflection_sized(np.array([1e-3]), g), deflection_sized(np.array([0.1]), g)
    (True, False)

    References
    ----------
    .. [1] docs/spec/pins.md §7.
    """
    return pin_travel(tau, g) <= travel_max
