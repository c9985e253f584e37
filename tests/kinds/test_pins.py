"""CLI tests of `gearcalc pins`: example designs, output formats, levels, hard cases and bad input (pins.md §9);
``gearcalc check`` refuses what a run refuses (issue 13)."""
import copy
import csv
import io
import json
import math
import random
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest
import tomli_w
from typer.testing import CliRunner

from conftest import cli
from gearcalc import grid as sw
from gearcalc.calculator import Options
from gearcalc.cli import app
from gearcalc.design import read_toml


ROOT = Path(__file__).resolve().parents[2]
CONFIGS = ROOT / "configs"
runner = CliRunner()
FIRST_ORDER = ("--set", "friction.model=first-order")
"""The first-order model for a shipped design (pins.md §4.6-4.7), whose file leaves the default (§4.9)."""

BASE = {
    "kind": "pins",
    "name": "test design",
    "gearing": {"profile": "cycloidal", "satellite_teeth": 20, "pins": 22, "eccentricity_mm": 3.9,
                "curtate_ratio": 0.75, "pin_radius_mm": 1.95, "axle_radius_mm": 0.95, "rotating_pins": False},
    # these tests pin the first-order model's numbers (pins.md §4.6-4.7; the default is the friction-consistent
    # model of §4.9, tests/pins/test_consistent.py): the designs say so, and so does FIRST_ORDER for the configs
    "friction": {"sliding": 0.1, "rolling_mm": 0.01, "axle": 0.1, "model": "first-order"},
    "load": {"mode": "multiplier", "torque_shaft": "H", "torque_Nm": 100.0, "crank_speed_rpm": 1000.0},
}


def changed(base, changes, drop=()):
    """A copy of a design dict with changes {"table__key": value} (None deletes) and dropped tables."""
    d = copy.deepcopy(base)
    for t in drop:
        d.pop(t, None)
    for dotted, v in changes.items():
        table, key = dotted.split("__")
        if v is None:
            d[table].pop(key, None)
        else:
            d.setdefault(table, {})[key] = v
    return d


def design(tmp_path, name="d.toml", drop=(), base=None, **changes):
    """Write BASE (or ``base``) with changes {"table__key": value} (None deletes) and dropped tables."""
    d = changed(BASE if base is None else base, changes, drop)
    p = tmp_path / name
    p.write_text(tomli_w.dumps(d))
    return p


def run(*args):
    r = runner.invoke(app, ["pins", *map(str, args)])
    return r.exit_code, r.stdout, r.stderr


def summary(*args):
    code, out, errtext = run(*args, "--format", "json")
    assert code in (0, 1), errtext
    return json.loads(out)["summary"], code, errtext


# ------------------------------------------------------------------ the shipped designs

PAPER_FORMULA = {  # file: printed (F_tr1, F_tr2, P_tr1, P_tr2, P_tr) and their decimals (seed 000, eqs. 3-7)
    "pins_paper_formula_cyc_u10.toml": ((9.85, 192, 0.028, 0.267, 0.295), (2, 0, 3, 3, 3)),
    "pins_paper_formula_cyc_u30.toml": ((4.46, 87, 0.031, 0.294, 0.325), (2, 0, 3, 3, 3)),
    "pins_paper_formula_circ_u10.toml": ((7.64, 210, 0.04, 0.692, 0.732), (2, 0, 2, 3, 3)),
    "pins_paper_formula_circ_u30.toml": ((4.44, 111, 0.071, 1.063, 1.134), (2, 0, 3, 3, 3)),
}


@pytest.mark.parametrize("fname", sorted(PAPER_FORMULA))
def test_paper_formula_configs(fname):
    s, code, _ = summary(CONFIGS / fname)
    assert code == 0 and s["model"] == "formula" and s["rotating_pins"] is True
    assert s["efficiency"] is None and s["mode"] is None and s["profile"] is None
    printed, dec = PAPER_FORMULA[fname]
    got = [s[k] for k in ("F_tr1_N", "F_tr2_N", "P_tr1_W", "P_tr2_W", "P_tr_W")]
    for g, p, d in zip(got, printed, dec):
        assert abs(g - p) <= 0.5 * 10.0 ** (-d) + 1e-12


CYC = ["pins_paper_cyc_u10_fixed.toml", "pins_paper_cyc_u10_rotating.toml",
       "pins_paper_cyc_u30_fixed.toml", "pins_paper_cyc_u30_rotating.toml"]


@pytest.mark.parametrize("fname", CYC)
def test_cycloidal_configs(fname):
    s, code, _ = summary(CONFIGS / fname, *FIRST_ORDER)
    assert code == 0 and s["model"] == "ideal" and s["tolerance_met"] is True
    # pins.md §10: a plausibility band of roughly 0.75-0.95
    assert 0.75 < s["efficiency"] < 0.95
    assert s["efficiency_err"] <= 1e-6 * s["loss_ratio"]
    assert s["pin_loss_bound_W"] >= s["pin_loss_max_W"]
    assert s["efficiency_reducer"] == pytest.approx(1 / (2 - s["efficiency_multiplier"]), rel=1e-12)
    # torque_in = u T_H / eta (multiplier, torque on H)
    assert s["torque_in_Nm"] == pytest.approx(s["ratio"] * 100.0 / s["efficiency"], rel=1e-12)
    assert s["loaded_pins_max"] < 22 / 2 if "u10" in fname else s["loaded_pins_max"] < 62 / 2


