"""Designs of the ``zstk`` calculator solved together: prepared as arrays, stacked by roller count N, swept.

One design, a batch and the points of a sweep take the same path (spec zstk.md §8): :func:`prepare` closes,
corrects, judges (:func:`gearcalc.zstk.check_designs`) and places P designs as arrays (P,);
:func:`solve_stack` groups the valid single-position ones by N and solves each group as one stack of arrays
(G, N); :func:`solve_sweeping` runs the phase ("cycle") and direction ("envelope") sweeps of one design.
Pure functions over floats and numpy arrays: the adapter (:mod:`gearcalc.kinds.zstk`) reads the design keys
into :class:`Designs` and turns a :class:`Stack` into output fields (:mod:`gearcalc.zstk.report`).

References
----------
The seed paper by Merko et al. (seed 003), cited in full in :mod:`gearcalc.zstk`; docs/spec/zstk.md.
"""
from __future__ import annotations

__all__ = ["Designs", "Prepared", "prepare", "Stack", "solve_stack", "stack_order", "gather", "Sweeping",
           "solve_sweeping"]

import math
import operator
from dataclasses import dataclass
from typing import Any, NamedTuple

import numpy as np

from ..arrays import unique_sorted
from ..units import deg_to_rad
from .capacity import AllowableLoad, allowable_load_sweeping
from .chain import Chain, chain_phases, limiting_ratios
from .envelope import Placement, SweepGrid, critical_placement, evaluate_placement
from .geometry import SCHEME_PARITY, remainder_360, single, take
from .stress import Materials, State, solve_placements
from .validity import Validity, check_designs


class Designs(NamedTuple):
    """P designs held column-wise: each field is one value shared by every design, or a list with one value per design.

    outer, inner, eccentricity, gap, length : nominal R_H, R_B, e, c and the roller length l [mm];
    rollers : N, or "auto"; correct : "outer" | "inner" | "gap"; scheme : "A"-"D", "cycle", or the polar
    angle theta_0 of roller 0 [deg]; separator : bool; load : Q [N]; direction : of Q [deg], or "envelope";
    clearance : s [mm]; roller_e, roller_nu, ring_e, ring_nu : E [MPa] and Poisson's ratio; inner_e,
    inner_nu, outer_e, outer_nu : the rings' own (None: ring_e, ring_nu); allowable : [sigma_H] [MPa]
    (None: the default).
    """

    outer: Any
    inner: Any
    eccentricity: Any
    gap: Any
    length: Any
    rollers: Any
    correct: Any
    scheme: Any
    separator: Any
    load: Any
    direction: Any
    clearance: Any
    roller_e: Any
    roller_nu: Any
    ring_e: Any
    ring_nu: Any
    inner_e: Any
    inner_nu: Any
    outer_e: Any
    outer_nu: Any
    allowable: Any


@dataclass
class Prepared:
    """P designs up to the load solve (:func:`prepare`), arrays of shape (P,).

    designs : the :class:`Designs`; validity : :func:`gearcalc.zstk.check_designs`; valid (and with a
    separator), n, chain (stacked), q (limiting-point ratio); phase phi_0 [rad]; letter (a symmetric
    scheme), cycle, scheme ("A"-"D", "cycle" or "angle"); envelope, gamma [rad]; load [N], clearance [mm];
    mats (stacked); allowable [MPa] and allowable_default.
    """

    size: int
    designs: Designs
    validity: Validity
    separator: np.ndarray
    valid: np.ndarray
    n: np.ndarray
    chain: Chain
    q: np.ndarray
    letter: np.ndarray
    cycle: np.ndarray
    scheme: np.ndarray
    phase: np.ndarray
    envelope: np.ndarray
    gamma: np.ndarray
    load: np.ndarray
    clearance: np.ndarray
    mats: Materials
    allowable: np.ndarray
    allowable_default: np.ndarray


