r"""KHV pin gearing, level ``ideal``: the output mechanism and the crank's drag in the summary (pins.md §4.10).

Applies :mod:`gearcalc.pins.wmech` to the ideal level's fields of n points: a pins-in-holes output mechanism
(``[output] mechanism = "pins_in_holes"``) in series with the teeth (its loss ratio, its resultant on the crank
bearing) and a drag torque at the crank (``load.drag_torque_Nm``); the shaft torques, the mean loss and the
force-like fields follow the satellite torque they imply.  Points with the ``"ideal"`` mechanism (pure torque, the
default) and no drag keep their numbers; the summary says the mechanism (``output_mechanism``).

Units N, mm, N·mm, N·m, rpm, W.
"""
from __future__ import annotations

import math

import numpy as np

from .wmech import bearing_force_with_w, series_values, w_hole_forces

__all__ = ["NEW_FIELDS", "BEARING_FIELDS", "w_unit_resultants", "output_fields", "w_bearing_columns"]

NEW_FIELDS = ("output_mechanism", "w_loss_ratio", "w_force_max_N", "backdrive_startup_torque_Nm")
"""The summary fields this module adds (pins.md §8)."""

BEARING_FIELDS = ("bearing_equivalent_load_N", "bearing_equivalent_load_err_N", "bearing_L10_h", "bearing_L10_h_err")
"""The crank bearing's life fields (pins.md §8.2), with pins_in_holes from |B + Q x| (:func:`w_bearing_columns`)."""

PHASES = 64
"""Hole-pattern phases over one pattern period for the resultant's extremes and the bearing force's mean."""
NODES = 1024
"""Crank angles over one tooth period (midpoints) of the bearing force with the mechanism's resultant."""

_SCALED = ("pin_force_max_N", "pin_loss_max_W", "loss_peak_W", "pin_loss_bound_W", "crank_torque_mean_Nm",
           "crank_torque_ripple_Nm", "axle_pressure_max_MPa")


def w_unit_resultants(n_holes, hole_circle_radius):
    r"""The resultant's least, largest and mean value per unit satellite torque, over the hole-pattern phase [1/mm].

    .. math:: \frac{Q}{T} = \frac{\sum_j s_j}{R_w \sum_j s_j^2}, \qquad s_j = \max(\sin(\varphi_0 + 2\pi j/n_w), 0),
        \qquad \varphi_0 \in [0, 2\pi/n_w)

    Parameters
    ----------
    n_holes : int
        n_w, [-].
    hole_circle_radius : float
        R_w, [mm].

    Returns
    -------
    q_min, q_max, q_mean : float
        [1/mm].  The mean: Gauss-Legendre (16 nodes) on each half of the pattern period, where Q/T is smooth (a
        hole crosses the crank arm at phase 0, for odd n_w the opposite side at half the period): exact to
        rounding (even n_w: 4/(pi R_w)).
    q_phases : ndarray
        Q/T at :data:`PHASES` phases over the period (midpoints), [1/mm].

    Examples
    --------
    >>> q = w_unit_resultants(8, 1.0)
    >>> round(q[0], 4), round(q[1], 4), round(q[2] * np.pi / 4, 12)
    (1.2071, 1.3066, 1.0)

    References
    ----------
    .. [1] docs/spec/pins.md §4.10 (the range's closed form for even n_w).
    """
    period = 2.0 * math.pi / n_holes
    x, wgt = np.polynomial.legendre.leggauss(16)
    half = period / 2.0
    nodes = np.concatenate(((x + 1.0) * half / 2.0, half + (x + 1.0) * half / 2.0))
    _, qg = w_hole_forces(1.0, n_holes, hole_circle_radius, nodes)
    q_mean = float(np.dot(np.concatenate((wgt, wgt)), qg) * (half / 2.0) / period)
    ends = np.array([0.0, half])                     # the extremes (even n_w: a hole on the arm, or between)
    mids = (np.arange(PHASES) + 0.5) / PHASES * period
    _, qe = w_hole_forces(1.0, n_holes, hole_circle_radius, ends)
    _, qm = w_hole_forces(1.0, n_holes, hole_circle_radius, mids)
    both = np.concatenate((qe, qm, qg))
    return float(both.min()), float(both.max()), q_mean, qm


