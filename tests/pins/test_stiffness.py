"""gearcalc.pins.stiffness: torsional stiffness, lost motion, hysteresis, backlash, transmission error (issue 37
items 1-2, pins.md §5.8).

Every expected value names its source: the closed forms of pins.md §5.8 from the ideal level's lever arms
(gearcalc.pins.forces, an independent code: closed-form phases and arms against solved penetrations).
"""
import math
from pathlib import Path

import numpy as np
import pytest

from gearcalc import api
from gearcalc.pins.contact import MULTIPLIER, REDUCER, ContactModel, Cycloid, CycloidProfile, backlash, contact_law
from gearcalc.pins.forces import lever_arm, lever_sum, pin_phase
from gearcalc.pins.friction import PinFriction
from gearcalc.pins.stiffness import (ARCMIN_PER_RAD, bearing_twist, linear_torsional_stiffness, torsion_curve, twist,
                                     unloaded_transmission_error)

CONFIGS = Path(__file__).resolve().parents[2] / "configs"
G1 = Cycloid.from_curtate_ratio(21, 22, 3.9, 0.75, 1.95)     # k = 1: every pin on its flank, psi* = pi (§4.3)
R_P1 = G1.e * G1.z1 / G1.k                                    # satellite pitch radius r_p1 = e z1/k (§4.1)


def _model(equidistant=0.0, stiffness=1e10, friction=None, g=G1):
    return ContactModel(g, CycloidProfile(g, 0.0, equidistant), contact_law("linear", stiffness=stiffness), 1.0,
                        REDUCER, friction)


def test_linear_stiff_contacts_give_the_closed_form_stiffness():
    # pins.md §5.8: K = n_d k_lin sum l_i^2 over the loaded pins (l_i of forces.py), each direction its own loaded
    # set (+T: the reducer's, -T: the multiplier's); measured 2026-12-07: |K/K_closed - 1| <= 1.5e-7 at 1e10 N/mm
    # (the geometric nonlinearity, first order in the twist: 1.75e-6 at 1e8 N/mm)
    th = np.linspace(0.0, G1.period, 7)
    c = torsion_curve(_model(), th, 1000.0, n_discs=2)
    for side, sigma in ((0, REDUCER), (1, MULTIPLIER)):
        K = linear_torsional_stiffness(th, G1, math.pi, 1e10, 2, sigma)
        np.testing.assert_allclose(c.sides[side], K, rtol=1e-6)
    np.testing.assert_allclose(c.stiffness, np.minimum(*c.sides), rtol=0)


def test_discs_in_parallel_at_their_own_crank_angles():
    # pins.md §12.7: with z2 = 21 and 2 discs the second disc runs half a pin pitch behind; in parallel (equal
    # twist) K = k_lin (S(theta) + S(theta + T_p/2)), not 2 k_lin S(theta)
    g = Cycloid.from_curtate_ratio(20, 21, 3.9, 0.75, 1.95)
    th = np.linspace(0.0, g.period, 5)
    c = torsion_curve(_model(g=g), th, 1000.0, n_discs=2)
    by_hand = 1e10 * sum(lever_sum(th + sh, g, math.pi, REDUCER) for sh in (0.0, g.period / 2)) * 1e-3 * math.pi / 10800
    np.testing.assert_allclose(c.sides[0], by_hand, rtol=1e-6)
    assert np.abs(c.sides[0] / (2e10 * lever_sum(th, g, math.pi, REDUCER) * 1e-3 * math.pi / 10800) - 1).max() > 1e-4


def test_closed_form_error_is_first_order_in_the_compliance():
    # pins.md §5.7(a): the error of the stiff limit is first order in T/k_lin: 100x the stiffness, ~1/100 the error
    th = np.array([0.05])
    err = [abs(torsion_curve(_model(stiffness=k), th, 1000.0).sides[0, 0]
               / linear_torsional_stiffness(th, G1, math.pi, k)[0] - 1.0) for k in (1e7, 1e9)]
    assert 30.0 < err[0] / err[1] < 300.0