def test_rotating_beats_fixed_when_mu_rot_below_f():
    # pins.md §10 structural trend: mu_rot = (0.1*0.95 + 0.01)/1.95 = 0.054 < f = 0.1
    for u in ("u10", "u30"):
        fixed = summary(CONFIGS / f"pins_paper_cyc_{u}_fixed.toml", *FIRST_ORDER)[0]
        rot = summary(CONFIGS / f"pins_paper_cyc_{u}_rotating.toml", *FIRST_ORDER)[0]
        assert rot["efficiency"] > fixed["efficiency"]
        assert rot["loss_ratio"] / fixed["loss_ratio"] == pytest.approx((0.1 * 0.95 + 0.01) / 1.95 / 0.1, rel=1e-5)


def test_circular_example_runs_the_contact_level():
    # the spec example (a circular profile is not conjugate: pins.md §1, §7) now computes at the contact level
    s, code, err = summary(CONFIGS / "pins_paper_circ_u10_fixed.toml", *FIRST_ORDER)
    assert code == 0 and s["model"] == "contact" and s["profile"] == "circular" and "Traceback" not in err
    assert s["tolerance_met"] is True and s["efficiency_err"] <= 1e-6 * s["loss_ratio"]


def test_json_and_csv_agree(tmp_path):
    f = CONFIGS / "pins_paper_cyc_u10_rotating.toml"
    s, _, _ = summary(f, *FIRST_ORDER)
    _, out, _ = run(f, *FIRST_ORDER, "--format", "csv")
    row = next(iter(csv.DictReader(io.StringIO(out))))
    for k, v in s.items():
        if k == "model_time_ms":
            continue                       # a measurement, different on every run
        if isinstance(v, float):
            assert float(row[k]) == v
        elif v is None:
            assert row[k] == ""


def test_table_output_runs():
    code, out, _ = run(CONFIGS / "pins_paper_cyc_u10_fixed.toml", *FIRST_ORDER, "--format", "table")
    assert code == 0 and "efficiency" in out


def test_detail_tables(tmp_path):
    code, out, _ = run(CONFIGS / "pins_paper_cyc_u10_fixed.toml", *FIRST_ORDER, "--format", "json", "--detail")
    obj = json.loads(out)
    crank, contacts = obj["detail"]["crank"], obj["detail"]["contacts"]
    s = obj["summary"]
    assert len(crank) >= s["n_crank"]
    assert sum(r["loaded_pins"] for r in crank) == len(contacts)
    assert max(r["force_N"] for r in contacts) == pytest.approx(s["pin_force_max_N"], rel=1e-12)
    assert max(r["loss_W"] for r in crank) == pytest.approx(s["loss_peak_W"], rel=1e-12)
    thetas = [r["theta_deg"] for r in crank]
    assert thetas == sorted(thetas) and thetas[0] == 0.0 and thetas[-1] == pytest.approx(360 / 22)
    code, out, _ = run(CONFIGS / "pins_paper_cyc_u10_fixed.toml", *FIRST_ORDER, "--format", "csv", "--detail")
    assert code == 0 and out.startswith("name,table,")


@pytest.mark.parametrize("mode", ["multiplier", "reducer"])
def test_detail_pin_phases_match_the_pointwise_phase(tmp_path, mode):
    import math

    from gearcalc import pins

    p = design(tmp_path, load__mode=mode)
    _, out, _ = run(p, "--format", "json", "--detail")
    rows = json.loads(out)["detail"]["contacts"]
    sigma = pins.MULTIPLIER if mode == "multiplier" else pins.REDUCER
    for r in rows[5:400:37]:
        ph = pins.pin_phase(r["pin"], math.radians(r["theta_deg"]), 22, sigma)
        assert math.degrees(ph) == pytest.approx(r["phase_deg"], abs=1e-9)


# ------------------------------------------------------------------ levels and operating points

def test_template_runs(tmp_path):
    r = runner.invoke(app, ["new", "pins"])
    p = tmp_path / "t.toml"
    p.write_text(r.stdout)
    code, out, err = run(p, "--format", "csv")
    assert code == 0, err
    assert "ideal" in out


def test_model_ideal_on_circular_is_an_error(tmp_path):
    # with its [contact] law complete: check() reports a missing face width first (issue 13, any level)
    p = design(tmp_path, gearing__profile="circular", contact__face_width_mm=10.0)
    code, _, err = run(p, "--model", "ideal")
    assert code == 2 and "gearing.profile" in err and "conjugate (cycloidal)" in err


def test_model_formula_needs_pin_load(tmp_path):
    code, _, err = run(design(tmp_path), "--model", "formula")
    assert code == 2 and "pin_load" in err


