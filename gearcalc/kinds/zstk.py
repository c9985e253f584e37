"""``gearcalc zstk``: closed rolling-body mechanism (eccentric ZSTK, leading inner ring).

Mapping only: the design keys (:mod:`gearcalc.zstk.schema`) to the arrays of :mod:`gearcalc.zstk.solve`
(validity, closure, placement, loads, the "cycle"/"envelope" sweeps), and its results
(:mod:`gearcalc.zstk.outputs`) to the summary fields, detail rows, warnings and failed checks of
:mod:`gearcalc.zstk.report`.  The numpy modules are imported inside the functions (this module stays light
for ``check``/``new``/``--help``).
Spec: zstk.md; source: Merko et al., seed 003_2d1da402cb0b8488.txt.
"""
from __future__ import annotations

from ..calculator import Calculator, Check, DesignError, InvalidPoints, Options, Result, keyed
from ..zstk import report as R
from ..zstk.schema import (B_OVER_RHO_LIMIT, DEFAULT_ALLOWABLE_MPA, HEADER, KEYS, MAX_ROLLERS, MODELS, SWEEP_WORK_MAX,
                           TABLE_FIELDS, TABLES)

DESIGN_KEYS = ("geometry.outer_raceway_radius_mm", "geometry.inner_raceway_radius_mm", "geometry.eccentricity_mm",
               "geometry.roller_gap_mm", "geometry.roller_length_mm", "geometry.rollers", "geometry.correct",
               "geometry.scheme", "geometry.separator", "load.radial_N", "load.direction_deg", "load.clearance_mm",
               "material.roller_E_MPa", "material.roller_poisson", "material.ring_E_MPa", "material.ring_poisson",
               "material.inner_ring_E_MPa", "material.inner_ring_poisson", "material.outer_ring_E_MPa",
               "material.outer_ring_poisson", "material.allowable_stress_MPa")
"""The key of each field of :class:`gearcalc.zstk.solve.Designs`, in its order."""


def check(design, problems) -> None:
    """Cross-key checks: raceways, eccentricity, gap, parity, N and the corrected geometry (spec §3.3, §9:
    :func:`gearcalc.zstk.check_designs`, the rules compute, batch and sweep use); the cost budget of the phase
    and direction sweeps (:func:`cost_problem`, at the default model)."""
    from ..engine import quiet_numpy

    with quiet_numpy():  # an overflow at an input's extreme (R_H = 1e-320) is a problem said below, not a warning
        p = _prepare(_design_columns([design]), 1)
    design.keep("zstk", _values(design), p)  # for its computation (_prepared): prepared once per run
    for key, msg in _problems(p, 0):
        problems.error(key, msg)
    if p.valid[0]:
        problem = cost_problem(design, int(p.n[0]), "equilibrium")
        if problem is not None:
            problems.error(*problem)


def _problems(p, k: int) -> list:
    """(dotted key, message) of each problem of design k of ``p`` (empty when it is valid)."""
    def at(v):
        return v[k] if isinstance(v, list) else v

    out = [] if p.separator[k] else [("geometry.separator", R.SEPARATOR_MESSAGE)]
    return out + [(KEYS[q], msg) for q, msg in p.validity.problems(k, at(p.designs.scheme), at(p.designs.rollers))]


def cost_problem(design, n: int, model: str):
    """(key, message) when the design's sweeps would exceed :data:`SWEEP_WORK_MAX`, else None (check and
    compute share it; check assumes the default model)."""
    from ..zstk import envelope

    cycle, envelope_ = design["geometry.scheme"] == "cycle", design["load.direction_deg"] == "envelope"
    work = envelope.sweep_work(n, cycle, envelope_, envelope.sweep_grid(model == "reference"))
    if work <= SWEEP_WORK_MAX:
        return None
    return "geometry.rollers", R.cost_message(design["geometry.rollers"], n, cycle, envelope_, model == "reference",
                                              work, SWEEP_WORK_MAX)


