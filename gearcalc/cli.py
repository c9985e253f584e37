"""The command line: a thin layer that parses designs, calls the calculators and renders.

Start-up matters: this module imports typer (plain click help, no rich) and the light frame
modules only.  numpy is imported by the calculators when they compute; rich only when a table
is rendered.
"""
from __future__ import annotations

import contextlib
import os
import sys
from collections import Counter
from typing import List, Optional

import typer

from . import __version__, registry
from .calculator import Options
from .output import silence_stdout
from .engine import EXIT_BUG, EXIT_CHECK, EXIT_INPUT, EXIT_IO, EXIT_OK  # noqa: F401 - the exit codes, once

app = typer.Typer(
    name="gearcalc",
    help="Engineering calculator for gear and mechanism designers: KHV pin gearing losses (pins), "
    "closed rolling-body mechanisms (zstk), multi-row planetary load sharing (rows). "
    "Exit codes: 0 ok, 1 a design check failed, 2 bad usage or input, 70 internal error, 74 output not "
    "written.",
    rich_markup_mode=None,
    pretty_exceptions_enable=False,
    no_args_is_help=True,
    context_settings={"help_option_names": ["-h", "--help"]},
)


class Abort(Exception):
    """Stop with a message on stderr and an exit code."""

    def __init__(self, message: str, code: int = EXIT_INPUT):
        super().__init__(message)
        self.code = code


def err(message: str) -> None:
    """A message on stderr; dropped when stderr cannot take it (a hung-up terminal), never sent to stdout."""
    if sys.stderr is None:  # print(file=None) would write to stdout
        return
    try:
        print(message, file=sys.stderr)
    except (OSError, ValueError):
        pass


def _version(value: bool):
    if value:
        print(f"gearcalc {__version__}")
        raise typer.Exit()


@app.callback()
def _root(
    version: bool = typer.Option(False, "--version", "-V", callback=_version, is_eager=True,
                                 help="Print the version and exit."),
):
    """gearcalc: numbers you can trust, with their accuracy stated."""


# ---------------------------------------------------------------- shared options
FORMAT_HELP = ("Output format: table | csv | json (default: table on a terminal, else csv; "
               "with -o, from the file's extension).")
O_FORMAT = typer.Option(None, "--format", "-f", help=FORMAT_HELP)
O_DETAIL = typer.Option(False, "--detail",
                        help="Add the per-element tables (per pin and crank angle, per roller, per row).")
O_OUTPUT = typer.Option(None, "--output", "-o", help="Write to this file instead of stdout ('-': stdout); a regular "
                        "file is replaced atomically keeping its mode, a device or FIFO written through.")
O_SET = typer.Option(None, "--set",
                     help="Override a design key for this run: KEY=VALUE with a dotted KEY (repeatable).")
O_TOL = typer.Option(1e-6, "--tol", help="Relative accuracy target for numerically computed results (0 < REL < 0.1).")
MODEL_HELP = "Force a model level; default: the cheapest level the design needs."
O_MODEL = typer.Option(None, "--model", metavar="LEVEL", help=MODEL_HELP)
O_PLOT = typer.Option(None, "--plot", help="Draw the calculator's figure to this file: png, pdf, svg, ... from its "
                      "extension (needs the 'plot' extra).")
O_DEBUG = typer.Option(False, "--debug", help="Show the traceback of an internal error.")
O_FIELDS = typer.Option(None, "--fields", metavar="A,B,...",
                        help="Summary fields to output, comma-separated (name always first); 'all' for every "
                        "field; 'file' adds the design's file; with --detail also detail columns. Default: a table "
                        "of several designs shows each kind's main fields, CSV and JSON every field.")
O_VERBOSE = typer.Option(False, "--verbose", "-v",
                         help="Repeat a warning that many designs share once per design (default: once, "
                         "with the count and the first names).")
O_JOBS = typer.Option(1, "--jobs", "-j", min=1, max=256,
                      help="Spread a batch or sweep over N processes; the results are identical to --jobs 1. "
                      "It pays only with idle cores: a sweep of cheap points (rows) on a busy machine is faster "
                      "with 1.")
O_SCHEDULER = typer.Option(None, "--scheduler", envvar="DASK_SCHEDULER_ADDRESS", metavar="ADDRESS|local[:N]",
                           show_envvar=False,
                           help="Compute on a Dask cluster: its scheduler's ADDRESS (tcp://HOST:8786, or a "
                           "scheduler file *.json), or local[:N] for N worker processes here (default: the "
                           "cores). Output identical to a run without it. Default: $DASK_SCHEDULER_ADDRESS. "
                           "Needs the 'dask' extra.")
O_WHERE = typer.Option(None, "--where", metavar="'FIELD<=VALUE'",
                       help="Keep only the rows where FIELD OP VALUE holds (OP: <, <=, >, >=, ==, !=; repeatable: "
                       "all must hold). VALUE: a number, true/false or a word.")
O_SAMPLE = typer.Option(None, "--sample", metavar="sobol:N|lhs:N|random:N",
                        help="Sample N points of the --vary KEY=LO:HI ranges instead of a grid (integer keys as "
                        "integers, LO..HI inclusive).")
O_SEED = typer.Option(0, "--seed", help="The seed of the sampled points (the same seed, the same points).")
O_RESUME = typer.Option(False, "--resume", help="With -o FILE (CSV or Parquet): keep the chunks written so far in "
                        ".FILE.partial when the run stops, and continue an interrupted run's from its next chunk.")


SHARED = {
    "fmt": (Optional[str], O_FORMAT),
    "detail": (bool, O_DETAIL),
    "output": (Optional[str], O_OUTPUT),
    "sets": (Optional[List[str]], O_SET),
    "tol": (float, O_TOL),
    "model": (Optional[str], O_MODEL),
    "plot": (Optional[str], O_PLOT),
    "debug": (bool, O_DEBUG),
    "jobs": (int, O_JOBS),
    "fields": (Optional[str], O_FIELDS),
    "verbose": (bool, O_VERBOSE),
    "scheduler": (Optional[str], O_SCHEDULER),
    "sample": (Optional[str], O_SAMPLE),
    "seed": (int, O_SEED),
    "where_": (Optional[List[str]], O_WHERE),
    "resume": (bool, O_RESUME),
}
"""The options several commands share, each declared once: parameter name -> (type, typer option)."""

COMPUTE = ("fmt", "detail", "output", "sets", "tol", "model", "plot", "debug", "jobs", "fields", "verbose")
"""The options of every computing command (the kind commands, ``run``), in the order their help lists them."""


