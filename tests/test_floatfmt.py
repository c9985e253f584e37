"""gearcalc.floatfmt: the vectorised repr of floats is repr, character for character; the CSV of a sweep written
with it is the CSV written cell by cell."""
import math
import random

import numpy as np
import pytest

from conftest import CONFIGS, cli
from gearcalc import floatfmt as F
from gearcalc import render as R

FIG3 = CONFIGS / "rows_fig3_n3_nw3_B2.4.toml"


def mismatches(values) -> list:
    """(value, ours, repr's) wherever floatfmt's text differs from repr (both signs of every value)."""
    x = np.asarray(values, dtype=np.float64).ravel()
    x = np.concatenate([x, -x])
    x = x[np.isfinite(x)]
    ours, ref = F.repr_floats(x), [repr(v) for v in x.tolist()]
    assert len(ours) == len(ref)
    return [(v, a, b) for v, a, b in zip(x.tolist(), ours, ref) if a != b][:10]


def neighbours(v: float, k: int = 2) -> list[float]:
    out, up, down = [v], v, v
    for _ in range(k):
        up, down = math.nextafter(up, math.inf), math.nextafter(down, -math.inf)
        out += [up, down]
    return [w for w in out if math.isfinite(w)]


def test_self_check_passes_here():
    # the tests below test the vectorised path only if it is the one used
    assert F.available()
    assert R._floatfmt() is F


def test_random_bit_patterns():
    # 4e5 doubles of every exponent (about 200 of each of the 2046 finite exponents) and significand (NaN and
    # infinities left out); seeded
    bits = np.random.default_rng(20240611).integers(0, 2**64, size=400_000, dtype=np.uint64)
    x = bits.view(np.float64)
    x = x[np.isfinite(x)]
    assert len(x) > 399_000 and np.unique(np.frexp(x)[1]).size > 2000
    ours = F.repr_floats(x)
    ref = list(map(repr, x.tolist()))
    assert ours == ref, [(a, b) for a, b in zip(ours, ref) if a != b][:10]


HARD = [
    0.0, 5e-324, 1e-323, 2.2250738585072014e-308, 2.225073858507201e-308, 2.2250738585072009e-308,
    1.7976931348623157e308, 0.1, 0.2, 0.3, 0.1 + 0.2, 1 / 3, 2 / 3, math.pi, math.e,
    float(2**53 - 1), float(2**53), float(2**53 + 1), float(2**53 + 2), 9007199254740993.0, float(2**63), float(2**64),
    1e15, 1e16, 1e17, 9999999999999998.0, 9.999999999999999e15, 99999999999999984.0, 123456789012345680.0,
    1234567890123456.8, 0.0001, 0.0001 * (1 + 2**-52), 0.0001 * (1 - 2**-53), 9.999999999999999e-5, 1e-5,
    0.00012, 0.001, 1e21, 1e22, 1e23, 9.5e-5, 123.0, 1000.0, 1e3 + 0.5, 100000.5, 1e100, 1e-100, 2.5e-300,
    1e300, 1.5e-7, 38.57142857142857, 0.12080476003796083, -10.456694566187274, 4.35, 2.675, 1.005, 0.5,
    1.25, 1234567890123.125,  # a tie at 15 digits (16 digits ending in 5; never a candidate)
    9 + 2**-16, 9.0000152587890625,  # a tie of two 16-digit candidates that both read back: the even one
    1974014630000000.25, 1974014630000000.75, 2**50 + 0.25,  # ties of two 17-digit candidates
    4.9e17, 490287408000000064.0,  # big integers (candidates exactly half an ulp away: left to repr)
]


def test_hard_cases_and_their_neighbours():
    values = [w for v in HARD for w in neighbours(v)]
    assert mismatches(values) == []


def test_powers_of_ten_and_two_and_their_neighbours():
    tens = [w for e in range(-323, 309) for w in neighbours(float(f"1e{e}"), 3)]
    assert mismatches(tens) == []
    twos = [w for k in range(-1074, 1024) for w in neighbours(math.ldexp(1.0, k), 1)]
    assert mismatches(twos) == []


