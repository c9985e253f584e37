"""The ``pins`` calculator: KHV planetary pin gearing, per-pin friction losses and efficiency.

Schema, cross-key checks and the glue between a design and the physics of :mod:`gearcalc.pins`
(spec: pins.md).  Three model levels; this module picks the cheapest one the design needs:

* ``formula``: the paper's eqs. (3)-(7) from a given normal force and pin speed ([pin_load]);
* ``ideal``: the rigid conjugate cycle model of a cycloidal satellite ([gearing], no modifications);
* ``contact``: the compliant contact model of :mod:`gearcalc.pins_contact` (circular-arc teeth,
  cycloids with clearance or modifications, a [contact] table, or ``--model contact``).

The ideal level solves a geometry once in unit scalings and scales it to operating points
(friction, torque, speed, mode), so ``gearcalc sweep`` over those keys runs as arrays (``sweep``).
No numpy at module level: ``gearcalc check``/``new``/``--help`` stay light.
"""
from __future__ import annotations

import math
import time

from ..calculator import REQUIRED, Calculator, DesignError, Field, Options, Problems, Result, Table

MODELS = ("formula", "ideal", "contact")

TABLES = (
    Table("pin_load", (
        Field("normal_force_N", "number", REQUIRED, "F_n, peak normal force on one pin", gt=0, example=1920.0),
        Field("pin_speed_rpm", "number", REQUIRED, "n_pin, bushing speed", gt=0, example=14.0),
        Field("pin_radius_mm", "number", REQUIRED, "R, outer radius of the bushing", gt=0, example=1.95),
        Field("axle_radius_mm", "number", REQUIRED, "r, radius of the axle (< R)", gt=0, example=0.95),
        Field("paper_pi", "bool", False, "compute with pi = 3.14 as the paper did"),
    ), doc="The paper's per-pin formula level, eqs. (3)-(7): give this table alone to run it",
        optional=True, in_template=False),
    Table("gearing", (
        Field("profile", "string", REQUIRED, "satellite tooth profile", choices=("cycloidal", "circular"),
              example="cycloidal"),
        Field("satellite_teeth", "integer", REQUIRED, "z1, teeth of the satellite", ge=2, example=20),
        Field("pins", "integer", REQUIRED, "z2, pins of the fixed ring (> z1)", ge=3, example=22),
        Field("eccentricity_mm", "number", REQUIRED, "e, crank eccentricity", gt=0, example=3.9),
        Field("pin_circle_radius_mm", "number", None, "R_p, pin-centre circle radius (or give curtate_ratio)",
              gt=0),
        Field("curtate_ratio", "number", None, "K1 = e*z2/(k*R_p), 0 < K1 < 1 (or give pin_circle_radius_mm)",
              gt=0, example=0.75),
        Field("pin_radius_mm", "number", REQUIRED, "R_b, pin (bushing) outer radius", gt=0, example=1.95),
        Field("axle_radius_mm", "number", None, "r, axle radius; required with rotating pins (< R_b)", gt=0,
              example=0.95),
        Field("rotating_pins", "bool", False, "pins are bushings turning on axles (else fixed pins)"),
        Field("discs", "integer", 1, "n_d, satellite discs, offset by 360/n_d degrees of crank", ge=1),
        Field("tooth_radius_mm", "number", "full", "rho_t, circular profile: tooth radius; \"full\": adjacent "
              "teeth tangent at the root", gt=0, choices=("full",)),
        Field("tooth_circle_radius_mm", "number", "zero_backlash",
              "R_t, circular profile: radius of the circle of tooth centres; \"zero_backlash\": the teeth just "
              "touch the pins' nominal paths", gt=0, choices=("zero_backlash",)),
        Field("equidistant_mod_mm", "number", 0.0, "Delta R_b, cycloidal: equidistant modification (> 0 adds "
              "clearance; contact level)"),
        Field("radial_mod_mm", "number", 0.0, "Delta R_p, cycloidal: radial modification of the pin circle of "
              "the design curve (contact level)"),
    ), doc="Geometry of the pin gear: runs the cycle model", optional=True),
    Table("friction", (
        Field("sliding", "number", None, "f, tooth-pin sliding friction; required with [gearing]", ge=0,
              example=0.1),
        Field("rolling_mm", "number", REQUIRED, "f_k, rolling friction between tooth and bushing", ge=0,
              example=0.01),
        Field("axle", "number", REQUIRED, "f_c, sliding friction between bushing and axle", ge=0, example=0.1),
    ), doc="Friction coefficients"),
    Table("load", (
        Field("mode", "string", REQUIRED, "multiplier: V drives H (the paper's); reducer: H drives V",
              choices=("multiplier", "reducer"), example="multiplier"),
        Field("torque_shaft", "string", REQUIRED, "the shaft whose torque is given: H (crank) or V (satellite)",
              choices=("H", "V"), example="H"),
        Field("torque_Nm", "number", REQUIRED, "T, torque on that shaft", gt=0, example=100.0),
        Field("crank_speed_rpm", "number", None, "n_H; powers and pin speeds need it", gt=0, example=1000.0),
    ), doc="Operating point; required with [gearing]", optional=True),
    Table("contact", (
        Field("law", "string", "hertz", "contact law: hertz (steel, ISO/TS 16281), palmgren, linear",
              choices=("hertz", "palmgren", "linear")),
        Field("face_width_mm", "number", None, "b, face width; required for hertz and palmgren", gt=0),
        Field("stiffness_N_per_mm", "number", None, "k_lin, contact stiffness; required for linear", gt=0),
        Field("friction_in_equilibrium", "bool", False, "include the friction forces in the moment balance"),
    ), doc="Compliant contact level (circular teeth, modified cycloids): the contact law", optional=True,
        in_template=False),
)

HEADER = """KHV planetary pin gearing after Prudnikov (seed 000): levels formula | ideal | contact.
[pin_load] alone: the paper's per-pin formula level.  [gearing] + [load]: the cycle model
(ideal for a cycloidal profile without modifications; circular profiles, modifications and
a [contact] table run the compliant contact level, which needs [contact] face_width_mm)."""

SUMMARY_KEYS = (
    "name", "model", "mode", "profile", "rotating_pins", "ratio", "curtate_ratio",
    "efficiency", "efficiency_err", "self_locking",
    "efficiency_multiplier", "efficiency_multiplier_err", "efficiency_reducer", "efficiency_reducer_err",
    "loss_ratio", "loss_ratio_err", "torque_in_Nm", "torque_out_Nm",
    "loss_mean_W", "loss_peak_W", "pin_force_max_N", "pin_force_max_phase_deg",
    "pin_loss_max_W", "pin_loss_max_phase_deg", "pin_loss_bound_W",
    "pin_speed_max_rpm", "pin_speed_signed_min_rpm", "pin_speed_signed_max_rpm", "spin_reversals",
    "sliding_speed_max_m_s", "loaded_pins_min", "loaded_pins_max", "psi_star_deg", "rolling_ok",
    "exit_entry_force_ratio", "low_spin_fraction", "te_pp_arcsec", "backlash_deg", "equilibrium_residual",
    "contact_law", "tooth_radius_mm", "tooth_circle_radius_mm",
    "n_crank", "model_time_ms", "tolerance_met",
    "F_tr1_N", "F_tr2_N", "P_tr1_W", "P_tr2_W", "P_tr_W", "P_tr_fixed_W",
)


def _fmt(x) -> str:
    return f"{x:.6g}"


# ---------------------------------------------------------------- cross-key checks

def _pin_circle(design):
    """(R_p, K1, 1 - K1) from whichever of pin_circle_radius_mm / curtate_ratio is given."""
    z1, z2 = design["gearing.satellite_teeth"], design["gearing.pins"]
    e, k = design["gearing.eccentricity_mm"], z2 - z1
    Rp, K1 = design["gearing.pin_circle_radius_mm"], design["gearing.curtate_ratio"]
    if K1 is not None:
        return e * z2 / (k * K1), K1, 1.0 - K1
    return Rp, e * z2 / (k * Rp), (k * Rp - e * z2) / (k * Rp)


