"""``gearcalc accuracy``: speed against error, per calculator, model level and tolerance.

Every design of the shipped suite (``gearcalc/data/accuracy/<kind>_{typical,hard}_*.toml``) is
computed at every model level that applies to it and at every requested ``--tol``.  For each run the
report gives

* the time per design (in process, after a warm-up call, median of repeated calls);
* the **error**: the difference from an independent high-resolution computation of the *same* level
  (rows: exact rational arithmetic for the stepwise recurrence, 50-digit decimal arithmetic for the
  exact and continuous levels; zstk and pins: the same level refined to ``HIGH_TOL``), relative to
  the value;
* the **estimated error**: what the tool itself states for that value (``sigma_max_err_MPa``,
  ``efficiency_err``, or the rounding bound of a closed form), relative;
* their **ratio**; the estimate is *honest* when ``error <= estimate + estimate of the
  high-resolution run``;
* the **model error**: the difference from the calculator's reference model (rows: the exact
  level; zstk: the ``reference`` level; pins: the contact level with a stiff linear law for
  cycloidal designs), which is what choosing a cheaper level costs;
* the **model sensitivity** (pins, ideal and contact levels): the change of the value under the other friction model
  (friction-consistent against first-order, pins.md §4.9), relative: what the model assumption costs.

The quantity compared is the calculator's headline result: rows ``K``, zstk ``sigma_max_MPa``,
pins ``efficiency``.  This module is the orchestration only; the physics stays in the calculators.
"""
from __future__ import annotations

import statistics
import time
from dataclasses import dataclass, replace
from decimal import Decimal, localcontext
from fractions import Fraction
from pathlib import Path
from typing import Any, Callable

from . import registry
from .calculator import DesignError, Options
from .design import InputError

SUITE = Path(__file__).parent / "data" / "accuracy"
TOLS = (1e-3, 1e-6, 1e-9)
HIGH_TOL = 1e-12
"""Tolerance of the high-resolution runs of the adaptive levels (zstk sweeps, pins ideal)."""
HIGH_TOL_CONTACT = 1e-9
"""Tolerance of the pins reference model's run (the contact level with a stiff linear law)."""
HIGH_TOL_CONTACT_CHECK = 1e-11
"""The pins contact level's independent high-resolution run: 100x tighter than the report's tightest tol (1e-9),
with the cycle mean by the Gauss-Kronrod pair ``HIGH_RULE_CONTACT`` instead of the level's own rule (the
trapezoid at tol >= 3e-7, gk7 below, pins.md §6).  Formerly the level at tol 1e-9 itself: at tol 1e-9 the error
was 0 by construction."""
HIGH_RULE_CONTACT = "gk15"
EPS = 2.220446049250313e-16
TIME_BUDGET = 0.05
"""Seconds of repeated calls per (design, level, tol) after the warm-up (at least one call)."""


@dataclass(frozen=True)
class KindSpec:
    """What the report compares for one calculator."""

    quantity: str
    """The summary field compared (``quantities`` may name another one for some levels)."""
    reference: str
    high_res: str
    estimate: Callable[[dict, str], float]
    """Absolute error the tool states for the quantity, from the summary and the level that ran."""
    high_value: Callable[[Any, dict, str, float], tuple[float, float] | None]
    """(value, its estimated absolute error) of the independent high-resolution computation
    (None for a closed form with nothing to refine)."""
    reference_value: Callable[[Any, dict], float | None]
    """The reference model's value for the design (None where it does not apply)."""
    quantities: tuple[tuple[str, str], ...] = ()
    """(level, field) pairs where a level reports another headline result."""
    sensitivity: Callable[[Any, dict, str], float | None] | None = None
    """The quantity's change under the calculator's alternative model assumption (pins: the friction model,
    friction-consistent against first-order, pins.md §4.9), relative; None where it does not apply."""

    def quantity_of(self, level: str) -> str:
        return dict(self.quantities).get(level, self.quantity)


