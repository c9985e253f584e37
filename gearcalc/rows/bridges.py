"""The compliant carrier and its equalising bridges: the carrier's axle displacements, the guided
Timoshenko beam compliance, and the bridge sizing of eq. (2) (rows.md §5).

Pure functions over floats and numpy arrays; units N, mm, N·mm, MPa (= N/mm²), rad.

References
----------
.. [1] The seed paper 004, cited in full in :mod:`gearcalc.rows`; docs/spec/rows.md (the
   section numbers "rows.md §x" refer to it).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .geometry import DEFAULT_SECTION_PER_RIM, face_geometry, rims_fit
from .sharing import KAPPA_STEPWISE_MAX, stepwise_active_set, stepwise_active_set_batch

__all__ = ["Verification", "carrier_compliance", "verify_carrier", "bridges_fit", "largest_feasible_width",
           "carrier_displacements", "carrier_matrix", "beam_compliance", "bridge_width_for_compliance",
           "size_bridges", "FLAGS", "size_bridges_batch", "carrier_compliance_batch", "verify_carrier_batch",
           "fits_batch", "feasible_widths", "feasible_rows"]

FLAGS = ("ok", "axes_too_stiff", "exceeds_max", "no_room")
"""The feasibility flags of a span (rows.md §5.5), in the order of :func:`size_bridges_batch`'s codes."""


def carrier_displacements(forces, lever_radius, planets_per_row, stiffness):
    """Axle mid-span displacements y_j of a compliant carrier under planet forces (rows.md §5.5).

    ``T_c,j = n_w a_w (Σ_{k<j} F_k + F_j/2)``, ``ψ_n = 0``, ``ψ_{j-1} = ψ_j + T_c,j / k_j``,
    ``y_j = a_w (ψ_{j-1} + ψ_j)/2``.

    Parameters
    ----------
    forces : F_j, tangential load of one planet on its axle, per row [N]
    lever_radius : a_w [mm]
    planets_per_row : n_w
    stiffness : k_j, torsional stiffness of span j [N·mm/rad]

    Returns
    -------
    y [mm], per row

    Examples
    --------
    >>> carrier_displacements([1.0, 1.0], 100.0, 3, [1e6, 1e6]).tolist()   # T_c = 3 x 100 x (0.5, 1.5) N·mm
    [0.0525, 0.0225]

    References
    ----------
    .. [1] Seed paper 004_971077b94d8d4426.txt (multi-row planetary gears; title, authors and journal not
       recoverable), its carrier with bridges; gearcalc specification docs/spec/rows.md §5.1, §5.5.
    """
    F = np.asarray(forces, float)
    Tc = planets_per_row * lever_radius * (np.cumsum(F) - 0.5 * F)
    dpsi = Tc / np.asarray(stiffness, float)
    # ψ_{j-1} = Σ_{m≥j} dpsi_m ; cheeks 0..n
    psi = np.concatenate([np.cumsum(dpsi[::-1])[::-1], [0.0]])
    return lever_radius * 0.5 * (psi[:-1] + psi[1:])


def carrier_matrix(lever_radius, planets_per_row, stiffness, rows: int):
    """Matrix Y with y = Y F for :func:`carrier_displacements` (linear in the forces).

    Examples
    --------
    >>> carrier_matrix(100.0, 3, [1e6, 1e6], 2).tolist()   # columns: unit force on row 1, on row 2
    [[0.0375, 0.015], [0.015, 0.0075]]

    References
    ----------
    .. [1] Seed paper 004_971077b94d8d4426.txt (multi-row planetary gears; title, authors and journal not
       recoverable), its carrier with bridges; gearcalc specification docs/spec/rows.md §5.5.
    """
    return np.stack([carrier_displacements(np.eye(rows)[k], lever_radius, planets_per_row, stiffness)
                     for k in range(rows)], axis=1)


