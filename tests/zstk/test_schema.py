"""The design keys of gearcalc.zstk.schema, the adapter's mapping of them, and the light package (zstk.md §9).

Expected values: the schema's own tables (every key the adapter reads is a field, every field is read), the
package's lazy names equal each module's ``__all__``, and ``gearcalc new``/``check``/``--help`` need no numpy.
"""
import importlib
import subprocess
import sys

import gearcalc.zstk as z
from gearcalc.kinds import zstk as adapter
from gearcalc.zstk import schema as S
from gearcalc.zstk.solve import Designs


def dotted(tables):
    return [f"{t.name}.{f.name}" for t in tables for f in t.fields]


def test_adapter_reads_every_key_once():
    # kinds/zstk.DESIGN_KEYS: one key per field of solve.Designs, and together exactly the schema's keys
    assert len(adapter.DESIGN_KEYS) == len(Designs._fields)
    assert sorted(adapter.DESIGN_KEYS) == sorted(dotted(S.TABLES))


def test_problem_keys_are_fields():
    # the quantities check_designs names (zstk/validity.py) map to schema keys
    assert set(S.KEYS.values()) <= set(dotted(S.TABLES))
    assert set(S.KEYS) == {"outer", "inner", "eccentricity", "gap", "rollers", "clearance"}


def test_defaults_and_bounds():
    assert S.MATERIAL.field("allowable_stress_MPa").default_doc.startswith("4000 ")   # DEFAULT_ALLOWABLE_MPA
    assert S.GEOMETRY.field("rollers").le == S.MAX_ROLLERS == 2000
    assert S.LOAD.field("radial_N").ge == S.MIN_FORCE_N == 1e-6
    assert S.GEOMETRY.field("scheme").choices == ("A", "B", "C", "D", "cycle")
    assert adapter.CALCULATOR.tables is S.TABLES and adapter.CALCULATOR.models == S.MODELS


def test_lazy_names_are_the_modules_all():
    for module, names in z._NAMES.items():
        assert list(names) == importlib.import_module(f"gearcalc.zstk.{module}").__all__, module
    assert z.close_chain is importlib.import_module("gearcalc.zstk.chain").close_chain


def test_schema_report_and_adapter_import_no_numpy():
    code = ("import sys\nimport gearcalc.kinds.zstk, gearcalc.zstk.schema, gearcalc.zstk.report\n"
            "print('numpy' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "False"
