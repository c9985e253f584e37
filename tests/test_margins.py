"""Checks as margins (issue 36 item 1; interface.md "Output", the kinds' specs): every design check is a signed,
dimensionless ``margin_<check>`` whose sign is the old flag's, ``failed_checks`` names the negative ones, a run
ends with one line per failing check, and a sweep point that is not a valid design is a row with its reason.

Every expected value is computed here from the summary's own inputs and outputs (sigma_max and the allowable
stress, the friction constants, the rim) or from the old flags; the flags themselves are tested elsewhere.
"""
import csv
import io
import math
import random

import pytest

import gearcalc
from conftest import CONFIGS, cli
from gearcalc import registry

CONFIG_FILES = sorted(CONFIGS.glob("*.toml"))
NEGATIVE_TIE = math.nextafter(0.0, -1.0)  # the least negative float: a failing check at the exact tie


def negatives(summary, kind):
    return [c.name for c in registry.get(kind).checks if summary.get(c.field) is not None and summary[c.field] < 0]


def agrees_with_flags(kind, s):
    """The old flags of the summary ``s`` against the signs of its margins (the same on every design)."""
    if kind == "zstk":
        assert s["pass"] == (s["margin_sigma"] >= 0)
        assert s["margin_closure"] >= 0 and s["margin_clearance"] >= 0  # validity rules: a computed design is inside
    elif kind == "rows":
        if "bridges_feasible" in s:
            assert s["bridges_feasible"] == (s["margin_bridge_fit"] >= 0)
        assert s["margin_bore"] >= 0
    else:
        if s["self_locking"] is None:
            assert s["margin_self_locking"] is None
        else:
            assert s["self_locking"] == (s["margin_self_locking"] < 0)
        assert (s["rolling_ok"] is None) == (s["margin_rolling"] is None)
        if s["rolling_ok"] is not None:
            assert s["rolling_ok"] == (s["margin_rolling"] >= 0)
    assert s["failed_checks"] == negatives(s, kind)


@pytest.mark.parametrize("path", CONFIG_FILES, ids=lambda p: p.stem)
def test_shipped_configs_margins_agree_with_flags(path):
    r = gearcalc.compute(path)
    agrees_with_flags(r.kind, r.summary)
    assert bool(r.failed) == bool(r.summary["failed_checks"])


def test_zstk_margins_value_and_sign_on_a_seeded_random_set():
    # 200 random designs around the worked example; the allowable stress straddles sigma_max so both signs occur
    rng = random.Random(36)
    for _ in range(40):
        over = {"load.radial_N": rng.uniform(1e3, 3e5), "load.clearance_mm": rng.uniform(-0.01, 0.01),
                "geometry.eccentricity_mm": rng.uniform(1.0, 10.0)}
        allow = [rng.uniform(300.0, 3000.0) for _ in range(5)]
        (part,) = gearcalc.sweep(CONFIGS / "zstk_merko_example.toml", {"material.allowable_stress_MPa": allow},
                                 overrides=over)
        for s in part.rows():
            agrees_with_flags("zstk", s)
            # independent: 1 - sigma_max/[sigma_H] from the two fields the summary prints
            assert s["margin_sigma"] == pytest.approx(1 - s["sigma_max_MPa"] / s["allowable_stress_MPa"], rel=1e-12,
                                                      abs=1e-15)
            assert s["margin_clearance"] == pytest.approx(1 - abs(s["clearance_mm"]) / s["r_min_mm"], rel=1e-12)