def beam_compliance(length, second_moment, area, youngs_modulus, poisson):
    """Compliance of a guided (clamped-clamped) Timoshenko beam under relative end translation.

    ``δ = (l/E) [ l²/(12 I) + 2.4(1+ν)/S ]``   (rows.md §5.1; 2.4(1+ν)/E = 1.2/G, shear factor 1.2)

    Parameters
    ----------
    length : l [mm]; second_moment : I [mm⁴]; area : S [mm²]
    youngs_modulus : E [MPa]; poisson : ν

    Returns
    -------
    δ [mm/N]

    Examples
    --------
    >>> d = 20.0   # a round axle, l = 40 mm: (40/2e5) (40²/(12 π d⁴/64) + 2.4 x 1.3/(π d²/4))
    >>> round(float(beam_compliance(40.0, math.pi * d**4 / 64, math.pi * d**2 / 4, 2e5, 0.3)) * 1e6, 6)
    5.381559

    References
    ----------
    .. [1] Seed paper 004_971077b94d8d4426.txt (multi-row planetary gears; title, authors and journal not
       recoverable), its axle and bridge compliances; gearcalc specification docs/spec/rows.md §5.1.
    """
    return length / youngs_modulus * (length**2 / (12.0 * second_moment) + 2.4 * (1.0 + poisson) / area)


def bridge_width_for_compliance(compliance, length, thickness, youngs_modulus, poisson):
    """Bridge width H whose compliance equals the required one (rows.md §5.3).

    Solves ``H³ - p H² - q = 0`` with ``p = 2.4(1+ν) l/(E h δ*)``, ``q = l³/(E h δ*)`` by Newton
    from ``H = p + q^{1/3}`` (monotone convergence: the cubic is increasing and convex right of
    its only positive root), to a relative step of 1e-14.

    Examples
    --------
    >>> H = bridge_width_for_compliance(1e-5, 40.0, 20.0, 2e5, 0.3)
    >>> d = beam_compliance(40.0, 20.0 * H**3 / 12, 20.0 * H, 2e5, 0.3)
    >>> abs(float(d) / 1e-5 - 1) < 1e-12
    True

    References
    ----------
    .. [1] Seed paper 004_971077b94d8d4426.txt (multi-row planetary gears; title, authors and journal not
       recoverable), eq. (2); gearcalc specification docs/spec/rows.md §5.3.
    """
    Eh = youngs_modulus * thickness * np.asarray(compliance, float)
    p = 2.4 * (1.0 + poisson) * length / Eh
    q = length**3 / Eh
    H = p + np.cbrt(q)
    for _ in range(100):
        f = H**3 - p * H**2 - q
        df = 3.0 * H**2 - 2.0 * p * H
        step = f / df
        H = H - step
        if np.all(np.abs(step) <= 1e-14 * np.abs(H)):
            break
    return H


def size_bridges(rows: int, planets_per_row: int, sun_diameter, module, rim_width, cheek, pressure_angle,
                 ratio, axle_diameter, bridge_thickness, youngs_modulus, poisson, polar_moment,
                 first_span=None):
    """Bridge widths H_j that make the carrier follow the sun's twist (eq. (2), rows.md §5.2-5.5).

    March ``D_{j+1} = (j+0.5) / (Q (n-j) - (j-0.5)/D_j)`` from the closure ``D_1`` (``H_1 = 0``
    by default, "axes only"), with ``Q = (1+ν) r_ba² (b_w+b) n_w / (E δ_o I_p cos α_w)``, then
    widths from ``D_j = 1 + (δ_o/δ_hj)(a_c/a_w)²``.  Spans that cannot be met are flagged
    (``axes_too_stiff``, ``exceeds_max``, ``no_room``) and clamped; the march continues with
    the clamped value.

    Parameters
    ----------
    rows, planets_per_row : n, n_w
    sun_diameter, module : d_a, m [mm]
    rim_width, cheek : b_w, b [mm] (span length l = b_w)
    pressure_angle : α_w [rad]
    ratio : i (sun input, ring fixed, carrier output)
    axle_diameter, bridge_thickness : d, h [mm]
    youngs_modulus, poisson : E [MPa], ν
    polar_moment : I_p of the sun with the sizing diameter [mm⁴]
    first_span : H_1 [mm], or None for "axes only" (H_1 = 0)

    Returns
    -------
    dict with ``H`` [mm], ``H_max`` [mm], ``H_rel`` = H/H_max (0 without room), ``D``, ``flags``,
    ``feasible`` (every flag ``ok``), ``Q``, ``axle_compliance`` [mm/N],
    ``stiffness`` (k_j of every span [N·mm/rad]), ``a_w``, ``a_c`` [mm].

    Examples
    --------
    >>> from gearcalc.rows.sharing import polar_moment
    >>> b_w = 3 * 90.0 / 3.5   # the paper's table, n = 3, B = 3, i = 10: H/H_max = 0, 0.10, 0.21
    >>> r = size_bridges(3, 3, 90.0, 5.0, b_w, 0.25 * b_w, math.radians(20.0), 10.0, 0.5 * b_w, 0.5 * b_w,
    ...                  2e5, 0.3, polar_moment(77.5))
    >>> r["H_rel"].round(2).tolist(), r["flags"]
    ([0.0, 0.1, 0.2], ['ok', 'ok', 'ok'])

    References
    ----------
    .. [1] Seed paper 004_971077b94d8d4426.txt (multi-row planetary gears; title, authors and journal not
       recoverable), eq. (2) and its table of H_j/H_max; gearcalc specification docs/spec/rows.md §5.2-5.6.
    """
    b = size_bridges_batch(rows, planets_per_row, sun_diameter, module, rim_width, cheek, pressure_angle, ratio,
                           axle_diameter, bridge_thickness, youngs_modulus, poisson, polar_moment, first_span)
    flags = [FLAGS[c] for c in b["flags"][0]]
    return {"H": b["H"][0], "H_max": float(b["H_max"][0]), "H_rel": b["H_rel"][0], "D": b["D"][0], "flags": flags,
            "feasible": all(f == "ok" for f in flags), "Q": float(b["Q"][0]),
            "axle_compliance": float(b["axle_compliance"][0]), "stiffness": b["stiffness"][0],
            "a_w": float(b["a_w"][0]), "a_c": float(b["a_c"][0]), "planet_teeth": float(b["planet_teeth"][0])}


