"""Tests of gearcalc.zstk.loads: the roller stiffness and the load distribution over the rollers (zstk.md §5),
through :func:`gearcalc.zstk.evaluate` and the load solvers.

Expected numbers come from exact identities (equilibrium in both components, F ∝ Q, sigma ∝ sqrt(Q),
delta ∝ Q^(9/10)), the closed form F_i = Q cos^(10/9) psi_i / sum cos^(19/9) psi of the symmetric case (§5.1),
Stribeck's 4.08 (NSK E728) and its limit 2 sqrt(pi) Gamma(37/18)/Gamma(14/9), an independent minimiser of the
potential (scipy BFGS), the ISO/TS 16281 constant 35 948 l^(8/9), and the light-load limit
|v| = s/2 + (Q/c_L)^(9/10).
"""
import math

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from gearcalc import hertz
from gearcalc import zstk as z

# the shared fixtures of the zstk tests (the paper's chain, a state, random geometries): tests/zstk/test_chain.py
from zstk.test_chain import Q, STEEL, equilibrium_error, geometries, make_geometry, paper_chain, state


# ----------------------------------------------------------------------------- §5 loads


@settings(max_examples=40, deadline=None)
@given(st.floats(0.0, 2 * math.pi), st.floats(-math.pi, math.pi), st.sampled_from([0.0, 0.01, -0.01, 0.1]))
def test_equilibrium_two_components(phase, gamma, clearance):
    # sum F_iB n_Bi = Q u in both components to 1e-9 relative (spec §7.2); F >= 0, F_H <= F_B
    ch = paper_chain()
    s = state(ch, phase, gamma, clearance=clearance)
    ax, tr = equilibrium_error(s, Q)
    assert ax <= 1e-9 and tr <= 1e-9
    assert s.loads.residual <= 1e-12 * (Q + np.sum(s.force_inner))
    assert np.all(s.force_inner >= 0) and np.all(s.force_outer <= s.force_inner)
    assert np.all(np.isfinite(s.sigma_inner)) and np.all(np.isfinite(s.sigma_outer))


def test_vectorised_over_phases_and_directions():
    ch = paper_chain()
    phases = np.linspace(0, 0.7, 5)[:, None]
    gammas = np.linspace(-np.pi, np.pi, 9)[None, :]
    s = state(ch, phases, gammas)
    assert s.force_inner.shape == (5, 9, ch.n)
    one = state(ch, float(phases[2, 0]), float(gammas[0, 4]))
    assert np.allclose(s.force_inner[2, 4], one.force_inner, rtol=1e-12, atol=1e-9)
    ax, tr = equilibrium_error(s, Q)
    assert np.max(ax) <= 1e-9 and np.max(tr) <= 1e-9


@pytest.mark.parametrize("scheme,n", [("A", 8), ("B", 7), ("C", 7), ("D", 8)])
@pytest.mark.parametrize("gamma", [0.0, np.pi])
def test_symmetric_closed_form(scheme, n, gamma):
    # F_iB = Q cos^(10/9) psi / sum cos^(19/9) psi (spec §5.1), mirror-symmetric forces, and the
    # direction root agrees with the closed form to round-off
    ch = paper_chain(n=n)
    s_sym = state(ch, z.scheme_phase(scheme, n), gamma, symmetric=True)
    s_gen = state(ch, z.scheme_phase(scheme, n), gamma)
    cpsi = np.maximum(np.cos(s_sym.psi), 0.0)
    expected = Q * cpsi ** (10 / 9) / np.sum(cpsi ** (19 / 9))
    assert np.allclose(s_sym.force_inner, expected, rtol=1e-13, atol=1e-9)
    assert np.allclose(s_gen.force_inner, expected, rtol=1e-9, atol=1e-7)
    assert np.allclose(s_sym.force_outer, expected * np.cos(s_sym.beta), rtol=1e-13, atol=1e-9)
    # mirror symmetry: the multiset of (theta, F) equals that of (-theta, F)
    a = sorted(zip(np.round(np.degrees(z.wrap_angle(s_sym.theta)), 6) % 360, np.round(s_sym.force_inner, 6)))
    b = sorted(zip(np.round(np.degrees(z.wrap_angle(-s_sym.theta)), 6) % 360, np.round(s_sym.force_inner, 6)))
    assert a == b
    fixed = state(ch, z.scheme_phase(scheme, n), gamma, fixed_direction=True)
    assert np.allclose(fixed.force_inner, s_sym.force_inner, rtol=1e-13, atol=1e-9)


