"""Roller stiffness and the load distribution over the rollers (spec zstk.md §5).

Zero clearance: direction root (§5.1); clearance or preload: bracketed 1-D root along the load,
or Newton on the convex potential (§5.2).

References
----------
The seed paper by Merko et al. (seed 003), cited in full in :mod:`gearcalc.zstk`; docs/spec/zstk.md.
"""
from __future__ import annotations

__all__ = ['LOAD_EXPONENT', 'E_STAR_REF', 'roller_stiffness', 'LoadSolution', 'load_zero_clearance',
           'load_along_direction', 'load_with_clearance', 'solve_loads']

from dataclasses import dataclass, field

import numpy as np

from .. import hertz
from ..roots import find_root
from .geometry import broadcast, wrap_angle


LOAD_EXPONENT = 10.0 / 9.0
"""Exponent of the roller load-deflection law F = c_L·delta^(10/9) (line contact)."""
E_STAR_REF = 2.1e5 / (2.0 * (1.0 - 0.3 ** 2))
"""Contact modulus of two steel bodies (E = 2.1e5 MPa, nu = 0.3) [MPa] (spec §11.4)."""


# ----------------------------------------------------------------------------- materials
def roller_stiffness(length, e_star_inner=E_STAR_REF, e_star_outer=E_STAR_REF):
    r"""Roller load-deflection constant c_L of both contacts in series [N/mm^(10/9)].

    .. math:: c_L = 35948\, l^{8/9} \left[\tfrac12 \left((E^*_{ref}/E^*_B)^{0.9} +
              (E^*_{ref}/E^*_H)^{0.9}\right)\right]^{-10/9}

    c_L = 35 948 l^(8/9) for steel, scaled for other materials by
    [½((E*_ref/E*_B)^0.9 + (E*_ref/E*_H)^0.9)]^(-10/9).

    Parameters
    ----------
    length : roller working length l [mm].
    e_star_inner, e_star_outer : contact moduli E*_B, E*_H [MPa].

    Returns
    -------
    c_L [N/mm^(10/9)]

    Examples
    --------
    >>> round(float(roller_stiffness(20.0)), 1) == round(35948.0 * 20.0 ** (8 / 9), 1)
    True

    References
    ----------
    ISO/TS 16281:2008 (roller stiffness 35 948 L^(8/9)); Harris T.A., Kotzalas M.N., Rolling Bearing Analysis
    (Palmgren's line-contact deflection); docs/spec/zstk.md §5 item 4, §11.4.
    """
    scale = 0.5 * ((E_STAR_REF / e_star_inner) ** 0.9 + (E_STAR_REF / e_star_outer) ** 0.9)
    return hertz.iso_roller_stiffness(length) * scale ** (-10.0 / 9.0)


# ----------------------------------------------------------------------------- §5 loads
@dataclass
class LoadSolution:
    """Roller forces at the inner contacts and the inner-ring displacement.

    force : F_iB [N], shape (..., N).  alpha : direction of the displacement [rad], shape (...).
    approach : delta [mm] along alpha (may be < 0 with preload).  residual : |sum F n - Q u|
    [N].  transverse : |component of sum F n normal to u| [N].  converged : target met.
    """

    force: np.ndarray
    alpha: np.ndarray
    approach: np.ndarray
    residual: np.ndarray
    transverse: np.ndarray
    converged: np.ndarray = field(default_factory=lambda: np.array(True))


def _per_roller(x):
    """A per-configuration quantity (scalar or shape (...)) shaped to broadcast against (..., N)."""
    return np.asarray(x, dtype=float)[..., None]


def _residual(force, normal_angle, gamma, load):
    fx = np.sum(force * np.cos(normal_angle - gamma[..., None]), axis=-1) - load
    fy = np.sum(force * np.sin(normal_angle - gamma[..., None]), axis=-1)
    return np.hypot(fx, fy), np.abs(fy)


