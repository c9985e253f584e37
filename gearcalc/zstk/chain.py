"""Closure of the roller chain and the roller positions (spec zstk.md §3.2, §4).

N* (Steiner chain condition), the corrections of R_H, R_B or c, N_max, the automatic N; the
Möbius map of the roller positions, the symmetric schemes, and explicit stepping as a cross-check.

References
----------
The seed paper by Merko et al. (seed 003), cited in full in :mod:`gearcalc.zstk`; docs/spec/zstk.md.
"""
from __future__ import annotations

__all__ = ['fractional_roller_number', 'corrected_outer_radius', 'corrected_inner_radius', 'corrected_gap',
           'roller_number_limit', 'auto_roller_number', 'auto_roller_numbers', 'largest_admissible_n',
           'largest_admissible_ns', 'Chain', 'close_chains', 'close_chain', 'limiting_point_ratio',
           'limiting_ratios', 'chain_phases', 'theta_of_phi',
           'phi_of_theta', 'roller_angles', 'scheme_phase', 'centres', 'neighbour_gaps', 'step_chain']

import math
from dataclasses import dataclass

import numpy as np

from ..roots import find_root
from .geometry import INTEGER_TOL, broadcast, centre_distance, roller_radius



# ----------------------------------------------------------------------------- §3.2 closure
def fractional_roller_number(outer_radius, inner_radius, eccentricity, gap):
    r"""Fractional roller number N* that closes the nominal chain (Steiner chain condition).

    .. math:: \sin^2(\pi/N^*) = \frac{(W - e)(W + e)}{(S - e)(S + e)}, \quad W = R_H - R_B + c,\ S = R_H + R_B

    sin²(pi/N*) = (W - e)(W + e) / ((S - e)(S + e)),  W = R_H - R_B + c,  S = R_H + R_B.

    Parameters
    ----------
    outer_radius, inner_radius, eccentricity, gap : R_H, R_B, e, c [mm].

    Returns
    -------
    N* [-]

    Examples
    --------
    >>> round(float(fractional_roller_number(100.0, 50.0, 6.0, 6.0)), 9)
    8.254222669

    References
    ----------
    Merko M.A. et al., «Анализ нормальных напряжений на площадках контакта звеньев механизмов с ЗСТК ...» (seed
    003_2d1da402cb0b8488.txt; no journal given; see :mod:`gearcalc.zstk`) (closure of the chain with the correction of
    R_H); docs/spec/zstk.md §3.2, condition (C); Coxeter H.S.M., Greitzer S.L., Geometry Revisited, MAA, 1967 (Steiner
    chains).
    """
    s = outer_radius + inner_radius
    w = outer_radius - inner_radius + gap
    e = eccentricity
    ratio = (w - e) * (w + e) / ((s - e) * (s + e))
    return np.pi / np.arcsin(np.sqrt(ratio))


def corrected_outer_radius(n, inner_radius, eccentricity, gap):
    r"""Outer raceway radius R_H' that closes a chain of exactly N rollers (correction "outer").

    .. math:: R_H' = \frac{R_B(1 + s^2) - c + \sqrt{s^2 (2 R_B - c)^2 + e^2 k^4}}{k^2}, \quad s =
              \sin(\pi/N),\ k = \cos(\pi/N)

    R_H' = [R_B(1 + s²) - c + sqrt(s²(2R_B - c)² + e² k⁴)] / k²,  s = sin(pi/N), k = cos(pi/N).

    Parameters
    ----------
    n : integer roller number N [-]; inner_radius, eccentricity, gap : R_B, e, c [mm].

    Returns
    -------
    R_H' [mm]

    Examples
    --------
    >>> round(float(fractional_roller_number(corrected_outer_radius(8, 50.0, 6.0, 6.0), 50.0, 6.0, 6.0)), 12)
    8.0

    References
    ----------
    Merko M.A. et al., «Анализ нормальных напряжений на площадках контакта звеньев механизмов с ЗСТК ...» (seed
    003_2d1da402cb0b8488.txt; no journal given; see :mod:`gearcalc.zstk`) (the paper's correction of the outer raceway
    radius); docs/spec/zstk.md §3.2 (closed-form root of (C)).
    """
    s2 = np.sin(np.pi / n) ** 2
    k2 = np.cos(np.pi / n) ** 2
    return (inner_radius * (1.0 + s2) - gap
            + np.sqrt(s2 * (2.0 * inner_radius - gap) ** 2 + eccentricity ** 2 * k2 * k2)) / k2


