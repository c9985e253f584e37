"""Tests of issue 16 ("zstk v2"): the maximum (Tresca) shear for any Poisson ratio, the allowable radial load,
the separator forces, the loaded-roller threshold and error floor, `separator = false`, and the joint
"cycle" + "envelope" search (spec docs/spec/zstk.md §2, §5, §5.4, §5.5, §8, §10).

Where the expected numbers come from:
* Tresca: the issue's values (0.330 p0 at nu = 0.2, 0.368 at 0.15, 0.408 at 0.1, 0.452 at 0.05), the exact depth
  sqrt((sqrt 5 - 1)/2) of tau_1, and a brute-force maximisation over depth (dense grid, then scipy) of the
  largest principal-stress difference of Johnson's closed-form stresses along the contact axis (§2.8, eq. 2.25;
  plane strain sigma_y = nu(sigma_x + sigma_z)), principal stresses sorted by numpy, not by the formula's case split;
* allowable load: the exact identity Q (sigma_H/sigma_max)² without clearance (sigma ∝ sqrt(Q), spec §5.1), and a
  brute-force scan of sigma_max over Q plus bisection written here, with clearance and preload;
* separator: the law of cosines for the roller's force balance (F_B n_B - F_H n_H has magnitude F_B sin beta);
* joint search: the old nested sweep (:func:`gearcalc.zstk.direction_maxima` over a phase grid per pitch, then a
  full direction sweep), which is independent of the roller-position formulation.
"""
import math

import numpy as np
import pytest

from conftest import CONFIGS, cli
from gearcalc import api, hertz
from gearcalc import zstk as z

EXAMPLE = CONFIGS / "zstk_merko_example.toml"
STEEL = z.Materials.from_elastic(20.0, 2.1e5, 0.3, 2.1e5, 0.3, 2.1e5, 0.3)
Q = 1e4


def compute(**sets):
    return api.compute(api.load(EXAMPLE, overrides=sets), detail=True)


def col(res, key):
    return np.array([row[key] for row in res.detail["rollers"]], dtype=float)


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


def test_product_reports_tresca_for_the_design_nu():
    # all bodies nu = 0.2: tau = 0.3302 sigma at 0.3217 b (summary at the critical contact, per contact in detail)
    res = compute(**{"material.roller_poisson": 0.2, "material.ring_poisson": 0.2})
    s = res.summary
    ratio, depth = (float(x) for x in brute_tresca(0.2))
    assert s["tau_max_MPa"] == pytest.approx(ratio * s["sigma_max_MPa"], rel=1e-9)
    i = s["sigma_max_roller"]
    assert s["tau_max_depth_mm"] == pytest.approx(depth * col(res, "b_B_mm")[i], rel=1e-5)
    assert np.allclose(col(res, "tau_max_B_MPa"), ratio * col(res, "sigma_B_MPa"), rtol=1e-9)
    assert np.allclose(col(res, "tau_depth_H_mm"), depth * col(res, "b_H_mm"), rtol=1e-5)
    # mixed: the smaller nu of a contact's two bodies governs (the body where the shear is largest)
    mixed = compute(**{"material.roller_poisson": 0.3, "material.inner_ring_poisson": 0.1})
    assert np.allclose(col(mixed, "tau_max_B_MPa"), brute_tresca(0.1)[0] * col(mixed, "sigma_B_MPa"), rtol=1e-9)
    assert np.allclose(col(mixed, "tau_max_H_MPa"), brute_tresca(0.3)[0] * col(mixed, "sigma_H_MPa"), rtol=1e-9)


def test_worked_example_tresca_equals_the_in_plane_value():
    s = compute().summary
    assert s["tau_max_MPa"] == hertz.TAU_MAX_RATIO * s["sigma_max_MPa"]
    # depth = 0.786151 b, b = 2 F/(pi l sigma) of the critical contact (Johnson eq. 4.43)
    res = compute()
    b = 2 * col(res, "F_B_N")[0] / (math.pi * 20.0 * s["sigma_max_MPa"])
    assert s["tau_max_depth_mm"] == pytest.approx(0.786151377757423 * b, rel=1e-12)


# ----------------------------------------------------------------------------- item 1: allowable radial load
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


