"""Tests of the contact level's candidate window (gearcalc.pins.contact_window; pins.md §5.5): which pins (and which
of their contacts) the equilibrium may load, chosen once from a scan and carried from one torque to another.

Independent references: a fresh solve (no warm start, its own window) at the same torque; the mean loss ratio of a
window of every pin (the window changes which pins are tried, never the equilibrium).
"""
import pytest

from gearcalc.pins import MULTIPLIER, REDUCER, Cycloid
from gearcalc.pins import contact as pc

from pins.test_contact import circ_u10, circular_model


def _u30_k1():
    g = Cycloid.from_pin_circle(60, 61, 1.95, 161.2, 2.5)
    rho, R_t = pc.full_tooth(g)
    return g, pc.CircularProfile(g, rho, R_t), pc.contact_law("hertz", face_width=10.0)


def test_window_inherited_from_a_lower_torque_holds_the_pins_that_touch_at_the_higher_one():
    # the candidate window depends on the tau range; carried to a 5x higher torque its range is scaled, and its
    # pins must be recomputed for that range: the cycle then equals a fresh solve at that torque
    g, prof, law = _u30_k1()
    low = pc.ContactModel(g, prof, law, 6.0e6, MULTIPLIER)
    low.set_window()
    high = pc.ContactModel(g, prof, law, 3.0e7, MULTIPLIER)
    high.inherit(low)
    fresh = pc.ContactModel(g, prof, law, 3.0e7, MULTIPLIER)
    a = pc.mean_loss_ratio(high, (1.0, 1.0, False), tol=1e-6)
    b = pc.mean_loss_ratio(fresh, (1.0, 1.0, False), tol=1e-6)
    assert abs(a.loss_ratio - b.loss_ratio) <= a.loss_ratio_err + b.loss_ratio_err
    assert high.window is None or high.window[2] >= low.window[2]


@pytest.mark.parametrize("sigma", [MULTIPLIER, REDUCER])
def test_candidate_window_changes_nothing(sigma):
    # the prefilter evaluates only the pins that can touch; every other pin stays unloaded (pins.md §5.5)
    a = pc.mean_loss_ratio(circular_model(sigma=sigma), (0.1, 0.1, False), tol=1e-6)
    b = pc.mean_loss_ratio(circular_model(sigma=sigma), (0.1, 0.1, False), tol=1e-6, grid=pc.CycleGrid(prefilter=False))
    assert a.sol.cand is not None and a.sol.cand.sum(axis=0).max() < circ_u10().z2
    # the states hold the window's pins over the period only (Solution.rows); the others carry no force
    assert a.sol.rows is not None and a.sol.force.shape[1] == a.sol.rows.size < circ_u10().z2
    assert b.sol.rows is None and b.sol.force.shape[1] == circ_u10().z2
    assert abs(a.loss_ratio - b.loss_ratio) <= 1e-3 * a.loss_ratio_err   # round-off of the solve paths only
    assert a.sol.force.max() == pytest.approx(b.sol.force.max(), rel=1e-10)
