"""--plot renders a PNG for a design and for a sweep (matplotlib, the plot extra)."""
import pytest

from conftest import CONFIGS, cli
from pins.test_output_mech import W8, _with

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
    pytest.param("pins", "pins_paper_cyc_u10_rotating.toml",       # ideal level: F, n_pin, P of one pin (Figs.
                 marks=pytest.mark.slow),                          # 8-11), lambda; long: CI runs it
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


# ------------------------------------------------------------------------- batches of several kinds
def png_size(path) -> tuple[int, int]:
    """(width, height) in pixels, from the PNG header (IHDR)."""
    import struct

    return struct.unpack(">II", path.read_bytes()[16:24])


ROWS1, ZSTK1 = CONFIGS / "rows_fig3_n3_nw3_B2.4.toml", CONFIGS / "zstk_merko_example.toml"


@pytest.mark.slow
def test_plot_of_a_mixed_batch_draws_every_kind(tmp_path):
    # before: the first kind's figure only, silently; now each kind's figure, stacked top to bottom
    sizes = {}
    for kind, config in (("rows", ROWS1), ("zstk", ZSTK1)):
        out = tmp_path / f"{kind}.png"
        assert cli(kind, config, "--plot", out, "--format", "json").code == 0
        sizes[kind] = png_size(out)
    out = tmp_path / "mixed.png"
    r = cli("run", ROWS1, ZSTK1, "--plot", out, "--format", "json")
    assert r.code == 0, r.err
    check_png(out)
    width, height = png_size(out)
    assert width == max(w for w, _ in sizes.values())
    assert height == sum(h for _, h in sizes.values())
    assert "--plot" not in r.err  # every design drawn: nothing to say


@pytest.mark.slow
def test_designs_a_figure_leaves_out_are_named(tmp_path):
    # a rows figure holds 4 designs (gearcalc/rows/plot.py): the fifth is named on stderr
    files = sorted(CONFIGS.glob("rows_fig3_c1_*.toml")) + sorted(CONFIGS.glob("rows_fig3_c2_*.toml"))[:2]
    out = tmp_path / "rows.png"
    r = cli("run", *files, "--plot", out, "--format", "json")
    assert r.code == 0, r.err
    check_png(out)
    assert f"the rows figure shows 4 of {len(files)} rows designs" in r.err
    assert str(files[4]) in r.err and str(files[0]) not in r.err


def test_stack_keeps_each_kinds_figure():
    import matplotlib.pyplot as plt

    from gearcalc.plot import DPI, stack

    figs = [("rows", plt.figure(figsize=(5, 2))), ("zstk", plt.figure(figsize=(3, 4)))]
    fig = stack(figs)
    assert [ax.get_label() for ax in fig.axes] == ["rows", "zstk"]
    assert [im.get_array().shape[:2] for ax in fig.axes for im in ax.images] == [(2 * DPI, 5 * DPI),
                                                                                  (4 * DPI, 3 * DPI)]
    assert tuple(fig.get_size_inches()) == (5.0, 6.0)
    plt.close(fig)


# ------------------------------------------------------------------------- sweep figures
def grid(**axes):
    """Sweep rows (dicts) over the product of the axes, the first varying slowest, efficiency made up."""
    import itertools

    keys = list(axes)
    return [dict(zip(keys, vals), efficiency=0.9 - 0.01 * i)
            for i, vals in enumerate(itertools.product(*axes.values()))]


@pytest.mark.parametrize("axes,x", [
    # a boolean last axis: was the x axis (True/False are ints)
    ({"friction.sliding": [0.02, 0.04, 0.06, 0.08], "gearing.rotating_pins": [True, False]}, "friction.sliding"),
    # a 2-value numeric last axis: was the x axis, the 31-value one made 31 legend entries
    ({"load.torque_Nm": [float(t) for t in range(10, 320, 10)], "gearing.pins": [22, 24]}, "load.torque_Nm"),
    # two long numeric axes: the longer; on a tie the later (the fastest varying)
    ({"a.x": [1, 2, 3, 4, 5], "b.y": [1, 2, 3]}, "a.x"),
    ({"a.x": [1, 2, 3], "b.y": [4, 5, 6]}, "b.y"),
    # text only: the last axis
    ({"load.mode": ["multiplier", "reducer"], "gearing.profile": ["cycloidal", "circular"]}, "gearing.profile"),
])
def test_sweep_x_axis(axes, x):
    from gearcalc.plot import _label, sweep_figure, sweep_x

    rows = grid(**axes)
    assert sweep_x(rows, list(axes)) == x
    fig = sweep_figure("pins", rows, list(axes))
    assert fig.axes[0].get_xlabel() == _label(x.split(".")[-1])


