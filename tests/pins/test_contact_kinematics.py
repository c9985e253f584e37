"""Tests of the contact model's geometry, moment and bearing force (gearcalc.pins.contact_kinematics; pins.md §5.1,
§5.5, §5.6).

Independent references: the law of cosines for the distance of a pin centre from the satellite centre
(|A_j - O1|^2 = R_p^2 + e^2 - 2 R_p e cos(2 pi j/z2 - theta)); the moment balance M(tau) = M_req at a solved state;
the rigid limit of pins.md §5.7(a): a stiff linear law on an unmodified cycloid carries the ideal level's pin forces
along the normals through the pitch point, recomputed here in the fixed frame (the bearing force's magnitude is
frame-independent).
"""
import numpy as np
import pytest

from gearcalc import pins
from gearcalc.pins import MULTIPLIER, REDUCER, Cycloid
from gearcalc.pins import contact as pc

PAPER = Cycloid.from_curtate_ratio(20, 22, 3.9, 0.75, 1.95)      # configs/pins_paper_cyc_u10_fixed.toml


def stiff(sigma, k_lin, g=PAPER, T=1e5):
    return pc.ContactModel(g, pc.CycloidProfile(g), pc.ContactLaw("linear", k_lin, 1.0), T, sigma)


@pytest.mark.parametrize("z1,z2", [(20, 22), (21, 22), (30, 33)])
def test_nominal_pin_positions_are_at_the_law_of_cosines_distance(z1, z2):
    g = Cycloid.from_curtate_ratio(z1, z2, 3.9, 0.75, 1.95)
    theta = np.linspace(-2.0, 5.0, 23)
    p = stiff(MULTIPLIER, 1e7, g).pose(theta)
    j = np.arange(z2)[:, None]
    r2 = g.R_p ** 2 + g.e ** 2 - 2 * g.R_p * g.e * np.cos(2 * np.pi * j / z2 - theta[None, :])
    assert p.x0.shape == (z2, theta.size)
    assert np.allclose(p.x0 ** 2 + p.y0 ** 2, r2, rtol=1e-13)


@pytest.mark.parametrize("sigma", [MULTIPLIER, REDUCER])
def test_the_solved_state_balances_the_required_moment(sigma):
    # pins.md §5.5: M(tau) = M_req = +T (multiplier), -T (reducer) at the solved rotation
    m = stiff(sigma, 1e7)
    theta = np.linspace(0.013, PAPER.period - 0.011, 7)
    sol = m.state(theta)
    M = m.moment(m.pose(theta), sol.tau)
    assert m.M_req == (1e5 if sigma == MULTIPLIER else -1e5)
    assert np.allclose(M, m.M_req, rtol=1e-6)


@pytest.mark.parametrize("sigma", [MULTIPLIER, REDUCER])
def test_bearing_force_of_a_stiff_contact_approaches_the_rigid_one(sigma):
    # B = -sum F_i n_i with the ideal level's forces (gearcalc.pins.forces) and the normals n_i = (P - A_i)/|P - A_i|
    # through the pitch point P = r_p2 (cos theta, sin theta) (pins.md §4.3); the contact level's deviation is the
    # deflection's, O(1/k): 100x smaller for a 100x stiffer law
    theta = np.linspace(0.013, PAPER.period - 0.011, 5)
    F = pins.pin_forces(theta, PAPER, pins.crest_cutoff(PAPER), 1e5, sigma)
    i = np.arange(PAPER.z2)[:, None]
    A = PAPER.R_p * np.array([np.cos(2 * np.pi * i / PAPER.z2), np.sin(2 * np.pi * i / PAPER.z2)])
    P = PAPER.r_p2 * np.array([np.cos(theta), np.sin(theta)])[:, None, :]
    n = (P - A) / np.hypot(*(P - A))
    rigid = np.hypot(*(-(F * n).sum(axis=1)))
    dev = []
    for k in (1e7, 1e9):
        m = stiff(sigma, k)
        Bx, By = m.bearing_force(m.state(theta))
        dev.append(np.max(np.abs(np.hypot(Bx, By) / rigid - 1)))
    assert dev[1] < 1e-6 and dev[1] < dev[0] / 50
