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

    Examples
    --------
    >>> round(float(rolling_margin(0.1, 1.95, 0.1, 0.95, 0.01)), 12)   # (0.195 - 0.105)/0.195
    0.461538461538
    >>> round(float(rolling_margin(0.01, 1.95, 0.1, 0.95, 0.01)), 12)   # (0.0195 - 0.105)/0.105
    -0.814285714286
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

    Examples
    --------
    >>> self_locking_margin([True, False, True, True], [0.2, 0.25, 1.5, np.nan], [False, False, True, True]).tolist()
    [0.8, 0.8, -0.5, -1.0]
    """
    lam = np.asarray(loss_ratio, dtype=float)
    with np.errstate(invalid="ignore", divide="ignore"):
        raw = np.where(np.asarray(multiplier, dtype=bool), 1.0 - lam, 1.0 / (1.0 + lam))
    raw = np.where(np.isnan(raw), -1.0, raw)
    locked = np.asarray(locked, dtype=bool)
    return np.where(locked, np.minimum(raw, -_TINY), np.maximum(raw, 0.0))


def stress_margin(stress, allowable):
    r"""The contact stress check as a margin: 1 - sigma_max/[sigma_H], written as a difference first so that its
    sign is exactly that of [sigma_H] - sigma_max (NaN where either is undefined).

    .. math:: m_{stress} = \frac{[\sigma_H] - \sigma_{max}}{[\sigma_H]}

    Examples
    --------
    >>> stress_margin([1000.0, 2500.0, np.nan], [2000.0, 2000.0, 2000.0]).tolist()[:2]
    [0.5, -0.25]
    """
    allow = np.asarray(allowable, dtype=float)
    return (allow - np.asarray(stress, dtype=float)) / allow


def margin_columns(cols: dict, v: dict) -> dict:
    """margin_self_locking, margin_rolling, margin_contact_stress and failed_checks of the summary columns ``cols``
    (lists over n points; None where undefined) and the points' values ``v`` (by argument name, lists): the
    self-locking margin where the summary has ``self_locking`` (the cycle levels), the rolling margin where it
    has ``rolling_ok`` (rotating pins), the stress margin where it has a contact stress and the point an allowable
    stress."""
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
