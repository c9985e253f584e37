"""KHV pin gearing, level ``contact``: the satellite tooth profiles by name (pins.md §5.2-5.3; issue 35).

The extension point of the contact level's geometry: :class:`ToothProfile` is what the contact model
(:mod:`gearcalc.pins.contact_model`) needs of a profile, :data:`PROFILES` names every profile and where its
factory lives, :func:`make_profile` builds one from a design's values (:class:`ProfileParams`).  A new profile is
one module (a class with the :class:`ToothProfile` members and a factory ``make(g, params) -> (profile, overlap)``)
plus one line in :data:`PROFILES`; the design key ``gearing.profile`` takes its choices from here.

No numpy here: ``gearcalc check`` and the schema read the names; the factory's module is imported on first use.
"""
from __future__ import annotations

import importlib
from dataclasses import dataclass
from typing import Any, Protocol, runtime_checkable

__all__ = ["ToothProfile", "ProfileParams", "ProfileEntry", "PROFILES", "profile_entry", "make_profile",
           "tooth_too_large"]


@runtime_checkable
class ToothProfile(Protocol):
    """What the contact level needs of a satellite tooth profile (pins.md §5.2-5.3).

    Attributes
    ----------
    g : the gear (:class:`gearcalc.pins.geometry.Cycloid`) the profile belongs to.
    contacts_per_pin : c, the teeth a pin can touch at once (the leading axis of every :class:`Contacts` array).
    play_free : the profile has no free play by construction (the backlash is 0 without a scan, pins.md §5.3).

    Methods
    -------
    prepare(pose, trig=None, sides=None)
        Store the profile's own data of a nominal pose (:class:`gearcalc.pins.contact_profiles.Pose`) in
        ``pose.aux`` (``trig``: cos/sin of the pins' curve parameters and of the satellite's turn, when the caller
        has them; ``sides``: only these of each pin's c contacts, indices, or None: all).
    contacts(pose, x, y, branch=None) -> Contacts
        The pin-tooth pairs at satellite-frame pin centres (x, y) (z2 or m, n): the penetration delta, the unit
        normal, the moment arm X x n, X . n and the normal's turning rate (:class:`~gearcalc.pins.contact_profiles
        .Contacts`), vectorised over every pair; ``branch``: the pieces' fixed geometry branches (a crest corner or
        a flank), or None: the profile chooses.
    switch(psi_f)
        The sign-change quantities of a change of the contact's geometry from the foot-point phases ``psi_f`` that
        :meth:`contacts` returned (called only where it returned some; None where it never does).
    summary_fields() -> dict
        The profile's own summary fields (pins.md §8: e.g. tooth_radius_mm), {} when it has none.
    """

    g: Any
    contacts_per_pin: int
    play_free: bool

    def prepare(self, pose, trig=None, sides=None) -> None:
        ...

    def contacts(self, pose, x, y, branch=None):
        ...

    def switch(self, psi_f):
        ...

    def summary_fields(self) -> dict:
        ...


@dataclass(frozen=True)
class ProfileParams:
    """A design's profile values (pins.md §7, table [gearing]): each profile reads the ones it needs.

    tooth_radius : rho_t [mm] or "full"; tooth_circle_radius : R_t [mm] or "zero_backlash" (circular teeth);
    radial_mod, equidistant_mod : Delta R_p, Delta R_b [mm] (cycloidal teeth).
    """

    tooth_radius: Any = "full"
    tooth_circle_radius: Any = "zero_backlash"
    radial_mod: float = 0.0
    equidistant_mod: float = 0.0


@dataclass(frozen=True)
class ProfileEntry:
    """Where a profile lives: ``module`` (in :mod:`gearcalc.pins`) holds ``factory(g, params) -> (profile,
    overlap)`` (``overlap``: a warning-worthy overlap of adjacent teeth); ``ideal``: the ideal level computes the
    profile when it is not modified (the paper's cycloid); else it needs the contact level."""

    module: str      # a module of gearcalc.pins, or a dotted absolute name
    factory: str
    ideal: bool = False


PROFILES = {
    "cycloidal": ProfileEntry("contact_profiles", "cycloidal_profile", ideal=True),
    "circular": ProfileEntry("contact_profiles", "circular_teeth"),
}
"""The tooth profiles by name (the choices of the design key ``gearing.profile``)."""


def profile_entry(name: str) -> ProfileEntry:
    """The registry entry of profile ``name``; ValueError listing the known names for any other.

    >>> profile_entry("circular").ideal
    False
    >>> profile_entry("involute")
    Traceback (most recent call last):
        ...
    ValueError: unknown tooth profile 'involute'; known: cycloidal, circular
    """
    try:
        return PROFILES[name]
    except (KeyError, TypeError):
        raise ValueError(f"unknown tooth profile {name!r}; known: {', '.join(PROFILES)}") from None


def make_profile(name: str, g, params: ProfileParams | None = None):
    """(profile, overlap) of profile ``name`` on gear ``g`` with the design's ``params``: the factory of its
    :data:`PROFILES` entry (which raises :class:`gearcalc.pins.contact_profiles.InadmissibleProfile` for a profile
    the contact level cannot run)."""
    entry = profile_entry(name)
    module = importlib.import_module(entry.module if "." in entry.module else f"{__package__}.{entry.module}")
    return getattr(module, entry.factory)(g, ProfileParams() if params is None else params)


# ============================================================ the circular teeth's numpy-free rule

def tooth_too_large(Rb, tooth_radius, Rp, e):
    r"""Whether a circular tooth is too large for any zero-backlash tooth circle (pins.md §5.3, §9):

    .. math:: R_b + \rho_t \ge R_p - e

    (the one rule: :func:`gearcalc.pins.contact.circular_profile`,
    :func:`gearcalc.pins.contact.zero_backlash_tooth_circle` and :func:`gearcalc.pins.checks.design_problems` call it;
    here, without numpy, for ``gearcalc check``).

    >>> tooth_too_large(2.75, 37.4, 44.227, 3.9), tooth_too_large(2.75, 37.6, 44.227, 3.9)
    (False, True)
    """
    return Rb + tooth_radius >= Rp - e
