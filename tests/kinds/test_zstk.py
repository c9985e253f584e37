"""Tests of the zstk adapter (gearcalc/kinds/zstk.py) through `gearcalc zstk` and the API: the spec's example, the
configs, outputs, exit codes, bad input, the Tresca shear reported for the design's Poisson ratios, and the sweep
and batch hooks."""
import copy
import csv
import dataclasses
import io
import json
import math
import subprocess
import sys
import tomllib
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from conftest import cli
from test_hertz import brute_tresca  # Johnson's axis stresses maximised by brute force (tests/test_hertz.py)
from gearcalc import api, hertz, registry
from gearcalc import grid as sw
from gearcalc.calculator import DesignError, Options
from gearcalc.cli import app
from gearcalc.design import apply_set, load, validate

ROOT = Path(__file__).resolve().parents[2]
CONFIGS = ROOT / "configs"
EXAMPLE = CONFIGS / "zstk_merko_example.toml"
runner = CliRunner()

BASE = """kind = "zstk"
name = "t"
[geometry]
outer_raceway_radius_mm = 100.0
inner_raceway_radius_mm = 50.0
eccentricity_mm = 6.0
roller_gap_mm = 6.0
roller_length_mm = 20.0
[load]
radial_N = 10000.0
"""


def run(*args):
    return runner.invoke(app, ["zstk", *(str(a) for a in args)])


def summary(*args):
    r = run(*args, "--format", "json")
    assert r.exit_code in (0, 1), r.output
    return json.loads(r.stdout)["summary"], r


def design(tmp_path, extra="", name="d.toml", base=BASE):
    p = tmp_path / name
    p.write_text(base + extra)
    return p


def test_example_unchanged_subprocess():
    # the spec's example, byte for byte, through the real console entry point
    p = subprocess.run([sys.executable, "-m", "gearcalc", "zstk", str(EXAMPLE), "--format", "json"],
                       capture_output=True, text=True, timeout=60, check=False)
    assert p.returncode == 0, p.stderr
    s = json.loads(p.stdout)["summary"]
    for key in ("name", "N", "N_star", "correction", "outer_raceway_radius_mm", "inner_raceway_radius_mm",
                "roller_gap_mm", "sigma_max_MPa", "sigma_max_contact", "sigma_max_roller", "sigma_max_angle_deg",
                "sigma_max_roller_radius_mm", "allowable_stress_MPa", "safety_factor", "pass"):
        assert key in s
    assert s["N"] == 8 and s["correction"] == "outer" and s["sigma_max_contact"] == "inner"
    assert s["sigma_max_roller"] == 0 and s["sigma_max_angle_deg"] == 0.0
    # no [sigma_H] in the design: the ISO 76 default, its source and a warning (spec §7.1.4)
    assert s["allowable_stress_MPa"] == 4000.0
    assert s["allowable_stress_source"] == "default: ISO 76 static reference"
    assert "static" in p.stderr and "not an endurance allowable" in p.stderr


def test_json_and_csv_agree():
    s, _ = summary(EXAMPLE)
    r = run(EXAMPLE, "--format", "csv")
    row = next(csv.DictReader(io.StringIO(r.stdout)))
    for k, v in s.items():
        if isinstance(v, float):
            assert float(row[k]) == v
        elif v is None:
            assert row[k] == ""


def test_configs_all_run():
    files = sorted(CONFIGS.glob("zstk_*.toml"))
    assert len(files) >= 10
    r = run(*files, "--format", "json")
    assert r.exit_code == 0, r.output
    objs = json.loads(r.stdout)
    by = {Path(o["file"]).name: o["summary"] for o in objs}
    # porism: every scheme of one N has one corrected radius (spec §4.2)
    assert by["zstk_merko_A_outer.toml"]["outer_raceway_radius_mm"] == by["zstk_merko_D_outer.toml"][
        "outer_raceway_radius_mm"]
    assert by["zstk_merko_A_outer.toml"]["N"] == 8 and by["zstk_merko_B_outer.toml"]["N"] == 7
    # the example is scheme A with R_H corrected
    assert by["zstk_merko_example.toml"]["sigma_max_MPa"] == by["zstk_merko_A_outer.toml"]["sigma_max_MPa"]
    for s in by.values():
        assert s["sigma_max_contact"] == "inner"


