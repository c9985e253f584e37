"""``gearcalc zstk``: closed rolling-body mechanism (eccentric ZSTK, leading inner ring).

Schema, cross-key checks and the compute driver; the physics is in :mod:`gearcalc.zstk`
(imported inside the functions: this module stays light for ``check``/``new``/``--help``).
Spec: zstk.md; source: Merko et al., seed 003_2d1da402cb0b8488.txt.
"""
from __future__ import annotations

import math

from ..calculator import REQUIRED, Calculator, DesignError, Field, Options, Result, Table

MODELS = ("equilibrium", "fixed-direction", "reference")
SCHEMES = ("A", "B", "C", "D")
DEFAULT_ALLOWABLE_MPA = 4000.0
DEFAULT_ALLOWABLE_SOURCE = "default: ISO 76 static reference"
B_OVER_RHO_LIMIT = 0.1
GRID_PHASE = 64        # points per pitch (spec §8)
GRID_DIRECTION = 720   # points per turn
GRID_CAP = 2 ** 16
# Physical ranges of the inputs (gearcalc's choice, spec §9 "a value outside its physical range"):
# lengths from 1 nm to 1 km, moduli from soft rubber (1 MPa) to beyond diamond (1e7 MPa).
MIN_LENGTH_MM, MAX_LENGTH_MM = 1e-6, 1e6
MIN_E_MPA, MAX_E_MPA = 1.0, 1e7
MAX_ROLLERS = 2000       # gearcalc's range (the spec asks N > 200 to work); keeps sweeps in memory
CHUNK_ELEMENTS = 1_000_000  # roller-configurations evaluated at once in the sweeps
REFINE_ROWS_MAX_N = 200  # above this the per-roller envelope rows are grid maxima (O(N²) refinement)

GEOMETRY = Table("geometry", (
    Field("outer_raceway_radius_mm", "number", REQUIRED, "R_H, outer (concave) raceway radius, nominal",
          gt=0, le=MAX_LENGTH_MM, example=100.0),
    Field("inner_raceway_radius_mm", "number", REQUIRED, "R_B, inner (convex) raceway radius, nominal",
          gt=0, le=MAX_LENGTH_MM, example=50.0),
    Field("eccentricity_mm", "number", REQUIRED, "e = |O_H O_B|, offset of the inner raceway centre",
          ge=0, le=MAX_LENGTH_MM, example=6.0),
    Field("roller_gap_mm", "number", 0.0, "c, gap between neighbouring rollers along their centre line",
          ge=0, le=MAX_LENGTH_MM, example=6.0),
    Field("roller_length_mm", "number", REQUIRED, "l, roller working length", ge=MIN_LENGTH_MM,
          le=MAX_LENGTH_MM, example=20.0),
    Field("rollers", "integer", "auto", "N, or \"auto\" = the largest N <= N* of the scheme's parity",
          choices=("auto",), ge=3, le=MAX_ROLLERS),
    Field("correct", "string", "outer", "parameter corrected to close the chain (the paper: outer)",
          choices=("outer", "inner", "gap")),
    Field("scheme", "number", "A", "chain phase: a symmetric scheme, the polar angle theta_0 of roller 0 "
          "in degrees, or \"cycle\" = envelope over every placement", choices=SCHEMES + ("cycle",)),
), doc="Raceways, eccentricity and the roller chain")

LOAD = Table("load", (
    Field("radial_N", "number", REQUIRED, "Q, radial load on the leading inner ring", gt=0, example=10000.0),
    Field("direction_deg", "number", 0.0, "direction of Q from the line of centres (0 = toward the narrowest "
          "gap, counter-clockwise), or \"envelope\" = every direction", choices=("envelope",)),
    Field("clearance_mm", "number", 0.0, "radial clearance s, total free travel of the inner ring (< 0: preload); "
          "|s| < the smallest roller radius"),
), doc="Load on the inner ring")