def prepare(d: Designs, size: int, max_rollers: int, default_allowable: float) -> Prepared:
    """Chain closure and correction, validity, phase, load direction and materials of ``size`` designs.

    Validity is :func:`gearcalc.zstk.check_designs` (the one rule set of check, compute, batch and sweep);
    a design without a separator is invalid too (spec §5.5).  Phases: :func:`gearcalc.zstk.chain_phases`
    (spec §4); directions and theta_0 are reduced exactly to (-180, 180] degrees first.

    Parameters
    ----------
    d : Designs
        The designs, held column-wise.
    size : int
        The number of designs P.
    max_rollers : int
        The largest N accepted, [-].
    default_allowable : float
        [sigma_H] of a design that gives none, [MPa].

    Returns
    -------
    prepared : Prepared
        Chains, materials, validity, phases, directions, loads and allowable stresses, arrays (P,).

    Examples
    --------
    >>> d = Designs(100.0, 50.0, [6.0, 60.0], 6.0, 20.0, "auto", "outer", "A", True, 1e4, 0.0, 0.0,
    ...             2.1e5, 0.3, 2.1e5, 0.3, None, None, None, None, None)
    >>> p = prepare(d, 2, 2000, 4000.0)
    >>> p.valid.tolist(), p.n.tolist(), p.allowable.tolist()
    ([True, False], [8, 0], [4000.0, 4000.0])

    References
    ----------
    docs/spec/zstk.md §3.2-3.3 (closure, validity), §4 (phase), §5.3 (direction), §5.5 (separator).
    """
    def per(v, fn, dtype=bool):
        """The function fn of each design's value (once when the value is shared by every design)."""
        if isinstance(v, list):
            return np.array([fn(x) for x in v], dtype=dtype)
        return np.full(size, fn(v), dtype=dtype)

    def num(v):
        return np.asarray(v, dtype=float) if isinstance(v, list) else np.full(size, float(v))

    def num_or(v, fallback):
        if v is None:
            return fallback
        if not isinstance(v, list):
            return np.full(size, float(v))
        return np.where(per(v, lambda x: x is not None), per(v, lambda x: 0.0 if x is None else x, float), fallback)

    r_h, r_b, e, c, clearance = num(d.outer), num(d.inner), num(d.eccentricity), num(d.gap), num(d.clearance)
    letter = per(d.scheme, lambda s: isinstance(s, str) and s in SCHEME_PARITY)
    cycle = per(d.scheme, lambda s: s == "cycle")
    parity = per(d.scheme, lambda s: SCHEME_PARITY.get(s, -1) if isinstance(s, str) else -1, np.int64)
    theta_deg = per(d.scheme, lambda s: 0.0 if isinstance(s, str) else s, float)
    validity = check_designs(r_h, r_b, e, c, per(d.rollers, lambda r: 0 if r == "auto" else r, np.int64), parity,
                             clearance, per(d.correct, str, object), max_rollers)
    separator = per(d.separator, bool)
    valid, n, chain = validity.valid & separator, validity.n, validity.chain
    q = limiting_ratios(chain, valid)
    phase = chain_phases(n, q, letter, per(d.scheme, lambda s: s in ("C", "D")), ~letter & ~cycle,
                         deg_to_rad(remainder_360(theta_deg)))
    gamma = deg_to_rad(remainder_360(per(d.direction, lambda v: 0.0 if isinstance(v, str) else v, float)))
    ring_e, ring_nu = num(d.ring_e), num(d.ring_nu)
    mats = Materials.from_elastic(num(d.length), num(d.roller_e), num(d.roller_nu), num_or(d.inner_e, ring_e),
                                  num_or(d.inner_nu, ring_nu), num_or(d.outer_e, ring_e), num_or(d.outer_nu, ring_nu))
    allowable_default = per(d.allowable, lambda v: v is None)
    allowable = np.where(allowable_default, default_allowable,
                         per(d.allowable, lambda v: 0.0 if v is None else v, float))
    return Prepared(size, d, validity, separator, valid, n, chain, q, letter, cycle,
                    per(d.scheme, lambda s: s if isinstance(s, str) else "angle", object), phase,
                    per(d.direction, lambda v: v == "envelope"), gamma, num(d.load), clearance, mats, allowable,
                    allowable_default)


