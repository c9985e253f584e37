r"""KHV pin gearing: the output (W) mechanism, no-load drag and the back-driving start-up torque (pins.md §4.10).

The pins-in-holes output mechanism (issue 37 item 3): n_w pins of radius r_w on a circle of radius R_w of the output
flange, each in a hole of radius r_h = r_w + e of the satellite (ideal clearance).  The satellite translates by the
eccentricity e relative to the flange and turns with it, so every hole centre sits at the pin centre plus the crank
vector e x (x along the crank arm, from the input axis to the satellite centre): every pin touches its hole at the
point of the hole farthest inward along the crank arm, the contact normal is x for every hole, and a pin can only
push.  The force of pin j on the satellite is -F_j x, F_j >= 0, at R_w (cos phi_j, sin phi_j) from the satellite
centre (phi_j: the hole's angle from the crank arm), its moment F_j R_w sin phi_j: only the holes with
sigma sin phi_j > 0 carry load (sigma the sign of the torque the mechanism gives the satellite).  With equal pin-hole
compliances and rigid discs a small twist deflects hole j by R_w sin phi_j along x, so (the classical linear
distribution)

.. math:: F_j = F_{max}\,\max(\sigma \sin\varphi_j, 0), \qquad
    F_{max} = \frac{|T|}{R_w \sum_j \max(\sigma\sin\varphi_j, 0)^2}, \qquad
    Q = \sum_j F_j \to \frac{4\,|T|}{\pi R_w}\ (n_w \to \infty)

and the resultant Q acts on the satellite along the crank arm, towards the input axis: the crank bearing carries it
on top of the tooth forces' resultant.  Material points of the satellite and of the flange at a contact move
relative to each other at e (omega_H - omega_V) across x (both bodies turn at omega_V, the satellite centre moves at
e omega_H): every pin slides in its hole at v_w = e |omega_H - omega_V| and the mechanism loses
f_w Q v_w (f_w the pin-hole coefficient; with rolling bushings the equivalent mu_rot of §4.6).

Sources: M. Blagojević, N. Marjanović, Ž. Đorđević, B. Stojanović, A. Disić, "A new design of a two-stage cycloidal
speed reducer", J. Mech. Des. 133(8), 085001, 2011 (the output-roller forces proportional to sin phi_j, their
resultant along the eccentricity); V. N. Kudryavtsev, Planetary Gears (Планетарные передачи), Mashinostroenie,
Leningrad, 1966 (the W-mechanism forces 4T/(pi R_w) and its loss); J. W. Sensinger, "Efficiency of high-sensitivity
gear trains, such as cycloid drives", J. Mech. Des. 135(7), 071006, 2013 (the output-mechanism loss as a separate
factor of the efficiency).  Units N, mm, N·mm, rad/s, m/s.
"""
from __future__ import annotations

import numpy as np

__all__ = ["w_hole_forces", "w_sliding_speed", "w_loss_ratio", "w_mode_efficiencies", "bearing_force_with_w",
           "drag_efficiencies", "backdrive_startup_torque", "teeth_torque", "series_values", "w_bearing_peak_mean"]


def w_hole_forces(torque, n_holes: int, hole_circle_radius, phase):
    r"""The pin-hole forces of a pins-in-holes output mechanism and their resultant on the satellite [N].

    .. math:: \varphi_j = \varphi_0 + \frac{2\pi j}{n_w}, \qquad
        F_j = \frac{|T|\,\max(\sigma\sin\varphi_j, 0)}{R_w \sum_k \max(\sigma\sin\varphi_k, 0)^2}, \qquad
        Q = \sum_j F_j, \qquad \sum_j F_j\,R_w \sin\varphi_j = T

    Parameters
    ----------
    torque : float or array_like
        Torque T the mechanism gives the satellite, signed (sigma = sign T), [N·mm].
    n_holes : int
        Number of holes n_w (>= 3), [-].
    hole_circle_radius : float
        Radius R_w of the holes' (and the pins') circle, [mm].
    phase : float or array_like
        Angle phi_0 of hole 0 from the crank arm, [rad].

    Returns
    -------
    F : ndarray
        Force of each pin on its hole, shape ``broadcast(torque, phase).shape + (n_w,)``, [N] (>= 0; the force on
        the satellite is -F_j along the crank arm).
    Q : ndarray
        Resultant on the satellite, along the crank arm towards the input axis, [N].

    Examples
    --------
    >>> F, Q = w_hole_forces(1000.0, 4, 10.0, np.pi / 2)      # one hole loaded, at 90 degrees
    >>> F.round(9).tolist(), round(float(Q), 9)
    ([100.0, 0.0, 0.0, 0.0], 100.0)

    References
    ----------
    .. [1] M. Blagojević et al., J. Mech. Des. 133(8), 085001, 2011 (forces proportional to sin phi_j);
       docs/spec/pins.md §4.10.
    """
    T = np.asarray(torque, dtype=float)
    phi = np.asarray(phase, dtype=float)[..., None] + 2.0 * np.pi * np.arange(n_holes) / n_holes
    sig = np.where(T >= 0.0, 1.0, -1.0)[..., None]
    s = np.maximum(sig * np.sin(phi), 0.0)
    F = np.abs(T)[..., None] * s / (hole_circle_radius * (s * s).sum(axis=-1, keepdims=True))
    return F, F.sum(axis=-1)


