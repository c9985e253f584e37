"""``gearcalc export FILE -o profile.dxf|.svg|.csv``: the geometry to manufacture, in mm.

pins: the satellite's tooth profile as made (layer ``PROFILE``; cycloidal with its equidistant and radial
modifications, or circular-arc teeth), the pin circle (``PIN_CIRCLE``) and the crank centre (``CRANK``), in the
satellite's frame at the nominal pose (satellite centre at the origin, pin 0 on +x, crank centre at (-e, 0)).
zstk: the rings (``OUTER_RING``, ``INNER_RING``) and the rollers (``ROLLERS``) at the reported placement (outer
ring centred at the origin, inner ring at (e, 0), the rollers at the angles of the result's ``rollers`` table).

Curves are polylines whose chords stay within ``chord_tol`` of the curve (adaptive subdivision, every vertex on
the curve); arcs and circles are exact arcs in DXF and SVG (polylines in CSV, by the same tolerance).
ezdxf (the ``dxf`` extra) is imported only for DXF; SVG is written here; CSV has one ``x,y`` row per vertex,
closed contours repeating their first vertex, a blank line between contours, a ``# layer`` line before each.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

FORMATS = (".dxf", ".svg", ".csv")
DXF_HINT = "DXF needs ezdxf: pip install 'gearcalc[dxf]' (or write FILE.svg / FILE.csv)"
MAX_LEVELS = 40
"""Subdivision rounds at most (each halves the parameter step of the segments still too far from the curve)."""
START_SEGMENTS = 16
"""Segments of the first subdivision of each curve."""


class ExportError(ValueError):
    """The design cannot be exported (its kind has no geometry, an inadmissible profile, no ezdxf for DXF)."""


@dataclass
class Arc:
    """A circle arc of radius r about (cx, cy) from angle a0 to a1 [rad] counter-clockwise (a full circle:
    a1 - a0 = 2 pi)."""

    cx: float
    cy: float
    r: float
    a0: float = 0.0
    a1: float = 2.0 * math.pi

    @property
    def full(self) -> bool:
        return self.a1 - self.a0 >= 2.0 * math.pi - 1e-15

    def points(self, tol: float) -> np.ndarray:
        """Vertices on the arc, chords within ``tol`` of it (the sagitta r (1 - cos(h/2)) <= tol)."""
        span = self.a1 - self.a0
        half = math.acos(max(-1.0, 1.0 - tol / self.r)) if tol < 2 * self.r else math.pi
        n = max(4 if self.full else 1, math.ceil(span / (2.0 * half)))
        t = self.a0 + span * np.arange(n + 1) / n
        return np.column_stack([self.cx + self.r * np.cos(t), self.cy + self.r * np.sin(t)])


@dataclass
class Curve:
    """A parametric curve f(t) -> (x, y) on [t0, t1], drawn as a polyline by :func:`subdivide`."""

    f: object
    t0: float
    t1: float


@dataclass
class Entity:
    """One contour of the drawing: pieces (Arc or Curve) joined end to end, on a layer; closed or not."""

    layer: str
    pieces: list
    closed: bool = True


@dataclass
class Drawing:
    """What export writes; ``teeth``: the satellite's tooth count (pins), for the checks."""

    entities: list = field(default_factory=list)
    points: list = field(default_factory=list)   # (layer, x, y)
    teeth: int | None = None


def subdivide(f, t0: float, t1: float, tol: float) -> tuple[np.ndarray, np.ndarray]:
    """(parameters, vertices) of a polyline on the curve f whose chords are within ``tol`` of it: each segment is
    split at its middle while the curve at 1/4, 1/2 or 3/4 of it is farther than ``tol`` from the chord
    (vectorised: one round splits every segment still too far)."""
    t = np.linspace(t0, t1, START_SEGMENTS + 1)
    for _ in range(MAX_LEVELS):
        x, y = f(t)
        a = np.column_stack([x, y])
        d = a[1:] - a[:-1]
        length = np.hypot(d[:, 0], d[:, 1])
        worst = np.zeros(len(d))
        for q in (0.25, 0.5, 0.75):
            mx, my = f(t[:-1] + q * np.diff(t))
            rx, ry = mx - a[:-1, 0], my - a[:-1, 1]
            dev = np.abs(rx * d[:, 1] - ry * d[:, 0]) / np.where(length > 0, length, 1.0)
            worst = np.maximum(worst, np.where(length > 0, dev, np.hypot(rx, ry)))
        split = worst > tol
        if not split.any():
            return t, a
        mids = (t[:-1] + 0.5 * np.diff(t))[split]
        t = np.sort(np.concatenate([t, mids]))
    raise ExportError(f"the profile could not be drawn within --chord-tol {tol:g} mm")


