"""``gearcalc optimize``: the best design in a box of key ranges, or the Pareto front of several objectives.

One objective (``--objective FIELD:min|max``):

1. **Global phase.**  A scrambled Sobol' sample of ``budget`` points of the box (:mod:`gearcalc.explore.sample`),
   evaluated by the grid sweep's chunks (:class:`gearcalc.explore.evaluate.Evaluator`).  A point is *feasible*
   when it is a valid design, passes the kind's design checks (``Calculator.failure``), meets every ``--where``
   and has a finite objective.
2. **Local refinement** of the best ``REFINE`` feasible points: the continuous keys by
   :func:`scipy.optimize.minimize` with SLSQP, in unit coordinates of the box (the bounds), each numeric
   ``--where`` an inequality constraint (its relative slack, :func:`gearcalc.explore.where.slack`) and ``==``
   an equality.  SLSQP is chosen because it takes bounds and inequality constraints as they are (no penalty
   weight to tune), and its gradients cost one vectorised batch per step: the point and its central
   differences (step :data:`STEP` of the range) are evaluated together, as one chunk.
3. **Integer keys** (tooth, roller, row counts) are never relaxed to reals: they stay at the candidate's values
   while the continuous keys are refined; then every neighbour within one step of each integer key (all
   combinations up to :data:`NEIGHBOURS_MAX`, else ±1 and ±2 of one key at a time) is refined in turn, and the
   search moves to a better neighbour until none is better (at most :data:`MOVES_MAX` moves).

The optimum reported is the best feasible point evaluated (sampled, refined or a difference point), so it meets
every condition exactly; ``converged`` says that the winning refinement ended with SLSQP's success and the integer
neighbourhood held no better point.  The objective's error is its ``FIELD_err`` output where the kind reports one
(e.g. ``efficiency_err``, ``sigma_max_err_MPa``), else 0 (exact to rounding: the field is a closed form).  Each
``--where`` is reported with its slack; a constraint is *active* within :data:`ACTIVE_TOL` (relative) of its bound.

Several objectives: the non-dominated feasible points of the sample (the Pareto front; not refined), each
objective minimised or maximised as given.
"""
from __future__ import annotations

import itertools
import math
from dataclasses import dataclass, field
from typing import Any

__all__ = ["Objective", "OptimizeResult", "parse_objectives", "optimize_design", "non_dominated", "BUDGET"]

BUDGET = 256
"""Points of the global phase by default (a power of 2: a balanced Sobol' sample)."""
REFINE = 3
"""The best feasible sample points refined."""
STEP = 1e-4
"""The step of the central differences, in unit coordinates (a fraction of the range)."""
ACTIVE_TOL = 1e-4
"""A constraint whose relative slack is within this of 0 is active."""
TIE = 1e-9
"""Two refinements whose best objectives agree to this (relative) found the same optimum."""
SHIFT = 1e-8
"""SLSQP is given each inequality as ``slack >= SHIFT``: it converges onto an active bound to within its own
tolerance from either side, and a final iterate outside by 1e-12 would be infeasible and not reported (the
optimum would fall back to an earlier, worse iterate)."""
NEIGHBOURS_MAX = 27
MOVES_MAX = 10
MAXITER = 100
FTOL = 1e-10
"""SLSQP's relative accuracy of the objective.  The points are rounded to 12 significant digits (like a grid's
values), so a tighter target only ends in line-search failures ("Positive directional derivative") at an
optimum already found."""
REFINE_BUDGET = 20
"""The refinement evaluates at most this many times the global phase's points (and at most the estimated
computing time a sweep may take, :data:`gearcalc.grid.SWEEP_SECONDS_MAX`); beyond, it stops unconverged."""


class OptimizeError(ValueError):
    """A malformed ``--objective`` or an optimisation that cannot start (no feasible point)."""


@dataclass(frozen=True)
class Objective:
    field: str
    sense: str  # "min" or "max"

    @property
    def sign(self) -> float:
        return 1.0 if self.sense == "min" else -1.0