def corrected_inner_radius(n, outer_radius, eccentricity, gap):
    r"""Inner raceway radius R_B' that closes a chain of exactly N rollers (correction "inner").

    .. math:: R_B' = \frac{R_H(1 + s^2) + c - \sqrt{s^2 (2 R_H + c)^2 + e^2 k^4}}{k^2}

    R_B' = [R_H(1 + s²) + c - sqrt(s²(2R_H + c)² + e² k⁴)] / k².

    Parameters
    ----------
    n : N [-]; outer_radius, eccentricity, gap : R_H, e, c [mm].

    Returns
    -------
    R_B' [mm]

    Examples
    --------
    >>> round(float(fractional_roller_number(100.0, corrected_inner_radius(8, 100.0, 6.0, 6.0), 6.0, 6.0)), 12)
    8.0

    References
    ----------
    docs/spec/zstk.md §3.2 (gearcalc's option; the paper corrects R_H).
    """
    s2 = np.sin(np.pi / n) ** 2
    k2 = np.cos(np.pi / n) ** 2
    return (outer_radius * (1.0 + s2) + gap
            - np.sqrt(s2 * (2.0 * outer_radius + gap) ** 2 + eccentricity ** 2 * k2 * k2)) / k2


def corrected_gap(n, outer_radius, inner_radius, eccentricity):
    r"""Roller gap c' that closes a chain of exactly N rollers (correction "gap").

    .. math:: c' = \sqrt{S^2 \sin^2(\pi/N) + e^2 \cos^2(\pi/N)} - (R_H - R_B)

    c' = sqrt(S² s² + e² k²) - (R_H - R_B).

    Parameters
    ----------
    n : N [-]; outer_radius, inner_radius, eccentricity : R_H, R_B, e [mm].

    Returns
    -------
    c' [mm]

    Examples
    --------
    >>> round(float(fractional_roller_number(100.0, 50.0, 6.0, corrected_gap(8, 100.0, 50.0, 6.0))), 12)
    8.0

    References
    ----------
    docs/spec/zstk.md §3.2 (gearcalc's own option; the paper does not use it).
    """
    s = outer_radius + inner_radius
    return (np.sqrt(s * s * np.sin(np.pi / n) ** 2 + eccentricity ** 2 * np.cos(np.pi / n) ** 2)
            - (outer_radius - inner_radius))


