"""gearcalc: engineering calculator for gear and mechanism designers.

The Python API (:mod:`gearcalc.api`) is re-exported here lazily (PEP 562), so ``gearcalc --help`` and
``gearcalc check`` import neither numpy nor the calculators:

>>> import gearcalc
>>> r = gearcalc.compute("configs/rows_fig3_n3_nw3_B2.4.toml")     # doctest: +SKIP
"""

__version__ = "0.2.0"

__all__ = ["compute", "compute_files", "load", "sweep", "sweep_chunk", "models", "Batch", "Result", "Design",
           "InputError", "DesignError", "optimize", "sensitivity", "__version__"]


def __getattr__(name):
    if name in ("optimize", "sensitivity"):  # gearcalc.explore: scipy, imported by these only
        from .explore import api as explore_api

        return getattr(explore_api, name)
    if name in __all__ and name != "__version__":
        from . import api

        return getattr(api, name)
    raise AttributeError(f"module 'gearcalc' has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | set(__all__))
