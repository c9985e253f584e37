"""Rendering of results: one module for every calculator and every format.

* ``json``: one object per design (an array for several), with ``summary``, the resolved
  ``design``, ``warnings``, ``checks_failed``, ``model`` and, with ``--detail``, ``detail``.
* ``csv``: a header and one row per design; the header is the union of the designs' fields in
  first-seen order (missing cells empty).  A batch of several kinds gets a leading ``kind``
  column.  With ``--detail`` the CSV holds the detail rows instead, in long form: (``kind``,)
  ``name``, ``table``, then the union of the detail columns.
* ``table``: rich tables for a terminal; the summary has one column per design and the unit of
  each quantity in its own column; detail tables carry units in their column headers.

Numbers are written in full precision (``repr``) in CSV and JSON, so the two agree exactly;
``None`` is ``null`` in JSON, an empty cell in CSV and ``n/a`` in a table.  rich is imported
only by the table renderer.
"""
from __future__ import annotations

import csv
import dataclasses
import functools
import io
import json
import math
import re
from dataclasses import dataclass
from typing import Any

from .calculator import Result
from .units import split_unit, unit_of

FORMATS = ("table", "csv", "json")


@dataclass
class Record:
    """One computed design: where it came from, the resolved design and its result."""

    source: str
    kind: str
    name: str
    design: dict
    result: Result


class NonFiniteOutput(RuntimeError):
    """A calculator produced NaN or infinity: a bug, never printed as a result."""


def plain(value: Any, where: str = "") -> Any:
    """Convert numpy scalars/arrays to plain Python; refuse NaN and infinity."""
    if hasattr(value, "tolist"):
        value = value.tolist()
    if isinstance(value, float):
        if not math.isfinite(value):
            raise NonFiniteOutput(f"non-finite value {value!r} in output field {where!r}")
        return value
    if isinstance(value, (list, tuple)):
        return [plain(v, where) for v in value]
    if isinstance(value, dict):
        return {k: plain(v, f"{where}.{k}" if where else k) for k, v in value.items()}
    return value


def to_json_obj(rec: Record, detail: bool) -> dict:
    obj = {
        "file": rec.source if rec.source != "-" else "<stdin>",
        "kind": rec.kind,
        "name": rec.name,
        "model": rec.result.model,
        "summary": plain(rec.result.summary),
        "warnings": list(rec.result.warnings),
        "checks_failed": list(rec.result.failed),
        "design": plain(rec.design),
    }
    if detail:
        obj["detail"] = plain(rec.result.detail)
    return obj


def render_json(records: list[Record], detail: bool = False, array: bool | None = None) -> str:
    """JSON: an object for one design, an array for several; ``array=True`` (a folder or several paths on the
    command line) makes it an array always, ``False`` an object for one design."""
    objs = [to_json_obj(r, detail) for r in records]
    data = objs[0] if len(objs) == 1 and not array else objs
    return json.dumps(data, indent=2, ensure_ascii=False, allow_nan=False) + "\n"


def csv_cell(value: Any) -> str:
    if type(value) is float:  # the common case first: a sweep writes millions of these
        if value - value != 0.0:
            raise NonFiniteOutput(f"non-finite value {value!r} in CSV output")
        return repr(value)
    value = plain(value)
    if value is None:
        return ""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return repr(value)
    if isinstance(value, list):
        return " ".join(csv_cell(v) for v in value)
    return neutralise(value) if isinstance(value, str) else str(value)


FORMULA_START = ("=", "+", "-", "@", "\t", "\r")
"""A CSV text cell starting with one of these would be read as a formula by a spreadsheet."""


def neutralise(text: str) -> str:
    """A CSV text cell a spreadsheet will not run as a formula: one starting with ``= + - @``, a tab or a
    carriage return gets a leading apostrophe (OWASP's CSV-injection rule, as csvkit and LibreOffice read
    it).  Numbers are never text cells, so a negative number keeps its sign.

    >>> neutralise("=HYPERLINK(1)"), neutralise("-x"), neutralise("Fig. 3")
    ("'=HYPERLINK(1)", "'-x", 'Fig. 3')
    """
    return "'" + text if text.startswith(FORMULA_START) else text


def _union(rows: list[dict]) -> list[str]:
    cols: dict[str, None] = {}
    for row in rows:
        for k in row:
            cols.setdefault(k, None)
    return list(cols)


def write_csv(rows: list[dict]) -> str:
    buf = io.StringIO()
    cols = _union(rows)
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(cols)
    get = [(c,) for c in cols]
    for row in rows:
        w.writerow([csv_cell(row.get(c)) for (c,) in get])
    return buf.getvalue()


def render_csv(records: list[Record], detail: bool = False, joined: bool = False) -> str:
    """One CSV: the summaries (or, with ``detail``, the detail rows in long form; ``joined``: each row with its
    design's summary fields after ``name`` and ``table``, as ``--detail --fields`` asks).  A batch of several
    kinds gets a leading ``kind`` column and the union of the kinds' columns (cells of another kind's
    fields empty)."""
    mixed = len({r.kind for r in records}) > 1
    if not detail:
        if mixed:
            return write_csv([{"kind": r.kind, **r.result.summary} for r in records])
        return write_csv([r.result.summary for r in records])
    rows = []
    for r in records:
        lead = {"kind": r.kind} if mixed else {}
        extra = {k: v for k, v in r.result.summary.items() if k != "name"} if joined else {}
        for table, trows in r.result.detail.items():
            rows.extend({**lead, "name": r.name, "table": table, **extra, **row} for row in trows)
    return write_csv(rows) if rows else "name,table\n"


def fmt_number(x: float) -> str:
    """A number with 6 significant digits: a table cell's (:func:`fmt_value`) and a message's.

    >>> fmt_number(1.4909365e-16), fmt_number(57.199999999999996)
    ('1.49094e-16', '57.2')
    """
    return f"{x:.6g}"


def fmt_value(value: Any) -> str:
    """Format a value for a table cell (6 significant digits, :func:`fmt_number`).

    >>> fmt_value(1.4909365e-16), fmt_value(True), fmt_value(None), fmt_value([1, 2])
    ('1.49094e-16', 'yes', 'n/a', '1 2')
    """
    value = plain(value)
    if value is None:
        return "n/a"
    if isinstance(value, bool):
        return "yes" if value else "no"
    if isinstance(value, float):
        return fmt_number(value)
    if isinstance(value, list):
        return " ".join(fmt_value(v) for v in value) or "-"
    return str(value)


# ----------------------------------------------------------------------------- field selection
ALL_FIELDS = "all"


