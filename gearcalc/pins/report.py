"""The texts and field lists of the ``pins`` calculator: summary fields filled from the physics results,
warnings and failed-check messages (pins.md §8, §9).

Imports nothing heavy (numpy, the physics) at module level.
"""
from __future__ import annotations

import math

from ..calculator import DesignError, Result

__all__ = ["PEAK_KEYS", "CONSISTENT_FIELDS", "OUTPUT_KEYS", "FORMULA_KEYS", "fmt", "cycle_notes",
           "admissibility_error", "profile_error", "tooth_overlap", "column", "columns", "plain", "ideal_columns",
           "problem", "warning", "friction_alias_error", "contact_notes",
           "cost_problem", "contact_error", "result", "report_problems"]

PEAK_KEYS = ("pin_force_max_N", "pin_force_max_phase_deg", "pin_loss_max_W", "pin_loss_max_phase_deg", "loss_peak_W",
             "pin_loss_bound_W")
"""The per-pin peaks the friction-consistent model replaces (one disc; pins.md §4.9)."""

CONSISTENT_FIELDS = (   # summary field <- gearcalc.pins.outputs.ConsistentPoint field
    ("crank_torque_mean_Nm", "crank_torque_mean"), ("crank_torque_ripple_Nm", "crank_torque_ripple"),
    ("bearing_force_max_N", "bearing_force_max"), ("bearing_force_mean_N", "bearing_force_mean"),
    ("contact_stress_max_MPa", "contact_stress_max"), ("axle_pressure_max_MPa", "axle_pressure_max"),
    ("efficiency", "efficiency"), ("efficiency_err", "efficiency_err"), ("self_locking", "self_locking"),
    ("efficiency_multiplier", "eta_vh"), ("efficiency_multiplier_err", "eta_vh_err"),
    ("efficiency_reducer", "eta_hv"), ("efficiency_reducer_err", "eta_hv_err"),
    ("loss_ratio", "loss_ratio"), ("loss_ratio_err", "loss_ratio_err"),
    ("torque_in_Nm", "torque_in"), ("torque_out_Nm", "torque_out"), ("loss_mean_W", "loss_mean"),
    ("tolerance_met", "converged"), ("n_crank", "n_crank"),
    ("pin_force_max_N", "force_max"), ("pin_force_max_phase_deg", "force_phase"),
    ("pin_loss_max_W", "loss_max"), ("loss_peak_W", "loss_peak"), ("pin_loss_max_phase_deg", "loss_phase"),
    ("pin_loss_bound_W", "loss_bound"))
OUTPUT_KEYS = CONSISTENT_FIELDS[:6]   # pins.md §8: every admissible point gets them (first-order ones too)

SELF_LOCKING_EMPTY = ("efficiency", "efficiency_err", "efficiency_multiplier", "efficiency_multiplier_err",
                      "torque_in_Nm", "torque_out_Nm")
"""The fields a self-locking design may leave empty; a table labels them "self-locking" (pins.md §4.7)."""

FORMULA_KEYS = ("F_tr1_N", "F_tr2_N", "P_tr1_W", "P_tr2_W", "P_tr_W", "P_tr_fixed_W")


def fmt(x) -> str:
    """A number in a message: 6 significant digits."""
    return f"{x:.6g}"


def admissibility_error(status: int, z1, z2, psi_star: float, Rb, rho_c: float, K1) -> DesignError:
    """The DesignError of an inadmissible ideal-level gear (pins.md §4.2, §12.10): status from
    :func:`gearcalc.pins.admissibility`."""
    from .ideal import TOO_FEW_TEETH

    if status == TOO_FEW_TEETH:
        return DesignError(
            "gearing.satellite_teeth",
            f"= {z1}: too few teeth for the tooth difference k = {z2 - z1}: at some crank angles no pin "
            f"carries load (the loaded arc psi* = {fmt(math.degrees(psi_star))} deg must exceed the pin "
            f"pitch 360/z2 = {fmt(360.0 / z2)} deg)")
    return DesignError(
        "gearing.pin_radius_mm",
        f"= {fmt(Rb)}: undercut: R_b must be < the least radius of curvature of the pin-centre curve "
        f"over the loaded arc, min rho_c = {fmt(rho_c)} mm (K1 = {fmt(K1)})")


