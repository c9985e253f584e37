"""Multi-row planetary gear: row load sharing from sun torsion, equalising carrier bridges, relative mass.

Pure functions over floats and numpy arrays; units N, mm, N·mm, MPa (= N/mm²), rad.  Every
function that takes a torsion parameter ``kappa`` broadcasts over a batch of designs (arrays of
any shape); row loops run over rows, never over designs.

Reference: seed paper 004_971077b94d8d4426.txt (multi-row planetary gears, after F. I. Plekhanov),
as reconstructed in the gearcalc specification ``rows.md`` (section numbers below refer to it).
"""
from __future__ import annotations

import math

import numpy as np

from . import hertz

RESCALE = 1e250
"""The far-end recurrence rescales its running values above this (rows.md §2.5)."""
KAPPA_UNIFORM = 1e-24
"""Below this torsion parameter the exact level returns the uniform limit (rows.md §3b)."""
KAPPA_STEPWISE_MAX = 8.0
"""The stepwise level is valid only for kappa < 8 (rows.md §2.5)."""


# ----------------------------------------------------------------------------- geometry
def polar_moment(torsion_diameter, bore=0.0):
    """Polar second moment of area of a (hollow) round shaft.

    ``I_p = pi (d_I^4 - d_0^4) / 32``

    Parameters
    ----------
    torsion_diameter : d_I [mm]
    bore : d_0 [mm], 0 for a solid sun

    Returns
    -------
    I_p [mm^4]

    Examples
    --------
    >>> round(float(polar_moment(10.0)), 4)   # pi 10^4 / 32
    981.7477
    """
    return math.pi * (np.asarray(torsion_diameter, float) ** 4 - np.asarray(bore, float) ** 4) / 32.0


def rim_width(relative_width, rows, cheek_ratio, sun_diameter):
    """Planet rim (row) width from the relative sun face width.

    ``b_w = B d_a / (n + b̄ (n - 1))``  (rows.md §7; b_a = n b_w + (n-1) b, B = b_a/d_a)

    Parameters
    ----------
    relative_width : B [-]
    rows : n [-]
    cheek_ratio : b̄ = b/b_w [-]
    sun_diameter : d_a [mm]

    Returns
    -------
    b_w [mm]

    Examples
    --------
    >>> rim_width(2.4, 3, 0.25, 90.0)
    61.714285714285715
    """
    return relative_width * sun_diameter / (rows + cheek_ratio * (rows - 1))


def torsion_parameter(mesh_stiffness, base_radius, planets_per_row, rim_width, shear_modulus, polar_moment):
    """Torsion parameter κ of the sun (dimensionless).

    ``kappa = 0.5 C r_ba^2 n_w b_w^2 / (G I_p)``  (rows.md §2.3)

    Parameters
    ----------
    mesh_stiffness : C, per unit face width [N/mm²]
    base_radius : r_ba = 0.5 d_a cos α_w [mm]
    planets_per_row : n_w [-]
    rim_width : b_w [mm]
    shear_modulus : G [MPa]
    polar_moment : I_p [mm⁴]

    Returns
    -------
    kappa [-]

    Examples
    --------
    >>> torsion_parameter(2.0, 1.0, 1, 1.0, 1.0, 1.0)   # 0.5 * 2 * 1 * 1 * 1 / (1 * 1)
    1.0
    """
    return 0.5 * mesh_stiffness * base_radius**2 * planets_per_row * rim_width**2 / (shear_modulus * polar_moment)


