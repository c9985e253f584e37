"""Design files: reading, overriding (``--set``), validating and resolving defaults.

One loader serves every calculator; it knows a calculator only through its schema
(:class:`gearcalc.calculator.Table` / :class:`~gearcalc.calculator.Field`) and its optional
``check`` hook.  Every problem found in a file is reported, each naming the file, the dotted
key and the constraint.  No numpy here: ``gearcalc check`` stays light.

Reading is bounded: a design file is read up to :data:`MAX_DESIGN_BYTES` (more is refused), dotted
keys have at most :data:`MAX_KEY_PARTS` parts and values nest at most :data:`MAX_NESTING` levels, so
that every file ends, in bounded time and memory, in a design or in messages naming the file.  Every
hint works on a bounded piece of the input, and every value or key echoed in a message is cut to
about :data:`SHOW_CHARS` characters.
"""
from __future__ import annotations

import difflib
import math
import os
import re
import stat
import sys
import tomllib
from dataclasses import dataclass, field
from typing import Any

from .calculator import REQUIRED, Calculator, Field, InputError, Problems, keyed  # noqa: F401 - InputError re-exported
from . import registry, units

MAX_DESIGN_BYTES = 1 << 20
"""The cap on one design file (1 MiB; the shipped designs are 1-2 KB). At most cap + 1 bytes are read."""
MAX_KEY_PARTS = 32
"""The most parts a dotted key or table header may have (tomllib's cost grows with their square)."""
MAX_NESTING = 32
"""The deepest nesting of tables, arrays and inline tables accepted (a design needs 3)."""
SHOW_CHARS = 60
"""Values and keys echoed in messages are cut to about this many characters."""
MAX_UNKNOWN_SHOWN = 20
"""Unknown keys reported one by one per table; the rest are counted."""
MAX_SUGGEST_CHARS = 100
"""Did-you-mean is not tried for words longer than this (no key is that long)."""
MAX_SKIPPED_SHOWN = 5
"""Files of a folder skipped for their names (``A.TOML``, ``b.toml.txt``) named in its note; the rest counted."""


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

    def keep(self, what: str, key: Any, value: Any) -> None:
        """Leave ``value`` (what a kind's check prepared from the values ``key``, e.g. its arrays) for this design's
        computation in this run (:meth:`take`): each design prepared once.  Not pickled (a worker prepares again)."""
        self.__dict__.setdefault("_kept", {})[what] = (key, value)

    def take(self, what: str, key: Any) -> Any:
        """The value :meth:`keep` left, when made from the values ``key`` (the design unchanged since), else None;
        taken once (a second computation of the design prepares afresh)."""
        kept = self.__dict__.get("_kept", {}).pop(what, None)
        return kept[1] if kept is not None and kept[0] == key else None

    def __getstate__(self) -> dict:
        return {k: v for k, v in self.__dict__.items() if k != "_kept"}

    def resolved(self, implicit: bool = False) -> dict[str, Any]:
        """The fully resolved design as plain data (for the JSON echo and reproducibility); ``implicit``: with the
        values the computation takes for keys left out (``check --resolved``: every key the computation uses)."""
        out: dict[str, Any] = {"kind": self.kind, "name": self.name}
        for table, vals in self.values.items():
            out[table] = {k: v for k, v in vals.items() if v is not None}
        fill = registry.get(self.kind).implicit if implicit else None
        for key, value in (fill(self) if fill else {}).items():
            table, _, name = key.partition(".")
            if table in out and out[table].get(name) is None:
                out[table][name] = value
        return out


class FolderFile(str):
    """A path found in a folder (not named on the command line): read only when it is a regular file."""


class PathProblem(str):
    """An entry of :func:`expand_paths` that cannot be read (an unreadable folder): loading it raises
    an :class:`InputError` with its message, so the rest of the batch goes on."""

    message: str

    def __new__(cls, path: str, message: str):
        obj = super().__new__(cls, path)
        obj.message = message
        return obj


def display_name(source: str) -> str:
    return "<stdin>" if source == "-" else str(source)


def _clip(text: Any, limit: int = SHOW_CHARS) -> str:
    """Text cut to about ``limit`` characters, with every non-printable character escaped (one line)."""
    text = str(text)
    cut = len(text) > limit
    if cut:
        text = text[: limit - 1]
    if not text.isprintable():
        text = "".join(c if c.isprintable() else c.encode("unicode_escape").decode("ascii") for c in text)
    return text + "…" if cut else text


