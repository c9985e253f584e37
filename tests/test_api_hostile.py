"""Hostile calls to the Python API (issue 34): whatever a program passes to ``gearcalc.compute``, ``load``,
``compute_files``, ``sweep``, ``sweep_chunk``, ``models``, ``optimize`` or ``sensitivity``, bad input raises
:class:`gearcalc.InputError` (a ``ValueError``) and nothing else, and no warning escapes.

The calls come from a seeded generator: wrong types at every level of a design, weird keys, objects that are no
TOML value (locks, generators, sets, bytes, numpy arrays, NaN, huge ints, 5000-deep nesting, cyclic dicts),
overrides that are not ``KEY=VALUE`` pairs, sweep axes that are not a mapping of keys to values, bad model
names, tolerances and options.  The suite runs a few hundred of them; ``python tests/test_api_hostile.py N``
runs ``N`` and counts the outcomes by exception type (what issue 34 measured).
"""
from __future__ import annotations

import collections
import collections.abc
import datetime
import decimal
import enum
import fractions
import itertools
import random
import sys
import threading
import tomllib
import types
import warnings
from collections.abc import Mapping
from pathlib import Path

import numpy as np
import pytest

import gearcalc

sys.path.insert(0, str(Path(__file__).resolve().parent))
from conftest import CONFIGS  # noqa: E402

# cheap designs of every kind (each computes in a few ms), the bases the generator mutates
SEEDS = ["rows_fig3_n3_nw3_B2.4.toml", "rows_bridges_n4_B4_i6.toml", "rows_mass_fig5_n3.toml",
         "pins_paper_cyc_u10_fixed.toml", "pins_paper_formula_circ_u10.toml", "zstk_merko_example.toml",
         "zstk_merko_A_inner.toml"]
BASES = {name: tomllib.loads((CONFIGS / name).read_text()) for name in SEEDS}
ROWS = "rows_fig3_n3_nw3_B2.4.toml"


# ------------------------------------------------------------------ odd objects
class StrSub(str):
    pass


class IntSub(int):
    pass


class FloatSub(float):
    pass


class Colour(enum.Enum):
    RED = 1


class RaisingMapping(Mapping):
    """A mapping whose reading fails (a program's bug, or a proxy to a closed resource)."""

    def __getitem__(self, key):
        raise RuntimeError("gone")

    def __iter__(self):
        raise RuntimeError("gone")

    def __len__(self):
        return 3


class LyingMapping(Mapping):
    """A mapping that lists keys it does not have."""

    def __getitem__(self, key):
        raise KeyError(key)

    def __iter__(self):
        return iter(["kind", "rows"])

    def __len__(self):
        return 2


class BadEq:
    """An object whose comparison and hash fail."""

    def __eq__(self, other):
        raise RuntimeError("no eq")

    def __hash__(self):
        raise RuntimeError("no hash")

    def __repr__(self):
        raise RuntimeError("no repr")


def deep_list(n):
    x: list = []
    for _ in range(n):
        x = [x]
    return x


def deep_dict(n):
    x: dict = {}
    for _ in range(n):
        x = {"a": x}
    return x


def cyclic_dict():
    d: dict = {"a": 1}
    d["self"] = d
    return d


def cyclic_list():
    v: list = [1]
    v.append(v)
    return v


def wide_dag(levels):
    """2**levels paths through ``levels`` shared lists (tiny in memory, huge when walked or copied)."""
    x: list = [1.0]
    for _ in range(levels):
        x = [x, x]
    return x


