"""Tests of the shared batch and sweep path (gearcalc/engine.py, gearcalc/grid.py): an output that is not finite is
the design's (or the sweep point's) error, never an exit 70 that costs the whole batch (issue 34)."""
import dataclasses
import json
import warnings

import numpy as np
import pytest

from conftest import CONFIGS, cli

GOOD = CONFIGS / "rows_fig3_n3_nw3_B2.4.toml"
MASS = CONFIGS / "rows_mass_fig5.toml"


@pytest.fixture
def overflowing(monkeypatch):
    """The rows calculator with an overflow injected: a design named "overflow" (and a sweep point with
    relative_width 2.2) gets an infinite K, as an input at the edge of its range once gave an infinite M (issue
    34: mass.efficiency = 5e-324, now refused by the schema). Everything else is the real calculator."""
    from gearcalc.kinds import rows

    calc = rows.CALCULATOR

    def spoil(d, res):
        if (d.name == "overflow" or d.get("rows.relative_width") == 2.2) and not isinstance(res, Exception):
            res.summary["K"] = np.float64(1e308) * 10  # inf, as numpy makes it (quietly here)
        return res

    def compute(d, opts):
        np.float64(1e308) * 10  # the RuntimeWarning numpy says on an overflow: it must not escape
        return spoil(d, calc.compute(d, opts))

    def batch(designs, opts):
        return [spoil(d, r) for d, r in zip(designs, calc.batch(designs, opts))] if calc.batch else None

    def sweep(base, raw, axes, points, options):
        cols = calc.sweep(base, raw, axes, points, options)
        if cols is not None:
            w = np.array([p["rows.relative_width"] for p in points])
            cols["K"] = np.where(w == 2.2, np.inf, cols["K"])
        return cols

    monkeypatch.setattr(rows, "CALCULATOR", dataclasses.replace(calc, compute=compute, batch=batch, sweep=sweep))


def _overflow_design(tmp_path):
    p = tmp_path / "over.toml"
    p.write_text(GOOD.read_text().replace('name = "Fig. 3 curve 4, B = 2.4"', 'name = "overflow"'))
    assert 'name = "overflow"' in p.read_text()
    return p


@pytest.mark.parametrize("fmt", ["json", "csv", "table"])
def test_nonfinite_output_is_that_designs_error_and_the_batch_goes_on(overflowing, tmp_path, fmt):
    bad = _overflow_design(tmp_path)
    r = cli("run", GOOD, bad, MASS, "--format", fmt)
    # exit 2 (interface.md "Exit codes": an input the calculation cannot carry), the other designs all emitted
    assert r.code == 2, r
    assert "Fig. 3 curve 4" in r.out and "Fig. 5, n = 2" in r.out and "overflow" not in r.out, r
    assert f"{bad}: K: the computed value is inf" in r.err and "no result for this design" in r.err, r
    assert "internal error" not in r.err and "Traceback" not in r.err and "RuntimeWarning" not in r.err, r
    if fmt == "json":
        assert [o["name"] for o in json.loads(r.out)] == ["Fig. 3 curve 4, B = 2.4", "Fig. 5, n = 2"]


def test_nonfinite_output_alone_and_one_by_one(overflowing, tmp_path):
    bad = _overflow_design(tmp_path)
    r = cli("rows", bad, "--format", "json")  # one design: the compute path, not the batch hook
    assert r.code == 2 and r.out == "" and "K: the computed value is inf" in r.err, r


def test_nonfinite_output_names_the_extreme_input(tmp_path):
    from gearcalc.calculator import Result
    from gearcalc.design import load
    from gearcalc.engine import finite_error

    p = tmp_path / "d.toml"
    p.write_text(MASS.read_text().replace("density_kg_m3 = 7800.0", "density_kg_m3 = 1e-200"))
    d = load(str(p))
    e = finite_error(d, Result(summary={"K": 1.0, "relative_mass_kg_per_kNm": float("nan")}))
    assert e.key == "relative_mass_kg_per_kNm" and "nan" in e.message and "mass.density_kg_m3 = 1e-200" in e.message
    assert finite_error(d, Result(summary={"K": 1.0}, detail={"rows": [{"w": 2.0}]})) is None
    e = finite_error(d, Result(summary={"K": 1.0}, detail={"rows": [{"w": 2.0}, {"w": float("-inf")}]}))
    assert e.key == "detail.rows.w"