def _size(n: int) -> str:
    return f"{n >> 20} MiB" if n % (1 << 20) == 0 else f"{n} bytes"


def _file_kind(mode: int) -> str:
    for test, word in ((stat.S_ISFIFO, "a FIFO"), (stat.S_ISCHR, "a character device"),
                       (stat.S_ISBLK, "a block device"), (stat.S_ISSOCK, "a socket"), (stat.S_ISDIR, "a folder")):
        if test(mode):
            return word
    return "not a regular file"


def _read_capped(read, where: str) -> bytes:
    """At most MAX_DESIGN_BYTES + 1 bytes from ``read(n)``; more is refused."""
    chunks, total = [], 0
    while total <= MAX_DESIGN_BYTES:
        chunk = read(min(1 << 16, MAX_DESIGN_BYTES + 1 - total))
        if not chunk:
            break
        chunks.append(chunk)
        total += len(chunk)
    if total > MAX_DESIGN_BYTES:
        raise InputError([f"{where}: larger than {_size(MAX_DESIGN_BYTES)}, the cap on a design file "
                          "(a design is a few KB of TOML)"])
    return b"".join(chunks)


def _read_bytes(source: str, where: str) -> bytes:
    if isinstance(source, PathProblem):
        raise InputError([source.message])
    if source == "-":
        return _read_capped(sys.stdin.buffer.read, where)
    from_folder = isinstance(source, FolderFile)
    flags = os.O_RDONLY | getattr(os, "O_CLOEXEC", 0) | getattr(os, "O_NOCTTY", 0)
    if from_folder:
        flags |= getattr(os, "O_NONBLOCK", 0)  # a FIFO put there after the listing must not block
    try:
        fd = _open_input(source, flags, where)
    except FileNotFoundError:
        extra = " (a broken symbolic link)" if os.path.islink(source) else ""
        raise InputError([f"{where}: no such file{extra}"]) from None
    except PermissionError:
        raise InputError([f"{where}: cannot be read (permission denied)"]) from None
    except OSError as exc:
        raise InputError([f"{where}: cannot be read ({exc.strerror or exc})"]) from None
    try:
        mode = os.fstat(fd).st_mode
        if stat.S_ISDIR(mode):
            raise InputError([f"{where}: is a directory (use 'gearcalc run' for folders)"])
        if from_folder and not stat.S_ISREG(mode):
            raise InputError([f"{where}: {_file_kind(mode)}, not a regular file; only regular files "
                              "are read from a folder (name it explicitly to read it)"])
        return _read_capped(lambda n: os.read(fd, n), where)
    except OSError as exc:
        raise InputError([f"{where}: cannot be read ({exc.strerror or exc})"]) from None
    finally:
        os.close(fd)


FIFO_WAIT = 1.0
"""Seconds a named FIFO may keep its reader waiting for a writer before gearcalc says it waits."""


def _open_input(source: str, flags: int, where: str) -> int:
    """``os.open``; opening a FIFO waits for a writer, and after :data:`FIFO_WAIT` seconds stderr says so
    (``gearcalc run d/*.toml`` with a FIFO among the files would otherwise wait silently)."""
    try:
        fifo = not flags & getattr(os, "O_NONBLOCK", 0) and stat.S_ISFIFO(os.stat(source).st_mode)
    except (OSError, ValueError):
        fifo = False
    if not fifo:
        return os.open(source, flags)
    import threading

    def say() -> None:
        if sys.stderr is not None:
            try:
                print(f"{where}: a FIFO; waiting for a program to write to it (Ctrl-C to stop)", file=sys.stderr,
                      flush=True)
            except (OSError, ValueError):
                pass

    timer = threading.Timer(FIFO_WAIT, say)
    timer.daemon = True
    timer.start()
    try:
        return os.open(source, flags)
    finally:
        timer.cancel()


# A chain of dotted-key parts (bare or quoted) at a key position: line start, a table header, or
# after "{" or "," (inline tables). Possessive/atomic where a part could backtrack: linear time.
_KEY_PART = r"""(?:[A-Za-z0-9_-]++|"[^"\n]*+"|'[^'\n]*+')"""
_LONG_KEY = re.compile(r"(?m)(?:^[ \t]*+(?:\[\[?[ \t]*+)?|[{,][ \t]*+)" + _KEY_PART
                       + r"(?:[ \t]*+\.[ \t]*+" + _KEY_PART + r"){%d}" % MAX_KEY_PARTS)