HOSTILE = [
    lambda: None, threading.Lock, lambda: (x for x in range(3)), lambda: {1, 2}, frozenset, lambda: b"bytes",
    lambda: bytearray(b"x"), lambda: np.array([1.0, 2.0]), lambda: np.array(3.0), lambda: np.zeros((2, 2)),
    lambda: np.float64("nan"), lambda: np.int64(7), lambda: np.bool_(True), lambda: np.array(["a"]),
    lambda: float("nan"), lambda: float("inf"), lambda: -float("inf"), lambda: 10 ** 400, lambda: 2 ** 64,
    lambda: -(2 ** 63) - 1, lambda: int("9" * 4000), lambda: 1 + 2j, lambda: decimal.Decimal("1.5"),
    lambda: fractions.Fraction(1, 3), object, lambda: (lambda: 0), lambda: int, datetime.datetime.now,
    lambda: datetime.date(2024, 1, 1), lambda: datetime.time(1, 2), lambda: datetime.timedelta(1),
    lambda: deep_list(5000), lambda: deep_dict(5000), lambda: deep_list(40), lambda: deep_dict(40), cyclic_dict,
    cyclic_list, lambda: wide_dag(40), lambda: "x" * 10 ** 6, lambda: "", lambda: "\x00", lambda: "é\u202e😀",
    lambda: (1, 2), lambda: range(3), lambda: {1: 2}, lambda: {None: 1}, lambda: {(1, 2): 3}, RaisingMapping,
    LyingMapping, BadEq, lambda: [BadEq()], lambda: {"a": BadEq()}, lambda: StrSub("rows"), lambda: IntSub(3),
    lambda: FloatSub(2.5), lambda: Path("x"), lambda: memoryview(b"ab"), lambda: Ellipsis, lambda: NotImplemented,
    lambda: ValueError("x"), lambda: iter([1, 2]), itertools.count, lambda: types.MappingProxyType({"a": 1}),
    lambda: collections.OrderedDict(a=1), lambda: [None], lambda: [threading.Lock()],
    lambda: {"a": threading.Lock()}, lambda: Colour.RED, lambda: [[1.0] * 3] * 3, lambda: [1, "a", None],
    lambda: {"": 1}, lambda: {"a.b": 1}, lambda: {StrSub("k"): 1}, lambda: sys, lambda: type("T", (), {}),
]
PLAUSIBLE = [lambda: 0, lambda: -1, lambda: 1e300, lambda: -1e300, lambda: 5e-324, lambda: 1e-300, lambda: True,
             lambda: False, lambda: 3, lambda: 2.4, lambda: "root", lambda: "auto", lambda: [], lambda: [1, 2, 3],
             lambda: {}, lambda: "10 kN", lambda: 2 ** 63 - 1, lambda: 0.5, lambda: 1000, lambda: "stepwise"]
KEYS = [lambda: 1, lambda: None, lambda: (1, 2), lambda: b"k", lambda: "", lambda: "x" * 1000, frozenset,
        lambda: 1.5, lambda: True, lambda: StrSub("count"), lambda: "rows.count", lambda: "\x00", lambda: "kind",
        lambda: "count", lambda: "nan", lambda: np.str_("count"), lambda: np.int64(1), lambda: "é" * 200]


def pick(rng, pool):
    return rng.choice(pool)()


def value(rng):
    return pick(rng, HOSTILE) if rng.random() < 0.7 else pick(rng, PLAUSIBLE)


def leaves(d):
    """Paths to the values of a design's data: top-level keys and the keys of its tables (two levels)."""
    for k, v in list(d.items()):
        if isinstance(v, dict):
            for k2 in list(v):
                yield (k, k2)
        else:
            yield (k,)


def dotted_keys(raw):
    return [".".join(p) for p in leaves(raw) if len(p) == 2 and all(type(q) is str for q in p)]


def fresh(name):
    return tomllib.loads((CONFIGS / name).read_text())


def mutate(rng, raw):
    """The design data with one to three hostile changes somewhere."""
    for _ in range(rng.randint(1, 3)):
        op = rng.randrange(7)
        tables = [k for k, v in raw.items() if isinstance(v, dict)]
        if op == 0 or not tables:  # a leaf anywhere
            paths = list(leaves(raw)) or [("kind",)]
            path = rng.choice(paths)
            node = raw
            for p in path[:-1]:
                node = node[p]
            node[path[-1]] = value(rng)
        elif op == 1:  # a whole table
            raw[rng.choice(tables)] = value(rng)
        elif op == 2:  # a weird key with a value, at the top or in a table
            node = raw if rng.random() < 0.4 else raw[rng.choice(tables)]
            try:
                node[pick(rng, KEYS)] = value(rng)
            except RuntimeError:  # BadEq as a dict key: its hash fails
                pass
        elif op == 3:
            raw["kind"] = value(rng) if rng.random() < 0.7 else rng.choice(["rows", "pins", "zstk", "Rows", ""])
        elif op == 4:
            raw["name"] = value(rng)
        elif op == 5:  # a leaf replaced by a container holding a hostile value
            paths = list(leaves(raw)) or [("kind",)]
            path = rng.choice(paths)
            node = raw
            for p in path[:-1]:
                node = node[p]
            node[path[-1]] = rng.choice([[value(rng)], {"v": value(rng)}, (value(rng),)])
        else:  # a key removed
            paths = list(leaves(raw))
            if paths:
                path = rng.choice(paths)
                node = raw
                for p in path[:-1]:
                    node = node[p]
                del node[path[-1]]
    return raw


