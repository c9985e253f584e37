"""Maxima over the chain phase ("cycle") and the load direction ("envelope") (spec zstk.md §8).

References
----------
The seed paper by Merko et al. (seed 003), cited in full in :mod:`gearcalc.zstk`; docs/spec/zstk.md.
"""
from __future__ import annotations

__all__ = ['GRID_PHASE', 'GRID_DIRECTION', 'GRID_CAP', 'CHUNK_ELEMENTS', 'REFINE_ROWS_MAX_N', 'REFERENCE_GRID_FACTOR',
           'SweepResult', 'maximise_periodic', 'SweepGrid', 'sweep_grid', 'sweep_work', 'Placement', 'ROLLER_FIELDS',
           'sigma_max_at', 'direction_maxima', 'roller_sigma', 'position_direction_max', 'critical_placement',
           'evaluate_placement', 'roller_envelope']

import math
from dataclasses import dataclass

import numpy as np

from ..roots import maximize_bracketed, minimize_golden
from .chain import Chain, close_chain, roller_angles, step_chain  # noqa: F401 (close_chain: the examples)
from .. import hertz
from .geometry import centre_distance, reduced_radii, roller_radius
from .loads import solve_loads
from .stress import Materials, critical, evaluate

GRID_PHASE = 64
"""First grid of the phase sweep ("cycle"), points per roller pitch (spec §8)."""
GRID_DIRECTION = 720
"""First grid of the direction sweep ("envelope"), points per turn (spec §8)."""
GRID_CAP = 2 ** 16
"""The largest grid a sweep doubles to (per pitch or per turn) before it stops with a warning."""
CHUNK_ELEMENTS = 1_000_000
"""Roller-configurations evaluated at once in the sweeps (bounds their memory)."""
REFINE_ROWS_MAX_N = 200
"""Above this N the per-roller envelope rows are grid maxima (their refinement is O(N²))."""
REFERENCE_GRID_FACTOR = 8
"""Grid multiplier of the ``reference`` level."""



# ----------------------------------------------------------------------------- §8 sweeps
@dataclass
class SweepResult:
    """Maximum of a periodic function found by grid + golden refinement + grid doubling.

    x : argmax [rad]; value : the maximum; err : error estimate of value; samples : the grid
    size M of the final level; step : the grid step [rad]; capped : the target was not met (the M cap was reached,
    or with ``floor`` the refinement reached the round-off of the angles first).
    """

    x: float
    value: float
    err: float
    samples: int
    step: float
    capped: bool = False
    floor: bool = False


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


def maximise_periodic(fun, start, period, samples, tol, cap=GRID_CAP, refine_rtol=None):
    r"""Maximum of a vectorised periodic function over one period (spec §8, sweeps).

    .. math:: \max_{x \in [x_0, x_0 + T)} f(x), \quad \text{error} = |v_M - v_{M/2}| + \text{refinement error} \le
              \text{tol} \cdot |v_M|

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
    (8 at the reference level); joint_position, joint_direction : the first grid of "cycle" with
    "envelope" (:func:`position_direction_max`): intervals of the roller position over a half turn, and
    load directions relative to the roller's normal over a turn.
    """

    phase: int = GRID_PHASE
    direction: int = GRID_DIRECTION
    cap: int = GRID_CAP
    chunk: int = CHUNK_ELEMENTS
    refine_rows_max_n: int = REFINE_ROWS_MAX_N
    factor: int = 1
    joint_position: int = 8
    joint_direction: int = 32


