"""One docstring form on every public physics function: numpydoc, checked by ruff and here (issue 35 item 5).

The physics modules are gearcalc/rows, gearcalc/zstk and gearcalc/pins but their schema, report, plot and figure
modules, and gearcalc/hertz.py, roots.py and quadrature.py (pyproject.toml selects ruff's pydocstyle rules, the
numpy convention, for the same files).  Each public (no leading underscore) module-level function's docstring
holds the sections Parameters, Returns, Examples and References and a ``.. math::`` block, but the functions of
:data:`NOT_A_FORMULA` need no math (each with its reason: helpers, drivers, registries).
``python benchmarks/docstrings.py`` prints the shares.
"""
import ast
import importlib.util
import pathlib
import shutil
import subprocess
import sys

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[1]
NOT_PHYSICS = {"__init__", "schema", "report", "plot", "figure"}
SHARED = ("gearcalc/hertz.py", "gearcalc/roots.py", "gearcalc/quadrature.py")
SECTIONS = ("Parameters", "Returns", "Examples", "References")

NOT_A_FORMULA = {
    # module:function -> why its docstring has no .. math:: block
    "gearcalc.zstk.geometry:broadcast": "array helper (np.broadcast_to without a copy)",
    "gearcalc.zstk.geometry:take": "array helper (designs selected from a dataclass of arrays)",
    "gearcalc.zstk.geometry:single": "array helper (one design's arrays as scalars)",
    "gearcalc.zstk.solve:prepare": "driver: calls the closure, validity and phase functions, each with its math",
    "gearcalc.zstk.solve:solve_stack": "driver: groups designs by N and calls the load and stress functions",
    "gearcalc.zstk.solve:gather": "array helper (results put back in the designs' order)",
    "gearcalc.zstk.solve:solve_sweeping": "driver: calls critical_placement and the allowable-load solver",
    "gearcalc.zstk.envelope:sweep_grid": "configuration: the sweeps' grid sizes",
    "gearcalc.pins.friction:friction_law": "registry look-up of a law by name",
    "gearcalc.pins.friction:register_friction_law": "registry entry of a law by name",
    "gearcalc.pins.contact_law:register_contact_law": "registry entry of a law by name",
    "gearcalc.pins.profiles:make_profile": "registry: the factory of a profile by name",
    "gearcalc.pins.profiles:profile_entry": "registry look-up of a profile by name",
    "gearcalc.pins.checks:select_level": "rule dispatch: the level a design's tables and profile call for",
    "gearcalc.pins.checks:design_problems": "rule dispatch: the problems of check in their order",
    "gearcalc.pins.checks:points_pass": "rule dispatch: the rules of design_problems over sweep points",
    "gearcalc.pins.outputs:consistent_outputs": "driver: runs consistent_cycles and consistent_point",
    "gearcalc.pins.batching:run_batch": "driver: the batch contract (results or exceptions, in order)",
    "gearcalc.pins.columns:float64": "value conversion (None as NaN)",
    "gearcalc.pins.columns:words_equal": "comparison of a column of words",
    "gearcalc.pins.detail:rows": "table helper (rows from columns)",
    "gearcalc.pins.contact_states:filled": "array helper (np.full without its wrapper)",
    "gearcalc.pins.contact_states:sorted_places": "array helper (places of parts in a stable sort)",
    "gearcalc.pins.contact_states:merged": "array helper (a sorted concatenation)",
    "gearcalc.pins.contact_states:same_rows": "comparison of two pin sets",
    "gearcalc.pins.contact_states:over_rows": "array helper (per-pin rows re-indexed)",
    "gearcalc.pins.contact_states:take_states": "array helper (states at some crank angles)",
    "gearcalc.pins.contact_states:put_states": "array helper (states written at some crank angles)",
    "gearcalc.pins.contact_states:concat_states": "array helper (states sorted together)",
    "gearcalc.pins.contact_states:relayout": "array helper (states over other pins)",
    "gearcalc.pins.contact_states:contact_index": "array helper (an index of contacts)",
    "gearcalc.pins.contact_states:sub_pose": "array helper (the pose at some crank angles)",
    "gearcalc.pins.contact_level:satellite_profile": "registry: the profile by name (circular_profile's math)",
    "gearcalc.pins.contact:solve_modes": "driver: runs cycle_at_torque for each mode (its math there)",
    "gearcalc.pins.columns:operating": "value conversion (the operating point's columns)",
    "gearcalc.pins.columns:friction_models": "rule dispatch: the friction model per point",
    "gearcalc.pins.checks:level_cause": "rule dispatch: why a level runs (select_level's rule)",
    "gearcalc.pins.margins:margin_columns": "driver: the three margin functions over summary columns",
}

