"""Tests of the contact level's moved breakpoints and their check on the quadrature's nodes (pins.md §6, issue 15).

A later pass of the torque fixed point, and the other mode of a design, move the last cycle's sign changes by Newton
instead of scanning one period again; the quadrature's nodes then confirm that no contact appeared or vanished.
Independent references: the full 256-interval scan of the same model (the located roots must agree to the
refinement's 1e-12 T_p), and the cycle computed from that scan (the loss ratio must agree within its error).
"""
import dataclasses
import tomllib
from pathlib import Path

import numpy as np
import pytest

from gearcalc.pins import contact as pc
from gearcalc.pins import contact_cycle as pcc
from gearcalc.pins import contact_relinearise as pcl
from gearcalc.pins import contact_roots as pcr
from gearcalc.pins import contact_model as pcm
from gearcalc.pins import contact_states as pcs
from gearcalc.pins import MULTIPLIER, REDUCER, Cycloid


def cycloid_model(T_sat, sigma=MULTIPLIER, friction=None, settings=None):
    # the paper's u = 10 cycloid (k = 2, K1 = 0.75), Hertz contacts of 10 mm
    g = Cycloid.from_curtate_ratio(20, 22, 3.9, 0.75, 1.95)
    return pc.ContactModel(g, pc.CycloidProfile(g, 0.0, 0.0), pc.contact_law("hertz", face_width=10.0), T_sat,
                           sigma, friction, settings)


def circular_model(T_sat, sigma=MULTIPLIER, friction=None, settings=None):
    g = Cycloid.from_pin_circle(20, 22, 3.9, 57.2, 2.75)
    rho, R_t = pc.full_tooth(g)
    return pc.ContactModel(g, pc.CircularProfile(g, rho, R_t), pc.contact_law("hertz", face_width=10.0), T_sat,
                           sigma, friction, settings)


@pytest.mark.parametrize("make", [cycloid_model, circular_model])
def test_moved_roots_are_the_scanned_roots_of_the_new_torque(make):
    tol = 1e-6
    a = make(1.0e6)
    a.set_window()
    prior = pcr._scan_roots(a, 256, tol, False)
    b = make(1.0e6 * (1.0 + 3e-5))              # the next pass: a torque a few 1e-5 away
    b.inherit(a)
    moved = pcr._incremental_roots(b, prior, 3e-5 * b.g.period, tol, False, 0.125 * b.g.period)
    full = pcr._scan_roots(b, 256, tol, False)
    assert moved is not None and not moved.scanned
    assert moved.roots.size == full.roots.size > 0
    assert np.max(np.abs(moved.roots - full.roots)) <= 4e-12 * b.g.period
    assert np.array_equal(moved.contact, full.contact)


@pytest.mark.parametrize("make, friction", [(circular_model, None), (circular_model, (0.1, 0.1, False)),
                                             (cycloid_model, (0.1, 0.1, False))])
def test_scan_roots_refined_from_the_smooth_side_take_fewer_calls_to_the_same_roots(make, friction, monkeypatch):
    # the contact entries and exits of the u = 10 paper geometries on the product's 64-interval scan (pins.md §6):
    # started from the cubic through the two scan points below zero, the refinement takes fewer calls than from the
    # scan's linear interpolation (the reference: _smooth_side_start switched off) and meets the roots of a refinement
    # run to steps of 1e-15 T_p with every solve stopped at steps of 1e-13 |tau| (the independent reference) as
    # closely as that one does: within 1e-11 T_p (measured: 3.1e-14..1.1e-12 T_p, the linear start 2.8e-14..1.4e-12)
    tol = 1e-6
    calls = []
    state = pc.ContactModel.state

    def counted(self, theta, *args, **kwargs):
        calls.append(np.size(theta))
        return state(self, theta, *args, **kwargs)

    def roots(settings=None, smooth=True):
        m = make(1.0e6, friction=friction, settings=settings)
        m.set_window()
        calls.clear()
        found = pcr._scan_roots(m, pc.DEFAULT_SETTINGS.cycle_coarse_scan, tol, False, smooth=smooth)
        return found, len(calls), m.g.period

    monkeypatch.setattr(pc.ContactModel, "state", counted)
    smooth, n_smooth, Tp = roots()
    # the solves and the refinement read these from the model's settings
    ref = roots(dataclasses.replace(pc.DEFAULT_SETTINGS, newton_stop=1e-13, refine_newton_stop=1e-13,
                                    refine_newton_small=1e-15, root_step=1e-15, smooth_start_curvature_margin=1e-8))[0]
    linear, n_linear, _ = roots(smooth=False)            # the scan's linear interpolation only
    assert smooth.roots.size == linear.roots.size == ref.roots.size > 0
    assert np.array_equal(smooth.contact, ref.contact) and np.array_equal(linear.contact, ref.contact)
    assert np.max(np.abs(smooth.roots - ref.roots)) <= 1e-11 * Tp
    assert np.max(np.abs(linear.roots - ref.roots)) <= 1e-11 * Tp
    assert n_smooth < n_linear            # the scan's call and one or two refinement calls against three


def test_a_root_that_cannot_be_moved_falls_back_to_the_scan():
    tol = 1e-6
    a = circular_model(1.0e6)
    a.set_window()
    prior = pcr._scan_roots(a, 256, tol, False)
    # one root too many (a contact that the new model does not have): the count does not match
    extra = pc.BreakpointRoots(np.sort(np.append(prior.roots, 0.5 * (prior.roots[0] + prior.roots[1]))),
                               np.append(prior.contact, True))
    assert pcr._incremental_roots(a, extra, 1e-6 * a.g.period, tol, False, 0.125 * a.g.period) is None


