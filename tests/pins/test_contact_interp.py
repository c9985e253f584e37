"""Tests of the states between a cycle's nodes (gearcalc/pins/contact_interp.py; pins.md §5.5, §6).

References: a cubic Hermite interpolant is exact for cubics, a Lagrange basis on m nodes for polynomials of degree
< m (the interpolation theorems); the Gauss-Kronrod cycle's own solved nodes.
"""
import numpy as np
import pytest

from gearcalc.pins import contact as pc
from gearcalc.pins import contact_interp as pci
from gearcalc.pins import MULTIPLIER, Cycloid
from gearcalc.quadrature import _KRONROD


def test_piece_guess_is_exact_for_a_cubic_within_a_piece_and_nan_in_a_piece_without_nodes():
    edges = np.array([0.0, 1.0, 2.0, 3.0])
    x = np.array([0.0, 0.3, 1.0, 1.2])                 # two nodes in each of the first two pieces, none in the third
    keys = pc.piece_keys(edges, x, np.array([0.5, 0.5, 1.5, 1.5]))
    tau, dtau = x ** 3 - x, 3.0 * x ** 2 - 1.0
    xq = np.array([0.1, 0.2, 1.1, 1.6, 2.5])
    key = pc.piece_keys(edges, xq, np.array([0.5, 0.5, 1.5, 1.5, 2.5]))
    guess = pci.piece_guess(keys, tau, dtau, key, xq, edges)
    assert np.allclose(guess[:4], xq[:4] ** 3 - xq[:4], rtol=0.0, atol=1e-13)   # Hermite: a cubic to round-off
    assert np.isnan(guess[4])                       # no solved node in that piece: the model's own start


@pytest.mark.parametrize("rule", ["gk7", "gk15"])
def test_lagrange_basis_on_kronrod_nodes_is_exact_below_their_count(rule):
    t = _KRONROD[rule][0]
    s = np.linspace(-0.9, 0.9, 11)
    coef = np.arange(1.0, t.size + 1.0)             # a polynomial of degree m - 1
    W = pci._lagrange_matrix(t, s)
    assert np.allclose(W @ np.polyval(coef, t), np.polyval(coef, s), rtol=1e-12, atol=0.0)
    assert np.array_equal(pci._lagrange_matrix(t, t[:3]), np.eye(t.size)[:3])     # at a node: the node


def test_gk_interpolated_states_lie_between_the_nodes_of_their_pieces():
    g = Cycloid.from_curtate_ratio(21, 22, 3.9, 0.75, 1.95)
    m = pc.ContactModel(g, pc.CycloidProfile(g, 0.0, 0.0), pc.contact_law("linear", stiffness=1e5), 1e4, MULTIPLIER)
    cyc = pc.mean_loss_ratio(m, (0.1, 0.1, False), tol=1e-5, rule="gk7")
    pts, mids = pci.gk_interpolated(cyc.sol, cyc.quad, "gk7", 64)
    assert pts.theta.size == mids.size > 0 and np.all(np.diff(pts.theta) >= 0.0)
    edges = cyc.breakpoints                         # each point inside the piece of its midpoint
    p = np.searchsorted(edges, mids) - 1
    assert np.all((pts.theta > edges[p]) & (pts.theta < edges[p + 1]))
    # tau is smooth on a piece: the interpolant stays within the range of the solved states
    assert pts.tau.min() >= cyc.sol.tau.min() - 1e-9 * np.ptp(cyc.sol.tau)
    assert pts.tau.max() <= cyc.sol.tau.max() + 1e-9 * np.ptp(cyc.sol.tau)
    assert np.all(pts.force >= 0.0) and np.all(pts.residual == 0.0)
    assert pci.gk_interpolated(cyc.sol, cyc.quad, "gk15", 64) is None       # not that rule's nodes
