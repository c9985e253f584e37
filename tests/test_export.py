"""gearcalc export: read the file back (ezdxf, an SVG parser, CSV) and check every vertex against the analytic
profile of the physics (gearcalc.pins.geometry.tooth_profile, the circular teeth of circular_profile, the zstk
detail table) within --chord-tol, the closure and the tooth count (issue 38 item 2)."""
import json
import math
import re
import xml.etree.ElementTree as ET

import numpy as np
import pytest

from conftest import CONFIGS, cli

TOL = 1e-3   # the default --chord-tol [mm]


def csv_contours(path):
    out, layer, pts = [], None, []
    for line in path.read_text(encoding="utf-8").splitlines():
        if line.startswith("# "):
            layer, pts = line[2:], []
            out.append((layer, pts))
        elif line and line[0] in "-0123456789":
            pts.append(tuple(map(float, line.split(","))))
    return [(layer, np.array(p)) for layer, p in out]


def dist_to_polyline(q, poly):
    """Distance of each point q (n, 2) from the polyline poly (m, 2): the nearest vertex's two segments."""
    from scipy.spatial import cKDTree

    _, i = cKDTree(poly).query(q)
    best = np.full(len(q), np.inf)
    for j0 in (i - 1, i):
        j0 = np.clip(j0, 0, len(poly) - 2)
        a, b = poly[j0], poly[j0 + 1]
        ab = b - a
        t = np.clip(np.einsum("ij,ij->i", q - a, ab) / np.maximum(np.einsum("ij,ij->i", ab, ab), 1e-300), 0, 1)
        best = np.minimum(best, np.hypot(*(q - a - t[:, None] * ab).T))
    return best


def gear_of(config, sets=()):
    from gearcalc.design import load, parse_set
    from gearcalc.pins.contact_level import gear

    gv = load(str(CONFIGS / config), parse_set(list(sets))).values["gearing"]
    g, Rp = gear(int(gv["satellite_teeth"]), int(gv["pins"]), float(gv["eccentricity_mm"]),
                 gv.get("pin_circle_radius_mm"), gv.get("curtate_ratio"), float(gv["pin_radius_mm"]))
    return g, Rp, gv


def analytic_cycloid(config, sets=()):
    """Dense polylines of every family's curve Gamma_b of the design curve (R_p + dR_p, R_b + dR_b)."""
    from gearcalc.pins.geometry import Cycloid, tooth_profile

    g, Rp, gv = gear_of(config, sets)
    Rp2 = Rp + float(gv.get("radial_mod_mm") or 0.0)
    d = Cycloid.from_pin_circle(g.z1, g.z2, g.e, Rp2, g.R_b + float(gv.get("equidistant_mod_mm") or 0.0))
    beta = np.linspace(0.0, 2.0 * math.pi, 400_001)
    return g, [np.column_stack(tooth_profile(beta, b, d)) for b in range(d.k)]


def crests(pts, centre=(0.0, 0.0)):
    """Local maxima of the radius along a closed contour."""
    r = np.hypot(pts[:-1, 0] - centre[0], pts[:-1, 1] - centre[1])
    return int(np.sum((r > np.roll(r, 1)) & (r >= np.roll(r, -1))))


@pytest.mark.parametrize("config,mods", [("pins_paper_cyc_u10_fixed.toml", ()),
                                         # the other two are long (a dense reference curve each): CI runs them
                                         pytest.param("pins_paper_cyc_u30_fixed.toml", (), marks=pytest.mark.slow),
                                         pytest.param("pins_paper_cyc_u10_fixed.toml",
                                                      ("gearing.equidistant_mod_mm=0.02", "gearing.radial_mod_mm=-0.03",
                                                       "contact.face_width_mm=10"), marks=pytest.mark.slow)])
