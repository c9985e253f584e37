"""gearcalc on a Dask cluster (``--scheduler``, gearcalc/distributed.py), against a real scheduler with two
worker processes on 127.0.0.1 (started once for this file) and against ``--scheduler local:2``.

The expected output is always gearcalc's own in-process output for the same command: byte for byte (the CSV
or JSON file), except the pins field ``model_time_ms``, a measured time that differs between any two runs.
Marked ``dask``: ``pytest -m "not dask"`` deselects these tests (they need the ``dask`` extra, part of ``test``).
"""
from __future__ import annotations

import csv
import io
import json
import os
import pty
import select
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from conftest import CONFIGS, PAPER, cli

distributed = pytest.importorskip("distributed", reason="the dask extra: pip install -e '.[test]'")

pytestmark = [pytest.mark.dask, pytest.mark.slow, pytest.mark.xdist_group("dask")]  # one cluster, started once

ENVELOPE = CONFIGS / "zstk_merko_A_envelope.toml"  # point by point, ~0.1 s a point: a sweep that lasts
START_TIMEOUT = 60


# ------------------------------------------------------------------------------------------- the cluster
def _env(work: Path) -> dict:
    """Environment of every process started here: Dask's scratch space inside ``work``, no inherited
    scheduler address, one BLAS thread."""
    env = dict(os.environ, DASK_TEMPORARY_DIRECTORY=str(work), OPENBLAS_NUM_THREADS="1")
    env.pop("DASK_SCHEDULER_ADDRESS", None)
    return env


def _start(args: list[str], work: Path, log: str) -> subprocess.Popen:
    """A Dask process in its own session (killed with its children), its log in ``work``."""
    with open(work / log, "wb") as fh:
        return subprocess.Popen([sys.executable, "-m", *args], stdout=fh, stderr=subprocess.STDOUT, cwd=work,
                                env=_env(work), start_new_session=True)


LOOPBACK = ["--host", "127.0.0.1", "--dashboard-address", "127.0.0.1:0"]
"""Every Dask process of the tests listens on 127.0.0.1 only: ``--host`` for its comm port (a worker's default is
every interface, IPv4 and IPv6), ``--dashboard-address`` for its HTTP server (every interface by default, even
with ``--no-dashboard``: it serves the health and metrics pages)."""


def _scheduler(scheduler_file: Path, work: Path, log: str = "scheduler.log") -> subprocess.Popen:
    """`dask scheduler` on a free port of 127.0.0.1, its address in ``scheduler_file`` once it is up."""
    proc = _start(["distributed.cli.dask_scheduler", *LOOPBACK, "--port", "0", "--no-dashboard",
                   "--scheduler-file", str(scheduler_file)], work, log)
    end = time.monotonic() + START_TIMEOUT
    try:
        while not scheduler_file.exists() or not scheduler_file.read_text().strip().endswith("}"):
            assert time.monotonic() < end and proc.poll() is None, (work / log).read_text()
            time.sleep(0.05)
    except BaseException:
        _stop(proc)
        raise
    return proc


def _worker(scheduler_file: Path, work: Path, name: str) -> subprocess.Popen:
    return _start(["distributed.cli.dask_worker", "--scheduler-file", str(scheduler_file), *LOOPBACK,
                   "--nthreads", "1", "--nworkers", "1", "--no-dashboard", "--local-directory", str(work),
                   "--name", name, "--death-timeout", "60"], work, f"{name}.log")


def _stop(proc: subprocess.Popen, sig=signal.SIGTERM) -> None:
    try:
        os.killpg(proc.pid, sig)
    except ProcessLookupError:
        pass
    try:
        proc.wait(timeout=10)
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        proc.wait(timeout=10)


class Cluster:
    def __init__(self, address, scheduler_file, client, work, procs):
        self.address, self.scheduler_file, self.client, self.work, self.procs = (address, scheduler_file, client,
                                                                                 work, procs)


