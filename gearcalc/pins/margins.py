"""The design checks of the ``pins`` calculator as margins (pins.md §8 "Checks"; architecture convention 10).

Each check is a signed, dimensionless margin, >= 0 passes, < 0 fails, None where it does not apply; the summary's
``failed_checks`` names the failing ones.  Pure functions over the summary's columns (lists over designs or sweep
points, None where undefined) and the points' values: one design, a batch and a sweep call the same functions.
"""
from __future__ import annotations

__all__ = ["CHECKS", "rolling_margin", "self_locking_margin", "stress_margin", "margin_columns"]

import numpy as np

from ..calculator import failed_check_column
from .checks import CHECKS

_TINY = float(np.nextafter(0.0, 1.0))


def _floats(values) -> np.ndarray:
    return np.array([np.nan if v is None else v for v in values], dtype=float)


def _plain(arr, defined) -> list:
    return [float(x) if ok else None for x, ok in zip(arr.tolist(), defined.tolist())]


def rolling_margin(sliding, bushing_radius, axle_friction, axle_radius, rolling):
    r"""The rolling condition f R_b >= f_c r + f_k (pins.md §4.5) as a margin, >= 0 exactly where it holds.

    .. math:: m_{rolling} = \frac{f R_b - (f_c r + f_k)}{\max(f R_b,\ f_c r + f_k)}

    In [-1, 1]: the drive's excess over the resistance as a fraction of the larger; 0 where both are 0 (the
    condition holds with equality).  Its sign is that of the difference of the two products the condition compares.

    Parameters
    ----------
    sliding : float or array_like
        The pin-tooth sliding friction coefficient f [-].
    bushing_radius : float or array_like
        The pin's bushing radius R_b [mm].
    axle_friction : float or array_like
        The axle friction coefficient f_c [-].
    axle_radius : float or array_like
        The axle radius r [mm].
    rolling : float or array_like
        The rolling friction coefficient f_k [mm].

    Returns
    -------
    margin : ndarray
        The rolling margin [-], in [-1, 1].

    Examples
    --------
    >>> round(float(rolling_margin(0.1, 1.95, 0.1, 0.95, 0.01)), 12)   # (0.195 - 0.105)/0.195
    0.461538461538
    >>> round(float(rolling_margin(0.01, 1.95, 0.1, 0.95, 0.01)), 12)   # (0.0195 - 0.105)/0.105
    -0.814285714286

    References
    ----------
    .. [1] Prudnikov, KHV planetary pin gearing: friction losses and efficiency (seed 000); gearcalc
       specification docs/spec/pins.md §4.5, §4.7, §4.9, §8 "Checks".
    """
    drive = np.asarray(sliding, dtype=float) * np.asarray(bushing_radius, dtype=float)
    resist = np.asarray(axle_friction, dtype=float) * np.asarray(axle_radius, dtype=float) + np.asarray(rolling,
                                                                                                    dtype=float)
    big = np.maximum(drive, resist)
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(big > 0, (drive - resist) / np.where(big > 0, big, 1.0), 0.0)


def self_locking_margin(multiplier, loss_ratio, locked):
    r"""Self-locking as a margin: the requested mode's efficiency, 0 at the locking limit (pins.md §4.7, §4.9).

    .. math:: m_{lock} = 1 - \bar\lambda \ \text{(multiplier)}, \qquad m_{lock} = \frac{1}{1 + \bar\lambda}
              \ \text{(reducer)}

    A multiplier self-locks at lambda >= 1 (its efficiency 1 - lambda <= 0); a reducer's efficiency falls to 0 as
    its loss ratio grows without bound toward a jam.  A mode that jams (no loss ratio: no positive normal force at
    some crank angle) has -1.  The sign follows ``locked`` (the summary's ``self_locking``) exactly: at the limit
    itself (lambda = 1), and for a contact-level reducer whose losses alone exceed the input (``stalled``), the
    margin is the least negative float, never 0.

    Parameters
    ----------
    multiplier, locked : array_like of bool
        The requested mode is the multiplier; it self-locks.
    loss_ratio : array_like of float
        Its loss ratio (NaN where it jams).

    Returns
    -------
    margin : ndarray
        The self-locking margin [-]: >= 0 runs, < 0 self-locks (-1 jams).

    Examples
    --------
    >>> self_locking_margin([True, False, True, True], [0.2, 0.25, 1.5, np.nan], [False, False, True, True]).tolist()
    [0.8, 0.8, -0.5, -1.0]

    References
    ----------
    .. [1] Prudnikov, KHV planetary pin gearing: friction losses and efficiency (seed 000); gearcalc
       specification docs/spec/pins.md §4.5, §4.7, §4.9, §8 "Checks".
    """
    lam = np.asarray(loss_ratio, dtype=float)
    with np.errstate(invalid="ignore", divide="ignore"):
        raw = np.where(np.asarray(multiplier, dtype=bool), 1.0 - lam, 1.0 / (1.0 + lam))
    raw = np.where(np.isnan(raw), -1.0, raw)
    locked = np.asarray(locked, dtype=bool)
    return np.where(locked, np.minimum(raw, -_TINY), np.maximum(raw, 0.0))


