"""zstk sweep and batch hooks: the stacked (numpy over designs) evaluation equals compute point by point.

The expected values are compute's own results, design by design (the independent numbers for the
physics are in test_zstk.py); here every column of the vectorised sweep and every field of a batch
must equal them exactly or to 1e-12 relative (round-off of a differently shaped array expression).
"""
import copy
import dataclasses
import math
import tomllib

import pytest

from conftest import CONFIGS, cli
from gearcalc import registry
from gearcalc import grid as sw
from gearcalc.calculator import DesignError, Options
from gearcalc.design import apply_set, load, validate

EXAMPLE = CONFIGS / "zstk_merko_example.toml"
ZSTK = registry.get("zstk")


def same(a, b, path="") -> None:
    """a == b, floats to 1e-12 relative (1e-300 absolute for values at zero)."""
    if isinstance(a, float) and isinstance(b, float):
        assert a == b or abs(a - b) <= 1e-12 * max(abs(a), abs(b)), (path, a, b)
    elif isinstance(a, dict):
        assert isinstance(b, dict) and list(a) == list(b), (path, list(a), list(b))
        for k in a:
            same(a[k], b[k], f"{path}.{k}")
    elif isinstance(a, list):
        assert isinstance(b, list) and len(a) == len(b), (path, a, b)
        for i, (x, y) in enumerate(zip(a, b)):
            same(x, y, f"{path}[{i}]")
    else:
        assert type(a) is type(b) and a == b, (path, a, b)


def raw_example(**sets):
    raw = tomllib.loads(EXAMPLE.read_text())
    apply_set(raw, list(sets.items()))
    return raw


def point_by_point(raw, axes, options):
    """The rows of a grid computed one design at a time (compute, no sweep hook)."""
    rows = []
    for p in sw.grid_points(axes):
        trial = copy.deepcopy(raw)
        apply_set(trial, list(p.items()))
        rows.append({**p, **ZSTK.compute(validate(trial, str(EXAMPLE)), options).summary})
    return rows


def hooked(raw, axes, options, monkeypatch=None):
    """The rows of the sweep hook (compute is disabled when monkeypatch is given: no silent fallback)."""
    if monkeypatch is not None:
        def no_compute(*a, **k):
            raise AssertionError("the sweep fell back to point-by-point compute")

        monkeypatch.setattr(registry, "get", lambda kind: dataclasses.replace(ZSTK, compute=no_compute))
    out = sw.evaluate(raw, str(EXAMPLE), axes, options)
    return out.rows() if hasattr(out, "rows") else out


AXES = [
    {"load.radial_N": [1e-6, 1.0, 1e4, 3.3e5, 1e9]},
    {"load.direction_deg": [0.0, 7.5, 30.0, 90.0, 179.0, 180.0, -45.0, 400.0]},
    {"load.clearance_mm": [-0.01, 0.0, 1e-6, 0.01, 0.05]},
    {"geometry.eccentricity_mm": [0.0, 1e-12, 0.5, 3.0, 6.0, 12.0, 20.0]},
    {"geometry.roller_gap_mm": [0.0, 1e-9, 2.0, 6.0, 11.0]},            # N changes with the gap
    {"geometry.outer_raceway_radius_mm": [90.0, 100.0, 130.0]},
    {"geometry.inner_raceway_radius_mm": [40.0, 50.0, 60.0]},
    {"geometry.roller_length_mm": [5.0, 20.0, 80.0]},
    {"geometry.scheme": ["A", "B", "C", "D", 0.0, 17.0, -123.0]},       # parity: N differs per scheme
    {"geometry.correct": ["outer", "inner", "gap"]},
    {"geometry.rollers": ["auto", 5, 7, 8, 12]},   # any N: the base design has a phase angle (below)
    {"material.roller_E_MPa": [7e4, 2.1e5, 4e5]},
    {"material.ring_poisson": [0.2, 0.3, 0.45]},
    {"material.inner_ring_E_MPa": [1e5, 3e5]},
    {"material.allowable_stress_MPa": [500.0, 2000.0, 4000.0]},
]


@pytest.mark.parametrize("axes", AXES, ids=[next(iter(a)) for a in AXES])
@pytest.mark.parametrize("model", ["equilibrium", "fixed-direction"])
def test_sweep_equals_point_by_point(axes, model, monkeypatch):
    sets = {} if "load.direction_deg" in axes else {"load.direction_deg": 20.0}
    if "geometry.rollers" in axes:
        sets["geometry.scheme"] = 10.0
    raw = raw_example(**sets)
    opts = Options(tol=1e-6, model=model)
    want = point_by_point(raw, axes, opts)
    got = hooked(raw, axes, opts, monkeypatch)
    same(got, want)


