"""Dimensions of the multi-row planetary gear and the rules they must satisfy.

Dimensions of the multi-row planetary gear and the rules they must satisfy (rows.md §1 "Notation", §2.3, §2.4, §5.4, §7,
§10).

Pure functions over floats and numpy arrays alike, written with arithmetic operators only: this module
imports no numpy, so ``gearcalc check`` (which derives the face widths) stays light.  The one
trigonometric function and the guarded division dispatch on the type: the math module for a Python
number (the result stays a Python float), numpy for an array; the two agree bit for bit on the range of
pressure angles (tests/test_rows_geometry.py).  Units mm, rad.

References
----------
.. [1] The seed paper 004, cited in full in :mod:`gearcalc.rows`; docs/spec/rows.md (the
   section numbers "rows.md §x" refer to it).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

__all__ = ["MESH_STIFFNESS_PER_E", "ROOT_DEPTH_MODULES", "RIM_MIN_MODULES", "PAPER_MAX_RELATIVE_WIDTH",
           "DEFAULT_SECTION_PER_RIM", "Face",
           "pitch_diameter", "root_diameter", "rim_width", "rim_width_from_cheek", "relative_width",
           "cheek_ratio_of", "base_radius", "face_geometry", "ratio_from_planet_teeth", "planet_teeth",
           "torsion_diameter", "shear_modulus", "mesh_stiffness", "rim_under_roots", "rims_fit", "bore_fits",
           "rim_too_thin", "planets_collide", "row_centres"]

MESH_STIFFNESS_PER_E = 0.075
"""C = 0.075 E, the mesh stiffness per unit face width [paper, citing its ref. 1] (rows.md §2.2)."""
ROOT_DEPTH_MODULES = 2.5
"""d_f = d_a - 2.5 m, the sun root diameter (rows.md §1 "Notation")."""
RIM_MIN_MODULES = 2.7
"""The rim under the tooth roots should be at least 1.2 tooth depths, 2.7 m [ISO 6336-3] (rows.md §10)."""
PAPER_MAX_RELATIVE_WIDTH = 10.0
"""B above this is far outside the paper's range (rows.md §10, "B huge")."""
DEFAULT_SECTION_PER_RIM = 0.5
"""Axle diameter d and bridge thickness h default to 0.5 b_w, the paper's table (rows.md §5.6, §7)."""


def _is_number(x) -> bool:
    return isinstance(x, (int, float))


def _cos(x):
    if _is_number(x):
        return math.cos(x)
    import numpy as np

    return np.cos(x)


def _sin(x):
    if _is_number(x):
        return math.sin(x)
    import numpy as np

    return np.sin(x)


def pitch_diameter(sun_teeth, module):
    """Sun pitch diameter ``d_a = z_a m`` [mm] (rows.md §1 "Notation").

    Parameters
    ----------
    sun_teeth : z_a [-]
    module : m [mm]

    Examples
    --------
    >>> pitch_diameter(18, 5.0)
    90.0

    References
    ----------
    .. [1] Seed paper 004_971077b94d8d4426.txt (multi-row planetary gears; title, authors and journal not
       recoverable); gearcalc specification docs/spec/rows.md §1 Notation.
    """
    return sun_teeth * module


def root_diameter(pitch_diameter, module):
    """Sun root diameter ``d_f = d_a - 2.5 m`` [mm] (rows.md §1 "Notation", §2.4).

    Examples
    --------
    >>> root_diameter(90.0, 5.0)
    77.5

    References
    ----------
    .. [1] Seed paper 004_971077b94d8d4426.txt (multi-row planetary gears; title, authors and journal not
       recoverable); gearcalc specification docs/spec/rows.md §1 Notation, §2.4.
    """
    return pitch_diameter - ROOT_DEPTH_MODULES * module


def rim_width(relative_width, rows, cheek_ratio, sun_diameter):
    """Planet rim (row) width from the relative sun face width.

    ``b_w = B d_a / (n + b̄ (n - 1))``  (rows.md §7; b_a = n b_w + (n-1) b, B = b_a/d_a)

    Parameters
    ----------
    relative_width : B [-]
    rows : n [-]
    cheek_ratio : b̄ = b/b_w [-]
    sun_diameter : d_a [mm]

    Returns
    -------
    b_w [mm]

    Examples
    --------
    >>> rim_width(2.4, 3, 0.25, 90.0)
    61.714285714285715

    References
    ----------
    .. [1] Seed paper 004_971077b94d8d4426.txt (multi-row planetary gears; title, authors and journal not
       recoverable), its B = b_a/d_a; gearcalc specification docs/spec/rows.md §1, §7.
    """
    return relative_width * sun_diameter / (rows + cheek_ratio * (rows - 1))


