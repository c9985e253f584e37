"""Physics tests of gearcalc.zstk.chain (spec zstk.md): geometry, closure, phase, the paper's claims, hard cases (the
load distribution: tests/zstk/test_loads.py).

Expected numbers come from exact identities, closed-form limits, published constants (Stribeck
4.08, Johnson/Hertz), independent solvers (scipy, explicit stepping) and the paper's claims.
"""
import math
from decimal import Decimal, getcontext

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from gearcalc import hertz
from gearcalc import zstk as z

PAPER = {"outer_radius": 100.0, "inner_radius": 50.0, "eccentricity": 6.0, "gap": 6.0}  # Merko et al. example
Q = 1e4
STEEL = z.Materials.from_elastic(20.0, 2.1e5, 0.3, 2.1e5, 0.3, 2.1e5, 0.3)


def paper_chain(n=None, correct="outer", **over):
    g = {**PAPER, **over}
    n_star = z.fractional_roller_number(g["outer_radius"], g["inner_radius"], g["eccentricity"], g["gap"])
    n = z.auto_roller_number(float(n_star)) if n is None else n
    return z.close_chain(g["outer_radius"], g["inner_radius"], g["eccentricity"], g["gap"], n, correct)


def state(chain, phase, gamma, load=Q, clearance=0.0, mats=STEEL, **kw):
    theta = z.roller_angles(phase, chain.n, chain.limiting_ratio)
    return z.evaluate(chain, mats, theta, gamma, load, clearance, **kw)


geometries = st.tuples(st.floats(20.0, 200.0), st.floats(0.1, 0.9), st.floats(0.0, 0.95), st.floats(0.0, 0.9))


def make_geometry(t):
    """(R_H, R_B, e, c) from unit fractions, valid by construction (e < D, e < S/sqrt2, c < 2R_B)."""
    r_h, fb, fe, fc = t
    r_b = fb * r_h
    d = r_h - r_b
    e = fe * min(d, (r_h + r_b) / math.sqrt(2))
    c = fc * min(2 * r_b, d)  # c < D keeps N* large enough to be interesting
    return r_h, r_b, e, c


def equilibrium_error(st_, load):
    nb, f = st_.normal_angle, st_.force_inner
    g = st_.gamma[..., None]
    ax = np.sum(f * np.cos(nb - g), axis=-1) - load
    tr = np.sum(f * np.sin(nb - g), axis=-1)
    return np.abs(ax) / load, np.abs(tr) / load



# ----------------------------------------------------------------------------- §3.1 geometry
@pytest.mark.parametrize("theta", np.linspace(-np.pi, np.pi, 13))
def test_radius_forms_agree(theta):
    # cancellation-free form == R_H - h(theta) (direct ellipse form), moderate geometry
    r = z.roller_radius(theta, 100.0, 50.0, 6.0)
    assert r == pytest.approx(100.0 - z.centre_distance(theta, 100.0, 50.0, 6.0), rel=1e-13)


def test_radius_extremes_exact():
    # r(0) = (D - e)/2, r(pi) = (D + e)/2 exactly (spec §3.1)
    assert z.roller_radius(0.0, 100.0, 50.0, 6.0) == 22.0
    assert z.roller_radius(np.pi, 100.0, 50.0, 6.0) == pytest.approx(28.0, rel=1e-15)


def test_tiny_roller_radius_accurate():
    # e -> D: the smallest roller is 1e-10 mm; check r(theta) at small theta against 50-digit Decimal
    # arithmetic of R_H - h(theta) (cos by its Taylor series), which the naive float form cannot resolve.
    getcontext().prec = 60
    r_h, r_b = 100.0, 50.0
    e = 50.0 - 2e-10
    for th in (0.0, 1e-6, 1e-3):
        x = Decimal(th)
        cos = 1 + sum((-1) ** k * x ** (2 * k) / Decimal(math.factorial(2 * k)) for k in range(1, 12))
        s, ed = Decimal(r_h) + Decimal(r_b), Decimal(e)
        exact = Decimal(r_h) - (s * s - ed * ed) / (2 * (s - ed * cos))
        assert float(z.roller_radius(th, r_h, r_b, e)) == pytest.approx(float(exact), rel=1e-12)


