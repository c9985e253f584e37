"""The batch engine: designs loaded, computed (in chunks, in worker processes with ``jobs > 1``) and
reported in order, with the exit status of the batch.

No typer, no printing: messages go to a callback (the CLI prints them on stderr, :mod:`gearcalc.api`
collects them), progress to another.  The CLI, the Python API and a distributed engine call these
functions; a chunk of designs is the unit a worker computes (:func:`compute_batched`).
"""
from __future__ import annotations

from typing import Callable, Iterable, Iterator

from . import registry
from .calculator import DesignError, Options

EXIT_OK, EXIT_CHECK, EXIT_INPUT, EXIT_BUG, EXIT_IO = 0, 1, 2, 70, 74

BATCH_CHUNK = 512
"""Designs per batch call at most: bounds memory and keeps a progress bar moving."""


def load_designs(files: Iterable[str], overrides=(), kind_hint: str | None = None, say: Callable = print,
                 debug: bool = False) -> tuple[list, int]:
    """Load and validate every file; (designs, worst exit status).  A bad file is that file's messages
    (``say``), never the end of the batch; a bug met on one file costs that file only (exit 70)."""
    from . import design as dmod

    worst, designs = EXIT_OK, []
    for f in files:
        try:
            d = dmod.load(f, list(overrides), kind_hint)
        except dmod.InputError as exc:
            for m in exc.warnings + exc.messages:
                say(m)
            worst = max(worst, EXIT_INPUT)
            continue
        except Exception:  # noqa: BLE001 - the last line of defence for one file
            if debug:
                import traceback

                say(traceback.format_exc().rstrip())
            say(f"{dmod.display_name(f)}: internal error while checking this design; please report it "
                "with the design file (run with --debug for the traceback)")
            worst = max(worst, EXIT_BUG)
            continue
        designs.append(d)
    return designs, worst


def compute_files(files: list, overrides, kind_hint: str | None, opts: Options, *, say: Callable = print,
                  progress: Callable | None = None, debug: bool = False, jobs: int = 1, verbose: bool = False,
                  cluster=None, option: str = "--model") -> tuple[list, int]:
    """The one batch: load and validate ``files``, check the model level, compute; (records, worst exit status).

    The command line (``gearcalc run`` and the kind commands) and :func:`gearcalc.api.compute_files` call it,
    each with its own words: ``option`` names the model level in a message (``--model``, ``model =``), an
    unknown level an ``InputError`` before anything is computed.  ``progress(n)``: called with the number of
    designs to compute, returns the ``advance(k)`` callback (or None).  ``cluster``: None, or a context manager
    entered for the computation only, yielding the Dask cluster (:class:`gearcalc.distributed.Cluster`) or None.
    """
    import contextlib

    designs, worst = load_designs(files, overrides, kind_hint, say, debug)
    for kind in sorted({d.kind for d in designs}):
        check_model(opts.model, kind, option)
    advance = progress(len(designs)) if progress is not None else None
    with cluster if cluster is not None else contextlib.nullcontext() as on:
        records, status = run(designs, opts, say=say, advance=advance, debug=debug, jobs=jobs, verbose=verbose,
                              cluster=on)
    return records, max(worst, status)


def check_model(model: str | None, kind: str, option: str = "--model") -> None:
    """A model level chosen by name: an ``InputError`` (a ``ValueError``) listing the kind's levels when it has no
    such level, naming the choice as ``{option} LEVEL`` (the Python API's option is ``model =``)."""
    if model is None:
        return
    levels = list(registry.get(kind).models)
    if model not in levels:
        from .design import InputError, _clip, _suggest

        raise InputError([f"{option} {_clip(model)}: a {kind} design has the levels " + ", ".join(levels)
                          + _suggest(model, levels)])


def compute_one(d, opts: Options, debug: bool = False):
    """Compute one validated design: (result or None, message lines, exit status).  Prints nothing."""
    try:
        with quiet_numpy():
            outcome = registry.get(d.kind).compute(d, opts)
    except Exception as exc:  # noqa: BLE001 - reported per design by report_one
        outcome = exc
    return report_one(d, outcome, debug)


def quiet_numpy():
    """numpy's floating-point warnings off (an overflow becomes inf, which :func:`finite_error` turns into the
    design's error): no ``RuntimeWarning`` escapes a computation."""
    import numpy as np

    return np.errstate(all="ignore")


EXTREME = (1e-100, 1e100)
"""Inputs of a magnitude outside these bounds (0 excepted) are named as the likely cause of a non-finite output."""


