"""The ``rows`` kind: schema, cross-key checks and the glue from a design to :mod:`gearcalc.rows`.

numpy and the physics are imported inside :func:`compute` only.
"""
from __future__ import annotations

import math

from ..calculator import REQUIRED, Calculator, DesignError, Field, Options, Problems, Result, Table
from ..units import MRAD_PER_RAD, deg_to_rad, nm_to_nmm

DIAMETER_WORDS = ("pitch", "root")

TABLES = (
    Table("gear", doc="the sun and the ratio", fields=(
        Field("sun_teeth", "integer", REQUIRED, "z_a, sun teeth", ge=3, le=10000, example=18),
        Field("module_mm", "number", REQUIRED, "m, module", ge=1e-3, le=1e4, example=5.0),
        Field("pressure_angle_deg", "number", 20.0, "alpha_w, working pressure angle", ge=1, lt=45),
        Field("ratio", "number", None, "i, ratio (sun input, ring fixed, carrier output); needed by [bridges]",
              gt=2, le=1e4, example=6.0),
        Field("planet_teeth", "integer", None, "z_g, planet teeth; i = 2 + 2 z_g / z_a (give ratio or this)",
              ge=1, le=1e6),
    )),
    Table("rows", doc="the planet rows", fields=(
        Field("count", "integer", REQUIRED, "n, rows of planets", ge=1, le=1000, example=3),
        Field("planets_per_row", "integer", REQUIRED, "n_w, planets in each row", ge=1, le=1000, example=3),
        Field("relative_width", "number", None, "B = b_a / d_a, sun face width over sun pitch diameter "
              "(give this or rim_width_mm)", ge=1e-9, le=1e4, example=3.0),
        Field("rim_width_mm", "number", None, "b_w, planet rim (row) width (give this or relative_width)",
              ge=1e-6, le=1e7),
        Field("cheek_ratio", "number", None, "b/b_w, cheek thickness over rim width (give this or cheek_mm)",
              ge=0, le=1e4, default_doc="0.25", example=0.25),
        Field("cheek_mm", "number", None, "b, cheek thickness = gap between rows (give this or cheek_ratio)",
              ge=0, le=1e7),
    )),
    Table("sun", doc="the sun shaft", fields=(
        Field("torque_Nm", "number", None, "T_a, sun torque; K does not depend on it, the line loads do",
              gt=0, le=1e15, example=1000.0),
        Field("torsion_diameter", "number", "pitch", "d_I for the polar moment: pitch diameter, root diameter "
              "(d_a - 2.5 m) or a diameter in mm", ge=1e-3, le=1e8, choices=DIAMETER_WORDS),
        Field("bore_mm", "number", 0.0, "d_0, sun bore (0: solid)", ge=0, le=1e8),
    )),
    Table("material", doc="elastic constants", fields=(
        Field("E_MPa", "number", 2.0e5, "E, Young's modulus", ge=1.0, le=1e7),
        Field("poisson", "number", 0.3, "nu, Poisson's ratio", ge=0, lt=0.5),
        Field("mesh_stiffness_MPa", "number", None, "C, mesh stiffness per unit face width (N/mm per mm)",
              ge=1e-3, le=1e8, default_doc="0.075 E_MPa"),
    )),
    Table("bridges", optional=True, doc="present: size the carrier bridges that equalise the rows (eq. (2))",
          fields=(
              Field("axle_diameter_mm", "number", None, "d, planet axle diameter", gt=0, le=1e7,
                    default_doc="0.5 b_w"),
              Field("bridge_thickness_mm", "number", None, "h, radial thickness of a bridge", gt=0, le=1e7,
                    default_doc="0.5 b_w"),
              Field("first_span", "number", "axes_only", "H_1: \"axes_only\" (H_1 = 0, the paper's closure) "
                    "or a width in mm", ge=0, le=1e8, choices=("axes_only",)),
              Field("torsion_diameter", "number", "root", "d_I used to size the bridges (the paper's table "
                    "needs \"root\")", ge=1e-3, le=1e8, choices=DIAMETER_WORDS),
          )),
    Table("mass", optional=True, doc="present: relative mass M(i) and the ratio that minimises it", fields=(
        Field("wall_ratio", "number", 0.06, "t, wall of ring rim, housing and covers over ring diameter", ge=0, le=1),
        Field("sun_fill", "number", 0.7, "k_a, fill factor of the sun", gt=0, le=1),
        Field("planet_fill", "number", 1.0, "k_g, fill factor of a planet", gt=0, le=1),
        Field("allowable_contact_MPa", "number", 600.0, "sigma_HP, allowable contact stress", ge=1e-3, le=1e6),
        Field("density_kg_m3", "number", 7800.0, "rho, density", gt=0, le=1e6),
        Field("efficiency", "number", 0.95, "eta, efficiency", gt=0, le=1),
        Field("unevenness", "number", 1.0, "K used in M; \"computed\" takes K_balanced with [bridges], "
              "else the design's K", ge=1e-3, le=1e6, choices=("computed",)),
        Field("ratio_range", "numbers", [2.2, 12.0], "[i_lo, i_hi] where the minimum is searched", gt=2, le=1e4,
              length=2),
    )),
)


