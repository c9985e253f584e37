"""The pins batch hook and the vectorised sweep (issue 6; gearcalc.pins.points: many operating points at once, through
the kinds/pins adapter): the same results as ``compute`` design by design.

Expected values here are ``compute`` itself (the contract of ``batch`` and ``sweep``: identical to one
design at a time) and the point-by-point evaluation of ``gearcalc sweep``.
"""
import csv
import io
import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from typer.testing import CliRunner

from gearcalc import design as dmod
from gearcalc import registry
from gearcalc import grid as sw
from gearcalc.calculator import DesignError, Options
from gearcalc.cli import app
from kinds.test_pins import BASE, CONFIGS, changed


PINS = registry.get("pins")
runner = CliRunner()
# these tests pin the first-order model's numbers (pins.md §4.6-4.7; the default is the friction-consistent model
# of §4.9, tests/pins/test_consistent.py): BASE says friction.model = "first-order", and so do the shipped designs here
FIRST_ORDER = [("friction.model", "first-order")]


def _read(src):
    """A shipped design's table with friction.model = "first-order"."""
    raw = dmod.read_toml(src)
    dmod.apply_set(raw, FIRST_ORDER)
    return raw


def make(**changes):
    """A validated design: BASE with changes {"table__key": value} (None deletes).

    A gear that only check()'s admissibility refuses (too few teeth, undercut; issue 13) is built without
    that check, so that the batch hook's own handling of inadmissible gears stays tested."""
    raw = changed(BASE, changes)
    try:
        return dmod.validate(raw, "mem.toml")
    except dmod.InputError:
        from unittest import mock

        from gearcalc.kinds import pins as kp

        with mock.patch.object(kp, "admissibility_problem", lambda design, level: None):
            return dmod.validate(raw, "mem.toml")


PIN_LOAD = {"pin_load__normal_force_N": 1920.0, "pin_load__pin_speed_rpm": 14.0, "pin_load__pin_radius_mm": 1.95,
            "pin_load__axle_radius_mm": 0.95}
VARIANTS = [
    {}, {"gearing__pins": 21}, {"gearing__pins": 23},
    {"gearing__satellite_teeth": 198, "gearing__pins": 200, "gearing__eccentricity_mm": 1.0},
    {"gearing__curtate_ratio": 1 - 1e-9, "gearing__pin_radius_mm": 1e-4, "gearing__pins": 21,
     "gearing__rotating_pins": True, "gearing__axle_radius_mm": 5e-5, "friction__rolling_mm": 1e-6},
    {"gearing__discs": 2}, {"gearing__discs": 3}, {"load__mode": "reducer"}, {"load__torque_shaft": "V"},
    {"load__crank_speed_rpm": None}, {"gearing__rotating_pins": True},
    {"gearing__rotating_pins": True, "friction__sliding": 0.001},            # rolling condition fails
    {"friction__sliding": 1.5},                                                # self-locking
    {"friction__sliding": 0.0, "friction__rolling_mm": 0.0, "friction__axle": 0.0},
    {"gearing__satellite_teeth": 3, "gearing__pins": 12, "gearing__pin_radius_mm": 0.5},   # too few teeth
    {"gearing__curtate_ratio": 0.99, "gearing__pin_radius_mm": 3.0},                       # undercut
    {"gearing__curtate_ratio": None, "gearing__pin_circle_radius_mm": 60.0},
    {"gearing__eccentricity_mm": 1e-6, "gearing__curtate_ratio": None, "gearing__pin_circle_radius_mm": 57.2},
    PIN_LOAD, {"contact__face_width_mm": 10.0},                                # contact level (or --model ideal)
]
DESIGNS = [make(**v) for v in VARIANTS] + [dmod.load(str(CONFIGS / f), FIRST_ORDER) for f in (
    "pins_paper_cyc_u10_fixed.toml", "pins_paper_cyc_u30_rotating.toml", "pins_paper_formula_cyc_u10.toml",
    "pins_paper_formula_circ_u30.toml")]


