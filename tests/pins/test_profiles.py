"""Tests of the satellite tooth profiles by name (gearcalc.pins.profiles; pins.md §5.2-5.3, §7; issue 35 item 1).

Independent references: the registry's own choices against the schema's key ``gearing.profile``; the closed-form
limit of a circular tooth, R_b + rho_t < R_p - e (a zero-backlash tooth circle of radius >= 0 must exist: pins.md
§5.3), against the circular profile's factory; a ValueError naming the known profiles for an unknown one.
"""
import pytest

from gearcalc.pins import Cycloid
from gearcalc.pins import contact_profiles as cp
from gearcalc.pins import profiles


def test_unknown_profile_names_are_value_errors_listing_the_known_ones():
    assert profiles.profile_entry("cycloidal").ideal and not profiles.profile_entry("circular").ideal
    for bad in ("involute", "", None, ["circular"]):
        with pytest.raises(ValueError, match=r"unknown tooth profile .*; known: cycloidal, circular"):
            profiles.profile_entry(bad)


@pytest.mark.parametrize("rho_t", [40.0, 50.5, 50.54, 50.56, 50.6, 60.0])
def test_a_circular_tooth_is_too_large_exactly_where_the_factory_refuses_it(rho_t):
    # the paper's u = 10 circular-arc gear (configs/pins_paper_circ_u10_fixed.toml): R_p = 57.2, e = 3.9, R_b = 2.75,
    # so rho_t < R_p - e - R_b = 50.55 mm fits a tooth circle (by hand)
    g = Cycloid.from_pin_circle(20, 22, 3.9, 57.2, 2.75)
    too_large = profiles.tooth_too_large(2.75, rho_t, 57.2, 3.9)
    assert too_large == (rho_t >= 57.2 - 3.9 - 2.75)
    if too_large:
        with pytest.raises(cp.InadmissibleProfile):
            profiles.make_profile("circular", g, profiles.ProfileParams(tooth_radius=rho_t))
    else:
        prof, _ = profiles.make_profile("circular", g, profiles.ProfileParams(tooth_radius=rho_t))
        fields = prof.summary_fields()
        assert fields["tooth_radius_mm"] == rho_t and fields["tooth_circle_radius_mm"] >= 0.0


def test_profiles_by_name_behind_one_protocol():
    # issue 35 item 1: tooth profiles chosen by name from a registry, one documented Protocol
    from gearcalc.pins import profiles, schema
    from gearcalc.pins.geometry import Cycloid
    g = Cycloid.from_curtate_ratio(20, 22, 3.9, 0.75, 1.95)
    for name in profiles.PROFILES:
        prof, overlap = profiles.make_profile(name, g)
        assert isinstance(prof, profiles.ToothProfile) and overlap is False and prof.play_free
    assert profiles.make_profile("circular", g)[0].summary_fields().keys() == {"tooth_radius_mm",
                                                                              "tooth_circle_radius_mm"}
    assert not profiles.make_profile("cycloidal", g, profiles.ProfileParams(equidistant_mod=0.01))[0].play_free
    with pytest.raises(ValueError, match=r"unknown tooth profile 'involute'; known: cycloidal, circular"):
        profiles.make_profile("involute", g)
    gearing = next(t for t in schema.TABLES if t.name == "gearing")
    assert tuple(next(f for f in gearing.fields if f.name == "profile").choices) == tuple(profiles.PROFILES)


def test_a_new_profile_is_a_module_plus_its_registration(monkeypatch):
    # the registry entry names the module and factory; nothing else changes to compute with it
    from gearcalc.pins import profiles
    from gearcalc.pins.contact_level import satellite_profile
    from gearcalc.pins.geometry import Cycloid
    monkeypatch.setitem(profiles.PROFILES, "arcs", profiles.ProfileEntry("gearcalc.pins.contact_profiles",
                                                                         "circular_teeth"))
    g = Cycloid.from_curtate_ratio(20, 22, 3.9, 0.75, 1.95)
    prof, _ = satellite_profile(g, "arcs", 3.0, "zero_backlash", 0.0, 0.0)
    assert prof.contacts_per_pin == 2 and prof.rho_t == 3.0
