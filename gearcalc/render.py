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
import io
import json
import math
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


def render_json(records: list[Record], detail: bool = False) -> str:
    objs = [to_json_obj(r, detail) for r in records]
    data = objs[0] if len(objs) == 1 else objs
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
    return str(value)


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


def render_csv(records: list[Record], detail: bool = False) -> str:
    """One CSV: the summaries (or, with ``detail``, the detail rows in long form).  A batch of several
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
        for table, trows in r.result.detail.items():
            rows.extend({**lead, "name": r.name, "table": table, **row} for row in trows)
    return write_csv(rows) if rows else "name,table\n"


def fmt_value(value: Any) -> str:
    """Format a value for a table cell (6 significant digits)."""
    value = plain(value)
    if value is None:
        return "n/a"
    if isinstance(value, bool):
        return "yes" if value else "no"
    if isinstance(value, float):
        return f"{value:.6g}"
    if isinstance(value, list):
        return " ".join(fmt_value(v) for v in value) or "-"
    return str(value)


def render_table(records: list[Record], detail: bool = False, width: int | None = None,
                 color: bool = False) -> str:
    """Rich tables, one summary per kind (a column per design), then the detail tables."""
    from rich.console import Console
    from rich.table import Table

    buf = io.StringIO()
    console = Console(file=buf, width=width or 1000, force_terminal=color, no_color=not color,
                      highlight=False, soft_wrap=False)
    kinds: dict[str, list[Record]] = {}
    for r in records:
        kinds.setdefault(r.kind, []).append(r)
    for kind, recs in kinds.items():
        t = Table(title=f"gearcalc {kind}", title_justify="left")
        t.add_column("quantity", style="bold", no_wrap=True)
        t.add_column("unit", no_wrap=True)
        for r in recs:
            t.add_column(r.name, justify="right", overflow="fold")
        fields = _union([r.result.summary for r in recs])
        for f in fields:
            if f == "name":
                continue
            t.add_row(f, unit_of(f), *(r.result.labels.get(f, "n/a") if r.result.summary.get(f) is None
                                       else fmt_value(r.result.summary.get(f)) for r in recs))
        console.print(t)
    if detail:
        for r in records:
            for table, rows in r.result.detail.items():
                if not rows:
                    continue
                console.print(rows_table(rows, f"{r.name}: {table}"))
    return buf.getvalue()


def rows_table(rows: list[dict], title: str = ""):
    """A rich table of plain rows: a column per field, units in the headers."""
    from rich.table import Table

    t = Table(title=title or None, title_justify="left")
    cols = _union(rows)
    for c in cols:
        base, u = split_unit(c)
        t.add_column(f"{base}\n[{u}]" if u else c, justify="right", overflow="fold")
    for row in rows:
        t.add_row(*(fmt_value(row.get(c)) for c in cols))
    return t


def render(records: list[Record], fmt: str, detail: bool = False, width: int | None = None,
           color: bool = False) -> str:
    if fmt == "json":
        return render_json(records, detail)
    if fmt == "csv":
        return render_csv(records, detail)
    return render_table(records, detail, width=width, color=color)


def render_rows(rows, fmt: str, title: str = "", width: int | None = None, color: bool = False) -> str:
    """Plain rows (a sweep; a list of dicts or :class:`Columns`): CSV with a union header, a JSON
    array, or one table."""
    if fmt == "csv":
        return write_csv_columns(rows) if isinstance(rows, Columns) else write_csv(rows)
    if isinstance(rows, Columns):
        rows = rows.rows()
    if fmt == "json":
        return json.dumps([plain(r) for r in rows], indent=2, ensure_ascii=False, allow_nan=False) + "\n"
    from rich.console import Console

    buf = io.StringIO()
    console = Console(file=buf, width=width or 1000, force_terminal=color, no_color=not color, highlight=False)
    console.print(rows_table(rows, title))
    return buf.getvalue()


class Columns:
    """Column-major rows (a sweep): ``data[name]`` is a list, every list as long as the others."""

    def __init__(self, data: dict[str, list]):
        self.data = data
        self.n = len(next(iter(data.values()))) if data else 0

    @classmethod
    def from_rows(cls, rows: list[dict]) -> "Columns":
        cols = _union(rows)
        return cls({c: [r.get(c) for r in rows] for c in cols})

    def rows(self) -> list[dict]:
        names = list(self.data)
        return [dict(zip(names, vals)) for vals in zip(*self.data.values())]


def _quote(text: str) -> str:
    if any(ch in text for ch in ',"\n\r'):
        return '"' + text.replace('"', '""') + '"'
    return text


def _csv_column(col: list, formatted: dict | None = None) -> list[str]:
    """A column's CSV cells, the same text as :func:`csv_cell` per value, in bulk: floats (with None for
    undefined) by ``repr`` with one finiteness check per column, ints by ``str``, other values once per
    distinct value.

    ``formatted`` (optional) remembers the cells of the float columns already formatted, keyed by their
    bit patterns: a column equal bit for bit to an earlier one (a varied key and the same input echoed in
    the summary; K and K_stepwise at the stepwise level) reuses its cells instead of formatting the same
    floats again, which is most of the time of a big sweep's CSV.
    """
    import math

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
        key = (type(v), tuple(v) if isinstance(v, list) else v)
        try:
            text = cache[key]
        except KeyError:
            text = cache[key] = _quote(csv_cell(v))
        except TypeError:
            text = _quote(csv_cell(v))
        out.append(text)
    return out


def write_csv_columns(cols: "Columns") -> str:
    """CSV of column-major rows; the same cells as :func:`write_csv` of the equivalent rows."""
    names = list(cols.data)
    parts = [",".join(_quote(k) for k in names) + "\n"]
    for start in range(0, cols.n, CSV_CHUNK):  # a block of rows at a time: bounded memory for big sweeps
        formatted: dict = {}
        cells = [_csv_column(cols.data[k][start:start + CSV_CHUNK], formatted) for k in names]
        parts.append("\n".join(map(",".join, zip(*cells))) + "\n")
    return "".join(parts)


CSV_CHUNK = 8192
"""Rows formatted at a time by :func:`write_csv_columns`."""
