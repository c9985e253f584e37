"""KHV pin gearing: a duty cycle of operating points evaluated as one design (pins.md §8.3; issue 37 item 5).

Pure functions on the per-row summaries; the rows themselves are computed by the calculator
(:mod:`gearcalc.kinds.pins`), at the ideal level all together (vectorised over the operating points).
"""
from __future__ import annotations

import math

__all__ = ["DUTY_KEYS", "duty_combine"]

DUTY_KEYS = ("duty_rows", "duty_efficiency", "duty_efficiency_err", "duty_loss_mean_W",
             "duty_bearing_equivalent_load_N", "duty_bearing_equivalent_load_err_N", "duty_bearing_L10_h",
             "duty_bearing_L10_h_err", "duty_contact_stress_max_MPa", "duty_contact_stress_max_row")
"""The summary fields of a duty cycle (null without a ``[duty]`` table)."""


def _weighted(values, weights):
    """Sum of w v over sum of w, or None where a value is missing."""
    if any(v is None for v in values):
        return None
    return math.fsum(w * v for v, w in zip(values, weights)) / math.fsum(weights)


def duty_combine(rows, share, speed, exponent, rating):
    r"""One duty cycle from its rows' results: mean efficiency and loss, the bearing's equivalent load and life.

    Row i runs a time share t_i at crank speed n_i with the row's results (its efficiency eta_i, mean loss P_i,
    the crank bearing's equivalent load F_i, contact stress sigma_i).  The bearing's equivalent load over the
    cycle weights the rows by the revolutions they turn (ISO 281, variable load and speed); the life in hours is
    that life in revolutions at the time-weighted mean crank speed; efficiency and loss are time-weighted (the
    efficiency's error likewise, an upper bound); the equivalent load's error is carried to first order.

    .. math::

        F_{eq} = \left(\frac{\sum_i t_i n_i F_i^p}{\sum_i t_i n_i}\right)^{1/p},\qquad
        \bar n = \frac{\sum_i t_i n_i}{\sum_i t_i},\qquad
        L_{10h} = \frac{10^6}{60\,\bar n}\left(\frac{C}{F_{eq}}\right)^p,\qquad
        \bar\eta = \frac{\sum_i t_i \eta_i}{\sum_i t_i},\qquad
        \delta F_{eq} = \frac{\sum_i t_i n_i F_i^{p-1}\,\delta F_i}{\sum_i t_i n_i F_{eq}^{p-1}}

    Parameters
    ----------
    rows : list of dict
        Each row's summary (``efficiency``, ``efficiency_err``, ``loss_mean_W``, ``bearing_equivalent_load_N``,
        ``bearing_equivalent_load_err_N``, ``contact_stress_max_MPa``; None: undefined).
    share : list of float
        t_i, the rows' time shares [-] (any positive scale: they are normalised).
    speed : list of float
        n_i, the rows' crank speeds [rpm].
    exponent : float
        p, the ISO 281 life exponent [-] (3 ball, 10/3 roller bearings).
    rating : float or None
        C, the bearing's basic dynamic load rating [N] (None: no life).

    Returns
    -------
    dict
        The :data:`DUTY_KEYS` fields: the row count; the efficiency [-] and its error; the mean loss [W]; the
        equivalent load [N] and its error; L10_h [h] and its error; the largest contact stress [MPa] and the row
        (1-based) that sets it.  None where a row leaves a value undefined (a self-locking row: no efficiency).

    Examples
    --------
    Two rows of equal time at 1000 and 3000 rpm with bearing loads 2 kN and 1 kN, a ball bearing (p = 3) of
    C = 10 kN: F_eq = ((1000·8 + 3000·1)/4000)^(1/3) kN, n̄ = 2000 rpm.

    >>> r = [dict(efficiency=0.9, efficiency_err=1e-9, loss_mean_W=10.0, bearing_equivalent_load_N=2000.0,
    ...           bearing_equivalent_load_err_N=0.0, contact_stress_max_MPa=900.0),
    ...      dict(efficiency=0.8, efficiency_err=1e-9, loss_mean_W=30.0, bearing_equivalent_load_N=1000.0,
    ...           bearing_equivalent_load_err_N=0.0, contact_stress_max_MPa=700.0)]
    >>> d = duty_combine(r, [1.0, 1.0], [1000.0, 3000.0], 3.0, 10000.0)
    >>> round(d["duty_bearing_equivalent_load_N"], 6), round(d["duty_efficiency"], 12), d["duty_contact_stress_max_row"]
    (1401.019665, 0.85, 1)

    References
    ----------
    .. [1] ISO 281:2007, Rolling bearings -- Dynamic load ratings and rating life (the mean load of a varying
       load and speed).
    .. [2] docs/spec/pins.md §8.3.
    """
    p = float(exponent)
    rev = [t * n for t, n in zip(share, speed)]
    out = dict.fromkeys(DUTY_KEYS)
    out["duty_rows"] = len(rows)
    out["duty_efficiency"] = _weighted([r["efficiency"] for r in rows], share)
    out["duty_efficiency_err"] = _weighted([r["efficiency_err"] for r in rows], share)
    out["duty_loss_mean_W"] = _weighted([r["loss_mean_W"] for r in rows], share)
    out.update(_duty_bearing(rows, rev, share, p, rating))
    stress = [r["contact_stress_max_MPa"] for r in rows]
    if all(s is not None for s in stress) and stress:
        i = max(range(len(stress)), key=lambda j: stress[j])
        out["duty_contact_stress_max_MPa"], out["duty_contact_stress_max_row"] = stress[i], i + 1
    return out


def _duty_bearing(rows, rev, share, p: float, rating) -> dict:
    """The duty's bearing fields of :func:`duty_combine`.

    The revolution-weighted p-mean of the rows' equivalent loads, its first-order error, and L10_h at the
    time-weighted mean speed (empty where a row has no load).
    """
    F = [r["bearing_equivalent_load_N"] for r in rows]
    dF = [r["bearing_equivalent_load_err_N"] for r in rows]
    out = {}
    if all(f is not None for f in F) and all(d is not None for d in dF) and math.fsum(rev) > 0.0:
        mean = math.fsum(w * f ** p for w, f in zip(rev, F)) / math.fsum(rev)
        F_eq = mean ** (1.0 / p)
        out["duty_bearing_equivalent_load_N"] = F_eq
        err = (math.fsum(w * f ** (p - 1.0) * d for w, f, d in zip(rev, F, dF))
               / (math.fsum(rev) * F_eq ** (p - 1.0))) if F_eq > 0.0 else 0.0
        out["duty_bearing_equivalent_load_err_N"] = err
        if rating is not None and F_eq > 0.0:
            n_mean = math.fsum(rev) / math.fsum(share)
            life = 1e6 / (60.0 * n_mean) * (float(rating) / F_eq) ** p
            out["duty_bearing_L10_h"] = life
            out["duty_bearing_L10_h_err"] = p * life * err / F_eq
    return out