def parse_fields(text: str | None) -> list[str] | None:
    """``--fields a,b,c`` as a list (``None`` for the default, ``["all"]`` for every field).

    >>> parse_fields("K, K_exact,,bridges_feasible"), parse_fields(None), parse_fields("all")
    (['K', 'K_exact', 'bridges_feasible'], None, ['all'])
    """
    if text is None:
        return None
    return [f.strip() for f in text.split(",") if f.strip()]


FILE_FIELD = "file"
"""``--fields file``: the design's file (``<stdin>`` for standard input), a column of a batch's table or CSV beside the
summary fields (not one of them: ``--fields all`` leaves it out, JSON has it beside the summary)."""


def unknown_fields(requested: list[str] | None, available: list[str], extra: tuple = ("name",)) -> list[str]:
    """Messages for requested fields that no result has (each with a did-you-mean); ``extra``: fields always
    there (``name``; ``file`` for a batch)."""
    if not requested or requested == [ALL_FIELDS]:
        return []
    import difflib

    have = set(available) | set(extra)
    available = list(available) + [f for f in extra if f not in available]
    out = []
    for f in requested:
        if f not in have:
            close = difflib.get_close_matches(f[:100], available, n=1, cutoff=0.6)
            out.append(f"--fields {f[:60]}: no such output field" + (f" (did you mean '{close[0]}'?)" if close else ""))
    return out


def select(names: list[str], requested: list[str] | None, default: list[str] | None, lead=("name",)) -> list[str]:
    """The fields to show, in order: ``lead`` first, then the requested ones (or the default ones, or all).

    >>> select(["name", "a", "b", "c"], None, ["c", "a"])
    ['name', 'c', 'a']
    >>> select(["name", "a", "b"], ["all"], None), select(["name", "a", "b"], ["b"], ["a"])
    (['name', 'a', 'b'], ['name', 'b'])
    """
    have = set(names)
    if requested == [ALL_FIELDS] or (requested is None and default is None):
        return list(names)
    wanted = requested if requested is not None else default
    out = [f for f in lead if f in have]
    out += [f for f in wanted if f in have and f not in out]
    return out


def filter_summary(summary: dict, fields: list[str] | None) -> dict:
    """The summary restricted to ``--fields`` (``name`` kept first); all of it without ``--fields``."""
    if fields is None or fields == [ALL_FIELDS]:
        return summary
    return {k: summary[k] for k in select(list(summary), fields, None)}


# ----------------------------------------------------------------------------- terminal tables
NAME_MIN = 12
"""A design name column is never narrower than this (it is elided with "…" beyond)."""
LONG_TEXT = 28
"""A text column whose cells are longer than this goes above the table (once per distinct value)."""


def _header_lines(field: str, width: int) -> list[str]:
    """A column header: the field's name wrapped at underscores to ``width``, then ``[unit]``.

    >>> _header_lines("sigma_max_roller_radius_mm", 10)
    ['sigma_max_', 'roller_', 'radius', '[mm]']
    """
    base, unit = split_unit(field)
    lines, cur = [], ""
    for part in re.split(r"(?<=_)", base):
        if cur and len(cur) + len(part) > width:
            lines.append(cur)
            cur = part
        else:
            cur += part
    lines.append(cur)
    return lines + ([f"[{unit}]"] if unit else [])


def _cells(text: str) -> int:
    """Terminal cells a text takes (a wide character takes two, a combining one none)."""
    from rich.cells import cell_len

    return cell_len(text)


def _column_width(field: str, cells: list[str]) -> int:
    base, unit = split_unit(field)
    data = max(map(_cells, cells), default=1)
    longest_part = max(map(len, re.split(r"(?<=_)", base)), default=1)
    return max(data, len(unit) + 2 if unit else 0, min(len(base), max(data, 10)), longest_part)


def _head(text: str, width: int) -> str:
    """The longest start of ``text`` that takes at most ``width`` terminal cells."""
    out = ""
    for ch in text:
        if _cells(out + ch) > width:
            break
        out += ch
    return out


def _elide(text: str, width: int, middle: bool = False) -> str:
    """``text`` cut to ``width`` terminal cells with "…" at the end (``middle``: in the middle, which keeps the
    part where names of variants usually differ).

    >>> _elide("Bridge table, n = 3, B = 3, i = 10", 20, middle=True), _elide("abcdef", 4)
    ('Bridge tab…3, i = 10', 'abc…')
    """
    if _cells(text) <= width:
        return text
    if middle and width >= 8:
        tail = (width - 1) // 2
        end = _head(text[::-1], tail)[::-1]
        return _head(text, width - 1 - _cells(end)) + "…" + end
    return _head(text, max(width - 1, 0)) + "…"


_TOKEN = re.compile(r"\S+ = \S+\s*|\S+\s*")
"""A word of a design name with its trailing space; ``u = 10`` is one word (a key and its value)."""


def _core(token: str) -> str:
    return token.strip().rstrip(",;")


def _matches(runs: list, start: bool, end: bool, toks: list) -> bool:
    """Whether a name's words ``toks`` fit a label's runs of kept words (``start``/``end``: the label begins/ends
    with a kept word; each "…" stands for at least one word).

    >>> _matches([["a"], ["c"]], True, False, ["a", "b", "c", "d"]), _matches([["a"], ["c"]], True, True, ["a", "c"])
    (True, False)
    """
    n, pos = len(toks), 0
    for r, run in enumerate(runs):
        size, first, last = len(run), r == 0, r == len(runs) - 1
        lo = 0 if first and start else pos + 1
        hi = 0 if first and start else n - size - (1 if last and not end else 0)
        if last and end:
            lo = max(lo, n - size)
            hi = min(hi, n - size)
        for s in range(lo, hi + 1):
            if toks[s:s + size] == run:
                pos = s + size
                break
        else:
            return False
    return True


def _label(tokens: list, kept: list[int]) -> str:
    out, prev = "", -1
    for t in kept:
        if t != prev + 1:
            out = out.rstrip(" ,;") + "…"
        out += tokens[t]
        prev = t
    if prev != len(tokens) - 1:
        out = out.rstrip(" ,;") + "…"
    return out.rstrip()


MAX_TOLD_APART = 2000
"""Tables of more distinct design names than this cut them in the middle (telling them apart costs about a
millisecond per name)."""