@settings(max_examples=40, deadline=None)
@given(geometries, st.floats(-math.pi, math.pi))
def test_tangency_and_normals(t, theta):
    r_h, r_b, e, _ = make_geometry(t)
    r = z.roller_radius(theta, r_h, r_b, e)
    p = z.centres(np.array(theta), r_h, r_b, e)
    # tangent to both raceways to 1e-9 mm (spec §7.2)
    assert abs(np.hypot(*p) - (r_h - r)) <= 1e-9
    assert abs(np.hypot(p[0] - e, p[1]) - (r_b + r)) <= 1e-9
    # beta: the angle O_B P O_H; sin beta = e |sin theta|/(R_B + r); signed offset rotates n_H into n_B
    bs = z.normal_angle_offset(theta, r_h, r_b, e)
    assert math.sin(abs(bs)) == pytest.approx(e * abs(math.sin(theta)) / (r_b + r), rel=1e-9, abs=1e-15)
    nb = np.array([p[0] - e, p[1]]) / (r_b + r)
    assert nb[0] == pytest.approx(math.cos(theta + bs), abs=1e-12)
    assert nb[1] == pytest.approx(math.sin(theta + bs), abs=1e-12)


def test_beta_zero_on_line_and_for_e0():
    assert z.normal_angle_offset(0.0, 100.0, 50.0, 6.0) == 0.0
    assert np.all(z.normal_angle_offset(np.linspace(-3, 3, 7), 100.0, 50.0, 0.0) == 0.0)


def test_reduced_radii_match_paper_eqs_4_5():
    r, h = 22.0, 78.0
    rb, rh = z.reduced_radii(r, h, 50.0, 100.0)
    assert rb == pytest.approx(r * 50.0 / (50.0 + r), rel=1e-15)  # eq. (4)
    assert rh == pytest.approx(r * 100.0 / (100.0 - r), rel=1e-15)  # eq. (5)
    assert rb == pytest.approx(hertz.reduced_radius(r, 50.0)) and rh == pytest.approx(hertz.reduced_radius(r, -100.0))


# ----------------------------------------------------------------------------- §3.2 closure
def test_worked_example_n_star():
    # sin²(pi/N*) = (W² - e²)/(S² - e²) with W = 56, S = 150, e = 6 (spec §3.2), evaluated directly
    n_star = math.pi / math.asin(math.sqrt((56.0 ** 2 - 36.0) / (150.0 ** 2 - 36.0)))
    assert z.fractional_roller_number(100.0, 50.0, 6.0, 6.0) == pytest.approx(n_star, rel=1e-14)
    assert z.auto_roller_number(n_star) == 8 and 8 < n_star < 9


@pytest.mark.parametrize("correct", ["outer", "inner", "gap"])
@settings(max_examples=30, deadline=None)
@given(t=geometries, dn=st.integers(-3, 2))
def test_correction_closes_chain(correct, t, dn):
    r_h, r_b, e, c = make_geometry(t)
    n_star = float(z.fractional_roller_number(r_h, r_b, e, c))
    n = max(3, math.floor(n_star) + dn)
    ch = z.close_chain(r_h, r_b, e, c, n, correct)
    assume(not z.chain_problems(ch))
    # N* of the corrected geometry == N to 1e-9 (spec §7.2)
    assert z.fractional_roller_number(ch.outer_radius, ch.inner_radius, ch.eccentricity, ch.gap) == pytest.approx(
        n, abs=1e-9)
    # the closure condition (C) in its inversive-distance form
    x, a = ch.outer_radius + ch.gap / 2, ch.inner_radius - ch.gap / 2
    lhs = (x * x + a * a - e * e) / (2 * x * a)
    assert lhs == pytest.approx(1 + 2 * math.tan(math.pi / n) ** 2, rel=1e-9)
    # direction of the correction follows from N vs N* (spec §3.2, choice of N)
    if n < n_star - 1e-9:
        assert {"outer": ch.corrected > ch.nominal, "inner": ch.corrected < ch.nominal,
                "gap": ch.corrected > ch.nominal}[correct]


