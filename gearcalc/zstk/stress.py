"""Loads and Hertz stresses of every roller of a placed chain (spec zstk.md §2, §5).

References
----------
The seed paper by Merko et al. (seed 003), cited in full in :mod:`gearcalc.zstk`; docs/spec/zstk.md.
"""
from __future__ import annotations

__all__ = ['Materials', 'State', 'evaluate', 'critical', 'solve_placements', 'Summary', 'summarise', 'safety_factor',
           'Contacts', 'roller_contacts', 'roller_approach', 'worst_width_ratio', 'separator_forces',
           'LOADED_RTOL', 'ROUNDOFF_RTOL', 'critical_shear', 'roller_field']

from dataclasses import dataclass

import numpy as np

from .. import hertz
from .chain import Chain, close_chain, close_chains, roller_angles, step_chain  # noqa: F401 (the examples)
from .geometry import broadcast, centre_distance, reduced_radii, roller_radius, wrap_angle
from .loads import LoadSolution, _per_roller, roller_stiffness, solve_loads



# ----------------------------------------------------------------------------- evaluation
@dataclass
class Materials:
    """Contact moduli and the roller constant of a design.

    e_star_inner, e_star_outer : E*_B, E*_H [MPa]; length : l [mm]; stiffness : c_L;
    poisson_inner, poisson_outer : the smaller Poisson's ratio of the two bodies of the inner / outer
    contact [-] (the body in which the maximum shear is largest, :func:`gearcalc.hertz.tresca_shear_ratio`).
    Floats for one design, arrays of shape (G,) for stacked designs.
    """

    e_star_inner: float
    e_star_outer: float
    length: float
    stiffness: float
    poisson_inner: float = 0.3
    poisson_outer: float = 0.3

    @classmethod
    def from_elastic(cls, length, roller_e, roller_nu, inner_e, inner_nu, outer_e, outer_nu):
        """The materials from the roller length [mm] and the elastic constants E [MPa] and nu [-] of each body."""
        eb = hertz.contact_modulus(roller_e, roller_nu, inner_e, inner_nu)
        eh = hertz.contact_modulus(roller_e, roller_nu, outer_e, outer_nu)
        stiffness = roller_stiffness(length, eb, eh)
        nu_b, nu_h = np.minimum(roller_nu, inner_nu), np.minimum(roller_nu, outer_nu)
        if np.ndim(stiffness) == 0:
            return cls(float(eb), float(eh), float(length), float(stiffness), float(nu_b), float(nu_h))
        return cls(*(broadcast(np.asarray(x, dtype=float), np.shape(stiffness)) for x in
                     (eb, eh, length, stiffness, nu_b, nu_h)))


@dataclass
class State:
    """Everything about the rollers of one or many configurations (arrays (..., N) or (...))."""

    theta: np.ndarray
    radius: np.ndarray
    beta: np.ndarray
    normal_angle: np.ndarray
    force_inner: np.ndarray
    force_outer: np.ndarray
    rho_inner: np.ndarray
    rho_outer: np.ndarray
    sigma_inner: np.ndarray
    sigma_outer: np.ndarray
    gamma: np.ndarray
    loads: LoadSolution

    @property
    def psi(self) -> np.ndarray:
        """Angle from the load direction u to each inner normal n_Bi, in (-pi, pi] [rad]."""
        return wrap_angle(self.normal_angle - self.gamma[..., None])


