"""Tests of gearcalc.rows.sharing: the level choice of row_sharing and the helpers compute and the sweep share
(rows.md §2, §3, §13.2-13.4), and the level functions against the paper's claims (rows.md §11), exact identities,
an independent dense transfer-matrix solve written here, scipy quadrature and closed-form limits.

Sources of expected values are named in each test: the seed paper 004_971077b94d8d4426.txt ("paper"), exact
identities, closed forms, or an independent computation.
"""
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from gearcalc import rows as R

from gearcalc.rows import sharing as S


@pytest.mark.parametrize("level", S.LEVELS)
@pytest.mark.parametrize("n", [1, 2, 3, 7])
def test_row_sharing_takes_K_from_the_level_named(level, n):
    kappa = np.array([1e-30, 0.01, 0.5, 3.0, 7.9, 8.0, 50.0])
    sh = S.row_sharing(kappa, 0.25, n, level)
    u_s, ok = S.stepwise_shares(kappa, 0.25, n)
    u_e, peak = S.exact_shares(kappa, 0.25, n)
    if n == 1:   # rows.md §13.2: K = 1 at every level and under every --model
        assert np.all(sh.K == 1.0) and np.all(sh.K_stepwise == 1) and np.all(sh.K_continuous == 1)
        assert not sh.unloaded.any()
        return
    K_c = S.continuous_k(kappa, 0.25, n)
    fallback = (level == "exact") | ((level == "stepwise") & ~ok)   # rows.md §13.3: kappa >= 8 -> exact
    want = K_c if level == "continuous" else np.where(fallback, u_e.max(-1), u_s.max(-1))
    assert np.array_equal(sh.K, want) and np.array_equal(sh.peak_factor, peak)
    assert sh.level.tolist() == [level if level != "stepwise" or v else "exact" for v in ok]
    # rows.md §2.2: with a rigid carrier row 1 carries K (the exact shares' argmax is noise at kappa = 1e-30)
    assert np.all(sh.K_row == 1)
    # rows.md §13.4: unloaded rows are those of the level supplying K at <= 1e-12 w̄
    used = u_e if level != "stepwise" else np.where(ok[:, None], u_s, u_e)
    assert np.array_equal(sh.unloaded, used <= S.UNLOADED_SHARE)


def test_row_sharing_batch_equals_one_design_bit_for_bit():
    kappa = np.geomspace(1e-6, 40.0, 50)
    batch = S.row_sharing(kappa, 0.3, 5, "stepwise")
    for k, kap in enumerate(kappa):
        one = S.row_sharing(float(kap), 0.3, 5, "stepwise")
        assert float(one.K) == batch.K[k] and float(one.K_continuous) == batch.K_continuous[k]
        assert np.array_equal(one.u, batch.u[k]) and str(one.level) == batch.level[k]


def test_unknown_level_lists_the_levels():
    with pytest.raises(ValueError, match="stepwise, exact, continuous"):
        S.row_sharing(0.5, 0.25, 3, "exakt")


def test_mean_line_load_and_twist_identity():
    # rows.md §2.2: sum w_N = T_a/(r_ba b_w n_w) and phi_{N-1} = 2 (w_1 - w_N)/(C r_ba)
    u, _ = S.stepwise_shares(0.7, 0.25, 4)
    w_mean = S.mean_line_load(2e6, 4, 40.0, 50.0, 3)
    assert (u * w_mean).sum() == pytest.approx(2e6 / (40.0 * 50.0 * 3), rel=1e-14)
    phi = S.twist_from_shares(u, w_mean, 1.5e4, 40.0)
    assert phi[0] == 0.0 and phi[3] == pytest.approx(2 * (u[0] - u[3]) * w_mean / (1.5e4 * 40.0), rel=1e-14)


@pytest.mark.parametrize("kappa,bbar,n", [(0.3, 0.25, 3), (2.0, 0.0, 5), (4.0, 0.5, 1)])
def test_continuous_profile_starts_at_K_and_averages_to_one(kappa, bbar, n):
    # rows.md §3c: u(0) = X coth X = K_continuous; the profile carries the mean load, its mean over the face is 1
    xi = np.linspace(0.0, 1.0, 20001)
    prof = S.continuous_profile(xi, kappa, bbar, n)
    assert prof[0] == pytest.approx(float(S.continuous_k(kappa, bbar, n)), rel=1e-14)
    assert np.trapezoid(prof, xi) == pytest.approx(1.0, rel=1e-7)
    assert np.all(S.continuous_profile(xi, 1e-14, bbar, n) == 1.0)


