r"""KHV pin gearing, level ``contact``: the output mechanism and the crank's drag in its summary (pins.md §4.10).

The ideal level's rules (:mod:`gearcalc.pins.wmech`, as :mod:`gearcalc.pins.output_mech` applies them) on the
contact level of one design: the teeth are solved at the torque they carry (:func:`~gearcalc.pins.wmech.teeth_torque`:
the drag added or taken on H, the satellite torque T_V (1 -+ lambda_W) on V), so their forces, losses, crank torque
and bearing-force history B(theta) are those of the satellite torque T_sat = T_V (1 -+ lambda_W)/n_d; their two
efficiencies go in series with the mechanism and the drag (:func:`~gearcalc.pins.wmech.series_values`), and the
crank bearing carries |B(theta) + Q(phi) x| over the contact level's crank angles and the hole phases
(:func:`~gearcalc.pins.wmech.w_bearing_peak_mean`).  The ``"ideal"`` mechanism without a drag changes nothing.

Units N, mm, N·mm, N·m, rpm, W.
"""
from __future__ import annotations

import math
from typing import NamedTuple

__all__ = ["ContactW", "contact_w", "contact_output_fields"]


class ContactW(NamedTuple):
    """The output mechanism and the drag of one contact-level design (:func:`contact_w`).

    mechanism : "ideal" or "pins_in_holes"; loss_ratio : lambda-bar_W [-] (0: ideal); drag : T_d [N·m];
    unit : :func:`gearcalc.pins.output_mech.w_unit_resultants` (None: ideal); teeth_torque : the torque the teeth
    carry on the given shaft [N·m].
    """

    mechanism: str
    loss_ratio: float
    drag: float
    unit: tuple | None
    teeth_torque: float

    @property
    def active(self) -> bool:
        """Whether the mechanism or a drag changes the pure-torque, drag-free results."""
        return self.unit is not None or self.drag > 0.0


def contact_w(a: dict, ratio: float) -> ContactW:
    r"""The mechanism's mean loss ratio and the teeth's torque of a contact-level design (pins.md §4.10).

    .. math:: \bar\lambda_W = f_w\,e\,(u + 1)\,\overline{Q/T}, \qquad \overline{Q/T} = \frac{4}{\pi R_w}
        \ \text{(even } n_w)

    (|omega_H/omega_V - 1| = u + 1 with fixed pins; f_w is ``output.friction``, else ``friction.sliding``.  A
    multiplier with lambda_W >= 1 self-locks through the mechanism: no positive satellite torque, its teeth are
    solved at the given torque.)

    Parameters
    ----------
    a : dict
        The design's values by argument name (:data:`gearcalc.pins.output_keys.OUTPUT_ARGS`, ``e`` [mm],
        ``sliding``, ``mode``, ``shaft``, ``torque`` [N·m]; None: absent).
    ratio : float
        u = z1/k, [-].

    Returns
    -------
    ContactW

    Examples
    --------
    >>> w = contact_w(dict(w_mech="pins_in_holes", w_holes=8, w_radius=35.0, w_friction=0.05, drag=None, e=3.9,
    ...                    sliding=0.1, mode="multiplier", shaft="V", torque=100.0), 10.0)
    >>> round(w.loss_ratio / (4 * 0.05 * 3.9 * 11 / (math.pi * 35.0)), 12), w.teeth_torque == 100.0 * (1 - w.loss_ratio)
    (1.0, True)

    References
    ----------
    .. [1] docs/spec/pins.md §4.10.
    """
    from .wmech import teeth_torque

    mech, drag = a.get("w_mech") or "ideal", float(a.get("drag") or 0.0)
    lam, unit = 0.0, None
    if mech == "pins_in_holes":
        from .output_mech import w_unit_resultants

        unit = w_unit_resultants(int(a["w_holes"]), float(a["w_radius"]))
        f_w = a["sliding"] if a.get("w_friction") is None else a["w_friction"]
        lam = f_w * a["e"] * (ratio + 1.0) * unit[2]
    mult = a["mode"] == "multiplier"
    locks = mult and lam >= 1.0         # the mechanism alone self-locks the multiplier: its teeth at the given torque
    T = a["torque"] if unit is None and drag == 0.0 else float(
        teeth_torque(a["torque"], 0.0 if locks else lam, drag, mult, a["shaft"] == "V"))
    return ContactW(mech, lam, drag, unit, T)


def _num(x):
    x = float(x)
    return x if math.isfinite(x) else None