@pytest.fixture(scope="session")
def cluster(tmp_path_factory):
    """`dask scheduler` and two `dask worker` processes (one thread each) on 127.0.0.1, free ports."""
    work = tmp_path_factory.mktemp("dask-cluster")
    file = work / "scheduler.json"
    procs = []
    client = None
    try:
        procs.append(_scheduler(file, work))
        procs += [_worker(file, work, "w1"), _worker(file, work, "w2")]
        client = distributed.Client(scheduler_file=str(file), timeout=START_TIMEOUT, set_as_default=False)
        client.wait_for_workers(2, timeout=START_TIMEOUT)
        yield Cluster(json.loads(file.read_text())["address"], file, client, work, procs)
    finally:
        if client is not None:
            client.close(timeout=10)
        for p in reversed(procs):
            _stop(p)


def _workers(cluster) -> dict[str, str]:
    """{name: address} of the cluster's workers."""
    return {w["name"]: a for a, w in cluster.client.scheduler_info(n_workers=-1)["workers"].items()}


# ------------------------------------------------------------------------------------------- helpers
def _both(tmp_path, args, scheduler, suffix="csv"):
    """(in-process run, cluster run) of one command, each writing -o into tmp_path: (exit, stderr, bytes)."""
    out = []
    for tag, extra in (("one", []), ("dask", ["--scheduler", scheduler])):
        path = tmp_path / f"{tag}.{suffix}"
        r = cli(*args, "-o", path, *extra)
        out.append((r.code, r.err, path.read_bytes() if path.exists() else None))
    return out


def _without_timings(data: bytes, fmt: str):
    """The output without ``model_time_ms`` (pins: a measured time): CSV rows as text cells, JSON as data."""
    if fmt == "json":
        def strip(x):
            if isinstance(x, dict):
                return {k: strip(v) for k, v in x.items() if k != "model_time_ms"}
            return [strip(v) for v in x] if isinstance(x, list) else x
        return strip(json.loads(data))
    rows = list(csv.reader(io.StringIO(data.decode())))
    keep = [j for j, name in enumerate(rows[0]) if name != "model_time_ms"]
    return [[r[j] for j in keep] for r in rows]


SWEEPS = {  # kind: (design, axes, format); several chunks each (the chunk is total / (4 x threads))
    "rows": (CONFIGS / "rows_mass_fig5.toml", ["rows.count=1,2,3,4", "gear.ratio=2.2:12:0.5"], "csv"),
    "zstk": (CONFIGS / "zstk_merko_example.toml", ["load.radial_N=1000:20000:500", "geometry.roller_gap_mm=4.0,6.0"],
             "csv"),
    "pins": (CONFIGS / "pins_paper_cyc_u10_fixed.toml", ["friction.sliding=0.01:0.3:0.01"], "json"),
}


def _sweep_args(kind):
    design, axes, fmt = SWEEPS[kind]
    return ["sweep", design, *[a for v in axes for a in ("--vary", v)], "--format", fmt], fmt


# ------------------------------------------------------------------------------------------- identical output
@pytest.mark.parametrize("kind", sorted(SWEEPS))
def test_sweep_on_scheduler_is_identical(tmp_path, cluster, kind):
    args, fmt = _sweep_args(kind)
    (c1, e1, one), (c2, e2, two) = _both(tmp_path, args, cluster.address, fmt)
    assert c1 == c2 and e1 == e2 and one is not None, e2
    if kind == "pins":
        assert _without_timings(one, fmt) == _without_timings(two, fmt)
    else:
        assert one == two  # byte for byte, hence in grid order


def _batch(tmp_path) -> list:
    """Every kind (the cheap pins levels), a design that fails a check (exit 1), one the schema refuses (exit 2,
    in the client) and one that raises a DesignError when computed (exit 2, on a worker)."""
    bad = tmp_path / "bad_key.toml"
    bad.write_text((CONFIGS / "rows_fig3_n3_nw3_B2.4.toml").read_text().replace("[rows]", "[rows]\ncont = 3"))
    span = tmp_path / "span.toml"
    span.write_text((CONFIGS / "rows_bridges_n4_B4_i6.toml").read_text().replace('"axes_only"', "1.0e4"))
    return (sorted(CONFIGS.glob("rows_fig3_*.toml")) + sorted(CONFIGS.glob("zstk_*.toml"))
            + sorted(CONFIGS.glob("pins_paper_cyc_*.toml")) + sorted(CONFIGS.glob("pins_paper_formula_*.toml"))
            + [PAPER / "rows_bridges_n3_B3_i4.toml", bad, span])


