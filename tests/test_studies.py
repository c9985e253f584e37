"""Studies that scale and resume (issue 36 item 6): ``sweep -o FILE.parquet``, ``--resume`` (CSV and Parquet,
``--jobs``, ``--scheduler``), ``gearcalc.sweep_grid(...).to_xarray()``.  gearcalc/studies.py.

An interrupted run is compared with an uninterrupted run of the same command: byte for byte (CSV), row for row
(Parquet).  One test interrupts with a real SIGINT once the partial output holds a complete chunk; the others stop
after k chunks through the test hook ``_GEARCALC_STOP_AFTER_CHUNKS`` (the same KeyboardInterrupt path)."""
from __future__ import annotations

import csv as csv_module
import json
import signal
import subprocess
import sys
import time

import pytest

from conftest import CONFIGS, cli, cli_proc

pa = pytest.importorskip("pyarrow")
pq = pytest.importorskip("pyarrow.parquet")

DESIGN = CONFIGS / "rows_fig3_c1_n4_nw5_B2.0.toml"
SMALL = ["--vary", "rows.relative_width=1:3:0.0005", "--vary", "rows.count=3,4"]
"""8 002 points: with --jobs 2 chunks of 1 001 (8 002 / (4 x 2)), 8 chunks."""
BIG = ["--vary", "rows.relative_width=1:3:0.000005"]
"""400 001 points: chunks of 65 536 (grid.CHUNK_POINTS: the vectorised rows path, ~3 us a point), 7 chunks."""


def _record(path):
    rec = path.parent / f".{path.name}.partial.json"
    return json.loads(rec.read_text()) if rec.exists() else None


def _leftovers(folder):
    return sorted(p.name for p in folder.iterdir() if p.name.startswith("."))


def _stopped(monkeypatch, k, *args, design=DESIGN):
    """Run the sweep in process, stopped (as by Ctrl-C) after k complete chunks."""
    monkeypatch.setenv("_GEARCALC_STOP_AFTER_CHUNKS", str(k))
    r = cli("sweep", design, *args)
    monkeypatch.delenv("_GEARCALC_STOP_AFTER_CHUNKS")
    assert r.code == 130, r
    return r


