"""The formula and ideal levels over many designs or sweep points as summary columns (pins.md §3, §4, §8).

The inputs are the points' values in the physics' names (``v[name]``: a list over the points, None where a
value is absent, as designs and sweep grids give them; the adapter :mod:`gearcalc.kinds.pins` maps the design
keys to these names); the outputs are plain Python columns (lists over the points, None: undefined) named as
the summary fields, with per point the DesignError it raises and its warnings (texts of
:mod:`gearcalc.pins.report`).  One design, a batch and a sweep run these same functions.

Names: gear ``z1, z2, e, Rp, K1, Rb, r, rotating, n_d``; operating point ``sliding, rolling, axle, mode, shaft,
torque, speed`` (:data:`OPERATING`); per-pin load ``force, pin_speed, load_pin_radius, load_axle_radius,
paper_pi``; ``face_width``; the friction model ``model`` and its alias ``alias``.
"""
from __future__ import annotations

import math

import numpy as np

from . import report as R
from .checks import friction_model
from .formula import formula_losses
from .friction import PinFriction
from .geometry import MULTIPLIER, REDUCER, Cycloid
from .ideal import DISC_SAMPLES_MAX, DISC_WORK_MAX, TOO_COSTLY
from .margins import margin_columns
from .operating import ARRAY_OPS, SCALAR_OPS, FrictionCoefficients, Gears, OperatingPoint, SatelliteLoad, floats
from .output_mech import output_fields, w_bearing_columns
from .points import ideal_points
from .schema import SUMMARY_KEYS

__all__ = ["OPERATING", "floats", "float64", "words_equal", "operating", "friction_models", "formula_columns",
           "IdealColumns", "ideal_columns", "level_columns"]

OPERATING = ("sliding", "rolling", "axle", "mode", "shaft", "torque", "speed")
"""The operating point's names: f, f_k [mm], f_c, the mode and the torque's shaft (words), T [N·m], n_H [rpm]."""
_WORDS = ("mode", "shaft")


def float64(v):
    """A value as a numpy float64 scalar (NaN where absent).

    Parameters
    ----------
    v : float or None
        The value.

    Returns
    -------
    x : numpy.float64
        The value, NaN for None.

    Examples
    --------
    >>> float(float64(2)), bool(np.isnan(float64(None)))
    (2.0, True)

    References
    ----------
    .. [1] docs/spec/pins.md §7 (absent design values).
    """
    return np.float64(math.nan if v is None else v)


def words_equal(words, word, one: bool):
    """Whether each word of a column is ``word`` (one point: a bool; else an array).

    Parameters
    ----------
    words : list of str or str
        The column (one point: its word).
    word : str
        The word looked for.
    one : bool
        One point.

    Returns
    -------
    equal : bool or ndarray of bool
        Per point.

    Examples
    --------
    >>> words_equal(["reducer", "multiplier"], "reducer", False).tolist(), words_equal("reducer", "reducer", True)
    ([True, False], True)

    References
    ----------
    .. [1] docs/spec/pins.md §7 (words of the design keys).
    """
    return words == word if one else np.array([w == word for w in words])


def operating(v, one: bool = False) -> dict:
    """The operating point's values (:data:`OPERATING`) over points.

    float arrays (NaN: absent) and lists of words; with ``one``, the single point's scalars (numpy float64, NaN
    where absent; the word).

    Parameters
    ----------
    v : dict
        The points' values by name, lists over the points (None: absent).
    one : bool, optional
        One point: scalars.

    Returns
    -------
    op : dict
        f, f_k [mm], f_c, T [N·m], n_H [rpm] as floats; the mode and the torque's shaft as words.

    Examples
    --------
    >>> v = {"sliding": [0.1], "rolling": [None], "axle": [None], "mode": ["multiplier"], "shaft": ["V"],
    ...      "torque": [10.0], "speed": [None]}
    >>> op = operating(v, one=True)
    >>> float(op["sliding"]), op["mode"], bool(np.isnan(op["rolling"]))
    (0.1, 'multiplier', True)

    References
    ----------
    .. [1] docs/spec/pins.md §7 (the operating point's keys).
    """
    out = {}
    for name in OPERATING:
        vals = v[name]
        if one:
            out[name] = vals[0] if name in _WORDS else float64(vals[0])
        else:
            out[name] = list(vals) if name in _WORDS else floats(vals)
    return out


