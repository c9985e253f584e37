"""The rows sweep with [bridges] evaluated as arrays (gearcalc/kinds/rows.py, rows.md §9) gives, point for point,
the design computed alone: the same columns in the same order, the same words, flags and empty cells, and the same
floats to round-off, over a grid that holds every kind of point (feasible, capped, no room, κ ≥ 8, unloaded rows
in the verification); the batch functions equal their scalar forms bit for bit."""
import copy
import itertools

import numpy as np
import pytest

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
    cols = Columns.from_rows(rows).data
    return Columns({**cols, "error": [None] * len(rows)})  # a sweep row's last column: why a point has no results


@pytest.mark.slow
def test_bridges_sweep_equals_each_point_alone():
    axes = {"rows.count": [1, 3, 4], "gear.ratio": [2.3, 4.0], "rows.planets_per_row": [3, 7],
            "bridges.first_span": ["axes_only", 0.1], "rows.relative_width": [0.4, 3.0, 40.0]}
    (part,) = list(gearcalc.sweep(BASE, axes))
    want = alone(BASE, axes)
    assert list(part.data) == list(want.data)  # the union of the columns in first-seen order (rows.md §13.5)
    got = part.lists().data
    for key, values in want.data.items():
        # floats to round-off: a design alone takes some powers in Python floats (pow), the arrays in numpy
        # (x*x), which differ in the last bit now and then (kappa, r_ba**2); the bridge arithmetic itself is one
        # function (size_bridges is size_bridges_batch of one design)
        assert [pytest.approx(v, rel=1e-12, abs=1e-12) if type(v) is float else v for v in values] == got[key], key
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
    assert list(part.data) == list(want.data)
    for key, values in want.data.items():
        assert [pytest.approx(v, rel=1e-12, abs=1e-12) if type(v) is float else v for v in values] == \
            part.lists().data[key], key


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


# ---------------------------------------------------------------- the cost of a sweep, estimated before it starts

def test_a_mistyped_step_is_refused_before_any_point_is_computed(monkeypatch, tmp_path):
    # issue 34: --vary rows.relative_width=1:1000:0.00001 is (1000 - 1)/1e-5 = 99 900 000 steps (99 900 000 points:
    # the stop lies 1e-8 of a step off the grid in floating point, beyond the parser's 1e-9); at the
    # vectorised bridges' estimate (kinds/rows.py sweep_cost: 10 us + 4 us a row, n = 3: 22 us) that is ~37 min,
    # over grid.SWEEP_SECONDS_MAX = 600 s: exit 2, the count and a coarser step, and no point evaluated
    from conftest import cli
    from gearcalc import grid, registry
    from gearcalc.template import template

    design = tmp_path / "new.toml"
    design.write_text(template(registry.get("rows")))  # `gearcalc new rows`: every template has [bridges]
    assert "[bridges]" in design.read_text()

    def never(*args, **kwargs):
        raise AssertionError("a point was computed")

    monkeypatch.setattr(grid, "evaluate_points", never)
    r = cli("sweep", design, "--vary", "rows.relative_width=1:1000:0.00001", "--format", "csv")
    assert r.code == 2 and r.out == ""
    assert "99900000 points" in r.err and "--vary rows.relative_width=1:1000:" in r.err and "coarser" in r.err


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
    assert grid.chunk_points(grid.prepare(BASE, "x.toml", {"rows.count": [3]})[1]) > 10_000


def test_the_progress_bar_says_the_time_left(tmp_path):
    # on a terminal's stderr a sweep's bar has a "left" column (rich's TimeRemainingColumn: the time once the
    # rate is known): a pins contact-level sweep of 12 points (its ~41 ms a point estimated)
    from conftest import CONFIGS
    from test_terminal import run_tty

    code, out, err = run_tty("sweep", CONFIGS / "pins_paper_circ_u30_rotating.toml", "--vary",
                             "friction.sliding=0.05:0.061:0.001", "--format", "csv", stdout_tty=False,
                             stderr_tty=True, env={"GEARCALC_PROGRESS_DELAY": "0"})
    # exit 1: at f <= 0.061 the bushings cannot roll (f R_b < f_c r + f_k), a failed check since issue 36
    assert code == 1 and len(out.splitlines()) == 1 + 12 and "12 of 12 points fail rolling" in err
    assert "computing" in err and "points" in err and "left" in err