def test_concentric_steiner_formula():
    # e = 0: (C) becomes sin(pi/N) = (X - A)/(X + A) (MathWorld "Steiner chain")
    ch = z.close_chain(100.0, 50.0, 0.0, 4.0, 9, "gap")
    x, a = ch.outer_radius + ch.gap / 2, ch.inner_radius - ch.gap / 2
    assert math.sin(math.pi / 9) == pytest.approx((x - a) / (x + a), rel=1e-13)
    assert ch.limiting_ratio == 0.0


def test_n_star_monotone():
    # N* falls when R_H or c grows, rises when R_B grows (spec §3.2)
    f = z.fractional_roller_number
    assert f(101.0, 50.0, 6.0, 6.0) < f(100.0, 50.0, 6.0, 6.0)
    assert f(100.0, 50.0, 6.0, 6.5) < f(100.0, 50.0, 6.0, 6.0)
    assert f(100.0, 51.0, 6.0, 6.0) > f(100.0, 50.0, 6.0, 6.0)


@pytest.mark.parametrize("correct", ["outer", "inner", "gap"])
def test_n_max_is_the_validity_limit(correct):
    # at N = N_max (real) the corrected geometry sits exactly on its validity limit (spec §3.3)
    r_h, r_b, e, c = 100.0, 50.0, 6.0, 6.0
    n_max = z.roller_number_limit(correct, r_h, r_b, e, c)
    if correct == "outer":
        assert z.corrected_outer_radius(n_max, r_b, e, c) - r_b - e == pytest.approx(0.0, abs=1e-9)
    elif correct == "inner":
        assert z.corrected_inner_radius(n_max, r_h, e, c) == pytest.approx(r_h - e, rel=1e-12)
    else:
        assert z.corrected_gap(n_max, r_h, r_b, e) == pytest.approx(0.0, abs=1e-9)
    assert z.roller_number_limit("outer", r_h, r_b, e, 0.0) == math.inf


def test_admissible_interval_reported():
    ok = z.close_chain(100.0, 50.0, 6.0, 6.0, 31)
    bad = z.close_chain(100.0, 50.0, 6.0, 6.0, 32)
    assert z.chain_problems(ok) == []
    (key, msg), = z.chain_problems(bad)
    assert key == "rollers" and "3 ≤ N ≤ 31" in msg
    assert z.chain_problems(z.close_chain(100.0, 50.0, 6.0, 6.0, 9, "gap")) == []
    assert "3 ≤ N ≤ 9" in z.chain_problems(z.close_chain(100.0, 50.0, 6.0, 6.0, 10, "gap"))[0][1]


@pytest.mark.parametrize("n_star,parity,expected", [(8.25, None, 8), (8.25, 0, 8), (8.25, 1, 7), (9.0 - 1e-10, 0, 8),
                                                    (9.0 - 1e-10, 1, 9), (8.0 + 1e-10, None, 8), (3.5, 0, 2)])
def test_auto_roller_number(n_star, parity, expected):
    assert z.auto_roller_number(n_star, parity) == expected


def test_exact_integer_n_star_means_no_correction():
    ch = z.close_chain(100.0, 50.0, 6.0, 6.0, 8)
    again = z.close_chain(ch.outer_radius, 50.0, 6.0, 6.0, 8)
    assert again.corrected == again.nominal