def design_arg(rng):
    """The ``design`` argument: mostly mutated design data, else a hostile object or path."""
    r = rng.random()
    name = rng.choice(SEEDS)
    if r < 0.55:
        return mutate(rng, fresh(name))
    if r < 0.65:
        return fresh(name)
    if r < 0.70:
        return str(CONFIGS / name)
    if r < 0.75:
        return gearcalc.load(CONFIGS / name)
    return rng.choice([
        lambda: value(rng), lambda: "no/such/file.toml", lambda: "a\x00b", lambda: b"no_such.toml",
        lambda: str(CONFIGS), lambda: "", lambda: Path("no_such.toml"), lambda: [fresh(name)],
        lambda: {"kind": "rows", 1: 2}, lambda: {"kind": "rows", "rows": {None: 1}},
        lambda: {"kind": "rows", "gear": {"sun_teeth": threading.Lock()}},
        lambda: types.MappingProxyType(fresh(name)), lambda: collections.OrderedDict(fresh(name)),
        lambda: gearcalc.Design("rows", "x", "<data>", {"rows": {"count": "a"}}),
        lambda: gearcalc.Design(value(rng), value(rng), value(rng), value(rng)),
    ])()


def overrides_arg(rng, raw=None):
    keys = dotted_keys(raw) if isinstance(raw, dict) else []
    key = rng.choice(keys) if keys else "rows.count"
    r = rng.random()
    if r < 0.3:  # a mapping
        return {(pick(rng, KEYS) if rng.random() < 0.3 else key): value(rng) for _ in range(rng.randint(0, 3))}
    if r < 0.6:  # a list of items, each a string or a pair or garbage
        items = []
        for _ in range(rng.randint(1, 3)):
            items.append(rng.choice([
                lambda: f"{key}=4", lambda: f"{key}", lambda: "=4", lambda: "a..b=1", lambda: "x" * 1000 + "=1",
                lambda: f"{key}=[1, 2", lambda: f"{key}=1\nkind='pins'", lambda: (key, value(rng)), lambda: (key,),
                lambda: (pick(rng, KEYS), 1), lambda: (key, 1, 2), lambda: value(rng), lambda: [key, 3],
                lambda: f"{key}=" + "[" * 3000 + "]" * 3000, lambda: f"{key}={'9' * 5000}", lambda: b"rows.count=4",
                lambda: ("." * 40, 1), lambda: (".".join(["a"] * 40), 1), lambda: ("rows..count", 1),
            ])())
        return items
    return rng.choice([
        lambda: value(rng), lambda: f"{key}=3", lambda: (f"{key}=3" for _ in range(2)),
        lambda: itertools.repeat((key, 3)), lambda: itertools.count(), lambda: iter([(key, 3)]),
        lambda: {key: 3}.items(), lambda: None, lambda: 5, lambda: [[key, 3]], lambda: {key: value(rng)},
    ])()


def near(v):
    """Values next to a design value, for an axis that mostly makes sense."""
    if isinstance(v, bool) or not isinstance(v, (int, float)):
        return [v]
    return [v, type(v)(v * 2) if v else 1]


def axes_arg(rng, raw=None):
    keys = dotted_keys(raw) if isinstance(raw, dict) else []
    key = rng.choice(keys) if keys else "rows.relative_width"
    if keys and rng.random() < 0.4:  # sensible axes, maybe with one odd value
        table, _, name = key.partition(".")
        values = near(raw[table][name])
        if rng.random() < 0.3:
            values.append(value(rng))
        container = rng.choice([list, tuple, list, np.array if all(type(v) in (int, float) for v in values)
                                else list])
        axes = {key: container(values)}
        if rng.random() < 0.3:
            other = rng.choice(keys)
            t2, _, n2 = other.partition(".")
            axes[other] = near(raw[t2][n2])
        return axes
    return rng.choice([
        lambda: value(rng), lambda: {}, lambda: {pick(rng, KEYS): [1, 2]}, lambda: {key: value(rng)},
        lambda: {key: []}, lambda: {key: "345"}, lambda: {key: range(1, 2 * 10 ** 8)}, lambda: {key: range(0)},
        lambda: {key: (x for x in [3, 4])}, lambda: {key: {3, 4}}, lambda: {key: [threading.Lock()]},
        lambda: {key: [None]}, lambda: {key: np.array([3, 4])}, lambda: {key: np.zeros((2, 2))},
        lambda: {"x.y": [1]}, lambda: {"": [1]}, lambda: {"rows": [1]}, lambda: {"rows.count.x": [1]},
        lambda: {key: itertools.count()}, lambda: {key: [deep_list(5000)]}, lambda: {key: [10 ** 400]},
        lambda: {key: [value(rng), value(rng)]}, lambda: {key: range(1, 10 ** 8)},
        lambda: {key: range(10 ** 5), "rows.count": range(10 ** 5)}, lambda: {key: [cyclic_list()]},
        lambda: [(key, [1, 2])], lambda: {key: [1, 2], 5: [1]}, lambda: {key: b"ab"}, lambda: {key: "a"},
        lambda: {key: [float("nan"), 1.0, 2.0]}, lambda: {key: [1.0, 2.0, float("inf")]},
        lambda: RaisingMapping(), lambda: {key: RaisingMapping()}, lambda: {key: [{}]},
    ])()


