"""KHV pin gearing, level ``ideal``: the cycle model solved for many gears at once (pins.md §4, §6).

:func:`ideal_cycles` integrates the unit-torque loss ratio of every gear of a batch over one period
(piecewise trapezoid and Richardson, :func:`gearcalc.quadrature.integrate_pieces`), with the per-pin
peaks; :func:`mean_loss_ratio` is the same integrator for one gear.  A batch equals one design at a
time, bit for bit.  Units N, mm, rad.

References
----------
.. [1] The paper (Prudnikov, seed 000), cited in full in :mod:`gearcalc.pins`; docs/spec/pins.md §4, §6.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NamedTuple
from dataclasses import field as dataclass_field

import numpy as np

from ..quadrature import QuadResult, integrate_pieces
from .cycle import cycle_breakpoints, disc_offsets, disc_sum_peak, sum_over_discs
from .geometry import as_arrays, crest_cutoffs, Cycloid, min_curvature_radius, spin_reversal_phases

__all__ = ["CycleIntegral", "mean_loss_ratio", "NODE_ROWS", "GRID_ROWS", "FIRST_LEVELS_MAX",
           "first_levels", "cycle_pieces", "TOO_FEW_TEETH", "UNDERCUT", "TOO_COSTLY", "DISC_SAMPLES_MAX",
           "DISC_WORK_MAX", "IdealCycles", "REFINE_SAMPLES", "admissibility", "ideal_cycles"]


# The functions below solve the cycle model of many gears at once: numpy over gears, pins, crank
# angles.  Inside, a crank-angle node of gear o carries its J = ceil(c_o - t_mid) loaded contacts
# as consecutive *entries* of flat arrays (one per loaded pin and node), and sums over a node's
# contacts are np.bincount over the node index: sequential in contact order, so a gear's numbers do
# not depend on the gears computed with it (a batch equals one design at a time, bit for bit).

@dataclass
class GearTable:
    """Per-gear constants of the cycle integrand, arrays of shape (m,), the gears sorted by z2.

    What the node functions (:func:`contacts_geo`, :func:`node_sums`) take per gear; :meth:`take` gives them
    at the nodes (a scalar when the table has one gear: the same values, fewer gathers).

    Attributes
    ----------
    z2 : ndarray of int
        Pins, [-].
    K1 : ndarray
        Curtate ratio e z2/(k R_p), [-].
    omk : ndarray
        1 - K1, [-].
    R_p, R_b : ndarray
        Pin-circle and pin radius, [mm].
    r_p1 : ndarray
        Satellite pitch radius e z1/k, [mm].
    c : ndarray
        Loaded contacts reach: pin j is loaded while j < ceil(c - t), [-].

    Examples
    --------
    >>> G = GearTable.of(as_arrays(Cycloid.from_curtate_ratio(20, 22, 3.9, 0.75, 1.95)), np.array([2.0285]))
    >>> int(G.z2[0]), round(float(G.K1[0]), 6), round(float(G.c[0]), 4)      # c = psi* z2/(2 pi)
    (22, 0.75, 7.1026)

    References
    ----------
    .. [1] docs/spec/pins.md §4.1-4.2, §6.
    """

    z2: np.ndarray
    K1: np.ndarray
    omk: np.ndarray
    R_p: np.ndarray
    R_b: np.ndarray
    r_p1: np.ndarray
    c: np.ndarray
    omk2: np.ndarray = None
    """(1 - K1)^2, as a product of arrays (a numpy scalar's ``** 2`` calls pow(), which is not always the
    correctly rounded square: one gear alone would then differ from the same gear in a batch)."""
    Ze: np.ndarray = None
    """Z_e = z2/k (the curvature of the pin-centre curve, pins.md §4.2; the contact stress needs it)."""
    trig: dict = dataclass_field(default_factory=dict)
    """Per z2: (j, sin, cos) of the rows' half phases pi j/z2 (:func:`_contacts`), computed once."""

    def __post_init__(self):
        if self.omk2 is None:
            self.omk2 = self.omk * self.omk

    @classmethod
    def of(cls, g: Cycloid, psi_star):
        """The table of gears ``g`` (array fields, shape (m,)) with their loaded-arc ends psi* [rad]."""
        if np.size(g.z2) == 1 and np.ndim(g.z2) == 1:       # one gear: the same values from Python scalars
            z1, z2 = int(g.z1[0]), int(g.z2[0])
            e, R_p, omk, R_b = (float(np.asarray(v, dtype=float)[0]) for v in (g.e, g.R_p, g.one_minus_K1, g.R_b))
            k = z2 - z1
            if k != 0 and k * R_p != 0.0:
                c = z2 / 2.0 if k == 1 else float(np.asarray(psi_star).reshape(-1)[0]) * z2 / (2.0 * math.pi)
                return cls(np.array([z2]), np.array([e * z2 / (k * R_p)]), np.array([omk]), np.array([R_p]),
                           np.array([R_b]), np.array([e * z1 / k]), np.array([c]), omk2=np.array([omk * omk]),
                           Ze=np.array([z2 / k]))
        z1, z2 = np.asarray(g.z1), np.asarray(g.z2)
        k = z2 - z1
        e, R_p = np.asarray(g.e, dtype=float), np.asarray(g.R_p, dtype=float)
        c = np.where(k == 1, z2 / 2.0, np.asarray(psi_star) * z2 / (2.0 * math.pi))
        return cls(z2, e * z2 / (k * R_p), np.asarray(g.one_minus_K1, dtype=float), R_p,
                   np.asarray(g.R_b, dtype=float), e * z1 / k, c, Ze=z2 / k)

    def rows(self, z2: int, n: int):
        """(j, sin(pi j/z2), cos(pi j/z2)) for the rows j = 0 .. n-1, as columns.

        (j, sin(pi j/z2), cos(pi j/z2)) for the rows j = 0 .. n-1, as columns (cached per z2; the values do not
        depend on how many rows were computed).
        """
        have = self.trig.get(z2)
        if have is None or have[0].shape[0] < n:
            j = np.arange(max(n, int(np.ceil(self.c.max())) + 1))[:, None]
            half = math.pi * (j / z2)
            have = self.trig[z2] = (j, np.sin(half), np.cos(half))
        j, sa, ca = have
        return j[:n], sa[:n], ca[:n]

    def take(self, name: str, idx):
        """Field ``name`` at gear indices ``idx`` (a scalar when there is one gear: same values, fewer gathers)."""
        arr = getattr(self, name)
        return arr[0] if arr.size == 1 else arr[idx]

    def blocks(self, gi):
        """(slice, z2) of the runs of nodes whose gears have the same number of pins (gears sorted by z2)."""
        if self.z2.size == 1:
            return [(slice(None), int(self.z2[0]))]
        z = self.z2[gi]
        cuts = np.flatnonzero(z[1:] != z[:-1]) + 1
        edges = [0, *cuts.tolist(), z.size]
        return [(slice(lo, hi), int(z[lo])) for lo, hi in zip(edges[:-1], edges[1:]) if hi > lo]


def colsum(a):
    r"""Sums over the rows (axis 0) in row order.

    .. math:: S_j = (\cdots((a_{0j} + a_{1j}) + a_{2j}) + \cdots) + a_{n-1,j}

    Sums over the rows (axis 0) in row order, so that a column's sum does not depend on the padding rows (zeros) or
    on the other columns.  numpy reduces a C-ordered array over its outer axis row by row (sequentially) when there
    are several columns; a single column is a contiguous reduction, which numpy sums pairwise, so that case takes
    the (sequential) cumulative sum.

    Parameters
    ----------
    a : ndarray, shape (rows, columns)
        Values (contacts x nodes), C-ordered.

    Returns
    -------
    ndarray, shape (columns,)
        ((a[0] + a[1]) + a[2]) + ... per column.

    Examples
    --------
    >>> colsum(np.array([[1e16, 1.0], [1.0, 2.0], [1.0, 3.0]])).tolist()     # 1e16 + 1 + 1 in order: 1e16
    [1e+16, 6.0]

    References
    ----------
    .. [1] docs/spec/pins.md §6 (a batch equals one design at a time, bit for bit).
    """
    return a.sum(axis=0) if a.shape[1] > 1 else np.cumsum(a, axis=0)[-1]


def _contacts(x, mid, gi, G: GearTable, z2: int, with_phase: bool = False):
    """Loaded contacts at nodes x (pieces with midpoints mid) of gears gi that all have z2 pins.

    Arrays of shape (rows j, nodes), j in load-side order; the rows beyond a node's J loaded contacts
    are padding (lever 0).  Returns J (loaded contacts per node), loaded, phase psi~ [rad] (or None),
    lever |l| [mm] and rho [mm].  Membership: j < J = ceil(c - mid) (pins.md §6, one-sided at piece
    ends); psi~ = 2 pi (j + t)/z2 (pins.md §4.1).  The half phase is a + b with a = pi j/z2 per row and
    b = pi t/z2 per node, so sin and cos of psi~/2 follow from the rows' and nodes' sines by the
    addition theorem (products instead of sines per contact: the trigonometric functions dominated
    the cost), and sin psi~ = 2 sin(psi~/2) cos(psi~/2); s and the lever arm then take the
    cancellation-free forms of :func:`s_factor` and :func:`lever_arm`.
    """
    J, j, loaded, lev, rho, _, _ = _contact_rows(x, mid, gi, G, z2)
    phase = 2.0 * math.pi * ((j + x) / z2) if with_phase else None
    return J, loaded, phase, lev, rho


