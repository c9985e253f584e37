"""The ``rows`` kind: design keys → :mod:`gearcalc.rows` → named summary and detail fields (rows.md).

Mapping only: physics, geometry and validity rules are :mod:`gearcalc.rows` functions (the same for ``check``,
``compute`` and the vectorised ``sweep``), texts :mod:`gearcalc.rows.report`.  ``check`` imports no numpy.
"""
from __future__ import annotations

import math

from ..calculator import Calculator, Check, DesignError, Options, Problems, Result
from ..registry import LEVELS
from ..rows import geometry as G
from ..rows import report as W
from ..rows.schema import FAST_SWEEP_KEYS, TABLES
from ..units import MRAD_PER_RAD, deg_to_rad, nm_to_nmm


def face(get):
    """The face geometry from the design's keys; ``get(key)`` gives a value (check, compute) or a column (sweep)."""
    return G.face_geometry(get("gear.sun_teeth"), get("gear.module_mm"), get("rows.count"),
                           deg_to_rad(get("gear.pressure_angle_deg")), relative_width=get("rows.relative_width"),
                           rim_width=get("rows.rim_width_mm"), cheek_ratio=get("rows.cheek_ratio"),
                           cheek=get("rows.cheek_mm"))


def ratio(get):
    """i from gear.ratio, else from gear.planet_teeth, else None."""
    i, z_g = get("gear.ratio"), get("gear.planet_teeth")
    return G.ratio_from_planet_teeth(z_g, get("gear.sun_teeth")) if i is None and z_g is not None else i


def diameter(reading, f):
    return G.torsion_diameter(reading, f.sun_diameter, f.root_diameter)


def check(design, problems: Problems) -> None:
    given = design.is_given
    if given("rows.relative_width") == given("rows.rim_width_mm"):
        problems.error("rows.relative_width", W.width_choice(given("rows.relative_width")))
        return
    if given("rows.cheek_ratio") and given("rows.cheek_mm"):
        problems.error("rows.cheek_ratio", "give one of rows.cheek_ratio and rows.cheek_mm, not both")
        return
    if not given("rows.cheek_ratio"):
        design.values["rows"]["cheek_ratio"] = 0.25
    za = design["gear.sun_teeth"]
    if given("gear.ratio") and given("gear.planet_teeth"):
        i_teeth = G.ratio_from_planet_teeth(design["gear.planet_teeth"], za)
        if abs(i_teeth - design["gear.ratio"]) > 1e-9 * i_teeth:
            problems.error("gear.ratio", W.ratio_disagrees(design["gear.ratio"], design["gear.planet_teeth"], i_teeth))
    f = face(design.get)
    if given("rows.cheek_mm") and not given("rows.rim_width_mm") and not G.rims_fit(f.rim_width):
        problems.error("rows.cheek_mm", W.no_room_for_rims(design["rows.cheek_mm"], f.relative_width * f.sun_diameter))
        return
    if design["material.mesh_stiffness_MPa"] is None:
        design.values["material"]["mesh_stiffness_MPa"] = G.mesh_stiffness(design["material.E_MPa"])
    d_i, d_f, bore = diameter(design["sun.torsion_diameter"], f), f.root_diameter, design["sun.bore_mm"]
    if not G.bore_fits(bore, d_f, d_i):
        problems.error("sun.bore_mm", W.bore_too_large(bore, d_f, d_i))
    i = ratio(design.get)
    if design.has("bridges"):
        if i is None:
            problems.error("gear.ratio", W.BRIDGES_NEED_RATIO)
        for key in ("axle_diameter_mm", "bridge_thickness_mm"):
            if design[f"bridges.{key}"] is None:
                design.values["bridges"][key] = G.DEFAULT_SECTION_PER_RIM * f.rim_width
        bd = design["bridges.torsion_diameter"]
        if not G.bore_fits(bore, diameter(bd, f)):
            problems.error("bridges.torsion_diameter", f"= {bd!r}: the sun bore {bore!r} mm must be smaller")
    if design.has("mass"):
        lo, hi = design["mass.ratio_range"]
        if not lo < hi:
            problems.error("mass.ratio_range", f"= [{lo!r}, {hi!r}]: the lower bound must be below the upper")
    nw = design["rows.planets_per_row"]
    if nw == 1:
        problems.warn(W.ONE_PLANET)
    if f.relative_width > G.PAPER_MAX_RELATIVE_WIDTH:
        problems.warn(W.WIDE.format(B=f.relative_width))
    if i is not None:
        z_g = G.planet_teeth(i, za)
        if given("gear.ratio") and abs(z_g - round(z_g)) > 1e-9:
            problems.warn(W.not_integer_planets(i, z_g))
        if G.planets_collide(za, z_g, nw):
            problems.warn(W.planets_collide(z_g, (za + z_g) * math.sin(math.pi / nw)))


