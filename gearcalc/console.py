"""The ``gearcalc`` command's entry point: the CLI (:mod:`gearcalc.cli`) with a fast start and a fast exit.

Two things cost a one-design call time without doing any of its work:

* ``gearcalc --help`` and ``gearcalc --version`` would import typer (and the stdlib modules it pulls
  in, ~40 ms on a clean environment) to print a fixed text. The top-level help is stored in
  ``gearcalc/data/help.txt``, the text typer prints at the standard width; it is printed from there
  when the terminal is at least :data:`HELP_COLUMNS` wide (or output is not a terminal), else typer
  renders it for the narrower width. ``tests/test_console.py`` fails when the stored text is not
  typer's, and tells how to regenerate it (``python -m gearcalc.console --write-help``).
* At exit, the interpreter frees numpy's and typer's modules one by one (~15 ms). Everything the
  command writes is complete when :func:`gearcalc.cli.main` returns (``-o`` files are closed and
  renamed, worker pools shut down), so :func:`main` flushes the standard streams and ends the
  process with :func:`os._exit`. :func:`gearcalc.cli.main` keeps the ordinary ``SystemExit`` for
  callers in the same process (tests, ``CliRunner``).

Before anything else, :func:`main` makes the process safe at its edges:

* A standard descriptor the caller closed (``>&-``, ``2>&-``, ``<&-``) is opened on the null device
  (:func:`open_standard_streams`), so that no file the command opens (an ``-o`` temporary file) takes its
  number. Standard output is opened read-only, as GNU coreutils do: data written there fails with
  ``EBADF`` and the run says ``gearcalc: cannot write standard output: Bad file descriptor`` (exit 74),
  before computing when the command knows where its data goes. Standard error is opened for writing: the
  messages are dropped, the exit status is the one of the run, and nothing meant for stderr reaches stdout.
* SIGTERM, SIGHUP, SIGQUIT and SIGUSR1 unwind like Ctrl-C (:func:`catch_stop_signals`), so an ``-o``
  temporary file is removed and worker processes are stopped; the exit status is 130 for SIGINT and SIGTERM
  and 128 + the signal's number for the others (:func:`interrupted_status`).

This module imports nothing beyond ``os`` and ``sys`` (``signal`` with the CLI) until it knows it needs the CLI.
"""
from __future__ import annotations

import os
import sys

HELP_COLUMNS = 80
"""Terminal width from which click wraps help at its maximum width (80 columns, text at 78)."""

HELP_FILE = os.path.join(os.path.dirname(__file__), "data", "help.txt")


BLAS_THREAD_VARIABLES = ("OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS")


def one_blas_thread(environ=os.environ) -> None:
    """Ask numpy's BLAS for one thread, unless the user chose a number (call before numpy is imported).

    gearcalc's linear algebra is on small matrices, where a BLAS thread pool gains nothing, and its
    threads keep spinning after each call, competing with the main thread on a small machine: 15 ms of
    a one-design zstk call on two cores, and the pool's creation costs every numpy import a few ms. Set
    ``OPENBLAS_NUM_THREADS`` (numpy's wheels) or ``MKL_NUM_THREADS`` to use more; ``--jobs`` is the way
    gearcalc uses several cores.

    >>> env = {"MKL_NUM_THREADS": "4"}
    >>> one_blas_thread(env); sorted(env.items())
    [('MKL_NUM_THREADS', '4'), ('OPENBLAS_NUM_THREADS', '1')]
    """
    for name in BLAS_THREAD_VARIABLES:
        environ.setdefault(name, "1")


def open_standard_streams() -> tuple:
    """Open each closed standard descriptor (0, 1, 2) on the null device and give Python a stream for it;
    the numbers of those that were closed.

    Standard input is opened write-only and standard output read-only, so that reading or writing them
    fails (``EBADF``) as it would on the closed descriptor; standard error write-only, so that messages are
    dropped. :data:`gearcalc.output.STDOUT_CLOSED` records a closed standard output."""
    closed = []
    for fd, flags in ((0, os.O_WRONLY), (1, os.O_RDONLY), (2, os.O_WRONLY)):
        try:
            os.fstat(fd)
            continue
        except OSError:
            pass
        try:
            new = os.open(os.devnull, flags)
            if new != fd:
                os.dup2(new, fd)
                os.close(new)
        except OSError:  # pragma: no cover - no null device: leave the descriptor closed
            continue
        closed.append(fd)
        mode = "r" if fd == 0 else "w"
        stream = open(fd, mode, encoding="utf-8", errors="backslashreplace" if fd == 2 else "strict", closefd=False)
        setattr(sys, ("stdin", "stdout", "stderr")[fd], stream)
    if 1 in closed:
        from . import output

        output.STDOUT_CLOSED = True
    return tuple(closed)