def _contact_rows(x, mid, gi, G: GearTable, z2: int):
    """The computation of :func:`_contacts`: J, row index j, loaded, lever |l| [mm], rho [mm], sin^2(psi~/2), s."""
    J = np.ceil(G.take("c", gi) - mid).astype(np.int64)
    j, sa, ca = G.rows(z2, int(J.max()))
    b = math.pi * (x / z2)
    sb, cb = np.sin(b), np.cos(b)
    sh = sa * cb + ca * sb                       # sin(psi/2)
    ch = ca * cb - sa * sb                       # cos(psi/2)
    loaded = j < J
    sh2 = sh * sh
    s = np.sqrt(G.take("omk2", gi) + 4.0 * G.take("K1", gi) * sh2)
    lev = np.where(loaded, np.abs(G.take("r_p1", gi) * (2.0 * sh * ch) / s), 0.0)
    rho = G.take("R_p", gi) * s
    return J, j, loaded, lev, rho, sh2, s


def contacts_geo(x, mid, gi, G: GearTable, z2: int):
    r"""The loaded contacts at crank-angle nodes, with sin^2(psi/2) and s(psi) (pins.md §4.1, §6).

    .. math:: J = \lceil c - t_{mid} \rceil, \qquad \sin^2\frac{\psi_j}{2}, \qquad s(\psi_j)\ (j < J)

    :func:`_contacts` with the squared half-phase sine and s(psi) that the friction-consistent sums need; lever
    and rho by the very operations of :func:`_contacts` (the same numbers, bit for bit).

    Parameters
    ----------
    x, mid : ndarray, shape (n,)
        Nodes t = theta/T_p and the midpoints of their pieces (loaded: j < ceil(c - mid)), [-].
    gi : ndarray of int, shape (n,), or None
        Each node's gear (row of ``G``; None: the table's one gear).
    G : GearTable
    z2 : int
        Pins of the nodes' gears (all the same).

    Returns
    -------
    J : ndarray of int, shape (n,)
        Loaded contacts per node.
    lev, rho, sh2, s : ndarray, shape (rows, n)
        Lever |l| (0 on the padding rows), radius of curvature rho, sin^2(psi/2) and s(psi), [mm, mm, -, -].

    Examples
    --------
    >>> G = GearTable.of(as_arrays(Cycloid.from_curtate_ratio(20, 22, 3.9, 0.75, 1.95)), np.array([2.0285]))
    >>> J, lev, rho, sh2, s = contacts_geo(np.array([0.25]), np.array([0.5]), None, G, 22)
    >>> int(J[0]), lev.shape                         # J = ceil(c - mid) = ceil(7.1026 - 0.5)
    (7, (7, 1))

    References
    ----------
    .. [1] docs/spec/pins.md §4.1, §4.2, §6.
    """
    J, _, _, lev, rho, sh2, s = _contact_rows(x, mid, gi, G, z2)
    return J, lev, rho, sh2, s


NODE_ROWS = ("N", "S", "rUx", "Sx", "Uy", "lever_max", "lever_row", "loss_max", "loss_row", "stress_max")
"""The rows of :func:`node_sums`: what the friction-consistent model (pins.md §4.9) needs per node."""


def node_sums(J, lev, rho, sh2, s, G: GearTable, gi):
    r"""Sums over a node's loaded contacts that do not depend on the friction (pins.md §4.9), rows :data:`NODE_ROWS`.

    In the crank frame (O1 = (e, 0), P = (r_p2, 0)) contact i has the unit normal
    n_i = (A_i - P)/rho_i = ((1 - K1 - 2 sin^2(psi/2))/s, sin(psi)/s) towards the pin centre, the lever
    |l_i| = r_p1 |sin psi|/s, rel_i = rho_i - R_b and sg_i = sign(rel_i) (the satellite slides along
    -sg_i z x n_i, since omega_V < 0).  Per node:

    .. math::

        N = \sum |l| |rel|,\ S = \sum l^2,\ r_{p1} U_x = -r_{p1} \sum sg\,|l| n_x,\
        S_x = \sum |l| n_x,\ U_y = -\sum sg\,l^2/r_{p1}

    then Q = N - r_p1 U_x, D_reducer = S - mu Q, D_multiplier = S + mu Q (:func:`consistent_node_values`).
    Also the largest |l| and |l| |rel| of a contact with their rows (the force and loss peaks), and the
    largest |l|/R_eff, R_eff = R_b (1 - R_b/rho_c) the reduced radius of pin and tooth (the contact stress;
    rho_c = R_p s^3/D_c of :func:`curvature_radius`, signed: the formula holds on both the convex and the
    concave part of the profile).  Padding rows (lever 0) add nothing.

    Parameters
    ----------
    J, lev, rho, sh2, s : ndarray
        What :func:`contacts_geo` returns at the nodes.
    G : GearTable
    gi : ndarray of int, shape (n,), or None
        Each node's gear (row of ``G``; None: the table's one gear).

    Returns
    -------
    ndarray, shape (len(NODE_ROWS), n)
        The rows :data:`NODE_ROWS` per node [mm^2, mm^2, mm^2, mm, mm, mm, -, mm^2, -, 1/mm].

    Examples
    --------
    >>> G = GearTable.of(as_arrays(Cycloid.from_curtate_ratio(20, 22, 3.9, 0.75, 1.95)), np.array([2.0285]))
    >>> sums = node_sums(*contacts_geo(np.array([0.25]), np.array([0.5]), None, G, 22), G, None)
    >>> bool(sums[1, 0] > 0.0 and sums[5, 0] ** 2 <= sums[1, 0])     # S = sum l^2 holds the largest l^2
    True

    References
    ----------
    .. [1] docs/spec/pins.md §4.9.
    """
    rb = G.take("R_b", gi)
    r_p1 = G.take("r_p1", gi)
    rel = rho - rb
    sg = np.sign(rel)
    u2 = 2.0 * sh2                                  # 2 sin^2(psi/2) = 1 - cos(psi)
    nx = (G.take("omk", gi) - u2) / s
    lev2 = lev * lev
    K1, Ze = G.take("K1", gi), G.take("Ze", gi)
    Dc = 1.0 + K1 * K1 * Ze - K1 * (1.0 + Ze) * (1.0 - u2)
    r_eff = rb * (1.0 - rb * Dc / (G.take("R_p", gi) * (s * s * s)))
    out = np.empty((len(NODE_ROWS), J.size))
    out[0] = colsum(lev * np.abs(rel))
    out[1] = colsum(lev2)
    out[2] = -r_p1 * colsum(sg * lev * nx)
    out[3] = colsum(lev * nx)
    out[4] = -colsum(sg * lev2) / r_p1
    rf = lev.argmax(axis=0)
    cols = np.arange(J.size)
    out[5], out[6] = lev[rf, cols], rf
    pl = lev * np.abs(rel)
    rp = pl.argmax(axis=0)
    out[7], out[8] = pl[rp, cols], rp
    out[9] = (lev / r_eff).max(axis=0)
    return out


GRID_ROWS = ("loss_ratio", "force", "loss", "total", "rel_first", "rel_last", "loaded")
"""The rows of :func:`_grid_rows`."""


def _grid_rows(J, lev, rel):
    """The integrand lambda/mu_eff and what the peaks need at each node, one gear (rows :data:`GRID_ROWS`).

    Per node, from its contacts (J loaded, lever arms |l|, rel = rho - R_b; pins.md §4.4-4.6, unit
    scalings): lambda/mu_eff, the largest force F/T_sat and the largest loss P/(T_sat |omega_V|) of a
    contact, the total loss, rho - R_b at the first and the last loaded contact, and J.  The same
    operations as the vectorised code for many gears (:func:`ideal_cycles`).
    """
    S = colsum(lev * lev)
    arel = np.abs(rel)
    out = np.empty((len(GRID_ROWS), J.size))
    out[0] = colsum(lev * arel) / S
    force = lev / S
    loss = force * arel * 1e-3                     # contact_loss_power(force, |rho - R_b|, 1)
    force.max(axis=0, out=out[1])
    loss.max(axis=0, out=out[2])
    out[3] = colsum(loss)
    out[4], out[5], out[6] = rel[0], rel[J - 1, np.arange(J.size)], J
    return out


PEAK_ROWS = ("force_row", "loss_row")
"""Rows a batch's integrand adds after :data:`GRID_ROWS` and :data:`NODE_ROWS` when it computes the friction-free
peaks: the contact of each node's largest force and loss (first occurrence), which the peaks' refinement needs."""