@functools.lru_cache(maxsize=4)
def _shortenings(distinct: tuple) -> list[list[str]]:
    """Per name, its labels from the whole name to the shortest that tells it apart (:func:`_distinct_labels`):
    the same order at every width, so one pass serves the layout and the rows."""
    tokens = [_TOKEN.findall(n) or [n] for n in distinct]
    cores = [[_core(t) for t in toks] for toks in tokens]
    posting: dict[str, set] = {}
    for i, cs in enumerate(cores):
        for c in cs:
            posting.setdefault(c, set()).add(i)
    out = []
    for i, (name, toks, cs) in enumerate(zip(distinct, tokens, cores)):
        kept, steps = list(range(len(toks))), [name]
        while len(kept) > 1:
            edge = set(kept) - {t for t in kept if t - 1 in kept and t + 1 in kept}
            edge |= {0, len(toks) - 1} & set(kept)
            for t in sorted(kept, key=lambda t: (t not in edge, -len(posting[cs[t]]), t)):
                trial = [k for k in kept if k != t]
                runs, cur = [], []
                for k in trial:
                    if cur and k != cur[-1] + 1:
                        runs.append([cs[j] for j in cur])
                        cur = []
                    cur.append(k)
                runs.append([cs[j] for j in cur])
                rivals = set.intersection(*sorted((posting[cs[k]] for k in trial), key=len)) - {i}
                if not any(_matches(runs, trial[0] == 0, trial[-1] == len(toks) - 1, cores[j]) for j in rivals):
                    kept = trial
                    steps.append(_label(toks, kept))
                    break
            else:
                break
        out.append(steps)
    return out


def _distinct_labels(names: list[str], width: int) -> list[str]:
    """Labels of at most ``width`` cells that tell the names apart: the words a name shares with other names become
    "…" (those at an end of what is left first, so that the label has few "…"; of those, the most common first)
    while the label still fits only its own name (a label never fits another name, so labels of distinct names
    differ); what is still too wide is cut in the middle.  ``width`` 0: every word is dropped that can be (the
    narrowest labels that tell the names apart).

    >>> _distinct_labels(["Paper: cycloidal, u = 10, fixed pins", "Paper: cycloidal, u = 30, fixed pins",
    ...                   "Paper: circular-arc, u = 10, fixed pins"], 24)
    ['…cycloidal, u = 10…', '…cycloidal, u = 30…', '…circular-arc, u = 10…']
    """
    distinct = list(dict.fromkeys(names))
    if len(distinct) > MAX_TOLD_APART:
        return [_elide(n, width, middle=True) if width else n for n in names]
    shorter = _shortenings(tuple(distinct))
    out = {}
    for name, steps in zip(distinct, shorter):
        label = next((s for s in steps if _cells(s) <= width), steps[-1])
        out[name] = _elide(label, width, middle=True) if width else label
    return [out[n] for n in names]


@dataclass
class Grid2D:
    """A table's content before layout: field names, cell texts, which columns are text (left-aligned)."""

    fields: list[str]
    cells: list[list[str]]
    text: list[bool]


def _layout(grid: Grid2D, width: int | None, elastic: int | None = 0, name_min: int = NAME_MIN):
    """Column widths that fit ``width`` (None: no limit): whole columns from the left while they fit; the
    ``elastic`` column (the design name) shrinks to ``name_min`` (at least :data:`NAME_MIN`: the width at which
    the names are still told apart) first.  Returns (widths, shown)."""
    widths = [_column_width(f, [row[j] for row in grid.cells]) for j, f in enumerate(grid.fields)]
    if width is None:
        return widths, len(widths)
    sep = 3  # a column separator and its padding

    def total(k):
        return sum(widths[:k]) + sep * (k - 1)

    name_min = max(NAME_MIN, min(name_min, width))
    if elastic is not None and total(len(widths)) > width and widths[elastic] > name_min:
        widths[elastic] = max(name_min, widths[elastic] - (total(len(widths)) - width))
    shown = len(widths)
    while shown > 1 and total(shown) > width:
        shown -= 1
    if total(shown) > width and elastic == 0:  # even the name alone is too wide: elide it to the width
        widths[0] = max(1, width)
    return widths, shown


def _lift_long_text(grid: Grid2D, key_col: int | None = None) -> tuple[Grid2D, list[str]]:
    """Move text columns with long cells out of the table into lines above it (once per distinct value)."""
    keep, lines = [], []
    for j, f in enumerate(grid.fields):
        col = [row[j] for row in grid.cells]
        if grid.text[j] and j != key_col and j != 0 and max(map(len, col), default=0) > LONG_TEXT:
            distinct = list(dict.fromkeys(col))
            if len(distinct) == 1:
                lines.append(f"{f}: {distinct[0]}")
            elif key_col is not None and len(distinct) <= 8:
                seen = dict.fromkeys((row[key_col], row[j]) for row in grid.cells)
                lines += [f"{f} ({k}): {v}" for k, v in seen]
            else:
                keep.append(j)
                continue
        else:
            keep.append(j)
    if len(keep) == len(grid.fields):
        return grid, []
    return Grid2D([grid.fields[j] for j in keep], [[row[j] for j in keep] for row in grid.cells],
                  [grid.text[j] for j in keep]), lines


def layout_table(grid: Grid2D, width: int | None, title: str = "", notes: list | None = None,
                 what: str = "columns", elastic: int | None = 0, lift_key: int | None = None,
                 above: tuple = (), keep: tuple = (), choose: str | None = "--fields"):
    """A rich renderable for a grid: units in headers, one line per row, no cell ever wrapped.

    Columns that do not fit ``width`` are left out and a note (for stderr) says which and how to see them
    (``choose``: the option that chooses columns, None when there is none); a column named in ``keep`` stays,
    moved left before the columns left out.
    """
    from rich.console import Group
    from rich.table import Table
    from rich.text import Text
    from rich import box

    grid, lifted = _lift_long_text(grid, lift_key)
    above = list(above) + lifted
    name_min = NAME_MIN
    if elastic == 0 and width is not None and len(grid.cells) > 1:  # design names: as wide as telling them apart needs
        name_min = max(map(_cells, _distinct_labels([row[0] for row in grid.cells], 0)), default=0)
    widths, shown = _layout(grid, width, elastic, name_min)
    kept = [j for j in range(shown, len(grid.fields)) if grid.fields[j] in keep]
    if kept:  # the columns to keep after as many others as fit with them
        rest = [j for j in range(len(grid.fields)) if j not in kept]
        for pos in range(len(rest) - 1, 0, -1):
            order = rest[:pos] + kept + rest[pos:]
            moved = Grid2D([grid.fields[j] for j in order], [[row[j] for j in order] for row in grid.cells],
                           [grid.text[j] for j in order])
            widths, shown = _layout(moved, width, elastic, name_min)
            if shown >= pos + len(kept):
                grid = moved
                break
        else:
            widths, shown = _layout(grid, width, elastic, name_min)
    if shown < len(grid.fields) and notes is not None:
        hidden = grid.fields[shown:]
        notes.append(f"{title + ': ' if title else ''}{len(hidden)} more {what} not shown at this width ("
                     + ", ".join(hidden[:6]) + (", …" if len(hidden) > 6 else "")
                     + (f"): choose them with {choose}, or use --format csv / json" if choose else
                        "): see them with --format csv / json"))
    t = Table(box=box.SIMPLE_HEAD, padding=(0, 1), pad_edge=False, show_edge=False)
    for j in range(shown):
        head = "\n".join(_header_lines(grid.fields[j], widths[j]))
        t.add_column(Text(head, style="bold"), justify="left" if grid.text[j] else "right", no_wrap=True,
                     vertical="bottom", overflow="ellipsis", min_width=widths[j], max_width=widths[j])
    names = _distinct_labels([row[elastic] for row in grid.cells], widths[elastic]) if (
        elastic is not None and elastic < shown) else None
    for k, row in enumerate(grid.cells):
        t.add_row(*(Text(names[k] if j == elastic and names else _elide(row[j], widths[j], middle=j == elastic))
                    for j in range(shown)))
    head = ([Text(title, style="bold")] if title else []) + [Text(line) for line in above]
    return Group(*head, t) if head else t


