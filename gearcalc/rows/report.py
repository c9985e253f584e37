"""The words of the ``rows`` calculator: summary field names, detail rows and warning texts (rows.md §8, §13).

No physics here: the values come from :mod:`gearcalc.rows`; the adapter (gearcalc/kinds/rows.py) passes them
in.  A field builder takes ``plain``, which turns a value of one design (:func:`one`) or a column of a sweep
(:func:`columns`) into output, None where the stepwise level does not exist.
"""
from __future__ import annotations

__all__ = ["one", "columns", "sharing_fields", "load_fields", "mass_fields", "detail_rows", "BRIDGE_FLAG_TEXT",
           "bridge_failure", "bridge_fields", "STEPWISE_UNAVAILABLE", "LEVELS_DIFFER", "MASS_ON_BOUND", "UNSETTLED",
           "K_BALANCED_UNAVAILABLE", "CHECKS", "margin_fields"]

STEPWISE_UNAVAILABLE = ("the stepwise level is not available at kappa = {kappa:.6g} >= 8 (the half-row twist "
                        "outweighs the mesh compliance): K comes from the exact level")
LEVELS_DIFFER = ("the stepwise and exact levels differ by {pct:+.3g} % (> 2 %): the paper's uniform-within-a-row "
                 "assumption is strained; consider --model exact")
MASS_ON_BOUND = "the mass minimum lies on an end of mass.ratio_range = [{lo!r}, {hi!r}]: widen it"
UNSETTLED = "the active-set verification ({label} diameter) did not settle within 3n iterations"
K_BALANCED_UNAVAILABLE = ("K_balanced is not available: the stepwise verification is invalid at kappa >= 8 with the "
                          "sizing diameter; the bridge widths are still reported")


# ------------------------------------------------------------------ the texts of check() (rows.md §7, §8)

def width_choice(both: bool) -> str:
    return "give exactly one of rows.relative_width (B) and rows.rim_width_mm (b_w)" + (", not both" if both else "")


def ratio_disagrees(i, z_g, i_teeth: float) -> str:
    return f"= {i!r} disagrees with gear.planet_teeth = {z_g} (2 + 2 z_g/z_a = {i_teeth:.6g}); give one of them"


def no_room_for_rims(cheek, b_a: float) -> str:
    return f"= {cheek!r}: the cheeks leave no room for the rims in b_a = B d_a = {b_a:.6g} mm"


def bore_too_large(bore, d_f: float, d_i: float) -> str:
    return (f"= {bore!r}: must be < min(root diameter d_f = {d_f:.6g}, torsion diameter d_I = {d_i:.6g}) = "
            f"{min(d_f, d_i):.6g} mm (a bore cannot cut the tooth roots)")


def rim_too_thin(rim: float, min_rim: float) -> str:
    return (f"the rim under the sun's tooth roots, (d_f - d_0)/2 = {rim:.4g} mm, is thinner than 1.2 tooth depths "
            f"(2.7 m = {min_rim:.4g} mm) [ISO 6336-3]: the teeth and rim may not carry as modelled")


def not_integer_planets(i, z_g: float) -> str:
    return (f"gear.ratio = {i!r} gives z_g = z_a (i - 2)/2 = {z_g:.6g} planet teeth, not an integer: not a "
            "realisable gear (the formulas stay continuous in i)")


def planets_collide(z_g: float, room: float) -> str:
    return f"the planets collide: z_g + 2 = {z_g + 2:.6g} >= (z_a + z_g) sin(pi/n_w) = {room:.6g} (adjacency condition)"


def first_span_too_wide(first: float, H_max: float) -> str:
    return f"= {first!r}: must be <= H_max = {H_max:.6g} mm, the widest bridge that fits between neighbouring planets"


BRIDGES_NEED_RATIO = "missing; [bridges] needs the ratio (give gear.ratio or gear.planet_teeth)"
ONE_PLANET = "one planet per row: sun bending and the unbalanced radial load are not modelled"
WIDE = "relative width B = {B:.4g} is far outside the paper's range (B <= 10)"
UNEVENNESS_UNAVAILABLE = ("= \"computed\": K is not available for this design (K_balanced is undefined at kappa >= 8); "
                          "give a number")


def one(value, defined=True):
    """A 0-d value of one design as a plain Python scalar (None where not defined)."""
    return (value.tolist() if hasattr(value, "tolist") else value) if defined else None


