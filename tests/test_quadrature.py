"""Tests of gearcalc.quadrature: piecewise trapezoid, Richardson, honest error, grading, breakpoints, for
both drivers (integrate_adaptive: one integral, per-piece doubling; integrate_pieces: many at once).

Expected values are closed-form integrals (stated next to each case) or scipy.integrate.quad.
"""
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from gearcalc.quadrature import (
    geometric_breakpoints,
    integrate_adaptive,
    integrate_pieces,
    nodes_of_pieces,
    piece_nodes,
    sign_change_breakpoints,
)


def test_piecewise_linear_is_exact():
    # trapezoid is exact for a linear function on each piece: integral of 2x+1 on [0, 3] = 9 + 3 = 12
    r = integrate_adaptive(lambda x, m: 2 * x + 1, [0.0, 1.3, 3.0], tol=1e-12)
    assert r.converged
    assert abs(r.value[0] - 12.0) < 1e-13
    assert r.err[0] < 1e-13


@pytest.mark.parametrize("tol", [1e-4, 1e-6, 1e-9])
def test_smooth_value_within_error_and_tolerance(tol):
    # integral of exp on [0, 1] = e - 1
    r = integrate_adaptive(lambda x, m: np.exp(x), [0.0, 1.0], tol=tol, n_start=16, n_max=2 ** 20)
    exact = math.e - 1
    assert r.converged
    assert abs(r.value[0] - exact) <= r.err[0]
    assert r.err[0] <= tol * abs(r.value[0])
    # Richardson is much better than the plain trapezoid
    assert abs(r.value[0] - exact) < abs(r.trapezoid[0] - exact) / 10


def test_jump_and_kink_with_breakpoints_second_order():
    # jump of 1 at x = 1/pi, kink |x - 0.7| on [0, 1]: exact = (1 - 1/pi) + (0.7^2 + 0.3^2)/2
    a, b = 1 / math.pi, 0.7
    exact = (1 - a) + (b * b + (1 - b) ** 2) / 2

    def f(x, mid):
        return np.where(mid > a, 1.0, 0.0) + np.abs(x - b)

    r = integrate_adaptive(f, [0.0, a, b, 1.0], tol=1e-10)
    assert r.converged
    assert abs(r.value[0] - exact) < 1e-13


def test_jump_without_breakpoint_is_only_first_order():
    # The same jump with the breakpoint omitted: the trapezoid error falls like 1/N, not 1/N^2
    a = 1 / math.pi
    exact = 1 - a

    def f(x, mid):
        return np.where(x > a, 1.0, 0.0)

    errs = []
    for n in (64, 128, 256, 512, 1024):
        r = integrate_adaptive(f, [0.0, 1.0], tol=1e-300, n_start=n, n_max=2 * n, min_levels=1)
        errs.append(abs(r.trapezoid[0] - exact))
    # first order: errors do not fall by 4 per doubling on average
    assert errs[0] / errs[-1] < 16 * 4
    with_bp = integrate_adaptive(lambda x, m: np.where(m > a, 1.0, 0.0), [0.0, a, 1.0], tol=1e-10)
    assert abs(with_bp.value[0] - exact) < 1e-14


def test_one_sided_limits_at_piece_ends():
    x, mid, piece = piece_nodes(np.array([0.0, 0.5, 1.0]), np.array([2, 4]))
    assert x.tolist() == [0.0, 0.25, 0.5, 0.5, 0.625, 0.75, 0.875, 1.0]
    assert mid.tolist() == [0.25] * 3 + [0.75] * 5
    assert piece.tolist() == [0] * 3 + [1] * 5


def test_a_tiny_integral_is_accepted_on_its_own_scale():
    # 1e-9 cos(x) on [0, 1] (= 1e-9 sin 1): the tolerance is relative (atol = 0: no absolute floor)
    r = integrate_adaptive(lambda x, m: 1e-9 * np.cos(x), [0.0, 1.0], tol=1e-8, atol=0.0, n_start=16, n_max=2 ** 20)
    exact = 1e-9 * math.sin(1.0)
    assert r.converged and abs(r.value[0] - exact) <= r.err[0] <= 1e-8 * exact


def test_cap_reports_not_converged():
    # x^(1/2) has an unbounded derivative at 0: with a tight tol and a small cap it must say so
    r = integrate_adaptive(lambda x, m: np.sqrt(x), [0.0, 1.0], tol=1e-12, n_start=16, n_max=256)
    assert not r.converged
    assert r.n <= 256
    assert abs(r.value[0] - 2 / 3) <= r.err[0]