def cycle_notes(design, s, tol: float, warnings, failed) -> None:
    """Append the warnings and failed checks shared by the cycle levels (pins.md §4.5, §4.7, §6, §12.4) of the
    summary ``s`` of ``design`` computed to ``tol``."""
    f, fk, fc, Rb = (design["friction.sliding"], design["friction.rolling_mm"], design["friction.axle"],
                     design["gearing.pin_radius_mm"])
    if s["rolling_ok"] is False:  # a failed check (margin_rolling < 0); the model goes on with fixed pins
        r = design["gearing.axle_radius_mm"]
        failed.append(f"rolling condition f*R_b >= f_c*r + f_k fails (f = {fmt(f)}, R_b = {fmt(Rb)} mm, "
                        f"f_c = {fmt(fc)}, r = {fmt(r)} mm, f_k = {fmt(fk)} mm: {fmt(f * Rb)} < "
                        f"{fmt(fc * r + fk)}): the bushings cannot turn; treated as fixed pins sliding with f")
    lam, E = s["loss_ratio"], s["loss_ratio_err"]
    jammed = s["self_locking"] and lam is None         # friction-consistent model: no positive normal forces
    if not s["tolerance_met"] and not jammed:
        warnings.append(f"tolerance {tol:g} not met: loss ratio {lam:.10g} +- {E:.3g} ({s['n_crank']} crank-angle "
                        f"intervals)")
    if jammed:
        failed.append(f"self-locking in the {s['mode']} mode: with the friction forces in the satellite's balance "
                      "(friction.model = \"consistent\", pins.md §4.9) no positive normal force carries the torque "
                      "at some crank angle (the drive jams); no efficiency. A lower friction.sliding or a larger "
                      "gearing.curtate_ratio (closer to 1) avoids it")
    elif s["self_locking"] and lam is not None and lam < 1.0:        # the output mechanism or the drag locks it
        failed.append(output_lock_text(s.get("backdrive_startup_torque_Nm"), s.get("w_loss_ratio") or 0.0))
    elif s["self_locking"]:
        failed.append(f"self-locking in the multiplier mode: the loss ratio {_ratio(lam)} >= 1 (the losses exceed "
                      "the power the V shaft delivers); no efficiency. A lower friction.sliding or a larger "
                      "gearing.curtate_ratio (closer to 1) lowers the loss ratio")
    if lam is not None and abs(1.0 - lam) <= E:
        warnings.append(f"at the self-locking limit: the loss ratio {lam:.10g} is within its error {E:.3g} of 1")
    other = "reducer" if s["mode"] == "multiplier" else "multiplier"
    if s.get("friction_model") == "consistent" and s[f"efficiency_{other}"] is None:
        warnings.append(f"the {other} mode self-locks (friction-consistent model, pins.md §4.9): "
                        f"efficiency_{other} is empty")
    if design["load.crank_speed_rpm"] is None:
        warnings.append("loss_mean_W, loss_peak_W, pin_loss_max_W, pin_loss_bound_W and the pin and sliding speeds "
                        "need load.crank_speed_rpm; they are left empty")


def profile_error(exc, design, g) -> DesignError:
    """The DesignError of an inadmissible contact-level profile (:class:`gearcalc.pins.contact.InadmissibleProfile`,
    pins.md §5.2-5.3, §9) of ``design`` with gear ``g``."""
    v, Rb, Rp, e = exc.values, g.R_b, g.R_p, g.e
    if exc.reason == "no_full_tooth":
        return DesignError("gearing.tooth_radius_mm",
                           f'= "full": no full circular tooth fits: R_b = {fmt(Rb)} mm must be < R_p - e '
                           f"= {fmt(Rp - e)} mm with a tooth circle that meets the pins' paths (pins.md §5.3)")
    if exc.reason == "tooth_too_large":
        return DesignError(*problem("tooth_too_large", rho_t=v["rho_t"], sum=v["sum"], limit=Rp - e))
    if exc.reason == "no_zero_backlash":
        return DesignError("gearing.tooth_radius_mm",
                           f"= {fmt(v['rho_t'])}: no zero-backlash tooth circle: the tooth never reaches the pins' "
                           f"nominal paths (R_b + rho_t = {fmt(v['sum'])} mm; pins.md §5.3)")
    if exc.reason == "interference":
        return DesignError("gearing.tooth_circle_radius_mm",
                           f"= {fmt(v['R_t'])}: the teeth interfere with the pins at nominal by "
                           f"{fmt(v['depth'] * 1e3)} um (least distance from a tooth centre to the "
                           f"pins' paths {fmt(v['distance'])} mm < R_b + rho_t = {fmt(v['sum'])} mm); make it smaller "
                           "or use \"zero_backlash\"")
    if exc.reason == "design_curve":
        return DesignError("gearing.radial_mod_mm",
                           f"= {fmt(design['gearing.radial_mod_mm'])}: the design curve's K1 = e*z2/(k*(R_p + Delta "
                           f"R_p)) = {fmt(v['K1'])} must be < 1")
    if exc.reason == "modification":
        return DesignError("gearing.equidistant_mod_mm", f"= {fmt(design['gearing.equidistant_mod_mm'])}: R_b + Delta "
                                                         f"R_b = {fmt(v['R_b'])} mm must be > 0")
    if exc.reason == "too_few_teeth":         # the ideal level's text (pins.md §12.10)
        from .ideal import TOO_FEW_TEETH

        return admissibility_error(TOO_FEW_TEETH, g.z1, g.z2, v["psi_star"], Rb, math.nan, g.K1)
    key = "gearing.equidistant_mod_mm" if design["gearing.equidistant_mod_mm"] != 0.0 else "gearing.pin_radius_mm"
    return DesignError(key, f"= {fmt(design[key])}: undercut: R_b + Delta R_b = {fmt(v['R_b'])} mm must be < the "
                            f"least radius of curvature of the design curve over the loaded arc, min rho_c = "
                            f"{fmt(v['rho_c'])} mm")