STOP_SIGNALS = ("SIGTERM", "SIGHUP", "SIGQUIT", "SIGUSR1")
"""Signals that stop a run like Ctrl-C (SIGINT): the same cleanup, exit status :func:`interrupted_status`."""


class Interrupted(KeyboardInterrupt):
    """Raised by the handler of a stop signal (:data:`STOP_SIGNALS`): a KeyboardInterrupt, so every path that
    cleans up after Ctrl-C (an ``-o`` temporary file removed, worker processes stopped) does so for it too."""

    def __init__(self, signum: int):
        super().__init__(signum)
        self.signum = signum


_HELD = None
"""While :func:`held_signals` holds them: the stop signals that came meanwhile (else None)."""


def _stop(signum, frame):
    if _HELD is not None:
        _HELD.append(signum)
        return
    if _in_import_machinery(frame) and _defer(signum):
        return
    raise _interruption(signum)


_DEFERRED = None
"""A stop signal that came inside the import machinery, to be raised a moment later (:func:`_defer`)."""


def _in_import_machinery(frame) -> bool:
    """Whether the signal interrupted importlib's own code (a module lock's callback, the finder), where an
    exception is printed and dropped ("Exception ignored in ... _get_module_lock") or leaves the import system
    half-updated: the run then went on to exit 0, or failed later with an internal error (exit 70). A module
    body's own code is not importlib's: an exception there unwinds the import cleanly.  The frames are followed
    outwards to the first module body, so that what importlib calls (a finder on ``sys.meta_path``, a loader) counts
    as importlib's."""
    while frame is not None and frame.f_code.co_name != "<module>":
        if frame.f_code.co_filename.startswith("<frozen importlib"):
            return True
        frame = frame.f_back
    return False


def _defer(signum: int) -> bool:
    """Raise the stop signal ``signum`` 5 ms from now, out of the import machinery (again later if it is still
    inside): a one-shot SIGALRM timer, which gearcalc uses for nothing else.  False where there is no timer."""
    import signal

    global _DEFERRED
    if not hasattr(signal, "setitimer"):
        return False
    _DEFERRED = signum
    signal.signal(signal.SIGALRM, _redeliver)
    signal.setitimer(signal.ITIMER_REAL, 0.005)
    return True


def _redeliver(_alarm, frame):
    global _DEFERRED
    signum, _DEFERRED = _DEFERRED, None
    if signum is not None:
        _stop(signum, frame)


def _interruption(signum: int) -> KeyboardInterrupt:
    import signal

    return KeyboardInterrupt() if signum == signal.SIGINT else Interrupted(signum)


class held_signals:  # noqa: N801 - a context manager, used like a function
    """``with held_signals(): fork()``: SIGINT and the stop signals are blocked in this thread (a process forked
    meanwhile starts with them blocked: a ``--jobs`` worker unblocks them once it has set its own handlers,
    :func:`gearcalc.grid.ignore_sigint`), and one that reaches this process (through another thread) is held
    and raised at the end: not raised inside ``os.fork``'s hooks, where Python would print and drop it."""

    def __enter__(self):
        import signal

        global _HELD
        self.outer, self.mask = _HELD, None
        if self.outer is None:
            _HELD = []
        if hasattr(signal, "pthread_sigmask"):
            self.mask = signal.pthread_sigmask(signal.SIG_BLOCK, stop_signal_numbers())
        return self

    def __exit__(self, kind, value, tb):
        import signal

        global _HELD
        if self.mask is not None:
            signal.pthread_sigmask(signal.SIG_SETMASK, self.mask)  # a blocked signal is taken here
        if self.outer is None:
            pending, _HELD = _HELD, None
            if pending and kind is None:
                raise _interruption(pending[0])
        return False


def stop_signal_numbers() -> set:
    """SIGINT and the :data:`STOP_SIGNALS` that this system has."""
    import signal

    return {getattr(signal, name) for name in ("SIGINT", *STOP_SIGNALS) if hasattr(signal, name)}


def catch_stop_signals() -> None:
    """Make the :data:`STOP_SIGNALS` raise :class:`Interrupted` in the main thread, and SIGINT
    KeyboardInterrupt as it does by default, both held by :class:`held_signals` (a signal the caller
    ignores, as ``nohup`` does for SIGHUP, stays ignored). ``--jobs`` workers are forked with these signals
    blocked and set their own handlers before they take them (:func:`gearcalc.grid.worker_pool`)."""
    import signal

    for name in ("SIGINT", *STOP_SIGNALS):
        signum = getattr(signal, name, None)
        if signum is None:
            continue
        try:
            if signal.getsignal(signum) != signal.SIG_IGN:
                signal.signal(signum, _stop)
        except (ValueError, OSError):  # not in the main thread
            pass