def evaluate(chain: Chain, mats: Materials, theta, gamma, load, clearance=0.0, symmetric=False,
             fixed_direction=False) -> State:
    r"""Loads and Hertz stresses of every roller for roller angles theta and load directions gamma.

    .. math:: F_{iH} = F_{iB} \cos\beta_i, \qquad \sigma_{i(B,H)} = \sqrt{\frac{F_{i(B,H)}
              E^*_{(B,H)}}{\pi\, l\, \rho_{i(B,H)}}}

    F_iH = F_iB cos beta_i (separator equilibrium); sigma = sqrt(F E*/(pi l rho)), the paper's
    eq. (3) (= Johnson's p0).

    Parameters
    ----------
    chain : the closed chain; mats : materials (floats, or arrays broadcastable to (...) for stacked
        designs of the same N, e.g. shape (G,) with theta of shape (G, N)).
    theta : roller angles [rad], (..., N); gamma : load directions [rad], broadcastable to (...).
    load : Q [N]; clearance : s [mm] (floats or arrays broadcastable to (...));
    symmetric, fixed_direction : see :func:`solve_loads`.

    Returns
    -------
    State

    Examples
    --------
    >>> ch = close_chain(100.0, 50.0, 6.0, 6.0, 8)
    >>> m = Materials.from_elastic(20.0, 2.1e5, 0.3, 2.1e5, 0.3, 2.1e5, 0.3)
    >>> st = evaluate(ch, m, roller_angles(0.0, 8, ch.limiting_ratio), 0.0, 1e4, symmetric=True)
    >>> bool(st.sigma_inner[0] > st.sigma_outer[0] > 0)
    True

    References
    ----------
    Merko M.A. et al., «Анализ нормальных напряжений на площадках контакта звеньев механизмов с ЗСТК ...» (seed
    003_2d1da402cb0b8488.txt; no journal given; see :mod:`gearcalc.zstk`), eqs. (3)-(7); Johnson K.L., Contact
    Mechanics, Cambridge University Press, 1985, §4.2; docs/spec/zstk.md §2, §5.
    """
    # per-design quantities as (..., 1): they broadcast against the rollers (floats give shape (1,))
    r_h, r_b, e = (_per_roller(x) for x in (chain.outer_radius, chain.inner_radius, chain.eccentricity))
    theta = np.asarray(theta, dtype=float)
    gamma = np.asarray(gamma, dtype=float)
    shape = np.broadcast_shapes(theta.shape[:-1], gamma.shape, r_h.shape[:-1], np.shape(load),
                                np.shape(clearance), np.shape(mats.stiffness))
    full = shape + theta.shape[-1:]
    # the geometry depends on the phase only: computed on theta's own shape, then broadcast (views)
    r = roller_radius(theta, r_h, r_b, e)
    h = centre_distance(theta, r_h, r_b, e)
    beta_s = np.arctan2(e * np.sin(theta), h - e * np.cos(theta))
    nb = theta + beta_s
    rho_b, rho_h = reduced_radii(r, h, r_b, r_h)
    gamma = broadcast(gamma, shape)
    sol = solve_loads(broadcast(nb, full), gamma, load, mats.stiffness, clearance, symmetric,
                      fixed_direction)
    f_b = sol.force
    f_h = f_b * np.cos(beta_s)
    length = _per_roller(mats.length)
    sig_b = hertz.peak_pressure(f_b, length, rho_b, _per_roller(mats.e_star_inner))
    sig_h = hertz.peak_pressure(f_h, length, rho_h, _per_roller(mats.e_star_outer))

    def b(a):
        return broadcast(a, full)

    return State(b(theta), b(r), b(np.abs(beta_s)), b(nb), f_b, f_h, b(rho_b), b(rho_h), sig_b, sig_h,
                 np.asarray(gamma), sol)


