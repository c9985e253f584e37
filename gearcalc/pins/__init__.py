"""KHV planetary pin (lantern) gearing: per-pin friction losses and the efficiency they cause.

The physics of the ``pins`` calculator as pure functions over floats and numpy arrays (no I/O, no design
keys), one module per part of the specification (docs/spec/pins.md).  Units inside: N, mm, N·mm, rad,
rad/s; a power F [N]·v [mm/s]·1e-3 is in W.

* :mod:`~gearcalc.pins.formula`: level ``formula``, the paper's per-pin maximum loss, eqs. (3)-(7) (§3).
* :mod:`~gearcalc.pins.geometry`: the cycloidal satellite, admissibility, crest cut-off psi*, lever arms,
  curvature, pin-centre curve and tooth profile (§4.1-4.3).
* :mod:`~gearcalc.pins.forces`: pin phases, the loaded set, the friction-free pin forces (§4.3-4.4).
* :mod:`~gearcalc.pins.efficiency`: rolling condition, sliding speeds, pin spin, losses, efficiencies
  (§4.5-4.7).
* :mod:`~gearcalc.pins.operating`: one operating point or many: friction regime, efficiencies with their
  error, shaft torques, a unit cycle scaled to a torque (§4.5-4.7).
* :mod:`~gearcalc.pins.cycle`: the cycle model of one gear: breakpoints, loaded-pin state, per-pin detail,
  sums over discs (§4.6, §6, §12.7).
* :mod:`~gearcalc.pins.ideal`: the ideal level's cycle integral for many gears at once (§4, §6).
* :mod:`~gearcalc.pins.consistent`: the friction-consistent cycles, jams, crank torque (§4.9).
* :mod:`~gearcalc.pins.outputs`: the ideal level's outputs of an operating point (§4.9, §8).
* :mod:`~gearcalc.pins.points`: the ideal level at many operating points at once, each geometry solved once
  (§4.4-4.9, §8).
* :mod:`~gearcalc.pins.detail`: the per-element detail tables of both cycle levels (§8).
* :mod:`~gearcalc.pins.contact`: level ``contact``, the compliant contact model (§5); its names are not
  re-exported here (use ``from gearcalc.pins import contact``).  It holds the torque fixed point and the modes
  (§4.9, §7) and re-exports the level's other modules: the tooth profiles and pin penetrations
  (:mod:`~gearcalc.pins.contact_profiles`, §5.2-5.3), the contact laws (:mod:`~gearcalc.pins.contact_law`, §5.4),
  the equilibrium at given crank angles (:mod:`~gearcalc.pins.contact_model`, §5.1, §5.5) and one cycle at one
  torque (:mod:`~gearcalc.pins.contact_cycle`, §5.6-5.7, §6).
* :mod:`~gearcalc.pins.contact_level`: the contact level of one design: profile, friction, modes, peaks (§5).

The calculator's design keys are in :mod:`~gearcalc.pins.schema`, its validity rules (each once, for
``check``, compute, batch and sweep) in :mod:`~gearcalc.pins.checks`, the formula and ideal levels over many
designs or points as summary columns in :mod:`~gearcalc.pins.columns`, a batch's groups in
:mod:`~gearcalc.pins.batching`, its texts and field lists in :mod:`~gearcalc.pins.report`, its figure in
:mod:`~gearcalc.pins.plot`; the adapter :mod:`gearcalc.kinds.pins` maps design keys to these functions and
their results to output fields.

Every public name of the physics modules above but the contact level's (:mod:`~gearcalc.pins.contact` and the
two it re-exports) and :mod:`~gearcalc.pins.detail` is available here, imported on first use (PEP 562), so that
``from gearcalc import pins`` (and the schema the calculator reads at start-up) imports no numpy.

The paper's worked value (pins.md §3): the rolling and axle friction power of the most loaded pin,
F = 1920 N at 14 rpm, R_b = 1.95 mm, r = 0.95 mm, f_k = 0.01 mm, f_c = 0.1, with pi = 3.14 as the paper:

>>> from gearcalc import pins
>>> round(float(pins.formula_losses(1920.0, 14, 1.95, 0.95, 0.01, 0.1, paper_pi=True).P_tr), 4)
0.2954

References
----------
.. [1] A. P. Prudnikov, "Power losses in pins and teeth contact area of KHV-type planetary gearing",
   *Mashinostroenie* (seed 000), eqs. (3)-(7) and Figs 3-7, as reconstructed in docs/spec/pins.md.
.. [2] S. K. Malhotra, M. A. Parameswaran, "Analysis of a cycloid speed reducer", *Mech. Mach. Theory*
   18(6):491-499, 1983 (kinematics, pins.md §4.1).
.. [3] B. Chen, T. Fang, C. Li, S. Wang, "Gear geometry of cycloid drives", *Science in China Series E*
   51, 2008 (the profile, pins.md §4.2).
.. [4] M. Blagojević et al., "Influence of the friction on the cycloidal speed reducer efficiency",
   *J. Balkan Tribol. Assoc.* 18(2):217-227, 2012 (friction in the satellite's balance, pins.md §4.9).
.. [5] K. L. Johnson, *Contact Mechanics*, Cambridge 1985, eq. (4.45) (Hertz line contact, pins.md §8).
"""
from __future__ import annotations