def _arr(x, n):
    return np.zeros(n) + np.asarray(x, dtype=float)


def _col(v, name, n, default):
    vals = v.get(name) or [None] * n
    return np.array([default if x is None else x for x in vals], dtype=float)


def _bearing(pts, i, q_phases, T_sat, multiplier, exponent: float = 10.0 / 3.0):
    """Peak, mean and p-mean of |B + Q x| of point i over the crank angles and the hole phases (pins.md §4.10, §8.2).

    (peak [N], mean [N], mean of |B + Q x|^p [N^p], its error [N^p]): the error is the larger change of the p-mean
    to either of the two interleaved half grids (every other crank angle and hole phase, even or odd).
    """
    from .consistent import crank_history
    from .geometry import MULTIPLIER, REDUCER, Cycloid

    at = (lambda x: x) if pts.one else (lambda x: np.asarray(x)[i])
    g = Cycloid(int(at(pts.z1)), int(at(pts.z2)), float(at(pts.e)), float(at(pts.Rp)), float(at(pts.Rb)),
                float(at(pts.omk)))
    t = (np.arange(NODES) + 0.5) / NODES
    consistent = bool(np.asarray(pts.cons).reshape(-1)[i])
    h = crank_history(g, float(at(pts.psi_star)), t, t, float(at(pts.mu)), MULTIPLIER if multiplier else REDUCER,
                      consistent=consistent)
    B = bearing_force_with_w(h["Bx"][:, None] * T_sat, h["By"][:, None] * T_sat, q_phases[None, :] * T_sat)
    Bp = B ** exponent
    m = float(np.nanmean(Bp))
    err = max(abs(float(np.nanmean(Bp[::2, ::2])) - m), abs(float(np.nanmean(Bp[1::2, 1::2])) - m))
    return float(np.nanmax(B)), float(np.nanmean(B)), m, err


