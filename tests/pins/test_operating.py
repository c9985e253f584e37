"""Tests of the operating-point physics moved out of the adapter (issue 14): gearcalc.pins
formula_losses over arrays, friction_regime, efficiency_torques, scale_unit_cycle, state_loss_ratio,
geometry_violations; gearcalc.pins.contact cycle_at_torque, fixed_point_settled, backlash, cycle_peaks.

Every expected value names its source on its line: the paper (seed 000, eqs. (3)-(7)), pins.md
sections, or the scalar form of the same function (arrays and scalars must agree bit for bit).
"""
import math

import numpy as np
import pytest

from gearcalc import pins, units
from gearcalc.pins import contact as pc
from gearcalc.pins import ARRAY_OPS, MULTIPLIER, REDUCER, SCALAR_OPS, Cycloid


def gear(z1=21, z2=22, e=3.9, K1=0.75, Rb=1.95):
    return Cycloid.from_curtate_ratio(z1, z2, e, K1, Rb)


# ------------------------------------------------------------------ formula level over arrays (pins.md §3)

def test_formula_losses_over_arrays_equal_the_scalar_calls_bit_for_bit():
    F, n, R, r = np.array([1920.0, 870.0, 2100.0]), np.array([14.0, 34.0, 18.0]), np.array([1.95, 1.95, 2.75]), \
        np.array([0.95, 0.95, 1.75])
    paper = np.array([True, False, True])
    f = np.array([0.1, 0.05, 0.2])
    arr = pins.formula_losses(F, n, R, r, 0.01, 0.1, paper_pi=paper, sliding_friction=f)
    for i in range(3):
        one = pins.formula_losses(float(F[i]), float(n[i]), float(R[i]), float(r[i]), 0.01, 0.1,
                                  paper_pi=bool(paper[i]))
        assert (arr.F_tr1[i], arr.F_tr2[i], arr.P_tr1[i], arr.P_tr2[i], arr.P_tr[i]) == \
            (one.F_tr1, one.F_tr2, one.P_tr1, one.P_tr2, one.P_tr)
        assert arr.P_tr_fixed[i] == pins.fixed_pin_formula_loss(float(F[i]), float(n[i]), float(R[i]), float(f[i]),
                                                                paper_pi=bool(paper[i]))
    assert round(float(arr.P_tr[0]), 3) == 0.295             # paper, Fig. 8 case: P_tr = 0.295 W


def test_formula_losses_without_sliding_friction_has_no_fixed_pin_loss():
    assert pins.formula_losses(1920, 14, 1.95, 0.95, 0.01, 0.1).P_tr_fixed is None     # pins.md §3


# ------------------------------------------------------------------ friction regime and efficiency (pins.md §4.5-4.7)

def test_friction_regime_rolls_only_when_the_rolling_condition_holds():
    rot = np.array([True, True, False])
    mu, rolls = pins.friction_regime(rot, 1.95, np.array([0.95, 0.95, np.nan]), np.array([0.1, 0.01, 0.1]),
                                     0.01, 0.1)
    assert rolls.tolist() == [True, False, False]            # f R_b >= f_c r + f_k (pins.md §4.5)
    assert mu[0] == (0.1 * 0.95 + 0.01) / 1.95               # mu_rot = (f_c r + f_k)/R_b (pins.md §4.6)
    assert mu[1:].tolist() == [0.01, 0.1]                    # slide with f


@pytest.mark.parametrize("multiplier", [False, True])
@pytest.mark.parametrize("on_V", [False, True])
def test_efficiency_torques_scalars_equal_arrays_and_the_spec_formulas(multiplier, on_V):
    lam = np.array([0.0, 0.1, 0.99, 1.0, 1.7])
    E = np.full(lam.shape, 1e-6)
    arr = pins.efficiency_torques(lam, E, 100.0, 10.5, multiplier, on_V)
    for i, x in enumerate(lam):
        one = pins.efficiency_torques(np.float64(x), np.float64(1e-6), np.float64(100.0), 10.5, multiplier, on_V,
                                      SCALAR_OPS)
        for name in ("efficiency", "efficiency_err", "T_V", "T_H", "torque_in", "torque_out", "eta_hv"):
            a, b = getattr(arr, name)[i], getattr(one, name)
            assert (a == b) or (math.isnan(a) and math.isnan(b)), name
        assert bool(arr.self_locking[i]) == bool(one.self_locking) == (multiplier and x >= 1.0)   # pins.md §4.7
    ok = lam < 1.0
    if multiplier:
        assert np.allclose(arr.efficiency[ok], 1.0 - lam[ok], rtol=0, atol=0)                 # eta_VH = 1 - lambda
        assert np.all(np.isnan(arr.efficiency[~ok]))                                           # self-locking
    else:
        assert np.array_equal(arr.efficiency, 1.0 / (1.0 + lam))                               # eta_HV = 1/(1 + lambda)


