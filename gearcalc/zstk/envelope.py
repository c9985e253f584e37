"""Maxima over the chain phase ("cycle") and the load direction ("envelope") (spec zstk.md §8).

References
----------
The seed paper by Merko et al. (seed 003), cited in full in :mod:`gearcalc.zstk`; docs/spec/zstk.md.
"""
from __future__ import annotations

__all__ = ['SweepResult', 'maximise_periodic', 'SweepGrid', 'sweep_work', 'Placement', 'ROLLER_FIELDS', 'sigma_max_at',
           'direction_maxima', 'critical_placement', 'evaluate_placement', 'roller_envelope']

import math
from dataclasses import dataclass

import numpy as np

from ..roots import minimize_golden
from .chain import Chain, close_chain, roller_angles, step_chain  # noqa: F401 (close_chain: the examples)
from .stress import Materials, critical, evaluate



# ----------------------------------------------------------------------------- §8 sweeps
@dataclass
class SweepResult:
    """Maximum of a periodic function found by grid + golden refinement + grid doubling.

    x : argmax [rad]; value : the maximum; err : error estimate of value; samples : the grid
    size M of the final level; step : the grid step [rad]; capped : the M cap was reached.
    """

    x: float
    value: float
    err: float
    samples: int
    step: float
    capped: bool = False


def _refine(fun, xs, ys, period, start, rtol, top=8):
    """Golden-section refinement of the local maxima of a periodic grid (vectorised)."""
    m = len(xs)
    left, right = np.roll(ys, 1), np.roll(ys, -1)
    idx = np.flatnonzero((ys >= left) & (ys >= right))
    if idx.size == 0:
        idx = np.array([int(np.argmax(ys))])
    idx = idx[np.argsort(-ys[idx])][:top]
    step = period / m
    res = minimize_golden(lambda x: -fun(x), xs[idx] - step, xs[idx] + step, rtol=rtol,
                          xtol=rtol * period)
    vals = -res.fun
    k = int(np.argmax(vals))
    x_best, v_best = float(res.x[k]), float(vals[k])
    # refinement error: how much the function moves within the golden bracket
    xe = float(res.err[k])
    around = fun(np.array([x_best - xe, x_best + xe]))
    err_ref = float(np.max(np.abs(around - v_best)))
    g = int(np.argmax(ys))
    if ys[g] > v_best:
        x_best, v_best, err_ref = float(xs[g]), float(ys[g]), 0.0
    # report the argmax in [start - period/2, start + period/2): a maximum at the start of the period
    # found slightly below it stays there instead of jumping to the end of the period
    x_best = start + float(np.mod(x_best - start + 0.5 * period, period)) - 0.5 * period
    return x_best, v_best, err_ref


def maximise_periodic(fun, start, period, samples, tol, cap=2 ** 16, refine_rtol=None):
    """Maximum of a vectorised periodic function over one period (spec §8, sweeps).

    .. math:: \\max_{x \\in [x_0, x_0 + T)} f(x), \\quad \\text{error} = |v_M - v_{M/2}| + \\text{refinement error} \\le
              \\text{tol} \\cdot |v_M|

    A uniform grid of M points (including ``start`` and ``start + period/2``), golden-section
    refinement of each local maximum within its two neighbouring intervals, then M doubled; the
    error estimate is the change of the refined maximum plus the refinement error, repeated
    until it is <= tol·max (M capped at ``cap``).

    Parameters
    ----------
    fun : callable, array of x [rad] -> array of values.
    start, period : the interval [start, start + period) [rad].
    samples : the initial M (even).
    tol : relative accuracy target.
    cap : the largest M.
    refine_rtol : golden-section tolerance on x (default 0.01·tol).

    Returns
    -------
    SweepResult

    Examples
    --------
    >>> r = maximise_periodic(lambda x: np.cos(x - 1.0), 0.0, 2 * np.pi, 16, 1e-9)
    >>> abs(r.x - 1.0) < 1e-4 and abs(r.value - 1.0) <= 1e-9
    True

    References
    ----------
    docs/spec/zstk.md §8 (sweeps, steps 2-4).
    """
    # maxima are smooth (quadratic) in x, so an x tolerance of 0.01 sqrt(tol) gives sigma to ~1e-4 tol;
    # the refinement error is measured, not assumed, and the tolerance is tightened if it dominates
    refine_rtol = 0.01 * math.sqrt(tol) if refine_rtol is None else refine_rtol
    m = int(samples)
    prev = None
    while True:
        xs = start + period * np.arange(m) / m
        ys = np.asarray(fun(xs), dtype=float)
        x, v, err_ref = _refine(fun, xs, ys, period, start, refine_rtol)
        if prev is not None:
            err = abs(v - prev) + err_ref
            if err <= tol * abs(v) or 2 * m > cap:
                return SweepResult(x, v, err, m, period / m, capped=err > tol * abs(v))
        if err_ref > 0.25 * tol * abs(v):
            refine_rtol *= 1e-3
        prev = v
        m *= 2