def friction_models(models, aliases, default: str) -> tuple[list, list]:
    """The friction model per point and the error of a contradicting alias.

    The friction model per point (:func:`gearcalc.pins.checks.friction_model`; "consistent" where the alias
    contradicts it) and per point None or the DesignError of that contradiction.

    Parameters
    ----------
    models : list of str or None
        "consistent", "first-order" or None per point.
    aliases : list of bool or None
        The alias per point.
    default : str
        The model of a point that names none.

    Returns
    -------
    names : list of str
        The model per point.
    errors : list
        Per point None or the DesignError of a contradiction.

    Examples
    --------
    >>> names, errors = friction_models([None, "first-order"], [None, True], "consistent")
    >>> names, errors[0], type(errors[1]).__name__
    (['consistent', 'consistent'], None, 'DesignError')

    References
    ----------
    .. [1] docs/spec/pins.md §4.9, §7.
    """
    out, errors = [], []
    for m, a in zip(models, aliases):
        name, contradiction = friction_model(m, a, default)
        out.append("consistent" if contradiction else name)
        errors.append(R.friction_alias_error(m, a) if contradiction else None)
    return out, errors


def formula_columns(v) -> dict:
    r"""The paper's eqs. (3)-(7) over designs or points (pins.md §3, :func:`~gearcalc.pins.formula.formula_losses`).

    .. math:: F_{tr1} = \frac{f_k F_n}{R}, \quad F_{tr2} = f_c F_n, \quad P_{tr} = (F_{tr1} R + F_{tr2} r)\,
        \frac{\pi n_{pin}}{30} \cdot 10^{-3}

    Columns of :data:`~gearcalc.pins.report.FORMULA_KEYS` (None without a per-pin load; P_tr_fixed_W needs f).

    Parameters
    ----------
    v : dict
        The points' values: force, pin_speed, load_pin_radius, load_axle_radius, rolling, axle, paper_pi, sliding.

    Returns
    -------
    columns : dict
        F_tr1_N, F_tr2_N [N], P_tr1_W, P_tr2_W, P_tr_W, P_tr_fixed_W [W], lists over the points.

    Examples
    --------
    >>> v = {"force": [1920.0], "pin_speed": [14.0], "load_pin_radius": [1.95], "load_axle_radius": [0.95],
    ...      "rolling": [0.01], "axle": [0.1], "paper_pi": [True], "sliding": [None]}
    >>> round(formula_columns(v)["P_tr_W"][0], 3)   # the paper's cycloidal u = 10 case (Fig. 8): 0.295 W
    0.295

    References
    ----------
    .. [1] A. P. Prudnikov, «Потери мощности в контакте цевок и зубьев планетарной передачи типа K-H-V» (Power losses in
       pins and teeth contact area of KHV-type planetary gearing), Машиностроение (seed file 000_fe288dec6e7c72f0.txt);
       eqs. (3)-(7); docs/spec/pins.md §3.
    """
    res = formula_losses(floats(v["force"]), floats(v["pin_speed"]), floats(v["load_pin_radius"]),
                         floats(v["load_axle_radius"]), floats(v["rolling"]), floats(v["axle"]),
                         paper_pi=np.array([bool(x) for x in v["paper_pi"]]), sliding_friction=floats(v["sliding"]))
    return {k: R.column(x) for k, x in zip(R.FORMULA_KEYS, (res.F_tr1, res.F_tr2, res.P_tr1, res.P_tr2, res.P_tr,
                                                            res.P_tr_fixed))}


