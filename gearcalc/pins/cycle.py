"""KHV pin gearing, level ``ideal``: the cycle model of one gear (pins.md §4.6, §6, §12.7).

The breakpoints of the loss ratio over one crank-angle period, the state of the loaded pins at crank
angles, the loss ratio and the per-pin detail of a cycle, and the sums over the discs of a multi-disc
gear.  Pure functions over floats and numpy arrays; units N, mm, rad.

References
----------
.. [1] The paper (Prudnikov, seed 000), cited in full in :mod:`gearcalc.pins`; docs/spec/pins.md §4.6, §6.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .. import units
from ..arrays import unique_sorted
from ..quadrature import geometric_breakpoints
from .efficiency import contact_loss_power, pin_spin, sliding_speed
from .geometry import Cycloid, lever_arm, MULTIPLIER, pitch_distance

__all__ = ["cycle_breakpoints", "CycleState", "cycle_state", "cycle_loss_ratio", "state_loss_ratio", "CycleDetail",
           "cycle_detail", "crank_order", "disc_offsets", "sum_over_discs", "disc_sum_range", "disc_sum_peak"]


# Over one period the load-side phases of the pins are psi_j(t) = 2 pi (j + t)/z2, j = 0 .. z2-1,
# t in [0, 1] (t = theta/T_p in the multiplier; t = 1 - theta/T_p in the reducer, by the mirror
# relation of §4.8 identity 5).  The loaded pins are a prefix j < J(t) with J = ceil(c - t),
# c = psi* z2/(2 pi); membership is decided at the piece midpoint.

def _loaded_count(t_mid, c):
    return np.ceil(c - np.asarray(t_mid, dtype=float)).astype(np.int64)


def cycle_breakpoints(g: Cycloid, psi_star: float, psi_0: float | None) -> np.ndarray:
    r"""Breakpoints of the cycle integrand in t = theta/T_p in [0, 1]  (pins.md §6, §12.12).

    0 and 1 (entry at psi~ = 0), the exit frac(psi* z2/2 pi), the spin reversal
    frac(psi_0 z2/2 pi) when psi_0 < psi*, and two geometric gradings:

    * K1 > 0.99: toward the entry t = 0 over the whole period, down to a quarter of the boundary
      layer width (1 - K1) z2/(2 pi); the layer's tail (1 - K1)^2/psi^2 is algebraic, so the grading
      must not stop at the first breakpoint;
    * a piece where a single pin carries the load (psi* barely above 2 pi/z2): lambda ~ 1/psi there,
      so toward that piece's start, down to its own distance from the entry.

    .. math:: t \in \{0,\ 1,\ \operatorname{frac}(\psi^* z_2 / 2\pi),\ \operatorname{frac}(\psi_0 z_2 / 2\pi)\}
        \cup \text{gradings}, \qquad t = \theta / T_p, \quad T_p = \frac{2\pi}{z_2}

    Parameters
    ----------
    g : Cycloid
        The gear.
    psi_star : float
        End of the loaded arc, [rad].
    psi_0 : float or None
        Spin-reversal phase, [rad], or None.

    Returns
    -------
    t : ndarray
        The sorted breakpoints in [0, 1], [-].

    Examples
    --------
    >>> g = Cycloid.from_curtate_ratio(21, 22, 3.9, 0.75, 1.95)   # k = 1, z2 even: exit at t = 0
    >>> cycle_breakpoints(g, np.pi, None).tolist()
    [0.0, 1.0]

    References
    ----------
    .. [1] docs/spec/pins.md §6, §12.12.
    """
    c = _exit_count(g, psi_star)
    pts = [0.0, 1.0, c - math.floor(c)]
    if psi_0 is not None and psi_0 < psi_star:
        c0 = psi_0 * g.z2 / (2.0 * math.pi)
        pts.append(c0 - math.floor(c0))
    pts = unique_sorted(np.array(pts))
    extra = []
    if g.one_minus_K1 < 0.01:
        extra.append(geometric_breakpoints(0.0, 1.0, g.one_minus_K1 * g.z2 / (2.0 * math.pi)))
    a, b = pts[:-1], pts[1:]
    for lo, hi in zip(a[_loaded_count(0.5 * (a + b), c) == 1], b[_loaded_count(0.5 * (a + b), c) == 1]):
        if lo > 0.0:
            extra.append(geometric_breakpoints(lo, hi, lo))
    return unique_sorted(np.concatenate([pts, *extra]))


def _exit_count(g, psi_star):
    """The count c = psi* z2/(2 pi), exact for k = 1."""
    return g.z2 / 2.0 if g.k == 1 else psi_star * g.z2 / (2.0 * math.pi)


@dataclass
class CycleState:
    """The loaded contacts at nodes t (one disc): rows j = 0 .. J_max-1 (load-side order).

    phase [rad], loaded (bool), lever |l| [mm], rho [mm], S = sum l^2 [mm^2] per node.
    """

    t: np.ndarray
    phase: np.ndarray
    loaded: np.ndarray
    lever: np.ndarray
    rho: np.ndarray
    S: np.ndarray


def cycle_state(t, t_mid, g: Cycloid, psi_star: float) -> CycleState:
    r"""Loaded-pin geometry at nodes t of pieces with midpoints t_mid (one-sided at piece ends).

    .. math:: \tilde\psi_i(t), \quad \text{loaded: } 0 < \tilde\psi_i < \psi^* \text{ at } t_{mid}, \quad
        l_i = \frac{r_{p1} \sin\tilde\psi_i}{s(\tilde\psi_i)}, \quad \rho_i = R_p\,s(\tilde\psi_i)

    Parameters
    ----------
    t : ndarray
        Nodes, t = theta/T_p, [-].
    t_mid : ndarray
        Midpoints of their pieces, [-].
    g : Cycloid
        The gear.
    psi_star : float
        End of the loaded arc, [rad].

    Returns
    -------
    state : CycleState
        Phases [rad], loaded flags, |lever arms| [mm], pitch distances [mm] and S = sum l² [mm²] at the nodes.

    Examples
    --------
    >>> g = Cycloid.from_curtate_ratio(21, 22, 3.9, 0.75, 1.95)
    >>> st = cycle_state(np.array([0.0, 1.0]), np.array([0.5, 0.5]), g, np.pi)
    >>> st.loaded.sum(axis=0).tolist()    # k = 1: half the pins
    [11, 11]

    References
    ----------
    .. [1] docs/spec/pins.md §4.3, §4.4, §6.
    """
    t = np.asarray(t, dtype=float)
    c = _exit_count(g, psi_star)
    J = _loaded_count(t_mid, c)
    jmax = math.ceil(c) + 1
    j = np.arange(jmax)[:, None]
    phase = math.pi * ((2.0 * j + 2.0 * t[None, :]) / g.z2)
    loaded = j < J[None, :]
    lev = np.where(loaded, np.abs(lever_arm(phase, g)), 0.0)
    rho = pitch_distance(phase, g)
    S = np.sum(lev * lev, axis=0)
    return CycleState(t, phase, loaded, lev, rho, S)


def cycle_loss_ratio(t, t_mid, g: Cycloid, psi_star: float, mu_eff: float):
    r"""The loss ratio lambda at nodes t of the cycle (one-sided at piece ends) (pins.md §4.6).

    .. math:: \lambda(t) = \mu_{eff}\,\frac{\sum_{i \in L} |l_i|\,|\rho_i - R_b|}{\sum_{i \in L} l_i^2}, \qquad
        L = \text{the loaded pins of the piece with midpoint } t_{mid}

    Parameters
    ----------
    t : ndarray
        Nodes, t = theta/T_p, [-].
    t_mid : ndarray
        Midpoints of their pieces, [-].
    g : Cycloid
        The gear.
    psi_star : float
        End of the loaded arc, [rad].
    mu_eff : float
        Effective friction coefficient, [-].

    Returns
    -------
    lam : ndarray
        Loss ratio at each node, [-].

    Examples
    --------
    >>> from gearcalc.pins import loss_ratio
    >>> g = Cycloid.from_curtate_ratio(21, 22, 3.9, 0.75, 1.95)
    >>> a = cycle_loss_ratio(np.array([0.3]), np.array([0.5]), g, np.pi, 0.1)
    >>> b = loss_ratio([0.3 * 2 * np.pi / 22], g, np.pi, 0.1, MULTIPLIER)
    >>> bool(abs(a[0] - b[0]) < 1e-13)
    True

    References
    ----------
    .. [1] A. P. Prudnikov, «Потери мощности в контакте цевок и зубьев планетарной передачи типа K-H-V» (Power losses in
       pins and teeth contact area of KHV-type planetary gearing), Машиностроение (seed file 000_fe288dec6e7c72f0.txt);
       docs/spec/pins.md §4.6, §6.
    """
    return state_loss_ratio(cycle_state(t, t_mid, g, psi_star), g, mu_eff)


def state_loss_ratio(st: CycleState, g: Cycloid, mu_eff, n_discs: int = 1):
    r"""The loss ratio lambda at the nodes of a :class:`CycleState`, averaged over n_d discs (pins.md §4.6, §12.7).

    .. math::

        \lambda(t) = \mu_{eff} \frac{\sum_i |l_i| |\rho_i - R_b|}{\sum_i l_i^2},\qquad
        \lambda_{n_d}(t) = \frac{1}{n_d} \sum_{d=0}^{n_d-1} \lambda(t + \Delta_d)

    with the disc offsets Delta_d of :func:`disc_offsets` (one period = 1 in t).

    Parameters
    ----------
    st : CycleState
        the loaded contacts at nodes t (one disc).
    g : Cycloid
    mu_eff : float
        effective friction coefficient [-].
    n_discs : int
        n_d, discs in phase-shifted sets.

    Returns
    -------
    ndarray
        lambda at the nodes [-].

    Examples
    --------
    >>> g = Cycloid.from_curtate_ratio(21, 22, 3.9, 0.75, 1.95)
    >>> st = cycle_state(np.array([0.3]), np.array([0.5]), g, np.pi)
    >>> bool(state_loss_ratio(st, g, 0.1)[0] == cycle_loss_ratio(np.array([0.3]), np.array([0.5]), g, np.pi, 0.1)[0])
    True

    References
    ----------
    .. [1] Prudnikov (seed 000), cited in full in :mod:`gearcalc.pins`; pins.md §4.6, §12.7.
    """
    lam = mu_eff * np.sum(st.lever * np.abs(st.rho - g.R_b), axis=0) / st.S
    if n_discs > 1:   # all discs: the mean of the discs' shifted histories (pins.md §12.7)
        lam = sum_over_discs(st.t, lam, disc_offsets(n_discs, g.z2), 1.0) / n_discs
    return lam


@dataclass(frozen=True)
class CycleDetail:
    """The ideal level's cycle at the nodes of its final grid (:func:`cycle_detail`), crank angle ascending.

    Per node: theta [deg], loss_ratio (all discs) [-], loss (all discs) [W] or None, loaded (pins of the
    first disc).  Per loaded contact of the first disc (row-major by node, then pin): contact_theta [deg],
    pin (index of the fixed ring), phase [deg], force [N] or None, sliding_speed [m/s] or None,
    pin_speed [rpm] or None, contact_loss [W] or None.  None: the torque or the crank speed is not known.
    """

    theta: np.ndarray
    loss_ratio: np.ndarray
    loss: np.ndarray | None
    loaded: np.ndarray
    contact_theta: np.ndarray
    pin: np.ndarray
    phase: np.ndarray
    force: np.ndarray | None
    sliding_speed: np.ndarray | None
    pin_speed: np.ndarray | None
    contact_loss: np.ndarray | None


def cycle_detail(g: Cycloid, sigma: int, st: CycleState, friction, load, n_discs: int = 1,
                 denominator=None) -> CycleDetail:
    r"""Loss ratio, forces, speeds and losses at the nodes of the ideal level's cycle (pins.md §4.4-4.6, §8).

    The cycle variable t maps to crank angle theta = T_p t (multiplier; pin i = -j mod z2) or
    theta = T_p (1 - t) (reducer; pin i = j + 1 mod z2), by the mirror relation of pins.md §4.8.

    .. math::

        F_j = T_{sat} \frac{|l_j|}{\sum_i l_i^2},\quad v_j = |\omega_V| |\rho_j - R_b|,\quad
        \omega_{pin} = -\omega_V \frac{\rho_j - R_b}{R_b},\quad P_j = \mu_{eff} F_j v_j 10^{-3}

    Parameters
    ----------
    g : Cycloid
    sigma : int
        +1 reducer, -1 multiplier.
    st : CycleState
        the loaded contacts at the nodes t (:func:`cycle_state`).
    friction : :class:`~gearcalc.pins.friction.PinFriction`
        mu_eff [-] and whether the pins roll.
    load : :class:`~gearcalc.pins.operating.SatelliteLoad`
        T_sat per disc [N·mm] (None: unknown, e.g. self-locking with the torque on H) and the signed satellite
        speed omega_V [rad/s] (None: no crank speed).
    n_discs : int
        n_d.
    denominator : ndarray, optional
        D per node, F_j = T_sat |l_j|/D (the friction-consistent model, pins.md §4.9, :func:`crank_history`);
        default S = sum l^2 (friction-free forces, §4.4).

    Returns
    -------
    CycleDetail

    Examples
    --------
    >>> from gearcalc.pins import REDUCER, PinFriction, SatelliteLoad
    >>> g = Cycloid.from_curtate_ratio(21, 22, 3.9, 0.75, 1.95)
    >>> st = cycle_state(np.array([0.0, 0.5, 1.0]), np.array([0.5, 0.5, 0.5]), g, np.pi)
    >>> d = cycle_detail(g, REDUCER, st, PinFriction(0.1, 0.1, False), SatelliteLoad(1000.0, -1.0))
    >>> d.theta.tolist() == sorted(d.theta.tolist()), bool(np.all(d.force >= 0)), d.loaded.tolist()  # k = 1: half
    (True, True, [11, 11, 11])

    References
    ----------
    .. [1] Prudnikov (seed 000), cited in full in :mod:`gearcalc.pins`; pins.md §4.4-4.6, §8.
    """
    t, mu_eff, torque_sat, omega_V = st.t, friction.mu_eff, load.torque_sat, load.omega_V
    Tp_deg = 360.0 / g.z2
    if denominator is not None:     # friction-consistent forces (pins.md §4.9)
        st = CycleState(st.t, st.phase, st.loaded, st.lever, st.rho, np.asarray(denominator, dtype=float))
    lam = state_loss_ratio(st, g, mu_eff, n_discs)
    if sigma == MULTIPLIER:      # theta = T_p t, pin i = -j mod z2
        theta, pin_shift, pin_sign = t * Tp_deg, 0, -1
    else:                        # theta = T_p (1 - t), pin i = j + 1 mod z2
        theta, pin_shift, pin_sign = (1.0 - t) * Tp_deg, 1, 1
    order = crank_order(theta, sigma)
    have_P = torque_sat is not None and omega_V is not None
    loaded = st.loaded[:, order]
    jj, nn = np.nonzero(loaded.T)[1], order[np.nonzero(loaded.T)[0]]      # row-major by node, then pin
    F = torque_sat * st.lever[jj, nn] / st.S[nn] if torque_sat is not None else None
    v = sliding_speed(st.rho[jj, nn], g.R_b, omega_V) if omega_V is not None else None
    if omega_V is not None:
        spin = units.rad_s_to_rpm(pin_spin(st.rho[jj, nn], g.R_b, omega_V)) if friction.rolls else np.zeros(jj.size)
        slide = np.zeros(jj.size) if friction.rolls else v / units.MM_PER_M
    else:
        spin = slide = None
    return CycleDetail(
        theta=theta[order], loss_ratio=lam[order],
        loss=(lam * (n_discs * torque_sat * abs(omega_V) * 1e-3))[order] if have_P else None,
        loaded=st.loaded.sum(axis=0)[order], contact_theta=theta[nn], pin=(pin_sign * jj + pin_shift) % g.z2,
        phase=np.degrees(st.phase[jj, nn]), force=F, sliding_speed=slide, pin_speed=spin,
        contact_loss=contact_loss_power(F, v, mu_eff) if have_P else None)


def crank_order(theta, sigma: int):
    r"""The nodes of a cycle grid in crank-angle order (pins.md §8: the detail tables' rows).

    A repeated angle (a jump) keeps its one-sided limits in crank-angle order: the reducer's theta = T_p (1 - t)
    runs against t, so its ties go in reverse node order (the left limit in t is the right limit in theta).

    .. math:: \theta_{o_0} \le \theta_{o_1} \le \dots, \qquad \theta = T_p\,t \ \text{(multiplier)}, \quad
        \theta = T_p\,(1 - t) \ \text{(reducer)}

    Parameters
    ----------
    theta : ndarray
        The nodes' crank angles, in the order of t [deg or rad].
    sigma : int
        +1 reducer, -1 multiplier.

    Returns
    -------
    order : ndarray of int
        The node indices, crank angle ascending (a stable sort; the reducer's ties reversed).

    Examples
    --------
    >>> from gearcalc.pins import REDUCER
    >>> crank_order(np.array([2.0, 1.0, 1.0, 0.0]), REDUCER).tolist()     # t ascending: the jump's limits swap
    [3, 2, 1, 0]
    >>> crank_order(np.array([0.0, 1.0, 1.0, 2.0]), MULTIPLIER).tolist()
    [0, 1, 2, 3]

    References
    ----------
    .. [1] docs/spec/pins.md §4.8 (the mirror relation of the modes), §8 (the detail tables).
    """
    if sigma == MULTIPLIER:
        return np.argsort(theta, kind="stable")
    return theta.size - 1 - np.argsort(theta[::-1], kind="stable")


def disc_offsets(n_discs: int, z2: int) -> np.ndarray:
    r"""Shifts in t = theta/T_p of the discs' cycles, frac(d z2/n_d), d = 0 .. n_d-1  (pins.md §12.7).

    .. math:: \Delta t_d = \operatorname{frac}\!\left(\frac{d\,z_2}{n_d}\right), \qquad d = 0, \dots, n_d - 1

    Parameters
    ----------
    n_discs : int
        Number of discs n_d, [-].
    z2 : int
        Number of pins, [-].

    Returns
    -------
    shifts : ndarray
        The shifts, [-] (in units of T_p).

    Examples
    --------
    >>> disc_offsets(2, 22).tolist()
    [0.0, 0.0]

    References
    ----------
    .. [1] docs/spec/pins.md §12.7.
    """
    d = np.arange(n_discs)
    return np.mod(d * z2, n_discs) / n_discs


def sum_over_discs(x, values, shifts, period, origin: float = 0.0, zero_outside: bool = False):
    r"""Sum over discs of a sampled periodic history, sum_d v(x + shift_d), by linear interpolation.

    .. math:: V(x) = \sum_d v(x + s_d), \qquad v \text{ linear between the samples, periodic with the period}

    Parameters
    ----------
    x : sample points, non-decreasing (repeated points hold one-sided limits).
    values : samples at x.
    shifts : the discs' shifts (0 for the first) [unit of x].
    period : the period of v [unit of x]; points are wrapped into [origin, origin + period).
    origin : start of the wrapped range.
    zero_outside : v = 0 outside [x[0], x[-1]] (a pin's history off its loaded arc).

    Returns
    -------
    The summed history at x.  Linear interpolation: error O(h^2) in the sample spacing h.

    Examples
    --------
    >>> sum_over_discs(np.array([0.0, 0.5, 1.0]), np.array([0.0, 1.0, 0.0]), [0.0, 0.5], 1.0).tolist()
    [1.0, 1.0, 1.0]

    References
    ----------
    .. [1] docs/spec/pins.md §12.7.
    """
    x = np.asarray(x, dtype=float)
    values = np.asarray(values, dtype=float)
    total = np.zeros_like(values)
    fill = 0.0 if zero_outside else None
    for s in shifts:  # a handful of discs: loop over discs, vectorised over samples
        y = np.mod(x + s - origin, period) + origin
        total += np.interp(y, x, values, left=fill, right=fill)
    return total


def _one_sided(y, x, values, right: bool):
    """Linear interpolation of samples taking the one-sided limit at a jump.

    x is non-decreasing, a repeated x is a jump: the right limit (the last of the repeated samples) if ``right``,
    else the left one; clamped outside [x[0], x[-1]].
    """
    n = x.size
    i = np.clip(np.searchsorted(x, y, side="right" if right else "left"), 1, n - 1)
    x0, x1, v0, v1 = x[i - 1], x[i], values[i - 1], values[i]
    dx = x1 - x0
    with np.errstate(divide="ignore", invalid="ignore"):
        r = np.where(dx > 0.0, (y - x0) / dx, 1.0 if not right else 0.0)
    out = v0 + np.clip(r, 0.0, 1.0) * (v1 - v0)
    return np.where(y <= x[0], values[0], np.where(y >= x[-1], values[-1], out))


def disc_sum_range(x, values, shifts, period, origin: float = 0.0):
    r"""Least and greatest value over the cycle of a sampled periodic history summed over discs, jumps included.

    The sum V(x) = sum_d v(x + s_d) jumps wherever one disc's history jumps; both one-sided limits of V are taken
    at every disc's samples (the union of the shifted sample points), so neither side of a jump is lost
    (pins.md §8, §12.7: the crank-torque ripple with several discs).

    .. math:: V(x^\pm) = \sum_d v\big((x + s_d)^\pm\big), \qquad
        \min V, \ \max V \ \text{over } x \in \bigcup_d \{x_j - s_d\}, \ \pm

    Parameters
    ----------
    x : ndarray
        Sample points, non-decreasing (repeated points hold one-sided limits) [unit of x].
    values : ndarray
        Samples at x [unit of the quantity].
    shifts : array_like
        The discs' shifts (0 for the first) [unit of x].
    period : float
        The period of v [unit of x]; points are wrapped into [origin, origin + period).
    origin : float
        Start of the wrapped range [unit of x].

    Returns
    -------
    lo, hi : float
        Least and greatest value of V, NaN samples ignored (NaN if all are NaN) [unit of the quantity].

    Examples
    --------
    >>> disc_sum_range(np.array([0.0, 0.5, 0.5, 1.0]), np.array([0.0, 0.0, 1.0, 1.0]), [0.0, 0.25], 1.0)
    (0.0, 2.0)

    References
    ----------
    .. [1] docs/spec/pins.md §8, §12.7.
    """
    x = np.asarray(x, dtype=float)
    values = np.asarray(values, dtype=float)
    shifts = np.asarray(shifts, dtype=float)
    pts = np.mod((x[None, :] - shifts[:, None]).ravel() - origin, period) + origin
    left = np.zeros(pts.size)
    right = np.zeros(pts.size)
    for s in shifts:  # a handful of discs: loop over discs, vectorised over samples
        y = np.mod(pts + s - origin, period) + origin
        left += _one_sided(np.where(y == origin, origin + period, y), x, values, False)   # v(origin^-) = v(end^-)
        right += _one_sided(y, x, values, True)
    both = np.concatenate((left, right))
    if np.isnan(both).all():
        return math.nan, math.nan
    return float(np.nanmin(both)), float(np.nanmax(both))


def disc_sum_peak(phase, values, n_d: int):
    r"""Peak over the cycle and the pins of a per-contact quantity summed over n_d discs, and its phase.

    The discs are 2 pi/n_d apart: a pin's history at phase psi is sum_d v(psi - 2 pi d/n_d) (pins.md
    §12.7), interpolated linearly between the samples (error O(h^2)).

    .. math:: V(\psi) = \sum_{d=0}^{n_d - 1} v\!\left(\psi - \frac{2\pi d}{n_d}\right), \qquad
        \text{peak} = \max_\psi V(\psi)

    Parameters
    ----------
    phase : load-side phases of the loaded contacts of the first disc [rad], shape (n,).
    values : the quantity at those contacts, shape (n,).
    n_d : number of discs.

    Returns
    -------
    (peak, phase of the peak [rad]).

    Examples
    --------
    >>> disc_sum_peak(np.array([0.0, 1.0, 2.0]), np.array([0.0, 1.0, 0.0]), 1)
    (1.0, 1.0)

    References
    ----------
    .. [1] docs/spec/pins.md §8, §12.7.
    """
    x, val = np.asarray(phase, dtype=float), np.asarray(values, dtype=float)
    order = np.argsort(x, kind="stable")
    x, val = x[order], val[order]
    shifts = -2.0 * np.pi * np.arange(n_d) / n_d
    pts = unique_sorted(np.concatenate([np.mod(x - s, 2.0 * np.pi) for s in shifts]))
    tot = np.zeros_like(pts)
    for s in shifts:  # a handful of discs; vectorised over the samples
        tot += np.interp(np.mod(pts + s, 2.0 * np.pi), x, val, left=0.0, right=0.0)
    i = int(np.argmax(tot))
    return float(tot[i]), float(pts[i])