# ----------------------------------------------------------------------------- §8 "cycle" and "envelope"
ROLLER_FIELDS = ("theta", "radius", "beta", "psi", "force_inner", "force_outer", "rho_inner", "rho_outer",
                 "sigma_inner", "sigma_outer")
"""The per-roller quantities of a :class:`~gearcalc.zstk.stress.State` that :func:`roller_envelope` gives."""


@dataclass(frozen=True)
class SweepGrid:
    """Grid settings of the phase and direction sweeps (spec §8).

    phase : points per roller pitch; direction : points per turn; cap : the largest grid; chunk :
    roller-configurations evaluated at once (bounds the memory); refine_rows_max_n : above this N the
    per-roller envelope rows are grid maxima (their refinement is O(N²)); factor : grid multiplier
    (8 at the reference level).
    """

    phase: int = 64
    direction: int = 720
    cap: int = 2 ** 16
    chunk: int = 1_000_000
    refine_rows_max_n: int = 200
    factor: int = 1


def sweep_work(n, cycle, envelope, grid=SweepGrid()):
    """Roller-configurations of the first grids of a design's sweeps (spec §8): N x phases x directions
    (the cost budget's measure).

    Examples
    --------
    >>> sweep_work(8, True, False), sweep_work(8, False, True), sweep_work(8, True, True)
    (512, 5760, 92160)
    """
    gf = grid.factor
    if cycle and envelope:
        return n * grid.phase * gf * min(grid.direction, max(grid.direction // 4, 16 * n)) * gf
    return n * (grid.phase * gf if cycle else 1) * (grid.direction * gf if envelope else 1)


@dataclass
class Placement:
    """The critical placement of a chain: phase phi_0 [rad], load direction gamma [rad], the sweeps' error
    estimate err [MPa] and their results (None for a quantity not swept); value : the direction sweep's
    maximum [MPa] (None without it)."""

    phase: float
    gamma: float
    err: float
    phase_sweep: SweepResult | None = None
    direction_sweep: SweepResult | None = None
    value: float | None = None


def sigma_max_at(chain: Chain, mats: Materials, phase, gamma, load, clearance, fixed_direction=False,
                 chunk=1_000_000):
    r"""The largest contact stress of the chain at each (phase, direction) configuration.

    .. math:: \sigma_{max}(\varphi_0, \gamma) = \max_i \max(\sigma_{iB}, \sigma_{iH}),
              \quad \sigma = \sqrt{F E^* / (\pi l \rho)}

    Parameters
    ----------
    chain : Chain
        One closed chain (float attributes).
    mats : Materials
        Its materials (floats).
    phase, gamma : array_like
        Chain phase phi_0 and load direction gamma [rad], broadcast against each other.
    load : float
        Q [N].
    clearance : float
        s [mm].
    fixed_direction : bool
        The ``fixed-direction`` level.
    chunk : int
        Roller-configurations evaluated at once (bounded memory).

    Returns
    -------
    sigma_max [MPa], the broadcast shape of phase and gamma.

    Examples
    --------
    >>> ch = close_chain(100.0, 50.0, 6.0, 6.0, 8)
    >>> m = Materials.from_elastic(20.0, 2.1e5, 0.3, 2.1e5, 0.3, 2.1e5, 0.3)
    >>> np.round(sigma_max_at(ch, m, 0.0, np.array([0.0, np.pi]), 1e4, 0.0), 3).tolist()
    [748.936, 728.77]

    References
    ----------
    Merko et al. (see the module), eq. (3); docs/spec/zstk.md §2, §8.
    """
    n, q = chain.n, chain.limiting_ratio
    phase, gamma = np.broadcast_arrays(np.asarray(phase, dtype=float), np.asarray(gamma, dtype=float))
    flat_p, flat_g = phase.ravel(), gamma.ravel()
    out = np.empty(flat_p.shape)
    step = max(1, chunk // n)
    for k in range(0, flat_p.size, step):
        st = evaluate(chain, mats, roller_angles(flat_p[k:k + step], n, q), flat_g[k:k + step], load,
                      clearance, fixed_direction=fixed_direction)
        out[k:k + step] = critical(st)[0]
    return out.reshape(phase.shape)


def direction_maxima(chain: Chain, mats: Materials, phase, gamma_grid, load, clearance, refine_rtol,
                     fixed_direction=False, chunk=1_000_000, candidates=3):
    r"""The maximum over the load directions of sigma_max, for each phase (vectorised over phases).

    .. math:: \hat\sigma(\varphi_0) = \max_\gamma \sigma_{max}(\varphi_0, \gamma)

    The direction grid is ranked with the model's own loads, and the best ``candidates`` grid points
    of each phase are refined by golden section within one grid step.  (Ranking with the
    fixed-direction closed form, 10x cheaper, picked the wrong directions at large e/D: the envelope
    came out low and did not converge as the phases doubled.)

    Parameters
    ----------
    chain, mats : one closed chain and its materials (floats).
    phase : array_like
        Chain phases phi_0 [rad].
    gamma_grid : ndarray
        Uniform direction grid over one turn [rad].
    load, clearance : float
        Q [N], s [mm].
    refine_rtol : float
        Golden-section tolerance (relative to the turn).
    fixed_direction, chunk, candidates : see :func:`sigma_max_at`; grid points refined per phase.

    Returns
    -------
    ndarray, the shape of phase [MPa].

    Examples
    --------
    >>> ch = close_chain(100.0, 50.0, 6.0, 6.0, 8)
    >>> m = Materials.from_elastic(20.0, 2.1e5, 0.3, 2.1e5, 0.3, 2.1e5, 0.3)
    >>> g = 2 * np.pi * np.arange(180) / 180
    >>> bool(direction_maxima(ch, m, np.array([0.0]), g, 1e4, 0.0, 1e-6)[0] >= 748.935)
    True

    References
    ----------
    docs/spec/zstk.md §5.3, §8.
    """
    n = chain.n
    step = 2 * np.pi / gamma_grid.size
    per = max(1, chunk // (gamma_grid.size * n))
    flat = np.ravel(phase)
    res = np.empty(flat.shape)
    q = chain.limiting_ratio
    for s in range(0, flat.size, per):
        ph = flat[s:s + per]
        st = evaluate(chain, mats, roller_angles(ph[:, None], n, q), gamma_grid[None, :], load, clearance,
                      fixed_direction=fixed_direction)
        screen = critical(st)[0]
        top = np.argsort(-screen, axis=-1)[:, :candidates]
        g0 = gamma_grid[top]
        php = np.broadcast_to(ph[:, None], g0.shape)
        at_grid = sigma_max_at(chain, mats, php, g0, load, clearance, fixed_direction, chunk)
        r = minimize_golden(lambda g, php=php: -sigma_max_at(chain, mats, php, g, load, clearance,
                                                             fixed_direction, chunk),
                            g0 - step, g0 + step, rtol=refine_rtol, xtol=refine_rtol * 2 * np.pi)
        res[s:s + per] = np.max(np.maximum(-r.fun, at_grid), axis=-1)
    return res.reshape(np.shape(phase))


def critical_placement(chain: Chain, mats: Materials, load, clearance, phase=None, gamma=None, *, tol,
                       refine_rtol, grid=SweepGrid(), fixed_direction=False) -> Placement:
    r"""The chain phase and/or load direction of the largest contact stress (spec §8, "cycle" and "envelope").

    .. math:: \sigma_{max} = \max_{\varphi_0 \in [0, 2\pi/N)} \max_{\gamma \in [0, 2\pi)}
              \sigma_{max}(\varphi_0, \gamma)

    ``phase=None`` sweeps the phase over one roller pitch ("cycle"); ``gamma=None`` sweeps the load
    direction over a turn ("envelope").  Each sweep is :func:`maximise_periodic` (grid, golden
    refinement, grid doubled until the change is <= tol); with both, the phase sweep maximises
    :func:`direction_maxima` on an inner grid of >= 16 directions per roller pitch (each roller's
    stress is one smooth bump over the directions), and the final value comes from the full direction
    sweep at the critical phase.

    Parameters
    ----------
    chain, mats : one closed chain and its materials (floats).
    load, clearance : float
        Q [N], s [mm].
    phase, gamma : float or None
        A fixed phase phi_0 / direction gamma [rad], or None to sweep it.
    tol : float
        Relative accuracy target of sigma_max.
    refine_rtol : float
        Golden-section tolerance.
    grid : SweepGrid
    fixed_direction : bool

    Returns
    -------
    Placement (err: the sum of the sweeps' error estimates [MPa]).

    Examples
    --------
    >>> ch = close_chain(100.0, 50.0, 6.0, 6.0, 8)
    >>> m = Materials.from_elastic(20.0, 2.1e5, 0.3, 2.1e5, 0.3, 2.1e5, 0.3)
    >>> pl = critical_placement(ch, m, 1e4, 0.0, phase=0.0, tol=1e-6, refine_rtol=1e-5)
    >>> round(pl.value, 3) >= 748.935, pl.direction_sweep.samples >= 720
    (True, True)

    References
    ----------
    Merko et al. (see the module), Fig. 2 (stresses over the roller positions); docs/spec/zstk.md §4.3,
    §5.3, §8.
    """
    n = chain.n
    gf = grid.factor
    err = 0.0
    out = Placement(phase, gamma, 0.0)
    if phase is None:
        pitch = 2 * np.pi / n
        if gamma is None:
            m_inner = min(grid.direction, max(grid.direction // 4, 16 * n)) * gf
            gamma_grid = 2 * np.pi * np.arange(m_inner) / m_inner
            fun = lambda ph: direction_maxima(chain, mats, ph, gamma_grid, load, clearance, refine_rtol,  # noqa: E731
                                              fixed_direction, grid.chunk)
        else:
            fun = lambda ph: sigma_max_at(chain, mats, ph, gamma, load, clearance, fixed_direction,  # noqa: E731
                                          grid.chunk)
        sw = maximise_periodic(fun, 0.0, pitch, grid.phase * gf, tol, grid.cap, refine_rtol)
        out.phase, out.phase_sweep = sw.x, sw
        err += sw.err
    if gamma is None:
        sw = maximise_periodic(lambda g: sigma_max_at(chain, mats, out.phase, g, load, clearance, fixed_direction,
                                                      grid.chunk),
                               0.0, 2 * np.pi, grid.direction * gf, tol, grid.cap, refine_rtol)
        out.gamma, out.direction_sweep, out.value = sw.x, sw, sw.value
        err += sw.err
    out.err = err
    return out


def evaluate_placement(chain: Chain, mats: Materials, placement: Placement, load, clearance, *, refine_rtol,
                       grid=SweepGrid(), fixed_direction=False, stepping=False, rows=False):
    r"""The chain at a placement of :func:`critical_placement`: its state, and optionally the explicit-stepping
    residual and each roller's maxima over the load directions (spec §4.1, §5.3, §8).

    .. math:: \theta_k = \theta(\varphi_0 + 2\pi k/N), \quad \gamma = \gamma_{crit}

    Parameters
    ----------
    chain, mats : one closed chain and its materials (floats).
    placement : Placement
        Phase and load direction [rad] (``direction_sweep.samples`` sets the grid of the rows).
    load, clearance : float
        Q [N], s [mm].
    refine_rtol : float
        Golden-section tolerance of the rows.
    grid : SweepGrid
    fixed_direction : bool
    stepping : bool
        Close the chain by explicit stepping (the reference level's cross-check).
    rows : bool
        Compute :func:`roller_envelope` (an "envelope" design).

    Returns
    -------
    (theta (N,) [rad], state (1, N), stepping residual (1,) [mm] or None, envelope rows or None)

    Examples
    --------
    >>> ch = close_chain(100.0, 50.0, 6.0, 6.0, 8)
    >>> m = Materials.from_elastic(20.0, 2.1e5, 0.3, 2.1e5, 0.3, 2.1e5, 0.3)
    >>> _, st, res, _ = evaluate_placement(ch, m, Placement(0.0, 0.0, 0.0), 1e4, 0.0, refine_rtol=1e-6, stepping=True)
    >>> round(float(st.sigma_inner[0, 0]), 6), bool(res[0] < 1e-9)
    (748.935693, True)

    References
    ----------
    Merko et al. (see the module), eqs. (3)-(7); docs/spec/zstk.md §4.1, §5.3, §8.
    """
    theta = roller_angles(placement.phase, chain.n, chain.limiting_ratio)
    state = evaluate(chain, mats, theta[None, :], np.array([placement.gamma]), load, clearance,
                     fixed_direction=fixed_direction)
    residual = None
    if stepping:
        _, res = step_chain(theta[0], chain.n, chain.outer_radius, chain.inner_radius, chain.eccentricity, chain.gap)
        residual = np.array([float(res)])
    env = None
    if rows:
        env = roller_envelope(chain, mats, theta, load, clearance, refine_rtol, placement.direction_sweep.samples,
                              grid=grid, fixed_direction=fixed_direction)
    return theta, state, residual, env


def roller_envelope(chain: Chain, mats: Materials, theta, load, clearance, refine_rtol, samples=None, *,
                    grid=SweepGrid(), fixed_direction=False):
    r"""Each roller's maxima over the load directions (spec §5.3), at a fixed placement theta.

    .. math:: \gamma_{iB} = \arg\max_\gamma \sigma_{iB}(\gamma), \quad \gamma_{iH} = \arg\max_\gamma \sigma_{iH}(\gamma)

    Grid maxima on the direction grid of ``samples`` points per turn, refined by golden section (up
    to ``grid.refine_rows_max_n`` rollers).

    Parameters
    ----------
    chain, mats : one closed chain and its materials (floats).
    theta : ndarray, shape (N,)
        Roller angles [rad].
    load, clearance : float
        Q [N], s [mm].
    refine_rtol : float
        Golden-section tolerance.
    samples : int or None
        Direction grid size (default ``grid.direction``).
    grid : SweepGrid
    fixed_direction : bool

    Returns
    -------
    (d_B, d_H, gamma_B, gamma_H): dicts of :data:`ROLLER_FIELDS` -> arrays (1, N), the roller quantities
    at each roller's own critical direction of its inner (B) and outer (H) contact, and those
    directions [rad], arrays (1, N).

    Examples
    --------
    >>> ch = close_chain(100.0, 50.0, 6.0, 6.0, 8)
    >>> m = Materials.from_elastic(20.0, 2.1e5, 0.3, 2.1e5, 0.3, 2.1e5, 0.3)
    >>> d_b, d_h, g_b, g_h = roller_envelope(ch, m, roller_angles(0.0, 8, ch.limiting_ratio), 1e4, 0.0, 1e-6)
    >>> round(float(d_b["sigma_inner"][0, 0]), 3), round(float(g_b[0, 0]), 12)
    (748.936, 0.0)

    References
    ----------
    docs/spec/zstk.md §5.3.
    """
    n = chain.n
    chunk = grid.chunk

    def diagonal(gams):
        """Roller i's quantities at load direction gams[i] (chunks of rollers, bounded memory)."""
        out = {f: np.empty(n) for f in ROLLER_FIELDS}
        step_n = max(1, chunk // n)
        for k in range(0, n, step_n):
            g = gams[k:k + step_n]
            st = evaluate(chain, mats, np.broadcast_to(theta, (g.size, n)), g, load, clearance,
                          fixed_direction=fixed_direction)
            rows = np.arange(g.size)
            for f in ROLLER_FIELDS:
                out[f][k:k + g.size] = getattr(st, f)[rows, k + rows]
        return {f: v[None, :] for f, v in out.items()}

    m = samples or grid.direction
    directions = 2 * np.pi * np.arange(m) / m
    best = np.full((2, n), -1.0)
    arg = np.zeros((2, n), dtype=int)
    step_m = max(1, chunk // n)
    for k in range(0, m, step_m):  # running per-roller maxima over the direction grid
        g = directions[k:k + step_m]
        st = evaluate(chain, mats, np.broadcast_to(theta, (g.size, n)), g, load, clearance,
                      fixed_direction=fixed_direction)
        for c, sig in enumerate((st.sigma_inner, st.sigma_outer)):
            j = np.argmax(sig, axis=0)
            v = sig[j, np.arange(n)]
            better = v > best[c]
            best[c] = np.where(better, v, best[c])
            arg[c] = np.where(better, k + j, arg[c])
    centre = np.concatenate([directions[arg[0]], directions[arg[1]]])
    if n <= grid.refine_rows_max_n:
        step = 2 * np.pi / m
        pick = np.concatenate([np.arange(n), np.arange(n)])
        contact = np.repeat([0, 1], n)
        th2 = np.broadcast_to(theta, (2 * n, n))

        def neg(g):
            s = evaluate(chain, mats, th2, g, load, clearance, fixed_direction=fixed_direction)
            rows = np.arange(2 * n)
            return -np.where(contact == 0, s.sigma_inner[rows, pick], s.sigma_outer[rows, pick])

        r = minimize_golden(neg, centre - step, centre + step, rtol=refine_rtol, xtol=refine_rtol * 2 * np.pi)
        g_best = np.where(-r.fun >= best.ravel(), r.x, centre)
    else:
        g_best = centre
    gam_b, gam_h = g_best[:n], g_best[n:]
    return diagonal(gam_b), diagonal(gam_h), gam_b[None, :], gam_h[None, :]
