"""KHV pin gearing, level ``contact``: the solved contact states and the helpers that take, put, merge and re-lay them
(pins.md §5.5, §5.6, §6).

:class:`Solution` is the state of the satellite at given crank angles, per contact and pin; the functions here take
states at some angles (:func:`take_states`), write them back (:func:`put_states`), concatenate them sorted by angle
(:func:`concat_states`, :func:`sorted_places`, :func:`merged`), and re-lay their per-pin arrays over other pins
(:func:`relayout`, :func:`over_rows`); and the small numerics both the equilibrium
(:mod:`gearcalc.pins.contact_model`) and the cycle (:mod:`gearcalc.pins.contact_cycle`) use (:func:`filled`,
:func:`distance_to`, :func:`hermite`, :func:`hermite_slope`, :func:`sub_pose`).  Pure functions over numpy arrays.
"""
from __future__ import annotations

import dataclasses
import functools
from dataclasses import dataclass

import numpy as np

from .contact_profiles import Pose

__all__ = ["Solution", "GEOMETRY_FIELDS", "PIN_FIELDS", "PIN_FILL", "filled", "sub_pose", "distance_to", "hermite",
           "hermite_slope", "take_states", "put_states", "sorted_places", "merged", "concat_states", "same_rows",
           "relayout", "over_rows", "contact_index"]


@dataclass
class Solution:
    """The solved contact state at crank angles theta (n,), per contact (c, z2, n).

    tau: transmission error phi - phi_nom [rad]; dtau: d tau/d theta [-]; residual: M - M_req [N·mm];
    delta [mm], force [N], v_t: tangential speed of the satellite at the contact per unit crank
    speed [mm/s per rad/s] (positive along z x n); phase: load-side phase of each pin [rad] (z2, n);
    zeta: pin phase measured along time, theta - phi_j wrapped to (-pi, pi] [rad] (z2, n);
    cand: (z2, n) the pins evaluated at each angle (the candidate window), None: all; the others cannot
    touch (delta = -inf, F = 0, v_t = 0 there);
    ddelta: (c, z2, n) d delta/d theta along the solution, n.dX/dtheta - (X x n) d tau/d theta [mm/rad]
    (the Newton slope of the contact entries and exits, :func:`cycle_breakpoints`);
    noise: (n,) the round-off floor of the residual [N·mm]: eps (R_p + e) sum |F'(delta) X x n|, the moment
    change of a round-off of the pin positions at every contact (the penetrations are differences of
    lengths ~R_p);
    g_tau: (n,) dG/dtau of the moment balance at the solution [N·mm/rad] (the warm start of another torque,
    :meth:`ContactModel.inherit`);
    nx, ny, wx, wy: (c, m, n) the contacts' normals and their turning rates (:class:`Contacts`) over the pins
    ``pins`` (m, n) the state was solved on (the candidate window, or all pins), at the solved rotation (within a
    last Newton step of it): kept for the crank bearing (:func:`crank_bearing`), None where not known;
    rows: (R,) the pins (sorted) that the per-pin arrays (delta, force, v_t, phase, zeta, switch, branch, cand,
    ddelta) hold, in that order: the pins the candidate window can hold over the period
    (:meth:`ContactModel.layout`); every other pin cannot touch anywhere on the cycle (R of z2 rows: the arrays
    of a u = 30 paper design are 6x smaller).  None: all z2 pins, in order;
    traction: (c, R, n) the friction forces per unit normal force the state was solved with (:meth:`ContactModel.
    traction` of the directions it settled on, or its piece's fixed ones), over the rows (0 where a pin is out of
    reach); None without friction in the balance.  At a piece end, or where no direction is consistent (the
    directions flip back and forth, :meth:`ContactModel._friction_fixed_point`), they can differ from the
    directions of the state's own sliding speeds: the crank bearing takes these (:func:`crank_bearing`).
    """

    theta: np.ndarray
    tau: np.ndarray
    dtau: np.ndarray
    residual: np.ndarray
    delta: np.ndarray
    force: np.ndarray
    v_t: np.ndarray
    phase: np.ndarray
    zeta: np.ndarray
    switch: np.ndarray | None = None
    branch: np.ndarray | None = None
    cand: np.ndarray | None = None
    ddelta: np.ndarray | None = None
    noise: np.ndarray | None = None
    g_tau: np.ndarray | None = None
    nx: np.ndarray | None = None
    ny: np.ndarray | None = None
    wx: np.ndarray | None = None
    wy: np.ndarray | None = None
    pins: np.ndarray | None = None
    rows: np.ndarray | None = None
    traction: np.ndarray | None = None

    def over_pins(self, z2: int) -> "Solution":
        """This state over all ``z2`` pins in order, to index its per-pin arrays by pin number: the rows scattered,
        every other pin out of reach (no contact; phases None where not held: :meth:`ContactModel.phases`)."""
        return relayout(self, None, z2)