def tooth_overlap(profile) -> str:
    """The warning of circular teeth larger than the full tooth (pins.md §5.3)."""
    full = profile.R_t * math.sin(math.pi / profile.g.z1)
    return (f"tooth_radius_mm = {fmt(profile.rho_t)} exceeds the full tooth R_t*sin(pi/z1) = {fmt(full)} mm: "
            "adjacent tooth circles overlap")


def no_equilibrium_error(exc, design, z1: int) -> DesignError:
    """A contact-level crank angle where no satellite rotation balances the torque (pins.md §5.5)."""
    key = "gearing.tooth_circle_radius_mm" if design["gearing.profile"] == "circular" else "gearing.equidistant_mod_mm"
    return DesignError(key, f"= {design[key]}: no contact can carry the torque at crank angle "
                            f"{fmt(math.degrees(float(exc.theta[0])))} deg: no satellite rotation within "
                            f"+-180/z1 = {fmt(180.0 / z1)} deg balances T_V = {fmt(exc.torque_V)} N*m (the "
                            "teeth do not mesh with the pins, or the torque crushes the contacts, or the satellite "
                            "turns so far under it that the search misses a balance among several; pins.md "
                            "§5.5, §7)")


def contact_error(exc, design, g) -> DesignError:
    """The DesignError of the contact level of ``design`` (gear ``g``) finding no equilibrium
    (:class:`gearcalc.pins.contact.NoEquilibrium`) or a geometry below floating-point resolution
    (:class:`~gearcalc.pins.contact.Unresolvable`)."""
    from .contact import NoEquilibrium

    if isinstance(exc, NoEquilibrium):
        return no_equilibrium_error(exc, design, design["gearing.satellite_teeth"])
    return unresolvable_error(design["gearing.eccentricity_mm"], g.R_p, design["gearing.pin_radius_mm"],
                              design.get("load.torque_Nm"))


def group_results(designs, cols, ideal, tol: float, detail: bool, t0: float) -> list:
    """Per design of a group computed together (:func:`gearcalc.pins.columns.level_columns`: its columns ``cols``
    and the ideal level's :class:`~gearcalc.pins.columns.IdealColumns` or None) its Result or DesignError, with
    the notes of :func:`cycle_notes`; ``model_time_ms`` is the group's time since ``t0`` per design."""
    import time

    out = []
    for i, d in enumerate(designs):
        summary, warnings, failed, tables = {k: col[i] for k, col in cols.items()}, [], [], {}
        if ideal is not None:
            if ideal.errors[i] is not None:
                out.append(ideal.errors[i])
                continue
            law = d.has("contact") and (d.is_given("contact.law") or d.is_given("contact.stiffness_N_per_mm"))
            warnings = ([CONTACT_TABLE_UNUSED] if law else []) + ideal.warnings[i]
            cycle_notes(d, summary, tol, warnings, failed)
            failed.extend(stress_failure(summary, d.get("material.allowable_stress_MPa")))
            tables = ideal.detail(i) if detail else {}
        out.append(result(summary, tables, warnings, failed))
    per_design = (time.perf_counter() - t0) * 1e3 / len(designs)
    for r in out:
        if isinstance(r, Result):
            r.summary["model_time_ms"] = per_design
    return out


def stress_failure(s, allowable) -> list:
    """The failed contact-stress check of a summary ``s`` (margin_contact_stress < 0), as a list of its message."""
    m = s.get("margin_contact_stress")
    if m is None or m >= 0:
        return []
    from ..floatfmt import apart

    shown, limit = apart(s["contact_stress_max_MPa"], allowable)  # never "1500 > 1500"
    return [f"contact_stress_max_MPa = {shown} > material.allowable_stress_MPa = {limit} (the Hertz stress of the "
            f"{s['model']} level's forces)"]


def result(summary, detail, warnings, failed) -> Result:
    """The Result of a design's summary; a table says why a value is missing: "self-locking" for the fields
    a self-locking design leaves empty (pins.md §4.7)."""
    out = Result(summary=summary, detail=detail, warnings=warnings, failed=failed, model=summary["model"])
    if summary["self_locking"]:
        out.labels.update({k: "self-locking" for k in SELF_LOCKING_EMPTY if summary[k] is None})
    return out


def report_problems(found, problems) -> None:
    """Report the problems of :func:`gearcalc.pins.checks.design_problems` (errors: :func:`problem`, warnings:
    :func:`warning`) to ``problems`` (:class:`gearcalc.calculator.Problems`)."""
    for severity, rule, values in found:
        if severity == "error":
            problems.error(*problem(rule, **values))
        else:
            problems.warn(warning(rule, **values))


def unresolvable_error(e, Rp, Rb, torque=None) -> DesignError:
    """A contact-level geometry below floating-point resolution (``torque``: load.torque_Nm, named as the other
    cause: the deflections scale with it)."""
    under = "" if torque is None else f" under load.torque_Nm = {fmt(torque)} N*m"
    hint = "" if torque is None else "; a larger torque deflects the contacts more"
    return DesignError("gearing.eccentricity_mm",
                       f"= {fmt(e)}: the contact level cannot resolve this geometry in floating point "
                       f"(R_p = {fmt(Rp)} mm, e = {fmt(e)} mm, R_b = {fmt(Rb)} mm: the deflections{under} are "
                       f"below the round-off of the pin positions{hint})")