def test_contact_table_and_modifications_select_the_contact_level(tmp_path):
    # pins.md §7: a [contact] table or a modification runs the contact level; --model contact forces it
    s, code, _ = summary(design(tmp_path, contact__law="linear", contact__stiffness_N_per_mm=1e7), "--tol", "1e-4")
    assert code == 0 and s["model"] == "contact"
    s, code, _ = summary(design(tmp_path, gearing__equidistant_mod_mm=0.01, contact__face_width_mm=10.0),
                         "--tol", "1e-4")
    assert code == 0 and s["model"] == "contact" and s["backlash_deg"] > 0
    # a plain cycloid with --model contact and no [contact] table: the hertz law needs the face width
    code, _, err = run(design(tmp_path), "--model", "contact")
    assert code == 2 and "contact.face_width_mm" in err and "missing" in err and "Traceback" not in err
    # --model ideal runs a cycloidal design with a [contact] table naming its law, ignoring the law with a warning
    code, _, err = run(design(tmp_path, contact__law="hertz", contact__face_width_mm=10.0), "--model", "ideal")
    assert code == 0 and "not used" in err
    # issue 37 item 6: a [contact] table with face_width_mm alone keeps the ideal level (no warning), which gives
    # the Hertz stress of its own forces, and says why it ran
    s, code, err = summary(design(tmp_path, contact__face_width_mm=10.0))
    assert code == 0 and s["model"] == "ideal" and s["contact_stress_max_MPa"] > 0 and "not used" not in err
    assert s["model_reason"] == "an unmodified cycloidal profile (rigid contacts)"


def test_pin_load_with_gearing_gives_both(tmp_path):
    p = design(tmp_path, pin_load__normal_force_N=1920.0, pin_load__pin_speed_rpm=14.0,
               pin_load__pin_radius_mm=1.95, pin_load__axle_radius_mm=0.95)
    s, _, _ = summary(p)
    assert s["model"] == "ideal" and s["P_tr_W"] is not None and s["efficiency"] is not None
    s, _, _ = summary(p, "--model", "formula")
    assert s["model"] == "formula" and s["efficiency"] is None
    assert s["P_tr_fixed_W"] == pytest.approx(0.1 * 1920 * 14 * 3.141592653589793 / 30 * 1.95e-3, rel=1e-12)


def test_torque_and_speed_do_not_change_efficiency(tmp_path):
    ref, _, _ = summary(design(tmp_path))
    for T in (1e-6, 1.0, 1e9):
        s, _, _ = summary(design(tmp_path, load__torque_Nm=T))
        assert s["efficiency"] == ref["efficiency"]
        assert s["pin_force_max_N"] == pytest.approx(ref["pin_force_max_N"] * T / 100.0, rel=1e-12)
    s, _, _ = summary(design(tmp_path, load__crank_speed_rpm=37.0))
    assert s["efficiency"] == ref["efficiency"]
    assert s["pin_speed_max_rpm"] == ref["pin_speed_max_rpm"] == 0.0
    assert s["sliding_speed_max_m_s"] == pytest.approx(ref["sliding_speed_max_m_s"] * 37 / 1000, rel=1e-12)


def test_torque_on_V_and_on_H_agree(tmp_path):
    for mode in ("multiplier", "reducer"):
        h, _, _ = summary(design(tmp_path, load__mode=mode))
        tv = h["torque_in_Nm"] if mode == "multiplier" else h["torque_out_Nm"]
        v, _, _ = summary(design(tmp_path, load__mode=mode, load__torque_shaft="V", load__torque_Nm=tv))
        assert v["pin_force_max_N"] == pytest.approx(h["pin_force_max_N"], rel=1e-12)
        assert v["loss_mean_W"] == pytest.approx(h["loss_mean_W"], rel=1e-12)
    red, _, _ = summary(design(tmp_path, load__mode="reducer"))
    mul, _, _ = summary(design(tmp_path))
    assert red["loss_ratio"] == pytest.approx(mul["loss_ratio"], rel=1e-12)     # mirror: same lambda_bar
    assert red["efficiency"] == red["efficiency_reducer"]
    # reducer: T_V = eta u T_H
    assert red["torque_out_Nm"] == pytest.approx(red["efficiency"] * 10 * 100.0, rel=1e-12)


def test_zero_friction_gives_exactly_one(tmp_path):
    s, code, _ = summary(design(tmp_path, friction__sliding=0.0, friction__rolling_mm=0.0, friction__axle=0.0))
    assert code == 0
    assert s["efficiency"] == 1.0 and s["efficiency_err"] == 0.0 and s["efficiency_reducer"] == 1.0
    assert s["loss_mean_W"] == 0.0 and s["pin_force_max_N"] > 0


def test_large_friction_self_locks_the_multiplier(tmp_path):
    s, code, err = summary(design(tmp_path, friction__sliding=1.0))
    assert code == 1 and s["self_locking"] is True and s["efficiency"] is None
    assert s["efficiency_multiplier"] is None and 0 < s["efficiency_reducer"] < 1
    assert "self-locking" in err
    code, out, _ = run(design(tmp_path, friction__sliding=1.0), "--format", "csv")
    row = next(iter(csv.DictReader(io.StringIO(out))))
    assert row["efficiency"] == "" and row["self_locking"] == "true"
    # the reducer is still reported and does not fail
    s, code, _ = summary(design(tmp_path, friction__sliding=1.0, load__mode="reducer"))
    assert code == 0 and s["self_locking"] is False and 0 < s["efficiency"] < 1


