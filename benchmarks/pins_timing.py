"""The command line shared by the pins timing scripts (``pins_contact.py``, ``pins_ideal.py``): the designs
(the files given, or the shipped ones matching a pattern), ``--tol``, ``--repeat`` and ``--json``; one printed line
per row of results, and the rows as JSON on request."""
from __future__ import annotations

import argparse
import glob
import json
import os

HERE = os.path.dirname(os.path.abspath(__file__))
CONFIGS = os.path.join(HERE, "..", "configs")
MODELS = ("consistent", "first-order")
"""The friction models every script times (pins.md §4.9 and §4.6-4.7)."""


def run(doc: str, argv, pattern: str, repeat: int, rows_of, line, header: str | None = None) -> int:
    """Parse ``argv``, time every design with ``rows_of(path, tol, repeat)`` (a list of dict rows), print
    ``line(row)`` for each (after ``header``), write the rows to ``--json``; returns the exit status."""
    ap = argparse.ArgumentParser(description=doc.split("\n\n")[0])
    ap.add_argument("configs", nargs="*")
    ap.add_argument("--tol", type=float, default=1e-6)
    ap.add_argument("--repeat", type=int, default=repeat)
    ap.add_argument("--json")
    a = ap.parse_args(argv)
    paths = a.configs or sorted(glob.glob(os.path.join(CONFIGS, pattern)))
    if header:
        print(header, flush=True)
    rows = []
    for path in paths:
        for row in rows_of(path, a.tol, a.repeat):
            rows.append(row)
            print(line(row), flush=True)
    if a.json:
        with open(a.json, "w") as fh:
            json.dump(rows, fh, indent=1)
    return 0