def test_cycle_from_moved_roots_equals_the_scanned_cycle_within_its_error():
    tol = 1e-6
    a = cycloid_model(1.0e6)
    first = pc.mean_loss_ratio(a, (0.1, 0.1, False), tol=tol)
    b = cycloid_model(1.0e6 * (1.0 + 1e-5))
    b.inherit(a)
    moved = pc.mean_loss_ratio(b, (0.1, 0.1, False), tol=tol, prior=first.roots, prior_width=1e-5)
    assert not moved.roots.scanned                  # the moved roots held on every node
    c = cycloid_model(1.0e6 * (1.0 + 1e-5))
    c.inherit(a)
    scanned = pc.mean_loss_ratio(c, (0.1, 0.1, False), tol=tol)
    assert scanned.roots.scanned
    assert np.max(np.abs(moved.breakpoints - scanned.breakpoints)) <= 4e-12 * b.g.period
    assert abs(moved.loss_ratio - scanned.loss_ratio) <= min(moved.loss_ratio_err, scanned.loss_ratio_err)


def test_a_missed_contact_is_caught_on_the_nodes():
    # a prior without the contact entries and exits (only the period's ends): the moved set is empty and the nodes
    # of the quadrature show the penetrations changing sign inside the single piece, so the cycle is recomputed
    # from the full scan (pins.md §6)
    tol = 1e-5
    a = circular_model(1.0e6)
    empty = pc.BreakpointRoots(np.empty(0), np.zeros(0, dtype=bool))
    cyc = pc.mean_loss_ratio(a, (0.1, 0.1, False), tol=tol, prior=empty)
    assert cyc.roots.scanned and cyc.roots.roots.size > 0
    ref = pc.mean_loss_ratio(circular_model(1.0e6), (0.1, 0.1, False), tol=tol)
    assert np.max(np.abs(cyc.breakpoints - ref.breakpoints)) <= 4e-12 * a.g.period
    assert abs(cyc.loss_ratio - ref.loss_ratio) <= min(cyc.loss_ratio_err, ref.loss_ratio_err)


def test_coarse_scan_is_confirmed_or_replaced():
    tol = 1e-6
    a = cycloid_model(1.0e6)
    coarse = pc.mean_loss_ratio(a, (0.1, 0.1, False), tol=tol, grid=pc.CycleGrid(coarse_scan=64, n_min=1))
    b = cycloid_model(1.0e6)
    full = pc.mean_loss_ratio(b, (0.1, 0.1, False), tol=tol, grid=pc.CycleGrid(n_min=1))
    assert np.max(np.abs(coarse.breakpoints - full.breakpoints)) <= 4e-12 * a.g.period
    assert abs(coarse.loss_ratio - full.loss_ratio) <= min(coarse.loss_ratio_err, full.loss_ratio_err)


def test_tiny_torque_balance_is_met_to_round_off():
    # a torque whose deflection is ~1e-8 of the satellite's rotation from nominal: the Newton solve stops at the
    # spacing of the floats, not at a fixed 1e-15 rad (pins.md §5.5), so the residual stays far below 1e-3
    a = circular_model(1.0)
    cyc = pc.mean_loss_ratio(a, (0.1, 0.1, False), tol=1e-4)
    assert np.max(np.abs(cyc.sol.residual)) / a.torque_sat < 1e-4


@pytest.mark.parametrize("make, friction, step", [(cycloid_model, None, 5e-6), (circular_model, None, 5e-6),
                                                  (circular_model, (0.1, 0.1, False), 5e-6),
                                                  (circular_model, (0.1, 0.1, False), -5e-6),
                                                  (circular_model, None, -2e-5)])
def test_pass_from_the_last_nodes_equals_the_full_pass_within_its_error(make, friction, step):
    # the next torque pass from the first pass's nodes (breakpoints not moved, pins.md §6(6)) against the full pass
    # at the same torque (moved roots, new nodes): the same loss ratio within the stated error, which holds the
    # first pass's quadrature error and the strips' bound.  Less torque moves the Hertz entries later and the exits
    # earlier, into the touching sides, whose strips hold no error (:func:`_strip_sides`): 2e-5 less is taken
    tol = 1e-6
    a = make(1.0e6, MULTIPLIER, friction)
    first = pc.mean_loss_ratio(a, (0.1, 0.1, False), tol=tol)
    T2 = 1.0e6 * (1.0 + step)                   # the paper designs' second passes: 1e-6 to 2e-5 away
    b = make(T2, MULTIPLIER, friction)
    b.inherit(a)
    lite = pc.relinearised_cycle(b, first, a, tol)
    assert lite is not None
    c = make(T2, MULTIPLIER, friction)
    c.inherit(a)
    full = pc.mean_loss_ratio(c, (0.1, 0.1, False), tol=tol, prior=first.roots, prior_width=5e-6)
    assert abs(lite.loss_ratio - full.loss_ratio) <= lite.loss_ratio_err + full.loss_ratio_err
    assert lite.loss_ratio_err >= first.loss_ratio_err * first.friction[4] / lite.friction[4]
    assert lite.loss_ratio != first.loss_ratio                  # the torque's own change, not the old value
    assert np.max(np.abs(lite.sol.residual)) / b.torque_sat < 0.01 * tol
    assert np.array_equal(lite.sol.theta, first.sol.theta)


