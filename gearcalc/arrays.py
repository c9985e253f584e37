"""Small array helpers shared by the calculators.

``numpy.unique`` on a plain array imports ``numpy.ma`` (about 8 ms) on its first call, for its masked-array
check; a command that computes one design pays that in its start-up.  :func:`unique_sorted` does the same job
for the unmasked arrays the calculators use, without it.
"""
from __future__ import annotations

import numpy as np


def unique_sorted(values):
    """The sorted distinct values of an array (flattened), as ``numpy.unique`` returns them.

    >>> unique_sorted([3, 1, 3, 2]).tolist()
    [1, 2, 3]
    >>> unique_sorted(np.array([0.5, -0.0, 0.0, 0.5])).tolist()
    [-0.0, 0.5]
    """
    a = np.sort(np.asarray(values).ravel())
    if a.size == 0:
        return a
    keep = np.empty(a.size, dtype=bool)
    keep[0] = True
    np.not_equal(a[1:], a[:-1], out=keep[1:])
    return a[keep]