def test_geometric_grading_resolves_boundary_layer():
    # x/sqrt(d^2 + x^2) on [0, 1], d = 1e-9: exact = sqrt(1 + d^2) - d
    d = 1e-9
    bp = np.concatenate(([0.0, 1.0], geometric_breakpoints(0.0, 1.0, d)))
    r = integrate_adaptive(lambda x, m: x / np.sqrt(d * d + x * x), bp, tol=1e-8, n_max=2 ** 20)
    exact = math.sqrt(1 + d * d) - d
    assert r.converged
    assert abs(r.value[0] - exact) <= r.err[0]
    assert r.n < 20000


def test_geometric_breakpoints_reach_the_layer():
    pts = geometric_breakpoints(1.0, 0.0, 1e-3)          # toward x0 = 1 from the left
    assert np.all(pts < 1.0) and np.all(pts > 0.0)
    assert 1.0 - pts.max() <= 1e-3 / 4
    assert geometric_breakpoints(0.0, 1.0, 2.0).size == 0


def test_sign_change_breakpoints():
    # zeros of cos(x) and of x - 2 on (0, 6): pi/2, 3 pi/2, 2
    br = sign_change_breakpoints(lambda x: np.vstack([np.cos(x), x - 2.0]), 0.0, 6.0, 100, 1e-14)
    assert np.allclose(br, [math.pi / 2, 2.0, 3 * math.pi / 2], atol=1e-13)


@settings(max_examples=30, deadline=None)
@given(amp=st.floats(0.1, 10), freq=st.floats(0.5, 30), shift=st.floats(-1, 1),
       cut=st.floats(0.05, 0.95), jump=st.floats(-5, 5))
def test_error_estimate_is_honest(amp, freq, shift, cut, jump):
    # amp sin(freq x) + 2 amp + jump*[x > cut] on [0, 1]: exact = amp (1 - cos freq)/freq + 2 amp + jump (1 - cut)
    def f(x, mid):
        return amp * np.sin(freq * x + shift) + 2 * amp + np.where(mid > cut, jump, 0.0)

    exact = amp * (math.cos(shift) - math.cos(freq + shift)) / freq + 2 * amp + jump * (1 - cut)
    for r in (integrate_adaptive(f, [0.0, cut, 1.0], tol=1e-6, n_max=2 ** 20),
              integrate_pieces(lambda x, m, p: f(x, m), [0.0, cut], [cut, 1.0], [0, 0], tol=1e-6)):
        assert r.converged
        assert abs(r.value[0] - exact) <= r.err[0] + 1e-14
        assert r.err[0] <= max(1e-6 * max(abs(r.value[0]), abs(r.trapezoid[0])), 1e-14)


def test_explicit_initial_counts_per_piece():
    # n_initial fixes the first level per piece; each doubling doubles it exactly (pins.md §12.6)
    r = integrate_adaptive(lambda x, m: np.exp(x), [0.0, 0.1, 1.0], tol=1e-300, n_initial=[5, 7],
                           n_max=48, min_levels=2)
    assert r.n_piece.tolist() == [20, 28] and r.n == 48
    assert abs(r.value[0] - (math.e - 1)) <= r.err[0]
    # counts that do not fit the pieces are ignored: the first level from n_start
    r = integrate_adaptive(lambda x, m: x, [0.0, 1.0], n_initial=[2, 2], n_start=16, tol=1e-12)
    assert r.n_piece.tolist() == [64] and r.value[0] == 0.5


