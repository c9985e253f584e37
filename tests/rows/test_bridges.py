"""Tests of gearcalc.rows.bridges: the carrier verification and the feasible-width search (rows.md §5.5).
Bridge sizing against the paper's table (rows.md §5.6) and the sized carrier's balance."""
import itertools
import math

import numpy as np
import pytest

import gearcalc
from gearcalc import rows as R
from gearcalc.rows import bridges as Br
from gearcalc.rows import sharing as S

ALPHA = math.radians(20.0)
D_A, E, NU = 90.0, 2e5, 0.3
G = E / (2 * (1 + NU))
R_BA = 0.5 * D_A * math.cos(ALPHA)
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


# ------------------------------------------------------------------ bridge table (paper, rows.md §5.6)
TABLE = {  # (n, B, i): H_j/H_max by row, row 1 on the sun-input side
    (4, 4.0, 4): [0, 0.25, 0.98, 1.00], (4, 4.0, 6): [0, 0.12, 0.43, 0.43], (4, 4.0, 10): [0, 0.06, 0.19, 0.19],
    (3, 3.0, 4): [0, 0.47, 1.00], (3, 3.0, 6): [0, 0.22, 0.46], (3, 3.0, 10): [0, 0.10, 0.21],
}


def sized(n, B, i, module=5.0, bore=0.0):
    d_a = 18 * module
    b_w = R.rim_width(B, n, 0.25, d_a)
    return R.size_bridges(n, 3, d_a, module, b_w, 0.25 * b_w, ALPHA, i, 0.5 * b_w, 0.5 * b_w, E, NU,
                          R.polar_moment(d_a - 2.5 * module, bore))


@pytest.mark.parametrize("key", list(TABLE))
def test_bridge_table_within_0035(key):
    res = sized(*key)
    rel = res["H"] / res["H_max"]
    assert np.all(np.abs(rel - np.array(TABLE[key])) <= 0.035), rel


def test_bridge_capped_cell_flagged():
    # rows.md §5.6: n = 3, B = 3, i = 4 row 3 asks for slightly more than H_max: capped and flagged
    res = sized(3, 3.0, 4)
    assert res["flags"] == ["ok", "ok", "exceeds_max"]
    assert res["H"][2] == res["H_max"]
    assert all(f == "ok" for f in sized(4, 4.0, 6)["flags"])


@pytest.mark.parametrize("module", [1.0, 3.0, 12.0])
def test_bridge_ratios_independent_of_module(module):
    a, b = sized(4, 4.0, 6), sized(4, 4.0, 6, module=module)
    assert np.allclose(a["H"] / a["H_max"], b["H"] / b["H_max"], rtol=1e-12, atol=1e-15)
    assert a["Q"] == pytest.approx(b["Q"], rel=1e-12)


def test_sized_width_has_required_compliance():
    # rows.md §11: the compliance of the sized width equals the required compliance
    res = sized(4, 4.0, 6)
    b_w = R.rim_width(4.0, 4, 0.25, 90.0)
    h = 0.5 * b_w
    geo = (res["a_c"] / res["a_w"]) ** 2
    for H, D in zip(res["H"][1:], res["D"][1:]):
        required = res["axle_compliance"] * geo / (D - 1)
        actual = R.beam_compliance(b_w, h * H**3 / 12, H * h, E, NU)
        assert actual == pytest.approx(required, rel=1e-12)


def test_sized_carrier_balances_rows():
    # rows.md §5.5: a design sized exactly (all flags ok) gives K_balanced = 1 up to rounding
    n, B, i = 4, 4.0, 6
    res = sized(n, B, i)
    d_a = 90.0
    b_w = R.rim_width(B, n, 0.25, d_a)
    Y = R.carrier_matrix(res["a_w"], 3, res["stiffness"], n) * 2 * b_w * math.cos(ALPHA) * 0.075 * E
    kap = float(R.torsion_parameter(0.075 * E, R_BA, 3, b_w, G, R.polar_moment(d_a - 12.5)))
    u, unloaded, ok, resid = R.stepwise_active_set(kap, 0.25, n, carrier=Y)
    assert ok and unloaded == [] and resid < 1e-12
    assert np.allclose(u, 1.0, rtol=0, atol=1e-12)
    # and the same carrier under the stiffer (pitch) sun over-compensates: the far rows carry more
    kap_p = float(R.torsion_parameter(0.075 * E, R_BA, 3, b_w, G, R.polar_moment(d_a)))
    u_p = R.stepwise_active_set(kap_p, 0.25, n, carrier=Y)[0]
    assert u_p.max() > 1.0 and np.argmax(u_p) > 0