def _min_norm_direction(normal_angle, alpha, loaded):
    """With a single loaded roller the displacement is not unique: take it along its normal."""
    single = np.sum(loaded, axis=-1) == 1
    if not np.any(single):
        return alpha
    j = np.argmax(loaded, axis=-1)
    nj = np.take_along_axis(normal_angle, j[..., None], axis=-1)[..., 0]
    return np.where(single, nj, alpha)


def load_zero_clearance(normal_angle, gamma, load, stiffness, symmetric=False, fixed_direction=False):
    r"""Roller forces without clearance: the direction root of spec §5.1.

    .. math:: \arg G(\alpha) = \gamma, \quad G = \sum_i \max(n_i \cdot w, 0)^{10/9} n_i, \qquad F_{iB} = Q
              \frac{a_i^{10/9}}{\sum_j a_j^{10/9} (n_j \cdot u)}

    With a_i = max(n_Bi·w, 0) and G(alpha) = sum a_i^(10/9) n_Bi, solve arg G(alpha) = gamma on
    [gamma - 90°, gamma + 90°]; then F_iB = Q a_i^(10/9)/sum_j a_j^(10/9)(n_Bj·u) and
    delta = [Q/(c_L sum_j a_j^(10/9)(n_Bj·u))]^(9/10).  Symmetric configurations (and the
    ``fixed_direction`` level) take alpha = gamma, the closed form
    F_iB = Q cos^(10/9) psi_i / sum cos^(19/9) psi_j.

    Parameters
    ----------
    normal_angle : polar angles of the inner normals n_Bi [rad], shape (..., N).
    gamma : load direction [rad], shape broadcastable to (...).
    load : Q [N]; stiffness : c_L [N/mm^(10/9)]; scalars or arrays broadcastable to (...).
    symmetric : bool (array) marking mirror-symmetric configurations.
    fixed_direction : take v parallel to u everywhere (the classical model).

    Returns
    -------
    LoadSolution

    Examples
    --------
    >>> ang = np.radians(np.arange(0.0, 360.0, 30.0))
    >>> sol = load_zero_clearance(ang, 0.0, 1000.0, 1e5)
    >>> round(float(np.sum(sol.force * np.cos(ang))), 9)
    1000.0

    References
    ----------
    Merko M.A. et al., «Анализ нормальных напряжений на площадках контакта звеньев механизмов с ЗСТК ...» (seed
    003_2d1da402cb0b8488.txt; no journal given; see :mod:`gearcalc.zstk`) (the loads F_iB come from its ref. [3], not
    available); docs/spec/zstk.md §5, §5.1; NSK technical catalogue E728 (Stribeck 4.37 / 4.08).
    """
    normal_angle = np.asarray(normal_angle, dtype=float)
    gamma = broadcast(np.asarray(gamma, dtype=float), normal_angle.shape[:-1]).copy()
    p = LOAD_EXPONENT
    fixed = broadcast(np.asarray(symmetric) | bool(fixed_direction), gamma.shape)

    rel = normal_angle - gamma[..., None]
    cos_rel, sin_rel = np.cos(rel), np.sin(rel)
    alpha = gamma.copy()
    a = np.maximum(cos_rel, 0.0)  # a_i at alpha = gamma (the fixed-direction / symmetric value)
    free = ~fixed
    if np.any(free):
        g_free = gamma[free]
        ang_free = normal_angle[free]
        cos_n, sin_n = np.cos(ang_free), np.sin(ang_free)
        cr, sr = cos_rel[free], sin_rel[free]

        def f(al):
            # arg G(alpha) - gamma, with G = sum max(n_i.w, 0)^(10/9) n_i
            a = np.maximum(cos_n * np.cos(al)[..., None] + sin_n * np.sin(al)[..., None], 0.0) ** p
            return np.arctan2(np.sum(a * sr, axis=-1), np.sum(a * cr, axis=-1))

        res = find_root(f, g_free - 0.5 * np.pi, g_free + 0.5 * np.pi, xtol=1e-15)
        alpha[free] = res.root
        a_free = np.maximum(np.cos(ang_free - alpha[free][..., None]), 0.0)
        alpha[free] = _min_norm_direction(ang_free, alpha[free], a_free > 0)
        a = a.copy() if not a.flags.writeable else a
        a[free] = np.maximum(np.cos(ang_free - alpha[free][..., None]), 0.0)
    a = a ** p
    denom = np.sum(a * cos_rel, axis=-1)
    force = _per_roller(load) * a / denom[..., None]
    approach = (load / (stiffness * denom)) ** (1.0 / p)
    fx = np.sum(force * cos_rel, axis=-1) - load
    fy = np.sum(force * sin_rel, axis=-1)
    return LoadSolution(force, alpha, approach, np.hypot(fx, fy), np.abs(fy), np.ones(gamma.shape, bool))


