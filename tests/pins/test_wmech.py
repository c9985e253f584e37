"""Tests of the output (W) mechanism, the drag torque, the start-up torque and the new friction laws (issue 37
items 3-4; gearcalc.pins.wmech, gearcalc.pins.friction; pins.md §4.10).

Independent references: the satellite's moment balance and the closed-form mean resultant 4 T/(pi R_w) of the
classical W-mechanism analysis (Blagojević et al. 2011; Kudryavtsev 1966); a per-node power balance from an
independent kinematic simulation (body positions differentiated numerically, not the module's v_w formula); power
balances at the crank worked by hand; the Stribeck curve's limits and a table interpolated by hand.
"""
import numpy as np
import pytest

from gearcalc.pins import friction as fr
from gearcalc.pins import wmech as w


@pytest.mark.parametrize("n_w", [3, 5, 8, 12])
@pytest.mark.parametrize("T", [2.5e5, -1.0e6])
def test_pin_hole_forces_balance_the_satellite_torque(n_w, T):
    R_w = 35.0
    phase = np.linspace(0.0, 2 * np.pi, 97)
    F, Q = w.w_hole_forces(T, n_w, R_w, phase)
    phi = phase[:, None] + 2 * np.pi * np.arange(n_w) / n_w
    # the moment of the pushes -F_j x at R_w (cos phi_j, sin phi_j) about the satellite centre is F_j R_w sin phi_j
    assert np.allclose((F * R_w * np.sin(phi)).sum(axis=1), T, rtol=1e-12)
    assert (F >= 0.0).all() and np.allclose(Q, F.sum(axis=1))


def test_the_mean_resultant_is_4T_over_pi_Rw_for_even_hole_counts():
    # even n_w: the loaded half holds sum sin^2 = n_w/4 and each hole's sin+ averages 1/pi over a turn, so the
    # cycle mean of Q is exactly 4 T/(pi R_w) (the classical W-mechanism result)
    T, R_w = 1.0e6, 30.0
    phase = (np.arange(4096) + 0.5) / 4096 * 2 * np.pi / 8
    _, Q = w.w_hole_forces(T, 8, R_w, phase)
    assert np.mean(Q) == pytest.approx(4 * T / (np.pi * R_w), rel=1e-6)


def _kinematics(theta, z1, z2, e, R_w, r_h, n_w, d=1e-6):
    """Independent simulation: contact points' material velocities of satellite and flange by central differences."""
    k = z2 - z1
    ratio_V = -k / z1                          # omega_V / omega_H, KHV with fixed pins
    beta = 2 * np.pi * np.arange(n_w) / n_w

    def bodies(th, th_body):
        # satellite: centre at e (cos th, sin th), turned by ratio_V * th; flange: at the origin, same turn
        a = ratio_V * th
        o1 = e * np.array([np.cos(th), np.sin(th)])
        rot = np.array([[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]])
        return o1, rot

    o1, rot = bodies(theta, theta)
    xhat = np.array([np.cos(theta), np.sin(theta)])
    holes = o1[:, None] + R_w * np.array([np.cos(ratio_V * theta + beta), np.sin(ratio_V * theta + beta)])
    contact = holes - r_h * xhat[:, None]      # the hole's farthest-inward point along the crank arm
    body_sat = rot.T @ (contact - o1[:, None])
    body_fl = rot.T @ contact

    def at(th):
        o, r = bodies(th, th)
        return o[:, None] + r @ body_sat, r @ body_fl

    sp, fp = at(theta + d)
    sm, fm = at(theta - d)
    return (sp - sm) / (2 * d), (fp - fm) / (2 * d), xhat, ratio_V * theta + beta - theta