def _line_col(text: str, pos: int) -> str:
    line = text.count("\n", 0, pos) + 1
    return f"line {line}, column {pos - text.rfind(chr(10), 0, pos)}"


def number_hint(text: str) -> str | None:
    """What is wrong with a value that looks like a number but is not TOML, and what to write; None otherwise.

    >>> number_hint("03")
    'leading zeros are not allowed in TOML numbers: write 3'
    >>> number_hint("0.1e")
    "incomplete exponent: write digits after the 'e' (0.1e3) or leave it out (0.1)"
    >>> number_hint("1,5")
    'TOML writes a decimal point, not a comma: write 1.5 (a list is [1, 5])'
    >>> number_hint("2."), number_hint("10 kN")
    ('a TOML float needs a digit after the point: write 2.0', None)
    """
    t = text.strip()
    if len(t) > _HINT_CHARS:
        return None
    m = re.fullmatch(r"([+-]?)(0[0-9_]+)((?:\.[0-9_]+)?(?:[eE][+-]?[0-9_]+)?)", t)
    if m:
        return f"leading zeros are not allowed in TOML numbers: write {m[1]}{m[2].lstrip('0_') or '0'}{m[3]}"
    m = re.fullmatch(r"([+-]?(?:[0-9_]+(?:\.[0-9_]*)?|\.[0-9_]+))[eE][+-]?", t)
    if m:
        return f"incomplete exponent: write digits after the 'e' ({t.rstrip('+-')}3) or leave it out ({m[1]})"
    if re.fullmatch(r"[+-]?[0-9][0-9_]*\.", t):
        return f"a TOML float needs a digit after the point: write {t}0"
    if re.fullmatch(r"[+-]?\.[0-9][0-9_]*", t):
        return f"a TOML float needs a digit before the point: write {t.replace('.', '0.')}"
    m = re.fullmatch(r"([+-]?[0-9]+),([0-9]+)", t)
    if m:
        return f"TOML writes a decimal point, not a comma: write {m[1]}.{m[2]} (a list is [{m[1]}, {m[2]}])"
    return None


_ERROR_AT = re.compile(r"\(at line (\d+), column (\d+)\)$")
_PART = r"""(?:[A-Za-z0-9_-]+|"[^"\n]*"|'[^'\n]*')"""
_ASSIGN = re.compile(r"^[ \t]*(" + _PART + r"(?:[ \t]*\.[ \t]*" + _PART + r")*)[ \t]*=[ \t]*(.*?)[ \t]*(?:#.*)?$")
_HEADER = re.compile(r"^[ \t]*\[[ \t]*([^\[\]\n]+?)[ \t]*\][ \t]*(?:#.*)?$")


def _syntax_hint(text: str, msg: str) -> str:
    """A sentence after a TOML syntax error saying what to write instead, for the usual mistakes: a number that
    is not TOML (:func:`number_hint`), a word without quotes, a key or a table given twice."""
    if msg.startswith(("Cannot overwrite a value", "Cannot declare")):
        return _twice(text)
    m = _ERROR_AT.search(msg)
    if not m:
        return ""
    lines = text.split("\n")
    line = lines[int(m[1]) - 1] if int(m[1]) <= len(lines) else ""
    a = _ASSIGN.match(line[:2 * _HINT_CHARS + 200])
    if not a:
        return ""
    key, value = a[1], a[2]
    hint = number_hint(value)
    if hint:
        return f"; {hint}"
    word = len(value) <= _HINT_CHARS and re.fullmatch(r"[A-Za-z][A-Za-z0-9_ .-]*", value)
    if msg.startswith("Invalid value") and word:
        return f"; a word is a string in TOML: write {key} = \"{value}\""
    return ""


def _twice(text: str) -> str:
    """Where a key or a table is given twice (a line scan of tables and keys; a design has no multi-line
    strings), as a sentence after the error."""
    seen: dict[str, int] = {}
    table = ""
    for n, line in enumerate(text.split("\n"), 1):
        h = _HEADER.match(line)
        if h:
            table = re.sub(r"[ \t]*\.[ \t]*", ".", h[1])
            if table in seen:
                return f"; the table [{_clip(table)}] is given twice (lines {seen[table]} and {n}): merge them into one"
            seen[table] = n
            continue
        a = _ASSIGN.match(line)
        if a:
            key = (table + "." if table else "") + re.sub(r"[ \t]*\.[ \t]*", ".", a[1])
            if key in seen:
                return f"; {_clip(key)} is given twice (lines {seen[key]} and {n}): keep one"
            seen[key] = n
    return ""


