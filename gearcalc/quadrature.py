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
* doubling stops when ``E <= max(tol |Q|, atol)`` on two successive doublings, or at ``n_max``.

Boundary layers (a feature of width ``w`` at a breakpoint) are resolved by geometric grading,
:func:`geometric_breakpoints`, which adds breakpoints at ``x0 + L q^m``.  Breakpoints that are not
known in closed form (the sign changes of a contact penetration at a compliant contact level) are
located by :func:`sign_change_breakpoints` with the shared bracketed root finder.

Everything is vectorised: the integrand receives arrays of nodes (in chunks) and may return
several components at once, each accepted on its own relative tolerance.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .roots import bisect


@dataclass
class QuadResult:
    """The result of :func:`integrate_piecewise`.

    value : Richardson value(s), shape (m,) for m components [unit of f x unit of x].
    err : conservative error estimate(s) |Q_2N - Q_N|, shape (m,).
    trapezoid : the finest plain trapezoid value(s) Q_2N, shape (m,).
    n : total number of intervals of the finest level.
    converged : whether the tolerance was met on two successive doublings.
    levels : number of doublings done.
    edges : piece ends, shape (p + 1,).
    n_piece : intervals per piece at the finest level, shape (p,).
    """

    value: np.ndarray
    err: np.ndarray
    trapezoid: np.ndarray
    n: int
    converged: bool
    levels: int
    edges: np.ndarray
    n_piece: np.ndarray

    def grid(self):
        """Nodes of the finest level: (x, piece midpoint, piece index), piece by piece.

        Breakpoints appear once per adjacent piece (the one-sided limits of both sides).

        Returns
        -------
        x, mid, piece : arrays of the same length (sum of n_piece + 1 over pieces).
        """
        return piece_nodes(self.edges, self.n_piece)


