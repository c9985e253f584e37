"""Tests of the output mechanism's, the drag's and the friction law's design keys and their cross-key rules
(gearcalc.pins.output_keys; pins.md §4.10).

Independent references: the rules of pins.md §4.10 (the hole circle must hold n_w holes of radius r_w + e and fit
inside R_p - R_b - e; the table law's lists of equal length, increasing speeds; a speed law only on fixed pins; the
mechanism at the ideal level only), each refused naming its key.
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


def test_the_contact_level_refuses_the_mechanism():
    from gearcalc import InputError
    d = _with(output=W8, contact={"law": "linear", "stiffness_N_per_mm": 1e6})
    with pytest.raises(InputError, match=r"output\.mechanism.*contact level"):
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