def shared(*names: str):
    """Give a command the shared options ``names`` (:data:`SHARED`) after its own parameters, in this order
    (sqlite-utils' ``output_options``): the command takes them as keyword arguments (``**options``)."""
    import functools
    import inspect

    def decorate(fn):
        sig = inspect.signature(fn)
        own = [p for p in sig.parameters.values() if p.kind is not inspect.Parameter.VAR_KEYWORD]
        added = [inspect.Parameter(n, inspect.Parameter.KEYWORD_ONLY, default=SHARED[n][1], annotation=SHARED[n][0])
                 for n in names]

        @functools.wraps(fn)
        def command(*args, **kwargs):
            return fn(*args, **kwargs)

        command.__signature__ = sig.replace(parameters=own + added)
        command.__annotations__ = {**typing_hints(fn), **{n: SHARED[n][0] for n in names}}
        del command.__wrapped__  # typer reads the signature above, not the function's own
        return command

    return decorate


def typing_hints(fn) -> dict:
    """A function's evaluated annotations (this module's are strings: ``from __future__ import annotations``)."""
    import typing

    return typing.get_type_hints(fn)


def model_levels(kinds) -> str:
    """The --model help with the levels of these kinds, cheapest first (the registry's: the calculators' own
    lists, without importing a calculator)."""
    kinds = [k for k in kinds if k in registry.kinds()]
    if len(kinds) == 1:
        return f"{MODEL_HELP} Levels: {', '.join(registry.levels(kinds[0]))}."
    return f"{MODEL_HELP} Levels: " + "; ".join(f"{k}: {', '.join(registry.levels(k))}" for k in kinds) + "."


class _Help(typer.core.TyperCommand):
    """A command whose help page names the model levels of its kinds under --model (``kinds``: None for all)."""

    kinds: Optional[tuple] = None

    def format_help(self, ctx, formatter) -> None:
        for p in self.params:
            if p.name == "model":
                p.help = model_levels(self.kinds or registry.kinds())
        super().format_help(ctx, formatter)


def _help_of(kind: Optional[str] = None):
    return type("Help", (_Help,), {"kinds": (kind,) if kind else None})


def examples(*lines: str) -> str:
    """A help page's epilog: example command lines, kept as written (click's \\b: no rewrapping)."""
    return "\b\nExamples:\n" + "\n".join(f"  {line}" for line in lines)


EXAMPLES = {
    "run": examples("gearcalc run configs --format table          # every design below a folder",
                    "gearcalc run configs --format json -o results.json",
                    "gearcalc run a.toml b.toml --fields name,efficiency --jobs 4"),
    "sweep": examples("gearcalc sweep configs/rows_mass_fig5.toml --vary rows.count=1,2,3,4 \\",
                      "    --vary gear.ratio=2.2:12:0.05 --plot fig5.png",
                      "gearcalc sweep gear.toml --vary friction.sliding=0.02:0.2:0.02 --format json"),
    "optimize": examples("gearcalc optimize gear.toml --vary rows.relative_width=1.6:3 --vary rows.count=2:5 \\",
                         "    --objective w_max_N_per_mm:min --where 'K<=1.5' --save best/",
                         "gearcalc optimize gear.toml --vary rows.relative_width=1.6:3 --objective K:min \\",
                         "    --objective w_max_N_per_mm:min --plot front.png"),
    "sensitivity": examples("gearcalc sensitivity gear.toml --vary rows.relative_width=1.6:3 \\",
                            "    --vary rows.cheek_ratio=0.1:0.5 --fields K,w_max_N_per_mm",
                            "gearcalc sensitivity gear.toml --vary rows.relative_width=1.6:3 --method morris"),
    "accuracy": examples("gearcalc accuracy pins --tols 1e-3,1e-6", "gearcalc accuracy --plot accuracy.png"),
    "check": examples("gearcalc check configs", "gearcalc check gear.toml --resolved > resolved.toml"),
    "new": examples("gearcalc new rows > gear.toml", "gearcalc new pins -o pins.toml     # --force replaces a file"),
    "report": examples("gearcalc report configs/zstk_merko_example.toml -o calc.html",
                       "gearcalc report a.toml b.toml -o calc.pdf       # PDF through a headless Chromium"),
    "export": examples("gearcalc export configs/pins_paper_cyc_u10_fixed.toml -o profile.dxf   # the dxf extra",
                       "gearcalc export configs/zstk_merko_example.toml -o chain.svg --chord-tol 0.0001"),
    "schema": examples("gearcalc schema rows -o gearcalc-rows.schema.json   # the file 'gearcalc new' points at"),
}


EXAMPLE_SET = {"pins": "friction.sliding=0.08", "zstk": "load.radial_N=12000", "rows": "rows.count=4"}
"""A --set for each kind's examples (tests/test_cli.py runs it on the kind's template)."""


def kind_examples(kind: str) -> str:
    return examples(f"gearcalc new {kind} > {kind}.toml && gearcalc {kind} {kind}.toml",
                    f"gearcalc {kind} {kind}.toml --detail --format json -o {kind}.json",
                    f"gearcalc {kind} {kind}.toml --set {EXAMPLE_SET.get(kind, 'KEY=VALUE')} --plot {kind}.png")


def pick_format(fmt: Optional[str], output: Optional[str], extra: tuple = ()) -> str:
    """The output format; ``extra``: formats this command writes beyond table, csv, json (sweep: parquet)."""
    formats = ["table", "csv", "json", *extra]
    if fmt is not None:
        fmt = fmt.lower()
        if fmt not in formats:
            raise Abort(f"--format {clip(fmt)}: must be one of " + ", ".join(formats) + did_you_mean(fmt, formats))
        return fmt
    if output and output != "-":  # -o - is standard output: the terminal/pipe rule
        ext = os.path.splitext(output)[1].lower()
        return {".json": "json", ".txt": "table", **{f".{x}": x for x in extra}}.get(ext, "csv")
    return "table" if sys.stdout.isatty() else "csv"


def clip(text) -> str:
    """A value the user gave, cut for an echo in a message (about 60 characters, one line)."""
    from .design import _clip

    return _clip(text)


def did_you_mean(word: str, choices: list[str]) -> str:
    from .design import _suggest

    return _suggest(word, choices)


def check_output_path(output: Optional[str], inputs=(), option: str = "-o", other: Optional[str] = None,
                      plot: bool = False) -> None:
    """Fail before any computation when the output cannot be written (the rules: gearcalc/output.py).

    Exit 2 for a path that cannot be right (missing folder, a directory, one of ``inputs``, the same file
    as ``other``, a figure format matplotlib cannot write); exit 74 for one the environment refuses."""
    from .output import UsageError, check

    try:
        check(output, option, inputs, other, plot)
    except UsageError as exc:
        raise Abort(str(exc)) from None


def check_outputs(output: Optional[str], plot: Optional[str], inputs=()) -> None:
    """check_output_path for -o and --plot together (and that they are not the same file)."""
    check_output_path(output, inputs)
    if plot is not None:
        check_output_path(plot, inputs, "--plot", other=output, plot=True)