def test_layout_switches_where_repr_does():
    # positional for 1e-4 <= |x| < 1e16, else scientific with two exponent digits at least
    got = F.repr_floats([0.0001, 0.00009999999999999999, 9999999999999998.0, 1e16, 1e-5, 1.5e100, 1e-100, -0.0,
                         0.0, 1e16 + 2, 123.0, 5e-324])
    assert got == ["0.0001", "9.999999999999999e-05", "9999999999999998.0", "1e+16", "1e-05", "1.5e+100",
                   "1e-100", "-0.0", "0.0", "1.0000000000000002e+16", "123.0", "5e-324"]


def test_short_decimals_of_every_length_and_exponent():
    rng = random.Random(5)
    values = []
    for _ in range(60_000):
        d = rng.randint(1, 17)
        values.append(float(f"{rng.randrange(10 ** (d - 1), 10 ** d)}e{rng.randint(-330, 310)}"))
    assert mismatches(values) == []


def test_ties_and_half_ulp_strings_decided_exactly(monkeypatch):
    # integers with quarters near 2**50..2**53 and small dyadics: exact ties of two candidates and strings exactly
    # half an ulp away, decided by round half to even without repr; the exact path must be taken and agree
    rng = np.random.default_rng(3)
    calls = []
    real = F._resolve_exact

    def spy(*args):
        calls.append(len(args[0]))
        return real(*args)

    monkeypatch.setattr(F, "_resolve_exact", spy)
    ints = rng.integers(2**49, 2**53, 50_000).astype(np.float64) + rng.integers(0, 4, 50_000) * 0.25
    dyadic = rng.integers(1, 2**30, 50_000).astype(np.float64) * np.ldexp(1.0, rng.integers(-40, 10, 50_000))
    assert mismatches(np.concatenate([ints, dyadic])) == []
    assert sum(calls) > 1000


def test_sweep_like_columns_need_no_repr():
    # values of a range axis and smooth functions of it: every one decided without repr
    x = 1.5 + np.arange(30_000) * 5e-6
    for column in (x, np.array([float(f"{v:.12g}") for v in x]), np.sqrt(x) * 38.57, 100 * (x / 1.2 - 1)):
        assert mismatches(column) == []
        assert len(F._digits(np.ascontiguousarray(column))[2]) == 0


def test_float_cells_rows_hold_the_text_between_zero_bytes():
    cells = F.float_cells(np.array([0.5, -1234.5678, 1e-7, 1e300, 0.001]))
    assert cells.dtype == np.uint8 and cells.shape[0] == 5 and cells.shape[1] <= F.WIDTH
    assert [bytes(r[r != 0]).decode() for r in cells] == ["0.5", "-1234.5678", "1e-07", "1e+300", "0.001"]


# ----------------------------------------------------------------------------- the CSV of a sweep

def test_sweep_csv_is_the_row_by_row_csv(monkeypatch):
    # a real sweep (columns of floats, constants, words, ints, flags, lists) written by the vectorised path
    # equals csv.writer with csv_cell (repr) per value
    import gearcalc

    calls = []
    real = F.float_cells
    monkeypatch.setattr(F, "float_cells", lambda x, *out: calls.append(len(x)) or real(x, *out))
    base = {"kind": "rows", "gear": {"sun_teeth": 18, "module_mm": 5.0},
            "rows": {"count": 3, "planets_per_row": 3, "relative_width": 2.4}, "sun": {"torque_Nm": 1e3}}
    axes = {"rows.relative_width": [round(0.5 + 0.0025 * k, 6) for k in range(3000)]}
    cols = next(iter(gearcalc.sweep(base, axes, model="stepwise")))
    assert cols.n == 3000
    text = R.write_csv_columns(cols)
    assert calls, "the vectorised path was not taken"
    assert text == R.write_csv(cols.rows())


def test_cli_sweep_csv_identical_either_way(monkeypatch):
    args = ("sweep", FIG3, "--vary", "rows.relative_width=1.0:3.0:0.001", "--vary", "sun.torque_Nm=1e-9,1,1e12",
            "--format", "csv")
    fast = cli(*args)
    monkeypatch.setattr(R, "_floatfmt", lambda: None)
    slow = cli(*args)
    assert fast.code == slow.code == 0
    assert fast.out.count("\n") == 1 + 2001 * 3 and fast.out == slow.out