# ----------------------------------------------------------------------------- verification (rows.md §5.5)
def carrier_compliance(lever_radius, planets_per_row, stiffness, rows: int, rim_width, pressure_angle, mesh_stiffness):
    """Dimensionless carrier compliance Y with ``C y / w̄ = Y u`` (rows.md §5.5).

    ``Y = C (2 b_w cos α_w) Y_F``, Y_F from :func:`carrier_matrix` (y per planet force) and
    ``F = 2 w b_w cos α_w`` the tangential load one planet puts on its axle [paper, with b_w restored].

    Parameters
    ----------
    lever_radius : a_w [mm]; planets_per_row : n_w; stiffness : k_j per span [N·mm/rad]; rows : n
    rim_width : b_w [mm]; pressure_angle : α_w [rad]; mesh_stiffness : C [N/mm²]

    Examples
    --------
    >>> Y = carrier_compliance(100.0, 3, np.array([1e9, 1e9]), 2, 40.0, 0.0, 1e4)
    >>> Y.shape, bool(Y[0, 0] > Y[1, 1] > 0)
    ((2, 2), True)

    References
    ----------
    .. [1] Seed paper 004_971077b94d8d4426.txt (multi-row planetary gears; title, authors and journal not
       recoverable), F = 2 w b_w cos α_w; gearcalc specification docs/spec/rows.md §5.1, §5.5.
    """
    force_per_load = 2.0 * rim_width * math.cos(pressure_angle)  # F / w [mm]
    return carrier_matrix(lever_radius, planets_per_row, stiffness, rows) * force_per_load * mesh_stiffness


@dataclass(frozen=True)
class Verification:
    """The stepwise load sharing with a compliant carrier (rows.md §5.5, §13.10)."""

    valid: bool
    """False where the stepwise system does not exist (κ ≥ 8, n ≥ 2): no shares"""
    shares: np.ndarray | None = None
    unloaded: list | None = None
    """1-based rows the active set left unloaded"""
    converged: bool = False
    """False if the active set did not settle within 3n iterations"""
    residual: float = 0.0

    @property
    def K(self) -> float | None:
        """K_balanced: the largest share, or None without a settled solution."""
        return float(self.shares.max()) if self.valid and self.converged else None


