"""A duty cycle of operating points evaluated as one design (gearcalc.pins.duty; pins.md §8.3; issue 37 item 5).

Independent references: each row run alone and combined here by hand (ISO 281 for a varying load and speed: the rows'
P^p weighted by their revolutions t_i n_i; L10_h at the time-weighted mean speed; time-weighted efficiency and loss).
The bearing's life of one operating point: test_outputs.py. With the W mechanism (pins.md §4.10, §8.2) each row's
load holds its resultant.
"""
from __future__ import annotations

import copy
import json

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from typer.testing import CliRunner

from gearcalc import api
from gearcalc.cli import app
from gearcalc.pins.duty import DUTY_KEYS, duty_combine


from pins.test_output_mech import RATED
from pins.test_outputs import PAPER, run_json  # the paper design through the CLI, as JSON

runner = CliRunner()


DUTY = {"torque_Nm": [100.0, 50.0, 150.0], "crank_speed_rpm": [1000.0, 1500.0, 500.0], "time_share": [0.5, 0.3, 0.2]}


def duty_file(tmp_path, duty=DUTY, **tables):
    import tomllib

    import tomli_w

    raw = tomllib.loads(PAPER.read_text())
    raw["duty"] = duty
    raw.update(tables)
    p = tmp_path / "duty.toml"
    p.write_text(tomli_w.dumps(raw))
    return p


@pytest.mark.parametrize("mode", ["multiplier", "reducer"])
def test_duty_cycle_equals_a_hand_combination_of_per_row_runs(tmp_path, mode):
    """Each row run alone (--set load.torque_Nm, load.crank_speed_rpm), combined here by hand: ISO 281 for a varying
    load and speed weights the rows' P^p by their revolutions t_i n_i; L10_h at the time-weighted mean speed;
    efficiency and loss time-weighted; the largest contact stress and its (1-based) row."""
    C, p = 60_000.0, 10.0 / 3.0
    path = duty_file(tmp_path, bearing={"C_N": C}, contact={"face_width_mm": 10.0})
    r = runner.invoke(app, ["run", str(path), "--format", "json", "--set", f"load.mode={mode}"])
    assert r.exit_code in (0, 1), r.stderr
    s = json.loads(r.stdout)["summary"]
    rows = [run_json("--set", f"load.torque_Nm={T}", "--set", f"load.crank_speed_rpm={n}", "--set", f"load.mode={mode}",
                     "--set", f"bearing.C_N={C}", "--set", "contact.face_width_mm=10")["summary"]
            for T, n in zip(DUTY["torque_Nm"], DUTY["crank_speed_rpm"])]
    t, n = DUTY["time_share"], DUTY["crank_speed_rpm"]
    w = [ti * ni for ti, ni in zip(t, n)]
    P = (sum(wi * row["bearing_equivalent_load_N"] ** p for wi, row in zip(w, rows)) / sum(w)) ** (1 / p)
    n_mean = sum(w) / sum(t)
    assert s["duty_rows"] == 3
    assert s["duty_bearing_equivalent_load_N"] == pytest.approx(P, rel=1e-13)
    assert s["duty_bearing_L10_h"] == pytest.approx(1e6 / (60 * n_mean) * (C / P) ** p, rel=1e-12)
    assert s["duty_efficiency"] == pytest.approx(sum(ti * row["efficiency"] for ti, row in zip(t, rows)) / sum(t),
                                                 rel=1e-14)
    assert s["duty_loss_mean_W"] == pytest.approx(sum(ti * row["loss_mean_W"] for ti, row in zip(t, rows)) / sum(t),
                                                  rel=1e-13)
    stress = [row["contact_stress_max_MPa"] for row in rows]
    assert s["duty_contact_stress_max_MPa"] == max(stress)
    assert s["duty_contact_stress_max_row"] == stress.index(max(stress)) + 1 == 3     # the 150 N·m row
    # the design's own fields are its [load] point's, unchanged by the duty table
    own = run_json("--set", f"load.mode={mode}", "--set", f"bearing.C_N={C}", "--set", "contact.face_width_mm=10")
    assert s["efficiency"] == own["summary"]["efficiency"]
    assert s["bearing_L10_h"] == own["summary"]["bearing_L10_h"]


def test_duty_rows_of_unequal_length_are_refused_naming_the_keys(tmp_path):
    bad = dict(DUTY, time_share=[0.5, 0.5])
    r = runner.invoke(app, ["run", str(duty_file(tmp_path, bad))])
    assert r.exit_code == 2
    assert "duty.time_share" in r.stderr and "same length" in r.stderr


def test_a_duty_design_in_a_batch_equals_it_alone(tmp_path):
    path = duty_file(tmp_path, bearing={"C_N": 60_000.0})
    alone = json.loads(runner.invoke(app, ["run", str(path), "--format", "json"]).stdout)["summary"]
    r = runner.invoke(app, ["run", str(path), str(PAPER), "--format", "json"])
    assert r.exit_code in (0, 1), r.stderr
    both = json.loads(r.stdout)
    first = both[0]["summary"] if isinstance(both, list) else both
    for k in ("duty_bearing_L10_h", "duty_efficiency", "duty_loss_mean_W", "duty_bearing_equivalent_load_N"):
        assert first[k] == alone[k]




