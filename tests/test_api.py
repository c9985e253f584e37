"""gearcalc.api: the Python entry points give what the command line gives (the CLI is a skin over them)."""
import json
import subprocess
import sys
import tomllib

import pytest

import gearcalc
from conftest import CONFIGS, PAPER, cli
from gearcalc import grid as sw
from gearcalc.calculator import Options

FIG3 = CONFIGS / "rows_fig3_n3_nw3_B2.4.toml"
BASE = {"kind": "rows", "gear": {"sun_teeth": 18, "module_mm": 5.0},
        "rows": {"count": 3, "planets_per_row": 3, "relative_width": 2.4}, "sun": {"torque_Nm": 1000.0}}


def test_import_gearcalc_is_light():
    # the API is re-exported lazily: importing gearcalc imports neither numpy nor typer
    code = "import sys, gearcalc; assert 'numpy' not in sys.modules and 'typer' not in sys.modules; print('ok')"
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert r.stdout.strip() == "ok", r.stderr


def test_compute_a_dict_a_path_and_a_loaded_design_agree():
    by_dict = gearcalc.compute(BASE)
    by_path = gearcalc.compute(FIG3)
    by_design = gearcalc.compute(gearcalc.load(FIG3))
    assert round(by_dict.summary["K"], 3) == 1.489  # the paper's stated value (seed 004, rows.md §11.1)
    assert by_dict.summary["K"] == by_path.summary["K"] == by_design.summary["K"]


def test_compute_equals_the_cli_json():
    res = gearcalc.compute(FIG3, detail=True)
    obj = json.loads(cli("rows", FIG3, "--format", "json", "--detail").out)
    mine = res.to_dict()
    for key in ("summary", "warnings", "checks_failed", "model", "detail", "design", "name", "kind"):
        assert mine[key] == obj[key], key


def test_overrides_are_set():
    four = gearcalc.compute(FIG3, overrides={"rows.count": 4})
    assert four.summary["rows"] == 4
    assert four.summary["K"] == gearcalc.compute(FIG3, overrides=[("rows.count", 4)]).summary["K"]


def test_unknown_model_is_a_value_error_listing_the_levels():
    with pytest.raises(ValueError, match="stepwise, exact, continuous"):
        gearcalc.compute(BASE, model="exakt")
    assert gearcalc.models("zstk") == ("equilibrium", "fixed-direction", "reference")


def test_bad_input_raises_input_error_with_every_message():
    bad = {**BASE, "rows": {"count": 0, "planets_per_row": 3, "relative_width": 2.4, "colour": "red"}}
    with pytest.raises(gearcalc.InputError) as info:
        gearcalc.compute(bad)
    text = "\n".join(info.value.messages)
    assert "rows.count" in text and "rows.colour" in text


def test_compute_files_returns_records_messages_and_status(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text("kind = 'rows'\n[gear]\n")
    batch = gearcalc.compute_files([FIG3, bad, PAPER / "rows_bridges_n3_B3_i4.toml"])
    assert batch.status == 2  # the worst: bad input
    assert [r.name for r in batch.records] == ["Fig. 3 curve 4, B = 2.4", "Bridge table, n = 3, B = 3, i = 4"]
    assert any("bad.toml" in m for m in batch.messages) and any("check failed" in m for m in batch.messages)
    r = cli("run", FIG3, bad, PAPER / "rows_bridges_n3_B3_i4.toml", "--format", "csv")
    assert r.code == batch.status and r.err.splitlines() == batch.messages


def test_sweep_yields_chunks_in_grid_order_equal_to_the_cli():
    axes = {"rows.relative_width": [2.0, 2.2, 2.4, 2.6, 2.8], "rows.count": [3, 4]}
    parts = list(gearcalc.sweep(FIG3, axes, chunk=3))
    assert [p.n for p in parts] == [3, 3, 3, 1]
    ks = [k for p in parts for k in p.data["K"]]
    whole = list(gearcalc.sweep(FIG3, axes))
    assert len(whole) == 1 and whole[0].data["K"] == ks
    r = cli("sweep", FIG3, "--vary", "rows.relative_width=2.0,2.2,2.4,2.6,2.8", "--vary", "rows.count=3,4",
            "--format", "csv", "--fields", "K")
    assert [float(line.split(",")[2]) for line in r.out.splitlines()[1:]] == ks


def test_sweep_chunk_is_a_pure_function_of_the_index_range():
    import tomllib

    raw = tomllib.loads(FIG3.read_text())
    axes = {"rows.relative_width": [2.0, 2.4, 2.8], "rows.count": [3, 4]}
    whole = gearcalc.sweep_chunk(raw, str(FIG3), axes, 0, 6)
    part = gearcalc.sweep_chunk(raw, str(FIG3), axes, 2, 5)
    assert part.data["K"] == whole.data["K"][2:5]
    assert part.data["rows.count"] == [3, 4, 3]


def test_to_pandas_when_pandas_is_installed():
    pd = pytest.importorskip("pandas")
    res = gearcalc.compute(FIG3, detail=True)
    assert res.to_pandas()["K"][0] == res.summary["K"]
    assert len(res.to_pandas("rows")) == 3 and isinstance(res.to_pandas(), pd.DataFrame)


def test_one_batch_engine_serves_the_cli_and_the_api(monkeypatch):
    # issue 35 item 2: `gearcalc run`, the kind commands and gearcalc.compute_files call the same batch function
    from gearcalc import engine

    real, callers = engine.compute_files, []

    def spy(*args, **kw):
        callers.append(kw.get("option", "--model"))
        return real(*args, **kw)

    monkeypatch.setattr(engine, "compute_files", spy)
    assert cli("run", FIG3, "--format", "json").code == 0
    assert cli("rows", FIG3, "--format", "json", "--model", "bogus").code == 2
    batch = gearcalc.compute_files([FIG3])
    assert batch.status == 0 and len(batch.records) == 1
    assert callers == ["--model", "--model", "model ="]


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
