"""Property-based tests (issue 7) of the ``pins`` calculator, end to end on random valid designs.

tests/pins/test_geometry.py holds the physics-level properties (``loss_ratio``, ``pin_forces`` and the
Willis forms over random gears).  This file checks the identities of pins.md on what
``CALCULATOR.compute`` returns for random TOML designs (cycloidal gears with k = 1..3, fixed or
rotating pins, one to three discs, both modes, torque on either shaft, with or without a crank
speed, with or without the paper's [pin_load] table), at every level the design allows, with the
crank-angle and contact detail tables.  Each test names the spec section (docs/spec/pins.md).
"""
import copy
import math

import numpy as np
import pytest
from hypothesis import given, reject, settings
from hypothesis import strategies as st

from gearcalc import registry
from gearcalc.calculator import DesignError, Options
from gearcalc.design import validate
from props_common import assert_all_finite, in_schema


CALC = registry.get("pins")
SCHEMA = {t.name: {f.name: f for f in t.fields} for t in CALC.tables}
PROPS = settings(max_examples=30, deadline=None, derandomize=True)
CONTACT = settings(max_examples=3, deadline=None, derandomize=True)


# ------------------------------------------------------------------ helpers
ADMISSIBILITY_KEYS = ("gearing.satellite_teeth", "gearing.pin_radius_mm")


def run(raw, model=None, detail=True, tol=1e-6):
    """Compute a design; a gear that the calculator finds inadmissible (too few teeth for k, undercut:
    pins.md §4.2, §12.10, which only the physics can decide) is rejected, not failed."""
    design = validate(copy.deepcopy(raw), "<hyp>")
    try:
        return CALC.compute(design, Options(tol=tol, model=model, detail=detail))
    except DesignError as exc:
        if exc.key in ADMISSIBILITY_KEYS:
            reject()
        raise


# ------------------------------------------------------------------ the design strategy
@st.composite
def designs(draw, rotating=None, discs=None, speed=None, pin_load=None, profile="cycloidal", mode=None,
            shaft=None):
    """A random valid pins design (dict as read from TOML).

    z1 6..60, k 1..3, K1 0.3..0.95, e 0.5..5 mm, R_b = (0.05..0.5) R_p sin(pi/z2) (no overlap),
    axle r = (0.1..0.8) R_b, friction f 0..0.3, f_k 0..0.05 mm, f_c 0..0.3, torque 1e-2..1e4 N*m on H
    or V, crank speed 10..5000 rpm or none, 1..3 discs."""
    z1 = draw(st.integers(6, 60))
    k = draw(st.integers(1, 3))
    z2 = z1 + k
    K1 = draw(st.floats(0.3, 0.95))
    e = draw(st.floats(0.5, 5.0))
    Rp = e * z2 / (k * K1)
    Rb = draw(st.floats(0.05, 0.5)) * Rp * math.sin(math.pi / z2)
    g = {"profile": profile, "satellite_teeth": z1, "pins": z2, "eccentricity_mm": e, "pin_radius_mm": Rb,
         "rotating_pins": draw(st.booleans()) if rotating is None else rotating,
         "discs": draw(st.integers(1, 3)) if discs is None else discs}
    if draw(st.booleans()):
        g["curtate_ratio"] = K1
    else:
        g["pin_circle_radius_mm"] = Rp
    if g["rotating_pins"] or draw(st.booleans()):
        g["axle_radius_mm"] = draw(st.floats(0.1, 0.8)) * Rb
    raw = {
        "kind": "pins", "name": "hyp", "gearing": g,
        "friction": {"sliding": draw(st.floats(0.0, 0.3)), "rolling_mm": draw(st.floats(0.0, 0.05)),
                     "axle": draw(st.floats(0.0, 0.3)),
                     # the first-order model (pins.md §4.6-4.7), whose laws these properties state
                     "model": "first-order"},
        "load": {"mode": mode or draw(st.sampled_from(["multiplier", "reducer"])),
                 "torque_shaft": shaft or draw(st.sampled_from(["H", "V"])),
                 "torque_Nm": 10 ** draw(st.floats(-2.0, 4.0))},
    }
    if draw(st.booleans()) if speed is None else speed:
        raw["load"]["crank_speed_rpm"] = draw(st.floats(10.0, 5000.0))
    if draw(st.booleans()) if pin_load is None else pin_load:
        R = draw(st.floats(0.5, 5.0))
        raw["pin_load"] = {"normal_force_N": 10 ** draw(st.floats(0.0, 5.0)),
                           "pin_speed_rpm": draw(st.floats(0.1, 1000.0)), "pin_radius_mm": R,
                           "axle_radius_mm": draw(st.floats(0.05, 0.95)) * R}
    return in_schema(raw)


