"""gearcalc.pins.checks: the pins calculator's validity rules, each written once (issue 14), against the
numbers and tables of the specification.

Every expected value names its source on its line: pins.md sections, the schema's budgets, or an independent
evaluation of the formula the rule states.
"""
import math

import numpy as np
import pytest

from gearcalc.pins import checks as C
from gearcalc.pins.ideal import TOO_FEW_TEETH, UNDERCUT
from gearcalc.pins.schema import (CONTACT_NODES_MAX, CONTACT_WORK_MAX, GROUP_PINS_MAX, GROUP_TOL_MIN,
                                  IDEAL_SWEEP_WORK_MAX, IDEAL_WORK_MAX)

PAPER = dict(z1=20, z2=22, e=3.9, Rp=None, K1=0.75, Rb=1.95)   # configs/pins_paper_cyc_u10_fixed.toml


@pytest.mark.parametrize("model, alias, expected", [
    (None, None, ("consistent", False)),            # pins.md §7: neither given: the default
    ("first-order", None, ("first-order", False)),
    (None, True, ("consistent", False)),            # pins.md §7: the alias true = "consistent"
    (None, False, ("first-order", False)),          # pins.md §7: the alias false = "first-order"
    ("consistent", True, ("consistent", False)),
    ("first-order", True, ("consistent", True)),    # contradiction: the alias wins, flagged
    ("consistent", False, ("first-order", True)),
])
def test_friction_model_and_its_alias(model, alias, expected):
    assert C.friction_model(model, alias, "consistent") == expected


def test_the_default_friction_model_applies_only_when_neither_key_is_given():
    assert C.friction_model(None, None, "first-order") == ("first-order", False)
    assert C.friction_model(None, True, "first-order") == ("consistent", False)


@pytest.mark.parametrize("model, tables, profile, modified, expected", [
    (None, {"pin_load"}, None, False, ("formula", None)),                      # pins.md §3: no gear
    (None, {"gearing", "load"}, "cycloidal", False, ("ideal", None)),          # pins.md §4
    (None, {"gearing", "load"}, "circular", False, ("contact", None)),         # pins.md §5.3
    (None, {"gearing", "load"}, "cycloidal", True, ("contact", None)),         # pins.md §5.2: modified
    (None, {"gearing", "load", "contact"}, "cycloidal", False, ("contact", None)),   # a contact law given
    (None, {"gearing", "pin_load"}, "cycloidal", False, ("ideal", None)),      # the gear wins over [pin_load]
    ("formula", {"gearing"}, "cycloidal", False, ("formula", "need_pin_load")),
    ("ideal", {"pin_load"}, None, False, ("ideal", "need_gearing")),
    ("contact", {"pin_load"}, None, False, ("contact", "need_gearing")),
    ("ideal", {"gearing"}, "circular", False, ("ideal", "ideal_profile")),     # no conjugate profile
    ("ideal", {"gearing"}, "circular", True, ("ideal", "ideal_profile")),      # the profile is named first
    ("ideal", {"gearing"}, "cycloidal", True, ("ideal", "ideal_mods")),
    ("contact", {"gearing"}, "cycloidal", False, ("contact", None)),           # any gear runs at contact
    ("formula", {"gearing", "pin_load"}, "circular", False, ("formula", None)),
])
def test_select_level(model, tables, profile, modified, expected):
    assert C.select_level(model, tables, profile, modified) == expected


def test_every_rule_name_has_a_message():
    from gearcalc.pins.report import PROBLEMS

    rules = {"need_pin_load", "need_gearing", "ideal_profile", "ideal_mods", "face_width", "stiffness", "no_tables",
             "pin_load_axle", "no_load", "no_sliding", "teeth", "one_circle", "overflow", "curtate_K1", "curtate_Rp",
             "overlap", "no_axle", "axle", "tooth_too_large", "friction_alias"}
    assert rules <= set(PROBLEMS)


@pytest.mark.parametrize("law, b, k, expected", [
    ("hertz", None, None, "face_width"), ("palmgren", None, 1e5, "face_width"),   # pins.md §5.4: b needed
    ("hertz", 10.0, None, None), ("linear", 10.0, None, "stiffness"),             # k_lin needed
    ("linear", None, 1e5, None),
])
def test_contact_law_problem(law, b, k, expected):
    assert C.contact_law_problem(law, b, k) == expected