def sweep_grid(reference=False) -> SweepGrid:
    """The sweep grids of the default levels, or of the ``reference`` level (spec §8).

    The sweep grids of the default levels, or of the ``reference`` level (:data:`REFERENCE_GRID_FACTOR` times
    finer), from the constants above read at call time (spec §8).

    Parameters
    ----------
    reference : bool, optional
        The reference level's grids.

    Returns
    -------
    grid : SweepGrid
        The grids' sizes and the refinement factor.

    Examples
    --------
    >>> sweep_grid().phase, sweep_grid(reference=True).factor
    (64, 8)

    References
    ----------
    .. [1] docs/spec/zstk.md §8.
    """
    return SweepGrid(GRID_PHASE, GRID_DIRECTION, GRID_CAP, CHUNK_ELEMENTS, REFINE_ROWS_MAX_N,
                     REFERENCE_GRID_FACTOR if reference else 1)


JOINT_COST = 3
"""Weight of a first-grid configuration of :func:`position_direction_max` in :func:`sweep_work`: its grid doubling
and box refinements cost about 3 times as much per first-grid point as the single sweeps' (measured: N = 2000,
3.8 s for 5.8e5 first-grid roller-configurations; the single sweeps ~2 us per unit)."""


def sweep_work(n, cycle, envelope, grid=SweepGrid()):
    r"""Roller-configurations of the first grids of a design's sweeps (spec §8).

    N x phases x directions (the cost budget's measure); "cycle" with "envelope": :data:`JOINT_COST` x N x
    (positions + 1) x relative directions of :func:`position_direction_max`'s first grid.

    .. math:: W = N\,P\,D \ \text{(the sweeps' grids, 1 where not swept)}, \qquad
        W = c_J\,N\,(P_J + 1)\,D_J \ \text{("cycle" with "envelope")}

    Parameters
    ----------
    n : int
        Roller number N, [-].
    cycle, envelope : bool
        The phase and the direction are swept.
    grid : SweepGrid, optional
        The grids.

    Returns
    -------
    work : int
        Roller configurations of the first grids.

    Examples
    --------
    >>> sweep_work(8, True, False), sweep_work(8, False, True), sweep_work(8, True, True)
    (512, 5760, 6912)

    References
    ----------
    .. [1] docs/spec/zstk.md §8, §9 (the cost budget).
    """
    gf = grid.factor
    if cycle and envelope:
        return JOINT_COST * n * (grid.joint_position * gf + 1) * grid.joint_direction * gf
    return n * (grid.phase * gf if cycle else 1) * (grid.direction * gf if envelope else 1)


@dataclass
class Placement:
    """The critical placement of a chain.

    phase phi_0 [rad], load direction gamma [rad], the sweeps' error estimate err [MPa] and their results (None for
    a quantity not swept); value : the direction sweep's maximum [MPa] (None without it).
    """

    phase: float
    gamma: float
    err: float
    phase_sweep: SweepResult | None = None
    direction_sweep: SweepResult | None = None
    value: float | None = None


def sigma_max_at(chain: Chain, mats: Materials, phase, gamma, load, clearance, fixed_direction=False,
                 chunk=CHUNK_ELEMENTS):
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
                     fixed_direction=False, chunk=CHUNK_ELEMENTS, candidates=3):
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


