"""Tests of the pins contact level (gearcalc.pins.contact; pins.md §5, §6, §9, §12).

The contact laws and the profiles' penetrations are tested in test_contact_law.py and test_contact_profiles.py, the
candidate window in test_contact_window.py; the torque fixed point (pins.md §6(6), §7) at the end of this file.
Independent references used here: the ideal level's closed-form lever arms, forces,
speeds and loss ratio (pins.md §4), which the contact level must approach for a stiff linear law on
an unmodified cycloid (pins.md §5.7(a)); exact kinematic identities (period, power balance); central
differences of the moment balance (the analytic derivatives); the friction-consistent reference values of
pins.md §4.9 and an independent brute-force rigid friction-consistent model written in this file (each
mode with its own forces, issue 15).
"""
import copy
import dataclasses
import functools
import json
import math
import warnings
from pathlib import Path

import numpy as np
import pytest
import tomli_w

from gearcalc import api, pins
from gearcalc.pins import contact as pc
from gearcalc.pins import contact_cycle as pcc
from gearcalc.pins import MULTIPLIER, REDUCER, Cycloid
from gearcalc.pins.operating import efficiency_torques, shaft_torques
from gearcalc.quadrature import integrate_adaptive
from kinds.test_pins import design, run, summary  # the pins CLI helpers, shared

ROOT = Path(__file__).resolve().parents[2]
CONFIGS = ROOT / "configs"


def circ_u10():
    return Cycloid.from_pin_circle(20, 22, 3.9, 57.2, 2.75)


@functools.lru_cache(maxsize=None)
def full_u10():
    return pc.full_tooth(circ_u10())


def circular_model(T_sat=1.0e6, sigma=MULTIPLIER, K1=None, friction=None):
    g = circ_u10() if K1 is None else Cycloid.from_curtate_ratio(20, 22, 3.9, K1, 2.75)
    rho, R_t = full_u10() if K1 is None else pc.full_tooth(g)
    return pc.ContactModel(g, pc.CircularProfile(g, rho, R_t), pc.contact_law("hertz", face_width=10.0), T_sat,
                           sigma, friction)


@functools.lru_cache(maxsize=None)
def config_summary(fname, *args):
    return summary(CONFIGS / fname, *args)[0]


# ------------------------------------------------------------------ convergence to the ideal level (§5.7(a))

@functools.lru_cache(maxsize=None)
def _stiff(z1, z2, sigma, k_lin):
    g = Cycloid.from_curtate_ratio(z1, z2, 3.9, 0.75, 1.95)
    m = pc.ContactModel(g, pc.CycloidProfile(g), pc.ContactLaw("linear", k_lin, 1.0), 1e5, sigma)
    theta = np.linspace(0.013, g.period - 0.011, 5)
    F_err = float(np.abs(m.state(theta).force[0] - pins.pin_forces(theta, g, pins.crest_cutoff(g), 1e5, sigma)).max()
                  / pins.pin_forces(theta, g, pins.crest_cutoff(g), 1e5, sigma).max())
    cyc = pc.mean_loss_ratio(m, (0.1, 0.1, False), tol=1e-7)
    ideal = pins.mean_loss_ratio(g, pins.crest_cutoff(g), pins.spin_reversal_phase(g), 0.1, tol=1e-10)
    return F_err, cyc.loss_ratio, cyc.loss_ratio_err, ideal.loss_ratio


@pytest.mark.parametrize("z1,z2", [(21, 22), (20, 22), (30, 33)])
@pytest.mark.parametrize("sigma", [MULTIPLIER, REDUCER])
def test_stiff_linear_contact_reproduces_the_ideal_force_distribution(z1, z2, sigma):
    # pins.md §5.7(a): the force error is first order in T_sat/k_lin, doubling k_lin halves it
    e1 = _stiff(z1, z2, sigma, 1e8)[0]
    e2 = _stiff(z1, z2, sigma, 2e8)[0]
    assert e1 / e2 == pytest.approx(2.0, rel=0.05)
    assert e2 < 5e-6                                  # reached: 1.1e-6 (k = 1), 2.2e-6 (k = 2), 2.1e-6 (k = 3)


def test_stiff_linear_contact_reproduces_the_ideal_loss_ratio_k1():
    # k = 1: lambda_bar converges to the ideal one at first order in T_sat/k_lin
    _, l1, E1, ideal = _stiff(21, 22, MULTIPLIER, 1e8)
    _, l2, E2, _ = _stiff(21, 22, MULTIPLIER, 2e8)
    d1, d2 = abs(l1 - ideal), abs(l2 - ideal)
    assert d1 / d2 == pytest.approx(2.0, rel=0.05)
    assert d2 / ideal < 3e-7 and E2 < d2           # reached: 2.7e-7 relative at k_lin = 2e8 N/mm, T = 1e5 N mm


@pytest.mark.parametrize("z1,z2", [(20, 22), (30, 33)])
def test_stiff_linear_contact_approaches_the_ideal_loss_ratio_k2_k3(z1, z2):
    # k >= 2: the pin keeps touching the crest corner over a crank angle ~ sqrt(delta) after psi*, so
    # lambda_bar approaches the ideal one as sqrt(T_sat/k_lin): x4 stiffness halves the difference
    _, l1, _, ideal = _stiff(z1, z2, MULTIPLIER, 1e8)
    _, l4, E4, _ = _stiff(z1, z2, MULTIPLIER, 4e8)
    assert (l1 - ideal) / (l4 - ideal) == pytest.approx(2.0, rel=0.05)
    assert 0 < (l4 - ideal) / ideal < 1e-4 and E4 < 0.1 * (l4 - ideal)


def test_stiff_contact_speeds_are_the_ideal_sliding_speeds():
    # pins.md §4.5: v = |omega_V| |rho - R_b| on a fixed pin (conjugate contact), omega_H = 1
    g = Cycloid.from_curtate_ratio(21, 22, 3.9, 0.75, 1.95)
    m = pc.ContactModel(g, pc.CycloidProfile(g), pc.ContactLaw("linear", 1e9, 1.0), 1e5, MULTIPLIER)
    theta = np.array([0.03, 0.17])
    s = m.state(theta)
    on = s.force[0] > 0
    psi = pins.pin_phase(np.arange(22)[:, None], theta[None, :], 22, REDUCER)
    ideal = (1 / 21) * (pins.pitch_distance(psi, g) - g.R_b)        # signed: v_t = omega_V (R_b - rho)
    assert np.allclose(s.v_t[0][on], ideal[on], rtol=1e-6)
    assert np.abs(s.dtau).max() < 1e-5


# ------------------------------------------------------------------ equilibrium and kinematics (§5.5, §5.6)

def _fixed_frame_moment(m, sol):
    """Moment about O1 of F n at C, recomputed in the fixed frame from first principles."""
    g = m.g
    th = sol.theta
    phi = -g.k * th / g.z1 + sol.tau
    O1 = g.e * np.array([np.cos(th), np.sin(th)])
    ct = m.contacts(m.pose(th), sol.tau)
    c, s = np.cos(phi), np.sin(phi)
    nX, nY = c * ct.nx - s * ct.ny, s * ct.nx + c * ct.ny                   # normal in the fixed frame
    j = np.arange(g.z2)[:, None]
    A = g.R_p * np.array([np.cos(2 * np.pi * j / g.z2), np.sin(2 * np.pi * j / g.z2)])
    Cx, Cy = A[0] + g.R_b * nX - O1[0], A[1] + g.R_b * nY - O1[1]
    return np.sum(sol.over_pins(g.z2).force * (Cx * nY - Cy * nX), axis=(0, 1))


@pytest.mark.parametrize("sigma", [MULTIPLIER, REDUCER])
def test_equilibrium_at_every_crank_angle_circular(sigma):
    m = circular_model(sigma=sigma)
    cyc = pc.mean_loss_ratio(m, (0.1, 0.1, False), tol=1e-5)
    sol = cyc.sol
    assert np.abs(sol.residual).max() <= 1e-10 * m.torque_sat
    M = _fixed_frame_moment(m, sol)
    assert np.allclose(M, m.M_req, rtol=1e-9)
    assert np.all(np.isfinite(sol.v_t)) and np.all(np.isfinite(sol.force))


def test_equilibrium_at_every_crank_angle_cycloid_with_clearance():
    g = Cycloid.from_curtate_ratio(20, 22, 3.9, 0.75, 1.95)
    m = pc.ContactModel(g, pc.CycloidProfile(g, equidistant_mod=0.01), pc.contact_law("hertz", face_width=10.0),
                        1.2e6, REDUCER)
    theta = np.linspace(0.0, g.period, 64)
    sol = m.state(theta)
    assert np.allclose(_fixed_frame_moment(m, sol), m.M_req, rtol=1e-9)
    assert np.all(sol.tau > 0)                  # reducer: the satellite turns forward through the clearance


