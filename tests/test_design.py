"""The loader's way in: every input, however odd, ends in a design or in exit-2 messages naming the file,
the key and the constraint, in bounded time and memory, and never costs the other files of a batch
(issue 13), and its hints never propose a wrong number (issue 12).

Every test writes only inside its own tmp_path; special files (FIFOs, symlinks to /dev/zero) are made
there privately.
"""
import json
import os
import subprocess
import sys
import threading
import time

import pytest

import gearcalc
from conftest import CONFIGS, cli

from gearcalc import design as dmod
from gearcalc.calculator import Field

ZSTK = CONFIGS / "zstk_merko_example.toml"
ZSTK_NAME = "Merko et al. worked example"
ROWS = CONFIGS / "rows_fig3_n3_nw3_B2.4.toml"


def folder_with_good(tmp_path, name="good.toml"):
    d = tmp_path / "designs"
    d.mkdir()
    (d / name).write_text(ZSTK.read_text())
    return d


def assert_each_line_names(err, *names):
    for line in err.strip().splitlines():
        assert any(n in line for n in names), line


# ---------------------------------------------------------------- one bad file never costs the batch
def test_integer_beyond_the_digit_limit_costs_only_its_file(tmp_path):
    d = folder_with_good(tmp_path)
    (d / "huge.toml").write_text('kind = "zstk"\n[load]\nradial_N = ' + "7" * 4301 + "\n")
    r = cli("run", d, "--format", "csv")
    assert r.code == 2, r
    assert ZSTK_NAME in r.out  # the good design is computed
    assert "huge.toml" in r.err and "4300 digits" in r.err and "line 3, column 12" in r.err
    assert "internal error" not in r.err


def test_symlink_to_dev_zero_in_a_folder_is_skipped(tmp_path):
    d = folder_with_good(tmp_path)
    (d / "zero.toml").symlink_to("/dev/zero")
    t0 = time.monotonic()
    r = cli("run", d, "--format", "csv")
    assert time.monotonic() - t0 < 10
    assert r.code == 0, r
    assert ZSTK_NAME in r.out
    assert "zero.toml: skipped: a character device" in r.err


def test_device_named_explicitly_meets_the_size_cap(tmp_path):
    link = tmp_path / "zero.toml"
    link.symlink_to("/dev/zero")
    t0 = time.monotonic()
    r = cli("check", link, ZSTK)
    assert time.monotonic() - t0 < 10
    assert r.code == 2 and "zero.toml: larger than 1 MiB" in r.err
    assert f"ok  {ZSTK}" in r.out


def test_fifo_in_a_folder_is_skipped_without_blocking(tmp_path):
    d = folder_with_good(tmp_path)
    os.mkfifo(d / "pipe.toml")  # no writer: reading it would block forever
    p = subprocess.run([sys.executable, "-m", "gearcalc", "check", str(d)], capture_output=True, text=True,
                       timeout=60)
    assert p.returncode == 0, p
    assert "pipe.toml: skipped: a FIFO" in p.stderr and "good.toml" in p.stdout


def test_fifo_named_explicitly_is_read(tmp_path):
    fifo = tmp_path / "pipe.toml"
    os.mkfifo(fifo)
    text = ZSTK.read_bytes()

    def writer():
        with open(fifo, "wb") as fh:
            fh.write(text)

    t = threading.Thread(target=writer, daemon=True)
    t.start()
    r = cli("check", fifo)
    t.join(timeout=10)
    assert r.code == 0 and ZSTK_NAME in r.out