def test_cycloid_csv_vertices_and_chords_within_tolerance(tmp_path, config, mods):
    out = tmp_path / "p.csv"
    sets = [a for m in mods for a in ("--set", m)]
    r = cli("export", CONFIGS / config, "-o", out, *sets)
    assert r.code == 0, r.err
    cont = dict(csv_contours(out))
    prof = cont["PROFILE"]
    g, fams = analytic_cycloid(config, mods)
    dense = [dist_to_polyline(prof, f) for f in fams]
    vertex_dev = np.min(dense, axis=0).max()
    a, b = prof[:-1], prof[1:]
    inner = np.concatenate([a + q * (b - a) for q in np.linspace(0.1, 0.9, 9)])
    chord_dev = np.min([dist_to_polyline(inner, f) for f in fams], axis=0).max()
    print(f"{config}: vertices {len(prof)}, max vertex deviation {vertex_dev:.3g} mm, max chord deviation "
          f"{chord_dev:.6g} mm")
    assert vertex_dev <= 1e-6                    # every vertex on the analytic curve (dense polyline: ~1e-7 mm)
    assert chord_dev <= TOL * (1 + 1e-3) + 1e-6  # every chord within --chord-tol
    assert np.array_equal(prof[0], prof[-1])     # closed
    assert crests(prof) == g.z1                  # one crest per tooth
    assert cont["CRANK"].tolist() == [[-g.e, 0.0]]
    pc = cont["PIN_CIRCLE"]
    assert np.allclose(np.hypot(pc[:, 0] + g.e, pc[:, 1]), g.R_p, rtol=1e-12, atol=0)


def test_coarser_chord_tol_fewer_vertices(tmp_path):
    fine, coarse = tmp_path / "f.csv", tmp_path / "c.csv"
    assert cli("export", CONFIGS / "pins_paper_cyc_u10_fixed.toml", "-o", fine).code == 0
    assert cli("export", CONFIGS / "pins_paper_cyc_u10_fixed.toml", "-o", coarse, "--chord-tol", "0.01").code == 0
    assert len(dict(csv_contours(coarse))["PROFILE"]) < len(dict(csv_contours(fine))["PROFILE"])


def test_circular_dxf_exact_arcs(tmp_path):
    ezdxf = pytest.importorskip("ezdxf")
    from gearcalc.pins.contact_profiles import circular_profile

    config = "pins_paper_circ_u10_fixed.toml"
    out = tmp_path / "p.dxf"
    r = cli("export", CONFIGS / config, "-o", out)
    assert r.code == 0, r.err
    doc = ezdxf.readfile(str(out))
    assert doc.header["$INSUNITS"] == 4          # mm
    g, Rp, gv = gear_of(config)
    prof, _ = circular_profile(g)
    arcs = [e for e in doc.modelspace() if e.dxf.layer == "PROFILE"]
    teeth = [a for a in arcs if abs(a.dxf.radius - prof.rho_t) < 1e-12]
    assert len(teeth) == g.z1
    for a in teeth:   # on the tooth circle R_t, at an odd multiple of pi/z1
        c = a.dxf.center
        assert abs(math.hypot(c.x, c.y) - prof.R_t) < 1e-9
        m = (math.atan2(c.y, c.x) * g.z1 / math.pi) % 2
        assert abs(m - 1) < 1e-9
    ends = []
    for a in arcs:
        c, rad = a.dxf.center, a.dxf.radius
        ends += [(c.x + rad * math.cos(math.radians(t)), c.y + rad * math.sin(math.radians(t)))
                 for t in (a.dxf.start_angle, a.dxf.end_angle)]
    ends = np.array(ends)
    # closed: every end point meets another arc's end point
    d = np.hypot(*(ends[:, None, :] - ends[None, :, :]).transpose(2, 0, 1)) + np.eye(len(ends)) * 1e9
    assert d.min(axis=1).max() < 1e-9
    circ = [e for e in doc.modelspace() if e.dxf.layer == "PIN_CIRCLE"]
    assert len(circ) == 1 and abs(circ[0].dxf.radius - Rp) < 1e-12 and circ[0].dxf.center.x == -g.e


