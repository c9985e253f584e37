"""The contact level's friction-direction choice and its error (pins.md §6, issue 37 item 6).

With the friction forces in the moment balance (pins.md §5.5) a contact's tangential force is -mu sign(slip), a
discrete choice.  Where a sliding speed passes through 0 the balance can hold no consistent direction over a short
stretch of crank angles (the contact would stick): with the direction of one side the speed has already changed
sign, with the other's not yet.  The model takes one of the two there, wherever the cutting of the cycle puts the
piece end or the state that fixes a piece's sets, and the cycle mean moves with that choice by up to the stretch's
length times the jump of lambda between the directions: a bias the quadrature's estimates cannot see (they see one
choice, refined).  :func:`friction_choice_error` bounds it from the piece ends where a friction direction flips
with both one-sided states contradicting their own slip (the cut lies inside the stretch, at no zero of either
side's slip, so another cutting can put it anywhere in the stretch).
"""
from __future__ import annotations

import numpy as np


ZERO_SLIP = 1e-9
"""A slip within ZERO_SLIP of its contact's largest |slip| over the cycle is at its zero (the located root's
resolution, 1e-12 T_p, times the slip's slope, is far below it): no direction contradicts it."""


def _contradicting(sol, friction):
    """(bad (c, R, n), slip (c, R, n)): loaded contacts whose friction force pushes along their own slip."""
    slip = friction.slip(sol.force, sol.v_t)
    loaded = sol.force > 0.0
    scale = np.max(np.where(loaded, np.abs(slip), 0.0), axis=-1, keepdims=True)
    bad = loaded & (np.sign(sol.traction) * np.sign(slip) > 0.0) & (np.abs(slip) > ZERO_SLIP * scale)
    return bad, slip


def contradiction_extent(theta, bad, slip, traction, p: int) -> float:
    r"""The crank-angle length into its own piece over which state ``p``'s friction direction is contradicted.

    One contact's values over the states sorted by theta.  The state's piece lies toward the neighbour (past any
    state at the same angle: the other piece's one-sided end) with the same friction direction.  Walking that way,
    every neighbour that contradicts its direction too adds its spacing; at the first that does not, the slip s is
    interpolated linearly to its zero (half the spacing where the slips have the same sign).  With no neighbour of
    the same direction: the spacing to the nearest other angle.

    .. math:: \ell = \sum_{\text{contradicting}} |\theta_m - \theta_q|
        + \frac{|s_q|}{|s_q| + |s_m|}\,|\theta_m - \theta_q|

    Parameters
    ----------
    theta : ndarray, shape (n,)
        Crank angles of the states, sorted [rad].
    bad : ndarray of bool, shape (n,)
        The contact's friction direction contradicts its slip.
    slip : ndarray, shape (n,)
        The slip whose sign sets the contact's friction direction [mm/s per rad/s].
    traction : ndarray, shape (n,)
        The friction force per unit normal force each state was solved with [-].
    p : int
        The state.

    Returns
    -------
    float
        Length of crank angle from state p into its piece with the direction contradicted [rad].

    Examples
    --------
    A piece end (state 1, direction +, slip +1) whose neighbour in the piece (state 0, slip -3) is consistent: the
    slip's zero lies a quarter of the way:

    >>> th, tr = np.array([0.0, 1.0, 1.0, 2.0]), np.array([1.0, 1.0, -1.0, -1.0])
    >>> bad, s = np.array([False, True, True, False]), np.array([-3.0, 1.0, -1.0, 1.0])
    >>> contradiction_extent(th, bad, s, tr, 1), contradiction_extent(th, bad, s, tr, 2)
    (0.25, 0.5)

    References
    ----------
    .. [1] docs/spec/pins.md §6 (the contact level's error: the friction direction's choice).
    """
    n = theta.size
    own = np.sign(traction[p])
    for d in (-1, 1):
        m = p + d
        while 0 <= m < n and theta[m] == theta[p]:
            m += d
        if 0 <= m < n and np.sign(traction[m]) == own:
            break
    else:
        other = np.abs(theta - theta[p])
        other = other[other > 0.0]
        return float(other.min()) if other.size else 0.0
    ext, q = 0.0, p
    while 0 <= m < n and bad[m] and np.sign(traction[m]) == own:
        ext, q, m = ext + abs(theta[m] - theta[q]), m, m + d
    if 0 <= m < n:
        s_q, s_m = abs(slip[q]), abs(slip[m])
        frac = s_q / (s_q + s_m) if slip[q] * slip[m] < 0.0 else 0.5
        ext += frac * abs(theta[m] - theta[q])
    return float(ext)


def friction_choice_error(model, cyc) -> float:
    r"""The bound of the cycle mean's error from the friction directions' discrete choice (pins.md §6).

    At a piece end where a contact's friction direction flips (its slip's located sign change) and both one-sided
    states contradict their own slip (the friction force pushes along it), the cut lies inside a stretch where no
    direction is consistent, [θ − ℓ_L, θ + ℓ_R] (:func:`contradiction_extent` into either piece), at no zero of
    either side's slip: another cutting of the cycle may put it anywhere in the stretch, and the mean moves by up to

    .. math:: E_c = \frac{1}{T_p} \sum_{\text{such ends}} |\lambda_L - \lambda_R|\, (\ell_L + \ell_R)

    (λ_L, λ_R the one-sided values at the end).  A cut at a zero of one side's slip (that state consistent) is the
    located root: no choice, nothing added.

    Parameters
    ----------
    model : ContactModel
        The cycle's model (friction in the balance: ``model.friction``; None: no choice, 0).
    cyc : ContactCycle
        The cycle solved with it.

    Returns
    -------
    float
        The bound of the error of the loss ratio's cycle mean [-].

    Examples
    --------
    Fixed pins whose sliding never changes sign within a piece have nothing to choose:

    >>> from gearcalc.pins.contact import MULTIPLIER, Cycloid, CycloidProfile, ContactModel, contact_law
    >>> from gearcalc.pins.contact_cycle import mean_loss_ratio
    >>> from gearcalc.pins.friction import PinFriction
    >>> g = Cycloid.from_curtate_ratio(21, 22, 3.9, 0.75, 1.95)
    >>> fr = PinFriction(0.1, 0.1, False)
    >>> model = ContactModel(g, CycloidProfile(g, 0.0, 0.0), contact_law("linear", stiffness=1e5), 1e4, MULTIPLIER, fr)
    >>> friction_choice_error(model, mean_loss_ratio(model, fr, tol=1e-5))
    0.0

    References
    ----------
    .. [1] docs/spec/pins.md §5.5 (friction in the balance), §6 (the contact level's error).
    """
    sol, fr = cyc.sol, model.friction
    if fr is None or sol.traction is None or sol.theta.size < 2:
        return 0.0
    bad, slip = _contradicting(sol, fr)
    th, tr = sol.theta, sol.traction
    ends = np.flatnonzero(th[1:] == th[:-1])               # one-sided pairs (n, n + 1) at a piece end
    flip = bad[..., ends] & bad[..., ends + 1] & (np.sign(tr[..., ends]) * np.sign(tr[..., ends + 1]) < 0.0)
    if not flip.any():
        return 0.0
    lam, total = cyc.lam, 0.0
    for c, r, i in zip(*np.nonzero(flip)):
        n = ends[i]
        ell = sum(contradiction_extent(th, bad[c, r], slip[c, r], tr[c, r], p) for p in (n, n + 1))
        total += abs(lam[n] - lam[n + 1]) * ell
    return total / model.g.period
