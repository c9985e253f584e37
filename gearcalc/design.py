"""Design files: reading, overriding (``--set``), validating and resolving defaults.

One loader serves every calculator; it knows a calculator only through its schema
(:class:`gearcalc.calculator.Table` / :class:`~gearcalc.calculator.Field`) and its optional
``check`` hook.  Every problem found in a file is reported, each naming the file, the dotted
key and the constraint.  No numpy here: ``gearcalc check`` stays light.
"""
from __future__ import annotations

import difflib
import math
import os
import re
import sys
import tomllib
from dataclasses import dataclass, field
from typing import Any

from .calculator import REQUIRED, Calculator, Field, Problems
from . import registry


@dataclass
class Design:
    """A validated design with every default filled in.

    ``values[table][key]`` holds the resolved values of the tables present (required tables
    and optional tables that the file gives).  ``given`` holds the dotted keys the file (or
    ``--set``) gave explicitly.
    """

    kind: str
    name: str
    source: str
    values: dict[str, dict[str, Any]]
    given: set[str] = field(default_factory=set)
    warnings: list[str] = field(default_factory=list)

    def __getitem__(self, dotted: str) -> Any:
        table, _, key = dotted.partition(".")
        return self.values[table][key]

    def get(self, dotted: str, default: Any = None) -> Any:
        table, _, key = dotted.partition(".")
        return self.values.get(table, {}).get(key, default)

    def has(self, table: str) -> bool:
        """True when the table is part of the design (given, or required by the kind)."""
        return table in self.values

    def is_given(self, dotted: str) -> bool:
        return dotted in self.given

    def resolved(self) -> dict[str, Any]:
        """The fully resolved design as plain data (for the JSON echo and reproducibility)."""
        out: dict[str, Any] = {"kind": self.kind, "name": self.name}
        for table, vals in self.values.items():
            out[table] = {k: v for k, v in vals.items() if v is not None}
        return out


class InputError(Exception):
    """Bad input in one file: carries every message (already prefixed by the file name)."""

    def __init__(self, messages: list[str], warnings: list[str] | None = None):
        super().__init__("\n".join(messages))
        self.messages = messages
        self.warnings = warnings or []


def display_name(source: str) -> str:
    return "<stdin>" if source == "-" else source


def read_toml(source: str) -> dict:
    """Read and parse a TOML design from a path or ``-`` (stdin); errors become InputError."""
    where = display_name(source)
    try:
        if source == "-":
            raw = sys.stdin.buffer.read()
        else:
            if os.path.isdir(source):
                raise InputError([f"{where}: is a directory (use 'gearcalc run' for folders)"])
            with open(source, "rb") as fh:
                raw = fh.read()
    except InputError:
        raise
    except FileNotFoundError:
        raise InputError([f"{where}: no such file"]) from None
    except PermissionError:
        raise InputError([f"{where}: cannot be read (permission denied)"]) from None
    except OSError as exc:
        raise InputError([f"{where}: cannot be read ({exc.strerror or exc})"]) from None
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        line = raw[: exc.start].count(b"\n") + 1
        raise InputError([f"{where}: not UTF-8 text (bad byte at line {line}); "
                          "a design file is TOML in UTF-8"]) from None
    if not text.strip():
        raise InputError([f"{where}: empty file; a design needs at least kind = \"...\" (see 'gearcalc new KIND')"])
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise InputError([f"{where}: TOML syntax error: {exc}"]) from None
    except RecursionError:
        raise InputError([f"{where}: TOML nesting too deep"]) from None


def parse_set(items: list[str]) -> list[tuple[str, Any]]:
    """Parse ``--set KEY=VALUE`` items; VALUE is read as a TOML value, else as a string."""
    out = []
    for item in items or []:
        key, sep, value = item.partition("=")
        key = key.strip()
        if not sep or not key:
            raise InputError([f"--set {item!r}: expected KEY=VALUE, e.g. --set rows.count=4"])
        value = value.strip()
        try:
            parsed = tomllib.loads(f"v = {value}")["v"]
        except tomllib.TOMLDecodeError:
            parsed = value
        out.append((key, parsed))
    return out