def omegas(s, raw):
    """(|omega_H|, |omega_V|) [rad/s]; omega_V = omega_H k/z1 (pins.md §2)."""
    w_h = math.pi * raw["load"]["crank_speed_rpm"] / 30.0
    return w_h, w_h / s["ratio"]


# ------------------------------------------------------------------ 1. no NaN or infinity anywhere
@pytest.mark.slow
@PROPS
@given(designs())
def test_every_output_finite_at_every_level(raw):
    # interface.md "Output": no NaN or infinity is ever a result; pins.md §7 "Which level runs":
    # a cycloid without modifications runs ideal, [pin_load] adds (or alone is) the formula level
    levels = [None, "ideal"] + (["formula"] if "pin_load" in raw else [])
    for model in levels:
        res = run(raw, model=model)
        assert_all_finite(res)
        s = res.summary
        assert s["model"] == res.model == (model or "ideal")
        if "pin_load" in raw:
            assert all(s[k] is not None for k in ("F_tr1_N", "F_tr2_N", "P_tr1_W", "P_tr2_W", "P_tr_W"))
        if model == "formula":       # pins.md §12.3: the cycle fields are null at the formula level
            assert s["efficiency"] is None and s["mode"] is None
            continue
        # pins.md §12.4: without a crank speed, powers and speeds are null (never NaN)
        if "crank_speed_rpm" not in raw["load"]:
            assert s["loss_mean_W"] is None and s["pin_loss_max_W"] is None and s["pin_speed_max_rpm"] is None
        assert run(raw, model=model, detail=False).summary.keys() == s.keys()


# ------------------------------------------------------------------ 2. efficiency, Willis, torques
@PROPS
@given(designs())
def test_efficiency_bounds_self_locking_and_willis(raw):
    res = run(raw, detail=False)
    s = res.summary
    lam, E = s["loss_ratio"], s["loss_ratio_err"]
    z1, z2 = raw["gearing"]["satellite_teeth"], raw["gearing"]["pins"]
    k = z2 - z1
    assert s["ratio"] == z1 / k
    assert lam >= 0 and E >= 0
    # pins.md §4.7: eta_HV = 1/(1 + lambda) in (0, 1]; eta_VH = 1 - lambda, or self-locking (null)
    assert 0 < s["efficiency_reducer"] <= 1
    assert s["efficiency_reducer"] == pytest.approx(1 / (1 + lam), rel=1e-14)
    assert s["efficiency_reducer_err"] == pytest.approx(E / (1 + lam) ** 2, rel=1e-12, abs=1e-300)
    locked = lam >= 1
    if locked:
        assert s["efficiency_multiplier"] is None
    else:
        assert 0 < s["efficiency_multiplier"] <= 1
        assert s["efficiency_multiplier"] == pytest.approx(1 - lam, rel=1e-14, abs=1e-15)
        assert s["efficiency_multiplier_err"] == E
        # pins.md §4.8 identity 5: eta_HV = 1/(2 - eta_VH) whenever neither self-locks
        assert s["efficiency_reducer"] == pytest.approx(1 / (2 - s["efficiency_multiplier"]), rel=1e-13)
    multiplier = raw["load"]["mode"] == "multiplier"
    # pins.md §4.7: self_locking flags the multiplier with lambda >= 1; never a negative efficiency
    assert s["self_locking"] == (locked and multiplier)
    assert bool(res.failed) == (s["self_locking"] or s["rolling_ok"] is False)  # the rolling check: issue 36
    assert ("self_locking" in s["failed_checks"]) == s["self_locking"] == (s["margin_self_locking"] < 0)
    if s["self_locking"]:
        assert s["efficiency"] is None and s["efficiency_err"] is None
    else:
        assert 0 < s["efficiency"] <= 1
        assert s["efficiency"] == (s["efficiency_multiplier"] if multiplier else s["efficiency_reducer"])
    # pins.md §4.7 Willis cross-check: psi0 = lambda k/z2, eta0 = 1 - psi0;
    # eta_VH = (z2 eta0 - z1)/k identically; eta_HV - eta_HV^W = lambda psi0/((1 + lambda)(1 + u psi0)) >= 0
    psi0 = lam * k / z2
    eta0 = 1 - psi0
    assert (z2 * eta0 - z1) / k == pytest.approx(1 - lam, rel=1e-12, abs=1e-12)
    assert (eta0 <= z1 / z2 * (1 + 1e-15)) == locked or abs(lam - 1) < 1e-12
    eta_w = k * eta0 / (z2 - z1 * eta0)
    diff = s["efficiency_reducer"] - eta_w
    assert diff >= -1e-15
    # (abs 1e-13: z2 - z1 eta0 cancels to ~1 + u psi0, losing ~z2 ulp in the test's own arithmetic)
    assert diff == pytest.approx(lam * psi0 / ((1 + lam) * (1 + (z1 / k) * psi0)), rel=1e-9, abs=1e-13)


