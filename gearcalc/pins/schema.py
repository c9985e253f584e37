"""The design keys of the ``pins`` calculator (pins.md §7): tables, types, bounds, defaults, cost budgets,
and the summary fields (pins.md §8).

Imports nothing heavy: ``gearcalc new pins``, ``gearcalc check`` and the man page read it.
"""
from __future__ import annotations

from ..calculator import REQUIRED, Field, Table
from ..registry import LEVELS
from ..units import MAX_FORCE_N, MAX_FRICTION, MAX_LENGTH_MM, MAX_SPEED_RPM, MAX_TEETH, MAX_TORQUE_NM, MIN_LENGTH_MM
from .profiles import PROFILES

__all__ = ["MODELS", "MAX_DISCS", "MAX_DUTY_ROWS", "IDEAL_WORK_MAX", "IDEAL_SWEEP_WORK_MAX", "CONTACT_NODES_MAX",
           "CONTACT_WORK_MAX", "GROUP_PINS_MAX", "GROUP_TOL_MIN", "MAX_STIFFNESS_N_PER_MM", "TABLES", "HEADER",
           "SUMMARY_KEYS", "OPERATING_KEYS", "GEOMETRY_KEYS", "PIN_LOAD_KEYS", "FORMULA_SWEEP_KEYS", "IDEAL_SWEEP_KEYS"]

MODELS = LEVELS["pins"]
MAX_DISCS = 64
MAX_DUTY_ROWS = 1000
"""Rows of a duty cycle: each is an operating point (at the contact level a full solve each)."""

