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

A model level is chosen by name; an unknown one is an ``InputError`` that lists the levels:

>>> gearcalc.compute(r.design, model="exakt")
Traceback (most recent call last):
...
gearcalc.calculator.InputError: model = exakt: a rows design has the levels stepwise, ... (did you mean 'exact'?)

Bad input of any kind (a design the schema refuses, one the physics cannot compute, a value that is no TOML value,
a malformed override or axis, an unknown model level, a tolerance outside (0, 0.1)) raises
:class:`InputError`, a ``ValueError`` whose ``messages`` name the key and the constraint; nothing else.  No numpy
warning escapes a computation.
"""
from __future__ import annotations

import os
import sys
from contextlib import contextmanager
from dataclasses import dataclass, field
from typing import Any, Iterable, Iterator, Mapping, NoReturn

from .calculator import DesignError, InputError, Options, Result
from .design import Design

__all__ = ["load", "compute", "compute_files", "sweep", "sweep_chunk", "Batch", "Result", "Design",
           "InputError", "DesignError", "models"]

DEFAULT_TOL = 1e-6

MAX_VALUES = 1 << 20
"""The most values (scalars, arrays and tables, counted as they are met) read from one design given as data, one
override's value or one axis's values: a design has about fifty (a design file of the 1 MiB cap, a few 100 000)."""

MAX_OVERRIDES = 10_000
"""The most overrides one call takes (a design has about fifty keys)."""


def models(kind: str) -> tuple[str, ...]:
    """The model levels of a kind, cheapest first.

    >>> models("rows")
    ('stepwise', 'exact', 'continuous')
    """
    return _registry().get(_kind_arg(kind, required=True)).models


def load(design, *, overrides: Iterable[Any] | Mapping[str, Any] = (), kind: str | None = None) -> Design:
    """A validated design, every default filled in.

    Parameters
    ----------
    design : str or os.PathLike or dict or Design
        A design file (``"-"``: standard input), the design as data (what ``tomllib`` gives for a file: tables
        of strings, numbers, booleans, dates and arrays; numpy numbers and arrays and tuples are taken as the
        plain values), or a design ``load`` returned (returned as it is unless ``overrides`` or another ``kind``
        are given).
    overrides : mapping, or iterable of ``"KEY=VALUE"`` strings or (key, value) pairs
        Values that replace the design's, as the command line's ``--set`` does: ``{"rows.count": 4}``,
        ``["rows.count=4"]`` (the value read as TOML) or ``[("rows.count", 4)]``.
    kind : str, optional
        Require this kind (as ``gearcalc rows`` does); a design without ``kind`` takes it.

    Raises
    ------
    InputError
        With ``messages``: every problem of the design, each naming the key and the constraint.
    """
    from . import design as dmod

    kind = _kind_arg(kind)
    pairs = _overrides(overrides)
    if (isinstance(design, Design) and not pairs and getattr(design, "_loaded", False)
            and kind in (None, design.kind)):
        return design
    raw, source = _raw(design, pairs)
    given = raw.get("kind")
    if kind is not None and isinstance(given, str) and given in _registry().kinds() and given != kind:
        _fail(f'{dmod.display_name(source)}: kind = "{given}": not a {kind} design (kind = "{kind}" was asked for)')
    d = dmod.validate(raw, source, kind)
    d._loaded = True  # checked here: handed back as it is next time
    return d


def _raw(design, overrides=()) -> tuple[dict, str]:
    """(design data as a file gives it, a fresh copy with the overrides set; its source name) from a path, data
    or a loaded design; ``overrides`` as :func:`load` takes them (checked by :func:`_overrides`)."""
    from . import design as dmod

    pairs = _overrides(overrides)

    if isinstance(design, Design):
        source = str.__str__(design.source) if isinstance(design.source, str) else "<data>"
        try:
            data = design.resolved()
        except Exception as exc:  # noqa: BLE001 - a Design built by hand with values that are no tables
            _fail(f"{dmod.display_name(source)}: a Design whose values are not tables ({_type(exc)}); "
                  "make one with gearcalc.load()")
        raw = _plain(data, dmod.display_name(source))
    elif isinstance(design, Mapping):
        source = "<data>"
        raw = _plain(design, source)
    elif isinstance(design, (str, bytes, os.PathLike)):
        try:
            source = os.fsdecode(design)
        except (TypeError, ValueError) as exc:
            _fail(f"design: not a path ({_type(design)}: {_type(exc)})")
        raw = dmod.read_toml(source)
    else:
        _fail(f"design: a path, the design as data (a dict) or a Design, not {_a(design)}")
    if pairs:
        dmod.apply_set(raw, pairs)
    return raw, source


def compute(design, *, model: str | None = None, tol: float = DEFAULT_TOL, detail: bool = False,
            overrides: Iterable[Any] | Mapping[str, Any] = (), kind: str | None = None) -> Result:
    """Compute one design: its :class:`~gearcalc.calculator.Result`.

    ``result.summary`` holds the summary fields (names with their unit suffix, as the CSV columns),
    ``result.detail`` the per-element tables (with ``detail=True``), ``result.warnings`` and
    ``result.failed`` (the failed design checks: the command line's exit status 1), ``result.design`` the
    resolved design; ``result.to_dict()`` is the JSON object, ``result.to_pandas()`` a one-row DataFrame.

    Raises ``InputError`` (a ``ValueError``) for bad input: a design the schema refuses, an unknown model level,
    a tolerance outside [1e-15, 0.1), and as its subclass ``DesignError`` a design the physics cannot compute
    (also one whose output would be infinite or NaN).
    """
    from .engine import check_model, finite_error

    model, tol, detail = _model_arg(model), _tol_arg(tol), _flag("detail", detail)
    d = load(design, overrides=overrides, kind=kind)
    check_model(model, d.kind, MODEL)
    with _quiet():
        result = _registry().get(d.kind).compute(d, Options(tol=tol, model=model, detail=detail))
    bad = finite_error(d, result)  # never an inf or a NaN as a result: the design's error, as on the command line
    if bad is not None:
        raise bad
    result.design = d.resolved()
    result.name, result.kind = d.name, d.kind
    return result


def _check_tol(tol) -> None:
    """An InputError for a tolerance :func:`_tol_arg` refuses (for :mod:`gearcalc.explore.api`)."""
    _tol_arg(tol)


MODEL = "model ="
"""How messages name the model level chosen in the Python API (the command line's ``--model``)."""


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

    def _repr_html_(self) -> str:
        """One row per design (the summaries, units in the column titles), the messages below (Jupyter)."""
        from .render import html_rows

        mixed = len({r.kind for r in self.records}) > 1
        return html_rows([({"kind": r.kind} if mixed else {}) | r.result.summary for r in self.records],
                         notes=self.messages)

    def to_pandas(self):
        """One row per design (the summaries; ``kind`` first when several kinds), as a pandas DataFrame."""
        import pandas as pd  # optional: not a dependency of gearcalc

        mixed = len({r.kind for r in self.records}) > 1
        return pd.DataFrame([({"kind": r.kind} if mixed else {}) | r.result.summary for r in self.records])


def compute_files(paths, *, kind: str | None = None, model: str | None = None, tol: float = DEFAULT_TOL,
                  detail: bool = False, overrides: Iterable[Any] | Mapping[str, Any] = (),
                  jobs: int = 1, progress=None, verbose: bool = False, say=None, scheduler=None) -> Batch:
    """Compute design files and folders (every ``*.toml`` below a folder), as ``gearcalc run`` does.

    A bad file is its messages and exit status 2, never the end of the batch; ``jobs > 1`` spreads the
    designs over worker processes (identical results), ``scheduler`` over a Dask cluster (``--scheduler``: an
    address, ``"local:N"``, or a ``distributed.Client``; needs the ``dask`` extra; identical results).
    ``progress(k)`` is called as designs finish; ``say(line)`` receives each message as it comes (default:
    collected in ``Batch.messages`` only).  Bad arguments (not the files' contents) raise ``InputError``.
    """
    from . import design as dmod
    from . import engine

    paths = _paths(paths)
    kind, model, tol = _kind_arg(kind), _model_arg(model), _tol_arg(tol)
    detail, verbose = _flag("detail", detail), _flag("verbose", verbose)
    jobs = _count("jobs", jobs, 1, MAX_JOBS)
    progress, say = _callback("progress", progress), _callback("say", say)
    scheduler = _scheduler_arg(scheduler)
    pairs = _overrides(overrides)
    batch = Batch()

    def tell(line: str) -> None:
        batch.messages.append(line)
        if say is not None:
            say(line)

    files = dmod.expand_paths(paths, warn=tell)
    cluster = None if scheduler is None else _on_cluster(scheduler, tell)
    with _quiet():
        records, status = engine.compute_files(files, pairs, kind, Options(tol=tol, model=model, detail=detail),
                                               say=tell, progress=progress and (lambda n: progress), verbose=verbose,
                                               jobs=jobs if scheduler is None else 1, cluster=cluster, option=MODEL)
    batch.records, batch.status = records, status
    return batch


def sweep(design, axes: Mapping[str, Any], *, model: str | None = None, tol: float = DEFAULT_TOL,
          overrides: Iterable[Any] | Mapping[str, Any] = (), chunk: int | None = None,
          scheduler=None) -> Iterator:
    """Evaluate one design over the product grid of ``axes`` (the first axis varies slowest), a chunk at a
    time: yields :class:`~gearcalc.render.Columns` (``.data[field]`` lists, the varied keys first, each made from
    the chunk's numpy array when first read; rows with ``.rows()``, a DataFrame with ``.to_pandas()``), in grid
    order.  Memory is bounded by the chunk,
    not by the grid.  ``scheduler``: the chunks are computed on a Dask cluster (an address, ``"local:N"``
    or a ``distributed.Client``; needs the ``dask`` extra), the same values in the same order.
    A point that is not a valid design, or whose output would be infinite or NaN, has every output None, its
    reason in the column ``error`` (None for a computed point) and its message in the chunk's ``errors``
    (``"at {'KEY': VALUE}: FIELD: the computed value is inf (...)"``); the other points are computed.

    ``axes`` maps dotted keys to their values: a list, a tuple, a ``range`` or a 1-d numpy array, not empty; at
    most ``gearcalc.grid.MAX_POINTS`` points in all (counted before any value is read).  The design, the axes and
    every axis value are checked when ``sweep`` is called (an ``InputError``); a design error at a grid point
    is raised when its chunk is computed.

    >>> import gearcalc
    >>> base = {"kind": "rows", "gear": {"sun_teeth": 18, "module_mm": 5.0},
    ...         "rows": {"count": 3, "planets_per_row": 3, "relative_width": 2.4}, "sun": {"torque_Nm": 1e3}}
    >>> [round(k, 3) for part in gearcalc.sweep(base, {"rows.relative_width": [2.0, 2.4]})
    ...  for k in part.data["K"]]
    [1.366, 1.489]
    """
    from . import grid as sw
    from .engine import check_model

    model, tol = _model_arg(model), _tol_arg(tol)
    chunk = None if chunk is None else _count("chunk", chunk)
    scheduler = _scheduler_arg(scheduler)
    axes = _axes(axes)
    raw, source = _raw(design, _overrides(overrides))
    opts = Options(tol=tol, model=model)
    prepared = sw.prepare(raw, source, axes, opts, AXES)
    check_model(model, raw["kind"], MODEL)
    if scheduler is None:  # (on a cluster the time is judged by its threads, when connected)
        problem = sw.cost_problem(axes, *prepared)
        if problem:  # the command line's words for a range, the API's
            _fail(AXES + problem.replace("narrow a --vary range", "narrow an axis").replace("(e.g. --vary ", "(e.g. "))
    else:
        from .distributed import parse

        if isinstance(scheduler, str):
            with _scheduler_errors():
                parse(scheduler)  # a malformed address fails now, not at the first chunk
    return _chunks(raw, source, axes, opts, chunk, prepared, scheduler)


AXES = "axes: "
"""How messages name a sweep's axis in the Python API (the command line's ``--vary``)."""


def sweep_grid(design, axes: Mapping[str, Iterable[Any]], *, model: str | None = None, tol: float = DEFAULT_TOL,
               overrides: Iterable[tuple[str, Any]] | Mapping[str, Any] = (), scheduler=None):
    """The whole of :func:`sweep` at once: a :class:`gearcalc.studies.GridSweep` (its chunks joined; memory: every
    point), with ``.data``, ``.rows()``, ``.to_pandas()`` and ``.to_xarray()`` (an ``xarray.Dataset`` with one
    dimension per varied key; xarray is not a dependency of gearcalc: install it to use this).

    >>> import gearcalc
    >>> base = {"kind": "rows", "gear": {"sun_teeth": 18, "module_mm": 5.0},
    ...         "rows": {"count": 3, "planets_per_row": 3, "relative_width": 2.4}, "sun": {"torque_Nm": 1e3}}
    >>> g = gearcalc.sweep_grid(base, {"rows.count": [2, 3], "rows.relative_width": [2.0, 2.4, 2.8]})
    >>> g.n, g.shape
    (6, (2, 3))
    """
    from . import grid as sw
    from .studies import GridSweep

    parts = list(sweep(design, axes, model=model, tol=tol, overrides=overrides, scheduler=scheduler))
    joined = sw.join_parts(parts) if parts else None
    data = joined.lists().data if joined is not None else {}
    return GridSweep(data, list(joined.errors) if joined is not None else [], axes)


def _chunks(raw: dict, source: str, axes: dict, opts: Options, chunk, prepared: tuple, scheduler) -> Iterator:
    from . import grid as sw

    if scheduler is None:  # numpy columns made lists as they are read (render.LazyLists): the same values
        from .render import LazyLists

        for part in _quietly(sw.stream(raw, source, axes, opts, chunk=chunk, prepared=prepared, arrays=True)):
            part.data = LazyLists(part.data)
            yield part
        return
    from .distributed import Cluster

    with _scheduler_errors(), Cluster(scheduler) as cluster:
        yield from _quietly(sw.stream(raw, source, axes, opts, chunk=chunk, cluster=cluster, prepared=prepared))


def sweep_chunk(raw: Mapping, source: str, axes: Mapping[str, Any], start: int, stop: int,
                model: str | None = None, tol: float = DEFAULT_TOL):
    """Points ``start`` to ``stop`` of the grid, evaluated: a pure function of (design, axes, index range),
    the unit a worker process or a cluster computes.  The same values as :func:`sweep` for those points (the
    design and the axes are checked as there)."""
    from . import grid as sw
    from .engine import check_model

    model, tol = _model_arg(model), _tol_arg(tol)
    if not isinstance(raw, Mapping):
        _fail(f"raw: the design as data (a dict), not {_a(raw)}")
    if not isinstance(source, str):
        _fail(f"source: the design's name or path (a string), not {_a(source)}")
    source = str.__str__(source)
    start, stop = _count("start", start, 0), _count("stop", stop, 0)
    axes = _axes(axes)
    raw = _plain(raw, source)
    total = sw.prepare(raw, source, axes, Options(tol=tol, model=model), AXES)[0]
    if not start < stop <= total:
        _fail(f"start = {start}, stop = {stop}: must be 0 <= start < stop <= {total} (the grid's points)")
    check_model(model, raw["kind"], MODEL)
    with _quiet():
        return sw.evaluate_range(raw, source, axes, start, stop, Options(tol=tol, model=model))


# ---------------------------------------------------------------- the arguments, checked
def _fail(message: str) -> NoReturn:
    raise InputError([message])


def _registry():
    from . import registry

    return registry


def _type(obj) -> str:
    """The type of ``obj`` for a message (never its repr: that may fail, or be huge)."""
    from .design import _clip

    t = type(obj)
    name = t.__qualname__ if t.__module__ == "builtins" else f"{t.__module__}.{t.__qualname__}"
    return _clip(name) if isinstance(name, str) else "object"


def _a(obj) -> str:
    name = _type(obj)
    return ("an " if name[:1] in "aeiou" else "a ") + name


_PLAIN = {str, int, float, bool}
_READABLE = (int, float, bool, type(None), bytes)


def _shown(obj) -> str:
    """A key or value for a message: its text when it is a simple value, else its type."""
    from .design import _show

    return _show(obj) if isinstance(obj, (str,) + _READABLE) else _a(obj)


def _kind_arg(kind, required: bool = False) -> str | None:
    from .design import _clip, _suggest

    kinds = _registry().kinds()
    if kind is None and not required:
        return None
    if not isinstance(kind, str):
        _fail(f"kind: a string, one of {', '.join(kinds)}; not {_a(kind)}")
    kind = str.__str__(kind)
    if kind not in kinds:
        _fail(f"kind = {_clip(repr(kind))}: unknown kind; the kinds are {', '.join(kinds)}" + _suggest(kind, kinds))
    return kind


def _model_arg(model) -> str | None:
    if model is None:
        return None
    if not isinstance(model, str):
        _fail(f"{MODEL} {_shown(model)}: a model level is a string, e.g. 'exact' (gearcalc.models(kind) lists them)")
    return str.__str__(model)


def _tol_arg(tol) -> float:
    """A tolerance: any real number (int, float, numpy, Fraction, Decimal) that
    :func:`~gearcalc.calculator.tol_problem` takes, as a float."""
    import decimal
    import numbers

    from .calculator import tol_problem

    real = isinstance(tol, (numbers.Real, decimal.Decimal)) and not isinstance(tol, bool)
    shown = f"tol = {_shown(tol) if real else _a(tol)}"
    try:
        value = float(tol) if real else None
    except (TypeError, ValueError, OverflowError):
        value = None
    problem = tol_problem(value)
    if problem:
        _fail(f"{shown}: {problem}")
    return value


def _flag(name: str, value) -> bool:
    """True or False (or a numpy bool, 0 or 1; None is False)."""
    if isinstance(value, bool):
        return value
    if value is None:
        return False
    numpy = sys.modules.get("numpy")
    if numpy is not None and isinstance(value, numpy.bool_):
        return bool(value)
    if type(value) is int and value in (0, 1):
        return bool(value)
    _fail(f"{name} = {_shown(value)}: must be True or False")


def _count(name: str, value, least: int = 1, most: int | None = None) -> int:
    """A whole number >= ``least`` (and <= ``most``): a Python or numpy integer, not a bool."""
    import operator

    if not isinstance(value, bool):
        try:
            n = operator.index(value)
        except TypeError:
            n = None
        if n is not None and n >= least and (most is None or n <= most):
            return n
    _fail(f"{name} = {_shown(value)}: must be a whole number >= {least}" + (f", <= {most}" if most else ""))


MAX_JOBS = 256
"""The most worker processes ``jobs`` asks for (the command line's ``--jobs`` range)."""


def _callback(name: str, fn):
    if fn is None or callable(fn):
        return fn
    _fail(f"{name}: a function or None, not {_a(fn)}")


def _scheduler_arg(scheduler):
    if scheduler is None:
        return None
    if isinstance(scheduler, str):
        return str.__str__(scheduler)
    distributed = sys.modules.get("distributed")
    if distributed is not None and isinstance(scheduler, distributed.Client):
        return scheduler
    _fail(f"scheduler: an address (tcp://HOST:8786), 'local[:N]', a scheduler file (*.json) or a "
          f"distributed.Client; not {_a(scheduler)}")


@contextmanager
def _scheduler_errors():
    """A cluster that cannot be used (``SchedulerError``: malformed, Dask missing, unreachable) as an InputError,
    named as the argument ``scheduler``."""
    from .distributed import SchedulerError

    try:
        yield
    except SchedulerError as exc:
        message = str(exc)
        if message.startswith("--scheduler"):
            message = "scheduler" + message[len("--scheduler"):]
        raise InputError([message]) from None


@contextmanager
def _on_cluster(scheduler, say):
    """The Dask cluster of ``scheduler`` for one computation (its errors as InputError, :func:`_scheduler_errors`)."""
    from .distributed import Cluster

    with _scheduler_errors(), Cluster(scheduler, say=say) as cluster:
        yield cluster


def _paths(paths) -> list[str]:
    if isinstance(paths, (str, bytes, os.PathLike)):
        paths = [paths]
    elif isinstance(paths, Mapping) or not isinstance(paths, Iterable):
        _fail(f"paths: a path or a list of paths (files and folders), not {_a(paths)}")
    out = []
    try:
        for k, p in enumerate(paths):
            try:
                out.append(os.fsdecode(p))
            except (TypeError, ValueError):
                _fail(f"paths[{k}]: a path (str or os.PathLike), not {_a(p)}")
    except InputError:
        raise
    except Exception as exc:  # noqa: BLE001 - a program's iterable that fails while read
        _fail(f"paths: could not be read ({_type(exc)})")
    return out


def _strings(value, where: str, what: str) -> list[str]:
    """One string, or an iterable of strings (at most :data:`MAX_OVERRIDES`), as a list; else an InputError
    saying ``what`` is expected."""
    from itertools import islice

    if isinstance(value, str):
        return [str.__str__(value)]
    if isinstance(value, (bytes, bytearray, Mapping)) or not isinstance(value, Iterable):
        _fail(f"{where}: {what}; not {_a(value)}")
    try:
        items = list(islice(value, MAX_OVERRIDES + 1))
    except Exception as exc:  # noqa: BLE001 - a program's iterable that fails while read
        _fail(f"{where}: could not be read ({_type(exc)})")
    if len(items) > MAX_OVERRIDES:
        _fail(f"{where}: more than {MAX_OVERRIDES} items")
    for k, item in enumerate(items):
        if not isinstance(item, str):
            _fail(f"{where}[{k}]: {what}; not {_a(item)}")
    return [str.__str__(item) for item in items]


def _key(key, where: str) -> str:
    """A dotted key of an override or an axis, checked."""
    from .design import _clip, key_problem

    if not isinstance(key, str):
        _fail(f"{where}: the key {_shown(key)} is not a string; a key is dotted text such as 'rows.count'")
    key = str.__str__(key)
    problem = key_problem(key)
    if problem:
        _fail(f"{where}: {_clip(repr(key))}: {problem}")
    return key


def _items(mapping: Mapping, where: str, limit: int) -> list[tuple[Any, Any]]:
    """The (key, value) pairs of a mapping, at most ``limit`` of them; a mapping that cannot be read (its
    ``__iter__`` or ``__getitem__`` fails) is an InputError."""
    from itertools import islice

    try:
        if type(mapping) is dict:
            items = list(islice(mapping.items(), limit + 1))
        else:
            items = [(k, mapping[k]) for k in islice(mapping, limit + 1)]
    except Exception as exc:  # noqa: BLE001 - a program's mapping that fails while read
        _fail(f"{where}: the mapping ({_type(mapping)}) could not be read ({_type(exc)})")
    if len(items) > limit:
        _fail(f"{where}: more than {limit} entries; a design has about fifty keys")
    return items


def _overrides(overrides) -> list[tuple[str, Any]]:
    """``overrides`` as checked (dotted key, plain value) pairs: from a mapping, or an iterable of ``"KEY=VALUE"``
    strings (the value read as TOML, as ``--set``) and (key, value) pairs; one string is one override."""
    from itertools import islice

    from .design import parse_set

    where = "overrides"
    if overrides is None:
        return []
    if isinstance(overrides, Mapping):
        items = _items(overrides, where, MAX_OVERRIDES)
    elif isinstance(overrides, str):
        items = [overrides]
    elif isinstance(overrides, (bytes, bytearray)) or not isinstance(overrides, Iterable):
        _fail(f"{where}: a mapping {{key: value}} or a list of 'KEY=VALUE' strings or (key, value) pairs; "
              f"not {_a(overrides)}")
    else:
        try:
            items = list(islice(overrides, MAX_OVERRIDES + 1))
        except Exception as exc:  # noqa: BLE001 - a program's iterable that fails while read
            _fail(f"{where}: could not be read ({_type(exc)})")
        if len(items) > MAX_OVERRIDES:
            _fail(f"{where}: more than {MAX_OVERRIDES} overrides; a design has about fifty keys")
    pairs = []
    for k, item in enumerate(items):
        if isinstance(overrides, Mapping):
            key, value = item
        elif isinstance(item, str):
            pairs.extend(parse_set([str.__str__(item)], "overrides:"))
            continue
        elif isinstance(item, (tuple, list)) and len(item) == 2:
            key, value = item
        else:
            _fail(f"{where}[{k}]: a 'KEY=VALUE' string or a (key, value) pair, not {_a(item)}")
        key = _key(key, where)
        pairs.append((key, _plain(value, f"{where}: {key}")))
    return pairs


def _axes(axes) -> dict[str, Any]:
    """A sweep's axes checked: a mapping of dotted keys to non-empty sequences of values (lists, tuples, ranges,
    1-d numpy arrays), at most ``MAX_POINTS`` points in all (counted from the lengths before any value is read:
    a ``range`` is never listed); the values plain copies."""
    from collections.abc import Sequence

    from . import grid as sw

    if not isinstance(axes, Mapping):
        _fail(f"axes: a mapping of keys to values, e.g. {{'rows.count': [3, 4]}}; not {_a(axes)}")
    items = _items(axes, "axes", MAX_OVERRIDES)
    if not items:
        _fail("axes: no axis; give at least one key and its values, e.g. {'rows.count': [3, 4]}")
    numpy = sys.modules.get("numpy")
    sample = isinstance(axes, sw.Sample)  # a sample (gearcalc.explore): point k is the k-th value of every axis
    out: dict[str, Any] = {}
    points = 1
    for key, values in items:
        key = _key(key, "axes")
        where = f"axes: {key}"
        if numpy is not None and isinstance(values, numpy.ndarray):
            if values.ndim != 1:
                _fail(f"{where}: a numpy array of {values.ndim} dimensions; an axis is one list of values")
        elif isinstance(values, (str, bytes, bytearray, memoryview)) or not isinstance(values, Sequence):
            _fail(f"{where}: a list, a tuple or a range of values, not {_a(values)}")
        try:
            n = len(values)
        except Exception as exc:  # noqa: BLE001 - a program's sequence that fails while read
            _fail(f"{where}: could not be read ({_type(exc)})")
        if n == 0:
            _fail(f"{where}: no values")
        if sample and out and n != points:
            _fail(f"{where}: {n} values; every axis of a sample has one value per point ({points})")
        points = n if sample else points * n
        if points > sw.MAX_POINTS:
            _fail(f"axes: the grid has more than {sw.MAX_POINTS} points (the cap)")
        out[key] = values
    for key, values in out.items():
        out[key] = _axis_values(values, f"axes: {key}")
    return sw.Sample(out) if sample else out


def _axis_values(values, where: str):
    """An axis's values as plain values: a ``range`` (ints) as it is, a numpy array as its list, other values
    each checked and copied."""
    from itertools import islice

    from . import grid as sw

    if isinstance(values, (range, sw.Range)):
        return values
    numpy = sys.modules.get("numpy")
    if numpy is not None and isinstance(values, numpy.ndarray):
        if values.dtype.kind not in "biufUO":
            _fail(f"{where}: a numpy array of {_type(values.dtype)} {values.dtype.kind!r}; an axis takes numbers, "
                  "strings or booleans")
        values = values.tolist()
    try:
        n = len(values)
        values = list(islice(values, n + 1))
    except Exception as exc:  # noqa: BLE001 - a program's sequence that fails while read
        _fail(f"{where}: could not be read ({_type(exc)})")
    if len(values) != n:
        _fail(f"{where}: a sequence whose length is not its number of values")
    if all(type(v) in _PLAIN for v in values):
        return values
    budget = [MAX_VALUES]
    return [_plain(v, f"{where}[{k}]", budget) for k, v in enumerate(values)]


def _plain(value: Any, where: str, budget: list[int] | None = None) -> Any:
    """``value`` as plain TOML data, a fresh copy: tables (dicts with string keys), arrays (lists), strings,
    ints, floats, booleans, dates and times.  Other mappings are taken as tables, tuples and other sequences
    as arrays, numpy numbers and arrays as their Python values, subclasses of str, int and float as those; any
    other object (a lock, a generator, a set, bytes, None, ...) is an InputError naming its place, as is a
    value nested more than ``MAX_NESTING`` levels deep (or containing itself) or of more than
    :data:`MAX_VALUES` values (``budget``: what is left of them).  Iterative: no recursion on hostile input.

    >>> import numpy as np
    >>> _plain({"a": (1, np.float64(2.5)), "b": {"c": np.array([1, 2])}}, "x")
    {'a': [1, 2.5], 'b': {'c': [1, 2]}}
    """
    import datetime
    from collections.abc import Sequence
    from itertools import islice

    from .design import MAX_NESTING, _clip

    if budget is None:
        budget = [MAX_VALUES]
    numpy = sys.modules.get("numpy")
    box: list[Any] = [None]
    stack: list[tuple[Any, Any, Any, str, int]] = [(box, 0, value, "", 0)]
    while stack:
        parent, slot, v, path, depth = stack.pop()
        at = f"{where}: {path}" if path else where
        budget[0] -= 1
        if budget[0] < 0:
            _fail(f"{where}: more than {MAX_VALUES} values (or values that repeat themselves); a design has "
                  "about fifty")
        t = type(v)
        if t in _PLAIN or isinstance(v, (datetime.date, datetime.time)):  # a datetime is a date
            parent[slot] = v
            continue
        if isinstance(v, str):  # subclasses: numpy.str_, a StrEnum
            parent[slot] = str.__str__(v)
            continue
        if isinstance(v, int):  # an IntEnum, a subclass (a bool is a bool)
            parent[slot] = int.__int__(v)
            continue
        if isinstance(v, float):  # numpy.float64, a subclass
            parent[slot] = float.__float__(v)
            continue
        if numpy is not None and isinstance(v, (numpy.generic, numpy.ndarray)):
            kind = v.dtype.kind
            if kind not in "biufU" or (isinstance(v, numpy.ndarray) and v.size > budget[0]):
                _fail(f"{at}: {_a(v)} of dtype {_clip(str(v.dtype))} is not a design value; a value is a string, "
                      "a number, a boolean, a date, an array or a table")
            budget[0] += 1  # counted as its Python value
            stack.append((parent, slot, v.tolist(), path, depth))
            continue
        container = isinstance(v, Mapping) or (isinstance(v, Sequence)
                                               and not isinstance(v, (bytes, bytearray, memoryview)))
        if not container:
            _fail(f"{at}: {_a(v)} is not a design value; a value is a string, a number, a boolean, a date, an "
                  "array (list) or a table (dict)")
        if depth >= MAX_NESTING:
            _fail(f"{at}: nested more than {MAX_NESTING} levels deep (or it contains itself); a design is tables "
                  "of plain values and arrays")
        if isinstance(v, Mapping):
            items = _items(v, at, max(budget[0], 0))
            out: Any = {}
            for k, x in items:
                if type(k) is not str:
                    if not isinstance(k, str):
                        _fail(f"{at}: the key {_shown(k)} is not a string; keys of a design are strings")
                    k = str.__str__(k)
                out[k] = None  # the order of the keys kept; the value filled in below
                sub = f"{path}.{k}" if path else k
                stack.append((out, k, x, _clip(sub, 120), depth + 1))
        else:
            try:
                n = len(v)
                if n > budget[0]:
                    _fail(f"{where}: more than {MAX_VALUES} values; a design has about fifty")
                elements = v if t is list else list(islice(v, n + 1))
                if len(elements) != n:
                    _fail(f"{at}: {_a(v)} whose length is not its number of elements")
            except InputError:
                raise
            except Exception as exc:  # noqa: BLE001 - a program's sequence that fails while read
                _fail(f"{at}: {_a(v)} that could not be read ({_type(exc)})")
            out = [None] * len(elements)
            for k, x in enumerate(elements):
                stack.append((out, k, x, f"{path}[{k}]", depth + 1))
        parent[slot] = out
    return box[0]


@contextmanager
def _quiet():
    """No numpy warning escapes a computation (a design's undefined values are flags and messages, never a
    ``RuntimeWarning``), whatever the caller's warning filters (e.g. ``simplefilter("error")``): numpy's
    floating-point warnings off (:func:`~gearcalc.engine.quiet_numpy`) and any other ``RuntimeWarning`` ignored."""
    import warnings

    from .engine import quiet_numpy

    with warnings.catch_warnings(), quiet_numpy():
        warnings.simplefilter("ignore", RuntimeWarning)
        yield


def _quietly(chunks: Iterator) -> Iterator:
    """The chunks of a sweep, each computed under :func:`_quiet` (not the caller's code between them)."""
    try:
        while True:
            with _quiet():
                try:
                    part = next(chunks)
                except StopIteration:
                    return
            yield part
    finally:
        chunks.close()