@pytest.mark.parametrize("at_once", [1, 2])
@pytest.mark.parametrize("tol,n_initial", [(1e-6, None), (1e-10, None), (1e-8, [3, 1, 2, 5])])
def test_levels_at_once_are_the_doublings_one_after_the_other(at_once, tol, n_initial):
    # at_once evaluates the first level and its doublings in one call (the coarser levels' sums from the nested nodes
    # of the finest grid): the same pieces, counts, value and error as doubling one level per call (to round-off of
    # the node positions), in fewer calls; integrand: a jump at 1/pi, a kink at 0.7, 1/(x + 1e-3) on the last piece
    calls = {True: 0, False: 0}

    def f(x, mid, tag):
        calls[tag] += 1
        return (np.where(mid > 1 / math.pi, 1.0, 0.0) + np.abs(x - 0.7)
                + np.where(mid > 0.8, 1.0 / (x - 0.8 + 1e-3), 0.0))

    edges = [0.0, 1 / math.pi, 0.7, 0.8, 1.0]
    one = integrate_adaptive(lambda x, m: f(x, m, False), edges, tol=tol, n_initial=n_initial)
    many = integrate_adaptive(lambda x, m: f(x, m, True), edges, tol=tol, n_initial=n_initial, at_once=at_once)
    assert many.n_piece.tolist() == one.n_piece.tolist() and many.converged == one.converged
    assert many.value[0] == pytest.approx(one.value[0], rel=1e-14)
    assert many.err[0] == pytest.approx(one.err[0], rel=1e-6, abs=1e-15)
    assert calls[True] == calls[False] - at_once
    exact = (1 - 1 / math.pi) + (0.7 ** 2 + 0.3 ** 2) / 2 + math.log(0.2 / 1e-3 + 1.0)
    assert abs(many.value[0] - exact) <= many.err[0]


# ------------------------------------------------------------------ many integrals at once (integrate_pieces)

def _three(x, mid, piece):
    # owner 0: exp on [0, 1] (= e - 1); owner 1: a jump and a kink on [0, 1/pi, 0.7, 1] (see above);
    # owner 2: 1/(x + 1e-3) on [0, 1] (= ln 1001), steep near 0
    return np.where(piece == 0, np.exp(x),
                    np.where(piece <= 3, np.where(mid > 1 / math.pi, 1.0, 0.0) + np.abs(x - 0.7), 1.0 / (x + 1e-3)))


A3, B3, O3 = [0.0, 0.0, 1 / math.pi, 0.7, 0.0], [1.0, 1 / math.pi, 0.7, 1.0, 1.0], [0, 1, 1, 1, 2]
EXACT3 = [math.e - 1, (1 - 1 / math.pi) + (0.7 ** 2 + 0.3 ** 2) / 2, math.log(1001.0)]


@pytest.mark.parametrize("tol", [1e-3, 1e-6, 1e-9])
def test_pieces_and_adaptive_agree_within_their_errors_owner_by_owner(tol):
    # each owner's integral within its error of the closed form, with either driver on the owner's pieces
    r = integrate_pieces(_three, A3, B3, O3, tol=tol)
    for o in range(3):
        sel = [i for i, w in enumerate(O3) if w == o]
        edges = [A3[sel[0]]] + [B3[i] for i in sel]
        one = integrate_adaptive(lambda x, m, p0=sel[0]: _three(x, m, np.full(x.shape, p0)), edges, tol=tol,
                                 n_start=16, n_max=2 ** 20)
        assert abs(r.value[o] - EXACT3[o]) <= r.err[o] + 1e-14
        assert abs(one.value[0] - EXACT3[o]) <= one.err[0] + 1e-14
        assert abs(r.value[o] - one.value[0]) <= r.err[o] + one.err[0] + 1e-14
        assert not one.converged or one.err[0] <= max(tol * abs(one.value[0]), 1e-14)


def test_pieces_owners_are_independent_and_rounds_do_not_matter():
    # an owner's result is the same bit for bit alone, with others, and whatever the first round's levels
    together = integrate_pieces(_three, A3, B3, O3, tol=1e-8)
    for first in (1, 2, 5, 9):
        r = integrate_pieces(_three, A3, B3, O3, tol=1e-8, first_levels=first, max_nodes=300)
        assert r.value.tolist() == together.value.tolist() and r.err.tolist() == together.err.tolist()
    alone = integrate_pieces(lambda x, m, p: _three(x, m, p + 4), [0.0], [1.0], [0], tol=1e-8)
    assert alone.value[0] == together.value[2] and alone.err[0] == together.err[2] and alone.n[0] == together.n[2]


def _alone(o, integrand=None):
    """Owner o of the _three integrals as a single-owner problem (integrate_pieces' own path for one owner):
    (f, a, b, owner); f is ``integrand`` (default _three) with owner o's piece numbers."""
    sel = [i for i, w in enumerate(O3) if w == o]
    integrand = integrand or _three
    return (lambda x, m, p: integrand(x, m, p + sel[0])), [A3[i] for i in sel], [B3[i] for i in sel], [0] * len(sel)