def test_modified():
    assert C.modified(0.0, 0.0) is False and C.modified(0.0, -0.1) is True and C.modified(1e-9, 0.0) is True


def test_pin_circle_curtate_from_either_given():
    Rp, K1, omk = C.pin_circle_curtate(20, 22, 3.9, None, 0.75)
    assert math.isclose(Rp, 3.9 * 22 / (2 * 0.75), rel_tol=1e-15)    # pins.md §4.1: R_p = e z2/(k K1)
    assert (K1, omk) == (0.75, 0.25)                                  # K1 as given, 1 - K1
    Rp, K1, omk = C.pin_circle_curtate(20, 22, 3.9, 57.2, None)
    assert Rp == 57.2 and math.isclose(K1, 3.9 * 22 / (2 * 57.2), rel_tol=1e-15)   # K1 = e z2/(k R_p)
    assert math.isclose(omk, 1 - K1, rel_tol=1e-14)


def _gear(p) -> C.GearGiven:
    return C.GearGiven(**{f: p[f] for f in ("z1", "z2", "e", "Rp", "K1", "Rb", "r", "rotating", "profile")})


def _violations(**over):
    p = dict(z1=[20], z2=[22], e=[3.9], Rp=[None], K1=[0.75], Rb=[1.95], r=[0.95], rotating=[False],
             profile=["cycloidal"], sliding=[0.1], load_pin_radius=[None], load_axle_radius=[None])
    p.update(over)
    return C.violations(_gear(p), p["sliding"], C.PinLoadGiven(p["load_pin_radius"], p["load_axle_radius"]))


def test_violations_at_the_pin_overlap_limit():
    limit = 57.2 * math.sin(math.pi / 22)                 # pins.md §7: R_b < R_p sin(pi/z2) = 8.14041 mm
    ok = _violations(Rb=[limit * (1 - 1e-9)], K1=[None], Rp=[57.2])
    bad = _violations(Rb=[limit * (1 + 1e-9)], K1=[None], Rp=[57.2])
    assert not ok.geometry.overlap[0] and bad.geometry.overlap[0]
    assert math.isclose(float(bad.geometry.overlap_limit[0]), limit, rel_tol=1e-15)


def test_violations_of_the_cross_key_rules():
    v = _violations(Rp=[57.2], K1=[0.75], sliding=[None], rotating=[True], r=[None], load_pin_radius=[1.95],
                    load_axle_radius=[1.95])
    assert v.one_circle[0] and v.no_sliding[0] and v.no_axle[0]        # pins.md §7: both circles, no f, no r
    assert v.pin_load_axle[0]                                           # pins.md §3: r < R (here r = R)
    v = _violations(Rp=[None], K1=[None])
    assert v.one_circle[0]                                              # neither given
    v = _violations(load_pin_radius=[1.95], load_axle_radius=[0.95])
    assert not (v.one_circle[0] or v.no_sliding[0] or v.no_axle[0] or v.pin_load_axle[0] or v.geometry.any()[0])


def test_violations_over_many_points_equal_each_point_alone():
    Rb = [1.0, 1.95, 9.0, 4.0]
    many = _violations(z1=[20] * 4, z2=[22] * 4, e=[3.9] * 4, Rp=[None] * 4, K1=[0.75, 1.2, 0.75, 0.75], Rb=Rb,
                       r=[0.5, 0.95, 0.95, 5.0], rotating=[True] * 4, profile=["cycloidal"] * 4, sliding=[0.1] * 4,
                       load_pin_radius=[None] * 4, load_axle_radius=[None] * 4)
    for i in range(4):
        one = _violations(K1=[[0.75, 1.2, 0.75, 0.75][i]], Rb=[Rb[i]], r=[[0.5, 0.95, 0.95, 5.0][i]], rotating=[True])
        for name in ("curtate", "overlap", "axle", "teeth"):
            assert getattr(many.geometry, name)[i] == getattr(one.geometry, name)[0], (i, name)
    assert many.geometry.curtate.tolist() == [False, True, False, False]    # pins.md §7: K1 < 1
    assert many.geometry.overlap.tolist() == [False, False, True, False]    # 9 >= 8.14041
    assert many.geometry.axle.tolist() == [False, False, False, True]       # r < R_b: 5 >= 4


