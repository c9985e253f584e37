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


# The contact level with the mechanism and the drag (pins.md §4.10: the same rules as the ideal level's, the teeth
# solved at the torque they carry).  Hertz contacts on the paper's cycloid (10 mm face width, ASSUMED as in
# configs/pins_paper_circ_u10_fixed.toml).
CONTACT = {"law": "hertz", "face_width_mm": 10.0}


def _contact(design, detail=False):
    import gearcalc.api as api
    return api.compute(design, model="contact", detail=detail)


def _hole_resultants(n_w, R_w, T_sat):
    # pins.md §4.10's closed form: F_j = T max(sin phi_j, 0)/(R_w sum_k max(sin phi_k, 0)^2), Q = sum_j F_j, at the
    # 64 hole phases (midpoints of one pattern period 2 pi/n_w) the ideal level takes
    phi0 = (np.arange(64) + 0.5) / 64 * 2 * np.pi / n_w
    s = np.maximum(np.sin(phi0[:, None] + 2 * np.pi * np.arange(n_w) / n_w), 0.0)
    F = T_sat * s / (R_w * (s * s).sum(axis=1, keepdims=True))
    return F.sum(axis=1)


def test_contact_level_with_a_frictionless_mechanism_keeps_its_efficiencies_and_raises_the_bearing_force():
    r0 = _contact(_with(contact=CONTACT), detail=True)
    r = _contact(_with(contact=CONTACT, output={**W8, "friction": 0.0}), detail=True)
    s0, s = r0.summary, r.summary
    for key in ("efficiency", "efficiency_reducer", "efficiency_multiplier", "torque_in_Nm", "torque_out_Nm",
                "pin_force_max_N", "crank_torque_mean_Nm"):
        assert s[key] == s0[key], key                        # f_w = 0, no drag: the same teeth, bit for bit
    # with the mechanism loss_mean_W is P_in - P_out of the shaft torques (the ideal level's rule), without it the
    # teeth's lambda T_V omega_V: the same to the torque fixed point's convergence (measured 2.7e-10)
    assert s["loss_mean_W"] == pytest.approx(s0["loss_mean_W"], rel=1e-9)
    assert s["output_mechanism"] == "pins_in_holes" and s["w_loss_ratio"] == 0.0
    # brute force over the detail's bearing history (one disc) and the hole phases: max |B + Q x|
    rows = r.detail["crank"]
    Bx = np.array([row["bearing_radial_N"] for row in rows])
    By = np.array([row["bearing_tangential_N"] for row in rows])
    Q = _hole_resultants(8, 35.0, 1e3 * s["torque_in_Nm"])   # T_sat = T_V/n_d, n_d = 1, lambda_W = 0
    peak = np.hypot(Bx[:, None] + Q[None, :], By[:, None]).max()
    assert s["bearing_force_max_N"] == pytest.approx(peak, rel=1e-12)
    assert s["bearing_force_max_N"] > 1.5 * s0["bearing_force_max_N"]
    assert s["bearing_force_mean_N"] > 1.5 * s0["bearing_force_mean_N"]
    assert s0["bearing_force_mean_N"] < s["bearing_force_mean_N"] < s["bearing_force_max_N"]
    # the resultant's closed-form peak 4 T_sat/(n_w R_w sin(pi/n_w)) (even n_w) against the 64 phases' largest
    assert s["w_force_max_N"] == pytest.approx(4e3 * s["torque_in_Nm"] / (8 * 35.0 * np.sin(np.pi / 8)), rel=1e-12)


@pytest.mark.parametrize("mode", ["multiplier", "reducer"])
def test_contact_level_mechanism_in_series_with_the_teeth(mode):
    # lambda_W = 4 f_w e |omega_H/omega_V - 1|/(pi R_w), |omega_H/omega_V - 1| = u + 1 = 11 (fixed pins, even n_w);
    # the teeth carry T_sat = T_V (1 -+ lambda_W) on V: the same contact run without the mechanism at that torque
    f_w = 0.05
    lam = 4 * f_w * 3.9 * 11 / (np.pi * 35.0)
    s = _contact(_with(contact=CONTACT, output={**W8, "friction": f_w},
                       load={"mode": mode, "torque_shaft": "V", "torque_Nm": 1000.0})).summary
    assert s["w_loss_ratio"] == pytest.approx(lam, rel=1e-12)
    lam = s["w_loss_ratio"]
    sat = 1000.0 * (1 - lam if mode == "multiplier" else 1 + lam)
    teeth = _contact(_with(contact=CONTACT, load={"mode": mode, "torque_shaft": "V", "torque_Nm": sat})).summary
    if mode == "multiplier":
        assert s["efficiency"] == pytest.approx(teeth["efficiency"] * (1 - lam), rel=1e-12)
    else:
        assert s["efficiency"] == pytest.approx(teeth["efficiency"] / (1 + lam), rel=1e-12)
    assert s["pin_force_max_N"] == teeth["pin_force_max_N"]      # the teeth's forces at the satellite torque
    # P_in - P_out = teeth loss + lambda_W |T_V omega_V| (no drag)
    w_V = 1000.0 * np.pi / 30 / 10.0
    assert s["loss_mean_W"] == pytest.approx(teeth["loss_mean_W"] + lam * 1000.0 * w_V, rel=1e-9)


