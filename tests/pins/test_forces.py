"""Tests of the ideal level's pin phases, loaded set and pin forces (gearcalc.pins.forces; pins.md §4.1, §4.3, §4.4,
§4.8).

Independent references: the naive phase formula 2 pi i/z2 - theta; the identities of pins.md §4.8 (the moment balance
at every crank angle, the full-circle lever sum, the k = 1 mean z2/4, the period T_p, the mirror between the modes),
recomputed here from the geometry's lever arms; the proportionality of lambda to mu and of F to T.
"""
import math

import numpy as np
import pytest

from gearcalc import pins
from gearcalc.pins import MULTIPLIER, REDUCER, Cycloid
from gearcalc.quadrature import integrate_adaptive

from pins.test_geometry import GEARS


@pytest.mark.parametrize("z2", [22, 50, 62, 200])
def test_pin_phase_exact_and_consistent(z2):
    # pins at 0 and pi are exact; elsewhere the phase agrees with the naive formula
    assert pins.pin_phase(0, 0.0, z2) == 0.0
    if z2 % 2 == 0:
        assert pins.pin_phase(z2 // 2, 0.0, z2) == math.pi
        assert pins.pin_phase(z2 // 2, 0.0, z2, MULTIPLIER) == math.pi
    theta = np.linspace(-7, 7, 301)
    i = np.arange(z2)[:, None]
    naive = np.mod(2 * np.pi * i / z2 - theta[None, :], 2 * np.pi)
    ph = pins.pin_phase(i, theta[None, :], z2)
    d = np.abs(ph - naive)
    assert np.all(np.minimum(d, 2 * np.pi - d) < 1e-12)
    assert np.all((ph >= 0) & (ph <= 2 * np.pi))
    phm = pins.pin_phase(i, theta[None, :], z2, MULTIPLIER)
    d = np.abs(phm - np.mod(-naive, 2 * np.pi))
    assert np.all(np.minimum(d, 2 * np.pi - d) < 1e-12)
    # a pin index outside [0, z2) is the same pin: the same phase, bit for bit, both modes
    for shift in (-2 * z2, z2, 3 * z2):
        assert np.array_equal(pins.pin_phase(i + shift, theta[None, :], z2), ph)
        assert np.array_equal(pins.pin_phase(i + shift, theta[None, :], z2, MULTIPLIER), phm)


@pytest.mark.parametrize("g", GEARS, ids=lambda g: f"z{g.z1}-{g.z2}")
@pytest.mark.parametrize("sigma", [REDUCER, MULTIPLIER])
def test_identity1_equilibrium_at_every_angle(g, sigma):
    ps = pins.crest_cutoff(g)
    theta = np.linspace(-1, 1, 333)
    T = 12345.0
    F = pins.pin_forces(theta, g, ps, T, sigma)
    psi = pins.pin_phase(np.arange(g.z2)[:, None], theta[None, :], g.z2, sigma)
    moment = np.sum(F * np.abs(pins.lever_arm(psi, g)), axis=0)
    assert np.allclose(moment, T, rtol=1e-12)
    # the loaded pins are those with 0 < psi~ < psi*; fewer than half for k >= 2
    n_loaded = np.count_nonzero(F > 0, axis=0)
    if g.k >= 2:
        assert n_loaded.max() < g.z2 / 2


@pytest.mark.parametrize("z2,K1", [(22, 0.75), (62, 0.5), (12, 0.95), (200, 0.99)])
def test_identity2_full_circle_sum(z2, K1):
    g = Cycloid.from_curtate_ratio(z2 - 1, z2, 3.9, K1, 0.5)
    theta = np.linspace(0, 1, 37)
    psi = pins.pin_phase(np.arange(z2)[:, None], theta[None, :], z2)
    lhs = np.sum((pins.lever_arm(psi, g) / g.r_p1) ** 2, axis=0)
    assert np.allclose(lhs, pins.full_circle_lever_sum(theta, z2, K1), rtol=1e-12)


@pytest.mark.parametrize("z2,K1", [(12, 0.9), (22, 0.75), (62, 0.5)])
def test_identity3_k1_mean_is_z2_over_4_but_pointwise_ripples(z2, K1):
    g = Cycloid.from_curtate_ratio(z2 - 1, z2, 3.9, K1, 0.5)
    bp = pins.cycle_breakpoints(g, math.pi, None)
    r = integrate_adaptive(lambda t, m: pins.cycle_state(t, m, g, math.pi).S / g.r_p1 ** 2, bp, tol=1e-12,
                           n_max=2 ** 20)
    assert abs(r.value[0] - z2 / 4) <= max(r.err[0], 1e-12 * z2)
    # the pointwise sum is not z2/4: the published F_max = 4 k T/(e z1 z2) is an approximation
    theta = np.linspace(0, 2 * np.pi / z2, 101)
    S = pins.lever_sum(theta, g, math.pi) / g.r_p1 ** 2
    ripple = (S.max() - S.min()) / (z2 / 4)
    assert ripple > 1e-6
    F_pub = 4 * 1000.0 / (g.z2 * g.r_p1)            # 4 T/(z2 r_p1), k = 1
    F_true = 1000.0 * g.r_p1 / (S * g.r_p1 ** 2)
    assert np.max(np.abs(F_true / F_pub - 1)) > 1e-6


def test_identity3_ripple_grows_with_K1():
    rip = []
    for K1 in (0.5, 0.8, 0.95):
        g = Cycloid.from_curtate_ratio(21, 22, 3.9, K1, 0.5)
        S = pins.lever_sum(np.linspace(0, 2 * np.pi / 22, 201), g, math.pi)
        rip.append(np.ptp(S) / S.mean())
    assert rip[0] < rip[1] < rip[2]


@pytest.mark.parametrize("g", GEARS, ids=lambda g: f"z{g.z1}-{g.z2}")
def test_identity4_period_is_Tp_and_not_half(g):
    ps = pins.crest_cutoff(g)
    theta = np.linspace(0, 2 * np.pi / g.z2, 57)[1:-1] + 1e-3
    lam = pins.loss_ratio(theta, g, ps, 0.1)
    assert np.allclose(pins.loss_ratio(theta + g.period, g, ps, 0.1), lam, rtol=1e-12)
    assert np.allclose(pins.loss_ratio(theta - 5 * g.period, g, ps, 0.1), lam, rtol=1e-12)
    assert np.max(np.abs(pins.loss_ratio(theta + g.period / 2, g, ps, 0.1) - lam)) > 1e-6


@pytest.mark.parametrize("g", GEARS, ids=lambda g: f"z{g.z1}-{g.z2}")
def test_identity5_mirror_between_modes(g):
    ps = pins.crest_cutoff(g)
    theta = np.linspace(-2, 2, 301)
    assert np.allclose(pins.loss_ratio(theta, g, ps, 0.1, REDUCER),
                       pins.loss_ratio(-theta, g, ps, 0.1, MULTIPLIER), rtol=1e-12)