def mass_params(get, n, nw, f, E, nu, unevenness, alpha) -> dict:
    return dict(rows=n, planets_per_row=nw, wall_ratio=get("mass.wall_ratio"), sun_fill=get("mass.sun_fill"),
                planet_fill=get("mass.planet_fill"), cheek_ratio=f.cheek_ratio,
                allowable_contact=get("mass.allowable_contact_MPa"), density=get("mass.density_kg_m3"),
                youngs_modulus=E, poisson=nu, efficiency=get("mass.efficiency"), unevenness=unevenness,
                pressure_angle=alpha)


def compute(design, options: Options) -> Result:
    import numpy as np

    from .. import rows as R

    f = face(design.get)
    n, nw, bore = design["rows.count"], design["rows.planets_per_row"], design["sun.bore_mm"]
    E, nu, C = design["material.E_MPa"], design["material.poisson"], design["material.mesh_stiffness_MPa"]
    G_sun = R.shear_modulus(E, nu)

    def kappa_for(d_i):
        return float(R.torsion_parameter(C, f.base_radius, nw, f.rim_width, G_sun, R.polar_moment(d_i, bore)))

    d_i = diameter(design["sun.torsion_diameter"], f)
    kappa = kappa_for(d_i)
    sh = R.row_sharing(kappa, f.cheek_ratio, n, options.model or "stepwise")
    warnings, failed = [], []
    if (options.model or "stepwise") == "stepwise" and not bool(sh.stepwise_valid):
        warnings.append(W.STEPWISE_UNAVAILABLE.format(kappa=kappa))
    s = W.sharing_fields(design.name, n, nw, f, d_i, kappa, sh, W.one)
    if s["K_stepwise_vs_exact_pct"] is not None and abs(s["K_stepwise_vs_exact_pct"]) > 2.0:
        warnings.append(W.LEVELS_DIFFER.format(pct=s["K_stepwise_vs_exact_pct"]))
    s["unloaded_rows"] = unloaded = [int(j) + 1 for j in np.flatnonzero(sh.unloaded)]
    T_a = design.get("sun.torque_Nm")
    if T_a is not None:
        s.update(W.load_fields(R.mean_line_load(nm_to_nmm(T_a), n, f.base_radius, f.rim_width, nw), sh, W.one))
    w_mean = s.get("w_mean_N_per_mm")
    twist = None if w_mean is None else R.twist_from_shares(sh.u, w_mean, C, f.base_radius) * MRAD_PER_RAD
    detail = {"rows": W.detail_rows(sh, n, w_mean, twist, unloaded)}
    K_bal = bridges(design, f, s, detail, warnings, failed, kappa_for, C, E, nu) if design.has("bridges") else None
    K_for_mass = s["K"] if K_bal is None else K_bal
    if design.has("mass"):
        K_m = K_for_mass if design["mass.unevenness"] == "computed" else design["mass.unevenness"]
        if K_m is None:
            raise DesignError("mass.unevenness", W.UNEVENNESS_UNAVAILABLE)
        alpha = deg_to_rad(design["gear.pressure_angle_deg"])
        m = R.mass_and_optimum(ratio(design.get), design["mass.ratio_range"], options.tol,
                               **mass_params(design.get, n, nw, f, E, nu, K_m, alpha))
        s.update(W.mass_fields(m, float(K_m), W.one))
        if m.ratio_opt_on_bound:
            lo, hi = design["mass.ratio_range"]
            warnings.append(W.MASS_ON_BOUND.format(lo=lo, hi=hi))
    s.update(margins(design.get, f, d_i, s.get("margin_bridge_fit"), W.one))
    if s["margin_rim"] is not None and s["margin_rim"] < 0:
        failed.append(W.rim_too_thin(G.rim_under_roots(f.root_diameter, bore), G.RIM_MIN_MODULES * design[
            "gear.module_mm"]))
    return Result(summary=s, detail=detail, warnings=warnings, failed=failed, model=s["model"])


