"""Tests of the rows adapter (gearcalc/kinds/rows.py): check, compute and the vectorised sweep apply the same
geometry and validity rules (one function each, gearcalc.rows.geometry), so a sweep point equals the design
computed alone."""
import copy
import itertools

import pytest

import gearcalc
from gearcalc.render import Columns

BASE = {"kind": "rows", "gear": {"sun_teeth": 18, "module_mm": 5.0},
        "rows": {"count": 3, "planets_per_row": 3, "relative_width": 2.4}, "sun": {"torque_Nm": 1e3}}
MASS_OPT = ("ratio_opt", "ratio_opt_err", "relative_mass_min_kg_per_kNm", "ratio_opt_on_bound")


def variant(**tables):
    d = {k: dict(v) if isinstance(v, dict) else v for k, v in BASE.items()}
    for table, values in tables.items():
        d[table] = {**d.get(table, {}), **values}
        for key, value in list(d[table].items()):
            if value is None:
                del d[table][key]
    return d


DESIGNS = {
    "B, b̄": variant(),
    "B, b in mm": variant(rows={"cheek_ratio": None, "cheek_mm": 12.0}),
    "b_w, b": variant(rows={"relative_width": None, "rim_width_mm": 50.0, "cheek_mm": 10.0}),
    "hollow root sun": variant(sun={"torsion_diameter": "root", "bore_mm": 30.0}),
    "mass, planet teeth": variant(gear={"planet_teeth": 27}, mass={}),
    "soft sun": variant(rows={"relative_width": 9.0}),
}


@pytest.mark.parametrize("name", list(DESIGNS))
@pytest.mark.parametrize("model", [None, "exact", "continuous"])
def test_sweep_point_equals_the_design_computed_alone(name, model):
    d = DESIGNS[name]
    alone = gearcalc.compute(d, model=model).summary
    (part,) = list(gearcalc.sweep(d, {"rows.count": [d["rows"]["count"]]}, model=model))
    for field, value in alone.items():
        if field == "name" or field in MASS_OPT:    # the batch golden section stops when every point converged
            continue
        assert part.data[field] == [value], field


def test_sweep_refuses_combinations_check_refuses():
    # each value alone passes check; a combination the sweep's batch of the same rules refuses, b_w > 0 (rows.md
    # §7) and d_0 < min(d_f, d_I) (rows.md §10), is a row with its reason (issue 36 item 1), the others computed
    (rows,) = gearcalc.sweep(DESIGNS["B, b in mm"], {"rows.relative_width": [2.4, 0.5], "rows.cheek_mm": [12.0, 40.0]})
    why = [r["error"] for r in rows.rows()]
    assert [w is None for w in why] == [True, True, True, False]  # B = 0.5 with b = 40 mm: b_w < 0
    assert why[3].startswith("rows.cheek_mm = 40.0: the cheeks leave no room for the rims")
    (rows,) = gearcalc.sweep(BASE, {"sun.bore_mm": [0.0, 60.0], "gear.module_mm": [5.0, 3.0]})
    why = [r["error"] for r in rows.rows()]
    assert [w is None for w in why] == [True, True, True, False] and why[3].startswith("sun.bore_mm = 60.0: must be <")
    assert rows.rows()[3]["K"] is None and rows.errors[0].startswith("at {'sun.bore_mm': 60.0, 'gear.module_mm': 3.0}")


# ---------------------------------------------------------------- the sweep with [bridges] evaluated as arrays
# (rows.md §9) gives, point for point, the design computed alone: the same columns in the same order, the same
# words, flags and empty cells, and the same floats to round-off, over a grid that holds every kind of point
# (feasible, capped, no room, κ ≥ 8, unloaded rows in the verification).
BRIDGES = {"kind": "rows", "gear": {"sun_teeth": 18, "module_mm": 5.0, "ratio": 6.0},
           "rows": {"count": 3, "planets_per_row": 3, "relative_width": 3.0}, "sun": {"torque_Nm": 1e3},
           "bridges": {}}


def alone(base, axes):
    rows = []
    for combo in itertools.product(*axes.values()):
        d = copy.deepcopy(base)
        for key, value in zip(axes, combo):
            table, _, name = key.partition(".")
            d[table][name] = value
        rows.append({**dict(zip(axes, combo)), **gearcalc.compute(d).summary})
    cols = Columns.from_rows(rows).data
    return Columns({**cols, "error": [None] * len(rows)})  # a sweep row's last column: why a point has no results


