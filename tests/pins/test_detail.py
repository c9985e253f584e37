"""Tests of the per-element detail tables of a cycle (gearcalc.pins.detail; pins.md §8), through ``gearcalc.compute``.

Independent references: Coulomb's sliding loss P = f F v of each contact (fixed pins: the loss coefficient is the
sliding friction f, pins.md §4.6); the power's additivity (a crank angle's loss is the sum of its contacts'); the
loaded-pin count of the contacts table (one row per loaded contact); the bearing force's polar form
(|B| = hypot(B_r, B_t), the angle atan2); the crank table's span, one period 360/z2.
"""
import math
from collections import defaultdict

import numpy as np
import pytest

import gearcalc
from conftest import CONFIGS
from gearcalc.pins.detail import rows

FIRST_ORDER = {"friction.model": "first-order"}


@pytest.fixture(scope="module", params=["multiplier", "reducer"])
def tables(request):
    r = gearcalc.compute(CONFIGS / "pins_paper_cyc_u10_fixed.toml", detail=True,
                         overrides={**FIRST_ORDER, "load.mode": request.param})
    return r.detail["crank"], r.detail["contacts"]


def test_each_contacts_loss_is_coulombs_and_the_crank_angles_loss_their_sum(tables):
    crank, contacts = tables
    f = 0.1                                             # friction.sliding of the design file, fixed pins
    by_theta = defaultdict(list)
    for c in contacts:
        assert c["loss_W"] == pytest.approx(f * c["force_N"] * c["sliding_speed_m_s"], rel=1e-12, abs=1e-12)
        by_theta[c["theta_deg"]].append(c)
    seen = 0
    for row in crank:
        here = by_theta.get(row["theta_deg"])
        if here is None or sum(1 for r in crank if r["theta_deg"] == row["theta_deg"]) > 1:
            continue                                   # a jump: the angle is held twice (both sides)
        assert row["loss_W"] == pytest.approx(math.fsum(c["loss_W"] for c in here), rel=1e-9)
        assert row["loaded_pins"] == len(here)        # one contacts row per loaded pin of the first disc
        seen += 1
    assert seen > len(crank) // 2


def test_the_bearing_force_is_its_components_in_polar_form(tables):
    crank, _ = tables
    for row in crank:
        assert row["bearing_force_N"] == pytest.approx(math.hypot(row["bearing_radial_N"], row["bearing_tangential_N"]),
                                                       rel=1e-12)
        assert row["bearing_angle_deg"] == pytest.approx(
            math.degrees(math.atan2(row["bearing_tangential_N"], row["bearing_radial_N"])), abs=1e-9)
    th = np.array([r["theta_deg"] for r in crank])
    assert np.all(np.diff(th) >= 0) and th[-1] - th[0] == pytest.approx(360.0 / 22, rel=1e-12)   # one period 360/z2


def test_rows_of_columns():
    assert rows({"a": np.array([1.5, 2.0]), "b": None, "c": [True, False]}) == \
        [{"a": 1.5, "b": None, "c": True}, {"a": 2.0, "b": None, "c": False}]