@pytest.mark.parametrize("args,key", [((100.0, 100.0, 0.0, 1.0), "inner"), ((100.0, 0.0, 0.0, 1.0), "inner"),
                                      ((100.0, 50.0, 50.0, 1.0), "eccentricity"),
                                      ((100.0, 50.0, -1.0, 1.0), "eccentricity"),
                                      ((100.0, 50.0, 6.0, 100.0), "gap"), ((100.0, 50.0, 6.0, -1.0), "gap"),
                                      ((100.0, 1.0, 71.5, 0.0), "eccentricity")])
def test_geometry_problems(args, key):
    assert key in [k for k, _ in z.geometry_problems(*args)]


# ----------------------------------------------------------------------------- §4 positions
@settings(max_examples=30, deadline=None)
@given(geometries, st.floats(0.0, 2 * math.pi))
def test_gaps_equal_c_for_any_phase(t, phase):
    # porism: the corrected chain closes from any phase; all N gaps == c to 1e-9 mm (spec §7.2)
    r_h, r_b, e, c = make_geometry(t)
    n = z.auto_roller_number(float(z.fractional_roller_number(r_h, r_b, e, c)))
    assume(n >= 3)
    ch = z.close_chain(r_h, r_b, e, c, n)
    assume(not z.chain_problems(ch))
    theta = z.roller_angles(phase, n, ch.limiting_ratio)
    gaps = z.neighbour_gaps(theta, ch.outer_radius, ch.inner_radius, ch.eccentricity)
    assert np.max(np.abs(gaps - ch.gap)) <= 1e-9


@pytest.mark.parametrize("phase", [0.0, 0.1, 0.3, 0.7, 2.0])
@pytest.mark.parametrize("correct", ["outer", "inner", "gap"])
def test_stepping_cross_check(phase, correct):
    # explicit stepping closes with residual < 1e-9 mm independent of the start, and matches the
    # closed-form Möbius positions (spec §4.1)
    ch = paper_chain(correct=correct)
    theta = z.roller_angles(phase, ch.n, ch.limiting_ratio)
    stepped, res = z.step_chain(theta[0], ch.n, ch.outer_radius, ch.inner_radius, ch.eccentricity, ch.gap)
    assert res < 1e-9
    assert np.max(np.abs(z.wrap_angle(stepped[:-1] - theta))) < 1e-10


def test_equal_rollers_equally_spaced_for_e0():
    ch = z.close_chain(100.0, 50.0, 0.0, 3.0, 10, "gap")
    theta = z.roller_angles(0.2, 10, ch.limiting_ratio)
    assert np.allclose(np.diff(theta), 2 * np.pi / 10, atol=1e-14)
    assert np.allclose(z.roller_radius(theta, 100.0, 50.0, 0.0), 25.0, rtol=1e-14)


def test_small_rollers_crowd_the_narrow_side():
    ch = paper_chain()
    th = z.roller_angles(0.0, ch.n, ch.limiting_ratio)
    steps = np.diff(np.degrees(th))
    assert steps[0] < steps[3]  # pitch at the narrow side < pitch at the wide side


@pytest.mark.parametrize("scheme,n,at0,at180", [("A", 8, "roller", "roller"), ("B", 7, "roller", "gap"),
                                               ("C", 7, "gap", "roller"), ("D", 8, "gap", "gap")])
def test_scheme_table(scheme, n, at0, at180):
    ch = paper_chain(n=n)
    th = np.degrees(z.wrap_angle(z.roller_angles(z.scheme_phase(scheme, n), n, ch.limiting_ratio)))

    def has(a):
        return np.any(np.abs(z.wrap_angle(np.radians(th - a))) < 1e-9)

    assert has(0.0) == (at0 == "roller")
    assert has(180.0) == (at180 == "roller")
    # mirror-symmetric about the line of centres: every roller has a mirror roller at -theta
    d = np.abs(z.wrap_angle(np.radians(th[:, None] + th[None, :])))
    assert np.all(np.min(d, axis=1) < 1e-9)