def contour_points(e: Entity, tol: float) -> np.ndarray:
    """The vertices of a contour (closed: the first vertex repeated at the end)."""
    parts = []
    for p in e.pieces:
        pts = p.points(tol) if isinstance(p, Arc) else subdivide(p.f, p.t0, p.t1, tol)[1]
        parts.append(pts if not parts else pts[1:])
    pts = np.concatenate(parts)
    if e.closed:
        pts[-1] = pts[0]  # the same point up to round-off: exactly closed
    return pts


# --- the kinds' geometry -------------------------------------------------------------------------------------------

def drawing(design, chord_tol: float) -> Drawing:
    """The drawing of a validated design (pins or zstk)."""
    if design.kind == "pins":
        return _pins(design)
    if design.kind == "zstk":
        return _zstk(design)
    raise ExportError(f"export draws pins and zstk designs; a {design.kind} design has no profile to export")


def _rot(x, y, a):
    c, s = math.cos(a), math.sin(a)
    return c * x - s * y, s * x + c * y


def _pins(design) -> Drawing:
    from .pins.contact_level import gear, satellite_profile
    from .pins.contact_profiles import InadmissibleProfile

    if "gearing" not in design.values:
        raise ExportError("no [gearing] table (a formula-level design of one pin's load): no profile to export")
    gv = design.values["gearing"]
    z1, z2, e = int(gv["satellite_teeth"]), int(gv["pins"]), float(gv["eccentricity_mm"])
    g, Rp = gear(z1, z2, e, gv.get("pin_circle_radius_mm"), gv.get("curtate_ratio"), float(gv["pin_radius_mm"]))
    try:
        prof, _ = satellite_profile(g, gv["profile"], gv.get("tooth_radius_mm", "full"),
                                    gv.get("tooth_circle_radius_mm", "zero_backlash"),
                                    float(gv.get("radial_mod_mm") or 0.0), float(gv.get("equidistant_mod_mm") or 0.0))
    except InadmissibleProfile as exc:
        raise ExportError(f"gearing.profile: {exc}") from None
    out = Drawing(teeth=z1)
    if gv["profile"] == "circular":
        out.entities.append(Entity("PROFILE", circular_pieces(z1, prof.rho_t, prof.R_t)))
    else:
        out.entities.append(Entity("PROFILE", cycloid_pieces(prof.design)))
    out.entities.append(Entity("PIN_CIRCLE", [Arc(-e, 0.0, Rp)]))
    out.points.append(("CRANK", -e, 0.0))
    return out


def cycloid_pieces(d) -> list:
    """The satellite of the (modified) cycloid ``d`` (:class:`gearcalc.pins.geometry.Cycloid`, its R_p and R_b the
    design curve's): z1 tooth spaces, each Gamma_0 of family 0 turned to 2 pi m/z1 (the tooth spaces are turned
    copies of one another, each symmetric about its axis), from crest to crest; a crest lies on the bisector
    pi/z1 from its tooth space's axis (for k >= 2 where two families' curves cross: pins.md §4.3)."""
    from .pins.geometry import tooth_profile

    half = crest_parameter(d)
    pieces = []
    for m in range(d.z1):
        a = 2.0 * math.pi * m / d.z1

        def f(t, a=a):
            x, y = tooth_profile(t, 0, d)
            return _rot(x, y, a)

        pieces.append(Curve(f, -half, half))
    return pieces


