"""The allowable radial load: the load at which sigma_max reaches [sigma_H] (spec zstk.md §5.4).

The paper's conclusion: the load capacity of the mechanism is judged at the inner contact of the
smallest roller on the load line, i.e. by sigma_max <= [sigma_H] (eqs. (1)-(2)).  Without clearance the
loads are proportional to Q (§5.1), so sigma_max ∝ sqrt(Q) and the allowable load is a closed form; with
clearance or preload it is the root of sigma_max(Q) = [sigma_H], found by a bracketed root finder in ln Q.

References
----------
The seed paper by Merko et al. (seed 003), cited in full in :mod:`gearcalc.zstk`; docs/spec/zstk.md.
"""
from __future__ import annotations

__all__ = ['AllowableLoad', 'allowable_load_closed_form', 'allowable_load_root', 'allowable_load',
           'allowable_load_sweeping']

from dataclasses import dataclass

import numpy as np

from ..roots import find_root
from .chain import close_chain, roller_angles  # noqa: F401 (the examples)
from .envelope import Placement, SweepGrid, critical_placement
from .stress import ROUNDOFF_RTOL, Materials, critical, evaluate

LOG_RANGE = 60.0
"""The bracket search gives up below Q_estimate·e^-60 (~1e-26): the preload alone then reaches [sigma_H]
and the allowable radial load is 0."""
SLOPE_STEP = 1e-4
"""Relative step in ln Q of the central difference that gives d ln sigma / d ln Q at the root (the error
estimate's slope)."""


@dataclass
class AllowableLoad:
    """Allowable radial loads of G configurations (arrays (G,)).

    load : Q_allow [N] (0 where the preload alone reaches [sigma_H]); err : its error estimate [N];
    slope : d ln sigma_max / d ln Q at Q_allow [-] (1/2 without clearance); preload_exceeds : the
    preload alone (Q -> 0) reaches [sigma_H].
    """

    load: np.ndarray
    err: np.ndarray
    slope: np.ndarray
    preload_exceeds: np.ndarray


def allowable_load_closed_form(load, sigma_max, allowable, sigma_err=0.0):
    r"""Allowable radial load without clearance, where every roller force is proportional to Q (spec §5.1).

    .. math:: Q_{allow} = Q \left(\frac{[\sigma_H]}{\sigma_{max}}\right)^2, \qquad
              \varepsilon_Q = 2 Q_{allow}\, \varepsilon_\sigma / \sigma_{max}

    (F ∝ Q and sigma ∝ sqrt(F); the placement of the maximum does not depend on Q, so this holds for
    the "cycle" and "envelope" maxima too).

    Parameters
    ----------
    load : array_like
        Q [N], at which sigma_max was computed.
    sigma_max, allowable : array_like
        sigma_max at Q and [sigma_H] [MPa].
    sigma_err : array_like
        Error estimate of sigma_max [MPa].

    Returns
    -------
    AllowableLoad

    Examples
    --------
    >>> r = allowable_load_closed_form(1e4, 748.935693220922, 4000.0)
    >>> round(float(r.load), 3), float(r.slope)
    (285253.463, 0.5)

    References
    ----------
    Merko et al. (see :mod:`gearcalc.zstk`), eqs. (1)-(3); docs/spec/zstk.md §5.1, §5.4.
    """
    load, sigma_max, allowable, sigma_err = np.broadcast_arrays(*(np.asarray(x, dtype=float) for x in
                                                                  (load, sigma_max, allowable, sigma_err)))
    q = load * (allowable / sigma_max) ** 2
    return AllowableLoad(q, 2.0 * q * sigma_err / sigma_max, np.full(q.shape, 0.5), np.zeros(q.shape, bool))