def test_detail_table():
    r = run(EXAMPLE, "--format", "json", "--detail")
    obj = json.loads(r.stdout)
    rows = obj["detail"]["rollers"]
    assert len(rows) == 8
    for col in ("i", "theta_deg", "r_mm", "psi_deg", "beta_deg", "F_B_N", "F_H_N", "rho_B_mm", "rho_H_mm",
                "sigma_B_MPa", "sigma_H_MPa", "b_B_mm", "b_H_mm", "tau_max_B_MPa"):
        assert col in rows[0]
    # equilibrium along the load from the printed table (16 digits): sum F cos psi = Q
    total = sum(r_["F_B_N"] * math.cos(math.radians(r_["psi_deg"])) for r_ in rows)
    assert total == pytest.approx(10000.0, rel=1e-12)
    assert max(r_["sigma_B_MPa"] for r_ in rows) == obj["summary"]["sigma_max_MPa"]
    r = run(EXAMPLE, "--format", "csv", "--detail")
    assert r.stdout.splitlines()[0].startswith("name,table,i,theta_deg")
    r = run(EXAMPLE, "--format", "table", "--detail")
    assert r.exit_code == 0 and "worked example: rollers" in r.stdout


@pytest.mark.parametrize("scheme,n", [("A", 8), ("B", 7), ("C", 7), ("D", 8)])
def test_schemes_parity_and_phase(tmp_path, scheme, n):
    s, _ = summary(design(tmp_path), "--set", f"geometry.scheme={scheme}")
    assert s["N"] == n and s["scheme"] == scheme
    assert (s["theta0_deg"] == 0.0) == (scheme in "AB")


def test_phase_angle(tmp_path):
    s, _ = summary(design(tmp_path), "--set", "geometry.scheme=12.5")
    assert s["scheme"] == "angle" and s["theta0_deg"] == pytest.approx(12.5, abs=1e-12)


def test_correction_fields(tmp_path):
    s, _ = summary(design(tmp_path), "--set", 'geometry.correct="inner"')
    assert s["correction"] == "inner" and s["nominal_mm"] == 50.0
    assert s["inner_raceway_radius_mm"] == pytest.approx(50.0 + s["correction_mm"], rel=1e-15)
    assert s["correction_mm"] < 0 and s["outer_raceway_radius_mm"] == 100.0
    g, _ = summary(design(tmp_path), "--set", 'geometry.correct="gap"')
    assert g["roller_gap_mm"] == pytest.approx(6.0 + g["correction_mm"]) and g["correction_mm"] > 0


@pytest.mark.slow
def test_envelope_and_cycle_honest_error(tmp_path):
    # the sweep's error estimate must cover the difference to the reference level (8x grids)
    p = design(tmp_path)
    for sets in (["load.direction_deg=envelope"], ["geometry.scheme=cycle"],
                 ["geometry.scheme=D", "load.direction_deg=envelope"]):
        args = [x for kv in sets for x in ("--set", kv)]
        d, _ = summary(p, *args)
        ref, _ = summary(p, *args, "--model", "reference")
        assert d["sigma_max_err_MPa"] > 0
        assert abs(d["sigma_max_MPa"] - ref["sigma_max_MPa"]) <= d["sigma_max_err_MPa"] + ref["sigma_max_err_MPa"]
        assert d["sigma_max_err_MPa"] <= 1e-6 * d["sigma_max_MPa"]
        if "load.direction_deg=envelope" in sets:
            assert d["direction_samples"] >= 720 and d["direction_step_deg"] > 0
        else:
            assert d["phase_samples"] >= 64
    assert ref["stepping_residual_mm"] < 1e-9


