"""optimize: the optimum against a dense brute-force grid, integer keys, the Pareto front, --save."""
import json
import tomllib

import numpy as np
import pytest
from conftest import CONFIGS, cli

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


@pytest.mark.slow
def test_jobs_give_the_same_optimum():
    vary = {"rows.relative_width": (1.6, 3.0), "rows.count": (2, 5)}
    one = gearcalc.optimize(ROWS, vary, "w_max_N_per_mm:min", where=["K<=1.4"], budget=64)
    two = gearcalc.optimize(ROWS, vary, "w_max_N_per_mm:min", where=["K<=1.4"], budget=64, jobs=2)
    assert one.to_dict() == two.to_dict()


def test_non_dominated_against_pairwise_comparison():
    F = np.random.default_rng(5).integers(0, 8, size=(200, 3)).astype(float)  # ties included
    expected = [not any(np.all(F[j] <= F[i]) and np.any(F[j] < F[i]) for j in range(len(F))) for i in range(len(F))]
    assert non_dominated(F).tolist() == expected


def test_front_is_non_dominated_and_saved_as_designs(tmp_path):
    out = tmp_path / "front"
    r = cli("optimize", ROWS, "--vary", "rows.relative_width=1.6:3", "--vary", "rows.count=2:5", "--objective",
            "K:min", "--objective", "w_max_N_per_mm:min", "--budget", "32", "--format", "json", "--save", out)
    assert r.code == 0, r.err
    front = json.loads(r.out)["front"]
    F = np.array([[m["K"], m["w_max_N_per_mm"]] for m in front])
    assert non_dominated(F).all() and len(front) > 2
    files = sorted(out.glob("*.toml"))
    assert len(files) == len(front)
    text = files[0].read_text()
    assert text.startswith("# Fig. 3 of seed 004")  # the original's comments kept
    again = gearcalc.compute(files[0])  # a ready design: the front member's values
    assert again.summary["K"] == front[0]["K"]
    r = cli("optimize", ROWS, "--vary", "rows.relative_width=1.6:3", "--objective", "K:min", "--save", out)
    assert r.code == 0 and (out / "rows_fig3_c4_n3_nw3_B2.8_opt.toml").exists()
    r = cli("optimize", ROWS, "--vary", "rows.relative_width=1.6:3", "--objective", "K:min", "--save", out)
    assert r.code == 2 and "never replaced" in r.err  # no clobbering


def test_with_values_keeps_comments_and_adds_missing_keys():
    text = "kind = \"rows\"  # k\n[rows]\ncount = 3  # the rows\n\n[sun]\ntorque_Nm = 1.0\n"
    out = with_values(text, {"rows.count": 4, "rows.relative_width": 2.5, "mass.efficiency": 0.9})
    assert "count = 4  # the rows" in out and "kind = \"rows\"  # k" in out
    assert tomllib.loads(out) == {"kind": "rows", "rows": {"count": 4, "relative_width": 2.5},
                                  "sun": {"torque_Nm": 1.0}, "mass": {"efficiency": 0.9}}


def test_no_feasible_point_exits_1_and_invalid_designs_are_infeasible():
    r = cli("optimize", ROWS, "--vary", "rows.relative_width=1.6:3", "--objective", "K:min", "--where", "K<1")
    assert r.code == 1 and "no feasible point" in r.err
    # a bore of 60 mm is valid only for modules above 60/15.5 (root diameter (z - 2.5) m, rows.md): the points
    # below are not designs, yet the search goes on among the others
    r = gearcalc.optimize(ROWS, {"gear.module_mm": (2.0, 6.0)}, "w_max_N_per_mm:max", overrides={"sun.bore_mm": 60},
                          budget=32)
    assert r.optimum["gear.module_mm"] > 60 / 15.5


@pytest.mark.parametrize("args, message", [
    (["--objective", "K:mini"], "did you mean 'min'"), (["--objective", "Kx:min"], "did you mean 'K'"),
    (["--objective", "K:min", "--where", "Kx<1"], "did you mean 'K'"),
])
def test_bad_objectives(args, message):
    r = cli("optimize", ROWS, "--vary", "rows.relative_width=1.6:3", "--budget", "4", *args)
    assert r.code == 2 and message in r.err


def test_api_raises_input_error_only():
    for kwargs in ({"objective": "K:sideways"}, {"objective": "K:min", "where": ["K=1"]}):
        with pytest.raises(gearcalc.InputError):
            gearcalc.optimize(ROWS, {"rows.relative_width": (1.6, 3.0)}, **kwargs)


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