def verify_carrier(kappa: float, cheek_ratio: float, rows: int, carrier) -> Verification:
    """Solve the stepwise load sharing with the carrier compliance (``K_balanced``; rows.md §5.5, §13.10).

    Parameters
    ----------
    kappa : κ of the sun reading verified [-]; cheek_ratio : b̄ [-]; rows : n
    carrier : Y from :func:`carrier_compliance`

    Examples
    --------
    >>> v = verify_carrier(0.5, 0.25, 3, np.zeros((3, 3)))   # a rigid carrier: the stepwise shares
    >>> v.converged, round(v.K, 6)
    (True, 1.690909)
    >>> verify_carrier(9.0, 0.25, 3, np.zeros((3, 3))).K is None   # κ ≥ 8: not available
    True

    References
    ----------
    .. [1] Seed paper 004_971077b94d8d4426.txt (multi-row planetary gears; title, authors and journal not
       recoverable), eq. (1) with the sized carrier; gearcalc specification docs/spec/rows.md §5.5, §13.10.
    """
    if rows > 1 and kappa >= KAPPA_STEPWISE_MAX:
        return Verification(False)
    u, unloaded, converged, residual = stepwise_active_set(kappa, cheek_ratio, rows, carrier=carrier)
    return Verification(True, u, unloaded, converged, residual)


def bridges_fit(relative_width, rows: int, planets_per_row: int, sun_teeth, module, pressure_angle, ratio,
                youngs_modulus, poisson, polar_moment, cheek_ratio=0.25, cheek=None, axle_diameter=None,
                bridge_thickness=None, first_span=None) -> bool:
    """True when every span's bridge can be sized at relative width B (all flags ``ok``; rows.md §5.5).

    The face is re-derived at B (:func:`~gearcalc.rows.geometry.face_geometry`); an axle diameter or
    bridge thickness of None is 0.5 b_w at that B (rows.md §7).

    Parameters
    ----------
    relative_width : B [-]; the others as :func:`size_bridges` and :func:`~gearcalc.rows.geometry.face_geometry`;
    polar_moment : I_p of the sun with the sizing diameter [mm⁴] (does not depend on B)

    Examples
    --------
    >>> from gearcalc.rows.sharing import polar_moment
    >>> Ip = polar_moment(77.5)
    >>> args = (3, 3, 18, 5.0, math.radians(20.0), 4.0, 2e5, 0.3, Ip)
    >>> bridges_fit(3.0, *args), bridges_fit(2.97, *args)   # the capped cell n = 3, B = 3, i = 4 (rows.md §5.6)
    (False, True)

    References
    ----------
    .. [1] Seed paper 004_971077b94d8d4426.txt (multi-row planetary gears; title, authors and journal not
       recoverable), eq. (2); gearcalc specification docs/spec/rows.md §5.5.
    """
    return bool(fits_batch(relative_width, rows, planets_per_row, sun_teeth, module, pressure_angle, ratio,
                           youngs_modulus, poisson, polar_moment, cheek_ratio, cheek, axle_diameter, bridge_thickness,
                           first_span)[0])


def largest_feasible_width(relative_width, *args, iterations: int = 40, **kwargs):
    """The largest relative width B (below the given one) at which every bridge can be sized (rows.md §5.5).

    Narrower rows twist less: scan down in 1 % steps to a tenth of B for the first width where
    :func:`bridges_fit` holds, then bisect to a relative 1e-6.

    Parameters
    ----------
    relative_width : B of the design [-]
    *args, **kwargs : the arguments of :func:`bridges_fit` after B

    Returns
    -------
    B_ok [-], or None when even a tenth of B does not fit

    Examples
    --------
    >>> from gearcalc.rows.sharing import polar_moment
    >>> B = largest_feasible_width(3.0, 3, 3, 18, 5.0, math.radians(20.0), 4.0, 2e5, 0.3, polar_moment(77.5))
    >>> 2.9 < B < 3.0
    True

    References
    ----------
    .. [1] Seed paper 004_971077b94d8d4426.txt (multi-row planetary gears; title, authors and journal not
       recoverable), eq. (2); gearcalc specification docs/spec/rows.md §5.5.
    """
    def ok(B):
        return bridges_fit(B, *args, **kwargs)

    hi = relative_width
    for k in range(1, 91):  # scan down in 1 % steps to a tenth of the width for the first feasible width
        lo = hi * (1.0 - 0.01 * k)
        if ok(lo):
            break
        hi_scan = lo
    else:
        return None
    hi = hi if k == 1 else hi_scan
    for _ in range(iterations):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if ok(mid) else (lo, mid)
        if hi - lo <= 1e-6 * hi:
            break
    return lo