def test_rows_margins_value_and_sign_on_a_seeded_random_set():
    rng = random.Random(361)
    widths = sorted(rng.uniform(1.5, 5.0) for _ in range(12))
    bores = [0.0] + sorted(rng.uniform(10.0, 70.0) for _ in range(4))
    (part,) = gearcalc.sweep(CONFIGS / "rows_bridges_n4_B4_i4.toml", {"rows.relative_width": widths,
                                                                        "sun.bore_mm": bores,
                                                                        "rows.count": [3, 4]})
    rows = part.rows()
    signs = {True: 0, False: 0}
    for s in rows:
        agrees_with_flags("rows", s)
        signs[s["bridges_feasible"]] += 1
        assert s["margin_bridge_fit"] not in (0.0, NEGATIVE_TIE)  # the ties' clamp is not what decides the sign
        bore = s["sun.bore_mm"]
        d_f = 18 * 5.0 - 2 * 1.25 * 5.0  # z_a m - 2.5 m (rows.md §2), the design's sun
        if bore == 0:
            assert s["margin_rim"] is None
        else:
            t = (d_f - bore) / 2
            assert s["margin_rim"] == pytest.approx(1 - 2.7 * 5.0 / t, rel=1e-12)  # ISO 6336-3: 2.7 m
            assert ("rim" in s["failed_checks"]) == (t < 2.7 * 5.0)
    assert signs[True] and signs[False]  # both outcomes are in the set
    # the same points one by one: the same margins and failed checks
    for s in rows[::17]:
        alone = gearcalc.compute(CONFIGS / "rows_bridges_n4_B4_i4.toml",
                                 overrides={k: s[k] for k in ("rows.relative_width", "sun.bore_mm", "rows.count")})
        for key in ("margin_bridge_fit", "margin_bore", "margin_rim", "failed_checks"):
            assert alone.summary[key] == pytest.approx(s[key], rel=1e-12) if isinstance(s[key], float) \
                else alone.summary[key] == s[key]
        assert bool(alone.failed) == bool(s["failed_checks"])


def test_pins_margins_value_and_sign_on_a_seeded_random_set():
    rng = random.Random(362)
    base = CONFIGS / "pins_paper_cyc_u10_rotating.toml"
    sliding = [0.05] + sorted(rng.uniform(0.0, 1.0) for _ in range(10))  # 0.05: the bushings cannot roll
    axle = sorted(rng.uniform(0.0, 0.4) for _ in range(3))
    seen = set()
    for mode in ("multiplier", "reducer"):
        for model in ("first-order", "consistent"):
            (part,) = gearcalc.sweep(base, {"friction.sliding": sliding, "friction.axle": axle,
                                            "gearing.rotating_pins": [True, False]},
                                     overrides={"load.mode": mode, "friction.model": model,
                                                "contact.face_width_mm": 10.0,
                                                "material.allowable_stress_MPa": 3400.0})
            for s in part.rows():
                agrees_with_flags("pins", s)
                seen.update(s["failed_checks"])
                f, fc = s["friction.sliding"], s["friction.axle"]
                drive, resist = f * 1.95, fc * 0.95 + 0.01  # R_b, r, f_k of the design file
                if s["gearing.rotating_pins"]:
                    assert s["margin_rolling"] == pytest.approx((drive - resist) / max(drive, resist), rel=1e-12)
                if s["contact_stress_max_MPa"] is None:  # a jammed mode has no forces
                    assert s["margin_contact_stress"] is None and s["self_locking"]
                else:
                    assert s["margin_contact_stress"] == pytest.approx(1 - s["contact_stress_max_MPa"] / 3400.0,
                                                                       rel=1e-12)
                lam = s["loss_ratio"]
                if not s["self_locking"]:
                    eta = 1 - lam if mode == "multiplier" else 1 / (1 + lam)
                    assert s["margin_self_locking"] == pytest.approx(eta, rel=1e-12)
                    assert s["efficiency"] == pytest.approx(eta, rel=1e-12)  # the requested mode's efficiency
    assert seen == {"self_locking", "rolling", "contact_stress"}  # every check fails somewhere in the set


