"""Physics tests of gearcalc.pins (pins.md §3, §4, §6, §9).

Independent references: the paper's printed worked values (seed 000, eqs. (3)-(7)); exact geometric
identities recomputed here from first principles (vectors in the fixed frame); closed forms of
pins.md §4.8; finer quadrature runs.
"""
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from gearcalc import pins
from gearcalc.pins import MULTIPLIER, REDUCER, Cycloid
from gearcalc.quadrature import integrate_adaptive


def gear(z1=20, z2=22, e=3.9, K1=0.75, Rb=1.95):
    return Cycloid.from_curtate_ratio(z1, z2, e, K1, Rb)


def u(a):
    return np.array([np.cos(a), np.sin(a)])


def cross(a, b):
    return a[0] * b[1] - a[1] * b[0]


# ------------------------------------------------------------------ formula level (pins.md §3)

# The paper's printed outputs (seed 000, eqs. (3)-(7) for Figs. 8-11); the last column is the
# number of decimals printed for (F_tr1, F_tr2, P_tr1, P_tr2, P_tr).
PAPER_CASES = [
    # F_n, R, r, n_pin, printed (F_tr1, F_tr2, P_tr1, P_tr2, P_tr), decimals
    ("cyc u10", 1920, 1.95, 0.95, 14, (9.85, 192, 0.028, 0.267, 0.295), (2, 0, 3, 3, 3)),
    ("cyc u30", 870, 1.95, 0.95, 34, (4.46, 87, 0.031, 0.294, 0.325), (2, 0, 3, 3, 3)),
    ("circ u10", 2100, 2.75, 1.75, 18, (7.64, 210, 0.04, 0.692, 0.732), (2, 0, 2, 3, 3)),
    ("circ u30", 1110, 2.5, 1.5, 61, (4.44, 111, 0.071, 1.063, 1.134), (2, 0, 3, 3, 3)),
]


@pytest.mark.parametrize("case", PAPER_CASES, ids=[c[0] for c in PAPER_CASES])
def test_paper_formula_cases_with_paper_pi(case):
    _, Fn, R, r, n, printed, dec = case
    res = pins.formula_losses(Fn, n, R, r, 0.01, 0.1, paper_pi=True)
    got = (res.F_tr1, res.F_tr2, res.P_tr1, res.P_tr2, res.P_tr)
    for g, p, d in zip(got, printed, dec):
        assert abs(g - p) <= 0.5 * 10.0 ** (-d) + 1e-12, (g, p)


@pytest.mark.parametrize("case", PAPER_CASES, ids=[c[0] for c in PAPER_CASES])
def test_paper_formula_cases_with_exact_pi(case):
    # exact pi: powers 0.05 % higher; tolerance half a unit plus 0.1 % (pins.md §3)
    _, Fn, R, r, n, printed, dec = case
    res = pins.formula_losses(Fn, n, R, r, 0.01, 0.1)
    got = (res.F_tr1, res.F_tr2, res.P_tr1, res.P_tr2, res.P_tr)
    for g, p, d in zip(got, printed, dec):
        assert abs(g - p) <= 0.5 * 10.0 ** (-d) + 1e-3 * abs(p), (g, p)
    ref = pins.formula_losses(Fn, n, R, r, 0.01, 0.1, paper_pi=True)
    assert res.P_tr / ref.P_tr == pytest.approx(math.pi / 3.14, rel=1e-14)


@settings(max_examples=30, deadline=None)
@given(Fn=st.floats(1, 1e5), n=st.floats(0.1, 1e4), R=st.floats(0.5, 20), q=st.floats(0.05, 0.95),
       fk=st.floats(1e-4, 0.1), fc=st.floats(1e-3, 0.5), f=st.floats(0.01, 0.5))
