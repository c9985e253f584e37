"""Tests of the ideal level's cycle model solved for many gears at once (gearcalc.pins.ideal; pins.md §4, §6, §9).

Independent references: the disc sums' budget re-derived by hand; the closed-form loss ratio of one loaded pin
(pins.md §4.6) and the friction-free limit; the admissibility rules of pins.md §4.2 (the loaded arc psi* against
the pin pitch 360/z2).
"""
import time


from conftest import CONFIGS, cli

PINS = CONFIGS / "pins_paper_cyc_u10_rotating.toml"


def test_disc_sum_guard_names_discs_and_tol():
    # 100 pins x 64 discs at --tol 1e-9 took 11 s (n_d^2 x loaded samples = 2.5e8 > pins.DISC_WORK_MAX = 2e8);
    # at 1e-12, 9.5 minutes.  Known only after the quadrature (the grid follows from --tol): run refuses it
    sets = ["--set", "gearing.satellite_teeth=98", "--set", "gearing.pins=100", "--set", "gearing.discs=64"]
    t = time.perf_counter()
    for tol in ("1e-9", "1e-12"):
        r = cli("pins", PINS, *sets, "--tol", tol)
        assert r.code == 2, r
        assert "gearing.discs" in r.err and f"--tol {tol.replace('e-9', 'e-09')}" in r.err
    assert time.perf_counter() - t < 10
    assert cli("pins", PINS, *sets, "--format", "json").code in (0, 1)      # the default --tol: 0.3 s
