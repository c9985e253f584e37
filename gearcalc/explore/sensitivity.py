"""``gearcalc sensitivity``: which varied key drives each output, by Sobol' indices or Morris screening.

**Sobol'** (default): Saltelli's scheme.  A scrambled Sobol' sequence of ``N`` points in ``2d`` dimensions gives
the matrices ``A`` (its first ``d`` columns) and ``B`` (the last ``d``); ``AB_i`` is ``A`` with column ``i`` from
``B``; the ``N (d + 2)`` points ``A, B, AB_1 .. AB_d`` are evaluated (as one sample: the grid sweep's chunks).
With the outputs standardised (mean 0, standard deviation 1 over all points, as SALib does), the estimators are
those of Saltelli et al. (2010), eq. (b) of Table 2 for the first order and Jansen's (f) for the total order:

.. math::
    S_i = \\frac{\\overline{f(B)\\,(f(AB_i) - f(A))}}{V}, \\qquad
    S_{Ti} = \\frac{\\overline{(f(A) - f(AB_i))^2}}{2V}, \\qquad V = \\operatorname{var}[f(A), f(B)]

Their confidence intervals: ``z_{0.975}`` times the standard deviation of the estimates over
:data:`RESAMPLES` bootstrap resamples of the ``N`` rows (a 95 % interval).

**Morris** (``--method morris``): ``N`` one-at-a-time trajectories on a ``p = 4`` level grid (Morris 1991; step
``Δ = p / (2 (p - 1))`` of the unit range), each key moved once per trajectory; the elementary effect of key ``i``
is ``(f(x + Δ e_i) - f(x)) / Δ`` (in output units per whole range); ``μ*`` is the mean of their absolute values
(with a bootstrap 95 % interval), ``σ`` their standard deviation (``ddof = 1``), ``μ`` their mean.

The dominant key of an output is the one of the largest total index (Morris: ``μ*``).  An output that does not
vary over the sample (:func:`_constant`: a key not varied and echoed, a margin defined nowhere) is left out of the
indices and the dominant keys, and one note names them: every index of it would be 0.  A point that is not a
valid design, or whose output is empty, drops its row of the scheme (``A``, ``B`` and every ``AB_i`` of it; a
Morris trajectory) for that output; the count is in the notes.  ``tests/explore/test_sensitivity.py`` checks these
estimators against SALib on the same samples and against the Ishigami function's closed-form indices.

References: A. Saltelli, P. Annoni, I. Azzini, F. Campolongo, M. Ratto, S. Tarantola, "Variance based sensitivity
analysis of model output. Design and estimator for the total sensitivity index", Computer Physics Communications
181 (2010) 259-270; M. D. Morris, "Factorial sampling plans for preliminary computational experiments",
Technometrics 33 (1991) 161-174; F. Campolongo, J. Cariboni, A. Saltelli, "An effective screening design for
sensitivity analysis of large models", Environmental Modelling & Software 22 (2007) 1509-1518 (μ*).
"""
from __future__ import annotations

from dataclasses import dataclass, field

__all__ = ["METHODS", "SensitivityResult", "saltelli_unit", "sobol_indices", "morris_unit", "morris_effects",
           "sensitivity_design"]

METHODS = ("sobol", "morris")
SAMPLES = {"sobol": 256, "morris": 64}
"""The default ``--samples``: the base size N of Saltelli's scheme (N (d+2) points), or Morris trajectories
(N (d+1) points)."""
RESAMPLES = 200
LEVELS = 4
MAX_POINTS = 1_000_000


class SensitivityError(ValueError):
    """A malformed ``--method`` or ``--samples``, or an analysis with nothing to analyse."""


def saltelli_unit(n: int, d: int, seed: int = 0):
    """The unit coordinates of Saltelli's scheme: ``(A, B, AB)`` with ``AB[i]`` the matrix ``AB_i`` (each
    ``n x d``), from a scrambled Sobol' sequence in ``2d`` dimensions."""
    import numpy as np

    from .sample import unit_sample

    base = unit_sample("sobol", n, 2 * d, seed)
    A, B = base[:, :d], base[:, d:]
    AB = np.repeat(A[None, :, :], d, axis=0)
    for i in range(d):
        AB[i, :, i] = B[:, i]
    return A, B, AB