def stress_margin(stress, allowable):
    r"""The contact stress check as a margin: 1 - sigma_max/[sigma_H].

    Written as a difference first so that its sign is exactly that of [sigma_H] - sigma_max (NaN where either is
    undefined).

    .. math:: m_{stress} = \frac{[\sigma_H] - \sigma_{max}}{[\sigma_H]}

    Parameters
    ----------
    stress : array_like
        The largest pin-tooth Hertz contact stress sigma_max [MPa].
    allowable : array_like
        The allowable contact stress [sigma_H] [MPa].

    Returns
    -------
    margin : ndarray
        The contact-stress margin [-]: >= 0 passes.

    Examples
    --------
    >>> stress_margin([1000.0, 2500.0, np.nan], [2000.0, 2000.0, 2000.0]).tolist()[:2]
    [0.5, -0.25]

    References
    ----------
    .. [1] Prudnikov, KHV planetary pin gearing: friction losses and efficiency (seed 000); gearcalc
       specification docs/spec/pins.md §5.4, §8 "Checks".
    """
    allow = np.asarray(allowable, dtype=float)
    return (allow - np.asarray(stress, dtype=float)) / allow


def margin_columns(cols: dict, v: dict) -> dict:
    """The margins and failed checks of summary columns: the three margins above over n points at once.

    The self-locking margin where the summary has ``self_locking`` (the cycle levels), the rolling margin where it
    has ``rolling_ok`` (rotating pins), the stress margin where it has a contact stress and the point an allowable
    stress; None where a check does not apply.

    Parameters
    ----------
    cols : dict of list
        Summary columns over n points (``self_locking``, ``mode``, ``loss_ratio``, ``rolling_ok``,
        ``contact_stress_max_MPa``; None where undefined).
    v : dict of list
        The points' values by argument name: ``sliding``, ``Rb``, ``axle``, ``r``, ``rolling`` and optionally
        ``allowable`` [MPa].

    Returns
    -------
    dict of list
        ``margin_self_locking``, ``margin_rolling``, ``margin_contact_stress`` [-] and ``failed_checks``.

    Examples
    --------
    >>> cols = {"self_locking": [False], "mode": ["reducer"], "loss_ratio": [0.25], "rolling_ok": [None],
    ...         "contact_stress_max_MPa": [1000.0]}
    >>> out = margin_columns(cols, {"allowable": [2000.0]})
    >>> out["margin_self_locking"], out["margin_rolling"], out["margin_contact_stress"], out["failed_checks"]
    ([0.8], [None], [0.5], [[]])

    References
    ----------
    .. [1] Prudnikov, KHV planetary pin gearing: friction losses and efficiency (seed 000); gearcalc
       specification docs/spec/pins.md §4.5, §4.7, §4.9, §8 "Checks".
    """
    locked = cols["self_locking"]
    has_lock = np.array([x is not None for x in locked])
    lock = self_locking_margin([m == "multiplier" for m in cols["mode"]], _floats(cols["loss_ratio"]),
                               [bool(x) for x in locked])
    has_roll = np.array([x is not None for x in cols["rolling_ok"]])
    roll = rolling_margin(*(_floats(v[k]) for k in ("sliding", "Rb", "axle", "r", "rolling"))) if has_roll.any() \
        else np.zeros(len(locked))
    stress = stress_margin(_floats(cols["contact_stress_max_MPa"]), _floats(v.get("allowable", [None] * len(locked))))
    out = {"margin_self_locking": _plain(lock, has_lock), "margin_rolling": _plain(roll, has_roll & ~np.isnan(roll)),
           "margin_contact_stress": _plain(stress, ~np.isnan(stress))}
    out["failed_checks"] = failed_check_column(out, CHECKS, len(locked))
    return out