def _utf16(raw: bytes) -> bool:
    """Whether the bytes are UTF-16 text (a byte-order mark, or a NUL byte beside every ASCII character)."""
    if raw.startswith((b"\xff\xfe", b"\xfe\xff")):
        return True
    head = raw[:256]
    return len(head) >= 4 and (head[1::2].count(0) > len(head) // 4 or head[0::2].count(0) > len(head) // 4)


def _parse(raw: bytes, where: str) -> dict:
    if b"\0" in raw[:256] or raw.startswith((b"\xff\xfe", b"\xfe\xff")):
        if _utf16(raw):
            raise InputError([f"{where}: UTF-16 text; a design file is TOML in UTF-8: save it as UTF-8 "
                              "(e.g. iconv -f UTF-16 -t UTF-8 old.toml > new.toml)"])
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        line = raw[: exc.start].count(b"\n") + 1
        raise InputError([f"{where}: not UTF-8 text (bad byte at line {line}); "
                          "a design file is TOML in UTF-8"]) from None
    if text.startswith("\ufeff"):  # a UTF-8 byte-order mark, as some Windows editors write
        text = text[1:]
    if not text.strip():
        raise InputError([f"{where}: empty file; a design needs at least kind = \"...\" (see 'gearcalc new KIND')"])
    m = _LONG_KEY.search(text)
    if m:
        raise InputError([f"{where}: {_line_col(text, m.start())}: a dotted key or table name of more than "
                          f"{MAX_KEY_PARTS} parts; a design key has 2 (table.key)"])
    try:
        doc = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        msg = str(exc)
        if msg.endswith("(at end of document)"):
            msg = msg[: -1] + f", {_line_col(text, len(text))})"
        raise InputError([f"{where}: TOML syntax error: {msg}{_syntax_hint(text, str(exc))}"]) from None
    except RecursionError:
        raise InputError([f"{where}: TOML nesting too deep (arrays or inline tables nested hundreds of "
                          f"levels); a design nests at most {MAX_NESTING} levels"]) from None
    except ValueError as exc:
        limit = sys.get_int_max_str_digits()
        if "limit" in str(exc) and limit:
            at = re.search(r"(?<![0-9_])[0-9][0-9_]{%d,}" % limit, text)  # from a run's start: linear
            place = f" at {_line_col(text, at.start())}" if at else ""
            raise InputError([f"{where}: an integer of more than {limit} digits{place}; no design value "
                              "needs that many (the largest accepted numbers have 16 digits)"]) from None
        raise
    _check_nesting(doc, where)
    return doc


def _check_nesting(doc: dict, where: str) -> None:
    """Refuse values nested deeper than MAX_NESTING (iteratively: no recursion on hostile input)."""
    stack: list[tuple[Any, int, str]] = [(doc, 0, "")]
    while stack:
        node, depth, path = stack.pop()
        if depth > MAX_NESTING:
            raise InputError([f"{where}: {_clip(path) or 'the document'}: nested more than {MAX_NESTING} levels "
                              "deep; a design is tables of plain values and arrays"])
        items = node.items() if isinstance(node, dict) else enumerate(node)
        for k, v in items:
            if isinstance(v, (dict, list)):
                sub = f"{path}.{k}" if path and isinstance(node, dict) else f"{path}[{k}]" if path else str(k)
                stack.append((v, depth + 1, sub[: 2 * SHOW_CHARS]))  # cut: no copy of long keys per child


def read_toml(source: str) -> dict:
    """Read and parse a TOML design from a path or ``-`` (stdin); every problem becomes an InputError.

    A path found in a folder (:class:`FolderFile`) is read only when it is a regular file; a path
    named explicitly may be a FIFO or a device (``<(cmd)``), always read with the size cap.
    """
    where = display_name(source)
    try:
        return _parse(_read_bytes(source, where), where)
    except InputError:
        raise
    except RecursionError:
        raise InputError([f"{where}: TOML nesting too deep; a design nests at most {MAX_NESTING} levels"]) from None
    except MemoryError:
        raise InputError([f"{where}: too large to read into memory"]) from None
    except Exception as exc:  # noqa: BLE001 - any other problem with this one file is this file's message
        raise InputError([f"{where}: cannot be read or parsed ({type(exc).__name__}: {_clip(exc)})"]) from None


_TRAILING = "Expected newline or end of document after a statement"
_WITH_UNIT = re.compile(r"[-+]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)(?:[eE][-+]?[0-9]+)?[ \t]*[^\s=0-9,.][^=\n\r]{0,40}")
"""A number with a unit after it (``10kN``, ``5 deg``): taken as a string, whose check proposes the bare number."""


def parse_set(items: list[str], word: str = "--set") -> list[tuple[str, Any]]:
    """Parse ``--set KEY=VALUE`` items: one key, one value.

    VALUE is read as one TOML value; anything after it (a second value, another ``key = value`` on a
    new line) is an error naming the item.  A bare word that is not TOML (``--set sun.torsion_diameter=root``)
    is taken as a string, unless it holds a newline or ``=``.  Messages name an item as ``{word} 'ITEM'`` (the
    Python API's word is ``overrides:``).
    """
    out = []
    for item in items or []:
        shown = f"{word} '{_clip(item)}'"
        key, sep, value = item.partition("=")
        key = key.strip()
        if not sep or not key:
            example = "--set rows.count=4" if word == "--set" else "'rows.count=4'"
            raise InputError([f"{shown}: expected KEY=VALUE, e.g. {example}"])
        problem = key_problem(key)
        if problem:
            raise InputError([f"{shown}: {problem}"])
        value = value.strip()
        if not value:
            raise InputError([f"{shown}: no value after '=' (quote an empty string: KEY='\"\"')"])
        if _LONG_KEY.search(value):
            raise InputError([f"{shown}: a dotted key of more than {MAX_KEY_PARTS} parts in the value"])
        try:
            doc = tomllib.loads(f"v = {value}")
        except tomllib.TOMLDecodeError as exc:
            hint = number_hint(value)
            if hint:
                raise InputError([f"{shown}: {hint}"]) from None
            if _WITH_UNIT.fullmatch(value):  # "10kN": a string, which the key's check converts (as in a file)
                out.append((key, value))
                continue
            if str(exc).startswith(_TRAILING) or "\n" in value or "\r" in value or "=" in value:
                raise InputError([f"{shown}: one key takes one value; found more after the value "
                                  "(quote a string: KEY='\"text\"')"]) from None
            if value[0] in "[{\"'":
                raise InputError([f"{shown}: not a TOML value ({_clip(exc)})"]) from None
            doc = {"v": value}  # a bare word: a string
        except RecursionError:
            raise InputError([f"{shown}: the value is nested too deeply"]) from None
        except ValueError as exc:
            if "limit" in str(exc):
                raise InputError([f"{shown}: an integer of more than {sys.get_int_max_str_digits()} "
                                  "digits; no design value needs that many"]) from None
            raise InputError([f"{shown}: not a value ({_clip(exc)})"]) from None
        if set(doc) != {"v"}:
            raise InputError([f"{shown}: one key takes one value; found more after the value"])
        _check_nesting(doc, shown)
        out.append((key, doc["v"]))
    return out


def key_problem(key: str) -> str | None:
    """Why ``key`` cannot be a dotted design key (an empty part, too many parts), or None."""
    if key.count(".") >= MAX_KEY_PARTS or not all(p.strip() for p in key.split(".")):
        return "the key must be a dotted key such as rows.count"
    return None


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
    """A did-you-mean among a few candidates; nothing for a word longer than any key could be."""
    if not isinstance(word, str) or len(word) > MAX_SUGGEST_CHARS:
        return ""
    close = difflib.get_close_matches(word, candidates, n=1, cutoff=0.6)
    return f" (did you mean '{close[0]}'?)" if close else ""


def _show(value: Any) -> str:
    """A value as written in TOML, for a message: at most about SHOW_CHARS characters, on one line."""
    if isinstance(value, str):
        return f'"{_clip(value)}"'
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (list, dict)):
        import reprlib

        r = reprlib.Repr()
        r.maxlevel, r.maxlist, r.maxdict, r.maxstring, r.maxother, r.maxlong = 3, 8, 4, 24, 24, 24
        return _clip(r.repr(value))
    try:
        return _clip(repr(value))
    except ValueError:  # an int beyond the digit limit
        return "<a very long number>"


