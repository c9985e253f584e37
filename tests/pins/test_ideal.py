"""Tests of the ideal level's cycle model solved for many gears at once (gearcalc.pins.ideal; pins.md §4, §6, §9).

Independent references: the disc sums' budget re-derived by hand; a gear's numbers alone against the same gear in a
batch (bit for bit); the refined peaks against a dense pointwise sweep (gearcalc.pins.forces); the loss ratio's
proportionality to mu and its friction-free limit 0 (pins.md §4.8); the admissibility rule of pins.md §4.2 (the loaded
arc psi* must exceed the pin pitch 360/z2).
"""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from conftest import CONFIGS, cli
from gearcalc import pins
from gearcalc.pins import MULTIPLIER, Cycloid

from pins.test_geometry import HONESTY, POW_SENSITIVE_K1, gear

PINS = CONFIGS / "pins_paper_cyc_u10_rotating.toml"


def test_disc_sum_guard_names_discs_and_tol():
    # 100 pins x 64 discs at --tol 1e-9 took 11 s (n_d^2 x loaded samples = 2.5e8 > pins.DISC_WORK_MAX = 2e8);
    # at 1e-12, 9.5 minutes.  Known only after the quadrature (the grid follows from --tol): run refuses it
    sets = ["--set", "gearing.satellite_teeth=98", "--set", "gearing.pins=100", "--set", "gearing.discs=64"]
    for tol in ("1e-9", "1e-12"):
        r = cli("pins", PINS, *sets, "--tol", tol)
        assert r.code == 2, r
        assert "gearing.discs" in r.err and f"--tol {tol.replace('e-9', 'e-09')}" in r.err
    assert cli("pins", PINS, *sets, "--format", "json").code in (0, 1)      # the default --tol: 0.3 s


def test_ideal_cycles_of_a_batch_equal_each_gear_alone():
    # pins.ideal_cycles: a gear's numbers do not depend on the gears solved with it (bit for bit)
    gs = HONESTY[:8] + [gear(20, 22, K1=0.75, Rb=1.0), gear(20, 22, K1=0.5), gear(3, 12, Rb=0.5)]  # last: too few teeth
    n_d = np.array([1, 2, 1, 3, 1, 1, 1, 1, 1, 1, 1])
    both = Cycloid(*(np.array([getattr(x, f) for x in gs]) for f in ("z1", "z2", "e", "R_p", "R_b", "one_minus_K1")))
    together = pins.ideal_cycles(both, n_d, tol=1e-6)
    assert together.status.tolist() == [0] * 10 + [pins.TOO_FEW_TEETH]
    fields = ("psi_star", "psi_0", "rho_c_min", "loss_ratio", "loss_ratio_err", "converged", "n_crank", "force",
              "force_phase", "loss", "loss_phase", "total", "rel_min", "rel_max", "rel_abs", "loaded_min", "loaded_max")
    for i, gi in enumerate(gs):
        alone = pins.ideal_cycles(pins.geometry.as_arrays(gi), n_d[i], tol=1e-6)
        for f in fields:
            assert np.array_equal(getattr(alone, f), getattr(together, f)[i:i + 1], equal_nan=True), (i, f)
        if alone.status[0] == 0:
            for a, b in zip(alone.grid(0), together.grid(i)):
                assert np.array_equal(a, b)


def test_a_gear_alone_equals_it_in_a_batch_where_a_scalar_square_would_round_otherwise():
    gs = [gear(z1, z1 + 2, K1=K1, Rb=1.0) for z1 in (20, 60) for K1 in POW_SENSITIVE_K1]
    both = Cycloid(*(np.array([getattr(x, f) for x in gs]) for f in ("z1", "z2", "e", "R_p", "R_b", "one_minus_K1")))
    together = pins.ideal_cycles(both, 1, tol=1e-6)
    for i, gi in enumerate(gs):
        alone = pins.ideal_cycles(pins.geometry.as_arrays(gi), 1, tol=1e-6)
        for f in ("loss_ratio", "loss_ratio_err", "force", "force_phase", "loss", "loss_phase", "total", "rel_min",
                  "rel_max", "rel_abs", "n_crank"):
            assert np.array_equal(getattr(alone, f), getattr(together, f)[i:i + 1]), (i, f)


