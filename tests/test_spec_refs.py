"""Every reference to the specification in code, tests and docs ("pins.md §4.9") resolves in docs/spec/.

The specification is part of the repository (docs/spec/, copied from the project's contract); a section
cited in a docstring or a test must exist there, so a reader can follow it.
"""
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
SPEC = ROOT / "docs" / "spec"
REF = re.compile(r"\b(pins|zstk|rows|interface)\.md(?:\s*§\s*([0-9]+(?:\.[0-9]+)*)([a-z])?)?")


def sections(doc: str) -> set[str]:
    """Section numbers of a spec file: '4', '4.9', numbered items of a section ('12.7': item 7 of §12) and
    rows' lettered levels ('3b')."""
    out, current = set(), ""
    for line in (SPEC / f"{doc}.md").read_text(encoding="utf-8").splitlines():
        m = re.match(r"^#+\s*§?\s*([0-9]+(?:\.[0-9]+)*)\.?\s", line)
        if m:
            current = m.group(1)
            out.add(current)
            continue
        m = re.match(r"^([0-9]+)\.\s", line)
        if m and current:
            out.add(current.split(".")[0] + "." + m.group(1))
        m = re.match(r"^#+\s*\(([a-z])\)", line)
        if m and current:
            out.add(current.split(".")[0] + m.group(1))
    return out


def references():
    found = []
    for base in ("gearcalc", "tests", "benchmarks"):
        for path in sorted((ROOT / base).rglob("*.py")):
            for k, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
                for m in REF.finditer(line):
                    found.append((f"{path.relative_to(ROOT)}:{k}", m.group(1), m.group(2), m.group(3)))
    return found


def test_the_spec_is_in_the_repository():
    for doc in ("interface", "pins", "zstk", "rows"):
        assert (SPEC / f"{doc}.md").is_file()


def test_every_spec_reference_resolves():
    known = {doc: sections(doc) for doc in ("interface", "pins", "zstk", "rows")}
    refs = references()
    assert len(refs) > 100  # the code cites the spec throughout
    bad = []
    for where, doc, number, letter in refs:
        if number is None:
            continue
        key = number + (letter or "")
        if key not in known[doc] and not (letter and number in known[doc]):
            bad.append(f"{where}: {doc}.md §{key}")
    assert not bad, "references to sections that do not exist:\n" + "\n".join(bad[:40])


@pytest.mark.parametrize("name", sorted(p.name for p in (SPEC / "examples").glob("*.toml")))
def test_the_spec_examples_are_shipped_unchanged(name):
    assert (ROOT / "configs" / name).read_bytes() == (SPEC / "examples" / name).read_bytes()