def test_cycle_power_balance_with_friction_in_equilibrium():
    # pins.md §5.5: with the friction forces in the balance, the cycle work of the coupling and of the crank
    # bearing equals the cycle loss; the elastic energy stored in the contacts returns over a period
    m = circular_model(friction=(0.1, 0.1, False))
    g = m.g

    def f(th, mid):
        s = m.state(th)
        q = m.traction(s)
        Bx, By = m.bearing_force(s, q)
        ang = (g.z2 / g.z1) * th - s.tau
        w1 = -g.k / g.z1 + s.dtau
        work = -m.M_req * w1 + g.e * (-Bx * np.sin(ang) + By * np.cos(ang))
        loss, _, _ = pc.contact_losses(s, g.R_b, 0.1, 0.1, False)
        return np.stack([work, loss.sum(axis=(0, 1))])

    bp = pc.cycle_breakpoints(m, tol=1e-5)
    work, loss = (integrate_adaptive(lambda th, mid, i=i: f(th, mid)[i], bp, tol=1e-5, n_max=2 ** 11)
                  for i in (0, 1))
    assert abs(work.value[0] - loss.value[0]) <= work.err[0] + loss.err[0]
    assert abs(work.value[0] - loss.value[0]) <= 1e-5 * loss.value[0]


def test_reducer_and_multiplier_are_time_reverses_without_friction_in_the_balance():
    # pins.md §5.7: with frictionless forces the multiplier's force history is the reducer's time-reversed,
    # so lambda_bar agrees and the entry/exit asymmetry flips with the mode
    a = pc.mean_loss_ratio(circular_model(sigma=MULTIPLIER), (0.1, 0.1, False), tol=1e-7)
    b = pc.mean_loss_ratio(circular_model(sigma=REDUCER), (0.1, 0.1, False), tol=1e-7)
    assert abs(a.loss_ratio - b.loss_ratio) <= a.loss_ratio_err + b.loss_ratio_err + 1e-12
    ra = pc.engagement_metrics(a.sol, a.spin)["exit_entry_force_ratio"]
    rb = pc.engagement_metrics(b.sol, b.spin)["exit_entry_force_ratio"]
    assert ra * rb == pytest.approx(1.0, abs=2e-3)


def test_error_estimate_is_honest_against_a_finer_run():
    m = circular_model()
    coarse = pc.mean_loss_ratio(m, (0.1, 0.1, False), tol=1e-5)
    fine = pc.mean_loss_ratio(m, (0.1, 0.1, False), tol=1e-9, grid=pc.CycleGrid(n_start=1024))
    assert coarse.converged
    assert abs(coarse.loss_ratio - fine.loss_ratio) <= coarse.loss_ratio_err
    assert coarse.loss_ratio_err <= 1e-5 * coarse.loss_ratio


@pytest.mark.parametrize("rule", ["gk7", "gk15"])
@pytest.mark.parametrize("friction", [None, (0.1, 0.1, False)])
def test_gauss_kronrod_option_is_honest_and_agrees_with_the_trapezoid(rule, friction):
    # the opt-in Gauss-Kronrod rule of the cycle mean (mean_loss_ratio(rule=...)): honest against a run 1e4x
    # tighter of the default trapezoid, and fewer crank angles than the trapezoid at the same tolerance
    def lam(tol, **kw):
        return pc.mean_loss_ratio(circular_model(friction=friction), (0.1, 0.1, False), tol=tol, **kw)

    gk, trap, ref = lam(1e-6, rule=rule), lam(1e-6), lam(1e-10, grid=pc.CycleGrid(n_start=1024))
    assert gk.converged and gk.quad.rule == rule
    assert abs(gk.loss_ratio - ref.loss_ratio) <= gk.loss_ratio_err + ref.loss_ratio_err
    assert gk.loss_ratio_err <= 1e-6 * gk.loss_ratio
    assert abs(gk.loss_ratio - trap.loss_ratio) <= gk.loss_ratio_err + trap.loss_ratio_err
    # the solved crank angles: the quadrature's nodes and both one-sided ends of every piece of the breakpoints;
    # the final grid adds the pieces' interpolated states (pc.gk_interpolated, ~settings.dense_per_period of them)
    pieces = np.unique(gk.breakpoints).size - 1
    assert gk.n_crank == gk.quad.n + 2 * pieces < trap.n_crank
    assert gk.n_crank + 0.9 * pc.DEFAULT_SETTINGS.dense_per_period < gk.sol.theta.size
    assert np.all(np.diff(gk.sol.theta) >= 0.0) and np.all(np.isfinite(gk.lam))
    assert np.all(np.isin(np.unique(gk.breakpoints), gk.sol.theta))


@pytest.mark.parametrize("friction", [None, (0.1, 0.1, False)])
def test_interpolated_states_of_a_gauss_kronrod_cycle_agree_with_solved_ones(friction):
    # the interpolating polynomial of each piece's 7 Kronrod nodes (pins.md §6, §8) against the equilibrium solved
    # at the same crank angles with the piece's own sets (an independent evaluation: Newton on the moment balance)
    model = circular_model(friction=friction)
    cyc = pc.mean_loss_ratio(model, (0.1, 0.1, False), tol=1e-6, rule="gk7")
    dense = cyc.sol.theta[cyc.sol.residual == 0.0][::5]        # interpolated rows carry residual 0 (not solved)
    direct = model.state(dense, model.reference(dense), phases=False)
    i = np.searchsorted(cyc.sol.theta, dense)
    assert dense.size > 150
    # measured 2026-11-27 (213 angles): force 1.2e-7, tau 1.0e-7 of their peaks
    F_scale = cyc.sol.force.max()
    assert np.max(np.abs(cyc.sol.force[..., i] - direct.force)) <= 1e-6 * F_scale
    assert np.max(np.abs(cyc.sol.tau[i] - direct.tau)) <= 1e-6 * np.max(np.abs(cyc.sol.tau))
    # the speeds of loaded contacts (others: of no use, 0 off the window) carry d tau/d theta, whose Hertz-law
    # singularity (theta - theta_0)^(1/9) at a contact entry the polynomial resolves less well: 5.9e-5 measured
    loaded = direct.force > 0.0
    assert np.max(np.abs(cyc.sol.v_t[..., i] - direct.v_t)[loaded]) <= 1e-4 * np.max(np.abs(cyc.sol.v_t))


def test_gauss_kronrod_option_through_the_torque_fixed_point_on_a_cycloid():
    # cycle_at_torque(rule="gk7") on the paper's cycloid u10 (face width 10 mm), torque on H: the loss ratio
    # agrees with the trapezoid's within the two errors (the quadrature's plus the fixed point's remainder)
    g = Cycloid.from_curtate_ratio(20, 22, 3.9, 0.75, 2.75)
    args = (pc.ContactCase(g, pc.CycloidProfile(g, 0.0, 0.0), pc.contact_law("hertz", face_width=10.0), 1,
                           (0.1, 0.1, False), 100.0, False), True, True)
    gk, trap = pc.cycle_at_torque(*args, tol=1e-6, rule="gk7"), pc.cycle_at_torque(*args, tol=1e-6)
    assert gk.settled and gk.cycle.converged
    assert abs(gk.loss_ratio - trap.loss_ratio) <= gk.loss_ratio_err + trap.loss_ratio_err
    assert gk.cycle.n_crank < trap.cycle.n_crank


def test_free_play_of_a_clearance_cycloid_is_the_clearance_over_the_lever_arm():
    # first order: the play on one flank is min over the pins of Delta R_b/|l_i| (pins.md §4.4 lever arms)
    g = Cycloid.from_curtate_ratio(21, 22, 3.9, 0.75, 1.95)
    dRb = 1e-4
    m = pc.ContactModel(g, pc.CycloidProfile(g, equidistant_mod=dRb), pc.contact_law("linear", stiffness=1e6), 1.0,
                        REDUCER)
    theta = np.array([0.07])
    lo, hi = pc.free_play(m, theta)
    psi = pins.pin_phase(np.arange(22)[:, None], theta[None, :], 22, REDUCER)
    lev = pins.lever_arm(psi, g)
    assert hi[0] == pytest.approx(dRb / lev.max(), rel=1e-3)
    assert -lo[0] == pytest.approx(dRb / -lev.min(), rel=1e-3)