def _outcome(design, options):
    try:
        return PINS.compute(design, options)
    except Exception as exc:  # noqa: BLE001
        return exc


def _assert_same(got, ref):
    if isinstance(ref, BaseException):
        assert type(got) is type(ref) and str(got) == str(ref)
        return
    assert not isinstance(got, BaseException), got
    drop = ("model_time_ms",)
    assert {k: v for k, v in got.summary.items() if k not in drop} == \
        {k: v for k, v in ref.summary.items() if k not in drop}
    assert list(got.summary) == list(ref.summary)
    assert (got.warnings, got.failed, got.model, got.labels) == (ref.warnings, ref.failed, ref.model, ref.labels)
    assert got.detail == ref.detail


@pytest.mark.parametrize("model,detail", [("ideal", False), ("ideal", True), ("formula", False), (None, False)])
def test_batch_equals_compute_design_by_design(model, detail):
    # every summary field, warning, failed check, label and detail table, bit for bit; errors as compute
    # raises them (--model ideal on a [contact] design: the ideal level with a warning)
    designs = DESIGNS[:-5] + DESIGNS[-4:] if model is None else DESIGNS   # the contact level once (slow)
    options = Options(tol=1e-6, model=model, detail=detail)
    out = PINS.batch(designs, options)
    assert len(out) == len(designs)
    for d, got in zip(designs, out):
        _assert_same(got, _outcome(d, options))


def test_batch_equals_compute_where_a_scalar_square_would_round_otherwise():
    # curtate ratios where numpy's scalar (1 - K1) ** 2 is not the product (test_pins.POW_SENSITIVE_K1): one
    # design alone (scalar bookkeeping) and in a batch give the same numbers, bit for bit
    from pins.test_geometry import POW_SENSITIVE_K1

    designs = [make(gearing__curtate_ratio=K1, gearing__pin_radius_mm=1.0, **extra) for K1 in POW_SENSITIVE_K1
               for extra in ({}, {"gearing__satellite_teeth": 60, "gearing__pins": 62, "load__mode": "reducer"})]
    options = Options(tol=1e-6, model="ideal")
    for d, got in zip(designs, PINS.batch(designs, options)):
        _assert_same(got, _outcome(d, options))


def test_batch_errors_are_returned_not_raised():
    out = PINS.batch([DESIGNS[14], DESIGNS[0], DESIGNS[15]], Options(model="ideal"))
    assert isinstance(out[0], DesignError) and out[0].key == "gearing.satellite_teeth"
    assert isinstance(out[2], DesignError) and out[2].key == "gearing.pin_radius_mm" and "undercut" in out[2].message
    assert out[1].summary["model"] == "ideal"
    bad = PINS.batch([make(gearing__profile="circular", contact__face_width_mm=10.0), DESIGNS[0]],
                     Options(model="ideal"))
    assert isinstance(bad[0], DesignError) and "conjugate (cycloidal)" in bad[0].message


def test_batch_model_time_is_the_groups_time_per_design():
    out = PINS.batch(DESIGNS[:4] + DESIGNS[-4:], Options())
    ideal = {r.summary["model_time_ms"] for r in out if r.model == "ideal"}
    formula = {r.summary["model_time_ms"] for r in out if r.model == "formula"}
    assert len(ideal) == 1 and len(formula) == 1 and min(ideal) > 0


# ------------------------------------------------------------------ the vectorised sweep

SRC = str(CONFIGS / "pins_paper_cyc_u10_fixed.toml")


def _sweep_rows(axes, src=SRC, options=None, raw=None):
    raw = _read(src) if raw is None else raw
    out = sw.evaluate(raw, src, axes, options or Options())
    return out.rows() if hasattr(out, "rows") else out


def _point(src, point, options, raw=None):
    import copy

    trial = copy.deepcopy(_read(src) if raw is None else raw)
    dmod.apply_set(trial, list(point.items()))
    return PINS.compute(dmod.validate(trial, src), options).summary


