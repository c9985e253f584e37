"""Dimensions of the multi-row planetary gear and the rules they must satisfy.

Dimensions of the multi-row planetary gear and the rules they must satisfy (rows.md §1 "Notation", §2.3, §2.4, §5.4, §7,
§10).

Pure functions over floats and numpy arrays alike, written with arithmetic operators only: this module
imports no numpy, so ``gearcalc check`` (which derives the face widths) stays light.  The one
trigonometric function and the guarded division dispatch on the type: the math module for a Python
number (the result stays a Python float), numpy for an array; the two agree bit for bit on the range of
pressure angles (tests/rows/test_geometry.py).  Units mm, rad.

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
           "rim_too_thin", "planets_collide", "row_centres", "bore_margin", "rim_margin"]

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
    """Sun pitch diameter d_a [mm].

    .. math:: d_a = z_a m

    Parameters
    ----------
    sun_teeth : int or array_like
        Number of sun teeth z_a, [-].
    module : float or array_like
        Module m, [mm].

    Returns
    -------
    d_a : float or ndarray
        Sun pitch diameter, [mm].

    Examples
    --------
    >>> pitch_diameter(18, 5.0)
    90.0

    References
    ----------
    .. [1] Seed paper 004_971077b94d8d4426.txt, an OCR of a Russian journal paper on multi-row planetary gears (title,
       authors, journal and year not recoverable; its ref. [1]: F. I. Plekhanov, «Зубчатые планетарные передачи»);
       docs/spec/rows.md §1 "Notation".
    """
    return sun_teeth * module


def root_diameter(pitch_diameter, module):
    r"""Sun root diameter d_f [mm].

    .. math:: d_f = d_a - 2.5\,m

    Parameters
    ----------
    pitch_diameter : float or array_like
        Sun pitch diameter d_a, [mm].
    module : float or array_like
        Module m, [mm].

    Returns
    -------
    d_f : float or ndarray
        Sun root diameter, [mm].

    Examples
    --------
    >>> root_diameter(90.0, 5.0)
    77.5

    References
    ----------
    .. [1] Seed paper 004_971077b94d8d4426.txt, an OCR of a Russian journal paper on multi-row planetary gears (title,
       authors, journal and year not recoverable; its ref. [1]: F. I. Plekhanov, «Зубчатые планетарные передачи»);
       docs/spec/rows.md §1 "Notation", §2.4.
    """
    return pitch_diameter - ROOT_DEPTH_MODULES * module


def rim_width(relative_width, rows, cheek_ratio, sun_diameter):
    r"""Planet rim (row) width b_w from the relative sun face width B [mm].

    .. math:: b_w = \frac{B\,d_a}{n + \bar b\,(n - 1)}, \qquad b_a = n\,b_w + (n - 1)\,b = B\,d_a, \quad b = \bar b\,b_w

    Parameters
    ----------
    relative_width : float or array_like
        Relative sun face width B = b_a/d_a, [-].
    rows : int or array_like
        Number of rows n, [-].
    cheek_ratio : float or array_like
        Cheek ratio b̄ = b/b_w, [-].
    sun_diameter : float or array_like
        Sun pitch diameter d_a, [mm].

    Returns
    -------
    b_w : float or ndarray
        Rim width, [mm].

    Examples
    --------
    >>> rim_width(2.4, 3, 0.25, 90.0)
    61.714285714285715

    References
    ----------
    .. [1] Seed paper 004_971077b94d8d4426.txt, an OCR of a Russian journal paper on multi-row planetary gears (title,
       authors, journal and year not recoverable; its ref. [1]: F. I. Plekhanov, «Зубчатые планетарные передачи»); its B
       = b_a/d_a; docs/spec/rows.md §1, §7.
    """
    return relative_width * sun_diameter / (rows + cheek_ratio * (rows - 1))


def rim_width_from_cheek(relative_width, rows, cheek, sun_diameter):
    r"""Rim width b_w from the relative face width and a cheek thickness in mm.

    .. math:: b_w = \frac{B\,d_a - (n - 1)\,b}{n} \qquad (b_a = n\,b_w + (n - 1)\,b = B\,d_a)

    b_w <= 0 means the cheeks leave no room for the rims (:func:`rims_fit`).

    Parameters
    ----------
    relative_width : float or array_like
        Relative sun face width B, [-].
    rows : int or array_like
        Number of rows n, [-].
    cheek : float or array_like
        Cheek thickness b, [mm].
    sun_diameter : float or array_like
        Sun pitch diameter d_a, [mm].

    Returns
    -------
    b_w : float or ndarray
        Rim width, [mm].

    Examples
    --------
    >>> rim_width_from_cheek(2.4, 3, 15.0, 90.0)   # (216 - 30) / 3
    62.0

    References
    ----------
    .. [1] Seed paper 004_971077b94d8d4426.txt, an OCR of a Russian journal paper on multi-row planetary gears (title,
       authors, journal and year not recoverable; its ref. [1]: F. I. Plekhanov, «Зубчатые планетарные передачи»); its B
       = b_a/d_a; docs/spec/rows.md §7.
    """
    return (relative_width * sun_diameter - (rows - 1) * cheek) / rows


def relative_width(rim_width, rows, cheek_ratio, sun_diameter):
    r"""Relative sun face width B = b_a/d_a [-].

    .. math:: B = \frac{b_a}{d_a} = \frac{n\,b_w + (n - 1)\,\bar b\,b_w}{d_a}

    Parameters
    ----------
    rim_width : float or array_like
        Rim width b_w, [mm].
    rows : int or array_like
        Number of rows n, [-].
    cheek_ratio : float or array_like
        Cheek ratio b̄ = b/b_w, [-].
    sun_diameter : float or array_like
        Sun pitch diameter d_a, [mm].

    Returns
    -------
    B : float or ndarray
        Relative face width, [-].

    Examples
    --------
    >>> relative_width(60.0, 3, 0.25, 90.0)   # (180 + 30) / 90
    2.3333333333333335

    References
    ----------
    .. [1] Seed paper 004_971077b94d8d4426.txt, an OCR of a Russian journal paper on multi-row planetary gears (title,
       authors, journal and year not recoverable; its ref. [1]: F. I. Plekhanov, «Зубчатые планетарные передачи»); its B
       = b_a/d_a; docs/spec/rows.md §1, §2.2.
    """
    return (rows * rim_width + (rows - 1) * cheek_ratio * rim_width) / sun_diameter


_rim_width = rim_width  # the names are taken by arguments of face_geometry
_relative_width = relative_width


def cheek_ratio_of(cheek, rim_width):
    r"""Cheek ratio b̄ = b/b_w [-], infinite where b_w <= 0 (no room for the rims).

    .. math:: \bar b = \frac{b}{b_w} \quad (b_w > 0), \qquad \bar b = \infty \quad (b_w \le 0)

    Parameters
    ----------
    cheek : float or array_like
        Cheek thickness b, [mm].
    rim_width : float or array_like
        Rim width b_w, [mm].

    Returns
    -------
    b̄ : float or ndarray
        Cheek ratio, [-].

    Examples
    --------
    >>> cheek_ratio_of(15.0, 60.0), cheek_ratio_of(15.0, 0.0)
    (0.25, inf)

    References
    ----------
    .. [1] Seed paper 004_971077b94d8d4426.txt, an OCR of a Russian journal paper on multi-row planetary gears (title,
       authors, journal and year not recoverable; its ref. [1]: F. I. Plekhanov, «Зубчатые планетарные передачи»);
       docs/spec/rows.md §7.
    """
    if _is_number(rim_width):
        return cheek / rim_width if rim_width > 0 else math.inf
    import numpy as np

    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(rim_width > 0, cheek / rim_width, np.inf)


def base_radius(sun_diameter, pressure_angle):
    r"""Sun base radius r_ba [mm].

    .. math:: r_{ba} = \tfrac12\,d_a \cos\alpha_w

    Parameters
    ----------
    sun_diameter : float or array_like
        Sun pitch diameter d_a, [mm].
    pressure_angle : float or array_like
        Working pressure angle α_w, [rad].

    Returns
    -------
    r_ba : float or ndarray
        Base radius, [mm].

    Examples
    --------
    >>> round(base_radius(90.0, math.radians(20.0)), 6)
    42.286168

    References
    ----------
    .. [1] Seed paper 004_971077b94d8d4426.txt, an OCR of a Russian journal paper on multi-row planetary gears (title,
       authors, journal and year not recoverable; its ref. [1]: F. I. Plekhanov, «Зубчатые планетарные передачи»);
       docs/spec/rows.md §1 "Notation".
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
    r"""The face of the sun from whichever widths were given: B or b_w, and b̄ or b.

    .. math::

        d_a = z_a m, \quad d_f = d_a - 2.5\,m, \quad r_{ba} = \tfrac12 d_a \cos\alpha_w, \quad b = \bar b\,b_w,

        B = \frac{n\,b_w + (n - 1)\,\bar b\,b_w}{d_a} \ \text{(b_w given)}, \qquad
        b_w = \frac{B\,d_a}{n + \bar b\,(n - 1)} \ \text{(B given)}, \qquad
        b_w = \frac{B\,d_a - (n - 1)\,b}{n}, \ \bar b = \frac{b}{b_w} \ \text{(B and b given)}

    Parameters
    ----------
    sun_teeth : int or array_like
        Number of sun teeth z_a, [-].
    module : float or array_like
        Module m, [mm].
    rows : int or array_like
        Number of rows n, [-].
    pressure_angle : float or array_like
        Working pressure angle α_w, [rad].
    relative_width : float or array_like, optional
        Relative face width B, [-]; None when ``rim_width`` is given.
    rim_width : float or array_like, optional
        Rim width b_w, [mm], or None.
    cheek_ratio : float or array_like, optional
        Cheek ratio b̄, [-], used unless ``cheek`` is given (default 0.25).
    cheek : float or array_like, optional
        Cheek thickness b, [mm], or None.

    Returns
    -------
    face : Face
        d_a, d_f, b_w, b̄, b, B and r_ba [mm, -].

    Examples
    --------
    >>> f = face_geometry(18, 5.0, 3, math.radians(20.0), relative_width=2.4)
    >>> f.rim_width, f.cheek, f.root_diameter
    (61.714285714285715, 15.428571428571429, 77.5)

    References
    ----------
    .. [1] Seed paper 004_971077b94d8d4426.txt, an OCR of a Russian journal paper on multi-row planetary gears (title,
       authors, journal and year not recoverable; its ref. [1]: F. I. Plekhanov, «Зубчатые планетарные передачи»); its B
       = b_a/d_a; docs/spec/rows.md §1, §7.
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
    r"""Ratio i of the planetary stage (sun input, ring fixed, carrier output) from the teeth [-].

    .. math:: i = 2 + \frac{2 z_g}{z_a}

    Parameters
    ----------
    planet_teeth : float or array_like
        Number of planet teeth z_g, [-].
    sun_teeth : int or array_like
        Number of sun teeth z_a, [-].

    Returns
    -------
    i : float or ndarray
        Ratio, [-].

    Examples
    --------
    >>> ratio_from_planet_teeth(36, 18)
    6.0

    References
    ----------
    .. [1] Seed paper 004_971077b94d8d4426.txt, an OCR of a Russian journal paper on multi-row planetary gears (title,
       authors, journal and year not recoverable; its ref. [1]: F. I. Plekhanov, «Зубчатые планетарные передачи»); its
       geometry of the bridges; docs/spec/rows.md §5.4, §7.
    """
    return 2.0 + 2.0 * planet_teeth / sun_teeth


def planet_teeth(ratio, sun_teeth):
    r"""Planet teeth z_g for a ratio [-], not necessarily an integer.

    .. math:: z_g = \frac{z_a\,(i - 2)}{2}

    Parameters
    ----------
    ratio : float or array_like
        Ratio i, [-].
    sun_teeth : int or array_like
        Number of sun teeth z_a, [-].

    Returns
    -------
    z_g : float or ndarray
        Number of planet teeth, [-].

    Examples
    --------
    >>> planet_teeth(6.0, 18)
    36.0

    References
    ----------
    .. [1] Seed paper 004_971077b94d8d4426.txt, an OCR of a Russian journal paper on multi-row planetary gears (title,
       authors, journal and year not recoverable; its ref. [1]: F. I. Plekhanov, «Зубчатые планетарные передачи»); its
       geometry of the bridges; docs/spec/rows.md §5.4.
    """
    return sun_teeth * (ratio - 2.0) / 2.0


def torsion_diameter(reading, pitch_diameter, root_diameter):
    r"""The diameter d_I of the sun's polar moment of inertia [mm].

    .. math:: d_I = d_a \ \text{("pitch")}, \qquad d_I = d_f \ \text{("root")}, \qquad d_I = \text{the given diameter}

    Parameters
    ----------
    reading : str or float or list
        ``"pitch"``, ``"root"`` or a diameter, [mm]; a list gives one reading per point of a batch.
    pitch_diameter : float or array_like
        Sun pitch diameter d_a, [mm].
    root_diameter : float or array_like
        Sun root diameter d_f, [mm].

    Returns
    -------
    d_I : float or ndarray
        Torsion diameter, [mm].

    Raises
    ------
    ValueError
        For an unknown reading, listing the known ones.

    Examples
    --------
    >>> torsion_diameter("root", 90.0, 77.5), torsion_diameter(80, 90.0, 77.5)
    (77.5, 80.0)

    References
    ----------
    .. [1] Seed paper 004_971077b94d8d4426.txt, an OCR of a Russian journal paper on multi-row planetary gears (title,
       authors, journal and year not recoverable; its ref. [1]: F. I. Plekhanov, «Зубчатые планетарные передачи»);
       docs/spec/rows.md §2.4 (a decision of gearcalc).
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
    r"""Shear modulus G of an isotropic material [MPa].

    .. math:: G = \frac{E}{2\,(1 + \nu)}

    Parameters
    ----------
    youngs_modulus : float or array_like
        Young's modulus E, [MPa].
    poisson : float or array_like
        Poisson's ratio ν, [-].

    Returns
    -------
    G : float or ndarray
        Shear modulus, [MPa].

    Examples
    --------
    >>> shear_modulus(2.6e5, 0.3)
    100000.0

    References
    ----------
    .. [1] Seed paper 004_971077b94d8d4426.txt, an OCR of a Russian journal paper on multi-row planetary gears (title,
       authors, journal and year not recoverable; its ref. [1]: F. I. Plekhanov, «Зубчатые планетарные передачи»);
       docs/spec/rows.md §1 "Notation".
    """
    return youngs_modulus / (2.0 * (1.0 + poisson))


