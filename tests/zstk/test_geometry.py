"""gearcalc.zstk.geometry: angle reduction and the roller tangent to both raceways (zstk.md §3.1, §4.3).

Independent references: IEEE 754 remainder (Python's math.remainder); the tangency conditions recomputed
here with plane vectors (outer ring centre O_H at the origin, inner ring centre O_B at (e, 0), so that the
gap is narrowest at theta = 0): a roller of radius r centred at P touches the outer raceway from inside,
|O_H P| + r = R_H, and the inner raceway from outside, |O_B P| = R_B + r.
"""
import math

import numpy as np
import pytest

from gearcalc.zstk import geometry as G


def test_remainder_360_is_ieee_remainder():
    rng = np.random.default_rng(35)
    x = np.concatenate([rng.uniform(-2000, 2000, 500), 10.0 ** rng.uniform(-5, 300, 200) * rng.choice([-1, 1], 200),
                        np.arange(-1260.0, 1261.0, 90.0)])             # ties at odd multiples of 180
    assert G.remainder_360(x).tolist() == [math.remainder(v, 360.0) for v in x]


def test_wrap_angle_is_in_the_half_open_interval_and_congruent():
    a = np.linspace(-20.0, 20.0, 4001)
    w = G.wrap_angle(a)
    assert np.all(w > -np.pi) and np.all(w <= np.pi)
    turns = (a - w) / (2 * np.pi)
    assert np.allclose(turns, np.round(turns), rtol=0, atol=1e-12)


@pytest.mark.parametrize("RH,RB,e", [(100.0, 50.0, 6.0), (80.0, 60.0, 1.0), (45.0, 20.0, 12.0)])
def test_the_roller_touches_both_raceways(RH, RB, e):
    theta = np.linspace(-np.pi, np.pi, 181)
    r = G.roller_radius(theta, RH, RB, e)
    h = G.centre_distance(theta, RH, RB, e)
    P = np.stack([h * np.cos(theta), h * np.sin(theta)])
    assert np.allclose(np.hypot(*P) + r, RH, rtol=1e-13, atol=0)                   # outer raceway, inside
    assert np.allclose(np.hypot(P[0] - e, P[1]), RB + r, rtol=1e-13, atol=0)       # inner raceway, outside
    r_min, r_max = G.extreme_roller_radii(RH, RB, e)
    assert r.min() == pytest.approx(r_min, rel=1e-14) and r.max() == pytest.approx(r_max, rel=1e-14)
    assert r_min == (RH - RB - e) / 2 and r_max == (RH - RB + e) / 2             # the gap at 0 and at pi
