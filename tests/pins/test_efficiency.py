"""gearcalc.pins.efficiency: sliding speed and pin spin at a contact, efficiencies from the mean loss ratio.

Independent references: the contact's velocities recomputed here with plane vectors (the satellite turns at
omega_V about the pitch point P; the contact lies on the line from the pin centre to P, pins.md §4.5); the
power balance of pins.md §4.7 (multiplier P_out = P_in - P_loss, reducer P_in = P_out + P_loss with
P_loss = lambda times the output-side power); Willis's fixed-carrier train expanded for small losses.
"""
import math

import numpy as np
import pytest

from gearcalc.pins import efficiency as E


def perp(v):
    """omega x v for a unit angular velocity along z: (x, y) -> (-y, x)."""
    return np.array([-v[1], v[0]])


@pytest.mark.parametrize("rho,Rb,omega_V,angle", [(10.0, 2.0, -3.0, 0.3), (1.5, 2.0, 7.0, 2.0),
                                                   (57.2, 1.95, -1.4, -1.1)])
def test_sliding_speed_and_pin_spin_from_the_contact_velocities(rho, Rb, omega_V, angle):
    u = np.array([math.cos(angle), math.sin(angle)])   # from the pin centre (origin) towards the pitch point
    P, c = rho * u, Rb * u                               # pitch point; contact point on the pin's surface
    v_sat = omega_V * perp(c - P)                        # satellite material point at c: rotation about P
    # fixed pin: the whole satellite velocity at c slides
    assert float(E.sliding_speed(rho, Rb, omega_V)) == pytest.approx(np.linalg.norm(v_sat), rel=1e-13)
    # a pin that rolls without slip: its surface velocity at c, omega_pin x (c - 0), equals the satellite's
    w_pin = float(E.pin_spin(rho, Rb, omega_V))
    assert w_pin * perp(c) == pytest.approx(v_sat, rel=1e-12, abs=1e-12 * np.linalg.norm(v_sat))


def test_sliding_speed_is_elementwise_over_arrays():
    rho = np.array([1.0, 2.0, 5.0])
    assert E.sliding_speed(rho, 2.0, 4.0).tolist() == [4.0, 0.0, 12.0]     # 4 |rho - 2|


@pytest.mark.parametrize("lam", [0.0, 0.01, 0.2, 0.9])
def test_efficiencies_follow_the_power_balance(lam):
    # multiplier: input power P, loss lam P (referred to the input side), output (1 - lam) P
    assert E.efficiency_multiplier(lam) == pytest.approx(1 - lam, rel=1e-15, abs=1e-15)
    # reducer: output power P, loss lam P, input (1 + lam) P
    assert E.efficiency_reducer(lam) == pytest.approx(1 / (1 + lam), rel=1e-15)


def test_self_locking_multiplier_has_no_positive_efficiency():
    assert E.efficiency_multiplier(1.0) == 0.0 and E.efficiency_multiplier(1.5) < 0


@pytest.mark.parametrize("z1,z2", [(20, 22), (30, 31), (60, 63)])
def test_willis_efficiencies(z1, z2):
    k = z2 - z1
    assert E.willis_efficiencies(0.0, z1, z2) == (1.0, 1.0, 1.0)            # lossless train
    for lam in (1e-2, 1e-3, 1e-4):
        eta0, vh, hv = E.willis_efficiencies(lam, z1, z2)
        assert eta0 == pytest.approx(1 - lam * k / z2, rel=1e-15)
        assert vh == pytest.approx(1 - lam, rel=1e-12)                      # Willis agrees with §4.7 exactly
        # the reducer: with eps = lam k / z2, a = z1 / k, k eta0 / (z2 - z1 eta0) = (1 - eps) / (1 + a eps)
        # = 1 - lam + (z1 / z2) lam^2 + O(lam^3), while 1 / (1 + lam) = 1 - lam + lam^2 + O(lam^3)
        assert hv - 1 / (1 + lam) == pytest.approx(-(k / z2) * lam ** 2, rel=3 * lam)