# ----------------------------------------------------------------------------- item 2: separator forces
@pytest.mark.parametrize("sets", [{}, {"load.direction_deg": 35.0, "load.clearance_mm": 0.01},
                                  {"load.direction_deg": "envelope"}])
def test_separator_force_balances_each_roller(sets):
    res = compute(**sets)
    fb, fh, fs = col(res, "F_B_N"), col(res, "F_H_N"), col(res, "F_S_N")
    beta = np.radians(col(res, "beta_deg"))
    # law of cosines: |F_B n_B - F_H n_H| with the angle beta between the normals is the separator's force
    assert np.allclose(fs, np.sqrt(np.maximum(fb ** 2 + fh ** 2 - 2 * fb * fh * np.cos(beta), 0.0)), rtol=1e-6,
                       atol=1e-9 * fb.max())
    assert np.all(fs >= 0) and res.summary["separator_force_max_N"] == fs.max() > 0


def test_separator_force_is_zero_without_eccentricity():
    s = compute(**{"geometry.eccentricity_mm": 0.0}).summary
    assert s["separator_force_max_N"] == 0.0


# ----------------------------------------------------------------------------- item 6: small ones
def test_round_off_rollers_are_not_counted_as_loaded():
    # e = 0, N = 8, load through a roller: the rollers at +-90 degrees carry ~1e-18 Q of round-off, not load
    ch = z.close_chains(np.array([100.0]), 60.0, 0.0, 0.0, np.array([8]), "gap")
    th = z.roller_angles(np.zeros(1), 8, ch.limiting_ratio)
    st = z.evaluate(ch, STEEL, th, np.zeros(1), Q, 0.0, symmetric=np.array([True]))
    assert np.count_nonzero(st.force_inner > 0) > 3        # the round-off is there
    s = z.summarise(st, np.array([Q]), np.zeros(1), np.array([True]))
    assert s.loaded[0] == 3                                 # 0 and +-45 degrees
    assert s.sigma_err[0] == 1e-12 * s.sigma_max[0]         # the round-off floor of a closed form


# ----------------------------------------------------------------------------- item 4: separator = false
def test_separator_false_is_refused():
    for command in ("zstk", "check"):
        r = cli(command, EXAMPLE, "--set", "geometry.separator=false", "--set", "geometry.roller_gap_mm=0")
        assert r.code == 2
        assert "geometry.separator" in r.err + r.out and "roller-to-roller contact" in r.err + r.out
    assert compute(**{"geometry.separator": True}).summary == compute().summary


# ----------------------------------------------------------------------------- item 5: joint search
def nested_reference(ch, mats, load, clearance, tol=1e-9):
    """The former nested sweep: phases per pitch x the direction envelope, then the full direction sweep."""
    n = ch.n
    m = min(720, max(180, 16 * n))
    gg = 2 * np.pi * np.arange(m) / m
    sw = z.maximise_periodic(lambda ph: z.direction_maxima(ch, mats, ph, gg, load, clearance, 1e-8),
                             0.0, 2 * np.pi / n, 64, tol, 2 ** 16, 1e-8)
    sw2 = z.maximise_periodic(lambda g: z.sigma_max_at(ch, mats, sw.x, g, load, clearance), 0.0, 2 * np.pi, 720, tol,
                              2 ** 16, 1e-8)
    return max(sw.value, sw2.value)


@pytest.mark.slow
@pytest.mark.parametrize("geometry, n, clearance", [((100.0, 50.0, 6.0, 6.0), 8, 0.01),   # (8, 0.0): as (3, 0.0)
                                                    ((100.0, 20.0, 60.0, 5.0), 5, 0.0),
                                                    ((100.0, 50.0, 6.0, 6.0), 3, 0.0),
                                                    ((100.0, 50.0, 10.0, 1.0), 5, -0.02)])
def test_joint_search_against_the_nested_sweep(geometry, n, clearance):
    ch = z.close_chain(*geometry, n)
    mats = z.Materials.from_elastic(20.0, 2.1e5, 0.3, 1.5e5, 0.25, 2.1e5, 0.25)
    pl = z.critical_placement(ch, mats, Q, clearance, tol=1e-6, refine_rtol=1e-5)
    ref = nested_reference(ch, mats, Q, clearance)
    assert abs(pl.value - ref) <= pl.err + 1e-9 * ref
    assert pl.err <= 1e-6 * pl.value
    # the placement reproduces the value
    assert float(z.sigma_max_at(ch, mats, pl.phase, pl.gamma, Q, clearance)) == pytest.approx(pl.value, rel=1e-9)