@pytest.mark.parametrize("g", [gear(20, 22), gear(60, 62)], ids=["u10", "u30"])
def test_the_first_rounds_levels_change_no_result(g, monkeypatch):
    # pins.first_levels is speed only: the levels guessed for the quadrature's first round (capped at
    # FIRST_LEVELS_MAX, then predicted from the observed rate) leave every number as it is
    assert [pins.first_levels(t) for t in (1e-3, 1e-6, 1e-9, 1e-12)] == [2, 4, 6, 6]
    capped = pins.ideal_cycles(pins.geometry.as_arrays(g), 1, tol=1e-9)
    monkeypatch.setattr(pins.ideal, "FIRST_LEVELS_MAX", 99)
    assert pins.first_levels(1e-9) == 9
    one_round = pins.ideal_cycles(pins.geometry.as_arrays(g), 1, tol=1e-9)
    for f in ("loss_ratio", "loss_ratio_err", "n_crank", "force", "force_phase", "loss", "total", "rel_abs"):
        assert np.array_equal(getattr(capped, f), getattr(one_round, f)), f
    assert np.array_equal(capped.grid_t, one_round.grid_t)


@pytest.mark.parametrize("tol", [1e-6, 1e-9])
def test_the_first_rounds_guess_by_pin_count_changes_no_result(tol, monkeypatch):
    # issue 15: the first round guesses one level less per doubling of z2 beyond 28 (the u = 30 paper gear,
    # z2 = 62, is accepted at 128 intervals at --tol 1e-6, where the guess of z2 = 22 evaluated 256); speed only
    assert pins.first_levels(1e-6, 22) == 4 and pins.first_levels(1e-6, 62) == 3
    assert pins.first_levels(1e-6, np.array([22, 62, 112, 10_000])).tolist() == [4, 3, 2, 2]
    gs = [gear(20, 22), gear(60, 62), gear(99, 100, K1=0.9)]
    both = Cycloid(*(np.array([getattr(x, f) for x in gs]) for f in ("z1", "z2", "e", "R_p", "R_b", "one_minus_K1")))
    guessed = [pins.ideal_cycles(pins.geometry.as_arrays(g), 1, tol=tol) for g in gs] + [
        pins.ideal_cycles(both, 1, tol=tol)]
    plain = pins.ideal.first_levels
    monkeypatch.setattr(pins.ideal, "first_levels", lambda t, z2=None: plain(t))
    fixed = [pins.ideal_cycles(pins.geometry.as_arrays(g), 1, tol=tol) for g in gs] + [
        pins.ideal_cycles(both, 1, tol=tol)]
    for a, b in zip(guessed, fixed):
        for f in ("loss_ratio", "loss_ratio_err", "n_crank", "force", "force_phase", "loss", "total", "rel_abs",
                  "grid_t", "grid_sums"):
            assert np.array_equal(getattr(a, f), getattr(b, f)), f


@pytest.mark.slow
@pytest.mark.parametrize("g", HONESTY[:4] + HONESTY[5:6], ids=lambda g: f"z{g.z1}-{g.z2}-K{g.K1:.9g}")
def test_ideal_cycles_peaks_against_a_dense_sweep(g):
    # the refined peaks (pins.md §12.1) against 200001 crank angles of one period, pointwise (pin_forces)
    r = pins.ideal_cycles(pins.geometry.as_arrays(g), 1, tol=1e-6)
    theta = np.linspace(0.0, g.period, 200001)
    F = pins.pin_forces(theta, g, float(r.psi_star[0]), 1.0, MULTIPLIER)
    psi = pins.pin_phase(np.arange(g.z2)[:, None], theta[None, :], g.z2, MULTIPLIER)
    P = pins.contact_loss_power(F, np.abs(pins.pitch_distance(psi, g) - g.R_b), 1.0)
    for got, dense in ((r.force[0], F.max()), (r.loss[0], P.max()), (r.total[0], P.sum(axis=0).max())):
        assert dense <= got * (1 + 1e-12) and got <= dense * (1 + 1e-6)


