"""Tests of the summary functions of gearcalc.zstk.stress (spec docs/spec/zstk.md §2, §8, §10).

Expected values: the worked example of Merko et al. as the product reports it (configs/zstk_merko_example.toml:
sigma_max 748.935693220922 MPa, b_B 0.2066159512375799 mm, delta 15.036652650445422 um, 5 loaded
rollers), and Johnson's line-contact relations b = 2F/(pi l sigma), tau_max = 0.3003 sigma.
"""
import numpy as np
import pytest

from gearcalc import zstk as z
from conftest import CONFIGS
from gearcalc import api

CHAIN = z.close_chains(np.array([100.0]), 50.0, 6.0, 6.0, np.array([8]))
STEEL = z.Materials.from_elastic(20.0, 2.1e5, 0.3, 2.1e5, 0.3, 2.1e5, 0.3)


def solved(clearance=0.0, gamma=0.0):
    return z.solve_placements(CHAIN, STEEL, np.zeros(1), CHAIN.limiting_ratio, np.array([gamma]), np.array([1e4]),
                              np.array([clearance]), np.array([True]))


def test_worked_example_summary():
    state, sym, step = solved()
    assert sym.tolist() == [True] and step is None
    s = z.summarise(state, np.array([1e4]), np.zeros(1), sym)
    assert s.sigma_max[0] == pytest.approx(748.935693220922, rel=1e-13)   # zstk.md §6 (product baseline)
    assert (s.roller[0], s.contact[0], s.loaded[0]) == (0, 0, 5)
    assert s.sigma_err[0] == 1e-12 * s.sigma_max[0]                        # closed form (§5.1): round-off floor
    assert s.approach[0] * 1e3 == pytest.approx(15.036652650445422, rel=1e-12)


def test_sweep_error_floor():
    # §8, issue 16 item 6: every estimate is at least 1e-12 sigma_max (the closed-form parts' round-off)
    state, sym, _ = solved()
    s = z.summarise(state, np.array([1e4]), np.zeros(1), sym, sweep_err=np.zeros(1))
    assert s.sigma_err[0] == 1e-12 * s.sigma_max[0]
    s = z.summarise(state, np.array([1e4]), np.zeros(1), sym, sweep_err=np.array([1e-3]))
    assert s.sigma_err[0] == pytest.approx(1e-3, rel=1e-9)     # the sweep term plus the solver's (~1e-13)


def test_contacts_follow_johnson():
    state, _, _ = solved(clearance=0.01, gamma=0.3)
    c = z.roller_contacts(state, state, STEEL)
    loaded = c.force_inner > 0
    # Johnson 1985 §4.2: b = 2F/(pi l p0); §2.8: tau_max = 0.3003 p0
    assert np.allclose(c.width_inner[loaded], 2 * c.force_inner[loaded] / (np.pi * 20.0 * c.sigma_inner[loaded]),
                       rtol=1e-12)
    assert np.allclose(c.shear_outer, 0.30028310600077 * c.sigma_outer, rtol=1e-13)
    assert z.worst_width_ratio(c, 0.1).tolist() == [-np.inf]
    assert z.worst_width_ratio(c, 1e-6)[0] == pytest.approx(np.max(np.where(loaded, c.width_inner / c.rho_inner,
                                                                            c.width_outer / c.rho_outer)))


def test_roller_approach_is_zero_at_the_edge_of_contact():
    # §5: F = c_L delta_i^(10/9) for delta_i > 0; unloaded rollers have delta_i <= 0
    state, _, _ = solved(clearance=0.01, gamma=0.3)
    d = z.roller_approach(state, np.array([0.01]))
    f = state.force_inner
    assert np.all(d[f == 0] <= 0)
    assert np.allclose(f[f > 0], STEEL.stiffness * d[f > 0] ** (10 / 9), rtol=1e-9)


def test_safety_factor():
    # §10: [sigma_H] / sigma_max, the worked example against the 4000 MPa default
    assert z.safety_factor(748.935693220922, 4000.0) == pytest.approx(5.340912492496302, rel=1e-15)
    assert np.isnan(z.safety_factor(0.0, 4000.0))


# ---------------------------------------------------------------- separator forces, loaded rollers (issue 16)
# Expected: the law of cosines for the roller's force balance (F_B n_B - F_H n_H has magnitude F_B sin beta); the
# exact zero of a concentric chain; the round-off floor 1e-12 sigma of a closed form (zstk.md §5.5).
EXAMPLE = CONFIGS / "zstk_merko_example.toml"


Q = 1e4


def compute(**sets):
    return api.compute(api.load(EXAMPLE, overrides=sets), detail=True)


def col(res, key):
    return np.array([row[key] for row in res.detail["rollers"]], dtype=float)


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
