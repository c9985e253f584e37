"""Validity of a ZSTK design (spec zstk.md §3.3, §9, §11.2).

References
----------
The seed paper by Merko et al. (seed 003), cited in full in :mod:`gearcalc.zstk`; docs/spec/zstk.md.
"""
from __future__ import annotations

__all__ = ['geometry_violations', 'chain_violations', 'Validity', 'check_designs', 'geometry_problems',
           'chain_problems']

import math
from dataclasses import dataclass

import numpy as np

from .chain import Chain, auto_roller_numbers, close_chain, close_chains, fractional_roller_number  # noqa: F401
from .geometry import INTEGER_TOL, extreme_roller_radii

GEOMETRY_RULES = ("inner_positive", "inner_inside", "eccentricity_range", "eccentricity_normals", "gap_range")
"""The rules of one geometry, in the order their messages are given (spec §3.3, §11.2)."""


def geometry_violations(outer_radius, inner_radius, eccentricity, gap):
    r"""The validity rules of a raceway geometry, element-wise: ``{rule: violated}`` (bool arrays).

    .. math:: R_H > R_B > 0, \quad 0 \le e < R_H - R_B, \quad e < (R_H + R_B)/\sqrt 2, \quad 0 \le c < 2 R_B

    The rules on e and c are judged only where R_H > R_B (their messages would be meaningless
    otherwise); NaN violates every rule it enters.

    Parameters
    ----------
    outer_radius, inner_radius, eccentricity, gap : float or array_like
        R_H, R_B, e, c [mm].

    Returns
    -------
    dict of bool arrays, keys :data:`GEOMETRY_RULES` in order.

    Examples
    --------
    >>> v = geometry_violations(100.0, 50.0, np.array([6.0, 52.0]), 6.0)
    >>> [k for k, m in v.items() if m.any()], v["eccentricity_range"].tolist()
    (['eccentricity_range'], [False, True])

    References
    ----------
    Merko et al. (see the module); docs/spec/zstk.md §3.3 (validity of the chain), §11.2.
    """
    r_h, r_b, e, c = (np.asarray(x, dtype=float) for x in (outer_radius, inner_radius, eccentricity, gap))
    inside = r_h > r_b
    e_ok = (0 <= e) & (e < r_h - r_b)
    return {"inner_positive": ~(r_b > 0),
            "inner_inside": ~inside,
            "eccentricity_range": inside & ~e_ok,
            "eccentricity_normals": inside & e_ok & ~(e < (r_h + r_b) / math.sqrt(2.0)),
            "gap_range": inside & ~((0 <= c) & (c < 2 * r_b))}


def chain_violations(chain: Chain):
    r"""The rules of a corrected chain, element-wise: ``{"range": ..., rule: ...}`` (bool arrays).

    "range": N < 3, or N outside the admissible interval (N < N_max; N <= N_max for the correction
    "gap"); then the rules of :func:`geometry_violations` on the corrected geometry.

    .. math:: 3 \le N < N_{max} \ (N \le N_{max} \text{ for "gap"}), \quad R_H > R_B > 0, \quad 0 \le e < R_H - R_B,
        \quad e < \frac{R_H + R_B}{\sqrt 2}, \quad 0 \le c < 2 R_B

    Parameters
    ----------
    chain : Chain
        A closed chain (floats, or arrays over designs).

    Returns
    -------
    dict of bool arrays.

    Examples
    --------
    >>> ch = close_chains(np.array([100.0, 100.0]), 50.0, 6.0, 6.0, np.array([8, 40]))
    >>> chain_violations(ch)["range"].tolist()
    [False, True]

    References
    ----------
    docs/spec/zstk.md §3.3.
    """
    n, lim = np.asarray(chain.n), np.asarray(chain.n_limit, dtype=float)
    with np.errstate(invalid="ignore"):
        in_range = np.where(np.asarray(chain.correct) == "gap", n <= lim + INTEGER_TOL,
                            np.where(np.isfinite(lim), n < lim - INTEGER_TOL, True))
    out = {"range": (n < 3) | ~in_range}
    for rule, bad in geometry_violations(chain.outer_radius, chain.inner_radius, chain.eccentricity,
                                         chain.gap).items():
        out["corrected_" + rule] = bad
    return out