def geometry(design) -> dict:
    """Derived geometry in mm (pure Python, used by check and compute)."""
    za, m = design["gear.sun_teeth"], design["gear.module_mm"]
    n = design["rows.count"]
    d_a = za * m
    bbar = design["rows.cheek_ratio"]
    if design.get("rows.rim_width_mm") is not None:
        b_w = design["rows.rim_width_mm"]
        if design.get("rows.cheek_mm") is not None:
            bbar = design["rows.cheek_mm"] / b_w
        B = (n * b_w + (n - 1) * bbar * b_w) / d_a
    else:
        B = design["rows.relative_width"]
        if design.get("rows.cheek_mm") is not None:
            # b = b̄ b_w and b_a = n b_w + (n-1) b = B d_a  ->  b_w = (B d_a - (n-1) b) / n
            b = design["rows.cheek_mm"]
            b_w = (B * d_a - (n - 1) * b) / n
            bbar = b / b_w if b_w > 0 else math.inf
        else:
            b_w = B * d_a / (n + bbar * (n - 1))
    alpha = deg_to_rad(design["gear.pressure_angle_deg"])
    ratio = design.get("gear.ratio")
    if ratio is None and design.get("gear.planet_teeth") is not None:
        ratio = 2.0 + 2.0 * design["gear.planet_teeth"] / za
    return {"d_a": d_a, "d_f": d_a - 2.5 * m, "b_w": b_w, "cheek_ratio": bbar, "b": bbar * b_w, "B": B,
            "alpha": alpha, "r_ba": 0.5 * d_a * math.cos(alpha), "ratio": ratio, "n": n}


def torsion_diameter(spec, geo) -> float:
    if spec == "pitch":
        return geo["d_a"]
    if spec == "root":
        return geo["d_f"]
    return float(spec)