def test_sweep_2d_grid_crossing_n(monkeypatch):
    """A product grid (gap x direction x clearance) in which N changes (auto N falls as the gap grows):
    the stacks of different N come back in grid order."""
    raw = raw_example(**{"geometry.scheme": 5.0})  # a phase angle: any N, not only even ones
    axes = {"geometry.roller_gap_mm": [0.0, 3.0, 6.0, 9.0, 12.0, 16.0], "load.direction_deg": [0.0, 25.0, 180.0],
            "load.clearance_mm": [0.0, 0.005]}
    opts = Options(tol=1e-6)
    want = point_by_point(raw, axes, opts)
    assert len({r["N"] for r in want}) >= 3  # the grid does cross several N
    same(hooked(raw, axes, opts, monkeypatch), want)


def test_sweep_reference_level(monkeypatch):
    raw = raw_example()
    axes = {"geometry.eccentricity_mm": [0.0, 6.0], "geometry.roller_gap_mm": [0.0, 6.0]}
    opts = Options(tol=1e-6, model="reference")
    want = point_by_point(raw, axes, opts)
    assert all(r["stepping_residual_mm"] < 1e-9 for r in want)
    same(hooked(raw, axes, opts, monkeypatch), want)


def test_sweep_with_cycle_or_envelope_falls_back():
    """"cycle"/"envelope" points run adaptive sweeps of their own: the hook declines (None) and the
    frame evaluates point by point."""
    base = load(str(EXAMPLE))
    for axes in ({"load.direction_deg": [0.0, "envelope"]}, {"geometry.scheme": ["A", "cycle"]}):
        points = sw.grid_points(axes)
        assert ZSTK.sweep(base, raw_example(), axes, points, Options()) is None
    raw = raw_example(**{"geometry.scheme": "cycle"})
    axes = {"load.radial_N": [1e3, 1e4]}
    assert ZSTK.sweep(load(str(EXAMPLE), [("geometry.scheme", "cycle")]), raw, axes, sw.grid_points(axes),
                      Options(model="fixed-direction")) is None


def test_impossible_point_errors_like_point_by_point():
    """Each axis value is valid with the base design, but (R_B = 90, e = 12) is not (e >= R_H - R_B = 10):
    the hook raises the DesignError the point gives on its own, naming the key, the constraint and the point."""
    raw = raw_example()
    axes = {"geometry.inner_raceway_radius_mm": [50.0, 90.0], "geometry.eccentricity_mm": [6.0, 12.0]}
    base = validate(copy.deepcopy(raw), str(EXAMPLE))
    with pytest.raises(DesignError) as hook_err:
        ZSTK.sweep(base, raw, axes, sw.grid_points(axes), Options())
    bad = {"geometry.inner_raceway_radius_mm": 90.0, "geometry.eccentricity_mm": 12.0}
    assert hook_err.value.key == "geometry.eccentricity_mm"
    assert str(bad) in hook_err.value.message
    # the same design on its own (gearcalc zstk --set ...) reports the same key and constraint
    trial = copy.deepcopy(raw)
    apply_set(trial, list(bad.items()))
    with pytest.raises(Exception) as alone:
        validate(trial, str(EXAMPLE))
    constraint = hook_err.value.message.split(" (at ")[0]
    assert f"geometry.eccentricity_mm {constraint}" in str(alone.value)  # "key = value: why" (calculator.keyed)
    with pytest.raises(sw.SweepError) as frame_err:  # through the frame: exit 2 in the CLI
        sw.evaluate(raw, str(EXAMPLE), axes, Options())
    assert "geometry.eccentricity_mm" in str(frame_err.value) and str(bad) in str(frame_err.value)


def test_impossible_combination_of_rollers_and_scheme():
    """An explicit N of the wrong parity for the scheme (A needs even N) only at one grid point."""
    raw = raw_example()
    axes = {"geometry.rollers": [8, 7], "geometry.scheme": ["B", "A"]}
    base = validate(copy.deepcopy(raw), str(EXAMPLE))
    with pytest.raises(DesignError) as err:
        ZSTK.sweep(base, raw, axes, sw.grid_points(axes), Options())
    assert err.value.key == "geometry.rollers" and "'geometry.rollers': 8, 'geometry.scheme': 'B'" in err.value.message


# ----------------------------------------------------------------------------- batch
CONFIG_FILES = sorted(CONFIGS.glob("zstk_*.toml"))


