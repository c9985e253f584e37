"""Shared test helpers: run the CLI in process (fast) or as a subprocess (end to end)."""
import os
import signal
import subprocess
import sys
from pathlib import Path

import pytest

from gearcalc.console import one_blas_thread

# The tests compute in this process: give numpy's BLAS one thread, as the command line does (before numpy is
# first imported). A thread pool on the small linear systems of rows' bridges and stepwise active set costs
# 3x on an idle two-core machine and up to 40x when other processes load it.
one_blas_thread()

ROOT = Path(__file__).resolve().parent.parent
CONFIGS = ROOT / "configs"
PAPER = ROOT / "paper"
"""Paper cases shipped apart from configs/ because they fail a design check on purpose."""
DATA = Path(__file__).resolve().parent / "data"

if signal.getsignal(signal.SIGINT) is signal.SIG_IGN:
    # pytest started in the background of a non-interactive shell (`pytest &`) inherits SIGINT ignored, and so
    # would every gearcalc subprocess of the Ctrl-C tests (an ignored signal stays ignored across exec):
    # give the suite the normal handler, so those tests test gearcalc, not how pytest was started
    signal.signal(signal.SIGINT, signal.default_int_handler)


class Run:
    def __init__(self, code, out, err):
        self.code, self.out, self.err = code, out, err

    def __repr__(self):
        return f"Run(code={self.code}, out={self.out[:300]!r}, err={self.err[:500]!r})"


def cli(*args, input=None):
    """Run gearcalc in process through click's test runner."""
    from typer.testing import CliRunner

    from gearcalc.cli import app

    r = CliRunner().invoke(app, [str(a) for a in args], input=input)
    if r.exception and not isinstance(r.exception, SystemExit):
        raise r.exception
    return Run(r.exit_code, r.stdout, r.stderr)


def cli_proc(*args, input=None, env=None, cwd=None):
    """Run ``python -m gearcalc`` as a subprocess (end to end)."""
    e = dict(os.environ)
    e.update(env or {})
    p = subprocess.run([sys.executable, "-m", "gearcalc", *map(str, args)], input=input, capture_output=True,
                       text=True, env=e, cwd=cwd, timeout=120)
    return Run(p.returncode, p.stdout, p.stderr)


@pytest.fixture
def write(tmp_path):
    """Write a design text to a file in tmp_path and return its path."""

    def _write(text, name="design.toml"):
        p = tmp_path / name
        p.write_text(text) if isinstance(text, str) else p.write_bytes(text)
        return p

    return _write