def check(design, problems: Problems) -> None:
    given = design.is_given
    n = design["rows.count"]
    if given("rows.relative_width") == given("rows.rim_width_mm"):
        problems.error("rows.relative_width", "give exactly one of rows.relative_width (B) and rows.rim_width_mm "
                       "(b_w)" + (", not both" if given("rows.relative_width") else ""))
        return
    if given("rows.cheek_ratio") and given("rows.cheek_mm"):
        problems.error("rows.cheek_ratio", "give one of rows.cheek_ratio and rows.cheek_mm, not both")
        return
    if not given("rows.cheek_ratio"):
        design.values["rows"]["cheek_ratio"] = 0.25
    za = design["gear.sun_teeth"]
    if given("gear.ratio") and given("gear.planet_teeth"):
        i_teeth = 2.0 + 2.0 * design["gear.planet_teeth"] / za
        if abs(i_teeth - design["gear.ratio"]) > 1e-9 * i_teeth:
            problems.error("gear.ratio", f"= {design['gear.ratio']!r} disagrees with gear.planet_teeth = "
                           f"{design['gear.planet_teeth']} (2 + 2 z_g/z_a = {i_teeth:.6g}); give one of them")
    geo = geometry(design)
    if given("rows.cheek_mm") and not given("rows.rim_width_mm") and geo["b_w"] <= 0:
        problems.error("rows.cheek_mm", f"= {design['rows.cheek_mm']!r}: the cheeks leave no room for the rims "
                       f"in b_a = B d_a = {geo['B'] * geo['d_a']:.6g} mm")
        return
    if design["material.mesh_stiffness_MPa"] is None:
        design.values["material"]["mesh_stiffness_MPa"] = 0.075 * design["material.E_MPa"]
    d_i = torsion_diameter(design["sun.torsion_diameter"], geo)
    bore = design["sun.bore_mm"]
    limit = min(geo["d_f"], d_i)
    if bore >= limit:
        problems.error("sun.bore_mm", f"= {bore!r}: must be < min(root diameter d_f = {geo['d_f']:.6g}, "
                       f"torsion diameter d_I = {d_i:.6g}) = {limit:.6g} mm (a bore cannot cut the tooth roots)")
    elif bore > 0 and (geo["d_f"] - bore) / 2 < 2.7 * design["gear.module_mm"]:
        problems.warn(f"the rim under the sun's tooth roots, (d_f - d_0)/2 = {(geo['d_f'] - bore) / 2:.4g} mm, "
                      f"is thinner than 1.2 tooth depths (2.7 m = {2.7 * design['gear.module_mm']:.4g} mm) "
                      "[ISO 6336-3]: the teeth and rim may not carry as modelled")
    ratio = geo["ratio"]
    if design.has("bridges"):
        if ratio is None:
            problems.error("gear.ratio", "missing; [bridges] needs the ratio (give gear.ratio or gear.planet_teeth)")
        for key in ("axle_diameter_mm", "bridge_thickness_mm"):
            if design[f"bridges.{key}"] is None:
                design.values["bridges"][key] = 0.5 * geo["b_w"]
        bd = design["bridges.torsion_diameter"]
        if bore >= torsion_diameter(bd, geo):
            problems.error("bridges.torsion_diameter", f"= {bd!r}: the sun bore {bore!r} mm must be smaller")
    if design.has("mass"):
        lo, hi = design["mass.ratio_range"]
        if not lo < hi:
            problems.error("mass.ratio_range", f"= [{lo!r}, {hi!r}]: the lower bound must be below the upper")
    nw = design["rows.planets_per_row"]
    if nw == 1:
        problems.warn("one planet per row: sun bending and the unbalanced radial load are not modelled")
    if geo["B"] > 10:
        problems.warn(f"relative width B = {geo['B']:.4g} is far outside the paper's range (B <= 10)")
    if ratio is not None:
        z_g = za * (ratio - 2.0) / 2.0
        if given("gear.ratio") and abs(z_g - round(z_g)) > 1e-9:
            problems.warn(f"gear.ratio = {ratio!r} gives z_g = z_a (i - 2)/2 = {z_g:.6g} planet teeth, not an "
                          "integer: not a realisable gear (the formulas stay continuous in i)")
        if nw >= 2 and (z_g + 2) >= (za + z_g) * math.sin(math.pi / nw):
            problems.warn(f"the planets collide: z_g + 2 = {z_g + 2:.6g} >= (z_a + z_g) sin(pi/n_w) = "
                          f"{(za + z_g) * math.sin(math.pi / nw):.6g} (adjacency condition)")
    if n >= 2 and geo["cheek_ratio"] == 0:
        pass  # b = 0 is valid (the exact identities of rows.md §3 apply)


