"""gearcalc benchmark: start-up and per-design times on the machine it runs on.

Usage:  python benchmarks/bench.py [--out benchmarks/results.csv] [--repeat 7]

Measures
* start-up: ``python -c pass``, ``gearcalc --help`` and one design of each installed kind, end to end
  (wall time of a subprocess, median of --repeat runs);
* per-design compute in process (after warm-up) for every shipped config, per calculator and model
  level, at --tol 1e-6 (median of --repeat runs).
It prints a table and writes it as CSV.
"""
from __future__ import annotations

import argparse
import csv
import os
import platform
import statistics
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
CONFIGS = ROOT / "configs"


def wall(cmd: list[str], repeat: int) -> float:
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=False)
        times.append(time.perf_counter() - t)
    return statistics.median(times)


def in_process(design, calc, options, repeat: int) -> float:
    calc.compute(design, options)  # warm-up
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        calc.compute(design, options)
        times.append(time.perf_counter() - t)
    return statistics.median(times)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=str(ROOT / "benchmarks" / "results.csv"))
    ap.add_argument("--repeat", type=int, default=7)
    args = ap.parse_args()

    from gearcalc import design as dmod
    from gearcalc import registry
    from gearcalc.calculator import Options

    rows = []
    py = sys.executable
    base = wall([py, "-c", "pass"], args.repeat)
    rows.append(("startup", "python -c pass", "", base * 1e3, ""))
    t = wall([py, "-m", "gearcalc", "--help"], args.repeat)
    rows.append(("startup", "gearcalc --help", "", t * 1e3, f"{t / base:.2f}x python"))
    examples = {}
    for f in sorted(CONFIGS.glob("*.toml")):
        try:
            d = dmod.load(str(f))
        except dmod.InputError:
            continue
        examples.setdefault(d.kind, []).append((f, d))
    for kind, items in examples.items():
        f = None
        for path, d in items:  # the first design of the kind that computes (a level may be missing)
            try:
                registry.get(kind).compute(d, Options())
            except Exception:
                continue
            f = path
            break
        if f is None:
            continue
        t = wall([py, "-m", "gearcalc", kind, str(f), "--format", "csv"], args.repeat)
        rows.append(("startup", f"gearcalc {kind} (one design, csv)", kind, t * 1e3, f.name))
    for kind, items in examples.items():
        calc = registry.get(kind)
        for f, d in items:
            for level in calc.models:
                try:
                    t = in_process(d, calc, Options(tol=1e-6, model=level), args.repeat)
                except Exception as exc:  # a level that does not apply to this design
                    rows.append(("compute", f.name, f"{kind}:{level}", float("nan"), f"n/a: {str(exc)[:60]}"))
                    continue
                rows.append(("compute", f.name, f"{kind}:{level}", t * 1e3, ""))
    header = ("group", "what", "kind:level", "time_ms", "note")
    with open(args.out, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(header)
        w.writerows(rows)
    print(f"# {platform.node()} {platform.machine()} {platform.processor() or ''} python {platform.python_version()}, "
          f"{os.cpu_count()} cpus")
    print(f"{'group':8} {'kind:level':22} {'time_ms':>10}  what / note")
    for g, what, kl, ms, note in rows:
        print(f"{g:8} {kl:22} {ms:10.3f}  {what} {note}")
    print(f"written: {args.out}")


if __name__ == "__main__":
    main()
