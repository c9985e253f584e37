"""``gearcalc sweep``: one design evaluated over a grid of key values.

A ``--vary KEY=SPEC`` gives one axis: ``start:stop:step`` (stop included when it lies on the grid,
to within 1e-9 of a step) or a list ``v1,v2,...`` (each a TOML value: numbers, ``"root"``, ...).
Several axes make a product grid; the first axis varies slowest.  Every axis value is validated
once against the base design (the error names the key and the value); a calculator that defines
``sweep`` evaluates the whole grid as arrays, others are evaluated point by point.
"""
from __future__ import annotations

import itertools
import math
import tomllib
from collections.abc import Sequence
from typing import Any

from .calculator import DesignError


class SweepError(ValueError):
    """A malformed ``--vary`` or a grid value the design does not accept."""


MAX_POINTS = 50_000_000


def parse_spec(key: str, spec: str) -> list[Any]:
    """Values of one axis from its SPEC.

    >>> parse_spec("rows.count", "4,3")
    [4, 3]
    >>> parse_spec("rows.relative_width", "2.0:2.8:0.4")
    [2.0, 2.4, 2.8]
    """
    spec = spec.strip()
    if not spec:
        raise SweepError(f"--vary {key}=: no values")
    if ":" in spec and not spec.startswith(("\"", "'")):
        parts = spec.split(":")
        if len(parts) != 3:
            raise SweepError(f"--vary {key}={spec}: a range is start:stop:step")
        try:
            start, stop, step = (float(p) for p in parts)
        except ValueError:
            raise SweepError(f"--vary {key}={spec}: start, stop and step must be numbers") from None
        if not all(math.isfinite(v) for v in (start, stop, step)) or step == 0 or (stop - start) / step < 0:
            raise SweepError(f"--vary {key}={spec}: the step must be non-zero and lead from start to stop")
        count = int(math.floor((stop - start) / step + 1e-9)) + 1
        if count > MAX_POINTS:
            raise SweepError(f"--vary {key}={spec}: {count} points is more than {MAX_POINTS}")
        ints = all(float(p).is_integer() and "." not in p and "e" not in p.lower() for p in parts)
        values = [start + k * step for k in range(count)]
        # print-friendly: 2.0 + 2*0.4 = 2.8000000000000003 -> 2.8 (the value the user typed a grid for)
        values = [float(f"{v:.12g}") for v in values]
        return [int(v) for v in values] if ints else values
    out = []
    for item in spec.split(","):
        item = item.strip()
        try:
            out.append(tomllib.loads(f"v = {item}")["v"])
        except tomllib.TOMLDecodeError:
            out.append(item)
    return out


def parse_vary(items: list[str]) -> dict[str, list[Any]]:
    axes: dict[str, list[Any]] = {}
    for item in items:
        key, sep, spec = item.partition("=")
        key = key.strip()
        if not sep or not key:
            raise SweepError(f"--vary {item!r}: expected KEY=SPEC, e.g. --vary rows.relative_width=2.0:2.8:0.1")
        if key in axes:
            raise SweepError(f"--vary {key}: given twice")
        axes[key] = parse_spec(key, spec)
    total = math.prod(len(v) for v in axes.values())
    if total > MAX_POINTS:
        raise SweepError(f"the grid has {total} points, more than {MAX_POINTS}")
    return axes


class Grid(Sequence):
    """The product grid of the axes (first axis slowest) as a sequence of points ``{key: value}``.

    Points are built on demand, so a vectorised sweep of millions of points never holds a dict per
    point: it takes whole axis columns with :meth:`column`.  A slice is a :class:`Grid` too (cheap to
    send to a worker process).

    >>> g = Grid({"a": [1, 2], "b": [10, 20, 30]})
    >>> len(g), g[4], g.column("b")
    (6, {'a': 2, 'b': 20}, [10, 20, 30, 10, 20, 30])
    >>> g[2:4].column("a"), list(g[2:4])
    ([1, 2], [{'a': 1, 'b': 30}, {'a': 2, 'b': 10}])
    """

    def __init__(self, axes: dict[str, list[Any]], start: int = 0, stop: int | None = None):
        self.axes = axes
        self.keys = list(axes)
        self.sizes = [len(axes[k]) for k in self.keys]
        total = math.prod(self.sizes)
        self.start = start
        self.stop = total if stop is None else stop

    def __len__(self) -> int:
        return self.stop - self.start

    def __getitem__(self, index):
        if isinstance(index, slice):
            start, stop, step = index.indices(len(self))
            if step != 1:
                return [self[k] for k in range(start, stop, step)]
            return Grid(self.axes, self.start + start, self.start + max(start, stop))
        k = index + len(self) if index < 0 else index
        if not 0 <= k < len(self):
            raise IndexError("grid point index out of range")
        k += self.start
        point = {}
        for key, size in zip(reversed(self.keys), reversed(self.sizes)):  # the last axis varies fastest
            k, r = divmod(k, size)
            point[key] = self.axes[key][r]
        return {key: point[key] for key in self.keys}

    def __iter__(self):
        combos = itertools.product(*(self.axes[k] for k in self.keys))
        return (dict(zip(self.keys, c)) for c in itertools.islice(combos, self.start, self.stop))

    def column(self, key: str) -> list[Any]:
        """The values of one varied key over the points, in order."""
        j = self.keys.index(key)
        inner = math.prod(self.sizes[j + 1:])
        block = list(itertools.chain.from_iterable(itertools.repeat(v, inner) for v in self.axes[key]))
        if not block or self.stop <= self.start:
            return []
        outer = math.prod(self.sizes[:j])
        first, last = self.start // len(block), -(-self.stop // len(block))
        values = block * max(0, min(outer, last) - first)
        offset = first * len(block)
        return values[self.start - offset:self.stop - offset]