class IdealColumns:
    """The ideal level over designs or points (:func:`ideal_columns`).

    columns : summary fields (plain Python lists over points; None: undefined);
    errors : per point, None or the DesignError ``compute`` raises for it (inadmissible, over budget, a loss
    ratio that overflows, a friction model contradicting its alias);
    warnings : per point, the geometry's warnings;
    detail(i) : the detail tables of point i (pins.md §8), built on demand.
    """

    def __init__(self, **kw):
        self.__dict__.update(kw)

    def detail(self, i: int) -> dict:
        """The detail tables of point ``i`` (pins.md §8), built on demand."""
        from .detail import ideal_detail
        from .outputs import satellite_torque

        k, cyc, n_d, consistent = int(self.gi[i]), self.cyc, int(self.n_d[i]), self.models[i] == "consistent"
        g = Cycloid(int(self.z1[i]), int(self.z2[i]), float(self.e[i]), float(self.Rp[i]), float(self.Rb[i]),
                    float(self.omk[i]))
        T_sat = float(self.T_sat[i]) if self.columns["pin_force_max_N"][i] is not None else None
        w_V = float(self.w_V[i]) if not math.isnan(self.speed[i]) else None
        sigma = MULTIPLIER if self.mode[i] == "multiplier" else REDUCER
        T_V = self.columns["torque_in_Nm" if sigma == MULTIPLIER else "torque_out_Nm"][i]
        if consistent and T_sat is not None:     # the friction-consistent efficiency's T_V (None: self-locking)
            T_sat = None if T_V is None else satellite_torque(T_V, n_d)
        load = SatelliteLoad(T_sat, None if w_V is None else -w_V)
        friction = PinFriction(float(self.mu[i]), float(self.f[i]), bool(self.rolls[i]))
        return ideal_detail(g, float(cyc.psi_star[k]), cyc.grid(k), friction, load, n_d, sigma, consistent)


def _gears(v, one: bool) -> Gears:
    """The gears of the points (scalars for one point, else arrays), with the face width and the bearing exponent."""
    absent = [None] * len(v["z1"])            # callers without [bearing] keys (tests, the API's own dicts)
    p = floats(v.get("bearing_p", absent))
    p = np.where(np.isnan(p), 10.0 / 3.0, p)     # ISO 281: roller bearings
    if one:
        e, Rb, K1, Rp, r, b = (float64(v[name][0]) for name in ("e", "Rb", "K1", "Rp", "r", "face_width"))
        return Gears(v["z1"][0], v["z2"][0], e, Rb, K1, Rp, v["n_d"][0], bool(v["rotating"][0]), r, b,
                     float(p.reshape(-1)[0]))
    z1, z2, n_d = (np.array(v[name], dtype=np.int64) for name in ("z1", "z2", "n_d"))
    e, Rb, K1, Rp, r, b = (floats(v[name]) for name in ("e", "Rb", "K1", "Rp", "r", "face_width"))
    return Gears(z1, z2, e, Rb, K1, Rp, n_d, np.array([bool(x) for x in v["rotating"]]), r, b, p)


def _law_coefficients(v, n: int, op: dict, one: bool):
    """The teeth's power-weighted mean coefficient per point for a speed-dependent law (pins.md §4.10).

    Put in ``op["sliding"]`` where the law applies; (mu-bar per point (NaN: Coulomb), the law's DesignError per
    point).
    """
    from ..calculator import DesignError
    from .geometry import crest_cutoff
    from .output_keys import LAW_ARGS, law_problem
    from .speed_friction import power_weighted_coefficient, satellite_speed, sliding_law

    mu_bar, errs, seen = np.full(n, np.nan), [None] * n, {}
    for i in range(n):
        a = {name: v[name][i] for name in (*LAW_ARGS, "rotating", "speed")}
        if (a["f_law"] or "coulomb") == "coulomb":
            continue
        problem = law_problem(a, "ideal")
        if problem:
            errs[i] = DesignError(*problem)
            continue
        z1, z2, e, Rb, K1, Rp = (v[name][i] for name in ("z1", "z2", "e", "Rb", "K1", "Rp"))
        key = (z1, z2, e, Rb, K1, Rp, a["speed"], *(repr(a[name]) for name in LAW_ARGS))
        if key not in seen:
            try:
                g = Cycloid.from_curtate_ratio(z1, z2, e, K1, Rb) if K1 is not None else \
                    Cycloid.from_pin_circle(z1, z2, e, Rp, Rb)
                seen[key] = power_weighted_coefficient(sliding_law(a), g, crest_cutoff(g),
                                                       satellite_speed(z1, z2, a["speed"]))
            except (ValueError, ArithmeticError):       # an inadmissible gear: said by the level's own checks
                seen[key] = np.nan
        mu_bar[i] = seen[key]
    if one:
        if mu_bar[0] == mu_bar[0]:
            op["sliding"] = np.float64(mu_bar[0])
    else:
        op["sliding"] = np.where(np.isnan(mu_bar), op["sliding"], mu_bar)
    return mu_bar, errs


