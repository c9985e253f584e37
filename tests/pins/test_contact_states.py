"""Tests of the solved contact states and their helpers (gearcalc.pins.contact_states; pins.md §5.5, §6, §12.6).

Independent references: exact identities — a cubic Hermite interpolant reproduces any cubic and its slope (Burden &
Faires §3.4); the nearest-point distance against a brute-force minimum; the merged parts against numpy's stable sort;
states taken apart and put together again against the states solved at once.
"""
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

from gearcalc.pins import MULTIPLIER, Cycloid
from gearcalc.pins import contact as pc
from gearcalc.pins import contact_states as cs

coef = st.floats(-1e3, 1e3)


@settings(max_examples=100, deadline=None)
@given(c=st.tuples(coef, coef, coef, coef), xa=st.floats(-10, 10), h=st.floats(1e-3, 10.0),
       t=st.floats(0.0, 1.0))
def test_hermite_reproduces_a_cubic_and_its_slope(c, xa, h, t):
    def f(x):
        return c[0] + c[1] * x + c[2] * x ** 2 + c[3] * x ** 3

    def df(x):
        return c[1] + 2 * c[2] * x + 3 * c[3] * x ** 2

    xb, x = xa + h, xa + t * h
    scale = sum(abs(a) for a in c) * (1 + abs(xa) + h) ** 3
    assert cs.hermite(t, h, f(xa), df(xa), f(xb), df(xb)) == pytest.approx(f(x), abs=1e-11 * scale)
    assert cs.hermite_slope(t, h, f(xa), df(xa), f(xb), df(xb)) == pytest.approx(df(x), abs=1e-10 * scale / h)


@settings(max_examples=100, deadline=None)
@given(p=hnp.arrays(float, st.integers(1, 20), elements=st.floats(-100, 100)),
       x=hnp.arrays(float, st.integers(0, 20), elements=st.floats(-200, 200)))
def test_distance_to_is_the_brute_force_minimum(p, x):
    p = np.sort(p)
    want = np.abs(x[:, None] - p[None, :]).min(axis=1) if x.size else x
    assert np.array_equal(cs.distance_to(p, x), want)


@settings(max_examples=100, deadline=None)
@given(st.lists(hnp.arrays(float, st.integers(1, 8), elements=st.sampled_from([0.0, 0.5, 1.0, 1.5, 2.0, 3.0])),
                min_size=1, max_size=4))
def test_merged_parts_are_the_stable_sort_of_their_concatenation(parts):
    whole = np.concatenate(parts)
    order = whole.argsort(kind="stable")
    tags = [np.full(a.size, i) + np.arange(a.size) / 100 for i, a in enumerate(parts)]   # which element went where
    places = cs.sorted_places(parts)
    assert np.array_equal(cs.merged(parts, places, 0), whole[order])
    assert np.array_equal(cs.merged(tags, places, 0), np.concatenate(tags)[order])


def test_states_taken_apart_and_put_together_are_the_states_solved_at_once():
    g = Cycloid.from_curtate_ratio(20, 22, 3.9, 0.75, 1.95)
    m = pc.ContactModel(g, pc.CycloidProfile(g), pc.ContactLaw("linear", 1e7, 1.0), 1e5, MULTIPLIER)
    theta = np.linspace(0.01, g.period - 0.01, 9)
    sol = m.state(theta)
    odd, even = cs.take_states(sol, slice(1, None, 2)), cs.take_states(sol, slice(0, None, 2))
    assert np.array_equal(odd.theta, theta[1::2]) and np.array_equal(odd.force, sol.force[..., 1::2])
    both = cs.concat_states([odd, even])                         # sorted by theta again
    for name in ("theta", "tau", "dtau", "force", "delta", "phase"):
        assert np.array_equal(getattr(both, name), getattr(sol, name)), name
    blank = cs.take_states(sol, slice(None))
    blank.force = np.zeros_like(sol.force)
    cs.put_states(blank, even, slice(0, None, 2))
    assert np.array_equal(blank.force[..., ::2], sol.force[..., ::2]) and not blank.force[..., 1::2].any()
