"""The figure of the ``pins`` calculator (pins.md §8); matplotlib is imported on use."""
from __future__ import annotations

__all__ = ["plot", "since_entry"]

ENGAGEMENT_KEYS = ("force_N", "pin_speed_rpm", "loss_W")
"""The panels drawn against the crank angle since the pin's entry (one engagement)."""


def since_entry(phase_deg, mode: str):
    """The crank angle since the pin entered its loaded arc [deg], from the load-side phases of the loaded
    contacts of the detail table: the phases are taken in (-180, 180] (the contact level reports a pin
    loaded just before phase 0, by its compliance, as a phase just below 360), and the pin enters at the
    smallest loaded phase (multiplier) or at the largest (reducer: the pin runs through its arc backwards).
    At the ideal level the loaded arc is [0, psi*]: the angle is phase (multiplier) or psi* - phase."""
    import numpy as np

    phase = np.asarray(phase_deg, dtype=float)
    phase = 180.0 - np.mod(180.0 - phase, 360.0)       # (-180, 180]
    if phase.size == 0:
        return phase
    return phase - phase.min() if mode == "multiplier" else phase.max() - phase


def plot(records, path: str, compute) -> list:
    """The pins figure (pins.md §8): force, pin speed (rotating pins only) and loss of one pin against crank
    angle over one engagement, the crank torque (the driving torque of a reducer, the paper's Figs 3-7) and
    lambda(theta) over one period; one curve per design (up to 6), the efficiencies in the title; with
    contact.stiffness_curve also the hysteresis loop (output torque against twist, crank held) and the transmission
    error over one period, unloaded and at T_rated (pins.md §5.8).
    Formula-level designs get a bar chart of P_tr1 and P_tr2 instead (up to 12).  ``compute(design, options)``
    recomputes a design with its detail tables (the calculator's).  Returns the records drawn.

    The steps: :func:`_formula_bars` (formula level only), else :func:`_recomputed`, :func:`_panels`,
    :func:`_figure`, :func:`_draw_run` per design and :func:`_label_axes`.
    """
    from ..plot import _pyplot, save

    plt = _pyplot()
    cyc = [r for r in records if r.result.model != "formula"][:6]
    if not cyc:
        return _formula_bars(plt, records[:12], path)
    runs = _recomputed(cyc, compute)
    panels = _panels(runs)
    fig, ax_of = _figure(plt, panels)
    titles = [_draw_run(ax_of, rec, res) for rec, res in runs]
    _label_axes(ax_of, panels)
    fig.suptitle("\n".join(titles), fontsize=8)
    save(fig, path)
    return cyc


def _formula_bars(plt, recs, path: str) -> list:
    """The bar chart of P_tr1 and P_tr2 of formula-level records ``recs`` (paper eqs 5, 6), saved to ``path``."""
    import numpy as np

    from ..plot import save

    fig, ax = plt.subplots(figsize=(7.5, 4))
    x = np.arange(len(recs))
    p1 = [r.result.summary["P_tr1_W"] for r in recs]
    p2 = [r.result.summary["P_tr2_W"] for r in recs]
    ax.bar(x, p1, label="P_tr1 (rolling, eq. 5)")
    ax.bar(x, p2, bottom=p1, label="P_tr2 (axle, eq. 6)")
    ax.set_xticks(x, [r.name for r in recs], rotation=20, ha="right", fontsize=7)
    ax.set_ylabel("maximum loss per pin [W]")
    ax.legend()
    save(fig, path)
    return recs


def _recomputed(cyc, compute) -> list:
    """(record, Result with detail tables) of each cycle-level record, recomputed at its own level."""
    from ..calculator import Options
    from ..design import validate

    runs = []
    for rec in cyc:
        d = validate(dict(rec.design), rec.source)
        runs.append((rec, compute(d, Options(model=rec.result.model, detail=True))))
    return runs