def overlaps(a, b) -> bool:
    return a.x0 < b.x1 and b.x0 < a.x1 and a.y0 < b.y1 and b.y0 < a.y1


TORQUES = [10.0 * k for k in range(1, 41)]  # 40 values: the x axis


@pytest.mark.parametrize("axes", [
    {"gearing.pins": list(range(10, 41)), "load.torque_Nm": TORQUES},     # 31 curves of a number: a colour bar
    {"gearing.pins": list(range(10, 41)), "load.mode": ["multiplier", "reducer"],
     "load.torque_Nm": TORQUES},                                            # a colour and 2 line styles
    pytest.param({"name.x": [f"n{i}" for i in range(31)], "load.torque_Nm": TORQUES},  # 31 texts: a legend beside
                 marks=pytest.mark.slow),                                             # the axes; long: CI runs it
])
def test_many_curves_hide_neither_title_nor_axes(axes):
    # before: 31 legend entries over the axes, up through the title
    from gearcalc.plot import LEGEND_MAX, sweep_figure

    fig = sweep_figure("pins", grid(**axes), list(axes))
    fig.tight_layout()
    fig.canvas.draw()
    r = fig.canvas.get_renderer()
    ax = fig.axes[0]
    title = fig._suptitle.get_window_extent(r)
    assert fig.bbox.x0 <= title.x0 and title.x1 <= fig.bbox.x1 and title.y1 <= fig.bbox.y1
    legend = ax.get_legend()
    boxes = [ax.get_window_extent(r)] + [a.get_window_extent(r) for a in fig.axes[1:]]  # the axes, the colour bar
    if legend is not None:
        assert len(legend.get_texts()) <= LEGEND_MAX or not overlaps(legend.get_window_extent(r), boxes[0])
        boxes.append(legend.get_window_extent(r))
    assert not any(overlaps(title, b) for b in boxes)
    assert len(ax.lines) == len(grid(**axes)) // len(TORQUES)  # one curve per combination of the other axes


# ------------------------------------------------------------------------- pins: the engagement at both levels
def pins_force_curve(tmp_path, model: str, mode: str):
    """The x data of the pin-force panel of the pins figure of the paper's cycloidal u = 10 gear (fixed pins) at
    this level and mode, the design's psi* (the ideal level's crest cut-off) and its pin pitch 360/z2 [deg]."""
    import gearcalc.plot as gplot
    from gearcalc import api
    from gearcalc.kinds.pins import compute
    from gearcalc.pins.plot import plot
    from gearcalc.render import Record

    config = CONFIGS / "pins_paper_cyc_u10_fixed.toml"
    over = {"load.mode": mode, "contact.face_width_mm": 10.0}
    res = api.compute(config, model=model, overrides=over)
    ideal = api.compute(config, model="ideal", overrides=over)
    kept = []
    gplot._collected = kept  # plot_records' figure collection: the figure is kept, not written
    try:
        plot([Record(str(config), "pins", res.design["name"], res.design, res)], str(tmp_path / "p.png"), compute)
    finally:
        gplot._collected = None
    (fig,) = kept
    ax = next(a for a in fig.axes if a.get_ylabel().startswith("pin force"))
    return ax.lines[0].get_xdata(), ideal.summary["psi_star_deg"], 360.0 / res.design["gearing"]["pins"]