def allowable_load_root(sigma_of_load, load, sigma_max, allowable, sigma_rel_err=0.0, xtol=1e-13):
    r"""Allowable radial load by a bracketed root find of sigma_max(Q) = [sigma_H] in x = ln Q (spec §5.4).

    .. math:: h(x) = \ln \sigma_{max}(e^x) - \ln [\sigma_H] = 0, \qquad
              \varepsilon_Q = Q_{allow} \left(\frac{\varepsilon_\sigma/\sigma}{d\ln\sigma/d\ln Q} + \Delta x\right)

    The bracket starts at the zero-clearance estimate x_0 = ln(Q ([sigma_H]/sigma_max)²) ± ln 2 and is
    widened outward (doubling) until h changes sign; Chandrupatla's method then narrows it to ``xtol``.
    If h(x_0 - 60) > 0 the preload alone reaches [sigma_H]: Q_allow = 0.

    Parameters
    ----------
    sigma_of_load : callable
        Array of Q (G,) [N] -> sigma_max (G,) [MPa] of the G configurations (vectorised).
    load, sigma_max : array_like, shape (G,)
        A load Q [N] and sigma_max there [MPa] (the start of the bracket search).
    allowable : array_like, shape (G,)
        [sigma_H] [MPa].
    sigma_rel_err : array_like
        Relative error estimate of the sigma_max function (solver and sweeps) [-].
    xtol : float
        Tolerance on ln Q.

    Returns
    -------
    AllowableLoad

    Examples
    --------
    >>> r = allowable_load_root(lambda q: 3.0 * np.sqrt(q + 100.0), np.array([1.0]), np.array([30.3]),
    ...                         np.array([60.0]))          # sigma = 3 sqrt(Q + 100) = 60 at Q = 300
    >>> round(float(r.load[0]), 9)
    300.0

    References
    ----------
    Merko et al. (see :mod:`gearcalc.zstk`), eqs. (1)-(2); Chandrupatla T.R., Adv. Eng. Software 28 (1997)
    145-149 (:func:`gearcalc.roots.find_root`); docs/spec/zstk.md §5.4.
    """
    load, sigma_max, allowable, sigma_rel_err = np.broadcast_arrays(*(np.asarray(x, dtype=float) for x in
                                                                      (load, sigma_max, allowable, sigma_rel_err)))
    log_allow = np.log(allowable)

    def h(x):
        return np.log(sigma_of_load(np.exp(x))) - log_allow

    x0 = np.log(load) + 2.0 * (log_allow - np.log(sigma_max))
    lo, hi, width = x0 - np.log(2.0), x0 + np.log(2.0), np.full(x0.shape, np.log(2.0))
    h_lo, h_hi = h(lo), h(hi)
    gave_up = np.zeros(x0.shape, bool)
    for _ in range(200):
        need_lo, need_hi = (h_lo > 0) & ~gave_up, h_hi < 0
        if not (np.any(need_lo) or np.any(need_hi)):
            break
        lo = np.where(need_lo, np.maximum(lo - width, x0 - LOG_RANGE), lo)
        hi = np.where(need_hi, hi + width, hi)
        width = 2.0 * width
        h_lo, h_hi = np.where(need_lo, h(lo), h_lo), np.where(need_hi, h(hi), h_hi)
        gave_up |= (h_lo > 0) & (lo <= x0 - LOG_RANGE)
    ok = ~gave_up
    x = np.where(ok, lo, -np.inf)
    x_err = np.zeros(x0.shape)
    slope = np.full(x0.shape, np.nan)
    if np.any(ok):
        sub = np.flatnonzero(ok)

        def h_sub(xs):
            full = np.array(x0)  # evaluate the unresolved elements at a harmless point
            full[sub] = xs
            return h(full)[sub]

        res = find_root(h_sub, lo[sub], hi[sub], xtol=xtol)
        x[sub], x_err[sub] = res.root, res.err
        step = SLOPE_STEP
        hp, hm = h(np.where(ok, x + step, x0)), h(np.where(ok, x - step, x0))
        slope[sub] = ((hp - hm) / (2.0 * step))[sub]
    q = np.where(ok, np.exp(x), 0.0)
    with np.errstate(divide="ignore", invalid="ignore"):
        err = np.where(ok, q * (sigma_rel_err / slope + x_err), np.exp(x0 - LOG_RANGE))
    return AllowableLoad(q, err, slope, gave_up)


