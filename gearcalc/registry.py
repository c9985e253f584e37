"""Which calculators exist: kind name -> module that defines ``CALCULATOR``.

Registering a calculator is one line here; the modules are imported only when used.
"""
from __future__ import annotations

import importlib
import importlib.util

KINDS = {
    "pins": "gearcalc.kinds.pins",
    "zstk": "gearcalc.kinds.zstk",
    "rows": "gearcalc.kinds.rows",
}


def kinds() -> list[str]:
    """The kinds whose module is present in this installation."""
    return [k for k in KINDS if importlib.util.find_spec(KINDS[k]) is not None]


def get(kind: str):
    """The :class:`~gearcalc.calculator.Calculator` of a kind."""
    return importlib.import_module(KINDS[kind]).CALCULATOR