# ----------------------------------------------------------------------------- stepwise level
def stepwise_shares(kappa, cheek_ratio, rows: int):
    """Row load ratios u_N = w_N / w̄ of the paper's stepwise model, by the far-end recurrence.

    Solves ``(1 - κ/8)(u_N - u_{N+1}) = κ(1+b̄) Σ_{k>N} u_k``, ``Σ u = n`` (rows.md §2.5):
    ``v_n = 1``, ``v_N = v_{N+1} + ρ Σ_{k>N} v_k`` with ``ρ = κ(1+b̄)/(1-κ/8)``, ``u = n v/Σv``.
    O(n), rescaled against overflow; valid for κ < 8 (for n ≥ 2).

    Parameters
    ----------
    kappa : torsion parameter κ [-], any shape S
    cheek_ratio : b̄ [-], broadcastable to S
    rows : n

    Returns
    -------
    u : array of shape S + (n,), rows from the input side; for κ ≥ 8 the entries are
        meaningless (uniform) and ``valid`` is False.
    valid : bool array of shape S

    Examples
    --------
    >>> u, ok = stepwise_shares(0.0, 0.25, 3)
    >>> u.tolist(), bool(ok)
    ([1.0, 1.0, 1.0], True)
    """
    kappa, cheek_ratio = np.broadcast_arrays(np.asarray(kappa, float), np.asarray(cheek_ratio, float))
    valid = (kappa < KAPPA_STEPWISE_MAX) | (rows == 1)
    with np.errstate(divide="ignore", invalid="ignore"):
        rho_rec = np.where(valid, kappa * (1.0 + cheek_ratio) / (1.0 - kappa / 8.0), 0.0)
    v = np.empty(kappa.shape + (rows,))
    v[..., rows - 1] = 1.0
    tail = np.ones(kappa.shape)  # Σ_{k>N} v_k (including v_{N+1})
    for N in range(rows - 2, -1, -1):
        v[..., N] = v[..., N + 1] + rho_rec * tail
        tail = tail + v[..., N]
        big = v[..., N] > RESCALE
        if np.any(big):
            scale = np.where(big, 1.0 / v[..., N], 1.0)
            v *= scale[..., None]
            tail = tail * scale
    u = rows * v / tail[..., None]
    return u, valid


def stepwise_dense(kappa: float, cheek_ratio: float, rows: int, form: str = "paper"):
    """Stepwise shares by a dense solve (cross-check for small n only; rows.md §2.5).

    ``form="paper"``: the paper's system (1) in dimensionless form (rows from row 1, nested sums)
    ``(1-κ/8)(u1-uN) = κ(1+b̄) Σ_{m<N} (n - S_m)``; ``form="difference"``: the difference form.

    Examples
    --------
    >>> bool(np.allclose(stepwise_dense(0.5, 0.25, 3), stepwise_shares(0.5, 0.25, 3)[0]))
    True
    """
    n = rows
    A = np.zeros((n, n))
    rhs = np.zeros(n)
    a = 1.0 - kappa / 8.0
    g = kappa * (1.0 + cheek_ratio)
    A[0, :] = 1.0
    rhs[0] = n
    for N in range(2, n + 1):
        r = N - 1
        if form == "paper":
            # (1-κ/8)(u1 - uN) + g Σ_{m=1}^{N-1} S_m = g (N-1) n
            A[r, 0] += a
            A[r, N - 1] -= a
            for m in range(1, N):
                A[r, :m] += g
            rhs[r] = g * (N - 1) * n
        else:
            # (1-κ/8)(u_{N-1} - u_N) - g Σ_{k≥N} u_k = 0
            A[r, N - 2] += a
            A[r, N - 1] -= a
            A[r, N - 1:] -= g
    return np.linalg.solve(A, rhs)


def twist_between(loads, p: int, q: int, sun_torque, base_radius, rim_width, cheek, planets_per_row,
                  shear_modulus, polar_moment):
    """Sun twist between the mid-planes of rows p < q (1-based) under the stepwise torque diagram.

    ``I_p G φ_{p→q} = (b_w+b) Σ_{m=p}^{q-1} (T_a - r_ba b_w n_w S_m) + 0.125 n_w b_w² r_ba (w_p - w_q)``
    (rows.md §2.1, general N and pair form).

    Parameters
    ----------
    loads : line loads w_1..w_n [N/mm]
    p, q : row numbers, 1 ≤ p < q ≤ n
    sun_torque : T_a [N·mm]
    base_radius, rim_width, cheek : r_ba, b_w, b [mm]
    planets_per_row : n_w
    shear_modulus : G [MPa]; polar_moment : I_p [mm⁴]

    Returns
    -------
    twist [rad]
    """
    w = np.asarray(loads, float)
    S = np.cumsum(w)
    k = base_radius * rim_width * planets_per_row
    body = (rim_width + cheek) * np.sum(sun_torque - k * S[p - 1:q - 1])
    half = 0.125 * planets_per_row * rim_width**2 * base_radius * (w[p - 1] - w[q - 1])
    return (body + half) / (shear_modulus * polar_moment)