def write_atomic(path: str, text) -> None:
    """Write to -o / --plot by the rules of gearcalc/output.py: special files and descriptors written
    through, symlinks followed, regular files replaced atomically keeping their mode, ``-`` is stdout."""
    from .output import write

    write(path, text)


def emit_text(render_fn, fmt: str, output: Optional[str]) -> bool:
    """Render (width and colour from the terminal) and write to stdout or to -o.

    Returns False, after an error message, when the calculator produced a non-finite value (a bug).
    """
    from .output import to_file, write_stdout
    from .render import NonFiniteOutput

    terminal = fmt == "table" and not to_file(output) and sys.stdout.isatty()
    try:
        text = render_fn(os.get_terminal_size().columns if terminal else None,
                         terminal and "NO_COLOR" not in os.environ)
    except NonFiniteOutput as exc:
        err(f"internal error: {exc}; please report it with the design file")
        return False
    if to_file(output):
        write_atomic(output, text)
    else:
        write_stdout(text)
    return True


def check_tol(tol: float) -> None:
    from .calculator import tol_problem

    problem = tol_problem(tol)
    if problem:
        raise Abort(f"--tol {tol}: {problem}")


def compute_files(paths: List[str], kind_hint: Optional[str], *, fmt: Optional[str], detail: bool,
                  output: Optional[str], sets: Optional[List[str]], tol: float, model: Optional[str],
                  plot: Optional[str], debug: bool, jobs: int = 1, fields: Optional[str] = None,
                  verbose: bool = False, scheduler: Optional[str] = None, where_: Optional[List[str]] = None) -> int:
    """The body of every computing command; returns the exit code."""
    from . import design as dmod

    conditions = _where(where_)
    fmt = pick_format(fmt, output)
    check_tol(tol)
    cluster = dask_cluster(scheduler, jobs, debug)
    check_outputs(output, plot)
    overrides = dmod.parse_set(sets or []) if sets else []
    files = dmod.expand_paths(paths)
    if not files:
        raise Abort("no design files found in " + " ".join(paths))
    if files.count("-") > 1:
        raise Abort("'-' (standard input) can be given once")
    check_outputs(output, plot, files)  # never overwrite an input design
    from . import engine
    from .design import InputError
    from .render import parse_fields

    chosen = parse_fields(fields)
    bars = []

    def progress(n: int):
        bars.append(Progress(n, "designs"))  # shown on a terminal once the work has run about a second
        return bars[0].advance

    try:
        opts = Options(tol=tol, model=model, detail=detail)
        records, worst = engine.compute_files(files, overrides, kind_hint, opts, say=err, progress=progress,
                                              debug=debug, jobs=jobs, verbose=verbose, cluster=on_cluster(cluster))
    except InputError as exc:  # an unknown --model level, before any computation
        raise Abort(str(exc)) from None
    finally:
        for bar in bars:
            bar.stop()
    if conditions:  # the designs shown; the exit status is the computation's
        from .explore.where import keep_records

        records = keep_records(records, conditions, Abort)
    array = len(paths) > 1 or any(p != "-" and os.path.isdir(p) for p in paths)
    return _emit(records, fmt, detail, output, plot, worst, chosen, array)


def _emit(records, fmt, detail, output, plot, worst, fields=None, array=None) -> int:
    from .render import render, unknown_fields

    if fields is not None and records:
        from .render import detail_columns

        have = dict.fromkeys(k for r in records for k in r.result.summary)
        bad = unknown_fields(fields, list(have) + sorted(detail_columns(records) - set(have) if detail else ()),
                             extra=("name", "file"))
        if bad:
            raise Abort("; ".join(bad) + " (the summary fields are the CSV columns: --format csv --fields all)")
    if records or (fmt == "json" and array):
        notes: list[str] = []
        if not emit_text(lambda width, color: render(records, fmt, detail, width=width, color=color, fields=fields,
                                                     notes=notes, array=array), fmt, output):
            return EXIT_BUG
        for note in dict.fromkeys(notes):
            err(note)
        if plot:
            from .plot import PLOT_HINT, plot_records

            try:
                for note in plot_records(records, plot):
                    err(note)
            except ImportError:
                err(PLOT_HINT)
                worst = max(worst, EXIT_INPUT)
    return worst


def _kind_command(kind: str, summary: str):
    @shared(*COMPUTE)
    def command(
        files: List[str] = typer.Argument(..., metavar="FILE...",
                                          help="Design files (TOML); '-' reads standard input."),
        **options,
    ):
        finish(lambda: compute_files(files, kind, **options), options["debug"])

    command.__doc__ = summary
    command.__name__ = kind
    return command


for _kind in registry.KINDS:  # the registry is the one list of kinds
    app.command(_kind, help=registry.help_of(_kind), cls=_help_of(_kind),
                epilog=kind_examples(_kind))(_kind_command(_kind, registry.help_of(_kind)))


@app.command("run", cls=_help_of(), epilog=EXAMPLES["run"])
@shared(*COMPUTE, "scheduler", "where_")
def run_cmd(
    paths: List[str] = typer.Argument(
        ..., metavar="PATH...", help="Design files or folders (every *.toml below a folder); '-' reads stdin."),
    **options,
):
    """Compute any design files, dispatching on their `kind`.

    JSON: an array when PATH is a folder or several PATHs are given (even if one design is computed),
    one object for a single file."""
    finish(lambda: compute_files(paths, None, **options), options["debug"])


@app.command("sweep", cls=_help_of(), epilog=EXAMPLES["sweep"])
@shared("fmt", "output", "sets", "tol", "model", "plot", "debug", "jobs", "fields", "scheduler", "sample", "seed",
        "where_", "resume")
