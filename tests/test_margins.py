"""Checks as margins (issue 36 item 1; interface.md "Output", the kinds' specs): every design check is a signed,
dimensionless ``margin_<check>`` whose sign is the old flag's, ``failed_checks`` names the negative ones, a run
ends with one line per failing check, and a sweep point that is not a valid design is a row with its reason.

Every expected value is computed here from the summary's own inputs and outputs (sigma_max and the allowable
stress, the friction constants, the rim) or from the old flags; the flags themselves are tested elsewhere.
"""
import math
import random

import pytest

import gearcalc
from conftest import CONFIGS
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