@pytest.mark.parametrize("level", S.LEVELS)
def test_mixed_rows_batch_equals_each_design_alone(level):
    # rows.md §9: grouping by n is a batching device only; every design gets what row_sharing gives it alone
    rng = np.random.default_rng(9)
    rows = rng.integers(1, 9, 120)
    kappa, bbar = 10 ** rng.uniform(-4, 1.5, 120), rng.uniform(0, 1, 120)
    b = S.row_sharing_mixed(kappa, bbar, rows, level)
    for k in range(120):
        one = S.row_sharing(kappa[k], bbar[k], int(rows[k]), level)
        assert (b.K[k], b.K_exact[k], b.K_continuous[k], b.peak_factor[k], b.K_row[k], b.level[k]) == \
            (one.K, one.K_exact, one.K_continuous, one.peak_factor, one.K_row, one.level)
        assert b.unloaded[k] == (np.flatnonzero(one.unloaded) + 1).tolist()


D_A, M_MOD = 90.0, 5.0  # z_a = 18, m = 5 (the examples); K does not depend on them
E, NU = 2e5, 0.3
G = E / (2 * (1 + NU))
ALPHA = math.radians(20.0)
R_BA = 0.5 * D_A * math.cos(ALPHA)

def kappa_of(n, n_w, B, bbar=0.25, d_i=D_A, bore=0.0, c_e=0.075):
    b_w = R.rim_width(B, n, bbar, D_A)
    return float(R.torsion_parameter(c_e * E, R_BA, n_w, b_w, G, R.polar_moment(d_i, bore)))


def k_step(n, n_w, B, bbar=0.25, **kw):
    u, ok = R.stepwise_shares(kappa_of(n, n_w, B, bbar, **kw), bbar, n)
    assert ok
    return float(u.max())


# ------------------------------------------------------------------ the paper's claims (rows.md §11)
def test_smoke_value_K_1489():
    # paper: K = 1.489 for n = 3, n_w = 3, B = 2.4, b̄ = 0.25, pitch diameter (the one stated value)
    assert round(k_step(3, 3, 2.4), 3) == 1.489


def test_kappa_default_constant():
    # rows.md §2.3: with the defaults κ = 0.2192 n_w (b_w/d_a)² (d_a/d_I)⁴ (4 significant digits)
    k = kappa_of(3, 3, 2.4)
    bw_da = 2.4 / (3 + 0.25 * 2)
    assert k == pytest.approx(0.2192 * 3 * bw_da**2, rel=2e-4)


FIG3 = [(4, 5), (3, 5), (4, 3), (3, 3)]  # paper's curves 1..4


@pytest.mark.parametrize("B", np.round(np.arange(2.0, 2.81, 0.1), 2))
def test_fig3_curve_order(B):
    # paper, Fig. 3: curve 1 > 2 > 3 > 4 at every B in [2.0, 2.8]
    ks = [k_step(n, nw, B) for n, nw in FIG3]
    assert ks[0] > ks[1] > ks[2] > ks[3]


@pytest.mark.parametrize("n,n_w", FIG3)
def test_fig3_curves_increase_with_B(n, n_w):
    ks = [k_step(n, n_w, B) for B in np.linspace(2.0, 2.8, 17)]
    assert np.all(np.diff(ks) > 0)


def test_conclusion_1_borderline():
    # paper's conclusion 1 "K > 1.5 for n >= 3 and B >= 2.4": holds for n_w = 5 and for n = 4;
    # n = 3, n_w = 3 at B = 2.4 is just below 1.5 (rows.md §11.3)
    for B in (2.4, 2.6, 2.8):
        assert k_step(3, 5, B) > 1.5 and k_step(4, 5, B) > 1.5 and k_step(4, 3, B) > 1.5
    assert abs(k_step(3, 3, 2.4) - 1.5) < 0.02


@pytest.mark.parametrize("B", [2.0, 2.4, 2.8])
def test_K_grows_with_n_and_n_w(B):
    ks = [k_step(n, 3, B) if n > 1 else 1.0 for n in range(1, 13)]
    assert np.all(np.diff(ks) > 0)
    assert k_step(3, 4, B) > k_step(3, 3, B)


def test_K_grows_with_kappa():
    ks = [R.stepwise_shares(k, 0.25, 4)[0].max() for k in np.linspace(0.01, 7.9, 40)]
    assert np.all(np.diff(ks) > 0)