def check(design, problems: Problems) -> None:
    """Cross-key checks (pins.md §7, §9); every problem is reported."""
    has_g, has_pl = design.has("gearing"), design.has("pin_load")
    if not has_g and not has_pl:
        problems.error("gearing", "missing; a pins design needs [gearing] (cycle model: efficiency, losses "
                                  "over the cycle) or [pin_load] (the paper's per-pin formula level)")
        return
    if has_pl:
        R, r = design["pin_load.pin_radius_mm"], design["pin_load.axle_radius_mm"]
        if r >= R:
            problems.error("pin_load.axle_radius_mm", f"= {_fmt(r)}: must be < pin_load.pin_radius_mm = {_fmt(R)} "
                                                      "(the axle must be smaller than the bushing)")
    if not has_g:
        return
    if not design.has("load"):
        problems.error("load", "missing; a design with [gearing] needs [load] (mode, torque_shaft, torque_Nm, "
                               "crank_speed_rpm)")
    if design["friction.sliding"] is None:
        problems.error("friction.sliding", "missing; required with [gearing] (f, tooth-pin sliding friction; "
                                           "it also drives rotating pins), a number >= 0")
    z1, z2 = design["gearing.satellite_teeth"], design["gearing.pins"]
    e, Rb = design["gearing.eccentricity_mm"], design["gearing.pin_radius_mm"]
    ok_teeth = z2 > z1
    if not ok_teeth:
        problems.error("gearing.pins", f"= {z2}: z2 must exceed z1 (k = z2 - z1 >= 1); "
                                       f"gearing.satellite_teeth = {z1}")
    Rp_given, K1_given = design["gearing.pin_circle_radius_mm"], design["gearing.curtate_ratio"]
    if (Rp_given is None) == (K1_given is None):
        problems.error("gearing.pin_circle_radius_mm",
                       "give exactly one of gearing.pin_circle_radius_mm (R_p) and gearing.curtate_ratio "
                       f"(K1 = e*z2/(k*R_p)); {'both' if Rp_given is not None else 'neither'} given")
    elif ok_teeth:
        Rp, K1, _ = _pin_circle(design)
        k = z2 - z1
        if design["gearing.profile"] == "cycloidal" and K1 >= 1.0:
            if K1_given is not None:
                problems.error("gearing.curtate_ratio", f"= {_fmt(K1)}: K1 = e*z2/(k*R_p) must be < 1 "
                                                        "(a curtate cycloid)")
            else:
                problems.error("gearing.pin_circle_radius_mm",
                               f"= {_fmt(Rp)}: K1 = e*z2/(k*R_p) = {_fmt(K1)} must be < 1: R_p must exceed "
                               f"e*z2/k = {_fmt(e * z2 / k)} mm (or reduce gearing.eccentricity_mm = {_fmt(e)})")
        limit = Rp * math.sin(math.pi / z2)
        if Rb >= limit:
            problems.error("gearing.pin_radius_mm", f"= {_fmt(Rb)}: pins overlap: R_b must be < R_p*sin(pi/z2) = "
                                                    f"{_fmt(limit)} mm (R_p = {_fmt(Rp)} mm, z2 = {z2})")
    if design["gearing.rotating_pins"]:
        r = design["gearing.axle_radius_mm"]
        if r is None:
            problems.error("gearing.axle_radius_mm", "missing; required with rotating_pins = true (r, axle "
                                                     "radius, > 0 and < pin_radius_mm)")
        elif r >= Rb:
            problems.error("gearing.axle_radius_mm", f"= {_fmt(r)}: must be < gearing.pin_radius_mm = {_fmt(Rb)} "
                                                     "(the axle must be smaller than the bushing)")
    rho_t = design["gearing.tooth_radius_mm"]
    one_circle = (Rp_given is None) != (K1_given is None)
    if design["gearing.profile"] == "circular" and ok_teeth and rho_t != "full" and one_circle:
        Rp = _pin_circle(design)[0]
        if Rb + rho_t >= Rp - e:
            problems.error("gearing.tooth_radius_mm",
                           f"= {_fmt(rho_t)}: R_b + rho_t = {_fmt(Rb + rho_t)} mm must be < R_p - e = {_fmt(Rp - e)} "
                           "mm (no zero-backlash tooth circle R_t exists; pins.md §5.3)")
    if design["gearing.profile"] == "cycloidal":
        for key in ("tooth_radius_mm", "tooth_circle_radius_mm"):
            if design.is_given(f"gearing.{key}") and design[f"gearing.{key}"] not in ("full", "zero_backlash"):
                problems.warn(f"gearing.{key} applies to the circular profile only; ignored for a cycloidal one")
    if design["gearing.profile"] == "circular" and _modified(design):
        problems.warn("gearing.equidistant_mod_mm and gearing.radial_mod_mm apply to the cycloidal profile only; "
                      "ignored for a circular one (give tooth_radius_mm / tooth_circle_radius_mm instead)")
    if design.has("contact"):   # without the table, a run at the contact level reports the missing key
        _check_contact_law(design, problems)


def _check_contact_law(design, problems: Problems) -> None:
    """The contact law's own key must be there (pins.md §5.4, §7)."""
    law = design.get("contact.law", "hertz")
    why = ("the contact level runs for a circular profile, a modified cycloid, a [contact] table or "
           "--model contact")
    if law in ("hertz", "palmgren") and design.get("contact.face_width_mm") is None:
        problems.error("contact.face_width_mm", f'missing; required by the {law} contact law (b, face width, '
                                                f'> 0; {why}); or set contact.law = "linear" with '
                                                'contact.stiffness_N_per_mm')
    if law == "linear" and design.get("contact.stiffness_N_per_mm") is None:
        problems.error("contact.stiffness_N_per_mm", "missing; required by the linear contact law (k_lin, "
                                                     f"> 0; {why})")


# ---------------------------------------------------------------- level selection

def _modified(design) -> bool:
    return design["gearing.equidistant_mod_mm"] != 0.0 or design["gearing.radial_mod_mm"] != 0.0


def select_level(design, model: str | None) -> str:
    """The level to run: the forced one (checked against the design) or the cheapest one needed."""
    has_g = design.has("gearing")
    if model is None:
        if not has_g:
            return "formula"
        if design["gearing.profile"] == "circular" or _modified(design) or design.has("contact"):
            return "contact"
        return "ideal"
    if model == "formula" and not design.has("pin_load"):
        raise DesignError("pin_load", "missing; --model formula needs [pin_load] (normal_force_N, "
                                      "pin_speed_rpm, pin_radius_mm, axle_radius_mm)")
    if model in ("ideal", "contact") and not has_g:
        raise DesignError("gearing", f"missing; --model {model} needs [gearing] and [load] (the cycle model)")
    if model == "ideal":
        if design["gearing.profile"] != "cycloidal":
            raise DesignError("gearing.profile", f'= "{design["gearing.profile"]}": the ideal level needs a '
                                                 'conjugate (cycloidal) profile; a circular profile needs the '
                                                 'contact level')
        if _modified(design):
            raise DesignError("gearing.equidistant_mod_mm", "the ideal level has no profile modifications "
                                                            "(they need the contact level); set them to 0")
    return model


# ---------------------------------------------------------------- compute

