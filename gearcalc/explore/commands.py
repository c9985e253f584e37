"""The bodies of ``gearcalc optimize`` and ``gearcalc sensitivity`` (the typer signatures are in
:mod:`gearcalc.cli`): parse, call :mod:`gearcalc.explore`, write.  Return the exit status."""
from __future__ import annotations

import os

from ..calculator import Options


def _common(a, plot=None):
    """(format, cluster, design as data, source, file shown) after every check that needs no computing."""
    from .. import cli
    from .. import design as dmod
    from ..engine import check_model

    fmt = cli.pick_format(a.fmt, a.output)
    cli.check_tol(a.tol)
    cluster = cli.dask_cluster(a.scheduler, a.jobs, a.debug)
    cli.check_outputs(a.output, plot, [a.file])
    raw = dmod.read_toml(a.file)
    if a.sets:
        dmod.apply_set(raw, dmod.parse_set(a.sets))
    kind = raw.get("kind")
    if isinstance(kind, str):
        try:
            check_model(a.model, kind)
        except ValueError as exc:
            raise cli.Abort(str(exc)) from None
    return fmt, cluster, raw, dmod.display_name(a.file)


def _value(v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    return f"{v:.10g}" if isinstance(v, float) else str(v)


def _optimum_text(r, where: str) -> str:
    o = r.objectives[0]
    lines = [f"gearcalc optimize {where}: {o.field} {o.sense}imised"]
    lines += [f"  {k} = {_value(v)}" for k, v in r.optimum.items()]
    err = "exact to rounding" if not r.error else f"± {r.error:.2g}"
    lines.append(f"  {o.field} = {_value(r.value)} ({err})")
    for c in r.constraints:
        state = "active" if c["active"] else "inactive"
        slack = "" if c["slack"] is None else f", slack {c['slack']:.3g}"
        lines.append(f"  where {c['where']}: {c['field_value'] if 'field_value' in c else _value(c['value'])}"
                     f" ({state}{slack})")
    lines.append(f"  {r.evaluations} evaluations; refinement "
                 + ("converged" if r.converged else "did not converge" if r.converged is False else "not run"))
    return "\n".join(lines) + "\n"


def optimize_body(a) -> int:
    from .. import cli
    from ..grid import SweepError
    from ..render import Columns, render_rows
    from .optimize import OptimizeError, optimize_design, parse_objectives
    from .sample import SampleError, parse_ranges
    from .where import WhereError, parse_where

    fmt, cluster, raw, where = _common(a, a.plot)
    if a.save is not None and (os.path.exists(a.save) and not os.path.isdir(a.save)
                               or not os.path.isdir(os.path.dirname(os.path.abspath(a.save)))):
        raise cli.Abort(f"--save {a.save}: must be a folder (created when missing) in an existing folder")
    try:
        box = parse_ranges(a.vary, raw)
        objectives = parse_objectives(a.objective)
        conditions = parse_where(a.where_)
        with cli.on_cluster(cluster):
            r = optimize_design(raw, a.file, box, objectives, conditions, Options(tol=a.tol, model=a.model),
                                a.budget, a.seed, a.jobs, cluster)
    except (SampleError, WhereError, OptimizeError) as exc:
        raise cli.Abort(f"{where}: {exc}") from None
    except SweepError as exc:
        raise cli.Abort(f"{where}: {exc}") from None
    for note in r.notes:
        cli.err(f"{where}: {note}")
    if r.optimum is None and r.front is None:
        return cli.EXIT_CHECK
    lead = tuple(box.keys) + tuple(o.field for o in objectives)
    if fmt == "json":
        import json

        text = json.dumps(r.to_dict(), indent=2, allow_nan=False) + "\n"
        cli.emit_text(lambda width, color: text, fmt, a.output)
    elif fmt == "table" and r.front is None:
        cli.emit_text(lambda width, color: _optimum_text(r, where), fmt, a.output)
    else:
        rows = r.front if r.front is not None else Columns.from_rows([r.outputs])
        notes: list = []
        cli.emit_text(lambda width, color: render_rows(rows, fmt, title=f"gearcalc optimize {where}", width=width,
                                                       color=color, fields=list(lead), lead=lead, notes=notes),
                      fmt, a.output)
    if a.plot:
        from ..plot import PLOT_HINT

        try:
            plot_front(r, a.plot)
        except ImportError:
            cli.err(PLOT_HINT)
            return cli.EXIT_INPUT
    if a.save is not None:
        from .designfile import save_designs

        from .. import design as dmod

        fixed = dict(dmod.parse_set(a.sets)) if a.sets else {}
        points = [{**fixed, **{k: row[k] for k in box.keys}} for row in r.rows()]
        try:
            paths = save_designs(a.save, a.file, raw, points)
            cli.err(f"{where}: wrote {paths[0]}" if len(paths) == 1 else
                    f"{where}: wrote {len(paths)} design files {os.path.basename(paths[0])} .. "
                    f"{os.path.basename(paths[-1])} into {a.save}")
        except FileExistsError as exc:
            raise cli.Abort(f"--save {a.save}: {exc.args[0]} exists (never replaced; choose another folder)") from None
        except OSError as exc:
            raise cli.Abort(f"--save {a.save}: {exc.strerror or exc}", cli.EXIT_IO) from None
    return cli.EXIT_OK


def plot_front(r, path: str) -> None:
    """The sampled points of an optimisation: the first two objectives, the front (or the optimum) over the
    dominated feasible points and the infeasible ones."""
    import numpy as np

    from ..plot import _label, _pyplot, save
    from .optimize import _column

    s = r.samples
    fig, ax = _pyplot().subplots(figsize=(7, 5))
    feas = np.array(s.data["feasible"], dtype=bool)
    o = r.objectives
    x = _column(s, o[0].field)
    if len(o) > 1:
        y = _column(s, o[1].field)
        ax.set_ylabel(_label(o[1].field))
    else:
        key = r.keys[0]
        y, x = x, _column(s, key)
        ax.set_xlabel(_label(key))
    ax.scatter(x[~feas], y[~feas], s=8, color="0.85", label="infeasible")
    ax.scatter(x[feas], y[feas], s=10, color="0.5", label="feasible")
    if r.front is not None:
        fx, fy = _column(r.front, o[0].field), _column(r.front, o[1].field)
        ax.plot(fx, fy, "o-", color="C3", label="non-dominated")
        ax.set_xlabel(_label(o[0].field))
    else:
        ax.plot([r.optimum[r.keys[0]]], [r.value], "*", color="C3", markersize=14, label="optimum")
        ax.set_ylabel(_label(o[0].field))
    ax.legend()
    save(fig, path)


def _sensitivity_text(r, where: str, fmt: str):
    from ..render import Columns, render_rows

    rows = Columns.from_rows(r.indices) if r.indices else Columns({"field": [], "key": []})
    text = render_rows(rows, fmt, title=f"gearcalc sensitivity {where} ({r.method})", lead=("field", "key"))
    if fmt == "table":
        text += "".join(f"{f}: dominated by {k}\n" if k else f"{f}: constant over the ranges\n"
                        for f, k in r.dominant.items())
        text += f"{r.evaluations} evaluations\n"
    return text


def sensitivity_body(a) -> int:
    from .. import cli
    from ..grid import SweepError
    from ..render import parse_fields
    from .sample import SampleError, parse_ranges
    from .sensitivity import SensitivityError, sensitivity_design

    fmt, cluster, raw, where = _common(a)
    chosen = parse_fields(a.fields)
    chosen = None if chosen in (None, ["all"]) else chosen
    try:
        box = parse_ranges(a.vary, raw)
        with cli.on_cluster(cluster):
            r = sensitivity_design(raw, a.file, box, Options(tol=a.tol, model=a.model), a.method.lower(), a.samples,
                                   a.seed, a.jobs, cluster, chosen)
    except (SampleError, SensitivityError, SweepError) as exc:
        raise cli.Abort(f"{where}: {exc}") from None
    for note in r.notes:
        cli.err(f"{where}: {note}")
    if fmt == "json":
        import json

        text = json.dumps(r.to_dict(), indent=2, allow_nan=False) + "\n"
        cli.emit_text(lambda width, color: text, fmt, a.output)
    else:
        cli.emit_text(lambda width, color: _sensitivity_text(r, where, fmt), fmt, a.output)
    return cli.EXIT_OK
