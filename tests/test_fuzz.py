"""Fuzzing of the loader (issue 13): mutated designs must end with exit 0, 1 or 2, in bounded time, with
every message naming its file, never a traceback, an internal error or a lost good file.

The loader fuzz drives ``gearcalc check`` in process over several thousand byte-level and structured
mutations of the shipped configs, ten files per call (so that a bad file is also seen not to cost its
neighbours).  A few dozen structured cases go through full computes (``gearcalc run``).  Everything is
generated from fixed seeds: a failure is reproducible from its chunk and case number.
"""
import copy
import random
import time
import tomllib
from collections import Counter

import pytest
import tomli_w

from conftest import CONFIGS, cli


pytestmark = pytest.mark.slow  # one of the few long files (`pytest -m "not slow"`: the quick loop)

SEEDS = sorted(CONFIGS.glob("*.toml"))
TEXTS = [p.read_text() for p in SEEDS]
EXTREMES = [0, -1, -1e300, 1e300, 1e-300, 5e-324, 2**63 - 1, -(2**63), 1e15, 0.5, 3, 7.0, 1000, 1001]
WEIRD = ["", "auto", "x" * 200, [], [1, 2, 3], {"a": 1}, True, False, "nan", "1e999", [[1]], "é", "\u0000",
         "10 kN", "05", "2.5e3", "0.25 in", "30°", "1" * 5000]
UNICODE = ["é", "\u200b", "\u202e", "\u2028", "\x85", "\ufeff", "😀", "\u0301", "Ω", "ｋｉｎｄ", "\t", "\x00",
           "\x1b[31m", "\U0010ffff", "ß"]
CHUNKS = 10
CASES_PER_CHUNK = 400  # 4000 loader cases in all
BATCH = 10


# ---------------------------------------------------------------- structured mutations (parsed, then dumped)
def leaves(d, prefix=()):
    for k, v in d.items():
        if isinstance(v, dict):
            yield from leaves(v, prefix + (k,))
        else:
            yield prefix + (k,), v


def set_path(d, path, value):
    for k in path[:-1]:
        nxt = d.get(k)
        if not isinstance(nxt, dict):
            nxt = d[k] = {}
        d = nxt
    d[path[-1]] = value


def del_path(d, path):
    for k in path[:-1]:
        d = d[k]
    del d[path[-1]]


def mutate(design, rng):
    """One structured mutation; returns (category, design)."""
    d = copy.deepcopy(design)
    paths = [p for p, _ in leaves(d) if p[0] not in ("kind",)]
    cat = rng.choice(["wrong_type", "missing_key", "unknown_key", "extreme_number", "nan_inf", "huge_array",
                      "deep_nesting", "multi", "moved_key"])
    if cat == "wrong_type" and paths:
        set_path(d, rng.choice(paths), rng.choice(WEIRD))
    elif cat == "missing_key" and paths:
        del_path(d, rng.choice(paths))
    elif cat == "unknown_key":
        p = rng.choice(paths) if paths else ("x",)
        set_path(d, p[:-1] + (p[-1] + rng.choice(["_x", "s", "mm"]),), 1.0)
    elif cat == "extreme_number" and paths:
        set_path(d, rng.choice(paths), rng.choice(EXTREMES))
    elif cat == "nan_inf" and paths:
        set_path(d, rng.choice(paths), rng.choice([float("nan"), float("inf"), float("-inf")]))
    elif cat == "huge_array" and paths:
        set_path(d, rng.choice(paths), [rng.random() for _ in range(rng.choice([2, 1000, 5000]))])
    elif cat == "deep_nesting":
        node = {"leaf": 1}
        for _ in range(rng.choice([5, 50, 200])):
            node = {"t": node}
        d[rng.choice(["deep", *[p[0] for p in paths]] or ["deep"])] = node
    elif cat == "moved_key" and len(paths) > 1:  # a key in the wrong table
        p, q = rng.sample(paths, 2)
        if len(p) == 2 and len(q) == 2 and p[0] != q[0]:
            val = d[p[0]].pop(p[1])
            d[q[0]][p[1]] = val
    else:
        cat = "multi"
        for _ in range(3):
            if paths:
                set_path(d, rng.choice(paths), rng.choice(EXTREMES + WEIRD))
    return cat, d


def dump(design):
    try:
        return tomli_w.dumps(design).encode()
    except (TypeError, ValueError, RecursionError):
        return None


# ---------------------------------------------------------------- byte-level mutations of the shipped texts
def nest(rng, depth):
    if rng.random() < 0.5:
        return "[" * depth + "1" + "]" * depth
    return "{a = " * depth + "1" + "}" * depth


