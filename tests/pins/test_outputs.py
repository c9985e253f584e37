"""Tests of the ideal level's outputs of one operating point (gearcalc.pins.outputs; pins.md §4.9, §8): the crank
bearing's equivalent load and L10 life (issue 37 item 5; pins.md §8.2), the satellite and crank torques, the
contact stress and the axle pressure.

Independent references: the equivalent load recomputed from the ``--detail`` crank table (the bearing force of one
disc at every node of the final grid, ordered by crank angle; a trapezoid rule over the crank angle, written here),
the ISO 281 life L10 = (C/P)^p 10^6 revolutions, L10_h = L10 10^6/(60 n) (written here), and the closed forms named
at each test (Hertz's line contact, a constant load's p-mean, the discs' equal shares).
"""
from __future__ import annotations

import json
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from typer.testing import CliRunner

from gearcalc.cli import app

from conftest import CONFIGS

runner = CliRunner()
PAPER = CONFIGS / "pins_paper_cyc_u10_fixed.toml"


def run_json(*args):
    r = runner.invoke(app, ["run", str(PAPER), "--format", "json", *args])
    assert r.exit_code in (0, 1), r.stderr
    return json.loads(r.stdout)


@pytest.mark.parametrize("p", [3.0, 10.0 / 3.0])
@pytest.mark.parametrize("mode", ["multiplier", "reducer"])
def test_l10_from_a_p_mean_computed_from_the_detail_table(p, mode):
    """L10 from a cubic (p = 3) or 10/3-power mean computed here from the detail table: the trapezoid rule over the
    table's crank angles (the jump in the loaded pin count is a repeated angle holding both sides).  The trapezoid
    at the final grid's spacing h differs from the summary's Richardson value by about (T_h - T_2h)/3, a third of
    the stated error, so the stated error must cover the difference."""
    C, n = 10_000.0, 1000.0
    d = run_json("--detail", "--set", f"bearing.C_N={C}", "--set", f"bearing.exponent={p!r}",
                 "--set", f"load.mode={mode}")
    s, rows = d["summary"], d["detail"]["crank"]
    th = np.array([r["theta_deg"] for r in rows])
    B = np.array([r["bearing_force_N"] for r in rows])
    assert np.all(np.diff(th) >= 0)
    mean_p = np.sum(0.5 * (B[1:] ** p + B[:-1] ** p) * np.diff(th)) / (th[-1] - th[0])
    P = mean_p ** (1.0 / p)
    assert B.min() <= P <= B.max()
    assert s["bearing_force_mean_N"] <= s["bearing_equivalent_load_N"] + s["bearing_equivalent_load_err_N"]
    assert abs(P - s["bearing_equivalent_load_N"]) <= s["bearing_equivalent_load_err_N"]
    assert 0 < s["bearing_equivalent_load_err_N"] < 1e-6 * P      # the default --tol 1e-6 (a relative target)
    L10_h = (C / P) ** p * 1e6 / (60.0 * n)
    assert abs(L10_h - s["bearing_L10_h"]) <= s["bearing_L10_h_err"]
    assert s["bearing_L10_h_err"] == pytest.approx(p * s["bearing_L10_h"] * s["bearing_equivalent_load_err_N"]
                                                   / s["bearing_equivalent_load_N"], rel=1e-12)


def test_without_a_rating_the_load_is_given_and_the_life_is_empty():
    """P needs only the force history (default exponent 10/3, ISO 281 roller); L10_h needs bearing.C_N."""
    s = run_json()["summary"]
    assert s["bearing_equivalent_load_N"] > 0 and s["bearing_L10_h"] is None and s["bearing_L10_h_err"] is None
    s2 = run_json("--set", "bearing.C_N=10000", "--set", f"bearing.exponent={10 / 3!r}")["summary"]
    assert s2["bearing_equivalent_load_N"] == s["bearing_equivalent_load_N"]


def test_life_scales_as_the_rating_to_the_power_p_and_inversely_with_speed():
    a = run_json("--set", "bearing.C_N=10000", "--set", "bearing.exponent=3")["summary"]
    b = run_json("--set", "bearing.C_N=20000", "--set", "bearing.exponent=3",
                 "--set", "load.crank_speed_rpm=2000")["summary"]
    assert b["bearing_L10_h"] == pytest.approx(a["bearing_L10_h"] * 2 ** 3 / 2, rel=1e-12)


def test_a_sweep_gives_the_same_bearing_fields_as_each_point_alone():
    """The vectorised sweep (all points at once) and each point computed alone: the same numbers."""
    r = runner.invoke(app, ["sweep", str(PAPER), "--vary", "bearing.C_N=10000,30000", "--vary",
                            "load.torque_Nm=50,100", "--vary", "bearing.exponent=3,3.5", "--format", "json"])
    assert r.exit_code in (0, 1), r.stderr
    rows = json.loads(r.stdout)
    assert len(rows) == 8
    for row in rows:
        alone = run_json(*(x for k in ("bearing.C_N", "load.torque_Nm", "bearing.exponent")
                           for x in ("--set", f"{k}={row[k]}")))["summary"]
        for key in ("bearing_equivalent_load_N", "bearing_equivalent_load_err_N", "bearing_L10_h",
                    "bearing_L10_h_err"):
            assert row[key] == pytest.approx(alone[key], rel=1e-12)
            assert math.isfinite(row[key])