# Designs (of a batch, or the points of a sweep) are held column-wise: ``cols[dotted key]`` is one resolved
# value shared by every design or a list with one value per design (:class:`gearcalc.zstk.solve.Designs`).

def _design_columns(designs) -> dict:
    """The resolved values of validated designs, one list per dotted key."""
    return {f"{t.name}.{f.name}": [d.values[t.name][f.name] for d in designs] for t in TABLES for f in t.fields}


def _values(design) -> tuple:
    """The values :func:`_prepare` reads of a design (what its prepared arrays are made from)."""
    return tuple(_hashable(design[key]) for key in DESIGN_KEYS)


def _prepared(design):
    """One design prepared (:func:`_prepare`): the arrays its check prepared (:meth:`Design.keep`), else anew."""
    p = design.take("zstk", _values(design)) if hasattr(design, "take") else None
    return p if p is not None else _prepare(_design_columns([design]), 1)


def _prepare(cols: dict, size: int):
    from ..zstk import solve

    return solve.prepare(solve.Designs(*(cols[key] for key in DESIGN_KEYS)), size, MAX_ROLLERS, DEFAULT_ALLOWABLE_MPA)


def _solve_stack(p, idx, model: str, names, detail: bool, arrays: bool = False):
    """The summary columns (field -> list, in ``idx`` order) of the single-position designs ``idx`` of ``p``
    and, with ``detail``, per design [warnings, failed, rows]; ``names``: a list indexed like ``p``, or one.
    ``arrays`` (a sweep): a column of numbers or flags defined at every design may be a numpy array instead
    (:func:`gearcalc.zstk.report.summary_fields`)."""
    from ..zstk import solve

    parts = [(sub, _columns([names[i] for i in sub] if isinstance(names, list) else names, model, stack, detail,
                            arrays=arrays))
             for sub, stack in solve.solve_stack(p, idx, model == "fixed-direction", model == "reference")]
    if len(parts) == 1:
        return parts[0][1]
    back = solve.stack_order(idx, [sub for sub, _ in parts])
    cols = {key: _gather([out[0][key] for _, out in parts], back) for key in parts[0][1][0]}
    return cols, solve.gather([out[1] for _, out in parts], back) if detail else None


def _gather(parts, back):
    """:func:`gearcalc.zstk.solve.gather` of a column's parts; numpy parts of one dtype stay an array."""
    import numpy as np

    from ..zstk import solve

    if all(isinstance(v, np.ndarray) for v in parts) and len({v.dtype for v in parts}) == 1:
        return np.concatenate(parts)[back]
    return solve.gather([v.tolist() if isinstance(v, np.ndarray) else v for v in parts], back)


def _columns(names, model: str, stack, detail: bool, sweep=None, arrays: bool = False):
    """Summary columns of a solved stack and, with ``detail``, per design [warnings, failed, rows].  ``sweep``
    of a "cycle"/"envelope" design: its :class:`gearcalc.zstk.solve.Sweeping` and the grid's cap."""
    from ..zstk import outputs

    fixed = model == "fixed-direction"
    fields, notes, env, value, err, capacity = {}, [], None, None, None, None
    if sweep is not None:
        sw, cap = sweep
        fields, notes = R.sweep_fields(sw.placement, cap)
        env, capacity, value, err = sw.rows, sw.capacity, sw.value, sw.err
    out = outputs.stack_outputs(stack, fixed, value, err, None if env is None else env[0], capacity)
    cols = R.summary_fields(names, model, stack, out, fields, arrays)
    if not detail:
        return cols, None
    d = outputs.roller_detail(stack.state, stack.mats, stack.clearance, env, B_OVER_RHO_LIMIT)
    rows, n = R.detail_rows(d, out.separator), stack.state.radius.shape[1]
    return cols, [[*R.messages(g, stack, out, fixed, d.worst[g], notes), rows[g * n:(g + 1) * n]]
                  for g in range(len(out.passed))]


def _result(cols, extra, j: int, model: str) -> Result:
    warnings, failed, rows = extra[j]
    return Result(summary={k: v[j] for k, v in cols.items()}, detail={"rollers": rows}, warnings=warnings,
                  failed=failed, model=model)


