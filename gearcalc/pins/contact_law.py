"""KHV pin gearing, level ``contact``: the pin-tooth contact laws, force against penetration (pins.md §5.4).

A compression-only line-contact law F = c max(delta, 0)^p: Hertz after ISO/TS 16281 (the roller constant of
:mod:`gearcalc.hertz`), Palmgren's line contact, or a linear spring (the stiff limit in which the contact level
approaches the ideal level, pins.md §5.7(a)).  Pure functions over floats and numpy arrays (N, mm).  Re-exported by
:mod:`gearcalc.pins.contact`, whose equilibrium evaluates them at every pair of every iteration.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import hertz

__all__ = ["PALMGREN_COEFFICIENT", "HERTZ_EXPONENT", "palmgren_line_constant", "ContactLaw", "CONTACT_LAWS",
           "register_contact_law", "contact_law"]

PALMGREN_COEFFICIENT = 3.84e-5
"""Palmgren's line contact: delta = 3.84e-5 Q^0.9 / b^0.8 (mm, N) [Harris & Kotzalas]."""
HERTZ_EXPONENT = hertz.LINE_LOAD_EXPONENT


def palmgren_line_constant(face_width):
    """Palmgren's line contact solved for the force: F = c delta^(10/9), c = b^(8/9)/3.84e-5^(10/9).

    Examples
    --------
    >>> 1.03 < palmgren_line_constant(10.0) / hertz.iso_contact_stiffness(10.0) < 1.05   # pins.md: within ~4 %
    True
    """
    return face_width ** (8.0 / 9.0) / PALMGREN_COEFFICIENT ** HERTZ_EXPONENT


@dataclass(frozen=True)
class ContactLaw:
    """A compression-only contact law F = c max(delta, 0)^p (N, mm).

    name : "hertz", "palmgren" or "linear"; constant : c; exponent : p (10/9 or 1).

    Examples
    --------
    >>> law = ContactLaw("linear", 1e5, 1.0)
    >>> law.force(np.array([-1e-3, 2e-3])).tolist()
    [0.0, 200.0]
    """

    name: str
    constant: float
    exponent: float

    def force(self, delta):
        """F(delta) [N]; 0 for delta <= 0."""
        delta = np.asarray(delta, dtype=float)
        if self.exponent == 1.0:
            return self.constant * np.maximum(delta, 0.0)
        out = np.zeros(delta.shape)
        on = delta > 0.0                      # few pairs touch: the power only where they do
        out[on] = self.constant * delta[on] ** self.exponent
        return out

    def force_on(self, delta, active):
        """F on a fixed active set: the law's smooth extension on the ``active`` pairs (a linear law goes on
        linearly below delta = 0), 0 elsewhere.  Used for one-sided derivatives at contact entry/exit."""
        if self.exponent == 1.0:
            return np.where(active, self.constant * np.asarray(delta, dtype=float), 0.0)
        return np.where(active, self.force(delta), 0.0)

    def force_stiffness(self, delta, active=None):
        """(F, dF/d delta) [N, N/mm] together: :meth:`force` and its stiffness c p delta^(p-1) (0 for delta <= 0), or
        on a fixed ``active`` set :meth:`force_on` and its derivative (the smooth extension: a linear law keeps c
        below delta = 0).  Under a power law the stiffness is p F/delta on the touching pairs (one power for both:
        the equilibrium evaluates them at every pair of every iteration).

        Examples
        --------
        >>> law = ContactLaw("hertz", 2e4, 10.0 / 9.0)
        >>> F, Fp = law.force_stiffness(np.array([-1e-3, 0.0, 2e-3]))
        >>> F.tolist()[:2], Fp.tolist()[:2], bool(np.isclose(Fp[2], 2e4 * 10.0 / 9.0 * 2e-3 ** (1.0 / 9.0), rtol=1e-15))
        ([0.0, 0.0], [0.0, 0.0], True)
        """
        delta = np.asarray(delta, dtype=float)
        if self.exponent == 1.0:
            if active is None:
                return self.constant * np.maximum(delta, 0.0), np.where(delta > 0.0, self.constant, 0.0)
            return np.where(active, self.constant * delta, 0.0), np.where(active, self.constant, 0.0)
        F, Fp = np.zeros(delta.shape), np.zeros(delta.shape)
        on = delta > 0.0 if active is None else (delta > 0.0) & active
        d = delta[on]
        f = self.constant * d ** self.exponent
        F[on] = f
        Fp[on] = self.exponent * f / d
        return F, Fp

    def deflection(self, force):
        """delta(F) [mm], the inverse of :meth:`force` for F >= 0."""
        return (np.asarray(force, dtype=float) / self.constant) ** (1.0 / self.exponent)


def _hertz(face_width, stiffness) -> ContactLaw:
    return ContactLaw("hertz", float(hertz.iso_contact_stiffness(face_width)), HERTZ_EXPONENT)


def _palmgren(face_width, stiffness) -> ContactLaw:
    return ContactLaw("palmgren", float(palmgren_line_constant(face_width)), HERTZ_EXPONENT)


def _linear(face_width, stiffness) -> ContactLaw:
    return ContactLaw("linear", float(stiffness), 1.0)


CONTACT_LAWS = {"hertz": _hertz, "palmgren": _palmgren, "linear": _linear}
"""The contact laws by name: name -> a function (face_width b [mm], stiffness k_lin [N/mm]) -> :class:`ContactLaw`.
The design key ``contact.law`` chooses among them (its choices in :mod:`gearcalc.pins.schema` are these names, and
:func:`gearcalc.pins.checks.contact_law_problem` says which constant each needs)."""


def register_contact_law(name: str, make) -> None:
    """Add a contact law by name: ``make(face_width, stiffness)`` returns its :class:`ContactLaw` (a new law is one
    function plus this call; the design key's choices are in :mod:`gearcalc.pins.schema`)."""
    CONTACT_LAWS[name] = make


def contact_law(name: str, face_width=None, stiffness=None) -> ContactLaw:
    """The law of a design by name (:data:`CONTACT_LAWS`): hertz/palmgren need the face width b [mm], linear the
    stiffness k_lin [N/mm].

    Raises
    ------
    ValueError
        For a name that is not a known law; the message lists the known ones.

    Examples
    --------
    >>> contact_law("linear", stiffness=2e5).constant
    200000.0
    >>> contact_law("hertzz", face_width=10.0)
    Traceback (most recent call last):
        ...
    ValueError: unknown contact law 'hertzz'; known: hertz, palmgren, linear
    """
    try:
        make = CONTACT_LAWS[name]
    except (KeyError, TypeError):
        raise ValueError(f"unknown contact law {name!r}; known: {', '.join(CONTACT_LAWS)}") from None
    return make(face_width, stiffness)
