"""Tests of gearcalc.zstk.capacity: the allowable radial load, at which sigma_max reaches [sigma_H] (zstk.md §5.4).

Where the expected numbers come from: the exact identity Q (sigma_H/sigma_max)² without clearance (sigma ∝ sqrt(Q),
spec §5.1); with clearance or preload a brute-force scan of sigma_max over Q plus bisection written here; the
closed form's own algebra (sigma ∝ sqrt(Q): doubling the allowable stress quadruples the load).
"""

import numpy as np
import pytest

from conftest import CONFIGS
from gearcalc import api
from gearcalc import zstk as z
from gearcalc.zstk import capacity as C

EXAMPLE = CONFIGS / "zstk_merko_example.toml"
STEEL = z.Materials.from_elastic(20.0, 2.1e5, 0.3, 2.1e5, 0.3, 2.1e5, 0.3)
Q = 1e4


def compute(**sets):
    return api.compute(api.load(EXAMPLE, overrides=sets), detail=True)


@pytest.mark.parametrize("sets", [{}, {"material.allowable_stress_MPa": 1500.0}, {"load.direction_deg": 20.0},
                                  {"geometry.scheme": "D"}, {"load.direction_deg": "envelope"},
                                  {"geometry.scheme": "cycle"}])
def test_allowable_load_without_clearance_is_the_closed_form(sets):
    s = compute(**sets).summary
    assert s["radial_load_allowable_N"] == Q * (s["allowable_stress_MPa"] / s["sigma_max_MPa"]) ** 2
    assert 0 < s["radial_load_allowable_err_N"] <= 1e-5 * s["radial_load_allowable_N"]


def test_root_find_reproduces_the_closed_form():
    # the general root (closed_form=False) at s = 0 equals Q (sigma_H/sigma_max)² within its own error estimate
    ch = z.close_chains(np.array([102.69691744943351]), 50.0, 6.0, 6.0, np.array([8]))
    th = z.roller_angles(np.zeros(1), 8, ch.limiting_ratio)
    for gamma, sym in ((0.0, True), (0.35, False)):
        st = z.evaluate(ch, STEEL, th, np.array([gamma]), Q, 0.0, symmetric=np.array([sym]))
        smax = z.critical(st)[0]
        exact = Q * (1500.0 / smax[0]) ** 2
        r = z.allowable_load(ch, STEEL, th, np.array([gamma]), np.array([Q]), np.zeros(1), smax, 1e-12 * smax,
                             np.array([1500.0]), np.array([sym]), closed_form=False)
        assert abs(r.load[0] - exact) <= r.err[0] and r.err[0] < 1e-9 * exact
        assert r.slope[0] == pytest.approx(0.5, rel=1e-6)      # sigma ∝ sqrt(Q)


def scan_root(sigma_of_load, allowable, q_lo, q_hi, points=400):
    """The first crossing of sigma_max(Q) = allowable on a log grid, then 60 bisections (the brute force)."""
    qs = np.geomspace(q_lo, q_hi, points)
    sig = np.array([sigma_of_load(q) for q in qs])
    k = int(np.argmax(sig >= allowable))
    assert k > 0 and sig[k] >= allowable > sig[k - 1]
    a, b = qs[k - 1], qs[k]
    for _ in range(60):
        m = 0.5 * (a + b)
        if sigma_of_load(m) >= allowable:
            b = m
        else:
            a = m
    return 0.5 * (a + b)


@pytest.mark.slow
@pytest.mark.parametrize("clearance, direction", [(0.01, 0.0), (0.05, 20.0), (-0.01, 0.0), (-0.02, 33.0)])
def test_allowable_load_with_clearance_against_a_scan(clearance, direction):
    allow = 1500.0
    res = compute(**{"load.clearance_mm": clearance, "load.direction_deg": direction,
                     "material.allowable_stress_MPa": allow})
    s = res.summary
    q_allow, err = s["radial_load_allowable_N"], s["radial_load_allowable_err_N"]

    def sigma_of_load(q):
        return api.compute(api.load(EXAMPLE, overrides={"load.clearance_mm": clearance, "load.direction_deg": direction,
                                                        "load.radial_N": float(q)})).summary["sigma_max_MPa"]

    brute = scan_root(sigma_of_load, allow, 1e3, 1e6, points=40)
    assert abs(q_allow - brute) <= err + 1e-9 * brute
    assert err <= 1e-9 * q_allow
    # the design at Q_allow reaches [sigma_H]
    assert sigma_of_load(q_allow) == pytest.approx(allow, rel=1e-10)


@pytest.mark.parametrize("sets", [{"load.direction_deg": "envelope"}, {"geometry.scheme": "cycle"},
                                  {"geometry.scheme": "cycle", "load.direction_deg": "envelope"}])
def test_allowable_load_of_sweeps_with_clearance(sets):
    allow = 1500.0
    over = {**sets, "load.clearance_mm": 0.02, "material.allowable_stress_MPa": allow}
    s = compute(**over).summary
    q_allow, err = s["radial_load_allowable_N"], s["radial_load_allowable_err_N"]
    at = api.compute(api.load(EXAMPLE, overrides={**over, "load.radial_N": q_allow})).summary
    # the swept maximum at Q_allow is [sigma_H] within the sweep's error, and the load error follows
    assert abs(at["sigma_max_MPa"] - allow) <= at["sigma_max_err_MPa"] + 1e-6 * allow
    assert 0 < err <= 1e-5 * q_allow


def test_preload_alone_over_the_allowable_gives_zero():
    res = compute(**{"load.clearance_mm": -0.2, "material.allowable_stress_MPa": 500.0})
    assert res.summary["radial_load_allowable_N"] == 0.0
    assert any("preload alone" in w for w in res.warnings)


def test_allowable_load_is_a_sweep_column():
    parts = api.sweep(api.load(EXAMPLE), {"material.allowable_stress_MPa": [1500.0, 4000.0],
                                          "load.clearance_mm": [0.0, 0.01]})
    values = [v for part in parts for v in part.data["radial_load_allowable_N"]]
    expected = []
    for allow in (1500.0, 4000.0):
        for s in (0.0, 0.01):
            one = compute(**{"material.allowable_stress_MPa": allow, "load.clearance_mm": s}).summary
            expected.append(one["radial_load_allowable_N"])
    assert np.allclose(values, expected, rtol=1e-12)       # grid order: the first axis varies slowest


def test_closed_form_limits_and_error_propagation():
    # sigma ∝ sqrt(Q) (F ∝ Q, Hertz sigma ∝ sqrt(F)): at sigma_max = [sigma_H] the allowable load is Q itself and
    # doubling [sigma_H] quadruples it; the error is the first-order propagation |dQ_allow/dsigma| err =
    # 2 Q_allow err / sigma_max, checked against a central difference of the same closed form
    sigma = 748.935693220922  # the worked example's sigma_max at Q = 1e4 N (tests/zstk/test_stress.py)
    r = C.allowable_load_closed_form(np.full(3, Q), np.full(3, sigma), np.array([sigma, 2.0 * sigma, 4000.0]),
                                     np.array([0.0, 0.0, 1e-3]))
    assert r.load[0] == Q and r.load[1] == 4.0 * Q and r.err[0] == r.err[1] == 0.0
    assert np.all(r.slope == 0.5)

    def q_of(s):
        return Q * (4000.0 / s) ** 2

    h = 1e-3
    assert r.err[2] == pytest.approx(abs(q_of(sigma + h) - q_of(sigma - h)) / 2, rel=1e-6)
    assert not np.any(r.preload_exceeds)
