"""--where: parsing (no eval), vectorised masks, and the filters of run and sweep (interface.md "Exploring")."""
import csv
import io
import json

import numpy as np
import pytest
from conftest import CONFIGS, cli

from gearcalc.explore.where import WhereError, mask, parse_where, slack

ROWS = CONFIGS / "rows_fig3_c4_n3_nw3_B2.8.toml"


@pytest.mark.parametrize("text, field, op, value", [
    ("K<=1.5", "K", "<=", 1.5), ("K < 2", "K", "<", 2.0), ("pass==true", "pass", "==", True),
    ("model != exact", "model", "!=", "exact"), ("w_max_N_per_mm>=1e2", "w_max_N_per_mm", ">=", 100.0),
    ('name=="a b"', "name", "==", "a b"),
])
def test_parse(text, field, op, value):
    (c,) = parse_where([text])
    assert (c.field, c.op, c.value) == (field, op, value)


@pytest.mark.parametrize("text", ["K=1", "K<<1", "K<=", "<=1", "model<exact", "pass>true", "K<=nan"])
def test_malformed_conditions_are_refused(text):
    with pytest.raises(WhereError, match="--where"):
        parse_where([text])


def test_user_text_is_never_evaluated():
    # a Python expression as VALUE is a word, and a word takes == and != only: nothing runs
    (c,) = parse_where(["model==__import__('os').getcwd()"])
    assert c.value == "__import__('os').getcwd()"
    with pytest.raises(WhereError):
        parse_where(["K<=__import__('os').getcwd()"])


def test_mask_over_lists_arrays_and_empty_values():
    conds = parse_where(["K<=1.5", "ok==true"])
    cols = {"K": np.array([1.0, 1.5, 1.6, np.nan]), "ok": [True, True, True, True]}
    assert mask(conds, cols).tolist() == [True, True, False, False]  # NaN (no value) fails
    assert mask(parse_where(["K>1"]), {"K": [None, 2, 0.5]}).tolist() == [False, True, False]
    assert mask(parse_where(["m!=x"]), {"m": ["x", "y", None]}).tolist() == [False, True, False]


def test_slack_is_relative_to_the_bound():
    assert slack(parse_where(["K<=2"])[0], [1.0, 3.0]).tolist() == [0.5, -0.5]  # (2 - K)/2
    assert slack(parse_where(["K>=4"])[0], [5.0]).tolist() == [0.25]  # (K - 4)/4
    assert slack(parse_where(["m==x"])[0], ["x"]) is None


def _csv(text):
    return list(csv.DictReader(io.StringIO(text)))


def test_sweep_where_keeps_exactly_the_rows_that_meet_it():
    grid = ["--vary", "rows.relative_width=1.6:3.0:0.05", "--vary", "rows.count=2,3,4"]
    every = _csv(cli("sweep", ROWS, *grid, "--format", "csv").out)
    kept = cli("sweep", ROWS, *grid, "--format", "csv", "--where", "K<=1.4", "--where", "rows.count>=3")
    assert kept.code == 0
    expected = [r for r in every if float(r["K"]) <= 1.4 and int(r["rows.count"]) >= 3]  # the filter by hand
    assert 0 < len(expected) < len(every)
    assert _csv(kept.out) == expected


def test_sweep_where_every_row_filtered_out():
    r = cli("sweep", ROWS, "--vary", "rows.relative_width=2,3", "--format", "json", "--where", "K<0")
    assert (r.code, json.loads(r.out)) == (0, [])
    r = cli("sweep", ROWS, "--vary", "rows.relative_width=2,3", "--format", "csv", "--where", "K<0", "--fields", "K")
    assert r.out == "rows.relative_width,K\n"


def test_where_names_an_unknown_field_with_a_suggestion():
    r = cli("sweep", ROWS, "--vary", "rows.relative_width=2,3", "--format", "csv", "--where", "Kx<=1")
    assert r.code == 2 and "--where Kx<=1: no such output field (did you mean 'K'?)" in r.err
    r = cli("run", ROWS, "--format", "csv", "--where", "Kx<=1")
    assert r.code == 2 and "did you mean 'K'?" in r.err


def test_run_where_filters_the_designs():
    files = sorted(CONFIGS.glob("rows_fig3_*.toml"))
    every = json.loads(cli("run", *files, "--format", "json").out)
    kept = json.loads(cli("run", *files, "--format", "json", "--where", "K<=1.5").out)
    assert [d["name"] for d in kept] == [d["name"] for d in every if d["summary"]["K"] <= 1.5]
    assert 0 < len(kept) < len(every)
