"""Load sharing between the rows.

The sun as a torsion shaft (I_p, kappa) and the three model levels (stepwise, exact, continuous), with the active-set
solver for a compliant carrier (rows.md §2, §3, §5.5).

Pure functions over floats and numpy arrays; units N, mm, N·mm, MPa (= N/mm²), rad.  Every function
that takes a torsion parameter ``kappa`` broadcasts over a batch of designs (arrays of any shape); row
loops run over rows, never over designs.

References
----------
.. [1] The seed paper 004, cited in full in :mod:`gearcalc.rows`; docs/spec/rows.md (the
   section numbers "rows.md §x" refer to it).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["RESCALE", "KAPPA_UNIFORM", "KAPPA_STEPWISE_MAX", "UNLOADED_SHARE", "LEVELS", "Sharing", "continuous_x",
           "continuous_profile", "row_sharing", "SharingBatch", "row_sharing_mixed", "mean_line_load",
           "twist_from_shares", "polar_moment", "torsion_parameter", "stepwise_shares", "stepwise_dense",
           "twist_between", "exact_shares", "exact_k_no_gap", "x_coth_x", "continuous_k", "stepwise_active_set",
           "stepwise_active_set_batch"]

RESCALE = 1e250
"""The far-end recurrence rescales its running values above this (rows.md §2.5)."""
KAPPA_UNIFORM = 1e-24
"""Below this torsion parameter the exact level returns the uniform limit (rows.md §3b)."""
KAPPA_STEPWISE_MAX = 8.0
"""The stepwise level is valid only for kappa < 8 (rows.md §2.5)."""
UNLOADED_SHARE = 1e-12
"""A row is unloaded when its load is <= 1e-12 w̄; the active set uses the same threshold (rows.md §13.4)."""
LEVELS = ("stepwise", "exact", "continuous")
"""The model levels, by name (rows.md §3)."""

def _row_max(x):
    """``x.max(axis=-1)``, column by column.

    numpy reduces a short last axis (the rows) point by point, 5x slower than elementwise ``maximum`` over the
    columns; the same values (a maximum does not round; NaN propagates).
    """
    out = x[..., 0].copy()
    for j in range(1, x.shape[-1]):
        np.maximum(out, x[..., j], out=out)
    return out


def _row_argmax(x):
    """``np.argmax(x, axis=-1)`` column by column (see :func:`_row_max`): the first largest, a NaN the largest."""
    best = x[..., 0].copy()
    out = np.zeros(best.shape, dtype=np.intp)
    for j in range(1, x.shape[-1]):
        c = x[..., j]
        more = (c > best) | (np.isnan(c) & ~np.isnan(best))
        out[more] = j
        best = np.where(more, c, best)
    return out


def _row_mean(x):
    """``x.mean(axis=-1)`` column by column (see :func:`_row_max`), bit for bit.

    numpy sums fewer than 8 values in order, ``((x0 + x1) + x2) + ...``, then divides by their count; 8 or more
    pairwise (numpy's own mean then).
    """
    n = x.shape[-1]
    if n >= 8:
        return x.mean(axis=-1)
    total = x[..., 0].copy()
    for j in range(1, n):
        total += x[..., j]
    return total / n


def _row_any(x):
    """``np.any(x, axis=-1)`` of flags column by column (see :func:`_row_max`)."""
    out = x[..., 0].copy()
    for j in range(1, x.shape[-1]):
        out |= x[..., j]
    return out


def polar_moment(torsion_diameter, bore=0.0):
    r"""Polar second moment of area of a (hollow) round shaft [mm⁴].

    .. math:: I_p = \frac{\pi\,(d_I^4 - d_0^4)}{32}

    Parameters
    ----------
    torsion_diameter : float or array_like
        Torsion diameter d_I, [mm].
    bore : float or array_like, optional
        Bore diameter d_0, [mm] (0: a solid sun).

    Returns
    -------
    I_p : ndarray
        Polar moment, [mm⁴].

    Examples
    --------
    >>> round(float(polar_moment(10.0)), 4)   # pi 10^4 / 32
    981.7477

    References
    ----------
    .. [1] Seed paper 004_971077b94d8d4426.txt, an OCR of a Russian journal paper on multi-row planetary gears (title,
       authors, journal and year not recoverable; its ref. [1]: F. I. Plekhanov, «Зубчатые планетарные передачи»);
       docs/spec/rows.md §1 "Notation", §2.4.
    """
    return math.pi * (np.asarray(torsion_diameter, float) ** 4 - np.asarray(bore, float) ** 4) / 32.0


def torsion_parameter(mesh_stiffness, base_radius, planets_per_row, rim_width, shear_modulus, polar_moment):
    r"""Torsion parameter κ of the sun [-].

    .. math:: \kappa = \frac{C\,r_{ba}^2\,n_w\,b_w^2}{2\,G\,I_p}

    Parameters
    ----------
    mesh_stiffness : float or array_like
        Mesh stiffness per unit face width C, [N/mm²].
    base_radius : float or array_like
        Sun base radius r_ba = 0.5 d_a cos α_w, [mm].
    planets_per_row : int or array_like
        Number of planets in a row n_w, [-].
    rim_width : float or array_like
        Rim width b_w, [mm].
    shear_modulus : float or array_like
        Shear modulus G, [MPa].
    polar_moment : float or array_like
        Polar moment I_p, [mm⁴].

    Returns
    -------
    kappa : float or ndarray
        Torsion parameter, [-].

    Examples
    --------
    >>> torsion_parameter(2.0, 1.0, 1, 1.0, 1.0, 1.0)   # 0.5 * 2 * 1 * 1 * 1 / (1 * 1)
    1.0

    References
    ----------
    .. [1] Seed paper 004_971077b94d8d4426.txt, an OCR of a Russian journal paper on multi-row planetary gears (title,
       authors, journal and year not recoverable; its ref. [1]: F. I. Plekhanov, «Зубчатые планетарные передачи»); eq.
       (1), in dimensionless form; docs/spec/rows.md §2.3.
    """
    return 0.5 * mesh_stiffness * base_radius**2 * planets_per_row * rim_width**2 / (shear_modulus * polar_moment)


def stepwise_shares(kappa, cheek_ratio, rows: int):
    r"""Row load ratios u_N = w_N/w̄ of the paper's stepwise model, by the far-end recurrence.

    .. math::

        \left(1 - \frac{\kappa}{8}\right)(u_N - u_{N+1}) = \kappa\,(1 + \bar b) \sum_{k > N} u_k,
        \qquad \sum_N u_N = n,

        v_n = 1, \quad v_N = v_{N+1} + \rho \sum_{k > N} v_k, \quad \rho = \frac{\kappa\,(1 + \bar b)}{1 - \kappa/8},
        \quad u = \frac{n\,v}{\sum v}

    O(n), rescaled against overflow; valid for κ < 8 (for n ≥ 2).

    Parameters
    ----------
    kappa : float or array_like
        Torsion parameter κ, [-], any shape S.
    cheek_ratio : float or array_like
        Cheek ratio b̄, [-], broadcastable to S.
    rows : int
        Number of rows n, [-].

    Returns
    -------
    u : ndarray
        Shares of shape S + (n,), rows from the input side, [-]; for κ ≥ 8 meaningless (uniform).
    valid : ndarray of bool
        Whether the stepwise level exists (κ < 8 or n = 1), shape S.

    Examples
    --------
    >>> u, ok = stepwise_shares(0.0, 0.25, 3)
    >>> u.tolist(), bool(ok)
    ([1.0, 1.0, 1.0], True)

    References
    ----------
    .. [1] Seed paper 004_971077b94d8d4426.txt, an OCR of a Russian journal paper on multi-row planetary gears (title,
       authors, journal and year not recoverable; its ref. [1]: F. I. Plekhanov, «Зубчатые планетарные передачи»); eq.
       (1); docs/spec/rows.md §2.3, §2.5.
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
    r"""Stepwise shares by a dense solve (a cross-check for small n only).

    .. math::

        \text{paper:}\quad \left(1 - \frac{\kappa}{8}\right)(u_1 - u_N)
        = \kappa\,(1 + \bar b) \sum_{m < N} (n - S_m), \qquad S_m = \sum_{k \le m} u_k,

        \text{difference:}\quad \left(1 - \frac{\kappa}{8}\right)(u_{N-1} - u_N)
        = \kappa\,(1 + \bar b) \sum_{k \ge N} u_k, \qquad \sum u = n

    Parameters
    ----------
    kappa : float
        Torsion parameter κ, [-].
    cheek_ratio : float
        Cheek ratio b̄, [-].
    rows : int
        Number of rows n, [-].
    form : {"paper", "difference"}, optional
        The paper's system (1) (rows from row 1, nested sums) or the difference form.

    Returns
    -------
    u : ndarray
        Shares u = w/w̄, shape (n,), [-].

    Examples
    --------
    >>> bool(np.allclose(stepwise_dense(0.5, 0.25, 3), stepwise_shares(0.5, 0.25, 3)[0]))
    True

    References
    ----------
    .. [1] Seed paper 004_971077b94d8d4426.txt, an OCR of a Russian journal paper on multi-row planetary gears (title,
       authors, journal and year not recoverable; its ref. [1]: F. I. Plekhanov, «Зубчатые планетарные передачи»); eq.
       (1); docs/spec/rows.md §2.5.
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
    r"""Sun twist between the mid-planes of rows p < q (1-based) under the stepwise torque diagram [rad].

    .. math::

        I_p\,G\,\varphi_{p \to q} = (b_w + b) \sum_{m=p}^{q-1} \left(T_a - r_{ba}\,b_w\,n_w\,S_m\right)
        + \tfrac18\,n_w\,b_w^2\,r_{ba}\,(w_p - w_q), \qquad S_m = \sum_{k \le m} w_k

    Parameters
    ----------
    loads : array_like
        Line loads w_1..w_n, [N/mm].
    p, q : int
        Row numbers, 1 ≤ p < q ≤ n.
    sun_torque : float
        Sun torque T_a, [N·mm].
    base_radius : float
        Sun base radius r_ba, [mm].
    rim_width : float
        Rim width b_w, [mm].
    cheek : float
        Cheek thickness b, [mm].
    planets_per_row : int
        Number of planets in a row n_w, [-].
    shear_modulus : float
        Shear modulus G, [MPa].
    polar_moment : float
        Polar moment I_p, [mm⁴].

    Returns
    -------
    phi : float
        Twist, [rad].

    Examples
    --------
    >>> u, _ = stepwise_shares(0.5, 0.25, 3)   # w̄ = 1, T_a = n r_ba b_w n_w w̄ = 3, C = 2κ = 1
    >>> round(float(twist_between(u, 1, 3, 3.0, 1.0, 1.0, 0.25, 1, 1.0, 1.0)), 12)   # = 2 (u_1 - u_3)/(C r_ba)
    2.4

    References
    ----------
    .. [1] Seed paper 004_971077b94d8d4426.txt, an OCR of a Russian journal paper on multi-row planetary gears (title,
       authors, journal and year not recoverable; its ref. [1]: F. I. Plekhanov, «Зубчатые планетарные передачи»); its
       twist angles leading to eq. (1); docs/spec/rows.md §2.1.
    """
    w = np.asarray(loads, float)
    S = np.cumsum(w)
    k = base_radius * rim_width * planets_per_row
    body = (rim_width + cheek) * np.sum(sun_torque - k * S[p - 1:q - 1])
    half = 0.125 * planets_per_row * rim_width**2 * base_radius * (w[p - 1] - w[q - 1])
    return (body + half) / (shear_modulus * polar_moment)


def exact_shares(kappa, cheek_ratio, rows: int):
    r"""Row shares and within-row peak of the piecewise exact model, by the impedance sweep.

    .. math::

        \theta'' = \lambda^2 \theta \ \text{(in a row)}, \quad \mu = \lambda\,b_w = \sqrt\kappa, \qquad
        r_{in} = \frac{r_{out} + \tanh\mu}{1 + r_{out}\tanh\mu}, \qquad
        r_{out,j-1} = \frac{r_{in,j}}{1 + \bar b\,\mu\,r_{in,j}}

    Inside a row the sun is a torsion shaft on an elastic foundation, across a gap a plain shaft;
    T(0) = T_a, T(b_a) = 0.  The sweep propagates the dimensionless stiffness r = T/(G I_p λ θ) from the free
    end (r = 0) and uses only tanh and e^(-μ), so it neither overflows nor loses precision.

    Parameters
    ----------
    kappa : float or array_like
        Torsion parameter κ, [-], any shape S.
    cheek_ratio : float or array_like
        Cheek ratio b̄, [-], broadcastable to S.
    rows : int
        Number of rows n, [-].

    Returns
    -------
    u : ndarray
        Shares w_j/w̄ of the row-mean loads, shape S + (n,), [-].
    peak_factor : ndarray
        w(0)/w̄, the load at the input edge of row 1 over the mean, shape S, [-].

    Examples
    --------
    >>> u, peak = exact_shares(1.0, 0.25, 1)
    >>> float(u[0]), round(float(peak), 6)   # n = 1: u = 1, peak = μ coth μ
    (1.0, 1.313035)

    References
    ----------
    .. [1] Seed paper 004_971077b94d8d4426.txt, an OCR of a Russian journal paper on multi-row planetary gears (title,
       authors, journal and year not recoverable; its ref. [1]: F. I. Plekhanov, «Зубчатые планетарные передачи»);
       docs/spec/rows.md §3b.
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
    avg = _row_mean(mean_theta)
    u = mean_theta / avg[..., None]
    peak = theta_in1 / avg
    u = np.where(tiny[..., None], 1.0, u)
    peak = np.where(tiny, 1.0, peak)
    return u, peak


def exact_k_no_gap(kappa, rows: int):
    r"""K of the exact level for b = 0 in closed form [-].

    .. math::

        K = n \left[1 - \frac{\sinh((n - 1)\mu)}{\sinh(n\mu)}\right]
          = n \left[1 - e^{-\mu}\,\frac{1 - e^{-2(n-1)\mu}}{1 - e^{-2n\mu}}\right], \qquad \mu = \sqrt\kappa

    (the second form is the one evaluated: stable for large μ).

    Parameters
    ----------
    kappa : float or array_like
        Torsion parameter κ, [-].
    rows : int
        Number of rows n, [-].

    Returns
    -------
    K : ndarray
        Unevenness factor, [-].

    Examples
    --------
    >>> round(float(exact_k_no_gap(1.0, 3)), 6)   # 3 (1 - sinh 2 / sinh 3) = 1.913883
    1.913883

    References
    ----------
    .. [1] Seed paper 004_971077b94d8d4426.txt, an OCR of a Russian journal paper on multi-row planetary gears (title,
       authors, journal and year not recoverable; its ref. [1]: F. I. Plekhanov, «Зубчатые планетарные передачи»);
       docs/spec/rows.md §3b, §11 (exact identities).
    """
    mu = np.sqrt(np.asarray(kappa, float))
    return rows * (1.0 - np.exp(-mu) * -np.expm1(-2.0 * (rows - 1) * mu) / -np.expm1(-2.0 * rows * mu))


def x_coth_x(x):
    r"""The function x coth x, stable for small x and large x.

    .. math:: f(x) = x \coth x, \qquad f(x) \approx 1 + \frac{x^2}{3} \quad (|x| < 10^{-4})

    Parameters
    ----------
    x : float or array_like
        Argument, [-].

    Returns
    -------
    f : ndarray
        x coth x, [-].

    Examples
    --------
    >>> float(x_coth_x(0.0)), round(float(x_coth_x(2.0)), 6)   # 2 / tanh 2 = 2.074629
    (1.0, 2.074629)

    References
    ----------
    .. [1] Seed paper 004_971077b94d8d4426.txt, an OCR of a Russian journal paper on multi-row planetary gears (title,
       authors, journal and year not recoverable; its ref. [1]: F. I. Plekhanov, «Зубчатые планетарные передачи»);
       docs/spec/rows.md §3c.
    """
    x = np.asarray(x, float)
    small = np.abs(x) < 1e-4
    with np.errstate(divide="ignore", invalid="ignore"):
        big = x / np.tanh(np.where(small, 1.0, x))
    return np.where(small, 1.0 + x * x / 3.0, big)


def continuous_x(kappa, cheek_ratio, rows):
    r"""The continuous level's decay length X = λ_eff b_a [-].

    .. math:: X = \sqrt{\frac{\kappa}{1 + \bar b}}\,\left(n + \bar b\,(n - 1)\right) \quad (n \ge 2), \qquad
        X = \sqrt\kappa \quad (n = 1)

    (the cheek gaps homogenised).

    Parameters
    ----------
    kappa : float or array_like
        Torsion parameter κ, [-].
    cheek_ratio : float or array_like
        Cheek ratio b̄, [-].
    rows : int or array_like
        Number of rows n, [-].

    Returns
    -------
    X : ndarray
        Decay length over the face width, [-].

    Examples
    --------
    >>> float(continuous_x(1.0, 0.0, 3)), float(continuous_x(4.0, 0.25, 1))
    (3.0, 2.0)

    References
    ----------
    .. [1] Seed paper 004_971077b94d8d4426.txt, an OCR of a Russian journal paper on multi-row planetary gears (title,
       authors, journal and year not recoverable; its ref. [1]: F. I. Plekhanov, «Зубчатые планетарные передачи»);
       docs/spec/rows.md §3c.
    .. [2] M. Hetényi, Beams on Elastic Foundation, University of Michigan Press, 1946.
    """
    kappa = np.asarray(kappa, float)
    rows = np.asarray(rows)
    return np.where(rows >= 2, np.sqrt(kappa / (1.0 + cheek_ratio)) * (rows + cheek_ratio * (rows - 1)), np.sqrt(kappa))


def continuous_k(kappa, cheek_ratio, rows):
    r"""K of the continuous (homogenised) model [-].

    .. math:: K = X \coth X, \qquad X = \lambda_{eff}\,b_a

    The torsional Winkler-foundation result.

    Parameters
    ----------
    kappa : float or array_like
        Torsion parameter κ, [-].
    cheek_ratio : float or array_like
        Cheek ratio b̄, [-].
    rows : int or array_like
        Number of rows n, [-].

    Returns
    -------
    K : ndarray
        Unevenness factor, [-].

    Examples
    --------
    >>> round(float(continuous_k(1.0, 0.0, 3)), 6)   # b = 0: X = 3, 3 coth 3 = 3.014909
    3.014909

    References
    ----------
    .. [1] Seed paper 004_971077b94d8d4426.txt, an OCR of a Russian journal paper on multi-row planetary gears (title,
       authors, journal and year not recoverable; its ref. [1]: F. I. Plekhanov, «Зубчатые планетарные передачи»);
       docs/spec/rows.md §3c.
    .. [2] M. Hetényi, Beams on Elastic Foundation, University of Michigan Press, 1946.
    """
    return x_coth_x(continuous_x(kappa, cheek_ratio, rows))


def continuous_profile(position, kappa, cheek_ratio, rows):
    r"""Load profile u(ξ) = w(x)/w̄ of the continuous level along the face [-].

    .. math:: u(\xi) = \frac{X \cosh(X (1 - \xi))}{\sinh X}
        = \frac{X \left(e^{-X\xi} + e^{-X(2 - \xi)}\right)}{1 - e^{-2X}}, \qquad \xi = \frac{x}{b_a}

    Evaluated in the second form (no overflow); uniform for X ≤ 1e-6.

    Parameters
    ----------
    position : array_like
        ξ = x/b_a from the input edge, [-].
    kappa : float
        Torsion parameter κ, [-].
    cheek_ratio : float
        Cheek ratio b̄, [-].
    rows : int
        Number of rows n, [-].

    Returns
    -------
    u : ndarray
        w(x)/w̄ at each position, [-].

    Examples
    --------
    >>> round(float(continuous_profile(0.0, 1.0, 0.0, 3)), 6)   # u(0) = X coth X = K_continuous
    3.014909

    References
    ----------
    .. [1] Seed paper 004_971077b94d8d4426.txt, an OCR of a Russian journal paper on multi-row planetary gears (title,
       authors, journal and year not recoverable; its ref. [1]: F. I. Plekhanov, «Зубчатые планетарные передачи»);
       docs/spec/rows.md §3c.
    .. [2] M. Hetényi, Beams on Elastic Foundation, University of Michigan Press, 1946.
    """
    xi = np.asarray(position, float)
    X = float(continuous_x(kappa, cheek_ratio, rows))
    if X <= 1e-6:
        return np.ones_like(xi)
    return X * (np.exp(-X * xi) + np.exp(-X * (2 - xi))) / -np.expm1(-2 * X)


@dataclass(frozen=True)
class Sharing:
    """The row shares of every level for a batch of designs with the same number of rows (shape S)."""

    u_stepwise: np.ndarray
    """stepwise shares u = w/w̄, shape S + (n,) (meaningless where not stepwise_valid)"""
    stepwise_valid: np.ndarray
    """the stepwise level exists (κ < 8 or n = 1), shape S"""
    u_exact: np.ndarray
    """exact-level shares, shape S + (n,)"""
    peak_factor: np.ndarray
    """w(0)/w̄ of the exact level"""
    K_stepwise: np.ndarray
    """max u of the stepwise level (NaN where it does not exist; 1 for n = 1)"""
    K_exact: np.ndarray
    K_continuous: np.ndarray
    K: np.ndarray
    """K of the level that supplies it"""
    K_row: np.ndarray
    """the row (1-based) that carries K"""
    level: np.ndarray
    """the level that supplies K, by name"""
    u: np.ndarray
    """the shares of that level (the exact ones for the continuous level)"""
    unloaded: np.ndarray
    """rows whose share is <= UNLOADED_SHARE (never for n = 1), shape S + (n,)"""


def row_sharing(kappa, cheek_ratio, rows: int, level: str = "stepwise") -> Sharing:
    r"""Row shares and K at every level, and K from the level chosen by name.

    .. math:: K = \max_j u_j = \frac{\max_j w_j}{\bar w}

    All three levels are computed; ``level`` chooses the one that supplies K.  Where the stepwise level
    does not exist (κ ≥ 8, n ≥ 2) K falls back to the exact level.  For n = 1, K = 1 at every level.
    With a rigid carrier the most loaded row is row 1 (rows.md §2.2): the stepwise recurrence is
    monotone in floating point, so its argmax is used; the exact and continuous levels report row 1
    (the exact shares' argmax is rounding noise at κ ≲ 1e-16).

    Parameters
    ----------
    kappa : float or array_like
        Torsion parameter κ, [-], any shape S.
    cheek_ratio : float or array_like
        Cheek ratio b̄, [-], broadcastable to S.
    rows : int
        Number of rows n, [-].
    level : {"stepwise", "exact", "continuous"}, optional
        The level that supplies K.

    Returns
    -------
    sharing : Sharing
        The shares and K of every level, the level used and the unloaded rows.

    Raises
    ------
    ValueError
        For an unknown level, listing the levels.

    Examples
    --------
    >>> s = row_sharing(0.5, 0.25, 3)   # ρ = 2/3: v = (31/9, 5/3, 1), u_1 = 3 v_1/Σv = 1.690909
    >>> str(s.level), round(float(s.K), 6), int(s.K_row)
    ('stepwise', 1.690909, 1)
    >>> str(row_sharing(9.0, 0.25, 3).level)   # κ ≥ 8: the stepwise level does not exist
    'exact'

    References
    ----------
    .. [1] Seed paper 004_971077b94d8d4426.txt, an OCR of a Russian journal paper on multi-row planetary gears (title,
       authors, journal and year not recoverable; its ref. [1]: F. I. Plekhanov, «Зубчатые планетарные передачи»); eq.
       (1) and its K = w_1/w̄; docs/spec/rows.md §2.2, §3, §13.2-13.4.
    """
    if level not in LEVELS:
        raise ValueError(f"unknown level {level!r}; the levels are " + ", ".join(LEVELS))
    u_s, valid = stepwise_shares(kappa, cheek_ratio, rows)
    u_e, peak = exact_shares(kappa, cheek_ratio, rows)
    if rows == 1:
        K_s = K_e = K_c = np.ones(valid.shape)
    else:
        K_s = np.where(valid, _row_max(u_s), np.nan)
        K_e = _row_max(u_e)
        K_c = continuous_k(kappa, cheek_ratio, rows)
    continuous = level == "continuous"
    use_exact = (level == "exact") | ((level == "stepwise") & ~valid)
    K = K_c if continuous else np.where(use_exact, K_e, K_s)
    names = np.full(valid.shape, "continuous") if continuous else np.where(use_exact, "exact", "stepwise")
    K_row = np.where(use_exact | continuous, 1, _row_argmax(u_s) + 1)
    u = np.where((use_exact | continuous)[..., None], u_e, u_s)
    unloaded = (u <= UNLOADED_SHARE) & (rows > 1)
    return Sharing(u_s, valid, u_e, peak, K_s, K_e, K_c, K, K_row, names, u, unloaded)


@dataclass(frozen=True)
class SharingBatch:
    """The K values of :class:`Sharing` for designs with different numbers of rows, one entry per design."""

    stepwise_valid: np.ndarray
    K_stepwise: np.ndarray
    K_exact: np.ndarray
    K_continuous: np.ndarray
    K: np.ndarray
    K_row: np.ndarray
    level: np.ndarray
    peak_factor: np.ndarray
    unloaded: list
    """the unloaded rows of each design, 1-based (one shared empty list where none)"""


def row_sharing_mixed(kappa, cheek_ratio, rows, level: str = "stepwise") -> SharingBatch:
    r""":func:`row_sharing` over a batch of designs whose numbers of rows differ.

    .. math:: K = \max_j u_j \quad \text{per design}

    The designs are grouped by n and each group is one batch of :func:`row_sharing`: no loop over designs.

    Parameters
    ----------
    kappa : ndarray
        Torsion parameters κ, [-], shape (P,).
    cheek_ratio : ndarray
        Cheek ratios b̄, [-], shape (P,).
    rows : ndarray of int
        Number of rows n per design, shape (P,).
    level : {"stepwise", "exact", "continuous"}, optional
        As :func:`row_sharing`.

    Returns
    -------
    batch : SharingBatch
        K of every level, the level used, the peak factor and the unloaded rows, one entry per design.

    Examples
    --------
    >>> b = row_sharing_mixed(np.array([0.5, 0.5, 9.0]), np.full(3, 0.25), np.array([3, 1, 3]))
    >>> b.level.tolist(), b.K.round(6).tolist()
    (['stepwise', 'stepwise', 'exact'], [1.690909, 1.0, 2.891354])

    References
    ----------
    .. [1] Seed paper 004_971077b94d8d4426.txt, an OCR of a Russian journal paper on multi-row planetary gears (title,
       authors, journal and year not recoverable; its ref. [1]: F. I. Plekhanov, «Зубчатые планетарные передачи»); eq.
       (1); docs/spec/rows.md §3, §9.
    """
    from ..arrays import unique_sorted

    P = len(rows)
    groups = unique_sorted(rows)
    if len(groups) == 1:  # one number of rows (most sweeps): that group is the batch, no gathering nor scattering
        # contiguous, as the gathered copies below are: numpy's SIMD loops (exp, tanh) follow the memory layout
        part = row_sharing(np.ascontiguousarray(kappa), np.ascontiguousarray(cheek_ratio), int(groups[0]), level)
        unloaded = [[]] * P
        for k in np.flatnonzero(_row_any(part.unloaded)):  # rows.md §13.4
            unloaded[k] = (np.flatnonzero(part.unloaded[k]) + 1).tolist()
        return SharingBatch(part.stepwise_valid, part.K_stepwise, part.K_exact, part.K_continuous, part.K,
                            part.K_row, part.level, part.peak_factor, unloaded)
    out = SharingBatch(np.ones(P, bool), np.ones(P), np.ones(P), np.ones(P), np.ones(P), np.ones(P, int),
                       np.empty(P, "<U10"), np.ones(P), [[]] * P)
    for n in groups:
        idx = np.flatnonzero(rows == n)
        part = row_sharing(kappa[idx], cheek_ratio[idx], int(n), level)
        for name in ("stepwise_valid", "K_stepwise", "K_exact", "K_continuous", "K", "K_row", "level", "peak_factor"):
            getattr(out, name)[idx] = getattr(part, name)
        for k in np.flatnonzero(_row_any(part.unloaded)):  # rows.md §13.4
            out.unloaded[idx[k]] = (np.flatnonzero(part.unloaded[k]) + 1).tolist()
    return out


def mean_line_load(sun_torque, rows, base_radius, rim_width, planets_per_row):
    r"""Mean line load w̄ of the meshes [N/mm].

    .. math:: \bar w = \frac{T_a}{n\,r_{ba}\,b_w\,n_w}

    Parameters
    ----------
    sun_torque : float or array_like
        Sun torque T_a, [N·mm].
    rows : int or array_like
        Number of rows n, [-].
    base_radius : float or array_like
        Sun base radius r_ba, [mm].
    rim_width : float or array_like
        Rim width b_w, [mm].
    planets_per_row : int or array_like
        Number of planets in a row n_w, [-].

    Returns
    -------
    w_mean : float or ndarray
        Mean line load, [N/mm].

    Examples
    --------
    >>> mean_line_load(1.2e6, 2, 50.0, 40.0, 3)
    100.0

    References
    ----------
    .. [1] Seed paper 004_971077b94d8d4426.txt, an OCR of a Russian journal paper on multi-row planetary gears (title,
       authors, journal and year not recoverable; its ref. [1]: F. I. Plekhanov, «Зубчатые планетарные передачи»); its
       w̄ = T_a/(n r_ba b_w n_w); docs/spec/rows.md §2.2.
    """
    return sun_torque / (rows * base_radius * rim_width * planets_per_row)


def twist_from_shares(shares, mean_load, mesh_stiffness, base_radius):
    r"""Sun twist between row 1 and each row from the solved loads [rad] (the twist identity).

    .. math:: \varphi_{1 \to j} = \frac{2\,(w_1 - w_j)}{C\,r_{ba}} = \frac{2\,(u_1 - u_j)\,\bar w}{C\,r_{ba}}

    Parameters
    ----------
    shares : ndarray
        Shares u = w/w̄ per row (last axis), [-].
    mean_load : float or array_like
        Mean line load w̄, [N/mm].
    mesh_stiffness : float or array_like
        Mesh stiffness per unit face width C, [N/mm²].
    base_radius : float or array_like
        Sun base radius r_ba, [mm].

    Returns
    -------
    phi : ndarray
        Twist of each row relative to row 1, [rad].

    Examples
    --------
    >>> [round(float(t), 12) for t in twist_from_shares(np.array([1.5, 0.5]), 100.0, 1e4, 50.0)]  # 2 x 100 / 5e5
    [0.0, 0.0004]

    References
    ----------
    .. [1] Seed paper 004_971077b94d8d4426.txt, an OCR of a Russian journal paper on multi-row planetary gears (title,
       authors, journal and year not recoverable; its ref. [1]: F. I. Plekhanov, «Зубчатые планетарные передачи»); eq.
       (1); docs/spec/rows.md §2.2.
    """
    return 2.0 * (shares[..., :1] - shares) / (mesh_stiffness * base_radius) * mean_load


def stepwise_active_set(kappa: float, cheek_ratio: float, rows: int, carrier=None, threshold: float = 1e-12):
    r"""Stepwise shares with unloaded rows handled by an active set.

    .. math::

        u_j = c - \left[\kappa\,(1 + \bar b) \sum_{m < j} (n - S_m) + \frac{\kappa}{8}\,(u_1 - u_j)\right]
        + (Y u)_1 - (Y u)_j \ \ \text{(active rows)}, \qquad u_j = 0 \ \ \text{(inactive)}, \qquad \sum u = n

    Unknowns u_1..u_n (loads over w̄) and c (the load row 1 would carry); Y (dimensionless, C y/w̄ = Y u) is
    the carrier compliance.  Rows with u ≤ 0 are deactivated; an inactive row whose implied load exceeds
    ``threshold`` is re-activated, the largest first.

    Parameters
    ----------
    kappa : float
        Torsion parameter κ, [-].
    cheek_ratio : float
        Cheek ratio b̄, [-].
    rows : int
        Number of rows n, [-].
    carrier : array_like, optional
        Dimensionless carrier compliance Y, shape (n, n); None: a rigid carrier.
    threshold : float, optional
        Share below which a row is unloaded, [-].

    Returns
    -------
    u : ndarray
        Shares, [-].
    unloaded : list of int
        1-based indices of the inactive rows.
    converged : bool
        False if the active set did not settle within 3n iterations.
    residual : float
        max |A x - b|/n of the final linear solve, [-].

    Examples
    --------
    >>> u, unloaded, converged, residual = stepwise_active_set(0.5, 0.25, 3)   # rigid carrier: system (1)
    >>> u.round(6).tolist(), unloaded, converged
    ([1.690909, 0.818182, 0.490909], [], True)

    References
    ----------
    .. [1] Seed paper 004_971077b94d8d4426.txt, an OCR of a Russian journal paper on multi-row planetary gears (title,
       authors, journal and year not recoverable; its ref. [1]: F. I. Plekhanov, «Зубчатые планетарные передачи»); eq.
       (1) with contact loss and a compliant carrier; docs/spec/rows.md §2.5, §5.5.
    """
    n = rows
    g = kappa * (1.0 + cheek_ratio)
    a8 = kappa / 8.0
    Y = np.zeros((n, n)) if carrier is None else np.asarray(carrier, float)
    # Row j (0-based) of the "implied load" map: u_j = c + sum_k M[j,k] u_k + const_j
    # twist term: g Σ_{m<j} (n - S_m) = g*j*n - g Σ_{m<j} S_m ; Σ_{m<j} S_m = Σ_k (j - k)_+ u_k
    j = np.arange(n)
    const = -g * j * n
    M = g * np.maximum(j[:, None] - j[None, :], 0)
    M[:, 0] -= a8
    M[j, j] += a8
    M += Y[:1, :] - Y
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


def stepwise_active_set_batch(kappa, cheek_ratio, rows: int, carrier=None, threshold: float = 1e-12):
    r""":func:`stepwise_active_set` over a batch of designs with the same number of rows.

    .. math:: u_j = c - \left[\kappa\,(1 + \bar b) \sum_{m < j} (n - S_m) + \frac{\kappa}{8}\,(u_1 - u_j)\right]
        + (Y u)_1 - (Y u)_j, \qquad \sum u = n

    The same iteration point by point, with masks: each round, the designs still iterating are grouped by
    their active set and each group is one stacked solve of its own size, so every design meets the same
    arithmetic as alone (the loop is over active sets and rounds, never over designs).

    Parameters
    ----------
    kappa : ndarray
        Torsion parameters κ, [-], shape (P,).
    cheek_ratio : ndarray
        Cheek ratios b̄, [-], shape (P,).
    rows : int
        Number of rows n, [-].
    carrier : ndarray, optional
        Dimensionless carrier compliances Y, shape (P, n, n); None: rigid carriers.
    threshold : float, optional
        Share below which a row is unloaded, [-].

    Returns
    -------
    u : ndarray
        Shares, shape (P, n), [-].
    unloaded : ndarray of bool
        The inactive rows, shape (P, n).
    converged : ndarray of bool
        Whether each design's active set settled, shape (P,).

    Examples
    --------
    >>> u, unloaded, converged = stepwise_active_set_batch(np.array([0.5, 0.25]), np.full(2, 0.25), 3)
    >>> u[0].round(6).tolist(), bool(unloaded.any()), converged.tolist()   # the first as stepwise_active_set
    ([1.690909, 0.818182, 0.490909], False, [True, True])

    References
    ----------
    .. [1] Seed paper 004_971077b94d8d4426.txt, an OCR of a Russian journal paper on multi-row planetary gears (title,
       authors, journal and year not recoverable; its ref. [1]: F. I. Plekhanov, «Зубчатые планетарные передачи»); eq.
       (1) with contact loss and a compliant carrier; docs/spec/rows.md §2.5, §5.5, §9.
    """
    kappa = np.asarray(kappa, float)
    P, n = kappa.shape[0], rows
    g = kappa * (1.0 + np.asarray(cheek_ratio, float))
    a8 = kappa / 8.0
    Y = np.zeros((P, n, n)) if carrier is None else np.asarray(carrier, float)
    j = np.arange(n)
    const = -g[:, None] * j * n
    M = g[:, None, None] * np.maximum(j[:, None] - j[None, :], 0)
    M[:, :, 0] -= a8[:, None]
    M[:, j, j] += a8[:, None]
    M += Y[:, :1, :] - Y
    active = np.ones((P, n), bool)
    u = np.zeros((P, n))
    going = np.ones(P, bool)
    converged = np.zeros(P, bool)
    for _ in range(3 * n + 1):
        todo = np.flatnonzero(going)
        if todo.size == 0:
            break
        sets, which = np.unique(active[todo], axis=0, return_inverse=True)
        for s, pattern in enumerate(sets):
            pts = todo[which.reshape(-1) == s]
            idx = np.flatnonzero(pattern)
            m, k = idx.size, pts.size
            A = np.zeros((k, m + 1, m + 1))
            b = np.zeros((k, m + 1, 1))
            A[:, :m, :m] = np.eye(m) - M[pts][:, idx][:, :, idx]
            A[:, :m, m] = -1.0
            b[:, :m, 0] = const[pts][:, idx]
            A[:, m, :m] = 1.0
            b[:, m, 0] = n
            x = np.linalg.solve(A, b)[..., 0]
            up = np.zeros((k, n))
            up[:, idx] = x[:, :m]
            u[pts] = up
            c = x[:, m]
            low = (up <= threshold) & pattern
            drop = low.any(axis=1)
            if drop.any():
                active[pts[drop]] &= ~low[drop]
                empty = ~active[pts[drop]].any(axis=1)
                going[pts[drop][empty]] = False  # no row left: not converged
            keep = ~drop
            if not keep.any():
                continue
            pk = pts[keep]
            implied = c[keep, None] + np.matmul(M[pk], up[keep][:, :, None])[..., 0] + const[pk]
            cand = ~active[pk] & (implied > threshold)
            settled = ~cand.any(axis=1)
            converged[pk[settled]] = True
            going[pk[settled]] = False
            more = np.flatnonzero(~settled)
            if more.size:
                best = np.argmax(np.where(cand[more], implied[more], -np.inf), axis=1)
                active[pk[more], best] = True
    return u, ~active, converged
