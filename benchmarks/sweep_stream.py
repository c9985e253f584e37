"""Streaming sweeps: peak memory and throughput of ``gearcalc sweep`` end to end (CSV to a file).

Usage:  python benchmarks/sweep_stream.py [--points 1e6,1e7] [--kind rows] [--jobs 1[,2]] [--repeat N]

For each grid size it runs ``gearcalc sweep`` as a user would, in a subprocess writing CSV to a file in a
temporary folder, and reports the wall time, the points per second and the subprocess's peak resident
memory (``ru_maxrss`` of the child, in MB: the greatest of the child and its worker processes) and its CPU time
(user + system of the child and its worker processes; both from ``os.wait4``), in total and per point: on a
shared machine the CPU time per
point is the steadier figure. The grid is one axis (rows: ``rows.relative_width``; zstk:
``load.radial_N``; pins: ``friction.sliding``) of the requested number of points. Issue-14 targets:
peak memory <= 300 MB at 1e7 rows points, >= 5e5 rows points/s.

``--jobs 1,2`` runs both, alternated; ``--repeat N`` runs every case N times (alternated) and ends with the best
and the median of each: other work on the machine slows single runs by up to a factor of two.
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

GRIDS = {
    "rows": ("rows_fig3_n3_nw3_B2.4.toml", "rows.relative_width", 1.5, 3.0),
    "zstk": ("zstk_merko_example.toml", "load.radial_N", 1000.0, 20000.0),
    "pins": ("pins_paper_cyc_u10_fixed.toml", "friction.sliding", 0.01, 0.3),
}


def run(kind: str, points: int, jobs: int, work: Path) -> dict:
    name, key, lo, hi = GRIDS[kind]
    step = (hi - lo) / (points - 1)
    out = work / f"{kind}_{points}.csv"
    cmd = GEARCALC + ["sweep", str(CONFIGS / name), "--vary", f"{key}={lo!r}:{hi!r}:{step!r}", "--format", "csv",
                      "-o", str(out), "--jobs", str(jobs)]
    with open(work / "stderr.txt", "w+") as err:
        t0 = time.perf_counter()
        p = subprocess.Popen(cmd, stdout=err, stderr=err)
        # wait4: this child's own resource usage (its workers' included), where RUSAGE_CHILDREN would give the
        # greatest peak of every child so far (wrong for the second and later runs)
        _, status, usage = os.wait4(p.pid, 0)
        wall = time.perf_counter() - t0
        p.returncode = os.waitstatus_to_exitcode(status)
        err.seek(0)
        stderr = err.read()
    peak = usage.ru_maxrss  # the greatest peak of the child and its worker processes, KB
    cpu = usage.ru_utime + usage.ru_stime  # the child's (and its workers') CPU time
    with open(out, "rb") as fh:
        rows = sum(1 for _ in fh) - 1
    size = out.stat().st_size
    out.unlink()
    return {"kind": kind, "points": rows, "jobs": jobs, "exit": p.returncode, "wall_s": wall,
            "points_per_s": rows / wall, "cpu_s": cpu, "cpu_us_per_point": 1e6 * cpu / max(rows, 1),
            "wall_us_per_point": 1e6 * wall / max(rows, 1), "peak_MB": peak / 1024.0,
            "csv_MB": size / 1e6, "stderr": stderr.strip()[-200:]}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--points", default="1e6,1e7")
    ap.add_argument("--kind", default="rows", choices=sorted(GRIDS))
    ap.add_argument("--jobs", default="1", help="one or more (comma-separated), alternated")
    ap.add_argument("--repeat", type=int, default=1, help="runs of every case, alternated")
    args = ap.parse_args()
    load = " ".join(f"{v:.2f}" for v in os.getloadavg()) if hasattr(os, "getloadavg") else "n/a"
    print(f"# python {sys.version.split()[0]}, {os.cpu_count()} cores, load average {load}, "
          f"gearcalc: {' '.join(GEARCALC)}")
    print("kind,points,jobs,exit,wall_s,points_per_s,cpu_s,cpu_us_per_point,wall_us_per_point,peak_MB,csv_MB")
    runs: dict = {}
    with tempfile.TemporaryDirectory() as tmp:
        for n in args.points.split(","):
            for _ in range(args.repeat):
                for jobs in (int(j) for j in args.jobs.split(",")):
                    r = run(args.kind, int(float(n)), jobs, Path(tmp))
                    runs.setdefault((int(float(n)), jobs), []).append(r)
                    print(f"{r['kind']},{r['points']},{r['jobs']},{r['exit']},{r['wall_s']:.2f},"
                          f"{r['points_per_s']:.0f},{r['cpu_s']:.2f},{r['cpu_us_per_point']:.2f},"
                          f"{r['wall_us_per_point']:.2f},{r['peak_MB']:.0f},{r['csv_MB']:.0f}", flush=True)
                    if r["exit"] not in (0, 1):
                        print("  stderr:", r["stderr"])
    if args.repeat > 1:
        import statistics

        for (n, jobs), rs in runs.items():
            walls, cpus = [r["wall_s"] for r in rs], [r["cpu_us_per_point"] for r in rs]
            peak = max(r["peak_MB"] for r in rs)
            print(f"# {n} points, --jobs {jobs}, {len(rs)} runs: wall best {min(walls):.2f} s "
                  f"({n / min(walls):.0f} points/s), median {statistics.median(walls):.2f} s; CPU per point best "
                  f"{min(cpus):.2f} us, median {statistics.median(cpus):.2f} us; peak {peak:.0f} MB")


if __name__ == "__main__":
    main()
