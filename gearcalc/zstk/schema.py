"""The design keys of the ``zstk`` calculator (zstk.md §9): tables, types, bounds, defaults, the cost budget.

Imports nothing heavy: ``gearcalc new zstk``, ``gearcalc check`` and the man page read it.  The sweep grids
(points per pitch and per turn, their cap) are numerics of the sweeps and live in :mod:`gearcalc.zstk.envelope`.
"""
from __future__ import annotations

from ..calculator import REQUIRED, Field, Table
from ..registry import LEVELS
from ..units import MAX_FORCE_N, MAX_LENGTH_MM, MIN_LENGTH_MM

__all__ = ["MODELS", "SCHEMES", "DEFAULT_ALLOWABLE_MPA", "DEFAULT_ALLOWABLE_SOURCE", "B_OVER_RHO_LIMIT", "MIN_E_MPA",
           "MAX_E_MPA", "MIN_FORCE_N", "SWEEP_WORK_MAX", "MAX_ROLLERS", "GEOMETRY", "LOAD", "MATERIAL", "TABLES",
           "KEYS", "HEADER", "TABLE_FIELDS"]

MODELS = LEVELS["zstk"]
SCHEMES = ("A", "B", "C", "D")
DEFAULT_ALLOWABLE_MPA = 4000.0
DEFAULT_ALLOWABLE_SOURCE = "default: ISO 76 static reference"
B_OVER_RHO_LIMIT = 0.1
"""Hertz's small-contact assumption (zstk.md §9): a loaded contact with b/rho above it is warned about."""
# Physical ranges of the inputs (gearcalc's choice, spec §9 "a value outside its physical range"):
# lengths from 1 nm to 1 km, moduli from soft rubber (1 MPa) to beyond diamond (1e7 MPa).
MIN_E_MPA, MAX_E_MPA = 1.0, 1e7
MIN_FORCE_N = 1e-6
"""Smallest radial load (1 uN): far below it the contact deflections approach the round-off of the roller
positions (~1e-16 x clearance) and the load solve cannot balance Q (5e-324 N gave solver_residual = 1 and
pass = true; with clearance, 1e-100 N raised BracketError); at 1e-6 N the worked example balances Q to 4e-8
with a clearance of 0.01 mm (included in sigma_max_err_MPa)."""
SWEEP_WORK_MAX = 6_000_000
"""Cost budget of a "cycle" and/or "envelope" design, in roller-configurations of its first sweep grid
(:func:`gearcalc.zstk.sweep_work`): ~2-7 us each with the refinements (N = 2000, "cycle" + "envelope": 1.7e6, 4 s;
N = 248 "cycle" + "envelope" at --model reference: 1.2e7, ~25 s, refused); the sweeps' memory is bounded by
:data:`gearcalc.zstk.envelope.CHUNK_ELEMENTS`."""
MAX_ROLLERS = 2000
"""gearcalc's range of N (the spec asks N > 200 to work); keeps the sweeps in memory."""

GEOMETRY = Table("geometry", (
    Field("outer_raceway_radius_mm", "number", REQUIRED, "R_H, outer (concave) raceway radius, nominal",
          gt=0, le=MAX_LENGTH_MM, example=100.0),
    Field("inner_raceway_radius_mm", "number", REQUIRED, "R_B, inner (convex) raceway radius, nominal",
          gt=0, le=MAX_LENGTH_MM, example=50.0),
    Field("eccentricity_mm", "number", REQUIRED, "e = |O_H O_B|, offset of the inner raceway centre",
          ge=0, le=MAX_LENGTH_MM, example=6.0),
    Field("roller_gap_mm", "number", 0.0, "c, gap between neighbouring rollers along their centre line",
          ge=0, le=MAX_LENGTH_MM, example=6.0),
    Field("roller_length_mm", "number", REQUIRED, "l, roller working length", ge=MIN_LENGTH_MM,
          le=MAX_LENGTH_MM, example=20.0),
    Field("rollers", "integer", "auto", "N, or \"auto\" = the largest N <= N* of the scheme's parity",
          choices=("auto",), ge=3, le=MAX_ROLLERS),
    Field("correct", "string", "outer", "parameter corrected to close the chain (the paper: outer)",
          choices=("outer", "inner", "gap")),
    Field("scheme", "number", "A", "chain phase: a symmetric scheme, the polar angle theta_0 of roller 0 "
          "in degrees, or \"cycle\" = envelope over every placement", choices=SCHEMES + ("cycle",)),
    Field("separator", "bool", True, "a separator holds each roller in place (the model); false (rollers "
          "touching without one) is refused: roller-to-roller contact is not modelled"),
), doc="Raceways, eccentricity and the roller chain")

