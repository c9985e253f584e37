"""The ``zstk`` figure: the paper's Fig. 2 (sigma_iB, sigma_iH against the roller radius r_i) and a drawing of
the chain, from the records of ``gearcalc zstk --plot`` (matplotlib through :mod:`gearcalc.plot`).

References
----------
Merko M.A. et al. (see :mod:`gearcalc.zstk`), Fig. 2; docs/spec/zstk.md §6, §10.
"""
from __future__ import annotations

__all__ = ["plot_records"]

import numpy as np


def plot_records(records, path: str) -> list:
    """The paper's Fig. 2 for each design (sigma_iB and sigma_iH against the roller radius r_i), and a
    drawing of the chain (raceways, rollers, load direction, critical roller) beside it; up to 4 designs
    (the records drawn are returned)."""
    from ..plot import _pyplot, save

    plt = _pyplot()
    recs = records[:4]
    fig, axes = plt.subplots(len(recs), 2, figsize=(12, 5 * len(recs)), squeeze=False,
                             gridspec_kw={"width_ratios": [1.4, 1]})
    for (ax, ax2), rec in zip(axes, recs):
        s, rows = rec.result.summary, rec.result.detail["rollers"]
        r = np.array([row["r_mm"] for row in rows])
        order = np.argsort(r, kind="stable")
        for key, label, mark in (("sigma_B_MPa", "inner contact σ_iB", "o-"),
                                 ("sigma_H_MPa", "outer contact σ_iH", "s--")):
            ax.plot(r[order], np.array([row[key] for row in rows])[order], mark, ms=4, label=label)
        if s["allowable_stress_MPa"] <= 1.5 * s["sigma_max_MPa"]:  # else it would squash the curves
            ax.axhline(s["allowable_stress_MPa"], color="r", lw=0.8, ls=":", label="[σ_H]")
        ax.set_xlabel("roller radius r_i [mm]")
        ax.set_ylabel("Hertz stress σ [MPa]")
        env = " (envelope over load directions)" if "gamma_B_deg" in rows[0] else ""
        ax.set_title(f"{rec.name}: N = {s['N']}, scheme {s['scheme']}{env}\n"
                     f"σ_max = {s['sigma_max_MPa']:.4g} MPa, roller {s['sigma_max_roller']} ({s['sigma_max_contact']})",
                     fontsize=9)
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8)
        r_h, r_b = s["outer_raceway_radius_mm"], s["inner_raceway_radius_mm"]
        e = rec.design["geometry"]["eccentricity_mm"]
        t = np.linspace(0, 2 * np.pi, 721)
        ax2.plot(r_h * np.cos(t), r_h * np.sin(t), "k-", lw=1.2)
        ax2.plot(e + r_b * np.cos(t), r_b * np.sin(t), "k-", lw=1.2)
        th = np.radians([row["theta_deg"] for row in rows])
        for k, (ti, ri) in enumerate(zip(th, r)):
            cx, cy = (r_h - ri) * np.cos(ti), (r_h - ri) * np.sin(ti)
            crit = k == s["sigma_max_roller"]
            ax2.fill(cx + ri * np.cos(t), cy + ri * np.sin(t), color="tab:red" if crit else "tab:blue", alpha=0.35)
            f_b = rows[k].get("F_B_N")
            load = f"\n{f_b:,.0f} N" if f_b and f_b >= 1 else f"\n{f_b:.2g} N" if f_b else ""  # load F_iB
            ax2.text(cx, cy, f"{k}{load}", ha="center", va="center", fontsize=7)
        g = np.radians(s["sigma_max_load_direction_deg"])
        ax2.annotate("", xy=(e + 0.8 * r_b * np.cos(g), 0.8 * r_b * np.sin(g)), xytext=(e, 0.0),
                     arrowprops={"arrowstyle": "->", "color": "tab:red", "lw": 1.5})
        ax2.set_aspect("equal")
        ax2.set_title("chain (narrowest gap at +x): roller index and load F_iB [N]\n"
                      "arrow: the load on the inner ring; red: the critical roller", fontsize=9)
        ax2.axis("off")
    save(fig, path)
    return recs