def stiffness_error(design, law, residual: float, tol: float) -> DesignError:
    """The moment balance not met to 1/100 of --tol: the torque too high for the contact stiffness (pins.md §5.5)."""
    stiff = (f"contact.stiffness_N_per_mm = {fmt(law.constant)} N/mm" if law.name == "linear"
             else f"the {law.name} law with contact.face_width_mm = {fmt(design['contact.face_width_mm'])} mm")
    return DesignError("load.torque_Nm", f"= {fmt(design['load.torque_Nm'])}: the torque is too high for the "
                                         f"contact stiffness ({stiff}): the satellite's moment balance is met only "
                                         f"to {residual:.3g} of the torque at some crank angle (more than 1/100 of "
                                         f"--tol {tol:g} and than its round-off floor; pins.md §5.5); "
                                         "lower the torque or stiffen the contacts (a residual that stays "
                                         "when the torque is lowered is a jump of the moment where a contact "
                                         "passes a sharp crest corner: a curtate ratio further from 1)")


def mode_warnings(modes, mode: str) -> list[str]:
    """The warnings of the contact level's modes (:class:`gearcalc.pins.contact.ModeCycles`): the requested mode
    jams (its numbers are the frictionless balance's), a torque fixed point that did not settle, a cycle whose nodes
    contradict their pieces' contact sets (:attr:`gearcalc.pins.contact.ContactCycle.held`)."""
    from .contact_cycle import deflection_sized, pin_travel    # the contact level ran: loaded
    out = []
    multiplier = mode == "multiplier"
    if multiplier in modes.jams:
        out.append(f"the {mode} mode jams (self-locks) with the friction forces in the moment "
                   f"balance at crank angle {fmt(math.degrees(float(modes.jams[multiplier].theta[0])))} deg: no "
                   "positive contact force balances the torque; forces, speeds and losses are those of the "
                   "frictionless balance (friction.model = \"first-order\")")
    for mult, t in modes.runs.items():
        if not t.settled:
            out.append(f"the torque fixed point T_V = u T_H/eta did not settle in {len(t.history)} passes (loss ratios "
                       f"{t.history[-2]:.10g}, {t.history[-1]:.10g})")
        st = t.model.settings
        sized = deflection_sized(t.cycle.sol.tau, t.model.g, st.travel_max)
        if not sized:
            travel = pin_travel(t.cycle.sol.tau, t.model.g)
            out.append(f"in the {'multiplier' if mult else 'reducer'} mode the satellite turns by up to "
                       f"{fmt(math.degrees(float(abs(t.cycle.sol.tau).max())))} deg under the load: a pin centre "
                       f"moves by {fmt(travel)} of the pin radius from its nominal place (more than {st.travel_max:g}: "
                       f"not a deflection; the balance can have several solutions, pins.md §7); its loss ratio is not "
                       f"known to the stated error")
        if not t.cycle.held:
            # a satellite that turns beyond a deflection is not scanned denser (pins.md §6): the text says which
            scan = ("with the sign changes scanned as usual (not denser: the satellite turns beyond a deflection, "
                    "above)" if not sized else
                    f"even with the sign changes scanned on {st.scan_max} angles (it changes between them, or the "
                    f"satellite turns so far under the load that its balance has several solutions)")
            out.append(f"the {'multiplier' if mult else 'reducer'} mode's cycle does not hold: at some solved crank "
                       f"angles a contact or a sliding direction differs from its piece's {scan}, pins.md §6-7; its "
                       f"loss ratio is not known to the stated error")
    return out


def contact_self_locking(mode: str, jammed: bool, loss_ratio: float, stalled: bool = False,
                         consistent: bool = True) -> str:
    """The failed check of a self-locking mode of the contact level (pins.md §4.9, §7): a jam, a multiplier's loss
    ratio >= 1, or a reducer that stalls (its losses alone exceed the input)."""
    if stalled:
        cause = ("the losses alone exceed the input power: the torque fixed point T_V = eta u T_H has no positive "
                 "T_V (a loss that stays at no load, e.g. a preload from teeth that interfere with the pins: "
                 "check gearing.equidistant_mod_mm and gearing.radial_mod_mm)")
    elif jammed:
        cause = "it jams: no positive contact force balances the torque with the friction forces at some crank angle"
    else:
        cause = f"the loss ratio {_ratio(loss_ratio)} >= 1 (the losses exceed the power the V shaft delivers)"
    model = "friction-consistent model, pins.md §4.9" if consistent else "first-order model, pins.md §7"
    return f"self-locking in the {mode} mode ({model}): {cause}; no efficiency. A lower friction.sliding lowers " \
           "the friction moments"