def _assert_rows_equal_points(axes, src=SRC, options=None, raw=None, vectorised=True):
    options = options or Options()
    base = dmod.validate(_read(src) if raw is None else raw, src)
    points = sw.grid_points(axes)
    assert (PINS.sweep(base, raw, axes, points, options) is not None) == vectorised
    rows = _sweep_rows(axes, src, options, raw)
    assert len(rows) == len(points)
    for point, row in zip(points, rows):
        ref = _point(src, point, options, raw)
        assert {k: row[k] for k in axes} == point
        for k, v in ref.items():
            if k == "model_time_ms":
                continue
            if isinstance(v, float):
                assert math.isclose(row[k], v, rel_tol=1e-12, abs_tol=1e-300), (point, k, row[k], v)
            else:
                assert row[k] == v, (point, k)


def test_operating_sweep_equals_point_by_point():
    _assert_rows_equal_points({"friction.sliding": [0.0, 0.04, 0.1, 1.5], "load.torque_shaft": ["H", "V"],
                               "load.mode": ["multiplier", "reducer"], "load.crank_speed_rpm": [10.0, 3000.0]})


def test_geometry_sweep_equals_point_by_point():
    _assert_rows_equal_points({"gearing.eccentricity_mm": [3.0, 3.5, 3.9], "gearing.curtate_ratio": [0.5, 0.75, 0.95]})
    _assert_rows_equal_points({"gearing.pins": [21, 22, 23], "gearing.pin_radius_mm": [1.0, 1.95],
                               "gearing.discs": [1, 2]})


def test_geometry_and_operating_sweep_equals_point_by_point():
    _assert_rows_equal_points({"gearing.eccentricity_mm": [3.5, 3.9], "friction.sliding": [0.05, 1.2],
                               "gearing.rotating_pins": [False, True], "load.mode": ["multiplier", "reducer"],
                               "gearing.axle_radius_mm": [0.5, 0.95], "pin_load.normal_force_N": [1000.0, 1920.0]},
                              src=str(CONFIGS / "pins_paper_cyc_u10_rotating.toml"),
                              raw={**_read(str(CONFIGS / "pins_paper_cyc_u10_rotating.toml")),
                                   "pin_load": {"normal_force_N": 1920.0, "pin_speed_rpm": 14.0,
                                                "pin_radius_mm": 1.95, "axle_radius_mm": 0.95}})


def test_formula_sweep_equals_point_by_point():
    src = str(CONFIGS / "pins_paper_formula_cyc_u10.toml")
    _assert_rows_equal_points({"pin_load.normal_force_N": [900.0, 1920.0], "friction.axle": [0.05, 0.1],
                               "pin_load.paper_pi": [False, True]}, src=src)


def test_sweeps_that_cannot_be_vectorised_fall_back():
    # the contact level, a key outside the vectorised set, and a grid with an invalid or inadmissible point
    _assert_rows_equal_points({"gearing.equidistant_mod_mm": [0.0]}, vectorised=False)
    base = dmod.load(SRC, FIRST_ORDER)
    for axes in ({"gearing.curtate_ratio": [0.75, 0.999999]},                     # undercut at the second
                 {"gearing.pins": [22, 40]},                                       # pins overlap at the second
                 {"gearing.satellite_teeth": [20, 22]}):                           # z2 <= z1 at the second
        assert PINS.sweep(base, {}, axes, sw.grid_points(axes), Options()) is None
    # the inadmissible point is a row with its reason, the other computed (issue 36 item 1)
    rows = _sweep_rows({"gearing.curtate_ratio": [0.75, 0.999999]})
    assert rows[0]["error"] is None and rows[0]["efficiency"] is not None
    assert "undercut" in rows[1]["error"] and rows[1]["efficiency"] is None