def test_run_on_scheduler_is_identical(tmp_path, cluster):
    files = _batch(tmp_path)
    (c1, e1, one), (c2, e2, two) = _both(tmp_path, ["run", *files, "--format", "json"], cluster.address, "json")
    assert c1 == c2 == 2 and e1 == e2  # the messages, in the same order
    assert "bridges.first_span" in e2 and "cont" in e2
    assert _without_timings(one, "json") == _without_timings(two, "json")
    rows = sorted(CONFIGS.glob("rows_*.toml"))
    (c1, e1, one), (c2, e2, two) = _both(tmp_path, ["run", *rows, "--format", "csv"], cluster.address)
    assert c1 == c2 == 0 and e1 == e2 and one == two


def test_environment_variable_names_the_scheduler(tmp_path, cluster):
    from typer.testing import CliRunner

    from gearcalc.cli import app

    args, _ = _sweep_args("rows")
    one = cli(*args)
    r = CliRunner().invoke(app, [str(a) for a in args], env={"DASK_SCHEDULER_ADDRESS": cluster.address})
    assert r.exit_code == 0 and r.stdout == one.out
    r = CliRunner().invoke(app, [str(a) for a in args] + ["--jobs", "2"],
                           env={"DASK_SCHEDULER_ADDRESS": cluster.address})
    assert r.exit_code == 2 and "choose one" in r.stderr


def test_python_api_takes_a_scheduler(cluster):
    import gearcalc

    design, axes = CONFIGS / "rows_mass_fig5.toml", {"rows.count": [1, 2, 3, 4], "gear.ratio": [2.5, 3.5, 6.0]}
    from gearcalc.grid import join_parts

    one = join_parts(list(gearcalc.sweep(design, axes, chunk=5))).data
    for scheduler in (cluster.address, cluster.client):  # an address, or a Client of the caller's (kept open)
        parts = list(gearcalc.sweep(design, axes, chunk=5, scheduler=scheduler))
        # an explicit chunk is kept as given on a cluster too (--resume needs the same chunk boundaries on every
        # run, issue 36): 12 points in chunks of 5
        assert len(parts) == 3 and join_parts(parts).data == one
    assert cluster.client.status == "running"
    files = sorted(CONFIGS.glob("rows_fig3_*.toml"))
    a, b = gearcalc.compute_files(files), gearcalc.compute_files(files, scheduler=cluster.address)
    assert [r.summary for r in a.results] == [r.summary for r in b.results] and a.messages == b.messages


def test_chunks_come_back_in_order_while_they_finish_out_of_order(cluster):
    # chunk k sleeps less the later it comes: the two workers finish them out of order; progress is called
    # as they finish (its sizes, k + 1, tell the order), the results come in submission order
    from gearcalc.distributed import Cluster

    done = []

    def work(data, k):
        time.sleep(data[k])
        return k

    delays = [0.4, 0.25, 0.15, 0.1, 0.05, 0.0, 0.0, 0.0]
    with Cluster(cluster.client) as c:
        got = list(c.ordered(work, [(k,) for k in range(len(delays))], delays, sizes=range(1, 9),
                             progress=done.append, window=4))
    assert got == list(range(len(delays)))
    deadline = time.monotonic() + 5
    while len(done) < len(delays) and time.monotonic() < deadline:  # callbacks run in Dask's thread
        time.sleep(0.01)
    assert sorted(done) == list(range(1, 9)) and done != sorted(done)


class _FakeFuture:
    def __init__(self, client, value):
        self.client, self.value, self.status = client, value, "finished"

    def add_done_callback(self, fn):
        fn(self)

    def result(self):
        return self.value

    def release(self):
        self.client.live -= 1

    def done(self):
        return True