def _node_rows(contacts: tuple, G: GearTable, gi=None, peaks: bool = True, with_rows: bool = False):
    """The rows of :func:`_grid_rows` and :func:`node_sums` at nodes of gears ``gi``, fused.

    The rows of :func:`_grid_rows` and then of :func:`node_sums`, by the very operations of those two (the same
    numbers, bit for bit), with the products and sums they share computed once; ``gi`` the gear of each node
    (None: one gear).  Without ``peaks`` the rows of the friction-free peaks (force, loss, total:
    :data:`GRID_ROWS` 1-3) are NaN (the friction-consistent model has its own peaks, pins.md §4.9); with
    ``with_rows`` (and ``peaks``) the rows :data:`PEAK_ROWS` follow.  ``contacts``: (J, lever, rho,
    sin^2(psi/2), s) of :func:`contacts_geo`.
    """
    J, lev, rho, sh2, s = contacts
    rb, r_p1 = G.take("R_b", gi), G.take("r_p1", gi)
    n = J.size
    rel = rho - rb
    arel = np.abs(rel)
    lev2 = lev * lev
    la = lev * arel
    g = len(GRID_ROWS)
    out = np.empty((g + len(NODE_ROWS) + (len(PEAK_ROWS) if with_rows else 0), n))
    S = out[g + 1] = colsum(lev2)
    N = out[g] = colsum(la)
    out[0] = N / S
    if peaks:
        force = lev / S
        loss = force * arel * 1e-3                 # contact_loss_power(force, |rho - R_b|, 1)
        force.max(axis=0, out=out[1])
        loss.max(axis=0, out=out[2])
        out[3] = colsum(loss)
        if with_rows:
            out[-2], out[-1] = force.argmax(axis=0), loss.argmax(axis=0)
    else:
        out[1:4] = np.nan
    cols = np.arange(n)
    out[4], out[5], out[6] = rel[0], rel[J - 1, cols], J
    sg = np.sign(rel)
    u2 = 2.0 * sh2                                  # 2 sin^2(psi/2) = 1 - cos(psi)
    nx = (G.take("omk", gi) - u2) / s
    K1, Ze = G.take("K1", gi), G.take("Ze", gi)
    Dc = 1.0 + K1 * K1 * Ze - K1 * (1.0 + Ze) * (1.0 - u2)
    r_eff = rb * (1.0 - rb * Dc / (G.take("R_p", gi) * (s * s * s)))
    out[g + 2] = -r_p1 * colsum(sg * lev * nx)
    out[g + 3] = colsum(lev * nx)
    out[g + 4] = -colsum(sg * lev2) / r_p1
    out[g + 6] = _first_row_of_max(lev, lev.max(axis=0, out=out[g + 5]))
    out[g + 8] = _first_row_of_max(la, la.max(axis=0, out=out[g + 7]))
    out[g + 9] = (lev / r_eff).max(axis=0)
    return out


def _first_row_of_max(a, top):
    """``a.argmax(axis=0)`` of a 2-D array given its column maxima ``top``: the first row holding each maximum.

    The same indices (NaN columns go to argmax itself), by a pass over the rows: numpy's argmax over the outer
    axis of a C-ordered array costs about ten times its max.
    """
    if a.shape[0] < 2 or np.isnan(top).any():
        return a.argmax(axis=0)
    row = np.zeros(a.shape[1], dtype=np.int64)
    for r in range(a.shape[0] - 1, 0, -1):          # the last write wins: the first row holding the maximum
        np.copyto(row, r, where=a[r] == top)
    np.copyto(row, 0, where=a[0] == top)
    return row


def _unit_loss_ratio(G: GearTable, piece_owner, grid_rows: bool = False, peaks: bool = True):
    """The integrand lambda(t)/mu_eff of the cycle mean, for :func:`~gearcalc.quadrature.integrate_pieces`.

    With ``grid_rows``, the rows of :func:`_grid_rows` and :func:`node_sums` follow it (:func:`_node_rows`;
    without ``peaks`` those of the friction-free peaks are NaN; several gears add :data:`PEAK_ROWS` when
    ``peaks``), which the quadrature carries to its final grid (the peaks and the friction-consistent model
    need them there, so the final grid is not evaluated again).
    """
    if grid_rows:
        alone = G.z2.size == 1 and np.all(piece_owner == 0)   # one gear: no peak rows (its own refinement)
        n_rows = len(GRID_ROWS) + len(NODE_ROWS) + (len(PEAK_ROWS) if peaks and not alone else 0)

        def f_rows(x, mid, piece):
            if alone:
                return _node_rows(contacts_geo(x, mid, None, G, int(G.z2[0])), G, None, peaks)
            gi = piece_owner[piece]
            out = np.empty((n_rows, x.size))
            for sl, z2 in G.blocks(gi):
                g = gi[sl]
                out[:, sl] = _node_rows(contacts_geo(x[sl], mid[sl], g, G, z2), G, g, peaks, peaks)
            return out
        return f_rows

    def f(x, mid, piece):
        gi = piece_owner[piece]
        out = np.empty(x.size)
        for sl, z2 in G.blocks(gi):
            g = gi[sl]
            _, _, _, lev, rho = _contacts(x[sl], mid[sl], g, G, z2)
            out[sl] = colsum(lev * np.abs(rho - G.take("R_b", g))) / colsum(lev * lev)
        return out
    return f


FIRST_LEVELS_MAX = 6
"""Most doublings of the first round (1024 intervals at n_start = 16): see :func:`first_levels`."""


def first_levels(tol: float, z2=None):
    r"""Doublings evaluated in the first round of the cycle quadrature (speed only, never a result).

    A typical gear needs E ~ 3e-5 4^-L at level L, so L = 1 + ceil(log_4(3e-5/tol)), at least 2, and at
    most :data:`FIRST_LEVELS_MAX`: a round costs about as much as evaluating a few hundred nodes, so
    small levels are best guessed in one round, while beyond it a wrong guess costs a whole level (twice
    the nodes before it) and the next round's prediction from the observed rate of convergence
    (:func:`~gearcalc.quadrature.integrate_pieces`) is the better guess (the paper designs at tol = 1e-9
    need 8 or 9 levels).  With ``z2`` (pins per gear, a scalar or an array): one level less per doubling
    of z2 beyond 28, since the intervals a gear needs fall about as 1/z2 (the loss ratio of many loaded
    pins varies less within a period: z2 = 56-80 needs one level less than z2 = 24-40, z2 = 100 two).

    .. math:: L = \min\!\left(6,\ \max\!\left(2,\ 1 + \left\lceil \log_4 \frac{3 \cdot 10^{-5}}{\text{tol}} \right\rceil
        - \left\lfloor \log_2 \frac{\max(z_2, 28)}{28} \right\rfloor\right)\right)

    Parameters
    ----------
    tol : float
        Relative accuracy target, [-].
    z2 : int or array_like, optional
        Pins per gear, [-].

    Returns
    -------
    levels : int or ndarray
        Doublings of the first round.

    Examples
    --------
    >>> [first_levels(t) for t in (1e-3, 1e-6, 1e-9)]
    [2, 4, 6]
    >>> first_levels(1e-6, np.array([22, 62, 120])).tolist()
    [4, 3, 2]

    References
    ----------
    .. [1] docs/spec/pins.md §6, §12.6.
    """
    base = 1 + math.ceil(math.log(3e-5 / tol, 4))
    if isinstance(z2, (int, np.integer)):
        return min(FIRST_LEVELS_MAX, max(2, base - max(0, math.floor(math.log2(max(int(z2), 28) / 28.0)))))
    if z2 is not None:
        z = np.asarray(z2, dtype=float)
        less = np.floor(np.log2(np.maximum(z, 28.0) / 28.0)).astype(np.int64)
        out = np.minimum(FIRST_LEVELS_MAX, np.maximum(2, base - less))
        return int(out) if out.ndim == 0 else out
    return min(FIRST_LEVELS_MAX, max(2, 1 + math.ceil(math.log(3e-5 / tol, 4))))


def _one_gear_pieces(z1: int, z2: int, psi_star: float, psi_0: float, one_minus_K1: float):
    """:func:`cycle_pieces` of one gear on Python floats.

    :func:`cycle_pieces` of one gear on Python floats (the same operations), or None when the gear needs a geometric
    grading (the vectorised code then calls :func:`cycle_breakpoints`).
    """
    c = z2 / 2.0 if z2 - z1 == 1 else psi_star * z2 / (2.0 * math.pi)
    pts = [0.0, 1.0, c - math.floor(c)]
    if psi_0 < psi_star:                                    # False for NaN (no spin reversal)
        c0 = psi_0 * z2 / (2.0 * math.pi)
        pts.append(c0 - math.floor(c0))
    pts.sort()
    a, b = [], []
    for lo, hi in zip(pts[:-1], pts[1:]):
        if hi > lo:
            if lo > 0.0 and math.ceil(c - 0.5 * (lo + hi)) == 1:
                return None                                  # a single pin carries the load: graded
            a.append(lo)
            b.append(hi)
    if one_minus_K1 < 0.01:
        return None                                          # K1 > 0.99: graded
    return np.array(a), np.array(b), np.zeros(len(a), dtype=np.int64)