def apply_set(raw: dict, overrides: list[tuple[str, Any]]) -> None:
    for key, value in overrides:
        node = raw
        parts = key.split(".")
        for p in parts[:-1]:
            nxt = node.get(p)
            if not isinstance(nxt, dict):
                nxt = node[p] = {}
            node = nxt
        node[parts[-1]] = value


def _suggest(word: str, candidates: list[str]) -> str:
    close = difflib.get_close_matches(word, candidates, n=1, cutoff=0.6)
    return f" (did you mean '{close[0]}'?)" if close else ""


def _show(value: Any) -> str:
    if isinstance(value, str):
        return f'"{value}"'
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (list, dict)):
        text = repr(value)
        return text if len(text) <= 60 else text[:57] + "..."
    return repr(value)


def check_value(f: Field, value: Any) -> tuple[Any, str | None]:
    """Check one value against its field; return (normalised value, error or None)."""
    if isinstance(value, str) and f.choices and f.type != "string":
        if value in f.choices:
            return value, None
        return value, "must be " + f.constraint() + _string_hint(f, value)
    t = f.type
    if t == "string":
        if not isinstance(value, str) or (f.choices and value not in f.choices):
            return value, "must be " + f.constraint() + (_string_hint(f, value) if isinstance(value, str) else "")
        return value, None
    if t == "bool":
        return (value, None) if isinstance(value, bool) else (value, "must be true or false")
    if t == "numbers":
        if not isinstance(value, list) or any(isinstance(v, bool) or not isinstance(v, (int, float)) for v in value):
            return value, "must be " + f.constraint()
        if f.length is not None and len(value) != f.length:
            return value, "must be " + f.constraint()
        vals = [float(v) for v in value]
        for v in vals:
            err = _bounds(f, v)
            if err:
                return value, err
        return vals, None
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return value, "must be " + f.constraint() + (_string_hint(f, value) if isinstance(value, str) else "")
    if t == "integer":
        if not isinstance(value, int):
            return value, "must be " + f.constraint()
    else:
        value = float(value)
        if not math.isfinite(value):
            return value, "must be a finite number"
    return value, _bounds(f, value)


def _string_hint(f: Field, value: str) -> str:
    """The fix for a string where a word or a number was expected: a did-you-mean among the words, or,
    for a number written with its unit ("5 mm"), that the unit belongs to the key's name."""
    hint = _suggest(value, list(f.choices)) if f.choices else ""
    if hint:
        return hint
    m = re.fullmatch(r"\s*([-+]?[0-9.]+(?:[eE][-+]?[0-9]+)?)\s*([A-Za-z°%/·*0-9]+)\s*", value)
    if m and f.type in ("number", "integer"):
        unit = f.name.rsplit("_", 1)[-1] if "_" in f.name else ""
        where = f" (the unit, {unit}, is in the key's name)" if unit and unit != f.name else ""
        return f"; write the bare number {m.group(1)}{where}"
    return ""


def _bounds(f: Field, v: float) -> str | None:
    if not math.isfinite(v):
        return "must be a finite number"
    bad = ((f.gt is not None and not v > f.gt) or (f.ge is not None and not v >= f.ge)
           or (f.lt is not None and not v < f.lt) or (f.le is not None and not v <= f.le))
    return ("must be " + f.constraint()) if bad else None


