"""``--plot FILE.png``: figures for designs and sweeps (matplotlib, the optional ``plot`` extra).

matplotlib is imported here only, and this module only when ``--plot`` is given.  A design's figure
comes from its calculator's ``plot`` hook; a batch of several kinds gets every kind's figure, stacked
in one file.  A sweep's figure is drawn here for every kind: the main result against the longest
numeric axis, one curve per combination of the other axes.
"""
from __future__ import annotations

from typing import Any

DPI = 120
"""Resolution of the raster figures (PNG), and of the kinds' figures stacked into one file."""

PLOT_HINT = "--plot needs matplotlib: pip install 'gearcalc[plot]' (from a clone: pip install '.[plot]')"
"""What a --plot without matplotlib says (an installed gearcalc, and a clone of the repository)."""

NAMES_SHOWN = 5
"""How many left-out designs a --plot note names (then "and N more")."""

LEGEND_MAX = 10
"""A sweep figure with more curves than this puts its legend beside the axes (a colour bar for one numeric
legend axis) so that it hides neither the curves nor the title."""

_collected: list | None = None  # the figures of the kinds' hooks while plot_records stacks them


def _pyplot():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def plot_records(records, path: str) -> list[str]:
    """Draw every kind's figure (the calculator's ``plot`` hook) to ``path``: one kind, its figure; several
    kinds, their figures stacked top to bottom in the order the kinds first appear.  Returns the notes for
    stderr: which designs a figure left out (a kind's figure holds a few designs)."""
    from . import registry
    from .design import display_name

    global _collected
    kinds = list(dict.fromkeys(r.kind for r in records))
    figures: list[tuple[str, Any]] = []
    notes: list[str] = []
    _collected = []
    try:
        for kind in kinds:
            mine = [r for r in records if r.kind == kind]
            calc = registry.get(kind)
            if calc.plot is None:
                notes.append(f"--plot {path}: the {kind} calculator has no figure: its {len(mine)} design(s) are "
                             "not drawn")
                continue
            drawn = calc.plot(mine, path)
            drawn = mine if drawn is None else drawn
            figures += [(kind, fig) for fig in _collected]
            _collected.clear()
            left = [r for r in mine if not any(r is d for d in drawn)]
            if left:
                names = ", ".join(display_name(r.source) for r in left[:NAMES_SHOWN])
                more = f" and {len(left) - NAMES_SHOWN} more" if len(left) > NAMES_SHOWN else ""
                notes.append(f"--plot {path}: the {kind} figure shows {len(mine) - len(left)} of {len(mine)} {kind} "
                             f"designs; not drawn: {names}{more} (give them to --plot separately)")
    finally:
        leftover, _collected = _collected, None
        if leftover:
            _pyplot().close("all")
    if not figures:
        raise ValueError(f"no figure for the {', '.join(kinds)} designs")
    if len(figures) == 1:
        save(figures[0][1], path)
    else:
        save(stack(figures), path, tight=False)
    return notes


def stack(figures):
    """One figure of several (kind, figure) pairs, top to bottom, each rendered at :data:`DPI` (a raster
    image per kind: the axes' ``label`` is the kind)."""
    import numpy as np

    plt = _pyplot()
    images = []
    for kind, fig in figures:
        fig.set_dpi(DPI)
        fig.canvas.draw()
        images.append((kind, np.asarray(fig.canvas.buffer_rgba()).copy()))
        plt.close(fig)
    width = max(im.shape[1] for _, im in images)
    height = sum(im.shape[0] for _, im in images)
    out = plt.figure(figsize=(width / DPI, height / DPI), dpi=DPI)
    top = 1.0
    for kind, im in images:
        h = im.shape[0] / height
        ax = out.add_axes((0.0, top - h, im.shape[1] / width, h), label=kind)
        ax.imshow(im, interpolation="none")
        ax.set_axis_off()
        top -= h
    return out


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


def sweep_x(rows: list[dict[str, Any]], axes: list[str]) -> str:
    """The x axis of a sweep's figure: the numeric axis (not true/false) with the most values, of those with
    more than 2 (a 2-value axis reads better as two curves); the last such axis on a tie (the fastest
    varying); else the longest numeric axis; else the last axis."""
    def numeric(a: str) -> bool:
        return all(isinstance(r[a], (int, float)) and not isinstance(r[a], bool) for r in rows)

    count = {a: len(dict.fromkeys(r[a] for r in rows)) for a in axes}
    num = [a for a in axes if numeric(a)]
    pool = [a for a in num if count[a] > 2] or num or axes[-1:]
    return max(reversed(pool), key=lambda a: count[a])