def rim_width_from_cheek(relative_width, rows, cheek, sun_diameter):
    """Rim width from the relative face width and a cheek thickness in mm (rows.md §7).

    ``b_a = n b_w + (n-1) b = B d_a``  so  ``b_w = (B d_a - (n-1) b) / n``; b_w <= 0 means the cheeks
    leave no room for the rims (:func:`rims_fit`).

    Parameters
    ----------
    relative_width : B [-]; rows : n [-]; cheek : b [mm]; sun_diameter : d_a [mm]

    Returns
    -------
    b_w [mm]

    Examples
    --------
    >>> rim_width_from_cheek(2.4, 3, 15.0, 90.0)   # (216 - 30) / 3
    62.0

    References
    ----------
    .. [1] Seed paper 004_971077b94d8d4426.txt (multi-row planetary gears; title, authors and journal not
       recoverable), its B = b_a/d_a; gearcalc specification docs/spec/rows.md §7.
    """
    return (relative_width * sun_diameter - (rows - 1) * cheek) / rows


def relative_width(rim_width, rows, cheek_ratio, sun_diameter):
    """Relative sun face width ``B = b_a / d_a = (n b_w + (n-1) b̄ b_w) / d_a`` [-] (rows.md §1, §7).

    Examples
    --------
    >>> relative_width(60.0, 3, 0.25, 90.0)   # (180 + 30) / 90
    2.3333333333333335

    References
    ----------
    .. [1] Seed paper 004_971077b94d8d4426.txt (multi-row planetary gears; title, authors and journal not
       recoverable), its B = b_a/d_a; gearcalc specification docs/spec/rows.md §1, §2.2.
    """
    return (rows * rim_width + (rows - 1) * cheek_ratio * rim_width) / sun_diameter


_rim_width = rim_width  # the names are taken by arguments of face_geometry
_relative_width = relative_width


def cheek_ratio_of(cheek, rim_width):
    """Cheek ratio ``b̄ = b / b_w`` [-], infinite where b_w <= 0 (no room for the rims; rows.md §7).

    Examples
    --------
    >>> cheek_ratio_of(15.0, 60.0), cheek_ratio_of(15.0, 0.0)
    (0.25, inf)

    References
    ----------
    .. [1] Seed paper 004_971077b94d8d4426.txt (multi-row planetary gears; title, authors and journal not
       recoverable); gearcalc specification docs/spec/rows.md §7.
    """
    if _is_number(rim_width):
        return cheek / rim_width if rim_width > 0 else math.inf
    import numpy as np

    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(rim_width > 0, cheek / rim_width, np.inf)


def base_radius(sun_diameter, pressure_angle):
    """Sun base radius ``r_ba = 0.5 d_a cos α_w`` [mm] (rows.md §1 "Notation").

    Parameters
    ----------
    sun_diameter : d_a [mm]
    pressure_angle : α_w [rad]

    Examples
    --------
    >>> round(base_radius(90.0, math.radians(20.0)), 6)
    42.286168

    References
    ----------
    .. [1] Seed paper 004_971077b94d8d4426.txt (multi-row planetary gears; title, authors and journal not
       recoverable); gearcalc specification docs/spec/rows.md §1 Notation.
    """
    return 0.5 * sun_diameter * _cos(pressure_angle)


@dataclass(frozen=True)
class Face:
    """The derived dimensions of one design or of a batch (every field a float or an array) [mm, -]."""

    sun_diameter: object
    """d_a [mm]"""
    root_diameter: object
    """d_f [mm]"""
    rim_width: object
    """b_w [mm]"""
    cheek_ratio: object
    """b̄ = b / b_w [-] (infinite where the rims have no room)"""
    cheek: object
    """b = b̄ b_w [mm]"""
    relative_width: object
    """B = b_a / d_a [-]"""
    base_radius: object
    """r_ba [mm]"""


