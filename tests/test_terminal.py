"""What a person sees in a terminal: tables that fit, progress on stderr only (real pseudo-terminals).

Each test runs ``python -m gearcalc`` with standard output and/or standard error on a pseudo-terminal of
a given size (as tmux at 80x24 or 120x40 would give), reads everything the program wrote, and checks the
layout rules of the man page's OUTPUT section: one line per design, units in the headers, no number
wrapped or cut, nothing on stdout but the data.
"""
import fcntl
import os
import pty
import re
import select
import struct
import subprocess
import sys
import termios

import pytest

from conftest import CONFIGS, PAPER

ANSI = re.compile(r"\x1b\[[0-9;?]*[A-Za-z]|\x1b\][^\x07]*\x07|\r")
NUMBER = re.compile(r"^-?(\d+(\.\d*)?|\.\d+)([eE][-+]?\d+)?$")


def _pty(cols, rows):
    master, slave = pty.openpty()
    fcntl.ioctl(slave, termios.TIOCSWINSZ, struct.pack("HHHH", rows, cols, 0, 0))
    return master, slave


def _drain(fds, proc, timeout=120):
    """Read every fd until the process ends and the fds are dry; {fd: bytes}."""
    out = {fd: b"" for fd in fds}
    live = set(fds)
    while live:
        ready, _, _ = select.select(list(live), [], [], timeout)
        if not ready:
            proc.kill()
            raise AssertionError("no output for %s s" % timeout)
        for fd in ready:
            try:
                chunk = os.read(fd, 65536)
            except OSError:  # EIO: the pty's other side is closed
                chunk = b""
            if chunk:
                out[fd] += chunk
            else:
                live.discard(fd)
    proc.wait(timeout=timeout)
    return out


def run_tty(*args, cols=80, rows=24, stdout_tty=True, stderr_tty=False, env=None):
    """Run gearcalc with stdout and/or stderr on a pty of that size; (exit code, stdout text, stderr text)."""
    e = dict(os.environ, **(env or {}))
    e.pop("COLUMNS", None)
    e.pop("NO_COLOR", None)
    fds, close = {}, []
    if stdout_tty:
        m_out, s_out = _pty(cols, rows)
        fds["out"], close = m_out, close + [s_out]
    if stderr_tty:
        m_err, s_err = _pty(cols, rows)
        fds["err"], close = m_err, close + [s_err]
    p = subprocess.Popen([sys.executable, "-m", "gearcalc", *map(str, args)],
                         stdout=close[0] if stdout_tty else subprocess.PIPE,
                         stderr=(close[-1] if stderr_tty else subprocess.PIPE), stdin=subprocess.DEVNULL, env=e)
    for fd in close:
        os.close(fd)
    readers = list(fds.values()) + ([p.stdout.fileno()] if not stdout_tty else []) + (
        [p.stderr.fileno()] if not stderr_tty else [])
    got = _drain(readers, p)
    out = got[fds["out"]] if stdout_tty else got[p.stdout.fileno()]
    err = got[fds["err"]] if stderr_tty else got[p.stderr.fileno()]
    for fd in fds.values():
        os.close(fd)
    return p.returncode, out.decode("utf-8", "replace"), err.decode("utf-8", "replace")


def table_lines(text):
    return [ANSI.sub("", line) for line in text.split("\n")]


def n_configs():
    return len(list(CONFIGS.glob("*.toml")))


@pytest.mark.slow
@pytest.mark.parametrize("cols,rows", [(80, 24), (120, 40)])
def test_run_configs_one_line_per_design_that_fits(cols, rows):
    code, out, err = run_tty("run", CONFIGS, cols=cols, rows=rows)
    assert code == 0, err  # the README's first command: every shipped design passes its checks
    lines = table_lines(out)
    assert max(len(line) for line in lines) <= cols
    # every design is one line: the rows under the rules of the three tables
    body = []
    for k, line in enumerate(lines):
        if line.startswith("─"):
            j = k + 1
            while j < len(lines) and lines[j].strip() and not lines[j].startswith("gearcalc "):
                body.append(lines[j])
                j += 1
    assert len(body) == n_configs()
    names = [re.split(r"\s{2,}", line.strip())[0] for line in body]
    assert len(set(names)) == len(names), names  # each design told apart by its (shortened) name
    # no number is folded or cut: every right-aligned cell that looks numeric parses as a number
    for line in body:
        for cell in re.split(r"\s{2,}", line.strip())[1:]:
            if cell and cell[0].isdigit():
                assert NUMBER.match(cell) or cell in ("n/a",), (cell, line)
    head = "\n".join(lines)
    for unit in ("[MPa]", "[N]", "[kg/(kN·m)]"):
        assert unit in head, unit  # units in the headers (not eaten as markup)


def test_two_point_sweep_shows_two_rows_at_120_columns():
    code, out, err = run_tty("sweep", CONFIGS / "pins_paper_cyc_u10_fixed.toml", "--vary", "friction.sliding=0.1,0.2",
                             cols=120, rows=40)
    assert code == 0, err
    lines = table_lines(out)
    rule = next(k for k, line in enumerate(lines) if line.startswith("─"))
    rows = [line for line in lines[rule + 1:] if line.strip()]
    assert [r.split()[0] for r in rows] == ["0.1", "0.2"]
    assert "efficiency" in out and max(map(len, lines)) <= 120


def test_narrow_terminal_leaves_columns_out_and_says_so_on_stderr():
    files = sorted(CONFIGS.glob("zstk_merko_[AB]_*.toml"))
    code, out, err = run_tty("zstk", *files, cols=50, rows=24)
    assert code == 0
    assert max(len(line) for line in table_lines(out)) <= 50
    assert "not shown at this width" in err and "--fields" in err


def test_progress_bar_on_stderr_only():
    # GEARCALC_PROGRESS_DELAY=0: the bar appears at once (1 s by default), so a short run shows it
    files = sorted(CONFIGS.glob("rows_*.toml"))
    code, out, err = run_tty("run", *files, "--format", "csv", stdout_tty=False, stderr_tty=True,
                             env={"GEARCALC_PROGRESS_DELAY": "0"})
    assert code == 0
    assert "computing" in err and "designs" in err  # the bar was drawn on the terminal of stderr
    assert "\x1b" not in out and "computing" not in out
    assert out.splitlines()[0].startswith("name,")  # stdout starts with the CSV header, no blank line


def test_no_progress_bar_for_a_quick_run():
    code, out, err = run_tty("rows", CONFIGS / "rows_fig3_n3_nw3_B2.4.toml", "--format", "csv",
                             stdout_tty=False, stderr_tty=True)
    assert code == 0 and "computing" not in err  # done well within the default 1 s delay


def test_one_design_is_a_vertical_table_with_units():
    code, out, err = run_tty("zstk", CONFIGS / "zstk_merko_example.toml", cols=80)
    lines = table_lines(out)
    assert max(map(len, lines)) <= 80
    row = next(line for line in lines if line.startswith("sigma_max_MPa "))
    assert row.split()[1:] == ["748.936", "MPa"]  # field, value, unit (the worked example's sigma_max)


def test_failing_paper_case_table_and_exit_1():
    code, out, err = run_tty("rows", PAPER / "rows_bridges_n3_B3_i4.toml", cols=80)
    assert code == 1
    assert "H_max" in err and "rows.relative_width from" in err