MAX_HOLES = 64
"""Output-mechanism holes (drives use 6-12)."""
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
GROUP_PINS_MAX = 200
"""An ideal-level design with more pins x discs than this is computed alone in a batch, as is any design at
``--tol`` below :data:`GROUP_TOL_MIN`: a group's arrays hold every member at the finest grid any member needs
(two 100-pin gears at 1e-15 took 2.9 GB together, 250 MB alone)."""
GROUP_TOL_MIN = 1e-9
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
        Field("profile", "string", REQUIRED, "satellite tooth profile", choices=tuple(PROFILES),
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
        Field("law", "string", None, "the teeth's sliding law: coulomb (absent: f = friction.sliding) | table "
              "(mu(v) from table_speed_m_s, table_mu) | stribeck (mu_c + (mu_s - mu_c) exp(-(v/v_s)^delta) + k_v v); "
              "ideal and contact levels, fixed pins, needs load.crank_speed_rpm (pins.md §4.10)",
              choices=("coulomb", "table", "stribeck")),
        Field("table_speed_m_s", "numbers", None, "v_k, sliding speeds of the mu(v) table, increasing", ge=0,
              le=1e4),
        Field("table_mu", "numbers", None, "mu_k, coefficients of the mu(v) table (linear between, held beyond)",
              ge=0, le=MAX_FRICTION),
        Field("stribeck_static", "number", None, "mu_s, breakaway coefficient", ge=0, le=MAX_FRICTION),
        Field("stribeck_coulomb", "number", None, "mu_c, mixed-film floor", ge=0, le=MAX_FRICTION),
        Field("stribeck_speed_m_s", "number", None, "v_s, Stribeck speed", gt=0, le=1e4),
        Field("stribeck_exponent", "number", None, "delta, shape exponent (absent: 2)", gt=0, le=10),
        Field("stribeck_viscous_s_per_m", "number", None, "k_v, viscous gradient (absent: 0)", ge=0, le=1e3),
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
        Field("drag_torque_Nm", "number", None, "T_d, no-load drag torque at the crank (seals), whatever the load; "
              "absent: none (ideal level, pins.md §4.10)", ge=0, le=MAX_TORQUE_NM),
    ), doc="Operating point; required with [gearing]", optional=True),
    Table("output", (
        Field("mechanism", "string", "ideal", "ideal: the output coupling transmits pure torque; pins_in_holes: "
              "n_w pins in holes of radius r_w + e, its forces on the crank bearing and its loss in the efficiency "
              "(ideal level, pins.md §4.10)", choices=("ideal", "pins_in_holes")),
        Field("holes", "integer", None, "n_w, holes (pins_in_holes)", ge=3, le=MAX_HOLES),
        Field("hole_circle_radius_mm", "number", None, "R_w, radius of the holes' circle (pins_in_holes)",
              ge=MIN_LENGTH_MM, le=MAX_LENGTH_MM),
        Field("pin_radius_mm", "number", None, "r_w, output pin (or its bushing) radius; holes r_w + e",
              ge=MIN_LENGTH_MM, le=MAX_LENGTH_MM),
        Field("friction", "number", None, "f_w, pin-hole friction (a rolling bushing: its equivalent); absent: "
              "friction.sliding", ge=0, le=MAX_FRICTION),
    ), doc="The output (W) mechanism between the satellite and the slow shaft (optional)", optional=True,
        in_template=False),
    Table("contact", (
        Field("law", "string", "hertz", "contact law: hertz (steel, ISO/TS 16281), palmgren, linear",
              choices=("hertz", "palmgren", "linear")),
        Field("face_width_mm", "number", None, "b, face width; required for hertz and palmgren",
              ge=MIN_LENGTH_MM, le=MAX_LENGTH_MM),
        Field("stiffness_N_per_mm", "number", None, "k_lin, contact stiffness; required for linear", gt=0,
              le=MAX_STIFFNESS_N_PER_MM),
        Field("friction_in_equilibrium", "bool", None, "alias of friction.model: true = \"consistent\", "
              "false = \"first-order\""),
        Field("stiffness_curve", "bool", None, "true: also the torsional stiffness, lost motion, hysteresis and "
              "transmission error with the crank held (contact level only; T_rated = load.torque_Nm on V)"),
    ), doc="Compliant contact level (circular teeth, modified cycloids): the contact law; face_width_mm alone "
           "gives the ideal level's contact stress without changing the level", optional=True,
        in_template=False),
    Table("material", (
        Field("allowable_stress_MPa", "number", None, "[sigma_H], allowable contact (Hertz) stress: the check "
              "margin_contact_stress = 1 - contact_stress_max_MPa/[sigma_H] (needs contact.face_width_mm)", gt=0,
              le=1e6),
    ), doc="The allowable contact stress of the tooth-pin contacts (optional)", optional=True, in_template=False),
    Table("bearing", (
        Field("C_N", "number", None, "C, basic dynamic load rating of one disc's crank bearing (ISO 281): "
              "bearing_L10_h at load.crank_speed_rpm (absent: no life)", gt=0, le=MAX_FORCE_N, example=10000.0),
        Field("exponent", "number", 10.0 / 3.0, "p, ISO 281 life exponent: 3 ball bearings, 10/3 roller "
              "bearings (the default: crank bearings of cycloidal drives are mostly needle/roller)", ge=1, le=10),
        Field("radial_stiffness_N_per_um", "number", None, "k_b, radial stiffness of one disc's crank bearing: "
              "in series with the pin contacts in the torsional stiffness (contact.stiffness_curve; absent: rigid)",
              gt=0, le=1e9),
    ), doc="The crank bearing's rating life and stiffness (optional)", optional=True, in_template=False),
    Table("duty", (
        Field("torque_Nm", "numbers", REQUIRED, "T_i, each row's torque on load.torque_shaft", gt=0,
              le=MAX_TORQUE_NM, example=[100.0, 50.0]),
        Field("crank_speed_rpm", "numbers", REQUIRED, "n_i, each row's crank speed", gt=0, le=MAX_SPEED_RPM,
              example=[1000.0, 1500.0]),
        Field("time_share", "numbers", REQUIRED, "t_i, each row's share of the time (normalised: any positive "
              "scale)", gt=0, le=1e12, example=[0.3, 0.7]),
    ), doc="A duty cycle: rows of (torque, crank speed, time share) evaluated as one design, as arrays of equal "
           "length or as [[duty]] rows (pins.md §8.3; optional)", optional=True, in_template=False, rows=True),
)

