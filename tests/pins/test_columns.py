"""gearcalc.pins.columns: the formula and ideal levels over many designs or points as summary columns (issue 14),
and gearcalc.pins.batching: which designs of a batch run together.

Every expected value names its source on its line: the paper's worked case (pins.md §3), the schema's field
list, or the same computation on one point (a point in an array equals it alone, bit for bit).
"""
import math

import pytest

from conftest import CONFIGS, cli
from gearcalc.calculator import DesignError
from gearcalc.pins import columns as K
from gearcalc.pins.batching import run_batch
from gearcalc.pins.schema import SUMMARY_KEYS

FIG8 = dict(force=[1920.0], pin_speed=[14.0], load_pin_radius=[1.95], load_axle_radius=[0.95], rolling=[0.01],
            axle=[0.1], paper_pi=[True], sliding=[None])                 # pins.md §3, cycloidal u = 10 (Fig. 8)


def test_formula_columns_reproduce_the_papers_printed_digits():
    c = K.formula_columns(FIG8)
    printed = {"F_tr1_N": (9.85, 2), "F_tr2_N": (192.0, 0), "P_tr1_W": (0.028, 3), "P_tr2_W": (0.267, 3),
               "P_tr_W": (0.295, 3)}                                    # pins.md §3, the paper's Fig. 8 row
    for key, (value, digits) in printed.items():
        assert abs(c[key][0] - value) <= 0.5 * 10 ** -digits, key
    assert c["P_tr_fixed_W"] == [None]                                  # no f: no fixed-pin variant (pins.md §3)


def test_formula_columns_of_points_equal_each_point_alone():
    two = {k: v * 2 for k, v in FIG8.items()}
    two["force"], two["sliding"] = [1920.0, 870.0], [0.1, None]
    many = K.formula_columns(two)
    for i in range(2):
        one = K.formula_columns({k: [v[i]] for k, v in two.items()})
        assert {k: v[i] for k, v in many.items()} == {k: v[0] for k, v in one.items()}
    # pins.md §3, fixed-pin variant: P_tr/P_tr,fix = (f_c r + f_k)/(f R)
    assert math.isclose(many["P_tr_W"][0] / many["P_tr_fixed_W"][0], (0.1 * 0.95 + 0.01) / (0.1 * 1.95), rel_tol=1e-12)


def test_friction_models_per_point():
    models, errors = K.friction_models([None, "first-order", "first-order"], [None, None, True], "consistent")
    assert models == ["consistent", "first-order", "consistent"] and errors[:2] == [None, None]
    assert isinstance(errors[2], DesignError) and errors[2].key == "contact.friction_in_equilibrium"
    assert errors[2].message == ('= true contradicts friction.model = "first-order" (the key is its alias; give one '
                                 'of them)')


def test_level_columns_of_the_formula_level():
    cols, ideal = K.level_columns(FIG8, "formula", ["a"], 1e-6, True, "consistent")
    assert ideal is None and list(cols) == list(SUMMARY_KEYS)            # schema.SUMMARY_KEYS, in order
    assert cols["model"] == ["formula"] and cols["rotating_pins"] == [True]   # eqs. (3)-(7): rotating pins
    assert cols["efficiency"] == [None] and cols["P_tr_W"] == K.formula_columns(FIG8)["P_tr_W"]


GEAR = dict(z1=[20], z2=[22], e=[3.9], Rp=[None], K1=[0.75], Rb=[1.95], r=[None], rotating=[False], n_d=[1],
            sliding=[0.1], rolling=[0.01], axle=[0.1], mode=["multiplier"], shaft=["H"], torque=[100.0],
            speed=[1000.0], face_width=[None], model=["first-order"], alias=[None])   # pins_paper_cyc_u10_fixed


def test_ideal_columns_of_a_point_alone_equal_it_among_others():
    two = {k: v * 2 for k, v in GEAR.items()}
    two["sliding"], two["model"] = [0.05, 0.1], ["consistent", "first-order"]
    many, _ = K.level_columns(two, "ideal", ["x", "y"], 1e-6, False, "consistent")
    for i in range(2):
        one, _ = K.level_columns({k: [v[i]] for k, v in two.items()}, "ideal", ["x", "y"][i:i + 1], 1e-6, False,
                                 "consistent")
        assert {k: v[i] for k, v in many.items()} == {k: v[0] for k, v in one.items()}, i   # bit for bit
    assert many["efficiency"][1] == pytest.approx(0.858, abs=5e-4)    # gearcalc.pins.points' example: 0.858


@pytest.mark.filterwarnings("ignore::RuntimeWarning")     # the overflow itself
@pytest.mark.parametrize("given", ["K1", "Rp"])
def test_a_loss_ratio_that_overflows_is_an_error_of_the_point(given):
    # K1 = 1e-306: R_p = e z2/(k K1) = 4.3e307 is finite, the first-order loss ratio (~1/K1) is not (pins.md §9)
    K1 = 1e-306
    v = dict(GEAR, K1=[K1] if given == "K1" else [None], Rp=[None] if given == "K1" else [3.9 * 22 / (2 * K1)])
    _, ideal = K.level_columns(v, "ideal", ["x"], 1e-6, False, "consistent")
    err = ideal.errors[0]
    assert isinstance(err, DesignError) and "overflows floating point" in err.message
    assert err.key == {"K1": "gearing.curtate_ratio", "Rp": "gearing.pin_circle_radius_mm"}[given]


@pytest.mark.filterwarnings("ignore::RuntimeWarning")
@pytest.mark.parametrize("model", ["first-order", "consistent"])
def test_a_sweep_refuses_a_loss_ratio_overflow_as_a_run_does(model):
    # issue 14: the overflow rule was compute's and batch's only; the vectorised sweep passed the point on and
    # failed with exit 70 (a non-finite value in the CSV output). The friction-consistent model jams there (no loss
    # ratio) but its sliding speeds overflow: run and sweep ended with exit 70 until 2026-11-27
    cfg = CONFIGS / "pins_paper_cyc_u10_fixed.toml"
    run = cli("run", cfg, "--set", "gearing.curtate_ratio=1e-306", "--set", f"friction.model={model}", "-f", "csv")
    sweep = cli("sweep", cfg, "--vary", "gearing.curtate_ratio=0.75,1e-306", "--set", f"friction.model={model}",
                "-f", "csv")
    assert run.code == sweep.code == 2
    text = "gearing.curtate_ratio = 1e-306: the loss ratio overflows floating point"       # report.loss_ratio_overflow
    assert text in run.err and text in sweep.err


def test_run_batch_groups_and_returns_exceptions_in_order():
    def level_of(d):
        if d == "bad":
            raise DesignError("gearing.pins", "= 0")
        return {"f": "formula", "i": "ideal", "I": "ideal", "c": "contact"}[d[0]]

    calls = []

    def group(ds, level):
        calls.append((level, list(ds)))
        return [f"{level}:{d}" for d in ds]

    out = run_batch(["i1", "c1", "bad", "f1", "I2", "i3"], level_of, lambda d, level: d[0] == "I",
                    lambda d: f"alone:{d}", group)
    assert out[:2] == ["ideal:i1", "alone:c1"] and isinstance(out[2], DesignError)
    assert out[3:] == ["formula:f1", "alone:I2", "ideal:i3"]
    assert calls == [("formula", ["f1"]), ("ideal", ["i1", "i3"])]      # one group per level, in design order
