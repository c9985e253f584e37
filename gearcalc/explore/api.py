"""The exploring functions of the Python API: :func:`sample` (points for :func:`gearcalc.sweep`),
:func:`optimize` and :func:`sensitivity`.  Bad input raises :class:`gearcalc.InputError` only.

>>> import gearcalc.explore.api as ex
>>> base = {"kind": "rows", "gear": {"sun_teeth": 18, "module_mm": 5.0},
...         "rows": {"count": 3, "planets_per_row": 3, "relative_width": 2.4}, "sun": {"torque_Nm": 1e3}}
>>> r = ex.optimize(base, {"rows.relative_width": (2.0, 2.8)}, "K:min", budget=16)
>>> r.optimum, round(r.value, 3), r.converged        # K grows with the width: the lower bound
({'rows.relative_width': 2.0}, 1.366, True)
"""
from __future__ import annotations

from typing import Any, Iterable, Mapping

__all__ = ["sample", "optimize", "sensitivity"]


def _vary(vary) -> list[str]:
    """``{key: (lo, hi)}`` or ``["KEY=LO:HI", ...]`` as the command line's strings; anything else an InputError."""
    from ..api import _a, _items, _key, _plain, _strings

    if isinstance(vary, Mapping):
        out = []
        for k, v in _items(vary, "vary", 10_000):
            k = _key(k, "vary")
            v = _plain(v, f"vary: {k}")
            if not isinstance(v, list) or len(v) != 2 or not all(type(x) in (int, float) for x in v):
                _fail(ValueError(f"vary: {k}: expected (LO, HI), two numbers; not {_a(v)}"))
            out.append(f"{k}={v[0]!r}:{v[1]!r}")
        return out
    return _strings(vary, "vary", "{key: (lo, hi)} or 'KEY=LO:HI' strings")


def _input(design, overrides):
    from ..api import _raw

    return _raw(design, overrides)


def _fail(exc) -> None:
    from ..design import InputError

    raise InputError([str(exc)]) from None


def _options(model, tol, kind):
    from .. import registry
    from ..api import MODEL, _model_arg, _tol_arg
    from ..calculator import Options
    from ..engine import check_model

    model, tol = _model_arg(model), _tol_arg(tol)
    if isinstance(kind, str) and kind in registry.kinds():
        check_model(model, kind, MODEL)
    return Options(tol=tol, model=model)


def _args(jobs, seed, scheduler) -> tuple:
    """``jobs``, ``seed`` and ``scheduler`` checked as :func:`gearcalc.compute_files` checks them."""
    from ..api import MAX_JOBS, _count, _scheduler_arg

    return _count("jobs", jobs, 1, MAX_JOBS), _count("seed", seed, 0), _scheduler_arg(scheduler)


def sample(design, vary, sampler: str = "sobol", n: int = 256, *, seed: int = 0,
           overrides: Iterable[tuple[str, Any]] | Mapping[str, Any] = ()):
    """``n`` points of the ranges ``vary`` (``{key: (lo, hi)}``) drawn by ``sampler`` (``"sobol"``, ``"lhs"``,
    ``"random"``) for ``seed``: axes for :func:`gearcalc.sweep` (a :class:`gearcalc.grid.Sample`), as
    ``gearcalc sweep --sample SAMPLER:N`` evaluates.  Integer keys are sampled as integers."""
    from .sample import SampleError, draw, parse_ranges, parse_sampler

    from ..api import _a, _count

    raw, _ = _input(design, overrides)
    if not isinstance(sampler, str):
        _fail(ValueError(f"sampler: 'sobol', 'lhs' or 'random'; not {_a(sampler)}"))
    n, seed = _count("n", n), _count("seed", seed, 0)
    try:
        name, count = parse_sampler(f"{sampler}:{n}")
        return draw(parse_ranges(_vary(vary), raw), name, count, seed)
    except (SampleError, ValueError) as exc:
        _fail(exc)


def optimize(design, vary, objective, *, where: Iterable[str] = (), budget: int = 256, seed: int = 0,
             refine: bool = True, model: str | None = None, tol: float = 1e-6,
             overrides: Iterable[tuple[str, Any]] | Mapping[str, Any] = (), jobs: int = 1, scheduler=None):
    """The best design over the box ``vary`` (``{key: (lo, hi)}``) for ``objective`` (``"FIELD:min"``, or a list
    of them: the Pareto front) under the ``where`` conditions (``"FIELD<=VALUE"``), as ``gearcalc optimize``:
    an :class:`gearcalc.explore.optimize.OptimizeResult` (``to_pandas()``, ``to_dict()``)."""
    from ..design import InputError
    from ..grid import SweepError
    from .optimize import OptimizeError, optimize_design, parse_objectives
    from .sample import SampleError, parse_ranges
    from .where import WhereError, parse_where

    from ..api import _flag, _quiet, _strings

    raw, source = _input(design, overrides)
    options = _options(model, tol, raw.get("kind"))
    jobs, seed, scheduler = _args(jobs, seed, scheduler)
    refine = _flag("refine", refine)
    if isinstance(budget, bool) or not isinstance(budget, int) or not 2 <= budget <= 1_000_000:
        from ..api import _shown

        _fail(ValueError(f"budget = {_shown(budget)}: must be a whole number of points, 2 to 1000000"))
    try:
        box = parse_ranges(_vary(vary), raw)
        objectives = parse_objectives(_strings(objective, "objective", "'FIELD:min' or a list of them"))
        conditions = parse_where(_strings(where, "where", "'FIELD<=VALUE' strings"))
        with _quiet():
            return _cluster(scheduler, lambda cluster: optimize_design(
                raw, source, box, objectives, conditions, options, budget, seed, jobs, cluster, refine))
    except InputError:
        raise
    except (SampleError, WhereError, OptimizeError, SweepError, ValueError) as exc:
        _fail(exc)


def sensitivity(design, vary, *, method: str = "sobol", samples: int | None = None, seed: int = 0,
                fields: Iterable[str] | None = None, model: str | None = None, tol: float = 1e-6,
                overrides: Iterable[tuple[str, Any]] | Mapping[str, Any] = (), jobs: int = 1, scheduler=None):
    """Sobol' indices (or Morris μ*, σ) of every numeric output over the box ``vary``, as ``gearcalc
    sensitivity``: a :class:`gearcalc.explore.sensitivity.SensitivityResult` (``to_pandas()``, ``dominant``)."""
    from ..design import InputError
    from ..grid import SweepError
    from .sample import SampleError, parse_ranges
    from .sensitivity import SensitivityError, sensitivity_design

    from ..api import _a, _count, _quiet, _strings

    raw, source = _input(design, overrides)
    options = _options(model, tol, raw.get("kind"))
    jobs, seed, scheduler = _args(jobs, seed, scheduler)
    samples = None if samples is None else _count("samples", samples)
    if not isinstance(method, str):
        _fail(ValueError(f"method: 'sobol' or 'morris'; not {_a(method)}"))
    try:
        box = parse_ranges(_vary(vary), raw)
        chosen = None if fields is None else _strings(fields, "fields", "output field names")
        with _quiet():
            return _cluster(scheduler, lambda cluster: sensitivity_design(
                raw, source, box, options, method, samples, seed, jobs, cluster, chosen))
    except InputError:
        raise
    except (SampleError, SensitivityError, SweepError, ValueError) as exc:
        _fail(exc)


def _cluster(scheduler, body):
    if scheduler is None:
        return body(None)
    from ..api import _scheduler_errors
    from ..distributed import Cluster

    with _scheduler_errors(), Cluster(scheduler) as cluster:
        return body(cluster)