MODELS = [lambda: None, lambda: "exakt", lambda: "", lambda: 1, lambda: ["stepwise"], lambda: b"exact",
          lambda: "stepwise", threading.Lock, lambda: float("nan"), lambda: "x" * 10000, lambda: StrSub("exact"),
          lambda: "--model", lambda: BadEq()]
TOLS = [lambda: 0, lambda: -1, lambda: 0.1, lambda: float("nan"), lambda: float("inf"), lambda: "1e-6",
        lambda: None, lambda: True, lambda: np.float64(1e-4), lambda: np.array([1e-6]), lambda: 10 ** 400,
        lambda: decimal.Decimal("1e-6"), lambda: 1j, lambda: [1e-6], lambda: 1e-3, lambda: BadEq(),
        lambda: np.array(1e-3), lambda: fractions.Fraction(1, 1000)]
FLAGS = [lambda: True, lambda: False, lambda: None, lambda: 1, lambda: "yes", lambda: np.bool_(True),
         lambda: np.array([True, False]), threading.Lock, lambda: BadEq()]
INTS = [lambda: 0, lambda: -1, lambda: "2", lambda: 2.5, lambda: None, lambda: 10 ** 400, lambda: True,
        lambda: np.int64(1), lambda: float("nan"), lambda: [1], lambda: 1]
CALLBACKS = [lambda: None, lambda: 5, lambda: "print", lambda: (lambda *a: None), lambda: [print]]
SCHEDULERS = [lambda: 5, lambda: [], threading.Lock, lambda: "local:0", lambda: "local:x", lambda: "", lambda: b"x",
              lambda: "local:999"]


def kwargs(rng, names, raw=None):
    out = {}
    for name in names:
        if rng.random() < 0.25:
            pool = {"model": MODELS, "tol": TOLS, "detail": FLAGS, "verbose": FLAGS, "jobs": INTS, "chunk": INTS,
                    "progress": CALLBACKS, "say": CALLBACKS, "scheduler": SCHEDULERS,
                    "kind": MODELS + [lambda: "rows", lambda: "pins", lambda: "zstk", lambda: "Rows"]}.get(name)
            if name == "overrides":
                out[name] = overrides_arg(rng, raw)
            elif pool is not None:
                out[name] = pick(rng, pool)
    return out


def explore_case(rng, fn):
    """A hostile call of ``gearcalc.optimize`` or ``gearcalc.sensitivity`` (small budgets: a valid one is cheap)."""
    design = design_arg(rng) if rng.random() < 0.4 else fresh(rng.choice(SEEDS))
    keys = dotted_keys(design) if isinstance(design, dict) else []
    key = rng.choice(keys) if keys else "rows.relative_width"
    vary = rng.choice([lambda: {key: (1.0, 2.0)}, lambda: value(rng), lambda: {key: value(rng)},
                       lambda: [f"{key}=1:2"], lambda: {pick(rng, KEYS): (1, 2)}, lambda: {key: (value(rng), 2)}])()
    kw = kwargs(rng, ["model", "tol", "overrides", "jobs", "scheduler"], design)
    if rng.random() < 0.2:
        kw["seed"] = pick(rng, INTS)
    if fn == "optimize":
        objective = rng.choice([lambda: "K:min", lambda: value(rng), lambda: ["K:min", value(rng)],
                                lambda: "efficiency:max", lambda: "sigma_max_MPa:min"])()
        kw["budget"] = rng.choice([lambda: 4, lambda: 8, lambda: value(rng), lambda: 0, lambda: 10 ** 9])()
        if rng.random() < 0.3:
            kw["where"] = rng.choice([lambda: value(rng), lambda: ["K<=2"], lambda: [value(rng)]])()
        if rng.random() < 0.2:
            kw["refine"] = pick(rng, FLAGS)
        return lambda: gearcalc.optimize(design, vary, objective, **kw)
    kw["samples"] = rng.choice([lambda: 8, lambda: value(rng)])()
    if rng.random() < 0.3:
        kw["method"] = rng.choice([lambda: "morris", lambda: value(rng)])()
    if rng.random() < 0.3:
        kw["fields"] = rng.choice([lambda: value(rng), lambda: ["K"]])()
    return lambda: gearcalc.sensitivity(design, vary, **kw)


