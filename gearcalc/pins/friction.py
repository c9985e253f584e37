r"""KHV pin gearing: the friction at the pin-tooth contacts, written once for every level.

The friction at the pin-tooth contacts, written once for every level (pins.md §4.5, §4.6, §5.5, §5.6).

Two pieces, each an extension point:

- a **friction law** (:class:`FrictionLaw`): the coefficient of a sliding contact from its sliding speed and its
  contact pressure, vectorised.  :class:`Coulomb` (a constant f) is the one the design keys give today; a speed- or
  pressure-dependent law is one class with a ``coefficient`` method plus a :func:`register_friction_law` call
  (:data:`FRICTION_LAWS`, :func:`friction_law` by name; an unknown name is a ValueError).
- the **rolling-pin rule**: a rotating bushing rolls where contact friction can drive it,

  .. math:: f R_b \ge f_c r + f_k \quad\Rightarrow\quad \mu_{eff} = \mu_{rot} = (f_c r + f_k)/R_b,

  else it slides with f (:func:`rolling_condition`, :func:`rotating_loss_coefficient`, :func:`friction_regime`).  At
  the contact level a pin touched twice rolls on the contact with the larger force (it sets the spin
  omega_pin = v_t/R_b and loses mu_rot F |v_t|) and the other contact slides at |v_t - omega_pin R_b| with f
  (:class:`PinFriction`: :meth:`~PinFriction.traction`, :meth:`~PinFriction.losses`,
  :meth:`~PinFriction.sign_components`).

The ideal level (:mod:`gearcalc.pins.ideal`, :mod:`gearcalc.pins.cycle`) integrates the loss ratio for a unit
coefficient and scales it by mu_eff: it assumes the coefficient does not vary over the cycle (a constant law:
``FrictionLaw.constant``); the contact level evaluates the law per contact.

Pure functions over floats and numpy arrays; units N, mm, rad/s, W.  Every level imports the rule from here: the
ideal level through :func:`friction_regime` and :func:`peak_coefficient`, the contact level through
:class:`PinFriction`.
"""
from __future__ import annotations

from typing import NamedTuple, Protocol, runtime_checkable

import numpy as np

__all__ = ["FrictionLaw", "Coulomb", "TableLaw", "StribeckLaw", "AtCrankSpeed", "FRICTION_LAWS",
           "register_friction_law",
           "friction_law", "rolling_condition",
           "rotating_loss_coefficient", "friction_regime", "peak_coefficient", "contact_loss_power", "PinFriction"]


# ============================================================ the law of a sliding contact

@runtime_checkable
class FrictionLaw(Protocol):
    """The friction coefficient of a sliding pin-tooth contact (the extension point of pins.md §4.5, §5.5).

    name : the law's name in :data:`FRICTION_LAWS`.
    constant : True when the coefficient depends on neither speed nor pressure (the ideal level, which scales a
    unit loss ratio by the coefficient, needs one).

    ``coefficient(speed, pressure)`` gives mu [-] at the sliding speeds [mm/s per rad/s of crank speed at the contact
    level] and contact pressures [N, the normal force; None where the caller has none], elementwise over numpy arrays
    of any shape (broadcast): a float is allowed for a constant law, and keeps the arithmetic of ``f * F * v``.
    """

    name: str
    constant: bool

    def coefficient(self, speed, pressure=None):
        """The friction coefficient mu [-] at the sliding speeds and contact pressures, elementwise."""
        ...


class Coulomb(NamedTuple):
    """Coulomb's law: mu = f whatever the speed and the pressure.

    Examples
    --------
    >>> Coulomb(0.1).coefficient(np.array([0.0, 5.0]))
    0.1
    >>> isinstance(Coulomb(0.1), FrictionLaw)
    True
    """

    f: float
    name: str = "coulomb"
    constant: bool = True

    def coefficient(self, speed, pressure=None):
        """The friction coefficient f (a float: it broadcasts against any speeds and pressures)."""
        return self.f


