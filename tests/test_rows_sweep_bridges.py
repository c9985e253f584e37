"""The rows sweep with [bridges] evaluated as arrays (gearcalc/kinds/rows.py, rows.md §9) gives, point for point,
the design computed alone: the same columns in the same order and the same values bit for bit, over a grid that
holds every kind of point (feasible, capped, no room, κ ≥ 8, unloaded rows in the verification)."""
import copy
import itertools

import numpy as np

import gearcalc
from gearcalc import rows as R
from gearcalc.render import Columns

BASE = {"kind": "rows", "gear": {"sun_teeth": 18, "module_mm": 5.0, "ratio": 6.0},
        "rows": {"count": 3, "planets_per_row": 3, "relative_width": 3.0}, "sun": {"torque_Nm": 1e3},
        "bridges": {}}


def alone(base, axes):
    rows = []
    for combo in itertools.product(*axes.values()):
        d = copy.deepcopy(base)
        for key, value in zip(axes, combo):
            table, _, name = key.partition(".")
            d[table][name] = value
        rows.append({**dict(zip(axes, combo)), **gearcalc.compute(d).summary})
    return Columns.from_rows(rows)


def test_bridges_sweep_equals_each_point_alone_bit_for_bit():
    axes = {"rows.count": [1, 3, 4], "gear.ratio": [2.3, 4.0], "rows.planets_per_row": [3, 7],
            "bridges.first_span": ["axes_only", 0.1], "rows.relative_width": [0.4, 3.0, 40.0]}
    (part,) = list(gearcalc.sweep(BASE, axes))
    want = alone(BASE, axes)
    assert list(part.data) == list(want.data)  # the union of the columns in first-seen order (rows.md §13.5)
    for key, values in want.data.items():
        assert part.lists().data[key] == values, key
    got = part.lists().data
    # the grid holds every case (else the equality above would prove less)
    assert 0 < sum(got["bridges_feasible"]) < len(got["bridges_feasible"])
    assert any(h == 0.0 for h in got["bridge_max_mm"])                       # no room (H_max <= 0)
    assert any(k is None for k in got["K_balanced"])                         # κ >= 8 (rows.md §13.10)
    assert any(u for u in got["unloaded_rows_balanced"])                     # the active set dropped rows
    assert any(v is None for v in got["bridge_rel_4"])                       # n = 1, 3 have no span 4


def test_bridges_sweep_varies_the_bridge_keys_as_arrays():
    axes = {"bridges.torsion_diameter": ["root", "pitch", 80.0], "bridges.axle_diameter_mm": [20.0, 40.0],
            "rows.relative_width": [2.4, 3.0]}
    (part,) = list(gearcalc.sweep(BASE, axes))
    want = alone(BASE, axes)
    assert part.lists().data == want.data


def test_size_bridges_batch_equals_size_bridges_per_design():
    # the scalar function is the batch of one: a batch of many designs gives each design's widths and flags
    B = np.linspace(0.3, 6.0, 25)
    for n, ratio, first in itertools.product((2, 3, 4), (2.5, 4.0, 10.0), (None, 2.0)):
        f = R.face_geometry(18, 5.0, n, np.radians(20.0), relative_width=B)
        batch = R.size_bridges_batch(n, 3, f.sun_diameter, 5.0, f.rim_width, f.cheek, np.radians(20.0), ratio,
                                     0.5 * f.rim_width, 0.5 * f.rim_width, 2e5, 0.3, R.polar_moment(77.5), first)
        for k, b in enumerate(B.tolist()):
            g = R.face_geometry(18, 5.0, n, np.radians(20.0), relative_width=b)
            one = R.size_bridges(n, 3, g.sun_diameter, 5.0, g.rim_width, g.cheek, np.radians(20.0), ratio,
                                 0.5 * g.rim_width, 0.5 * g.rim_width, 2e5, 0.3, R.polar_moment(77.5), first)
            assert [R.FLAGS[c] for c in batch["flags"][k]] == one["flags"]
            for key in ("H", "H_rel", "D", "stiffness"):
                assert np.array_equal(batch[key][k], one[key]), key


def test_active_set_batch_equals_the_scalar_active_set():
    # compliant carriers that over-compensate (negative loads, rows dropped and re-activated), in one batch
    rng = np.random.default_rng(7)
    n, P = 5, 40
    kappa = rng.uniform(0.05, 3.0, P)
    Y = rng.uniform(-2.0, 2.0, (P, n, n))
    u, unloaded, converged = R.stepwise_active_set_batch(kappa, np.full(P, 0.25), n, Y)
    dropped = 0
    for k in range(P):
        u1, off, ok, _ = R.stepwise_active_set(float(kappa[k]), 0.25, n, carrier=Y[k])
        assert ok == converged[k] and off == (np.flatnonzero(unloaded[k]) + 1).tolist()
        assert np.array_equal(u[k], u1)  # the same solves of the same sizes: bit for bit
        dropped += bool(off)
    assert dropped > 0 and not converged.all()