def compute(design, options: Options) -> Result:
    import numpy as np

    from .. import rows as R
    from ..roots import minimize_golden

    geo = geometry(design)
    n, nw = geo["n"], design["rows.planets_per_row"]
    bbar, b_w, r_ba = geo["cheek_ratio"], geo["b_w"], geo["r_ba"]
    E, nu = design["material.E_MPa"], design["material.poisson"]
    G = E / (2.0 * (1.0 + nu))
    C = design["material.mesh_stiffness_MPa"]
    bore = design["sun.bore_mm"]
    warnings: list[str] = []
    failed: list[str] = []

    def kappa_for(d_i):
        return float(R.torsion_parameter(C, r_ba, nw, b_w, G, R.polar_moment(d_i, bore)))

    d_i = torsion_diameter(design["sun.torsion_diameter"], geo)
    kappa = kappa_for(d_i)
    u_step, valid = R.stepwise_shares(kappa, bbar, n)
    valid = bool(valid)
    u_exact, peak = R.exact_shares(kappa, bbar, n)
    peak = float(peak)
    if n == 1:
        K_step = K_exact = K_cont = 1.0
    else:
        K_step = float(u_step.max()) if valid else None
        K_exact = float(u_exact.max())
        K_cont = float(R.continuous_k(kappa, bbar, n))
    model = options.model or "stepwise"
    if model == "stepwise" and not valid:
        warnings.append(f"the stepwise level is not available at kappa = {kappa:.6g} >= 8 (the half-row twist "
                        "outweighs the mesh compliance): K comes from the exact level")
        model = "exact"
    if model == "stepwise":
        K, u_used, K_row = K_step, u_step, int(np.argmax(u_step)) + 1
    elif model == "exact":
        K, u_used, K_row = K_exact, u_exact, int(np.argmax(u_exact)) + 1
    else:
        K, u_used, K_row = K_cont, u_exact, 1
    if n == 1:
        K = 1.0
    step_vs_exact = None if K_step is None else 100.0 * (K_step / K_exact - 1.0)
    if step_vs_exact is not None and abs(step_vs_exact) > 2.0:
        warnings.append(f"the stepwise and exact levels differ by {step_vs_exact:+.3g} % (> 2 %): the paper's "
                        "uniform-within-a-row assumption is strained; consider --model exact")
    unloaded = [int(j) + 1 for j in np.flatnonzero(u_used <= 1e-12)] if n > 1 else []
    s = {
        "name": design.name,
        "rows": n,
        "planets_per_row": nw,
        "relative_width": geo["B"],
        "rim_width_mm": b_w,
        "cheek_ratio": bbar,
        "torsion_diameter_mm": d_i,
        "kappa": kappa,
        "model": model,
        "K": K,
        "K_row": K_row,
        "K_stepwise": K_step,
        "stepwise_valid": valid,
        "K_exact": K_exact,
        "K_continuous": K_cont,
        "K_stepwise_vs_exact_pct": step_vs_exact,
        "K_vs_continuous_pct": 100.0 * (K / K_cont - 1.0),
        "peak_factor": peak,
        "row1_face_factor": peak / K_exact,
        "unloaded_rows": unloaded,
    }
    T_a = design.get("sun.torque_Nm")
    w_mean = None
    if T_a is not None:
        w_mean = nm_to_nmm(T_a) / (n * r_ba * b_w * nw)
        s["w_mean_N_per_mm"] = w_mean
        s["w_max_N_per_mm"] = K * w_mean
        s["w_peak_N_per_mm"] = peak * w_mean
    detail_rows = []
    twist = 2.0 * (u_used[0] - u_used) / (C * r_ba) * (w_mean or 0.0) * MRAD_PER_RAD
    for j in range(n):
        row = {"row": j + 1}
        if valid:
            row["u_stepwise"] = float(u_step[j])
            row["share_stepwise_pct"] = 100.0 * float(u_step[j]) / n
            if w_mean is not None:
                row["w_stepwise_N_per_mm"] = float(u_step[j]) * w_mean
        row["u_exact"] = float(u_exact[j])
        row["share_exact_pct"] = 100.0 * float(u_exact[j]) / n
        if w_mean is not None:
            row["w_exact_N_per_mm"] = float(u_exact[j]) * w_mean
            row["twist_mrad"] = float(twist[j])
        row["unloaded"] = (j + 1) in unloaded
        detail_rows.append(row)
    detail = {"rows": detail_rows}

    K_for_mass = K
    if design.has("bridges"):
        K_bal = _bridges(design, geo, s, detail, warnings, failed, kappa_for, C, E, nu, R, np)
        if K_bal is not None:
            K_for_mass = K_bal
    if design.has("mass"):
        unev = design["mass.unevenness"]
        K_m = K_for_mass if unev == "computed" else unev
        if K_m is None:
            raise DesignError("mass.unevenness", "= \"computed\": K is not available for this design "
                              "(K_balanced is undefined at kappa >= 8); give a number")
        lo, hi = design["mass.ratio_range"]
        args = dict(rows=n, planets_per_row=nw, wall_ratio=design["mass.wall_ratio"],
                    sun_fill=design["mass.sun_fill"], planet_fill=design["mass.planet_fill"], cheek_ratio=bbar,
                    allowable_contact=design["mass.allowable_contact_MPa"], density=design["mass.density_kg_m3"],
                    youngs_modulus=E, poisson=nu, efficiency=design["mass.efficiency"], unevenness=K_m,
                    pressure_angle=geo["alpha"])
        opt = minimize_golden(lambda i: R.relative_mass(i, **args), lo, hi, rtol=options.tol)
        i_opt, i_err = float(opt.x), float(opt.err)
        ratio = geo["ratio"] if geo["ratio"] is not None else i_opt
        s["relative_mass_kg_per_kNm"] = float(R.relative_mass(ratio, **args))
        s["ratio"] = ratio
        s["ratio_opt"] = i_opt
        s["ratio_opt_err"] = i_err
        s["ratio_opt_on_bound"] = bool(opt.on_bound)
        s["relative_mass_min_kg_per_kNm"] = float(opt.fun)
        s["mass_unevenness"] = float(K_m)
        if opt.on_bound:
            warnings.append(f"the mass minimum lies on an end of mass.ratio_range = [{lo!r}, {hi!r}]: widen it")
    return Result(summary=s, detail=detail, warnings=warnings, failed=failed, model=model)