def compute(design, options: Options) -> Result:
    """Run the level the design needs (or ``--model``); see the module docstring."""
    from .. import pins  # noqa: F401  (numpy and the physics load here, outside the timed model)

    t0 = time.perf_counter()
    level = select_level(design, options.model)
    summary = dict.fromkeys(SUMMARY_KEYS)
    summary["name"] = design.name
    summary["model"] = level
    warnings: list[str] = []
    failed: list[str] = []
    detail: dict = {}
    if design.has("pin_load"):
        _formula(design, summary)
    if level == "formula":
        summary["rotating_pins"] = True        # eqs. (3)-(7) are the paper's rotating-pin losses
    else:
        CYCLE_LEVELS[level](design, options, summary, warnings, failed, detail)
    summary["model_time_ms"] = (time.perf_counter() - t0) * 1e3
    result = Result(summary=summary, detail=detail, warnings=warnings, failed=failed, model=level)
    if summary["self_locking"] and hasattr(result, "labels"):   # tables say why a value is missing (§4.7)
        result.labels.update({k: "self-locking" for k in ("efficiency", "efficiency_err", "efficiency_multiplier",
                                                           "efficiency_multiplier_err", "torque_in_Nm",
                                                           "torque_out_Nm") if summary[k] is None})
    return result


def _formula(design, summary) -> None:
    from .. import pins

    res = pins.formula_losses(design["pin_load.normal_force_N"], design["pin_load.pin_speed_rpm"],
                              design["pin_load.pin_radius_mm"], design["pin_load.axle_radius_mm"],
                              design["friction.rolling_mm"], design["friction.axle"], design["pin_load.paper_pi"])
    summary.update(F_tr1_N=res.F_tr1, F_tr2_N=res.F_tr2, P_tr1_W=res.P_tr1, P_tr2_W=res.P_tr2, P_tr_W=res.P_tr)
    f = design["friction.sliding"]
    if f is not None:
        summary["P_tr_fixed_W"] = pins.fixed_pin_formula_loss(
            design["pin_load.normal_force_N"], design["pin_load.pin_speed_rpm"], design["pin_load.pin_radius_mm"],
            f, design["pin_load.paper_pi"])


# ---------------------------------------------------------------- cycle levels: operating points
#
# The cycle levels share the mapping from a loss ratio to efficiencies and torques, and the friction
# regime; both are vectorised over operating points (arrays), so that a single design and a whole
# sweep run the same code.  The ideal level's geometric solution does not depend on the torque, the
# speed or the friction coefficient (pins.md §4.6, §4.8 identity 8: lambda ∝ mu_eff, F ∝ T,
# v ∝ omega): it is solved once per geometry in unit scalings (IdealSolution) and then scaled to
# every operating point.  The contact level (not available yet) is not linear in the torque: it
# will solve per point and reuse ``_friction_regime`` and ``_efficiency_torques``.

OPERATING_KEYS = ("friction.sliding", "friction.rolling_mm", "friction.axle", "load.mode", "load.torque_shaft",
                  "load.torque_Nm", "load.crank_speed_rpm")
"""Keys an operating point may change without changing the ideal level's geometric solution."""


def _operating_points(design, points=None) -> dict:
    """The operating-point keys as arrays over points (from ``points`` where given, else the design).

    Numbers become float arrays (NaN where absent: no crank speed), words stay lists."""
    import numpy as np

    points = points or [{}]
    out = {}
    for key in OPERATING_KEYS:
        vals = [p.get(key, design[key]) for p in points]
        out[key] = vals if key in ("load.mode", "load.torque_shaft") else np.array(
            [np.nan if v is None else float(v) for v in vals])
    return out


def _friction_regime(design, op):
    """(mu_eff, rolls, rolling_ok) per operating point (pins.md §4.5-4.6); rolling_ok is None for fixed pins."""
    import numpy as np

    from .. import pins

    f, fk, fc = op["friction.sliding"], op["friction.rolling_mm"], op["friction.axle"]
    Rb = design["gearing.pin_radius_mm"]
    if not design["gearing.rotating_pins"]:
        return f, np.zeros(f.shape, dtype=bool), None
    r = design["gearing.axle_radius_mm"]
    ok = pins.rolling_condition(f, Rb, fc, r, fk)
    return np.where(ok, pins.rotating_loss_coefficient(fc, r, fk, Rb), f), ok, ok


def _efficiency_torques(lam, E, op, ratio) -> dict:
    """Efficiencies, self-locking and shaft torques from loss ratios, per operating point (pins.md §4.7).

    Arrays; NaN marks an undefined value (no efficiency when the multiplier self-locks, no T_V
    when it self-locks with the torque given on H).  Keys: locked, eta_vh, eta_vh_err, eta_hv,
    eta_hv_err, efficiency, efficiency_err, T_V, T_H, torque_in, torque_out [N·m]."""
    import numpy as np

    from .. import pins

    multiplier = np.array([m == "multiplier" for m in op["load.mode"]])
    on_V = np.array([s == "V" for s in op["load.torque_shaft"]])
    T = op["load.torque_Nm"]
    locked = lam >= 1.0
    eta_vh = np.where(locked, np.nan, pins.efficiency_multiplier(lam))
    eta_hv = pins.efficiency_reducer(lam)
    eta_hv_err = E / (1.0 + lam) ** 2
    with np.errstate(invalid="ignore"):
        T_V = np.where(on_V, T, np.where(multiplier, ratio * T / eta_vh, eta_hv * ratio * T))
        T_H = np.where(on_V, np.where(multiplier, eta_vh * T / ratio, T / (eta_hv * ratio)), T)
    return {
        "locked": locked, "eta_vh": eta_vh, "eta_vh_err": np.where(locked, np.nan, E), "eta_hv": eta_hv,
        "eta_hv_err": eta_hv_err, "efficiency": np.where(multiplier, eta_vh, eta_hv),
        "efficiency_err": np.where(multiplier, np.where(locked, np.nan, E), eta_hv_err),
        "self_locking": locked & multiplier, "T_V": T_V, "T_H": T_H,
        "torque_in": np.where(multiplier, T_V, T_H), "torque_out": np.where(multiplier, T_H, T_V),
    }


class IdealSolution:
    """The ideal level's solution of one geometry in unit scalings (mu = 1, T_sat = 1 N·mm, |omega_V| = 1).

    g, psi_star, psi_0 : the gear, the end of the loaded arc and the spin reversal [rad];
    unit : the cycle mean of lambda at mu = 1 (pins.CycleIntegral);
    t, tmid, state : the final crank-angle grid and the loaded contacts there (pins.CycleState);
    force, force_phase : max over the cycle and the pins of F/T_sat (summed over the discs) [1/mm]
        and the load-side phase where it occurs [rad];
    loss, loss_phase : the same for P/(mu T_sat |omega_V|) [W per (N·mm·rad/s)];
    total : max over the cycle of the summed losses of all discs, per the same unit;
    rel_min, rel_max, rel_abs : extremes of rho - R_b and of |rho - R_b| over the loaded contacts [mm];
    loaded_min, loaded_max : pins carrying load (per disc).
    """

    def __init__(self, **kw):
        self.__dict__.update(kw)


