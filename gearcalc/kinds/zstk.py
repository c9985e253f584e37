"""``gearcalc zstk``: closed rolling-body mechanism (eccentric ZSTK, leading inner ring).

Schema, and the mapping of design keys to the physics of :mod:`gearcalc.zstk` (validity, closure, loads,
stresses, the "cycle"/"envelope" sweeps) and of its results to the summary fields, detail rows, warnings and
failed checks; :mod:`gearcalc.zstk` is imported inside the functions (this module stays light for
``check``/``new``/``--help``).
Spec: zstk.md; source: Merko et al., seed 003_2d1da402cb0b8488.txt.
"""
from __future__ import annotations

import math

from ..calculator import REQUIRED, Calculator, DesignError, Field, Options, Result, Table
from ..units import MAX_FORCE_N, MAX_LENGTH_MM, MIN_LENGTH_MM

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
MIN_E_MPA, MAX_E_MPA = 1.0, 1e7
ROUNDOFF_RTOL = 1e-12
"""Floor of the error estimate sigma_max_err_MPa, relative to sigma_max (spec §8: the closed-form parts are
accurate to about 1e-12; estimates of 0 or 4 eps fell below the actual difference to an independent solver)."""
MIN_FORCE_N = 1e-6
"""Smallest radial load (1 uN): far below it the contact deflections approach the round-off of the roller
positions (~1e-16 x clearance) and the load solve cannot balance Q (5e-324 N gave solver_residual = 1 and
pass = true; with clearance, 1e-100 N raised BracketError); at 1e-6 N the worked example balances Q to 4e-8
with a clearance of 0.01 mm (included in sigma_max_err_MPa)."""
SWEEP_WORK_MAX = 6_000_000
"""Cost budget of a "cycle" and/or "envelope" design, in roller-configurations of its first sweep grid
(:func:`gearcalc.zstk.sweep_work`): ~2-7 us each with the refinements (N = 2000, "cycle" + "envelope": 1.7e6, 4 s;
N = 248 "cycle" + "envelope" at --model reference: 1.2e7, ~25 s, refused); the sweeps' memory is bounded by
CHUNK_ELEMENTS."""
MAX_ROLLERS = 2000       # gearcalc's range (the spec asks N > 200 to work); keeps sweeps in memory
CHUNK_ELEMENTS = 1_000_000  # roller-configurations evaluated at once in the sweeps
REFINE_ROWS_MAX_N = 200  # above this the per-roller envelope rows are grid maxima (O(N²) refinement)
SEPARATOR_MESSAGE = ("= false: rollers without a separator are not modelled. The rollers' tangential reactions "
                     "F_iB·sin(beta_i) would then be carried by roller-to-roller contacts (possible only with "
                     "roller_gap_mm = 0), a statically indeterminate closed chain that needs every roller's own "
                     "displacement; gearcalc models the separator only (zstk.md §5.5). Use separator = true "
                     "(roller_gap_mm may be 0)")
DEFAULT_ALLOWABLE_WARNING = (f"no material.allowable_stress_MPa: checked against {DEFAULT_ALLOWABLE_MPA:g} MPa "
                             f"({DEFAULT_ALLOWABLE_SOURCE}), a static (permanent-deformation) reference, "
                             "not an endurance allowable")

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
    Field("separator", "bool", True, "a separator holds each roller in place (the model); false (rollers "
          "touching without one) is refused: roller-to-roller contact is not modelled"),
), doc="Raceways, eccentricity and the roller chain")