class TableLaw(NamedTuple):
    r"""A user table mu(v): linear interpolation in the sliding speed, held constant beyond the table's ends.

    .. math:: \mu(v) = \mu_k + (\mu_{k+1} - \mu_k)\,\frac{v - v_k}{v_{k+1} - v_k}, \qquad v_k \le v \le v_{k+1}

    speed_m_s : the table's sliding speeds v_k [m/s], strictly increasing, >= 0; mu : the coefficients mu_k [-], >= 0
    (design keys ``friction.table_speed_m_s`` and ``friction.table_mu``, pins.md §4.10).  The pressure is not used.
    Speeds are in m/s: a caller with speeds per unit crank speed scales them first.

    Examples
    --------
    >>> law = TableLaw((0.0, 1.0), (0.12, 0.06))
    >>> law.coefficient(np.array([0.5, 2.0])).tolist()
    [0.09, 0.06]
    >>> isinstance(law, FrictionLaw)
    True
    """

    speed_m_s: tuple
    mu: tuple
    name: str = "table"
    constant: bool = False

    def coefficient(self, speed, pressure=None):
        """The coefficient mu [-] at the sliding speeds [m/s] (linear interpolation, constant beyond the ends)."""
        return np.interp(np.abs(np.asarray(speed, dtype=float)), np.asarray(self.speed_m_s, dtype=float),
                         np.asarray(self.mu, dtype=float))


class StribeckLaw(NamedTuple):
    r"""The Stribeck curve of a lubricated sliding contact (static, Coulomb and viscous parts).

    .. math:: \mu(v) = \mu_c + (\mu_s - \mu_c)\,e^{-(|v|/v_s)^{\delta}} + k_v\,|v|

    mu_s : the static (breakaway) coefficient [-]; mu_c : the Coulomb (mixed-film floor) coefficient [-];
    v_s : the Stribeck speed [m/s] (> 0); delta : the shape exponent [-] (> 0; 2 is Gaussian, Armstrong-Hélouvry's
    usual value); k_v : the viscous gradient [s/m] (>= 0, the full-film rise).  The pressure is not used (a
    pressure-dependent film is a further law).  Speeds are in m/s.

    Source: B. Armstrong-Hélouvry, P. Dupont, C. Canudas de Wit, "A survey of models, analysis tools and compensation
    methods for the control of machines with friction", Automatica 30(7), 1083-1138, 1994 (the Stribeck friction
    model, their eq. (1)-(3) family); L. C. Bo, D. Pavelescu, "The friction-speed relation and its influence on the
    critical velocity of stick-slip motion", Wear 82(3), 277-289, 1982 (the exponent delta).  pins.md §4.10.

    Examples
    --------
    >>> law = StribeckLaw(0.15, 0.05, 0.1, 2.0, 0.01)
    >>> round(float(law.coefficient(0.0)), 12), round(float(law.coefficient(1.0)), 6)
    (0.15, 0.06)
    """

    mu_s: float
    mu_c: float
    v_s: float
    delta: float = 2.0
    k_v: float = 0.0
    name: str = "stribeck"
    constant: bool = False

    def coefficient(self, speed, pressure=None):
        """The coefficient mu [-] at the sliding speeds [m/s]."""
        v = np.abs(np.asarray(speed, dtype=float))
        return self.mu_c + (self.mu_s - self.mu_c) * np.exp(-(v / self.v_s) ** self.delta) + self.k_v * v


class AtCrankSpeed(NamedTuple):
    """A law in m/s read by the contact level, whose sliding speeds are per rad/s of crank speed (pins.md §4.10, §5.6).

    coefficient(speed, pressure) = law.coefficient(speed * omega_H / 1000, pressure): speed [mm/s per rad/s],
    omega_H [rad/s] the crank speed, pressure [N] the normal force (passed on).

    Examples
    --------
    >>> law = AtCrankSpeed(TableLaw((0.0, 1.0), (0.12, 0.06)), 100.0)   # 5 mm/s per rad/s at 100 rad/s: 0.5 m/s
    >>> law.coefficient(np.array([5.0])).tolist(), law.constant
    ([0.09], False)
    """

    law: FrictionLaw
    omega_H: float
    name: str = "at_crank_speed"
    constant: bool = False

    def coefficient(self, speed, pressure=None):
        """The law's coefficient at the speeds [mm/s per rad/s] times omega_H, in m/s."""
        return self.law.coefficient(np.asarray(speed, dtype=float) * (self.omega_H * 1e-3), pressure)


FRICTION_LAWS = {"coulomb": Coulomb, "table": TableLaw, "stribeck": StribeckLaw}
"""Friction laws by name: name -> a class (or function) taking the law's parameters and returning a
:class:`FrictionLaw`."""


def register_friction_law(name: str, make) -> None:
    """Add a friction law by name: ``make(**params)`` returns a :class:`FrictionLaw` (one module plus this call).

    Parameters
    ----------
    name : str
        The law's name in :data:`FRICTION_LAWS`.
    make : callable
        Its factory.

    Returns
    -------
    None

    Examples
    --------
    >>> register_friction_law("coulomb", Coulomb)   # the law already registered, registered again
    >>> friction_law("coulomb", 0.2).coefficient(3.0)
    0.2

    References
    ----------
    .. [1] docs/spec/pins.md §4.5 (the friction law by name, the extension point).
    """
    FRICTION_LAWS[name] = make