def sweep_cmd(
    file: str = typer.Argument(..., metavar="FILE", help="One design file ('-' reads standard input)."),
    vary: List[str] = typer.Option(..., "--vary", help="KEY=SPEC: an axis of the grid; SPEC is start:stop:step "
                                   "or v1,v2,...; several --vary make a product grid (the first varies slowest)."),
    **options,
):
    """Evaluate one design over a grid of key values; one output row per point.

    Exit 1 when any point fails a design check (the count is said on stderr), as the same design alone
    would."""

    def body(fmt, output, sets, tol, model, plot, debug, jobs, fields, scheduler, sample, seed, where_,
             resume) -> int:
        from . import design as dmod
        from . import grid as sw
        from .engine import check_model
        from .render import CsvRenderer, parse_fields
        from .studies import StudyError  # the standard library's hashlib and json only

        f = pick_format(fmt, output, ("parquet",))
        check_tol(tol)
        cluster = dask_cluster(scheduler, jobs, debug)
        check_outputs(output, plot, [file])
        _study_checks(f, output, plot, resume)
        chosen = parse_fields(fields)
        where = dmod.display_name(file)
        try:
            conditions = _where(where_)
            axes = sw.parse_vary(vary) if sample is None else None
            raw = dmod.read_toml(file)
            if sets:
                dmod.apply_set(raw, dmod.parse_set(sets))
            if sample is not None:
                axes = _sample_axes(vary, raw, sample, seed)
            kind = raw.get("kind")
            if isinstance(kind, str) and kind in registry.kinds():
                try:
                    check_model(model, kind)
                except ValueError as exc:
                    raise Abort(str(exc)) from None
            calc = registry.get(kind) if isinstance(kind, str) and kind in registry.kinds() else None
            bar = Progress(sw.size_of(axes), "points")
            try:
                with on_cluster(cluster):
                    csv_out = f == "csv" and not plot and calc is not None
                    # CSV: each chunk formatted where it is computed (in the --jobs workers too)
                    post = CsvRenderer(kind, chosen, tuple(axes)) if csv_out else None
                    post = _filtered(conditions, post)
                    options = Options(tol=tol, model=model)
                    sink = _study_sink(f, output, resume, raw, axes, options, chosen, where_, vary, sample, seed)
                    chunks = sw.stream(raw, file, axes, options, progress=bar.advance, jobs=jobs, cluster=cluster,
                                       debug=debug, arrays=csv_out or f == "parquet", post=post,
                                       plan=sink.plan if resume else None)
                    if f == "table" or plot:  # a table and a figure show every point at once
                        result = _sweep_whole(chunks, f, output, chosen, axes, where, plot, calc)
                    elif f == "parquet":  # one row group a chunk
                        result = _sweep_parquet(chunks, sink, chosen, tuple(axes), calc, where)
                    else:  # CSV and JSON are written a chunk at a time: memory follows the chunk, not the grid
                        result = _sweep_stream(chunks, f, output, chosen, tuple(axes), calc, where, sink)
            finally:
                bar.stop()
        except sw.SweepError as exc:
            raise Abort(f"{where}: {exc}") from None
        except StudyError as exc:
            raise Abort(str(exc)) from None
        if result is None:
            return EXIT_BUG
        failed, total, code = result
        for line in check_counts(calc, failed, total, "points"):
            err(f"{where}: {line}")
        return max(code, EXIT_CHECK) if set(failed) - {"errors"} else code

    finish(lambda: body(**options), options["debug"])


def _where(items):
    """The ``--where`` conditions (an empty list without any)."""
    if not items:
        return []
    from .explore.where import WhereError, parse_where

    try:
        return parse_where(items)
    except WhereError as exc:
        raise Abort(str(exc)) from None


def _filtered(conditions, post):
    """A sweep's ``post`` step with the ``--where`` conditions applied first (``post`` itself without any)."""
    if not conditions:
        return post
    from .explore.where import Filtered

    return Filtered(tuple(conditions), post)


def _sample_axes(vary, raw, sample: str, seed: int):
    """The axes of ``sweep --sample``: the sampled points of the ``--vary KEY=LO:HI`` ranges."""
    from .explore.sample import SampleError, draw, parse_ranges, parse_sampler

    try:
        sampler, n = parse_sampler(sample)
        return draw(parse_ranges(vary, raw), sampler, n, seed)
    except SampleError as exc:
        raise Abort(str(exc)) from None


O_RANGE = typer.Option(..., "--vary", metavar="KEY=LO:HI", help="A varied key and its range (repeatable); an "
                       "integer key (a count) takes the integers LO..HI.")


@app.command("optimize", cls=_help_of(), epilog=EXAMPLES["optimize"])
@shared("fmt", "output", "sets", "tol", "model", "plot", "debug", "jobs", "scheduler")
def optimize_cmd(
    file: str = typer.Argument(..., metavar="FILE", help="One design file ('-' reads standard input)."),
    vary: List[str] = O_RANGE,
    objective: List[str] = typer.Option(..., "--objective", metavar="FIELD:min|max",
                                        help="The output to minimise or maximise; several: the Pareto front."),
    where_: Optional[List[str]] = O_WHERE,
    budget: int = typer.Option(256, "--budget", min=2, max=1_000_000, help="Points of the global (sampled) phase."),
    seed: int = O_SEED,
    save: Optional[str] = typer.Option(None, "--save", metavar="DIR",
                                       help="Write each optimum or front member as a design file into DIR."),
    **options,
):
    """Find the design that minimises or maximises outputs over ranges of keys.

    One objective: a Sobol' sample, then SLSQP on the best points, integer keys searched among their
    neighbours. Several: the non-dominated points (Pareto front). Exit 1 when no point is feasible."""
    params = locals_of(locals())
    from .explore.commands import optimize_body

    finish(lambda: optimize_body(params), params.debug)


@app.command("sensitivity", cls=_help_of(), epilog=EXAMPLES["sensitivity"])
@shared("fields", "fmt", "output", "sets", "tol", "model", "debug", "jobs", "scheduler")
def sensitivity_cmd(
    file: str = typer.Argument(..., metavar="FILE", help="One design file ('-' reads standard input)."),
    vary: List[str] = O_RANGE,
    method: str = typer.Option("sobol", "--method", metavar="sobol|morris",
                               help="Sobol' indices (first order, total) or Morris screening (mu*, sigma)."),
    samples: Optional[int] = typer.Option(None, "--samples", metavar="N", help="Sobol': the base size N (N (d+2) "
                                          "points; default 256); Morris: trajectories (N (d+1) points; default 64)."),
    seed: int = O_SEED,
    **options,
):
    """Which varied key drives each output: Sobol' indices with confidence intervals, or Morris mu*."""
    params = locals_of(locals())
    from .explore.commands import sensitivity_body

    finish(lambda: sensitivity_body(params), params.debug)


def locals_of(values: dict):
    """A command's parameters as attributes (its shared ``**options`` among them)."""
    import types

    values = dict(values)
    return types.SimpleNamespace(**values.pop("options", {}), **values)


def dask_cluster(scheduler: Optional[str], jobs: int, debug: bool):
    """The Dask cluster of ``--scheduler`` (:class:`gearcalc.distributed.Cluster`, connected when first used;
    it says its dashboard on a terminal), or None: then gearcalc does not import Dask."""
    if scheduler is None:
        return None
    from .distributed import Cluster, SchedulerError, is_terminal, parse

    try:
        parse(scheduler)  # an empty value (a script's unset variable) is refused before --jobs is looked at
    except SchedulerError as exc:
        raise Abort(str(exc)) from None
    if jobs > 1:
        given = any(a.startswith("--scheduler") for a in sys.argv)
        source = "" if given else " (from DASK_SCHEDULER_ADDRESS)"
        raise Abort(f"--jobs {jobs} and --scheduler {clip(scheduler)}{source}: choose one (--scheduler local:N "
                    "computes in N processes on this machine)")

    class Told(Cluster):
        def connect(self):
            fresh = self.client is None
            super().connect()
            if fresh and is_terminal():
                err(self.describe())
            return self

    try:
        return Told(scheduler, say=err, debug=debug)
    except SchedulerError as exc:
        raise Abort(str(exc)) from None