def _panels(runs) -> list:
    """(key, y label) of the panels the runs fill: no pin-speed panel for fixed pins, no crank-torque panel without
    one, the torsion panels only with contact.stiffness_curve (pins.md §5.8)."""
    rotating = any(any((row.get("pin_speed_rpm") or 0.0) != 0.0 for row in res.detail["contacts"])
                   for _, res in runs)
    torque = any(any(row.get("crank_torque_Nm") is not None for row in res.detail["crank"]) for _, res in runs)
    panels = [("force_N", "pin force F [N]")] + ([("pin_speed_rpm", "pin speed n_pin [rpm]")] if rotating else [])
    panels += [("loss_W", "pin loss P [W]")] + ([("crank_torque_Nm", "crank torque [N·m]")] if torque else [])
    panels += [("loss_ratio", "loss ratio lambda")]
    if any("torsion" in res.detail for _, res in runs):     # contact.stiffness_curve (pins.md §5.8)
        panels += [("twist", "output torque T [N·m]"), ("te", "transmission error [arcsec]")]
    return panels


def _figure(plt, panels):
    """(figure, axes by panel key): two rows of panels, column by column, no empty panel."""
    ncol = (len(panels) + 1) // 2
    fig, axes = plt.subplots(2, ncol, figsize=(5 * ncol, 7), squeeze=False)
    flat = list(axes.T.ravel()) if ncol > 1 else list(axes.ravel())
    for ax in flat[len(panels):]:                # no empty panel (fixed pins have no spin)
        fig.delaxes(ax)
    return fig, {key: flat[i] for i, (key, _) in enumerate(panels)}


def _draw_run(ax_of, rec, res) -> str:
    """Draw one design's curves on the panels ``ax_of``; its title line (mode, efficiency, friction model)."""
    import numpy as np

    s = res.summary
    contacts = res.detail["contacts"]
    since = since_entry([r["phase_deg"] for r in contacts], s["mode"])
    order = np.argsort(since, kind="stable")
    rows = [contacts[i] for i in order]
    since = since[order]
    label = rec.name
    for key in ENGAGEMENT_KEYS:
        y = [r[key] for r in rows]
        if key in ax_of and all(v is not None for v in y):
            ax_of[key].plot(since, y, label=label)
    crank = res.detail["crank"]
    th = [r["theta_deg"] for r in crank]
    ax_of["loss_ratio"].plot(th, [r["loss_ratio"] for r in crank], label=label)
    if "crank_torque_Nm" in ax_of and crank and crank[0].get("crank_torque_Nm") is not None:
        ax_of["crank_torque_Nm"].plot(th, [r["crank_torque_Nm"] for r in crank], label=label)
    if "torsion" in res.detail:       # the loop in the table's order: +T up and down, then -T
        loop = res.detail["torsion"]
        ax_of["twist"].plot([r["twist_arcmin"] for r in loop], [r["torque_Nm"] for r in loop], ".-", label=label)
        te = res.detail["transmission_error"]
        line = ax_of["te"].plot([r["crank_deg"] for r in te], [r["te_unloaded_arcsec"] for r in te], "--",
                                label=f"{label}, no load")
        ax_of["te"].plot([r["crank_deg"] for r in te], [r["te_rated_arcsec"] for r in te],
                         color=line[0].get_color(), label=f"{label}, T_rated")
    eff = s["efficiency"]
    model = s.get("friction_model") or ""
    return (f"{label}: {s['mode']} efficiency " + (f"{eff:.4f}" if eff is not None else "self-locking")
            + (f" ({model})" if model else ""))


def _label_axes(ax_of, panels) -> None:
    """The axis labels of every panel and the legends of the loss-ratio and transmission-error panels."""
    for key, ylab in panels:
        ax = ax_of[key]
        ax.set_ylabel(ylab)
        ax.set_xlabel("crank angle since entry [deg]" if key in ENGAGEMENT_KEYS
                      else "output twist, crank held [arcmin]" if key == "twist"
                      else "crank angle theta over one period 360/z2 [deg]")
    ax_of["loss_ratio"].legend(fontsize=7)
    if "te" in ax_of:
        ax_of["te"].legend(fontsize=7)
