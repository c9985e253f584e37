"""Vectorised bracketed root finding and bounded minimisation over numpy arrays.

The one place in gearcalc where scalar equations are solved iteratively (scipy is not a run-time
dependency).  Every function works element-wise on arrays of brackets, loops over iterations
only (never over elements), and returns an honest error bound with each result.

* :func:`find_root`: Chandrupatla's method (inverse quadratic interpolation safeguarded by
  bisection), a bracketing method as robust as bisection and as fast as Brent's.
* :func:`bisect`: plain bisection, for functions that are only piecewise continuous.
* :func:`minimize_golden`: golden-section search for a unimodal function on an interval.

References
----------
T. R. Chandrupatla, "A new hybrid quadratic/bisection algorithm for finding the zero of a
nonlinear function without using derivatives", Advances in Engineering Software 28 (1997) 145-149.
J. Kiefer, "Sequential minimax search for a maximum", Proc. AMS 4 (1953) 502-506.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

EPS = np.finfo(float).eps


class BracketError(ValueError):
    """f(a) and f(b) do not differ in sign for some elements (``mask`` marks them)."""

    def __init__(self, message: str, mask):
        super().__init__(message)
        self.mask = mask


@dataclass
class RootResult:
    """Roots with their error bounds.

    root : best estimate (the bracket end with the smaller |f|).
    err : width of the final bracket, which contains a sign change: |true root - root| <= err.
    iterations : iterations used (the maximum over elements).
    converged : per element, whether the tolerance was met.
    """

    root: np.ndarray
    err: np.ndarray
    iterations: int
    converged: np.ndarray


def _prepare(f, a, b):
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    fa, fb = np.asarray(f(a), dtype=float), np.asarray(f(b), dtype=float)
    a, b, fa, fb = (x.copy() for x in np.broadcast_arrays(a, b, fa, fb))
    bad = (np.sign(fa) * np.sign(fb) > 0) | ~np.isfinite(fa) | ~np.isfinite(fb)
    if np.any(bad):
        raise BracketError(f"{int(np.count_nonzero(bad))} bracket(s) without a sign change "
                           "or with a non-finite end", bad)
    return a, b, fa, fb


def find_root(f, a, b, xtol: float = 0.0, rtol: float = 4 * EPS, maxiter: int = 200) -> RootResult:
    r"""Roots of ``f`` on the brackets ``[a, b]`` (element-wise), by Chandrupatla's method.

    Iterates until every bracket is narrower than ``2 (rtol |x| + xtol)`` or ``f`` is exactly 0.

    Parameters
    ----------
    f : callable mapping an array of x to an array of f(x) of the same shape (vectorised).
    a, b : bracket ends [same unit as x]; f(a) and f(b) must differ in sign (or be 0).
    xtol : absolute tolerance on x [unit of x].
    rtol : relative tolerance on x [-]; values below 4 eps are raised to it.
    maxiter : iteration cap.

    Returns
    -------
    RootResult

    .. math:: f(x^*) = 0, \qquad |b_k - a_k| \le 2\,(\text{rtol}\,|x| + \text{xtol})

    Examples
    --------
    >>> r = find_root(lambda x: x**2 - 2.0, [0.0, 0.0], [2.0, 3.0])
    >>> bool(np.allclose(r.root, np.sqrt(2.0)))
    True

    References
    ----------
    .. [1] T. R. Chandrupatla, A new hybrid quadratic/bisection algorithm for finding the zero of a nonlinear
       function without using derivatives, Advances in Engineering Software 28(3):145-149, 1997; docs/spec/pins.md
       §5.5, docs/spec/zstk.md §5.1.
    """
    rtol = max(rtol, 4 * EPS)
    x1, x2, f1, f2 = _prepare(f, a, b)
    # Chandrupatla's state: x1 newest point, x2 the point across the sign change, x3 the discarded.
    x3, f3 = x2.copy(), f2.copy()
    t = np.full(x1.shape, 0.5)
    done = (f1 == 0) | (f2 == 0)
    it = 0
    while not np.all(done) and it < maxiter:
        it += 1
        xt = x1 + t * (x2 - x1)
        ft = np.asarray(f(xt), dtype=float)
        ft = np.broadcast_to(ft, x1.shape)
        act = ~done
        same = (np.sign(ft) == np.sign(f1)) & act
        cross = act & ~same
        # same sign as f1: x3 <- x1, x1 <- xt ; else x3 <- x2, x2 <- x1, x1 <- xt
        x3 = np.where(same, x1, np.where(cross, x2, x3))
        f3 = np.where(same, f1, np.where(cross, f2, f3))
        x2 = np.where(cross, x1, x2)
        f2 = np.where(cross, f1, f2)
        x1 = np.where(act, xt, x1)
        f1 = np.where(act, ft, f1)
        xm = np.where(np.abs(f1) < np.abs(f2), x1, x2)
        tol = rtol * np.abs(xm) + xtol  # stop when the bracket is narrower than 2 tol
        width = np.abs(x2 - x1)
        with np.errstate(divide="ignore", invalid="ignore"):
            tl = np.where(width > 0, tol / width, 1.0)
            done = done | (tl > 0.5) | (f1 == 0) | ~np.isfinite(ft)
            xi = (x1 - x2) / (x3 - x2)
            phi = (f1 - f2) / (f3 - f2)
            iqi = (phi * phi < xi) & ((1 - phi) ** 2 < 1 - xi)
            t_iqi = (f1 / (f2 - f1) * f3 / (f2 - f3)
                     + (x3 - x1) / (x2 - x1) * f1 / (f3 - f1) * f2 / (f3 - f2))
        t = np.where(iqi & np.isfinite(t_iqi), t_iqi, 0.5)
        tl_c = np.clip(np.nan_to_num(tl, nan=0.5), 0.0, 0.5)
        t = np.clip(t, tl_c, 1.0 - tl_c)
    root = np.where(np.abs(f1) <= np.abs(f2), x1, x2)
    err = np.where((f1 == 0) | (f2 == 0), 0.0, np.abs(x2 - x1))
    converged = err <= 2.0 * (rtol * np.abs(root) + xtol) + 0.0
    converged |= (f1 == 0) | (f2 == 0)
    return RootResult(root, err, it, converged)


def bisect(f, a, b, xtol: float = 0.0, rtol: float = 4 * EPS, maxiter: int = 200) -> RootResult:
    r"""Roots of ``f`` on ``[a, b]`` by bisection (element-wise); see :func:`find_root`.

    Robust for functions with jumps: it returns a sign-change location within ``err``.

    .. math:: f(a_k)\,f(b_k) \le 0, \qquad m = \tfrac12 (a_k + b_k), \qquad |b_k - a_k| \le 2\,(\text{rtol}\,|x| +
        \text{xtol})

    Parameters
    ----------
    f : callable
        Vectorised: an array of x to f(x) of the same shape.
    a, b : float or array_like
        Bracket ends, [unit of x]; f(a) and f(b) must differ in sign (or be 0).
    xtol : float, optional
        Absolute tolerance on x, [unit of x].
    rtol : float, optional
        Relative tolerance on x, [-].
    maxiter : int, optional
        Iteration cap.

    Returns
    -------
    result : RootResult
        The roots, their errors and whether each converged.

    Examples
    --------
    >>> r = bisect(lambda x: np.cos(x), 1.0, 2.0, xtol=1e-12)
    >>> abs(float(r.root) - np.pi / 2) < 1e-12
    True

    References
    ----------
    .. [1] R. L. Burden, J. D. Faires, Numerical Analysis, 9th ed., Brooks/Cole, 2011, §2.1 (the bisection
       method); docs/spec/pins.md §6.
    """
    rtol = max(rtol, 2 * EPS)
    lo, hi, flo, fhi = _prepare(f, a, b)
    it = 0
    while it < maxiter:
        width = np.abs(hi - lo)
        mid = 0.5 * (lo + hi)
        if np.all(width <= 2.0 * (rtol * np.abs(mid) + xtol)):
            break
        it += 1
        fm = np.broadcast_to(np.asarray(f(mid), dtype=float), lo.shape)
        left = np.sign(fm) == np.sign(flo)
        lo = np.where(left, mid, lo)
        flo = np.where(left, fm, flo)
        hi = np.where(left, hi, mid)
        fhi = np.where(left, fhi, fm)
    root = 0.5 * (lo + hi)
    err = 0.5 * np.abs(hi - lo)
    return RootResult(root, err, it, err <= rtol * np.abs(root) + xtol + 0.0)


@dataclass
class MinResult:
    """Minimisers with their error bounds.

    x : best point found; err : half the final bracket, but never below 3 sqrt(eps) |x|
    (a search on function values cannot place a flat minimum more finely); fun : f(x);
    on_bound : the minimiser lies at an end of the search interval.
    """

    x: np.ndarray
    err: np.ndarray
    fun: np.ndarray
    on_bound: np.ndarray
    iterations: int


INV_PHI = (np.sqrt(5.0) - 1.0) / 2.0


def minimize_golden(f, a, b, rtol: float = 1e-6, xtol: float = 0.0, maxiter: int = 300) -> MinResult:
    r"""Minimum of a unimodal ``f`` on ``[a, b]`` (element-wise) by golden-section search.

    .. math:: x_1 = b - \varphi^{-1}(b - a), \quad x_2 = a + \varphi^{-1}(b - a), \quad \varphi = \frac{1 + \sqrt5}{2},
        \qquad \text{err} = \max\!\left(\tfrac12 |b - a|,\ 3\sqrt{\varepsilon}\,|x|\right)

    Parameters
    ----------
    f : vectorised callable.
    a, b : interval ends, a < b.
    rtol, xtol : stop when half the bracket is <= rtol |x| + xtol.

    Returns
    -------
    MinResult, with err = max(half the final bracket, 3 sqrt(eps) |x|).

    Examples
    --------
    >>> r = minimize_golden(lambda x: (x - 3.0) ** 2, 0.0, 10.0, rtol=1e-10)
    >>> abs(float(r.x) - 3.0) <= float(r.err)
    True

    References
    ----------
    .. [1] J. Kiefer, Sequential minimax search for a maximum, Proceedings of the American Mathematical Society
       4(3):502-506, 1953; docs/spec/rows.md §6.
    """
    lo, hi = np.broadcast_arrays(np.asarray(a, dtype=float), np.asarray(b, dtype=float))
    lo, hi = lo.copy(), hi.copy()
    a0, b0 = lo.copy(), hi.copy()
    c = hi - INV_PHI * (hi - lo)
    d = lo + INV_PHI * (hi - lo)
    fc, fd = np.asarray(f(c), dtype=float), np.asarray(f(d), dtype=float)
    lo, hi, c, d, fc, fd = (x.copy() for x in np.broadcast_arrays(lo, hi, c, d, fc, fd))
    a0, b0 = lo.copy(), hi.copy()
    floor = 3.0 * np.sqrt(EPS)
    it = 0
    while it < maxiter:
        mid = 0.5 * (lo + hi)
        half = 0.5 * (hi - lo)
        if np.all(half <= np.maximum(rtol, floor) * np.abs(mid) + xtol):
            break
        it += 1
        left = fc < fd  # the minimum lies in [lo, d], else in [c, hi]
        hi = np.where(left, d, hi)
        lo = np.where(left, lo, c)
        x_new = np.where(left, hi - INV_PHI * (hi - lo), lo + INV_PHI * (hi - lo))
        f_new = np.asarray(f(x_new), dtype=float)
        c, fc, d, fd = (np.where(left, x_new, d), np.where(left, f_new, fd),
                        np.where(left, c, x_new), np.where(left, fc, f_new))
    # candidates: the two interior points and the ends
    xs = np.stack([c, d, a0, b0])
    fs = np.stack(np.broadcast_arrays(fc, fd, np.asarray(f(a0), dtype=float), np.asarray(f(b0), dtype=float)))
    k = np.argmin(fs, axis=0)
    x = np.take_along_axis(xs, k[None], axis=0)[0]
    fun = np.take_along_axis(fs, k[None], axis=0)[0]
    err = np.maximum(0.5 * (hi - lo), floor * np.abs(x))
    on_bound = (np.abs(x - a0) <= err) | (np.abs(x - b0) <= err) | (k >= 2)
    return MinResult(x, err, fun, on_bound, it)



@dataclass
class MaxBoundResult:
    """Maximisers with a bound on what each bracket can still hide.

    x : best point found; value : f(x); bound : value + bound >= the maximum of f over the bracket when f is
    concave there (:func:`maximize_bracketed`); converged : bound <= the target (else the bracket reached the
    round-off of x first, or the iteration cap); iterations : the most any element used; evaluations : points
    of f evaluated, summed over the elements.
    """

    x: np.ndarray
    value: np.ndarray
    bound: np.ndarray
    converged: np.ndarray
    iterations: int
    evaluations: int



SECTIONS = 8
"""New points per bracket and iteration of :func:`maximize_bracketed` (one call of f)."""


def _drop_bound(xl, xb, xr, fl, fb, fr):
    """The tangent bound of a concave f over [xl, xr] above its best sample fb at xb (xl < xb < xr)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        b = np.maximum((fb - fl) * (xr - xb) / (xb - xl), (fb - fr) * (xb - xl) / (xr - xb))
    return np.where((xb > xl) & (xr > xb) & np.isfinite(b), np.maximum(b, 0.0), np.inf)


