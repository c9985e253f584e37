"""Cycle integration: a piecewise composite rule with Richardson extrapolation and an honest error.

The integrands of the cycle models (the loss ratio of a pin gear over one crank-angle period, and
the like) are smooth between known breakpoints (a pin enters or leaves the loaded set, a pin's spin
reverses) and jump or kink at them.  A uniform grid that ignores the breakpoints converges
erratically (kinks) or only to first order (jumps), so:

* the period is cut into smooth *pieces* at the breakpoints;
* each piece gets its own composite trapezoid; its end nodes are evaluated as one-sided limits,
  because the integrand is told the piece it belongs to (its midpoint, where set membership is
  decided);
* the node count per piece is fixed at the first level (proportional to the piece length, at least
  2) and then doubled exactly on every piece; only the new (odd) nodes are evaluated;
* the reported value is the Richardson value ``Q_2N + (Q_2N - Q_N)/3`` and the reported error the
  conservative ``E = |Q_2N - Q_N|`` (pins.md §6 and §12.6): an independent finer computation lies
  within it;
* doubling stops when ``E <= max(tol |Q|, atol)`` on two successive doublings, or at ``n_max``
  (:func:`integrate_pieces` also stops an integral at once where its sum is not finite: it would stay so
  at every finer level; value and error NaN, not converged).

Two drivers apply this rule: :func:`integrate_adaptive` (one integral; a piece is doubled only while it
needs it) and :func:`integrate_pieces` (many integrals at once, all pieces of an integral doubled
together; its docstring says why both remain).

Boundary layers (a feature of width ``w`` at a breakpoint) are resolved by geometric grading,
:func:`geometric_breakpoints`, which adds breakpoints at ``x0 + L q^m``.  Breakpoints that are not
known in closed form (the sign changes of a contact penetration at a compliant contact level) are
located by :func:`sign_change_breakpoints` with the shared bracketed root finder.

Everything is vectorised: the integrand receives arrays of nodes (in chunks, for
:func:`integrate_pieces`).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .arrays import unique_sorted
from .roots import bisect


@dataclass
class QuadResult:
    """The result of :func:`integrate_adaptive`.

    value : Richardson value, shape (1,) [unit of f x unit of x].
    err : conservative error estimate |Q_2N - Q_N|, shape (1,).
    trapezoid : the finest plain trapezoid value Q_2N, shape (1,).
    n : total number of intervals of the finest level.
    converged : whether the tolerance was met on two successive doublings.
    levels : the most doublings of a piece.
    edges : piece ends, shape (p + 1,).
    n_piece : intervals per piece at the finest level, shape (p,).
    rule : ``"trapezoid"``, or a Gauss-Kronrod rule (``"gk7"``, ``"gk15"``): then ``trapezoid`` holds the Kronrod
        value, ``n`` the integrand evaluations, ``levels`` the most bisections of a piece, ``edges`` the ends
        of the (bisected) pieces, ``n_piece`` the nodes per piece and ``mid`` the midpoint of the breakpoints'
        piece each of them lies in (its set membership).
    """

    value: np.ndarray
    err: np.ndarray
    trapezoid: np.ndarray
    n: int
    converged: bool
    levels: int
    edges: np.ndarray
    n_piece: np.ndarray
    rule: str = "trapezoid"
    mid: np.ndarray | None = None

    def grid(self):
        """Nodes of the finest level: (x, piece midpoint, piece index), piece by piece.

        Breakpoints appear once per adjacent piece (the one-sided limits of both sides).  For a Gauss-Kronrod
        rule: the Kronrod nodes of every piece (no piece ends), with the midpoint of the breakpoints' piece.

        Returns
        -------
        x, mid, piece : arrays of the same length (sum of n_piece + 1 over pieces; Gauss-Kronrod: of n_piece).
        """
        if self.rule != "trapezoid":
            t = _KRONROD[self.rule][0]
            a, b = self.edges[:-1], self.edges[1:]
            x = (0.5 * (a + b))[:, None] + (0.5 * (b - a))[:, None] * t[None, :]
            piece = np.repeat(np.arange(a.size), t.size)
            return x.ravel(), self.mid[piece], piece
        return piece_nodes(self.edges, self.n_piece)


def piece_nodes(edges, n_piece):
    r"""All nodes of a piecewise uniform grid, piece by piece (ends included on every piece).

    .. math:: x_{p,k} = a_p + (b_p - a_p)\,\frac{k}{n_p}, \quad k = 0, \dots, n_p, \qquad
        m_p = \tfrac12 (a_p + b_p)

    Parameters
    ----------
    edges : piece ends, increasing, shape (p + 1,).
    n_piece : intervals per piece, shape (p,).

    Returns
    -------
    x, mid, piece : nodes, the midpoint of their piece, and their piece index.

    Examples
    --------
    >>> x, mid, piece = piece_nodes(np.array([0.0, 1.0, 3.0]), np.array([2, 2]))
    >>> x.tolist(), piece.tolist()
    ([0.0, 0.5, 1.0, 1.0, 2.0, 3.0], [0, 0, 0, 1, 1, 1])

    References
    ----------
    .. [1] docs/spec/pins.md §6 (the cycle quadrature's pieces and one-sided ends).
    """
    edges = np.asarray(edges, dtype=float)
    n_piece = np.asarray(n_piece, dtype=np.int64)
    counts = n_piece + 1
    piece = np.repeat(np.arange(len(n_piece)), counts)
    start = np.concatenate(([0], np.cumsum(counts)[:-1]))
    k = np.arange(int(counts.sum())) - np.repeat(start, counts)
    a, b = edges[:-1][piece], edges[1:][piece]
    frac = k / n_piece[piece]
    x = np.where(k == n_piece[piece], b, a + (b - a) * frac)
    return x, 0.5 * (a + b), piece


def geometric_breakpoints(x0: float, x1: float, width: float, ratio: float = 0.5) -> np.ndarray:
    r"""Breakpoints grading a piece geometrically toward its end ``x0``.

    Returns ``x0 + (x1 - x0) ratio^m`` for m = 1 ... M, M the first with a distance below
    ``width / 4`` (so a boundary layer of that width is covered by several pieces); empty when
    ``width`` is not smaller than the piece.  ``x1`` may lie on either side of ``x0``.

    .. math:: x_m = x_0 + (x_1 - x_0)\,q^m, \quad m = 1, \dots, M, \qquad
        M = \left\lceil \frac{\ln(4 |x_1 - x_0| / w)}{\ln(1/q)} \right\rceil \ (\le 200)

    Parameters
    ----------
    x0 : the end to grade toward [unit of x].
    x1 : the other end of the piece [unit of x].
    width : width of the boundary layer at x0 [unit of x], > 0.
    ratio : geometric ratio, 0 < ratio < 1.

    Returns
    -------
    x : ndarray
        The breakpoints, nearest to x1 first, [unit of x].

    Examples
    --------
    >>> geometric_breakpoints(0.0, 1.0, 0.1).tolist()
    [0.5, 0.25, 0.125, 0.0625, 0.03125, 0.015625]

    References
    ----------
    .. [1] docs/spec/pins.md §6 (geometric grading of boundary layers), §12.6.
    """
    span = x1 - x0
    if width <= 0 or not np.isfinite(width) or abs(span) <= width:
        return np.empty(0)
    m = int(np.ceil(np.log(4.0 * abs(span) / width) / np.log(1.0 / ratio)))
    m = min(m, 200)
    return x0 + span * ratio ** np.arange(1, m + 1)


def sign_change_breakpoints(g, a: float, b: float, n_scan: int, xtol: float) -> np.ndarray:
    r"""Locate every sign change of the components of ``g`` on [a, b] (breakpoints not known in closed form).

    ``g(x)`` maps an array of x (shape (n,)) to an array (c, n) of c components (penetrations,
    tangential speeds).  Each component is scanned on ``n_scan`` uniform intervals, and each
    sign change between neighbours is refined by bisection to ``xtol``.  Changes closer together
    than the scan step can be missed: choose n_scan accordingly (the caller's responsibility).

    .. math:: \{x \in (a, b) : g_c(x) = 0,\ \operatorname{sign} g_c \text{ changes}\}, \qquad
        |x - x^*| \le \text{xtol}

    Parameters
    ----------
    g : callable
        g(x) maps an array of x, shape (n,), to an array (c, n) of c components.
    a, b : float
        The range, [unit of x].
    n_scan : int
        Uniform scan intervals.
    xtol : float
        Location tolerance of each root, [unit of x].

    Returns
    -------
    Sorted array of the located breakpoints (inside (a, b)).

    Examples
    --------
    >>> sign_change_breakpoints(lambda x: np.sin(x)[None], 0.5, 7.0, 64, 1e-13).round(10).tolist()
    [3.1415926536, 6.2831853072]

    References
    ----------
    .. [1] docs/spec/pins.md §6 (breakpoints located numerically at the contact level).
    """
    x = np.linspace(a, b, n_scan + 1)
    v = np.atleast_2d(np.asarray(g(x), dtype=float))
    sgn = np.sign(v)
    change = sgn[:, :-1] * sgn[:, 1:] < 0
    comp, idx = np.nonzero(change)
    if comp.size == 0:
        return np.empty(0)

    def h(t):
        return np.atleast_2d(np.asarray(g(t), dtype=float))[comp, np.arange(comp.size)]

    res = bisect(h, x[idx], x[idx + 1], xtol=xtol)
    return np.sort(res.root)


def _kronrod_table(xk, wk, wg):
    """(nodes, Kronrod weights, Gauss weights) on [-1, 1], ascending, from the non-negative half (0 last).

    The Gauss nodes are every second Kronrod node from the second.
    """
    xk, wk, wg = (np.asarray(v, dtype=float) for v in (xk, wk, wg))
    t = np.concatenate((-xk[:-1], xk[::-1]))
    w = np.concatenate((wk[:-1], wk[::-1]))
    g = np.zeros(t.size)
    g[1::2] = np.concatenate((wg[:-1], wg[::-1]))
    return t, w, g


# Gauss-Kronrod pairs (QUADPACK's qk15 constants; the 7-point Kronrod extension of the 3-point Gauss rule)
_KRONROD = {
    "gk7": _kronrod_table([0.960491268708020283423507092629080, 0.774596669241483377035853079956480,
                           0.434243749346802558002071502844628, 0.0],
                          [0.104656226026467265193823857192073, 0.268488089868333440728569280666710,
                           0.401397414775962222905051818618432, 0.450916538658474142345110087045571],
                          [5.0 / 9.0, 8.0 / 9.0]),
    "gk15": _kronrod_table([0.991455371120812639206854697526329, 0.949107912342758524526189684047851,
                            0.864864423359769072789712788640926, 0.741531185599394439863864773280788,
                            0.586087235467691130294144845693013, 0.405845151377397166906606412076961,
                            0.207784955007898467600689403773245, 0.0],
                           [0.022935322010529224963732008058970, 0.063092092629978553290700663189204,
                            0.104790010322250183839876322541518, 0.140653259715525918745189590510238,
                            0.169004726639267902826583426598550, 0.190350578064785409913256402421014,
                            0.204432940075298892414161999234649, 0.209482141084727828012999174891714],
                           [0.129484966168869693270611432679082, 0.279705391489276667901467771423780,
                            0.381830050505118944950369775488975, 0.417959183673469387755102040816327]),
}


def _gauss_kronrod(f, a, b, rule: str, tol: float, atol: float, n_max: int) -> QuadResult:
    """:func:`integrate_adaptive` with a Gauss-Kronrod rule per piece (``rule`` ``"gk7"`` or ``"gk15"``).

    Each piece gets the Kronrod value K_p and the error e_p = |K_p - G_p| of the embedded Gauss rule (the error
    of the lower-order rule: conservative for K_p on a piece where f is smooth).  Q = sum K_p, E = sum e_p,
    accepted when E <= max(tol |Q|, atol); otherwise the pieces with the largest e_p are bisected, largest
    first, until the others hold at most half of the tolerance, as many as ``n_max`` evaluations in all allow
    (unconverged when none fits).  The halves of a piece keep the midpoint of the breakpoints' piece as their
    ``mid`` (set membership), and no piece end is evaluated (one-sided limits are not needed).
    """
    t, wk, wg = _KRONROD[rule]
    m = t.size
    mid0 = 0.5 * (a + b)

    def apply(a, b, mid):
        x = (0.5 * (a + b))[:, None] + (0.5 * (b - a))[:, None] * t[None, :]
        v = np.asarray(f(x.ravel(), np.repeat(mid, m)), dtype=float).reshape(a.size, m)
        h = 0.5 * (b - a)
        return h * (v @ wk), h * (v @ wg)

    K, G = apply(a, b, mid0)
    mid, depth = mid0, np.zeros(a.size, dtype=np.int64)
    n = m * a.size
    converged = False
    while True:
        e = np.abs(K - G)
        Q = float(np.sum(K))
        budget = max(tol * abs(Q), atol)
        if float(np.sum(e)) <= budget:
            converged = True
            break
        splittable = 0.5 * (a + b) > a                  # a piece whose halves are still distinct floats
        est = np.where(splittable, e, 0.0)
        order = np.argsort(-est, kind="stable")
        rest = e.sum() - np.cumsum(est[order])
        k = int(np.searchsorted(-rest, -0.5 * budget)) + 1
        k = min(k, (n_max - n) // (2 * m), int(np.count_nonzero(est > 0.0)))
        if k <= 0:
            break
        sel = np.zeros(a.size, dtype=bool)
        sel[order[:k]] = True
        c = 0.5 * (a[sel] + b[sel])
        K2, G2 = apply(np.concatenate((a[sel], c)), np.concatenate((c, b[sel])), np.concatenate((mid[sel], mid[sel])))
        keep = ~sel
        a = np.concatenate((a[keep], a[sel], c))
        b = np.concatenate((b[keep], c, b[sel]))
        mid = np.concatenate((mid[keep], mid[sel], mid[sel]))
        depth = np.concatenate((depth[keep], depth[sel] + 1, depth[sel] + 1))
        K, G = np.concatenate((K[keep], K2)), np.concatenate((G[keep], G2))
        o = np.argsort(a, kind="stable")
        a, b, mid, depth, K, G = a[o], b[o], mid[o], depth[o], K[o], G[o]
        n += 2 * m * k
    value = float(np.sum(K))
    return QuadResult(value=np.array([value]), err=np.array([float(np.sum(np.abs(K - G)))]),
                      trapezoid=np.array([value]), n=int(n), converged=converged, levels=int(depth.max()),
                      edges=np.concatenate((a, b[-1:])), n_piece=np.full(a.size, m, dtype=np.int64), rule=rule,
                      mid=mid)


def integrate_adaptive(f, breakpoints, tol: float = 1e-6, atol: float = 1e-14, n_start: int = 128,
                       n_max: int = 2 ** 12, min_levels: int = 2, n_initial=None,
                       rule: str = "trapezoid", n_min: int = 2, at_once: int = 0) -> QuadResult:
    r"""Piecewise composite trapezoid with Richardson extrapolation, refined piece by piece (pins.md §6, §12.6).

    The rule of the module docstring (first level ``n_start`` intervals per range shared out in proportion to the
    piece lengths, rounded up, at least ``n_min`` per piece; node counts then doubled exactly, only the new nodes
    evaluated; one-sided piece ends; the integrand ``f(x, mid)`` told the piece midpoint), but a piece is doubled only
    while it needs it.  Every piece is doubled ``min_levels`` times; then, with the piece
    estimates e_p = T_2N,p - T_N,p of each piece's last doubling and e'_p of the one before,

    .. math::

        Q = \sum_p T_{2N,p} + e_p/3,\qquad E = \Big|\sum_p \hat e_p\Big|

    with \hat e_p = (4 e_p - e'_p)/3, the change of the piece's Richardson value, on a piece in its asymptotic regime
    (e'_p/e_p in :data:`ROMBERG_RATIO`), else e_p (:func:`piece_errors`), is accepted when E <= max(tol |Q|, atol)
    and the other pieces' |sum e'_p| <= max(tol |Q|, atol): on those the rule of two successive doublings, with each
    piece's own last two (decided 2026-11-27: before, every piece kept e_p and that rule, which overstated the
    error of Q 30-100x on the contact level's smooth pieces, pins.md §6).  Otherwise the pieces with the largest
    estimates (|\hat e_p|, or max(|e_p|, |e'_p|)) are doubled, largest first, until the others hold at most half
    of the tolerance (the tiny pieces of a geometric grading, whose estimates are far below it, stop
    after ``min_levels`` doublings), as many of them as ``n_max`` intervals in all allow.  Stops
    unconverged when not even the first of them can be doubled.

    ``n_initial`` (one count per piece, optional) replaces the first level's counts, e.g. a quarter of
    the final counts of a run on nearly the same integrand (the next pass of the torque fixed point).
    ``n_min`` is the least count of a piece at the first level (default 2; 1 lets the tiny pieces of a
    geometric grading cost 4 intervals after the two doublings instead of 8).

    ``at_once`` (at most ``min_levels``): the first level and that many doublings in one call of ``f`` (the finest
    grid's nodes; the coarser levels' sums from its nested subsets), for an integrand whose calls cost more than its
    nodes; the doublings are then accepted as above.

    ``rule`` ``"gk7"`` or ``"gk15"`` (opt-in) replaces the composite trapezoid by a Gauss-Kronrod pair per piece,
    pieces bisected while needed (:func:`_gauss_kronrod`; ``n_start``, ``min_levels`` and ``n_initial`` unused,
    ``n_max`` caps the evaluations): far fewer evaluations on smooth pieces, no piece ends among the nodes.

    Returns a :class:`QuadResult` (value and err of one component; ``levels`` the most doublings of a
    piece, ``n_piece`` the intervals per piece).  With a ``tol`` that is never met, every piece whose
    estimate is not 0 is doubled at every level, as ``n_max`` allows: the uniform doubling of pins.md §6.

    Parameters
    ----------
    f : callable
        The integrand f(x, mid): nodes x and the midpoints of their pieces (set membership), arrays.
    breakpoints : array_like
        Ends of the smooth pieces, increasing, [unit of x].
    tol, atol : float, optional
        Relative and absolute tolerance of the value.
    n_start : int, optional
        First level's intervals per range.
    n_max : int, optional
        Most intervals in all (Gauss-Kronrod: evaluations).
    min_levels : int, optional
        Doublings every piece gets.
    n_initial : array_like, optional
        First level's intervals per piece.
    rule : {"trapezoid", "gk7", "gk15"}, optional
        The rule per piece.
    n_min : int, optional
        Least intervals of a piece at the first level.
    at_once : int, optional
        Doublings evaluated in the first call of ``f``.

    Returns
    -------
    result : QuadResult
        The value and error of one component, the grid and the counts.

    Examples
    --------
    A jump at x = 1 and a kink at x = 2 (exact on the pieces), and a smooth piece:

    >>> g = lambda x, mid: np.where(mid < 1.0, 0.0, 1.0) + np.abs(x - 2.0) + np.where(mid > 3.0, np.exp(x), 0.0)
    >>> r = integrate_adaptive(g, [0.0, 1.0, 2.0, 3.0, 4.0], tol=1e-6)
    >>> bool(abs(r.value[0] - (7.0 + math.e ** 4 - math.e ** 3)) <= r.err[0] / 10), r.converged, r.n_piece.tolist()
    (True, True, [128, 128, 128, 128])

    (the exponential piece's Richardson value is off by 1/15 of its estimate, the change from the level before;
    with e_p alone it took 1024 intervals.)

    References
    ----------
    pins.md §6 (rule, error estimate), §12.6 (per-piece doubling at the contact level).
    """
    edges = unique_sorted(np.asarray(breakpoints, dtype=float))
    a, b = edges[:-1], edges[1:]
    keep = b > a
    a, b = a[keep], b[keep]
    if rule != "trapezoid":
        if rule not in _KRONROD:
            raise ValueError(f"rule {rule!r}: one of 'trapezoid', {', '.join(map(repr, _KRONROD))}")
        return _gauss_kronrod(f, a, b, rule, tol, atol, n_max)
    edges = np.concatenate((a, b[-1:]))
    p = a.size
    if n_initial is not None and np.size(n_initial) == p:
        n_piece = np.maximum(n_min, np.asarray(n_initial)).astype(np.int64)
    else:
        # ceil: no piece coarser than n_start per period (a node spacing of at most (b - a)/n_start at the first level)
        n_piece = np.maximum(n_min, np.ceil(n_start * (b - a) / (b[-1] - a[0]) * (1.0 - 1e-12))).astype(np.int64)
    mid_p = 0.5 * (a + b)
    L = max(0, min(int(at_once), min_levels))
    if L and int(n_piece.sum()) << L > n_max:
        L = 0
    x, mid, piece = piece_nodes(edges, n_piece << L)
    w = np.where(np.concatenate(([True], piece[1:] != piece[:-1])) | np.concatenate((piece[1:] != piece[:-1], [True])),
                 0.5, 1.0)
    v = np.asarray(f(x, mid), dtype=float).ravel()
    e_last = np.full(p, np.nan)
    e_prev = np.full(p, np.nan)
    lev = np.zeros(p, dtype=np.int64)
    if L:
        # the nested levels of the finest grid: every 2^(L - l)-th node of a piece is level l's
        k = np.arange(x.size) - np.repeat(np.concatenate(([0], np.cumsum((n_piece << L) + 1)[:-1])), (n_piece << L) + 1)
        traps = []
        for ell in range(L + 1):
            on = (k % (1 << (L - ell))) == 0
            traps.append(np.bincount(piece[on], weights=(v * w)[on], minlength=p) * (b - a) / (n_piece << ell))
        trap = traps[-1]
        e_last = traps[-1] - traps[-2]
        if L >= 2:
            e_prev = traps[-2] - traps[-3]
        n_piece = n_piece << L
        lev[:] = L
    else:
        trap = np.bincount(piece, weights=v * w, minlength=p) * (b - a) / n_piece
    act = np.arange(p)
    converged = False
    first = L > 0
    while True:
        if first:
            first = False        # the levels evaluated at once: to the acceptance below
        elif act.size == 0 or int(n_piece.sum() + n_piece[act].sum()) > n_max:
            break
        else:
            act = _double(f, act, a, b, n_piece, mid_p, trap, e_last, e_prev, lev, p)
        if np.any(lev < min_levels):
            act = np.nonzero(lev < min_levels)[0]
            continue
        Q = float(np.sum(trap + e_last / 3.0))
        budget = max(tol * abs(Q), atol)
        E, E_prev, est = piece_errors(e_last, e_prev)
        if E <= budget and E_prev <= budget:
            converged = True
            break
        order = np.argsort(-est, kind="stable")
        rest = est.sum() - np.cumsum(est[order])          # what the unrefined pieces hold
        k = int(np.searchsorted(-rest, -0.5 * budget)) + 1  # first count whose rest is <= budget/2
        # within the cap on intervals: the largest estimates first
        room = n_max - int(n_piece.sum())
        k = min(k, int(np.searchsorted(np.cumsum(n_piece[order]), room, side="right")))
        act = np.sort(order[:k])
    done = np.isfinite(e_last)
    e = np.where(done, e_last, 0.0)
    value = float(np.sum(trap + e / 3.0))
    err = piece_errors(e_last, e_prev)[0] if np.all(done) else float("inf")
    return QuadResult(value=np.array([value]), err=np.array([err]), trapezoid=np.array([float(trap.sum())]),
                      n=int(n_piece.sum()), converged=converged, levels=int(lev.max()), edges=edges,
                      n_piece=n_piece)


ROMBERG_RATIO = (3.0, 5.0)
"""A piece whose last two trapezoid differences shrink by a ratio in this range is in the asymptotic regime of the
Euler-Maclaurin expansion (4 for a smooth piece; 2^(1 + a) for an end singularity t^a, a in [0.58, 1.32]): its
error is estimated by the change of its Richardson value (:func:`piece_errors`; pins.md §6)."""


def piece_errors(e_last, e_prev):
    r"""The composite trapezoid's error estimates from each piece's last two differences (pins.md §6, §12.6).

    With e_p = T_2N,p - T_N,p and e'_p = T_N,p - T_N/2,p, a piece whose ratio r_p = e'_p/e_p lies in
    :data:`ROMBERG_RATIO` is in its asymptotic regime: its Richardson value R_2N = T_2N + e_p/3 is estimated to be
    off by at most the change from the level before,

    .. math:: \hat e_p = R_{2N,p} - R_{N,p} = (4 e_p - e'_p)/3,

    the error of R_N, which on a smooth piece is ~16x that of R_2N; for an end singularity t^a (r = 2^(1 + a))
    R_2N is off by e_p (1/(r - 1) - 1/3), at most half of |\hat e_p| over the range.  Every other piece keeps e_p
    (the error of T_N, ~4/3 that of T_2N, and far more than that of R_2N on a smooth piece), and the rule of two
    successive doublings: its e'_p must be within the tolerance too.  Honest wherever the integrand is resolved (at
    least 2 nodes per wavelength: tested on x^a, a in [0.05, 4], and on oscillations; below that both rules alias).
    Returns (E, E', est): E = |sum_p \hat e_p or e_p| (signed: the pieces' errors cancel as the trapezoid's do),
    E' = |sum e'_p| over the other pieces, and each piece's own estimate for refinement, |\hat e_p| or
    max(|e_p|, |e'_p|).

    Parameters
    ----------
    e_last : ndarray
        e_p = T_2N,p - T_N,p of each piece, [unit of the integral].
    e_prev : ndarray
        e'_p = T_N,p - T_N/2,p of each piece, [unit of the integral].

    Returns
    -------
    E : float
        The error estimate of the Richardson value, [unit of the integral].
    E_prev : float
        |sum e'_p| over the pieces that are not asymptotic.
    est : ndarray
        Each piece's own estimate for refinement.

    Examples
    --------
    A smooth piece (ratio 4.0, Richardson exact to its h^4 term) and a piece that is not yet asymptotic:

    >>> E, E_prev, est = piece_errors(np.array([1e-6, 1e-6]), np.array([4.1e-6, 1e-5]))
    >>> f"{E:.4g} {E_prev:.4g} {est[0]:.4g} {est[1]:.4g}"
    '9.667e-07 1e-05 3.333e-08 1e-05'

    References
    ----------
    .. [1] docs/spec/pins.md §6 (rule, error estimate), §12.6.
    .. [2] W. Romberg, Vereinfachte numerische Integration, Det Kongelige Norske Videnskabers Selskab
       Forhandlinger 28 (7), 1955 (Richardson extrapolation of the trapezoid rule).
    """
    e_prev_f = np.where(np.isfinite(e_prev), e_prev, 0.0)
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = e_prev / e_last
    asym = np.isfinite(ratio) & (ratio >= ROMBERG_RATIO[0]) & (ratio <= ROMBERG_RATIO[1])
    change = (4.0 * e_last - e_prev) / 3.0
    E = float(abs(np.sum(np.where(asym, change, e_last))))
    E_prev = float(abs(np.sum(np.where(asym, 0.0, e_prev_f))))
    est = np.where(asym, np.abs(change), np.maximum(np.abs(e_last), np.abs(e_prev_f)))
    return E, E_prev, est


def richardson_mean(w, w_half):
    r"""Richardson-corrected quadrature weights from a nested grid's trapezoid weights.

    .. math:: R_N = T_N + \frac{T_N - T_{N/2}}{3} = \sum_i \frac{4 w_i - w_{1/2,i}}{3}\,f_i

    The trapezoid weights at levels N (``w``) and N/2 (``w_half``): Simpson's rule on every piece.

    Parameters
    ----------
    w : ndarray
        Trapezoid weights at level N, [unit of x].
    w_half : ndarray
        Trapezoid weights at level N/2, 0 at the nodes it does not hold, [unit of x].

    Returns
    -------
    weights : ndarray
        The Richardson (Simpson) weights, [unit of x].

    Examples
    --------
    >>> x = np.linspace(0.0, 1.0, 5)
    >>> w = richardson_mean(np.array([0.125, 0.25, 0.25, 0.25, 0.125]), np.array([0.25, 0.0, 0.5, 0.0, 0.25]))
    >>> float(np.sum(w * x ** 3))
    0.25

    References
    ----------
    .. [1] docs/spec/pins.md §6, §8.
    """
    return (4.0 * w - w_half) / 3.0


def _double(f, act, a, b, n_piece, mid_p, trap, e_last, e_prev, lev, p):
    """One doubling of the pieces ``act`` of :func:`integrate_adaptive` (its arrays updated in place).

    The new (odd) nodes evaluated, the trapezoid sums, the last two differences and the levels.
    """
    cnt = n_piece[act]
    pc = np.repeat(act, cnt)
    st = np.concatenate(([0], np.cumsum(cnt)[:-1]))
    j = np.arange(int(cnt.sum())) - np.repeat(st, cnt)
    h_new = (b - a) / (2 * n_piece)
    xn = a[pc] + h_new[pc] * (2 * j + 1)
    vn = np.asarray(f(xn, mid_p[pc]), dtype=float).ravel()
    s = np.bincount(pc, weights=vn, minlength=p)[act]
    new = 0.5 * trap[act] + h_new[act] * s
    e_prev[act], e_last[act] = e_last[act], new - trap[act]
    trap[act] = new
    n_piece[act] *= 2
    lev[act] += 1
    return act


# ------------------------------------------------------------------ many integrals at once

@dataclass
class PiecewiseBatch:
    """The result of :func:`integrate_pieces`: one integral per owner, arrays over owners.

    value : Richardson values Q_2N + (Q_2N - Q_N)/3, shape (n_owner,).
    err : conservative error estimates |Q_2N - Q_N|.
    trapezoid : the finest plain trapezoid values Q_2N.
    n : intervals of each owner's finest level (int).
    converged : whether each owner met the tolerance on two successive doublings.
    levels : doublings done per owner.
    a, b, owner : the pieces (ends and owner), owner by owner.
    n_piece : intervals per piece at its owner's finest level.
    carried : the rows after the first of the integrand's values at the nodes of :meth:`grid`, in its
        order, shape (c, nodes); None when the integrand returns one row.
    nodes : :meth:`grid` when it is already known (else computed on demand).
    """

    value: np.ndarray
    err: np.ndarray
    trapezoid: np.ndarray
    n: np.ndarray
    converged: np.ndarray
    levels: np.ndarray
    a: np.ndarray
    b: np.ndarray
    owner: np.ndarray
    n_piece: np.ndarray
    carried: np.ndarray | None = None
    nodes: tuple | None = None

    def grid(self):
        """Nodes of every owner's finest level, piece by piece: (x, piece midpoint, piece index).

        Breakpoints appear once per adjacent piece (the one-sided limits of both sides).  These are the
        nodes the integrand was evaluated at, bit for bit.
        """
        if self.nodes is None:
            self.nodes = nodes_of_pieces(self.a, self.b, self.n_piece)
        return self.nodes


def nodes_of_pieces(a, b, n_piece):
    r"""All nodes of uniform grids on pieces [a_p, b_p] with n_p intervals, piece by piece.

    Like :func:`piece_nodes` for pieces that need not be contiguous (several integrals at once).
    Node k of piece p is ``a_p + (b_p - a_p) (k/n_p)`` (``b_p`` itself at k = n_p), the formula
    :func:`integrate_pieces` evaluates its integrand at.

    .. math:: x_{p,k} = a_p + (b_p - a_p)\,\frac{k}{n_p}, \quad k = 0, \dots, n_p

    Parameters
    ----------
    a, b : ndarray
        Piece ends, shape (p,), [unit of x].
    n_piece : ndarray of int
        Intervals per piece, shape (p,).

    Returns
    -------
    x, mid, piece : nodes, the midpoint of their piece, and their piece index.

    Examples
    --------
    >>> x, mid, piece = nodes_of_pieces(np.array([0.0, 0.0]), np.array([1.0, 2.0]), np.array([2, 1]))
    >>> x.tolist(), piece.tolist()
    ([0.0, 0.5, 1.0, 0.0, 2.0], [0, 0, 0, 1, 1])

    References
    ----------
    .. [1] docs/spec/pins.md §6.
    """
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    n_piece = np.asarray(n_piece, dtype=np.int64)
    counts = n_piece + 1
    piece = np.repeat(np.arange(n_piece.size), counts)
    start = np.cumsum(counts) - counts
    k = np.arange(int(counts.sum())) - start[piece]
    ap, bp, npc = a[piece], b[piece], n_piece[piece]
    x = np.where(k == npc, bp, ap + (bp - ap) * (k / npc))
    return x, 0.5 * (ap + bp), piece


def _new_nodes(a, length, n0, pieces, ells):
    """The new (odd) nodes of levels ``ells`` of pieces ``pieces``, level by level and piece by piece.

    Node j of level l (> 0) of piece p is ``a_p + (b_p - a_p) ((2 j + 1)/(n0_p 2^l))``: node k = (2 j + 1)
    2^(L - l) of the piece's grid at any level L >= l (:func:`nodes_of_pieces`), bit for bit, because the
    two quotients of integers are the same rational number, rounded once.

    Parameters
    ----------
    a, length, n0 : piece starts, lengths and level-0 intervals, shape (P,).
    pieces, ells : the (piece, level) pairs taking part, level-major, shape (K,).

    Returns
    -------
    x, piece, level, j : the nodes, their piece, level and index within the level's new nodes of the piece.
    """
    den = n0[pieces] * 2 ** ells                    # intervals of the level
    cnt = den // 2                                   # its new nodes
    pair = np.repeat(np.arange(cnt.size), cnt)
    j = np.arange(pair.size) - (np.cumsum(cnt) - cnt)[pair]
    pn = pieces[pair]
    x = a[pn] + length[pn] * ((2 * j + 1) / den[pair])
    return x, pn, ells[pair], j


def _level0_nodes(a, b, length, n0):
    """Every node of level 0, piece by piece (as :func:`nodes_of_pieces`): x, piece, index k, trapezoid weight."""
    counts = n0 + 1
    piece = np.repeat(np.arange(n0.size), counts)
    start = np.cumsum(counts) - counts
    k = np.arange(piece.size) - start[piece]
    npc = n0[piece]
    x = np.where(k == npc, b[piece], a[piece] + length[piece] * (k / npc))
    w = np.ones(x.size)
    w[start] = 0.5
    w[start + n0] = 0.5
    return x, piece, k, w


def _carried_on_grid(kept, n0, piece_level):
    """Gather the carried rows of every evaluated node onto the final grid (:meth:`PiecewiseBatch.grid`).

    ``kept``: per evaluation, (piece, k, level, rows): node k of its piece's grid of that level (n0 2^level
    intervals); ``piece_level``: the final level of each piece's owner.  On the final grid of level L the
    node is k 2^(L - level) when level <= L; nodes not on it (of finer grids) are dropped.  Every node of
    the final grid was evaluated once.  ``kept`` is emptied as its rows are placed, so that each evaluation's
    rows are freed once copied (the peak memory: about one copy of the rows, not three).
    """
    if not kept:
        return None
    counts = n0 * 2 ** piece_level + 1
    start = np.cumsum(counts) - counts
    out = np.empty((kept[0][3].shape[0], int(counts.sum())))
    while kept:
        pn, k, ell, rows = kept.pop(0)
        d = piece_level[pn] - ell                   # levels from the node's grid to the final one
        down = np.maximum(-d, 0)
        use = np.flatnonzero((k & ((1 << down) - 1)) == 0)       # on the final grid
        dest = start[pn[use]] + ((k[use] << np.maximum(d[use], 0)) >> down[use])
        if use.size < 4096:                          # a design alone: one call
            out[:, dest] = rows[:, use]
        else:                                        # row by row: contiguous gathers, twice as fast as 2-D ones
            for r in range(out.shape[0]):
                out[r][dest] = rows[r].take(use)
        del rows
    return out


def integrate_pieces(f, a, b, owner, n_owner: int | None = None, tol: float = 1e-6, atol: float = 1e-14,
                     n_start: int = 16, n_max: int = 2 ** 20, accept_levels: int = 2, min_levels: int = 2,
                     first_levels=None, n_initial=None, chunk: int = 2 ** 16,
                     max_nodes: int = 2 ** 22) -> PiecewiseBatch:
    r"""Many piecewise integrals at once (one per owner), each with uniform doubling (pins.md §6, §12.6).

    Every owner's pieces get the first level's node counts (``n_start`` intervals shared out in proportion
    to the piece lengths, at least 2 per piece), and then all of an owner's pieces are doubled together;
    an owner is accepted when ``E <= max(tol |Q|, atol)`` on ``accept_levels`` successive doublings (at
    least ``min_levels`` doublings, at most ``n_max`` intervals), with the Richardson value
    ``Q_2N + (Q_2N - Q_N)/3`` and the conservative error ``E = |Q_2N - Q_N|``.  An owner whose sum is not
    finite at a level (an integrand that overflows) stops there, not converged, with value and error NaN:
    a non-finite sum stays so at every finer level, so doubling on to ``n_max`` would only cost time.

    Why two entry points.  :func:`integrate_adaptive` integrates one function and doubles piece by piece
    (the contact level: a few costly integrands, pieces of very different difficulty).  This one integrates
    the cycles of many gears in one vectorised solve (the ideal level of a batch or a sweep, and a ≤ 1 ms
    design alone through the one-owner fast path, :func:`_one_owner`); its uniform doubling per owner keeps
    an owner's result independent of the owners solved with it, bit for bit, which per-piece refinement
    across a batch would not without the same bookkeeping.  Both use the same nodes
    (:func:`piece_nodes`, :func:`nodes_of_pieces`), one-sided piece ends and Richardson step.  How the work is
    organised, none of which changes a result beyond round-off:

    * the integrand is evaluated for all owners together (numpy over owners);
    * several levels are evaluated per round (``first_levels``, then a prediction from the observed
      rate of convergence), because an evaluation call costs far more than its nodes.  Each level is
      still checked in order, and an owner stops at the first level the rule accepts; the levels
      evaluated beyond it are discarded;
    * a node is placed as :func:`nodes_of_pieces` places it on the final grid (``a + (b - a)(k/n)``), so
      the integrand's values at the final grid are known without evaluating it again (``carried``).

    Each trapezoid sum is accumulated per piece and per level in node order (``np.bincount``), so an
    owner's result does not depend on the other owners integrated with it; a single owner runs its
    bookkeeping on Python scalars (the same operations, :func:`_one_owner`).

    .. math:: Q = T_{2N} + \frac{T_{2N} - T_N}{3}, \qquad E = |T_{2N} - T_N| \ \text{per integral}

    Parameters
    ----------
    f : callable ``f(x, mid, piece)`` -> array (n,) or (1 + c, n): the integrand at nodes ``x`` of the
        pieces ``piece`` whose midpoints are ``mid`` (decide set membership from ``mid``: one-sided
        ends).  Rows after the first are not integrated but carried to the final grid (``carried``):
        values the caller needs there, computed with the integrand.
    a, b : piece ends, shape (p,), a < b; the pieces of an owner are contiguous and ordered.
    owner : owner (integral) of each piece, non-decreasing, shape (p,).
    n_owner : number of owners (default: max(owner) + 1).
    tol : relative tolerance, > 0; atol : absolute floor of the tolerance [unit of the integral].
    n_start : intervals of an owner's first level; n_max : cap on an owner's intervals.
    accept_levels : successive doublings that must meet the tolerance; min_levels : least doublings done.
    first_levels : levels evaluated in the first round (scalar or per owner); speed only.
    n_initial : intervals per piece of the first level (overrides ``n_start``), shape (p,).
    chunk : largest number of nodes passed to f at once.
    max_nodes : largest number of new nodes evaluated in one round (memory bound).

    Returns
    -------
    PiecewiseBatch

    Examples
    --------
    Two integrals: exp on [0, 1] (= e - 1), and x^2 on [0, 0.5] + [0.5, 2] (= 8/3).

    >>> r = integrate_pieces(lambda x, m, p: np.where(p == 0, np.exp(x), x * x),
    ...                      [0.0, 0.0, 0.5], [1.0, 0.5, 2.0], [0, 1, 1], tol=1e-10)
    >>> bool(abs(r.value[0] - (np.e - 1)) < 1e-12 and abs(r.value[1] - 8 / 3) < 1e-12), r.converged.tolist()
    (True, [True, True])

    References
    ----------
    pins.md §6 and §12.6 (rule, error estimate, adaptivity).
    """
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    owner = np.asarray(owner, dtype=np.int64)
    n_owner = int(owner.max()) + 1 if n_owner is None else int(n_owner)
    length = b - a
    if n_initial is None:
        total = np.bincount(owner, length, minlength=n_owner)
        n0 = np.maximum(2, np.rint(n_start * length / total[owner])).astype(np.int64)
    else:
        n0 = np.asarray(n_initial, dtype=np.int64)
        if n0.shape != a.shape or np.any(n0 < 1):
            raise ValueError(f"n_initial needs {a.size} positive interval counts, one per piece")
    N0 = np.bincount(owner, n0, minlength=n_owner).astype(np.int64)
    # the last level: the first L >= 1 with N0 2^L * 2 > n_max (the doubling would exceed the cap)
    cap = np.maximum(1, np.floor(np.log2(np.maximum(n_max // np.maximum(N0, 1), 1))).astype(np.int64))

    def evaluate(x, mid, piece):
        """The integrand at the nodes, in chunks: (values to integrate, carried rows or None)."""
        if x.size <= chunk:
            v = np.asarray(f(x, mid, piece), dtype=float)
        else:                                        # filled chunk by chunk (no second copy of the rows)
            first = np.asarray(f(x[:chunk], mid[:chunk], piece[:chunk]), dtype=float)
            v = np.empty(first.shape[:-1] + (x.size,))
            v[..., :chunk] = first
            for s in range(chunk, x.size, chunk):
                v[..., s:s + chunk] = f(x[s:s + chunk], mid[s:s + chunk], piece[s:s + chunk])
        return (v[0], v[1:]) if v.ndim == 2 else (v, None)

    mid_p = 0.5 * (a + b)
    if n_owner == 1:
        return _one_owner(evaluate, a, b, length, mid_p, owner, n0, int(N0[0]), int(cap[0]), tol, atol,
                          accept_levels, min_levels, first_levels, max_nodes)
    x0, piece0, k0, w0 = _level0_nodes(a, b, length, n0)
    P = a.size
    pieces = np.arange(P)
    kept = []                                        # carried rows per evaluation: (piece, level, j, rows)
    T = None                                         # trapezoid per piece, at each owner's level
    Q = np.zeros(n_owner)
    level = np.zeros(n_owner, dtype=np.int64)        # levels done per owner
    streak = np.zeros(n_owner, dtype=np.int64)       # successive accepted doublings
    e_last = np.full(n_owner, np.inf)
    e_prev = np.full(n_owner, np.inf)
    done = np.zeros(n_owner, dtype=bool)
    out_value, out_err, out_trap = np.zeros(n_owner), np.zeros(n_owner), np.zeros(n_owner)
    out_conv = np.zeros(n_owner, dtype=bool)
    out_level = np.zeros(n_owner, dtype=np.int64)
    target = np.maximum(1, np.zeros(n_owner, dtype=np.int64) + (min_levels if first_levels is None else first_levels))
    while not np.all(done):
        act = ~done
        goal = np.where(act, np.minimum(np.maximum(target, level + 1), cap), level)
        # bound the nodes of the round: N0 (2^goal - 2^level) new nodes per owner
        while np.sum(np.where(act, N0 * (2.0 ** goal - 2.0 ** level), 0.0)) > max_nodes and np.any(goal > level + 1):
            goal = np.where(goal > level + 1, goal - 1, goal)
        lo, hi = int(level[act].min()) + 1, int(goal[act].max())
        # the new (odd) nodes of every level lo..hi of every piece taking part, level by level
        ells = np.arange(lo, hi + 1)
        take = act[owner] & (level[owner] < ells[:, None]) & (goal[owner] >= ells[:, None])     # (L, P)
        li, pi = np.nonzero(take)
        xn, pn, ln, jn = _new_nodes(a, length, n0, pieces[pi], ells[li])
        kn = 2 * jn + 1                              # node of the grid of its level
        if T is None:                                # the first round carries level 0
            xn, pn = np.concatenate((x0, xn)), np.concatenate((piece0, pn))
            ln, kn = np.concatenate((0 * piece0, ln)), np.concatenate((k0, kn))
        vn, rows = evaluate(xn, mid_p[pn], pn)
        if rows is not None:
            kept.append((pn, kn, ln, rows))
        if T is None:
            m0 = ln == 0
            T = np.bincount(piece0, vn[m0] * w0, minlength=P) * (length / n0)
            Q = np.bincount(owner, T, minlength=n_owner)
        # node sums per level and piece, in node order
        L = hi - lo + 1
        S = np.bincount(np.maximum(ln - lo + 1, 0) * P + pn, vn, minlength=(L + 1) * P).reshape(L + 1, P)
        ON = act & (level < ells[:, None]) & (goal >= ells[:, None])     # owner takes part in level ell
        Qs = np.empty((L, n_owner))
        ONp = ON[:, owner]
        hS = S[1:] * (length / (n0 * 2.0 ** ells[:, None]))
        for i in range(L):   # the doubling recursion, level by level (a piece stays put off its levels)
            T = np.where(ONp[i], 0.5 * T + hS[i], T)
            Qs[i] = np.bincount(owner, T, minlength=n_owner)
        Qprev = np.vstack([Q[None, :], Qs[:-1]])
        with np.errstate(invalid="ignore"):          # inf - inf of a non-finite sum (it stops below)
            E = np.abs(Qs - Qprev)
        OK = E <= np.maximum(tol * np.abs(Qs), atol)
        ST = np.empty((L, n_owner), dtype=np.int64)
        for i in range(L):
            streak = np.where(ON[i], (streak + 1) * OK[i], streak)
            ST[i] = streak
        # a non-finite sum stays non-finite at every finer level: the owner stops at once (value and error NaN)
        NONFIN = ON & ~np.isfinite(Qs)
        CONV = ON & (ells[:, None] >= min_levels) & (ST >= accept_levels) & ~NONFIN
        STOP = CONV | (ON & (ells[:, None] >= cap)) | NONFIN
        stopped = STOP.any(axis=0)
        cols = np.arange(n_owner)
        if np.any(stopped):
            first = np.argmax(STOP, axis=0)                      # an owner stops at its first accepted level
            Qf, Qp = Qs[first, cols], Qprev[first, cols]
            bad = NONFIN[first, cols]
            with np.errstate(invalid="ignore"):
                out_value = np.where(stopped, np.where(bad, np.nan, Qf + (Qf - Qp) / 3.0), out_value)
                out_err = np.where(stopped, np.where(bad, np.nan, E[first, cols]), out_err)
            out_trap = np.where(stopped, Qf, out_trap)
            out_conv = np.where(stopped, CONV[first, cols], out_conv)
            out_level = np.where(stopped, ells[first], out_level)
            done = done | stopped
        part = ON.any(axis=0) & ~stopped                         # owners that go on: at level goal now
        li = np.minimum(np.maximum(goal - lo, 0), L - 1)
        e_prev = np.where(part, np.where(goal - 1 > level, E[np.maximum(li - 1, 0), cols], e_last), e_prev)
        e_last = np.where(part, E[li, cols], e_last)
        Q = np.where(part, Qs[li, cols], Q)
        level = np.where(done, out_level, np.where(part, goal, level))
        if np.all(done):
            break
        # next round: predict the level that meets the rule from the observed rate (speed only)
        thr = np.maximum(tol * np.abs(Q), atol)
        with np.errstate(divide="ignore", invalid="ignore"):
            rate = np.minimum(np.maximum(np.where(e_prev > 0, e_last / e_prev, 1.0 / 16.0), 1.0 / 16.0), 0.9)
            more = np.ceil(np.log(thr / e_last) / np.log(rate))
        more = np.where(np.isfinite(more) & (e_last > thr), np.minimum(np.maximum(more, 1), 8), 0).astype(np.int64)
        target = np.maximum(level + more + np.maximum(accept_levels - streak - (more > 0), 0),
                            np.maximum(level + 1, min_levels))
    n_piece = n0 * 2 ** out_level[owner]
    vn = rows = None                                 # the last evaluation's rows: freed once placed on the grid
    return PiecewiseBatch(value=out_value, err=out_err, trapezoid=out_trap, n=N0 * 2 ** out_level,
                          converged=out_conv, levels=out_level, a=a, b=b, owner=owner, n_piece=n_piece,
                          carried=_carried_on_grid(kept, n0, out_level[owner]))


def _one_owner(evaluate, a, b, length, mid_p, owner, n0, N0: int, cap: int, tol, atol, accept_levels, min_levels,
               first_levels, max_nodes) -> PiecewiseBatch:
    """:func:`integrate_pieces` for a single owner: the same nodes, sums, acceptance and rounds, bit for bit.

    The first round evaluates levels 0..G at once as the grid of level G, node by node in grid order
    (:func:`nodes_of_pieces`); a node's level follows from its index k (level 0 where 2^G divides k, else
    G minus the power of 2 in k), and the nodes of a level and piece are summed in the same order as by
    level (ascending), so the sums are the same.  When the rule accepts a level of the first round, its
    grid is every 2^(G - L)-th node of this one: no scatter, and no second computation of the grid.  Later
    rounds evaluate the new nodes of their levels, as :func:`integrate_pieces` does.  The bookkeeping
    (levels, streak, the trapezoid recursion over the pieces and its sum over them, the acceptance test,
    the prediction of the next round) runs on Python floats and ints, which round exactly as numpy's
    float64 element operations do, and which cost far less than numpy calls on arrays of one element
    when a single design is computed.  Sums run in the order ``np.bincount`` uses (piece by piece from
    0.0), so the result equals the owner's result in a batch of many.
    """
    P = a.size
    pieces = np.arange(P)
    kept = []
    T: list[float] | None = None
    Q = 0.0
    level, streak = 0, 0
    e_last = e_prev = math.inf
    target = max(1, min_levels if first_levels is None else
                 first_levels if isinstance(first_levels, int) else int(np.max(first_levels)))
    first_round = None
    while True:
        goal = min(max(target, level + 1), cap)
        while N0 * (2.0 ** goal - 2.0 ** level) > max_nodes and goal > level + 1:
            goal -= 1
        lo, L = level + 1, goal - level
        if T is None:
            # levels 0..goal: the grid of level goal, in grid order
            npc = n0 * 2 ** goal
            counts = npc + 1
            pn = np.repeat(pieces, counts)
            start = np.cumsum(counts) - counts
            kn = np.arange(pn.size) - start[pn]
            xn = np.where(kn == npc[pn], b[pn], a[pn] + length[pn] * (kn / npc[pn]))
            coarse = (kn & ((1 << goal) - 1)) == 0                   # level 0: every 2^goal-th node
            ln = np.where(coarse, 0, goal - (np.frexp(kn & -kn)[1] - 1))
            mid = mid_p[pn]
            vn, rows = evaluate(xn, mid, pn)
            first_round = (xn, mid, pn, kn, goal, rows)
            w0 = np.where((kn == 0) | (kn == npc[pn]), 0.5, 1.0)[coarse]
            T = (np.bincount(pn[coarse], vn[coarse] * w0, minlength=P) * (length / n0)).tolist()
            Q = _sum_in_order(T)
        else:
            # the new (odd) nodes of levels lo..goal, level by level and piece by piece
            ells = np.repeat(np.arange(lo, goal + 1), P)
            xn, pn, ln, jn = _new_nodes(a, length, n0, np.tile(pieces, L), ells)
            kn = 2 * jn + 1
            vn, rows = evaluate(xn, mid_p[pn], pn)
            if rows is not None:
                kept.append((pn, kn, ln, rows))
        S = np.bincount(np.maximum(ln - lo + 1, 0) * P + pn, vn, minlength=(L + 1) * P).reshape(L + 1, P)
        hS = (S[1:] * (length / (n0 * 2.0 ** np.arange(lo, goal + 1)[:, None]))).tolist()
        stop = None
        for i in range(L):       # the doubling recursion and the acceptance, level by level
            T = [0.5 * t + s for t, s in zip(T, hS[i])]
            q = _sum_in_order(T)
            if not math.isfinite(q):   # stays non-finite at every finer level: stop at once (value and error NaN)
                stop = (math.nan, math.nan, q, False, lo + i)
                break
            e = abs(q - Q)
            streak = (streak + 1) if e <= max(tol * abs(q), atol) else 0
            conv = lo + i >= min_levels and streak >= accept_levels
            if conv or lo + i >= cap:
                stop = (q + (q - Q) / 3.0, e, q, conv, lo + i)
                break
            e_prev, e_last, Q = e_last, e, q
        if stop is not None:
            break
        level = goal
        # next round: predict the level that meets the rule from the observed rate (speed only)
        thr = max(tol * abs(Q), atol)
        rate = min(max(e_last / e_prev if e_prev > 0 else 1.0 / 16.0, 1.0 / 16.0), 0.9)
        more = 0
        if e_last > thr > 0.0:
            more = min(max(math.ceil(math.log(thr / e_last) / math.log(rate)), 1), 8)
        target = max(level + more + max(accept_levels - streak - (more > 0), 0), max(level + 1, min_levels))
    value, err, trap, conv, out_level = stop
    x1, mid1, p1, k1, g1, rows1 = first_round
    carried = nodes = None
    if out_level <= g1:          # accepted within the first round: its grid, every 2^(g1 - L)-th node
        on = slice(None) if out_level == g1 else (k1 & ((1 << (g1 - out_level)) - 1)) == 0
        nodes = (x1[on], mid1[on], p1[on])
        carried = None if rows1 is None else rows1[:, on]
    elif rows1 is not None:
        kept.insert(0, (p1, k1, np.full(p1.size, g1), rows1))
        carried = _carried_on_grid(kept, n0, np.full(P, out_level))
    return PiecewiseBatch(value=np.array([value]), err=np.array([err]), trapezoid=np.array([trap]),
                          n=np.array([N0 * 2 ** out_level]), converged=np.array([conv]),
                          levels=np.array([out_level]), a=a, b=b, owner=owner, n_piece=n0 * 2 ** out_level,
                          carried=carried, nodes=nodes)


def _sum_in_order(values) -> float:
    """Sum of floats from 0.0 in the given order.

    Sum of floats from 0.0 in the given order (as ``np.bincount`` accumulates; Python 3.12's ``sum`` would
    compensate).
    """
    total = 0.0
    for v in values:
        total += v
    return total