def test_formula_derived_consequences(Fn, n, R, q, fk, fc, f):
    r = q * R
    res = pins.formula_losses(Fn, n, R, r, fk, fc)
    # R cancels in P_tr1 = f_k F_n omega 1e-3
    assert res.P_tr1 == pytest.approx(fk * Fn * n * math.pi / 30 * 1e-3, rel=1e-12)
    # P_tr2/P_tr = f_c r/(f_c r + f_k)
    assert res.P_tr2 / res.P_tr == pytest.approx(fc * r / (fc * r + fk), rel=1e-12)
    # P_tr/P_tr,fix = (f_c r + f_k)/(f R)
    fix = pins.fixed_pin_formula_loss(Fn, n, R, f)
    assert res.P_tr / fix == pytest.approx((fc * r + fk) / (f * R), rel=1e-12)


# ------------------------------------------------------------------ geometry (pins.md §4.1-4.3)

def test_s_factor_matches_law_of_cosines_and_is_cancellation_free():
    psi = np.linspace(0, 2 * np.pi, 97)
    K1 = 0.6
    assert np.allclose(pins.s_factor(psi, K1, 1 - K1), np.sqrt(1 + K1 ** 2 - 2 * K1 * np.cos(psi)), rtol=1e-14)
    # K1 = 1 - 1e-12 at psi = 0: s = 1e-12 exactly (the naive form gives 0 or noise)
    assert pins.s_factor(0.0, 1 - 1e-12, 1e-12) == pytest.approx(1e-12, rel=1e-12)
    # small psi: s ~ sqrt(d^2 + K1 psi^2)
    d, p = 1e-9, 3e-9
    assert pins.s_factor(p, 1 - d, d) == pytest.approx(math.sqrt(d * d + (1 - d) * p * p), rel=1e-9)


def test_contact_point_lies_on_the_normal_through_the_pitch_point():
    g = gear()
    psi = np.linspace(0.01, 3.1, 50)
    cx, cy = pins.contact_point(psi, g)
    A = g.R_p * u(psi)
    P = np.array([g.r_p2, 0.0])[:, None]
    C = np.vstack([cx, cy])
    assert np.allclose(np.hypot(*(C - A)), g.R_b, rtol=1e-12)                    # on the pin
    assert np.allclose(cross(C - A, P - A), 0.0, atol=1e-9)                       # on line A-P
    assert np.allclose(np.hypot(*(A - P)), pins.pitch_distance(psi, g), rtol=1e-13)


def test_lever_arm_is_moment_arm_of_the_normal_about_O1():
    # |(P - O1) x n| with n the unit normal from A through P; signed as in pins.md §4.4
    g = gear(z1=33, z2=36, K1=0.6)
    psi = np.linspace(-3, 3, 41)
    A = g.R_p * u(psi)
    P = np.array([g.r_p2, 0.0])[:, None]
    O1 = np.array([g.e, 0.0])[:, None]
    n = (P - A) / np.hypot(*(P - A))
    arm = -cross(P - O1, n)          # moment of a unit force along n is -l (pins.md §4.4 sign)
    assert np.allclose(pins.lever_arm(psi, g), arm, rtol=1e-12, atol=1e-12)


@pytest.mark.parametrize("z1,z2,K1", [(20, 22, 0.75), (21, 22, 0.6), (30, 33, 0.9), (60, 62, 0.5)])
def test_curvature_radius_matches_the_pin_centre_curve(z1, z2, K1):
    # curvature of c_0(beta) = R_p u(beta) - e u(Z_e beta) from its analytic derivatives, against
    # R_p s^3/D at psi = -Z_d beta (the parameter relation of pins.md §4.2)
    g = gear(z1, z2, K1=K1)
    Zd, Ze = z1 / g.k, z2 / g.k
    psi = np.linspace(0.3, 3.0, 9)
    beta = -psi / Zd
    dx = -g.R_p * np.sin(beta) + g.e * Ze * np.sin(Ze * beta)
    dy = g.R_p * np.cos(beta) - g.e * Ze * np.cos(Ze * beta)
    ddx = -g.R_p * np.cos(beta) + g.e * Ze ** 2 * np.cos(Ze * beta)
    ddy = -g.R_p * np.sin(beta) + g.e * Ze ** 2 * np.sin(Ze * beta)
    radius = (dx * dx + dy * dy) ** 1.5 / np.abs(dx * ddy - dy * ddx)
    assert np.allclose(radius, np.abs(pins.curvature_radius(psi, g)), rtol=1e-11)


