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

This module imports nothing beyond ``os`` and ``sys`` until it knows it needs the CLI.
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


def main() -> None:
    """Run ``gearcalc`` with the arguments of the process and leave with its exit status."""
    args = sys.argv[1:]
    one_blas_thread()
    if args in (["--help"], ["-h"]) and _standard_width() and os.path.isfile(HELP_FILE):
        with open(HELP_FILE, encoding="utf-8") as fh:
            _leave(_write(fh.read()))
    if args in (["--version"], ["-V"]):
        from . import __version__

        _leave(_write(f"gearcalc {__version__}\n"))
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
