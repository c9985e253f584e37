"""Tests of the pins contact laws (gearcalc.pins.contact_law; pins.md §5.4).

Independent references: the ISO/TS 16281 roller constant (pins.md §5.4: Q = 35948 L^(8/9) delta^(10/9) for a
roller's two contacts in series), Palmgren's line contact (Harris & Kotzalas: delta = 3.84e-5 Q^0.9 / b^0.8), the
closed-form stiffness c p delta^(p-1) and central differences of the force.
"""
import numpy as np
import pytest

from gearcalc import hertz
from gearcalc.pins import contact_law as cl


def test_hertz_constant_is_the_iso_roller_constant_for_one_contact():
    # ISO/TS 16281: Q = 35948 L^(8/9) delta_roller^(10/9), the roller's two contacts in series; one contact
    # carries Q at delta_roller/2, so Q = 35948 2^(10/9) L^(8/9) delta^(10/9) (~7.77e4 b^(8/9), pins.md §5.4)
    for b in (1.0, 10.0, 37.0):
        law = cl.contact_law("hertz", face_width=b)
        delta = 1e-3
        roller_force = 35948.0 * b ** (8 / 9) * (2 * delta) ** (10 / 9)
        assert float(law.force(delta)) == pytest.approx(roller_force, rel=1e-13)
    assert hertz.iso_contact_stiffness(1.0) == pytest.approx(7.77e4, rel=1e-3)


def test_palmgren_law_inverts_palmgrens_deflection_and_agrees_within_4_percent():
    # Palmgren: delta = 3.84e-5 Q^0.9 / b^0.8 (Harris & Kotzalas); pins.md: within about 4 % of ISO
    law = cl.contact_law("palmgren", face_width=10.0)
    Q = 2500.0
    delta = 3.84e-5 * Q ** 0.9 / 10.0 ** 0.8
    assert float(law.force(delta)) == pytest.approx(Q, rel=1e-12)
    ratio = cl.palmgren_line_constant(10.0) / hertz.iso_contact_stiffness(10.0)
    assert 1.0 < ratio < 1.04


def test_laws_are_compression_only_and_linear_extension_for_one_sided_derivatives():
    lin = cl.contact_law("linear", stiffness=2e5)
    d = np.array([-1e-3, 0.0, 1e-3])
    assert lin.force(d).tolist() == [0.0, 0.0, 200.0]
    assert cl.contact_law("hertz", face_width=5.0).force(d)[:2].tolist() == [0.0, 0.0]
    assert lin.force_on(d, np.array([True, True, False])).tolist() == [-200.0, 0.0, 0.0]
    assert float(lin.deflection(200.0)) == pytest.approx(1e-3)



@pytest.mark.parametrize("name, kw", [("hertz", {"face_width": 10.0}), ("palmgren", {"face_width": 4.0}),
                                      ("linear", {"stiffness": 2e5})])
def test_force_stiffness_is_the_force_and_its_derivative(name, kw):
    # the joint evaluation of the equilibrium (one power, F' = p F/delta) against the force alone, the closed-form
    # stiffness c p delta^(p-1) (0 where delta <= 0; on a fixed set, the linear law's c below 0 too) and the
    # derivative of F by central differences (F'' bounded away from delta = 0: O(h^2) ~ 1e-10 relative)
    law = cl.contact_law(name, **kw)
    c, p = law.constant, law.exponent
    d = np.array([[-2e-3, 0.0, 1e-6], [3e-4, 2e-3, -1e-9]])
    active = np.array([[True, True, True], [False, True, True]])
    touch = d > 0.0
    closed = np.where(touch, c * p * np.where(touch, d, 1.0) ** (p - 1.0), 0.0)
    F, Fp = law.force_stiffness(d)
    np.testing.assert_allclose(F, law.force(d), rtol=1e-15, atol=0.0)
    np.testing.assert_allclose(Fp, closed, rtol=1e-14, atol=0.0)
    F, Fp = law.force_stiffness(d, active)
    np.testing.assert_allclose(F, law.force_on(d, active), rtol=1e-15, atol=0.0)
    on_set = np.where(active, c, 0.0) if p == 1.0 else np.where(active, closed, 0.0)
    np.testing.assert_allclose(Fp, on_set, rtol=1e-14, atol=0.0)
    x, h = np.array([3e-4, 2e-3]), 1e-8
    fd = (law.force(x + h) - law.force(x - h)) / (2.0 * h)
    np.testing.assert_allclose(law.force_stiffness(x)[1], fd, rtol=1e-6)


def test_contact_law_by_name_unknown_name_is_a_value_error_listing_the_known_ones():
    # issue 35: contact_law("hertzz") silently returned the Hertz law
    with pytest.raises(ValueError, match=r"unknown contact law 'hertzz'; known: hertz, palmgren, linear"):
        cl.contact_law("hertzz", face_width=10.0)
    assert set(cl.CONTACT_LAWS) == {"hertz", "palmgren", "linear"}
    for name in cl.CONTACT_LAWS:
        assert cl.contact_law(name, face_width=10.0, stiffness=1e5).name == name


def test_contact_law_problem_knows_the_same_laws_and_rejects_unknown_names():
    from gearcalc.pins import checks, schema
    assert list(checks.LAW_NEEDS) == list(cl.CONTACT_LAWS)
    law_field = next(f for t in schema.TABLES if t.name == "contact" for f in t.fields if f.name == "law")
    assert tuple(law_field.choices) == tuple(cl.CONTACT_LAWS)
    with pytest.raises(ValueError, match="unknown contact law 'hertzz'"):
        checks.contact_law_problem("hertzz", 10.0, None)
