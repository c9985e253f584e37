"""KHV pin gearing: the per-element detail tables of a cycle (pins.md §8).

Rows (dicts of plain values) over the final crank-angle grid: ``crank`` (one per crank angle) and
``contacts`` (one per loaded contact of the first disc), of the ideal level (:func:`detail_tables`, from
:func:`~gearcalc.pins.cycle.cycle_detail` and :func:`~gearcalc.pins.outputs.crank_detail`) and of the
contact level (:func:`contact_detail`, from its solved cycle).  Units: N, µm, m/s, rpm, W, N·m, degrees.

Example: rows from equal-length columns (a None column stays None in every row):

>>> rows({"theta_deg": [0.0, 1.5], "force_N": None})
[{'theta_deg': 0.0, 'force_N': None}, {'theta_deg': 1.5, 'force_N': None}]

References
----------
.. [1] The paper (Prudnikov, seed 000), cited in full in :mod:`gearcalc.pins`; docs/spec/pins.md §8.
"""
from __future__ import annotations

import numpy as np

from .. import units
from .cycle import cycle_detail
from .outputs import crank_detail

__all__ = ["rows", "detail_tables", "contact_detail"]


def contact_detail(g, sol, cyc, T_V, w_H, n_d, crank=None, consistent: bool = False):
    r"""Detail tables of the contact level (pins.md §8).

    ``crank`` and ``contacts`` rows of the final grid (first disc; piece ends appear twice, the one-sided limits).
    ``crank``: the :class:`~gearcalc.pins.contact.CrankBearing` of the cycle (the crank torque of all discs,
    friction-consistent forces only (``consistent``), and one disc's bearing force), or None.

    .. math:: \lambda(\theta) = \frac{\sum_j P_j(\theta)}{T_{sat}\,\omega_H\,k/z_1}, \qquad
        \text{TE} = \tau(\theta) \ \text{[arcsec]}

    Parameters
    ----------
    g : Cycloid
        The gear.
    sol : Solution
        The states of the final grid.
    cyc : ContactCycle
        The cycle (its losses and loss ratios per node).
    T_V : float
        Torque on V, [N·m].
    w_H : float or None
        Crank speed, [rad/s].
    n_d : int
        Discs, [-].
    crank : CrankBearing, optional
        The crank torque and bearing force.
    consistent : bool, optional
        The friction-consistent forces.

    Returns
    -------
    tables : dict
        ``crank`` and ``contacts``: lists of rows (dicts).

    Examples
    --------
    >>> from gearcalc.pins import contact_cycle as cc
    >>> from gearcalc.pins.contact import MULTIPLIER, Cycloid, CycloidProfile, ContactModel, contact_law
    >>> g = Cycloid.from_curtate_ratio(21, 22, 3.9, 0.75, 1.95)
    >>> model = ContactModel(g, CycloidProfile(g, 0.0, 0.0), contact_law("linear", stiffness=1e5), 1e4, MULTIPLIER)
    >>> cyc = cc.mean_loss_ratio(model, (0.1, 0.1, False), tol=1e-5)
    >>> len(contact_detail(g, cyc.sol, cyc, 10.0, None, 1)["crank"]) == cyc.sol.theta.size   # a row per node
    True

    References
    ----------
    .. [1] docs/spec/pins.md §5.6, §8.
    """
    theta_deg = np.degrees(sol.theta)
    have_P = w_H is not None
    lam = cyc.lam
    loaded_c = sol.force > 0.0
    crank = rows({
        "theta_deg": theta_deg, "TE_arcsec": np.degrees(sol.tau) * 3600.0, "loss_ratio": lam,
        "loss_W": lam * n_d * units.nm_to_nmm(T_V) / n_d * (w_H * g.k / g.z1) * 1e-3 if have_P else None,
        "loaded_pins": loaded_c.any(axis=0).sum(axis=0),
        "crank_torque_Nm": crank.crank_torque if crank is not None and consistent else None,
        "bearing_force_N": crank.bearing_force if crank is not None else None,
        "bearing_radial_N": crank.bearing_radial if crank is not None else None,
        "bearing_tangential_N": crank.bearing_tangential if crank is not None else None,
        "bearing_angle_deg": crank.bearing_angle if crank is not None else None,
    })
    n_idx, j_idx, c_idx = np.nonzero(np.transpose(loaded_c, (2, 1, 0)))    # row-major: node, pin, contact
    pins = j_idx if sol.rows is None else sol.rows[j_idx]                   # the state's rows: the pins (sorted)
    rpm = units.rad_s_to_rpm(w_H) if have_P else None
    contacts = rows({
        "theta_deg": theta_deg[n_idx], "pin": pins, "contact": c_idx,
        "phase_deg": np.degrees(sol.phase[j_idx, n_idx]), "force_N": sol.force[c_idx, j_idx, n_idx],
        "penetration_um": sol.delta[c_idx, j_idx, n_idx] * units.UM_PER_MM,
        "sliding_speed_m_s": cyc.slide[c_idx, j_idx, n_idx] * w_H / units.MM_PER_M if have_P else None,
        "pin_speed_rpm": cyc.spin[j_idx, n_idx] * rpm if have_P else None,
        "loss_W": cyc.loss[c_idx, j_idx, n_idx] * w_H * 1e-3 if have_P else None,
    })
    return {"crank": crank, "contacts": contacts}


