"""KHV pin gearing, level ``contact``: the memory of solved crank angles a contact model's warm starts use (§5.5).

:class:`WarmStarts` is the part of :class:`~gearcalc.pins.contact_model.ContactModel` that remembers the solved
angles (tau, d tau/d theta, G_tau per angle, sorted; one memory for the frictionless solves, one with friction) and
interpolates the warm start of a new angle from them (cubic Hermite between its neighbours).  Its methods read and
write the model's parts (:mod:`gearcalc.pins.contact_parts`: ``_memo``, ``_gtau``).
"""
from __future__ import annotations

import numpy as np

from .contact_states import Solution, filled, hermite, hermite_slope

__all__ = ["WarmStarts"]


class WarmStarts:
    """The warm-start memory of a :class:`~gearcalc.pins.contact_model.ContactModel` (a part of its class)."""

    def _remember(self, key, sol: Solution) -> None:
        """The solved angles of ``sol`` into the memory ``key`` (0: frictionless solves, 1: with friction).

        Sorted by theta with tau, d tau/d theta and G_tau (NaN where unknown); an angle solved again replaces its
        older state.
        """
        old, old_g = self._memo[key], self._gtau[key]
        th, ta, dt, gt = sol.theta, sol.tau, sol.dtau, sol.g_tau
        if old is not None:
            # an angle solved again replaces its older state (one inherited from another torque, or from a solve
            # with other sets): a warm start between a new state and an old one at the next angle would carry the old
            # one's error (~1e-3 of tau after a torque pass of lambda_bar ~ 0.1)
            if th.size:
                # the old angles within 1e-12 T_p of a new one: the stretches [x - eps, x + eps] of the sorted memory
                eps = 1e-12 * self.g.period
                lo = old[0].searchsorted(th - eps, side="left")
                hi = old[0].searchsorted(th + eps, side="right")
                if (hi > lo).any():
                    cover = np.zeros(old[0].size + 1, dtype=np.int64)
                    np.add.at(cover, lo, 1)
                    np.add.at(cover, hi, -1)
                    keep = np.cumsum(cover[:-1]) == 0
                    old = tuple(o[keep] for o in old)
                    old_g = None if old_g is None else old_g[keep]
            th, ta, dt = (np.concatenate((o, v)) for o, v in zip(old, (th, ta, dt)))
            if gt is not None and old_g is None:
                old_g = filled(old[0].shape, np.nan)    # unknown there (inherited, mirrored): no Newton warm start
            gt = None if old_g is None or gt is None else np.concatenate((old_g, gt))
        order = th.argsort(kind="stable")
        self._memo[key] = (th[order], ta[order], dt[order])
        self._gtau[key] = None if gt is None else gt[order]

    def _guess(self, theta, key, slope: bool = False):
        """The rotation tau at theta from the solved angles around it.

        The cubic Hermite interpolant of tau and d tau/d theta between the two neighbours (the tangent line of
        the nearer one where they coincide or lie on one side only), or None when nothing is solved yet.
        ``slope``: (tau, d tau/d theta) of that interpolant.
        """
        memo = self._memo[key] if key == 0 or self.friction is not None else None
        if memo is None:
            return None
        th, ta, dt = memo
        if th.size == 1:
            line = ta[0] + dt[0] * (theta - th[0])
            return (line, dt[0] + 0.0 * line) if slope else line
        j = np.minimum(np.maximum(th.searchsorted(theta, side="right"), 1), th.size - 1)
        a, b = j - 1, j
        near = np.where(np.abs(theta - th[a]) <= np.abs(th[b] - theta), a, b)
        line = ta[near] + dt[near] * (theta - th[near])
        h = th[b] - th[a]
        inside = (h > 0.0) & (theta >= th[a]) & (theta <= th[b])
        with np.errstate(divide="ignore", invalid="ignore"):
            t = np.where(inside, (theta - th[a]) / h, 0.0)
            herm = hermite(t, h, ta[a], dt[a], ta[b], dt[b])
            if slope:
                d_herm = hermite_slope(t, h, ta[a], dt[a], ta[b], dt[b])
                return np.where(inside, herm, line), np.where(inside, d_herm, dt[near])
        return np.where(inside, herm, line)