def test_columns_with_none_zeros_duplicates_and_text_equal_row_by_row():
    rng = random.Random(11)
    n = 2000
    a = [rng.uniform(-1e3, 1e3) * 10 ** rng.randint(-12, 20) for _ in range(n)]
    data = {
        "a": a,
        "same_as_a": list(a),                              # reused cells
        "a_with_none": [None if k % 7 == 0 else v for k, v in enumerate(a)],
        "zeros": [rng.choice([0.0, -0.0]) for _ in range(n)],  # 0.0 == -0.0: not a constant column
        "const": [2.5] * n,
        "const_zero": [0.0] * n,
        "none": [None] * n,
        "ints": [rng.randint(-10**20, 10**20) for _ in range(n)],
        "mixed": [rng.choice([1, 1.0, True, -0.0, 0.0, "x", None, [1.0, -0.0]]) for _ in range(n)],
        "words": [rng.choice(["stepwise", "exact", "ü, \"quoted\"", "=formula", ""]) for _ in range(n)],
        "name": ["Fig. 3, B = 2.4"] * n,
        "flags": [rng.random() < 0.5 for _ in range(n)],
    }
    cols = R.Columns(data)
    assert R.write_csv_columns(cols) == R.write_csv(cols.rows())


def test_text_with_a_nul_character_falls_back_to_cell_by_cell():
    n = 1000
    cols = R.Columns({"x": [k / 7 for k in range(n)], "t": ["a\0b" if k == 5 else "c" for k in range(n)]})
    assert R.write_csv_columns(cols) == R.write_csv(cols.rows())


@pytest.mark.parametrize("bad", [math.nan, math.inf, -math.inf])
def test_non_finite_float_raises_on_the_vectorised_path(bad):
    n = 1000
    for col in ([k / 3 for k in range(n - 1)] + [bad], [None] + [k / 3 for k in range(n - 2)] + [bad]):
        with pytest.raises(R.NonFiniteOutput):
            R.write_csv_columns(R.Columns({"x": col}))


def test_a_failed_self_check_keeps_repr(monkeypatch):
    monkeypatch.setattr(F, "_OK", False)
    assert R._floatfmt() is None
    cols = R.Columns({"x": [k / 7 for k in range(1000)], "y": [-0.0] * 1000})
    assert R.write_csv_columns(cols) == R.write_csv(cols.rows())


# ----------------------------------------------------------------------------- one decimal exponent; cells in place

from hypothesis import given, settings, strategies as st  # noqa: E402


def one_exponent_blocks(rng, count: int):
    """Blocks of doubles of one decimal exponent each (the fast path's input): random, short decimals, their
    neighbours, both signs, over every exponent of the fast path's range."""
    for k in range(count):
        e = int(rng.integers(-249, 249))
        n = int(rng.integers(1, 2000))
        x = (1.0 + 9.0 * rng.random(n)) * 10.0 ** e
        if k % 3 == 1:  # short decimals
            x = np.array([float(f"{v:.{int(rng.integers(1, 16))}g}") for v in x.tolist()])
        elif k % 3 == 2:  # neighbours
            x = np.nextafter(x, np.where(rng.random(n) < 0.5, np.inf, -np.inf))
        x = x * np.where(rng.random(n) < 0.3, -1.0, 1.0)
        yield x[np.floor(np.log10(np.abs(x))) == np.floor(np.log10(np.abs(x[0])))]


@pytest.mark.slow
def test_one_exponent_path_is_the_general_path_bit_for_bit():
    rng = np.random.default_rng(14)
    fast = 0
    for x in one_exponent_blocks(rng, 1500):
        a = np.abs(x)
        e = F._exponent(float(a.min()))
        if e != F._exponent(float(a.max())):
            continue
        got = F._digits_one_exponent(x, a, e)
        if got is None:  # a power of two or a decision near its threshold: the general way
            continue
        fast += 1
        D, E, bad = F._digits_general(x)
        assert (got[0] == D).all() and (got[1] == E).all() and len(bad) == 0
    assert fast > 1000


@pytest.mark.slow
@settings(max_examples=300, deadline=None, derandomize=True)
@given(st.integers(-300, 300), st.lists(st.floats(1.0, 9.999999999999998), min_size=1, max_size=300),
       st.booleans())