def test_active_set_unloads_rows_with_overcompensating_carrier():
    # A carrier compliance that pushes load to the far end: near rows unload; equilibrium holds.
    n = 5
    Y = -np.tril(np.ones((n, n))) * 3.0  # strongly overcompensating, made-up but admissible matrix
    u, unloaded, ok, resid = R.stepwise_active_set(0.5, 0.25, n, carrier=Y)
    assert ok and unloaded, u
    assert np.all(u >= 0) and u.sum() == pytest.approx(n, rel=1e-12)
    assert all(u[j - 1] == 0 for j in unloaded)


# ---------------------------------------------------------------- the batch sizing; where every bridge fits
def test_size_bridges_batch_equals_size_bridges_per_design():
    # the scalar function is the batch of one: a batch of many designs gives each design's widths and flags
    B = np.linspace(0.3, 6.0, 25)
    for n, ratio, first in itertools.product((2, 3, 4), (2.5, 4.0, 10.0), (None, 2.0)):
        f = R.face_geometry(18, 5.0, n, np.radians(20.0), relative_width=B)
        batch = R.size_bridges_batch(n, 3, f.sun_diameter, 5.0, f.rim_width, f.cheek, np.radians(20.0), ratio,
                                     0.5 * f.rim_width, 0.5 * f.rim_width, 2e5, 0.3, R.polar_moment(77.5), first)
        for k, b in enumerate(B.tolist()):
            g = R.face_geometry(18, 5.0, n, np.radians(20.0), relative_width=b)
            one = R.size_bridges(n, 3, g.sun_diameter, 5.0, g.rim_width, g.cheek, np.radians(20.0), ratio,
                                 0.5 * g.rim_width, 0.5 * g.rim_width, 2e5, 0.3, R.polar_moment(77.5), first)
            assert [R.FLAGS[c] for c in batch["flags"][k]] == one["flags"]
            for key in ("H", "H_rel", "D", "stiffness"):
                assert np.array_equal(batch[key][k], one[key]), key


def _feasible(path, **sets):
    d = gearcalc.design.read_toml(path)
    for key, value in sets.items():
        table, _, name = key.partition("__")
        d[table][name] = value
    return gearcalc.compute(d).summary["bridges_feasible"]


def test_the_bridge_hint_gives_the_window_and_its_bounds_are_where_the_flag_flips():
    # the paper's capped cell (rows.md §5.6): only 2.67 <= B <= 2.97 fits (issue 34); the hint says both bounds,
    # rounded inward to 3 decimals, and the design computed alone flips bridges_feasible between them and 0.001
    # outside them (an independent evaluation: the check itself at those widths)
    from conftest import CONFIGS, cli

    paper = CONFIGS.parent / "paper" / "rows_bridges_n3_B3_i4.toml"
    for sets in ([], ["--set", "rows.relative_width=2.4"]):  # above and below the window
        r = cli("rows", paper, *sets, "--format", "csv")
        assert r.code == 1 and "every bridge fits for rows.relative_width from 2.666 to 2.973 (rows.count = 3)" \
            in r.err, r.err
    for B, fits in ((2.665, False), (2.666, True), (2.8, True), (2.973, True), (2.974, False)):
        assert _feasible(paper, rows__relative_width=B) is fits, B
    r = cli("rows", paper, "--set", "rows.count=4", "--format", "csv")
    assert r.code == 1 and "from 4.000 to 4.035 (rows.count = 4)" in r.err
    for B, fits in ((3.999, False), (4.0, True), (4.035, True), (4.036, False)):
        assert _feasible(paper, rows__count=4, rows__relative_width=B) is fits, B
    # five rows: no width fits (B/30 to 30 B tried); four rows do
    r = cli("rows", paper, "--set", "rows.count=5", "--format", "csv")
    assert "no rows.relative_width makes every bridge fit with rows.count = 5" in r.err
    assert "rows.count = 4 does, for rows.relative_width from 4.000 to 4.035" in r.err


def test_feasible_widths_bisects_each_edge_to_1e_9():
    # each bound fits, and a width 1e-8 (relative) beyond it does not: the bisection's 1e-9 (bridges.py)
    Ip = R.polar_moment(77.5)
    args = (3, 18, 5.0, np.radians(20.0), 4.0, 2e5, 0.3, Ip)
    (lo, hi), = R.feasible_widths(3.0, 3, *args)
    assert R.bridges_fit(lo, 3, *args) and R.bridges_fit(hi, 3, *args)
    assert not R.bridges_fit(lo * (1 - 1e-8), 3, *args) and not R.bridges_fit(hi * (1 + 1e-8), 3, *args)
    assert R.feasible_widths(3.0, 5, *args) == [] and R.feasible_rows(3.0, 5, *args)[0] == 4
