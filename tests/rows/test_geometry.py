"""Tests of gearcalc.rows.geometry: the dimensions and validity rules (rows.md §1 "Notation", §2.4, §7, §10).

Expected values come from the spec's formulas written out here; the batch (array) results must equal the
one-design (float) results bit for bit, since check, compute and the sweep call the same functions.
"""
import math
import subprocess
import sys

import numpy as np
import pytest

from gearcalc.rows import geometry as G

ALPHA = math.radians(20.0)


@pytest.mark.parametrize("given", ["B, b̄", "B, b", "b_w, b̄", "b_w, b"])
def test_face_geometry_follows_rows_md_7(given):
    # rows.md §7: d_a = z_a m, b_w = B d_a/(n + b̄(n-1)), b = b̄ b_w; b_a = n b_w + (n-1) b = B d_a
    n, d_a = 3, 90.0
    kw = {"B, b̄": dict(relative_width=2.4, cheek_ratio=0.25), "B, b": dict(relative_width=2.4, cheek=15.0),
          "b_w, b̄": dict(rim_width=60.0, cheek_ratio=0.25), "b_w, b": dict(rim_width=60.0, cheek=15.0)}[given]
    f = G.face_geometry(18, 5.0, n, ALPHA, **kw)
    assert f.sun_diameter == d_a and f.root_diameter == d_a - 2.5 * 5.0            # rows.md §1
    assert f.base_radius == pytest.approx(0.5 * d_a * math.cos(ALPHA), rel=1e-15)
    assert f.cheek == pytest.approx(f.cheek_ratio * f.rim_width, rel=1e-15)
    assert n * f.rim_width + (n - 1) * f.cheek == pytest.approx(f.relative_width * d_a, rel=1e-14)
    if "cheek" in kw:
        assert f.cheek == pytest.approx(15.0, rel=1e-14)


def test_face_geometry_batch_equals_one_design_bit_for_bit():
    rng = np.random.default_rng(3)
    za, m, n = rng.integers(3, 80, 200), rng.uniform(0.5, 10, 200), rng.integers(1, 12, 200)
    alpha, B, bbar = np.radians(rng.uniform(1, 44.9, 200)), rng.uniform(0.1, 5, 200), rng.uniform(0, 1, 200)
    batch = G.face_geometry(za.astype(float), m, n, alpha, relative_width=B, cheek_ratio=bbar)
    for k in range(200):
        one = G.face_geometry(int(za[k]), float(m[k]), int(n[k]), float(alpha[k]), relative_width=float(B[k]),
                              cheek_ratio=float(bbar[k]))
        for name in ("sun_diameter", "root_diameter", "rim_width", "cheek_ratio", "cheek", "relative_width",
                     "base_radius"):
            assert getattr(one, name) == getattr(batch, name)[k]
            assert type(getattr(one, name)) is float    # a float design stays in Python floats


def test_cos_of_a_float_equals_numpy_on_the_pressure_angle_range():
    # the float path (math) and the array path (numpy) of base_radius agree bit for bit on 1 <= alpha_w < 45 deg
    alpha = np.radians(np.arange(1.0, 45.0, 1e-4))
    assert np.array_equal(G.base_radius(1.0, alpha), np.array([G.base_radius(1.0, float(a)) for a in alpha]))


def test_no_room_for_the_rims():
    # rows.md §7: b_w = (B d_a - (n-1) b)/n <= 0 -> the cheeks leave no room; b̄ is infinite there, never an error
    f = G.face_geometry(18, 5.0, 2, ALPHA, relative_width=1.0, cheek=90.0)
    assert f.rim_width == 0.0 and f.cheek_ratio == math.inf and not G.rims_fit(f.rim_width)
    b_w = G.rim_width_from_cheek(np.array([1.0, 2.4]), 2, 90.0, 90.0)
    assert G.rims_fit(b_w).tolist() == [False, True]
    assert G.cheek_ratio_of(90.0, b_w).tolist() == [math.inf, 90.0 / 63.0]   # b_w = (216 - 90)/2 = 63


def test_torsion_diameter_readings():
    # rows.md §2.4: "pitch" -> d_a, "root" -> d_f, or a diameter in mm; a list gives one reading per point
    assert G.torsion_diameter("pitch", 90.0, 77.5) == 90.0 and G.torsion_diameter("root", 90.0, 77.5) == 77.5
    assert G.torsion_diameter(80, 90.0, 77.5) == 80.0
    d = G.torsion_diameter(["root", 70.0, "pitch"], np.array([90.0, 90.0, 95.0]), np.array([77.5, 77.5, 82.5]))
    assert d.tolist() == [77.5, 70.0, 95.0]
    with pytest.raises(ValueError, match="pitch"):
        G.torsion_diameter("tip", 90.0, 77.5)


def test_validity_rules_floats_and_arrays_alike():
    # rows.md §10: d_0 < min(d_f, d_I); rim under the roots >= 2.7 m; adjacency z_g + 2 < (z_a + z_g) sin(pi/n_w)
    bore = np.array([0.0, 60.0, 77.5, 80.0])
    assert G.bore_fits(bore, 77.5, 90.0).tolist() == [True, True, False, False]
    assert [G.bore_fits(float(b), 77.5, 90.0) for b in bore] == [True, True, False, False]
    assert G.bore_fits(70.0, 77.5, 65.0) is False
    assert G.rim_too_thin(77.5, bore, 5.0).tolist() == [False, True, True, True]   # (77.5 - 60)/2 = 8.75 < 13.5
    assert G.rim_too_thin(77.5, 40.0, 5.0) is False                                # 18.75 mm
    z_g = np.array([9.0, 36.0, 36.0])
    n_w = np.array([3, 3, 5])
    want = [bool(n >= 2 and z + 2 >= (18 + z) * math.sin(math.pi / n)) for z, n in zip(z_g, n_w)]
    assert G.planets_collide(18, z_g, n_w).tolist() == want == [False, False, True]
    assert G.planets_collide(18, 36.0, 1) is False


def test_ratio_and_planet_teeth_are_inverse():
    # rows.md §5.4: i = 2 + 2 z_g/z_a, z_g = z_a (i - 2)/2
    assert G.ratio_from_planet_teeth(27, 18) == 5.0 and G.planet_teeth(5.0, 18) == 27.0


def test_defaults_of_the_stiffness_and_sections():
    # rows.md §2.2: C = 0.075 E [paper]; §7: d = h = 0.5 b_w; G = E/(2(1+nu))
    assert G.mesh_stiffness(2e5) == 0.075 * 2e5 and G.DEFAULT_SECTION_PER_RIM == 0.5
    assert G.shear_modulus(2e5, 0.3) == 2e5 / 2.6


def test_check_imports_no_numpy():
    # the geometry module and the adapter's check need no numpy: `gearcalc check` stays light
    code = ("import sys\nfrom gearcalc.design import load\n"
            "d = load('configs/rows_bridges_n4_B4_i6.toml')\n"
            "assert 'numpy' not in sys.modules, 'numpy imported'\nprint('ok')")
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=str(_root()))
    assert p.stdout.strip() == "ok", p.stderr


def _root():
    from pathlib import Path

    return Path(__file__).resolve().parents[2]