@pytest.mark.parametrize("friction", [None, (0.1, 0.1, False)])
def test_strips_a_hertz_entry_moved_out_of_are_integrated(friction):
    # 2e-5 more torque moves the circular-arc design's Hertz entries earlier and its exits later, out of the touching
    # sides: each strip's integral, e_r d/(1 + p) from the two sides' states at the old place (pins.md §6(6)), joins
    # the value; the pass is taken (refused when those strips were only bounded) and meets the full pass at 1/100 of
    # the tolerance within 5 % of its stated error (0.3-0.7 % measured; without the strips' integral 19-29 %, with its
    # sign turned 38-58 %)
    tol = 1e-6
    a = circular_model(1.0e6, MULTIPLIER, friction)
    first = pc.mean_loss_ratio(a, (0.1, 0.1, False), tol=tol)
    T2 = 1.0e6 * (1.0 + 2e-5)
    b = circular_model(T2, MULTIPLIER, friction)
    b.inherit(a)
    lite = pc.relinearised_cycle(b, first, a, tol)
    assert lite is not None
    full = pc.mean_loss_ratio(circular_model(T2, MULTIPLIER, friction), (0.1, 0.1, False), tol=0.01 * tol)
    assert abs(lite.loss_ratio - full.loss_ratio) <= 0.05 * lite.loss_ratio_err


@pytest.mark.parametrize("friction", [None, (0.1, 0.1, False)])
def test_touching_sets_past_a_hertz_entry_give_the_other_sides_state(friction):
    # the premise of the strips' bound under a power law (pins.md §6(6), :func:`_strip_sides`): a piece whose pin
    # touches, solved past the zero of its penetration, holds the pin at delta < 0, where the law's extension that its
    # one-sided derivatives use has force and stiffness 0: the other side's state, speeds included, to round-off, at
    # every contact entry and exit of the cycle
    a = circular_model(1.0e6, MULTIPLIER, friction)
    cyc = pc.mean_loss_ratio(a, (0.1, 0.1, False), tol=1e-5)
    roots = cyc.roots.roots[cyc.roots.contact]
    assert roots.size >= 2
    eps = 1e-7 * a.g.period
    for r in roots:
        sets = {s: a.reference(np.array([r + s * eps])) for s in (-1, 1)}
        touching = max(sets, key=lambda s: int(np.count_nonzero(sets[s][0])))
        theta = np.array([r - 0.5 * touching * eps])             # on the side that does not touch
        own, past = (a.state(theta, sets[s], phases=False) for s in (-touching, touching))
        assert np.count_nonzero(sets[touching][0]) == np.count_nonzero(sets[-touching][0]) + 1
        # to the solver's stop (~1e-15 of tau); an extension with stiffness (a linear law's) would change d tau/d theta
        # by its share of the stiffness, and with it every sliding speed
        assert abs(past.tau[0] - own.tau[0]) <= 1e-12 * abs(own.tau[0])
        assert np.max(np.abs(past.force - own.force)) <= 1e-12 * np.max(own.force)
        assert abs(past.dtau[0] - own.dtau[0]) <= 1e-12 * abs(own.dtau[0])
        assert np.max(np.abs(past.v_t - own.v_t)) <= 1e-12 * np.max(np.abs(own.v_t))


def test_pass_from_the_last_nodes_refuses_a_far_torque():
    # 2 % more torque moves the contact entries by ~1e-3 T_p, across the nodes of their graded pieces: the strips'
    # bound exceeds the tolerance, or a node's penetration changes sign against its piece; a full pass is needed
    tol = 1e-6
    a = circular_model(1.0e6)
    first = pc.mean_loss_ratio(a, (0.1, 0.1, False), tol=tol)
    b = circular_model(1.02e6)
    b.inherit(a)
    assert pc.relinearised_cycle(b, first, a, tol) is None


def test_torque_fixed_point_with_and_without_the_pass_from_the_last_nodes(monkeypatch):
    # the paper's u = 10 circular-arc design (fixed pins, first-order and friction-consistent): the fixed point's
    # loss ratio with the second pass from the first one's nodes agrees with the full passes' within both errors
    g = Cycloid.from_pin_circle(20, 22, 3.9, 57.2, 2.75)
    rho, R_t = pc.full_tooth(g)
    prof, law = pc.CircularProfile(g, rho, R_t), pc.contact_law("hertz", face_width=10.0)
    for consistent in (False, True):
        out = {}
        for flag in (True, False):
            settings = dataclasses.replace(pc.DEFAULT_SETTINGS, cycle_relinearise=flag)
            case = pc.ContactCase(g, prof, law, 1, (0.1, 0.1, False), 100.0, False)
            out[flag] = pc.cycle_at_torque(case, True, consistent, tol=1e-6, settings=settings)
        assert out[True].settled and out[False].settled
        assert abs(out[True].loss_ratio - out[False].loss_ratio) <= out[True].loss_ratio_err + out[False].loss_ratio_err
        assert len(out[True].history) <= len(out[False].history)


def test_angles_solved_again_replace_their_inherited_warm_starts():
    # a pass at a torque 10 % away inherits the window scan's states (scaled and moved by a Newton step: off by
    # ~1e-3 of tau); solving the same angles again replaces them, so that the warm starts between them are the
    # cubic Hermite of this torque's states (pins.md §5.5): the memory keeps one state per angle
    a = circular_model(1.0e6)
    scan = a.set_window()
    b = circular_model(1.1e6)
    b.inherit(a)
    n = b._memo[0][0].size
    s = b.state(scan.theta, phases=False)
    th, tau, _ = b._memo[0]
    assert th.size == n
    assert np.array_equal(tau[np.searchsorted(th, s.theta)], s.tau)
    mid = scan.theta[:-1] + 0.5 * np.diff(scan.theta)
    c = circular_model(1.1e6)
    c.inherit(a)                                   # the inherited starts only
    new, inherited = b._guess(mid, 0), c._guess(mid, 0)
    exact = c.state(mid, phases=False).tau
    assert np.max(np.abs(new - exact)) < 0.1 * np.max(np.abs(inherited - exact))


