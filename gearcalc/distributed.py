"""Sweeps and batches on a Dask cluster (``--scheduler``): chunks submitted to ``dask.distributed``, results
taken back in order.

gearcalc does not schedule anything itself here: Dask places the chunks on its workers, retries the chunks of
a lost worker (it still has their task) and reports progress.  What gearcalc sends is data, never a path:

* a sweep: one task holding ``(design data, source name, axes, options)`` (shipped once, fetched by each worker
  from a peer; recomputed from the scheduler's copy when the worker holding it is lost), and one task per chunk
  of grid points, ``evaluate_range(data, start, stop)``: a pure function of those (:func:`gearcalc.grid.
  evaluate_range`);
* a batch: one task per chunk of loaded designs, :func:`gearcalc.engine.compute_batched`.

Results are taken in submission order from a window of chunks in flight (:meth:`Cluster.ordered`): the
client holds one chunk's results at a time, a finished chunk that is not yet due stays on its worker, and a
new chunk is submitted as one is taken.  The output is therefore the in-process output, byte for byte.

This module imports nothing of Dask until a cluster is used: without ``--scheduler`` gearcalc never imports it.
Dask is the optional extra ``gearcalc[dask]``.
"""
from __future__ import annotations

import contextlib
import os
import sys
from collections import deque
from typing import Any, Callable, Iterable, Iterator

EXTRA = "gearcalc[dask]"
ENV = "DASK_SCHEDULER_ADDRESS"
CONNECT_TIMEOUT_S = 10
"""Seconds to reach a scheduler before the run stops with a message."""

LOOPBACK = "127.0.0.1"
LOCAL_DASHBOARD = "127.0.0.1:8787"
"""``local:N`` listens on the loopback interface only: its scheduler, its workers and nannies, and the
dashboard (Dask's usual port, another free one when it is taken; the notice gives the address).  Dask's
default for the dashboard is every interface (0.0.0.0:8787), where anyone who reaches the machine could
read the run's pages (its tasks, the workers' logs and call stacks) for as long as it lasts."""

WAIT_NOTICE_S = 5
"""Seconds without any worker after which the wait is said on stderr (the wait itself has no end: a batch
system may take long to start workers; Ctrl-C stops it)."""


class SchedulerError(Exception):
    """A ``--scheduler`` that cannot be used: malformed, Dask missing, no scheduler at the address, workers
    without gearcalc.  The message says what to do."""


def parse(spec: str) -> tuple[str, Any]:
    """What a ``--scheduler`` value asks for: ``("local", workers or None)``, ``("file", path)`` for a
    scheduler file (``dask scheduler --scheduler-file``), else ``("address", address)``.

    >>> parse("local"), parse("local:3"), parse("tcp://10.0.0.5:8786")
    (('local', None), ('local', 3), ('address', 'tcp://10.0.0.5:8786'))
    """
    text = spec.strip()
    if not text:
        raise SchedulerError("--scheduler: give a scheduler address (tcp://HOST:8786) or local[:N]")
    if text == "local" or text.startswith("local:"):
        count = text.partition(":")[2]
        if not count:
            return "local", None
        if not count.isdigit() or not 1 <= int(count) <= 256:
            from .design import _clip

            raise SchedulerError(f"--scheduler {_clip(text)}: local:N takes a number of worker processes from 1 "
                                 "to 256")
        return "local", int(count)
    if text.endswith(".json"):
        if not os.path.isfile(text):
            from .design import _clip

            raise SchedulerError(f"--scheduler {_clip(text)}: no such scheduler file (as `dask scheduler "
                                 "--scheduler-file` writes it)")
        return "file", text
    return "address", text


def _dask():
    """``distributed``, or a SchedulerError naming the extra."""
    try:
        import distributed
    except ImportError as exc:
        raise SchedulerError(f"--scheduler needs Dask (dask.distributed), which is not installed here: "
                             f"pip install '{EXTRA}' ({exc})") from None
    return distributed