def _output_errors(v, n: int, pts, errors: list) -> None:
    """The output mechanism's and the drag's problems per point (:func:`gearcalc.pins.output_keys.output_problem`)."""
    from ..calculator import DesignError
    from .output_keys import OUTPUT_ARGS, output_problem

    Rp = np.zeros(n) + np.asarray(pts.Rp, dtype=float)
    for i in range(n):
        if errors[i] is None:
            a = {name: v[name][i] for name in (*OUTPUT_ARGS, "e", "Rb", "mode", "shaft", "torque")}
            problem = output_problem(a, "ideal", float(Rp[i]))
            errors[i] = DesignError(*problem) if problem else None


def ideal_columns(v, n: int, tol: float, models: list, model_errors: list) -> IdealColumns:
    r"""The ideal level (pins.md §4) of n designs or sweep points, numpy over them.

    .. math:: \bar\lambda = \mu_{eff}\,\bar\lambda_1, \qquad \eta_{VH} = 1 - \bar\lambda, \qquad
        \eta_{HV} = \frac{1}{1 + \bar\lambda} \ \text{(first-order; the friction-consistent model of pins.md §4.9
        by default)}

    The distinct geometries are solved once each, together (:func:`~gearcalc.pins.points.ideal_points`, unit
    scalings); every point then scales its geometry's solution by its friction, torque, speed and mode.  One
    point (a design computed alone) runs the same formulas on scalars (``SCALAR_OPS``): the same numbers, bit
    for bit, without the cost of numpy calls on arrays of one element.  ``models``, ``model_errors``:
    :func:`friction_models` of the points.

    Parameters
    ----------
    v : dict
        The points' values by name (gear, operating point, face width).
    n : int
        The number of points.
    tol : float
        Relative accuracy target, [-].
    models : list of str
        The friction model per point.
    model_errors : list
        Per point None or the DesignError of a contradicting alias.

    Returns
    -------
    ideal : IdealColumns
        The summary columns, the errors and warnings per point, and the detail tables on demand.

    Examples
    --------
    >>> v = dict(z1=[20], z2=[22], e=[3.9], Rp=[None], K1=[0.75], Rb=[1.95], r=[None], rotating=[False], n_d=[1],
    ...          sliding=[0.1], rolling=[None], axle=[None], mode=["multiplier"], shaft=["V"], torque=[10.0],
    ...          speed=[None], face_width=[None])
    >>> round(ideal_columns(v, 1, 1e-6, ["consistent"], [None]).columns["efficiency"][0], 5)   # paper cyc u10, fixed
    0.87363

    References
    ----------
    .. [1] A. P. Prudnikov, «Потери мощности в контакте цевок и зубьев планетарной передачи типа K-H-V» (Power losses in
       pins and teeth contact area of KHV-type planetary gearing), Машиностроение (seed file 000_fe288dec6e7c72f0.txt);
       docs/spec/pins.md §4, §4.9, §8, §10.
    """
    one = n == 1
    gears, op = _gears(v, one), operating(v, one)
    mu_bar, law_errors = None, None
    if any(x not in (None, "coulomb") for x in v.get("f_law", ())):   # a speed-dependent law (pins.md §4.10)
        mu_bar, law_errors = _law_coefficients(v, n, op, one)
    # consistent designs of one disc need no friction-free peaks (pins.md §4.9 has its own)
    alone = bool(np.all(np.asarray(gears.n_d) == 1)
                 and all(m == "consistent" and err is None for m, err in zip(models, model_errors)))
    pts = ideal_points(gears, FrictionCoefficients(op["sliding"], op["rolling"], op["axle"]),
                       OperatingPoint(op["torque"], op["speed"], words_equal(op["mode"], "multiplier", one),
                                      words_equal(op["shaft"], "V", one)),
                       np.array([m == "consistent" for m in models]), tol=tol, xp=SCALAR_OPS if one else ARRAY_OPS,
                       first_order_peaks=not alone)
    errors, warnings = _admissibility(pts, n, tol)
    for more in (model_errors, law_errors or [None] * n):
        errors = [err if err is not None else m_err for err, m_err in zip(errors, more)]
    arrays = _ideal_fields(pts)
    if any(m not in (None, "ideal") for m in v.get("w_mech", ())) or any(d for d in v.get("drag", ())):
        _output_errors(v, n, pts, errors)      # the output mechanism and the crank's drag (pins.md §4.10)
    arrays = output_fields(arrays, v, pts, n)
    mu_col = np.full(n, np.nan) if mu_bar is None else mu_bar
    arrays["sliding_friction_mean"] = mu_col[0] if one else mu_col
    for i in np.flatnonzero(pts.multi_disc):
        warnings[i].append(R.MULTI_DISC_PEAKS)
    columns = R.ideal_columns(arrays, op["mode"], gears.rotating, pts.rolls, models, n)
    columns.update(w_bearing_columns(_bearing_columns(pts, gears.p, floats(v.get("bearing_C", [None] * n)),
                                                      op["speed"], n), arrays, n))   # with |B + Q x| (pins.md §8.2)
    _overflow_errors(columns, arrays, errors, v, n)
    kept = dict(z1=gears.z1, z2=gears.z2, e=gears.e, Rp=pts.Rp, Rb=gears.Rb, omk=pts.omk, n_d=gears.n_d, mu=pts.mu,
                f=op["sliding"], rolls=pts.rolls, T_sat=pts.sc.torque_sat, w_V=pts.sc.omega_V, speed=op["speed"],
                mode=op["mode"])
    if one:
        kept = {name: [x] for name, x in kept.items()}
    return IdealColumns(columns=columns, errors=errors, warnings=warnings, cyc=pts.cyc, gi=pts.gi, models=models,
                        **kept)


