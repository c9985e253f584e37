"""Samplers beyond the grid: ``--vary KEY=LO:HI`` ranges and ``--sample sobol:N|lhs:N|random:N --seed S``.

A sample is drawn once, in the calling process, as an ``N x d`` matrix of unit coordinates
(:mod:`scipy.stats.qmc`: a scrambled Sobol' sequence, a Latin hypercube, or independent uniforms), then mapped to
the ranges: a number key to ``LO + u (HI - LO)``, an integer key (the schema's ``"integer"`` fields: tooth, roller,
row counts) to one of ``LO..HI`` inclusive, each equally likely (``LO + floor(u (HI - LO + 1))``).  Point ``k`` of a
sample is a function of (sampler, N, seed, k) alone; the points are evaluated in chunks of the grid sweep
(:class:`gearcalc.grid.Sample`), so one process, ``--jobs`` and ``--scheduler`` give the same rows.

Floats are rounded to 12 significant digits (:func:`gearcalc.grid.round12`, as a grid's values): the CSV shows
the value the design file of that point would hold.
"""
from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

__all__ = ["Box", "parse_ranges", "parse_sampler", "unit_sample", "draw", "SAMPLERS", "MAX_SAMPLE"]

SAMPLERS = ("sobol", "lhs", "random")

MAX_SAMPLE = 1_000_000
"""Points of one sample at most: the matrix is drawn whole in the calling process (8 bytes a value, so 8 MB a
varied key at the cap) before its chunks are evaluated."""


class SampleError(ValueError):
    """A malformed ``--vary`` range or ``--sample``."""


@dataclass(frozen=True)
class Box:
    """The varied keys and their inclusive ranges: ``keys``, ``lo``, ``hi`` (floats) and ``ints`` (True for an
    integer key)."""

    keys: tuple
    lo: tuple
    hi: tuple
    ints: tuple

    @property
    def d(self) -> int:
        return len(self.keys)

    def values(self, unit):
        """Unit coordinates (``n x d``, in [0, 1)) to the keys' values (``n x d`` floats; integer keys hold
        integers)."""
        import numpy as np

        from ..grid import round12

        u = np.asarray(unit, dtype=np.float64).reshape(-1, self.d)
        lo, hi = np.array(self.lo), np.array(self.hi)
        ints = np.array(self.ints, dtype=bool)
        x = lo + u * (hi - lo)
        k = np.minimum(np.floor(lo + u * (hi - lo + 1.0)), hi)
        x = np.where(ints, k, round12(x))
        return x

    def axes(self, unit):
        """The sample as :class:`gearcalc.grid.Sample` axes (lists of Python ints and floats)."""
        from ..grid import Sample

        x = self.values(unit)
        return Sample({key: ([int(v) for v in x[:, j].tolist()] if self.ints[j] else x[:, j].tolist())
                       for j, key in enumerate(self.keys)})


