"""The outputs of solved ``zstk`` designs: strength check, allowable load, shear, separator force, roller detail.

Pure functions over a :class:`gearcalc.zstk.solve.Stack` (G designs of one roller count, arrays (G,) and
(G, N)); the field names and texts are :mod:`gearcalc.zstk.report`'s.

References
----------
The seed paper by Merko et al. (seed 003), cited in full in :mod:`gearcalc.zstk`; docs/spec/zstk.md §2, §5, §10.
"""
from __future__ import annotations

__all__ = ["Outputs", "stack_outputs", "RollerDetail", "roller_detail", "Margins", "margins"]

from dataclasses import dataclass

import numpy as np

from .capacity import AllowableLoad, allowable_load
from .chain import largest_admissible_ns
from .geometry import broadcast, extreme_roller_radii
from .stress import (Contacts, Summary, critical_shear, roller_approach, roller_contacts, roller_field, safety_factor,
                     separator_forces, summarise, worst_width_ratio)


@dataclass(frozen=True)
class Outputs:
    """The summary quantities of G stacked designs (arrays (G,) unless said).

    summary : :func:`gearcalc.zstk.summarise`; capacity : the allowable radial load; shear, shear_depth :
    tau_max [MPa] at the critical contact and its depth [mm]; separator : F_S of every roller [N], (G, N);
    passed : sigma_max <= [sigma_H]; safety : [sigma_H]/sigma_max (NaN where sigma_max <= 0); r_min, r_max :
    the extreme roller radii [mm]; admissible_max : the largest admissible N of each design (a list); margins :
    the design checks as margins (:func:`margins`).
    """

    summary: Summary
    capacity: AllowableLoad
    shear: np.ndarray
    shear_depth: np.ndarray
    separator: np.ndarray
    passed: np.ndarray
    safety: np.ndarray
    r_min: np.ndarray
    r_max: np.ndarray
    admissible_max: list
    margins: "Margins"


def stack_outputs(stack, fixed_direction=False, sweep_value=None, sweep_err=None, inner=None,
                  capacity=None) -> Outputs:
    r"""The summary quantities of a solved stack (spec §10).

    sigma_max and its error, the strength check, the allowable radial load, the maximum shear, the separator forces.

    .. math:: S = [\sigma_H] / \sigma_{max}, \qquad F_{iS} = F_{iB} \sin\beta_i, \qquad
              r_{min,max} = (R_H - R_B \mp e)/2

    Parameters
    ----------
    stack : :class:`gearcalc.zstk.solve.Stack`
        G solved designs.
    fixed_direction : bool
        The ``fixed-direction`` level.
    sweep_value, sweep_err : array_like, shape (G,), or None
        A sweeping design's maximum and error estimate [MPa] (:func:`gearcalc.zstk.summarise`).
    inner : mapping or None
        A direction envelope's rows of the inner contacts (their separator forces), else the stack's state.
    capacity : AllowableLoad or None
        A sweeping design's allowable load; None: :func:`gearcalc.zstk.allowable_load` of the stack.

    Returns
    -------
    Outputs

    Examples
    --------
    >>> from gearcalc.zstk.solve import Designs, prepare, solve_stack
    >>> d = Designs(100.0, 50.0, 6.0, 6.0, 20.0, "auto", "outer", "A", True, 1e4, 0.0, 0.0, 2.1e5, 0.3, 2.1e5,
    ...             0.3, None, None, None, None, None)
    >>> (_, stack), = solve_stack(prepare(d, 1, 2000, 4000.0), [0])
    >>> o = stack_outputs(stack)        # the worked example, zstk.md §6: sigma_max = 748.94 MPa
    >>> round(float(o.summary.sigma_max[0]), 2), round(float(o.safety[0]), 4), o.admissible_max
    (748.94, 5.3409, [31])
    >>> round(float(o.r_min[0]), 4)     # (R_H - R_B - e)/2 with the corrected R_H = 102.6969 mm
    23.3485

    References
    ----------
    Merko et al. (see :mod:`gearcalc.zstk`), eq. (3); docs/spec/zstk.md §3.1, §5 (item 2), §5.4, §10.
    """
    st, chain = stack.state, stack.chain
    sm = summarise(st, stack.load, stack.clearance, stack.symmetric, fixed_direction, sweep_value, sweep_err)
    size = st.radius.shape[0]
    if capacity is None:
        capacity = allowable_load(chain, stack.mats, st.theta, stack.gamma, stack.load, stack.clearance, sm.sigma_max,
                                  sm.sigma_err, stack.allowable, stack.symmetric, fixed_direction)
    tau, depth = critical_shear(st, sm, stack.mats)
    rows = st if inner is None else inner
    separator = separator_forces(roller_field(rows, "force_inner"), roller_field(rows, "beta"))
    r_min, r_max = extreme_roller_radii(chain.outer_radius, chain.inner_radius, chain.eccentricity)
    admissible = largest_admissible_ns(broadcast(chain.n_limit, (size,)), broadcast(chain.correct, (size,)))
    m = margins(sm.sigma_max, stack.allowable, chain.n, chain.n_limit, chain.correct, stack.clearance, r_min)
    return Outputs(sm, capacity, tau, depth, separator, m.sigma >= 0.0,
                   safety_factor(sm.sigma_max, stack.allowable), r_min, r_max, admissible, m)


@dataclass(frozen=True)
class Margins:
    """The design checks of G designs as signed, dimensionless margins (>= 0 passes; zstk.md §10).

    Arrays (G,): sigma (the strength check), closure (N against the chain's N_max), clearance (|s| against r_min).
    """

    sigma: np.ndarray
    closure: np.ndarray
    clearance: np.ndarray


