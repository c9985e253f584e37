"""The rows calculator through the command line: examples, formats, fields, hard cases, bad input."""
import csv
import io
import json
import math

import pytest

from conftest import PAPER, CONFIGS, cli

EXAMPLES = ["rows_fig3_n3_nw3_B2.4.toml", "rows_bridges_n4_B4_i6.toml", "rows_mass_fig5.toml"]
BASE = """kind = "rows"
[gear]
sun_teeth = 18
module_mm = 5.0
[rows]
count = 3
planets_per_row = 3
relative_width = 2.4
[sun]
torque_Nm = 1000.0
"""


def as_json(*args):
    r = cli("rows", *args, "--format", "json")
    assert r.code in (0, 1), r
    return json.loads(r.out), r


@pytest.mark.parametrize("name", EXAMPLES)
def test_examples_json_csv_table_agree(name):
    path = CONFIGS / name
    obj, _ = as_json(path)
    r = cli("rows", path, "--format", "csv")
    row = next(csv.DictReader(io.StringIO(r.out)))
    for k, v in obj["summary"].items():
        if isinstance(v, float):
            assert float(row[k]) == v  # repr round trip: identical
        elif v is None:
            assert row[k] == ""
    t = cli("rows", path, "--format", "table")
    assert t.code == 0 and "K_exact" in t.out and obj["name"] in t.out


def test_smoke_value_through_cli():
    obj, _ = as_json(CONFIGS / "rows_fig3_n3_nw3_B2.4.toml")
    s = obj["summary"]
    assert round(s["K"], 3) == 1.489  # paper's stated value
    assert s["model"] == "stepwise" and s["K_row"] == 1 and s["unloaded_rows"] == []
    assert obj["design"]["material"]["mesh_stiffness_MPa"] == 0.075 * 2e5  # default echoed
    # equilibrium in the detail: Σ w = T_a / (r_ba b_w n_w) = n w̄
    obj, _ = as_json(CONFIGS / "rows_fig3_n3_nw3_B2.4.toml", "--detail")
    w = [r["w_stepwise_N_per_mm"] for r in obj["detail"]["rows"]]
    assert sum(w) == pytest.approx(3 * obj["summary"]["w_mean_N_per_mm"], rel=1e-13)
    assert sum(r["share_exact_pct"] for r in obj["detail"]["rows"]) == pytest.approx(100.0, rel=1e-13)


def test_bridge_example_fields():
    obj, r = as_json(CONFIGS / "rows_bridges_n4_B4_i6.toml")
    s = obj["summary"]
    paper = [0, 0.12, 0.43, 0.43]  # paper's table, i = 6, n = 4, B = 4
    assert all(abs(s[f"bridge_rel_{j + 1}"] - paper[j]) <= 0.035 for j in range(4))
    assert s["bridges_feasible"] is True and s["K_balanced"] == pytest.approx(1.0, abs=1e-12)
    assert r.code == 0


def test_capped_bridge_exit_1():
    obj, r = as_json(PAPER / "rows_bridges_n3_B3_i4.toml")
    assert r.code == 1 and obj["summary"]["bridges_feasible"] is False
    assert "exceeds_max" in r.err and obj["checks_failed"]
    assert obj["summary"]["bridge_rel_3"] == 1.0


@pytest.mark.parametrize("module,torque", [(2.0, 10.0), (8.0, 1e6)])
def test_bridge_ratios_do_not_change_with_module_or_torque(module, torque):
    a, _ = as_json(CONFIGS / "rows_bridges_n4_B4_i6.toml")
    b, _ = as_json(CONFIGS / "rows_bridges_n4_B4_i6.toml", "--set", f"gear.module_mm={module}",
                   "--set", f"sun.torque_Nm={torque}")
    for j in range(1, 5):
        assert b["summary"][f"bridge_rel_{j}"] == pytest.approx(a["summary"][f"bridge_rel_{j}"], rel=1e-9, abs=1e-12)
    assert b["summary"]["K"] == pytest.approx(a["summary"]["K"], rel=1e-12)


def test_mass_example():
    obj, _ = as_json(CONFIGS / "rows_mass_fig5.toml")
    s = obj["summary"]
    # closed form (rows.md §6): i* = 2 + sqrt(C0/A), n = 2, n_w = 3, t = 0.06, k_a = 0.7, k_g = 1, b̄ = 0.25
    L_h, L_a = 0.25 * 3 + 2 + 0.25, 0.25 * 1 + 2
    A = 8 * 0.06 * L_h + 1 * 2 * 3 / 4 + 0.25 * 3 / 4
    C0 = 8 * 0.06 * L_h + 0.7 * L_a + 0.25 * 3
    assert abs(s["ratio_opt"] - (2 + math.sqrt(C0 / A))) <= s["ratio_opt_err"]
    assert s["ratio"] == s["ratio_opt"] and s["ratio_opt_on_bound"] is False
    assert s["relative_mass_kg_per_kNm"] == s["relative_mass_min_kg_per_kNm"]


