"""Tests of the output mechanism's, the drag's and the friction law's design keys and their cross-key rules
(gearcalc.pins.output_keys; pins.md §4.10).

Independent references: the rules of pins.md §4.10 (the hole circle must hold n_w holes of radius r_w + e and fit
inside R_p - R_b - e; the table law's lists of equal length, increasing speeds; a speed law only on fixed pins, at
the ideal and contact levels, with a crank speed; a reducer's input torque above the crank's drag), each refused
naming its key.
"""
import pytest

from pins.test_output_mech import W8, _run, _with


@pytest.mark.parametrize("output,key", [
    ({"mechanism": "pins_in_holes", "holes": 8, "pin_radius_mm": 6.0}, "output.hole_circle_radius_mm"),
    ({**W8, "hole_circle_radius_mm": 12.0}, "output.hole_circle_radius_mm"),       # 8 holes of 9.9 mm overlap
    ({**W8, "hole_circle_radius_mm": 45.0}, "output.hole_circle_radius_mm"),       # past R_p - R_b - e = 51.35
])
def test_bad_output_keys_name_the_key(output, key):
    from gearcalc import InputError
    with pytest.raises(InputError, match=key.replace(".", r"\.")):
        _run(_with(output=output))


def test_the_contact_level_takes_a_speed_dependent_law_and_the_mechanism():
    # pins.md §4.10: the contact level reads the law at its sliding speeds times the crank speed (issue 37 item 4;
    # it refused the law before); its results: tests/pins/test_contact_level.py
    law = {"law": "table", "table_speed_m_s": [0.0, 1.0], "table_mu": [0.1, 0.1]}
    s = _run(_with(friction=law, output=W8, contact={"law": "linear", "stiffness_N_per_mm": 1e6}))
    assert s["model"] == "contact" and s["output_mechanism"] == "pins_in_holes"


@pytest.mark.parametrize("contact", [None, {"law": "linear", "stiffness_N_per_mm": 1e6}])
def test_a_drag_that_takes_the_whole_reducer_input_is_refused_at_both_levels(contact):
    # the teeth would carry T_H - T_d <= 0 (pins.md §4.10); before: negative output torques at the ideal level
    from gearcalc import InputError
    d = _with(load={"mode": "reducer", "torque_Nm": 2.0, "drag_torque_Nm": 2.0}, **({"contact": contact} if contact
                                                                                      else {}))
    with pytest.raises(InputError, match=r"load\.drag_torque_Nm.*all of the reducer's input"):
        _run(d)


@pytest.mark.parametrize("friction,gearing,load,key", [
    ({"law": "table", "table_speed_m_s": [0.0, 1.0], "table_mu": [0.1]}, {}, {}, "friction.table_mu"),
    ({"law": "table", "table_speed_m_s": [1.0, 1.0], "table_mu": [0.1, 0.1]}, {}, {}, "friction.table_speed_m_s"),
    ({"law": "stribeck", "stribeck_static": 0.1, "stribeck_coulomb": 0.05}, {}, {}, "friction.stribeck_speed_m_s"),
    ({"law": "table", "table_speed_m_s": [0.0, 1.0], "table_mu": [0.1, 0.1]}, {"rotating_pins": True}, {},
     "friction.law"),
])
def test_bad_law_keys_name_the_key(friction, gearing, load, key):
    from gearcalc import InputError
    with pytest.raises(InputError, match=key.replace(".", r"\.")):
        _run(_with(friction=friction, gearing=gearing, load=load))