def test_envelope_detail_has_directions(tmp_path):
    r = run(design(tmp_path), "--set", "load.direction_deg=envelope", "--format", "json", "--detail")
    obj = json.loads(r.stdout)
    rows = obj["detail"]["rollers"]
    assert "gamma_B_deg" in rows[0] and "gamma_H_deg" in rows[0]
    smax = max(r_["sigma_B_MPa"] for r_ in rows)
    s = obj["summary"]
    assert abs(smax - s["sigma_max_MPa"]) <= s["sigma_max_err_MPa"] + 1e-9 * smax
    # the envelope maximum sits at the smallest roller, inner contact (the paper's claim 2)
    assert s["sigma_max_roller_radius_mm"] == pytest.approx(min(r_["r_mm"] for r_ in rows))


def test_fixed_direction_level(tmp_path):
    p = design(tmp_path)
    sym, _ = summary(p, "--model", "fixed-direction")
    eq, _ = summary(p)
    assert sym["sigma_max_MPa"] == pytest.approx(eq["sigma_max_MPa"], rel=1e-13)
    assert sym["transverse_residual"] < 1e-12
    off, r = summary(p, "--model", "fixed-direction", "--set", "geometry.scheme=10", "--set", "load.direction_deg=25")
    assert off["transverse_residual"] > 1e-4 and "transverse" in r.stderr
    full, _ = summary(p, "--set", "geometry.scheme=10", "--set", "load.direction_deg=25")
    assert full["transverse_residual"] < 1e-12 and full["solver_residual"] < 1e-12


def test_clearance_and_preload(tmp_path):
    p = design(tmp_path)
    for s_ in ("0.02", "-0.01"):
        s, _ = summary(p, "--set", f"load.clearance_mm={s_}", "--set", "geometry.scheme=10",
                       "--set", "load.direction_deg=30")
        assert s["solver_residual"] <= 1e-12 and s["clearance_mm"] == float(s_)
        assert 0 <= s["approach_direction_deg"] < 360 and s["approach_um"] >= 0
    s, _ = summary(p, "--set", "load.clearance_mm=-0.01", "--set", "load.radial_N=1e-3")
    assert s["loaded_rollers"] == 8 and s["sigma_max_MPa"] > 100


def test_strength_check_exit_1(tmp_path):
    p = design(tmp_path, "[material]\nallowable_stress_MPa = 700.0\n")
    s, r = summary(p)
    assert r.exit_code == 1 and s["pass"] is False
    assert s["allowable_stress_source"] == "design" and s["safety_factor"] < 1
    assert "check failed" in r.stderr and "sigma_max_MPa" in r.stderr


def test_a_failed_strength_check_prints_the_digits_that_show_the_excess(tmp_path):
    import re

    sigma = summary(EXAMPLE)[0]["sigma_max_MPa"]  # the example's own stress: the allowable a hair below it
    allow = sigma * (1 - 1e-8)
    assert f"{sigma:.6g}" == f"{allow:.6g}"  # at six digits the message would read "x > x"
    s, r = summary(EXAMPLE, "--set", f"material.allowable_stress_MPa={allow!r}")
    assert r.exit_code == 1 and s["pass"] is False
    shown, limit = re.search(r"sigma_max_MPa = (\S+) > allowable_stress_MPa = (\S+) ", r.stderr).groups()
    assert float(shown) > float(limit), r.stderr


def test_huge_load_fails_and_warns(tmp_path):
    s, r = summary(design(tmp_path), "--set", "load.radial_N=1e9")
    assert r.exit_code == 1 and s["pass"] is False and "b/rho" in r.stderr
    t, _ = summary(design(tmp_path), "--set", "load.radial_N=1e-6")
    assert t["sigma_max_MPa"] > 0 and t["pass"] is True


def test_many_rollers_cli(tmp_path):
    s, _ = summary(design(tmp_path), "--set", "geometry.inner_raceway_radius_mm=97.5", "--set",
                   "geometry.eccentricity_mm=0.5", "--set", "geometry.roller_gap_mm=0.05")
    assert s["N"] > 200 and s["solver_residual"] < 1e-12


