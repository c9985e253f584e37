"""Tests of the ideal level's cycle model of one gear (gearcalc.pins.cycle; pins.md §4.6, §6, §12.7): the breakpoints
of the loss ratio over a period, the state of the loaded pins, the sums over several discs.

Independent references: the pointwise loss ratio of gearcalc.pins.forces at theta = t T_p (multiplier) and
(1 - t) T_p (reducer); the closed-form disc offsets (n_d discs spaced by 2 pi/n_d of crank angle, pins.md §4.4); a
sum over the discs written here by np.interp on the periodic history.
"""
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from gearcalc import pins
from gearcalc.pins import MULTIPLIER, REDUCER

from pins.test_geometry import GEARS


def test_cycle_integrand_equals_pointwise_loss_ratio():
    # cycle_loss_ratio(t) is lambda_multiplier(theta = t T_p) and lambda_reducer(theta = (1 - t) T_p)
    for g in GEARS:
        ps = pins.crest_cutoff(g)
        bp = pins.cycle_breakpoints(g, ps, None)
        t = np.linspace(0, 1, 203)[1:-1]
        t = t[np.min(np.abs(t[:, None] - bp[None, :]), axis=1) > 1e-6]
        mid = 0.5 * (bp[np.searchsorted(bp, t) - 1] + bp[np.searchsorted(bp, t)])
        lam = pins.cycle_loss_ratio(t, mid, g, ps, 0.1)
        assert np.allclose(lam, pins.loss_ratio(t * g.period, g, ps, 0.1, MULTIPLIER), rtol=1e-12)
        assert np.allclose(lam, pins.loss_ratio((1 - t) * g.period, g, ps, 0.1, REDUCER), rtol=1e-12)


def test_disc_sum_of_a_periodic_history():
    # two discs half a period apart on a sine: sum is 0 everywhere; shift of one period: doubles
    x = np.linspace(0, 1, 201)
    v = np.sin(2 * np.pi * x)
    assert np.allclose(pins.sum_over_discs(x, v, [0.0, 0.5], 1.0), 0.0, atol=1e-3)
    assert np.allclose(pins.sum_over_discs(x, v, [0.0, 1.0], 1.0), 2 * v, atol=1e-12)
    assert pins.disc_offsets(3, 22).tolist() == pytest.approx([0.0, 1 / 3, 2 / 3])


@pytest.mark.parametrize("g", GEARS, ids=lambda g: f"z{g.z1}-{g.z2}")
def test_breakpoints_hold_the_exit_and_the_count_of_loaded_pins_is_constant_between_them(g):
    # pins.md §6: the loss ratio is smooth between breakpoints because the loaded set changes only there; the exit
    # is at t = frac(psi* z2/(2 pi)) (closed form); between two breakpoints the count of pins with 0 < psi < psi*
    # (gearcalc.pins.forces, pointwise) is one number
    ps = pins.crest_cutoff(g)
    bp = pins.cycle_breakpoints(g, ps, None)
    assert bp[0] == 0.0 and bp[-1] == 1.0 and np.all(np.diff(bp) > 0)
    exit_t = math.fmod(ps * g.z2 / (2 * math.pi), 1.0)
    assert np.min(np.abs(bp - exit_t)) < 1e-12 or exit_t < 1e-12
    for lo, hi in zip(bp[:-1], bp[1:]):
        t = np.linspace(lo, hi, 9)[1:-1]
        F = pins.pin_forces(t * g.period, g, ps, 1.0, MULTIPLIER)
        assert len(set(np.count_nonzero(F > 0, axis=0).tolist())) == 1


@settings(max_examples=80, deadline=None)
@given(n_d=st.integers(1, 12), z2=st.integers(3, 400))
def test_disc_offsets_are_the_fractions_of_d_z2_over_n_d(n_d, z2):
    # pins.md §12.7: disc d is shifted by frac(d z2/n_d) periods; with gcd(z2, n_d) = c the shifts are the multiples
    # of c/n_d, each c times (number theory: d z2 mod n_d runs over the multiples of c)
    s = pins.disc_offsets(n_d, z2)
    assert s.tolist() == pytest.approx([(d * z2 % n_d) / n_d for d in range(n_d)], abs=0)
    c = math.gcd(z2, n_d)
    assert sorted(s.tolist()) == pytest.approx(sorted([j * c / n_d for j in range(n_d // c)] * c), abs=1e-15)


@pytest.mark.parametrize("n_d", [2, 3, 5])
def test_equally_shifted_sines_sum_to_zero_over_the_cycle(n_d):
    # identity: sum_d sin(2 pi (x + d/n_d)) = 0 for n_d >= 2; on a grid holding every shifted sample the linear
    # interpolation is exact at the points disc_sum_range evaluates, so the range is [0, 0] to round-off
    x = np.arange(0, 60 * n_d + 1) / (60 * n_d)
    lo, hi = pins.disc_sum_range(x, np.sin(2 * np.pi * x), np.arange(n_d) / n_d, 1.0)
    assert abs(lo) < 1e-13 and abs(hi) < 1e-13


def test_disc_sum_range_keeps_both_sides_of_a_jump():
    # a unit step at x = 0.5 summed with itself shifted by 0.25: 0, 1 or 2 (by hand), the jump's two sides kept
    x = np.array([0.0, 0.5, 0.5, 1.0])
    assert pins.disc_sum_range(x, np.array([0.0, 0.0, 1.0, 1.0]), [0.0, 0.25], 1.0) == (0.0, 2.0)
    assert pins.disc_sum_range(x, np.array([0.0, 0.0, 1.0, 1.0]), [0.0], 1.0) == (0.0, 1.0)