def interrupted_status(exc: BaseException) -> int:
    """The exit status of a run stopped by ``exc``: 130 for Ctrl-C (SIGINT) and SIGTERM, 128 + the number of
    any other stop signal (129 SIGHUP, 131 SIGQUIT, 138 SIGUSR1 on Linux), as the shell reports a process
    that signal ended.

    >>> import signal
    >>> interrupted_status(KeyboardInterrupt()), interrupted_status(Interrupted(signal.SIGTERM))
    (130, 130)
    >>> interrupted_status(Interrupted(signal.SIGHUP)) == 128 + signal.SIGHUP
    True
    """
    import signal

    signum = getattr(exc, "signum", signal.SIGINT)
    return 130 if signum in (signal.SIGINT, signal.SIGTERM) else 128 + int(signum)


def interrupted_message(exc: BaseException) -> str:
    """``gearcalc: interrupted``, naming the signal when it was not SIGINT or SIGTERM."""
    import signal

    signum = getattr(exc, "signum", signal.SIGINT)
    if signum in (signal.SIGINT, signal.SIGTERM):
        return "gearcalc: interrupted"
    return f"gearcalc: interrupted ({signal.Signals(signum).name})"


def main() -> None:
    """Run ``gearcalc`` with the arguments of the process and leave with its exit status."""
    open_standard_streams()
    try:
        _main()
    except KeyboardInterrupt as exc:  # before the CLI's own handling (while importing, parsing)
        _say(interrupted_message(exc))
        _leave(interrupted_status(exc))


def _say(line: str) -> None:
    try:
        sys.stderr.write(line + "\n")
    except (OSError, ValueError, AttributeError):
        pass


def _main() -> None:
    args = sys.argv[1:]
    one_blas_thread()
    if args in (["--help"], ["-h"]) and _standard_width() and os.path.isfile(HELP_FILE):
        with open(HELP_FILE, encoding="utf-8") as fh:
            _leave(_write(fh.read()))
    if args in (["--version"], ["-V"]):
        from . import __version__

        _leave(_write(f"gearcalc {__version__}\n"))
    catch_stop_signals()  # before the CLI (and any file it makes); the fast paths above make none
    from .cli import main as cli_main

    try:
        cli_main()
        code = 0
    except SystemExit as stop:
        code = exit_status(stop.code)
    _leave(code)


def _standard_width() -> bool:
    """Whether click would wrap help at its maximum width here (as ``shutil.get_terminal_size``)."""
    try:
        columns = int(os.environ.get("COLUMNS", "0"))
    except ValueError:
        columns = 0
    if columns <= 0:
        try:
            columns = os.get_terminal_size(sys.__stdout__.fileno()).columns
        except (AttributeError, ValueError, OSError):
            columns = HELP_COLUMNS  # not a terminal: shutil's fallback width
    return columns >= HELP_COLUMNS


def _write(text: str) -> int:
    sys.stdout.write(text)
    return 0


def exit_status(code) -> int:
    """The process status ``sys.exit(code)`` would give (None is 0, text is printed and gives 1).

    >>> exit_status(None), exit_status(2)
    (0, 2)
    """
    if code is None:
        return 0
    if isinstance(code, int):
        return code & 0xFF
    try:
        print(code, file=sys.stderr)
    except (OSError, ValueError):
        pass
    return 1


def _leave(code: int):
    """Flush the standard streams and end the process without the interpreter's teardown."""
    from .output import silence_stdout

    try:
        sys.stdout.flush()
    except BrokenPipeError:  # the reader left: the output was not wanted, nothing failed
        silence_stdout()
    except OSError as exc:  # disk full, I/O error, ...: the output is lost; exit status 74 (EX_IOERR)
        if code != 74:  # 74: the CLI has said so already
            try:
                sys.stderr.write(f"gearcalc: cannot write standard output: {exc.strerror or exc}\n")
            except (OSError, ValueError):
                pass
        code = 74 if code in (0, 1) else code
        silence_stdout()
    except ValueError:
        pass
    try:
        sys.stderr.flush()
    except (OSError, ValueError):
        pass
    os._exit(code)


def render_help() -> str:
    """The top-level help as typer prints it at the standard width (the text of ``help.txt``)."""
    import subprocess

    env = {**os.environ, "COLUMNS": str(HELP_COLUMNS)}
    code = "import sys; from gearcalc.cli import main; sys.argv = ['gearcalc', '--help']; main()"
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, check=False)
    return done.stdout


if __name__ == "__main__" and sys.argv[1:] == ["--write-help"]:
    with open(HELP_FILE, "w", encoding="utf-8") as out:
        out.write(render_help())
    print(f"written: {HELP_FILE}")
