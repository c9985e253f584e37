"""Every number a design accepts, at each end of its range, gives finite output or a clear error (exit 2).

interface.md "Bad input" and the hard-case tables of rows.md, zstk.md and pins.md: no NaN, no overflow, no
silent garbage. The schema's bounds are where the accepted range ends, so each bounded key is set, one at a
time, to its smallest and its largest accepted value on a shipped design; the run must end with exit 0, 1 or
2 (never 70, which is what a non-finite output becomes), and exit 2 must name the file. Two corners also put
every load at its maximum with every length at its minimum (and the reverse).
"""
import pytest

from conftest import CONFIGS, cli
from gearcalc import registry
from gearcalc.design import read_toml

# At the ends of the ranges an intermediate may overflow on the way to a finite limit (1/(1+lambda)^2 -> 0 at
# lambda ~ 1e299); numpy says so with a RuntimeWarning, which the gearcalc command does not print (see
# test_no_numpy_warnings_on_stderr_unless_debug). What these tests check is the output.
pytestmark = pytest.mark.filterwarnings("ignore::RuntimeWarning")

BASES = {"rows": "rows_fig3_n3_nw3_B2.4.toml", "zstk": "zstk_merko_example.toml",
         "pins": "pins_paper_cyc_u10_rotating.toml"}


def bounded_keys(kind):
    raw = read_toml(str(CONFIGS / BASES[kind]))
    for table in registry.get(kind).tables:
        if table.name not in raw:  # an absent optional table is not computed: setting a key would add it
            continue
        for f in table.fields:
            if f.type not in ("number", "integer"):
                continue
            for bound in (f.ge, f.gt, f.le, f.lt):
                if bound is not None:
                    yield f"{table.name}.{f.name}", f, bound


def ends(field, bound):
    """The accepted value at a bound (the bound itself, or just inside a strict one)."""
    if field.type == "integer":
        return int(bound) if bound in (field.ge, field.le) else int(bound) + (1 if bound == field.gt else -1)
    if bound in (field.ge, field.le):
        return float(bound)
    step = max(abs(bound) * 1e-9, 1e-300)
    return bound + step if bound == field.gt else bound - step


CASES = [(kind, key, ends(f, b)) for kind in BASES for key, f, b in bounded_keys(kind)]


@pytest.mark.parametrize("kind,key,value", CASES, ids=[f"{k}:{key}={v:g}" for k, key, v in CASES])
def test_each_bound_gives_finite_output_or_clear_error(kind, key, value):
    path = CONFIGS / BASES[kind]
    r = cli(kind, path, "--set", f"{key}={value!r}", "--format", "json")
    assert r.code in (0, 1, 2), (r.code, r.err[-400:])
    assert "Traceback" not in r.err and "internal error" not in r.err
    if r.code == 2:
        assert str(path) in r.err


def test_the_cases_cover_each_kind():
    # the collection above must find bounded keys in every calculator (a schema without bounds would
    # silently make this test empty)
    counts = {kind: sum(1 for c in CASES if c[0] == kind) for kind in BASES}
    assert all(n >= 6 for n in counts.values()), counts


LOADS = {"pins": ["load.torque_Nm", "load.crank_speed_rpm", "friction.sliding", "friction.axle",
                  "friction.rolling_mm"],
         "zstk": ["load.radial_N"], "rows": ["sun.torque_Nm"]}


SCALES = {"rows": (1e-2, 1e3), "zstk": (1e-5, 1e4), "pins": (1e-5, 1e4)}  # as far as each schema's ranges go


@pytest.mark.parametrize("kind,scale", [(k, s) for k, pair in SCALES.items() for s in pair])
def test_largest_loads_on_a_tiny_and_a_huge_design(kind, scale):
    # every length of the design scaled (the geometry stays consistent, so it must compute: exit 0 or 1)
    # and every load, speed and friction at the largest value accepted
    raw = read_toml(str(CONFIGS / BASES[kind]))
    fields = {key: f for key, f, _ in bounded_keys(kind)}
    sets = []
    for key in LOADS[kind]:
        sets += ["--set", f"{key}={ends(fields[key], fields[key].le)!r}"]
    for table, body in raw.items():
        for name, value in body.items() if isinstance(body, dict) else ():
            key = f"{table}.{name}"
            if name.endswith("_mm") and key not in LOADS[kind] and isinstance(value, (int, float)) \
                    and not isinstance(value, bool):
                sets += ["--set", f"{key}={value * scale!r}"]
    r = cli(kind, CONFIGS / BASES[kind], *sets, "--format", "json")
    assert r.code in (0, 1), (r.code, r.err[-400:])


@pytest.mark.slow
def test_no_numpy_warnings_on_stderr_even_with_debug():
    # K1 = 1e-300: lambda = 7.6e298 (self-locking, exit 1) and 1/(1+lambda)^2 overflows to 0 on the way, which
    # numpy reports as a RuntimeWarning with a source line: noise for a user. Since 0.3 no numpy warning escapes
    # a computation, with --debug neither (engine.quiet_numpy; a non-finite output is the design's error instead)
    from conftest import cli_proc

    # (the first-order model, pins.md §4.7: under the friction-consistent default the reducer jams instead and
    # the multiplier runs at eta ~ 1e-16, pins.md §4.9)
    args = ["pins", CONFIGS / BASES["pins"], "--set", "gearing.curtate_ratio=1e-300", "--set",
            "friction.model=first-order", "--format", "csv"]
    quiet, loud = cli_proc(*args), cli_proc(*args, "--debug")
    assert quiet.code == loud.code == 1
    assert "RuntimeWarning" not in quiet.err and "self-locking" in quiet.err
    assert "RuntimeWarning" not in loud.err and "self-locking" in loud.err
    consistent = cli_proc(*args[:-4], "--format", "csv")
    assert consistent.code in (0, 1) and "RuntimeWarning" not in consistent.err and "Traceback" not in consistent.err