# ----------------------------------------------------------------------------- a batch of designs (rows.md §9)
def size_bridges_batch(rows: int, planets_per_row, sun_diameter, module, rim_width, cheek, pressure_angle, ratio,
                       axle_diameter, bridge_thickness, youngs_modulus, poisson, polar_moment, first_span=None):
    """:func:`size_bridges` over a batch of P designs with the same number of rows n (rows.md §9): the march
    loops over spans, over arrays of designs; Newton's iteration for the widths runs, for each design, until
    every width of that design has converged (as one design alone does), the converged designs masked out.

    Parameters
    ----------
    rows : n; the others as :func:`size_bridges`, each a number or an array of shape (P,);
    first_span : H_1 [mm] per design, 0 (or None) for "axes only"

    Returns
    -------
    dict of arrays: ``H``, ``H_rel``, ``D``, ``flags`` (codes into :data:`FLAGS`), ``stiffness`` of shape (P, n);
    ``H_max``, ``feasible``, ``Q``, ``axle_compliance``, ``a_w``, ``a_c``, ``planet_teeth`` of shape (P,)

    Examples
    --------
    >>> from gearcalc.rows.sharing import polar_moment
    >>> b_w = 3 * 90.0 / 3.5   # the paper's table, n = 3, B = 3, i = 10 and 4 (size_bridges' example)
    >>> r = size_bridges_batch(3, 3, 90.0, 5.0, b_w, 0.25 * b_w, math.radians(20.0), np.array([10.0, 4.0]),
    ...                        0.5 * b_w, 0.5 * b_w, 2e5, 0.3, polar_moment(77.5))
    >>> r["H_rel"].round(2).tolist(), [[FLAGS[c] for c in f] for f in r["flags"]]
    ([[0.0, 0.1, 0.2], [0.0, 0.47, 1.0]], [['ok', 'ok', 'ok'], ['ok', 'ok', 'exceeds_max']])

    References
    ----------
    .. [1] Seed paper 004_971077b94d8d4426.txt (multi-row planetary gears; title, authors and journal not
       recoverable), eq. (2) and its table of H_j/H_max; gearcalc specification docs/spec/rows.md §5.2-5.6, §9.
    """
    n = rows
    args = np.broadcast_arrays(*(np.asarray(v, float) for v in (
        planets_per_row, sun_diameter, module, rim_width, cheek, pressure_angle, ratio, axle_diameter,
        bridge_thickness, youngs_modulus, poisson, polar_moment, 0.0 if first_span is None else first_span)))
    nw, d_a, m, span, cheek, alpha, ratio, d, h, E, nu, Ip, first = (np.atleast_1d(a) for a in args)
    P = d_a.shape[0]
    cos_a = np.cos(alpha)
    r_ba = 0.5 * d_a * cos_a
    z_a = d_a / m
    z_g = z_a * (ratio - 2.0) / 2.0
    a_w = 0.25 * d_a * ratio
    a_c = 0.5 * (d_a * (ratio - 1.0) - 2.5 * m - h)
    H_max = 2.0 * math.pi * a_c / nw - m * (z_g + 1.0)
    delta_o = beam_compliance(span, math.pi * d**4 / 64.0, math.pi * d**2 / 4.0, E, nu)
    Q = (1.0 + nu) * r_ba**2 * (span + cheek) * nw / (E * delta_o * Ip * cos_a)
    geo = (a_c / a_w) ** 2

    def D_of(H):
        with np.errstate(divide="ignore", invalid="ignore"):
            dh = beam_compliance(span, h * H**3 / 12.0, H * h, E, nu)
            return np.where(H > 0, 1.0 + delta_o / dh * geo, 1.0)

    room = H_max > 0
    flags = np.where(room[:, None], 0, 3) * np.ones(n, int)
    D = np.ones((P, n))
    H = np.zeros((P, n))
    D_max = D_of(np.where(room, H_max, 1.0))
    D[:, 0] = np.where(first > 0, D_of(np.where(first > 0, first, 1.0)), 1.0)
    for j in range(1, n):  # 0-based j: span j+1 (rows.md §5.2)
        denom = Q * (n - j) - (j - 0.5) / D[:, j - 1]
        with np.errstate(divide="ignore"):
            D_req = np.where(denom > 0, (j + 0.5) / np.where(denom > 0, denom, 1.0), np.inf)
        stiff, over = D_req < 1.0, D_req > D_max
        flags[:, j] = np.where(room, np.where(stiff, 1, np.where(over, 2, 0)), 3)
        D[:, j] = np.where(stiff, 1.0, np.where(over, D_max, D_req))
    D[~room] = 1.0
    need = (D > 1.0) & (flags == 0)
    if need.any():
        with np.errstate(divide="ignore"):
            delta_star = np.where(need, delta_o[:, None] * geo[:, None] / np.where(need, D - 1.0, 1.0), 1.0)
        H = np.where(need, _widths(delta_star, need, span[:, None], h[:, None], E[:, None], nu[:, None]), 0.0)
    H = np.where(flags == 2, H_max[:, None], H)
    H[:, 0] = np.where(room & (first > 0), first, H[:, 0])
    Hs = np.maximum(H, 1e-300)
    with np.errstate(divide="ignore"):
        d_h = np.where(H > 0, beam_compliance(span[:, None], h[:, None] * Hs**3 / 12.0, Hs * h[:, None], E[:, None],
                                              nu[:, None]), np.inf)
    stiffness = nw[:, None] * ((a_w**2 / delta_o)[:, None] + np.where(H > 0, (a_c**2)[:, None] / d_h, 0.0))
    rel = np.where(room[:, None], H / np.where(room, H_max, 1.0)[:, None], 0.0)  # never 0/0 (rows.md §13.6)
    return {"H": H, "H_max": H_max, "H_rel": rel, "D": D, "flags": flags, "feasible": (flags == 0).all(axis=1),
            "Q": Q, "axle_compliance": delta_o, "stiffness": stiffness, "a_w": a_w, "a_c": a_c, "planet_teeth": z_g}


