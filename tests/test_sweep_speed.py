"""Sweep throughput (issue 36 item 8): the work a chunk of a sweep does follows the chunk, not the grid, and
the shortcuts taken give the same values as the plain path.  No timings: the work is counted."""
from __future__ import annotations

import math
import tomllib
from collections.abc import Sequence

import numpy as np

from conftest import CONFIGS
from gearcalc import grid as sw
from gearcalc import pins
from gearcalc.calculator import Options
from gearcalc.pins import consistent as pc


class CountingAxis(Sequence):
    """An axis of values that counts the values read (a stand-in for a long lazy axis)."""

    def __init__(self, values):
        self.values, self.reads = list(values), 0

    def __len__(self):
        return len(self.values)

    def __getitem__(self, k):
        out = self.values[k]
        self.reads += len(out) if isinstance(k, slice) else 1
        return out


def test_grid_iter_of_a_late_chunk_reads_the_chunk_only():
    """Iterating the last 10 points of a 100 000-point axis reads about 10 values (itertools.product over the
    axis read all of them, for every chunk: a sweep quadratic in the grid size)."""
    axis = CountingAxis(range(100_000))
    g = sw.Grid({"a": [1, 2], "b": axis})
    part = g[len(g) - 10:]
    points = list(part)
    assert points == [{"a": 2, "b": v} for v in range(99_990, 100_000)]
    assert axis.reads <= 20


def test_grid_iter_is_the_product_in_order():
    """Every slice of a grid iterates as the same slice of the plain product (first axis slowest), over block
    boundaries too."""
    import itertools

    axes = {"a": [1, 2, 3], "b": sw.Range(0.5, 0.1, 7), "c": ["x", "y"], "d": sw.Range(1, 2, 5, ints=True)}
    full = [dict(zip(axes, c)) for c in itertools.product(*axes.values())]
    g = sw.Grid(axes)
    for start, stop in ((0, len(full)), (5, 6), (13, 200), (199, 210), (len(full) - 1, len(full))):
        assert list(g[start:stop]) == full[start:stop]
    old = sw.ITER_BLOCK
    try:
        sw.ITER_BLOCK = 4
        assert list(g[3:50]) == full[3:50]
    finally:
        sw.ITER_BLOCK = old
    assert list(sw.Grid({})) == [{}]


def test_zstk_sweep_checks_the_values_of_its_chunk_only(monkeypatch):
    """A zstk chunk checks the distinct values of its own points (it checked every value of the axis for every
    chunk); the columns are those of the whole-axis check."""
    from gearcalc import design
    from gearcalc.design import validate
    from gearcalc.kinds import zstk

    src = CONFIGS / "zstk_merko_example.toml"
    raw = tomllib.loads(src.read_text())
    axes = sw.parse_vary(["load.radial_N=1000:50999:1"])
    base = validate(raw, str(src))
    calls = []
    real = design.check_value

    def counting(field, value):
        calls.append(value)
        return real(field, value)

    monkeypatch.setattr(design, "check_value", counting)
    g = sw.Grid(axes)
    cols = zstk.sweep(base, raw, axes, g[49_990:], Options())
    assert len(calls) == 10
    monkeypatch.setattr(design, "check_value", real)
    alone = zstk.sweep(base, raw, axes, list(g[49_990:]), Options())
    assert cols == alone
    floats = sw.parse_vary(["load.radial_N=1000.0:20000.0:0.5"])   # a float axis: its values taken as they are
    g = sw.Grid(floats)
    assert zstk.sweep(base, raw, floats, g[100:300], Options()) == zstk.sweep(base, raw, floats, list(g[100:300]),
                                                                               Options())


def _cycles():
    g = pins.geometry._as_arrays(pins.Cycloid.from_curtate_ratio(20, 22, 3.9, 0.75, 1.95))
    return pins.ideal_cycles(g, np.array([1]))