def _problems(bad, tables=("gearing", "load"), **over):
    p = dict(PAPER, r=None, rotating=False, profile="cycloidal", tooth_radius="full",
             tooth_circle_radius="zero_backlash", is_modified=False, load_pin_radius=None, load_axle_radius=None)
    p.update(over)
    found = C.design_problems(bad, set(tables), _gear(p), C.PinLoadGiven(p["load_pin_radius"], p["load_axle_radius"]),
                              p["tooth_radius"], p["tooth_circle_radius"], p["is_modified"])
    return [(s, rule) for s, rule, _ in found]


def test_design_problems_in_the_order_check_reports_them():
    assert _problems(_violations(), ()) == [("error", "no_tables")]
    assert _problems(_violations()) == []
    assert _problems(_violations(sliding=[None]), ("gearing",)) == [("error", "no_load"), ("error", "no_sliding")]
    assert _problems(_violations(K1=[1.2]), K1=1.2) == [("error", "curtate_K1")]
    bad = _violations(K1=[None], Rp=[5.0], Rb=[2.75])     # K1 = 3.9*22/(2*5) = 8.58 >= 1, R_b >= 5 sin(pi/22)
    assert _problems(bad, K1=None, Rp=5.0, Rb=2.75) == [("error", "curtate_Rp"), ("error", "overlap")]
    assert _problems(_violations(z2=[20]), z2=20) == [("error", "teeth")]


def test_a_curtate_ratio_that_overflows_the_pin_circle_ends_the_list():
    bad = _violations(K1=[5e-324], Rb=[100.0])          # R_p = e z2/(k K1) = inf: no rule after it is evaluable
    assert bad.geometry.overflow[0]
    assert _problems(bad, K1=5e-324, Rb=100.0, rotating=True, r=200.0) == [("error", "overflow")]


@pytest.mark.parametrize("K1", [1e308, 1.7976931348623157e308])
def test_a_curtate_ratio_so_large_that_k_K1_overflows_is_refused_not_a_crash(K1, tmp_path):
    # issue 34: K1 = 1e308 with k = 2 made k*K1 = inf, R_p = 0 and a ZeroDivisionError (exit 70, `check` too).
    # pins.md §9: "K1 = e·z2/(k·R_p) must be < 1", naming gearing.curtate_ratio, in check and run alike
    Rp, K1_, omk = C.pin_circle_curtate(20, 22, 3.9, None, K1)
    assert Rp == 0.0 and K1_ == K1 and omk == 1.0 - K1               # R_p = e z2/(k K1) underflows to 0
    from conftest import CONFIGS, cli

    design = CONFIGS / "pins_paper_cyc_u30_fixed.toml"
    for cmd in ("check", "pins"):
        r = cli(cmd, design, "--set", f"gearing.curtate_ratio={K1!r}")
        assert r.code == 2 and "gearing.curtate_ratio" in r.err and "must be < 1" in r.err, (cmd, r)
        assert "internal error" not in r.err, r


def test_design_problems_of_the_circular_profile_and_its_warnings():
    # pins.md §5.3: R_b + rho_t < R_p - e, with R_p = e z2/(k K1) = 57.2 mm: 1.95 + 51.4 > 53.3
    assert _problems(_violations(profile=["circular"]), profile="circular", tooth_radius=51.4) == \
        [("error", "tooth_too_large")]
    assert _problems(_violations(profile=["circular"]), profile="circular", tooth_radius=51.3) == []
    assert _problems(_violations(), tooth_radius=3.0, tooth_circle_radius=40.0) == \
        [("warn", "circular_only"), ("warn", "circular_only")]
    assert _problems(_violations(profile=["circular"]), profile="circular", is_modified=True) == \
        [("warn", "cycloid_mods_ignored")]


def test_ideal_admissibility():
    assert C.ideal_admissibility(**PAPER)[0] == 0
    status, psi_star, _, _ = C.ideal_admissibility(3, 12, 1.0, None, 0.75, 0.5)   # tests/pins/test_geometry.py's gear
    assert status == TOO_FEW_TEETH and psi_star <= 2 * math.pi / 12   # pins.md §12.10: psi* <= 2 pi/z2
    status, _, rho_c, K1 = C.ideal_admissibility(**dict(PAPER, K1=0.999999))
    assert status == UNDERCUT and 1.95 >= rho_c and K1 == pytest.approx(0.999999, rel=1e-12)   # pins.md §4.2


