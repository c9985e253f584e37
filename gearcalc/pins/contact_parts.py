"""KHV pin gearing, level ``contact``: the parts of a contact model, kept apart (issue 35 item 1).

A :class:`~gearcalc.pins.contact_model.ContactModel` is made of three objects:

- :class:`ContactSetup`, immutable: the gear, tooth profile, contact law, torque per satellite, mode, friction and
  numerical settings it was made with (and what follows from them: M_req, the pin indices);
- :class:`SolverState`, what its solves change: the candidate window, the located sign changes, the warm starts, the
  last pose, the densest scan a cycle needed, the refinement flag;
- :class:`ContactCaches`, what the models of one design share (the models of later torques and of the other mode
  inherit it): the nominal scans.

:class:`ModelParts` gives the model its former attribute names as properties over these parts (read-only for the
set-up).  The equilibrium's exceptions (:class:`NoEquilibrium`, :class:`Jam`) are here too: every part of the
model raises them.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .contact_settings import DEFAULT_SETTINGS, ContactSettings
from .friction import PinFriction
from .geometry import REDUCER

__all__ = ["EPS", "NoEquilibrium", "Jam", "ContactSetup", "SolverState", "ContactCaches", "ModelParts"]

EPS = float(np.finfo(float).eps)


class NoEquilibrium(ValueError):
    """No satellite rotation within +-pi/z1 balances the torque at some crank angle."""

    def __init__(self, theta):
        super().__init__("no contact can carry the torque")
        self.theta = theta


class Jam(NoEquilibrium):
    """With the friction forces in the moment balance, no positive contact force balances the torque at
    some crank angle although the frictionless balance has a solution: the mode jams (self-locks) there
    (pins.md §4.9, §5.5)."""


@dataclass(frozen=True, eq=False)
class ContactSetup:
    """The immutable set-up of a contact model (pins.md §5.1, §5.5).

    g : the pin gear; profile : a :class:`gearcalc.pins.profiles.ToothProfile`; law : the contact law;
    torque_sat : T_sat [N·mm]; sigma : +1 reducer, -1 multiplier; friction : :class:`~gearcalc.pins.friction.
    PinFriction` in the moment balance, or None; settings : :class:`~gearcalc.pins.contact_settings.ContactSettings`.
    M_req : the required moment, -T_sat (reducer) or +T_sat (multiplier); pins : (z2, 1) the pin indices.
    """

    g: object
    profile: object
    law: object
    torque_sat: float
    sigma: int
    friction: PinFriction | None = None
    settings: ContactSettings = DEFAULT_SETTINGS
    M_req: float = field(init=False)
    pins: np.ndarray = field(init=False, repr=False)

    def __post_init__(self):
        torque = float(self.torque_sat)
        object.__setattr__(self, "torque_sat", torque)
        object.__setattr__(self, "M_req", -torque if self.sigma == REDUCER else torque)
        object.__setattr__(self, "pins", np.arange(self.g.z2)[:, None])
        if self.friction is not None and not isinstance(self.friction, PinFriction):
            object.__setattr__(self, "friction", PinFriction(*self.friction))


@dataclass(eq=False)
class SolverState:
    """What a contact model's solves change (none of it changes a result, only where the solves start and which pins
    they evaluate).

    window : (z_lo, z_hi, m, tau_bound): candidate pins by time phase, or None: all; sides : (window, sides): the
    contacts of each pin the window's states evaluate while that window is the model's; clearance : (theta, tau,
    clearance, (candidates, sides)) of the last final grid's check; last_pose : the pose of the last state (its foot
    points start the next torque's); memo : solved (theta, tau, dtau) for warm starts, 0 frictionless, 1 final;
    gtau : dG/dtau at the memo's angles (None: unknown); roots : the located sign changes of its last cycle;
    layout : (window, rows, pos) of the window's rows; scan_n : the densest full scan a cycle of this design
    needed; refining : its solves refine a breakpoint (tighter Newton stops); mirrored : it started from the other
    mode's solution.
    """

    window: tuple | None = None
    sides: tuple | None = None
    clearance: tuple | None = None
    last_pose: object = None
    memo: dict = field(default_factory=lambda: {0: None, 1: None})
    gtau: dict = field(default_factory=lambda: {0: None, 1: None})
    roots: object = None
    layout: tuple | None = None
    scan_n: int = 0
    refining: bool = False
    mirrored: bool = False


@dataclass(eq=False)
class ContactCaches:
    """What the contact models of one design share (a later torque's and the other mode's models inherit it):
    nominal : n_scan -> the nominal scan's (psi, delta, arm) (:meth:`~gearcalc.pins.contact_model.ContactModel.
    set_window`)."""

    nominal: dict = field(default_factory=dict)


def _setup(name: str):
    return property(lambda self: getattr(self.setup, name), doc=f"The set-up's ``{name}`` (read-only).")


def _state(name: str):
    return property(lambda self: getattr(self.solver, name), lambda self, v: setattr(self.solver, name, v),
                    doc=f"The solver state's ``{name}``.")


class ModelParts:
    """A contact model's parts (``setup``, ``solver``, ``caches``) under the model's attribute names."""

    setup: ContactSetup
    solver: SolverState
    caches: ContactCaches

    g, profile, law, torque_sat, sigma = (_setup(n) for n in ("g", "profile", "law", "torque_sat", "sigma"))
    friction, settings, M_req, pins = (_setup(n) for n in ("friction", "settings", "M_req", "pins"))
    window, clearance, last_pose, roots, scan_n = (_state(n) for n in ("window", "clearance", "last_pose", "roots",
                                                                        "scan_n"))
    _sides, _memo, _gtau, _layout = (_state(n) for n in ("sides", "memo", "gtau", "layout"))
    _refining, _mirrored = _state("refining"), _state("mirrored")

    @property
    def _nominal_cache(self) -> dict:
        return self.caches.nominal