def check_value(f: Field, value: Any) -> tuple[Any, str | None]:
    """Check one value against its field; return (normalised value, error or None)."""
    if isinstance(value, str) and f.type in ("number", "integer") and value not in f.choices:
        converted, why = quantity_value(f, value)  # "2 kN*m" on a key in N·m: 2000
        if why:
            return value, why
        if converted is not None:
            value = int(converted) if f.type == "integer" and converted.is_integer() else converted
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
        try:
            vals = [float(v) for v in value]
        except OverflowError:
            return value, "must be " + f.constraint() + " (a number is too large)"
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
        try:
            value = float(value)
        except OverflowError:
            return value, "must be a finite number"
        if not math.isfinite(value):
            return value, "must be a finite number"
    return value, _bounds(f, value)


# A number at the start of a hint's text: digits only (no "_", no "0x"), an optional fraction and exponent.
_NUMBER = re.compile(r"[-+]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)(?:[eE][-+]?[0-9]+)?")
_HINT_CHARS = 64
"""Only strings this short are read for a number (and a unit) to propose: linear and bounded."""


def _number_text(x: float, integer: bool) -> str | None:
    """A number as TOML text: an integer when it is one, else the shortest exact float."""
    if x.is_integer() and abs(x) < 1e16:
        return str(int(x))
    if integer:
        return None
    return repr(x)