# ----------------------------------------------------------------------------- exact level
def exact_shares(kappa, cheek_ratio, rows: int):
    """Row shares and within-row peak of the piecewise exact model, by the impedance sweep.

    Inside a row the sun is a torsion shaft on an elastic foundation (θ'' = λ²θ, μ = λ b_w = √κ),
    across a gap a plain shaft; T(0) = T_a, T(b_a) = 0.  The sweep propagates the dimensionless
    stiffness r = T/(G I_p λ θ) from the free end and uses only tanh and e^(-μ), so it neither
    overflows nor loses precision (rows.md §3b).

    Parameters
    ----------
    kappa : κ [-], any shape S
    cheek_ratio : b̄ [-], broadcastable
    rows : n

    Returns
    -------
    u : shares w_j / w̄ of the row-mean loads, shape S + (n,)
    peak_factor : w(0)/w̄, the load at the input edge of row 1 over the mean, shape S

    Examples
    --------
    >>> u, peak = exact_shares(1.0, 0.25, 1)
    >>> float(u[0]), round(float(peak), 6)   # n = 1: u = 1, peak = μ coth μ
    (1.0, 1.313035)
    """
    kappa, cheek_ratio = np.broadcast_arrays(np.asarray(kappa, float), np.asarray(cheek_ratio, float))
    tiny = kappa < KAPPA_UNIFORM
    mu = np.sqrt(np.where(tiny, 1.0, kappa))
    em = np.exp(-mu)
    em2 = em * em
    tau = np.tanh(mu)  # accurate for tiny and large mu alike
    sech = 2.0 * em / (1.0 + em2)
    s = np.expm1(-mu) ** 2 / (1.0 + em2)  # 1 - sech mu without cancellation
    r_in = np.empty(kappa.shape + (rows,))
    r_out = np.empty(kappa.shape + (rows,))
    ro = np.zeros(kappa.shape)
    for j in range(rows - 1, -1, -1):
        r_out[..., j] = ro
        ri = (ro + tau) / (1.0 + ro * tau)
        r_in[..., j] = ri
        ro = ri / (1.0 + cheek_ratio * mu * ri)
    mean_theta = np.empty(kappa.shape + (rows,))
    theta_in1 = 1.0 / r_in[..., 0]
    th = theta_in1
    for j in range(rows):
        ro = r_out[..., j]
        denom = 1.0 + ro * tau
        mean_theta[..., j] = th * (tau + ro * s) / (mu * denom)
        if j + 1 < rows:
            th = th * sech / denom * ro / r_in[..., j + 1]
    avg = mean_theta.mean(axis=-1)
    u = mean_theta / avg[..., None]
    peak = theta_in1 / avg
    u = np.where(tiny[..., None], 1.0, u)
    peak = np.where(tiny, 1.0, peak)
    return u, peak


def exact_k_no_gap(kappa, rows: int):
    """K of the exact level for b = 0 in closed form (rows.md §11, exact identities).

    ``K = n [1 - sinh((n-1)μ) / sinh(nμ)]``, μ = √κ, evaluated stably as
    ``n [1 - e^{-μ} (1 - e^{-2(n-1)μ}) / (1 - e^{-2nμ})]``.

    Examples
    --------
    >>> round(float(exact_k_no_gap(1.0, 3)), 6)   # 3 (1 - sinh 2 / sinh 3) = 1.913883
    1.913883
    """
    mu = np.sqrt(np.asarray(kappa, float))
    return rows * (1.0 - np.exp(-mu) * -np.expm1(-2.0 * (rows - 1) * mu) / -np.expm1(-2.0 * rows * mu))


