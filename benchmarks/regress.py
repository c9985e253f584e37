"""Sweep speed against a stored commit: fails (exit 1) when a fixed sweep got slower than a threshold.

Usage:  python benchmarks/regress.py [--against COMMIT] [--threshold 1.3] [--runs N] [--quick] [--keep]

A few fixed sweeps (rows, one float axis; zstk at a fixed load direction, one float axis; pins at the ideal level
over a friction axis, over a torque x friction grid, and over geometry axes; rows and zstk to Parquet, which
needs pyarrow) are run end to end, as a user runs them (``python -m gearcalc sweep CONFIG --vary ... -o FILE.csv``
or ``FILE.parquet``, in a subprocess), by this working tree (A) and
by a git worktree of ``--against`` (B, made in a temporary folder and removed at the end), in turns: A B A B ...
Each run's CPU time (user + system of the process and its children, from ``os.wait4``) is taken, and the ratio
A/B pair by pair: on a shared machine the CPU time is the steadier figure, and pairing keeps the ratio meaningful
while the machine's speed drifts.  The verdict of a case is the median of its pairs' CPU ratios; wall times are
printed beside it.  Exit 1 when any case's median ratio exceeds ``--threshold``, 2 on a usage or git error, else 0.

``--quick``: smaller grids and two pairs (about a minute); the default is three pairs of the full grids (a few
minutes).  A benchmark, not a unit test: run it by hand or in a nightly job, on a quiet machine if possible.

The default baseline (:data:`BASELINE`) is the commit of issue 36's speed fixes (zstk sweeps linear in the grid,
the pins consistent model once per distinct point, the API's lists on demand); pass a release tag or another
commit with ``--against``.
"""
from __future__ import annotations

import argparse
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent

BASELINE = "4ab824a370f5"
"""The commit compared against by default (issue 36 item 8: the speed fixes of 2026-12-07)."""

PARQUET_SINCE = "a7aa946"
"""A commit with ``-o FILE.parquet`` (before the Parquet speed-ups of 2026-12-07): the Parquet cases' baseline."""

CASES = {  # name: (config, --vary specs (full), --vary specs (quick)[, format: csv when not given])
    "rows": ("rows_fig3_n3_nw3_B2.4.toml", ["rows.relative_width=0.5:3.0:2.5e-06"],
             ["rows.relative_width=0.5:3.0:1.25e-05"]),
    "rows-parquet": ("rows_fig3_n3_nw3_B2.4.toml", ["rows.relative_width=0.5:3.0:2.5e-06"],
                     ["rows.relative_width=0.5:3.0:1.25e-05"], "parquet"),  # -o FILE.parquet (pyarrow)
    "zstk-parquet": ("zstk_merko_example.toml", ["load.radial_N=1000.0:20000.0:0.0475"],
                     ["load.radial_N=1000.0:20000.0:0.125"], "parquet"),
    "zstk": ("zstk_merko_example.toml", ["load.radial_N=1000.0:20000.0:0.0475"],  # several chunks: a cost
             ["load.radial_N=1000.0:20000.0:0.125"]),                             # growing with the grid shows
    "pins-friction": ("pins_paper_cyc_u10_fixed.toml", ["friction.sliding=0.01:0.3:2.9e-05"],
                      ["friction.sliding=0.01:0.3:0.000145"]),
    "pins-torque": ("pins_paper_cyc_u10_fixed.toml", ["load.torque_Nm=10:20000:2", "friction.sliding=0.05,0.1"],
                    ["load.torque_Nm=10:20000:10", "friction.sliding=0.05,0.1"]),
    "pins-geometry": ("pins_paper_cyc_u10_fixed.toml", ["gearing.eccentricity_mm=3.0:4.5:0.00075"],
                      ["gearing.eccentricity_mm=3.0:4.5:0.00375"]),
    # geometries whose final grids mostly miss --tol for the friction-consistent mean (the refinement of many
    # gears at once), both modes, rotating pins
    "pins-geometry-refine": ("pins_paper_cyc_u10_rotating.toml",
                             ["gearing.eccentricity_mm=1.0:2.0:0.0002", "load.mode=multiplier,reducer"],
                             ["gearing.eccentricity_mm=1.0:2.0:0.001", "load.mode=multiplier,reducer"]),
}