def margins(get, f, d_i, fit, plain, n=None) -> dict:
    """margin_bore, margin_rim and failed_checks (:func:`gearcalc.rows.report.margin_fields`) of a design or the
    columns of a sweep (``get``: a key's value or column); ``fit``: margin_bridge_fit, None without [bridges]."""
    bore = get("sun.bore_mm")
    diameters = (f.root_diameter, d_i) + (() if fit is None else (diameter(get("bridges.torsion_diameter"), f),))
    return W.margin_fields(fit, G.bore_margin(bore, *diameters), G.rim_margin(f.root_diameter, bore,
                                                                              get("gear.module_mm")), plain, n)


def bridges(design, f, s, detail, warnings, failed, kappa_for, C, E, nu):
    """Size the bridges and verify the sized carrier; fills the summary and detail; returns K_balanced."""
    from .. import rows as R

    n, nw, m = design["rows.count"], design["rows.planets_per_row"], design["gear.module_mm"]
    alpha, i = deg_to_rad(design["gear.pressure_angle_deg"]), ratio(design.get)
    first = design["bridges.first_span"]
    first_mm = None if first == "axes_only" else float(first)
    d_size = diameter(design["bridges.torsion_diameter"], f)
    Ip = R.polar_moment(d_size, design["sun.bore_mm"])
    res = R.size_bridges(n, nw, f.sun_diameter, m, f.rim_width, f.cheek, alpha, i, design["bridges.axle_diameter_mm"],
                         design["bridges.bridge_thickness_mm"], E, nu, Ip, first_span=first_mm)
    if first_mm is not None and res["H_max"] > 0 and first_mm > res["H_max"]:
        raise DesignError("bridges.first_span", W.first_span_too_wide(first_mm, res["H_max"]))
    if not res["feasible"]:
        hint = None
        if design.get("rows.rim_width_mm") is None:  # where every bridge fits: B's windows, else another n
            given = {k: design[f"bridges.{k}_mm"] if design.is_given(f"bridges.{k}_mm") else None
                     for k in ("axle_diameter", "bridge_thickness")}
            args = (nw, design["gear.sun_teeth"], m, alpha, i, E, nu, Ip)
            kwargs = dict(cheek_ratio=design["rows.cheek_ratio"], cheek=design.get("rows.cheek_mm"),
                          first_span=first_mm, **given)
            windows = R.feasible_widths(f.relative_width, n, *args, **kwargs)
            hint = (n, windows, None, []) if windows else (n, [], *R.feasible_rows(f.relative_width, n, *args,
                                                                                     **kwargs))
        failed.append(W.bridge_failure(res["flags"], res["H_max"], hint))
    Y = R.carrier_compliance(res["a_w"], nw, res["stiffness"], n, f.rim_width, alpha, C)
    verified = {}
    for label, d_i in (("sized", d_size), ("pitch", f.sun_diameter), ("root", f.root_diameter)):
        verified[label] = v = R.verify_carrier(kappa_for(d_i), f.cheek_ratio, n, Y)
        if v.valid and not v.converged:
            warnings.append(W.UNSETTLED.format(label=label))
    if verified["sized"].K is None:
        warnings.append(W.K_BALANCED_UNAVAILABLE)
    fields, detail["bridges"] = W.bridge_fields(res, d_size, verified)
    s.update(fields)
    return s["K_balanced"]