@pytest.mark.parametrize("z1, z2", [(21, 22), (20, 22), (60, 62)])
def test_backlash_of_a_small_clearance_is_its_first_order_limit(z1, z2):
    # closed-form limit: each flank's least play is Delta R_b over the largest lever arm of the ideal level (pins.md
    # §4.4) over the cycle, to first order in Delta R_b (second order: ~1e-9 relative at 1e-4 mm)
    g = Cycloid.from_curtate_ratio(z1, z2, 3.9, 0.75, 1.95)
    dRb = 1e-4
    m = pc.ContactModel(g, pc.CycloidProfile(g, equidistant_mod=dRb), pc.contact_law("linear", stiffness=1e6), 1.0,
                        REDUCER)
    lev = pins.lever_arm(np.linspace(1e-9, 2.0 * np.pi - 1e-9, 200001), g)
    assert pc.backlash(m) == pytest.approx(dRb / lev.max() + dRb / -lev.min(), rel=1e-6)


def test_backlash_is_the_least_play_of_a_dense_scan():
    # independent reference: the free play on 4097 crank angles of one period, its least value per flank; the zoomed
    # search may only find a smaller one (between the samples), by at most the scan's O(h^2) at a smooth minimum
    g = Cycloid.from_curtate_ratio(20, 22, 3.9, 0.75, 1.95)
    m = pc.ContactModel(g, pc.CycloidProfile(g, -0.01, 0.01), pc.contact_law("linear", stiffness=1e6), 1.0, REDUCER)
    lo, hi = pc.free_play(m, np.linspace(0.0, g.period, 4097))
    dense = np.abs(lo).min() + hi.min()
    j = pc.backlash(m)
    assert dense * (1.0 - 1e-6) <= j <= dense * (1.0 + 1e-13)


# ------------------------------------------------------------------ the paper's observations (§5.7(b), §10)

def test_circular_profile_loses_less_than_the_cycloid_with_rotating_pins():
    # paper: with rotating pins the circular profile's mean loss per cycle is lower than the cycloid's,
    # although its per-pin peak loss is higher (pins.md §5.7(b)); reproduced on the paper designs
    for u in ("u10", "u30"):
        circ = config_summary(f"pins_paper_circ_{u}_rotating.toml")
        cyc = config_summary(f"pins_paper_cyc_{u}_rotating.toml")
        assert circ["model"] == "contact" and cyc["model"] == "ideal"
        assert circ["loss_mean_W"] < cyc["loss_mean_W"]
        assert circ["efficiency"] > cyc["efficiency"]
        assert circ["pin_loss_max_W"] > cyc["pin_loss_max_W"]


@functools.lru_cache(maxsize=None)
def _k09(mode):
    p = CONFIGS / "pins_paper_circ_u10_rotating.toml"
    # documented admissible geometry: the paper's u = 10 circular design with K1 = 0.9 (R_p = 47.667 mm)
    return summary(p, "--set", f"gearing.pin_circle_radius_mm={3.9 * 11 / 0.9!r}", "--set", f"load.mode={mode}",
                   "--tol", "1e-5")[0]


def test_spin_reverses_between_entry_and_exit_on_a_documented_geometry():
    # paper: the pin spins one way while the tooth enters and the other way while it leaves.  Not with the
    # default K1 = 0.75 (the spin keeps its sign: a known deviation), but with K1 = 0.9
    s = _k09("multiplier")
    assert s["spin_reversals"] >= 1
    assert s["pin_speed_signed_min_rpm"] < 0 < s["pin_speed_signed_max_rpm"]
    assert s["low_spin_fraction"] > 0.05           # a phase of near-zero pin speed (paper: about a third)
    d = config_summary("pins_paper_circ_u10_rotating.toml")
    assert d["spin_reversals"] == 0 and d["low_spin_fraction"] == 0.0


def test_exit_entry_force_ratio_known_deviation():
    # paper: exit force x1.7 (u = 10) and x2.6 (u = 30) the entry force.  With convex circular teeth the load
    # sits around the tangency of the tooth circle with the pin path, nearly symmetric in time: the ratio is
    # ~1 and, frictionless, flips with the mode (time reversal).  Recorded as a known deviation (pins.md §11)
    for fname in ("pins_paper_circ_u10_rotating.toml", "pins_paper_circ_u30_rotating.toml"):
        r = config_summary(fname)["exit_entry_force_ratio"]
        assert 0.99 < r < 1.01
    assert _k09("multiplier")["exit_entry_force_ratio"] * _k09("reducer")["exit_entry_force_ratio"] == \
        pytest.approx(1.0, abs=2e-3)


@pytest.mark.parametrize("u", ["u10", "u30"])
def test_circular_configs_run_and_rotating_pins_help(u):
    fixed = config_summary(f"pins_paper_circ_{u}_fixed.toml")
    rot = config_summary(f"pins_paper_circ_{u}_rotating.toml")
    for s in (fixed, rot):
        assert s["model"] == "contact" and s["tolerance_met"] is True
        assert s["efficiency_err"] <= 1e-6 * s["loss_ratio"]
        assert s["equilibrium_residual"] < 1e-9
        assert s["pin_loss_bound_W"] >= s["pin_loss_max_W"]
        assert s["backlash_deg"] == 0.0 and s["te_pp_arcsec"] > 0
    # pins.md §10 structural trend: rotating >= fixed when mu_rot <= f
    assert rot["efficiency"] > fixed["efficiency"]
    assert rot["pin_speed_max_rpm"] > 0 and fixed["pin_speed_max_rpm"] == 0.0


# ------------------------------------------------------------------ CLI, level choice, hard cases (§7, §9)

CIRC = {
    "kind": "pins", "name": "circ",
    "gearing": {"profile": "circular", "satellite_teeth": 20, "pins": 22, "eccentricity_mm": 3.9,
                "pin_circle_radius_mm": 57.2, "pin_radius_mm": 2.75, "axle_radius_mm": 1.75, "rotating_pins": True},
    "friction": {"sliding": 0.1, "rolling_mm": 0.01, "axle": 0.1},
    "load": {"mode": "multiplier", "torque_shaft": "H", "torque_Nm": 100.0, "crank_speed_rpm": 1000.0},
    "contact": {"law": "hertz", "face_width_mm": 10.0},
}


def circ_design(tmp_path, **changes):
    return design(tmp_path, "c.toml", base=CIRC, **changes)


@pytest.mark.parametrize("changes,key,text", [
    ({"gearing__tooth_circle_radius_mm": 47.0}, "gearing.tooth_circle_radius_mm", "interfere with the pins at nominal"),
    ({"gearing__tooth_circle_radius_mm": 20.0}, "gearing.tooth_circle_radius_mm", "no contact can carry the torque"),
    ({"gearing__tooth_radius_mm": 60.0}, "gearing.tooth_radius_mm", "must be < R_p - e"),
    ({"contact__face_width_mm": None}, "contact.face_width_mm", "missing"),
    ({"contact__law": "linear"}, "contact.stiffness_N_per_mm", "missing"),
    ({"load__torque_Nm": 1e9}, "gearing.tooth_circle_radius_mm", "no contact can carry the torque"),
])
def test_circular_hard_cases_are_clear_errors(tmp_path, changes, key, text):
    code, out, err = run(circ_design(tmp_path, **changes))
    assert code == 2 and out == "" and "Traceback" not in err
    assert "c.toml" in err and key in err and text in err


def test_circular_with_model_ideal_is_an_error(tmp_path):
    code, _, err = run(circ_design(tmp_path), "--model", "ideal")
    assert code == 2 and "gearing.profile" in err and "conjugate (cycloidal)" in err


@pytest.mark.parametrize("changes,key,text", [
    # k = 1 (z1 = 21, R_p = 114.4 mm, K1 = 0.75): min rho_c = 16.33 mm < R_b + Delta R_b = 16.95 mm
    ({"gearing__equidistant_mod_mm": 15.0, "gearing__satellite_teeth": 21, "gearing__pin_circle_radius_mm": 114.4},
     "gearing.equidistant_mod_mm", "undercut"),
    ({"gearing__radial_mod_mm": -15.0}, "gearing.radial_mod_mm", "must be < 1"),
])
def test_cycloid_modification_hard_cases(tmp_path, changes, key, text):
    d = copy.deepcopy(CIRC)
    d["gearing"].update({"profile": "cycloidal", "pin_radius_mm": 1.95, "axle_radius_mm": 0.95})
    for dotted, v in changes.items():
        t, k = dotted.split("__")
        d[t][k] = v
    p = tmp_path / "m.toml"
    p.write_text(tomli_w.dumps(d))
    code, _, err = run(p)
    assert code == 2 and key in err and text in err and "Traceback" not in err