def test_pins_face_width_alone_keeps_the_ideal_level_with_its_stress():
    # issue 37 item 6: the stress of the ideal level's own forces, no switch to the contact level
    path = CONFIGS / "pins_paper_cyc_u10_rotating.toml"
    r = gearcalc.compute(path, overrides={"contact.face_width_mm": 10.0, "material.allowable_stress_MPa": 3000.0})
    forced = gearcalc.compute(path, model="ideal", overrides={"contact.face_width_mm": 10.0})
    assert r.model == "ideal" and r.summary["model_reason"] == "an unmodified cycloidal profile (rigid contacts)"
    assert r.summary["contact_stress_max_MPa"] == forced.summary["contact_stress_max_MPa"] > 3000.0
    assert r.summary["failed_checks"] == ["contact_stress"] and "allowable_stress_MPa = 3000" in r.failed[0]
    law = gearcalc.compute(path, overrides={"contact.face_width_mm": 10.0, "contact.law": "hertz"})
    assert law.model == "contact" and law.summary["model_reason"].startswith("[contact] names a contact law")


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


def test_sweep_and_batch_end_with_one_line_per_failing_check(tmp_path):
    r = cli("sweep", CONFIGS / "zstk_merko_example.toml", "--vary", "load.radial_N=1e4:4e5:1e4", "--set",
            "material.allowable_stress_MPa=2000", "--format", "csv", "--fields", "sigma_max_MPa,allowable_stress_MPa")
    rows = list(csv.DictReader(io.StringIO(r.out)))
    over = sum(float(x["sigma_max_MPa"]) > float(x["allowable_stress_MPa"]) for x in rows)  # counted independently
    assert 0 < over < len(rows) and r.code == 1
    assert r.err.strip().splitlines()[-1].endswith(
        f"{over} of {len(rows)} points fail sigma (sigma_max > allowable_stress)")
    assert "check failed at" not in r.err
    for p in sorted(CONFIGS.glob("zstk_merko_*.toml")):
        (tmp_path / p.name).write_text(p.read_text())
    r = cli("run", tmp_path, "--set", "material.allowable_stress_MPa=760", "--format", "csv", "--fields",
            "sigma_max_MPa")
    sigmas = [float(x["sigma_max_MPa"]) for x in csv.DictReader(io.StringIO(r.out))]
    failing = sum(s > 760 for s in sigmas)
    assert r.code == 1 and 0 < failing < len(sigmas)
    assert f"{failing} of {len(sigmas)} zstk designs fail sigma (sigma_max > allowable_stress)" in r.err
    assert r.err.count("check failed: sigma_max_MPa") == failing  # the per-file messages are kept


@pytest.mark.parametrize("column", [
    [1.0, -2.0, None, True, False, -0.0, float("nan"), -3, NEGATIVE_TIE],
    [None] * 4, [1.0, -1.0, "words"], [10 ** 400, -(10 ** 400), -1],
    "numpy float", "numpy int", "numpy flags", "numpy objects",
])
def test_failing_points_of_a_column_at_once_are_those_value_by_value(column):
    """The count and the failed_checks of sweep columns (a numpy comparison, a list of numbers as floats) are
    those of the rule of one value (calculator._below_zero: a number below zero; None, a flag, a word never)."""
    import numpy as np

    from gearcalc.calculator import Check, Calculator, _below_zero, failed_check_column

    column = {"numpy float": np.array([1.0, -1.0, np.nan, NEGATIVE_TIE]), "numpy int": np.array([3, -1, 0]),
              "numpy flags": np.array([True, False]), "numpy objects": np.array([1.0, None, -2.0], dtype=object),
              }.get(column, column) if isinstance(column, str) else column
    values = column.tolist() if hasattr(column, "tolist") else column
    below = [k for k, v in enumerate(values) if _below_zero(v)]
    calc = Calculator("x", "x", (), None, checks=(Check("a", ""), Check("b", "")))
    assert calc.failed_points({"margin_a": column}) == ({"a": len(below)} if below else {})
    got = failed_check_column({"margin_a": column, "margin_b": [-1.0] * len(values)}, calc.checks, len(values))
    assert got == [(["a"] if k in below else []) + ["b"] for k in range(len(values))]