GEOMETRY_FIELDS = ("nx", "ny", "wx", "wy", "pins")
"""The :class:`Solution` fields over the pins it was solved on (m, not its rows): never scattered to its rows."""

PIN_FIELDS = ("delta", "force", "v_t", "phase", "zeta", "switch", "branch", "cand", "ddelta", "traction")
"""The :class:`Solution` fields over its ``rows`` (the pin axis second to last), with the values of a pin that is not
a candidate (out of reach: no contact)."""

PIN_FILL = {"delta": -np.inf, "force": 0.0, "v_t": 0.0, "switch": np.nan, "branch": -1, "cand": False, "ddelta": 0.0,
             "traction": 0.0}


def filled(shape, value, dtype=float):
    """np.full without its Python wrapper (the scatters of every solve call it): an empty array filled in place."""
    out = np.empty(shape, dtype)
    out.fill(value)
    return out


def sub_pose(pose: Pose, sel) -> Pose:
    """The pose at the crank angles ``sel`` (a boolean mask or indices over the last axis)."""
    return Pose(pose.theta[sel], pose.x0[:, sel], pose.y0[:, sel], pose.beta0[:, sel], pose.z2,
                {k: v[..., sel] for k, v in pose.aux.items()}, None if pose._psi is None else pose._psi[:, sel])


def distance_to(points, x):
    """The distance from each of ``x`` to the nearest of ``points`` (sorted, not empty).

    >>> distance_to(np.array([0.0, 1.0]), np.array([-1.0, 0.25, 0.5, 3.0])).tolist()
    [1.0, 0.25, 0.5, 2.0]
    """
    k = np.minimum(np.maximum(points.searchsorted(x), 1), points.size)
    return np.minimum(np.abs(x - points[k - 1]), np.abs(x - points[np.minimum(k, points.size - 1)]))


def hermite(t, h, fa, da, fb, db):
    """The cubic Hermite interpolant at t = (x - x_a)/h in [0, 1] of values f and slopes d at x_a and x_a + h."""
    t2, t3 = t * t, t * t * t
    return ((2 * t3 - 3 * t2 + 1) * fa + (t3 - 2 * t2 + t) * h * da + (-2 * t3 + 3 * t2) * fb + (t3 - t2) * h * db)


def hermite_slope(t, h, fa, da, fb, db):
    """The derivative d/dx of :func:`hermite` at t = (x - x_a)/h.

    >>> bool(abs(hermite_slope(0.3, 2.0, 1.0, -0.5, 4.0, 2.0)
    ...          - (hermite(0.3 + 1e-7, 2.0, 1.0, -0.5, 4.0, 2.0) - hermite(0.3 - 1e-7, 2.0, 1.0, -0.5, 4.0, 2.0))
    ...          / 4e-7) < 1e-8)
    True
    """
    t2 = t * t
    return (6.0 * t2 - 6.0 * t) * (fa - fb) / h + (3.0 * t2 - 4.0 * t + 1.0) * da + (3.0 * t2 - 2.0 * t) * db


def take_states(sol: Solution, sel) -> Solution:
    """The states of ``sol`` at the crank angles ``sel`` (an index or slice over the last axis)."""
    n = sol.theta.size
    return Solution(**{f.name: (v[..., sel] if isinstance(v, np.ndarray) and v.shape[-1:] == (n,) and f.name != "rows"
                                else v)
                       for f in dataclasses.fields(sol) for v in (getattr(sol, f.name),)})


def put_states(sol: Solution, part: Solution, sel) -> None:
    """The states of ``part`` written into ``sol`` at the crank angles ``sel`` (in place; theta is not written)."""
    n = sol.theta.size
    for f in dataclasses.fields(sol):
        a = getattr(sol, f.name)
        if isinstance(a, np.ndarray) and a.shape[-1:] == (n,) and f.name not in ("theta", "pins", "rows"):
            a[..., sel] = getattr(part, f.name)


def sorted_places(thetas: list) -> list:
    """Where the crank angles of each part land when all are sorted together (stable: ties keep the parts' order); one
    part already sorted (the quadrature's nodes solved in one call): all of it in place (a slice)."""
    if len(thetas) == 1 and not (thetas[0][1:] < thetas[0][:-1]).any():
        return [slice(None)]
    theta = np.concatenate(thetas)
    place = np.empty(theta.size, dtype=np.int64)
    place[theta.argsort(kind="stable")] = np.arange(theta.size)
    bounds = np.cumsum([0] + [t.size for t in thetas])
    return [place[a:b] for a, b in zip(bounds[:-1], bounds[1:])]