def run(tree: Path, config: str, vary: list[str], out: Path, fmt: str = "csv") -> tuple[float, float, int]:
    """(CPU seconds, wall seconds, exit status) of one sweep by the gearcalc of ``tree``."""
    import time

    cmd = [sys.executable, "-m", "gearcalc", "sweep", str(tree / "configs" / config), "--format", fmt, "-o", str(out)]
    for v in vary:
        cmd += ["--vary", v]
    env = dict(os.environ, PYTHONPATH=str(tree), OPENBLAS_NUM_THREADS="1")
    t0 = time.perf_counter()
    p = subprocess.Popen(cmd, cwd=tree, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    _, status, usage = os.wait4(p.pid, 0)  # this child's usage (its worker processes included)
    wall = time.perf_counter() - t0
    return usage.ru_utime + usage.ru_stime, wall, os.waitstatus_to_exitcode(status)


def _points(path: Path, fmt: str) -> int:
    """The rows of a sweep's output (CSV: its lines less the header; Parquet: the footer's count)."""
    if fmt == "parquet":
        import pyarrow.parquet as pq

        return pq.ParquetFile(path).metadata.num_rows
    with open(path, "rb") as fh:
        return sum(1 for _ in fh) - 1


def git(*args: str) -> str:
    return subprocess.run(["git", "-C", str(ROOT), *args], check=True, capture_output=True, text=True).stdout.strip()


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--against", default=BASELINE, help=f"the baseline commit or tag (default {BASELINE})")
    ap.add_argument("--threshold", type=float, default=1.3, help="largest median CPU ratio A/B allowed (1.3)")
    ap.add_argument("--runs", type=int, default=None, help="pairs of runs per case (3; --quick 2)")
    ap.add_argument("--quick", action="store_true", help="smaller grids, two pairs")
    ap.add_argument("--cases", default=",".join(CASES), help="comma-separated, of: " + ", ".join(CASES))
    ap.add_argument("--keep", action="store_true", help="keep the baseline's worktree (its path is printed)")
    args = ap.parse_args()
    runs = args.runs or (2 if args.quick else 3)
    names = [c for c in args.cases.split(",") if c]
    unknown = [c for c in names if c not in CASES]
    if unknown or runs < 1:
        print(f"regress.py: unknown case {unknown[0]!r}" if unknown else "regress.py: --runs must be >= 1",
              file=sys.stderr)
        return 2
    try:
        commit = git("rev-parse", "--verify", "--quiet", args.against + "^{commit}")
    except subprocess.CalledProcessError:
        print(f"regress.py: {args.against!r} is not a commit of {ROOT} (give --against COMMIT)", file=sys.stderr)
        return 2
    work = Path(tempfile.mkdtemp(prefix="gearcalc-regress-"))
    base = work / "baseline"
    try:
        git("worktree", "add", "--detach", str(base), commit)
        load = " ".join(f"{v:.1f}" for v in os.getloadavg())
        changed = " + changes" if git("status", "--porcelain", "--untracked-files=no") else ""
        print(f"# A: {ROOT} ({git('rev-parse', '--short', 'HEAD')}{changed}), B: {args.against} ({commit[:10]}); "
              f"{runs} pairs a case, load average {load}")
        print("case,points,A_cpu_s,B_cpu_s,cpu_ratio_median,A_wall_s,B_wall_s,A_points_per_cpu_s,verdict")
        failed = []
        for name in names:
            config, full, quick, *rest = CASES[name]
            fmt = rest[0] if rest else "csv"
            vary = quick if args.quick else full
            a_cpu, b_cpu, a_wall, b_wall, ratios = [], [], [], [], []
            points = 0
            for _ in range(runs):
                ca, wa, ra = run(ROOT, config, vary, work / f"a.{fmt}", fmt)
                cb, wb, rb = run(base, config, vary, work / f"b.{fmt}", fmt)
                if rb == 2 and ra == 0 and fmt != "csv":  # a baseline from before that output format
                    print(f"{name}: skipped, {args.against} has no --format {fmt} (pass --against {PARQUET_SINCE} "
                          "or later)", file=sys.stderr)
                    break
                if ra != 0 or rb != 0:
                    print(f"{name}: exit {ra} (A) / {rb} (B)", file=sys.stderr)
                    failed.append(name)
                    break
                a_cpu.append(ca), b_cpu.append(cb), a_wall.append(wa), b_wall.append(wb), ratios.append(ca / cb)
                points = _points(work / f"a.{fmt}", fmt)
            if not ratios:
                continue
            r = statistics.median(ratios)
            verdict = "ok" if r <= args.threshold else f"SLOWER than {args.threshold}x"
            if r > args.threshold:
                failed.append(name)
            ca = statistics.median(a_cpu)
            print(f"{name},{points},{ca:.2f},{statistics.median(b_cpu):.2f},{r:.2f},{statistics.median(a_wall):.2f},"
                  f"{statistics.median(b_wall):.2f},{points / ca:.0f},{verdict}", flush=True)
        if failed:
            print(f"# FAILED: {', '.join(dict.fromkeys(failed))}")
            return 1
        print("# every case within the threshold")
        return 0
    finally:
        if args.keep:
            print(f"# baseline worktree kept: {base}")
        else:
            subprocess.run(["git", "-C", str(ROOT), "worktree", "remove", "--force", str(base)], capture_output=True)
            shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    sys.exit(main())
