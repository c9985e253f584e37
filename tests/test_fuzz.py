"""Fuzzing of the loader and the CLI: random and mutated designs must end with exit 0, 1 or 2, a
message naming the file (and the key where there is one), and never a traceback or exit 70.

The cases are generated from the shipped configs with a seeded generator, so a failure is
reproducible from its case id.  Categories and counts are listed by ``test_case_counts``.
"""
import copy
import random
import tomllib

import pytest
import tomli_w

from conftest import CONFIGS, cli

SEEDS = sorted(CONFIGS.glob("*.toml"))
EXTREMES = [0, -1, -1e300, 1e300, 1e-300, 5e-324, 2**63 - 1, -(2**63), 1e15, 0.5, 3, 7.0, 1000, 1001]
WEIRD = ["", "auto", "x" * 200, [], [1, 2, 3], {"a": 1}, True, False, "nan", "1e999", [[1]], "é", "\u0000"]


def seeds_by_kind():
    out = {}
    for p in SEEDS:
        d = tomllib.loads(p.read_text())
        out.setdefault(d["kind"], []).append(d)
    return out


def leaves(d, prefix=()):
    for k, v in d.items():
        if isinstance(v, dict):
            yield from leaves(v, prefix + (k,))
        else:
            yield prefix + (k,), v


def set_path(d, path, value):
    for k in path[:-1]:
        d = d.setdefault(k, {})
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
                      "deep_nesting", "multi"])
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
        set_path(d, rng.choice(paths), [rng.random() for _ in range(rng.choice([2, 1000, 100_000]))])
    elif cat == "deep_nesting":
        node = {"leaf": 1}
        for _ in range(rng.choice([5, 50, 200])):
            node = {"t": node}
        d[rng.choice(["deep", *[p[0] for p in paths]] or ["deep"])] = node
    else:
        for _ in range(3):
            if paths:
                set_path(d, rng.choice(paths), rng.choice(EXTREMES + WEIRD))
    return cat, d


def raw_case(rng, base_text):
    """Byte-level cases: truncation, random bytes, non-UTF-8, empty, binary."""
    b = base_text.encode()
    cat = rng.choice(["truncated", "byte_flip", "non_utf8", "empty", "binary", "garbage_toml"])
    if cat == "truncated":
        data = b[: rng.randrange(len(b))]
    elif cat == "byte_flip":
        data = bytearray(b)
        for _ in range(rng.randrange(1, 6)):
            data[rng.randrange(len(data))] = rng.randrange(256)
        data = bytes(data)
    elif cat == "non_utf8":
        data = b + b"\n# \xff\xfe\xfa\n"
    elif cat == "empty":
        data = rng.choice([b"", b"   \n\n", b"# only a comment\n"])
    elif cat == "binary":
        data = bytes(rng.randrange(256) for _ in range(rng.randrange(1, 400)))
    else:
        data = rng.choice([b"[[[", b"a = ", b"kind = ", b"= 1", b"[gear]\n[gear]\n", b'kind = "rows"\nkind = "rows"\n'])
    return cat, data


def dump(design):
    try:
        return tomli_w.dumps(design).encode()
    except (TypeError, ValueError):
        return None


def generate(n_structured=900, n_raw=300, seed=20261121):
    rng = random.Random(seed)
    kinds = seeds_by_kind()
    all_seeds = [d for ds in kinds.values() for d in ds]
    texts = [p.read_text() for p in SEEDS]
    cases = []
    while len(cases) < n_structured:
        cat, d = mutate(rng.choice(all_seeds), rng)
        data = dump(d)
        if data is not None:
            cases.append((cat, data))
    for _ in range(n_raw):
        cases.append(raw_case(rng, rng.choice(texts)))
    return cases


CASES = generate()


def test_case_counts():
    from collections import Counter

    counts = Counter(c for c, _ in CASES)
    assert sum(counts.values()) >= 1000 and len(counts) >= 14, counts


@pytest.mark.parametrize("chunk", range(10))
def test_fuzz_cases_end_cleanly(tmp_path, chunk):
    failures = []
    for i, (cat, data) in enumerate(CASES):
        if i % 10 != chunk:
            continue
        p = tmp_path / f"case{i}.toml"
        p.write_bytes(data)
        r = cli("run", p, "--format", "json")
        ok = r.code in (0, 1, 2) and "Traceback" not in r.err
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