# ----------------------------------------------------------------------------- hard cases
def test_e_zero_and_tiny_continuous():
    a = paper_chain(eccentricity=0.0)
    b = paper_chain(eccentricity=1e-12)
    assert a.limiting_ratio == 0.0 and 0 < b.limiting_ratio < 1e-12
    sa, sb = state(a, 0.0, 0.0), state(b, 0.0, 0.0)
    # sigma ∝ sqrt(F) is not Lipschitz where F -> 0 (rollers at 90°), hence the absolute 1e-4 MPa (1e-7 of sigma_max)
    assert np.allclose(sa.sigma_inner, sb.sigma_inner, rtol=1e-9, atol=1e-4)
    assert np.all(sa.beta == 0.0)


def test_vanishing_smallest_roller_finite():
    # e -> D with the rollers of the nominal geometry (correct = "gap" keeps R_H, R_B): tiny roller, finite sigma
    ch = z.close_chain(100.0, 50.0, 50.0 - 1e-6, 0.0, 12, "gap")
    assert not z.chain_problems(ch)
    s = state(ch, 0.0, 0.0)
    assert s.radius[0] == pytest.approx(5e-7, rel=1e-6)
    assert np.all(np.isfinite(s.sigma_inner)) and np.isfinite(np.max(s.sigma_inner))
    b = hertz.semi_width(s.force_inner[0], 20.0, s.rho_inner[0], STEEL.e_star_inner)
    assert b > 0.1 * s.rho_inner[0]  # the b/rho warning case


def test_gap_zero_and_tiny_continuous():
    a, b = paper_chain(gap=0.0), paper_chain(gap=1e-9)
    assert a.n_limit == math.inf
    sa, sb = state(a, 0.0, 0.0), state(b, 0.0, 0.0)
    assert np.allclose(sa.sigma_inner, sb.sigma_inner, rtol=1e-6)


def test_many_rollers():
    # N > 200 (spec §9): every invariant holds
    ch = paper_chain(outer_radius=100.0, inner_radius=97.5, eccentricity=0.5, gap=0.05)
    assert ch.n > 200
    theta = z.roller_angles(0.1, ch.n, ch.limiting_ratio)
    gaps = z.neighbour_gaps(theta, ch.outer_radius, ch.inner_radius, ch.eccentricity)
    assert np.max(np.abs(gaps - ch.gap)) <= 1e-9
    s = state(ch, 0.1, 0.7)
    ax, tr = equilibrium_error(s, Q)
    assert ax <= 1e-9 and tr <= 1e-9


@pytest.mark.parametrize("load", [1e-6, 1e9])
def test_extreme_loads(load):
    ch = paper_chain()
    s = state(ch, 0.2, 0.3, load=load)
    ax, tr = equilibrium_error(s, load)
    assert ax <= 1e-9 and tr <= 1e-9
    assert np.all(np.isfinite(s.sigma_inner))


# ----------------------------------------------------------------------------- the paper's claims (§6)
def test_claim1_inner_contact_more_stressed():
    for n, scheme in ((8, "A"), (7, "B"), (7, "C"), (8, "D")):
        ch = paper_chain(n=n)
        for gamma in np.linspace(0, 2 * np.pi, 13):
            s = state(ch, z.scheme_phase(scheme, n), gamma)
            loaded = s.force_inner > 0
            assert np.all(s.sigma_inner[loaded] > s.sigma_outer[loaded])


@pytest.mark.parametrize("scheme,n", [("A", 8), ("B", 7)])
def test_claim2_max_at_smallest_roller_on_load_line(scheme, n):
    ch = paper_chain(n=n)
    s = state(ch, z.scheme_phase(scheme, n), 0.0, symmetric=True)
    _, i, contact = z.critical(s)
    assert i == 0 and contact == 0 and s.theta[0] == 0.0
    assert s.radius[0] == pytest.approx(np.min(s.radius))


