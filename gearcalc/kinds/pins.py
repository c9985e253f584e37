"""The ``pins`` calculator: design keys → :mod:`gearcalc.pins` → named summary and detail fields (pins.md).

Mapping only: validity rules in :mod:`gearcalc.pins.checks` (one set for check, compute, batch and sweep), the
formula and ideal levels over many designs :mod:`~gearcalc.pins.columns`, the contact level
:mod:`~gearcalc.pins.contact_level`, batch groups :mod:`~gearcalc.pins.batching`, keys :mod:`~gearcalc.pins.schema`,
texts :mod:`~gearcalc.pins.report`.  No numpy at module level: ``check``/``new``/``--help`` stay light.
"""
from __future__ import annotations

import math
import time

from ..calculator import Calculator, DesignError, Options, Problems, Result
from ..pins import checks as C
from ..pins import report as R
from ..pins.output_keys import LAW_ARGS, OUTPUT_ARGS, law_problem, output_problem
from ..pins.schema import (CONTACT_NODES_MAX, CONTACT_WORK_MAX, FORMULA_SWEEP_KEYS, GEOMETRY_KEYS,  # noqa: F401
                           HEADER, IDEAL_SWEEP_KEYS, IDEAL_WORK_MAX, MODELS, TABLES)

KEYS = {    # argument name of gearcalc.pins.checks, .columns, .contact_level -> design key
    "z1": "gearing.satellite_teeth", "z2": "gearing.pins", "e": "gearing.eccentricity_mm",
    "Rp": "gearing.pin_circle_radius_mm", "K1": "gearing.curtate_ratio", "Rb": "gearing.pin_radius_mm",
    "r": "gearing.axle_radius_mm", "rotating": "gearing.rotating_pins", "n_d": "gearing.discs",
    "profile": "gearing.profile", "tooth_radius": "gearing.tooth_radius_mm",
    "tooth_circle_radius": "gearing.tooth_circle_radius_mm", "equidistant_mod": "gearing.equidistant_mod_mm",
    "radial_mod": "gearing.radial_mod_mm", "sliding": "friction.sliding", "rolling": "friction.rolling_mm",
    "axle": "friction.axle", "mode": "load.mode", "shaft": "load.torque_shaft", "torque": "load.torque_Nm",
    "speed": "load.crank_speed_rpm", "force": "pin_load.normal_force_N", "pin_speed": "pin_load.pin_speed_rpm",
    "load_pin_radius": "pin_load.pin_radius_mm", "load_axle_radius": "pin_load.axle_radius_mm",
    "paper_pi": "pin_load.paper_pi", "face_width": "contact.face_width_mm", "model": "friction.model",
    "alias": "contact.friction_in_equilibrium", "law": "contact.law", "stiffness": "contact.stiffness_N_per_mm",
    "allowable": "material.allowable_stress_MPa", "torsion": "contact.stiffness_curve",
    "bearing_C": "bearing.C_N", "bearing_p": "bearing.exponent", "bearing_k": "bearing.radial_stiffness_N_per_um",
    **OUTPUT_ARGS,                                  # the output mechanism and the crank's drag (pins.md §4.10)
    **LAW_ARGS,                                     # the teeth's speed-dependent sliding law (pins.md §4.10)
}
CONTACT_LEVEL_ARGS = ("law", "stiffness")
"""The [contact] keys (argument names of :data:`KEYS`) that ask for the contact level (pins.md §3): a table with
face_width_mm alone (or with the friction alias) does not change the level; the ideal level gives the Hertz stress
of its own forces with it."""

GEAR_FIELDS = ("z1", "z2", "e", "Rp", "K1", "Rb", "r", "rotating", "profile")
"""The fields of :class:`gearcalc.pins.checks.GearGiven`, argument names of :data:`KEYS`."""

DEFAULT_FRICTION_MODEL = "consistent"
"""The friction model of a design that names none (pins.md §4.9, §7; tests of first-order numbers patch it)."""


def _args(values) -> dict:
    """Argument name -> its values over designs or points (``values(key)``: a list, None where absent)."""
    return {name: values(key) for name, key in KEYS.items()}


def _one(design) -> dict:
    """The design's values by argument name (None: absent; contact.law "hertz" by default)."""
    return {**{name: design.get(key) for name, key in KEYS.items()}, "law": design.get(KEYS["law"], "hertz")}