def test_scale_unit_cycle_scalars_equal_arrays():
    from types import SimpleNamespace

    vals = dict(force=np.array([0.01, 0.02]), total=np.array([0.03, 0.05]), loss=np.array([0.004, 0.006]),
                rel_min=np.array([-1.0, 0.5]), rel_max=np.array([2.0, 3.0]), rel_abs=np.array([2.0, 3.0]),
                psi_0=np.array([0.5, np.nan]), psi_star=np.array([3.0, 2.0]), force_phase=np.array([1.0, 0.5]),
                loss_phase=np.array([1.5, 0.7]))
    lam, mu, rolls, f = np.array([0.05, 0.2]), np.array([0.1, 0.05]), np.array([True, False]), np.array([0.1, 0.1])
    T_V, n_d, n_H = np.array([800.0, 90.0]), np.array([1, 2]), np.array([1000.0, 500.0])
    z1, k, Rb = np.array([20, 30]), np.array([1, 2]), np.array([2.0, 1.5])

    def gears(i=slice(None)):
        return pins.Gears(z1[i], z1[i] + k[i], 3.0, Rb[i], 0.5, np.nan, n_d[i])

    arr = pins.scale_unit_cycle(SimpleNamespace(**vals), lam, pins.PinFriction(mu, f, rolls), T_V, n_H, gears(),
                                ARRAY_OPS)
    for i in range(2):
        u = SimpleNamespace(**{key: v[i] for key, v in vals.items()})
        one = pins.scale_unit_cycle(u, lam[i], pins.PinFriction(mu[i], f[i], rolls[i]), T_V[i], n_H[i], gears(i),
                                    SCALAR_OPS)
        for name in pins.ScaledCycle.__dataclass_fields__:
            a, b = getattr(arr, name)[i], getattr(one, name)
            assert (a == b) or (math.isnan(a) and math.isnan(b)), name
    assert arr.force_max[0] == units.nm_to_nmm(800.0) * 0.01          # F = T_sat F_unit (pins.md §4.8 id. 8)
    assert arr.spin_reversals.tolist() == [1, 0]                           # psi_0 < psi* on a rolling pin only
    assert arr.sliding_speed_max[0] == 0.0 and arr.spin_abs_max[1] == 0.0   # rolling pins do not slide
    nan = pins.scale_unit_cycle(SimpleNamespace(**vals), lam, pins.PinFriction(mu, f, rolls), T_V,
                                np.array([np.nan, np.nan]), gears(), ARRAY_OPS)
    assert np.all(np.isnan(nan.loss_mean)) and np.all(np.isnan(nan.loss_phase))   # no crank speed: no losses


def test_state_loss_ratio_is_the_cycle_loss_ratio_and_the_disc_mean():
    g = gear()
    t, mid = np.linspace(0.0, 1.0, 9), np.full(9, 0.5)
    st = pins.cycle_state(t, mid, g, math.pi)
    assert np.array_equal(pins.state_loss_ratio(st, g, 0.1), pins.cycle_loss_ratio(t, mid, g, math.pi, 0.1))
    two = pins.state_loss_ratio(st, g, 0.1, 2)
    ref = pins.sum_over_discs(t, pins.state_loss_ratio(st, g, 0.1), pins.disc_offsets(2, 22), 1.0) / 2
    assert np.array_equal(two, ref)                                        # mean over the discs (pins.md §12.7)


# ------------------------------------------------------------------ validity rules (pins.md §4.2, §7, §9)

