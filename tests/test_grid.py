"""gearcalc sweep: grid parsing, validation, and the vectorised path equal to point-by-point evaluation."""
import copy
import csv
import io
import json
import tomllib
from collections.abc import Sequence

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import gearcalc
from conftest import CONFIGS, cli
from gearcalc import grid as sw
from gearcalc.calculator import Options

FIG3 = CONFIGS / "rows_fig3_n3_nw3_B2.4.toml"
FIG5 = CONFIGS / "rows_mass_fig5.toml"


@pytest.mark.parametrize("spec,expected", [
    ("4,3", [4, 3]), ("2.0:2.8:0.4", [2.0, 2.4, 2.8]), ("1:4:1", [1, 2, 3, 4]), ("2.2:12:0.05", None),
    ('"pitch","root",80.0', ["pitch", "root", 80.0]), ("5", [5]), ("3:1:-1", [3, 2, 1]),
])
def test_parse_spec(spec, expected):
    got = sw.parse_spec("k", spec)
    if expected is None:
        assert len(got) == 197 and got[0] == 2.2 and got[-1] == 12.0  # stop included when on the grid
    else:
        assert got == expected


@pytest.mark.parametrize("bad", ["1:2", "a:b:c", "1:2:0", "2:1:1", ""])
def test_parse_spec_errors(bad):
    with pytest.raises(sw.SweepError):
        sw.parse_spec("k", bad)


def point_by_point(path, axes, options):
    raw = tomllib.loads(path.read_text())
    from gearcalc import registry
    from gearcalc.design import apply_set, validate

    out = []
    for p in sw.grid_points(axes):
        trial = copy.deepcopy(raw)
        apply_set(trial, list(p.items()))
        d = validate(trial, str(path))
        out.append({**p, **registry.get("rows").compute(d, options).summary, "error": None})  # a sweep row ends in it
    return out


@pytest.mark.parametrize("path,axes,model", [
    (FIG3, {"rows.count": [4, 3], "rows.planets_per_row": [5, 3], "rows.relative_width": [2.0, 2.4, 2.8]}, None),
    (FIG3, {"rows.count": [1, 2, 7], "rows.relative_width": [0.5, 20.0, 60.0]}, None),  # n = 1 and κ ≥ 8
    (FIG3, {"sun.torsion_diameter": ["pitch", "root", 70.0], "material.E_MPa": [1e5, 2e5]}, "exact"),
    (FIG3, {"rows.cheek_ratio": [0.0, 0.5], "sun.bore_mm": [0.0, 40.0]}, "continuous"),
    (FIG5, {"rows.count": [1, 2, 3, 4], "gear.ratio": [2.5, 3.5, 6.0]}, None),
    (FIG5, {"mass.wall_ratio": [0.0, 0.06, 0.2], "mass.unevenness": [1.0, 1.4]}, None),
])
def test_vectorised_sweep_equals_point_by_point(path, axes, model):
    opts = Options(tol=1e-8, model=model)
    raw = tomllib.loads(path.read_text())
    fast = sw.evaluate(raw, str(path), axes, opts)
    fast = fast.rows() if hasattr(fast, "rows") else fast
    slow = point_by_point(path, axes, opts)
    assert len(fast) == len(slow)
    for a, b in zip(fast, slow):
        assert set(a) == set(b)
        for k in a:
            if isinstance(b[k], float):
                if k.startswith("ratio_opt") or k.startswith("relative_mass_min") or k == "ratio":
                    # both are golden-section results to --tol on the same function: agree within the error
                    assert a[k] == pytest.approx(b[k], rel=1e-6, abs=2 * b.get("ratio_opt_err", 0)), k
                else:
                    assert a[k] == pytest.approx(b[k], rel=1e-12, abs=1e-14), k
            else:
                assert a[k] == b[k], k


def test_fig3_and_fig5_from_one_command_each():
    r = cli("sweep", FIG3, "--vary", "rows.count=4,3", "--vary", "rows.planets_per_row=5,3",
            "--vary", "rows.relative_width=2.0:2.8:0.02")
    rows = list(csv.DictReader(io.StringIO(r.out)))
    assert r.code == 0 and len(rows) == 4 * 41
    at = {(int(x["rows.count"]), int(x["rows.planets_per_row"]), x["rows.relative_width"]): float(x["K"])
          for x in rows}
    assert round(at[(3, 3, "2.4")], 3) == 1.489  # the paper's stated value
    r = cli("sweep", FIG5, "--vary", "rows.count=1,2,3,4", "--vary", "gear.ratio=2.2:12:0.05", "--format", "json")
    pts = json.loads(r.out)
    assert r.code == 0 and len(pts) == 4 * 197
    assert all("relative_mass_kg_per_kNm" in p for p in pts)