def test_closed_form_by_hand_at_one_crank_angle():
    # pins.md §4.4: l_i = r_p1 sin psi_i/s_i; K = k_lin sum over 0 < psi < pi of l^2, in N·m/arcmin
    psi = pin_phase(np.arange(22), 0.1, 22, REDUCER)
    s = np.sqrt(1.0 + G1.K1 ** 2 - 2.0 * G1.K1 * np.cos(psi))
    lev = R_P1 * np.sin(psi) / s
    K = 1e10 * np.sum(np.where((psi > 0) & (psi < math.pi), lev ** 2, 0.0)) * 1e-3 * math.pi / 10800.0
    assert torsion_curve(_model(), np.array([0.1]), 1000.0).sides[0, 0] == pytest.approx(K, rel=1e-6)


def test_contact_normals_meet_at_the_pitch_point_so_the_bearing_carries_T_over_r_p1():
    # pins.md §5.8, bearing_twist: every loaded normal of the conjugate cycloid passes through P, r_p1 = e z1/k from
    # O1 (§4.4), so arm_j = P x n_j and the contacts' resultant B has B_t = M/r_p1 across O1P.  P fitted by least
    # squares from the contact model's own normals and arms (an independent code: solved penetrations)
    m = _model(stiffness=1e10)
    pose = m.pose(np.array([0.1]))
    T_sat = 1e5                                                    # N·mm
    tau = twist(m, np.array([0.1]), np.array([T_sat]), np.array([1.0]))
    ct = m.contacts(pose, tau)
    F = m.law.force(ct.delta)[..., 0]
    on = F > 0
    nx, ny, arm = ct.nx[..., 0][on], ct.ny[..., 0][on], ct.arm[..., 0][on]
    P, *_ = np.linalg.lstsq(np.column_stack((ny, -nx)), arm, rcond=None)    # arm = P_x n_y - P_y n_x
    # measured 2026-12-07: the lines miss the fitted P by <= 6.0e-7 mm (7.4e-9 r_p1: the normals of the deflected,
    # twisted state), |P| = r_p1 to 5e-9
    assert np.abs(P[0] * ny - P[1] * nx - arm).max() < 1e-7 * R_P1
    assert math.hypot(*P) == pytest.approx(R_P1, rel=1e-7)
    B = np.array([np.sum(F[on] * nx), np.sum(F[on] * ny)])
    M = np.sum(F[on] * arm)
    assert abs(M) == pytest.approx(T_sat, rel=1e-7)       # the root to 1e-15 rad times k S ~ 3e14 N·mm/rad: 5e-9
    assert abs(P[0] * B[1] - P[1] * B[0]) / R_P1 == pytest.approx(T_sat / R_P1, rel=1e-7)   # B_t r_p1 = M


def test_bearing_in_series_gives_the_closed_form_stiffness():
    # pins.md §5.8: the crank bearing (k_b per disc) in series with the contacts: 1/K = 1/(k_lin sum_d S_d)
    # + 1/(n_d k_b r_p1^2), S of the ideal level's lever arms (forces.lever_sum); a stiff linear law (1e10 N/mm):
    # the contacts' own closed form holds to 1.5e-7 (test above), the bearing term is exact
    th = np.linspace(0.0, G1.period, 5)
    k_b = 2e5                                                      # N/mm = 200 N/um
    c = torsion_curve(_model(), th, 1000.0, n_discs=2, bearing_stiffness=k_b)
    S = lever_sum(th, G1, math.pi, REDUCER)
    by_hand = 1.0 / (1.0 / (1e10 * 2 * S) + 1.0 / (2 * k_b * R_P1 ** 2)) * 1e-3 * math.pi / 10800.0
    np.testing.assert_allclose(c.sides[0], by_hand, rtol=1e-6)
    np.testing.assert_allclose(c.sides[0], linear_torsional_stiffness(th, G1, math.pi, 1e10, 2, REDUCER, k_b),
                               rtol=1e-6)
    rigid = torsion_curve(_model(), th, 1000.0, n_discs=2)
    assert (c.sides[0] < 0.5 * rigid.sides[0]).all()               # the bearing dominates at these stiffnesses
    assert float(bearing_twist(G1, 1e5, k_b)) == 1e5 / (k_b * R_P1 ** 2)