class Cluster:
    """A Dask cluster to compute on, connected on first use and closed (its futures cancelled, a local
    cluster stopped) by ``with``.

    ``spec`` is a ``--scheduler`` value (:func:`parse`) or a connected ``distributed.Client`` (used as it is,
    not closed).  ``say(line)`` receives the notices (the dashboard address, a wait for workers);
    ``debug`` keeps Dask's log messages and numpy's warnings.
    """

    def __init__(self, spec, say: Callable[[str], None] | None = None, debug: bool = False):
        self.spec, self.say, self.debug = spec, say, debug
        if isinstance(spec, str):
            parse(spec)  # a malformed value fails before any work
        self.client = self.local = None
        self.own_client = isinstance(spec, str)
        self.threads = 0
        self.address = self.dashboard = None

    def __enter__(self) -> "Cluster":
        return self

    def __exit__(self, exc_type, exc, tb) -> bool:
        self.close()
        return False

    def connect(self) -> "Cluster":
        """Reach the scheduler (or start the local cluster) and wait for a worker."""
        if self.client is not None:
            return self
        distributed = _dask()
        if not self.debug:
            import logging
            import warnings

            # a lost scheduler is logged at ERROR with tracebacks, which gearcalc says in one line; Dask's
            # configuration gives some loggers their own level (distributed.client: warning), hence each
            for name in [*logging.root.manager.loggerDict, "distributed", "tornado", "bokeh"]:
                if name.split(".")[0] in ("distributed", "tornado", "bokeh"):
                    logging.getLogger(name).setLevel(logging.CRITICAL)
            # a local cluster's dashboard moves to a free port when 8787 is taken: the notice gives the address
            warnings.filterwarnings("ignore", message="Port .* is already in use", category=UserWarning)
        if not self.own_client:
            self.client = self.spec
        else:
            what, value = parse(self.spec)
            try:
                if what == "local":
                    import logging

                    workers = value or os.cpu_count() or 1
                    with _workers_ignore_sigint():
                        self.local = distributed.LocalCluster(
                            n_workers=workers, threads_per_worker=1, processes=True, host=LOOPBACK,
                            dashboard_address=LOCAL_DASHBOARD,
                            silence_logs=logging.DEBUG if self.debug else logging.ERROR)
                    self.client = distributed.Client(self.local, set_as_default=False)
                elif what == "file":
                    self.client = distributed.Client(scheduler_file=value, timeout=CONNECT_TIMEOUT_S,
                                                     set_as_default=False)
                else:
                    self.client = distributed.Client(value, timeout=CONNECT_TIMEOUT_S, set_as_default=False)
            except (OSError, TimeoutError, ValueError) as exc:
                self.close()
                from .design import _clip

                reason = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
                raise SchedulerError(f"--scheduler {_clip(self.spec)}: no Dask scheduler could be reached "
                                     f"({_clip(reason)}); start one with `dask scheduler` and workers with "
                                     "`dask worker ADDRESS`, or use --scheduler local") from None
        self.address = self.client.scheduler.address
        self.dashboard = self._dashboard()
        try:
            self.threads = self._wait_for_threads()
        except OSError:  # the scheduler went away while gearcalc waited for a worker
            raise self.lost() from None
        return self

    def lost(self) -> SchedulerError:
        """The error of a scheduler lost during the run (killed, its host gone): one line, exit 2 as for
        one that cannot be reached at the start; nothing more comes from the cluster."""
        from .design import _clip

        spec = str(self.spec) if isinstance(self.spec, str) else self.address
        where = "" if self.address in (None, spec) else f" at {self.address}"
        return SchedulerError(f"--scheduler {_clip(spec)}: lost the connection to the Dask scheduler{where} "
                              "during the run; start it and its workers again and rerun")

    def _gone(self) -> bool:
        """Whether the client has lost its scheduler (reconnecting, or closed after failing to)."""
        client = self.client
        return client is None or getattr(client, "status", "running") in ("connecting", "closing", "closed")

    def _dashboard(self) -> str | None:
        """The dashboard's address when the scheduler serves one (its page needs bokeh on the scheduler)."""
        try:
            link = self.client.dashboard_link
        except Exception:  # noqa: BLE001 - no dashboard service: nothing to point at
            return None
        if self.local is not None:
            import importlib.util

            if importlib.util.find_spec("bokeh") is None:
                return link + " (pip install bokeh to see it)"
        return link

    def _wait_for_threads(self) -> int:
        """The worker threads of the cluster, after waiting for the first worker."""
        import time

        told = False
        start = time.monotonic()
        while True:
            threads = sum(self.client.nthreads().values())
            if threads:
                return threads
            if not told and time.monotonic() - start > WAIT_NOTICE_S and self.say:
                self.say(f"gearcalc: the Dask scheduler at {self.address} has no workers yet; waiting for one "
                         "(Ctrl-C stops)")
                told = True
            time.sleep(0.1)

    def describe(self) -> str:
        """One line for a terminal: where the work goes and the dashboard."""
        workers = len(self.client.nthreads())
        line = (f"gearcalc: computing on the Dask cluster at {self.address}: {workers} worker"
                f"{'s' if workers != 1 else ''}, {self.threads} thread{'s' if self.threads != 1 else ''}")
        return line + (f"; dashboard {self.dashboard}" if self.dashboard else "")

    def close(self) -> None:
        client, local = self.client, self.local
        self.client = self.local = None
        try:
            if client is not None and self.own_client:
                client.close(timeout=10)
        finally:
            if local is not None:
                local.close(timeout=10)

    def ordered(self, fn: Callable, chunks: Iterable[tuple], shared: Any = None,
                sizes: Iterable[int] | None = None, progress: Callable[[int], None] | None = None,
                window: int | None = None) -> Iterator:
        """``fn(shared, *chunk)`` of every chunk computed on the cluster, yielded in the chunks' order.

        At most ``window`` chunks are in flight (default: twice the cluster's threads, at least 4); the next
        is submitted when the oldest is taken, before it is yielded.  ``progress(size)`` is called as each
        chunk finishes, in any order (``sizes``: the work of each chunk, default 1).  Closing the iterator
        (or an exception, KeyboardInterrupt included) cancels the chunks in flight.
        """
        import uuid

        self.connect()
        client = self.client
        token = uuid.uuid4().hex[:12]
        width = window or max(4, 2 * self.threads)
        data = client.submit(_identity, shared, key=f"gearcalc-data-{token}", pure=False)
        todo = enumerate(zip(chunks, sizes if sizes is not None else _ones()))
        flight: deque = deque()

        def submit() -> bool:
            for k, (args, size) in todo:
                fut = client.submit(fn, data, *args, key=f"gearcalc-chunk-{token}-{k}", pure=False)
                if progress is not None:
                    fut.add_done_callback(lambda f, n=size: progress(n) if f.status == "finished" else None)
                flight.append(fut)
                return True
            return False

        try:
            while len(flight) < width and submit():
                pass
            while flight:
                fut = flight.popleft()
                result = self._result(fut)
                fut.release()
                submit()
                yield result
        except SchedulerError:
            raise
        except Exception as exc:
            if _cancelled_by_loss(exc) or self._gone():
                raise self.lost() from None
            raise
        finally:
            pending = list(flight) + [data]
            flight.clear()
            if pending and self.client is not None:
                try:
                    client.cancel(pending)
                except Exception:  # noqa: BLE001 - the cluster is going away anyway
                    pass

    def _result(self, fut):
        """A chunk's value, waited for while the scheduler is there (a future submitted as the connection
        was lost is never cancelled: it would wait for ever)."""
        while not fut.done():
            if self.client is None or getattr(self.client, "status", "running") in ("closing", "closed"):
                raise self.lost()
            try:
                fut.result(timeout=1)
            except Exception:  # noqa: BLE001 - not done yet, or done: then _result says what it was
                pass
        return _result(fut)


