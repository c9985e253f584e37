"""``gearcalc sweep``: one design evaluated over a grid of key values (the module is ``grid``; the Python
function :func:`gearcalc.sweep` streams its chunks).

A ``--vary KEY=SPEC`` gives one axis: ``start:stop:step`` (stop included when it lies on the grid,
to within 1e-9 of a step) or a list ``v1,v2,...`` (each a TOML value: numbers, ``"root"``, ...).
Several axes make a product grid; the first axis varies slowest.  Every axis value is validated
once against the base design (the error names the key and the value); a calculator that defines
``sweep`` evaluates the whole grid as arrays, others are evaluated point by point.
"""
from __future__ import annotations

import itertools
import math
import sys
import tomllib
from collections.abc import Sequence
from typing import Any

from .calculator import DesignError, InputError


class SweepError(InputError):
    """A malformed ``--vary`` or a grid value the design does not accept: an :class:`InputError` of one message
    (so a ``ValueError``)."""

    def __init__(self, message: str):
        super().__init__([message])


MAX_POINTS = 100_000_000
"""Grid points of one sweep written as CSV or JSON: those stream a chunk at a time (:func:`stream`), so memory
does not grow with the points (a range axis is lazy, :class:`Range`); the cap bounds the time (hours at
~1e5 points/s)."""

MAX_WHOLE_POINTS = 300_000
"""Grid points of a sweep shown as one table or drawn (``--format table``, ``--plot``): those hold every
point's summary at once (measured peaks: rows 1.7 KB, pins 2.8 KB a point with its ~50 fields and the
output text), so 300 000 points peak below 1 GB."""

LAZY_FROM = 100_000

ITER_BLOCK = 65_536
"""Points of a :class:`Grid` built at a time when it is iterated point by point."""
"""A range axis of more values than this is a lazy :class:`Range` rather than a list."""


class Range(Sequence):
    """The values of a ``start:stop:step`` axis, computed on demand (a list of 1e7 floats would take 320 MB).

    Value ``k`` is ``start + k*step`` rounded to 12 significant digits (2.0 + 2*0.4 = 2.8000000000000003 is
    2.8, the value the user typed a grid for), an int for an integer range.

    >>> r = Range(2.0, 0.4, 3)
    >>> len(r), list(r), r[-1], r[1:3]
    (3, [2.0, 2.4, 2.8], 2.8, [2.4, 2.8])
    """

    def __init__(self, start: float, step: float, count: int, ints: bool = False):
        self.start, self.step, self.count, self.ints = start, step, count, ints

    def __len__(self) -> int:
        return self.count

    def __getitem__(self, k):
        if isinstance(k, slice):
            start, stop, step = k.indices(self.count)
            if self.ints:
                return [self[j] for j in range(start, stop, step)]
            import numpy as np

            return self.take(np.arange(start, stop, step)).tolist()
        if k < 0:
            k += self.count
        if not 0 <= k < self.count:
            raise IndexError("range index out of range")
        v = float(f"{self.start + k * self.step:.12g}")
        return int(v) if self.ints else v

    def take(self, k):
        """Values ``k`` (an array of valid indices >= 0) as a float64 array, bit for bit ``[self[j] for j in k]``
        (:func:`round12` of ``start + k*step``); for a range of floats only."""
        import numpy as np

        return round12(self.start + np.asarray(k, dtype=np.float64) * self.step)

    def __eq__(self, other) -> bool:
        return isinstance(other, Sequence) and len(other) == len(self) and all(a == b for a, b in zip(self, other))

    def __repr__(self) -> str:
        return f"Range(start={self.start!r}, step={self.step!r}, count={self.count})"

    def __reduce__(self):
        return Range, (self.start, self.step, self.count, self.ints)


_POW10 = [float(10 ** k) for k in range(23)]


def round12(v):
    """``float(f"{x:.12g}")`` of every value of a float64 array, vectorised and bit for bit the same: ``x`` rounded
    to 12 significant digits (half to even, on the exact binary value) and read back (correctly rounded).

    For ``1e-11 <= |x| < 1e12`` (every practical grid value): with ``E = floor(log10 |x|)`` and ``P = 10**(11-E)``
    (an exact double, ``0 <= 11-E <= 22``), ``x*P = hi + lo`` exactly (Dekker's product), ``N`` the integer
    nearest ``hi + lo`` (ties to even: ``lo`` decides a tie of ``hi``), and ``N / P`` is the correctly rounded
    value of the decimal ``N * 10**(E-11)``, as the parser gives.  Zeros are kept (``-0.0`` too); other values
    (and any whose ``E`` the logarithm misjudged) take the formatted path.

    >>> import numpy as np
    >>> round12(np.array([2.0 + 2 * 0.4, 0.1 + 0.2, -1/3, 0.0, 1e300])).tolist()
    [2.8, 0.3, -0.333333333333, 0.0, 1e+300]
    """
    import numpy as np

    global _POW10
    if isinstance(_POW10, list):
        _POW10 = np.array(_POW10)
    v = np.asarray(v, dtype=np.float64)
    a = np.abs(v)
    out = np.empty_like(v)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        E = np.floor(np.log10(a))
        fast = (a >= 1e-11) & (a < 1e12) & np.isfinite(E)
        p = np.where(fast, 11.0 - E, 0.0)
        fast &= (p >= 0) & (p <= 22)
        P = _POW10[np.where(fast, p, 0.0).astype(np.intp)]  # exact doubles
        x = np.where(fast, a, 1.0)
        hi = x * P
        # Dekker: lo = x*P - hi exactly, by Veltkamp halves (26 bits each) of both factors
        cx = x * 134217729.0
        xh = cx - (cx - x)
        xl = x - xh
        cp = P * 134217729.0
        ph = cp - (cp - P)
        pl = P - ph
        lo = ((xh * ph - hi) + xh * pl + xl * ph) + xl * pl
        r = np.rint(hi)  # ties to even: right when hi + lo is a tie (lo == 0)
        d = hi - r  # exact
        r = np.where((d == 0.5) & (lo > 0), r + 1.0, r)
        r = np.where((d == -0.5) & (lo < 0), r - 1.0, r)
        # E right: 1e11 <= hi + lo < 1e12 (N may round up to 1e12: then the value is 10**(E+1), as the text)
        fast &= ((hi > 1e11) | ((hi == 1e11) & (lo >= 0))) & (hi < 1e12)
        out[:] = np.copysign(r / P, v)
    zero = v == 0
    out[zero] = v[zero]
    for k in np.flatnonzero(~(fast | zero)).tolist():
        out[k] = float(f"{float(v[k]):.12g}")
    return out