def test_bearing_stiffness_key_enters_the_summary_and_rigid_is_the_default():
    # [bearing] radial_stiffness_N_per_um (issue 37 item 1): absent, the crank is rigid (as before); given, the
    # least stiffness K obeys 1/K - 1/K_rigid = 1/(n_d k_b r_p1^2) at the same crank angle (the series term is
    # the same at every angle, so the least stays where it was)
    path = str(CONFIGS / "pins_paper_cyc_u10_fixed.toml")
    over = {"contact.face_width_mm": 10.0, "contact.law": "linear", "contact.stiffness_N_per_mm": 1e6,
            "contact.stiffness_curve": True}
    rigid = api.compute(path, model="contact", overrides=over).summary
    soft = api.compute(path, model="contact", overrides={**over, "bearing.radial_stiffness_N_per_um": 500.0}).summary
    assert soft["torsional_stiffness_crank_deg"] == rigid["torsional_stiffness_crank_deg"]
    n_d = 1                                                        # gearing.discs: the default
    r_p1 = 3.9 * 20 / 2                                            # e z1/k of pins_paper_cyc_u10_fixed (z1 20, k 2)
    term = 1.0 / (n_d * 5e5 * r_p1 ** 2) / (1e-3 * math.pi / 10800.0)   # arcmin per N·m
    got = 1.0 / soft["torsional_stiffness_Nm_per_arcmin"] - 1.0 / rigid["torsional_stiffness_Nm_per_arcmin"]
    assert got == pytest.approx(term, rel=1e-6)


def test_without_friction_the_loop_closes_and_with_it_opens():
    th = np.array([0.0, 0.1])
    assert np.all(torsion_curve(_model(stiffness=1e6), th, 100.0).hysteresis == 0.0)    # one branch per sign
    c = torsion_curve(_model(stiffness=1e6, friction=PinFriction(0.1, 0.1, False)), th, 100.0)
    assert np.all(c.hysteresis > 0.0)
    # friction opposes the twist: loading needs less twist than without friction, unloading holds more (where
    # it is not held at the reversal's twist)
    free = torsion_curve(_model(stiffness=1e6), th, 100.0).twist
    assert np.all((c.twist[0] < free[0]) & (c.twist[2] > free[2]))
    held = c.twist[1] == c.twist[0, -1]
    assert np.all(held | (c.twist[1] > free[0])) and np.all(c.twist[1] >= c.twist[0])
    assert np.all(c.twist[3] <= c.twist[2])
    # at the reversal the contacts stick: the unloading branch starts at the loading branch's twist at T_r
    np.testing.assert_array_equal(c.twist[1, -1], c.twist[0, -1])
    np.testing.assert_array_equal(c.twist[3, -1], c.twist[2, -1])


def test_twist_is_odd_in_the_torque_at_a_symmetric_crank_angle():
    # theta = 0 is a mirror position of the k = 1 gear: tau(-T) = -tau(T)
    t = twist(_model(stiffness=1e6), np.zeros(2), np.array([3e5, -3e5]), np.array([1.0, -1.0]))
    assert t[0] > 0.0 and t[1] == pytest.approx(-t[0], rel=1e-9)


@pytest.mark.parametrize("d", [1e-3, 1e-4])
def test_equidistant_modification_gives_the_geometric_backlash(d):
    # pins.md §5.8: a pure equidistant modification opens each flank by tau = d/max_psi l(psi); l = r_p1 sin psi/s
    # is largest, = r_p1, at cos psi = K1, so j = 2 d/r_p1 (measured 2026-12-07: within 3e-9, the free play's
    # root tolerance 1e-15 rad of 1e-6 rad)
    assert backlash(_model(d)) == pytest.approx(2.0 * d / R_P1, rel=1e-8)


def test_lost_motion_holds_the_backlash():
    d = 1e-3
    c = torsion_curve(_model(d, stiffness=1e6), np.linspace(0.0, G1.period, 4), 100.0)
    assert np.all(c.lost_motion > 2.0 * d / R_P1 * ARCMIN_PER_RAD)


def test_unmodified_conjugate_cycloid_has_no_unloaded_transmission_error():
    # pins.md §4: the conjugate cycloid touches every flank pin at the nominal pose, at every crank angle
    assert np.all(unloaded_transmission_error(_model(), np.linspace(0.0, G1.period, 9)) == 0.0)