def test_cost_budgets_at_their_limits():
    assert not C.ideal_over_budget(IDEAL_WORK_MAX, 1) and C.ideal_over_budget(IDEAL_WORK_MAX + 1, 1)
    assert C.ideal_over_budget(np.array([10_000, 10_000]), np.array([20, 21])).tolist() == [False, True]
    z2_H = CONTACT_WORK_MAX // (CONTACT_NODES_MAX * 3)      # schema.CONTACT_WORK_MAX: 114 pins on H, 344 on V
    z2_V = CONTACT_WORK_MAX // CONTACT_NODES_MAX
    assert (z2_H, z2_V) == (114, 344)
    assert (C.contact_pins_max(False), C.contact_pins_max(True)) == (z2_H, z2_V)   # the bound its message names
    assert not C.contact_over_budget(z2_H, False) and C.contact_over_budget(z2_H + 1, False)
    assert not C.contact_over_budget(z2_V, True) and C.contact_over_budget(z2_V + 1, True)
    assert not C.computed_alone(GROUP_PINS_MAX, 1, GROUP_TOL_MIN) and C.computed_alone(GROUP_PINS_MAX + 1, 1, 1e-6)
    assert C.computed_alone(22, 1, GROUP_TOL_MIN / 10)


def test_points_pass():
    n = 3
    pts = dict(z1=[20] * n, z2=[22] * n, n_d=[1] * n, e=[3.9] * n, Rb=[1.95] * n, K1=[0.5, 0.75, 0.9], Rp=[None] * n)
    ok = _violations(**{k: v for k, v in pts.items() if k != "n_d"}, r=[None] * n, rotating=[False] * n,
                     profile=["cycloidal"] * n, sliding=[0.1] * n, load_pin_radius=[None] * n,
                     load_axle_radius=[None] * n)

    def gear(p):
        return _gear(dict(p, r=[None] * n, rotating=[False] * n, profile=["cycloidal"] * n))

    assert C.points_pass(ok, False, False, gear(pts), pts["n_d"])
    assert not C.points_pass(ok, False, False, gear(pts), [1, 1, 10_000])   # z2 n_d over budget
    big = dict(pts, z2=[IDEAL_SWEEP_WORK_MAX // 2 + 1] * n, z1=[IDEAL_SWEEP_WORK_MAX // 2] * n)
    assert not C.points_pass(ok, False, False, gear(big), big["n_d"])   # sum of z2 n_d over the distinct geometries
    curtate = _violations(K1=[0.75, 1.2, 0.75])
    assert not C.points_pass(curtate, False, False, gear(dict(pts, K1=[0.75, 1.2, 0.75])), pts["n_d"])
    assert C.points_pass(curtate, True, False, gear(pts), pts["n_d"])   # the formula level: only the [pin_load] rule


def test_the_rule_and_word_functions_are_small():
    # issue 35 (benchmarks/code_shape.py's counts): at most 8 parameters and 80 lines per function of the pins
    # rules (checks), words (report), figure (plot) and geometry_violations
    import ast
    import pathlib

    import gearcalc

    pins = pathlib.Path(gearcalc.__file__).parent / "pins"
    for module in ("checks", "report", "plot", "geometry"):
        for node in ast.walk(ast.parse((pins / f"{module}.py").read_text(encoding="utf-8"))):
            if not isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                continue
            if module == "geometry" and node.name != "geometry_violations":
                continue               # the rest of geometry.py is another change's
            a = node.args
            params = len(a.posonlyargs) + len(a.args) + len(a.kwonlyargs) + (a.vararg is not None) + (
                a.kwarg is not None)
            assert params <= 8, (module, node.name, params)
            assert node.end_lineno - node.lineno + 1 <= 80, (module, node.name)


def test_the_rules_know_no_design_key():
    # issue 35 item 2: the physics names no design-file key; the keys are the adapter's (kinds/pins.py KEYS) and
    # the report's words (e.g. the level's reason, report.LEVEL_REASONS)
    import ast
    import inspect

    from gearcalc.kinds.pins import KEYS

    tree = ast.parse(inspect.getsource(C))
    docstrings = {id(n.value) for n in ast.walk(tree) if isinstance(n, ast.Expr)}   # the documentation's words
    texts = [n.value for n in ast.walk(tree)
             if isinstance(n, ast.Constant) and isinstance(n.value, str) and id(n) not in docstrings]
    for key in KEYS.values():
        name = key.partition(".")[2]
        with_unit = any(unit in name for unit in ("_mm", "_N", "_MPa", "_rpm"))   # e.g. stiffness_N_per_mm
        assert not any(key in t or (with_unit and name in t) for t in texts), key
