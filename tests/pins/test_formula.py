"""gearcalc.pins.formula: the paper's per-pin maximum friction loss, eqs. (3)-(7) (pins.md §3).

Expected values: the paper's printed numbers (seed 000, Figs. 8-11: F_tr1, F_tr2, P_tr1, P_tr2, P_tr to their
printed decimals) from the inputs of the shipped designs that reproduce them; otherwise the equations' own
structure (pi = 3.14 against math.pi, the fixed pin's loss against the rolling one's).
"""
import math
import tomllib

import numpy as np
import pytest

from conftest import CONFIGS
from gearcalc.pins import formula as F

PRINTED = {  # file: printed (F_tr1 [N], F_tr2 [N], P_tr1 [W], P_tr2 [W], P_tr [W]) and their decimals
    "pins_paper_formula_cyc_u10.toml": ((9.85, 192, 0.028, 0.267, 0.295), (2, 0, 3, 3, 3)),
    "pins_paper_formula_cyc_u30.toml": ((4.46, 87, 0.031, 0.294, 0.325), (2, 0, 3, 3, 3)),
    "pins_paper_formula_circ_u10.toml": ((7.64, 210, 0.04, 0.692, 0.732), (2, 0, 2, 3, 3)),
    "pins_paper_formula_circ_u30.toml": ((4.44, 111, 0.071, 1.063, 1.134), (2, 0, 3, 3, 3)),
}


def inputs(fname):
    d = tomllib.loads((CONFIGS / fname).read_text())
    pl, fr = d["pin_load"], d["friction"]
    return (pl["normal_force_N"], pl["pin_speed_rpm"], pl["pin_radius_mm"], pl["axle_radius_mm"],
            fr["rolling_mm"], fr["axle"])


@pytest.mark.parametrize("fname", sorted(PRINTED))
def test_the_papers_printed_values(fname):
    r = F.formula_losses(*inputs(fname), paper_pi=True)
    printed, decimals = PRINTED[fname]
    for got, p, d in zip((r.F_tr1, r.F_tr2, r.P_tr1, r.P_tr2, r.P_tr), printed, decimals):
        assert abs(got - p) <= 0.5 * 10.0 ** (-d) + 1e-12
    assert r.P_tr == r.P_tr1 + r.P_tr2 and r.P_tr_fixed is None


def test_paper_pi_scales_every_power_by_3_14_over_pi():
    args = inputs("pins_paper_formula_cyc_u10.toml")
    paper, exact = F.formula_losses(*args, paper_pi=True), F.formula_losses(*args)
    assert (paper.F_tr1, paper.F_tr2) == (exact.F_tr1, exact.F_tr2)          # the forces have no pi
    for a, b in ((paper.P_tr1, exact.P_tr1), (paper.P_tr2, exact.P_tr2), (paper.P_tr, exact.P_tr)):
        assert a / b == pytest.approx(3.14 / math.pi, rel=1e-14)
    assert F.pin_angular_speed(30.0) == pytest.approx(math.pi, rel=1e-15)    # 30 rpm = half a turn per second


def test_fixed_pin_loss_is_the_rolling_loss_with_f_R_for_f_k():
    # eq. (5) with F_tr1 = f_k F_n / R replaced by the sliding force f F_n: P_fix / P_tr1 = f R / f_k
    Fn, n, R, r, fk, fc = inputs("pins_paper_formula_circ_u30.toml")
    f = 0.1
    res = F.formula_losses(Fn, n, R, r, fk, fc, sliding_friction=f)
    assert res.P_tr_fixed / res.P_tr1 == pytest.approx(f * R / fk, rel=1e-14)
    assert F.fixed_pin_formula_loss(Fn, n, R, f) == res.P_tr_fixed


def test_arrays_are_elementwise_and_nan_propagates():
    Fn = np.array([1920.0, 960.0, np.nan])
    res = F.formula_losses(Fn, 14.0, 1.95, 0.95, 0.01, 0.1, paper_pi=True)
    one = F.formula_losses(1920.0, 14.0, 1.95, 0.95, 0.01, 0.1, paper_pi=True)
    assert res.P_tr[0] == one.P_tr and res.P_tr[1] == pytest.approx(one.P_tr / 2, rel=1e-15)   # linear in F_n
    assert np.isnan(res.P_tr[2])
