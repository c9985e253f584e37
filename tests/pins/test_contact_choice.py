"""gearcalc.pins.contact_choice: the friction direction's discrete choice in the contact level's error (issue 37
item 6, pins.md §6).

The band design u = 30's multiplier cuts its spin reversal inside the stretch where neither direction is
consistent: the bound |lambda_L - lambda_R| (l_L + l_R)/T_p, recomputed here from the cycle's one-sided states.
"""
from pathlib import Path

import numpy as np
import pytest

from gearcalc import api
from gearcalc.pins import contact_level as cl
from gearcalc.pins.contact_choice import contradiction_extent, friction_choice_error

CONFIGS = Path(__file__).resolve().parents[2] / "configs"


def test_extent_walks_through_contradicting_neighbours_then_interpolates():
    # states 0..4 of one piece (direction +1, consistent slip < 0), its end 4 and the other piece's 5 at the same
    # angle: 3 and 4 contradict (slip > 0); from 4: spacing to 3 (1.0), then 3 -> 2 with slips 1 and -1: half of 1.0
    th = np.array([0.0, 1.0, 2.0, 3.0, 4.0, 4.0])
    tr = np.array([1.0, 1.0, 1.0, 1.0, 1.0, -1.0])
    slip = np.array([-3.0, -2.0, -1.0, 1.0, 2.0, 2.0])
    bad = np.array([False, False, False, True, True, False])
    assert contradiction_extent(th, bad, slip, tr, 4) == pytest.approx(1.5)
    assert contradiction_extent(th, bad, slip, tr, 3) == pytest.approx(0.5)


def test_band_design_bound_by_hand_from_the_one_sided_states(monkeypatch):
    got = {}
    orig = cl.contact_level

    def keep(*a, **k):
        got["r"] = orig(*a, **k)
        return got["r"]

    monkeypatch.setattr(cl, "contact_level", keep)
    api.compute(CONFIGS / "pins_circ_band_u30.toml", tol=1e-9)
    tc = got["r"].modes.requested                     # the multiplier
    cyc, model = tc.cycle, tc.model
    sol = cyc.sol
    slip = model.friction.slip(sol.force, sol.v_t)
    bad = (sol.force > 0) & (np.sign(sol.traction) * np.sign(slip) > 0)
    ends = np.flatnonzero((sol.theta[1:] == sol.theta[:-1]) & bad[..., :-1].any(axis=(0, 1))
                          & bad[..., 1:].any(axis=(0, 1)))
    assert ends.size == 1                             # the spin reversal at theta ~ 0.01372 rad (pins.md §6)
    n = ends[0]
    c, r = np.argwhere(bad[..., n] & bad[..., n + 1])[0]
    # linear zero of each side's slip toward its in-piece neighbour (n - 1 and n + 2 consistent here)
    ell = sum(abs(sol.theta[m] - sol.theta[q]) * abs(slip[c, r, q]) / (abs(slip[c, r, q]) + abs(slip[c, r, m]))
              for q, m in ((n, n - 1), (n + 1, n + 2)))
    by_hand = abs(cyc.lam[n] - cyc.lam[n + 1]) * ell / model.g.period
    assert friction_choice_error(model, cyc) == pytest.approx(by_hand, rel=1e-12)
    assert 2e-10 < by_hand < 1e-9                      # measured 4.5e-10: it covers the plateaus 2.2e-10 apart