def test_claim2_envelope_max_at_smallest_roller():
    ch = paper_chain()
    for scheme in ("A", "D"):
        theta = z.roller_angles(z.scheme_phase(scheme, ch.n), ch.n, ch.limiting_ratio)
        gammas = np.linspace(0, 2 * np.pi, 721)
        s = z.evaluate(ch, STEEL, theta, gammas, Q)
        per_roller = np.max(s.sigma_inner, axis=0)
        i = int(np.argmax(per_roller))
        assert s.radius[0, i] == pytest.approx(np.min(s.radius[0]), rel=1e-9)
        assert np.max(per_roller) > np.max(np.max(s.sigma_outer, axis=0))


def test_claim3_u_shape_on_line_of_centres():
    # per-roller maximum over gamma = 0 and 180°: maxima at the smallest and largest rollers, minima off the line
    ch = paper_chain()
    theta = z.roller_angles(0.0, ch.n, ch.limiting_ratio)
    s = z.evaluate(ch, STEEL, theta, np.array([0.0, np.pi]), Q, symmetric=True)
    env = np.max(s.sigma_inner, axis=0)
    r = s.radius[0]
    order = np.argsort(r)
    sig = env[order]
    inner = sig[1:-1]
    assert sig[0] > np.max(inner) and sig[-1] > np.max(inner)  # ends highest
    k = int(np.argmin(sig))
    assert 0 < k < len(sig) - 1  # the minimum lies between (off the load line)


@pytest.mark.parametrize("scheme", ["A", "D"])
def test_claim4_outer_vs_inner_correction(scheme):
    res = []
    for correct in ("outer", "inner"):
        ch = paper_chain(correct=correct)
        s = state(ch, z.scheme_phase(scheme, ch.n), 0.0, symmetric=True)
        res.append(float(z.critical(s)[0]))
    assert abs(res[0] / res[1] - 1) < 0.05


def test_claim5_correction_enlarges_rollers():
    ch = paper_chain()
    d = ch.corrected - ch.nominal
    assert d > 0
    r_min0, r_max0 = z.roller_radius(0.0, 100.0, 50.0, 6.0), z.roller_radius(np.pi, 100.0, 50.0, 6.0)
    assert z.roller_radius(0.0, ch.outer_radius, 50.0, 6.0) - r_min0 == pytest.approx(d / 2, rel=1e-12)
    assert z.roller_radius(np.pi, ch.outer_radius, 50.0, 6.0) - r_max0 == pytest.approx(d / 2, rel=1e-12)


def test_dissimilar_materials_use_their_moduli():
    m = z.Materials.from_elastic(20.0, 2.1e5, 0.3, 1.1e5, 0.34, 2.1e5, 0.3)
    ch = paper_chain()
    s = state(ch, 0.0, 0.0, mats=m, symmetric=True)
    i = 0
    assert s.sigma_inner[i] == pytest.approx(
        hertz.peak_pressure(s.force_inner[i], 20.0, s.rho_inner[i], hertz.contact_modulus(2.1e5, 0.3, 1.1e5, 0.34)),
        rel=1e-14)
    assert s.sigma_outer[i] == pytest.approx(
        hertz.peak_pressure(s.force_outer[i], 20.0, s.rho_outer[i], hertz.contact_modulus(2.1e5, 0.3, 2.1e5, 0.3)),
        rel=1e-14)