def _force_law(approach, stiffness):
    return stiffness * np.maximum(approach, 0.0) ** LOAD_EXPONENT


def load_along_direction(normal_angle, gamma, load, stiffness, clearance):
    r"""Roller forces with clearance (or preload) and v parallel to u (spec §5.2, symmetric case).

    .. math:: f(\delta) = \sum_i c_L \max(\delta \cos\psi_i - s/2, 0)^{10/9} \cos\psi_i - Q = 0

    Solves f(delta) = sum c_L max(delta cos psi_i - s/2, 0)^(10/9) cos psi_i - Q = 0 (f is
    non-decreasing) with the bracketed root finder: for s >= 0 on [s/(2m), ((Q/(c_L m))^0.9 +
    s/2)/m], m = max cos psi_i; for s < 0 on a bracket doubled outward.

    Parameters
    ----------
    normal_angle : [rad], (..., N); gamma : [rad], (...); load : Q [N];
    stiffness : c_L; clearance : s [mm] (< 0 preload); load, stiffness and clearance are scalars or
    arrays broadcastable to (...).

    Returns
    -------
    LoadSolution (alpha = gamma).

    Examples
    --------
    >>> ang = np.radians(np.arange(0.0, 360.0, 30.0))
    >>> sol = load_along_direction(ang, 0.0, 1000.0, 1e5, 0.01)
    >>> round(float(np.sum(sol.force * np.cos(ang))), 6)
    1000.0

    References
    ----------
    docs/spec/zstk.md §5.2 (symmetric case).
    """
    normal_angle = np.asarray(normal_angle, dtype=float)
    gamma = broadcast(np.asarray(gamma, dtype=float), normal_angle.shape[:-1]).copy()
    cos_psi = np.cos(normal_angle - gamma[..., None])
    shape = gamma.shape
    load, stiffness, clearance = (broadcast(np.asarray(x, dtype=float), shape) for x in
                                  (load, stiffness, clearance))
    half = 0.5 * clearance
    half_r, stiff_r = half[..., None], stiffness[..., None]
    m = np.max(cos_psi, axis=-1)

    def f(delta):
        return np.sum(_force_law(delta[..., None] * cos_psi - half_r, stiff_r) * cos_psi, axis=-1) - load

    base = (load / (stiffness * m)) ** 0.9
    clear = clearance >= 0
    # s >= 0: [s/(2m), ((Q/(c_L m))^0.9 + s/2)/m] with a 1 % margin (round-off in d may leave f(hi) a hair
    # below 0); s < 0: a bracket around 0 doubled outward
    width = np.where(clear, base / m, (base + np.abs(half)) / m)
    lo = np.where(clear, half / m, -width)
    hi = np.where(clear, (1.01 * base + half) / m, width)
    for _ in range(200):  # widen outward until the bracket holds a sign change
        flo, fhi = f(lo), f(hi)
        if np.all(flo <= 0) and np.all(fhi >= 0):
            break
        lo = np.where(flo > 0, lo - width, lo)
        hi = np.where(fhi < 0, hi + width, hi)
        width = 2.0 * width
    res = find_root(f, lo, hi, xtol=1e-17 * (np.abs(clearance) + base))
    delta = res.root
    force = _force_law(delta[..., None] * cos_psi - half_r, stiff_r)
    residual, transverse = _residual(force, normal_angle, gamma, load)
    return LoadSolution(force, gamma, delta, residual, transverse, res.converged)


