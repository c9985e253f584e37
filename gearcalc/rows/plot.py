"""The ``rows`` figure: row loads at the row centres and the continuous level's load profile (rows.md §3, §8)."""
from __future__ import annotations

__all__ = ["plot"]


def plot(records, path: str) -> list:
    """Row loads (stepwise and exact, as u = w/w̄) at the row centres along the sun face, with the
    continuous level's load profile u(x) = X cosh(X(1 - x/b_a)) / sinh X; one panel per design (up to 4: the
    records drawn are returned)."""
    import numpy as np

    from ..plot import _pyplot, save
    from .geometry import row_centres
    from .sharing import continuous_profile

    plt = _pyplot()
    recs = records[:4]
    fig, axes = plt.subplots(len(recs), 1, figsize=(7.5, 3.6 * len(recs)), squeeze=False)
    for ax, rec in zip(axes[:, 0], recs):
        s = rec.result.summary
        n, bbar = s["rows"], s["cheek_ratio"]
        L = n + bbar * (n - 1)  # face length in units of b_w
        centres = np.array(row_centres(n, bbar))
        rows = rec.result.detail["rows"]
        width = 0.35 / L
        if s["stepwise_valid"] and n > 1:
            ax.bar(centres - width / 2, [r["u_stepwise"] for r in rows], width, label="stepwise (row mean)")
        ax.bar(centres + width / 2, [r["u_exact"] for r in rows], width, label="exact (row mean)")
        xi = np.linspace(0, 1, 400)
        prof = continuous_profile(xi, s["kappa"], bbar, n)
        ax.plot(xi, prof, "k-", lw=1.2, label=f"continuous profile (K = {s['K_continuous']:.3f})")
        ax.axhline(1.0, color="grey", lw=0.8, ls=":")
        ax.set_xlim(0, 1)
        ax.set_xlabel("position along the sun face from the input, x / b_a [-]")
        ax.set_ylabel("line load / mean, w / w_mean [-]")
        ax.set_title(f"{rec.name}: K = {s['K']:.4g} ({s['model']}), n = {n}, n_w = {s['planets_per_row']}")
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8)
    save(fig, path)
    return recs