def test_fixed_direction_leaves_transverse_force():
    # off-symmetric: v ∥ u leaves an unbalanced transverse force (spec §5.1), the equilibrium model none
    ch = paper_chain()
    fixed = state(ch, 0.3, 0.4, fixed_direction=True)
    full = state(ch, 0.3, 0.4)
    assert fixed.loads.transverse / Q > 1e-4
    assert full.loads.transverse / Q < 1e-12


def scipy_forces(normal_angle, gamma, clearance, stiffness, load):
    """Roller forces from scipy's BFGS minimisation of the potential Pi(v) (spec §5.2), independent."""
    from scipy.optimize import minimize

    n = np.stack([np.cos(normal_angle), np.sin(normal_angle)], -1)
    u = np.array([math.cos(gamma), math.sin(gamma)])
    scale = 1e-3  # v in µm for a well-scaled problem

    def pi(v):
        d = np.maximum(n @ (v * scale) - clearance / 2, 0.0)
        return (stiffness * 9 / 19 * np.sum(d ** (19 / 9)) - load * u @ (v * scale)) / load

    def grad(v):
        d = np.maximum(n @ (v * scale) - clearance / 2, 0.0)
        return (stiffness * (d ** (10 / 9)) @ n - load * u) * scale / load

    res = minimize(pi, 10 * u, jac=grad, method="BFGS", options={"gtol": 1e-14})
    d = np.maximum(n @ (res.x * scale) - clearance / 2, 0.0)
    return stiffness * d ** (10 / 9)


@pytest.mark.parametrize("clearance", [0.0, 0.02, -0.01])
def test_equilibrium_matches_scipy_minimiser(clearance):
    ch = paper_chain()
    s = state(ch, 0.37, 0.9, clearance=clearance)
    f_ref = scipy_forces(s.normal_angle, 0.9, clearance, STEEL.stiffness, Q)
    assert np.allclose(s.force_inner, f_ref, rtol=1e-5, atol=1e-3)


@pytest.mark.parametrize("z_count", [10, 20, 40])
def test_stribeck_line_contact(z_count):
    # e = 0, zero clearance, a roller on the load line: Q_max Z/F_r within 0.5 % of 4.08 (NSK E728)
    ch = z.close_chain(100.0, 50.0, 0.0, 3.0, z_count, "gap")
    s = state(ch, 0.0, 0.0, symmetric=True)
    factor = np.max(s.force_inner) * z_count / Q
    assert factor == pytest.approx(4.08, rel=5e-3)
    # a gap on the load line gives a lower factor, clearly lower for few rollers (Z = 10: about -6 %)
    s_gap = state(ch, np.pi / z_count, 0.0, symmetric=True)
    gap_factor = np.max(s_gap.force_inner) * z_count / Q
    assert gap_factor < factor - 1e-3
    if z_count == 10:
        assert gap_factor < 0.97 * factor


def test_stribeck_limit():
    # Z -> infinity: 2 sqrt(pi) Gamma(37/18)/Gamma(14/9) (spec §7.1, derived); Z = 2000 within 1e-5
    from scipy.special import gamma as gam

    limit = 2 * math.sqrt(math.pi) * gam(37 / 18) / gam(14 / 9)
    assert round(limit, 2) == 4.08
    ch = z.close_chain(100.0, 99.0, 0.0, 0.0, 2000, "gap")
    s = state(ch, 0.0, 0.0, symmetric=True)
    assert np.max(s.force_inner) * 2000 / Q == pytest.approx(limit, rel=1e-5)