def margins(sigma_max, allowable, n, n_limit, correct, clearance, r_min) -> Margins:
    r"""The zstk design checks as margins (zstk.md §10): >= 0 passes, < 0 fails.

    .. math:: m_\sigma = \frac{[\sigma_H] - \sigma_{max}}{[\sigma_H]}, \qquad
              m_{closure} = 1 - \frac{N}{N_{max}}, \qquad m_{clearance} = 1 - \frac{|s|}{r_{min}}

    m_sigma is 1 - sigma_max/[sigma_H], written as a difference first so that its sign is exactly that of
    [sigma_H] - sigma_max (the check ``pass``: sigma_max <= [sigma_H]).  closure and clearance are distances to
    validity rules (zstk.md §3.3, §9): a design past them is not computed (an error, a sweep's ``error`` row), so
    on a computed design they are >= 0 (N = N_max of the "gap" correction, closed within 1e-9, is 0; no N_max: 1).

    Parameters
    ----------
    sigma_max, allowable : array_like, shape (G,)
        sigma_max and [sigma_H] [MPa].
    n : int or array_like
        N.
    n_limit : array_like
        N_max of the chain (inf: none).
    correct : str or array_like of str
        The correction ("gap" admits N = N_max).
    clearance, r_min : array_like
        s and the smallest roller radius (R_H - R_B - e)/2 [mm].

    Returns
    -------
    Margins
        ``sigma``, ``closure`` and ``clearance``, arrays (G,) [-].

    Examples
    --------
    >>> m = margins(np.array([748.94]), np.array([4000.0]), 8, np.array([31.94]), "outer", np.array([0.0]),
    ...             np.array([23.35]))
    >>> round(float(m.sigma[0]), 6), round(float(m.closure[0]), 6), float(m.clearance[0])
    (0.812765, 0.74953, 1.0)

    References
    ----------
    .. [1] Merko, M. A. et al., the closed system of rolling bodies (seed 003): the strength check against the
       allowable contact stress; gearcalc specification docs/spec/zstk.md §3.3, §9, §10.
    """
    allowable = np.asarray(allowable, dtype=float)
    sigma = (allowable - np.asarray(sigma_max, dtype=float)) / allowable
    lim = np.asarray(n_limit, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        closure = np.where(np.isfinite(lim), 1.0 - np.asarray(n, dtype=float) / lim, 1.0)
        clear = 1.0 - np.abs(np.asarray(clearance, dtype=float)) / np.asarray(r_min, dtype=float)
    shape = sigma.shape
    return Margins(sigma, np.maximum(np.broadcast_to(closure, shape), 0.0), np.maximum(np.broadcast_to(clear, shape),
                                                                                        0.0))


@dataclass(frozen=True)
class RollerDetail:
    """The per-roller quantities of G designs (arrays (G, N)).

    Rollers (the state, or the inner contacts' envelope rows: theta, radius, psi, beta), contacts
    (:func:`gearcalc.zstk.roller_contacts`); approach delta_i [mm] of a single placement, or gamma_inner,
    gamma_outer [rad], the load directions of each contact's envelope; worst : the largest b/rho above the limit,
    -inf where none, (G,).
    """

    rollers: object
    contacts: Contacts
    approach: np.ndarray | None
    gamma_inner: np.ndarray | None
    gamma_outer: np.ndarray | None
    worst: np.ndarray


def roller_detail(state, mats, clearance, envelope=None, width_limit=0.1) -> RollerDetail:
    r"""Hertz semi-widths, shear and approach of every roller (spec §2, §5.2, §10).

    The separator forces are :attr:`Outputs.separator`.

    .. math:: b = \sqrt{4 F \rho / (\pi l E^*)}, \qquad \delta_i = \delta \cos(\theta_{n_{Bi}} - \alpha) - s/2

    Parameters
    ----------
    state : State
        G solved configurations.
    mats : Materials
        Their materials.
    clearance : array_like, shape (G,)
        s [mm].
    envelope : tuple or None
        (d_B, d_H, gamma_B, gamma_H): the per-contact envelope rows of a direction sweep
        (:func:`gearcalc.zstk.roller_envelope`), used instead of ``state``.
    width_limit : float
        b/rho above which a loaded contact is reported in ``worst`` (Hertz's small-contact assumption, §9).

    Returns
    -------
    RollerDetail

    Examples
    --------
    >>> from gearcalc.zstk import close_chain, evaluate, roller_angles, Materials
    >>> ch = close_chain(100.0, 50.0, 6.0, 6.0, 8)
    >>> m = Materials.from_elastic(20.0, 2.1e5, 0.3, 2.1e5, 0.3, 2.1e5, 0.3)
    >>> st = evaluate(ch, m, roller_angles(np.zeros(1), 8, ch.limiting_ratio), np.zeros(1), 1e4, symmetric=True)
    >>> r = roller_detail(st, m, np.zeros(1))
    >>> round(float(r.contacts.width_inner[0, 0]), 6), round(float(r.approach[0, 0] * 1e3), 6), r.worst.tolist()
    (0.206616, 15.036653, [-inf])

    References
    ----------
    Merko et al. (see :mod:`gearcalc.zstk`), eqs. (3)-(5); docs/spec/zstk.md §2, §5.2, §9, §10.
    """
    d_b, d_h, gam_b, gam_h = envelope if envelope is not None else (state, state, None, None)
    ct = roller_contacts(d_b, d_h, mats)
    approach = roller_approach(state, clearance) if envelope is None else None
    return RollerDetail(d_b, ct, approach, gam_b, gam_h, worst_width_ratio(ct, width_limit))