def contact_output_fields(w: ContactW, summary: dict, cl, a: dict, ratio: float, n_discs: int):
    r"""The contact level's summary fields with the output mechanism and the drag (pins.md §4.10).

    .. math:: \eta = \text{series\_values}(\eta^{teeth}_{HV}, \eta^{teeth}_{VH}, \bar\lambda_W, T_d), \qquad
        B_W = \max / \text{mean}\ |B(\theta) + Q(\varphi)\,x|, \qquad Q = \frac{Q}{T}(\varphi)\,T_{sat}

    Parameters
    ----------
    w : ContactW
        :func:`contact_w` of the design.
    summary : dict
        The contact level's summary of the teeth (solved at ``w.teeth_torque``).
    cl : ContactLevel
        :func:`gearcalc.pins.contact_level.contact_level`'s result (``locked``, ``et_reducer``,
        ``et_multiplier``, ``crank``).
    a : dict
        The design's values by argument name (``mode``, ``shaft``, ``torque`` [N·m], ``speed`` [rpm]).
    ratio : float
        u = z1/k, [-].
    n_discs : int
        n_d.

    Returns
    -------
    fields : dict
        The fields to update (``output_mechanism`` always; the efficiencies, torques, mean loss, self-locking,
        bearing force and the mechanism's fields when it or a drag is there).
    failed : list of str
        The failed check of a requested multiplier that cannot be back-driven (the load below the start-up
        torque), else empty.

    Examples
    --------
    A drag of 1 N·m on teeth of efficiencies 0.8 and 0.75, u = 10, 100 N·m on V (pins.md §4.10: 0.75 - 10/100):

    >>> from types import SimpleNamespace as NS
    >>> cl = NS(locked={True: False, False: False}, et_reducer=NS(eta_hv=[0.8]), et_multiplier=NS(eta_vh=[0.75]))
    >>> a = dict(mode="multiplier", shaft="V", torque=100.0, speed=None)
    >>> f, failed = contact_output_fields(ContactW("ideal", 0.0, 1.0, None, 100.0), {"self_locking": False}, cl, a,
    ...                                   10.0, 1)
    >>> round(f["efficiency"], 12), round(f["backdrive_startup_torque_Nm"], 9), failed
    (0.65, 13.333333333, [])

    References
    ----------
    .. [1] docs/spec/pins.md §4.10.
    """
    from .report import output_lock_text
    from .wmech import series_values

    out = {"output_mechanism": w.mechanism, "w_loss_ratio": None, "w_force_max_N": None,
           "backdrive_startup_torque_Nm": None}
    if not w.active:
        return out, []
    mult, locked = a["mode"] == "multiplier", cl.locked
    hv0 = math.nan if locked[False] else float(cl.et_reducer.eta_hv[0])
    vh0 = math.nan if locked[True] else float(cl.et_multiplier.eta_vh[0])
    w_H = math.nan if a["speed"] is None else a["speed"] * math.pi / 30.0      # as the ideal level
    r = {k: float(v) for k, v in series_values((hv0, vh0), w.loss_ratio, w.drag, a["torque"], ratio, mult,
                                                a["shaft"] == "V", w_H).items()}
    drag_locked = bool(r["locked"]) and not locked[True]
    lock = bool(summary["self_locking"]) or drag_locked
    out.update(efficiency_reducer=_num(r["eta_HV"]), efficiency_multiplier=_num(r["eta_VH"]), self_locking=lock)
    out["efficiency"] = out["efficiency_multiplier" if mult else "efficiency_reducer"]
    out["torque_in_Nm"] = None if lock else _num(r["torque_in"])
    out["torque_out_Nm"] = None if lock else _num(r["torque_out"])
    if summary.get("loss_mean_W") is not None:
        out["loss_mean_W"] = None if lock else _num(r["loss"])
    if w.drag > 0.0:
        out["backdrive_startup_torque_Nm"] = _num(r["startup"])
    if w.unit is not None:
        out["w_loss_ratio"] = w.loss_ratio
        out.update(_w_bearing(w, cl.crank, r, a, n_discs))
    return out, [output_lock_text(out["backdrive_startup_torque_Nm"], w.loss_ratio)] if drag_locked else []


def _w_bearing(w: ContactW, cb, r: dict, a: dict, n_discs: int) -> dict:
    """The crank bearing with the mechanism's resultant at the series values' satellite torque.

    For :func:`contact_output_fields` (``r``: its series values): the mechanism's peak force, the bearing's peak and
    mean of |B + Q x| and its life (:func:`_w_bearing_life`); none when lambda_W >= 1 locks the multiplier
    (pins.md §4.10).
    """
    import numpy as np

    from .wmech import w_bearing_peak_mean

    T_sat = 1e3 * r["torque_V"] * r["sat_factor"] / n_discs             # [N·mm]
    if not (r["torque_V"] > 0.0 and r["sat_factor"] > 0.0 and cb is not None):
        return {}
    Q = np.asarray(w.unit[3]) * T_sat
    peak, mean = w_bearing_peak_mean(cb.bearing_radial, cb.bearing_tangential, Q, cb.mean_weights)
    return {"w_force_max_N": w.unit[1] * T_sat, "bearing_force_max_N": peak, "bearing_force_mean_N": mean,
            **_w_bearing_life(cb, Q, a)}


def _w_bearing_life(cb, w_resultants, a: dict) -> dict:
    """The crank bearing's equivalent load and L10_h with the mechanism's resultant (pins.md §4.10, §8.2).

    The p-mean of |B(theta) + Q(phi) x| with the cycle mean's weights over the contact level's crank angles and
    the plain mean over the hole phases; its error the difference from the plain trapezoid's p-mean, as for the
    teeth's bearing force alone (``kinds.pins._contact_bearing_fields``).
    """
    import numpy as np

    from .outputs import bearing_life
    from .report import BEARING_KEYS
    from .wmech import bearing_force_with_w

    if cb.mean_weights is None:
        return {}
    p = 10.0 / 3.0 if a.get("bearing_p") is None else float(a["bearing_p"])
    B = bearing_force_with_w(np.asarray(cb.bearing_radial, dtype=float)[:, None],
                             np.asarray(cb.bearing_tangential, dtype=float)[:, None],
                             np.asarray(w_resultants, dtype=float)[None, :])
    Bp = (B ** p).mean(axis=1)
    m = float(np.dot(cb.mean_weights, Bp))
    dm = abs(m - float(np.dot(cb.trapezoid_weights, Bp)))
    C, n = a.get("bearing_C"), a.get("speed")
    vals = bearing_life(m, dm, p, 1.0, math.nan if C is None else C, math.nan if n is None else n)
    return {k: (float(v) if math.isfinite(float(v)) else None) for k, v in zip(BEARING_KEYS, vals)}