def test_one_row_is_uniform_at_every_level():
    # rows.md §2.3: for n = 1 there is no equation and K = 1 exactly
    for kappa in (1e-30, 0.3, 50.0, 1e6):
        u, ok = R.stepwise_shares(kappa, 0.25, 1)
        ue, peak = R.exact_shares(kappa, 0.25, 1)
        assert ok and u[0] == 1.0 and ue[0] == 1.0
        mu = math.sqrt(kappa)
        expected = 1.0 if mu < 1e-12 else mu / math.tanh(mu)  # μ coth μ
        assert peak == pytest.approx(expected, rel=1e-12)


# ------------------------------------------------------------------ exact identities
def torque_diagram(x, loads, T_a, b_w, b, n_w):
    """T(x) of the stepwise model: T_a at x = 0, falling at w_j r_ba n_w inside row j."""
    T = T_a
    for j, w in enumerate(loads):
        start = j * (b_w + b)
        T -= w * R_BA * n_w * np.clip(x - start, 0.0, b_w)
    return T


@pytest.mark.parametrize("seed", range(6))
def test_twist_formula_equals_quadrature(seed):
    from scipy.integrate import quad

    rng = np.random.default_rng(seed)
    n = int(rng.integers(2, 11))
    n_w, b_w, b = 3, 40.0 * rng.uniform(0.5, 1.5), 10.0 * rng.uniform(0, 1.5)
    loads = rng.uniform(5, 60, n)
    T_a = R_BA * b_w * n_w * loads.sum()  # equilibrium: T(b_a) = 0
    I_p = R.polar_moment(D_A)
    p, q = sorted(rng.choice(np.arange(1, n + 1), 2, replace=False))
    mid = lambda j: (j - 1) * (b_w + b) + 0.5 * b_w  # noqa: E731
    brk = [k * (b_w + b) + o for k in range(n) for o in (0.0, b_w)]
    val, _ = quad(lambda x: torque_diagram(x, loads, T_a, b_w, b, n_w), mid(p), mid(q), points=brk,
                  limit=500, epsabs=0, epsrel=1e-13)
    phi = R.twist_between(loads, p, q, T_a, R_BA, b_w, b, n_w, G, I_p)
    assert phi == pytest.approx(val / (G * I_p), rel=1e-9)


def test_paper_twist_formulas_equal_general():
    # paper's N = 2, 3, 4 formulas (rows.md §2.1) against the general one
    rng = np.random.default_rng(7)
    w = rng.uniform(5, 50, 4)
    T_a, b_w, b, n_w = 5e5, 40.0, 10.0, 3
    k = R_BA * b_w * n_w
    GI = G * R.polar_moment(D_A)
    paper = [
        (T_a - w[0] * k) * (b_w + b) + 0.125 * n_w * b_w**2 * R_BA * (w[0] - w[1]),
        (2 * (T_a - w[0] * k) - w[1] * k) * (b_w + b) + 0.125 * n_w * b_w**2 * R_BA * (w[0] - w[2]),
        (3 * (T_a - w[0] * k) - 2 * w[1] * k - w[2] * k) * (b_w + b) + 0.125 * n_w * b_w**2 * R_BA * (w[0] - w[3]),
    ]
    for N in (2, 3, 4):
        assert R.twist_between(w, 1, N, T_a, R_BA, b_w, b, n_w, G, R.polar_moment(D_A)) == pytest.approx(
            paper[N - 2] / GI, rel=1e-12)


@pytest.mark.parametrize("n", range(2, 9))
@pytest.mark.parametrize("kappa", [0.01, 0.5, 3.0, 7.5])
def test_recurrence_equals_dense_forms(n, kappa):
    u, ok = R.stepwise_shares(kappa, 0.25, n)
    assert ok
    assert np.allclose(u, R.stepwise_dense(kappa, 0.25, n, "paper"), rtol=1e-12)
    assert np.allclose(u, R.stepwise_dense(kappa, 0.25, n, "difference"), rtol=1e-12)


def test_stepwise_solution_satisfies_system_1_dimensional():
    # rows.md §2.2: w1 - wN = 0.5 C r_ba φ_{N-1}, Σw = T_a/(r_ba b_w n_w), φ from the twist formula
    n, n_w, B = 4, 3, 2.6
    b_w = R.rim_width(B, n, 0.25, D_A)
    T_a = 1.0e6
    w_bar = T_a / (n * R_BA * b_w * n_w)
    u, _ = R.stepwise_shares(kappa_of(n, n_w, B), 0.25, n)
    w = u * w_bar
    assert w.sum() == pytest.approx(T_a / (R_BA * b_w * n_w), rel=1e-13)
    for N in range(2, n + 1):
        phi = R.twist_between(w, 1, N, T_a, R_BA, b_w, 0.25 * b_w, n_w, G, R.polar_moment(D_A))
        assert w[0] - w[N - 1] == pytest.approx(0.5 * 0.075 * E * R_BA * phi, rel=1e-10)