def mesh_stiffness(youngs_modulus):
    r"""The default mesh stiffness per unit face width C [N/mm²].

    .. math:: C = 0.075\,E

    Parameters
    ----------
    youngs_modulus : float or array_like
        Young's modulus E, [MPa].

    Returns
    -------
    C : float or ndarray
        Mesh stiffness per unit face width, [N/mm²].

    Examples
    --------
    >>> mesh_stiffness(2e5)
    15000.0

    References
    ----------
    .. [1] Seed paper 004_971077b94d8d4426.txt, an OCR of a Russian journal paper on multi-row planetary gears (title,
       authors, journal and year not recoverable; its ref. [1]: F. I. Plekhanov, «Зубчатые планетарные передачи»); its C
       = 0.075 E, citing its ref. [1]; docs/spec/rows.md §2.2.
    """
    return MESH_STIFFNESS_PER_E * youngs_modulus


def rim_under_roots(root_diameter, bore):
    r"""Thickness of the sun's rim under the tooth roots [mm].

    .. math:: s_R = \frac{d_f - d_0}{2}

    Parameters
    ----------
    root_diameter : float or array_like
        Sun root diameter d_f, [mm].
    bore : float or array_like
        Bore diameter d_0 of a hollow sun, [mm] (0: solid).

    Returns
    -------
    s_R : float or ndarray
        Rim thickness, [mm].

    Examples
    --------
    >>> rim_under_roots(77.5, 57.5)
    10.0

    References
    ----------
    .. [1] Seed paper 004_971077b94d8d4426.txt, an OCR of a Russian journal paper on multi-row planetary gears (title,
       authors, journal and year not recoverable; its ref. [1]: F. I. Plekhanov, «Зубчатые планетарные передачи»);
       docs/spec/rows.md §10.
    .. [2] ISO 6336-3:2019, Calculation of load capacity of spur and helical gears - Part 3: Calculation of tooth
       bending strength (rim thickness factor Y_B).
    """
    return (root_diameter - bore) / 2


