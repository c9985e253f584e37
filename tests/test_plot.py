"""--plot renders a PNG for a design and for a sweep (matplotlib, the plot extra)."""
import pytest

from conftest import CONFIGS, cli

pytest.importorskip("matplotlib")
PNG = b"\x89PNG\r\n\x1a\n"


def check_png(path, min_bytes=10_000):
    data = path.read_bytes()
    assert data[:8] == PNG and len(data) > min_bytes  # a real figure, not an empty canvas


def test_rows_sweep_plots_fig3_and_fig5(tmp_path):
    out = tmp_path / "fig3.png"
    r = cli("sweep", CONFIGS / "rows_fig3_n3_nw3_B2.4.toml", "--vary", "rows.count=4,3",
            "--vary", "rows.planets_per_row=5,3", "--vary", "rows.relative_width=2.0:2.8:0.1", "--plot", out)
    assert r.code == 0
    check_png(out)
    out = tmp_path / "fig5.png"
    r = cli("sweep", CONFIGS / "rows_mass_fig5.toml", "--vary", "rows.count=1,2,3,4",
            "--vary", "gear.ratio=2.2:12:0.2", "--plot", out)
    assert r.code == 0
    check_png(out)


def test_plot_folder_missing(tmp_path):
    r = cli("rows", CONFIGS / "rows_fig3_n3_nw3_B2.4.toml", "--plot", tmp_path / "no" / "x.png")
    assert r.code == 2 and "does not exist" in r.err


@pytest.mark.parametrize("kind,config", [
    ("rows", "rows_fig3_n3_nw3_B2.4.toml"),           # row loads along the sun face
    ("zstk", "zstk_merko_example.toml"),              # one position: Fig. 2 (sigma vs roller radius) + the chain
    ("zstk", "zstk_merko_A_envelope.toml"),           # envelope over load directions
    ("pins", "pins_paper_cyc_u10_rotating.toml"),     # ideal level: F, n_pin, P of one pin (Figs. 8-11), lambda
    ("pins", "pins_paper_formula_cyc_u10.toml"),      # formula level: the per-pin loss bars
])
def test_design_plot(tmp_path, kind, config):
    out = tmp_path / f"{kind}.png"
    r = cli(kind, CONFIGS / config, "--plot", out)
    assert r.code == 0
    check_png(out)


@pytest.mark.parametrize("config,vary", [
    ("zstk_merko_example.toml", ["load.radial_N=1000:20000:1000"]),
    ("pins_paper_cyc_u10_fixed.toml", ["friction.sliding=0.02:0.2:0.02", "load.mode=multiplier,reducer"]),
])
def test_sweep_plots_of_zstk_and_pins(tmp_path, config, vary):
    out = tmp_path / "sweep.png"
    args = []
    for v in vary:
        args += ["--vary", v]
    r = cli("sweep", CONFIGS / config, *args, "--plot", out)
    assert r.code == 0, r.err
    check_png(out)


def test_plot_of_a_mixed_batch_draws_the_first_kind(tmp_path):
    out = tmp_path / "mixed.png"
    r = cli("run", CONFIGS / "rows_fig3_n3_nw3_B2.4.toml", CONFIGS / "zstk_merko_example.toml", "--plot", out,
            "--format", "json")
    assert r.code == 0
    check_png(out)