def _newton(c0, vx, vy, nx, ny, ux, uy, load, stiffness, scale0, rtol, maxiter):
    """Newton with backtracking on Pi(x) = c_L (9/19) sum max(c0_i + x·n_i, 0)^(19/9) - Q u·x (vectorised).

    Returns (x_x, x_y, a, force, converged); an element stops when its residual meets the target or
    no step decreases Pi or the residual any more (the round-off floor).
    """
    p = LOAD_EXPONENT
    k19 = stiffness * 9.0 / 19.0
    stiff_r = _per_roller(stiffness)

    def state(vx, vy):
        d = c0 + vx[..., None] * nx + vy[..., None] * ny
        a = np.maximum(d, 0.0)
        force = stiff_r * a ** p
        gx = np.sum(force * nx, axis=-1) - load * ux
        gy = np.sum(force * ny, axis=-1) - load * uy
        pot = k19 * np.sum(a ** (p + 1.0), axis=-1) - load * (ux * vx + uy * vy)
        return a, force, gx, gy, pot

    a, force, gx, gy, pot = state(vx, vy)
    converged = np.hypot(gx, gy) <= rtol * (load + np.sum(force, axis=-1))
    done = converged.copy()
    for _ in range(maxiter):
        if np.all(done):
            break
        w = stiff_r * p * a ** (p - 1.0)
        hxx, hxy, hyy = np.sum(w * nx * nx, -1), np.sum(w * nx * ny, -1), np.sum(w * ny * ny, -1)
        lam = 1e-12 * (hxx + hyy) + 1e-9 * scale0 * ((hxx + hyy) == 0)
        hxx, hyy = hxx + lam, hyy + lam
        det = hxx * hyy - hxy * hxy
        det = np.where(det > 1e-14 * (hxx + hyy) ** 2, det, (hxx + hyy) ** 2 * 1e-14)
        dx = -(hyy * gx - hxy * gy) / det
        dy = -(hxx * gy - hxy * gx) / det
        slope = gx * dx + gy * dy
        t = np.ones_like(vx)
        acc = done.copy()
        gnorm = np.hypot(gx, gy)
        nvx, nvy = vx.copy(), vy.copy()
        for _ in range(40):
            tx, ty = vx + t * dx, vy + t * dy
            _, _, tgx, tgy, tpot = state(tx, ty)
            ok = ~acc & ((tpot <= pot + 1e-4 * t * slope) | (np.hypot(tgx, tgy) < gnorm))
            nvx, nvy = np.where(ok, tx, nvx), np.where(ok, ty, nvy)
            acc |= ok
            if np.all(acc):
                break
            t = np.where(acc, t, 0.5 * t)
        moved = (nvx != vx) | (nvy != vy)
        vx, vy = nvx, nvy
        a, force, gx, gy, pot = state(vx, vy)
        converged = np.hypot(gx, gy) <= rtol * (load + np.sum(force, axis=-1))
        done = converged | ~moved  # no acceptable step: the round-off floor is reached
    return vx, vy, a, force, converged