# ----------------------------------------------------------------------------- rows
def rows_stepwise_k_rational(kappa: float, cheek_ratio: float, rows: int) -> Fraction:
    """K of the stepwise recurrence (rows.md §2.5) in exact rational arithmetic.

    The float inputs are converted exactly; ``v_n = 1``, ``v_N = v_{N+1} + ρ Σ_{k>N} v_k``,
    ``ρ = κ(1+b̄)/(1-κ/8)``, ``u = n v / Σ v``; no rounding at all.

    >>> float(rows_stepwise_k_rational(0.0, 0.25, 3))
    1.0
    """
    k, b = Fraction(kappa), Fraction(cheek_ratio)
    rho = k * (1 + b) / (1 - k / 8)
    v, tail = [Fraction(1)], Fraction(1)
    for _ in range(rows - 1):
        nxt = v[-1] + rho * tail
        v.append(nxt)
        tail += nxt
    return rows * max(v) / tail


def rows_exact_k_decimal(kappa: float, cheek_ratio: float, rows: int, digits: int = 50) -> Decimal:
    """K of the exact (piecewise hyperbolic) level in ``digits``-digit decimal arithmetic.

    The same impedance sweep as :func:`gearcalc.rows.exact_shares` (rows.md §3b), with every
    hyperbolic function from ``Decimal.exp``: an independent high-precision evaluation.

    >>> round(float(rows_exact_k_decimal(1.0, 0.0, 3)), 6)   # 3 (1 - sinh 2 / sinh 3), rows.md §11
    1.913883
    """
    with localcontext() as ctx:
        ctx.prec = digits
        if kappa == 0.0:
            return Decimal(1)
        mu = Decimal(kappa).sqrt()
        b = Decimal(cheek_ratio)
        em2 = (-2 * mu).exp()
        tau = (1 - em2) / (1 + em2)
        sech = 2 * (-mu).exp() / (1 + em2)
        s = 1 - sech
        r_in, r_out, ro = [Decimal(0)] * rows, [Decimal(0)] * rows, Decimal(0)
        for j in range(rows - 1, -1, -1):
            r_out[j] = ro
            ri = (ro + tau) / (1 + ro * tau)
            r_in[j] = ri
            ro = ri / (1 + b * mu * ri)
        th = 1 / r_in[0]
        means = []
        for j in range(rows):
            ro = r_out[j]
            denom = 1 + ro * tau
            means.append(th * (tau + ro * s) / (mu * denom))
            if j + 1 < rows:
                th = th * sech / denom * ro / r_in[j + 1]
        return max(means) * rows / sum(means)


def rows_continuous_k_decimal(kappa: float, cheek_ratio: float, rows: int, digits: int = 50) -> Decimal:
    """K = X coth X of the continuous level (rows.md §3c) in decimal arithmetic.

    >>> round(float(rows_continuous_k_decimal(1.0, 0.0, 3)), 6)   # 3 coth 3
    3.014909
    """
    with localcontext() as ctx:
        ctx.prec = digits
        k, b = Decimal(kappa), Decimal(cheek_ratio)
        if rows == 1:  # one row carries the whole load (rows.md §4)
            return Decimal(1)
        x = (k / (1 + b)).sqrt() * (rows + b * (rows - 1))
        if x == 0:
            return Decimal(1)
        e2 = (-2 * x).exp()
        return x * (1 + e2) / (1 - e2)


ROWS_ROUNDING = 64
"""The rows levels are closed forms; their stated error is ``ROWS_ROUNDING · n · ε · K`` (rounding)."""


def _rows_estimate(s: dict, level: str) -> float:
    return ROWS_ROUNDING * s["rows"] * EPS * s["K"]


def _rows_high(design, s: dict, level: str, tol: float) -> tuple[float, float]:
    kappa, bbar, n = s["kappa"], s["cheek_ratio"], s["rows"]
    if level == "stepwise":
        return float(rows_stepwise_k_rational(kappa, bbar, n)), 0.0
    if level == "exact":
        return float(rows_exact_k_decimal(kappa, bbar, n)), 0.0
    return float(rows_continuous_k_decimal(kappa, bbar, n)), 0.0


