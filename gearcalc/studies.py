"""Sweeps that scale and resume: ``-o study.parquet`` and ``--resume`` (docs/spec/interface.md, "Studies").

* **Parquet** (:class:`ParquetOut`): one row group per chunk of the sweep, written as it comes (pyarrow, the
  ``parquet`` extra, imported only here); typed columns (float64, int64, bool, string; a list-valued output a
  Parquet list); the schema is fixed by the first chunk (every chunk has the grid's columns,
  :func:`gearcalc.grid.stream`); the file's key-value metadata says how it was made (:func:`metadata`).
* **Resume** (:class:`Resumable`): with ``--resume`` a sweep to a regular file writes ``.NAME.partial`` beside
  the target and, after each complete chunk, ``.NAME.partial.json``: what was computed (:func:`fingerprint`),
  the points a chunk and how many chunks (and bytes, or row groups) are complete.  An interrupted run keeps
  both; the next run with ``--resume`` checks the fingerprint (exit 2 saying what differs), keeps the complete
  chunks, computes the rest with the recorded chunk size and renames the partial file over the target.

This module imports only the standard library until pyarrow is needed.
"""
from __future__ import annotations

import hashlib
import json
import os

PARQUET_HINT = "--format parquet needs pyarrow: pip install 'gearcalc[parquet]'"
PARTIAL_VERSION = 1
"""The version of the ``.NAME.partial.json`` record (a partial output of another version is not resumed)."""


class StudyError(Exception):
    """A ``--resume`` or Parquet problem found before any computation (exit status 2)."""


def need_pyarrow() -> None:
    """Fail (StudyError, exit 2, with the pip command) when pyarrow is not installed."""
    try:
        import pyarrow  # noqa: F401
        import pyarrow.parquet  # noqa: F401
    except ImportError:
        raise StudyError(PARQUET_HINT) from None


def design_hash(raw: dict) -> str:
    """The sha256 of the resolved design (after ``--set``) as canonical JSON (keys sorted)."""
    text = json.dumps(raw, sort_keys=True, separators=(",", ":"), ensure_ascii=False, default=str)
    return hashlib.sha256(text.encode()).hexdigest()


def axes_json(axes, sample: dict | None = None) -> str:
    """The sweep's points as JSON: per varied key, a range ``{"start", "step", "count"}`` or its list of values;
    for ``--sample``, the sampler, N, the seed and the ``--vary`` ranges (the points follow from them)."""
    from .grid import Range

    if sample is not None:
        return json.dumps(sample, sort_keys=True)
    out = {}
    for key, values in axes.items():
        if isinstance(values, Range):
            out[key] = {"start": values.start, "step": values.step, "count": len(values), "ints": values.ints}
        else:
            out[key] = list(values)
    return json.dumps(out, default=str)


def fingerprint(raw: dict, axes, options, fmt: str, fields, where, sample: dict | None = None) -> dict:
    """What a sweep's output depends on (all strings): a partial output is resumed only when every one is the
    same."""
    from . import __version__

    return {
        "gearcalc_version": __version__,
        "format": fmt,
        "design_sha256": design_hash(raw),
        "axes": axes_json(axes, sample),
        "sampler": sample["sampler"] if sample else "",
        "seed": str(sample["seed"]) if sample else "",
        "points": str(_size(axes)),
        "model": options.model or "",
        "tol": repr(float(options.tol)),
        "fields": ",".join(fields) if fields else "",
        "where": json.dumps([str(w) for w in where or ()]),
    }


def _size(axes) -> int:
    from .grid import size_of

    return size_of(axes)


def metadata(finger: dict, chunk: int) -> dict:
    """A Parquet file's key-value metadata (``gearcalc.*`` keys): the fingerprint and the points a chunk."""
    meta = {f"gearcalc.{k}": v for k, v in finger.items() if k != "format"}
    meta["gearcalc.chunk_points"] = str(chunk)
    return meta


class _Counting:
    """The running totals a resumed sweep starts from (failed points per check, points, exit status)."""

    def __init__(self):
        from collections import Counter

        self.failed, self.total, self.code = Counter(), 0, 0


