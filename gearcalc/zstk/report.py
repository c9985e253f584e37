"""The words of the ``zstk`` calculator: summary field names, detail rows, warning and failure texts (zstk.md §10).

No physics here: the values come from :mod:`gearcalc.zstk.outputs` and :mod:`gearcalc.zstk.solve`; the adapter
(gearcalc/kinds/zstk.py) passes them in.  Imports no numpy at import time (``check`` and ``new`` read the texts).
"""
from __future__ import annotations

import math

from ..units import UM_PER_MM, rad_to_deg
from .schema import B_OVER_RHO_LIMIT, DEFAULT_ALLOWABLE_MPA, DEFAULT_ALLOWABLE_SOURCE

__all__ = ["SEPARATOR_MESSAGE", "DEFAULT_ALLOWABLE_WARNING", "cost_message", "wrap_deg", "sweep_fields",
           "summary_fields", "detail_rows", "warnings", "messages"]

SEPARATOR_MESSAGE = ("= false: rollers without a separator are not modelled. The rollers' tangential reactions "
                     "F_iB·sin(beta_i) would then be carried by roller-to-roller contacts (possible only with "
                     "roller_gap_mm = 0), a statically indeterminate closed chain that needs every roller's own "
                     "displacement; gearcalc models the separator only (zstk.md §5.5). Use separator = true "
                     "(roller_gap_mm may be 0)")
DEFAULT_ALLOWABLE_WARNING = (f"no material.allowable_stress_MPa: checked against {DEFAULT_ALLOWABLE_MPA:g} MPa "
                             f"({DEFAULT_ALLOWABLE_SOURCE}), a static (permanent-deformation) reference, "
                             "not an endurance allowable")


def cost_message(rollers, n: int, cycle: bool, envelope: bool, reference: bool, work, budget) -> str:
    """The refusal of a design whose sweeps would cost ``work`` roller-configurations, over ``budget``.

    >>> cost_message("auto", 1619, True, True, True, 8.08e7, 6e6)[:40]
    '= "auto": N = 1619 rollers with geometry'
    """
    what = " + ".join(w for w, on in (('geometry.scheme = "cycle"', cycle),
                                       ('load.direction_deg = "envelope"', envelope)) if on)
    shown = f'"{rollers}"' if isinstance(rollers, str) else rollers
    return (f"= {shown}: N = {n} rollers with {what}{' at --model reference' if reference else ''} need {work:.3g} "
            f"roller-configurations, over the budget of {budget:.3g} (~10 s): fewer rollers, or one sweep at a time "
            "(a fixed scheme or a fixed load direction)")


def wrap_deg(x_rad):
    """Degrees in (-180, 180] (arrays or floats); round-off just above -180 is shown as 180.

    >>> wrap_deg(-3.141592653589793).tolist(), wrap_deg(-0.0).tolist()
    (180.0, 0.0)
    """
    import numpy as np

    from .geometry import wrap_angle

    d = rad_to_deg(wrap_angle(x_rad))
    return np.where(d <= -180.0 + 1e-9, 180.0, d + 0.0)  # + 0.0: no -0.0


def sweep_fields(placement, cap: int) -> tuple[dict, list]:
    """The sweep fields (samples and step of the phase and direction sweeps, None where not swept) of a
    :class:`gearcalc.zstk.Placement`, and a note for each sweep stopped at the grid's ``cap``."""
    notes, fields = [], {}
    for what, per, sw in (("phase", "pitch", placement.phase_sweep), ("direction", "turn", placement.direction_sweep)):
        fields[f"{what}_samples"] = None if sw is None else sw.samples
        fields[f"{what}_step_deg"] = None if sw is None else float(rad_to_deg(sw.step))
        if sw is not None and sw.capped and getattr(sw, "floor", False):
            notes.append(f"{what} sweep's refinement reached the round-off of the angles with error "
                         f"{sw.err:.3g} MPa above the target")
        elif sw is not None and sw.capped:
            notes.append(f"{what} sweep stopped at the cap of {cap} points per {per} with error "
                         f"{sw.err:.3g} MPa above the target")
    return fields, notes


