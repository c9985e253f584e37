"""The papers' questions as worked examples (issue 36 item 7): each file in examples/ states its one
``gearcalc optimize`` command in its comments; the test runs that command's problem through the API and
compares the optimum with a brute-force grid over the same box, evaluated by ``gearcalc.sweep``.

The bound, for a maximised objective (a minimised one mirrored): every grid point is a point of the box, so
the optimiser's value is at least the grid's best feasible value (less the objective's own stated error);
and it is at most the grid's best plus the largest change of the objective between the grid's best and its
feasible neighbours (the improvement one grid cell can hold), its keys within one cell of the grid's best.
"""
import shlex

import pytest
from conftest import ROOT, cli

import gearcalc

EXAMPLES = ROOT / "examples"


def command(path):
    """The ``gearcalc optimize`` command written in the example's comments, as (vary, objective, where):
    ``vary`` the ``--vary`` strings as typed (the API takes them; a key's type decides whether it is an integer
    key, not the look of its range) and ``box`` their ranges as numbers."""
    lines = [ln.lstrip("#").strip() for ln in path.read_text().splitlines() if ln.startswith("#")]
    start = next(k for k, ln in enumerate(lines) if ln.startswith("gearcalc optimize"))
    text = ""
    for ln in lines[start:]:
        text += ln.rstrip("\\").strip() + " "
        if not ln.endswith("\\"):
            break
    args = shlex.split(text)
    assert args[:3] == ["gearcalc", "optimize", f"examples/{path.name}"]
    vary, box, objective, where = [], {}, None, []
    for opt, value in zip(args[3::2], args[4::2]):
        if opt == "--vary":
            vary.append(value)
            key, _, rng = value.partition("=")
            lo, hi = rng.split(":")
            box[key] = (float(lo), float(hi))
        elif opt == "--objective":
            objective = value
        else:
            assert opt == "--where"
            where.append(value)
    return vary, box, objective, where


def grid(path, axes):
    return [r for part in gearcalc.sweep(path, axes) for r in part.rows()]


def neighbours(best, rows, keys, steps):
    """The grid points one step from ``best`` along one key."""
    out = []
    for r in rows:
        d = [abs(r[k] - best[k]) / steps[k] for k in keys]
        if sorted(round(x, 6) for x in d) == [0.0] * (len(keys) - 1) + [1.0]:
            out.append(r)
    return out


def linspace(lo, hi, n):
    return [round(lo + (hi - lo) * k / (n - 1), 10) for k in range(n)]


def test_the_commands_name_their_files():
    assert sorted(p.name for p in EXAMPLES.glob("*.toml")) == [
        "seed000_pins_multiplier.toml", "seed003_zstk_smallest_outer.toml", "seed004_rows_mass.toml"]
    for path in EXAMPLES.glob("*.toml"):
        vary, box, objective, where = command(path)
        assert vary and box and objective and where


@pytest.mark.slow
def test_seed000_multiplier_efficiency_under_a_contact_stress_limit():
    path = EXAMPLES / "seed000_pins_multiplier.toml"
    vary, box, objective, where = command(path)
    assert objective == "efficiency:max" and where == ["margin_contact_stress>=0"]
    r = gearcalc.optimize(path, vary, objective, where=where)
    keys = list(box)
    n = {"gearing.eccentricity_mm": 5, "gearing.pin_circle_radius_mm": 26, "gearing.pin_radius_mm": 4}
    axes = {k: linspace(*box[k], n[k]) for k in keys}
    steps = {k: (box[k][1] - box[k][0]) / (n[k] - 1) for k in keys}
    rows = grid(path, axes)
    feasible = [g for g in rows if g["error"] is None and g["margin_contact_stress"] >= 0]
    best = max(feasible, key=lambda g: g["efficiency"])
    cell = max(abs(g["efficiency"] - best["efficiency"]) for g in neighbours(best, feasible, keys, steps))
    err = r.error + best["efficiency_err"]
    assert best["efficiency"] - err <= r.value <= best["efficiency"] + cell
    for k in keys:
        assert abs(r.optimum[k] - best[k]) <= steps[k] * (1 + 1e-9), k
    # the largest eccentricity and pins of the box, R_p where the stress reaches the allowable
    assert r.optimum["gearing.eccentricity_mm"] == box["gearing.eccentricity_mm"][1]
    assert r.optimum["gearing.pin_radius_mm"] == box["gearing.pin_radius_mm"][1]
    assert r.constraints[0]["active"] and r.outputs["margin_contact_stress"] >= 0
    assert r.converged and 0 < r.error < 1e-6


def test_seed003_smallest_outer_raceway_carrying_the_required_load():
    path = EXAMPLES / "seed003_zstk_smallest_outer.toml"
    vary, box, objective, where = command(path)
    assert objective == "outer_raceway_radius_mm:min" and where == ["radial_load_allowable_N>=200000"]
    r = gearcalc.optimize(path, vary, objective, where=where)
    key = "geometry.outer_raceway_radius_mm"
    lo, hi = box[key]
    step = 0.1
    rows = grid(path, {key: linspace(lo, hi, round((hi - lo) / step) + 1)})
    feasible = [g for g in rows if g["error"] is None and g["radial_load_allowable_N"] >= 200000]
    best = min(feasible, key=lambda g: g["outer_raceway_radius_mm"])
    # the objective is the key itself (exact): the optimum lies in the grid cell below the grid's best
    assert best["outer_raceway_radius_mm"] - step <= r.value <= best["outer_raceway_radius_mm"]
    assert r.error == 0.0 and r.value == r.optimum[key]
    assert r.outputs["N"] == best["N"] == 16  # the 16-roller branch, below the 14-roller one (file's comment)
    assert r.constraints[0]["active"] and r.outputs["radial_load_allowable_N"] >= 200000
    assert r.converged


@pytest.mark.slow
def test_seed004_rows_and_width_of_least_relative_mass():
    path = EXAMPLES / "seed004_rows_mass.toml"
    vary, box, objective, where = command(path)
    assert objective == "relative_mass_kg_per_kNm:min" and where == ["K<=1.15"]
    assert box["rows.count"] == (1, 6)
    r = gearcalc.optimize(path, vary, objective, where=where)
    lo, hi = box["rows.relative_width"]
    step = 0.05
    widths = linspace(lo, hi, round((hi - lo) / step) + 1)
    rows = grid(path, {"rows.count": list(range(1, 7)), "rows.relative_width": widths})
    feasible = [g for g in rows if g["error"] is None and g["K"] <= 1.15]
    best = min(feasible, key=lambda g: g["relative_mass_kg_per_kNm"])
    # the grid holds the optimum itself (the smallest width of the box): the same point, the same value
    assert r.optimum == {"rows.count": best["rows.count"], "rows.relative_width": best["rows.relative_width"]}
    assert r.value == pytest.approx(best["relative_mass_kg_per_kNm"], rel=1e-12)
    assert r.converged and r.error == 0.0
    single = min(g["relative_mass_kg_per_kNm"] for g in rows if g["rows.count"] == 1)
    assert r.value < single  # more rows pay, as far as K <= 1.15 lets them


@pytest.mark.parametrize("name", ["seed003_zstk_smallest_outer.toml", "seed004_rows_mass.toml"])
def test_the_examples_run_as_designs(name):
    r = cli("run", str(EXAMPLES / name), "-f", "json")
    assert r.code == 0, r.err
