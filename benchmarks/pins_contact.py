"""Contact-level times of the pins designs (issue 15): every configs/pins_paper_*.toml (or the files given), at
``--tol`` (default 1e-6), both friction models, in-process, the best of ``--repeat`` runs (default 5).

Usage::

    python benchmarks/pins_contact.py [--tol 1e-6] [--repeat 5] [--json out.json] [config.toml ...]

A plain cycloid gets ``contact.face_width_mm = 10`` (the Hertz law needs it; the paper designs' circular-arc configs
set it).  The time is the run's own ``model_time_ms`` (the calculation, without loading and output); the VM's
timings vary by up to +-50 % between runs, so compare runs made one after the other.
"""
from __future__ import annotations

import os
import sys

import gearcalc
from pins_timing import MODELS, run


def time_design(path: str, friction: str, tol: float, repeat: int) -> dict:
    """The best ``model_time_ms`` of ``repeat`` runs of one design at the contact level, with its summary."""
    overrides = {"friction.model": friction}
    with open(path) as fh:
        if "face_width_mm" not in fh.read():
            overrides["contact.face_width_mm"] = 10.0
    best, summary = float("inf"), None
    for _ in range(repeat):
        r = gearcalc.compute(path, model="contact", tol=tol, overrides=overrides)
        if r.summary["model_time_ms"] < best:
            best, summary = r.summary["model_time_ms"], r.summary
    return {"design": os.path.basename(path)[:-5], "friction": friction, "time_ms": best,
            "n_crank": summary["n_crank"], "efficiency": summary["efficiency"],
            "efficiency_err": summary["efficiency_err"]}


def main(argv=None) -> int:
    return run(__doc__, argv, "pins_paper_c*.toml", 5,
               lambda path, tol, repeat: [time_design(path, f, tol, repeat) for f in MODELS],
               lambda row: f"{row['design']:32s} {row['friction']:12s} {row['time_ms']:7.1f} ms  n_crank "
                           f"{row['n_crank']:5d}  eta {row['efficiency']:.9f} +- {row['efficiency_err']:.1e}")


if __name__ == "__main__":
    sys.exit(main())
