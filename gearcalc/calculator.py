"""The contract between the frame (loader, CLI, renderer) and one calculator.

A calculator is registered in :mod:`gearcalc.registry` by kind name and module path.  Its
module (``gearcalc.kinds.<kind>``) defines a module-level ``CALCULATOR`` of type
:class:`Calculator`:

* ``tables``: the design-file schema, a list of :class:`Table` of :class:`Field`.  The shared
  loader (:mod:`gearcalc.design`) checks types, ranges, unknown keys and fills defaults from it,
  and ``gearcalc new KIND`` prints the template from it.
* ``check(design, problems)``: cross-field checks on the resolved design (optional).
* ``compute(design, options) -> Result``: the calculation.  It may raise :class:`DesignError`
  for impossible inputs only discovered while computing (exit code 2).
* ``sweep(base, raw, axes, points, options) -> dict[str, list] | list[dict] | None`` (optional):
  the summaries of a whole grid at once, vectorised, column-major (a list per field) or as rows;
  ``None`` falls back to point-by-point evaluation.
* ``sweep_cost(base, axes, options) -> float`` (optional): the estimated seconds of computing one point
  of that grid (by the path ``sweep`` takes); a sweep over its time budget is refused before it starts,
  and its chunks are sized by it (:func:`gearcalc.grid.prepare`, :func:`gearcalc.grid.chunk_points`).
* ``batch(designs, options) -> list[Result | Exception]`` (optional): many designs of the kind
  at once (numpy over designs), identical to ``compute`` design by design.
* ``plot(records, path)`` (optional): draw the calculator's figure (matplotlib, imported inside) and
  return the records it drew (a figure holds a few designs; :func:`gearcalc.plot.plot_records` names the rest).

This module imports nothing heavy: ``gearcalc --help`` loads it.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Callable, Sequence

REQUIRED = object()
"""Sentinel default: the key must be given."""


@dataclass(frozen=True)
class Field:
    """One design key.

    Parameters
    ----------
    name : key name inside its table; dimensional keys end in their unit (``_mm``).
    type : ``"number"``, ``"integer"``, ``"bool"``, ``"string"`` or ``"numbers"`` (an array).
    default : a value, :data:`REQUIRED`, or ``None`` (optional, absent unless given).
    doc : one line for the template and the man page.
    choices : strings accepted (for ``"string"``: the only values; for the other types: words
        accepted besides a value of the type, e.g. ``"auto"``).
    gt, ge, lt, le : bounds on numbers (and on every element of ``"numbers"``).
    length : the exact length of a ``"numbers"`` array.
    default_doc : how the default is shown when it is derived from other keys (``"0.5 b_w"``).
    example : the value the template (``gearcalc new``) writes for a required or optional key;
        a key with neither default nor example is written commented out.
    alternative_to : the name of an exclusive key of the same table; the template keeps exactly one of the
        two active.
    """

    name: str
    type: str
    default: Any = None
    doc: str = ""
    choices: tuple = ()
    gt: float | None = None
    ge: float | None = None
    lt: float | None = None
    le: float | None = None
    length: int | None = None
    default_doc: str = ""
    example: Any = None
    alternative_to: str = ""
    """The key of the same table this one replaces (the two exclusive): the template writes this one commented
    out, with its example value, and says to swap the two lines."""

    def constraint(self) -> str:
        """Human-readable statement of the admissible values."""
        parts = []
        if self.type == "integer":
            parts.append("an integer")
        elif self.type == "number":
            parts.append("a number")
        elif self.type == "bool":
            parts.append("true or false")
        elif self.type == "numbers":
            parts.append(f"an array of {self.length} numbers" if self.length else "an array of numbers")
        for op, bound in (("> ", self.gt), (">= ", self.ge), ("< ", self.lt), ("<= ", self.le)):
            if bound is not None:
                parts.append(op + _fmt(bound))
        text = " ".join(parts[:1]) + ("" if len(parts) < 2 else " " + ", ".join(parts[1:]))
        if self.choices:
            words = " | ".join(f'"{c}"' for c in self.choices)
            text = words if self.type == "string" else f"{text}, or {words}"
        return text


def _fmt(x: float) -> str:
    if float(x).is_integer() and abs(x) < 1e6:
        return repr(int(x))
    return f"{x:g}"


@dataclass(frozen=True)
class Table:
    """One TOML table of a design.

    ``optional=True`` means the table may be absent, and an absent table is not computed
    ("model only what the design needs"); its fields' defaults then do not apply.
    ``in_template=False`` writes the table commented out in ``gearcalc new``.
    ``rows=True``: a table of rows, whose fields are arrays of equal length (one entry a row); the file may
    give it column-wise (``[duty]`` with arrays) or row-wise as an array of tables (``[[duty]]``, one table
    a row), which is read as the columns (:func:`gearcalc.design.columns_of_rows`).
    """

    name: str
    fields: tuple[Field, ...]
    doc: str = ""
    optional: bool = False
    in_template: bool = True
    rows: bool = False

    def field(self, name: str) -> Field | None:
        for f in self.fields:
            if f.name == name:
                return f
        return None


TOL_MIN, TOL_MAX = 1e-15, 0.1
"""The range of ``--tol`` (``tol``): [1e-15, 0.1).  A relative accuracy below 1e-15 is under float64's round-off
(2.2e-16 relative): no computation can meet it, and the levels it would ask for overflow."""


def tol_problem(tol) -> str | None:
    """What is wrong with a tolerance (``"must be ..."``), or None: the one rule of the CLI and the API.

    >>> tol_problem(1e-6), tol_problem(1e-320)
    (None, 'must be >= 1e-15 and < 0.1 (a relative accuracy, e.g. 1e-6; below 1e-15 is under the round-off of floats)')
    """
    if isinstance(tol, (int, float)) and not isinstance(tol, bool) and TOL_MIN <= tol < TOL_MAX:
        return None
    return "must be >= 1e-15 and < 0.1 (a relative accuracy, e.g. 1e-6; below 1e-15 is under the round-off of floats)"


@dataclass
class Options:
    """Run options that reach the calculator."""

    tol: float = 1e-6
    model: str | None = None
    detail: bool = False
    settings: Any = None
    """A kind's numerical settings, passed explicitly (pins: the contact level's
    :class:`~gearcalc.pins.contact_settings.ContactSettings`); None: the shipped ones."""


@dataclass
class Result:
    """What a calculator returns for one design.

    ``summary`` holds the summary fields in display order (JSON-able scalars, ``None`` for
    undefined, lists of ints allowed); names carry their unit suffix.  ``detail`` maps a table
    name to a list of rows (dicts).  ``failed`` lists the design checks that failed (exit 1).
    """

    summary: dict[str, Any]
    detail: dict[str, list[dict[str, Any]]] = field(default_factory=dict)
    warnings: list[str] = field(default_factory=list)
    failed: list[str] = field(default_factory=list)
    model: str = ""
    labels: dict[str, str] = field(default_factory=dict)
    """Text a table shows instead of "n/a" for a summary field that is None (e.g. "self-locking")."""
    name: str = ""
    kind: str = ""
    design: dict[str, Any] = field(default_factory=dict)
    """The resolved design (set by :func:`gearcalc.compute`), as the JSON output echoes it."""

    def to_dict(self, detail: bool = True) -> dict[str, Any]:
        """The result as plain data, the JSON object of ``gearcalc KIND FILE --format json``."""
        from .render import plain

        out = {"kind": self.kind, "name": self.name, "model": self.model, "summary": plain(self.summary),
               "warnings": list(self.warnings), "checks_failed": list(self.failed), "design": plain(self.design)}
        if detail:
            out["detail"] = plain(self.detail)
        return out

    def _repr_html_(self) -> str:
        """The summary as an HTML table of field, value and unit (Jupyter)."""
        from .render import html_vertical

        return html_vertical(self.summary, self.labels, " ".join(p for p in (self.kind, self.name) if p))

    def to_pandas(self, table: str | None = None):
        """The summary as a one-row pandas DataFrame, or a detail table (``table="rollers"``) with a row per
        element. pandas is not a dependency of gearcalc: install it to use this."""
        import pandas as pd

        if table is None:
            return pd.DataFrame([self.summary])
        if table not in self.detail:
            raise ValueError(f"no detail table {table!r}; this result has " + (", ".join(self.detail) or "none")
                             + " (compute with detail=True)")
        return pd.DataFrame(self.detail[table])


def keyed(key: str, message: str) -> str:
    """A problem's key and message as one text: ``key = value: why`` when the message starts with the value
    (``"= 20: ..."``), else ``key: message``.

    >>> keyed("gearing.pins", "= 20: too many"), keyed("rows.count", "missing"), keyed("", "no key")
    ('gearing.pins = 20: too many', 'rows.count: missing', 'no key')
    """
    if not key:
        return message
    return f"{key} {message}" if message.startswith("= ") else f"{key}: {message}"


class InputError(ValueError):
    """Bad input (exit code 2): carries every message (a design's already prefixed by the file name).

    The one exception the Python API raises for bad input: a ``ValueError``, so ``except ValueError`` sees it.
    """

    def __init__(self, messages: list[str], warnings: list[str] | None = None):
        super().__init__("\n".join(messages))
        self.messages = messages
        self.warnings = warnings or []

    def __reduce__(self):  # pickled (from a worker process) with its attributes, whatever __init__ takes
        return _rebuild, (type(self), self.args, self.__dict__)


def _rebuild(cls, args, state):
    obj = cls.__new__(cls, *args)
    obj.__dict__.update(state)
    return obj


class DesignError(InputError):
    """An input that the schema accepted but the physics cannot: exit code 2.  An :class:`InputError` (its one
    message is :func:`keyed`), so bad input of either kind is caught as one.

    Parameters
    ----------
    key : dotted key the problem is about (``"geometry.eccentricity_mm"``).
    message : the constraint, with the values, e.g. ``"= 52: must be < 50 (...)"``.
    """

    def __init__(self, key: str, message: str):
        super().__init__([keyed(key, message)])
        self.key = key
        self.message = message


class InvalidPoints(DesignError):
    """Some points of a vectorised sweep (``Calculator.sweep``) are not valid designs: ``messages[k]`` is the
    message of point k (its key and constraint, as the point alone would give), None for a valid point.  The sweep
    computes the valid points and gives the others a row with its ``error`` (:func:`gearcalc.grid.evaluate_points`).
    """

    def __init__(self, messages: list):
        first = next(m for m in messages if m is not None)
        super().__init__("", first)
        self.messages = messages


@dataclass
class Problems:
    """Collects every problem found in one design (errors) and the warnings."""

    errors: list[tuple[str, str]] = field(default_factory=list)
    warnings: list[str] = field(default_factory=list)

    def error(self, key: str, message: str) -> None:
        self.errors.append((key, message))

    def warn(self, message: str) -> None:
        self.warnings.append(message)


@dataclass(frozen=True)
class Check:
    """A design check as a margin (architecture convention 10): the summary field ``margin_<name>`` holds a signed,
    dimensionless margin, >= 0 passes, < 0 fails, None where the check does not apply.

    name : the check's name in ``failed_checks`` (``"sigma"``); fails : what a failing point breaks, for the
    run-end counts (``"sigma_max > allowable"``).
    """

    name: str
    fails: str

    @property
    def field(self) -> str:
        return "margin_" + self.name


def failed_checks(summary: dict, checks) -> list:
    """The names of the checks a design's summary fails (its margin < 0), in the order of ``checks``.

    >>> failed_checks({"margin_sigma": -0.1, "margin_rim": None}, (Check("sigma", ""), Check("rim", "")))
    ['sigma']
    """
    return [c.name for c in checks if _below_zero(summary.get(c.field))]


def _below_zero(v) -> bool:
    return v is not None and not isinstance(v, (bool, str)) and v < 0


def _below_zero_points(col) -> list:
    """The indices of a column's values below zero (:func:`_below_zero` of each): a numpy column of numbers by one
    comparison (a flag is no margin; NaN is not below zero), another column value by value."""
    kind = getattr(getattr(col, "dtype", None), "kind", None)
    if kind in ("f", "i", "u"):
        import numpy as np

        return np.flatnonzero(col < 0).tolist()
    if kind == "b":
        return []
    col = col.tolist() if hasattr(col, "tolist") else col  # a numpy column of objects: its values as Python's
    if col and type(col[0]) in _NO_MARGIN and col.count(col[0]) == len(col):  # (identity first: one pass in C)
        return []  # one value that is no margin at every point (a margin not defined anywhere: None)
    types = set(map(type, col))
    if types <= _NO_MARGIN:  # e.g. a margin not defined at any point (None)
        return []
    if types <= _NUMBERS:  # as floats: None is NaN and a flag 0 or 1, neither below zero; a sign is kept
        import numpy as np

        try:
            return np.flatnonzero(np.array(col, dtype=np.float64) < 0).tolist()
        except OverflowError:  # an integer past the floats: value by value
            pass
    return [k for k, v in enumerate(col) if _below_zero(v)]


_NO_MARGIN = {type(None), bool, str}
"""The types of values that are never below zero (:func:`_below_zero`)."""
_NUMBERS = {float, int, bool, type(None)}


def failed_check_column(columns: dict, checks, n: int) -> list:
    """:func:`failed_checks` of every point of column-major summaries (a list of lists of names).  The points that
    fail no check share one empty list (as rows' ``unloaded_rows`` do): 65 536 new lists a sweep chunk, their
    garbage collection, and the list-by-list scans of the writers cost a rows sweep to Parquet about a tenth of its
    CPU time (2026-12-07); a failing point has a list of its own."""
    none: list = []
    out = [none] * n
    for c in checks:
        col = columns.get(c.field)
        if col is None:
            continue
        for k in _below_zero_points(col):
            if out[k] is none:
                out[k] = [c.name]
            else:
                out[k].append(c.name)
    return out


@dataclass(frozen=True)
class Calculator:
    """A registered calculator (see the module docstring)."""

    kind: str
    title: str
    tables: tuple[Table, ...]
    compute: Callable[[Any, Options], Result]
    check: Callable[[Any, Problems], None] | None = None
    models: tuple[str, ...] = ()
    header: str = ""
    sweep: Callable[..., Any] | None = None
    sweep_cost: Callable[..., float] | None = None
    plot: Callable[..., Any] | None = None
    batch: Callable[[Sequence[Any], Options], list[Any]] | None = None
    """Optional: compute many validated designs of this kind at once (numpy over designs).

    ``batch(designs, options)`` returns one item per design, in order: the ``Result`` that
    ``compute(design, options)`` would return, or the exception it would raise
    (``DesignError`` and other exceptions are returned, not raised).  The results must be
    identical to ``compute``; the CLI uses it for batches of two or more designs.
    """

    implicit: Callable[[Any], dict] | None = None
    """Optional: the values the computation takes for keys a valid design leaves out and no schema default fills
    (dotted key -> value, e.g. the default allowable stress), for ``gearcalc check --resolved``."""
    table_fields: tuple[str, ...] = ()
    """The summary fields a terminal table shows for several designs (after ``name``), the handful an
    engineer reads first; ``--fields`` chooses others.  Empty: every field."""
    sweep_plot: tuple[str, ...] = ()
    """The summary fields a sweep's figure plots against the varied key: the first that the sweep has."""
    failure: tuple[tuple[str, Any], ...] = ()
    """(summary field, value) pairs of the flags kept for readers of earlier versions (e.g. ``(("pass", False),)``);
    they are derived from the margins of :attr:`checks`."""
    checks: tuple[Check, ...] = ()
    """The design checks as margins (:class:`Check`): ``compute`` reports the failing ones in ``Result.failed``
    and the summary's ``failed_checks``; a run counts the points failing each."""

    def failed_points(self, columns: dict) -> dict:
        """How many points of column-major summaries fail each design check (its margin < 0): check name -> count,
        the checks with no failing point left out (an empty dict: every point passes)."""
        out = {}
        for c in self.checks:
            col = columns.get(c.field)
            if col is None:
                continue
            count = len(_below_zero_points(col))
            if count:
                out[c.name] = count
        return out

    def check_lines(self, failed: dict, total: int, what: str) -> list:
        """One line per design check that some points (or designs) fail (``failed``: check name -> count), in the
        order of :attr:`checks`: "312 of 4096 points fail sigma (sigma_max > allowable_stress)"."""
        return [f"{failed[c.name]} of {total} {what} fail {c.name} ({c.fails})" for c in self.checks
                if failed.get(c.name)]

    def table(self, name: str) -> Table | None:
        for t in self.tables:
            if t.name == name:
                return t
        return None