@contextlib.contextmanager
def on_cluster(cluster):
    """The body of a command on the ``--scheduler`` cluster (closed at the end: its futures cancelled, a local
    cluster stopped), an unusable one an :class:`Abort`; with no cluster, the body alone."""
    if cluster is None:
        yield None
        return
    from .distributed import SchedulerError

    try:
        with cluster:
            yield cluster
    except SchedulerError as exc:
        raise Abort(str(exc)) from None


def _fields_or_abort(fields, names) -> None:
    from .render import unknown_fields

    bad = unknown_fields(fields, list(names))
    if bad:
        raise Abort("; ".join(bad))


def _sweep_stream(chunks, fmt: str, output, fields, lead: tuple, calc, where: str, sink=None):
    """Write a sweep's chunks as they come (CSV: the header once; JSON: one array); (failed points, points,
    exit status), or None after an internal-error message (a non-finite value).  ``sink``: the output
    (``--resume``: a :class:`gearcalc.studies.Resumable`, its header already written when resumed)."""
    from .output import stream, to_file
    from .render import CsvPiece, NonFiniteOutput, csv_blocks, json_array_piece, select_columns

    failed, total = Counter(), 0
    code = EXIT_OK
    try:
        with sink if sink is not None else stream(output if to_file(output) else None) as out:
            first = True
            done = getattr(out, "chunk_done", None)
            for part in chunks:
                if done is not None and out.resumed:  # the interrupted run's header and chunks are kept
                    first, failed, total, code = False, out.start.failed, out.start.total, out.start.code
                    out.resumed = False
                if _point_errors(part, where, failed):
                    code = EXIT_INPUT
                if isinstance(part, CsvPiece):  # formatted where it was computed (CsvRenderer)
                    if first:
                        _fields_or_abort(fields, part.columns)
                        out.write(part.header())
                    failed += Counter(part.failed)
                    total += part.n
                    for block in part.blocks():
                        out.write(block)
                    first = False
                    del part
                    if done is not None:
                        done(failed, total, code)
                    continue
                if first:
                    _fields_or_abort(fields, part.data)
                if not part.n and fmt == "json":  # every point filtered out (--where): no element
                    continue
                failed += Counter(calc.failed_points(part.data))
                total += part.n
                shown = select_columns(part, fields, lead)
                if fmt == "csv":
                    for block in csv_blocks(shown, header=first, binary=True):
                        out.write(block)
                else:
                    out.write(json_array_piece(shown, first))
                first = False
                del part, shown  # one chunk at a time
                if done is not None:
                    done(failed, total, code)
            if done is not None and out.resumed:  # resumed after the last chunk: nothing left to compute
                failed, total, code = out.start.failed, out.start.total, out.start.code
            if fmt == "json":
                out.write("[]\n" if first else "\n]\n")
    except NonFiniteOutput as exc:
        err(f"internal error: {exc}; please report it with the design file")
        return None
    return failed, total, code


def _study_checks(fmt: str, output, plot, resume: bool) -> None:
    """Parquet and ``--resume``: what they need, before any computation (exit 2)."""
    from .output import _special, descriptor, to_file
    from .studies import StudyError, need_pyarrow

    if fmt == "parquet":
        if plot:
            raise Abort("--plot draws from a table of every point; it does not go with --format parquet")
        if not to_file(output) and sys.stdout.isatty():
            raise Abort("--format parquet: a binary file; give -o FILE.parquet or a pipe")
        try:
            need_pyarrow()
        except StudyError as exc:
            raise Abort(str(exc)) from None
    if resume:
        if fmt not in ("csv", "parquet") or plot:
            raise Abort("--resume: resumes CSV or Parquet output written with -o FILE (not "
                        + ("--plot" if plot else fmt) + ")")
        if not to_file(output) or descriptor(output) is not None or _special(output):
            raise Abort("--resume needs -o FILE, a regular file (its partial output is kept beside it)")


def _study_sink(fmt: str, output, resume: bool, raw, axes, options, fields, where_, vary, sample, seed):
    """The output of a Parquet or ``--resume`` sweep: a :class:`gearcalc.studies.Resumable` (``--resume``), a
    :func:`gearcalc.output.stream` (Parquet), or None (the default output of :func:`_sweep_stream`)."""
    if not resume and fmt != "parquet":
        return None
    from . import studies

    spec = {"sampler": sample.split(":")[0], "n": sample.split(":", 1)[-1], "seed": seed, "vary": list(vary)} \
        if sample is not None else None
    finger = studies.fingerprint(raw, axes, options, fmt, fields, where_, spec)
    if resume:
        return studies.Resumable(output, finger, say=err)
    from .output import stream, to_file

    sink = stream(output if to_file(output) else None)
    sink.finger = finger
    return sink


def _sweep_parquet(chunks, sink, fields, lead: tuple, calc, where: str):
    """Write a sweep's chunks as Parquet, one row group each (:class:`gearcalc.studies.ParquetOut`); (failed
    points, points, exit status)."""
    from . import grid as sw
    from .render import select_columns
    from .studies import ParquetOut, metadata

    failed, total = Counter(), 0
    code = EXIT_OK
    with sink as out:
        done = getattr(out, "chunk_done", None)
        finger = getattr(out, "finger", None) or sink.finger
        writer = None

        def opened():
            meta = metadata(finger, getattr(out, "size", 0) or sw.CHUNK_POINTS)
            made = ParquetOut(out, meta, getattr(out, "prev", None), getattr(out, "groups", 0))
            if done is not None:
                out.writer = made
            return made

        try:
            for part in chunks:
                if writer is None:
                    writer = opened()
                    if done is not None and out.resumed:
                        failed, total, code = out.start.failed, out.start.total, out.start.code
                    _fields_or_abort(fields, part.data)
                if _point_errors(part, where, failed):
                    code = EXIT_INPUT
                failed += Counter(calc.failed_points(part.data))
                total += part.n
                writer.write(select_columns(part, fields, lead))
                del part
                if done is not None:
                    done(failed, total, code)
            if writer is None:  # no chunk left to compute (resumed after the last one) or no point
                writer = opened()
                if done is not None and out.resumed:
                    failed, total, code = out.start.failed, out.start.total, out.start.code
        finally:
            if writer is not None:
                writer.close()  # the footer, also when stopped: a partial file is a Parquet file of its chunks
    return failed, total, code


POINT_ERRORS_SHOWN = 20
"""The messages of points without results a sweep says one by one; the rest are counted at the end (each row
has its reason in the ``error`` column)."""