@settings(max_examples=60, deadline=None)
@given(z1=st.integers(2, 40), dz=st.integers(-1, 4), e=st.floats(0.5, 6.0), K1=st.floats(0.3, 1.1),
       Rb=st.floats(0.2, 9.0), rot=st.booleans(), r=st.floats(0.1, 3.0))
def test_vectorised_point_checks_agree_with_the_loader(z1, dz, e, K1, Rb, rot, r):
    # the sweep's array checks (kinds.pins._points_pass_checks) accept exactly the points the loader accepts,
    # apart from the ideal level's admissibility (too few teeth, undercut: check() runs pins.admissibility),
    # which the vectorised solve reports itself (its errors make the sweep fall back point by point)
    from unittest import mock

    from gearcalc.kinds import pins as kp

    raw = _read(SRC)
    raw["gearing"] = {**raw["gearing"], "satellite_teeth": z1, "pins": z1 + dz, "eccentricity_mm": e,
                      "curtate_ratio": K1, "pin_radius_mm": Rb, "rotating_pins": rot, "axle_radius_mm": r}
    try:
        with mock.patch.object(kp, "admissibility_problem", lambda design, level: None):
            dmod.validate(raw, SRC)
        ok = True
    except dmod.InputError:
        ok = False
    base = dmod.load(SRC, FIRST_ORDER)
    point = {f"gearing.{k}": v for k, v in raw["gearing"].items() if k != "profile"}
    assert kp._points_pass_checks(base, lambda key: [point.get(key, base.get(key))], 1, "ideal") == ok


def test_cli_geometry_sweep_equals_single_runs():
    fo = ("--set", "friction.model=first-order")
    r = runner.invoke(app, ["sweep", SRC, *fo, "--vary", "gearing.eccentricity_mm=3.5:3.9:0.2", "--format", "csv"])
    assert r.exit_code == 0, r.stderr
    rows = list(csv.DictReader(io.StringIO(r.stdout)))
    assert [float(x["gearing.eccentricity_mm"]) for x in rows] == [3.5, 3.7, 3.9]
    for row in rows:
        e = row["gearing.eccentricity_mm"]
        one = runner.invoke(app, ["pins", SRC, *fo, "--set", f"gearing.eccentricity_mm={e}", "--format", "csv"])
        assert one.exit_code == 0, one.stderr
        (ref,) = list(csv.DictReader(io.StringIO(one.stdout)))
        for k, v in ref.items():
            if k not in ("model_time_ms",) and k in row:
                assert row[k] == v, (k, row[k], v)


def test_the_ideal_level_modules_are_small_steps_with_parameter_objects():
    # issue 35 (benchmarks/code_shape.py's counts): no function of the ideal level's point modules takes more than 8
    # parameters (the gears, the friction, the operating point and the satellite's load travel as the parameter
    # objects of gearcalc.pins.operating) or is over 80 lines with its docstring, and no pins module imports a private
    # name (_x) of these modules
    import ast
    import pathlib

    import gearcalc

    pins = pathlib.Path(gearcalc.__file__).parent / "pins"
    modules = ("points", "outputs", "operating", "detail", "cycle", "columns", "speed_friction")
    for module in modules:
        for node in ast.walk(ast.parse((pins / f"{module}.py").read_text(encoding="utf-8"))):
            if not isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                continue
            a = node.args
            positional = a.posonlyargs + a.args
            params = len(positional) + len(a.kwonlyargs) + (a.vararg is not None) + (a.kwarg is not None) - (
                1 if positional and positional[0].arg in ("self", "cls") else 0)
            assert params <= 8, (module, node.name, params)
            assert node.end_lineno - node.lineno + 1 <= 80, (module, node.name)
    private = []
    for path in sorted(pins.glob("*.py")):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.ImportFrom) and node.level == 1 and node.module in modules \
                    and node.module != path.stem:
                private += [f"{path.stem} <- {node.module}.{a.name}" for a in node.names
                            if a.name.startswith("_") and not a.name.startswith("__")]
    assert private == []