def _tables(design) -> set:
    """The design's tables that choose its level: "contact" only where [contact] names a law or a stiffness
    (:data:`CONTACT_LEVEL_ARGS`; face_width_mm alone gives the ideal level's stress)."""
    asks = design.has("contact") and any(design.is_given(KEYS[name]) for name in CONTACT_LEVEL_ARGS)
    return {t for t in ("gearing", "pin_load", "load") if design.has(t)} | ({"contact"} if asks else set())


def level_reason(design, model: str | None) -> str:
    """Why the design runs at its level (the summary's model_reason; :func:`gearcalc.pins.checks.level_cause`)."""
    return R.level_reason(C.level_cause(model, _tables(design), design.get(KEYS["profile"]), _modified(design)), model)


def friction_model(design) -> str:
    """``friction.model``, or its alias ``contact.friction_in_equilibrium``; the default when neither is given."""
    model, alias = design.get(KEYS["model"]), design.get(KEYS["alias"])
    name, contradiction = C.friction_model(model, alias, DEFAULT_FRICTION_MODEL)
    if contradiction:
        raise R.friction_alias_error(model, alias)
    return name


def _modified(design) -> bool:
    return design.has("gearing") and C.modified(design["gearing.equidistant_mod_mm"], design["gearing.radial_mod_mm"])


def _gear_given(values) -> C.GearGiven:
    """The gear as given (``values(key)``: one design's value, or a list over designs or points)."""
    return C.GearGiven(*(values(KEYS[name]) for name in GEAR_FIELDS))


def _pin_load_given(values) -> C.PinLoadGiven:
    """The per-pin load's radii as given (``values(key)`` as for :func:`_gear_given`)."""
    return C.PinLoadGiven(values(KEYS["load_pin_radius"]), values(KEYS["load_axle_radius"]))


def _violations(values):
    """:func:`gearcalc.pins.checks.violations` of designs or points (``values(key)``: a list, None where absent)."""
    return C.violations(_gear_given(values), values(KEYS["sliding"]), _pin_load_given(values))


def check(design, problems: Problems) -> None:
    """Cross-key checks (pins.md §7, §9; :func:`gearcalc.pins.checks.design_problems`); every problem is reported."""
    from ..engine import quiet_numpy

    a, tables = _one(design), _tables(design)
    with quiet_numpy():  # an overflow at an input's extreme is a problem said below, never a numpy warning
        found = C.design_problems(_violations(lambda key: [design.get(key)]), tables, _gear_given(design.get),
                                  _pin_load_given(design.get), a["tooth_radius"], a["tooth_circle_radius"],
                                  _modified(design))
    R.report_problems(found, problems)
    duty = _duty_problem(design, tables)
    if duty is not None:
        problems.error(*duty)
    if "gearing" not in tables or found and found[-1][1] == "overflow":
        return
    level = select_level(design, None)
    problem = _law_problem(a) if "contact" in tables or level == "contact" else None
    if problem is None and level in ("ideal", "contact"):
        problem = output_problem(a, level, _pin_circle(a)) or law_problem(a, level)
    if problem is None and not problems.errors:
        problem = cost_problem(design, level) or (admissibility_problem(design, level) if level != "formula" else None)
    if problem is not None:
        problems.error(*problem)


def _duty_problem(design, tables):
    """(key, message) when the [duty] table's arrays do not form rows (pins.md §8.3), else None."""
    from ..pins.schema import MAX_DUTY_ROWS

    if not design.has("duty"):
        return None
    if "gearing" not in tables or "load" not in tables:
        return "duty", "a duty cycle needs [gearing] and [load] (the rows vary load.torque_Nm and crank_speed_rpm)"
    n = [len(design.get("duty." + k) or ()) for k in ("torque_Nm", "crank_speed_rpm", "time_share")]
    if len(set(n)) != 1:
        return ("duty.time_share", f"duty.torque_Nm, duty.crank_speed_rpm and duty.time_share must have the same "
                f"length (one entry per row): {n[0]}, {n[1]} and {n[2]} given")
    if not 1 <= n[0] <= MAX_DUTY_ROWS:
        return "duty.torque_Nm", f"a duty cycle has 1 to {MAX_DUTY_ROWS} rows ({n[0]} given)"
    return None