def _point_errors(part, where: str, said: Counter) -> bool:
    """Say the errors of a sweep chunk's points that could not be computed (their outputs are empty, their reason
    in the ``error`` column), the first :data:`POINT_ERRORS_SHOWN` of the sweep; any?"""
    errors = getattr(part, "errors", ())
    for e in errors[:max(0, POINT_ERRORS_SHOWN - said["errors"])]:
        err(f"{where}: {e}")
    said["errors"] += len(errors)
    return bool(errors)


def _sweep_whole(chunks, fmt: str, output, fields, axes, where: str, plot, calc):
    """Collect every chunk, then render (a table) and draw (--plot); (failed points, points, exit status) or
    None after an internal-error message."""
    from . import grid as sw
    from .render import render_rows

    total = sw.size_of(axes)
    if total > sw.MAX_WHOLE_POINTS:
        what = "--plot" if plot else "a table"
        raise Abort(f"{where}: the grid has {total} points; {what} holds every point at once and takes at most "
                    f"{sw.MAX_WHOLE_POINTS} (memory): write --format csv or json, which stream any size")
    parts = list(chunks)
    said = Counter()
    code = EXIT_INPUT if any([_point_errors(p, where, said) for p in parts]) else EXIT_OK
    rows = sw.join_parts(parts)
    _fields_or_abort(fields, rows.data)
    default = list(calc.table_fields) or None
    notes: list[str] = []
    title = f"gearcalc sweep {where}"
    if not emit_text(lambda width, color: render_rows(rows, fmt, title=title, width=width, color=color,
                                                      fields=fields, default=default, lead=tuple(axes),
                                                      notes=notes), fmt, output):
        return None
    for note in notes:
        err(note)
    if plot:
        from .plot import PLOT_HINT, plot_sweep

        try:
            plot_sweep(calc.kind, rows.rows(), list(axes), plot)
        except ImportError:
            err(PLOT_HINT)
            code = EXIT_INPUT
    return Counter(calc.failed_points(rows.data)) + said, rows.n, code


def check_counts(calc, failed: dict, total: int, what: str) -> list:
    """A sweep's closing lines: one per design check that some points fail (:meth:`Calculator.check_lines`), and
    the count of the points without results."""
    lines = calc.check_lines(failed, total, what)
    if failed.get("errors"):
        lines.append(f"{failed['errors']} of {total} {what} have no results (not a valid design, or a non-finite "
                     "output: the reason is in their error column)")
    return lines


def math_prod(values) -> int:
    out = 1
    for v in values:
        out *= v
    return out


class Progress:
    """A progress bar on stderr, only when stderr is a terminal, shown once the work has run :attr:`DELAY`
    seconds (so quick runs print nothing), for any amount of work: a single slow design shows an
    elapsed-time bar, a batch or sweep advances per design or per finished chunk.  Never on stdout.

    ``advance(k)`` counts ``k`` units done; ``stop()`` removes the bar (it is transient).
    """

    DELAY = 1.0
    """Seconds before the bar appears; ``GEARCALC_PROGRESS_DELAY`` sets another (the tests use 0)."""

    def __init__(self, total: int, unit: str = "designs", stream=None):
        import threading

        self.total, self.unit, self.done = max(int(total), 0), unit, 0
        self.stream = sys.stderr if stream is None else stream
        self.bar = self.task = None
        self.lock = threading.Lock()
        self.timer = None
        if _is_terminal(self.stream):
            try:
                delay = float(os.environ.get("GEARCALC_PROGRESS_DELAY", self.DELAY))
            except ValueError:
                delay = self.DELAY
            self.timer = threading.Timer(delay, self._show)
            self.timer.daemon = True
            self.timer.start()

    def _show(self) -> None:
        from rich.console import Console
        from rich.progress import (BarColumn, MofNCompleteColumn, Progress as Bar, TextColumn, TimeElapsedColumn,
                                   TimeRemainingColumn)

        with self.lock:
            if self.timer is None:  # stopped meanwhile
                return
            console = Console(file=self.stream, stderr=True)
            eta = (TextColumn("left"), TimeRemainingColumn()) if self.total else ()  # once the rate is known
            self.bar = Bar(TextColumn("computing"), BarColumn(), MofNCompleteColumn(), TextColumn(self.unit),
                           TimeElapsedColumn(), *eta, console=console, transient=True)
            self.bar.start()
            self.task = self.bar.add_task("computing", total=self.total or None, completed=self.done)

    def advance(self, k: int = 1) -> None:
        with self.lock:
            self.done += k
            if self.bar is not None:
                self.bar.update(self.task, completed=self.done)

    def stop(self) -> None:
        with self.lock:
            if self.timer is not None:
                self.timer.cancel()
                self.timer = None
            if self.bar is not None:
                self.bar.stop()
                self.bar = None


def _is_terminal(stream) -> bool:
    try:
        return stream.isatty()
    except (AttributeError, ValueError, OSError):
        return False


@app.command("report", epilog=EXAMPLES["report"])
def report_cmd(
    files: List[str] = typer.Argument(..., metavar="FILE...", help="Design files (TOML) or folders; '-' reads "
                                      "standard input."),
    output: str = typer.Option(..., "--output", "-o", metavar="FILE",
                               help="The report: FILE.html (self-contained) or FILE.pdf (printed by a headless "
                                    "Chromium)."),
    sets: Optional[List[str]] = O_SET,
    tol: float = O_TOL,
    model: Optional[str] = O_MODEL,
    debug: bool = O_DEBUG,
):
    """A calculation report of the designs: one self-contained HTML page (inline SVG figures, nothing loaded
    from the network) with the checks, inputs and where each came from, assumptions, method, results and
    references; or PDF when a Chromium is on PATH. Exit status as for run."""

    def body() -> int:
        from . import design as dmod
        from . import engine

        ext = os.path.splitext(output)[1].lower()
        if ext not in (".html", ".htm", ".pdf"):
            raise Abort(f"-o {clip(output)}: a report is FILE.html or FILE.pdf")
        try:
            import jinja2  # noqa: F401
        except ImportError:
            raise Abort("report needs jinja2: pip install jinja2") from None
        from .report import browser, build, html_to_pdf

        exe = browser() if ext == ".pdf" else None
        if ext == ".pdf" and exe is None:
            raise Abort(f"-o {clip(output)}: a PDF needs Chromium on PATH (apt-get install chromium); or write "
                        "-o FILE.html and print it to PDF from a browser")
        check_tol(tol)
        overrides = dmod.parse_set(sets or []) if sets else []
        paths = dmod.expand_paths(files)
        if not paths:
            raise Abort("no design files found in " + " ".join(files))
        check_outputs(output, None, paths)
        designs, worst = engine.load_designs(paths, overrides, None, err, debug)
        for kind in sorted({d.kind for d in designs}):
            try:
                engine.check_model(model, kind)
            except ValueError as exc:
                raise Abort(str(exc)) from None
        records, status = engine.run(designs, Options(tol=tol, model=model, detail=True), say=err, debug=debug)
        worst = max(worst, status)
        if not records:
            return worst
        html = build(records, designs, {k for k, _ in overrides}, tol, model)
        if exe is not None:
            try:
                write_atomic(output, html_to_pdf(html, exe))
            except (OSError, ValueError) as exc:
                err(f"-o {clip(output)}: {exc}")
                return max(worst, EXIT_IO)
        else:
            write_atomic(output, html)
        return worst

    finish(body, debug)


