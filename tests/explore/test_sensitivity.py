"""sensitivity: the estimators against SALib on the same samples and against the Ishigami function's closed form;
the command on a rows design whose K does not depend on the torque (rows.md: K is a ratio of loads)."""
import math

import numpy as np
import pytest
from conftest import CONFIGS, cli

import gearcalc
from gearcalc.explore.sensitivity import morris_effects, morris_unit, saltelli_unit, sobol_indices

ROWS = CONFIGS / "rows_fig3_c4_n3_nw3_B2.8.toml"
PROBLEM = {"num_vars": 3, "names": ["x1", "x2", "x3"], "bounds": [[0.0, 1.0]] * 3}


def ishigami(u, a=7.0, b=0.1):
    x = -math.pi + 2 * math.pi * np.asarray(u)
    return np.sin(x[..., 0]) + a * np.sin(x[..., 1]) ** 2 + b * x[..., 2] ** 4 * np.sin(x[..., 0])


def ishigami_indices(a=7.0, b=0.1):
    """Closed form (Ishigami & Homma 1990; Sobol' & Levitan 1999): the variances of the terms."""
    V1 = 0.5 * (1 + b * math.pi ** 4 / 5) ** 2
    V2 = a ** 2 / 8
    V13 = b ** 2 * math.pi ** 8 * (1 / 18 - 1 / 50)
    V = V1 + V2 + V13
    return [V1 / V, V2 / V, 0.0], [(V1 + V13) / V, V2 / V, V13 / V]


def _salib_layout(yA, yB, yAB):
    n, d = yA.size, yAB.shape[0]
    Y = np.empty((n, d + 2))
    Y[:, 0], Y[:, -1], Y[:, 1:-1] = yA, yB, yAB.T
    return Y.ravel()  # SALib's order: A_j, AB_1j .. AB_dj, B_j for every row j


@pytest.mark.slow
def test_sobol_estimators_equal_salib_on_the_same_samples():
    salib = pytest.importorskip("SALib.analyze.sobol")
    A, B, AB = saltelli_unit(1024, 3, seed=4)
    yA, yB, yAB = ishigami(A), ishigami(B), ishigami(AB)
    ours = sobol_indices(yA, yB, yAB)
    ref = salib.analyze(PROBLEM, _salib_layout(yA, yB, yAB), calc_second_order=False, seed=1)
    np.testing.assert_allclose(ours["S1"], ref["S1"], rtol=1e-12, atol=1e-14)
    np.testing.assert_allclose(ours["ST"], ref["ST"], rtol=1e-12, atol=1e-14)
    # the intervals come from other bootstrap resamples: the same spread, not the same numbers
    for k in ("S1_conf", "ST_conf"):
        assert np.all(ours[k] > 0.5 * ref[k]) and np.all(ours[k] < 2 * ref[k])


@pytest.mark.slow
def test_sobol_indices_of_ishigami_within_their_intervals():
    S1, ST = ishigami_indices()
    A, B, AB = saltelli_unit(8192, 3, seed=0)
    s = sobol_indices(ishigami(A), ishigami(B), ishigami(AB))
    assert np.all(np.abs(s["S1"] - S1) <= s["S1_conf"])
    assert np.all(np.abs(s["ST"] - ST) <= s["ST_conf"])


def test_morris_equals_salib_on_the_same_trajectories():
    salib = pytest.importorskip("SALib.analyze.morris")
    X = morris_unit(40, 3, seed=2)
    y = ishigami(X)
    ours = morris_effects(X, y)
    ref = salib.analyze(PROBLEM, X, y, num_levels=4, seed=1)
    for k in ("mu", "mu_star", "sigma"):
        np.testing.assert_allclose(ours[k], np.asarray(ref[k], dtype=float), rtol=1e-12, atol=1e-12)


def test_morris_trajectories_move_each_key_once_by_delta():
    X = morris_unit(10, 4, seed=0).reshape(10, 5, 4)
    steps = np.diff(X, axis=1)
    assert np.all(np.count_nonzero(steps, axis=2) == 1)  # one key a move
    assert np.allclose(np.abs(steps).sum(axis=2), 4 / 6)  # delta = p / (2 (p - 1)), p = 4
    assert np.all(np.count_nonzero(steps, axis=1) == 1)  # every key once
    assert X.min() >= 0 and X.max() <= 1


def test_outputs_that_do_not_vary_are_left_out_and_said_once():
    """An output constant over the sample (the design's cheek ratio, echoed; the row count, not varied) would
    report every index 0: it is left out of the indices and the dominant keys, and one stderr line names them."""
    vary = ["rows.relative_width=1.6:3", "sun.torque_Nm=500:2000"]
    r = gearcalc.sensitivity(ROWS, vary, samples=8)
    fields = {i["field"] for i in r.indices}
    assert "K" in fields and "relative_width" in fields  # varies (an echo of a varied key too)
    assert not fields & {"cheek_ratio", "rows", "planets_per_row"} and "cheek_ratio" not in r.dominant
    said = [n for n in r.notes if "do not vary" in n]
    assert len(said) == 1 and "cheek_ratio" in said[0]
    args = ["sensitivity", ROWS, "--vary", vary[0], "--vary", vary[1], "--samples", "8"]
    out = cli(*args, "--format", "csv")
    assert out.code == 0 and sum("do not vary" in line for line in out.err.splitlines()) == 1
    assert ",".join(["cheek_ratio", "rows.relative_width"]) not in out.out