def columns(points: int):
    """``plain`` for a sweep of that many points: a list per field, None where not defined; a column of floats,
    ints or flags defined everywhere is a numpy array (its own copy) instead, which the CSV writer formats
    without a list (:meth:`gearcalc.render.Columns.lists` gives the list), and a column of one word is a list of
    one str object (the CSV writer sees a constant at once: ``list.count`` compares identical objects first)."""
    import numpy as np

    def column(values, defined=None):
        values = np.broadcast_to(values, (points,))
        if defined is None or np.all(defined):
            if values.dtype == np.float64 or values.dtype.kind in "iub":
                return np.array(values)
            if values.dtype.kind == "U" and points and bool((values == values[0]).all()):
                return [str(values[0])] * points
        if defined is not None and not np.any(defined):  # defined nowhere (e.g. the rim of a solid sun)
            return [None] * points
        out = values.tolist()
        for k in [] if defined is None else np.flatnonzero(~defined).tolist():
            out[k] = None
        return out

    return column


def sharing_fields(name, n, nw, f, d_i, kappa, sh, plain):
    """The load-sharing summary fields; ``plain(values, defined=None)`` turns a value (compute) or a column
    (sweep) into output, None where ``defined`` is False (the stepwise level does not exist)."""
    import numpy as np

    K_step = np.where(sh.stepwise_valid, sh.K_stepwise, np.nan)
    return {"name": name, "rows": plain(n), "planets_per_row": plain(nw), "relative_width": plain(f.relative_width),
            "rim_width_mm": plain(f.rim_width), "cheek_ratio": plain(f.cheek_ratio),
            "torsion_diameter_mm": plain(d_i), "kappa": plain(kappa), "model": plain(sh.level), "K": plain(sh.K),
            "K_row": plain(sh.K_row), "K_stepwise": plain(K_step, sh.stepwise_valid),
            "stepwise_valid": plain(sh.stepwise_valid), "K_exact": plain(sh.K_exact),
            "K_continuous": plain(sh.K_continuous),
            "K_stepwise_vs_exact_pct": plain(100.0 * (np.nan_to_num(K_step) / sh.K_exact - 1.0), sh.stepwise_valid),
            "K_vs_continuous_pct": plain(100.0 * (sh.K / sh.K_continuous - 1.0)), "peak_factor": plain(sh.peak_factor),
            "row1_face_factor": plain(sh.peak_factor / sh.K_exact)}


def load_fields(w, sh, plain) -> dict:
    """The line-load fields from the mean line load w̄ [N/mm]."""
    return {"w_mean_N_per_mm": plain(w), "w_max_N_per_mm": plain(sh.K * w),
            "w_peak_N_per_mm": plain(sh.peak_factor * w)}


def mass_fields(m, unevenness, plain) -> dict:
    """The fields of :func:`gearcalc.rows.mass.mass_and_optimum`."""
    return {"relative_mass_kg_per_kNm": plain(m.relative_mass), "ratio": plain(m.ratio),
            "ratio_opt": plain(m.ratio_opt),
            "ratio_opt_err": plain(m.ratio_opt_err), "ratio_opt_on_bound": plain(m.ratio_opt_on_bound),
            "relative_mass_min_kg_per_kNm": plain(m.relative_mass_min), "mass_unevenness": plain(unevenness)}


def detail_rows(sh, n: int, w_mean, twist, unloaded) -> list[dict]:
    """The per-row detail table of one design: shares, line loads, twist, unloaded mark (rows.md §8)."""
    rows = []
    for j in range(n):
        row = {"row": j + 1}
        if bool(sh.stepwise_valid):
            row["u_stepwise"] = float(sh.u_stepwise[j])
            row["share_stepwise_pct"] = 100.0 * float(sh.u_stepwise[j]) / n
            if w_mean is not None:
                row["w_stepwise_N_per_mm"] = float(sh.u_stepwise[j]) * w_mean
        row["u_exact"] = float(sh.u_exact[j])
        row["share_exact_pct"] = 100.0 * float(sh.u_exact[j]) / n
        if w_mean is not None:
            row["w_exact_N_per_mm"] = float(sh.u_exact[j]) * w_mean
            row["twist_mrad"] = float(twist[j])
        row["unloaded"] = (j + 1) in unloaded
        rows.append(row)
    return rows


BRIDGE_FLAG_TEXT = {
    "exceeds_max": "needs a stiffer bridge than the widest that fits between neighbouring planets",
    "axes_too_stiff": "the planet axes alone are stiffer than equal sharing needs (a bridge only stiffens)",
    "no_room": "has no room for a bridge between neighbouring planets",
}