def _range_hint(key: str, parts: list[str]) -> str:
    """For a range with units ("1kN:50kN:1kN"): the bare numbers in the key's unit, converted by the rule that
    converts a number with a unit in a design file (:func:`gearcalc.design.with_unit`)."""
    from . import units
    from .design import number_hint, with_unit

    for p in parts:
        hint = number_hint(p)
        if hint:
            return f" ({p.strip()[:20]}: {hint})"
    unit = units.unit_of(key)
    if not unit:
        return ""
    numbers = []
    for p in parts:
        try:
            numbers.append(float(p))
        except ValueError:
            numbers.append(with_unit(p, unit))
    if any(x is None for x in numbers):
        return f"; write bare numbers in {unit} (the unit is in the key's name)"
    shown = ":".join(str(int(x)) if x.is_integer() and abs(x) < 1e16 else f"{x:.15g}" for x in numbers)
    return f"; write the bare numbers {shown} (in {unit}: the unit is in the key's name)"


def parse_spec(key: str, spec: str) -> list[Any]:
    """Values of one axis from its SPEC.

    >>> parse_spec("rows.count", "4,3")
    [4, 3]
    >>> parse_spec("rows.relative_width", "2.0:2.8:0.4")
    [2.0, 2.4, 2.8]
    """
    spec = spec.strip()
    from .design import _clip

    shown = _clip(spec)  # echoed in messages: at most about 60 characters
    if not spec:
        raise SweepError(f"--vary {key}=: no values")
    if ":" in spec and not spec.startswith(("\"", "'")):
        parts = spec.split(":")
        if len(parts) != 3:
            raise SweepError(f"--vary {key}={shown}: a range is start:stop:step")
        try:
            start, stop, step = (float(p) for p in parts)
        except ValueError:
            raise SweepError(f"--vary {key}={shown}: start, stop and step must be numbers"
                             + _range_hint(key, parts)) from None
        if not all(math.isfinite(v) for v in (start, stop, step)):
            raise SweepError(f"--vary {key}={shown}: start, stop and step must be finite numbers")
        span = stop - start
        if step == 0 or not math.isfinite(span) or span / step < 0:
            why = ("the step must be non-zero and lead from start to stop" if math.isfinite(span)
                   else "stop - start overflows (beyond 1.8e308); use a smaller range")
            raise SweepError(f"--vary {key}={shown}: {why}")
        ratio = span / step
        if not ratio < MAX_POINTS:          # also inf: a step far below the range (e.g. 1:2:5e-324)
            raise SweepError(f"--vary {key}={shown}: the step is too small for the range: "
                             f"{'more than 1e308' if not math.isfinite(ratio) else f'{ratio + 1:.6g}'} points, "
                             f"more than the cap of {MAX_POINTS}")
        count = int(math.floor(ratio + 1e-9)) + 1
        if count > 1 and start + step == start:
            raise SweepError(f"--vary {key}={shown}: the step {step:g} is below the resolution of the start value "
                             f"{start:g} (every point would be the same number)")
        ints = all(float(p).is_integer() and "." not in p and "e" not in p.lower() for p in parts)
        values = Range(start, step, count, ints)
        return values if count > LAZY_FROM else list(values)
    items = spec.split(",")
    if len(items) > MAX_POINTS:
        raise SweepError(f"--vary {key}=...: {len(items)} values, more than the cap of {MAX_POINTS}")
    out = []
    for item in items:
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
        # a block of points at a time from the axis columns of the block: the cost follows the points iterated, not
        # the grid (itertools.product over the axes from the grid's start walked every point before it)
        if not self.keys:
            yield from ({} for _ in range(self.start, self.stop))
            return
        for a in range(self.start, self.stop, ITER_BLOCK):
            block = Grid(self.axes, a, min(a + ITER_BLOCK, self.stop))
            for combo in zip(*(block.column(k) for k in self.keys)):
                yield dict(zip(self.keys, combo))

    def column(self, key: str, array: bool = False) -> list[Any]:
        """The values of one varied key over the points, in order (built for these points only: a chunk of a
        huge grid costs the chunk, not the grid).  ``array``: a float64 numpy array for an axis that is a
        :class:`Range` of floats (computed at once, the same values), else the list."""
        j = self.keys.index(key)
        inner = math.prod(self.sizes[j + 1:])
        values, size = self.axes[key], self.sizes[j]
        if isinstance(values, Range) and not values.ints:
            import numpy as np

            # computed once per grid (chunk): the calculator's sweep and the axis column of its output both ask
            cache = self.__dict__.setdefault("_columns", {})
            column = cache.get(key)
            if column is None:
                column = cache[key] = values.take((np.arange(self.start, self.stop) // inner) % size)
            return column.copy() if array else column.tolist()
        out: list[Any] = []
        i = self.start
        if inner == 1:  # the fastest axis: whole slices of its values
            while i < self.stop:
                k = i % size
                end = min(self.stop, i + size - k)
                out.extend(values[k:k + end - i])
                i = end
            return out
        while i < self.stop:  # one run of equal values at a time
            end = min(self.stop, (i // inner + 1) * inner)
            out.extend(itertools.repeat(values[(i // inner) % size], end - i))
            i = end
        return out


class Sample(dict):
    """Axes whose ``k``-th values together are point ``k`` (a sample drawn by ``gearcalc sweep --sample``,
    :mod:`gearcalc.explore.sample`), not the axes of a product grid: every axis holds one value per point.  A plain
    dict otherwise, so that every path of a grid sweep (chunks, ``--jobs``, ``--scheduler``) takes it unchanged;
    :func:`points_of` gives its points.

    >>> s = Sample({"a": [1, 2, 3], "b": [0.5, 0.25, 0.75]})
    >>> size_of(s), list(points_of(s, 1, 3)), points_of(s, 1, 3).column("b")
    (3, [{'a': 2, 'b': 0.25}, {'a': 3, 'b': 0.75}], [0.25, 0.75])
    """


class Zipped(Grid):
    """The points ``start`` to ``stop`` of a :class:`Sample` (point ``k``: the ``k``-th value of every axis), with
    :class:`Grid`'s interface (a slice, ``column``)."""

    def __init__(self, axes: dict[str, list[Any]], start: int = 0, stop: int | None = None):
        self.axes, self.keys = axes, list(axes)
        total = len(next(iter(axes.values()))) if axes else 0
        self.sizes = [total] * len(self.keys)
        self.start, self.stop = start, total if stop is None else stop

    def __getitem__(self, index):
        if isinstance(index, slice):
            start, stop, step = index.indices(len(self))
            if step != 1:
                return [self[k] for k in range(start, stop, step)]
            return Zipped(self.axes, self.start + start, self.start + max(start, stop))
        k = index + len(self) if index < 0 else index
        if not 0 <= k < len(self):
            raise IndexError("sample point index out of range")
        return {key: self.axes[key][self.start + k] for key in self.keys}

    def __iter__(self):
        return (self[k] for k in range(len(self)))

    def column(self, key: str, array: bool = False) -> list[Any]:
        values = self.axes[key][self.start:self.stop]
        if array and all(type(v) is float for v in values):
            import numpy as np

            return np.array(values, dtype=np.float64)
        return list(values)


def points_of(axes: dict[str, list[Any]], start: int = 0, stop: int | None = None) -> Grid:
    """Points ``start`` to ``stop`` of the axes: of the product grid, or of a :class:`Sample`."""
    return (Zipped if isinstance(axes, Sample) else Grid)(axes, start, stop)


def size_of(axes: dict[str, list[Any]]) -> int:
    """The number of points of the axes (a product grid's, or a :class:`Sample`'s)."""
    return len(points_of(axes))


def ignore_sigint() -> None:
    """Initializer of ``--jobs`` worker processes: they ignore Ctrl-C (SIGINT goes to the whole process
    group), so that the main process alone reports "interrupted" and shuts the pool down, without a
    KeyboardInterrupt traceback from every worker.  The other stop signals: SIGQUIT (from the keyboard
    too) is ignored likewise; SIGTERM, SIGHUP and SIGUSR1 end the worker at once and quietly (the default
    action: a forked worker would otherwise inherit the main process's handler, which raises), and the
    main process, signalled with its process group, cleans up and reports."""
    import signal

    signal.signal(signal.SIGINT, signal.SIG_IGN)
    for name, action in (("SIGQUIT", signal.SIG_IGN), ("SIGTERM", signal.SIG_DFL), ("SIGHUP", signal.SIG_DFL),
                         ("SIGUSR1", signal.SIG_DFL)):
        signum = getattr(signal, name, None)
        if signum is not None and (name == "SIGTERM" or signal.getsignal(signum) != signal.SIG_IGN):
            signal.signal(signum, action)  # SIGTERM always: the pool stops its workers with it
    if hasattr(signal, "pthread_sigmask"):  # forked with them blocked (WorkerPool.submit): now they may come
        from .console import stop_signal_numbers

        signal.pthread_sigmask(signal.SIG_UNBLOCK, stop_signal_numbers())


_MALLOC_TUNED = False


def keep_freed_memory() -> bool:
    """Let glibc's malloc keep the memory a streamed sweep frees and allocates again chunk after chunk (numpy
    temporaries, a chunk's columns and CSV text: blocks of 64 KB to 25 MB) instead of returning it to the system
    and taking it back, page by page: without this a CSV sweep of 1e6 points takes about 220 000 page faults
    (measured: 0.3-0.5 s of system time, about a tenth of the run), with it about 23 000, at the same peak memory.
    ``mallopt``: blocks below 64 MB from the heap (no ``mmap`` per block), at most 256 MB of free heap kept.
    Process-wide, so called for the CLI's CSV sweeps and their worker processes only; once; a no-op (False)
    where the C library is not glibc."""
    global _MALLOC_TUNED
    if _MALLOC_TUNED:
        return True
    try:
        import ctypes
        import platform

        if platform.libc_ver()[0] != "glibc":
            return False
        libc = ctypes.CDLL(None)
        M_TRIM_THRESHOLD, M_TOP_PAD, M_MMAP_THRESHOLD = -1, -2, -3
        ok = (libc.mallopt(M_MMAP_THRESHOLD, 64 << 20) == 1) & (libc.mallopt(M_TRIM_THRESHOLD, 256 << 20) == 1)
        ok &= libc.mallopt(M_TOP_PAD, 64 << 20) == 1
    except (OSError, AttributeError, ValueError):  # pragma: no cover - not glibc
        return False
    _MALLOC_TUNED = bool(ok)
    return _MALLOC_TUNED


def _init_sweep_worker(slots=None) -> None:
    """Initializer of the worker processes of a CSV sweep: Ctrl-C ignored, freed memory kept, and the shared
    buffers of :class:`Slots` (None: results go back through the pool's pipe) kept for :func:`evaluate_post`."""
    global _WORKER_SLOTS
    ignore_sigint()
    keep_freed_memory()
    _WORKER_SLOTS = slots


_WORKER_SLOTS = None
"""In a worker process of a CSV sweep: the :class:`Slots` it shares with the main process (or None)."""


class Slots:
    """Buffers of shared memory through which ``--jobs`` workers hand a chunk's CSV text to the main process.

    Through the pool's pipe, a chunk's text (about 21 MB for 65 536 points of the rows kind) is pickled, written
    into a pipe of 64 KB in some 300 pieces, read back, joined and unpickled: five copies and hundreds of process
    switches, most of them in the main process that also writes the file.  Here the worker copies its text once
    into a slot of an anonymous shared mapping, made before the workers are forked so that they inherit it, and
    the main process writes the file straight from the slot (measured with the blocks no longer joined,
    :class:`gearcalc.render.CsvRenderer`: a sixth less CPU time for a ``--jobs 2`` sweep of 1e6 points).
    A slot is lent to one chunk in flight at a time (:meth:`take`, :meth:`give`); a text larger than a slot goes
    through the pipe as before.  Only where workers are forked (the mapping cannot be pickled): :meth:`make`
    says None elsewhere, or when the system refuses the mapping.  Pages are reserved when first written: a slot
    costs the memory of the largest text it held.
    """

    def __init__(self, count: int, size: int):
        import mmap

        self.count, self.size = count, size
        self.map = mmap.mmap(-1, count * size)  # MAP_SHARED | MAP_ANONYMOUS: inherited by forked children
        self.free = list(range(count))

    @classmethod
    def make(cls, count: int, context) -> "Slots | None":
        if context.get_start_method() != "fork":
            return None
        size = min(SLOT_BYTES, max(1 << 20, SLOT_TOTAL // max(count, 1)))
        try:
            return cls(count, size)
        except (OSError, ValueError, OverflowError):  # pragma: no cover - no shared memory here
            return None

    def take(self) -> int:
        return self.free.pop()

    def give(self, slot: int) -> None:
        self.free.append(slot)

    def view(self, slot: int, size: int) -> memoryview:
        """The ``size`` bytes written into ``slot`` (valid until the slot is lent again)."""
        start = slot * self.size
        return memoryview(self.map)[start:start + size]

    def store(self, slot: int, blocks) -> int | None:
        """Copy the blocks (bytes-like) one after another into ``slot``; their total size, or None when they do
        not fit (nothing is then to be read from the slot)."""
        if sum(map(len, blocks)) > self.size:
            return None
        at = start = slot * self.size
        for block in blocks:
            self.map[at:at + len(block)] = block
            at += len(block)
        return at - start

    def close(self) -> None:
        try:
            self.map.close()
        except BufferError:  # a view of a slot is still held: the mapping goes when the last view does
            pass


SLOT_BYTES = 64 << 20
"""The size of a :class:`Slots` buffer: a chunk of 65 536 points of the widest kind's CSV fits."""

SLOT_TOTAL = 1 << 30
"""The address space all the slots of a sweep may reserve (slots are smaller when there are many)."""


class _InSlot:
    """A worker's result whose text is in a shared slot (:meth:`Slots.store`): the result without its text, the
    slot and the text's size."""

    __slots__ = ("piece", "slot", "size")

    def __init__(self, piece, slot: int, size: int):
        self.piece, self.slot, self.size = piece, slot, size

    def __reduce__(self):
        return _InSlot, (self.piece, self.slot, self.size)


def worker_pool(jobs: int, keep_memory: bool = False, slots: Slots | None = None, context=None):
    """The process pool of ``--jobs``: workers that ignore Ctrl-C (:func:`ignore_sigint`), stopped at once
    (SIGTERM) when the pool is shut down while a KeyboardInterrupt propagates, instead of finishing their
    chunks first.  ``keep_memory``: the workers keep the memory they free (:func:`keep_freed_memory`);
    ``slots``: the :class:`Slots` they share with this process (with ``keep_memory``; ``context`` the
    multiprocessing context whose start method forks)."""
    from concurrent.futures import Future, ProcessPoolExecutor

    class QuietFuture(Future):
        """A future that takes no exception once it is done (cancelled). Python 3.11's pool marks every pending
        future broken when a worker dies (``terminate_broken``) without asking whether it was cancelled
        meanwhile, and the InvalidStateError ends its manager thread with a traceback on stderr: seen when
        SIGTERM or SIGHUP to the process group ended the workers while the main process cancelled its futures
        (CPython 3.11.7)."""

        def set_exception(self, exception) -> None:
            with self._condition:
                if not self.done():
                    super().set_exception(exception)

    class WorkerPool(ProcessPoolExecutor):
        def submit(self, fn, /, *args, **kwargs):
            # the workers are forked here (at the first submit) with the stop signals held: see held_signals
            from .console import held_signals

            with held_signals():
                future = super().submit(fn, *args, **kwargs)
            future.__class__ = QuietFuture  # the same object the pool's manager thread holds
            return future

        def __init__(self, *args, **kwargs):
            super().__init__(*args, **kwargs)
            # The call queue's feeder thread may be blocked writing chunks into a pipe that stopped workers no longer
            # read; the manager thread joins it when it finds the pool broken (a worker ended by SIGTERM or SIGHUP
            # to the process group, or by _stop_workers), and on CPython 3.11.2 that join never returns (seen: a
            # batch with --jobs 2 hung after each stop signal). The workers' own exit does not wait for it: the
            # feeder goes on sending the end-of-work markers while the manager joins the workers.
            queue = getattr(self, "_call_queue", None)
            if queue is not None:
                queue.cancel_join_thread()

        def _stop_workers(self) -> None:
            for proc in list((getattr(self, "_processes", None) or {}).values()):
                if proc.is_alive():
                    proc.terminate()

        def shutdown(self, wait: bool = True, *, cancel_futures: bool = False) -> None:
            if isinstance(sys.exc_info()[1], KeyboardInterrupt):
                self._stop_workers()
                cancel_futures = True
            super().shutdown(wait=wait, cancel_futures=cancel_futures)

        def __exit__(self, exc_type, exc, tb):
            if exc_type is not None and issubclass(exc_type, KeyboardInterrupt):
                self._stop_workers()
                super().shutdown(wait=True, cancel_futures=True)
                return False
            return super().__exit__(exc_type, exc, tb)

    if keep_memory:
        return WorkerPool(max_workers=jobs, initializer=_init_sweep_worker, initargs=(slots,), mp_context=context)
    return WorkerPool(max_workers=jobs, initializer=ignore_sigint)


def grid_points(axes: dict[str, list[Any]]) -> Grid:
    """The product grid (first axis slowest): a sequence of points ``{key: value}``."""
    return points_of(axes)


def validate_axes(raw: dict, source: str, axes: dict[str, list[Any]], word: str = "--vary ") -> None:
    """Validate the axis values: every value against its field (type, bounds, choices), a value its key never
    accepts being a :class:`SweepError` before anything is computed.  A point whose values together do not make
    a valid design (a cross-key rule) is a row with its reason (:func:`evaluate_points`), not an error.  A message
    names the axis as ``{word}KEY=VALUE`` (the Python API's word is ``axes: ``).
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
            if field.type in ("number", "integer") and isinstance(values, list):  # "10kN": the number in the key's unit
                values[:] = [_quantity(field, v) for v in values]
            for v in _values_to_check(values):
                _, problem = check_value(field, v)
                if problem:
                    raise SweepError(f"{word}{key}={_clip(v)}: {problem}")
            continue
        trial = copy.deepcopy(raw)  # not a key of the kind: the loader's words (did you mean ...?)
        apply_set(trial, [(key, values[0])])
        try:
            validate(trial, source)
        except InputError as exc:
            prefix = display_name(source) + ": "  # the caller names the file once
            raise SweepError("; ".join(f"{word}{key}={_clip(values[0])}: {m.removeprefix(prefix)}"
                                       for m in exc.messages)) from None



def _quantity(field, value):
    """A quantity string on a numeric key (``"10 kN"``) as the number in the key's unit; any other value as is."""
    if not isinstance(value, str):
        return value
    from .design import check_value

    number, problem = check_value(field, value)
    return value if problem or isinstance(number, str) else number


def _clip(value) -> str:
    from .design import _clip as clip

    return clip(repr(value))


def _values_to_check(values: list) -> list:
    """The values whose field check stands for all: for an axis of finite floats (a range), its least and
    greatest (a field's bounds are an interval, its type is float for all); else every value.

    >>> _values_to_check([0.5, 0.1, 0.3]), _values_to_check([1, "root"]), _values_to_check(range(1, 10**8))
    ([0.1, 0.5], [1, 'root'], [1, 99999999])
    """
    if isinstance(values, (Range, range)):  # monotone, one type (a Python range: ints)
        return [values[0], values[-1]] if len(values) else []
    if len(values) > 2 and all(type(v) is float for v in values):
        import math

        if all(map(math.isfinite, values)):
            return [min(values), max(values)]
    if len(values) > 2 and all(type(v) is int for v in values):  # e.g. a sample's integer key: each value once
        return list(dict.fromkeys(values))
    return values


def evaluate(raw: dict, source: str, axes: dict[str, list[Any]], options, progress=None, jobs: int = 1):
    """Summary rows of every grid point, each led by the varied keys, as one :class:`Columns` (or rows):
    :func:`stream`'s chunks joined.  With ``jobs > 1`` the chunks are evaluated in worker processes;
    the rows are identical to ``jobs = 1``.
    """
    return join_parts(list(stream(raw, source, axes, options, progress=progress, jobs=jobs)))


CHUNK_POINTS = 65_536
"""Grid points evaluated at a time at most: a streamed sweep holds one chunk (about 50-100 MB of Python values for
the widest kind), and a progress bar advances per chunk; costly points make smaller chunks (:func:`chunk_points`)."""


ERROR_FIELD = "error"
"""The last column of every sweep row: why the point has no results (not a valid design, or a non-finite output;
its outputs are then empty), None for a computed point (interface.md "Sweeps")."""


def evaluate_points(raw: dict, source: str, axes: dict[str, list[Any]], points: list[dict], options,
                    progress=None, arrays: bool = False) -> list[dict]:
    """Evaluate the given grid points: the calculator's vectorised sweep if it has one, else one by one.
    ``arrays``: columns of floats, counts or flags may stay numpy arrays (the CSV writer's fast path); else every
    column of a :class:`Columns` is a list.  A point that is not a valid design, or with a NaN or infinite output,
    has its outputs None, its reason in the column :data:`ERROR_FIELD` and its message in the chunk's
    ``Columns.errors`` (:func:`blank_nonfinite`): the sweep goes on."""
    import copy

    from . import registry
    from .calculator import InvalidPoints
    from .design import InputError, apply_set, validate
    from .engine import finite_error, quiet_numpy
    from .render import Columns

    base = validate(copy.deepcopy(raw), source)
    calc = registry.get(base.kind)
    fast = getattr(calc, "sweep", None)
    if fast is not None:
        try:
            with quiet_numpy():
                summaries = fast(base, raw, axes, points, options)
        except InvalidPoints as exc:  # the valid points computed together, the others rows with their reason
            return _with_invalid(raw, source, axes, points, options, progress, exc.messages)
        except DesignError:  # a rule the kind's sweep does not say point by point: each point on its own
            summaries = None
        if summaries is not None:
            if progress:
                progress(len(points))
            if isinstance(summaries, dict):  # column-major: keep it so (fast CSV)
                reasons = [None] * len(points)
                errors = blank_nonfinite(summaries, points, base, into=reasons)
                axis_columns = {k: points.column(k, arrays) if isinstance(points, Grid) else [p[k] for p in points]
                                for k in axes}
                cols = Columns({**axis_columns, **summaries, ERROR_FIELD: reasons})
                cols = cols if arrays else cols.lists()
                cols.errors = errors
                return cols
            rows = [{**p, **s, ERROR_FIELD: None} for p, s in zip(points, summaries)]
            errors = blank_nonfinite(rows, points, base, lead=axes)
            return Columns.from_rows(rows, errors) if errors else rows
    rows, errors = [], []
    for p in points:
        trial = copy.deepcopy(raw)
        apply_set(trial, list(p.items()))
        try:
            d = validate(trial, source)
            with quiet_numpy():
                res = calc.compute(d, options)
        except (InputError, DesignError) as exc:  # not a valid design: a row with its reason, the sweep goes on
            why = "; ".join(exc.messages) if isinstance(exc, InputError) else str(exc)
            errors.append(f"at {p}: {why}")
            rows.append({**p, ERROR_FIELD: why})
            if progress:
                progress(1)
            continue
        bad = finite_error(d, res)
        if bad is not None:  # the point's error, its outputs empty: the sweep goes on
            why = str(bad).replace('this design', 'this point')
            errors.append(f"at {p}: {why}")
            rows.append({**p, **dict.fromkeys(res.summary), ERROR_FIELD: why})  # its columns kept, outputs None
        else:
            rows.append({**p, **res.summary, ERROR_FIELD: None})
        if progress:
            progress(1)
    if errors:
        cols = Columns.from_rows(rows, errors)
        return Columns({**{k: v for k, v in cols.data.items() if k != ERROR_FIELD},
                        ERROR_FIELD: cols.data[ERROR_FIELD]}, errors)  # the reason last, whichever row came first
    return rows


def _with_invalid(raw, source, axes, points, options, progress, messages):
    """A chunk some of whose points are not valid designs (``messages``: each point's reason, None where valid):
    the valid ones evaluated together (:func:`evaluate_points`), the others rows of their axes and reason."""
    import numpy as np

    from .render import Columns

    n, good = len(points), [k for k, m in enumerate(messages) if m is None]
    data = {k: points.column(k) if isinstance(points, Grid) else [p[k] for p in points] for k in axes}
    reasons = np.array(messages, dtype=object)
    errors = [f"at {points[k]}: {m}" for k, m in enumerate(messages) if m is not None]
    if good:
        sub = as_columns(evaluate_points(raw, source, axes, [points[k] for k in good], options, progress)).lists()
        for name, col in sub.data.items():
            if name in axes:
                continue
            full = reasons if name == ERROR_FIELD else np.full(n, None, dtype=object)
            full[good] = np.array(col + [None], dtype=object)[:-1]  # (a column of lists stays a column of lists)
            if name != ERROR_FIELD:
                data[name] = full.tolist()
        errors += sub.errors
    data[ERROR_FIELD] = reasons.tolist()
    if progress:
        progress(n - len(good))
    return Columns(data, errors)


_NEVER_FLOAT = (type(None), str, list, bool)
"""Types no float compares equal to, or only finite ones (bool): a list column of one such value holds no NaN."""


def blank_nonfinite(data, points, base, lead=(), into: list | None = None) -> list[str]:
    """The points of a sweep's summaries (columns, or rows) with a NaN or infinite output (never printed,
    interface.md "Output"): each such point's outputs made None (an empty CSV cell, a JSON null; ``lead``, the
    varied keys of rows, kept) and its message returned, as :func:`gearcalc.engine.finite_error` words a
    design's.  A column of floats is checked by one sum (non-finite values propagate through it), point by
    point only when that is not finite.  Rows get the reason in :data:`ERROR_FIELD`; columns in ``into`` (a list
    over the points), when given."""
    import math

    import numpy as np

    if isinstance(data, list):  # rows
        bad = [k for k, r in enumerate(data) if any(type(v) is float and not math.isfinite(v) for v in r.values())]
        errors = [_point_error(base, points[k], {f: v for f, v in data[k].items() if f not in lead}) for k in bad]
        for k, e in zip(bad, errors):
            data[k] = {f: (v if f in lead else None) for f, v in data[k].items()}
            data[k][ERROR_FIELD] = e.removeprefix(f"at {points[k]}: ")
        return errors
    mask = None
    for col in data.values():
        if isinstance(col, np.ndarray):
            if col.dtype.kind != "f":
                continue
            m = ~np.isfinite(col)
        elif isinstance(col, list):
            if col and type(col[0]) in _NEVER_FLOAT and col.count(col[0]) == len(col):
                continue  # one value (None, a word, a shared list) at every point: no float (count: by identity first)
            try:
                total = sum(col)  # a column of numbers: one sum
            except TypeError:  # words, None, lists: the floats among them
                total = sum(v for v in col if type(v) is float) if float in set(map(type, col)) else 0.0
            if math.isfinite(total):
                continue
            m = np.array([type(v) is float and not math.isfinite(v) for v in col])
        else:
            continue
        if m.any():
            mask = m if mask is None else mask | m
    if mask is None or not mask.any():
        return []
    bad = np.flatnonzero(mask).tolist()
    errors = [_point_error(base, points[k], {f: col[k] for f, col in data.items()}) for k in bad]
    for k, e in zip(bad, errors) if into is not None else ():
        into[k] = e.removeprefix(f"at {points[k]}: ")
    for f, col in data.items():
        col = col.tolist() if isinstance(col, np.ndarray) else list(col)
        for k in bad:
            col[k] = None
        data[f] = col
    return errors


def _point_error(base, point: dict, summary: dict) -> str:
    """The message of a sweep point whose summary has a non-finite value."""
    from .calculator import Result
    from .engine import finite_error

    bad = finite_error(_PointDesign(base, point), Result(summary=summary))
    return f"at {point}: {str(bad).replace('this design', 'this point')}"


class _PointDesign:
    """The resolved values of a sweep point (the base design with the point's values), as
    :func:`gearcalc.engine.finite_error` reads them to name the likely cause."""

    def __init__(self, base, point: dict):
        self.values = {t: dict(v or {}) for t, v in base.values.items()}
        for key, value in point.items():
            table, _, name = key.partition(".")
            self.values.setdefault(table, {})[name] = value


def _finished(result, shaped, slots: "Slots | None" = None):
    """A worker's chunk: already shaped and post-processed (:func:`evaluate_post`; its text read from its shared
    slot, valid until the slot is lent again), or Columns to shape."""
    from .render import Columns

    if isinstance(result, _InSlot):
        return result.piece.with_text(slots.view(result.slot, result.size))
    return shaped(result) if isinstance(result, Columns) else result


def join_parts(parts: list):
    """Concatenate the results of chunks (lists of rows or Columns) in order."""
    from .render import Columns

    if all(isinstance(p, Columns) for p in parts):
        names = list(parts[0].data)
        if all(list(p.data) == names for p in parts):
            import numpy as np

            def joined(k):
                cols = [p.data[k] for p in parts]
                if cols and all(isinstance(c, np.ndarray) for c in cols):
                    return np.concatenate(cols)
                return [v for c in cols for v in (c.tolist() if isinstance(c, np.ndarray) else c)]

            return Columns({k: joined(k) for k in names}, [e for p in parts for e in p.errors])
    rows: list[dict] = []
    for p in parts:
        rows.extend(p.rows() if isinstance(p, Columns) else p)
    return rows


def as_columns(part):
    """A chunk's result (Columns, or rows from point-by-point evaluation) as :class:`Columns`."""
    from .render import Columns

    return part if isinstance(part, Columns) else Columns.from_rows(part)


def evaluate_range(raw: dict, source: str, axes: dict[str, list[Any]], start: int, stop: int, options,
                   progress=None, arrays: bool = False):
    """Grid points ``start`` to ``stop`` evaluated, as :class:`Columns`: a pure function of (design, axes,
    index range), the unit a worker process or a cluster computes.  The caller validates the design and the
    axes once (:func:`prepare`).  ``arrays``: as in :func:`evaluate_points`."""
    return as_columns(evaluate_points(raw, source, axes, points_of(axes, start, stop), options, progress, arrays))


def prepare(raw: dict, source: str, axes: dict[str, list[Any]], options=None,
            word: str = "--vary ") -> tuple[int, float]:
    """Validate the base design and every axis value once (``word``: as in :func:`validate_axes`), and estimate
    the grid's cost: (points, estimated seconds a point, :func:`point_seconds`); nothing is computed."""
    import copy

    from .design import validate

    base = validate(copy.deepcopy(raw), source)
    validate_axes(raw, source, axes, word)
    total = size_of(axes)
    return total, point_seconds(base, axes, options)


SWEEP_SECONDS_MAX = 600.0
"""The estimated computing time a sweep may take, in seconds (its points times the estimated cost of a point,
:func:`point_seconds`, over the worker processes): a grid beyond it is refused before any point is computed, so
that a mistyped step (``1:1000:0.00001``, 1e8 points) is an error at once rather than hours of work.  The same
rule for every kind; at the vectorised rows path (~3 us a point) the cap of :data:`MAX_POINTS` comes first."""

POINT_SECONDS_DEFAULT = 1e-3
"""The estimated cost of a point of a kind without its own estimate (``Calculator.sweep_cost``)."""

FIRST_OUTPUT_SECONDS = 1.0
"""A chunk holds the points computed in about this time (at most :data:`CHUNK_POINTS`): a streamed sweep says its
first rows within about a second, and a progress bar moves at least as often."""


def point_seconds(base, axes: dict[str, list[Any]], options=None) -> float:
    """The estimated seconds of computing one point of the grid of ``base`` (a validated design) over ``axes``:
    the kind's ``sweep_cost(base, axes, options)`` (its vectorised or point-by-point path, its level and size),
    or :data:`POINT_SECONDS_DEFAULT`."""
    from . import registry
    from .calculator import Options

    calc = registry.get(base.kind)
    cost = getattr(calc, "sweep_cost", None)
    return float(cost(base, axes, options or Options())) if cost is not None else POINT_SECONDS_DEFAULT


def chunk_points(seconds: float) -> int:
    """Points in a chunk of a grid whose points cost ``seconds`` each: about :data:`FIRST_OUTPUT_SECONDS` of work,
    1 to :data:`CHUNK_POINTS`.

    >>> chunk_points(3e-6), chunk_points(0.04), chunk_points(5.0)
    (65536, 25, 1)
    """
    return max(1, min(CHUNK_POINTS, int(FIRST_OUTPUT_SECONDS / max(seconds, 1e-12))))


def _duration(seconds: float) -> str:
    """A duration in words.

    >>> _duration(42.0), _duration(5400.0), _duration(2.5e5)
    ('42 s', '90 min', '2.9 days')
    """
    if seconds < 120:
        return f"{seconds:.0f} s"
    if seconds < 7200:
        return f"{seconds / 60:.0f} min"
    return f"{seconds / 3600:.2g} h" if seconds < 172800 else f"{seconds / 86400:.2g} days"


def cost_problem(axes: dict[str, list[Any]], total: int, seconds: float, workers: int = 1) -> str | None:
    """The message refusing a grid whose estimated time (``total`` points at ``seconds`` each, over ``workers``)
    exceeds :data:`SWEEP_SECONDS_MAX`, with a coarser step of its longest range axis that fits; else None.

    >>> text = cost_problem({"a": Range(1.0, 1e-5, 99_900_001)}, 99_900_001, 2e-5)
    >>> text[:60]
    'the grid has 99900001 points at about 0.02 ms a point: about'
    >>> text[61:]  # doctest: +ELLIPSIS
    '33 min of computing, more than a sweep may take (10 min); ...(e.g. --vary a=1:1000:3.36e-05, 29732143 points)...'
    >>> cost_problem({"a": [1, 2]}, 2, 2e-5) is None
    True
    """
    estimate = total * seconds / max(workers, 1)
    if estimate <= SWEEP_SECONDS_MAX:
        return None
    text = (f"the grid has {total} points at about {seconds * 1e3:.2g} ms a point"
            + (f" over {workers} processes" if workers > 1 else "")
            + f": about {_duration(estimate)} of computing, more than a sweep may take ({_duration(SWEEP_SECONDS_MAX)})"
            + "; narrow a --vary range or take a coarser step")
    fits = int(SWEEP_SECONDS_MAX * max(workers, 1) / seconds)
    key = max(axes, key=lambda k: len(axes[k])) if axes else None
    values = axes.get(key)
    if isinstance(values, Range) and len(values) > 1:
        count = fits // (total // len(values))
        if count >= 2:
            stop = values.start + (len(values) - 1) * values.step
            step = (stop - values.start) / (count - 1)
            step = float(f"{step:.3g}")
            step = step if abs((stop - values.start) / step) < count else float(f"{step * 1.01:.3g}")
            points = int(math.floor(abs((stop - values.start) / step) + 1e-9)) + 1
            text += f" (e.g. --vary {key}={values.start:g}:{stop:g}:{step:g}, {points * (total // len(values))} points)"
    return text + ", or split the grid into several sweeps"


STRUCTURE_PROBES = 256
"""At most this many points are evaluated ahead of a multi-chunk sweep to learn its columns."""


def columns_of(raw: dict, source: str, axes: dict[str, list[Any]], options) -> list[str] | None:
    """The columns of every point of a grid, in order, learnt ahead from one point per combination of the
    axes' values that are not floats (counts and words decide which fields a design has; a float changes
    only values): None when there are more than :data:`STRUCTURE_PROBES` combinations."""
    discrete = {k: _discrete(vals) for k, vals in axes.items()}
    if any(v is None for v in discrete.values()):
        return None
    combos = math.prod(max(1, len(v)) for v in discrete.values())
    if combos > STRUCTURE_PROBES:
        return None
    first = {k: vals[0] for k, vals in axes.items()}
    probes = []
    for combo in itertools.product(*(v or [None] for v in discrete.values())):
        point = dict(first)
        point.update({k: v for k, v in zip(discrete, combo) if v is not None})
        probes.append(point)
    probe = as_columns(evaluate_points(raw, source, axes, probes, options))
    return list(probe.data)


def _discrete(values) -> list | None:
    """The distinct values of an axis that are not floats, in order (lists too: compared by value); None when
    there are more than :data:`STRUCTURE_PROBES` (counted up to there only: a range of 1e7 ints costs 257).

    >>> _discrete([3, 2.5, 3, "root", [1, 2], [1, 2]]), _discrete(range(10**7))
    ([3, 'root', [1, 2]], None)
    """
    if isinstance(values, Range) and not values.ints:
        return []
    out, seen = [], set()
    for v in values:
        if isinstance(v, float):
            continue
        try:
            key = (type(v), v)
            hash(key)
        except TypeError:  # a list value: by its text
            key = (type(v), repr(v))
        if key not in seen:
            seen.add(key)
            out.append(v)
            if len(out) > STRUCTURE_PROBES:
                return None
    return out


def shape(part, header: list[str], axes):
    """A chunk's :class:`Columns` with the grid's columns ``header`` in order (a column a point lacks: None),
    or the :class:`SweepError` of a column the header does not have (a CSV header is written once)."""
    from .render import Columns

    extra = [k for k in part.data if k not in header]
    if extra:  # a column the probes did not show: keep the header (the CSV already has it), say so
        raise SweepError("the grid's points do not all have the same output fields ("
                         + ", ".join(extra[:5]) + " appear late); split the sweep by "
                         + ", ".join(axes) + " or give fewer points per run")
    if list(part.data) == header:
        return part
    return Columns({k: part.data.get(k, [None] * part.n) for k in header}, part.errors)


def evaluate_post(raw: dict, source: str, axes: dict[str, list[Any]], start: int, stop: int, options, arrays: bool,
                  header: list[str], post, slot: int | None = None):
    """:func:`evaluate_range` shaped to ``header`` and passed through ``post`` (a picklable callable, e.g.
    :class:`gearcalc.render.CsvRenderer`): what a ``--jobs`` worker process returns, so that the formatting of
    its chunk runs in the worker too.  ``slot``: in a worker sharing :class:`Slots` with the main process, a
    result with ``blocks()`` and ``with_text()`` (:class:`gearcalc.render.CsvPiece`) leaves its text in that
    slot and returns an :class:`_InSlot` (when the text fits)."""
    piece = post(shape(evaluate_range(raw, source, axes, start, stop, options, None, arrays), header, axes))
    if slot is not None and _WORKER_SLOTS is not None and hasattr(piece, "blocks"):
        size = _WORKER_SLOTS.store(slot, piece.blocks())
        if size is not None:
            return _InSlot(piece.with_text(b""), slot, size)
    return piece


def stream(raw: dict, source: str, axes: dict[str, list[Any]], options, chunk: int | None = None,
           progress=None, jobs: int = 1, cluster=None, debug: bool = False, arrays: bool = False, post=None,
           plan=None, prepared: tuple[int, float] | None = None):
    """The grid evaluated and yielded a chunk at a time (:class:`Columns`, grid order): memory follows the
    chunk, not the grid.  Every chunk has the same columns (those of the whole grid, missing values None),
    so a CSV header written from the first chunk holds for all; with ``jobs > 1`` chunks are evaluated in
    worker processes, a window of ``2 jobs`` in flight; with a ``cluster``
    (:class:`gearcalc.distributed.Cluster`) on its Dask workers, a window of twice its threads in flight.
    The chunks' values are the same in every case.  ``arrays``: columns of floats, counts or flags may be numpy
    arrays rather than lists (the same values; the CSV writer formats those fastest); else every column is a list.
    ``post`` (a picklable callable of a shaped chunk, optional): each chunk is yielded as ``post(chunk)``,
    computed in the worker processes with ``jobs > 1`` (e.g. its CSV text: formatting is most of a big sweep's
    time), in this process otherwise; a :class:`gearcalc.render.CsvPiece` from a worker holds its text in shared
    memory (:class:`Slots`), valid until the next chunk is asked for: write it before.

    ``plan`` (optional, ``--resume``: :mod:`gearcalc.studies`): called once with (points a chunk, points) before any
    point is computed; returns (points a chunk, chunks to skip): the chunk size to use (a resumed run's recorded
    one, so that the chunk boundaries are those of the interrupted run) and how many leading chunks are already
    written (not computed again; the progress bar counts them as done).
    ``prepared``: what :func:`prepare` gave, when the caller has validated the design and the axes already."""
    from .render import Columns

    total, seconds = prepare(raw, source, axes, options) if prepared is None else prepared
    if cluster is not None and total:
        jobs = cluster.connect().threads
    problem = cost_problem(axes, total, seconds, jobs)
    if problem:  # before any point is computed
        raise SweepError(problem)
    size = chunk or chunk_points(seconds)
    if jobs > 1 and not chunk:  # enough chunks to keep every worker busy
        size = min(size, max(1, -(-total // (4 * jobs))))
    skip = 0
    if plan is not None:
        size, skip = plan(size, total)
    ranges = [(k, min(k + size, total)) for k in range(0, total, size)]
    if post is not None and len(ranges) > 1:  # a CSV sweep of the CLI in chunks: freed and allocated again
        keep_freed_memory()
    header = None
    if len(ranges) > 1:  # the columns of the whole grid: a resumed run's are those of the interrupted one
        header = columns_of(raw, source, axes, options)
    if skip:
        if progress:
            progress(sum(b - a for a, b in ranges[:skip]))
        ranges = ranges[skip:]

    def shaped(part: Columns):
        nonlocal header
        if header is None:
            header = list(part.data)
        part = shape(part, header, axes)
        return post(part) if post is not None else part

    if cluster is not None and ranges:
        from .distributed import sweep_chunk, sweep_data

        on_worker = header is not None and post is not None  # the worker shapes and post-processes its chunk
        data = sweep_data(raw, source, axes, options, debug, *((header, post) if on_worker else ()))
        parts = cluster.ordered(sweep_chunk, ranges, data, [b - a for a, b in ranges], progress)
        try:
            for part in parts:
                yield _finished(part, shaped)
        finally:
            parts.close()  # the chunks in flight cancelled at once, not when the generator is collected
        return
    if jobs > 1 and len(ranges) > 1:
        yield from _in_workers(raw, source, axes, options, ranges, jobs, header, post, arrays, shaped, progress)
        return
    for a, b in ranges:
        yield shaped(evaluate_range(raw, source, axes, a, b, options, progress, arrays))


def _in_workers(raw, source, axes, options, ranges, jobs: int, header, post, arrays: bool, shaped, progress):
    """:func:`stream`'s chunks evaluated by ``jobs`` worker processes, a window of ``2 jobs`` in flight, yielded in
    order.  With ``header`` and ``post`` the workers shape and post-process their chunks, and a CSV text comes
    back through a shared slot (:class:`Slots`) where the workers are forked."""
    import multiprocessing
    from collections import deque

    on_worker = header is not None and post is not None  # the worker shapes and post-processes its chunk
    context = multiprocessing.get_context()
    slots = Slots.make(2 * jobs, context) if on_worker else None
    try:
        with worker_pool(jobs, keep_memory=post is not None, slots=slots, context=context) as pool:
            window: deque = deque()

            def finish():
                n, fut, slot = window.popleft()
                yield _finished(fut.result(), shaped, slots)
                if slot is not None:  # the consumer is done with the chunk: its slot may be lent again
                    slots.give(slot)
                if progress:
                    progress(n)

            for a, b in ranges:
                slot = None
                if on_worker:
                    slot = slots.take() if slots is not None else None
                    fut = pool.submit(evaluate_post, raw, source, axes, a, b, options, arrays, header, post, slot)
                else:
                    fut = pool.submit(evaluate_range, raw, source, axes, a, b, options, None, arrays)
                window.append((b - a, fut, slot))
                if len(window) >= 2 * jobs:
                    yield from finish()
            while window:
                yield from finish()
    finally:
        if slots is not None:
            slots.close()