def test_tiny_eccentricity(tmp_path):
    p = design(tmp_path, gearing__eccentricity_mm=1e-6, gearing__curtate_ratio=None,
               gearing__pin_circle_radius_mm=57.2)
    s, code, _ = summary(p)
    assert code == 1 and s["self_locking"] is True
    s, code, _ = summary(design(tmp_path, gearing__eccentricity_mm=1e-6, gearing__curtate_ratio=None,
                                gearing__pin_circle_radius_mm=57.2, load__mode="reducer", load__torque_shaft="V"))
    # forces ~ T_V/r_p1 with r_p1 = e z1/k = 1e-5 mm: finite and huge
    assert code == 0 and 0 < s["efficiency"] < 1e-3 and 1e9 < s["pin_force_max_N"] < 1e12


def test_no_crank_speed_leaves_powers_empty(tmp_path):
    s, code, err = summary(design(tmp_path, load__crank_speed_rpm=None))
    assert code == 0 and s["efficiency"] is not None and s["pin_force_max_N"] is not None
    assert s["loss_mean_W"] is None and s["pin_speed_max_rpm"] is None and s["pin_loss_max_W"] is None
    assert "crank_speed_rpm" in err


def test_rolling_condition_violated_falls_back_to_fixed(tmp_path):
    fixed, _, _ = summary(design(tmp_path))
    s, code, err = summary(design(tmp_path, gearing__rotating_pins=True, friction__sliding=0.05,
                                  friction__axle=0.1, friction__rolling_mm=0.01))
    # a failed check (issue 36 item 1: margin_rolling < 0; it was a warning), the model goes on with fixed pins
    assert code == 1 and s["rolling_ok"] is False and s["margin_rolling"] < 0 and "check failed" in err
    assert s["failed_checks"] == ["rolling"]
    for word in ("f = 0.05", "f_c = 0.1", "r = 0.95", "f_k = 0.01", "R_b = 1.95"):
        assert word in err
    assert s["loss_ratio"] == pytest.approx(fixed["loss_ratio"] * 0.5, rel=1e-6)
    assert s["pin_speed_max_rpm"] == 0.0


@pytest.mark.parametrize("k", [1, 2, 3])
def test_tooth_differences(tmp_path, k):
    s, code, _ = summary(design(tmp_path, gearing__pins=20 + k))
    assert code == 0 and s["tolerance_met"]
    assert (s["psi_star_deg"] == 180.0) == (k == 1)


def test_many_pins(tmp_path):
    s, code, _ = summary(design(tmp_path, gearing__satellite_teeth=198, gearing__pins=200,
                                gearing__eccentricity_mm=1.0))
    assert code == 0 and s["tolerance_met"] and 0.5 < s["efficiency"] < 1


def test_curtate_ratio_near_one(tmp_path):
    s, code, _ = summary(design(tmp_path, gearing__curtate_ratio=1 - 1e-9, gearing__pin_radius_mm=1e-4,
                                  gearing__pins=21, gearing__rotating_pins=True, gearing__axle_radius_mm=5e-5,
                                  friction__rolling_mm=1e-6))
    assert code == 0 and s["tolerance_met"] and s["spin_reversals"] == 1
    assert s["pin_speed_signed_min_rpm"] < 0 < s["pin_speed_signed_max_rpm"]


def test_two_discs_halve_the_pin_force(tmp_path):
    one, _, _ = summary(design(tmp_path))
    two, _, _ = summary(design(tmp_path, gearing__discs=2))
    assert two["efficiency"] == one["efficiency"]
    # the discs are 180 deg apart and psi* < 180 deg: a pin never carries both discs at once
    assert two["pin_force_max_N"] == pytest.approx(one["pin_force_max_N"] / 2, rel=1e-12)
    assert two["loss_mean_W"] == pytest.approx(one["loss_mean_W"], rel=1e-12)


def test_batch_worst_exit_code(tmp_path):
    good = design(tmp_path, "good.toml")
    bad = design(tmp_path, "bad.toml", gearing__pins=20)
    code, out, err = run(good, bad, "--format", "csv")
    assert code == 2 and len(list(csv.DictReader(io.StringIO(out)))) == 1 and "bad.toml" in err


# ------------------------------------------------------------------ bad input (pins.md §9)