def face_geometry(sun_teeth, module, rows, pressure_angle, relative_width=None, rim_width=None, cheek_ratio=0.25,
                  cheek=None):
    """The face of the sun from whichever widths were given: B or b_w, and b̄ or b (rows.md §7).

    ``d_a = z_a m``, ``d_f = d_a - 2.5 m``, ``r_ba = 0.5 d_a cos α_w``; with b_w given
    ``B = (n b_w + (n-1) b̄ b_w)/d_a`` (b̄ = b/b_w when b is given); with B given
    ``b_w = B d_a/(n + b̄(n-1))``, or ``b_w = (B d_a - (n-1) b)/n`` and ``b̄ = b/b_w`` when b is given;
    always ``b = b̄ b_w``.

    Parameters
    ----------
    sun_teeth : z_a [-]; module : m [mm]; rows : n [-]; pressure_angle : α_w [rad]
    relative_width : B [-], or None when rim_width is given
    rim_width : b_w [mm], or None
    cheek_ratio : b̄ [-], used unless cheek is given
    cheek : b [mm], or None

    Returns
    -------
    :class:`Face`

    Examples
    --------
    >>> f = face_geometry(18, 5.0, 3, math.radians(20.0), relative_width=2.4)
    >>> f.rim_width, f.cheek, f.root_diameter
    (61.714285714285715, 15.428571428571429, 77.5)

    References
    ----------
    .. [1] Seed paper 004_971077b94d8d4426.txt (multi-row planetary gears; title, authors and journal not
       recoverable), its B = b_a/d_a; gearcalc specification docs/spec/rows.md §1, §7.
    """
    d_a = pitch_diameter(sun_teeth, module)
    d_f = root_diameter(d_a, module)
    n = rows
    bbar = cheek_ratio
    if rim_width is not None:
        b_w = rim_width
        if cheek is not None:
            bbar = cheek / b_w
        B = _relative_width(b_w, n, bbar, d_a)
    else:
        B = relative_width
        if cheek is not None:
            b_w = rim_width_from_cheek(B, n, cheek, d_a)
            bbar = cheek_ratio_of(cheek, b_w)
        else:
            b_w = _rim_width(B, n, bbar, d_a)
    return Face(d_a, d_f, b_w, bbar, bbar * b_w, B, base_radius(d_a, pressure_angle))


def ratio_from_planet_teeth(planet_teeth, sun_teeth):
    """Ratio ``i = 2 + 2 z_g / z_a`` (sun input, ring fixed, carrier output; rows.md §5.4, §7).

    Examples
    --------
    >>> ratio_from_planet_teeth(36, 18)
    6.0

    References
    ----------
    .. [1] Seed paper 004_971077b94d8d4426.txt (multi-row planetary gears; title, authors and journal not
       recoverable), its geometry of the bridges; gearcalc specification docs/spec/rows.md §5.4, §7.
    """
    return 2.0 + 2.0 * planet_teeth / sun_teeth


def planet_teeth(ratio, sun_teeth):
    """Planet teeth ``z_g = z_a (i - 2) / 2`` [-], not necessarily an integer (rows.md §5.4).

    Examples
    --------
    >>> planet_teeth(6.0, 18)
    36.0

    References
    ----------
    .. [1] Seed paper 004_971077b94d8d4426.txt (multi-row planetary gears; title, authors and journal not
       recoverable), its geometry of the bridges; gearcalc specification docs/spec/rows.md §5.4.
    """
    return sun_teeth * (ratio - 2.0) / 2.0


def torsion_diameter(reading, pitch_diameter, root_diameter):
    """The diameter d_I of the sun's polar moment (rows.md §2.4).

    Parameters
    ----------
    reading : ``"pitch"`` (d_I = d_a), ``"root"`` (d_I = d_f) or a diameter [mm]; a list gives one
        reading per point of a batch
    pitch_diameter, root_diameter : d_a, d_f [mm]

    Returns
    -------
    d_I [mm]

    Raises
    ------
    ValueError
        for an unknown reading, listing the known ones.

    Examples
    --------
    >>> torsion_diameter("root", 90.0, 77.5), torsion_diameter(80, 90.0, 77.5)
    (77.5, 80.0)

    References
    ----------
    .. [1] Seed paper 004_971077b94d8d4426.txt (multi-row planetary gears; title, authors and journal not
       recoverable); gearcalc specification docs/spec/rows.md §2.4.
    """
    if isinstance(reading, str):
        if reading == "pitch":
            return pitch_diameter
        if reading == "root":
            return root_diameter
        raise ValueError(f"unknown torsion diameter {reading!r}; give \"pitch\", \"root\" or a diameter in mm")
    if isinstance(reading, (list, tuple)):
        import numpy as np

        return np.array([torsion_diameter(r, pitch_diameter[k], root_diameter[k]) for k, r in enumerate(reading)])
    return float(reading) if _is_number(reading) else reading


def shear_modulus(youngs_modulus, poisson):
    """``G = E / (2 (1 + ν))`` [MPa] (rows.md §1 "Notation").

    Examples
    --------
    >>> shear_modulus(2.6e5, 0.3)
    100000.0

    References
    ----------
    .. [1] Seed paper 004_971077b94d8d4426.txt (multi-row planetary gears; title, authors and journal not
       recoverable); gearcalc specification docs/spec/rows.md §1 Notation.
    """
    return youngs_modulus / (2.0 * (1.0 + poisson))


