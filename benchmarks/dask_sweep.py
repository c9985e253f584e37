"""Sweeps on Dask (``--scheduler``): throughput in process vs ``local:2`` vs a scheduler with two workers, and
the client's peak memory.

Usage:  python benchmarks/dask_sweep.py [--kind zstk] [--points 1e6] [--modes inproc,jobs2,local,cluster]
                                        [--repeats 1]

Each run is ``gearcalc sweep`` as a user types it, in a subprocess writing CSV to a file in a temporary folder;
the grid is one axis (rows: ``rows.relative_width``; zstk: ``load.radial_N``, vectorised; zstk-envelope: the same
axis of a load-direction envelope design, point by point at ~0.1 s a point; pins: ``friction.sliding``).
Reported: wall time (the minimum over the repeats), points per second, and the peak resident memory of the
gearcalc process alone (``VmHWM`` of /proc/PID/status, read every 50 ms until it exits: the workers of
``local`` are its children and are not counted), plus the CSV size.

* ``inproc``: no ``--scheduler`` (one process);
* ``jobs2``: ``--jobs 2`` (the standard library's process pool: what two processes give on this machine);
* ``local``: ``--scheduler local:2`` (the cluster's start, about 2.5 s, is in the time);
* ``cluster``: ``--scheduler tcp://127.0.0.1:PORT`` of a scheduler and two single-threaded workers that this
  script starts first (their start is not in the time), with the commands printed::

      dask scheduler --host 127.0.0.1 --port 0 --no-dashboard --scheduler-file S.json
      OPENBLAS_NUM_THREADS=1 dask worker --scheduler-file S.json --nthreads 1 --local-directory DIR   (twice)
"""
from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
CONFIGS = ROOT / "configs"
_SCRIPT = Path(sys.executable).with_name("gearcalc")
GEARCALC = [str(_SCRIPT)] if _SCRIPT.is_file() else [sys.executable, "-m", "gearcalc"]
_DASK = Path(sys.executable).with_name("dask")

GRIDS = {
    "rows": ("rows_fig3_n3_nw3_B2.4.toml", "rows.relative_width", 1.5, 3.0),
    "zstk": ("zstk_merko_example.toml", "load.radial_N", 1000.0, 20000.0),
    "pins": ("pins_paper_cyc_u10_fixed.toml", "friction.sliding", 0.01, 0.3),
    # the load-direction envelope: point by point, ~0.1 s a point (the kind of study a cluster is for)
    "zstk-envelope": ("zstk_merko_A_envelope.toml", "load.radial_N", 1000.0, 20000.0),
}


def _peak_kb(pid: int) -> int | None:
    try:
        with open(f"/proc/{pid}/status") as fh:
            for line in fh:
                if line.startswith("VmHWM:"):
                    return int(line.split()[1])
    except OSError:
        return None
    return None


def run(kind: str, points: int, scheduler: str | None, work: Path, env: dict, jobs: int = 1) -> dict:
    name, key, lo, hi = GRIDS[kind]
    step = (hi - lo) / (points - 1)
    out = work / f"{kind}_{points}.csv"
    cmd = GEARCALC + ["sweep", str(CONFIGS / name), "--vary", f"{key}={lo!r}:{hi!r}:{step!r}", "--format", "csv",
                      "-o", str(out)] + (["--scheduler", scheduler] if scheduler else []) + (["--jobs", str(jobs)]
                                                                                          if jobs > 1 else [])
    t0 = time.perf_counter()
    p = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env)
    peak = 0
    while p.poll() is None:
        peak = max(peak, _peak_kb(p.pid) or 0)
        time.sleep(0.05)
    wall = time.perf_counter() - t0
    _, err = p.communicate()
    rows = size = 0
    if out.exists():
        with open(out, "rb") as fh:
            rows = sum(1 for _ in fh) - 1
        size = out.stat().st_size
        out.unlink()
    return {"exit": p.returncode, "wall_s": wall, "points": rows, "peak_MB": peak / 1024.0, "csv_MB": size / 1e6,
            "stderr": err.strip()[-300:]}


