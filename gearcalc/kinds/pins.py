"""The ``pins`` calculator: KHV planetary pin gearing, per-pin friction losses and efficiency.

Cross-key checks and the glue between a design and the physics of :mod:`gearcalc.pins` (spec: pins.md):
design keys to physics arguments, physics results to named output fields; the keys are in
:mod:`gearcalc.pins.schema`, the texts and field lists in :mod:`gearcalc.pins.report`.  Three model levels;
this module picks the cheapest one the design needs:

* ``formula``: the paper's eqs. (3)-(7) from a given normal force and pin speed ([pin_load]);
* ``ideal``: the rigid conjugate cycle model of a cycloidal satellite ([gearing], no modifications);
* ``contact``: the compliant contact model of :mod:`gearcalc.pins.contact` (circular-arc teeth,
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

from ..calculator import Calculator, DesignError, Options, Problems, Result
from ..pins import report as R
from ..pins.schema import (CONTACT_NODES_MAX, CONTACT_WORK_MAX, FORMULA_SWEEP_KEYS, HEADER, IDEAL_SWEEP_KEYS,
                           IDEAL_SWEEP_WORK_MAX, IDEAL_WORK_MAX, MODELS, OPERATING_KEYS, SUMMARY_KEYS, TABLES)


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
    R_pl, r_pl = _floats(values("pin_load.pin_radius_mm")), _floats(values("pin_load.axle_radius_mm"))
    rot = np.array([bool(v) for v in values("gearing.rotating_pins")])
    r = _floats(values("gearing.axle_radius_mm"))
    z1, z2 = values("gearing.satellite_teeth"), values("gearing.pins")
    has_g = all(v is not None for v in z1 + z2)
    cycloidal = np.array([p == "cycloidal" for p in values("gearing.profile")])
    geometry = pins.geometry_violations(
        z1 if has_g else 0, z2 if has_g else 0, _floats(values("gearing.eccentricity_mm")), Rpg, K1g,
        _floats(values("gearing.pin_radius_mm")), r, rot, cycloidal)
    with np.errstate(invalid="ignore"):
        return {"pin_load.axle_radius_mm": r_pl >= R_pl,
                "friction.sliding": np.array([v is None for v in values("friction.sliding")]),
                "gearing.pin_circle_radius_mm": np.isnan(K1g) == np.isnan(Rpg),
                "gearing.axle_radius_mm": rot & np.isnan(r), "geometry": geometry}


def check(design, problems: Problems) -> None:
    """Cross-key checks (pins.md §7, §9); every problem is reported."""
    has_g, has_pl = design.has("gearing"), design.has("pin_load")
    if not has_g and not has_pl:
        problems.error(*R.problem("no_tables"))
        return
    bad = _violations(lambda key: [design.get(key)])
    if has_pl:
        if bad["pin_load.axle_radius_mm"][0]:
            problems.error(*R.problem("pin_load_axle", r=design["pin_load.axle_radius_mm"],
                                      R=design["pin_load.pin_radius_mm"]))
    if not has_g:
        return
    if not design.has("load"):
        problems.error(*R.problem("no_load"))
    if bad["friction.sliding"][0]:
        problems.error(*R.problem("no_sliding"))
    z1, z2 = design["gearing.satellite_teeth"], design["gearing.pins"]
    e, Rb = design["gearing.eccentricity_mm"], design["gearing.pin_radius_mm"]
    geo = bad["geometry"]
    ok_teeth = not geo.teeth[0]
    if not ok_teeth:
        problems.error(*R.problem("teeth", z1=z1, z2=z2))
    Rp_given, K1_given = design["gearing.pin_circle_radius_mm"], design["gearing.curtate_ratio"]
    if bad["gearing.pin_circle_radius_mm"][0]:
        problems.error(*R.problem("one_circle", given="both" if Rp_given is not None else "neither"))
    elif ok_teeth:
        Rp, K1, _ = _pin_circle(design)
        k = z2 - z1
        if geo.overflow[0]:        # e.g. K1 = 5e-324: R_p = inf (was exit 70)
            problems.error(*R.problem("overflow", K1=K1, e=e, ratio=z2 / k))
            return
        if geo.curtate[0]:
            if K1_given is not None:
                problems.error(*R.problem("curtate_K1", K1=K1))
            else:
                problems.error(*R.problem("curtate_Rp", Rp=Rp, K1=K1, limit=e * z2 / k, e=e))
        limit = float(geo.overlap_limit[0])        # R_p sin(pi/z2) (gearcalc.pins.geometry_violations)
        if geo.overlap[0]:
            problems.error(*R.problem("overlap", Rb=Rb, limit=limit, Rp=Rp, z2=z2))
    if design["gearing.rotating_pins"]:
        r = design["gearing.axle_radius_mm"]
        if bad["gearing.axle_radius_mm"][0]:
            problems.error(*R.problem("no_axle"))
        elif geo.axle[0]:
            problems.error(*R.problem("axle", r=r, Rb=Rb))
    rho_t = design["gearing.tooth_radius_mm"]
    one_circle = (Rp_given is None) != (K1_given is None)
    if design["gearing.profile"] == "circular" and ok_teeth and rho_t != "full" and one_circle:
        Rp = _pin_circle(design)[0]
        if Rb + rho_t >= Rp - e:
            problems.error(*R.problem("tooth_too_large", rho_t=rho_t, sum=Rb + rho_t, limit=Rp - e))
    if design["gearing.profile"] == "cycloidal":
        for key in ("tooth_radius_mm", "tooth_circle_radius_mm"):
            if design.is_given(f"gearing.{key}") and design[f"gearing.{key}"] not in ("full", "zero_backlash"):
                problems.warn(R.CIRCULAR_ONLY.format(key=key))
    if design["gearing.profile"] == "circular" and _modified(design):
        problems.warn(R.CYCLOID_MODS_IGNORED)
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
        return key, R.ideal_cost_text(design[key], z2, n_d, IDEAL_WORK_MAX)
    if level == "contact":
        on_V = design.get("load.torque_shaft") == "V"
        passes = 1 if on_V else 3
        if z2 * CONTACT_NODES_MAX * passes > CONTACT_WORK_MAX:
            return "gearing.pins", R.contact_cost_text(z2, CONTACT_NODES_MAX, passes, CONTACT_WORK_MAX, on_V)
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
        err = R.admissibility_error(int(status[0]), z1, z2, float(psi_star[0]), design["gearing.pin_radius_mm"],
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


def _check_contact_law(design, problems: Problems) -> None:
    """The contact law's own key must be there (pins.md §5.4, §7)."""
    law = design.get("contact.law", "hertz")
    if law in ("hertz", "palmgren") and design.get("contact.face_width_mm") is None:
        problems.error(*R.problem("face_width", law=law))
    if law == "linear" and design.get("contact.stiffness_N_per_mm") is None:
        problems.error(*R.problem("stiffness"))


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
        raise DesignError(*R.problem("need_pin_load"))
    if model in ("ideal", "contact") and not has_g:
        raise DesignError(*R.problem("need_gearing", model=model))
    if model == "ideal":
        if design["gearing.profile"] != "cycloidal":
            raise DesignError(*R.problem("ideal_profile", profile=design["gearing.profile"]))
        if _modified(design):
            raise DesignError(*R.problem("ideal_mods"))
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
            summary.update({k: formula[k][i] for k in R.FORMULA_KEYS})
            if d.get("friction.sliding") is None:
                summary["P_tr_fixed_W"] = None
        if level == "formula":
            summary["rotating_pins"] = True        # eqs. (3)-(7) are the paper's rotating-pin losses
        else:
            if d.has("contact"):   # only with --model ideal: a [contact] table otherwise selects "contact"
                warnings.append(R.CONTACT_TABLE_UNUSED)
            warnings.extend(ideal.warnings[i])
            summary.update({k: cols[k][i] for k in cols})
            if summary["loss_ratio"] is None and not summary["self_locking"]:   # overflowed (K1 ~ 1e-300 and
                # below): refused, not exit 70 (a jammed mode of the friction-consistent model has no loss ratio)
                key = "gearing.curtate_ratio" if d.get("gearing.curtate_ratio") is not None else \
                    "gearing.pin_circle_radius_mm"
                out.append(R.loss_ratio_overflow(key, d[key]))
                continue
            R.cycle_notes(d, summary, options.tol, warnings, failed)
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
    summary.update({k: cols[k][0] for k in R.FORMULA_KEYS})