@pytest.mark.parametrize("tol", [1e-3, 1e-8, 1e-12])
@pytest.mark.parametrize("first,max_nodes", [(None, 2 ** 22), (1, 2 ** 22), (3, 2 ** 22), (9, 2 ** 22), (1, 300)])
def test_single_owner_equals_the_owner_among_many(tol, first, max_nodes):
    # the single-owner path (scalar bookkeeping, first round as one grid) gives every owner's result and
    # final grid bit for bit as the many-owner path, in one round or several, with levels discarded or not
    together = integrate_pieces(_three, A3, B3, O3, tol=tol)
    for o in range(3):
        f, a, b, owner = _alone(o)
        r = integrate_pieces(f, a, b, owner, tol=tol, first_levels=first, max_nodes=max_nodes)
        for name in ("value", "err", "trapezoid", "n", "converged", "levels"):
            assert getattr(r, name)[0] == getattr(together, name)[o], (o, name)
        sel = np.repeat(together.owner, together.n_piece + 1) == o
        for got, ref in zip(r.grid(), nodes_of_pieces(r.a, r.b, r.n_piece)):
            assert np.array_equal(got, ref)
        assert np.array_equal(r.grid()[0], together.grid()[0][sel])


def _with_rows(x, mid, piece):
    # the _three integrands, then rows to carry: the node, its midpoint and piece, and a smooth function
    return np.stack([_three(x, mid, piece), x, mid, piece.astype(float), np.sin(7.0 * x)])


@pytest.mark.parametrize("first,max_nodes", [(None, 2 ** 22), (9, 2 ** 22), (1, 300)])
def test_carried_rows_are_the_integrand_at_the_final_grid(first, max_nodes):
    # rows after the first are not integrated but delivered at the final grid's nodes (in its order): each
    # node's values are those of the evaluation at exactly that node, whichever round evaluated it, and
    # nodes of discarded levels are dropped; one owner alone and among many
    many = integrate_pieces(_with_rows, A3, B3, O3, tol=1e-9, first_levels=first, max_nodes=max_nodes)
    plain = integrate_pieces(_three, A3, B3, O3, tol=1e-9, first_levels=first, max_nodes=max_nodes)
    assert many.value.tolist() == plain.value.tolist() and many.err.tolist() == plain.err.tolist()
    cases = [many] + [integrate_pieces(*_alone(o, _with_rows), tol=1e-9, first_levels=first, max_nodes=max_nodes)
                      for o in range(3)]
    for r in cases:
        x, mid, piece = r.grid()
        assert r.carried.shape == (4, x.size)
        assert np.array_equal(r.carried[0], x) and np.array_equal(r.carried[1], mid)
        assert np.array_equal(r.carried[3], np.sin(7.0 * x))
    assert np.array_equal(many.carried[2], many.grid()[2].astype(float))
    assert plain.carried is None


def test_pieces_cap_and_grid():
    # at the cap the doubling stops, not converged, with the last two levels' difference as the error
    r = integrate_pieces(_three, A3, B3, O3, tol=1e-300, n_max=256)
    assert r.converged.tolist() == [False, True, False]          # owner 1 is piecewise linear: E = 0 <= atol
    assert r.n[0] == r.n[2] == 256 and r.err[0] > 0 and r.err[2] > 0
    x, mid, piece = r.grid()
    assert x.size == int(np.sum(r.n_piece + 1)) and np.all(np.diff(piece) >= 0)
    assert x.tolist() == nodes_of_pieces(r.a, r.b, r.n_piece)[0].tolist()


# ------------------------------------------------------------------ the opt-in Gauss-Kronrod rule (integrate_adaptive)

@pytest.mark.parametrize("rule,degree", [("gk7", 11), ("gk15", 23)])
def test_gauss_kronrod_is_exact_for_polynomials_of_its_degree(rule, degree):
    # the Kronrod rule of m nodes integrates polynomials of degree 3m/2 + 1 exactly on every piece; the error
    # estimate |K - G| then measures the embedded Gauss rule (degree 2 (m - 1)/2 - 1): not exact, but above the
    # true error 0.  int_0^1 x^d dx = 1/(d + 1)
    r = integrate_adaptive(lambda x, m: x ** degree, [0.0, 1.0], tol=1.0, rule=rule)
    assert r.converged and r.rule == rule and r.n == {"gk7": 7, "gk15": 15}[rule]
    assert abs(r.value[0] - 1.0 / (degree + 1)) < 1e-15
    assert r.err[0] >= abs(r.value[0] - 1.0 / (degree + 1))