# ----------------------------------------------------------------------------- validity (rows.md §7, §10)
def rims_fit(rim_width):
    """True where the cheeks leave room for the rims.

    .. math:: b_w > 0

    Parameters
    ----------
    rim_width : float or array_like
        Rim width b_w, [mm].

    Returns
    -------
    ok : bool or ndarray of bool
        True where the rims fit.

    Examples
    --------
    >>> rims_fit(62.0), rims_fit(-1.0)
    (True, False)

    References
    ----------
    .. [1] Seed paper 004_971077b94d8d4426.txt, an OCR of a Russian journal paper on multi-row planetary gears (title,
       authors, journal and year not recoverable; its ref. [1]: F. I. Plekhanov, «Зубчатые планетарные передачи»);
       docs/spec/rows.md §7.
    """
    return rim_width > 0


def bore_fits(bore, *diameters):
    r"""True where the bore is smaller than every given diameter.

    .. math:: d_0 < \min(d_f, d_I, \dots)

    The bridge sizing diameter is checked likewise.

    Parameters
    ----------
    bore : float or array_like
        Bore diameter d_0, [mm].
    *diameters : float or array_like
        The diameters the bore must stay below (d_f, d_I, ...), [mm].

    Returns
    -------
    ok : bool or ndarray of bool
        True where the bore fits.

    Examples
    --------
    >>> bore_fits(50.0, 77.5, 90.0), bore_fits(80.0, 77.5, 90.0)
    (True, False)

    References
    ----------
    .. [1] Seed paper 004_971077b94d8d4426.txt, an OCR of a Russian journal paper on multi-row planetary gears (title,
       authors, journal and year not recoverable; its ref. [1]: F. I. Plekhanov, «Зубчатые планетарные передачи»);
       docs/spec/rows.md §10.
    """
    ok = True
    for d in diameters:
        ok = ok & (bore < d)
    return ok