def test_tolerance_controls_ratio_error():
    loose, _ = as_json(CONFIGS / "rows_mass_fig5.toml", "--tol", "1e-3")
    tight, _ = as_json(CONFIGS / "rows_mass_fig5.toml", "--tol", "1e-9")
    assert loose["summary"]["ratio_opt_err"] > 10 * tight["summary"]["ratio_opt_err"]
    assert abs(loose["summary"]["ratio_opt"] - tight["summary"]["ratio_opt"]) <= loose["summary"]["ratio_opt_err"]
    # never below the sqrt(eps) floor (rows.md §6)
    assert tight["summary"]["ratio_opt_err"] >= 3 * math.sqrt(2.220446049250313e-16) * tight["summary"]["ratio_opt"]


def test_mass_with_computed_unevenness_uses_K(write):
    p = write(BASE + "[mass]\nunevenness = \"computed\"\n")
    obj, _ = as_json(p)
    assert obj["summary"]["mass_unevenness"] == obj["summary"]["K"]


@pytest.mark.parametrize("model", ["stepwise", "exact", "continuous"])
def test_model_option(model):
    obj, _ = as_json(CONFIGS / "rows_fig3_n3_nw3_B2.4.toml", "--model", model)
    s = obj["summary"]
    assert s["model"] == model and s["K"] == s[f"K_{model}"]


def test_unknown_model_is_usage_error():
    r = cli("rows", CONFIGS / "rows_fig3_n3_nw3_B2.4.toml", "--model", "ideal")
    assert r.code == 2 and "stepwise, exact, continuous" in r.err


# ------------------------------------------------------------------ hard cases (rows.md §10)
def test_one_row(write):
    obj, _ = as_json(write(BASE.replace("count = 3", "count = 1")), "--model", "continuous")
    s = obj["summary"]
    assert s["K"] == s["K_stepwise"] == s["K_exact"] == s["K_continuous"] == 1.0
    mu = math.sqrt(s["kappa"])
    assert s["peak_factor"] == pytest.approx(mu / math.tanh(mu), rel=1e-12)


def test_one_row_bridges_nothing_to_size(write):
    obj, r = as_json(write(BASE.replace("count = 3", "count = 1") + "[bridges]\n").__str__(),
                     "--set", "gear.ratio=6")
    s = obj["summary"]
    assert r.code == 0 and s["bridges_feasible"] and s["bridge_1_mm"] == 0.0 and s["K_balanced"] == 1.0


@pytest.mark.parametrize("n", [200, 1000])
def test_many_rows(write, n):
    obj, _ = as_json(write(BASE.replace("count = 3", f"count = {n}")))
    s = obj["summary"]
    assert 1 <= s["K"] <= n and s["stepwise_valid"]


def test_huge_B_falls_back_to_exact(write):
    obj, r = as_json(write(BASE.replace("relative_width = 2.4", "relative_width = 40.0")))
    s = obj["summary"]
    assert s["stepwise_valid"] is False and s["K_stepwise"] is None and s["model"] == "exact"
    assert "not available" in r.err and "outside the paper's range" in r.err
    assert math.isfinite(s["peak_factor"]) and s["K"] == s["K_exact"]
    c = cli("rows", write(BASE.replace("relative_width = 2.4", "relative_width = 40.0")), "--format", "csv")
    row = next(csv.DictReader(io.StringIO(c.out)))
    assert row["K_stepwise"] == "" and row["K_stepwise_vs_exact_pct"] == ""
    t = cli("rows", write(BASE.replace("relative_width = 2.4", "relative_width = 40.0")), "--format", "table")
    assert "n/a" in t.out


def test_huge_B_with_bridges_reports_widths_and_null_K_balanced(write):
    p = write(BASE.replace("relative_width = 2.4", "relative_width = 40.0") + "[bridges]\n")
    obj, r = as_json(p, "--set", "gear.ratio=6")
    s = obj["summary"]
    assert s["K_balanced"] is None and "K_balanced is not available" in r.err
    assert all(math.isfinite(s[f"bridge_{j}_mm"]) for j in range(1, 4))


def test_small_B(write):
    obj, _ = as_json(write(BASE.replace("relative_width = 2.4", "relative_width = 1e-9")))
    s = obj["summary"]
    for k in ("K", "K_exact", "K_continuous", "peak_factor"):
        assert s[k] == pytest.approx(1.0, abs=1e-12)


def test_zero_cheek(write):
    obj, _ = as_json(write(BASE + ""), "--set", "rows.cheek_ratio=0")
    s = obj["summary"]
    assert s["peak_factor"] == pytest.approx(s["K_continuous"], rel=1e-12)


def test_single_planet_warns(write):
    _, r = as_json(write(BASE.replace("planets_per_row = 3", "planets_per_row = 1")))
    assert "sun bending" in r.err


