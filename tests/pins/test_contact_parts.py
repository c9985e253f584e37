"""Tests of the parts of a contact model (gearcalc.pins.contact_parts; pins.md §5.1, §5.5; issue 35 item 1): the
immutable set-up, the solver state and the errors of a design without equilibrium.

Independent references: the sign convention of pins.md §5.5 (the required moment M_req = -T_sat in the reducer,
+T_sat in the multiplier); the API's rule that bad input is a ValueError (interface.md).
"""
import dataclasses

import pytest

from gearcalc.pins import MULTIPLIER, REDUCER, Cycloid
from gearcalc.pins import contact as pc
from gearcalc.pins.contact_parts import ContactSetup, Jam, NoEquilibrium
from gearcalc.pins.contact_settings import DEFAULT_SETTINGS
from gearcalc.pins.friction import PinFriction

G = Cycloid.from_curtate_ratio(20, 22, 3.9, 0.75, 1.95)


@pytest.mark.parametrize("sigma,sign", [(REDUCER, -1.0), (MULTIPLIER, 1.0)])
def test_the_required_moment_is_signed_by_the_mode(sigma, sign):
    s = ContactSetup(G, pc.CycloidProfile(G), pc.ContactLaw("linear", 1e7, 1.0), 12345, sigma)
    assert s.torque_sat == 12345.0 and type(s.torque_sat) is float
    assert s.M_req == sign * 12345.0
    assert s.pins.ravel().tolist() == list(range(22)) and s.settings is DEFAULT_SETTINGS
    with pytest.raises(dataclasses.FrozenInstanceError):
        s.torque_sat = 1.0


def test_a_friction_tuple_becomes_a_pin_friction_and_the_model_reads_its_setup():
    law = pc.ContactLaw("linear", 1e7, 1.0)
    m = pc.ContactModel(G, pc.CycloidProfile(G), law, 1e5, MULTIPLIER, (0.1, 0.1, False))
    assert isinstance(m.friction, PinFriction) and m.setup.friction is m.friction
    assert (m.g, m.law, m.sigma, m.M_req) == (G, law, MULTIPLIER, 1e5)
    with pytest.raises(AttributeError):
        m.g = G                                   # the set-up is read-only through the model
    m.window = None                               # the solver's state is the model's to change
    assert m.solver.window is None


def test_no_equilibrium_and_a_jam_are_value_errors():
    # interface.md: bad input reaches the API user as a ValueError; a jam is a case of no equilibrium
    assert issubclass(NoEquilibrium, ValueError) and issubclass(Jam, NoEquilibrium)