def _admissibility(pts, n: int, tol: float) -> tuple[list, list]:
    """Per point the DesignError of an inadmissible gear (pins.md §4.2, §12.10) and the warning of §4.5.

    The messages of check() (:func:`gearcalc.pins.checks.ideal_admissibility`), and of a gear over the work budget
    (known after the quadrature only: not in check()); (errors, warnings) over the points.
    """
    errors: list = [None] * n
    warnings: list[list[str]] = [[] for _ in range(n)]
    status, psi_0, Rp, omk, Rb, cyc, gi = pts.status, pts.psi_0, pts.Rp, pts.omk, pts.Rb, pts.cyc, pts.gi
    at = (lambda arr, i: arr) if pts.one else (lambda arr, i: arr[i])
    bad = ([0] if status != 0 else []) if pts.one else np.flatnonzero(status != 0)
    for i in bad:
        if at(status, i) == TOO_COSTLY:
            errors[i] = R.too_costly_error(int(at(pts.n_d, i)), int(at(pts.field("n_crank"), i)), tol,
                                           DISC_SAMPLES_MAX, DISC_WORK_MAX)
            continue
        errors[i] = R.admissibility_error(int(at(status, i)), int(at(pts.z1, i)), int(at(pts.z2, i)),
                                          float(at(pts.psi_star, i)), float(at(Rb, i)), float(cyc.rho_c_min[gi[i]]),
                                          float(at(pts.K1, i)))
    inside = (status == 0) & (Rb >= Rp * omk)
    for i in ([0] if inside else []) if pts.one else np.flatnonzero(inside):
        p0 = None if np.isnan(at(psi_0, i)) else float(at(psi_0, i))
        warnings[i].append(R.pitch_point_inside(at(Rb, i), at(Rp, i) * at(omk, i), p0))
    return errors, warnings