def cycle_pieces(g: Cycloid, psi_star, psi_0):
    r"""Smooth pieces of the cycle integrand of many gears in t = theta/T_p: (a, b, owner), gear by gear.

    The breakpoints are those of :func:`cycle_breakpoints`: 0, 1, the exit frac(psi* z2/2 pi) and the
    spin reversal frac(psi_0 z2/2 pi) when psi_0 < psi*, computed for all gears at once; a gear that
    needs a geometric grading (K1 > 0.99, or a piece where a single pin carries the load) gets
    :func:`cycle_breakpoints` itself.

    Parameters
    ----------
    g : gears with array fields, shape (m,).
    psi_star : psi* per gear [rad]; psi_0 : spin reversal phase per gear, NaN where none [rad].

    .. math:: t \in \{0,\ 1,\ \operatorname{frac}(\psi^* z_2 / 2\pi),\ \operatorname{frac}(\psi_0 z_2 / 2\pi)\},
        \qquad t = \theta / T_p

    Returns
    -------
    a, b : ndarray
        Piece ends, [-].
    owner : ndarray of int
        Each piece's gear.

    Examples
    --------
    >>> g = as_arrays(Cycloid.from_curtate_ratio(20, 22, 3.9, 0.75, 1.95))
    >>> a, b, owner = cycle_pieces(g, crest_cutoffs(g), np.array([np.nan]))
    >>> a.size, float(a[0]), float(b[-1]), owner.tolist()
    (2, 0.0, 1.0, [0, 0])

    References
    ----------
    .. [1] docs/spec/pins.md §6, §12.12.
    """
    z1, z2 = np.asarray(g.z1), np.asarray(g.z2)
    psi_star, psi_0 = np.asarray(psi_star, dtype=float), np.asarray(psi_0, dtype=float)
    m = z2.size
    if m == 1:
        one = _one_gear_pieces(int(z1.flat[0]), int(z2.flat[0]), float(psi_star.flat[0]), float(psi_0.flat[0]),
                               float(np.asarray(g.one_minus_K1).flat[0]))
        if one is not None:
            return one
    c = np.where(z2 - z1 == 1, z2 / 2.0, psi_star * z2 / (2.0 * math.pi))
    c0 = psi_0 * z2 / (2.0 * math.pi)
    with np.errstate(invalid="ignore"):
        f0 = np.where(psi_0 < psi_star, c0 - np.floor(c0), np.nan)
    pts = np.stack([np.zeros(m), np.ones(m), c - np.floor(c), f0], axis=1)
    pts.sort(axis=1)                                   # NaN (no spin reversal) last
    a, b = pts[:, :-1], pts[:, 1:]
    with np.errstate(invalid="ignore"):
        valid = b > a
        single = valid & (np.ceil(c[:, None] - 0.5 * (a + b)) == 1) & (a > 0.0)
    graded = (np.asarray(g.one_minus_K1) < 0.01) | np.any(single, axis=1)
    valid &= ~graded[:, None]
    owner = np.repeat(np.arange(m), valid.sum(axis=1))
    a, b = a[valid], b[valid]
    if np.any(graded):
        parts_a, parts_b, parts_o = [a], [b], [owner]
        for i in np.flatnonzero(graded):   # the rare graded gears, one by one
            gi = Cycloid(int(z1[i]), int(z2[i]), float(np.asarray(g.e)[i]), float(np.asarray(g.R_p)[i]),
                         float(np.asarray(g.R_b)[i]), float(np.asarray(g.one_minus_K1)[i]))
            bp = cycle_breakpoints(gi, float(psi_star[i]), None if np.isnan(psi_0[i]) else float(psi_0[i]))
            parts_a.append(bp[:-1])
            parts_b.append(bp[1:])
            parts_o.append(np.full(bp.size - 1, i))
        a, b, owner = np.concatenate(parts_a), np.concatenate(parts_b), np.concatenate(parts_o)
        order = np.argsort(owner, kind="stable")
        a, b, owner = a[order], b[order], owner[order]
    return a, b, owner


TOO_FEW_TEETH, UNDERCUT = 1, 2
"""Status codes of :class:`IdealCycles`: psi* <= 2 pi/z2 (pins.md §12.10); R_b >= min rho_c (§4.2)."""
TOO_COSTLY = 3
"""Status code: the sums over n_d discs (pins.md §12.7) on the final grid would exceed DISC_SAMPLES_MAX or
DISC_WORK_MAX (their size follows from n_d and the crank-angle grid that --tol needs, known only after the
quadrature); the gear's peaks are then not computed."""
DISC_SAMPLES_MAX = 10_000_000
"""n_d x loaded samples of one gear's disc sums: the merged phase grid and its sums, ~5 arrays of 8 bytes a
sample (~0.4 GB)."""
DISC_WORK_MAX = 200_000_000
"""n_d^2 x loaded samples of one gear's disc sums (n_d interpolations over n_d x samples points, ~45 ns each:
~10 s).  100 pins x 64 discs at --tol 1e-9 are 2.5e8 (11 s); at 1e-12, 8e9 (9.5 minutes)."""


@dataclass
class IdealCycles:
    """The ideal level's cycle solution of many gears in unit scalings (mu = 1, T_sat = 1 N·mm, |omega_V| = 1).

    Arrays over gears, shape (m,):

    psi_star, psi_0 : end of the loaded arc and spin-reversal phase (NaN: none) [rad];
    rho_c_min : least radius of curvature of the pin-centre curve over the loaded arc [mm];
    status : 0 (admissible), TOO_FEW_TEETH, UNDERCUT or TOO_COSTLY; the fields below are NaN where status != 0;
    loss_ratio, loss_ratio_err, converged, n_crank : the cycle mean of lambda at mu = 1, its error
        |Q_2N - Q_N| and the quadrature's acceptance and intervals (pins.md §6);
    force, force_phase : max over the cycle and the pins of F/T_sat (summed over the discs) [1/mm] and
        the load-side phase where it occurs [rad];
    loss, loss_phase : the same for P/(mu T_sat |omega_V|) [W per (N·mm·rad/s)];
    total : max over the cycle of the summed losses of all discs, per the same unit;
    rel_min, rel_max, rel_abs : extremes of rho - R_b and of |rho - R_b| over the loaded contacts [mm];
    loaded_min, loaded_max : pins carrying load (per disc).

    grid_t, grid_mid, grid_gear : the final crank-angle grid (t = theta/T_p) of every admissible gear,
    gear by gear (:meth:`grid`).
    """

    psi_star: np.ndarray
    psi_0: np.ndarray
    rho_c_min: np.ndarray
    status: np.ndarray
    loss_ratio: np.ndarray
    loss_ratio_err: np.ndarray
    converged: np.ndarray
    n_crank: np.ndarray
    force: np.ndarray
    force_phase: np.ndarray
    loss: np.ndarray
    loss_phase: np.ndarray
    total: np.ndarray
    rel_min: np.ndarray
    rel_max: np.ndarray
    rel_abs: np.ndarray
    loaded_min: np.ndarray
    loaded_max: np.ndarray
    grid_t: np.ndarray
    grid_mid: np.ndarray
    grid_gear: np.ndarray
    grid_sums: np.ndarray | None = None
    """The friction-independent node sums of :func:`node_sums` on the final grid, rows :data:`NODE_ROWS`."""
    grid_weights: np.ndarray | None = None
    """Trapezoid weights of the final grid's nodes at its level L and at L-1, L-2 (every 2nd, 4th node),
    shape (3, nodes): a gear's weights of one level sum to 1 (the cycle mean over t = theta/T_p)."""
    table: object = None
    """The admissible gears' constants (:class:`GearTable`, in their solve order ``solved``) and their pieces."""
    solved: np.ndarray | None = None
    pieces: tuple | None = None
    n_piece: np.ndarray | None = None
    """Intervals of each of ``pieces`` on the final grid (set for a gear solved alone; else None)."""

    def grid(self, i: int):
        """(t, t_mid) of gear i's final grid (piece ends twice: the one-sided limits)."""
        at = np.flatnonzero(self.grid_gear == i)      # one contiguous run (the gears are not in index order)
        return self.grid_t[at], self.grid_mid[at]


REFINE_SAMPLES = 32
"""Samples of a peak's bracket (two grid intervals) before its parabolic vertex (:func:`ideal_cycles`)."""


def _peak_values(u, mid, gi, row, kind, G: GearTable):
    """A peak candidate's quantity at crank angles u.

    kind 0 the force of contact ``row``, 1 its loss, 2 the total loss of the node; with the load-side phase of
    contact ``row`` [rad].  The points are ordered by gear.
    """
    val, ph = np.empty(u.size), np.empty(u.size)
    for sl, z2 in G.blocks(gi):
        g = gi[sl]
        _, _, phase, lev, rho = _contacts(u[sl], mid[sl], g, G, z2, with_phase=True)
        force = lev / colsum(lev * lev)
        loss = force * np.abs(rho - G.take("R_b", g)) * 1e-3          # contact_loss_power(force, |rho - R_b|, 1)
        col = np.arange(force.shape[1])
        r = row[sl]
        k = kind[sl]
        val[sl] = np.where(k == 0, force[r, col], np.where(k == 1, loss[r, col], colsum(loss)))
        ph[sl] = phase[r, col]
    return val, ph


