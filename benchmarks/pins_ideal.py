"""Ideal-level times of the pins designs (issue 15): the paper's cycloidal designs (configs/pins_paper_cyc_*.toml, or
the files given), at ``--tol`` (default 1e-6), both friction models (the default "consistent", pins.md §4.9, and
"first-order", §4.6-4.7), in-process, the best of ``--repeat`` calls (default 30).

Usage::

    python benchmarks/pins_ideal.py [--tol 1e-6] [--repeat 30] [--json out.json] [config.toml ...]

Per design and friction model it prints the least ``model_time_ms`` of the calls (the run's own wall-clock
time of the calculation, without loading and output: what issue 15's target of 1 ms refers to) and the least
CPU time (``time.process_time``) of a whole ``gearcalc.compute`` call (loading included), which other work on
a shared machine disturbs less.  The calls of the two friction models alternate, and the VM's timings vary
between runs: compare runs made one after the other (e.g. with ``PYTHONPATH`` pointing at another checkout).
"""
from __future__ import annotations

import os
import sys
import time

import gearcalc
from pins_timing import MODELS, run


def time_design(path: str, tol: float, repeat: int) -> list[dict]:
    """The best ``model_time_ms`` and CPU time of ``repeat`` ideal-level calls of one design, per friction model."""
    best = {m: [float("inf"), float("inf"), None] for m in MODELS}
    for m in MODELS:                          # warm-up (imports, caches)
        gearcalc.compute(path, model="ideal", tol=tol, overrides={"friction.model": m})
    for _ in range(repeat):
        for m in MODELS:                      # alternate the models, so that a disturbance hits both
            c0 = time.process_time()
            r = gearcalc.compute(path, model="ideal", tol=tol, overrides={"friction.model": m})
            cpu = (time.process_time() - c0) * 1e3
            b = best[m]
            b[0] = min(b[0], r.summary["model_time_ms"])
            b[1] = min(b[1], cpu)
            b[2] = r.summary
    rows = []
    for m in MODELS:
        wall, cpu, s = best[m]
        rows.append({"design": os.path.basename(path)[:-5], "friction": m, "model_time_ms": wall, "cpu_ms": cpu,
                     "n_crank": s["n_crank"], "efficiency": s["efficiency"], "efficiency_err": s["efficiency_err"]})
    return rows


def line(row) -> str:
    eta = "self-locking" if row["efficiency"] is None else f"{row['efficiency']:.9f} +- {row['efficiency_err']:.1e}"
    return (f"{row['design']:30s} {row['friction']:12s} {row['model_time_ms']:13.3f} {row['cpu_ms']:7.3f}  "
            f"{row['n_crank']:7d}  {eta}")


def main(argv=None) -> int:
    return run(__doc__, argv, "pins_paper_cyc_*.toml", 30, time_design, line,
               f"{'design':30s} {'friction':12s} {'model_time_ms':>13s} {'cpu_ms':>7s}  n_crank  efficiency")


if __name__ == "__main__":
    sys.exit(main())