def test_strided_nodes_keep_both_ends_and_every_stride_th():
    # pieces of 32, 8, 4 and 1 intervals at stride 8: strides 8, 2, 1, 1 (each leaves a piece at least 4 intervals,
    # the graded pieces at a Hertz entry keep all their nodes)
    counts = [33, 9, 5, 2]
    ps = np.repeat(np.arange(4), counts)
    xs = np.concatenate([p + np.linspace(0.0, 1.0, c) for p, c in enumerate(counts)])
    keep, lo, hi, t = pcl._strided(xs, ps, 8)
    kept = [np.flatnonzero(keep[ps == p]) for p in range(4)]
    assert [k.tolist() for k in kept] == [list(range(0, 33, 8)), list(range(0, 9, 2)), list(range(5)), [0, 1]]
    # every node lies between its two kept neighbours of the same piece, at the place t
    assert np.all(ps[lo] == ps) and np.all(ps[hi] == ps) and np.all(keep[lo]) and np.all(keep[hi])
    inner = ~keep
    assert np.allclose(xs[lo] + t * (xs[hi] - xs[lo]), xs) and np.all((t[inner] > 0.0) & (t[inner] < 1.0))
    # exact identity: the trapezoid integrates a linear function exactly, piece by piece
    w = pcl._trapezoid_weights(xs[keep], ps[keep])
    assert np.isclose(np.dot(w, 3.0 * xs[keep] + 1.0), sum(3.0 * (p + 0.5) + 1.0 for p in range(4)), rtol=1e-14)


def test_moved_states_are_exact_for_a_change_linear_in_theta():
    # _moved interpolates the change linearly between the kept nodes: a change linear in theta is reproduced to
    # round-off, values out of reach (-inf) stay, forces are clipped at 0 and the residual is the old one
    a = circular_model(1.0e6)
    a.set_window()                               # the pins out of the window: delta = -inf
    sol = a.state(np.linspace(0.0, a.g.period, 9), phases=False)
    kept = np.array([0, 4, 8])
    lo, hi = np.repeat([0, 1, 2], [4, 4, 1]), np.repeat([1, 2, 2], [4, 4, 1])
    t = np.array([0, 0.25, 0.5, 0.75, 0, 0.25, 0.5, 0.75, 0])
    change = 1e-3 * (1.0 + sol.theta)
    part = pcs.take_states(sol, kept)
    part.tau = part.tau + change[kept]
    on = sol.cand                                # the candidates change; the other pins keep their fill values
    part.force = part.force + np.where(on[:, kept], change[kept], 0.0)
    part.residual = part.residual + 1.0
    moved = pcl._moved(sol, part, kept, lo, hi, t)
    assert np.allclose(moved.tau, sol.tau + change, rtol=0.0, atol=1e-15)
    both = on & on[:, kept[lo]] & on[:, kept[hi]]    # a candidate at the node and at the kept nodes around it
    assert np.allclose(moved.force[:, both], (sol.force + change)[:, both], rtol=0.0, atol=1e-15 * sol.force.max())
    assert np.array_equal(moved.force[:, ~on], sol.force[:, ~on]) and np.any(both) and not np.all(on)
    assert np.array_equal(np.isinf(moved.delta), np.isinf(sol.delta)) and np.any(np.isinf(sol.delta))
    part.force = part.force - 2.0 * change[kept] - 1e9        # an interpolated fall below 0 is clipped
    assert np.all(np.delete(pcl._moved(sol, part, kept, lo, hi, t).force, kept, axis=-1) >= 0.0)
    assert np.array_equal(moved.residual[kept], part.residual)
    assert np.array_equal(np.delete(moved.residual, kept), np.delete(sol.residual, kept))


@pytest.mark.parametrize("make, friction", [(cycloid_model, None), (circular_model, (0.1, 0.1, False))])
def test_strided_pass_agrees_with_every_node_solved(make, friction):
    # the pass from the last nodes solving every 8th node of each piece (interpolating the change between them)
    # against the same pass solving every node (stride 1): the loss ratio within the strided pass's error, which
    # holds the difference's trapezoid error against every other solved node; the interpolated states within 5 %
    # of the torque's change of them of the solved ones
    tol = 1e-6
    a = make(1.0e6, MULTIPLIER, friction)
    first = pc.mean_loss_ratio(a, (0.1, 0.1, False), tol=tol)
    T2 = 1.0e6 * (1.0 + 5e-6)
    runs = {}
    for stride in (1, 8):
        b = make(T2, MULTIPLIER, friction)
        b.inherit(a)
        runs[stride] = pc.relinearised_cycle(b, first, a, tol, stride=stride)
        assert runs[stride] is not None
    one, eight = runs[1], runs[8]
    assert abs(one.loss_ratio - eight.loss_ratio) <= eight.loss_ratio_err
    assert eight.loss_ratio_err >= one.loss_ratio_err * 0.999
    assert one.loss_ratio != eight.loss_ratio                 # the interpolation is not the solve
    assert np.array_equal(one.sol.theta, eight.sol.theta)
    # farther than 1e-3 T_p from the breakpoints (closer, a contact entry's speeds change like (theta - theta_0)^(1/9)
    # with its place: within the strips E_s bounds, and at most as far off as the unmoved state)
    far = pcs.distance_to(first.roots.roots, one.sol.theta) > 1e-3 * a.g.period
    for field in ("tau", "force", "v_t"):
        solved, strided, old = (getattr(c.sol, field) for c in (one, eight, first))
        fin = np.isfinite(old)
        err, change = np.where(fin, np.abs(strided - solved), 0.0), np.where(fin, np.abs(solved - old), 0.0)
        assert np.max(err[..., far]) <= 0.05 * np.max(change[..., far])
        assert np.max(err) <= np.max(change)


