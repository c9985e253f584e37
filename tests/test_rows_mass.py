"""Tests of gearcalc.rows.mass.mass_and_optimum (rows.md §6, §13.8); the mass formula itself is tested in
tests/test_rows.py."""
import numpy as np
import pytest

from gearcalc.rows import mass as M


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