def w_sliding_speed(eccentricity, omega_H, omega_V):
    r"""Sliding speed of every output pin in its hole [same unit as e times rad/s].

    .. math:: v_w = e\,|\omega_H - \omega_V|

    Parameters
    ----------
    eccentricity : float or array_like
        Eccentricity e, [mm].
    omega_H : float or array_like
        Crank angular speed, signed, [rad/s].
    omega_V : float or array_like
        Satellite (output flange) angular speed, signed, [rad/s].

    Returns
    -------
    v_w : ndarray
        Sliding speed, [mm/s].

    Examples
    --------
    >>> float(w_sliding_speed(3.9, 100.0, -10.0))
    429.0

    References
    ----------
    .. [1] docs/spec/pins.md §4.10 (derived: both bodies turn at omega_V, the satellite centre moves at e omega_H).
    """
    return np.asarray(eccentricity) * np.abs(np.asarray(omega_H) - np.asarray(omega_V))


def w_loss_ratio(friction, eccentricity, hole_circle_radius, n_holes: int, speed_ratio, phase):
    r"""Loss of the output mechanism over the power it transmits [-], at the hole phases phi_0.

    .. math:: \lambda_W = \frac{f_w\,Q\,v_w}{|T\,\omega_V|}
        = f_w\,\frac{e}{R_w}\,\frac{\sum_j s_j}{\sum_j s_j^2}\,\left|\frac{\omega_H}{\omega_V} - 1\right|,
        \qquad s_j = \max(\sin\varphi_j, 0), \qquad
        \bar\lambda_W \to \frac{4 f_w e}{\pi R_w}\left|\frac{\omega_H}{\omega_V} - 1\right|

    Parameters
    ----------
    friction : float or array_like
        Pin-hole coefficient f_w (or a rolling bushing's mu_rot), [-].
    eccentricity : float
        Eccentricity e, [mm].
    hole_circle_radius : float
        R_w, [mm].
    n_holes : int
        n_w, [-].
    speed_ratio : float
        omega_H/omega_V, signed (KHV with fixed pins: -z1/k), [-].
    phase : float or array_like
        Angle of hole 0 from the crank arm, [rad].

    Returns
    -------
    lam_W : ndarray
        Loss ratio, [-].

    Examples
    --------
    >>> round(float(w_loss_ratio(0.1, 1.0, 10.0, 4, -10.0, np.pi / 2)), 12)     # 0.1 * 100 N * 11 mm/s / 1000
    0.11

    References
    ----------
    .. [1] V. N. Kudryavtsev, Planetary Gears, Mashinostroenie, 1966 (the W mechanism's loss);
       docs/spec/pins.md §4.10.
    """
    _, Q = w_hole_forces(1.0, n_holes, hole_circle_radius, phase)
    return np.asarray(friction) * Q * eccentricity * np.abs(speed_ratio - 1.0)