def _rows_reference(design, s: dict) -> float:
    return float(rows_exact_k_decimal(s["kappa"], s["cheek_ratio"], s["rows"]))


# ----------------------------------------------------------------------------- zstk
ZSTK_ROUNDING = 1e-12
"""zstk.md §8: the closed-form parts are accurate to round-off, about 1e-12 relative."""


def _zstk_estimate(s: dict, level: str) -> float:
    return (s.get("sigma_max_err_MPa") or 0.0) + ZSTK_ROUNDING * abs(s["sigma_max_MPa"])


def _rerun(design, level: str, tol: float, settings=None) -> dict:
    return registry.get(design.kind).compute(design, Options(tol=tol, model=level, settings=settings)).summary


def _zstk_high(design, s: dict, level: str, tol: float) -> tuple[float, float]:
    # the reference level refines to 1e-12 whatever the tol (zstk.md §8): against itself at HIGH_TOL its error was 0
    # by construction; the equilibrium level (the same model, 8x coarser grids) at HIGH_TOL is independent of it
    other = "equilibrium" if level == "reference" else level
    hs = _rerun(design, other, HIGH_TOL)
    return hs["sigma_max_MPa"], _zstk_estimate(hs, other)


def _zstk_reference(design, s: dict) -> float:
    return _rerun(design, "reference", HIGH_TOL)["sigma_max_MPa"]


# ----------------------------------------------------------------------------- pins
PINS_FLOOR = 1e-14
"""pins.md §6: the cycle integrals are accepted at E <= max(tol·λ, 1e-14)."""
PINS_STIFF = 1e9
"""Linear contact stiffness of the pins reference model [N/mm] (pins.md §6: a stiff linear law)."""


def _pins_estimate(s: dict, level: str) -> float:
    if level == "formula":
        return 0.0
    return (s.get("efficiency_err") or 0.0) + PINS_FLOOR


def _pins_high(design, s: dict, level: str, tol: float) -> tuple[float, float] | None:
    if level == "formula":
        return None  # a closed form of the given peak values: nothing to refine
    if level == "contact":
        from .pins.contact_settings import DEFAULT_SETTINGS

        # a rule no tol of the report uses, passed explicitly (ContactSettings.rule)
        hs = _rerun(design, level, HIGH_TOL_CONTACT_CHECK, replace(DEFAULT_SETTINGS, rule=HIGH_RULE_CONTACT))
    else:
        hs = _rerun(design, level, HIGH_TOL)
    return hs["efficiency"], _pins_estimate(hs, level)


def _pins_sensitivity(design, s: dict, level: str) -> float | None:
    """(eta - eta_other)/eta: the efficiency under the design's friction model against the other one
    (friction-consistent, pins.md §4.9, against first-order, §4.6-4.7) at the same level (ideal or contact), both at
    tol 1e-6 whatever the row's tolerance (a property of the design, computed once: two runs per design; a contact
    run takes 20-100 ms since issue 15)."""
    from .design import validate
    from .kinds.pins import friction_model

    if level not in ("ideal", "contact") or s.get("efficiency") is None:
        return None
    own = friction_model(design)
    eta = {}
    for model in (own, "first-order" if own == "consistent" else "consistent"):
        raw = design.resolved()
        raw.setdefault("friction", {})["model"] = model
        raw.get("contact", {}).pop("friction_in_equilibrium", None)
        eta[model] = registry.get("pins").compute(validate(raw, design.source),
                                                  Options(tol=1e-6, model=level)).summary["efficiency"]
    if None in eta.values():
        return None
    a, b = eta.values()
    return _rel(a - b, a)