def byte_case(rng, text):
    """One byte-level mutation; returns (category, bytes)."""
    b = text.encode()
    lines = text.splitlines(keepends=True)
    cat = rng.choice(["truncated", "byte_flip", "dup_lines", "bom", "crlf", "huge_int", "huge_float", "big_int",
                      "deep_array", "long_string", "long_key", "many_keys", "wrong_table", "unicode",
                      "dotted_key", "quoted_number", "junk_line", "shuffled", "non_utf8", "empty", "binary",
                      "dup_table", "control"])
    i = rng.randrange(len(lines))
    key_lines = [k for k, ln in enumerate(lines) if "=" in ln and not ln.lstrip().startswith("#")]
    kl = rng.choice(key_lines) if key_lines else i

    def put_value(value):
        ln = lines[kl]
        k = ln.split("=", 1)[0]
        out = lines[:kl] + [f"{k}= {value}\n"] + lines[kl + 1:]
        return "".join(out).encode()

    if cat == "truncated":
        data = b[: rng.randrange(len(b))]
    elif cat == "byte_flip":
        data = bytearray(b)
        for _ in range(rng.randrange(1, 6)):
            data[rng.randrange(len(data))] = rng.randrange(256)
        data = bytes(data)
    elif cat == "dup_lines":
        out = list(lines)
        for _ in range(rng.randrange(1, 4)):
            k = rng.randrange(len(out))
            out.insert(k, out[k])
        data = "".join(out).encode()
    elif cat == "bom":
        data = b"\xef\xbb\xbf" + b if rng.random() < 0.8 else b"\xef\xbb\xbf\xef\xbb\xbf" + b
    elif cat == "crlf":
        data = text.replace("\n", rng.choice(["\r\n", "\r"])).encode()
    elif cat == "huge_int":
        data = put_value(rng.choice(["", "-", "+"]) + "9" * rng.choice([4301, 5000, 20_000]))
    elif cat == "huge_float":
        data = put_value(rng.choice(["1" * 400 + ".5", "1e99999", "-1e400", "0." + "0" * 5000 + "1",
                                     "1" * 5000 + ".0", "6.02e23", "1e-400"]))
    elif cat == "big_int":
        data = put_value(str(rng.choice([2**53 + 1, 2**63, 2**64, -(2**63) - 1, 10**20, 10**300, -10**4299])))
    elif cat == "deep_array":
        data = put_value(nest(rng, rng.choice([3, 10, 33, 40, 300, 3000])))
    elif cat == "long_string":
        s = rng.choice(["x", "9", "1 mm ", "\\u00e9", "é"]) * rng.choice([61, 1000, 32_000, 60_000])
        data = put_value(f'"{s}"')
    elif cat == "long_key":
        key = rng.choice(["k", "radial_N", "é"]) * rng.choice([61, 5000, 100_000])
        data = (text + ("\n" if rng.random() < 0.5 else "\n[load]\n") + f"{key} = 1\n").encode()
    elif cat == "many_keys":
        n = rng.choice([21, 500, 3000, 12_000])
        head = "" if rng.random() < 0.5 else "[" + rng.choice(["load", "gear", "gearing", "rows", "x"]) + "]\n"
        data = (text + "\n" + head + "".join(f"key_{j} = {j}\n" for j in range(n))).encode()
    elif cat == "wrong_table":  # a key line moved under another table header
        headers = [k for k, ln in enumerate(lines) if ln.startswith("[")]
        if key_lines and headers:
            out = list(lines)
            moved = out.pop(kl)
            h = rng.choice([k for k, ln in enumerate(out) if ln.startswith("[")])
            out.insert(h + 1, moved)
            data = "".join(out).encode()
        else:
            data = b
    elif cat == "unicode":
        chars = list(text)
        for _ in range(rng.randrange(1, 5)):
            chars.insert(rng.randrange(len(chars) + 1), rng.choice(UNICODE))
        data = "".join(chars).encode("utf-8", "surrogatepass")
    elif cat == "dotted_key":
        n = rng.choice([2, 5, 31, 32, 33, 200, 20_000])
        key = ".".join(rng.choice(["a", '"q"', "load", "x y".replace(" ", "_")]) for _ in range(n))
        data = (text + "\n" + rng.choice([f"{key} = 1\n", f"[{key}]\nz = 1\n", f"w = {{{key} = 1}}\n"])).encode()
    elif cat == "quoted_number":
        data = put_value('"' + rng.choice(["10000", "2.5e3", "05", "10 kN", "0.25 in", "5 mm", "1 m", "30°",
                                           "0.5 rad", "200 GPa", "2 kN·m", "3000 rpm", "5 furlongs", "-0",
                                           ".5", "1e999", "+7", "1_000"]) + '"')
    elif cat == "junk_line":
        junk = rng.choice(["[[[", "a = ", "kind = ", "= 1", "[gear]\n[gear]", 'kind = "rows"', "a.b = 1\na = 2",
                           "x = [1, 'a']", '"""', "'''", 'x = "\\q"', "[[load]]", "x = 1979-05-27T07:32:00Z",
                           "x = {a = 1, a = 2}", "x = 0x7fffffffffffffffffff", "x = inf", "x = -nan",
                           "[a.\"b\".'c']", "kind = 1"])
        out = list(lines)
        out.insert(rng.randrange(len(out) + 1), junk + "\n")
        data = "".join(out).encode()
    elif cat == "shuffled":
        out = list(lines)
        rng.shuffle(out)
        data = "".join(out).encode()
    elif cat == "non_utf8":
        data = b[: rng.randrange(len(b))] + rng.choice([b"\xff", b"\xc3", b"\xed\xa0\x80", b"\xfe\xff"]) + b
    elif cat == "empty":
        data = rng.choice([b"", b"   \n\n", b"# only a comment\n", b"\xef\xbb\xbf", b"\n" * 1000])
    elif cat == "binary":
        data = bytes(rng.randrange(256) for _ in range(rng.randrange(1, 400)))
    elif cat == "dup_table":
        headers = [ln for ln in lines if ln.startswith("[")]
        data = (text + "\n" + (rng.choice(headers) if headers else "[x]\n") + "k = 1\n").encode()
    else:  # control characters in a value or a comment
        data = put_value('"' + rng.choice(["\x07", "\x1b", "\x7f", "\\u0000", "\\n", "a\\tb"]) + '"')
    return cat, data


