"""Tests of the contact level's breakpoints (gearcalc/pins/contact_roots.py; pins.md §6).

Independent references: the full scan of the same model (the roots of a scan at another density, or moved from a
nearby torque, must agree with it to the refinement's 1e-12 T_p), and the states at the pieces' midpoints, which
hold their pieces' sets by construction.
"""
import numpy as np
import pytest

from gearcalc.pins import contact as pc
from gearcalc.pins import contact_roots as pcr
from gearcalc.pins import contact_states as pcs
from gearcalc.pins import MULTIPLIER, Cycloid


def model(T_sat=1.0e6, friction=None):
    # the paper's u = 10 cycloid (k = 2, K1 = 0.75), Hertz contacts of 10 mm (pins.md §10)
    g = Cycloid.from_curtate_ratio(20, 22, 3.9, 0.75, 1.95)
    m = pc.ContactModel(g, pc.CycloidProfile(g, 0.0, 0.0), pc.contact_law("hertz", face_width=10.0), T_sat,
                        MULTIPLIER, friction)
    m.set_window()
    return m


def test_located_breakpoints_from_a_prior_a_coarse_scan_and_the_full_scan_agree():
    tol = 1e-6
    m = model()
    full, edges, n = pcr.locate_breakpoints(m, 256, tol, False)
    assert full.scanned and n == 256 and edges[0] == 0.0 and edges[-1] == m.g.period
    assert np.all(np.diff(edges) > 0.0) and np.all(np.isin(full.roots, edges))
    coarse, _, _ = pcr.locate_breakpoints(m, 256, tol, False, coarse_scan=64)
    moved, moved_edges, _ = pcr.locate_breakpoints(m, 256, tol, False, prior=full, prior_width=1e-6)
    for found in (coarse, moved):
        assert not found.scanned                     # to be confirmed on the quadrature's nodes
        assert found.roots.size == full.roots.size > 0
        assert np.max(np.abs(found.roots - full.roots)) <= 4e-12 * m.g.period
        assert np.array_equal(found.contact, full.contact)
    assert moved_edges.size == edges.size


def test_a_prior_that_cannot_be_moved_falls_back_to_the_full_scan_as_dense_as_the_model_needs():
    m = model()
    prior = pcr.BreakpointRoots(np.array([0.5 * m.g.period]), np.array([True]))   # a root this model lacks
    m.scan_n = 1024                  # a denser scan that an earlier pass of this design needed (pins.md §6)
    found, _, n = pcr.locate_breakpoints(m, 256, 1e-6, False, prior=prior, prior_width=1e-6)
    assert found.scanned and n == 1024


def test_components_put_the_penetrations_first_with_their_slopes():
    m = model()
    s = m.state(np.linspace(0.0, m.g.period, 5), phases=False)
    v, dv, n_delta = pcr.cycle_components(s, False)
    assert n_delta == s.delta[..., 0].size and v.shape == dv.shape == (v.shape[0], 5)
    known = np.isfinite(v[:n_delta])                 # a candidate's penetration (NaN: not a candidate, no sign)
    assert known.any() and np.all(np.isfinite(dv[:n_delta][known]))            # its slope is known
    assert np.all(np.isnan(dv[n_delta:]))                                       # the others' are not


@pytest.mark.parametrize("friction", [None, (0.1, 0.1, False)])
def test_nodes_against_a_neighbouring_pieces_reference_do_not_hold(friction):
    # the midpoints of the pieces hold their own sets; against references that are each the neighbouring piece's
    # state (told this piece's midpoint) they do not: a contact enters or leaves between the two (signs differ)
    tol = 1e-6
    m = model(friction=friction)
    found, edges, _ = pcr.locate_breakpoints(m, 256, tol, False)
    mids = 0.5 * (edges[:-1] + edges[1:])
    ref = m.state(mids, phases=False)
    assert pcr.pieces_hold(([ref], [mids]), [ref], edges, False, tol, m.g.period)
    v = pcr.cycle_components(ref, False)[0]
    assert np.any(np.sign(v) * np.sign(np.roll(v, 1, axis=1)) < 0.0)
    wrong = pcs.take_states(ref, np.roll(np.arange(mids.size), 1))
    wrong.theta = mids.copy()
    assert not pcr.pieces_hold(([ref], [mids]), [wrong], edges, False, tol, m.g.period)