def crest_parameter(d) -> float:
    """beta* > 0 at which Gamma_0(beta) reaches the bisector's polar angle pi/z1 (the crest): pi/z1 for k = 1,
    else the first crossing, by a scan and bisection."""
    from .pins.geometry import tooth_profile

    target = math.pi / d.z1
    if d.k == 1:
        return target

    def h(t):
        x, y = tooth_profile(t, 0, d)
        return np.arctan2(y, x) - target

    grid = np.linspace(0.0, 2.0 * math.pi * d.k / d.z1, 4097)[1:]
    v = h(grid)
    idx = np.flatnonzero(v >= 0.0)
    if not len(idx):
        raise ExportError("no crest found for the cycloidal profile")
    lo, hi = (grid[idx[0] - 1] if idx[0] else 0.0), grid[idx[0]]
    for _ in range(80):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if h(mid) < 0.0 else (lo, mid)
    return 0.5 * (lo + hi)


def circular_pieces(z1: int, rho: float, Rt: float) -> list:
    """Circular-arc teeth: z1 tooth circles (radius rho about R_t u((2m+1) pi/z1)); each tooth's outer arc, from
    where it meets its neighbour (overlapping or tangent teeth, on the bisector) or else the root circle
    sqrt(R_t^2 - rho^2) (the circle through the points where a ray from the centre touches a tooth), joined by
    root arcs.  Exact arcs."""
    s = math.sin(math.pi / z1)
    if rho >= Rt * s:   # teeth meet on the bisectors: rho sin(phi - pi/z1) = R_t sin(pi/z1), the outer root
        phi0 = math.pi / z1 + math.pi - math.asin(min(1.0, Rt * s / rho))
        r0 = None
    else:
        phi0 = math.acos(-rho / Rt)
        r0 = math.sqrt(Rt * Rt - rho * rho)
    pieces = []
    for m in range(z1):
        a = (2 * m + 1) * math.pi / z1
        pieces.append(Arc(Rt * math.cos(a), Rt * math.sin(a), rho, a - phi0, a + phi0))
        if r0 is not None:
            end = math.atan2(*reversed(_rot(Rt + rho * math.cos(phi0), rho * math.sin(phi0), a)))
            nxt = a + 2 * math.pi / z1
            start = math.atan2(*reversed(_rot(Rt + rho * math.cos(-phi0), rho * math.sin(-phi0), nxt)))
            end = end % (2 * math.pi)
            start = end + ((start - end) % (2 * math.pi))
            pieces.append(Arc(0.0, 0.0, r0, end, start))
    return pieces


def _zstk(design) -> Drawing:
    from .calculator import Options
    from .engine import compute_one

    result, lines, status = compute_one(design, Options(detail=True))
    if result is None:
        raise ExportError("; ".join(lines) or "the design could not be computed")
    s, rows = result.summary, result.detail["rollers"]
    rh, rb = float(s["outer_raceway_radius_mm"]), float(s["inner_raceway_radius_mm"])
    e = float(design.values["geometry"]["eccentricity_mm"])
    out = Drawing()
    out.entities.append(Entity("OUTER_RING", [Arc(0.0, 0.0, rh)]))
    out.entities.append(Entity("INNER_RING", [Arc(e, 0.0, rb)]))
    for row in rows:   # the figure's placement (gearcalc/zstk/figure.py): centre at (R_H - r_i) u(theta_i)
        th, r = math.radians(row["theta_deg"]), float(row["r_mm"])
        out.entities.append(Entity("ROLLERS", [Arc((rh - r) * math.cos(th), (rh - r) * math.sin(th), r)]))
    return out


def _n(v) -> str:
    """A coordinate as written: the shortest text that reads back to the same float."""
    return repr(float(v))


# --- writers -------------------------------------------------------------------------------------------------------

def write(d: Drawing, ext: str, tol: float = 1e-3):
    """The file's content (str, or bytes for DXF)."""
    if ext == ".csv":
        return _csv(d, tol)
    if ext == ".svg":
        return _svg(d, tol)
    return _dxf(d, tol)


def _csv(d: Drawing, tol: float) -> str:
    out = []
    for e in d.entities:
        out.append(f"# {e.layer}\nx_mm,y_mm")
        out.extend(f"{_n(x)},{_n(y)}" for x, y in contour_points(e, tol))
        out.append("")
    for layer, x, y in d.points:
        out.append(f"# {layer}\nx_mm,y_mm\n{_n(x)},{_n(y)}\n")
    return "\n".join(out)