@dataclass
class Validity:
    """The validity of P designs (arrays of shape (P,)), from :func:`check_designs`.

    chain : the closed chains (meaningless where not valid); n, n_star : N and N*; valid : bool;
    stages : the rule groups ``{rule: violated}`` in order: a design's problems are the violated
    rules of its first stage that has any (the later rules assume the earlier ones hold).
    """

    chain: Chain
    n: np.ndarray
    n_star: np.ndarray
    valid: np.ndarray
    stages: tuple
    inputs: dict

    def rules(self, k: int) -> list:
        """The violated rules of design k (empty when it is valid)."""
        for stage in self.stages:
            bad = [rule for rule, mask in stage.items() if mask[k]]
            if bad:
                return bad
        return []

    def problems(self, k: int, scheme, rollers) -> list:
        """(quantity, message) of each violated rule of design k.

        Quantity one of "outer", "inner", "eccentricity", "gap", "rollers", "clearance".  ``scheme`` and
        ``rollers`` are the design's values as given (for the messages).
        """
        v = {name: (x[k] if np.ndim(x) else x) for name, x in self.inputs.items()}
        out = []
        for rule in self.rules(k):
            if rule in GEOMETRY_RULES:
                out.append(_geometry_message(rule, v["outer"], v["inner"], v["eccentricity"], v["gap"]))
            elif rule == "parity":
                parity = int(v["parity"])
                out.append(("rollers", f"= {rollers}: geometry.scheme = \"{scheme}\" needs an "
                            f"{'even' if parity == 0 else 'odd'} number of rollers (A, D even; B, C odd); "
                            "change geometry.rollers or geometry.scheme"))
            elif rule == "clearance":
                r_min = extreme_roller_radii(v["outer"], v["inner"], v["eccentricity"])[0]
                out.append(("clearance", f"= {float(v['clearance']):g}: |clearance| must be < the smallest roller "
                            f"radius (R_H − R_B − e)/2 = {float(r_min):.6g} mm (the load model assumes small "
                            "displacements)"))
            elif rule == "too_few":
                which = f" of the parity of scheme \"{scheme}\"" if v["parity"] >= 0 else ""
                out.append(("rollers", f"= \"auto\": no N ≥ 3{which} lies below N* = {float(self.n_star[k]):.6g} "
                            "(the raceways leave room for fewer than 3 rollers; reduce the gap or the "
                            "eccentricity, or give geometry.rollers explicitly)"))
            elif rule == "too_many":
                out.append(("rollers", f"= \"auto\": N = {int(self.n[k])} (N* = {float(self.n_star[k]):.6g}) "
                            f"exceeds gearcalc's range of {v['max_rollers']} rollers (the rollers are tiny "
                            "compared with the raceways; check the radii, the eccentricity and the gap)"))
            else:  # the corrected chain
                out.append(_chain_message(rule, _one(self.chain, k)))
        return out