@pytest.mark.parametrize("z1,z2", [(20, 22), (21, 22), (30, 33), (9, 13)])
def test_tooth_profile_is_the_contact_point_in_the_satellite_frame(z1, z2):
    # crank-frame contact point, rotated into the satellite frame (X = Rot(-phi)(C - O1),
    # phi = -k theta/z1), equals Gamma_b(beta), beta = phi_i + k theta/z1, b = i mod k
    g = gear(z1, z2, K1=0.7)
    k = g.k
    for theta in (0.0, 0.37, -1.2):
        for i in range(z2):
            psi = 2 * np.pi * i / z2 - theta
            cx, cy = pins.contact_point(psi, g)               # crank frame: crank along x
            C = (u(theta) * cx + np.array([-np.sin(theta), np.cos(theta)]) * cy)   # fixed frame
            O1 = g.e * u(theta)
            phi = -k * theta / z1
            X = np.array([[np.cos(-phi), -np.sin(-phi)], [np.sin(-phi), np.cos(-phi)]]) @ (C - O1)
            G = pins.tooth_profile(2 * np.pi * i / z2 + k * theta / z1, i % k, g)
            assert np.allclose(X, G, atol=1e-10)


@pytest.mark.parametrize("z1,z2", [(20, 22), (60, 62), (30, 33), (40, 44), (12, 15)])
def test_crest_cutoff_puts_the_contact_on_a_crest(z1, z2):
    g = gear(z1, z2)
    ps = pins.crest_cutoff(g)
    assert 0 < ps < np.pi
    assert pins.contact_angle_offset(ps, g) == pytest.approx(-np.pi / z1, abs=1e-12)
    # in the satellite frame (tooth_profile), the contact point of a pin at psi* lies on a crest
    # axis (2m+1) pi/z1; pin 0 at theta = -psi*: beta = k theta/z1
    theta = -ps
    G = pins.tooth_profile(g.k * theta / z1, 0, g)
    ang = np.arctan2(G[1], G[0])
    frac = np.mod(ang * z1 / np.pi, 2.0)
    assert frac == pytest.approx(1.0, abs=1e-9)


def test_crest_cutoff_is_pi_for_k1():
    assert pins.crest_cutoff(gear(21, 22)) == math.pi


def test_spin_reversal_phase():
    g = gear(K1=0.98, Rb=1.95)          # R_p (1 - K1) = 1.75 < R_b
    p0 = pins.spin_reversal_phase(g)
    assert p0 is not None
    assert pins.pitch_distance(p0, g) == pytest.approx(g.R_b, rel=1e-12)
    assert pins.spin_reversal_phase(gear()) is None


# ------------------------------------------------------------------ identities (pins.md §4.8)

GEARS = [gear(21, 22), gear(20, 22), gear(60, 62), gear(30, 33, K1=0.6), gear(11, 12, K1=0.9)]


@pytest.mark.parametrize("g", GEARS, ids=lambda g: f"z{g.z1}-{g.z2}")
def test_a_window_that_is_not_a_full_period_is_biased(g):
    # the mean over half a period differs from the cycle mean by far more than the error estimate
    ps = pins.crest_cutoff(g)
    full = pins.mean_loss_ratio(g, ps, pins.spin_reversal_phase(g), 0.1)
    bp = pins.cycle_breakpoints(g, ps, pins.spin_reversal_phase(g))
    half = integrate_adaptive(lambda t, m: pins.cycle_loss_ratio(t, m, g, ps, 0.1),
                              np.append(bp[bp < 0.5], 0.5), tol=1e-10, n_max=2 ** 20)
    assert abs(half.value[0] / 0.5 - full.loss_ratio) > 100 * full.loss_ratio_err


def ez_cross(r):
    """z x r for planar vectors (2, ...)."""
    return np.array([-r[1], r[0]])