def generate(chunk, n=CASES_PER_CHUNK):
    rng = random.Random(20261125 * 100 + chunk)
    designs = [tomllib.loads(t) for t in TEXTS]
    cases = []
    while len(cases) < n:
        if rng.random() < 0.7:
            cases.append(byte_case(rng, rng.choice(TEXTS)))
        else:
            cat, d = mutate(rng.choice(designs), rng)
            data = dump(d)
            if data is not None:
                cases.append(("s_" + cat, data))
    return cases


def check_batch(paths, r, elapsed):
    """Problems with one `gearcalc check` over a batch of files (an empty list when it is all right)."""
    problems = []
    if r.code not in (0, 1, 2):
        problems.append(f"exit {r.code}")
    for word in ("Traceback", "internal error"):
        if word in r.err or word in r.out:
            problems.append(word)
    names = [str(p) for p in paths]
    for line in r.err.splitlines():
        if not any(line.startswith(n + ":") for n in names):
            problems.append(f"stderr line names no file: {line[:200]!r}")
    for n in names:
        ok = f"ok  {n}  (" in r.out
        if ok == (f"{n}:" in r.err and f"{n}: warning" not in r.err):
            problems.append(f"{n}: neither ok nor reported (or both)")
    if r.code == 0 and any(f"ok  {n}  (" not in r.out for n in names):
        problems.append("exit 0 with a failed file")
    if elapsed > 10:
        problems.append(f"took {elapsed:.1f} s")
    return problems


@pytest.mark.parametrize("chunk", range(CHUNKS))
def test_loader_fuzz(tmp_path, chunk):
    """Every mutation ends in ok or messages naming its file; no file costs its neighbours."""
    cases = generate(chunk)
    failures = []
    for start in range(0, len(cases), BATCH):
        paths = []
        for i in range(start, min(start + BATCH, len(cases))):
            p = tmp_path / f"c{chunk}_{i}.toml"
            p.write_bytes(cases[i][1])
            paths.append(p)
        t0 = time.monotonic()
        r = cli("check", *paths)
        problems = check_batch(paths, r, time.monotonic() - t0)
        if problems:
            failures.append((chunk, start, [cases[i][0] for i in range(start, start + len(paths))], problems[:3]))
        for p in paths:
            p.unlink()
    assert not failures, failures[:3]


def test_loader_fuzz_covers_every_category():
    assert CHUNKS * CASES_PER_CHUNK >= 4000
    counts = Counter(cat for chunk in range(2) for cat, _ in generate(chunk))  # two chunks of ten suffice
    assert len(counts) >= 30, counts
    assert min(counts.values()) >= 5, counts


# ---------------------------------------------------------------- a few full computes
def compute_cases(n=40, seed=20261121):
    rng = random.Random(seed)
    # the contact-level pins designs take seconds each: the cheaper levels and the other kinds only
    designs = [tomllib.loads(t) for p, t in zip(SEEDS, TEXTS) if not p.name.startswith("pins_paper_circ")]
    cases = []
    while len(cases) < n:
        cat, d = mutate(rng.choice(designs), rng)
        if cat == "huge_array":
            continue
        data = dump(d)
        if data is not None:
            cases.append((cat, data))
    return cases