class _FakeClient:
    """Computes at submit and counts the futures alive: the window's bound without a cluster's timing."""

    class scheduler:
        address = "fake://"

    def __init__(self):
        self.live = self.most = 0

    def nthreads(self):
        return {"w": 1}

    def submit(self, fn, *args, key, pure):
        args = [a.value if isinstance(a, _FakeFuture) else a for a in args]
        self.live += 1
        self.most = max(self.most, self.live)
        return _FakeFuture(self, fn(*args))

    def cancel(self, futures):
        self.live -= len(futures)


@pytest.mark.parametrize("window", [1, 3, 8])
def test_window_bounds_the_chunks_in_flight(window):
    from gearcalc.distributed import Cluster

    client = _FakeClient()
    with Cluster(client) as c:
        it = c.ordered(lambda data, k: data + k, [(k,) for k in range(50)], 1000, window=window)
        assert [next(it) for _ in range(10)] == list(range(1000, 1010))
        it.close()  # the rest cancelled
    assert client.most == window + 1  # the chunks and the shared data
    assert client.live == 0


def test_workers_with_another_gearcalc_are_refused(cluster, monkeypatch):
    import gearcalc

    monkeypatch.setattr(gearcalc, "__version__", "0.0.0-client")  # the workers run the real one
    args, _ = _sweep_args("rows")
    r = cli(*args, "--scheduler", cluster.address)
    assert r.code == 2 and "runs gearcalc" in r.err and "0.0.0-client" in r.err and "same version" in r.err, r.err
    r = cli("run", CONFIGS / "rows_fig3_n3_nw3_B2.4.toml", "--scheduler", cluster.address)
    assert r.code == 2 and "same version" in r.err and not r.out


def test_design_error_at_a_point_is_that_points_message(tmp_path, cluster):
    # each value is valid alone, e = 20 with R_B = 80 is not; float axes, so the chunk finds it on a worker
    args = ["sweep", CONFIGS / "zstk_merko_example.toml", "--vary", "geometry.eccentricity_mm=6.0,10.0,20.0,24.0",
            "--vary", "geometry.inner_raceway_radius_mm=50.0,70.0,80.0"]
    (c1, e1, one), (c2, e2, two) = _both(tmp_path, args, cluster.address)
    # since the margins (issue 36) such a point is a row with its reason in the ``error`` column and the sweep
    # goes on (exit 2): the cluster writes the in-process output byte for byte, with the same messages
    assert c1 == c2 == 2 and e1 == e2 and one == two and one is not None
    assert "geometry.eccentricity_mm" in e2 and "'geometry.inner_raceway_radius_mm': 80.0" in e2
    assert "Traceback" not in e2
    import csv
    import io

    rows = list(csv.DictReader(io.StringIO(one.decode())))
    bad = [(r["geometry.eccentricity_mm"], r["geometry.inner_raceway_radius_mm"]) for r in rows if r["error"]]
    assert len(rows) == 12 and bad == [("20.0", "80.0"), ("24.0", "80.0")]  # R_H - R_B - e <= 0 there only


# ------------------------------------------------------------------------------------------- failures
def test_worker_killed_mid_sweep_gives_the_full_identical_output(tmp_path, cluster):
    """A third worker takes chunks and is killed (SIGKILL, with its nanny) while it computes one: Dask
    computes its chunks elsewhere and the output is the in-process output."""
    args = ["sweep", ENVELOPE, "--vary", "load.radial_N=1000:30000:1000", "--format", "csv"]
    w3 = _worker(cluster.scheduler_file, cluster.work, "w3")  # starts while the reference is computed
    try:
        ref = tmp_path / "one.csv"
        assert cli(*args, "-o", ref).code == 0
        cluster.client.wait_for_workers(3, timeout=START_TIMEOUT)
        victim = _workers(cluster)["w3"]
        out = tmp_path / "dask.csv"
        p = subprocess.Popen([sys.executable, "-m", "gearcalc", *map(str, args), "-o", str(out), "--scheduler",
                              cluster.address], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                             env=_env(tmp_path))
        try:
            deadline = time.monotonic() + START_TIMEOUT
            while not any("gearcalc-chunk" in str(k) for k in cluster.client.processing([victim]).get(victim, ())):
                assert p.poll() is None and time.monotonic() < deadline, p.communicate()
                time.sleep(0.02)
            _stop(w3, signal.SIGKILL)
            assert p.poll() is None  # killed mid-sweep
            _, err = p.communicate(timeout=120)
        finally:
            if p.poll() is None:
                p.kill()
        assert p.returncode == 0, err
        assert out.read_bytes() == ref.read_bytes()
    finally:
        _stop(w3, signal.SIGKILL)