@app.command("export", epilog=EXAMPLES["export"])
def export_cmd(
    file: str = typer.Argument(..., metavar="FILE", help="A pins or zstk design file (TOML)."),
    output: str = typer.Option(..., "--output", "-o", metavar="FILE",
                               help="FILE.dxf (needs the 'dxf' extra), FILE.svg or FILE.csv."),
    chord_tol: float = typer.Option(1e-3, "--chord-tol", metavar="MM", help="Largest distance of a chord from the "
                                    "curve it replaces [mm] (default 1 µm); arcs are written as exact arcs."),
    sets: Optional[List[str]] = O_SET,
    debug: bool = O_DEBUG,
):
    """The geometry to manufacture: pins, the satellite's tooth profile as made (cycloidal with its
    modifications, or circular arcs), the pin circle and the crank centre; zstk, the rings and rollers at the
    reported placement. Units: mm."""

    def body() -> int:
        from . import design as dmod
        from . import export as ex

        ext = os.path.splitext(output)[1].lower()
        if ext not in ex.FORMATS:
            raise Abort(f"-o {clip(output)}: export writes FILE.dxf, FILE.svg or FILE.csv")
        if not (0.0 < chord_tol <= 1.0):
            raise Abort(f"--chord-tol {chord_tol:g}: must be > 0 and <= 1 mm")
        check_outputs(output, None, [file])
        overrides = dmod.parse_set(sets or []) if sets else []
        d = dmod.load(file, overrides)
        for w in d.warnings:
            err(f"{dmod.display_name(file)}: warning: {w}")
        try:
            drawing = ex.drawing(d, chord_tol)
            data = ex.write(drawing, ext, chord_tol)
        except ex.ExportError as exc:
            raise Abort(f"{dmod.display_name(file)}: {exc}") from None
        write_atomic(output, data)
        return EXIT_OK

    finish(body, debug)


@app.command("accuracy", epilog=EXAMPLES["accuracy"])
def accuracy_cmd(
    kinds: Optional[List[str]] = typer.Argument(None, metavar="[KIND]...",
                                              help="Calculators to report (default: all): pins, zstk, rows."),
    tols: str = typer.Option("1e-3,1e-6,1e-9", "--tols",
                             help="Comma-separated tolerances to run every level at (what each --tol costs)."),
    budget: float = typer.Option(0.05, "--time-budget", min=0.0,
                                 help="Seconds of repeated calls per design, level and tolerance for the median "
                                      "time (after one warm-up call, which alone is the timing when it takes "
                                      "longer)."),
    detail: bool = typer.Option(False, "--detail", help="One row per suite design instead of one per level and tol."),
    fmt: Optional[str] = O_FORMAT,
    output: Optional[str] = O_OUTPUT,
    plot: Optional[str] = typer.Option(None, "--plot", help="Draw time against error (log axes, one curve per "
                                       "level) to this PNG file (needs the 'plot' extra)."),
    debug: bool = O_DEBUG,
):
    """Speed against error: every model level on the shipped suite of typical and hard designs.

    For each level and tolerance: median time per design, error against an independent high-resolution
    computation, the error the tool estimated, their ratio (honest when the error does not exceed the
    estimate), and the model error against the calculator's reference model. Exit 1 when an estimate
    was not honest."""

    def body() -> int:
        from . import accuracy as acc
        from .render import render_rows

        f = pick_format(fmt, output)
        check_outputs(output, plot)
        names = kinds or [k for k in registry.kinds() if k in acc.SPECS]
        for k in names:
            if k not in registry.kinds():
                raise Abort(f"accuracy {clip(k)}: unknown calculator; choose from " + ", ".join(registry.kinds())
                            + did_you_mean(k, list(registry.kinds())))
            if k not in acc.SPECS:
                raise Abort(f"accuracy {k}: the {k} calculator has no accuracy suite yet (gearcalc/accuracy.py)")
        try:
            tol_list = [float(t) for t in tols.split(",") if t.strip()]
        except ValueError:
            raise Abort(f"--tols {clip(tols)}: must be comma-separated numbers, e.g. 1e-3,1e-6,1e-9") from None
        if not tol_list:
            raise Abort("--tols: give at least one tolerance")
        for t in tol_list:
            check_tol(t)
        total = sum(len(acc.suite(k)) * len(registry.get(k).models) for k in names) * len(tol_list)
        bar = Progress(total, "runs")
        try:
            rows = acc.report(names, tol_list, budget, bar.advance)
        finally:
            bar.stop()
        out = rows if detail else acc.summarise(rows)
        title = "gearcalc accuracy: " + "; ".join(f"{k}: {acc.SPECS[k].quantity}" for k in names)
        notes: list[str] = []
        if not emit_text(lambda width, color: render_rows(out, f, title=title, width=width, color=color, notes=notes,
                                                          lift_key=0, keep=("honest",), choose=None), f, output):
            return EXIT_BUG
        for note in notes:
            err(note)
        if plot:
            from .plot import PLOT_HINT, plot_accuracy

            try:
                plot_accuracy(acc.summarise(rows), plot)
            except ImportError:
                err(PLOT_HINT)
                return EXIT_INPUT
        dishonest = [r for r in rows if r.get("honest") is False]
        for r in dishonest:
            err(f"accuracy: {r['kind']} {r['case']} at the {r['level']} level, tol {r['tol']:g}: the error "
                f"{r['error']:.3g} exceeds the estimate {r['error_est']:.3g}")
        return EXIT_CHECK if dishonest else EXIT_OK

    finish(body, debug)


@app.command("check", epilog=EXAMPLES["check"])
def check_cmd(
    paths: List[str] = typer.Argument(..., metavar="PATH...", help="Design files or folders."),
    sets: Optional[List[str]] = O_SET,
    resolved: bool = typer.Option(False, "--resolved",
                                  help="Print each valid design with every default filled in (also those the "
                                  "computation derives, such as the default allowable stress), as TOML."),
    debug: bool = O_DEBUG,
):
    """Validate design files only; print every problem found.

    check runs every check a run reports as bad input that follows from the design alone (the schema, the
    cross-key and geometric checks, the cost guards). It does not see --model or --tol, so these are
    reported by a run only: the pins disc-sum budget (it depends on --tol), the contact solve's "no contact
    carries the torque", geometries below floating-point resolution and a loss-ratio overflow."""

    def body() -> int:
        from . import design as dmod

        overrides = dmod.parse_set(sets or []) if sets else []
        files = dmod.expand_paths(paths)
        if not files:
            raise Abort("no design files found in " + " ".join(paths))
        from .engine import load_designs

        worst = EXIT_OK
        for f in files:  # file by file: each file's messages and its "ok" line in order
            designs, code = load_designs([f], overrides, None, err, debug)
            worst = max(worst, code)
            if not designs:
                continue
            d = designs[0]
            for w in d.warnings:
                err(f"{dmod.display_name(f)}: warning: {w}")
            if resolved:
                import tomli_w

                sys.stdout.write(f"# {dmod.display_name(f)}\n" + tomli_w.dumps(d.resolved(implicit=True)) + "\n")
            else:
                print(f"ok  {dmod.display_name(f)}  ({d.kind}: {d.name})")
        return worst

    finish(body, debug)