MATERIAL = Table("material", (
    Field("roller_E_MPa", "number", 2.1e5, "Young's modulus of the rollers", ge=MIN_E_MPA, le=MAX_E_MPA),
    Field("roller_poisson", "number", 0.3, "Poisson's ratio of the rollers", gt=0, lt=0.5),
    Field("ring_E_MPa", "number", 2.1e5, "Young's modulus of both rings", ge=MIN_E_MPA, le=MAX_E_MPA),
    Field("ring_poisson", "number", 0.3, "Poisson's ratio of both rings", gt=0, lt=0.5),
    Field("inner_ring_E_MPa", "number", None, "override ring_E_MPa for the inner ring", ge=MIN_E_MPA, le=MAX_E_MPA,
          default_doc="ring_E_MPa"),
    Field("inner_ring_poisson", "number", None, "override ring_poisson for the inner ring", gt=0, lt=0.5,
          default_doc="ring_poisson"),
    Field("outer_ring_E_MPa", "number", None, "override ring_E_MPa for the outer ring", ge=MIN_E_MPA, le=MAX_E_MPA,
          default_doc="ring_E_MPa"),
    Field("outer_ring_poisson", "number", None, "override ring_poisson for the outer ring", gt=0, lt=0.5,
          default_doc="ring_poisson"),
    Field("allowable_stress_MPa", "number", None, "[sigma_H], allowable contact stress", gt=0,
          default_doc="4000 (ISO 76 static reference, not an endurance allowable)"),
), doc="Elastic constants and the allowable contact stress")

KEYS = {"outer": "geometry.outer_raceway_radius_mm", "inner": "geometry.inner_raceway_radius_mm",
        "eccentricity": "geometry.eccentricity_mm", "gap": "geometry.roller_gap_mm",
        "rollers": "geometry.rollers"}
CORRECTED_FIELD = {"outer": "outer_raceway_radius_mm", "inner": "inner_raceway_radius_mm", "gap": "roller_gap_mm"}


def _geometry(design):
    return (design["geometry.outer_raceway_radius_mm"], design["geometry.inner_raceway_radius_mm"],
            design["geometry.eccentricity_mm"], design["geometry.roller_gap_mm"])


def _parity(scheme):
    from ..zstk import SCHEME_PARITY

    return SCHEME_PARITY.get(scheme) if isinstance(scheme, str) else None


def _closed_chain(design, problems=None):
    """The corrected chain, or the problems that prevent it (list of (dotted key, message))."""
    from .. import zstk as z

    found = []
    r_h, r_b, e, c = _geometry(design)
    for key, msg in z.geometry_problems(r_h, r_b, e, c):
        found.append((KEYS[key], msg))
    scheme, rollers = design["geometry.scheme"], design["geometry.rollers"]
    parity = _parity(scheme)
    if rollers != "auto" and parity is not None and rollers % 2 != parity:
        found.append(("geometry.rollers", (f"= {rollers}: geometry.scheme = \"{scheme}\" needs an "
                      f"{'even' if parity == 0 else 'odd'} number of rollers (A, D even; B, C odd); "
                      "change geometry.rollers or geometry.scheme")))
    if found:
        return None, found
    r_min = (r_h - r_b - e) / 2
    s_cl = design["load.clearance_mm"]
    if not abs(s_cl) < r_min:
        found.append(("load.clearance_mm", (f"= {s_cl:g}: |clearance| must be < the smallest roller radius "
                      f"(R_H − R_B − e)/2 = {r_min:.6g} mm (the load model assumes small displacements)")))
        return None, found
    correct = design["geometry.correct"]
    n_star = float(z.fractional_roller_number(r_h, r_b, e, c))
    if rollers == "auto":
        n = z.auto_roller_number(n_star, parity)
        if n < 3:
            which = f" of the parity of scheme \"{scheme}\"" if parity is not None else ""
            return None, [("geometry.rollers", (f"= \"auto\": no N ≥ 3{which} lies below N* = {n_star:.6g} "
                           "(the raceways leave room for fewer than 3 rollers; reduce the gap or the "
                           "eccentricity, or give geometry.rollers explicitly)"))]
    else:
        n = int(rollers)
    if n > MAX_ROLLERS:
        return None, [("geometry.rollers", (f"= \"auto\": N = {n} (N* = {n_star:.6g}) exceeds gearcalc's range of "
                       f"{MAX_ROLLERS} rollers (the rollers are tiny compared with the raceways; check the radii, "
                       "the eccentricity and the gap)"))]
    chain = z.close_chain(r_h, r_b, e, c, n, correct)
    for key, msg in z.chain_problems(chain):
        found.append((KEYS[key], msg))
    return (None if found else chain), found