def _widths(compliance, need, length, thickness, youngs_modulus, poisson):
    """:func:`bridge_width_for_compliance` of the spans ``need`` (P, n), each design's Newton iteration stopped
    when all its spans have converged (as :func:`size_bridges` stops it for one design)."""
    Eh = youngs_modulus * thickness * compliance
    p = 2.4 * (1.0 + poisson) * length / Eh
    q = length**3 / Eh
    H = p + np.cbrt(q)
    going = np.flatnonzero(need.any(axis=1))
    for _ in range(100):
        if going.size == 0:
            break
        Hg, pg, qg = H[going], p[going], q[going]
        f = Hg**3 - pg * Hg**2 - qg
        df = 3.0 * Hg**2 - 2.0 * pg * Hg
        step = f / df
        Hg = Hg - step
        H[going] = np.where(need[going], Hg, H[going])
        done = np.all((np.abs(step) <= 1e-14 * np.abs(Hg)) | ~need[going], axis=1)
        going = going[~done]
    return H


def carrier_compliance_batch(lever_radius, planets_per_row, stiffness, rows: int, rim_width, pressure_angle,
                             mesh_stiffness):
    """:func:`carrier_compliance` over a batch: Y of shape (P, n, n) from arrays of shape (P,) (stiffness (P, n)).

    Examples
    --------
    >>> Y = carrier_compliance_batch(np.array([100.0]), 3, np.array([[1e9, 1e9]]), 2, 40.0, 0.0, 1e4)
    >>> bool(np.array_equal(Y[0], carrier_compliance(100.0, 3, np.array([1e9, 1e9]), 2, 40.0, 0.0, 1e4)))
    True

    References
    ----------
    .. [1] Seed paper 004_971077b94d8d4426.txt (multi-row planetary gears; title, authors and journal not
       recoverable), F = 2 w b_w cos α_w; gearcalc specification docs/spec/rows.md §5.1, §5.5.
    """
    a_w = np.asarray(lever_radius, float)[:, None, None]
    unit = np.eye(rows)  # row k: a unit force on row k
    Tc = planets_per_row * a_w if np.ndim(planets_per_row) == 0 else np.asarray(planets_per_row)[:, None, None] * a_w
    Tc = Tc * (np.cumsum(unit, axis=1) - 0.5 * unit)
    dpsi = Tc / np.asarray(stiffness, float)[:, None, :]
    psi = np.concatenate([np.cumsum(dpsi[..., ::-1], axis=-1)[..., ::-1], np.zeros(dpsi.shape[:2] + (1,))], axis=-1)
    y = a_w * 0.5 * (psi[..., :-1] + psi[..., 1:])  # y[p, k, j]: span j under a unit force on row k
    force_per_load = 2.0 * np.asarray(rim_width, float) * np.cos(pressure_angle)
    return np.swapaxes(y, 1, 2) * np.reshape(force_per_load, (-1, 1, 1)) * np.reshape(mesh_stiffness, (-1, 1, 1))