def _console(buf, width, color):
    from rich.console import Console

    return Console(file=buf, width=width or 10_000, force_terminal=color, no_color=not color, highlight=False,
                   soft_wrap=False, emoji=False, markup=False)


def _cell(result, field: str) -> str:
    value = result.summary.get(field)
    if value is None and field in result.summary:
        return result.labels.get(field, "n/a")
    if field not in result.summary:
        return ""
    return fmt_value(value)


def _is_text(values: list) -> bool:
    return any(isinstance(v, str) for v in values) and not any(
        isinstance(v, (int, float)) and not isinstance(v, bool) for v in values)


def summary_grid(records: list[Record], fields: list[str] | None, default: list[str] | None) -> Grid2D:
    """One row per design: ``name`` then the selected fields (the kind's table fields by default); a field no
    design has is left out."""
    names = _union([r.result.summary for r in records])
    cols = select(names, fields, default)
    cols = [c for c in cols if any(c in r.result.summary for r in records)]
    cells = [[r.name if c == "name" else _cell(r.result, c) for c in cols] for r in records]
    text = [c == "name" or _is_text([r.result.summary.get(c) for r in records]) for c in cols]
    return Grid2D(cols, cells, text)


def vertical_grid(rec: Record, fields: list[str] | None) -> Grid2D:
    """One design as field / value / unit rows (every field by default)."""
    names = [f for f in select(list(rec.result.summary), fields, None) if f != "name"]
    cells = [[f, _cell(rec.result, f), unit_of(f)] for f in names]
    return Grid2D(["field", "value", "unit"], cells, [True, True, True])


def render_table(records: list[Record], detail: bool = False, width: int | None = None,
                 color: bool = False, fields: list[str] | None = None, notes: list | None = None) -> str:
    """Tables for a terminal.

    One design alone: a vertical field / value / unit table of its whole summary (or of ``fields``).
    Several: per kind, one row per design with ``name`` and the kind's table fields (``Calculator.table_fields``;
    ``fields`` chooses others, ``["all"]`` every field).  Columns that do not fit ``width`` are left out and
    named in ``notes``.  Then the detail tables with ``detail``.
    """
    from . import registry

    buf = io.StringIO()
    console = _console(buf, width, color)
    kinds: dict[str, list[Record]] = {}
    for r in records:
        kinds.setdefault(r.kind, []).append(r)
    for kind, recs in kinds.items():
        if len(records) == 1:
            grid = vertical_grid(recs[0], fields)
            title = f"gearcalc {kind}: {recs[0].name}"
            console.print(layout_table(grid, width, title, notes, elastic=1))
            continue
        default = list(getattr(registry.get(kind), "table_fields", ()) or ()) or None
        grid = summary_grid(recs, fields, default)
        console.print(layout_table(grid, width, f"gearcalc {kind}", notes))
    if detail:
        for r in records:
            for table, rows in r.result.detail.items():
                if rows:
                    console.print(layout_table(rows_grid(rows), width, f"{r.name}: {table}", notes,
                                               elastic=None, choose="--detail --fields"))
    return buf.getvalue()


def rows_grid(rows: list[dict], fields: list[str] | None = None, lead: tuple = ()) -> Grid2D:
    """Plain rows (detail, sweep, accuracy) as a grid: a column per field, in first-seen order."""
    cols = _union(rows)
    if fields is not None:
        cols = select(cols, fields, None, lead=lead)
    cells = [[fmt_value(row.get(c)) if c in row else "" for c in cols] for row in rows]
    text = [_is_text([row.get(c) for row in rows]) for c in cols]
    return Grid2D(cols, cells, text)


def rows_table(rows: list[dict], title: str = "", width: int | None = None, notes: list | None = None):
    """A rich table of plain rows: a column per field, units in the headers."""
    return layout_table(rows_grid(rows), width, title, notes, elastic=None)


def render(records: list[Record], fmt: str, detail: bool = False, width: int | None = None,
           color: bool = False, fields: list[str] | None = None, notes: list | None = None,
           array: bool | None = None) -> str:
    """Render computed designs as ``fmt``; ``fields`` selects summary fields (``--fields``); ``array`` forces
    a JSON array (a folder or several paths) even for one design."""
    joined = False
    if fields is not None and fields != [ALL_FIELDS]:
        with_file = FILE_FIELD in fields and fmt != "json"  # JSON has the file beside the summary
        columns = detail_columns(records) if detail else set()
        wanted = [f for f in fields if f in columns]
        joined = detail and fmt == "csv" and any(f not in columns for f in fields)
        records = [Record(r.source, r.kind, r.name, r.design,
                          Result(summary=filter_summary(_with_file(r) if with_file else r.result.summary, fields),
                                 detail=_filter_detail(r.result.detail, wanted) if wanted else r.result.detail,
                                 warnings=r.result.warnings, failed=r.result.failed, model=r.result.model,
                                 labels=r.result.labels))
                   for r in records]
    if fmt == "json":
        return render_json(records, detail, array)
    if fmt == "csv":
        return render_csv(records, detail, joined)
    return render_table(records, detail, width=width, color=color, fields=fields, notes=notes)


def detail_columns(records: list[Record]) -> set:
    """The columns of the records' detail tables (``--detail --fields`` chooses among them too)."""
    return {c for r in records for rows in r.result.detail.values() for row in rows for c in row}


