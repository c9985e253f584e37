"""gearcalc from Python: the functions the command line calls, for notebooks and programs.

No typer, no printing: results are returned, messages collected.  ``import gearcalc`` re-exports these
names lazily, so ``gearcalc --help`` stays fast.

>>> import gearcalc
>>> r = gearcalc.compute({"kind": "rows", "gear": {"sun_teeth": 18, "module_mm": 5.0},
...                       "rows": {"count": 3, "planets_per_row": 3, "relative_width": 2.4},
...                       "sun": {"torque_Nm": 1000.0}})
>>> round(r.summary["K"], 3)   # the paper's stated value (seed 004, rows.md §11.1)
1.489
>>> r.model, r.failed
('stepwise', [])

A model level is chosen by name; an unknown one is a ``ValueError`` that lists the levels:

>>> gearcalc.compute(r.design, model="exakt")
Traceback (most recent call last):
...
ValueError: --model exakt: a rows design has the levels stepwise, exact, continuous (did you mean 'exact'?)
"""
from __future__ import annotations

import os
from dataclasses import dataclass, field
from typing import Any, Iterable, Iterator, Mapping

from .calculator import DesignError, Options, Result
from .design import Design, InputError

__all__ = ["load", "compute", "compute_files", "sweep", "sweep_chunk", "Batch", "Result", "Design",
           "InputError", "DesignError", "models"]

DEFAULT_TOL = 1e-6


def models(kind: str) -> tuple[str, ...]:
    """The model levels of a kind, cheapest first.

    >>> models("rows")
    ('stepwise', 'exact', 'continuous')
    """
    from . import registry

    if kind not in registry.kinds():
        raise ValueError(f"unknown kind {kind!r}; the kinds are " + ", ".join(registry.kinds()))
    return registry.get(kind).models


def load(design, *, overrides: Iterable[tuple[str, Any]] | Mapping[str, Any] = (), kind: str | None = None) -> Design:
    """A validated design, every default filled in.

    Parameters
    ----------
    design : str or os.PathLike or dict or Design
        A design file (``"-"``: standard input), the design as data (what ``tomllib`` gives for a file), or
        a loaded design (returned as it is unless ``overrides`` are given).
    overrides : mapping or pairs of (dotted key, value)
        Values that replace the design's, as ``--set`` does: ``{"rows.count": 4}``.
    kind : str, optional
        Require this kind (as ``gearcalc rows`` does); a design without ``kind`` takes it.

    Raises
    ------
    InputError
        With ``messages``: every problem of the design, each naming the key and the constraint.
    """
    from . import design as dmod

    if isinstance(design, Design) and not _pairs(overrides):
        return design
    raw, source = _raw(design, overrides)
    return dmod.validate(raw, source, kind)


def _pairs(overrides) -> list[tuple[str, Any]]:
    """``overrides`` as (dotted key, value) pairs, from a mapping or pairs."""
    return list(overrides.items()) if isinstance(overrides, Mapping) else list(overrides)


def _raw(design, overrides=()) -> tuple[dict, str]:
    """(design data as a file gives it, with the overrides set; its source name) from a path, data or a
    loaded design."""
    import copy

    from . import design as dmod

    if isinstance(design, Design):
        raw, source = copy.deepcopy(design.resolved()), design.source
    elif isinstance(design, Mapping):
        raw, source = copy.deepcopy(dict(design)), "<data>"
    else:
        source = os.fspath(design)
        raw = dmod.read_toml(source)
    pairs = _pairs(overrides)
    if pairs:
        dmod.apply_set(raw, pairs)
    return raw, source


def compute(design, *, model: str | None = None, tol: float = DEFAULT_TOL, detail: bool = False,
            overrides: Iterable[tuple[str, Any]] | Mapping[str, Any] = (), kind: str | None = None) -> Result:
    """Compute one design: its :class:`~gearcalc.calculator.Result`.

    ``result.summary`` holds the summary fields (names with their unit suffix, as the CSV columns),
    ``result.detail`` the per-element tables (with ``detail=True``), ``result.warnings`` and
    ``result.failed`` (the failed design checks: the command line's exit status 1), ``result.design`` the
    resolved design; ``result.to_dict()`` is the JSON object, ``result.to_pandas()`` a one-row DataFrame.

    Raises ``InputError`` for a design the schema refuses, ``DesignError`` for one the physics cannot
    compute (also for an output that would be infinite or NaN), ``ValueError`` for an unknown model level or a
    tolerance outside [1e-15, 0.1).
    """
    from . import registry
    from .engine import check_model, finite_error, quiet_numpy

    d = load(design, overrides=overrides, kind=kind)
    _check_tol(tol)
    check_model(model, d.kind)
    with quiet_numpy():
        result = registry.get(d.kind).compute(d, Options(tol=tol, model=model, detail=detail))
    bad = finite_error(d, result)  # never an inf or a NaN as a result: the design's error, as on the command line
    if bad is not None:
        raise bad
    result.design = d.resolved()
    result.name, result.kind = d.name, d.kind
    return result


def _check_tol(tol: float) -> None:
    from .calculator import tol_problem

    problem = tol_problem(tol)
    if problem:
        raise ValueError(f"tol = {tol!r}: {problem}")


