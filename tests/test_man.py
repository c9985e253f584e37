"""The man page stays in sync with the program.

It fails when the man page misses a command, an option of any command (in that command's synopsis
and in OPTIONS), a model level, a design key (in its kind's keys section), a summary field or a
detail-table column of any kind (in its kind's field sections, collected by computing every shipped
config at every model level it supports), or an exit code the CLI can return; and when groff warns
while rendering it.
"""
from __future__ import annotations

import functools
import re
import shutil
import subprocess

import pytest
import typer

from conftest import CONFIGS, ROOT

MAN_PATH = ROOT / "man" / "gearcalc.1"
MAN = MAN_PATH.read_text()
KINDS = ("pins", "zstk", "rows")


def plain(text: str) -> str:
    """The man source with the groff escapes this page uses turned into plain characters."""
    text = text.replace("\\-", "-").replace("\\(dq", '"').replace("\\&", "").replace("\\e", "\\")
    return re.sub(r"\\f[BIRP]", "", text)


TEXT = plain(MAN)


def section(title: str) -> str:
    """The text of the .SH or .SS section with this title, up to the next heading of any level."""
    m = re.search(rf"^\.S[HS] \"?{re.escape(title)}\"?\s*$(.*?)(?=^\.S[HS] |\Z)", TEXT, re.M | re.S)
    assert m, f"the man page has no section {title!r}"
    return m.group(1)


def words(text: str) -> set[str]:
    """Identifiers in a text (keys, fields, table names)."""
    return set(re.findall(r"[A-Za-z_][A-Za-z0-9_]*", text))


def tags(text: str) -> list[str]:
    """The tag lines of the .TP entries of a text."""
    return re.findall(r"^\.TP[^\n]*\n([^\n]*)", text, re.M)


def numbered(name: str) -> str:
    """A field numbered per row or span (bridge_rel_3, bridge_3_mm) stands for its first member."""
    return re.sub(r"_\d+(?=_|$)", "_1", name)


@functools.lru_cache(maxsize=None)
def group():
    from gearcalc.cli import app

    return typer.main.get_command(app)


def opts_of(cmd) -> list[str]:
    """Every option string of a click command, its help option included."""
    ctx = cmd.make_context(cmd.name or "gearcalc", [], resilient_parsing=True)
    out = []
    for p in cmd.get_params(ctx):
        if p.param_type_name == "option":
            out += [o for o in p.opts + p.secondary_opts if o.startswith("-")]
    return out


def synopsis(name: str | None) -> str:
    """The synopsis line(s) of one command: from `.B gearcalc NAME` to the next `.br` or `.PP`."""
    head = r"\.B gearcalc" + (rf" {name}" if name else "") + r"\s*$"
    m = re.search(rf"^{head}(.*?)(?=^\.(?:br|PP)\b|^\.SH |\Z)", section("SYNOPSIS"), re.M | re.S)
    assert m, f"no synopsis for gearcalc {name or ''}"
    return m.group(1)


# ------------------------------------------------------------------------- commands and options
def test_every_command_documented():
    commands = section("COMMANDS")
    documented = {t.split()[1].strip('"') for t in tags(commands) if t.startswith((".B ", ".BI ", ".BR "))}
    missing = [n for n in group().commands if n not in documented]
    assert not missing, f"commands without an entry in COMMANDS: {missing}"
    missing = [n for n in group().commands if not re.search(rf"^\.B gearcalc {n}\s*$", section("SYNOPSIS"), re.M)]
    assert not missing, f"commands without a synopsis: {missing}"


@pytest.mark.parametrize("name", [None, "pins", "zstk", "rows", "run", "sweep", "check", "new"])
def test_synopsis_lists_every_option(name):
    g = group()
    if name is not None and name not in g.commands:
        pytest.skip(f"no command {name}")
    cmd = g if name is None else g.commands[name]
    text = synopsis(name)
    missing = [o for o in opts_of(cmd) if not re.search(rf"(?<![\w-]){re.escape(o)}(?![\w-])", text)]
    assert not missing, f"gearcalc {name or ''}: options missing from its synopsis: {missing}"


def test_new_commands_get_their_synopsis_checked():
    # the parametrised list above must grow with the CLI (accuracy and any later command)
    listed = {"pins", "zstk", "rows", "run", "sweep", "check", "new"}
    for name in set(group().commands) - listed:
        text = synopsis(name)
        missing = [o for o in opts_of(group().commands[name])
                   if not re.search(rf"(?<![\w-]){re.escape(o)}(?![\w-])", text)]
        assert not missing, f"gearcalc {name}: options missing from its synopsis: {missing}"