def test_zstk_svg_and_dxf_match_the_detail(tmp_path):
    ezdxf = pytest.importorskip("ezdxf")
    config = CONFIGS / "zstk_merko_example.toml"
    obj = json.loads(cli("run", config, "--format", "json", "--detail").out)
    s, rows = obj["summary"], obj["detail"]["rollers"]
    e = obj["design"]["geometry"]["eccentricity_mm"]
    want = {("OUTER_RING", 0.0, 0.0, s["outer_raceway_radius_mm"]),
            ("INNER_RING", e, 0.0, s["inner_raceway_radius_mm"])}
    rh = s["outer_raceway_radius_mm"]
    want |= {("ROLLERS", (rh - r["r_mm"]) * math.cos(math.radians(r["theta_deg"])),
              (rh - r["r_mm"]) * math.sin(math.radians(r["theta_deg"])), r["r_mm"]) for r in rows}
    dxf, svg = tmp_path / "z.dxf", tmp_path / "z.svg"
    assert cli("export", config, "-o", dxf).code == 0
    assert cli("export", config, "-o", svg).code == 0
    got = {(c.dxf.layer, c.dxf.center.x, c.dxf.center.y, c.dxf.radius) for c in ezdxf.readfile(str(dxf)).modelspace()}
    assert len(got) == len(want) == s["N"] + 2
    for w in want:
        assert any(g[0] == w[0] and max(abs(a - b) for a, b in zip(g[1:], w[1:])) < 1e-9 for g in got), w
    root = ET.parse(svg).getroot()
    assert root.get("width").endswith("mm")
    paths = root.findall(".//{http://www.w3.org/2000/svg}path")
    assert len(paths) == s["N"] + 2
    for p in paths:   # a full circle as two half arcs: M start A r r 0 0 1 opposite A r r 0 0 1 start Z
        nums = [float(x) for x in re.findall(r"-?\d+\.?\d*(?:e-?\d+)?", p.get("d"))]
        x0, y0, r = nums[0], nums[1], nums[2]
        cx, cy = (x0 + nums[7]) / 2, (y0 + nums[8]) / 2
        assert any(w[0] == p.get("class") and abs(cx - w[1]) < 1e-9 and abs(cy - w[2]) < 1e-9
                   and abs(r - w[3]) < 1e-12 for w in want)


def test_bad_input(tmp_path):
    r = cli("export", CONFIGS / "rows_fig3_n3_nw3_B2.4.toml", "-o", tmp_path / "x.svg")
    assert r.code == 2 and "pins and zstk" in r.err
    r = cli("export", CONFIGS / "pins_paper_formula_cyc_u10.toml", "-o", tmp_path / "x.svg")
    assert r.code == 2 and "[gearing]" in r.err and not (tmp_path / "x.svg").exists()
    r = cli("export", CONFIGS / "zstk_merko_example.toml", "-o", tmp_path / "x.png")
    assert r.code == 2 and "FILE.dxf" in r.err
    r = cli("export", CONFIGS / "zstk_merko_example.toml", "-o", tmp_path / "x.svg", "--chord-tol", "0")
    assert r.code == 2 and "--chord-tol" in r.err


def test_cycloid_dxf_and_svg_read_back(tmp_path):
    """The DXF polyline (ezdxf) and the SVG path (xml.etree) hold the same vertices, on the analytic curve."""
    ezdxf = pytest.importorskip("ezdxf")
    config = "pins_paper_cyc_u10_fixed.toml"
    dxf, svg = tmp_path / "p.dxf", tmp_path / "p.svg"
    assert cli("export", CONFIGS / config, "-o", dxf).code == 0
    assert cli("export", CONFIGS / config, "-o", svg).code == 0
    doc = ezdxf.readfile(str(dxf))
    assert doc.header["$INSUNITS"] == 4
    (poly,) = [e for e in doc.modelspace() if e.dxf.layer == "PROFILE"]
    assert poly.closed
    pd = np.array([(x, y) for x, y, *_ in poly.get_points()])
    path = next(p for p in ET.parse(svg).getroot().iter("{http://www.w3.org/2000/svg}path")
                if p.get("class") == "PROFILE")
    d = path.get("d")
    assert d.startswith("M ") and d.endswith(" Z")
    ps = np.array(re.findall(r"[ML] (\S+) (\S+)", d), dtype=float)
    g, fams = analytic_cycloid(config)
    for name, pts in (("dxf", pd), ("svg", ps)):
        dev = np.min([dist_to_polyline(pts, f) for f in fams], axis=0).max()
        print(f"{name}: {len(pts)} vertices, max vertex deviation {dev:.3g} mm")
        assert dev <= 1e-6
        assert crests(np.vstack([pts, pts[:1]])) == g.z1
    assert np.allclose(pd, ps[:len(pd)], rtol=0, atol=1e-12)