_REFINE_FRACTIONS = np.arange(REFINE_SAMPLES + 1) / REFINE_SAMPLES
_REFINE_FRACTIONS.setflags(write=False)


def _one_gear_peaks(t, tmid, piece, G: GearTable, rows, refine: bool = True) -> dict:
    """The final-grid extremes and the refined peaks of :func:`ideal_cycles` for one gear with one disc.

    ``rows``: the rows of :func:`_grid_rows` after the first (the quadrature carried them) at the final grid
    (t, tmid, piece).  The same maxima (first occurrence: the first node holding the grid maximum, then the
    first contact of that node holding it) and the same parabolic refinement as the vectorised code for
    many gears, operation for operation, so that one design equals the same design in a batch bit for bit.
    The contact of a peak's node is found with the refining samples (one evaluation: the node's values are
    those the quadrature met, bit for bit); the bookkeeping of the three peaks (force, loss, total loss)
    runs on Python floats.  Returns the IdealCycles fields rel_min, rel_max, rel_abs, loaded_min,
    loaded_max, force, force_phase, loss, loss_phase and total of the gear.
    """
    z2 = int(G.z2[0])
    force, loss, tot, first, final, J = rows[:len(GRID_ROWS) - 1]
    # rho grows with the phase on [0, pi] (pins.md §4.2): rho - R_b is least at a node's first loaded
    # contact and largest at its last
    res = {"rel_min": first.min(), "rel_max": final.max(), "rel_abs": np.maximum(np.abs(first), np.abs(final)).max(),
           "loaded_min": J.min(), "loaded_max": J.max()}
    if not refine:              # the friction-free peaks are not wanted (friction-consistent model, pins.md §4.9)
        return res
    # grid maxima: the first node holding the maximum (its contact below)
    nds = [int(np.argmax(vals)) for vals in (force, loss, tot)]
    # each refined inside the grid intervals around its node, within the node's piece (one-sided ends)
    last = t.size - 1
    lo, hi = [], []
    for nd in nds:
        lo.append(t[nd - 1] if nd > 0 and piece[nd - 1] == piece[nd] else t[nd])
        hi.append(t[nd + 1] if nd < last and piece[nd + 1] == piece[nd] else t[nd])
    lo, hi = np.array(lo), np.array(hi)
    M = REFINE_SAMPLES
    n = M + 1
    u = lo[:, None] + (hi - lo)[:, None] * _REFINE_FRACTIONS                  # (3, M + 1)
    # the samples, and the force and loss peaks' grid nodes (for their contacts), in one evaluation
    x = np.concatenate((u.ravel(), t[nds[:2]]))
    mid = np.concatenate((np.repeat(tmid[nds], n), tmid[nds[:2]]))
    _, _, _, lev, rho = _contacts(x, mid, None, G, z2)
    F = lev / colsum(lev * lev)
    P = F * np.abs(rho - G.R_b[0]) * 1e-3
    row_f, row_p = int(np.argmax(F[:, 3 * n])), int(np.argmax(P[:, 3 * n + 1]))
    contact = (row_f, row_p, 0)
    vals = (F[row_f, :n], P[row_p, n:2 * n], colsum(P)[2 * n:3 * n])
    best = [force[nds[0]], loss[nds[1]], tot[nds[2]]]
    at = [t[nd] for nd in nds]                      # crank angle of the best value met so far
    xv, interior = [], False
    for k in range(3):
        v, uk = vals[k], u[k]
        bi = int(np.argmax(v))
        bm = min(max(bi, 1), M - 1)
        f0, fm, fp = v[bm], v[bm - 1], v[bm + 1]
        den = fp - 2.0 * f0 + fm
        if 0 < bi < M and den < 0.0:
            xk = uk[bm] - 0.5 * (uk[bm + 1] - uk[bm]) * (fp - fm) / den
            xv.append(min(max(xk, uk[bm - 1]), uk[bm + 1]))
            interior = True
        else:
            xv.append(uk[bi])
        if v[bi] > best[k]:
            best[k], at[k] = v[bi], uk[bi]
    # the parabolas' vertices (where none is interior, each "vertex" is its best sample, whose value is known
    # and already taken: the evaluation would change nothing)
    if interior:
        _, _, _, lev, rho = _contacts(np.array(xv), tmid[nds], None, G, z2)
        F = lev / colsum(lev * lev)
        P = F * np.abs(rho - G.R_b[0]) * 1e-3
        vv = (F[row_f, 0], P[row_p, 1], colsum(P)[2])
        for k in range(3):
            if vv[k] > best[k]:
                best[k], at[k] = vv[k], xv[k]
    for k, key in enumerate(("force", "loss", "total")):
        res[key] = best[k]
        if key != "total":       # the load-side phase of the peak's contact, as _contacts computes it
            res[key + "_phase"] = 2.0 * math.pi * ((contact[k] + at[k]) / z2)
    return res


def _min_curvature_radius_one(g: Cycloid, psi_star: float):
    """:func:`min_curvature_radius` of one gear on Python floats.

    :func:`min_curvature_radius` of one gear (fields of one element) on Python floats, operation for operation (the
    transcendental functions as the same numpy ufuncs, which round as they do on arrays), or None where a value is
    not finite (the array code then decides, with its NaN rules).
    """
    z1, z2 = int(np.asarray(g.z1).flat[0]), int(np.asarray(g.z2).flat[0])
    e, R_p, omk = (float(np.asarray(v).flat[0]) for v in (g.e, g.R_p, g.one_minus_K1))
    k = z2 - z1
    if k * R_p == 0.0 or k == 0:
        return None
    K1 = e * z2 / (k * R_p)
    Ze = z2 / k
    A = 1.0 + K1 * K1
    p, q = 1.0 + K1 * K1 * Ze, K1 * (1.0 + Ze)
    if not (math.isfinite(K1) and K1 > 0.0 and q > 0.0 and math.isfinite(psi_star)):
        return None
    c_lo, pq = float(np.cos(psi_star)), p / q
    c_hi = pq if pq < 1.0 else 1.0
    c_star = 3.0 * p / q - A / K1
    if not (math.isfinite(c_star) and math.isfinite(pq)):
        return None
    c = min(max(c_star, c_lo), c_hi)                     # np.clip
    psi = psi_star if c_star <= c_lo else 0.0 if (c_star >= 1.0 and c_hi >= 1.0) else \
        float(np.arccos(min(max(c, -1.0), 1.0)))
    # curvature_radius(psi, g): R_p s^3/D
    D = 1.0 + K1 * K1 * Ze - K1 * (1.0 + Ze) * float(np.cos(psi))
    sh = float(np.sin(0.5 * psi))
    s = math.sqrt(omk * omk + 4.0 * K1 * sh * sh)
    if D == 0.0:
        return None
    rc = R_p * float(np.power(s, 3)) / D
    return rc if (c_lo < pq and rc > 0) else math.inf


def _spin_reversal_one(g: Cycloid):
    """:func:`spin_reversal_phases` of one gear (fields of one element) on Python floats, operation for operation."""
    z1, z2 = int(np.asarray(g.z1).flat[0]), int(np.asarray(g.z2).flat[0])
    e, R_p, R_b, omk = (float(np.asarray(v).flat[0]) for v in (g.e, g.R_p, g.R_b, g.one_minus_K1))
    if (z2 - z1) * R_p == 0.0:
        return spin_reversal_phases(g)
    q = R_b / R_p
    den = 4.0 * (e * z2 / ((z2 - z1) * R_p))
    if den == 0.0 or not math.isfinite(den):
        return spin_reversal_phases(g)
    arg = (q * q - omk * omk) / den                      # omk ** 2 of an array is the square omk * omk
    ok = 0.0 < arg < 1.0
    return np.array([2.0 * float(np.arcsin(math.sqrt(arg))) if ok else math.nan])


_ADMISSIBLE_ONE: dict = {}
"""(z1, z2, e, R_p, R_b, 1 - K1) -> (status, psi*, min rho_c) of one gear: the design checks (at loading) and the
ideal level's solve ask for the same gear's; a pure function of those floats, so the second asks the dict (speed
only; at most ``_ADMISSIBLE_KEEP`` gears kept)."""
_ADMISSIBLE_KEEP = 256