def _duty(design, options: Options, base: Result) -> Result:
    """The duty cycle's fields (:func:`gearcalc.pins.duty.duty_combine`) added to the design's own result: each row
    is the design at that torque and crank speed, computed as a batch (the ideal level: all rows together)."""
    import dataclasses

    from ..pins.duty import duty_combine

    T, n, t = (design.get("duty." + k) for k in ("torque_Nm", "crank_speed_rpm", "time_share"))
    rows = []
    for T_i, n_i in zip(T, n):
        values = {k: dict(v) for k, v in design.values.items() if k != "duty"}
        values["load"].update(torque_Nm=T_i, crank_speed_rpm=n_i)
        rows.append(dataclasses.replace(design, values=values, given=set(design.given), warnings=[]))
    results = batch(rows, options)
    for i, r in enumerate(results):
        if isinstance(r, BaseException):
            raise r
        base.warnings.extend(f"duty row {i + 1}: {w}" for w in r.warnings)
    p = design.get("bearing.exponent") if design.has("bearing") else None
    base.summary.update(duty_combine([r.summary for r in results], t, n, 10.0 / 3.0 if p is None else p,
                                     design.get("bearing.C_N") if design.has("bearing") else None))
    return base


def cost_problem(design, level: str):
    """(key, message) when the design's computation at that level would exceed its cost budget
    (:data:`IDEAL_WORK_MAX`, :data:`CONTACT_WORK_MAX`), else None.  ``check`` and compute share it."""
    if level not in ("ideal", "contact") or not design.has("gearing"):
        return None
    z2, n_d, on_V = design[KEYS["z2"]], design[KEYS["n_d"]], design.get(KEYS["shaft"]) == "V"
    if level == "ideal" and C.ideal_over_budget(z2, n_d):
        return R.ideal_cost_problem(z2, n_d)
    if level == "contact" and C.contact_over_budget(z2, on_V):
        return R.contact_cost_problem(z2, C.contact_passes(on_V), C.contact_pins_max(on_V), on_V)
    return None


def admissibility_problem(design, level: str):
    """(key, message) of the first geometric admissibility problem the computation at that level reports
    (pins.md §4.2, §5.2-5.3, §9, §12.10), else None: the same rules as compute, run here so that ``gearcalc
    check`` reports them too.  Needs a design that passed the other checks."""
    a = _one(design)
    if level == "ideal":
        status, psi_star, rho_c, K1 = C.ideal_admissibility(*(a[n] for n in ("z1", "z2", "e", "Rp", "K1", "Rb")))
        err = status and R.admissibility_error(status, a["z1"], a["z2"], psi_star, a["Rb"], rho_c, K1)
        return (err.key, err.message) if err else None
    try:
        made = _satellite(design, a)
    except DesignError as exc:
        return exc.key, exc.message
    design.keep("pins", _satellite_values(a), made)  # for its computation (_contact): built once per run
    return None


def _pin_circle(a):
    """R_p [mm] from either key (None: neither given or not computable)."""
    if a["Rp"] is not None:
        return a["Rp"]
    try:
        return a["e"] * a["z2"] / ((a["z2"] - a["z1"]) * a["K1"])
    except (TypeError, ZeroDivisionError):
        return None


def select_level(design, model: str | None, budget: bool = False) -> str:
    """The level to run (:func:`gearcalc.pins.checks.select_level`); with ``budget``, within its cost budget."""
    level, rule = C.select_level(model, _tables(design), design.get(KEYS["profile"]), _modified(design))
    problem = R.problem(rule, model=model, profile=design.get(KEYS["profile"])) if rule else None
    problem = problem or (cost_problem(design, level) if budget else None)
    if problem is not None:
        raise DesignError(*problem)
    return level


def compute(design, options: Options) -> Result:
    """Run the level the design needs (or ``--model``): the formula and ideal levels as a group of one (a batch
    equals ``compute`` design by design), the contact level on its own; a ``[duty]`` cycle adds its rows."""
    if design.has("duty"):
        import dataclasses

        own = dataclasses.replace(design, values={k: v for k, v in design.values.items() if k != "duty"})
        return _duty(design, options, compute(own, options))
    t0 = time.perf_counter()
    level = select_level(design, options.model, budget=True)
    if level != "contact":
        (out,) = _group([design], level, options, t0)
        if isinstance(out, BaseException):
            raise out
        return out
    warnings, failed, detail = [], [], {}
    summary = _contact(design, options, warnings, failed, detail)
    summary["model_time_ms"] = (time.perf_counter() - t0) * 1e3
    return R.result(summary, detail, warnings, failed)