def with_unit(text: str, unit: str) -> float | None:
    """The number that ``text``, a number with a unit ("10 kN", "10kN"), stands for in ``unit`` (the unit of a
    key's name); None when it is no such text or the unit is not one gearcalc knows.

    >>> with_unit("10 kN", "N"), with_unit("1.5 m", "mm"), with_unit("10 apples", "N")
    (10000.0, 1500.0, None)
    """
    text = text.strip()
    m = _NUMBER.match(text) if len(text) <= _HINT_CHARS and unit else None
    rest = text[m.end():].strip() if m else ""
    if not rest:
        return None
    try:
        y = units.convert_hint(float(m.group(0)), rest, unit)
    except (ValueError, OverflowError):
        return None
    return y if y is not None and math.isfinite(y) else None


def quantity_value(f: Field, text: str) -> tuple[float | None, str | None]:
    """A number with a unit (``"2 kN*m"``) on a key with a unit in its name, in the key's unit (pint, imported
    only here): (value, None); (None, why) for a unit of another quantity; (None, None) when the text is no
    quantity (the check's hint then proposes a bare number)."""
    unit = units.unit_of(f.name)
    text = text.strip()
    m = _NUMBER.match(text) if unit and len(text) <= _HINT_CHARS else None
    rest = text[m.end():].strip() if m else ""
    if not rest:
        return None, None
    try:
        number = float(m.group(0))
    except (ValueError, OverflowError):
        return None, None
    if not math.isfinite(number):
        return None, None
    from .quantity import convert

    return convert(number, rest, unit)


def _string_hint(f: Field, value: str) -> str:
    """The fix for a string where a word or a number was expected: a did-you-mean among the words; for
    a quoted number, the number without quotes; for a number with a unit ("10 kN"), the number in the
    key's unit (the unit is in the key's name) when the unit is one gearcalc knows, else no number.
    Never a wrong number: what cannot be converted exactly is not proposed."""
    if f.choices:
        hint = _suggest(value, list(f.choices))
        if hint:
            return hint
    if f.type not in ("number", "integer"):
        return ""
    unit = units.unit_of(f.name)
    integer = f.type == "integer"
    what = "an integer" if integer else "a number"
    generic = (f"; write a bare number in {unit} (the unit is in the key's name)" if unit
               else f"; write {what} without quotes (the key has no unit)")
    text = value.strip()
    if len(text) > _HINT_CHARS:
        return generic
    m = _NUMBER.match(text)
    if not m:
        return ""
    try:
        x = float(m.group(0))
    except (ValueError, OverflowError):
        return generic
    if not math.isfinite(x):
        return generic
    rest = text[m.end():].strip()
    if not rest:
        shown = _number_text(x, integer)
        return f"; write it without quotes: {shown}" if shown else f"; write {what} without quotes"
    y = units.convert_hint(x, rest, unit) if unit else None
    if y is None or not math.isfinite(y):
        return generic
    shown = _number_text(y, integer) if y.is_integer() else (None if integer else f"{y:.15g}")
    if shown is None:
        return generic
    if units.same_unit(rest, unit):
        return f"; write the bare number {shown} (the unit, {unit}, is in the key's name)"
    return (f"; write the bare number {shown} ({_clip(text, 30)} = {shown} {unit}: the unit, {unit}, is in the "
            "key's name)")