def check_designs(outer_radius, inner_radius, eccentricity, gap, rollers, parity, clearance, correct,
                  max_rollers):
    r"""Close the chains of P designs and judge every validity rule (spec §3.3, §9), vectorised.

    The one rule set of the ``zstk`` calculator: ``compute``, ``batch``, ``sweep`` and ``check`` all
    call it.  Stages, in order: the raceway geometry and the parity of N; the clearance bound
    |s| < (R_H - R_B - e)/2; an automatic N >= 3; N <= ``max_rollers``; the corrected chain
    (:func:`chain_violations`: N in range, then the corrected geometry).

    .. math:: |s| < \frac{R_H - R_B - e}{2}, \qquad 3 \le N \le N_{max,user}, \qquad
        \text{and the rules of chain\_violations}

    Parameters
    ----------
    outer_radius, inner_radius, eccentricity, gap : array_like, shape (P,)
        Nominal R_H, R_B, e, c [mm].
    rollers : array_like of int, shape (P,)
        The given N, 0 for "auto" (the largest N <= N* of the scheme's parity).
    parity : array_like of int, shape (P,)
        N mod 2 of the scheme (0 even, 1 odd), -1 for any.
    clearance : array_like, shape (P,)
        Radial clearance s [mm].
    correct : array_like of str, shape (P,) or str
        "outer" | "inner" | "gap".
    max_rollers : int
        The largest N accepted.

    Returns
    -------
    Validity

    Examples
    --------
    >>> v = check_designs([100.0, 100.0], 50.0, [6.0, 60.0], 6.0, [0, 0], [0, 0], 0.0, "outer", 2000)
    >>> v.valid.tolist(), v.n.tolist(), v.rules(1)
    ([True, False], [8, 0], ['eccentricity_range'])

    References
    ----------
    Merko et al. (see the module); docs/spec/zstk.md §3.2-3.3, §9, §11.2.
    """
    r_h, r_b, e, c, s = np.broadcast_arrays(*(np.asarray(x, dtype=float) for x in
                                             (outer_radius, inner_radius, eccentricity, gap, clearance)))
    shape = r_h.shape
    n_given = np.broadcast_to(np.asarray(rollers, dtype=np.int64), shape)
    parity = np.broadcast_to(np.asarray(parity, dtype=np.int64), shape)
    auto = n_given == 0
    with np.errstate(divide="ignore", invalid="ignore"):
        n_star = fractional_roller_number(r_h, r_b, e, c)
        n_auto = auto_roller_numbers(np.where(np.isfinite(n_star), n_star, 0.0), parity)
    n = np.where(auto, n_auto, n_given)
    chain = close_chains(r_h, r_b, e, c, n, correct)
    first = geometry_violations(r_h, r_b, e, c)
    first["parity"] = ~auto & (parity >= 0) & (n_given % 2 != parity)
    with np.errstate(invalid="ignore"):
        stages = (first, {"clearance": ~(np.abs(s) < extreme_roller_radii(r_h, r_b, e)[0])},
                  {"too_few": auto & (n_auto < 3)}, {"too_many": n > max_rollers})
    corrected = chain_violations(chain)
    stages += ({"range": corrected.pop("range")}, corrected)
    valid = ~np.any([m for stage in stages for m in stage.values()], axis=0)
    inputs = {"outer": r_h, "inner": r_b, "eccentricity": e, "gap": c, "clearance": s, "parity": parity,
              "max_rollers": max_rollers}
    return Validity(chain, n, n_star, valid, stages, inputs)


def _one(chain: Chain, k: int) -> Chain:
    """Design k of stacked chains, with Python scalars."""
    vals = [np.asarray(getattr(chain, f)).reshape(-1)[k] if np.ndim(getattr(chain, f)) else getattr(chain, f)
            for f in Chain.__dataclass_fields__]
    return Chain(*(v.item() if hasattr(v, "item") else v for v in vals))


def _geometry_message(rule, r_h, r_b, e, c):
    r_h, r_b, e, c = float(r_h), float(r_b), float(e), float(c)
    if rule == "inner_positive":
        return "inner", f"= {r_b:g}: must be > 0"
    if rule == "inner_inside":
        return "inner", (f"= {r_b:g}: must be < outer_raceway_radius_mm = {r_h:g} "
                         "(the inner raceway lies inside the outer one)")
    if rule == "eccentricity_range":
        return "eccentricity", (f"= {e:g}: must be >= 0 and < outer_raceway_radius_mm − "
                                f"inner_raceway_radius_mm = {r_h - r_b:g} (smallest roller radius (R_H − R_B − e)/2 "
                                "would be ≤ 0)")
    if rule == "eccentricity_normals":
        return "eccentricity", (f"= {e:g}: must be < (R_H + R_B)/√2 = {(r_h + r_b) / math.sqrt(2.0):g} "
                                "(the contact normals of the widest rollers would diverge by ≥ 90°)")
    return "gap", (f"= {c:g}: must be >= 0 and < 2·inner_raceway_radius_mm = {2 * r_b:g} "
                   "(the rollers inflated by c/2 must stay outside the inner raceway)")