def friction_law(name: str, *args, **params) -> FrictionLaw:
    """The friction law ``name`` (:data:`FRICTION_LAWS`) with its parameters.

    Parameters
    ----------
    name : str
        The law's name.
    *args, **params
        The law's parameters (Coulomb: f, [-]).

    Returns
    -------
    law : FrictionLaw
        The law; ``law.coefficient(speed, pressure)`` gives mu, [-].

    Raises
    ------
    ValueError
        For a name that is not a known law; the message lists the known ones.

    Examples
    --------
    >>> friction_law("coulomb", 0.1).coefficient(1.0)
    0.1
    >>> friction_law("coulmb", 0.1)
    Traceback (most recent call last):
        ...
    ValueError: unknown friction law 'coulmb'; known: coulomb, table, stribeck

    References
    ----------
    .. [1] docs/spec/pins.md §4.5, §5.5.
    """
    try:
        make = FRICTION_LAWS[name]
    except (KeyError, TypeError):
        raise ValueError(f"unknown friction law {name!r}; known: {', '.join(FRICTION_LAWS)}") from None
    return make(*args, **params)


# ============================================================ the rolling-pin rule (pins.md §4.5-4.6)

def rolling_condition(sliding_friction, bushing_radius, axle_friction, axle_radius, rolling_coefficient) -> bool:
    r"""Whether contact friction can drive the bushing against its resistance.

    .. math:: f\,R_b \ge f_c\,r + f_k

    Parameters
    ----------
    sliding_friction : float or array_like
        Tooth-pin sliding friction f, [-].
    bushing_radius : float or array_like
        Bushing radius R_b, [mm].
    axle_friction : float or array_like
        Bushing-axle friction f_c, [-].
    axle_radius : float or array_like
        Axle radius r, [mm] (NaN: fixed pins, False).
    rolling_coefficient : float or array_like
        Rolling friction f_k, [mm].

    Returns
    -------
    rolls : bool or ndarray of bool
        True where the bushing turns.

    Examples
    --------
    >>> rolling_condition(0.1, 1.95, 0.1, 0.95, 0.01)
    True

    References
    ----------
    .. [1] docs/spec/pins.md §4.5 (derived).
    """
    return sliding_friction * bushing_radius >= axle_friction * axle_radius + rolling_coefficient


def rotating_loss_coefficient(axle_friction, axle_radius, rolling_coefficient, bushing_radius):
    r"""Equivalent friction coefficient of a rolling bushing [-].

    .. math:: \mu_{rot} = \frac{f_c\,r + f_k}{R_b}

    Parameters
    ----------
    axle_friction : float or array_like
        Bushing-axle friction f_c, [-].
    axle_radius : float or array_like
        Axle radius r, [mm].
    rolling_coefficient : float or array_like
        Rolling friction f_k, [mm].
    bushing_radius : float or array_like
        Bushing radius R_b, [mm].

    Returns
    -------
    mu_rot : float or ndarray
        Equivalent coefficient, [-].

    Examples
    --------
    >>> round(rotating_loss_coefficient(0.1, 0.95, 0.01, 1.95), 12)
    0.053846153846

    References
    ----------
    .. [1] A. P. Prudnikov, «Потери мощности в контакте цевок и зубьев планетарной передачи типа K-H-V» (Power losses in
       pins and teeth contact area of KHV-type planetary gearing), Машиностроение (seed file 000_fe288dec6e7c72f0.txt);
       eqs. (3)-(7) (the rolling and axle losses); docs/spec/pins.md §4.6.
    """
    return (axle_friction * axle_radius + rolling_coefficient) / bushing_radius


