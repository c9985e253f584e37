"""Tests of the output (W) mechanism, the drag torque and the start-up torque (issue 37 items 3-4;
gearcalc.pins.wmech; pins.md §4.10).  The mechanism's keys in a run: test_output_mech.py and test_output_keys.py;
the friction laws: test_friction.py and test_speed_friction.py.

Independent references: the satellite's moment balance and the closed-form mean resultant 4 T/(pi R_w) of the
classical W-mechanism analysis (Blagojević et al. 2011; Kudryavtsev 1966); a per-node power balance from an
independent kinematic simulation (body positions differentiated numerically, not the module's v_w formula); power
balances at the crank worked by hand.
"""
import numpy as np
import pytest

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


@pytest.mark.parametrize("n_w", [4, 8, 10])
def test_resultant_range_closed_form_for_even_hole_counts(n_w):
    # pins.md §4.10: sum of sin over the loaded half = cos(phi_0 - pi/n_w)/sin(pi/n_w), sum of sin^2 = n_w/4, so
    # Q/(T/R_w) ranges over [4 cot(pi/n_w)/n_w, 4/(n_w sin(pi/n_w))] (n_w = 8: 1.2071, 1.3066)
    phase = np.linspace(0.0, 2 * np.pi / n_w, 2001)
    _, Q = w.w_hole_forces(1.0, n_w, 1.0, phase)
    assert Q.min() == pytest.approx(4 / (n_w * np.tan(np.pi / n_w)), rel=1e-9)
    assert Q.max() == pytest.approx(4 / (n_w * np.sin(np.pi / n_w)), rel=1e-9)


@pytest.mark.parametrize("mult,on_V", [(True, False), (False, False), (True, True), (False, True)])
def test_teeth_torque_gives_the_series_shaft_torques(mult, on_V):
    # teeth of constant efficiencies run at teeth_torque on the same shaft: their torque on V (u T_H/eta_VH or
    # u T_H eta_HV on H) is T_V (1 -+ lambda_W) of series_values, the satellite's torque (pins.md §4.10)
    hv, vh, lam, T_d, T, u = 0.8, 0.75, 0.05, 2.0, 100.0, 10.0
    Tt = float(w.teeth_torque(T, lam, T_d, mult, on_V))
    teeth_V = Tt if on_V else (u * Tt / vh if mult else u * Tt * hv)
    r = w.series_values((hv, vh), lam, T_d, T, u, mult, on_V, 1.0)
    assert teeth_V == pytest.approx(float(r["torque_V"] * r["sat_factor"]), rel=1e-14)


def test_series_values_power_balance_and_start_up():
    # P_in - P_out = teeth loss + lambda_W T_V omega_V + T_d omega_H, worked by hand for the multiplier on V
    hv, vh, lam, T_d, T_V, u, wH = 0.8, 0.75, 0.05, 2.0, 100.0, 10.0, 3.0
    r = w.series_values((hv, vh), lam, T_d, T_V, u, True, True, wH)
    teeth = (1 - vh) * T_V * (1 - lam) * wH / u
    assert float(r["loss"]) == pytest.approx(teeth + lam * T_V * wH / u + T_d * wH, rel=1e-13)
    assert float(r["startup"]) == pytest.approx(u * T_d / (vh * (1 - lam)), rel=1e-14)
    low = w.series_values((hv, vh), lam, T_d, 0.5 * float(r["startup"]), u, True, True, wH)
    assert bool(low["locked"]) and np.isnan(low["eta_VH"])


def test_bearing_peak_and_mean_over_angles_and_phases():
    # brute force: every (theta_i, phi_m) pair; the mean with the angles' weights and the phases equally weighted
    rng = np.random.default_rng(7)
    Bx, By, Q = rng.normal(size=9), rng.normal(size=9), rng.uniform(0, 2, size=5)
    wts = rng.uniform(size=9)
    wts /= wts.sum()
    pairs = [[np.hypot(Bx[i] + q, By[i]) for q in Q] for i in range(9)]
    peak, mean = w.w_bearing_peak_mean(Bx, By, Q, wts)
    assert peak == max(map(max, pairs))
    assert mean == pytest.approx(sum(wts[i] * sum(pairs[i]) / 5 for i in range(9)), rel=1e-14)
