"""Filters: ``--where 'FIELD<=VALUE'`` (repeatable: every condition must hold).

The operators are ``<``, ``<=``, ``>``, ``>=``, ``==`` and ``!=``; VALUE is read as a TOML value (a number,
``true``/``false``, a quoted string) or else taken as a bare word (``--where 'level==exact'``).  Nothing the user
types is evaluated as code: a condition is parsed into (field, operator, value) and applied to a whole chunk's
column at once with numpy.  A number compares with ``<``..``!=``; a word or a flag only with ``==`` and ``!=``.
A point whose FIELD is empty (a field the design does not have, or an output that could not be computed) fails
every condition on it.  FIELD names are checked against the output's fields, with a did-you-mean.

>>> conds = parse_where(["K<=1.5", "pass==true"])
>>> [c.text for c in conds], conds[0].value
(['K<=1.5', 'pass==true'], 1.5)
>>> mask(conds, {"K": [1.2, 1.6, 1.4, None], "pass": [True, True, False, True]}).tolist()
[True, False, False, False]
"""
from __future__ import annotations

import re
import tomllib
from dataclasses import dataclass
from typing import Any

__all__ = ["Condition", "WhereError", "parse_where", "unknown", "mask", "slack", "select"]

OPERATORS = ("<=", ">=", "==", "!=", "<", ">")
_PATTERN = re.compile(r"^\s*([^<>=!\s]+)\s*(<=|>=|==|!=|<|>)\s*(.*?)\s*$", re.S)


class WhereError(ValueError):
    """A malformed ``--where`` or one naming a field the output does not have."""


@dataclass(frozen=True)
class Condition:
    """``field op value``: ``value`` a float, a bool or a str."""

    field: str
    op: str
    value: Any
    text: str

    @property
    def numeric(self) -> bool:
        return isinstance(self.value, float)


def parse_where(items) -> list[Condition]:
    """The conditions of ``--where`` options (none: an empty list).

    >>> parse_where(["efficiency >= 0.9"])[0]
    Condition(field='efficiency', op='>=', value=0.9, text='efficiency>=0.9')
    >>> try:
    ...     parse_where(["K=1"])
    ... except WhereError as exc:
    ...     print(str(exc)[-16:])
    (equality is ==)
    """
    from ..design import _clip

    out = []
    for item in items or ():
        m = _PATTERN.match(item)
        if not m or not m.group(3):
            hint = " (equality is ==)" if "=" in item and not m else ""
            raise WhereError(f"--where {_clip(item)}: expected FIELD OP VALUE with OP one of <, <=, >, >=, ==, !="
                             + hint)
        name, op, text = m.groups()
        try:
            value = tomllib.loads(f"v = {text}")["v"]
        except tomllib.TOMLDecodeError:
            value = text
        if isinstance(value, (int, float)) and not isinstance(value, bool):
            value = float(value)
            if value != value:
                raise WhereError(f"--where {_clip(item)}: the value must be a number, not nan")
        elif isinstance(value, (bool, str)):
            if op not in ("==", "!="):
                raise WhereError(f"--where {_clip(item)}: {op} compares numbers; a word or true/false takes == or !=")
        else:
            raise WhereError(f"--where {_clip(item)}: the value must be a number, true/false or a word")
        out.append(Condition(name, op, value, f"{name}{op}{text}"))
    return out


def unknown(conditions: list[Condition], available) -> list[str]:
    """Messages for the conditions naming a field not among ``available`` (each with a did-you-mean)."""
    from ..design import _suggest

    have = list(available)
    return [f"--where {c.text[:60]}: no such output field" + _suggest(c.field, have)
            for c in conditions if c.field not in have]


def _numbers(column):
    """A column (list or numpy array) as float64 (empty, words and flags: NaN)."""
    import numpy as np

    if isinstance(column, np.ndarray) and column.dtype.kind in "fiu":
        return column.astype(np.float64, copy=False)
    return np.array([float(v) if isinstance(v, (int, float)) and not isinstance(v, bool) else np.nan
                     for v in column], dtype=np.float64)