def _s1(fA, fB, fAB, var):
    import numpy as np

    return np.mean(fB * (fAB - fA), axis=-1) / var


def _st(fA, fAB, var):
    import numpy as np

    return 0.5 * np.mean((fA - fAB) ** 2, axis=-1) / var


def sobol_indices(fA, fB, fAB, resamples: int = RESAMPLES, seed: int = 0, conf: float = 0.95) -> dict:
    """First-order and total Sobol' indices with bootstrap confidence half-widths, from the outputs at ``A``
    and ``B`` (``n``) and at ``AB_i`` (``d x n``): ``{"S1", "S1_conf", "ST", "ST_conf"}`` (arrays of ``d``).
    The outputs are standardised first; a constant output has every index 0.

    >>> import numpy as np
    >>> A, B, AB = saltelli_unit(1024, 2)
    >>> f = lambda x: x[..., 0]                      # only the first input matters: S = (1, 0)
    >>> s = sobol_indices(f(A), f(B), f(AB))
    >>> np.round(s["S1"], 2).tolist(), np.round(s["ST"], 2).tolist()
    ([1.0, 0.0], [1.0, 0.0])
    """
    import numpy as np
    from scipy.stats import norm

    fA, fB, fAB = (np.asarray(v, dtype=np.float64) for v in (fA, fB, fAB))
    y = np.concatenate([fA, fB, fAB.ravel()])
    d, n = fAB.shape
    zero = {k: np.zeros(d) for k in ("S1", "S1_conf", "ST", "ST_conf")}
    sd = y.std()
    if not n or np.ptp(y) <= np.finfo(float).eps or not sd > 0:
        return zero
    mu = y.mean()
    fA, fB, fAB = (fA - mu) / sd, (fB - mu) / sd, (fAB - mu) / sd
    var = np.var(np.concatenate([fA, fB]))
    if not var > np.finfo(float).eps:
        return zero
    out = {"S1": _s1(fA, fB, fAB, var), "ST": _st(fA, fAB, var)}
    r = np.random.default_rng(seed).integers(n, size=(resamples, n))
    vr = np.var(np.concatenate([fA[r], fB[r]], axis=1), axis=1)  # one variance per resample
    vr = np.where(vr > np.finfo(float).eps, vr, np.nan)
    z = norm.ppf(0.5 + conf / 2)
    s1 = np.mean(fB[r][None] * (fAB[:, r] - fA[r][None]), axis=-1) / vr  # d x resamples
    st = 0.5 * np.mean((fA[r][None] - fAB[:, r]) ** 2, axis=-1) / vr
    out["S1_conf"] = z * np.nanstd(s1, axis=1, ddof=1)
    out["ST_conf"] = z * np.nanstd(st, axis=1, ddof=1)
    return out


