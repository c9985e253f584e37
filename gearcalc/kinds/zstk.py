"""``gearcalc zstk``: closed rolling-body mechanism (eccentric ZSTK, leading inner ring).

Schema, cross-key checks and the compute driver; the physics is in :mod:`gearcalc.zstk`
(imported inside the functions: this module stays light for ``check``/``new``/``--help``).
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
ROUNDOFF_ULPS = 4
"""Floor of the cycle/envelope error estimate sigma_max_err_MPa: 4 eps |sigma_max| (the stresses' own round-off;
a sweep's estimate fell 1.2e-12 relative below the actual error when it was smaller)."""
MIN_FORCE_N = 1e-6
"""Smallest radial load (1 uN): far below it the contact deflections approach the round-off of the roller
positions (~1e-16 x clearance) and the load solve cannot balance Q (5e-324 N gave solver_residual = 1 and
pass = true; with clearance, 1e-100 N raised BracketError); at 1e-6 N the worked example balances Q to 4e-8
with a clearance of 0.01 mm (included in sigma_max_err_MPa)."""
SWEEP_WORK_MAX = 6_000_000
"""Cost budget of a "cycle" and/or "envelope" design, in roller-configurations of its first sweep grid
(:func:`sweep_work`): ~1.5-3 us each with the refinements (N = 118, "cycle" + "envelope": 5.4e6, 9 s;
the worked example at --model reference: 5.9e6, 18 s); the sweeps' memory is bounded by CHUNK_ELEMENTS."""
MAX_ROLLERS = 2000       # gearcalc's range (the spec asks N > 200 to work); keeps sweeps in memory
CHUNK_ELEMENTS = 1_000_000  # roller-configurations evaluated at once in the sweeps
REFINE_ROWS_MAX_N = 200  # above this the per-roller envelope rows are grid maxima (O(N²) refinement)
DEFAULT_ALLOWABLE_WARNING = (f"no material.allowable_stress_MPa: checked against {DEFAULT_ALLOWABLE_MPA:g} MPa "
                             f"({DEFAULT_ALLOWABLE_SOURCE}), a static (permanent-deformation) reference, "
                             "not an endurance allowable")
ROLLER_FIELDS = ("theta", "radius", "beta", "psi", "force_inner", "force_outer", "rho_inner", "rho_outer",
                 "sigma_inner", "sigma_outer")
"""The per-roller quantities of a zstk.State that the detail table shows."""

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
    """Cross-key checks: raceways, eccentricity, gap, parity, N and the corrected geometry (spec §3.3, §9);
    the cost budget of the phase and direction sweeps (:func:`cost_problem`, at the default model)."""
    chain, found = _closed_chain(design)
    for key, msg in found:
        problems.error(key, msg)
    if chain is not None:
        problem = cost_problem(design, int(chain.n), "equilibrium")
        if problem is not None:
            problems.error(*problem)


def sweep_work(n: int, cycle: bool, envelope: bool, model: str = "equilibrium") -> int:
    """Roller-configurations of the first grids of a design's sweeps (spec §8): N x phases x directions."""
    gf = 8 if model == "reference" else 1
    if cycle and envelope:
        return n * GRID_PHASE * gf * min(GRID_DIRECTION, max(GRID_DIRECTION // 4, 16 * n)) * gf
    return n * (GRID_PHASE * gf if cycle else 1) * (GRID_DIRECTION * gf if envelope else 1)


def cost_problem(design, n: int, model: str):
    """(key, message) when the design's sweeps would exceed :data:`SWEEP_WORK_MAX`, else None (check and
    compute share it; check assumes the default model)."""
    cycle, envelope = design["geometry.scheme"] == "cycle", design["load.direction_deg"] == "envelope"
    work = sweep_work(n, cycle, envelope, model)
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


def _note_cap(sweep, what: str, per: str, warnings: list) -> None:
    """Warn when a phase or direction sweep hit its grid cap before meeting the tolerance."""
    if sweep.capped:
        warnings.append(f"{what} sweep stopped at the cap of {GRID_CAP} points per {per} with error "
                        f"{sweep.err:.3g} MPa above the target")


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

    Element-wise the same arithmetic as :func:`_closed_chain` + :func:`check` (one design), so that
    a design is valid here exactly when it is valid on its own.
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
    p.size = size
    r_h, r_b, e, c = (num(KEYS[k]) for k in ("outer", "inner", "eccentricity", "gap"))
    p.auto = per("geometry.rollers", lambda r: r == "auto")
    n_given = per("geometry.rollers", lambda r: 0 if r == "auto" else r, np.int64)
    p.letter = per("geometry.scheme", lambda s: isinstance(s, str) and s in SCHEMES)
    p.cycle = per("geometry.scheme", lambda s: s == "cycle")
    p.scheme = per("geometry.scheme", lambda s: s if isinstance(s, str) else "angle", object)
    parity = per("geometry.scheme", lambda s: z.SCHEME_PARITY.get(s, -1) if isinstance(s, str) else -1, np.int64)
    mid_gap = per("geometry.scheme", lambda s: s in ("C", "D"))
    theta_deg = per("geometry.scheme", lambda s: 0.0 if isinstance(s, str) else s, float)
    with np.errstate(divide="ignore", invalid="ignore"):
        n_star = z.fractional_roller_number(r_h, r_b, e, c)
        n_auto = z.auto_roller_numbers(np.where(np.isfinite(n_star), n_star, 0.0), parity)
    n = np.where(p.auto, n_auto, n_given)
    p.chain = z.close_chains(r_h, r_b, e, c, n, per("geometry.correct", str, object))
    clearance = num("load.clearance_mm")
    # validity: the conditions of zstk.geometry_problems, the parity check, the clearance bound,
    # z.auto_roller_number < 3, MAX_ROLLERS and zstk.chain_problems, element-wise
    sqrt2 = np.sqrt(2.0)

    def geometry_ok(r_h, r_b, e, c):
        return ((r_b > 0) & (r_h > r_b) & (0 <= e) & (e < r_h - r_b) & (e < (r_h + r_b) / sqrt2)
                & (0 <= c) & (c < 2 * r_b))

    ch = p.chain
    lim = ch.n_limit
    with np.errstate(invalid="ignore"):
        in_range = np.where(ch.correct == "gap", n <= lim + z.INTEGER_TOL,
                            np.where(np.isfinite(lim), n < lim - z.INTEGER_TOL, True))
        p.valid = (geometry_ok(r_h, r_b, e, c)
                   & ~(~p.auto & (parity >= 0) & (n_given % 2 != parity))
                   & (np.abs(clearance) < (r_h - r_b - e) / 2)
                   & ~(p.auto & (n_auto < 3)) & (n <= MAX_ROLLERS) & (n >= 3) & in_range
                   & geometry_ok(ch.outer_radius, ch.inner_radius, ch.eccentricity, ch.gap))
    p.n = n
    p.q = np.where(p.valid, ch.limiting_ratio if np.all(p.valid) else _masked_ratio(ch, p.valid), 0.0)
    # the phase phi_0 of roller 0: scheme table (spec §4.2) or from the angle theta_0 (spec §4.3)
    angle = ~p.letter & ~p.cycle
    p.phase = np.where(p.letter, np.where(mid_gap, np.pi / np.maximum(n, 1), 0.0),
                       np.where(angle, z.phi_of_theta(deg_to_rad(_remainder_360(theta_deg)), p.q), 0.0))
    p.envelope = per("load.direction_deg", lambda v: v == "envelope")
    p.gamma = deg_to_rad(_remainder_360(per("load.direction_deg", lambda v: 0.0 if isinstance(v, str) else v,
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


def _masked_ratio(chain, valid):
    """Limiting-point ratio q of the valid chains (0 elsewhere, where it may be undefined)."""
    import numpy as np

    from .. import zstk as z

    q = np.zeros(valid.shape)
    q[valid] = z.limiting_point_ratio(chain.outer_radius[valid], chain.inner_radius[valid],
                                      chain.eccentricity[valid], chain.gap[valid])
    return q


def _remainder_360(x):
    """math.remainder(x, 360) element-wise, exactly: x - 360 k, k the integer nearest to x/360 (ties even)."""
    import numpy as np

    r = x - 360.0 * np.round(x / 360.0)  # exact: |r| <= 180 and 360 k is a multiple of 8
    r = np.where(r > 180.0, r - 360.0, r)  # x/360 rounded onto a tie: the nearest k is the other one
    return np.where(r < -180.0, r + 360.0, r)


def _take(obj, idx):
    """A Chain or Materials of the designs ``idx`` (array attributes indexed; strings/objects too)."""
    import dataclasses

    import numpy as np

    return type(obj)(*(np.asarray(getattr(obj, f.name))[idx] for f in dataclasses.fields(obj)))


def _solve_stack(p: _Prepared, idx, options: Options, names, detail: bool):
    """Solve the single-position designs ``idx`` of ``p`` (valid, not "cycle", not "envelope").

    ``names``: the name of every design of ``p`` (a list indexed like ``p``), or one name for all.

    Groups them by N, solves each group as one stack (G, N), and returns the summary columns
    (dict field -> list, in ``idx`` order) and, with ``detail``, per design (warnings, failed, rows).
    """
    import numpy as np

    from ..arrays import unique_sorted

    from .. import zstk as z

    model = options.model or "equilibrium"
    fixed = model == "fixed-direction"
    idx = np.asarray(idx)
    ns = p.n[idx]
    parts = []
    for nn in unique_sorted(ns):
        sub = idx[ns == nn]
        nn = int(nn)
        chain, mats = _take(p.chain, sub), _take(p.mats, sub)
        theta = z.roller_angles(p.phase[sub], nn, p.q[sub])
        theta0 = theta[:, 0]
        gamma = p.gamma[sub]
        # mirror-symmetric configurations (spec §5.1): a scheme with the load on the line of centres,
        # or e = 0 with the load line through a roller or a mid-gap
        k = (gamma - theta0) / (np.pi / nn)
        symmetric = ((p.letter[sub] & (np.abs(np.sin(gamma)) < 1e-15))
                     | ((chain.eccentricity == 0.0) & (np.abs(k - np.round(k)) < 1e-12)))
        state = z.evaluate(chain, mats, theta, gamma, p.load[sub], p.clearance[sub], symmetric=symmetric,
                           fixed_direction=fixed)
        stepping = None
        if model == "reference":
            _, stepping = z.step_chain(theta0, nn, chain.outer_radius, chain.inner_radius, chain.eccentricity,
                                       chain.gap)
        out = _finish([names[i] for i in sub] if isinstance(names, list) else names, model, p.scheme[sub], chain,
                      mats, state, theta0, gamma, p.load[sub], p.clearance[sub], symmetric,
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


def _n_admissible_max(lim: float, correct: str):
    """The largest admissible N (None: no limit); Python integers, exact for any size of the limit."""
    if not math.isfinite(lim):
        return None
    if correct == "gap":
        return math.floor(lim + 1e-9)
    return int(math.ceil(lim - 1e-9) - 1)


def _finish(names, model, schemes, chain, mats, state, theta0, gamma, load, clearance, symmetric, allowable,
            fixed, sweeping=False, sweep_value=None, err_sweep=None, sweep_fields=None, stepping=None,
            detail=True, envelope_rows=None, notes=()):
    """Summary columns of G stacked designs from their solved state (arrays (G, N) and (G,)).

    With ``detail``, also per design: (warnings, failed, detail rows).  ``sweeping`` marks a "cycle" or
    "envelope" design (G = 1): ``sweep_value``, ``err_sweep`` and ``sweep_fields`` come from its sweeps,
    ``envelope_rows`` holds its per-roller envelope columns (d_B, d_H, gamma_B, gamma_H) and ``notes`` the
    warnings of its sweeps.
    """
    import numpy as np

    from .. import hertz
    from .. import zstk as z
    from ..units import UM_PER_MM

    size = theta0.shape[0]
    smax, i_crit, contact = z.critical(state)
    if sweep_value is not None:
        smax = np.where(sweep_value > smax, sweep_value, smax)
    sol = state.loads
    shape = (size,)
    residual, transverse = z.broadcast(sol.residual, shape), z.broadcast(sol.transverse, shape)
    converged = z.broadcast(sol.converged, shape)
    f_sum = np.sum(sol.force, axis=-1)
    solver_residual = residual / (load + f_sum)
    transverse_residual = transverse / load
    if fixed:
        along = np.sqrt(np.maximum(residual ** 2 - transverse ** 2, 0.0))
        solver_residual = along / (load + f_sum)

    def at_crit(a):
        return np.take_along_axis(np.asarray(a), i_crit[:, None], axis=-1)[:, 0]

    f_crit = np.where(contact == 0, at_crit(state.force_inner), at_crit(state.force_outer))
    closed_form = symmetric & (clearance == 0.0) & (not sweeping)
    resid_abs = residual if not fixed else solver_residual * (load + f_sum)
    with np.errstate(divide="ignore", invalid="ignore"):
        err_solver = np.where(closed_form | ~(f_crit > 0), 0.0, 0.5 * smax * resid_abs / f_crit)
    sigma_err = (0.0 if err_sweep is None else err_sweep) + err_solver
    if sweeping:   # a sweep's estimate is never below the round-off of the value itself (4 ulp)
        sigma_err = np.maximum(sigma_err, ROUNDOFF_ULPS * np.finfo(float).eps * np.abs(smax))
    allow, default_allowable = allowable
    passed = smax <= allow
    cname = ["inner" if c == 0 else "outer" for c in contact.tolist()]
    r_crit = at_crit(state.radius)
    # the displacement (spec §11.3): |delta| along alpha + 180 degrees when delta < 0
    delta = z.broadcast(sol.approach, shape)
    alpha = z.broadcast(sol.alpha, shape)
    neg = delta < 0
    delta, alpha = np.where(neg, -delta, delta), np.where(neg, alpha + np.pi, alpha)
    alpha_deg = np.mod(_deg(alpha), 360.0)
    alpha_deg = np.where(alpha_deg >= 360.0, 0.0, alpha_deg)
    n_adm = [_n_admissible_max(lim, corr) for lim, corr in zip(z.broadcast(chain.n_limit, shape).tolist(),
                                                               z.broadcast(chain.correct, shape).tolist())]
    with np.errstate(divide="ignore"):
        safety = np.where(smax > 0, allow / np.where(smax > 0, smax, 1.0), 0.0).tolist()
    positive = (smax > 0).tolist()
    n = state.radius.shape[-1]

    def col(v):
        return z.broadcast(v, shape).tolist()

    def nones():
        return [None] * size

    sweep_fields = sweep_fields or {}
    cols = {
        "name": names if isinstance(names, list) else [names] * size,
        "model": [model] * size,
        "scheme": schemes.tolist(),
        "theta0_deg": col(_wrap_deg(theta0)),
        "N": [n] * size,
        "N_star": col(chain.n_star),
        "N_admissible_max": n_adm,
        "correction": col(chain.correct),
        "outer_raceway_radius_mm": col(chain.outer_radius),
        "inner_raceway_radius_mm": col(chain.inner_radius),
        "roller_gap_mm": col(chain.gap),
        "nominal_mm": col(chain.nominal),
        "correction_mm": col(chain.corrected - chain.nominal),
        "r_min_mm": col((chain.outer_radius - chain.inner_radius - chain.eccentricity) / 2),
        "r_max_mm": col((chain.outer_radius - chain.inner_radius + chain.eccentricity) / 2),
        "sigma_max_MPa": col(smax),
        "sigma_max_err_MPa": col(sigma_err),
        "sigma_max_contact": cname,
        "sigma_max_roller": col(i_crit),
        "sigma_max_angle_deg": col(_wrap_deg(at_crit(state.theta))),
        "sigma_max_roller_radius_mm": col(r_crit),
        "sigma_max_load_direction_deg": col(_wrap_deg(gamma)),
        "allowable_stress_MPa": col(allow),
        "allowable_stress_source": [DEFAULT_ALLOWABLE_SOURCE if d else "design" for d in default_allowable.tolist()],
        "safety_factor": [v if ok else None for v, ok in zip(safety, positive)],
        "pass": col(passed),
        "approach_um": col(delta * UM_PER_MM),
        "approach_direction_deg": col(alpha_deg),
        "clearance_mm": col(clearance),
        "loaded_rollers": col(np.count_nonzero(state.force_inner > 0, axis=-1)),
        "solver_residual": col(solver_residual),
        "transverse_residual": col(transverse_residual),
        "phase_samples": [sweep_fields.get("phase_samples")] * size,
        "phase_step_deg": [sweep_fields.get("phase_step_deg")] * size,
        "direction_samples": [sweep_fields.get("direction_samples")] * size,
        "direction_step_deg": [sweep_fields.get("direction_step_deg")] * size,
        "stepping_residual_mm": nones() if stepping is None else col(stepping),
    }
    if not detail:
        return cols, None

    # ---- the per-roller table (with "envelope": each roller's maxima over the directions)
    if envelope_rows is None:
        d_b = d_h = {f: getattr(state, f) for f in ROLLER_FIELDS}
        gam_b = gam_h = None
    else:
        d_b, d_h, gam_b, gam_h = envelope_rows
    length, e_b, e_h = (np.reshape(np.asarray(x, dtype=float), (-1, 1)) for x in
                        (mats.length, mats.e_star_inner, mats.e_star_outer))
    f_b, f_h = d_b["force_inner"], d_h["force_outer"]
    s_b, s_h = d_b["sigma_inner"], d_h["sigma_outer"]
    rho_b, rho_h = d_b["rho_inner"], d_h["rho_outer"]
    b_b = hertz.semi_width(f_b, length, rho_b, e_b)
    b_h = hertz.semi_width(f_h, length, rho_h, e_h)
    deg = np.degrees
    table = {
        "i": z.broadcast(np.arange(n), (size, n)),
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
    if envelope_rows is not None:
        table["gamma_B_deg"] = deg(z.wrap_angle(gam_b))
        table["gamma_H_deg"] = deg(z.wrap_angle(gam_h))
    else:
        approach = (z.broadcast(sol.approach, shape)[:, None] * np.cos(state.normal_angle - z.broadcast(
            sol.alpha, shape)[:, None]) - 0.5 * np.asarray(clearance, dtype=float)[:, None])
        table["delta_um"] = approach * UM_PER_MM
    keys = list(table)
    flat = zip(*(z.broadcast(v, (size, n)).ravel().tolist() for v in table.values()))
    rows_flat = [dict(zip(keys, vals)) for vals in flat]
    worst = np.full(size, -np.inf)
    for f, b, rho in ((f_b, b_b, rho_b), (f_h, b_h, rho_h)):
        bad = (f > 0) & (b > B_OVER_RHO_LIMIT * rho)
        worst = np.maximum(worst, np.max(np.where(bad, b / rho, -np.inf), axis=-1))

    # ---- warnings and failed checks, per design (text only where there is something to say)
    warn_solver = ~np.asarray(converged, dtype=bool)
    warn_fixed = fixed & (transverse_residual > 1e-9)
    fail_at = np.flatnonzero(~passed)
    out = []
    for g in range(size):
        warnings = list(notes)
        if warn_solver[g]:
            why = (" (round-off floor: with clearance and so small a load the contact deflections approach the "
                   "round-off of the roller positions, about 1e-16·clearance)" if clearance[g] > 0 else "")
            warnings.append(f"the load solve reached a relative residual of {solver_residual[g]:.3g}, not the "
                            f"target 1e-12·(Q + ΣF){why}; sigma_max_err_MPa includes it")
        if warn_fixed[g]:
            warnings.append(f"fixed-direction model: the rollers leave an unbalanced transverse force of "
                            f"{100 * transverse_residual[g]:.3g} % of Q (use the default equilibrium model)")
        if default_allowable[g]:
            warnings.append(DEFAULT_ALLOWABLE_WARNING)
        if np.isfinite(worst[g]):
            warnings.append(f"a loaded contact has b/rho = {worst[g]:.3g} > {B_OVER_RHO_LIMIT}: Hertz's "
                            "small-contact assumption is doubtful")
        if stepping is not None and stepping[g] > 1e-9:
            warnings.append(f"explicit stepping closes with a residual of {stepping[g]:.3g} mm (> 1e-9 mm)")
        out.append([warnings, [], rows_flat[g * n:(g + 1) * n]])
    for g in fail_at.tolist():
        out[g][1].append(f"sigma_max_MPa = {smax[g]:.6g} > allowable_stress_MPa = {allow[g]:.6g} ({cname[g]} "
                         f"contact of roller {i_crit[g]}, r = {r_crit[g]:.6g} mm)")
    return cols, out


def _result(cols, extra, j: int, model: str) -> Result:
    warnings, failed, rows = extra[j]
    return Result(summary={k: v[j] for k, v in cols.items()}, detail={"rollers": rows}, warnings=warnings,
                  failed=failed, model=model)


def _invalid(design):
    """The DesignError of a design that :func:`_prepare` found invalid (the messages of :func:`check`)."""
    _, found = _closed_chain(design)
    if not found:  # _prepare and _closed_chain disagree: a bug
        raise RuntimeError("zstk: the stacked validity check rejected a design that check() accepts")
    return DesignError(*found[0])


def compute(design, options: Options) -> Result:
    """Close the chain, place it, share the load, and check the Hertz stresses (spec zstk.md).

    A single-position design is a stack of one (:func:`_solve_stack`, the same code as ``batch`` and
    ``sweep``); "cycle" and "envelope" designs run their phase and direction sweeps first.
    """
    p = _prepare(_design_columns([design]), 1)
    if not p.valid[0]:
        raise _invalid(design)
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
        out[k] = _invalid(designs[k])
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
        key, msg = _point_problem(raw, base, points[k])
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


def _point_problem(raw, base, point):
    """(dotted key, message) of the first problem of one grid point, as ``gearcalc zstk`` reports it."""
    import copy

    from ..design import InputError, apply_set, validate

    trial = copy.deepcopy(raw)
    apply_set(trial, list(point.items()))
    try:
        design = validate(trial, base.source)
    except InputError:
        design = None
    if design is None:  # the check hook's problems (validate prefixes them with the file name)
        from ..design import Design

        values = {t: dict(v) for t, v in base.values.items()}
        for k, v in point.items():
            table, _, name = k.partition(".")
            field = next(t.field(name) for t in TABLES if t.name == table)
            values[table][name] = check_value(field, v)[0]
        design = Design(kind=base.kind, name=base.name, source=base.source, values=values)
    _, found = _closed_chain(design)
    if not found:
        raise RuntimeError(f"zstk sweep: the stacked validity check rejected the point {point}, which check() accepts")
    return found[0]


def _one(obj):
    """A Chain or Materials of one design with float attributes (from arrays of shape (1,))."""
    import dataclasses

    import numpy as np

    vals = []
    for f in dataclasses.fields(obj):
        v = np.asarray(getattr(obj, f.name)).reshape(-1)[0]
        vals.append(v.item() if hasattr(v, "item") else v)
    return type(obj)(*vals)


def _compute_sweeping(design, p, options: Options) -> Result:
    """A "cycle" (phase) and/or "envelope" (direction) design: adaptive sweeps (spec §8), then the summary."""
    import numpy as np

    from .. import zstk as z
    from ..roots import minimize_golden
    from ..units import deg_to_rad

    model = options.model or "equilibrium"
    problem = cost_problem(design, int(p.n[0]), model)
    if problem is not None:
        raise DesignError(*problem)
    chain, mats = _one(p.chain), _one(p.mats)
    load, clearance = float(p.load[0]), float(p.clearance[0])
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
    notes: list[str] = []

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
        the model's own loads, and the best ``candidates`` grid points of each phase are refined by golden
        section.  (Ranking with the fixed-direction closed form, 10x cheaper, picked the wrong directions
        at large e/D: the envelope came out low and did not converge as the phases doubled.)"""
        step = 2 * np.pi / gamma_grid.size
        chunk = max(1, CHUNK_ELEMENTS // (gamma_grid.size * n))
        flat = np.ravel(phase)
        res = np.empty(flat.shape)
        for s in range(0, flat.size, chunk):
            ph = flat[s:s + chunk]
            st = z.evaluate(chain, mats, z.roller_angles(ph[:, None], n, q), gamma_grid[None, :], load, clearance,
                            fixed_direction=fixed)
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
        sweep_fields["phase_step_deg"] = float(_deg(sw.step))
        _note_cap(sw, "phase", "pitch", notes)
    else:
        phase = float(p.phase[0])
    theta = z.roller_angles(phase, n, q)

    # ---- the direction
    if envelope:
        sw = z.maximise_periodic(lambda g: sigma_max(phase, g), 0.0, 2 * np.pi, GRID_DIRECTION * grid_factor,
                                 tol, GRID_CAP, refine_rtol)
        gamma = sw.x
        err_sweep += sw.err
        sweep_fields["direction_samples"] = sw.samples
        sweep_fields["direction_step_deg"] = float(_deg(sw.step))
        _note_cap(sw, "direction", "turn", notes)
        sweep_value = np.array([sw.value])
    else:
        gamma = float(p.gamma[0])
        sweep_value = None

    state = z.evaluate(chain, mats, theta[None, :], np.array([gamma]), load, clearance, fixed_direction=fixed)
    stepping = None
    if ref:
        _, res = z.step_chain(theta[0], n, chain.outer_radius, chain.inner_radius, chain.eccentricity, chain.gap)
        stepping = np.array([float(res)])
    rows = None
    if envelope:
        rows = _envelope_quantities(chain, mats, theta, load, clearance, fixed, refine_rtol,
                                    sweep_fields["direction_samples"])
    cols, extra = _finish([design.name], model, p.scheme[:1], p.chain, p.mats, state, theta[:1], np.array([gamma]),
                          np.array([load]), np.array([clearance]), np.array([False]),
                          (p.allowable[:1], p.allowable_default[:1]), fixed,
                          sweeping=True, sweep_value=sweep_value, err_sweep=np.array([err_sweep]),
                          sweep_fields=sweep_fields, stepping=stepping, detail=True, envelope_rows=rows, notes=notes)
    return _result(cols, extra, 0, model)


def _envelope_quantities(chain, mats, theta, load, clearance, fixed, refine_rtol, direction_samples):
    """Each roller's maxima over the load directions (spec §5.3): grid maxima on the final direction grid,
    refined by golden section (up to REFINE_ROWS_MAX_N rollers); returns (d_B, d_H, gamma_B, gamma_H),
    the roller quantities at each roller's own critical direction, arrays of shape (1, N)."""
    import numpy as np

    from .. import zstk as z
    from ..roots import minimize_golden

    n = chain.n

    def diagonal(gams):
        """Roller i's quantities at load direction gams[i] (chunks of rollers, bounded memory)."""
        out = {f: np.empty(n) for f in ROLLER_FIELDS}
        step_n = max(1, CHUNK_ELEMENTS // n)
        for k in range(0, n, step_n):
            g = gams[k:k + step_n]
            st = z.evaluate(chain, mats, np.broadcast_to(theta, (g.size, n)), g, load, clearance,
                            fixed_direction=fixed)
            rows = np.arange(g.size)
            for f in ROLLER_FIELDS:
                out[f][k:k + g.size] = getattr(st, f)[rows, k + rows]
        return {f: v[None, :] for f, v in out.items()}

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
    return diagonal(gam_b), diagonal(gam_h), gam_b[None, :], gam_h[None, :]


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
            f_b = rows[k].get("F_B_N")
            load = f"\n{f_b:,.0f} N" if f_b and f_b >= 1 else f"\n{f_b:.2g} N" if f_b else ""  # load F_iB
            ax2.text(cx, cy, f"{k}{load}", ha="center", va="center", fontsize=7)
        g = np.radians(s["sigma_max_load_direction_deg"])
        ax2.annotate("", xy=(e + 0.8 * r_b * np.cos(g), 0.8 * r_b * np.sin(g)), xytext=(e, 0.0),
                     arrowprops={"arrowstyle": "->", "color": "tab:red", "lw": 1.5})
        ax2.set_aspect("equal")
        ax2.set_title("chain (narrowest gap at +x): roller index and load F_iB [N]\n"
                      "arrow: the load on the inner ring; red: the critical roller", fontsize=9)
        ax2.axis("off")
    save(fig, path)


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