def _ideal_solution(design, options: Options, warnings) -> IdealSolution:
    """Geometry, admissibility and the unit-scaled cycle solution of a cycloidal design (pins.md §4, §6)."""
    from types import SimpleNamespace

    import numpy as np

    from .. import pins

    z1, z2 = design["gearing.satellite_teeth"], design["gearing.pins"]
    e, Rb = design["gearing.eccentricity_mm"], design["gearing.pin_radius_mm"]
    n_d = design["gearing.discs"]
    Rp, _, omk = _pin_circle(design)
    g = pins.Cycloid(z1, z2, float(e), float(Rp), float(Rb), float(omk))

    # admissibility (pins.md §4.2, §12.10)
    psi_star = pins.crest_cutoff(g)
    if psi_star <= g.period:
        raise DesignError("gearing.satellite_teeth",
                          f"= {z1}: too few teeth for the tooth difference k = {g.k}: at some crank angles no pin "
                          f"carries load (the loaded arc psi* = {_fmt(math.degrees(psi_star))} deg must exceed the "
                          f"pin pitch 360/z2 = {_fmt(360.0 / z2)} deg)")
    rho_c = pins.min_curvature_radius(g, psi_star)
    if Rb >= rho_c:
        raise DesignError("gearing.pin_radius_mm",
                          f"= {_fmt(Rb)}: undercut: R_b must be < the least radius of curvature of the pin-centre "
                          f"curve over the loaded arc, min rho_c = {_fmt(rho_c)} mm (K1 = {_fmt(g.K1)})")
    psi_0 = pins.spin_reversal_phase(g)
    if Rb >= g.R_p * g.one_minus_K1:
        warnings.append(f"R_b = {_fmt(Rb)} mm >= R_p*(1 - K1) = {_fmt(g.R_p * g.one_minus_K1)} mm: the pitch point "
                        "lies inside the pin near entry"
                        + (f"; the pin spin reverses at psi = {_fmt(math.degrees(psi_0))} deg" if psi_0 else ""))

    # cycle mean of the loss ratio per unit friction (pins.md §4.6, §6); lambda_bar = mu_eff * unit
    unit = pins.mean_loss_ratio(g, psi_star, psi_0, 1.0, tol=options.tol)
    t, tmid, _ = unit.quad.grid()
    st = pins.cycle_state(t, tmid, g, psi_star)

    def evaluate(x, mid):
        """Unit force F/T_sat and loss P/(mu T_sat |omega_V|) of the loaded contacts (pins.md §4.4-4.6)."""
        s = pins.cycle_state(x, np.broadcast_to(mid, np.shape(x)), g, psi_star)
        force = np.where(s.loaded, s.lever / s.S, 0.0)
        return SimpleNamespace(phase=s.phase, force=force, loss=pins.contact_loss_power(force, np.abs(s.rho - Rb), 1.0))

    h0 = evaluate(t, tmid)
    force, loss = h0.force, h0.loss
    if n_d == 1:
        picks = [(force, lambda h: h.force), (loss, lambda h: h.loss),
                 (loss.sum(axis=0)[None, :], lambda h: h.loss.sum(axis=0)[None, :])]
        (F1, phF), (P1, phP), (tot, _) = _refined_maxima(t, tmid, evaluate, picks)
    else:   # the discs' histories summed per pin and per crank angle (pins.md §12.7)
        F1, phF = _disc_sum_peak(st.phase, st.loaded, force, n_d)
        P1, phP = _disc_sum_peak(st.phase, st.loaded, loss, n_d)
        tot = float(pins.sum_over_discs(t, loss.sum(axis=0), pins.disc_offsets(n_d, z2), 1.0).max())
    rel = (st.rho - Rb)[st.loaded]
    counts = st.loaded.sum(axis=0)
    return IdealSolution(g=g, psi_star=psi_star, psi_0=psi_0, unit=unit, t=t, tmid=tmid, state=st,
                         force=F1, force_phase=phF, loss=P1, loss_phase=phP, total=tot,
                         rel_min=float(rel.min()), rel_max=float(rel.max()), rel_abs=float(np.abs(rel).max()),
                         loaded_min=int(counts.min()), loaded_max=int(counts.max()))


def _ideal_summaries(design, sol: IdealSolution, op) -> tuple[list[dict], dict]:
    """Summaries of the operating points ``op`` (arrays) of one solved geometry, and the arrays used."""
    import numpy as np

    from .. import units

    g = sol.g
    n_d = design["gearing.discs"]
    mu, rolls, rolling_ok = _friction_regime(design, op)
    lam, E = mu * sol.unit.loss_ratio, mu * sol.unit.loss_ratio_err
    et = _efficiency_torques(lam, E, op, g.ratio)
    T_sat = units.nm_to_nmm(et["T_V"]) / n_d                                  # N·mm per disc
    w_V = units.rpm_to_rad_s(op["load.crank_speed_rpm"]) * g.k / g.z1        # |omega_V| [rad/s]
    F_max = T_sat * sol.force                                                 # N
    spin_rpm = units.rad_s_to_rpm(w_V) / g.R_b                                # rpm per mm of rho - R_b
    v_max = w_V * sol.rel_abs                                                 # mm/s
    mu_rot = np.where(rolls, mu, np.nan)
    cols = {
        "rolling_ok": rolling_ok, "efficiency": et["efficiency"], "efficiency_err": et["efficiency_err"],
        "self_locking": et["self_locking"], "efficiency_multiplier": et["eta_vh"],
        "efficiency_multiplier_err": et["eta_vh_err"], "efficiency_reducer": et["eta_hv"],
        "efficiency_reducer_err": et["eta_hv_err"], "loss_ratio": lam, "loss_ratio_err": E,
        "torque_in_Nm": et["torque_in"], "torque_out_Nm": et["torque_out"],
        "loss_mean_W": lam * et["T_V"] * w_V, "loss_peak_W": mu * T_sat * w_V * sol.total,
        "pin_force_max_N": F_max, "pin_loss_max_W": mu * T_sat * w_V * sol.loss,
        "pin_loss_bound_W": np.where(rolls, mu_rot, op["friction.sliding"]) * F_max * v_max * 1e-3,
        "pin_speed_max_rpm": np.where(rolls, spin_rpm * max(abs(sol.rel_min), abs(sol.rel_max)), 0.0 * w_V),
        "pin_speed_signed_min_rpm": np.where(rolls, spin_rpm * sol.rel_min, 0.0 * w_V),
        "pin_speed_signed_max_rpm": np.where(rolls, spin_rpm * sol.rel_max, 0.0 * w_V),
        "spin_reversals": (rolls & (sol.psi_0 is not None and sol.psi_0 < sol.psi_star)).astype(int),
        "sliding_speed_max_m_s": np.where(rolls, 0.0 * w_V, v_max / units.MM_PER_M),
    }
    fixed = {"model": "ideal", "profile": "cycloidal", "rotating_pins": design["gearing.rotating_pins"],
             "ratio": g.ratio, "curtate_ratio": g.K1, "pin_force_max_phase_deg": math.degrees(sol.force_phase),
             "pin_loss_max_phase_deg": math.degrees(sol.loss_phase), "loaded_pins_min": sol.loaded_min,
             "loaded_pins_max": sol.loaded_max, "psi_star_deg": math.degrees(sol.psi_star),
             "n_crank": sol.unit.n_crank, "tolerance_met": sol.unit.converged}
    out = []
    for k in range(lam.size):
        s = dict.fromkeys(SUMMARY_KEYS)
        s.update(fixed)
        s["mode"] = op["load.mode"][k]
        for key, arr in cols.items():
            s[key] = None if arr is None else _plain(arr[k])
        if s["pin_force_max_N"] is None:
            s["pin_force_max_phase_deg"] = None
        if s["pin_loss_max_W"] is None:
            s["pin_loss_max_phase_deg"] = None
        out.append(s)
    return out, {"mu": mu, "rolls": rolls, "lam": lam, "E": E, "T_sat": T_sat, "w_V": w_V}


def _plain(x):
    """A numpy scalar as a plain bool/int/float, NaN as None (undefined)."""
    import numpy as np

    if isinstance(x, (np.bool_, bool)):
        return bool(x)
    if isinstance(x, (np.integer, int)):
        return int(x)
    x = float(x)
    return None if math.isnan(x) else x


def _ideal(design, options: Options, summary, warnings, failed, detail) -> None:
    """The rigid conjugate cycle model (pins.md §4) of one cycloidal design: a one-point sweep."""
    from .. import pins

    if design.has("contact"):   # only with --model ideal: a [contact] table otherwise selects "contact"
        warnings.append("the [contact] table is not used by the ideal level")
    sol = _ideal_solution(design, options, warnings)
    op = _operating_points(design)
    (s,), used = _ideal_summaries(design, sol, op)
    summary.update({k: v for k, v in s.items() if k not in ("name", "model_time_ms") and k not in _FORMULA_KEYS})
    _cycle_notes(design, s, options, warnings, failed)
    if options.detail:
        T_sat = float(used["T_sat"][0]) if s["pin_force_max_N"] is not None else None
        w_V = float(used["w_V"][0]) if design["load.crank_speed_rpm"] is not None else None
        sigma = pins.MULTIPLIER if design["load.mode"] == "multiplier" else pins.REDUCER
        detail.update(_detail_tables(sol.g, sigma, sol.state, sol.t, float(used["mu"][0]), T_sat,
                                     None if w_V is None else -w_V, bool(used["rolls"][0]), design["gearing.discs"]))