def batch(designs, options: Options) -> list:
    """Many pins designs at once (:func:`gearcalc.pins.batching.run_batch`): per design, the Result ``compute``
    returns or the exception it raises; ``model_time_ms`` of a design of a group is the group's time per design."""
    from ..pins.batching import run_batch

    return run_batch(designs, lambda d: select_level(d, options.model, budget=True),
                     lambda d, level: d.has("duty") or (
                         level == "ideal" and C.computed_alone(d[KEYS["z2"]], d[KEYS["n_d"]], options.tol)),
                     lambda d: compute(d, options), lambda ds, level: _group(ds, level, options, time.perf_counter()))


def _group(designs, level: str, options: Options, t0: float) -> list:
    """Results (or DesignErrors) of designs that all run at the formula or the ideal level, computed together."""
    from ..pins.columns import level_columns

    cols, ideal = level_columns(_args(lambda key: [d.get(key) for d in designs]), level, [d.name for d in designs],
                                options.tol, any(d.has("pin_load") for d in designs), DEFAULT_FRICTION_MODEL)
    cols["model_reason"] = [level_reason(d, options.model) for d in designs]
    return _group_results(designs, cols, ideal, options, t0)


def _rolling(value) -> C.RollingValues:
    """The design's values in the rolling condition (``value(name)``: the value of an argument name of :data:`KEYS`,
    e.g. ``a.get`` of :func:`_one`)."""
    return C.RollingValues(*(value(name) for name in ("sliding", "Rb", "axle", "r", "rolling")))


def _value_of(design):
    """``value(name)``: the design's value of an argument name of :data:`KEYS` (None: absent)."""
    return lambda name: design.get(KEYS[name])


def _group_results(designs, cols, ideal, options: Options, t0: float) -> list:
    """Per design of a group computed together (:func:`gearcalc.pins.columns.level_columns`: its columns ``cols``
    and the ideal level's :class:`~gearcalc.pins.columns.IdealColumns` or None) its Result or DesignError, with
    the notes of :func:`gearcalc.pins.report.cycle_notes`; ``model_time_ms`` is the group's time since ``t0`` per
    design."""
    out = []
    for i, d in enumerate(designs):
        summary, warnings, failed, tables = {k: col[i] for k, col in cols.items()}, [], [], {}
        if ideal is not None:
            if ideal.errors[i] is not None:
                out.append(ideal.errors[i])
                continue
            value = _value_of(d)
            law = d.has("contact") and (d.is_given(KEYS["law"]) or d.is_given(KEYS["stiffness"]))
            warnings = ([R.CONTACT_TABLE_UNUSED] if law else []) + ideal.warnings[i]
            R.cycle_notes(summary, _rolling(value), value("speed"), options.tol, warnings, failed)
            failed.extend(R.stress_failure(summary, value("allowable")))
            tables = ideal.detail(i) if options.detail else {}
        out.append(R.result(summary, tables, warnings, failed))
    per_design = (time.perf_counter() - t0) * 1e3 / len(designs)
    for r in out:
        if isinstance(r, Result):
            r.summary["model_time_ms"] = per_design
    return out


def sweep(base, raw, axes, points, options):
    """A grid of points as columns (a list per summary field): the formula level over ``FORMULA_SWEEP_KEYS``,
    the ideal level over ``IDEAL_SWEEP_KEYS``, each distinct geometry solved once (pins.md §4.8 identity 8).
    None (the caller evaluates point by point and reports the first bad point exactly as it would) for other
    keys, the contact level, or a grid with an invalid or inadmissible point.  ``model_time_ms``: per point."""
    from ..pins.columns import level_columns

    t0 = time.perf_counter()
    level = select_level(base, options.model)
    if base.has("duty") or any(k not in {"formula": FORMULA_SWEEP_KEYS, "ideal": IDEAL_SWEEP_KEYS}.get(level, ())
                               for k in axes):      # a duty cycle: point by point (each point's rows as a batch)
        return None
    n, varied = len(points), set(axes)

    def values(key):
        fixed = base.get(key)
        return [p.get(key, fixed) for p in points] if key in varied else [fixed] * n

    if not _points_pass_checks(base, values, n, level):
        return None
    cols, ideal = level_columns(_args(values), level, [base.name] * n, options.tol, base.has("pin_load"),
                                DEFAULT_FRICTION_MODEL)
    if ideal is not None and any(err is not None for err in ideal.errors):
        return None
    cols["model_time_ms"] = [(time.perf_counter() - t0) * 1e3 / max(n, 1)] * n
    cols["model_reason"] = [level_reason(base, options.model)] * n
    return cols