def maximize_bracketed(f, a, b, fa, fb, target, maxiter: int = 60, sections: int = SECTIONS) -> MaxBoundResult:
    r"""Maxima of ``f`` on the brackets ``[a, b]`` (element-wise), each refined to a bound.

    Maxima of ``f`` on the brackets ``[a, b]`` (element-wise), each refined only until the bound on what its bracket
    can still hide is <= ``target``.

    Each iteration evaluates ``sections`` new points per bracket in one call of f, sorts them with the bracket
    ends and the best point so far, and keeps the neighbours x_{i-1} < x_i < x_{i+1} of the best sample x_i as
    the next bracket.  The points: the cell centres of ``sections`` equal cells of the bracket, or, once the
    parabola through the bracket and its best point is concave with curvature K, the cell centres of a box
    around its vertex with cells of width sqrt(target/K)/2 (so a smooth maximum is resolved in a few calls; a box
    that misses it leaves a bracket that still holds it, and the next step samples that bracket: the bracket
    shrinks at least 4-fold every two calls).

    The bound: for f concave on [x_{i-1}, x_{i+1}], f'(x_i) lies between the secant slopes on either side, so
    the maximum is at most

    .. math:: f_i + \max\Big((f_i - f_{i-1})\frac{x_{i+1} - x_i}{x_i - x_{i-1}},\
              (f_i - f_{i+1})\frac{x_i - x_{i-1}}{x_{i+1} - x_i}\Big)

    (with equal spacing, the larger drop to a neighbour).  The best sample is a new point or the previous best,
    never a bracket end: where an end is the largest sample (f flat, or its maximum at that end) the bound above
    still holds for f concave (0 for a constant f), and the bracket shrinks towards that end.  It holds at a
    kink where f peaks (f is concave across it); a convex kink (f the larger of two smooth pieces) is never a
    maximum and leaves the bracket as it shrinks.  An element whose bracket reaches the round-off of x
    (16 eps (|a| + |b| + b - a)) before its bound meets the target stops there, ``converged`` False, with the
    bound it reached.

    Parameters
    ----------
    f : callable ``f(x, idx)``: x of shape (len(idx), k), the points of the elements ``idx`` (1-D integer array)
        still refined; returns f there, the shape of x.
    a, b : bracket ends (1-D, a < b); fa, fb : f there.
    target : the bound wanted [unit of f], scalar or per element.
    maxiter : iteration cap.
    sections : new points per iteration.

    Returns
    -------
    MaxBoundResult

    Examples
    --------
    >>> r = maximize_bracketed(lambda x, i: -(x - 0.3) ** 2, np.array([0.0]), np.array([1.0]),
    ...                        np.array([-0.09]), np.array([-0.49]), 1e-12)
    >>> bool(r.converged[0]), bool(r.value[0] <= 0.0 <= r.value[0] + r.bound[0] <= 1e-12)
    (True, True)

    References
    ----------
    .. [1] docs/spec/zstk.md §8, §11.8 (the joint maximum over phase and direction and its bound).
    """
    lo, hi = np.asarray(a, dtype=float).copy(), np.asarray(b, dtype=float).copy()
    flo, fhi = np.asarray(fa, dtype=float).copy(), np.asarray(fb, dtype=float).copy()
    target = np.broadcast_to(np.asarray(target, dtype=float), lo.shape)
    scale = np.abs(lo) + np.abs(hi) + (hi - lo)  # the round-off of x: 16 eps of this (also about x = 0)
    k = int(sections)
    cells = (np.arange(k) + 0.5) / k
    x, value = 0.5 * (lo + hi), np.maximum(flo, fhi)  # the first iteration: no best interior point yet
    first, shrunk = np.ones(lo.shape, bool), np.ones(lo.shape, bool)
    bound = np.full(lo.shape, np.inf)
    act = np.arange(lo.size)
    evaluations, it = 0, 0
    while act.size and it < maxiter:
        it += 1
        lft, h, xb = lo[act], hi[act], x[act]
        fl, fh, fbest = flo[act], fhi[act], value[act]
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            s_l, s_r = (fbest - fl) / (xb - lft), (fh - fbest) / (h - xb)
            curv = 2.0 * (s_l - s_r) / (h - lft)  # -f'' of the parabola through (lft, xb, h)
            vertex = xb - 0.5 * ((xb - lft) ** 2 * (fbest - fh) - (h - xb) ** 2 * (fbest - fl)) / (
                (xb - lft) * (fbest - fh) + (h - xb) * (fbest - fl))
            width = 0.5 * k * np.sqrt(target[act] / curv)  # two samples tied about a maximum: bound K w^2 <= target/4
        zoom = ~first[act] & shrunk[act] & (curv > 0) & np.isfinite(vertex) & (width < 0.5 * (h - lft))
        zl = np.clip(vertex - 0.5 * width, lft, h - width)
        zl = np.where(zoom, zl, lft)
        zw = np.where(zoom, width, h - lft)
        pts = zl[:, None] + zw[:, None] * cells[None, :]
        vals = np.asarray(f(pts, act), dtype=float)
        evaluations += pts.size
        fresh = first[act]  # no best point yet: its slot repeats the left end
        allx = np.concatenate([lft[:, None], pts, np.where(fresh, lft, xb)[:, None], h[:, None]], axis=1)
        allf = np.concatenate([fl[:, None], vals, np.where(fresh, fl, fbest)[:, None], fh[:, None]], axis=1)
        order = np.argsort(allx, axis=1, kind="stable")
        allx, allf = np.take_along_axis(allx, order, 1), np.take_along_axis(allf, order, 1)
        # the best point: a new sample or the previous best, never a bracket end nor the first iteration's
        # placeholder (a copy of the left end: taken as the best where that end is the largest sample, e.g. a flat
        # f, its left neighbour would be itself and the bound inf)
        cand = np.concatenate([np.full((act.size, 1), -np.inf), vals,
                               np.where(fresh, -np.inf, fbest)[:, None], np.full((act.size, 1), -np.inf)], axis=1)
        i = np.argmax(np.take_along_axis(cand, order, 1), axis=1)
        rows = np.arange(act.size)
        xl, xi, xr = allx[rows, i - 1], allx[rows, i], allx[rows, i + 1]
        fl2, fi, fr2 = allf[rows, i - 1], allf[rows, i], allf[rows, i + 1]
        x[act], value[act], first[act] = xi, fi, False
        bound[act] = _drop_bound(xl, xi, xr, fl2, fi, fr2)
        shrunk[act] = (xr - xl) <= 0.25 * (h - lft)  # else (a box that missed) the next step samples the bracket
        lo[act], hi[act], flo[act], fhi[act] = xl, xr, fl2, fr2
        stalled = (xr - xl) <= 16 * EPS * scale[act]
        act = act[~((bound[act] <= target[act]) | stalled)]
    return MaxBoundResult(x, value, bound, bound <= target, it, evaluations)
