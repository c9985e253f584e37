"""The shape of the pins ideal-level modules (issue 35, "a codebase a newcomer can change").

Measured from the source alone (ast), as ``python benchmarks/code_shape.py`` measures the package: no function of
:data:`MODULES` takes more than 8 parameters (the operating point, the friction and the gears travel as the parameter
objects of :mod:`gearcalc.pins.operating`), none is over 80 lines with its docstring, and no module of the package
imports a private name (``_x``) of these modules.
"""
import ast
import pathlib

import pytest

PINS = pathlib.Path(__file__).resolve().parents[1] / "gearcalc" / "pins"
MODULES = ("points", "outputs", "operating", "detail", "cycle", "columns", "speed_friction")
MAX_PARAMS, MAX_LINES = 8, 80          # the targets of issue 35 (benchmarks/code_shape.py)


def functions(module: str):
    tree = ast.parse((PINS / f"{module}.py").read_text(encoding="utf-8"))
    return [n for n in ast.walk(tree) if isinstance(n, (ast.FunctionDef, ast.AsyncFunctionDef))]


def params(fn) -> int:
    """Parameters as benchmarks/code_shape.py counts them (self and cls not)."""
    a = fn.args
    positional = a.posonlyargs + a.args
    return (len(positional) + len(a.kwonlyargs) + (a.vararg is not None) + (a.kwarg is not None)
            - (1 if positional and positional[0].arg in ("self", "cls") else 0))


@pytest.mark.parametrize("module", MODULES)
def test_no_long_argument_lists(module):
    assert {f.name: params(f) for f in functions(module) if params(f) > MAX_PARAMS} == {}


@pytest.mark.parametrize("module", MODULES)
def test_no_long_functions(module):
    lines = {f.name: f.end_lineno - f.lineno + 1 for f in functions(module)}
    assert {name: n for name, n in lines.items() if n > MAX_LINES} == {}


def test_no_private_name_of_these_modules_is_imported_elsewhere():
    found = []
    for path in sorted(PINS.glob("*.py")):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.ImportFrom) and node.level == 1 and node.module in MODULES \
                    and node.module != path.stem:
                found += [f"{path.stem} <- {node.module}.{a.name}" for a in node.names
                          if a.name.startswith("_") and not a.name.startswith("__")]
    assert found == []