def piece_nodes(edges, n_piece):
    """All nodes of a piecewise uniform grid, piece by piece (ends included on every piece).

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
    """Breakpoints grading a piece geometrically toward its end ``x0``.

    Returns ``x0 + (x1 - x0) ratio^m`` for m = 1 ... M, M the first with a distance below
    ``width / 4`` (so a boundary layer of that width is covered by several pieces); empty when
    ``width`` is not smaller than the piece.  ``x1`` may lie on either side of ``x0``.

    Parameters
    ----------
    x0 : the end to grade toward [unit of x].
    x1 : the other end of the piece [unit of x].
    width : width of the boundary layer at x0 [unit of x], > 0.
    ratio : geometric ratio, 0 < ratio < 1.

    Examples
    --------
    >>> geometric_breakpoints(0.0, 1.0, 0.1).tolist()
    [0.5, 0.25, 0.125, 0.0625, 0.03125, 0.015625]
    """
    span = x1 - x0
    if width <= 0 or not np.isfinite(width) or abs(span) <= width:
        return np.empty(0)
    m = int(np.ceil(np.log(4.0 * abs(span) / width) / np.log(1.0 / ratio)))
    m = min(m, 200)
    return x0 + span * ratio ** np.arange(1, m + 1)


def sign_change_breakpoints(g, a: float, b: float, n_scan: int, xtol: float) -> np.ndarray:
    """Locate every sign change of the components of ``g`` on [a, b] (breakpoints not known in closed form).

    ``g(x)`` maps an array of x (shape (n,)) to an array (c, n) of c components (penetrations,
    tangential speeds).  Each component is scanned on ``n_scan`` uniform intervals, and each
    sign change between neighbours is refined by bisection to ``xtol``.  Changes closer together
    than the scan step can be missed: choose n_scan accordingly (the caller's responsibility).

    Returns
    -------
    Sorted array of the located breakpoints (inside (a, b)).

    Examples
    --------
    >>> sign_change_breakpoints(lambda x: np.sin(x)[None], 0.5, 7.0, 64, 1e-13).round(10).tolist()
    [3.1415926536, 6.2831853072]
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


def _evaluate(f, x, mid, m_expected, chunk):
    out = []
    for s in range(0, x.size, chunk):
        v = np.asarray(f(x[s:s + chunk], mid[s:s + chunk]), dtype=float)
        out.append(np.atleast_2d(v) if v.ndim <= 1 else v)
    vals = np.concatenate(out, axis=1) if out else np.zeros((m_expected or 1, 0))
    return vals


def integrate_piecewise(f, breakpoints, tol: float = 1e-6, atol: float = 1e-14, n_start: int = 16,
                        n_max: int = 2 ** 20, accept_levels: int = 2, chunk: int = 2 ** 15,
                        min_levels: int = 2, n_initial=None) -> QuadResult:
    """Integrate ``f`` over [min(breakpoints), max(breakpoints)], smooth between the breakpoints.

    Composite trapezoid on every piece, node doubling, Richardson value and conservative error
    (module docstring).  The first level has ``n_start`` intervals over the whole range, shared
    out in proportion to the piece lengths with at least 2 per piece.

    Parameters
    ----------
    f : callable ``f(x, mid)`` -> array (n,) or (m, n): the integrand at nodes ``x`` of pieces
        whose midpoints are ``mid`` (decide set membership from ``mid``, never from ``x``, so that
        piece ends are one-sided limits).
    breakpoints : the range ends and every point where f may jump or kink [unit of x].
    tol : relative tolerance on each component, > 0.
    atol : absolute floor of the tolerance [unit of the integral].
    n_start : intervals of the first level.
    n_max : cap on the total number of intervals.
    accept_levels : successive doublings that must meet the tolerance.
    chunk : largest number of nodes passed to f at once (memory bound).
    min_levels : least number of doublings done.
    n_initial : intervals per piece of the first level (overrides ``n_start``), e.g. 10 x the
        ``n_piece`` of an earlier run on the same breakpoints for a uniformly 10x finer check.

    Returns
    -------
    QuadResult

    Examples
    --------
    A jump at x = 1 and a kink at x = 2: exact with the breakpoints given.

    >>> g = lambda x, mid: np.where(mid < 1.0, 0.0, 1.0) + np.abs(x - 2.0)
    >>> r = integrate_piecewise(g, [0.0, 1.0, 2.0, 3.0], tol=1e-10)
    >>> float(abs(r.value[0] - 4.5)) < 1e-12, bool(r.converged)
    (True, True)

    References
    ----------
    pins.md §6 and §12.6 (rule, error estimate, adaptivity).
    """
    edges = np.unique(np.asarray(breakpoints, dtype=float))
    if edges.size < 2:
        raise ValueError("integrate_piecewise needs at least two distinct breakpoints")
    length = edges[1:] - edges[:-1]
    keep = length > 0
    a, b = edges[:-1][keep], edges[1:][keep]
    edges = np.concatenate((a, b[-1:]))
    total = b[-1] - a[0]
    if n_initial is None:
        n0 = np.maximum(2, np.rint(n_start * (b - a) / total)).astype(np.int64)
    else:
        n0 = np.asarray(n_initial, dtype=np.int64)
        if n0.shape != a.shape or np.any(n0 < 1):
            raise ValueError(f"n_initial needs {a.size} positive interval counts, one per piece")
    mid_p = 0.5 * (a + b)

    # level 0: every node of every piece
    x, mid, piece = piece_nodes(edges, n0)
    vals = _evaluate(f, x, mid, None, chunk)
    m = vals.shape[0]
    h = (b - a) / n0
    w = np.ones(x.size)
    counts = n0 + 1
    start = np.concatenate(([0], np.cumsum(counts)[:-1]))
    w[start] = 0.5
    w[start + n0] = 0.5
    sums = np.zeros((m, a.size))
    np.add.at(sums.T, piece, (vals * w).T)
    trap_p = sums * h                       # (m, p) trapezoid per piece
    q_old = trap_p.sum(axis=1)
    n_piece = n0.copy()
    errs = []
    converged = False
    level = 0
    q_new = q_old
    while True:
        if int(n_piece.sum()) * 2 > n_max and level >= min_levels:
            break
        level += 1
        h_new = (b - a) / (2 * n_piece)
        # new nodes: odd positions of the doubled grid, piece by piece
        cnt = n_piece
        pc = np.repeat(np.arange(a.size), cnt)
        st = np.concatenate(([0], np.cumsum(cnt)[:-1]))
        j = np.arange(int(cnt.sum())) - np.repeat(st, cnt)
        xn = a[pc] + h_new[pc] * (2 * j + 1)
        v = _evaluate(f, xn, mid_p[pc], m, chunk)
        s = np.zeros((m, a.size))
        np.add.at(s.T, pc, v.T)
        trap_p = 0.5 * trap_p + h_new * s
        n_piece = 2 * n_piece
        q_new = trap_p.sum(axis=1)
        e = np.abs(q_new - q_old)
        errs.append(bool(np.all(e <= np.maximum(tol * np.abs(q_new), atol))))
        if level >= min_levels and len(errs) >= accept_levels and all(errs[-accept_levels:]):
            converged = True
            q_old_final = q_old
            break
        q_old_final = q_old
        q_old = q_new
        if int(n_piece.sum()) * 2 > n_max:
            break
    value = q_new + (q_new - q_old_final) / 3.0
    err = np.abs(q_new - q_old_final)
    return QuadResult(value=value, err=err, trapezoid=q_new, n=int(n_piece.sum()), converged=converged,
                      levels=level, edges=edges, n_piece=n_piece)