def _floats(vals):
    """A float array from a list of numbers and None (NaN)."""
    import numpy as np

    return np.array([np.nan if v is None else v for v in vals], dtype=float)


def _formula_columns(values, n: int) -> dict:
    """The paper's eqs. (3)-(7) over designs or points (pins.md §3): columns of R.FORMULA_KEYS (None without
    [pin_load]; P_tr_fixed_W needs friction.sliding)."""
    import numpy as np

    from .. import pins

    F, n_pin = _floats(values("pin_load.normal_force_N")), _floats(values("pin_load.pin_speed_rpm"))
    R_pl, r_pl = _floats(values("pin_load.pin_radius_mm")), _floats(values("pin_load.axle_radius_mm"))
    fk, fc, f = (_floats(values(k)) for k in ("friction.rolling_mm", "friction.axle", "friction.sliding"))
    paper = np.array([bool(v) for v in values("pin_load.paper_pi")])
    res = pins.formula_losses(F, n_pin, R_pl, r_pl, fk, fc, paper_pi=paper, sliding_friction=f)
    return {k: R.column(v) for k, v in (("F_tr1_N", res.F_tr1), ("F_tr2_N", res.F_tr2), ("P_tr1_W", res.P_tr1),
                                        ("P_tr2_W", res.P_tr2), ("P_tr_W", res.P_tr), ("P_tr_fixed_W", res.P_tr_fixed))}




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
        from .. import pins

        k, cyc = int(self.gi[i]), self.cyc
        g = pins.Cycloid(int(self.z1[i]), int(self.z2[i]), float(self.e[i]), float(self.Rp[i]), float(self.Rb[i]),
                         float(self.omk[i]))
        T_sat = float(self.T_sat[i]) if self.columns["pin_force_max_N"][i] is not None else None
        w_V = float(self.w_V[i]) if design["load.crank_speed_rpm"] is not None else None
        sigma = pins.MULTIPLIER if design["load.mode"] == "multiplier" else pins.REDUCER
        T_V = self.columns["torque_in_Nm" if sigma == pins.MULTIPLIER else "torque_out_Nm"][i]
        return pins.detail.ideal_detail(g, float(cyc.psi_star[k]), *cyc.grid(k), float(self.mu[i]), sigma,
                                        self.models[i] == "consistent", T_sat, None if w_V is None else -w_V,
                                        bool(self.rolls[i]), int(self.n_d[i]), T_V)


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
    models, model_errors = _friction_models(values)
    op = _operating_values(values, one)
    pts = pins.ideal_points(
        z1, z2, e, Rb, K1g, Rpg, n_d, rot, r, op["friction.sliding"], op["friction.rolling_mm"], op["friction.axle"],
        _words_equal(op["load.mode"], "multiplier", one), _words_equal(op["load.torque_shaft"], "V", one),
        op["load.torque_Nm"], op["load.crank_speed_rpm"], np.array([m == "consistent" for m in models]),
        _floats(values("contact.face_width_mm")), tol=options.tol, xp=xp,
        # a consistent design alone needs no friction-free peaks
        first_order_peaks=not (one and n_d == 1 and models[0] == "consistent" and model_errors[0] is None))
    # admissibility (pins.md §4.2, §12.10) and the warning of §4.5, per point
    errors: list = [None] * n
    warnings: list[list[str]] = [[] for _ in range(n)]
    status, psi_0, Rp, omk, cyc, gi = pts.status, pts.psi_0, pts.Rp, pts.omk, pts.cyc, pts.gi
    at = (lambda arr, i: arr) if one else (lambda arr, i: arr[i])
    bad = ([0] if status != 0 else []) if one else np.flatnonzero(status != 0)
    for i in bad:                             # the messages of check() (admissibility_problem)
        if at(status, i) == pins.TOO_COSTLY:  # known after the quadrature only: not in check()
            errors[i] = R.too_costly_error(int(at(n_d, i)), int(at(pts.field("n_crank"), i)), options.tol,
                                           pins.DISC_SAMPLES_MAX, pins.DISC_WORK_MAX)
            continue
        errors[i] = R.admissibility_error(int(at(status, i)), int(at(z1, i)), int(at(z2, i)),
                                          float(at(pts.psi_star, i)), float(at(Rb, i)), float(cyc.rho_c_min[gi[i]]),
                                          float(at(pts.K1, i)))
    inside = (status == 0) & (Rb >= Rp * omk)
    for i in ([0] if inside else []) if one else np.flatnonzero(inside):
        p0 = None if xp.isnan(at(psi_0, i)) else float(at(psi_0, i))
        warnings[i].append(R.pitch_point_inside(at(Rb, i), at(Rp, i) * at(omk, i), p0))
    errors = [err if err is not None else m_err for err, m_err in zip(errors, model_errors)]
    arrays = R.ideal_fields(pts)
    for i in np.flatnonzero(pts.multi_disc):
        warnings[i].append(R.MULTI_DISC_PEAKS)
    mu, rolls, T_sat, w_V = pts.mu, pts.rolls, pts.sc.torque_sat, pts.sc.omega_V
    columns = R.ideal_columns(arrays, op["load.mode"], rot, rolls, models, n)
    if one:
        z1, z2, e, Rp, Rb, omk, n_d, mu, rolls, T_sat, w_V = (
            [v] for v in (z1, z2, e, Rp, Rb, omk, n_d, mu, rolls, T_sat, w_V))
    return IdealColumns(columns=columns, errors=errors, warnings=warnings, cyc=cyc, gi=gi, z1=z1, z2=z2, e=e, Rp=Rp,
                        Rb=Rb, omk=omk, n_d=n_d, mu=mu, rolls=rolls, T_sat=T_sat, w_V=w_V, models=models)