# ---------------------------------------------------------------- where every bridge fits: both bounds

def _feasible(path, **sets):
    d = gearcalc.design.read_toml(path)
    for key, value in sets.items():
        table, _, name = key.partition("__")
        d[table][name] = value
    return gearcalc.compute(d).summary["bridges_feasible"]


def test_the_bridge_hint_gives_the_window_and_its_bounds_are_where_the_flag_flips():
    # the paper's capped cell (rows.md §5.6): only 2.67 <= B <= 2.97 fits (issue 34); the hint says both bounds,
    # rounded inward to 3 decimals, and the design computed alone flips bridges_feasible between them and 0.001
    # outside them (an independent evaluation: the check itself at those widths)
    from conftest import CONFIGS, cli

    paper = CONFIGS.parent / "paper" / "rows_bridges_n3_B3_i4.toml"
    for sets in ([], ["--set", "rows.relative_width=2.4"]):  # above and below the window
        r = cli("rows", paper, *sets, "--format", "csv")
        assert r.code == 1 and "every bridge fits for rows.relative_width from 2.666 to 2.973 (rows.count = 3)" \
            in r.err, r.err
    for B, fits in ((2.665, False), (2.666, True), (2.8, True), (2.973, True), (2.974, False)):
        assert _feasible(paper, rows__relative_width=B) is fits, B
    r = cli("rows", paper, "--set", "rows.count=4", "--format", "csv")
    assert r.code == 1 and "from 4.000 to 4.035 (rows.count = 4)" in r.err
    for B, fits in ((3.999, False), (4.0, True), (4.035, True), (4.036, False)):
        assert _feasible(paper, rows__count=4, rows__relative_width=B) is fits, B
    # five rows: no width fits (B/30 to 30 B tried); four rows do
    r = cli("rows", paper, "--set", "rows.count=5", "--format", "csv")
    assert "no rows.relative_width makes every bridge fit with rows.count = 5" in r.err
    assert "rows.count = 4 does, for rows.relative_width from 4.000 to 4.035" in r.err


def test_feasible_widths_bisects_each_edge_to_1e_9():
    # each bound fits, and a width 1e-8 (relative) beyond it does not: the bisection's 1e-9 (bridges.py)
    Ip = R.polar_moment(77.5)
    args = (3, 18, 5.0, np.radians(20.0), 4.0, 2e5, 0.3, Ip)
    (lo, hi), = R.feasible_widths(3.0, 3, *args)
    assert R.bridges_fit(lo, 3, *args) and R.bridges_fit(hi, 3, *args)
    assert not R.bridges_fit(lo * (1 - 1e-8), 3, *args) and not R.bridges_fit(hi * (1 + 1e-8), 3, *args)
    assert R.feasible_widths(3.0, 5, *args) == [] and R.feasible_rows(3.0, 5, *args)[0] == 4


def test_bridges_sweep_with_the_mass_of_the_balanced_rows():
    # mass.unevenness = "computed" takes K_balanced with [bridges] (rows.md §6): the arrays give it too
    base = {**BASE, "mass": {"unevenness": "computed"}}
    axes = {"rows.relative_width": [2.4, 2.7, 3.0], "gear.ratio": [4.0, 6.0]}
    (part,) = list(gearcalc.sweep(base, axes))
    want = alone(base, axes)
    assert list(part.data) == list(want.data)
    for key, values in want.data.items():
        assert [pytest.approx(v, rel=1e-12, abs=1e-12) if type(v) is float else v for v in values] == \
            part.lists().data[key], key
