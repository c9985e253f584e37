"""Tests of gearcalc.rows.sharing: the level choice of row_sharing and the helpers compute and the sweep share
(rows.md §2, §3, §13.2-13.4).  The level functions themselves are tested in tests/test_rows.py."""
import numpy as np
import pytest

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
