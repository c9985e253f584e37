"""Tests of the pins contact level's tooth profiles and penetrations (gearcalc.pins.contact_profiles; pins.md §5.2,
§5.3).

Independent references: brute-force least distances by dense sampling of the pin-centre curves (the tooth-centre
distance, the signed distance to the design curve), the tangency of the "full" tooth to its neighbours, the ideal
level's lever arms (pins.md §4.4: a small rotation tau presses pin i by tau |l_i|), and the safeguarded Newton foot
point run to 1e-14 rad.
"""
import math

import numpy as np
import pytest

from gearcalc import pins
from gearcalc.pins import REDUCER, Cycloid
from gearcalc.pins import contact as pc
from gearcalc.pins import contact_profiles as cp
from gearcalc.pins.contact_law import contact_law
from pins.test_contact import circ_u10, circular_model, full_u10  # the contact tests' shared geometry


def _brute_distance(R_t, g, n=200001):
    """Least distance from R_t u(pi/z1) to every family's pin-centre curve, by dense sampling."""
    chi = math.pi / g.z1
    beta = np.linspace(chi - 0.7, chi + 0.7, n)
    best = np.inf
    for b in range(g.k):
        cx, cy = pins.pin_centre_curve(beta, b, g)
        best = min(best, float(np.min(np.hypot(cx - R_t * math.cos(chi), cy - R_t * math.sin(chi)))))
    return best


@pytest.mark.parametrize("R_t", [0.0, 20.0, 46.0, 50.0])
def test_tooth_centre_distance_matches_brute_force(R_t):
    g = circ_u10()
    got = float(cp.tooth_centre_distance(R_t, g))
    assert got == pytest.approx(_brute_distance(R_t, g), abs=1e-6)   # sampling step 7e-6 rad x 57 mm
    assert got <= _brute_distance(R_t, g) + 1e-12                    # the refined minimum is not above samples
    if R_t == 0.0:
        assert got == pytest.approx(57.2 - 3.9, rel=1e-14)           # D(0) = R_p - e


def test_full_tooth_is_tangent_to_its_neighbours_and_just_touches_the_pin_paths():
    g = circ_u10()
    rho, R_t = full_u10()
    chi = math.pi / 20
    T0, T1 = R_t * np.array([math.cos(chi), math.sin(chi)]), R_t * np.array([math.cos(3 * chi), math.sin(3 * chi)])
    assert np.hypot(*(T1 - T0)) == pytest.approx(2 * rho, rel=1e-12)      # adjacent teeth tangent at the root
    assert float(cp.tooth_centre_distance(R_t, g)) == pytest.approx(g.R_b + rho, rel=1e-12)
    # over a whole period at the nominal pose no pair interferes, and some pair touches (zero backlash)
    m = circular_model()
    theta = np.linspace(0.0, g.period, 2001)
    d = m.contacts(m.pose(theta), np.zeros(theta.size)).delta
    assert d.max() <= 1e-9
    assert d.max() >= -1e-6


def test_zero_backlash_circle_is_the_smallest_root():
    g = circ_u10()
    rho = 4.0
    R_t = cp.zero_backlash_tooth_circle(g, rho)
    assert float(cp.tooth_centre_distance(R_t, g)) == pytest.approx(g.R_b + rho, rel=1e-12)
    smaller = np.linspace(0.0, R_t * (1 - 1e-6), 400)
    assert np.all(cp.tooth_centre_distance(smaller, g) > g.R_b + rho)
    assert cp.zero_backlash_tooth_circle(g, 60.0) is None                    # R_b + rho_t >= R_p - e


# ------------------------------------------------------------------ cycloidal penetration (pins.md §5.2)

