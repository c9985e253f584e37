"""Tests of gearcalc.calculator, the contract between the frame and a calculator: checks as margins (a margin < 0
fails, None does not apply; interface.md "Output"), the run-end lines, the tolerance rule, the bad-input exceptions
and the statement of a key's constraint.

Where the expected values come from: the margins' sign convention itself (IEEE: -0.0 is not below zero, the least
negative float is), the old flags of every shipped config, counts made here from the printed fields, the bounds
[1e-15, 0.1) of --tol (interface.md), and pickle's round trip (an error raised in a worker process).
"""
import csv
import io
import math
import pickle

import numpy as np
import pytest

import gearcalc
from conftest import CONFIGS, cli
from gearcalc import registry
from gearcalc.calculator import (Calculator, Check, DesignError, Field, InputError, InvalidPoints, failed_check_column,
                                 failed_checks, tol_problem)

CONFIG_FILES = sorted(CONFIGS.glob("*.toml"))
NEGATIVE_TIE = math.nextafter(0.0, -1.0)  # the least negative float: a failing check at the exact tie


def negatives(summary, kind):
    return [c.name for c in registry.get(kind).checks if summary.get(c.field) is not None and summary[c.field] < 0]


def agrees_with_flags(kind, s):
    """The old flags of the summary ``s`` against the signs of its margins (the same on every design)."""
    if kind == "zstk":
        assert s["pass"] == (s["margin_sigma"] >= 0)
        assert s["margin_closure"] >= 0 and s["margin_clearance"] >= 0  # validity rules: a computed design is inside
    elif kind == "rows":
        if "bridges_feasible" in s:
            assert s["bridges_feasible"] == (s["margin_bridge_fit"] >= 0)
        assert s["margin_bore"] >= 0
    else:
        if s["self_locking"] is None:
            assert s["margin_self_locking"] is None
        else:
            assert s["self_locking"] == (s["margin_self_locking"] < 0)
        assert (s["rolling_ok"] is None) == (s["margin_rolling"] is None)
        if s["rolling_ok"] is not None:
            assert s["rolling_ok"] == (s["margin_rolling"] >= 0)
    assert s["failed_checks"] == negatives(s, kind)


@pytest.mark.parametrize("path", CONFIG_FILES, ids=lambda p: p.stem)
def test_shipped_configs_margins_agree_with_flags(path):
    r = gearcalc.compute(path)
    agrees_with_flags(r.kind, r.summary)
    assert bool(r.failed) == bool(r.summary["failed_checks"])


def test_sweep_and_batch_end_with_one_line_per_failing_check(tmp_path):
    r = cli("sweep", CONFIGS / "zstk_merko_example.toml", "--vary", "load.radial_N=1e4:4e5:1e4", "--set",
            "material.allowable_stress_MPa=2000", "--format", "csv", "--fields", "sigma_max_MPa,allowable_stress_MPa")
    rows = list(csv.DictReader(io.StringIO(r.out)))
    over = sum(float(x["sigma_max_MPa"]) > float(x["allowable_stress_MPa"]) for x in rows)  # counted independently
    assert 0 < over < len(rows) and r.code == 1
    assert r.err.strip().splitlines()[-1].endswith(
        f"{over} of {len(rows)} points fail sigma (sigma_max > allowable_stress)")
    assert "check failed at" not in r.err
    for p in sorted(CONFIGS.glob("zstk_merko_*.toml")):
        (tmp_path / p.name).write_text(p.read_text())
    r = cli("run", tmp_path, "--set", "material.allowable_stress_MPa=760", "--format", "csv", "--fields",
            "sigma_max_MPa")
    sigmas = [float(x["sigma_max_MPa"]) for x in csv.DictReader(io.StringIO(r.out))]
    failing = sum(s > 760 for s in sigmas)
    assert r.code == 1 and 0 < failing < len(sigmas)
    assert f"{failing} of {len(sigmas)} zstk designs fail sigma (sigma_max > allowable_stress)" in r.err
    assert r.err.count("check failed: sigma_max_MPa") == failing  # the per-file messages are kept


CHECKS = (Check("a", "a fails"), Check("b", "b fails"), Check("c", "c fails"), Check("d", "d fails"))


def test_failed_checks_are_the_negative_margins_in_the_checks_order():
    summary = {"margin_d": -1.0, "margin_a": NEGATIVE_TIE, "margin_b": -0.0, "margin_c": None}
    assert failed_checks(summary, CHECKS) == ["a", "d"]           # -0.0 passes (not < 0), the tie below it fails
    assert failed_checks({"margin_a": 0.0, "margin_b": 1e-300}, CHECKS) == []
    assert failed_checks({"margin_a": True, "margin_b": "x"}, CHECKS) == []  # a flag or a word is not a margin