def test_contact_level_drag_and_start_up_torque():
    # u T_d/eta_VH (pins.md §4.10, the ideal level's formula) with the contact level's multiplier efficiency of the
    # same teeth (torque on V: the drag does not change the teeth's load); eta^d_VH = eta_VH - u T_d/T_V
    u, T_d, T_V = 10.0, 2.0, 50.0
    base = _with(contact=CONTACT, output={**W8, "friction": 0.05}, load={"torque_shaft": "V", "torque_Nm": T_V})
    eta = _contact(base).summary["efficiency_multiplier"]
    s = _contact(_with(contact=CONTACT, output={**W8, "friction": 0.05},
                       load={"torque_shaft": "V", "torque_Nm": T_V, "drag_torque_Nm": T_d})).summary
    T0 = u * T_d / eta
    assert s["backdrive_startup_torque_Nm"] == pytest.approx(T0, rel=1e-12)
    assert s["efficiency_multiplier"] == pytest.approx(eta - u * T_d / T_V, rel=1e-12)
    assert s["torque_out_Nm"] == pytest.approx(T_V * eta / u - T_d, rel=1e-12)
    below = _contact(_with(contact=CONTACT, load={"torque_shaft": "V", "torque_Nm": u * T_d, "drag_torque_Nm": T_d}))
    # T_V = u T_d < u T_d/eta, the start-up torque (eta < 1)
    assert below.summary["self_locking"] is True and below.summary["efficiency"] is None
    assert any("start-up torque" in f for f in below.failed)


@pytest.mark.parametrize("mode", ["multiplier", "reducer"])
def test_ideal_and_contact_levels_agree_with_the_mechanism_and_drag(mode):
    # the stiff limit (pins.md §5.7) on a k = 1 cycloid, as tests/pins/test_contact_level.py's
    # test_stiff_linear_contact_outputs_approach_the_ideal_level_on_a_k1_cycloid: its measured tolerances (efficiency
    # and bearing force 1e-5; measured here 2026-12-07 <= 8e-7 and <= 2.7e-6); the mechanism's loss ratio is the
    # same formula on the same inputs; the crank torque is the gear's, T_H +- T_d (multiplier +, reducer -)
    import gearcalc.api as api
    over = {"gearing.satellite_teeth": 21, "gearing.pins": 22, "gearing.eccentricity_mm": 1.95,
            "friction.sliding": 0.1, "contact.face_width_mm": 10.0, "load.mode": mode, "load.drag_torque_Nm": 0.5,
            **{"output." + k: v for k, v in {**W8, "friction": 0.05}.items()}}
    path = str(__import__("pathlib").Path(__file__).parents[2] / "configs" / "pins_paper_cyc_u10_fixed.toml")
    ideal = api.compute(path, model="ideal", overrides=over).summary
    cont = api.compute(path, model="contact", overrides={**over, "contact.law": "linear",
                                                         "contact.stiffness_N_per_mm": 1e9}).summary
    assert cont["w_loss_ratio"] == ideal["w_loss_ratio"]
    for key, rel in (("efficiency_reducer", 1e-5), ("efficiency_multiplier", 1e-5), ("torque_in_Nm", 1e-5),
                     ("torque_out_Nm", 1e-5), ("bearing_force_max_N", 1e-5), ("bearing_force_mean_N", 1e-5),
                     ("w_force_max_N", 1e-5), ("backdrive_startup_torque_Nm", 1e-5)):
        assert cont[key] == pytest.approx(ideal[key], rel=rel), key
    assert cont["crank_torque_mean_Nm"] == pytest.approx(100.0 + (0.5 if mode == "multiplier" else -0.5), rel=1e-10)