def test_explicit_small_tooth_circle_reports_backlash(tmp_path):
    s, code, _ = summary(circ_design(tmp_path, gearing__tooth_circle_radius_mm=46.5), "--tol", "1e-5")
    assert code == 0 and s["backlash_deg"] > 0 and s["tooth_circle_radius_mm"] == 46.5
    # the play, turned into pin-circle arc (R_p ~ 57 mm), is of the order of the clearance 2 x (46.68 - 46.5) mm
    assert 0.05 < math.radians(s["backlash_deg"]) * 57.2 < 1.0


def test_zero_friction_is_exact_and_tiny_torque_is_finite(tmp_path):
    s, code, _ = summary(circ_design(tmp_path, friction__sliding=0.0, friction__rolling_mm=0.0, friction__axle=0.0),
                         "--tol", "1e-4")
    assert code == 0 and s["efficiency"] == 1.0 and s["efficiency_err"] == 0.0
    s, code, _ = summary(circ_design(tmp_path, load__torque_Nm=1e-6), "--tol", "1e-4")
    assert code == 0 and 0.9 < s["efficiency"] < 1.0 and s["pin_force_max_N"] > 0


def test_linear_law_forces_scale_with_torque(tmp_path):
    # pins.md §9: with the linear law the results change with T only through geometric nonlinearity
    base = {"contact__law": "linear", "contact__stiffness_N_per_mm": 1e9, "load__torque_shaft": "V"}
    a = summary(circ_design(tmp_path, load__torque_Nm=10.0, **base), "--tol", "1e-6")[0]
    b = summary(circ_design(tmp_path, load__torque_Nm=20.0, **base), "--tol", "1e-6")[0]
    assert b["pin_force_max_N"] / a["pin_force_max_N"] == pytest.approx(2.0, rel=1e-3)


def test_contact_detail_tables(tmp_path):
    code, out, _ = run(CONFIGS / "pins_paper_circ_u10_rotating.toml", "--detail", "--format", "json", "--tol", "1e-4")
    assert code == 0
    obj = json.loads(out)
    s, crank, contacts = obj["summary"], obj["detail"]["crank"], obj["detail"]["contacts"]
    assert sum(r["loaded_pins"] for r in crank) <= len(contacts)
    assert max(r["force_N"] for r in contacts) == pytest.approx(s["pin_force_max_N"], rel=1e-12)
    te = [r["TE_arcsec"] for r in crank]
    assert max(te) - min(te) == pytest.approx(s["te_pp_arcsec"], rel=1e-12)
    assert all(r["penetration_um"] > 0 for r in contacts)


def test_two_discs_share_the_torque(tmp_path):
    one = summary(circ_design(tmp_path), "--tol", "1e-5")[0]
    two = summary(circ_design(tmp_path, gearing__discs=2), "--tol", "1e-5")[0]
    assert two["pin_force_max_N"] < 0.6 * one["pin_force_max_N"]
    assert two["efficiency"] == pytest.approx(one["efficiency"], abs=5e-3)


# ------------------------------------------------------------------ issue 15: speed, friction per mode, residual

def _fd_check_model(profile_kind):
    if profile_kind == "circular":
        return circular_model(friction=(0.1, 0.1, False))
    g = Cycloid.from_curtate_ratio(20, 22, 3.9, 0.75, 1.95)          # k = 2: crest corners
    return pc.ContactModel(g, pc.CycloidProfile(g, 0.0, 0.02), pc.contact_law("hertz", face_width=10.0), 1e6,
                           MULTIPLIER, (0.1, 0.1, False))


@pytest.mark.parametrize("profile_kind", ["circular", "cycloidal"])
def test_analytic_derivatives_match_central_differences(profile_kind):
    # pins.md §5.5-5.6: G_tau and G_theta (hence d tau/d theta = -G_theta/G_tau) analytic; reference: central
    # differences of the moment balance M(tau, theta) itself (independent of the derivative formulas)
    m = _fd_check_model(profile_kind)
    theta = np.linspace(0.01, m.g.period - 0.01, 7)
    s = m.state(theta)
    pose = m.pose(theta)
    q = m.traction(s)
    G, G_tau = m._balance(pose, s.tau, q)[:2]
    h = 1e-4 * np.abs(s.tau).max()             # round-off ~ eps R_p G_tau/(|arm| h), truncation ~ (h/tau)^2
    fd_tau = (m.moment(pose, s.tau + h, q) - m.moment(pose, s.tau - h, q)) / (2 * h)
    assert np.allclose(G_tau, fd_tau, rtol=1e-6)
    ht = 1e-6
    fd_th = (m.moment(m.pose(theta + ht), s.tau, q) - m.moment(m.pose(theta - ht), s.tau, q)) / (2 * ht)
    fd_dtau = -fd_th / fd_tau
    assert np.allclose(s.dtau, fd_dtau, rtol=1e-5, atol=1e-9)


# §4.9 reference values of an independent friction-consistent model (K1 = 0.75, fixed pins): k = 1,
# z1/z2 = 10/11, f = 0.1: eta_HV 0.83078, eta_VH 0.84594 (first-order 0.85075, 0.82457); f = 0.3: 0.52580,
# 0.62833.  The pin radius is not printed there: R_b/e = 0.9 reproduces the printed first-order pair to all
# five digits (0.850755, 0.824573; the first-order efficiency is linear in R_b), so it is the geometry used.
K1_REF = {
    "kind": "pins", "name": "k1 reference",
    "gearing": {"profile": "cycloidal", "satellite_teeth": 10, "pins": 11, "eccentricity_mm": 1.0,
                "curtate_ratio": 0.75, "pin_radius_mm": 0.9, "axle_radius_mm": 0.25, "rotating_pins": False},
    "friction": {"sliding": 0.1, "rolling_mm": 0.0, "axle": 0.0},
    "load": {"mode": "multiplier", "torque_shaft": "V", "torque_Nm": 10.0},
    "contact": {"law": "linear", "stiffness_N_per_mm": 1e9},
}


@pytest.mark.parametrize("f,model,eta_hv,eta_vh", [
    (0.1, "consistent", 0.83078, 0.84594),
    (0.3, "consistent", 0.52580, 0.62833),
    (0.1, "first-order", 0.85075, 0.82457),
])
def test_contact_friction_in_equilibrium_matches_the_reference_model(tmp_path, f, model, eta_hv, eta_vh):
    # pins.md §4.9/§5.5: each mode solved with its own forces; stiff linear law (the rigid limit)
    p = design(tmp_path, "k1.toml", base=K1_REF, friction__sliding=f, friction__model=model)
    s, code, _ = summary(p, "--model", "contact", "--tol", "1e-7")
    assert code == 0 and s["model"] == "contact"
    assert s["efficiency_reducer"] == pytest.approx(eta_hv, abs=1e-5)
    assert s["efficiency_multiplier"] == pytest.approx(eta_vh, abs=1e-5)
    assert s["efficiency"] == s["efficiency_multiplier"] and s["self_locking"] is False


def _cross(a, b):
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


def _rigid_consistent(z1, z2, K1, e, R_b, f, sigma, n=4001):
    """Independent brute-force friction-consistent rigid model (pins.md §4.9) of a k = 1 cycloid, fixed pins:
    per crank angle all pins with 0 < psi < pi load with F_i = c |l_i|; the satellite's moment balance about O1
    with the normal and friction forces gives c; the crank torque from the bearing force; efficiency from the
    cycle means of the shaft powers (uniform grid over one period, plain trapezoid; the pieces end at 0,
    T_p/2 and T_p, grid points for odd n, so the error is O(n^-2))."""
    k = z2 - z1
    R_p = e * z2 / (k * K1)
    r_p2 = e * z2 / k                               # fixed pitch circle radius
    theta = np.linspace(0.0, 2 * np.pi / z2, n)
    phi_pins = 2 * np.pi * np.arange(z2) / z2
    w_H, w_V = 1.0, -k / z1
    PH, PW = [], []
    for th in theta:
        O1 = e * np.array([np.cos(th), np.sin(th)])
        P = r_p2 * np.array([np.cos(th), np.sin(th)])
        A = R_p * np.stack([np.cos(phi_pins), np.sin(phi_pins)], axis=1)
        psi = np.mod(sigma * (phi_pins - th), 2 * np.pi)
        on = (psi > 1e-12) & (psi < np.pi - 1e-12)
        A = A[on]
        AP = A - P
        rho = np.linalg.norm(AP, axis=1)
        nvec = AP / rho[:, None]                   # from the contact point toward the pin centre
        C = A - R_b * nvec
        rel = C - P
        vel = w_V * np.stack([-rel[:, 1], rel[:, 0]], axis=1)   # satellite velocity at C relative to the pin
        vhat = vel / np.linalg.norm(vel, axis=1)[:, None]
        lever = np.abs(_cross(C - O1, nvec))
        force_dir = -nvec - f * vhat               # force of the pin on the satellite per unit normal force
        m_unit = _cross(C - O1, force_dir) * lever
        T_W = 1.0 if sigma == REDUCER else -1.0     # reducer: the coupling resists (+T); multiplier: it drives
        c = -T_W / m_unit.sum()
        assert c > 0
        B = -(force_dir * (c * lever)[:, None]).sum(axis=0)
        T_H = _cross(O1, B)
        PH.append(T_H * w_H)
        PW.append(T_W * w_V)
    PH, PW = np.trapezoid(PH, theta), np.trapezoid(PW, theta)
    return -PW / PH if sigma == REDUCER else -PH / PW