def parse_objectives(items) -> list[Objective]:
    """``FIELD:min`` / ``FIELD:max`` (a bare FIELD: min).

    >>> parse_objectives(["K:min", "relative_mass_kg_per_kNm:max"])
    [Objective(field='K', sense='min'), Objective(field='relative_mass_kg_per_kNm', sense='max')]
    """
    from ..design import _clip, _suggest

    out = []
    for item in items or ():
        name, sep, sense = item.strip().rpartition(":")
        if not sep:
            name, sense = item.strip(), "min"
        sense = sense.strip().lower()
        if not name or sense not in ("min", "max"):
            raise OptimizeError(f"--objective {_clip(item)}: expected FIELD:min or FIELD:max"
                                + _suggest(sense, ["min", "max"]))
        if any(o.field == name for o in out):
            raise OptimizeError(f"--objective {name}: given twice")
        out.append(Objective(name.strip(), sense))
    if not out:
        raise OptimizeError("no --objective FIELD:min|max given")
    return out


@dataclass
class OptimizeResult:
    """What :func:`gearcalc.optimize` returns.

    One objective: ``optimum`` (the varied keys' values), ``value`` and ``error`` of the objective, ``outputs``
    (every output field there), ``constraints`` (per ``--where``: value, relative slack, active), ``evaluations``
    (points evaluated), ``converged``, ``notes``.  Several objectives: ``front`` (the non-dominated points, a
    :class:`gearcalc.render.Columns` with the varied keys and every output).  ``samples``: the global phase's
    points, with a ``feasible`` column.
    """

    keys: tuple
    objectives: list
    optimum: dict | None = None
    value: float | None = None
    error: float | None = None
    outputs: dict = field(default_factory=dict)
    constraints: list = field(default_factory=list)
    evaluations: int = 0
    converged: bool | None = None
    notes: list = field(default_factory=list)
    front: Any = None
    samples: Any = None

    def rows(self) -> list[dict]:
        """The optimum (one row) or the front's members (one row each): the varied keys, then the outputs."""
        if self.front is not None:
            return self.front.rows()
        return [self.outputs] if self.outputs else []

    def to_dict(self) -> dict:
        if self.front is not None:
            return {"objectives": [f"{o.field}:{o.sense}" for o in self.objectives], "front": self.rows(),
                    "evaluations": self.evaluations, "notes": self.notes}
        o = self.objectives[0]
        return {"objective": f"{o.field}:{o.sense}", "optimum": self.optimum, "value": self.value,
                "error": self.error, "constraints": self.constraints, "evaluations": self.evaluations,
                "converged": self.converged, "outputs": self.outputs, "notes": self.notes}

    def to_pandas(self):
        """The optimum or the front as a pandas DataFrame (one row a design)."""
        import pandas as pd

        return pd.DataFrame(self.rows())