def friction_regime(rotating, bushing_radius, axle_radius, sliding_friction, rolling_coefficient, axle_friction,
                    xp=None):
    r"""Effective friction coefficient and whether the pins roll, per operating point (pins.md §4.5-4.6).

    .. math::

        \mu_{eff} = \begin{cases} \mu_{rot} = (f_c r + f_k)/R_b & \text{rotating and } f R_b \ge f_c r + f_k \\
        f & \text{otherwise (fixed pins, or bushings that cannot turn: they slide)} \end{cases}

    Parameters
    ----------
    rotating : bool or array_like of bool
        whether the pins carry rotating bushings.
    bushing_radius : float or array_like
        R_b [mm].
    axle_radius : float or array_like
        r [mm]; NaN (absent) for fixed pins.
    sliding_friction : float or array_like
        f, tooth-pin sliding friction [-].
    rolling_coefficient : float or array_like
        f_k [mm].
    axle_friction : float or array_like
        f_c [-].
    xp : :data:`gearcalc.pins.operating.ARRAY_OPS` or :data:`~gearcalc.pins.operating.SCALAR_OPS`; None: numpy.

    Returns
    -------
    mu_eff : float or ndarray
        [-].
    rolls : bool or ndarray of bool
        rotating pins whose rolling condition holds (false for fixed pins).

    Examples
    --------
    >>> friction_regime(np.array([True, False]), 1.95, np.array([0.95, np.nan]), 0.1, 0.01, 0.1)[0].tolist()
    [0.05384615384615384, 0.1]

    References
    ----------
    .. [1] Prudnikov (seed 000), cited in full in :mod:`gearcalc.pins`; pins.md §4.5-4.6.
    """
    where = np.where if xp is None else xp.where
    rolls = rotating & rolling_condition(sliding_friction, bushing_radius, axle_friction, axle_radius,
                                         rolling_coefficient)          # NaN r (fixed pins) compares False
    mu = where(rolls, rotating_loss_coefficient(axle_friction, axle_radius, rolling_coefficient, bushing_radius),
               sliding_friction)
    return mu, rolls


def peak_coefficient(mu_eff, rolls, sliding_friction, xp=None):
    r"""The coefficient of a pin's peak loss bound: mu_eff where the pins roll, else f [-].

    .. math:: \mu_{peak} = \mu_{eff} \ \text{(rolling pins)}, \qquad \mu_{peak} = f \ \text{otherwise}

    Parameters
    ----------
    mu_eff : float or array_like
        Effective coefficient, [-].
    rolls : bool or array_like of bool
        The pins roll.
    sliding_friction : float or array_like
        Sliding friction f, [-].
    xp : optional
        :data:`gearcalc.pins.operating.ARRAY_OPS` or :data:`~gearcalc.pins.operating.SCALAR_OPS`; None: numpy.

    Returns
    -------
    mu : float or ndarray
        The coefficient, [-].

    Examples
    --------
    >>> peak_coefficient(np.array([0.05, 0.05]), np.array([True, False]), 0.1).tolist()
    [0.05, 0.1]

    References
    ----------
    .. [1] docs/spec/pins.md §8.
    """
    return (np.where if xp is None else xp.where)(rolls, mu_eff, sliding_friction)


def contact_loss_power(force, speed, mu_eff):
    r"""Loss at one contact [W].

    .. math:: P = \mu_{eff}\,F\,v \cdot 10^{-3}

    Parameters
    ----------
    force : float or array_like
        Normal force F, [N].
    speed : float or array_like
        Sliding speed v, [mm/s].
    mu_eff : float or array_like
        Effective friction coefficient, [-].

    Returns
    -------
    P : ndarray
        Loss, [W].

    Examples
    --------
    >>> float(contact_loss_power(100.0, 1000.0, 0.1))
    10.0

    References
    ----------
    .. [1] docs/spec/pins.md §4.6.
    """
    return mu_eff * np.asarray(force) * np.asarray(speed) * 1e-3


# ============================================================ the rule at the contact level (pins.md §5.5, §5.6)