def test_every_option_has_an_entry_in_options():
    g = group()
    all_opts = set(opts_of(g))
    for cmd in g.commands.values():
        all_opts.update(opts_of(cmd))
    tagged = " ".join(tags(section("OPTIONS")))
    missing = [o for o in sorted(all_opts) if not re.search(rf"(?<![\w-]){re.escape(o)}(?![\w-])", tagged)]
    assert not missing, f"options without an entry in OPTIONS: {missing}"


@pytest.mark.parametrize("kind", KINDS)
def test_every_model_level_documented(kind):
    from gearcalc import registry

    levels = registry.get(kind).models
    documented = {t.split()[1] for t in tags(section(f"{kind} model levels")) if t.startswith(".B ")}
    missing = [m for m in levels if m not in documented]
    assert not missing, f"{kind}: model levels without an entry in '{kind} model levels': {missing}"
    model_entry = re.search(r"^\.TP\n\.BI --model.*?(?=^\.TP|\Z)", section("OPTIONS"), re.M | re.S).group(0)
    missing = [m for m in levels if m not in model_entry]
    assert not missing, f"--model entry misses the {kind} levels {missing}"


# ------------------------------------------------------------------------- exit codes
def exit_codes() -> set[int]:
    """Every exit code the CLI module can return: its EXIT_* constants and literal codes."""
    import gearcalc.cli as cli

    src = (ROOT / "gearcalc" / "cli.py").read_text()
    codes = {v for k, v in vars(cli).items() if k.startswith("EXIT_") and isinstance(v, int)}
    codes.update(int(c) for c in re.findall(r"\bcode = (\d+)\b", src))
    codes.update(int(c) for c in re.findall(r"sys\.exit\((\d+)\)", src))
    return codes


def test_every_exit_code_documented():
    codes = exit_codes()
    assert {0, 1, 2, 70, 130} <= codes  # the contract's four and the interrupt
    text = section("EXIT STATUS")
    documented = {int(t.split()[1]) for t in tags(text) if re.fullmatch(r"\.B \d+", t)}
    assert not codes - documented, f"exit codes not documented: {sorted(codes - documented)}"


# ------------------------------------------------------------------------- design keys
@pytest.mark.parametrize("kind", KINDS)
def test_every_design_key_documented(kind):
    from gearcalc import registry

    calc = registry.get(kind)
    text = section(f"{kind} keys")
    have = words(text)
    missing = [t.name for t in calc.tables if f"[{t.name}]" not in text]
    missing += [f"{t.name}.{f.name}" for t in calc.tables for f in t.fields if f.name not in have]
    assert not missing, f"{kind} design keys not in the section '{kind} keys': {missing}"


# ------------------------------------------------------------------------- output fields
# Designs computed to collect the output fields: every shipped config of a kind at every model level
# it supports, except the slow pins contact level, which takes one circular design at --tol 1e-3 (its
# fields do not depend on the geometry: the summary always holds every pins key).
PINS_CONTACT = "pins_paper_circ_u10_rotating.toml"


@functools.lru_cache(maxsize=None)
def output_fields(kind: str):
    """(summary field names, {detail table: column names}) over the designs described above."""
    from gearcalc import design as dmod
    from gearcalc import registry
    from gearcalc.calculator import DesignError, Options

    calc = registry.get(kind)
    summary: dict[str, None] = {}
    detail: dict[str, dict[str, None]] = {}
    levels_run = set()
    for path in sorted(CONFIGS.glob(f"{kind}_*.toml")):
        d = dmod.load(str(path), [], None)
        for level in calc.models:
            tol = 1e-6
            if kind == "pins" and level == "contact":
                if path.name != PINS_CONTACT:
                    continue
                tol = 1e-3
            try:
                r = calc.compute(d, Options(tol=tol, model=level, detail=True))
            except DesignError:  # this design does not support this level
                continue
            levels_run.add(level)
            summary.update(dict.fromkeys(r.summary))
            for table, rows in r.detail.items():
                cols = detail.setdefault(table, {})
                for row in rows:
                    cols.update(dict.fromkeys(row))
    assert levels_run == set(calc.models), f"{kind}: no shipped config runs the levels {set(calc.models) - levels_run}"
    return list(summary), {t: list(c) for t, c in detail.items()}


