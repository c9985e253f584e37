"""gearcalc.zstk.solve: designs prepared column-wise, stacked by N, put back in order (zstk.md §8).

Expected values: identities (a shared value and a list of equal values prepare the same arrays; the stacked
results return in the caller's order) and the worked example of Merko et al. (N = 8 for scheme A, zstk.md §6).
"""
import numpy as np

from gearcalc.zstk import solve

EXAMPLE = dict(outer=100.0, inner=50.0, eccentricity=6.0, gap=6.0, length=20.0, rollers="auto", correct="outer",
               scheme="A", separator=True, load=1e4, direction=0.0, clearance=0.0, roller_e=2.1e5, roller_nu=0.3,
               ring_e=2.1e5, ring_nu=0.3, inner_e=None, inner_nu=None, outer_e=None, outer_nu=None, allowable=None)


def designs(**changes):
    return solve.Designs(**{**EXAMPLE, **changes})


def test_shared_values_and_lists_prepare_alike():
    one = solve.prepare(designs(), 3, 2000, 4000.0)
    many = solve.prepare(solve.Designs(*([v] * 3 for v in designs())), 3, 2000, 4000.0)
    for name in ("valid", "n", "phase", "gamma", "load", "clearance", "allowable", "allowable_default", "scheme"):
        assert np.array_equal(getattr(one, name), getattr(many, name)), name
    assert one.n.tolist() == [8, 8, 8]                                  # N = 8 (zstk.md §6, scheme A)
    assert one.mats.e_star_inner.tolist() == many.mats.e_star_inner.tolist()


def test_words_and_overrides():
    p = solve.prepare(designs(scheme=["A", "cycle", 30.0], direction=[0.0, "envelope", 390.0],
                              allowable=[None, 900.0, None], inner_e=[None, 1e5, None], separator=[True, True, False]),
                      3, 2000, 4000.0)
    assert p.cycle.tolist() == [False, True, False] and p.envelope.tolist() == [False, True, False]
    assert p.scheme.tolist() == ["A", "cycle", "angle"] and p.letter.tolist() == [True, False, False]
    assert p.gamma[2] == np.radians(30.0)                           # 390 deg reduced exactly to 30 deg
    assert p.allowable.tolist() == [4000.0, 900.0, 4000.0] and p.allowable_default.tolist() == [True, False, True]
    assert p.mats.e_star_inner[1] < p.mats.e_star_inner[0]           # softer inner ring
    assert p.valid.tolist() == [True, True, False] and p.validity.valid[2]   # refused for the separator alone


def test_stacks_by_roller_count_return_in_order():
    p = solve.prepare(designs(rollers=[10, 8, 10, 8, 6]), 5, 2000, 4000.0)
    idx = np.array([0, 1, 2, 4])
    groups = solve.solve_stack(p, idx)
    assert [s.state.radius.shape for _, s in groups] == [(1, 6), (1, 8), (2, 10)]   # increasing N
    back = solve.stack_order(idx, [sub for sub, _ in groups])
    assert solve.gather([sub.tolist() for sub, _ in groups], back) == idx.tolist()


def test_gather_identity_on_a_random_partition():
    rng = np.random.default_rng(0)
    idx = np.sort(rng.choice(50, 20, replace=False))
    perm = rng.permutation(idx)
    groups = [perm[:7], perm[7:8], perm[8:]]
    assert solve.gather([g.tolist() for g in groups], solve.stack_order(idx, groups)) == idx.tolist()