@dataclass(frozen=True)
class Stack:
    """G solved designs of one roller count N.

    chain, mats (arrays (G,)), state (arrays (G, N)); gamma [rad], load [N], clearance [mm], symmetric (solved in
    closed form), allowable [MPa], allowable_default, scheme, arrays (G,); stepping: the explicit-stepping residual
    (G,) [mm] of the reference level, else None.
    """

    chain: Chain
    mats: Materials
    state: State
    gamma: np.ndarray
    load: np.ndarray
    clearance: np.ndarray
    symmetric: np.ndarray
    allowable: np.ndarray
    allowable_default: np.ndarray
    scheme: np.ndarray
    stepping: np.ndarray | None = None


def solve_stack(p: Prepared, idx, fixed_direction=False, reference=False) -> list:
    """Solve the single-position designs ``idx`` of ``p`` (valid, not "cycle", not "envelope"), grouped by N.

    Returns a list of (indices into ``p``, :class:`Stack`), one per roller count N, in increasing N
    (:func:`stack_order` and :func:`gather` put their results back in the order of ``idx``).

    Parameters
    ----------
    p : Prepared
        The prepared designs.
    idx : ndarray of int
        The designs to solve.
    fixed_direction : bool, optional
        The ``fixed-direction`` level (v parallel to u everywhere).
    reference : bool, optional
        The reference level (explicit stepping of the chain too).

    Returns
    -------
    stacks : list of tuple
        (indices into ``p``, :class:`Stack`), one per roller count N, in increasing N.

    Examples
    --------
    >>> d = Designs(100.0, 50.0, [6.0, 60.0], 6.0, 20.0, "auto", "outer", "A", True, 1e4, 0.0, 0.0,
    ...             2.1e5, 0.3, 2.1e5, 0.3, None, None, None, None, None)
    >>> [(k.tolist(), round(float(s.state.sigma_inner.max()), 3)) for k, s in solve_stack(prepare(d, 2, 2000, 4000.0),
    ...                                                                                    np.array([0]))]
    [([0], 748.936)]

    References
    ----------
    docs/spec/zstk.md §4-§5, §8 (stacked designs).
    """
    idx = np.asarray(idx)
    ns = p.n[idx]
    out = []
    for nn in unique_sorted(ns):
        sub = idx[ns == nn]
        chain, mats = take(p.chain, sub), take(p.mats, sub)
        state, symmetric, stepping = solve_placements(chain, mats, p.phase[sub], p.q[sub], p.gamma[sub], p.load[sub],
                                                      p.clearance[sub], p.letter[sub], fixed_direction, reference)
        out.append((sub, Stack(chain, mats, state, p.gamma[sub], p.load[sub], p.clearance[sub], symmetric,
                               p.allowable[sub], p.allowable_default[sub], p.scheme[sub], stepping)))
    return out


def stack_order(idx, groups):
    r"""The permutation that restores the order of ``idx`` after grouping.

    The permutation that puts the concatenated results of ``groups`` (index arrays that partition ``idx``) back in
    the order of ``idx``.

    .. math:: \text{back} = \operatorname{argsort}(\text{concat}(\text{groups})) \ \text{in the order of idx}

    Parameters
    ----------
    idx : ndarray of int
        The designs in their order.
    groups : list of ndarray of int
        Index arrays that partition ``idx``.

    Returns
    -------
    back : ndarray of int
        The permutation of the concatenated results.

    Examples
    --------
    >>> stack_order(np.array([4, 7, 9]), [np.array([7]), np.array([4, 9])]).tolist()
    [1, 0, 2]

    References
    ----------
    .. [1] docs/spec/zstk.md §8 "Vectorisation" (designs stacked by N).
    """
    order = np.concatenate(groups)
    where = np.empty(int(idx.max()) + 1, dtype=np.int64)
    where[idx] = np.arange(idx.size)
    return np.argsort(where[order], kind="stable")


def gather(lists, back) -> list:
    """Concatenate lists and reorder them by the permutation ``back`` (:func:`stack_order`).

    Parameters
    ----------
    lists : list of list
        The results of each group.
    back : ndarray of int
        The permutation of :func:`stack_order`.

    Returns
    -------
    out : list
        The results in the order of the designs.

    Examples
    --------
    >>> gather([["b"], ["a", "c"]], np.array([1, 0, 2]))
    ['a', 'b', 'c']

    References
    ----------
    .. [1] docs/spec/zstk.md §8 "Vectorisation" (designs stacked by N).
    """
    flat = [v for part in lists for v in part]
    if len(flat) == 1:
        return flat
    return list(operator.itemgetter(*back.tolist())(flat))