@pytest.mark.parametrize("kind", KINDS)
def test_every_summary_field_documented(kind):
    fields, _ = output_fields(kind)
    have = words(section(f"{kind} summary fields"))
    missing = sorted({numbered(f) for f in fields} - have)
    assert not missing, f"{kind} summary fields not in the section '{kind} summary fields': {missing}"


@pytest.mark.parametrize("kind", KINDS)
def test_every_detail_column_documented(kind):
    _, tables = output_fields(kind)
    assert tables, f"{kind}: --detail gave no table"
    text = section(f"{kind} detail tables")
    have = words(text)
    missing = [t for t in tables if not re.search(rf"^\.TP\n\.B {t}\b", text, re.M)]
    missing += [f"{t}.{c}" for t, cols in tables.items() for c in cols if c not in have]
    assert not missing, f"{kind} detail tables/columns not in the section '{kind} detail tables': {missing}"


def test_numbered_fields_are_really_numbered():
    # the normalisation above must not hide a field: only the per-row/per-span families are numbered
    fields, _ = output_fields("rows")
    assert {numbered(f) for f in fields if re.search(r"_\d+(_|$)", f)} == {"bridge_rel_1", "bridge_1_mm"}


# ------------------------------------------------------------------------- completion and rendering
def test_completion_documented():
    opts = section("OPTIONS")
    for shell in ("bash", "zsh", "fish"):
        assert shell in section("SHELL COMPLETION"), shell
    assert "--install-completion" in opts and "--show-completion" in opts


def test_readme_documents_completion():
    readme = (ROOT / "README.md").read_text()
    assert re.search(r"^## Shell completion$", readme, re.M)
    for word in ("--install-completion", "--show-completion", "bash", "zsh", "fish"):
        assert word in readme, word


@pytest.mark.skipif(shutil.which("groff") is None, reason="groff is not installed")
def test_man_page_renders_without_warnings():
    p = subprocess.run(["groff", "-man", "-ww", "-z", str(MAN_PATH)], capture_output=True, text=True, timeout=60)
    assert p.returncode == 0 and not p.stderr.strip(), p.stderr
    p = subprocess.run(["groff", "-man", "-ww", "-Tutf8", str(MAN_PATH)], capture_output=True, text=True,
                       timeout=60, env={"LC_ALL": "C.UTF-8", "PATH": "/usr/bin:/bin"})
    assert p.returncode == 0 and not p.stderr.strip(), p.stderr
    assert "gearcalc" in p.stdout


def completion(env: dict) -> subprocess.CompletedProcess:
    """Run the app as the installed `gearcalc` command would, with completion variables set."""
    import os
    import sys

    e = {k: v for k, v in os.environ.items() if not k.startswith(("_GEARCALC", "COMP_", "_TYPER"))}
    e.update(env)
    return subprocess.run([sys.executable, "-c", "from gearcalc.cli import app; app(prog_name='gearcalc')"],
                          env=e, capture_output=True, text=True, timeout=60)


@pytest.mark.parametrize("words, cword, expected", [
    ("gearcalc ro", 1, ["rows"]),                                     # a command
    ("gearcalc rows --mo", 2, ["--model"]),                           # an option of a command
    ("gearcalc --ver", 1, ["--version"]),                             # a root option
])
def test_bash_completion_completes_as_documented(words, cword, expected):
    p = completion({"_GEARCALC_COMPLETE": "complete_bash", "COMP_WORDS": words, "COMP_CWORD": str(cword)})
    assert p.returncode == 0, p.stderr
    assert p.stdout.split() == expected


@pytest.mark.parametrize("shell, marker", [("bash", "complete -o default -F _gearcalc_completion gearcalc"),
                                           ("zsh", "#compdef gearcalc"),
                                           ("fish", "complete --command gearcalc")])
def test_completion_script_of_each_shell(shell, marker):
    # the documented way to print a given shell's script from any shell
    p = completion({"_GEARCALC_COMPLETE": f"source_{shell}"})
    assert p.returncode == 0 and marker in p.stdout, (p.stdout, p.stderr)