def rim_too_thin(root_diameter, bore, module):
    r"""True where a hollow sun's rim under the roots is thinner than 1.2 tooth depths.

    .. math:: d_0 > 0 \quad\text{and}\quad \frac{d_f - d_0}{2} < 2.7\,m

    Parameters
    ----------
    root_diameter : float or array_like
        Sun root diameter d_f, [mm].
    bore : float or array_like
        Bore diameter d_0, [mm] (0: solid, never too thin).
    module : float or array_like
        Module m, [mm].

    Returns
    -------
    thin : bool or ndarray of bool
        True where the rim is too thin.

    Examples
    --------
    >>> rim_too_thin(77.5, 70.0, 5.0), rim_too_thin(77.5, 0.0, 5.0)
    (True, False)

    References
    ----------
    .. [1] Seed paper 004_971077b94d8d4426.txt, an OCR of a Russian journal paper on multi-row planetary gears (title,
       authors, journal and year not recoverable; its ref. [1]: F. I. Plekhanov, «Зубчатые планетарные передачи»);
       docs/spec/rows.md §10.
    .. [2] ISO 6336-3:2019, Calculation of load capacity of spur and helical gears - Part 3: Calculation of tooth
       bending strength (rim thickness factor Y_B).
    """
    return (bore > 0) & (rim_under_roots(root_diameter, bore) < RIM_MIN_MODULES * module)