def parse_ranges(items: list[str], raw: dict | None = None) -> Box:
    """``KEY=LO:HI`` ranges (``--vary`` of a sample, ``optimize``, ``sensitivity``): each key's field must be a
    number or an integer, LO < HI, both accepted by the field (type and bounds).  ``raw``: the design, for its
    kind's schema (without it every key is a number).

    >>> b = parse_ranges(["rows.relative_width=2:3", "rows.count=2:5"], {"kind": "rows"})
    >>> b.keys, b.lo, b.hi, b.ints
    (('rows.relative_width', 'rows.count'), (2.0, 2.0), (3.0, 5.0), (False, True))
    """
    from .. import registry
    from ..design import _clip, _suggest, check_value

    kind = (raw or {}).get("kind")
    calc = registry.get(kind) if isinstance(kind, str) and kind in registry.kinds() else None
    keys, lo, hi, ints = [], [], [], []
    for item in items:
        key, sep, spec = item.partition("=")
        key, shown = key.strip(), _clip(item)
        if not sep or not key:
            raise SampleError(f"--vary {shown}: expected KEY=LO:HI, e.g. --vary rows.relative_width=2.0:2.8")
        if key in keys:
            raise SampleError(f"--vary {key}: given twice")
        parts = spec.split(":")
        if len(parts) != 2:
            raise SampleError(f"--vary {shown}: a sampled range is LO:HI (a grid's start:stop:step needs no --sample)")
        try:
            a, b = (float(p) for p in parts)
        except ValueError:
            raise SampleError(f"--vary {shown}: LO and HI must be numbers") from None
        if not (math.isfinite(a) and math.isfinite(b)) or not a < b:
            raise SampleError(f"--vary {shown}: LO and HI must be finite numbers with LO < HI")
        integer = False
        if calc is not None:
            table, _, name = key.partition(".")
            t = calc.table(table)
            field = t.field(name) if t is not None else None
            if field is None:
                known = [f"{t.name}.{f.name}" for t in calc.tables for f in t.fields
                         if f.type in ("number", "integer")]
                raise SampleError(f"--vary {shown}: {key} is not a key of a {kind} design" + _suggest(key, known))
            if field.type not in ("number", "integer"):
                raise SampleError(f"--vary {shown}: {key} is not a number (a sampled range needs a number key)")
            integer = field.type == "integer"
            if integer and not (a.is_integer() and b.is_integer()):
                raise SampleError(f"--vary {shown}: {key} is an integer: LO and HI must be integers")
            for v in (a, b):
                _, problem = check_value(field, int(v) if integer else v)
                if problem:
                    raise SampleError(f"--vary {key}={_clip(v)}: {problem}")
        keys.append(key)
        lo.append(a)
        hi.append(b)
        ints.append(integer)
    if not keys:
        raise SampleError("no --vary KEY=LO:HI given")
    return Box(tuple(keys), tuple(lo), tuple(hi), tuple(ints))


def parse_sampler(spec: str) -> tuple[str, int]:
    """``sobol:N``, ``lhs:N`` or ``random:N`` as (sampler, N).

    >>> parse_sampler("sobol:256"), parse_sampler("LHS:10")
    (('sobol', 256), ('lhs', 10))
    """
    from ..design import _clip, _suggest

    name, sep, count = spec.strip().partition(":")
    name = name.lower()
    if name not in SAMPLERS:
        raise SampleError(f"--sample {_clip(spec)}: the samplers are sobol:N, lhs:N, random:N"
                          + _suggest(name, SAMPLERS))
    try:
        n = int(count)
    except ValueError:
        raise SampleError(f"--sample {_clip(spec)}: N must be a whole number of points, e.g. {name}:256") from None
    if not 1 <= n <= MAX_SAMPLE:
        raise SampleError(f"--sample {_clip(spec)}: N must be 1 to {MAX_SAMPLE}")
    return name, n


def unit_sample(sampler: str, n: int, d: int, seed: int = 0):
    """``n`` points in the unit cube ``[0, 1)^d`` (an ``n x d`` array), a function of (sampler, n, d, seed) alone:
    ``sobol`` a scrambled Sobol' sequence (its first ``n`` points; balanced when ``n`` is a power of 2),
    ``lhs`` a Latin hypercube, ``random`` independent uniforms (numpy's PCG64).

    >>> u = unit_sample("lhs", 4, 2, seed=1)
    >>> u.shape, sorted((u[:, 0] * 4).astype(int).tolist())   # one point in each quarter
    ((4, 2), [0, 1, 2, 3])
    """
    import numpy as np

    if sampler == "random":
        return np.random.default_rng(seed).random((n, d))
    from scipy.stats import qmc

    if sampler == "lhs":
        return qmc.LatinHypercube(d, rng=np.random.default_rng(seed)).random(n)
    with warnings.catch_warnings():  # scipy's note that n is not a power of 2: the user chose n
        warnings.simplefilter("ignore", UserWarning)
        return qmc.Sobol(d, scramble=True, rng=np.random.default_rng(seed)).random(n)


def draw(box: Box, sampler: str, n: int, seed: int = 0):
    """The sample as :class:`gearcalc.grid.Sample` axes."""
    return box.axes(unit_sample(sampler, n, box.d, seed))