def _filter_detail(detail: dict, wanted: list[str]) -> dict:
    """The detail tables restricted to the ``wanted`` columns, in that order; a table with none of them is left out."""
    out = {}
    for table, rows in detail.items():
        cols = [c for c in wanted if any(c in row for row in rows)]
        if cols:
            out[table] = [{c: row[c] for c in cols if c in row} for row in rows]
    return out


def _with_file(rec: Record) -> dict:
    """The summary with a ``file`` field after ``name`` (``--fields file``)."""
    summary = dict(rec.result.summary)
    lead = {"name": summary.pop("name")} if "name" in summary else {}
    return {**lead, FILE_FIELD: "<stdin>" if rec.source == "-" else str(rec.source), **summary}


def render_rows(rows, fmt: str, title: str = "", width: int | None = None, color: bool = False,
                fields: list[str] | None = None, default: list[str] | None = None, lead: tuple = (),
                notes: list | None = None, lift_key: int | None = None, keep: tuple = (),
                choose: str | None = "--fields") -> str:
    """Plain rows (a sweep; a list of dicts or :class:`Columns`): CSV with a union header, a JSON
    array, or one table.  ``fields`` (``--fields``) selects columns after the ``lead`` ones (the varied keys);
    a table shows ``default`` when no ``fields`` are given, and lifts columns that are the same on every row
    (a sweep's fixed inputs) above it."""
    if fields is not None and fields != [ALL_FIELDS]:
        rows = _select_rows(rows, fields, lead)
    if fmt == "csv":
        return write_csv_columns(rows) if isinstance(rows, Columns) else write_csv(rows)
    if isinstance(rows, Columns):
        rows = rows.rows()
    if fmt == "json":
        return json.dumps([plain(r) for r in rows], indent=2, ensure_ascii=False, allow_nan=False) + "\n"
    grid = rows_grid(rows, default if fields is None else None, lead=lead)
    above = []
    if len(rows) > 1:
        grid, above = _lift_constant(grid, keep=len(lead))
    buf = io.StringIO()
    console = _console(buf, width, color)
    console.print(layout_table(grid, width, title, notes, what="columns", elastic=None, lift_key=lift_key,
                               above=tuple(above), keep=keep, choose=choose))
    return buf.getvalue()


def _select_rows(rows, fields, lead):
    if isinstance(rows, Columns):
        keep = select(list(rows.data), fields, None, lead=lead)
        return Columns({k: rows.data[k] for k in keep})
    keep = select(_union(rows), fields, None, lead=lead)
    return [{k: r[k] for k in keep if k in r} for r in rows]


def _lift_constant(grid: Grid2D, keep: int = 0) -> tuple[Grid2D, list[str]]:
    """Columns with one value on every row (but the first ``keep``) become ``field = value`` lines."""
    const = [j for j in range(keep, len(grid.fields))
             if len({row[j] for row in grid.cells}) == 1 and len(grid.fields) - keep > 1]
    if not const or len(const) == len(grid.fields):
        return grid, []
    lines = ["same on every row: " + "; ".join(
        f"{grid.fields[j]} = {grid.cells[0][j]}" for j in const)]
    stay = [j for j in range(len(grid.fields)) if j not in const]
    return Grid2D([grid.fields[j] for j in stay], [[row[j] for j in stay] for row in grid.cells],
                  [grid.text[j] for j in stay]), lines


def select_columns(cols: "Columns", fields: list[str] | None, lead: tuple = ()) -> "Columns":
    """The ``lead`` columns (a sweep's varied keys) and ``fields`` (``--fields``; None or ``all``: every one)."""
    if fields is None or fields == [ALL_FIELDS]:
        return cols
    return Columns({k: cols.data[k] for k in select(list(cols.data), fields, None, lead=lead)}, cols.errors)


def json_array_piece(cols: "Columns", first: bool) -> str:
    """A chunk of rows as part of one JSON array, the same text as ``json.dumps(rows, indent=2)`` once the
    pieces are joined and closed with ``"\\n]\\n"`` (``"[]\\n"`` for no rows).

    >>> c = Columns({"a": [1.5, None], "b": ["x", "y"]})
    >>> json_array_piece(c, True) + "\\n]\\n" == json.dumps(c.rows(), indent=2) + "\\n"
    True
    """
    if not cols.n:
        return ""
    body = ",\n".join("  " + json.dumps(plain(r), indent=2, ensure_ascii=False, allow_nan=False).replace("\n", "\n  ")
                      for r in cols.rows())
    return ("[\n" if first else ",\n") + body


class Columns:
    """Column-major rows (a sweep): ``data[name]`` is a list, every list as long as the others.  Inside a
    streamed sweep a column of floats, counts or flags may be a numpy array (float64, integers, bool:
    ``grid.stream(arrays=True)``, for the CSV writer); :meth:`lists` gives the columns as lists, :meth:`rows`
    plain Python values either way.  ``errors``: the messages of the points that could not be computed (their
    outputs None), e.g. ``"at {'mass.efficiency': 1e-300}: relative_mass_kg_per_kNm: the computed value is inf
    (...)"``."""

    def __init__(self, data: dict[str, list], errors: list[str] | None = None):
        self.data = data
        self.n = len(next(iter(data.values()))) if data else 0
        self.errors = list(errors or [])

    def lists(self) -> "Columns":
        """These columns with every numpy array as a list of Python values (self when there is none)."""
        if not any(hasattr(v, "tolist") for v in self.data.values()):
            return self
        return Columns({k: v.tolist() if hasattr(v, "tolist") else v for k, v in self.data.items()}, self.errors)

    @classmethod
    def from_rows(cls, rows: list[dict], errors: list[str] | None = None) -> "Columns":
        cols = _union(rows)
        return cls({c: [r.get(c) for r in rows] for c in cols}, errors)

    def rows(self) -> list[dict]:
        names = list(self.data)
        return [dict(zip(names, vals)) for vals in zip(*self.lists().data.values())]

    def _repr_html_(self) -> str:
        """The columns as an HTML table with units (Jupyter), the errors of the points below it."""
        head = Columns({k: v[:HTML_MAX_ROWS] for k, v in self.data.items()}, self.errors[:20])
        return html_rows(head.rows(), notes=head.errors, total=self.n)

    def to_pandas(self):
        """A pandas DataFrame (pandas is not a dependency of gearcalc: install it to use this)."""
        import pandas as pd

        return pd.DataFrame(self.data)


