"""KHV pin gearing, level ``contact``: the geometry, moment balance and speeds of a contact model (pins.md §5.1,
§5.5, §5.6).

:class:`ContactKinematics` is the part of :class:`~gearcalc.pins.contact_model.ContactModel` that evaluates a pose:
the nominal pin positions, the contacts and penetrations (the profile's), the moment balance G(tau) and its slope,
d tau/d theta and the contact speeds, the friction forces (:class:`~gearcalc.pins.friction.PinFriction`), the states
scattered over the window's rows and the crank bearing's force.  Its methods read the model's parts
(:mod:`gearcalc.pins.contact_parts`).
"""
from __future__ import annotations

import math

import numpy as np

from .contact_parts import EPS
from .contact_profiles import Contacts, Pose
from .contact_states import Solution, contact_index, filled, sub_pose, take_states

__all__ = ["ContactKinematics"]

_CONTACT_FIELDS = ("delta", "nx", "ny", "arm", "xn", "switch", "branch", "wx", "wy")


def _with_cols(full, part, cols):
    """``full`` (..., n) with its columns ``cols`` replaced by ``part`` (a copy; None stays None)."""
    if full is None or part is None:
        return full
    out = np.array(full, dtype=np.result_type(full, part), copy=True)
    out[..., cols] = part
    return out