BAD = [
    ({"gearing__pins": 20}, "gearing.pins", "z2 must exceed z1"),
    ({"gearing__pins": 18}, "gearing.pins", "z2 must exceed z1"),
    ({"gearing__satellite_teeth": 20.5}, "gearing.satellite_teeth", "integer"),
    ({"gearing__satellite_teeth": 1}, "gearing.satellite_teeth", ">= 2"),
    ({"gearing__eccentricity_mm": 0.0}, "gearing.eccentricity_mm", ">= 1e-06"),
    ({"gearing__eccentricity_mm": -1.0}, "gearing.eccentricity_mm", ">= 1e-06"),
    ({"gearing__curtate_ratio": None, "gearing__pin_circle_radius_mm": 0.0}, "gearing.pin_circle_radius_mm",
     ">= 1e-06"),
    ({"gearing__pin_radius_mm": 0.0}, "gearing.pin_radius_mm", ">= 1e-06"),
    ({"load__torque_Nm": 0.0}, "load.torque_Nm", "> 0"),
    ({"load__crank_speed_rpm": -5.0}, "load.crank_speed_rpm", "> 0"),
    ({"contact__face_width_mm": 0.0}, "contact.face_width_mm", ">= 1e-06"),
    ({"contact__stiffness_N_per_mm": -1.0}, "contact.stiffness_N_per_mm", "> 0"),
    ({"gearing__curtate_ratio": 1.0}, "gearing.curtate_ratio", "K1 = e*z2/(k*R_p) must be < 1"),
    ({"gearing__curtate_ratio": 1.2}, "gearing.curtate_ratio", "K1 = e*z2/(k*R_p) must be < 1"),
    ({"gearing__curtate_ratio": None, "gearing__pin_circle_radius_mm": 42.9}, "gearing.pin_circle_radius_mm",
     "must be < 1"),
    ({"gearing__curtate_ratio": None}, "gearing.pin_circle_radius_mm", "exactly one"),
    ({"gearing__pin_circle_radius_mm": 60.0}, "gearing.pin_circle_radius_mm", "exactly one"),
    ({"gearing__pin_radius_mm": 8.2}, "gearing.pin_radius_mm", "pins overlap"),
    ({"gearing__rotating_pins": True, "gearing__axle_radius_mm": 1.95}, "gearing.axle_radius_mm",
     "smaller than the bushing"),
    ({"gearing__rotating_pins": True, "gearing__axle_radius_mm": None}, "gearing.axle_radius_mm", "missing"),
    ({"friction__sliding": -0.1}, "friction.sliding", ">= 0"),
    ({"friction__axle": -0.1}, "friction.axle", ">= 0"),
    ({"friction__rolling_mm": -0.1}, "friction.rolling_mm", ">= 0"),
    ({"friction__sliding": None}, "friction.sliding", "missing"),
    ({"load__mode": "speedup"}, "load.mode", '"multiplier" | "reducer"'),
    ({"load__torque_shaft": None}, "load.torque_shaft", "missing"),
    ({"gearing__eccentricty_mm": 3.9}, "gearing.eccentricty_mm", "did you mean 'gearing.eccentricity_mm'"),
    # undercut: K1 = 0.99 gives min rho_c = 2.42 mm over the loaded arc; R_b = 3 < R_p sin(pi/z2) = 6.17
    ({"gearing__curtate_ratio": 0.99, "gearing__pin_radius_mm": 3.0}, "gearing.pin_radius_mm", "undercut"),
    # circular teeth: R_b + rho_t = 1.95 + 52 >= R_p - e = 57.2 - 3.9 (pins.md §5.3, §9)
    ({"gearing__profile": "circular", "gearing__tooth_radius_mm": 52.0}, "gearing.tooth_radius_mm",
     "must be < R_p - e"),
    # k = 9 with 3 teeth: psi* below one pin pitch
    ({"gearing__satellite_teeth": 3, "gearing__pins": 12, "gearing__pin_radius_mm": 0.5},
     "gearing.satellite_teeth", "too few teeth"),
]


@pytest.mark.parametrize("changes,key,text", BAD, ids=[b[1] + ":" + b[2][:20] for b in BAD])
def test_bad_input(tmp_path, changes, key, text):
    p = design(tmp_path, "bad_design.toml", **changes)
    code, out, err = run(p)
    assert code == 2, err
    assert "bad_design.toml" in err and key in err and text in err, err
    assert "Traceback" not in err and out == ""


def test_missing_tables(tmp_path):
    code, _, err = run(design(tmp_path, drop=("load",)))
    assert code == 2 and "load" in err and "missing" in err
    p = tmp_path / "empty.toml"
    p.write_text('kind = "pins"\n[friction]\nrolling_mm = 0.01\naxle = 0.1\n')
    code, _, err = run(p)
    assert code == 2 and "[gearing]" in err and "[pin_load]" in err


def test_pin_load_axle_not_smaller(tmp_path):
    p = tmp_path / "f.toml"
    p.write_text((CONFIGS / "pins_paper_formula_cyc_u10.toml").read_text().replace("0.95", "2.0"))
    code, _, err = run(p)
    assert code == 2 and "pin_load.axle_radius_mm" in err


@pytest.mark.parametrize("tol", ["0", "-1e-6", "0.1", "0.5"])
def test_bad_tolerance(tmp_path, tol):
    code, _, err = run(design(tmp_path), "--tol", tol)
    assert code == 2 and "--tol" in err


def test_tolerance_is_honoured(tmp_path):
    loose, _, _ = summary(design(tmp_path), "--tol", "1e-3")
    tight, _, _ = summary(design(tmp_path), "--tol", "1e-10")
    assert loose["n_crank"] < tight["n_crank"]
    assert loose["loss_ratio_err"] <= 1e-3 * loose["loss_ratio"]
    assert tight["loss_ratio_err"] <= 1e-10 * tight["loss_ratio"]
    assert abs(loose["efficiency"] - tight["efficiency"]) <= loose["efficiency_err"]