def _overflow_errors(columns: dict, arrays: dict, errors: list, v, n: int) -> None:
    """The DesignError of a loss ratio that overflowed floating point (K1 ~ 1e-300 and below: refused, not exit 70).

    Put in ``errors`` at the points without an error and without a loss ratio that do not self-lock, or that
    self-lock with an infinite field: a jammed mode of the friction-consistent model has no loss ratio, but its
    speeds and losses (they grow as 1/K1) may have overflowed; found only for such points (a pass over the fields).
    """
    overflow = None
    for i, (lam, locked) in enumerate(zip(columns["loss_ratio"], columns["self_locking"])):
        if errors[i] is not None or lam is not None:
            continue
        if locked and overflow is None:
            overflow = np.zeros(n, dtype=bool)
            for a in arrays.values():
                x = np.asarray(a)
                if x.dtype.kind == "f" and x.shape in ((), (n,)):
                    overflow |= np.isinf(x)
        if not locked or overflow[i]:
            given = v["K1"][i] is not None
            errors[i] = R.loss_ratio_overflow(given, v["K1" if given else "Rp"][i])


def level_columns(v, level: str, names: list, tol: float, pin_load: bool, default_model: str):
    r"""Every summary field over the points of one level, and the ideal level's columns.

    .. math:: \eta_{VH} = 1 - \bar\lambda, \qquad \eta_{HV} = \frac{1}{1 + \bar\lambda}

    Every summary field (:data:`~gearcalc.pins.schema.SUMMARY_KEYS`, in order) over the points of one level,
    "formula" or "ideal", and the :class:`IdealColumns` (None at the other levels; at the contact level only the
    names, the level and the formula's columns, which :mod:`gearcalc.pins.contact_level` completes).

    ``v``: the points' values by name; ``names``: their names; ``pin_load``: some point has a per-pin load (the
    formula's columns, :func:`formula_columns`); ``default_model``: the friction model of a point that names
    none (:func:`friction_models`).  None where a field is not computed; the formula level is the paper's
    rotating-pin loss.

    Parameters
    ----------
    v : dict
        The points' values by name.
    level : str
        "formula", "ideal" or "contact".
    names : list of str
        The points' names.
    tol : float
        Relative accuracy target, [-].
    pin_load : bool
        Some point has a per-pin load.
    default_model : str
        The friction model of a point that names none.

    Returns
    -------
    columns : dict
        Every summary field, lists over the points.
    ideal : IdealColumns or None
        The ideal level's columns.

    Examples
    --------
    >>> v = dict(z1=[20], z2=[22], e=[3.9], Rp=[None], K1=[0.75], Rb=[1.95], r=[None], rotating=[False], n_d=[1],
    ...          sliding=[0.1], rolling=[None], axle=[None], mode=["multiplier"], shaft=["V"], torque=[10.0],
    ...          speed=[None], face_width=[None], model=[None], alias=[None])
    >>> cols, ideal = level_columns(v, "ideal", ["cyc_u10"], 1e-6, False, "consistent")
    >>> round(cols["efficiency_multiplier"][0], 5), round(cols["efficiency_reducer"][0], 5)
    (0.87363, 0.86061)

    References
    ----------
    .. [1] A. P. Prudnikov, «Потери мощности в контакте цевок и зубьев планетарной передачи типа K-H-V» (Power losses in
       pins and teeth contact area of KHV-type planetary gearing), Машиностроение (seed file 000_fe288dec6e7c72f0.txt);
       docs/spec/pins.md §3, §4, §8.
    """
    n = len(names)
    out = {key: [None] * n for key in SUMMARY_KEYS}
    ideal = None
    if level == "ideal":
        models, errors = friction_models(v["model"], v["alias"], default_model)
        ideal = ideal_columns(v, n, tol, models, errors)
        out.update(ideal.columns)
    out["name"], out["model"] = names, [level] * n
    if level == "formula":
        out["rotating_pins"] = [True] * n        # eqs. (3)-(7) are the paper's rotating-pin losses
    if pin_load:
        out.update(formula_columns(v))
    out.update(margin_columns(out, v))
    return {key: out[key] for key in SUMMARY_KEYS}, ideal