def _bridges(design, geo, s, detail, warnings, failed, kappa_for, C, E, nu, R, np):
    """Size the bridges, verify the sized carrier; fills the summary; returns K_balanced."""
    n, nw = geo["n"], design["rows.planets_per_row"]
    b_w, bbar = geo["b_w"], geo["cheek_ratio"]
    first = design["bridges.first_span"]
    first_mm = None if first == "axes_only" else float(first)
    d_size = torsion_diameter(design["bridges.torsion_diameter"], geo)
    bore = design["sun.bore_mm"]
    res = R.size_bridges(n, nw, geo["d_a"], design["gear.module_mm"], b_w, geo["b"], geo["alpha"], geo["ratio"],
                         design["bridges.axle_diameter_mm"], design["bridges.bridge_thickness_mm"], E, nu,
                         R.polar_moment(d_size, bore), first_span=first_mm)
    H, H_max, flags = res["H"], res["H_max"], res["flags"]
    if first_mm is not None and H_max > 0 and first_mm > H_max:
        raise DesignError("bridges.first_span", f"= {first_mm!r}: must be <= H_max = {H_max:.6g} mm, the widest "
                          "bridge that fits between neighbouring planets")
    rel = H / H_max if H_max > 0 else np.zeros(n)
    s["bridge_max_mm"] = max(H_max, 0.0)
    s["bridge_torsion_diameter_mm"] = d_size
    for j in range(n):
        s[f"bridge_rel_{j + 1}"] = float(rel[j])
    for j in range(n):
        s[f"bridge_{j + 1}_mm"] = float(H[j])
    feasible = all(f == "ok" for f in flags)
    s["bridges_feasible"] = feasible
    if not feasible:
        failed.append(_bridge_failure(design, flags, H_max, R))
    # verification: stepwise with the compliant carrier, each sun stiffness reading
    Fscale = 2.0 * b_w * math.cos(geo["alpha"])  # F = 2 w b_w cos α_w
    Y = R.carrier_matrix(res["a_w"], nw, res["stiffness"], n) * Fscale * C  # C y / w̄ = Y u
    results = {}
    for label, d_i in (("sized", d_size), ("pitch", geo["d_a"]), ("root", geo["d_f"])):
        kap = kappa_for(d_i)
        if n > 1 and kap >= R.KAPPA_STEPWISE_MAX:
            results[label] = None
            continue
        u, unloaded, ok, resid = R.stepwise_active_set(kap, bbar, n, carrier=Y)
        if not ok:
            warnings.append(f"the active-set verification ({label} diameter) did not settle within 3n iterations")
            results[label] = None
            continue
        results[label] = (u, unloaded, resid)
    if results["sized"] is None:
        warnings.append("K_balanced is not available: the stepwise verification is invalid at kappa >= 8 "
                        "with the sizing diameter; the bridge widths are still reported")
    K_bal = None if results["sized"] is None else float(results["sized"][0].max())
    s["K_balanced"] = K_bal
    s["K_balanced_pitch"] = None if results["pitch"] is None else float(results["pitch"][0].max())
    s["K_balanced_root"] = None if results["root"] is None else float(results["root"][0].max())
    s["unloaded_rows_balanced"] = [] if results["sized"] is None else results["sized"][1]
    u_bal = None if results["sized"] is None else results["sized"][0]
    detail["bridges"] = [
        {"span": j + 1, "D": float(res["D"][j]), "H_mm": float(H[j]), "H_rel": float(rel[j]), "flag": flags[j],
         "u_balanced": None if u_bal is None else float(u_bal[j])}
        for j in range(n)
    ]
    return K_bal


BRIDGE_FLAG_TEXT = {
    "exceeds_max": "needs a stiffer bridge than the widest that fits between neighbouring planets",
    "axes_too_stiff": "the planet axes alone are stiffer than equal sharing needs (a bridge only stiffens)",
    "no_room": "has no room for a bridge between neighbouring planets",
}


def _bridge_failure(design, flags, H_max, R) -> str:
    """The failed bridge check in a designer's words: which span, why, H_max, and the widest feasible rows."""
    spans = "; ".join(f"span {j + 1} {BRIDGE_FLAG_TEXT.get(f, f)} ({f})" for j, f in enumerate(flags) if f != "ok")
    text = f"the bridges cannot equalise the rows: {spans} (H_max = {H_max:.4g} mm)"
    B_ok = _largest_feasible_width(design, R)
    if B_ok is not None:
        text += f"; rows.relative_width <= {math.floor(B_ok * 1000) / 1000:g} makes every bridge fit"
    return text