class ContactKinematics:
    """Geometry, moment and speeds of a :class:`~gearcalc.pins.contact_model.ContactModel` (a part of its class)."""

    # -- geometry -------------------------------------------------------------------------------
    def pose(self, theta, idx=None, sides=None) -> Pose:
        """Nominal satellite-frame pin positions at crank angles theta (tau = 0); ``idx`` (m, n): only
        these pins (default: all, shape (z2, n)); ``sides``: only these of each pin's contacts (default: all;
        :attr:`sides`)."""
        g = self.g
        theta = np.atleast_1d(np.asarray(theta, dtype=float))
        sel = self.pins if idx is None else idx
        beta0 = 2.0 * math.pi * sel / g.z2 + (g.k / g.z1) * theta[None, :]
        a = (g.z2 / g.z1) * theta[None, :]
        trig = (np.cos(beta0), np.sin(beta0), np.cos(a), np.sin(a))
        x0 = g.R_p * trig[0] - g.e * trig[2]
        y0 = g.R_p * trig[1] - g.e * trig[3]
        p = Pose(theta, x0, y0, beta0 if beta0.shape == x0.shape else np.broadcast_to(beta0, x0.shape), g.z2)
        p.aux["idx"] = sel if np.shape(sel) == x0.shape else np.broadcast_to(sel, x0.shape)
        self.profile.prepare(p, trig, sides)
        return p

    def contacts(self, pose: Pose, tau, branch=None) -> Contacts:
        """Penetrations and normals with the satellite turned by tau from nominal (tau shape (n,))."""
        c, s = np.cos(tau), np.sin(tau)
        x = c * pose.x0 + s * pose.y0
        y = -s * pose.x0 + c * pose.y0
        return self.profile.contacts(pose, x, y, branch)

    def moment(self, pose: Pose, tau, traction=None, ref=None):
        """M(tau): total moment of the contact forces about O1, counter-clockwise positive [N·mm], (n,).

        ``traction`` (c, z2, n), optional: signed tangential force per unit normal force, +q meaning a
        force q F along +(z x n) on the satellite; its moment is q F (C . n), C = X + R_b n.
        ``ref`` = (active, branch), optional: evaluate on a fixed active set and contact branch (the
        smooth extension of one piece of the cycle, for one-sided derivatives at its ends).
        """
        if ref is None:
            ct = self.contacts(pose, tau)
            F = self.law.force(ct.delta)
        else:
            ct = self.contacts(pose, tau, ref[1])
            F = self.law.force_on(ct.delta, ref[0])
        if traction is None:
            return (F * ct.arm).sum(axis=(0, 1))
        return (F * (ct.arm + traction * (ct.xn + self.g.R_b))).sum(axis=(0, 1))

    def _balance(self, pose: Pose, tau, traction=None, ref=None):
        r"""G = M - M_req and its analytic derivative G_tau, with the contact data (pins.md §5.5).

        With the moment arm A = X x n + q (X.n + R_b) of a pair, dn = (w . dX)(z x n) and
        dX/dtau = (y, -x):

        .. math::

            G_\tau = \sum -F'(\delta)\,(X\times n)\,A + F\,(1 + w\cdot X_\tau)(X\cdot n - q\,X\times n)

        Returns (G, G_tau, ct, F, Fp, A, q, x, y, G_geo), G_geo the part of G_tau at fixed deflections."""
        c, s = np.cos(tau), np.sin(tau)
        x = c * pose.x0 + s * pose.y0
        y = -s * pose.x0 + c * pose.y0
        if ref is None:
            ct = self.profile.contacts(pose, x, y)
            F, Fp = self.law.force_stiffness(ct.delta)
        else:
            ct = self.profile.contacts(pose, x, y, ref[1])
            F, Fp = self.law.force_stiffness(ct.delta, ref[0])
        q = 0.0 if traction is None else traction
        A = ct.arm if traction is None else ct.arm + q * (ct.xn + self.g.R_b)
        G, G_tau, G_geo = self._moment_slope(ct, F, Fp, A, q, x, y)
        return G, G_tau, ct, F, Fp, A, q, x, y, G_geo

    def _moment_slope(self, ct: Contacts, F, Fp, A, q, x, y):
        """(G, G_tau, G_geo) of :meth:`_balance` from the contact data; G_geo: the part of G_tau from the turning
        geometry at fixed deflections, sum F (1 + w.X_tau)(X.n - q X x n)."""
        G = (F * A).sum(axis=(0, 1)) - self.M_req
        one = 1.0 + (ct.wx * y - ct.wy * x)
        G_geo = (F * one * (ct.xn - q * ct.arm)).sum(axis=(0, 1))
        return G, (-Fp * ct.arm * A).sum(axis=(0, 1)) + G_geo, G_geo

    def _sliding_at(self, pose: Pose, tau, dtau):
        """The contacts' forces and sliding speeds v_t at the rotations ``tau`` with the turning rate d tau/d theta
        ``dtau`` given (a warm start's interpolant, :meth:`_guess`), without an equilibrium: the first friction
        directions of :meth:`_friction_fixed_point` (:meth:`traction` reads ``force`` and ``v_t``), as
        :meth:`_kinematics` gives them but for its own d tau/d theta (v_t = O1'.n + (d tau/d theta - k/z1)(C.n),
        pins.md §5.6).  Returns a :class:`Solution` holding tau, d tau/d theta, the forces and v_t."""
        g = self.g
        ct = self.contacts(pose, tau)
        ang = (g.z2 / g.z1) * pose.theta - tau
        v_t = self._tangential_speed(np.cos(ang), np.sin(ang), ct, dtau)
        return Solution(pose.theta, tau, dtau, None, ct.delta, self.law.force(ct.delta), v_t, None, None)

    def _tangential_speed(self, ca, sa, ct: Contacts, dtau):
        """The sliding speed v_t of every contact per unit crank speed [mm/rad] (pins.md §5.6): with omega_H = 1,
        v = z x O1' + w1 z x (C - O1) and v_t = v.(z x n) = O1'.n + w1 (C.n), O1' = e u(theta - phi), C = X + R_b n
        in the satellite axes and w1 = d tau/d theta - k/z1; ``ca``, ``sa``: cos and sin of z2 theta/z1 - tau."""
        g = self.g
        return g.e * (ca * ct.nx + sa * ct.ny) + (-(g.k / g.z1) + dtau) * (ct.xn + g.R_b)

    def _full(self, sol: Solution, idx, sides=None) -> Solution:
        """The solution over the rows of :meth:`layout`: the candidates' values scattered, the others untouched by
        contact (a state at crank angles outside [0, T_p] whose candidates the layout does not hold: over the union
        of both); solved on some contacts of each pin only (``sides``, :attr:`sides`): over all of them, the others
        out of reach like the pins out of the window (their normals and turning rates over the candidates 0: they
        carry no force)."""
        if idx is None:
            return sol
        rows, pos = self.layout()
        if rows is not None and (pos[idx] < 0).any():
            rows = np.union1d(rows, idx)
            pos = np.full(self.g.z2, -1)
            pos[rows] = np.arange(rows.size)
        n = sol.theta.size
        R = self.g.z2 if rows is None else rows.size
        at, cols = pos[idx], np.arange(n)[None, :]

        C, cs = self.profile.contacts_per_pin, contact_index(self.profile, sides)

        # the places of the states' (c, m, n) entries in the rows' (C, R, n), flat: one index for every field
        flat = ((cs * R + at[None]) * n + cols[None]).ravel()

        def scatter(a, fill):
            if a is None:
                return None
            lead = a.shape[:-3]
            out = filled(lead + (C * R * n,), fill, a.dtype)
            out[..., flat] = a.reshape(lead + (-1,))
            return out.reshape(lead + (C, R, n))

        def every(a):
            # the geometry over the candidates (c, m, n): the contacts left out get 0 (no force, no moment)
            if a is None or sides is None:
                return a
            out = np.zeros(a.shape[:-3] + (C,) + a.shape[-2:], dtype=a.dtype)
            out[..., sides, :, :] = a
            return out

        cand = np.zeros((R, n), dtype=bool)
        cand[at, cols] = True
        return Solution(sol.theta, sol.tau, sol.dtau, sol.residual, scatter(sol.delta, -np.inf),
                        scatter(sol.force, 0.0), scatter(sol.v_t, 0.0), None, None,
                        scatter(sol.switch, np.nan), scatter(sol.branch, -1), cand, scatter(sol.ddelta, 0.0),
                        sol.noise, sol.g_tau, every(sol.nx), every(sol.ny), every(sol.wx), every(sol.wy), sol.pins,
                        rows, scatter(sol.traction, 0.0))

    def reference(self, theta):
        """(active, branch, traction) of the solved state at theta: the fixed sets of the pieces with these
        midpoints (traction: the friction forces' directions with friction in the balance, else None)."""
        sol = self.state(theta, phases=False)
        return sol.force > 0.0, sol.branch, None if self.friction is None else self.traction(sol)

    def traction(self, sol: Solution):
        """Tangential force per unit normal force against the sliding (pins.md §5.5, §5.6).

        Fixed pins: -f sign(v_t) at every contact.  Rolling pins: -mu_rot sign(v_t) at the contact with
        the larger force (the rolling resistance), -f sign(v_t - omega_pin R_b) at the other one: the rule of
        :meth:`gearcalc.pins.friction.PinFriction.traction`.
        """
        return self.friction.traction(sol.force, sol.v_t)

    def _kinematics(self, pose: Pose, tau, traction, ref=None, step: bool = False):
        r"""Forces, d tau/d theta and the contact speeds at the solved tau (pins.md §5.6).

        d tau/d theta = -G_theta/G_tau, both analytic (on the piece's active set and branches ``ref``);
        at fixed tau, dX/dtheta = -Rot(-phi) O1' + (k/z1)(-y, x), so with V = dX/dtheta

        .. math::

            G_\theta = \sum F'(\delta)(n\cdot V) A + F\left[V\times n + (w\cdot V)(X\cdot n)
                       + q\,(n\cdot V - (w\cdot V)(X\times n))\right]

        ``step``: ``tau`` is a warm start; where its Newton step s = -G/G_tau is one that :meth:`_solve` would take
        and stop after (G_tau < 0, |s| <= 1e-8 |tau|) and the arms' turn moves the moment by |G_geo s| <= 1e-11
        |M_req| at most, the state is moved by it: tau + s, delta - (X x n) s (exact to O((R_p + e) s^2) ~ 1e-22 mm,
        d delta/d tau = -(X x n)), the forces and slopes anew from those deflections, the residual with the arms'
        turn G_geo s added; the geometry (normals, arms, positions) stays at ``tau`` (its change, (R_p + e) s ~ 1e-10
        mm, is far below the deflections' resolution).  Returns (Solution, need): ``need`` marks the angles whose
        warm start was farther (they need :meth:`_solve`).
        """
        g = self.g
        th = pose.theta
        G, G_tau, ct, F, Fp, A, q, x, y, G_geo = self._balance(pose, tau, traction)
        need = None
        if step:
            with np.errstate(divide="ignore", invalid="ignore"):
                s = -G / G_tau
                small = self.settings.refine_newton_small if self._refining else self.settings.newton_small
                take = ((G_tau < 0.0) & np.isfinite(s) & (np.abs(s) <= small * np.abs(tau))
                        & (np.abs(G_geo * s) <= 1e-3 * small * abs(self.M_req)))
            need = ~take
            if take.any():
                s = np.where(take, s, 0.0)
                tau = tau + s
                ct.delta = ct.delta - ct.arm * s
                F, Fp = self.law.force_stiffness(ct.delta)
                G, G_tau, _ = self._moment_slope(ct, F, Fp, A, q, x, y)
                G = G + G_geo * s       # the moment at tau + s to first order in s: the arms' turn added
        G_tau0 = G_tau
        cr, F_r, Fp_r, A_r = ct, F, Fp, A
        if ref is not None:
            # the piece's sets differ from the solution's own only at some angles (a piece end, a contact at
            # delta = 0): the one-sided derivatives are evaluated there alone, the others are the same
            other = (ref[0] != (F > 0.0)).any(axis=(0, 1))
            if ref[1] is not None:
                other |= (ref[1] != ct.branch).any(axis=(0, 1))
            if other.any():
                cols = np.flatnonzero(other)
                sub_ref = (ref[0][..., cols], None if ref[1] is None else ref[1][..., cols])
                sub_q = traction[..., cols] if isinstance(traction, np.ndarray) else traction
                _, gt, cs, fs, fps, As, _, _, _, _ = self._balance(sub_pose(pose, cols), tau[cols], sub_q, sub_ref)
                G_tau = G_tau.copy()
                G_tau[cols] = gt
                cr = Contacts(*(_with_cols(getattr(ct, k), getattr(cs, k), cols) for k in _CONTACT_FIELDS))
                F_r, Fp_r, A_r = (_with_cols(a, b, cols) for a, b in ((F, fs), (Fp, fps), (A, As)))
        kz = g.k / g.z1
        ang = (g.z2 / g.z1) * th - tau
        ca, sa = np.cos(ang), np.sin(ang)
        vx = g.e * sa - kz * y
        vy = -g.e * ca + kz * x
        dd = cr.nx * vx + cr.ny * vy
        om = cr.wx * vx + cr.wy * vy
        d_arm = vx * cr.ny - vy * cr.nx + om * cr.xn
        d_xn = dd - om * cr.arm
        G_th = (Fp_r * dd * A_r + F_r * (d_arm + q * d_xn)).sum(axis=(0, 1))
        dtau = -G_th / G_tau
        v_t = self._tangential_speed(ca, sa, ct, dtau)
        ddelta = (dd if cr is ct else ct.nx * vx + ct.ny * vy) - ct.arm * dtau
        noise = EPS * (g.R_p + g.e) * np.abs(Fp * ct.arm).sum(axis=(0, 1))
        switch = ct.switch if ct.psi_f is None else self.profile.switch(ct.psi_f)
        # the friction forces solved with, per contact (a copy: the caller's array stays its own)
        solved_q = None if traction is None else np.array(np.broadcast_to(traction, F.shape), dtype=float)
        sol = Solution(th, tau, dtau, G, ct.delta, F, v_t, None, None, switch, ct.branch, None, ddelta, noise,
                       G_tau0, ct.nx, ct.ny, ct.wx, ct.wy, pose.aux["idx"], traction=solved_q)
        return (sol, need) if step else sol

    def _picker(self, theta, rows=None):
        """(idx, pick): the candidate pins (m, n) at crank angles theta (all pins when there is no window) and the
        candidates' columns of an array over the pins ``rows`` (a state's :attr:`Solution.rows`; None: all z2),
        (c, R, n) -> (c, m, n) (scalars and None unchanged)."""
        idx = self.candidates(theta)
        if idx is None:
            idx = np.broadcast_to(self.pins, (self.g.z2, np.size(theta)))
        cols = np.arange(np.size(theta))[None, :]
        at = idx
        if rows is not None:
            at = np.minimum(np.maximum(rows.searchsorted(idx), 0), rows.size - 1)
            if not np.array_equal(rows[at], idx):
                raise ValueError("the state's rows do not hold every candidate pin")

        def pick(a):
            return a if a is None or np.ndim(a) == 0 else a[:, at, cols]

        return idx, pick

    def solved_contacts(self, sol: Solution):
        """The contacts of a solved state (theta, tau, branches) over the candidate pins, and ``pick``: the
        candidates' columns of an array over its rows (c, R, n) -> (c, m, n) (scalars and None unchanged)."""
        idx, pick = self._picker(sol.theta, sol.rows)
        return self.contacts(self.pose(sol.theta, idx), sol.tau, pick(sol.branch)), pick

    def kept_contacts(self, sol: Solution):
        """:meth:`solved_contacts` from the normals the solution kept (:class:`Solution`: nx, ny, wx, wy over its
        ``pins``) when they are over this model's candidate pins at every angle; else evaluated anew.

        At a piece end (a crank angle held twice, one-sided) they are evaluated anew all the same: where a
        cycloidal pin passes to a crest corner its foot point on the design curve jumps there, and the kept one
        may be the other side's (the profile's corner, whose curvature radius is 0); anew, from the nominal foot
        point, with the state's branch."""
        if sol.pins is None or sol.nx is None:
            return self.solved_contacts(sol)
        theta = sol.theta
        idx, pick = self._picker(theta, sol.rows)
        if sol.pins.shape != idx.shape or not np.array_equal(sol.pins, idx):
            return self.solved_contacts(sol)
        nx, ny, wx, wy = sol.nx, sol.ny, sol.wx, sol.wy
        twice = np.concatenate(([False], theta[1:] == theta[:-1]))
        ends = np.flatnonzero(twice | np.concatenate((twice[1:], [False])))
        if ends.size:
            anew = self.solved_contacts(take_states(sol, ends))[0]
            nx, ny, wx, wy = (_with_cols(a, getattr(anew, k), ends) for a, k in ((nx, "nx"), (ny, "ny"),
                                                                                   (wx, "wx"), (wy, "wy")))
        ct = Contacts(pick(sol.delta), nx, ny, None, None, wx=wx, wy=wy)
        ct.branch = pick(sol.branch)
        return ct, pick

    def bearing_force(self, sol: Solution, traction=None, ct=None, pick=None):
        """Force B of the crank bearing on the satellite (crank-frame axes turned by phi) [N], (2, n).

        Satellite equilibrium: B = -sum (F n + q F (z x n)) (the coupling gives a pure torque); ``ct``, ``pick``: the
        state's :meth:`solved_contacts`, when known."""
        if ct is None:
            ct, pick = self.solved_contacts(sol)
        F, q = pick(sol.force), 0.0 if traction is None else pick(traction)
        return -(F * (ct.nx - q * ct.ny)).sum(axis=(0, 1)), -(F * (ct.ny + q * ct.nx)).sum(axis=(0, 1))
