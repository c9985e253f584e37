"""Tests of the pins friction module (gearcalc.pins.friction; pins.md §4.5, §4.6, §5.5, §5.6; issue 35 item 1).

Independent references: the rolling condition f R_b >= f_c r + f_k and mu_rot = (f_c r + f_k)/R_b of pins.md §4.5-4.6
evaluated by hand, and the per-contact rule of pins.md §5.6 written out on a two-contact pin.
"""
import numpy as np
import pytest

from gearcalc.pins import friction as fr


def test_coulomb_is_a_friction_law_by_name_and_unknown_names_are_value_errors():
    law = fr.friction_law("coulomb", 0.1)
    assert isinstance(law, fr.FrictionLaw) and law.constant
    assert law.coefficient(np.array([0.0, 3.0]), np.array([1.0, 2.0])) == 0.1
    with pytest.raises(ValueError, match=r"unknown friction law 'coulmb'; known: coulomb"):
        fr.friction_law("coulmb", 0.1)


def test_the_rolling_pin_rule_by_hand():
    # pins.md §4.5: f R_b = 0.1 x 1.95 = 0.195 >= f_c r + f_k = 0.1 x 0.95 + 0.01 = 0.105: the pins roll
    assert fr.rolling_condition(0.1, 1.95, 0.1, 0.95, 0.01)
    assert not fr.rolling_condition(0.05, 1.95, 0.1, 0.95, 0.01)      # 0.0975 < 0.105
    mu, rolls = fr.friction_regime(np.array([True, True, False]), 1.95, np.array([0.95, 0.95, np.nan]),
                                   np.array([0.1, 0.05, 0.1]), 0.01, 0.1)
    assert mu.tolist() == [0.105 / 1.95, 0.05, 0.1] and rolls.tolist() == [True, False, False]


def _two_contacts():
    # one pin, two contacts, three instants: (c, R, n) = (2, 1, 3)
    F = np.array([[[3.0, 1.0, 0.0]], [[1.0, 2.0, 0.0]]])
    v = np.array([[[2.0, -1.0, 0.5]], [[5.0, 4.0, -0.5]]])
    return F, v


def test_losses_and_traction_follow_pins_md_5_6_on_a_rolling_pin():
    F, v = _two_contacts()
    R_b, mu_rot, f = 2.0, 0.05, 0.1
    loss, spin, slide = fr.PinFriction(mu_rot, f, True).losses(F, v, R_b)
    # instant 0: contact 0 leads (3 N > 1 N): spin v0/R_b = 1, it loses mu_rot F |v|; contact 1 slides at |5 - 2|
    assert spin[0].tolist() == [2.0 / R_b, 4.0 / R_b, 0.0]
    assert loss[:, 0, 0].tolist() == [mu_rot * 3.0 * 2.0, f * 1.0 * 3.0]
    assert loss[:, 0, 1].tolist() == [f * 1.0 * 5.0, mu_rot * 2.0 * 4.0]    # instant 1: contact 1 leads
    assert slide[:, 0, 0].tolist() == [0.0, 3.0]
    q = fr.PinFriction(mu_rot, f, True).traction(F, v)
    assert q[:, 0, 0].tolist() == [-mu_rot, -f]                           # 5 - 2 > 0: against it
    assert q[:, 0, 1].tolist() == [f, -mu_rot]                            # -1 - 4 < 0: f forwards
    qf = fr.PinFriction(f, f, False).traction(F, v)
    assert qf[:, 0, 1].tolist() == [f, -f]                                 # fixed pins: -f sign(v_t)


def test_a_speed_dependent_law_plugs_into_the_contact_rule():
    class Stribeck:                       # a made-up law: mu = 0.1 + 0.01 v
        name, constant = "stribeck", False

        def coefficient(self, speed, pressure=None):
            return 0.1 + 0.01 * np.asarray(speed)

    assert isinstance(Stribeck(), fr.FrictionLaw)
    F, v = _two_contacts()
    loss = fr.PinFriction(0.1, 0.1, False, Stribeck()).losses(F, v, 2.0)[0]
    assert loss[1, 0, 1] == pytest.approx((0.1 + 0.01 * 4.0) * 2.0 * 4.0, rel=1e-15)
    rolled = fr.PinFriction(0.05, 0.1, True, Stribeck()).losses(F, v, 2.0)[0]
    assert rolled[1, 0, 0] == pytest.approx((0.1 + 0.01 * 3.0) * 1.0 * 3.0, rel=1e-15)