def admissibility(g: Cycloid):
    r"""(status, psi*, min rho_c) of many cycloidal gears (arrays of shape (m,)).

    status 0, TOO_FEW_TEETH (psi* <= 2 pi/z2, pins.md §12.10) or UNDERCUT (R_b >= min rho_c over the loaded arc,
    §4.2).  The ideal level's checks, also run by ``gearcalc check``
    (:func:`gearcalc.pins.checks.ideal_admissibility`).  One gear's result is remembered: loading a design checks
    it, and its solve asks again (:data:`_ADMISSIBLE_ONE`).

    .. math:: \text{TOO\_FEW\_TEETH}: \ \psi^* \le \frac{2\pi}{z_2}, \qquad
        \text{UNDERCUT}: \ R_b \ge \min_{0 \le \psi \le \psi^*} \rho_c(\psi)

    Parameters
    ----------
    g : Cycloid
        Gears whose fields are arrays of shape (m,).

    Returns
    -------
    status : ndarray of int
        0, TOO_FEW_TEETH or UNDERCUT per gear.
    psi_star : ndarray
        End of the loaded arc, [rad].
    rho_c : ndarray
        Least radius of curvature of the pin-centre curve over the loaded arc, [mm].

    Examples
    --------
    >>> g = as_arrays(Cycloid.from_curtate_ratio(20, 22, 3.9, 0.75, 1.95))
    >>> status, psi_star, rho_c = admissibility(g)
    >>> status.tolist(), psi_star.round(6).tolist(), rho_c.round(6).tolist()
    ([0], [2.028497], [14.955298])

    References
    ----------
    .. [1] docs/spec/pins.md §4.2, §12.10.
    """
    if np.size(g.z2) == 1:
        key = tuple(float(np.asarray(v).flat[0]) for v in (g.z1, g.z2, g.e, g.R_p, g.R_b, g.one_minus_K1))
        out = _ADMISSIBLE_ONE.get(key)
        if out is None:
            out = _admissibility(g)
            if len(_ADMISSIBLE_ONE) >= _ADMISSIBLE_KEEP:
                _ADMISSIBLE_ONE.clear()
            _ADMISSIBLE_ONE[key] = out
        return tuple(a.copy() for a in out)
    return _admissibility(g)


def _admissibility(g: Cycloid):
    z2 = np.atleast_1d(g.z2)
    psi_star = crest_cutoffs(g)
    if z2.size == 1:
        rho_c = _min_curvature_radius_one(g, float(psi_star[0]))
        if rho_c is not None:           # one gear on Python floats: the same operations as the arrays below
            status = TOO_FEW_TEETH if psi_star[0] <= 2.0 * math.pi / int(z2[0]) else 0
            if status == 0 and float(np.asarray(g.R_b).flat[0]) >= rho_c:
                status = UNDERCUT
            return np.array([status], dtype=np.int64), psi_star, np.array([rho_c])
    status = np.where(psi_star <= 2.0 * math.pi / z2, TOO_FEW_TEETH, 0)
    rho_c = np.atleast_1d(min_curvature_radius(g, psi_star))
    status = np.where((status == 0) & (np.asarray(g.R_b) >= rho_c), UNDERCUT, status)
    return status, psi_star, rho_c


class CycleSettings(NamedTuple):
    """How :func:`ideal_cycles` integrates, and whether the friction-free peaks are wanted.

    tol, n_max, n_start as :func:`~gearcalc.quadrature.integrate_pieces` takes them; ``first_order_peaks``.
    """

    tol: float = 1e-6
    n_max: int = 2 ** 20
    n_start: int = 16
    first_order_peaks: bool = True


def ideal_cycles(g: Cycloid, n_discs, tol: float = 1e-6, n_max: int = 2 ** 20, n_start: int = 16,
                 first_order_peaks: bool = True) -> IdealCycles:
    r"""Solve the ideal level (pins.md §4, §6) of many cycloidal gears at once, in unit scalings.

    For every gear: psi* (:func:`crest_cutoffs`), the admissibility checks (pins.md §4.2, §12.10),
    the spin reversal, the cycle mean of the loss ratio at mu = 1 (:func:`cycle_pieces` and the
    piecewise trapezoid of :func:`~gearcalc.quadrature.integrate_pieces`, all gears together), and on
    the final grid the peaks of the pin force, the pin loss and the total loss (:func:`_batch_peaks`;
    for n_d > 1 discs the discs' histories summed per pin and crank angle, pins.md §12.7).

    A gear's numbers do not depend on the gears solved with it (sums over contacts in contact order,
    :func:`colsum`; the quadrature accumulates per gear), so a batch gives, bit for bit, what each
    design gives alone.  The integrand also returns what the peaks and the friction-consistent model
    need per node (:func:`_node_rows`), which the quadrature carries to its final grid: the grid is not
    evaluated again.  One gear with one disc (a design computed alone) takes a shorter path to the same
    numbers (:func:`_ideal_alone`, :func:`_one_gear_peaks`: scalar bookkeeping).

    .. math:: \bar\lambda_1 = \frac{1}{T_p} \int_0^{T_p}
        \frac{\sum_{i \in L} |l_i|\,|\rho_i - R_b|}{\sum_{i \in L} l_i^2}\,d\theta \ \ (\mu = 1), \qquad
        F_{max} = \max_\theta \frac{T_{sat}\,r_{p1}}{S(\theta)}

    Parameters
    ----------
    g : gears whose fields are arrays of shape (m,).
    n_discs : discs per gear, shape (m,) (or a scalar).
    tol : relative accuracy target of the cycle mean.
    n_max : cap on crank-angle intervals per period; n_start : intervals of the first level.
    first_order_peaks : False: the friction-free peaks of the one-disc gears (force, loss, total and their
        phases) are not needed (they stay NaN): the friction-consistent model has its own
        (:func:`consistent_cycles`).

    Returns
    -------
    IdealCycles

    Examples
    --------
    >>> g = as_arrays(Cycloid.from_curtate_ratio(20, 22, 3.9, 0.75, 1.95))
    >>> r = ideal_cycles(g, 1)
    >>> bool(r.status[0] == 0 and r.converged[0] and r.loss_ratio_err[0] <= 1e-6 * r.loss_ratio[0])
    True

    References
    ----------
    pins.md §4.2-4.6, §6, §12.1, §12.7, §12.10-12.12.
    """
    z2 = np.atleast_1d(g.z2)
    m = z2.size
    n_discs = np.zeros(m, dtype=np.int64) + n_discs
    status, psi_star, rho_c = admissibility(g)
    psi_0 = _spin_reversal_one(g) if m == 1 else spin_reversal_phases(g)
    how = CycleSettings(tol, n_max, n_start, first_order_peaks)
    if m == 1 and status[0] == 0 and n_discs[0] == 1:
        return _ideal_alone(g, status, psi_star, rho_c, psi_0, how)
    ok = np.flatnonzero(status == 0)
    if ok.size > 1:                                   # groups of equal z2 (then of similar loaded counts)
        ok = ok[np.lexsort((psi_star[ok], z2[ok]))]
    out = _nan_fields(m)
    if ok.size == 0:
        empty = np.zeros(0)
        return IdealCycles(psi_star, psi_0, rho_c, status, grid_t=empty, grid_mid=empty,
                           grid_gear=np.zeros(0, dtype=np.int64), **out)
    return _ideal_batch(g, n_discs, ok, (psi_star, psi_0, rho_c, status), out, how)


def _nan_fields(m: int) -> dict:
    """The per-gear fields of :class:`IdealCycles` before the solve: NaN, False and 0."""
    nan = np.full(m, np.nan)
    out = {k: nan.copy() for k in ("loss_ratio", "loss_ratio_err", "force", "force_phase", "loss", "loss_phase",
                                   "total", "rel_min", "rel_max", "rel_abs")}
    out.update(converged=np.zeros(m, dtype=bool), n_crank=np.zeros(m, dtype=np.int64),
               loaded_min=np.zeros(m, dtype=np.int64), loaded_max=np.zeros(m, dtype=np.int64))
    return out


