"""gearcalc.pins.duty: a duty cycle evaluated as one design (issue 37 item 5, pins.md §8.3).

Expected values by hand: ISO 281's mean load of a varying load and speed (the rows weighted by the revolutions they
turn) from the rows run alone; with the W mechanism (pins.md §4.10, §8.2) each row's load holds its resultant.
"""
import copy

import pytest

from gearcalc import api
from gearcalc.pins.duty import DUTY_KEYS, duty_combine

PAPER = {   # the paper's u = 10 cycloid, fixed pins (configs/pins_paper_cyc_u10_fixed.toml, pins.md §10)
    "kind": "pins", "name": "paper u10 cycloid",
    "gearing": {"profile": "cycloidal", "satellite_teeth": 20, "pins": 22, "eccentricity_mm": 3.9,
                "curtate_ratio": 0.75, "pin_radius_mm": 1.95, "axle_radius_mm": 0.95, "rotating_pins": False},
    "friction": {"sliding": 0.1, "rolling_mm": 0.01, "axle": 0.1},
    "load": {"mode": "multiplier", "torque_shaft": "H", "torque_Nm": 100.0, "crank_speed_rpm": 1000.0},
    "bearing": {"C_N": 100000.0},
    "output": {"mechanism": "pins_in_holes", "holes": 8, "hole_circle_radius_mm": 35.0, "pin_radius_mm": 6.0},
}
DUTY = {"torque_Nm": [50.0, 100.0, 150.0], "crank_speed_rpm": [2000.0, 1000.0, 500.0], "time_share": [2.0, 1.0, 1.0]}


def test_duty_with_the_mechanism_combines_the_rows_loads_by_hand():
    # each row alone (with the mechanism's resultant in its load), combined by ISO 281 by hand; p = 10/3
    d = copy.deepcopy(PAPER)
    d["duty"] = DUTY
    s = api.compute(d).summary
    rows = []
    for T, n in zip(DUTY["torque_Nm"], DUTY["crank_speed_rpm"]):
        r = copy.deepcopy(PAPER)
        r["load"].update(torque_Nm=T, crank_speed_rpm=n)
        rows.append(api.compute(r).summary)
    p = 10.0 / 3.0
    rev = [t * n for t, n in zip(DUTY["time_share"], DUTY["crank_speed_rpm"])]
    F_eq = (sum(w * r["bearing_equivalent_load_N"] ** p for w, r in zip(rev, rows)) / sum(rev)) ** (1 / p)
    n_mean = sum(rev) / sum(DUTY["time_share"])
    assert s["duty_bearing_equivalent_load_N"] == pytest.approx(F_eq, rel=1e-12)
    assert s["duty_bearing_L10_h"] == pytest.approx(1e6 / (60 * n_mean) * (1e5 / F_eq) ** p, rel=1e-12)
    # the rows' loads hold the mechanism: larger than the same rows without it
    plain = copy.deepcopy(d)
    del plain["output"]
    assert s["duty_bearing_equivalent_load_N"] > 1.4 * api.compute(plain).summary["duty_bearing_equivalent_load_N"]


def test_a_row_without_a_load_leaves_the_bearing_fields_null():
    rows = [dict(efficiency=0.9, efficiency_err=0.0, loss_mean_W=1.0, bearing_equivalent_load_N=None,
                 bearing_equivalent_load_err_N=None, contact_stress_max_MPa=None)]
    out = duty_combine(rows, [1.0], [1000.0], 3.0, 1e4)
    assert set(out) == set(DUTY_KEYS)
    assert out["duty_bearing_equivalent_load_N"] is None and out["duty_bearing_L10_h"] is None
    assert out["duty_efficiency"] == 0.9 and out["duty_rows"] == 1