def _contacts(g, theta, sigma):
    """Loaded contacts at theta in the fixed frame, from first principles."""
    ps = pins.crest_cutoff(g)
    i = np.arange(g.z2)
    psi_t = pins.pin_phase(i, theta, g.z2, sigma)
    loaded = (psi_t > 0) & (psi_t < ps)
    A = g.R_p * u(2 * np.pi * i / g.z2)[:, loaded]
    P = (g.r_p2 * u(theta))[:, None]
    O1 = g.e * u(theta)
    rho = np.hypot(*(A - P))
    C = A - g.R_b * (A - P) / rho
    n = (P - A) / rho                       # normal on the satellite, from the pin toward P
    return A, P, O1, C, n, rho, loaded


@pytest.mark.parametrize("g", GEARS, ids=lambda g: f"z{g.z1}-{g.z2}")
@pytest.mark.parametrize("sigma", [REDUCER, MULTIPLIER])
def test_identity6_7_velocity_and_power_balance(g, sigma):
    wH = 50.0
    wV = -wH * g.k / g.z1
    mu = 0.1
    T = 5000.0
    for theta in (0.011, 0.2, 1.3):
        _, _, O1, C, n, rho, loaded = _contacts(g, theta, sigma)
        v = wH * ez_cross(O1)[:, None] + wV * ez_cross(C - O1[:, None])
        # 6: no normal velocity; magnitude v_i = |omega_V| |rho - R_b|
        assert np.allclose(np.sum(v * n, axis=0), 0.0, atol=1e-9 * np.abs(v).max())
        assert np.allclose(np.hypot(*v), pins.sliding_speed(rho, g.R_b, wV), rtol=1e-10)
        # the normal forces balance the torque with the sign of the mode (pins.md §5.5)
        F = pins.pin_forces([theta], g, pins.crest_cutoff(g), T, sigma)[loaded, 0]
        Fn = F * n
        M = np.sum(cross(C - O1[:, None], Fn))
        assert M == pytest.approx(-sigma * T, rel=1e-11)
        # 7: add friction against sliding; satellite equilibrium gives B and T_W; power balance
        Ft = -mu * F * v / np.hypot(*v)
        Fc = Fn + Ft
        B = -Fc.sum(axis=1)
        TW = -np.sum(cross(C - O1[:, None], Fc))
        lhs = TW * wV + B @ (wH * ez_cross(O1))
        losses = np.sum(pins.contact_loss_power(F, np.hypot(*v), mu)) / 1e-3
        assert lhs == pytest.approx(losses, rel=1e-10)


@settings(max_examples=25, deadline=None)
@given(z1=st.integers(6, 80), k=st.integers(1, 3), K1=st.floats(0.3, 0.95), qb=st.floats(0.05, 0.6),
       mu=st.floats(0.001, 0.3))
def test_invariants_over_random_gears(z1, k, K1, qb, mu):
    z2 = z1 + k
    e = 2.0
    Rp = e * z2 / (k * K1)
    Rb = qb * Rp * math.sin(math.pi / z2)
    g = Cycloid.from_curtate_ratio(z1, z2, e, K1, Rb)
    ps = pins.crest_cutoff(g)
    if ps <= g.period or Rb >= pins.min_curvature_radius(g, ps):
        return                                 # inadmissible: the calculator refuses it (tested in CLI)
    theta = np.linspace(-1, 1, 41)
    # 8: lambda proportional to mu; 5: mirror
    l1 = pins.loss_ratio(theta, g, ps, mu, REDUCER)
    assert np.allclose(pins.loss_ratio(theta, g, ps, 2 * mu, REDUCER), 2 * l1, rtol=1e-13)
    assert np.allclose(pins.loss_ratio(-theta, g, ps, mu, MULTIPLIER), l1, rtol=1e-11)
    # 1: equilibrium
    F = pins.pin_forces(theta, g, ps, 1.0, REDUCER)
    psi = pins.pin_phase(np.arange(z2)[:, None], theta[None, :], z2)
    assert np.allclose(np.sum(F * np.abs(pins.lever_arm(psi, g)), axis=0), 1.0, rtol=1e-12)
    # efficiencies: eta_HV = 1/(2 - eta_VH) and the Willis forms (pins.md §4.7)
    lam = pins.mean_loss_ratio(g, ps, pins.spin_reversal_phase(g), mu, tol=1e-6).loss_ratio
    _, w_vh, w_hv = pins.willis_efficiencies(lam, z1, z2)
    assert w_vh == pytest.approx(pins.efficiency_multiplier(lam), rel=1e-12, abs=1e-14)
    diff = pins.efficiency_reducer(lam) - w_hv
    psi0 = lam * k / z2
    assert diff == pytest.approx(lam * psi0 / ((1 + lam) * (1 + (z1 / k) * psi0)), rel=1e-9, abs=1e-14)
    if lam < 1:
        assert pins.efficiency_reducer(lam) == pytest.approx(1 / (2 - pins.efficiency_multiplier(lam)), rel=1e-13)