def test_brute_force_rigid_model_gives_the_reference_values():
    # the independent model in this file reproduces pins.md §4.9's printed values (checks the test's reference)
    assert _rigid_consistent(10, 11, 0.75, 1.0, 0.9, 0.1, REDUCER) == pytest.approx(0.83078, abs=1e-5)
    assert _rigid_consistent(10, 11, 0.75, 1.0, 0.9, 0.1, MULTIPLIER) == pytest.approx(0.84594, abs=1e-5)


def test_consistent_contact_agrees_with_the_brute_force_rigid_model_at_another_geometry(tmp_path):
    # k = 1, z1/z2 = 12/13, K1 = 0.6, R_b = 1.2 e, f = 0.2: the contact level (stiff linear law, friction in
    # the balance) against the independent rigid model above, to 1e-5 (pins.md §4.9 "Limits and checks")
    p = design(tmp_path, "k1b.toml", base=K1_REF, gearing__satellite_teeth=12, gearing__pins=13,
               gearing__curtate_ratio=0.6, gearing__pin_radius_mm=1.2, friction__sliding=0.2)
    s, code, _ = summary(p, "--model", "contact", "--tol", "1e-7")
    assert code == 0
    assert s["efficiency_reducer"] == pytest.approx(_rigid_consistent(12, 13, 0.6, 1.0, 1.2, 0.2, REDUCER), abs=1e-5)
    assert s["efficiency_multiplier"] == pytest.approx(_rigid_consistent(12, 13, 0.6, 1.0, 1.2, 0.2, MULTIPLIER),
                                                       abs=1e-5)


def test_reducer_jams_while_the_multiplier_runs(tmp_path):
    # pins.md §4.9: at high friction the reducer jams (no positive normal-force solution; k = 1, u = 10 at
    # f ~ 0.68) while the multiplier still runs; the jammed mode is self-locking, the other one computed
    p = design(tmp_path, "jam.toml", base=K1_REF, friction__sliding=0.9, load__mode="reducer")
    s, code, err = summary(p, "--model", "contact", "--tol", "1e-6")
    assert code == 1 and s["self_locking"] is True
    assert s["efficiency"] is None and s["efficiency_reducer"] is None
    assert 0.0 < s["efficiency_multiplier"] < 0.6
    assert "self-locking in the reducer mode" in err and "jams" in err
    s, code, _ = summary(design(tmp_path, "run.toml", base=K1_REF, friction__sliding=0.9), "--model", "contact",
                         "--tol", "1e-6")
    assert code == 0 and s["self_locking"] is False and s["efficiency_reducer"] is None
    assert s["efficiency"] == s["efficiency_multiplier"] > 0.0


def test_first_order_contact_keeps_one_loss_ratio_for_both_modes(tmp_path):
    # friction.model = "first-order" (pins.md §4.7): frictionless forces, eta_VH = 1 - lambda, eta_HV = 1/(1 + lambda)
    s = summary(circ_design(tmp_path, friction__model="first-order"), "--tol", "1e-6")[0]
    lam = s["loss_ratio"]
    assert s["efficiency_multiplier"] == pytest.approx(1.0 - lam, abs=1e-15)
    assert s["efficiency_reducer"] == pytest.approx(1.0 / (1.0 + lam), abs=1e-15)


def test_consistent_power_balance_and_mode_efficiencies_from_the_crank_torque():
    # the cycle power balance with friction in the equilibrium (pins.md §5.5): <P_H> + <P_W> = <sum P_j>; the
    # reducer's efficiency from the shaft powers <-P_W>/<P_H> equals 1/(1 + lambda_bar) within the error
    m = circular_model(sigma=REDUCER, friction=(0.1, 0.1, False))
    g = m.g

    def f(th, mid):
        s = m.state(th)
        Bx, By = m.bearing_force(s, m.traction(s))
        ang = (g.z2 / g.z1) * th - s.tau
        T_H = g.e * (np.cos(ang) * By - np.sin(ang) * Bx)          # O1 x B (satellite axes)
        loss, _, _ = pc.contact_losses(s, g.R_b, 0.1, 0.1, False)
        return np.stack([T_H, loss.sum(axis=(0, 1))])

    bp = pc.cycle_breakpoints(m, tol=1e-6)
    P_H, loss = (integrate_adaptive(lambda th, mid, i=i: f(th, mid)[i], bp, tol=1e-6, n_max=2 ** 12).value[0]
                 for i in (0, 1))
    P_W = -m.torque_sat * g.k / g.z1 * g.period                  # T_W omega_V over a period, T_W = +T_sat
    assert P_H + P_W == pytest.approx(loss, rel=1e-6)
    lam = pc.mean_loss_ratio(m, (0.1, 0.1, False), tol=1e-7).loss_ratio
    assert -P_W / P_H == pytest.approx(1.0 / (1.0 + lam), abs=1e-7)


def test_residual_above_the_tolerance_is_an_error(tmp_path, monkeypatch):
    # pins.md §5.5, issue 15 item 5: an equilibrium that is not met is an error for the design (exit 2)
    # every state evaluated 1e-4 of its rotation off the root (the solves' and the warm-started nodes' alike)
    orig = pc.ContactModel._kinematics

    def off(self, pose, tau, traction, ref=None, step=False):
        sol = orig(self, pose, tau * (1.0 + 1e-4), traction, ref)
        return (sol, np.zeros(sol.theta.size, dtype=bool)) if step else sol

    monkeypatch.setattr(pc.ContactModel, "_kinematics", off)
    code, out, err = run(circ_design(tmp_path), "--tol", "1e-4")
    assert code == 2 and out == "" and "Traceback" not in err
    assert "load.torque_Nm" in err and "too high for the contact stiffness" in err


@pytest.mark.parametrize("fname,ratio", [("pins_circ_band_u10.toml", 2.04), ("pins_circ_band_u30.toml", 1.72)])
def test_band_configs_show_the_papers_circular_profile_findings(fname, ratio):
    # pins.md §5.7(b) on a documented (fitted) geometry: in the two-touch band of the tooth radius the pin spin
    # reverses once between entry and exit, the exit force exceeds the entry force (paper: x1.7 and x2.6) and
    # part of the loaded time runs at low spin (paper: about a third); the values are this model's own
    s = config_summary(fname)
    assert s["model"] == "contact" and s["tolerance_met"] is True and s["mode"] == "multiplier"
    assert s["spin_reversals"] == 1
    assert s["exit_entry_force_ratio"] == pytest.approx(ratio, abs=0.01)
    assert 0.05 < s["low_spin_fraction"] < 0.34


def test_the_band_is_narrow(tmp_path):
    # 0.05 mm either side of the u = 10 band point the exit/entry ratio is back near 1 (README sweep)
    base = json.loads(json.dumps(CIRC))
    base["gearing"].update({"pin_circle_radius_mm": 44.227})
    for rho, lo, hi in ((3.522, 1.0, 1.4), (3.603, 0.7, 1.0)):
        p = design(tmp_path, "band.toml", base=base, gearing__tooth_radius_mm=rho)
        s = summary(p, "--tol", "1e-5")[0]
        assert lo < s["exit_entry_force_ratio"] < hi


def test_the_other_mode_seeded_by_the_mirror_gives_the_same_result():
    # the reducer started from the solved multiplier, mirrored (tau_R(-theta) = -tau_M(theta), pins.md §4.8(5)),
    # is the same cycle as the reducer solved from scratch: the seed only warm-starts and bounds the window
    g, (rho, R_t) = circ_u10(), full_u10()
    case = pc.ContactCase(g, pc.CircularProfile(g, rho, R_t), pc.contact_law("hertz", face_width=10.0), 1,
                          (0.1, 0.1, False), 100.0, False)
    m = pc.cycle_at_torque(case, True, True, tol=1e-6)
    alone = pc.cycle_at_torque(case, False, True, tol=1e-6)
    seeded = pc.cycle_at_torque(case, False, True, tol=1e-6, seed=m.model)
    assert seeded.loss_ratio == pytest.approx(alone.loss_ratio, abs=1e-3 * alone.loss_ratio_err + 1e-15)
    assert seeded.model.window is not None


