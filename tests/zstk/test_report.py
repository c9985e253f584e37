"""Tests of gearcalc.zstk.report, the words and fields of the zstk calculator (zstk.md §10): the margins and
failed_checks, angles in degrees, the cost refusal.

Where the expected numbers come from: 1 - sigma_max/[sigma_H] and 1 - |s|/r_min from the summary's own fields;
the old flag ``pass``; the angle identity deg = rad * 180/pi modulo 360 (math.remainder, not the package's wrap).
"""
import math
import random

import numpy as np
import pytest

import gearcalc
from conftest import CONFIGS
from gearcalc import registry
from gearcalc.zstk import report as R


def negatives(summary, kind):
    return [c.name for c in registry.get(kind).checks if summary.get(c.field) is not None and summary[c.field] < 0]


def agrees_with_flags(s):
    """The old flag ``pass`` of the summary ``s`` against the sign of margin_sigma; the validity rules' margins."""
    assert s["pass"] == (s["margin_sigma"] >= 0)
    assert s["margin_closure"] >= 0 and s["margin_clearance"] >= 0  # validity rules: a computed design is inside
    assert s["failed_checks"] == negatives(s, "zstk")


def test_zstk_margins_value_and_sign_on_a_seeded_random_set():
    # 200 random designs around the worked example; the allowable stress straddles sigma_max so both signs occur
    rng = random.Random(36)
    for _ in range(40):
        over = {"load.radial_N": rng.uniform(1e3, 3e5), "load.clearance_mm": rng.uniform(-0.01, 0.01),
                "geometry.eccentricity_mm": rng.uniform(1.0, 10.0)}
        allow = [rng.uniform(300.0, 3000.0) for _ in range(5)]
        (part,) = gearcalc.sweep(CONFIGS / "zstk_merko_example.toml", {"material.allowable_stress_MPa": allow},
                                 overrides=over)
        for s in part.rows():
            agrees_with_flags(s)
            # independent: 1 - sigma_max/[sigma_H] from the two fields the summary prints
            assert s["margin_sigma"] == pytest.approx(1 - s["sigma_max_MPa"] / s["allowable_stress_MPa"], rel=1e-12,
                                                      abs=1e-15)
            assert s["margin_clearance"] == pytest.approx(1 - abs(s["clearance_mm"]) / s["r_min_mm"], rel=1e-12)


def test_wrap_deg_is_the_angle_modulo_a_turn_in_the_half_open_interval():
    # independent: math.remainder(deg, 360) lies in [-180, 180]; -180 is shown as 180 (the interval (-180, 180])
    x = np.array([0.0, -0.0, 1.0, -1.0, math.pi, -math.pi, 3 * math.pi, -1.5 * math.pi, 7.5, -100.0, 1e3, 2 * math.pi])
    got = R.wrap_deg(x)
    want = np.array([math.remainder(math.degrees(v), 360.0) for v in x])
    want[want <= -180.0 + 1e-9] = 180.0
    assert np.allclose(got, want, rtol=1e-12, atol=1e-9)
    assert np.all((got > -180.0) & (got <= 180.0))
    assert not np.signbit(got[1])                                # -0.0 shown as 0
    assert float(R.wrap_deg(-math.pi)) == 180.0 == float(R.wrap_deg(math.pi))


def test_cost_message_names_the_sweeps_the_count_and_the_budget():
    text = R.cost_message(2000, 2000, True, False, False, 1.234e8, 6e6)
    assert text.startswith('= 2000: N = 2000 rollers with geometry.scheme = "cycle" need 1.23e+08 ')
    assert "over the budget of 6e+06" in text and "--model reference" not in text
    both = R.cost_message("auto", 1619, True, True, True, 8.08e7, 6e6)
    assert both.startswith('= "auto": N = 1619 rollers with geometry.scheme = "cycle" + load.direction_deg = '
                           '"envelope" at --model reference need 8.08e+07')