def other_mode_jams(multiplier: bool) -> str:
    """The warning of the mode not requested jamming (pins.md §4.9)."""
    return (f"the {'multiplier' if multiplier else 'reducer'} mode jams (self-locks) with the friction "
            "forces in the moment balance: efficiency_" + ("multiplier" if multiplier else "reducer") + " is empty")


def contact_fields(profile: str, rotating: bool, mode: str, g, law, geo, tc, pk, metrics, backlash, residual,
                   rolling_ok) -> dict:
    """The contact level's summary fields from its results (pins.md §8) for the design's ``profile`` name,
    ``rotating`` pins and load ``mode``: the cycle ``tc``
    (:class:`~gearcalc.pins.contact.TorqueCycle`), its peaks ``pk``, engagement ``metrics``, backlash [deg] and
    equilibrium residual."""
    from .contact import deflection_sized        # the contact level ran: loaded
    cyc, sol = tc.cycle, tc.cycle.sol
    return {
        "model": "contact", "profile": profile, "rotating_pins": rotating, "mode": mode, "ratio": g.ratio,
        "curtate_ratio": g.K1,
        "rolling_ok": None if rolling_ok is None else bool(rolling_ok[0]),
        "loss_ratio": tc.loss_ratio, "loss_ratio_err": tc.loss_ratio_err, "n_crank": cyc.n_crank,
        # the quadrature, the torque fixed point, the nodes' check of the pieces' contact sets and a deflection-sized
        # rotation (pins.md §6-7)
        "tolerance_met": (bool(cyc.converged) and bool(tc.settled) and bool(cyc.held)
                          and deflection_sized(sol.tau, g, tc.model.settings.travel_max)),
        "pin_force_max_N": pk.force if math.isfinite(tc.torque_V) else None,
        "pin_force_max_phase_deg": math.degrees(pk.force_phase), "loaded_pins_min": pk.loaded_min,
        "loaded_pins_max": pk.loaded_max,
        "psi_star_deg": math.degrees(pk.psi_star) if pk.psi_star is not None else None,
        "exit_entry_force_ratio": metrics["exit_entry_force_ratio"],
        "low_spin_fraction": metrics["low_spin_fraction"], "spin_reversals": metrics["spin_reversals"],
        "te_pp_arcsec": math.degrees(float(sol.tau.max() - sol.tau.min())) * 3600.0,
        "backlash_deg": backlash,
        "equilibrium_residual": residual,
        "contact_law": law.name, "tooth_radius_mm": geo.get("tooth_radius_mm"),
        "tooth_circle_radius_mm": geo.get("tooth_circle_radius_mm"),
    }


def efficiency_fields(et_m, et_r, locked: dict, multiplier: bool, plain) -> dict:
    """The efficiency and torque fields from the two modes' :class:`~gearcalc.pins.operating.EfficiencyTorques`
    (arrays of one point) and which modes self-lock (pins.md §4.7, §4.9); ``plain``: numpy scalar to Python."""
    s = {}
    et = et_m if multiplier else et_r
    s["efficiency_multiplier"] = None if locked[True] else plain(et_m.eta_vh[0])
    s["efficiency_multiplier_err"] = None if locked[True] else plain(et_m.eta_vh_err[0])
    s["efficiency_reducer"] = None if locked[False] else plain(et_r.eta_hv[0])
    s["efficiency_reducer_err"] = None if locked[False] else plain(et_r.eta_hv_err[0])
    s["self_locking"] = locked[multiplier]
    s["efficiency"] = s["efficiency_multiplier" if multiplier else "efficiency_reducer"]
    s["efficiency_err"] = s["efficiency_multiplier_err" if multiplier else "efficiency_reducer_err"]
    s["torque_in_Nm"] = None if locked[multiplier] else plain(et.torque_in[0])
    s["torque_out_Nm"] = None if locked[multiplier] else plain(et.torque_out[0])
    return s


def crest_warning(crank) -> list[str]:
    """The warning of loaded contacts on the crest corners of the teeth (k >= 2, pins.md §5.2, §8), or none."""
    if crank is None or not crank.crest_loaded:
        return []
    return ["a loaded pin touches the crest corner of a tooth (k >= 2: the cycloid cut off at psi*, a sharp edge) "
            "in the compliant contact: the Hertz stress there is unbounded; contact_stress_max_MPa covers the flank "
            "contacts only (a rounded crest would carry it)"]


def operating_fields(ov) -> dict:
    """The loss and speed fields of :class:`~gearcalc.pins.contact.ContactOperating` (pins.md §8)."""
    return {"loss_mean_W": ov.loss_mean, "loss_peak_W": ov.loss_peak, "pin_loss_max_W": ov.loss_max,
            "pin_loss_max_phase_deg": ov.loss_phase, "pin_loss_bound_W": ov.loss_bound,
            "pin_speed_max_rpm": ov.spin_abs_max, "pin_speed_signed_min_rpm": ov.spin_min,
            "pin_speed_signed_max_rpm": ov.spin_max, "sliding_speed_max_m_s": ov.sliding_speed_max}