@dataclass(frozen=True)
class Sweeping:
    """A "cycle" and/or "envelope" design solved (:func:`solve_sweeping`).

    The critical placement's stack (G = 1), the placement (its sweeps), the per-contact envelope rows (d_B, d_H,
    gamma_B, gamma_H) of "envelope" or None, the allowable radial load, and the sweeps' maximum (None without a
    direction sweep) and error estimate [MPa], arrays (1,).
    """

    stack: Stack
    placement: Placement
    rows: tuple | None
    capacity: AllowableLoad
    value: np.ndarray | None
    err: np.ndarray


def solve_sweeping(p: Prepared, tol: float, grid: SweepGrid, fixed_direction=False, reference=False) -> Sweeping:
    """The critical placement of the one design of ``p`` and its allowable radial load.

    The critical placement of the one design of ``p`` over its phase and/or load direction
    (:func:`gearcalc.zstk.critical_placement`), its allowable radial load, and the placement evaluated.

    The refinements aim at 0.01 sqrt(tol) relative (1e-12 at the reference level, which also closes the chain
    by explicit stepping); a fixed direction or phase is the design's own.

    Parameters
    ----------
    p : Prepared
        One prepared design ("cycle" and/or "envelope").
    tol : float
        The relative tolerance of the results.
    grid : SweepGrid
        The sweeps' grids.
    fixed_direction : bool, optional
        The ``fixed-direction`` level.
    reference : bool, optional
        The reference level.

    Returns
    -------
    sweeping : Sweeping
        The critical placement's stack, the placement, the envelope rows, the allowable radial load, the maximum
        and its error, arrays (1,).

    Examples
    --------
    >>> d = Designs(100.0, 50.0, 6.0, 6.0, 20.0, "auto", "outer", "cycle", True, 1e4, 0.0, 0.0,
    ...             2.1e5, 0.3, 2.1e5, 0.3, None, None, None, None, None)
    >>> s = solve_sweeping(prepare(d, 1, 2000, 4000.0), 1e-6, SweepGrid())
    >>> round(float(s.stack.state.sigma_inner.max()), 3), round(float(s.capacity.load[0]) / 1e3, 3)
    (748.936, 285.253)

    References
    ----------
    docs/spec/zstk.md §5.4 (allowable load), §8 (the sweeps).
    """
    chain, mats = single(p.chain), single(p.mats)
    load, clearance = float(p.load[0]), float(p.clearance[0])
    cycle, envelope = bool(p.cycle[0]), bool(p.envelope[0])
    refine_rtol = 1e-12 if reference else 0.01 * math.sqrt(tol)  # see zstk.maximise_periodic
    phase, gamma = None if cycle else float(p.phase[0]), None if envelope else float(p.gamma[0])
    pl = critical_placement(chain, mats, load, clearance, phase, gamma, tol=tol, refine_rtol=refine_rtol, grid=grid,
                            fixed_direction=fixed_direction)
    capacity = allowable_load_sweeping(chain, mats, load, clearance, float(p.allowable[0]), pl, phase=phase,
                                       gamma=gamma, tol=tol, refine_rtol=refine_rtol, grid=grid,
                                       fixed_direction=fixed_direction)
    pl.gamma = pl.gamma if envelope else float(p.gamma[0])  # the design's direction (as a stacked design's)
    _, state, stepping, rows = evaluate_placement(chain, mats, pl, load, clearance, refine_rtol=refine_rtol,
                                                  grid=grid, fixed_direction=fixed_direction, stepping=reference,
                                                  rows=envelope)
    stack = Stack(p.chain, p.mats, state, np.array([pl.gamma]), np.array([load]), np.array([clearance]),
                  np.array([False]), p.allowable[:1], p.allowable_default[:1], p.scheme[:1], stepping)
    return Sweeping(stack, pl, rows, capacity, None if pl.value is None else np.array([pl.value]), np.array([pl.err]))
