"""KHV pin gearing, contact level: torsional stiffness, lost motion, hysteresis and transmission error (pins.md §5.8).

With the input (the crank, H) held at a crank angle theta, a torque on the output shaft V twists the satellite by
tau(T) against the compliant pin contacts (:mod:`gearcalc.pins.contact_kinematics`: the moment balance of §5.5
about the satellite centre O1, which the rigid crank holds).  The pins are fixed, so the output V turns with the
satellite: the output twist is tau itself, measured from the rigid kinematics (tau = 0).  Friction at the
contacts opposes the contacts' relative motion under the twist, which reverses between loading and unloading:
the loading and unloading branches differ (the hysteresis loop).  Pure functions of a
:class:`~gearcalc.pins.contact_model.ContactModel`; no design keys.

References
----------
.. [1] GB/T 35089-2018, Robot joint precision reducers: torsional stiffness as the secant between 50 % and 100 %
   of the rated torque; lost motion at +-3 % of it; docs/spec/pins.md §5.8.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..roots import find_root
from .cycle import disc_offsets

__all__ = ["ARCMIN_PER_RAD", "FRACTIONS", "twist", "bearing_twist", "linear_torsional_stiffness", "TorsionCurve",
           "torsion_curve", "unloaded_transmission_error", "torsion_outputs",
           "N_TORSION", "N_TE"]

ARCMIN_PER_RAD = 10800.0 / math.pi
"""Arc minutes per radian."""

FRACTIONS = (0.03, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0)
"""The torques of the curve as fractions of the rated torque (0.03: lost motion; 0.5 and 1.0: the secant)."""


def _bracket(G, n: int, limit: float):
    """Brackets [a, b] of the roots of a decreasing G (n,) about tau = 0, by doubling a step from 1e-12 rad."""
    G0 = G(np.zeros(n))
    d = np.where(G0 > 0.0, 1.0, -1.0)
    a, b = np.zeros(n), np.zeros(n)
    open_ = G0 != 0.0
    h, prev = 1e-12, np.zeros(n)
    while open_.any():
        step = min(h, limit)
        found = open_ & (np.sign(G(d * step)) != np.sign(G0))
        a, b = np.where(found, prev, a), np.where(found, d * step, b)
        open_ &= ~found
        prev = np.where(open_, d * step, prev)
        if step >= limit:
            break
        h *= 2.0
    return np.minimum(a, b), np.maximum(a, b), open_


def twist(model, theta, torque_sat, direction, xtol: float = 1e-15, n_discs: int = 1,
          bearing_stiffness: float | None = None):
    r"""Output twist of the satellite with the crank held, at given torques and loading directions.

    The root tau of the moment balance about O1 (pins.md §5.5) with the required moment -T_sat (a positive torque
    twists the satellite by tau > 0) at each crank angle and torque.  With friction in the model
    (``model.friction``), the tangential force of each contact opposes its sliding under the twist,
    v_t = (C . n) d tau (the crank held: O1 does not move), d tau of the sign ``direction`` (+1: tau increasing,
    loading towards positive torque or unloading from a negative one); the directions are those of the
    frictionless solution's contacts (:meth:`~gearcalc.pins.friction.PinFriction.traction`).

    .. math:: \frac{1}{n_d}\sum_d \sum_j F_{dj}\left((X\times n)_{dj} + q_{dj}\,(C\cdot n)_{dj}\right)
        = -T_{sat}, \qquad q_j = -\mu\,\operatorname{sign}\left((C\cdot n)_j\,s\right)

    Parameters
    ----------
    model : ContactModel
        The satellite (its gear, profile, law and friction; its own torque is not used).
    theta : array_like
        Crank angles, [rad], shape (n,).
    torque_sat : array_like
        Signed torque per satellite, [N·mm], shape (n,).
    direction : array_like
        The sign s of d tau (+1 or -1), [-], shape (n,).
    xtol : float, optional
        Absolute tolerance on tau, [rad].
    n_discs : int, optional
        Discs n_d on the one output: they twist alike and carry n_d T_sat together, each at its own crank angle
        (shifted by :func:`~gearcalc.pins.cycle.disc_offsets` pin pitches; equal shares where the shifts are whole
        pitches), [-].
    bearing_stiffness : float or None, optional
        k_b, radial stiffness of one disc's crank bearing, [N/mm], in series (:func:`bearing_twist`); None: rigid.

    Returns
    -------
    tau : ndarray
        The twist, [rad], shape (n,); 0 at zero torque.

    Raises
    ------
    gearcalc.pins.contact.NoEquilibrium
        At a torque no rotation within +-pi/z1 balances.

    Examples
    --------
    >>> from gearcalc.pins.contact import REDUCER, ContactModel, CycloidProfile, Cycloid, contact_law
    >>> g = Cycloid.from_curtate_ratio(21, 22, 3.9, 0.75, 1.95)
    >>> m = ContactModel(g, CycloidProfile(g, 0.0, 0.0), contact_law("linear", stiffness=1e6), 1.0, REDUCER)
    >>> t = twist(m, np.zeros(2), np.array([1e5, -1e5]), np.array([1.0, -1.0]))
    >>> bool(t[0] > 0.0), bool(abs(t[0] + t[1]) < 1e-9 * abs(t[0]))
    (True, True)

    References
    ----------
    .. [1] docs/spec/pins.md §5.5, §5.8.
    """
    theta = np.atleast_1d(np.asarray(theta, dtype=float))
    M_req = -np.asarray(torque_sat, dtype=float) * np.ones(theta.size)
    tau = np.zeros(theta.size)
    live = M_req != 0.0
    if not live.any():
        return tau
    tau[live] = _contact_twist(model, theta[live], M_req[live],
                               (np.asarray(direction, dtype=float) * np.ones(theta.size))[live], xtol, n_discs)
    if bearing_stiffness is not None:
        tau[live] += bearing_twist(model.g, -M_req[live], bearing_stiffness)
    return tau


def _contact_twist(model, theta, M, sv, xtol: float, n_discs: int):
    """The contacts' twist (O1 held) at the required moments M != 0 (:func:`twist`).

    The root of the discs' moment balance, frictionless first, then with the friction directions of that solution's
    contacts.
    """
    from .contact import NoEquilibrium

    # the discs: their crank angles shifted by disc_offsets pin pitches, one pose per distinct shift (pins.md §12.7)
    shifts, counts = np.unique(disc_offsets(n_discs, model.g.z2), return_counts=True)
    poses = [model.pose(theta + sh * model.g.period) for sh in shifts]
    w = counts / float(n_discs)

    def solve(tractions):
        def G(t):
            return sum(wd * model.moment(p, t, tr) for wd, p, tr in zip(w, poses, tractions)) - M

        a, b, open_ = _bracket(G, M.size, math.pi / model.g.z1)
        if open_.any():
            raise NoEquilibrium(theta[open_])
        return find_root(G, a, b, xtol=xtol, rtol=0.0).root

    t = solve([None] * len(poses))
    if model.friction is not None:
        cts = [model.contacts(p, t) for p in poses]
        t = solve([model.friction.traction(model.law.force(ct.delta), (ct.xn + model.g.R_b) * sv) for ct in cts])
    return t


def bearing_twist(g, torque_sat, bearing_stiffness: float):
    r"""Output twist from the crank bearing's radial compliance, in series with the contacts (pins.md §5.8).

    Every normal of the conjugate contacts passes through the pitch point P, r_p1 = e z1/k from O1 along the crank
    arm (the ideal level's lever arms, pins.md §4.4: l_j = r_p1 (t.n_j), t across the arm), so the contacts'
    resultant B on the satellite carries the moment about O1 with its component across the arm alone:
    B_t = T_sat/r_p1.  The bearing gives way by d_t = B_t/k_b across the arm; with the crank held and the teeth in
    mesh the satellite rolls on the pins about P: it turns by d_t/r_p1 (a displacement along the arm only changes
    the mesh's centre distance: second order).  Friction and non-conjugate (circular) teeth move B's line of
    action off P by O(mu) and by their normals' spread: the same formula, first order.

    .. math:: \tau_b = \frac{T_{sat}}{k_b\,r_{p1}^2}, \qquad r_{p1} = \frac{e z_1}{k}

    Parameters
    ----------
    g : Cycloid
        The gear (e, z1, k).
    torque_sat : array_like
        Signed torque on one satellite (disc), [N·mm].
    bearing_stiffness : float
        k_b, radial stiffness of one disc's crank bearing, [N/mm].

    Returns
    -------
    tau_b : ndarray
        The bearing's share of the output twist, [rad].

    Examples
    --------
    >>> from gearcalc.pins.geometry import Cycloid
    >>> g = Cycloid.from_curtate_ratio(21, 22, 3.9, 0.75, 1.95)   # r_p1 = 3.9 * 21 = 81.9 mm
    >>> round(float(bearing_twist(g, 81.9 ** 2, 1.0)), 12)
    1.0

    References
    ----------
    .. [1] docs/spec/pins.md §4.4 (the lever arms), §5.8 (the crank bearing in series).
    """
    return np.asarray(torque_sat, dtype=float) / (bearing_stiffness * g.r_p1 ** 2)


def linear_torsional_stiffness(theta, g, psi_star: float, stiffness: float, n_discs: int = 1, sigma: int = 1,
                               bearing_stiffness: float | None = None):
    r"""Torsional stiffness at the output of an unmodified cycloid with linear contacts and a rigid or compliant crank.

    A rotation tau of the satellite about O1 presses pin i by tau l_i (l_i the ideal level's lever arm, pins.md
    §4.4), so F_i = k_lin l_i tau and the moment is k_lin tau sum l_i^2 over the loaded pins (no friction, small
    rotations: the closed form the contact level must reproduce as k_lin grows, pins.md §5.8).  A crank bearing of
    radial stiffness k_b per disc adds, in series, the twist T_sat/(k_b r_p1^2) of each disc (:func:`bearing_twist`:
    the discs' bearings in parallel, n_d k_b r_p1^2 at the output).

    .. math:: K_c = k_{lin} \sum_d S(\theta + \Delta_d T_p), \quad S = \sum_{j\in L} l_j^2, \qquad
        \frac{1}{K} = \left(\frac{1}{K_c} + \frac{1}{n_d k_b r_{p1}^2}\right) \cdot 10^{3}\,\frac{10800}{\pi}

    Parameters
    ----------
    theta : float or array_like
        Crank angles, [rad].
    g : Cycloid
        The gear.
    psi_star : float
        End of the loaded arc, [rad].
    stiffness : float
        k_lin, contact stiffness, [N/mm].
    n_discs : int, optional
        Discs on the output, in parallel, each at its crank angle shifted by Delta_d pin pitches
        (:func:`~gearcalc.pins.cycle.disc_offsets`), [-].
    sigma : int, optional
        The loaded pins: +1 those of a positive torque (:func:`twist`; the reducer's), -1 those of a negative one.
    bearing_stiffness : float or None, optional
        k_b, radial stiffness of one disc's crank bearing, [N/mm]; None: rigid.

    Returns
    -------
    K : ndarray
        Torsional stiffness at the output, [N·m/arcmin].

    Examples
    --------
    >>> from gearcalc.pins.geometry import Cycloid
    >>> g = Cycloid.from_curtate_ratio(21, 22, 3.9, 0.75, 1.95)
    >>> bool(linear_torsional_stiffness(0.0, g, math.pi, 1e6) > 0.0)
    True

    References
    ----------
    .. [1] S. K. Malhotra, M. A. Parameswaran, Analysis of a cycloid speed reducer, Mechanism and Machine Theory
       18(6):491-499, 1983 (the lever arms); docs/spec/pins.md §4.4, §5.8.
    """
    from .forces import lever_sum

    theta = np.asarray(theta, dtype=float)
    S = sum(lever_sum(theta + sh * g.period, g, psi_star, sigma) for sh in disc_offsets(n_discs, g.z2))
    K = stiffness * S
    if bearing_stiffness is not None:
        K = 1.0 / (1.0 / K + 1.0 / (n_discs * bearing_stiffness * g.r_p1 ** 2))
    return K * 1e-3 / ARCMIN_PER_RAD


@dataclass
class TorsionCurve:
    """The twist curves at crank angles theta (:func:`torsion_curve`).

    theta (n,) [rad]; torque (f,) [N·m] the output torques of the fractions; twist (4, f, n) [arcmin]: the branches
    loading +, unloading +, loading -, unloading - (torques +T, +T, -T, -T); stiffness, lost_motion, hysteresis (n,)
    [N·m/arcmin, arcmin, arcmin] per crank angle; sides (2, n) [N·m/arcmin]: the secant stiffness towards +T and -T.
    """

    theta: np.ndarray
    torque: np.ndarray
    twist: np.ndarray
    stiffness: np.ndarray
    lost_motion: np.ndarray
    hysteresis: np.ndarray
    sides: np.ndarray


def torsion_curve(model, theta, rated_torque: float, n_discs: int = 1, fractions=FRACTIONS,
                  bearing_stiffness: float | None = None) -> TorsionCurve:
    r"""Twist against output torque with the crank held: stiffness, lost motion and hysteresis per crank angle.

    Loading 0 -> +T_r -> 0 -> -T_r -> 0 at each crank angle (:func:`twist`, friction against the twist's direction
    on each branch).  The stiffness is the secant between 50 % and 100 % of T_r on the loading branches (the lower
    of the two directions), the lost motion the twist span between +3 % and -3 % of T_r on the loading branches
    (it includes the play, :func:`~gearcalc.pins.contact.free_play`), the hysteresis the largest width of the loop
    between a loading and an unloading branch at equal torque.  At a reversal the contacts stick (the twist stays
    while the torque falls until it meets the unloading branch): an unloading branch is taken no farther out than
    the twist at T_r.

    .. math:: K = \min_\pm \frac{0.5\,T_r}{|\varphi(\pm T_r) - \varphi(\pm 0.5 T_r)|}, \qquad
        LM = \varphi(0.03\,T_r) - \varphi(-0.03\,T_r), \qquad
        H = \max_T |\min(\varphi_{unload}(T), \varphi(T_r)) - \varphi_{load}(T)|

    Parameters
    ----------
    model : ContactModel
        The satellite (its friction, if any, gives the hysteresis).
    theta : array_like
        Crank angles, [rad], shape (n,).
    rated_torque : float
        T_r, rated torque on the output V, [N·m].
    n_discs : int, optional
        Discs sharing the torque, [-].
    fractions : tuple of float, optional
        The torques as fractions of T_r; must hold 0.03, 0.5 and 1.0.
    bearing_stiffness : float or None, optional
        k_b, radial stiffness of one disc's crank bearing, [N/mm] (:func:`twist`); None: rigid.

    Returns
    -------
    TorsionCurve

    Examples
    --------
    >>> from gearcalc.pins.contact import REDUCER, ContactModel, CycloidProfile, Cycloid, contact_law
    >>> g = Cycloid.from_curtate_ratio(21, 22, 3.9, 0.75, 1.95)
    >>> m = ContactModel(g, CycloidProfile(g, 0.0, 0.0), contact_law("linear", stiffness=1e6), 1.0, REDUCER)
    >>> c = torsion_curve(m, np.array([0.0]), 100.0)
    >>> float(c.hysteresis[0]), bool(c.stiffness[0] > 0.0)     # no friction: the loop closes
    (0.0, True)

    References
    ----------
    .. [1] GB/T 35089-2018, Robot joint precision reducers (torsional stiffness, lost motion); docs/spec/pins.md §5.8.
    """
    theta = np.atleast_1d(np.asarray(theta, dtype=float))
    fr = np.asarray(fractions, dtype=float)
    n, f = theta.size, fr.size
    signs_T = np.array([1.0, 1.0, -1.0, -1.0])
    signs_d = np.array([1.0, -1.0, -1.0, 1.0])
    branches = 4 if model.friction is not None else 1
    T = (signs_T[:, None, None] * fr[None, :, None] * np.ones(n)[None, None, :])[::(1 if branches == 4 else 2)]
    d = (signs_d[:, None, None] * np.ones((f, n))[None])[::(1 if branches == 4 else 2)]
    th = np.broadcast_to(theta, T.shape)
    tau = twist(model, th.ravel(), (T * rated_torque * 1e3 / n_discs).ravel(), d.ravel(),
                n_discs=n_discs, bearing_stiffness=bearing_stiffness).reshape(T.shape)
    tw = tau * ARCMIN_PER_RAD
    if branches == 1:
        tw = np.stack((tw[0], tw[0], tw[1], tw[1]))
    i50, i100, i3 = (int(np.argmin(np.abs(fr - x))) for x in (0.5, 1.0, 0.03))
    # at a reversal the contacts stick: the twist stays while the torque falls to the unloading branch, which the
    # path then follows; its part beyond the reversal's twist is never reached
    tw[1] = np.minimum(tw[1], tw[0, i100])
    tw[3] = np.maximum(tw[3], tw[2, i100])
    k_pos = 0.5 * rated_torque / np.abs(tw[0, i100] - tw[0, i50])
    k_neg = 0.5 * rated_torque / np.abs(tw[2, i100] - tw[2, i50])
    lost = tw[0, i3] - tw[2, i3]
    hyst = np.maximum(np.abs(tw[1] - tw[0]).max(axis=0), np.abs(tw[3] - tw[2]).max(axis=0))
    return TorsionCurve(theta, fr * rated_torque, tw, np.minimum(k_pos, k_neg), lost, hyst, np.stack((k_pos, k_neg)))


def unloaded_transmission_error(model, theta):
    r"""Transmission error at no load: the rotation at which the first contact closes, towards positive torque.

    With rigid contacts and no load the satellite rests where the first pair touches when it turns in the load's
    direction: tau_+(theta) of :func:`~gearcalc.pins.contact.free_play` (0 where a pair touches at the nominal
    pose: an unmodified conjugate cycloid has no transmission error).

    .. math:: TE_0(\theta) = \tau_+(\theta) = \min\{\tau > 0 : \max_j \delta_j(\tau) = 0\}

    Parameters
    ----------
    model : ContactModel
        The satellite.
    theta : array_like
        Crank angles, [rad].

    Returns
    -------
    te : ndarray
        The transmission error, [rad].

    Examples
    --------
    >>> from gearcalc.pins.contact import REDUCER, ContactModel, CycloidProfile, Cycloid, contact_law
    >>> g = Cycloid.from_curtate_ratio(21, 22, 3.9, 0.75, 1.95)
    >>> m = ContactModel(g, CycloidProfile(g, 0.0, 0.0), contact_law("linear", stiffness=1e6), 1.0, REDUCER)
    >>> float(np.ptp(unloaded_transmission_error(m, np.linspace(0.0, g.period, 5))))
    0.0

    References
    ----------
    .. [1] docs/spec/pins.md §5.6 (TE), §5.8.
    """
    from .contact import free_play

    return free_play(model, np.atleast_1d(np.asarray(theta, dtype=float)), sides=(1.0,))[0]


N_TORSION = 16
"""Crank angles of the twist curves over one pin pitch T_p (:func:`_sampling_err` gives their sampling error)."""

N_TE = 64
"""Crank angles of the transmission error over one pin pitch T_p (sampling error: :func:`_sampling_err`)."""


def _sampling_err(v, largest: bool) -> float:
    """Error of the extreme of a T_p-periodic sampled function.

    The larger of its change from the even half of the samples to all and of its periodic neighbours' distance
    from it (a kink at the extreme: slope times spacing).
    """
    v = np.asarray(v, dtype=float)
    i = int(np.argmax(v) if largest else np.argmin(v))
    half = v[::2].max() if largest else v[::2].min()
    return float(max(abs(v[i] - half), abs(v[i - 1] - v[i]), abs(v[(i + 1) % v.size] - v[i])))


def torsion_outputs(model, rated_torque: float, n_discs: int, backlash_deg: float, xtol: float = 1e-15,
                    bearing_stiffness: float | None = None):
    r"""Torsional stiffness, lost motion, hysteresis, backlash and transmission error of one design (pins.md §5.8).

    :func:`torsion_curve` at ``N_TORSION`` crank angles over one pin pitch T_p (the contact pattern repeats with
    T_p): the stiffness is the least over them, the lost motion and the hysteresis the largest; each error is the
    larger of the change of that extreme from the even half of the angles to all of them and of its neighbouring
    samples' distance from it (the sampling over theta), plus the solver's tolerance carried through.  The
    transmission error over one cycle (tau is T_p-periodic, pins.md §5.6) at no load
    (:func:`unloaded_transmission_error`) and at T_r (loading branch), peak-to-peak on ``N_TE`` angles, error as
    above (for its largest and its least value).  The backlash is the contact level's
    (:func:`gearcalc.pins.contact.backlash`, min over the cycle).  A crank bearing of radial stiffness k_b adds its
    twist in series (:func:`bearing_twist`).

    .. math:: K = \min_\theta K(\theta), \quad LM = \max_\theta LM(\theta), \quad
        \mathrm{TE}_{pp} = \max_\theta \tau - \min_\theta \tau

    Parameters
    ----------
    model : ContactModel
        The satellite (reducer sense; friction in it or None).
    rated_torque : float
        T_r on the output V, [N·m].
    n_discs : int
        Discs sharing the torque, [-].
    backlash_deg : float
        The contact level's backlash, [deg].
    xtol : float, optional
        The twist solver's tolerance, [rad].
    bearing_stiffness : float or None, optional
        k_b, radial stiffness of one disc's crank bearing, [N/mm]; None: rigid.

    Returns
    -------
    summary : dict
        The summary fields (pins.md §8).
    tables : dict
        The detail tables "torsion", "torsion_crank" and "transmission_error" (lists of row dicts).

    Examples
    --------
    >>> from gearcalc.pins.contact import REDUCER, ContactModel, CycloidProfile, Cycloid, contact_law
    >>> g = Cycloid.from_curtate_ratio(21, 22, 3.9, 0.75, 1.95)
    >>> m = ContactModel(g, CycloidProfile(g, 0.0, 0.0), contact_law("linear", stiffness=1e6), 1.0, REDUCER)
    >>> s, t = torsion_outputs(m, 100.0, 1, 0.0)
    >>> s["hysteresis_arcmin"], s["te_unloaded_pp_arcsec"]
    (0.0, 0.0)

    References
    ----------
    .. [1] GB/T 35089-2018, Robot joint precision reducers; docs/spec/pins.md §5.8, §8.
    """
    Tp = model.g.period
    th = np.arange(N_TORSION) * (Tp / N_TORSION)
    c = torsion_curve(model, th, rated_torque, n_discs, bearing_stiffness=bearing_stiffness)
    th_te = np.arange(N_TE) * (Tp / N_TE)
    te0 = unloaded_transmission_error(model, th_te) * ARCMIN_PER_RAD * 60.0
    te1 = twist(model, th_te, np.full(N_TE, rated_torque * 1e3 / n_discs), np.ones(N_TE), xtol,
                n_discs, bearing_stiffness) * ARCMIN_PER_RAD * 60.0
    summary = _torsion_summary(c, te0, te1, rated_torque, backlash_deg, 2.0 * xtol * ARCMIN_PER_RAD,
                               model.friction is not None)
    return summary, _torsion_tables(c, th_te, te0, te1)


def _torsion_summary(c: TorsionCurve, te0, te1, rated_torque: float, backlash_deg: float, tol_am: float,
                     friction: bool) -> dict:
    """The summary fields of :func:`torsion_outputs` from its curves and TE samples.

    Errors: :func:`_sampling_err` plus the solver's tolerance ``tol_am`` [arcmin] carried through.
    """
    i = int(np.argmin(c.stiffness))
    k = float(c.stiffness[i])
    k_span = float(np.abs(c.twist[0, -1, i] - c.twist[0, int(np.argmin(np.abs(np.asarray(FRACTIONS) - 0.5))), i]))
    lm, hy = float(c.lost_motion.max()), float(c.hysteresis.max())
    return {
        "torsional_stiffness_Nm_per_arcmin": k,
        "torsional_stiffness_Nm_per_arcmin_err": _sampling_err(c.stiffness, False) + k * tol_am / k_span,
        "torsional_stiffness_crank_deg": math.degrees(float(c.theta[i])),
        "lost_motion_arcmin": lm, "lost_motion_arcmin_err": _sampling_err(c.lost_motion, True) + tol_am,
        "hysteresis_arcmin": hy, "hysteresis_arcmin_err": _sampling_err(c.hysteresis, True) + (
            tol_am if friction else 0.0),
        "backlash_arcmin": backlash_deg * 60.0, "backlash_arcmin_err": 1e-12 * backlash_deg * 60.0 + tol_am,
        "rated_torque_Nm": rated_torque,
        "te_unloaded_pp_arcsec": float(np.ptp(te0)),
        "te_unloaded_pp_arcsec_err": _sampling_err(te0, True) + _sampling_err(te0, False) + (
            60.0 * tol_am if np.ptp(te0) > 0.0 else 0.0),
        "te_rated_pp_arcsec": float(np.ptp(te1)),
        "te_rated_pp_arcsec_err": _sampling_err(te1, True) + _sampling_err(te1, False) + 60.0 * tol_am,
    }


def _torsion_tables(c: TorsionCurve, th_te, te0, te1) -> dict:
    """The detail tables of :func:`torsion_outputs`.

    The loop at the crank angle of the least stiffness, the figures and the transmission error per crank angle.
    """
    deg = math.degrees
    i = int(np.argmin(c.stiffness))
    names = ("loading +", "unloading +", "loading -", "unloading -")
    sign = (1.0, 1.0, -1.0, -1.0)
    torsion = [{"branch": names[b], "crank_deg": deg(float(c.theta[i])), "torque_Nm": sign[b] * float(T),
                "twist_arcmin": float(c.twist[b, j, i])}
               for b in range(4) for j, T in (enumerate(c.torque) if b in (0, 2) else list(enumerate(c.torque))[::-1])]
    crank = [{"crank_deg": deg(float(t)), "stiffness_Nm_per_arcmin": float(c.stiffness[j]),
              "lost_motion_arcmin": float(c.lost_motion[j]), "hysteresis_arcmin": float(c.hysteresis[j])}
             for j, t in enumerate(c.theta)]
    te = [{"crank_deg": deg(float(t)), "te_unloaded_arcsec": float(te0[j]), "te_rated_arcsec": float(te1[j])}
          for j, t in enumerate(th_te)]
    return {"torsion": torsion, "torsion_crank": crank, "transmission_error": te}
