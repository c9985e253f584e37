"""Property-based tests (issue 7) of the ``zstk`` calculator, end to end on random valid designs.

tests/zstk/test_chain.py holds the physics-level properties (tangency, closure of random chains,
equilibrium of ``zstk.evaluate`` at random phases and directions, scaling).  This file checks the
same invariants, and the output contract, on what ``CALCULATOR.compute`` returns for random TOML
designs: the summary and the per-roller detail table (``--detail``), at every model level, for
every correction, scheme, phase angle, load direction, clearance/preload and material pairing.
Each test names the spec section (docs/spec/zstk.md) its property comes from.
"""
import copy
import math

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from gearcalc import registry
from gearcalc import zstk as z
from gearcalc.calculator import Options
from gearcalc.design import validate
from props_common import assert_all_finite, in_schema

CALC = registry.get("zstk")
SCHEMA = {t.name: {f.name: f for f in t.fields} for t in CALC.tables}
PROPS = settings(max_examples=40, deadline=None, derandomize=True)
FEW = settings(max_examples=5, deadline=None, derandomize=True)
NESTED = settings(max_examples=3, deadline=None, derandomize=True)
STEEL = (2.1e5, 0.3)


# ------------------------------------------------------------------ helpers
def run(raw, model=None, detail=True, tol=1e-6):
    design = validate(copy.deepcopy(raw), "<hyp>")
    return CALC.compute(design, Options(tol=tol, model=model, detail=detail))


def col(result, key):
    return np.array([row[key] for row in result.detail["rollers"]], dtype=float)


def e_star(e1, nu1, e2, nu2):
    """Johnson's contact modulus 1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2 (zstk.md §2), written out here."""
    return 1.0 / ((1 - nu1 ** 2) / e1 + (1 - nu2 ** 2) / e2)


def moduli(raw):
    """(E*_B, E*_H) of a design dict: roller with inner ring, roller with outer ring (zstk.md §2, §9)."""
    m = raw.get("material", {})
    er, nur = m.get("roller_E_MPa", STEEL[0]), m.get("roller_poisson", STEEL[1])
    eg, nug = m.get("ring_E_MPa", STEEL[0]), m.get("ring_poisson", STEEL[1])
    eb, nub = m.get("inner_ring_E_MPa", eg), m.get("inner_ring_poisson", nug)
    eh, nuh = m.get("outer_ring_E_MPa", eg), m.get("outer_ring_poisson", nug)
    return e_star(er, nur, eb, nub), e_star(er, nur, eh, nuh)


# ------------------------------------------------------------------ the design strategy
@st.composite
def designs(draw, scheme=None, direction=None, clearance=None, materials=None, r_b_max=0.95):
    """A random valid zstk design (dict as read from TOML), valid by construction.

    R_H 20..200 mm, R_B = (0.3..r_b_max) R_H (so D = R_H - R_B <= 0.7 R_H), e = (0..0.95) D (also e = 0
    exactly), c = (0..0.3) D (also c = 0): then W/S <= 0.7 and N* >= 4, so every scheme parity has an
    N >= 3 below N*, and N* <= ~130.  Q 1e-3..1e6 N; direction on the line of centres or anywhere;
    clearance 0 or -2 %..+5 % of the smallest roller radius; steel or random materials per body."""
    r_h = draw(st.floats(20.0, 200.0))
    r_b = r_h * draw(st.floats(0.3, r_b_max))
    d = r_h - r_b
    e = d * draw(st.just(0.0) | st.floats(0.0, 0.95))
    c = d * draw(st.just(0.0) | st.floats(0.0, 0.3))
    raw = {
        "kind": "zstk", "name": "hyp",
        "geometry": {"outer_raceway_radius_mm": r_h, "inner_raceway_radius_mm": r_b, "eccentricity_mm": e,
                     "roller_gap_mm": c, "roller_length_mm": draw(st.floats(1.0, 100.0)),
                     "correct": draw(st.sampled_from(["outer", "inner", "gap"]))},
        "load": {"radial_N": 10 ** draw(st.floats(-3.0, 6.0))},
        "material": {},
    }
    sch = scheme if scheme is not None else draw(st.sampled_from(["A", "B", "C", "D", "angle"]))
    raw["geometry"]["scheme"] = draw(st.floats(-179.0, 180.0)) if sch == "angle" else sch
    if direction is None:
        raw["load"]["direction_deg"] = draw(st.sampled_from([0.0, 180.0]) | st.floats(-180.0, 180.0))
    else:
        raw["load"]["direction_deg"] = direction
    r_min = (d - e) / 2
    s = clearance if clearance is not None else draw(st.just(0.0) | st.floats(-0.02, 0.05))
    raw["load"]["clearance_mm"] = s * r_min
    if materials if materials is not None else draw(st.booleans()):
        mat = raw["material"]
        for key in ("roller", "inner_ring", "outer_ring"):
            mat[f"{key}_E_MPa"] = draw(st.floats(5e4, 4e5))
            mat[f"{key}_poisson"] = draw(st.floats(0.1, 0.45))
    if draw(st.booleans()):
        raw["material"]["allowable_stress_MPa"] = draw(st.floats(100.0, 5000.0))
    return in_schema(raw)