def _ideal_fields(pts) -> dict:
    """The ideal level's summary fields (pins.md §8) from :class:`gearcalc.pins.points.IdealPoints`.

    Per field an array over the points, or the one point's value (NaN: undefined).  The friction-consistent
    values (:data:`gearcalc.pins.report.CONSISTENT_FIELDS`) replace the first-order ones at the points of that
    model (the per-pin peaks only with one disc; with several, the friction-free peaks are scaled to the
    friction-consistent torque).
    """
    one, et, sc, xp = pts.one, pts.et, pts.sc, (SCALAR_OPS if pts.one else ARRAY_OPS)
    field = pts.field
    arrays = {
        "efficiency": et.efficiency, "efficiency_err": et.efficiency_err, "self_locking": et.self_locking,
        "efficiency_multiplier": et.eta_vh, "efficiency_multiplier_err": et.eta_vh_err,
        "efficiency_reducer": et.eta_hv, "efficiency_reducer_err": et.eta_hv_err, "loss_ratio": pts.lam,
        "loss_ratio_err": pts.E, "torque_in_Nm": et.torque_in, "torque_out_Nm": et.torque_out,
        "loss_mean_W": sc.loss_mean, "loss_peak_W": sc.loss_peak,
        "pin_force_max_N": sc.force_max, "pin_loss_max_W": sc.loss_max, "pin_loss_bound_W": sc.loss_bound,
        "pin_speed_max_rpm": sc.spin_abs_max, "pin_speed_signed_min_rpm": sc.spin_min,
        "pin_speed_signed_max_rpm": sc.spin_max, "spin_reversals": sc.spin_reversals,
        "sliding_speed_max_m_s": sc.sliding_speed_max,
        "ratio": pts.z1 / pts.k, "curtate_ratio": pts.K1, "loaded_pins_min": field("loaded_min"),
        "loaded_pins_max": field("loaded_max"), "psi_star_deg": xp.degrees(pts.psi_star),
        "n_crank": field("n_crank"), "tolerance_met": field("converged"),
        "pin_force_max_phase_deg": sc.force_phase, "pin_loss_max_phase_deg": sc.loss_phase,
    }
    p, n = pts.consistent, np.size(pts.cons)
    if p is None:                                 # no admissible point
        ext = {key: (math.nan if one else np.full(n, np.nan)) for key, _ in R.OUTPUT_KEYS}
    else:
        ext = {key: getattr(p, name) for key, name in R.CONSISTENT_FIELDS}
    warn_nd = pts.multi_disc
    if np.any(warn_nd):          # several discs: the friction-free peaks, at the friction-consistent torque
        scale = p.torque_scale
        for key in ("pin_force_max_N", "pin_loss_max_W", "loss_peak_W", "pin_loss_bound_W"):
            arrays[key] = arrays[key] * scale if one else np.where(warn_nd, arrays[key] * scale, arrays[key])
    for key, v in ext.items():
        if key in arrays:       # the friction-consistent values replace the first-order ones (pins.md §4.9)
            m_ = pts.peaks if key in R.PEAK_KEYS else pts.cons
            arrays[key] = ((v if m_[0] else arrays[key]) if one else np.where(m_, v, arrays[key]))
        else:
            arrays[key] = v
    return arrays


def _bearing_columns(pts, exponent, rating, speed, n: int) -> dict:
    """The crank bearing's equivalent load and L10_h over the n points of the ideal level (pins.md §8.2).

    :func:`gearcalc.pins.outputs.bearing_life` of the points ``pts`` as summary columns (None: undefined; L10_h needs
    bearing.C_N and the crank speed).
    """
    from .outputs import bearing_life

    p = pts.consistent
    if p is None or p.bearing_pmean is None:
        return {k: [None] * n for k in R.BEARING_KEYS}
    vals = bearing_life(p.bearing_pmean, p.bearing_pmean_err, exponent, p.torque_sat, rating, speed)
    out = {}
    for key, v in zip(R.BEARING_KEYS, vals):
        v = np.broadcast_to(np.asarray(v, dtype=float), (n,))
        out[key] = [x if math.isfinite(x) else None for x in v.tolist()]
    return out