def _cycle_notes(design, s, options: Options, warnings, failed) -> None:
    """Warnings and failed checks shared by the cycle levels (pins.md §4.5, §4.7, §6, §12.4)."""
    f, fk, fc, Rb = (design["friction.sliding"], design["friction.rolling_mm"], design["friction.axle"],
                     design["gearing.pin_radius_mm"])
    if s["rolling_ok"] is False:
        r = design["gearing.axle_radius_mm"]
        warnings.append(f"rolling condition f*R_b >= f_c*r + f_k fails (f = {_fmt(f)}, R_b = {_fmt(Rb)} mm, "
                        f"f_c = {_fmt(fc)}, r = {_fmt(r)} mm, f_k = {_fmt(fk)} mm: {_fmt(f * Rb)} < "
                        f"{_fmt(fc * r + fk)}): the bushings cannot turn; treated as fixed pins sliding with f")
    lam, E = s["loss_ratio"], s["loss_ratio_err"]
    if not s["tolerance_met"]:
        warnings.append(f"tolerance {options.tol:g} not met at {s['n_crank']} crank-angle intervals: "
                        f"loss ratio {lam:.10g} +- {E:.3g}")
    if s["self_locking"]:
        failed.append(f"self-locking in the multiplier mode: the loss ratio {lam:.6g} >= 1 (the losses exceed "
                      "the power the V shaft delivers); no efficiency")
    if abs(1.0 - lam) <= E:
        warnings.append(f"at the self-locking limit: the loss ratio {lam:.10g} is within its error {E:.3g} of 1")
    if design["load.crank_speed_rpm"] is None:
        warnings.append("loss_mean_W, loss_peak_W, pin_loss_max_W, pin_loss_bound_W and the pin and sliding speeds "
                        "need load.crank_speed_rpm; they are left empty")


_FORMULA_KEYS = ("F_tr1_N", "F_tr2_N", "P_tr1_W", "P_tr2_W", "P_tr_W", "P_tr_fixed_W")


def sweep(base, raw, axes, points, options):
    """A grid of operating points of one geometry as arrays (the ideal level; pins.md §4.8 identity 8).

    The geometry is solved once; friction, torque, speed, mode and torque shaft (``OPERATING_KEYS``)
    scale it per point.  Other varied keys, or a design that is not at the ideal level, return None:
    the caller evaluates point by point.  The result equals point-by-point evaluation.
    """
    import time as _time

    from .. import pins

    if not base.has("gearing") or any(k not in OPERATING_KEYS for k in axes):
        return None
    if select_level(base, options.model) != "ideal":
        return None
    t0 = _time.perf_counter()
    sol = _ideal_solution(base, options, [])
    op = _operating_points(base, points)
    summaries, _ = _ideal_summaries(base, sol, op)
    if base.has("pin_load"):
        res = pins.formula_losses(base["pin_load.normal_force_N"], base["pin_load.pin_speed_rpm"],
                                  base["pin_load.pin_radius_mm"], base["pin_load.axle_radius_mm"],
                                  op["friction.rolling_mm"], op["friction.axle"], base["pin_load.paper_pi"])
        fix = pins.fixed_pin_formula_loss(base["pin_load.normal_force_N"], base["pin_load.pin_speed_rpm"],
                                          base["pin_load.pin_radius_mm"], op["friction.sliding"],
                                          base["pin_load.paper_pi"])
        for k, s in enumerate(summaries):
            s.update(F_tr1_N=float(res.F_tr1[k]), F_tr2_N=float(res.F_tr2[k]), P_tr1_W=float(res.P_tr1[k]),
                     P_tr2_W=float(res.P_tr2[k]), P_tr_W=float(res.P_tr[k]), P_tr_fixed_W=float(fix[k]))
    per_point = (_time.perf_counter() - t0) * 1e3 / len(points)
    for s in summaries:
        s["name"] = base.name
        s["model_time_ms"] = per_point
    return summaries


def _contact_law(design):
    """The contact law of the design (pins.md §5.4); DesignError when its key is missing."""
    from .. import pins_contact as pc

    problems = Problems()
    _check_contact_law(design, problems)
    if problems.errors:
        raise DesignError(*problems.errors[0])
    return pc.contact_law(design.get("contact.law", "hertz"), design.get("contact.face_width_mm"),
                          design.get("contact.stiffness_N_per_mm"))


def _contact_profile(design, g, warnings):
    """The satellite profile of the contact level with its admissibility checks (pins.md §5.2-5.3, §9).

    Returns (profile, fields): fields holds tooth_radius_mm and tooth_circle_radius_mm (circular)."""
    from .. import pins
    from .. import pins_contact as pc

    Rp, Rb, e, z1, z2 = g.R_p, g.R_b, g.e, g.z1, g.z2
    if design["gearing.profile"] == "circular":
        rho_t, R_t = design["gearing.tooth_radius_mm"], design["gearing.tooth_circle_radius_mm"]
        explicit_R_t = R_t != "zero_backlash"
        if rho_t == "full":
            if R_t != "zero_backlash":
                s = math.sin(math.pi / z1)
                rho_t = R_t * s        # adjacent teeth tangent at the root on the given circle
            else:
                full = pc.full_tooth(g)
                if full is None:
                    raise DesignError("gearing.tooth_radius_mm",
                                      f'= "full": no full circular tooth fits: R_b = {_fmt(Rb)} mm must be < R_p - e '
                                      f"= {_fmt(Rp - e)} mm with a tooth circle that meets the pins' paths "
                                      "(pins.md §5.3)")
                rho_t, R_t = full
        if Rb + rho_t >= Rp - e:
            raise DesignError("gearing.tooth_radius_mm",
                              f"= {_fmt(rho_t)}: R_b + rho_t = {_fmt(Rb + rho_t)} mm must be < R_p - e = "
                              f"{_fmt(Rp - e)} mm (no zero-backlash tooth circle R_t exists; pins.md §5.3)")
        if not explicit_R_t and R_t == "zero_backlash":
            R_t = pc.zero_backlash_tooth_circle(g, rho_t)
            if R_t is None:
                raise DesignError("gearing.tooth_radius_mm",
                                  f"= {_fmt(rho_t)}: no zero-backlash tooth circle: the tooth never reaches the pins' "
                                  f"nominal paths (R_b + rho_t = {_fmt(Rb + rho_t)} mm; pins.md §5.3)")
        elif explicit_R_t:
            D = float(pc.tooth_centre_distance(R_t, g))
            if D < Rb + rho_t - 1e-12 * Rp:
                raise DesignError("gearing.tooth_circle_radius_mm",
                                  f"= {_fmt(R_t)}: the teeth interfere with the pins at nominal by "
                                  f"{_fmt((Rb + rho_t - D) * 1e3)} um (least distance from a tooth centre to the "
                                  f"pins' paths {_fmt(D)} mm < R_b + rho_t = {_fmt(Rb + rho_t)} mm); make it smaller "
                                  "or use \"zero_backlash\"")
        if rho_t > R_t * math.sin(math.pi / z1) * (1.0 + 1e-12):
            warnings.append(f"tooth_radius_mm = {_fmt(rho_t)} exceeds the full tooth R_t*sin(pi/z1) = "
                            f"{_fmt(R_t * math.sin(math.pi / z1))} mm: adjacent tooth circles overlap")
        return pc.CircularProfile(g, rho_t, R_t), {"tooth_radius_mm": float(rho_t),
                                                   "tooth_circle_radius_mm": float(R_t)}
    dRb, dRp = design["gearing.equidistant_mod_mm"], design["gearing.radial_mod_mm"]
    k = g.k
    Rpd = Rp + dRp
    if Rpd <= 0.0 or e * z2 >= k * Rpd:
        raise DesignError("gearing.radial_mod_mm",
                          f"= {_fmt(dRp)}: the design curve's K1 = e*z2/(k*(R_p + Delta R_p)) = "
                          f"{_fmt(e * z2 / (k * Rpd)) if Rpd > 0 else 'inf'} must be < 1")
    if Rb + dRb <= 0.0:
        raise DesignError("gearing.equidistant_mod_mm", f"= {_fmt(dRb)}: R_b + Delta R_b = {_fmt(Rb + dRb)} mm must "
                                                        "be > 0")
    prof = pc.CycloidProfile(g, dRp, dRb)
    gd = prof.design
    if prof.psi_star <= g.period:
        raise DesignError("gearing.satellite_teeth",
                          f"= {z1}: too few teeth for the tooth difference k = {k}: at some crank angles no pin "
                          f"carries load (the loaded arc psi* = {_fmt(math.degrees(prof.psi_star))} deg must exceed "
                          f"the pin pitch 360/z2 = {_fmt(360.0 / z2)} deg)")
    rho_c = pins.min_curvature_radius(gd, prof.psi_star)
    if gd.R_b >= rho_c:
        key = "gearing.equidistant_mod_mm" if dRb != 0.0 else "gearing.pin_radius_mm"
        raise DesignError(key, f"= {_fmt(design[key])}: undercut: R_b + Delta R_b = {_fmt(gd.R_b)} mm must be < the "
                               f"least radius of curvature of the design curve over the loaded arc, min rho_c = "
                               f"{_fmt(rho_c)} mm")
    return prof, {}