def allowable_load(chain, mats: Materials, theta, gamma, load, clearance, sigma_max, sigma_err, allowable,
                   symmetric=False, fixed_direction=False, closed_form=True, xtol=1e-13) -> AllowableLoad:
    r"""Allowable radial load of G placed configurations (stacked designs of one N, spec §5.4).

    .. math:: \sigma_{max}(Q_{allow}) = [\sigma_H]

    Without clearance (s = 0, and ``closed_form``) :func:`allowable_load_closed_form`; otherwise
    :func:`allowable_load_root` on the configurations as placed (roller angles theta, load direction
    gamma, the same load model).

    Parameters
    ----------
    chain, mats : Chain, Materials
        Floats, or arrays (G,) of one N.
    theta : ndarray, shape (G, N)
        Roller angles [rad].
    gamma, load, clearance, sigma_max, sigma_err, allowable : array_like, shape (G,)
        Load direction [rad], Q [N], s [mm], sigma_max at Q and its error estimate [MPa], [sigma_H] [MPa].
    symmetric : array_like of bool, shape (G,)
        Mirror-symmetric configurations (closed-form loads, spec §5.1).
    fixed_direction : bool
        The ``fixed-direction`` level.
    closed_form : bool
        Use the closed form where s = 0 (False: the root find everywhere, the tests' cross-check).
    xtol : float
        Tolerance on ln Q of the root find.

    Returns
    -------
    AllowableLoad

    Examples
    --------
    >>> ch = close_chain(100.0, 50.0, 6.0, 6.0, 8)
    >>> m = Materials.from_elastic(20.0, 2.1e5, 0.3, 2.1e5, 0.3, 2.1e5, 0.3)
    >>> th = roller_angles(np.zeros(1), 8, ch.limiting_ratio)
    >>> r = allowable_load(ch, m, th, np.zeros(1), np.array([1e4]), np.array([0.01]), np.array([709.01]),
    ...                    np.zeros(1), np.array([4000.0]), symmetric=np.array([True]))
    >>> bool(r.load[0] > 2.8e5), bool(r.err[0] < 1e-9 * r.load[0])
    (True, True)

    References
    ----------
    Merko et al. (see :mod:`gearcalc.zstk`), eqs. (1)-(2); docs/spec/zstk.md §5.1, §5.2, §5.4.
    """
    gamma, load, clearance, sigma_max, sigma_err, allowable = (np.atleast_1d(np.asarray(x, dtype=float)) for x in
                                                               (gamma, load, clearance, sigma_max, sigma_err,
                                                                allowable))
    size = load.shape[0]
    symmetric = np.broadcast_to(np.asarray(symmetric, dtype=bool), (size,))
    out = allowable_load_closed_form(load, sigma_max, allowable, sigma_err)
    roots = np.flatnonzero(~((clearance == 0.0) & closed_form) & (sigma_max > 0))
    if roots.size:
        theta = np.broadcast_to(np.asarray(theta, dtype=float), (size,) + np.shape(theta)[-1:])

        def pick(obj):
            import dataclasses

            if np.ndim(getattr(obj, dataclasses.fields(obj)[0].name)) == 0:
                return obj
            return type(obj)(*(np.asarray(getattr(obj, f.name))[roots] for f in dataclasses.fields(obj)))

        ch, ms = pick(chain), pick(mats)
        th, gm, cl, sy = theta[roots], gamma[roots], clearance[roots], symmetric[roots]

        def sigma_of_load(q):
            st = evaluate(ch, ms, th, gm, q, cl, symmetric=sy, fixed_direction=fixed_direction)
            return critical(st)[0]

        r = allowable_load_root(sigma_of_load, load[roots], sigma_max[roots], allowable[roots],
                                sigma_err[roots] / sigma_max[roots], xtol)
        for name in ("load", "err", "slope", "preload_exceeds"):
            getattr(out, name)[roots] = getattr(r, name)
    return out


def placement_value(placement: Placement):
    r"""The maximum that a :class:`Placement`'s sweeps found [MPa] (the direction sweep's, else the phase sweep's).

    .. math:: \sigma_{max} = \max_{\varphi_0,\ \gamma} \sigma_{max}(\varphi_0, \gamma)

    Parameters
    ----------
    placement : Placement
        The critical placement of a chain.

    Returns
    -------
    sigma_max : float
        The swept maximum, [MPa].

    Examples
    --------
    >>> ch = close_chain(100.0, 50.0, 6.0, 6.0, 8)
    >>> m = Materials.from_elastic(20.0, 2.1e5, 0.3, 2.1e5, 0.3, 2.1e5, 0.3)
    >>> round(float(placement_value(critical_placement(ch, m, 1e4, 0.0, phase=0.0, tol=1e-8, refine_rtol=1e-6))), 3)
    748.936

    References
    ----------
    .. [1] M. A. Merko, M. V. Mesnyankin, A. V. Kolotov, A. E. Mityaev, M. V. Savitskaya, A. M. Merko, S. A. Yurov,
       «Анализ нормальных напряжений на площадках контакта звеньев механизмов с ЗСТК при ведущем внутреннем кольце и
       вводе поправки по радиусу дорожки качения наружного кольца», Siberian Federal University, UDC 621.838.2 (seed
       file 003_2d1da402cb0b8488.txt; no journal or year given); docs/spec/zstk.md §4.3, §5.3, §8.
    """
    if placement.value is not None:
        return placement.value
    return placement.phase_sweep.value