def _ideal_batch(g: Cycloid, n_discs, ok, solo: tuple, out: dict, how: CycleSettings) -> IdealCycles:
    """:func:`ideal_cycles` of the admissible gears ``ok`` (in solve order), all together.

    ``solo``: (psi*, psi_0, min rho_c, status) of every gear; ``out``: the fields to fill.  The quadrature
    carries the rows of :func:`_node_rows` to the final grid; the gears of several discs whose disc sums would
    cost too much are refused there (TOO_COSTLY) and dropped from the grid.
    """
    psi_star, psi_0, rho_c, status = solo
    gk = Cycloid(*(np.atleast_1d(v)[ok] for v in (g.z1, g.z2, g.e, g.R_p, g.R_b, g.one_minus_K1)))
    G = GearTable.of(gk, psi_star[ok])
    n_ok = ok.size
    a, b, owner = cycle_pieces(gk, psi_star[ok], psi_0[ok])
    jmax = int(np.ceil(G.c.max())) + 1
    alone = n_ok == 1 and n_discs[ok[0]] == 1      # one design: the same numbers, fewer array operations
    peaks = how.first_order_peaks
    # chunks of about 2^14 contacts (at least 1024 nodes): the integrand's (contact, node) arrays then stay
    # in the cache; twice as fast per node as arrays of 2^20 at tol = 1e-9 (speed only: nodes are independent)
    q = integrate_pieces(_unit_loss_ratio(G, owner, grid_rows=True, peaks=peaks), a, b, owner, n_ok,
                         tol=how.tol, n_max=how.n_max, n_start=how.n_start,
                         first_levels=first_levels(how.tol, G.z2[0] if alone else G.z2),
                         chunk=max(1024, 2 ** 14 // jmax))
    out["loss_ratio"][ok], out["loss_ratio_err"][ok] = q.value, q.err
    out["converged"][ok], out["n_crank"][ok] = q.converged, q.n
    t, tmid, piece = q.grid()
    extra = dict(table=G, solved=ok, pieces=(a, b, owner))
    n_grid = len(GRID_ROWS) - 1
    if alone:                                        # the grid's values came with the quadrature
        for key, value in _one_gear_peaks(t, tmid, piece, G, q.carried, peaks).items():
            out[key][ok[0]] = value
        return IdealCycles(psi_star, psi_0, rho_c, status, grid_t=t, grid_mid=tmid,
                           grid_gear=np.zeros(t.size, dtype=np.int64) + ok[0],
                           grid_sums=q.carried[n_grid:n_grid + len(NODE_ROWS)],
                           grid_weights=_grid_weights(t, piece, q.n_piece), n_piece=q.n_piece, **extra, **out)
    rows, gi = q.carried, owner[piece]
    keep = _disc_budget(gi, G, n_discs[ok], status, ok)
    if keep is not None:
        t, tmid, piece, gi, rows = t[keep], tmid[keep], piece[keep], gi[keep], rows[:, keep]
    grid = _FinalGrid(t, tmid, piece, gi, rows)
    _grid_extremes(grid, ok, out)
    one = n_discs[ok] == 1
    for i in np.flatnonzero(~one):                   # several discs (pins.md §12.7): one by one
        if status[ok[i]] == 0:
            _disc_peaks(grid, i, G, int(n_discs[ok[i]]), ok, status, out)
    if peaks and one.any():
        _batch_peaks(grid, np.flatnonzero(one), G, ok, out)
    return IdealCycles(psi_star, psi_0, rho_c, status, grid_t=t, grid_mid=tmid, grid_gear=ok[gi],
                       grid_sums=rows[n_grid:n_grid + len(NODE_ROWS)], grid_weights=_grid_weights(t, piece),
                       **extra, **out)


@dataclass(frozen=True)
class _FinalGrid:
    """The final crank-angle grid of a batch, gear by gear.

    Nodes t, their pieces' midpoints, pieces, gears (solve order) and the carried rows of :func:`_node_rows`
    (the first, lambda, dropped).
    """

    t: np.ndarray
    mid: np.ndarray
    piece: np.ndarray
    gear: np.ndarray
    rows: np.ndarray

    def runs(self):
        """(gears present, the first node of each): the grid's runs of one gear."""
        first = np.flatnonzero(np.diff(self.gear, prepend=-1))
        return self.gear[first], first


def _disc_budget(gi, G: GearTable, n_d, status, ok):
    """Refuse (TOO_COSTLY) the gears of several discs whose disc sums the final grid makes too costly.

    Disc sums too large for the grid --tol needed are refused before any array is built (DISC_SAMPLES_MAX,
    DISC_WORK_MAX).  Returns the mask of the grid nodes to keep, or None (all).
    """
    multi = n_d > 1
    if not multi.any():
        return None
    bound = np.bincount(gi, minlength=ok.size) * (np.ceil(G.c).astype(np.int64) + 1) * n_d
    costly = multi & ((bound > DISC_SAMPLES_MAX) | (bound * n_d > DISC_WORK_MAX))
    if not costly.any():
        return None
    status[ok[costly]] = TOO_COSTLY
    return ~costly[gi]


def _grid_extremes(grid: _FinalGrid, ok, out: dict):
    """rel_min, rel_max, rel_abs, loaded_min, loaded_max of every gear of the grid, from the carried rows.

    rho grows with the phase on [0, pi] (pins.md §4.2), so along a node's loaded contacts rho - R_b is least at
    the first and largest at the last.
    """
    if not grid.t.size:
        return
    here, seg = grid.runs()
    oo = ok[here]
    first, final, J = grid.rows[3], grid.rows[4], grid.rows[5].astype(np.int64)
    out["rel_min"][oo] = np.minimum.reduceat(first, seg)
    out["rel_max"][oo] = np.maximum.reduceat(final, seg)
    out["rel_abs"][oo] = np.maximum.reduceat(np.maximum(np.abs(first), np.abs(final)), seg)
    out["loaded_min"][oo] = np.minimum.reduceat(J, seg)
    out["loaded_max"][oo] = np.maximum.reduceat(J, seg)


def _disc_peaks(grid: _FinalGrid, i: int, G: GearTable, n_d: int, ok, status, out: dict):
    """The peaks of gear i of several discs: its contacts on its final grid summed over the discs (pins.md §12.7).

    Refused (TOO_COSTLY) when its loaded samples make the sums too costly.
    """
    at = np.flatnonzero(grid.gear == i)
    if not at.size:
        return
    zz = int(G.z2[i])
    t, gb = grid.t[at], grid.gear[at]
    J, _, loaded, lev, rho, _, _ = _contact_rows(t, grid.mid[at], gb, G, zz)    # as _contacts
    samples = int(np.count_nonzero(loaded))
    if n_d * samples > DISC_SAMPLES_MAX or n_d * n_d * samples > DISC_WORK_MAX:
        status[ok[i]] = TOO_COSTLY                   # refused: the caller names gearing.discs and --tol
        return
    force = lev / colsum(lev * lev)
    loss = force * np.abs(rho - G.take("R_b", gb)) * 1e-3      # contact_loss_power(force, |rho - R_b|, 1)
    ph = 2.0 * math.pi * ((np.arange(loaded.shape[0])[:, None] + t) / zz)
    out["force"][ok[i]], out["force_phase"][ok[i]] = disc_sum_peak(ph[loaded], force[loaded], n_d)
    out["loss"][ok[i]], out["loss_phase"][ok[i]] = disc_sum_peak(ph[loaded], loss[loaded], n_d)
    out["total"][ok[i]] = float(sum_over_discs(t, colsum(loss), disc_offsets(n_d, zz), 1.0).max())


def _grid_picks(grid: _FinalGrid, G: GearTable):
    """The grid maxima of every gear of the grid, per kind (force, loss, total).

    Returns the gears present and, as arrays (3, gears present): the first node holding the grid maximum, its
    contact row, the maximum and its load-side phase.
    """
    here, seg = grid.runs()
    g = len(GRID_ROWS) - 1
    where = np.searchsorted(here, grid.gear) if here.size > 1 else None
    zero = np.zeros(grid.t.size)
    picks = np.zeros((3, here.size), dtype=np.int64), np.zeros((3, here.size), dtype=np.int64), \
        np.zeros((3, here.size)), np.zeros((3, here.size))
    for kind, (val, row) in enumerate(((0, g + len(NODE_ROWS)), (1, g + len(NODE_ROWS) + 1), (2, None))):
        node_val = grid.rows[val]
        node_row = zero if row is None else grid.rows[row]
        if here.size == 1:                               # grid maximum per gear, first occurrence
            nd = np.atleast_1d(np.argmax(node_val))
            best = node_val[nd]
        else:
            best = np.maximum.reduceat(node_val, seg)
            hit = np.flatnonzero(node_val == best[where])
            nd = hit[np.searchsorted(grid.gear[hit], here)]
        rr = node_row[nd].astype(np.int64)
        picks[0][kind], picks[1][kind], picks[2][kind] = nd, rr, best
        picks[3][kind] = 2.0 * math.pi * ((rr + grid.t[nd]) / G.z2[here])    # as _contacts
    return here, picks


def _batch_peaks(grid: _FinalGrid, sel, G: GearTable, ok, out: dict):
    """Peaks of the one-disc gears ``sel``: refined around the grid maxima (:func:`ideal_cycles`).

    Each starts at its largest grid value and is refined inside the two grid intervals around that node (the
    same piece only: piece ends stay one-sided) by ``REFINE_SAMPLES`` samples and the vertex of the parabola
    through the best sample and its neighbours, keeping the largest value met (a maximum of values actually
    evaluated, never an extrapolation).
    """
    here, picks = _grid_picks(grid, G)
    sel = sel[np.isin(sel, here)]
    if not sel.size:
        return
    col = np.searchsorted(here, sel)
    K, M = 3 * sel.size, REFINE_SAMPLES
    gsel = np.repeat(sel, 3)                                   # gear-major: groups stay contiguous
    kind = np.tile(np.arange(3), sel.size)
    cc = np.repeat(col, 3)
    nd, row, grid_best, grid_ph = (p[kind, cc] for p in picks)
    t, piece = grid.t, grid.piece
    last = t.size - 1
    same_prev = (nd > 0) & (piece[np.maximum(nd - 1, 0)] == piece[nd])
    same_next = (nd < last) & (piece[np.minimum(nd + 1, last)] == piece[nd])
    lo = np.where(same_prev, t[np.maximum(nd - 1, 0)], t[nd])
    hi = np.where(same_next, t[np.minimum(nd + 1, last)], t[nd])
    u = lo[:, None] + (hi - lo)[:, None] * (np.arange(M + 1) / M)
    vals, phs = _peak_values(u.ravel(), np.repeat(grid.mid[nd], M + 1), np.repeat(gsel, M + 1),
                             np.repeat(row, M + 1), np.repeat(kind, M + 1), G)
    vals, phs = vals.reshape(K, M + 1), phs.reshape(K, M + 1)
    r = np.arange(K)
    bi = np.argmax(vals, axis=1)
    bm = np.minimum(np.maximum(bi, 1), M - 1)
    f0, fm, fp = vals[r, bm], vals[r, bm - 1], vals[r, bm + 1]
    den = fp - 2.0 * f0 + fm
    interior = (bi > 0) & (bi < M) & (den < 0.0)
    xv = u[r, bm] - 0.5 * (u[r, bm + 1] - u[r, bm]) * (fp - fm) / np.where(interior, den, -1.0)
    xv = np.where(interior, np.minimum(np.maximum(xv, u[r, bm - 1]), u[r, bm + 1]), u[r, bi])
    vv, phv = _peak_values(xv, grid.mid[nd], gsel, row, kind, G)
    better = vals[r, bi] > grid_best
    best, best_ph = np.where(better, vals[r, bi], grid_best), np.where(better, phs[r, bi], grid_ph)
    better = vv > best
    best, best_ph = np.where(better, vv, best).reshape(-1, 3), np.where(better, phv, best_ph).reshape(-1, 3)
    okk = ok[sel]
    out["force"][okk], out["force_phase"][okk] = best[:, 0], best_ph[:, 0]
    out["loss"][okk], out["loss_phase"][okk] = best[:, 1], best_ph[:, 1]
    out["total"][okk] = best[:, 2]


def _ideal_alone(g: Cycloid, status, psi_star, rho_c, psi_0, how: CycleSettings) -> IdealCycles:
    """:func:`ideal_cycles` of one admissible gear with one disc (a design computed alone).

    The same steps and numbers as there, without the bookkeeping of many gears (fields of one element).
    """
    fields = (g.z1, g.z2, g.e, g.R_p, g.R_b, g.one_minus_K1)
    gk = g if all(isinstance(v, np.ndarray) and v.ndim == 1 for v in fields) else Cycloid(*map(np.atleast_1d, fields))
    G = GearTable.of(gk, psi_star)
    a, b, owner = cycle_pieces(gk, psi_star, psi_0)
    jmax = int(np.ceil(G.c.max())) + 1
    q = integrate_pieces(_unit_loss_ratio(G, owner, grid_rows=True, peaks=how.first_order_peaks), a, b, owner, 1,
                         tol=how.tol, n_max=how.n_max, n_start=how.n_start,
                         first_levels=first_levels(how.tol, int(G.z2[0])), chunk=max(1024, 2 ** 14 // jmax))
    t, tmid, piece = q.grid()
    peaks = _one_gear_peaks(t, tmid, piece, G, q.carried, how.first_order_peaks)
    nan = math.nan
    f = np.array([[peaks.get(k, nan)] for k in ("force", "force_phase", "loss", "loss_phase", "total", "rel_min",
                                                 "rel_max", "rel_abs")])
    solved = np.zeros(1, dtype=np.int64)
    return IdealCycles(psi_star, psi_0, rho_c, status, loss_ratio=q.value, loss_ratio_err=q.err,
                       converged=np.asarray(q.converged, dtype=bool), n_crank=np.asarray(q.n, dtype=np.int64),
                       force=f[0], force_phase=f[1], loss=f[2], loss_phase=f[3], total=f[4], rel_min=f[5], rel_max=f[6],
                       rel_abs=f[7], loaded_min=np.array([peaks["loaded_min"]]).astype(np.int64),
                       loaded_max=np.array([peaks["loaded_max"]]).astype(np.int64), grid_t=t, grid_mid=tmid,
                       grid_gear=np.zeros(t.size, dtype=np.int64), grid_sums=q.carried[len(GRID_ROWS) - 1:],
                       grid_weights=_grid_weights(t, piece, q.n_piece), table=G, solved=solved, pieces=(a, b, owner),
                       n_piece=q.n_piece)


def _grid_weights(t, piece, n_piece=None):
    """Trapezoid weights of a final grid's nodes at its levels L, L-1 and L-2.

    Trapezoid weights of a final grid's nodes (piece by piece, ends on every piece) at its level L and at L-1 and
    L-2 (every 2nd and 4th node of each piece; a final level has at least 4 intervals a piece, pins.md §6, §12.6),
    shape (3, nodes).  ``n_piece``: the intervals of each piece when they are known (one gear: the pieces are filled
    one by one, the same numbers).
    """
    w = np.zeros((3, t.size))
    if t.size == 0:
        return w
    if n_piece is not None and len(n_piece) <= 8:
        s = 0
        for n in np.asarray(n_piece).tolist():
            e = s + n
            h = (float(t[e]) - float(t[s])) / n          # as below: (last - first)/(count - 1)
            for r, (f, step) in enumerate(((1.0, 1), (2.0, 2), (4.0, 4))):
                fh = f * h
                w[r, s:e + 1:step] = fh
                w[r, s] = fh * 0.5
                if n % step == 0:
                    w[r, e] = fh * 0.5
            s = e + 1
        return w
    new_piece = np.empty(t.size, dtype=bool)
    new_piece[0] = True
    np.not_equal(piece[1:], piece[:-1], out=new_piece[1:])
    start = np.flatnonzero(new_piece)
    count = np.concatenate((start[1:], [t.size])) - start
    run = np.repeat(np.arange(start.size), count)
    k = np.arange(t.size) - start[run]
    n = (count - 1)[run]
    h = ((t[start + count - 1] - t[start]) / (count - 1))[run]
    end = np.where((k == 0) | (k == n), 0.5, 1.0)
    w[0] = h * end
    w[1] = np.where(k % 2 == 0, 2.0 * h * end, 0.0)
    w[2] = np.where(k % 4 == 0, 4.0 * h * end, 0.0)
    return w


@dataclass
class CycleIntegral:
    """Cycle mean of the loss ratio: value (Richardson), err (|Q_2N - Q_N|), and the quadrature."""

    loss_ratio: float
    loss_ratio_err: float
    converged: bool
    n_crank: int
    quad: QuadResult | None


def mean_loss_ratio(g: Cycloid, psi_star: float, psi_0: float | None, mu_eff: float, tol: float = 1e-6,
                    n_max: int = 2 ** 20, n_start: int = 16, n_initial=None) -> CycleIntegral:
    r"""Cycle mean lambda_bar = (1/T_p) integral of lambda over one period, with an honest error.

    Piecewise trapezoid between the breakpoints of :func:`cycle_pieces` (those of
    :func:`cycle_breakpoints`), doubled to ``tol`` (pins.md §6), with the integrator and integrand
    of :func:`ideal_cycles` (one gear).  mu_eff = 0 short-circuits to exactly 0 with error 0.

    .. math:: \bar\lambda = \frac{1}{T_p} \int_0^{T_p} \lambda(\theta)\,d\theta, \qquad
        \lambda = \mu_{eff}\,\frac{\sum_{i \in L} |l_i|\,|\rho_i - R_b|}{\sum_{i \in L} l_i^2}

    Parameters
    ----------
    g : the gear; psi_star : end of the loaded arc [rad]; psi_0 : spin reversal phase or None [rad].
    mu_eff : f (fixed pins) or mu_rot (rolling pins) [-].
    tol : relative accuracy target.
    n_max : cap on crank-angle intervals per period.
    n_start : intervals of the first level.
    n_initial : intervals per piece of the first level (see :func:`~gearcalc.quadrature.integrate_pieces`).

    Returns
    -------
    CycleIntegral

    Examples
    --------
    >>> from gearcalc.pins import crest_cutoff
    >>> g = Cycloid.from_curtate_ratio(20, 22, 3.9, 0.75, 1.95)
    >>> r = mean_loss_ratio(g, crest_cutoff(g), None, 0.1)
    >>> bool(r.converged and r.loss_ratio_err < 1e-6 * r.loss_ratio)
    True

    References
    ----------
    .. [1] A. P. Prudnikov, «Потери мощности в контакте цевок и зубьев планетарной передачи типа K-H-V» (Power losses in
       pins and teeth contact area of KHV-type planetary gearing), Машиностроение (seed file 000_fe288dec6e7c72f0.txt);
       docs/spec/pins.md §4.6, §6.
    """
    if mu_eff == 0.0:
        return CycleIntegral(0.0, 0.0, True, 0, None)
    ga = as_arrays(g)
    ps = np.array([psi_star], dtype=float)
    a, b, owner = cycle_pieces(ga, ps, np.array([np.nan if psi_0 is None else psi_0]))
    unit = _unit_loss_ratio(GearTable.of(ga, ps), owner)
    q = integrate_pieces(lambda x, mid, piece: mu_eff * unit(x, mid, piece), a, b, owner, 1, tol=tol,
                         n_max=n_max, n_start=n_start, n_initial=n_initial, first_levels=first_levels(tol))
    quad = QuadResult(value=q.value, err=q.err, trapezoid=q.trapezoid, n=int(q.n[0]), converged=bool(q.converged[0]),
                      levels=int(q.levels[0]), edges=np.concatenate((a, b[-1:])), n_piece=q.n_piece)
    return CycleIntegral(float(q.value[0]), float(q.err[0]), bool(q.converged[0]), int(q.n[0]), quad)