def sweep(base, raw, axes, points, options):
    """The summaries of a whole grid as columns (no Python loop per point; rows.md §9), from the same geometry,
    validity and load-sharing functions as :func:`check` and :func:`compute`.

    Points are grouped by the number of rows n, each group one batch of :func:`gearcalc.rows.row_sharing` and,
    with [bridges], of :func:`gearcalc.rows.size_bridges_batch` and :func:`gearcalc.rows.verify_carrier_batch`;
    the mass optimum is one vectorised golden-section search.  Varied keys outside ``FAST_SWEEP_KEYS``, or
    ``mass.unevenness = "computed"`` where K is undefined, return None: the caller evaluates them point by point.
    """
    import numpy as np

    from .. import rows as R

    if not vectorised(base, axes):
        return None
    computed = base.has("mass") and (base["mass.unevenness"] == "computed" or "mass.unevenness" in axes
                                     and any(isinstance(v, str) for v in axes["mass.unevenness"]))
    P = len(points)

    def col(key):
        if key in axes:
            vals = points.column(key, True) if hasattr(points, "column") else [p[key] for p in points]
            return vals if key in WORDS else np.array(vals, dtype=float)
        v = base.get(key)
        return v if isinstance(v, str) or v is None else np.full(P, float(v))

    def get(key):
        return col(key).astype(int) if key == "rows.count" else col(key)

    f = face(get)
    n, nw = get("rows.count"), col("rows.planets_per_row")
    d_i, bore = diameter(col("sun.torsion_diameter"), f), col("sun.bore_mm")
    invalid_points(f, d_i, bore, col, base.has("bridges"))
    E, nu = col("material.E_MPa"), col("material.poisson")
    C = col("material.mesh_stiffness_MPa") if base.is_given("material.mesh_stiffness_MPa") or \
        "material.mesh_stiffness_MPa" in axes else G.mesh_stiffness(E)
    kappa = R.torsion_parameter(C, f.base_radius, nw, f.rim_width, R.shear_modulus(E, nu), R.polar_moment(d_i, bore))
    sh = R.row_sharing_mixed(kappa, f.cheek_ratio, n, options.model or "stepwise")
    column = W.columns(P)
    cols = W.sharing_fields(base.name, n, nw.astype(int), f, d_i, kappa, sh, column)
    cols["name"] = [base.name] * P
    cols["unloaded_rows"] = sh.unloaded
    T_a = col("sun.torque_Nm")
    if T_a is not None:
        cols.update(W.load_fields(R.mean_line_load(nm_to_nmm(T_a), n, f.base_radius, f.rim_width, nw), sh, column))
    if base.has("bridges"):
        bridge_cols, K_bal, late = bridges_columns(base, axes, points, col, f, n, nw, bore, E, nu, C, column)
        cols.update(bridge_cols)
    if base.has("mass"):
        (lo, hi), unev = base["mass.ratio_range"], col("mass.unevenness")
        if computed:
            if np.isnan(K_bal).any():  # K_balanced undefined: point by point says so at its first point
                return None
            unev = K_bal
        m = R.mass_and_optimum(ratio(col), (np.full(P, lo), np.full(P, hi)), options.tol,
                               **mass_params(col, n, nw, f, E, nu, unev, deg_to_rad(col("gear.pressure_angle_deg"))))
        cols.update(W.mass_fields(m, unev, column))
    cols.update(margins(col, f, d_i, cols.get("margin_bridge_fit"), column, P))
    for key in late if base.has("bridges") else ():
        cols[key] = cols.pop(key)
    return cols  # column-major: the sweep writes it without building a dict per point


def invalid_points(f, d_i, bore, col, bridges: bool) -> None:
    """Raise :class:`~gearcalc.calculator.InvalidPoints` when some points of a sweep break a rule of :func:`check`
    (rims that fit, the sun bore, with [bridges] the bore of the sizing diameter): each such point's message."""
    import numpy as np

    from ..calculator import InvalidPoints, keyed

    d_f = np.broadcast_to(f.root_diameter, np.shape(f.rim_width))
    rules = [(~G.rims_fit(f.rim_width), "rows.cheek_mm", lambda k: W.no_room_for_rims(
        _at(col("rows.cheek_mm"), k), _at(f.relative_width * f.sun_diameter, k))),
             (~G.bore_fits(bore, d_f, d_i), "sun.bore_mm", lambda k: W.bore_too_large(
                 _at(bore, k), _at(d_f, k), _at(d_i, k)))]
    if bridges:
        bd = col("bridges.torsion_diameter")
        rules.append((~G.bore_fits(bore, diameter(bd, f)), "bridges.torsion_diameter",
                      lambda k: f"= {_at(bd, k)!r}: the sun bore {_at(bore, k)!r} mm must be smaller"))
    why = [None] * len(d_f)
    for bad, key, message in rules:
        for k in np.flatnonzero(bad).tolist():
            why[k] = why[k] or keyed(key, message(k))
    if why.count(None) != len(why):
        raise InvalidPoints(why)