def _bounds(f: Field, v: float) -> str | None:
    if isinstance(v, float) and not math.isfinite(v):  # an int (of any size) compares exactly
        return "must be a finite number"
    bad = ((f.gt is not None and not v > f.gt) or (f.ge is not None and not v >= f.ge)
           or (f.lt is not None and not v < f.lt) or (f.le is not None and not v <= f.le))
    return ("must be " + f.constraint()) if bad else None


def _unknown_key_hint(key: str, table: str | None, calc: Calculator) -> str:
    """Why a key is unknown and where it belongs: a key of another table names that table; a table
    name used as a key says it is a table; else the closest key, in this table first."""
    homes = [t.name for t in calc.tables if t.field(key) is not None and t.name != table]
    if homes:
        where = " or ".join(f"[{h}]" for h in homes)
        return f" ({key} belongs in {where}, i.e. {homes[0]}.{key})"
    table_names = [t.name for t in calc.tables]
    if table is not None and key in table_names:
        return f" ([{key}] is a table of its own, at the top level)"
    if table is None:
        hint = _suggest(key, table_names + ["kind", "name"])
        if hint:
            return hint
    else:
        names = [f.name for f in calc.table(table).fields]
        close = difflib.get_close_matches(key, names, n=1, cutoff=0.6) if len(key) <= MAX_SUGGEST_CHARS else []
        if close:
            return f" (did you mean '{table}.{close[0]}'?)"
    all_keys = [f"{t.name}.{f.name}" for t in calc.tables for f in t.fields]
    hint = _suggest(f"{table}.{key}" if table else key, all_keys)
    if hint or table is not None:
        return hint
    bare = {k.split(".", 1)[1]: k for k in all_keys}
    close = difflib.get_close_matches(key, list(bare), n=1, cutoff=0.6) if len(key) <= MAX_SUGGEST_CHARS else []
    return f" (did you mean '{bare[close[0]]}'?)" if close else ""


def columns_of_rows(raw: dict, where: str, kind_hint: str | None = None) -> dict:
    """Read a ``[[table]]`` array of tables of a rows table (``Table.rows``) as its columns.

    ``[[duty]]`` rows ``{torque_Nm = 100, crank_speed_rpm = 1000, time_share = 0.3}`` become the table
    ``duty = {torque_Nm = [...], crank_speed_rpm = [...], time_share = [...]}`` that the column-wise form gives,
    so that both forms are one design (the same checks, ``--set duty.torque_Nm=[...]`` on either).  Every row
    must give every key of the table: a missing or unknown key is an error naming the row (1-based).
    Anything else (an unknown kind, a list that is not of tables) is left to :func:`validate`.  Returns
    ``raw`` itself when it has no such rows, else a shallow copy (the caller's mapping is not changed).
    """
    kind = raw.get("kind", kind_hint)
    if not isinstance(kind, str) or kind not in registry.kinds():
        return raw
    errors: list[str] = []
    for table in registry.get(kind).tables:
        rows = raw.get(table.name)
        if not table.rows or not isinstance(rows, list) or not rows or not all(isinstance(r, dict) for r in rows):
            continue
        names = [f.name for f in table.fields]
        for i, row in enumerate(rows, 1):
            errors += [f"{where}: {table.name}[{i}].{_clip(key)}: unknown key; a [[{table.name}]] row takes "
                       + ", ".join(names) for key in row if key not in names][:MAX_UNKNOWN_SHOWN]
            errors += [f"{where}: {table.name}[{i}].{name}: missing; every [[{table.name}]] row gives "
                       + ", ".join(names) for name in names if name not in row]
            if len(errors) > MAX_UNKNOWN_SHOWN:
                break
        raw = {**raw, table.name: {name: [row.get(name) for row in rows] for name in names}}
    if errors:
        raise InputError(errors)
    return raw