def test_hard_case_n248():
    # spec §9: R_H = 100, R_B = 97.5, e = 0.5, c = 0.05, N = 248: the maximum is scheme A with the load toward
    # the narrowest gap (the former nested sweep's result, 509.3923211253138 MPa)
    s = api.compute(api.load(EXAMPLE, overrides={
        "geometry.inner_raceway_radius_mm": 97.5, "geometry.eccentricity_mm": 0.5, "geometry.roller_gap_mm": 0.05,
        "geometry.scheme": "cycle", "load.direction_deg": "envelope"})).summary
    assert s["N"] == 248
    assert abs(s["sigma_max_MPa"] - 509.3923211253138) <= s["sigma_max_err_MPa"] + 1e-12 * 509.4
    assert s["sigma_max_err_MPa"] <= 1e-6 * s["sigma_max_MPa"]


def test_grid_rows_without_refinement_equal_a_re_evaluation():
    # above refine_rows_max_n the rows keep the quantities of each roller's best grid direction: they equal
    # evaluating the chain at that direction
    ch = z.close_chain(100.0, 50.0, 6.0, 6.0, 8)
    theta = z.roller_angles(0.1, 8, ch.limiting_ratio)
    d_b, d_h, g_b, g_h = z.roller_envelope(ch, STEEL, theta, Q, 0.0, 1e-6, 360,
                                           grid=z.SweepGrid(refine_rows_max_n=0))
    for i in range(8):
        st = z.evaluate(ch, STEEL, theta[None, :], np.array([g_b[0, i]]), Q)
        assert d_b["sigma_inner"][0, i] == pytest.approx(st.sigma_inner[0, i], rel=1e-12)
        assert d_b["force_inner"][0, i] == pytest.approx(st.force_inner[0, i], rel=1e-12)
        st = z.evaluate(ch, STEEL, theta[None, :], np.array([g_h[0, i]]), Q)
        assert d_h["sigma_outer"][0, i] == pytest.approx(st.sigma_outer[0, i], rel=1e-12)


def test_cost_guard_refuses_before_starting():
    r = cli("zstk", EXAMPLE, "--set", "geometry.inner_raceway_radius_mm=97.5", "--set", "geometry.eccentricity_mm=0.5",
            "--set", "geometry.roller_gap_mm=0.05", "--set", "geometry.rollers=2000", "--set", "geometry.scheme=cycle",
            "--set", "load.direction_deg=envelope", "--model", "reference")
    assert r.code == 2 and "over the budget" in r.err and "geometry.rollers" in r.err


@pytest.mark.parametrize("clearance", [0.0, 0.01])
def test_roller_sigma_is_roller_zero_of_the_full_evaluation(clearance):
    # §8: f(phi, rho) = max(sigma_0B, sigma_0H) of the chain with roller 0 at phi, load at its normal + rho;
    # roller k at phase phi_0 is roller 0 at phi_0 + 2 pi k/N
    ch = z.close_chain(100.0, 50.0, 6.0, 6.0, 8)
    pos = np.array([0.0, 0.3, 2.0, 3.1])
    rel = np.array([0.0, -0.2, 0.4, 1.0])
    f = z.roller_sigma(ch, STEEL, pos, rel, Q, clearance)
    theta = z.roller_angles(pos, 8, ch.limiting_ratio)
    nb0 = np.array([z.evaluate(ch, STEEL, theta[i:i + 1], 0.0, Q, clearance).normal_angle[0, 0] for i in range(4)])
    st = z.evaluate(ch, STEEL, theta, nb0 + rel, Q, clearance)
    assert np.array_equal(f, np.maximum(st.sigma_inner[:, 0], st.sigma_outer[:, 0]))
    pitch = 2 * np.pi / 8
    shifted = z.evaluate(ch, STEEL, z.roller_angles(pos - 3 * pitch, 8, ch.limiting_ratio), nb0 + rel, Q, clearance)
    assert np.allclose(np.maximum(shifted.sigma_inner[:, 3], shifted.sigma_outer[:, 3]), f, rtol=1e-12)