def w_mode_efficiencies(loss_ratio_teeth, loss_ratio_w):
    r"""Efficiencies of both modes with the output mechanism in series with the teeth [-].

    .. math:: \eta_{HV} = \frac{1}{(1 + \bar\lambda)(1 + \bar\lambda_W)}, \qquad
        \eta_{VH} = (1 - \bar\lambda_W)(1 - \bar\lambda)

    Parameters
    ----------
    loss_ratio_teeth : float or array_like
        Cycle-mean loss ratio of the teeth, lambda-bar (pins.md §4.6), [-].
    loss_ratio_w : float or array_like
        Cycle-mean loss ratio of the output mechanism, [-].

    Returns
    -------
    eta_HV, eta_VH : float or ndarray
        Reducer and multiplier efficiencies, [-].

    Examples
    --------
    >>> [round(float(x), 12) for x in w_mode_efficiencies(0.25, 0.0)]
    [0.8, 0.75]

    References
    ----------
    .. [1] J. W. Sensinger, J. Mech. Des. 135(7), 071006, 2013 (the output mechanism as a factor);
       docs/spec/pins.md §4.7, §4.10.
    """
    lt, lw = np.asarray(loss_ratio_teeth), np.asarray(loss_ratio_w)
    return 1.0 / ((1.0 + lt) * (1.0 + lw)), (1.0 - lw) * (1.0 - lt)


def bearing_force_with_w(bearing_radial, bearing_tangential, w_resultant):
    r"""The crank-bearing force on the satellite with the output mechanism's resultant added [N].

    .. math:: |B_W| = \sqrt{(B_x + Q)^2 + B_y^2}

    (B = minus the sum of the other forces on the satellite; the mechanism pushes it by -Q along the crank arm.)

    Parameters
    ----------
    bearing_radial : float or array_like
        B_x, the tooth-force bearing force along the crank arm (outward), [N].
    bearing_tangential : float or array_like
        B_y, across the crank arm, [N].
    w_resultant : float or array_like
        Q of :func:`w_hole_forces`, [N].

    Returns
    -------
    B : ndarray
        |B_W|, [N].

    Examples
    --------
    >>> float(bearing_force_with_w(-3.0, 4.0, 6.0))
    5.0

    References
    ----------
    .. [1] docs/spec/pins.md §4.9, §4.10.
    """
    return np.hypot(np.asarray(bearing_radial) + w_resultant, bearing_tangential)


def drag_efficiencies(eta_HV, eta_VH, drag_torque, torque_V, ratio):
    r"""Both modes' efficiencies with a no-load drag torque at the crank (seals, bearings' drag) [-].

    .. math:: \eta^d_{HV} = \frac{\eta_{HV}}{1 + \eta_{HV}\,u\,T_d/|T_V|}, \qquad
        \eta^d_{VH} = \eta_{VH} - u\,\frac{T_d}{|T_V|}

    (reducer: the input power adds T_d omega_H; multiplier: the output power loses it; u = |omega_H/omega_V|.)

    Parameters
    ----------
    eta_HV, eta_VH : float or array_like
        The gearing's efficiencies without drag, [-].
    drag_torque : float or array_like
        Drag torque T_d at the crank, >= 0, [N·m].
    torque_V : float or array_like
        Torque on the slow shaft V, [N·m].
    ratio : float
        u = |omega_H/omega_V|, [-].

    Returns
    -------
    eta_HV_d, eta_VH_d : ndarray
        [-] (eta_VH_d <= 0: the load cannot back-drive the crank).

    Examples
    --------
    >>> [round(float(x), 12) for x in drag_efficiencies(0.8, 0.75, 1.0, 100.0, 10.0)]
    [0.740740740741, 0.65]

    References
    ----------
    .. [1] docs/spec/pins.md §4.10 (derived: a power balance at the crank).
    """
    a = ratio * np.asarray(drag_torque) / np.abs(np.asarray(torque_V, dtype=float))
    return eta_HV / (1.0 + eta_HV * a), eta_VH - a


