"""gearcalc.pins.contact_level: the contact level of one design, moved out of the adapter (issue 14).

Every expected value names its source on its line: pins.md sections, or an independent evaluation of the
formula a function states.
"""
import math

import pytest

from gearcalc.pins.contact import contact_law
from gearcalc.pins.contact_level import backlash_deg, contact_friction, contact_level, gear, satellite_profile

BAND = (20, 22, 3.9, 44.227, None, 2.75)       # configs/pins_circ_band_u10.toml: z1, z2, e, R_p, K1, R_b
LAW = contact_law("hertz", 10.0)


def test_gear_from_either_circle():
    g, Rp = gear(20, 22, 3.9, None, 0.75, 1.95)
    assert math.isclose(Rp, 3.9 * 22 / (2 * 0.75), rel_tol=1e-15)         # pins.md §4.1: R_p = e z2/(k K1)
    assert math.isclose(g.K1, 0.75, rel_tol=1e-14) and (g.z1, g.z2, g.e, g.R_b) == (20, 22, 3.9, 1.95)
    g, Rp = gear(*BAND)
    assert Rp == 44.227 and math.isclose(g.K1, 3.9 * 22 / (2 * 44.227), rel_tol=1e-14)   # K1 = e z2/(k R_p)


@pytest.mark.parametrize("f, mu, rolls", [
    (0.1, (0.1 * 0.95 + 0.01) / 1.95, True),     # pins.md §4.5: f R_b = 0.195 >= f_c r + f_k = 0.105: they roll
    (0.05, 0.05, False),                         # 0.0975 < 0.105: the bushings slide, mu_eff = f
])
def test_contact_friction_of_rotating_pins(f, mu, rolls):
    m, r, ok = contact_friction(True, 1.95, 0.95, f, 0.01, 0.1)
    assert math.isclose(float(m[0]), mu, rel_tol=1e-15) and bool(r[0]) is rolls and bool(ok[0]) is rolls


def test_contact_friction_of_fixed_pins():
    m, r, ok = contact_friction(False, 1.95, None, 0.1, 0.01, 0.1)
    assert float(m[0]) == 0.1 and not r[0] and ok is None                 # pins.md §4.6: fixed pins slide with f


def test_the_full_circular_tooth():
    g, _ = gear(*BAND)
    prof, overlap = satellite_profile(g, True, "full", "zero_backlash", 0.0, 0.0)
    assert math.isclose(prof.rho_t, prof.R_t * math.sin(math.pi / 20), rel_tol=1e-12)   # pins.md §5.3
    assert not overlap
    prof, overlap = satellite_profile(g, True, 3.576, "zero_backlash", 0.0, 0.0)
    assert prof.rho_t == 3.576 and not overlap


def test_backlash_of_a_play_free_profile_is_zero_by_construction():
    assert backlash_deg(None, True) == 0.0                                # pins.md §5.3: no model needed


def _point(**over):
    return {**dict(sliding=0.1, rolling=0.01, axle=0.1, mode="multiplier", shaft="H", torque=100.0, speed=1000.0),
            **over}


def test_a_frictionless_contact_level_loses_nothing():
    g, _ = gear(*BAND)
    prof, _ = satellite_profile(g, True, "full", "zero_backlash", 0.0, 0.0)
    cl = contact_level(g, prof, LAW, _point(sliding=0.0, rolling=0.0, axle=0.0), 1, False, None, "consistent", 1e-4,
                       True)
    assert cl.balanced and not cl.consistent          # pins.md §4.9: no friction, nothing to put in the balance
    assert cl.modes.requested.loss_ratio == 0.0 and cl.operating.loss_mean == 0.0
    # pins.md §4.7: eta_HV = 1/(1 + lambda), eta_VH = 1 - lambda at lambda = 0
    assert float(cl.et_multiplier.eta_vh[0]) == 1.0 and float(cl.et_reducer.eta_hv[0]) == 1.0
    assert cl.locked == {True: False, False: False} and cl.backlash == 0.0 and cl.detail is None


def test_the_contact_level_equals_the_calculators_contact_run():
    from gearcalc import design as dmod
    from gearcalc.calculator import Options
    from gearcalc.kinds import pins as kind_pins

    from conftest import CONFIGS

    d = dmod.load(CONFIGS / "pins_circ_band_u10.toml")
    s = kind_pins.compute(d, Options(tol=1e-4)).summary
    g, _ = gear(*BAND)
    prof, _ = satellite_profile(g, True, 3.576, "zero_backlash", 0.0, 0.0)
    cl = contact_level(g, prof, LAW, _point(), 1, True, 1.75, "consistent", 1e-4, True, detail=True)
    assert s["loss_ratio"] == cl.modes.requested.loss_ratio and s["efficiency"] == float(cl.et_multiplier.eta_vh[0])
    assert s["equilibrium_residual"] == cl.residual and set(cl.detail) == {"crank", "contacts"}