@settings(max_examples=20, deadline=None)
@given(st.floats(-1.0, 1.0), st.floats(1e-3, 1e3))
def test_scaling_invariants(gamma, k):
    # s = 0: F ∝ Q, sigma ∝ sqrt(Q), delta ∝ Q^(9/10) (spec §7.2)
    ch = paper_chain()
    a = state(ch, 0.2, gamma, load=Q)
    b = state(ch, 0.2, gamma, load=Q * k)
    assert np.allclose(b.force_inner, k * a.force_inner, rtol=1e-9, atol=1e-9 * Q * k)
    assert np.allclose(b.sigma_inner, math.sqrt(k) * a.sigma_inner, rtol=1e-9, atol=1e-9)
    assert b.loads.approach == pytest.approx(k ** 0.9 * a.loads.approach, rel=1e-9)


def test_clearance_models_agree_when_symmetric():
    # symmetric configuration with clearance: the 1-D root (v ∥ u) and the 2-D Newton agree
    ch = paper_chain()
    for s_ in (0.03, -0.01):
        th = z.roller_angles(0.0, ch.n, ch.limiting_ratio)
        nb = th + z.normal_angle_offset(th, ch.outer_radius, ch.inner_radius, ch.eccentricity)
        one = z.load_along_direction(nb, 0.0, Q, STEEL.stiffness, s_)
        two = z.load_with_clearance(nb, 0.0, Q, STEEL.stiffness, s_)
        assert np.allclose(one.force, two.force, rtol=1e-9, atol=1e-9)
        assert two.alpha == pytest.approx(0.0, abs=1e-9)


def test_clearance_concentrates_load_and_preload_spreads_it():
    ch = paper_chain()
    zero = state(ch, 0.0, 0.0, symmetric=True)
    loose = state(ch, 0.0, 0.0, clearance=0.05, symmetric=True)
    tight = state(ch, 0.0, 0.0, clearance=-0.03, symmetric=True)
    assert np.max(loose.force_inner) > np.max(zero.force_inner)
    assert np.count_nonzero(loose.force_inner) < np.count_nonzero(zero.force_inner)
    assert np.count_nonzero(tight.force_inner) == ch.n


def test_preload_small_load():
    # forces stay non-zero as Q -> 0 with preload; delta may be negative (spec §9)
    ch = paper_chain()
    for load in (1e-3, 1e-6):
        s = state(ch, 0.3, 0.5, load=load, clearance=-0.01)
        assert np.all(s.force_inner > 1.0)
        assert s.loads.residual <= 1e-12 * (load + np.sum(s.force_inner))
        assert np.all(np.isfinite(s.force_inner))


def test_min_norm_displacement_single_loaded_roller():
    # e = 0, N = 3, load through a roller: only that roller is loaded; v along its normal (spec §11.3)
    ch = z.close_chain(100.0, 50.0, 0.0, 0.0, 3, "gap")
    s = state(ch, 0.0, 0.0)
    assert np.count_nonzero(s.force_inner) == 1
    assert s.force_inner[0] == pytest.approx(Q, rel=1e-12)
    assert s.loads.alpha == pytest.approx(0.0, abs=1e-12)


def test_normals_perpendicular_to_load():
    # e = 0, Z = 8, phi_0 = 0, gamma = 90°: rollers with n ⊥ u get F = 0, no NaN, continuous at 90° ± 1e-9
    ch = z.close_chain(100.0, 50.0, 0.0, 3.0, 8, "gap")
    vals = [state(ch, 0.0, math.radians(90.0) + d) for d in (-1e-9 * math.pi / 180, 0.0, 1e-9 * math.pi / 180)]
    for v in vals:
        assert np.all(np.isfinite(v.force_inner)) and np.all(np.isfinite(v.sigma_inner))
    assert np.allclose(vals[0].force_inner, vals[1].force_inner, atol=1e-3)
    assert np.allclose(vals[2].force_inner, vals[1].force_inner, atol=1e-3)
    assert vals[1].force_inner[0] == pytest.approx(0.0, abs=1e-9)