def _contact(design, options: Options, summary, warnings, failed, detail) -> None:
    """The compliant contact level (pins.md §5) of one design (circular or cycloidal profile).

    The satellite rotation is solved at every crank angle (gearcalc.pins_contact); the cycle mean of
    the loss ratio uses the shared quadrature with contact entry/exit and spin reversals as
    breakpoints.  The loss ratio depends (weakly) on the torque, so with the torque given on H the
    torque on V is iterated to the fixed point T_V = u T_H/eta (multiplier) or eta u T_H (reducer)
    (pins.md §7)."""
    import numpy as np

    from .. import pins, units
    from .. import pins_contact as pc

    z1, z2 = design["gearing.satellite_teeth"], design["gearing.pins"]
    e, Rb, n_d = design["gearing.eccentricity_mm"], design["gearing.pin_radius_mm"], design["gearing.discs"]
    Rp, _, omk = _pin_circle(design)
    g = pins.Cycloid(z1, z2, float(e), float(Rp), float(Rb), float(omk))
    law = _contact_law(design)
    profile, geo = _contact_profile(design, g, warnings)
    op = _operating_points(design)
    mu_a, rolls_a, rolling_ok = _friction_regime(design, op)
    mu, rolls, f = float(mu_a[0]), bool(rolls_a[0]), float(design["friction.sliding"])
    multiplier = design["load.mode"] == "multiplier"
    sigma = pins.MULTIPLIER if multiplier else pins.REDUCER
    friction = (mu, f, rolls) if design.get("contact.friction_in_equilibrium", False) else None
    on_V = design["load.torque_shaft"] == "V"
    T = float(design["load.torque_Nm"])
    lam, cyc, T_V, history = 0.0, None, None, []
    for _ in range(8):                    # the torque fixed point (one pass when T is given on V)
        if on_V:
            T_V = T
        elif multiplier:
            if lam >= 1.0:
                break                      # self-locking: no T_V balances T_H; keep the last solution
            T_V = g.ratio * T / (1.0 - lam)
        else:
            T_V = g.ratio * T / (1.0 + lam)
        model = pc.ContactModel(g, profile, law, units.nm_to_nmm(T_V) / n_d, sigma, friction)
        try:
            with np.errstate(all="ignore"):       # non-finite values are caught below, never printed
                cyc = pc.mean_loss_ratio(model, mu, f, rolls, tol=options.tol)
        except pc.NoEquilibrium as exc:
            key = ("gearing.tooth_circle_radius_mm" if design["gearing.profile"] == "circular"
                   else "gearing.equidistant_mod_mm")
            raise DesignError(key, f"= {design[key]}: no contact can carry the torque at crank angle "
                                   f"{_fmt(math.degrees(float(exc.theta[0])))} deg: no satellite rotation within "
                                   f"+-180/z1 = {_fmt(180.0 / z1)} deg balances T_V = {_fmt(T_V)} N*m (the teeth "
                                   "do not mesh with the pins, or the torque crushes the contacts; pins.md "
                                   "§5.5)") from None
        if not (np.isfinite(cyc.loss_ratio) and np.all(np.isfinite(cyc.sol.force)) and np.all(np.isfinite(cyc.lam))):
            raise DesignError("gearing.eccentricity_mm",
                              f"= {_fmt(e)}: the contact level cannot resolve this geometry in floating point "
                              f"(R_p = {_fmt(Rp)} mm, e = {_fmt(e)} mm, R_b = {_fmt(Rb)} mm: the deflections are "
                              "below the round-off of the pin positions)")
        history.append(cyc.loss_ratio)
        lam = cyc.loss_ratio
        if on_V or _fixed_point_settled(history, options.tol):
            break
    else:
        warnings.append(f"the torque fixed point T_V = u T_H/eta did not settle in 8 passes (loss ratios "
                        f"{history[-2]:.10g}, {history[-1]:.10g})")
    E = cyc.loss_ratio_err
    if mu == 0.0 and f == 0.0:
        lam, E = 0.0, 0.0
    et = _efficiency_torques(np.array([lam]), np.array([E]), op, g.ratio)
    sol = cyc.sol
    n_H = design["load.crank_speed_rpm"]
    w_H = units.rpm_to_rad_s(n_H) if n_H is not None else None
    Fmax_c = sol.force                                                     # (c, z2, n)
    loaded_c = Fmax_c > 0.0
    loaded = loaded_c.any(axis=0)
    F_pin = Fmax_c.max(axis=0)
    loss_pin = cyc.loss.sum(axis=0)                                        # N·mm/s per rad/s
    t = sol.theta / g.period
    if n_d == 1:
        i = np.unravel_index(int(np.argmax(F_pin)), F_pin.shape)
        F1, phF = float(F_pin[i]), float(sol.phase[i])
        i = np.unravel_index(int(np.argmax(loss_pin)), loss_pin.shape)
        P1, phP = float(loss_pin[i]), float(sol.phase[i])
        tot = float(loss_pin.sum(axis=0).max())
    else:
        F1, phF = _disc_sum_peak(sol.phase, loaded, F_pin, n_d)
        P1, phP = _disc_sum_peak(sol.phase, loaded, loss_pin, n_d)
        tot = float(pins.sum_over_discs(t, loss_pin.sum(axis=0), pins.disc_offsets(n_d, z2), 1.0).max())
    vt_load = np.abs(sol.v_t[loaded_c]) if loaded_c.any() else np.zeros(1)
    spin_load = cyc.spin[loaded] if rolls else np.zeros(1)
    slide_load = cyc.slide[loaded_c] if loaded_c.any() else np.zeros(1)
    metrics = pc.engagement_metrics(sol, cyc.spin if rolls else np.zeros(F_pin.shape))
    counts = loaded.sum(axis=0)
    observed = sol.phase[loaded]
    backlash = _backlash(model, profile, design)
    s = {
        "model": "contact", "profile": design["gearing.profile"], "rotating_pins": design["gearing.rotating_pins"],
        "mode": design["load.mode"], "ratio": g.ratio, "curtate_ratio": g.K1,
        "rolling_ok": None if rolling_ok is None else bool(rolling_ok[0]),
        "loss_ratio": lam, "loss_ratio_err": E, "n_crank": cyc.n_crank, "tolerance_met": bool(cyc.converged),
        "pin_force_max_N": F1 if math.isfinite(T_V) else None,
        "pin_force_max_phase_deg": math.degrees(phF), "loaded_pins_min": int(counts.min()),
        "loaded_pins_max": int(counts.max()),
        "psi_star_deg": math.degrees(float(observed.max())) if observed.size else None,
        "exit_entry_force_ratio": metrics["exit_entry_force_ratio"],
        "low_spin_fraction": metrics["low_spin_fraction"], "spin_reversals": metrics["spin_reversals"],
        "te_pp_arcsec": math.degrees(float(sol.tau.max() - sol.tau.min())) * 3600.0,
        "backlash_deg": backlash,
        "equilibrium_residual": float(np.abs(sol.residual).max() / model.torque_sat),
        "contact_law": law.name, "tooth_radius_mm": geo.get("tooth_radius_mm"),
        "tooth_circle_radius_mm": geo.get("tooth_circle_radius_mm"),
    }
    for key, name in (("efficiency", "efficiency"), ("efficiency_err", "efficiency_err"),
                      ("self_locking", "self_locking"), ("efficiency_multiplier", "eta_vh"),
                      ("efficiency_multiplier_err", "eta_vh_err"), ("efficiency_reducer", "eta_hv"),
                      ("efficiency_reducer_err", "eta_hv_err"), ("torque_in_Nm", "torque_in"),
                      ("torque_out_Nm", "torque_out")):
        s[key] = _plain(et[name][0])
    if w_H is not None:
        Pw = w_H * 1e-3                                                   # W per (N·mm/s per rad/s)
        s["loss_mean_W"] = lam * T_V * (w_H * g.k / g.z1)
        s["loss_peak_W"] = tot * Pw
        s["pin_loss_max_W"] = P1 * Pw
        s["pin_loss_max_phase_deg"] = math.degrees(phP)
        coeff = mu if rolls else f
        s["pin_loss_bound_W"] = coeff * F1 * float(vt_load.max()) * Pw
        rpm = units.rad_s_to_rpm(w_H)
        s["pin_speed_max_rpm"] = float(np.abs(spin_load).max()) * rpm if rolls else 0.0
        s["pin_speed_signed_min_rpm"] = float(spin_load.min()) * rpm if rolls else 0.0
        s["pin_speed_signed_max_rpm"] = float(spin_load.max()) * rpm if rolls else 0.0
        s["sliding_speed_max_m_s"] = (float(slide_load.max()) if rolls else float(vt_load.max())) * w_H / units.MM_PER_M
    summary.update(s)
    _cycle_notes(design, summary, options, warnings, failed)
    if s["equilibrium_residual"] > 1e-9:
        warnings.append(f"equilibrium residual {s['equilibrium_residual']:.3g} of the torque at some crank angle")
    if options.detail:
        detail.update(_contact_detail(g, sol, cyc, T_V, w_H, n_d))