def _friction_models(values) -> tuple[list, list]:
    """friction.model per point (:func:`friction_model`; "consistent" where it fails) and per point None or the
    DesignError of a contradiction with its alias."""
    out, errors = [], []
    for m, a in zip(values("friction.model"), values("contact.friction_in_equilibrium")):
        try:
            out.append(friction_model({"friction.model": m, "contact.friction_in_equilibrium": a}))
            errors.append(None)
        except DesignError as exc:
            out.append("consistent")
            errors.append(exc)
    return out, errors


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
    from ..pins import contact as pc

    problems = Problems()
    _check_contact_law(design, problems)
    if problems.errors:
        raise DesignError(*problems.errors[0])
    return pc.contact_law(design.get("contact.law", "hertz"), design.get("contact.face_width_mm"),
                          design.get("contact.stiffness_N_per_mm"))


def _contact_profile(design, g, warnings):
    """The satellite profile of the contact level (:func:`gearcalc.pins.contact.circular_profile`,
    :func:`~gearcalc.pins.contact.cycloid_profile`); returns (profile, fields): tooth_radius_mm and
    tooth_circle_radius_mm (circular)."""
    from ..pins import contact as pc

    try:
        if design["gearing.profile"] != "circular":
            return pc.cycloid_profile(g, design["gearing.radial_mod_mm"], design["gearing.equidistant_mod_mm"]), {}
        rho_t, R_t = design["gearing.tooth_radius_mm"], design["gearing.tooth_circle_radius_mm"]
        prof, overlap = pc.circular_profile(g, None if rho_t == "full" else rho_t,
                                            None if R_t == "zero_backlash" else R_t)
    except pc.InadmissibleProfile as exc:
        raise R.profile_error(exc, design, g) from None
    if overlap:
        warnings.append(R.tooth_overlap(prof))
    return prof, {"tooth_radius_mm": prof.rho_t, "tooth_circle_radius_mm": prof.R_t}