def critical(state: State):
    r"""Location of the largest stress of each configuration.

    Returns (sigma_max, roller index, contact 0 = inner / 1 = outer), arrays of shape (...);
    ties (mirror rollers) go to the lowest index, inner before outer.

    .. math:: \sigma_{max} = \max_{i,\ c \in \{B, H\}} \sigma_{i,c}

    Parameters
    ----------
    state : State
        The rollers of one or many configurations (arrays (..., N)).

    Returns
    -------
    sigma_max : ndarray
        The largest stress, [MPa], shape (...).
    roller : ndarray of int
        Its roller, shape (...).
    contact : ndarray of int
        Its contact, 0 = inner, 1 = outer, shape (...).

    Examples
    --------
    >>> ch = close_chain(100.0, 50.0, 6.0, 6.0, 8)
    >>> m = Materials.from_elastic(20.0, 2.1e5, 0.3, 2.1e5, 0.3, 2.1e5, 0.3)
    >>> st = evaluate(ch, m, roller_angles(np.zeros(1), 8, ch.limiting_ratio), np.zeros(1), 1e4, symmetric=True)
    >>> s, k, c = critical(st)
    >>> round(float(s[0]), 3), int(k[0]), int(c[0])   # the inner contact of roller 0 on the load line
    (748.936, 0, 0)

    References
    ----------
    .. [1] M. A. Merko, M. V. Mesnyankin, A. V. Kolotov, A. E. Mityaev, M. V. Savitskaya, A. M. Merko, S. A. Yurov,
       «Анализ нормальных напряжений на площадках контакта звеньев механизмов с ЗСТК при ведущем внутреннем кольце и
       вводе поправки по радиусу дорожки качения наружного кольца», Siberian Federal University, UDC 621.838.2 (seed
       file 003_2d1da402cb0b8488.txt; no journal or year given); its conclusion (the inner contact of the smallest
       roller on the load line); docs/spec/zstk.md
       §5.4, §10.
    """
    both = np.stack([state.sigma_inner, state.sigma_outer], axis=-2)  # (..., 2, N)
    flat = both.reshape(both.shape[:-2] + (-1,))
    smax = np.max(flat, axis=-1)
    near = flat >= smax[..., None] * (1.0 - 1e-12)
    n = state.sigma_inner.shape[-1]
    order = np.tile(np.arange(n), 2) * 2 + np.repeat([0, 1], n)  # roller-major, inner first
    key = np.where(near, order, np.iinfo(np.int64).max)
    k = np.argmin(key, axis=-1)
    return smax, k % n, k // n




def solve_placements(chain: Chain, mats: Materials, phase, q, gamma, load, clearance, scheme_symmetric,
                     fixed_direction=False, stepping=False):
    r"""Place G chains of the same N and solve their loads and stresses (stacked designs, spec §4-§5).

    Mirror-symmetric configurations (spec §5.1), solved in closed form: a symmetric scheme with the load
    on the line of centres (|sin gamma| < 1e-15), or e = 0 with the load line through a roller or a
    mid-gap,

    .. math:: (\gamma - \theta_0) / (\pi / N) \in \mathbb{Z} \quad (\pm 10^{-12})

    Parameters
    ----------
    chain, mats : Chain, Materials
        Arrays of shape (G,), one N for all.
    phase : array_like, shape (G,)
        Chain phase phi_0 [rad].
    q : array_like, shape (G,)
        Limiting-point ratio of each chain [-].
    gamma, load, clearance : array_like, shape (G,)
        Load direction [rad], Q [N], s [mm].
    scheme_symmetric : array_like of bool, shape (G,)
        The placement is a symmetric scheme (A-D).
    fixed_direction : bool
        The ``fixed-direction`` level.
    stepping : bool
        Also close each chain by explicit stepping (the reference level's cross-check).

    Returns
    -------
    (state, symmetric, stepping residual [mm] or None)

    Examples
    --------
    >>> ch = close_chains(np.array([100.0]), 50.0, 6.0, 6.0, np.array([8]))
    >>> m = Materials.from_elastic(20.0, 2.1e5, 0.3, 2.1e5, 0.3, 2.1e5, 0.3)
    >>> st, sym, _ = solve_placements(ch, m, np.zeros(1), ch.limiting_ratio, np.zeros(1), np.array([1e4]),
    ...                               np.zeros(1), np.array([True]))
    >>> round(float(st.sigma_inner[0, 0]), 6), sym.tolist()
    (748.935693, [True])

    References
    ----------
    Merko et al. (see the module), eqs. (3)-(7); docs/spec/zstk.md §4.2, §5.1, §8.
    """
    n = int(np.ravel(chain.n)[0])
    theta = roller_angles(phase, n, q)
    theta0 = theta[:, 0]
    k = (gamma - theta0) / (np.pi / n)
    symmetric = ((scheme_symmetric & (np.abs(np.sin(gamma)) < 1e-15))
                 | ((chain.eccentricity == 0.0) & (np.abs(k - np.round(k)) < 1e-12)))
    state = evaluate(chain, mats, theta, gamma, load, clearance, symmetric=symmetric, fixed_direction=fixed_direction)
    residual = None
    if stepping:
        _, residual = step_chain(theta0, n, chain.outer_radius, chain.inner_radius, chain.eccentricity, chain.gap)
    return state, symmetric, residual


