"""Tests of the pins calculator's texts and field lists (gearcalc.pins.report; pins.md §8, §9): messages that name
the key and the constraint with the design's own numbers, and the plain values of the summary's fields.

Independent references: the budgets and rules of pins.md §4.2 and §9 re-derived by hand at each test; the exact
identity between the many-array and the one-array conversions of the fields.
"""
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

from gearcalc.pins import report as R


def test_contact_self_locking_text_reads():
    # before: "...§4.9): it the loss ratio 1.23881 >= 1" (k = 1 circular u10, pins = 21, f = 0.6, consistent)
    text = R.contact_self_locking("multiplier", False, 1.2388051276)
    assert "§4.9): the loss ratio 1.23881 >= 1 (the losses" in text and "it the" not in text
    assert "§4.9): it jams: no positive contact force" in R.contact_self_locking("reducer", True, math.inf)


def test_the_cost_problems_name_the_key_and_the_budget():
    # pins.md §9: the ideal level's budget is 200 000 pin-discs (z2 x n_d), the contact level's 1 500 000 contact
    # solves of 4352 crank angles x 3 passes with the torque on H (1 pass on V): 1 500 000 // 13 056 = 114 pins on H,
    # 1 500 000 // 4352 = 344 pins on V
    assert R.cost_problem("ideal", 10_000, 20, False) is None                   # 200 000: at the budget, allowed
    key, text = R.cost_problem("ideal", 10_000, 21, False)
    assert key == "gearing.discs" and "10000 x 21 = 210000" in text and "200000" in text
    assert R.cost_problem("contact", 114, 1, False) is None
    key, text = R.cost_problem("contact", 115, 1, False)
    assert key == "gearing.pins" and "at most 114 pins" in text
    assert R.cost_problem("contact", 344, 1, True) is None and R.cost_problem("contact", 345, 1, True)[0] == \
        "gearing.pins"


def test_too_few_teeth_names_the_loaded_arc_and_the_pin_pitch():
    # pins.md §4.2: the loaded arc psi* must exceed the pin pitch 360/z2 (z2 = 4: 90 deg); psi* = 1 rad = 57.2958 deg
    from gearcalc.pins.ideal import TOO_FEW_TEETH

    e = R.admissibility_error(TOO_FEW_TEETH, 2, 4, 1.0, 2.5, 0.0, 0.5)
    assert e.key == "gearing.satellite_teeth" and "k = 2" in e.message
    assert "psi* = 57.2958 deg" in e.message and "360/z2 = 90 deg" in e.message


@settings(max_examples=60, deadline=None)
@given(hnp.arrays(np.float64, st.integers(0, 6), elements=st.one_of(st.floats(allow_nan=True, allow_infinity=False),
                                                                     st.just(np.nan))),
       hnp.arrays(np.int64, st.integers(0, 6), elements=st.integers(-5, 5)))
def test_columns_equal_column_array_by_array(a, b):
    # identity: the block conversion of many float arrays equals the one-array one, NaN as None (undefined)
    n = min(a.size, b.size)
    a, b = a[:n], b[:n]
    out = R.columns({"x": a, "k": b, "y": -a}, n)
    assert list(out) == ["x", "k", "y"]
    assert out["x"] == R.column(a) and out["k"] == R.column(b) == b.tolist() and out["y"] == R.column(-a)
    assert [v is None for v in out["x"]] == np.isnan(a).tolist()
    assert all(R.plain(v) == w for v, w in zip(a, out["x"]) if w is not None)


def test_plain_values():
    assert R.plain(np.float64("nan")) is None and R.plain(np.bool_(True)) is True and R.plain(np.int32(7)) == 7
    assert type(R.plain(np.int64(3))) is int and type(R.plain(np.float32(0.5))) is float
    assert math.isinf(R.plain(np.inf))
    with pytest.raises((TypeError, ValueError)):
        R.plain("x")
