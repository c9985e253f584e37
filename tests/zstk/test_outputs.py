"""gearcalc.zstk.outputs and report: the outputs of a solved stack and their names (zstk.md §6, §10).

Expected values: the worked example of Merko et al. as the product reports it (sigma_max 748.935693220922 MPa,
configs/zstk_merko_example.toml), spec §6 item 5 (correcting R_H moves r_min and r_max by Delta R_H / 2),
Johnson's b = 2F/(pi l sigma), F_S = F_B sin(beta) (zstk.md §5 item 2), and the field lists of zstk.md §10.
"""
import numpy as np
import pytest

from gearcalc.zstk import geometry, outputs, report, solve

EXAMPLE = solve.Designs(100.0, 50.0, 6.0, 6.0, 20.0, "auto", "outer", "A", True, 1e4, 0.0, 0.0, 2.1e5, 0.3, 2.1e5,
                        0.3, None, None, None, None, [None, 500.0])


def stack():
    (_, s), = solve.solve_stack(solve.prepare(EXAMPLE, 2, 2000, 4000.0), [0, 1])
    return s


def test_worked_example_outputs():
    s = stack()
    o = outputs.stack_outputs(s)
    sm = o.summary
    assert sm.sigma_max[0] == pytest.approx(748.935693220922, rel=1e-13)          # zstk.md §6 (product baseline)
    assert o.passed.tolist() == [True, False]                                      # 748.9 <= 4000, > 500
    assert o.safety.tolist() == pytest.approx([4000.0 / sm.sigma_max[0], 500.0 / sm.sigma_max[1]], rel=1e-15)
    d_rh = s.chain.outer_radius[0] - 100.0                                        # zstk.md §6 item 5
    assert d_rh > 0
    assert o.r_min[0] == pytest.approx(22.0 + d_rh / 2, rel=1e-14)                # (100 - 50 - 6)/2 = 22
    assert o.r_max[0] == pytest.approx(28.0 + d_rh / 2, rel=1e-14)                # (100 - 50 + 6)/2 = 28
    f_s = s.state.force_inner * np.sin(np.abs(s.state.beta))                      # zstk.md §5 item 2
    assert np.array_equal(o.separator, f_s)
    assert o.admissible_max == [31, 31]                                           # N < N_max = 31.94 (check)


def test_roller_detail_follows_johnson():
    s = stack()
    d = outputs.roller_detail(s.state, s.mats, s.clearance)
    loaded = d.contacts.force_inner > 0
    b = 2 * d.contacts.force_inner[loaded] / (np.pi * 20.0 * d.contacts.sigma_inner[loaded])   # Johnson (4.45)
    assert d.contacts.width_inner[loaded] == pytest.approx(b, rel=1e-12)
    assert d.approach[0, 0] * 1e3 == pytest.approx(15.036652650445422, rel=1e-12)  # approach_um of the example
    assert d.gamma_inner is None and d.worst.tolist() == [-np.inf, -np.inf]


def test_extreme_roller_radii_are_the_ends_of_r_theta():
    rng = np.random.default_rng(1)
    r_b = rng.uniform(1, 100, 50)
    r_h = r_b + rng.uniform(1, 100, 50)
    e = rng.uniform(0, 0.99, 50) * (r_h - r_b)
    r_min, r_max = geometry.extreme_roller_radii(r_h, r_b, e)
    assert r_min == pytest.approx(geometry.roller_radius(0.0, r_h, r_b, e), rel=1e-12)
    assert r_max == pytest.approx(geometry.roller_radius(np.pi, r_h, r_b, e), rel=1e-12)


def test_fields_and_rows_have_the_spec_names():
    s = stack()
    o = outputs.stack_outputs(s)
    cols = report.summary_fields("ex", "equilibrium", s, o, {})
    spec = ["name", "model", "scheme", "theta0_deg", "N", "N_star", "correction", "outer_raceway_radius_mm",
            "inner_raceway_radius_mm", "roller_gap_mm", "correction_mm", "r_min_mm", "r_max_mm", "sigma_max_MPa",
            "sigma_max_contact", "sigma_max_roller", "sigma_max_angle_deg", "sigma_max_roller_radius_mm",
            "sigma_max_load_direction_deg", "allowable_stress_MPa", "allowable_stress_source", "safety_factor",
            "pass", "tau_max_MPa", "tau_max_depth_mm", "separator_force_max_N", "radial_load_allowable_N",
            "radial_load_allowable_err_N", "approach_um", "approach_direction_deg", "clearance_mm", "loaded_rollers"]
    assert set(spec) <= set(cols) and all(len(v) == 2 for v in cols.values())   # zstk.md §10
    assert cols["allowable_stress_source"] == ["default: ISO 76 static reference", "design"]
    assert cols["separator_force_max_N"] == np.max(o.separator, axis=-1).tolist()
    rows = report.detail_rows(outputs.roller_detail(s.state, s.mats, s.clearance), o.separator)
    assert len(rows) == 16 and [r["i"] for r in rows[:8]] == list(range(8))
    assert list(rows[0])[:8] == ["i", "theta_deg", "r_mm", "psi_deg", "beta_deg", "F_B_N", "F_H_N", "F_S_N"]


def test_messages():
    s = stack()
    o = outputs.stack_outputs(s)
    warnings, failed = report.messages(1, s, o, False, -np.inf)
    assert warnings == [] and failed[0].startswith("sigma_max_MPa = 748.936 > allowable_stress_MPa = 500 (inner")
    warnings, failed = report.messages(0, s, o, False, 0.25, ["note"])
    assert warnings[:2] == ["note", report.DEFAULT_ALLOWABLE_WARNING] and "b/rho = 0.25 > 0.1" in warnings[2]
    assert failed == []
    assert report.wrap_deg(np.array([-np.pi, np.pi / 2])).tolist() == [180.0, 90.0]
    text = report.cost_message(10, 10, True, False, False, 7e6, 6e6)
    assert text.startswith('= 10: N = 10 rollers with geometry.scheme = "cycle" need 7e+06')