from ..lazy import lazy_names

_MODULES = ("formula", "geometry", "forces", "efficiency", "friction", "operating", "cycle", "ideal", "consistent",
            "points", "outputs", "detail", "contact", "contact_level", "checks", "columns", "batching", "schema",
            "report", "plot")
_NAMES = {
    "formula": ("PAPER_PI", "pin_angular_speed", "rolling_friction_force", "axle_friction_force", "friction_power",
                "FormulaLosses", "formula_losses", "fixed_pin_formula_loss"),
    "geometry": ("REDUCER", "MULTIPLIER", "Cycloid", "GeometryViolations", "geometry_violations", "s_factor",
                 "pitch_distance", "lever_arm", "contact_point", "contact_angle_offset", "crest_cutoff",
                 "crest_cutoffs", "spin_reversal_phase", "spin_reversal_phases", "curvature_radius",
                 "min_curvature_radius", "pin_centre_curve", "tooth_profile", "PinMounting"),
    "forces": ("pin_phase", "lever_sum", "pin_forces", "loss_ratio", "full_circle_lever_sum"),
    "friction": ("FrictionLaw", "Coulomb", "FRICTION_LAWS", "register_friction_law", "friction_law",
                 "peak_coefficient", "PinFriction"),
    "efficiency": ("rolling_condition", "rotating_loss_coefficient", "sliding_speed", "pin_spin",
                   "contact_loss_power", "efficiency_multiplier", "efficiency_reducer", "willis_efficiencies"),
    "operating": ("SCALAR_OPS", "ARRAY_OPS", "pin_circle", "friction_regime", "efficiency_reducer_err",
                  "shaft_torques", "EfficiencyTorques", "efficiency_torques", "ScaledCycle", "scale_unit_cycle",
                  "Gears", "FrictionCoefficients", "OperatingPoint", "SatelliteLoad"),
    "cycle": ("cycle_breakpoints", "CycleState", "cycle_state", "cycle_loss_ratio", "state_loss_ratio", "CycleDetail",
              "cycle_detail", "crank_order", "disc_offsets", "sum_over_discs", "disc_sum_range", "disc_sum_peak"),
    "ideal": ("CycleIntegral", "mean_loss_ratio", "NODE_ROWS", "GRID_ROWS", "FIRST_LEVELS_MAX",
              "first_levels", "cycle_pieces", "TOO_FEW_TEETH", "UNDERCUT", "TOO_COSTLY", "DISC_SAMPLES_MAX",
              "DISC_WORK_MAX", "IdealCycles", "REFINE_SAMPLES", "admissibility", "ideal_cycles"),
    "consistent": ("consistent_node_values", "ConsistentCycles", "CONSISTENT_CHUNK_NODES", "REFINE_BLOCK",
                   "CONSISTENT_N_MAX", "consistent_cycles", "crank_history"),
    "points": ("IdealPoints", "ideal_points"),
    "outputs": ("STEEL_E_MPA", "STEEL_NU", "STEEL_E_STAR_MPA", "ConsistentEfficiencies", "consistent_efficiencies",
                "satellite_torque", "crank_torque", "contact_stress", "axle_pressure", "pin_loss_bound",
                "ConsistentPoint", "consistent_point", "consistent_outputs", "bearing_life", "CrankDetail",
                "crank_detail"),
}
__all__, __getattr__, __dir__ = lazy_names(__name__, globals(), _MODULES, _NAMES)