def cost_problem(level: str, z2: int, n_d: int, torque_on_V: bool):
    """(key, message) of a design over its level's cost budget (:func:`gearcalc.pins.checks.ideal_over_budget`,
    :func:`~gearcalc.pins.checks.contact_over_budget`; pins.md §9), else None."""
    from .checks import contact_over_budget, contact_passes, ideal_over_budget
    from .schema import CONTACT_NODES_MAX, CONTACT_WORK_MAX, IDEAL_WORK_MAX

    if level == "ideal" and ideal_over_budget(z2, n_d):
        key = "gearing.discs" if n_d > 1 else "gearing.pins"
        return key, ideal_cost_text(n_d if n_d > 1 else z2, z2, n_d, IDEAL_WORK_MAX)
    if level == "contact" and contact_over_budget(z2, torque_on_V):
        return "gearing.pins", contact_cost_text(z2, CONTACT_NODES_MAX, contact_passes(torque_on_V), CONTACT_WORK_MAX,
                                                 torque_on_V)
    return None


def ideal_cost_text(key_value, z2: int, n_d: int, budget: int) -> str:
    """A design over the ideal level's budget of pin-discs (pins.md §9)."""
    return (f"= {key_value}: gearing.pins x gearing.discs = {z2} x {n_d} = {z2 * n_d} exceeds the ideal "
            f"level's budget of {budget} pin-discs (about 35 us each: ~10 s, ~0.5 GB); use fewer pins or discs")


def contact_cost_text(z2: int, nodes: int, passes: int, budget: int, on_V: bool) -> str:
    """A design over the contact level's budget of contact solves (pins.md §9)."""
    where = "with the torque on V" if on_V else "with the torque on H (3 passes of the torque fixed point)"
    return (f"= {z2}: too many pins for the contact level: {z2} pins x {nodes} crank angles x {passes} pass(es) = "
            f"{z2 * nodes * passes} contact solves exceeds its budget of {budget} (~10 s): at most "
            f"{budget // (nodes * passes)} pins {where}; a cycloidal profile without modifications or [contact] "
            "runs the ideal level, which takes up to 10 000 pins")


def too_costly_error(n_d: int, n_crank: int, tol: float, samples_max: float, work_max: float) -> DesignError:
    """The disc sums of an ideal-level design over budget at --tol: known after the quadrature only."""
    return DesignError(
        "gearing.discs", f"= {n_d}: the sums over {n_d} discs on the {n_crank} crank-angle intervals per pin "
        f"pitch that --tol {tol:g} needs exceed the ideal level's budget (n_d x loaded samples <= "
        f"{samples_max:.3g}, n_d^2 x loaded samples <= {work_max:.3g}: ~10 s, ~0.4 GB); "
        "use fewer discs or a larger --tol")


def pitch_point_inside(Rb, Rp_omk, psi_0) -> str:
    """The warning of the pitch point inside the pin near entry (pins.md §4.5); psi_0 [rad] or None."""
    return (f"R_b = {fmt(Rb)} mm >= R_p*(1 - K1) = {fmt(Rp_omk)} mm: the pitch point lies inside the pin near entry"
            + (f"; the pin spin reverses at psi = {fmt(math.degrees(psi_0))} deg" if psi_0 else ""))


MULTI_DISC_PEAKS = ("pin_force_max_N, pin_loss_max_W and loss_peak_W with several discs follow the friction-free "
                    "force distribution (first-order model) at the friction-consistent torque; the efficiencies, "
                    "crank torque and bearing force are friction-consistent")
CONTACT_TABLE_UNUSED = ("the [contact] table's contact law is not used by the ideal level (rigid contacts; "
                        "contact.face_width_mm gives the contact stress and the axle pressure)")


def loss_ratio_overflow(curtate_given: bool, value) -> DesignError:
    """The loss ratio overflowing floating point (K1 ~ 1e-300 and below; pins.md §9): ``value`` of the curtate
    ratio where it is given, else of the pin circle."""
    key = "gearing.curtate_ratio" if curtate_given else "gearing.pin_circle_radius_mm"
    return DesignError(key, f"= {fmt(value)}: the loss ratio overflows floating point (it grows as 1/K1, "
                            "K1 = e*z2/(k*R_p): the curtate ratio is too small for this gear)")


# ---------------------------------------------------------------- plain values of the fields

def column(arr) -> list:
    """Plain Python values of an array (bool, int or float; NaN becomes None: undefined)."""
    import numpy as np

    arr = np.asarray(arr)
    out = arr.tolist()
    if arr.dtype.kind == "f" and np.isnan(arr).any():
        out = [None if v != v else v for v in out]
    return out


def columns(arrays: dict, n: int) -> dict:
    """Plain Python lists of many arrays of shape (n,) (see :func:`column`), the float ones converted together."""
    import numpy as np

    out, floats = {}, []
    for key, arr in arrays.items():
        if arr.dtype.kind == "f":
            floats.append(key)
        else:
            out[key] = arr.tolist()
    if floats:
        block = np.array([arrays[k] for k in floats])
        holes = np.isnan(block).any(axis=1).tolist()
        for key, vals, hole in zip(floats, block.tolist(), holes):
            out[key] = [None if v != v else v for v in vals] if hole else vals
    return {key: out[key] for key in arrays}