def test_identity9_rolling_speed():
    g = gear(K1=0.98)                   # spin reverses inside the loaded arc
    psi = np.linspace(0.001, 2.0, 200)
    rho = pins.pitch_distance(psi, g)
    wV = -10.0
    spin = pins.pin_spin(rho, g.R_b, wV)
    v = pins.sliding_speed(rho, g.R_b, wV)
    assert np.allclose(np.abs(spin) * g.R_b, v, rtol=1e-13)
    assert np.all(spin[rho < g.R_b] * g.R_b < 0)
    assert np.allclose(spin[rho < g.R_b] * g.R_b, -v[rho < g.R_b], rtol=1e-13)


def test_rolling_condition_and_mu_rot():
    assert pins.rolling_condition(0.1, 1.95, 0.1, 0.95, 0.01)          # 0.195 >= 0.105
    assert not pins.rolling_condition(0.05, 1.95, 0.1, 0.95, 0.01)     # 0.0975 < 0.105
    assert pins.rotating_loss_coefficient(0.1, 0.95, 0.01, 1.95) == pytest.approx(0.105 / 1.95, rel=1e-15)


# ------------------------------------------------------------------ cycle integration (pins.md §6)

HONEST = [gear(21, 22), gear(20, 22), gear(60, 62), gear(30, 33, K1=0.6), gear(11, 12, K1=0.9),
          gear(20, 22, K1=0.98), gear(21, 22, K1=0.999, Rb=0.1), gear(20, 22, K1=1 - 1e-9, Rb=1e-4),
          gear(21, 22, K1=1 - 1e-9, Rb=1e-4), Cycloid.from_curtate_ratio(199, 200, 1.0, 0.8, 0.5),
          # K1 -> 1 with a spin reversal inside the layer's algebraic tail (grading over the whole period)
          Cycloid.from_curtate_ratio(199, 203, 6.38e-6, 1 - 1e-9, 5.0e-12),
          # psi* barely above one pin pitch: a single loaded pin, lambda ~ 1/psi (graded piece)
          Cycloid.from_curtate_ratio(4, 8, 1.2e-5, 1e-6, 9.2e-6)]


@pytest.mark.parametrize("g", HONEST, ids=lambda g: f"z{g.z1}-{g.z2}-K{g.K1:.9g}")
def test_error_estimate_is_honest_against_10x_finer(g):
    ps = pins.crest_cutoff(g)
    p0 = pins.spin_reversal_phase(g)
    assert g.R_b < pins.min_curvature_radius(g, ps)          # admissible
    r = pins.mean_loss_ratio(g, ps, p0, 0.1, tol=1e-6)
    assert r.converged
    assert r.loss_ratio_err <= 1e-6 * r.loss_ratio
    # every piece 10x finer (same breakpoints), then doubled twice: an independent, finer value
    fine = pins.mean_loss_ratio(g, ps, p0, 0.1, tol=1e-300, n_initial=10 * r.quad.n_piece,
                                n_max=40 * r.n_crank)
    assert fine.n_crank == 40 * r.n_crank
    assert abs(fine.loss_ratio - r.loss_ratio) <= r.loss_ratio_err
    assert np.isfinite(fine.loss_ratio)