def validate(raw: dict, source: str, kind_hint: str | None = None) -> Design:
    """Validate a parsed design against its calculator; raise InputError listing every problem."""
    where = display_name(source)
    errors: list[str] = []
    raw = columns_of_rows(raw, where, kind_hint)
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
        name = _show(name)
    table_names = [t.name for t in calc.tables]
    values: dict[str, dict[str, Any]] = {}
    given: set[str] = set()
    unknown = 0
    for key, val in raw.items():
        if key in ("kind", "name"):
            continue
        if key not in table_names:
            unknown += 1
            if unknown <= MAX_UNKNOWN_SHOWN:
                errors.append(f"{where}: {_clip(key)}: unknown key{_unknown_key_hint(key, None, calc)}; "
                              f"a {kind} design has the tables " + ", ".join(f"[{t}]" for t in table_names))
            continue
        if not isinstance(val, dict):
            errors.append(f"{where}: {key}: must be a table [{key}]")
    if unknown > MAX_UNKNOWN_SHOWN:
        errors.append(f"{where}: … and {unknown - MAX_UNKNOWN_SHOWN} more unknown keys at the top level")
    for table in calc.tables:
        given_tab = raw.get(table.name)
        if not isinstance(given_tab, dict):
            if given_tab is not None:
                continue  # reported above
            if table.optional:
                continue
            given_tab = {}
        names = [f.name for f in table.fields]
        unknown = 0
        for key in given_tab:
            if key not in names:
                unknown += 1
                if unknown <= MAX_UNKNOWN_SHOWN:
                    errors.append(f"{where}: {table.name}.{_clip(key)}: unknown key"
                                  f"{_unknown_key_hint(key, table.name, calc)}; [{table.name}] takes "
                                  + ", ".join(names))
        if unknown > MAX_UNKNOWN_SHOWN:
            errors.append(f"{where}: … and {unknown - MAX_UNKNOWN_SHOWN} more unknown keys in [{table.name}]")
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
            raise InputError([f"{where}: {keyed(k, m)}" for k, m in problems.errors],
                             [f"{where}: warning: {w}" for w in problems.warnings])
        design.warnings.extend(problems.warnings)
    return design


def load(source: str, overrides: list[tuple[str, Any]] | None = None, kind_hint: str | None = None) -> Design:
    """Read, override and validate one design file (``-`` for stdin)."""
    raw = read_toml(source)
    if overrides:
        raw = columns_of_rows(raw, display_name(source), kind_hint)
        apply_set(raw, overrides)
    try:
        return validate(raw, source, kind_hint)
    except (RecursionError, MemoryError) as exc:
        raise InputError([f"{display_name(source)}: too large or too deeply nested to check "
                          f"({type(exc).__name__})"]) from None


def expand_paths(paths: list[str], warn=None) -> list[str]:
    """Files from PATHs: a folder stands for every ``*.toml`` below it (sorted); files that look like designs
    under another name (``A.TOML``, ``b.toml.txt``) are named in one note per folder (``warn``).

    From a folder only regular files (or symbolic links to them) are taken: a ``*.toml`` that is a
    FIFO, a device or a socket is skipped with a warning (``warn``, default: standard error), so that
    a folder never blocks or streams forever.  A folder (or sub-folder) that cannot be listed is an
    entry whose loading fails with its reason (a :class:`PathProblem`).  Paths named explicitly are
    kept as given.
    """
    if warn is None:
        def warn(message: str) -> None:
            print(message, file=sys.stderr)
    out: list[str] = []
    for p in paths:
        if p != "-" and os.path.isdir(p):
            found: list[str] = []

            def unreadable(exc: OSError, found=found, p=p) -> None:
                folder = exc.filename or p
                reason = "permission denied" if isinstance(exc, PermissionError) else (exc.strerror or str(exc))
                found.append(PathProblem(folder, f"{folder}: folder cannot be read ({reason})"))

            misnamed: list[str] = []
            for root, dirs, files in os.walk(p, onerror=unreadable):
                dirs.sort()
                for f in sorted(files):
                    if not f.endswith(".toml"):
                        if f.lower().endswith((".toml", ".toml.txt")):  # a design under a name a folder skips
                            misnamed.append(os.path.relpath(os.path.join(root, f), p))
                        continue
                    path = os.path.join(root, f)
                    try:
                        mode = os.stat(path).st_mode
                    except OSError:
                        found.append(FolderFile(path))  # a broken link: reading it names the problem
                        continue
                    if stat.S_ISREG(mode):
                        found.append(FolderFile(path))
                    else:
                        warn(f"{path}: skipped: {_file_kind(mode)}, not a regular file")
            if misnamed:
                shown = ", ".join(_clip(m) for m in misnamed[:MAX_SKIPPED_SHOWN])
                more = f", … and {len(misnamed) - MAX_SKIPPED_SHOWN} more" if len(misnamed) > MAX_SKIPPED_SHOWN else ""
                warn(f"{p}: skipped {len(misnamed)} file{'s' if len(misnamed) > 1 else ''} not named *.toml: "
                     f"{shown}{more} (a folder stands for its *.toml files; rename them, or name them explicitly)")
            out.extend(found)
        else:
            out.append(p)
    return out