DOC_OF = {
    # module:function -> the function whose docstring it is given at run time (f.__doc__ = g.__doc__)
    "gearcalc.pins.contact_profiles:full_tooth": "_full_tooth",
}

NOT_YET: set = set()
"""The public physics functions whose docstrings are not numpydoc yet: none (a name listed here must be one that
lacks a section; a new public physics function comes with its numpydoc docstring)."""


def physics_modules():
    out = []
    for pkg in ("rows", "zstk", "pins"):
        out += [p for p in sorted((ROOT / "gearcalc" / pkg).glob("*.py")) if p.stem not in NOT_PHYSICS]
    return out + [ROOT / s for s in SHARED]


def public_functions():
    """{"module:function": docstring} of the public module-level functions of the physics modules."""
    out = {}
    docs = {}
    for path in physics_modules():
        mod = ".".join(path.relative_to(ROOT).with_suffix("").parts)
        tree = ast.parse(path.read_text(encoding="utf-8"), str(path))
        for node in tree.body:
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                docs[f"{mod}:{node.name}"] = ast.get_docstring(node) or ""
                if not node.name.startswith("_"):
                    out[f"{mod}:{node.name}"] = docs[f"{mod}:{node.name}"]
    for name, other in DOC_OF.items():
        out[name] = docs[name.split(":")[0] + ":" + other]
    return out


def missing(doc: str, formula: bool = True) -> list:
    """The numpydoc parts ``doc`` lacks: sections (a title underlined by dashes) and the math block."""
    lines = [s.strip() for s in doc.splitlines()]
    have = {a for a, b in zip(lines, lines[1:]) if b and set(b) == {"-"}}
    out = [s for s in SECTIONS if s not in have]
    if formula and ".. math::" not in doc:
        out.append(".. math::")
    return out


def test_the_physics_functions_are_found():
    # a guard that the walk finds the modules: hundreds of public physics functions
    assert len(public_functions()) > 250


def test_every_public_physics_function_has_the_numpydoc_sections():
    bad = {}
    for name, doc in public_functions().items():
        if name in NOT_YET:
            continue
        lack = missing(doc, formula=name not in NOT_A_FORMULA)
        if lack:
            bad[name] = lack
    assert not bad, "docstrings without numpydoc sections: " + "; ".join(f"{k} lacks {v}" for k, v in bad.items())


def test_the_lists_of_exceptions_are_current():
    funcs = public_functions()
    gone = sorted((NOT_YET | set(NOT_A_FORMULA)) - set(funcs))
    assert not gone, f"listed functions that no longer exist: {gone}"
    done = sorted(n for n in NOT_YET if not missing(funcs[n], formula=n not in NOT_A_FORMULA))
    assert not done, f"converted: take them off NOT_YET: {done}"
    assert not NOT_YET & set(NOT_A_FORMULA)


def _configured_rules():
    import tomllib

    lint = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["tool"]["ruff"]["lint"]
    assert lint["pydocstyle"]["convention"] == "numpy"
    return lint["select"]


def test_the_physics_docstrings_pass_ruff_pydocstyle():
    assert "D" in _configured_rules()
    if importlib.util.find_spec("ruff") is not None:
        ruff = [sys.executable, "-m", "ruff"]
    elif shutil.which("ruff"):
        ruff = [shutil.which("ruff")]
    else:
        pytest.skip("ruff is not installed (it is in the test extra: pip install -e .[test])")
    files = [str(p.relative_to(ROOT)) for p in physics_modules()]
    # the rules of pyproject.toml: pydocstyle's (D) with the numpy convention among them (a --select on the
    # command line would drop the configured ignores)
    r = subprocess.run(ruff + ["check", "--no-cache", *files], cwd=ROOT, capture_output=True, text=True)
    assert r.returncode == 0, r.stdout + r.stderr