def verify_carrier_batch(kappa, cheek_ratio, rows: int, carrier):
    """:func:`verify_carrier` over a batch: (valid, shares (P, n), unloaded (P, n), converged, K) with K NaN where
    :attr:`Verification.K` is None (κ ≥ 8 with n ≥ 2, or an unsettled active set).

    Examples
    --------
    >>> valid, u, unloaded, converged, K = verify_carrier_batch(np.array([0.5, 9.0]), np.full(2, 0.25), 3,
    ...                                                         np.zeros((2, 3, 3)))
    >>> valid.tolist(), K.round(6).tolist()   # verify_carrier's examples
    ([True, False], [1.690909, nan])

    References
    ----------
    .. [1] Seed paper 004_971077b94d8d4426.txt (multi-row planetary gears; title, authors and journal not
       recoverable), eq. (1) with the sized carrier; gearcalc specification docs/spec/rows.md §5.5, §13.10.
    """
    kappa = np.asarray(kappa, float)
    P = kappa.shape[0]
    valid = ~((rows > 1) & (kappa >= KAPPA_STEPWISE_MAX))
    u, unloaded, converged = np.zeros((P, rows)), np.zeros((P, rows), bool), np.zeros(P, bool)
    k = np.flatnonzero(valid)
    if k.size:
        u[k], unloaded[k], converged[k] = stepwise_active_set_batch(kappa[k], np.broadcast_to(cheek_ratio, (P,))[k],
                                                                    rows, np.asarray(carrier)[k])
    ok = valid & converged
    K = np.where(ok, np.where(ok[:, None], u, -np.inf).max(axis=1), np.nan)
    return valid, u, unloaded, converged, K


# ----------------------------------------------------------------------------- where every bridge fits (rows.md §5.5)
SCAN_SPAN = 30.0
""":func:`feasible_widths` scans relative widths from B/SCAN_SPAN to B SCAN_SPAN ..."""
SCAN_POINTS = 3000
"""... at this many geometric steps (0.23 % apart: a window narrower than that may be missed) ..."""
SCAN_BISECTIONS = 24
"""... and bisects each edge of a window this many times (to a relative 1e-9)."""


def fits_batch(relative_width, rows: int, planets_per_row, sun_teeth, module, pressure_angle, ratio, youngs_modulus,
               poisson, polar_moment, cheek_ratio=0.25, cheek=None, axle_diameter=None, bridge_thickness=None,
               first_span=None):
    """:func:`bridges_fit` at every relative width of an array (one batch of :func:`size_bridges_batch`): the
    rims fit, every span's flag is ``ok`` and a first span in mm fits within H_max.

    Examples
    --------
    >>> from gearcalc.rows.sharing import polar_moment
    >>> fits_batch(np.array([2.6, 2.7, 2.97, 3.0]), 3, 3, 18, 5.0, math.radians(20.0), 4.0, 2e5, 0.3,
    ...            polar_moment(77.5)).tolist()   # the capped paper cell n = 3, B = 3, i = 4 (rows.md §5.6)
    [False, True, True, False]

    References
    ----------
    .. [1] Seed paper 004_971077b94d8d4426.txt (multi-row planetary gears; title, authors and journal not
       recoverable), eq. (2); gearcalc specification docs/spec/rows.md §5.5.
    """
    B = np.atleast_1d(np.asarray(relative_width, float))
    face = face_geometry(sun_teeth, module, rows, pressure_angle, relative_width=B, cheek_ratio=cheek_ratio,
                         cheek=cheek)
    room = np.asarray(rims_fit(face.rim_width))
    b_w = np.where(room, face.rim_width, 1.0)
    section = DEFAULT_SECTION_PER_RIM * b_w
    res = size_bridges_batch(rows, planets_per_row, face.sun_diameter, module, b_w, np.where(room, face.cheek, 0.0),
                             pressure_angle, ratio, section if axle_diameter is None else axle_diameter,
                             section if bridge_thickness is None else bridge_thickness, youngs_modulus, poisson,
                             polar_moment, first_span=first_span)
    first = 0.0 if first_span is None else first_span
    return room & res["feasible"] & ~((first > 0) & (res["H_max"] > 0) & (first > res["H_max"]))