def roller_number_limit(correct, outer_radius, inner_radius, eccentricity, gap):
    r"""The bound N_max of the admissible roller numbers 3 <= N < N_max (N <= N_max for "gap").

    .. math:: \text{outer: } \sin^2(\pi/N_{max}) = \frac{c (2e + c)}{4 R_B (R_B + e)}, \quad
              \text{inner: } \frac{c (2e + c)}{4 R_H (R_H - e)}, \quad \text{gap: } \frac{D^2 - e^2}{S^2
              - e^2}

    "outer": sin²(pi/N_max) = c(2e + c)/(4 R_B (R_B + e));  "inner": ... /(4 R_H (R_H - e));
    "gap": sin²(pi/N_max) = (D² - e²)/(S² - e²).  ``inf`` when there is no limit (c = 0).

    Parameters
    ----------
    correct : "outer" | "inner" | "gap".
    outer_radius, inner_radius, eccentricity, gap : nominal R_H, R_B, e, c [mm].

    Returns
    -------
    N_max [-] (float, ``inf`` for no limit; an array for array inputs)

    Examples
    --------
    >>> round(roller_number_limit("outer", 100.0, 50.0, 6.0, 6.0), 6)
    31.940856

    References
    ----------
    docs/spec/zstk.md §3.3.
    """
    e, c = eccentricity, gap
    if correct == "outer":
        ratio = c * (2.0 * e + c) / (4.0 * inner_radius * (inner_radius + e))
    elif correct == "inner":
        ratio = c * (2.0 * e + c) / (4.0 * outer_radius * (outer_radius - e))
    elif correct == "gap":
        s, d = outer_radius + inner_radius, outer_radius - inner_radius
        ratio = (d - e) * (d + e) / ((s - e) * (s + e))
    else:
        raise ValueError(f"unknown correction {correct!r}")
    ratio = np.asarray(ratio, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        limit = np.where(ratio <= 0.0, np.inf,
                         np.where(ratio >= 1.0, 2.0, np.pi / np.arcsin(np.sqrt(np.clip(ratio, 0.0, 1.0)))))
    return float(limit) if limit.ndim == 0 else limit


def auto_roller_number(n_star, parity=None):
    r"""The default N: the largest integer <= N* (of the scheme's parity, if one is given).

    .. math:: N = \lfloor N^* \rfloor \ (\text{or } \operatorname{round}(N^*) \text{ within } 10^{-9}), \qquad
        N \leftarrow N - 1 \ \text{when } N \bmod 2 \ne \text{parity}

    N* within :data:`INTEGER_TOL` of an integer counts as that integer (spec §11.5).

    Parameters
    ----------
    n_star : float
        Fractional roller number N*, [-].
    parity : {0, 1, None}, optional
        0 (even), 1 (odd) or None (any).

    Returns
    -------
    n : int
        Roller number N, [-]; may be < 3, which the caller reports.

    Examples
    --------
    >>> auto_roller_number(8.25), auto_roller_number(8.25, 1), auto_roller_number(7.9999999999, 0)
    (8, 7, 8)

    References
    ----------
    .. [1] M. A. Merko, M. V. Mesnyankin, A. V. Kolotov, A. E. Mityaev, M. V. Savitskaya, A. M. Merko, S. A. Yurov,
       «Анализ нормальных напряжений на площадках контакта звеньев механизмов с ЗСТК при ведущем внутреннем кольце и
       вводе поправки по радиусу дорожки качения наружного кольца», Siberian Federal University, UDC 621.838.2 (seed
       file 003_2d1da402cb0b8488.txt; no journal or year given); the integer roller number of the closed chain;
       docs/spec/zstk.md §3.2, §4.2, §11.5.
    """
    nearest = round(n_star)
    n = nearest if abs(n_star - nearest) < INTEGER_TOL else math.floor(n_star)
    if parity is not None and n % 2 != parity:
        n -= 1
    return int(n)


def auto_roller_numbers(n_star, parity):
    r""":func:`auto_roller_number` over arrays, element-wise.

    .. math:: N = \lfloor N^* \rfloor \ (\text{or } \operatorname{round}(N^*) \text{ within } 10^{-9}), \qquad
        N \leftarrow N - 1 \ \text{when parity} \ge 0 \text{ and } N \bmod 2 \ne \text{parity}

    Parameters
    ----------
    n_star : array_like
        Fractional roller numbers N*, [-].
    parity : array_like of int
        0 (even), 1 (odd) or -1 (any), per design.

    Returns
    -------
    n : ndarray of int
        Roller numbers N, [-].

    Examples
    --------
    >>> auto_roller_numbers(np.array([8.25, 8.25, 7.9999999999]), np.array([-1, 1, 0])).tolist()
    [8, 7, 8]

    References
    ----------
    .. [1] M. A. Merko, M. V. Mesnyankin, A. V. Kolotov, A. E. Mityaev, M. V. Savitskaya, A. M. Merko, S. A. Yurov,
       «Анализ нормальных напряжений на площадках контакта звеньев механизмов с ЗСТК при ведущем внутреннем кольце и
       вводе поправки по радиусу дорожки качения наружного кольца», Siberian Federal University, UDC 621.838.2 (seed
       file 003_2d1da402cb0b8488.txt; no journal or year given); docs/spec/zstk.md §3.2, §4.2, §11.5.
    """
    n_star = np.asarray(n_star, dtype=float)
    nearest = np.round(n_star)
    n = np.where(np.abs(n_star - nearest) < INTEGER_TOL, nearest, np.floor(n_star)).astype(np.int64)
    parity = np.asarray(parity)
    return np.where((parity >= 0) & (n % 2 != parity), n - 1, n)


def largest_admissible_n(limit, correct):
    r"""The largest admissible N for the bound N_max of :func:`roller_number_limit` (None: no limit).

    .. math:: N = \lceil N_{max} - 10^{-9} \rceil - 1 \ \text{("outer", "inner": } N < N_{max}), \qquad
        N = \lfloor N_{max} + 10^{-9} \rfloor \ \text{("gap": } N \le N_{max})

    Python integers, exact for any size of the limit.

    Parameters
    ----------
    limit : float
        The bound N_max, [-] (inf: none).
    correct : {"outer", "inner", "gap"}
        The corrected quantity.

    Returns
    -------
    n : int or None
        The largest admissible N, [-], or None without a limit.

    Examples
    --------
    >>> [largest_admissible_n(lim, c) for lim, c in ((31.940856, "outer"), (9.2, "gap"), (np.inf, "outer"))]
    [31, 9, None]

    References
    ----------
    .. [1] M. A. Merko, M. V. Mesnyankin, A. V. Kolotov, A. E. Mityaev, M. V. Savitskaya, A. M. Merko, S. A. Yurov,
       «Анализ нормальных напряжений на площадках контакта звеньев механизмов с ЗСТК при ведущем внутреннем кольце и
       вводе поправки по радиусу дорожки качения наружного кольца», Siberian Federal University, UDC 621.838.2 (seed
       file 003_2d1da402cb0b8488.txt; no journal or year given); docs/spec/zstk.md §3.3.
    """
    if not math.isfinite(limit):
        return None
    if correct == "gap":
        return math.floor(limit + 1e-9)
    return int(math.ceil(limit - 1e-9) - 1)


def largest_admissible_ns(limits, corrects) -> list:
    r""":func:`largest_admissible_n` of G designs at once (arrays (G,) of N_max and of the corrected quantity).

    .. math:: N_g = \lceil N_{max,g} - 10^{-9} \rceil - 1 \ \text{("outer", "inner")}, \qquad
        N_g = \lfloor N_{max,g} + 10^{-9} \rfloor \ \text{("gap")}

    A list of Python integers (None without a limit), the same as the function of each design.  A limit of 2**52 or
    more (where a float's ceiling minus one is not exact) goes through the function.

    Parameters
    ----------
    limits : array_like, shape (G,)
        The bounds N_max of :func:`roller_number_limit`, [-] (inf: none).
    corrects : sequence of {"outer", "inner", "gap"}, length G
        Each design's corrected quantity.

    Returns
    -------
    n : list of (int or None)
        The largest admissible N of each design, [-], or None without a limit.

    Examples
    --------
    >>> largest_admissible_ns([31.940856, 9.2, np.inf, 7.0], ["outer", "gap", "outer", "outer"])
    [31, 9, None, 6]

    References
    ----------
    .. [1] As :func:`largest_admissible_n` (Merko et al., seed file 003); docs/spec/zstk.md §3.3.
    """
    limits = np.asarray(limits, dtype=np.float64)
    gap = np.asarray(corrects) == "gap"
    finite = np.isfinite(limits)
    exact = finite & (np.abs(limits) < 2.0 ** 52)
    with np.errstate(invalid="ignore"):
        n = np.where(gap, np.floor(limits + 1e-9), np.ceil(limits - 1e-9) - 1.0)
    out = np.where(exact, n, 0.0).astype(np.int64).tolist()
    for k in np.flatnonzero(~exact).tolist():
        out[k] = largest_admissible_n(float(limits[k]), "gap" if gap[k] else "outer")
    return out


@dataclass
class Chain:
    """A closed chain: corrected geometry and its integer roller number.

    Attributes: outer_radius R_H, inner_radius R_B, eccentricity e, gap c [mm] (after
    correction), n (N), n_star (nominal N*), correct ("outer" | "inner" | "gap"), nominal and
    corrected value of the corrected quantity [mm], n_limit (N_max).  Either floats (one chain,
    :func:`close_chain`) or arrays of shape (G,) (stacked designs, :func:`close_chains`).
    """

    outer_radius: float
    inner_radius: float
    eccentricity: float
    gap: float
    n: int
    n_star: float
    correct: str
    nominal: float
    corrected: float
    n_limit: float

    @property
    def limiting_ratio(self):
        """The limiting-point ratio q = x_s/X of the chain (:func:`limiting_point_ratio`)."""
        q = limiting_point_ratio(self.outer_radius, self.inner_radius, self.eccentricity, self.gap)
        return float(q) if np.ndim(q) == 0 else q


def close_chains(outer_radius, inner_radius, eccentricity, gap, n, correct="outer"):
    r"""Correct one parameter of each of many designs so that exactly N rollers close each chain.

    .. math:: \sin^2\frac{\pi}{N} = \frac{(W - e)(W + e)}{(S - e)(S + e)}, \qquad W = R_H - R_B + c,\ S = R_H + R_B,

    solved for R_H ("outer"), R_B ("inner") or c ("gap") (:func:`corrected_outer_radius`,
    :func:`corrected_inner_radius`, :func:`corrected_gap`).  Element-wise :func:`close_chain` over arrays of shape
    (G,) (N and ``correct`` per design or one for all).  Invalid geometries give NaN or meaningless values, never an
    exception: the caller checks validity (:func:`geometry_problems`, :func:`chain_problems`).

    Parameters
    ----------
    outer_radius, inner_radius, eccentricity, gap : array_like
        Nominal R_H, R_B, e, c, [mm], shape (G,).
    n : array_like of int
        Integer roller numbers N, shape (G,) or scalar.
    correct : str or array_like of str
        "outer" | "inner" | "gap", or one per design.

    Returns
    -------
    chain : Chain
        Array attributes of shape (G,) (``correct`` an object array of strings).

    Examples
    --------
    >>> ch = close_chains(np.array([100.0, 100.0]), 50.0, 6.0, 6.0, np.array([8, 6]))
    >>> np.round(ch.corrected - ch.nominal, 6).tolist()
    [2.696917, 38.286579]

    References
    ----------
    .. [1] M. A. Merko, M. V. Mesnyankin, A. V. Kolotov, A. E. Mityaev, M. V. Savitskaya, A. M. Merko, S. A. Yurov,
       «Анализ нормальных напряжений на площадках контакта звеньев механизмов с ЗСТК при ведущем внутреннем кольце и
       вводе поправки по радиусу дорожки качения наружного кольца», Siberian Federal University, UDC 621.838.2 (seed
       file 003_2d1da402cb0b8488.txt; no journal or year given); closure of the chain with the correction of R_H;
       docs/spec/zstk.md §3.2.
    """
    r_h, r_b, e, c = np.broadcast_arrays(*(np.asarray(x, dtype=float) for x in
                                           (outer_radius, inner_radius, eccentricity, gap)))
    shape = r_h.shape
    n = broadcast(np.asarray(n), shape)
    corr = broadcast(np.asarray(correct, dtype=object), shape)
    with np.errstate(divide="ignore", invalid="ignore"):
        n_star = fractional_roller_number(r_h, r_b, e, c)
        exact = np.abs(n_star - n) < INTEGER_TOL
        out_h, out_b, out_c = r_h.copy(), r_b.copy(), c.copy()
        nominal, limit = np.empty(shape), np.empty(shape)
        for kind in set(corr.ravel().tolist()):
            m = corr == kind
            if kind == "outer":
                out_h = np.where(m & ~exact, corrected_outer_radius(n, r_b, e, c), out_h)
                nominal = np.where(m, r_h, nominal)
            elif kind == "inner":
                out_b = np.where(m & ~exact, corrected_inner_radius(n, r_h, e, c), out_b)
                nominal = np.where(m, r_b, nominal)
            elif kind == "gap":
                out_c = np.where(m & ~exact, corrected_gap(n, r_h, r_b, e), out_c)
                nominal = np.where(m, c, nominal)
            else:
                raise ValueError(f"unknown correction {kind!r}")
            limit = np.where(m, roller_number_limit(kind, r_h, r_b, e, c), limit)
    corrected = np.where(corr == "outer", out_h, np.where(corr == "inner", out_b, out_c))
    return Chain(out_h, out_b, e.copy(), out_c, n.astype(np.int64), n_star, corr, nominal, corrected, limit)


def close_chain(outer_radius, inner_radius, eccentricity, gap, n, correct="outer"):
    r"""Correct one parameter so that exactly N rollers close the chain.

    .. math:: \sin^2\frac{\pi}{N} = \frac{(W - e)(W + e)}{(S - e)(S + e)}, \qquad W = R_H - R_B + c,\ S = R_H + R_B

    solved for the corrected quantity.  When N equals N* (within :data:`INTEGER_TOL`) the correction is exactly
    zero.  Validity (spec §3.3) is checked by :func:`chain_problems`, not here.  The same arithmetic as
    :func:`close_chains` (one design).

    Parameters
    ----------
    outer_radius, inner_radius, eccentricity, gap : float
        Nominal R_H, R_B, e, c, [mm].
    n : int
        The integer roller number N, [-].
    correct : {"outer", "inner", "gap"}, optional
        The corrected quantity: R_H (the paper's), R_B or c.

    Returns
    -------
    chain : Chain
        The corrected geometry, N, N* and the nominal and corrected values, [mm].

    Examples
    --------
    >>> ch = close_chain(100.0, 50.0, 6.0, 6.0, 8)
    >>> round(ch.corrected - ch.nominal, 6)
    2.696917

    References
    ----------
    .. [1] M. A. Merko, M. V. Mesnyankin, A. V. Kolotov, A. E. Mityaev, M. V. Savitskaya, A. M. Merko, S. A. Yurov,
       «Анализ нормальных напряжений на площадках контакта звеньев механизмов с ЗСТК при ведущем внутреннем кольце и
       вводе поправки по радиусу дорожки качения наружного кольца», Siberian Federal University, UDC 621.838.2 (seed
       file 003_2d1da402cb0b8488.txt; no journal or year given); closure of the chain with the correction of R_H;
       docs/spec/zstk.md §3.2.
    """
    if correct not in ("outer", "inner", "gap"):
        raise ValueError(f"unknown correction {correct!r}")
    ch = close_chains(outer_radius, inner_radius, eccentricity, gap, n, correct)
    return Chain(float(ch.outer_radius), float(ch.inner_radius), float(ch.eccentricity), float(ch.gap), int(n),
                 float(ch.n_star), correct, float(ch.nominal), float(ch.corrected), float(ch.n_limit))



# ----------------------------------------------------------------------------- §4 positions
def limiting_point_ratio(outer_radius, inner_radius, eccentricity, gap):
    r"""The ratio q = x_s/X, with x_s the limiting point of the inflated circles inside the inner one.

    .. math:: q = \frac{x_s}{X}, \quad x_s = \frac{2 X^2 e}{X^2 - A^2 + e^2 + \sqrt{((X - e)^2 - A^2)((X + e)^2 -
              A^2)}}, \quad X = R_H + c/2,\ A = R_B - c/2

    x_s = 2X²e / (X² - A² + e² + sqrt(((X - e)² - A²)((X + e)² - A²))),  X = R_H + c/2,
    A = R_B - c/2.  q = 0 for e = 0 (no division by e).

    Parameters
    ----------
    outer_radius, inner_radius, eccentricity, gap : R_H, R_B, e, c [mm].

    Returns
    -------
    q [-], 0 <= q < 1 (float; an array for array inputs)

    Examples
    --------
    >>> float(limiting_point_ratio(100.0, 50.0, 0.0, 6.0))
    0.0

    References
    ----------
    derived; docs/spec/zstk.md §4.1 (Möbius map w = X(z - x_s)/(X² - x_s z)).
    """
    x = outer_radius + 0.5 * gap
    a = inner_radius - 0.5 * gap
    e = eccentricity
    root = np.sqrt(((x - e) ** 2 - a * a) * ((x + e) ** 2 - a * a))
    q = 2.0 * x * e / (x * x - a * a + e * e + root)
    return float(q) if np.ndim(q) == 0 else q


def limiting_ratios(chain: Chain, valid):
    r"""Limiting-point ratio q of stacked chains, 0 where ``valid`` is False (where q may be undefined).

    .. math:: q = \frac{x_s}{X} \ \text{where valid (as limiting\_point\_ratio)}, \qquad q = 0 \ \text{elsewhere}

    Parameters
    ----------
    chain : Chain
        Stacked chains, arrays of shape (G,).
    valid : ndarray of bool
        The valid designs, shape (G,).

    Returns
    -------
    q : ndarray
        Limiting-point ratios, [-], shape (G,).

    Examples
    --------
    >>> ch = close_chains(np.array([100.0, 100.0]), 50.0, np.array([6.0, 60.0]), 6.0, np.array([8, 8]))
    >>> np.round(limiting_ratios(ch, np.array([True, False])), 6).tolist()
    [0.070827, 0.0]

    References
    ----------
    .. [1] docs/spec/zstk.md §4.1 (derived).
    """
    if np.all(valid):
        return np.where(valid, chain.limiting_ratio, 0.0)
    q = np.zeros(valid.shape)
    q[valid] = limiting_point_ratio(chain.outer_radius[valid], chain.inner_radius[valid],
                                    chain.eccentricity[valid], chain.gap[valid])
    return np.where(valid, q, 0.0)


def chain_phases(n, q, scheme, mid_gap, angle, theta0):
    r"""Chain phases phi_0 of stacked designs [rad].

    .. math:: \varphi_0 = 0 \ \text{(A, B)}, \quad \frac{\pi}{N} \ \text{(C, D)}, \quad
        \varphi(\theta_0) \ \text{(a given angle of roller 0)}, \quad 0 \ \text{otherwise}

    Parameters
    ----------
    n : ndarray of int
        Roller numbers N, shape (G,).
    q : float or ndarray
        Limiting-point ratios, [-].
    scheme : ndarray of bool
        A symmetric scheme.
    mid_gap : ndarray of bool
        Scheme C or D (a gap at theta = 0).
    angle : ndarray of bool
        The angle of roller 0 is given.
    theta0 : ndarray
        That angle, [rad].

    Returns
    -------
    phi0 : ndarray
        Chain phases, [rad].

    Examples
    --------
    >>> t = np.array([True, True, False])
    >>> np.round(chain_phases(np.array([8, 8, 8]), 0.0, t, np.array([False, True, False]), ~t,
    ...                       np.array([0.0, 0.0, 0.5])), 6).tolist()
    [0.0, 0.392699, 0.5]

    References
    ----------
    .. [1] M. A. Merko, M. V. Mesnyankin, A. V. Kolotov, A. E. Mityaev, M. V. Savitskaya, A. M. Merko, S. A. Yurov,
       «Анализ нормальных напряжений на площадках контакта звеньев механизмов с ЗСТК при ведущем внутреннем кольце и
       вводе поправки по радиусу дорожки качения наружного кольца», Siberian Federal University, UDC 621.838.2 (seed
       file 003_2d1da402cb0b8488.txt; no journal or year given); its schemes A-D; docs/spec/zstk.md §4.2-4.3.
    """
    return np.where(scheme, np.where(mid_gap, np.pi / np.maximum(n, 1), 0.0),
                    np.where(angle, phi_of_theta(theta0, q), 0.0))


def theta_of_phi(phi, q):
    r"""Polar angle theta of a roller centre from its uniformising angle phi.

    .. math:: \theta = \varphi - 2 \operatorname{atan2}(q \sin\varphi,\ 1 + q \cos\varphi)

    theta = phi - 2 atan2(q sin phi, 1 + q cos phi).

    Parameters
    ----------
    phi [rad]; q : limiting-point ratio [-].

    Returns
    -------
    theta [rad] (continuous in phi: theta(phi + 2 pi) = theta(phi) + 2 pi)

    Examples
    --------
    >>> round(float(theta_of_phi(phi_of_theta(0.7, 0.3), 0.3)), 15)
    0.7

    References
    ----------
    derived; docs/spec/zstk.md §4.1.
    """
    return phi - 2.0 * np.arctan2(q * np.sin(phi), 1.0 + q * np.cos(phi))


def phi_of_theta(theta, q):
    r"""Uniformising angle phi of a roller centre from its polar angle theta [rad]: the inverse of :func:`theta_of_phi`.

    .. math:: \varphi = \theta + 2 \operatorname{atan2}(q \sin\theta,\ 1 - q \cos\theta)

    Parameters
    ----------
    theta : float or array_like
        Polar angle, [rad].
    q : float or array_like
        Limiting-point ratio, [-].

    Returns
    -------
    phi : ndarray
        Uniformising angle, [rad].

    Examples
    --------
    >>> float(phi_of_theta(np.pi, 0.5))
    3.141592653589793

    References
    ----------
    .. [1] docs/spec/zstk.md §4.1 (derived: the Möbius map of the limiting points).
    """
    return theta + 2.0 * np.arctan2(q * np.sin(theta), 1.0 - q * np.cos(theta))


def roller_angles(phase, n, q, pitch=None):
    r"""Polar angles theta_k = theta(phi_0 + 2 pi k/N) of the N roller centres, k = 0 ... N-1.

    .. math:: \theta_k = \theta(\varphi_0 + 2\pi k / N), \quad k = 0 \ldots N - 1

    Parameters
    ----------
    phase : chain phase phi_0 [rad], any shape (...).
    n : roller count N.
    q : limiting-point ratio [-], a scalar or an array broadcastable to phase (one per design).
    pitch : spacing in phi [rad]; default 2 pi/N (2 pi/N* for an open chain).

    Returns
    -------
    theta [rad], shape (..., N)

    Examples
    --------
    >>> np.round(np.degrees(roller_angles(0.0, 4, 0.0)), 9).tolist()
    [0.0, 90.0, 180.0, 270.0]

    References
    ----------
    derived; docs/spec/zstk.md §4.1, §4.2 (the paper's schemes A-D).
    """
    pitch = 2.0 * np.pi / n if pitch is None else pitch
    phi = np.asarray(phase, dtype=float)[..., None] + pitch * np.arange(n)
    return theta_of_phi(phi, np.asarray(q, dtype=float)[..., None])


def scheme_phase(scheme, n):
    r"""Chain phase phi_0 of a symmetric scheme [rad].

    .. math:: \varphi_0 = 0 \ \text{(A, B)}, \qquad \varphi_0 = \frac{\pi}{N} \ \text{(C, D)}

    Parameters
    ----------
    scheme : {"A", "B", "C", "D"}
        The paper's scheme.
    n : int
        Roller number N, [-].

    Returns
    -------
    phi0 : float
        Chain phase, [rad].

    Examples
    --------
    >>> scheme_phase("A", 8), round(scheme_phase("D", 8), 12)
    (0.0, 0.392699081699)

    References
    ----------
    .. [1] M. A. Merko, M. V. Mesnyankin, A. V. Kolotov, A. E. Mityaev, M. V. Savitskaya, A. M. Merko, S. A. Yurov,
       «Анализ нормальных напряжений на площадках контакта звеньев механизмов с ЗСТК при ведущем внутреннем кольце и
       вводе поправки по радиусу дорожки качения наружного кольца», Siberian Federal University, UDC 621.838.2 (seed
       file 003_2d1da402cb0b8488.txt; no journal or year given); its schemes A-D; docs/spec/zstk.md §4.2.
    """
    return 0.0 if scheme in ("A", "B") else math.pi / n


def centres(theta, outer_radius, inner_radius, eccentricity):
    r"""Roller centres P in the frame of O_H [mm].

    .. math:: P = h(\theta)\,(\cos\theta,\ \sin\theta)

    with h the centre distance O_H P (:func:`~gearcalc.zstk.geometry.centre_distance`).

    Parameters
    ----------
    theta : array_like
        Polar angles of the roller centres, [rad].
    outer_radius, inner_radius, eccentricity : float or array_like
        R_H, R_B, e, [mm].

    Returns
    -------
    P : ndarray
        Centres, [mm], shape (..., 2).

    Examples
    --------
    >>> np.round(centres(np.array([0.0]), 100.0, 50.0, 6.0), 9).tolist()   # h(0) = R_H - r(0) = 100 - 22
    [[78.0, 0.0]]

    References
    ----------
    .. [1] docs/spec/zstk.md §3.1 (derived).
    """
    h = centre_distance(theta, outer_radius, inner_radius, eccentricity)
    return np.stack([h * np.cos(theta), h * np.sin(theta)], axis=-1)


def neighbour_gaps(theta, outer_radius, inner_radius, eccentricity):
    """Gaps between consecutive rollers (the last with the first) [mm].

    .. math:: c_k = |P_{k+1} - P_k| - r_k - r_{k+1}

    Parameters
    ----------
    theta : ndarray
        Polar angles of the roller centres, [rad], shape (..., N).
    outer_radius, inner_radius, eccentricity : float or array_like
        R_H, R_B, e, [mm].

    Returns
    -------
    gaps : ndarray
        c_k, [mm], shape (..., N).

    Examples
    --------
    >>> ch = close_chain(100.0, 50.0, 6.0, 6.0, 8)
    >>> th = roller_angles(0.3, ch.n, ch.limiting_ratio)
    >>> bool(np.allclose(neighbour_gaps(th, ch.outer_radius, ch.inner_radius, ch.eccentricity), 6.0, atol=1e-9))
    True

    References
    ----------
    .. [1] docs/spec/zstk.md §3.2, §7.2 (the gap invariant).
    """
    p = centres(theta, outer_radius, inner_radius, eccentricity)
    r = roller_radius(theta, outer_radius, inner_radius, eccentricity)
    p_next, r_next = np.roll(p, -1, axis=-2), np.roll(r, -1, axis=-1)
    return np.linalg.norm(p_next - p, axis=-1) - r - r_next


def step_chain(theta0, n, outer_radius, inner_radius, eccentricity, gap, scan=64):
    """Explicit stepping of the chain (the cross-check of spec §4.1), vectorised over starts.

    .. math:: g(t) = |P(t) - P_k| - r_k - r(t) - c = 0

    From theta_k, scan forward (one turn) to the first sign change of g(t) = |P(t) - P_k| - r_k - r(t) - c
    and solve g = 0 with the bracketed root finder to 1e-14 rad.  After N steps the chain
    should return to roller 0.

    Parameters
    ----------
    theta0 : start angles [rad], shape (...).
    n : number of steps N.
    outer_radius, inner_radius, eccentricity, gap : the (corrected) geometry [mm], scalars or arrays
        broadcastable to theta0 (stacked designs of the same N).
    scan : scan points per half turn ahead (the whole turn ahead is scanned).

    Returns
    -------
    (theta, residual): the stepped angles, shape (..., N + 1), and the closure residual
    |P_N - P_0| [mm], shape (...).

    Examples
    --------
    >>> ch = close_chain(100.0, 50.0, 6.0, 6.0, 8)
    >>> _, res = step_chain(0.4, ch.n, ch.outer_radius, ch.inner_radius, ch.eccentricity, ch.gap)
    >>> bool(res < 1e-9)
    True

    References
    ----------
    docs/spec/zstk.md §4.1 (the cross-check of the closed form), §8 (reference level).
    """
    theta0, r_h, r_b, e, c = np.broadcast_arrays(*(np.asarray(x, dtype=float) for x in
                                                    (theta0, outer_radius, inner_radius, eccentricity, gap)))
    base = theta0.ndim

    def geo(t):
        """The geometry (R_H, R_B, e, c) shaped to broadcast against t (one design per start)."""
        tail = (1,) * (np.ndim(t) - base)
        return tuple(np.reshape(x, x.shape + tail) for x in (r_h, r_b, e, c))

    th = [theta0]
    # the whole turn ahead: in a very eccentric chain a neighbour can lie more than 180 degrees ahead
    frac = np.linspace(0.0, 2.0 * np.pi, 2 * scan + 1)[1:]
    for _ in range(n):  # sequential by nature; a cross-check only, never on the hot path
        tk = th[-1]
        pk = centres(tk, *geo(tk)[:3])
        rk = roller_radius(tk, *geo(tk)[:3])

        def g(t, pk=pk, rk=rk):
            pk_b = pk.reshape(pk.shape[:-1] + (1,) * (np.ndim(t) - np.ndim(rk)) + (2,))
            rk_b = np.reshape(rk, np.shape(rk) + (1,) * (np.ndim(t) - np.ndim(rk)))
            gt = geo(t)
            return (np.linalg.norm(centres(t, *gt[:3]) - pk_b, axis=-1) - rk_b
                    - roller_radius(t, *gt[:3]) - gt[3])

        ts = tk[..., None] + frac
        gs = g(ts)
        first = np.argmax(gs > 0, axis=-1)
        hi = np.take_along_axis(ts, first[..., None], axis=-1)[..., 0]
        lo = np.where(first > 0, np.take_along_axis(ts, np.maximum(first - 1, 0)[..., None], axis=-1)[..., 0], tk)
        th.append(find_root(g, lo, hi, xtol=1e-14).root)
    theta = np.stack(th, axis=-1)
    g0 = geo(theta0)[:3]
    residual = np.linalg.norm(centres(theta[..., -1], *g0) - centres(theta[..., 0], *g0), axis=-1)
    return theta, residual