@PROPS
@given(designs(speed=True))
def test_torques_and_power_balance(raw):
    # pins.md §4.7: multiplier T_V = u T_H/eta_VH, reducer T_V = eta_HV u T_H; input = output + loss,
    # with the loss lambda_bar T_V |omega_V| (§4.6)
    res = run(raw, detail=False)
    s = res.summary
    if s["self_locking"]:
        return                              # no T balances T_H (torques null, tested above)
    u, eta = s["ratio"], s["efficiency"]
    t_in, t_out = s["torque_in_Nm"], s["torque_out_Nm"]
    multiplier = raw["load"]["mode"] == "multiplier"
    given_on_input = (raw["load"]["torque_shaft"] == "V") == multiplier
    assert (t_in if given_on_input else t_out) == raw["load"]["torque_Nm"]
    w_h, w_v = omegas(s, raw)
    if multiplier:                          # V drives H
        assert t_out * u == pytest.approx(eta * t_in, rel=1e-12)
        p_in, p_out, t_v = t_in * w_v, t_out * w_h, t_in
    else:                                   # H drives V
        assert t_out == pytest.approx(eta * u * t_in, rel=1e-12)
        p_in, p_out, t_v = t_in * w_h, t_out * w_v, t_out
    assert s["loss_mean_W"] == pytest.approx(s["loss_ratio"] * t_v * w_v, rel=1e-12, abs=1e-300)
    assert s["loss_mean_W"] == pytest.approx(p_in - p_out, rel=1e-9, abs=1e-12 * p_in)
    # pins.md §8: the peak of the total loss over the cycle is at least its mean (within the mean's
    # error); the eq. (7) bound (peak force x peak speed) is >= the true per-pin peak
    assert s["loss_peak_W"] >= s["loss_mean_W"] - s["loss_ratio_err"] * t_v * w_v * (1 + 1e-9) - 1e-15 * p_in
    assert s["pin_loss_bound_W"] >= s["pin_loss_max_W"] * (1 - 1e-12)


# ------------------------------------------------------------------ 3. scaling laws of the ideal level
@pytest.mark.slow
@PROPS
@given(designs(speed=True), st.floats(1e-3, 1e3), st.floats(1e-2, 1e2), st.floats(0.01, 10.0))
def test_lambda_independent_of_torque_and_speed_linear_in_friction(raw, kt, kn, kf):
    base = run(raw, detail=False).summary
    # pins.md §4.8 identity 8: lambda depends neither on the torque nor on the speed; F ∝ T, and the
    # powers scale with T n, the pin speeds with n
    other = copy.deepcopy(raw)
    other["load"]["torque_Nm"] *= kt
    other["load"]["crank_speed_rpm"] *= kn
    o = run(other, detail=False).summary
    for key in ("loss_ratio", "loss_ratio_err", "efficiency", "efficiency_reducer", "efficiency_multiplier"):
        assert o[key] == base[key], key
    scaled = {"pin_force_max_N": kt, "loss_mean_W": kt * kn, "pin_loss_max_W": kt * kn, "loss_peak_W": kt * kn,
              "pin_speed_max_rpm": kn, "torque_in_Nm": kt, "torque_out_Nm": kt}
    for key, factor in scaled.items():
        if base[key] is not None:
            assert o[key] == pytest.approx(factor * base[key], rel=1e-12, abs=1e-300), key
    # pins.md §4.6 and §4.8 identity 8: lambda ∝ mu_eff; scaling f, f_k and f_c together scales
    # mu_eff (f, or mu_rot = (f_c r + f_k)/R_b) and keeps the rolling condition f R_b >= f_c r + f_k
    rough = copy.deepcopy(raw)
    for key in ("sliding", "rolling_mm", "axle"):
        rough["friction"][key] *= kf
    r = run(rough, detail=False).summary
    assert r["rolling_ok"] == base["rolling_ok"]
    assert r["loss_ratio"] == pytest.approx(kf * base["loss_ratio"], rel=1e-12, abs=1e-300)