@pytest.mark.parametrize("sets,key,words", [
    (["geometry.inner_raceway_radius_mm=100"], "geometry.inner_raceway_radius_mm", "must be <"),
    (["geometry.inner_raceway_radius_mm=0"], "geometry.inner_raceway_radius_mm", "> 0"),
    (["geometry.roller_length_mm=0"], "geometry.roller_length_mm", ">= 1e-06"),
    (["geometry.outer_raceway_radius_mm=1e300"], "geometry.outer_raceway_radius_mm", "<= 1e+06"),
    (["load.clearance_mm=30"], "load.clearance_mm", "smallest roller radius"),
    (["load.clearance_mm=-1e300"], "load.clearance_mm", "smallest roller radius"),
    (["geometry.eccentricity_mm=-1"], "geometry.eccentricity_mm", ">= 0"),
    (["geometry.eccentricity_mm=52"], "geometry.eccentricity_mm", "= 50"),
    (["geometry.eccentricity_mm=50"], "geometry.eccentricity_mm", "(R_H − R_B − e)/2 would be ≤ 0"),
    (["geometry.inner_raceway_radius_mm=1", "geometry.eccentricity_mm=72", "geometry.roller_gap_mm=0"],
     "geometry.eccentricity_mm", "90°"),
    (["geometry.roller_gap_mm=-1"], "geometry.roller_gap_mm", ">= 0"),
    (["geometry.roller_gap_mm=100"], "geometry.roller_gap_mm", "< 2·inner_raceway_radius_mm = 100"),
    (["load.radial_N=0"], "load.radial_N", ">= 1e-06"),      # zstk/schema.MIN_FORCE_N (issue 13)
    (["material.roller_E_MPa=0"], "material.roller_E_MPa", ">= 1"),
    (["material.inner_ring_E_MPa=5e-324"], "material.inner_ring_E_MPa", ">= 1"),
    (["material.allowable_stress_MPa=-5"], "material.allowable_stress_MPa", "> 0"),
    (["material.ring_poisson=0.5"], "material.ring_poisson", "< 0.5"),
    (["material.roller_poisson=0"], "material.roller_poisson", "> 0"),
    (["geometry.rollers=8.5"], "geometry.rollers", "an integer"),
    (["geometry.rollers=2"], "geometry.rollers", ">= 3"),
    (["geometry.rollers=2001"], "geometry.rollers", "<= 2000"),
    (["geometry.inner_raceway_radius_mm=99.9", "geometry.eccentricity_mm=0", "geometry.roller_gap_mm=0"],
     "geometry.rollers", "range of 2000 rollers"),
    (["geometry.rollers=40"], "geometry.rollers", "3 ≤ N ≤ 31"),
    (["geometry.rollers=7"], "geometry.rollers", "geometry.scheme"),
    (["geometry.inner_raceway_radius_mm=10", "geometry.roller_gap_mm=19", "geometry.eccentricity_mm=0"],
     "geometry.rollers", "N* = 2.18"),
    (["geometry.scheme=E"], "geometry.scheme", '"A" | "B"'),
    (["load.direction_deg=sideways"], "load.direction_deg", '"envelope"'),
    (["load.radial_N=nan"], "load.radial_N", "finite"),
    (["geometry.eccentricity_mm=inf"], "geometry.eccentricity_mm", "finite"),
])
def test_bad_input_exit_2(tmp_path, sets, key, words):
    p = design(tmp_path)
    args = [x for kv in sets for x in ("--set", kv)]
    r = run(p, *args, "--format", "csv")
    assert r.exit_code == 2, r.output
    assert "d.toml" in r.stderr and key in r.stderr and words in r.stderr, r.stderr
    assert "Traceback" not in r.output and "nan" not in r.stdout


