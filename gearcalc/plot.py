"""``--plot FILE.png``: figures for designs and sweeps (matplotlib, the optional ``plot`` extra).

matplotlib is imported here only, and this module only when ``--plot`` is given.  A design's figure
comes from its calculator's ``plot`` hook; a sweep's figure is drawn here for every kind: the main
result against the fastest-varying numeric axis, one curve per combination of the other axes.
"""
from __future__ import annotations

from typing import Any

# The quantity a sweep plots for each kind (and for rows with a mass table).
SWEEP_Y = {"rows": "K", "rows+mass": "relative_mass_kg_per_kNm", "zstk": "sigma_max_MPa", "pins": "efficiency"}


def _pyplot():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def plot_records(records, path: str) -> None:
    """Draw the figure of the first design's calculator for the designs of that kind."""
    from . import registry

    kind = records[0].kind
    calc = registry.get(kind)
    if calc.plot is None:
        raise ValueError(f"the {kind} calculator has no figure")
    calc.plot([r for r in records if r.kind == kind], path)


def _label(name: str) -> str:
    from .units import split_unit

    base, unit = split_unit(name)
    return f"{base} [{unit}]" if unit else base


def plot_sweep(kind: str | None, rows: list[dict[str, Any]], axes: list[str], path: str) -> None:
    """The swept result against the last numeric axis, one curve per combination of the others."""
    plt = _pyplot()
    y_key = SWEEP_Y.get(f"{kind}+mass") if kind == "rows" and "relative_mass_kg_per_kNm" in rows[0] else None
    y_key = y_key or SWEEP_Y.get(kind or "", "")
    numeric = [a for a in axes if all(isinstance(r[a], (int, float)) for r in rows)]
    x_key = numeric[-1] if numeric else axes[-1]
    others = [a for a in axes if a != x_key]
    curves: dict[tuple, list] = {}
    for r in rows:
        curves.setdefault(tuple(r[a] for a in others), []).append(r)
    fig, ax = plt.subplots(figsize=(7.5, 5))
    for key, pts in curves.items():
        xs = [p[x_key] for p in pts]
        ys = [p.get(y_key) for p in pts]
        label = ", ".join(f"{a.split('.')[-1]} = {v}" for a, v in zip(others, key)) or y_key
        ax.plot(xs, [float("nan") if y is None else y for y in ys], marker="." if len(xs) < 40 else None,
                label=label)
    ax.set_xlabel(_label(x_key.split(".")[-1]))
    ax.set_ylabel(_label(y_key))
    ax.grid(True, alpha=0.3)
    if len(curves) > 1 or others:
        ax.legend(fontsize=8)
    ax.set_title(f"gearcalc sweep: {y_key} against {x_key}")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def save(fig, path: str) -> None:
    import matplotlib.pyplot as plt

    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
