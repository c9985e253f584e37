"""``--plot FILE.png``: figures for designs and sweeps (matplotlib, the optional ``plot`` extra).

matplotlib is imported here only, and this module only when ``--plot`` is given.  A design's figure
comes from its calculator's ``plot`` hook; a sweep's figure is drawn here for every kind: the main
result against the fastest-varying numeric axis, one curve per combination of the other axes.
"""
from __future__ import annotations

from typing import Any



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


def sweep_y(kind: str | None, row: dict[str, Any]) -> str:
    """The field a sweep's figure plots: the first of the calculator's ``sweep_plot`` fields the sweep has."""
    from . import registry

    if kind not in registry.kinds():
        return ""
    wanted = registry.get(kind).sweep_plot
    return next((f for f in wanted if row.get(f) is not None), wanted[-1] if wanted else "")


def plot_sweep(kind: str | None, rows: list[dict[str, Any]], axes: list[str], path: str) -> None:
    """The swept result against the last numeric axis, one curve per combination of the others."""
    plt = _pyplot()
    y_key = sweep_y(kind, rows[0])
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
    save(fig, path)


def plot_accuracy(rows: list[dict[str, Any]], path: str) -> None:
    """Time per design against relative error on log axes: one panel per calculator, one curve per model level
    through its tolerances (filled: the actual error; hollow, dashed: the estimated error)."""
    plt = _pyplot()
    kinds = list(dict.fromkeys(r["kind"] for r in rows))
    fig, axes = plt.subplots(1, len(kinds), figsize=(6 * len(kinds), 4.8), squeeze=False)
    floor = 1e-17  # an error of exactly 0 is drawn here (log axes)
    for ax, kind in zip(axes[0], kinds):
        levels = list(dict.fromkeys(r["level"] for r in rows if r["kind"] == kind))
        for k, level in enumerate(levels):
            pts = [r for r in rows if r["kind"] == kind and r["level"] == level and r["error_max"] is not None]
            if not pts:
                continue
            t = [r["time_ms_median"] for r in pts]
            color = f"C{k}"
            ax.plot(t, [max(r["error_max"], floor) for r in pts], "o-", color=color, label=f"{level}: error")
            ax.plot(t, [max(r["error_est_max"], floor) for r in pts], "o--", mfc="none", color=color,
                    label=f"{level}: estimated")
            for r, x in zip(pts, t):
                ax.annotate(f"tol {r['tol']:g}", (x, max(r["error_max"], floor)), fontsize=6,
                            xytext=(3, 3), textcoords="offset points")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("median time per design [ms]")
        ax.set_ylabel("largest relative error over the suite [-]")
        ax.set_title(f"{kind}: error vs its high-resolution computation", fontsize=9)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
    save(fig, path)


def save(fig, path: str) -> None:
    """Render to memory in the format of the path's extension (png without one), then write it by the
    -o rules (gearcalc/output.py): special files written through, symlinks followed, atomic, mode kept."""
    import io
    import os

    import matplotlib.pyplot as plt

    from .output import write

    fig.tight_layout()
    buffer = io.BytesIO()
    fig.savefig(buffer, dpi=120, format=os.path.splitext(path)[1].lower().lstrip(".") or "png")
    plt.close(fig)
    write(path, buffer.getvalue())