def test_consistent_cycles_evaluates_each_distinct_point_once(monkeypatch):
    """Points of the same gear, friction, discs and mode (a torque axis) are evaluated once: the node work
    follows the distinct points (2 here, not 6), and every point's values are those of the point alone, bit
    for bit (pins v2 evaluated every point on every node: the README's torque x friction sweep 2.3-3.4x slower)."""
    cyc = _cycles()
    mu = np.array([0.1, 0.05, 0.1, 0.1, 0.05, 0.1])
    sizes = []
    real = pc._point_nodes

    def counting(c, gear):
        sizes.append(gear.size)
        return real(c, gear)

    monkeypatch.setattr(pc, "_point_nodes", counting)
    many = pc.consistent_cycles(cyc, np.zeros(6, dtype=np.int64), mu)
    assert sizes == [2]
    monkeypatch.setattr(pc, "_point_nodes", real)
    pair = pc.consistent_cycles(cyc, np.zeros(2, dtype=np.int64), np.array([0.1, 0.05]))
    for f in pc.ConsistentCycles.__dataclass_fields__:
        got = getattr(many, f)
        for i, m in enumerate(mu):
            j = 0 if m == 0.1 else 1
            assert np.array_equal(got[..., i], getattr(pair, f)[..., j], equal_nan=True), f


def test_pins_torque_sweep_equals_points_alone():
    """A pins torque x friction sweep (the consistent model's distinct points shared) gives each point's
    own compute result."""
    from gearcalc import api

    src = CONFIGS / "pins_paper_cyc_u10_fixed.toml"
    parts = list(api.sweep(str(src), {"load.torque_Nm": [10.0, 20.0, 30.0], "friction.sliding": [0.05, 0.1]}))
    cols = parts[0].data
    for i in range(6):
        t, f = cols["load.torque_Nm"][i], cols["friction.sliding"][i]
        alone = api.compute(str(src), overrides={"load.torque_Nm": t, "friction.sliding": f}).summary
        for key in ("efficiency", "torque_in_Nm", "pin_force_max_N", "crank_torque_ripple_Nm", "bearing_force_max_N"):
            assert cols[key][i] == alone[key], key


def test_api_sweep_columns_are_lists_made_on_demand():
    """gearcalc.sweep's chunks hold lists (the API's promise) of the same values as the plain path, though the
    chunk keeps numpy arrays until a column is read (a rows sweep spent 43 % of its API time making lists of
    columns nobody read)."""
    import json
    import pickle

    from gearcalc import api

    cases = [("rows_fig3_n3_nw3_B2.4.toml", {"rows.relative_width": sw.Range(1.5, 0.25, 7), "rows.count": [3, 4]}),
             ("zstk_merko_example.toml", {"load.radial_N": sw.Range(1000.0, 500.5, 5)}),
             ("pins_paper_cyc_u10_fixed.toml", {"friction.sliding": [0.05, 0.1], "load.torque_Nm": [10.0, 20.0]})]
    for name, axes in cases:
        src = str(CONFIGS / name)
        raw = tomllib.loads((CONFIGS / name).read_text())
        want = list(sw.stream(raw, src, axes, Options()))
        got = list(api.sweep(src, axes))
        assert len(got) == len(want)
        for g, w in zip(got, want):
            lazy = dict.__getitem__(g.data, next(k for k in g.data if k.startswith(("rows.", "load.", "friction."))))
            assert not isinstance(lazy, list) or name.startswith("pins")  # a float axis stays an array until read
            first = next(iter(g.data))
            assert g.data[first] == w.data[first] and type(g.data[first]) is list
            assert g.data.get("nope", 1) == 1
            assert type(g.data.pop("model_time_ms", [])) is list  # a timing: not compared
            w.data.pop("model_time_ms", None)
            assert dict(g.data) == w.data and g.data == w.data and g.rows() == w.rows()
            for k, v in g.data.items():
                assert type(v) is list and [type(x) for x in v] == [type(x) for x in w.data[k]], k
            assert json.dumps(g.data) == json.dumps(w.data)
            assert pickle.loads(pickle.dumps(g.data)) == w.data


