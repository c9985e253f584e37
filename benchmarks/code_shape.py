"""The shape of the pins contact level's code (issue 35 item 1): sizes, import circles, private names, parameters.

Run from the repository root: ``python benchmarks/code_shape.py [package_dir]`` (default ``gearcalc/pins``).
Prints, from the source alone (ast; nothing is imported):

- lines per contact module (``contact*.py``, ``friction.py``, ``settings.py`` where present);
- the largest function and class of those modules (lines);
- the import circles among the package's modules, in-function imports included (strongly connected components of
  the graph of ``from . import x`` / ``from .x import y`` / ``import gearcalc.pins.x`` edges);
- the private names (``_x``) one module of the package imports from another;
- functions of the package with more than 8 parameters and the largest count; functions over 80 lines.

``python benchmarks/code_shape.py --tests`` instead counts the tests that mirror the code (issue 35 item 3): the
modules of ``gearcalc`` over 100 lines, and those with a test file at the mirrored path (``gearcalc/x.py`` ->
``tests/test_x.py``, ``gearcalc/pkg/x.py`` -> ``tests/pkg/test_x.py``); the rest are listed.
"""
from __future__ import annotations

import ast
import pathlib
import sys

CONTACT = ("contact", "friction", "profile", "settings")


def _modules(root: pathlib.Path) -> dict:
    return {p.stem: p for p in sorted(root.glob("*.py"))}


def _target(node: ast.ImportFrom, pkg: str) -> str | None:
    if node.level == 1:
        return node.module or ""
    if node.module and node.module.startswith(pkg + "."):
        return node.module[len(pkg) + 1:]
    return None


def _imports(tree: ast.AST, pkg: str, names: set):
    """(module imported, name imported) pairs within the package, every import statement (in functions too)."""
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom):
            mod = _target(node, pkg)
            if mod is None:
                continue
            for alias in node.names:
                if mod == "":               # from . import x: the module x
                    if alias.name in names:
                        yield alias.name, None
                elif mod in names:
                    yield mod, alias.name


def _circles(graph: dict) -> list:
    index, low, stack, on, out = {}, {}, [], set(), []
    counter = [0]

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in graph[v]:
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1 or v in graph[v]:
                out.append(sorted(comp))

    sys.setrecursionlimit(10000)
    for v in graph:
        if v not in index:
            visit(v)
    return out


def _span(node) -> int:
    return node.end_lineno - node.lineno + 1


def _code_span(node) -> int:
    """Lines of a function without its docstring."""
    body = node.body
    doc = body and isinstance(body[0], ast.Expr) and isinstance(body[0].value, ast.Constant) \
        and isinstance(body[0].value.value, str)
    return _span(node) - (_span(body[0]) if doc else 0)


def _params(fn) -> int:
    a = fn.args
    return len(a.posonlyargs) + len(a.args) + len(a.kwonlyargs) + (a.vararg is not None) + (a.kwarg is not None) - (
        1 if (a.posonlyargs or a.args) and (a.posonlyargs + a.args)[0].arg in ("self", "cls") else 0)


def main(root: str = "gearcalc/pins") -> None:
    root_p = pathlib.Path(root)
    pkg = ".".join(root_p.parts)
    mods = _modules(root_p)
    trees = {m: ast.parse(p.read_text(), str(p)) for m, p in mods.items()}
    graph, private = {m: set() for m in mods}, []
    for m, tree in trees.items():
        for mod, name in _imports(tree, pkg, set(mods)):
            if mod != m:
                graph[m].add(mod)
            if name is not None and name.startswith("_") and not name.startswith("__") and mod != m:
                private.append(f"{m} <- {mod}.{name}")

    print("lines per contact module:")
    total = 0
    contact = [m for m in mods if m.startswith(CONTACT) or m in ("friction", "profiles")]
    for m in contact:
        n = len(mods[m].read_text().splitlines())
        total += n
        print(f"  {m + '.py':28s} {n:5d}")
    print(f"  {'total':28s} {total:5d} in {len(contact)} modules")

    funcs, classes = [], []
    for m, tree in trees.items():
        for node in ast.walk(tree):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                funcs.append((m, node))
            elif isinstance(node, ast.ClassDef):
                classes.append((m, node))
    cf = [(m, f) for m, f in funcs if m in contact]
    cc = [(m, c) for m, c in classes if m in contact]
    if cf:
        m, f = max(cf, key=lambda t: _span(t[1]))
        print(f"largest contact function: {m}.{f.name} {_span(f)} lines")
    if cc:
        m, c = max(cc, key=lambda t: _span(t[1]))
        print(f"largest contact class: {m}.{c.name} {_span(c)} lines")
    big = [(m, c) for m, c in classes if _span(c) > 400]
    print(f"classes over 400 lines (package): {len(big)}", ", ".join(f"{m}.{c.name} ({_span(c)})" for m, c in big))

    circles = _circles({m: sorted(v) for m, v in graph.items()})
    print(f"import circles (package, in-function imports included): {len(circles)}")
    for c in circles:
        print("  ", " ".join(c))
    print(f"private names imported across modules (package): {len(private)}")
    for p in private:
        print("  ", p)

    many = sorted(((_params(f), m, f.name) for m, f in funcs if _params(f) > 8), reverse=True)
    print(f"functions with > 8 parameters (package): {len(many)}; max {max((_params(f) for _, f in funcs), default=0)}")
    for n, m, name in many:
        print(f"   {n:3d} {m}.{name}")
    print(f"  of them in the contact modules: {sum(m in contact for _, m, _ in many)}; max parameters there: "
          f"{max((_params(f) for m, f in funcs if m in contact), default=0)}")
    long_ = sorted(((_span(f), _code_span(f), m, f.name) for m, f in funcs if _span(f) > 80), reverse=True)
    print(f"functions over 80 lines (package): {len(long_)}; without their docstrings: "
          f"{sum(c > 80 for _, c, _, _ in long_)}")
    for n, c, m, name in long_:
        print(f"   {n:4d} ({c:4d} without docstring) {m}.{name}")
    print(f"  of them in the contact modules: {sum(m in contact for _, _, m, _ in long_)}")


def mirrored_tests(src: str = "gearcalc", tests: str = "tests", min_lines: int = 100) -> tuple:
    """(modules over ``min_lines`` lines, those with a mirrored test file) as sorted lists of source paths."""
    src_root, test_root = pathlib.Path(src), pathlib.Path(tests)
    big, mirrored = [], []
    for path in sorted(src_root.rglob("*.py")):
        if path.name == "__main__.py" or len(path.read_text().splitlines()) <= min_lines:
            continue
        rel = path.relative_to(src_root)
        stem = rel.parent.name if path.name == "__init__.py" else rel.stem     # a package's __init__: the package
        folder = rel.parent.parent if path.name == "__init__.py" else rel.parent
        big.append(str(path))
        if (test_root / folder / f"test_{stem}.py").exists():
            mirrored.append(str(path))
    return big, mirrored


def tests_main(src: str = "gearcalc", tests: str = "tests") -> None:
    big, mirrored = mirrored_tests(src, tests)
    print(f"modules over 100 lines: {len(big)}; with a mirrored test file: {len(mirrored)} "
          f"({100 * len(mirrored) / max(len(big), 1):.0f} %)")
    for path in big:
        if path not in mirrored:
            print(f"  no tests/.../test_<module>.py: {path}")


if __name__ == "__main__":
    if sys.argv[1:2] == ["--tests"]:
        tests_main(*sys.argv[2:])
    else:
        main(*sys.argv[1:])
