"""Tests of gearcalc.hertz (Hertz line contact) against independent forms and constants."""
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from gearcalc import hertz

# (E1, nu1, E2, nu2): steel/steel, steel/bronze, steel/cast iron, ceramic/steel
MATERIALS = [(2.1e5, 0.3, 2.1e5, 0.3), (2.1e5, 0.3, 1.1e5, 0.34), (2.06e5, 0.29, 1.2e5, 0.25),
             (3.1e5, 0.26, 2.08e5, 0.3)]
# (roller radius, raceway radius with sign: > 0 convex (inner ring), < 0 concave (outer ring))
PAIRS = [(22.0, 50.0), (22.0, -100.0), (5.0, 7.0), (5.0, -5.5)]


def paper_eq3(force, length, rho, e1, nu1, e2, nu2):
    """The paper's eq. (3) written out literally (Merko et al.)."""
    return math.sqrt(force * e1 * e2 / (math.pi * (e1 * (1 - nu2 ** 2) + e2 * (1 - nu1 ** 2)) * length * rho))


@pytest.mark.parametrize("mat", MATERIALS)
@pytest.mark.parametrize("pair", PAIRS)
def test_paper_eq3_is_johnson_p0(mat, pair):
    # spec §7.1.3: eq. (3) equals Johnson's p0 = sqrt(P'E*/(pi R)) to 1e-12, dissimilar materials,
    # convex and concave contacts; rho from eqs. (4)/(5) equals 1/R = 1/r ± 1/R_raceway.
    r, big = pair
    rho = r * abs(big) / (abs(big) + r) if big > 0 else r * abs(big) / (abs(big) - r)
    assert hertz.reduced_radius(r, big) == pytest.approx(rho, rel=1e-13)
    force, length = 3456.7, 18.0
    e_star = hertz.contact_modulus(*mat)
    p0 = hertz.peak_pressure(force, length, rho, e_star)
    assert p0 == pytest.approx(paper_eq3(force, length, rho, *mat), rel=1e-12)
    # eq. (6) with k of eq. (7)
    k = hertz.stress_coefficient(*mat)
    assert k * math.sqrt(force / (length * rho)) == pytest.approx(p0, rel=1e-12)


@settings(max_examples=60, deadline=None)
@given(st.floats(1e3, 1e6), st.floats(0.01, 0.49), st.floats(1e3, 1e6), st.floats(0.01, 0.49))
def test_paired_modulus_identity(e1, nu1, e2, nu2):
    # E1E2/(E1(1-nu2²) + E2(1-nu1²)) == 1/((1-nu1²)/E1 + (1-nu2²)/E2): exact algebraic identity
    assert hertz.paired_modulus(e1, nu1, e2, nu2) == pytest.approx(hertz.contact_modulus(e1, nu1, e2, nu2),
                                                                   rel=1e-13)


@pytest.mark.parametrize("mat", MATERIALS)
@pytest.mark.parametrize("pair", PAIRS)
def test_roark_forms(mat, pair):
    # Roark (cylinder on cylinder / in a seat): sigma = 0.798 sqrt(p/(K_D C_E)), 2b = 1.60 sqrt(p K_D C_E);
    # the constants are sqrt(2/pi) and sqrt(8/pi) rounded, so agreement to 2e-4 and 3e-3 (spec §2).
    e1, nu1, e2, nu2 = mat
    r, big = pair
    d1, d2 = 2 * r, 2 * abs(big)
    k_d = d1 * d2 / (d1 + d2) if big > 0 else d1 * d2 / (d2 - d1)
    c_e = (1 - nu1 ** 2) / e1 + (1 - nu2 ** 2) / e2
    force, length = 5000.0, 20.0
    p = force / length
    rho = hertz.reduced_radius(r, big)
    e_star = hertz.contact_modulus(*mat)
    assert hertz.peak_pressure(force, length, rho, e_star) == pytest.approx(0.798 * math.sqrt(p / (k_d * c_e)),
                                                                             rel=2e-4)
    assert 2 * hertz.semi_width(force, length, rho, e_star) == pytest.approx(1.60 * math.sqrt(p * k_d * c_e),
                                                                              rel=3e-3)


