"""Physics of the eccentric closed rolling-body mechanism (ZSTK) with a leading inner ring.

Pure functions over floats and numpy arrays (no I/O, no design objects, no key names).  Units: mm,
N, MPa, radians inside; degrees only at the interface (:mod:`gearcalc.kinds.zstk`).  Arrays of
roller quantities have the shape ``(..., N)``: leading axes for phases, load directions or stacked
designs.  Frame: O_H = (0, 0), O_B = (e, 0); +x points to the narrowest point of the annular gap
(theta = 0); angles grow counter-clockwise.

Modules (spec ``docs/spec/zstk.md``):

* :mod:`.geometry` §3.1 roller radius, centre distance, contact normals and beta (closed form);
* :mod:`.chain` §3.2 closure as a Steiner chain (N*, the corrections of R_H, R_B or c, N_max) and
  §4 the roller positions through the Möbius map (explicit stepping as a cross-check);
* :mod:`.validity` §3.3, §9 the validity rules, one vectorised rule set;
* :mod:`.loads` §5 the load distribution (zero clearance: direction root; clearance/preload:
  bracketed 1-D root or Newton on the convex potential);
* :mod:`.stress` §2 the Hertz stresses (through :mod:`gearcalc.hertz`) and the summary quantities;
* :mod:`.envelope` §8 the sweeps over the chain phase ("cycle") and the load direction ("envelope");
* :mod:`.capacity` §5.4 the allowable radial load (sigma_max = [sigma_H]);
* :mod:`.outputs` §10 the outputs of solved designs (strength check, shear, separator force, roller detail).

The calculator's design keys are in :mod:`.schema`, its field names and texts in :mod:`.report`, its figure
in :mod:`.figure`; :mod:`.solve` prepares, stacks by N and sweeps the designs of a run, a batch or a sweep;
the adapter :mod:`gearcalc.kinds.zstk` maps design keys to these functions and their results to output fields.

Every public name of the physics modules above is available here (``from gearcalc import zstk as z``),
imported on first use (PEP 562), so that the schema the calculator reads at start-up imports no numpy.

References
----------
Merko M.A., Mesnyankin M.V., Kolotov A.V., Mityaev A.E., Savitskaya M.V., Merko A.M., Yurov S.A.,
«Анализ нормальных напряжений на площадках контакта звеньев механизмов с ЗСТК при ведущем
внутреннем кольце и вводе поправки по радиусу дорожки качения наружного кольца» (Siberian Federal
University; UDC 621.838.2; no journal or year given: seed 003_2d1da402cb0b8488.txt), eqs. (1)-(7);
docs/spec/zstk.md.
"""
from __future__ import annotations

from ..lazy import lazy_names

_MODULES = ("geometry", "chain", "validity", "loads", "stress", "envelope", "capacity", "outputs", "solve", "schema",
            "report", "figure")
_NAMES = {
    "geometry": ("SCHEME_PARITY", "INTEGER_TOL", "broadcast", "take", "single", "wrap_angle", "remainder_360",
                 "roller_radius", "extreme_roller_radii", "centre_distance", "normal_angle_offset", "reduced_radii"),
    "chain": ("fractional_roller_number", "corrected_outer_radius", "corrected_inner_radius", "corrected_gap",
              "roller_number_limit", "auto_roller_number", "auto_roller_numbers", "largest_admissible_n",
              "largest_admissible_ns", "Chain", "close_chains", "close_chain", "limiting_point_ratio",
              "limiting_ratios", "chain_phases", "theta_of_phi",
              "phi_of_theta", "roller_angles", "scheme_phase", "centres", "neighbour_gaps", "step_chain"),
    "validity": ("geometry_violations", "chain_violations", "Validity", "check_designs", "geometry_problems",
                 "chain_problems"),
    "loads": ("LOAD_EXPONENT", "E_STAR_REF", "roller_stiffness", "LoadSolution", "load_zero_clearance",
              "load_along_direction", "load_with_clearance", "solve_loads"),
    "stress": ("Materials", "State", "evaluate", "critical", "solve_placements", "Summary", "summarise",
               "safety_factor", "Contacts", "roller_contacts", "roller_approach", "worst_width_ratio",
               "separator_forces", "LOADED_RTOL", "ROUNDOFF_RTOL", "critical_shear", "roller_field"),
    "envelope": ("GRID_PHASE", "GRID_DIRECTION", "GRID_CAP", "CHUNK_ELEMENTS", "REFINE_ROWS_MAX_N",
                 "REFERENCE_GRID_FACTOR", "SweepResult", "maximise_periodic", "SweepGrid", "sweep_grid", "sweep_work",
                 "Placement", "ROLLER_FIELDS", "sigma_max_at", "direction_maxima", "roller_sigma",
                 "position_direction_max", "critical_placement", "evaluate_placement", "roller_envelope"),
    "capacity": ("AllowableLoad", "allowable_load_closed_form", "allowable_load_root", "allowable_load",
                 "allowable_load_sweeping"),
    "outputs": ("Outputs", "stack_outputs", "RollerDetail", "roller_detail", "Margins", "margins"),
}
__all__, __getattr__, __dir__ = lazy_names(__name__, globals(), _MODULES, _NAMES)
