"""pins/report.py holds words: the stress computations and the design's keys of the contact summary are the
adapter's (kinds/pins.py), issue 35 item 2."""
import inspect

from gearcalc.pins import report


def test_pins_report_computes_no_stress():
    source = inspect.getsource(report)
    for physics in ("contact_stress(", "axle_pressure(", "STEEL_E_STAR_MPA"):
        assert physics not in source, physics


def test_contact_fields_take_values_not_the_design():
    assert "design" not in inspect.signature(report.contact_fields).parameters


def test_the_ideal_fields_are_chosen_by_the_physics_not_the_report():
    # the friction-consistent values replacing the first-order ones, scaled peaks: gearcalc.pins.columns
    assert not hasattr(report, "ideal_fields")