def sweep_cost(base, axes, options) -> float:
    """Estimated seconds of one point of a sweep (:func:`gearcalc.grid.point_seconds`), measured on one core
    (2026-12-07): :func:`sweep`'s arrays 25 us a point (43 000 points/s end to end), plus, at the ideal level,
    each distinct geometry of the grid's geometry axes as alone (1-2 ms measured); point by point the formula
    level 1 ms, the ideal level 1 ms + 35 us a pin-disc (:data:`IDEAL_WORK_MAX`), the contact level 0.22 ms a pin
    and pass of the torque fixed point (38-40 ms for ``configs/pins_paper_circ_u30_rotating.toml``: 62 pins,
    3 passes).  Below the default --tol the ideal level's pin-disc term grows as the crank-angle nodes a gear
    needs, (1e-6/tol)^(1/2) (trapezoid and Richardson, E ~ h^2; measured 2026-12-07: 320 nodes a gear at 1e-6,
    9 900 at 1e-9, 8 ms a geometry in a batch), so a chunk stays about a second of work and its memory bounded
    (1 001 eccentricities at 1e-9 in one chunk took 1.3-2 GB)."""
    try:
        level = select_level(base, options.model)
    except DesignError:
        return 1e-3  # the sweep reports the error at its first point
    vectorised = all(k in {"formula": FORMULA_SWEEP_KEYS, "ideal": IDEAL_SWEEP_KEYS}.get(level, ()) for k in axes)
    geometries = math.prod(len(v) for k, v in axes.items() if k in GEOMETRY_KEYS)
    if vectorised and (level != "ideal" or geometries == 1):
        return 2.5e-5
    if level == "formula" or not base.has("gearing"):
        return 1e-3
    z2 = max([base["gearing.pins"]] + [v for v in axes.get("gearing.pins", []) if isinstance(v, int)])
    if level == "ideal":
        n_d = max([base["gearing.discs"]] + [v for v in axes.get("gearing.discs", []) if isinstance(v, int)])
        nodes = max(1.0, math.sqrt(1e-6 / options.tol))       # the nodes a gear needs, relative to --tol 1e-6
        if vectorised:  # each distinct geometry solved once (as alone: 1-2 ms measured), then 25 us a point
            points = math.prod(len(v) for v in axes.values())
            return 2.5e-5 + (1e-3 + 35e-6 * z2 * n_d * nodes) * geometries / max(points, 1)
        return 1e-3 + 35e-6 * z2 * base["gearing.discs"] * nodes
    return 2.2e-4 * z2 * C.contact_passes(base.get(KEYS["shaft"]) == "V")


def _points_pass_checks(base, values, n: int, level: str) -> bool:
    """Whether every point passes the checks its varied keys can break (else: point by point, as the loader)."""
    return C.points_pass(_violations(values), level == "formula", base.has("pin_load"), _gear_given(values),
                         values(KEYS["n_d"]))


def _law_problem(a):
    rule = C.contact_law_problem(a["law"], a["face_width"], a["stiffness"])
    return R.problem(rule, law=a["law"]) if rule else None


SATELLITE_ARGS = ("z1", "z2", "e", "Rp", "K1", "Rb", "law", "face_width", "stiffness", "profile", "tooth_radius",
                  "tooth_circle_radius", "radial_mod", "equidistant_mod")
"""The arguments :func:`_satellite` reads."""


def _satellite_values(a) -> tuple:
    return tuple(a[n] for n in SATELLITE_ARGS)


