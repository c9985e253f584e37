"""What one equilibrium solve of the pins contact level costs against the crank angles it holds (issue 15): the fixed
cost of a call and the cost per angle, which bound what merging calls (e.g. of the two modes) can save.

Usage::

    python benchmarks/pins_state_calls.py [--repeat 7] [--json out.json]

The u = 10 paper geometries (z1/z2 = 20/22, e = 3.9 mm): circular-arc teeth of the full tooth on R_p = 57.2 mm,
R_b = 2.75 mm, and the cycloid of K1 = 0.75, R_b = 1.95 mm; Hertz contacts of 10 mm, 1e6 N*mm on the satellite,
friction in the balance (f = 0.1, fixed pins).  After a cycle at tol 1e-6 (warm starts from its states, as in the
product), ``ContactModel.state`` at n random crank angles of one period: the best of ``--repeat`` runs.  Measured
2026-11-27 on this 2-core VM (two runs, its speed drifts): 0.57-0.88 ms at 2 angles, 3.9-5.2 ms at 700, 7.4-9.4 ms
at 1400 (circular); 1.1-1.7, 6.7-9.1 and 16-19 ms (cycloid): a call costs ~0.6-0.9 or ~1.1-1.7 ms however few
angles it holds, an angle ~5-7 or ~10-13 us.
"""
from __future__ import annotations

import argparse
import json
import sys
import time

import numpy as np

from gearcalc.pins import MULTIPLIER, Cycloid
from gearcalc.pins import contact as pc

SIZES = (2, 8, 64, 350, 700, 1400)


def models():
    """(name, solved ContactModel) of the two u = 10 paper geometries, a cycle at tol 1e-6 solved on each."""
    law = pc.contact_law("hertz", face_width=10.0)
    g = Cycloid.from_pin_circle(20, 22, 3.9, 57.2, 2.75)
    rho, R_t = pc.full_tooth(g)
    circ = pc.ContactModel(g, pc.CircularProfile(g, rho, R_t), law, 1.0e6, MULTIPLIER, (0.1, 0.1, False))
    g = Cycloid.from_curtate_ratio(20, 22, 3.9, 0.75, 1.95)
    cyc = pc.ContactModel(g, pc.CycloidProfile(g, 0.0, 0.0), law, 1.0e6, MULTIPLIER, (0.1, 0.1, False))
    for m in (circ, cyc):
        pc.mean_loss_ratio(m, (0.1, 0.1, False), tol=1e-6)
    return [("circular u10", circ), ("cycloid u10", cyc)]


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--repeat", type=int, default=7)
    ap.add_argument("--json")
    a = ap.parse_args(argv)
    rows = []
    for name, m in models():
        for n in SIZES:
            best = float("inf")
            for rep in range(a.repeat):
                theta = np.sort(np.random.default_rng(rep).uniform(0.0, m.g.period, n))
                t0 = time.perf_counter()
                m.state(theta, phases=False)
                best = min(best, time.perf_counter() - t0)
            rows.append({"design": name, "angles": n, "ms": best * 1e3, "us_per_angle": best / n * 1e6})
            print(f"{name:14s} {n:5d} angles  {best * 1e3:7.3f} ms  {best / n * 1e6:8.2f} us/angle", flush=True)
    if a.json:
        with open(a.json, "w") as fh:
            json.dump(rows, fh, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