# ----------------------------------------------------------------------------- materials and sweeps
def test_stiffness_material_scaling():
    # steel: the ISO/TS 16281 constant unchanged; softer rings: smaller constant
    assert z.roller_stiffness(20.0) == pytest.approx(35948.0 * 20.0 ** (8 / 9), rel=1e-14)
    assert z.E_STAR_REF == pytest.approx(115384.615, rel=1e-8)
    soft = hertz.contact_modulus(2.1e5, 0.3, 1.1e5, 0.34)
    assert z.roller_stiffness(20.0, soft, soft) == pytest.approx(
        35948.0 * 20.0 ** (8 / 9) * (z.E_STAR_REF / soft) ** -1.0, rel=1e-12)


def test_min_norm_displacement_with_clearance():
    # a light load through a roller with clearance: one loaded roller, v along its normal with
    # |v| = s/2 + (Q/c_L)^(9/10) (spec §5, §11.3)
    th = z.roller_angles(0.0, 3, 0.0)
    s = z.load_with_clearance(th, 0.0, 100.0, 1e5, 0.05)
    assert np.count_nonzero(s.force) == 1 and s.force[0] == pytest.approx(100.0, rel=1e-12)
    assert s.alpha == pytest.approx(0.0, abs=1e-12)
    assert s.approach == pytest.approx(0.025 + (100.0 / 1e5) ** 0.9, rel=1e-9)


@settings(max_examples=40, deadline=None)
@given(geometries, st.floats(0.0, 2 * math.pi), st.floats(-math.pi, math.pi), st.sampled_from([0.0, 0.02, -0.005]),
       st.sampled_from(["outer", "inner", "gap"]))
def test_equilibrium_random_designs(t, phase, gamma, clearance, correct):
    # §7.2 invariants over random valid designs, phases, directions, clearances and corrections
    r_h, r_b, e, c = make_geometry(t)
    n = z.auto_roller_number(float(z.fractional_roller_number(r_h, r_b, e, c)))
    assume(n >= 3)
    ch = z.close_chain(r_h, r_b, e, c, n, correct)
    assume(not z.chain_problems(ch))
    s = state(ch, phase, gamma, clearance=clearance)
    ax, tr = equilibrium_error(s, Q)
    assert ax <= 1e-9 and tr <= 1e-9
    assert np.all(s.force_inner >= 0) and np.all(s.force_outer <= s.force_inner)
    assert np.all(np.isfinite(s.sigma_inner)) and np.all(np.isfinite(s.sigma_outer))
    loaded = s.force_inner > 0
    assert np.all(s.sigma_inner[loaded] > s.sigma_outer[loaded])  # claim 1 (same material)


@pytest.mark.parametrize("load", [1e-6, 1.0, 1e8])
@pytest.mark.parametrize("clearance", [1e-4, 0.05, -1e-4, -0.05])
def test_clearance_solver_reaches_target_on_a_grid(load, clearance):
    # spec §11.1: residual <= 1e-12 (Q + sum F) for every phase and direction, also where the contact
    # deflection ((Q/c_L)^0.9 ~ 1e-11 mm at Q = 1e-6 N) is far below the clearance (round-off of s/2)
    ch = paper_chain()
    th = z.roller_angles(np.linspace(0, 2 * np.pi / ch.n, 9)[:, None], ch.n, ch.limiting_ratio)
    s = z.evaluate(ch, STEEL, th, np.linspace(-np.pi, np.pi, 25)[None, :], load, clearance)
    assert np.all(s.loads.converged)
    assert np.all(s.loads.residual <= 1e-12 * (load + np.sum(s.force_inner, axis=-1)))
    ax, tr = equilibrium_error(s, load)
    if clearance > 0:  # forces ~ Q: the invariant relative to Q holds as well
        assert np.max(ax) <= 1e-9 and np.max(tr) <= 1e-9