@dataclass
class Batch:
    """What :func:`compute_files` returns: the computed designs in order, every message (in the order the
    command line prints them on stderr) and the exit status (0 ok, 1 a check failed, 2 bad input, 70 a bug).
    """

    records: list = field(default_factory=list)
    messages: list[str] = field(default_factory=list)
    status: int = 0

    @property
    def results(self) -> list[Result]:
        return [r.result for r in self.records]

    def to_pandas(self):
        """One row per design (the summaries; ``kind`` first when several kinds), as a pandas DataFrame."""
        import pandas as pd  # optional: not a dependency of gearcalc

        mixed = len({r.kind for r in self.records}) > 1
        return pd.DataFrame([({"kind": r.kind} if mixed else {}) | r.result.summary for r in self.records])


def compute_files(paths, *, kind: str | None = None, model: str | None = None, tol: float = DEFAULT_TOL,
                  detail: bool = False, overrides: Iterable[tuple[str, Any]] | Mapping[str, Any] = (),
                  jobs: int = 1, progress=None, verbose: bool = False, say=None, scheduler=None) -> Batch:
    """Compute design files and folders (every ``*.toml`` below a folder), as ``gearcalc run`` does.

    A bad file is its messages and exit status 2, never the end of the batch; ``jobs > 1`` spreads the
    designs over worker processes (identical results), ``scheduler`` over a Dask cluster (``--scheduler``: an
    address, ``"local:N"``, or a ``distributed.Client``; needs the ``dask`` extra; identical results).
    ``progress(k)`` is called as designs finish; ``say(line)`` receives each message as it comes (default:
    collected in ``Batch.messages`` only).
    """
    from . import design as dmod
    from . import engine

    paths = [os.fspath(p) for p in ([paths] if isinstance(paths, (str, os.PathLike)) else paths)]
    _check_tol(tol)
    batch = Batch()

    def tell(line: str) -> None:
        batch.messages.append(line)
        if say is not None:
            say(line)

    files = dmod.expand_paths(paths, warn=tell)
    designs, worst = engine.load_designs(files, _pairs(overrides), kind, tell)
    for k in sorted({d.kind for d in designs}):
        engine.check_model(model, k)
    opts = Options(tol=tol, model=model, detail=detail)
    if scheduler is None:
        records, status = engine.run(designs, opts, say=tell, advance=progress, jobs=jobs, verbose=verbose)
    else:
        from .distributed import Cluster

        with Cluster(scheduler, say=tell) as cluster:
            records, status = engine.run(designs, opts, say=tell, advance=progress, verbose=verbose,
                                         cluster=cluster)
    batch.records, batch.status = records, max(worst, status)
    return batch


def sweep(design, axes: Mapping[str, Iterable[Any]], *, model: str | None = None, tol: float = DEFAULT_TOL,
          overrides: Iterable[tuple[str, Any]] | Mapping[str, Any] = (), chunk: int | None = None,
          scheduler=None) -> Iterator:
    """Evaluate one design over the product grid of ``axes`` (the first axis varies slowest), a chunk at a
    time: yields :class:`~gearcalc.render.Columns` (``.data[field]`` lists, the varied keys first, each made from
    the chunk's numpy array when first read; rows with ``.rows()``, a DataFrame with ``.to_pandas()``), in grid
    order.  Memory is bounded by the chunk,
    not by the grid.  ``scheduler``: the chunks are computed on a Dask cluster (an address, ``"local:N"``
    or a ``distributed.Client``; needs the ``dask`` extra), the same values in the same order.
    A point whose output would be infinite or NaN has every output None and its message in the chunk's
    ``errors`` (``"at {'KEY': VALUE}: FIELD: the computed value is inf (...)"``); the other points are computed.

    >>> import gearcalc
    >>> base = {"kind": "rows", "gear": {"sun_teeth": 18, "module_mm": 5.0},
    ...         "rows": {"count": 3, "planets_per_row": 3, "relative_width": 2.4}, "sun": {"torque_Nm": 1e3}}
    >>> [round(k, 3) for part in gearcalc.sweep(base, {"rows.relative_width": [2.0, 2.4]})
    ...  for k in part.data["K"]]
    [1.366, 1.489]
    """
    from collections.abc import Sequence

    from . import grid as sw

    axes = {k: v if isinstance(v, Sequence) and not isinstance(v, str) else list(v) for k, v in axes.items()}
    raw, source = _raw(design, overrides)
    _check_tol(tol)
    kind = raw.get("kind")
    if isinstance(kind, str):
        from . import registry

        if kind in registry.kinds():
            from .engine import check_model

            check_model(model, kind)
    from .render import LazyLists

    if scheduler is None:  # numpy columns made lists as they are read (LazyLists): the same values
        for part in sw.stream(raw, source, axes, Options(tol=tol, model=model), chunk=chunk, arrays=True):
            part.data = LazyLists(part.data)
            yield part
        return
    from .distributed import Cluster

    with Cluster(scheduler) as cluster:
        yield from sw.stream(raw, source, axes, Options(tol=tol, model=model), chunk=chunk, cluster=cluster)


def sweep_chunk(raw: Mapping, source: str, axes: Mapping[str, list], start: int, stop: int,
                model: str | None = None, tol: float = DEFAULT_TOL):
    """Points ``start`` to ``stop`` of the grid, evaluated: a pure function of (design, axes, index range),
    the unit a worker process or a cluster computes.  The same values as :func:`sweep` for those points."""
    from . import grid as sw

    return sw.evaluate_range(dict(raw), source, {k: list(v) for k, v in axes.items()}, start, stop,
                             Options(tol=tol, model=model))