def make_case(rng, tmp: Path | None = None):
    """One hostile call: (label, thunk)."""
    fn = rng.choices(["compute", "load", "sweep", "sweep_chunk", "compute_files", "models", "optimize",
                      "sensitivity"], weights=[30, 15, 30, 8, 10, 2, 3, 3])[0]
    if fn in ("optimize", "sensitivity"):
        return fn, explore_case(rng, fn)
    if fn == "models":
        arg = value(rng) if rng.random() < 0.7 else rng.choice(["rows", "pins", "zstk", "row"])
        return fn, lambda: gearcalc.models(arg)
    if fn in ("compute", "load"):
        design = design_arg(rng)
        names = ["overrides", "kind"] + (["model", "tol", "detail"] if fn == "compute" else [])
        kw = kwargs(rng, names, design)
        return fn, lambda: getattr(gearcalc, fn)(design, **kw)
    if fn == "sweep":
        design = design_arg(rng) if rng.random() < 0.5 else fresh(rng.choice(SEEDS))
        axes = axes_arg(rng, design)
        kw = kwargs(rng, ["model", "tol", "overrides", "chunk", "scheduler"], design)
        return fn, lambda: next(iter(gearcalc.sweep(design, axes, **kw)))
    if fn == "sweep_chunk":
        raw = design_arg(rng) if rng.random() < 0.5 else fresh(rng.choice(SEEDS))
        axes = axes_arg(rng, raw)
        source = rng.choice([lambda: "<data>", lambda: value(rng)])()
        start, stop = rng.choice([(0, 1), (0, 2), (1, 0), (-1, 2), (0, 10 ** 9), ("0", 1), (None, None), (0.5, 1),
                                  (10 ** 400, 1), (0, 1), (0, 1), (1, 2), (np.int64(0), np.int64(1)), (0, 0)])
        kw = kwargs(rng, ["model", "tol"], raw)
        return fn, lambda: gearcalc.sweep_chunk(raw, source, axes, start, stop, **kw)
    paths = rng.choice([
        lambda: value(rng), lambda: [value(rng)], lambda: [str(CONFIGS / rng.choice(SEEDS)), value(rng)],
        lambda: str(CONFIGS / rng.choice(SEEDS)), lambda: [Path("no/such.toml")], lambda: ["a\x00b"],
        lambda: [b"no_such.toml"], lambda: (str(CONFIGS / s) for s in SEEDS[:2]), lambda: [],
        lambda: [CONFIGS / rng.choice(SEEDS)], lambda: [str(tmp)] if tmp else [],
    ])()
    kw = kwargs(rng, ["kind", "model", "tol", "detail", "overrides", "jobs", "progress", "verbose", "say",
                      "scheduler"])
    if kw.get("jobs") not in (None, 1, np.int64(1), True) and isinstance(kw.get("jobs"), int) and kw["jobs"] > 1:
        kw["jobs"] = 1  # no process pools here
    return fn, lambda: gearcalc.compute_files(paths, **kw)


def outcome(thunk):
    """(exception type name or "ok", [warning categories that escaped])."""
    with warnings.catch_warnings(record=True) as seen:
        warnings.simplefilter("always")
        try:
            thunk()
            what = "ok"
        except gearcalc.InputError:
            what = "InputError"
        except Exception as exc:  # noqa: BLE001 - counted
            what = type(exc).__name__
    return what, [w.category.__name__ for w in seen]


def cases(seed: int, n: int, tmp: Path | None = None):
    rng = random.Random(seed)
    for i in range(n):
        fn, thunk = make_case(rng, tmp)
        yield i, fn, thunk


# ------------------------------------------------------------------ the suite's share
SUITE_SEED, SUITE_CASES = 34, 600


def test_input_error_is_a_value_error():
    assert issubclass(gearcalc.InputError, ValueError)
    assert issubclass(gearcalc.DesignError, gearcalc.InputError)


def test_hostile_calls_raise_only_input_error_and_no_warning(tmp_path):
    (tmp_path / "bad.toml").write_text("kind = 'rows'\n[rows]\ncount = 0\n")
    bad = []
    for i, fn, thunk in cases(SUITE_SEED, SUITE_CASES, tmp_path):
        what, warned = outcome(thunk)
        if what not in ("ok", "InputError") or warned:
            bad.append((i, fn, what, warned))
    assert not bad, f"{len(bad)} of {SUITE_CASES} hostile calls: {bad[:10]}"


# ------------------------------------------------------------------ the cases of issue 34, one by one
BASE = {"kind": "rows", "gear": {"sun_teeth": 18, "module_mm": 5.0},
        "rows": {"count": 3, "planets_per_row": 3, "relative_width": 2.4}, "sun": {"torque_Nm": 1000.0}}


def refused(call) -> list[str]:
    """The messages of the InputError ``call()`` raises (the test fails on any other outcome)."""
    with pytest.raises(gearcalc.InputError) as info:
        call()
    return info.value.messages


def with_gear(**values):
    return {**BASE, "gear": {**BASE["gear"], **values}}


@pytest.mark.parametrize("thing", [threading.Lock(), (x for x in [1]), {1, 2}, b"18", None, 1j, object()],
                         ids=["lock", "generator", "set", "bytes", "None", "complex", "object"])