def _pins_reference(design, s: dict) -> float | None:
    from .design import validate

    if design.get("gearing.profile") != "cycloidal":
        return None
    raw = design.resolved()
    raw["contact"] = {"law": "linear", "stiffness_N_per_mm": PINS_STIFF}
    stiff = validate(raw, design.source)
    return registry.get("pins").compute(stiff, Options(tol=HIGH_TOL_CONTACT, model="contact")).summary["efficiency"]


SPECS = {
    "rows": KindSpec("K", "the exact level (piecewise hyperbolic solution), 50-digit decimal arithmetic",
                     "stepwise: exact rational arithmetic; exact, continuous: 50-digit decimal arithmetic",
                     _rows_estimate, _rows_high, _rows_reference),
    "zstk": KindSpec("sigma_max_MPa", "the reference level (full equilibrium, stepped chain, 8x sweep grids) "
                     f"at tol {HIGH_TOL:g}", f"the same level at tol {HIGH_TOL:g} (reference: the equilibrium level, "
                     "whose 8x coarser grids it refines; itself at any tol is 1e-12)",
                     _zstk_estimate, _zstk_high, _zstk_reference),
    "pins": KindSpec("efficiency", f"the contact level with a stiff linear law ({PINS_STIFF:g} N/mm) at tol "
                     f"{HIGH_TOL_CONTACT:g} (cycloidal designs)",
                     f"the same level at tol {HIGH_TOL:g} (contact: at tol {HIGH_TOL_CONTACT_CHECK:g} with the "
                     f"{HIGH_RULE_CONTACT} rule, not its own)",
                     _pins_estimate, _pins_high, _pins_reference, quantities=(("formula", "P_tr_W"),),
                     sensitivity=_pins_sensitivity),
}


# ----------------------------------------------------------------------------- running
def suite(kind: str) -> list[tuple[str, str, Any]]:
    """(case name, "typical" | "hard", validated design) of the shipped suite of a kind."""
    from .design import load

    out = []
    for path in sorted(SUITE.glob(f"{kind}_*.toml")):
        tag = path.stem.split("_")[1]
        out.append((path.stem[len(kind) + 1:], tag, load(str(path))))
    return out


def time_call(fn: Callable[[], Any], budget: float = TIME_BUDGET, max_calls: int = 50) -> tuple[Any, float]:
    """(result of the first call, median seconds per call).

    The first call warms up (imports, caches); calls are then repeated until ``budget`` seconds are spent.
    A first call that alone takes longer than the budget is its own timing (a slow case is not warm-up
    dominated, and repeating it would double the report's time)."""
    t = time.perf_counter()
    first = fn()
    dt = time.perf_counter() - t
    if dt >= budget:
        return first, dt
    times: list[float] = []
    spent = 0.0
    while not times or (spent < budget and len(times) < max_calls):
        t = time.perf_counter()
        fn()
        dt = time.perf_counter() - t
        times.append(dt)
        spent += dt
    return first, statistics.median(times)


def _rel(x: float, ref: float) -> float:
    return abs(x) / abs(ref) if ref else abs(x)


def run_case(kind: str, case: str, tag: str, design, level: str, tol: float, budget: float = TIME_BUDGET,
             references: bool = True) -> dict:
    """One row of the detailed report: a design at one level and tolerance."""
    spec = SPECS[kind]
    calc = registry.get(kind)
    opts = Options(tol=tol, model=level)
    row: dict[str, Any] = {"kind": kind, "level": level, "tol": tol, "case": case, "tag": tag}
    try:
        res, seconds = time_call(lambda: calc.compute(design, opts), budget)
    except DesignError as exc:
        row.update(ran=None, note=f"n/a: {exc}"[:120])
        return row
    s = res.summary
    ran = s.get("model") or level
    value = s[spec.quantity_of(ran)]
    row.update(ran=ran, quantity=spec.quantity_of(ran), time_ms=seconds * 1e3, value=value)
    if ran != level:
        row["note"] = f"the {level} level does not apply: {ran} ran"
    if value is None:
        row["note"] = "no value at this level"
        return row
    high = _cached(("high", kind, case, ran), lambda: spec.high_value(design, s, ran, tol))
    if high is None:
        row["note"] = "closed form: rounding only, nothing to refine"
        return row
    est = spec.estimate(s, ran)
    hi, hi_est = high
    err = abs(value - hi)
    row.update(value_high=hi, error=_rel(err, hi), error_est=_rel(est, hi),
               ratio=(err / est) if est > 0 else (0.0 if err == 0 else None),
               honest=bool(err <= est + hi_est))
    ref = _cached(("reference", kind, case), lambda: _reference(kind, design)) if references else None
    row["model_error"] = None if ref is None else _rel(value - ref, ref)
    if spec.sensitivity is not None:   # the alternative model assumption's effect (pins: the friction model)
        row["model_sensitivity"] = _cached(("sensitivity", kind, case, ran), lambda: spec.sensitivity(design, s, ran))
    return row