def test_blocks_of_one_exponent_are_repr(e, mantissas, negative):
    x = np.array(mantissas) * 10.0 ** e * (-1.0 if negative else 1.0)
    x = x[np.isfinite(x) & (x != 0)]
    if len(x):
        assert mismatches(x) == []


@pytest.mark.slow
@settings(max_examples=300, deadline=None, derandomize=True)
@given(st.lists(st.integers(0, 2**64 - 1), min_size=1, max_size=200), st.integers(0, 5), st.integers(0, 40))
def test_cells_width_holds_every_cell_and_cells_write_in_place(patterns, lead, extra):
    # random bit patterns (subnormals, zeros of both signs, huge and tiny exponents): cells_width is at least
    # float_cells' own width, and cells written into a band of a wider matrix (its rest zeroed) are the same text
    x = np.array(patterns, dtype=np.uint64).view(np.float64)
    x = x[np.isfinite(x)]
    if not len(x):
        return
    own = F.float_cells(x)
    w = F.cells_width(x)
    assert w >= own.shape[1] and w <= F.WIDTH
    big = np.full((len(x), lead + w + extra + 1), 7, dtype=np.uint8)
    F.float_cells(x, big[:, lead:lead + w + extra])
    assert (big[:, :lead] == 7).all() and (big[:, lead + w + extra:] == 7).all()
    band = big[:, lead:lead + w + extra]
    assert [bytes(r[r != 0]) for r in band] == [repr(v).encode() for v in x.tolist()]


@pytest.mark.slow
@settings(max_examples=300, deadline=None, derandomize=True)
@given(st.lists(st.integers(0, 2**64 - 1), min_size=1, max_size=50))
def test_cells_width_from_the_bounds_is_the_same(patterns):
    # the CSV writer passes (min, max) it has: the width is the one cells_width finds alone, signs mixed or not
    x = np.array(patterns, dtype=np.uint64).view(np.float64)
    x = x[np.isfinite(x)]
    for y in (x, np.abs(x), -np.abs(x)):
        if len(y):
            assert F.cells_width(y, (float(y.min()), float(y.max()))) == F.cells_width(y)


def test_cells_width_at_the_switches_to_scientific_notation():
    for v in (9.999999999999999e15, 1e16, 1e15, 9.999999999999999e-5, 1e-4, 1e-5, 1e23, 9.999999999999999e22,
              0.0, -0.0, 5e-324, 1.7976931348623157e308):
        x = np.array([v, 1.5])
        assert F.cells_width(x) >= F.float_cells(x).shape[1], v


def test_float_cells_refuses_a_band_too_narrow():
    with pytest.raises(ValueError):
        F.float_cells(np.array([1.5, 2.25]), np.zeros((2, 5), dtype=np.uint8))


def test_many_blocks_equal_columns_constants_and_text_equal_row_by_row(monkeypatch):
    # several matrices of rows (CSV_MATRIX_ROWS made small), columns equal bit for bit (copied cells), -0.0 and
    # 0.0, None, constants merged with their neighbours, a first column of text and a NUL in one block only
    monkeypatch.setattr(R, "CSV_MATRIX_ROWS", 1000)
    monkeypatch.setattr(R, "CSV_CHUNK", 300)
    rng = np.random.default_rng(8)
    n = 3333
    x = 1.5 + np.arange(n) * 7e-4
    y = np.sqrt(x) * 38.57 * np.where(rng.random(n) < 0.5, -1, 1)
    data = {
        "name": ["Fig. 3, B = 2.4"] * n,
        "x": x, "count": [3] * n, "x_again": x.copy(), "y": y, "const": np.full(n, 90.0),
        "zeros": np.where(rng.random(n) < 0.5, 0.0, -0.0), "word": ["stepwise"] * n, "y_again": list(y),
        "y_none": [None if k % 5 == 0 else v for k, v in enumerate(y.tolist())],
        "flags": [bool(k % 3) for k in range(n)], "ints": list(range(n)), "empty": [[]] * n,
        "big": x * 1e20, "small": x * 1e-7, "last": [None] * n,
    }
    cols = R.Columns(data)
    assert R.write_csv_columns(cols) == R.write_csv(cols.lists().rows())
    data["word"] = ["a\0b" if k == 1500 else "c" for k in range(n)]
    cols = R.Columns(data)
    assert R.write_csv_columns(cols) == R.write_csv(cols.lists().rows())