def _fixed_point_settled(history, tol: float) -> bool:
    """Whether the torque fixed point has settled: the remaining error c |d_n|/(1 - c) of the last loss
    ratio, with the contraction c = |d_n/d_(n-1)| of the last two changes d, is below tol/10 of it."""
    if len(history) < 2:
        return False
    d1 = abs(history[-1] - history[-2])
    if d1 <= 1e-15 + 1e-3 * tol * abs(history[-1]):
        return True
    if len(history) < 3:
        return False
    c = d1 / max(abs(history[-2] - history[-3]), 1e-300)
    return c < 0.5 and c * d1 / (1.0 - c) <= 0.1 * tol * abs(history[-1])


def _backlash(model, profile, design):
    """backlash_deg: the satellite's angular play at no load, both flanks [deg] (pins.md §5.3).

    For each flank, the least rotation over the cycle from the nominal position to the first contact
    (:func:`gearcalc.pins_contact.free_play`), summed over the two flanks: 0 for an unmodified cycloid
    and for the zero-backlash tooth circle (it touches the pins' paths), positive with clearance.
    Sampled on 129 crank angles of one period, each least value refined by golden-section search
    between the neighbouring angles."""
    import numpy as np

    from .. import pins_contact as pc
    from ..roots import minimize_golden

    if design["gearing.profile"] == "cycloidal" and not _modified(design):
        return 0.0
    if design["gearing.profile"] == "circular" and design["gearing.tooth_circle_radius_mm"] == "zero_backlash":
        return 0.0
    Tp = model.g.period
    theta = np.linspace(0.0, Tp, 129)
    total = 0.0
    for side in (0, 1):
        def play(x, side=side):
            pair = pc.free_play(model, np.atleast_1d(x))
            return np.reshape(np.abs(pair[side]), np.shape(x))

        p = play(theta)
        i = int(np.argmin(p))
        a, b = theta[max(i - 1, 0)], theta[min(i + 1, theta.size - 1)]
        res = minimize_golden(play, a, b, rtol=1e-9)
        total += min(float(res.fun), float(p[i]))
    return math.degrees(total)


def _contact_detail(g, sol, cyc, T_V, w_H, n_d):
    """Detail tables of the contact level (pins.md §8): ``crank`` and ``contacts`` rows of the final grid
    (first disc; piece ends appear twice, the one-sided limits)."""
    import numpy as np

    from .. import units

    theta_deg = np.degrees(sol.theta)
    have_P = w_H is not None
    lam = cyc.lam
    loaded_c = sol.force > 0.0
    crank = _rows({
        "theta_deg": theta_deg, "TE_arcsec": np.degrees(sol.tau) * 3600.0, "loss_ratio": lam,
        "loss_W": lam * n_d * units.nm_to_nmm(T_V) / n_d * (w_H * g.k / g.z1) * 1e-3 if have_P else None,
        "loaded_pins": loaded_c.any(axis=0).sum(axis=0),
    })
    n_idx, j_idx, c_idx = np.nonzero(np.transpose(loaded_c, (2, 1, 0)))    # row-major: node, pin, contact
    rpm = units.rad_s_to_rpm(w_H) if have_P else None
    contacts = _rows({
        "theta_deg": theta_deg[n_idx], "pin": j_idx, "contact": c_idx,
        "phase_deg": np.degrees(sol.phase[j_idx, n_idx]), "force_N": sol.force[c_idx, j_idx, n_idx],
        "penetration_um": sol.delta[c_idx, j_idx, n_idx] * units.UM_PER_MM,
        "sliding_speed_m_s": cyc.slide[c_idx, j_idx, n_idx] * w_H / units.MM_PER_M if have_P else None,
        "pin_speed_rpm": cyc.spin[j_idx, n_idx] * rpm if have_P else None,
        "loss_W": cyc.loss[c_idx, j_idx, n_idx] * w_H * 1e-3 if have_P else None,
    })
    return {"crank": crank, "contacts": contacts}


CYCLE_LEVELS = {"ideal": _ideal, "contact": _contact}
"""The cycle-model levels: each fills the summary of a design with [gearing] and [load]."""