@settings(max_examples=30, deadline=None)
@given(amp=st.floats(0.1, 10), freq=st.floats(0.5, 30), shift=st.floats(-1, 1),
       cut=st.floats(0.05, 0.95), jump=st.floats(-5, 5))
@pytest.mark.parametrize("rule", ["gk7", "gk15"])
def test_gauss_kronrod_error_estimate_is_honest(rule, amp, freq, shift, cut, jump):
    # the same integrands as test_error_estimate_is_honest: a jump at a breakpoint, smooth on both sides
    def f(x, mid):
        return amp * np.sin(freq * x + shift) + 2 * amp + np.where(mid > cut, jump, 0.0)

    exact = amp * (math.cos(shift) - math.cos(freq + shift)) / freq + 2 * amp + jump * (1 - cut)
    r = integrate_adaptive(f, [0.0, cut, 1.0], tol=1e-6, n_max=2 ** 20, rule=rule)
    assert r.converged
    assert abs(r.value[0] - exact) <= r.err[0] + 1e-14
    assert r.err[0] <= max(1e-6 * abs(r.value[0]), 1e-14)


@pytest.mark.parametrize("rule", ["gk7", "gk15"])
def test_gauss_kronrod_bisects_with_the_membership_of_the_breakpoints_piece(rule):
    # a piece's halves keep its midpoint as mid (set membership): the step decided by mid stays a step at the
    # breakpoint 1, though the halves' own midpoints lie elsewhere; exp on [1, 3] needs bisection at tol 1e-13.
    # int_0^1 0 + int_1^3 (1 + e^x) = 2 + e^3 - e
    def f(x, mid):
        return np.where(mid < 1.0, 0.0, 1.0 + np.exp(x))

    r = integrate_adaptive(f, [0.0, 1.0, 3.0], tol=1e-13, rule=rule)
    exact = 2.0 + math.e ** 3 - math.e
    assert r.converged and abs(r.value[0] - exact) <= r.err[0] + 1e-15
    x, mid, piece = r.grid()
    assert x.size == r.n_piece.sum() and np.all((x > 0.0) & (x < 3.0))
    assert set(np.unique(mid).tolist()) <= {0.5, 2.0}
    assert np.all((mid == 0.5) == (x < 1.0))
    if rule == "gk7":       # n counts every evaluation, the bisected pieces' own included
        assert r.levels >= 1 and r.n > r.n_piece.sum()


def test_gauss_kronrod_is_honest_on_a_graded_boundary_layer_and_needs_fewer_evaluations():
    # the x^(1/9) layer of the Hertz law, graded geometrically (pins.md §6): closed form 9/10
    edges = np.sort(np.concatenate(([0.0, 1.0], geometric_breakpoints(0.0, 1.0, 1e-8, ratio=0.25))))
    trap = integrate_adaptive(lambda x, mid: x ** (1.0 / 9.0), edges, tol=1e-6)
    for rule in ("gk7", "gk15"):
        q = integrate_adaptive(lambda x, mid: x ** (1.0 / 9.0), edges, tol=1e-6, rule=rule)
        assert q.converged and abs(q.value[0] - 0.9) <= q.err[0] <= 1e-6 * 0.9
        assert q.n < trap.n


def test_gauss_kronrod_cap_and_unknown_rule():
    # the cap on evaluations: unconverged, the estimate still bounds the error; int_0^1 sqrt(x) = 2/3
    r = integrate_adaptive(lambda x, m: np.sqrt(x), [0.0, 1.0], tol=1e-15, n_max=100, rule="gk7")
    assert not r.converged and r.n <= 100 and abs(r.value[0] - 2.0 / 3.0) <= r.err[0]
    with pytest.raises(ValueError, match="rule"):
        integrate_adaptive(lambda x, m: x, [0.0, 1.0], rule="simpson")