def on_line(raw):
    return isinstance(raw["geometry"]["scheme"], str) and raw["load"]["direction_deg"] in (0.0, 180.0)


# ------------------------------------------------------------------ 1. no NaN or infinity anywhere
@pytest.mark.slow
@PROPS
@given(designs())
def test_every_output_finite_at_every_level(raw):
    # interface.md "Output": no NaN or infinity is ever a result; zstk.md §8: the model levels
    # (the reference level has its own test below)
    for model in ("equilibrium", "fixed-direction"):
        res = run(raw, model=model)
        assert_all_finite(res)
        assert res.summary["model"] == model == res.model
        assert len(res.detail["rollers"]) == res.summary["N"]
        assert run(raw, model=model, detail=False).summary == res.summary   # --detail changes no summary field


# Found by hypothesis (then rounded): one angular pitch of this chain exceeds 180 deg (N = 5, e/D = 0.87); the
# stepping cross-check once scanned only half a turn ahead and raised BracketError here (exit 70)
WIDE_PITCH = {"kind": "zstk", "name": "wide pitch",
              "geometry": {"outer_raceway_radius_mm": 20.0, "inner_raceway_radius_mm": 7.5, "eccentricity_mm": 10.9,
                           "roller_gap_mm": 3.1, "roller_length_mm": 1.0, "correct": "inner", "scheme": "B"},
              "load": {"radial_N": 1.0, "direction_deg": 0.0, "clearance_mm": 0.0}, "material": {}}


@FEW
@example(raw=WIDE_PITCH)
@given(designs())
def test_reference_level_finite(raw):
    # interface.md "Output" and exit codes (never an internal error); zstk.md §8: the reference level
    # adds the stepped chain, whose closure residual is < 1e-9 mm (§7.2) independent of the phase
    res = run(raw, model="reference")
    assert_all_finite(res)
    assert res.summary["stepping_residual_mm"] < 1e-9


@pytest.mark.slow
@NESTED
@given(designs(scheme="cycle", direction="envelope", r_b_max=0.85),
       st.sampled_from(["equilibrium", "fixed-direction"]))
def test_cycle_and_envelope_outputs_finite(raw, model):
    # interface.md "Output" and zstk.md §8 (sweep fields, sigma_max_err_MPa) for the nested sweep;
    # tol = 1e-2 keeps it cheap (see test_nested_sweep_meets_tolerance for tighter tolerances)
    res = run(raw, model=model, tol=1e-2)
    assert_all_finite(res)
    s = res.summary
    # zstk.md §8: the joint search's grid doubled at least once (roller positions per turn, relative directions)
    assert s["phase_samples"] >= 32 and s["direction_samples"] >= 64
    assert 0.0 <= s["sigma_max_err_MPa"]