def load_with_clearance(normal_angle, gamma, load, stiffness, clearance, rtol=1e-12, maxiter=100):
    r"""Roller forces with clearance or preload, full 2-D equilibrium (spec §5.2, general case).

    .. math:: \min_v \Pi(v) = c_L \tfrac{9}{19} \sum_i \max(v \cdot n_i - s/2, 0)^{19/9} - Q\, u \cdot v

    Minimises the convex potential Pi(v) = c_L (9/19) sum max(v·n_Bi - s/2, 0)^(19/9) - Q u·v by
    Newton's method with backtracking (a singular Hessian is regularised), starting from the
    zero-clearance solution shifted by s/2 along w; stops when |sum F_iB n_Bi - Q u| <=
    rtol·(Q + sum F_iB) (spec §11.1).  Vectorised: the 2x2 systems of all configurations are
    solved together.

    Parameters
    ----------
    normal_angle : [rad], (..., N); gamma : [rad], (...); load : Q [N]; stiffness : c_L;
    clearance : s [mm]; load, stiffness and clearance are scalars or arrays broadcastable to (...);
    rtol : residual target; maxiter : Newton iteration cap.

    Returns
    -------
    LoadSolution (approach >= 0 along alpha; converged marks the target met).

    Examples
    --------
    >>> ang = np.radians(np.arange(0.0, 360.0, 30.0) + 7.0)
    >>> sol = load_with_clearance(ang, 0.0, 1000.0, 1e5, 0.01)
    >>> bool(sol.residual <= 1e-12 * (1000.0 + np.sum(sol.force)))
    True

    References
    ----------
    docs/spec/zstk.md §5.2, §11.1.
    """
    normal_angle = np.asarray(normal_angle, dtype=float)
    gamma = broadcast(np.asarray(gamma, dtype=float), normal_angle.shape[:-1]).copy()
    nx, ny = np.cos(normal_angle), np.sin(normal_angle)
    ux, uy = np.cos(gamma), np.sin(gamma)
    shape = gamma.shape
    load, stiffness, clearance = (broadcast(np.asarray(x, dtype=float), shape) for x in
                                  (load, stiffness, clearance))
    half = 0.5 * clearance
    half_r = half[..., None]
    p = LOAD_EXPONENT

    start = load_zero_clearance(normal_angle, gamma, load, stiffness)
    # Newton on the offset x = v - v0 from a base point v0 at which the rollers that carry a light load
    # touch exactly, so that the approaches c0_i + x·n_i carry no cancellation of s/2 against v·n_i
    # and deflections far below eps·s stay resolved.  With clearance (s > 0) v0 is the vertex of the
    # clearance polygon {v: v·n_i <= s/2} farthest along u: the corner of the two rollers whose
    # normals bracket the load direction (c0 = 0 exactly for both); with preload v0 = 0.
    # Start: v = v0 + delta_0 w_0.
    clear = clearance > 0
    v0x, v0y = np.zeros(shape), np.zeros(shape)
    c0 = broadcast(-half_r, normal_angle.shape).copy()
    if np.any(clear):
        rel = wrap_angle(normal_angle - gamma[..., None])
        below = np.argmax(np.where(rel <= 0, rel, -np.inf), axis=-1)[..., None]
        above = np.argmin(np.where(rel > 0, rel, np.inf), axis=-1)[..., None]
        pair = np.concatenate([below, above], axis=-1)
        jx, jy = np.take_along_axis(nx, pair, -1), np.take_along_axis(ny, pair, -1)
        det = jx[..., 0] * jy[..., 1] - jx[..., 1] * jy[..., 0]
        with np.errstate(divide="ignore", invalid="ignore"):
            cx = half * (jy[..., 1] - jy[..., 0]) / det
            cy = half * (jx[..., 0] - jx[..., 1]) / det
        cc = cx[..., None] * nx + cy[..., None] * ny - half_r
        np.put_along_axis(cc, pair, 0.0, axis=-1)
        cc = np.minimum(cc, 0.0)  # v0 lies inside every other roller's play (round-off guard)
        v0x, v0y = np.where(clear, cx, v0x), np.where(clear, cy, v0y)
        c0 = np.where(clear[..., None], cc, c0)
    # regularisation scale of a singular Hessian (no loaded roller), per configuration
    scale0 = stiffness * p * np.maximum(start.approach, 1e-300) ** (p - 1.0)
    xx, xy = start.approach * np.cos(start.alpha), start.approach * np.sin(start.alpha)
    xx, xy, a, force, converged = _newton(c0, xx, xy, nx, ny, ux, uy, load, stiffness, scale0, rtol, maxiter)
    vx, vy = xx + v0x, xy + v0y
    # a single loaded roller leaves v free across its normal: take the minimum-norm v (spec §11.3)
    loaded = a > 0
    single = np.sum(loaded, axis=-1) == 1
    if np.any(single):
        j = np.argmax(loaded, axis=-1)[..., None]
        njx, njy = np.take_along_axis(nx, j, -1)[..., 0], np.take_along_axis(ny, j, -1)[..., 0]
        t = vx * njx + vy * njy
        px, py = t * njx, t * njy
        others = (px[..., None] * nx + py[..., None] * ny - half_r) * ~loaded
        use = single & np.all(others <= 0, axis=-1)
        vx, vy = np.where(use, px, vx), np.where(use, py, vy)
    delta = np.hypot(vx, vy)
    alpha = np.arctan2(vy, vx)
    residual, transverse = _residual(force, normal_angle, gamma, load)
    return LoadSolution(force, alpha, delta, residual, transverse, converged)


