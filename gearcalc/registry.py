"""Which calculators exist: the one list of kinds.

Each kind is a module that defines ``CALCULATOR`` (a :class:`gearcalc.calculator.Calculator`) and a
one-line help, kept here so that ``gearcalc --help`` lists the commands without importing any
calculator.  Registering a calculator is one entry here: its command (``gearcalc KIND``), its
template (``gearcalc new KIND``), its figures, its sweep plots and its place in ``gearcalc run`` and
``gearcalc accuracy`` all follow from it.  The modules are imported only when used.
"""
from __future__ import annotations

import functools
import importlib
import importlib.util

KINDS = {
    "pins": ("gearcalc.kinds.pins",
             "KHV pin gearing: per-pin friction losses, cycle-averaged losses, efficiency."),
    "zstk": ("gearcalc.kinds.zstk",
             "Closed rolling-body mechanism: roller chain, closure correction, roller loads, contact stresses, "
             "strength check."),
    "rows": ("gearcalc.kinds.rows",
             "Multi-row planetary gear: row load sharing K, carrier bridge widths, relative mass."),
}


LEVELS = {
    "pins": ("formula", "ideal", "contact"),
    "zstk": ("equilibrium", "fixed-direction", "reference"),
    "rows": ("stepwise", "exact", "continuous"),
}
"""Each kind's model levels, cheapest first: its calculator's ``models`` (read from here, the one list) and the
``--model`` help (which so imports no calculator)."""


@functools.cache
def _present() -> tuple[str, ...]:
    return tuple(k for k, (module, _) in KINDS.items() if importlib.util.find_spec(module) is not None)


def kinds() -> list[str]:
    """The kinds whose module is present in this installation (looked up once a process: an installation does not
    change while it runs; each design's validation asks)."""
    return list(_present())


def help_of(kind: str) -> str:
    """The one-line help of a kind's command (no import of the calculator)."""
    return KINDS[kind][1]


def levels(kind: str) -> tuple[str, ...]:
    """The model levels of a kind, cheapest first (no import of the calculator)."""
    return LEVELS[kind]


def get(kind: str):
    """The :class:`~gearcalc.calculator.Calculator` of a kind."""
    return importlib.import_module(KINDS[kind][0]).CALCULATOR