# ---------------------------------------------------------------- duty_combine, the pure function

def _row(eta, loss, F, stress, dF=0.0):
    return dict(efficiency=eta, efficiency_err=1e-9, loss_mean_W=loss, bearing_equivalent_load_N=F,
                bearing_equivalent_load_err_N=dF, contact_stress_max_MPa=stress)


def test_one_row_is_the_iso_281_life_of_that_row():
    # ISO 281: L10_h = 10^6/(60 n) (C/P)^p; one row is its own duty cycle (p = 3, C = 10 kN, P = 2 kN, 1500 rpm:
    # 10^6/90000 x 125 = 1388.9 h)
    from gearcalc.pins.duty import duty_combine

    d = duty_combine([_row(0.9, 10.0, 2000.0, 900.0, dF=2.0)], [1.0], [1500.0], 3.0, 10_000.0)
    assert d["duty_rows"] == 1 and d["duty_bearing_equivalent_load_N"] == pytest.approx(2000.0, rel=1e-15)
    assert d["duty_bearing_L10_h"] == pytest.approx(1e6 / (60 * 1500.0) * 5.0 ** 3, rel=1e-14)
    # the error carried to first order: dL/L = p dP/P (3 x 2/2000)
    assert d["duty_bearing_L10_h_err"] == pytest.approx(3 * d["duty_bearing_L10_h"] * 2.0 / 2000.0, rel=1e-14)
    assert (d["duty_efficiency"], d["duty_contact_stress_max_row"]) == (0.9, 1)


@settings(max_examples=50, deadline=None)
@given(st.lists(st.tuples(st.floats(0.01, 10.0), st.floats(1.0, 5000.0)), min_size=1, max_size=6),
       st.floats(0.5, 2e4), st.floats(1e-3, 1e3), st.sampled_from([3.0, 10.0 / 3.0]))
def test_equal_rows_give_that_row_whatever_the_shares_and_speeds(rows, F, scale, p):
    # identity: the p-mean of equal loads is that load, a weighted mean of equal efficiencies that efficiency; and
    # the shares are normalised (scaling them all changes nothing but the rounding)
    from gearcalc.pins.duty import duty_combine

    share, speed = [t for t, _ in rows], [n for _, n in rows]
    same = [_row(0.8, 12.5, F, 700.0) for _ in rows]
    d = duty_combine(same, share, speed, p, None)
    assert d["duty_bearing_equivalent_load_N"] == pytest.approx(F, rel=1e-12)
    assert d["duty_efficiency"] == pytest.approx(0.8, rel=1e-14)
    assert d["duty_loss_mean_W"] == pytest.approx(12.5, rel=1e-14)
    assert d["duty_bearing_L10_h"] is None                      # no rating, no life
    scaled = duty_combine(same, [t * scale for t in share], speed, p, None)
    assert scaled["duty_bearing_equivalent_load_N"] == pytest.approx(d["duty_bearing_equivalent_load_N"], rel=1e-12)


def test_a_self_locking_row_leaves_the_duty_efficiency_undefined():
    # pins.md §8.3: a row without an efficiency (self-locking) makes the time-weighted mean undefined, not a mean of
    # the others
    from gearcalc.pins.duty import duty_combine

    d = duty_combine([_row(0.9, 10.0, 2000.0, 900.0), _row(None, 30.0, 1000.0, 950.0)], [1.0, 1.0],
                     [1000.0, 1000.0], 3.0, 10_000.0)
    assert d["duty_efficiency"] is None and d["duty_loss_mean_W"] == 20.0
    assert (d["duty_contact_stress_max_MPa"], d["duty_contact_stress_max_row"]) == (950.0, 2)


# ---------------------------------------------------------------- with the W mechanism (§4.10, §8.2)
PAPER_W = {**RATED, "output": {"mechanism": "pins_in_holes", "holes": 8, "hole_circle_radius_mm": 35.0,
                                "pin_radius_mm": 6.0}}    # the paper's u = 10 cycloid, C = 100 kN (test_output_mech)
DUTY_W = {"torque_Nm": [50.0, 100.0, 150.0], "crank_speed_rpm": [2000.0, 1000.0, 500.0], "time_share": [2.0, 1.0, 1.0]}


def test_duty_with_the_mechanism_combines_the_rows_loads_by_hand():
    # each row alone (with the mechanism's resultant in its load), combined by ISO 281 by hand; p = 10/3
    d = copy.deepcopy(PAPER_W)
    d["duty"] = DUTY_W
    s = api.compute(d).summary
    rows = []
    for T, n in zip(DUTY_W["torque_Nm"], DUTY_W["crank_speed_rpm"]):
        r = copy.deepcopy(PAPER_W)
        r["load"].update(torque_Nm=T, crank_speed_rpm=n)
        rows.append(api.compute(r).summary)
    p = 10.0 / 3.0
    rev = [t * n for t, n in zip(DUTY_W["time_share"], DUTY_W["crank_speed_rpm"])]
    F_eq = (sum(w * r["bearing_equivalent_load_N"] ** p for w, r in zip(rev, rows)) / sum(rev)) ** (1 / p)
    n_mean = sum(rev) / sum(DUTY_W["time_share"])
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