def rows(columns: dict) -> list[dict]:
    """Rows (dicts) from equal-length columns; a None column stays None in every row.

    Parameters
    ----------
    columns : dict
        Name -> a list or array, or None.

    Returns
    -------
    rows : list of dict
        One dict per row.

    Examples
    --------
    >>> rows({"a": [1, 2], "b": None})
    [{'a': 1, 'b': None}, {'a': 2, 'b': None}]

    References
    ----------
    .. [1] docs/spec/pins.md §8 (the detail tables).
    """
    n = max(len(v) for v in columns.values() if v is not None)
    cols = {k: (v.tolist() if hasattr(v, "tolist") else v) if v is not None else [None] * n
            for k, v in columns.items()}
    keys = list(cols)
    return [dict(zip(keys, vals)) for vals in zip(*cols.values())]


def detail_tables(g, sigma, st, friction, load, n_d: int = 1, hist=None, consistent=False):
    r"""Rows of the final grid (pins.md §8, :func:`~gearcalc.pins.cycle.cycle_detail`).

    ``crank`` (one per crank angle: the loss ratio and loss of all discs, the loaded pins of the first, the crank
    torque of all discs along the power flow and the crank-bearing force of the first disc: magnitude, radial (along
    the crank arm, outward) and tangential components, direction from the crank arm) and ``contacts`` (one per
    loaded contact of the first disc); piece ends appear twice (the one-sided limits of both sides). ``hist``:
    :func:`~gearcalc.pins.consistent.crank_history` at the nodes; with ``consistent`` the forces are the
    friction-consistent ones (pins.md §4.9).

    .. math:: \lambda = \mu_{eff}\,\frac{\sum_{i \in L} |l_i|\,|\rho_i - R_b|}{S}, \qquad
        F_i = \frac{T_{sat}\,|l_i|}{S}, \qquad S = \sum_{i \in L} l_i^2

    Parameters
    ----------
    g : Cycloid
        The gear.
    sigma : int
        +1 reducer, -1 multiplier.
    st : CycleState
        The loaded contacts at the nodes t = theta/T_p (:func:`~gearcalc.pins.cycle.cycle_state`).
    friction : PinFriction
        mu_eff [-] and whether the pins roll.
    load : SatelliteLoad
        T_sat, the torque on one disc [N·mm], and omega_V, the output speed [rad/s] (each None: not known).
    n_d : int, optional
        Discs, [-].
    hist : dict, optional
        :func:`~gearcalc.pins.consistent.crank_history` at the nodes.
    consistent : bool, optional
        The friction-consistent forces.

    Returns
    -------
    tables : dict
        ``crank`` and ``contacts``: lists of rows (dicts).

    Examples
    --------
    >>> from gearcalc.pins import PinFriction, SatelliteLoad
    >>> from gearcalc.pins.cycle import cycle_state
    >>> from gearcalc.pins.geometry import Cycloid, crest_cutoff
    >>> g = Cycloid.from_curtate_ratio(20, 22, 3.9, 0.75, 1.95)
    >>> st = cycle_state(np.array([0.0, 0.5]), np.array([0.5, 0.5]), g, crest_cutoff(g))
    >>> d = detail_tables(g, -1, st, PinFriction(0.1, 0.1, False), SatelliteLoad(1e4, None))
    >>> round(d["crank"][0]["loss_ratio"], 6), d["crank"][0]["loaded_pins"]
    (0.132085, 7)

    References
    ----------
    .. [1] A. P. Prudnikov, «Потери мощности в контакте цевок и зубьев планетарной передачи типа K-H-V» (Power losses in
       pins and teeth contact area of KHV-type planetary gearing), Машиностроение (seed file 000_fe288dec6e7c72f0.txt);
       docs/spec/pins.md §4.4, §4.6, §8.
    """
    d = cycle_detail(g, sigma, st, friction, load, n_d, denominator=hist["D"] if consistent else None)
    cols = {"theta_deg": d.theta, "TE_arcsec": np.zeros(d.theta.size), "loss_ratio": d.loss_ratio,
            "loss_W": d.loss, "loaded_pins": d.loaded}
    if hist is not None:
        have = load.torque_sat is not None
        cd = crank_detail(hist, st.t, sigma, g.z2, load.torque_sat, n_d) if have else None
        cols.update({
            "crank_torque_Nm": cd.crank_torque if have and consistent else None,
            "bearing_force_N": cd.bearing_force if have else None,
            "bearing_radial_N": cd.bearing_radial if have else None,
            "bearing_tangential_N": cd.bearing_tangential if have else None,
            "bearing_angle_deg": cd.bearing_angle if have else None,
        })
    crank = rows(cols)
    contacts = rows({"theta_deg": d.contact_theta, "pin": d.pin, "phase_deg": d.phase, "force_N": d.force,
                      "sliding_speed_m_s": d.sliding_speed, "pin_speed_rpm": d.pin_speed, "loss_W": d.contact_loss})
    return {"crank": crank, "contacts": contacts}


