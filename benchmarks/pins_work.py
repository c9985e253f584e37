"""The work the pins contact level does per design (issue 15), counted rather than timed: equilibrium solves (state
calls), the crank angles they hold, moment-balance evaluations and the contact pairs evaluated, per friction model.

Usage::

    python benchmarks/pins_work.py [--tol 1e-6] [--json out.json] [config.toml ...]

The VM's timings drift by up to +-50 % between runs and +-5-10 % between interleaved ones, so a change worth a few
per cent cannot be judged by time alone; these counts do not drift (the same code gives the same counts), and with
the per-call and per-angle costs of ``pins_state_calls.py`` they say where the time goes.  Columns:

* ``calls``: :meth:`ContactModel.state` calls (each an equilibrium solve with the friction fixed point);
* ``angles``: the crank angles those calls hold, summed;
* ``balances`` / ``bal_angles``: :meth:`ContactModel._balance` evaluations (one per Newton iteration or kinematics)
  and the crank angles they hold, summed;
* ``pairs``: contact pairs evaluated (profile ``contacts`` calls: candidate pins x contacts x angles, summed).

A plain cycloid gets ``contact.face_width_mm = 10`` (the Hertz law needs it), as in ``pins_contact.py``.
"""
from __future__ import annotations

import sys

import gearcalc
from gearcalc.pins import contact as pc
from pins_timing import MODELS, run

COUNTS = ("calls", "angles", "balances", "bal_angles", "pairs")


def _counting():
    """Wrap the counted methods (once); returns the dict of counters they add to."""
    counts = dict.fromkeys(COUNTS, 0)
    depth = [0]

    def wrap(cls, name, count):
        f = getattr(cls, name)

        def w(self, *a, **k):
            count(self, a)
            return f(self, *a, **k)

        setattr(cls, name, w)

    def state(self, a):
        counts["calls"] += 1
        counts["angles"] += int(getattr(a[0], "size", 1))

    def balance(self, a):
        counts["balances"] += 1
        counts["bal_angles"] += int(a[1].size)

    def contacts(self, a):
        counts["pairs"] += int(a[1].size) * (1 if self.contacts_per_pin == 1 else a[0].aux["tx"].shape[0])

    # only the outermost state call counts (set_window's scan calls state itself)
    orig_state = pc.ContactModel.state

    def outer_state(self, *a, **k):
        depth[0] += 1
        try:
            if depth[0] == 1:
                state(self, a)
            return orig_state(self, *a, **k)
        finally:
            depth[0] -= 1

    pc.ContactModel.state = outer_state
    wrap(pc.ContactModel, "_balance", balance)
    wrap(pc.CircularProfile, "contacts", contacts)
    wrap(pc.CycloidProfile, "contacts", contacts)
    return counts


COUNTERS = None


def count_design(path: str, friction: str, tol: float) -> dict:
    """The counts of one design at the contact level under one friction model."""
    global COUNTERS
    if COUNTERS is None:
        COUNTERS = _counting()
    overrides = {"friction.model": friction}
    with open(path) as fh:
        if "face_width_mm" not in fh.read():
            overrides["contact.face_width_mm"] = 10.0
    for k in COUNTS:
        COUNTERS[k] = 0
    r = gearcalc.compute(path, model="contact", tol=tol, overrides=overrides)
    return {"design": path.rsplit("/", 1)[-1][:-5], "friction": friction, "n_crank": r.summary["n_crank"],
            **dict(COUNTERS)}


def main(argv=None) -> int:
    return run(__doc__, argv, "pins_paper_c*.toml", 1,
               lambda path, tol, repeat: [count_design(path, f, tol) for f in MODELS],
               lambda row: f"{row['design']:32s} {row['friction']:12s} " + " ".join(
                   f"{row[k]:9d}" for k in COUNTS),
               header=f"{'design':32s} {'friction':12s} " + " ".join(f"{k:>9s}" for k in COUNTS))


if __name__ == "__main__":
    sys.exit(main())