def test_failed_check_column_and_counts_equal_the_points_one_by_one():
    rng = np.random.default_rng(35)
    n = 50
    cols = {"margin_a": rng.normal(size=n), "margin_b": [None if k % 3 == 0 else float(v) for k, v in
                                                         enumerate(rng.normal(size=n))],
            "margin_d": rng.normal(size=n).tolist()}
    per_point = [failed_checks({k: (v[i] if isinstance(v, list) else float(v[i])) for k, v in cols.items()},
                               CHECKS) for i in range(n)]
    assert failed_check_column(cols, CHECKS, n) == per_point
    assert failed_check_column({}, CHECKS, 3) == [[], [], []]
    calc = Calculator("t", "test", (), lambda d, o: None, checks=CHECKS)
    counts = calc.failed_points(cols)
    assert counts == {c: sum(c in p for p in per_point) for c in "abd" if any(c in p for p in per_point)}
    lines = calc.check_lines(counts, n, "points")
    assert lines == [f"{counts[c]} of {n} points fail {c} ({c} fails)" for c in "abd" if c in counts]


@pytest.mark.parametrize("tol, ok", [(1e-15, True), (math.nextafter(1e-15, 0.0), False), (1e-6, True),
                                     (math.nextafter(0.1, 0.0), True), (0.1, False), (float("nan"), False),
                                     (True, False), ("1e-6", False), (1, False)])
def test_tol_problem_is_the_range_of_the_interface(tol, ok):
    # interface.md: --tol in [1e-15, 0.1), a number (not a bool or a string)
    assert (tol_problem(tol) is None) is ok


def test_input_errors_survive_a_worker_process():
    # a worker's exception reaches the parent by pickle: the same type, messages, key and warnings
    errors = [InputError(["a.toml: x = 1: must be > 2", "a.toml: y: missing"], ["a warning"]),
              DesignError("geometry.eccentricity_mm", "= 52: must be < 50"),
              InvalidPoints([None, "geometry.rollers = 2: must be >= 3", None])]
    for e in errors:
        back = pickle.loads(pickle.dumps(e))
        assert type(back) is type(e) and isinstance(back, ValueError)
        assert back.args == e.args and back.__dict__ == e.__dict__
    assert str(errors[1]) == "geometry.eccentricity_mm = 52: must be < 50"
    assert str(errors[2]) == "geometry.rollers = 2: must be >= 3"


def test_field_constraint_states_the_bounds_and_words():
    assert Field("x_mm", "number", gt=0, le=1e5).constraint() == "a number > 0, <= 100000"
    assert Field("n", "integer", ge=3, choices=("auto",)).constraint() == 'an integer >= 3, or "auto"'
    assert Field("s", "string", choices=("root", "pitch")).constraint() == '"root" | "pitch"'
    assert Field("v", "numbers", length=2, ge=0.5).constraint() == "an array of 2 numbers >= 0.5"
    assert Field("t", "number", lt=1e7).constraint() == "a number < 1e+07"


@pytest.mark.parametrize("column", [
    [1.0, -2.0, None, True, False, -0.0, float("nan"), -3, NEGATIVE_TIE],
    [None] * 4, [1.0, -1.0, "words"], [10 ** 400, -(10 ** 400), -1],
    "numpy float", "numpy int", "numpy flags", "numpy objects",
])
def test_failing_points_of_a_column_at_once_are_those_value_by_value(column):
    """The count and the failed_checks of sweep columns (a numpy comparison, a list of numbers as floats) are
    those of the rule of one value (calculator._below_zero: a number below zero; None, a flag, a word never)."""
    import numpy as np

    from gearcalc.calculator import Check, Calculator, _below_zero, failed_check_column

    column = {"numpy float": np.array([1.0, -1.0, np.nan, NEGATIVE_TIE]), "numpy int": np.array([3, -1, 0]),
              "numpy flags": np.array([True, False]), "numpy objects": np.array([1.0, None, -2.0], dtype=object),
              }.get(column, column) if isinstance(column, str) else column
    values = column.tolist() if hasattr(column, "tolist") else column
    below = [k for k, v in enumerate(values) if _below_zero(v)]
    calc = Calculator("x", "x", (), None, checks=(Check("a", ""), Check("b", "")))
    assert calc.failed_points({"margin_a": column}) == ({"a": len(below)} if below else {})
    got = failed_check_column({"margin_a": column, "margin_b": [-1.0] * len(values)}, calc.checks, len(values))
    assert got == [(["a"] if k in below else []) + ["b"] for k in range(len(values))]