# ------------------------------------------------------------------------- installed with the package
def _wheel_files(tmp_path, hook: str) -> list[str]:
    """The files of the wheel the project's build backend makes with ``hook`` (build_wheel, build_editable) for a
    stand-in project: the project's backend and data-files table and man page, one empty package (offline,
    with the setuptools installed here; the real pyproject needs a newer one than the test environment may
    have, for its SPDX license)."""
    import sys
    import tomllib
    import zipfile

    meta = tomllib.loads((ROOT / "pyproject.toml").read_text())
    system, tables = meta["build-system"], meta["tool"]["setuptools"]
    proj = tmp_path / "proj"
    for folder in system.get("backend-path", []):
        shutil.copytree(ROOT / folder, proj / folder)
    (proj / "man").mkdir(parents=True)
    shutil.copy(MAN_PATH, proj / "man" / "gearcalc.1")
    (proj / "standin").mkdir()
    (proj / "standin" / "__init__.py").write_text("")
    data = "".join(f'"{k}" = {v!r}\n'.replace("'", '"') for k, v in tables["data-files"].items())
    (proj / "pyproject.toml").write_text(
        f'[build-system]\nrequires = []\nbuild-backend = "{system["build-backend"]}"\n'
        f"backend-path = {system.get('backend-path', [])!r}\n".replace("'", '"')
        + '[project]\nname = "standin"\nversion = "1"\n[tool.setuptools]\npackages = ["standin"]\n'
        + f"[tool.setuptools.data-files]\n{data}")
    out = tmp_path / "wheels"
    out.mkdir()
    code = ("import sys; sys.path[:0] = " + repr([str(proj / p) for p in system.get("backend-path", [])])
            + f"; import {system['build-backend']} as b; print(b.{hook}({str(out)!r}))")
    r = subprocess.run([sys.executable, "-c", code], cwd=proj, capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr[-2000:]
    return zipfile.ZipFile(out / r.stdout.split()[-1]).namelist()


def _builds_wheels() -> bool:
    """Whether the setuptools here builds wheels offline (its own bdist_wheel from 70.1, else the wheel package)."""
    import importlib.util

    import setuptools

    major, minor = (int(p) for p in setuptools.__version__.split(".")[:2])
    return (major, minor) >= (70, 1) or importlib.util.find_spec("wheel") is not None


@pytest.mark.skipif(not _builds_wheels(), reason="the setuptools here cannot build a wheel offline")
@pytest.mark.parametrize("hook", ["build_wheel", "build_editable"])  # pip install . / pip install -e .
def test_wheels_install_the_man_page(tmp_path, hook):
    # `man gearcalc` finds <prefix>/share/man/man1/gearcalc.1 (man-db: <dir>/../share/man of each PATH <dir>)
    names = _wheel_files(tmp_path, hook)
    assert "standin-1.data/data/share/man/man1/gearcalc.1" in names, names


def test_editable_install_installs_the_man_page(tmp_path):
    # setuptools' editable wheel runs install_data only if the distribution has `has_data`, which it lacks
    # (it has has_data_files): `pip install -e .` installed no man page.  The project's build backend adds it;
    # here setuptools' own step of the editable build, with what the backend does first (a subprocess: the
    # class is patched there only)
    import sys
    import tomllib

    system = tomllib.loads((ROOT / "pyproject.toml").read_text())["build-system"]
    paths = [str(ROOT / p) for p in system.get("backend-path", [])]
    script = f"""
import sys
sys.path[:0] = {paths!r}
import {system["build-backend"]} as backend
from setuptools.dist import Distribution
from setuptools.command.editable_wheel import editable_wheel
getattr(backend, "data_in_editable", lambda: None)()
dist = Distribution({{"name": "standin", "version": "1", "packages": [], "py_modules": [],
                     "data_files": [("share/man/man1", [{str(MAN_PATH)!r}])]}})
step = editable_wheel(dist)
dist.reinitialize_command("install").install_data = {str(tmp_path / "data")!r}
step._run_install("data")
"""
    r = subprocess.run([sys.executable, "-c", script], cwd=tmp_path, capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr[-2000:]
    assert (tmp_path / "data" / "share" / "man" / "man1" / "gearcalc.1").read_text() == MAN


def test_sdist_carries_the_build_backend():
    # a wheel built from the sdist needs the backend (backend-path) and the man page
    import tomllib

    system = tomllib.loads((ROOT / "pyproject.toml").read_text())["build-system"]
    manifest = (ROOT / "MANIFEST.in").read_text() if (ROOT / "MANIFEST.in").exists() else ""
    for folder in system.get("backend-path", []):
        module = system["build-backend"].split(".")[0] + ".py"
        assert f"include {folder}/{module}" in manifest