def _satellite(design, a):
    """(gear, contact law, satellite profile, overlap) of the contact level (pins.md §5.2-5.4); DesignError for
    a missing constant of the law or an inadmissible profile."""
    from ..pins.contact import InadmissibleProfile, contact_law
    from ..pins.contact_level import gear, satellite_profile

    g = gear(*(a[n] for n in ("z1", "z2", "e", "Rp", "K1", "Rb")))[0]
    if _law_problem(a):
        raise DesignError(*_law_problem(a))
    law = contact_law(a["law"], a["face_width"], a["stiffness"])
    try:
        return (g, law, *satellite_profile(g, a["profile"], a["tooth_radius"], a["tooth_circle_radius"],
                                           a["radial_mod"], a["equidistant_mod"]))
    except InadmissibleProfile as exc:
        raise R.profile_error(exc, g, a["radial_mod"], a["equidistant_mod"]) from None


def _contact(design, options: Options, warnings, failed, detail) -> dict:
    """The summary of the compliant contact level (:func:`gearcalc.pins.contact_level.contact_level`)."""
    from ..pins import contact as pc
    from ..pins.columns import OPERATING, level_columns
    from ..pins.contact_level import ContactDesign, contact_level
    from ..pins.margins import margin_columns

    from ..pins.output_contact import contact_output_fields, contact_w
    from ..pins.speed_friction import sliding_law

    a = _one(design)
    problem = output_problem(a, "contact", _pin_circle(a)) or law_problem(a, "contact")
    if problem:
        raise DesignError(*problem)
    cols, _ = level_columns({n: [x] for n, x in a.items()}, "contact", [design.name], options.tol,
                            design.has("pin_load"), DEFAULT_FRICTION_MODEL)
    summary = {k: v[0] for k, v in cols.items()}
    made = design.take("pins", _satellite_values(a)) if hasattr(design, "take") else None
    g, law, profile, overlap = made if made is not None else _satellite(design, a)
    warnings.extend([R.tooth_overlap(profile)] if overlap else [])
    model = friction_model(design)
    w = contact_w(a, g.ratio)       # the teeth carry the output mechanism's and the drag's torque (pins.md §4.10)
    point = {**{n: a[n] for n in OPERATING}, "torque": w.teeth_torque, "law": sliding_law(a)}    # a speed law: §4.10
    try:
        cl = contact_level(ContactDesign(g, profile, law, a["n_d"], a["rotating"], a["r"], a["bearing_k"]),
                           point, model, options.tol,
                           profile.play_free, options.detail, settings=options.settings, torsion=bool(a["torsion"]))
    except pc.NoEquilibrium as exc:
        raise R.no_equilibrium_error(exc, a["z1"], a["profile"], a["tooth_circle_radius"],
                                     a["equidistant_mod"]) from None
    except pc.Unresolvable:
        raise R.unresolvable_error(a["e"], g.R_p, a["Rb"], a["torque"]) from None
    turns = {mult: C.satellite_turn(t) for mult, t in cl.modes.runs.items()}    # deflection-sized (pins.md §7)
    warnings.extend(R.mode_warnings(cl.modes, a["mode"], turns))
    if not cl.balanced:
        raise R.stiffness_error(law, a["face_width"], a["torque"], cl.residual, options.tol)
    summary.update(_contact_summary(design, g, law, profile, cl, model))
    R.contact_notes(summary, _rolling(a.get), a["speed"], options.tol, warnings, failed, cl)
    fields, drag_lock = contact_output_fields(w, summary, cl, a, g.ratio, a["n_d"])
    summary.update(fields)
    failed.extend(drag_lock)
    summary.update({k: v[0] for k, v in margin_columns({k: [v] for k, v in summary.items()},
                                                       {n: [x] for n, x in a.items()}).items()})
    failed.extend(R.stress_failure(summary, a["allowable"]))
    summary["model_reason"] = level_reason(design, options.model)
    if cl.torsion is not None:          # only when the design asks (contact.stiffness_curve, pins.md §5.8)
        summary.update(cl.torsion[0])
        detail.update(cl.torsion[1] if options.detail else {})
    detail.update(cl.detail or {})
    return summary