@pytest.mark.slow
def test_resume_after_sigint_is_byte_identical(tmp_path):
    ref, out = tmp_path / "ref.csv", tmp_path / "out.csv"
    assert cli("sweep", DESIGN, *BIG, "-o", ref).code == 0
    out.write_text("the old content\n")
    proc = subprocess.Popen([sys.executable, "-m", "gearcalc", "sweep", str(DESIGN), *BIG, "-o", str(out),
                             "--resume"], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 120
    while proc.poll() is None and time.monotonic() < deadline:  # ready: the partial output holds a chunk
        rec = _record(out)
        if rec and rec["chunks"] >= 1:
            proc.send_signal(signal.SIGINT)
            break
        time.sleep(0.01)
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == 130, err
    rec = _record(out)
    assert 1 <= rec["chunks"] < 7 and rec["chunk_points"] == 65536
    assert out.read_text() == "the old content\n"  # the target is replaced only when the sweep is complete
    partial = tmp_path / ".out.csv.partial"
    assert partial.stat().st_size >= rec["bytes"]
    r = cli_proc("sweep", DESIGN, *BIG, "-o", out, "--resume")
    assert r.code == 0, r
    assert out.read_bytes() == ref.read_bytes()
    assert _leftovers(tmp_path) == []


def test_resume_with_jobs_is_byte_identical(tmp_path, monkeypatch):
    ref, out = tmp_path / "ref.csv", tmp_path / "out.csv"
    assert cli("sweep", DESIGN, *SMALL, "-o", ref).code == 0
    _stopped(monkeypatch, 3, *SMALL, "-o", out, "--resume", "--jobs", "2")
    assert _record(out)["chunks"] == 3 and _record(out)["chunk_points"] == 1001
    assert not out.exists()
    _stopped(monkeypatch, 5, *SMALL, "-o", out, "--resume")  # --jobs 1 now: the recorded chunks still
    assert _record(out)["chunks"] == 5
    r = cli("sweep", DESIGN, *SMALL, "-o", out, "--resume", "--jobs", "2")
    assert r.code == 0, r
    assert out.read_bytes() == ref.read_bytes()
    assert _leftovers(tmp_path) == []


def test_resume_keeps_the_exit_status_and_counts(tmp_path, monkeypatch):
    """Points failing their check only in the chunks of the interrupted run still make the resumed run exit 1,
    with the same count: the loads fall along the grid, the high ones (pass = false: 630 of 1 996, chunks of 250)
    come first."""
    args = ["--vary", "load.radial_N=400000:1000:-200", "--jobs", "2"]
    design = CONFIGS / "zstk_merko_A_gap.toml"
    ref = cli("sweep", design, *args, "-o", tmp_path / "ref.csv")
    assert ref.code == 1 and "630 of 1996 points fail sigma" in ref.err, ref
    _stopped(monkeypatch, 3, *args, "-o", tmp_path / "out.csv", "--resume", design=design)
    r = cli("sweep", design, *args, "-o", tmp_path / "out.csv", "--resume")
    assert (r.code, r.err) == (ref.code, ref.err)
    assert (tmp_path / "out.csv").read_bytes() == (tmp_path / "ref.csv").read_bytes()


def test_parquet_resume_is_row_identical(tmp_path, monkeypatch):
    ref, out = tmp_path / "ref.parquet", tmp_path / "out.parquet"
    assert cli("sweep", DESIGN, *SMALL, "-o", ref, "--jobs", "2").code == 0
    _stopped(monkeypatch, 2, *SMALL, "-o", out, "--resume", "--jobs", "2")
    partial = tmp_path / ".out.parquet.partial"
    assert pq.ParquetFile(partial).num_row_groups == 2  # a Parquet file of the complete chunks
    _stopped(monkeypatch, 5, *SMALL, "-o", out, "--resume")  # its 2 row groups copied, 3 more
    assert pq.ParquetFile(partial).num_row_groups == 5
    assert cli("sweep", DESIGN, *SMALL, "-o", out, "--resume").code == 0
    a, b = pq.read_table(ref), pq.read_table(out)
    assert a.schema == b.schema and a.equals(b)
    assert pq.ParquetFile(out).num_row_groups == 8  # one a chunk
    assert _leftovers(tmp_path) == []


@pytest.mark.slow
def test_parquet_types_values_and_metadata(tmp_path):
    out = tmp_path / "s.parquet"
    r = cli("sweep", DESIGN, *SMALL, "-o", out, "--tol", "1e-7")
    assert r.code == 0, r
    t = pq.read_table(out)
    csv = cli("sweep", DESIGN, *SMALL, "--format", "csv", "--tol", "1e-7").out.splitlines()
    assert t.num_rows == len(csv) - 1 == 8002
    types = dict(zip(t.schema.names, t.schema.types))
    assert types["rows.count"] == types["rows"] == pa.int64()
    assert types["K"] == types["rows.relative_width"] == pa.float64()
    assert types["stepwise_valid"] == pa.bool_() and types["name"] == pa.string()
    assert types["unloaded_rows"] == pa.list_(pa.float64())
    # the values are the CSV's (the CSV writes Python's repr of each float: the same double)
    last = list(csv_module.DictReader(csv))[-1]
    row = t.slice(t.num_rows - 1).to_pylist()[0]
    assert row["K"] == float(last["K"]) and row["rows.count"] == int(last["rows.count"])
    meta = pq.read_metadata(out).metadata
    assert meta[b"gearcalc.gearcalc_version"] == b"0.2.0"
    assert meta[b"gearcalc.tol"] == b"1e-07" and meta[b"gearcalc.model"] == b""
    assert meta[b"gearcalc.chunk_points"] == b"65536"
    axes = json.loads(meta[b"gearcalc.axes"])  # a range of up to grid.LAZY_FROM values is its list of values
    assert list(axes) == ["rows.relative_width", "rows.count"] and axes["rows.count"] == [3, 4]
    assert axes["rows.relative_width"][:3] == [1.0, 1.0005, 1.001] and len(axes["rows.relative_width"]) == 4001
    big = tmp_path / "big.parquet"
    assert cli("sweep", DESIGN, *BIG, "--fields", "K", "-o", big).code == 0
    assert json.loads(pq.read_metadata(big).metadata[b"gearcalc.axes"]) == {  # a lazy range: its definition
        "rows.relative_width": {"start": 1.0, "step": 5e-06, "count": 400001, "ints": False}}
    assert len(meta[b"gearcalc.design_sha256"]) == 64


def test_parquet_sample_metadata(tmp_path):
    out = tmp_path / "s.parquet"
    r = cli("sweep", DESIGN, "--vary", "rows.relative_width=1:3", "--sample", "sobol:64", "--seed", "7", "-o", out)
    assert r.code == 0, r
    meta = pq.read_metadata(out).metadata
    assert (meta[b"gearcalc.sampler"], meta[b"gearcalc.seed"]) == (b"sobol", b"7")
    assert json.loads(meta[b"gearcalc.axes"])["vary"] == ["rows.relative_width=1:3"]
    assert pq.read_table(out).num_rows == 64


def test_resume_refuses_other_settings(tmp_path, monkeypatch):
    out = tmp_path / "out.csv"
    _stopped(monkeypatch, 2, *SMALL, "-o", out, "--resume", "--jobs", "2")
    before = (tmp_path / ".out.csv.partial").read_bytes()
    r = cli("sweep", DESIGN, *SMALL, "-o", out, "--resume", "--tol", "1e-7", "--set", "rows.planets_per_row=4")
    assert r.code == 2
    assert "other settings" in r.err and "design_sha256" in r.err and "tol (1e-06 then, 1e-07 now)" in r.err
    assert (tmp_path / ".out.csv.partial").read_bytes() == before  # left as it was


@pytest.mark.parametrize("args, words", [
    (["--resume"], "needs -o FILE"),
    (["--resume", "-o", "x.json"], "CSV or Parquet"),
    (["--resume", "-o", "x.csv", "--format", "table"], "CSV or Parquet"),
    (["--format", "parquet", "--plot", "p.png", "-o", "x.parquet"], "--plot"),
    (["--format", "feather"], "table, csv, json, parquet"),
])
def test_usage_errors(tmp_path, monkeypatch, args, words):
    monkeypatch.chdir(tmp_path)
    r = cli("sweep", DESIGN, *SMALL, *args)
    assert r.code == 2 and words in r.err, r
    assert list(tmp_path.iterdir()) == []


def test_parquet_without_pyarrow(tmp_path, monkeypatch):
    monkeypatch.setitem(sys.modules, "pyarrow", None)  # import pyarrow raises ImportError
    r = cli("sweep", DESIGN, *SMALL, "-o", tmp_path / "x.parquet")
    assert r.code == 2 and "pip install 'gearcalc[parquet]'" in r.err
    assert list(tmp_path.iterdir()) == []


def test_sweep_grid_to_xarray():
    xr = pytest.importorskip("xarray")
    import gearcalc

    axes = {"rows.count": [2, 3], "rows.relative_width": [2.0, 2.4, 2.8]}
    g = gearcalc.sweep_grid(DESIGN, axes)
    ds = g.to_xarray()
    assert isinstance(ds, xr.Dataset) and dict(ds.sizes) == {"rows.count": 2, "rows.relative_width": 3}
    # each cell is the row of the same point (the first axis varies slowest)
    for row in g.rows():
        cell = ds.sel({"rows.count": row["rows.count"], "rows.relative_width": row["rows.relative_width"]})
        assert cell["K"].item() == row["K"] and cell["rows"].item() == row["rows"]
    assert g.to_pandas().shape == (6, len(g.data))


@pytest.mark.slow
@pytest.mark.dask
@pytest.mark.xdist_group("dask")
def test_resume_on_scheduler(tmp_path):
    pytest.importorskip("distributed")
    ref, out = tmp_path / "ref.csv", tmp_path / "out.csv"
    assert cli("sweep", DESIGN, *SMALL, "-o", ref).code == 0
    r = cli_proc("sweep", DESIGN, *SMALL, "-o", out, "--resume", "--scheduler", "local:2",
                 env={"_GEARCALC_STOP_AFTER_CHUNKS": "2"})
    assert r.code == 130 and _record(out)["chunks"] == 2, r
    r = cli_proc("sweep", DESIGN, *SMALL, "-o", out, "--resume", "--scheduler", "local:2")
    assert r.code == 0, r
    assert out.read_bytes() == ref.read_bytes()


@pytest.mark.slow
def test_parquet_partial_without_footer_starts_over(tmp_path, monkeypatch):
    """A partial Parquet file whose run was killed hard (SIGKILL: no footer) cannot be read: said, started over."""
    ref, out = tmp_path / "ref.parquet", tmp_path / "out.parquet"
    assert cli("sweep", DESIGN, *SMALL, "-o", ref, "--jobs", "2").code == 0
    _stopped(monkeypatch, 2, *SMALL, "-o", out, "--resume", "--jobs", "2")
    partial = tmp_path / ".out.parquet.partial"
    partial.write_bytes(partial.read_bytes()[:-100])  # as if killed before the footer was written
    r = cli("sweep", DESIGN, *SMALL, "-o", out, "--resume", "--jobs", "2")
    assert r.code == 0 and "was not closed" in r.err and "starting from the first point" in r.err, r
    assert pq.read_table(out).equals(pq.read_table(ref))
    assert _leftovers(tmp_path) == []


def test_csv_partial_shorter_than_recorded_starts_over(tmp_path, monkeypatch):
    ref, out = tmp_path / "ref.csv", tmp_path / "out.csv"
    assert cli("sweep", DESIGN, *SMALL, "-o", ref, "--jobs", "2").code == 0
    _stopped(monkeypatch, 2, *SMALL, "-o", out, "--resume", "--jobs", "2")
    partial = tmp_path / ".out.csv.partial"
    partial.write_bytes(partial.read_bytes()[:-10])
    r = cli("sweep", DESIGN, *SMALL, "-o", out, "--resume", "--jobs", "2")
    assert r.code == 0 and "shorter than recorded" in r.err, r
    assert out.read_bytes() == ref.read_bytes()


def test_resume_refused_before_any_chunk_leaves_nothing(tmp_path):
    """A sweep refused before its first chunk (an axis value the design rejects) leaves no partial output."""
    out = tmp_path / "out.csv"
    r = cli("sweep", DESIGN, "--vary", "rows.relative_width=1:3:0.5", "--vary", "rows.count=3,0", "-o", out,
            "--resume")
    assert r.code == 2, r
    assert list(tmp_path.iterdir()) == []


def test_parquet_floats_plain_words_dictionary(tmp_path):
    """Float columns are written without a dictionary (nearly every value of a sweep is distinct: building one
    and giving it up cost most of the write), words and counts with one (gearcalc/studies.py
    ``_dictionary_columns``)."""
    out = tmp_path / "s.parquet"
    assert cli("sweep", DESIGN, *SMALL, "-o", out).code == 0
    group = pq.ParquetFile(out).metadata.row_group(0)
    encodings = {group.column(k).path_in_schema: group.column(k).encodings for k in range(group.num_columns)}
    assert not any("DICTIONARY" in e for e in encodings["K"] + encodings["rows.relative_width"])
    assert any("DICTIONARY" in e for e in encodings["name"])
    assert any("DICTIONARY" in e for e in encodings["rows.count"])


def test_parquet_floats_byte_stream_split(tmp_path):
    """Float columns are written BYTE_STREAM_SPLIT (the bytes of the values grouped by position before zstd: a
    sweep's smooth values compress to about 60 % and the write is faster, gearcalc/studies.py
    ``_split_columns``); words and counts keep their dictionary, and the values read back are the ones written."""
    out = tmp_path / "s.parquet"
    assert cli("sweep", DESIGN, *SMALL, "-o", out).code == 0
    group = pq.ParquetFile(out).metadata.row_group(0)
    encodings = {group.column(k).path_in_schema: group.column(k).encodings for k in range(group.num_columns)}
    assert all("BYTE_STREAM_SPLIT" in encodings[k] for k in ("K", "rows.relative_width", "kappa"))
    assert "BYTE_STREAM_SPLIT" not in encodings["name"] + encodings["rows.count"]
    csv = tmp_path / "s.csv"
    assert cli("sweep", DESIGN, *SMALL, "-o", csv).code == 0
    table = pq.read_table(out)
    with open(csv, newline="") as f:
        rows = list(csv_module.DictReader(f))
    assert [float(r["K"]) for r in rows] == table.column("K").to_pylist()


def test_parquet_does_not_import_pandas(tmp_path):
    """``pyarrow.array`` imports pandas when it is installed (0.3 s a run); the usual columns are built from their
    numpy buffers instead (gearcalc/studies.py ``_from_buffers``)."""
    pytest.importorskip("pandas")
    out = tmp_path / "s.parquet"
    code = ("import sys; from gearcalc.cli import main\n"
            "try:\n    main()\nexcept SystemExit as e:\n    assert not e.code, e.code\n"
            "print('pandas' in sys.modules)")
    argv = ["sweep", str(DESIGN), *SMALL, "-o", str(out)]
    p = subprocess.run([sys.executable, "-c", code, *argv], capture_output=True, text=True, timeout=300,
                       cwd=tmp_path)
    assert p.returncode == 0, p.stderr
    assert p.stdout.strip() == "False"


@pytest.mark.parametrize("kind, values", [
    ("double", [1.5, None, -0.0, float("inf")]), ("double", [None, None]), ("double", [1.5, 2]),
    ("double", [True, 1.0]), ("int64", [3, None, -1]), ("int64", [2 ** 62, 0]), ("bool", [True, None, False]),
    ("string", ["a", None, "bé", ""]), ("string", ["Fig. 3"] * 5), ("string", ["", ""]),
    ("string", ["a", 1.5, [1]]), ("list_double", [[], []]), ("list_double", [[1.0], [], None]),
    ("list_string", [["bore"], []]), ("list_double", [[2.0, 3.0]] * 3), ("list_double", [[]] * 4),
    ("list_string", [["bore", "rim"]] * 2), ("list_double", [[1], [1.0]]), ("string", [None] * 3 + ["a"]),
    ("list_double", [["a"]] * 2),
])
def test_parquet_columns_as_pyarrow_array_makes_them(kind, values):
    """Each column built from buffers is the array ``pyarrow.array`` makes of it (a word of another type: its
    JSON text), and a value the type does not take is refused as before (the type changes within the sweep)."""
    import numpy as np

    from gearcalc.grid import SweepError
    from gearcalc.studies import _array

    types = {"double": pa.float64(), "int64": pa.int64(), "bool": pa.bool_(), "string": pa.string(),
             "list_double": pa.list_(pa.float64()), "list_string": pa.list_(pa.string())}
    field = pa.field("x", types[kind])
    try:
        want = pa.array([json.dumps(v) if kind == "string" and v is not None and not isinstance(v, str) else v
                         for v in values], type=field.type)
    except (pa.ArrowInvalid, pa.ArrowTypeError, TypeError):
        with pytest.raises(SweepError):
            _array(field, values, len(values))
        return
    got = _array(field, values, len(values))
    got.validate(full=True)
    assert got.equals(want)
    if kind in ("double", "int64", "bool") and None not in values:
        dtype = {"double": float, "int64": np.int64, "bool": bool}[kind]
        try:
            column = np.array(values, dtype=dtype)
        except (OverflowError, TypeError):
            return
        assert _array(field, column, len(values)).equals(pa.array(column, type=field.type))


def test_parquet_errors_and_failed_checks_are_words_from_the_first_chunk(tmp_path):
    """A first chunk without an error or a failed check (None, empty lists) typed those columns float64 and
    list<double>: the first error or failed check of a later chunk stopped the sweep ("changes type").  They are
    words whatever the first chunk holds (gearcalc/studies.py ``ParquetOut.write``)."""
    from gearcalc.render import Columns
    from gearcalc.studies import ParquetOut

    out = tmp_path / "s.parquet"

    class Sink:
        def __init__(self, fh):
            self.fh = fh

        def write(self, data):
            self.fh.write(data)

    with open(out, "wb") as fh:
        w = ParquetOut(Sink(fh), {"gearcalc.test": "1"})
        w.write(Columns({"x": [1.0, 2.0], "failed_checks": [[], []], "error": [None, None]}))
        w.write(Columns({"x": [3.0, None], "failed_checks": [["sigma", "closure"], []],
                         "error": [None, "at the point: not a valid design"]}))
        w.close()
    t = pq.read_table(out)
    assert t.schema.field("error").type == pa.string()
    assert t.schema.field("failed_checks").type == pa.list_(pa.string())
    assert t.column("failed_checks").to_pylist() == [[], [], ["sigma", "closure"], []]
    assert t.column("error").to_pylist() == [None, None, None, "at the point: not a valid design"]
    assert t.column("x").to_pylist() == [1.0, 2.0, 3.0, None]


def test_failed_check_column_shares_one_empty_list():
    """The points failing no check share one empty list (gearcalc/calculator.py ``failed_check_column``: 65 536
    new lists a chunk were a tenth of a rows Parquet sweep's CPU); a failing point has its own list, in the
    checks' order (the expected lists: the margins below zero, by hand)."""
    from gearcalc.calculator import Check, failed_check_column

    cols = {"margin_a": [0.5, -1.0, -2.0, 1.0], "margin_b": [None, -0.1, 3.0, 0.0]}
    out = failed_check_column(cols, [Check("a", ""), Check("b", "")], 4)
    assert out == [[], ["a", "b"], ["a"], []]
    assert out[0] is out[3]
    assert out[1] is not out[2]