@pytest.mark.parametrize("x0", [0.0, 1.0, 3.0, 6.0])
def test_maximise_periodic_known_function(x0):
    # a smooth periodic function with its maximum 2.0 at x0, and one with a kink
    r = z.maximise_periodic(lambda x: 2.0 - (1 - np.cos(x - x0)) ** 2 - 0.1 * (1 - np.cos(x - x0)),
                            0.0, 2 * np.pi, 16, 1e-10)
    assert abs(r.value - 2.0) <= max(r.err, 1e-12)
    assert abs(z.wrap_angle(r.x - x0)) < 1e-4
    k = z.maximise_periodic(lambda x: 1.0 - np.abs(z.wrap_angle(x - x0)), 0.0, 2 * np.pi, 16, 1e-8)
    assert abs(k.value - 1.0) <= k.err + 1e-12


def test_cycle_phase_envelope_covers_schemes():
    # the placement envelope over one pitch is >= every scheme's value (A and D are phases of the chain)
    ch = paper_chain()

    def f(ph):
        return z.critical(state(ch, ph, 0.0))[0]

    sw = z.maximise_periodic(f, 0.0, 2 * np.pi / ch.n, 64, 1e-8)
    for scheme in ("A", "D"):
        assert sw.value >= f(z.scheme_phase(scheme, ch.n)) - 1e-9
    fine = np.max(f(np.linspace(0, 2 * np.pi / ch.n, 4001)))
    assert abs(sw.value - fine) <= max(sw.err, 1e-6 * sw.value)


def test_stepping_finds_a_neighbour_more_than_half_a_turn_ahead():
    """A very eccentric chain (R_H = 20, R_B' = 5.65 after the inner correction, e = 10.94, c = 3.125,
    N = 5) has a pitch of 187.5° about O_H between its two largest rollers; the explicit stepping must
    still close it (spec §7.2: residual < 1e-9 mm, any start phase).  Found by a property test."""
    ch = z.close_chain(20.0, 7.5, 10.9375, 3.125, 5, "inner")
    theta = z.roller_angles(np.array([0.0, 0.3, 1.0]), ch.n, ch.limiting_ratio)
    assert np.max(np.diff(np.concatenate([theta[0], [theta[0, 0] + 2 * np.pi]]))) > np.pi  # the wide pitch
    _, res = z.step_chain(theta[:, 0], ch.n, ch.outer_radius, ch.inner_radius, ch.eccentricity, ch.gap)
    assert np.all(res < 1e-9)


def test_remainder_360_is_exact_for_every_float():
    # issue 34: the reduction of a direction or phase angle lost every digit above about 1e17 (33 of 300 random
    # angles >= 4e40 gave a BracketError). math.remainder(x, 360) is the reference (IEEE remainder, exact).
    import random

    from gearcalc.zstk.geometry import remainder_360

    rng = random.Random(34)
    xs = [rng.choice((-1, 1)) * 10 ** rng.uniform(-5, 308) for _ in range(3000)]
    xs += [180.0 + 360.0 * k for k in range(-40, 40)] + [1.7976931348623157e308, -1.7976931348623157e308, 5e-324]
    got = remainder_360(np.array(xs)).tolist()
    assert got == [math.remainder(x, 360.0) for x in xs]


@settings(max_examples=200, deadline=None)
@given(st.lists(st.tuples(st.one_of(st.floats(allow_nan=False), st.sampled_from([0.0, 1e-9, 5.0 - 1e-9, 5.0 + 1e-10,
                                                                             2.0 ** 52, -2.0 ** 53, math.inf])),
                          st.sampled_from(["outer", "inner", "gap"])), max_size=12))
def test_largest_admissible_ns_is_the_function_of_each_design(pairs):
    """The vectorised N_admissible_max of a stack (zstk.md §3.3) equals the scalar rule point by point: the same
    Python integers (None without a limit), also at the 1e-9 edges and past 2**52 (where floats lose the -1)."""
    limits = np.array([p[0] for p in pairs], dtype=float)
    corrects = np.array([p[1] for p in pairs], dtype=object)
    got = z.largest_admissible_ns(limits, corrects)
    want = [z.largest_admissible_n(lim, c) for lim, c in pairs]
    assert got == want and [type(v) for v in got] == [type(v) for v in want]