# ----------------------------------------------------------------------------- summary quantities
LOADED_RTOL = 1e-12
"""A roller counts as loaded when F_iB > LOADED_RTOL · max_j F_jB (spec §10): a roller whose normal is
exactly perpendicular to the load carries ~1e-18 Q of round-off, not a load."""
ROUNDOFF_RTOL = 1e-12
"""Round-off floor of sigma_max_err_MPa, relative to sigma_max (spec §8: the closed-form parts are accurate
to about 1e-12 relative; estimates of 0 or 4 eps fell below the actual difference to an independent solver)."""


def roller_field(rollers, name):
    r"""A per-roller quantity of a state or of envelope rows, arrays (G, N).

    A per-roller quantity (``"theta"``, ``"force_inner"``, ...) of a :class:`State` or of the per-contact envelope
    rows of :func:`gearcalc.zstk.roller_envelope` (a mapping), arrays (G, N).

    .. math:: x_{g,i} = \text{rollers}[\text{name}]_{g,i}

    Parameters
    ----------
    rollers : State or Mapping
        A state or the per-contact envelope rows.
    name : str
        The quantity's name.

    Returns
    -------
    values : ndarray
        The quantity, in its own unit, arrays (G, N).

    Examples
    --------
    >>> roller_field({"beta": 0.5}, "beta")
    0.5

    References
    ----------
    .. [1] docs/spec/zstk.md §10 (per-roller output).
    """
    return rollers[name] if isinstance(rollers, dict) else getattr(rollers, name)


def separator_forces(force_inner, beta):
    r"""Force of the separator on each roller (spec §5 item 2).

    The tangential reaction that keeps the roller in place, perpendicular to O_H P_i, [N] (>= 0; zero on the line of
    centres and when e = 0).

    .. math:: F_{iS} = F_{iB} \sin\beta_i

    Roller equilibrium along n_Hi gives F_iH = F_iB cos beta_i; across it the separator balances
    F_iB sin beta_i (the normals n_Bi and n_Hi differ by beta_i).

    Parameters
    ----------
    force_inner : array_like
        F_iB [N].
    beta : array_like
        Angle between the contact normals [rad].

    Returns
    -------
    F_iS [N], the broadcast shape.

    Examples
    --------
    >>> float(separator_forces(1000.0, np.pi / 6))
    499.99999999999994

    References
    ----------
    docs/spec/zstk.md §5 (item 2, separator), §10.
    """
    return np.asarray(force_inner, dtype=float) * np.sin(np.abs(beta))


@dataclass
class Summary:
    """The summary quantities of G configurations (arrays of shape (G,)), from :func:`summarise`.

    sigma_max [MPa], roller (index), contact (0 inner, 1 outer), sigma_err (error estimate [MPa]),
    radius and theta of the critical roller [mm, rad], solver_residual (|sum F n - Q u|/(Q + sum F);
    the component along u for the fixed-direction level), transverse_residual (|transverse force|/Q),
    converged, approach (|delta| [mm]) along approach_direction [rad], loaded (rollers with
    F_iB > :data:`LOADED_RTOL` · max F_jB).
    """

    sigma_max: np.ndarray
    roller: np.ndarray
    contact: np.ndarray
    sigma_err: np.ndarray
    radius: np.ndarray
    theta: np.ndarray
    solver_residual: np.ndarray
    transverse_residual: np.ndarray
    converged: np.ndarray
    approach: np.ndarray
    approach_direction: np.ndarray
    loaded: np.ndarray


