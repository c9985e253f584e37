"""How a batch of ``pins`` designs is computed: which designs run together (pins.md §6).

The formula and ideal levels run in groups, numpy over the designs of a group (the ideal level's geometries in
one vectorised solve, :func:`gearcalc.pins.columns.level_columns`); a design at the contact level, or one that
would make its group costly (:func:`gearcalc.pins.checks.computed_alone`), runs alone.  A group's numbers
equal each design's alone, bit for bit, so the split changes only the time.  No design keys: the adapter
:mod:`gearcalc.kinds.pins` passes the functions that read them.
"""
from __future__ import annotations

__all__ = ["GROUPED_LEVELS", "run_batch"]

GROUPED_LEVELS = ("formula", "ideal")
"""The levels whose designs a batch computes together."""


def run_batch(designs, level_of, alone, compute_one, compute_group) -> list:
    """Per design, in order, its result or the exception computing it raised (the batch contract).

    Parameters
    ----------
    designs : sequence
    level_of : callable
        ``level_of(design)``: the level it runs (raises for a design that cannot run).
    alone : callable
        ``alone(design, level)``: a design of a grouped level that is computed alone nevertheless.
    compute_one : callable
        ``compute_one(design)``: the result of one design (raises).
    compute_group : callable
        ``compute_group(designs, level)``: per design its result or exception, computed together.

    Returns
    -------
    results : list
        Per design, in order, its result or the exception computing it raised.

    Examples
    --------
    >>> run_batch([1, 2, 3], lambda d: "ideal" if d < 3 else "contact", lambda d, level: False,
    ...           lambda d: f"alone {d}", lambda ds, level: [f"{level} {d}" for d in ds])
    ['ideal 1', 'ideal 2', 'alone 3']

    References
    ----------
    .. [1] docs/spec/interface.md (batches: every design computed, a bad one reported and passed over).
    """
    results: list = [None] * len(designs)
    groups: dict[str, list[int]] = {level: [] for level in GROUPED_LEVELS}
    for i, d in enumerate(designs):
        try:
            level = level_of(d)
            if level in groups and not alone(d, level):
                groups[level].append(i)
                continue
            results[i] = compute_one(d)
        except Exception as exc:  # noqa: BLE001  (returned, as the contract says)
            results[i] = exc
    for level, idx in groups.items():
        if idx:
            for i, r in zip(idx, compute_group([designs[i] for i in idx], level)):
                results[i] = r
    return results
