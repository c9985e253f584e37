"""The ``pins`` calculator: KHV planetary pin gearing, per-pin friction losses and efficiency.

Schema, cross-key checks and the glue between a design and the physics of :mod:`gearcalc.pins` and
:mod:`gearcalc.pins_outputs` (spec: pins.md): design keys to physics arguments, physics results to named
output fields, and the warning and error texts.  Three model levels; this module picks the cheapest one the design needs:

* ``formula``: the paper's eqs. (3)-(7) from a given normal force and pin speed ([pin_load]);
* ``ideal``: the rigid conjugate cycle model of a cycloidal satellite ([gearing], no modifications);
* ``contact``: the compliant contact model of :mod:`gearcalc.pins_contact` (circular-arc teeth,
  cycloids with clearance or modifications, a [contact] table, or ``--model contact``).

The ideal level solves a geometry once in unit scalings and scales it to operating points
(friction, torque, speed, mode), so ``gearcalc sweep`` over those keys runs as arrays (``sweep``).  The
friction-consistent model (the default, pins.md §4.9) is not linear in the friction: it is evaluated per
operating point from friction-free sums the geometry's solve keeps on its final grid (still arrays).
No numpy at module level: ``gearcalc check``/``new``/``--help`` stay light.
"""
from __future__ import annotations

import math
import time
from types import SimpleNamespace

from ..calculator import REQUIRED, Calculator, DesignError, Field, Options, Problems, Result, Table
from ..units import MAX_FORCE_N, MAX_FRICTION, MAX_LENGTH_MM, MAX_SPEED_RPM, MAX_TEETH, MAX_TORQUE_NM, MIN_LENGTH_MM

MODELS = ("formula", "ideal", "contact")
MAX_DISCS = 64
"""Satellite discs (drives use 1-3); the cost grows with n_d, and 64 discs take ~0.4 s."""
IDEAL_WORK_MAX = 200_000
"""Cost budget of one ideal-level design: pins x discs (z2 n_d).  The cycle and the disc sums cost about
35 us per pin and disc at the default --tol (4000 pins x 64 discs: 9 s), so the budget keeps a design
under ~10 s and its arrays under ~0.5 GB; 10 000 pins with up to 20 discs, 64 discs with up to 3125 pins."""
IDEAL_SWEEP_WORK_MAX = 100_000
"""Pin-discs (sum of z2 n_d over the distinct geometries) one vectorised ideal-level sweep solves together; a
larger grid is evaluated point by point.  All geometries are solved at once, ~7 KB a pin-disc: 20 001
eccentricities x 22 pins took 3 GB together (21 s), 115 MB point by point (24 s)."""
CONTACT_NODES_MAX = 4096 + 256
"""Crank angles one contact-level pass evaluates at most: the quadrature's cap (2^12) and the scan."""
CONTACT_WORK_MAX = 1_500_000
"""Cost budget of one contact-level design, in pin-contact solves: z2 x CONTACT_NODES_MAX x the torque
fixed point's passes (1 with the torque on V; 3, the usual count, with it on H).  A solve costs 3-17 us, so
the budget is ~5-25 s at the node cap (most designs converge with a fifth of the nodes): z2 <= 114 with the
torque on H, z2 <= 344 on V."""
MAX_STIFFNESS_N_PER_MM = 1e12
"""A linear contact stiffness far above steel's (~1e6 N/mm per mm of face); the accuracy reference uses 1e9."""

