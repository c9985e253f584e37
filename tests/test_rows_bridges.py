"""Tests of gearcalc.rows.bridges: the carrier verification and the feasible-width search (rows.md §5.5).
Bridge sizing against the paper's table is tested in tests/test_rows.py."""
import math

import numpy as np
import pytest

from gearcalc.rows import bridges as Br
from gearcalc.rows import sharing as S

ALPHA = math.radians(20.0)
PAPER_CELL = (3, 3, 18, 5.0, ALPHA, 4.0, 2e5, 0.3)   # n = 3, n_w = 3, z_a = 18, m = 5, i = 4 (rows.md §5.6)


def test_rigid_carrier_verification_is_the_stepwise_level():
    # rows.md §5.5: with y = 0 the active set solves system (1)
    v = Br.verify_carrier(0.8, 0.25, 4, np.zeros((4, 4)))
    u, _ = S.stepwise_shares(0.8, 0.25, 4)
    assert v.valid and v.converged and v.unloaded == [] and np.allclose(v.shares, u, rtol=1e-12)
    assert v.K == pytest.approx(float(u.max()), rel=1e-12)


def test_verification_not_available_at_kappa_8():
    # rows.md §13.10: K_balanced is null where the stepwise system is invalid
    v = Br.verify_carrier(S.KAPPA_STEPWISE_MAX, 0.25, 3, np.zeros((3, 3)))
    assert not v.valid and v.K is None
    assert Br.verify_carrier(50.0, 0.25, 1, np.zeros((1, 1))).K == 1.0   # n = 1: nothing to share


def test_carrier_compliance_scales_the_force_matrix():
    # rows.md §5.5: F = 2 w b_w cos alpha_w, C y / w̄ = Y u
    k = np.array([2e9, 3e9, 4e9])
    Y = Br.carrier_compliance(120.0, 3, k, 3, 40.0, ALPHA, 1.5e4)
    assert np.allclose(Y, Br.carrier_matrix(120.0, 3, k, 3) * 2 * 40.0 * math.cos(ALPHA) * 1.5e4, rtol=1e-15)


def test_largest_feasible_width_of_the_capped_paper_cell():
    # rows.md §5.6: n = 3, B = 3, i = 4 asks slightly more than H_max in span 3; the CLI says B <= 2.973 fits
    Ip = S.polar_moment(77.5)                                # root diameter, solid sun
    assert not Br.bridges_fit(3.0, *PAPER_CELL, Ip)
    B_ok = Br.largest_feasible_width(3.0, *PAPER_CELL, Ip)
    assert math.floor(B_ok * 1000) / 1000 == 2.973
    assert Br.bridges_fit(B_ok, *PAPER_CELL, Ip) and not Br.bridges_fit(B_ok * (1 + 1e-5), *PAPER_CELL, Ip)


def test_feasible_width_uses_the_given_sections():
    # given d and h stay fixed while B moves; None follows 0.5 b_w (rows.md §7)
    Ip = S.polar_moment(77.5)
    b_w = 3.0 * 90.0 / 3.5
    assert Br.bridges_fit(3.0, *PAPER_CELL, Ip, axle_diameter=0.5 * b_w, bridge_thickness=0.5 * b_w) is False
    assert Br.bridges_fit(1.0, *PAPER_CELL, Ip, cheek=200.0) is False     # no room for the rims