def test_one_gears_admissibility_is_remembered_and_handed_out_as_copies():
    # pins.md §4.2, §12.10: loading a design checks it and its solve asks again; the second answer comes from the
    # remembered first, equal to a fresh computation (the many-gear path) and not shared with the caller
    from gearcalc.pins import ideal

    g = Cycloid.from_curtate_ratio(20, 22, 3.9, 0.75, 1.95)
    one = Cycloid(*(np.atleast_1d(v) for v in (g.z1, g.z2, g.e, g.R_p, g.R_b, g.one_minus_K1)))
    ideal._ADMISSIBLE_ONE.clear()
    first = ideal.admissibility(one)
    first[1][0] = -1.0                                   # the caller's copy: the remembered value stays
    again = ideal.admissibility(one)
    fresh = ideal._admissibility(one)
    assert len(ideal._ADMISSIBLE_ONE) == 1
    assert all(np.array_equal(a, b) for a, b in zip(again, fresh)) and again[1][0] > 0.0
    two = Cycloid(*(np.repeat(np.atleast_1d(v), 2) for v in (g.z1, g.z2, g.e, g.R_p, g.R_b, g.one_minus_K1)))
    assert np.array_equal(ideal.admissibility(two)[1], np.repeat(fresh[1], 2))


# ---------------------------------------------------------------- the cycle mean and admissibility (pins.md §4.2, §4.8)

@settings(max_examples=25, deadline=None)
@given(z1=st.integers(8, 60), k=st.integers(1, 3), K1=st.floats(0.3, 0.9), mu=st.floats(1e-3, 0.5))
def test_the_cycle_mean_is_proportional_to_mu_and_zero_without_friction(z1, k, K1, mu):
    # pins.md §4.8: lambda(theta) = mu times a function of the geometry alone, so its cycle mean too; f = 0: exactly 0
    g = Cycloid.from_curtate_ratio(z1, z1 + k, 2.0, K1, 0.2 * 2.0 * (z1 + k) / (k * K1) * np.sin(np.pi / (z1 + k)))
    ps = pins.crest_cutoff(g)
    if ps <= g.period or g.R_b >= pins.min_curvature_radius(g, ps):
        return                                          # inadmissible: refused before any cycle (pins.md §4.2)
    p0 = pins.spin_reversal_phase(g)
    one = pins.mean_loss_ratio(g, ps, p0, mu, tol=1e-8)
    two = pins.mean_loss_ratio(g, ps, p0, 2 * mu, tol=1e-8)
    assert two.loss_ratio == pytest.approx(2 * one.loss_ratio, rel=1e-12)
    assert pins.mean_loss_ratio(g, ps, p0, 0.0, tol=1e-8).loss_ratio == 0.0


def test_too_few_teeth_is_the_loaded_arc_against_the_pin_pitch():
    # pins.md §4.2 and the guards' case: z1 = 2, z2 = 4 (k = 2), K1 = 0.5, e = 1, R_b = 2.5: psi* <= 360/z2 = 90 deg
    # (the paper gear z1 = 20, z2 = 22 passes: psi* = 116.2 deg > 360/22 = 16.4 deg)
    bad = Cycloid.from_curtate_ratio(2, 4, 1.0, 0.5, 2.5)
    ok = Cycloid.from_curtate_ratio(20, 22, 3.9, 0.75, 1.95)
    assert pins.crest_cutoff(bad) <= 2 * np.pi / 4 and pins.crest_cutoff(ok) > 2 * np.pi / 22
    status = pins.admissibility(pins.geometry.as_arrays(bad))[0]
    assert status.tolist() == [pins.TOO_FEW_TEETH]
    assert pins.admissibility(pins.geometry.as_arrays(ok))[0].tolist() == [0]