def output_fields(arrays: dict, v: dict, pts, n: int) -> dict:
    r"""The ideal level's fields with the output mechanism and the crank's drag (pins.md §4.10), n points.

    .. math:: \eta_{HV} = \frac{\eta^0_{HV}/(1+\bar\lambda_W)}{1 + u T_d \eta^0_{HV}/((1+\bar\lambda_W)|T_V|)},
        \qquad \eta_{VH} = \eta^0_{VH}(1 - \bar\lambda_W) - u\,\frac{T_d}{|T_V|}, \qquad
        T_{sat} = \frac{T_V}{n_d}(1 \pm \bar\lambda_W)

    (+ reducer: the satellite also drives the mechanism's loss; - multiplier.)  The force-like fields scale with
    T_sat; the bearing force is |B + Q x| over the crank angles and the hole phases, and so are the bearing's
    equivalent load and life (:data:`BEARING_FIELDS`, pins.md §8.2; :func:`_w_bearing`).

    Parameters
    ----------
    arrays : dict
        the ideal fields (:mod:`gearcalc.pins.columns`) of the points (arrays over them, or one point's scalars).
    v : dict
        The points' values by argument name (:data:`OUTPUT_ARGS` among them; lists, None where absent).
    pts : IdealPoints
        The points (:func:`gearcalc.pins.points.ideal_points`).
    n : int
        The number of points.

    Returns
    -------
    arrays : dict
        The fields, updated where a point has the mechanism or a drag, with :data:`NEW_FIELDS` added (and
        :data:`BEARING_FIELDS` where a point has the mechanism).

    Examples
    --------
    >>> from gearcalc.pins.columns import ideal_columns
    >>> v = dict(z1=[20], z2=[22], e=[3.9], Rp=[None], K1=[0.75], Rb=[1.95], r=[None], rotating=[False], n_d=[1],
    ...          sliding=[0.1], rolling=[None], axle=[None], mode=["multiplier"], shaft=["H"], torque=[100.0],
    ...          speed=[1000.0], face_width=[None], w_mech=["pins_in_holes"], w_holes=[8], w_radius=[35.0],
    ...          w_pin=[6.0], w_friction=[0.0], drag=[None])
    >>> cols = ideal_columns(v, 1, 1e-6, ["consistent"], [None]).columns
    >>> cols["output_mechanism"][0], round(cols["efficiency"][0], 5)      # f_w = 0: the teeth's efficiency
    ('pins_in_holes', 0.87363)

    References
    ----------
    .. [1] docs/spec/pins.md §4.10, §8.2; Sensinger 2013 (the output mechanism as a factor); Blagojević et al. 2011.
    """
    one = pts.one
    mech = [(m or "ideal") for m in (v.get("w_mech") or [None] * n)]
    drag = _col(v, "drag", n, 0.0)
    has_w = np.array([m == "pins_in_holes" for m in mech])
    active = has_w | (drag > 0.0)
    out = dict(arrays)
    nan = np.full(n, np.nan)
    new = {"output_mechanism": np.array(mech, dtype=object), "w_loss_ratio": nan.copy(),
           "w_force_max_N": nan.copy(), "backdrive_startup_torque_Nm": nan.copy()}
    if active.any():
        st = _series(out, v, pts, n, has_w, drag)
        upd = st.pop("upd")
        upd.update(_w_bearing(out, v, pts, n, has_w, st))
        sl = st["sl"]
        life = {key: upd.pop(key) for key in BEARING_FIELDS}
        for key, val in upd.items():
            out[key] = np.where(active, val, sl if key == "self_locking" else _arr(out[key], n))
        if has_w.any():
            out.update(life)
        new["w_loss_ratio"] = np.where(has_w, st["lam_w"], np.nan)
        new["w_force_max_N"] = st["wmax"]
        new["backdrive_startup_torque_Nm"] = st["start"]
        sl_new = out["self_locking"]
        out["self_locking"] = sl_new == 1.0 if not np.isnan(sl_new).any() else sl_new
        if one:
            for key in list(upd) + (list(life) if has_w.any() else []):
                x = out[key][0]
                out[key] = bool(x) if key == "self_locking" and x == x else x
    for key, val in new.items():
        out[key] = val[0] if one else val
    return out