LOAD = Table("load", (
    Field("radial_N", "number", REQUIRED, f"Q, radial load on the leading inner ring (>= {MIN_FORCE_N:g} N: "
          "smaller loads are below the round-off of the load solve)", ge=MIN_FORCE_N, le=MAX_FORCE_N,
          example=10000.0),
    Field("direction_deg", "number", 0.0, "direction of Q from the line of centres (0 = toward the narrowest "
          "gap, counter-clockwise), or \"envelope\" = every direction", choices=("envelope",)),
    Field("clearance_mm", "number", 0.0, "radial clearance s, total free travel of the inner ring (< 0: preload); "
          "|s| < the smallest roller radius"),
), doc="Load on the inner ring")

MATERIAL = Table("material", (
    Field("roller_E_MPa", "number", 2.1e5, "Young's modulus of the rollers", ge=MIN_E_MPA, le=MAX_E_MPA),
    Field("roller_poisson", "number", 0.3, "Poisson's ratio of the rollers", gt=0, lt=0.5),
    Field("ring_E_MPa", "number", 2.1e5, "Young's modulus of both rings", ge=MIN_E_MPA, le=MAX_E_MPA),
    Field("ring_poisson", "number", 0.3, "Poisson's ratio of both rings", gt=0, lt=0.5),
    Field("inner_ring_E_MPa", "number", None, "override ring_E_MPa for the inner ring", ge=MIN_E_MPA, le=MAX_E_MPA,
          default_doc="ring_E_MPa"),
    Field("inner_ring_poisson", "number", None, "override ring_poisson for the inner ring", gt=0, lt=0.5,
          default_doc="ring_poisson"),
    Field("outer_ring_E_MPa", "number", None, "override ring_E_MPa for the outer ring", ge=MIN_E_MPA, le=MAX_E_MPA,
          default_doc="ring_E_MPa"),
    Field("outer_ring_poisson", "number", None, "override ring_poisson for the outer ring", gt=0, lt=0.5,
          default_doc="ring_poisson"),
    Field("allowable_stress_MPa", "number", None, "[sigma_H], allowable contact stress (at most 1e6 MPa, far above "
          "any material's strength: Q_allow grows as its square and overflowed at 1e308)", gt=0, le=1e6,
          default_doc=f"{DEFAULT_ALLOWABLE_MPA:g} (ISO 76 static reference, not an endurance allowable)"),
), doc="Elastic constants and the allowable contact stress")

TABLES = (GEOMETRY, LOAD, MATERIAL)

KEYS = {"outer": "geometry.outer_raceway_radius_mm", "inner": "geometry.inner_raceway_radius_mm",
        "eccentricity": "geometry.eccentricity_mm", "gap": "geometry.roller_gap_mm",
        "rollers": "geometry.rollers", "clearance": "load.clearance_mm"}
"""The design key of each quantity that :func:`gearcalc.zstk.check_designs` names in a problem."""

HEADER = ("Merko et al. (seed 003): rollers of different diameters between an outer raceway (R_H) and an\n"
          "eccentric inner raceway (R_B, offset e); one raceway radius (or the gap) is corrected so that an\n"
          "integer number of rollers closes the chain.  Units: mm, N, MPa, degrees.")
TABLE_FIELDS = ("N", "sigma_max_MPa", "sigma_max_contact", "sigma_max_roller", "pass")
"""The summary fields a table of several designs shows."""