def test_subprocess_exit_codes_and_no_traceback():
    # the real entry point: a good design, and the circular example forced to the ideal level (an error)
    r = subprocess.run([sys.executable, "-m", "gearcalc", "pins", str(CONFIGS / "pins_paper_cyc_u30_fixed.toml"),
                        str(CONFIGS / "pins_paper_circ_u10_fixed.toml"), "--model", "ideal", "--format", "json"],
                       capture_output=True, text=True, timeout=60, check=False)
    assert r.returncode == 2
    assert "Traceback" not in r.stderr and "conjugate (cycloidal)" in r.stderr
    [obj] = json.loads(r.stdout)  # two paths: an array, here of the one design that computed
    assert obj["summary"]["model"] == "ideal"


@pytest.mark.parametrize("mode", ["multiplier", "reducer"])
def test_summary_power_balance(tmp_path, mode):
    # input power - output power = mean loss (pins.md §4.7): T_in w_in - T_out w_out, w_V = w_H k/z1
    import math

    s, _, _ = summary(design(tmp_path, load__mode=mode))
    wH = 1000.0 * math.pi / 30
    wV = wH * 2 / 20
    w_in, w_out = (wV, wH) if mode == "multiplier" else (wH, wV)
    assert s["torque_in_Nm"] * w_in - s["torque_out_Nm"] * w_out == pytest.approx(s["loss_mean_W"], rel=1e-12)


def test_sweep_runs_point_by_point(tmp_path):
    r = runner.invoke(app, ["sweep", str(design(tmp_path)), "--vary", "gearing.curtate_ratio=0.6,0.8",
                            "--format", "csv"])
    assert r.exit_code == 0, r.stderr
    rows = list(csv.DictReader(io.StringIO(r.stdout)))
    assert [float(x["curtate_ratio"]) for x in rows] == [0.6, 0.8]
    assert float(rows[0]["efficiency"]) < float(rows[1]["efficiency"])


@pytest.mark.slow
@pytest.mark.parametrize("changes", [{}, {"gearing__pins": 21}, {"gearing__pins": 23, "load__mode": "reducer"},
                                     {"gearing__curtate_ratio": 0.9}])
def test_peaks_against_dense_pointwise_evaluation(tmp_path, changes):
    # the reported peaks (refined between nodes) against a dense pointwise sweep of one period
    import numpy as np

    from gearcalc import pins

    s, _, _ = summary(design(tmp_path, **changes))
    z2 = changes.get("gearing__pins", 22)
    g = pins.Cycloid.from_curtate_ratio(20, z2, 3.9, changes.get("gearing__curtate_ratio", 0.75), 1.95)
    ps = pins.crest_cutoff(g)
    sigma = pins.REDUCER if changes.get("load__mode") == "reducer" else pins.MULTIPLIER
    theta = np.linspace(0, g.period, 200001)
    T_sat = (s["torque_in_Nm"] if sigma == pins.MULTIPLIER else s["torque_out_Nm"]) * 1e3
    F = pins.pin_forces(theta, g, ps, T_sat, sigma)
    psi = pins.pin_phase(np.arange(z2)[:, None], theta[None, :], z2, sigma)
    v = pins.sliding_speed(pins.pitch_distance(psi, g), g.R_b, 1000 * np.pi / 30 * g.k / 20)
    P = pins.contact_loss_power(F, v, 0.1)
    for key, dense in (("pin_force_max_N", F.max()), ("pin_loss_max_W", P.max()), ("loss_peak_W", P.sum(0).max())):
        assert dense <= s[key] * (1 + 1e-12)
        assert s[key] <= dense * (1 + 1e-6)


def test_detail_with_three_discs(tmp_path):
    # n_d = 3: the crank table holds the total over the discs; its mean over the period is lambda_bar
    import numpy as np

    _, out, _ = run(design(tmp_path, gearing__discs=3), "--format", "json", "--detail")
    obj = json.loads(out)
    s, crank = obj["summary"], obj["detail"]["crank"]
    th = np.array([r["theta_deg"] for r in crank])
    lam = np.array([r["loss_ratio"] for r in crank])
    trapezoid = getattr(np, "trapezoid", None) or np.trapz   # numpy >= 2 or older
    mean = trapezoid(lam, th) / (360 / 22)
    assert mean == pytest.approx(s["loss_ratio"], rel=1e-4)
    assert max(r["loss_W"] for r in crank) == pytest.approx(s["loss_peak_W"], rel=1e-9)
    one, _, _ = summary(design(tmp_path))
    assert s["efficiency"] == one["efficiency"]


def test_at_the_self_locking_limit(tmp_path):
    # lambda is proportional to f: f = 0.1/lambda(0.1) puts lambda_bar at 1 within its error estimate
    ref, _, _ = summary(design(tmp_path))
    f = 0.1 / ref["loss_ratio"]
    s, code, err = summary(design(tmp_path, friction__sliding=f))
    assert abs(s["loss_ratio"] - 1.0) <= s["loss_ratio_err"]
    assert "at the self-locking limit" in err
    assert (code == 1) == s["self_locking"]
    assert s["efficiency"] is None or s["efficiency"] >= 0.0