def _series(out: dict, v: dict, pts, n: int, has_w, drag) -> dict:
    """The mechanism in series with the teeth and the crank's drag (:func:`output_fields`).

    The efficiencies, shaft torques, mean loss, self-locking and the force-like fields scaled to the satellite
    torque T_sat ("upd"), with the values the bearing needs (T_sat [N·mm], lam_w, the unit resultants q, ...).
    """
    n_w = _col(v, "w_holes", n, 0.0)
    R_w, f_w = _col(v, "w_radius", n, np.nan), _col(v, "w_friction", n, np.nan)
    sliding = _col(v, "sliding", n, np.nan)
    f_w = np.where(np.isnan(f_w), sliding, f_w)
    z1, k = _arr(pts.z1, n), _arr(pts.k, n)
    u = z1 / k
    e = _arr(pts.e, n)
    n_d = _arr(pts.n_d, n)
    mult = np.array([m == "multiplier" for m in (v["mode"])])
    on_V = np.array([s == "V" for s in v["shaft"]])
    T = _col(v, "torque", n, np.nan)
    speed = _col(v, "speed", n, np.nan)

    def get(key):
        return _arr(out[key], n)

    sl = np.zeros(n) + np.asarray(out["self_locking"], dtype=float)        # NaN: undefined
    hv0, vh0 = get("efficiency_reducer"), get("efficiency_multiplier")
    T_V_old = np.where(mult, get("torque_in_Nm"), get("torque_out_Nm"))
    q = {}
    lam_w = np.zeros(n)
    for i in np.flatnonzero(has_w):
        key = (int(n_w[i]), float(R_w[i]))
        if key not in q:
            q[key] = w_unit_resultants(*key)
        lam_w[i] = f_w[i] * e[i] * (u[i] + 1.0) * q[key][2]       # |omega_H/omega_V - 1| = u + 1 (fixed pins)
    r = series_values((hv0, vh0), lam_w, drag, T, u, mult, on_V, speed * math.pi / 30.0)
    hv, vh, locked, T_in, T_out, loss, start, T_V = (r[key] for key in (
        "eta_HV", "eta_VH", "locked", "torque_in", "torque_out", "loss", "startup", "torque_V"))
    # lambda_W >= 1 locks the multiplier by the mechanism alone: no shaft torques; the teeth stay at the given
    # torque (scale 1) and the mechanism's force is undefined, as at the contact level (pins.md §4.10)
    w_lock = mult & (lam_w >= 1.0)
    T_in, T_out, loss = (np.where(w_lock, np.nan, x) for x in (T_in, T_out, loss))
    with np.errstate(divide="ignore", invalid="ignore"):
        T_sat = np.where(w_lock, np.nan, 1e3 * T_V / n_d * r["sat_factor"])      # [N·mm]
        scale = np.where(w_lock, 1.0, np.where(T_V_old > 0.0, T_V / T_V_old * r["sat_factor"], np.nan))
    upd = {"efficiency_reducer": hv, "efficiency_multiplier": vh, "efficiency": np.where(mult, vh, hv),
           "torque_in_Nm": T_in, "torque_out_Nm": T_out, "loss_mean_W": loss,
           "self_locking": np.where(locked, 1.0, sl)}
    for key in _SCALED:
        upd[key] = get(key) * scale
    upd["contact_stress_max_MPa"] = get("contact_stress_max_MPa") * np.sqrt(scale)     # Hertz: sigma ∝ sqrt(F)
    return dict(upd=upd, sl=sl, lam_w=lam_w, q=q, n_w=n_w, R_w=R_w, mult=mult, T_sat=T_sat, scale=scale,
                speed=speed, start=start)


def _w_bearing(out: dict, v: dict, pts, n: int, has_w, st: dict) -> dict:
    """The crank bearing with the mechanism's resultant (:func:`output_fields`; pins.md §4.10, §8.2).

    Peak and mean of |B + Q x| [N], and the bearing's equivalent load and L10_h from its p-mean over the crank
    angles and the hole phases (:func:`gearcalc.pins.outputs.bearing_life`); the points without the mechanism
    keep the teeth's, scaled to their T_sat.  Sets ``st["wmax"]``, the resultant's peak [N].
    """
    from .outputs import bearing_life

    n_w, R_w, mult, T_sat, q = st["n_w"], st["R_w"], st["mult"], st["T_sat"], st["q"]
    bmax, bmean = _arr(out["bearing_force_max_N"], n) * st["scale"], _arr(out["bearing_force_mean_N"], n) * st["scale"]
    wmax, pm, dpm = np.full(n, np.nan), np.full(n, np.nan), np.full(n, np.nan)
    p = np.where(np.isnan(_col(v, "bearing_p", n, np.nan)), 10.0 / 3.0, _col(v, "bearing_p", n, np.nan))
    ok = (np.zeros(n) + np.asarray(pts.status)) == 0                 # admissible gears only
    gi = np.zeros(n, dtype=np.int64) + np.asarray(pts.gi).reshape(-1)[:n] if not pts.one else np.zeros(1, np.int64)
    mu = _arr(pts.mu, n)
    cons = np.zeros(n, dtype=bool) | np.asarray(pts.cons).reshape(-1)[:n]
    unit = {}          # |B + Q x| is linear in T_sat: one unit-torque history per gear, friction, mode, holes, p
    for i in np.flatnonzero(has_w & np.isfinite(T_sat) & ok):
        qmin, qmax, qmean, qph = q[(int(n_w[i]), float(R_w[i]))]
        key = (int(gi[i]), float(mu[i]), bool(mult[i]), bool(cons[i]), int(n_w[i]), float(R_w[i]), float(p[i]))
        if key not in unit:
            unit[key] = _bearing(pts, i, qph, 1.0, bool(mult[i]), float(p[i]))
        bmax[i], bmean[i] = unit[key][0] * T_sat[i], unit[key][1] * T_sat[i]
        pm[i], dpm[i] = unit[key][2], unit[key][3]
        wmax[i] = qmax * T_sat[i]
    st["wmax"] = wmax
    with np.errstate(divide="ignore", invalid="ignore"):
        life = bearing_life(pm, dpm, p, np.abs(T_sat), _col(v, "bearing_C", n, np.nan), st["speed"])
    return dict(bearing_force_max_N=bmax, bearing_force_mean_N=bmean, **dict(zip(BEARING_FIELDS, life)))