@pytest.mark.parametrize("z1,z2", [(21, 22), (20, 22), (30, 33)])
def test_unmodified_cycloid_touches_every_loaded_pin_and_presses_by_the_lever_arm(z1, z2):
    g = Cycloid.from_curtate_ratio(z1, z2, 3.9, 0.75, 1.95)
    prof = cp.CycloidProfile(g)
    m = pc.ContactModel(g, prof, contact_law("linear", stiffness=1e6), 1.0, REDUCER)
    theta = np.array([0.01, 0.1, 0.2])
    pose = m.pose(theta)
    psi = pins.pin_phase(np.arange(z2)[:, None], theta[None, :], z2, REDUCER)
    on_flank = (psi > 1e-3) & (psi < prof.psi_star - 1e-3)
    d0 = m.contacts(pose, np.zeros(3)).delta[0]
    assert np.abs(d0[on_flank]).max() < 1e-12
    # a small rotation presses pin i by tau |l_i| (pins.md §4.4: the lever arm of the normal through P);
    # central difference in tau (the second-order term cancels)
    tau = 1e-6
    slope = (m.contacts(pose, np.full(3, tau)).delta[0] - m.contacts(pose, np.full(3, -tau)).delta[0]) / (2 * tau)
    lever = np.abs(pins.lever_arm(psi, g))
    assert np.allclose(slope[on_flank], lever[on_flank], rtol=1e-6)


def test_cycloid_signed_distance_matches_brute_force_and_the_equidistant_modification():
    g = Cycloid.from_curtate_ratio(20, 22, 3.9, 0.75, 1.95)
    prof = cp.CycloidProfile(g, equidistant_mod=0.02)
    m = pc.ContactModel(g, prof, contact_law("linear", stiffness=1e6), 1.0, REDUCER)
    theta = np.array([0.05])
    pose = m.pose(theta)
    tau = 2e-4
    ct = m.contacts(pose, np.full(1, tau))
    c, s = math.cos(tau), math.sin(tau)
    x, y = c * pose.x0 + s * pose.y0, -s * pose.x0 + c * pose.y0
    beta = np.linspace(0.0, 2 * math.pi, 400001)
    for j in (1, 2, 3):       # pins on their flanks (reducer: psi between 0 and psi*)
        cx, cy = pins.pin_centre_curve(beta, j % 2, g)
        dist = np.min(np.hypot(cx - x[j, 0], cy - y[j, 0]))
        # delta = -d - Delta R_b with |d| the distance to the design curve, to sampling accuracy
        assert abs(ct.delta[0, j, 0] + 0.02) == pytest.approx(dist, abs=2e-6)
        assert ct.delta[0, j, 0] + 0.02 > 0           # the rotation pushes the flank into these pins
    d0 = m.contacts(pose, np.zeros(1)).delta[0, 1:4, 0]
    assert np.allclose(d0, -0.02, atol=1e-12)        # nominal: every flank pin clear by Delta R_b


@pytest.mark.parametrize("z1, z2, tau", [(20, 22, 2e-4), (60, 62, -1e-4), (10, 11, 5e-4)])
def test_cycloid_foot_point_from_nominal_meets_the_bracketed_newton(z1, z2, tau):
    # a fresh pose's foot points (Halley's first step from the nominal one, then Newton until a step below 1e-7 rad)
    # against the safeguarded Newton of foot_point run to |d beta| < 1e-14 from the same start (pins.md §5.2): the
    # same foot point to 1e-12 rad, in at most three curve evaluations (the pins at the line of centres, where the
    # design curve turns fastest, take the third; the others stop after two, a Newton first step needed three)
    g = Cycloid.from_curtate_ratio(z1, z2, 3.9, 0.75, 1.95)
    prof = cp.CycloidProfile(g)
    m = pc.ContactModel(g, prof, contact_law("hertz", face_width=10.0), 1.0, REDUCER)
    theta = np.linspace(0.0, g.period, 7)
    pose = m.pose(theta)
    c, s = math.cos(tau), math.sin(tau)
    x, y = c * pose.x0 + s * pose.y0, -s * pose.x0 + c * pose.y0
    start = tuple(pose.aux[k] for k in cp._START_KEYS)
    calls = []
    curve = prof._curve_of
    prof._curve_of = lambda trig: calls.append(1) or curve(trig)
    beta = prof._newton_trig(pose.aux["beta"], pose.aux["fam"], x, y, 8, 1e-7, start)[0]
    del prof._curve_of
    exact = prof.foot_point(pose.aux["beta"], pose.aux["fam"], x, y, tol=1e-14)
    assert np.max(np.abs(beta - exact)) < 1e-12
    assert len(calls) <= 3