@pytest.mark.slow
def test_bridges_sweep_equals_each_point_alone():
    axes = {"rows.count": [1, 3, 4], "gear.ratio": [2.3, 4.0], "rows.planets_per_row": [3, 7],
            "bridges.first_span": ["axes_only", 0.1], "rows.relative_width": [0.4, 3.0, 40.0]}
    (part,) = list(gearcalc.sweep(BRIDGES, axes))
    want = alone(BRIDGES, axes)
    assert list(part.data) == list(want.data)  # the union of the columns in first-seen order (rows.md §13.5)
    got = part.lists().data
    for key, values in want.data.items():
        # floats to round-off: a design alone takes some powers in Python floats (pow), the arrays in numpy
        # (x*x), which differ in the last bit now and then (kappa, r_ba**2); the bridge arithmetic itself is one
        # function (size_bridges is size_bridges_batch of one design)
        assert [pytest.approx(v, rel=1e-12, abs=1e-12) if type(v) is float else v for v in values] == got[key], key
    # the grid holds every case (else the equality above would prove less)
    assert 0 < sum(got["bridges_feasible"]) < len(got["bridges_feasible"])
    assert any(h == 0.0 for h in got["bridge_max_mm"])                       # no room (H_max <= 0)
    assert any(k is None for k in got["K_balanced"])                         # κ >= 8 (rows.md §13.10)
    assert any(u for u in got["unloaded_rows_balanced"])                     # the active set dropped rows
    assert any(v is None for v in got["bridge_rel_4"])                       # n = 1, 3 have no span 4


def test_bridges_sweep_varies_the_bridge_keys_as_arrays():
    axes = {"bridges.torsion_diameter": ["root", "pitch", 80.0], "bridges.axle_diameter_mm": [20.0, 40.0],
            "rows.relative_width": [2.4, 3.0]}
    (part,) = list(gearcalc.sweep(BRIDGES, axes))
    want = alone(BRIDGES, axes)
    assert list(part.data) == list(want.data)
    for key, values in want.data.items():
        assert [pytest.approx(v, rel=1e-12, abs=1e-12) if type(v) is float else v for v in values] == \
            part.lists().data[key], key


def test_bridges_sweep_with_the_mass_of_the_balanced_rows():
    # mass.unevenness = "computed" takes K_balanced with [bridges] (rows.md §6): the arrays give it too
    base = {**BRIDGES, "mass": {"unevenness": "computed"}}
    axes = {"rows.relative_width": [2.4, 2.7, 3.0], "gear.ratio": [4.0, 6.0]}
    (part,) = list(gearcalc.sweep(base, axes))
    want = alone(base, axes)
    assert list(part.data) == list(want.data)
    for key, values in want.data.items():
        assert [pytest.approx(v, rel=1e-12, abs=1e-12) if type(v) is float else v for v in values] == \
            part.lists().data[key], key


def test_a_mistyped_step_is_refused_before_any_point_is_computed(monkeypatch, tmp_path):
    # issue 34: --vary rows.relative_width=1:1000:0.00001 is (1000 - 1)/1e-5 = 99 900 000 steps (99 900 000 points:
    # the stop lies 1e-8 of a step off the grid in floating point, beyond the parser's 1e-9); at the
    # vectorised bridges' estimate (kinds/rows.py sweep_cost: 10 us + 4 us a row, n = 3: 22 us) that is ~37 min,
    # over grid.SWEEP_SECONDS_MAX = 600 s: exit 2, the count and a coarser step, and no point evaluated
    from conftest import cli
    from gearcalc import grid, registry
    from gearcalc.template import template

    design = tmp_path / "new.toml"
    design.write_text(template(registry.get("rows")))  # `gearcalc new rows`: every template has [bridges]
    assert "[bridges]" in design.read_text()

    def never(*args, **kwargs):
        raise AssertionError("a point was computed")

    monkeypatch.setattr(grid, "evaluate_points", never)
    r = cli("sweep", design, "--vary", "rows.relative_width=1:1000:0.00001", "--format", "csv")
    assert r.code == 2 and r.out == ""
    assert "99900000 points" in r.err and "--vary rows.relative_width=1:1000:" in r.err and "coarser" in r.err