def test_nested_sweep_meets_tolerance(monkeypatch):
    # zstk.md §8 steps 2-4: the sweep doubles M until the error <= tol sigma_max; sigma is smooth apart
    # from kinks, so the estimate must fall as M doubles.  Found by test_cycle_and_envelope_outputs_finite
    # (R_H 178.6, R_B 145.7, e 21.56, c 0.049); rounded here.  Regression: the inner direction envelope
    # ranked the directions with the fixed-direction model, whose maxima lie far from the equilibrium
    # model's at large e/D; sigma_max came out 2.1e-6 relative low (588.4648 against 588.4661 MPa), its
    # change between doublings did not fall, and the sweep stopped at the cap with an estimate of 0.243
    # MPa (measured at cap 128; the full cap 2^16 took ~300 s).  With the directions ranked by the model's
    # own loads it converges at M = 128 (estimate 7.7e-13 MPa); the cap is lowered to 128 so a regression
    # fails fast.
    import gearcalc.zstk.envelope as kz

    monkeypatch.setattr(kz, "GRID_CAP", 128)
    raw = {"kind": "zstk", "name": "nested",
           "geometry": {"outer_raceway_radius_mm": 100.0, "inner_raceway_radius_mm": 80.0, "eccentricity_mm": 12.0,
                        "roller_gap_mm": 0.05, "roller_length_mm": 20.0, "scheme": "cycle"},
           "load": {"radial_N": 1e4, "direction_deg": "envelope"}}
    res = run(raw, tol=1e-4, detail=False)
    s = res.summary
    assert not any("cap" in w for w in res.warnings), res.warnings
    assert s["sigma_max_err_MPa"] <= 1e-4 * s["sigma_max_MPa"]


# ------------------------------------------------------------------ 2. closure of the chain
@PROPS
@given(designs())
def test_chain_closes_with_equal_gaps_and_tangency(raw):
    res = run(raw)
    s = res.summary
    n, r_h, r_b, c = s["N"], s["outer_raceway_radius_mm"], s["inner_raceway_radius_mm"], s["roller_gap_mm"]
    e = raw["geometry"]["eccentricity_mm"]
    theta = np.radians(col(res, "theta_deg"))
    r = col(res, "r_mm")
    # zstk.md §4.1: indices increase counter-clockwise, so the N angular pitches are positive and
    # add up to exactly one turn (the chain is closed)
    pitch = np.mod(np.diff(np.append(theta, theta[0])), 2 * np.pi)
    assert np.all(pitch > 0)
    assert pitch.sum() == pytest.approx(2 * np.pi, abs=1e-9)
    # zstk.md §7.2: all N neighbour gaps equal c (after correction, §11.10) within 1e-9 mm, and each
    # roller touches both raceways within 1e-9 mm
    P = (r_h - r)[:, None] * np.stack([np.cos(theta), np.sin(theta)], axis=1)
    gaps = np.linalg.norm(np.roll(P, -1, axis=0) - P, axis=1) - r - np.roll(r, -1)
    assert np.max(np.abs(gaps - c)) <= 1e-9
    assert np.max(np.abs(np.linalg.norm(P - [e, 0.0], axis=1) - (r_b + r))) <= 1e-9
    # zstk.md §7.2: N* recomputed from the corrected geometry equals N within 1e-9
    assert float(z.fractional_roller_number(r_h, r_b, e, c)) == pytest.approx(n, abs=1e-9)
    # zstk.md §3.1: r_min = (D - e)/2 <= r_i <= r_max = (D + e)/2
    assert np.all(r >= s["r_min_mm"] * (1 - 1e-12)) and np.all(r <= s["r_max_mm"] * (1 + 1e-12))
    # zstk.md §4.2-4.3: roller 0 is the phase reference: theta_0 of the scheme or the given angle
    assert s["theta0_deg"] == pytest.approx(float(np.degrees(theta[0])), abs=1e-9)
    sch = raw["geometry"]["scheme"]
    if sch in ("A", "B"):
        assert s["theta0_deg"] == pytest.approx(0.0, abs=1e-9)
    elif not isinstance(sch, str):
        assert s["theta0_deg"] == pytest.approx(sch, abs=1e-9)
    # zstk.md §4.2: parity of N per scheme (A, D even; B, C odd)
    if isinstance(sch, str):
        assert n % 2 == z.SCHEME_PARITY[sch]