class LazyLists(dict):
    """Columns (a dict of column name -> list) whose numpy arrays become lists when first read: the Python API's
    ``Columns.data`` holds lists as it promises, and a caller reading a few columns of a big sweep does not pay
    for turning every other array into Python values.  Every way of reading a value (``[]``, ``get``,
    ``values``, ``items``, iteration, ``dict(...)``, ``==``, pickling) sees lists."""

    def __getitem__(self, key):
        v = dict.__getitem__(self, key)
        if hasattr(v, "tolist"):
            v = v.tolist()
            dict.__setitem__(self, key, v)
        return v

    def _all(self) -> "LazyLists":
        for key in dict.keys(self):
            self[key]
        return self

    def get(self, key, default=None):
        return self[key] if key in self else default

    def __iter__(self):  # overridden: dict(self) and {**self} then read through __getitem__
        return iter(dict.keys(self))

    def values(self):
        return dict.values(self._all())

    def items(self):
        return dict.items(self._all())

    def pop(self, key, *default):
        if key in self:
            self[key]
        return dict.pop(self, key, *default)

    def popitem(self):
        self._all()
        return dict.popitem(self)

    def setdefault(self, key, default=None):
        return self[key] if key in self else dict.setdefault(self, key, default)

    def copy(self) -> dict:
        return dict(self._all())

    def __eq__(self, other):
        return dict.__eq__(self._all(), other)

    __hash__ = None

    def __repr__(self) -> str:
        return dict.__repr__(self._all())

    def __reduce__(self):
        return dict, (dict(self._all()),)


def _quote(text: str) -> str:
    if any(ch in text for ch in ',"\n\r'):
        return '"' + text.replace('"', '""') + '"'
    return text


def _csv_column(col: list, formatted: dict | None = None, types: set | None = None) -> list[str]:
    """A column's CSV cells, the same text as :func:`csv_cell` per value, in bulk: floats (with None for
    undefined) by ``repr`` with one finiteness check per column, ints by ``str``, other values once per
    distinct value.

    ``formatted`` (optional) remembers the cells of the float columns already formatted, keyed by their
    bit patterns: a column equal bit for bit to an earlier one (a varied key and the same input echoed in
    the summary; K and K_stepwise at the stepwise level) reuses its cells instead of formatting the same
    floats again, which is most of the time of a big sweep's CSV.  ``types``: the set of the types of the
    values, when the caller has it.
    """
    import math

    if hasattr(col, "tolist"):  # a numpy array: its Python values
        col = col.tolist()
    if types is None:
        types = set(map(type, col))
    undefined = type(None) in types
    # constant: an axis not varied, a fixed input (a float zero is not: 0.0 == -0.0 but their text differs)
    if len(types) == 1 and col.count(col[0]) == len(col) and not (col[0] == 0 and type(col[0]) is float):
        return [_quote(csv_cell(col[0]))] * len(col)
    if types <= {float, type(None)}:
        floats = [v for v in col if v is not None] if undefined else col
        if formatted is not None:
            from array import array

            bits = array("d", floats).tobytes()  # bit patterns: 0.0 and -0.0 differ, as their text does
            key = (bits, tuple(k for k, v in enumerate(col) if v is None)) if undefined else bits
            if key in formatted:
                return formatted[key]
        if not all(map(math.isfinite, floats)):
            raise NonFiniteOutput("non-finite value in CSV output")
        cells = ["" if v is None else repr(v) for v in col] if undefined else list(map(repr, col))
        if formatted is not None:
            formatted[key] = cells
        return cells
    if types == {int}:
        return list(map(str, col))
    out, cache = [], {}
    for v in col:  # words, flags and lists repeat: format each distinct value once
        t = type(v)
        # by value for words, ints, flags; else by repr: 0.0 == -0.0 and [1] == [1.0], but their text differs
        key = (t, v) if t in (str, int, bool, type(None)) else (t, repr(v))
        try:
            text = cache[key]
        except KeyError:
            text = cache[key] = _quote(csv_cell(v))
        except TypeError:
            text = _quote(csv_cell(v))
        out.append(text)
    return out


def write_csv_columns(cols: "Columns", header: bool = True) -> str:
    """CSV of column-major rows; the same cells as :func:`write_csv` of the equivalent rows (``header=False``:
    the rows only, for the second and later chunks of a streamed sweep)."""
    return "".join(csv_blocks(cols, header))


def csv_blocks(cols: "Columns", header: bool = True, binary: bool = False):
    """The CSV text of :func:`write_csv_columns` in blocks (a streamed sweep writes each block as it is
    formatted, so the text of a whole sweep is never held); ``binary``: as UTF-8 bytes (the vectorised path makes
    bytes, or a bytearray: no decoding and encoding again for a file).

    Blocks of at least :data:`CSV_VECTOR_ROWS` rows are written by :func:`_csv_rows_vectorised` (floats by
    :mod:`gearcalc.floatfmt`), up to :data:`CSV_MATRIX_ROWS` rows at a time; smaller ones cell by cell
    (:func:`_csv_column`), :data:`CSV_CHUNK` rows at a time: the same text.  Columns may be lists or numpy
    arrays (:class:`Columns`)."""
    names = list(cols.data)
    if header:
        text = ",".join(_quote(k) for k in names) + "\n"
        yield text.encode() if binary else text
    fast = _floatfmt() if cols.n >= CSV_VECTOR_ROWS and names else None
    step = CSV_MATRIX_ROWS if fast else CSV_CHUNK
    scratch: list = [None]  # the vectorised path's matrix, used again by the next block of the same size
    for start in range(0, cols.n, step):
        part = [cols.data[k][start:start + step] for k in names]
        data = _csv_rows_vectorised(part, fast, scratch) if fast and len(part[0]) >= CSV_VECTOR_ROWS else None
        if data is not None:
            yield data if binary else data.decode()
            continue
        for at in range(0, len(part[0]), CSV_CHUNK):  # cell by cell
            formatted: dict = {}
            cells = [_csv_column(col[at:at + CSV_CHUNK], formatted) for col in part]
            text = "\n".join(map(",".join, zip(*cells))) + "\n"
            yield text.encode() if binary else text


@dataclass(frozen=True)
class CsvPiece:
    """A sweep chunk as CSV (:class:`CsvRenderer`): its points ``n``, how many fail a design check, the
    columns it had (``columns``) and shows (``shown``), and the rows' text as UTF-8 (no header): a bytes-like
    object, or a tuple of them to write one after another (:meth:`blocks`)."""

    n: int
    failed: int
    columns: list
    shown: list
    text: Any
    errors: tuple = ()
    """The messages of the points that could not be computed (:attr:`Columns.errors`)."""

    def header(self) -> bytes:
        """The CSV header line of the columns shown (:func:`csv_blocks`' first block)."""
        return (",".join(_quote(k) for k in self.shown) + "\n").encode()

    def blocks(self) -> tuple:
        """The rows' text as blocks of bytes to write one after another (``text`` is one, or a tuple of them)."""
        return self.text if isinstance(self.text, tuple) else (self.text,)

    def with_text(self, text) -> "CsvPiece":
        """The same piece with another text (e.g. a view of the shared memory it was copied into)."""
        return dataclasses.replace(self, text=text)


