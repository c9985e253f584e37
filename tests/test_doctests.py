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