def merged(arrays: list, places: list, axis: int):
    """The arrays written at their ``places`` (:func:`sorted_places`) along ``axis``, the last one: the sorted
    concatenation in one pass."""
    a0 = arrays[0]
    shape = list(a0.shape)
    shape[axis] = sum(a.shape[axis] for a in arrays)
    out = np.empty(shape, dtype=np.result_type(*arrays))
    lead = (slice(None),) * axis
    for a, p in zip(arrays, places):
        out[lead + (p,)] = a
    return out


def concat_states(parts: list[Solution]) -> Solution:
    """The states of ``parts`` together, sorted by theta (stable), over their rows (over the union of them where the
    parts' rows differ, :func:`relayout`)."""
    rows = parts[0].rows
    if not all(same_rows(p.rows, rows) for p in parts):
        full = [p for p in parts if p.rows is None]
        rows = None if full else functools.reduce(np.union1d, [p.rows for p in parts])
        z2 = full[0].force.shape[-2] if full else None
        parts = [relayout(p, rows, z2) for p in parts]
    places = sorted_places([p.theta for p in parts])
    theta = merged([p.theta for p in parts], places, 0)

    def cat(name, axis):
        if any(getattr(p, name) is None for p in parts):
            return None
        return merged([getattr(p, name) for p in parts], places, axis)

    geometry = [None] * len(GEOMETRY_FIELDS)
    if all(p.pins is not None for p in parts) and len({p.pins.shape[0] for p in parts}) == 1:
        geometry = [cat(name, getattr(parts[0], name).ndim - 1) for name in GEOMETRY_FIELDS]

    return Solution(theta, cat("tau", 0), cat("dtau", 0), cat("residual", 0), cat("delta", 2),
                    cat("force", 2), cat("v_t", 2), cat("phase", 1), cat("zeta", 1),
                    None if parts[0].switch is None else cat("switch", 3),
                    None if parts[0].branch is None else cat("branch", 2),
                    None if any(p.cand is None for p in parts) else cat("cand", 1), cat("ddelta", 2),
                    cat("noise", 0), cat("g_tau", 0), *geometry, rows,
                    None if parts[0].traction is None else cat("traction", 2))


def same_rows(a, b) -> bool:
    """Whether two :attr:`Solution.rows` are the same pins."""
    return (a is None and b is None) or (a is not None and b is not None and np.array_equal(a, b))


def relayout(sol: Solution, rows, z2: int | None = None) -> Solution:
    """``sol`` over the pins ``rows`` (sorted; None: all ``z2``): each per-pin array's rows of these pins, a pin that
    ``sol`` does not hold with the values of a pin out of reach (no contact; :data:`PIN_FILL`; phases then None, to
    be computed, :meth:`ContactModel.phases`)."""
    if same_rows(sol.rows, rows):
        return sol
    n_src = sol.force.shape[-2]
    src = np.arange(n_src) if sol.rows is None else sol.rows
    dst = np.arange(z2) if rows is None else rows
    held = np.isin(dst, src).all()
    out = {}
    for name in PIN_FIELDS:
        a = getattr(sol, name)
        if name == "cand" and a is None and not held:
            a = np.ones((n_src, sol.theta.size), dtype=bool)
        if a is None or (name in ("phase", "zeta") and not held):
            out[name] = None
        else:
            out[name] = over_rows(a, src, dst, PIN_FILL.get(name))
    return dataclasses.replace(sol, rows=rows, **out)


def over_rows(a, src, dst, fill):
    """``a`` (..., len(src), n) over the pins ``src`` (sorted) as (..., len(dst), n) over the pins ``dst`` (sorted): a
    pin that ``a`` does not hold gets ``fill``."""
    at = np.minimum(np.maximum(src.searchsorted(dst), 0), src.size - 1)
    have = src[at] == dst
    if have.all():
        return a[..., at, :]
    b = filled(a.shape[:-2] + (dst.size, a.shape[-1]), fill, a.dtype)
    b[..., have, :] = a[..., at[have], :]
    return b


def contact_index(profile, sides):
    """The contacts of each pin that a state holds, as an index (c, 1, 1) over the profile's c per pin (all of them
    when ``sides`` is None; :attr:`ContactModel.sides`)."""
    return (np.arange(profile.contacts_per_pin) if sides is None else np.asarray(sides))[:, None, None]
