"""The design keys of the ``rows`` calculator (rows.md §7): tables, types, bounds, defaults.

Imports nothing heavy: ``gearcalc new rows``, ``gearcalc check`` and the man page read it.
"""
from __future__ import annotations

from ..calculator import REQUIRED, Field, Table

__all__ = ["DIAMETER_WORDS", "TABLES"]

DIAMETER_WORDS = ("pitch", "root")

TABLES = (
    Table("gear", doc="the sun and the ratio", fields=(
        Field("sun_teeth", "integer", REQUIRED, "z_a, sun teeth", ge=3, le=10000, example=18),
        Field("module_mm", "number", REQUIRED, "m, module", ge=1e-3, le=1e4, example=5.0),
        Field("pressure_angle_deg", "number", 20.0, "alpha_w, working pressure angle", ge=1, lt=45),
        Field("ratio", "number", None, "i, ratio (sun input, ring fixed, carrier output); needed by [bridges]",
              gt=2, le=1e4, example=6.0),
        Field("planet_teeth", "integer", None, "z_g, planet teeth; i = 2 + 2 z_g / z_a (give ratio or this)",
              ge=1, le=1e6),
    )),
    Table("rows", doc="the planet rows", fields=(
        Field("count", "integer", REQUIRED, "n, rows of planets", ge=1, le=1000, example=3),
        Field("planets_per_row", "integer", REQUIRED, "n_w, planets in each row", ge=1, le=1000, example=3),
        Field("relative_width", "number", None, "B = b_a / d_a, sun face width over sun pitch diameter "
              "(give this or rim_width_mm)", ge=1e-9, le=1e4, example=3.0),
        Field("rim_width_mm", "number", None, "b_w, planet rim (row) width (give this or relative_width)",
              ge=1e-6, le=1e7),
        Field("cheek_ratio", "number", None, "b/b_w, cheek thickness over rim width (give this or cheek_mm)",
              ge=0, le=1e4, default_doc="0.25", example=0.25),
        Field("cheek_mm", "number", None, "b, cheek thickness = gap between rows (give this or cheek_ratio)",
              ge=0, le=1e7),
    )),
    Table("sun", doc="the sun shaft", fields=(
        Field("torque_Nm", "number", None, "T_a, sun torque; K does not depend on it, the line loads do",
              gt=0, le=1e15, example=1000.0),
        Field("torsion_diameter", "number", "pitch", "d_I for the polar moment: pitch diameter, root diameter "
              "(d_a - 2.5 m) or a diameter in mm", ge=1e-3, le=1e8, choices=DIAMETER_WORDS),
        Field("bore_mm", "number", 0.0, "d_0, sun bore (0: solid)", ge=0, le=1e8),
    )),
    Table("material", doc="elastic constants", fields=(
        Field("E_MPa", "number", 2.0e5, "E, Young's modulus", ge=1.0, le=1e7),
        Field("poisson", "number", 0.3, "nu, Poisson's ratio", ge=0, lt=0.5),
        Field("mesh_stiffness_MPa", "number", None, "C, mesh stiffness per unit face width (N/mm per mm)",
              ge=1e-3, le=1e8, default_doc="0.075 E_MPa"),
    )),
    Table("bridges", optional=True, doc="present: size the carrier bridges that equalise the rows (eq. (2))",
          fields=(
              Field("axle_diameter_mm", "number", None, "d, planet axle diameter", gt=0, le=1e7,
                    default_doc="0.5 b_w"),
              Field("bridge_thickness_mm", "number", None, "h, radial thickness of a bridge", gt=0, le=1e7,
                    default_doc="0.5 b_w"),
              Field("first_span", "number", "axes_only", "H_1: \"axes_only\" (H_1 = 0, the paper's closure) "
                    "or a width in mm", ge=0, le=1e8, choices=("axes_only",)),
              Field("torsion_diameter", "number", "root", "d_I used to size the bridges (the paper's table "
                    "needs \"root\")", ge=1e-3, le=1e8, choices=DIAMETER_WORDS),
          )),
    Table("mass", optional=True, doc="present: relative mass M(i) and the ratio that minimises it", fields=(
        Field("wall_ratio", "number", 0.06, "t, wall of ring rim, housing and covers over ring diameter", ge=0, le=1),
        Field("sun_fill", "number", 0.7, "k_a, fill factor of the sun", gt=0, le=1),
        Field("planet_fill", "number", 1.0, "k_g, fill factor of a planet", gt=0, le=1),
        Field("allowable_contact_MPa", "number", 600.0, "sigma_HP, allowable contact stress", ge=1e-3, le=1e6),
        Field("density_kg_m3", "number", 7800.0, "rho, density", gt=0, le=1e6),
        Field("efficiency", "number", 0.95, "eta, efficiency (a drive passes at least 1 %)", ge=0.01, le=1),
        Field("unevenness", "number", 1.0, "K used in M; \"computed\" takes K_balanced with [bridges], "
              "else the design's K", ge=1e-3, le=1e6, choices=("computed",)),
        Field("ratio_range", "numbers", [2.2, 12.0], "[i_lo, i_hi] where the minimum is searched", gt=2, le=1e4,
              length=2),
    )),
)


FAST_SWEEP_KEYS = frozenset({
    "gear.sun_teeth", "gear.module_mm", "gear.pressure_angle_deg", "gear.ratio", "rows.count",
    "rows.planets_per_row", "rows.relative_width", "rows.rim_width_mm", "rows.cheek_ratio", "rows.cheek_mm",
    "sun.torque_Nm", "sun.torsion_diameter", "sun.bore_mm", "material.E_MPa", "material.poisson",
    "material.mesh_stiffness_MPa", "mass.wall_ratio", "mass.sun_fill", "mass.planet_fill",
    "mass.allowable_contact_MPa", "mass.density_kg_m3", "mass.efficiency", "mass.unevenness",
    "bridges.axle_diameter_mm", "bridges.bridge_thickness_mm", "bridges.first_span", "bridges.torsion_diameter",
})
"""The keys a vectorised rows sweep may vary (:func:`gearcalc.kinds.rows.sweep`); others run point by point."""