def test_a_non_finite_sum_stops_its_owner_at_once():
    # an integrand that overflows (a pins sweep point with curtate_ratio 1e-306) stayed non-finite at every
    # level and was doubled to n_max (2^20 intervals, seconds); its owner now stops at the first level whose sum
    # is not finite, value and error NaN, not converged; the other owners are untouched
    def f(x, mid, piece):
        with np.errstate(over="ignore"):
            return np.where(piece == 1, np.exp(800.0 + x), np.exp(x))

    r = integrate_pieces(f, [0.0, 0.0], [1.0, 1.0], [0, 1], tol=1e-10, n_max=2 ** 20)
    ok = integrate_pieces(lambda x, m, p: np.exp(x), [0.0], [1.0], [0], tol=1e-10, n_max=2 ** 20)
    assert r.value[0] == ok.value[0] and r.err[0] == ok.err[0] and r.n[0] == ok.n[0] and r.converged[0]
    assert math.isnan(r.value[1]) and math.isnan(r.err[1]) and not r.converged[1] and r.n[1] <= 64
    alone = integrate_pieces(lambda x, m, p: f(x, m, p + 1), [0.0], [1.0], [0], tol=1e-10, n_max=2 ** 20)
    assert math.isnan(alone.value[0]) and math.isnan(alone.err[0]) and not alone.converged[0]   # one-owner path
    assert alone.n[0] <= 64


# ---- the pieces' Richardson estimate (piece_errors; pins.md §6, decided 2026-11-27)

@settings(max_examples=60, deadline=None)
@given(a=st.floats(0.05, 4.0), tol=st.sampled_from([1e-3, 1e-5, 1e-7, 1e-9]), n_start=st.sampled_from([2, 8, 64]))
def test_romberg_estimate_is_honest_on_an_end_singularity(a, tol, n_start):
    # int_0^1 x^a dx = 1/(1 + a) (closed form); x^a with a in [0.58, 1.32] makes the ratio of two differences
    # 2^(1 + a) fall in ROMBERG_RATIO, where R_2N is off by e (1/(r - 1) - 1/3) and the estimate is e (4 - r)/3
    r = integrate_adaptive(lambda x, m: x ** a, [0.0, 1.0], tol=tol, n_start=n_start, n_max=2 ** 20)
    assert r.err[0] <= tol * abs(r.value[0]) if r.converged else r.n > 2 ** 19     # small a: error ~ h^(1 + a)
    assert abs(r.value[0] - 1.0 / (1.0 + a)) <= r.err[0]


@settings(max_examples=60, deadline=None)
@given(amp=st.floats(0.1, 10), freq=st.floats(0.5, 200), shift=st.floats(-3, 3),
       tol=st.sampled_from([1e-3, 1e-6, 1e-9]))
def test_romberg_estimate_is_honest_on_a_resolved_oscillation(amp, freq, shift, tol):
    # amp sin(freq x + shift) + 2 amp on [0, 1], closed form; the first level has >= 1 node per radian (resolved: below
    # 2 nodes per wavelength any rule aliases, and so did the two-doubling rule before, in 80 % of such cases)
    def f(x, mid):
        return amp * np.sin(freq * x + shift) + 2 * amp

    exact = amp * (math.cos(shift) - math.cos(freq + shift)) / freq + 2 * amp
    n_start = 1 << max(1, math.ceil(math.log2(freq)))
    r = integrate_adaptive(f, [0.0, 1.0], tol=tol, n_start=n_start, n_max=2 ** 22)
    assert r.converged and r.err[0] <= tol * abs(r.value[0])
    assert abs(r.value[0] - exact) <= r.err[0] + 1e-15 * abs(exact)


def test_romberg_estimate_needs_fewer_nodes_and_stays_conservative():
    # exp on [0, 1] (exact e - 1) from 64 intervals: the change of the Richardson value overstates its error ~15x
    # (R_N's error against R_2N's ~16x smaller), where e_p alone overstated it ~10^4x and doubled to tol on it
    from gearcalc.quadrature import piece_errors

    r = integrate_adaptive(lambda x, m: np.exp(x), [0.0, 1.0], tol=1e-10, n_start=64)
    actual = abs(r.value[0] - (math.e - 1))
    assert r.converged and r.n == 256 and 5 <= r.err[0] / actual <= 30
    # the rule by hand: a piece off its asymptotic ratio keeps e_p and the two-doubling rule; a piece without a
    # difference before (one level) too
    E, E_prev, est = piece_errors(np.array([1e-6, 1e-6]), np.array([4e-6, 2e-6]))
    assert E == pytest.approx(1e-6) and E_prev == pytest.approx(2e-6) and est.tolist() == pytest.approx([0.0, 2e-6])
    E, E_prev, _ = piece_errors(np.array([1e-6]), np.array([np.nan]))
    assert E == pytest.approx(1e-6) and E_prev == 0.0