def check(design, problems) -> None:
    """Cross-key checks: raceways, eccentricity, gap, parity, N and the corrected geometry (spec §3.3, §9)."""
    _, found = _closed_chain(design)
    for key, msg in found:
        problems.error(key, msg)


def _materials(design):
    from .. import zstk as z

    ring_e, ring_nu = design["material.ring_E_MPa"], design["material.ring_poisson"]

    def pick(key, default):
        v = design.get(key)
        return default if v is None else v

    return z.Materials.from_elastic(
        design["geometry.roller_length_mm"], design["material.roller_E_MPa"], design["material.roller_poisson"],
        pick("material.inner_ring_E_MPa", ring_e), pick("material.inner_ring_poisson", ring_nu),
        pick("material.outer_ring_E_MPa", ring_e), pick("material.outer_ring_poisson", ring_nu))


def _deg(x):
    from ..units import rad_to_deg

    return float(rad_to_deg(x))


def _wrap_deg(x_rad):
    """Degrees in (-180, 180]; round-off just above -180 is shown as 180."""
    from .. import zstk as z

    d = _deg(z.wrap_angle(x_rad))
    return 180.0 if d <= -180.0 + 1e-9 else d + 0.0  # no -0.0


def _note_cap(sweep, what: str, per: str, warnings: list) -> None:
    """Warn when a phase or direction sweep hit its grid cap before meeting the tolerance."""
    if sweep.capped:
        warnings.append(f"{what} sweep stopped at the cap of {GRID_CAP} points per {per} with error "
                        f"{sweep.err:.3g} MPa above the target")


