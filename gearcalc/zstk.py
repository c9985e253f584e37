"""Physics of the eccentric closed rolling-body mechanism (ZSTK) with a leading inner ring.

Pure functions over floats and numpy arrays (no I/O).  Units: mm, N, MPa, radians inside;
degrees only at the interface (:mod:`gearcalc.kinds.zstk`).  Arrays of roller quantities have
the shape ``(..., N)``: leading axes for phases, load directions or stacked designs.

Frame: O_H = (0, 0), O_B = (e, 0); +x points to the narrowest point of the annular gap
(theta = 0); angles grow counter-clockwise.

Sections (spec ``zstk.md``):

* §3.1 roller radius, centre distance, contact normals and beta (closed form);
* §3.2-3.3 closure as a Steiner chain: N*, the corrections of R_H, R_B or c, N_max;
* §4 the roller positions through the Möbius map (and explicit stepping as a cross-check);
* §5 the load distribution (zero clearance: direction root; clearance/preload: bracketed
  1-D root or Newton on the convex potential);
* §2 the Hertz stresses (through :mod:`gearcalc.hertz`);
* §8 the sweeps over the chain phase ("cycle") and the load direction ("envelope").

Reference: Merko M.A. et al., «Анализ нормальных напряжений на площадках контакта звеньев
механизмов с ЗСТК ...» (seed 003_2d1da402cb0b8488.txt), eqs. (1)-(7); gearcalc spec zstk.md.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from . import hertz
from .roots import find_root, minimize_golden

LOAD_EXPONENT = 10.0 / 9.0
"""Exponent of the roller load-deflection law F = c_L·delta^(10/9) (line contact)."""
E_STAR_REF = 2.1e5 / (2.0 * (1.0 - 0.3 ** 2))
"""Contact modulus of two steel bodies (E = 2.1e5 MPa, nu = 0.3) [MPa] (spec §11.4)."""
SCHEME_PARITY = {"A": 0, "B": 1, "C": 1, "D": 0}
"""N mod 2 of each symmetric scheme (spec §4.2)."""
INTEGER_TOL = 1e-9
"""|N* - round(N*)| below this makes N* an integer (spec §11.5)."""


# ----------------------------------------------------------------------------- helpers
def broadcast(a, shape):
    """``np.broadcast_to`` that returns an array already of the shape unchanged (cheap on hot paths).

    >>> broadcast(2.0, (3,)).tolist()
    [2.0, 2.0, 2.0]
    """
    a = np.asarray(a)
    return a if a.shape == shape else np.broadcast_to(a, shape)


def wrap_angle(angle):
    """Angle wrapped to (-pi, pi] [rad].

    >>> float(wrap_angle(np.pi)), float(wrap_angle(-np.pi)), round(float(wrap_angle(3 * np.pi / 2)), 12)
    (3.141592653589793, 3.141592653589793, -1.570796326795)
    """
    return np.pi - np.mod(np.pi - np.asarray(angle, dtype=float), 2.0 * np.pi)


# ----------------------------------------------------------------------------- §3.1 geometry
def roller_radius(theta, outer_radius, inner_radius, eccentricity):
    """Radius of the roller tangent to both raceways whose centre lies at polar angle theta.

    r(theta) = [(D - e)(S - e) + 4 R_H e sin²(theta/2)] / [2((S - e) + 2 e sin²(theta/2))],
    with S = R_H + R_B and D = R_H - R_B; every term is non-negative (no cancellation).

    Parameters
    ----------
    theta : polar angle of the roller centre about O_H, from the narrowest point [rad].
    outer_radius, inner_radius : R_H, R_B [mm].
    eccentricity : e [mm].

    Returns
    -------
    r [mm]; r(0) = (D - e)/2 and r(pi) = (D + e)/2.

    Examples
    --------
    >>> float(roller_radius(0.0, 100.0, 50.0, 6.0)), float(roller_radius(np.pi, 100.0, 50.0, 6.0))
    (22.0, 28.0)

    References
    ----------
    spec zstk.md §3.1 (centre locus: the ellipse with foci O_H, O_B and major axis S).
    """
    s, d = outer_radius + inner_radius, outer_radius - inner_radius
    h2 = np.sin(0.5 * np.asarray(theta, dtype=float)) ** 2
    e = eccentricity
    return ((d - e) * (s - e) + 4.0 * outer_radius * e * h2) / (2.0 * ((s - e) + 2.0 * e * h2))


def centre_distance(theta, outer_radius, inner_radius, eccentricity):
    """Distance h = |O_H P| of the roller centre from the outer-ring centre.

    h(theta) = (S² - e²) / (2 (S - e cos theta)) = R_H - r(theta).

    Parameters
    ----------
    theta [rad]; outer_radius, inner_radius, eccentricity [mm].

    Returns
    -------
    h [mm]

    Examples
    --------
    >>> float(centre_distance(0.0, 100.0, 50.0, 6.0))
    78.0

    References
    ----------
    spec zstk.md §3.1.
    """
    s, e = outer_radius + inner_radius, eccentricity
    return (s - e) * (s + e) / (2.0 * (s - e * np.cos(theta)))


def normal_angle_offset(theta, outer_radius, inner_radius, eccentricity):
    """Signed angle beta_s from the outer normal n_H to the inner normal n_B (counter-clockwise).

    beta_s = atan2(e sin theta, h - e cos theta); |beta_s| = beta = angle O_B P O_H, and the
    polar angle of n_B = (P - O_B)/|P - O_B| is theta + beta_s.

    Parameters
    ----------
    theta [rad]; outer_radius, inner_radius, eccentricity [mm].

    Returns
    -------
    beta_s [rad], in (-pi/2, pi/2) for a valid design (e < S/sqrt 2).

    Examples
    --------
    >>> float(normal_angle_offset(0.0, 100.0, 50.0, 6.0)), float(normal_angle_offset(np.pi, 100.0, 50.0, 0.0))
    (0.0, 0.0)

    References
    ----------
    spec zstk.md §3.1 (sin beta = e |sin theta|/(R_B + r)).
    """
    h = centre_distance(theta, outer_radius, inner_radius, eccentricity)
    return np.arctan2(eccentricity * np.sin(theta), h - eccentricity * np.cos(theta))


def reduced_radii(roller_r, centre_dist, inner_radius, outer_radius):
    """Reduced radii of the inner and outer contact of each roller (the paper's eqs. 4, 5).

    rho_B = r R_B/(R_B + r) (convex on convex);  rho_H = r R_H/(R_H - r) = r R_H/h (convex in
    concave), formed with h so that no R_H - r is subtracted.

    Parameters
    ----------
    roller_r : r [mm]; centre_dist : h = R_H - r [mm]; inner_radius, outer_radius : R_B, R_H [mm].

    Returns
    -------
    (rho_B, rho_H) [mm]

    Examples
    --------
    >>> [round(float(x), 6) for x in reduced_radii(22.0, 78.0, 50.0, 100.0)]
    [15.277778, 28.205128]

    References
    ----------
    Merko et al., eqs. (4) and (5).
    """
    return (roller_r * inner_radius / (inner_radius + roller_r),
            roller_r * outer_radius / centre_dist)


# ----------------------------------------------------------------------------- §3.2 closure
def fractional_roller_number(outer_radius, inner_radius, eccentricity, gap):
    """Fractional roller number N* that closes the nominal chain (Steiner chain condition).

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
    spec zstk.md §3.2, condition (C); Coxeter & Greitzer 1967 (inversive distance of a chain).
    """
    s = outer_radius + inner_radius
    w = outer_radius - inner_radius + gap
    e = eccentricity
    ratio = (w - e) * (w + e) / ((s - e) * (s + e))
    return np.pi / np.arcsin(np.sqrt(ratio))


def corrected_outer_radius(n, inner_radius, eccentricity, gap):
    """Outer raceway radius R_H' that closes a chain of exactly N rollers (correction "outer").

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
    spec zstk.md §3.2 (closed-form root of (C)); the paper corrects R_H.
    """
    s2 = np.sin(np.pi / n) ** 2
    k2 = np.cos(np.pi / n) ** 2
    return (inner_radius * (1.0 + s2) - gap
            + np.sqrt(s2 * (2.0 * inner_radius - gap) ** 2 + eccentricity ** 2 * k2 * k2)) / k2


def corrected_inner_radius(n, outer_radius, eccentricity, gap):
    """Inner raceway radius R_B' that closes a chain of exactly N rollers (correction "inner").

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
    spec zstk.md §3.2.
    """
    s2 = np.sin(np.pi / n) ** 2
    k2 = np.cos(np.pi / n) ** 2
    return (outer_radius * (1.0 + s2) + gap
            - np.sqrt(s2 * (2.0 * outer_radius + gap) ** 2 + eccentricity ** 2 * k2 * k2)) / k2


def corrected_gap(n, outer_radius, inner_radius, eccentricity):
    """Roller gap c' that closes a chain of exactly N rollers (correction "gap").

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
    spec zstk.md §3.2 (gearcalc's own option; the paper does not use it).
    """
    s = outer_radius + inner_radius
    return (np.sqrt(s * s * np.sin(np.pi / n) ** 2 + eccentricity ** 2 * np.cos(np.pi / n) ** 2)
            - (outer_radius - inner_radius))


def roller_number_limit(correct, outer_radius, inner_radius, eccentricity, gap):
    """The bound N_max of the admissible roller numbers 3 <= N < N_max (N <= N_max for "gap").

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
    spec zstk.md §3.3.
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
    """The default N: the largest integer <= N* (of the scheme's parity, if one is given).

    N* within :data:`INTEGER_TOL` of an integer counts as that integer (spec §11.5).

    Parameters
    ----------
    n_star : N* [-]; parity : 0 (even), 1 (odd) or None (any).

    Returns
    -------
    N (int; may be < 3, which the caller reports)

    Examples
    --------
    >>> auto_roller_number(8.25), auto_roller_number(8.25, 1), auto_roller_number(7.9999999999, 0)
    (8, 7, 8)
    """
    nearest = round(n_star)
    n = nearest if abs(n_star - nearest) < INTEGER_TOL else math.floor(n_star)
    if parity is not None and n % 2 != parity:
        n -= 1
    return int(n)


def auto_roller_numbers(n_star, parity):
    """:func:`auto_roller_number` over arrays: parity 0 (even), 1 (odd) or -1 (any), element-wise.

    Examples
    --------
    >>> auto_roller_numbers(np.array([8.25, 8.25, 7.9999999999]), np.array([-1, 1, 0])).tolist()
    [8, 7, 8]
    """
    n_star = np.asarray(n_star, dtype=float)
    nearest = np.round(n_star)
    n = np.where(np.abs(n_star - nearest) < INTEGER_TOL, nearest, np.floor(n_star)).astype(np.int64)
    parity = np.asarray(parity)
    return np.where((parity >= 0) & (n % 2 != parity), n - 1, n)


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
        q = limiting_point_ratio(self.outer_radius, self.inner_radius, self.eccentricity, self.gap)
        return float(q) if np.ndim(q) == 0 else q


def close_chains(outer_radius, inner_radius, eccentricity, gap, n, correct="outer"):
    """Correct one parameter of each of many designs so that exactly N rollers close each chain.

    Element-wise :func:`close_chain` over arrays of shape (G,) (N and ``correct`` per design or
    one for all).  Invalid geometries give NaN or meaningless values, never an exception: the
    caller checks validity (:func:`geometry_problems`, :func:`chain_problems`).

    Parameters
    ----------
    outer_radius, inner_radius, eccentricity, gap : nominal R_H, R_B, e, c [mm], shape (G,).
    n : integer roller numbers N, shape (G,) or scalar.
    correct : "outer" | "inner" | "gap", or an array of them (one per design).

    Returns
    -------
    Chain with array attributes of shape (G,) (``correct`` an object array of strings).

    Examples
    --------
    >>> ch = close_chains(np.array([100.0, 100.0]), 50.0, 6.0, 6.0, np.array([8, 6]))
    >>> np.round(ch.corrected - ch.nominal, 6).tolist()
    [2.696917, 38.286579]

    References
    ----------
    spec zstk.md §3.2.
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
    """Correct one parameter so that exactly N rollers close the chain.

    Parameters
    ----------
    outer_radius, inner_radius, eccentricity, gap : nominal R_H, R_B, e, c [mm].
    n : the integer roller number N.
    correct : which quantity is corrected: "outer" (R_H, the paper's), "inner" (R_B), "gap" (c).

    Returns
    -------
    Chain.  When N equals N* (within :data:`INTEGER_TOL`) the correction is exactly zero.
    Validity (spec §3.3) is checked by :func:`chain_problems`, not here.  The same arithmetic as
    :func:`close_chains` (one design).

    Examples
    --------
    >>> ch = close_chain(100.0, 50.0, 6.0, 6.0, 8)
    >>> round(ch.corrected - ch.nominal, 6)
    2.696917

    References
    ----------
    spec zstk.md §3.2.
    """
    if correct not in ("outer", "inner", "gap"):
        raise ValueError(f"unknown correction {correct!r}")
    ch = close_chains(outer_radius, inner_radius, eccentricity, gap, n, correct)
    return Chain(float(ch.outer_radius), float(ch.inner_radius), float(ch.eccentricity), float(ch.gap), int(n),
                 float(ch.n_star), correct, float(ch.nominal), float(ch.corrected), float(ch.n_limit))


def geometry_problems(outer_radius, inner_radius, eccentricity, gap):
    """Violations of the validity conditions of spec §3.3 / §11.2 for one geometry.

    Returns a list of (quantity, message) with quantity in {"outer", "inner", "eccentricity",
    "gap"}; empty when R_H > R_B > 0, 0 <= e < R_H - R_B, e < S/sqrt 2 and 0 <= c < 2R_B.

    Examples
    --------
    >>> geometry_problems(100.0, 50.0, 6.0, 6.0)
    []
    >>> geometry_problems(100.0, 50.0, 52.0, 6.0)[0][0]
    'eccentricity'
    """
    out = []
    r_h, r_b, e, c = outer_radius, inner_radius, eccentricity, gap
    if not r_b > 0:
        out.append(("inner", f"= {r_b:g}: must be > 0"))
    if not r_h > r_b:
        out.append(("inner", (f"= {r_b:g}: must be < outer_raceway_radius_mm = {r_h:g} "
                             "(the inner raceway lies inside the outer one)")))
        return out
    if not 0 <= e < r_h - r_b:
        out.append(("eccentricity", (f"= {e:g}: must be >= 0 and < outer_raceway_radius_mm − "
                    f"inner_raceway_radius_mm = {r_h - r_b:g} (smallest roller radius (R_H − R_B − e)/2 "
                    "would be ≤ 0)")))
    elif not e < (r_h + r_b) / math.sqrt(2.0):
        out.append(("eccentricity", (f"= {e:g}: must be < (R_H + R_B)/√2 = {(r_h + r_b) / math.sqrt(2.0):g} "
                    "(the contact normals of the widest rollers would diverge by ≥ 90°)")))
    if not 0 <= c < 2 * r_b:
        out.append(("gap", (f"= {c:g}: must be >= 0 and < 2·inner_raceway_radius_mm = {2 * r_b:g} "
                           "(the rollers inflated by c/2 must stay outside the inner raceway)")))
    return out


def chain_problems(chain: Chain):
    """Violations of spec §3.3 by a corrected chain: list of (quantity, message).

    Checks N >= 3, N inside the admissible interval, and the corrected geometry (the same
    conditions as :func:`geometry_problems` plus the correction-specific one).

    Examples
    --------
    >>> chain_problems(close_chain(100.0, 50.0, 6.0, 6.0, 8))
    []
    >>> chain_problems(close_chain(100.0, 50.0, 6.0, 6.0, 40))[0][0]
    'rollers'
    """
    lim = chain.n_limit
    if chain.correct == "gap":
        ok = chain.n <= lim + INTEGER_TOL
        rng = f"3 ≤ N ≤ {math.floor(lim + INTEGER_TOL)}"
    else:
        ok = chain.n < lim - INTEGER_TOL if math.isfinite(lim) else True
        rng = (f"3 ≤ N ≤ {math.ceil(lim - INTEGER_TOL) - 1} (N < N_max = {lim:.6g})"
               if math.isfinite(lim) else "N ≥ 3")
    what = {"outer": "outer_raceway_radius_mm", "inner": "inner_raceway_radius_mm",
            "gap": "roller_gap_mm"}[chain.correct]
    if chain.n < 3 or not ok:
        return [("rollers", (f"= {chain.n}: must be in the admissible range {rng} for correct = "
                            f"\"{chain.correct}\" (N* = {chain.n_star:.6g}; beyond the range the corrected "
                            f"{what} = {chain.corrected:.6g} leaves no valid chain)"))]
    out = []
    for key, msg in geometry_problems(chain.outer_radius, chain.inner_radius, chain.eccentricity, chain.gap):
        out.append(("rollers", (f"= {chain.n}: the corrected geometry ({what} = {chain.corrected:.6g}) is "
                               f"invalid: {key} {msg}")))
    return out


# ----------------------------------------------------------------------------- §4 positions
def limiting_point_ratio(outer_radius, inner_radius, eccentricity, gap):
    """q = x_s/X, with x_s the limiting point of the inflated circles inside the inner one.

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
    spec zstk.md §4.1 (Möbius map w = X(z - x_s)/(X² - x_s z)).
    """
    x = outer_radius + 0.5 * gap
    a = inner_radius - 0.5 * gap
    e = eccentricity
    root = np.sqrt(((x - e) ** 2 - a * a) * ((x + e) ** 2 - a * a))
    q = 2.0 * x * e / (x * x - a * a + e * e + root)
    return float(q) if np.ndim(q) == 0 else q


def theta_of_phi(phi, q):
    """Polar angle theta of a roller centre from its uniformising angle phi.

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
    spec zstk.md §4.1.
    """
    return phi - 2.0 * np.arctan2(q * np.sin(phi), 1.0 + q * np.cos(phi))


def phi_of_theta(theta, q):
    """Inverse of :func:`theta_of_phi`: phi = theta + 2 atan2(q sin theta, 1 - q cos theta) [rad].

    Examples
    --------
    >>> float(phi_of_theta(np.pi, 0.5))
    3.141592653589793
    """
    return theta + 2.0 * np.arctan2(q * np.sin(theta), 1.0 - q * np.cos(theta))


def roller_angles(phase, n, q, pitch=None):
    """Polar angles theta_k = theta(phi_0 + 2 pi k/N) of the N roller centres, k = 0 ... N-1.

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
    spec zstk.md §4.1.
    """
    pitch = 2.0 * np.pi / n if pitch is None else pitch
    phi = np.asarray(phase, dtype=float)[..., None] + pitch * np.arange(n)
    return theta_of_phi(phi, np.asarray(q, dtype=float)[..., None])


def scheme_phase(scheme, n):
    """Chain phase phi_0 of a symmetric scheme [rad]: 0 for A and B, pi/N for C and D.

    Examples
    --------
    >>> scheme_phase("A", 8), round(scheme_phase("D", 8), 12)
    (0.0, 0.392699081699)

    References
    ----------
    spec zstk.md §4.2.
    """
    return 0.0 if scheme in ("A", "B") else math.pi / n


def centres(theta, outer_radius, inner_radius, eccentricity):
    """Roller centres P = h (cos theta, sin theta) [mm], shape (..., 2)."""
    h = centre_distance(theta, outer_radius, inner_radius, eccentricity)
    return np.stack([h * np.cos(theta), h * np.sin(theta)], axis=-1)


def neighbour_gaps(theta, outer_radius, inner_radius, eccentricity):
    """Gaps |P_{k+1} - P_k| - r_k - r_{k+1} between consecutive rollers (the last with the first) [mm].

    Examples
    --------
    >>> ch = close_chain(100.0, 50.0, 6.0, 6.0, 8)
    >>> th = roller_angles(0.3, ch.n, ch.limiting_ratio)
    >>> bool(np.allclose(neighbour_gaps(th, ch.outer_radius, ch.inner_radius, ch.eccentricity), 6.0, atol=1e-9))
    True
    """
    p = centres(theta, outer_radius, inner_radius, eccentricity)
    r = roller_radius(theta, outer_radius, inner_radius, eccentricity)
    p_next, r_next = np.roll(p, -1, axis=-2), np.roll(r, -1, axis=-1)
    return np.linalg.norm(p_next - p, axis=-1) - r - r_next


def step_chain(theta0, n, outer_radius, inner_radius, eccentricity, gap, scan=64):
    """Explicit stepping of the chain (the cross-check of spec §4.1), vectorised over starts.

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


# ----------------------------------------------------------------------------- materials
def roller_stiffness(length, e_star_inner=E_STAR_REF, e_star_outer=E_STAR_REF):
    """Roller load-deflection constant c_L of both contacts in series [N/mm^(10/9)].

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
    ISO/TS 16281:2008; spec zstk.md §5 item 4 and §11.4.
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
    """Roller forces without clearance: the direction root of spec §5.1.

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
    spec zstk.md §5, §5.1.
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
    """Roller forces with clearance (or preload) and v parallel to u (spec §5.2, symmetric case).

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
    spec zstk.md §5.2.
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
    """Roller forces with clearance or preload, full 2-D equilibrium (spec §5.2, general case).

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
    spec zstk.md §5.2, §11.1.
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
    """Dispatch to the load model (spec §5, §8): closed form, direction root, 1-D or Newton solve.

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


# ----------------------------------------------------------------------------- evaluation
@dataclass
class Materials:
    """Contact moduli and the roller constant of a design.

    e_star_inner, e_star_outer : E*_B, E*_H [MPa]; length : l [mm]; stiffness : c_L.
    Floats for one design, arrays of shape (G,) for stacked designs.
    """

    e_star_inner: float
    e_star_outer: float
    length: float
    stiffness: float

    @classmethod
    def from_elastic(cls, length, roller_e, roller_nu, inner_e, inner_nu, outer_e, outer_nu):
        eb = hertz.contact_modulus(roller_e, roller_nu, inner_e, inner_nu)
        eh = hertz.contact_modulus(roller_e, roller_nu, outer_e, outer_nu)
        stiffness = roller_stiffness(length, eb, eh)
        if np.ndim(stiffness) == 0:
            return cls(float(eb), float(eh), float(length), float(stiffness))
        return cls(*(broadcast(np.asarray(x, dtype=float), np.shape(stiffness)) for x in
                     (eb, eh, length, stiffness)))


@dataclass
class State:
    """Everything about the rollers of one or many configurations (arrays (..., N) or (...))."""

    theta: np.ndarray
    radius: np.ndarray
    beta: np.ndarray
    normal_angle: np.ndarray
    force_inner: np.ndarray
    force_outer: np.ndarray
    rho_inner: np.ndarray
    rho_outer: np.ndarray
    sigma_inner: np.ndarray
    sigma_outer: np.ndarray
    gamma: np.ndarray
    loads: LoadSolution

    @property
    def psi(self) -> np.ndarray:
        """Angle from the load direction u to each inner normal n_Bi, in (-pi, pi] [rad]."""
        return wrap_angle(self.normal_angle - self.gamma[..., None])


def evaluate(chain: Chain, mats: Materials, theta, gamma, load, clearance=0.0, symmetric=False,
             fixed_direction=False) -> State:
    """Loads and Hertz stresses of every roller for roller angles theta and load directions gamma.

    F_iH = F_iB cos beta_i (separator equilibrium); sigma = sqrt(F E*/(pi l rho)), the paper's
    eq. (3) (= Johnson's p0).

    Parameters
    ----------
    chain : the closed chain; mats : materials (floats, or arrays broadcastable to (...) for stacked
        designs of the same N, e.g. shape (G,) with theta of shape (G, N)).
    theta : roller angles [rad], (..., N); gamma : load directions [rad], broadcastable to (...).
    load : Q [N]; clearance : s [mm] (floats or arrays broadcastable to (...));
    symmetric, fixed_direction : see :func:`solve_loads`.

    Returns
    -------
    State

    Examples
    --------
    >>> ch = close_chain(100.0, 50.0, 6.0, 6.0, 8)
    >>> m = Materials.from_elastic(20.0, 2.1e5, 0.3, 2.1e5, 0.3, 2.1e5, 0.3)
    >>> st = evaluate(ch, m, roller_angles(0.0, 8, ch.limiting_ratio), 0.0, 1e4, symmetric=True)
    >>> bool(st.sigma_inner[0] > st.sigma_outer[0] > 0)
    True

    References
    ----------
    Merko et al., eqs. (3)-(7); spec zstk.md §2, §5.
    """
    # per-design quantities as (..., 1): they broadcast against the rollers (floats give shape (1,))
    r_h, r_b, e = (_per_roller(x) for x in (chain.outer_radius, chain.inner_radius, chain.eccentricity))
    theta = np.asarray(theta, dtype=float)
    gamma = np.asarray(gamma, dtype=float)
    shape = np.broadcast_shapes(theta.shape[:-1], gamma.shape, r_h.shape[:-1], np.shape(load),
                                np.shape(clearance), np.shape(mats.stiffness))
    full = shape + theta.shape[-1:]
    # the geometry depends on the phase only: computed on theta's own shape, then broadcast (views)
    r = roller_radius(theta, r_h, r_b, e)
    h = centre_distance(theta, r_h, r_b, e)
    beta_s = np.arctan2(e * np.sin(theta), h - e * np.cos(theta))
    nb = theta + beta_s
    rho_b, rho_h = reduced_radii(r, h, r_b, r_h)
    gamma = broadcast(gamma, shape)
    sol = solve_loads(broadcast(nb, full), gamma, load, mats.stiffness, clearance, symmetric,
                      fixed_direction)
    f_b = sol.force
    f_h = f_b * np.cos(beta_s)
    length = _per_roller(mats.length)
    sig_b = hertz.peak_pressure(f_b, length, rho_b, _per_roller(mats.e_star_inner))
    sig_h = hertz.peak_pressure(f_h, length, rho_h, _per_roller(mats.e_star_outer))

    def b(a):
        return broadcast(a, full)

    return State(b(theta), b(r), b(np.abs(beta_s)), b(nb), f_b, f_h, b(rho_b), b(rho_h), sig_b, sig_h,
                 np.asarray(gamma), sol)


def critical(state: State):
    """Location of the largest stress of each configuration.

    Returns (sigma_max, roller index, contact 0 = inner / 1 = outer), arrays of shape (...);
    ties (mirror rollers) go to the lowest index, inner before outer.
    """
    both = np.stack([state.sigma_inner, state.sigma_outer], axis=-2)  # (..., 2, N)
    flat = both.reshape(both.shape[:-2] + (-1,))
    smax = np.max(flat, axis=-1)
    near = flat >= smax[..., None] * (1.0 - 1e-12)
    n = state.sigma_inner.shape[-1]
    order = np.tile(np.arange(n), 2) * 2 + np.repeat([0, 1], n)  # roller-major, inner first
    key = np.where(near, order, np.iinfo(np.int64).max)
    k = np.argmin(key, axis=-1)
    return smax, k % n, k // n


# ----------------------------------------------------------------------------- §8 sweeps
@dataclass
class SweepResult:
    """Maximum of a periodic function found by grid + golden refinement + grid doubling.

    x : argmax [rad]; value : the maximum; err : error estimate of value; samples : the grid
    size M of the final level; step : the grid step [rad]; capped : the M cap was reached.
    """

    x: float
    value: float
    err: float
    samples: int
    step: float
    capped: bool = False


def _refine(fun, xs, ys, period, start, rtol, top=8):
    """Golden-section refinement of the local maxima of a periodic grid (vectorised)."""
    m = len(xs)
    left, right = np.roll(ys, 1), np.roll(ys, -1)
    idx = np.flatnonzero((ys >= left) & (ys >= right))
    if idx.size == 0:
        idx = np.array([int(np.argmax(ys))])
    idx = idx[np.argsort(-ys[idx])][:top]
    step = period / m
    res = minimize_golden(lambda x: -fun(x), xs[idx] - step, xs[idx] + step, rtol=rtol,
                          xtol=rtol * period)
    vals = -res.fun
    k = int(np.argmax(vals))
    x_best, v_best = float(res.x[k]), float(vals[k])
    # refinement error: how much the function moves within the golden bracket
    xe = float(res.err[k])
    around = fun(np.array([x_best - xe, x_best + xe]))
    err_ref = float(np.max(np.abs(around - v_best)))
    g = int(np.argmax(ys))
    if ys[g] > v_best:
        x_best, v_best, err_ref = float(xs[g]), float(ys[g]), 0.0
    # report the argmax in [start - period/2, start + period/2): a maximum at the start of the period
    # found slightly below it stays there instead of jumping to the end of the period
    x_best = start + float(np.mod(x_best - start + 0.5 * period, period)) - 0.5 * period
    return x_best, v_best, err_ref


def maximise_periodic(fun, start, period, samples, tol, cap=2 ** 16, refine_rtol=None):
    """Maximum of a vectorised periodic function over one period (spec §8, sweeps).

    A uniform grid of M points (including ``start`` and ``start + period/2``), golden-section
    refinement of each local maximum within its two neighbouring intervals, then M doubled; the
    error estimate is the change of the refined maximum plus the refinement error, repeated
    until it is <= tol·max (M capped at ``cap``).

    Parameters
    ----------
    fun : callable, array of x [rad] -> array of values.
    start, period : the interval [start, start + period) [rad].
    samples : the initial M (even).
    tol : relative accuracy target.
    cap : the largest M.
    refine_rtol : golden-section tolerance on x (default 0.01·tol).

    Returns
    -------
    SweepResult

    Examples
    --------
    >>> r = maximise_periodic(lambda x: np.cos(x - 1.0), 0.0, 2 * np.pi, 16, 1e-9)
    >>> abs(r.x - 1.0) < 1e-4 and abs(r.value - 1.0) <= 1e-9
    True
    """
    # maxima are smooth (quadratic) in x, so an x tolerance of 0.01 sqrt(tol) gives sigma to ~1e-4 tol;
    # the refinement error is measured, not assumed, and the tolerance is tightened if it dominates
    refine_rtol = 0.01 * math.sqrt(tol) if refine_rtol is None else refine_rtol
    m = int(samples)
    prev = None
    while True:
        xs = start + period * np.arange(m) / m
        ys = np.asarray(fun(xs), dtype=float)
        x, v, err_ref = _refine(fun, xs, ys, period, start, refine_rtol)
        if prev is not None:
            err = abs(v - prev) + err_ref
            if err <= tol * abs(v) or 2 * m > cap:
                return SweepResult(x, v, err, m, period / m, capped=err > tol * abs(v))
        if err_ref > 0.25 * tol * abs(v):
            refine_rtol *= 1e-3
        prev = v
        m *= 2