# ----------------------------------------------------------------------------- continuous level
def x_coth_x(x):
    """x coth x, stable for small x (1 + x²/3 below 1e-4) and large x.

    Examples
    --------
    >>> float(x_coth_x(0.0)), round(float(x_coth_x(2.0)), 6)   # 2 / tanh 2 = 2.074629
    (1.0, 2.074629)
    """
    x = np.asarray(x, float)
    small = np.abs(x) < 1e-4
    with np.errstate(divide="ignore", invalid="ignore"):
        big = x / np.tanh(np.where(small, 1.0, x))
    return np.where(small, 1.0 + x * x / 3.0, big)


def continuous_k(kappa, cheek_ratio, rows):
    """K of the continuous (homogenised) model: ``K = X coth X``, ``X = λ_eff b_a`` (rows.md §3c).

    ``X = sqrt(κ/(1+b̄)) (n + b̄(n-1))`` for n ≥ 2 and ``X = √κ`` for n = 1 (the cheek gaps
    homogenised; the torsional Winkler-foundation result, Hetényi 1946).

    Examples
    --------
    >>> round(float(continuous_k(1.0, 0.0, 3)), 6)   # b = 0: X = 3, 3 coth 3 = 3.014909
    3.014909
    """
    kappa = np.asarray(kappa, float)
    rows = np.asarray(rows)
    x = np.where(rows >= 2, np.sqrt(kappa / (1.0 + cheek_ratio)) * (rows + cheek_ratio * (rows - 1)), np.sqrt(kappa))
    return x_coth_x(x)