def test_every_level_uses_the_one_rule():
    # the ideal level's regime and bound and the contact level's losses are the friction module's
    from gearcalc.pins import contact_cycle, efficiency, operating
    assert operating.friction_regime is fr.friction_regime
    assert efficiency.rolling_condition is fr.rolling_condition
    assert efficiency.rotating_loss_coefficient is fr.rotating_loss_coefficient
    assert contact_cycle.PinFriction is fr.PinFriction


def test_the_coulomb_law_through_the_interface_is_the_contact_levels_own_bit_for_bit():
    # the extension point is the path the numbers take: the contact cycle with Coulomb(f) as an explicit FrictionLaw
    # (its coefficient read at every contact's speed and force) equals the built-in rule's, bit for bit, with the
    # friction forces in the balance too
    from gearcalc.pins import contact as pc
    from gearcalc.pins.geometry import Cycloid
    g = Cycloid.from_curtate_ratio(21, 22, 3.9, 0.75, 1.95)
    prof, law = pc.CycloidProfile(g, 0.0, 0.01), pc.contact_law("linear", stiffness=1e5)
    out = []
    for friction in (fr.PinFriction(0.1, 0.1, False), fr.PinFriction(0.1, 0.1, False, fr.Coulomb(0.1))):
        tc = pc.cycle_at_torque(pc.ContactCase(g, prof, law, 1, friction, 10.0, True), False, True, tol=1e-4)
        out.append((tc.loss_ratio, tc.loss_ratio_err, tc.cycle.sol.tau.tobytes(), tc.cycle.loss.tobytes()))
    assert out[0] == out[1]


def test_table_and_stribeck_laws():
    law = fr.friction_law("table", speed_m_s=(0.0, 0.5, 2.0), mu=(0.12, 0.08, 0.05))
    # by hand: 0.25 m/s halfway between 0.12 and 0.08; 1.25 m/s halfway between 0.08 and 0.05; ends held
    assert law.coefficient(np.array([0.25, 1.25, 5.0, -0.25])).tolist() == pytest.approx([0.10, 0.065, 0.05, 0.10])
    assert isinstance(law, fr.FrictionLaw) and not law.constant
    s = fr.friction_law("stribeck", mu_s=0.15, mu_c=0.05, v_s=0.1, delta=2.0, k_v=0.01)
    assert float(s.coefficient(0.0)) == pytest.approx(0.15, rel=1e-12)              # breakaway
    assert float(s.coefficient(0.1)) == pytest.approx(0.05 + 0.1 * np.exp(-1) + 0.001, rel=1e-12)
    assert float(s.coefficient(10.0)) == pytest.approx(0.05 + 0.1, rel=1e-12)       # full film: mu_c + k_v v


def test_a_law_at_the_contact_level_reads_its_speeds_times_the_crank_speed():
    # pins.md §4.10, §5.6: the contact level's sliding speeds are mm/s per rad/s of crank speed; v [m/s] = v_t omega_H
    # / 1000: 4 mm/s per rad/s at 100 rad/s is 0.4 m/s, on the table (0, 0.12) - (1, 0.06) 0.12 - 0.4*0.06 = 0.096
    law = fr.AtCrankSpeed(fr.TableLaw((0.0, 1.0), (0.12, 0.06)), 100.0)
    assert law.coefficient(np.array([4.0, -4.0, 20.0])).tolist() == pytest.approx([0.096, 0.096, 0.06], rel=1e-15)
    assert isinstance(law, fr.FrictionLaw) and not law.constant
    pf = fr.PinFriction(0.1, 0.1, False, law)
    assert pf.varies and not fr.PinFriction(0.1, 0.1, False).varies
    F, v = np.array([[[2.0, 1.0, 0.0]]]), np.array([[[4.0, -4.0, 20.0]]])
    # the friction force against the sliding, -mu(|v|) sign(v), and with a piece's directions: sign(d) mu(|v|)
    assert pf.traction(F, v).ravel().tolist() == pytest.approx([-0.096, 0.096, -0.06], rel=1e-15)
    assert pf.along(np.array([[[1.0, 1.0, 0.0]]]), F, v).ravel().tolist() == pytest.approx([0.096, 0.096, 0.0],
                                                                                            rel=1e-15)
