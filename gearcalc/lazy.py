"""Packages whose public names are imported on first use (PEP 562): ``import gearcalc.rows`` and
``import gearcalc.pins`` stay cheap (no numpy), and ``pins.Cycloid`` imports ``pins.geometry`` when first used.

A package calls :func:`lazy_names` once and binds what it returns as its module-level ``__all__``,
``__getattr__`` and ``__dir__``.
"""
from __future__ import annotations

import importlib


def lazy_names(package: str, namespace: dict, modules: tuple[str, ...], names: dict[str, tuple[str, ...]]):
    """``(__all__, __getattr__, __dir__)`` of a package that re-exports ``names`` (module -> public names).

    Parameters
    ----------
    package : str
        the package's ``__name__``.
    namespace : dict
        the package's ``globals()``: a name, once imported, is stored there, so later look-ups are plain.
    modules : tuple of str
        the package's modules, reachable as attributes too (``pins.contact``).
    names : dict
        module -> the public names it holds.

    Examples
    --------
    >>> ns = {}
    >>> all_, getattr_, dir_ = lazy_names("json", ns, ("decoder",), {"decoder": ("JSONDecoder",)})
    >>> all_, getattr_("JSONDecoder").__name__, "JSONDecoder" in ns, getattr_("decoder").__name__
    (['JSONDecoder'], 'JSONDecoder', True, 'json.decoder')
    """
    where = {name: module for module, held in names.items() for name in held}

    def __getattr__(name: str):
        """The public names of the modules, imported on first use (PEP 562)."""
        module = where.get(name)
        if module is None:
            if name in modules:
                return importlib.import_module(f"{package}.{name}")
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        value = getattr(importlib.import_module(f"{package}.{module}"), name)
        namespace[name] = value
        return value

    def __dir__():
        return sorted(set(namespace) | set(where))

    return sorted(where), __getattr__, __dir__