def _largest_feasible_width(design, R, iterations: int = 40):
    """The largest relative width B (below the design's) at which every bridge can be sized, by bisection
    (narrower rows twist less); None when even a very narrow gear is infeasible or the rim is given in mm."""
    import copy

    if design.get("rows.rim_width_mm") is not None:
        return None

    def ok(B):
        trial = copy.copy(design)
        trial.values = {t: dict(v) for t, v in design.values.items()}
        trial.values["rows"]["relative_width"] = B
        geo = geometry(trial)
        if geo["b_w"] <= 0:
            return False
        for key in ("axle_diameter_mm", "bridge_thickness_mm"):  # derived from b_w unless given (as check())
            if not design.is_given(f"bridges.{key}"):
                trial.values["bridges"][key] = 0.5 * geo["b_w"]
        first = design["bridges.first_span"]
        res = R.size_bridges(geo["n"], design["rows.planets_per_row"], geo["d_a"], design["gear.module_mm"],
                             geo["b_w"], geo["b"], geo["alpha"], geo["ratio"], trial["bridges.axle_diameter_mm"],
                             trial["bridges.bridge_thickness_mm"], design["material.E_MPa"],
                             design["material.poisson"],
                             R.polar_moment(torsion_diameter(design["bridges.torsion_diameter"], geo),
                                            design["sun.bore_mm"]),
                             first_span=None if first == "axes_only" else float(first))
        return all(f == "ok" for f in res["flags"])

    hi = geometry(design)["B"]
    for k in range(1, 91):  # scan down in 1 % steps to a tenth of the width for the first feasible width
        lo = hi * (1.0 - 0.01 * k)
        if ok(lo):
            break
        hi_scan = lo
    else:
        return None
    hi = hi if k == 1 else hi_scan
    for _ in range(iterations):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if ok(mid) else (lo, mid)
        if hi - lo <= 1e-6 * hi:
            break
    return lo


FAST_SWEEP_KEYS = {
    "gear.sun_teeth", "gear.module_mm", "gear.pressure_angle_deg", "gear.ratio", "rows.count",
    "rows.planets_per_row", "rows.relative_width", "rows.rim_width_mm", "rows.cheek_ratio", "rows.cheek_mm",
    "sun.torque_Nm", "sun.torsion_diameter", "sun.bore_mm", "material.E_MPa", "material.poisson",
    "material.mesh_stiffness_MPa", "mass.wall_ratio", "mass.sun_fill", "mass.planet_fill",
    "mass.allowable_contact_MPa", "mass.density_kg_m3", "mass.efficiency", "mass.unevenness",
}