def _refined_maxima(t, tmid, evaluate, picks):
    """Maxima of several gridded quantities, each refined between the neighbouring nodes of its piece.

    picks : list of (values (rows, nodes) on the grid, quantity(histories) -> (rows, points)).
    Each maximum starts at its largest grid entry; one golden-section search (gearcalc.roots,
    vectorised over the picks) refines it inside the bracket of the neighbouring nodes of the same
    piece (piece ends stay one-sided values).  Returns [(max, load-side phase at the max [rad])]
    (the phase of the first contact row for a quantity with one row, such as a total)."""
    import numpy as np

    from ..roots import minimize_golden

    rows, nodes, lo, hi, grid_best = [], [], [], [], []
    for values, _ in picks:
        row, n = np.unravel_index(int(np.argmax(values)), values.shape)
        rows.append(int(row))
        nodes.append(int(n))
        grid_best.append(float(values[row, n]))
        lo.append(t[n - 1] if n > 0 and tmid[n - 1] == tmid[n] else t[n])
        hi.append(t[n + 1] if n + 1 < t.size and tmid[n + 1] == tmid[n] else t[n])
    mid = tmid[nodes]

    def negative(x):
        h = evaluate(np.asarray(x, dtype=float), mid)
        return -np.array([q(h)[rows[i], i] for i, (_, q) in enumerate(picks)])

    res = minimize_golden(negative, np.array(lo), np.array(hi), rtol=1e-12)
    better = -res.fun > np.array(grid_best)
    t_best = np.where(better, res.x, t[nodes])
    best = np.where(better, -res.fun, grid_best)
    phase = evaluate(t_best, mid).phase[rows, np.arange(len(picks))]
    return [(float(b), float(p)) for b, p in zip(best, phase)]


def _disc_sum_peak(phase, loaded, values, n_d: int):
    """Peak over the cycle and the pins of a per-contact quantity summed over n_d discs, and its phase.

    The discs are 2 pi/n_d apart: a pin's history at phase psi is sum_d v(psi - 2 pi d/n_d) (pins.md
    §12.7), interpolated linearly between the samples of the first disc (error O(h^2))."""
    import numpy as np

    x, val = phase[loaded], values[loaded]
    order = np.argsort(x, kind="stable")
    x, val = x[order], val[order]
    shifts = -2.0 * np.pi * np.arange(n_d) / n_d
    pts = np.unique(np.concatenate([np.mod(x - s, 2.0 * np.pi) for s in shifts]))
    tot = np.zeros_like(pts)
    for s in shifts:  # a handful of discs; vectorised over the samples
        tot += np.interp(np.mod(pts + s, 2.0 * np.pi), x, val, left=0.0, right=0.0)
    i = int(np.argmax(tot))
    return float(tot[i]), float(pts[i])


def _rows(columns: dict) -> list[dict]:
    """Rows (dicts) from equal-length columns; a None column stays None in every row."""
    n = max(len(v) for v in columns.values() if v is not None)
    cols = {k: (v.tolist() if hasattr(v, "tolist") else v) if v is not None else [None] * n
            for k, v in columns.items()}
    keys = list(cols)
    return [dict(zip(keys, vals)) for vals in zip(*cols.values())]


def _detail_tables(g, sigma, st, t, mu, T_sat, omega_V, rolls, n_d: int = 1):
    """Rows of the final grid (pins.md §8): ``crank`` (one per crank angle: the loss ratio and loss of
    all discs, the loaded pins of the first) and ``contacts`` (one per loaded contact of the first disc);
    piece ends appear twice (the one-sided limits of both sides)."""
    import numpy as np

    from .. import pins, units

    Tp_deg = 360.0 / g.z2
    lam = mu * np.sum(st.lever * np.abs(st.rho - g.R_b), axis=0) / st.S
    if n_d > 1:   # all discs: the mean of the discs' shifted histories (pins.md §12.7)
        lam = pins.sum_over_discs(t, lam, pins.disc_offsets(n_d, g.z2), 1.0) / n_d
    if sigma == pins.MULTIPLIER:      # theta = T_p t, pin i = -j mod z2
        theta, pin_shift, pin_sign = t * Tp_deg, 0, -1
    else:                             # theta = T_p (1 - t), pin i = j + 1 mod z2
        theta, pin_shift, pin_sign = (1.0 - t) * Tp_deg, 1, 1
    order = np.argsort(theta, kind="stable")
    have_P = T_sat is not None and omega_V is not None
    crank = _rows({
        "theta_deg": theta[order], "TE_arcsec": np.zeros(order.size), "loss_ratio": lam[order],
        "loss_W": (lam * (n_d * T_sat * abs(omega_V) * 1e-3))[order] if have_P else None,
        "loaded_pins": st.loaded.sum(axis=0)[order],
    })
    loaded = st.loaded[:, order]
    jj, nn = np.nonzero(loaded.T)[1], order[np.nonzero(loaded.T)[0]]      # row-major by node, then pin
    F = T_sat * st.lever[jj, nn] / st.S[nn] if T_sat is not None else None
    v = pins.sliding_speed(st.rho[jj, nn], g.R_b, omega_V) if omega_V is not None else None
    if omega_V is not None:
        spin = units.rad_s_to_rpm(pins.pin_spin(st.rho[jj, nn], g.R_b, omega_V)) if rolls else np.zeros(jj.size)
        slide = np.zeros(jj.size) if rolls else v / units.MM_PER_M
    else:
        spin = slide = None
    contacts = _rows({
        "theta_deg": theta[nn], "pin": (pin_sign * jj + pin_shift) % g.z2,
        "phase_deg": np.degrees(st.phase[jj, nn]), "force_N": F, "sliding_speed_m_s": slide,
        "pin_speed_rpm": spin, "loss_W": pins.contact_loss_power(F, v, mu) if have_P else None,
    })
    return {"crank": crank, "contacts": contacts}


def plot(records, path: str) -> None:
    """The pins figure (pins.md §8): force, pin speed and loss of one pin against crank angle over one
    engagement, and lambda(theta) over one period; one curve per design (up to 6).  Formula-level
    designs get a bar chart of P_tr1 and P_tr2 instead."""
    import numpy as np

    from ..design import validate
    from ..plot import _pyplot, save

    plt = _pyplot()
    cyc = [r for r in records if r.result.model != "formula"][:6]
    if not cyc:
        recs = records[:12]
        fig, ax = plt.subplots(figsize=(7.5, 4))
        x = np.arange(len(recs))
        p1 = [r.result.summary["P_tr1_W"] for r in recs]
        p2 = [r.result.summary["P_tr2_W"] for r in recs]
        ax.bar(x, p1, label="P_tr1 (rolling, eq. 5)")
        ax.bar(x, p2, bottom=p1, label="P_tr2 (axle, eq. 6)")
        ax.set_xticks(x, [r.name for r in recs], rotation=20, ha="right", fontsize=7)
        ax.set_ylabel("maximum loss per pin [W]")
        ax.legend()
        save(fig, path)
        return
    fig, axes = plt.subplots(2, 2, figsize=(10, 7))
    (aF, aN), (aP, aL) = axes
    for rec in cyc:
        d = validate(dict(rec.design), rec.source)
        res = compute(d, Options(model=rec.result.model, detail=True))
        s = res.summary
        rows = sorted(res.detail["contacts"], key=lambda r: r["phase_deg"])
        phase = np.array([r["phase_deg"] for r in rows])
        # crank angle since the pin entered its loaded arc
        since = phase if s["mode"] == "multiplier" else s["psi_star_deg"] - phase
        label = rec.name
        for ax, key in ((aF, "force_N"), (aN, "pin_speed_rpm"), (aP, "loss_W")):
            y = [r[key] for r in rows]
            if all(v is not None for v in y):
                ax.plot(since, y, label=label)
        crank = res.detail["crank"]
        aL.plot([r["theta_deg"] for r in crank], [r["loss_ratio"] for r in crank], label=label)
    for ax, ylab in ((aF, "pin force F [N]"), (aN, "pin speed n_pin [rpm]"), (aP, "pin loss P [W]")):
        ax.set_xlabel("crank angle since entry [deg]")
        ax.set_ylabel(ylab)
    aL.set_xlabel("crank angle theta over one period 360/z2 [deg]")
    aL.set_ylabel("loss ratio lambda")
    aL.legend(fontsize=7)
    save(fig, path)


CALCULATOR = Calculator(
    kind="pins",
    title="KHV planetary pin gearing: per-pin friction losses and efficiency",
    tables=TABLES,
    compute=compute,
    check=check,
    models=MODELS,
    header=HEADER,
    sweep=sweep,
    plot=plot,
)