@contextlib.contextmanager
def _workers_ignore_sigint():
    """Start a local cluster's worker processes with Ctrl-C ignored: SIGINT goes to the whole process group,
    and the client alone reports it ("interrupted") and stops them, instead of a KeyboardInterrupt traceback
    from each.  An ignored signal stays ignored across fork and exec; the client ignores it only while it
    starts them (about two seconds: a Ctrl-C then is lost, SIGTERM still stops gearcalc).  (Blocking the
    signal instead does not reach the workers: their tracebacks came back.)"""
    import signal
    import threading

    if threading.current_thread() is not threading.main_thread():
        yield
        return
    before = signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, before)


def _ones():
    while True:
        yield 1


def _cancelled_by_loss(exc: BaseException) -> bool:
    """A future Dask cancelled because the client lost its scheduler."""
    return getattr(exc, "reason", None) == "scheduler-connection-lost"


def _result(fut):
    """A finished chunk's value; a failure that is the workers' environment becomes a SchedulerError."""
    try:
        value = fut.result()
    except ModuleNotFoundError as exc:
        if "gearcalc" in str(exc):
            raise SchedulerError("a Dask worker cannot import gearcalc: install it (the same version) on every "
                                 f"worker: pip install '{EXTRA}'") from None
        raise
    except Exception as exc:
        if type(exc).__name__ == "KilledWorker":
            raise SchedulerError(f"Dask gave up on a chunk after its workers died repeatedly ({exc}); see the "
                                 "workers' logs (memory limit?)") from None
        raise
    if isinstance(value, VersionSkew):
        raise SchedulerError(str(value))
    if isinstance(value, BaseException):  # the in-process error of that chunk (a design error of a point)
        raise value
    return value