@PROPS
@given(designs())
def test_correction_sign_and_roller_growth(raw):
    # zstk.md §3.2 "Choice of N": with rollers = "auto", N <= N*, so R_H' >= R_H (outer),
    # R_B' <= R_B (inner) or c' >= c (gap); §6.5: under "outer", r_min and r_max grow by dR_H/2
    s = run(raw, detail=False).summary
    g = raw["geometry"]
    assert s["N"] <= s["N_star"] + 1e-9
    dc = s["correction_mm"]
    sign = {"outer": 1.0, "inner": -1.0, "gap": 1.0}[g["correct"]]
    assert sign * dc >= 0.0
    d0, e = g["outer_raceway_radius_mm"] - g["inner_raceway_radius_mm"], g["eccentricity_mm"]
    if g["correct"] == "outer":
        assert s["r_min_mm"] == pytest.approx((d0 - e) / 2 + dc / 2, rel=1e-12, abs=1e-12 * d0)
        assert s["r_max_mm"] == pytest.approx((d0 + e) / 2 + dc / 2, rel=1e-12, abs=1e-12 * d0)


# ------------------------------------------------------------------ 3. equilibrium and forces
@pytest.mark.slow
@PROPS
@given(designs(), st.sampled_from(["equilibrium", "fixed-direction"]))
def test_force_equilibrium_from_the_detail_table(raw, model):
    res = run(raw, model=model)
    s = res.summary
    Q = raw["load"]["radial_N"]
    F = col(res, "F_B_N")
    psi = np.radians(col(res, "psi_deg"))
    along, across = np.sum(F * np.cos(psi)) - Q, np.sum(F * np.sin(psi))
    # zstk.md §7.2 with §11.1: sum F_iB n_Bi = Q u in both components, to 1e-9 of (Q + sum F)
    # (with preload the forces exceed Q; the solver's own target is 1e-12 (Q + sum F))
    scale = Q + F.sum()
    assert abs(along) <= 1e-9 * scale
    if model == "fixed-direction":
        # zstk.md §8: the fixed-direction level leaves a transverse force and reports it
        assert abs(across) / Q == pytest.approx(s["transverse_residual"], rel=1e-6, abs=1e-9 * scale / Q)
    else:
        assert abs(across) <= 1e-9 * scale
        assert s["solver_residual"] <= 1e-9 or any("residual" in w for w in res.warnings)
    # zstk.md §7.2 and §5 item 2: F >= 0, F_iH = F_iB cos beta_i <= F_iB
    FH = col(res, "F_H_N")
    beta = np.radians(col(res, "beta_deg"))
    assert np.all(F >= 0) and np.all(FH >= 0) and np.all(FH <= F)
    assert np.allclose(FH, F * np.cos(beta), rtol=1e-12, atol=0)
    # zstk.md §10: a roller counts as loaded above 1e-12 of the largest roller force (not its round-off)
    assert s["loaded_rollers"] == int(np.count_nonzero(F > 1e-12 * F.max())) >= 1


@PROPS
@given(designs())
@example({"kind": "zstk", "name": "hyp",     # mirror rollers 1 ulp apart (found by CI's run of this test)
          "geometry": {"outer_raceway_radius_mm": 20.0, "inner_raceway_radius_mm": 6.015625,
                       "eccentricity_mm": 6.9921875, "roller_gap_mm": 0.0, "roller_length_mm": 1.0,
                       "correct": "outer", "scheme": "B"},
          "load": {"radial_N": 1.0, "direction_deg": 180.0, "clearance_mm": 0.0}, "material": {}})
