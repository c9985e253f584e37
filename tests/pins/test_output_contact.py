"""Tests of the contact level's output mechanism and drag driver (gearcalc.pins.output_contact; pins.md §4.10).

Its runs through the keys: tests/pins/test_output_mech.py (the contact level's tests at its end).  Independent
references: lambda_W = 4 f_w e (u + 1)/(pi R_w) of the classical W-mechanism analysis (even n_w); the drag's power
balance at the crank worked by hand.
"""
import math
from types import SimpleNamespace as NS

import pytest

from gearcalc.pins.output_contact import ContactW, contact_output_fields, contact_w

A = dict(w_mech="pins_in_holes", w_holes=8, w_radius=35.0, w_friction=None, drag=None, e=3.9, sliding=0.1,
         mode="multiplier", shaft="H", torque=100.0, speed=None)


def test_contact_w_defaults_to_the_ideal_mechanism_and_the_given_torque():
    w = contact_w({**A, "w_mech": None}, 10.0)
    assert w == ContactW("ideal", 0.0, 0.0, None, 100.0) and not w.active


def test_contact_w_takes_friction_sliding_as_f_w_and_adds_the_drag_on_H():
    w = contact_w({**A, "drag": 2.0}, 10.0)
    assert w.loss_ratio == pytest.approx(4 * 0.1 * 3.9 * 11 / (math.pi * 35.0), rel=1e-12)
    assert w.teeth_torque == 102.0 and w.active           # the multiplier's teeth deliver T_H + T_d


def test_a_drag_that_locks_the_multiplier_is_a_failed_check():
    # eta_VH - u T_d/T_V = 0.75 - 10 x 10/100 < 0: below the start-up torque u T_d/eta_VH = 133.3 N·m
    cl = NS(locked={True: False, False: False}, et_reducer=NS(eta_hv=[0.8]), et_multiplier=NS(eta_vh=[0.75]))
    a = {**A, "shaft": "V"}
    f, failed = contact_output_fields(ContactW("ideal", 0.0, 10.0, None, 100.0), {"self_locking": False}, cl, a,
                                      10.0, 1)
    assert f["self_locking"] is True and f["efficiency"] is None and f["torque_in_Nm"] is None
    assert f["backdrive_startup_torque_Nm"] == pytest.approx(10 * 10 / 0.75, rel=1e-14)
    assert len(failed) == 1 and "start-up torque" in failed[0]


@pytest.mark.parametrize("shaft", ["H", "V"])
def test_a_mechanism_that_locks_the_multiplier_leaves_the_teeth_at_the_given_torque(shaft):
    # lambda_W = 4 f_w e (u + 1)/(pi R_w) = 4 x 0.9 x 3.9 x 11/(35 pi) = 1.40 >= 1: eta_VH (1 - lambda_W) < 0, the
    # satellite gets no positive torque (before: the teeth were asked for T_V (1 - lambda_W) < 0)
    w = contact_w({**A, "w_friction": 0.9, "shaft": shaft}, 10.0)
    assert w.loss_ratio > 1.0 and w.teeth_torque == 100.0
    cl = NS(locked={True: False, False: False}, et_reducer=NS(eta_hv=[0.8]), et_multiplier=NS(eta_vh=[0.75]),
            crank=NS(bearing_radial=[1.0], bearing_tangential=[1.0], mean_weights=None))
    f, failed = contact_output_fields(w, {"self_locking": False}, cl, {**A, "shaft": shaft}, 10.0, 1)
    assert f["self_locking"] is True and f["w_force_max_N"] is None and "bearing_force_max_N" not in f
    assert len(failed) == 1 and "loss ratio 1.40" in failed[0]
