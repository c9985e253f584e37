"""Tests of gearcalc.report.method: the report's key equations with the design's values substituted.

Where the expected numbers come from: Johnson 1985 §4.2, p0 = sqrt(F E*/(pi l rho)) with
1/E* = (1 - nu_1²)/E_1 + (1 - nu_2²)/E_2 (so Merko's k = sqrt(E*/pi)); the roller-raceway curvature
rho = r R/(R ± r) (Merko et al. eqs. (4)-(5)); the worked example's sigma_max = 748.9357 MPa (zstk.md §6);
the identities [sigma_H]/sigma_max and w_max = K w_mean (rows.md §2.2).  A printed value has 6 significant digits.
"""
import math
import re
import tomllib
import types

import pytest

from conftest import CONFIGS
from gearcalc import api
from gearcalc.report.method import method_lines

NUMBER = r"[-+]?\d+(?:\.\d+)?(?:e[-+]?\d+)?"


def lines_of(path, overrides=None, kind="zstk"):
    res = api.compute(api.load(path, overrides=overrides or {}), detail=True)
    design = tomllib.loads(path.read_text())
    for key, value in (overrides or {}).items():
        table, _, name = key.partition(".")
        design.setdefault(table, {})[name] = value
    return res.summary, method_lines(types.SimpleNamespace(kind=kind, result=res, design=design))


def numbers(text):
    return [float(x) for x in re.findall(NUMBER, text)]


def six(x):
    return pytest.approx(x, rel=5e-6)


@pytest.mark.parametrize("ring", [(2.1e5, 0.3), (1.1e5, 0.34)])
def test_zstk_contact_stress_equation_with_the_designs_values(ring):
    e_ring, nu_ring = ring
    s, lines = lines_of(CONFIGS / "zstk_merko_example.toml", {"material.ring_E_MPa": e_ring,
                                                              "material.ring_poisson": nu_ring})
    (rho_line, _), (k_line, _), (sigma_line, ref), *_ = lines
    assert "Johnson 1985" in ref
    r, R = numbers(rho_line.split(" = ")[2])[:2]
    assert numbers(rho_line)[-1] == six(r * R / (R + r))              # inner contact: rho = r R/(R + r)
    e_star = 1.0 / ((1 - 0.3 ** 2) / 2.1e5 + (1 - nu_ring ** 2) / e_ring)
    k = math.sqrt(e_star / math.pi)
    assert numbers(k_line.split(" = ")[-1])[0] == six(k)
    k_printed, F, L, rho, p0 = numbers(" = ".join(sigma_line.split(" = ")[2:]))[:5]
    assert k_printed == six(k) and L == 20.0 and p0 == six(k * math.sqrt(F / (L * rho)))
    assert p0 == six(s["sigma_max_MPa"])                              # the equation gives the reported value
    if ring == (2.1e5, 0.3):
        assert p0 == six(748.9357)                                    # Merko et al.'s worked example


def test_zstk_safety_factor_and_closure_lines():
    s, lines = lines_of(CONFIGS / "zstk_merko_example.toml")
    closure, safety = lines[-2][0], lines[-1][0]
    assert numbers(closure)[:2] == [six(s["N_star"]), s["N"]] and s["N"] == 8
    allow, sigma, factor = numbers(safety.split(" = ", 1)[1])
    assert allow == 4000.0 and factor == six(4000.0 / 748.935693220922) and factor == six(allow / sigma)


def test_rows_lines_hold_w_max_equal_k_times_the_mean():
    s, lines = lines_of(CONFIGS / "rows_fig3_n3_nw3_B2.4.toml", kind="rows")
    K = numbers(lines[0][0].split(" = ")[2])[0]
    w_max, w_mean = (numbers(part)[0] for part in lines[2][0].split(" = ")[2:4])
    assert K == six(s["K"]) and w_max == six(K * w_mean)
    assert numbers(lines[1][0])[-3:] == [six(s["K_stepwise"]), six(s["K_exact"]), six(s["K_continuous"])]


def test_an_unknown_kind_has_no_method_lines():
    rec = types.SimpleNamespace(kind="other", result=types.SimpleNamespace(summary={}, detail={}), design={})
    assert method_lines(rec) == []