def _uniform(f, edges, tol):
    """The uniform rule on the same pieces (gearcalc.quadrature.integrate_pieces, one integral, 128 intervals
    first): every piece doubled at every level."""
    from gearcalc.quadrature import integrate_pieces

    edges = np.asarray(edges, dtype=float)
    return integrate_pieces(lambda x, mid, piece: f(x, mid), edges[:-1], edges[1:], np.zeros(edges.size - 1, int),
                            tol=tol, n_start=128, n_max=2 ** 20)


def test_adaptive_quadrature_refines_only_the_pieces_that_need_it():
    # pins.md §12.6 (contact level): a piece is doubled only while its own estimate needs it.  Exact values:
    # int_0^1 1 dx + int_1^2 |x - 2| dx + int_2^3 x dx = 1 + 0.5 + 2.5 (trapezoid-exact pieces), and
    # int_3^4 e^x dx = e^4 - e^3 (closed form), which alone needs refinement
    def f(x, mid):
        return np.where(mid < 1.0, 1.0, np.where(mid < 2.0, np.abs(x - 2.0), np.where(mid < 3.0, x, np.exp(x))))

    exact = 4.0 + math.e ** 4 - math.e ** 3
    q = integrate_adaptive(f, [0.0, 1.0, 2.0, 3.0, 4.0], tol=1e-12, n_max=2 ** 14)
    assert q.converged and abs(q.value[0] - exact) <= q.err[0] <= 1e-12 * exact
    assert q.n_piece[:3].tolist() == [128, 128, 128]            # n_start/4 = 32 per piece, doubled twice only
    assert q.n_piece[3] > 128
    # the uniform rule (integrate_pieces: every piece of an integral doubled together) spends its doublings on
    # every piece
    u = _uniform(f, [0.0, 1.0, 2.0, 3.0, 4.0], tol=1e-12)
    assert abs(u.value[0] - q.value[0]) <= u.err[0] + q.err[0] and u.n[0] > q.n
    # the cap on intervals: the largest estimates are doubled first, and the result says it is unconverged
    capped = integrate_adaptive(f, [0.0, 1.0, 2.0, 3.0, 4.0], tol=1e-14, n_max=1024)
    assert not capped.converged and capped.n <= 1024 and abs(capped.value[0] - exact) <= capped.err[0]


def test_adaptive_quadrature_grades_a_boundary_layer_cheaply():
    # a geometrically graded x^(1/9) layer at 0 (the Hertz law's entry singularity, pins.md §6): the tiny
    # pieces stop after two doublings, the estimate stays honest against the closed form 9/10
    from gearcalc.quadrature import geometric_breakpoints

    edges = np.sort(np.concatenate(([0.0, 1.0], geometric_breakpoints(0.0, 1.0, 1e-8, ratio=0.25))))
    q = integrate_adaptive(lambda x, mid: x ** (1.0 / 9.0), edges, tol=1e-6)
    assert q.converged and abs(q.value[0] - 0.9) <= q.err[0] <= 1e-6 * 0.9
    u = _uniform(lambda x, mid: x ** (1.0 / 9.0), edges, tol=1e-6)
    assert q.n_piece.min() == 8 and q.n < u.n[0]


@pytest.mark.parametrize("fname,model,changes", [
    ("pins_paper_circ_u10_fixed.toml", None, {}),
    ("pins_paper_circ_u10_fixed.toml", None, {"friction.model": "first-order"}),
    ("pins_paper_circ_u30_rotating.toml", None, {}),
    ("pins_circ_band_u10.toml", None, {}),
    ("pins_paper_cyc_u10_fixed.toml", "contact", {"contact.face_width_mm": 10}),
])
def test_contact_efficiency_errors_are_honest_on_the_paper_configs(fname, model, changes):
    # pins.md §6, §12.6: the reported efficiency_err (quadrature plus the torque fixed point's remainder) bounds
    # the difference to a run 100x tighter.  (--tol 1e-8: tighter runs meet the equilibrium residual limit,
    # tol/100, only to round-off; the cycloid's reference stops at the 2^12 intervals of the contact level,
    # with its own error estimate added.)
    from gearcalc import api

    path = Path(__file__).resolve().parents[2] / "configs" / fname
    run_ = functools.partial(api.compute, str(path), model=model, overrides=changes)
    s, ref = run_(tol=1e-6).summary, run_(tol=1e-8).summary
    for mode in ("reducer", "multiplier"):
        eta, err = s[f"efficiency_{mode}"], s[f"efficiency_{mode}_err"]
        assert abs(eta - ref[f"efficiency_{mode}"]) <= err + ref[f"efficiency_{mode}_err"]
        assert abs(eta - ref[f"efficiency_{mode}"]) <= 0.5 * err     # measured: at most 0.14 of it


@pytest.mark.slow
def test_a_tiny_torque_is_an_input_error_never_a_crash():
    # issue 34: torque_Nm = 1e-20 was an IndexError in _interior_states (no sign change located: the contacts
    # never change sets), exit 70. pins.md §9: the deflections are then below the round-off of the pin positions,
    # an error naming the geometry and the torque (exit 2); the ideal level (cycloidal) computes any torque
    from conftest import CONFIGS, cli

    r = cli("pins", CONFIGS / "pins_paper_circ_u10_fixed.toml", "--set", "load.torque_Nm=1e-20", "--format", "csv")
    assert r.code == 2 and "cannot resolve this geometry" in r.err and "load.torque_Nm = 1e-20" in r.err, r
    assert "internal error" not in r.err, r


def test_interior_states_without_a_located_sign_change():
    # the stretch around every midpoint is then the whole period: the nearest state solved, whatever its place
    # (real solved states: no patch of the module's helpers)
    from types import SimpleNamespace

    import gearcalc.pins.contact_cycle as cc

    g = pc.Cycloid.from_curtate_ratio(21, 22, 3.9, 0.75, 1.95)
    model = pc.ContactModel(g, pc.CycloidProfile(g, 0.0, 0.0), pc.contact_law("linear", stiffness=1e5), 1e4,
                            pc.MULTIPLIER)
    seen = model.state(np.array([0.1, 0.5, 0.9]) * g.period, phases=False)
    found = SimpleNamespace(seen=[seen], roots=np.empty(0))
    col, known = cc._interior_states(found, np.array([0.2, 0.8]) * g.period, g.period,
                                     cc.DEFAULT_SETTINGS.interior_margin)
    assert col.tolist() == [0, 2] and np.array_equal(known.theta, seen.theta)


# ================================================================== the torque fixed point (pins.md §6(6), §7)
# (moved from tests/test_pins_fixed_point.py) The designs are shipped configs with changed keys: K1 = e z2/(k R_p)
# = 1.95 x 21/57.2 = 0.716 (u10) and 1.95 x 61/161.2 = 0.738 (u30), both admissible cycloid-wise too.
# Independent references used: the same operating point computed with the torque given on V (one pass, no fixed
# point) at the T_V the fixed point reports; the fixed point of the code before the contact speed-up
# (eta_VH = 0.1905224); a fresh solve (no warm start, its own window) at the same torque.

U10 = str(CONFIGS / "pins_paper_circ_u10_fixed.toml")
U30 = str(CONFIGS / "pins_paper_circ_u30_fixed.toml")
K1_U10 = {"gearing.pins": 21, "gearing.eccentricity_mm": 1.95, "friction.sliding": 1.0, "friction.model": "first-order"}
K1_U30 = {"gearing.pins": 61, "gearing.eccentricity_mm": 1.95, "friction.sliding": 1.0, "friction.model": "first-order"}


def _summary(path, overrides, tol=1e-6):
    return api.compute(path, overrides=overrides, model="contact", tol=tol).summary


# ------------------------------------------------------------------ the fixed point's step and remainder