def grid_points(axes: dict[str, list[Any]]) -> Grid:
    """The product grid (first axis slowest): a sequence of points ``{key: value}``."""
    return Grid(axes)


def validate_axes(raw: dict, source: str, axes: dict[str, list[Any]]) -> None:
    """Validate the axis values against the base design.

    Every value is checked against its field (type and bounds, cheap); the whole design, with its
    cross-key checks, is validated with each value substituted alone for at most
    ``FULL_CHECKS`` representative values per axis (both ends and evenly spaced ones between).
    Combinations are checked by the calculator's sweep or by the point-by-point evaluation.
    """
    import copy

    from . import registry
    from .design import InputError, apply_set, check_value, display_name, validate

    kind = raw.get("kind")
    calc = registry.get(kind) if isinstance(kind, str) and kind in registry.kinds() else None
    for key, values in axes.items():
        table, _, name = key.partition(".")
        field = calc.table(table).field(name) if calc and calc.table(table) else None
        if field is not None:
            for v in values:
                _, problem = check_value(field, v)
                if problem:
                    raise SweepError(f"--vary {key}={v!r}: {problem}")
        step = max(1, len(values) // (FULL_CHECKS - 1))
        picks = sorted(set(list(range(0, len(values), step)) + [len(values) - 1]))
        for k in picks:
            trial = copy.deepcopy(raw)
            apply_set(trial, [(key, values[k])])
            try:
                validate(trial, source)
            except InputError as exc:
                prefix = display_name(source) + ": "  # the caller names the file once
                raise SweepError("; ".join(f"--vary {key}={values[k]!r}: {m.removeprefix(prefix)}"
                                           for m in exc.messages)) from None


FULL_CHECKS = 16


def evaluate(raw: dict, source: str, axes: dict[str, list[Any]], options, progress=None, jobs: int = 1) -> list[dict]:
    """Summary rows of every grid point, each led by the varied keys.

    With ``jobs > 1`` the points are split into contiguous chunks evaluated in worker processes;
    the rows come back in grid order and are identical to ``jobs = 1``.
    """
    import copy

    from .design import validate

    validate(copy.deepcopy(raw), source)
    validate_axes(raw, source, axes)
    points = grid_points(axes)
    if jobs > 1 and len(points) > 1:
        from concurrent.futures import ProcessPoolExecutor

        size = -(-len(points) // jobs)
        chunks = [points[k:k + size] for k in range(0, len(points), size)]
        parts = []
        with ProcessPoolExecutor(max_workers=jobs) as pool:
            for part in pool.map(evaluate_points, [raw] * len(chunks), [source] * len(chunks),
                                 [axes] * len(chunks), chunks, [options] * len(chunks)):
                parts.append(part)
                if progress:
                    progress(len(chunks[len(parts) - 1]))
        return join_parts(parts)
    return evaluate_points(raw, source, axes, points, options, progress)


def evaluate_points(raw: dict, source: str, axes: dict[str, list[Any]], points: list[dict], options,
                    progress=None) -> list[dict]:
    """Evaluate the given grid points: the calculator's vectorised sweep if it has one, else one by one."""
    import copy

    from . import registry
    from .design import InputError, apply_set, validate

    base = validate(copy.deepcopy(raw), source)
    calc = registry.get(base.kind)
    fast = getattr(calc, "sweep", None)
    if fast is not None:
        try:
            summaries = fast(base, raw, axes, points, options)
        except DesignError as exc:
            raise SweepError(f"{exc.key}: {exc.message}") from None
        if summaries is not None:
            if progress:
                progress(len(points))
            if isinstance(summaries, dict):  # column-major: keep it so (fast CSV)
                from .render import Columns

                axis_columns = {k: points.column(k) if isinstance(points, Grid) else [p[k] for p in points]
                                for k in axes}
                return Columns({**axis_columns, **summaries})
            return [{**p, **s} for p, s in zip(points, summaries)]
    rows = []
    for p in points:
        trial = copy.deepcopy(raw)
        apply_set(trial, list(p.items()))
        try:
            d = validate(trial, source)
            res = calc.compute(d, options)
        except InputError as exc:
            raise SweepError(f"at {p}: " + "; ".join(exc.messages)) from None
        except DesignError as exc:
            raise SweepError(f"at {p}: {exc.key}: {exc.message}") from None
        rows.append({**p, **res.summary})
        if progress:
            progress(1)
    return rows


def join_parts(parts: list):
    """Concatenate the results of chunks (lists of rows or Columns) in order."""
    from .render import Columns

    if all(isinstance(p, Columns) for p in parts):
        names = list(parts[0].data)
        if all(list(p.data) == names for p in parts):
            return Columns({k: [v for p in parts for v in p.data[k]] for k in names})
    rows: list[dict] = []
    for p in parts:
        rows.extend(p.rows() if isinstance(p, Columns) else p)
    return rows