def bore_margin(bore, *diameters):
    r"""The bore check as a margin (rows.md §10): ``1 - d_0/min(d)``.

    >= 0 exactly where :func:`bore_fits` holds except at d_0 = min(d) (0: the bore touches; the check, strict,
    fails there and the design is not valid).

    .. math:: m_{bore} = \frac{\min(d_f, d_I, \dots) - d_0}{\min(d_f, d_I, \dots)}

    Parameters
    ----------
    bore : float or array_like
        The sun's bore d_0 [mm] (0: a solid sun).
    *diameters : float or array_like
        The diameters the bore must stay inside (root diameter d_f, torsion diameter d_I, ...) [mm].

    Returns
    -------
    margin : float or ndarray
        The bore margin [-]: >= 0 passes.

    Examples
    --------
    >>> bore_margin(50.0, 77.5, 100.0), bore_margin(0.0, 77.5)
    (0.3548387096774194, 1.0)

    References
    ----------
    .. [1] gearcalc specification docs/spec/rows.md §10.
    """
    smallest = diameters[0]
    for d in diameters[1:]:
        smallest = smallest if _is_number(smallest) and _is_number(d) and smallest <= d else _minimum(smallest, d)
    return (smallest - bore) / smallest


def _minimum(a, b):
    if _is_number(a) and _is_number(b):
        return min(a, b)
    import numpy as np

    return np.minimum(a, b)