def _invalid(p, k: int):
    """The DesignError of design k of ``p``, found invalid: its first problem."""
    return DesignError(*_problems(p, k)[0])


def compute(design, options: Options) -> Result:
    """Close the chain, place it, share the load, and check the Hertz stresses (spec zstk.md).

    A single-position design is a stack of one (:func:`_solve_stack`, the same code as ``batch`` and
    ``sweep``); "cycle" and "envelope" designs run their phase and direction sweeps first.
    """
    p = _prepared(design)
    if not p.valid[0]:
        raise _invalid(p, 0)
    model = options.model or "equilibrium"
    if p.cycle[0] or p.envelope[0]:
        return _compute_sweeping(design, p, options)
    cols, extra = _solve_stack(p, [0], model, [design.name], detail=True)
    return _result(cols, extra, 0, model)


def batch(designs, options: Options) -> list:
    """Many validated designs at once (numpy over designs): one Result (or exception) per design.

    The single-position designs are stacked by roller count N and solved together; "cycle" and
    "envelope" designs (phase and direction sweeps of their own) are computed one by one.
    Identical to :func:`compute` design by design.
    """
    import numpy as np

    model = options.model or "equilibrium"
    out: list = [None] * len(designs)
    if not designs:
        return out
    if len(designs) == 1:
        p = _prepared(designs[0])
    else:
        p = _prepare(_design_columns(designs), len(designs))
        sweeping = p.valid & (p.cycle | p.envelope)
        for k, d in enumerate(designs):  # a stacked design's own arrays are not needed: let them go
            if not sweeping[k] and hasattr(d, "take"):
                d.take("zstk", None)
    stack = np.flatnonzero(p.valid & ~p.cycle & ~p.envelope)
    for k in np.flatnonzero(~p.valid).tolist():
        out[k] = _invalid(p, k)
    for k in np.flatnonzero(p.valid & (p.cycle | p.envelope)).tolist():
        try:
            out[k] = _compute_sweeping(designs[k], p if len(designs) == 1 else _prepared(designs[k]), options)
        except Exception as exc:  # returned, not raised (the batch contract)
            out[k] = exc
    if stack.size:
        cols, extra = _solve_stack(p, stack, model, [d.name for d in designs], detail=True)
        for j, k in enumerate(stack.tolist()):
            out[k] = _result(cols, extra, j, model)
    return out


def sweep(base, raw, axes, points, options):
    """The summaries of a whole grid as columns (spec zstk.md §8: designs stacked by N).

    Every grid point is a design of its own (any key may vary, the roller count N included); the
    points are validated element-wise with the arithmetic of :func:`check` and solved in stacks of
    the same N, exactly as :func:`compute` would solve each.  Points that are not valid designs raise
    :class:`~gearcalc.calculator.InvalidPoints` with the message each point on its own gives (key and
    constraint); the sweep computes the others and gives these a row with the reason.  Grids with "cycle" or
    "envelope" points return None (evaluated point by point: each
    such point runs adaptive sweeps of its own).
    """
    import numpy as np

    from ..design import check_value
    from ..grid import Grid, Range

    size = len(points)
    cols = {f"{t.name}.{f.name}": base.values[t.name][f.name] for t in TABLES for f in t.fields}
    for key in axes:
        table, _, name = key.partition(".")
        field = next((t.field(name) for t in TABLES if t.name == table), None)
        if field is None:
            return None
        column = points.column(key) if isinstance(points, Grid) else [pt[key] for pt in points]
        if isinstance(axes[key], Range) and not axes[key].ints and isinstance(points, Grid):
            cols[key] = column  # floats: check_value(field, x)[0] is x itself for every float x
            continue
        resolved = {}  # the values of these points only (a chunk of a long axis costs the chunk, not the axis)
        for v in column:
            h = _hashable(v)
            if h not in resolved:
                resolved[h] = check_value(field, v)[0]
        cols[key] = [resolved[_hashable(v)] for v in column]
    p = _prepare(cols, size)
    if not np.all(p.valid):  # each invalid point's first problem (its row's error); the valid ones are computed
        raise InvalidPoints([None if ok else keyed(*_problems(p, k)[0]) for k, ok in enumerate(p.valid.tolist())])
    if np.any(p.cycle | p.envelope):
        return None
    return _solve_stack(p, np.arange(size), options.model or "equilibrium", base.name, detail=False, arrays=True)[0]