def _nonfinite(value, where: str = ""):
    """The first (field path, value) of a non-finite float in summary or detail data, or None."""
    import math

    if isinstance(value, float) or type(value).__name__.startswith("float"):
        return None if math.isfinite(value) else (where, float(value))
    if hasattr(value, "dtype") and hasattr(value, "shape"):  # a numpy array
        import numpy as np

        if value.dtype.kind in "fc" and not np.all(np.isfinite(value)):
            return where, float(value[~np.isfinite(value)].flat[0])
        return None
    if isinstance(value, dict):
        for k, v in value.items():
            hit = _nonfinite(v, f"{where}.{k}" if where else str(k))
            if hit:
                return hit
    elif isinstance(value, (list, tuple)):
        for v in value:
            hit = _nonfinite(v, where)
            if hit:
                return hit
    return None


def finite_error(design, result) -> DesignError | None:
    """The :class:`DesignError` of a result with a NaN or an infinite output field (which is never printed,
    interface.md "Output"): the field, the value and the likely cause (the design's inputs of extreme
    magnitude, from its resolved values), or None when every output is finite."""
    hit = _nonfinite(result.summary) or _nonfinite(result.detail, "detail")
    if hit is None:
        return None
    where, value = hit
    extreme = []
    for table, vals in design.values.items():
        for k, v in (vals or {}).items():
            if isinstance(v, float) and v != 0 and not EXTREME[0] <= abs(v) <= EXTREME[1]:
                extreme.append(f"{table}.{k} = {v!r}")
    cause = ("likely cause: " + ", ".join(extreme[:3]) + " (an input of extreme magnitude)" if extreme
             else "an input at an extreme of its range")
    return DesignError(where, f"the computed value is {value!r} (the arithmetic overflowed or underflowed; "
                              f"{cause}); no result for this design")


def report_one(d, outcome, debug: bool = False):
    """(result or None, message lines, exit status) of a design from its Result or the exception it raised."""
    from .design import display_name

    where = display_name(d.source)
    lines = [f"{where}: warning: {w}" for w in d.warnings]
    if isinstance(outcome, DesignError):
        lines.append(f"{where}: {outcome}")  # key and message (calculator.keyed)
        return None, lines, EXIT_INPUT
    if isinstance(outcome, BaseException):
        if debug:
            import traceback

            lines.append("".join(traceback.format_exception(outcome)).rstrip())
        lines.append(f"{where}: internal error in the {d.kind} calculator; please report it with this design "
                     "file (run with --debug for the traceback)")
        return None, lines, EXIT_BUG
    result = outcome
    bad = finite_error(d, result)
    if bad is not None:
        lines.append(f"{where}: {bad}")
        return None, lines, EXIT_INPUT
    lines += [f"{where}: warning: {w}" for w in result.warnings]
    lines += [f"{where}: check failed: {f}" for f in result.failed]
    return result, lines, EXIT_CHECK if result.failed else EXIT_OK


def compute_batched(designs, opts: Options, debug: bool = False) -> list:
    """Outcomes of many designs in one process, in order: each kind with a ``batch`` hook computes its
    designs together (numpy over designs), the others one by one.  A pure function of its arguments: the
    unit a worker process (or a cluster) computes."""
    outcomes: list = [None] * len(designs)
    by_kind: dict[str, list[int]] = {}
    for k, d in enumerate(designs):
        by_kind.setdefault(d.kind, []).append(k)
    for kind, idx in by_kind.items():
        batch = registry.get(kind).batch
        if batch is not None and len(idx) > 1:
            try:
                with quiet_numpy():
                    results = batch([designs[k] for k in idx], opts)
            except Exception:  # noqa: BLE001 - a bug in the batch path: one by one reports per design
                results = None
            if results is not None and len(results) == len(idx):
                for k, res in zip(idx, results):
                    outcomes[k] = report_one(designs[k], res, debug)
                continue
        for k in idx:
            outcomes[k] = compute_one(designs[k], opts, debug)
    return outcomes