def test_uniform_grid_ignoring_breakpoints_converges_badly_for_k2():
    # pins.md §6: for k >= 2 the jumps at psi* make a plain uniform grid first order
    g = gear(20, 22)
    ps = pins.crest_cutoff(g)
    exact = pins.mean_loss_ratio(g, ps, None, 0.1, tol=1e-12).loss_ratio

    def pointwise(t, mid):
        return pins.loss_ratio(t * g.period, g, ps, 0.1, MULTIPLIER)

    errs = [abs(integrate_adaptive(pointwise, [0.0, 1.0], tol=1e-300, n_start=n, n_max=2 * n,
                                   min_levels=1).trapezoid[0] - exact) for n in (256, 512, 1024, 2048)]
    assert errs[-1] > 1e-9           # nowhere near the piecewise rule's 1e-13
    assert errs[0] / errs[-1] < 40   # not second order (which would give 64)


def test_zero_friction_short_circuits():
    g = gear()
    r = pins.mean_loss_ratio(g, pins.crest_cutoff(g), None, 0.0)
    assert r.loss_ratio == 0.0 and r.loss_ratio_err == 0.0 and r.converged
    assert pins.efficiency_multiplier(r.loss_ratio) == 1.0
    assert pins.efficiency_reducer(r.loss_ratio) == 1.0


def test_tiny_eccentricity_self_locks_in_the_multiplier():
    g = Cycloid.from_pin_circle(20, 22, 1e-6, 57.2, 1.95)
    ps = pins.crest_cutoff(g)
    r = pins.mean_loss_ratio(g, ps, pins.spin_reversal_phase(g), 0.1)
    assert np.isfinite(r.loss_ratio) and r.loss_ratio > 1
    assert 0 < pins.efficiency_reducer(r.loss_ratio) < 1e-4


@pytest.mark.parametrize("z1,z2", [(49, 50), (48, 50), (21, 22)])
def test_pins_exactly_at_0_and_pi_keep_lambda_continuous(z1, z2):
    # at theta = 0 pins sit exactly at psi = 0 and (z2 even) pi; lambda is continuous through theta = 0
    g = gear(z1, z2, K1=0.7)
    ps = pins.crest_cutoff(g)
    for sigma in (REDUCER, MULTIPLIER):
        # theta = 0 is an entry (lever 0) and, for k = 1, an exit at pi (lever 0); the crest exit of
        # k >= 2 lies elsewhere (frac(psi* z2/2 pi) != 0 here)
        assert (ps * z2 / (2 * np.pi)) % 1 > 1e-6 or g.k == 1
        lam = pins.loss_ratio([-1e-12, 0.0, 1e-12], g, ps, 0.1, sigma)
        assert np.ptp(lam) < 1e-9


@pytest.mark.parametrize("K1,Rb,loops", [(0.99, 3.0, True), (0.99, 2.5, True), (0.99, 2.3, False),
                                         (0.75, 1.95, False), (0.95, 5.0, False)])
def test_undercut_criterion_matches_a_loop_in_the_profile(K1, Rb, loops):
    # independent check of pins.md §4.2: the tooth profile (an offset of c_b) forms a loop, seen as a
    # reversal of its tangent against the pin-centre curve's, exactly when R_b > min rho_c (convex part)
    g = gear(K1=K1, Rb=Rb)
    ps = pins.crest_cutoff(g)
    assert (Rb > pins.min_curvature_radius(g, ps)) == loops
    beta = -np.linspace(1e-6, ps, 20001) / (g.z1 / g.k)
    h = 1e-7
    dG = np.subtract(pins.tooth_profile(beta + h, 0, g), pins.tooth_profile(beta - h, 0, g))
    dc = np.subtract(pins.pin_centre_curve(beta + h, 0, g), pins.pin_centre_curve(beta - h, 0, g))
    assert bool(np.any(np.sum(dG * dc, axis=0) < 0)) == loops


# ------------------------------------------------------------------ speed work (issue 6): same answers, honest errors

