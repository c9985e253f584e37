"""Sampled points evaluated for the optimiser and the sensitivity analysis: the grid sweep's pure chunks
(:func:`gearcalc.grid.evaluate_range` over a :class:`gearcalc.grid.Sample`), in this process, in ``--jobs`` worker
processes or on a Dask cluster, in order, so that all three give the same numbers.

Unlike ``gearcalc sweep``, a point that is not a valid design (a combination of values the design's cross-key
checks refuse, e.g. cheeks that leave no room for the rims) does not stop the evaluation: its outputs are empty
(None) and its message kept; the explorer treats it as infeasible.  A chunk holding such a point is split in two
until the point is alone, so the valid points keep the vectorised path.
"""
from __future__ import annotations

from typing import Any

__all__ = ["Evaluator", "explore_chunk"]


def _tolerant(raw: dict, source: str, axes, start: int, stop: int, options):
    """Points ``start`` to ``stop`` as rows (dicts) or Columns; an invalid point alone: its varied keys and its
    message (key ``"error"``)."""
    from ..grid import SweepError, evaluate_range, points_of

    try:
        return [evaluate_range(raw, source, axes, start, stop, options)]
    except SweepError as exc:
        if stop - start == 1:
            return [{**points_of(axes, start, stop)[0], "error": str(exc)}]
    mid = (start + stop) // 2
    return _tolerant(raw, source, axes, start, mid, options) + _tolerant(raw, source, axes, mid, stop, options)


def explore_chunk(data: tuple, start: int, stop: int):
    """The unit of work: points ``start`` to ``stop`` of the sample in ``data`` (design, source, axes, options)
    as :class:`gearcalc.render.Columns` (column ``error``: None, or the message of a point that is not a valid
    design).  A pure function of its arguments."""
    from ..grid import join_parts
    from ..render import Columns

    raw, source, axes, options = data
    parts = _tolerant(raw, source, axes, start, stop, options)
    rows: list[dict] = []
    cols = [p for p in parts if isinstance(p, Columns)]
    if len(cols) == len(parts):
        out = join_parts(parts) if len(parts) > 1 else parts[0]
        if isinstance(out, Columns):
            if "error" not in out.data:  # the sweep's own column holds the messages of its invalid points
                out.data["error"] = [None] * out.n
            return out
        rows = out
    else:
        for p in parts:
            rows.extend(p.rows() if isinstance(p, Columns) else [p])
    for r in rows:
        r.setdefault("error", None)
    return Columns.from_rows(rows)


class Evaluator:
    """Evaluates samples of one design: ``evaluator(axes)`` the :class:`Columns` of the points of a
    :class:`gearcalc.grid.Sample`, in order; counts the points it evaluated (``evaluations``).  ``jobs > 1``:
    worker processes; ``cluster``: a :class:`gearcalc.distributed.Cluster`.  The same values in every case."""

    def __init__(self, raw: dict, source: str, options, jobs: int = 1, cluster=None, chunk: int | None = None):
        import copy

        from ..design import validate
        from ..grid import point_seconds

        self.raw, self.source, self.options = raw, source, options
        self.jobs, self.cluster, self.chunk = jobs, cluster, chunk
        self.base = validate(copy.deepcopy(raw), source)
        self.evaluations = 0
        self._pool = None
        self._seconds = None
        self._point_seconds = point_seconds

    def seconds(self, axes) -> float:
        """The estimated cost of a point (:func:`gearcalc.grid.point_seconds`)."""
        if self._seconds is None:
            self._seconds = self._point_seconds(self.base, axes, self.options)
        return self._seconds

    def __call__(self, axes) -> Any:
        from ..grid import chunk_points, join_parts, size_of
        from ..render import Columns

        total = size_of(axes)
        self.evaluations += total
        if not total:
            return Columns({k: [] for k in list(axes) + ["error"]})
        size = self.chunk or chunk_points(self.seconds(axes))
        workers = self.cluster.connect().threads if self.cluster is not None else self.jobs
        if workers > 1:
            size = min(size, max(1, -(-total // (4 * workers))))
        ranges = [(a, min(a + size, total)) for a in range(0, total, size)]
        data = (self.raw, self.source, axes, self.options)
        if self.cluster is not None:
            parts = list(self.cluster.ordered(explore_chunk, ranges, data, [b - a for a, b in ranges]))
        elif self.jobs > 1 and len(ranges) > 1:
            parts = [f.result() for f in [self.pool().submit(explore_chunk, data, a, b) for a, b in ranges]]
        else:
            parts = [explore_chunk(data, a, b) for a, b in ranges]
        out = join_parts(parts)
        return out if isinstance(out, Columns) else Columns.from_rows(out)

    def pool(self):
        if self._pool is None:
            from ..grid import worker_pool

            self._pool = worker_pool(self.jobs)
        return self._pool

    def close(self) -> None:
        if self._pool is not None:
            self._pool.shutdown(cancel_futures=True)
            self._pool = None

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
        return False