def sweep_cost(base, axes, options) -> float:
    """Estimated seconds of one point of a sweep (:func:`gearcalc.grid.point_seconds`): the stacked solve of
    :func:`sweep` 0.1 ms a point (9 570 points/s, README); a "cycle" or "envelope" point (computed alone) 1 ms
    + 10 us per roller-configuration of its first phase and direction grids (zstk.md §8; measured 2026-12-07:
    98 ms for the 8 640 of ``configs/zstk_merko_A_envelope.toml``, the refinements included)."""
    from ..zstk import envelope

    cycle = base["geometry.scheme"] == "cycle" or _among("cycle", axes.get("geometry.scheme", ()))
    envelope_ = base["load.direction_deg"] == "envelope" or _among("envelope", axes.get("load.direction_deg", ()))
    if not (cycle or envelope_):
        return 1e-4
    p = _prepare(_design_columns([base]), 1)
    n = int(p.n[0]) if p.valid[0] else 3
    grid = envelope.sweep_grid((options.model or "equilibrium") == "reference")
    return 1e-3 + 1e-5 * envelope.sweep_work(n, cycle, envelope_, grid)


def _among(word: str, values) -> bool:
    """``word in values``, at once for a range axis (numbers only: ``in`` would compare every value, 1e8 of them)."""
    from ..grid import Range

    return not isinstance(values, (range, Range)) and word in values


def _hashable(v):
    return tuple(v) if isinstance(v, list) else (type(v).__name__, v)


def _compute_sweeping(design, p, options: Options) -> Result:
    """A "cycle" (phase) and/or "envelope" (direction) design: :func:`gearcalc.zstk.solve.solve_sweeping`
    (spec §8), then the summary."""
    from ..zstk import envelope, solve

    model = options.model or "equilibrium"
    problem = cost_problem(design, int(p.n[0]), model)
    if problem is not None:
        raise DesignError(*problem)
    grid = envelope.sweep_grid(model == "reference")
    sw = solve.solve_sweeping(p, options.tol, grid, model == "fixed-direction", model == "reference")
    cols, extra = _columns([design.name], model, sw.stack, True, (sw, grid.cap))
    return _result(cols, extra, 0, model)


def plot(records, path: str) -> list:
    """The paper's Fig. 2 and a drawing of the chain for up to 4 designs (:mod:`gearcalc.zstk.figure`); the
    records drawn."""
    from ..zstk.figure import plot_records

    return plot_records(records, path)


def implicit(design) -> dict:
    """The material values the computation takes for keys left out (:func:`gearcalc.zstk.solve.prepare`): each
    ring's elastic constants from ring_E_MPa / ring_poisson, the default allowable stress."""
    return {"material.inner_ring_E_MPa": design["material.ring_E_MPa"],
            "material.inner_ring_poisson": design["material.ring_poisson"],
            "material.outer_ring_E_MPa": design["material.ring_E_MPa"],
            "material.outer_ring_poisson": design["material.ring_poisson"],
            "material.allowable_stress_MPa": DEFAULT_ALLOWABLE_MPA}


CALCULATOR = Calculator(
    kind="zstk",
    implicit=implicit,
    title="closed rolling-body mechanism (eccentric ZSTK, leading inner ring)",
    tables=TABLES,
    compute=compute,
    check=check,
    sweep=sweep,
    sweep_cost=sweep_cost,
    batch=batch,
    models=MODELS,
    table_fields=TABLE_FIELDS,
    sweep_plot=("sigma_max_MPa",),
    failure=(("pass", False),),
    checks=tuple(Check(*c) for c in R.CHECKS),
    plot=plot,
    header=HEADER,
)