@pytest.mark.slow
@PROPS
@given(designs(mode="multiplier"))
def test_modes_share_lambda_and_zero_friction_is_lossless(raw):
    # pins.md §4.8 identity 5: lambda_reducer(theta) = lambda_multiplier(-theta): the same mean
    mult = run(raw, detail=False).summary
    red_raw = copy.deepcopy(raw)
    red_raw["load"]["mode"] = "reducer"
    red = run(red_raw, detail=False).summary
    assert red["loss_ratio"] == pytest.approx(mult["loss_ratio"], rel=1e-9, abs=1e-15)
    assert abs(red["loss_ratio"] - mult["loss_ratio"]) <= red["loss_ratio_err"] + mult["loss_ratio_err"] + 1e-15
    # pins.md §9 and §4.8 identity 8: f = f_k = f_c = 0 gives eta = 1 exactly, error 0
    ideal = copy.deepcopy(raw)
    ideal["friction"] = {**ideal["friction"], "sliding": 0.0, "rolling_mm": 0.0, "axle": 0.0}
    s = run(ideal, detail=False).summary
    assert s["efficiency"] == 1.0 and s["efficiency_err"] == 0.0 and s["loss_ratio"] == 0.0
    assert s["efficiency_reducer"] == 1.0 and s["efficiency_multiplier"] == 1.0


@PROPS
@given(designs(rotating=True))
def test_rotating_pins_beat_fixed_when_mu_rot_below_f(raw):
    # pins.md §10 "Trend checks" (structural): rotating >= fixed whenever mu_rot <= f; and the
    # rolling condition (§4.5) decides whether the bushings turn at all
    g, fr = raw["gearing"], raw["friction"]
    mu_rot = (fr["axle"] * g["axle_radius_mm"] + fr["rolling_mm"]) / g["pin_radius_mm"]
    rolls = fr["sliding"] * g["pin_radius_mm"] >= fr["axle"] * g["axle_radius_mm"] + fr["rolling_mm"]
    rot = run(raw, detail=False).summary
    fixed_raw = copy.deepcopy(raw)
    fixed_raw["gearing"]["rotating_pins"] = False
    fixed = run(fixed_raw, detail=False).summary
    assert rot["rolling_ok"] == rolls and fixed["rolling_ok"] is None
    if not rolls:
        assert rot["loss_ratio"] == fixed["loss_ratio"]           # treated as fixed pins (§4.5)
    elif mu_rot <= fr["sliding"]:
        assert rot["loss_ratio"] <= fixed["loss_ratio"] * (1 + 1e-12)
        assert rot["efficiency_reducer"] >= fixed["efficiency_reducer"] * (1 - 1e-12)


