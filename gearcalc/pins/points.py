"""KHV pin gearing, level ``ideal``: many operating points at once (pins.md §4.4-4.9, §6, §8).

Every distinct geometry among the points is solved once, all of them together, in unit scalings
(:func:`~gearcalc.pins.ideal.ideal_cycles`); every point then scales its geometry's solution by its friction,
torque, speed and mode (pins.md §4.8 identity 8: lambda ∝ mu_eff, F ∝ T, v ∝ omega), first-order
(:func:`~gearcalc.pins.operating.efficiency_torques`, :func:`~gearcalc.pins.operating.scale_unit_cycle`), and
friction-consistent where asked (:func:`~gearcalc.pins.outputs.consistent_outputs`).  One point runs the same
formulas on scalars (``xp=SCALAR_OPS``): the same numbers as in an array, bit for bit, without the cost of
numpy calls on arrays of one element.  Units: N, mm, N·m, rpm, W as in :mod:`gearcalc.pins.operating`.

References
----------
.. [1] The paper (Prudnikov, seed 000), cited in full in :mod:`gearcalc.pins`; docs/spec/pins.md §4.4-4.9, §8.
"""
from __future__ import annotations

from dataclasses import dataclass
from types import SimpleNamespace

import numpy as np

from .friction import PinFriction
from .geometry import Cycloid
from .ideal import IdealCycles, ideal_cycles
from .operating import SCALAR_OPS, EfficiencyTorques, FrictionCoefficients, Gears, OperatingPoint, SatelliteLoad
from .operating import ScaledCycle, efficiency_torques, friction_regime, pin_circle, scale_unit_cycle
from .outputs import ConsistentPoint, consistent_outputs

__all__ = ["IdealPoints", "ideal_points"]


@dataclass
class IdealPoints:
    """The ideal level at n operating points (:func:`ideal_points`): arrays over the points, or the one point's scalars.

    cyc : the solved geometries (:class:`~gearcalc.pins.ideal.IdealCycles`); gi : each point's geometry;
    z1, z2, e, Rp, Rb, omk, n_d, k, K1 : the points' gears (R_p and 1 - K1 from either given one);
    status, psi_star, psi_0 : admissibility and the loaded arc's phases [rad] per point;
    mu, rolls : mu_eff and whether the pins roll; lam, E : the first-order loss ratio and its error;
    et, sc : the first-order efficiencies and torques and the scaled cycle (T_sat [N·mm], omega_V [rad/s]);
    consistent : the friction-consistent results (:class:`~gearcalc.pins.outputs.ConsistentPoint`, None when
    no point is admissible); cons, peaks, multi_disc : the points whose efficiencies, whose peaks (one disc) are
    friction-consistent, and the consistent points with several discs (their peaks stay friction-free, scaled
    to the friction-consistent torque).
    """

    cyc: IdealCycles
    gi: np.ndarray
    one: bool
    z1: object
    z2: object
    e: object
    Rp: object
    Rb: object
    omk: object
    n_d: object
    k: object
    K1: object
    status: object
    psi_star: object
    psi_0: object
    mu: object
    rolls: object
    lam: object
    E: object
    et: EfficiencyTorques
    sc: ScaledCycle
    consistent: ConsistentPoint | None
    cons: np.ndarray
    peaks: np.ndarray
    multi_disc: np.ndarray

    def field(self, name: str):
        """An :class:`~gearcalc.pins.ideal.IdealCycles` field per point.

        An array over points, or the one point's Python scalar.
        """
        arr = getattr(self.cyc, name)
        return arr.item(0) if self.one else arr[self.gi]