def test_explicit_n_below_n_star_3_is_valid(tmp_path):
    # spec §11.6: N* < 3 is no error when N is given and its correction is valid
    s, _ = summary(design(tmp_path), "--set", "geometry.inner_raceway_radius_mm=10", "--set",
                   "geometry.roller_gap_mm=19", "--set", "geometry.eccentricity_mm=0", "--set", "geometry.rollers=3",
                   "--set", 'geometry.correct="gap"', "--set", "geometry.scheme=B")
    assert s["N"] == 3 and s["N_star"] < 3 and s["roller_gap_mm"] < 19


def test_check_command(tmp_path):
    good = design(tmp_path)
    bad = design(tmp_path, "", "bad.toml", BASE.replace("eccentricity_mm = 6.0", "eccentricity_mm = 60.0"))
    r = runner.invoke(app, ["check", str(good), str(bad)])
    assert r.exit_code == 2 and "ok" in r.stdout and "bad.toml: geometry.eccentricity_mm" in r.stderr


def test_template_runs(tmp_path):
    r = runner.invoke(app, ["new", "zstk"])
    p = tmp_path / "new.toml"
    p.write_text(r.stdout)
    r2 = run(p, "--format", "csv")
    assert r2.exit_code == 0, r2.output


def test_run_command(tmp_path):
    r = run(design(tmp_path), "--format", "json")
    r2 = runner.invoke(app, ["run", str(design(tmp_path)), "--format", "json"])
    assert json.loads(r2.stdout)["summary"] == json.loads(r.stdout)["summary"]


def test_cycle_with_envelope(tmp_path):
    # spec §11.8: the maximum over placements and directions together bounds both single sweeps
    p = design(tmp_path)
    both, _ = summary(p, "--set", "geometry.scheme=cycle", "--set", "load.direction_deg=envelope")
    env, _ = summary(p, "--set", "load.direction_deg=envelope")
    cyc, _ = summary(p, "--set", "geometry.scheme=cycle")
    tol = both["sigma_max_err_MPa"] + env["sigma_max_err_MPa"] + cyc["sigma_max_err_MPa"]
    assert both["sigma_max_MPa"] >= max(env["sigma_max_MPa"], cyc["sigma_max_MPa"]) - tol
    # §8: the joint search's grid doubled at least once (roller positions per turn, relative directions per turn)
    assert both["phase_samples"] >= 32 and both["direction_samples"] >= 64


@pytest.mark.slow
def test_plot(tmp_path):
    pytest.importorskip("matplotlib")
    out = tmp_path / "zstk.png"
    r = run(EXAMPLE, CONFIGS / "zstk_merko_A_envelope.toml", "--plot", out, "--format", "csv")
    assert r.exit_code == 0, r.output
    data = out.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 10_000


@pytest.mark.parametrize("key", ["geometry.scheme", "load.direction_deg"])
def test_huge_angles_are_reduced(tmp_path, key):
    # angles are periodic: 1e300 degrees is reduced modulo 360 exactly (math.remainder), never NaN
    big, _ = summary(design(tmp_path), "--set", f"{key}=1e300")
    small, _ = summary(design(tmp_path), "--set", f"{key}={math.remainder(1e300, 360.0)!r}")
    assert big["sigma_max_MPa"] == small["sigma_max_MPa"]


def test_vanishing_roller_warns(tmp_path):
    # e -> R_H - R_B with the raceways kept (correct = "gap"): a tiny smallest roller, finite stress and the
    # b/rho warning (spec §9)
    s, r = summary(design(tmp_path), "--set", "geometry.eccentricity_mm=49.9999", "--set", 'geometry.correct="gap"')
    assert s["r_min_mm"] == pytest.approx(5e-5, rel=1e-6)
    assert math.isfinite(s["sigma_max_MPa"]) and s["sigma_max_roller_radius_mm"] == pytest.approx(5e-5, rel=1e-6)
    assert "b/rho" in r.stderr


