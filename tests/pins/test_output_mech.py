"""Tests of the output (W) mechanism and the crank's drag in the ideal level's summary (gearcalc.pins.output_mech;
pins.md §4.10; issue 37 items 3-4).

Independent references: power balances at the crank worked by hand (the teeth's loss of the run without the
mechanism, lambda_W = 4 f_w e (u + 1)/(pi R_w) of the classical W-mechanism analysis, the drag T_d omega_H); the
resultant's closed-form peak 4 T_sat/(n_w R_w sin(pi/n_w)); the start-up torque u T_d/eta_VH; the points of a sweep
computed one by one.
"""
import numpy as np
import pytest


PAPER = {   # configs/pins_paper_cyc_u10_fixed.toml
    "kind": "pins", "name": "paper u10 fixed",
    "gearing": {"profile": "cycloidal", "satellite_teeth": 20, "pins": 22, "eccentricity_mm": 3.9,
                "curtate_ratio": 0.75, "pin_radius_mm": 1.95, "axle_radius_mm": 0.95, "rotating_pins": False},
    "friction": {"sliding": 0.1, "rolling_mm": 0.01, "axle": 0.1},
    "load": {"mode": "multiplier", "torque_shaft": "H", "torque_Nm": 100.0, "crank_speed_rpm": 1000.0},
}


W8 = {"mechanism": "pins_in_holes", "holes": 8, "hole_circle_radius_mm": 35.0, "pin_radius_mm": 6.0}


def _run(design):
    import gearcalc.api as api
    return api.compute(design).summary


def _with(**tables):
    import copy
    d = copy.deepcopy(PAPER)
    for t, vals in tables.items():
        d.setdefault(t, {}).update(vals)
    return d


def test_ideal_mechanism_is_the_default_and_said():
    s = _run(PAPER)
    assert s["output_mechanism"] == "ideal" and s["w_loss_ratio"] is None and s["backdrive_startup_torque_Nm"] is None


@pytest.mark.parametrize("mode,shaft", [("multiplier", "H"), ("reducer", "H"), ("multiplier", "V"), ("reducer", "V")])
def test_power_balance_with_the_mechanism_and_drag(mode, shaft):
    # P_in - P_out = the teeth's loss (lambda of the ideal run at the satellite torque) + the W mechanism's loss
    # (lambda_W |T_V omega_V|, lambda_W = 4 f_w e (u + 1)/(pi R_w) for 8 holes) + the drag T_d omega_H
    f_w, T_d, u = 0.05, 0.5, 10.0
    d = _with(load={"mode": mode, "torque_shaft": shaft, "drag_torque_Nm": T_d}, output={**W8, "friction": f_w})
    s = _run(d)
    lam_w = 4 * f_w * 3.9 * (u + 1) / (np.pi * 35.0)
    assert s["w_loss_ratio"] == pytest.approx(lam_w, rel=1e-4)
    teeth = _run(_with(load={"mode": mode, "torque_shaft": shaft}))["loss_ratio"]
    w_H = 1000.0 * np.pi / 30
    T_V = s["torque_in_Nm"] if mode == "multiplier" else s["torque_out_Nm"]
    T_H = s["torque_out_Nm"] if mode == "multiplier" else s["torque_in_Nm"]
    T_sat = T_V * (1 - lam_w if mode == "multiplier" else 1 + lam_w)
    losses = teeth * T_sat * w_H / u + lam_w * T_V * w_H / u + T_d * w_H
    P_in, P_out = (T_V * w_H / u, T_H * w_H) if mode == "multiplier" else (T_H * w_H, T_V * w_H / u)
    assert P_in - P_out == pytest.approx(losses, rel=1e-9)
    assert s["loss_mean_W"] == pytest.approx(losses, rel=1e-9)
    assert s["efficiency"] == pytest.approx(P_out / P_in, rel=1e-12)


def test_bearing_force_rise_on_the_paper_design_through_the_keys():
    # the review of issue 37: 1.6-1.7 times the pure-torque peak with 8 holes (R_w = 35 mm ASSUMED, as above);
    # the resultant's peak 4 T_sat/(n_w R_w sin(pi/8)) at T_sat = 1144.655 N m (pins.md §4.10)
    s0, s = _run(PAPER), _run(_with(output=W8))
    assert 1.6 <= s["bearing_force_max_N"] / s0["bearing_force_max_N"] <= 1.7
    assert s["w_force_max_N"] == pytest.approx(4 * 1144.6554210712009e3 / (8 * 35.0 * np.sin(np.pi / 8)), rel=1e-9)
    assert s["efficiency"] < s0["efficiency"]          # f_w = friction.sliding = 0.1 by default


def test_start_up_torque_and_back_driving():
    # torque on V: below u T_d/eta_VH the multiplier cannot be back-driven (self_locking, exit status 1)
    s = _run(_with(load={"torque_shaft": "V", "torque_Nm": 50.0, "drag_torque_Nm": 2.0}))
    eta = _run(_with(load={"torque_shaft": "V", "torque_Nm": 50.0}))["efficiency_multiplier"]
    T0 = 10.0 * 2.0 / eta
    assert s["backdrive_startup_torque_Nm"] == pytest.approx(T0, rel=1e-12)
    below = _run(_with(load={"torque_shaft": "V", "torque_Nm": 0.9 * T0, "drag_torque_Nm": 2.0}))
    assert below["self_locking"] is True and below["efficiency"] is None


def test_sweep_over_torque_and_speed_equals_the_points():
    import gearcalc.api as api
    d = _with(load={"drag_torque_Nm": 0.5}, output=W8)
    axes = {"load.torque_Nm": [1.0, 10.0, 100.0], "load.crank_speed_rpm": [100.0, 1000.0]}
    cols = {}
    for chunk in api.sweep(d, axes):
        for k, v in chunk.data.items():
            cols.setdefault(k, []).extend(v)
    i = 0
    for T in axes["load.torque_Nm"]:
        for n in axes["load.crank_speed_rpm"]:
            s = _run(_with(load={"drag_torque_Nm": 0.5, "torque_Nm": T, "crank_speed_rpm": n}, output=W8))
            assert cols["efficiency"][i] == s["efficiency"] and cols["bearing_force_max_N"][i] == \
                s["bearing_force_max_N"]
            i += 1