def solve_loads(normal_angle, gamma, load, stiffness, clearance=0.0, symmetric=False,
                fixed_direction=False):
    r"""Dispatch to the load model (spec §5, §8): closed form, direction root, 1-D or Newton solve.

    .. math:: \sum_i F_{iB}\,n_{Bi} = Q\,u, \qquad F_{iB} = c_L \max(v \cdot n_{Bi} - s/2,\ 0)^{10/9}

    (closed form F_iB = Q cos^(10/9) psi_i / sum cos^(19/9) psi_j for a symmetric configuration without clearance).

    Parameters
    ----------
    normal_angle [rad] (..., N); gamma [rad] (...); load Q [N]; stiffness c_L; clearance s [mm]
    (load, stiffness, clearance: scalars, or arrays broadcastable to (...) for stacked designs);
    symmetric : mirror-symmetric configuration (v parallel to u exactly), bool or array (...);
    fixed_direction : the ``fixed-direction`` level (v parallel to u everywhere).

    Returns
    -------
    LoadSolution

    Examples
    --------
    >>> ang = np.radians(np.arange(0.0, 360.0, 45.0))
    >>> round(float(solve_loads(ang, 0.0, 800.0, 1e5, symmetric=True).force[0]), 6)
    407.700684
    >>> two = solve_loads(np.stack([ang, ang]), 0.0, 800.0, 1e5, np.array([0.0, 0.01]), symmetric=True)
    >>> np.round(two.force[:, 0], 6).tolist()
    [407.700684, 472.738137]

    References
    ----------
    docs/spec/zstk.md §5, §8 (model levels).
    """
    if np.ndim(clearance) == 0:  # one clearance for every configuration
        if clearance == 0.0:
            return load_zero_clearance(normal_angle, gamma, load, stiffness, symmetric, fixed_direction)
        if fixed_direction or np.all(symmetric):
            return load_along_direction(normal_angle, gamma, load, stiffness, clearance)
        return load_with_clearance(normal_angle, gamma, load, stiffness, clearance)
    # stacked designs: each configuration goes to its own solver, the results are scattered back
    normal_angle = np.asarray(normal_angle, dtype=float)
    shape = normal_angle.shape[:-1]
    gamma, load, stiffness, clearance = (broadcast(np.asarray(x, dtype=float), shape) for x in
                                         (gamma, load, stiffness, clearance))
    symmetric = broadcast(np.asarray(symmetric, dtype=bool), shape)
    zero = clearance == 0.0
    along = ~zero & (symmetric | bool(fixed_direction))
    groups = [(zero, lambda k: load_zero_clearance(normal_angle[k], gamma[k], load[k], stiffness[k],
                                                    symmetric[k], fixed_direction)),
              (along, lambda k: load_along_direction(normal_angle[k], gamma[k], load[k], stiffness[k],
                                                     clearance[k])),
              (~zero & ~along, lambda k: load_with_clearance(normal_angle[k], gamma[k], load[k], stiffness[k],
                                                             clearance[k]))]
    groups = [(m, solve) for m, solve in groups if np.any(m)]
    if len(groups) == 1:
        return groups[0][1](Ellipsis)
    out = LoadSolution(np.empty(normal_angle.shape), np.empty(shape), np.empty(shape), np.empty(shape),
                       np.empty(shape), np.empty(shape, bool))
    for m, solve in groups:
        part = solve(m)
        for name in ("force", "alpha", "approach", "residual", "transverse", "converged"):
            getattr(out, name)[m] = getattr(part, name)
    return out