def validate(raw: dict, source: str, kind_hint: str | None = None) -> Design:
    """Validate a parsed design against its calculator; raise InputError listing every problem."""
    where = display_name(source)
    errors: list[str] = []
    kind = raw.get("kind")
    if kind is None:
        if kind_hint is None:
            raise InputError([f"{where}: kind: missing; must be one of {', '.join(registry.kinds())}"])
        kind = kind_hint
    if not isinstance(kind, str) or kind not in registry.kinds():
        raise InputError([f"{where}: kind = {_show(kind)}: must be one of "
                          + ", ".join(f'"{k}"' for k in registry.kinds())
                          + (_suggest(kind, list(registry.kinds())) if isinstance(kind, str) else "")])
    if kind_hint is not None and kind != kind_hint:
        raise InputError([f"{where}: kind = \"{kind}\": this command computes \"{kind_hint}\" designs "
                          f"(use 'gearcalc {kind}' or 'gearcalc run')"])
    calc: Calculator = registry.get(kind)
    name = raw.get("name", os.path.splitext(os.path.basename(where))[0])
    if not isinstance(name, str):
        errors.append(f"{where}: name = {_show(name)}: must be a string")
        name = str(name)
    table_names = [t.name for t in calc.tables]
    all_keys = [f"{t.name}.{f.name}" for t in calc.tables for f in t.fields]
    values: dict[str, dict[str, Any]] = {}
    given: set[str] = set()
    for key, val in raw.items():
        if key in ("kind", "name"):
            continue
        if key not in table_names:
            hint = _suggest(key, table_names + ["kind", "name"])
            if not hint:
                bare = {k.split(".", 1)[1]: k for k in all_keys}
                close = difflib.get_close_matches(key, list(bare), n=1, cutoff=0.6)
                hint = f" (did you mean '{bare[close[0]]}'?)" if close else ""
            errors.append(f"{where}: {key}: unknown key{hint}; a {kind} design has the tables "
                          + ", ".join(f"[{t}]" for t in table_names))
            continue
        if not isinstance(val, dict):
            errors.append(f"{where}: {key}: must be a table [{key}]")
    for table in calc.tables:
        given_tab = raw.get(table.name)
        if not isinstance(given_tab, dict):
            if given_tab is not None:
                continue  # reported above
            if table.optional:
                continue
            given_tab = {}
        names = [f.name for f in table.fields]
        for key in given_tab:
            if key not in names:
                close = difflib.get_close_matches(key, names, n=1, cutoff=0.6)
                hint = (f" (did you mean '{table.name}.{close[0]}'?)" if close
                        else _suggest(f"{table.name}.{key}", all_keys))
                errors.append(f"{where}: {table.name}.{key}: unknown key{hint}; [{table.name}] takes "
                              + ", ".join(names))
        resolved: dict[str, Any] = {}
        for f in table.fields:
            dotted = f"{table.name}.{f.name}"
            if f.name in given_tab:
                value, err = check_value(f, given_tab[f.name])
                if err:
                    errors.append(f"{where}: {dotted} = {_show(given_tab[f.name])}: {err}")
                resolved[f.name] = value
                given.add(dotted)
            elif f.default is REQUIRED:
                errors.append(f"{where}: {dotted}: missing; required ({f.constraint()}"
                              + (f"; {f.doc}" if f.doc else "") + ")")
                resolved[f.name] = None
            else:
                resolved[f.name] = f.default
        values[table.name] = resolved
    if errors:
        raise InputError(errors)
    design = Design(kind=kind, name=name, source=source, values=values, given=given)
    if calc.check is not None:
        problems = Problems()
        calc.check(design, problems)
        if problems.errors:
            raise InputError([f"{where}: {k}: {m}" if k else f"{where}: {m}" for k, m in problems.errors],
                             [f"{where}: warning: {w}" for w in problems.warnings])
        design.warnings.extend(problems.warnings)
    return design


def load(source: str, overrides: list[tuple[str, Any]] | None = None, kind_hint: str | None = None) -> Design:
    """Read, override and validate one design file (``-`` for stdin)."""
    raw = read_toml(source)
    if overrides:
        apply_set(raw, overrides)
    return validate(raw, source, kind_hint)


def expand_paths(paths: list[str]) -> list[str]:
    """Files from PATHs: a folder stands for every ``*.toml`` below it (sorted)."""
    out: list[str] = []
    for p in paths:
        if p != "-" and os.path.isdir(p):
            found = []
            for root, dirs, files in os.walk(p):
                dirs.sort()
                found.extend(os.path.join(root, f) for f in sorted(files) if f.endswith(".toml"))
            out.extend(found)
        else:
            out.append(p)
    return out