@dataclass(frozen=True)
class CsvRenderer:
    """A sweep chunk to its :class:`CsvPiece`: the failed points counted by the kind's calculator, the
    columns chosen by ``--fields`` (``lead``: the varied keys first), the rows formatted by :func:`csv_blocks`.
    Picklable, so that ``--jobs`` worker processes format their own chunks (:func:`gearcalc.grid.stream`'s
    ``post``): the same bytes as formatting in this process."""

    kind: str
    fields: list | None = None
    lead: tuple = ()

    def __call__(self, part: "Columns") -> CsvPiece:
        from . import registry

        failed = registry.get(self.kind).failed_points(part.data)
        shown = select_columns(part, self.fields, self.lead)
        # the blocks as they come (about 3 MB each): joining them would copy the whole chunk's text once more
        blocks = tuple(csv_blocks(shown, header=False, binary=True))
        return CsvPiece(part.n, failed, list(part.data), list(shown.data), blocks[0] if len(blocks) == 1 else blocks,
                        tuple(getattr(part, "errors", ())))


CSV_VECTOR_ROWS = 512
"""Blocks of fewer rows are formatted cell by cell: the vectorised path makes about 100 numpy calls per float
column, which cost more than ``repr`` below a few hundred values (measured: even at 256 to 512 rows)."""


def _floatfmt():
    """:mod:`gearcalc.floatfmt` when it agrees with ``repr`` here (its self-check), else None."""
    try:
        from . import floatfmt
    except ImportError:  # pragma: no cover - numpy is a dependency
        return None
    return floatfmt if floatfmt.available() else None


