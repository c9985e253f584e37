"""Tests of gearcalc.rows.mass: the relative mass against the paper's volumes and the Hertz torque, the optimum
ratio against its closed form, mass_and_optimum (rows.md §6, §13.8)."""
import math

import numpy as np
import pytest

from gearcalc import hertz
from gearcalc import rows as R
from gearcalc.rows import mass as M

E, NU = 2e5, 0.3
ALPHA = math.radians(20.0)


def test_ratio_used_is_the_given_one_else_the_optimum():
    # rows.md §13.8: `ratio` is gear.ratio when given, else ratio_opt
    free = M.mass_and_optimum(None, (2.2, 12.0), 1e-10, rows=2, planets_per_row=3)
    assert free.ratio is free.ratio_opt and free.relative_mass == pytest.approx(free.relative_mass_min, rel=1e-15)
    # rows.md §6: the minimiser of the printed bracket is 2 + sqrt(C0/A), within ratio_opt_err
    i_star = float(M.mass_optimum_closed_form(2, 3, 0.06, 0.7, 1.0, 0.25))
    assert abs(float(free.ratio_opt) - i_star) <= float(free.ratio_opt_err)
    fixed = M.mass_and_optimum(5.0, (2.2, 12.0), 1e-10, rows=2, planets_per_row=3)
    assert fixed.ratio == 5.0 and fixed.relative_mass == float(M.relative_mass(5.0, 2, 3))
    assert not bool(fixed.ratio_opt_on_bound)


def test_batch_of_designs():
    n = np.array([1, 2, 3, 4])
    m = M.mass_and_optimum(None, (np.full(4, 2.2), np.full(4, 12.0)), 1e-9, rows=n, planets_per_row=3)
    i_star = M.mass_optimum_closed_form(n, 3, 0.06, 0.7, 1.0, 0.25)
    assert np.all(np.abs(m.ratio_opt - i_star) <= m.ratio_opt_err)
    assert np.all(np.diff(m.relative_mass_min) < 0)     # rows.md §11.7: M falls with n


# ------------------------------------------------------------------ relative mass
def test_mass_prefactor_from_volumes_and_hertz_torque():
    # rows.md §6: M = volume × density / output torque, with the Hertz-limited torque
    n, n_w, i, d_a, b_w = 3, 3, 4.5, 90.0, 40.0
    t, ka, kg, bbar = 0.06, 0.7, 1.0, 0.25
    sigma, rho, eta, K = 600.0, 7800.0, 0.95, 1.3
    c_h = (2 * math.pi * (1 - NU**2)) ** -0.5
    rho_red = 0.5 * d_a * math.sin(ALPHA) * (i - 2) / i
    w_allow = (sigma / c_h) ** 2 * rho_red / E  # N/mm
    T_a = n * n_w * b_w * (0.5 * d_a * math.cos(ALPHA)) * w_allow / K  # N·mm
    T_out = eta * i * T_a / 1e6  # kN·m
    volume = math.pi * d_a**2 * b_w / 4 * R.mass_bracket(i, n, n_w, t, ka, kg, bbar) * 1e-9  # m³
    expected = rho * volume / T_out
    got = R.relative_mass(i, n, n_w, t, ka, kg, bbar, sigma, rho, E, NU, eta, K, ALPHA)
    assert float(got) == pytest.approx(expected, rel=1e-12)


@pytest.mark.parametrize("n", [1, 2, 3, 4])
@pytest.mark.parametrize("t", [0.0, 0.06, 0.15])
def test_ratio_opt_matches_closed_form(n, t):
    from gearcalc.roots import minimize_golden

    f = lambda i: R.relative_mass(i, n, 3, t, 0.7, 1.0, 0.25)  # noqa: E731
    opt = minimize_golden(f, 2.2, 12.0, rtol=1e-9)
    exact = float(R.mass_optimum_closed_form(n, 3, t, 0.7, 1.0, 0.25))
    assert abs(float(opt.x) - exact) <= float(opt.err)
    assert not bool(opt.on_bound)


def test_ratio_opt_moves_with_wall_ratio():
    # paper's claim 7 / rows.md §6: the minimum is found numerically; changing t must move it
    from gearcalc.roots import minimize_golden

    a, b = (minimize_golden(lambda i, t=t: R.relative_mass(i, 2, 3, t), 2.2, 12.0, rtol=1e-8) for t in (0.06, 0.10))
    assert abs(float(a.x) - float(b.x)) > 100 * (float(a.err) + float(b.err))
    assert abs(float(a.x) - 3.5) > 0.1  # the printed bracket does not put it at the paper's 3.5


def test_mass_falls_with_n_at_every_ratio():
    # paper's conclusion 4 (rows.md §6): M falls with n at every i of the Fig. 5 set
    i = np.arange(2.2, 12.0001, 0.05)
    M = np.array([R.relative_mass(i, n, 3) for n in (1, 2, 3, 4)])
    assert np.all(np.diff(M, axis=0) < 0)


def test_hertz_constant():
    # rows.md §6, §13.9: (2π(1-ν²))^(-1/2) = 0.418 for ν = 0.3 (Johnson, Contact Mechanics)
    assert round(float(hertz.line_pressure_constant(0.3)), 3) == 0.418


# ------------------------------------------------------------------ an efficiency without physical meaning
@pytest.mark.parametrize("eta", ["5e-324", "1e-300", "0.001"])
def test_tiny_efficiency_refused_by_check_run_and_sweep(eta, tmp_path):
    # issue 34: efficiency = 5e-324 made M = inf (exit 70, no output at all) while `check` said ok. A gear that
    # passes under 1 % of its power is no drive (rows.md §7: eta in [0.01, 1]): the one rule refuses it in
    # check, run and sweep alike, naming file, key and bound; the other designs of the batch are still computed.
    from conftest import CONFIGS, cli

    text = (CONFIGS / "rows_mass_fig5.toml").read_text().replace("efficiency = 0.95", f"efficiency = {eta}")
    bad = tmp_path / "e.toml"
    bad.write_text(text)
    r = cli("check", bad)
    assert r.code == 2 and "mass.efficiency" in r.err and str(bad) in r.err and ">= 0.01" in r.err, r
    good = CONFIGS / "rows_fig3_n3_nw3_B2.4.toml"
    for fmt in ("json", "csv", "table"):
        r = cli("run", good, bad, "--format", fmt)
        assert r.code == 2 and "Fig. 3 curve 4" in r.out and "mass.efficiency" in r.err, (fmt, r)
    r = cli("sweep", CONFIGS / "rows_mass_fig5.toml", "--vary", f"mass.efficiency=0.9,{eta},0.95", "--format", "csv")
    assert r.code == 2 and "mass.efficiency" in r.err and "Traceback" not in r.err, r