class Resumable:
    """``-o FILE --resume``: the sweep written to ``.NAME.partial`` beside the target (symlinks followed), its
    progress in ``.NAME.partial.json`` after each complete chunk; both kept when the run stops early, the partial
    file renamed over the target (keeping an old file's mode) and the record removed when it ends well.

    Used as the output of :func:`gearcalc.cli._sweep_stream` (``write``, ``chunk_done``) and as the ``plan`` of
    :func:`gearcalc.grid.stream` (the chunk size, the chunks to skip)."""

    def __init__(self, path: str, finger: dict, say=None):
        from .output import _target

        self.path, self.finger, self.say = path, finger, say
        self.target = _target(path)
        folder, name = os.path.split(self.target)
        self.data = os.path.join(folder, f".{name}.partial")
        self.record = self.data + ".json"
        self.fd = None
        self.size = 0  # points a chunk
        self.chunks = 0  # complete chunks in the partial file
        self.bytes = 0  # its length after them (CSV)
        self.groups = 0  # its row groups (Parquet)
        self.kept = None  # the record of the interrupted run, when it is resumed
        self.resumed = False
        self.start = _Counting()
        self.parquet = finger["format"] == "parquet"
        self.writer = None  # a ParquetOut writing into this file
        self.prev = None  # Parquet: the interrupted run's file, copied into the new one

    # -- opening -------------------------------------------------------------------------------------------------
    def __enter__(self) -> "Resumable":
        from .output import OutputError

        try:
            self.fd = os.open(self.data, os.O_RDWR | os.O_CREAT | getattr(os, "O_CLOEXEC", 0), 0o666)
        except OSError as exc:
            raise OutputError(self.data, exc) from None
        try:
            import fcntl

            fcntl.flock(self.fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except ImportError:  # pragma: no cover - not on POSIX
            pass
        except OSError:
            os.close(self.fd)
            self.fd = None
            raise StudyError(f"--resume: {self.data} is being written by another gearcalc") from None
        prev = self.data + ".prev"
        if self.parquet and os.path.exists(prev):  # a resumed run killed hard: its file has no footer, this one has
            os.replace(prev, self.data)
            os.close(self.fd)
            self.fd = os.open(self.data, os.O_RDWR | getattr(os, "O_CLOEXEC", 0))
            self._lock()
        self.kept = self._read_record()
        if self.kept is not None:
            self._check(self.kept)
        return self

    def _read_record(self):
        try:
            with open(self.record, encoding="utf-8") as f:
                kept = json.load(f)
        except FileNotFoundError:
            return None
        except (OSError, ValueError):
            self._note("its progress record is unreadable")
            return None
        if not isinstance(kept, dict) or kept.get("version") != PARTIAL_VERSION:
            self._note("its progress record is of another kind")
            return None
        return kept

    def _note(self, why: str) -> None:
        if self.say:
            self.say(f"gearcalc: --resume: {self.data}: {why}; starting from the first point")

    def _check(self, kept: dict) -> None:
        was = kept.get("fingerprint", {})
        differ = [k for k in self.finger if was.get(k) != self.finger[k]]
        if differ:
            what = ", ".join(f"{k} ({_short(was.get(k))} then, {_short(self.finger[k])} now)" for k in differ)
            raise StudyError(f"--resume: the partial output {self.data} was computed with other settings: {what}; "
                             "run the same command again, or delete it to start over")

    # -- the plan of grid.stream ----------------------------------------------------------------------------------
    def plan(self, size: int, total: int) -> tuple[int, int]:
        """(points a chunk, chunks to skip): the interrupted run's chunk size and complete chunks when resumed."""
        kept = self.kept
        if kept is not None and int(kept.get("chunk_points", 0)) >= 1 and self._usable(kept):
            self.size = int(kept["chunk_points"])
            self.chunks = int(kept["chunks"])
            self.bytes = int(kept.get("bytes", 0))
            self.groups = int(kept.get("row_groups", 0))
            from collections import Counter

            failed = kept.get("failed", {})
            self.start.failed = Counter({str(k): int(v) for k, v in failed.items()}) if isinstance(failed, dict) \
                else Counter()
            for k in ("total", "code"):
                setattr(self.start, k, int(kept.get(k, 0)))
            self.resumed = self.chunks > 0
        else:
            self.size = size
            self._restart()
        if not self.parquet:
            os.ftruncate(self.fd, self.bytes)
            os.lseek(self.fd, self.bytes, os.SEEK_SET)
        self._save()
        return self.size, self.chunks

    def _usable(self, kept: dict) -> bool:
        """Whether the partial file holds what the record says (a hard kill may have left less)."""
        if self.parquet:
            try:
                import pyarrow.parquet as pq

                groups = pq.ParquetFile(self.data).num_row_groups
            except Exception:  # noqa: BLE001 - no footer: the run was killed before it could close the file
                self._note("the file was not closed (the run was killed)")
                return False
            if groups < int(kept.get("row_groups", 0)):
                self._note("it holds fewer row groups than recorded")
                return False
            if int(kept.get("row_groups", 0)):  # copied into the new file (Parquet files are not appended to)
                self.prev = self.data + ".prev"
                os.replace(self.data, self.prev)
                fd = os.open(self.data, os.O_RDWR | os.O_CREAT | getattr(os, "O_CLOEXEC", 0), 0o666)
                os.close(self.fd)
                self.fd = fd
                self._lock()
            return True
        if os.fstat(self.fd).st_size < int(kept.get("bytes", 0)):
            self._note("it is shorter than recorded")
            return False
        return True

    def _lock(self) -> None:
        try:
            import fcntl

            fcntl.flock(self.fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except (ImportError, OSError):  # pragma: no cover - we made the file
            pass

    def _restart(self) -> None:
        self.chunks = self.bytes = self.groups = 0
        self.start = _Counting()
        self.resumed = False
        if self.parquet:
            os.ftruncate(self.fd, 0)

    def _save(self, counts=None) -> None:
        record = {"version": PARTIAL_VERSION, "fingerprint": self.finger, "chunk_points": self.size,
                  "chunks": self.chunks, "bytes": self.bytes, "row_groups": self.groups}
        if counts is not None:
            failed, total, code = counts
            record.update(failed=dict(failed), total=total, code=code)
        else:
            record.update(failed=dict(self.start.failed), total=self.start.total, code=self.start.code)
        tmp = self.record + ".tmp"
        with open(tmp, "w", encoding="utf-8") as f:
            json.dump(record, f)
        os.replace(tmp, self.record)

    # -- writing --------------------------------------------------------------------------------------------------
    def write(self, data) -> None:
        from .output import OutputError

        if isinstance(data, str):
            data = data.encode("utf-8")
        try:
            view = memoryview(data)
            while view:
                view = view[os.write(self.fd, view):]
        except OSError as exc:
            raise OutputError(self.path, exc) from None
        self._written += len(data)

    _written = 0

    def tell(self) -> int:
        return self.bytes + self._written

    def chunk_done(self, failed, total: int, code: int) -> None:
        """A chunk is complete (its bytes written, or its row group): record it, with the running totals."""
        self.chunks += 1
        if self.parquet:
            self.groups = self.writer.groups if self.writer is not None else self.groups
        else:
            self.bytes += self._written
            self._written = 0
        self._save((failed, total, code))
        if self.chunks == _stop_after():  # a test's interruption after k chunks (tests/test_studies.py)
            raise KeyboardInterrupt


    def __exit__(self, kind, value, tb) -> bool:
        from .output import OutputError, _keep_owner

        if kind is not None:  # keep what is complete for the next --resume
            self._close(truncate=not self.parquet and self._written)  # a chunk half written is not kept
            if self.prev is not None:  # stopped while copying: the interrupted run's file is still the one
                copied = self.writer.groups if self.writer is not None else 0
                if copied < int(self.kept.get("row_groups", 0)):
                    os.replace(self.prev, self.data)
                else:
                    os.unlink(self.prev)
                self.prev = None
            if self.chunks == 0 and (self.kept is None or self.size):  # nothing complete: nothing to resume
                for leftover in (self.data, self.record):
                    try:
                        os.unlink(leftover)
                    except FileNotFoundError:
                        pass
            return False
        try:
            os.fsync(self.fd)
            try:
                old = os.stat(self.target)
            except FileNotFoundError:
                old = None
            if old is not None:
                import stat

                os.fchmod(self.fd, stat.S_IMODE(old.st_mode))
                _keep_owner(self.fd, old)
            self._close()
            os.replace(self.data, self.target)
        except OSError as exc:
            self._close()
            raise OutputError(self.path, exc) from None
        for leftover in (self.record, self.prev):
            if leftover:
                try:
                    os.unlink(leftover)
                except FileNotFoundError:
                    pass
        return False

    def _close(self, truncate: bool = False) -> None:
        if self.fd is not None:
            try:
                if truncate:
                    os.ftruncate(self.fd, self.bytes)
            except OSError:
                pass
            os.close(self.fd)
            self.fd = None


def _stop_after() -> int | None:
    value = os.environ.get("_GEARCALC_STOP_AFTER_CHUNKS")
    return int(value) if value and value.isdigit() else None


def _short(value) -> str:
    text = str(value)
    return text if len(text) <= 40 else text[:37] + "..."


class _FileOf:
    """A writable file object over an output (:class:`gearcalc.output.Sink`, :class:`Resumable`) for pyarrow.
    pyarrow writes a row group in pieces of a few kB: they are gathered and written to the output by
    :meth:`flush` (:class:`ParquetOut` flushes after each row group and at the end)."""

    closed = False

    def __init__(self, out):
        self.out, self.pos = out, 0
        self.pending = bytearray()

    def write(self, data) -> int:
        size = len(memoryview(data).cast("B"))
        self.pending += data
        self.pos += size
        if len(self.pending) >= 1 << 22:
            self.flush()
        return size

    def tell(self) -> int:
        return self.pos

    def flush(self) -> None:
        if self.pending:
            data, self.pending = self.pending, bytearray()  # written as it is (a memoryview), not copied
            self.out.write(data)

    def close(self) -> None:
        self.flush()
        self.closed = True

    def writable(self) -> bool:
        return True

    def seekable(self) -> bool:
        return False


class ParquetOut:
    """A sweep's chunks as Parquet: one row group per chunk (:meth:`write`), the schema from the first chunk with
    the file's key-value metadata, the footer on :meth:`close` (also when the run stops early, so that a partial
    file of ``--resume`` is a Parquet file of its complete chunks)."""

    def __init__(self, out, meta: dict, prev: str | None = None, groups: int = 0):
        self.out, self.meta = out, meta
        self.file = _FileOf(out)
        self.writer = self.schema = None
        self.groups = 0
        self.copy = (prev, groups) if prev and groups else None
        if self.copy:  # a resumed run: the interrupted run's row groups first
            import pyarrow.parquet as pq

            old = pq.ParquetFile(prev)
            self._open(old.schema_arrow)
            for k in range(groups):
                self.writer.write_table(old.read_row_group(k))
                self.file.flush()
                self.groups += 1

    def _open(self, schema) -> None:
        import pyarrow.parquet as pq

        self.schema = schema.with_metadata({**(schema.metadata or {}), **{k.encode(): v.encode()
                                                                          for k, v in self.meta.items()}})
        self.writer = pq.ParquetWriter(self.file, self.schema, compression="zstd",
                                       use_dictionary=_dictionary_columns(self.schema),
                                       use_byte_stream_split=_split_columns(self.schema))

    def write(self, part) -> None:
        """One chunk (:class:`gearcalc.render.Columns`) as one row group (none for a chunk with no rows)."""
        import pyarrow as pa

        if self.writer is None:  # error and failed_checks are words whatever the first chunk holds (None, []):
            # typed from it, a later chunk's first error or failed check would not fit and stop the sweep
            words = {"error": pa.string(), "failed_checks": pa.list_(pa.string())}
            self._open(pa.schema([(k, words.get(k) or _type_of(v)) for k, v in part.data.items()]))
        if not part.n:
            return
        arrays = []
        for field in self.schema:
            values = part.data.get(field.name)
            arrays.append(_array(field, values, part.n))
        self.writer.write_table(pa.Table.from_arrays(arrays, schema=self.schema))
        self.file.flush()  # the row group in the output before the chunk is counted done (--resume)
        self.groups += 1

    def close(self) -> None:
        if self.writer is not None:
            self.writer.close()
            self.writer = None
        self.file.flush()  # the footer


def _dictionary_columns(schema) -> list:
    """The columns written dictionary-encoded: words, integers, flags and lists of words (few distinct values a
    chunk), not float64 ones (nearly every value distinct in a sweep: the dictionary is built, then given up,
    for every page; plain floats compress smaller and are written about three times faster).  A list column is
    named by its leaf (``name.list.element``)."""
    return [leaf for leaf, floating in _leaves(schema) if not floating]


def _split_columns(schema) -> list:
    """The columns written BYTE_STREAM_SPLIT: the float64 ones (the others are :func:`_dictionary_columns`).  Their
    values' bytes grouped by position (the sign and exponent bytes of a sweep's smooth values nearly constant)
    compress to about 60 % with zstd, and the write is about a quarter faster; the values read back are the
    same (an encoding, not a rounding)."""
    return [leaf for leaf, floating in _leaves(schema) if floating]


def _leaves(schema) -> list:
    """(the leaf's name, a float?) of every column: a list column named by its leaf (``name.list.element``)."""
    import pyarrow as pa

    out = []
    for field in schema:
        kind = field.type
        leaf = field.name
        if pa.types.is_list(kind):
            kind, leaf = kind.value_type, f"{field.name}.list.element"
        out.append((leaf, pa.types.is_floating(kind)))
    return out


def _type_of(values):
    """The Arrow type of a column: from a numpy array's dtype, else from its first value that is not None (bool,
    int64, float64, string); a list-valued output (e.g. rows' ``unloaded_rows``) a list of float64 (its values
    may be counts or numbers; an empty list says nothing), of strings when its first value is a word; a column
    with no value in the first chunk is float64."""
    import pyarrow as pa

    dtype = getattr(values, "dtype", None)
    if dtype is not None:
        return {"b": pa.bool_(), "i": pa.int64(), "u": pa.int64(), "f": pa.float64()}.get(dtype.kind, pa.string())
    first = next((v for v in values if v is not None), None)
    if first is None:
        return pa.float64()
    if isinstance(first, (list, tuple)):
        inner = next((x for v in values if v for x in v if x is not None), 0.0)
        return pa.list_(pa.string() if isinstance(inner, str) else pa.float64())
    return _scalar_type(first)


def _scalar_type(value):
    import pyarrow as pa

    if isinstance(value, bool):
        return pa.bool_()
    if isinstance(value, int):
        return pa.int64()
    if isinstance(value, float):
        return pa.float64()
    return pa.string()


def _array(field, values, n: int):
    """One column of a chunk as an Arrow array of the field's type.  The usual columns (a numpy column; a list of
    numbers, flags or words, None where a point has no value; a list of lists none of which holds anything) are
    built from their buffers (:func:`_from_numpy`): no Python object a value, and no ``pyarrow.array``, whose first
    call imports pandas when it is installed (0.3 s); any other column by ``pyarrow.array``."""
    import pyarrow as pa

    from .grid import SweepError

    if values is None:
        return pa.nulls(n, field.type)
    try:
        made = _from_buffers(field.type, values, n)
        if made is not None:
            return made
        if field.type == pa.string() and not hasattr(values, "dtype"):
            values = [v if v is None or isinstance(v, str) else json.dumps(v) for v in values]
        elif hasattr(values, "dtype") and values.dtype.kind == "u":
            values = values.astype("int64")
        return pa.array(values, type=field.type)
    except (pa.ArrowInvalid, pa.ArrowTypeError, TypeError, ValueError, OverflowError):
        raise SweepError(f"the output {field.name} changes type within the sweep ({field.type} in the first chunk); "
                         "write CSV or JSON, or split the sweep") from None


_NONE = type(None)
_SCALARS = {"double": ({float, _NONE}, "float64", "f"), "int64": ({int, _NONE}, "int64", "iu"),
            "bool": ({bool, _NONE}, "bool", "b")}
"""Arrow type -> (the Python types of a list column that :func:`_from_buffers` converts, the numpy dtype, the
kinds of a numpy column it takes); other values (an int or a word in a float column, a numpy scalar, a float
array in an int column) go to ``pyarrow.array``, which converts or refuses them as it did."""


def _from_buffers(kind, values, n: int):
    """The Arrow array of ``values`` built from numpy buffers, or None when they are not of a usual shape."""
    import numpy as np
    import pyarrow as pa

    scalar = _SCALARS.get(str(kind))
    dtype = getattr(values, "dtype", None)
    if dtype is not None:
        if scalar is None or dtype.kind not in scalar[2] or np.ndim(values) != 1:
            return None
        return _from_numpy(kind, np.asarray(values, dtype=scalar[1]), None, n)
    first = values[0] if n else None
    same = n and values.count(first) == n  # one value at every point (list.count compares identical objects first)
    if first is None and (same or values.count(None) == n):
        return pa.nulls(n, kind)
    if kind == pa.string() and type(first) is str and same:
        return _strings(values, n, False, True)  # one word
    if pa.types.is_list(kind) and type(first) is list and same:  # one list (e.g. no unloaded row anywhere)
        inner = _from_buffers(kind.value_type, first * n, len(first) * n) if first else pa.nulls(0, kind.value_type)
        if inner is None or len(first) * n >= 2 ** 31:
            return None
        offsets = np.arange(n + 1, dtype=np.int32) * len(first)
        return pa.ListArray.from_arrays(_from_numpy(pa.int32(), offsets, None, n + 1), inner, type=kind)
    types = set(map(type, values))
    if scalar is not None:
        allowed, want, _ = scalar
        if not types <= allowed:
            return None
        if _NONE not in types:
            return _from_numpy(kind, np.array(values, dtype=want), None, n)
        held = np.array(values, dtype=object)
        valid = held != None  # noqa: E711 - element by element
        data = np.zeros(n, dtype=want)
        data[valid] = held[valid].astype(want)
        return _from_numpy(kind, data, valid, n)
    if kind == pa.string() and types <= {str, _NONE}:
        return _strings(values, n, _NONE in types)
    if pa.types.is_list(kind) and types == {list}:  # e.g. failed_checks: the values of every list, their offsets
        import itertools

        offsets = np.zeros(n + 1, dtype=np.int64)
        np.cumsum(np.fromiter(map(len, values), dtype=np.int64, count=n), out=offsets[1:])
        flat = list(itertools.chain.from_iterable(values)) if offsets[-1] else []
        inner = _from_buffers(kind.value_type, flat, len(flat)) if flat else pa.nulls(0, kind.value_type)
        if inner is None or offsets[-1] >= 2 ** 31:
            return None
        return pa.ListArray.from_arrays(_from_numpy(pa.int32(), offsets.astype(np.int32), None, n + 1), inner,
                                        type=kind)
    return None


def _from_numpy(kind, data, valid, n: int):
    """An Arrow array of ``n`` values over a numpy column (float64, int64, int32: its buffer, not copied; bool:
    its bits packed); ``valid``: None, or where the values are (the others null)."""
    import numpy as np
    import pyarrow as pa

    data = np.ascontiguousarray(data)
    if data.dtype == np.bool_:
        data = np.packbits(data, bitorder="little")
    bitmap, nulls = None, 0
    if valid is not None:
        nulls = int(n - np.count_nonzero(valid))
        bitmap = pa.py_buffer(np.packbits(valid, bitorder="little")) if nulls else None
    return pa.Array.from_buffers(kind, n, [bitmap, pa.py_buffer(data)], null_count=nulls)


def _strings(values, n: int, missing: bool, same: bool | None = None):
    """A string column from a list of words (None: null) by its offsets and UTF-8 bytes; ``same``: whether every
    value is the first (None: not known yet)."""
    import numpy as np
    import pyarrow as pa

    if same is None:
        same = not missing and n and values.count(values[0]) == n
    if same:  # one word (a design's name): its bytes repeated
        word = values[0].encode()
        offsets = np.arange(n + 1, dtype=np.int64) * len(word)
        if offsets[-1] >= 2 ** 31:
            return None
        return pa.Array.from_buffers(pa.string(), n, [None, pa.py_buffer(offsets.astype(np.int32)),
                                                      pa.py_buffer(word * n)])
    if missing:
        valid = np.array(values, dtype=object) != None  # noqa: E711 - element by element
        values = ["" if v is None else v for v in values]
    encoded = list(map(str.encode, values))
    offsets = np.zeros(n + 1, dtype=np.int64)
    np.cumsum(np.fromiter(map(len, encoded), dtype=np.int64, count=n), out=offsets[1:])
    if offsets[-1] >= 2 ** 31:
        return None
    bitmap, nulls = None, 0
    if missing:
        nulls = int(n - np.count_nonzero(valid))
        bitmap = pa.py_buffer(np.packbits(valid, bitorder="little"))
    return pa.Array.from_buffers(pa.string(), n, [bitmap, pa.py_buffer(offsets.astype(np.int32)),
                                                  pa.py_buffer(b"".join(encoded))], null_count=nulls)


class GridSweep:
    """A whole sweep (:func:`gearcalc.sweep_grid`): :class:`gearcalc.render.Columns`' ``data`` (lists), ``n``,
    ``errors``, ``rows()`` and ``to_pandas()``, with the ``axes`` it was computed over, so that
    :meth:`to_xarray` can give the grid its shape."""

    def __init__(self, data: dict, errors: list, axes):
        from .grid import Sample

        self.data, self.errors = data, list(errors)
        self.n = len(next(iter(data.values()))) if data else 0
        self.sample = isinstance(axes, Sample)
        self.axes = {k: list(v) for k, v in axes.items()}

    @property
    def shape(self) -> tuple:
        """One length per varied key (a ``--sample``'s points: one dimension, ``point``)."""
        return (self.n,) if self.sample else tuple(len(v) for v in self.axes.values())

    def rows(self) -> list[dict]:
        names = list(self.data)
        return [dict(zip(names, vals)) for vals in zip(*self.data.values())]

    def to_pandas(self):
        """A pandas DataFrame, one row a point (pandas is not a dependency of gearcalc: install it to use this)."""
        import pandas as pd

        return pd.DataFrame(self.data)

    def to_xarray(self):
        """An ``xarray.Dataset``: one dimension per varied key (its values the coordinates, in the order of the
        axes; the first varies slowest, as in the rows), one variable per output.  A sampled sweep
        (``explore.api.sample``) has one dimension ``point`` and the varied keys as coordinates along it.  An
        output a point lacks (a failed point's) is NaN in a numeric variable, None in another.  xarray is not a
        dependency of gearcalc: install it to use this."""
        import numpy as np
        import xarray as xr

        if self.sample:
            dims = ("point",)
            coords = {k: ("point", np.asarray(self.data.get(k, v))) for k, v in self.axes.items()}
        else:
            dims = tuple(self.axes)
            coords = {k: np.asarray(v) for k, v in self.axes.items()}
        variables = {k: (dims, _values(v).reshape(self.shape)) for k, v in self.data.items() if k not in self.axes}
        return xr.Dataset(variables, coords=coords)


def _values(column: list):
    """A column as a numpy array: bool, int64 or float64 (None as NaN) when its values are all of one such type,
    else an array of objects (words, lists; None kept)."""
    import numpy as np

    kinds = {type(v) for v in column if v is not None}
    missing = any(v is None for v in column)
    if kinds == {bool} and not missing:
        return np.asarray(column, dtype=bool)
    if kinds and kinds <= {int} and not missing:
        return np.asarray(column, dtype=np.int64)
    if kinds and kinds <= {int, float}:
        return np.asarray([np.nan if v is None else v for v in column], dtype=float)
    out = np.empty(len(column), dtype=object)
    out[:] = column
    return out