def _contact(design, options: Options, summary, warnings, failed, detail) -> None:
    """The compliant contact level (pins.md §5) of one design (circular or cycloidal profile).

    The satellite rotation is solved at every crank angle (gearcalc.pins.contact); the cycle mean of
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
    from ..pins import contact as pc

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
    try:
        modes = pc.solve_modes(g, profile, law, design["load.torque_Nm"], design["load.torque_shaft"] == "V",
                               multiplier, n_d, mu, f, rolls, consistent, tol=options.tol)
    except pc.Jam:
        raise
    except pc.NoEquilibrium as exc:
        raise R.no_equilibrium_error(exc, design, z1) from None
    except pc.Unresolvable:
        raise R.unresolvable_error(e, Rp, Rb) from None
    runs, jams, tc = modes.runs, modes.jams, modes.requested
    warnings.extend(R.mode_warnings(modes, design["load.mode"]))
    residual, excess = pc.equilibrium_residual(runs.values(), options.tol)
    if not excess <= 1.0:
        raise R.stiffness_error(design, law, residual, options.tol)
    # the loss ratio of each mode: its own (consistent) or the requested mode's (first-order)
    lam = tc.loss_ratio
    et_m, et_r, locked = pc.mode_efficiencies(modes, consistent, op["load.torque_Nm"], g.ratio,
                                              _words_equal(op["load.mode"], "multiplier", False),
                                              _words_equal(op["load.torque_shaft"], "V", False))
    n_H = design["load.crank_speed_rpm"]
    w_H = units.rpm_to_rad_s(n_H) if n_H is not None else None
    cyc = tc.cycle
    pk = pc.cycle_peaks(cyc, g, n_d, rolls)
    metrics = pc.engagement_metrics(cyc.sol, cyc.spin if rolls else np.zeros(cyc.sol.force.shape[1:]))
    summary.update(R.contact_fields(design, g, law, geo, tc, pk, metrics, _backlash(tc.model, profile, design),
                                    residual, rolling_ok))
    summary.update(R.efficiency_fields(et_m, et_r, locked, multiplier, R.plain))
    summary["friction_model"] = friction_model(design)
    if w_H is not None:
        summary.update(R.operating_fields(pc.operating_values(pk, g, lam, tc.torque_V, w_H, mu, f, rolls)))
    if consistent and locked[multiplier]:
        # the shared notes word self-locking for the first-order multiplier; this level words it per mode
        summary["self_locking"] = False
        R.cycle_notes(design, summary, options.tol, warnings, failed)
        summary["self_locking"] = True
        failed.append(R.contact_self_locking(design["load.mode"], multiplier in jams, lam))
    else:
        R.cycle_notes(design, summary, options.tol, warnings, failed)
    warnings.extend(R.other_mode_jams(mult) for mult in jams if mult != multiplier)
    if options.detail:
        detail.update(pins.detail.contact_detail(g, cyc.sol, cyc, tc.torque_V, w_H, n_d))


def _backlash(model, profile, design):
    """backlash_deg (pins.md §5.3): 0 without play by construction (an unmodified cycloid, the zero-backlash
    tooth circle), else :func:`gearcalc.pins.contact.backlash`."""
    from ..pins import contact as pc

    if design["gearing.profile"] == "cycloidal" and not _modified(design):
        return 0.0
    if design["gearing.profile"] == "circular" and design["gearing.tooth_circle_radius_mm"] == "zero_backlash":
        return 0.0
    return math.degrees(pc.backlash(model))



def plot(records, path: str) -> None:
    """The figure of :mod:`gearcalc.pins.plot` (matplotlib imported there, on use)."""
    from ..pins.plot import plot as draw

    draw(records, path, compute)


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