def test_sweep_with_bridges_falls_back_point_by_point():
    r = cli("sweep", CONFIGS / "rows_bridges_n4_B4_i6.toml", "--vary", "gear.ratio=6,10", "--format", "json")
    pts = json.loads(r.out)
    assert r.code == 0 and [round(p["bridge_rel_3"], 2) for p in pts] == [0.40, 0.18]


def test_sweep_bad_value_names_key_and_value():
    r = cli("sweep", FIG3, "--vary", "rows.count=3,0")
    assert r.code == 2 and "rows.count=0" in r.err and "rows.count" in r.err
    r = cli("sweep", FIG3, "--vary", "rows.cont=3")
    assert r.code == 2 and "did you mean 'rows.count'" in r.err
    r = cli("sweep", FIG3, "--vary", "rows.count")
    assert r.code == 2 and "KEY=SPEC" in r.err


def test_sweep_combination_error(tmp_path):
    # each value is valid alone, the combination is not: a bore beyond the root of the smaller module
    r = cli("sweep", FIG3, "--vary", "gear.module_mm=2,5", "--vary", "sun.bore_mm=0,60")
    assert r.code == 2 and "sun.bore_mm" in r.err


def test_jobs_give_identical_sweep():
    args = ["sweep", FIG5, "--vary", "rows.count=1,2,3,4", "--vary", "gear.ratio=2.2:12:0.5", "--format", "csv"]
    one, four = cli(*args), cli(*args, "--jobs", "4")
    assert one.code == four.code == 0 and one.out == four.out
    args = ["sweep", CONFIGS / "rows_bridges_n4_B4_i6.toml", "--vary", "gear.ratio=4,6,10", "--format", "json"]
    assert cli(*args).out == cli(*args, "-j", "3").out  # point by point in the workers


def test_columnar_csv_equals_row_csv():
    from gearcalc.render import Columns, write_csv, write_csv_columns

    rows = [{"a": 1.5, "name": "x, y", "l": [1, 2], "n": None, "b": True}, {"a": 2.0, "name": 'q"q', "b": False,
                                                                           "l": [], "n": None}]
    assert write_csv_columns(Columns.from_rows(rows)) == write_csv(rows)


@settings(max_examples=150, deadline=None, derandomize=True)
@given(st.lists(st.sampled_from([0.0, -0.0, 1.0, 0.1, 1e-300, -2.5, 1e16, None]), min_size=1, max_size=12),
       st.data())
def test_columnar_csv_reuses_only_identical_float_columns(base, data):
    # the writer reuses the text of a float column equal bit for bit to an earlier one; the row-by-row
    # writer (csv_cell per value) is the reference. 0.0 == -0.0 but their text differs, so do their bits.
    from gearcalc.render import Columns, write_csv, write_csv_columns

    twin = list(base)
    flips = data.draw(st.lists(st.integers(0, len(base) - 1), max_size=3))
    for k in flips:  # a sign flip of a zero, or a None, is a different column
        twin[k] = -twin[k] if isinstance(twin[k], float) else 0.0
    rows = [{"a": a, "b": b, "c": a} for a, b in zip(base, twin)]
    assert write_csv_columns(Columns.from_rows(rows)) == write_csv(rows)


# ---------------------------------------------------------------- the grid as a lazy sequence

@settings(max_examples=200, deadline=None, derandomize=True)
@given(st.lists(st.integers(1, 4), min_size=1, max_size=4), st.data())
def test_grid_equals_the_product_of_its_axes(sizes, data):
    # the reference: itertools.product, first axis slowest (the documented order of the sweep's rows)
    import itertools

    axes = {f"k{i}": [10 * i + v for v in range(n)] for i, n in enumerate(sizes)}
    ref = [dict(zip(axes, combo)) for combo in itertools.product(*axes.values())]
    grid = sw.grid_points(axes)
    assert len(grid) == len(ref) and list(grid) == ref
    assert [grid[k] for k in range(-len(ref), len(ref))] == ref + ref
    a = data.draw(st.integers(0, len(ref)))
    b = data.draw(st.integers(0, len(ref)))
    part = grid[a:b]
    assert list(part) == ref[a:b] and len(part) == len(ref[a:b])
    for key in axes:
        assert grid.column(key) == [p[key] for p in ref]
        assert part.column(key) == [p[key] for p in ref[a:b]]
    with pytest.raises(IndexError):
        grid[len(ref)]