def bridge_failure(flags, H_max, hint=None) -> str:
    """The failed bridge check in a designer's words: which span, why, H_max, and where every bridge fits.

    ``hint``: (n, windows of B at n, another n or None, its windows), from
    :func:`gearcalc.rows.feasible_widths` and :func:`gearcalc.rows.feasible_rows`; the nearest window is said,
    its bounds rounded inward (each a width that fits).

    >>> text = bridge_failure(["ok", "ok", "exceeds_max"], 134.26, (3, [(2.66562, 2.97387)], None, []))
    >>> text[text.index("(H_max"):]
    '(H_max = 134.3 mm); every bridge fits for rows.relative_width from 2.666 to 2.973 (rows.count = 3)'
    >>> text = bridge_failure(["ok", "exceeds_max", "ok", "exceeds_max", "ok"], 150.0, (5, [], 4, [(3.9991, 4.0364)]))
    >>> text[text.index("; no"):text.index(" (widths")]
    '; no rows.relative_width makes every bridge fit with rows.count = 5'
    >>> text[text.index("tried); "):]
    'tried); rows.count = 4 does, for rows.relative_width from 4.000 to 4.036'
    """
    spans = "; ".join(f"span {j + 1} {BRIDGE_FLAG_TEXT.get(f, f)} ({f})" for j, f in enumerate(flags) if f != "ok")
    text = f"the bridges cannot equalise the rows: {spans} (H_max = {H_max:.4g} mm)"
    if hint is None:
        return text
    n, windows, other, other_windows = hint
    if windows:
        return text + f"; every bridge fits for rows.relative_width {_window(windows[0])} (rows.count = {n})"
    text += f"; no rows.relative_width makes every bridge fit with rows.count = {n} (widths from B/30 to 30 B tried)"
    if other is None:
        return text + f", nor with rows.count = 2 to {n + 10}"
    return text + f"; rows.count = {other} does, for rows.relative_width {_window(other_windows[0])}"


def _window(window) -> str:
    """A window of relative widths in words, its bounds rounded inward to 3 decimals (more when it is narrower).

    >>> _window((2.66562, 2.97387)), _window((None, 0.51)), _window((12.00049, None)), _window((1.00012, 1.00031))
    ('from 2.666 to 2.973', '<= 0.51', '>= 12.001', 'from 1.0002 to 1.0003')
    """
    import math

    lo, hi = window
    for digits in range(3, 13):
        scale = 10.0**digits
        up = None if lo is None else math.ceil(lo * scale) / scale
        down = None if hi is None else math.floor(hi * scale) / scale
        if up is None or down is None or up <= down:
            break
    if lo is None:
        return f"<= {down:.{digits}f}".rstrip("0").rstrip(".")
    if hi is None:
        return f">= {up:.{digits}f}"
    return f"from {up:.{digits}f} to {down:.{digits}f}"


CHECKS = (("bridge_fit", "a span's bridge does not fit between 0 and H_max"),
          ("bore", "sun bore >= min(d_f, d_I)"), ("rim", "rim under the roots < 2.7 m"))
"""The design checks (name, what a failing point breaks), rows.md §8: their margins are margin_<name>."""


def margin_fields(fit, bore, rim, plain, n: int | None = None) -> dict:
    """margin_bore, margin_rim (None for a solid sun, where ``rim`` is NaN) and failed_checks, with the bridge fit
    ``fit`` (margin_bridge_fit, a field of :func:`bridge_fields`; None without [bridges]); ``plain`` makes the
    values of one design (:func:`one`, ``n`` None) or the columns of ``n`` points (:func:`columns`)."""
    import numpy as np

    from ..calculator import Check, failed_check_column

    out = {"margin_bore": plain(bore), "margin_rim": plain(rim, ~np.isnan(rim))}
    margins = {**out, "margin_bridge_fit": fit}
    if n is None:
        out["failed_checks"] = failed_check_column({k: [v] for k, v in margins.items()},
                                                   [Check(*c) for c in CHECKS], 1)[0]
    else:
        out["failed_checks"] = failed_check_column(margins, [Check(*c) for c in CHECKS], n)
    return out


def bridge_fields(res, sizing_diameter, verified) -> tuple[dict, list[dict]]:
    """The bridge summary fields and detail rows (rows.md §8) from :func:`gearcalc.rows.size_bridges` and the
    :class:`~gearcalc.rows.bridges.Verification` of each sun reading (``sized``, ``pitch``, ``root``)."""
    H, rel, n = res["H"], res["H_rel"], len(res["H"])
    s = {"bridge_max_mm": max(res["H_max"], 0.0), "bridge_torsion_diameter_mm": sizing_diameter}
    s.update({f"bridge_rel_{j + 1}": float(rel[j]) for j in range(n)})
    s.update({f"bridge_{j + 1}_mm": float(H[j]) for j in range(n)})
    sized = verified["sized"]
    u_bal = None if sized.K is None else sized.shares
    s.update(bridges_feasible=res["feasible"], margin_bridge_fit=res["margin"], K_balanced=sized.K,
             K_balanced_pitch=verified["pitch"].K,
             K_balanced_root=verified["root"].K, unloaded_rows_balanced=[] if u_bal is None else sized.unloaded)
    detail = [{"span": j + 1, "D": float(res["D"][j]), "H_mm": float(H[j]), "H_rel": float(rel[j]),
               "flag": res["flags"][j], "u_balanced": None if u_bal is None else float(u_bal[j])} for j in range(n)]
    return s, detail