def test_geometry_violations_rule_by_rule():
    z1 = [21, 22, 21, 21, 21, 21]
    z2 = [22, 22, 22, 22, 22, 22]
    K1 = [0.75, 0.75, 1.0, 0.75, 0.75, 5e-324]
    Rb = [1.95, 1.95, 1.95, 20.0, 1.95, 1.95]
    r = [np.nan, np.nan, np.nan, np.nan, 2.0, np.nan]
    rot = [False, False, False, False, True, False]
    v = pins.geometry_violations(z1, z2, 3.9, np.nan, K1, Rb, pins.PinMounting(r, rot), True)
    assert v.teeth.tolist() == [False, True, False, False, False, False]      # z2 > z1
    assert v.curtate[2] and not v.curtate[0]                                  # K1 < 1 (cycloid)
    assert v.overlap[3] and not v.overlap[0]                                  # R_b < R_p sin(pi/z2)
    assert v.axle[4] and not v.axle[0]                                        # r < R_b
    assert v.overflow.tolist() == [False, True, False, False, False, True]    # R_p = e z2/(k K1) finite (k = 0 too)
    assert v.any().tolist() == [False, True, True, True, True, True]
    assert v.pin_circle_radius[0] == 3.9 * 22 / (1 * 0.75)                    # R_p = e z2/(k K1) (pins.md §7)
    assert not pins.geometry_violations(21, 22, 3.9, np.nan, 1.0, 1.95, cycloidal=False).curtate[0]


# ------------------------------------------------------------------ the contact level (pins.md §5, §7)

def test_fixed_point_settles_on_a_contraction():
    assert not pc.fixed_point_settled([0.1], 1e-6)
    assert pc.fixed_point_settled([0.1, 0.1], 1e-6)                      # no change
    assert not pc.fixed_point_settled([0.1, 0.2], 1e-6)                  # one large change
    assert pc.fixed_point_settled([0.1, 0.11, 0.1101, 0.110101], 1e-3)   # contraction c = 0.01


def _linear(k=1e5):
    return pc.contact_law("linear", stiffness=k)


def test_cycle_at_torque_on_V_is_one_pass_and_on_H_is_the_fixed_point():
    g = gear()
    prof = pc.CycloidProfile(g, 0.0, 0.0)
    on_V = pc.cycle_at_torque(pc.ContactCase(g, prof, _linear(), 1, (0.1, 0.1, False), 50.0, True), False, tol=1e-5)
    assert len(on_V.history) == 1 and on_V.torque_V == 50.0 and on_V.settled
    on_H = pc.cycle_at_torque(pc.ContactCase(g, prof, _linear(), 1, (0.1, 0.1, False), 5.0, False), False, tol=1e-5)
    # reducer: T_V = u T_H/(1 + lambda) at the fixed point (pins.md §4.7, §7)
    assert on_H.torque_V == pytest.approx(g.ratio * 5.0 / (1.0 + on_H.history[-2]), rel=0, abs=1e-12)
    assert on_H.settled and on_H.loss_ratio == on_H.cycle.loss_ratio


def test_cycle_at_torque_without_friction_is_exactly_lossless():
    g = gear()
    case = pc.ContactCase(g, pc.CycloidProfile(g, 0.0, 0.0), _linear(), 1, (0.0, 0.0, False), 5.0, True)
    tc = pc.cycle_at_torque(case, True)
    assert (tc.loss_ratio, tc.loss_ratio_err) == (0.0, 0.0)              # pins.md §9: zero friction is exact


def test_cycle_at_torque_reports_the_torque_tried_when_no_equilibrium():
    g = gear()
    prof = pc.CycloidProfile(g, 0.0, 0.0)
    with pytest.raises(pc.NoEquilibrium) as info:
        pc.cycle_at_torque(pc.ContactCase(g, prof, pc.contact_law("linear", stiffness=1e-9), 1, (0.1, 0.1, False), 1e9,
                                          True), False)
    assert info.value.torque_V == 1e9


def test_backlash_is_zero_without_clearance_and_positive_with_it():
    g = gear()
    none = pc.ContactModel(g, pc.CycloidProfile(g, 0.0, 0.0), _linear(), 1.0, REDUCER)
    play = pc.ContactModel(g, pc.CycloidProfile(g, 0.0, 1e-3), _linear(), 1.0, REDUCER)
    assert pc.backlash(none) == pytest.approx(0.0, abs=1e-9)             # unmodified cycloid (pins.md §5.3)
    assert pc.backlash(play) > 0.0


def test_cycle_peaks_of_one_disc_are_the_maxima_over_the_solution():
    g = gear()
    m = pc.ContactModel(g, pc.CycloidProfile(g, 0.0, 0.0), _linear(), 1e4, MULTIPLIER)
    cyc = pc.mean_loss_ratio(m, (0.1, 0.1, False), tol=1e-4)
    pk = pc.cycle_peaks(cyc, g, 1, False)
    assert pk.force == float(cyc.sol.force.max())                      # peak pin force
    assert pk.total == float(cyc.loss.sum(axis=(0, 1)).max())          # all pins
    assert (pk.spin_min, pk.spin_max, pk.spin_abs) == (0.0, 0.0, 0.0)  # fixed pins do not spin