def _contact_summary(design, g, law, profile, cl, model: str) -> dict:
    """The contact level's summary fields (pins.md §8) from :class:`gearcalc.pins.contact_level.ContactLevel`
    ``cl`` of ``design`` with gear ``g``, contact ``law``, satellite ``profile`` and friction ``model``."""
    geo = profile.summary_fields()
    multiplier = design["load.mode"] == "multiplier"
    s = R.contact_fields(design["gearing.profile"], design["gearing.rotating_pins"], design["load.mode"], g, law, geo,
                         cl, C.satellite_turn(cl.modes.requested))
    s.update(R.efficiency_fields(cl.et_multiplier, cl.et_reducer, cl.locked, multiplier, R.plain))
    s.update(_crank_fields(cl, design, s["pin_force_max_N"]))
    s["friction_model"] = model
    if cl.operating is not None:
        s.update(R.operating_fields(cl.operating))
    return s


def _crank_fields(cl, design, force_max) -> dict:
    """The crank torque, crank-bearing force, contact stress and axle pressure of the contact level (pins.md §8)
    from its :class:`~gearcalc.pins.contact.CrankBearing` ``cl.crank``: the crank torque only with the requested
    mode's friction-consistent forces (null first-order or jammed), the stress with ``contact.face_width_mm``
    over the flank contacts, the axle pressure for rotating pins (F_max/(2 r b))."""
    from ..pins.outputs import STEEL_E_STAR_MPA, axle_pressure, contact_stress

    cb, b = cl.crank, design.get("contact.face_width_mm")
    own = cl.consistent and (design["load.mode"] == "multiplier") not in cl.modes.jams
    stress = (R.plain(contact_stress(1.0, cb.stress_factor, b, STEEL_E_STAR_MPA))
              if b is not None and math.isfinite(cb.stress_factor) else None)
    rotating, r = design["gearing.rotating_pins"], design.get("gearing.axle_radius_mm")
    return {"crank_torque_mean_Nm": cb.crank_torque_mean if own else None,
            "crank_torque_ripple_Nm": cb.crank_torque_ripple if own else None,
            "bearing_force_max_N": cb.bearing_force_max, "bearing_force_mean_N": cb.bearing_force_mean,
            "contact_stress_max_MPa": stress,
            "axle_pressure_max_MPa": (R.plain(axle_pressure(force_max, r, b))
                                      if rotating and b is not None and force_max is not None else None),
            **_contact_bearing_fields(cb, design)}


def _contact_bearing_fields(cb, design) -> dict:
    """The crank bearing's equivalent load and L10_h at the contact level (pins.md §8.2): the p-mean of one disc's
    |B| with the cycle mean's weights; its error the difference from the plain trapezoid's p-mean (the
    Richardson-corrected mean's error is below it)."""
    import numpy as np

    from ..pins.outputs import bearing_life

    if cb.mean_weights is None:
        return dict.fromkeys(R.BEARING_KEYS)
    p = design.get("bearing.exponent") if design.has("bearing") else None
    p = 10.0 / 3.0 if p is None else float(p)
    Bp = np.asarray(cb.bearing_force, dtype=float) ** p
    m = float(np.sum(cb.mean_weights * Bp))
    dm = abs(m - float(np.sum(cb.trapezoid_weights * Bp)))
    C = design.get("bearing.C_N") if design.has("bearing") else None
    n = design.get("load.crank_speed_rpm")
    vals = bearing_life(m, dm, p, 1.0, math.nan if C is None else C, math.nan if n is None else n)
    return {k: (float(v) if math.isfinite(float(v)) else None) for k, v in zip(R.BEARING_KEYS, vals)}


def plot(records, path: str) -> list:
    """The figure of :mod:`gearcalc.pins.plot` (matplotlib imported there, on use); the records drawn."""
    from ..pins.plot import plot as draw

    return draw(records, path, compute)


def implicit(design) -> dict:
    """``friction.model`` as the computation takes it when left out (its alias contact.friction_in_equilibrium,
    else the default), unless the alias is given (the design then says it)."""
    return {} if design.get(KEYS["alias"]) is not None else {KEYS["model"]: friction_model(design)}


CALCULATOR = Calculator(
    kind="pins", title="KHV planetary pin gearing: per-pin friction losses and efficiency", tables=TABLES,
    implicit=implicit, compute=compute, check=check, models=MODELS, header=HEADER, sweep=sweep,
    sweep_cost=sweep_cost,
    table_fields=("model", "efficiency", "self_locking", "pin_force_max_N", "P_tr_W"), sweep_plot=("efficiency",),
    failure=(("self_locking", True),), plot=plot, batch=batch,
    checks=C.CHECKS,
)