def test_hertz_stresses_and_summary_agree_with_the_detail(raw):
    res = run(raw)
    s = res.summary
    g = raw["geometry"]
    length = g["roller_length_mm"]
    r_h, r_b = s["outer_raceway_radius_mm"], s["inner_raceway_radius_mm"]
    r, F, FH = col(res, "r_mm"), col(res, "F_B_N"), col(res, "F_H_N")
    eb, eh = moduli(raw)
    # zstk.md §2, eqs. (4)-(5): reduced radii of the convex and the concave contact
    rho_b, rho_h = r * r_b / (r_b + r), r * r_h / (r_h - r)
    assert np.allclose(col(res, "rho_B_mm"), rho_b, rtol=1e-12)
    assert np.allclose(col(res, "rho_H_mm"), rho_h, rtol=1e-9)
    # zstk.md §2, eq. (3) = Johnson's p0 = sqrt(F E*/(pi l rho)); b = 2F/(pi l sigma); tau_max ~ 0.30 sigma
    sb, sh = col(res, "sigma_B_MPa"), col(res, "sigma_H_MPa")
    assert np.allclose(sb, np.sqrt(F * eb / (np.pi * length * rho_b)), rtol=1e-11, atol=0)
    assert np.allclose(sh, np.sqrt(FH * eh / (np.pi * length * rho_h)), rtol=1e-9, atol=0)
    loaded = F > 0
    assert np.allclose(col(res, "b_B_mm")[loaded], 2 * F[loaded] / (np.pi * length * sb[loaded]), rtol=1e-11)
    assert np.all(col(res, "b_B_mm")[~loaded] == 0.0)
    # zstk.md §2: the Tresca maximum for the smaller nu of the contact's bodies: 0.3003 sigma for nu >= 0.2423,
    # else (1 - u) sqrt(1 - u^2)/2 sigma, u(1 + u) = 2 nu (test_zstk_v2.py checks it against a depth scan)
    m = raw.get("material", {})
    nu_r, nu_g = m.get("roller_poisson", STEEL[1]), m.get("ring_poisson", STEEL[1])
    nu = min(nu_r, m.get("inner_ring_poisson", nu_g))
    u = (math.sqrt(1 + 8 * nu) - 1) / 2
    ratio = max(0.30028310600077, 0.5 * (1 - u) * math.sqrt(1 - u * u))
    assert np.allclose(col(res, "tau_max_B_MPa"), ratio * sb, rtol=1e-12)
    # zstk.md §6 claim 1: the inner contact is the more stressed when E*_B >= E*_H
    if eb >= eh:
        assert np.all(sb[loaded] > sh[loaded])
    # zstk.md §10: sigma_max and where it occurs are those of the detail table
    both = np.concatenate([sb, sh])
    # (where mirror rollers agree within 1e-12, up to round-off, the lower index is named, inner first: its
    # value can be the maximum's last bit below it; this hypothesis example: 78.42987502178308 against ...309)
    assert s["sigma_max_MPa"] == both.max()
    i, contact = s["sigma_max_roller"], s["sigma_max_contact"]
    at = (sb if contact == "inner" else sh)[i]
    assert s["sigma_max_MPa"] * (1 - 1e-12) <= at <= s["sigma_max_MPa"]
    order = np.stack([sb, sh], axis=1).ravel()       # roller-major, inner first (zstk.md §10)
    assert np.flatnonzero(order >= s["sigma_max_MPa"] * (1 - 1e-12))[0] == 2 * i + (contact == "outer")
    assert s["sigma_max_roller_radius_mm"] == r[i]
    assert s["sigma_max_angle_deg"] == pytest.approx(res.detail["rollers"][i]["theta_deg"], abs=1e-9)
    # zstk.md §10: strength check; interface.md exit codes: a failed check is listed in `failed`
    assert s["safety_factor"] == pytest.approx(s["allowable_stress_MPa"] / s["sigma_max_MPa"], rel=1e-15)
    assert s["pass"] == (s["sigma_max_MPa"] <= s["allowable_stress_MPa"]) == (not res.failed)
    given_allowable = raw["material"].get("allowable_stress_MPa")
    assert s["allowable_stress_MPa"] == (4000.0 if given_allowable is None else given_allowable)  # §7.1.4


