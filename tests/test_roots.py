"""Tests of gearcalc.roots: the vectorised bracketed root finders and the golden-section minimiser.

scipy serves as the independent reference (scipy.optimize.brentq / minimize_scalar).
"""
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from gearcalc.roots import BracketError, bisect, find_root, minimize_golden

CASES = [  # (f, a, b), each with one sign change
    (lambda x: np.cos(x) - x, 0.0, 1.0),
    (lambda x: x**3 - 2 * x - 5, 2.0, 3.0),  # Wallis' cubic, root 2.0945514815423265
    (lambda x: np.exp(x) - 1e6, 0.0, 30.0),
    (lambda x: np.tanh(50 * (x - 0.3)), -1.0, 1.0),  # steep
    (lambda x: (x - 1.0) ** 3, 0.0, 3.0),  # triple root: slow for interpolation, bisection fallback
    (lambda x: np.where(x < 0.7, -1.0, 1.0), 0.0, 1.0),  # a jump: any method must return the jump
]


@pytest.mark.parametrize("f,a,b", CASES)
@pytest.mark.parametrize("method", [find_root, bisect])
def test_against_brentq(f, a, b, method):
    from scipy.optimize import brentq

    ref = brentq(lambda x: float(f(np.float64(x))), a, b, xtol=1e-14, rtol=8.9e-16, maxiter=1000)
    r = method(f, a, b, xtol=1e-13)
    assert bool(r.converged)
    assert abs(float(r.root) - ref) <= float(r.err) + 2e-13


def test_wallis_cubic_published_root():
    # the classical root of x^3 - 2x - 5 (Wallis, quoted by Newton): 2.0945514815423265
    r = find_root(lambda x: x**3 - 2 * x - 5, 2.0, 3.0)
    assert float(r.root) == pytest.approx(2.0945514815423265, rel=1e-15)


def test_vectorised_equals_scalar():
    c = np.linspace(0.1, 10.0, 50)
    r = find_root(lambda x: x**2 - c, 0.0, 10.0)
    assert np.allclose(r.root, np.sqrt(c), rtol=1e-14)
    for k in (0, 17, 49):
        rk = find_root(lambda x, ck=c[k]: x**2 - ck, 0.0, 10.0)
        assert float(rk.root) == pytest.approx(r.root[k], rel=1e-14)


def test_bracket_without_sign_change_raises():
    with pytest.raises(BracketError) as e:
        find_root(lambda x: x**2 + 1, np.array([-1.0, 0.0]), np.array([1.0, 2.0]))
    assert e.value.mask.tolist() == [True, True]


def test_exact_zero_at_end():
    r = find_root(lambda x: x - 1.0, 1.0, 2.0)
    assert float(r.root) == 1.0 and float(r.err) == 0.0


@settings(max_examples=50, deadline=None)
@given(root=st.floats(-1e3, 1e3), scale=st.floats(1e-3, 1e3))
def test_error_bound_is_honest(root, scale):
    f = lambda x: np.sinh((x - root) / scale)  # noqa: E731
    r = find_root(f, root - 7 * scale, root + 3 * scale, xtol=1e-12)
    assert abs(float(r.root) - root) <= float(r.err) + 1e-15 * abs(root)


@pytest.mark.parametrize("x0", [0.3, 3.1, 11.5])
def test_golden_against_scipy(x0):
    from scipy.optimize import minimize_scalar

    f = lambda x: (x - x0) ** 2 * (1 + 0.1 * x) + 0.5  # noqa: E731
    ref = minimize_scalar(f, bounds=(0.0, 12.0), method="bounded", options={"xatol": 1e-12}).x
    r = minimize_golden(f, 0.0, 12.0, rtol=1e-10)
    assert abs(float(r.x) - ref) <= float(r.err) + 1e-9
    assert abs(float(r.x) - x0) <= float(r.err) + 1e-9 * x0


def test_golden_bound_flag_and_floor():
    r = minimize_golden(lambda x: x, 1.0, 2.0, rtol=1e-12)
    assert bool(r.on_bound) and float(r.x) == 1.0
    # a search on values cannot place a minimum better than ~sqrt(eps): the error never claims more
    r = minimize_golden(lambda x: (x - 2.0) ** 2, 0.0, 5.0, rtol=1e-15)
    assert float(r.err) >= 3 * math.sqrt(np.finfo(float).eps) * 2.0 * 0.999


def test_golden_vectorised():
    x0 = np.array([1.0, 2.5, 4.0])
    r = minimize_golden(lambda x: (x - x0) ** 2, 0.0, 5.0, rtol=1e-9)
    assert np.all(np.abs(r.x - x0) <= r.err)


# a smooth peak (reference: scipy's bounded Brent on the negated function; accurate to round-off in value at a
# smooth maximum), a flat-topped (quartic) peak, a concave kink and sin near the bracket end (exact maxima 0, 0, 1)
MAX_CASES = [
    (lambda x: np.cos(3 * x) + 0.1 * np.sin(7 * x), -0.5, 0.5, None),
    (lambda x: -(x - 0.2) ** 4, -1.0, 1.0, 0.0),
    (lambda x: -np.abs(x - 0.3) * 5 - (x - 0.3) ** 2, 0.0, 1.0, 0.0),
    (lambda x: np.sin(x), 0.0, 1.6, 1.0),
]


@pytest.mark.parametrize("f,a,b,exact", MAX_CASES)
@pytest.mark.parametrize("target", [1e-6, 1e-12])
def test_maximize_bracketed_bound_covers_the_maximum(f, a, b, exact, target):
    from scipy.optimize import minimize_scalar

    from gearcalc.roots import maximize_bracketed

    ref = exact
    if ref is None:
        ref = -minimize_scalar(lambda x: -float(f(x)), bounds=(a, b), method="bounded", options={"xatol": 1e-13}).fun
    r = maximize_bracketed(lambda x, i: f(x), np.array([a]), np.array([b]), f(np.array([a])), f(np.array([b])),
                           target)
    assert bool(r.converged[0]) and r.bound[0] <= target
    assert r.value[0] <= ref + 1e-15 and ref <= r.value[0] + r.bound[0] + 1e-15
    assert r.iterations <= 40


@pytest.mark.parametrize("f,exact", [
    (lambda x: np.full_like(x, 2.5), 2.5),   # constant: the maximum is every sample (e.g. zstk at e = 0)
    (lambda x: -x, 0.0),                     # decreasing: the maximum is the left end of the bracket
])
def test_maximize_bracketed_left_end_best_has_a_finite_bound(f, exact):
    # regression: the first iteration's placeholder for the best point repeated the left end; when that end was
    # (or tied with) the largest sample it was taken as the best point, its left neighbour was itself and the bound
    # was inf (not converged) -- the concentric zstk design's sigma_max_err_MPa came out inf.  The exact maxima
    # on [0, 1] are f(0).
    from gearcalc.roots import maximize_bracketed

    a, b = np.array([0.0]), np.array([1.0])
    r = maximize_bracketed(lambda x, i: f(x), a, b, f(a), f(b), 1e-12)
    assert bool(r.converged[0]) and np.isfinite(r.bound[0]) and r.bound[0] <= 1e-12
    assert r.value[0] <= exact <= r.value[0] + r.bound[0]
