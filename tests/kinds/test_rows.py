"""Tests of the rows adapter (gearcalc/kinds/rows.py): check, compute and the vectorised sweep apply the same
geometry and validity rules (one function each, gearcalc.rows.geometry), so a sweep point equals the design
computed alone."""
import pytest

import gearcalc

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