# the four cycloidal paper designs (configs/pins_paper_cyc_*: the rotating ones share the geometry) and the
# hard cases of pins.md §9: k = 1, 2, 3, z2 = 200, K1 -> 1 (k = 1 and 2), a spin reversal inside the
# boundary layer, and a spin reversal in the loaded arc
HONESTY = [gear(20, 22), gear(60, 62), gear(21, 22), gear(20, 23), Cycloid.from_curtate_ratio(198, 200, 1.0, 0.75, 0.3),
           gear(20, 22, K1=0.99, Rb=0.5), gear(20, 22, K1=1 - 1e-9, Rb=1e-4), gear(21, 22, K1=1 - 1e-9, Rb=1e-4),
           Cycloid.from_curtate_ratio(199, 203, 6.38e-6, 1 - 1e-9, 5.0e-12),
           Cycloid.from_curtate_ratio(21, 22, 1.0, 0.999, 0.1)]


@pytest.mark.parametrize("g", HONESTY, ids=lambda g: f"z{g.z1}-{g.z2}-K{g.K1:.9g}")
def test_reported_error_bounds_the_actual_error_at_every_tolerance(g):
    # pins.md §6: E = |Q_2N - Q_N| must bound the actual error of the reported (Richardson) value.  The
    # reference is independent of the runs checked: every piece of the tol = 1e-9 grid made 2x finer,
    # then doubled twice (8x), with its own error estimate.
    ps, p0 = pins.crest_cutoff(g), pins.spin_reversal_phase(g)
    runs = {tol: pins.mean_loss_ratio(g, ps, p0, 1.0, tol=tol) for tol in (1e-3, 1e-6, 1e-9)}
    fine = runs[1e-9]
    ref = pins.mean_loss_ratio(g, ps, p0, 1.0, tol=1e-300, n_initial=2 * fine.quad.n_piece, n_max=8 * fine.n_crank)
    assert ref.n_crank == 8 * fine.n_crank and ref.loss_ratio_err < fine.loss_ratio_err
    for tol, r in runs.items():
        assert r.converged and r.loss_ratio_err <= tol * r.loss_ratio
        assert abs(r.loss_ratio - ref.loss_ratio) <= r.loss_ratio_err + ref.loss_ratio_err, tol


# Curtate ratios for which numpy's scalar (1 - K1) ** 2 (a pow() call) is not the correctly rounded square
# (1 - K1) * (1 - K1) (glibc, x86-64), while an array's ** 2 multiplies: a one-gear code path that squared a
# scalar gave other numbers than the same gear solved in a batch.
POW_SENSITIVE_K1 = (0.3648, 0.4898, 0.6824, 0.7449)


@pytest.mark.parametrize("z1,k,K1", [(20, 2, 0.75), (60, 2, 0.75), (20, 3, 0.5), (10, 2, 0.95), (100, 4, 0.3),
                                     (7, 2, 0.999), (30, 3, 0.05)])
def test_crest_cutoffs_against_the_bracketed_root_finder(z1, k, K1):
    # the nested scan + inverse quadratic interpolation of crest_cutoffs against gearcalc.roots.find_root
    # (Chandrupatla) on the same first sign change (pins.md §4.3, §12.11)
    from gearcalc.roots import find_root

    g = Cycloid.from_curtate_ratio(z1, z1 + k, 1.0, K1, 0.0)
    g = Cycloid.from_curtate_ratio(z1, z1 + k, 1.0, K1, 0.4 * g.R_p * math.sin(math.pi / g.z2))
    psi = np.linspace(0.0, math.pi, 4097)[1:]
    h = pins.contact_angle_offset(psi, g) + math.pi / g.z1
    i = int(np.argmax(h <= 0))
    ref = find_root(lambda x: pins.contact_angle_offset(x, g) + math.pi / g.z1, psi[i - 1], psi[i], xtol=1e-16).root
    assert abs(pins.crest_cutoff(g) - float(ref)) < 1e-13