def _value(v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    return f"{v:g}" if isinstance(v, float) else str(v)


def plot_sweep(kind: str | None, rows: list[dict[str, Any]], axes: list[str], path: str) -> None:
    """The swept result against :func:`sweep_x`, one curve per combination of the other axes."""
    save(sweep_figure(kind, rows, axes), path)


def _is_number(v) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool)


STYLES = ("-", "--", ":", "-.")


def sweep_figure(kind: str | None, rows: list[dict[str, Any]], axes: list[str]):
    """The figure of :func:`plot_sweep`.  Up to :data:`LEGEND_MAX` curves: a legend naming each.  More: the
    longest numeric one of the other axes is a colour (with a colour bar) and the rest, up to 4 combinations,
    a line style (a legend); else a legend beside the axes.  The title is the figure's, above everything."""
    plt = _pyplot()
    y_key = sweep_y(kind, rows[0])
    x_key = sweep_x(rows, axes)
    others = [a for a in axes if a != x_key]
    curves: dict[tuple, list] = {}
    for r in rows:
        curves.setdefault(tuple(r[a] for a in others), []).append(r)
    count = {a: len(dict.fromkeys(r[a] for r in rows)) for a in others}
    shaded = [a for a in others if all(_is_number(r[a]) for r in rows)]
    colour = max(reversed(shaded), key=lambda a: count[a]) if shaded and len(curves) > LEGEND_MAX else None
    rest = [a for a in others if a != colour]
    styles = list(dict.fromkeys(tuple(r[a] for a in rest) for r in rows))
    if colour is not None and len(styles) > len(STYLES):
        colour = None                      # too many line styles to tell apart: a legend beside the axes
    beside = colour is None and len(curves) > LEGEND_MAX
    grid2 = map_grid(rows, axes, y_key, x_key)
    if grid2 is None:
        fig, ax = plt.subplots(figsize=(10.5 if beside else 7.5, 5.2))
    else:                               # two numeric axes of >= 3 values: the curves and a contour map beside them
        fig, (ax, ax_map) = plt.subplots(1, 2, figsize=((10.5 if beside else 7.5) + 6.5, 5.2))
        _contour_map(fig, ax_map, grid2, y_key)
    if colour is not None:
        import matplotlib as mpl

        values = [r[colour] for r in rows]
        cmap, norm = mpl.colormaps["viridis"], mpl.colors.Normalize(min(values), max(values))
        ci = others.index(colour)
    numeric_x = all(_is_number(r[x_key]) for r in rows)
    for key, pts in curves.items():
        if numeric_x:
            pts = sorted(pts, key=lambda p: p[x_key])
        xs = [p[x_key] if numeric_x else _value(p[x_key]) for p in pts]
        ys = [float("nan") if p.get(y_key) is None else p.get(y_key) for p in pts]
        label = ", ".join(f"{a.split('.')[-1]} = {_value(v)}" for a, v in zip(others, key)) or y_key
        if colour is None:
            ax.plot(xs, ys, marker="." if len(xs) < 40 else None, label=label)
        else:
            style = STYLES[styles.index(tuple(v for a, v in zip(others, key) if a != colour))]
            ax.plot(xs, ys, style, color=cmap(norm(key[ci])), lw=1.2)
    ax.set_xlabel(_label(x_key.split(".")[-1]))
    ax.set_ylabel(_label(y_key))
    ax.grid(True, alpha=0.3)
    if colour is not None:
        import matplotlib as mpl

        bar = fig.colorbar(mpl.cm.ScalarMappable(norm=norm, cmap=cmap), ax=ax)
        bar.set_label(_label(colour.split(".")[-1]))
        if rest:
            from matplotlib.lines import Line2D

            ax.legend([Line2D([], [], color="k", ls=STYLES[i]) for i in range(len(styles))],
                      [", ".join(f"{a.split('.')[-1]} = {_value(v)}" for a, v in zip(rest, st)) for st in styles],
                      fontsize=8)
    elif beside:
        ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.02, 1.0), borderaxespad=0.0,
                  ncol=(len(curves) + 29) // 30)
    elif len(curves) > 1 or others:
        ax.legend(fontsize=8)
    fig.suptitle(f"gearcalc sweep: {y_key} against {x_key}", fontsize=11)
    return fig