def summarise(state: State, load, clearance, symmetric, fixed_direction=False, sweep_value=None, sweep_err=None,
              roundoff=ROUNDOFF_RTOL) -> Summary:
    r"""The largest stress, where it occurs, its error estimate and the solver's residuals (spec §8, §10).

    .. math:: \varepsilon_\sigma = \max\left(\varepsilon_{sweep} + \tfrac12 \sigma_{max}\, |r| / F_{crit},\;
              \epsilon_{ro}\, \sigma_{max}\right)

    (sigma ∝ sqrt(F): a relative load error r/F moves sigma by half as much); the solver term is zero
    for the closed form (a mirror-symmetric configuration without clearance).  The estimate is at
    least ``roundoff`` |sigma_max| (the round-off of the closed-form parts, about 1e-12 relative: estimates
    below it fell below the actual difference to an independent solver).

    Parameters
    ----------
    state : State
        G solved configurations (arrays (G, N)).
    load, clearance : array_like, shape (G,)
        Q [N], s [mm].
    symmetric : array_like of bool, shape (G,)
        Mirror-symmetric configurations (solved in closed form).
    fixed_direction : bool
        The ``fixed-direction`` level (its residual is the component along u).
    sweep_value : array_like or None
        The maximum found by a direction sweep [MPa] (used when above the state's own).
    sweep_err : array_like or None
        The sweeps' error estimate [MPa]; None for a single placement.
    roundoff : float
        Floor of the estimate, relative to |sigma_max| (:data:`ROUNDOFF_RTOL`).

    Returns
    -------
    Summary

    Examples
    --------
    >>> ch = close_chain(100.0, 50.0, 6.0, 6.0, 8)
    >>> m = Materials.from_elastic(20.0, 2.1e5, 0.3, 2.1e5, 0.3, 2.1e5, 0.3)
    >>> st = evaluate(ch, m, roller_angles(np.zeros(1), 8, ch.limiting_ratio), np.zeros(1), 1e4, symmetric=True)
    >>> s = summarise(st, np.array([1e4]), np.zeros(1), np.array([True]))
    >>> floor = bool(s.sigma_err[0] == 1e-12 * s.sigma_max[0])
    >>> round(float(s.sigma_max[0]), 6), int(s.roller[0]), int(s.contact[0]), floor
    (748.935693, 0, 0, True)

    References
    ----------
    Merko et al. (see the module), eq. (3); docs/spec/zstk.md §8 (accuracy), §10 (output), §11.1, §11.3.
    """
    size = state.sigma_inner.shape[0]
    smax, i_crit, contact = critical(state)
    if sweep_value is not None:
        smax = np.where(sweep_value > smax, sweep_value, smax)
    sol = state.loads
    shape = (size,)
    residual, transverse = broadcast(sol.residual, shape), broadcast(sol.transverse, shape)
    converged = broadcast(sol.converged, shape)
    f_sum = np.sum(sol.force, axis=-1)
    solver_residual = residual / (load + f_sum)
    transverse_residual = transverse / load
    if fixed_direction:
        along = np.sqrt(np.maximum(residual ** 2 - transverse ** 2, 0.0))
        solver_residual = along / (load + f_sum)

    def at_crit(a):
        return np.take_along_axis(np.asarray(a), i_crit[:, None], axis=-1)[:, 0]

    f_crit = np.where(contact == 0, at_crit(state.force_inner), at_crit(state.force_outer))
    closed_form = symmetric & (clearance == 0.0) & (sweep_err is None)
    resid_abs = residual if not fixed_direction else solver_residual * (load + f_sum)
    with np.errstate(divide="ignore", invalid="ignore"):
        err_solver = np.where(closed_form | ~(f_crit > 0), 0.0, 0.5 * smax * resid_abs / f_crit)
    sigma_err = np.maximum((0.0 if sweep_err is None else sweep_err) + err_solver, roundoff * np.abs(smax))
    # the displacement (spec §11.3): |delta| along alpha + 180 degrees when delta < 0
    delta = broadcast(sol.approach, shape)
    alpha = broadcast(sol.alpha, shape)
    neg = delta < 0
    delta, alpha = np.where(neg, -delta, delta), np.where(neg, alpha + np.pi, alpha)
    return Summary(smax, i_crit, contact, sigma_err, at_crit(state.radius), at_crit(state.theta), solver_residual,
                   transverse_residual, converged, delta, alpha, np.count_nonzero(
                       state.force_inner > LOADED_RTOL * np.max(state.force_inner, axis=-1, keepdims=True), axis=-1))


