"""--sample: integer keys, bounds, determinism, and the same rows on one process, in chunks and with --jobs."""
import csv
import io

import numpy as np
import pytest
from conftest import CONFIGS, cli

import gearcalc
from gearcalc.explore.api import sample
from gearcalc.explore.sample import SampleError, parse_ranges, parse_sampler, unit_sample

ROWS = CONFIGS / "rows_fig3_c4_n3_nw3_B2.8.toml"
RAW = {"kind": "rows"}


@pytest.mark.parametrize("sampler", ["sobol", "lhs", "random"])
def test_the_same_seed_gives_the_same_points(sampler):
    a = unit_sample(sampler, 64, 3, seed=7)
    assert np.array_equal(a, unit_sample(sampler, 64, 3, seed=7))
    assert not np.array_equal(a, unit_sample(sampler, 64, 3, seed=8))
    assert a.min() >= 0 and a.max() < 1


def test_latin_hypercube_strata():
    u = unit_sample("lhs", 50, 2, seed=0)
    for j in range(2):  # one point in each of the 50 strata of each axis (the definition of an LHS)
        assert sorted((u[:, j] * 50).astype(int).tolist()) == list(range(50))


@pytest.mark.parametrize("items, message", [
    (["rows.count=2.5:4"], "integer"), (["rows.relative_width=3:2"], "LO < HI"),
    (["rows.relative_widht=2:3"], "did you mean 'rows.relative_width'"), (["rows.count=0:3"], "rows.count"),
    (["rows.relative_width=2:3:0.1"], "LO:HI"), (["mass.ratio_range=1:2"], "not a number"),
])
def test_bad_ranges(items, message):
    with pytest.raises(SampleError, match=message):
        parse_ranges(items, RAW)


@pytest.mark.parametrize("spec", ["halton:8", "sobol:x", "sobol:0", "sobol:1000001"])
def test_bad_samplers(spec):
    with pytest.raises(SampleError, match="--sample"):
        parse_sampler(spec)


def test_chunks_and_jobs_give_the_same_rows():
    axes = sample(ROWS, {"rows.count": (2, 5), "rows.relative_width": (1.6, 3.0)}, "sobol", 300, seed=2)
    whole = [r for part in gearcalc.sweep(ROWS, axes) for r in part.rows()]
    chunked = [r for part in gearcalc.sweep(ROWS, axes, chunk=7) for r in part.rows()]
    assert whole == chunked
    args = ["sweep", ROWS, "--vary", "rows.count=2:5", "--vary", "rows.relative_width=1.6:3", "--sample",
            "sobol:300", "--seed", "2", "--format", "csv"]
    one, two = cli(*args), cli(*args, "--jobs", "2")
    assert one.code == two.code == 0 and one.out == two.out
    got = list(csv.DictReader(io.StringIO(one.out)))
    assert [float(r["K"]) for r in got] == [r["K"] for r in whole]


def test_sweep_sample_options_are_checked():
    r = cli("sweep", ROWS, "--vary", "rows.relative_width=2:3", "--sample", "sobel:8")
    assert r.code == 2 and "did you mean 'sobol'" in r.err
