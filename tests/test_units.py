"""gearcalc.units: unit suffixes of field names, the internal conversions, and the loader's unit hints.

Expected values come from the definitions of the units: 1 in = 25.4 mm exactly (international inch, 1959),
1 lbf = 0.45359237 kg x 9.80665 m/s² exactly (international pound, standard gravity), 1 psi = 1 lbf/in²,
1 rpm = 2 pi / 60 rad/s, 1° = pi / 180 rad, 1 bar = 1e5 Pa.
"""
import math

import pytest

from gearcalc import units as U

LBF_N = 0.45359237 * 9.80665          # the international pound-force [N], exact by definition


@pytest.mark.parametrize("name,unit", [
    ("torque_in_Nm", "N·m"), ("sigma_max_MPa", "MPa"), ("w_mean_N_per_mm", "N/mm"), ("roller_gap_mm", "mm"),
    ("F_tr1_N", "N"), ("P_tr_W", "W"), ("model_time_ms", "ms"),
    ("efficiency", ""), ("mass_per_torque_kg_per_kNm", "kg/(kN·m)"),
])
def test_unit_of_reads_the_longest_suffix(name, unit):
    # "_N_per_mm" must win over "_mm", "_ms" over "_s"-less names, "_MPa" over nothing: the suffix table order
    assert U.unit_of(name) == unit


def test_split_unit_is_unit_of_with_the_stem():
    for name in ("w_mean_N_per_mm", "sigma_max_MPa", "efficiency", "crank_speed_rpm"):
        stem, unit = U.split_unit(name)
        assert unit == U.unit_of(name) and stem + name[len(stem):] == name
        assert (stem == name) == (unit == "")
    assert U.split_unit("w_mean_N_per_mm") == ("w_mean", "N/mm")


def test_internal_conversions_follow_the_definitions():
    assert U.nm_to_nmm(2.5) == 2500.0                                   # 1 N·m = 1000 N·mm
    assert U.deg_to_rad(180.0) == pytest.approx(math.pi, rel=1e-15)
    assert U.rad_to_deg(math.pi / 2) == pytest.approx(90.0, rel=1e-15)
    assert U.rpm_to_rad_s(60.0) == pytest.approx(2 * math.pi, rel=1e-15)  # 60 rpm = one turn per second
    assert U.rad_s_to_rpm(U.rpm_to_rad_s(1234.5)) == pytest.approx(1234.5, rel=1e-15)


@pytest.mark.parametrize("value,given,key,expected", [
    (1.0, "in", "mm", 25.4),
    (1.0, "ft", "mm", 12 * 25.4),
    (1.0, "lbf", "N", LBF_N),
    (1.0, "lbf·ft", "N·m", LBF_N * 12 * 25.4e-3),
    (1.0, "psi", "MPa", LBF_N / 25.4 ** 2),                  # lbf/in² in N/mm²
    (10.0, "bar", "MPa", 1.0),                               # 1e6 Pa
    (1.0, "rad/s", "rpm", 60 / (2 * math.pi)),
    (1.0, "rad", "°", 180 / math.pi),
    (30.0, "arcmin", "°", 0.5),
    (3.6, "km/h", "m/s", 1.0),
    (2.0, "kN·m", "N·m", 2000.0),
    (1.0, "g/cm³", "kg/m³", 1000.0),
    (1.0, "N/µm", "N/mm", 1000.0),
    (5.0, "Degrees", "°", 5.0),                              # spelled-out words: any case
])
def test_convert_hint_follows_the_unit_definitions(value, given, key, expected):
    assert U.convert_hint(value, given, key) == pytest.approx(expected, rel=1e-14)


def test_convert_hint_refuses_unknown_units_and_other_quantities():
    assert U.convert_hint(1.0, "furlong", "mm") is None
    assert U.convert_hint(1.0, "kN", "mm") is None                 # a force on a length key
    assert U.convert_hint(1.0, "mm", "") is None                   # a dimensionless key
    assert U.convert_hint(1.0, "KN", "N") is None                  # symbols are case-sensitive (MN vs mN)


def test_same_unit_is_the_keys_own_unit_however_written():
    assert U.same_unit("deg", "°") and U.same_unit("N / mm2", "MPa") and U.same_unit("N·m", "N·m")
    assert not U.same_unit("kN", "N") and not U.same_unit("rad", "°") and not U.same_unit("xyz", "mm")
