"""Tests of the design keys of the ``pins`` calculator (gearcalc.pins.schema; pins.md §7, §9): their bounds and the
levels' cost budgets, each refused with exit 2 naming the key (issue 13, the compute side).

Each test says where its expected numbers come from (the schema's bounds and budgets re-derived by hand).
"""
import pytest

from conftest import CONFIGS, cli
from gearcalc.kinds import pins as kp
from gearcalc.units import MAX_TEETH

PINS = CONFIGS / "pins_paper_cyc_u10_rotating.toml"
CIRC = CONFIGS / "pins_paper_circ_u10_fixed.toml"


@pytest.mark.parametrize("z1,z2", [(2 ** 53 + 1, 2 ** 53 + 3), (10 ** 6, 10 ** 6 + 2), (MAX_TEETH, MAX_TEETH + 1)])
def test_tooth_counts_beyond_the_bound_are_refused(z1, z2):
    # 2^53 + 1: the first integer a double cannot hold (z2 - z1 rounded to 0: exit 70 before); 1e6: 24 s and
    # 3.9 GB before; MAX_TEETH + 1 pins: one past the schema's bound (units.MAX_TEETH = 10 000)
    for cmd in ("check", "pins"):
        r = cli(cmd, PINS, "--set", f"gearing.satellite_teeth={z1}", "--set", f"gearing.pins={z2}")
        assert r.code == 2, r
        assert "gearing.pins" in r.err and "10000" in r.err


def test_a_tiny_curtate_ratio_is_refused():
    # K1 = 5e-324 gives R_p = e z2/(k K1) = inf (exit 70 before, found by a seeded hostile run): refused with
    # the pin circle's range [MIN_LENGTH_MM, MAX_LENGTH_MM]
    for cmd in ("check", "pins"):
        r = cli(cmd, PINS, "--set", "gearing.curtate_ratio=5e-324")
        assert r.code == 2 and "gearing.curtate_ratio" in r.err, r


def test_the_largest_accepted_tooth_count_computes():
    # z2 = MAX_TEETH with k = 2 and R_b small enough for 10 000 pins (R_p sin(pi/z2) ~ 0.03 mm at R_p ~ 97 mm)
    r = cli("pins", PINS, "--set", f"gearing.satellite_teeth={MAX_TEETH - 2}", "--set", f"gearing.pins={MAX_TEETH}",
            "--set", "gearing.eccentricity_mm=0.01", "--set", "gearing.pin_radius_mm=0.01",
            "--set", "gearing.axle_radius_mm=0.005", "--format", "json")
    assert r.code in (0, 1), r


def test_ideal_cost_guard_names_pins_and_discs():
    # 10 000 pins x 64 discs = 640 000 pin-discs > IDEAL_WORK_MAX = 200 000 (pins/schema.py: ~35 us each)
    sets = ["--set", "gearing.satellite_teeth=9998", "--set", "gearing.pins=10000", "--set", "gearing.discs=64"]
    for cmd in ("check", "pins"):
        r = cli(cmd, PINS, *sets)
        assert r.code == 2, r
        assert "gearing.discs" in r.err and "640000" in r.err and str(kp.IDEAL_WORK_MAX) in r.err


def test_contact_cost_guard_names_pins():
    # the case: a contact-level design with z1 = 2000 ran past 60 s.  The budget allows
    # CONTACT_WORK_MAX // (CONTACT_NODES_MAX * 3) = 114 pins with the torque on H
    limit = kp.CONTACT_WORK_MAX // (kp.CONTACT_NODES_MAX * 3)
    assert limit == 114
    for cmd in ("check", "pins"):
        r = cli(cmd, CIRC, "--set", "gearing.satellite_teeth=2000", "--set", "gearing.pins=2002",
                "--set", "gearing.pin_circle_radius_mm=5720.0")
        assert r.code == 2, r
        assert "gearing.pins" in r.err and "contact level" in r.err and f"at most {limit} pins" in r.err