@settings(max_examples=50, deadline=None)
@given(st.floats(1e-3, 1e7), st.floats(0.5, 100.0), st.floats(0.1, 500.0), st.floats(1e4, 4e5))
def test_semi_width_identities(force, length, rho, e_star):
    # Johnson (4.43)/(4.45): b = 2F/(pi l p0); and the trap b = sqrt(2PR/(pi E*)) is sqrt(2) too small
    p0 = hertz.peak_pressure(force, length, rho, e_star)
    b = hertz.semi_width(force, length, rho, e_star)
    assert b == pytest.approx(2 * force / (math.pi * length * p0), rel=1e-12)
    assert b / math.sqrt(2 * (force / length) * rho / (math.pi * e_star)) == pytest.approx(math.sqrt(2), rel=1e-12)


def test_russian_form_for_nu_03():
    # 0.418 sqrt(F E_pr/(l rho)), E_pr = 2E1E2/(E1+E2): exact only for nu = 0.3 on both bodies, up to the
    # rounding of 0.418 (sqrt(1/(2 pi 0.91)) = 0.41822...)
    e1, e2 = 2.1e5, 1.2e5
    force, length, rho = 7000.0, 15.0, 12.0
    e_pr = 2 * e1 * e2 / (e1 + e2)
    p0 = hertz.peak_pressure(force, length, rho, hertz.contact_modulus(e1, 0.3, e2, 0.3))
    assert p0 == pytest.approx(0.418 * math.sqrt(force * e_pr / (length * rho)), rel=6e-4)
    # with nu = 0.25 the form is off by more than its rounding
    p0b = hertz.peak_pressure(force, length, rho, hertz.contact_modulus(e1, 0.25, e2, 0.25))
    assert abs(p0b / (0.418 * math.sqrt(force * e_pr / (length * rho))) - 1) > 1e-2


def test_subsurface_shear_constants():
    # Johnson §2.8: on the axis of a Hertz line contact, sigma_x = -p0/b[(b²+2z²)/sqrt(b²+z²) - 2z],
    # sigma_z = -p0 b/sqrt(b²+z²); tau_1 = |sigma_x - sigma_z|/2 has its maximum 0.30 p0 at 0.786 b.
    # Independent numerical maximisation with scipy.
    from scipy.optimize import minimize_scalar

    def tau(t):  # b = p0 = 1
        sx = -((1 + 2 * t * t) / math.sqrt(1 + t * t) - 2 * t)
        sz = -1 / math.sqrt(1 + t * t)
        return 0.5 * abs(sx - sz)

    res = minimize_scalar(lambda t: -tau(t), bounds=(0.2, 2.0), method="bounded", options={"xatol": 1e-12})
    assert -res.fun == pytest.approx(hertz.TAU_MAX_RATIO, rel=1e-10)
    assert res.x == pytest.approx(hertz.TAU_MAX_DEPTH_RATIO, rel=1e-6)
    assert hertz.max_subsurface_shear(1000.0) == pytest.approx(1000.0 * hertz.TAU_MAX_RATIO)
    assert round(hertz.TAU_MAX_RATIO, 2) == 0.30 and round(hertz.TAU_MAX_DEPTH_RATIO, 3) == 0.786


def test_vectorised_and_zero_force():
    f = np.array([[0.0, 1.0, 10.0], [100.0, 1e3, 1e4]])
    rho = np.array([5.0, 10.0, 20.0])
    p0 = hertz.peak_pressure(f, 20.0, rho, 115384.6)
    assert p0.shape == (2, 3) and p0[0, 0] == 0.0 and np.all(np.isfinite(p0))
    assert hertz.semi_width(f, 20.0, rho, 115384.6)[0, 0] == 0.0
    # p0 ∝ sqrt(F): exact scaling
    assert p0[1, 2] / p0[0, 2] == pytest.approx(math.sqrt(1e3), rel=1e-13)


