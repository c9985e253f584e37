"""The figure of the ``pins`` calculator (pins.md §8); matplotlib is imported on use."""
from __future__ import annotations

__all__ = ["plot", "since_entry"]


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
    recomputes a design with its detail tables (the calculator's).  Returns the records drawn."""
    import numpy as np

    from ..calculator import Options
    from ..design import validate
    from ..plot import _pyplot, save

    plt = _pyplot()
    cyc = [r for r in records if r.result.model != "formula"][:6]
    if not cyc:
        recs = records[:12]
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
    runs = []
    for rec in cyc:
        d = validate(dict(rec.design), rec.source)
        runs.append((rec, compute(d, Options(model=rec.result.model, detail=True))))
    rotating = any(any((row.get("pin_speed_rpm") or 0.0) != 0.0 for row in res.detail["contacts"])
                   for _, res in runs)
    torque = any(any(row.get("crank_torque_Nm") is not None for row in res.detail["crank"]) for _, res in runs)
    panels = [("force_N", "pin force F [N]")] + ([("pin_speed_rpm", "pin speed n_pin [rpm]")] if rotating else [])
    panels += [("loss_W", "pin loss P [W]")] + ([("crank_torque_Nm", "crank torque [N·m]")] if torque else [])
    panels += [("loss_ratio", "loss ratio lambda")]
    if any("torsion" in res.detail for _, res in runs):     # contact.stiffness_curve (pins.md §5.8)
        panels += [("twist", "output torque T [N·m]"), ("te", "transmission error [arcsec]")]
    ncol = (len(panels) + 1) // 2
    fig, axes = plt.subplots(2, ncol, figsize=(5 * ncol, 7), squeeze=False)
    flat = list(axes.T.ravel()) if ncol > 1 else list(axes.ravel())
    for ax in flat[len(panels):]:                # no empty panel (fixed pins have no spin)
        fig.delaxes(ax)
    ax_of = {key: flat[i] for i, (key, _) in enumerate(panels)}
    titles = []
    for rec, res in runs:
        s = res.summary
        contacts = res.detail["contacts"]
        since = since_entry([r["phase_deg"] for r in contacts], s["mode"])
        order = np.argsort(since, kind="stable")
        rows = [contacts[i] for i in order]
        since = since[order]
        label = rec.name
        for key in ("force_N", "pin_speed_rpm", "loss_W"):
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
        titles.append(f"{label}: {s['mode']} efficiency "
                      + (f"{eff:.4f}" if eff is not None else "self-locking") + (f" ({model})" if model else ""))
    for key, ylab in panels:
        ax = ax_of[key]
        ax.set_ylabel(ylab)
        ax.set_xlabel("crank angle since entry [deg]" if key in ("force_N", "pin_speed_rpm", "loss_W")
                      else "output twist, crank held [arcmin]" if key == "twist"
                      else "crank angle theta over one period 360/z2 [deg]")
    ax_of["loss_ratio"].legend(fontsize=7)
    if "te" in ax_of:
        ax_of["te"].legend(fontsize=7)
    fig.suptitle("\n".join(titles), fontsize=8)
    save(fig, path)
    return cyc
