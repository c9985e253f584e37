"""The docstring examples of every gearcalc module run and print what they show."""
import doctest
import importlib
import pkgutil

import pytest

import gearcalc

MODULES = sorted(m.name for m in pkgutil.walk_packages(gearcalc.__path__, "gearcalc.")
                 if m.name not in ("gearcalc.__main__",))


@pytest.mark.parametrize("name", MODULES)
def test_docstring_examples(name):
    module = importlib.import_module(name)
    result = doctest.testmod(module, optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    assert result.failed == 0, f"{result.failed} of {result.attempted} examples failed in {name}"


def test_the_examples_are_many():
    # a guard that the collection above finds the modules: the physics modules carry most examples
    finder = doctest.DocTestFinder()
    physics = [n for n in MODULES if n.split(".")[1] in ("rows", "zstk", "pins", "roots", "grid", "hertz")]
    found = sum(len(t.examples) for n in physics for t in finder.find(importlib.import_module(n)))
    assert found >= 40


@pytest.mark.parametrize("name", MODULES)
def test_docstrings_hold_no_control_characters(name):
    # a "\frac" or "\rho" written into a non-raw string becomes a form feed or a carriage return: the math of
    # the docstring is then corrupted (pins.contact.effective_radius held form feeds until 0.2.0)
    text = open(importlib.import_module(name).__file__, encoding="utf-8").read()
    bad = sorted({f"U+{ord(c):04X}" for c in text if ord(c) < 32 and c not in "\n\t"})
    assert not bad, f"{name} holds control characters {bad}"