def ideal_points(gears: Gears, friction: FrictionCoefficients, op: OperatingPoint, consistent, tol: float = 1e-6,
                 xp=None, first_order_peaks: bool = True) -> IdealPoints:
    r"""The ideal level (pins.md §4) at n operating points: the geometries solved once, the points scaled.

    .. math:: \bar\lambda = \mu_{eff}\,\bar\lambda_1, \qquad F \propto T_{sat}, \qquad v \propto \omega_V

    Parameters
    ----------
    gears : :class:`~gearcalc.pins.operating.Gears`
        The points' gears: z1, z2, e [mm], R_b [mm], K1 or R_p [mm] (the other NaN), n_d, rotating, r [mm], b [mm]
        (NaN: none; for the contact stress and the axle pressure), the crank bearing's exponent p [-].
    friction : :class:`~gearcalc.pins.operating.FrictionCoefficients`
        f [-], f_k [mm], f_c [-] per point.
    op : :class:`~gearcalc.pins.operating.OperatingPoint`
        T [N·m], n_H [rpm] (NaN: none), the mode and the shaft T is given on, per point.
    consistent : array_like of bool
        Points of the friction-consistent model (pins.md §4.9).
    tol : float
        Relative accuracy target of the cycle integrals.
    xp : SCALAR_OPS for one point on scalars; default ARRAY_OPS.
    first_order_peaks : bool
        Whether the points need the friction-free per-pin peaks (not when all are consistent with one disc).

    Returns
    -------
    IdealPoints

    Examples
    --------
    The paper's u = 10 gear (z1 = 20, z2 = 22, e = 3.9 mm, K1 = 0.75, R_b = 1.95 mm), fixed pins, f = 0.1,
    100 N·m on H as a multiplier: the first-order and the friction-consistent efficiency (the paper reads about
    0.85 off its Fig. 3a, pins.md §10):

    >>> from gearcalc.pins import SCALAR_OPS
    >>> p = ideal_points(Gears(20, 22, 3.9, 1.95, 0.75, float("nan")), FrictionCoefficients(0.1, 0.01, 0.1),
    ...                  OperatingPoint(100.0, 1000.0, True, False), np.array([True]), xp=SCALAR_OPS)
    >>> round(float(p.et.efficiency), 4), round(float(p.consistent.efficiency), 4)
    (0.858, 0.8736)

    References
    ----------
    .. [1] pins.md §4.4-4.9 (scaling, efficiencies, friction-consistent model), §6, §8.
    """
    from .operating import ARRAY_OPS

    xp = xp or ARRAY_OPS
    one = xp is SCALAR_OPS
    z1, z2, k = gears.z1, gears.z2, gears.k
    Rp, omk = pin_circle(z1, z2, gears.e, gears.Rp, gears.K1, xp)     # pins.md §7: R_p or K1; NaN raises no warning
    K1 = gears.e * z2 / (k * Rp)                                      # as Cycloid.K1
    cyc, gi = _solve_geometries(gears, Rp, omk, one, tol, first_order_peaks)

    def field(name):
        arr = getattr(cyc, name)
        return arr.item(0) if one else arr[gi]

    status, psi_star, psi_0 = field("status"), field("psi_star"), field("psi_0")
    # operating points: lambda_bar = mu_eff * unit, forces ∝ T_sat, speeds ∝ omega_V (pins.md §4.4-4.7)
    mu, rolls = friction_regime(gears.rotating, gears.Rb, gears.r, friction.f, friction.f_k, friction.f_c, xp)
    pf = PinFriction(mu, friction.f, rolls)
    lam, E = mu * field("loss_ratio"), mu * field("loss_ratio_err")
    et = efficiency_torques(lam, E, op.T, z1 / k, op.multiplier, op.torque_on_V, xp)
    unit = SimpleNamespace(**{name: field(name) for name in _UNIT_FIELDS}, psi_0=psi_0, psi_star=psi_star)
    sc = scale_unit_cycle(unit, lam, pf, et.T_V, op.n_H, gears, xp)
    p, cons = consistent_outputs(cyc, gi, np.asarray(consistent), gears, pf, op,
                                 SatelliteLoad(sc.torque_sat, sc.omega_V), tol)
    nd_a = np.zeros(np.size(consistent), dtype=np.int64) + np.asarray(gears.n_d)
    return IdealPoints(cyc, gi, one, z1, z2, gears.e, Rp, gears.Rb, omk, gears.n_d, k, K1, status, psi_star, psi_0, mu,
                       rolls, lam, E, et, sc, p, cons, cons & (nd_a == 1), cons & (nd_a > 1))


_UNIT_FIELDS = ("force", "total", "loss", "rel_min", "rel_max", "rel_abs", "force_phase", "loss_phase")
"""The :class:`~gearcalc.pins.ideal.IdealCycles` fields :func:`~gearcalc.pins.operating.scale_unit_cycle` scales."""


def _solve_geometries(gears: Gears, Rp, omk, one: bool, tol: float, first_order_peaks: bool):
    """The distinct geometries of the points solved together (:func:`~gearcalc.pins.ideal.ideal_cycles`).

    Returns the :class:`~gearcalc.pins.ideal.IdealCycles` and each point's geometry in it; one point: its gear alone
    (``first_order_peaks``: whether it needs the friction-free per-pin peaks).
    """
    z1, z2, e, Rb, n_d = gears.z1, gears.z2, gears.e, gears.Rb, gears.n_d
    if one:
        gi = np.zeros(1, dtype=np.int64)
        g = Cycloid(np.array([z1]), np.array([z2]), np.array([e]), np.array([Rp]), np.array([Rb]), np.array([omk]))
        return ideal_cycles(g, np.array([n_d]), tol=tol, first_order_peaks=first_order_peaks), gi
    key = np.stack([z1, z2, e, Rp, omk, Rb, n_d], axis=1).astype(float)
    uniq, gi = np.unique(key, axis=0, return_inverse=True)
    gi = gi.reshape(-1)
    g = Cycloid(uniq[:, 0].astype(np.int64), uniq[:, 1].astype(np.int64), uniq[:, 2], uniq[:, 3], uniq[:, 5],
                uniq[:, 4])
    return ideal_cycles(g, uniq[:, 6].astype(np.int64), tol=tol, first_order_peaks=first_order_peaks), gi
