"""--plot renders a PNG for a design and for a sweep (matplotlib, the plot extra)."""
import pytest

from conftest import CONFIGS, cli

pytest.importorskip("matplotlib")
PNG = b"\x89PNG\r\n\x1a\n"


def check_png(path, min_bytes=10_000):
    data = path.read_bytes()
    assert data[:8] == PNG and len(data) > min_bytes  # a real figure, not an empty canvas


def test_rows_design_plot(tmp_path):
    out = tmp_path / "rows.png"
    r = cli("rows", CONFIGS / "rows_fig3_n3_nw3_B2.4.toml", "--plot", out)
    assert r.code == 0
    check_png(out)


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