@pytest.mark.parametrize("angle", [1.3266152821258527e+39, -7.5e250, 1e300, 4.0e40 + 2.0 ** 90])
def test_a_huge_load_direction_is_reduced_exactly(angle, tmp_path):
    # issue 34: direction_deg = 1.33e39 was a BracketError (exit 70): x - 360 round(x/360) loses everything at
    # that size. The direction is x modulo 360 exactly (math.remainder: fmod is exact for floats), so the results
    # equal those of the reduced angle (zstk.md §1: gamma is a direction, in deg).
    from conftest import cli

    def summary(value):
        r = cli("zstk", EXAMPLE, "--set", f"load.direction_deg={value!r}", "--format", "json")
        assert r.code == 0 and "internal error" not in r.err, r
        s = json.loads(r.out)["summary"]
        s.pop("model_time_ms", None)
        return s

    assert summary(angle) == summary(math.remainder(angle, 360.0))


# ---------------------------------------------------------------- zstk v2 (issue 16) through the adapter
# Tresca: the brute force over depth of Johnson's axis stresses (tests/test_hertz.py); the worked example's depth
# 0.786151 b with b = 2 F/(pi l sigma) (Johnson eq. 4.43).
def compute(**sets):
    return api.compute(api.load(EXAMPLE, overrides=sets), detail=True)


def col(res, key):
    return np.array([row[key] for row in res.detail["rollers"]], dtype=float)


# ----------------------------------------------------------------------------- item 3: Tresca shear


def test_product_reports_tresca_for_the_design_nu():
    # all bodies nu = 0.2: tau = 0.3302 sigma at 0.3217 b (summary at the critical contact, per contact in detail)
    res = compute(**{"material.roller_poisson": 0.2, "material.ring_poisson": 0.2})
    s = res.summary
    ratio, depth = (float(x) for x in brute_tresca(0.2))
    assert s["tau_max_MPa"] == pytest.approx(ratio * s["sigma_max_MPa"], rel=1e-9)
    i = s["sigma_max_roller"]
    assert s["tau_max_depth_mm"] == pytest.approx(depth * col(res, "b_B_mm")[i], rel=1e-5)
    assert np.allclose(col(res, "tau_max_B_MPa"), ratio * col(res, "sigma_B_MPa"), rtol=1e-9)
    assert np.allclose(col(res, "tau_depth_H_mm"), depth * col(res, "b_H_mm"), rtol=1e-5)
    # mixed: the smaller nu of a contact's two bodies governs (the body where the shear is largest)
    mixed = compute(**{"material.roller_poisson": 0.3, "material.inner_ring_poisson": 0.1})
    assert np.allclose(col(mixed, "tau_max_B_MPa"), brute_tresca(0.1)[0] * col(mixed, "sigma_B_MPa"), rtol=1e-9)
    assert np.allclose(col(mixed, "tau_max_H_MPa"), brute_tresca(0.3)[0] * col(mixed, "sigma_H_MPa"), rtol=1e-9)


def test_worked_example_tresca_equals_the_in_plane_value():
    s = compute().summary
    assert s["tau_max_MPa"] == hertz.TAU_MAX_RATIO * s["sigma_max_MPa"]
    # depth = 0.786151 b, b = 2 F/(pi l sigma) of the critical contact (Johnson eq. 4.43)
    res = compute()
    b = 2 * col(res, "F_B_N")[0] / (math.pi * 20.0 * s["sigma_max_MPa"])
    assert s["tau_max_depth_mm"] == pytest.approx(0.786151377757423 * b, rel=1e-12)


# ----------------------------------------------------------------------------- item 4: separator = false
def test_separator_false_is_refused():
    for command in ("zstk", "check"):
        r = cli(command, EXAMPLE, "--set", "geometry.separator=false", "--set", "geometry.roller_gap_mm=0")
        assert r.code == 2
        assert "geometry.separator" in r.err + r.out and "roller-to-roller contact" in r.err + r.out
    assert compute(**{"geometry.separator": True}).summary == compute().summary