def test_a_bad_exponent_is_refused_naming_the_key(tmp_path):
    r = runner.invoke(app, ["run", str(PAPER), "--set", "bearing.C_N=10000", "--set", "bearing.exponent=0.5"])
    assert r.exit_code == 2
    assert "bearing.exponent" in r.stderr


@pytest.mark.parametrize("mode", ["multiplier", "reducer"])
def test_contact_level_l10_from_the_detail_table(mode):
    """The contact level (circular-arc paper design): P from the --detail crank table by the trapezoid rule over its
    crank angles, written here, lies within the stated error of the summary's (its error is the difference
    between the Richardson-corrected and the plain trapezoid p-mean, pins.md §8.2); L10_h from it likewise."""
    C, n, p = 10_000.0, 1000.0, 10.0 / 3.0
    r = runner.invoke(app, ["run", str(CONFIGS / "pins_paper_circ_u10_fixed.toml"), "--format", "json", "--detail",
                            "--set", f"bearing.C_N={C}", "--set", f"load.mode={mode}"])
    assert r.exit_code in (0, 1), r.stderr
    d = json.loads(r.stdout)
    s, rows = d["summary"], d["detail"]["crank"]
    assert s["model"] == "contact"
    th = np.array([row["theta_deg"] for row in rows])
    B = np.array([row["bearing_force_N"] for row in rows])
    P = (np.sum(0.5 * (B[1:] ** p + B[:-1] ** p) * np.diff(th)) / (th[-1] - th[0])) ** (1 / p)
    assert abs(P - s["bearing_equivalent_load_N"]) <= s["bearing_equivalent_load_err_N"] * (1 + 1e-9)
    assert 0 < s["bearing_equivalent_load_err_N"] < 1e-6 * P
    L10_h = (C / P) ** p * 1e6 / (60.0 * n)
    assert abs(L10_h - s["bearing_L10_h"]) <= s["bearing_L10_h_err"] * (1 + 1e-9)


# ---------------------------------------------------------------- the outputs' closed forms

@settings(max_examples=100, deadline=None)
@given(T=st.floats(1.0, 1e8), u=st.floats(1e-6, 1.0), b=st.floats(0.1, 100.0))
def test_contact_stress_is_hertzs_line_contact(T, u, b):
    # Johnson 1985, eq. (4.45): p0 = sqrt(F E*/(pi b R)) with F/R = T_sat u; steel on steel E* = E/(2(1 - nu^2))
    # (E = 210 GPa, nu = 0.3: 115 384.6 MPa)
    from gearcalc.pins.outputs import contact_stress

    E_star = 210_000.0 / (2 * (1 - 0.3 ** 2))
    assert float(contact_stress(T, u, b, E_star)) == pytest.approx(math.sqrt(T * u * E_star / (math.pi * b)), rel=1e-12)
    assert math.isnan(float(contact_stress(T, u, float("nan"), E_star)))           # no face width, no stress


@pytest.mark.parametrize("p", [3.0, 10.0 / 3.0])
def test_a_constant_bearing_force_is_its_own_equivalent_load(p):
    # ISO 281: the p-mean of a constant load is that load; |B|/T_sat = 4/mm at T_sat = 2000 N mm: P = 8000 N; with
    # C = 40 kN at 1500 rpm, L10_h = 10^6/(60 x 1500) x 5^p h; the errors carried to first order: dP = P/p dm/m
    from gearcalc.pins.outputs import bearing_life

    m = 4.0 ** p
    P, dP, L, dL = (float(x) for x in bearing_life(m, 1e-6 * m, p, 2000.0, 40_000.0, 1500.0))
    assert P == pytest.approx(8000.0, rel=1e-14)
    assert L == pytest.approx(1e6 / (60 * 1500.0) * 5.0 ** p, rel=1e-13)
    assert dP == pytest.approx(8000.0 / p * 1e-6, rel=1e-12) and dL == pytest.approx(p * L * dP / P, rel=1e-12)
    assert all(math.isnan(float(x)) for x in bearing_life(m, 0.0, p, 2000.0, float("nan"), 1500.0)[2:])


def test_the_discs_share_the_output_torque_and_the_axle_pressure_is_on_the_projected_area():
    # pins.md §12.7: n_d discs share T_V equally (100 N m over 3 discs: 33 333.3 N mm each, summing to 10^5 N mm);
    # pins.md §8: p = F/(2 r b), 1900 N on 2 x 0.95 mm x 10 mm = 100 MPa
    from gearcalc.pins.outputs import axle_pressure, satellite_torque

    assert 3 * satellite_torque(100.0, 3) == pytest.approx(1e5, rel=1e-15)
    assert axle_pressure(1900.0, 0.95, 10.0) == pytest.approx(100.0, rel=1e-15)