def compute(design, options: Options) -> Result:
    """Close the chain, place it, share the load, and check the Hertz stresses (spec zstk.md)."""
    import numpy as np

    from .. import zstk as z
    from ..roots import minimize_golden
    from ..units import UM_PER_MM, deg_to_rad

    model = options.model or "equilibrium"
    chain, found = _closed_chain(design)
    if chain is None:
        key, msg = found[0]
        raise DesignError(key, msg)
    mats = _materials(design)
    load = float(design["load.radial_N"])
    clearance = float(design["load.clearance_mm"])
    scheme = design["geometry.scheme"]
    direction = design["load.direction_deg"]
    envelope = direction == "envelope"
    cycle = scheme == "cycle"
    fixed = model == "fixed-direction"
    ref = model == "reference"
    tol = options.tol
    grid_factor = 8 if ref else 1
    refine_rtol = 1e-12 if ref else 0.01 * math.sqrt(tol)  # see zstk.maximise_periodic
    n, q = chain.n, chain.limiting_ratio
    warnings: list[str] = []

    def sigma_max(phase, gamma):
        """sigma_max of each (phase, direction) configuration, evaluated in chunks (bounded memory)."""
        phase, gamma = np.broadcast_arrays(np.asarray(phase, dtype=float), np.asarray(gamma, dtype=float))
        flat_p, flat_g = phase.ravel(), gamma.ravel()
        out = np.empty(flat_p.shape)
        step = max(1, CHUNK_ELEMENTS // n)
        for k in range(0, flat_p.size, step):
            st = z.evaluate(chain, mats, z.roller_angles(flat_p[k:k + step], n, q), flat_g[k:k + step], load,
                            clearance, fixed_direction=fixed)
            out[k:k + step] = z.critical(st)[0]
        return out.reshape(phase.shape)

    def direction_envelope(phase, gamma_grid, candidates=3):
        """Max over directions for each phase (vectorised over phases): the direction grid is ranked with
        the fixed-direction closed form (10x cheaper than the root solve), and the best ``candidates``
        grid points of each phase are refined by golden section on the model's own loads."""
        step = 2 * np.pi / gamma_grid.size
        chunk = max(1, CHUNK_ELEMENTS // (gamma_grid.size * n))
        flat = np.ravel(phase)
        res = np.empty(flat.shape)
        for s in range(0, flat.size, chunk):
            ph = flat[s:s + chunk]
            st = z.evaluate(chain, mats, z.roller_angles(ph[:, None], n, q), gamma_grid[None, :], load, clearance,
                            fixed_direction=True)
            screen = z.critical(st)[0]
            top = np.argsort(-screen, axis=-1)[:, :candidates]
            g0 = gamma_grid[top]
            php = np.broadcast_to(ph[:, None], g0.shape)
            at_grid = sigma_max(php, g0)
            r = minimize_golden(lambda g, php=php: -sigma_max(php, g), g0 - step, g0 + step,
                                rtol=refine_rtol, xtol=refine_rtol * 2 * np.pi)
            res[s:s + chunk] = np.max(np.maximum(-r.fun, at_grid), axis=-1)
        return res.reshape(np.shape(phase))

    # ---- the phase
    sweep_fields = {"phase_samples": None, "phase_step_deg": None,
                    "direction_samples": None, "direction_step_deg": None}
    err_sweep = 0.0
    pitch = 2 * np.pi / n
    if cycle:
        if envelope:
            # inner direction grid of the nested sweep: >= 16 points per roller pitch (each roller's stress
            # is one smooth bump over the directions), refined by golden section; the final value comes
            # from the full direction sweep (720 per turn, doubled to --tol) at the critical phase below
            m_inner = min(GRID_DIRECTION, max(GRID_DIRECTION // 4, 16 * n)) * grid_factor
            gamma_grid = 2 * np.pi * np.arange(m_inner) / m_inner
            sw = z.maximise_periodic(lambda ph: direction_envelope(ph, gamma_grid), 0.0, pitch,
                                     GRID_PHASE * grid_factor, tol, GRID_CAP, refine_rtol)
        else:
            gamma0 = float(deg_to_rad(math.remainder(direction, 360.0)))
            sw = z.maximise_periodic(lambda ph: sigma_max(ph, gamma0), 0.0, pitch,
                                     GRID_PHASE * grid_factor, tol, GRID_CAP, refine_rtol)
        phase = sw.x
        err_sweep += sw.err
        sweep_fields["phase_samples"] = sw.samples
        sweep_fields["phase_step_deg"] = _deg(sw.step)
        _note_cap(sw, "phase", "pitch", warnings)
    elif isinstance(scheme, str):
        phase = z.scheme_phase(scheme, n)
    else:
        phase = float(z.phi_of_theta(deg_to_rad(math.remainder(float(scheme), 360.0)), q))
    theta = z.roller_angles(phase, n, q)
    theta0 = float(theta[0])

    # ---- the direction
    if envelope:
        sw = z.maximise_periodic(lambda g: sigma_max(phase, g), 0.0, 2 * np.pi, GRID_DIRECTION * grid_factor,
                                 tol, GRID_CAP, refine_rtol)
        gamma = sw.x
        err_sweep += sw.err
        sweep_fields["direction_samples"] = sw.samples
        sweep_fields["direction_step_deg"] = _deg(sw.step)
        _note_cap(sw, "direction", "turn", warnings)
        sweep_value = sw.value
    else:
        gamma = float(deg_to_rad(math.remainder(direction, 360.0)))
        sweep_value = None

    symmetric = False
    if not (cycle or envelope):
        on_line = abs(math.sin(gamma)) < 1e-15  # gamma = 0 or 180 degrees
        if isinstance(scheme, str) and on_line:
            symmetric = True
        elif chain.eccentricity == 0.0:
            k = (gamma - theta0) / (math.pi / n)
            symmetric = abs(k - round(k)) < 1e-12
    state = z.evaluate(chain, mats, theta, gamma, load, clearance, symmetric=symmetric, fixed_direction=fixed)
    crit = z.critical(state)
    smax, i_crit, contact = float(crit[0]), int(crit[1]), int(crit[2])
    if sweep_value is not None and sweep_value > smax:
        smax = sweep_value
    sol = state.loads
    f_sum = float(np.sum(sol.force))
    solver_residual = float(sol.residual) / (load + f_sum)
    transverse_residual = float(sol.transverse) / load
    if fixed:
        along = math.sqrt(max(float(sol.residual) ** 2 - float(sol.transverse) ** 2, 0.0))
        solver_residual = along / (load + f_sum)
    if not bool(np.all(sol.converged)):
        why = (" (round-off floor: with clearance and so small a load the contact deflections approach the "
               "round-off of the roller positions, about 1e-16·clearance)" if clearance > 0 else "")
        warnings.append(f"the load solve reached a relative residual of {solver_residual:.3g}, not the "
                        f"target 1e-12·(Q + ΣF){why}; sigma_max_err_MPa includes it")
    if fixed and transverse_residual > 1e-9:
        warnings.append(f"fixed-direction model: the rollers leave an unbalanced transverse force of "
                        f"{100 * transverse_residual:.3g} % of Q (use the default equilibrium model)")
    f_crit = float((state.force_inner if contact == 0 else state.force_outer)[i_crit])
    closed_form = symmetric and clearance == 0.0 and not (cycle or envelope)
    if closed_form:
        err_solver = 0.0
    else:
        resid_abs = float(sol.residual) if not fixed else solver_residual * (load + f_sum)
        err_solver = 0.5 * smax * resid_abs / f_crit if f_crit > 0 else 0.0
    sigma_err = err_sweep + err_solver

    # ---- strength check
    allowable = design.get("material.allowable_stress_MPa")
    if allowable is None:
        allowable, source = DEFAULT_ALLOWABLE_MPA, DEFAULT_ALLOWABLE_SOURCE
        warnings.append(f"no material.allowable_stress_MPa: checked against {DEFAULT_ALLOWABLE_MPA:g} MPa "
                        f"({DEFAULT_ALLOWABLE_SOURCE}), a static (permanent-deformation) reference, "
                        "not an endurance allowable")
    else:
        source = "design"
    allowable = float(allowable)
    passed = smax <= allowable
    cname = "inner" if contact == 0 else "outer"
    failed = [] if passed else [
        (f"sigma_max_MPa = {smax:.6g} > allowable_stress_MPa = {allowable:.6g} ({cname} contact of roller "
        f"{i_crit}, r = {float(state.radius[i_crit]):.6g} mm)")]

    # ---- displacement (spec §11.3)
    delta, alpha = float(sol.approach), float(sol.alpha)
    if delta < 0:
        delta, alpha = -delta, alpha + math.pi
    alpha_deg = _deg(alpha) % 360.0
    if alpha_deg >= 360.0:
        alpha_deg = 0.0

    # ---- detail
    rows, b_checks = _detail_rows(chain, mats, state, load, clearance, fixed, envelope, refine_rtol,
                                  sweep_fields["direction_samples"])
    if any(b_checks):
        worst = max(b_checks)
        warnings.append(f"a loaded contact has b/rho = {worst:.3g} > {B_OVER_RHO_LIMIT}: Hertz's small-contact "
                        "assumption is doubtful")

    stepping = None
    if ref:
        _, res = z.step_chain(theta0, n, chain.outer_radius, chain.inner_radius, chain.eccentricity, chain.gap)
        stepping = float(res)
        if stepping > 1e-9:
            warnings.append(f"explicit stepping closes with a residual of {stepping:.3g} mm (> 1e-9 mm)")

    r_all = state.radius
    summary = {
        "name": design.name,
        "model": model,
        "scheme": scheme if isinstance(scheme, str) else "angle",
        "theta0_deg": _wrap_deg(theta0),
        "N": n,
        "N_star": chain.n_star,
        "N_admissible_max": _n_admissible_max(chain),
        "correction": chain.correct,
        "outer_raceway_radius_mm": chain.outer_radius,
        "inner_raceway_radius_mm": chain.inner_radius,
        "roller_gap_mm": chain.gap,
        "nominal_mm": chain.nominal,
        "correction_mm": chain.corrected - chain.nominal,
        "r_min_mm": (chain.outer_radius - chain.inner_radius - chain.eccentricity) / 2,
        "r_max_mm": (chain.outer_radius - chain.inner_radius + chain.eccentricity) / 2,
        "sigma_max_MPa": smax,
        "sigma_max_err_MPa": sigma_err,
        "sigma_max_contact": cname,
        "sigma_max_roller": i_crit,
        "sigma_max_angle_deg": _wrap_deg(float(state.theta[i_crit])),
        "sigma_max_roller_radius_mm": float(r_all[i_crit]),
        "sigma_max_load_direction_deg": _wrap_deg(gamma),
        "allowable_stress_MPa": allowable,
        "allowable_stress_source": source,
        "safety_factor": allowable / smax if smax > 0 else None,
        "pass": passed,
        "approach_um": delta * UM_PER_MM,
        "approach_direction_deg": alpha_deg,
        "clearance_mm": clearance,
        "loaded_rollers": int(np.count_nonzero(state.force_inner > 0)),
        "solver_residual": solver_residual,
        "transverse_residual": transverse_residual,
        **sweep_fields,
        "stepping_residual_mm": stepping,
    }
    return Result(summary=summary, detail={"rollers": rows}, warnings=warnings, failed=failed, model=model)


def _n_admissible_max(chain):
    lim = chain.n_limit
    if not math.isfinite(lim):
        return None
    if chain.correct == "gap":
        return math.floor(lim + 1e-9)
    return int(math.ceil(lim - 1e-9) - 1)


def _detail_rows(chain, mats, state, load, clearance, fixed, envelope, refine_rtol, direction_samples):
    """Per-roller table (with ``envelope``: each roller's maxima over the load directions, refined by
    golden section from the final direction grid); and the b/rho ratios of the loaded contacts."""
    import numpy as np

    from .. import hertz
    from .. import zstk as z
    from ..roots import minimize_golden
    from ..units import UM_PER_MM

    n = chain.n
    theta = state.theta
    fields = ("theta", "radius", "beta", "psi", "force_inner", "force_outer", "rho_inner", "rho_outer",
              "sigma_inner", "sigma_outer")

    def diagonal(gams):
        """Roller i's quantities at load direction gams[i] (chunks of rollers, bounded memory)."""
        out = {f: np.empty(n) for f in fields}
        step_n = max(1, CHUNK_ELEMENTS // n)
        for k in range(0, n, step_n):
            g = gams[k:k + step_n]
            st = z.evaluate(chain, mats, np.broadcast_to(theta, (g.size, n)), g, load, clearance,
                            fixed_direction=fixed)
            rows = np.arange(g.size)
            for f in fields:
                out[f][k:k + g.size] = getattr(st, f)[rows, k + rows]
        return out

    if not envelope:
        d_b = d_h = {f: np.asarray(getattr(state, f)) for f in fields}
        gam_b = gam_h = None
    else:
        m = direction_samples or GRID_DIRECTION
        grid = 2 * np.pi * np.arange(m) / m
        best = np.full((2, n), -1.0)
        arg = np.zeros((2, n), dtype=int)
        step_m = max(1, CHUNK_ELEMENTS // n)
        for k in range(0, m, step_m):  # running per-roller maxima over the direction grid
            g = grid[k:k + step_m]
            st = z.evaluate(chain, mats, np.broadcast_to(theta, (g.size, n)), g, load, clearance,
                            fixed_direction=fixed)
            for c, sig in enumerate((st.sigma_inner, st.sigma_outer)):
                j = np.argmax(sig, axis=0)
                v = sig[j, np.arange(n)]
                better = v > best[c]
                best[c] = np.where(better, v, best[c])
                arg[c] = np.where(better, k + j, arg[c])
        centre = np.concatenate([grid[arg[0]], grid[arg[1]]])
        if n <= REFINE_ROWS_MAX_N:
            step = 2 * np.pi / m
            pick = np.concatenate([np.arange(n), np.arange(n)])
            contact = np.repeat([0, 1], n)
            th2 = np.broadcast_to(theta, (2 * n, n))

            def neg(g):
                s = z.evaluate(chain, mats, th2, g, load, clearance, fixed_direction=fixed)
                rows = np.arange(2 * n)
                return -np.where(contact == 0, s.sigma_inner[rows, pick], s.sigma_outer[rows, pick])

            r = minimize_golden(neg, centre - step, centre + step, rtol=refine_rtol, xtol=refine_rtol * 2 * np.pi)
            g_best = np.where(-r.fun >= best.ravel(), r.x, centre)
        else:
            g_best = centre
        gam_b, gam_h = g_best[:n], g_best[n:]
        d_b, d_h = diagonal(gam_b), diagonal(gam_h)

    f_b, f_h = d_b["force_inner"], d_h["force_outer"]
    s_b, s_h = d_b["sigma_inner"], d_h["sigma_outer"]
    rho_b, rho_h = d_b["rho_inner"], d_h["rho_outer"]
    b_b = hertz.semi_width(f_b, mats.length, rho_b, mats.e_star_inner)
    b_h = hertz.semi_width(f_h, mats.length, rho_h, mats.e_star_outer)
    deg = np.degrees
    cols = {
        "i": np.arange(n),
        "theta_deg": deg(z.wrap_angle(d_b["theta"])),
        "r_mm": d_b["radius"],
        "psi_deg": deg(d_b["psi"]),
        "beta_deg": deg(d_b["beta"]),
        "F_B_N": f_b,
        "F_H_N": f_h,
        "rho_B_mm": rho_b,
        "rho_H_mm": rho_h,
        "sigma_B_MPa": s_b,
        "sigma_H_MPa": s_h,
        "b_B_mm": b_b,
        "b_H_mm": b_h,
        "tau_max_B_MPa": hertz.max_subsurface_shear(s_b),
        "tau_max_H_MPa": hertz.max_subsurface_shear(s_h),
    }
    if envelope:
        cols["gamma_B_deg"] = deg(z.wrap_angle(gam_b))
        cols["gamma_H_deg"] = deg(z.wrap_angle(gam_h))
    else:
        nb = np.asarray(state.normal_angle)
        approach = float(state.loads.approach) * np.cos(nb - float(state.loads.alpha)) - 0.5 * clearance
        cols["delta_um"] = approach * UM_PER_MM
    lists = {k: np.asarray(v).tolist() for k, v in cols.items()}
    rows = [{k: lists[k][j] for k in cols} for j in range(n)]
    ratios = []
    for f, b, rho in ((f_b, b_b, rho_b), (f_h, b_h, rho_h)):
        bad = (f > 0) & (b > B_OVER_RHO_LIMIT * rho)
        if np.any(bad):
            ratios.append(float(np.max((b / rho)[bad])))
    return rows, ratios


def plot(records, path: str) -> None:
    """The paper's Fig. 2 for each design (sigma_iB and sigma_iH against the roller radius r_i), and a
    drawing of the chain (raceways, rollers, load direction, critical roller) beside it; up to 4 designs."""
    import numpy as np

    from ..plot import _pyplot, save

    plt = _pyplot()
    recs = records[:4]
    fig, axes = plt.subplots(len(recs), 2, figsize=(12, 5 * len(recs)), squeeze=False,
                             gridspec_kw={"width_ratios": [1.4, 1]})
    for (ax, ax2), rec in zip(axes, recs):
        s, rows = rec.result.summary, rec.result.detail["rollers"]
        r = np.array([row["r_mm"] for row in rows])
        order = np.argsort(r, kind="stable")
        for key, label, mark in (("sigma_B_MPa", "inner contact σ_iB", "o-"),
                                 ("sigma_H_MPa", "outer contact σ_iH", "s--")):
            ax.plot(r[order], np.array([row[key] for row in rows])[order], mark, ms=4, label=label)
        if s["allowable_stress_MPa"] <= 1.5 * s["sigma_max_MPa"]:  # else it would squash the curves
            ax.axhline(s["allowable_stress_MPa"], color="r", lw=0.8, ls=":", label="[σ_H]")
        ax.set_xlabel("roller radius r_i [mm]")
        ax.set_ylabel("Hertz stress σ [MPa]")
        env = " (envelope over load directions)" if "gamma_B_deg" in rows[0] else ""
        ax.set_title(f"{rec.name}: N = {s['N']}, scheme {s['scheme']}{env}\n"
                     f"σ_max = {s['sigma_max_MPa']:.4g} MPa, roller {s['sigma_max_roller']} ({s['sigma_max_contact']})",
                     fontsize=9)
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8)
        r_h, r_b = s["outer_raceway_radius_mm"], s["inner_raceway_radius_mm"]
        e = rec.design["geometry"]["eccentricity_mm"]
        t = np.linspace(0, 2 * np.pi, 721)
        ax2.plot(r_h * np.cos(t), r_h * np.sin(t), "k-", lw=1.2)
        ax2.plot(e + r_b * np.cos(t), r_b * np.sin(t), "k-", lw=1.2)
        th = np.radians([row["theta_deg"] for row in rows])
        for k, (ti, ri) in enumerate(zip(th, r)):
            cx, cy = (r_h - ri) * np.cos(ti), (r_h - ri) * np.sin(ti)
            crit = k == s["sigma_max_roller"]
            ax2.fill(cx + ri * np.cos(t), cy + ri * np.sin(t), color="tab:red" if crit else "tab:blue", alpha=0.35)
            ax2.text(cx, cy, str(k), ha="center", va="center", fontsize=7)
        g = np.radians(s["sigma_max_load_direction_deg"])
        ax2.annotate("", xy=(e + 0.8 * r_b * np.cos(g), 0.8 * r_b * np.sin(g)), xytext=(e, 0.0),
                     arrowprops={"arrowstyle": "->", "color": "tab:red", "lw": 1.5})
        ax2.set_aspect("equal")
        ax2.set_title("chain (narrowest gap at +x); arrow: load on the inner ring", fontsize=9)
        ax2.axis("off")
    save(fig, path)


CALCULATOR = Calculator(
    kind="zstk",
    title="closed rolling-body mechanism (eccentric ZSTK, leading inner ring)",
    tables=(GEOMETRY, LOAD, MATERIAL),
    compute=compute,
    check=check,
    models=MODELS,
    plot=plot,
    header=("Merko et al. (seed 003): rollers of different diameters between an outer raceway (R_H) and an\n"
            "eccentric inner raceway (R_B, offset e); one raceway radius (or the gap) is corrected so that an\n"
            "integer number of rollers closes the chain.  Units: mm, N, MPa, degrees."),
)