def critical_shear(state: State, summary: Summary, mats: Materials):
    r"""Maximum (Tresca) subsurface shear at the critical contact of each configuration, and its depth (spec §2).

    .. math:: \tau_{max} = k_\tau(\nu)\, \sigma_{max}, \qquad z = k_z(\nu)\, b, \quad b = 2 \sigma_{max} \rho / E^*

    (b = sqrt(4 F rho/(pi l E*)) with F = pi l rho sigma²/E*); nu, rho and E* of the critical roller's
    critical contact; k_tau, k_z from :func:`gearcalc.hertz.tresca_shear_ratio`.

    Parameters
    ----------
    state : State
        G configurations (arrays (G, N)).
    summary : Summary
        Their :func:`summarise` (sigma_max, roller, contact).
    mats : Materials
        Floats or arrays (G,).

    Returns
    -------
    (tau_max [MPa], depth [mm]), arrays (G,).

    Examples
    --------
    >>> ch = close_chain(100.0, 50.0, 6.0, 6.0, 8)
    >>> m = Materials.from_elastic(20.0, 2.1e5, 0.3, 2.1e5, 0.3, 2.1e5, 0.3)
    >>> st = evaluate(ch, m, roller_angles(np.zeros(1), 8, ch.limiting_ratio), np.zeros(1), 1e4, symmetric=True)
    >>> tau, z = critical_shear(st, summarise(st, np.array([1e4]), np.zeros(1), np.array([True])), m)
    >>> round(float(tau[0]), 4), round(float(z[0]), 6)
    (224.8927, 0.162431)

    References
    ----------
    Johnson K.L., Contact Mechanics, 1985, §2.8, §4.2; docs/spec/zstk.md §2, §10.
    """
    size = state.sigma_inner.shape[0]
    inner = summary.contact == 0
    i = summary.roller[:, None]
    rho = np.where(inner, np.take_along_axis(state.rho_inner, i, -1)[:, 0],
                   np.take_along_axis(state.rho_outer, i, -1)[:, 0])
    e_star = np.where(inner, broadcast(mats.e_star_inner, (size,)), broadcast(mats.e_star_outer, (size,)))
    nu = np.where(inner, broadcast(mats.poisson_inner, (size,)), broadcast(mats.poisson_outer, (size,)))
    k_tau, k_z = hertz.tresca_shear_ratio(nu)
    return k_tau * summary.sigma_max, k_z * 2.0 * summary.sigma_max * rho / e_star


def safety_factor(sigma_max, allowable):
    r"""Static safety factor of the contact stress, NaN where sigma_max <= 0 (no loaded contact).

    .. math:: S = [\sigma_H] / \sigma_{max}

    Parameters
    ----------
    sigma_max, allowable : float or array_like
        Largest contact stress and the allowable contact stress [MPa].

    Returns
    -------
    S [-]

    Examples
    --------
    >>> safety_factor(np.array([748.935693220922, 0.0]), 4000.0).tolist()
    [5.340912492496302, nan]

    References
    ----------
    docs/spec/zstk.md §10 (strength check; ISO 76 for the default 4000 MPa).
    """
    smax = np.asarray(sigma_max, dtype=float)
    with np.errstate(divide="ignore"):
        return np.where(smax > 0, allowable / np.where(smax > 0, smax, 1.0), np.nan)