def test_size_cap(tmp_path):
    body = 'kind = "zstk"\n'
    at_cap = tmp_path / "at_cap.toml"
    at_cap.write_text(body + "#" * (dmod.MAX_DESIGN_BYTES - len(body) - 1) + "\n")
    over = tmp_path / "over.toml"
    over.write_text(body + "#" * (dmod.MAX_DESIGN_BYTES - len(body)) + "\n")
    r = cli("check", at_cap, over)
    assert r.code == 2
    assert "over.toml: larger than 1 MiB" in r.err and "at_cap.toml: larger" not in r.err
    assert "at_cap.toml: geometry" in r.err  # read, parsed and validated
    r = cli("check", "-", input=b"# x\n" * (dmod.MAX_DESIGN_BYTES // 4 + 1))
    assert r.code == 2 and "<stdin>: larger than 1 MiB" in r.err


def test_unreadable_folder_says_so(tmp_path, monkeypatch):
    d = tmp_path / "locked"
    d.mkdir()
    (d / "a.toml").write_text(ZSTK.read_text())
    if os.geteuid() == 0:  # root reads anything: simulate the refusal
        real = os.scandir

        def scandir(path="."):
            if os.fspath(path) == str(d):
                raise PermissionError(13, "Permission denied", str(d))
            return real(path)

        monkeypatch.setattr(os, "scandir", scandir)
    else:
        d.chmod(0)
    try:
        r = cli("check", d, ZSTK)
    finally:
        d.chmod(0o755)
    assert r.code == 2 and "no design files" not in r.err
    assert f"{d}: folder cannot be read (permission denied)" in r.err
    assert f"ok  {ZSTK}" in r.out


# ---------------------------------------------------------------- text details
def test_utf8_bom_is_accepted(tmp_path):
    p = tmp_path / "bom.toml"
    p.write_bytes(b"\xef\xbb\xbf" + ZSTK.read_bytes())
    r = cli("run", p, "--format", "csv")
    assert r.code == 0, r
    assert ZSTK_NAME in r.out


def test_error_at_end_of_document_has_line_and_column(tmp_path):
    p = tmp_path / "cut.toml"
    p.write_text('kind = "zstk"\n[load]\nradial_N =')
    r = cli("check", p)
    assert r.code == 2 and "cut.toml: TOML syntax error" in r.err
    assert "at end of document, line 3, column 11" in r.err


def test_long_dotted_keys_and_deep_nesting_are_refused_fast(tmp_path):
    cases = {
        "dots.toml": ".".join(["a"] * 200_000) + " = 1\n",  # tomllib: quadratic in the parts
        "header.toml": "[" + ".".join(["a"] * 5000) + "]\n",
        "arrays.toml": "a = " + "[" * 100_000 + "]" * 100_000 + "\n",
        "inline.toml": "x = " + "{a = " * 50_000 + "1" + "}" * 50_000 + "\n",
        "nest40.toml": 'kind = "zstk"\nx = ' + "[" * 40 + "]" * 40 + "\n",
    }
    for name, text in cases.items():
        (tmp_path / name).write_text(text)
    t0 = time.monotonic()
    r = cli("check", *sorted(tmp_path.iterdir()))
    assert time.monotonic() - t0 < 5, r
    assert r.code == 2
    for name in cases:
        assert name in r.err
    assert "more than 32 parts" in r.err and "nested more than 32 levels" in r.err
    assert_each_line_names(r.err, *cases)


def test_every_echoed_key_and_value_is_cut_and_on_one_line(tmp_path):
    key = "k" * 400_000
    p = tmp_path / "long.toml"
    p.write_text(f'kind = "rows"\n{key} = 1\n"new\\nline" = 2\nname = ["{"x" * 100_000}"]\n'
                 f'[gear]\nmodule_mm = "{"9" * 100_000}"\n{key} = 1\n')
    t0 = time.monotonic()
    r = cli("check", p)
    assert time.monotonic() - t0 < 5
    assert r.code == 2
    for line in r.err.splitlines():
        assert "long.toml" in line and len(line) < 400, line[:500]
    assert "new\\nline: unknown key" in r.err


# ---------------------------------------------------------------- --set: one key, one value
@pytest.mark.parametrize("item", [
    'load.radial_N=1\nkind = "zstk"',
    "load.radial_N=1 2",
    "load.radial_N=1\n[geometry]",
    "load.radial_N=true story",
    "name=a=b",
    "name=two\nlines",
    "load.radial_N=[1,",
])
def test_set_takes_one_value(item):
    r = cli("check", ZSTK, "--set", item)
    assert r.code == 2 and r.err.startswith("--set '"), r
    assert "load.radial_N" in r.err or "name=" in r.err
    assert "ok" not in r.out


def test_set_bare_word_is_still_a_string():
    r = cli("check", ZSTK, "--set", "name=my design", "--resolved")
    assert r.code == 0 and 'name = "my design"' in r.out


def test_set_integer_beyond_the_digit_limit():
    r = cli("check", ZSTK, "--set", "load.radial_N=" + "1" * 5000)
    assert r.code == 2 and "more than 4300 digits" in r.err and "internal error" not in r.err


@pytest.mark.parametrize("quote", ['"', ""])
def test_40kb_digit_string_via_set_is_fast(quote):
    t0 = time.monotonic()
    r = cli("check", ZSTK, "--set", f"load.radial_N={quote}{'1' * 40_000}x{quote}")
    assert time.monotonic() - t0 < 1
    assert r.code == 2 and len(r.err) < 1000


def test_32kb_digit_string_in_a_file_is_fast(tmp_path):
    p = tmp_path / "digits.toml"
    p.write_text(ZSTK.read_text().replace("radial_N = 10000.0", 'radial_N = "' + "1" * 32_000 + '"', 1))
    t0 = time.monotonic()
    r = cli("check", p)
    assert time.monotonic() - t0 < 1
    assert r.code == 2 and "load.radial_N" in r.err


# ---------------------------------------------------------------- many unknown keys
def test_250000_unknown_keys_are_counted_not_each_suggested():
    raw = {"kind": "zstk", **{f"key_{i}": 1 for i in range(250_000)},
           "load": {f"radial_{i}": 1 for i in range(250_000)}}
    t0 = time.monotonic()
    with pytest.raises(dmod.InputError) as exc:
        dmod.validate(raw, "many.toml")
    assert time.monotonic() - t0 < 5
    msgs = exc.value.messages
    assert "many.toml: … and 249980 more unknown keys at the top level" in msgs
    assert "many.toml: … and 249980 more unknown keys in [load]" in msgs
    assert len(msgs) < 60


def test_a_file_full_of_unknown_keys_is_fast(tmp_path):
    p = tmp_path / "keys.toml"
    p.write_text('kind = "zstk"\n' + "".join(f"k{i:x} = 1\n" for i in range(100_000)))
    t0 = time.monotonic()
    r = cli("check", p)
    assert time.monotonic() - t0 < 5
    assert r.code == 2 and "more unknown keys" in r.err and r.err.count("\n") < 40


# ---------------------------------------------------------------- hints
def test_key_in_the_wrong_table_names_its_table(tmp_path):
    p = tmp_path / "wrong.toml"
    p.write_text(ZSTK.read_text().replace("[geometry]", "[geometry]\nradial_N = 5", 1))
    r = cli("check", p)
    assert r.code == 2
    assert "wrong.toml: geometry.radial_N: unknown key (radial_N belongs in [load], i.e. load.radial_N)" in r.err
    p.write_text('radial_N = 5\n' + ZSTK.read_text())  # at the top level
    r = cli("check", p)
    assert "radial_N: unknown key (radial_N belongs in [load], i.e. load.radial_N)" in r.err
    p.write_text(ZSTK.read_text() + "\n[geometry.load]\nradial_N = 1\n")  # a table inside a table
    r = cli("check", p)
    assert "geometry.load: unknown key ([load] is a table of its own, at the top level)" in r.err


def test_typo_in_the_right_table_still_gets_did_you_mean(tmp_path):
    p = tmp_path / "typo.toml"
    p.write_text(ZSTK.read_text().replace("[load]", "[load]\nradial_NN = 5", 1))
    r = cli("check", p)
    assert "load.radial_NN: unknown key (did you mean 'load.radial_N'?)" in r.err


HINTS = [
    ("force_N", "10000", "write it without quotes: 10000"),
    ("force_N", "2.5e3", "write it without quotes: 2500"),
    ("force_N", "05", "write it without quotes: 5"),
    ("force_N", "10 kN", "write the bare number 10000 "),
    ("length_mm", "0.25 in", "write the bare number 6.35 "),
    ("length_mm", "5 mm", "write the bare number 5 (the unit, mm, is in the key's name)"),
    ("length_mm", "1 m", "write the bare number 1000 "),
    ("speed_rpm", "3000 rpm", "write the bare number 3000 "),
    ("torque_Nm", "2 kN·m", "write the bare number 2000 "),
    ("torque_Nm", "2 kNm", "write the bare number 2000 "),
    ("modulus_MPa", "200 GPa", "write the bare number 200000 "),
    ("angle_deg", "30 deg", "write the bare number 30 "),
    ("angle_deg", "30°", "write the bare number 30 "),
    ("angle_deg", "0.5 rad", "write the bare number 28.6478897565412 "),
    ("length_mm", "5 furlongs", "write a bare number in mm (the unit is in the key's name)"),
    ("length_mm", "5 N", "write a bare number in mm (the unit is in the key's name)"),
    ("force_N", "1" * 40_000, "write a bare number in N (the unit is in the key's name)"),
]


@pytest.fixture
def no_pint(monkeypatch):
    """The loader as without pint installed: quantity strings get the bare number proposed (the hint path)."""
    from gearcalc import quantity

    def missing():
        raise ImportError("no pint")

    monkeypatch.setattr(quantity, "_registry", missing)


@pytest.mark.parametrize("name,value,hint", HINTS)
def test_hint_numbers(no_pint, name, value, hint):
    _, err = dmod.check_value(Field(name, "number", ge=0), value)
    assert hint in err, err
    assert len(err) < 200


def test_hint_never_proposes_a_wrong_number(no_pint):
    # the old regex gave 1000 for "10000", 2.5 for "2.5e3", 0 for "05", 10 for "10 kN", 0.25 for "0.25 in"
    for name, value, wrong in [("force_N", "10000", " 1000"), ("force_N", "2.5e3", " 2.5"),
                               ("force_N", "05", " 0"), ("force_N", "10 kN", " 10 "),
                               ("length_mm", "0.25 in", "number 0.25")]:
        _, err = dmod.check_value(Field(name, "number"), value)
        assert not err.rstrip(")").endswith(wrong.strip()) and f"number{wrong}" not in err, err


def test_hint_through_the_cli():
    r = cli("check", ZSTK, "--set", 'load.radial_N="10 apples"')
    assert r.code == 2 and "load.radial_N = \"10 apples\"" in r.err and "write a bare number in N" in r.err
    r = cli("check", ROWS, "--set", 'gear.sun_teeth="05"')
    assert r.code == 2 and "write it without quotes: 5" in r.err


# ----------------------------------------------------------------------------- words a person reads (issue 34)
@pytest.mark.parametrize("old,new,hint", [
    ("eccentricity_mm = 6.0", "eccentricity_mm = 6,0", "TOML writes a decimal point, not a comma: write 6.0"),
    ('correct = "outer"', "correct = outer", 'a word is a string in TOML: write correct = "outer"'),
    ("eccentricity_mm = 6.0", "eccentricity_mm = 6.0\neccentricity_mm = 7.0",
     "geometry.eccentricity_mm is given twice (lines 8 and 9): keep one"),
    ("[load]", "[load]\n[load]", "the table [load] is given twice"),
    ("roller_gap_mm = 6.0", "roller_gap_mm = 06.0", "leading zeros are not allowed in TOML numbers: write 6.0"),
    ("roller_gap_mm = 6.0", "roller_gap_mm = 6e", "incomplete exponent"),
])
def test_usual_toml_mistakes_say_what_to_write(tmp_path, old, new, hint):
    text = ZSTK.read_text()
    assert old in text
    p = tmp_path / "d.toml"
    p.write_text(text.replace(old, new, 1))
    r = cli("check", p)
    assert r.code == 2 and "TOML syntax error" in r.err and hint in r.err, r.err


@pytest.mark.parametrize("encoding", ["utf-16", "utf-16-le", "utf-16-be"])
def test_a_utf16_file_is_named_as_such(tmp_path, encoding):
    p = tmp_path / "d.toml"
    p.write_bytes(ZSTK.read_text().encode(encoding))  # utf-16: with a byte-order mark; -le/-be: without
    r = cli("check", p)
    assert r.code == 2 and "UTF-16 text" in r.err and "save it as UTF-8" in r.err, r.err


def test_a_folder_names_the_files_it_skips_for_their_names(tmp_path):
    d = folder_with_good(tmp_path)
    (d / "A.TOML").write_text(ZSTK.read_text())
    (d / "b.toml.txt").write_text(ZSTK.read_text())
    (d / "notes.txt").write_text("not a design")
    r = cli("check", d)
    assert r.code == 0 and r.out.count("ok ") == 1
    assert "skipped 2 files not named *.toml: A.TOML, b.toml.txt" in r.err and "notes.txt" not in r.err, r.err


@pytest.mark.parametrize("item,words", [
    ("geometry.rollers=08", "leading zeros are not allowed in TOML numbers: write 8"),
    ("load.radial_N=0.1e", "incomplete exponent: write digits after the 'e' (0.1e3) or leave it out (0.1)"),
    ("load.radial_N=1,5", "TOML writes a decimal point, not a comma: write 1.5"),
])
def test_set_says_what_is_wrong_with_a_number(item, words):
    r = cli("check", ZSTK, "--set", item)
    assert r.code == 2 and words in r.err and "one key takes one value" not in r.err, r.err


def test_set_and_vary_with_a_unit_convert_as_a_file_does(tmp_path):
    p = tmp_path / "d.toml"
    p.write_text(ZSTK.read_text().replace("radial_N = 10000.0", 'radial_N = "10kN"'))
    in_file = cli("check", "--resolved", p)
    assert in_file.code == 0 and "radial_N = 10000.0" in in_file.out, in_file.err  # 10 kN = 10000 N
    r = cli("check", "--resolved", ZSTK, "--set", "load.radial_N=10kN")
    assert r.code == 0 and "radial_N = 10000.0" in r.out, r.err
    r = cli("sweep", ZSTK, "--vary", "load.radial_N=10kN,20000", "-f", "csv", "--fields", "load.radial_N")
    assert r.code == 0 and r.out.splitlines()[1:] == ["10000.0", "20000"], r.out + r.err
    # a range takes bare numbers only: the hint proposes them
    r = cli("sweep", ZSTK, "--vary", "load.radial_N=1kN:50kN:1kN", "-f", "csv")
    assert r.code == 2 and "write the bare numbers 1000:50000:1000 (in N" in r.err, r.err


def test_a_problem_with_a_value_reads_key_equals_value():
    r = cli("check", CONFIGS / "pins_paper_cyc_u10_fixed.toml", "--set", "gearing.pins=20")
    assert r.code == 2 and "gearing.pins = 20: " in r.err and ": =" not in r.err, r.err
    r = cli("sweep", ZSTK, "--vary", "geometry.rollers=7,8", "-f", "csv")
    assert r.code == 2 and "geometry.rollers = 7: " in r.err and ": =" not in r.err, r.err


@pytest.mark.parametrize("path,lines", [
    (ZSTK, ["allowable_stress_MPa = 4000.0", "inner_ring_E_MPa = 210000.0"]),  # zstk.md: the ISO 76 default
    (CONFIGS / "pins_paper_cyc_u10_fixed.toml", ['model = "consistent"']),      # pins.md §4.9: the default model
])
def test_check_resolved_shows_the_values_the_computation_takes(tmp_path, path, lines):
    import json

    r = cli("check", path, "--resolved")
    assert r.code == 0 and all(line in r.out for line in lines), r.out
    p = tmp_path / "resolved.toml"
    p.write_text(r.out)
    before = json.loads(cli("run", path, "-f", "json").out)["summary"]
    after = json.loads(cli("run", p, "-f", "json").out)["summary"]
    for s in (before, after):
        s.pop("model_time_ms", None)
        s.pop("allowable_stress_source", None)  # "default" before, "design" once written out
    assert after == before  # the resolved design computes the same results


# ----------------------------------------------------------------------------- units in values (issue 38 item 4)
@pytest.mark.parametrize("name,value,expected", [
    ("torque_Nm", "200 N*m", 200.0),
    ("torque_Nm", "2 kN*m", 2000.0),          # 1 kN·m = 1000 N·m
    ("torque_Nm", "2 kN·m", 2000.0),
    ("length_mm", "0.1 in", 2.54),            # 1 in = 25.4 mm exactly
    ("length_mm", "1 m", 1000.0),
    ("force_N", "10kN", 10000.0),
    ("modulus_MPa", "200 GPa", 200000.0),     # 1 GPa = 1000 MPa
    ("speed_rpm", "100 1/min", 100.0),        # min^-1 is revolutions per minute
    ("speed_rpm", "1 Hz", 60.0),              # one revolution a second
    ("angle_deg", "30°", 30.0),
])
def test_quantity_strings_are_converted_to_the_keys_unit(name, value, expected):
    v, err = dmod.check_value(Field(name, "number", ge=0), value)
    assert err is None and v == pytest.approx(expected, rel=1e-12), (v, err)


@pytest.mark.parametrize("name,value,words", [
    ("length_mm", "2 kN*m", "kN*m is a torque, this key is a length (mm)"),
    ("torque_Nm", "10 kN", "kN is a force, this key is a torque (N·m)"),
    ("speed_rpm", "5 deg", "deg is an angle, this key is a speed of rotation (rpm)"),
])
def test_a_quantity_of_another_dimension_is_named(name, value, words):
    _, err = dmod.check_value(Field(name, "number", ge=0), value)
    assert err == words


def test_converted_values_are_checked_against_the_bounds():
    _, err = dmod.check_value(Field("length_mm", "number", le=1000.0), "2 m")  # 2000 mm > 1000
    assert err and err.startswith("must be a number <= 1000"), err


def test_the_resolved_design_shows_the_converted_number(tmp_path):
    p = tmp_path / "d.toml"
    p.write_text(ZSTK.read_text().replace("eccentricity_mm = 6.0", 'eccentricity_mm = "0.25 in"'))
    r = cli("check", "--resolved", p)
    assert r.code == 0 and "eccentricity_mm = 6.35" in r.out, r.err  # 0.25 in = 6.35 mm
    r = cli("zstk", p, "-f", "json")
    assert r.code in (0, 1) and json.loads(r.out)["design"]["geometry"]["eccentricity_mm"] == 6.35


@pytest.mark.slow
def test_pint_is_imported_only_when_a_quantity_string_appears(tmp_path):
    code = ("import sys; from gearcalc.cli import main; sys.argv = ['gearcalc'] + sys.argv[1:]\n"
            "try:\n    main()\nexcept SystemExit:\n    pass\n"
            "sys.stderr.write('PINT=%s' % ('pint' in sys.modules))")
    p = tmp_path / "d.toml"
    p.write_text(ZSTK.read_text().replace("eccentricity_mm = 6.0", 'eccentricity_mm = "6 mm"'))
    for args, imported in ((["--help"], False), (["check", str(ZSTK)], False), (["zstk", str(ZSTK)], False),
                           (["check", str(p)], True)):
        r = subprocess.run([sys.executable, "-c", code, *args], capture_output=True, text=True, cwd=tmp_path)
        assert f"PINT={imported}" in r.stderr, (args, r.stderr[-500:])


@pytest.mark.parametrize("value", ["1 2**2**2**2**2**2**2 m", "1 m^2^2^2^2^2^2^2^2", "1 m**(10**10)", "1 mm*99**9",
                                   "1 m*1000000", "1 __import__('os')"])
def test_a_unit_text_pint_would_compute_for_ever_is_not_a_quantity(value):
    # pint's parser evaluates powers of numbers (2**2**...: a number of 2**65536 bits): such texts never reach it
    _, err = dmod.check_value(Field("length_mm", "number", ge=0), value)
    assert err.startswith("must be a number") and "write a bare number in mm" in err, err


# ---------------------------------------------------------------- a rows table given as [[rows]] (pins.md §8.3)
PINS = CONFIGS / "pins_paper_cyc_u10_fixed.toml"
DUTY_ROWS = [(100.0, 1000.0, 0.3), (50.0, 1500.0, 0.7), (150.0, 500.0, 0.25)]


def duty_as_rows(rows=DUTY_ROWS, extra=""):
    return PINS.read_text() + "".join(
        f"\n[[duty]]\ntorque_Nm = {t}\ncrank_speed_rpm = {n}\ntime_share = {s}\n" for t, n, s in rows) + extra


def duty_as_columns(rows=DUTY_ROWS):
    t, n, s = zip(*rows)
    return PINS.read_text() + f"\n[duty]\ntorque_Nm = {list(t)}\ncrank_speed_rpm = {list(n)}\ntime_share = {list(s)}\n"


def test_duty_rows_are_the_same_design_as_duty_columns(tmp_path):
    """The two spellings of one duty cycle (an array of tables, a table of arrays) give the same design: the
    same resolved keys and the same computed summary (the reference is the column-wise form)."""
    rows, cols = tmp_path / "rows.toml", tmp_path / "cols.toml"
    rows.write_text(duty_as_rows())
    cols.write_text(duty_as_columns())
    assert dmod.load(str(rows)).resolved() == dmod.load(str(cols)).resolved()
    a, b = (json.loads(cli("run", p, "-f", "json", "--set", "contact.face_width_mm=10").out) for p in (rows, cols))
    for s in (a, b):
        s.pop("file"), s["summary"].pop("model_time_ms", None)
    assert a == b and a["summary"]["duty_rows"] == 3 and a["summary"]["duty_contact_stress_max_MPa"] > 0


def test_set_overrides_a_column_of_duty_rows(tmp_path):
    rows = tmp_path / "rows.toml"
    rows.write_text(duty_as_rows())
    d = dmod.load(str(rows), overrides=[("duty.torque_Nm", [10.0, 20.0, 30.0])])
    assert d["duty.torque_Nm"] == [10.0, 20.0, 30.0] and d["duty.time_share"] == [0.3, 0.7, 0.25]


def test_a_duty_row_with_a_missing_or_unknown_key_is_named_by_its_row(tmp_path):
    rows = tmp_path / "rows.toml"
    rows.write_text(duty_as_rows(extra="\n[[duty]]\ntorque_Nm = 10.0\ntime_sharee = 1.0\n"))
    r = cli("run", rows)
    assert r.code == 2 and "Traceback" not in r.err
    assert f"{rows}: duty[4].time_sharee: unknown key" in r.err
    assert f"{rows}: duty[4].crank_speed_rpm: missing" in r.err and f"{rows}: duty[4].time_share: missing" in r.err


def test_the_api_reads_duty_rows_without_changing_the_callers_mapping():
    import tomllib

    import gearcalc

    raw = tomllib.loads(duty_as_rows())
    before = json.dumps(raw, sort_keys=True)
    s = gearcalc.compute(raw).summary
    assert s["duty_rows"] == 3 and json.dumps(raw, sort_keys=True) == before
# ---------------------------------------------------------------- each design prepared once per run (issue 35 item 2)
# What its check prepared (Design.keep), its computation uses (Design.take); a design changed after its check is
# prepared again. Expected: call counts, and the same summary as the design computed afresh.
def counting(monkeypatch, module, name):
    calls = []
    real = getattr(module, name)

    def spy(*args, **kw):
        calls.append(1)
        return real(*args, **kw)

    monkeypatch.setattr(module, name, spy)
    return calls


def test_zstk_design_is_prepared_once(monkeypatch):
    from gearcalc.zstk import solve

    calls = counting(monkeypatch, solve, "prepare")
    path = CONFIGS / "zstk_merko_A_envelope.toml"  # a direction sweep: computed alone, as in a batch
    once = gearcalc.compute_files([path]).results[0].summary
    assert len(calls) == 1  # the check's arrays serve the computation
    again = gearcalc.compute(gearcalc.load(path)).summary
    assert len(calls) == 2
    assert {k: v for k, v in once.items() if k != "model_time_ms"} == \
        {k: v for k, v in again.items() if k != "model_time_ms"}


def test_pins_contact_design_builds_its_profile_once(monkeypatch):
    from gearcalc.pins import contact_level

    calls = counting(monkeypatch, contact_level, "satellite_profile")
    gearcalc.compute_files([CONFIGS / "pins_paper_circ_u10_fixed.toml"])  # the contact level
    assert len(calls) == 1


def test_a_design_changed_after_its_check_is_prepared_again(monkeypatch):
    from gearcalc.zstk import solve

    path = CONFIGS / "zstk_merko_A_inner.toml"
    d = gearcalc.load(path)
    d.values["load"]["radial_N"] *= 2  # after the check: its prepared arrays no longer fit
    calls = counting(monkeypatch, solve, "prepare")
    changed = gearcalc.compute(d).summary
    assert len(calls) == 1
    fresh = gearcalc.compute(path, overrides={"load.radial_N": d["load.radial_N"]}).summary  # check + compute: 1
    assert {k: v for k, v in changed.items() if k != "model_time_ms"} == \
        {k: v for k, v in fresh.items() if k != "model_time_ms"}
    twice = gearcalc.compute(d).summary  # computed again: prepared again, the same numbers
    assert twice["name"] == changed["name"] and len(calls) == 3