def backdrive_startup_torque(drag_torque, ratio, eta_VH):
    r"""The smallest slow-shaft torque that back-drives the gear against the crank's drag [N·m].

    .. math:: T_{V,start} = \frac{u\,T_d}{\eta_{VH}} \quad (\eta_{VH} > 0), \qquad \infty \ \text{otherwise}

    (the multiplier's output power T_V eta_VH omega_V - T_d omega_H >= 0; below it the drive cannot be driven
    backwards.)

    Parameters
    ----------
    drag_torque : float or array_like
        Drag torque T_d at the crank, [N·m].
    ratio : float
        u = |omega_H/omega_V|, [-].
    eta_VH : float or array_like
        Multiplier efficiency of the gearing without drag, [-].

    Returns
    -------
    T_start : ndarray
        [N·m] (inf for a self-locking gear).

    Examples
    --------
    >>> float(backdrive_startup_torque(0.5, 10.0, 0.8))
    6.25

    References
    ----------
    .. [1] docs/spec/pins.md §4.10 (derived).
    """
    eta = np.asarray(eta_VH, dtype=float)
    safe = np.where(eta > 0.0, eta, 1.0)
    return np.where(eta > 0.0, ratio * np.asarray(drag_torque) / safe, np.inf)


def teeth_torque(torque, loss_ratio_w, drag_torque, multiplier, torque_on_V):
    r"""The torque the teeth carry, on the shaft of the given torque, with the output mechanism and a drag [N·m].

    .. math:: T^{teeth} = T \pm T_d \ (\text{on H: multiplier} +, \text{reducer} -), \qquad
        T^{teeth} = T\,(1 \mp \bar\lambda_W) \ (\text{on V: multiplier} -, \text{reducer} +)

    (on H the crank's drag is delivered (multiplier) or taken (reducer) by the teeth; on V the satellite gives the
    mechanism T_sat = T_V (1 -+ lambda_W)/n_d, pins.md §4.10.)  The teeth computed at this torque on the same shaft
    (the contact level) give the same shaft torques as :func:`series_values` with their efficiencies.

    Parameters
    ----------
    torque : float or array_like
        The given torque T, [N·m].
    loss_ratio_w : float or array_like
        Cycle-mean loss ratio of the output mechanism, [-].
    drag_torque : float or array_like
        Drag torque T_d at the crank, >= 0, [N·m].
    multiplier, torque_on_V : bool or array_like of bool
        The mode and the shaft of the torque.

    Returns
    -------
    T_teeth : ndarray
        [N·m].

    Examples
    --------
    >>> [float(teeth_torque(100.0, 0.1, 2.0, m, v)) for m, v in ((True, False), (False, False), (True, True))]
    [102.0, 98.0, 90.0]

    References
    ----------
    .. [1] docs/spec/pins.md §4.10 (derived: the power balance at the crank and the satellite's torque).
    """
    T, lw, Td, mult = (np.asarray(x) for x in (torque, loss_ratio_w, drag_torque, multiplier))
    return np.where(torque_on_V, T * np.where(mult, 1.0 - lw, 1.0 + lw), np.where(mult, T + Td, T - Td))