class PinFriction(NamedTuple):
    """The friction of one operating point at the contact level (pins.md §5.5, §5.6), or of many at the ideal level.

    (mu_eff, f, rolls), as the tuple it replaces (it unpacks the same); at the ideal level (:func:`friction_regime`,
    :func:`gearcalc.pins.points.ideal_points`) the fields may be arrays over the operating points.

    mu_eff : mu_rot where the pins roll, else f [-]; sliding : f [-]; rolls : the pins roll;
    law : the sliding contacts' :class:`FrictionLaw` (None: Coulomb with f, the coefficient of fixed pins mu_eff).

    Examples
    --------
    >>> pf = PinFriction(0.05, 0.1, True)
    >>> pf.traction(np.array([[[2.0]], [[1.0]]]), np.array([[[1.0]], [[3.0]]])).ravel().tolist()
    [-0.05, -0.1]
    """

    mu_eff: float
    sliding: float
    rolls: bool
    law: "FrictionLaw | None" = None

    def traction(self, force, v):
        """Tangential force per unit normal force against the sliding (c, R, n) (pins.md §5.5, §5.6).

        Fixed pins: -f sign(v_t) at every contact.  Rolling pins: -mu_rot sign(v_t) at the contact with the larger
        force (the rolling resistance), -f sign(v_t - omega_pin R_b) at the other one.
        """
        law = self.law
        if not self.rolls:
            return -(self.sliding if law is None else law.coefficient(np.abs(v), force)) * np.sign(v)
        is_lead, rel = self._lead(force, v)
        f = self.sliding if law is None else law.coefficient(np.abs(rel), force)
        return np.where(is_lead, -self.mu_eff * np.sign(v), -f * np.sign(rel))

    @property
    def varies(self) -> bool:
        """The sliding coefficient depends on the state (a law that is not constant): iterate it with the state."""
        return self.law is not None and not self.law.constant

    def along(self, directions, force, v):
        """:meth:`traction` with the directions of ``directions`` (a piece's, pins.md §5.5).

        The law's coefficients at this state's speeds and forces (c, R, n): -|mu| where ``directions`` < 0, +|mu|
        where > 0, 0 where 0.
        """
        if not self.rolls:
            mu = np.broadcast_to(self.law.coefficient(np.abs(v), force), np.shape(v))
        else:
            is_lead, rel = self._lead(force, v)
            mu = np.where(is_lead, self.mu_eff, self.law.coefficient(np.abs(rel), force))
        return np.sign(directions) * mu

    def _lead(self, force, v):
        """The rolling pin's lead contact (the larger force) and the speeds relative to it: (is_lead, v - v_lead)."""
        lead = np.argmax(force, axis=0)
        v_lead = np.take_along_axis(v, lead[None], axis=0)
        return np.arange(v.shape[0])[:, None, None] == lead[None], v - v_lead

    def slip(self, force, v):
        """The sliding speed whose sign sets each contact's friction direction in :meth:`traction` (c, R, n).

        Fixed pins: v_t; rolling pins: v_t at the lead contact, v_t - omega_pin R_b at the other one
        (pins.md §5.5; the tangential force is -mu sign(slip)).
        """
        if not self.rolls:
            return np.asarray(v)
        is_lead, rel = self._lead(force, v)
        return np.where(is_lead, v, rel)

    def losses(self, force, v, R_b: float):
        """Per-contact loss per unit crank speed, the pin spin and the sliding speeds (pins.md §5.6, §4.6).

        Fixed pins: every loaded contact slides at |v_t| with mu_eff = f.  Rolling pins: the contact with the larger
        force sets the spin omega_pin = v_t/R_b and loses mu_rot F |v_t|; another loaded contact on the same pin
        slides at |v_t - omega_pin R_b| with f.

        Returns (loss (c, R, n) [N·mm/s per rad/s], spin (R, n) [-], slide (c, R, n) [mm/s per rad/s]).
        """
        F = force
        if not self.rolls:
            slide = np.abs(v)
            mu = self.mu_eff if self.law is None else self.law.coefficient(slide, F)
            return contact_loss_power(F, slide, mu) * 1e3, np.zeros(F.shape[1:]), slide
        lead = np.argmax(F, axis=0)
        v_lead = np.take_along_axis(v, lead[None], axis=0)[0]
        loaded = (F > 0.0).any(axis=0)
        spin = np.where(loaded, v_lead / R_b, 0.0)
        is_lead = np.arange(F.shape[0])[:, None, None] == lead[None]
        slide = np.where(is_lead, 0.0, np.abs(v - v_lead[None]))
        f = self.sliding if self.law is None else self.law.coefficient(slide, F)
        loss = np.where(is_lead, self.mu_eff * F * np.abs(v), f * F * slide)
        return loss, spin, slide

    @staticmethod
    def sign_components(force, v_t, loaded):
        """The rolling-pin rule's own sign changes over two contacts per pin (pins.md §6).

        The lead's switch (F_0 - F_1 where both are loaded, else NaN) and the other contact's sliding speed
        relative to the lead (v_t - v_lead on the loaded non-lead contact, else NaN); (2 arrays, shapes (R, n)
        and (2, R, n)).
        """
        lead = (force[1] > force[0]).astype(np.intp)          # np.argmax over the two contacts (ties: the first)
        v_lead = np.where(lead == 1, v_t[1], v_t[0])[None]
        other = loaded & (np.arange(2)[:, None, None] != lead[None])
        return (np.where(loaded.all(axis=0), force[0] - force[1], np.nan),
                np.where(other, v_t - v_lead, np.nan))
