"""The command line: a thin layer that parses designs, calls the calculators and renders.

Start-up matters: this module imports typer (plain click help, no rich) and the light frame
modules only.  numpy is imported by the calculators when they compute; rich only when a table
is rendered.
"""
from __future__ import annotations

import os
import sys
from typing import List, Optional

import typer

from . import __version__, registry
from .calculator import DesignError, Options
from .console import _silence_stdout

EXIT_OK, EXIT_CHECK, EXIT_INPUT, EXIT_BUG = 0, 1, 2, 70

app = typer.Typer(
    name="gearcalc",
    help="Engineering calculator for gear and mechanism designers: KHV pin gearing losses (pins), "
    "closed rolling-body mechanisms (zstk), multi-row planetary load sharing (rows). "
    "Exit codes: 0 ok, 1 a design check failed, 2 bad usage or input, 70 internal error.",
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
    print(message, file=sys.stderr)


def _version(value: bool):
    if value:
        print(f"gearcalc {__version__}")
        raise typer.Exit()


@app.callback()
def _root(
    version: bool = typer.Option(False, "--version", callback=_version, is_eager=True,
                                 help="Print the version and exit."),
):
    """gearcalc: numbers you can trust, with their accuracy stated."""


# ---------------------------------------------------------------- shared options
FORMAT_HELP = ("Output format: table | csv | json (default: table on a terminal, else csv; "
               "with -o, from the file's extension).")
O_FORMAT = typer.Option(None, "--format", "-f", help=FORMAT_HELP)
O_DETAIL = typer.Option(False, "--detail",
                        help="Add the per-element tables (per pin and crank angle, per roller, per row).")
O_OUTPUT = typer.Option(None, "--output", "-o", help="Write to this file (atomically) instead of stdout.")
O_SET = typer.Option(None, "--set",
                     help="Override a design key for this run: KEY=VALUE with a dotted KEY (repeatable).")
O_TOL = typer.Option(1e-6, "--tol", help="Relative accuracy target for numerically computed results (0 < REL < 0.1).")
O_MODEL = typer.Option(None, "--model", help="Force a model level (see the calculator's levels); "
                       "default: the cheapest level the design needs.")
O_PLOT = typer.Option(None, "--plot", help="Draw the calculator's figure to this PNG file (needs the 'plot' extra).")
O_DEBUG = typer.Option(False, "--debug", help="Show the traceback of an internal error.")
O_JOBS = typer.Option(1, "--jobs", "-j", min=1, max=256,
                      help="Spread a batch or sweep over N processes; the results are identical to --jobs 1.")


def pick_format(fmt: Optional[str], output: Optional[str]) -> str:
    if fmt is not None:
        fmt = fmt.lower()
        if fmt not in ("table", "csv", "json"):
            raise Abort(f"--format {fmt}: must be one of table, csv, json"
                        + did_you_mean(fmt, ["table", "csv", "json"]))
        return fmt
    if output:
        ext = os.path.splitext(output)[1].lower()
        return {".json": "json", ".txt": "table"}.get(ext, "csv")
    return "table" if sys.stdout.isatty() else "csv"


def did_you_mean(word: str, choices: list[str]) -> str:
    from .design import _suggest

    return _suggest(word, choices)


def check_output_path(output: Optional[str]) -> None:
    """Fail before any computation when the output cannot be written."""
    if not output:
        return
    folder = os.path.dirname(os.path.abspath(output))
    if not os.path.isdir(folder):
        raise Abort(f"-o {output}: the folder {folder} does not exist")
    if os.path.isdir(output):
        raise Abort(f"-o {output}: is a directory")
    if not os.access(folder, os.W_OK):
        raise Abort(f"-o {output}: the folder {folder} is not writable")


def write_atomic(path: str, text: str) -> None:
    """Write text to path via a temporary file in the same folder and a rename."""
    import tempfile

    folder = os.path.dirname(os.path.abspath(path))
    fd, tmp = tempfile.mkstemp(dir=folder, prefix="." + os.path.basename(path) + ".", suffix=".tmp")
    try:
        with os.fdopen(fd, "w", encoding="utf-8", newline="") as fh:
            fh.write(text)
            fh.flush()
            os.fsync(fh.fileno())
        os.replace(tmp, path)
    except BaseException:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise


def emit_text(render_fn, fmt: str, output: Optional[str]) -> bool:
    """Render (width and colour from the terminal) and write to stdout or atomically to -o.

    Returns False, after an error message, when the calculator produced a non-finite value (a bug).
    """
    from .render import NonFiniteOutput

    terminal = fmt == "table" and not output and sys.stdout.isatty()
    try:
        text = render_fn(os.get_terminal_size().columns if terminal else None,
                         terminal and "NO_COLOR" not in os.environ)
    except NonFiniteOutput as exc:
        err(f"internal error: {exc}; please report it with the design file")
        return False
    if output:
        write_atomic(output, text)
    else:
        sys.stdout.write(text)
        sys.stdout.flush()
    return True


def check_tol(tol: float) -> None:
    if not (0.0 < tol < 0.1):
        raise Abort(f"--tol {tol}: must be > 0 and < 0.1 (a relative accuracy, e.g. 1e-6)")


def compute_files(paths: List[str], kind_hint: Optional[str], fmt: Optional[str], detail: bool,
                  output: Optional[str], sets: Optional[List[str]], tol: float, model: Optional[str],
                  plot: Optional[str], debug: bool, jobs: int = 1) -> int:
    """The body of every computing command; returns the exit code."""
    from . import design as dmod

    fmt = pick_format(fmt, output)
    check_tol(tol)
    check_output_path(output)
    if plot:
        check_output_path(plot)
    overrides = dmod.parse_set(sets or []) if sets else []
    files = dmod.expand_paths(paths)
    if not files:
        raise Abort("no design files found in " + " ".join(paths))
    if files.count("-") > 1:
        raise Abort("'-' (standard input) can be given once")
    worst = EXIT_OK
    designs = []
    for f in files:
        try:
            d = dmod.load(f, overrides, kind_hint)
        except dmod.InputError as exc:
            for w in exc.warnings:
                err(w)
            for m in exc.messages:
                err(m)
            worst = max(worst, EXIT_INPUT)
            continue
        designs.append(d)
    if model is not None:
        for d in designs:
            calc = registry.get(d.kind)
            if model not in calc.models:
                raise Abort(f"--model {model}: a {d.kind} design has the levels " + ", ".join(calc.models)
                            + did_you_mean(model, list(calc.models)))
    opts = Options(tol=tol, model=model, detail=detail)
    records = []
    advance, stop = _progress(len(designs) * 20)  # a bar only for long batches on a terminal
    try:
        worst = _compute_all(designs, opts, records, worst, debug, advance, jobs)
    finally:
        stop()
    return _emit(records, fmt, detail, output, plot, worst)


def compute_one(d, opts, debug: bool = False):
    """Compute one validated design: (result or None, stderr lines, exit code).

    Prints nothing itself, so that ``--jobs`` workers and the main process report identically.
    """
    try:
        outcome = registry.get(d.kind).compute(d, opts)
    except Exception as exc:
        outcome = exc
    return report_one(d, outcome, debug)


def report_one(d, outcome, debug: bool = False):
    """(result or None, stderr lines, exit code) of a design from its Result or the exception it raised."""
    from . import design as dmod

    where = dmod.display_name(d.source)
    lines = [f"{where}: warning: {w}" for w in d.warnings]
    if isinstance(outcome, DesignError):
        lines.append(f"{where}: {outcome.key}: {outcome.message}" if outcome.key else f"{where}: {outcome.message}")
        return None, lines, EXIT_INPUT
    if isinstance(outcome, BaseException):
        if debug:
            import traceback

            lines.append("".join(traceback.format_exception(outcome)).rstrip())
        lines.append(f"{where}: internal error in the {d.kind} calculator; please report it with this design "
                     "file (run with --debug for the traceback)")
        return None, lines, EXIT_BUG
    result = outcome
    lines += [f"{where}: warning: {w}" for w in result.warnings]
    lines += [f"{where}: check failed: {f}" for f in result.failed]
    return result, lines, EXIT_CHECK if result.failed else EXIT_OK


BATCH_CHUNK = 512
"""Designs per batch call: bounds memory and keeps a progress bar moving."""


def compute_batched(designs, opts, debug: bool = False):
    """Outcomes of many designs in one process, in the order of ``designs``: each kind with a ``batch`` hook
    computes its designs together (numpy over designs), the others one by one."""
    outcomes: list = [None] * len(designs)
    by_kind: dict[str, list[int]] = {}
    for k, d in enumerate(designs):
        by_kind.setdefault(d.kind, []).append(k)
    for kind, idx in by_kind.items():
        batch = registry.get(kind).batch
        if batch is not None and len(idx) > 1:
            try:
                results = batch([designs[k] for k in idx], opts)
            except Exception:  # a bug in the batch path: fall back to one by one, which reports per design
                results = None
            if results is not None and len(results) == len(idx):
                for k, res in zip(idx, results):
                    outcomes[k] = report_one(designs[k], res, debug)
                continue
        for k in idx:
            outcomes[k] = compute_one(designs[k], opts, debug)
    return outcomes


def _outcomes(designs, opts, debug):
    """Outcomes in order, computed a chunk at a time (so that a progress bar moves)."""
    for start in range(0, len(designs), BATCH_CHUNK):
        yield from compute_batched(designs[start:start + BATCH_CHUNK], opts, debug)


def _compute_all(designs, opts, records, worst, debug, advance, jobs: int = 1) -> int:
    from .render import Record

    if jobs > 1 and len(designs) > 1:
        from concurrent.futures import ProcessPoolExecutor

        pool = ProcessPoolExecutor(max_workers=jobs)
        size = max(1, -(-len(designs) // (4 * jobs)))
        chunks = [designs[k:k + size] for k in range(0, len(designs), size)]
        outcomes = (o for part in pool.map(compute_batched, chunks, [opts] * len(chunks), [debug] * len(chunks))
                    for o in part)
    else:
        pool = None
        outcomes = _outcomes(designs, opts, debug)
    try:
        for d, (result, lines, code) in zip(designs, outcomes):
            if advance:
                advance(20)
            for line in lines:
                err(line)
            worst = max(worst, code)
            if result is not None:
                records.append(Record(d.source, d.kind, d.name, d.resolved(), result))
    finally:
        if pool is not None:
            pool.shutdown(cancel_futures=True)
    return worst


def _emit(records, fmt, detail, output, plot, worst) -> int:
    from .render import render

    if records:
        if not emit_text(lambda width, color: render(records, fmt, detail, width=width, color=color), fmt, output):
            return EXIT_BUG
        if plot:
            from .plot import plot_records

            try:
                plot_records(records, plot)
            except ImportError:
                err("--plot needs matplotlib: pip install 'gearcalc[plot]'")
                worst = max(worst, EXIT_INPUT)
    return worst


def _kind_command(kind: str, summary: str):
    def command(
        files: List[str] = typer.Argument(..., metavar="FILE...",
                                          help="Design files (TOML); '-' reads standard input."),
        fmt: Optional[str] = O_FORMAT,
        detail: bool = O_DETAIL,
        output: Optional[str] = O_OUTPUT,
        sets: Optional[List[str]] = O_SET,
        tol: float = O_TOL,
        model: Optional[str] = O_MODEL,
        plot: Optional[str] = O_PLOT,
        debug: bool = O_DEBUG,
        jobs: int = O_JOBS,
    ):
        finish(lambda: compute_files(files, kind, fmt, detail, output, sets, tol, model, plot, debug, jobs), debug)

    command.__doc__ = summary
    command.__name__ = kind
    return command


KIND_HELP = {
    "pins": "KHV pin gearing: per-pin friction losses, cycle-averaged losses, efficiency.",
    "zstk": "Closed rolling-body mechanism: roller chain, closure correction, roller loads, contact stresses, "
            "strength check.",
    "rows": "Multi-row planetary gear: row load sharing K, carrier bridge widths, relative mass.",
}
for _kind, _help in KIND_HELP.items():
    app.command(_kind, help=_help)(_kind_command(_kind, _help))


@app.command("run")
def run_cmd(
    paths: List[str] = typer.Argument(
        ..., metavar="PATH...", help="Design files or folders (every *.toml below a folder); '-' reads stdin."),
    fmt: Optional[str] = O_FORMAT,
    detail: bool = O_DETAIL,
    output: Optional[str] = O_OUTPUT,
    sets: Optional[List[str]] = O_SET,
    tol: float = O_TOL,
    model: Optional[str] = O_MODEL,
    plot: Optional[str] = O_PLOT,
    debug: bool = O_DEBUG,
    jobs: int = O_JOBS,
):
    """Compute any design files, dispatching on their `kind`."""
    finish(lambda: compute_files(paths, None, fmt, detail, output, sets, tol, model, plot, debug, jobs), debug)


@app.command("sweep")
def sweep_cmd(
    file: str = typer.Argument(..., metavar="FILE", help="One design file ('-' reads standard input)."),
    vary: List[str] = typer.Option(..., "--vary", help="KEY=SPEC: an axis of the grid; SPEC is start:stop:step "
                                   "or v1,v2,...; several --vary make a product grid (the first varies slowest)."),
    fmt: Optional[str] = O_FORMAT,
    output: Optional[str] = O_OUTPUT,
    sets: Optional[List[str]] = O_SET,
    tol: float = O_TOL,
    model: Optional[str] = O_MODEL,
    plot: Optional[str] = O_PLOT,
    debug: bool = O_DEBUG,
    jobs: int = O_JOBS,
):
    """Evaluate one design over a grid of key values; one output row per point."""

    def body() -> int:
        from . import design as dmod
        from . import sweep as sw
        from .render import render_rows

        f = pick_format(fmt, output)
        check_tol(tol)
        check_output_path(output)
        if plot:
            check_output_path(plot)
        try:
            axes = sw.parse_vary(vary)
            raw = dmod.read_toml(file)
            if sets:
                dmod.apply_set(raw, dmod.parse_set(sets))
            kind = raw.get("kind")
            if model is not None and kind in registry.kinds() and model not in registry.get(kind).models:
                levels = list(registry.get(kind).models)
                raise Abort(f"--model {model}: a {kind} design has the levels " + ", ".join(levels)
                            + did_you_mean(model, levels))
            progress, stop = _progress(math_prod(len(v) for v in axes.values()))
            try:
                rows = sw.evaluate(raw, file, axes, Options(tol=tol, model=model), progress, jobs)
            finally:
                stop()
        except sw.SweepError as exc:
            raise Abort(f"{dmod.display_name(file)}: {exc}") from None
        title = f"gearcalc sweep {dmod.display_name(file)}"
        if not emit_text(lambda width, color: render_rows(rows, f, title=title, width=width, color=color), f, output):
            return EXIT_BUG
        if plot:
            try:
                from .plot import plot_sweep

                plot_sweep(raw.get("kind"), rows.rows() if hasattr(rows, "rows") else rows, list(axes), plot)
            except ImportError:
                err("--plot needs matplotlib: pip install 'gearcalc[plot]'")
                return EXIT_INPUT
        return EXIT_OK

    finish(body, debug)


def math_prod(values) -> int:
    out = 1
    for v in values:
        out *= v
    return out


def _progress(total: int, always: bool = False):
    """A rich progress bar on stderr for long runs on a terminal; (advance, stop) callables.

    Shown for ``total`` >= 2000 units (about a second of work) or when ``always``; never when stderr
    is not a terminal."""
    if (total < 2000 and not always) or not sys.stderr.isatty():
        return None, lambda: None
    from rich.progress import Progress

    bar = Progress(transient=True, console=None)
    bar.start()
    task = bar.add_task("computing", total=total)
    return (lambda k: bar.advance(task, k)), bar.stop


@app.command("accuracy")
def accuracy_cmd(
    kinds: Optional[List[str]] = typer.Argument(None, metavar="[KIND]...",
                                              help="Calculators to report (default: all): pins, zstk, rows."),
    tols: str = typer.Option("1e-3,1e-6,1e-9", "--tols",
                             help="Comma-separated tolerances to run every level at (what each --tol costs)."),
    budget: float = typer.Option(0.25, "--time-budget", min=0.0,
                                 help="Seconds of repeated calls per design, level and tolerance for the median "
                                      "time (after one warm-up call; at least one timed call)."),
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
        check_output_path(output)
        if plot:
            check_output_path(plot)
        names = kinds or list(KIND_HELP)
        for k in names:
            if k not in registry.kinds():
                raise Abort(f"accuracy {k}: unknown calculator; choose from " + ", ".join(registry.kinds())
                            + did_you_mean(k, list(registry.kinds())))
        try:
            tol_list = [float(t) for t in tols.split(",") if t.strip()]
        except ValueError:
            raise Abort(f"--tols {tols}: must be comma-separated numbers, e.g. 1e-3,1e-6,1e-9") from None
        if not tol_list:
            raise Abort("--tols: give at least one tolerance")
        for t in tol_list:
            check_tol(t)
        total = sum(len(acc.suite(k)) * len(registry.get(k).models) for k in names) * len(tol_list)
        advance, stop = _progress(total, always=True)
        try:
            rows = acc.report(names, tol_list, budget, advance)
        finally:
            stop()
        out = rows if detail else acc.summarise(rows)
        title = "gearcalc accuracy: " + "; ".join(f"{k}: {acc.SPECS[k].quantity} vs {acc.SPECS[k].reference}"
                                                  for k in names)
        if not emit_text(lambda width, color: render_rows(out, f, title=title, width=width, color=color), f, output):
            return EXIT_BUG
        if plot:
            try:
                from .plot import plot_accuracy

                plot_accuracy(acc.summarise(rows), plot)
            except ImportError:
                err("--plot needs matplotlib: pip install 'gearcalc[plot]'")
                return EXIT_INPUT
        dishonest = [r for r in rows if r.get("honest") is False]
        for r in dishonest:
            err(f"accuracy: {r['kind']} {r['case']} at the {r['level']} level, tol {r['tol']:g}: the error "
                f"{r['error']:.3g} exceeds the estimate {r['error_est']:.3g}")
        return EXIT_CHECK if dishonest else EXIT_OK

    finish(body, debug)


@app.command("check")
def check_cmd(
    paths: List[str] = typer.Argument(..., metavar="PATH...", help="Design files or folders."),
    sets: Optional[List[str]] = O_SET,
    resolved: bool = typer.Option(False, "--resolved",
                                  help="Print each valid design with every default filled in, as TOML."),
    debug: bool = O_DEBUG,
):
    """Validate design files only; print every problem found."""

    def body() -> int:
        from . import design as dmod

        overrides = dmod.parse_set(sets or []) if sets else []
        files = dmod.expand_paths(paths)
        if not files:
            raise Abort("no design files found in " + " ".join(paths))
        worst = EXIT_OK
        for f in files:
            try:
                d = dmod.load(f, overrides)
            except dmod.InputError as exc:
                for m in exc.warnings + exc.messages:
                    err(m)
                worst = EXIT_INPUT
                continue
            for w in d.warnings:
                err(f"{dmod.display_name(f)}: warning: {w}")
            if resolved:
                import tomli_w

                sys.stdout.write(f"# {dmod.display_name(f)}\n" + tomli_w.dumps(d.resolved()) + "\n")
            else:
                print(f"ok  {dmod.display_name(f)}  ({d.kind}: {d.name})")
        return worst

    finish(body, debug)


@app.command("new")
def new_cmd(
    kind: str = typer.Argument(..., metavar="KIND", help="pins | zstk | rows"),
    output: Optional[str] = O_OUTPUT,
):
    """Print a complete, commented template design of that kind (every key, its unit, its default)."""

    def body() -> int:
        from .template import template

        if kind not in registry.kinds():
            raise Abort(f"new {kind}: unknown kind; must be one of {', '.join(registry.kinds())}"
                        + did_you_mean(kind, list(registry.kinds())))
        check_output_path(output)
        text = template(registry.get(kind))
        if output:
            write_atomic(output, text)
        else:
            sys.stdout.write(text)
        return EXIT_OK

    finish(body, False)


def finish(body, debug: bool) -> None:
    """Run a command body; map errors to exit codes; end quietly on a broken pipe."""
    try:
        code = body()
    except Abort as exc:
        err(f"gearcalc: {exc}")
        code = exc.code
    except BrokenPipeError:
        _silence_stdout()
        code = EXIT_OK
    except KeyboardInterrupt:
        err("gearcalc: interrupted")
        code = 130
    except Exception as exc:  # noqa: BLE001 - the last line of defence
        from .design import InputError

        if isinstance(exc, InputError):
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


def _terminate(signum, frame):  # SIGTERM: unwind like Ctrl-C, so no temporary file is left behind
    raise KeyboardInterrupt


def main() -> None:
    import signal

    try:
        signal.signal(signal.SIGTERM, _terminate)
    except (ValueError, OSError):  # not in the main thread
        pass
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
        _silence_stdout()
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