def test_csv_sweep_with_undefined_stepwise_values():
    # regression: a float column with some None (K_stepwise where the stepwise level does not exist,
    # rows.md §6, at large B) made the columnar CSV writer fail (exit 70); the JSON says which are null
    args = ["sweep", FIG3, "--vary", "rows.count=4", "--vary", "rows.relative_width=1:30:1"]
    as_csv, as_json = cli(*args, "-f", "csv"), cli(*args, "-f", "json")
    assert as_csv.code == as_json.code == 0, as_csv.err
    rows = list(csv.DictReader(io.StringIO(as_csv.out)))
    nulls = [r["K_stepwise"] is None for r in json.loads(as_json.out)]
    assert 0 < sum(nulls) < len(nulls)  # the case mixes defined and undefined values
    assert [r["K_stepwise"] == "" for r in rows] == nulls


# ----------------------------------------------------------------------------- vectorised range axes (issue 14)
def _scalar_values(r: sw.Range, ks) -> list[float]:
    """Value k of a range as the per-point path computes it: start + k*step rounded through 12 digits."""
    return [float(f"{r.start + k * r.step:.12g}") for k in ks]


def _bits(values) -> bytes:
    import numpy as np

    return np.asarray(values, dtype=np.float64).tobytes()  # 0.0 and -0.0 differ


AWKWARD_RANGES = [
    pytest.param(1.5, 1.5 / (1e6 - 1), 1_000_000, marks=pytest.mark.slow),  # a million points: long (CI)
    (0.0, 0.1, 200_000), (0.0, 1 / 3, 300_000), (5.0, -0.1, 200_000),
    (-3.0, 1e-5, 600_001), (1e11, 0.37, 100_000), (9.99999, 1e-7, 200_000), (1e-12, 1e-13, 100_000),
    pytest.param(-1.0, 2e-6, 1_000_001, marks=pytest.mark.slow),
    (123456.789, 0.001, 200_000), (2.2, 0.005, 1961), (0.999999999999, 1e-13, 50_000),
    (-0.0, -0.1, 10), (0.0, -0.1, 10), (1e15, 1.0, 10_000), (99999999999.5, 0.25, 20_000), (1e300, -1e297, 100),
    (3.0, -1.5 / (2.5e5 - 1), 250_000),
]


