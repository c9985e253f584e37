"""Tests of a torque pass from the last pass's nodes (gearcalc/pins/contact_relinearise.py; pins.md §6(6), §7).

References: at the last pass's own torque the change is 0 by construction (the pass must return the last mean, to
the equilibria's own accuracy);
a cycle of a Gauss-Kronrod rule keeps no final-grid record (no pass); the full pass at the new torque (its mean
within the two stated errors).
"""
import numpy as np

from gearcalc.pins import contact as pc
from gearcalc.pins import contact_relinearise as pcl
from gearcalc.pins import MULTIPLIER, Cycloid


def models(*torques):
    g = Cycloid.from_curtate_ratio(20, 22, 3.9, 0.75, 1.95)
    law, prof = pc.contact_law("hertz", face_width=10.0), pc.CycloidProfile(g, 0.0, 0.0)
    return [pc.ContactModel(g, prof, law, t, MULTIPLIER) for t in torques]


def test_a_pass_at_the_same_torque_returns_the_last_mean():
    a, b = models(1.0e6, 1.0e6)
    first = pc.mean_loss_ratio(a, (0.1, 0.1, False), tol=1e-6)
    b.inherit(a)
    same = pcl.relinearised_cycle(b, first, a, 1e-6)
    assert same is not None
    # the nodes solved again: their equilibria to 1/100 of the tolerance (settings.inner_share), the mean as close
    assert abs(same.loss_ratio - first.loss_ratio) <= pc.DEFAULT_SETTINGS.inner_share * 1e-6 * first.loss_ratio
    assert np.array_equal(same.breakpoints, first.breakpoints)


def test_a_pass_at_a_nearby_torque_meets_the_full_pass_within_the_errors():
    a, b, c = models(1.0e6, 1.0e6 * (1.0 + 2e-5), 1.0e6 * (1.0 + 2e-5))
    first = pc.mean_loss_ratio(a, (0.1, 0.1, False), tol=1e-6)
    b.inherit(a)
    lite = pcl.relinearised_cycle(b, first, a, 1e-6)
    full = pc.mean_loss_ratio(c, (0.1, 0.1, False), tol=1e-6)
    assert lite is not None and lite.loss_ratio_err > 0.0
    assert abs(lite.loss_ratio - full.loss_ratio) <= lite.loss_ratio_err + full.loss_ratio_err


def test_no_pass_from_a_gauss_kronrod_cycle():
    a, b = models(1.0e6, 1.0e6 * (1.0 + 1e-6))
    first = pc.mean_loss_ratio(a, (0.1, 0.1, False), tol=1e-6, rule="gk7")
    b.inherit(a)
    assert first.nodes is None and pcl.relinearised_cycle(b, first, a, 1e-6) is None


def test_strip_sides_of_a_sliding_direction_and_a_linear_law_count_both():
    flips = np.array([[True]])
    step = np.array([[1e-6, 1e-6]])
    left, right = pcl._strip_sides(flips, step, np.array([[0.5]]), 0, True)     # not a penetration (n_delta 0)
    assert left.tolist() == right.tolist() == [1.0]
    left, right = pcl._strip_sides(flips, step, np.array([[-1e-4]]), 1, False)  # a linear law
    assert left.tolist() == right.tolist() == [1.0]