def test_unloaded_transmission_error_of_an_equidistant_modification():
    # pins.md §5.8 to first order: TE_0(theta) = d/max_j l_j(theta) (the pin with the longest arm closes first);
    # the error is second order: 10x smaller d, ~10x smaller relative error
    th = np.linspace(0.0, G1.period, 9)
    lev = lever_arm(pin_phase(np.arange(22)[:, None], th[None, :], 22, REDUCER), G1).max(axis=0)
    rel = []
    for d in (1e-3, 1e-4):
        te = unloaded_transmission_error(_model(d), th)
        rel.append(np.abs(te / (d / lev) - 1.0).max())
    assert rel[1] < 1e-5 and 5.0 < rel[0] / rel[1] < 20.0


def test_outputs_only_when_asked_and_then_all_with_errors():
    path = str(CONFIGS / "pins_paper_cyc_u10_fixed.toml")
    over = {"contact.face_width_mm": 10.0, "contact.law": "linear", "contact.stiffness_N_per_mm": 1e6}
    plain = api.compute(path, model="contact", overrides=over)
    assert "torsional_stiffness_Nm_per_arcmin" not in plain.summary
    r = api.compute(path, model="contact", detail=True, overrides={**over, "contact.stiffness_curve": True})
    s = r.summary
    for key in ("torsional_stiffness_Nm_per_arcmin", "lost_motion_arcmin", "hysteresis_arcmin", "backlash_arcmin",
                "te_unloaded_pp_arcsec", "te_rated_pp_arcsec"):
        assert s[key] >= 0.0 and s[key + "_err"] >= 0.0, key
    assert s["rated_torque_Nm"] == 1000.0                    # 100 N·m on H times u = 10 (pins.md §5.8)
    assert s["backlash_arcmin"] == 0.0 and s["te_unloaded_pp_arcsec"] == 0.0      # unmodified cycloid
    assert {"torsion", "torsion_crank", "transmission_error"} <= set(r.detail)
    assert len(r.detail["torsion"]) == 44 and len(r.detail["transmission_error"]) == 64
    for key in plain.summary:                                 # the asked-for outputs add to, and change, nothing
        if key != "model_time_ms":
            assert s[key] == plain.summary[key], key


@pytest.mark.slow
def test_the_pins_figure_draws_the_loop_and_the_te(tmp_path):
    pytest.importorskip("matplotlib")
    import gearcalc.plot as gplot
    from gearcalc.kinds.pins import compute
    from gearcalc.pins.plot import plot
    from gearcalc.render import Record

    config = CONFIGS / "pins_paper_circ_u10_fixed.toml"
    res = api.compute(config, overrides={"contact.stiffness_curve": True}, detail=True)
    kept = []
    gplot._collected = kept                   # the figure is kept, not written (as tests/test_plot.py does)
    try:
        plot([Record(str(config), "pins", res.design["name"], res.design, res)], str(tmp_path / "p.png"), compute)
    finally:
        gplot._collected = None
    (fig,) = kept
    loop = next(a for a in fig.axes if a.get_xlabel().startswith("output twist"))
    np.testing.assert_array_equal(loop.lines[0].get_xdata(), [r["twist_arcmin"] for r in res.detail["torsion"]])
    te = next(a for a in fig.axes if a.get_ylabel().startswith("transmission error"))
    assert len(te.lines) == 2                 # no load and T_rated
    plain = api.compute(config)               # not asked: the figure keeps its panels
    kept = []
    gplot._collected = kept
    try:
        plot([Record(str(config), "pins", plain.design["name"], plain.design, plain)], str(tmp_path / "q.png"),
             compute)
    finally:
        gplot._collected = None
    assert not any(a.get_xlabel().startswith("output twist") for a in kept[0].axes)


def test_the_torsion_fields_are_plain_python_numbers():
    """The Python API returns plain floats (interface.md: JSON-ready values), not numpy scalars, for every torsion
    field (torsional_stiffness_Nm_per_arcmin_err was a numpy float64)."""
    import tomllib

    import gearcalc
    from conftest import CONFIGS

    d = tomllib.loads((CONFIGS / "pins_paper_circ_u10_fixed.toml").read_text())
    d.setdefault("contact", {})["stiffness_curve"] = True
    s = gearcalc.compute(d).summary
    numpy_typed = [k for k, v in s.items() if type(v).__module__ == "numpy"]
    assert "torsional_stiffness_Nm_per_arcmin_err" in s and not numpy_typed, numpy_typed