# ---------------------------------------------------------------- the maximum (Tresca) shear for any Poisson ratio
# (issue 16 item 3; zstk.md §2) Expected: the issue's values (0.330 p0 at nu = 0.2, 0.368 at 0.15, 0.408 at 0.1,
# 0.452 at 0.05), the exact depth sqrt((sqrt 5 - 1)/2) of tau_1, and a brute-force maximisation over depth (dense
# grid, then scipy) of the largest principal-stress difference of Johnson's closed-form stresses along the contact
# axis (§2.8, eq. 2.25; plane strain sigma_y = nu(sigma_x + sigma_z)), principal stresses sorted by numpy.
# ----------------------------------------------------------------------------- item 3: Tresca shear
def axis_stresses(t, nu):
    """Johnson 1985 eq. 2.25 along the axis (x = 0) of a Hertz line contact, over p0; plane strain."""
    s = np.sqrt(1.0 + t * t)
    sx = -((1.0 + 2.0 * t * t) / s - 2.0 * t)
    sz = -1.0 / s
    return sx, nu * (sx + sz), sz


def brute_tresca(nu):
    from scipy.optimize import minimize_scalar

    def tau(t):
        p = np.sort(np.stack(axis_stresses(np.asarray(t, float), nu)), axis=0)
        return 0.5 * (p[-1] - p[0])

    t = np.linspace(0.0, 3.0, 30001)
    k = int(np.argmax(tau(t)))
    r = minimize_scalar(lambda x: -tau(x), bracket=(t[k - 1], t[k], t[k + 1]), tol=1e-12)
    return -r.fun, r.x


@pytest.mark.parametrize("nu, expected", [(0.2, 0.330), (0.15, 0.368), (0.1, 0.408), (0.05, 0.452)])
def test_tresca_matches_the_issue_values(nu, expected):
    ratio, depth = hertz.tresca_shear_ratio(nu)
    assert round(float(ratio), 3) == expected
    assert depth < hertz.TAU_MAX_DEPTH_RATIO          # shallower than the in-plane maximum


@pytest.mark.parametrize("nu", [0.01, 0.05, 0.1, 0.2, 0.24, 0.2422, 0.2423, 0.25, 0.3, 0.35, 0.45, 0.499])
def test_tresca_against_brute_force_over_depth(nu):
    ratio, depth = hertz.tresca_shear_ratio(nu)
    b_ratio, b_depth = brute_tresca(nu)
    assert float(ratio) == pytest.approx(b_ratio, rel=1e-10)
    assert float(depth) == pytest.approx(b_depth, rel=1e-5)


def test_tresca_constants_are_exact():
    t = math.sqrt((math.sqrt(5.0) - 1.0) / 2.0)   # tau_1 maximum: t^4 + t^2 = 1 (the issue)
    assert hertz.TAU_MAX_DEPTH_RATIO == t == pytest.approx(0.786151377757423, abs=1e-15)
    assert hertz.TAU_MAX_RATIO == pytest.approx(t ** 5, rel=1e-13)
    from scipy.optimize import brentq, minimize_scalar

    def out_of_plane(nu):  # max over depth of (sigma_y - sigma_z)/2 alone
        r = minimize_scalar(lambda x: -0.5 * (axis_stresses(x, nu)[1] - axis_stresses(x, nu)[2]), bounds=(0.0, 2.0),
                            method="bounded", options={"xatol": 1e-12})
        return -r.fun

    nu_c = brentq(lambda nu: out_of_plane(nu) - t ** 5, 0.2, 0.3, xtol=1e-12)
    assert hertz.TRESCA_POISSON_CROSSOVER == pytest.approx(nu_c, abs=1e-7)
    # at and above the crossover the in-plane values, bit for bit (the results of nu = 0.3 designs stay)
    assert [float(x) for x in hertz.tresca_shear_ratio(0.3)] == [hertz.TAU_MAX_RATIO, hertz.TAU_MAX_DEPTH_RATIO]