def sweep(base, raw, axes, points, options):
    """The summaries of a whole grid as columns (no Python loop per point; rows.md §9).

    Points are grouped by the number of rows n; each group is one batch of the recurrence, the
    impedance sweep and the closed forms, and the mass optimum is one vectorised golden-section
    search.  Designs with [bridges] (dense verification solves per point) or varied keys outside
    ``FAST_SWEEP_KEYS`` return None: the caller evaluates them point by point.
    """
    import numpy as np

    from ..arrays import unique_sorted

    from .. import rows as R
    from ..roots import minimize_golden

    if base.has("bridges") or any(k not in FAST_SWEEP_KEYS for k in axes):
        return None
    if base.has("mass") and (base["mass.unevenness"] == "computed" or "mass.unevenness" in axes
                             and any(isinstance(v, str) for v in axes["mass.unevenness"])):
        return None
    P = len(points)

    def col(key, default=None):
        if key in axes:
            vals = points.column(key) if hasattr(points, "column") else [p[key] for p in points]
            if key == "sun.torsion_diameter":
                return vals
            return np.array(vals, dtype=float)
        v = base.get(key, default)
        return v if isinstance(v, str) or v is None else np.full(P, float(v))

    n = col("rows.count").astype(int)
    nw = col("rows.planets_per_row")
    za, m = col("gear.sun_teeth"), col("gear.module_mm")
    d_a = za * m
    d_f = d_a - 2.5 * m
    alpha = np.radians(col("gear.pressure_angle_deg"))
    r_ba = 0.5 * d_a * np.cos(alpha)
    cheek_mm = col("rows.cheek_mm")
    if base.get("rows.rim_width_mm") is not None:
        b_w = col("rows.rim_width_mm")
        bbar = cheek_mm / b_w if cheek_mm is not None else col("rows.cheek_ratio")
        B = (n * b_w + (n - 1) * bbar * b_w) / d_a
    else:
        B = col("rows.relative_width")
        if cheek_mm is not None:
            b_w = (B * d_a - (n - 1) * cheek_mm) / n
            if np.any(b_w <= 0):
                where = points[int(np.argmax(b_w <= 0))]
                raise DesignError("rows.cheek_mm", f"the cheeks leave no room for the rims at {where}")
            bbar = cheek_mm / b_w
        else:
            bbar = col("rows.cheek_ratio")
            b_w = B * d_a / (n + bbar * (n - 1))
    tdia = col("sun.torsion_diameter")
    if isinstance(tdia, str) or isinstance(tdia, list):
        words = [tdia] * P if isinstance(tdia, str) else tdia
        d_i = np.array([d_a[k] if w == "pitch" else d_f[k] if w == "root" else float(w) for k, w in enumerate(words)])
    else:
        d_i = tdia
    bore = col("sun.bore_mm")
    bad = bore >= np.minimum(d_f, d_i)
    if np.any(bad):
        raise DesignError("sun.bore_mm", f"must be < min(d_f, d_I) at {points[int(np.argmax(bad))]}")
    E, nu = col("material.E_MPa"), col("material.poisson")
    C = col("material.mesh_stiffness_MPa") if base.is_given("material.mesh_stiffness_MPa") or \
        "material.mesh_stiffness_MPa" in axes else 0.075 * E
    G = E / (2.0 * (1.0 + nu))
    kappa = R.torsion_parameter(C, r_ba, nw, b_w, G, R.polar_moment(d_i, bore))
    K_step = np.full(P, np.nan)
    K_exact = np.ones(P)
    peak = np.ones(P)
    valid = np.ones(P, bool)
    K_row_step = np.ones(P, int)
    model = options.model or "stepwise"
    unloaded = [[]] * P  # one shared empty list: entries with unloaded rows are replaced, never appended to
    for nn in unique_sorted(n):
        idx = np.flatnonzero(n == nn)
        u, ok = R.stepwise_shares(kappa[idx], bbar[idx], int(nn))
        ue, pk = R.exact_shares(kappa[idx], bbar[idx], int(nn))
        valid[idx] = ok
        K_step[idx] = np.where(ok, u.max(axis=-1), np.nan)
        K_row_step[idx] = np.argmax(u, axis=-1) + 1
        K_exact[idx] = ue.max(axis=-1)
        peak[idx] = pk
        if nn > 1:  # rows.md §13.4: unloaded when the load of the level supplying K is <= 1e-12 w̄
            u_used = ue if model != "stepwise" else np.where(ok[:, None], u, ue)
            for k in np.flatnonzero(np.any(u_used <= 1e-12, axis=-1)):
                unloaded[idx[k]] = (np.flatnonzero(u_used[k] <= 1e-12) + 1).tolist()
    K_cont = R.continuous_k(kappa, bbar, n)
    one = n == 1
    K_step = np.where(one, 1.0, K_step)
    K_exact = np.where(one, 1.0, K_exact)
    K_cont = np.where(one, 1.0, K_cont)
    use_exact = (model == "exact") | ((model == "stepwise") & ~valid)
    if model == "continuous":
        K = K_cont
    else:
        K = np.where(use_exact, K_exact, K_step)
    models = np.where(model == "continuous", "continuous", np.where(use_exact, "exact", "stepwise"))
    K_row = np.where(use_exact | (model == "continuous"), 1, K_row_step)
    defined = valid | one  # the stepwise level exists (rows.md §6); elsewhere its columns are None

    def where_defined(values):  # a column that is None where the stepwise level does not exist
        out = values.tolist()
        if not defined.all():
            for k in np.flatnonzero(~defined).tolist():
                out[k] = None
        return out

    cols = {
        "name": [base.name] * P, "rows": n.tolist(), "planets_per_row": nw.astype(int).tolist(),
        "relative_width": B.tolist(), "rim_width_mm": b_w.tolist(), "cheek_ratio": bbar.tolist(),
        "torsion_diameter_mm": d_i.tolist(), "kappa": kappa.tolist(), "model": models.tolist(), "K": K.tolist(),
        "K_row": K_row.tolist(),
        "K_stepwise": where_defined(K_step),
        "stepwise_valid": defined.tolist(), "K_exact": K_exact.tolist(), "K_continuous": K_cont.tolist(),
        "K_stepwise_vs_exact_pct": where_defined(100.0 * (np.nan_to_num(K_step) / K_exact - 1.0)),
        "K_vs_continuous_pct": (100.0 * (K / K_cont - 1.0)).tolist(), "peak_factor": peak.tolist(),
        "row1_face_factor": (peak / K_exact).tolist(), "unloaded_rows": unloaded,
    }
    T_a = col("sun.torque_Nm")
    if T_a is not None:
        w_mean = T_a * 1000.0 / (n * r_ba * b_w * nw)
        cols["w_mean_N_per_mm"] = w_mean.tolist()
        cols["w_max_N_per_mm"] = (K * w_mean).tolist()
        cols["w_peak_N_per_mm"] = (peak * w_mean).tolist()
    if base.has("mass"):
        lo, hi = base["mass.ratio_range"]
        args = dict(rows=n, planets_per_row=nw, wall_ratio=col("mass.wall_ratio"), sun_fill=col("mass.sun_fill"),
                    planet_fill=col("mass.planet_fill"), cheek_ratio=bbar,
                    allowable_contact=col("mass.allowable_contact_MPa"), density=col("mass.density_kg_m3"),
                    youngs_modulus=E, poisson=nu, efficiency=col("mass.efficiency"),
                    unevenness=col("mass.unevenness"), pressure_angle=alpha)
        opt = minimize_golden(lambda i: R.relative_mass(i, **args), np.full(P, lo), np.full(P, hi), rtol=options.tol)
        ratio = col("gear.ratio")
        ratio = opt.x if ratio is None else ratio
        cols["relative_mass_kg_per_kNm"] = R.relative_mass(ratio, **args).tolist()
        cols["ratio"] = np.asarray(ratio, float).tolist()
        cols["ratio_opt"] = opt.x.tolist()
        cols["ratio_opt_err"] = opt.err.tolist()
        cols["ratio_opt_on_bound"] = opt.on_bound.tolist()
        cols["relative_mass_min_kg_per_kNm"] = opt.fun.tolist()
        cols["mass_unevenness"] = col("mass.unevenness").tolist()
    return cols  # column-major: the sweep writes it without building a dict per point