def w_bearing_columns(columns: dict, arrays: dict, n: int) -> dict:
    r"""The bearing's life columns (:data:`BEARING_FIELDS`) with the mechanism's values where a point has it.

    A point with pins_in_holes takes the equivalent load and life of |B + Q x| (:func:`output_fields`), the others
    keep the teeth's (pins.md §8.2), and so does a point whose mechanism's force is undefined (``w_force_max_N``
    NaN: a multiplier that lambda_W >= 1 locks runs its teeth at the given torque, as the contact level).

    .. math:: P = T_{sat}\Big(\frac{1}{N M}\sum_{i,j} \hat B_W(\theta_i, \varphi_j)^p\Big)^{1/p}, \qquad
        L_{10h} = \frac{10^6}{60\,n_H}\Big(\frac{C}{P}\Big)^p

    Parameters
    ----------
    columns : dict
        The teeth's columns (:func:`gearcalc.pins.report.bearing_columns`: lists over the n points, None: undefined).
    arrays : dict
        :func:`output_fields`'s fields, which hold :data:`BEARING_FIELDS` when a point has pins_in_holes (NaN for the
        others).
    n : int
        The number of points.

    Returns
    -------
    dict
        The columns to update with (``columns`` itself when no point has the mechanism).

    Examples
    --------
    >>> cols = {k: [1.0, 2.0] for k in BEARING_FIELDS}
    >>> arr = {**{k: np.array([5.0, np.nan]) for k in BEARING_FIELDS}, "w_force_max_N": np.array([9.0, np.nan]),
    ...        "output_mechanism": np.array(["pins_in_holes", "ideal"], dtype=object)}
    >>> w_bearing_columns(cols, arr, 2)["bearing_L10_h"]
    [5.0, 2.0]

    References
    ----------
    .. [1] ISO 281:2007 (the mean load of a varying load); docs/spec/pins.md §4.10, §8.2.
    """
    if BEARING_FIELDS[0] not in arrays:
        return columns
    out = {}
    for key in BEARING_FIELDS:
        w = np.broadcast_to(np.asarray(arrays[key], dtype=float), (n,))
        mech = np.broadcast_to(np.asarray(arrays["output_mechanism"], dtype=object), (n,))
        has_q = np.isfinite(np.broadcast_to(np.asarray(arrays.get("w_force_max_N", np.nan), dtype=float), (n,)))
        out[key] = [(None if not math.isfinite(x) else x) if m == "pins_in_holes" and q else c
                    for x, m, q, c in zip(w.tolist(), mech.tolist(), has_q.tolist(), columns[key])]
    return {**columns, **out}