def test_cost_guard_refuses_before_starting():
    r = cli("zstk", EXAMPLE, "--set", "geometry.inner_raceway_radius_mm=97.5", "--set", "geometry.eccentricity_mm=0.5",
            "--set", "geometry.roller_gap_mm=0.05", "--set", "geometry.rollers=2000", "--set", "geometry.scheme=cycle",
            "--set", "load.direction_deg=envelope", "--model", "reference")
    assert r.code == 2 and "over the budget" in r.err and "geometry.rollers" in r.err


# ---------------------------------------------------------------- the sweep and batch hooks
# The stacked (numpy over designs) evaluation equals compute point by point. The expected values are compute's own
# results, design by design (the independent numbers for the physics are above and in tests/zstk/); here every
# column of the vectorised sweep and every field of a batch must equal them exactly or to 1e-12 relative (round-off
# of a differently shaped array expression).
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
        rows.append({**p, **ZSTK.compute(validate(trial, str(EXAMPLE)), options).summary, "error": None})
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
    """Each axis value is valid with the base design, but (R_B = 90, e = 12) is not (e >= R_H - R_B = 10): the
    hook says so for that point only (InvalidPoints), with the key and constraint the point gives on its own; the
    frame gives the point a row with that reason and empty results, and computes the others (issue 36 item 1)."""
    from gearcalc.calculator import InvalidPoints

    raw = raw_example()
    axes = {"geometry.inner_raceway_radius_mm": [50.0, 90.0], "geometry.eccentricity_mm": [6.0, 12.0]}
    base = validate(copy.deepcopy(raw), str(EXAMPLE))
    with pytest.raises(InvalidPoints) as hook_err:
        ZSTK.sweep(base, raw, axes, sw.grid_points(axes), Options())
    bad = {"geometry.inner_raceway_radius_mm": 90.0, "geometry.eccentricity_mm": 12.0}
    k_bad = list(sw.grid_points(axes)).index(bad)
    messages = hook_err.value.messages
    assert [m is None for m in messages] == [k != k_bad for k in range(4)]
    # the same design on its own (gearcalc zstk --set ...) reports the same key and constraint
    trial = copy.deepcopy(raw)
    apply_set(trial, list(bad.items()))
    with pytest.raises(Exception) as alone:
        validate(trial, str(EXAMPLE))
    assert messages[k_bad].startswith("geometry.eccentricity_mm = ") and messages[k_bad] in str(alone.value)
    rows = sw.evaluate(raw, str(EXAMPLE), axes, Options())  # through the frame: a row per point, in grid order
    rows = rows.rows() if hasattr(rows, "rows") else rows
    assert rows[k_bad]["error"] == messages[k_bad] and rows[k_bad]["sigma_max_MPa"] is None
    assert {k: rows[k_bad][k] for k in axes} == bad
    good = [r for k, r in enumerate(rows) if k != k_bad]
    for r in good:
        trial = copy.deepcopy(raw)
        apply_set(trial, [(k, r[k]) for k in axes])
        same({k: r[k] for k in r if k not in axes}, {**ZSTK.compute(validate(trial, str(EXAMPLE)), Options()).summary,
                                                      "error": None})


def test_impossible_combination_of_rollers_and_scheme():
    """An explicit N of the wrong parity for the scheme (A, D even; B, C odd) at two grid points, (8, B) and (7, A):
    their rows name geometry.rollers; the other two are computed."""
    raw = raw_example()
    axes = {"geometry.rollers": [8, 7], "geometry.scheme": ["B", "A"]}
    rows = sw.evaluate(raw, str(EXAMPLE), axes, Options())
    rows = rows.rows() if hasattr(rows, "rows") else rows
    errors = [(r["geometry.rollers"], r["geometry.scheme"], r["error"]) for r in rows if r["error"] is not None]
    assert [e[:2] for e in errors] == [(8, "B"), (7, "A")] and all(e[2].startswith("geometry.rollers") for e in errors)
    assert sum(r["sigma_max_MPa"] is not None for r in rows) == 2


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