def _svg_path(e: Entity, tol: float) -> str:
    """Path data: arcs as SVG arcs (an exact full circle as two half arcs), curves as lines; y up (the
    drawing is flipped by the group's transform)."""
    cmds = []
    for p in e.pieces:
        if isinstance(p, Arc):
            pts = [(p.cx + p.r * math.cos(a), p.cy + p.r * math.sin(a))
                   for a in ((p.a0, p.a0 + math.pi, p.a1) if p.full else (p.a0, p.a1))]
            if not cmds:
                cmds.append(f"M {_n(pts[0][0])} {_n(pts[0][1])}")
            for x, y in pts[1:]:
                large = 1 if (p.a1 - p.a0 > math.pi and not p.full) else 0
                cmds.append(f"A {_n(p.r)} {_n(p.r)} 0 {large} 1 {_n(x)} {_n(y)}")
        else:
            pts = subdivide(p.f, p.t0, p.t1, tol)[1]
            if not cmds:
                cmds.append(f"M {_n(pts[0, 0])} {_n(pts[0, 1])}")
            cmds.extend(f"L {_n(x)} {_n(y)}" for x, y in pts[1:])
    if e.closed:
        cmds.append("Z")
    return " ".join(cmds)


def _svg(d: Drawing, tol: float) -> str:
    pts = np.concatenate([contour_points(e, max(tol, 1e-2)) for e in d.entities])
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    pad = 0.02 * float(max(hi - lo)) + 1.0
    x0, y0, w, h = lo[0] - pad, -(hi[1] + pad), (hi - lo)[0] + 2 * pad, (hi - lo)[1] + 2 * pad
    lines = ['<?xml version="1.0" encoding="UTF-8"?>',
             f'<svg xmlns="http://www.w3.org/2000/svg" width="{_n(w)}mm" height="{_n(h)}mm" '
             f'viewBox="{_n(x0)} {_n(y0)} {_n(w)} {_n(h)}">',
             "<!-- gearcalc export: units mm, y up (the group flips the y axis) -->",
             '<g transform="scale(1,-1)" fill="none" stroke="black" stroke-width="0.05">']
    for e in d.entities:
        lines.append(f'<path id="{e.layer.lower()}-{len(lines)}" class="{e.layer}" d="{_svg_path(e, tol)}"/>')
    for layer, x, y in d.points:
        lines.append(f'<circle class="{layer}" cx="{_n(x)}" cy="{_n(y)}" r="0.3"/>')
    lines += ["</g>", "</svg>", ""]
    return "\n".join(lines)


def _dxf(d: Drawing, tol: float) -> bytes:
    try:
        import ezdxf
        from ezdxf import units
    except ImportError:
        raise ExportError(DXF_HINT) from None
    import io

    doc = ezdxf.new("R2010")
    doc.units = units.MM
    doc.header["$MEASUREMENT"] = 1
    msp = doc.modelspace()
    for e in d.entities:
        if e.layer not in doc.layers:
            doc.layers.add(e.layer)
        if len(e.pieces) == 1 and isinstance(e.pieces[0], Arc) and e.pieces[0].full:
            p = e.pieces[0]
            msp.add_circle((p.cx, p.cy), p.r, dxfattribs={"layer": e.layer})
        elif all(isinstance(p, Arc) for p in e.pieces):
            for p in e.pieces:
                msp.add_arc((p.cx, p.cy), p.r, math.degrees(p.a0), math.degrees(p.a1), dxfattribs={"layer": e.layer})
        else:
            msp.add_lwpolyline([tuple(v) for v in contour_points(e, tol)[:-1]], close=e.closed,
                               dxfattribs={"layer": e.layer})
    for layer, x, y in d.points:
        if layer not in doc.layers:
            doc.layers.add(layer)
        msp.add_point((x, y), dxfattribs={"layer": layer})
    buf = io.StringIO()
    doc.write(buf)
    return buf.getvalue().encode("utf-8")