_CACHE: dict[tuple, Any] = {}


def _cached(key: tuple, make: Callable[[], Any]) -> Any:
    """High-resolution values, references and sensitivities depend on the shipped design only, not on --tol:
    computed once per process."""
    if key not in _CACHE:
        _CACHE[key] = make()
    return _CACHE[key]


def _reference(kind: str, design) -> float | None:
    try:
        s = registry.get(kind).compute(design, Options(tol=1e-6)).summary
        return SPECS[kind].reference_value(design, s)
    except (DesignError, InputError):   # no reference for this design (e.g. past the contact level's cost bound)
        return None


def levels_for(kind: str) -> tuple[str, ...]:
    return registry.get(kind).models


def report(kinds: list[str], tols=TOLS, budget: float = TIME_BUDGET, progress=None, levels=None,
           cases=None, references: bool = True) -> list[dict]:
    """The detailed rows: every suite design of every kind at every level and tolerance.

    ``levels`` and ``cases`` (names without the kind prefix) restrict the report, and
    ``references=False`` skips the reference-model runs (for tests)."""
    rows = []
    for kind in kinds:
        cases_k = [c for c in suite(kind) if cases is None or c[0] in cases]
        for level in levels_for(kind):
            if levels is not None and level not in levels:
                continue
            for tol in tols:
                for case, tag, design in cases_k:
                    rows.append(run_case(kind, case, tag, design, level, tol, budget, references))
                    if progress:
                        progress(1)
    return rows


def summarise(rows: list[dict]) -> list[dict]:
    """One row per (kind, level, tol): median time, worst errors and ratios, honesty over the suite."""
    groups: dict[tuple, list[dict]] = {}
    for r in rows:
        groups.setdefault((r["kind"], r["level"], r["tol"]), []).append(r)
    out = []
    for (kind, level, tol), rs in groups.items():
        ran = [r for r in rs if r.get("time_ms") is not None]
        valued = [r for r in ran if r.get("error") is not None]
        ratios = [r["ratio"] for r in valued]
        models = [r["model_error"] for r in valued if r.get("model_error") is not None]
        sens = [r["model_sensitivity"] for r in valued if r.get("model_sensitivity") is not None]
        out.append({
            "kind": kind, "level": level, "tol": tol, "designs": len(ran), "not_applicable": len(rs) - len(ran),
            "time_ms_median": statistics.median(r["time_ms"] for r in ran) if ran else None,
            "time_ms_max": max(r["time_ms"] for r in ran) if ran else None,
            "error_max": max(r["error"] for r in valued) if valued else None,
            "error_est_max": max(r["error_est"] for r in valued) if valued else None,
            "ratio_max": None if not valued or any(x is None for x in ratios) else max(ratios),
            "honest": all(r["honest"] for r in valued) if valued else None,
            "model_error_max": max(models) if models else None,
            "model_sensitivity_max": max(sens) if sens else None,
            "reference": SPECS[kind].reference,
            "high_resolution": SPECS[kind].high_res,
        })
    return out