def _csv_rows_vectorised(part: list, ff, scratch: list | None = None) -> bytearray | None:
    """The CSV rows of columns (lists or numpy arrays of equal length) as UTF-8 bytes (a bytearray), the text of
    :func:`_csv_column`'s cells, built as one matrix of bytes: a row per CSV row, each column's cells in a band of
    fixed width (zero bytes where a cell is shorter, all dropped at the end by one ``translate``), a comma after
    each band, a newline after the last.

    Float columns (with None for undefined) are formatted by ``ff`` (:mod:`gearcalc.floatfmt`, the text of
    ``repr``), :data:`CSV_CHUNK` rows at a time, and copied into their band (as wide as
    :func:`gearcalc.floatfmt.cells_width`); a float column equal bit for bit to an earlier one copies its band.
    A column with one text on every row (a fixed input, a word, a count) is a constant: the constants and commas
    are one template row, copied into every row at once before the bands are filled.  Other columns are
    formatted by :func:`_csv_column`.  ``scratch``: a list of one item, the matrix's buffer kept from the previous
    call and used again when it has the size (no allocation nor zeroing per block).  None when a text cell holds
    a NUL character (it would be dropped with the zero bytes): the caller formats those rows cell by cell."""
    import numpy as np

    n = len(part[0])
    bands: list = []  # (offset, band): the variable bands (:func:`_csv_band`)
    done: dict = {}  # a float column's fingerprint (its rows of None, three values) -> [(values, offset)]
    row = bytearray()  # the template row: constants and commas in place, zeros in the bands
    for col in part:
        band = _csv_band(col, ff)
        if band is None:
            return None
        if isinstance(band, bytes):  # one text on every row
            row += band + b","
            continue
        bands.append((len(row), band))
        row += bytes(band[0]) + b","
    row[-1:] = b"\n"  # the end of the line instead of the last ","
    width = len(row)
    buf = scratch[0] if scratch is not None and scratch[0] is not None and len(scratch[0]) == n * width else None
    if buf is None:
        buf = bytearray(n * width)
        if scratch is not None:
            scratch[0] = buf
    out = np.frombuffer(buf, dtype=np.uint8).reshape(n, width)
    out[:] = np.frombuffer(bytes(row), dtype=np.uint8)  # one pass: faster than a strided pass per constant
    floats, copies = [], []
    for at, (w, kind, cells, none) in bands:
        if kind == "text":
            _put(out, at, cells)
            continue
        x = cells  # bit patterns compared: 0.0 and -0.0 differ, as their text does
        key = (none, x[0].tobytes(), x[-1].tobytes(), x[n // 2].tobytes())
        same = next((o for y, o in done.get(key, ()) if np.array_equal(x.view(np.int64), y.view(np.int64))), None)
        if same is not None:  # bit for bit an earlier column (and None in the same rows): its cells
            copies.append((at, w, same))
            continue
        done.setdefault(key, []).append((x, at))
        floats.append((at, w, x, none))
    for start in range(0, n, CSV_CHUNK):
        stop = min(start + CSV_CHUNK, n)
        for at, _w, x, _ in floats:
            # formatted into a matrix of their own, then copied into the band (its columns beyond the cells stay
            # zero): faster than writing the cells in place, a few strided passes over rows 360 bytes apart
            _put(out[start:stop], at, ff.float_cells(x[start:stop]))
    for at, w, _, none in floats:
        if none:
            out[list(none), at:at + w] = 0  # None: an empty cell
    for at, w, same in copies:
        _put(out, at, out[:, same:same + w])
    del out  # the buffer's export released
    return buf.translate(None, b"\0")


def _put(out, at: int, cells) -> None:
    """Copy ``cells`` (a uint8 matrix of ``w`` columns, a row per row of ``out``) into columns ``at`` to ``at + w``
    of ``out``: as one item of ``w`` bytes per row (a void dtype), which numpy copies a row at a time, rather than
    ``w`` single bytes per row (measured: a third less time for cells of 19 bytes)."""
    w = cells.shape[1]
    if w:
        void = f"V{w}"
        src = cells if cells.strides[1] == 1 else cells.copy()
        out[:, at:at + w].view(void)[:, 0] = src.view(void)[:, 0]


def _csv_band(col, ff):
    """A column's band for :func:`_csv_rows_vectorised`: its one cell as bytes when every row has the same text
    (a constant), else ``(width, kind, cells, none)``: kind ``"float"`` with ``cells`` the float64 values to
    format (a placeholder where undefined) and ``none`` the rows of None (a tuple), or ``"text"`` with ``cells`` a
    uint8 matrix (a row per cell, zero bytes where a cell is shorter).  None for a cell with a NUL character.
    The cells of :func:`_csv_column`; a float64 numpy array is a column of floats with no None, an array of ints
    or flags a column of those."""
    import numpy as np

    if isinstance(col, np.ndarray):
        if col.dtype != np.float64:
            if col.dtype.kind in "iub" and len(col) and col.min() == col.max():  # one count or flag (e.g. rows)
                return _text_band([_quote(csv_cell(col[0].item()))])
            return _text_band(_csv_column(col.tolist()))
        x = np.ascontiguousarray(col)
        lo, hi = float(x.min()), float(x.max())  # NaN propagates to both
        if not (math.isfinite(lo) and math.isfinite(hi)):
            raise NonFiniteOutput("non-finite value in CSV output")
        if lo == hi != 0:  # constant (0.0 is not: 0.0 == -0.0, the text differs); else equal is bit for bit equal
            return _text_band([repr(lo)])
        return ff.cells_width(x, (lo, hi)), "float", x, ()
    first = col[0]
    # a constant: only a str equals a str, only None equals None, only an empty list an empty list (a number may
    # equal a number of another type and text: 1 == 1.0 == True); list.count compares identical objects at once
    if type(first) in (str, type(None)) or (type(first) is list and not first):
        try:
            same = col.count(first) == len(col)
        except (TypeError, ValueError):  # an element that cannot say (an array): not a constant
            same = False
        if same:
            return _text_band([_quote(csv_cell(first))])
    types = set(map(type, col))
    if float not in types or not types <= {float, type(None)}:
        return _text_band(_csv_column(col, types=types))
    undefined = type(None) in types
    from array import array

    values = array("d", [v for v in col if v is not None] if undefined else col)
    x = np.frombuffer(values, dtype=np.float64)
    if not np.isfinite(x).all():
        _csv_column(col, types=types)  # raises NonFiniteOutput, as the cell-by-cell path does
        raise NonFiniteOutput("non-finite value in CSV output")  # pragma: no cover - not reached
    if not undefined and x[0] != 0 and (x == x[0]).all():  # constant (0.0 is not: 0.0 == -0.0, the text differs)
        return _text_band([repr(col[0])])
    none = tuple(k for k, v in enumerate(col) if v is None) if undefined else ()
    if undefined:  # a placeholder where undefined: those cells are emptied
        defined = np.ones(len(col), dtype=bool)
        defined[list(none)] = False
        full = np.ones(len(col))
        full[defined] = x
        x = full
    return ff.cells_width(x), "float", x, none


def _text_band(cells: list[str]):
    """A band of text cells for :func:`_csv_band`: the cell as bytes when there is one text on every row, else
    ``(width, "text", matrix, ())``; None for a cell with a NUL character."""
    import numpy as np

    if cells.count(cells[0]) == len(cells):
        enc = cells[0].encode()
        return None if b"\0" in enc else enc
    joined = "".join(cells)
    if "\0" in joined:
        return None
    if joined.isascii():  # code points as uint32, one a byte
        m = np.array(cells, dtype="U").view(np.uint32).reshape(len(cells), -1).astype(np.uint8)
    else:
        enc = [c.encode() for c in cells]
        m = np.array(enc, dtype=f"S{max(map(len, enc))}").view(np.uint8).reshape(len(cells), -1)
    return m.shape[1], "text", m, ()


CSV_CHUNK = 8192
"""Rows formatted at a time: cell by cell (:func:`csv_blocks`), or each float column's cells on the vectorised
path (:func:`_csv_rows_vectorised`: numpy's temporaries of 8192 values stay in the processor's cache)."""

CSV_MATRIX_ROWS = 8192
"""Rows assembled into one matrix and compacted at once by :func:`_csv_rows_vectorised`: about 3 MB for the
widest rows, which stays in the processor's cache (measured: 4 % less CPU time than 65 536 rows at once)."""


# ----------------------------------------------------------------------------- HTML tables (Jupyter)
HTML_MAX_ROWS = 500
"""Rows an HTML table shows (a notebook cell stays readable); the rest are counted below it."""


def html_header(field: str) -> str:
    """A column title with its unit from the field's suffix: ``sigma_max_MPa`` -> ``sigma_max [MPa]``."""
    base, unit = split_unit(field)
    return f"{base} [{unit}]" if unit else field


def _html_cell(value: Any, label: str = "") -> str:
    """One ``<td>``: the value as a table shows it (6 digits), the exact number in its ``title``."""
    import html

    value = plain(value)
    text = label if value is None and label else fmt_value(value)
    exact = ""
    if isinstance(value, float) and not isinstance(value, bool):
        exact = f' title="{html.escape(repr(value))}"'
    align = ' style="text-align:right"' if isinstance(value, (int, float)) and not isinstance(value, bool) else ""
    return f"<td{exact}{align}>{html.escape(text)}</td>"


def html_vertical(summary: dict, labels: dict | None = None, caption: str = "") -> str:
    """A summary as an HTML table of (field, value, unit) rows: ``Result._repr_html_``."""
    import html

    labels = labels or {}
    out = ["<table>"]
    if caption:
        out.append(f"<caption>{html.escape(caption)}</caption>")
    out.append("<thead><tr><th>field</th><th>value</th><th>unit</th></tr></thead><tbody>")
    for name, value in summary.items():
        base, unit = split_unit(name)
        cell = _html_cell(value, labels.get(name, ""))
        out.append(f"<tr><th style=\"text-align:left\">{html.escape(base)}</th>{cell}<td>{html.escape(unit)}</td></tr>")
    out.append("</tbody></table>")
    return "".join(out)


def html_rows(rows: list[dict], caption: str = "", notes: list | None = None, total: int | None = None) -> str:
    """Rows (dicts) as an HTML table, one column per field with its unit in the title: batches and sweeps
    (``Batch._repr_html_``, ``Columns._repr_html_``); at most :data:`HTML_MAX_ROWS` rows shown."""
    import html

    names = _union(rows)
    out = ["<table>"]
    if caption:
        out.append(f"<caption>{html.escape(caption)}</caption>")
    out.append("<thead><tr>" + "".join(f"<th>{html.escape(html_header(n))}</th>" for n in names) + "</tr></thead>")
    out.append("<tbody>")
    for row in rows[:HTML_MAX_ROWS]:
        out.append("<tr>" + "".join(_html_cell(row.get(n)) for n in names) + "</tr>")
    out.append("</tbody></table>")
    lines = list(notes or [])
    total = len(rows) if total is None else total
    if total > HTML_MAX_ROWS:
        lines.insert(0, f"… {total - HTML_MAX_ROWS} more rows (to_pandas() or the CSV output holds them all)")
    out += [f"<p>{html.escape(str(line))}</p>" for line in lines]
    return "".join(out)