def test_api_raises_the_design_error_and_no_warning_escapes(overflowing, tmp_path):
    import gearcalc

    with warnings.catch_warnings():
        warnings.simplefilter("error")  # a numpy RuntimeWarning would fail here
        with pytest.raises(gearcalc.DesignError, match="K: the computed value is inf"):
            gearcalc.compute(_overflow_design(tmp_path))
        assert gearcalc.compute(GOOD).summary["K"] > 1
        b = gearcalc.compute_files([GOOD, _overflow_design(tmp_path)])
    assert b.status == 2 and [r.name for r in b.records] == ["Fig. 3 curve 4, B = 2.4"]


@pytest.mark.parametrize("fmt", ["csv", "json", "table"])
def test_sweep_point_with_a_nonfinite_output_is_its_error_and_the_sweep_goes_on(overflowing, fmt):
    # interface.md "Exit codes" and man page `sweep`: the point's outputs empty, its message on stderr, exit 2
    r = cli("sweep", GOOD, "--vary", "rows.relative_width=2.0,2.2,2.4", "--format", fmt)
    assert r.code == 2, r
    assert "at {'rows.relative_width': 2.2}: K: the computed value is inf" in r.err, r
    assert "internal error" not in r.err and "Traceback" not in r.err, r
    if fmt == "csv":
        lines = r.out.splitlines()
        assert len(lines) == 4 and lines[2].startswith("2.2,") and set(lines[2][4:]) == {","}, lines
        assert lines[1].startswith("2.0,") and lines[3].startswith("2.4,") and "inf" not in r.out
    elif fmt == "json":
        rows = json.loads(r.out)
        assert [p["rows.relative_width"] for p in rows] == [2.0, 2.2, 2.4]
        assert rows[1]["K"] is None and rows[0]["K"] > 1 and rows[2]["K"] > 1


def test_sweep_api_chunk_carries_the_point_errors(overflowing):
    import gearcalc

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        parts = list(gearcalc.sweep(GOOD, {"rows.relative_width": [2.0, 2.2, 2.4]}))
    assert len(parts) == 1 and parts[0].data["K"][1] is None and parts[0].data["K"][0] > 1
    assert len(parts[0].errors) == 1 and "2.2" in parts[0].errors[0]


@pytest.mark.parametrize("fmt", ["csv", "json"])
def test_jobs_2_batch_and_sweep_carry_the_errors_from_the_workers(overflowing, tmp_path, fmt):
    # the workers are forked (the injected overflow goes with them): the same messages, rows and exit status
    bad = _overflow_design(tmp_path)
    one = cli("run", GOOD, bad, MASS, "--format", fmt)
    two = cli("run", GOOD, bad, MASS, "--format", fmt, "--jobs", "2")
    assert (two.code, two.out, two.err) == (one.code, one.out, one.err) and two.code == 2, two
    axis = ("--vary", "rows.relative_width=2.0,2.2,2.4,2.6")
    one = cli("sweep", GOOD, *axis, "--format", fmt)
    two = cli("sweep", GOOD, *axis, "--format", fmt, "--jobs", "2")
    assert (two.code, two.out, two.err) == (one.code, one.out, one.err) and two.code == 2, two
    assert two.err.count("the computed value is inf") == 1, two


def test_point_by_point_sweep_point_with_a_nonfinite_output(overflowing):
    # a design with [bridges] is swept point by point (man page `sweep`): the same empty row and message
    design = CONFIGS / "rows_bridges_n3_B3_i6.toml"
    r = cli("sweep", design, "--vary", "rows.relative_width=2.0,2.2,2.4", "--format", "json")
    assert r.code == 2 and "at {'rows.relative_width': 2.2}: K: the computed value is inf" in r.err, r
    rows = json.loads(r.out)
    assert [p["rows.relative_width"] for p in rows] == [2.0, 2.2, 2.4] and list(rows[1]) == list(rows[0])
    assert rows[1]["K"] is None and rows[1]["bridges_feasible"] is None and rows[0]["K"] > 1
