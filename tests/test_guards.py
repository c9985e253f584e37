"""Input that cannot hurt (issue 13, the compute side): every number the schema accepts is computed or refused
with exit 2, in bounded time and memory; Ctrl-C with --jobs.  The pins calculator's guards: tests/pins/test_schema.py
(bounds, cost budgets), tests/pins/test_ideal.py (the disc sums), tests/kinds/test_pins.py (check == run).

Each test says where its expected numbers come from.
"""
import importlib
import os
import signal
import subprocess
import sys
import time

import pytest
import tomli_w

from conftest import CONFIGS, cli
from gearcalc import registry
from gearcalc.calculator import Options
from gearcalc.design import load, read_toml

sw = importlib.import_module("gearcalc.grid")   # the sweep module

PINS = CONFIGS / "pins_paper_cyc_u10_rotating.toml"
CIRC = CONFIGS / "pins_paper_circ_u10_fixed.toml"
ZSTK = CONFIGS / "zstk_merko_example.toml"


# ---------------------------------------------------------------- 2. cost guards name the key


def test_zstk_sweep_cost_guard_names_rollers():
    # R_B = 99.6, e = 0.1, c = 0: N = 1619 rollers; "cycle" + "envelope" took 112 s with the nested sweep, ~3 s
    # with the joint search (zstk.md §8).  At --model reference its first grid is 3 x 1619 x 65 roller positions
    # x 256 relative directions = 8.08e7 roller-configurations > SWEEP_WORK_MAX = 6e6 (zstk/schema.py): refused
    # before it starts; at the default model (1.4e6) check accepts it
    sets = ["--set", "geometry.inner_raceway_radius_mm=99.6", "--set", "geometry.eccentricity_mm=0.1",
            "--set", "geometry.roller_gap_mm=0.0", "--set", 'geometry.scheme="cycle"',
            "--set", 'load.direction_deg="envelope"']
    r = cli("zstk", ZSTK, *sets, "--model", "reference")
    assert r.code == 2, r
    assert "geometry.rollers" in r.err and "8.08e+07" in r.err and "envelope" in r.err
    assert cli("check", ZSTK, *sets).code == 0


def test_sweep_point_cap_is_refused_without_materialising():
    # 1e300 points: refused from the arithmetic alone (the grid is never built)
    t = time.perf_counter()
    with pytest.raises(sw.SweepError, match="more than the cap"):
        sw.parse_spec("k", "1:1e300:1")
    with pytest.raises(sw.SweepError, match="more than"):
        sw.parse_vary(["a=1:1000:1", "b=1:1000:1", "c=1:101:1"])  # 1.01e8 points > MAX_POINTS = 1e8
    assert time.perf_counter() - t < 1.0


# ---------------------------------------------------------------- 3. angles mod 360


def test_direction_1e17_equals_its_remainder():
    # 1e17 = 360 k + 280 exactly (10^17 = 0 mod 8 and 10 mod 45, so 280 mod 360), i.e. -80 deg
    assert 10 ** 17 % 360 == 280
    opts = Options(tol=1e-6)
    calc = registry.get("zstk")
    for clearance in (0.0, 0.01):
        big = calc.compute(load(str(ZSTK), [("load.direction_deg", 1e17), ("load.clearance_mm", clearance)]), opts)
        small = calc.compute(load(str(ZSTK), [("load.direction_deg", -80.0), ("load.clearance_mm", clearance)]), opts)
        for key in ("sigma_max_MPa", "sigma_max_load_direction_deg", "approach_um", "loaded_rollers"):
            assert big.summary[key] == small.summary[key], key


# ---------------------------------------------------------------- 4. --vary overflow


@pytest.mark.parametrize("spec,message", [
    ("1:2:5e-324", "step is too small"),                 # (2-1)/5e-324 = inf: OverflowError before
    ("1e308:-1e308:-1e300", "overflows"),               # stop - start = -inf: OverflowError before
    ("1:1.0000000000000002:1e-17", "resolution"),       # 1 + 1e-17 == 1: every point the same number
    ("1e400:2:1", "finite"),
])
def test_vary_specs_whose_arithmetic_overflows_exit_2(spec, message):
    with pytest.raises(sw.SweepError, match=message):
        sw.parse_spec("gearing.eccentricity_mm", spec)
    r = cli("sweep", PINS, "--vary", f"gearing.eccentricity_mm={spec}")
    assert r.code == 2, r
    assert "Traceback" not in r.err


# ---------------------------------------------------------------- 6. zstk tiny load, round-off floor


def test_zstk_tiny_load_is_refused():
    # 5e-324 N returned solver_residual = 1.0 and pass = true; the schema now starts at MIN_FORCE_N = 1 uN,
    # where the worked example with 0.01 mm clearance balances Q to ~4e-8 (the error estimate includes it)
    from gearcalc.zstk import schema as kz

    r = cli("zstk", ZSTK, "--set", "load.radial_N=5e-324")
    assert r.code == 2 and "load.radial_N" in r.err
    s = registry.get("zstk").compute(load(str(ZSTK), [("load.radial_N", kz.MIN_FORCE_N),
                                                      ("load.clearance_mm", 0.01)]), Options(tol=1e-6)).summary
    assert s["solver_residual"] < 1e-6 and s["sigma_max_MPa"] > 0 and s["sigma_max_err_MPa"] > 0


def test_sweep_error_estimates_have_a_round_off_floor():
    # a cycle/envelope estimate is at least 4 eps |sigma_max| (kinds/zstk.ROUNDOFF_ULPS)
    import numpy as np

    for sets in ([("geometry.scheme", "cycle")], [("load.direction_deg", "envelope")]):
        s = registry.get("zstk").compute(load(str(ZSTK), sets), Options(tol=1e-3)).summary
        assert s["sigma_max_err_MPa"] >= 4 * np.finfo(float).eps * s["sigma_max_MPa"]


# ---------------------------------------------------------------- 7. Ctrl-C with --jobs 2


@pytest.mark.skipif(sys.platform == "win32", reason="process groups")
@pytest.mark.parametrize("command", ["sweep", "run"])
def test_sigint_with_jobs_reports_once_without_worker_tracebacks(tmp_path, command):
    # contact-level work (~0.1 s a design or point since issue 15: 64 of them) in 2 workers; Ctrl-C goes to the
    # whole process group.
    # Without the workers' SIG_IGN initializer the sweep printed two KeyboardInterrupt tracebacks here.
    if command == "run":
        for i in range(64):
            raw = read_toml(str(CIRC))
            raw["load"]["torque_Nm"] = 100.0 + i
            (tmp_path / f"d{i}.toml").write_text(tomli_w.dumps(raw))
        args = ["run", str(tmp_path)]
    else:
        args = ["sweep", str(CIRC), "--vary", "friction.sliding=0.01:0.4:0.006"]
    p = subprocess.Popen([sys.executable, "-m", "gearcalc", *args, "--jobs", "2", "-o", str(tmp_path / "out.csv")],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, start_new_session=True)
    time.sleep(1.0)
    if p.poll() is not None:
        pytest.skip("the run ended before the signal (a fast machine)")
    os.killpg(p.pid, signal.SIGINT)
    try:
        _, err = p.communicate(timeout=60)
    except subprocess.TimeoutExpired:
        os.killpg(p.pid, signal.SIGKILL)
        p.communicate()
        pytest.fail("the run did not stop on SIGINT")
    assert p.returncode == 130, err
    assert "KeyboardInterrupt" not in err and "Traceback" not in err, err
    assert err.count("interrupted") == 1, err