def _holds(c: Condition, column):
    import numpy as np

    if c.numeric:
        x = _numbers(column)
        with np.errstate(invalid="ignore"):
            ok = {"<": x < c.value, "<=": x <= c.value, ">": x > c.value, ">=": x >= c.value,
                  "==": x == c.value, "!=": x != c.value}[c.op]
        return ok & ~np.isnan(x)
    values = column.tolist() if isinstance(column, np.ndarray) else column
    want = c.value
    eq = np.array([type(v) is type(want) and v == want for v in values], dtype=bool)
    present = np.array([v is not None for v in values], dtype=bool)
    return eq if c.op == "==" else ~eq & present


def mask(conditions: list[Condition], columns: dict, n: int | None = None):
    """The points (a bool array) where every condition holds; ``columns``: field -> list or numpy array."""
    import numpy as np

    if n is None:
        n = len(next(iter(columns.values()))) if columns else 0
    ok = np.ones(n, dtype=bool)
    for c in conditions:
        col = columns.get(c.field)
        ok &= _holds(c, col) if col is not None else False
    return ok


def slack(c: Condition, column):
    """A numeric condition's signed slack per point, relative to its bound: ``>= 0`` where it holds
    (``<``/``<=``: ``(VALUE - x)/|VALUE|``; ``>``/``>=``: ``(x - VALUE)/|VALUE|``; ``==``: ``-|x - VALUE|/|VALUE|``;
    the scale is 1 for a bound of 0).  NaN where the field is empty; None for ``!=`` and a word or flag.

    >>> slack(parse_where(["K<=2"])[0], [1.0, 3.0]).tolist()
    [0.5, -0.5]
    """
    import numpy as np

    if not c.numeric or c.op == "!=":
        return None
    x = _numbers(column)
    scale = abs(c.value) or 1.0
    if c.op in ("<", "<="):
        return (c.value - x) / scale
    if c.op in (">", ">="):
        return (x - c.value) / scale
    return -np.abs(x - c.value) / scale


def select(part, keep):
    """The points of a :class:`gearcalc.render.Columns` where ``keep`` (a bool array) holds, as Columns (its
    messages kept)."""
    import numpy as np

    from ..render import Columns

    if keep.all():
        return part
    idx = np.flatnonzero(keep)
    data = {}
    for k, col in part.data.items():
        if isinstance(col, np.ndarray):
            data[k] = col[idx]
        else:
            data[k] = [col[i] for i in idx.tolist()]
    out = Columns(data, part.errors)
    out.n = int(idx.size)
    return out


@dataclass(frozen=True)
class Filtered:
    """A sweep chunk's ``post`` step (:func:`gearcalc.grid.stream`) with the ``--where`` conditions applied first
    (picklable, so the ``--jobs`` workers filter their own chunks): the fields are checked against the chunk's,
    a condition on a field it lacks a :class:`gearcalc.grid.SweepError`."""

    conditions: tuple
    post: Any = None

    def __call__(self, part):
        from ..grid import SweepError

        bad = unknown(list(self.conditions), list(part.data))
        if bad:
            raise SweepError("; ".join(bad))
        part = select(part, mask(list(self.conditions), part.data, part.n))
        return self.post(part) if self.post is not None else part


def keep_records(records, conditions: list[Condition], fail=WhereError) -> list:
    """The computed designs of a batch (``gearcalc run``) whose summaries meet every condition; a condition on a
    field no design has raises ``fail`` (the command line's Abort) with a did-you-mean."""
    have = dict.fromkeys(k for r in records for k in r.result.summary)
    bad = unknown(conditions, list(have)) if records else []
    if bad:
        raise fail("; ".join(bad))
    if not records:
        return records
    columns = {k: [r.result.summary.get(k) for r in records] for k in have}
    keep = mask(conditions, columns, len(records))
    return [r for r, k in zip(records, keep.tolist()) if k]