def test_an_object_that_is_no_toml_value_is_named_by_its_key(thing):
    # before: copy.deepcopy of the design raised TypeError (a lock, a generator) or validation took it
    (message,) = refused(lambda: gearcalc.compute(with_gear(sun_teeth=thing)))
    assert message.startswith("<data>: gear.sun_teeth: ") and "not a design value" in message


def test_non_string_keys_deep_and_cyclic_designs():
    # before: TypeError in _unknown_key_hint, RecursionError in copy.deepcopy
    assert refused(lambda: gearcalc.compute({"kind": "rows", 1: 2})) == [
        "<data>: the key 1 is not a string; keys of a design are strings"]
    assert "gear: the key None" in refused(lambda: gearcalc.compute(with_gear(**{"x": 1}) | {"gear": {None: 1}}))[0]
    assert "nested more than 32 levels" in refused(lambda: gearcalc.compute(with_gear(module_mm=deep_list(5000))))[0]
    assert "nested more than 32 levels" in refused(lambda: gearcalc.load({**BASE, "rows": deep_dict(5000)}))[0]
    assert "contains itself" in refused(lambda: gearcalc.compute(with_gear(module_mm=cyclic_dict())))[0]
    assert "more than" in refused(lambda: gearcalc.compute(with_gear(module_mm=wide_dag(30))))[0]
    assert "could not be read" in refused(lambda: gearcalc.compute(RaisingMapping()))[0]


def test_overrides_take_a_mapping_key_value_strings_or_pairs():
    four = gearcalc.compute(BASE, overrides={"rows.count": 4}).summary
    for same in (["rows.count=4"], "rows.count=4", [("rows.count", 4)], (("rows.count", np.int64(4)),),
                 iter(["rows.count = 4"]), {"rows.count": 4}.items()):
        assert gearcalc.compute(BASE, overrides=same).summary == four, same
    assert gearcalc.compute(BASE, overrides=None).summary == gearcalc.compute(BASE).summary
    # before: AttributeError in apply_set, TypeError, or an endless list() of an endless iterator
    for bad, words in ((["rows.count"], "overrides: 'rows.count': expected KEY=VALUE"),
                       ([5], "overrides[0]: a 'KEY=VALUE' string or a (key, value) pair, not an int"),
                       ([("rows.count",)], "overrides[0]: a 'KEY=VALUE' string or a (key, value) pair, not a tuple"),
                       ({1: 4}, "overrides: the key 1 is not a string"), (5, "overrides: a mapping"),
                       ({"rows..count": 4}, "the key must be a dotted key"),
                       ({"rows.count": threading.Lock()}, "overrides: rows.count: a _thread.lock is not"),
                       (itertools.repeat(("rows.count", 4)), "more than 10000 overrides"),
                       (b"rows.count=4", "overrides: a mapping")):
        (message,) = refused(lambda bad=bad: gearcalc.compute(BASE, overrides=bad))
        assert words in message and "--set" not in message, (bad, message)


def test_sweep_axes_are_a_mapping_of_keys_to_values_checked_at_the_call():
    # before: TypeError, IndexError or AttributeError in grid, at the first chunk (sweep was lazy)
    for axes, words in (({"rows.count": 4}, "axes: rows.count: a list, a tuple or a range of values, not an int"),
                        ({"rows.count": []}, "axes: rows.count: no values"),
                        ({"rows.count": "34"}, "not a str"), ({"rows.count": {3, 4}}, "not a set"),
                        ({"rows.count": (x for x in [3])}, "not a generator"),
                        ({1: [3]}, "axes: the key 1 is not a string"), ([("rows.count", [3])], "axes: a mapping"),
                        ({}, "axes: no axis"), ({"rows.count": np.zeros((2, 2))}, "2 dimensions"),
                        ({"rows.count": [3, None]}, "axes: rows.count[1]: a NoneType is not a design value"),
                        ({"rows.count": [3, 0]}, "axes: rows.count=0: must be an integer >= 1")):
        (message,) = refused(lambda axes=axes: gearcalc.sweep(BASE, axes))
        assert words in message and "--vary" not in message, (axes, message)


def test_the_point_cap_is_checked_before_any_value():
    # before: every one of the 2e8 values was checked first (no answer in a minute; the CLI refuses at once)
    (message,) = refused(lambda: gearcalc.sweep(BASE, {"sun.torque_Nm": range(1, 2 * 10 ** 8)}))
    assert message == "axes: the grid has more than 100000000 points (the cap)"
    (message,) = refused(lambda: gearcalc.sweep(BASE, {"rows.count": range(1, 10 ** 5), "gear.module_mm": [1] * 2000}))
    assert "more than 100000000 points" in message
    # a long range under the cap is checked by its ends (a range is monotone): refused at once, not value by value
    (message,) = refused(lambda: gearcalc.sweep(BASE, {"rows.count": range(1, 10 ** 8)}))
    assert message.startswith("axes: rows.count=99999999: must be an integer >= 1, <= ")