# ------------------------------------------------------------------ 4. the detail tables
@pytest.mark.slow
@PROPS
@given(designs(discs=1, speed=True, mode="multiplier"))
def test_detail_equilibrium_and_cycle_mean(raw):
    res = run(raw)
    s = res.summary
    crank, contacts = res.detail["crank"], res.detail["contacts"]
    # pins.md §6: the crank table spans one period T_p = 360/z2 deg of crank angle, in order
    theta = np.array([row["theta_deg"] for row in crank])
    Tp = 360.0 / raw["gearing"]["pins"]
    assert theta[0] == pytest.approx(0.0, abs=1e-12) and theta[-1] == pytest.approx(Tp, rel=1e-12)
    assert np.all(np.diff(theta) >= 0)
    # pins.md §8 and §12.6: lambda_bar is the Richardson value Q_2N + (Q_2N - Q_N)/3 with error
    # E = |Q_2N - Q_N|; the trapezoid over the final grid is Q_2N, so it lies within E/3 of it
    lam = np.array([row["loss_ratio"] for row in crank])
    trap = float(np.sum(0.5 * (lam[1:] + lam[:-1]) * np.diff(theta))) / Tp
    assert abs(trap - s["loss_ratio"]) <= s["loss_ratio_err"] / 3 * (1 + 1e-6) + 1e-14 * max(s["loss_ratio"], 1e-300)
    # pins.md §4.3 and §8: loaded pins per crank angle within the summary's range, phases in (0, psi*]
    counts = [row["loaded_pins"] for row in crank]
    assert min(counts) == s["loaded_pins_min"] and max(counts) == s["loaded_pins_max"] >= 1
    phase = np.array([row["phase_deg"] for row in contacts])
    assert np.all(phase >= 0) and np.all(phase <= s["psi_star_deg"] * (1 + 1e-12))
    assert len(contacts) == sum(counts)
    # pins.md §4.8 identity 1: sum over the loaded pins of F_i |l_i| = T_sat at every crank angle, with
    # |l| = r_p1 sin(psi)/s(psi), s = sqrt((1-K1)^2 + 4 K1 sin^2(psi/2)) written out here
    if s["pin_force_max_N"] is None:
        return
    t_v = 1e3 * s["torque_in_Nm"]                          # multiplier: V is the input shaft [N*mm]
    K1, z1 = s["curtate_ratio"], raw["gearing"]["satellite_teeth"]
    k = raw["gearing"]["pins"] - z1
    r_p1 = raw["gearing"]["eccentricity_mm"] * z1 / k
    psi = np.radians(phase)
    lever = r_p1 * np.sin(psi) / np.sqrt((1 - K1) ** 2 + 4 * K1 * np.sin(psi / 2) ** 2)
    F = np.array([row["force_N"] for row in contacts])
    moments = np.add.reduceat(F * lever, np.cumsum([0] + counts[:-1]))
    assert np.allclose(moments, t_v, rtol=1e-9)
    # pins.md §12.1: pin_force_max_N is the largest actual pin force (>= every grid value)
    assert s["pin_force_max_N"] >= F.max() * (1 - 1e-12)


# ------------------------------------------------------------------ 5. the formula level
@PROPS
@given(designs(pin_load=True))
def test_formula_level_identities(raw):
    # pins.md §3, eqs. (3)-(7) and "Derived consequences": P_tr = P_tr1 + P_tr2; R cancels from
    # P_tr1 = f_k F_n omega 1e-3; P_tr2/P_tr = f_c r/(f_c r + f_k)
    s = run(raw, model="formula", detail=False).summary
    pl, fr = raw["pin_load"], raw["friction"]
    w = math.pi * pl["pin_speed_rpm"] / 30.0
    assert s["F_tr1_N"] == pytest.approx(fr["rolling_mm"] * pl["normal_force_N"] / pl["pin_radius_mm"], rel=1e-14)
    assert s["F_tr2_N"] == pytest.approx(fr["axle"] * pl["normal_force_N"], rel=1e-14)
    assert s["P_tr_W"] == pytest.approx(s["P_tr1_W"] + s["P_tr2_W"], rel=1e-14)
    assert s["P_tr1_W"] == pytest.approx(fr["rolling_mm"] * pl["normal_force_N"] * w * 1e-3, rel=1e-13)
    den = fr["axle"] * pl["axle_radius_mm"] + fr["rolling_mm"]
    if s["P_tr_W"] > 0:
        assert s["P_tr2_W"] / s["P_tr_W"] == pytest.approx(fr["axle"] * pl["axle_radius_mm"] / den, rel=1e-12)


# ------------------------------------------------------------------ 6. the contact level (few: ~0.5 s each)
@CONTACT
@given(designs(profile="circular", discs=1, speed=True, pin_load=False))
def test_contact_level_finite_and_efficiency_relations(raw):
    # interface.md "Output" and pins.md §5 (circular-arc profile: the contact level); §4.7 relations
    # hold at every level: 0 < eta <= 1 or self-locking, eta_HV = 1/(1 + lambda), eta_VH = 1 - lambda
    raw["contact"] = {"law": "hertz", "face_width_mm": 10.0}
    res = run(raw, tol=1e-4)
    assert_all_finite(res)
    s = res.summary
    assert s["model"] == "contact"
    lam = s["loss_ratio"]
    assert lam >= 0
    assert s["efficiency_reducer"] == pytest.approx(1 / (1 + lam), rel=1e-14)
    assert s["self_locking"] == (lam >= 1 and raw["load"]["mode"] == "multiplier")
    if not s["self_locking"]:
        assert 0 < s["efficiency"] <= 1
    if lam < 1:
        assert s["efficiency_multiplier"] == pytest.approx(1 - lam, rel=1e-14, abs=1e-15)
