"""Tests of gearcalc.explore.evaluate: sampled points evaluated for the explorers, a point that is not a valid design
kept as an empty row with its message, the same numbers in one process and in --jobs workers.

Where the expected values come from: rows.md's root diameter (z - 2.5) m, which a bore must stay under (the
sun of 18 teeth takes a bore of 60 mm only for m > 60/15.5); each valid point computed alone (gearcalc.compute).
"""
import copy
import tomllib

import pytest

import gearcalc
from conftest import CONFIGS
from gearcalc.calculator import Options
from gearcalc.explore.evaluate import Evaluator
from gearcalc.grid import Sample

ROWS = CONFIGS / "rows_fig3_c4_n3_nw3_B2.8.toml"


def test_invalid_designs_are_infeasible_and_the_search_goes_on():
    # a bore of 60 mm is valid only for modules above 60/15.5 (root diameter (z - 2.5) m, rows.md): the points
    # below are not designs, yet the search goes on among the others
    r = gearcalc.optimize(ROWS, {"gear.module_mm": (2.0, 6.0)}, "w_max_N_per_mm:max", overrides={"sun.bore_mm": 60},
                          budget=32)
    assert r.optimum["gear.module_mm"] > 60 / 15.5


@pytest.mark.slow
def test_jobs_give_the_same_optimum():
    vary = {"rows.relative_width": (1.6, 3.0), "rows.count": (2, 5)}
    one = gearcalc.optimize(ROWS, vary, "w_max_N_per_mm:min", where=["K<=1.4"], budget=64)
    two = gearcalc.optimize(ROWS, vary, "w_max_N_per_mm:min", where=["K<=1.4"], budget=64, jobs=2)
    assert one.to_dict() == two.to_dict()


def test_an_invalid_point_is_an_empty_row_with_its_message_and_the_others_are_computed():
    raw = tomllib.loads(ROWS.read_text())
    raw["sun"]["bore_mm"] = 60.0
    modules = [6.0, 2.0, 5.0, 3.0, 4.5, 3.5]          # 60/15.5 = 3.87: 2, 3 and 3.5 leave no room for the bore
    with Evaluator(raw, str(ROWS), Options(), chunk=len(modules)) as ev:
        cols = ev(Sample({"gear.module_mm": modules})).lists().data
        assert ev.evaluations == len(modules)
    assert cols["gear.module_mm"] == modules            # in order, the invalid ones in place
    for k, m in enumerate(modules):
        if m < 60 / 15.5:
            assert "sun.bore_mm" in cols["error"][k] and cols["K"][k] is None
        else:
            d = copy.deepcopy(raw)
            d["gear"]["module_mm"] = m
            alone = gearcalc.compute(d).summary
            assert cols["error"][k] is None
            assert cols["K"][k] == alone["K"] and cols["w_max_N_per_mm"][k] == alone["w_max_N_per_mm"]