class NoIter(collections.abc.Sequence):
    """A long axis that may be indexed but not listed whole."""

    def __len__(self):
        return 10 ** 8

    def __getitem__(self, k):
        if isinstance(k, slice):
            return [self[j] for j in range(*k.indices(len(self)))]
        return k if 0 <= k < len(self) else IndexError(k)

    def __iter__(self):
        raise AssertionError("the whole axis was listed")


def test_a_chunk_of_a_long_axis_reads_only_its_points():
    # before: Grid.__iter__ went through itertools.product, which copies every axis whole (1e8 values for a chunk)
    from gearcalc.grid import Grid

    g = Grid({"a": [1, 2], "b": NoIter()}, 10 ** 8 - 2, 10 ** 8 + 1)
    assert list(g) == [{"a": 1, "b": 10 ** 8 - 2}, {"a": 1, "b": 10 ** 8 - 1}, {"a": 2, "b": 0}]
    # before: zstk's cost estimate asked `"cycle" in axis`, comparing every value of a range (12 s for 1e8)
    from gearcalc.calculator import Options
    from gearcalc.kinds.zstk import sweep_cost

    base = gearcalc.load(CONFIGS / "zstk_merko_example.toml")
    assert sweep_cost(base, {"geometry.scheme": range(1, 10 ** 15)}, Options()) == sweep_cost(base, {}, Options())


def test_api_messages_name_api_parameters_and_the_cli_keeps_its_options():
    from conftest import cli

    from gearcalc.calculator import tol_problem

    (message,) = refused(lambda: gearcalc.compute(BASE, model="exakt"))
    assert message.startswith("model = exakt: a rows design has the levels stepwise, exact, continuous")
    assert refused(lambda: gearcalc.compute(BASE, tol=0.5)) == [
        "tol = 0.5: " + tol_problem(0.5)]  # the command line's rule and words for --tol
    assert "tol = a str" in refused(lambda: gearcalc.compute(BASE, tol="1e-6"))[0]
    fig3 = CONFIGS / ROWS
    assert "--model exakt: a rows design" in cli("rows", fig3, "--model", "exakt").err
    assert "--set 'rows.count': expected KEY=VALUE, e.g. --set rows.count=4" in cli("rows", fig3, "--set",
                                                                                    "rows.count").err
    assert "--vary rows.count=0: must be" in cli("sweep", fig3, "--vary", "rows.count=3,0").err


def test_valid_but_odd_inputs_compute():
    plain = gearcalc.compute(BASE).summary
    odd = {"kind": StrSub("rows"), "gear": collections.OrderedDict(sun_teeth=np.int64(18), module_mm=np.float64(5)),
           "rows": types.MappingProxyType({"count": IntSub(3), "planets_per_row": np.int32(3),
                                           "relative_width": FloatSub(2.4)}),
           np.str_("sun"): {"torque_Nm": np.array(1000.0)}}
    assert gearcalc.compute(odd, tol=np.float64(1e-6), detail=np.bool_(False)).summary == plain
    from_file = gearcalc.compute(str(CONFIGS / ROWS)).summary
    assert gearcalc.compute(Path(CONFIGS / ROWS), tol=fractions.Fraction(1, 10 ** 6)).summary == from_file
    assert gearcalc.compute(CONFIGS / ROWS, tol=decimal.Decimal("1e-6")).summary == from_file
    assert gearcalc.compute(str(CONFIGS / ROWS).encode()).summary == from_file
    zstk = CONFIGS / "zstk_merko_example.toml"
    ten = gearcalc.compute(zstk, overrides={"geometry.rollers": 10}).summary
    assert gearcalc.compute(zstk, overrides={"geometry.rollers": np.int64(10)}).summary == ten
    widths = [2.0, 2.4]
    ks = [k for part in gearcalc.sweep(BASE, {"rows.relative_width": widths}) for k in part.data["K"]]
    for axis in (tuple(widths), np.array(widths)):
        assert [k for part in gearcalc.sweep(BASE, {"rows.relative_width": axis}) for k in part.data["K"]] == ks
    counts = [part.data["rows.count"] for part in gearcalc.sweep(BASE, {"rows.count": range(3, 6)}, chunk=np.int64(2))]
    assert counts == [[3, 4], [5]]
    chunk = gearcalc.sweep_chunk(BASE, "<data>", {"rows.count": range(3, 6)}, np.int64(1), 3)
    assert chunk.data["rows.count"] == [4, 5]
    assert gearcalc.compute_files(CONFIGS / ROWS, detail=None).status == 0