def _at(v, k):
    """Point k's value of a column (or the value shared by every point) as a plain number or word."""
    import numpy as np

    v = v[k] if isinstance(v, list) or np.ndim(v) else v
    return v.item() if hasattr(v, "item") else v


def vectorised(base, axes) -> bool:
    """Whether :func:`sweep` evaluates the grid as arrays: every varied key in ``FAST_SWEEP_KEYS`` and K of the
    mass ("computed" unevenness) a column the sweep has (K_balanced, with [bridges] and a fixed unevenness)."""
    if any(k not in FAST_SWEEP_KEYS for k in axes):
        return False
    computed = base.has("mass") and (base["mass.unevenness"] == "computed" or "mass.unevenness" in axes
                                     and any(isinstance(v, str) for v in axes["mass.unevenness"]))
    return not computed or (base.has("bridges") and "mass.unevenness" not in axes)


def sweep_cost(base, axes, options) -> float:
    """Estimated seconds of one point of a sweep (:func:`gearcalc.grid.point_seconds`), measured on one core
    (2026-12-07): the arrays of :func:`sweep` 3 us a point (+ 0.1 us a row), with [bridges] 10 us + 4 us a row
    + the verification's dense solves (1.5e-8 n³ s); point by point 1 ms, with [bridges] 20 ms (an infeasible
    design's hint searches its widths)."""
    rows = axes.get("rows.count", [base["rows.count"]])
    n = max(v for v in rows if isinstance(v, int)) if any(isinstance(v, int) for v in rows) else base["rows.count"]
    solves = 1.5e-8 * n**3 if base.has("bridges") else 0.0
    if vectorised(base, axes):
        return (1e-5 + 4e-6 * n if base.has("bridges") else 3e-6 + 1e-7 * n) + solves
    return (2e-2 if base.has("bridges") else 1e-3) + 3 * solves