def _pty_run(args, env, until: str, timeout: float = START_TIMEOUT):
    """Start gearcalc with stderr on a terminal (its notices and progress bar), in its own session; return
    (process, terminal fd, text so far) once ``until`` appeared on the terminal."""
    master, slave = pty.openpty()
    p = subprocess.Popen([sys.executable, "-m", "gearcalc", *map(str, args)], stdout=subprocess.DEVNULL,
                         stderr=slave, env=env, start_new_session=True)
    os.close(slave)
    text, deadline = "", time.monotonic() + timeout
    while until not in text:
        assert p.poll() is None and time.monotonic() < deadline, text
        if select.select([master], [], [], 0.1)[0]:
            text += os.read(master, 65536).decode(errors="replace")
    return p, master, text


def _finish(p, master, text, timeout=60):
    """Wait for the process; the terminal's whole text."""
    deadline = time.monotonic() + timeout
    while p.poll() is None or select.select([master], [], [], 0)[0]:
        if time.monotonic() > deadline:
            os.killpg(p.pid, signal.SIGKILL)
            pytest.fail("gearcalc did not stop after SIGINT:\n" + text)
        if select.select([master], [], [], 0.1)[0]:
            try:
                chunk = os.read(master, 65536)
            except OSError:  # the terminal closed with the process
                break
            if not chunk:
                break
            text += chunk.decode(errors="replace")
    p.wait(timeout=10)
    os.close(master)
    return text


def test_sigint_cancels_the_futures_and_exits_130(tmp_path, cluster):
    args = ["sweep", ENVELOPE, "--vary", "load.radial_N=1000:400000:1000", "-o", tmp_path / "out.csv",
            "--scheduler", cluster.address]
    p, master, text = _pty_run(args, _env(tmp_path), "computing on the Dask cluster at " + cluster.address)
    deadline = time.monotonic() + START_TIMEOUT
    while not any("gearcalc-chunk" in str(k) for ks in cluster.client.processing().values() for k in ks):
        assert time.monotonic() < deadline
        time.sleep(0.02)
    os.kill(p.pid, signal.SIGINT)
    text = _finish(p, master, text)
    assert p.returncode == 130, text
    assert text.count("gearcalc: interrupted") == 1 and "Traceback" not in text, text
    assert not (tmp_path / "out.csv").exists()
    left = None
    deadline = time.monotonic() + 20   # a chunk that runs finishes (Dask does not stop a running task)
    while left != 0 and time.monotonic() < deadline:
        left = cluster.client.run_on_scheduler(lambda dask_scheduler: sum(
            "gearcalc" in str(k) for k in dask_scheduler.tasks))
        time.sleep(0.1)
    assert left == 0, "the scheduler still holds gearcalc's tasks"


def test_scheduler_killed_mid_run_is_a_message(tmp_path):
    """A scheduler of its own (one worker) SIGKILLed while a sweep's chunk computes: one line saying the
    connection was lost (exit 2, as an unreachable scheduler), no traceback, and -o as it was before."""
    file = tmp_path / "scheduler.json"
    sched = _scheduler(file, tmp_path, "victim.log")
    procs = [sched, _worker(file, tmp_path, "only")]
    try:
        address = json.loads(file.read_text())["address"]
        out = tmp_path / "out" / "study.csv"
        out.parent.mkdir()
        out.write_text("an earlier study\n")
        args = ["sweep", ENVELOPE, "--vary", "load.radial_N=1000:400000:1000", "-o", out, "--scheduler", address]
        p = subprocess.Popen([sys.executable, "-m", "gearcalc", *map(str, args)], stdout=subprocess.PIPE,
                             stderr=subprocess.PIPE, text=True, env=_env(tmp_path))
        try:
            with distributed.Client(address, timeout=START_TIMEOUT, set_as_default=False) as watch:
                deadline = time.monotonic() + START_TIMEOUT
                while not any("gearcalc-chunk" in str(k) for ks in watch.processing().values() for k in ks):
                    assert p.poll() is None and time.monotonic() < deadline, p.communicate()
                    time.sleep(0.02)
            _stop(sched, signal.SIGKILL)
            assert p.poll() is None  # killed mid-run
            _, err = p.communicate(timeout=60)
        finally:
            if p.poll() is None:
                p.kill()
        assert p.returncode == 2, err
        assert err == (f"gearcalc: --scheduler {address}: lost the connection to the Dask scheduler during the "
                       "run; start it and its workers again and rerun\n"), err
        assert out.read_text() == "an earlier study\n" and os.listdir(out.parent) == ["study.csv"]
    finally:
        for proc in reversed(procs):
            _stop(proc, signal.SIGKILL)