def test_fuzz_full_computes_end_cleanly(tmp_path):
    failures = []
    for i, (cat, data) in enumerate(compute_cases()):
        p = tmp_path / f"case{i}.toml"
        p.write_bytes(data)
        t0 = time.monotonic()
        r = cli("run", p, "--format", "json")
        ok = r.code in (0, 1, 2) and "Traceback" not in r.err and time.monotonic() - t0 < 20
        if r.code == 2:
            ok = ok and f"case{i}.toml" in r.err
        if not ok:
            failures.append((i, cat, r.code, r.err[-300:]))
    assert not failures, failures[:5]


def test_directory_and_unreadable_inputs(tmp_path):
    r = cli("rows", tmp_path)  # a folder without designs
    assert r.code == 2 and "no design files" in r.err
    r = cli("run", tmp_path / "missing.toml")
    assert r.code == 2 and "missing.toml" in r.err


# ---------------------------------------------------------------- --set extremes over every numeric key (issue 34)
SET_EXTREMES = [0.0, -0.0, 5e-324, 1e-320, 1e-300, 1e-20, 1e-9, -1.0, -1e308, 1e308, 1.7976931348623157e308, 1e20,
                "inf", "-inf", "nan", 1e-6, 0.999999999, 1.0000000001, 10 ** 20, 2, 3, 1e6, 1e9, 4e40, -4e40,
                1.3266152821258527e+39]


def _near(bound):
    """A field's bound and the floats just beside it (where exits 70 hide: accepted, yet at an edge)."""
    import math

    out = [bound, math.nextafter(bound, math.inf), math.nextafter(bound, -math.inf), bound * (1 + 1e-12),
           bound * (1 - 1e-12)]
    return [v for v in out if math.isfinite(v)]


def _set_value(field, rng):
    values = list(SET_EXTREMES)
    for bound in (field.gt, field.ge, field.lt, field.le):
        if bound is not None:
            values += _near(float(bound)) * 3
    v = rng.choice(values)
    if isinstance(v, str):
        return v
    if field.type == "integer" and isinstance(v, float) and v.is_integer() and abs(v) < 1e19:
        v = int(v)
    return repr(v)


def set_cases(n=300, seed=20261207):
    """(command line) cases: 1-3 --set of a numeric key of a table the design has, to an extreme or a bound's
    neighbour; `run` (CSV), `check` or a three-point `sweep`. The contact-level pins designs (seconds each) are
    checked, not run; their exits 70 of issue 34 have tests of their own."""
    from gearcalc import registry

    rng = random.Random(seed)
    cases = []
    designs = [(p, tomllib.loads(t)) for p, t in zip(SEEDS, TEXTS)]
    while len(cases) < n:
        path, raw = rng.choice(designs)
        calc = registry.get(raw["kind"])
        fields = [(t.name, f) for t in calc.tables if t.name in raw for f in t.fields
                  if f.type in ("number", "integer")]
        sets = []
        for _ in range(rng.choice((1, 1, 2, 3))):
            table, field = rng.choice(fields)
            sets += ["--set", f"{table}.{field.name}={_set_value(field, rng)}"]
        slow = path.name.startswith(("pins_paper_circ", "pins_circ"))
        cmd = "check" if slow else rng.choice(("run", "run", "run", "check", "sweep"))
        if cmd == "sweep":
            table, field = rng.choice(fields)
            axis = ",".join(_set_value(field, rng) for _ in range(3))
            cases.append(("sweep", path, "--vary", f"{table}.{field.name}={axis}", *sets, "--format", "csv"))
        else:
            cases.append((cmd, path, *sets, *(("--format", "csv") if cmd == "run" else ())))
    return cases


def test_set_extremes_never_exit_70():
    """Issue 34: a value the schema accepts is a result or a clear input error (exit 0, 1 or 2), never an exit 70,
    a traceback or a numpy warning (warnings are errors here: one would be an exit 70)."""
    import warnings

    failures, codes = [], Counter()
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        for i, args in enumerate(set_cases()):
            r = cli(*args)
            codes[r.code] += 1
            if r.code not in (0, 1, 2) or "Traceback" in r.err or "internal error" in r.err or "Warning" in r.err:
                failures.append((i, [str(a) for a in args[1:]], r.code, r.err[-300:]))
    assert not failures, failures[:5]
    assert codes[0] + codes[1] >= 30 and codes[2] >= 30, codes  # both results and refusals are exercised