@pytest.mark.parametrize("model", [pytest.param("equilibrium", marks=pytest.mark.slow), "fixed-direction"])  # CI: both
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
    lists = lambda c: {k: v.tolist() if hasattr(v, "tolist") else v for k, v in c.items()}  # noqa: E731
    assert lists(cols) == lists(alone)  # (a column of numbers may be a numpy array: the sweep's columns)
    floats = sw.parse_vary(["load.radial_N=1000.0:20000.0:0.5"])   # a float axis: its values taken as they are
    g = sw.Grid(floats)
    assert lists(zstk.sweep(base, raw, floats, g[100:300], Options())) == lists(
        zstk.sweep(base, raw, floats, list(g[100:300]), Options()))


# ------------------------------------------------------------- guards (issue 13): cost, angles, tiny load, round-off
def test_zstk_sweep_cost_guard_names_rollers():
    # R_B = 99.6, e = 0.1, c = 0: N = 1619 rollers; "cycle" + "envelope" took 112 s with the nested sweep, ~3 s
    # with the joint search (zstk.md §8).  At --model reference its first grid is 3 x 1619 x 65 roller positions
    # x 256 relative directions = 8.08e7 roller-configurations > SWEEP_WORK_MAX = 6e6 (zstk/schema.py): refused
    # before it starts; at the default model (1.4e6) check accepts it
    sets = ["--set", "geometry.inner_raceway_radius_mm=99.6", "--set", "geometry.eccentricity_mm=0.1",
            "--set", "geometry.roller_gap_mm=0.0", "--set", 'geometry.scheme="cycle"',
            "--set", 'load.direction_deg="envelope"']
    r = cli("zstk", EXAMPLE, *sets, "--model", "reference")
    assert r.code == 2, r
    assert "geometry.rollers" in r.err and "8.08e+07" in r.err and "envelope" in r.err
    assert cli("check", EXAMPLE, *sets).code == 0


def test_direction_1e17_equals_its_remainder():
    # 1e17 = 360 k + 280 exactly (10^17 = 0 mod 8 and 10 mod 45, so 280 mod 360), i.e. -80 deg
    assert 10 ** 17 % 360 == 280
    opts = Options(tol=1e-6)
    calc = registry.get("zstk")
    for clearance in (0.0, 0.01):
        big = calc.compute(load(str(EXAMPLE), [("load.direction_deg", 1e17), ("load.clearance_mm", clearance)]),
                           opts)
        small = calc.compute(load(str(EXAMPLE), [("load.direction_deg", -80.0), ("load.clearance_mm", clearance)]),
                             opts)
        for key in ("sigma_max_MPa", "sigma_max_load_direction_deg", "approach_um", "loaded_rollers"):
            assert big.summary[key] == small.summary[key], key


def test_zstk_tiny_load_is_refused():
    # 5e-324 N returned solver_residual = 1.0 and pass = true; the schema now starts at MIN_FORCE_N = 1 uN,
    # where the worked example with 0.01 mm clearance balances Q to ~4e-8 (the error estimate includes it)
    from gearcalc.zstk import schema as kz

    r = cli("zstk", EXAMPLE, "--set", "load.radial_N=5e-324")
    assert r.code == 2 and "load.radial_N" in r.err
    s = registry.get("zstk").compute(load(str(EXAMPLE), [("load.radial_N", kz.MIN_FORCE_N),
                                                      ("load.clearance_mm", 0.01)]), Options(tol=1e-6)).summary
    assert s["solver_residual"] < 1e-6 and s["sigma_max_MPa"] > 0 and s["sigma_max_err_MPa"] > 0


def test_sweep_error_estimates_have_a_round_off_floor():
    # a cycle/envelope estimate is at least 4 eps |sigma_max| (kinds/zstk.ROUNDOFF_ULPS)
    import numpy as np

    for sets in ([("geometry.scheme", "cycle")], [("load.direction_deg", "envelope")]):
        s = registry.get("zstk").compute(load(str(EXAMPLE), sets), Options(tol=1e-3)).summary
        assert s["sigma_max_err_MPa"] >= 4 * np.finfo(float).eps * s["sigma_max_MPa"]
