"""The entry point: the stored top-level help is typer's, fast paths import nothing heavy, exit statuses."""
import json
import os
import subprocess
import sys

import pytest

from conftest import CONFIGS, cli, cli_proc
from gearcalc import console

FIG3 = CONFIGS / "rows_fig3_n3_nw3_B2.4.toml"


def test_stored_help_is_what_typer_prints():
    with open(console.HELP_FILE, encoding="utf-8") as fh:
        stored = fh.read()
    assert stored == console.render_help(), (
        "gearcalc/data/help.txt is out of date: regenerate it with `python -m gearcalc.console --write-help`")


def run(*args, columns=None, importtime=False):
    env = {k: v for k, v in os.environ.items() if k != "COLUMNS"}
    if columns:
        env["COLUMNS"] = str(columns)
    flags = ["-X", "importtime"] if importtime else []
    return subprocess.run([sys.executable, *flags, "-m", "gearcalc", *args], capture_output=True, text=True,
                          env=env, timeout=60)


@pytest.mark.parametrize("args", [["--help"], ["-h"], ["--version"]])
def test_fast_paths_do_not_import_typer_or_numpy(args):
    p = run(*args, importtime=True)
    assert p.returncode == 0
    imported = [line.rsplit("|", 1)[-1].strip() for line in p.stderr.splitlines() if line.startswith("import time")]
    assert imported and not [m for m in imported if m.split(".")[0] in ("typer", "numpy", "rich")]


def test_fast_help_equals_typer_help_and_narrow_terminals_get_typer():
    from gearcalc import __version__

    assert run("--help").stdout == console.render_help()
    assert run("--version").stdout == f"gearcalc {__version__}\n"
    narrow = run("--help", columns=60)  # click wraps to the narrower width: typer renders it
    assert narrow.returncode == 0 and narrow.stdout != console.render_help()
    assert max(map(len, narrow.stdout.splitlines())) <= 60
    assert "sweep" in narrow.stdout


def test_exit_status_follows_sys_exit(capsys):
    assert console.exit_status(None) == 0 and console.exit_status(2) == 2 and console.exit_status(70) == 70
    assert console.exit_status("gearcalc: stop") == 1  # as sys.exit("text"): printed on stderr, status 1
    assert "gearcalc: stop" in capsys.readouterr().err


def test_other_arguments_reach_the_cli():
    # the entry point hands everything else to typer: usage errors keep click's text and exit 2
    p = run("--versoin")
    assert p.returncode == 2 and "No such option" in p.stderr
    p = run("rows", "--help")
    assert p.returncode == 0 and "Usage: gearcalc rows" in p.stdout


@pytest.mark.slow
def test_console_keeps_every_exit_code_and_all_output(write, tmp_path):
    # console.main() leaves with os._exit after flushing: the process status must be the one main() chose, and a
    # large piped output must arrive whole (a lost buffer would cut the CSV short).
    r = cli_proc("sweep", FIG3, "--vary", "rows.relative_width=0.5:3.0:0.0002", "-f", "csv")
    assert r.code == 0
    assert len(r.out.splitlines()) == 1 + 12501  # header + (3.0-0.5)/0.0002 + 1 points
    assert cli_proc("check", write("kind = 'rows'\n[rows]\ncount = 3\n")).code == 2
    out = tmp_path / "o.json"
    r = cli_proc("run", FIG3, "-o", out)
    assert r.code == cli("run", FIG3, "-o", tmp_path / "ref.json").code
    assert json.loads(out.read_text()) and out.read_text() == (tmp_path / "ref.json").read_text()


def closed(redirect, *args, cwd=None):
    """``gearcalc ARGS`` with a standard descriptor closed by the shell (``>&-``, ``2>&-``); the other two piped."""
    return subprocess.run(["sh", "-c", f'exec "$@" {redirect}', "sh", sys.executable, "-m", "gearcalc",
                           *map(str, args)], capture_output=True, text=True, timeout=120, cwd=cwd)


EBADF = "gearcalc: cannot write standard output: Bad file descriptor\n"  # os.strerror(errno.EBADF) on Linux


@pytest.mark.parametrize("args", [["run", FIG3], ["sweep", FIG3, "--vary", "rows.count=1,2"], ["new", "rows"],
                                  ["check", FIG3], ["--version"]])
def test_closed_stdout_is_exit_74_with_one_line(args):
    # `gearcalc ... >&-`: data has nowhere to go: one line on stderr, exit 74 (EX_IOERR), never a traceback
    # (coreutils: `echo x >&-` says "write error: Bad file descriptor", exit 1; 74 is gearcalc's cannot-write)
    p = closed(">&-", *args)
    assert (p.returncode, p.stderr) == (74, EBADF)


def test_closed_stdout_with_an_output_file_is_a_good_run(tmp_path):
    # the data goes to -o: a closed standard output is not needed; the file is written and the run exits 0
    p = closed(">&-", "run", FIG3, "-o", "out.csv", cwd=tmp_path)
    assert (p.returncode, p.stderr) == (0, "")
    assert (tmp_path / "out.csv").read_text() == cli("run", FIG3, "-f", "csv").out
    assert os.listdir(tmp_path) == ["out.csv"]  # the output did not take descriptor 1's number either


def test_closed_stderr_keeps_the_exit_status_and_stdout_clean(write):
    # `2>&-`: a good run exits 0 with its data alone on stdout; messages are dropped, never mixed into the data
    good = closed("2>&-", "run", FIG3, "-f", "csv")
    assert (good.returncode, good.stdout) == (0, cli("run", FIG3, "-f", "csv").out)
    warned = CONFIGS / "zstk_merko_A_gap.toml"  # a design with a warning on stderr (no allowable stress)
    ref = cli("run", warned, "-f", "csv")
    assert ref.err  # the warning that must not reach stdout
    p = closed("2>&-", "run", warned, "-f", "csv")
    assert (p.returncode, p.stdout) == (ref.code, ref.out)
    bad = closed("2>&-", "run", write("kind = 'rows'\n[rows]\ncount = 3\n"))
    assert (bad.returncode, bad.stdout) == (2, "")


def test_a_stop_signal_inside_the_import_machinery_is_raised_after_it():
    """A stop signal whose handler runs inside importlib's own code (seen in CI: "Exception ignored in
    _get_module_lock.<locals>.cb ... Interrupted", then exit 0, or an internal error) is not raised there: it is
    raised a moment later, outside, as the same Interrupted."""
    import signal
    import time

    from gearcalc import console

    ns: dict = {}
    exec(compile("import sys\ndef cb():\n    return sys._getframe()\nframe = cb()", "<frozen importlib._bootstrap>",
                 "exec"), ns)                                            # a frame of importlib's own code
    old = signal.getsignal(signal.SIGALRM)
    try:
        assert console._stop(signal.SIGUSR1, ns["frame"]) is None       # not raised inside importlib
        with pytest.raises(console.Interrupted) as raised:
            time.sleep(2)                                                 # the 5 ms timer raises it here
        assert raised.value.signum == signal.SIGUSR1
        with pytest.raises(console.Interrupted):                          # elsewhere: raised at once
            console._stop(signal.SIGUSR1, sys._getframe())
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, old)
