"""Tests of gearcalc.zstk.validity: the one vectorised rule set of check, compute, batch and sweep
(spec docs/spec/zstk.md §3.3, §9, §11.2).

Expected values: the conditions of §3.3 written out here, and the messages of the scalar helpers
(geometry_problems, chain_problems), which the vectorised rules must reproduce design by design.
"""
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from gearcalc import zstk as z
from gearcalc.zstk import validity as V

PAPER = (100.0, 50.0, 6.0, 6.0)  # Merko et al. worked example: R_H, R_B, e, c [mm]


def spec_geometry_ok(r_h, r_b, e, c):
    """§3.3 / §11.2 written out: R_H > R_B > 0, 0 <= e < R_H - R_B, e < (R_H + R_B)/sqrt 2, 0 <= c < 2 R_B."""
    return r_b > 0 and r_h > r_b and 0 <= e < r_h - r_b and e < (r_h + r_b) / math.sqrt(2) and 0 <= c < 2 * r_b


@settings(max_examples=200, deadline=None)
@given(st.floats(-10, 300), st.floats(-10, 300), st.floats(-10, 300), st.floats(-10, 300))
def test_geometry_rules_are_the_spec_conditions(r_h, r_b, e, c):
    # §3.3: valid exactly when no rule is violated; the scalar problems are the violated rules' messages
    bad = V.geometry_violations(r_h, r_b, e, c)
    assert (not any(bool(m) for m in bad.values())) == spec_geometry_ok(r_h, r_b, e, c)
    assert [k for k, _ in z.geometry_problems(r_h, r_b, e, c)] == [
        {"inner_positive": "inner", "inner_inside": "inner", "gap_range": "gap"}.get(r, "eccentricity")
        for r, m in bad.items() if m]


def test_geometry_rules_vectorised_equal_one_by_one():
    rng = np.random.default_rng(7)
    g = rng.uniform(-5, 150, size=(4, 500))
    vec = V.geometry_violations(*g)
    for k in range(g.shape[1]):
        one = V.geometry_violations(*g[:, k])
        assert {r: bool(m[k]) for r, m in vec.items()} == {r: bool(m) for r, m in one.items()}


def test_worked_example_is_valid():
    # the paper's example: N* = 8.254 -> N = 8 (scheme A, even), corrected R_H (§6)
    v = z.check_designs([PAPER[0]], PAPER[1], PAPER[2], PAPER[3], [0], [0], 0.0, "outer", 2000)
    assert v.valid.tolist() == [True] and v.n.tolist() == [8] and v.rules(0) == []
    assert v.problems(0, "A", "auto") == []


@pytest.mark.parametrize("geometry, rollers, parity, clearance, correct, rule", [
    ((100.0, 150.0, 6.0, 6.0), 0, 0, 0.0, "outer", "inner_inside"),        # §3.3 R_B < R_H
    ((100.0, 50.0, 60.0, 6.0), 0, 0, 0.0, "outer", "eccentricity_range"),  # §3.3 e < D
    ((100.0, 50.0, 6.0, 200.0), 0, 0, 0.0, "outer", "gap_range"),          # §3.3 c < 2 R_B
    ((100.0, 50.0, 6.0, 6.0), 7, 0, 0.0, "outer", "parity"),               # §4.2 A needs an even N
    ((100.0, 50.0, 6.0, 6.0), 0, 0, 30.0, "outer", "clearance"),           # §9 |s| < r_min = 22
    ((100.0, 50.0, 6.0, 90.0), 0, 0, 0.0, "outer", "too_few"),             # N* = 2.6: no auto N >= 3
    ((100.0, 50.0, 6.0, 6.0), 40, -1, 0.0, "outer", "range"),              # §3.3 N < N_max = 31.94
    ((100.0, 50.0, 6.0, 6.0), 10, -1, 0.0, "gap", "range"),                # §3.3 N <= N_max = 9.x for "gap"
])
def test_each_rule(geometry, rollers, parity, clearance, correct, rule):
    v = z.check_designs(*([x] for x in geometry), [rollers], [parity], clearance, correct, 2000)
    assert v.valid.tolist() == [False]
    assert v.rules(0) == [rule]
    assert len(v.problems(0, "A", rollers or "auto")) == 1


def test_first_stage_reports_every_violation():
    # §9: the geometry and parity problems of one design are all reported together
    v = z.check_designs([100.0], [50.0], [60.0], [200.0], [7], [0], 0.0, "outer", 2000)
    assert v.rules(0) == ["eccentricity_range", "gap_range", "parity"]
    assert [q for q, _ in v.problems(0, "A", 7)] == ["eccentricity", "gap", "rollers"]


def test_too_many_rollers():
    # gearcalc's range: N <= max_rollers (here lowered to 5 for the worked example's N = 8)
    v = z.check_designs([100.0], [50.0], [6.0], [6.0], [0], [-1], 0.0, "outer", 5)
    assert v.rules(0) == ["too_many"]


def test_chain_problems_match_the_stacked_rules():
    # the scalar message of a corrected chain is the stacked rule's message (one rule set)
    for n in (3, 8, 31, 32, 40):
        ch = z.close_chain(*PAPER, n)
        v = z.check_designs([PAPER[0]], PAPER[1], PAPER[2], PAPER[3], [n], [-1], 0.0, "outer", 2000)
        assert [m for _, m in v.problems(0, "cycle", n)] == [m for _, m in z.chain_problems(ch)]
        assert bool(v.valid[0]) == (z.chain_problems(ch) == [])


def test_allowable_stress_has_an_upper_bound_so_the_capacity_stays_finite():
    # issue 34 fuzz: allowable_stress_MPa = 1e308 made radial_load_allowable_N = inf (Q_allow grows as [sigma_H]^2,
    # zstk.md §5.4); the schema bounds it at 1e6 MPa (zstk.md §5.4), in check and run alike
    from conftest import CONFIGS, cli

    for cmd in ("check", "run"):
        r = cli(cmd, CONFIGS / "zstk_merko_A_inner.toml", "--set", "material.allowable_stress_MPa=1e308")
        assert r.code == 2 and "material.allowable_stress_MPa" in r.err and "<= 1e+06" in r.err, r
    r = cli("run", CONFIGS / "zstk_merko_A_inner.toml", "--set", "material.allowable_stress_MPa=1e6",
            "--format", "json")
    assert r.code == 0, r


def test_checking_an_extreme_radius_says_no_numpy_warning():
    # issue 34 fuzz: outer_raceway_radius_mm = 1e-320 printed numpy's "overflow encountered in divide" while the
    # check said its error; no numpy warning ever escapes (interface.md "Output"): as errors here, one would be exit 70
    import warnings

    from conftest import CONFIGS, cli

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        r = cli("check", CONFIGS / "zstk_merko_C_inner.toml", "--set", "geometry.outer_raceway_radius_mm=1e-320")
    assert r.code == 2 and "must be < outer_raceway_radius_mm" in r.err and "internal error" not in r.err, r