# ------------------------------------------------------------------------------------------- listening sockets
def _listening(pids) -> list[tuple[str, int, str]]:
    """(address, port, command) of every listening inet socket of these processes and their children."""
    psutil = pytest.importorskip("psutil")  # installed with distributed
    found = []
    for pid in pids:
        try:
            top = psutil.Process(pid)
            procs = [top, *top.children(recursive=True)]
        except psutil.NoSuchProcess:
            continue
        for proc in procs:
            try:
                conns = proc.net_connections(kind="inet")
                what = " ".join(proc.cmdline()[1:3])
            except psutil.Error:  # ended meanwhile
                continue
            found += [(c.laddr.ip, c.laddr.port, f"{proc.pid} {what}") for c in conns
                      if c.status == psutil.CONN_LISTEN]
    return found


def _loopback(address: str) -> bool:
    import ipaddress

    return ipaddress.ip_address(address).is_loopback


def test_fixture_cluster_listens_on_loopback_only(cluster):
    # the scheduler (its comm port and HTTP server), each worker's nanny and the worker it starts
    found = _listening([proc.pid for proc in cluster.procs])
    assert len({who for _, _, who in found}) >= 5, found
    assert [s for s in found if not _loopback(s[0])] == [], found


def test_local_cluster_listens_on_loopback_only(tmp_path):
    # --scheduler local:2 listens only on 127.0.0.1 (scheduler, nannies, workers, dashboard) for the whole run
    args = ["sweep", ENVELOPE, "--vary", "load.radial_N=1000:400000:1000", "-o", tmp_path / "out.csv",
            "--scheduler", "local:2"]
    p, master, text = _pty_run(args, _env(tmp_path), "computing on the Dask cluster at ")
    try:
        found: set = set()
        deadline = time.monotonic() + START_TIMEOUT
        while len({who for _, _, who in found}) < 3:  # gearcalc (scheduler, nannies, dashboard), two workers
            assert p.poll() is None and time.monotonic() < deadline, (found, text)
            found |= set(_listening([p.pid]))
            time.sleep(0.1)
    finally:
        os.killpg(p.pid, signal.SIGINT)
        text = _finish(p, master, text)
    assert [s for s in found if not _loopback(s[0])] == [], sorted(found)
    assert "dashboard http://127.0.0.1:" in text, text


# ------------------------------------------------------------------------------------------- local:2
def test_local_cluster_is_identical(tmp_path):
    import dask

    with dask.config.set({"temporary-directory": str(tmp_path)}):
        args, fmt = _sweep_args("zstk")
        (c1, e1, one), (c2, e2, two) = _both(tmp_path, args, "local:2", fmt)
        assert c1 == c2 == 0 and e1 == e2 and one == two
        files = _batch(tmp_path)
        (c1, e1, one), (c2, e2, two) = _both(tmp_path, ["run", *files, "--format", "json"], "local:2", "json")
        assert c1 == c2 == 2 and e1 == e2
        assert _without_timings(one, "json") == _without_timings(two, "json")


