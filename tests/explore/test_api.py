"""Tests of gearcalc.explore.api, the exploring functions of the Python API (sample, optimize, sensitivity).

Where the expected values come from: each sampled point computed alone (gearcalc.compute); the binomial spread of
400 draws over 4 equally likely integers; rows.md (K is a ratio of loads: it does not depend on the torque, exactly);
the API's promise that bad input raises gearcalc.InputError, a ValueError, and nothing else.
"""
import pytest

import gearcalc
from conftest import CONFIGS
from gearcalc.explore.api import sample

ROWS = CONFIGS / "rows_fig3_c4_n3_nw3_B2.8.toml"


def test_api_raises_input_error_only():
    for kwargs in ({"objective": "K:sideways"}, {"objective": "K:min", "where": ["K=1"]}):
        with pytest.raises(gearcalc.InputError):
            gearcalc.optimize(ROWS, {"rows.relative_width": (1.6, 3.0)}, **kwargs)


@pytest.mark.parametrize("sampler", ["sobol", "lhs", "random"])
def test_integer_keys_are_integers_over_the_whole_inclusive_range(sampler):
    s = sample(ROWS, {"rows.count": (2, 5), "rows.relative_width": (1.6, 3.0)}, sampler, 400, seed=3)
    counts, widths = s["rows.count"], s["rows.relative_width"]
    assert all(type(c) is int for c in counts) and set(counts) == {2, 3, 4, 5}  # LO and HI both drawn
    assert all(type(w) is float and 1.6 <= w <= 3.0 for w in widths)
    # equally likely: 400 points, 100 expected per value; 4 standard deviations (sqrt(400 * 1/4 * 3/4) = 8.7)
    assert all(abs(counts.count(v) - 100) < 35 for v in (2, 3, 4, 5))


def test_sampled_points_are_the_designs_computed_alone():
    axes = sample(ROWS, {"rows.count": (2, 5), "rows.relative_width": (1.6, 3.0)}, "sobol", 8, seed=1)
    rows = [r for part in gearcalc.sweep(ROWS, axes) for r in part.rows()]
    assert len(rows) == 8
    for r in rows[:4]:  # each point computed on its own (gearcalc.compute): the same K
        alone = gearcalc.compute(ROWS, overrides={k: r[k] for k in axes})
        assert r["K"] == alone.summary["K"]


def test_k_does_not_depend_on_the_torque():
    vary = {"rows.relative_width": (1.6, 3.0), "sun.torque_Nm": (500.0, 2000.0)}
    r = gearcalc.sensitivity(ROWS, vary, samples=64, fields=["K", "w_mean_N_per_mm"])
    by = {(i["field"], i["key"]): i for i in r.indices}
    assert by["K", "sun.torque_Nm"]["ST"] == 0.0 and by["K", "sun.torque_Nm"]["S1"] == 0.0  # exactly: K is unchanged
    assert r.dominant == {"K": "rows.relative_width", "w_mean_N_per_mm": "sun.torque_Nm"}
    assert r.evaluations == 64 * (2 + 2)
    assert len(r.to_dict()["indices"]) == 4


def test_a_box_of_invalid_designs_is_refused_with_the_designs_reason():
    # a bore of 60 mm needs a root diameter (z - 2.5) m = 15.5 m above it (rows.md): no module of [2, 3.5] takes
    # it, so no point is a design, and the refusal says why (it said "no such output field" when the sweep's
    # messages of its invalid points were dropped)
    with pytest.raises(gearcalc.InputError, match=r"no point of the sample is a valid design, e\.g\. sun\.bore_mm"):
        gearcalc.optimize(ROWS, {"gear.module_mm": (2.0, 3.5)}, "w_max_N_per_mm:max",
                          overrides={"sun.bore_mm": 60}, budget=8)


def test_sensitivity_says_how_many_points_are_not_designs():
    # modules in [2, 6] with a 60 mm bore: those below 60/15.5 = 3.87 are not designs (rows.md's root diameter);
    # Saltelli's scheme evaluates N (d + 2) = 8 x 4 = 32 points, some of each kind
    r = gearcalc.sensitivity(ROWS, {"gear.module_mm": (2.0, 6.0), "rows.relative_width": (1.6, 3.0)},
                             overrides={"sun.bore_mm": 60}, samples=8, fields=["K"])
    assert r.evaluations == 32
    (note,) = [n for n in r.notes if "not valid designs" in n]
    invalid = int(note.split(" of ")[0])
    assert 0 < invalid < 32 and "of 32 points are not valid designs (e.g. sun.bore_mm = 60" in note
