"""``gearcalc new KIND``: a complete, commented template design built from the kind's schema."""
from __future__ import annotations

from typing import Any

from .calculator import REQUIRED, Calculator, Field


def toml_value(value: Any) -> str:
    """A TOML literal for one value (tomli-w does the quoting and float formatting)."""
    import tomli_w

    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(toml_value(v) for v in value) + "]"
    return tomli_w.dumps({"v": value}).split("=", 1)[1].strip()


def _comment(f: Field) -> str:
    if f.default is REQUIRED:
        state = "required"
    elif f.default is None:
        state = "optional" + (f"; default {f.default_doc}" if f.default_doc else "")
    else:
        state = f"default {toml_value(f.default)}"
    text = f"{state}; {f.constraint()}"
    return f"{f.doc} ({text})" if f.doc else text


def template(calc: Calculator) -> str:
    """The template text; it parses as TOML and runs as it is."""
    lines = [
        f"#:schema ./gearcalc-{calc.kind}.schema.json",  # taplo: 'gearcalc schema KIND -o' writes that file
        f"# gearcalc {calc.kind} design: {calc.title}",
        "# Every key with its unit (in the name), its default and its constraint.",
        "# Commented keys are optional alternatives; delete what you do not need.",
    ]
    if calc.header:
        lines += [f"# {h}" for h in calc.header.splitlines()]
    lines += [f'kind = "{calc.kind}"', f'name = "new {calc.kind} design"', ""]
    for table in calc.tables:
        active = table.in_template
        prefix = "" if active else "# "
        if table.doc:
            lines.append(f"# {table.doc}" + (" (optional table)" if table.optional else ""))
        lines.append(f"{prefix}[{table.name}]")
        for f in table.fields:
            value = f.example if f.example is not None else (
                None if f.default in (None, REQUIRED) else f.default)
            if f.alternative_to and value is not None:  # exclusive keys: exactly one of the two active
                swap = f" (instead of {f.alternative_to}: uncomment this line and comment out that one)"
                lines.append(f"# {f.name} = {toml_value(value)}".ljust(40) + f"  # {_comment(f)}{swap}")
                continue
            if value is None:
                lines.append(f"# {f.name} = ...".ljust(40) + f"  # {_comment(f)}")
            else:
                lines.append(f"{prefix}{f.name} = {toml_value(value)}".ljust(40) + f"  # {_comment(f)}")
        lines.append("")
    return "\n".join(lines)
