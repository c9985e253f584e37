"""Multi-row planetary gear: row load sharing from sun torsion, equalising carrier bridges, relative mass.

The physics of the ``rows`` calculator as pure functions over floats and numpy arrays, one module per
part of the specification (docs/spec/rows.md):

* :mod:`~gearcalc.rows.geometry`: the gear's dimensions and the rules they must satisfy (§1, §2.4, §7,
  §10); imports no numpy.
* :mod:`~gearcalc.rows.sharing`: the sun's torsion parameter and the stepwise, exact and continuous
  load-sharing levels, the active set for a compliant carrier (§2, §3, §5.5).
* :mod:`~gearcalc.rows.bridges`: the compliant carrier and the bridge sizing of eq. (2) (§5).
* :mod:`~gearcalc.rows.mass`: the relative mass M(i) and its optimum ratio (§6).

Every public name of the modules is available here, imported on first use (so that a caller that needs
only the geometry, such as ``gearcalc check``, does not import numpy).

The paper's one stated value (rows.md §11.1): K = 1.489 for n = 3 rows of n_w = 3 planets, B = 2.4:

>>> import math
>>> from gearcalc import rows as R
>>> d_a = R.pitch_diameter(18, 5.0)                             # z_a = 18, m = 5 mm
>>> b_w = R.rim_width(2.4, 3, 0.25, d_a)
>>> r_ba = R.base_radius(d_a, math.radians(20.0))
>>> G = R.shear_modulus(2e5, 0.3)
>>> kappa = R.torsion_parameter(R.mesh_stiffness(2e5), r_ba, 3, b_w, G, R.polar_moment(d_a))
>>> u, valid = R.stepwise_shares(kappa, 0.25, 3)
>>> round(float(u.max()), 3), bool(valid)
(1.489, True)

References
----------
.. [1] Seed paper 004_971077b94d8d4426.txt: an OCR of a Russian journal paper on multi-row planetary
   gears (its title, authors and journal cannot be recovered; its ref. [1] is F. I. Plekhanov,
   «Зубчатые планетарные передачи»), as reconstructed in docs/spec/rows.md.
"""
from __future__ import annotations

from ..lazy import lazy_names

_MODULES = ("geometry", "sharing", "bridges", "mass")
_NAMES = {
    "geometry": ("MESH_STIFFNESS_PER_E", "ROOT_DEPTH_MODULES", "RIM_MIN_MODULES", "PAPER_MAX_RELATIVE_WIDTH",
                 "DEFAULT_SECTION_PER_RIM",
                 "Face", "pitch_diameter", "root_diameter", "rim_width", "rim_width_from_cheek", "relative_width",
                 "cheek_ratio_of", "base_radius", "face_geometry", "ratio_from_planet_teeth", "planet_teeth",
                 "torsion_diameter", "shear_modulus", "mesh_stiffness", "rim_under_roots", "rims_fit",
                 "bore_fits", "rim_too_thin", "planets_collide", "row_centres"),
    "sharing": ("RESCALE", "KAPPA_UNIFORM", "KAPPA_STEPWISE_MAX", "UNLOADED_SHARE", "LEVELS", "Sharing",
                "polar_moment", "torsion_parameter", "stepwise_shares", "stepwise_dense", "twist_between",
                "exact_shares", "exact_k_no_gap", "x_coth_x", "continuous_x", "continuous_k",
                "continuous_profile", "row_sharing", "SharingBatch", "row_sharing_mixed", "mean_line_load",
                "twist_from_shares",
                "stepwise_active_set", "stepwise_active_set_batch"),
    "bridges": ("Verification", "carrier_displacements", "carrier_matrix",
                "carrier_compliance", "beam_compliance", "bridge_width_for_compliance", "size_bridges",
                "verify_carrier", "bridges_fit", "largest_feasible_width", "FLAGS", "size_bridges_batch",
                "carrier_compliance_batch", "verify_carrier_batch", "fits_batch", "feasible_widths", "feasible_rows"),
    "mass": ("Mass", "mass_bracket", "relative_mass", "mass_optimum_closed_form", "mass_and_optimum"),
}
__all__, __getattr__, __dir__ = lazy_names(__name__, globals(), _MODULES, _NAMES)