@PROPS
@given(designs(clearance=0.0), st.floats(1e-3, 1e3))
def test_zero_clearance_load_scaling(raw, k):
    # zstk.md §7.2: with s = 0, F ∝ Q, sigma ∝ sqrt(Q), delta ∝ Q^(9/10) (the direction is unchanged)
    a = run(raw)
    big = copy.deepcopy(raw)
    big["load"]["radial_N"] *= k
    b = run(big)
    Fa = col(a, "F_B_N")
    assert np.allclose(col(b, "F_B_N"), k * Fa, rtol=1e-9, atol=1e-12 * k * Fa.max())
    assert b.summary["sigma_max_MPa"] == pytest.approx(math.sqrt(k) * a.summary["sigma_max_MPa"], rel=1e-9)
    assert b.summary["approach_um"] == pytest.approx(k ** 0.9 * a.summary["approach_um"], rel=1e-8)
    assert b.summary["approach_direction_deg"] == pytest.approx(a.summary["approach_direction_deg"], abs=1e-7)


@pytest.mark.slow
@PROPS
@given(designs(), st.sampled_from("ABCD"), st.sampled_from([0.0, 180.0]))
def test_symmetric_configurations(raw, scheme, gamma):
    # zstk.md §5.1 and §7.2: schemes A-D with the load on the line of centres are mirror-symmetric:
    # the forces are mirror-symmetric, and fixed-direction and equilibrium agree to round-off
    # (with clearance or preload too: both solve along the load line, §5.2)
    raw["geometry"]["scheme"] = scheme
    raw["load"]["direction_deg"] = gamma
    eq, fd = run(raw, model="equilibrium"), run(raw, model="fixed-direction")
    F, theta = col(eq, "F_B_N"), col(eq, "theta_deg")
    scale = F.max()
    assert np.allclose(col(fd, "F_B_N"), F, rtol=1e-9, atol=1e-12 * scale)
    assert fd.summary["transverse_residual"] <= 1e-9
    assert fd.summary["sigma_max_MPa"] == pytest.approx(eq.summary["sigma_max_MPa"], rel=1e-9)
    # mirror: for every roller at theta there is one at -theta with the same force
    t = np.mod(theta, 360.0)
    for ti, fi in zip(t, F):
        gap = np.abs(np.mod(t + ti + 180.0, 360.0) - 180.0)      # angular distance of each roller to -ti
        j = int(np.argmin(gap))
        assert gap[j] <= 1e-7
        assert F[j] == pytest.approx(fi, rel=1e-9, abs=1e-12 * scale)


# ------------------------------------------------------------------ 4. sweeps: envelopes dominate
@pytest.mark.slow
@FEW
@given(designs(direction="envelope"), st.floats(-180.0, 180.0))
def test_direction_envelope_dominates_every_direction(raw, gamma):
    # zstk.md §5.3: "envelope" reports each roller's maximum over the load directions and the global
    # maximum; so it is >= the value at any one direction (within the reported error and --tol)
    env = run(raw, tol=1e-6)
    one = copy.deepcopy(raw)
    one["load"]["direction_deg"] = gamma
    fixed = run(one)
    slack = env.summary["sigma_max_err_MPa"] + 1e-6 * env.summary["sigma_max_MPa"]
    assert env.summary["sigma_max_MPa"] >= fixed.summary["sigma_max_MPa"] - slack
    assert np.all(col(env, "sigma_B_MPa") >= col(fixed, "sigma_B_MPa") - slack)
    assert np.all(col(env, "sigma_H_MPa") >= col(fixed, "sigma_H_MPa") - slack)


@FEW
@given(designs(scheme="cycle"), st.floats(-179.0, 180.0))
def test_cycle_dominates_every_placement(raw, theta0):
    # zstk.md §4.3: "cycle" is the envelope over every placement of the chain (phase over one pitch),
    # so it is >= the value at any given phase angle theta_0 (same N: both take any parity)
    if raw["load"]["direction_deg"] == "envelope":
        raw["load"]["direction_deg"] = 0.0
    cyc = run(raw, tol=1e-6)
    one = copy.deepcopy(raw)
    one["geometry"]["scheme"] = theta0
    fixed = run(one)
    assert cyc.summary["N"] == fixed.summary["N"]
    slack = cyc.summary["sigma_max_err_MPa"] + 1e-6 * cyc.summary["sigma_max_MPa"]
    assert cyc.summary["sigma_max_MPa"] >= fixed.summary["sigma_max_MPa"] - slack
