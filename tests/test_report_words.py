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


def test_the_report_reads_no_design():
    # issue 35 item 2: the message helpers take numbers; the design's keys are the adapter's (kinds/pins.py)
    for name, fn in inspect.getmembers(report, inspect.isfunction):
        if fn.__module__ == report.__name__:
            assert "design" not in inspect.signature(fn).parameters, name
    source = inspect.getsource(report)
    for read in ("design[", "design.get(", ".is_given(", ".has("):
        assert read not in source, read


def test_the_report_calls_no_physics():
    # issue 35 item 2: the rules and quantities are computed by gearcalc.pins.checks and the physics modules
    source = inspect.getsource(report)
    for physics in ("deflection_sized", "pin_travel", "bearing_life", "over_budget(", "contact_passes("):
        assert physics not in source, physics


def test_one_number_format_for_messages_and_cells():
    # issue 35: the report's fmt duplicated render.fmt_value's 6 significant digits; now both use fmt_number
    from gearcalc import render

    assert report.fmt is render.fmt_number
    for x in (57.199999999999996, 1.4909365e-16, 0.75, 1e300):
        assert render.fmt_value(x) == render.fmt_number(x) == format(x, ".6g")
