"""Times of the contact level's backlash (``backlash_deg``, pins.md §8) on satellites with clearance or preload:
cycloids of the paper's sizes (u = 10, 11 and 30, K1 = 0.75, e = 3.9 mm, R_b = 1.95 mm) with equidistant and
radial modifications, and the u = 10 circular-arc design with an explicit tooth circle.  The best of ``--repeat``
runs (default 3) of :func:`gearcalc.pins.contact.backlash`, in-process.

Usage::

    python benchmarks/pins_backlash.py [--repeat 3]

The backlash does not depend on the load; the contact law and torque only build the model.  Before 2026-11-27 (a
golden-section search with one crank angle per evaluation, each free play doubled from 1e-12 rad) a design with
clearance took 0.45-1.2 s; the VM's timings vary by up to +-50 % between runs.
"""
from __future__ import annotations

import argparse
import sys
import time

from gearcalc.pins import REDUCER, Cycloid
from gearcalc.pins import contact as pc


def designs():
    """(name, ContactModel) of the timed satellites."""
    law = pc.contact_law("linear", stiffness=1e5)
    out = []
    for z1, z2 in ((21, 22), (20, 22), (60, 62)):
        g = Cycloid.from_curtate_ratio(z1, z2, 3.9, 0.75, 1.95)
        for dRp, dRb in ((0.0, 0.02), (0.02, 0.0), (-0.01, 0.01), (0.0, 1e-4)):
            out.append((f"cycloid {z1}/{z2} dRp={dRp:g} dRb={dRb:g}",
                        pc.ContactModel(g, pc.CycloidProfile(g, dRp, dRb), law, 1e3, REDUCER)))
    g = Cycloid.from_pin_circle(20, 22, 3.9, 57.2, 2.75)
    rho, _ = pc.full_tooth(g)
    out.append(("circular 20/22 R_t=46.5", pc.ContactModel(g, pc.CircularProfile(g, rho, 46.5), law, 1e3, REDUCER)))
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--repeat", type=int, default=3)
    a = ap.parse_args(argv)
    for name, model in designs():
        best, value = float("inf"), None
        for _ in range(a.repeat):
            t = time.perf_counter()
            value = pc.backlash(model)
            best = min(best, time.perf_counter() - t)
        print(f"{name:36s} backlash {value:.15e} rad  {best * 1e3:7.1f} ms", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