def test_colliding_planets_warn(write):
    _, r = as_json(write(BASE), "--set", "rows.planets_per_row=12", "--set", "gear.ratio=6")
    assert "collide" in r.err


def test_non_integer_planet_teeth_warns(write):
    _, r = as_json(write(BASE), "--set", "gear.ratio=5.1")
    assert "not an integer" in r.err


def test_hollow_sun(write):
    obj, r = as_json(write(BASE), "--set", "sun.bore_mm=60", "--set", "sun.torsion_diameter=\"root\"")
    assert obj["summary"]["kappa"] > 0 and "thinner than 1.2 tooth depths" in r.err
    r = cli("rows", write(BASE), "--set", "sun.bore_mm=77.5", "--set", "sun.torsion_diameter=\"root\"")
    assert r.code == 2 and "sun.bore_mm" in r.err and "77.5" in r.err


@pytest.mark.parametrize("bore", [70.0, 77.0, 77.49])
def test_bore_near_root_is_finite(write, bore):
    obj, _ = as_json(write(BASE), "--set", f"sun.bore_mm={bore}", "--set", "sun.torsion_diameter=\"root\"")
    assert all(v is None or not isinstance(v, float) or math.isfinite(v) for v in obj["summary"].values())


BAD = [
    ("gear.ratio", "[gear]\nsun_teeth = 18\nmodule_mm = 5.0\nratio = 2.0\n", "> 2"),
    ("mass.ratio_range", "[mass]\nratio_range = [2.0, 12.0]\n", "> 2"),
    ("rows.count", "", "count = 0"),
    ("rows.planets_per_row", "", "planets_per_row = 0"),
    ("material.poisson", "[material]\npoisson = 0.5\n", "< 0.5"),
    ("mass.efficiency", "[mass]\nefficiency = 1.2\n", "<= 1"),
    ("gear.module_mm", "", "module_mm = -5.0"),
    ("gear.sun_teeth", "", "sun_teeth = 17.5"),
    ("rows.relative_width", "", "relative_width = 2.4\nrim_width_mm = 50.0"),
    ("rows.cheek_ratio", "", "cheek_ratio = 0.25\ncheek_mm = 10.0"),
    ("gear.ratio", "[bridges]\n", "missing"),
]


@pytest.mark.parametrize("key,extra,what", BAD)
def test_bad_input_names_file_key_constraint(write, key, extra, what):
    text = BASE
    if what.startswith(("count", "planets", "module", "sun_teeth", "relative_width", "cheek_ratio")):
        field = what.split(" =")[0]
        lines = [ln for ln in text.splitlines() if not ln.startswith(field)]
        text = "\n".join(lines) + "\n"
        text = text.replace("[rows]\n", "[rows]\n" + what + "\n") if key.startswith("rows") else \
            text.replace("[gear]\n", "[gear]\n" + what + "\n")
    if extra.startswith("[gear]"):
        text = text.replace("[gear]\nsun_teeth = 18\nmodule_mm = 5.0\n", extra)
    elif extra:
        text += extra
    p = write(text, "bad_design.toml")
    r = cli("rows", p)
    assert r.code == 2, r
    assert "bad_design.toml" in r.err and key in r.err, r.err
    assert "Traceback" not in r.err


def test_ratio_and_planet_teeth_must_agree(write):
    r = cli("rows", write(BASE), "--set", "gear.ratio=6", "--set", "gear.planet_teeth=30")
    assert r.code == 2 and "disagrees" in r.err
    ok = cli("rows", write(BASE), "--set", "gear.ratio=6", "--set", "gear.planet_teeth=36", "--format", "json")
    assert ok.code == 0


def test_first_span_above_max(write):
    r = cli("rows", write(BASE + "[bridges]\nfirst_span = 1e6\n"), "--set", "gear.ratio=6")
    assert r.code == 2 and "bridges.first_span" in r.err and "H_max" in r.err


def test_first_span_in_mm(write):
    obj, _ = as_json(write(BASE + "[bridges]\nfirst_span = 5.0\n"), "--set", "gear.ratio=6")
    assert obj["summary"]["bridge_1_mm"] == 5.0


def test_rim_width_and_cheek_mm_inputs(write):
    a, _ = as_json(write(BASE))
    b_w = a["summary"]["rim_width_mm"]
    text = BASE.replace("relative_width = 2.4", f"rim_width_mm = {b_w!r}\ncheek_mm = {0.25 * b_w!r}")
    b, _ = as_json(write(text, "b.toml"))
    assert b["summary"]["relative_width"] == pytest.approx(2.4, rel=1e-14)
    assert b["summary"]["K"] == pytest.approx(a["summary"]["K"], rel=1e-12)
    text = BASE.replace("relative_width = 2.4", f"relative_width = 2.4\ncheek_mm = {0.25 * b_w!r}")
    c, _ = as_json(write(text, "c.toml"))
    assert c["summary"]["K"] == pytest.approx(a["summary"]["K"], rel=1e-12)