def test_a_design_error_is_an_input_error_and_both_pickle_whole():
    import pickle

    from gearcalc.grid import SweepError

    assert issubclass(SweepError, gearcalc.InputError)
    axes = {"geometry.inner_raceway_radius_mm": [50.0, 90.0], "geometry.eccentricity_mm": [6.0, 12.0]}
    # e = 12 with R_B = 90 only is not a valid design: since the margins (issue 36) that point is a row with its
    # reason in the ``error`` column and in the chunk's ``errors``, and the other three points are computed
    parts = list(gearcalc.sweep(CONFIGS / "zstk_merko_example.toml", axes))
    errors = [e for part in parts for e in part.errors]
    assert len(errors) == 1 and "geometry.eccentricity_mm" in errors[0] and "90" in errors[0]
    rows = [r for part in parts for r in part.rows()]
    assert [r["error"] is None for r in rows] == [True, True, True, False]
    for exc in (gearcalc.DesignError("a.b", "= 1: must be > 2"), gearcalc.InputError(["x: bad", "y: bad"], ["w"]),
                SweepError("axes: bad")):
        back = pickle.loads(pickle.dumps(exc))
        assert type(back) is type(exc) and back.__dict__ == exc.__dict__ and str(back) == str(exc)


def test_a_hand_built_design_is_checked_and_a_loaded_one_kept():
    d = gearcalc.load(BASE)
    assert gearcalc.load(d) is d
    assert refused(lambda: gearcalc.load(d, kind="pins")) == ['<data>: kind = "rows": not a pins design (kind = "pins" '
                                                              'was asked for)']
    made = gearcalc.Design("rows", "x", "<data>", {"rows": {"count": "a"}})
    assert any("rows.count" in m for m in refused(lambda: gearcalc.compute(made)))
    assert "values are not tables" in refused(lambda: gearcalc.compute(gearcalc.Design("rows", "x", "<data>", 5)))[0]


def test_no_numpy_warning_escapes():
    # inputs the schema took whose arithmetic overflowed (before: a RuntimeWarning, an error under "error");
    # each call computes, or raises InputError (a value refused, an output that would not be finite)
    for name, key, v in (("rows_bridges_n4_B4_i6.toml", "rows.relative_width", 1e-09),
                         ("rows_bridges_n4_B4_i6.toml", "bridges.bridge_thickness_mm", 1e-15),
                         ("pins_paper_cyc_u10_fixed.toml", "gearing.curtate_ratio", 1e-300),
                         ("zstk_merko_example.toml", "material.allowable_stress_MPa", 1e300)):
        path = CONFIGS / name
        for fn, args in ((gearcalc.compute, (path, None, {key: v})), (gearcalc.sweep, (path, {key: [v, 2 * v]}, ())),
                         (gearcalc.compute_files, (path, None, {key: v}))):
            with warnings.catch_warnings():
                warnings.simplefilter("error")
                try:
                    if fn is gearcalc.sweep:
                        next(fn(args[0], args[1]))
                    else:
                        fn(args[0], overrides=args[2])
                except gearcalc.InputError:
                    pass


def main(argv):  # pragma: no cover - the measurement behind issue 34 (python tests/test_api_hostile.py 4000)
    import signal
    import tempfile
    import time

    n = int(argv[1]) if len(argv) > 1 else 3000
    seed = int(argv[2]) if len(argv) > 2 else 1
    each = open(argv[3], "w") if len(argv) > 3 else None  # one line per case: number, function, outcome

    class Timeout(BaseException):  # not caught by outcome()
        pass

    def alarm(*_):
        raise Timeout

    signal.signal(signal.SIGALRM, alarm)
    import resource

    resource.setrlimit(resource.RLIMIT_AS, (3 << 30, 3 << 30))  # an unbounded list() is a MemoryError, not the OOM
    counts: collections.Counter = collections.Counter()
    by_fn: collections.Counter = collections.Counter()
    warned: collections.Counter = collections.Counter()
    examples: dict = {}
    t0 = time.perf_counter()
    with tempfile.TemporaryDirectory() as tmp:
        Path(tmp, "bad.toml").write_text("kind = 'rows'\n[rows]\ncount = 0\n")
        for i, fn, thunk in cases(seed, n, Path(tmp)):
            signal.alarm(5)
            try:
                what, w = outcome(thunk)
            except Timeout:
                what, w = "Timeout (5 s)", []
            finally:
                signal.alarm(0)
            counts[what] += 1
            if each:
                print(i, fn, what, *w, file=each, flush=True)
            by_fn[fn, what] += 1
            for c in w:
                warned[c] += 1
            examples.setdefault(what, (i, fn))
    print(f"{n} hostile calls (seed {seed}) in {time.perf_counter() - t0:.1f} s")
    for what, k in counts.most_common():
        print(f"  {k:6d}  {what}  (first: case {examples[what]})")
    print("by function:", dict(sorted(by_fn.items())))
    print("warnings escaped:", dict(warned) or 0)


if __name__ == "__main__":  # pragma: no cover
    main(sys.argv)