def mesh_stiffness(youngs_modulus):
    """The default mesh stiffness per unit face width ``C = 0.075 E`` [N/mm²] [paper] (rows.md §2.2).

    Examples
    --------
    >>> mesh_stiffness(2e5)
    15000.0

    References
    ----------
    .. [1] Seed paper 004_971077b94d8d4426.txt (multi-row planetary gears; title, authors and journal not
       recoverable), C = 0.075 E, citing its ref. [1]; gearcalc specification docs/spec/rows.md §2.2.
    """
    return MESH_STIFFNESS_PER_E * youngs_modulus


def rim_under_roots(root_diameter, bore):
    """Thickness of the sun's rim under the tooth roots ``(d_f - d_0) / 2`` [mm] (rows.md §10).

    Examples
    --------
    >>> rim_under_roots(77.5, 57.5)
    10.0

    References
    ----------
    .. [1] Seed paper 004_971077b94d8d4426.txt (multi-row planetary gears; title, authors and journal not
       recoverable); gearcalc specification docs/spec/rows.md §10; ISO 6336-3 rim-thickness factor.
    """
    return (root_diameter - bore) / 2


# ----------------------------------------------------------------------------- validity (rows.md §7, §10)
def rims_fit(rim_width):
    """True where the cheeks leave room for the rims, ``b_w > 0`` (rows.md §7).

    Examples
    --------
    >>> rims_fit(62.0), rims_fit(-1.0)
    (True, False)

    References
    ----------
    .. [1] Seed paper 004_971077b94d8d4426.txt (multi-row planetary gears; title, authors and journal not
       recoverable); gearcalc specification docs/spec/rows.md §7.
    """
    return rim_width > 0


def bore_fits(bore, *diameters):
    """True where the bore is smaller than every given diameter.

    True where the bore is smaller than every given diameter (rows.md §10: d_0 < min(d_f, d_I); the bridge sizing
    diameter likewise).

    Examples
    --------
    >>> bore_fits(50.0, 77.5, 90.0), bore_fits(80.0, 77.5, 90.0)
    (True, False)

    References
    ----------
    .. [1] Seed paper 004_971077b94d8d4426.txt (multi-row planetary gears; title, authors and journal not
       recoverable); gearcalc specification docs/spec/rows.md §10.
    """
    ok = True
    for d in diameters:
        ok = ok & (bore < d)
    return ok


def rim_too_thin(root_diameter, bore, module):
    """True where a hollow sun's rim under the roots is too thin (rows.md §10).

    True where a hollow sun's rim under the roots is thinner than 1.2 tooth depths, ``(d_f - d_0)/2 < 2.7 m`` [ISO
    6336-3] (rows.md §10).

    Examples
    --------
    >>> rim_too_thin(77.5, 70.0, 5.0), rim_too_thin(77.5, 0.0, 5.0)
    (True, False)

    References
    ----------
    .. [1] Seed paper 004_971077b94d8d4426.txt (multi-row planetary gears; title, authors and journal not
       recoverable); gearcalc specification docs/spec/rows.md §10; ISO 6336-3 rim-thickness factor.
    """
    return (bore > 0) & (rim_under_roots(root_diameter, bore) < RIM_MIN_MODULES * module)


def planets_collide(sun_teeth, planet_teeth, planets_per_row):
    """True where neighbouring planets of a row collide.

    ``z_g + 2 >= (z_a + z_g) sin(π/n_w)`` for n_w >= 2 (the adjacency condition; rows.md §10).

    Examples
    --------
    >>> planets_collide(18, 36.0, 3), planets_collide(18, 36.0, 5)
    (False, True)

    References
    ----------
    .. [1] Seed paper 004_971077b94d8d4426.txt (multi-row planetary gears; title, authors and journal not
       recoverable); gearcalc specification docs/spec/rows.md §10 (the adjacency condition).
    """
    return (planets_per_row >= 2) & ((planet_teeth + 2) >= (sun_teeth + planet_teeth) * _sin(math.pi / planets_per_row))


def row_centres(rows, cheek_ratio):
    """Mid-planes of the rows along the sun face, as fractions of b_a from the input side (rows.md §2.1).

    ``x_j / b_a = ((j - 1)(1 + b̄) + 0.5) / (n + b̄ (n - 1))``, j = 1..n

    Examples
    --------
    >>> row_centres(2, 0.0)
    [0.25, 0.75]

    References
    ----------
    .. [1] Seed paper 004_971077b94d8d4426.txt (multi-row planetary gears; title, authors and journal not
       recoverable), its twist angles at the rims' symmetry planes; gearcalc specification docs/spec/rows.md §2.1.
    """
    length = rows + cheek_ratio * (rows - 1)
    return [(j * (1 + cheek_ratio) + 0.5) / length for j in range(rows)]