def test_power_balance_per_node_and_the_sliding_speed_from_independent_kinematics():
    z1, z2, e, R_w, r_w, n_w, f_w, T = 20, 22, 3.9, 35.0, 6.0, 8, 0.1, 1.0e6
    omega_H, omega_V = 1.0, -(z2 - z1) / z1
    for theta in np.linspace(0.0, 2 * np.pi, 13):
        v_sat, v_fl, xhat, phi = _kinematics(theta, z1, z2, e, R_w, r_w + e, n_w)
        rel = v_sat - v_fl
        # every pin slides across the crank arm at e |omega_H - omega_V|
        assert np.allclose(rel.T @ xhat, 0.0, atol=1e-7)
        assert np.allclose(np.linalg.norm(rel, axis=0), w.w_sliding_speed(e, omega_H, omega_V), rtol=1e-8)
        sig = -1.0 if T * omega_V < 0 else 1.0                   # T along omega_V: power flows into the satellite
        F, Q = w.w_hole_forces(sig * T, n_w, R_w, phi[0])
        push = -F[None, :] * xhat[:, None]                       # the pins' pushes on the satellite
        P_sat = float(np.sum(push * v_sat))
        P_fl = float(np.sum(-push * v_fl))
        assert P_sat == pytest.approx(sig * T * omega_V, rel=1e-7)  # friction-free: the satellite gets T omega_V
        assert P_sat + P_fl == pytest.approx(0.0, abs=1e-6 * abs(P_sat))
        loss = float(np.sum(f_w * F * np.linalg.norm(rel, axis=0)))
        lam = w.w_loss_ratio(f_w, e, R_w, n_w, omega_H / omega_V, phi[0])
        assert lam * abs(T * omega_V) == pytest.approx(loss, rel=1e-7)


def test_bearing_force_rise_on_the_paper_design():
    # configs/pins_paper_cyc_u10_fixed.toml: T_H = 100 N m in multiplier mode, T_sat = 1144.655 N m (gearcalc run);
    # 8 holes on R_w = 35 mm (ASSUMED: 0.61 R_p; the paper gives no output mechanism).  The review of issue 37 found
    # a peak bearing force 1.6-1.7 times the pure-torque one with 8 holes.
    from gearcalc.pins.consistent import crank_history
    from gearcalc.pins.geometry import MULTIPLIER, Cycloid, crest_cutoff
    g = Cycloid.from_curtate_ratio(20, 22, 3.9, 0.75, 1.95)
    t = (np.arange(400) + 0.5) / 400
    h = crank_history(g, crest_cutoff(g), t, t, 0.1, MULTIPLIER)
    T_sat = 1144.6554210712009e3
    Bx, By = h["Bx"] * T_sat, h["By"] * T_sat
    _, Q = w.w_hole_forces(T_sat, 8, 35.0, (np.arange(64) + 0.5) / 64 * 2 * np.pi / 8)
    peak0 = np.hypot(Bx, By).max()
    peak = w.bearing_force_with_w(Bx[:, None], By[:, None], Q[None, :]).max()
    assert peak0 == pytest.approx(26994.5, rel=1e-3)           # bearing_force_max_N of gearcalc run
    assert 1.6 <= peak / peak0 <= 1.7


def test_drag_torque_power_balances_by_hand():
    # T_V = 100 N m, u = 10, omega_V = 1 rad/s, T_d = 1 N m at the crank (omega_H = 10 rad/s)
    # reducer: gear input 100/0.8 = 125 W, crank input 125 + 10 = 135 W: 100/135
    # multiplier: gear output 0.75 x 100 = 75 W, minus 10 W: 65/100
    hv, vh = w.drag_efficiencies(0.8, 0.75, 1.0, 100.0, 10.0)
    assert float(hv) == pytest.approx(100 / 135, rel=1e-12) and float(vh) == pytest.approx(0.65, rel=1e-12)
    T0 = w.backdrive_startup_torque(1.0, 10.0, 0.75)
    assert float(T0) == pytest.approx(10 / 0.75, rel=1e-12)
    assert float(w.drag_efficiencies(0.8, 0.75, 1.0, T0, 10.0)[1]) == pytest.approx(0.0, abs=1e-12)
    assert float(w.backdrive_startup_torque(1.0, 10.0, -0.1)) == np.inf


def test_series_efficiencies_with_the_output_mechanism():
    # reducer: 100 W out, W mechanism loses 0.1 x 100 = 10 W, teeth 0.25 x 110 = 27.5 W: 100/137.5
    # multiplier: 100 W in, W loses 10 W, teeth 0.25 x 90 = 22.5 W: 67.5/100
    hv, vh = w.w_mode_efficiencies(0.25, 0.1)
    assert float(hv) == pytest.approx(100 / 137.5, rel=1e-12) and float(vh) == pytest.approx(0.675, rel=1e-12)


