"""The man page stays in sync with the CLI: every command and option, and every rows output field."""
import re

import pytest
import typer

from conftest import ROOT

MAN = (ROOT / "man" / "gearcalc.1").read_text()
TEXT = MAN.replace("\\-", "-").replace("\\(dq", '"')


def commands():
    from gearcalc.cli import app

    group = typer.main.get_command(app)
    return group


def test_every_command_documented():
    group = commands()
    for name in group.commands:
        assert re.search(rf"^\.B[I]? \"?{name}\b", TEXT, re.M) or f".BI \"{name} " in TEXT, name


def test_every_option_documented():
    group = commands()
    opts = {o for p in group.params for o in p.opts if o.startswith("--")}
    for cmd in group.commands.values():
        for p in cmd.params:
            opts.update(o for o in p.opts + p.secondary_opts if o.startswith("-"))
    missing = [o for o in sorted(opts) if o not in TEXT]
    assert not missing, missing


def test_every_exit_code_documented():
    for code in ("0", "1", "2", "70"):
        assert re.search(rf"^\.B {code}$", MAN, re.M)


@pytest.mark.parametrize("kind", ["rows", "zstk", "pins"])
def test_every_design_key_documented(kind):
    from gearcalc import registry

    if kind not in registry.kinds():
        pytest.skip(f"{kind} not installed")
    calc = registry.get(kind)
    for table in calc.tables:
        assert f"[{table.name}]" in TEXT, table.name
        for f in table.fields:
            assert f.name in TEXT, f"{table.name}.{f.name}"


def test_rows_summary_fields_documented():
    from conftest import CONFIGS, cli
    import json

    for name in ("rows_bridges_n4_B4_i6.toml", "rows_mass_fig5.toml"):
        s = json.loads(cli("rows", CONFIGS / name, "--format", "json").out)["summary"]
        for k in s:
            k = re.sub(r"_\d+(_mm)?$", r"\1", k).replace("bridge_mm", "bridge_1_mm")
            assert k in TEXT or k.rstrip("_") in TEXT, k