# ----------------------------------------------------------------------------- compliant carrier
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
    """
    F = np.asarray(forces, float)
    Tc = planets_per_row * lever_radius * (np.cumsum(F) - 0.5 * F)
    dpsi = Tc / np.asarray(stiffness, float)
    # ψ_{j-1} = Σ_{m≥j} dpsi_m ; cheeks 0..n
    psi = np.concatenate([np.cumsum(dpsi[::-1])[::-1], [0.0]])
    return lever_radius * 0.5 * (psi[:-1] + psi[1:])


def carrier_matrix(lever_radius, planets_per_row, stiffness, rows: int):
    """Matrix Y with y = Y F for :func:`carrier_displacements` (linear in the forces)."""
    return np.stack([carrier_displacements(np.eye(rows)[k], lever_radius, planets_per_row, stiffness)
                     for k in range(rows)], axis=1)


def stepwise_active_set(kappa: float, cheek_ratio: float, rows: int, carrier=None, threshold: float = 1e-12):
    """Stepwise shares with unloaded rows handled by an active set (rows.md §2.5, §5.5).

    Unknowns u_1..u_n (loads over w̄) and c (the load row 1 would carry).  Active rows:
    ``u_j = c - [κ(1+b̄) Σ_{m<j}(n - S_m) + (κ/8)(u_1 - u_j)] + (Y u)_1 - (Y u)_j``, where
    ``Y`` (dimensionless, ``C y/w̄ = Y u``) is the carrier compliance (``None``: rigid carrier);
    inactive rows ``u_j = 0``; equilibrium ``Σ u = n``.  Rows with u ≤ 0 are deactivated; an
    inactive row whose implied load exceeds ``threshold`` is re-activated, the largest first.

    Returns
    -------
    u : shares [-]
    unloaded : 1-based indices of the inactive rows
    converged : False if the active set did not settle within 3n iterations
    residual : max |A x - b| / n of the final linear solve
    """
    n = rows
    g = kappa * (1.0 + cheek_ratio)
    a8 = kappa / 8.0
    Y = np.zeros((n, n)) if carrier is None else np.asarray(carrier, float)
    # Row j (0-based) of the "implied load" map: u_j = c + sum_k M[j,k] u_k + const_j
    # twist term: g Σ_{m<j} (n - S_m) = g*j*n - g Σ_{m<j} S_m ; Σ_{m<j} S_m = Σ_k (j - k)_+ u_k
    M = np.zeros((n, n))
    const = np.zeros(n)
    for j in range(n):
        const[j] = -g * j * n
        for k in range(j):
            M[j, k] += g * (j - k)
        M[j, 0] -= a8
        M[j, j] += a8
        M[j, :] += Y[0, :] - Y[j, :]
    active = np.ones(n, bool)
    u = np.zeros(n)
    residual = 0.0
    for _ in range(3 * n + 1):
        idx = np.flatnonzero(active)
        m = idx.size
        A = np.zeros((m + 1, m + 1))
        b = np.zeros(m + 1)
        # active row equations: u_j - Σ_{k active} M[j,k] u_k - c = const_j
        A[:m, :m] = np.eye(m) - M[np.ix_(idx, idx)]
        A[:m, m] = -1.0
        b[:m] = const[idx]
        A[m, :m] = 1.0
        b[m] = n
        x = np.linalg.solve(A, b)
        residual = float(np.max(np.abs(A @ x - b))) / n
        u = np.zeros(n)
        u[idx] = x[:m]
        c = x[m]
        if np.any(u[idx] <= threshold):
            worst = idx[u[idx] <= threshold]
            active[worst] = False
            if not np.any(active):
                break
            continue
        implied = c + M @ u + const
        cand = np.flatnonzero(~active & (implied > threshold))
        if cand.size == 0:
            return u, (np.flatnonzero(~active) + 1).tolist(), True, residual
        active[cand[np.argmax(implied[cand])]] = True
    return u, (np.flatnonzero(~active) + 1).tolist(), False, residual


# ----------------------------------------------------------------------------- bridges (eq. (2))
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
    dict with ``H`` [mm], ``H_max`` [mm], ``D``, ``flags``, ``Q``, ``axle_compliance`` [mm/N],
    ``stiffness`` (k_j of every span [N·mm/rad]), ``a_w``, ``a_c`` [mm].
    """
    n = rows
    d_a, m = sun_diameter, module
    span = rim_width  # l, the span length
    r_ba = 0.5 * d_a * math.cos(pressure_angle)
    z_a = d_a / m
    z_g = z_a * (ratio - 2.0) / 2.0
    a_w = 0.25 * d_a * ratio
    a_c = 0.5 * (d_a * (ratio - 1.0) - 2.5 * m - bridge_thickness)
    H_max = 2.0 * math.pi * a_c / planets_per_row - m * (z_g + 1.0)
    I_o = math.pi * axle_diameter**4 / 64.0
    S_o = math.pi * axle_diameter**2 / 4.0
    delta_o = beam_compliance(span, I_o, S_o, youngs_modulus, poisson)
    Q = (1.0 + poisson) * r_ba**2 * (rim_width + cheek) * planets_per_row / (
        youngs_modulus * delta_o * polar_moment * math.cos(pressure_angle))
    geo = (a_c / a_w) ** 2

    def D_of(H):
        H = np.asarray(H, float)
        with np.errstate(divide="ignore"):
            dh = beam_compliance(span, bridge_thickness * H**3 / 12.0, H * bridge_thickness, youngs_modulus, poisson)
            return np.where(H > 0, 1.0 + delta_o / dh * geo, 1.0)

    flags = ["ok"] * n
    D = np.ones(n)
    H = np.zeros(n)
    if H_max <= 0:
        flags = ["no_room"] * n
    else:
        D_max = float(D_of(H_max))
        D_req = np.ones(n)
        D_req[0] = 1.0 if not first_span else float(D_of(first_span))
        D[0] = D_req[0]
        for j in range(1, n):  # 0-based j: span j+1, equation index j (1-based) = j
            denom = Q * (n - j) - (j - 0.5) / D[j - 1]
            D_req[j] = (j + 0.5) / denom if denom > 0 else math.inf
            if D_req[j] < 1.0:
                flags[j] = "axes_too_stiff"
                D[j] = 1.0
            elif D_req[j] > D_max:
                flags[j] = "exceeds_max"
                D[j] = D_max
            else:
                D[j] = D_req[j]
        # widths
        need = (D > 1.0) & np.array([f == "ok" for f in flags])
        if np.any(need):
            delta_star = delta_o * geo / (D[need] - 1.0)
            H[need] = bridge_width_for_compliance(delta_star, span, bridge_thickness, youngs_modulus, poisson)
        for j, f in enumerate(flags):
            if f == "exceeds_max":
                H[j] = H_max
        if first_span:
            H[0] = first_span
    with np.errstate(divide="ignore"):
        d_h = np.where(H > 0, beam_compliance(span, bridge_thickness * np.maximum(H, 1e-300) ** 3 / 12.0,
                                              np.maximum(H, 1e-300) * bridge_thickness, youngs_modulus, poisson),
                       np.inf)
    stiffness = planets_per_row * (a_w**2 / delta_o + np.where(H > 0, a_c**2 / d_h, 0.0))
    return {"H": H, "H_max": H_max, "D": D, "flags": flags, "Q": Q, "axle_compliance": delta_o,
            "stiffness": stiffness, "a_w": a_w, "a_c": a_c, "planet_teeth": z_g}


