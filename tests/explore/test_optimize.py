"""optimize: the optimum against a dense brute-force grid, integer keys, the Pareto front, --save."""
import tomllib

import numpy as np
import pytest
from conftest import CONFIGS

import gearcalc
from gearcalc.explore.designfile import with_values
from gearcalc.explore.optimize import non_dominated

ROWS = CONFIGS / "rows_fig3_c4_n3_nw3_B2.8.toml"


def _grid(axes):
    rows = [r for part in gearcalc.sweep(ROWS, axes) for r in part.rows()]
    return rows


@pytest.mark.slow
def test_constrained_optimum_matches_a_dense_grid():
    # minimise the peak line load with K <= 1.4: the wider the face and the more rows, the lower w_max but the
    # higher K, so the constraint is active; the reference is the best point of a 1e-4 grid of the width
    r = gearcalc.optimize(ROWS, {"rows.relative_width": (1.6, 3.0), "rows.count": (2, 5)}, "w_max_N_per_mm:min",
                          where=["K<=1.4"])
    grid = _grid({"rows.relative_width": [round(1.6 + k * 1e-4, 4) for k in range(14001)], "rows.count": [2, 3, 4, 5]})
    feasible = [g for g in grid if g["K"] <= 1.4]
    best = min(feasible, key=lambda g: g["w_max_N_per_mm"])
    same = sorted((g for g in feasible if g["rows.count"] == best["rows.count"]),
                  key=lambda g: g["rows.relative_width"])
    step = max(abs(a["w_max_N_per_mm"] - b["w_max_N_per_mm"]) for a, b in zip(same, same[1:]))  # one grid step
    assert r.optimum["rows.count"] == best["rows.count"]
    assert best["w_max_N_per_mm"] - step <= r.value <= best["w_max_N_per_mm"]  # at least as good, within a step
    assert r.outputs["K"] <= 1.4 and r.constraints[0]["active"] and r.converged
    assert r.error == 0.0  # rows' fields are closed forms (no *_err)
    assert r.evaluations > 256


@pytest.mark.slow
def test_integer_keys_only_find_the_best_combination():
    # every combination computed (a grid of 4 x 4) is the reference
    vary = {"rows.count": (2, 5), "rows.planets_per_row": (3, 6)}
    r = gearcalc.optimize(ROWS, vary, "w_max_N_per_mm:min", where=["K<=1.6"], budget=16)
    grid = _grid({"rows.count": [2, 3, 4, 5], "rows.planets_per_row": [3, 4, 5, 6]})
    best = min((g for g in grid if g["K"] <= 1.6), key=lambda g: g["w_max_N_per_mm"])
    assert r.optimum == {"rows.count": best["rows.count"], "rows.planets_per_row": best["rows.planets_per_row"]}
    assert r.value == best["w_max_N_per_mm"] and r.converged


def test_non_dominated_against_pairwise_comparison():
    F = np.random.default_rng(5).integers(0, 8, size=(200, 3)).astype(float)  # ties included
    expected = [not any(np.all(F[j] <= F[i]) and np.any(F[j] < F[i]) for j in range(len(F))) for i in range(len(F))]
    assert non_dominated(F).tolist() == expected


def test_with_values_keeps_comments_and_adds_missing_keys():
    text = "kind = \"rows\"  # k\n[rows]\ncount = 3  # the rows\n\n[sun]\ntorque_Nm = 1.0\n"
    out = with_values(text, {"rows.count": 4, "rows.relative_width": 2.5, "mass.efficiency": 0.9})
    assert "count = 4  # the rows" in out and "kind = \"rows\"  # k" in out
    assert tomllib.loads(out) == {"kind": "rows", "rows": {"count": 4, "relative_width": 2.5},
                                  "sun": {"torque_Nm": 1.0}, "mass": {"efficiency": 0.9}}


def test_starts_sharing_a_combination_keep_the_best_runs_outcome():
    # without integer keys every start refines the same (empty) combination: its outcome is the run that
    # found the best point (the last run used to overwrite it), and runs that tie succeed if one did
    from gearcalc.explore.optimize import _keep

    runs = {}
    _keep(runs, (), (True, "ok", 1.0))
    _keep(runs, (), (False, "line search", 2.0))  # a worse run later: ignored
    assert runs[()] == (True, "ok", 1.0)
    _keep(runs, (), (False, "line search", 1.0 - 1e-12))  # the same optimum to 1e-9: still converged
    assert runs[()][0] is True
    _keep(runs, (), (False, "line search", 0.5))  # a better point found by a failed run: not converged
    assert runs[()] == (False, "line search", 0.5)