def allowable_load_sweeping(chain, mats: Materials, load, clearance, allowable, placement: Placement, *, phase=None,
                            gamma=None, tol, refine_rtol, grid=SweepGrid(), fixed_direction=False,
                            maxiter=8) -> AllowableLoad:
    r"""Allowable radial load of a "cycle" and/or "envelope" design.

    The load at which the swept maximum reaches [sigma_H] (spec §5.4, §8).

    .. math:: \max_{\varphi_0, \gamma} \sigma_{max}(Q_{allow}; \varphi_0, \gamma) = [\sigma_H]

    Without clearance the closed form at the sweep's maximum (the critical placement does not depend on
    Q).  Otherwise a monotone fixed-point iteration: Q_{k+1} = the root at the critical placement p_k of
    Q_k (:func:`allowable_load_root`), then p_{k+1} = the critical placement at Q_{k+1}
    (:func:`~gearcalc.zstk.critical_placement`).  A fixed placement's maximum is <= the swept one, so
    Q_{k+1} >= Q_allow and the sweep at Q_{k+1} reaches [sigma_H]; the iteration stops when it exceeds it
    by no more than tol (usually the first check: the placement is unchanged).  The error estimate adds
    that excess and the sweep's error, divided by d ln sigma/d ln Q.

    Parameters
    ----------
    chain, mats : one closed chain and its materials (floats).
    load, clearance, allowable : float
        Q [N] at which ``placement`` was found, s [mm], [sigma_H] [MPa].
    placement : Placement
        The critical placement at Q (its ``err`` is the sweeps' error estimate [MPa]).
    phase, gamma : float or None
        The design's fixed phase / direction [rad], None for a swept one (as :func:`critical_placement`).
    tol, refine_rtol, grid, fixed_direction : as :func:`critical_placement`.
    maxiter : the iteration cap.

    Returns
    -------
    AllowableLoad (arrays of shape (1,)).

    Examples
    --------
    >>> ch = close_chain(100.0, 50.0, 6.0, 6.0, 8)
    >>> m = Materials.from_elastic(20.0, 2.1e5, 0.3, 2.1e5, 0.3, 2.1e5, 0.3)
    >>> pl = critical_placement(ch, m, 1e4, 0.0, phase=0.0, tol=1e-8, refine_rtol=1e-6)
    >>> r = allowable_load_sweeping(ch, m, 1e4, 0.0, 4000.0, pl, phase=0.0, tol=1e-8, refine_rtol=1e-6)
    >>> round(float(r.load[0]) / 1e3, 3)
    285.253

    References
    ----------
    Merko et al. (see :mod:`gearcalc.zstk`), eqs. (1)-(2); docs/spec/zstk.md §5.4, §8.
    """
    value = placement_value(placement)
    placement_err = max(placement.err, ROUNDOFF_RTOL * value)  # the floor of sigma_max_err_MPa
    if clearance == 0.0:
        return allowable_load_closed_form(np.array([load]), np.array([value]), np.array([allowable]),
                                          np.array([placement_err]))
    n, q_ratio = chain.n, chain.limiting_ratio
    pl, q_at, v_at = placement, float(load), float(value)
    for _ in range(maxiter):
        theta = roller_angles(pl.phase, n, q_ratio)

        def sigma_of_load(q, theta=theta, pl=pl):
            qs = np.atleast_1d(q)
            st = evaluate(chain, mats, np.broadcast_to(theta, (qs.size, n)), np.full(qs.size, pl.gamma), qs,
                          clearance, fixed_direction=fixed_direction)
            return critical(st)[0]

        r = allowable_load_root(sigma_of_load, np.array([q_at]), np.array([v_at]), np.array([allowable]),
                                np.array([max(pl.err / v_at, ROUNDOFF_RTOL)]))
        if r.preload_exceeds[0]:
            return r
        q_new = float(r.load[0])
        pl_new = critical_placement(chain, mats, q_new, clearance, phase, gamma, tol=tol, refine_rtol=refine_rtol,
                                    grid=grid, fixed_direction=fixed_direction)
        v_new = placement_value(pl_new)
        excess = max(v_new - allowable, 0.0) / allowable
        if excess <= tol:
            err = q_new * ((excess + max(pl_new.err / v_new, ROUNDOFF_RTOL)) / r.slope[0]) + float(r.err[0])
            return AllowableLoad(np.array([q_new]), np.array([err]), r.slope, r.preload_exceeds)
        pl, q_at, v_at = pl_new, q_new, v_new
    err = q_new * ((excess + max(pl_new.err / v_new, ROUNDOFF_RTOL)) / r.slope[0]) + float(r.err[0])
    return AllowableLoad(np.array([q_new]), np.array([err]), r.slope, r.preload_exceeds)