def transfer_matrix_exact(kappa, bbar, n):
    """Independent exact solution for small μ: dense solve of the piecewise cosh/sinh solution.

    Units: b_w = 1, λ = μ, G I_p = 1, T_a = 1.  Row j: θ = A cosh(μx) + B sinh(μx), x ∈ [0, 1];
    gap: θ = P + R x, x ∈ [0, b̄].  Continuity of θ and T = -θ' at every interface.
    """
    mu = math.sqrt(kappa)
    nunk = 2 * n + 2 * (n - 1)
    A = np.zeros((nunk, nunk))
    rhs = np.zeros(nunk)
    r = 0
    row = lambda j: 4 * j  # noqa: E731  (A_j, B_j) at 4j, 4j+1; gap j (after row j) at 4j+2, 4j+3
    # T(0) = 1: -θ'(0) = -μ B_0 = 1
    A[r, row(0) + 1] = -mu
    rhs[r] = 1.0
    r += 1
    ch, sh = math.cosh(mu), math.sinh(mu)
    for j in range(n - 1):
        a, g = row(j), row(j) + 2
        # θ continuity row j end -> gap start: A ch + B sh = P
        A[r, a], A[r, a + 1], A[r, g] = ch, sh, -1.0
        r += 1
        # T continuity: μ(A sh + B ch) = R
        A[r, a], A[r, a + 1], A[r, g + 1] = mu * sh, mu * ch, -1.0
        r += 1
        nxt = row(j + 1)
        # gap end -> next row start: P + R b̄ = A'
        A[r, g], A[r, g + 1], A[r, nxt] = 1.0, bbar, -1.0
        r += 1
        # R = μ B'
        A[r, g + 1], A[r, nxt + 1] = 1.0, -mu
        r += 1
    a = row(n - 1)
    A[r, a], A[r, a + 1] = mu * sh, mu * ch  # T(end) = 0
    x = np.linalg.solve(A, rhs)
    means = np.array([(x[row(j)] * sh + x[row(j) + 1] * (ch - 1)) / mu for j in range(n)])
    return means / means.mean(), x[0] / means.mean()


@pytest.mark.parametrize("n", [1, 2, 3, 5])
@pytest.mark.parametrize("kappa", [0.05, 0.8, 4.0])
@pytest.mark.parametrize("bbar", [0.0, 0.25, 1.0])
def test_exact_level_equals_independent_dense_solve(n, kappa, bbar):
    u, peak = R.exact_shares(kappa, bbar, n)
    u_ref, peak_ref = transfer_matrix_exact(kappa, bbar, n)
    assert np.allclose(u, u_ref, rtol=1e-9)
    assert peak == pytest.approx(peak_ref, rel=1e-9)


@pytest.mark.parametrize("n", [2, 3, 7, 40])
@pytest.mark.parametrize("kappa", [1e-6, 0.3, 5.0, 400.0])
def test_exact_no_gap_identities(n, kappa):
    # rows.md §11: with b = 0, K_exact = n[1 - sinh((n-1)μ)/sinh(nμ)] and peak_factor = nμ coth(nμ) = K_continuous
    u, peak = R.exact_shares(kappa, 0.0, n)
    assert u.max() == pytest.approx(float(R.exact_k_no_gap(kappa, n)), rel=1e-9)
    mu = math.sqrt(kappa)
    assert peak == pytest.approx(n * mu / math.tanh(n * mu), rel=1e-9)
    assert peak == pytest.approx(float(R.continuous_k(kappa, 0.0, n)), rel=1e-12)


def test_exact_close_to_stepwise_on_fig3_points():
    # rows.md §11: stepwise against exact within 1 % on the 36 Fig. 3 points, stepwise slightly higher
    for n, nw in FIG3:
        for B in np.round(np.arange(2.0, 2.81, 0.1), 2):
            k = kappa_of(n, nw, B)
            ks = R.stepwise_shares(k, 0.25, n)[0].max()
            ke = R.exact_shares(k, 0.25, n)[0].max()
            assert 0 < ks / ke - 1 < 0.01


