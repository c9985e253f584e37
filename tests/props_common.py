"""Helpers shared by the property tests (tests/test_props_*.py)."""
import math
import numbers


def _finite_or_none(value, where):
    """Every number in an output is finite; None marks an undefined value (interface.md "Output")."""
    if value is None or isinstance(value, (bool, str)):
        return
    if isinstance(value, numbers.Real):
        assert math.isfinite(value), f"{where} = {value!r} is not finite"
        return
    if isinstance(value, (list, tuple)):
        for k, v in enumerate(value):
            _finite_or_none(v, f"{where}[{k}]")
        return
    if isinstance(value, dict):
        for k, v in value.items():
            _finite_or_none(v, f"{where}.{k}")
        return
    raise AssertionError(f"{where} = {value!r}: unexpected type {type(value).__name__}")


def assert_all_finite(result):
    """No NaN or infinity in a Result's summary or detail tables."""
    _finite_or_none(result.summary, "summary")
    for name, rows in result.detail.items():
        for j, row in enumerate(rows):
            _finite_or_none(row, f"detail.{name}[{j}]")


def in_schema(raw):
    """The generator only writes keys of the schema, with values the loader's own field check accepts
    (types, words, bounds): guards the strategies against drifting from the schema."""
    from gearcalc import registry
    from gearcalc.design import check_value

    calc = registry.get(raw["kind"])
    for table, vals in raw.items():
        if table in ("kind", "name"):
            continue
        for key, v in vals.items():
            field = calc.table(table).field(key)
            assert field is not None, (table, key)
            _, problem = check_value(field, v)
            assert problem is None, (table, key, v, problem)
    return raw