def test_table_and_stribeck_laws():
    law = fr.friction_law("table", speed_m_s=(0.0, 0.5, 2.0), mu=(0.12, 0.08, 0.05))
    # by hand: 0.25 m/s halfway between 0.12 and 0.08; 1.25 m/s halfway between 0.08 and 0.05; ends held
    assert law.coefficient(np.array([0.25, 1.25, 5.0, -0.25])).tolist() == pytest.approx([0.10, 0.065, 0.05, 0.10])
    assert isinstance(law, fr.FrictionLaw) and not law.constant
    s = fr.friction_law("stribeck", mu_s=0.15, mu_c=0.05, v_s=0.1, delta=2.0, k_v=0.01)
    assert float(s.coefficient(0.0)) == pytest.approx(0.15, rel=1e-12)              # breakaway
    assert float(s.coefficient(0.1)) == pytest.approx(0.05 + 0.1 * np.exp(-1) + 0.001, rel=1e-12)
    assert float(s.coefficient(10.0)) == pytest.approx(0.05 + 0.1, rel=1e-12)       # full film: mu_c + k_v v


@pytest.mark.parametrize("n_w", [4, 8, 10])
def test_resultant_range_closed_form_for_even_hole_counts(n_w):
    # pins.md §4.10: sum of sin over the loaded half = cos(phi_0 - pi/n_w)/sin(pi/n_w), sum of sin^2 = n_w/4, so
    # Q/(T/R_w) ranges over [4 cot(pi/n_w)/n_w, 4/(n_w sin(pi/n_w))] (n_w = 8: 1.2071, 1.3066)
    phase = np.linspace(0.0, 2 * np.pi / n_w, 2001)
    _, Q = w.w_hole_forces(1.0, n_w, 1.0, phase)
    assert Q.min() == pytest.approx(4 / (n_w * np.tan(np.pi / n_w)), rel=1e-9)
    assert Q.max() == pytest.approx(4 / (n_w * np.sin(np.pi / n_w)), rel=1e-9)


# ---------------------------------------------------------------- the design keys at the ideal level (pins.md §4.10)

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


@pytest.mark.parametrize("output,key", [
    ({"mechanism": "pins_in_holes", "holes": 8, "pin_radius_mm": 6.0}, "output.hole_circle_radius_mm"),
    ({**W8, "hole_circle_radius_mm": 12.0}, "output.hole_circle_radius_mm"),       # 8 holes of 9.9 mm overlap
    ({**W8, "hole_circle_radius_mm": 45.0}, "output.hole_circle_radius_mm"),       # past R_p - R_b - e = 51.35
])
def test_bad_output_keys_name_the_key(output, key):
    from gearcalc import InputError
    with pytest.raises(InputError, match=key.replace(".", r"\.")):
        _run(_with(output=output))


def test_the_contact_level_refuses_the_mechanism():
    from gearcalc import InputError
    d = _with(output=W8, contact={"law": "linear", "stiffness_N_per_mm": 1e6})
    with pytest.raises(InputError, match=r"output\.mechanism.*contact level"):
        _run(d)


def test_efficiency_map_contour_from_the_plotted_data():
    # issue 37 item 4: a torque x speed sweep drawn as a contour map beside the curves; the map's data are the
    # sweep's efficiencies at their grid places
    pytest.importorskip("matplotlib")
    import matplotlib.pyplot as plt

    import gearcalc.api as api
    from gearcalc.plot import sweep_figure
    d = _with(load={"drag_torque_Nm": 0.5}, output=W8)
    axes = {"load.torque_Nm": [1.0, 10.0, 100.0, 1000.0], "load.crank_speed_rpm": [100.0, 1000.0, 3000.0]}
    rows = []
    for chunk in api.sweep(d, axes):
        rows.extend(chunk.rows())
    fig = sweep_figure("pins", rows, list(axes))
    ax_map = fig.axes[1]
    x_key, y_key, xs, ys, Z = ax_map.gearcalc_map
    assert (x_key, y_key) == ("load.torque_Nm", "load.crank_speed_rpm")
    for r in rows:
        assert Z[ys.index(r[y_key])][xs.index(r[x_key])] == r["efficiency"]
    filled = next(c for c in ax_map.collections if hasattr(c, "levels"))
    eff = [r["efficiency"] for r in rows]
    assert filled.levels[0] <= min(eff) and max(eff) <= filled.levels[-1]
    assert len(fig.axes[0].lines) == 3          # the curves stay: one per speed
    plt.close(fig)