def test_merged_parts_equal_the_sorted_concatenation():
    # exact identity: writing each part at its sorted places equals concatenating and sorting (stable, so equal angles
    # keep the parts' order, as the one-sided piece ends need)
    rng = np.random.default_rng(1)
    thetas = [rng.random(5), np.array([0.5, 0.25, 0.5]), rng.random(4)]
    arrays = [rng.random((2, 6, t.size)) for t in thetas]
    order = np.argsort(np.concatenate(thetas), kind="stable")
    expected = np.concatenate(arrays, axis=-1)[..., order]
    places = pcs.sorted_places(thetas)
    assert np.array_equal(pcs.merged(thetas, places, 0), np.concatenate(thetas)[order])
    assert np.array_equal(pcs.merged(arrays, places, 2), expected)


def test_states_over_the_windows_pins_are_the_states_over_all_pins():
    # Solution.rows: a state holds the pins the window can hold over the period; over all pins (over_pins) it equals
    # the same state solved without a window (every pin; the others carry no force), and states over other rows are
    # concatenated over the union of them
    a = circular_model(1.0e6)
    a.set_window()
    rows = a.layout()[0]
    assert rows is not None and rows.size < a.g.z2
    theta = np.linspace(0.0, a.g.period, 11)
    s = a.state(theta)
    assert np.array_equal(s.rows, rows) and s.force.shape[1] == s.phase.shape[0] == rows.size
    b = circular_model(1.0e6)                     # no window: every pin
    r = b.state(theta)
    full = s.over_pins(a.g.z2)
    assert r.rows is None and np.max(np.abs(full.force - r.force)) <= 1e-9 * r.force.max()
    assert np.array_equal(full.force > 0.0, r.force > 0.0)
    assert np.array_equal(a.phases(theta, rows)[0], b.phases(theta)[0][rows])       # same pins, same phases
    # back to the window's rows: the identity
    back = pcs.relayout(full, rows)
    assert all(np.array_equal(getattr(back, k), getattr(s, k)) for k in ("delta", "force", "v_t", "cand"))
    # parts over different rows: over the union (here all pins), in theta order
    both = pcs.concat_states([s, pcs.take_states(r, slice(0, 3))])
    assert both.rows is None and both.force.shape[1] == a.g.z2 and np.all(np.diff(both.theta) >= 0.0)


@pytest.mark.parametrize("make", [cycloid_model, circular_model])
@pytest.mark.parametrize("sigma", [MULTIPLIER, REDUCER])
def test_window_scan_from_the_linearised_balance_is_the_all_pin_solve(make, sigma):
    # set_window solves its scan on the window's pins from the linearised balance's tau (pins.md §5.5); the
    # independent reference is the all-pin solve bracketed by doubling (no window, no linearisation)
    m = make(1.0e6, sigma)
    scan = m.set_window()
    assert m.window is not None and m.window[2] < m.g.z2
    ref = make(1.0e6, sigma)
    pose = ref.pose(scan.theta)
    tau = ref._bracketed(pose, None, 1e-15, 1e-9, newton=True)
    # both stop after a Newton step below 1e-8 |tau| (pins.md §5.5): quadratic convergence leaves ~1e-16 of tau,
    # superlinear only next to a Hertz contact entry (1.6e-12 seen); the residuals stay far below tol/100
    assert np.max(np.abs(scan.tau - tau)) <= 1e-11 * np.max(np.abs(tau))
    assert np.max(np.abs(ref.moment(pose, scan.tau) - ref.M_req)) <= 1e-11 * abs(ref.M_req)
    assert np.allclose(scan.over_pins(ref.g.z2).force, ref._kinematics(pose, tau, None).force, rtol=1e-9,
                       atol=1e-9 * scan.force.max())
    # the linearisation's error, <= (R_p + e) tau^2/2 in the penetrations, is a few % of tau at most: far inside
    # the window's factor of 2
    est = m._linearised_tau(scan.theta.size, 1e-9)
    assert np.max(np.abs(est - tau)) <= 0.05 * np.max(np.abs(tau))


def test_doubling_bracket_holds_the_root_or_reports_none():
    # G(t) = 3e-4 - t (root 3e-4), and one without a root within the limit
    a, b, open_ = pcm._doubling_bracket(lambda t: np.array([3e-4, 5.0]) - t, 2, 1e-9, 1.0)
    assert a[0] <= 3e-4 <= b[0] and b[0] <= 2.0 * 3e-4 + 1e-9 and a[0] >= 0.5 * 3e-4 - 1e-9
    assert open_.tolist() == [False, True]
    # a root below 0: the steps go the other way (G decreasing, G(0) < 0)
    a, b, open_ = pcm._doubling_bracket(lambda t: -2e-3 - t, 1, 1e-9, 1.0)
    assert a[0] <= -2e-3 <= b[0] and not open_[0]


def test_window_scan_without_a_linearised_root_solves_every_pin(monkeypatch):
    # where the linearised balance has no root (or its window's range does not hold), the scan is solved over all
    # pins by doubling and Newton and the window taken from that range (pins.md §5.5): the same scan and window
    a = circular_model(1.0e6)
    scan = a.set_window()
    monkeypatch.setattr(pc.ContactModel, "_linearised_tau", lambda self, n_scan, h0: None)
    b = circular_model(1.0e6)
    full = b.set_window()
    assert b.window[2] == a.window[2] and b.window[:2] == pytest.approx(a.window[:2], rel=1e-12)
    assert np.max(np.abs(full.tau - scan.tau)) <= 1e-11 * np.max(np.abs(scan.tau))
    assert full.cand is None and scan.cand is not None           # every pin solved, against the window's


