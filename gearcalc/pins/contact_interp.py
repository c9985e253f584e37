"""KHV pin gearing, level ``contact``: states between the solved nodes of a cycle (pins.md §5.5, §6, §8).

The warm starts of the nodes from the solved ones of the same piece (:func:`piece_keys`, :func:`piece_guess`: cubic
Hermite in tau) and the states between the nodes of a Gauss-Kronrod cycle by each piece's interpolating polynomial
(:func:`gk_interpolated`).  Pure functions over the states of :mod:`gearcalc.pins.contact_states`.
"""
from __future__ import annotations

import numpy as np

from ..quadrature import _KRONROD, QuadResult
from .contact_states import Solution, hermite

__all__ = ["piece_keys", "piece_guess", "gk_interpolated"]


def piece_keys(edges, x, mid):
    r"""The nodes' places within the piece of their midpoint, as sortable keys.

    The nodes' places 2 p + (x - a_p)/(b_p - a_p) in [2 p, 2 p + 1], p the piece of the midpoint ``mid`` (edges
    sorted): the keys of two pieces never meet, so the piece ends are told apart from their neighbours'.

    .. math:: \text{key} = 2p + \frac{x - a_p}{b_p - a_p} \in [2p,\ 2p + 1], \qquad p = \text{the piece of } mid

    Parameters
    ----------
    edges : ndarray
        Piece ends, sorted, [rad].
    x : ndarray
        Nodes, [rad].
    mid : ndarray
        The midpoints of their pieces, [rad].

    Returns
    -------
    keys : ndarray
        Sortable keys, [-].

    Examples
    --------
    >>> piece_keys(np.array([0.0, 1.0, 2.0]), np.array([0.0, 0.5, 1.0, 1.0, 2.0]),
    ...            np.array([0.5, 0.5, 0.5, 1.5, 1.5])).tolist()
    [0.0, 0.5, 1.0, 2.0, 3.0]

    References
    ----------
    .. [1] docs/spec/pins.md §6, §12.6.
    """
    p = np.minimum(np.maximum(edges.searchsorted(mid) - 1, 0), edges.size - 2)
    a, b = edges[p], edges[p + 1]
    with np.errstate(divide="ignore", invalid="ignore"):
        t = np.where(b > a, (x - a) / (b - a), 0.5)
    return 2.0 * p + np.minimum(np.maximum(t, 0.0), 1.0)


def piece_guess(keys, tau, dtau, key, x, edges):
    r"""Warm starts of tau at the nodes ``key`` from the solved nodes of the same piece.

    Warm starts of tau at the nodes ``key`` (:func:`piece_keys`) from the solved nodes of the same piece around each
    (keys sorted): the cubic Hermite interpolant of tau and d tau/d theta (one-sided at the piece's ends, from
    inside it), error O(h^4) in their spacing h; NaN where the piece has no solved node on either side (then the
    model's own warm start, :meth:`ContactModel.state`).  None when nothing is solved yet.

    .. math:: \tau(x) \approx p\!\left(\frac{x - x_a}{h}\right), \qquad h = x_b - x_a \quad \text{(cubic Hermite)}

    Parameters
    ----------
    keys : ndarray
        The solved nodes' keys (:func:`piece_keys`), sorted.
    tau, dtau : ndarray
        tau [rad] and d tau/d theta [-] at the solved nodes.
    key : ndarray
        The keys of the nodes to start.
    x : ndarray
        Their crank angles, [rad].
    edges : ndarray
        Piece ends, [rad].

    Returns
    -------
    guess : ndarray or None
        Warm starts, [rad] (NaN without solved nodes on both sides in the piece), or None.

    Examples
    --------
    >>> piece_guess(np.array([0.0, 1.0]), np.array([0.0, 1.0]), np.array([1.0, 1.0]), np.array([0.5, 2.5]),
    ...             np.array([0.5, 1.5]), np.array([0.0, 1.0, 2.0])).tolist()   # tau = theta; no node in piece 2
    [0.5, nan]

    References
    ----------
    .. [1] docs/spec/pins.md §5.5, §12.6 (warm starts).
    """
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