def test_fixed_point_step_remainder_is_never_negative_and_refuses_a_locked_multiplier():
    # a multiplier whose loss ratio passed 1 has no T_V = u T_H/(1 - lambda): no contraction, no step (before the
    # fix the contraction was computed with 1 - lambda < 0: a negative c, a negative remainder, a false exit)
    assert pc._fixed_point_step([0.92, 1.07], [11648.0, 25413.0], 2000.0, -1.0) == (math.inf, None)
    rng = np.random.default_rng(7)
    for _ in range(200):
        lam = rng.uniform(0.0, 0.99, 2)
        T = rng.uniform(1.0, 1e4, 2)
        for a in (-1.0, 1.0):
            r, step = pc._fixed_point_step(list(lam), list(T), 100.0, a)
            assert r >= 0.0
            assert step is None or step > 0.0


def test_fixed_point_step_on_a_linear_loss_ratio_lands_on_the_fixed_point():
    # lambda(T) = 0.1 + 0.01 (T - 10), reducer: T (1 + lambda) = 10 -> T (1 + 0.01 T) = 10 (closed form); lambda
    # linear, so the secant slope is exact and one Newton step of the quadratic is within (T - T*)^2 0.01/phi'
    T_star = (-1.0 + math.sqrt(1.4)) / 0.02
    lam = lambda t: 0.1 + 0.01 * (t - 10.0)                      # noqa: E731
    T = [10.0, 11.0]
    for _ in range(4):
        r, step = pc._fixed_point_step([lam(t) for t in T], T, 10.0, 1.0)
        T.append(step)
    assert T[-1] == pytest.approx(T_star, rel=1e-12)
    assert r == pytest.approx(abs(lam(T[-2]) - lam(T_star)), rel=1e-3, abs=1e-15)


def test_locked_multiplier_has_a_nonnegative_error_that_holds_the_last_change():
    # k1_circ_z20_21_e195, f = 1, first-order: before the fix efficiency_reducer_err = -0.0211 and
    # loss_ratio_err = -0.0907 ("loss ratio 1.074749188 +- -0.0907" at a tighter tol)
    s = _summary(U10, K1_U10)
    assert s["curtate_ratio"] == pytest.approx(1.95 * 21 / 57.2)
    assert s["self_locking"] is True and s["loss_ratio"] >= 1.0
    assert s["loss_ratio_err"] >= 0.0 and s["efficiency_reducer_err"] >= 0.0
    # the fixed point's passes: T_V grows with lambda and lambda with T_V (0.921 at 11648 N m, 1.003 at 25413)
    assert s["loss_ratio_err"] > 0.01


@pytest.mark.parametrize("c, lam0, expect", [
    # a preload loss L(T) = c + lam0 T (linear: the secant is exact): the reducer's fixed point T + L(T) = u T_H
    # has the root T* = (u T_H - c)/(1 + lam0), positive iff c < u T_H (closed form; u T_H = 10 here)
    (70.0, 0.0, True), (10.0, 0.5, True), (12.0, 3.0, True),
    (9.0, 0.5, False),            # L >= u T_H at both passes (T = 3, 2.5), but T* = 0.67 > 0: no stall
    (0.0, 0.1, False),            # an ordinary reducer: L << u T_H
])
def test_reducer_stalls_exactly_when_the_preload_fixed_point_has_no_positive_torque(c, lam0, expect):
    T = [3.0, 2.5]
    history = [(c + lam0 * t) / t for t in T]
    L_ok = all(h * t >= 10.0 for h, t in zip(history, T))
    assert pc.reducer_stalls(history, T, 10.0) is (expect and L_ok)
    assert (10.0 - c) / (1.0 + lam0) > 0.0 or not L_ok or expect


def test_reducer_with_interfering_teeth_self_locks_in_two_passes_not_eight(monkeypatch):
    # equidistant modification -1.9 mm of the paper's u = 10 cycloid: the teeth interfere with the pins, the loss
    # stays ~7e7 N mm per crank radian at any torque, so lambda ~ 1/T_V; before the stall rule the reducer's fixed
    # point halved T_V for 8 passes (lambda 129 -> 8e16, 26 s) and reported efficiency_reducer = 1.2e-17
    cyc = str(CONFIGS / "pins_paper_cyc_u10_fixed.toml")
    ov = {"gearing.equidistant_mod_mm": -1.9, "contact.face_width_mm": 10.0, "load.mode": "reducer",
          "friction.model": "first-order"}
    torques, run = [], pc.mean_loss_ratio

    def counted(model, *a, **k):
        torques.append(model.torque_sat)
        return run(model, *a, **k)

    monkeypatch.setattr(pc, "mean_loss_ratio", counted)
    r = api.compute(cyc, overrides=ov, model="contact", tol=1e-6)
    assert r.summary["self_locking"] is True and r.summary["efficiency_reducer"] is None
    assert any("losses alone exceed the input power" in f for f in r.failed)
    assert len(set(torques)) == 2                             # two passes of the fixed point, then the stall
    assert r.summary["loss_ratio"] > 1.0 / 1e-3               # the losses dwarf the output at the last pass


def _sample(name, profile, z1, z2, e, K1, R_b, r, mode):
    """A design of the guards' random sample (kinds/test_pins._random_pins_design): rotating pins, f = 0.1,
    100 N*m on H, Hertz contacts of 10 mm."""
    return {"kind": "pins", "name": name, "gearing": {
        "profile": profile, "satellite_teeth": z1, "pins": z2, "eccentricity_mm": e, "curtate_ratio": K1,
        "pin_radius_mm": R_b, "axle_radius_mm": r, "rotating_pins": True},
        "friction": {"sliding": 0.1, "rolling_mm": 0.01, "axle": 0.1},
        "load": {"mode": mode, "torque_shaft": "H", "torque_Nm": 100.0, "crank_speed_rpm": 1000.0},
        "contact": {"law": "hertz", "face_width_mm": 10.0}}


@pytest.fixture
def cycles(monkeypatch):
    """The :class:`~gearcalc.pins.contact.TorqueCycle` of every cycle_at_torque call of the test, in order."""
    runs, orig = [], pc.cycle_at_torque

    def recorded(*a, **k):
        runs.append(orig(*a, **k))
        return runs[-1]

    monkeypatch.setattr(pc, "cycle_at_torque", recorded)
    return runs


WANDERING = _sample("z 3/5 circular, rotating pins", "circular", 3, 5, 2.215, 0.811, 2.446, 1.433, "reducer")
"""A design of the guards' random sample (seed 13, no. 29) whose loss ratio jumps with the torque: the
number of pieces of its cycle changes between 29 and 50 from one pass to the next."""


def test_a_wandering_fixed_point_stops_after_four_passes_with_its_spread_as_error(cycles):
    # before: eight passes (0.130, 0.129, 0.119, 0.122, 0.129, 0.127, 0.120, 0.123; 2.7 s) and an error of the last
    # change only (0.002); now four passes and their spread in the error (2026-11-27: 0.1235, 0.1259, 0.1302, 0.1274,
    # spread 0.0067; the pieces' sets taken from the breakpoint search's states: spread 0.0029)
    assert pc.fixed_point_stalls([0.1303, 0.1295, 0.1193, 0.1224])
    r = api.compute(WANDERING, model="contact", tol=1e-3)
    s = r.summary
    assert not s["tolerance_met"]
    assert any("did not settle in 4 passes" in w for w in r.warnings)
    # the reducer (the requested mode); the multiplier wanders too since it scans its own breakpoints (2026-11-27:
    # 0.1001, 0.0927, 0.0919, 0.0910, 0.0916, five passes), and settled when it moved the reducer's, mirrored: which
    # passes settle on this design of several equilibria depends on the path (pins.md §7), both are flagged
    reducer = next(tc for tc in cycles if tc.model.sigma == REDUCER)
    assert not reducer.settled
    history = reducer.history
    assert len(history) == 4
    assert s["loss_ratio_err"] >= max(history) - min(history) > 1e-3


@pytest.mark.xfail(strict=True, reason="known defect, pins.md §7 'Several equilibria': the satellite turns by up to "
                                       "0.44 rad under this load and the pieces' sets hold another equilibrium than "
                                       "the angles solved one by one (0.1210 against 0.1109)")
def test_the_wandering_designs_cycle_is_the_mean_of_its_states_solved_angle_by_angle(cycles):
    # an independent reference: the uniform mean of lambda over 8192 crank angles, each solved on its own (its own
    # active set and friction directions; O(1/N) at the jumps, ~1e-4 here); the cycle at the same torque on V
    on_V = {**WANDERING, "load": {**WANDERING["load"], "torque_shaft": "V", "torque_Nm": 133.5}}
    s = api.compute(on_V, model="contact", tol=1e-3).summary
    t = next(r for r in cycles if r.model.sigma == REDUCER)
    m = t.model
    R_b, mu, f, rolls, scale = t.cycle.friction
    theta = (np.arange(8192) + 0.5) * (m.g.period / 8192)
    ref = pc.ContactModel(m.g, m.profile, m.law, m.torque_sat, m.sigma, m.friction)
    ref.set_window()
    lam = float(np.mean(pc.contact_losses(ref.state(theta, phases=False), R_b, mu, f, rolls)[0].sum(axis=(0, 1))))
    assert abs(s["loss_ratio"] - lam / scale) <= s["loss_ratio_err"] + 1e-3 * lam / scale