def plain(x):
    """A numpy scalar as a plain bool/int/float, NaN as None (undefined)."""
    import numpy as np

    if isinstance(x, (np.bool_, bool)):
        return bool(x)
    if isinstance(x, (np.integer, int)):
        return int(x)
    x = float(x)
    return None if math.isnan(x) else x


# ---------------------------------------------------------------- the cross-key checks (pins.md §7, §9)

CONTACT_WHY = "the contact level runs for a circular profile, a modified cycloid, a [contact] table or --model contact"

PROBLEMS = {
    "no_tables": ("gearing", "missing; a pins design needs [gearing] (cycle model: efficiency, losses over the cycle) "
                             "or [pin_load] (the paper's per-pin formula level)"),
    "pin_load_axle": ("pin_load.axle_radius_mm", "= {r:.6g}: must be < pin_load.pin_radius_mm = {R:.6g} (the axle "
                                                 "must be smaller than the bushing)"),
    "no_load": ("load", "missing; a design with [gearing] needs [load] (mode, torque_shaft, torque_Nm, "
                        "crank_speed_rpm)"),
    "no_sliding": ("friction.sliding", "missing; required with [gearing] (f, tooth-pin sliding friction; it also "
                                       "drives rotating pins), a number >= 0"),
    "teeth": ("gearing.pins", "= {z2}: z2 must exceed z1 (k = z2 - z1 >= 1); gearing.satellite_teeth = {z1}"),
    "one_circle": ("gearing.pin_circle_radius_mm", "give exactly one of gearing.pin_circle_radius_mm (R_p) and "
                                                   "gearing.curtate_ratio (K1 = e*z2/(k*R_p)); {given} given"),
    "overflow": ("gearing.curtate_ratio", "= {K1:.6g}: R_p = e*z2/(k*K1) overflows (K1 too small for e = {e:.6g} mm "
                                          "and z2/k = {ratio:.6g}); give a larger K1 or gearing.pin_circle_radius_mm"),
    "curtate_K1": ("gearing.curtate_ratio", "= {K1:.6g}: K1 = e*z2/(k*R_p) must be < 1 (a curtate cycloid)"),
    "curtate_Rp": ("gearing.pin_circle_radius_mm", "= {Rp:.6g}: K1 = e*z2/(k*R_p) = {K1:.6g} must be < 1: R_p must "
                                                   "exceed e*z2/k = {limit:.6g} mm (or reduce "
                                                   "gearing.eccentricity_mm = {e:.6g})"),
    "overlap": ("gearing.pin_radius_mm", "= {Rb:.6g}: pins overlap: R_b must be < R_p*sin(pi/z2) = {limit:.6g} mm "
                                         "(R_p = {Rp:.6g} mm, z2 = {z2})"),
    "no_axle": ("gearing.axle_radius_mm", "missing; required with rotating_pins = true (r, axle radius, > 0 and < "
                                          "pin_radius_mm)"),
    "axle": ("gearing.axle_radius_mm", "= {r:.6g}: must be < gearing.pin_radius_mm = {Rb:.6g} (the axle must be "
                                       "smaller than the bushing)"),
    "tooth_too_large": ("gearing.tooth_radius_mm", "= {rho_t:.6g}: R_b + rho_t = {sum:.6g} mm must be < R_p - e = "
                                                   "{limit:.6g} mm (no zero-backlash tooth circle R_t exists; "
                                                   "pins.md §5.3)"),
    "face_width": ("contact.face_width_mm", "missing; required by the {law} contact law (b, face width, > 0; "
                                            + CONTACT_WHY + '); or set contact.law = "linear" with '
                                            "contact.stiffness_N_per_mm"),
    "stiffness": ("contact.stiffness_N_per_mm", "missing; required by the linear contact law (k_lin, > 0; "
                                                + CONTACT_WHY + ")"),
    "need_pin_load": ("pin_load", "missing; --model formula needs [pin_load] (normal_force_N, pin_speed_rpm, "
                                  "pin_radius_mm, axle_radius_mm)"),
    "need_gearing": ("gearing", "missing; --model {model} needs [gearing] and [load] (the cycle model)"),
    "ideal_profile": ("gearing.profile", '= "{profile}": the ideal level needs a conjugate (cycloidal) profile; a '
                                         "circular profile needs the contact level"),
    "ideal_mods": ("gearing.equidistant_mod_mm", "the ideal level has no profile modifications (they need the "
                                                 "contact level); set them to 0"),
    "friction_alias": ("contact.friction_in_equilibrium", "= {alias} contradicts friction.model = \"{model}\" (the "
                                                          "key is its alias; give one of them)"),
}
"""The cross-key problems: rule -> (key, message template)."""

CIRCULAR_ONLY = "gearing.{key} applies to the circular profile only; ignored for a cycloidal one"
CYCLOID_MODS_IGNORED = ("gearing.equidistant_mod_mm and gearing.radial_mod_mm apply to the cycloidal profile only; "
                        "ignored for a circular one (give tooth_radius_mm / tooth_circle_radius_mm instead)")


