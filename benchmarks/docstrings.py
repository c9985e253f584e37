"""The docstrings of the public physics functions (issue 35 item 5): how many carry math and numpydoc sections.

Run from the repository root: ``python benchmarks/docstrings.py [-v]``. From the source alone (ast; nothing is
imported), over the public (no leading underscore) module-level functions of the physics modules
(:data:`PHYSICS`), prints the share whose docstring holds a ``.. math::`` block and each of the sections
Parameters, Returns, Examples and References; ``-v`` lists the functions that miss any.
"""
from __future__ import annotations

import ast
import pathlib
import sys

# the physics modules: gearcalc/rows, gearcalc/zstk and gearcalc/pins but their schema, report and plot modules,
# and the shared numerical modules
NOT_PHYSICS = {"__init__", "schema", "report", "plot", "figure"}
SHARED = ("gearcalc/hertz.py", "gearcalc/roots.py", "gearcalc/quadrature.py")
SECTIONS = ("Parameters", "Returns", "Examples", "References")
DOC_OF = {("contact_profiles", "full_tooth"): "_full_tooth"}
"""Public functions whose docstring is another's, assigned at run time (``f.__doc__ = g.__doc__``)."""


def physics_modules(root: str | pathlib.Path = ".") -> list:
    """The paths of the physics modules under the repository root ``root``."""
    root = pathlib.Path(root)
    out = []
    for pkg in ("rows", "zstk", "pins"):
        out += [p for p in sorted((root / "gearcalc" / pkg).glob("*.py")) if p.stem not in NOT_PHYSICS]
    return out + [root / s for s in SHARED]


def public_functions(path: pathlib.Path) -> list:
    """(name, docstring) of the public module-level functions of the module at ``path``."""
    tree = ast.parse(path.read_text(encoding="utf-8"), str(path))
    docs = {n.name: ast.get_docstring(n) or "" for n in tree.body if isinstance(n, (ast.FunctionDef,
                                                                                   ast.AsyncFunctionDef))}
    return [(name, docs[DOC_OF.get((path.stem, name), name)]) for name in docs if not name.startswith("_")]


def has_section(doc: str, name: str) -> bool:
    """Whether the numpydoc section ``name`` (a title underlined by dashes) is in ``doc``."""
    lines = [s.strip() for s in doc.splitlines()]
    return any(a == name and b and set(b) == {"-"} for a, b in zip(lines, lines[1:]))


def has_math(doc: str) -> bool:
    """Whether ``doc`` holds a ``.. math::`` block."""
    return ".. math::" in doc


def survey(root: str | pathlib.Path = ".") -> dict:
    """{"module:function": {"math": bool, "Parameters": bool, ...}} over the public physics functions."""
    out = {}
    for path in physics_modules(root):
        mod = ".".join(path.relative_to(root).with_suffix("").parts)
        for name, doc in public_functions(path):
            row = {"math": has_math(doc)}
            row.update({s: has_section(doc, s) for s in SECTIONS})
            out[f"{mod}:{name}"] = row
    return out


def main(argv: list) -> None:
    rows = survey(".")
    n = len(rows)
    print(f"public physics functions: {n}")
    for key in ("math",) + SECTIONS:
        k = sum(r[key] for r in rows.values())
        print(f"  {key:12s} {k:4d}  {100 * k / max(n, 1):5.1f} %")
    if "-v" in argv:
        for f, r in rows.items():
            miss = [k for k, v in r.items() if not v]
            if miss:
                print(f"  {f}: no {', '.join(miss)}")


if __name__ == "__main__":
    main(sys.argv[1:])