def roller_sigma(chain: Chain, mats: Materials, position, relative_direction, load, clearance, fixed_direction=False,
                 chunk=CHUNK_ELEMENTS):
    r"""The larger contact stress of roller 0 at a position, under a load relative to its normal.

    The larger contact stress of roller 0 placed at the uniformising angle ``position``, under a load whose
    direction is ``relative_direction`` from that roller's inner normal (spec §4.1, §8).

    .. math:: f(\varphi, \rho) = \max(\sigma_{0B}, \sigma_{0H}), \quad \theta_k = \theta(\varphi + 2\pi k/N),
              \quad \gamma = \theta_0 + \beta_0 + \rho

    Every roller is roller 0 at another position (theta_k = theta(phi_0 + 2 pi k/N)), so the maximum of
    sigma_max over chain phases and load directions is the maximum of f over the roller position
    phi in [0, 2 pi) and rho; the mirror symmetry of the chain makes f(-phi, -rho) = f(phi, rho).

    Parameters
    ----------
    chain, mats : one closed chain and its materials (floats).
    position, relative_direction : array_like
        phi [rad] and rho [rad], broadcast against each other.
    load, clearance : float
        Q [N], s [mm].
    fixed_direction, chunk : see :func:`sigma_max_at`.

    Returns
    -------
    f [MPa], the broadcast shape.

    Examples
    --------
    >>> ch = close_chain(100.0, 50.0, 6.0, 6.0, 8)
    >>> m = Materials.from_elastic(20.0, 2.1e5, 0.3, 2.1e5, 0.3, 2.1e5, 0.3)
    >>> round(float(roller_sigma(ch, m, 0.0, 0.0, 1e4, 0.0)), 6)      # scheme A, load on the line of centres
    748.935693

    References
    ----------
    Merko et al. (see the module), eq. (3); docs/spec/zstk.md §4.1, §8.
    """
    n, q = chain.n, chain.limiting_ratio
    r_h, r_b, e = chain.outer_radius, chain.inner_radius, chain.eccentricity
    pos, rel = np.broadcast_arrays(np.asarray(position, dtype=float), np.asarray(relative_direction, dtype=float))
    flat_p, flat_r = pos.ravel(), rel.ravel()
    out = np.empty(flat_p.shape)
    step = max(1, chunk // n)
    for k in range(0, flat_p.size, step):
        # evaluate()'s arithmetic, the stresses of roller 0 only (the same numbers, less work)
        theta = roller_angles(flat_p[k:k + step], n, q)
        h = centre_distance(theta, r_h, r_b, e)
        beta_s = np.arctan2(e * np.sin(theta), h - e * np.cos(theta))
        nb = theta + beta_s
        sol = solve_loads(nb, nb[:, 0] + flat_r[k:k + step], load, mats.stiffness, clearance,
                          fixed_direction=fixed_direction)
        f_b = sol.force[:, 0]
        rho_b, rho_h = reduced_radii(roller_radius(theta[:, 0], r_h, r_b, e), h[:, 0], r_b, r_h)
        sig_b = hertz.peak_pressure(f_b, mats.length, rho_b, mats.e_star_inner)
        sig_h = hertz.peak_pressure(f_b * np.cos(beta_s[:, 0]), mats.length, rho_h, mats.e_star_outer)
        out[k:k + step] = np.maximum(sig_b, sig_h)
    return out.reshape(pos.shape)


JOINT_INNER_TOP = 2
"""Local maxima over the relative direction refined per roller position (f is one bump there, spec §8; the second
is the margin for a kink)."""
JOINT_OUTER_TOP = 4
"""Local maxima over the roller position (of the maximum over the directions) refined per level."""
JOINT_INNER_SHARE = 0.02
"""The inner (direction) maximisations' bound as a share of the outer one's target: their round-off-like error
enters the outer tangent bound's secants."""


def _inner_direction_max(f, pos, m_count, target=None, scale=None):
    r"""g(phi) = max over rho of f(phi, rho) at each position (1-D ``pos``).

    A grid of ``m_count`` relative directions over a turn, its :data:`JOINT_INNER_TOP` largest local maxima
    (periodic) refined within one grid step by :func:`gearcalc.roots.maximize_bracketed` to ``target`` (None:
    ``scale`` times the grid's largest |f|). Returns (g, the bound on what g misses at each position, rho at g, all
    converged, the target).
    """
    rel = 2 * np.pi * np.arange(m_count) / m_count
    rel = np.where(rel > np.pi, rel - 2 * np.pi, rel)
    vals = f(pos[:, None], rel[None, :])
    if target is None:
        target = scale * float(np.max(np.abs(vals)))
    left, right = np.roll(vals, 1, axis=1), np.roll(vals, -1, axis=1)
    peak = (vals >= left) & (vals >= right) & ((vals > left) | (vals > right))  # not a flat stretch (unloaded)
    score = np.where(peak, vals, -np.inf)
    k = np.argsort(-score, axis=1, kind="stable")[:, :JOINT_INNER_TOP]
    rows = np.broadcast_to(np.arange(pos.size)[:, None], k.shape)
    ok = np.isfinite(score[rows, k])
    ok[:, 0] |= ~ok[:, 0]  # a row without a local maximum (a constant row) refines its first grid point
    row, kk = rows[ok], k[ok]
    h = 2 * np.pi / m_count
    res = maximize_bracketed(lambda x, i: f(pos[row[i]][:, None], x), rel[kk] - h, rel[kk] + h,
                             vals[row, (kk - 1) % m_count], vals[row, (kk + 1) % m_count], target)
    at_grid = vals[row, kk]
    better = res.value >= at_grid
    cand_v = np.where(better, res.value, at_grid)
    cand_x = np.where(better, res.x, rel[kk])
    cand_u = np.maximum(cand_v, res.value + res.bound)
    value, upper, best_x = np.full(pos.size, -np.inf), np.full(pos.size, -np.inf), np.zeros(pos.size)
    np.maximum.at(upper, row, cand_u)
    order = np.lexsort((cand_v, row))  # per row ascending: the last write of each row is its best candidate
    value[row[order]], best_x[row[order]] = cand_v[order], cand_x[order]
    return value, upper - value, best_x, bool(np.all(res.converged)), target


def position_direction_max(chain: Chain, mats: Materials, load, clearance, *, tol, refine_rtol, grid=SweepGrid(),
                           fixed_direction=False, top=JOINT_OUTER_TOP):
    r"""Maximum of sigma_max over the chain phase and the load direction together.

    Maximum of sigma_max over the chain phase and the load direction together ("cycle" with "envelope", spec §8,
    §11.8), as the maximum of one roller's stress over its position and the relative load direction.

    .. math:: \max_{\varphi_0, \gamma} \sigma_{max} = \max_{\varphi \in [0, \pi]} g(\varphi), \quad
              g(\varphi) = \max_{\rho} f(\varphi, \rho)

    (:func:`roller_sigma`; [0, pi] by the mirror symmetry, which makes g even about 0 and pi).  Each level
    evaluates g at P + 1 positions over [0, pi], g itself by a grid of M relative directions over a turn and a
    bracketed maximisation of its largest local maxima (:func:`_inner_direction_max`).  The ``top`` largest local
    maxima of g on the position grid are refined by a bracketed golden-section maximisation within one grid
    step (:func:`gearcalc.roots.maximize_bracketed`), each only until the tangent bound on what its bracket can
    still hide is <= tol·max/4: the refinement error is that bound (the largest over the candidates, above the
    best value found) plus 4 times the largest inner bound (the inner maxima are low by at most that bound,
    which also enters the outer secants).  Then P and M are doubled; the error estimate is the change of the
    maximum plus the refinement error, repeated until it is <= tol·max.  A refinement that reaches the
    round-off of the angles before its target stops the doubling at the next level (``capped``).

    What a level cannot see: a local maximum of g narrower than two position steps, or of f narrower than two
    direction steps, that no grid point rises toward.  The doubled level is the check of that (the change of
    the maximum); f is one smooth bump in rho relative to the roller's normal with kinks where rollers enter or
    leave the load zone, and g is smooth between such kinks (spec §8), so the first grids resolve them.

    Parameters
    ----------
    chain, mats : one closed chain and its materials (floats).
    load, clearance : float
        Q [N], s [mm].
    tol : float
        Relative accuracy target.
    refine_rtol : float
        Unused (the refinements stop on their value bound); kept for the callers' uniform signature.
    grid : SweepGrid
        ``joint_position``, ``joint_direction`` (times ``factor``), ``cap``, ``chunk``.
    fixed_direction : bool
    top : int
        Local maxima over the position refined per level.

    Returns
    -------
    (position phi [rad], relative direction rho [rad], load direction gamma [rad], value [MPa], SweepResult of
    the positions (samples: positions per turn), SweepResult of the directions (samples: per turn)).

    Examples
    --------
    >>> ch = close_chain(100.0, 50.0, 6.0, 6.0, 8)
    >>> m = Materials.from_elastic(20.0, 2.1e5, 0.3, 2.1e5, 0.3, 2.1e5, 0.3)
    >>> phi, rho, gam, v, sp, sd = position_direction_max(ch, m, 1e4, 0.0, tol=1e-6, refine_rtol=1e-5)
    >>> round(v, 6), round(phi, 9), round(rho, 9)
    (748.935693, 0.0, 0.0)

    References
    ----------
    Merko et al. (see the module), Fig. 2; docs/spec/zstk.md §4.1, §8, §11.8.
    """
    del refine_rtol
    gf = grid.factor
    p_count, m_count = grid.joint_position * gf, grid.joint_direction * gf
    r_h, r_b, e = chain.outer_radius, chain.inner_radius, chain.eccentricity

    def f(pos, rel):
        return roller_sigma(chain, mats, pos, rel, load, clearance, fixed_direction, grid.chunk)

    prev, stalled = None, False
    while True:
        h = np.pi / p_count
        pos_grid = h * np.arange(p_count + 1)
        g, gap, _, conv, t_in = _inner_direction_max(f, pos_grid, m_count, scale=0.25 * tol * JOINT_INNER_SHARE)
        target = t_in / JOINT_INNER_SHARE
        stalled |= not conv
        ext = np.concatenate([g[1:2], g, g[-2:-1]])  # g is even about 0 and pi
        peak = np.flatnonzero((g >= ext[:-2]) & (g >= ext[2:]))
        if peak.size == 0:
            peak = np.array([int(np.argmax(g))])
        peak = peak[np.argsort(-g[peak], kind="stable")][:top]
        gaps = [float(np.max(gap))]

        def outer(x, i, m_count=m_count, t_in=t_in, gaps=gaps):
            v, gp, _, c, _ = _inner_direction_max(f, x.ravel(), m_count, t_in)
            gaps.append(float(np.max(gp)))
            if not c:
                nonlocal stalled
                stalled = True
            return v.reshape(x.shape)

        res = maximize_bracketed(outer, pos_grid[peak] - h, pos_grid[peak] + h, ext[peak], ext[peak + 2], target)
        stalled |= not bool(np.all(res.converged))
        b = int(np.argmax(res.value))
        g_best = int(np.argmax(g))
        if res.value[b] >= g[g_best]:
            pos_b, v = float(res.x[b]), float(res.value[b])
        else:
            pos_b, v = float(pos_grid[g_best]), float(g[g_best])
        err_ref = max(float(np.max(res.value + res.bound)) - v, 0.0) + 4.0 * max(gaps)
        capped = 2 * m_count > grid.cap
        if prev is not None:
            err = abs(v - prev) + err_ref
            if err <= tol * abs(v) or capped or stalled:
                break
        prev = v
        p_count, m_count = 2 * p_count, 2 * m_count
    v_b, _, rho_b, _, _ = _inner_direction_max(f, np.array([pos_b]), m_count, t_in)
    rel_b = float(rho_b[0])
    if v_b[0] > v:
        v = float(v_b[0])
    if pos_b < 0.0:  # g is even about 0: the mirror position (f(-phi, -rho) = f(phi, rho))
        pos_b, rel_b = -pos_b, -rel_b
    t0 = float(roller_angles(pos_b, chain.n, chain.limiting_ratio)[0])
    gamma = t0 + float(np.arctan2(e * np.sin(t0), centre_distance(t0, r_h, r_b, e) - e * np.cos(t0))) + rel_b
    over = err > tol * abs(v)
    floor = over and stalled
    return (pos_b, rel_b, gamma, v, SweepResult(pos_b, v, err, 2 * p_count, np.pi / p_count, over, floor),
            SweepResult(rel_b, v, err, m_count, 2 * np.pi / m_count, over, floor))


def critical_placement(chain: Chain, mats: Materials, load, clearance, phase=None, gamma=None, *, tol,
                       refine_rtol, grid=SweepGrid(), fixed_direction=False) -> Placement:
    r"""The chain phase and/or load direction of the largest contact stress (spec §8, "cycle" and "envelope").

    .. math:: \sigma_{max} = \max_{\varphi_0 \in [0, 2\pi/N)} \max_{\gamma \in [0, 2\pi)}
              \sigma_{max}(\varphi_0, \gamma)

    ``phase=None`` sweeps the phase over one roller pitch ("cycle"); ``gamma=None`` sweeps the load
    direction over a turn ("envelope").  Each sweep is :func:`maximise_periodic` (grid, golden
    refinement, grid doubled until the change is <= tol); with both, :func:`position_direction_max`
    (one roller's stress over its position and the load direction relative to its normal); the phase
    is then the chain phase in [0, 2 pi/N) that puts a roller at the critical position.

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
    if phase is None and gamma is None:
        pos, _, gam, value, sw_pos, sw_dir = position_direction_max(chain, mats, load, clearance, tol=tol,
                                                                    refine_rtol=refine_rtol, grid=grid,
                                                                    fixed_direction=fixed_direction)
        pitch = 2 * np.pi / n
        phase0 = float(np.mod(pos, pitch))
        if pitch - phase0 <= 1e-15 * pitch:
            phase0 = 0.0
        return Placement(phase0, float(np.mod(gam + np.pi, 2 * np.pi) - np.pi), sw_pos.err, sw_pos, sw_dir, value)
    if phase is None:
        pitch = 2 * np.pi / n
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
    r"""The chain at a placement of :func:`critical_placement`.

    Its state, and optionally the explicit-stepping residual and each roller's maxima over the load directions (spec
    §4.1, §5.3, §8).

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
        samples = max(placement.direction_sweep.samples, grid.direction * grid.factor)  # >= the envelope's own grid
        env = roller_envelope(chain, mats, theta, load, clearance, refine_rtol, samples, grid=grid,
                              fixed_direction=fixed_direction)
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
    refine = n <= grid.refine_rows_max_n
    # without refinement the rows are the grid maxima: their quantities are kept as the grid runs (no O(N²)
    # re-evaluation at each roller's own direction)
    kept = None if refine else [{f: np.zeros(n) for f in ROLLER_FIELDS} for _ in range(2)]
    cols = np.arange(n)
    for k in range(0, m, step_m):  # running per-roller maxima over the direction grid
        g = directions[k:k + step_m]
        st = evaluate(chain, mats, np.broadcast_to(theta, (g.size, n)), g, load, clearance,
                      fixed_direction=fixed_direction)
        for c, sig in enumerate((st.sigma_inner, st.sigma_outer)):
            j = np.argmax(sig, axis=0)
            v = sig[j, cols]
            better = v > best[c]
            best[c] = np.where(better, v, best[c])
            arg[c] = np.where(better, k + j, arg[c])
            if kept is not None:
                for f in ROLLER_FIELDS:
                    kept[c][f] = np.where(better, np.broadcast_to(getattr(st, f), sig.shape)[j, cols], kept[c][f])
    centre = np.concatenate([directions[arg[0]], directions[arg[1]]])
    if kept is not None:
        return ({f: v[None, :] for f, v in kept[0].items()}, {f: v[None, :] for f, v in kept[1].items()},
                centre[None, :n], centre[None, n:])
    if refine:
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
    gam_b, gam_h = g_best[:n], g_best[n:]
    return diagonal(gam_b), diagonal(gam_h), gam_b[None, :], gam_h[None, :]