# ---------------------------------------------------------------- a speed-dependent law at the ideal level (§4.10)

def test_power_weighted_coefficient_against_a_brute_force_cycle():
    # independent: the friction-free pin forces of gearcalc.pins.forces (pointwise membership) and the pitch distances
    # at 32 000 crank angles of one tooth period; sum mu(v_i) F_i v_i / sum F_i v_i.  The two quadratures of a
    # discontinuous integrand (a pin leaves at psi*) agree to ~1e-6.
    from gearcalc.pins.forces import pin_forces, pin_phase
    from gearcalc.pins.geometry import Cycloid, crest_cutoff, pitch_distance
    from gearcalc.pins.speed_friction import power_weighted_coefficient
    g = Cycloid.from_curtate_ratio(20, 22, 3.9, 0.75, 1.95)
    ps, w_V = crest_cutoff(g), 1000 * np.pi / 30 / 10
    law = fr.TableLaw((0.0, 2.0), (0.12, 0.04))
    th = (np.arange(32000) + 0.5) / 32000 * 2 * np.pi / 22
    F = pin_forces(th, g, ps, 1.0)
    v = w_V * np.abs(pitch_distance(pin_phase(np.arange(22)[:, None], th[None, :], 22), g) - 1.95) * 1e-3
    brute = (law.coefficient(v) * F * v).sum() / (F * v).sum()
    assert power_weighted_coefficient(law, g, ps, w_V) == pytest.approx(brute, rel=1e-5)


def test_a_constant_table_is_coulombs_law():
    s0 = _run(PAPER)
    s = _run(_with(friction={"law": "table", "table_speed_m_s": [0.0, 5.0], "table_mu": [0.1, 0.1]}))
    assert s["sliding_friction_mean"] == pytest.approx(0.1, rel=1e-14)
    assert s["efficiency"] == pytest.approx(s0["efficiency"], rel=1e-13)


def test_stribeck_makes_the_efficiency_depend_on_speed():
    # at 0.01 rpm every contact slides at v <= 8.73e-6 m/s (sliding_speed_max_m_s 0.8731 at 1000 rpm), so
    # |mu-bar - mu_s| <= k_v v + (mu_s - mu_c)(v/v_s)^2 = 1.75e-7 + 7.6e-10; at high speed the viscous rise shows
    f = {"law": "stribeck", "stribeck_static": 0.15, "stribeck_coulomb": 0.05, "stribeck_speed_m_s": 0.1,
         "stribeck_viscous_s_per_m": 0.02}
    slow = _run(_with(friction=f, load={"crank_speed_rpm": 0.01}))
    assert abs(slow["sliding_friction_mean"] - 0.15) <= 0.02 * 8.732e-6 + 0.1 * (8.732e-5) ** 2
    effs = [_run(_with(friction=f, load={"crank_speed_rpm": n}))["efficiency"] for n in (10.0, 1000.0, 3000.0)]
    assert effs[0] < effs[1] and effs[2] < effs[1]


@pytest.mark.parametrize("friction,gearing,load,key", [
    ({"law": "table", "table_speed_m_s": [0.0, 1.0], "table_mu": [0.1]}, {}, {}, "friction.table_mu"),
    ({"law": "table", "table_speed_m_s": [1.0, 1.0], "table_mu": [0.1, 0.1]}, {}, {}, "friction.table_speed_m_s"),
    ({"law": "stribeck", "stribeck_static": 0.1, "stribeck_coulomb": 0.05}, {}, {}, "friction.stribeck_speed_m_s"),
    ({"law": "table", "table_speed_m_s": [0.0, 1.0], "table_mu": [0.1, 0.1]}, {"rotating_pins": True}, {},
     "friction.law"),
])
def test_bad_law_keys_name_the_key(friction, gearing, load, key):
    from gearcalc import InputError
    with pytest.raises(InputError, match=key.replace(".", r"\.")):
        _run(_with(friction=friction, gearing=gearing, load=load))