HEADER = """KHV planetary pin gearing after Prudnikov (seed 000): levels formula | ideal | contact.
[pin_load] alone: the paper's per-pin formula level.  [gearing] + [load]: the cycle model
(ideal for a cycloidal profile without modifications; circular profiles, modifications and
a contact.law or contact.stiffness_N_per_mm run the compliant contact level, which needs
[contact] face_width_mm; face_width_mm alone gives the ideal level's contact stress)."""

SUMMARY_KEYS = (
    "name", "model", "mode", "profile", "rotating_pins", "ratio", "curtate_ratio",
    "efficiency", "efficiency_err", "self_locking",
    "efficiency_multiplier", "efficiency_multiplier_err", "efficiency_reducer", "efficiency_reducer_err",
    "loss_ratio", "loss_ratio_err", "torque_in_Nm", "torque_out_Nm",
    "loss_mean_W", "loss_peak_W", "pin_force_max_N", "pin_force_max_phase_deg",
    "pin_loss_max_W", "pin_loss_max_phase_deg", "pin_loss_bound_W",
    "pin_speed_max_rpm", "pin_speed_signed_min_rpm", "pin_speed_signed_max_rpm", "spin_reversals",
    "sliding_speed_max_m_s", "crank_torque_mean_Nm", "crank_torque_ripple_Nm", "bearing_force_max_N",
    "bearing_force_mean_N", "bearing_equivalent_load_N", "bearing_equivalent_load_err_N", "bearing_L10_h",
    "bearing_L10_h_err", "contact_stress_max_MPa", "axle_pressure_max_MPa", "friction_model",
    "loaded_pins_min", "loaded_pins_max", "psi_star_deg", "rolling_ok",
    "exit_entry_force_ratio", "low_spin_fraction", "te_pp_arcsec", "backlash_deg", "equilibrium_residual",
    "contact_law", "tooth_radius_mm", "tooth_circle_radius_mm",
    "n_crank", "model_time_ms", "tolerance_met",
    "F_tr1_N", "F_tr2_N", "P_tr1_W", "P_tr2_W", "P_tr_W", "P_tr_fixed_W",
    "duty_rows", "duty_efficiency", "duty_efficiency_err", "duty_loss_mean_W", "duty_bearing_equivalent_load_N",
    "duty_bearing_equivalent_load_err_N", "duty_bearing_L10_h", "duty_bearing_L10_h_err",
    "duty_contact_stress_max_MPa", "duty_contact_stress_max_row",
    "model_reason", "margin_self_locking", "margin_rolling", "margin_contact_stress", "failed_checks",
    "output_mechanism", "w_loss_ratio", "w_force_max_N", "backdrive_startup_torque_Nm", "sliding_friction_mean",
)


OPERATING_KEYS = ("friction.sliding", "friction.rolling_mm", "friction.axle", "load.mode", "load.torque_shaft",
                  "load.torque_Nm", "load.crank_speed_rpm")
"""Keys an operating point may change without changing the ideal level's geometric solution."""

GEOMETRY_KEYS = ("gearing.satellite_teeth", "gearing.pins", "gearing.eccentricity_mm", "gearing.pin_circle_radius_mm",
                 "gearing.curtate_ratio", "gearing.pin_radius_mm", "gearing.axle_radius_mm", "gearing.rotating_pins",
                 "gearing.discs")
"""Geometry keys a vectorised ideal-level sweep may vary (each distinct geometry is solved once)."""

PIN_LOAD_KEYS = ("pin_load.normal_force_N", "pin_load.pin_speed_rpm", "pin_load.pin_radius_mm",
                 "pin_load.axle_radius_mm", "pin_load.paper_pi")
FORMULA_SWEEP_KEYS = PIN_LOAD_KEYS + ("friction.sliding", "friction.rolling_mm", "friction.axle",
                                      "material.allowable_stress_MPa")
IDEAL_SWEEP_KEYS = OPERATING_KEYS + GEOMETRY_KEYS + PIN_LOAD_KEYS + ("contact.face_width_mm",
                                                                    "material.allowable_stress_MPa", "bearing.C_N",
                                                                    "bearing.exponent") + (
    "load.drag_torque_Nm", "output.mechanism", "output.holes", "output.hole_circle_radius_mm", "output.pin_radius_mm",
    "output.friction")