def summary_fields(names, model: str, stack, out, sweep: dict, arrays: bool = False) -> dict:
    """The summary columns (field -> list over the G designs) of a :class:`gearcalc.zstk.solve.Stack` and its
    :class:`gearcalc.zstk.outputs.Outputs`; ``names`` a list over the designs or one name; ``sweep`` the
    :func:`sweep_fields` of a sweeping design (empty: None).  ``arrays`` (a sweep's columns): a column of
    float64, integers or flags is a numpy array of its own (the same values: ``.tolist()`` gives the list; the CSV
    and Parquet writers take it without a Python object a value)."""
    import numpy as np

    from .geometry import broadcast

    sm, chain, state = out.summary, stack.chain, stack.state
    size, n = state.radius.shape
    alpha_deg = np.mod(rad_to_deg(sm.approach_direction), 360.0)
    safety = out.safety.tolist()

    def col(v):
        v = broadcast(v, (size,))
        return np.array(v) if arrays and v.dtype in (np.float64, np.int64, np.bool_) else v.tolist()

    return {
        "name": names if isinstance(names, list) else [names] * size, "model": [model] * size,
        "scheme": stack.scheme.tolist(), "theta0_deg": col(wrap_deg(state.theta[:, 0])), "N": [n] * size,
        "N_star": col(chain.n_star), "N_admissible_max": out.admissible_max,
        "correction": col(chain.correct), "outer_raceway_radius_mm": col(chain.outer_radius),
        "inner_raceway_radius_mm": col(chain.inner_radius), "roller_gap_mm": col(chain.gap),
        "nominal_mm": col(chain.nominal), "correction_mm": col(chain.corrected - chain.nominal),
        "r_min_mm": col(out.r_min), "r_max_mm": col(out.r_max),
        "sigma_max_MPa": col(sm.sigma_max), "sigma_max_err_MPa": col(sm.sigma_err),
        "sigma_max_contact": _contacts(sm.contact),
        "sigma_max_roller": col(sm.roller), "sigma_max_angle_deg": col(wrap_deg(sm.theta)),
        "sigma_max_roller_radius_mm": col(sm.radius), "sigma_max_load_direction_deg": col(wrap_deg(stack.gamma)),
        "tau_max_MPa": col(out.shear), "tau_max_depth_mm": col(out.shear_depth),
        "separator_force_max_N": col(np.max(out.separator, axis=-1)), "allowable_stress_MPa": col(stack.allowable),
        "allowable_stress_source": [DEFAULT_ALLOWABLE_SOURCE if d else "design" for d in
                                    stack.allowable_default.tolist()],
        "safety_factor": [v if ok else None for v, ok in zip(safety, (sm.sigma_max > 0).tolist())],
        "pass": col(out.passed), "radial_load_allowable_N": col(out.capacity.load),
        "radial_load_allowable_err_N": col(out.capacity.err), "approach_um": col(sm.approach * UM_PER_MM),
        "approach_direction_deg": col(np.where(alpha_deg >= 360.0, 0.0, alpha_deg)),
        "clearance_mm": col(stack.clearance), "loaded_rollers": col(sm.loaded),
        "solver_residual": col(sm.solver_residual), "transverse_residual": col(sm.transverse_residual),
        **{k: [sweep.get(k)] * size for k in ("phase_samples", "phase_step_deg", "direction_samples",
                                              "direction_step_deg")},
        "stepping_residual_mm": [None] * size if stack.stepping is None else col(stack.stepping),
        **margin_fields(out.margins, col),
    }


CHECKS = ("sigma", "sigma_max > allowable_stress"), ("closure", "N above the chain's N_max"), \
    ("clearance", "|clearance| >= r_min")
"""The design checks (name, what a failing point breaks), zstk.md §10: their margins are margin_<name>."""


def margin_fields(m, col) -> dict:
    """The summary's margins (margin_sigma, margin_closure, margin_clearance) and failed_checks, as columns."""
    from ..calculator import Check, failed_check_column

    cols = {"margin_sigma": col(m.sigma), "margin_closure": col(m.closure), "margin_clearance": col(m.clearance)}
    cols["failed_checks"] = failed_check_column(cols, [Check(*c) for c in CHECKS], len(cols["margin_sigma"]))
    return cols


def _contact(c) -> str:
    return "inner" if c == 0 else "outer"