def morris_unit(r: int, d: int, seed: int = 0, levels: int = LEVELS):
    """``r`` Morris trajectories in the unit cube: an ``r (d+1) x d`` array, trajectory after trajectory (each
    ``d + 1`` points, one key moved by ``±Δ`` between consecutive points, every key once).

    >>> import numpy as np
    >>> X = morris_unit(3, 2, seed=1)
    >>> X.shape, sorted(set(np.round(np.abs(np.diff(X.reshape(3, 3, 2), axis=1)).sum(axis=2), 12).ravel().tolist()))
    ((9, 2), [0.666666666667])
    """
    import numpy as np

    rng = np.random.default_rng(seed)
    delta = levels / (2.0 * (levels - 1))
    grid = np.arange(levels // 2) / (levels - 1)  # the base levels x with x + delta <= 1
    out = np.empty((r, d + 1, d))
    for t in range(r):
        base = rng.choice(grid, size=d)
        up = rng.random(d) < 0.5
        x = np.where(up, base, base + delta)
        out[t, 0] = x
        for k, i in enumerate(rng.permutation(d)):
            x = x.copy()
            x[i] += delta if up[i] else -delta
            out[t, k + 1] = x
    return out.reshape(r * (d + 1), d)


def morris_effects(X, y, levels: int = LEVELS, resamples: int = RESAMPLES, seed: int = 0, conf: float = 0.95) -> dict:
    """``mu``, ``mu_star``, ``mu_star_conf`` and ``sigma`` (arrays of ``d``) of the elementary effects of the
    trajectories ``X`` (unit coordinates, :func:`morris_unit`) with outputs ``y``.  A trajectory holding a NaN
    output is dropped."""
    import numpy as np
    from scipy.stats import norm

    X = np.asarray(X, dtype=np.float64)
    d = X.shape[1]
    T = X.reshape(-1, d + 1, d)
    Y = np.asarray(y, dtype=np.float64).reshape(-1, d + 1)
    good = np.all(np.isfinite(Y), axis=1)
    T, Y = T[good], Y[good]
    delta = levels / (2.0 * (levels - 1))
    dx = np.diff(T, axis=1)  # r x d x d: the step of each move
    moved = np.argmax(np.abs(dx), axis=2)  # which key each move changed
    sign = np.sign(np.take_along_axis(dx, moved[..., None], axis=2)[..., 0])
    ee_moves = np.diff(Y, axis=1) * sign / delta  # r x d
    ee = np.empty((d, T.shape[0]))
    rows = np.arange(T.shape[0])[:, None]
    ee[moved, rows] = ee_moves
    out = {"mu": ee.mean(axis=1), "mu_star": np.abs(ee).mean(axis=1),
           "sigma": ee.std(axis=1, ddof=1) if ee.shape[1] > 1 else np.full(d, np.nan)}
    r = np.random.default_rng(seed).integers(ee.shape[1], size=(resamples, ee.shape[1]))
    out["mu_star_conf"] = norm.ppf(0.5 + conf / 2) * np.abs(ee[:, r]).mean(axis=2).std(axis=1, ddof=1)
    out["trajectories"] = int(T.shape[0])
    return out


@dataclass
class SensitivityResult:
    """What :func:`gearcalc.sensitivity` returns: ``indices`` (one row per output field and varied key:
    ``S1``, ``S1_conf``, ``ST``, ``ST_conf``, or Morris ``mu_star``, ``mu_star_conf``, ``sigma``, ``mu``),
    ``dominant`` (output field -> the key of the largest total index, or μ*), ``evaluations``, ``notes``."""

    method: str
    keys: tuple
    indices: list = field(default_factory=list)
    dominant: dict = field(default_factory=dict)
    evaluations: int = 0
    notes: list = field(default_factory=list)

    def to_dict(self) -> dict:
        return {"method": self.method, "keys": list(self.keys), "indices": self.indices, "dominant": self.dominant,
                "evaluations": self.evaluations, "notes": self.notes}

    def to_pandas(self):
        """The indices as a pandas DataFrame (one row per output field and varied key)."""
        import pandas as pd

        return pd.DataFrame(self.indices)


def _outputs(cols, keys, fields):
    """The numeric output fields to analyse (``fields``: those asked for), in order."""
    import numpy as np

    from .where import _numbers

    out = []
    for name, col in cols.data.items():
        if name in keys or name in ("error", "model_time_ms") or name.endswith("_err"):
            continue
        if fields is not None and name not in fields:
            continue
        values = col.tolist() if isinstance(col, np.ndarray) else col
        if not any(isinstance(v, (int, float)) and not isinstance(v, bool) for v in values):
            continue
        out.append((name, _numbers(col)))
    return out


CONSTANT_NAMED = 8
"""The outputs left out as constant that the note names (the rest are counted)."""


def _constant(y) -> bool:
    """Whether an output does not vary over the sample: its values (those it has) equal to the last bits (their
    spread at most one rounding of the largest), e.g. a key that is not varied, echoed (``cheek_ratio``), or a
    margin not defined at any point.  Such an output would have every index 0 (:func:`sobol_indices`)."""
    import numpy as np

    have = y[np.isfinite(y)]
    if not have.size:
        return False  # no value at all: said by the analysis ("fewer than 2 complete rows")
    return float(np.ptp(have)) <= np.finfo(float).eps * max(1.0, float(np.max(np.abs(have))))


def sensitivity_design(raw: dict, source: str, box, options, method: str = "sobol", samples: int | None = None,
                       seed: int = 0, jobs: int = 1, cluster=None, fields=None) -> SensitivityResult:
    """The analysis of :mod:`this module <gearcalc.explore.sensitivity>` (the command's and the API's body)."""
    import numpy as np

    from ..design import _suggest
    from ..grid import SweepError, cost_problem
    from .evaluate import Evaluator

    if method not in METHODS:
        raise SensitivityError(f"--method {method!r}: the methods are sobol, morris" + _suggest(method, METHODS))
    n = SAMPLES[method] if samples is None else samples
    d = box.d
    total = n * (d + 2) if method == "sobol" else n * (d + 1)
    if not 2 <= n or total > MAX_POINTS:
        raise SensitivityError(f"--samples {n}: must be at least 2 and give at most {MAX_POINTS} points "
                               f"({method} evaluates {'N (d+2)' if method == 'sobol' else 'N (d+1)'})")
    result = SensitivityResult(method, box.keys)
    if method == "sobol":
        A, B, AB = saltelli_unit(n, d, seed)
        unit = np.concatenate([A, B, AB.reshape(d * n, d)])
    else:
        unit = morris_unit(n, d, seed)
    with Evaluator(raw, source, options, jobs, cluster) as ev:
        axes = box.axes(unit)
        problem = cost_problem(axes, total, ev.seconds(axes), max(jobs, 1))
        if problem:
            raise SweepError(problem.replace("the grid has", "the analysis has"))
        cols = ev(axes)
        result.evaluations = ev.evaluations
    invalid = sum(e is not None for e in cols.data["error"])
    if invalid:
        first = next(e for e in cols.data["error"] if e)
        result.notes.append(f"{invalid} of {total} points are not valid designs (e.g. {first})")
    outputs = _outputs(cols, box.keys, fields)
    if fields is not None:
        have = [k for k in cols.data if k not in ("error",)]
        bad = [f"--fields {f}: no such numeric output field" + _suggest(f, have) for f in fields
               if f not in [o[0] for o in outputs]]
        if bad:
            raise SensitivityError("; ".join(bad))
    constant = [name for name, y in outputs if _constant(y)]
    if constant:
        shown = ", ".join(constant[:CONSTANT_NAMED]) + (f" and {len(constant) - CONSTANT_NAMED} more"
                                                        if len(constant) > CONSTANT_NAMED else "")
        result.notes.append(f"{len(constant)} output{'s' if len(constant) > 1 else ''} that do not vary over the "
                            f"sample left out (every index would be 0): {shown}")
        outputs = [(name, y) for name, y in outputs if name not in constant]
    for name, y in outputs:
        if method == "sobol":
            yA, yB, yAB = y[:n], y[n:2 * n], y[2 * n:].reshape(d, n)
            good = np.isfinite(yA) & np.isfinite(yB) & np.all(np.isfinite(yAB), axis=0)
            if good.sum() < 2:
                result.notes.append(f"{name}: fewer than 2 complete rows of the scheme; not analysed")
                continue
            if not good.all():
                result.notes.append(f"{name}: {int((~good).sum())} of {n} rows dropped (a point without the value)")
            s = sobol_indices(yA[good], yB[good], yAB[:, good], seed=seed)
            rank = s["ST"]
            cols_out = ("S1", "S1_conf", "ST", "ST_conf")
        else:
            s = morris_effects(unit, y, seed=seed)
            if s["trajectories"] < 2:
                result.notes.append(f"{name}: fewer than 2 complete trajectories; not analysed")
                continue
            if s["trajectories"] < n:
                result.notes.append(f"{name}: {n - s['trajectories']} of {n} trajectories dropped")
            rank = s["mu_star"]
            cols_out = ("mu_star", "mu_star_conf", "sigma", "mu")
        for j, key in enumerate(box.keys):
            result.indices.append({"field": name, "key": key, **{c: float(s[c][j]) for c in cols_out}})
        if np.all(rank == 0):
            result.dominant[name] = None  # constant over the box
        else:
            result.dominant[name] = box.keys[int(np.argmax(rank))]
    return result