@pytest.mark.parametrize("model", ["equilibrium", "fixed-direction", "reference"])
def test_batch_equals_compute_for_every_config(model):
    designs = [load(str(p)) for p in CONFIG_FILES]
    opts = Options(tol=1e-6, model=model)
    if model == "reference":  # the envelope config at the reference level takes ~0.3 s; once is enough
        designs = [d for d in designs if d["load.direction_deg"] != "envelope"]
    got = ZSTK.batch(designs, opts)
    for d, b in zip(designs, got):
        a = ZSTK.compute(d, opts)
        same([a.summary, a.detail, a.warnings, a.failed, a.model], [b.summary, b.detail, b.warnings, b.failed, b.model],
             d.source)


VARIANTS = [
    [("load.direction_deg", 30.0)], [("load.clearance_mm", 0.01), ("load.direction_deg", 33.0)],
    [("load.clearance_mm", -0.004)], [("geometry.scheme", 17.0)],
    [("geometry.eccentricity_mm", 0.0), ("geometry.scheme", "B")],
    [("geometry.roller_gap_mm", 0.0), ("geometry.rollers", 11), ("geometry.scheme", "B")],
    [("geometry.correct", "gap"), ("geometry.scheme", "D")],
    [("material.allowable_stress_MPa", 800.0)], [("load.radial_N", 1e9)],   # fails the check; b/rho warning
    [("geometry.outer_raceway_radius_mm", 100.0), ("geometry.inner_raceway_radius_mm", 97.5),
     ("geometry.eccentricity_mm", 0.5), ("geometry.roller_gap_mm", 0.05), ("load.direction_deg", 10.0)],  # N > 200
    [("geometry.scheme", "cycle")], [("load.direction_deg", "envelope"), ("geometry.eccentricity_mm", 2.0)],
]


@pytest.mark.parametrize("model", ["equilibrium", "fixed-direction"])
def test_batch_of_mixed_designs_equals_compute(model):
    """Different N, clearance, direction, scheme, material and sweeping designs in one batch, in order."""
    designs = [load(str(EXAMPLE), v) for v in VARIANTS] * 2
    opts = Options(tol=1e-6, model=model)
    got = ZSTK.batch(designs, opts)
    assert len(got) == len(designs)
    for d, b in zip(designs, got):
        a = ZSTK.compute(d, opts)
        same([a.summary, a.detail, a.warnings, a.failed], [b.summary, b.detail, b.warnings, b.failed])
    assert any(r.failed for r in got) and len({r.summary["N"] for r in got}) >= 4


def test_batch_returns_the_exception_of_an_impossible_design():
    """A design that escaped validation (here: values changed after it) comes back as compute's DesignError."""
    good = load(str(EXAMPLE))
    bad = load(str(EXAMPLE))
    bad.values["geometry"]["eccentricity_mm"] = 60.0
    with pytest.raises(DesignError) as alone:
        ZSTK.compute(bad, Options())
    got = ZSTK.batch([good, bad, good], Options())
    assert isinstance(got[1], DesignError) and (got[1].key, got[1].message) == (alone.value.key, alone.value.message)
    same(got[0].summary, got[2].summary)


# ----------------------------------------------------------------------------- CLI
def test_cli_sweep_example():
    r = cli("sweep", EXAMPLE, "--vary", "load.direction_deg=0:90:15", "--vary", "geometry.roller_gap_mm=4,6",
            "--format", "csv")
    assert r.code == 0, r
    lines = r.out.strip().splitlines()
    header = lines[0].split(",")
    assert header[:2] == ["load.direction_deg", "geometry.roller_gap_mm"] and "sigma_max_MPa" in header
    assert len(lines) == 1 + 7 * 2
    # one point against the design on its own (the CSV cell is the repr of the float)
    one = load(str(EXAMPLE), [("load.direction_deg", 45), ("geometry.roller_gap_mm", 4)])
    want = ZSTK.compute(one, Options()).summary["sigma_max_MPa"]
    row = dict(zip(header, lines[1 + 3 * 2].split(",")))
    assert row["load.direction_deg"] == "45" and row["geometry.roller_gap_mm"] == "4"
    assert math.isclose(float(row["sigma_max_MPa"]), want, rel_tol=1e-12)


def test_cli_sweep_impossible_point_exit_2():
    r = cli("sweep", EXAMPLE, "--vary", "geometry.inner_raceway_radius_mm=50,90", "--vary",
            "geometry.eccentricity_mm=6,12")
    assert r.code == 2, r
    assert "geometry.eccentricity_mm" in r.err and "must be" in r.err and "'geometry.eccentricity_mm': 12" in r.err
    assert "Traceback" not in r.err