@pytest.mark.parametrize("bbar,B", [(0.25, 2.4), (0.25, 3.0), (0.0, 2.4), (0.0, 3.0)])
def test_refining_rows_converges_to_continuous_like_1_over_n(bbar, B):
    # rows.md §3, §13.11: error ratio on doubling n in [1.8, 2.2] for n >= 64, B <= 3
    errs_s, errs_e = [], []
    for n in (16, 32, 64, 128, 256):
        k = kappa_of(n, 3, B, bbar)
        kc = float(R.continuous_k(k, bbar, n))
        errs_s.append(abs(R.stepwise_shares(k, bbar, n)[0].max() - kc))
        errs_e.append(abs(R.exact_shares(k, bbar, n)[0].max() - kc))
    for errs in (errs_s, errs_e):
        assert errs[-1] < errs[0] / 10
        for a, b in zip(errs[2:], errs[3:]):
            assert 1.8 <= a / b <= 2.2


def test_continuous_small_x_series():
    # rows.md §3c: x coth x = 1 + x²/3 below 1e-4, continuous with the direct form
    x = np.array([1e-12, 9.99e-5, 1.001e-4, 1.0])
    assert np.allclose(R.x_coth_x(x), [1.0, 1 + (9.99e-5) ** 2 / 3, 1.001e-4 / np.tanh(1.001e-4), 1 / np.tanh(1.0)],
                       rtol=1e-15)


# ------------------------------------------------------------------ invariance
def test_K_independent_of_torque_E_and_module():
    # rows.md §2.3: T_a, E and the module cancel (pitch d_I)
    ref = None
    for module in (1.0, 5.0, 20.0):
        for e in (7e4, 2e5, 2.1e5):
            d_a = 18 * module
            b_w = R.rim_width(2.4, 3, 0.25, d_a)
            r_ba = 0.5 * d_a * math.cos(ALPHA)
            k = float(R.torsion_parameter(0.075 * e, r_ba, 3, b_w, e / 2.6, R.polar_moment(d_a)))
            K = R.stepwise_shares(k, 0.25, 3)[0].max()
            ref = K if ref is None else ref
            assert K == pytest.approx(ref, rel=1e-12)


# ------------------------------------------------------------------ hard cases (rows.md §4, §10)
def test_many_rows_no_overflow():
    for n in (200, 1000):
        for kappa in (1e-4, 0.5, 7.99):
            u, ok = R.stepwise_shares(kappa, 0.25, n)
            ue, peak = R.exact_shares(kappa, 0.25, n)
            assert ok and np.all(np.isfinite(u)) and np.all(np.isfinite(ue)) and np.isfinite(peak)
            assert u.sum() == pytest.approx(n, rel=1e-12) and ue.sum() == pytest.approx(n, rel=1e-12)
            assert np.all(u >= 0) and np.all(np.diff(u) <= 0)


def test_far_rows_keep_relative_precision():
    # rows.md §2.5: every row to full relative precision, far rows many orders below the mean
    n, kappa = 30, 7.0
    u = R.stepwise_shares(kappa, 0.25, n)[0]
    assert u[-1] < 1e-20
    with np.errstate(all="ignore"):
        ref = R.stepwise_dense(kappa, 0.25, 6, "difference")
    u6 = R.stepwise_shares(kappa, 0.25, 6)[0]
    assert np.allclose(u6, ref, rtol=1e-11)
    # the recurrence ratios are exact: (1 - κ/8)(u_N - u_{N+1}) = κ(1+b̄) Σ_{k>N} u_k, relative per row
    lhs = (1 - kappa / 8) * (u[:-1] - u[1:])
    rhs = kappa * 1.25 * np.cumsum(u[::-1])[::-1][1:]
    assert np.allclose(lhs, rhs, rtol=1e-12, atol=0)


def test_small_B_tends_to_uniform():
    for B in (1e-3, 1e-6, 1e-9):
        k = kappa_of(3, 3, B)
        assert R.stepwise_shares(k, 0.25, 3)[0].max() == pytest.approx(1.0, abs=1e-5)
        assert R.exact_shares(k, 0.25, 3)[0].max() == pytest.approx(1.0, abs=1e-5)
        assert float(R.continuous_k(k, 0.25, 3)) == pytest.approx(1.0, abs=1e-5)
    assert R.exact_shares(1e-30, 0.25, 3)[1] == 1.0


