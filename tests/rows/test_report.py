"""Tests of gearcalc.rows.report, the words and fields of the rows calculator (rows.md §8, §13): the margins and
failed_checks, the columns of a sweep, the bridge hint's windows.

Where the expected numbers come from: ISO 6336-3's rim of 2.7 m under the roots (margin_rim = 1 - 2.7 m/t), the
old flag ``bridges_feasible``, each point computed alone; a window's bounds rounded inward (each printed bound lies
inside the window, within one unit of its last digit).
"""
import math
import random
import re

import numpy as np
import pytest

import gearcalc
from conftest import CONFIGS
from gearcalc import registry
from gearcalc.rows import report as R

NEGATIVE_TIE = math.nextafter(0.0, -1.0)  # the least negative float: a failing check at the exact tie


def negatives(summary, kind):
    return [c.name for c in registry.get(kind).checks if summary.get(c.field) is not None and summary[c.field] < 0]


def agrees_with_flags(s):
    """The old flag ``bridges_feasible`` of the summary ``s`` against the sign of margin_bridge_fit; the bore."""
    if "bridges_feasible" in s:
        assert s["bridges_feasible"] == (s["margin_bridge_fit"] >= 0)
    assert s["margin_bore"] >= 0
    assert s["failed_checks"] == negatives(s, "rows")


def test_rows_margins_value_and_sign_on_a_seeded_random_set():
    rng = random.Random(361)
    widths = sorted(rng.uniform(1.5, 5.0) for _ in range(12))
    bores = [0.0] + sorted(rng.uniform(10.0, 70.0) for _ in range(4))
    (part,) = gearcalc.sweep(CONFIGS / "rows_bridges_n4_B4_i4.toml", {"rows.relative_width": widths,
                                                                        "sun.bore_mm": bores,
                                                                        "rows.count": [3, 4]})
    rows = part.rows()
    signs = {True: 0, False: 0}
    for s in rows:
        agrees_with_flags(s)
        signs[s["bridges_feasible"]] += 1
        assert s["margin_bridge_fit"] not in (0.0, NEGATIVE_TIE)  # the ties' clamp is not what decides the sign
        bore = s["sun.bore_mm"]
        d_f = 18 * 5.0 - 2 * 1.25 * 5.0  # z_a m - 2.5 m (rows.md §2), the design's sun
        if bore == 0:
            assert s["margin_rim"] is None
        else:
            t = (d_f - bore) / 2
            assert s["margin_rim"] == pytest.approx(1 - 2.7 * 5.0 / t, rel=1e-12)  # ISO 6336-3: 2.7 m
            assert ("rim" in s["failed_checks"]) == (t < 2.7 * 5.0)
    assert signs[True] and signs[False]  # both outcomes are in the set
    # the same points one by one: the same margins and failed checks
    for s in rows[::17]:
        alone = gearcalc.compute(CONFIGS / "rows_bridges_n4_B4_i4.toml",
                                 overrides={k: s[k] for k in ("rows.relative_width", "sun.bore_mm", "rows.count")})
        for key in ("margin_bridge_fit", "margin_bore", "margin_rim", "failed_checks"):
            assert alone.summary[key] == pytest.approx(s[key], rel=1e-12) if isinstance(s[key], float) \
                else alone.summary[key] == s[key]
        assert bool(alone.failed) == bool(s["failed_checks"])


def test_a_sweep_column_is_none_exactly_where_undefined():
    plain = R.columns(4)
    values = np.array([1.5, 2.5, np.nan, 4.0])
    assert plain(values, ~np.isnan(values)) == [1.5, 2.5, None, 4.0]
    full = plain(values[[0, 1, 3, 3]])
    assert isinstance(full, np.ndarray) and full.tolist() == [1.5, 2.5, 4.0, 4.0]
    words = plain(np.array(["pitch"] * 4))
    assert words == ["pitch"] * 4 and all(w is words[0] for w in words)   # one str object: a constant column
    assert R.one(np.float64(2.5)) == 2.5 and type(R.one(np.float64(2.5))) is float and R.one(1.0, False) is None


def test_margin_fields_of_one_design_equal_the_sweep_columns():
    # the same margins through one() and columns(): the failed checks of each point are the negative margins
    bore = np.array([0.2, -0.1, 0.3])
    rim = np.array([np.nan, 0.4, -0.05])
    fit = [0.1, 0.2, -0.3]
    cols = R.margin_fields(fit, bore, rim, R.columns(3), 3)
    assert cols["failed_checks"] == [[], ["bore"], ["bridge_fit", "rim"]]
    assert cols["margin_rim"] == [None, 0.4, -0.05]
    for k in range(3):
        one = R.margin_fields(fit[k], bore[k], rim[k], R.one)
        assert one["failed_checks"] == cols["failed_checks"][k]
        assert one["margin_rim"] == cols["margin_rim"][k] and one["margin_bore"] == cols["margin_bore"][k]


@pytest.mark.parametrize("lo, hi", [(2.66562, 2.97387), (1.00012, 1.00031), (4.0000001, 4.0364), (0.123456, 9.87)])
def test_the_bridge_hint_rounds_its_window_inward(lo, hi):
    text = R.bridge_failure(["ok", "exceeds_max"], 134.26, (3, [(lo, hi)], None, []))
    assert "span 2 needs a stiffer bridge" in text and "(H_max = 134.3 mm)" in text
    a, b = map(float, re.search(r"from ([0-9.]+) to ([0-9.]+) \(rows.count = 3\)", text).groups())
    digits = len(re.search(r"from [0-9]+\.([0-9]+) ", text).group(1))
    assert lo <= a <= b <= hi                                     # inward: every printed width fits
    assert a - lo < 10.0 ** -digits and hi - b < 10.0 ** -digits  # and no more than one unit of the last digit