def _chain_message(rule, chain: Chain):
    what = {"outer": "outer_raceway_radius_mm", "inner": "inner_raceway_radius_mm",
            "gap": "roller_gap_mm"}[chain.correct]
    if rule == "range":
        lim = chain.n_limit
        if chain.correct == "gap":
            rng = f"3 ≤ N ≤ {math.floor(lim + INTEGER_TOL)}"
        else:
            rng = (f"3 ≤ N ≤ {math.ceil(lim - INTEGER_TOL) - 1} (N < N_max = {lim:.6g})"
                   if math.isfinite(lim) else "N ≥ 3")
        return "rollers", (f"= {chain.n}: must be in the admissible range {rng} for correct = "
                           f"\"{chain.correct}\" (N* = {chain.n_star:.6g}; beyond the range the corrected "
                           f"{what} = {chain.corrected:.6g} leaves no valid chain)")
    key, msg = _geometry_message(rule.removeprefix("corrected_"), chain.outer_radius, chain.inner_radius,
                                 chain.eccentricity, chain.gap)
    return "rollers", (f"= {chain.n}: the corrected geometry ({what} = {chain.corrected:.6g}) is "
                       f"invalid: {key} {msg}")


def geometry_problems(outer_radius, inner_radius, eccentricity, gap):
    r"""Violations of the validity conditions of spec §3.3 / §11.2 for one geometry.

    Returns a list of (quantity, message) with quantity in {"outer", "inner", "eccentricity",
    "gap"}; empty when R_H > R_B > 0, 0 <= e < R_H - R_B, e < S/sqrt 2 and 0 <= c < 2R_B
    (the messages of :func:`geometry_violations`).

    .. math:: R_H > R_B > 0, \quad 0 \le e < R_H - R_B, \quad e < \frac{R_H + R_B}{\sqrt 2}, \quad 0 \le c < 2 R_B

    Parameters
    ----------
    outer_radius, inner_radius, eccentricity, gap : float
        R_H, R_B, e, c, [mm].

    Returns
    -------
    problems : list of tuple
        (quantity, message), empty when every rule holds.

    Examples
    --------
    >>> geometry_problems(100.0, 50.0, 6.0, 6.0)
    []
    >>> geometry_problems(100.0, 50.0, 52.0, 6.0)[0][0]
    'eccentricity'

    References
    ----------
    .. [1] M. A. Merko, M. V. Mesnyankin, A. V. Kolotov, A. E. Mityaev, M. V. Savitskaya, A. M. Merko, S. A. Yurov,
       «Анализ нормальных напряжений на площадках контакта звеньев механизмов с ЗСТК при ведущем внутреннем кольце и
       вводе поправки по радиусу дорожки качения наружного кольца», Siberian Federal University, UDC 621.838.2 (seed
       file 003_2d1da402cb0b8488.txt; no journal or year given); docs/spec/zstk.md §3.3, §11.2.
    """
    return [_geometry_message(rule, outer_radius, inner_radius, eccentricity, gap)
            for rule, bad in geometry_violations(outer_radius, inner_radius, eccentricity, gap).items() if bad]


def chain_problems(chain: Chain):
    r"""Violations of spec §3.3 by one corrected chain: list of (quantity, message).

    Checks N >= 3, N inside the admissible interval, and the corrected geometry (the rules of
    :func:`chain_violations`; the range first: the geometry is judged only inside it).

    .. math:: 3 \le N < N_{max} \ (N \le N_{max} \text{ for "gap"}), \quad \text{then the corrected geometry's rules}

    Parameters
    ----------
    chain : Chain
        One corrected chain (floats).

    Returns
    -------
    problems : list of tuple
        (quantity, message), empty when every rule holds.

    Examples
    --------
    >>> chain_problems(close_chain(100.0, 50.0, 6.0, 6.0, 8))
    []
    >>> chain_problems(close_chain(100.0, 50.0, 6.0, 6.0, 40))[0][0]
    'rollers'

    References
    ----------
    .. [1] M. A. Merko, M. V. Mesnyankin, A. V. Kolotov, A. E. Mityaev, M. V. Savitskaya, A. M. Merko, S. A. Yurov,
       «Анализ нормальных напряжений на площадках контакта звеньев механизмов с ЗСТК при ведущем внутреннем кольце и
       вводе поправки по радиусу дорожки качения наружного кольца», Siberian Federal University, UDC 621.838.2 (seed
       file 003_2d1da402cb0b8488.txt; no journal or year given); docs/spec/zstk.md §3.3.
    """
    bad = {rule: bool(m) for rule, m in chain_violations(chain).items()}
    if bad.pop("range"):
        return [_chain_message("range", chain)]
    return [_chain_message(rule, chain) for rule, b in bad.items() if b]