LOAD = Table("load", (
    Field("radial_N", "number", REQUIRED, f"Q, radial load on the leading inner ring (>= {MIN_FORCE_N:g} N: "
          "smaller loads are below the round-off of the load solve)", ge=MIN_FORCE_N, le=MAX_FORCE_N,
          example=10000.0),
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

TABLES = (GEOMETRY, LOAD, MATERIAL)

KEYS = {"outer": "geometry.outer_raceway_radius_mm", "inner": "geometry.inner_raceway_radius_mm",
        "eccentricity": "geometry.eccentricity_mm", "gap": "geometry.roller_gap_mm",
        "rollers": "geometry.rollers", "clearance": "load.clearance_mm"}

def check(design, problems) -> None:
    """Cross-key checks: raceways, eccentricity, gap, parity, N and the corrected geometry (spec §3.3, §9:
    :func:`gearcalc.zstk.check_designs`, the rules compute, batch and sweep use); the cost budget of the phase
    and direction sweeps (:func:`cost_problem`, at the default model)."""
    p = _prepare(_design_columns([design]), 1)
    for key, msg in _problems(p, 0):
        problems.error(key, msg)
    if p.valid[0]:
        problem = cost_problem(design, int(p.n[0]), "equilibrium")
        if problem is not None:
            problems.error(*problem)


def _problems(p, k: int) -> list:
    """(dotted key, message) of each problem of design k of ``p`` (empty when it is valid)."""
    def at(key):
        return p.cols[key][k] if isinstance(p.cols[key], list) else p.cols[key]

    out = [] if p.separator[k] else [("geometry.separator", SEPARATOR_MESSAGE)]
    return out + [(KEYS[q], msg) for q, msg in p.validity.problems(k, at("geometry.scheme"), at("geometry.rollers"))]


def _grid(model: str):
    """The sweep grids of a model level (the constants above, read at call time)."""
    from .. import zstk as z

    return z.SweepGrid(GRID_PHASE, GRID_DIRECTION, GRID_CAP, CHUNK_ELEMENTS, REFINE_ROWS_MAX_N,
                       8 if model == "reference" else 1)


def cost_problem(design, n: int, model: str):
    """(key, message) when the design's sweeps would exceed :data:`SWEEP_WORK_MAX`, else None (check and
    compute share it; check assumes the default model)."""
    from .. import zstk as z

    cycle, envelope = design["geometry.scheme"] == "cycle", design["load.direction_deg"] == "envelope"
    work = z.sweep_work(n, cycle, envelope, _grid(model))
    if work <= SWEEP_WORK_MAX:
        return None
    what = " + ".join(w for w, on in (('geometry.scheme = "cycle"', cycle),
                                       ('load.direction_deg = "envelope"', envelope)) if on)
    rollers = design["geometry.rollers"]
    shown = f'"{rollers}"' if isinstance(rollers, str) else rollers
    return ("geometry.rollers", f"= {shown}: N = {n} rollers with {what}"
                                f"{' at --model reference' if model == 'reference' else ''} need {work:.3g} "
                                f"roller-configurations, over the budget of {SWEEP_WORK_MAX:.3g} (~10 s): fewer "
                                "rollers, or one sweep at a time (a fixed scheme or a fixed load direction)")


def _deg(x):
    from ..units import rad_to_deg

    return rad_to_deg(x)


def _wrap_deg(x_rad):
    """Degrees in (-180, 180] (arrays or floats); round-off just above -180 is shown as 180."""
    import numpy as np

    from .. import zstk as z

    d = _deg(z.wrap_angle(x_rad))
    return np.where(d <= -180.0 + 1e-9, 180.0, d + 0.0)  # + 0.0: no -0.0


# ----------------------------------------------------------------------------- stacked designs
# Designs (of a batch, or the points of a sweep) are held column-wise: ``cols[dotted key]`` is one
# resolved value shared by every design or a list with one value per design.  They are prepared
# together (closure, correction, phase, direction, materials as arrays over designs), grouped by
# the roller count N, and each group is solved as one stack of arrays (G, N) (spec zstk.md §8).

def _design_columns(designs) -> dict:
    """The resolved values of validated designs, one list per dotted key."""
    return {f"{t.name}.{f.name}": [d.values[t.name][f.name] for d in designs] for t in TABLES for f in t.fields}


class _Prepared:
    """Arrays of shape (P,) describing P designs up to the load solve (see :func:`_prepare`)."""


def _prepare(cols: dict, size: int) -> _Prepared:
    """Chain closure and correction, validity, phase, load direction and materials of ``size`` designs.

    Validity is :func:`gearcalc.zstk.check_designs` (the one rule set of check, compute, batch and sweep).
    """
    import numpy as np

    from .. import zstk as z
    from ..units import deg_to_rad

    def num(key):
        v = cols[key]
        return np.asarray(v, dtype=float) if isinstance(v, list) else np.full(size, float(v))

    def per(key, fn, dtype=bool):
        """fn of each design's value (once when the value is shared by every design)."""
        v = cols[key]
        if isinstance(v, list):
            return np.array([fn(x) for x in v], dtype=dtype)
        return np.full(size, fn(v), dtype=dtype)

    def num_or(key, fallback):
        v = cols[key]
        if v is None:
            return fallback
        if not isinstance(v, list):
            return np.full(size, float(v))
        return np.where(per(key, lambda x: x is not None), per(key, lambda x: 0.0 if x is None else x, float),
                        fallback)

    p = _Prepared()
    p.size, p.cols = size, cols
    r_h, r_b, e, c = (num(KEYS[k]) for k in ("outer", "inner", "eccentricity", "gap"))
    n_given = per("geometry.rollers", lambda r: 0 if r == "auto" else r, np.int64)
    p.letter = per("geometry.scheme", lambda s: isinstance(s, str) and s in SCHEMES)
    p.cycle = per("geometry.scheme", lambda s: s == "cycle")
    p.scheme = per("geometry.scheme", lambda s: s if isinstance(s, str) else "angle", object)
    parity = per("geometry.scheme", lambda s: z.SCHEME_PARITY.get(s, -1) if isinstance(s, str) else -1, np.int64)
    mid_gap = per("geometry.scheme", lambda s: s in ("C", "D"))
    theta_deg = per("geometry.scheme", lambda s: 0.0 if isinstance(s, str) else s, float)
    clearance = num("load.clearance_mm")
    p.validity = z.check_designs(r_h, r_b, e, c, n_given, parity, clearance, per("geometry.correct", str, object),
                                 MAX_ROLLERS)
    p.separator = per("geometry.separator", bool)
    p.valid, p.n, p.chain = p.validity.valid & p.separator, p.validity.n, p.validity.chain
    p.q = z.limiting_ratios(p.chain, p.valid)
    p.phase = z.chain_phases(p.n, p.q, p.letter, mid_gap, ~p.letter & ~p.cycle,
                             deg_to_rad(z.remainder_360(theta_deg)))
    p.envelope = per("load.direction_deg", lambda v: v == "envelope")
    p.gamma = deg_to_rad(z.remainder_360(per("load.direction_deg", lambda v: 0.0 if isinstance(v, str) else v,
                                            float)))
    p.load, p.clearance = num("load.radial_N"), clearance
    ring_e, ring_nu = num("material.ring_E_MPa"), num("material.ring_poisson")
    p.mats = z.Materials.from_elastic(
        num("geometry.roller_length_mm"), num("material.roller_E_MPa"), num("material.roller_poisson"),
        num_or("material.inner_ring_E_MPa", ring_e), num_or("material.inner_ring_poisson", ring_nu),
        num_or("material.outer_ring_E_MPa", ring_e), num_or("material.outer_ring_poisson", ring_nu))
    p.allowable_default = per("material.allowable_stress_MPa", lambda v: v is None)
    p.allowable = np.where(p.allowable_default, DEFAULT_ALLOWABLE_MPA,
                           per("material.allowable_stress_MPa", lambda v: 0.0 if v is None else v, float))
    return p


def _solve_stack(p: _Prepared, idx, options: Options, names, detail: bool):
    """Solve the single-position designs ``idx`` of ``p`` (valid, not "cycle", not "envelope").

    ``names``: the name of every design of ``p`` (a list indexed like ``p``), or one name for all.

    Groups them by N, solves each group as one stack (G, N), and returns the summary columns
    (dict field -> list, in ``idx`` order) and, with ``detail``, per design (warnings, failed, rows).
    """
    import numpy as np

    from .. import zstk as z
    from ..arrays import unique_sorted

    model = options.model or "equilibrium"
    fixed = model == "fixed-direction"
    idx = np.asarray(idx)
    ns = p.n[idx]
    parts = []
    for nn in unique_sorted(ns):
        sub = idx[ns == nn]
        chain, mats = z.take(p.chain, sub), z.take(p.mats, sub)
        state, symmetric, stepping = z.solve_placements(chain, mats, p.phase[sub], p.q[sub], p.gamma[sub], p.load[sub],
                                                        p.clearance[sub], p.letter[sub], fixed, model == "reference")
        out = _finish([names[i] for i in sub] if isinstance(names, list) else names, model, p.scheme[sub], chain,
                      mats, state, p.gamma[sub], p.load[sub], p.clearance[sub], symmetric,
                      (p.allowable[sub], p.allowable_default[sub]), fixed, stepping=stepping, detail=detail)
        parts.append((sub, out))
    if len(parts) == 1:
        return parts[0][1]
    order = np.concatenate([sub for sub, _ in parts])
    back = np.argsort(_positions(idx, order), kind="stable")
    cols = {key: _gather([out[0][key] for _, out in parts], back) for key in parts[0][1][0]}
    extra = None
    if detail:
        extra = _gather([out[1] for _, out in parts], back)
    return cols, extra


def _positions(idx, order):
    """Position in ``idx`` of every element of ``order`` (a permutation of idx)."""
    import numpy as np

    where = np.empty(int(idx.max()) + 1, dtype=np.int64)
    where[idx] = np.arange(idx.size)
    return where[order]


def _gather(lists, back):
    """Concatenate lists and reorder them by the permutation ``back``."""
    import operator

    flat = [v for part in lists for v in part]
    if len(flat) == 1:
        return flat
    return list(operator.itemgetter(*back.tolist())(flat))


def _finish(names, model, schemes, chain, mats, state, gamma, load, clearance, symmetric, allowable, fixed,
            stepping=None, detail=True, sweep=None, capacity=None):
    """Summary columns of G stacked designs from their solved state (arrays (G, N) and (G,)).

    With ``detail``, also per design: (warnings, failed, detail rows).  ``sweep`` (a "cycle" or "envelope"
    design, G = 1): (value, err, fields, envelope rows (d_B, d_H, gamma_B, gamma_H) or None, notes).
    ``capacity``: the allowable radial load (:class:`gearcalc.zstk.AllowableLoad`) of a sweeping design
    (computed here for single positions).
    """
    import numpy as np

    from .. import zstk as z
    from ..units import UM_PER_MM

    value, err, fields, env, notes = sweep or (None, None, {}, None, ())
    sm = z.summarise(state, load, clearance, symmetric, fixed, value, err, ROUNDOFF_RTOL)
    size, n = state.radius.shape
    allow, default_allowable = allowable
    if capacity is None:
        capacity = z.allowable_load(chain, mats, state.theta, gamma, load, clearance, sm.sigma_max, sm.sigma_err,
                                    allow, symmetric, fixed)
    tau, tau_depth = z.critical_shear(state, sm, mats)
    d_b = env[0] if env is not None else state
    get_b = (lambda f: d_b[f]) if isinstance(d_b, dict) else (lambda f: getattr(d_b, f))
    separator_max = np.max(z.separator_forces(get_b("force_inner"), get_b("beta")), axis=-1)
    passed = sm.sigma_max <= allow
    cname = ["inner" if c == 0 else "outer" for c in sm.contact.tolist()]
    alpha_deg = np.mod(_deg(sm.approach_direction), 360.0)
    safety = z.safety_factor(sm.sigma_max, allow).tolist()

    def col(v):
        return z.broadcast(v, (size,)).tolist()

    cols = {
        "name": names if isinstance(names, list) else [names] * size, "model": [model] * size,
        "scheme": schemes.tolist(), "theta0_deg": col(_wrap_deg(state.theta[:, 0])), "N": [n] * size,
        "N_star": col(chain.n_star),
        "N_admissible_max": [z.largest_admissible_n(lim, c) for lim, c in zip(col(chain.n_limit), col(chain.correct))],
        "correction": col(chain.correct), "outer_raceway_radius_mm": col(chain.outer_radius),
        "inner_raceway_radius_mm": col(chain.inner_radius), "roller_gap_mm": col(chain.gap),
        "nominal_mm": col(chain.nominal), "correction_mm": col(chain.corrected - chain.nominal),
        "r_min_mm": col((chain.outer_radius - chain.inner_radius - chain.eccentricity) / 2),
        "r_max_mm": col((chain.outer_radius - chain.inner_radius + chain.eccentricity) / 2),
        "sigma_max_MPa": col(sm.sigma_max), "sigma_max_err_MPa": col(sm.sigma_err), "sigma_max_contact": cname,
        "sigma_max_roller": col(sm.roller), "sigma_max_angle_deg": col(_wrap_deg(sm.theta)),
        "sigma_max_roller_radius_mm": col(sm.radius), "sigma_max_load_direction_deg": col(_wrap_deg(gamma)),
        "tau_max_MPa": col(tau), "tau_max_depth_mm": col(tau_depth), "separator_force_max_N": col(separator_max),
        "allowable_stress_MPa": col(allow),
        "allowable_stress_source": [DEFAULT_ALLOWABLE_SOURCE if d else "design" for d in default_allowable.tolist()],
        "safety_factor": [v if ok else None for v, ok in zip(safety, (sm.sigma_max > 0).tolist())],
        "pass": col(passed), "radial_load_allowable_N": col(capacity.load),
        "radial_load_allowable_err_N": col(capacity.err), "approach_um": col(sm.approach * UM_PER_MM),
        "approach_direction_deg": col(np.where(alpha_deg >= 360.0, 0.0, alpha_deg)), "clearance_mm": col(clearance),
        "loaded_rollers": col(sm.loaded), "solver_residual": col(sm.solver_residual),
        "transverse_residual": col(sm.transverse_residual),
        **{k: [fields.get(k)] * size for k in ("phase_samples", "phase_step_deg", "direction_samples",
                                               "direction_step_deg")},
        "stepping_residual_mm": [None] * size if stepping is None else col(stepping),
    }
    if not detail:
        return cols, None
    rows = _roller_rows(state, mats, clearance, env)
    out = []
    for g in range(size):
        warnings = list(notes) + _warnings(sm, g, clearance[g], fixed, default_allowable[g], rows[1][g], stepping)
        if capacity.preload_exceeds[g]:
            warnings.append(f"the preload alone (load.clearance_mm = {clearance[g]:.6g}) reaches allowable_stress_MPa "
                            f"= {allow[g]:.6g}: radial_load_allowable_N = 0")
        failed = [] if passed[g] else [f"sigma_max_MPa = {sm.sigma_max[g]:.6g} > allowable_stress_MPa = {allow[g]:.6g} "
                                       f"({cname[g]} contact of roller {sm.roller[g]}, r = {sm.radius[g]:.6g} mm)"]
        out.append([warnings, failed, rows[0][g * n:(g + 1) * n]])
    return cols, out


def _roller_rows(state, mats, clearance, env):
    """The per-roller detail rows of G designs (a flat list, G x N) and each design's worst b/rho."""
    import numpy as np

    from .. import zstk as z
    from ..units import UM_PER_MM

    size, n = state.radius.shape
    d_b, d_h, gam_b, gam_h = env if env is not None else (state, state, None, None)
    ct = z.roller_contacts(d_b, d_h, mats)
    get = (lambda f: d_b[f]) if isinstance(d_b, dict) else (lambda f: getattr(d_b, f))
    table = {"i": z.broadcast(np.arange(n), (size, n)), "theta_deg": np.degrees(z.wrap_angle(get("theta"))),
             "r_mm": get("radius"), "psi_deg": np.degrees(get("psi")), "beta_deg": np.degrees(get("beta")),
             "F_B_N": ct.force_inner, "F_H_N": ct.force_outer,
             "F_S_N": z.separator_forces(ct.force_inner, get("beta")), "rho_B_mm": ct.rho_inner,
             "rho_H_mm": ct.rho_outer, "sigma_B_MPa": ct.sigma_inner, "sigma_H_MPa": ct.sigma_outer,
             "b_B_mm": ct.width_inner, "b_H_mm": ct.width_outer, "tau_max_B_MPa": ct.shear_inner,
             "tau_max_H_MPa": ct.shear_outer, "tau_depth_B_mm": ct.shear_depth_inner,
             "tau_depth_H_mm": ct.shear_depth_outer}
    if env is not None:
        table["gamma_B_deg"], table["gamma_H_deg"] = np.degrees(z.wrap_angle(gam_b)), np.degrees(z.wrap_angle(gam_h))
    else:
        table["delta_um"] = z.roller_approach(state, clearance) * UM_PER_MM
    keys = list(table)
    flat = zip(*(z.broadcast(v, (size, n)).ravel().tolist() for v in table.values()))
    return [dict(zip(keys, vals)) for vals in flat], z.worst_width_ratio(ct, B_OVER_RHO_LIMIT)


def _warnings(sm, g, clearance, fixed, default_allowable, worst, stepping) -> list:
    """The warnings of design g (text only where there is something to say)."""
    out = []
    if not sm.converged[g]:
        why = (" (round-off floor: with clearance and so small a load the contact deflections approach the "
               "round-off of the roller positions, about 1e-16·clearance)" if clearance > 0 else "")
        out.append(f"the load solve reached a relative residual of {sm.solver_residual[g]:.3g}, not the "
                   f"target 1e-12·(Q + ΣF){why}; sigma_max_err_MPa includes it")
    if fixed and sm.transverse_residual[g] > 1e-9:
        out.append(f"fixed-direction model: the rollers leave an unbalanced transverse force of "
                   f"{100 * sm.transverse_residual[g]:.3g} % of Q (use the default equilibrium model)")
    if default_allowable:
        out.append(DEFAULT_ALLOWABLE_WARNING)
    if math.isfinite(worst):
        out.append(f"a loaded contact has b/rho = {worst:.3g} > {B_OVER_RHO_LIMIT}: Hertz's "
                   "small-contact assumption is doubtful")
    if stepping is not None and stepping[g] > 1e-9:
        out.append(f"explicit stepping closes with a residual of {stepping[g]:.3g} mm (> 1e-9 mm)")
    return out


def _result(cols, extra, j: int, model: str) -> Result:
    warnings, failed, rows = extra[j]
    return Result(summary={k: v[j] for k, v in cols.items()}, detail={"rollers": rows}, warnings=warnings,
                  failed=failed, model=model)


def _invalid(p, k: int):
    """The DesignError of design k of ``p``, found invalid: its first problem."""
    return DesignError(*_problems(p, k)[0])


def compute(design, options: Options) -> Result:
    """Close the chain, place it, share the load, and check the Hertz stresses (spec zstk.md).

    A single-position design is a stack of one (:func:`_solve_stack`, the same code as ``batch`` and
    ``sweep``); "cycle" and "envelope" designs run their phase and direction sweeps first.
    """
    p = _prepare(_design_columns([design]), 1)
    if not p.valid[0]:
        raise _invalid(p, 0)
    model = options.model or "equilibrium"
    if p.cycle[0] or p.envelope[0]:
        return _compute_sweeping(design, p, options)
    cols, extra = _solve_stack(p, [0], options, [design.name], detail=True)
    return _result(cols, extra, 0, model)


def batch(designs, options: Options) -> list:
    """Many validated designs at once (numpy over designs): one Result (or exception) per design.

    The single-position designs are stacked by roller count N and solved together; "cycle" and
    "envelope" designs (phase and direction sweeps of their own) are computed one by one.
    Identical to :func:`compute` design by design.
    """
    import numpy as np

    model = options.model or "equilibrium"
    out: list = [None] * len(designs)
    if not designs:
        return out
    p = _prepare(_design_columns(designs), len(designs))
    stack = np.flatnonzero(p.valid & ~p.cycle & ~p.envelope)
    for k in np.flatnonzero(~p.valid).tolist():
        out[k] = _invalid(p, k)
    for k in np.flatnonzero(p.valid & (p.cycle | p.envelope)).tolist():
        try:
            out[k] = _compute_sweeping(designs[k], _prepare(_design_columns([designs[k]]), 1), options)
        except Exception as exc:  # returned, not raised (the batch contract)
            out[k] = exc
    if stack.size:
        cols, extra = _solve_stack(p, stack, options, [d.name for d in designs], detail=True)
        for j, k in enumerate(stack.tolist()):
            out[k] = _result(cols, extra, j, model)
    return out


def sweep(base, raw, axes, points, options):
    """The summaries of a whole grid as columns (spec zstk.md §8: designs stacked by N).

    Every grid point is a design of its own (any key may vary, the roller count N included); the
    points are validated element-wise with the arithmetic of :func:`check` and solved in stacks of
    the same N, exactly as :func:`compute` would solve each.  A point that is not a valid design
    raises the DesignError that the point on its own gives, naming the key, the constraint and the
    point.  Grids with "cycle" or "envelope" points return None (evaluated point by point: each
    such point runs adaptive sweeps of its own).
    """
    import numpy as np

    size = len(points)
    cols = {}
    for t in TABLES:
        for f in t.fields:
            key = f"{t.name}.{f.name}"
            cols[key] = base.values[t.name][f.name]
    for key in axes:
        table, _, name = key.partition(".")
        field = next((t.field(name) for t in TABLES if t.name == table), None)
        if field is None:
            return None
        resolved = {}
        for v in axes[key]:
            resolved[_hashable(v)] = check_value(field, v)[0]
        cols[key] = [resolved[_hashable(pt[key])] for pt in points]
    p = _prepare(cols, size)
    if not np.all(p.valid):
        k = int(np.argmax(~p.valid))
        key, msg = _problems(p, k)[0]
        raise DesignError(key, f"{msg} (at {points[k]})")
    if np.any(p.cycle | p.envelope):
        return None
    out, _ = _solve_stack(p, np.arange(size), options, base.name, detail=False)
    return out


def _hashable(v):
    return tuple(v) if isinstance(v, list) else (type(v).__name__, v)


def check_value(field, value):
    from ..design import check_value as cv

    return cv(field, value)


def _compute_sweeping(design, p, options: Options) -> Result:
    """A "cycle" (phase) and/or "envelope" (direction) design: :func:`gearcalc.zstk.critical_placement`
    (spec §8), then the summary."""
    import numpy as np

    from .. import zstk as z
    from ..units import deg_to_rad

    model = options.model or "equilibrium"
    problem = cost_problem(design, int(p.n[0]), model)
    if problem is not None:
        raise DesignError(*problem)
    chain, mats = z.single(p.chain), z.single(p.mats)
    load, clearance = float(p.load[0]), float(p.clearance[0])
    cycle, envelope = design["geometry.scheme"] == "cycle", design["load.direction_deg"] == "envelope"
    fixed, ref = model == "fixed-direction", model == "reference"
    refine_rtol = 1e-12 if ref else 0.01 * math.sqrt(options.tol)  # see zstk.maximise_periodic
    grid = _grid(model)
    gamma0 = None if envelope else float(deg_to_rad(math.remainder(design["load.direction_deg"], 360.0)))
    pl = z.critical_placement(chain, mats, load, clearance, None if cycle else float(p.phase[0]), gamma0,
                              tol=options.tol, refine_rtol=refine_rtol, grid=grid, fixed_direction=fixed)
    notes, fields = [], {}
    for what, per, sw in (("phase", "pitch", pl.phase_sweep), ("direction", "turn", pl.direction_sweep)):
        fields[f"{what}_samples"] = None if sw is None else sw.samples
        fields[f"{what}_step_deg"] = None if sw is None else float(_deg(sw.step))
        if sw is not None and sw.capped:
            notes.append(f"{what} sweep stopped at the cap of {GRID_CAP} points per {per} with error "
                         f"{sw.err:.3g} MPa above the target")
    capacity = z.allowable_load_sweeping(chain, mats, load, clearance, float(p.allowable[0]), pl,
                                         phase=None if cycle else float(p.phase[0]), gamma=gamma0, tol=options.tol,
                                         refine_rtol=refine_rtol, grid=grid, fixed_direction=fixed)
    pl.gamma = pl.gamma if envelope else float(p.gamma[0])  # the design's direction (as a stacked design's)
    _, state, stepping, rows = z.evaluate_placement(chain, mats, pl, load, clearance, refine_rtol=refine_rtol,
                                                    grid=grid, fixed_direction=fixed, stepping=ref, rows=envelope)
    cols, extra = _finish([design.name], model, p.scheme[:1], p.chain, p.mats, state, np.array([pl.gamma]),
                          np.array([load]), np.array([clearance]), np.array([False]),
                          (p.allowable[:1], p.allowable_default[:1]), fixed, stepping=stepping,
                          sweep=(None if pl.value is None else np.array([pl.value]), np.array([pl.err]), fields, rows,
                                 notes), capacity=capacity)
    return _result(cols, extra, 0, model)


def plot(records, path: str) -> None:
    """The paper's Fig. 2 and a drawing of the chain for up to 4 designs (:mod:`gearcalc.zstk.figure`)."""
    from ..zstk.figure import plot_records

    plot_records(records, path)


CALCULATOR = Calculator(
    kind="zstk",
    title="closed rolling-body mechanism (eccentric ZSTK, leading inner ring)",
    tables=TABLES,
    compute=compute,
    check=check,
    sweep=sweep,
    batch=batch,
    models=MODELS,
    table_fields=("N", "sigma_max_MPa", "sigma_max_contact", "sigma_max_roller", "pass"),
    sweep_plot=("sigma_max_MPa",),
    failure=(("pass", False),),
    plot=plot,
    header=("Merko et al. (seed 003): rollers of different diameters between an outer raceway (R_H) and an\n"
            "eccentric inner raceway (R_B, offset e); one raceway radius (or the gap) is corrected so that an\n"
            "integer number of rollers closes the chain.  Units: mm, N, MPa, degrees."),
)