@dataclass
class Contacts:
    """Per-roller contact quantities (arrays (G, N)) of the inner (B) and outer (H) contacts.

    Force [N], peak stress [MPa], reduced radius [mm], Hertz semi-width b [mm], maximum (Tresca) subsurface shear
    [MPa] and its depth below the contact centre [mm].
    """

    force_inner: np.ndarray
    force_outer: np.ndarray
    sigma_inner: np.ndarray
    sigma_outer: np.ndarray
    rho_inner: np.ndarray
    rho_outer: np.ndarray
    width_inner: np.ndarray
    width_outer: np.ndarray
    shear_inner: np.ndarray
    shear_outer: np.ndarray
    shear_depth_inner: np.ndarray = None
    shear_depth_outer: np.ndarray = None


def roller_contacts(inner, outer, mats: Materials) -> Contacts:
    r"""Hertz semi-widths and maximum subsurface shear of every roller's two contacts (spec §2).

    .. math:: b = \sqrt{4 F \rho / (\pi l E^*)} = 2F/(\pi l \sigma), \qquad \tau_{max} = k_\tau(\nu)\,\sigma
              \text{ at depth } z = k_z(\nu)\, b

    k_tau, k_z: the Tresca maximum along the contact axis in plane strain
    (:func:`gearcalc.hertz.tresca_shear_ratio`), for the smaller Poisson's ratio of the contact's two
    bodies: 0.3003 and 0.7862 for nu >= 0.2423, larger and shallower below it.

    Parameters
    ----------
    inner, outer : State or mapping
        The roller quantities (``force_inner``, ``sigma_inner``, ``rho_inner`` of ``inner``, the
        ``*_outer`` ones of ``outer``), arrays (G, N); the same State twice for one placement, the
        per-contact envelope rows of :func:`gearcalc.zstk.roller_envelope` otherwise.
    mats : Materials
        Floats or arrays (G,).

    Returns
    -------
    Contacts

    Examples
    --------
    >>> ch = close_chain(100.0, 50.0, 6.0, 6.0, 8)
    >>> m = Materials.from_elastic(20.0, 2.1e5, 0.3, 2.1e5, 0.3, 2.1e5, 0.3)
    >>> st = evaluate(ch, m, roller_angles(np.zeros(1), 8, ch.limiting_ratio), np.zeros(1), 1e4, symmetric=True)
    >>> c = roller_contacts(st, st, m)
    >>> round(float(c.width_inner[0, 0]), 6), round(float(c.shear_inner[0, 0] / c.sigma_inner[0, 0]), 4)
    (0.206616, 0.3003)
    >>> round(float(c.shear_depth_inner[0, 0] / c.width_inner[0, 0]), 6)
    0.786151

    References
    ----------
    Merko et al. (see the module), eqs. (3)-(5); Johnson K.L., Contact Mechanics, 1985, §4.2, §2.8;
    docs/spec/zstk.md §2.
    """
    get = roller_field
    length, e_b, e_h, nu_b, nu_h = (np.reshape(np.asarray(x, dtype=float), (-1, 1)) for x in
                                    (mats.length, mats.e_star_inner, mats.e_star_outer, mats.poisson_inner,
                                     mats.poisson_outer))
    f_b, f_h = get(inner, "force_inner"), get(outer, "force_outer")
    s_b, s_h = get(inner, "sigma_inner"), get(outer, "sigma_outer")
    rho_b, rho_h = get(inner, "rho_inner"), get(outer, "rho_outer")
    b_b = hertz.semi_width(f_b, length, rho_b, e_b)
    b_h = hertz.semi_width(f_h, length, rho_h, e_h)
    (k_b, z_b), (k_h, z_h) = hertz.tresca_shear_ratio(nu_b), hertz.tresca_shear_ratio(nu_h)
    return Contacts(f_b, f_h, s_b, s_h, rho_b, rho_h, b_b, b_h, k_b * s_b, k_h * s_h, z_b * b_b, z_h * b_h)