TABLES = (
    Table("pin_load", (
        Field("normal_force_N", "number", REQUIRED, "F_n, peak normal force on one pin", gt=0, le=MAX_FORCE_N,
              example=1920.0),
        Field("pin_speed_rpm", "number", REQUIRED, "n_pin, bushing speed", gt=0, le=MAX_SPEED_RPM, example=14.0),
        Field("pin_radius_mm", "number", REQUIRED, "R, outer radius of the bushing", ge=MIN_LENGTH_MM,
              le=MAX_LENGTH_MM, example=1.95),
        Field("axle_radius_mm", "number", REQUIRED, "r, radius of the axle (< R)", ge=MIN_LENGTH_MM,
              le=MAX_LENGTH_MM, example=0.95),
        Field("paper_pi", "bool", False, "compute with pi = 3.14 as the paper did"),
    ), doc="The paper's per-pin formula level, eqs. (3)-(7): give this table alone to run it",
        optional=True, in_template=False),
    Table("gearing", (
        Field("profile", "string", REQUIRED, "satellite tooth profile", choices=("cycloidal", "circular"),
              example="cycloidal"),
        Field("satellite_teeth", "integer", REQUIRED, f"z1, teeth of the satellite (at most {MAX_TEETH - 1})", ge=2,
              le=MAX_TEETH - 1, example=20),
        Field("pins", "integer", REQUIRED, f"z2, pins of the fixed ring (> z1; at most {MAX_TEETH}: exact in floating "
              "point, bounded memory)", ge=3, le=MAX_TEETH, example=22),
        Field("eccentricity_mm", "number", REQUIRED, "e, crank eccentricity", ge=MIN_LENGTH_MM, le=MAX_LENGTH_MM,
              example=3.9),
        Field("pin_circle_radius_mm", "number", None, "R_p, pin-centre circle radius (or give curtate_ratio)",
              ge=MIN_LENGTH_MM, le=MAX_LENGTH_MM, example=57.2, alternative_to="curtate_ratio"),
        Field("curtate_ratio", "number", None, "K1 = e*z2/(k*R_p), 0 < K1 < 1 (or give pin_circle_radius_mm)",
              gt=0, example=0.75),
        Field("pin_radius_mm", "number", REQUIRED, "R_b, pin (bushing) outer radius", ge=MIN_LENGTH_MM,
              le=MAX_LENGTH_MM, example=1.95),
        Field("axle_radius_mm", "number", None, "r, axle radius; required with rotating pins (< R_b)",
              ge=MIN_LENGTH_MM, le=MAX_LENGTH_MM, example=0.95),
        Field("rotating_pins", "bool", False, "pins are bushings turning on axles (else fixed pins)"),
        Field("discs", "integer", 1, "n_d, satellite discs, offset by 360/n_d degrees of crank", ge=1,
              le=MAX_DISCS),
        Field("tooth_radius_mm", "number", "full", "rho_t, circular profile: tooth radius; \"full\": adjacent "
              "teeth tangent at the root", gt=0, le=MAX_LENGTH_MM, choices=("full",)),
        Field("tooth_circle_radius_mm", "number", "zero_backlash",
              "R_t, circular profile: radius of the circle of tooth centres; \"zero_backlash\": the teeth just "
              "touch the pins' nominal paths", gt=0, le=MAX_LENGTH_MM, choices=("zero_backlash",)),
        Field("equidistant_mod_mm", "number", 0.0, "Delta R_b, cycloidal: equidistant modification (> 0 adds "
              "clearance; contact level)", ge=-MAX_LENGTH_MM, le=MAX_LENGTH_MM),
        Field("radial_mod_mm", "number", 0.0, "Delta R_p, cycloidal: radial modification of the pin circle of "
              "the design curve (contact level)", ge=-MAX_LENGTH_MM, le=MAX_LENGTH_MM),
    ), doc="Geometry of the pin gear: runs the cycle model", optional=True),
    Table("friction", (
        Field("sliding", "number", None, "f, tooth-pin sliding friction; required with [gearing]", ge=0,
              le=MAX_FRICTION, example=0.1),
        Field("rolling_mm", "number", REQUIRED, "f_k, rolling friction between tooth and bushing", ge=0,
              le=MAX_LENGTH_MM, example=0.01),
        Field("axle", "number", REQUIRED, "f_c, sliding friction between bushing and axle", ge=0,
              le=MAX_FRICTION, example=0.1),
        Field("model", "string", None, "consistent (default): the friction forces enter the satellite's force "
              "balance, each mode solved on its own (pins.md §4.9); first-order: forces without friction, losses "
              "charged afterwards (§4.6-4.7, the paper's)", choices=("consistent", "first-order")),
    ), doc="Friction coefficients"),
    Table("load", (
        Field("mode", "string", REQUIRED, "multiplier: V (the slow satellite output shaft) drives H (the fast "
              "crank): the paper's; reducer: H drives V",
              choices=("multiplier", "reducer"), example="multiplier"),
        Field("torque_shaft", "string", REQUIRED, "the shaft whose torque is given: H = crank (fast shaft) or "
              "V = satellite output (slow shaft)",
              choices=("H", "V"), example="H"),
        Field("torque_Nm", "number", REQUIRED, "T, torque on that shaft", gt=0, le=MAX_TORQUE_NM, example=100.0),
        Field("crank_speed_rpm", "number", None, "n_H; powers and pin speeds need it", gt=0, le=MAX_SPEED_RPM,
              example=1000.0),
    ), doc="Operating point; required with [gearing]", optional=True),
    Table("contact", (
        Field("law", "string", "hertz", "contact law: hertz (steel, ISO/TS 16281), palmgren, linear",
              choices=("hertz", "palmgren", "linear")),
        Field("face_width_mm", "number", None, "b, face width; required for hertz and palmgren",
              ge=MIN_LENGTH_MM, le=MAX_LENGTH_MM),
        Field("stiffness_N_per_mm", "number", None, "k_lin, contact stiffness; required for linear", gt=0,
              le=MAX_STIFFNESS_N_PER_MM),
        Field("friction_in_equilibrium", "bool", None, "alias of friction.model: true = \"consistent\", "
              "false = \"first-order\""),
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
    "sliding_speed_max_m_s", "crank_torque_mean_Nm", "crank_torque_ripple_Nm", "bearing_force_max_N",
    "bearing_force_mean_N", "contact_stress_max_MPa", "axle_pressure_max_MPa", "friction_model",
    "loaded_pins_min", "loaded_pins_max", "psi_star_deg", "rolling_ok",
    "exit_entry_force_ratio", "low_spin_fraction", "te_pp_arcsec", "backlash_deg", "equilibrium_residual",
    "contact_law", "tooth_radius_mm", "tooth_circle_radius_mm",
    "n_crank", "model_time_ms", "tolerance_met",
    "F_tr1_N", "F_tr2_N", "P_tr1_W", "P_tr2_W", "P_tr_W", "P_tr_fixed_W",
)


def _fmt(x) -> str:
    return f"{x:.6g}"


# ---------------------------------------------------------------- cross-key checks

def _pin_circle(design):
    """(R_p, K1, 1 - K1) from whichever of pin_circle_radius_mm / curtate_ratio is given
    (:func:`gearcalc.pins.pin_circle`; K1 as given, else e z2/(k R_p))."""
    from .. import pins

    z1, z2 = design["gearing.satellite_teeth"], design["gearing.pins"]
    e, k = design["gearing.eccentricity_mm"], z2 - z1
    Rp, K1 = design["gearing.pin_circle_radius_mm"], design["gearing.curtate_ratio"]
    Rp, omk = pins.pin_circle(z1, z2, e, math.nan if Rp is None else Rp, math.nan if K1 is None else K1,
                              pins.SCALAR_OPS)
    return Rp, (e * z2 / (k * Rp) if K1 is None else K1), omk


DEFAULT_FRICTION_MODEL = "consistent"
"""The friction model of a design that names none (pins.md §4.9, §7); tests that pin first-order numbers set
it to "first-order", which is the same as giving ``friction.model = "first-order"`` in every design."""


def friction_model(design) -> str:
    """The friction model of a design: ``friction.model``, or its alias ``contact.friction_in_equilibrium``
    (true: "consistent", false: "first-order"); "consistent" when neither is given (pins.md §4.9, §7)."""
    model, alias = design.get("friction.model"), design.get("contact.friction_in_equilibrium")
    if alias is None:
        return model or DEFAULT_FRICTION_MODEL
    from_alias = "consistent" if alias else "first-order"
    if model is not None and model != from_alias:
        raise DesignError("contact.friction_in_equilibrium", f"= {str(alias).lower()} contradicts friction.model = "
                                                             f"\"{model}\" (the key is its alias; give one of them)")
    return from_alias


def _violations(values) -> dict:
    """The cross-key rules over designs or sweep points (``values(key)``: a key's values, None where absent):
    per rule's key a boolean array; "geometry": :func:`gearcalc.pins.geometry_violations`.  The one rule set
    of :func:`check` (one design) and of a vectorised sweep (:func:`_points_pass_checks`)."""
    import numpy as np

    from .. import pins

    K1g, Rpg = _floats(values("gearing.curtate_ratio")), _floats(values("gearing.pin_circle_radius_mm"))
    R, r_pl = _floats(values("pin_load.pin_radius_mm")), _floats(values("pin_load.axle_radius_mm"))
    rot = np.array([bool(v) for v in values("gearing.rotating_pins")])
    r = _floats(values("gearing.axle_radius_mm"))
    z1, z2 = values("gearing.satellite_teeth"), values("gearing.pins")
    has_g = all(v is not None for v in z1 + z2)
    cycloidal = np.array([p == "cycloidal" for p in values("gearing.profile")])
    geometry = pins.geometry_violations(
        z1 if has_g else 0, z2 if has_g else 0, _floats(values("gearing.eccentricity_mm")), Rpg, K1g,
        _floats(values("gearing.pin_radius_mm")), r, rot, cycloidal)
    with np.errstate(invalid="ignore"):
        return {"pin_load.axle_radius_mm": r_pl >= R,
                "friction.sliding": np.array([v is None for v in values("friction.sliding")]),
                "gearing.pin_circle_radius_mm": np.isnan(K1g) == np.isnan(Rpg),
                "gearing.axle_radius_mm": rot & np.isnan(r), "geometry": geometry}


def check(design, problems: Problems) -> None:
    """Cross-key checks (pins.md §7, §9); every problem is reported."""
    has_g, has_pl = design.has("gearing"), design.has("pin_load")
    if not has_g and not has_pl:
        problems.error("gearing", "missing; a pins design needs [gearing] (cycle model: efficiency, losses "
                                  "over the cycle) or [pin_load] (the paper's per-pin formula level)")
        return
    bad = _violations(lambda key: [design.get(key)])
    if has_pl:
        R, r = design["pin_load.pin_radius_mm"], design["pin_load.axle_radius_mm"]
        if bad["pin_load.axle_radius_mm"][0]:
            problems.error("pin_load.axle_radius_mm", f"= {_fmt(r)}: must be < pin_load.pin_radius_mm = {_fmt(R)} "
                                                      "(the axle must be smaller than the bushing)")
    if not has_g:
        return
    if not design.has("load"):
        problems.error("load", "missing; a design with [gearing] needs [load] (mode, torque_shaft, torque_Nm, "
                               "crank_speed_rpm)")
    if bad["friction.sliding"][0]:
        problems.error("friction.sliding", "missing; required with [gearing] (f, tooth-pin sliding friction; "
                                           "it also drives rotating pins), a number >= 0")
    z1, z2 = design["gearing.satellite_teeth"], design["gearing.pins"]
    e, Rb = design["gearing.eccentricity_mm"], design["gearing.pin_radius_mm"]
    geo = bad["geometry"]
    ok_teeth = not geo.teeth[0]
    if not ok_teeth:
        problems.error("gearing.pins", f"= {z2}: z2 must exceed z1 (k = z2 - z1 >= 1); "
                                       f"gearing.satellite_teeth = {z1}")
    Rp_given, K1_given = design["gearing.pin_circle_radius_mm"], design["gearing.curtate_ratio"]
    if bad["gearing.pin_circle_radius_mm"][0]:
        problems.error("gearing.pin_circle_radius_mm",
                       "give exactly one of gearing.pin_circle_radius_mm (R_p) and gearing.curtate_ratio "
                       f"(K1 = e*z2/(k*R_p)); {'both' if Rp_given is not None else 'neither'} given")
    elif ok_teeth:
        Rp, K1, _ = _pin_circle(design)
        k = z2 - z1
        if geo.overflow[0]:        # e.g. K1 = 5e-324: R_p = inf (was exit 70)
            problems.error("gearing.curtate_ratio", f"= {_fmt(K1)}: R_p = e*z2/(k*K1) overflows (K1 too small for "
                                                    f"e = {_fmt(e)} mm and z2/k = {_fmt(z2 / k)}); give a larger K1 or "
                                                    "gearing.pin_circle_radius_mm")
            return
        if geo.curtate[0]:
            if K1_given is not None:
                problems.error("gearing.curtate_ratio", f"= {_fmt(K1)}: K1 = e*z2/(k*R_p) must be < 1 "
                                                        "(a curtate cycloid)")
            else:
                problems.error("gearing.pin_circle_radius_mm",
                               f"= {_fmt(Rp)}: K1 = e*z2/(k*R_p) = {_fmt(K1)} must be < 1: R_p must exceed "
                               f"e*z2/k = {_fmt(e * z2 / k)} mm (or reduce gearing.eccentricity_mm = {_fmt(e)})")
        limit = float(geo.overlap_limit[0])        # R_p sin(pi/z2) (gearcalc.pins.geometry_violations)
        if geo.overlap[0]:
            problems.error("gearing.pin_radius_mm", f"= {_fmt(Rb)}: pins overlap: R_b must be < R_p*sin(pi/z2) = "
                                                    f"{_fmt(limit)} mm (R_p = {_fmt(Rp)} mm, z2 = {z2})")
    if design["gearing.rotating_pins"]:
        r = design["gearing.axle_radius_mm"]
        if bad["gearing.axle_radius_mm"][0]:
            problems.error("gearing.axle_radius_mm", "missing; required with rotating_pins = true (r, axle "
                                                     "radius, > 0 and < pin_radius_mm)")
        elif geo.axle[0]:
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
    level = select_level(design, None)
    if design.has("contact") or level == "contact":
        _check_contact_law(design, problems)
    if problems.errors:
        return
    problem = cost_problem(design, level)
    if problem is None and level in ("ideal", "contact"):
        problem = admissibility_problem(design, level)
    if problem is not None:
        problems.error(*problem)


def cost_problem(design, level: str):
    """(key, message) when the design's computation at that level would exceed its cost budget
    (:data:`IDEAL_WORK_MAX`, :data:`CONTACT_WORK_MAX`), else None.  ``check`` and compute share it."""
    if level not in ("ideal", "contact") or not design.has("gearing"):
        return None
    z2, n_d = design["gearing.pins"], design["gearing.discs"]
    if level == "ideal" and z2 * n_d > IDEAL_WORK_MAX:
        key = "gearing.discs" if n_d > 1 else "gearing.pins"
        return (key, f"= {design[key]}: gearing.pins x gearing.discs = {z2} x {n_d} = {z2 * n_d} exceeds the ideal "
                     f"level's budget of {IDEAL_WORK_MAX} pin-discs (about 35 us each: ~10 s, ~0.5 GB); use fewer "
                     "pins or discs")
    if level == "contact":
        on_V = design.get("load.torque_shaft") == "V"
        passes = 1 if on_V else 3
        work = z2 * CONTACT_NODES_MAX * passes
        if work > CONTACT_WORK_MAX:
            where = "with the torque on V" if on_V else "with the torque on H (3 passes of the torque fixed point)"
            return ("gearing.pins", f"= {z2}: too many pins for the contact level: {z2} pins x {CONTACT_NODES_MAX} "
                                    f"crank angles x {passes} pass(es) = {work} contact solves exceeds its budget of "
                                    f"{CONTACT_WORK_MAX} (~10 s): at most "
                                    f"{CONTACT_WORK_MAX // (CONTACT_NODES_MAX * passes)} pins {where}; a cycloidal "
                                    "profile without modifications or [contact] runs the ideal level, which takes up "
                                    "to 10 000 pins")
    return None


def admissibility_problem(design, level: str):
    """(key, message) of the first geometric admissibility problem the computation at that level reports
    (pins.md §4.2, §5.2-5.3, §9, §12.10), else None: the same functions as compute, run once here so that
    ``gearcalc check`` reports them too.  Needs a design that passed the other checks."""
    from .. import pins

    if level == "ideal":
        import numpy as np

        z1, z2 = design["gearing.satellite_teeth"], design["gearing.pins"]
        Rp, K1, omk = _pin_circle(design)
        g = pins.Cycloid(np.array([z1]), np.array([z2]), np.array([float(design["gearing.eccentricity_mm"])]),
                         np.array([float(Rp)]), np.array([float(design["gearing.pin_radius_mm"])]),
                         np.array([float(omk)]))
        status, psi_star, rho_c = pins.admissibility(g)
        if status[0] == 0:
            return None
        err = _admissibility_error(int(status[0]), z1, z2, float(psi_star[0]), design["gearing.pin_radius_mm"],
                                   float(rho_c[0]), _ideal_K1(design))
        return err.key, err.message
    try:
        _contact_law(design)
        z1, z2 = design["gearing.satellite_teeth"], design["gearing.pins"]
        Rp, _, omk = _pin_circle(design)
        g = pins.Cycloid(z1, z2, float(design["gearing.eccentricity_mm"]), float(Rp),
                         float(design["gearing.pin_radius_mm"]), float(omk))
        _contact_profile(design, g, [])
    except DesignError as exc:
        return exc.key, exc.message
    return None


def _ideal_K1(design) -> float:
    """K1 = e z2/(k R_p) as the ideal level computes it."""
    z1, z2 = design["gearing.satellite_teeth"], design["gearing.pins"]
    return design["gearing.eccentricity_mm"] * z2 / ((z2 - z1) * _pin_circle(design)[0])


def _admissibility_error(status: int, z1, z2, psi_star: float, Rb, rho_c: float, K1) -> DesignError:
    """The DesignError of an inadmissible ideal-level gear (pins.md §4.2, §12.10): status from
    :func:`gearcalc.pins.admissibility`."""
    from .. import pins

    if status == pins.TOO_FEW_TEETH:
        return DesignError(
            "gearing.satellite_teeth",
            f"= {z1}: too few teeth for the tooth difference k = {z2 - z1}: at some crank angles no pin "
            f"carries load (the loaded arc psi* = {_fmt(math.degrees(psi_star))} deg must exceed the pin "
            f"pitch 360/z2 = {_fmt(360.0 / z2)} deg)")
    return DesignError(
        "gearing.pin_radius_mm",
        f"= {_fmt(Rb)}: undercut: R_b must be < the least radius of curvature of the pin-centre curve "
        f"over the loaded arc, min rho_c = {_fmt(rho_c)} mm (K1 = {_fmt(K1)})")


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

def _new_summary(name: str, level: str) -> dict:
    """A summary with every field of the kind, None until computed."""
    summary = dict.fromkeys(SUMMARY_KEYS)
    summary.update(name=name, model=level)
    return summary


def compute(design, options: Options) -> Result:
    """Run the level the design needs (or ``--model``); see the module docstring.

    The formula and ideal levels run as a group of one (:func:`batch` computes many designs with the
    same code, so a batch equals ``compute`` design by design); the contact level runs on its own.
    """
    from .. import pins  # noqa: F401  (numpy and the physics load here, outside the timed model)

    t0 = time.perf_counter()
    level = select_level(design, options.model)
    problem = cost_problem(design, level)      # check() ran it for the level without --model
    if problem is not None:
        raise DesignError(*problem)
    if level != "contact":
        (out,) = _group([design], level, options, t0)
        if isinstance(out, BaseException):
            raise out
        return out
    summary = _new_summary(design.name, level)
    warnings: list[str] = []
    failed: list[str] = []
    detail: dict = {}
    if design.has("pin_load"):
        _formula(design, summary)
    _contact(design, options, summary, warnings, failed, detail)
    summary["model_time_ms"] = (time.perf_counter() - t0) * 1e3
    return _result(summary, detail, warnings, failed, level)


def _result(summary, detail, warnings, failed, level) -> Result:
    result = Result(summary=summary, detail=detail, warnings=warnings, failed=failed, model=level)
    if summary["self_locking"]:   # tables say why a value is missing (§4.7)
        result.labels.update({k: "self-locking" for k in ("efficiency", "efficiency_err", "efficiency_multiplier",
                                                           "efficiency_multiplier_err", "torque_in_Nm",
                                                           "torque_out_Nm") if summary[k] is None})
    return result


def batch(designs, options: Options) -> list:
    """Many pins designs at once: per design, the Result ``compute`` returns or the exception it raises.

    Designs at the formula and ideal levels are computed together, numpy over designs (the ideal
    level's geometries all in one vectorised solve, :func:`gearcalc.pins.ideal_cycles`); designs at
    the contact level are computed one by one.  ``model_time_ms`` of a design computed in a group is
    the group's time divided by the number of its designs.
    """
    from .. import pins  # noqa: F401

    results: list = [None] * len(designs)
    groups: dict[str, list[int]] = {"formula": [], "ideal": []}
    for i, d in enumerate(designs):
        try:
            level = select_level(d, options.model)
            problem = cost_problem(d, level)
            if problem is not None:
                raise DesignError(*problem)
        except DesignError as exc:
            results[i] = exc
            continue
        if level == "contact" or (level == "ideal" and _alone(d, options)):
            try:
                results[i] = compute(d, options)
            except Exception as exc:  # noqa: BLE001  (returned, as the contract says)
                results[i] = exc
        else:
            groups[level].append(i)
    for level, idx in groups.items():
        if idx:
            out = _group([designs[i] for i in idx], level, options, time.perf_counter())
            for i, r in zip(idx, out):
                results[i] = r
    return results


GROUP_PINS_MAX = 200
"""An ideal-level design with more pins x discs than this is computed alone in a batch, as is any design at
``--tol`` below :data:`GROUP_TOL_MIN`: a group's arrays hold every member at the finest grid any member needs
(two 100-pin gears at 1e-15 took 2.9 GB together, 250 MB alone)."""
GROUP_TOL_MIN = 1e-9


def _alone(design, options: Options) -> bool:
    return (options.tol < GROUP_TOL_MIN
            or design["gearing.pins"] * design["gearing.discs"] > GROUP_PINS_MAX)


def _group(designs, level: str, options: Options, t0: float) -> list:
    """Results (or DesignErrors) of designs that all run at the formula or the ideal level, computed together."""
    n = len(designs)

    def values(key):
        return [d.get(key) for d in designs]

    formula = _formula_columns(values, n) if any(d.has("pin_load") for d in designs) else None
    errors: list = [None] * n
    if level == "ideal":
        ideal = _ideal_columns(values, n, options, detail=options.detail)
        cols, errors = ideal.columns, ideal.errors
    out = []
    for i, d in enumerate(designs):
        if errors[i] is not None:
            out.append(errors[i])
            continue
        summary = _new_summary(d.name, level)
        warnings: list[str] = []
        failed: list[str] = []
        detail: dict = {}
        if d.has("pin_load"):
            summary.update({k: formula[k][i] for k in _FORMULA_KEYS})
            if d.get("friction.sliding") is None:
                summary["P_tr_fixed_W"] = None
        if level == "formula":
            summary["rotating_pins"] = True        # eqs. (3)-(7) are the paper's rotating-pin losses
        else:
            if d.has("contact"):   # only with --model ideal: a [contact] table otherwise selects "contact"
                warnings.append("the [contact] table's contact law is not used by the ideal level (rigid contacts; "
                                "contact.face_width_mm gives the contact stress and the axle pressure)")
            warnings.extend(ideal.warnings[i])
            summary.update({k: cols[k][i] for k in cols})
            if summary["loss_ratio"] is None and not summary["self_locking"]:   # overflowed (K1 ~ 1e-300 and
                # below): refused, not exit 70 (a jammed mode of the friction-consistent model has no loss ratio)
                key = "gearing.curtate_ratio" if d.get("gearing.curtate_ratio") is not None else \
                    "gearing.pin_circle_radius_mm"
                out.append(DesignError(key, f"= {_fmt(d[key])}: the loss ratio overflows floating point (it grows as "
                                            "1/K1, K1 = e*z2/(k*R_p): the curtate ratio is too small for this gear)"))
                continue
            _cycle_notes(d, summary, options, warnings, failed)
            if options.detail:
                detail.update(ideal.detail(i, d))
        out.append(_result(summary, detail, warnings, failed, level))
    per_design = (time.perf_counter() - t0) * 1e3 / n
    for r in out:
        if isinstance(r, Result):
            r.summary["model_time_ms"] = per_design
    return out


def _formula(design, summary) -> None:
    """The formula-level fields of one design (the contact level's path)."""
    cols = _formula_columns(lambda key: [design.get(key)], 1)
    summary.update({k: cols[k][0] for k in _FORMULA_KEYS})


def _floats(vals):
    """A float array from a list of numbers and None (NaN)."""
    import numpy as np

    return np.array([np.nan if v is None else v for v in vals], dtype=float)


def _column(arr) -> list:
    """Plain Python values of an array (bool, int or float; NaN becomes None: undefined)."""
    import numpy as np

    arr = np.asarray(arr)
    out = arr.tolist()
    if arr.dtype.kind == "f" and np.isnan(arr).any():
        out = [None if v != v else v for v in out]
    return out


def _columns(arrays: dict, n: int) -> dict:
    """Plain Python lists of many arrays of shape (n,) (see :func:`_column`), the float ones converted together."""
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


def _formula_columns(values, n: int) -> dict:
    """The paper's eqs. (3)-(7) over designs or points (pins.md §3): columns of _FORMULA_KEYS (None without
    [pin_load]; P_tr_fixed_W needs friction.sliding)."""
    import numpy as np

    from .. import pins

    F, n_pin = _floats(values("pin_load.normal_force_N")), _floats(values("pin_load.pin_speed_rpm"))
    R, r = _floats(values("pin_load.pin_radius_mm")), _floats(values("pin_load.axle_radius_mm"))
    fk, fc, f = (_floats(values(k)) for k in ("friction.rolling_mm", "friction.axle", "friction.sliding"))
    paper = np.array([bool(v) for v in values("pin_load.paper_pi")])
    res = pins.formula_losses(F, n_pin, R, r, fk, fc, paper_pi=paper, sliding_friction=f)
    return {k: _column(v) for k, v in (("F_tr1_N", res.F_tr1), ("F_tr2_N", res.F_tr2), ("P_tr1_W", res.P_tr1),
                                        ("P_tr2_W", res.P_tr2), ("P_tr_W", res.P_tr), ("P_tr_fixed_W", res.P_tr_fixed))}


# ---------------------------------------------------------------- cycle levels: operating points
#
# The cycle levels share the mapping from a loss ratio to efficiencies and torques, and the friction
# regime; both are vectorised over operating points (arrays), so that one design, a batch of designs
# and a whole sweep run the same code.  The ideal level's geometric solution does not depend on the
# torque, the speed or the friction coefficient (pins.md §4.6, §4.8 identity 8: lambda ∝ mu_eff,
# F ∝ T, v ∝ omega): each distinct geometry is solved once in unit scalings
# (gearcalc.pins.ideal_cycles, all geometries together) and then scaled to every design or point.
# The contact level is not linear in the torque: it solves per design and reuses ``_friction_regime``
# and ``_efficiency_torques``.

OPERATING_KEYS = ("friction.sliding", "friction.rolling_mm", "friction.axle", "load.mode", "load.torque_shaft",
                  "load.torque_Nm", "load.crank_speed_rpm")
"""Keys an operating point may change without changing the ideal level's geometric solution."""

GEOMETRY_KEYS = ("gearing.satellite_teeth", "gearing.pins", "gearing.eccentricity_mm", "gearing.pin_circle_radius_mm",
                 "gearing.curtate_ratio", "gearing.pin_radius_mm", "gearing.axle_radius_mm", "gearing.rotating_pins",
                 "gearing.discs")
"""Geometry keys a vectorised ideal-level sweep may vary (each distinct geometry is solved once)."""

PIN_LOAD_KEYS = ("pin_load.normal_force_N", "pin_load.pin_speed_rpm", "pin_load.pin_radius_mm",
                 "pin_load.axle_radius_mm", "pin_load.paper_pi")
FORMULA_SWEEP_KEYS = PIN_LOAD_KEYS + ("friction.sliding", "friction.rolling_mm", "friction.axle")
IDEAL_SWEEP_KEYS = OPERATING_KEYS + GEOMETRY_KEYS + PIN_LOAD_KEYS


def _operating_points(design, points=None) -> dict:
    """The operating-point keys as arrays over points (from ``points`` where given, else the design).

    Numbers become float arrays (NaN where absent: no crank speed), words stay lists."""
    points = points or [{}]
    return _operating_values(lambda key: [p.get(key, design[key]) for p in points])


def _operating_values(values, one: bool = False) -> dict:
    """The operating-point keys over points: float arrays (NaN: absent) and lists of words; with ``one``,
    the values of the single point as scalars (numpy float64, NaN where absent; the word)."""
    out = {}
    for key in OPERATING_KEYS:
        vals = values(key)
        if one:
            v = vals[0]
            out[key] = v if key in ("load.mode", "load.torque_shaft") else _float64(v)
        else:
            out[key] = list(vals) if key in ("load.mode", "load.torque_shaft") else _floats(vals)
    return out


def _float64(v):
    """A design value as a numpy float64 scalar (NaN where absent)."""
    import numpy as np

    return np.float64(math.nan if v is None else v)


def _words_equal(words, word, one: bool):
    """Whether each word of an operating-point column is ``word`` (one point: a bool; else an array)."""
    import numpy as np

    return words == word if one else np.array([w == word for w in words])


def _friction_regime(design, op):
    """(mu_eff, rolls, rolling_ok) per operating point (pins.md §4.5-4.6); rolling_ok is None for fixed pins."""
    import numpy as np

    if not design["gearing.rotating_pins"]:
        f = op["friction.sliding"]
        return f, np.zeros(f.shape, dtype=bool), None
    m = op["friction.sliding"].shape
    mu, rolls, ok = _friction_arrays(np.ones(m, dtype=bool), np.full(m, float(design["gearing.pin_radius_mm"])),
                                     np.full(m, float(design["gearing.axle_radius_mm"])), op)
    return mu, rolls, ok


def _friction_arrays(rotating, Rb, r, op, xp=None):
    """(mu_eff, rolls, rolling condition) per point (:func:`gearcalc.pins.friction_regime`); the condition
    is only meaningful where ``rotating``."""
    from .. import pins

    mu, ok = pins.friction_regime(rotating, Rb, r, op["friction.sliding"], op["friction.rolling_mm"],
                                  op["friction.axle"], xp or pins.ARRAY_OPS)
    return mu, ok, ok


def _efficiency_torques(lam, E, op, ratio, xp=None):
    """:func:`gearcalc.pins.efficiency_torques` of the operating points ``op`` (pins.md §4.7)."""
    from .. import pins

    xp = xp or pins.ARRAY_OPS
    one = xp is pins.SCALAR_OPS
    multiplier = _words_equal(op["load.mode"], "multiplier", one)
    return pins.efficiency_torques(lam, E, op["load.torque_Nm"], ratio, multiplier,
                                   _words_equal(op["load.torque_shaft"], "V", one), xp)


class IdealColumns:
    """The ideal level over designs or points (:func:`_ideal_columns`).

    columns : summary fields (plain Python lists over points; None: undefined);
    errors : per point, None or the DesignError ``compute`` raises for it;
    warnings : per point, the geometry's warnings;
    detail(i, design) : the detail tables of point i (pins.md §8), built on demand.
    """

    def __init__(self, **kw):
        self.__dict__.update(kw)

    def detail(self, i: int, design) -> dict:
        from .. import pins, pins_outputs

        k, cyc = int(self.gi[i]), self.cyc
        g = pins.Cycloid(int(self.z1[i]), int(self.z2[i]), float(self.e[i]), float(self.Rp[i]), float(self.Rb[i]),
                         float(self.omk[i]))
        t, tmid = cyc.grid(k)
        st = pins.cycle_state(t, tmid, g, float(cyc.psi_star[k]))
        T_sat = float(self.T_sat[i]) if self.columns["pin_force_max_N"][i] is not None else None
        w_V = float(self.w_V[i]) if design["load.crank_speed_rpm"] is not None else None
        sigma = pins.MULTIPLIER if design["load.mode"] == "multiplier" else pins.REDUCER
        consistent = self.models[i] == "consistent"
        hist = pins.crank_history(g, float(cyc.psi_star[k]), t, tmid, float(self.mu[i]), sigma, consistent)
        if consistent and T_sat is not None:
            # the friction-consistent T_sat: from T_V of the consistent efficiency (torque_in/out, pins.md §4.9)
            T_V = self.columns["torque_in_Nm" if sigma == pins.MULTIPLIER else "torque_out_Nm"][i]
            T_sat = None if T_V is None else pins_outputs.satellite_torque(T_V, int(self.n_d[i]))
        return _detail_tables(g, sigma, st, t, float(self.mu[i]), T_sat, None if w_V is None else -w_V,
                              bool(self.rolls[i]), int(self.n_d[i]), hist, consistent)


def _ideal_columns(values, n: int, options: Options, detail: bool = False) -> IdealColumns:
    """The ideal level (pins.md §4) of n designs or sweep points, numpy over them.

    ``values(key)`` gives a key's values over the points (None where absent).  The distinct geometries
    are solved once each, together (gearcalc.pins.ideal_cycles, unit scalings); every point then
    scales its geometry's solution by its friction, torque, speed and mode.  One point (a design computed
    alone) runs the same formulas on scalars (``gearcalc.pins.SCALAR_OPS``): the same numbers, bit for bit, without
    the cost of numpy calls on arrays of one element."""
    import numpy as np

    from .. import pins

    one = n == 1
    if one:                                   # scalars (NaN where absent), as _floats gives
        def num(key):
            return _float64(values(key)[0])

        z1, z2, n_d = values("gearing.satellite_teeth")[0], values("gearing.pins")[0], values("gearing.discs")[0]
        e, Rb, K1g, Rpg = (num(key) for key in ("gearing.eccentricity_mm", "gearing.pin_radius_mm",
                                                "gearing.curtate_ratio", "gearing.pin_circle_radius_mm"))
        rot, r = bool(values("gearing.rotating_pins")[0]), num("gearing.axle_radius_mm")
        xp = pins.SCALAR_OPS
    else:
        z1 = np.array(values("gearing.satellite_teeth"), dtype=np.int64)
        z2 = np.array(values("gearing.pins"), dtype=np.int64)
        e, Rb = _floats(values("gearing.eccentricity_mm")), _floats(values("gearing.pin_radius_mm"))
        K1g, Rpg = _floats(values("gearing.curtate_ratio")), _floats(values("gearing.pin_circle_radius_mm"))
        n_d = np.array(values("gearing.discs"), dtype=np.int64)
        rot = np.array([bool(v) for v in values("gearing.rotating_pins")])
        r = _floats(values("gearing.axle_radius_mm"))
        xp = pins.ARRAY_OPS
    k = z2 - z1
    Rp, omk = pins.pin_circle(z1, z2, e, Rpg, K1g, xp)     # pins.md §7: R_p or K1; NaN raises no warning
    K1 = e * z2 / (k * Rp)                    # as pins.Cycloid.K1
    if one:
        gi = np.zeros(1, dtype=np.int64)
        g = pins.Cycloid(np.array([z1]), np.array([z2]), np.array([e]), np.array([Rp]), np.array([Rb]),
                         np.array([omk]))
        try:                                  # a consistent design alone needs no friction-free peaks
            model = friction_model({"friction.model": values("friction.model")[0],
                                    "contact.friction_in_equilibrium": values("contact.friction_in_equilibrium")[0]})
        except DesignError:                   # reported by _friction_models
            model = None
        cyc = pins.ideal_cycles(g, np.array([n_d]), tol=options.tol,
                                first_order_peaks=not (n_d == 1 and model == "consistent"))
    else:
        key = np.stack([z1, z2, e, Rp, omk, Rb, n_d], axis=1).astype(float)
        uniq, gi = np.unique(key, axis=0, return_inverse=True)
        gi = gi.reshape(-1)
        g = pins.Cycloid(uniq[:, 0].astype(np.int64), uniq[:, 1].astype(np.int64), uniq[:, 2], uniq[:, 3],
                         uniq[:, 5], uniq[:, 4])
        cyc = pins.ideal_cycles(g, uniq[:, 6].astype(np.int64), tol=options.tol)

    def field(name):
        """An IdealCycles field per point: an array over points, or the one point's Python scalar."""
        arr = getattr(cyc, name)
        return arr.item(0) if one else arr[gi]

    # admissibility (pins.md §4.2, §12.10) and the warning of §4.5, per point
    errors: list = [None] * n
    warnings: list[list[str]] = [[] for _ in range(n)]
    status, psi_star, psi_0 = field("status"), field("psi_star"), field("psi_0")
    at = (lambda arr, i: arr) if one else (lambda arr, i: arr[i])
    bad = ([0] if status != 0 else []) if one else np.flatnonzero(status != 0)
    for i in bad:                             # the messages of check() (admissibility_problem)
        if at(status, i) == pins.TOO_COSTLY:  # known after the quadrature only: not in check()
            n_d_i, n_i = int(at(n_d, i)), int(at(field("n_crank"), i))
            errors[i] = DesignError(
                "gearing.discs", f"= {n_d_i}: the sums over {n_d_i} discs on the {n_i} crank-angle intervals per pin "
                f"pitch that --tol {options.tol:g} needs exceed the ideal level's budget (n_d x loaded samples <= "
                f"{pins.DISC_SAMPLES_MAX:.3g}, n_d^2 x loaded samples <= {pins.DISC_WORK_MAX:.3g}: ~10 s, ~0.4 GB); "
                "use fewer discs or a larger --tol")
            continue
        errors[i] = _admissibility_error(int(at(status, i)), int(at(z1, i)), int(at(z2, i)), float(at(psi_star, i)),
                                         float(at(Rb, i)), float(cyc.rho_c_min[gi[i]]), float(at(K1, i)))
    inside = (status == 0) & (Rb >= Rp * omk)
    for i in ([0] if inside else []) if one else np.flatnonzero(inside):
        p0 = None if xp.isnan(at(psi_0, i)) else float(at(psi_0, i))
        warnings[i].append(f"R_b = {_fmt(at(Rb, i))} mm >= R_p*(1 - K1) = {_fmt(at(Rp, i) * at(omk, i))} mm: the "
                           "pitch point lies inside the pin near entry"
                           + (f"; the pin spin reverses at psi = {_fmt(math.degrees(p0))} deg" if p0 else ""))

    # operating points: lambda_bar = mu_eff * unit, forces ∝ T_sat, speeds ∝ omega_V (pins.md §4.4-4.7)
    op = _operating_values(values, one)
    mu, rolls, rolling_ok = _friction_arrays(rot, Rb, r, op, xp)
    lam, E = mu * field("loss_ratio"), mu * field("loss_ratio_err")
    et = _efficiency_torques(lam, E, op, z1 / k, xp)
    unit = SimpleNamespace(**{name: field(name) for name in ("force", "total", "loss", "rel_min", "rel_max",
                                                             "rel_abs", "force_phase", "loss_phase")},
                           psi_0=psi_0, psi_star=psi_star)
    sc = pins.scale_unit_cycle(unit, lam, mu, rolls, op["friction.sliding"], et.T_V, n_d,
                               op["load.crank_speed_rpm"], z1, k, Rb, xp)
    T_sat, w_V = sc.torque_sat, sc.omega_V
    models = _friction_models(values, n, errors)
    cons_mask = np.array([m_ == "consistent" for m_ in models])
    arrays = {
        "efficiency": et.efficiency, "efficiency_err": et.efficiency_err, "self_locking": et.self_locking,
        "efficiency_multiplier": et.eta_vh, "efficiency_multiplier_err": et.eta_vh_err,
        "efficiency_reducer": et.eta_hv, "efficiency_reducer_err": et.eta_hv_err, "loss_ratio": lam,
        "loss_ratio_err": E, "torque_in_Nm": et.torque_in, "torque_out_Nm": et.torque_out,
        "loss_mean_W": sc.loss_mean, "loss_peak_W": sc.loss_peak,
        "pin_force_max_N": sc.force_max, "pin_loss_max_W": sc.loss_max, "pin_loss_bound_W": sc.loss_bound,
        "pin_speed_max_rpm": sc.spin_abs_max, "pin_speed_signed_min_rpm": sc.spin_min,
        "pin_speed_signed_max_rpm": sc.spin_max, "spin_reversals": sc.spin_reversals,
        "sliding_speed_max_m_s": sc.sliding_speed_max,
        "ratio": z1 / k, "curtate_ratio": K1, "loaded_pins_min": field("loaded_min"),
        "loaded_pins_max": field("loaded_max"), "psi_star_deg": xp.degrees(psi_star), "n_crank": field("n_crank"),
        "tolerance_met": field("converged"),
        "pin_force_max_phase_deg": sc.force_phase, "pin_loss_max_phase_deg": sc.loss_phase,
    }
    ext = _consistent_fields(cyc, gi, status, cons_mask, values, n, op, mu, rolls, rot, r, z1, k, n_d, T_sat, w_V,
                             options.tol)
    cons, peaks = ext.pop("_consistent"), ext.pop("_peaks")
    warn_nd = ext.pop("_multi_disc")
    scale = ext.pop("_torque_scale", None)
    if np.any(warn_nd):          # several discs: the friction-free peaks, at the friction-consistent torque
        for key in ("pin_force_max_N", "pin_loss_max_W", "loss_peak_W", "pin_loss_bound_W"):
            arrays[key] = arrays[key] * scale if one else np.where(warn_nd, arrays[key] * scale, arrays[key])
    for key, v in ext.items():
        if key in arrays:       # the friction-consistent values replace the first-order ones (pins.md §4.9)
            m_ = peaks if key in _PEAK_KEYS else cons
            arrays[key] = ((v if m_[0] else arrays[key]) if one else np.where(m_, v, arrays[key]))
        else:
            arrays[key] = v
    for i in np.flatnonzero(warn_nd):
        warnings[i].append("pin_force_max_N, pin_loss_max_W and loss_peak_W with several discs follow the "
                           "friction-free force distribution (first-order model) at the friction-consistent torque; "
                           "the efficiencies, crank torque and bearing force are friction-consistent")
    if one:
        columns = {"model": ["ideal"], "mode": [op["load.mode"]], "profile": ["cycloidal"], "rotating_pins": [rot],
                   "rolling_ok": [bool(rolling_ok) if rot else None], "friction_model": models}
        for key, v in arrays.items():             # plain Python values; NaN: undefined
            v = v.item() if isinstance(v, np.generic) else v
            columns[key] = [None if v != v else v]
        z1, z2, e, Rp, Rb, omk, n_d, mu, rolls, T_sat, w_V = (
            [v] for v in (z1, z2, e, Rp, Rb, omk, n_d, mu, rolls, T_sat, w_V))
    else:
        columns = {"model": ["ideal"] * n, "mode": list(op["load.mode"]), "profile": ["cycloidal"] * n,
                   "rotating_pins": rot.tolist(),
                   "rolling_ok": [bool(o) if q else None for o, q in zip(rolling_ok.tolist(), rot.tolist())],
                   "friction_model": models}
        columns.update(_columns(arrays, n))
    return IdealColumns(columns=columns, errors=errors, warnings=warnings, cyc=cyc, gi=gi, z1=z1, z2=z2, e=e, Rp=Rp,
                        Rb=Rb, omk=omk, n_d=n_d, mu=mu, rolls=rolls, T_sat=T_sat, w_V=w_V, models=models)


def _friction_models(values, n: int, errors: list) -> list:
    """friction.model per point (:func:`friction_model`); a contradiction with its alias is that point's error."""
    out = []
    for i, (m, a) in enumerate(zip(values("friction.model"), values("contact.friction_in_equilibrium"))):
        try:
            out.append(friction_model({"friction.model": m, "contact.friction_in_equilibrium": a}))
        except DesignError as exc:
            if errors[i] is None:
                errors[i] = exc
            out.append("consistent")
    return out


_PEAK_KEYS = ("pin_force_max_N", "pin_force_max_phase_deg", "pin_loss_max_W", "pin_loss_max_phase_deg", "loss_peak_W",
              "pin_loss_bound_W")

_CONSISTENT_FIELDS = (   # summary field <- gearcalc.pins_outputs.ConsistentPoint field
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
_OUTPUT_KEYS = _CONSISTENT_FIELDS[:6]   # pins.md §8: every admissible point gets them (first-order ones too)


def _consistent_fields(cyc, gi, status, cons_mask, values, n, op, mu, rolls, rot, r, z1, k, n_d, T_sat, w_V, tol):
    """The friction-consistent efficiencies, torques and peaks (pins.md §4.9) of the points whose model is
    "consistent", and the outputs of pins.md §8 every point gets (:func:`gearcalc.pins_outputs.consistent_outputs`):
    per summary field an array over the n points, or the one point's float (NaN: undefined), plus ``_consistent``
    (mask of the points whose efficiency fields are replaced), ``_peaks`` (those whose peaks are replaced: one
    disc), ``_multi_disc`` (consistent points with several discs, whose peaks stay first-order) and
    ``_torque_scale``."""
    import numpy as np

    from .. import pins_outputs

    one = n == 1
    modes = [op["load.mode"]] if one else op["load.mode"]
    shafts = [op["load.torque_shaft"]] if one else op["load.torque_shaft"]
    p, cons = pins_outputs.consistent_outputs(
        cyc, gi, status, np.asarray(cons_mask), np.array([m == "multiplier" for m in modes]), mu, T_sat, w_V, r, rot,
        rolls, z1, k, n_d, _floats(values("contact.face_width_mm")), _floats(values("friction.sliding")),
        op["load.torque_Nm"], np.array([w == "V" for w in shafts]), tol)
    nd_a = np.zeros(n, dtype=np.int64) + np.asarray(n_d)
    flags = {"_consistent": cons, "_multi_disc": cons & (nd_a > 1), "_peaks": cons & (nd_a == 1)}
    if p is None:                                 # no admissible point
        return {**{key: (math.nan if one else np.full(n, np.nan)) for key, _ in _OUTPUT_KEYS}, **flags}
    return {**{key: getattr(p, name) for key, name in _CONSISTENT_FIELDS}, "_torque_scale": p.torque_scale, **flags}


def _plain(x):
    """A numpy scalar as a plain bool/int/float, NaN as None (undefined)."""
    import numpy as np

    if isinstance(x, (np.bool_, bool)):
        return bool(x)
    if isinstance(x, (np.integer, int)):
        return int(x)
    x = float(x)
    return None if math.isnan(x) else x


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
    jammed = s["self_locking"] and lam is None         # friction-consistent model: no positive normal forces
    if not s["tolerance_met"] and not jammed:
        warnings.append(f"tolerance {options.tol:g} not met at {s['n_crank']} crank-angle intervals: "
                        f"loss ratio {lam:.10g} +- {E:.3g}")
    if jammed:
        failed.append(f"self-locking in the {s['mode']} mode: with the friction forces in the satellite's balance "
                      "(friction.model = \"consistent\", pins.md §4.9) no positive normal force carries the torque "
                      "at some crank angle (the drive jams); no efficiency. A lower friction.sliding or a larger "
                      "gearing.curtate_ratio (closer to 1) avoids it")
    elif s["self_locking"]:
        failed.append(f"self-locking in the multiplier mode: the loss ratio {lam:.6g} >= 1 (the losses exceed "
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


_FORMULA_KEYS = ("F_tr1_N", "F_tr2_N", "P_tr1_W", "P_tr2_W", "P_tr_W", "P_tr_fixed_W")


def sweep(base, raw, axes, points, options):
    """A grid of points as arrays: the formula and ideal levels, over operating and geometry keys.

    * Formula level (``[pin_load]``): the keys of ``FORMULA_SWEEP_KEYS``, eqs. (3)-(7) over the points.
    * Ideal level: ``OPERATING_KEYS`` (friction, torque, speed, mode, torque shaft), ``GEOMETRY_KEYS``
      (teeth, pins, eccentricity, pin circle or curtate ratio, pin and axle radii, rotating pins,
      discs) and ``PIN_LOAD_KEYS``.  Each distinct geometry of the grid is solved once, all of them
      together (numpy over geometries, :func:`gearcalc.pins.ideal_cycles`); every point scales its
      geometry's solution (pins.md §4.8 identity 8).

    Other varied keys, the contact level, or a grid where some point is invalid or inadmissible
    return None: the caller then evaluates point by point (and reports the first bad point exactly as
    it would).  The summaries equal point-by-point evaluation (``model_time_ms``: the grid's time per
    point).  Returns the summaries column-major (a list per field).
    """
    t0 = time.perf_counter()
    level = select_level(base, options.model)
    allowed = {"formula": FORMULA_SWEEP_KEYS, "ideal": IDEAL_SWEEP_KEYS}.get(level, ())
    if any(k not in allowed for k in axes):
        return None
    from .. import pins  # noqa: F401

    n = len(points)
    varied = set(axes)

    def values(key):
        if key not in varied:
            return [base.get(key)] * n
        fixed = base.get(key)
        return [p.get(key, fixed) for p in points]

    if not _points_pass_checks(base, values, n, level):
        return None
    cols: dict = {}
    if level == "ideal":
        ideal = _ideal_columns(values, n, options)
        if any(err is not None for err in ideal.errors):
            return None
        cols.update(ideal.columns)
    out = {key: [None] * n for key in SUMMARY_KEYS}
    out.update(cols)
    out["name"] = [base.name] * n
    if level == "formula":
        out["model"] = ["formula"] * n
        out["rotating_pins"] = [True] * n
    if base.has("pin_load"):
        out.update(_formula_columns(values, n))
    per_point = (time.perf_counter() - t0) * 1e3 / max(n, 1)
    out["model_time_ms"] = [per_point] * n
    return {key: out[key] for key in SUMMARY_KEYS}


def _points_pass_checks(base, values, n: int, level: str) -> bool:
    """Whether every point passes the cross-key checks of :func:`check` that the varied keys can break.

    The sweep validates every axis value on its own (type, bounds) and the whole design with a few
    representative values; the combinations are checked here, as arrays: z2 > z1, exactly one of R_p
    and K1, K1 < 1, no overlapping pins, the axle smaller than the bushing (and, at the formula level,
    than the [pin_load] bushing), f given.  A point that fails makes the sweep fall back to point-by-
    point evaluation, which reports it with the loader's message."""
    import numpy as np

    bad = _violations(values)
    if base.has("pin_load") and np.any(bad["pin_load.axle_radius_mm"]):
        return False
    if level == "formula":
        return True
    if np.any(bad["friction.sliding"]) or np.any(bad["geometry"].teeth) or np.any(bad["gearing.pin_circle_radius_mm"]):
        return False
    z1 = np.array(values("gearing.satellite_teeth"), dtype=np.int64)
    z2 = np.array(values("gearing.pins"), dtype=np.int64)
    e, Rb = _floats(values("gearing.eccentricity_mm")), _floats(values("gearing.pin_radius_mm"))
    K1g, Rpg = _floats(values("gearing.curtate_ratio")), _floats(values("gearing.pin_circle_radius_mm"))
    n_d = np.array(values("gearing.discs"), dtype=np.int64)
    if np.any(z2 * n_d > IDEAL_WORK_MAX):          # cost_problem: reported point by point
        return False
    key = np.nan_to_num(np.stack([z1, z2, n_d, e, Rb, K1g, Rpg], axis=1).astype(float), nan=-1.0)
    geometries = np.unique(key, axis=0)         # each distinct geometry is solved once (_ideal_columns)
    if float((geometries[:, 1] * geometries[:, 2]).sum()) > IDEAL_SWEEP_WORK_MAX:
        return False   # point by point instead (bounded memory, one progress step per point)
    return not (np.any(bad["geometry"].any()) or np.any(bad["gearing.axle_radius_mm"]))


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
    (pins.md §7).

    Friction model (:func:`friction_model`, pins.md §4.9, §5.5): "consistent" (the default) puts the
    friction forces into the moment balance and solves each mode (reducer, multiplier) with its own
    forces; a mode jams (no positive contact force balances the torque at some crank angle) and is then
    self-locking in that mode, the other one still computed.  "first-order" solves the requested mode
    with frictionless forces and takes both efficiencies from its loss ratio (§4.7)."""
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
    consistent = friction_model(design) == "consistent" and not (mu == 0.0 and f == 0.0)

    def run(mult: bool, in_equilibrium: bool, seed=None):
        try:
            return pc.cycle_at_torque(g, profile, law, design["load.torque_Nm"], design["load.torque_shaft"] == "V",
                                      mult, n_d, mu, f, rolls, in_equilibrium, tol=options.tol, seed=seed)
        except pc.Jam:
            raise
        except pc.NoEquilibrium as exc:
            key = ("gearing.tooth_circle_radius_mm" if design["gearing.profile"] == "circular"
                   else "gearing.equidistant_mod_mm")
            raise DesignError(key, f"= {design[key]}: no contact can carry the torque at crank angle "
                                   f"{_fmt(math.degrees(float(exc.theta[0])))} deg: no satellite rotation within "
                                   f"+-180/z1 = {_fmt(180.0 / z1)} deg balances T_V = {_fmt(exc.torque_V)} N*m (the "
                                   "teeth do not mesh with the pins, or the torque crushes the contacts; pins.md "
                                   "§5.5)") from None
        except pc.Unresolvable:
            raise DesignError("gearing.eccentricity_mm",
                              f"= {_fmt(e)}: the contact level cannot resolve this geometry in floating point "
                              f"(R_p = {_fmt(Rp)} mm, e = {_fmt(e)} mm, R_b = {_fmt(Rb)} mm: the deflections are "
                              "below the round-off of the pin positions)") from None

    # each mode with its own forces (consistent), or the requested mode's frictionless forces (first-order)
    jams = {}
    runs = {}
    for mult in ((multiplier, not multiplier) if consistent else (multiplier,)):
        seed = runs[multiplier].model if mult != multiplier and multiplier in runs else None
        try:
            runs[mult] = run(mult, consistent, seed)       # the other mode starts from the first one, mirrored
        except pc.Jam as exc:
            jams[mult] = exc
    if multiplier in jams:
        # the requested mode jams: its forces, speeds and peaks are those of the frictionless balance
        runs[multiplier] = run(multiplier, False)
        warnings.append(f"the {design['load.mode']} mode jams (self-locks) with the friction forces in the moment "
                        f"balance at crank angle {_fmt(math.degrees(float(jams[multiplier].theta[0])))} deg: no "
                        "positive contact force balances the torque; forces, speeds and losses are those of the "
                        "frictionless balance (friction.model = \"first-order\")")
    tc = runs[multiplier]
    for mult, t in runs.items():
        if not t.settled:
            warnings.append(f"the torque fixed point T_V = u T_H/eta did not settle in 8 passes (loss ratios "
                            f"{t.history[-2]:.10g}, {t.history[-1]:.10g})")
    cyc, model, T_V, lam, E = tc.cycle, tc.model, tc.torque_V, tc.loss_ratio, tc.loss_ratio_err
    sol = cyc.sol
    # the equilibrium residual against its limit: 1/100 of --tol (pins.md §6: inner tolerances 100x tighter),
    # or 100x the round-off floor of the penetrations (stiff contacts: deflections of 1e-7 mm on R_p)
    residual, excess = 0.0, 0.0
    for t in runs.values():
        r = np.abs(t.cycle.sol.residual) / t.model.torque_sat
        limit = np.maximum(0.01 * options.tol, 100.0 * t.cycle.sol.noise / t.model.torque_sat)
        residual, excess = max(residual, float(r.max())), max(excess, float(np.max(r / limit)))
    if not excess <= 1.0:
        stiff = (f"contact.stiffness_N_per_mm = {_fmt(law.constant)} N/mm" if law.name == "linear"
                 else f"the {law.name} law with contact.face_width_mm = {_fmt(design['contact.face_width_mm'])} mm")
        raise DesignError("load.torque_Nm", f"= {_fmt(design['load.torque_Nm'])}: the torque is too high for the "
                                            f"contact stiffness ({stiff}): the satellite's moment balance is met only "
                                            f"to {residual:.3g} of the torque at some crank angle (more than 1/100 of "
                                            f"--tol {options.tol:g} and than its round-off floor; pins.md §5.5); "
                                            "lower the torque or stiffen the contacts (a residual that stays "
                                            "when the torque is lowered is a jump of the moment where a contact "
                                            "passes a sharp crest corner: a curtate ratio further from 1)")
    # the loss ratio of each mode: its own (consistent) or the requested mode's (first-order)
    lam_mode = {m: (runs[m].loss_ratio, runs[m].loss_ratio_err) for m in runs if m not in jams}
    if not consistent:
        lam_mode = {True: (lam, E), False: (lam, E)}
    et_m = _efficiency_torques(np.array([lam_mode.get(True, (np.inf, np.nan))[0]]),
                               np.array([lam_mode.get(True, (np.inf, np.nan))[1]]), op, g.ratio)
    et_r = _efficiency_torques(np.array([lam_mode.get(False, (0.0, np.nan))[0]]),
                               np.array([lam_mode.get(False, (0.0, np.nan))[1]]), op, g.ratio)
    locked = {True: bool(et_m.locked[0]) or True in jams, False: False in jams}
    n_H = design["load.crank_speed_rpm"]
    w_H = units.rpm_to_rad_s(n_H) if n_H is not None else None
    pk = pc.cycle_peaks(cyc, g, n_d, rolls)
    metrics = pc.engagement_metrics(sol, cyc.spin if rolls else np.zeros(sol.force.shape[1:]))
    backlash = _backlash(model, profile, design)
    s = {
        "model": "contact", "profile": design["gearing.profile"], "rotating_pins": design["gearing.rotating_pins"],
        "mode": design["load.mode"], "ratio": g.ratio, "curtate_ratio": g.K1,
        "rolling_ok": None if rolling_ok is None else bool(rolling_ok[0]),
        "loss_ratio": lam, "loss_ratio_err": E, "n_crank": cyc.n_crank, "tolerance_met": bool(cyc.converged),
        "pin_force_max_N": pk.force if math.isfinite(T_V) else None,
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
    et = et_m if multiplier else et_r
    s["efficiency_multiplier"] = None if locked[True] else _plain(et_m.eta_vh[0])
    s["efficiency_multiplier_err"] = None if locked[True] else _plain(et_m.eta_vh_err[0])
    s["efficiency_reducer"] = None if locked[False] else _plain(et_r.eta_hv[0])
    s["efficiency_reducer_err"] = None if locked[False] else _plain(et_r.eta_hv_err[0])
    s["self_locking"] = locked[multiplier]
    s["efficiency"] = s["efficiency_multiplier" if multiplier else "efficiency_reducer"]
    s["efficiency_err"] = s["efficiency_multiplier_err" if multiplier else "efficiency_reducer_err"]
    s["torque_in_Nm"] = None if locked[multiplier] else _plain(et.torque_in[0])
    s["torque_out_Nm"] = None if locked[multiplier] else _plain(et.torque_out[0])
    if w_H is not None:
        Pw = w_H * 1e-3                                                   # W per (N·mm/s per rad/s)
        s["loss_mean_W"] = lam * T_V * (w_H * g.k / g.z1)
        s["loss_peak_W"] = pk.total * Pw
        s["pin_loss_max_W"] = pk.loss * Pw
        s["pin_loss_max_phase_deg"] = math.degrees(pk.loss_phase)
        coeff = mu if rolls else f
        s["pin_loss_bound_W"] = coeff * pk.force * pk.contact_speed * Pw
        rpm = units.rad_s_to_rpm(w_H)
        s["pin_speed_max_rpm"] = pk.spin_abs * rpm if rolls else 0.0
        s["pin_speed_signed_min_rpm"] = pk.spin_min * rpm if rolls else 0.0
        s["pin_speed_signed_max_rpm"] = pk.spin_max * rpm if rolls else 0.0
        s["sliding_speed_max_m_s"] = (pk.slide if rolls else pk.contact_speed) * w_H / units.MM_PER_M
    summary.update(s)
    if consistent and locked[multiplier]:
        # the shared notes word self-locking for the first-order multiplier; this level words it per mode
        summary["self_locking"] = False
        _cycle_notes(design, summary, options, warnings, failed)
        summary["self_locking"] = True
        cause = ("jams: no positive contact force balances the torque with the friction forces at some crank angle"
                 if multiplier in jams else f"the loss ratio {lam:.6g} >= 1 (the losses exceed the power the V shaft "
                                             "delivers)")
        failed.append(f"self-locking in the {design['load.mode']} mode (friction-consistent model, pins.md §4.9): "
                      f"it {cause}; no efficiency. A lower friction.sliding lowers the friction moments")
    else:
        _cycle_notes(design, summary, options, warnings, failed)
    for mult in jams:
        if mult != multiplier:
            warnings.append(f"the {'multiplier' if mult else 'reducer'} mode jams (self-locks) with the friction "
                            "forces in the moment balance: efficiency_" + ("multiplier" if mult else "reducer")
                            + " is empty")
    if options.detail:
        detail.update(_contact_detail(g, sol, cyc, T_V, w_H, n_d))


def _backlash(model, profile, design):
    """backlash_deg (pins.md §5.3): 0 without play by construction (an unmodified cycloid, the zero-backlash
    tooth circle), else :func:`gearcalc.pins_contact.backlash`."""
    from .. import pins_contact as pc

    if design["gearing.profile"] == "cycloidal" and not _modified(design):
        return 0.0
    if design["gearing.profile"] == "circular" and design["gearing.tooth_circle_radius_mm"] == "zero_backlash":
        return 0.0
    return math.degrees(pc.backlash(model))


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


def _rows(columns: dict) -> list[dict]:
    """Rows (dicts) from equal-length columns; a None column stays None in every row."""
    n = max(len(v) for v in columns.values() if v is not None)
    cols = {k: (v.tolist() if hasattr(v, "tolist") else v) if v is not None else [None] * n
            for k, v in columns.items()}
    keys = list(cols)
    return [dict(zip(keys, vals)) for vals in zip(*cols.values())]


def _detail_tables(g, sigma, st, t, mu, T_sat, omega_V, rolls, n_d: int = 1, hist=None, consistent=False):
    """Rows of the final grid (pins.md §8, :func:`gearcalc.pins.cycle_detail`): ``crank`` (one per crank
    angle: the loss ratio and loss of all discs, the loaded pins of the first, the crank torque of all discs
    along the power flow and the crank-bearing force of the first disc: magnitude, radial (along the crank
    arm, outward) and tangential components, direction from the crank arm) and ``contacts`` (one per
    loaded contact of the first disc); piece ends appear twice (the one-sided limits of both sides).
    ``hist``: :func:`gearcalc.pins.crank_history` at the nodes; with ``consistent`` the forces are the
    friction-consistent ones (pins.md §4.9)."""
    import numpy as np

    from .. import pins, pins_outputs

    d = pins.cycle_detail(g, sigma, st, mu, T_sat, omega_V, rolls, n_d,
                          denominator=hist["D"] if consistent else None)
    cols = {"theta_deg": d.theta, "TE_arcsec": np.zeros(d.theta.size), "loss_ratio": d.loss_ratio,
            "loss_W": d.loss, "loaded_pins": d.loaded}
    if hist is not None:
        have = T_sat is not None
        cd = pins_outputs.crank_detail(hist, t, sigma, g.z2, T_sat, n_d) if have else None
        cols.update({
            "crank_torque_Nm": cd.crank_torque if have and consistent else None,
            "bearing_force_N": cd.bearing_force if have else None,
            "bearing_radial_N": cd.bearing_radial if have else None,
            "bearing_tangential_N": cd.bearing_tangential if have else None,
            "bearing_angle_deg": cd.bearing_angle if have else None,
        })
    crank = _rows(cols)
    contacts = _rows({"theta_deg": d.contact_theta, "pin": d.pin, "phase_deg": d.phase, "force_N": d.force,
                      "sliding_speed_m_s": d.sliding_speed, "pin_speed_rpm": d.pin_speed, "loss_W": d.contact_loss})
    return {"crank": crank, "contacts": contacts}


def plot(records, path: str) -> None:
    """The pins figure (pins.md §8): force, pin speed (rotating pins only) and loss of one pin against crank
    angle over one engagement, the crank torque (the driving torque of a reducer, the paper's Figs 3-7) and
    lambda(theta) over one period; one curve per design (up to 6), the efficiencies in the title.
    Formula-level designs get a bar chart of P_tr1 and P_tr2 instead."""
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
    runs = []
    for rec in cyc:
        d = validate(dict(rec.design), rec.source)
        runs.append((rec, compute(d, Options(model=rec.result.model, detail=True))))
    rotating = any(any((row.get("pin_speed_rpm") or 0.0) != 0.0 for row in res.detail["contacts"])
                   for _, res in runs)
    torque = any(any(row.get("crank_torque_Nm") is not None for row in res.detail["crank"]) for _, res in runs)
    panels = [("force_N", "pin force F [N]")] + ([("pin_speed_rpm", "pin speed n_pin [rpm]")] if rotating else [])
    panels += [("loss_W", "pin loss P [W]")] + ([("crank_torque_Nm", "crank torque [N·m]")] if torque else [])
    panels += [("loss_ratio", "loss ratio lambda")]
    ncol = (len(panels) + 1) // 2
    fig, axes = plt.subplots(2, ncol, figsize=(5 * ncol, 7), squeeze=False)
    flat = list(axes.T.ravel()) if ncol > 1 else list(axes.ravel())
    for ax in flat[len(panels):]:                # no empty panel (fixed pins have no spin)
        fig.delaxes(ax)
    ax_of = {key: flat[i] for i, (key, _) in enumerate(panels)}
    titles = []
    for rec, res in runs:
        s = res.summary
        rows = sorted(res.detail["contacts"], key=lambda r: r["phase_deg"])
        phase = np.array([r["phase_deg"] for r in rows])
        # crank angle since the pin entered its loaded arc
        since = phase if s["mode"] == "multiplier" else s["psi_star_deg"] - phase
        label = rec.name
        for key in ("force_N", "pin_speed_rpm", "loss_W"):
            y = [r[key] for r in rows]
            if key in ax_of and all(v is not None for v in y):
                ax_of[key].plot(since, y, label=label)
        crank = res.detail["crank"]
        th = [r["theta_deg"] for r in crank]
        ax_of["loss_ratio"].plot(th, [r["loss_ratio"] for r in crank], label=label)
        if "crank_torque_Nm" in ax_of and crank and crank[0].get("crank_torque_Nm") is not None:
            ax_of["crank_torque_Nm"].plot(th, [r["crank_torque_Nm"] for r in crank], label=label)
        eff = s["efficiency"]
        model = s.get("friction_model") or ""
        titles.append(f"{label}: {s['mode']} efficiency "
                      + (f"{eff:.4f}" if eff is not None else "self-locking") + (f" ({model})" if model else ""))
    for key, ylab in panels:
        ax = ax_of[key]
        ax.set_ylabel(ylab)
        ax.set_xlabel("crank angle since entry [deg]" if key in ("force_N", "pin_speed_rpm", "loss_W")
                      else "crank angle theta over one period 360/z2 [deg]")
    ax_of["loss_ratio"].legend(fontsize=7)
    fig.suptitle("\n".join(titles), fontsize=8)
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
    table_fields=("model", "efficiency", "self_locking", "pin_force_max_N", "P_tr_W"),
    sweep_plot=("efficiency",),
    failure=(("self_locking", True),),
    plot=plot,
    batch=batch,
)