def test_pass_with_a_wider_window_takes_the_last_states_over_its_rows():
    # a second pass whose window was recomputed for a wider tau range holds more pins (ContactModel.layout): the last
    # pass's states and sets are taken over its rows (the added pins out of reach: no force), so the pass agrees with
    # the same pass on the last window's rows to round-off (pins.md §5.5)
    tol = 1e-6
    a = circular_model(1.0e6)
    first = pc.mean_loss_ratio(a, (0.1, 0.1, False), tol=tol)
    T2 = 1.0e6 * (1.0 + 5e-6)
    same = circular_model(T2)
    same.inherit(a)
    wide = circular_model(T2)
    wide.inherit(a)
    t_lo, t_hi = wide.window[3]                               # the multiplier's: both negative
    wide._window_for(4.0 * t_lo, t_hi)                        # a wider range: more pins
    assert wide.layout()[0].size > same.layout()[0].size
    assert np.isin(same.layout()[0], wide.layout()[0]).all()
    r_same, r_wide = (pc.relinearised_cycle(m, first, a, tol) for m in (same, wide))
    assert r_same is not None and r_wide is not None
    assert np.array_equal(r_wide.sol.rows, wide.layout()[0])
    assert abs(r_wide.loss_ratio - r_same.loss_ratio) <= 1e-12 * r_same.loss_ratio
    extra = ~np.isin(r_wide.sol.rows, r_same.sol.rows)
    assert np.all(r_wide.sol.force[:, extra] == 0.0)
    # rows that leave out a pin carrying force in the last pass: a full pass instead
    loaded = first.sol.rows[first.sol.force.max(axis=(0, 2)) > 0.0]
    narrow = circular_model(T2)
    narrow.inherit(a)
    rows = np.setdiff1d(narrow.layout()[0], loaded[:1])
    pos = np.full(narrow.g.z2, -1)
    pos[rows] = np.arange(rows.size)
    narrow._layout = (narrow.window, rows, pos)
    assert pc.relinearised_cycle(narrow, first, a, tol) is None


def test_refinement_cuts_a_jump_into_sections_and_keeps_newton_for_a_root():
    # a smooth root (Newton: a few calls, to 1e-12) and a jump (steps leave the bracket: cut into `sections` parts
    # per call, 8x narrower instead of bisection's 2x): exact places known (pins.md §6)
    calls = []

    def h(x, k):
        calls.append(x.size)
        return (np.where(k == 0, np.sin(x - 0.3), np.where(x < 0.7123456789, -2.0, 1.0)),
                np.where(k == 0, np.cos(x - 0.3), np.nan))

    jtol = 1e-9
    brackets = ([0.0, 0.0], [1.0, 1.0], [np.sin(-0.3), -2.0], [np.sin(0.7), 1.0])
    r = pcr._refine_sign_changes(h, brackets, pcr.RootStops(1e-12, jump_xtol=jtol))
    assert abs(r[0] - 0.3) <= 1e-12 and abs(r[1] - 0.7123456789) <= jtol
    # bisection alone would take log2(1/2e-9) ~ 29 calls for the jump; sections of 8: ~ log8 of it plus a few
    assert len(calls) <= 14
    assert max(calls) <= pc.DEFAULT_SETTINGS.sections     # one bracket cut (sections - 1 points), one point
    n_cut, calls[:] = len(calls), []
    r2 = pcr._refine_sign_changes(h, brackets, pcr.RootStops(1e-12, jump_xtol=jtol, sections=2))     # bisection
    assert abs(r2[1] - 0.7123456789) <= jtol and len(calls) >= 2 * n_cut


def test_later_passes_start_from_the_full_pass_nodes_on_the_band_design(monkeypatch):
    # the shipped u = 10 band design (rotating pins, both modes friction-consistent): its coarse start is ~1.5e-4 of
    # lambda off, so the fixed point does not settle at the second pass; the third starts from the first's nodes
    # too (pins.md §6(6)): one full pass per mode instead of three, each mode's efficiency within both stated errors
    # of the full passes' (the reference: settings.cycle_relinearise off)
    from gearcalc.pins.contact_level import ContactDesign, contact_level, gear, satellite_profile

    cfg = tomllib.loads((Path(__file__).resolve().parents[2] / "configs" / "pins_circ_band_u10.toml").read_text())
    G, F, L = cfg["gearing"], cfg["friction"], cfg["load"]
    g = gear(G["satellite_teeth"], G["pins"], G["eccentricity_mm"], G["pin_circle_radius_mm"], None,
             G["pin_radius_mm"])[0]
    prof = satellite_profile(g, G["profile"], G["tooth_radius_mm"], G["tooth_circle_radius_mm"], 0.0, 0.0)[0]
    law = pc.contact_law(cfg["contact"]["law"], face_width=cfg["contact"]["face_width_mm"])
    point = {"sliding": F["sliding"], "rolling": F["rolling_mm"], "axle": F["axle"], "mode": L["mode"],
             "shaft": L["torque_shaft"], "torque": L["torque_Nm"], "speed": L["crank_speed_rpm"]}
    full_passes = []
    mean = pc.mean_loss_ratio

    def counted(*args, **kwargs):
        full_passes.append(1)
        return mean(*args, **kwargs)

    monkeypatch.setattr(pc, "mean_loss_ratio", counted)        # the fixed point's passes
    monkeypatch.setattr(pcc, "mean_loss_ratio", counted)       # and the quadrature's own retries
    out = {}
    for flag in (True, False):
        full_passes.clear()
        settings = dataclasses.replace(pc.DEFAULT_SETTINGS, cycle_relinearise=flag)
        cl = contact_level(ContactDesign(g, prof, law, 1, G["rotating_pins"], G["axle_radius_mm"]), point, "consistent",
                           1e-6, prof.play_free, settings=settings)
        out[flag] = (cl, len(full_passes))
    (lite, n_lite), (full, n_full) = out[True], out[False]
    assert n_lite == 2 and n_full >= 6
    for et in ("et_multiplier", "et_reducer"):
        eta = "eta_vh" if et == "et_multiplier" else "eta_hv"
        a, b = getattr(lite, et), getattr(full, et)
        assert abs(getattr(a, eta)[0] - getattr(b, eta)[0]) <= getattr(a, eta + "_err")[0] + getattr(b, eta + "_err")[0]
        assert getattr(a, eta + "_err")[0] <= 1e-6 * getattr(a, eta)[0]
    for cl in (lite, full):                    # tolerance_met (pins.md §6-7)
        for t in cl.modes.runs.values():
            assert t.cycle.converged and t.settled and t.cycle.held and pc.deflection_sized(t.cycle.sol.tau, g)