@settings(max_examples=40, deadline=None)
@given(z1=st.integers(3, 150), k=st.integers(1, 4), K1=st.floats(0.02, 0.999), q=st.floats(0.05, 0.95))
def test_closed_form_least_curvature_radius_against_a_dense_scan(z1, k, K1, q):
    # min_curvature_radius (closed form at c* = 3p/q - A/K1, pins.md §4.2) against a dense scan of
    # curvature_radius over the convex part of [0, psi*]: never above it, and within the scan's resolution
    g = Cycloid.from_curtate_ratio(z1, z1 + k, 1.0, K1, 0.0)
    ps = pins.crest_cutoff(Cycloid.from_curtate_ratio(z1, z1 + k, 1.0, K1, q * g.R_p * math.sin(math.pi / g.z2)))
    psi = np.linspace(0.0, ps, 200001)
    rc = pins.curvature_radius(psi, g)
    rc = rc[rc > 0]
    got = pins.min_curvature_radius(g, ps)
    if rc.size == 0:
        assert got == math.inf
    else:
        assert got <= rc.min() * (1 + 1e-12)
        assert got >= rc.min() * (1 - 1e-6)


def test_pin_circle_both_ways_and_scalars_equal_arrays():
    """:func:`gearcalc.pins.pin_circle`: R_p from K1 = e z2/(k R_p) (paper u = 10 design: R_p = 3.9 x 22/(2 x 0.75)
    = 57.2 mm) and 1 - K1 from R_p without cancellation (the spec's K1 recovered to 1e-15); one gear on Python
    floats equals the same gear in an array, bit for bit, and equals :class:`gearcalc.pins.Cycloid`'s."""
    Rp, omk = pins.pin_circle(20, 22, 3.9, math.nan, 0.75, pins.SCALAR_OPS)
    assert Rp == pytest.approx(57.2, rel=1e-15) and omk == 0.25
    Rp2, omk2 = pins.pin_circle(20, 22, 3.9, 57.2, math.nan, pins.SCALAR_OPS)
    assert Rp2 == 57.2 and 1.0 - omk2 == pytest.approx(3.9 * 22 / (2 * 57.2), rel=1e-15)
    R_arr, o_arr = pins.pin_circle(np.array([20, 20]), np.array([22, 22]), np.array([3.9, 3.9]),
                                   np.array([np.nan, 57.2]), np.array([0.75, np.nan]))
    assert R_arr.tolist() == [Rp, Rp2] and o_arr.tolist() == [omk, omk2]
    g1, g2 = Cycloid.from_curtate_ratio(20, 22, 3.9, 0.75, 1.95), Cycloid.from_pin_circle(20, 22, 3.9, 57.2, 1.95)
    assert (g1.R_p, g1.one_minus_K1) == (Rp, omk) and (g2.R_p, g2.one_minus_K1) == (Rp2, omk2)


@pytest.mark.parametrize("multiplier", [False, True])
@pytest.mark.parametrize("on_V", [False, True])
def test_shaft_torques_balance_the_powers(multiplier, on_V):
    """:func:`gearcalc.pins.shaft_torques`: input power x efficiency = output power (pins.md §4.7), with
    omega_H = u |omega_V|; the given torque is returned unchanged on its shaft."""
    u, eta_vh, eta_hv, T = 10.0, 0.87, 0.86, 100.0
    T_V, T_H = pins.shaft_torques(T, u, eta_vh, eta_hv, multiplier, on_V, pins.SCALAR_OPS)
    w_V = 1.0
    w_H = u * w_V
    if multiplier:      # V drives H
        assert T_H * w_H == pytest.approx(eta_vh * T_V * w_V, rel=1e-15)
    else:
        assert T_V * w_V == pytest.approx(eta_hv * T_H * w_H, rel=1e-15)
    assert (T_V if on_V else T_H) == T
    # the reducer efficiency's error: |d eta_HV/d lambda| E (central difference)
    lam, E, h = 0.15, 2e-7, 1e-6
    d = (pins.efficiency_reducer(lam + h) - pins.efficiency_reducer(lam - h)) / (2 * h)
    assert pins.efficiency_reducer_err(lam, E) == pytest.approx(abs(d) * E, rel=1e-8)