def test_pins_geometry_axis_costs_its_geometries():
    """An ideal-level grid over a geometry axis costs each distinct geometry as alone (1 ms + 35 us a pin-disc,
    kinds/pins.py sweep_cost): chunks of about a second's work, a grid of hours refused; a friction axis stays
    at 25 us a point (it cost 25 us a point whatever the axes: one chunk of 1e4 geometries, 21 s and ~1 GB)."""
    src = CONFIGS / "pins_paper_cyc_u10_fixed.toml"
    raw = tomllib.loads(src.read_text())
    per_geometry = 1e-3 + 35e-6 * 22 * 1                    # the config: 22 pins, one disc
    geo = {"gearing.eccentricity_mm": sw.Range(3.0, 0.00015, 10_000)}
    total, seconds = sw.prepare(raw, str(src), geo, Options())
    assert seconds == 2.5e-5 + per_geometry
    assert sw.chunk_points(seconds) < 1_000
    both = {**geo, "friction.sliding": [0.05, 0.1]}          # two points a geometry
    assert sw.prepare(raw, str(src), both, Options())[1] == 2.5e-5 + per_geometry / 2
    assert sw.prepare(raw, str(src), {"friction.sliding": sw.Range(0.01, 1e-5, 10_000)}, Options())[1] == 2.5e-5
    # below the default --tol a gear needs (1e-6/tol)^(1/2) times the nodes (320 -> 9 900 at 1e-9, measured):
    # its pin-disc term grows as much, so a chunk stays about a second of work and bounded memory (one chunk of
    # 1 001 eccentricities at 1e-9 took 1.3-2 GB)
    tight = sw.prepare(raw, str(src), geo, Options(tol=1e-9))[1]
    assert tight == 2.5e-5 + 1e-3 + 35e-6 * 22 * 1 * math.sqrt(1e-6 / 1e-9)
    assert sw.chunk_points(tight) < 50
    assert sw.prepare(raw, str(src), geo, Options(tol=1e-3))[1] == 2.5e-5 + per_geometry     # never below
    huge = {"gearing.eccentricity_mm": sw.Range(3.0, 1.5e-6, 1_000_000)}
    assert "more than a sweep may take" in sw.cost_problem(huge, 1_000_000, sw.prepare(raw, str(src), huge,
                                                                                          Options())[1])


GEOMETRY_CASES = [   # (config, axes): each row must be that design's own compute result, bit for bit
    ("pins_paper_cyc_u10_fixed.toml", {"gearing.eccentricity_mm": sw.Range(1.0, 0.05, 21)}),
    ("pins_paper_cyc_u10_fixed.toml", {"gearing.eccentricity_mm": [1.0, 2.5, 3.9],
                                       "load.mode": ["multiplier", "reducer"], "friction.sliding": [0.1, 0.3]}),
    ("pins_paper_cyc_u10_fixed.toml", {"gearing.eccentricity_mm": [3.5, 3.9], "load.mode": ["reducer"],
                                       "friction.sliding": [0.79, 0.7908141]}),     # near the jam limit: capped
    ("pins_paper_circ_u10_fixed.toml", {"gearing.eccentricity_mm": [3.7, 3.9]}),     # the contact level
    ("pins_paper_cyc_u10_rotating.toml", {"gearing.eccentricity_mm": sw.Range(1.5, 0.2, 6),
                                          "gearing.curtate_ratio": [0.5, 0.9]}),
    ("pins_paper_cyc_u30_fixed.toml", {"gearing.pin_radius_mm": [0.8, 1.2], "load.mode": ["multiplier", "reducer"],
                                       "gearing.discs": [1, 2]}),
]


def test_pins_geometry_sweep_rows_are_the_designs_alone_bit_for_bit(monkeypatch):
    """A sweep whose geometry varies (the gears solved together, the friction-consistent refinement of many
    gears at once) gives every row exactly what ``gearcalc.compute`` gives that design alone: the same sums in
    the same order, cycloidal and circular-arc teeth, fixed and rotating pins, both modes, one and two discs,
    refinements that converge and that stop at the cap (CONSISTENT_N_MAX)."""
    from gearcalc import api

    refined = {"pairs": 0, "capped": 0}
    real = pc._refine_consistent

    def counting(job):
        value, err, conv, n_out, jam = real(job)
        refined["pairs"] += job.gear.size
        refined["capped"] += int((n_out == pc.CONSISTENT_N_MAX).sum())
        return value, err, conv, n_out, jam

    monkeypatch.setattr(pc, "_refine_consistent", counting)

    for name, axes in GEOMETRY_CASES:
        src = str(CONFIGS / name)
        rows = [r for part in api.sweep(src, axes) for r in part.rows()]
        points = sw.grid_points(axes)
        assert len(rows) == len(points)
        for point, row in zip(points, rows):
            alone = api.compute(src, overrides=point).summary
            for key, want in alone.items():
                if key == "model_time_ms" or key not in row:
                    continue
                got = row[key]
                same = got == want or (isinstance(want, float) and math.isnan(want) and math.isnan(got))
                assert same, (name, point, key, got, want)
    assert refined["pairs"] > 20 and refined["capped"] > 0     # the sweeps' refinement (a design alone has its own)