@pytest.mark.parametrize("z1, z2", [(21, 22), (20, 22), (30, 33)])
@pytest.mark.parametrize("profile", ["cycloid", "circular"])
def test_a_pins_contact_depends_on_its_time_phase_alone(z1, z2, profile):
    # the premise of the window's margin (window_margin): pin j + 1 at theta + T_p is pin j at theta, one tooth pitch
    # turned (the pin circle turns by 2 pi/z2 (1 + k/z1) = 2 pi/z1 in the satellite frame, the crank arm by the
    # same), so a scan of all pins at n crank angles samples the time phase every T_p/n.  Exact identity, to round-off.
    g = Cycloid.from_curtate_ratio(z1, z2, 3.9, 0.75, 1.95)
    prof = pc.CycloidProfile(g, 0.05, 0.02) if profile == "cycloid" else pc.CircularProfile(g, *pc.full_tooth(g))
    m = pc.ContactModel(g, prof, pc.contact_law("linear", stiffness=1e5), 1e5, MULTIPLIER)
    theta = np.linspace(0.0, g.period, 8)[:-1] + 0.1 * g.period / 8
    tau = np.linspace(-3e-4, 3e-4, theta.size)
    idx = np.tile(np.arange(z2)[:, None], (1, theta.size))
    a = m.contacts(m.pose(theta, idx), tau)
    b = m.contacts(m.pose(theta + g.period, np.mod(idx + 1, z2)), tau)
    near = a.delta > -0.5 * g.R_b           # the pins near their teeth (a far pin's pair of teeth is a tie at +-pi)
    assert near.sum() >= theta.size
    assert np.max(np.abs(a.delta - b.delta)[near]) <= 1e-12 * g.R_p
    assert np.max(np.abs(a.arm - b.arm)[near]) <= 1e-12 * g.R_p


@pytest.mark.parametrize("make", [cycloid_model, circular_model])
@pytest.mark.parametrize("sigma", [MULTIPLIER, REDUCER])
def test_no_pin_outside_the_window_touches_on_the_final_grid(make, sigma):
    # the window's margin is window_margin scan spacings of time phase (pins.md §5.5): every pin it leaves out is
    # evaluated at the cycle's solved tau, over the whole final grid (friction in the balance: its own tau)
    m = make(1.0e6, sigma, (0.1, 0.1, False))
    cyc = pc.mean_loss_ratio(m, (0.1, 0.1, False), tol=1e-6)
    assert m.window is not None
    theta, tau = cyc.sol.theta, cyc.sol.tau
    inside = m.candidates(theta)
    assert inside.shape[0] <= m.g.z2 - 2
    out = np.array([np.setdiff1d(np.arange(m.g.z2), inside[:, i]) for i in range(theta.size)]).T
    delta = m.contacts(m.pose(theta, out), tau).delta
    assert np.all(delta < 0.0)
    # and no wider than the margin makes it: at most two pins more than are loaded at once anywhere on the grid
    at_once = np.any(cyc.sol.force > 0.0, axis=0).sum(axis=0).max()
    assert 2 <= at_once and m.window[2] <= at_once + 2


def test_a_window_that_leaves_out_a_touching_pin_is_refused():
    # the check of the pins next to the window (ContactModel.window_holds): windows cut short at either end until a
    # pin that touches somewhere is the first one left out
    m = circular_model(1.0e6)
    m.set_window()
    s = m.state(np.linspace(0.0, m.g.period, 33), phases=False)
    assert m.window_holds(s.tau, s.theta)
    z_lo, z_hi, n, t = m.window
    idx = m.candidates(s.theta)                          # (n, angles): position 0 has the largest time phase
    rows = np.searchsorted(s.rows, idx)
    loaded = np.any(s.force[:, rows, np.arange(s.theta.size)] > 0.0, axis=(0, 2))    # per position
    first, last = np.flatnonzero(loaded)[[0, -1]]
    assert 0 < last - first + 1 < n
    m.window = (z_lo, z_hi, last, t)                     # the positions from `last` on left out (smallest phases)
    assert not m.window_holds(s.tau, s.theta)
    m.window = (z_lo, z_hi - (first + 1) * m.g.period, n - first - 1, t)     # the positions up to `first` left out
    assert not m.window_holds(s.tau, s.theta)
    m.window = (z_lo, z_hi, n, t)
    assert m.window_holds(s.tau, s.theta)