def problem(rule: str, **values) -> tuple[str, str]:
    """(key, message) of a cross-key rule of :data:`PROBLEMS` with its numbers."""
    key, text = PROBLEMS[rule]
    return key, text.format(**values)


def warning(rule: str, name: str = "") -> str:
    """The text of a warning of :func:`gearcalc.pins.checks.design_problems`: "circular_only" (``name``: the
    argument, tooth_radius or tooth_circle_radius) or "cycloid_mods_ignored"."""
    return CIRCULAR_ONLY.format(key=name + "_mm") if rule == "circular_only" else CYCLOID_MODS_IGNORED


def friction_alias_error(model, alias) -> DesignError:
    """contact.friction_in_equilibrium contradicting friction.model (pins.md §7)."""
    return DesignError(*problem("friction_alias", alias=str(alias).lower(), model=model))


def contact_notes(design, s, tol: float, warnings, failed, cl, multiplier: bool) -> None:
    """The warnings and failed checks of the contact level's summary ``s`` (pins.md §4.9, §8) from its
    :class:`~gearcalc.pins.contact_level.ContactLevel` ``cl``: :func:`cycle_notes`, then the self-locking of the
    requested mode in the friction-consistent model, the other mode jamming, contacts on crest corners."""
    modes, consistent, crank = cl.modes, cl.consistent, cl.crank
    stalled = modes.requested.stalled and multiplier not in modes.jams
    if (consistent or stalled) and s["self_locking"]:
        # the shared notes word self-locking for the first-order multiplier; this level words it per mode
        s["self_locking"] = False
        cycle_notes(design, s, tol, warnings, failed)
        s["self_locking"] = True
        failed.append(contact_self_locking(design["load.mode"], multiplier in modes.jams, modes.requested.loss_ratio,
                                           stalled, consistent))
    else:
        cycle_notes(design, s, tol, warnings, failed)
    warnings.extend(other_mode_jams(mult) for mult in modes.jams if mult != multiplier)
    warnings.extend(crest_warning(crank))


def ideal_columns(arrays: dict, mode, rotating, rolls, models: list, n: int) -> dict:
    """The ideal level's summary columns (plain Python lists over the n points; None: undefined) from the
    fields of :func:`~gearcalc.pins.columns._ideal_fields`, the points' mode (a word, or a list of them), rotating
    pins and rolling (bools, or arrays) and friction models."""
    import numpy as np

    if n == 1:
        out = {"model": ["ideal"], "mode": [mode], "profile": ["cycloidal"], "rotating_pins": [rotating],
               "rolling_ok": [bool(rolls) if rotating else None], "friction_model": models}
        for key, v in arrays.items():             # plain Python values; NaN: undefined
            v = v.item() if isinstance(v, np.generic) else v
            out[key] = [None if v != v else v]
        return out
    out = {"model": ["ideal"] * n, "mode": list(mode), "profile": ["cycloidal"] * n,
           "rotating_pins": rotating.tolist(),
           "rolling_ok": [bool(o) if q else None for o, q in zip(rolls.tolist(), rotating.tolist())],
           "friction_model": models}
    out.update(columns(arrays, n))
    return out


def _ratio(ratio: float) -> str:
    """A loss ratio compared with 1 in a message: the digits that tell it from 1 (never "1 >= 1" for 1.0000001)."""
    from ..floatfmt import apart

    return apart(ratio, 1.0)[0]


BEARING_KEYS = ("bearing_equivalent_load_N", "bearing_equivalent_load_err_N", "bearing_L10_h", "bearing_L10_h_err")


def bearing_columns(pts, exponent, rating, speed, n: int) -> dict:
    """The crank bearing's equivalent load and L10_h (:func:`gearcalc.pins.outputs.bearing_life`) as summary
    columns over the n points of the ideal level (None: undefined; L10_h needs bearing.C_N and the crank speed)."""
    import numpy as np

    from .outputs import bearing_life

    p = pts.consistent
    if p is None or p.bearing_pmean is None:
        return {k: [None] * n for k in BEARING_KEYS}
    vals = bearing_life(p.bearing_pmean, p.bearing_pmean_err, exponent, p.torque_sat, rating, speed)
    out = {}
    for key, v in zip(BEARING_KEYS, vals):
        v = np.broadcast_to(np.asarray(v, dtype=float), (n,))
        out[key] = [x if math.isfinite(x) else None for x in v.tolist()]
    return out


def output_lock_text(startup, loss_ratio_w: float) -> str:
    """The failed check of a multiplier that the output mechanism or the crank's drag locks (pins.md §4.10), at
    either level: the mechanism's loss ratio >= 1, or a load below the back-driving start-up torque."""
    if loss_ratio_w >= 1.0:
        return (f"self-locking in the multiplier mode: the output mechanism's loss ratio {loss_ratio_w:.6g} >= 1 "
                "(pins.md §4.10); no efficiency. A lower output.friction lowers it")
    at = "" if startup is None else f" T_V,start = {startup:.6g} N·m"
    return (f"self-locking in the multiplier mode: the load is below the back-driving start-up torque{at} (the "
            "crank's drag load.drag_torque_Nm; pins.md §4.10); no efficiency")