def outcomes(designs: list, opts: Options, debug: bool = False, jobs: int = 1, cluster=None,
             progress: Callable | None = None) -> Iterator:
    """(design, result or None, message lines, exit status) for every design, in order.

    In one process the designs are computed in chunks (about 20, at most :data:`BATCH_CHUNK` designs), so a
    progress bar moves; with ``jobs > 1`` the chunks go to worker processes, with a ``cluster``
    (:class:`gearcalc.distributed.Cluster`) to its Dask workers (results identical).  ``progress(k)``, when
    given, is called as chunks of ``k`` designs finish (on a cluster: in the order they finish)."""
    if cluster is not None and designs:
        from .distributed import batch_chunk, batch_data

        threads = cluster.connect().threads
        size = min(BATCH_CHUNK, max(1, -(-len(designs) // (4 * threads))))
        chunks = [designs[k:k + size] for k in range(0, len(designs), size)]
        parts = cluster.ordered(batch_chunk, [(c,) for c in chunks], batch_data(opts, debug),
                                [len(c) for c in chunks], progress)
        try:
            for chunk, part in zip(chunks, parts):
                for d, o in zip(chunk, part):
                    yield (d, *o)
        finally:
            parts.close()
        return
    if jobs > 1 and len(designs) > 1:
        from .grid import worker_pool  # workers ignore Ctrl-C: the main process reports it once

        pool = worker_pool(jobs)
        size = max(1, -(-len(designs) // (4 * jobs)))
        chunks = [designs[k:k + size] for k in range(0, len(designs), size)]
        try:
            parts = pool.map(compute_batched, chunks, [opts] * len(chunks), [debug] * len(chunks))
            for chunk, part in zip(chunks, parts):
                for d, o in zip(chunk, part):
                    yield (d, *o)
        finally:
            pool.shutdown(cancel_futures=True)
        return
    size = min(BATCH_CHUNK, max(1, -(-len(designs) // 20)))
    for start in range(0, len(designs), size):
        chunk = designs[start:start + size]
        for d, o in zip(chunk, compute_batched(chunk, opts, debug)):
            yield (d, *o)
        if progress:
            progress(len(chunk))


class Warnings:
    """Warnings of a batch: one that many designs share is said once, with the count and the first names.

    >>> w = Warnings(); w.add("low", "a.toml"); w.add("low", "b.toml"); w.add("odd", "a.toml")
    >>> w.lines()
    ['warning (2 designs: a.toml, b.toml): low', 'a.toml: warning: odd']
    """

    SHOWN = 4

    def __init__(self, verbose: bool = False, say: Callable = print):
        self.verbose, self.say = verbose, say
        self.seen: dict[str, list[str]] = {}

    def add(self, text: str, where: str) -> None:
        if self.verbose:  # each as it comes, in design order
            self.say(f"{where}: warning: {text}")
            return
        self.seen.setdefault(text, []).append(where)

    def lines(self) -> list[str]:
        out = []
        for text, wheres in self.seen.items():
            if len(wheres) == 1:
                out.append(f"{wheres[0]}: warning: {text}")
                continue
            names = ", ".join(wheres[: self.SHOWN]) + (f", … and {len(wheres) - self.SHOWN} more (--verbose lists "
                                                         "each)" if len(wheres) > self.SHOWN else "")
            out.append(f"warning ({len(wheres)} designs: {names}): {text}")
        return out

    def flush(self) -> None:
        for line in self.lines():
            self.say(line)
        self.seen.clear()


def run(designs: list, opts: Options, *, say: Callable = print, advance: Callable | None = None,
        debug: bool = False, jobs: int = 1, verbose: bool = False, cluster=None) -> tuple[list, int]:
    """Compute designs in order; (records, worst exit status).  Errors are said as they come, warnings
    once per text at the end (``verbose``: each as it comes).  ``cluster``: computed on its Dask workers
    (:class:`gearcalc.distributed.Cluster`), ``advance`` then called as their chunks finish."""
    from .design import display_name
    from .render import Record

    said = Warnings(verbose, say)
    records, worst = [], EXIT_OK
    failing: dict = {}  # kind -> check name -> designs failing it
    try:
        for d, result, lines, code in outcomes(designs, opts, debug, jobs, cluster,
                                               advance if cluster is not None else None):
            if advance and cluster is None:
                advance(1)
            prefix = f"{display_name(d.source)}: warning: "
            for line in lines:
                if line.startswith(prefix):
                    said.add(line[len(prefix):], display_name(d.source))
                else:
                    say(line)
            worst = max(worst, code)
            if result is not None:
                records.append(Record(d.source, d.kind, d.name, d.resolved(), result))
                for name in result.summary.get("failed_checks") or ():
                    failing.setdefault(d.kind, {}).setdefault(name, 0)
                    failing[d.kind][name] += 1
    finally:
        said.flush()
    if len(designs) > 1:  # a batch ends with one line per failing check (interface.md "Checks")
        for kind, counts in failing.items():
            total = sum(1 for d in designs if d.kind == kind)
            for line in registry.get(kind).check_lines(counts, total, f"{kind} designs"):
                say(line)
    return records, worst