def _contacts(contact) -> list:
    """:func:`_contact` of each design (an array (G,) of 0 inner, 1 outer): a list of the two words."""
    import numpy as np

    return np.array(["outer", "inner"], dtype=object)[(np.asarray(contact) == 0).astype(np.intp)].tolist()


def detail_rows(detail, separator) -> list[dict]:
    """The per-roller detail rows of G designs, a flat list (G x N, design by design), from a
    :class:`gearcalc.zstk.outputs.RollerDetail` and the separator forces (G, N) [N] (zstk.md §10)."""
    import numpy as np

    from .geometry import broadcast, wrap_angle
    from .stress import roller_field

    ct, r = detail.contacts, detail.rollers
    size, n = ct.sigma_inner.shape

    def get(name):
        return roller_field(r, name)

    table = {"i": broadcast(np.arange(n), (size, n)), "theta_deg": np.degrees(wrap_angle(get("theta"))),
             "r_mm": get("radius"), "psi_deg": np.degrees(get("psi")), "beta_deg": np.degrees(get("beta")),
             "F_B_N": ct.force_inner, "F_H_N": ct.force_outer, "F_S_N": separator, "rho_B_mm": ct.rho_inner,
             "rho_H_mm": ct.rho_outer, "sigma_B_MPa": ct.sigma_inner, "sigma_H_MPa": ct.sigma_outer,
             "b_B_mm": ct.width_inner, "b_H_mm": ct.width_outer, "tau_max_B_MPa": ct.shear_inner,
             "tau_max_H_MPa": ct.shear_outer, "tau_depth_B_mm": ct.shear_depth_inner,
             "tau_depth_H_mm": ct.shear_depth_outer}
    if detail.approach is None:
        table["gamma_B_deg"] = np.degrees(wrap_angle(detail.gamma_inner))
        table["gamma_H_deg"] = np.degrees(wrap_angle(detail.gamma_outer))
    else:
        table["delta_um"] = detail.approach * UM_PER_MM
    keys = list(table)
    flat = zip(*(broadcast(v, (size, n)).ravel().tolist() for v in table.values()))
    return [dict(zip(keys, vals)) for vals in flat]


def warnings(sm, g: int, clearance, fixed: bool, default_allowable, worst, stepping) -> list:
    """The warnings of design g of a :class:`gearcalc.zstk.Summary` (text only where there is something to say):
    the load solve's residual, the fixed-direction level's transverse force, the default allowable, b/rho
    (``worst``, -inf: none above :data:`~gearcalc.zstk.schema.B_OVER_RHO_LIMIT`), explicit stepping."""
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
        from ..floatfmt import apart

        out.append(f"a loaded contact has b/rho = {apart(worst, B_OVER_RHO_LIMIT, 3)[0]} > {B_OVER_RHO_LIMIT}: Hertz's "
                   "small-contact assumption is doubtful")
    if stepping is not None and stepping[g] > 1e-9:
        out.append(f"explicit stepping closes with a residual of {stepping[g]:.3g} mm (> 1e-9 mm)")
    return out


def messages(g: int, stack, out, fixed: bool, worst, notes=()) -> tuple[list, list]:
    """(warnings, failed checks) of design g of a stack: the sweeps' ``notes``, :func:`warnings`, a preload that
    alone reaches the allowable stress; the failed strength check sigma_max <= [sigma_H] (zstk.md §10)."""
    sm, clearance, allow = out.summary, stack.clearance[g], stack.allowable[g]
    found = list(notes) + warnings(sm, g, clearance, fixed, stack.allowable_default[g], worst, stack.stepping)
    if out.capacity.preload_exceeds[g]:
        found.append(f"the preload alone (load.clearance_mm = {clearance:.6g}) reaches allowable_stress_MPa "
                     f"= {allow:.6g}: radial_load_allowable_N = 0")
    if out.passed[g]:
        return found, []
    from ..floatfmt import apart

    shown, limit = apart(sm.sigma_max[g], allow)  # never "1500 > 1500"
    failed = [f"sigma_max_MPa = {shown} > allowable_stress_MPa = {limit} ({_contact(sm.contact[g])} contact of "
              f"roller {sm.roller[g]}, r = {sm.radius[g]:.6g} mm)"]
    return found, failed