# ------------------------------------------------------------------ the fixed point is the fixed point

def test_torque_on_H_and_the_same_point_with_the_torque_on_V_agree_within_their_errors():
    # k1_circ_z60_61_e195, f = 1, first-order, multiplier: before the fix eta_VH = 0.1918566518 +- 2.6e-7 (the
    # window carried to a higher torque left out pins that touch there); the code before the contact speed-up
    # gave 0.1905224; with the torque on V at T_V = u T_H/eta (one pass, no fixed point) 0.19052178
    on_H = _summary(U30, K1_U30)
    assert on_H["tolerance_met"] is True
    T_V = 60.0 * 100.0 / on_H["efficiency"]
    on_V = _summary(U30, {**K1_U30, "load.torque_shaft": "V", "load.torque_Nm": T_V})
    assert abs(on_H["efficiency"] - on_V["efficiency"]) <= on_H["efficiency_err"] + on_V["efficiency_err"]
    assert on_V["torque_out_Nm"] == pytest.approx(100.0, rel=10.0 * on_H["efficiency_err"] / on_H["efficiency"])
    assert on_H["efficiency"] == pytest.approx(0.1905224, abs=1e-6)
    assert on_H["efficiency_err"] < 1e-6


# ------------------------------------------------------------------ passes that run out

def test_a_fixed_point_that_does_not_settle_is_not_a_met_tolerance(monkeypatch):
    # two passes are not enough for k1_circ_z60_61_e195 (the loss ratio changes by 5.7e-3 between them): the
    # warning, tolerance_met false, and the error holds the last change
    orig = pc.cycle_at_torque
    runs = []

    def two_passes(*args, **kw):
        kw["passes"] = 2
        runs.append(orig(*args, **kw))
        return runs[-1]

    monkeypatch.setattr(pc, "cycle_at_torque", two_passes)
    res = api.compute(U30, overrides=K1_U30, model="contact", tol=1e-6)
    s = res.summary
    tc = runs[0]
    assert not tc.settled and len(tc.history) == 2
    assert s["tolerance_met"] is False
    assert s["loss_ratio_err"] >= abs(tc.history[-1] - tc.history[-2]) > 1e-3
    assert any("did not settle in 2 passes" in w for w in res.warnings)
    assert any("tolerance 1e-06 not met" in w for w in res.warnings)


# ------------------------------------------------------------------ texts, fields, warnings

@pytest.mark.parametrize("model", [None, "first-order"])
def test_contact_summary_names_the_friction_model(model):
    s = _summary(U10, {} if model is None else {"friction.model": model})
    assert s["friction_model"] == (model or "consistent")


def test_no_numpy_warning_when_a_mode_jams_at_K1_above_1():
    # the circular u10 config with pins = 21: K1 = 3.9 x 21/57.2 = 1.43 (a circular profile has no curtate-ratio
    # rule, pins.md §9 names it for the cycloid); at f = 1 the multiplier jams (lambda_bar = inf, eta_HV = 0):
    # before the fix shaft_torques divided by it and numpy warned "divide by zero"
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        s = _summary(U10, {"gearing.pins": 21, "friction.sliding": 1.0})
        T_V, T_H = shaft_torques(np.array([100.0]), 10.0, np.array([np.nan]), np.array([0.0]), np.array([False]),
                                 np.array([True]))
        et = efficiency_torques(np.array([np.inf]), np.array([np.nan]), np.array([100.0]), 10.0, np.array([True]),
                                np.array([False]))
    assert s["self_locking"] is True and s["curtate_ratio"] > 1.0
    assert math.isinf(T_H[0]) and bool(et.locked[0])


FAR = _sample("z 6/10 circular, rotating pins", "circular", 6, 10, 4.155, 0.5, 3.462, 2.385, "multiplier")
"""Design no. 52 of the guards' random sample (seed 13): its cycle held, with a stated error of 4e-6, a
reducer loss ratio 0.180 where the crank angles solved one by one give 0.198 (pins.md §7 "Several equilibria")."""


@pytest.mark.parametrize("design,held", [(WANDERING, False), (FAR, True)])
def test_designs_whose_satellite_turns_far_beyond_a_deflection_are_flagged(design, held):
    # pins.md §6-7: a pin centre that moves by more than travel_max of its radius under the load (here 1.6 and 0.7;
    # the paper designs 0.004-0.042), and a cycle whose nodes contradict their pieces even on the densest scan, are
    # flagged: tolerance_met false and a warning naming the cause, instead of a loss ratio 2-15 % off its reference
    r = api.compute(design, model="contact", tol=1e-3)
    assert r.summary["tolerance_met"] is False
    assert any("a pin centre moves by" in w and "not a deflection" in w for w in r.warnings)
    assert any("does not hold" in w for w in r.warnings) is not held


def test_a_satellite_turning_beyond_a_deflection_is_not_scanned_denser(cycles):
    # pins.md §6: a cycle whose nodes contradict their pieces is scanned 4x denser (to 4096 angles) only where the
    # satellite turns by a deflection; beyond it (here 1.6 of the pin radius) the cycle is flagged whatever the scan,
    # and the denser scans at the quadrature's cap cost seconds a pass (a random design, seed 103 no. 34, 13.4 s ->
    # 5.8 s); the warning says the scan was not refined
    r = api.compute(WANDERING, model="contact", tol=1e-3)
    far = [t for t in cycles if not pc.deflection_sized(t.cycle.sol.tau, t.model.g)]
    assert far and all(t.model.scan_n < 1024 for t in far)
    assert any("does not hold" in w and "not denser" in w for w in r.warnings)
    assert r.summary["tolerance_met"] is False


def test_paper_designs_turn_by_a_deflection(cycles):
    # the paper's u = 10 circular-arc design: a pin centre moves by 0.042 of its radius at most, below travel_max
    r = api.compute(CONFIGS / "pins_paper_circ_u10_fixed.toml", model="contact")
    travel = [pc.pin_travel(t.cycle.sol.tau, t.model.g) for t in cycles]
    assert max(travel) == pytest.approx(0.042, abs=0.001) and max(travel) < pc.DEFAULT_SETTINGS.travel_max
    assert r.summary["tolerance_met"] is True and not any("pin centre" in w for w in r.warnings)


def test_an_unconverged_cycle_mean_stops_the_fixed_point_at_its_own_error(monkeypatch, cycles):
    # pins.md §7: when the cycle mean did not converge (its quadrature at the cap of its angles, here 2^6 instead of
    # 2^12 at tol 1e-9), the fixed point stops once its remaining change is below that mean's own error: more passes
    # would refine what the error swamps (a random design, seed 103 no. 34, took eight passes and 19.7 s before,
    # 13.4 s after).  The band design u = 30, first-order (one mode), whose loss ratio moves with the torque
    # (d ln lambda/d ln T = -0.15): three passes without the rule, two with it.  Reference: the same design with the
    # cap of 2^12 (converged), within the capped run's stated error (1.9e-8 against 4.7e-8)
    original = pc.mean_loss_ratio

    def capped(model, friction, tol=1e-6, grid=None, *a, **k):
        grid = dataclasses.replace(pc.CycleGrid() if grid is None else grid, n_max=2 ** 6)   # the cap on angles
        return original(model, friction, tol, grid, *a, **k)

    path = str(CONFIGS / "pins_circ_band_u30.toml")
    over = {"friction.model": "first-order"}
    monkeypatch.setattr(pc, "mean_loss_ratio", capped)      # the fixed point's passes
    monkeypatch.setattr(pcc, "mean_loss_ratio", capped)     # and the quadrature's own retries
    s = _summary(path, over, tol=1e-9)
    tc = cycles[-1]
    assert not tc.cycle.converged and not s["tolerance_met"]
    assert tc.settled and len(tc.history) == 2
    assert tc.loss_ratio_err >= tc.cycle.loss_ratio_err
    monkeypatch.setattr(pc, "mean_loss_ratio", original)
    monkeypatch.setattr(pcc, "mean_loss_ratio", original)
    ref = _summary(path, over, tol=1e-9)
    assert ref["tolerance_met"]
    assert abs(s["loss_ratio"] - ref["loss_ratio"]) <= s["loss_ratio_err"]