def map_grid(rows: list[dict[str, Any]], axes: list[str], z_key: str, x_key: str):
    """The grid of a contour map of ``z_key`` (issue 37: the efficiency map), or None: exactly two axes, both
    numeric (not true/false) with at least 3 values each and every combination present.  (x_key, y_key, xs, ys,
    Z) with xs, ys the sorted values and Z[j, i] the result at (xs[i], ys[j]) (NaN: undefined)."""
    if len(axes) != 2 or x_key not in axes or not z_key:
        return None
    y_key = axes[0] if axes[1] == x_key else axes[1]
    if not all(_is_number(r[a]) for r in rows for a in axes):
        return None
    xs, ys = sorted(dict.fromkeys(r[x_key] for r in rows)), sorted(dict.fromkeys(r[y_key] for r in rows))
    if len(xs) < 3 or len(ys) < 3 or len(rows) != len(xs) * len(ys):
        return None
    z = [[float("nan")] * len(xs) for _ in ys]
    ix, iy = {v: i for i, v in enumerate(xs)}, {v: j for j, v in enumerate(ys)}
    for r in rows:
        v = r.get(z_key)
        z[iy[r[y_key]]][ix[r[x_key]]] = float("nan") if not _is_number(v) else float(v)
    return x_key, y_key, xs, ys, z


def _contour_map(fig, ax, grid2, z_key: str) -> None:
    """Filled contours of the map (:func:`map_grid`) with labelled lines and a colour bar; the grid is kept on the
    axes as ``ax.gearcalc_map`` (tests read the plotted data there)."""
    import numpy as np

    x_key, y_key, xs, ys, z = grid2
    Z = np.ma.masked_invalid(np.array(z, dtype=float))
    ax.gearcalc_map = grid2
    if Z.count() and float(Z.max()) > float(Z.min()):
        filled = ax.contourf(xs, ys, Z, levels=12, cmap="viridis")
        lines = ax.contour(xs, ys, Z, levels=filled.levels, colors="k", linewidths=0.5)
        ax.clabel(lines, fontsize=7, fmt="%.3g")
        fig.colorbar(filled, ax=ax).set_label(_label(z_key))
    else:                               # a constant (or empty) map: its value said, no contours
        ax.text(0.5, 0.5, f"{z_key} = {float(Z.max()):.4g} everywhere" if Z.count() else f"no {z_key}",
                ha="center", va="center", transform=ax.transAxes)
    ax.set_xlabel(_label(x_key.split(".")[-1]))
    ax.set_ylabel(_label(y_key.split(".")[-1]))
    ax.set_title(f"{z_key} map", fontsize=10)


def plot_accuracy(rows: list[dict[str, Any]], path: str) -> None:
    """Time per design against relative error on log axes: one panel per calculator, one curve per model level
    through its tolerances (filled: the actual error; hollow, dashed: the estimated error)."""
    save(accuracy_figure(rows), path)


def accuracy_figure(rows: list[dict[str, Any]]):
    """The figure of :func:`plot_accuracy` (from :func:`gearcalc.accuracy.summarise`'s rows)."""
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
        _log_ticks(ax.xaxis)
        ax.set_xlabel("median time per design [ms]")
        ax.set_ylabel("largest relative error over the suite [-]")
        ax.set_title(f"{kind}: error vs its high-resolution computation", fontsize=9)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
    fig.tight_layout()
    _dodge(fig, [t for ax in axes[0] for t in ax.texts])
    return fig


def _dodge(fig, labels) -> None:
    """Move each label up (by its height) until it overlaps none before it: the points of a model level at
    several tolerances may coincide."""
    renderer = fig.canvas.get_renderer()
    placed = []
    for label in labels:
        for _ in range(len(labels)):
            box = label.get_window_extent(renderer)
            if not any(box.overlaps(b) for b in placed):
                break
            x, y = label.xyann
            label.xyann = (x, y + box.height * 72.0 / fig.dpi + 1.0)
        placed.append(label.get_window_extent(renderer))


def _log_ticks(axis) -> None:
    """Plain tick labels at 1, 2, 5 per decade on a log axis (no minor labels, which overprint on a range
    of less than a decade), slanted so that neighbours never touch."""
    from matplotlib.ticker import FuncFormatter, LogLocator, NullFormatter

    axis.set_major_locator(LogLocator(base=10.0, subs=(1.0, 2.0, 5.0)))
    axis.set_major_formatter(FuncFormatter(lambda v, _: f"{v:g}"))
    axis.set_minor_formatter(NullFormatter())
    axis.set_tick_params(labelrotation=30)


def save(fig, path: str, tight: bool = True) -> None:
    """Render to memory in the format of the path's extension (png without one), then write it by the
    -o rules (gearcalc/output.py): special files written through, symlinks followed, atomic, mode kept.
    Inside :func:`plot_records` the figure is kept for it instead."""
    import io
    import os

    import matplotlib.pyplot as plt

    from .output import write

    if tight:
        fig.tight_layout()
    if _collected is not None:
        _collected.append(fig)
        return
    buffer = io.BytesIO()
    fig.savefig(buffer, dpi=DPI, format=os.path.splitext(path)[1].lower().lstrip(".") or "png")
    plt.close(fig)
    write(path, buffer.getvalue())