# ----------------------------------------------------------------------------- relative mass
def mass_bracket(ratio, rows, planets_per_row, wall_ratio, sun_fill, planet_fill, cheek_ratio):
    """The paper's volume bracket {…} of the relative mass (rows.md §6), in units of π d_a² b_w / 4.

    ``8t(i-1)²[b̄(n+1)+n+0.25] + k_a[b̄(n-1)+n] + k_g n n_w (0.5i-1)² + b̄(n+1)(0.5i)²``
    """
    i = np.asarray(ratio, float)
    n, b = rows, cheek_ratio
    return (8.0 * wall_ratio * (i - 1.0) ** 2 * (b * (n + 1) + n + 0.25) + sun_fill * (b * (n - 1) + n)
            + planet_fill * n * planets_per_row * (0.5 * i - 1.0) ** 2 + b * (n + 1) * (0.5 * i) ** 2)


def relative_mass(ratio, rows, planets_per_row, wall_ratio=0.06, sun_fill=0.7, planet_fill=1.0, cheek_ratio=0.25,
                  allowable_contact=600.0, density=7800.0, youngs_modulus=2e5, poisson=0.3, efficiency=0.95,
                  unevenness=1.0, pressure_angle=math.radians(20.0)):
    """Relative mass M of the gear per output torque [kg/(kN·m)] (rows.md §6).

    ``M = 2π ρ K E {…} / [η (σ_HP/c_H)² n n_w (i-2) sin 2α_w] × 1e-3``, ``c_H = (2π(1-ν²))^(-1/2)``
    (the OCR'd prefactor with its missing cos α_w restored; ρ in kg/m³, E and σ_HP in MPa).

    Examples
    --------
    >>> round(float(relative_mass(3.5, 2, 3)), 3)   # bracket 16.246875 x prefactor 866.45 x 1e-3
    14.077
    """
    i = np.asarray(ratio, float)
    c_h = hertz.line_pressure_constant(poisson)
    pref = 2.0 * math.pi * density * unevenness * youngs_modulus / (
        efficiency * (allowable_contact / c_h) ** 2 * rows * planets_per_row * (i - 2.0) * np.sin(2.0 * pressure_angle))
    return 1e-3 * pref * mass_bracket(i, rows, planets_per_row, wall_ratio, sun_fill, planet_fill, cheek_ratio)


def mass_optimum_closed_form(rows, planets_per_row, wall_ratio, sun_fill, planet_fill, cheek_ratio):
    """Minimiser of M(i) for constant K: ``i* = 2 + sqrt(C₀/A)`` (rows.md §6, x = i - 2).

    Examples
    --------
    >>> round(float(mass_optimum_closed_form(2, 3, 0.06, 0.7, 1.0, 0.25)), 4)  # 2 + sqrt(3.765/3.1275)
    3.0972
    """
    n, b, t = rows, cheek_ratio, wall_ratio
    L_h = b * (n + 1) + n + 0.25
    L_a = b * (n - 1) + n
    A = 8 * t * L_h + planet_fill * n * planets_per_row / 4.0 + b * (n + 1) / 4.0
    C0 = 8 * t * L_h + sun_fill * L_a + b * (n + 1)
    return 2.0 + np.sqrt(C0 / A)