@pytest.mark.parametrize("rotating", [False, True])
def test_vectorised_sweep_equals_point_by_point(tmp_path, rotating):
    # the sweep hook solves the geometry once and scales it per operating point (pins.md §4.8, 8)
    import math

    from gearcalc import registry
    from gearcalc import grid as sw
    from gearcalc.calculator import Options
    from gearcalc.design import read_toml

    base = design(tmp_path, gearing__rotating_pins=rotating,
                  pin_load__normal_force_N=1920.0, pin_load__pin_speed_rpm=14.0, pin_load__pin_radius_mm=1.95,
                  pin_load__axle_radius_mm=0.95)
    axes = {"friction.sliding": [0.0, 0.04, 0.1, 1.5], "load.torque_shaft": ["H", "V"],
            "load.mode": ["multiplier", "reducer"], "load.crank_speed_rpm": [10.0, 3000.0]}
    raw = read_toml(str(base))
    rows = sw.evaluate(raw, str(base), axes, Options())
    rows = rows.rows() if hasattr(rows, "rows") else rows      # column-major (render.Columns)
    assert registry.get("pins").sweep is not None and len(rows) == 32
    for row in rows:
        point = {k: row[k] for k in axes}
        changes = {k.replace(".", "__"): v for k, v in point.items()}
        ref, _, _ = summary(design(tmp_path, "p.toml", gearing__rotating_pins=rotating,
                                   pin_load__normal_force_N=1920.0, pin_load__pin_speed_rpm=14.0,
                                   pin_load__pin_radius_mm=1.95, pin_load__axle_radius_mm=0.95, **changes))
        for k, v in ref.items():
            if k in ("model_time_ms", "name"):
                continue
            if isinstance(v, float):
                assert math.isclose(row[k], v, rel_tol=1e-12, abs_tol=1e-300), (point, k, row[k], v)
            else:
                assert row[k] == v, (point, k)


def test_sweep_over_geometry_is_vectorised(tmp_path):
    # geometry keys are vectorised too (each distinct geometry solved once; tests/test_pins_batch.py
    # compares with point-by-point evaluation); the contact level falls back point by point
    from gearcalc import registry
    from gearcalc.calculator import Options
    from gearcalc.design import load

    d = load(str(design(tmp_path)))
    out = registry.get("pins").sweep(d, {}, {"gearing.curtate_ratio": [0.6]}, [{"gearing.curtate_ratio": 0.6}],
                                     Options())
    assert out["curtate_ratio"] == [pytest.approx(0.6, rel=1e-15)] and out["model"] == ["ideal"]
    c = load(str(design(tmp_path, "c.toml", contact__law="hertz", contact__face_width_mm=10.0)))
    assert registry.get("pins").sweep(c, {}, {"friction.sliding": [0.1]}, [{"friction.sliding": 0.1}],
                                      Options()) is None


# ---------------------------------------------------------------- check == run (issue 13; moved from test_guards.py)

PINS = CONFIGS / "pins_paper_cyc_u10_rotating.toml"



def _random_pins_design(rng: random.Random) -> dict:
    """A valid-looking pins design: every value inside its field's bounds, the combination not checked."""
    raw = read_toml(str(PINS))
    g = raw["gearing"]
    g["profile"] = rng.choice(["cycloidal", "cycloidal", "circular"])
    z1 = rng.choice([rng.randint(2, 6), rng.randint(2, 40)])
    k = rng.choice([1, 1, 2, 3, 4])
    g["satellite_teeth"], g["pins"] = z1, z1 + k
    g["eccentricity_mm"] = round(rng.uniform(0.5, 5.0), 3)
    g["curtate_ratio"] = round(rng.uniform(0.2, 0.95), 3)
    r_p = g["eccentricity_mm"] * (z1 + k) / (k * g["curtate_ratio"])
    g["pin_radius_mm"] = round(rng.uniform(0.2, 1.02) * r_p * math.sin(math.pi / (z1 + k)), 3)
    g["axle_radius_mm"] = round(g["pin_radius_mm"] * rng.uniform(0.3, 0.8), 3)
    if g["profile"] == "cycloidal" and rng.random() < 0.3:
        g["equidistant_mod_mm"] = round(rng.uniform(0.0, 0.05), 4)
    if g["profile"] == "circular" or rng.random() < 0.2:
        raw["contact"] = {"law": "hertz"} if rng.random() < 0.2 else {"law": "hertz", "face_width_mm": 10.0}
    return raw


SOLVE_TIME = ("no contact can carry the torque", "cannot resolve this geometry in floating point")
"""The two bad-input findings of the contact level that only its solve can make (pins.md §5.5)."""


@pytest.mark.slow
def test_check_agrees_with_run_on_random_pins_designs(tmp_path):
    # issue 13: check said ok while run said bad input for 19 of 60 random designs (undercut, too few teeth
    # for k, equidistant_mod_mm without contact.face_width_mm).  Seeded: the same 30 designs every run.
    rng = random.Random(13)
    refused = 0
    for i in range(30):
        raw = _random_pins_design(rng)
        path = tmp_path / f"d{i}.toml"
        path.write_text(tomli_w.dumps(raw))
        c = cli("check", path)
        if c.code == 2:
            refused += 1
            continue                        # check refuses: run refuses too (validate runs the same check)
        r = cli("pins", path, "--tol", "1e-3", "-o", tmp_path / f"d{i}.csv")
        assert r.code != 70, r
        if r.code == 2 and any(m in r.err for m in SOLVE_TIME):
            continue                        # found by the contact solve itself (pins.md §5.5)
        assert (r.code == 2) == (c.code == 2), (raw, c, r)
    assert refused > 0                      # the sample holds some bad designs