def ideal_detail(g, psi_star, grid, friction, load, n_discs, sigma, consistent):
    r"""The ideal level's detail tables of one gear (pins.md §8) on its final grid.

    :func:`detail_tables` with the crank history of :func:`~gearcalc.pins.consistent.crank_history`.  With
    ``consistent`` the forces are the friction-consistent ones, and ``load``'s T_sat is the friction-consistent
    efficiency's (pins.md §4.9; :func:`~gearcalc.pins.outputs.satellite_torque` of its T_V, None when self-locking).

    .. math:: F_i = \frac{T_{sat}\,|l_i|}{D}, \qquad B = -\sum_i F_i\,(n_i + q_i\,z \times n_i)

    Parameters
    ----------
    g : Cycloid
        The gear.
    psi_star : float
        End of the loaded arc, [rad].
    grid : tuple of ndarray
        (t, t_mid): the final grid's nodes t = theta/T_p and their pieces' midpoints, [-]
        (:meth:`~gearcalc.pins.ideal.IdealCycles.grid`).
    friction : PinFriction
        mu_eff [-] and whether the pins roll.
    load : SatelliteLoad
        T_sat, the torque on one disc [N·mm] (None without a torque), and omega_V, the output speed [rad/s] (None:
        no crank speed).
    n_discs : int
        Discs, [-].
    sigma : int
        +1 reducer, -1 multiplier.
    consistent : bool
        The friction-consistent forces.

    Returns
    -------
    tables : dict
        ``crank`` and ``contacts``: lists of rows (dicts).

    Examples
    --------
    Friction-free forces: the bearing's tangential force is T_H/e = T_sat k/(z1 e) = 1e4 x 2/(20 x 3.9) N:

    >>> from gearcalc.pins import PinFriction, SatelliteLoad
    >>> from gearcalc.pins.geometry import Cycloid, crest_cutoff
    >>> g = Cycloid.from_curtate_ratio(20, 22, 3.9, 0.75, 1.95)
    >>> d = ideal_detail(g, crest_cutoff(g), (np.array([0.0, 0.5]), np.array([0.5, 0.5])),
    ...                  PinFriction(0.1, 0.1, False), SatelliteLoad(1e4, None), 1, -1, False)
    >>> round(d["crank"][0]["bearing_tangential_N"], 6), d["crank"][0]["loaded_pins"]
    (-256.410256, 7)

    References
    ----------
    .. [1] docs/spec/pins.md §4.9, §8.
    """
    from .consistent import crank_history
    from .cycle import cycle_state

    t, t_mid = grid
    st = cycle_state(t, t_mid, g, psi_star)
    hist = crank_history(g, psi_star, t, t_mid, friction.mu_eff, sigma, consistent)
    return detail_tables(g, sigma, st, friction, load, n_discs, hist, consistent)
