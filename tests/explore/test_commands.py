"""Tests of gearcalc.explore.commands, the bodies of `gearcalc optimize` and `gearcalc sensitivity`: output formats,
--save (never clobbering), exit statuses, the did-you-mean of bad words.

Where the expected values come from: pairwise Pareto dominance computed here; each saved design computed again;
the evaluation count of Saltelli's scheme, N (d + 2); the CSV header of interface.md.
"""
import json

import numpy as np
import pytest

import gearcalc
from conftest import CONFIGS, cli
from gearcalc.explore.optimize import non_dominated

ROWS = CONFIGS / "rows_fig3_c4_n3_nw3_B2.8.toml"


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


def test_no_feasible_point_exits_1():
    r = cli("optimize", ROWS, "--vary", "rows.relative_width=1.6:3", "--objective", "K:min", "--where", "K<1")
    assert r.code == 1 and "no feasible point" in r.err


@pytest.mark.parametrize("args, message", [
    (["--objective", "K:mini"], "did you mean 'min'"), (["--objective", "Kx:min"], "did you mean 'K'"),
    (["--objective", "K:min", "--where", "Kx<1"], "did you mean 'K'"),
])
def test_bad_objectives(args, message):
    r = cli("optimize", ROWS, "--vary", "rows.relative_width=1.6:3", "--budget", "4", *args)
    assert r.code == 2 and message in r.err


def test_command_table_and_json_and_morris():
    args = ["sensitivity", ROWS, "--vary", "rows.relative_width=1.6:3", "--vary", "rows.count=2:5", "--samples", "32",
            "--fields", "K"]
    r = cli(*args, "--format", "json")
    assert r.code == 0, r.err
    out = json.loads(r.out)
    assert out["method"] == "sobol" and set(out["dominant"]) == {"K"} and out["evaluations"] == 32 * 4
    r = cli(*args, "--method", "morris", "--format", "csv")
    assert r.code == 0 and r.out.splitlines()[0] == "field,key,mu_star,mu_star_conf,sigma,mu"
    r = cli(*args, "--method", "morriss")
    assert r.code == 2 and "did you mean 'morris'" in r.err
    r = cli(*args[:-1], "Kx")
    assert r.code == 2 and "did you mean 'K'" in r.err
