"""The design checks of the ``pins`` calculator as margins (gearcalc.pins.margins; pins.md §8 "Checks"; issue 36
item 1): every check a signed, dimensionless ``margin_<check>`` whose sign is the old flag's.

Every expected value is computed here from the summary's own inputs and outputs (sigma_max and the allowable
stress, the friction constants of the design file) or from the old flags, or from the closed forms of pins.md §8
written at each test.
"""
import random

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import gearcalc
from conftest import CONFIGS


from test_calculator import agrees_with_flags  # the flags against the margins, every kind


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


# ---------------------------------------------------------------- the margins' functions (pins.md §4.5, §4.7, §8)

pos = st.floats(0.0, 10.0)


@settings(max_examples=200, deadline=None)
@given(f=pos, R_b=pos, f_c=pos, r=pos, f_k=pos)
def test_rolling_margin_sign_is_the_rolling_condition(f, R_b, f_c, r, f_k):
    # pins.md §4.5: the pins roll where f R_b >= f_c r + f_k; the margin's sign is that comparison's, its value the
    # difference over the larger product, so within [-1, 1]
    from gearcalc.pins.margins import rolling_margin

    m = float(rolling_margin(f, R_b, f_c, r, f_k))
    drive, resist = f * R_b, f_c * r + f_k
    assert (m >= 0) == (drive >= resist)
    assert -1.0 <= m <= 1.0
    if max(drive, resist) > 0:
        assert m == pytest.approx((drive - resist) / max(drive, resist), rel=1e-12, abs=1e-300)


def test_rolling_margin_of_the_paper_design():
    # configs/pins_paper_cyc_u10_rotating.toml: f = 0.1, R_b = 1.95, f_c = 0.1, r = 0.95, f_k = 0.01 mm:
    # (0.195 - 0.105)/0.195 = 6/13 (by hand); nothing to drive and nothing to resist: the equality, 0
    from gearcalc.pins.margins import rolling_margin

    assert rolling_margin([0.1, 0.0], [1.95, 1.95], [0.1, 0.0], [0.95, 0.95], [0.01, 0.0]).tolist() == \
        pytest.approx([6 / 13, 0.0], rel=1e-12)


@settings(max_examples=200, deadline=None)
@given(lam=st.floats(0.0, 5.0), multiplier=st.booleans())
def test_self_locking_margin_is_the_requested_modes_efficiency(lam, multiplier):
    # pins.md §4.7: eta_VH = 1 - lambda (multiplier), eta_HV = 1/(1 + lambda) (reducer); the sign follows the flag
    # exactly, the least negative float at the limit lambda = 1 itself
    from gearcalc.pins.margins import self_locking_margin

    eta = 1 - lam if multiplier else 1 / (1 + lam)
    locked = eta <= 0
    m = float(self_locking_margin([multiplier], [lam], [locked])[0])
    assert (m < 0) == locked
    if not locked:
        assert m == pytest.approx(eta, rel=1e-15, abs=1e-300)
    elif eta < 0:
        assert m == pytest.approx(eta, rel=1e-15)


def test_a_jammed_mode_has_margin_minus_one_and_the_limit_is_negative():
    # pins.md §8 "Checks": a jam (no loss ratio, NaN) is -1; lambda = 1 on a multiplier is the limit: the efficiency 0,
    # the flag set, so the margin is negative (the least negative float, nextafter(0, -1))
    from gearcalc.pins.margins import self_locking_margin

    m = self_locking_margin([False, True], [np.nan, 1.0], [True, True])
    assert m[0] == -1.0 and m[1] == np.nextafter(0.0, -1.0)


def test_stress_margin_is_one_minus_the_stress_ratio():
    # 1 - sigma/[sigma_H]: 1 - 1800/2000 = 0.1, 1 - 2000/2000 = 0 (passes at the equality), 1 - 2600/2000 = -0.3
    from gearcalc.pins.margins import stress_margin

    assert stress_margin([1800.0, 2000.0, 2600.0], 2000.0).tolist() == pytest.approx([0.1, 0.0, -0.3], rel=1e-14)