def test_huge_B_exact_tends_to_n_and_stepwise_invalid():
    for B in (30.0, 300.0, 3000.0):
        k = kappa_of(4, 3, B)
        assert k >= 8
        u, ok = R.stepwise_shares(k, 0.25, 4)
        assert not ok and np.all(np.isfinite(u))
        ue, peak = R.exact_shares(k, 0.25, 4)
        assert np.all(np.isfinite(ue)) and np.isfinite(peak)
    assert R.exact_shares(kappa_of(4, 3, 3000.0), 0.25, 4)[0].max() == pytest.approx(4.0, rel=1e-9)


def test_batch_shapes():
    kappas = np.array([[0.1, 0.5], [2.0, 9.0]])
    u, ok = R.stepwise_shares(kappas, 0.25, 5)
    assert u.shape == (2, 2, 5) and ok.tolist() == [[True, True], [True, False]]
    ue, peak = R.exact_shares(kappas, 0.25, 5)
    for idx in np.ndindex(2, 2):
        ue1, pk1 = R.exact_shares(kappas[idx], 0.25, 5)
        assert np.allclose(ue[idx], ue1, rtol=1e-14) and peak[idx] == pytest.approx(float(pk1), rel=1e-14)


# ------------------------------------------------------------------ properties
@settings(max_examples=60, deadline=None)
@given(n=st.integers(1, 40), kappa=st.floats(1e-8, 7.9), bbar=st.floats(0.0, 2.0))
def test_rigid_carrier_loads_positive_monotone_bounded(n, kappa, bbar):
    for u in (R.stepwise_shares(kappa, bbar, n)[0], R.exact_shares(kappa, bbar, n)[0]):
        assert np.all(u > 0) and np.all(np.diff(u) <= 1e-12)
        assert 1 - 1e-12 <= u.max() <= n + 1e-12
        assert 100 * u.sum() / n == pytest.approx(100.0, rel=1e-12)


@settings(max_examples=40, deadline=None)
@given(n=st.integers(2, 30), kappa=st.floats(8.0, 1e8), bbar=st.floats(0.0, 2.0))
def test_soft_sun_exact_level_finite(n, kappa, bbar):
    u, peak = R.exact_shares(kappa, bbar, n)
    assert np.all(np.isfinite(u)) and np.isfinite(peak) and np.all(u >= 0)
    assert u.sum() == pytest.approx(n, rel=1e-12)


# ---------------------------------------------------------------- the batch active set equals the scalar one
def test_active_set_batch_equals_the_scalar_active_set():
    # compliant carriers that over-compensate (negative loads, rows dropped and re-activated), in one batch
    rng = np.random.default_rng(7)
    n, P = 5, 40
    kappa = rng.uniform(0.05, 3.0, P)
    Y = rng.uniform(-2.0, 2.0, (P, n, n))
    u, unloaded, converged = R.stepwise_active_set_batch(kappa, np.full(P, 0.25), n, Y)
    dropped = 0
    for k in range(P):
        u1, off, ok, _ = R.stepwise_active_set(float(kappa[k]), 0.25, n, carrier=Y[k])
        assert ok == converged[k] and off == (np.flatnonzero(unloaded[k]) + 1).tolist()
        assert np.array_equal(u[k], u1)  # the same solves of the same sizes: bit for bit
        dropped += bool(off)
    assert dropped > 0 and not converged.all()


@pytest.mark.parametrize("n", range(1, 13))
def test_row_reductions_are_numpys_bit_for_bit(n):
    """The column-by-column reductions over the rows (gearcalc/rows/sharing.py ``_row_max``, ``_row_argmax``,
    ``_row_mean``, ``_row_any``; numpy reduces a short last axis point by point, 5x slower) give numpy's
    ``max``, ``argmax``, ``mean`` and ``any`` over ``axis=-1`` bit for bit, NaN and ties included."""
    import numpy as np

    from gearcalc.rows.sharing import _row_any, _row_argmax, _row_max, _row_mean

    rng = np.random.default_rng(n)
    x = rng.random((2, 500, n)) * 10.0 ** rng.integers(-8, 8, (2, 500, n))
    x[rng.random(x.shape) < 0.02] = np.nan
    x[rng.random(x.shape) < 0.05] = 0.5  # ties
    assert np.array_equal(_row_max(x), x.max(axis=-1), equal_nan=True)
    assert np.array_equal(_row_argmax(x), np.argmax(x, axis=-1))
    assert _row_mean(x).tobytes() == x.mean(axis=-1).tobytes()
    assert np.array_equal(_row_any(x > 1), np.any(x > 1, axis=-1))
