"""KHV pin gearing, level ``ideal``: the friction-consistent cycles (pins.md §4.9).

Friction in the satellite's balance, each mode (reducer, multiplier) solved with its own forces on the
nodes of :func:`gearcalc.pins.ideal_cycles`, refined to the tolerance; jams; the crank torque and the
crank-bearing force over the cycle.  Units N, mm, rad.

References
----------
.. [1] The paper (Prudnikov, seed 000), cited in full in :mod:`gearcalc.pins`; docs/spec/pins.md §4.9.
.. [2] Blagojević et al. (friction forces in the satellite's balance), cited in full in :mod:`gearcalc.pins`.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from .cycle import disc_offsets, disc_sum_range
from .geometry import as_arrays, Cycloid, MULTIPLIER, REDUCER
from .ideal import colsum, contacts_geo, GearTable, IdealCycles, node_sums
from ..quadrature import richardson_mean

__all__ = ["consistent_node_values", "ConsistentCycles", "CONSISTENT_CHUNK_NODES", "REFINE_BLOCK", "CONSISTENT_N_MAX",
           "consistent_cycles", "REFINE_CELLS", "RefineJob", "crank_history"]


def consistent_node_values(sums, mu, sigma: int):
    r"""Friction-consistent forces, loss ratio and crank-bearing load at cycle nodes (pins.md §4.9), unit torque.

    From the friction-free node sums of :func:`node_sums` (rows :data:`NODE_ROWS`) and mu = mu_eff.  The
    friction forces mu F_i act against the sliding; the moment balance of the satellite about O1 with
    F_i = c |l_i| gives

    .. math::

        c = \frac{T_{sat}}{D_\sigma},\quad D_{reducer} = S - \mu Q,\quad D_{multiplier} = S + \mu Q,\quad
        Q = N - r_{p1} U_x,\quad \lambda = \frac{P_{loss}}{T_{sat} |\omega_V|} = \frac{\mu N}{D_\sigma}

    and the crank-bearing force on the satellite B = -sum of the pin forces, in the crank frame (x along
    the crank arm O1):

    .. math::

        B_x = c (S_x \mp \mu U_y),\quad B_y = c (\pm S + \mu r_{p1} U_x)/r_{p1}\quad (\text{upper sign: reducer})

    and the crank torque T_H = O1 x B = e B_y (the torque the crank's shaft applies).  ``crank`` is the
    crank torque along the power flow, sigma T_H (the input torque of a reducer, the output torque of a
    multiplier).  A node with D <= 0 jams (no positive normal-force solution).

    Parameters
    ----------
    sums : ndarray, shape (len(NODE_ROWS), n)
        node sums of :func:`node_sums` [mm^2, mm] (N, S, r_p1 U_x, S_x, U_y, ...).
    mu : float or ndarray, shape (n,)
        mu_eff [-].
    sigma : int
        +1 reducer, -1 multiplier.

    Returns
    -------
    dict of arrays (n,): D [mm^2], lam [-], c = F/(T_sat |l|) [1/mm^2], Bx, By = B/T_sat [1/mm], and
    jam (D <= 0).

    Examples
    --------
    >>> sums = np.array([[1.0], [4.0], [0.5], [0.1], [-0.2]] + [[0.0]] * 5)   # N, S, r_p1 U_x, S_x, U_y
    >>> v = consistent_node_values(sums, 0.1, REDUCER)
    >>> float(v["D"][0]), float(v["lam"][0])     # S - mu Q, Q = N - r_p1 U_x = 0.5
    (3.95, 0.02531645569620253)

    References
    ----------
    pins.md §4.9 [derived; checked against an independent model]; Blagojević et al. 2012 (model 2).
    """
    N, S, Q = sums[0], sums[1], sums[0] - sums[2]
    D = S - sigma * mu * Q
    with np.errstate(divide="ignore", invalid="ignore"):
        lam = mu * N / D
        c = 1.0 / D
    return {"D": D, "lam": lam, "c": c, "jam": ~(D > 0.0)}


@dataclass
class ConsistentCycles:
    """The friction-consistent model (pins.md §4.9) per operating point and mode, in unit scalings.

    Arrays of shape (2, P) (row 0 the reducer, row 1 the multiplier): loss_ratio, err, converged, jammed,
    n_crank; the others, of shape (P,), are those of each point's own mode (``mode``).

    loss_ratio, err, converged : cycle mean of lambda_sigma = P_loss/(T_sat |omega_V|), its error
        |Q_2N - Q_N| and the acceptance (pins.md §6); NaN where the mode jams;
    jammed : some crank angle has no positive normal-force solution (D <= 0);
    n_crank : crank-angle intervals of the grid the value comes from;
    force, force_phase : largest F/T_sat of a contact [1/mm] and its load-side phase [rad];
    loss, loss_phase : largest P/(mu T_sat |omega_V|) of a contact and its phase [rad]; total : largest summed
        one over the cycle;
    stress : largest F/(T_sat R_eff) [1/mm^2] (the Hertz peak pressure is sqrt(E* T_sat stress/(pi b)));
    bearing_max, bearing_mean : largest and mean |B|/T_sat of one disc's crank bearing [1/mm];
    crank_mean, crank_min, crank_max : crank torque along the power flow over T_sat, summed over the discs [-];
    bearing_pmean, bearing_pmean_err : cycle mean of (|B|/T_sat)^p, p = ``bearing_exponent`` [1/mm^p], and its
        quadrature error (the trapezoid rules at h and 2h differ by it; the mean is their Richardson value).
    The peaks are the largest values at the nodes of the final grid (error O(h^2)).  The result of one point
    with one disc on a gear solved alone (a design computed alone) also has ``scalars``: the same values as
    Python scalars (each field's ``[..., 0].tolist()``).
    """

    loss_ratio: np.ndarray
    err: np.ndarray
    converged: np.ndarray
    jammed: np.ndarray
    n_crank: np.ndarray
    force: np.ndarray
    force_phase: np.ndarray
    loss: np.ndarray
    loss_phase: np.ndarray
    total: np.ndarray
    stress: np.ndarray
    bearing_max: np.ndarray
    bearing_mean: np.ndarray
    crank_mean: np.ndarray
    crank_min: np.ndarray
    crank_max: np.ndarray
    bearing_pmean: np.ndarray
    bearing_pmean_err: np.ndarray


CONSISTENT_CHUNK_NODES = 2 ** 18
"""Points x final-grid nodes of the friction-consistent evaluation done at once (~20 arrays of 8 bytes a node:
~40 MB); a larger sweep is evaluated a chunk of points at a time (the same numbers: points are independent)."""
REFINE_BLOCK = 2 ** 20
"""(friction, mode) pairs x new nodes of the refining doublings evaluated at once (memory)."""
CONSISTENT_N_MAX = 2 ** 16
"""Cap of the refining quadrature of the friction-consistent model (intervals per period): near the jam limit
lambda has a pole beside the cycle and converges slowly; the value is then reported with its error."""


def _point_nodes(cyc: IdealCycles, gear):
    """Flat indices of the final-grid nodes of each point's gear, the point of each, and the counts."""
    gg = cyc.grid_gear
    if gear.size == 1 and cyc.solved.size == 1 and gg.size and gear[0] == cyc.solved[0]:   # one design
        return np.arange(gg.size), np.zeros(gg.size, dtype=np.int64), np.array([gg.size])
    order_start = np.flatnonzero(np.diff(gg, prepend=-1) != 0) if gg.size else np.zeros(0, dtype=np.int64)
    first = np.full(cyc.status.size, -1, dtype=np.int64)
    cnt = np.zeros(cyc.status.size, dtype=np.int64)
    if gg.size:
        runs = np.diff(np.append(order_start, gg.size))
        first[gg[order_start]] = order_start
        cnt[gg[order_start]] = runs
    counts = cnt[gear]
    pt = np.repeat(np.arange(gear.size), counts)
    starts = np.cumsum(counts) - counts
    idx = np.arange(int(counts.sum())) - starts[pt] + first[gear][pt]
    return idx, pt, counts


@dataclass(frozen=True)
class _Points:
    """Operating points of :func:`consistent_cycles`.

    Arrays (P,): gear, mu_eff, discs, mode sigma, the bearing's load exponent p.
    """

    gear: np.ndarray
    mu: np.ndarray
    n_d: np.ndarray
    sigma: np.ndarray
    p: np.ndarray

    def take(self, sel):
        """The points ``sel`` (an index array or a slice)."""
        return _Points(self.gear[sel], self.mu[sel], self.n_d[sel], self.sigma[sel], self.p[sel])


def consistent_cycles(cyc: IdealCycles, gear, mu, n_discs=1, tol: float = 1e-6, mode=None,
                      chunk_nodes: int = CONSISTENT_CHUNK_NODES, bearing_exponent=10.0 / 3.0) -> ConsistentCycles:
    r"""The friction-consistent efficiency model (pins.md §4.9) of operating points, both modes.

    Every point has a solved gear (``gear``: its index in the gears of ``cyc``, which must be admissible)
    and an effective friction mu_eff.  The friction-free node sums that :func:`ideal_cycles` keeps on its
    final grid give, at any friction, the friction-consistent loss ratio at every node
    (:func:`consistent_node_values`); its cycle mean follows from the same trapezoid rule on the same
    pieces at the final level L and at L-1, L-2 (:func:`_cycle_means`).  Where that is not accepted
    (friction near the jam limit), the doubling continues from the final grid, evaluating only the new
    nodes, all gears together (:func:`_refine_consistent`), up to :data:`CONSISTENT_N_MAX`.  A mode jams
    where D <= 0 at some node.  One point with one disc on the whole grid of a gear solved alone takes a
    shorter path to the same numbers, bit for bit (:func:`_one_point`).

    .. math:: Q = Q_L + \frac{Q_L - Q_{L-1}}{3}, \qquad E = |Q_L - Q_{L-1}| \le \max(\text{tol}\,|Q|,\ 10^{-14}),
        \qquad \text{jam where } D \le 0

    Parameters
    ----------
    cyc : IdealCycles
    gear : ndarray of int, shape (P,)
    mu : ndarray, shape (P,)
    n_discs : int or ndarray (P,)
    tol : relative accuracy target.
    mode : int or ndarray (P,), optional
        sigma of each point (+1 reducer, -1 multiplier; default multiplier): the mode whose forces, peaks,
        crank-bearing force and crank torque are computed (the cycle means are computed for both).
    chunk_nodes : int
        points x nodes evaluated at once (memory); more are evaluated a chunk of points at a time.

    Returns
    -------
    ConsistentCycles

    Examples
    --------
    >>> from gearcalc.pins import ideal_cycles
    >>> g = as_arrays(Cycloid.from_curtate_ratio(10, 11, 1.95, 0.75, 1.755))   # pins.md §4.9 reference
    >>> cc = consistent_cycles(ideal_cycles(g, 1), np.array([0]), np.array([0.1]))
    >>> round(1.0 / (1.0 + float(cc.loss_ratio[0, 0])), 5), round(1.0 - float(cc.loss_ratio[1, 0]), 5)
    (0.83078, 0.84594)

    References
    ----------
    pins.md §4.9, §6.
    """
    gear = np.atleast_1d(np.asarray(gear, dtype=np.int64))
    P = gear.size
    pts = _Points(gear, np.zeros(P) + mu, np.zeros(P, dtype=np.int64) + n_discs,
                  np.zeros(P, dtype=np.int64) + (MULTIPLIER if mode is None else mode), np.zeros(P) + bearing_exponent)
    return _dispatch(cyc, pts, tol, chunk_nodes)


def _dispatch(cyc: IdealCycles, pts: _Points, tol: float, chunk_nodes: int) -> ConsistentCycles:
    """:func:`_one_point` where it applies, else :func:`_many_points`."""
    if pts.gear.size == 1 and pts.n_d[0] == 1 and cyc.solved is not None and cyc.solved.size == 1 \
            and pts.gear[0] == cyc.solved[0] and cyc.grid_t.size:
        return _one_point(cyc, float(pts.mu[0]), int(pts.sigma[0]), tol, float(pts.p[0]))
    return _many_points(cyc, pts, tol, chunk_nodes)


def _many_points(cyc: IdealCycles, pts: _Points, tol: float, chunk_nodes: int) -> ConsistentCycles:
    """:func:`consistent_cycles` of many points: each distinct point once, a chunk of points at a time."""
    P = pts.gear.size
    if P > 1:  # points of the same gear, friction, discs, mode and exponent (a torque or speed axis) once
        key = np.stack((pts.gear, pts.mu.view(np.int64), pts.n_d, pts.sigma, pts.p.view(np.int64)), axis=1)
        _, first, inv = np.unique(key, axis=0, return_index=True, return_inverse=True)
        if first.size < P:
            sel = np.sort(first)                   # each distinct point where it first appears, in order
            rank = np.empty(first.size, dtype=np.int64)
            rank[np.argsort(first)] = np.arange(first.size)
            back = rank[inv.reshape(-1)]
            part = _dispatch(cyc, pts.take(sel), tol, chunk_nodes)
            return ConsistentCycles(**{f: getattr(part, f)[..., back] for f in ConsistentCycles.__dataclass_fields__})
    per_gear = np.bincount(cyc.grid_gear, minlength=cyc.status.size) if cyc.grid_gear.size else \
        np.zeros(cyc.status.size, dtype=np.int64)
    nodes = per_gear[pts.gear]
    if P > 1 and int(nodes.sum()) > chunk_nodes:   # many points (a sweep): a chunk of points at a time
        chunk = np.cumsum(nodes) // chunk_nodes        # non-decreasing chunk number per point
        cuts = [0, *(np.flatnonzero(np.diff(chunk)) + 1).tolist(), P]
        parts = [_dispatch(cyc, pts.take(slice(a, b)), tol, 1 << 62) for a, b in zip(cuts[:-1], cuts[1:])]
        return ConsistentCycles(**{f: np.concatenate([getattr(q, f) for q in parts], axis=-1)
                                   for f in ConsistentCycles.__dataclass_fields__})
    return _points_cycles(cyc, pts, tol)


@dataclass
class _OnGrid:
    """Points on their gears' final grids.

    Per node the point ``pt``, the node sums, weights (3, n), t, the midpoints ``mid``; per point its first node
    ``seg``, node count, table row ``slot``.
    """

    pt: np.ndarray
    sums: np.ndarray
    w: np.ndarray
    t: np.ndarray
    mid: np.ndarray
    seg: np.ndarray
    counts: np.ndarray
    slot: np.ndarray


def _gather(cyc: IdealCycles, gear) -> _OnGrid:
    """The final-grid nodes of each point's gear (:func:`_point_nodes`), gathered point by point."""
    P = gear.size
    idx, pt, counts = _point_nodes(cyc, gear)
    if idx.size == cyc.grid_t.size and (P == 1 or np.array_equal(idx, np.arange(idx.size))):
        # the points take the whole grid in its order (one point, or one point a gear in solve order): no gathers
        sums, w, t, mid = cyc.grid_sums, cyc.grid_weights, cyc.grid_t, cyc.grid_mid
    else:
        sums, w, t, mid = cyc.grid_sums[:, idx], cyc.grid_weights[:, idx], cyc.grid_t[idx], cyc.grid_mid[idx]
    if cyc.solved.size == 1:
        slot = np.zeros(P, dtype=np.int64)
    else:
        where = np.zeros(cyc.status.size, dtype=np.int64)
        where[cyc.solved] = np.arange(cyc.solved.size)  # a gear's row of the table (solved in z2 order)
        slot = where[gear]
    return _OnGrid(pt, sums, w, t, mid, np.cumsum(counts) - counts, counts, slot)


_FIELDS = ("force", "force_phase", "loss", "loss_phase", "total", "stress", "bearing_max", "bearing_mean",
           "crank_mean", "crank_min", "crank_max", "bearing_pmean", "bearing_pmean_err")
"""The fields of :class:`ConsistentCycles` of each point's own mode."""


def _points_cycles(cyc: IdealCycles, pts: _Points, tol: float) -> ConsistentCycles:
    """:func:`consistent_cycles` of distinct points, all evaluated together.

    The cycle means of both modes (:func:`_cycle_means`), the fields of each point's own mode
    (:func:`_own_mode`), and the refinement of the means the final grid does not accept (:func:`_refine_points`).
    """
    P = pts.gear.size
    grid = _gather(cyc, pts.gear)
    block = np.full((17, P), np.nan)                    # one allocation for every field (rows as views)
    res = {"loss_ratio": block[0:2], "err": block[2:4]}
    res.update({k: block[4 + r] for r, k in enumerate(_FIELDS)})
    conv = np.zeros((2, P), dtype=bool)
    jam = np.zeros((2, P), dtype=bool)
    n_crank = np.zeros((2, P), dtype=np.int64) + cyc.n_crank[pts.gear]
    lam2 = _cycle_means(grid, pts, tol, res, (conv, jam))
    _own_mode(cyc.table, grid, pts, res)
    own_jam = np.where(pts.sigma == REDUCER, jam[0], jam[1])
    if own_jam.any():
        for key in _FIELDS:
            res[key] = np.where(own_jam, np.nan, res[key])
    _refine_points(cyc.table, grid, pts, lam2, tol, (res, conv, jam, n_crank))
    zero = pts.mu == 0.0                               # f = f_k = f_c = 0: lambda = 0 exactly (pins.md §9)
    res["loss_ratio"][:, zero], res["err"][:, zero] = 0.0, 0.0
    conv[:, zero] = True
    return ConsistentCycles(converged=conv, jammed=jam, n_crank=n_crank, **res)


def _cycle_means(grid: _OnGrid, pts: _Points, tol: float, res: dict, flags: tuple):
    """The cycle means of lambda of both modes on the final grids (rows 0 reducer, 1 multiplier).

    With their errors, acceptance and jams (``flags``: converged, jammed, filled in).  Returns lambda at the
    nodes, shape (2, n).

    Q_L + (Q_L - Q_{L-1})/3, E = |Q_L - Q_{L-1}|, accepted when E <= max(tol |Q|, 1e-14) on the two last
    doublings (pins.md §6); the three levels' trapezoid sums in one (sequential, per bin) bincount.
    """
    conv, jam = flags
    P, pt, sums, w = pts.gear.size, grid.pt, grid.sums, grid.w
    mu_n = pts.mu[pt]
    N, S, Q = sums[0], sums[1], sums[0] - sums[2]
    muQ = mu_n * Q
    D2 = np.stack((S - muQ, S + muQ))
    bad = ~(D2 > 0.0)
    if bool(bad.any()):
        jam[:] = np.bincount(np.concatenate((pt, pt + P)), bad.ravel(), minlength=2 * P).reshape(2, P) > 0
        with np.errstate(divide="ignore", invalid="ignore"):
            lam2 = np.where(bad, 0.0, (mu_n * N) / D2)
    else:
        lam2 = (mu_n * N) / D2
    pt6 = np.concatenate([pt + r * P for r in range(6)])
    q = np.bincount(pt6, (w[None, :, :] * lam2[:, None, :]).ravel(), minlength=6 * P).reshape(2, 3, P)
    E1, E0 = np.abs(q[:, 0] - q[:, 1]), np.abs(q[:, 1] - q[:, 2])
    ok = (E1 <= np.maximum(tol * np.abs(q[:, 0]), 1e-14)) & (E0 <= np.maximum(tol * np.abs(q[:, 1]), 1e-14))
    res["loss_ratio"][:] = np.where(jam, np.nan, q[:, 0] + (q[:, 0] - q[:, 1]) / 3.0)
    res["err"][:] = np.where(jam, np.nan, E1)
    conv[:] = ok & ~jam
    return lam2


def _own_mode(G: GearTable, grid: _OnGrid, pts: _Points, res: dict):
    """Forces, peaks, crank bearing and crank torque of each point's own mode on its final grid (pins.md §4.9).

    The peaks are the largest values at the nodes (exact: no rounding), with the load-side phase of the first
    node holding the force and loss peak; the means Richardson-corrected (pins.md §8); n_d > 1 discs sum the
    crank torques (pins.md §12.7).
    """
    P, pt, sums, t, seg, counts = pts.gear.size, grid.pt, grid.sums, grid.t, grid.seg, grid.counts
    r_p1, z2 = G.r_p1[grid.slot], G.z2[grid.slot]
    mu_n, sg = pts.mu[pt], pts.sigma[pt]
    S, Q = sums[1], sums[0] - sums[2]
    D = S - (sg * mu_n) * Q
    with np.errstate(divide="ignore", invalid="ignore"):
        c = np.where(D > 0.0, 1.0 / D, np.nan)
    F = sums[5] * c
    Bx = c * (sums[3] - sg * mu_n * sums[4])
    By = c * (sg * S + mu_n * sums[2]) / r_p1[pt]
    Bm = np.hypot(Bx, By)
    crank = sg * (r_p1[pt] / _ratio_of(G, grid.slot)[pt]) * By   # sigma e B_y, e = r_p1/u
    Pl = sums[7] * c * 1e-3
    _own_peaks(np.stack((F, Pl, sums[0] * c * 1e-3, sums[9] * c, Bm, crank)), grid, P, z2, res)
    finite = np.isfinite(c)
    crank_m = crank
    if not finite.all():
        Bm, crank_m = np.where(finite, Bm, 0.0), np.where(finite, crank, 0.0)
    wr = richardson_mean(grid.w[0], grid.w[1])        # Richardson-corrected means (pins.md §8)
    means = np.bincount(np.concatenate((pt, pt + P)), np.concatenate((wr * Bm, wr * crank_m)), minlength=2 * P)
    res["bearing_mean"], res["crank_mean"] = means[:P], means[P:] * pts.n_d
    Bp = Bm ** pts.p[pt]                       # the bearing's equivalent load (pins.md §8.2): mean of |B|^p
    res["bearing_pmean"] = np.bincount(pt, wr * Bp, minlength=P)
    res["bearing_pmean_err"] = np.abs(np.bincount(pt, (grid.w[0] - grid.w[1]) * Bp, minlength=P))
    for i in np.flatnonzero(pts.n_d > 1):      # the discs' torques summed (pins.md §12.7): a handful of points
        sl = slice(seg[i], seg[i] + counts[i])
        # both one-sided limits at every disc's jump (NaN where the mode jams at every node: no crank torque)
        res["crank_min"][i], res["crank_max"][i] = disc_sum_range(t[sl], crank[sl],
                                                                  disc_offsets(int(pts.n_d[i]), int(z2[i])), 1.0)


def _own_peaks(stacked, grid: _OnGrid, P: int, z2, res: dict):
    """The peaks of ``stacked`` per point, and the phases of the force and loss peaks' contacts.

    ``stacked``: F, P_loss, the total, F/R_eff, |B|, the crank torque at the nodes.
    """
    pt, sums, t = grid.pt, grid.sums, grid.t
    nonempty = grid.counts > 0
    segs, cols = grid.seg[nonempty], np.flatnonzero(nonempty)
    if not segs.size:
        return
    # the maxima are exact (no rounding): one point reduces its whole grid
    peak = np.fmax.reduce(stacked, axis=1)[:, None] if P == 1 else np.fmax.reduceat(stacked, segs, axis=1)
    for r, key in enumerate(("force", "loss", "total", "stress", "bearing_max", "crank_max")):
        res[key][cols] = peak[r]
    crank = stacked[5]
    res["crank_min"][cols] = np.fmin.reduce(crank) if P == 1 else np.fmin.reduceat(crank, segs)
    for key, arr, row in (("force", stacked[0], 6), ("loss", stacked[1], 8)):   # the load-side phase of the peak's
        hit = np.flatnonzero(arr == res[key][pt])                                # contact (the first node holding
        if hit.size:                                                             # the maximum)
            ph = pt[hit]
            first = np.ones(hit.size, dtype=bool)
            first[1:] = ph[1:] != ph[:-1]
            h, pts_ = hit[first], ph[first]
            res[key + "_phase"][pts_] = 2.0 * math.pi * ((sums[row, h] + t[h]) / z2[pts_])


def _refine_points(G: GearTable, grid: _OnGrid, pts: _Points, lam2, tol: float, state: tuple):
    """Continue the doubling where the final grid does not meet the tolerance (friction near the jam limit).

    Every (point, mode) pair not accepted, not jammed and of mu > 0, of all gears at once
    (:func:`_refine_consistent`); ``state``: (res, converged, jammed, n_crank), updated.
    """
    res, conv, jam, n_crank = state
    redo_m, redo_p = np.nonzero(~conv & ~jam & (pts.mu > 0.0)[None, :])
    if not redo_p.size:
        return
    job = _refine_job(G, grid, pts, lam2, tol, (redo_m, redo_p))
    val, err, cv, nn, jm = _refine_consistent(job)
    res["loss_ratio"][redo_m, redo_p] = np.where(jm, np.nan, val)
    res["err"][redo_m, redo_p] = np.where(jm, np.nan, err)
    conv[redo_m, redo_p], n_crank[redo_m, redo_p] = cv, nn
    jam[redo_m, redo_p] |= jm


def _refine_job(G: GearTable, grid: _OnGrid, pts: _Points, lam2, tol: float, pairs: tuple):
    """The :class:`RefineJob` of the (mode, point) ``pairs``.

    Their gears' pieces from the final grids and each pair's trapezoid sums at levels L and L-1 (each summed as
    numpy sums a row: the same numbers as one gear).
    """
    mm, pp = pairs
    slots, gear_of = np.unique(grid.slot[pp], return_inverse=True)
    gear_of = gear_of.reshape(-1)
    rep = pp[np.unique(gear_of, return_index=True)[1]]      # a point of each gear (they share its grid)
    a, b, n, owner = _grid_pieces(grid, rep)
    start, length = grid.seg[pp], grid.counts[pp]
    flat = lam2.ravel()
    base = mm * lam2.shape[1] + start
    q, q_prev = np.empty(pp.size), np.empty(pp.size)
    for L in np.unique(length).tolist():
        k = np.flatnonzero(length == L)
        cols = np.arange(L)
        lam = flat[base[k][:, None] + cols]
        at = start[k][:, None] + cols
        q_prev[k], q[k] = (lam * grid.w[1][at]).sum(axis=1), (lam * grid.w[0][at]).sum(axis=1)
    sigma = np.where(mm == 0, REDUCER, MULTIPLIER)
    return RefineJob(G, (a, b, n, owner), slots, gear_of, pts.mu[pp], sigma, (q, q_prev), tol)


def _grid_pieces(grid: _OnGrid, rep):
    """Pieces (a, b, intervals, owner) of the final grids of the points ``rep`` (one per gear), gear by gear."""
    cnt = grid.counts[rep]
    idx = np.arange(int(cnt.sum())) - np.repeat(np.cumsum(cnt) - cnt, cnt) + np.repeat(grid.seg[rep], cnt)
    t, mid = grid.t[idx], grid.mid[idx]
    gear = np.repeat(np.arange(rep.size), cnt)
    new_piece = np.empty(t.size, dtype=bool)
    new_piece[0] = True
    new_piece[1:] = (mid[1:] != mid[:-1]) | (gear[1:] != gear[:-1])
    start = np.flatnonzero(new_piece)
    count = np.concatenate((start[1:], [t.size])) - start
    return t[start], t[start + count - 1], count - 1, gear[start]


def _seq_sums(rows):
    """Sums of each row of a 2-D array in node order.

    Sums of each row of a 2-D array from 0.0 in node order (as ``np.bincount`` accumulates; a cumulative sum is
    sequential, unlike numpy's pairwise ``sum``).
    """
    return np.cumsum(rows, axis=1)[:, -1]


def _one_point(cyc: IdealCycles, mu: float, sigma: int, tol: float, p: float) -> ConsistentCycles:
    """:func:`consistent_cycles` of one point with one disc on the whole grid of a gear solved alone.

    The same formulas, sums (in node order) and acceptance, operation for operation, so the same numbers bit for
    bit; the bookkeeping runs on Python scalars and the per-node values are computed once for both modes (a
    design computed alone: a few hundred nodes, where numpy's cost per call dominates).
    """
    sums, w = cyc.grid_sums, cyc.grid_weights
    N, S = sums[0], sums[1]
    Q = N - sums[2]
    nan = math.nan
    muQ = mu * Q
    D2 = np.empty((2, Q.size))
    np.subtract(S, muQ, out=D2[0])
    np.add(S, muQ, out=D2[1])
    good = D2 > 0.0
    jam = [not g for g in good.all(axis=1).tolist()]
    if jam[0] or jam[1]:
        with np.errstate(divide="ignore", invalid="ignore"):
            lam2 = np.where(good, (mu * N) / D2, 0.0)
    else:
        lam2 = (mu * N) / D2
    loss_ratio, err, conv = [nan, nan], [nan, nan], [False, False]
    q = _seq_sums((w[None, :, :] * lam2[:, None, :]).reshape(6, -1)).reshape(2, 3).tolist() if mu != 0.0 else \
        [[0.0] * 3] * 2              # mu = 0: lambda = 0 exactly (set below)
    for m in range(2):
        q0, q1, q2 = q[m]
        E1, E0 = abs(q0 - q1), abs(q1 - q2)
        if not jam[m]:
            loss_ratio[m], err[m] = q0 + (q0 - q1) / 3.0, E1
            conv[m] = E1 <= max(tol * abs(q0), 1e-14) and E0 <= max(tol * abs(q1), 1e-14)
    n_crank = [int(cyc.n_crank[0])] * 2
    own = 0 if sigma == REDUCER else 1
    res = _one_point_own(cyc, mu, sigma, p, D2[own]) if not jam[own] else dict.fromkeys(_FIELDS, nan)
    state = (loss_ratio, err, conv, jam, n_crank)
    if mu > 0.0:
        _one_point_refine(cyc, mu, sigma, lam2, tol, state)
    else:                                              # f = f_k = f_c = 0: lambda = 0 exactly (pins.md §9)
        loss_ratio[:], err[:], conv[:] = [0.0, 0.0], [0.0, 0.0], [True, True]
    vals = np.array(list(res.values()))
    out = {k: vals[i:i + 1] for i, k in enumerate(res)}
    cc = ConsistentCycles(loss_ratio=np.array(loss_ratio)[:, None], err=np.array(err)[:, None],
                          converged=np.array(conv)[:, None], jammed=np.array(jam)[:, None],
                          n_crank=np.array(n_crank, dtype=np.int64)[:, None], **out)
    # the same values as Python scalars (what ``field[..., 0].tolist()`` gives), for the one point's outputs
    cc.scalars = dict(loss_ratio=loss_ratio, err=err, converged=conv, jammed=jam, n_crank=n_crank, **res)
    return cc


def _one_point_own(cyc: IdealCycles, mu: float, sigma: int, p: float, D) -> dict:
    """The fields of :func:`_one_point`'s own mode, as :func:`_own_mode` computes them, on Python scalars.

    D > 0 at every node (``D``: its denominators).
    """
    sums, w, t = cyc.grid_sums, cyc.grid_weights, cyc.grid_t
    G = cyc.table
    r_p1, z2 = float(G.r_p1[0]), int(G.z2[0])
    res = dict.fromkeys(_FIELDS, math.nan)
    smu = sigma * mu
    c = 1.0 / D
    stacked = np.empty((6, c.size))      # F, P_loss, the total, F/R_eff, |B|, the crank torque (rows as views)
    np.multiply(sums[5], c, out=stacked[0])
    Bx = c * (sums[3] - smu * sums[4])
    By = c * (sigma * sums[1] + mu * sums[2]) / r_p1
    np.hypot(Bx, By, out=stacked[4])
    crank = np.multiply(sigma * (r_p1 / float(G.Ze[0] - 1.0)), By, out=stacked[5])   # sigma e B_y, e = r_p1/u
    np.multiply(sums[7] * c, 1e-3, out=stacked[1])
    np.multiply(sums[0] * c, 1e-3, out=stacked[2])
    np.multiply(sums[9], c, out=stacked[3])
    peak = np.fmax.reduce(stacked, axis=1).tolist()
    for r, key in enumerate(("force", "loss", "total", "stress", "bearing_max", "crank_max")):
        res[key] = peak[r]
    res["crank_min"] = float(np.fmin.reduce(crank))
    for key, r, row in (("force", 0, 6), ("loss", 1, 8)):     # the load-side phase of the peak's contact
        h = int(stacked[r].argmax())                              # (the first node holding the maximum;
        if not stacked[r, h] == peak[r]:                          # argmax stops at a NaN, fmax skips it)
            hit = np.flatnonzero(stacked[r] == peak[r])
            h = int(hit[0]) if hit.size else -1
        if h >= 0:
            res[key + "_phase"] = 2.0 * math.pi * ((float(sums[row, h]) + float(t[h])) / z2)
    both = stacked[4:6]                                    # |B| and the crank torque
    if not np.isfinite(c).all():   # 1/D overflows where D is subnormal: those nodes count 0 in the means
        both = np.where(np.isfinite(c), both, 0.0)
    res["bearing_mean"], res["crank_mean"] = _seq_sums(richardson_mean(w[0], w[1]) * both).tolist()
    Bp = both[0] ** p                      # the bearing's equivalent load (pins.md §8.2): mean of |B|^p
    res["bearing_pmean"], d = _seq_sums(np.stack((richardson_mean(w[0], w[1]) * Bp, (w[0] - w[1]) * Bp))).tolist()
    res["bearing_pmean_err"] = abs(d)
    return res


def _one_point_refine(cyc: IdealCycles, mu: float, sigma: int, lam2, tol: float, state: tuple):
    """Continue the doubling of :func:`_one_point`'s modes the final grid does not accept (near the jam limit).

    ``state``: the lists (loss_ratio, err, converged, jammed, n_crank) over the modes, updated.
    """
    loss_ratio, err, conv, jam, n_crank = state
    redo = [m for m in range(2) if not conv[m] and not jam[m]]
    if not redo:
        return
    sig = [REDUCER if m == 0 else MULTIPLIER for m in redo]
    if cyc.n_piece is not None:
        val, e, cv, nn, jm = _refine_one(cyc.table, cyc.pieces, cyc.n_piece, cyc.grid_weights, mu, sig, lam2[redo],
                                         tol)
    else:
        grid = _gather(cyc, cyc.solved[:1])             # a gear solved with others' bookkeeping: the general path
        pts = _Points(cyc.solved[:1], np.array([mu]), np.ones(1, dtype=np.int64), np.array([sigma]), np.zeros(1))
        job = _refine_job(cyc.table, grid, pts, lam2, tol, (np.array(redo), np.zeros(len(redo), dtype=np.int64)))
        val, e, cv, nn, jm = _refine_consistent(job)
    for i, m in enumerate(redo):
        if jm[i]:
            jam[m] = True
            loss_ratio[m] = err[m] = math.nan
        else:
            loss_ratio[m], err[m] = float(val[i]), float(e[i])
        conv[m], n_crank[m] = bool(cv[i]), int(nn[i])


def _refine_one(G: GearTable, pieces, n_piece, w, mu: float, sigma: list, lam, tol: float):
    """The consistent refinement of one gear solved alone, on Python scalars.

    :func:`_refine_consistent` of one gear solved alone (its table ``G``, its ``pieces`` (a, b, owner) and their
    intervals ``n_piece`` on the final grid, weights ``w``) for one friction ``mu`` and the modes ``sigma`` (a list;
    ``lam``: their lambda at the grid's nodes, shape (K, nodes)): the same nodes, sums and acceptance, operation for
    operation (the same numbers, bit for bit), with the bookkeeping on Python scalars.  Returns lists over the
    modes: value, E, accepted, intervals, jammed.
    """
    z2 = int(G.z2[0])
    rb, omk, r_p1 = G.R_b[0], G.omk[0], G.r_p1[0]
    a, b = pieces[0].tolist(), pieces[1].tolist()
    n = np.asarray(n_piece).tolist()
    mids = [0.5 * (ap + bp) for ap, bp in zip(a, b)]
    q, q_prev = (lam[:, None, :] * w[None, :2, :]).sum(axis=2).T.tolist()   # each row as (lam * w[l]).sum(axis=1)
    K = len(q)
    ok_prev = [abs(q[k] - q_prev[k]) <= max(tol * abs(q[k]), 1e-14) for k in range(K)]
    value, err, conv, jam, n_out = [math.nan] * K, [math.nan] * K, [False] * K, [False] * K, [0] * K
    active = list(range(K))
    smu = np.array([[s * mu] for s in sigma])                    # sigma mu per mode, as a column
    while active:
        total = sum(n)
        if 2 * total > CONSISTENT_N_MAX:               # the cap: the best value and its error
            for k in active:
                value[k], err[k], n_out[k] = q[k] + (q[k] - q_prev[k]) / 3.0, abs(q[k] - q_prev[k]), total
            break
        xs, ms, hs = [], [], []                        # the new nodes, their pieces' midpoints and half-widths
        for ap, bp, n_p, mp in zip(a, b, n, mids):
            xs.append(ap + (bp - ap) * (np.arange(1, 2 * n_p, 2) / (2 * n_p)))
            ms.append(np.full(n_p, mp))
            hs.append(np.full(n_p, (bp - ap) / (2 * n_p)))
        x = np.concatenate(xs)
        J, lev, rho, sh2, s = contacts_geo(x, np.concatenate(ms), None, G, z2)
        rel = rho - rb
        nx = (omk - 2.0 * sh2) / s
        Nn = colsum(lev * np.abs(rel))
        Sn = colsum(lev * lev)
        Qn = Nn + r_p1 * colsum(np.sign(rel) * lev * nx)
        hp = np.concatenate(hs)
        q_new = [0.5 * v for v in q]
        D = Sn[None, :] - smu[active] * Qn[None, :]
        good = (D > 0.0).all(axis=1).tolist()
        if all(good):
            f = mu * Nn[None, :] / D
        else:                                          # a jammed mode's values are not used
            with np.errstate(divide="ignore", invalid="ignore"):
                f = mu * Nn[None, :] / D
        sums = (f * hp).sum(axis=1).tolist()             # row by row: a mode's sum does not depend on the other
        n = [2 * n_p for n_p in n]
        still = []
        for i, k in enumerate(active):
            q_new[k] += sums[i]
            ok = abs(q_new[k] - q[k]) <= max(tol * abs(q_new[k]), 1e-14)
            if not good[i]:
                jam[k], n_out[k] = True, 2 * total
            elif ok and ok_prev[k]:
                value[k], err[k] = q_new[k] + (q_new[k] - q[k]) / 3.0, abs(q_new[k] - q[k])
                conv[k], n_out[k] = True, sum(n)
            else:
                still.append(k)
            ok_prev[k] = ok
        active = still
        q_prev, q = q, q_new
    return value, err, conv, n_out, jam


def _ratio_of(G: GearTable, slot):
    """The ratio u = z1/k of the gears at ``slot`` of the table (Z_e - 1 = z1/k)."""
    return G.Ze[slot] - 1.0


REFINE_CELLS = 2 ** 18
"""New nodes x contact rows of the friction-consistent refinement evaluated at once (gears cut whole; a gear larger
than that alone): the arrays stay near the cache, and the memory is bounded whatever the gears' grids."""


class RefineJob(NamedTuple):
    """(friction, mode) pairs of several gears whose cycle mean the final grid does not accept.

    What :func:`_refine_consistent` refines:

    table : the gears' constants (:class:`~gearcalc.pins.ideal.GearTable`).
    pieces : (a, b, n, owner) of the gears' final grids, gear by gear: piece ends, intervals, gear (index into
        ``slot``).
    slot : each gear's row of ``table``, increasing (the table is in z2 order).
    gear, mu, sigma : per pair, its gear (index into ``slot``), mu_eff and mode (+1 reducer, -1 multiplier).
    sums : per pair, the trapezoid sums (Q_L, Q_{L-1}) of its lambda on the final grid.
    tol : relative accuracy target.
    """

    table: GearTable
    pieces: tuple
    slot: np.ndarray
    gear: np.ndarray
    mu: np.ndarray
    sigma: np.ndarray
    sums: tuple
    tol: float


def _refine_consistent(job: RefineJob):
    """Continue the cycle quadrature's doubling of the friction-consistent lambda, all gears at once.

    Continue the doubling of the cycle quadrature (pins.md §6) of the friction-consistent lambda beyond the final
    grid of the first-order solve, for (friction, mode) pairs of many gears at once, evaluating only the new
    nodes (their friction-free sums once for all pairs of a gear), until the rule accepts each pair
    (E <= max(tol |Q|, 1e-14) on two successive doublings) or :data:`CONSISTENT_N_MAX`.  The gears double in
    step, each with its own pieces; a pair's sums are those of its gear alone (:func:`_refine_one`), bit for bit:
    the contact sums run in contact order per node, and a pair's sum over its gear's new nodes is numpy's sum of
    a row of that length (:func:`_pair_sums`).  Returns arrays over the pairs: Richardson value, E, accepted,
    intervals, jammed (D <= 0 at a new node).
    """
    a, b, n, owner = job.pieces
    n = n.copy()
    U, tol = job.slot.size, job.tol
    q, q_prev = job.sums
    ok_prev = np.abs(q - q_prev) <= np.maximum(tol * np.abs(q), 1e-14)   # the final grid's last doubling
    K = q.size
    value, err = np.full(K, np.nan), np.full(K, np.nan)
    conv, jam = np.zeros(K, dtype=bool), np.zeros(K, dtype=bool)
    n_out = np.zeros(K, dtype=np.int64)
    active = np.ones(K, dtype=bool)
    while active.any():
        total = np.bincount(owner, n, minlength=U).astype(np.int64)     # intervals per gear
        live = np.bincount(job.gear[active], minlength=U) > 0
        capped = live & (2 * total > CONSISTENT_N_MAX)            # the cap: the best value and its error
        if capped.any():
            c = active & capped[job.gear]
            value[c] = q[c] + (q[c] - q_prev[c]) / 3.0
            err[c] = np.abs(q[c] - q_prev[c])
            n_out[c] = total[job.gear[c]]
            active &= ~c
            live &= ~capped
        if not live.any():
            break
        q_new = 0.5 * q
        bad = _doubling_sums(job, (a, b, n, owner), live, active, q_new)
        jam |= bad
        n_out[bad] = 2 * total[job.gear[bad]]
        active &= ~bad
        n = np.where(live[owner], 2 * n, n)
        ok = np.abs(q_new - q) <= np.maximum(tol * np.abs(q_new), 1e-14)
        done = active & ok & ok_prev
        value[done] = q_new[done] + (q_new[done] - q[done]) / 3.0
        err[done] = np.abs(q_new[done] - q[done])
        conv |= done
        n_out[done] = 2 * total[job.gear[done]]
        active &= ~done
        step = live[job.gear]
        q_prev, q, ok_prev = np.where(step, q, q_prev), np.where(step, q_new, q), np.where(step, ok, ok_prev)
    return value, err, conv, n_out, jam


def _doubling_sums(job: RefineJob, pieces: tuple, live, active, q_new):
    """One doubling of the gears ``live``: adds each active pair's sum over its gear's new nodes to ``q_new``.

    The gears are evaluated a group at a time (about :data:`REFINE_CELLS` new nodes x contact rows, cut at
    gears).  Returns the pairs jammed at a new node (D <= 0).
    """
    a, b, n, owner = pieces
    G = job.table
    total = np.bincount(owner, n, minlength=job.slot.size).astype(np.int64)
    rows = np.ceil(G.c[job.slot]).astype(np.int64) + 1
    gears = np.flatnonzero(live)
    group = np.cumsum(total[gears] * rows[gears]) // REFINE_CELLS   # non-decreasing group number per gear
    cuts = [0, *(np.flatnonzero(np.diff(group)) + 1).tolist(), gears.size]
    bad = np.zeros(job.gear.size, dtype=bool)
    for lo, hi in zip(cuts[:-1], cuts[1:]):
        gs = gears[lo:hi]
        pc = np.flatnonzero(np.isin(owner, gs))              # the group's pieces (gear by gear)
        nn = n[pc]
        piece = np.repeat(pc, nn)
        j = np.arange(int(nn.sum())) - np.repeat(np.cumsum(nn) - nn, nn)
        x = a[piece] + (b - a)[piece] * ((2 * j + 1) / (2 * n[piece]))
        gi = job.slot[owner[piece]]
        Nn, Sn, Qn = _new_node_sums(G, x, (0.5 * (a + b))[piece], gi)
        hp = ((b - a) / (2 * n))[piece]
        start = np.zeros(job.slot.size, dtype=np.int64)      # each gear's first new node in the group's arrays
        start[gs] = np.cumsum(total[gs]) - total[gs]
        pairs = np.flatnonzero(active & np.isin(job.gear, gs))
        _pair_sums(job, pairs, (start, total), (Nn, Sn, Qn, hp), (q_new, bad))
    return bad


def _new_node_sums(G: GearTable, x, mid, gi):
    """N, S and Q = N - r_p1 U_x (pins.md §4.9, :func:`~gearcalc.pins.ideal.node_sums`) at new nodes.

    At nodes x of the table's gears ``gi`` (z2-ordered), as :func:`_refine_one` computes them for one gear.
    """
    Nn, Sn, Qn = np.empty(x.size), np.empty(x.size), np.empty(x.size)
    for sl, z2 in G.blocks(gi):
        g = gi[sl]
        J, lev, rho, sh2, s = contacts_geo(x[sl], mid[sl], g, G, z2)
        rel = rho - G.take("R_b", g)
        nx = (G.take("omk", g) - 2.0 * sh2) / s
        Nn[sl] = colsum(lev * np.abs(rel))
        Sn[sl] = colsum(lev * lev)
        Qn[sl] = Nn[sl] + G.take("r_p1", g) * colsum(np.sign(rel) * lev * nx)
    return Nn, Sn, Qn


def _pair_sums(job: RefineJob, pairs, at: tuple, node: tuple, acc: tuple):
    """Each pair's sum of mu N/D times the half-step over its gear's new nodes, added to q_new; jams marked.

    A pair's nodes are a row of a (pairs, nodes) array of the pairs of gears with as many new nodes: numpy sums
    each row as it sums that row alone (the sums of :func:`_refine_one`), pairs in blocks of
    :data:`REFINE_BLOCK` cells.
    """
    start, total = at
    Nn, Sn, Qn, hp = node
    q_new, bad = acc
    length = total[job.gear[pairs]]
    for L in np.unique(length).tolist():
        kk_all = pairs[length == L]
        step = max(1, REFINE_BLOCK // max(L, 1))
        for c0 in range(0, kk_all.size, step):             # (pairs, new nodes) blocks of bounded size
            kk = kk_all[c0:c0 + step]
            at_ = start[job.gear[kk]][:, None] + np.arange(L)
            D = Sn[at_] - (job.sigma[kk] * job.mu[kk])[:, None] * Qn[at_]
            b = ~(D > 0.0).all(axis=1)
            bad[kk[b]] = True
            with np.errstate(divide="ignore", invalid="ignore"):
                f = job.mu[kk][:, None] * Nn[at_] / D
            q_new[kk] += (f * hp[at_]).sum(axis=1)          # row by row: a pair's sum does not depend on the others


def crank_history(g: Cycloid, psi_star: float, t, t_mid, mu_eff: float, sigma: int, consistent: bool = True):
    r"""Per node of a cycle grid: the force denominator D, the crank-bearing force and the crank torque, unit T_sat.

    The friction-consistent model of pins.md §4.9 (:func:`consistent_node_values`); with ``consistent``
    false the forces are the friction-free ones of §4.4 (D = S; the bearing force then has no friction
    part either).  t = theta/T_p in the cycle variable of :func:`cycle_state` (multiplier theta = T_p t,
    reducer theta = T_p (1 - t)).

    .. math:: F_i = \frac{T_{sat}\,|l_i|}{D}, \qquad B = -\sum_i F_i\,(n_i + q_i\,z \times n_i), \qquad
        \frac{T_H}{T_{sat}} = \sigma\,e\,B_y

    Parameters
    ----------
    g : Cycloid
        The gear.
    psi_star : float
        End of the loaded arc, [rad].
    t, t_mid : ndarray
        Nodes t = theta/T_p and the midpoints of their pieces, [-].
    mu_eff : float
        Effective friction coefficient, [-].
    sigma : int
        +1 reducer, -1 multiplier.
    consistent : bool, optional
        The friction-consistent forces (else the friction-free ones).

    Returns
    -------
    dict of arrays over the nodes: D [mm^2] (F_i = T_sat |l_i|/D), lam [-], Bx, By (crank frame, x along
    the crank arm; per N·mm of T_sat) [1/mm], crank (the crank torque along the power flow over T_sat,
    sigma e B_y) [-], jam (D <= 0).

    Examples
    --------
    >>> g = Cycloid.from_curtate_ratio(21, 22, 3.9, 0.75, 1.95)
    >>> h = crank_history(g, np.pi, np.array([0.2]), np.array([0.5]), 0.0, REDUCER)
    >>> round(float(h["crank"][0]) * 21, 12)           # friction-free: T_H = T_sat/u
    1.0

    References
    ----------
    pins.md §4.9 (crank-bearing force, crank torque), §8 (the detail table).
    """
    G = GearTable.of(as_arrays(g), np.array([psi_star]))
    t = np.asarray(t, dtype=float)
    J, lev, rho, sh2, s = contacts_geo(t, np.asarray(t_mid, dtype=float), None, G, int(g.z2))
    sums = node_sums(J, lev, rho, sh2, s, G, None)
    v = consistent_node_values(sums, mu_eff if consistent else 0.0, sigma)
    mu = mu_eff if consistent else 0.0
    Bx = v["c"] * (sums[3] - sigma * mu * sums[4])
    By = v["c"] * (sigma * sums[1] + mu * sums[2]) / g.r_p1
    lam = mu_eff * sums[0] / v["D"]
    return {"D": v["D"], "lam": lam, "Bx": Bx, "By": By, "crank": sigma * g.e * By, "jam": v["jam"]}