@app.command("new", epilog=EXAMPLES["new"])
def new_cmd(
    kind: str = typer.Argument(..., metavar="KIND", help="pins | zstk | rows"),
    output: Optional[str] = typer.Option(None, "--output", "-o", help="Write to this new file instead of stdout "
                                         "('-': stdout); an existing file is refused (it may be a design you "
                                         "edited) unless --force is given."),
    force: bool = typer.Option(False, "--force", help="With -o: replace an existing file."),
):
    """Print a complete, commented template design of that kind (every key, its unit, its default).

    Its first line, #:schema ./gearcalc-KIND.schema.json, points TOML editors (taplo) at the file that
    'gearcalc schema KIND -o gearcalc-KIND.schema.json' writes."""
    from .template import template

    finish(lambda: _write_kind_text("new", kind, output, force, template), False)


@app.command("schema", epilog=EXAMPLES["schema"])
def schema_cmd(
    kind: str = typer.Argument(..., metavar="KIND", help="pins | zstk | rows"),
    output: Optional[str] = typer.Option(None, "--output", "-o", help="Write to this new file instead of stdout "
                                         "('-': stdout); an existing file is refused unless --force is given."),
    force: bool = typer.Option(False, "--force", help="With -o: replace an existing file."),
):
    """Print the JSON Schema (draft 2020-12) of KIND's design files, for TOML editors: types, units, bounds, words,
    required and unknown keys (cross-key rules are checked by 'gearcalc check' only)."""
    from .schemajson import schema_text

    finish(lambda: _write_kind_text("schema", kind, output, force, schema_text), False)


def _write_kind_text(command: str, kind: str, output: Optional[str], force: bool, make) -> int:
    """Write ``make(calculator)`` for ``gearcalc new|schema KIND [-o FILE] [--force]``."""
    from .output import descriptor, to_file, write_stdout

    if kind not in registry.kinds():
        raise Abort(f"{command} {clip(kind)}: unknown kind; must be one of {', '.join(registry.kinds())}"
                    + did_you_mean(kind, list(registry.kinds())))
    check_output_path(output)
    if output and output != "-" and not force and descriptor(output) is None and os.path.isfile(output):
        raise Abort(f"{command} -o {output}: the file exists; add --force to replace it")
    text = make(registry.get(kind))
    if to_file(output):
        write_atomic(output, text)
    else:
        write_stdout(text)
    return EXIT_OK


def _stopped_by(exc: BaseException) -> KeyboardInterrupt | None:
    """The stop (Ctrl-C or a stop signal) during whose unwinding ``exc`` was raised, else None: the exceptions it
    was raised while handling (``__context__``), followed to the first KeyboardInterrupt."""
    seen = set()
    while exc is not None and id(exc) not in seen:
        if isinstance(exc, KeyboardInterrupt):
            return exc
        seen.add(id(exc))
        exc = exc.__context__
    return None


def finish(body, debug: bool) -> None:
    """Run a command body; map errors to exit codes; end quietly on a broken pipe."""
    try:
        code = body()
    except Abort as exc:
        err(f"gearcalc: {exc}")
        code = exc.code
    except BrokenPipeError:
        silence_stdout()
        code = EXIT_OK
    except KeyboardInterrupt as exc:  # Ctrl-C, or a stop signal (gearcalc.console.catch_stop_signals)
        from .console import interrupted_message, interrupted_status

        err(interrupted_message(exc))
        code = interrupted_status(exc)
    except Exception as exc:  # noqa: BLE001 - the last line of defence
        from .design import InputError
        from .output import OutputError, write_error

        stop = _stopped_by(exc)
        if stop is not None:  # raised while unwinding from a stop signal (a pool or an import cut short): the stop's
            from .console import interrupted_message, interrupted_status

            if debug:
                import traceback

                traceback.print_exc()
            err(interrupted_message(stop))
            raise typer.Exit(interrupted_status(stop)) from None
        if isinstance(exc, OSError) and write_error(exc):  # e.g. ENOSPC from a print to stdout
            exc = OutputError(exc.filename or "standard output", exc)
        if isinstance(exc, OutputError):  # the environment refused a write: not a bug
            err(f"gearcalc: {exc}")
            code = EXIT_IO
        elif isinstance(exc, InputError):
            for m in exc.messages:
                err(m)
            code = EXIT_INPUT
        else:
            if debug:
                import traceback

                traceback.print_exc()
            err("gearcalc: internal error; please report it with the command and design file "
                "(run with --debug for the traceback)")
            code = EXIT_BUG
    raise typer.Exit(code)


def main() -> None:
    from .console import catch_stop_signals

    catch_stop_signals()  # SIGTERM, SIGHUP, ...: unwind like Ctrl-C, so no temporary file is left behind
    if "--debug" not in sys.argv[1:]:
        # numpy's RuntimeWarnings (an overflow to inf in an intermediate whose limit is the right answer,
        # e.g. 1/(1+lambda)^2 -> 0) are not the user's to act on; a non-finite output is refused by the
        # renderer anyway. --debug shows them.
        import warnings

        warnings.filterwarnings("ignore", category=RuntimeWarning)
    everything = app.registered_commands
    app.registered_commands = _commands_to_build(sys.argv[1:], everything)
    try:
        app(prog_name="gearcalc")  # the same usage lines for `gearcalc` and `python -m gearcalc`
    except BrokenPipeError:
        silence_stdout()
        sys.exit(0)
    finally:
        app.registered_commands = everything


def _commands_to_build(args: list[str], commands: list) -> list:
    """The commands typer must build for this call: only the invoked one when the first argument names it.

    typer turns every registered command's signature into click parameters before it parses the
    arguments (~4 ms for the eight commands). ``gearcalc run ...`` needs only ``run``; an argument
    that is not a command name, an option before the command (``--version``, ``--help``) and shell
    completion (which lists every command) keep them all.
    """
    if not args or os.environ.get("_GEARCALC_COMPLETE"):
        return commands
    invoked = [c for c in commands if c.name == args[0]]
    return invoked or commands