def _identity(x):
    return x


class VersionSkew(Exception):
    """A worker runs another gearcalc than the client: its numbers could differ."""


def _worker_setup(version: str, debug: bool):
    """On a worker: the same gearcalc as the client, and numpy's warnings as quiet as the command line's."""
    from . import __version__

    if version != __version__:
        return VersionSkew(f"a Dask worker runs gearcalc {__version__}, this client {version}: install the same "
                           "version on every worker (the results would differ otherwise)")
    if not debug:
        import warnings

        warnings.filterwarnings("ignore", category=RuntimeWarning)
    return None


def sweep_data(raw: dict, source: str, axes: dict, options, debug: bool = False, header=None, post=None) -> tuple:
    """The data a sweep's chunks share: the design as data (what the file holds), its name, the axes and the
    options, the client's gearcalc version, and optionally the grid's columns and the ``post`` step of
    :func:`gearcalc.grid.stream` (a CSV chunk is then formatted on its worker)."""
    from . import __version__

    return raw, source, axes, options, __version__, debug, header, post


def sweep_chunk(data: tuple, start: int, stop: int):
    """Grid points ``start`` to ``stop`` evaluated on a worker (:func:`gearcalc.grid.evaluate_range`): their
    :class:`~gearcalc.render.Columns` (with ``post``: shaped to the grid's columns and post-processed, as
    :func:`gearcalc.grid.evaluate_post`), or the ``SweepError`` the in-process sweep raises for them (a design
    error at a point), returned as a value so that the client raises it at that chunk's turn."""
    from .grid import SweepError, evaluate_post, evaluate_range

    raw, source, axes, options, version, debug, header, post = data
    skew = _worker_setup(version, debug)
    if skew is not None:
        return skew
    try:
        if post is not None:
            return evaluate_post(raw, source, axes, start, stop, options, True, header, post)
        return evaluate_range(raw, source, axes, start, stop, options)
    except SweepError as exc:
        return exc


def batch_data(options, debug: bool = False) -> tuple:
    """The data a batch's chunks share: the options, the debug flag and the client's gearcalc version."""
    from . import __version__

    return options, debug, __version__


def batch_chunk(data: tuple, designs: list) -> list:
    """Outcomes of a chunk of loaded designs on a worker (:func:`gearcalc.engine.compute_batched`: a design
    error is that design's messages)."""
    from .engine import compute_batched

    options, debug, version = data
    skew = _worker_setup(version, debug)
    if skew is not None:
        return skew
    return compute_batched(designs, options, debug)


def is_terminal(stream=None) -> bool:
    stream = sys.stderr if stream is None else stream
    try:
        return stream.isatty()
    except (AttributeError, ValueError, OSError):
        return False