def rim_margin(root_diameter, bore, module):
    r"""The rim check of a hollow sun as a margin (rows.md §10): ``1 - 2.7 m/t``.

    t = (d_f - d_0)/2 is the rim under the roots; the margin is < 0 exactly where :func:`rim_too_thin`; NaN for a
    solid sun (d_0 = 0: no rim to check).

    .. math:: m_{rim} = \frac{t - 2.7\,m}{t}, \qquad t = \frac{d_f - d_0}{2}

    Parameters
    ----------
    root_diameter : float or array_like
        The sun's root diameter d_f [mm].
    bore : float or array_like
        The sun's bore d_0 [mm].
    module : float or array_like
        The module m [mm].

    Returns
    -------
    margin : float or ndarray
        The rim margin [-]: >= 0 passes; NaN for a solid sun.

    Examples
    --------
    >>> rim_margin(77.5, 57.5, 5.0), rim_margin(77.5, 70.0, 5.0)
    (-0.35, -2.6)

    References
    ----------
    .. [1] gearcalc specification docs/spec/rows.md §10; ISO 6336-3 rim-thickness factor.
    """
    t = rim_under_roots(root_diameter, bore)
    m = (t - RIM_MIN_MODULES * module) / t
    if _is_number(bore):
        return m if bore > 0 else math.nan
    import numpy as np

    return np.where(np.asarray(bore) > 0, m, np.nan)


def planets_collide(sun_teeth, planet_teeth, planets_per_row):
    r"""True where neighbouring planets of a row collide (the adjacency condition).

    .. math:: n_w \ge 2 \quad\text{and}\quad z_g + 2 \ge (z_a + z_g) \sin\frac{\pi}{n_w}

    Parameters
    ----------
    sun_teeth : int or array_like
        Number of sun teeth z_a, [-].
    planet_teeth : float or array_like
        Number of planet teeth z_g, [-].
    planets_per_row : int or array_like
        Number of planets in a row n_w, [-].

    Returns
    -------
    collide : bool or ndarray of bool
        True where the planets' tip circles overlap.

    Examples
    --------
    >>> planets_collide(18, 36.0, 3), planets_collide(18, 36.0, 5)
    (False, True)

    References
    ----------
    .. [1] Seed paper 004_971077b94d8d4426.txt, an OCR of a Russian journal paper on multi-row planetary gears (title,
       authors, journal and year not recoverable; its ref. [1]: F. I. Plekhanov, «Зубчатые планетарные передачи»);
       docs/spec/rows.md §10 (the adjacency condition).
    """
    return (planets_per_row >= 2) & ((planet_teeth + 2) >= (sun_teeth + planet_teeth) * _sin(math.pi / planets_per_row))


def row_centres(rows, cheek_ratio):
    r"""Mid-planes of the rows along the sun face, as fractions of b_a from the input side.

    .. math:: \frac{x_j}{b_a} = \frac{(j - 1)(1 + \bar b) + \tfrac12}{n + \bar b\,(n - 1)}, \qquad j = 1, \dots, n

    Parameters
    ----------
    rows : int
        Number of rows n, [-].
    cheek_ratio : float
        Cheek ratio b̄ = b/b_w, [-].

    Returns
    -------
    x : list of float
        x_j/b_a of each row, [-].

    Examples
    --------
    >>> row_centres(2, 0.0)
    [0.25, 0.75]

    References
    ----------
    .. [1] Seed paper 004_971077b94d8d4426.txt, an OCR of a Russian journal paper on multi-row planetary gears (title,
       authors, journal and year not recoverable; its ref. [1]: F. I. Plekhanov, «Зубчатые планетарные передачи»); its
       twist angles at the rims' symmetry planes; docs/spec/rows.md §2.1.
    """
    length = rows + cheek_ratio * (rows - 1)
    return [(j * (1 + cheek_ratio) + 0.5) / length for j in range(rows)]