def plot(records, path: str) -> None:
    """Row loads (stepwise and exact, as u = w/w̄) at the row centres along the sun face, with the
    continuous level's load profile u(x) = X cosh(X(1 - x/b_a)) / sinh X; one panel per design (up to 4)."""
    import numpy as np

    from ..plot import _pyplot, save

    plt = _pyplot()
    recs = records[:4]
    fig, axes = plt.subplots(len(recs), 1, figsize=(7.5, 3.6 * len(recs)), squeeze=False)
    for ax, rec in zip(axes[:, 0], recs):
        s = rec.result.summary
        n, bbar = s["rows"], s["cheek_ratio"]
        L = n + bbar * (n - 1)  # face length in units of b_w
        centres = (np.arange(n) * (1 + bbar) + 0.5) / L
        rows = rec.result.detail["rows"]
        width = 0.35 / L
        if s["stepwise_valid"] and n > 1:
            ax.bar(centres - width / 2, [r["u_stepwise"] for r in rows], width, label="stepwise (row mean)")
        ax.bar(centres + width / 2, [r["u_exact"] for r in rows], width, label="exact (row mean)")
        X = np.sqrt(s["kappa"] / (1 + bbar)) * L if n > 1 else np.sqrt(s["kappa"])
        xi = np.linspace(0, 1, 400)
        if X > 1e-6:
            prof = X * (np.exp(-X * xi) + np.exp(-X * (2 - xi))) / -np.expm1(-2 * X)
        else:
            prof = np.ones_like(xi)
        ax.plot(xi, prof, "k-", lw=1.2, label=f"continuous profile (K = {s['K_continuous']:.3f})")
        ax.axhline(1.0, color="grey", lw=0.8, ls=":")
        ax.set_xlim(0, 1)
        ax.set_xlabel("position along the sun face from the input, x / b_a [-]")
        ax.set_ylabel("line load / mean, w / w_mean [-]")
        ax.set_title(f"{rec.name}: K = {s['K']:.4g} ({s['model']}), n = {n}, n_w = {s['planets_per_row']}")
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8)
    save(fig, path)


CALCULATOR = Calculator(
    kind="rows",
    title="multi-row planetary gear: row load sharing, equalising carrier bridges, relative mass",
    tables=TABLES,
    compute=compute,
    check=check,
    models=("stepwise", "exact", "continuous"),
    header="Seed paper 004_971077b94d8d4426.txt; physics in rows.md. Lengths in mm, torque in N*m, stresses in MPa.",
    sweep=sweep,
    table_fields=("K", "K_exact", "bridges_feasible", "K_balanced", "relative_mass_min_kg_per_kNm"),
    sweep_plot=("relative_mass_kg_per_kNm", "K"),
    failure=(("bridges_feasible", False),),
    plot=plot,
)