class LocalDaskCluster:
    """``dask scheduler`` and two ``dask worker`` processes (one thread each) on 127.0.0.1, in ``work``."""

    def __init__(self, work: Path, env: dict, workers: int = 2):
        import json

        dask = [str(_DASK)] if _DASK.is_file() else None
        sched = dask + ["scheduler"] if dask else [sys.executable, "-m", "distributed.cli.dask_scheduler"]
        worker = dask + ["worker"] if dask else [sys.executable, "-m", "distributed.cli.dask_worker"]
        file = work / "scheduler.json"
        self.commands = [sched + ["--host", "127.0.0.1", "--port", "0", "--no-dashboard", "--scheduler-file",
                                  str(file)]]
        self.commands += [worker + ["--scheduler-file", str(file), "--nthreads", "1", "--no-dashboard",
                                    "--local-directory", str(work), "--name", f"w{k}"] for k in range(workers)]
        self.log = open(work / "dask.log", "wb")
        self.procs = [subprocess.Popen(self.commands[0], stdout=self.log, stderr=subprocess.STDOUT, env=env)]
        end = time.monotonic() + 60
        while not file.exists() or not file.read_text().strip().endswith("}"):
            if time.monotonic() > end:
                raise RuntimeError("the scheduler did not start (see dask.log)")
            time.sleep(0.05)
        self.address = json.loads(file.read_text())["address"]
        self.procs += [subprocess.Popen(c, stdout=self.log, stderr=subprocess.STDOUT, env=env)
                       for c in self.commands[1:]]
        import distributed

        with distributed.Client(self.address, timeout=60, set_as_default=False) as client:
            client.wait_for_workers(workers, timeout=60)

    def close(self) -> None:
        for p in reversed(self.procs):
            p.terminate()
        for p in self.procs:
            try:
                p.wait(timeout=20)
            except subprocess.TimeoutExpired:
                p.kill()
        self.log.close()


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--kind", default="zstk", choices=sorted(GRIDS))
    ap.add_argument("--points", default="1e6", help="comma-separated grid sizes")
    ap.add_argument("--modes", default="inproc,jobs2,local,cluster")
    ap.add_argument("--repeats", type=int, default=1)
    args = ap.parse_args()
    modes = args.modes.split(",")
    print(f"# python {sys.version.split()[0]}, {os.cpu_count()} cores, gearcalc: {' '.join(GEARCALC)}")
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        env = dict(os.environ, DASK_TEMPORARY_DIRECTORY=str(work))
        env.setdefault("OPENBLAS_NUM_THREADS", "1")  # as gearcalc asks for itself (console.one_blas_thread)
        env.pop("DASK_SCHEDULER_ADDRESS", None)
        cluster = None
        if "cluster" in modes:
            cluster = LocalDaskCluster(work, env)
            print("# cluster: " + " ; ".join(" ".join(Path(c[0]).name if i == 0 else c[i] for i in range(len(c)))
                                               for c in cluster.commands))
        try:
            print("kind,points,mode,exit,wall_s,points_per_s,client_peak_MB,csv_MB")
            for n in args.points.split(","):
                base = None
                for mode in modes:
                    scheduler = {"local": "local:2", "cluster": cluster and cluster.address}.get(mode)
                    best = None
                    for _ in range(args.repeats):
                        r = run(args.kind, int(float(n)), scheduler, work, env, 2 if mode == "jobs2" else 1)
                        if best is None or r["wall_s"] < best["wall_s"]:
                            best = r
                    rate = best["points"] / best["wall_s"]
                    base = rate if mode == "inproc" else base
                    ratio = f"  (x{rate / base:.2f} of inproc)" if base and mode != "inproc" else ""
                    print(f"{args.kind},{best['points']},{mode},{best['exit']},{best['wall_s']:.2f},{rate:.0f},"
                          f"{best['peak_MB']:.0f},{best['csv_MB']:.0f}{ratio}", flush=True)
                    if best["exit"] not in (0, 1):
                        print("  stderr:", best["stderr"])
        finally:
            if cluster is not None:
                cluster.close()


if __name__ == "__main__":
    main()