def roller_approach(state: State, clearance):
    r"""Elastic approach of each roller's contacts (spec §5.2).

    The displacement's component along its inner normal less half the clearance, [mm], arrays (G, N); <= 0 for an
    unloaded roller.

    .. math:: \delta_i = \delta \cos(\theta_{n_{Bi}} - \alpha) - s/2

    Parameters
    ----------
    state : State
        The rollers of G configurations.
    clearance : ndarray
        Radial clearance s, [mm], shape (G,).

    Returns
    -------
    delta : ndarray
        Approach δ_i, [mm], arrays (G, N).

    Examples
    --------
    >>> ch = close_chain(100.0, 50.0, 6.0, 6.0, 8)
    >>> m = Materials.from_elastic(20.0, 2.1e5, 0.3, 2.1e5, 0.3, 2.1e5, 0.3)
    >>> st = evaluate(ch, m, roller_angles(np.zeros(1), 8, ch.limiting_ratio), np.zeros(1), 1e4, symmetric=True)
    >>> round(float(roller_approach(st, np.zeros(1))[0, 0] * 1e3), 6)    # um, = approach_um of the example
    15.036653

    References
    ----------
    docs/spec/zstk.md §5.
    """
    sol = state.loads
    shape = (state.sigma_inner.shape[0],)
    return (broadcast(sol.approach, shape)[:, None] * np.cos(state.normal_angle - broadcast(
        sol.alpha, shape)[:, None]) - 0.5 * np.asarray(clearance, dtype=float)[:, None])


def worst_width_ratio(contacts: Contacts, limit):
    r"""The largest b/rho of a loaded contact above ``limit`` per configuration.

    The largest b/rho of a loaded contact above ``limit`` per configuration, -inf where none is (Hertz's
    small-contact assumption, spec §9).

    .. math:: \max_{i,\ c:\ F_{i,c} > 0,\ b/\rho > \text{limit}} \frac{b_{i,c}}{\rho_{i,c}}

    Parameters
    ----------
    contacts : Contacts
        Per-roller contact quantities (arrays (G, N)).
    limit : float
        The b/rho above which a contact is reported, [-].

    Returns
    -------
    ratio : ndarray
        The largest b/rho, [-], -inf where none exceeds the limit, shape (G,).

    Examples
    --------
    >>> ch = close_chain(100.0, 50.0, 6.0, 6.0, 8)
    >>> m = Materials.from_elastic(20.0, 2.1e5, 0.3, 2.1e5, 0.3, 2.1e5, 0.3)
    >>> st = evaluate(ch, m, roller_angles(np.zeros(1), 8, ch.limiting_ratio), np.zeros(1), 1e4, symmetric=True)
    >>> worst_width_ratio(roller_contacts(st, st, m), 0.1).tolist()
    [-inf]

    References
    ----------
    .. [1] K. L. Johnson, Contact Mechanics, Cambridge University Press, 1985, §4.2 (the half-space assumption
       b << rho); docs/spec/zstk.md §9.
    """
    worst = np.full(contacts.sigma_inner.shape[0], -np.inf)
    for f, b, rho in ((contacts.force_inner, contacts.width_inner, contacts.rho_inner),
                      (contacts.force_outer, contacts.width_outer, contacts.rho_outer)):
        bad = (f > 0) & (b > limit * rho)
        worst = np.maximum(worst, np.max(np.where(bad, b / rho, -np.inf), axis=-1))
    return worst