def bridges_columns(base, axes, points, col, f, n, nw, bore, E, nu, C, column):
    """The bridge summary columns of a sweep (:func:`bridges`' fields; rows.md §8, §9) and K_balanced (NaN where
    undefined): the points grouped by n, each group one batch; the columns of every n in the order the points
    first show them (a design alone lists its own n's columns: the union of §13.5)."""
    import numpy as np

    from .. import rows as R

    P = len(n)
    alpha, m, i = deg_to_rad(col("gear.pressure_angle_deg")), col("gear.module_mm"), ratio(col)
    section = {k: col(f"bridges.{k}_mm") if base.is_given(f"bridges.{k}_mm") or f"bridges.{k}_mm" in axes
               else G.DEFAULT_SECTION_PER_RIM * f.rim_width for k in ("axle_diameter", "bridge_thickness")}
    first = col("bridges.first_span")
    first = np.array([0.0 if v == "axes_only" else float(v) for v in first], dtype=float) \
        if isinstance(first, list) else np.full(P, 0.0 if first == "axes_only" else float(first))
    d_size = diameter(col("bridges.torsion_diameter"), f)
    Ip = R.polar_moment(d_size, bore)
    G_sun = R.shear_modulus(E, nu)
    H_max, H, rel, margin = np.zeros(P), {}, {}, np.zeros(P)
    feasible = np.zeros(P, bool)
    K = {label: np.full(P, np.nan) for label in ("sized", "pitch", "root")}
    unloaded = [[]] * P
    order = list(dict.fromkeys(np.asarray(n)[np.sort(np.unique(n, return_index=True)[1])].tolist()))
    for rows in order:
        k = np.flatnonzero(n == rows)

        def at(v, k=k):
            return v[k] if np.ndim(v) else v

        res = R.size_bridges_batch(rows, at(nw), at(f.sun_diameter), at(m), at(f.rim_width), at(f.cheek), at(alpha),
                                   at(i), at(section["axle_diameter"]), at(section["bridge_thickness"]), at(E),
                                   at(nu), at(Ip), first_span=at(first))
        wide = (first[k] > 0) & (res["H_max"] > 0) & (first[k] > res["H_max"])
        if wide.any():
            j = int(k[np.argmax(wide)])
            raise DesignError("bridges.first_span", W.first_span_too_wide(
                float(first[j]), float(res["H_max"][np.argmax(wide)])) + f" at {points[j]}")
        H_max[k], feasible[k], margin[k] = res["H_max"], res["feasible"], res["margin"]
        for j in range(rows):
            H.setdefault(j, np.full(P, np.nan))[k] = res["H"][:, j]
            rel.setdefault(j, np.full(P, np.nan))[k] = res["H_rel"][:, j]
        Y = R.carrier_compliance_batch(res["a_w"], at(nw), res["stiffness"], rows, at(f.rim_width), at(alpha), at(C))
        for label, d_i in (("sized", d_size), ("pitch", f.sun_diameter), ("root", f.root_diameter)):
            kappa = R.torsion_parameter(at(C), at(f.base_radius), at(nw), at(f.rim_width), at(G_sun),
                                        R.polar_moment(at(d_i), at(bore)))
            kappa = np.broadcast_to(kappa, k.shape)
            _, _, off, _, K[label][k] = R.verify_carrier_batch(kappa, np.broadcast_to(at(f.cheek_ratio), k.shape),
                                                               rows, Y)
            if label == "sized":
                for q in np.flatnonzero(off.any(axis=1) & ~np.isnan(K[label][k])):  # rows.md §13.4
                    unloaded[k[q]] = (np.flatnonzero(off[q]) + 1).tolist()
    out = {"bridge_max_mm": column(np.maximum(H_max, 0.0)), "bridge_torsion_diameter_mm": column(d_size)}
    first_n, late = order[0], []
    for name, values in (("bridge_rel", rel), ("bridge", H)):
        for j in range(first_n):
            out[f"{name}_{j + 1}" + ("_mm" if name == "bridge" else "")] = column(values[j], ~np.isnan(values[j]))
    out.update(bridges_feasible=column(feasible), margin_bridge_fit=column(margin),
               K_balanced=column(K["sized"], ~np.isnan(K["sized"])),
               K_balanced_pitch=column(K["pitch"], ~np.isnan(K["pitch"])),
               K_balanced_root=column(K["root"], ~np.isnan(K["root"])), unloaded_rows_balanced=unloaded)
    seen = first_n
    for rows in order[1:]:  # a larger n's own columns: after every column of the points before (rows.md §13.5)
        for name, values in (("bridge_rel", rel), ("bridge", H)):
            for j in range(seen, rows):
                late.append(f"{name}_{j + 1}" + ("_mm" if name == "bridge" else ""))
                out[late[-1]] = column(values[j], ~np.isnan(values[j]))
        seen = max(seen, rows)
    return out, K["sized"], late


WORDS = ("sun.torsion_diameter", "bridges.torsion_diameter", "bridges.first_span")
"""Keys whose values may be words: a sweep keeps their column a list."""


def plot(records, path: str) -> list:
    """The figure of :mod:`gearcalc.rows.plot` (matplotlib imported there, on use); the records drawn."""
    from ..rows.plot import plot as draw

    return draw(records, path)


CALCULATOR = Calculator(
    kind="rows", title="multi-row planetary gear: row load sharing, equalising carrier bridges, relative mass",
    tables=TABLES, compute=compute, check=check, models=LEVELS["rows"],
    header="Seed paper 004_971077b94d8d4426.txt; physics in rows.md. Lengths in mm, torque in N*m, stresses in MPa.",
    sweep=sweep, sweep_cost=sweep_cost,
    table_fields=("K", "K_exact", "bridges_feasible", "K_balanced", "relative_mass_min_kg_per_kNm"),
    sweep_plot=("relative_mass_kg_per_kNm", "K"), failure=(("bridges_feasible", False),), plot=plot,
    checks=tuple(Check(*c) for c in W.CHECKS),
)