def non_dominated(F):
    """The rows of ``F`` (``n x m`` objectives, all minimised) that no other row dominates (no worse in every
    objective, better in one), as a bool array; vectorised over blocks of rows.

    >>> non_dominated([[1, 3], [2, 2], [3, 1], [2, 3], [3, 3]]).tolist()
    [True, True, True, False, False]
    """
    import numpy as np

    F = np.asarray(F, dtype=np.float64)
    n = F.shape[0]
    keep = np.ones(n, dtype=bool)
    block = max(1, 2_000_000 // max(n * F.shape[1], 1))
    for a in range(0, n, block):
        Fi = F[a:a + block, None, :]
        le = np.all(F[None, :, :] <= Fi, axis=2)
        lt = np.any(F[None, :, :] < Fi, axis=2)
        keep[a:a + block] = ~np.any(le & lt, axis=1)
    return keep


def _column(cols, name):
    import numpy as np

    from .where import _numbers

    col = cols.data.get(name)
    return _numbers(col) if col is not None else np.full(cols.n, np.nan)


class _Problem:
    """The box, the conditions and the objective(s) over evaluated Columns."""

    def __init__(self, box, objectives, conditions, evaluator, calc):
        self.box, self.objectives, self.conditions = box, objectives, conditions
        self.evaluate, self.calc = evaluator, calc
        self.archive = []  # (f, feasible, row) of every evaluated point, single objective
        self.limit = None  # the evaluations the refinement may reach

    def feasible(self, cols):
        import numpy as np

        from .where import mask

        ok = mask(self.conditions, cols.data, cols.n)
        ok &= np.array([e is None for e in cols.data["error"]], dtype=bool)
        for name, value in self.calc.failure:
            col = cols.data.get(name)
            if col is not None:
                ok &= np.array([not (v is not None and v == value and type(v) is type(value)) for v in col],
                               dtype=bool)
        for o in self.objectives:
            ok &= np.isfinite(_column(cols, o.field))
        return ok

    def check_names(self, cols) -> None:
        from ..design import _suggest
        from .where import WhereError, unknown

        have = [k for k in cols.data if k != "error"]
        if all(e is not None for e in cols.data["error"]):
            raise OptimizeError("no point of the sample is a valid design, e.g. " + cols.data["error"][0])
        bad = unknown(self.conditions, have)
        bad += [f"--objective {o.field}: no such output field" + _suggest(o.field, have)
                for o in self.objectives if o.field not in have]
        if bad:
            raise WhereError("; ".join(bad))

    def axes(self, ints_values, cont_unit):
        """A Sample of points: integer keys from ``ints_values`` (n x k), continuous keys from unit coordinates."""
        from ..grid import Sample, round12

        box = self.box
        out, ci, ii = {}, 0, 0
        for j, key in enumerate(box.keys):
            if box.ints[j]:
                out[key] = [int(v) for v in ints_values[:, ii].tolist()]
                ii += 1
            else:
                x = box.lo[j] + cont_unit[:, ci] * (box.hi[j] - box.lo[j])
                out[key] = round12(x).tolist()
                ci += 1
        return Sample(out)

    def record(self, cols, f, feas):
        for k in range(cols.n):
            self.archive.append((float(f[k]), bool(feas[k]), {name: col[k] for name, col in cols.lists().data.items()}))


def _refine(problem, ints, u0, scale):
    """SLSQP over the continuous keys (unit coordinates ``u0``) with the integer keys at ``ints``; (success,
    message, the best feasible objective evaluated by this run, inf if none)."""
    import numpy as np
    from scipy.optimize import minimize

    from .where import slack

    obj = problem.objectives[0]
    dc = u0.size
    cache: dict = {}
    conds = [c for c in problem.conditions if slack(c, [0.0]) is not None]

    def batch(u):
        key = tuple(np.round(u, 15).tolist())
        if key in cache:
            return cache[key]
        if problem.limit is not None and problem.evaluate.evaluations >= problem.limit:
            raise _Undefined("the refinement's budget of evaluations is spent")
        h = np.where(u + STEP <= 1.0, STEP, -STEP)
        pts = [u] + [u + h[i] * e for i, e in enumerate(np.eye(dc))] + [
            np.clip(u - h[i] * e, 0.0, 1.0) for i, e in enumerate(np.eye(dc))]
        U = np.array(pts)
        cols = problem.evaluate(problem.axes(np.repeat(ints[None, :], len(U), axis=0), U))
        feas = problem.feasible(cols)
        f = obj.sign * _column(cols, obj.field)
        problem.record(cols, f, feas)
        g = np.array([slack(c, cols.data[c.field]) for c in conds]).reshape(len(conds), len(U))
        steps = U[1:1 + dc] - U[1 + dc:]  # central where both sides are inside, one-sided otherwise
        d = np.diag(steps)

        def grad(v):
            return (v[1:1 + dc] - v[1 + dc:]) / d

        out = (f[0] / scale, grad(f) / scale, g[:, 0], np.array([grad(gi) for gi in g]).reshape(len(conds), dc),
               np.all(np.isfinite(f)) and np.all(np.isfinite(g)))
        cache[key] = out
        return out

    def fun(u):
        v = batch(u)
        if not v[4]:
            raise _Undefined("a point near the candidate is not a valid design (refinement stopped there)")
        return v[0]

    constraints = []
    ineq = [k for k, c in enumerate(conds) if c.op != "=="]
    eq = [k for k, c in enumerate(conds) if c.op == "=="]
    if ineq:
        constraints.append({"type": "ineq", "fun": lambda u: batch(u)[2][ineq] - SHIFT,
                            "jac": lambda u: batch(u)[3][ineq]})
    if eq:
        constraints.append({"type": "eq", "fun": lambda u: batch(u)[2][eq], "jac": lambda u: batch(u)[3][eq]})
    start = len(problem.archive)

    def found():
        return min((a[0] for a in problem.archive[start:] if a[1]), default=math.inf)

    try:
        res = minimize(fun, u0, jac=lambda u: batch(u)[1], method="SLSQP", bounds=[(0.0, 1.0)] * dc,
                       constraints=constraints, options={"maxiter": MAXITER, "ftol": FTOL})
    except _Undefined as exc:
        return False, str(exc), found()
    return bool(res.success), str(res.message), found()


def _keep(runs, key, run) -> None:
    """Several starts may share one integer combination (always, without integer keys): the combination's
    outcome is that of its run that found the best point, not of the last run; runs that found the same best
    (to :data:`TIE`, relative) succeed when one of them did."""
    old = runs.get(key)
    if old is None:
        runs[key] = run
    elif abs(run[2] - old[2]) <= TIE * max(abs(run[2]), abs(old[2])):
        runs[key] = (old[0] or run[0], old[1] if old[0] else run[1], min(old[2], run[2]))
    elif run[2] < old[2]:
        runs[key] = run


class _Undefined(Exception):
    pass


def _neighbours(center, lo, hi):
    """Integer combinations within one step of ``center`` (clipped to the box), the centre excluded."""
    k = len(center)
    if 3 ** k - 1 <= NEIGHBOURS_MAX:
        combos = itertools.product(*[[v - 1, v, v + 1] for v in center])
    else:
        combos = []
        for j in range(k):
            for s in (-2, -1, 1, 2):
                c = list(center)
                c[j] += s
                combos.append(c)
    out = []
    for c in combos:
        c = tuple(int(v) for v in c)
        if c != tuple(center) and all(a <= v <= b for v, a, b in zip(c, lo, hi)) and c not in out:
            out.append(c)
    return out


def optimize_design(raw: dict, source: str, box, objectives, conditions, options, budget: int = BUDGET,
                    seed: int = 0, jobs: int = 1, cluster=None, refine: bool = True) -> OptimizeResult:
    """The optimisation of :mod:`this module <gearcalc.explore.optimize>` (the command's and the API's body)."""
    import numpy as np

    from .. import registry
    from ..grid import SweepError, cost_problem
    from .evaluate import Evaluator
    from .sample import unit_sample
    from .where import slack

    result = OptimizeResult(box.keys, objectives)
    with Evaluator(raw, source, options, jobs, cluster) as ev:
        calc = registry.get(ev.base.kind)
        unit = unit_sample("sobol", budget, box.d, seed)
        samples_axes = box.axes(unit)
        seconds = ev.seconds(samples_axes)
        problem = cost_problem(samples_axes, budget, seconds, max(jobs, 1))
        if problem:
            raise SweepError(problem.replace("the grid has", "the global phase has"))
        P = _Problem(box, objectives, conditions, ev, calc)
        from ..grid import SWEEP_SECONDS_MAX

        P.limit = budget + min(REFINE_BUDGET * budget, int(SWEEP_SECONDS_MAX * max(jobs, 1) / max(seconds, 1e-12)))
        cols = ev(samples_axes)
        P.check_names(cols)
        feas = P.feasible(cols)
        cols.data["feasible"] = feas.tolist()
        result.samples = cols
        if not feas.any():
            result.evaluations = ev.evaluations
            result.notes.append(f"no feasible point among the {budget} sampled: widen the ranges or loosen --where")
            return result
        if len(objectives) > 1:
            F = np.column_stack([o.sign * _column(cols, o.field) for o in objectives])[feas]
            idx = np.flatnonzero(feas)[non_dominated(F)]
            from .where import select

            keep = np.zeros(cols.n, dtype=bool)
            keep[idx] = True
            front = select(cols, keep)
            order = np.argsort(_column(front, objectives[0].field) * objectives[0].sign, kind="stable")
            result.front = select(front, np.ones(front.n, dtype=bool)) if front.n < 2 else _reorder(front, order)
            result.evaluations = ev.evaluations
            result.notes.append(f"{front.n} non-dominated of {int(feas.sum())} feasible sampled points (not refined)")
            return result
        obj = objectives[0]
        f = obj.sign * _column(cols, obj.field)
        P.record(cols, f, feas)
        ints = np.array(box.ints, dtype=bool)
        U = unit  # the sample's unit coordinates: the continuous keys' starting points
        values = box.values(unit)
        order = [k for k in np.argsort(np.where(feas, f, np.inf), kind="stable").tolist() if feas[k]][:REFINE]
        scale = max(abs(float(f[order[0]])), 1e-300)
        converged = None
        if refine:
            starts = [(values[k, ints].astype(int), U[k, ~ints]) for k in order]
            runs = {}
            for iv, u0 in starts:  # integer keys only: nothing to refine, the neighbourhood decides
                _keep(runs, tuple(iv.tolist()), _refine(P, iv, u0, scale) if (~ints).any() else (True, "", 0.0))
            center = _best(P, box)
            moves = 0
            while ints.any() and moves <= MOVES_MAX:
                cint, cu = _split(box, center)
                for nb in _neighbours(cint.tolist(), np.array(box.lo)[ints], np.array(box.hi)[ints]):
                    if nb in runs:
                        continue
                    if (~ints).any():
                        runs[nb] = _refine(P, np.array(nb), cu, scale)
                    else:
                        c = ev(P.axes(np.array([nb]), np.zeros((1, 0))))
                        P.record(c, obj.sign * _column(c, obj.field), P.feasible(c))
                        runs[nb] = (True, "", 0.0)
                new = _best(P, box)
                if new == center:
                    break
                center, moves = new, moves + 1
            cint, _ = _split(box, center)
            success, message, _ = runs.get(tuple(cint.tolist()), (False, "the optimum is a sampled point", 0.0))
            converged = bool(success) and moves <= MOVES_MAX
            if not success:
                result.notes.append(f"refinement: {message}")
        best = min((a for a in P.archive if a[1]), key=lambda a: a[0])
        row = best[2]
        result.optimum = {k: row[k] for k in box.keys}
        result.outputs = {k: v for k, v in row.items() if k != "error"}
        result.value = row[obj.field]
        err = row.get(error_field(obj.field, row))
        result.error = float(err) if isinstance(err, (int, float)) and not isinstance(err, bool) else 0.0
        for c in conditions:
            s = slack(c, [row.get(c.field)])
            s = None if s is None or math.isnan(float(s[0])) else float(s[0])
            result.constraints.append({"where": c.text, "value": row.get(c.field), "slack": s,
                                       "active": s is not None and abs(s) <= ACTIVE_TOL})
        result.converged = converged
        result.evaluations = ev.evaluations
    return result


def error_field(name: str, row) -> str | None:
    """The output holding the error estimate of output ``name``: ``NAME_err`` or, for a name with a unit,
    ``BASE_err_UNIT`` (zstk's ``sigma_max_err_MPa``); None when the kind reports none.

    >>> error_field("sigma_max_MPa", {"sigma_max_err_MPa": 1e-9}), error_field("K", {"K": 1.0})
    ('sigma_max_err_MPa', None)
    """
    from ..units import split_unit

    base, unit = split_unit(name)
    for candidate in (f"{name}_err", f"{base}_err_{unit}" if unit else None):
        if candidate and candidate in row:
            return candidate
    return None


def _reorder(cols, order):
    import numpy as np

    from ..render import Columns

    data = {k: (v[order] if isinstance(v, np.ndarray) else [v[i] for i in order.tolist()])
            for k, v in cols.data.items()}
    return Columns(data, cols.errors)


def _best(P, box):
    """The varied keys' values of the best feasible point evaluated so far."""
    best = min((a for a in P.archive if a[1]), key=lambda a: a[0])
    return tuple(best[2][k] for k in box.keys)


def _split(box, point):
    """(integer keys' values, continuous keys' unit coordinates) of a point."""
    import numpy as np

    ints = [int(v) for v, i in zip(point, box.ints) if i]
    cont = [(v - a) / (b - a) for v, a, b, i in zip(point, box.lo, box.hi, box.ints) if not i]
    return np.array(ints, dtype=int), np.clip(np.array(cont, dtype=float), 0.0, 1.0)