def test_local_cluster_ctrl_c_to_the_process_group(tmp_path):
    # Ctrl-C on a terminal signals the whole process group, the local workers included: one "interrupted",
    # no worker traceback; the message line pointed at the dashboard
    args = ["sweep", ENVELOPE, "--vary", "load.radial_N=1000:400000:1000", "-o", tmp_path / "out.csv",
            "--scheduler", "local:2"]
    p, master, text = _pty_run(args, _env(tmp_path), "computing on the Dask cluster at ")
    time.sleep(0.3)
    os.killpg(p.pid, signal.SIGINT)
    text = _finish(p, master, text)
    assert p.returncode == 130, text
    assert "2 workers" in text and "dashboard http://" in text, text
    assert text.count("gearcalc: interrupted") == 1, text
    assert "Traceback" not in text and "KeyboardInterrupt" not in text, text
    assert not (tmp_path / "out.csv").exists()


# ------------------------------------------------------------------------------------------- without Dask
def test_dask_is_not_imported_without_scheduler(tmp_path):
    args, _ = _sweep_args("rows")
    for cmd in (args, ["run", CONFIGS / "rows_fig3_n3_nw3_B2.4.toml", "--format", "csv"]):
        p = subprocess.run([sys.executable, "-X", "importtime", "-m", "gearcalc", *map(str, cmd), "-o",
                            str(tmp_path / "out.csv")], capture_output=True, text=True, env=_env(tmp_path),
                           timeout=60)
        assert p.returncode == 0, p.stderr[-2000:]
        imported = [line.rsplit("|", 1)[-1].strip() for line in p.stderr.splitlines() if "|" in line]
        assert "gearcalc.grid" in imported or "gearcalc.engine" in imported
        assert not [m for m in imported if m.split(".")[0] in ("dask", "distributed", "gearcalc.distributed")]
        assert "gearcalc.distributed" not in imported


def test_missing_dask_names_the_extra(monkeypatch):
    monkeypatch.setitem(sys.modules, "distributed", None)  # import distributed: ImportError
    args, _ = _sweep_args("rows")
    r = cli(*args, "--scheduler", "local:2")
    assert r.code == 2 and "pip install 'gearcalc[dask]'" in r.err, r.err
    r = cli("run", CONFIGS / "rows_fig3_n3_nw3_B2.4.toml", "--scheduler", "tcp://127.0.0.1:8786")
    assert r.code == 2 and "gearcalc[dask]" in r.err and "Traceback" not in r.err


@pytest.mark.parametrize("value,says", [
    ("local:0", "local:N takes a number of worker processes from 1 to 256"),
    ("local:two", "local:N takes a number"),
    ("", "give a scheduler address"),
])
def test_bad_scheduler_value(value, says):
    args, _ = _sweep_args("rows")
    r = cli(*args, "--scheduler", value)
    assert r.code == 2 and says in r.err, r.err


def test_jobs_and_scheduler_together_are_refused():
    r = cli("run", CONFIGS / "rows_fig3_n3_nw3_B2.4.toml", "--jobs", "2", "--scheduler", "local:2")
    assert r.code == 2 and "choose one" in r.err
    r = cli("run", CONFIGS / "rows_fig3_n3_nw3_B2.4.toml", "--jobs", "2", "--scheduler", "")
    assert r.code == 2 and "give a scheduler address" in r.err and "choose one" not in r.err, r.err


def test_empty_environment_variable_is_unset():
    # an empty DASK_SCHEDULER_ADDRESS is no address (click, as POSIX tools read empty variables); an empty
    # --scheduler is refused (test_bad_scheduler_value)
    from typer.testing import CliRunner

    from gearcalc.cli import app

    args, _ = _sweep_args("rows")
    r = CliRunner().invoke(app, [str(a) for a in args], env={"DASK_SCHEDULER_ADDRESS": ""})
    assert r.exit_code == 0 and r.stdout == cli(*args).out and not r.stderr


def test_unreachable_scheduler_is_a_message(monkeypatch):
    import socket

    from gearcalc import distributed as gd

    monkeypatch.setattr(gd, "CONNECT_TIMEOUT_S", 1)
    with socket.socket() as s:  # a free port: nothing listens there
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    r = cli("run", CONFIGS / "rows_fig3_n3_nw3_B2.4.toml", "--scheduler", f"tcp://127.0.0.1:{port}")
    assert r.code == 2 and "no Dask scheduler could be reached" in r.err and "dask scheduler" in r.err, r.err
