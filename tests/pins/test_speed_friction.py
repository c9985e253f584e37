"""Tests of a speed-dependent friction law at the ideal level (gearcalc.pins.speed_friction; pins.md §4.10).

Independent references: a brute-force power-weighted mean over 32 000 crank angles from the friction-free pin forces;
Coulomb's law as a constant table; the Stribeck curve's low-speed limit mu_s.
"""
import numpy as np
import pytest

from gearcalc.pins import friction as fr

from pins.test_output_mech import PAPER, _run, _with


def test_power_weighted_coefficient_against_a_brute_force_cycle():
    # independent: the friction-free pin forces of gearcalc.pins.forces (pointwise membership) and the pitch distances
    # at 32 000 crank angles of one tooth period; sum mu(v_i) F_i v_i / sum F_i v_i.  The two quadratures of a
    # discontinuous integrand (a pin leaves at psi*) agree to ~1e-6.
    from gearcalc.pins.forces import pin_forces, pin_phase
    from gearcalc.pins.geometry import Cycloid, crest_cutoff, pitch_distance
    from gearcalc.pins.speed_friction import power_weighted_coefficient
    g = Cycloid.from_curtate_ratio(20, 22, 3.9, 0.75, 1.95)
    ps, w_V = crest_cutoff(g), 1000 * np.pi / 30 / 10
    law = fr.TableLaw((0.0, 2.0), (0.12, 0.04))
    th = (np.arange(32000) + 0.5) / 32000 * 2 * np.pi / 22
    F = pin_forces(th, g, ps, 1.0)
    v = w_V * np.abs(pitch_distance(pin_phase(np.arange(22)[:, None], th[None, :], 22), g) - 1.95) * 1e-3
    brute = (law.coefficient(v) * F * v).sum() / (F * v).sum()
    assert power_weighted_coefficient(law, g, ps, w_V) == pytest.approx(brute, rel=1e-5)


def test_a_constant_table_is_coulombs_law():
    s0 = _run(PAPER)
    s = _run(_with(friction={"law": "table", "table_speed_m_s": [0.0, 5.0], "table_mu": [0.1, 0.1]}))
    assert s["sliding_friction_mean"] == pytest.approx(0.1, rel=1e-14)
    assert s["efficiency"] == pytest.approx(s0["efficiency"], rel=1e-13)


def test_stribeck_makes_the_efficiency_depend_on_speed():
    # at 0.01 rpm every contact slides at v <= 8.73e-6 m/s (sliding_speed_max_m_s 0.8731 at 1000 rpm), so
    # |mu-bar - mu_s| <= k_v v + (mu_s - mu_c)(v/v_s)^2 = 1.75e-7 + 7.6e-10; at high speed the viscous rise shows
    f = {"law": "stribeck", "stribeck_static": 0.15, "stribeck_coulomb": 0.05, "stribeck_speed_m_s": 0.1,
         "stribeck_viscous_s_per_m": 0.02}
    slow = _run(_with(friction=f, load={"crank_speed_rpm": 0.01}))
    assert abs(slow["sliding_friction_mean"] - 0.15) <= 0.02 * 8.732e-6 + 0.1 * (8.732e-5) ** 2
    effs = [_run(_with(friction=f, load={"crank_speed_rpm": n}))["efficiency"] for n in (10.0, 1000.0, 3000.0)]
    assert effs[0] < effs[1] and effs[2] < effs[1]
