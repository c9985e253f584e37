"""``gearcalc schema KIND`` (issue 38 item 3): the JSON Schema accepts every shipped design and agrees with
``gearcalc check`` on seeded mutations, except the cross-key rules a per-key schema cannot express."""
from __future__ import annotations

import copy
import json
import random
import tomllib

import jsonschema
import pytest

from conftest import CONFIGS, ROOT, cli

from gearcalc import registry
from gearcalc.schemajson import json_schema

SHIPPED = sorted(CONFIGS.glob("*.toml")) + sorted((ROOT / "paper").glob("*.toml"))
MUTATIONS = 300
SEED = 38


def validator(kind):
    return jsonschema.Draft202012Validator(json_schema(registry.get(kind)))


def test_the_schemas_are_valid_draft_2020_12():
    for kind in registry.kinds():
        jsonschema.Draft202012Validator.check_schema(json_schema(registry.get(kind)))


@pytest.mark.parametrize("path", SHIPPED, ids=lambda p: p.name)
def test_every_shipped_design_validates(path):
    raw = tomllib.loads(path.read_text())
    errors = [e.message for e in validator(raw["kind"]).iter_errors(raw)]
    assert not errors, errors


def test_the_command_prints_the_schema_and_new_points_at_it(tmp_path):
    r = cli("schema", "zstk")
    assert r.code == 0 and json.loads(r.out) == json_schema(registry.get("zstk"))
    out = tmp_path / "gearcalc-zstk.schema.json"
    assert cli("schema", "zstk", "-o", out).code == 0 and json.loads(out.read_text())["properties"]["kind"] == {
        "const": "zstk", "description": "the calculator"}
    assert cli("schema", "zstk", "-o", out).code == 2  # never clobber
    r = cli("new", "zstk")
    assert r.out.splitlines()[0] == "#:schema ./gearcalc-zstk.schema.json"
    design = tmp_path / "d.toml"
    design.write_text(r.out)
    assert cli("check", design).code == 0
    assert not list(validator("zstk").iter_errors(tomllib.loads(r.out)))


def _mutate(rng: random.Random, raw: dict, calc) -> tuple[dict, str]:
    """One mutation of a valid design: (mutated design, what was done)."""
    raw = copy.deepcopy(raw)
    tables = [t for t in calc.tables if isinstance(raw.get(t.name), dict)]
    table = rng.choice(tables)
    f = rng.choice(table.fields)
    cat = rng.choice(["wrong_type", "out_of_range", "unknown_key", "unknown_table", "missing", "bad_word",
                      "in_range", "kind", "table_not_table"])
    tab = raw[table.name]
    if cat == "wrong_type":
        value = rng.choice(["abc", True, [1, 2], {"a": 1}, 1.5, 7])
        tab[f.name] = value
    elif cat in ("out_of_range", "in_range"):
        bounds = [b for b in (f.gt, f.ge, f.lt, f.le) if b is not None]
        if f.type not in ("number", "integer") or not bounds:
            tab[f.name] = "not a value"
        else:
            b = rng.choice(bounds)
            step = rng.choice([-1, 1]) * (abs(b) * 0.5 + 1)
            value = b + (0 if cat == "in_range" and rng.random() < 0.5 else step)
            tab[f.name] = int(value) if f.type == "integer" else float(value)
    elif cat == "unknown_key":
        tab[rng.choice(["colour", f.name + "x", "radius"])] = 1.0
    elif cat == "unknown_table":
        raw[rng.choice(["extra", "loads", "geometryx"])] = {"a": 1}
    elif cat == "missing":
        tab.pop(f.name, None)
        if rng.random() < 0.3:
            raw.pop(table.name)
    elif cat == "bad_word":
        tab[f.name] = rng.choice(list(f.choices) + ["nope"]) if f.choices else "nope"
    elif cat == "kind":
        raw["kind"] = rng.choice(["rows", "pins", "zstk", "gears", 3])
    else:
        raw[table.name] = rng.choice([1, "x", [1]])
    return raw, f"{cat} {table.name}.{f.name}"


def _field_level_ok(raw, kind) -> bool:
    """Whether the design passes the loader's per-key checks (without the kind's cross-key check)."""
    import dataclasses

    from gearcalc import design as dmod

    calc = registry.get(kind)
    real = registry.get
    registry.get = lambda k: dataclasses.replace(real(k), check=None) if k == kind else real(k)
    try:
        dmod.validate(raw, "m.toml")
        return True
    except dmod.InputError:
        return False
    finally:
        registry.get = real
        assert calc is registry.get(kind)


def _integral_float_on_integer_key(raw, calc) -> bool:
    """JSON has one number type: 3.0 is an integer to JSON Schema, a float (refused on an integer key) to TOML."""
    for t in calc.tables:
        tab = raw.get(t.name)
        if isinstance(tab, dict):
            for f in t.fields:
                v = tab.get(f.name)
                if f.type == "integer" and isinstance(v, float) and v.is_integer():
                    return True
    return False


@pytest.mark.slow
def test_the_schema_and_check_agree_on_seeded_mutations(tmp_path):
    import tomli_w

    rng = random.Random(SEED)
    counts = {"agree_accept": 0, "agree_reject": 0, "cross_key": 0, "integral_float": 0}
    disagreements = []
    for k in range(MUTATIONS):
        path = rng.choice(SHIPPED)
        raw = tomllib.loads(path.read_text())
        calc = registry.get(raw["kind"])
        mutated, what = _mutate(rng, raw, calc)
        p = tmp_path / f"m{k}.toml"
        p.write_text(tomli_w.dumps(mutated))
        check_ok = cli("check", p).code == 0
        schema_ok = not list(validator(raw["kind"]).iter_errors(mutated))
        if schema_ok == check_ok:
            counts["agree_accept" if check_ok else "agree_reject"] += 1
        elif _integral_float_on_integer_key(mutated, calc):
            counts["integral_float"] += 1
        elif schema_ok and not check_ok and _field_level_ok(mutated, raw["kind"]):
            counts["cross_key"] += 1  # a rule of Calculator.check (exclusive keys, tables needed together, ...)
        else:
            disagreements.append((path.name, what, check_ok, schema_ok))
    print("schema vs check:", counts)
    assert not disagreements, disagreements[:10]
    assert counts["agree_reject"] > MUTATIONS // 2 and counts["agree_accept"] > 0


def test_duty_rows_and_duty_columns_both_validate():
    """pins.md §8.3: a duty cycle is given as arrays of equal length or as [[duty]] rows; the schema accepts
    both and refuses a row with an unknown key, as the loader does."""
    base = tomllib.loads((CONFIGS / "pins_paper_cyc_u10_fixed.toml").read_text())
    cols = {**base, "duty": {"torque_Nm": [100.0, 50.0], "crank_speed_rpm": [1e3, 1.5e3], "time_share": [0.3, 0.7]}}
    rows = {**base, "duty": [{"torque_Nm": 100.0, "crank_speed_rpm": 1e3, "time_share": 0.3}]}
    bad = {**base, "duty": [{"torque_Nm": 100.0, "crank_speed_rpm": 1e3, "time_sharee": 0.3}]}
    v = validator("pins")
    assert v.is_valid(cols) and v.is_valid(rows) and not v.is_valid(bad)
