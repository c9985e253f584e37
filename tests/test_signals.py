"""Reliability at the edges of a run (issue 7): interrupted output, progress bars, pipes."""
import os
import signal
import subprocess
import sys
import time

import pytest

from conftest import CONFIGS, cli_proc

SLOW = CONFIGS / "pins_paper_circ_u10_fixed.toml"  # the contact level: about 0.1 s per point


def _start(*args, cwd=None):
    return subprocess.Popen([sys.executable, "-m", "gearcalc", *map(str, args)], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, cwd=cwd)


@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM])
def test_interrupted_output_leaves_no_file_and_no_temporary(tmp_path, sig):
    out = tmp_path / "out.csv"
    # 79 contact-level points: many seconds of work, interrupted after 1.5 s
    p = _start("sweep", SLOW, "--vary", "friction.sliding=0.01:0.4:0.005", "-o", out)
    time.sleep(1.5)
    assert p.poll() is None, "the run ended before the signal: make it longer"
    p.send_signal(sig)
    _, err = p.communicate(timeout=60)
    assert p.returncode == 130
    assert "Traceback" not in err and "interrupted" in err
    assert os.listdir(tmp_path) == []  # neither out.csv nor .out.csv.*.tmp


def test_no_progress_bar_when_stderr_is_not_a_terminal():
    # 2520 points would get a bar on a terminal; piped, stderr stays silent
    r = cli_proc("sweep", CONFIGS / "rows_fig3_n3_nw3_B2.4.toml", "--vary", "rows.count=1,2,3",
                 "--vary", "rows.relative_width=0.5:4.695:0.005", "--format", "csv")
    assert r.code == 0 and r.err == ""
    assert len(r.out.splitlines()) == 1 + 3 * 840


def test_head_closes_the_pipe_quietly():
    # `gearcalc run configs | head -1`: exit quietly, nothing on stderr
    p = subprocess.run(f'"{sys.executable}" -m gearcalc run "{CONFIGS}" | head -1', shell=True,
                       capture_output=True, text=True, timeout=300)
    assert p.stdout.startswith("kind,name,")  # CSV when piped; several kinds: a kind column
    assert "rror" not in p.stderr and "Traceback" not in p.stderr