def feasible_widths(relative_width, rows: int, *args, **kwargs) -> list:
    """The windows of relative width [B_lo, B_hi] in which every bridge fits (:func:`fits_batch`) at this number
    of rows, nearest to the given B first (rows.md §5.5).

    Feasibility is not monotone in B (the paper's capped cell fits only for 2.666 <= B <= 2.973: narrower rows
    need a bridge wider than H_max in span 2, wider ones in span 3), so the widths from B/:data:`SCAN_SPAN` to
    B :data:`SCAN_SPAN` are scanned at :data:`SCAN_POINTS` geometric steps and each edge bisected
    (:data:`SCAN_BISECTIONS` times, to a relative 1e-9); every step is one array of designs.

    Parameters
    ----------
    relative_width : B of the design [-]; rows : n;
    *args, **kwargs : the arguments of :func:`fits_batch` after ``rows``

    Returns
    -------
    list of (B_lo, B_hi): each bound a width that fits, within a relative 1e-9 of the edge; None for a window
    open beyond the scanned range

    Examples
    --------
    >>> from gearcalc.rows.sharing import polar_moment
    >>> args = (3, 18, 5.0, math.radians(20.0), 4.0, 2e5, 0.3, polar_moment(77.5))
    >>> [(round(lo, 4), round(hi, 4)) for lo, hi in feasible_widths(3.0, 3, *args)]
    [(2.6656, 2.9738)]
    >>> feasible_widths(3.0, 5, *args)   # five rows: no width fits
    []

    References
    ----------
    .. [1] Seed paper 004_971077b94d8d4426.txt (multi-row planetary gears; title, authors and journal not
       recoverable), eq. (2); gearcalc specification docs/spec/rows.md §5.5.
    """
    B = np.geomspace(relative_width / SCAN_SPAN, relative_width * SCAN_SPAN, SCAN_POINTS)
    with np.errstate(all="ignore"):
        ok = fits_batch(B, rows, *args, **kwargs)
        edges = np.flatnonzero(ok[1:] != ok[:-1])
        inside = np.where(ok[edges], B[edges], B[edges + 1])  # the side of each edge that fits
        outside = np.where(ok[edges], B[edges + 1], B[edges])
        for _ in range(SCAN_BISECTIONS if edges.size else 0):
            mid = 0.5 * (inside + outside)
            fit = fits_batch(mid, rows, *args, **kwargs)
            inside, outside = np.where(fit, mid, inside), np.where(fit, outside, mid)
    bounds = dict(zip(edges.tolist(), inside.tolist()))
    windows, start = [], None if ok[0] else False
    for k in range(SCAN_POINTS):
        if ok[k] and start is False:
            start = bounds[k - 1]
        elif not ok[k] and start is not False:
            windows.append((start, bounds[k - 1]))
            start = False
    if start is not False:
        windows.append((start, None))
    return sorted(windows, key=lambda w: min(abs(math.log(b / relative_width)) for b in w if b is not None)
                  if w != (None, None) else 0.0)


def feasible_rows(relative_width, rows: int, *args, span: int = 10, **kwargs):
    """The number of rows nearest to ``rows`` (2 to ``rows + span``, at most 1000) at which some relative width
    makes every bridge fit, and its windows (:func:`feasible_widths`); (None, []) when none has one.

    Examples
    --------
    >>> from gearcalc.rows.sharing import polar_moment
    >>> args = (3, 18, 5.0, math.radians(20.0), 4.0, 2e5, 0.3, polar_moment(77.5))
    >>> n, windows = feasible_rows(3.0, 5, *args)
    >>> n, [(round(lo, 3), round(hi, 3)) for lo, hi in windows]
    (4, [(3.999, 4.036)])

    References
    ----------
    .. [1] Seed paper 004_971077b94d8d4426.txt (multi-row planetary gears; title, authors and journal not
       recoverable), eq. (2); gearcalc specification docs/spec/rows.md §5.5.
    """
    others = sorted((n for n in range(2, min(1000, rows + span) + 1) if n != rows), key=lambda n: (abs(n - rows), n))
    for n in others:
        windows = feasible_widths(relative_width, n, *args, **kwargs)
        if windows:
            return n, windows
    return None, []