@pytest.mark.parametrize("mode", [pytest.param("reducer", marks=pytest.mark.slow), "multiplier"])  # CI: both
def test_pins_engagement_in_the_same_range_at_both_levels(tmp_path, mode):
    # the contact level reports a pin loaded just before phase 0 (compliance) as a phase just below 360: the
    # reducer's curve (psi* - phase) lay at 180-360 deg at the contact level, at 0-180 at the ideal level
    import numpy as np

    x_ideal, psi, pitch = pins_force_curve(tmp_path, "ideal", mode)
    x_contact, _, _ = pins_force_curve(tmp_path, "contact", mode)
    assert x_ideal.min() == 0.0 and x_ideal.max() == pytest.approx(psi, rel=1e-12)  # [0, psi*]: the ideal arc
    assert x_contact.min() == 0.0
    # the compliant pins reach a little past the ideal arc, by less than one pin pitch
    assert psi <= x_contact.max() < psi + pitch
    assert np.all(np.diff(x_contact) >= 0)


# ------------------------------------------------------------------------- accuracy --plot
@pytest.mark.slow
def test_accuracy_tick_labels_do_not_overprint():
    # times within one decade (zstk's levels: 25-300 ms on this machine) got minor labels 3x10^1, 4x10^1 ...
    # printed over each other; the rows are made up in the shape of gearcalc.accuracy.summarise's
    from gearcalc.plot import accuracy_figure

    rows = [{"kind": kind, "level": level, "tol": tol, "time_ms_median": t * scale, "error_max": e,
             "error_est_max": 10 * e}
            for kind, scale in (("zstk", 1.0), ("rows", 0.01))
            for level, t0 in (("equilibrium", 25.0), ("reference", 260.0))
            for tol, t, e in ((1e-3, t0, 1e-8), (1e-6, t0 * 1.1, 1e-12), (1e-9, t0 * 1.15, 1e-12))]
    fig = accuracy_figure(rows)
    fig.canvas.draw()
    r = fig.canvas.get_renderer()
    for ax in fig.axes:
        lo, hi = ax.get_xlim()
        labels = [t for t in ax.get_xticklabels() + ax.get_xticklabels(minor=True)
                  if t.get_text() and t.get_visible() and lo <= t.get_position()[0] <= hi]
        assert len(labels) >= 2
        boxes = [t.get_window_extent(r) for t in labels]
        assert not any(overlaps(a, b) for i, a in enumerate(boxes) for b in boxes[i + 1:]), \
            [t.get_text() for t in labels]
        assert not [t for t in ax.get_xticklabels(minor=True) if t.get_text()]
        tols = [t.get_window_extent(r) for t in ax.texts]  # the tol labels of coinciding points
        assert not any(overlaps(a, b) for i, a in enumerate(tols) for b in tols[i + 1:])


def test_efficiency_map_contour_from_the_plotted_data():
    # issue 37 item 4: a torque x speed sweep drawn as a contour map beside the curves; the map's data are the
    # sweep's efficiencies at their grid places
    pytest.importorskip("matplotlib")
    import matplotlib.pyplot as plt

    import gearcalc.api as api
    from gearcalc.plot import sweep_figure
    d = _with(load={"drag_torque_Nm": 0.5}, output=W8)
    axes = {"load.torque_Nm": [1.0, 10.0, 100.0, 1000.0], "load.crank_speed_rpm": [100.0, 1000.0, 3000.0]}
    rows = []
    for chunk in api.sweep(d, axes):
        rows.extend(chunk.rows())
    fig = sweep_figure("pins", rows, list(axes))
    ax_map = fig.axes[1]
    x_key, y_key, xs, ys, Z = ax_map.gearcalc_map
    assert (x_key, y_key) == ("load.torque_Nm", "load.crank_speed_rpm")
    for r in rows:
        assert Z[ys.index(r[y_key])][xs.index(r[x_key])] == r["efficiency"]
    filled = next(c for c in ax_map.collections if hasattr(c, "levels"))
    eff = [r["efficiency"] for r in rows]
    assert filled.levels[0] <= min(eff) and max(eff) <= filled.levels[-1]
    assert len(fig.axes[0].lines) == 3          # the curves stay: one per speed
    plt.close(fig)