def series_values(teeth_efficiencies, loss_ratio_w, drag_torque, torque, ratio, multiplier, torque_on_V, omega_H):
    r"""The teeth in series with the output mechanism and a crank drag: efficiencies, torques, loss, start-up.

    Both modes' efficiencies, the shaft torques, the mean loss and the back-driving start-up torque (pins.md §4.10).

    .. math:: \eta^1_{HV} = \frac{\eta_{HV}}{1+\bar\lambda_W}, \quad \eta^1_{VH} = \eta_{VH}(1 - \bar\lambda_W),
        \quad T_V = \frac{u (T_H + T_d)}{\eta^1_{VH}} \ \text{or} \ u (T_H - T_d)\,\eta^1_{HV} \ \text{(T on H)},
        \quad \eta^d = \text{drag\_efficiencies}(\eta^1, T_d, T_V), \quad
        T_{V,start} = \frac{u T_d}{\eta^1_{VH}}, \quad T_{sat} n_d = T_V (1 \mp \bar\lambda_W)

    Parameters
    ----------
    teeth_efficiencies : tuple of (float or array_like)
        The teeth's (eta_HV, eta_VH), [-].
    loss_ratio_w : float or array_like
        Cycle-mean loss ratio of the output mechanism (0: the ideal mechanism), [-].
    drag_torque : float or array_like
        Drag torque T_d at the crank, >= 0, [N·m].
    torque : float or array_like
        The given torque T, [N·m].
    ratio : float or array_like
        u = |omega_H/omega_V|, [-].
    multiplier, torque_on_V : bool or array_like of bool
        The mode and the shaft of the torque.
    omega_H : float or array_like
        Crank speed, [rad/s] (NaN: none).

    Returns
    -------
    values : dict of ndarray
        ``eta_HV``, ``eta_VH`` (NaN where <= 0), ``locked`` (the multiplier requested and eta_VH <= 0),
        ``torque_in``, ``torque_out``, ``torque_V`` [N·m], ``loss`` (P_in - P_out) [W], ``startup`` (NaN without
        a drag) [N·m], ``sat_factor`` (1 -+ lambda_W: T_sat n_d = T_V sat_factor) [-].

    Examples
    --------
    >>> v = series_values((0.8, 0.75), 0.0, 1.0, 100.0, 10.0, False, True, 1.0)     # reducer, T_V = 100 N·m
    >>> round(float(v["eta_HV"]), 12), float(v["torque_in"]), round(float(v["loss"]), 9)
    (0.740740740741, 13.5, 3.5)

    References
    ----------
    .. [1] docs/spec/pins.md §4.10; Sensinger 2013 (the output mechanism as a factor).
    """
    hv0, vh0, lam_w, drag, T, u, mult = (np.asarray(x) for x in (*teeth_efficiencies, loss_ratio_w, drag_torque,
                                                                  torque, ratio, multiplier))
    hv1, vh1 = hv0 / (1.0 + lam_w), vh0 * (1.0 - lam_w)
    with np.errstate(divide="ignore", invalid="ignore"):
        T_V = np.where(torque_on_V, T, np.where(mult, (T + drag) * u / vh1, (T - drag) * u * hv1))
        hv, vh = drag_efficiencies(hv1, vh1, drag, T_V, u)
        T_H = np.where(mult, T_V * vh1 / u - drag, T_V / (u * hv1) + drag)
        locked = mult & ~(vh > 0.0)
        vh = np.where(vh > 0.0, vh, np.nan)
        w_H = np.asarray(omega_H)
        loss = np.where(mult, T_V * w_H / u - T_H * w_H, T_H * w_H - T_V * w_H / u)
        start = np.where(drag > 0.0, backdrive_startup_torque(drag, u, vh1), np.nan)
    return {"eta_HV": hv, "eta_VH": vh, "locked": locked, "torque_in": np.where(mult, T_V, T_H),
            "torque_out": np.where(mult, T_H, T_V), "torque_V": T_V, "loss": loss, "startup": start,
            "sat_factor": np.where(mult, 1.0 - lam_w, 1.0 + lam_w)}


def w_bearing_peak_mean(bearing_radial, bearing_tangential, w_resultants, weights=None):
    r"""Peak and mean of the crank-bearing force with the output mechanism, over crank angles and hole phases [N].

    .. math:: \max_{i,m} |B(\theta_i) + Q(\varphi_m)\,x|, \qquad
        \sum_i w_i\,\frac{1}{M}\sum_m |B(\theta_i) + Q(\varphi_m)\,x|

    (the hole pattern turns against the crank: over the running every tooth phase meets every hole phase,
    pins.md §4.10.)

    Parameters
    ----------
    bearing_radial, bearing_tangential : array_like
        The teeth's bearing force B(theta_i) along the crank arm (outward) and across it, [N] (n,).
    w_resultants : array_like
        Q at M hole phases (:func:`w_hole_forces`), [N] (M,).
    weights : array_like, optional
        The cycle mean's weights over theta_i (summing to 1); None: the plain mean (a uniform grid of midpoints).

    Returns
    -------
    peak, mean : float
        [N].

    Examples
    --------
    >>> w_bearing_peak_mean([-3.0, 0.0], [4.0, 0.0], [6.0, 3.0])     # |(3, 4)|, |(0, 4)|, 6, 3
    (6.0, 4.5)

    References
    ----------
    .. [1] docs/spec/pins.md §4.10.
    """
    B = bearing_force_with_w(np.asarray(bearing_radial, dtype=float)[:, None],
                             np.asarray(bearing_tangential, dtype=float)[:, None],
                             np.asarray(w_resultants, dtype=float)[None, :])
    if weights is None:
        return float(np.nanmax(B)), float(np.nanmean(B))
    return float(np.nanmax(B)), float(np.dot(np.asarray(weights, dtype=float), B.mean(axis=1)))