@pytest.mark.parametrize("sigma", [MULTIPLIER, REDUCER])
def test_circular_states_evaluate_the_pressed_tooth_only_and_equal_the_states_over_both(sigma):
    # ContactModel.sides: of each pin's two teeth only the one the torque presses it against can touch for the
    # window's range of tau (the same convex bound as the window's pins); the states over that tooth, scattered to
    # both (the other out of reach), are the states over both teeth: the other carries no force anywhere
    m = circular_model(1.0e6, sigma, (0.1, 0.1, False))
    m.set_window()
    assert m.sides is not None and m.sides.tolist() == ([1] if sigma == MULTIPLIER else [0])
    theta = np.linspace(0.0, m.g.period, 41)
    s = m.state(theta, phases=False)
    ref = circular_model(1.0e6, sigma, (0.1, 0.1, False))
    ref.set_window()
    ref._sides = None                                    # both teeth of every window pin
    assert ref.sides is None
    r = ref.state(theta, phases=False)
    assert s.force.shape == r.force.shape and s.force.shape[0] == 2
    # each solve stops after a Newton step below 1e-6 |tau| (newton_stop): its error C s^2 <= ~3e-12 |tau| (C <= 3)
    assert np.allclose(s.tau, r.tau, rtol=1e-11, atol=0.0)
    assert np.allclose(s.force, r.force, rtol=1e-10, atol=1e-10 * r.force.max())
    assert np.all(r.force[1 - m.sides[0]] == 0.0)        # the tooth left out is loaded nowhere
    assert np.allclose(s.dtau, r.dtau, rtol=1e-9, atol=1e-12)
    # a cycloid has one contact per pin: nothing to leave out
    c = cycloid_model(1.0e6, sigma)
    c.set_window()
    assert c.sides is None


def test_mirrored_sides_are_the_other_modes_own():
    # without friction in the balance the reducer is the multiplier run backwards: the mirror swaps each pin's teeth
    a = circular_model(1.0e6, MULTIPLIER)
    a.set_window()
    b = circular_model(1.0e6, REDUCER)
    b.mirror(a)
    fresh = circular_model(1.0e6, REDUCER)
    fresh.set_window()
    assert a.sides.tolist() == [1] and b.sides.tolist() == fresh.sides.tolist() == [0]
    # a model that inherits the window keeps its sides; without a window there are none
    c = circular_model(1.0e6 * 0.9, MULTIPLIER)
    c.inherit(a)
    assert c.sides.tolist() == [1]
    c.window = None
    assert c.sides is None


def test_a_tooth_left_out_that_touches_is_refused():
    # the check on the final grid (ContactModel.window_holds) covers the teeth that ContactModel.sides leaves out
    m = circular_model(1.0e6, MULTIPLIER)
    m.set_window()
    s = m.state(np.linspace(0.0, m.g.period, 33), phases=False)
    assert m.window_holds(s.tau, s.theta)
    m._sides = (m.window, np.array([0]))                 # the wrong tooth: the loaded one is now left out
    assert not m.window_holds(s.tau, s.theta)


def test_the_next_pass_skips_the_window_check_only_within_the_clearance(monkeypatch):
    # ContactModel.window_holds(prev=...): the pairs left out keep a clearance c on the last pass's final grid; a pass
    # whose tau moved by d with (R_p + e)(d + d^2/2) < c cannot have closed it (|d delta/d tau| <= R_p + e): nothing
    # evaluated; a larger move is evaluated again
    a = circular_model(1.0e6)
    a.set_window()
    s = a.state(np.linspace(0.0, a.g.period, 33), phases=False)
    assert a.window_holds(s.tau, s.theta)
    theta, tau, c, _ = a.clearance
    assert c > 0.0 and theta is s.theta
    b = circular_model(1.0e6)
    b.inherit(a)
    evaluated = []
    orig = pc.ContactModel.contacts
    monkeypatch.setattr(pc.ContactModel, "contacts", lambda self, *x, **k: evaluated.append(1) or orig(self, *x, **k))
    small = 0.5 * c / (a.g.R_p + a.g.e)
    assert b.window_holds(s.tau + small, s.theta, a) and not evaluated
    assert b.clearance[2] == pytest.approx(c - (a.g.R_p + a.g.e) * (small + 0.5 * small ** 2), rel=1e-12)
    # a move that could close it: evaluated
    d = 1.01 * c / (a.g.R_p + a.g.e)
    t_lo, t_hi = b.window[3]
    assert np.all((s.tau - d >= t_lo) & (s.tau - d <= t_hi))      # (a move into the window's range of tau)
    b.window_holds(s.tau - d, s.theta, a)
    assert evaluated
    evaluated.clear()
    b.window_holds(s.tau, s.theta[::-1].copy(), a)                 # other crank angles: evaluated
    assert evaluated


@pytest.mark.parametrize("make", [cycloid_model, circular_model])
def test_a_pose_reused_at_another_torque_gives_the_states_of_a_fresh_one(make):
    # ContactModel.state(reuse=...): the last pass's pose of the same crank angles and candidates (its cycloid foot
    # points the warm start of the new torque's) against a fresh pose: the same states to the solves' precision
    # (settings.newton_stop: ~3e-12 of tau), and a pose of other angles is not taken
    a = make(1.0e6, MULTIPLIER, (0.1, 0.1, False))
    a.set_window()
    theta = np.linspace(0.003, a.g.period - 0.002, 37)
    a.state(theta, phases=False)
    b = make(1.0e6 * (1.0 + 3e-5), MULTIPLIER, (0.1, 0.1, False))
    b.inherit(a)
    c = make(1.0e6 * (1.0 + 3e-5), MULTIPLIER, (0.1, 0.1, False))
    c.inherit(a)
    reused = b.state(theta, phases=False, reuse=a.last_pose)
    assert b.last_pose is a.last_pose
    fresh = c.state(theta, phases=False)
    assert c.last_pose is not a.last_pose
    assert np.allclose(reused.tau, fresh.tau, rtol=1e-11, atol=0.0)
    assert np.allclose(reused.force, fresh.force, rtol=1e-8, atol=1e-9 * fresh.force.max())
    c.state(theta[:-1], phases=False, reuse=a.last_pose)          # other angles: a pose of its own
    assert c.last_pose is not a.last_pose