def _lagrange_matrix(nodes, points):
    """The Lagrange basis of ``nodes`` at ``points``.

    L (len(points), len(nodes)), sum_k L[j, k] f(nodes[k]) is the interpolating polynomial at points[j] (barycentric
    weights; exact for polynomials of degree < len(nodes)).

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
    loaded interval, the detail and the check of the breakpoints (:func:`~gearcalc.pins.contact_roots.pieces_hold`),
    never the mean (pins.md §6, §8).  Returns (the interpolated :class:`Solution`, sorted by theta; each point's
    piece midpoint), or None when the nodes are not found on ``sol``.

    Parameters
    ----------
    sol : Solution
        The solved states of a Gauss-Kronrod cycle.
    q : QuadResult
        Its quadrature (the bisected pieces).
    rule : {"gk7", "gk15"}
        The rule.
    per_period : int
        Interpolated points per period (at least 2 a piece).

    Returns
    -------
    interpolated : tuple or None
        (the interpolated :class:`Solution`, sorted by theta; each point's piece midpoint [rad]), or None.

    Examples
    --------
    >>> from gearcalc.pins.contact import MULTIPLIER, ContactModel, Cycloid, CycloidProfile, contact_law
    >>> from gearcalc.pins.contact import mean_loss_ratio
    >>> g = Cycloid.from_curtate_ratio(21, 22, 3.9, 0.75, 1.95)
    >>> model = ContactModel(g, CycloidProfile(g, 0.0, 0.0), contact_law("linear", stiffness=1e5), 1e4, MULTIPLIER)
    >>> cyc = mean_loss_ratio(model, (0.1, 0.1, False), tol=1e-5, rule="gk7")
    >>> pts, mids = gk_interpolated(cyc.sol, cyc.quad, "gk7", 8)
    >>> pts.theta.size, bool(np.all(np.diff(pts.theta) >= 0.0))
    (12, True)

    References
    ----------
    .. [1] A. S. Kronrod, Nodes and Weights of Quadrature Formulas, Consultants Bureau, New York, 1965;
       docs/spec/pins.md §6, §8.
    """
    points = _gk_points(sol, q, rule, per_period)
    if points is None:
        return None
    K, W, theta, mids = points
    return _interpolated(sol, K, W, theta), mids


def _gk_points(sol: Solution, q: QuadResult, rule: str, per_period: int):
    """The interpolated points of :func:`gk_interpolated`: (K, W, theta, mids) or None.

    K (n, m): the indices into ``sol`` of each point's piece's Kronrod nodes; W (n, m): their Lagrange weights at the
    point; theta: the points (J per piece in proportion to its length, strictly inside its outer nodes); mids: their
    pieces' midpoints.  None when the nodes are not found on ``sol`` or no point is left.
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
    # (n, m): one row of weights per point, and the node indices into sol
    return k_all[piece], _lagrange_matrix(t, s), c[piece] + h[piece] * s, mid_all[piece]


def _interpolated(sol: Solution, K, W, theta) -> Solution:
    """The states at ``theta`` from the nodes ``K`` of ``sol`` with the weights ``W`` (:func:`gk_interpolated`)."""
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
    return Solution(theta, interp(sol.tau), interp(sol.dtau), np.zeros(n), delta,
                    np.maximum(interp_pins(sol.force, 0.0), 0.0), interp_pins(sol.v_t, 0.0), None, None,
                    interp_pins(sol.switch, np.nan), per_piece(sol.branch, lambda v: v[..., 0]),
                    None if sol.cand is None else cand, interp_pins(sol.ddelta, 0.0),
                    per_piece(sol.noise, lambda v: v.max(axis=-1)), interp(sol.g_tau), rows=sol.rows,
                    traction=per_piece(sol.traction, lambda v: v[..., 0]))
