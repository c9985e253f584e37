"""Tests of the contact model's equilibrium at given crank angles (gearcalc.pins.contact_model; pins.md §5.1, §5.5).

Independent references: a design of the guards' random sample whose satellite turns so far that no contact carries
the torque (the design error named at its crank angle); the period T_p of the transmission error (pins.md §5.6:
phi(theta + T_p) - phi(theta) = -k T_p/z1 exactly); central differences of the solved rotation for d tau/d theta.
"""
import numpy as np
import pytest

from gearcalc import api
from gearcalc.calculator import DesignError
from gearcalc.pins import contact as pc
from gearcalc.pins import contact_model as pcm

from pins.test_contact import _sample, circular_model


def test_a_bracket_that_the_next_search_does_not_hold_is_no_equilibrium_not_an_internal_error():
    # a 4/5 cycloid of the guards' random sample (seed 5, no. 29) turns so far under 400 N*m that the contacts at a
    # bracket's ends differ from the doubling's (the foot point jumps flank): exit 70 before, now the design error
    # naming the crank angle (pins.md §5.5, §7)
    design = _sample("z 4/5 cycloid", "cycloidal", 4, 5, 0.513, 0.615, 1.869, 0.661, "multiplier")
    with pytest.raises(DesignError, match="no contact can carry the torque at crank angle"):
        api.compute(design, model="contact", tol=1e-6)
    # the helper: brackets whose ends hold no sign change at the second search raise NoEquilibrium at their angles
    theta = np.array([0.1, 0.2, 0.3])
    with pytest.raises(pc.NoEquilibrium) as exc:
        pcm._bracket_root(lambda t: np.array([1.0, -1.0, 1.0]) * (t - 0.5) + np.array([0.0, 0.0, 9.0]), theta,
                         np.zeros(3), np.ones(3), 1e-12)
    assert exc.value.theta.tolist() == [0.3]


def test_transmission_error_has_period_Tp():
    # pins.md §5.6: phi(theta + T_p) - phi(theta) = -k T_p/z1 exactly, i.e. tau is T_p-periodic
    m = circular_model()
    s = m.state(np.array([0.0, m.g.period, 0.1, 0.1 + m.g.period]))
    assert s.tau[1] == pytest.approx(s.tau[0], abs=1e-14)
    assert s.tau[3] == pytest.approx(s.tau[2], abs=1e-14)


def test_dtau_dtheta_matches_the_derivative_of_the_solved_tau():
    m = circular_model()
    th, h = 0.1, 1e-5
    s = m.state(np.array([th - h, th, th + h]))
    assert s.dtau[1] == pytest.approx((s.tau[2] - s.tau[0]) / (2 * h), rel=1e-5)