def test_check_reports_the_compute_time_checks():
    # the three classes of the issue, each refused by check with the key compute names
    cases = [
        # undercut: z1 = 2, z2 = 3, K1 = 0.8, e = 1 (R_p = 3.75 mm): R_b = 2.9 mm is above the least curvature
        # radius of the pin-centre curve (pins.admissibility), below the overlap limit R_p sin(60 deg) = 3.25 mm
        ([("gearing.satellite_teeth", 2), ("gearing.pins", 3), ("gearing.curtate_ratio", 0.8),
          ("gearing.eccentricity_mm", 1.0), ("gearing.pin_radius_mm", 2.9), ("gearing.axle_radius_mm", 1.0)],
         "gearing.pin_radius_mm", PINS),
        # too few teeth: z1 = 2, z2 = 4 (k = 2), K1 = 0.5, e = 1 (R_p = 4 mm), R_b = 2.5 mm: psi* <= 360/z2
        ([("gearing.satellite_teeth", 2), ("gearing.pins", 4), ("gearing.curtate_ratio", 0.5),
          ("gearing.eccentricity_mm", 1.0), ("gearing.pin_radius_mm", 2.5), ("gearing.axle_radius_mm", 1.0)],
         "gearing.satellite_teeth", PINS),
        ([("gearing.equidistant_mod_mm", 0.01)], "contact.face_width_mm", PINS),          # contact level, no [contact]
    ]
    for sets, key, base in cases:
        args = [a for k, v in sets for a in ("--set", f"{k}={v!r}")]
        c, r = cli("check", base, *args), cli("pins", base, *args)
        assert c.code == 2 and r.code == 2, (sets, c, r)
        assert key in c.err and key in r.err
# ---------------------------------------------------------------- sweeps (issue 36 item 8): shared points, cost
def test_pins_torque_sweep_equals_points_alone():
    """A pins torque x friction sweep (the consistent model's distinct points shared) gives each point's
    own compute result."""
    from gearcalc import api

    src = CONFIGS / "pins_paper_cyc_u10_fixed.toml"
    parts = list(api.sweep(str(src), {"load.torque_Nm": [10.0, 20.0, 30.0], "friction.sliding": [0.05, 0.1]}))
    cols = parts[0].data
    for i in range(6):
        t, f = cols["load.torque_Nm"][i], cols["friction.sliding"][i]
        alone = api.compute(str(src), overrides={"load.torque_Nm": t, "friction.sliding": f}).summary
        for key in ("efficiency", "torque_in_Nm", "pin_force_max_N", "crank_torque_ripple_Nm", "bearing_force_max_N"):
            assert cols[key][i] == alone[key], key


def test_pins_geometry_axis_costs_its_geometries():
    """An ideal-level grid over a geometry axis costs each distinct geometry as alone (1 ms + 35 us a pin-disc,
    kinds/pins.py sweep_cost): chunks of about a second's work, a grid of hours refused; a friction axis stays
    at 25 us a point (it cost 25 us a point whatever the axes: one chunk of 1e4 geometries, 21 s and ~1 GB)."""
    src = CONFIGS / "pins_paper_cyc_u10_fixed.toml"
    raw = tomllib.loads(src.read_text())
    per_geometry = 1e-3 + 35e-6 * 22 * 1                    # the config: 22 pins, one disc
    geo = {"gearing.eccentricity_mm": sw.Range(3.0, 0.00015, 10_000)}
    total, seconds = sw.prepare(raw, str(src), geo, Options())
    assert seconds == 2.5e-5 + per_geometry
    assert sw.chunk_points(seconds) < 1_000
    both = {**geo, "friction.sliding": [0.05, 0.1]}          # two points a geometry
    assert sw.prepare(raw, str(src), both, Options())[1] == 2.5e-5 + per_geometry / 2
    assert sw.prepare(raw, str(src), {"friction.sliding": sw.Range(0.01, 1e-5, 10_000)}, Options())[1] == 2.5e-5
    # below the default --tol a gear needs (1e-6/tol)^(1/2) times the nodes (320 -> 9 900 at 1e-9, measured):
    # its pin-disc term grows as much, so a chunk stays about a second of work and bounded memory (one chunk of
    # 1 001 eccentricities at 1e-9 took 1.3-2 GB)
    tight = sw.prepare(raw, str(src), geo, Options(tol=1e-9))[1]
    assert tight == 2.5e-5 + 1e-3 + 35e-6 * 22 * 1 * math.sqrt(1e-6 / 1e-9)
    assert sw.chunk_points(tight) < 50
    assert sw.prepare(raw, str(src), geo, Options(tol=1e-3))[1] == 2.5e-5 + per_geometry     # never below
    huge = {"gearing.eccentricity_mm": sw.Range(3.0, 1.5e-6, 1_000_000)}
    assert "more than a sweep may take" in sw.cost_problem(huge, 1_000_000, sw.prepare(raw, str(src), huge,
                                                                                          Options())[1])
