"""Physics of the eccentric closed rolling-body mechanism (ZSTK) with a leading inner ring.

Pure functions over floats and numpy arrays (no I/O, no design objects, no key names).  Units: mm,
N, MPa, radians inside; degrees only at the interface (:mod:`gearcalc.kinds.zstk`).  Arrays of
roller quantities have the shape ``(..., N)``: leading axes for phases, load directions or stacked
designs.  Frame: O_H = (0, 0), O_B = (e, 0); +x points to the narrowest point of the annular gap
(theta = 0); angles grow counter-clockwise.

Modules (spec ``docs/spec/zstk.md``):

* :mod:`.geometry` §3.1 roller radius, centre distance, contact normals and beta (closed form);
* :mod:`.chain` §3.2 closure as a Steiner chain (N*, the corrections of R_H, R_B or c, N_max) and
  §4 the roller positions through the Möbius map (explicit stepping as a cross-check);
* :mod:`.validity` §3.3, §9 the validity rules, one vectorised rule set;
* :mod:`.loads` §5 the load distribution (zero clearance: direction root; clearance/preload:
  bracketed 1-D root or Newton on the convex potential);
* :mod:`.stress` §2 the Hertz stresses (through :mod:`gearcalc.hertz`) and the summary quantities;
* :mod:`.envelope` §8 the sweeps over the chain phase ("cycle") and the load direction ("envelope");
* :mod:`.capacity` §5.4 the allowable radial load (sigma_max = [sigma_H]).

Every public name of the modules is re-exported here (``from gearcalc import zstk as z``).

References
----------
Merko M.A., Mesnyankin M.V., Kolotov A.V., Mityaev A.E., Savitskaya M.V., Merko A.M., Yurov S.A.,
«Анализ нормальных напряжений на площадках контакта звеньев механизмов с ЗСТК при ведущем
внутреннем кольце и вводе поправки по радиусу дорожки качения наружного кольца» (Siberian Federal
University; UDC 621.838.2; no journal or year given: seed 003_2d1da402cb0b8488.txt), eqs. (1)-(7);
docs/spec/zstk.md.
"""
from __future__ import annotations

import numpy as np  # noqa: F401 (the examples' np, as in the modules)

from . import capacity, chain, envelope, geometry, loads, stress, validity
from .capacity import *  # noqa: F401,F403
from .chain import *  # noqa: F401,F403
from .envelope import *  # noqa: F401,F403
from .geometry import *  # noqa: F401,F403
from .loads import *  # noqa: F401,F403
from .stress import *  # noqa: F401,F403
from .validity import *  # noqa: F401,F403

_MODULES = (geometry, chain, validity, loads, stress, envelope, capacity)
__all__ = [name for m in _MODULES for name in m.__all__]

# the examples of the modules' functions count as this package's own (doctest finds re-exported
# functions only through __test__)
__test__ = {name: obj for m in _MODULES for name in m.__all__
            if getattr(obj := getattr(m, name), "__doc__", None) and callable(obj)}