@pytest.mark.parametrize("start,step,count", AWKWARD_RANGES)
def test_range_take_is_bit_identical_to_per_point_values(start, step, count):
    import numpy as np

    r = sw.Range(start, step, count)
    assert _bits(r.take(np.arange(count))) == _bits(_scalar_values(r, range(count)))
    assert r[count // 3:count // 3 + 7] == _scalar_values(r, range(count // 3, count // 3 + 7))
    assert _bits(r[-5:]) == _bits([r[k] for k in range(count - 5, count)])


@pytest.mark.slow  # 300 random ranges: long; the awkward ranges above stay in the quick loop
@settings(max_examples=300, deadline=None)
@given(st.floats(-1e13, 1e13, allow_nan=False), st.floats(1e-10, 1e4) | st.floats(-1e4, -1e-10),
       st.integers(1, 3000), st.integers(0, 10**7))
def test_range_take_random(start, step, count, offset):
    import numpy as np

    r = sw.Range(start, step, offset + count)
    ks = np.arange(offset, offset + count)
    assert _bits(r.take(ks)) == _bits(_scalar_values(r, ks.tolist()))


def test_round12_exact_ties_and_random_doubles():
    import numpy as np

    rng = np.random.default_rng(14)
    ties = np.arange(10**11, 10**11 + 20_000) + 0.5  # exactly half way at the 12th digit: half to even
    spread = rng.uniform(-1, 1, 50_000) * 10.0 ** rng.uniform(-14, 14, 50_000)
    bits = rng.integers(0, 2**63 - 1, 20_000).view(np.float64)
    x = np.concatenate([ties, ties * 0.5, ties * 2.0 ** -10, spread, bits,
                        [0.0, -0.0, 1e-11, 1e12, 999999999999.5]])
    x = x[np.isfinite(x)]
    assert _bits(sw.round12(x)) == _bits([float(f"{v:.12g}") for v in x.tolist()])


def test_grid_column_array_of_a_lazy_range():
    import numpy as np

    r = sw.Range(1.5, 0.1 / 3, 200_001)
    g = sw.Grid({"rows.count": [2, 3], "rows.relative_width": r, "x": [1, 2, 3]})
    part = g[123_456:123_456 + 70_000]
    for key in ("rows.count", "rows.relative_width", "x"):
        listed = part.column(key)
        assert listed == [p[key] for p in part] and type(listed) is list
        arr = part.column(key, True)
        if key == "rows.relative_width":
            assert isinstance(arr, np.ndarray) and _bits(arr) == _bits(listed)
        else:
            assert arr == listed


@pytest.mark.slow
def test_stream_arrays_same_csv_and_json_as_lists():
    """Chunks with float64 array columns (the CLI's CSV path) write the same bytes as chunks of lists, and the
    public chunks (arrays=False) hold lists only."""
    import numpy as np

    from gearcalc.render import csv_blocks, json_array_piece

    raw = tomllib.loads(FIG3.read_text())
    axes = {"rows.count": [2, 3], "rows.relative_width": sw.Range(1.5, 1.5 / 4099, 4100)}
    opts = Options(tol=1e-9)
    with_arrays = list(sw.stream(raw, str(FIG3), axes, opts, chunk=3000, arrays=True))
    plain = list(sw.stream(raw, str(FIG3), axes, opts, chunk=3000))
    assert any(isinstance(v, np.ndarray) for p in with_arrays for v in p.data.values())
    assert all(type(v) is list for p in plain for v in p.data.values())
    for a, b in zip(with_arrays, plain, strict=True):
        assert a.lists().data == b.data and a.rows() == b.rows()
        first = a is with_arrays[0]
        assert b"".join(csv_blocks(a, first, binary=True)) == "".join(csv_blocks(b, first)).encode()
        assert json_array_piece(a, first) == json_array_piece(b, first)
    joined = sw.join_parts(with_arrays)
    assert joined.lists().data == sw.join_parts(plain).data


def test_csv_of_float_arrays_equals_csv_of_lists():
    import numpy as np

    from gearcalc.render import Columns, NonFiniteOutput, write_csv_columns

    rng = np.random.default_rng(3)
    for n in (3, 600, 9000):
        x = rng.normal(size=n) * 10.0 ** rng.integers(-8, 18, n)
        x[:2] = [-0.0, 0.0]
        cols = {"x": x, "same": x.copy(), "const": np.full(n, 2.5), "zeros": np.zeros(n), "mixed": [1.5] * n,
                "word": ["a"] * n, "scaled": x * 3}
        as_lists = {k: v.tolist() if isinstance(v, np.ndarray) else v for k, v in cols.items()}
        assert write_csv_columns(Columns(cols)) == write_csv_columns(Columns(as_lists))
        bad = x.copy()
        bad[-1] = np.inf
        with pytest.raises(NonFiniteOutput):
            write_csv_columns(Columns({"x": bad}))


def test_csv_formatted_in_the_workers_is_the_same_output_exit_and_message():
    # --jobs: each chunk is counted (failed points) and formatted as CSV in its worker (render.CsvRenderer);
    # the bytes, the failed-point message and the exit status are those of the in-process sweep.  The paper
    # bridge case fails its check above rows.relative_width = 2.973 (README), so some points fail (exit 1).
    paper = CONFIGS.parent / "paper" / "rows_bridges_n3_B3_i4.toml"
    args = ["sweep", paper, "--vary", "rows.relative_width=2.5:3.2:0.01", "--vary", "rows.count=3,4",
            "--format", "csv", "--fields", "K,bridges_feasible"]
    one, two = cli(*args), cli(*args, "--jobs", "2")
    assert one.code == 1 and "points fail bridge_fit" in one.err
    assert (two.code, two.out, two.err) == (one.code, one.out, one.err)
    assert one.out.splitlines()[0] == "rows.relative_width,rows.count,K,bridges_feasible"
    assert len(one.out.splitlines()) == 1 + 71 * 2


def test_range_column_computed_once_per_grid_and_handed_out_as_copies():
    from gearcalc.grid import Grid, Range

    g = Grid({"a": Range(1.5, 0.1, 200_000), "b": [1, 2]}, 10, 5000)
    first = g.column("a", True)
    first[:] = -1.0  # a caller's changes stay its own
    again = g.column("a", True)
    assert again is not first and again.tolist() == g.column("a") == [p["a"] for p in g]


def test_keep_freed_memory_is_idempotent():
    import platform

    from gearcalc.grid import keep_freed_memory

    assert keep_freed_memory() == keep_freed_memory() == (platform.libc_ver()[0] == "glibc")


def test_jobs_csv_through_shared_slots_or_the_pipe_is_the_same_file(tmp_path, monkeypatch):
    # --jobs: a chunk's CSV text comes back through a shared slot (grid.Slots) where the workers are forked, and
    # through the pool's pipe when it does not fit a slot; the file is the same either way, and as with --jobs 1
    import multiprocessing

    args = ["sweep", FIG3, "--vary", "rows.relative_width=1.5:3.0:0.0001", "--format", "csv"]
    assert cli(*args, "-o", tmp_path / "one.csv").code == 0
    seen = []
    finished = sw._finished
    monkeypatch.setattr(sw, "_finished", lambda result, *a: seen.append(type(result).__name__) or finished(result, *a))
    assert cli(*args, "-o", tmp_path / "slots.csv", "--jobs", "2").code == 0
    forked = multiprocessing.get_context().get_start_method() == "fork"
    assert seen and set(seen) == ({"_InSlot"} if forked else {"CsvPiece"})
    seen.clear()
    monkeypatch.setattr(sw, "SLOT_BYTES", 4096)  # no chunk fits: every text through the pipe
    assert cli(*args, "-o", tmp_path / "pipe.csv", "--jobs", "2").code == 0
    assert seen and set(seen) == {"CsvPiece"}
    one = (tmp_path / "one.csv").read_bytes()
    assert len(one.splitlines()) == 1 + 15001
    assert (tmp_path / "slots.csv").read_bytes() == one == (tmp_path / "pipe.csv").read_bytes()


def test_slots_only_where_workers_are_forked():
    import multiprocessing

    assert sw.Slots.make(4, multiprocessing.get_context("spawn")) is None
    if "fork" in multiprocessing.get_all_start_methods():
        slots = sw.Slots.make(2, multiprocessing.get_context("fork"))
        slot = slots.take()
        assert slots.store(slot, [b"ab", bytearray(b"c"), memoryview(b"de")]) == 5
        assert bytes(slots.view(slot, 5)) == b"abcde"
        assert slots.store(slot, [b"x" * (slots.size + 1)]) is None  # too large: the caller uses the pipe
        slots.give(slot)
        slots.close()


# ---------------------------------------------------------------- the cost of a sweep, estimated before it starts
BRIDGES = {"kind": "rows", "gear": {"sun_teeth": 18, "module_mm": 5.0, "ratio": 6.0},
           "rows": {"count": 3, "planets_per_row": 3, "relative_width": 3.0}, "sun": {"torque_Nm": 1e3},
           "bridges": {}}


def test_the_cost_rule_is_one_for_every_kind():
    # the same budget (600 s) takes a pins contact-level grid of 1e4 points (kinds/pins.py sweep_cost: 0.22 ms a
    # pin and pass x 62 pins x 3 passes = 41 ms a point: 409 s) and refuses 2e4 (818 s), unless 10 processes
    # share it
    from conftest import CONFIGS
    from gearcalc import grid
    from gearcalc.calculator import Options

    raw = gearcalc.design.read_toml(CONFIGS / "pins_paper_circ_u30_rotating.toml")
    axes = {"friction.sliding": grid.Range(0.01, 1e-5, 10_000)}
    total, seconds = grid.prepare(raw, "x.toml", axes, Options())
    assert total == 10_000 and grid.cost_problem(axes, total, seconds) is None
    big = {"friction.sliding": grid.Range(0.01, 1e-6, 20_000)}
    assert "20000 points" in grid.cost_problem(big, 20_000, seconds)
    assert grid.cost_problem(big, 20_000, seconds, workers=10) is None  # --jobs 10


@pytest.mark.slow
def test_costly_points_make_small_chunks():
    # a contact-level point costs ~41 ms (kinds/pins.py sweep_cost): chunks of about a second's work
    # (grid.FIRST_OUTPUT_SECONDS), so a streamed sweep shows its first rows at once, not after 65 536 points
    from conftest import CONFIGS
    from gearcalc import grid

    raw = gearcalc.design.read_toml(CONFIGS / "pins_paper_circ_u30_rotating.toml")
    seconds = grid.prepare(raw, "x.toml", {"friction.sliding": [0.1]})[1]
    size = grid.chunk_points(seconds)
    assert 1 <= size < 64 and size == int(grid.FIRST_OUTPUT_SECONDS / seconds)
    parts = list(gearcalc.sweep(raw, {"friction.sliding": [0.05 + 0.001 * k for k in range(size + 1)]}))
    assert [p.n for p in parts] == [size, 1]
    # cheap vectorised points keep big chunks (rows with bridges, n = 3: 22 us a point, 45 454 points)
    assert grid.chunk_points(grid.prepare(BRIDGES, "x.toml", {"rows.count": [3]})[1]) > 10_000


# ---------------------------------------------------------------- a chunk reads its own points (issue 36 item 8)
# The work a chunk of a sweep does follows the chunk, not the grid: counted, not timed.
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


# ---------------------------------------------------------------- a point that is not a valid design (issue 36 item 1)
def test_invalid_sweep_points_are_rows_and_the_sweep_goes_on():
    # the example of the issue: R_H = 50 and 55 leave no room for the rollers with R_B = 50 and e = 6
    r = cli("sweep", CONFIGS / "zstk_merko_example.toml", "--vary", "geometry.outer_raceway_radius_mm=50:70:5",
            "--format", "csv", "--fields", "sigma_max_MPa,margin_sigma,failed_checks,error")
    assert r.code == 2, r
    rows = list(csv.DictReader(io.StringIO(r.out)))
    assert [x["geometry.outer_raceway_radius_mm"] for x in rows] == ["50", "55", "60", "65", "70"]
    assert rows[0]["error"].startswith("geometry.inner_raceway_radius_mm = 50: must be < outer_raceway_radius_mm")
    assert rows[1]["error"].startswith("geometry.eccentricity_mm = 6: must be")
    assert rows[0]["sigma_max_MPa"] == rows[1]["sigma_max_MPa"] == ""
    assert all(x["error"] == "" and float(x["sigma_max_MPa"]) > 0 for x in rows[2:])
    assert "2 of 5 points have no results" in r.err and "at {'geometry.outer_raceway_radius_mm': 50}" in r.err
    # the API: the same rows, the messages in Columns.errors
    (part,) = gearcalc.sweep(CONFIGS / "zstk_merko_example.toml",
                             {"geometry.outer_raceway_radius_mm": [50.0, 55.0, 60.0]})
    assert [e is None for e in part.data["error"]] == [False, False, True] and len(part.errors) == 2
    # a key the kind does not have is still refused before the sweep starts
    r = cli("sweep", CONFIGS / "zstk_merko_example.toml", "--vary", "geometry.outer_radius_mm=50:70:5")
    assert r.code == 2 and "outer_radius_mm" in r.err and not r.out


# ---------------------------------------------------------------- grids that cannot be built (issue 13)
PINS = CONFIGS / "pins_paper_cyc_u10_rotating.toml"


def test_sweep_point_cap_is_refused_without_materialising():
    # 1e300 points: refused from the arithmetic alone (the grid is never built): the peak memory of both refusals
    # (measured 2.9 MB, the first call's imports included) stays far below the 808 MB of the 1.01e8 points as floats
    import tracemalloc

    tracemalloc.start()
    try:
        with pytest.raises(sw.SweepError, match="more than the cap"):
            sw.parse_spec("k", "1:1e300:1")
        with pytest.raises(sw.SweepError, match="more than"):
            sw.parse_vary(["a=1:1000:1", "b=1:1000:1", "c=1:101:1"])  # 1.01e8 points > MAX_POINTS = 1e8
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < 50_000_000, peak


@pytest.mark.parametrize("spec,message", [
    ("1:2:5e-324", "step is too small"),                 # (2-1)/5e-324 = inf: OverflowError before
    ("1e308:-1e308:-1e300", "overflows"),               # stop - start = -inf: OverflowError before
    ("1:1.0000000000000002:1e-17", "resolution"),       # 1 + 1e-17 == 1: every point the same number
    ("1e400:2:1", "finite"),
])
def test_vary_specs_whose_arithmetic_overflows_exit_2(spec, message):
    with pytest.raises(sw.SweepError, match=message):
        sw.parse_spec("gearing.eccentricity_mm", spec)
    r = cli("sweep", PINS, "--vary", f"gearing.eccentricity_mm={spec}")
    assert r.code == 2, r
    assert "Traceback" not in r.err
