"""Python's ``repr`` of floats, vectorised with numpy: the text of a whole column of doubles at once.

``repr(float)`` is the shortest decimal string that reads back as the same double (David Gay's dtoa, mode 0);
of several such strings of that length it takes the one nearest the double.  :func:`float_cells` writes that
text for an array of finite doubles as a matrix of ASCII bytes, byte for byte what ``repr`` writes;
:func:`repr_floats` gives it as strings.

How, with exact arithmetic wherever a digit is decided:

* ``E = floor(log10|x|)``: from the binary exponent and one comparison with the least double >= ``10**(E+1)``
  (a table), so it is exact.
* ``Y = |x| * 10**(16-E)`` lies in ``[1e16, 1e17)``.  With ``|x| = m * 2**e`` (``m`` a 53-bit integer) and
  ``10**(16-E) = (P1 + P2) * 2**g`` (a tabulated double-double, 106 bits, ``P1`` in ``[1, 2)``), ``m * P1`` is
  computed exactly as a double and its rounding error (Dekker's product of Veltkamp halves of at most 26
  bits; both factors near 1 or ``2**53``, so nothing overflows or underflows), ``m * P2`` is added and the
  sum scaled by ``2**(e+g)`` exactly: ``Y = D + f``, ``D`` the nearest integer (17 digits) and ``f`` in
  ``[-1/2, 1/2]`` within about 1e-14 of its true value.
* A decimal string reads back as ``x`` when it is nearer to ``x`` than half an ulp: ``h = ulp(x)/2`` scaled by
  ``10**(16-E)``, in ``(0.55, 11.2)``.  The nearest 15- and 16-digit numbers follow from ``D`` and ``f``
  (``D = 100 q + r``: the nearest 15-digit one is ``100 q`` or ``100 (q + 1)`` as ``r + f`` is below or above
  50), and so do their distances to ``Y``; the first of the nearest 15-, 16- and 17-digit numbers nearer
  than ``h`` is the answer, trailing zeros dropped.  For a normal double whose significand is not a power
  of two this is dtoa's answer: the strings that read back lie in an interval symmetric around ``x`` and 1
  ulp wide, narrower than the gaps between 15-digit numbers, so a string of at most 15 digits reads back
  only if the nearest 15-digit number does (and then, zero-padded, it is that one); else the nearest
  16-digit number if it reads back (dtoa takes the nearest of those that do); else the nearest 17-digit
  number, which always does.
* Each decision compares a computed quantity with a threshold (``h``, 5, 50, 1/2).  Where the two are closer
  than :data:`MARGIN` (1e-9, about 1e5 times the worst error) the value is decided exactly when every
  quantity is exact (``10**(16-E)`` a double, ``0 <= 16-E <= 22``, and ``Y`` a multiple of ``2**-45``: all
  of ``1e-3 <= |x| < 1e17``, and the short binary fractions below, whose ties these are): a string exactly
  half an ulp away reads back when the significand is even, and of two candidates equally near, dtoa takes
  the one with an even last digit.  Otherwise it is left to ``repr``: about 6 values in 1e4 of random bit
  patterns (mostly subnormals; the rest mostly integers beyond 1e17 whose candidates lie exactly half an ulp
  away), none of a typical sweep.
* Zeros and doubles with an all-zero significand (powers of two, whose interval below is half as wide) take
  their digits from a table made once with ``repr``; subnormals are left to ``repr``.

The text: positional for ``-4 <= E < 16`` (``1234.5``, ``0.00012``, ``123.0``: ``.0`` when there is no
fraction), else ``d.ddde±XX`` (``1e+16``, ``2.5e-07``, ``1e-300``: at least two exponent digits); a ``-``
before a negative value, ``-0.0`` included.

The arithmetic assumes IEEE doubles rounded to nearest in numpy's float64 operations (every current
platform); :func:`available` checks that once against ``repr`` on hard cases and says False otherwise, so
that callers keep ``repr``.
"""
from __future__ import annotations

import math
import numpy as np

__all__ = ["apart", "available", "cells_width", "float_cells", "repr_floats", "MARGIN", "WIDTH"]

def apart(a: float, b: float, digits: int = 6) -> tuple[str, str]:
    """``a`` and ``b`` for a message that compares them ("a > b"): ``digits`` significant digits, more when that
    would print two different values the same (``repr`` at most).

    >>> apart(1500.0043, 1500.0), apart(0.5, 0.25)
    (('1500.004', '1500'), ('0.5', '0.25'))
    """
    a, b = float(a), float(b)
    for d in range(digits, 18):
        text_a, text_b = f"{a:.{d}g}", f"{b:.{d}g}"
        if text_a != text_b or a == b:
            return text_a, text_b
    return repr(a), repr(b)


EMIN, EMAX = -308, 308
"""Decimal exponents of normal doubles."""

MARGIN = 1e-9
"""A decision closer than this (in units of the 17th significant digit) is taken exactly or left to ``repr``."""

WIDTH = 24
"""The longest ``repr`` of a double: ``-2.2250738585072014e-308``."""

_T = None  # the tables, built on first use (about 50 ms)
_OK = None  # the self-check's verdict


class _Tables:
    def __init__(self):
        n = EMAX - EMIN + 1
        # by E - EMIN: 10**(16-E) = (P1 + P2) * 2**g, P1 = P1h + P1l (Veltkamp halves); S0 = g - 1075
        self.P1, self.P1h, self.P1l, self.P2 = (np.empty(n) for _ in range(4))
        self.S0 = np.empty(n, dtype=np.int32)
        self.exact = np.empty(n, dtype=bool)
        for i, E in enumerate(range(EMIN, EMAX + 1)):
            p = 16 - E
            # 10**p * 2**-g = num / den in [1, 2), integers (int / int is correctly rounded in Python)
            if p >= 0:
                g = (10 ** p).bit_length() - 1
                num, den = 10 ** p, 1 << g
            else:
                g = -(10 ** -p).bit_length()
                num, den = 1 << -g, 10 ** -p
            p1 = num / den
            a, b = p1.as_integer_ratio()  # p1 = a / b, b a power of two
            rest = num * b - a * den  # num / den - p1 = rest / (den * b)
            c = p1 * 134217729.0  # Veltkamp: halves of at most 26 bits
            hi = c - (c - p1)
            self.P1[i], self.P1h[i], self.P1l[i], self.P2[i] = p1, hi, p1 - hi, rest / (den * b)
            self.S0[i] = g - 1075
            self.exact[i] = rest == 0
        # by biased exponent b (|x| in [2**(b-1023), 2**(b-1022)); 0 as 1): k = floor((b - 1023) log10 2)
        # and the least double >= 10**(k+1); E is k or k + 1
        self.K0 = np.empty(2048, dtype=np.int64)
        self.TK = np.empty(2048)
        least = {}
        for b in range(2048):
            k = ((max(b, 1) - 1023) * 78913) >> 18  # floor(e log10 2) for |e| < 1650 (as in Ryu)
            if k not in least:
                num, den = (10 ** (k + 1), 1) if k + 1 >= 0 else (1, 10 ** -(k + 1))
                try:
                    f = num / den
                except OverflowError:
                    f = math.inf
                if math.isfinite(f):
                    fa, fb = f.as_integer_ratio()
                    if fa * den < num * fb:
                        f = math.nextafter(f, math.inf)
                least[k] = f
            self.K0[b], self.TK[b] = k - EMIN, least[k]
        # zeros (b = 0) and powers of two by biased exponent: (17-digit D, E) from repr
        self.pow2_D = np.zeros(2048, dtype=np.int64)
        self.pow2_E = np.zeros(2048, dtype=np.int64)
        for b in range(1, 2047):
            self.pow2_D[b], self.pow2_E[b] = _parse(repr(math.ldexp(1.0, b - 1023)))
        self.mod10 = (np.arange(100) % 10).astype(np.int64)
        # four digits of 0..9999 as ASCII in one uint32 (its bytes are the text on any byte order): words[p] has
        # the text of g at g and, at 10000 + g, the text without its trailing zeros but for the first p
        # characters (zero bytes instead), for the last word with a non-zero digit
        self.dig4 = np.frombuffer("".join(f"{g:04d}" for g in range(10000)).encode(), dtype=np.uint32)
        chars = self.dig4.view(np.uint8).reshape(10000, 4)
        nonzero = chars != 48
        length = np.where(nonzero.any(axis=1), 4 - nonzero[:, ::-1].argmax(axis=1), 0)  # without trailing zeros
        self.words = []
        for p in range(5):
            cut = np.where(np.arange(4) < np.maximum(length, p)[:, None], chars, 0).astype(np.uint8)
            self.words.append(np.concatenate([self.dig4, cut.view(np.uint32).ravel()]))
        # "e+16", "e-05", "e-324" by E + 400, in 8 bytes
        self.exp8 = np.frombuffer(b"".join(f"e{E:+03d}".encode().ljust(8, b"\0") for E in range(-400, 401)),
                                  dtype=np.uint64)


def _parse(text: str) -> tuple[int, int]:
    """``repr`` of a positive double as (its digits as a 17-digit integer, its decimal exponent).

    >>> _parse("1234.5"), _parse("1e-05"), _parse("0.0")
    ((12345000000000000, 3), (10000000000000000, -5), (0, 0))
    """
    mant, _, exp = text.partition("e")
    whole, _, frac = mant.partition(".")
    digits = (whole + frac).lstrip("0")
    if not digits:
        return 0, 0
    E = (int(exp) if exp else 0) - len(frac) + len(digits) - 1
    return int(digits) * 10 ** (17 - len(digits)), E


def _tables() -> _Tables:
    global _T
    if _T is None:
        _T = _Tables()
    return _T


FAST_RANGE = (1e-250, 1e250)
"""Magnitudes for which :func:`_digits_one_exponent` scales ``|x|`` directly (no underflow or overflow)."""


def _digits(x: np.ndarray):
    """(D, E, fallback) of finite doubles: D the digits of ``repr(|x|)`` as a 17-digit integer (in [1e16, 1e17),
    0 for a zero), E its decimal exponent, ``fallback`` the indices of the values given by ``repr``.

    Values of one decimal exponent (most blocks of a sweep's column) take :func:`_digits_one_exponent` (the same
    numbers, fewer numpy passes); the others, and any block with a decision near its threshold, a power of two,
    a zero or a subnormal, the general way (:func:`_digits_general`)."""
    if len(x):
        a = np.abs(x)
        lo, hi = float(a.min()), float(a.max())
        if FAST_RANGE[0] <= lo and hi < FAST_RANGE[1]:
            e = _exponent(lo)
            if e == _exponent(hi):
                got = _digits_one_exponent(x, a, e)
                if got is not None:
                    return got
    return _digits_general(x)


def _exponent(v: float) -> int:
    """``floor(log10(v))`` of a positive normal double, exactly (the tables of :func:`_digits`)."""
    T = _tables()
    b = math.frexp(v)[1] + 1022  # the biased exponent: v in [2**(b-1023), 2**(b-1022))
    return int(T.K0[b]) + (v >= float(T.TK[b])) + EMIN


def _digits_one_exponent(x, a, E: int):
    """:func:`_digits` of doubles all of decimal exponent ``E`` with ``1e-250 <= |x| < 1e250``, or None for a
    block the general way must take (a decision within :data:`MARGIN` of its threshold, a power of two).

    The numbers of :func:`_digits_general`, bit for bit, with fewer passes: ``|x| = m 2**e`` and
    ``10**(16-E) = (P1 + P2) 2**g`` scaled together, ``|x| * (P1 2**g)`` and its rounding error (Dekker's product
    of the Veltkamp halves of ``|x|`` and of ``P1 2**g``) are ``m * P1`` and its error scaled by ``2**(e+g)``
    exactly (a power of two, and no product underflows or overflows in this range), so ``Y = D17 + f`` and ``h``
    come out the same without taking ``m`` and ``e`` apart."""
    T = _tables()
    i = E - EMIN
    bits = x.view(np.int64)
    frac = bits & ((1 << 52) - 1)
    if frac.min() == 0:  # a power of two: its digits from the table, the general way
        return None
    g = int(T.S0[i]) + 1075
    P1, P1h, P1l, P2 = (math.ldexp(float(v[i]), g) for v in (T.P1, T.P1h, T.P1l, T.P2))
    c = a * 134217729.0  # Veltkamp halves of |x|
    ah = c - (c - a)
    al = a - ah
    y = a * P1  # an integer: Y in [1e16, 1e17] and y within an ulp of it
    err = ((ah * P1h - y) + ah * P1l + al * P1h) + al * P1l  # a * P1 = y + err exactly (Dekker)
    r = err + a * P2
    k = np.rint(r)
    f = r - k  # exact
    D17 = y.astype(np.int64) + k.astype(np.int64)
    # half an ulp of x, scaled like Y: 2**(b-1023) (the exponent bits of x) * 2**-53 * P1 2**g
    h = (bits & (0x7FF << 52)).view(np.float64) * math.ldexp(float(T.P1[i]), g - 53)
    D, g15, g16, a16, _ = _shortest(D17, f, h, T.mod10)
    if (min(float(np.abs(g15).min()), float(np.abs(g16).min()), float(a16.min())) < MARGIN
            or float(np.abs(f).max()) > 0.5 - MARGIN):
        return None  # a decision near its threshold: exactly or by repr, the general way
    Es = np.full(len(x), E, dtype=np.int64)
    if D.max() == 10**17:
        carry = D == 10**17
        D[carry] = 10**16
        Es += carry
    return D, Es, np.zeros(0, dtype=np.intp)


def _shortest(D17, f, h, mod10):
    """The shortest of the 15-, 16- and 17-digit candidates that reads back, as a 17-digit integer D, and the
    margins of the decisions: the nearest 15- and 16-digit numbers (D17 = 100 q + r2, r2 = 10 s + r1) read
    back when g > 0 (their distance, 50 - |u - 50| for 15 digits, is below h, half an ulp of x scaled like
    Y = D17 + f); a16 = |u16 - 5| is the distance of a 16-digit tie; and (q, r1, u15, u16) for the exact
    resolution of the unsure ones."""
    q = D17 // 100
    r2 = D17 - 100 * q
    r1 = mod10.take(r2)
    u15 = r2 + f  # Y - 100 q
    u16 = r1 + f  # Y - 10 s
    a16 = np.abs(u16 - 5.0)
    g15 = np.abs(u15 - 50.0) - (50.0 - h)
    g16 = a16 - (5.0 - h)
    D = np.where(g15 > 0.0, (q + (u15 > 50.0)) * 100, np.where(g16 > 0.0, D17 - r1 + 10 * (u16 > 5.0), D17))
    return D, g15, g16, a16, (q, r1, u15, u16)


def _digits_general(x: np.ndarray):
    """:func:`_digits` of any finite doubles."""
    T = _tables()
    bits = x.view(np.int64)
    frac = bits & ((1 << 52) - 1)
    b = (bits >> 52) & 0x7FF
    i = T.K0.take(b) + (np.abs(x) >= T.TK.take(b))  # E - EMIN, exact
    i0 = int(i[0])
    if i0 == i.min() == i.max():  # one decimal exponent (most columns): the table entries are numbers
        P1, P1h, P1l, P2, S0 = (float(T.P1[i0]), float(T.P1h[i0]), float(T.P1l[i0]), float(T.P2[i0]),
                                int(T.S0[i0]))
    else:
        P1, P1h, P1l, P2, S0 = T.P1.take(i), T.P1h.take(i), T.P1l.take(i), T.P2.take(i), T.S0.take(i)
    S = b.astype(np.int32) + S0  # |x| * 10**(16-E) = m * (P1 + P2) * 2**S
    mf = (frac | (1075 << 52)).view(np.float64)  # m = 2**52 + frac as a double
    c = mf * 134217729.0  # Veltkamp halves of m
    mh = c - (c - mf)
    ml = mf - mh
    y = mf * P1
    err = ((mh * P1h - y) + mh * P1l + ml * P1h) + ml * P1l  # m * P1 = y + err exactly (Dekker)
    r = np.ldexp(err + mf * P2, S)
    k = np.rint(r)
    f = r - k  # exact
    D17 = np.ldexp(y, S).astype(np.int64) + k.astype(np.int64)  # ldexp(y, S) > 2**53: an integer
    h = np.ldexp(P1, S - 1)  # half an ulp of x, scaled like Y
    D, g15, g16, a16, (q, r1, u15, u16) = _shortest(D17, f, h, T.mod10)
    # a decision within MARGIN of its threshold (or a tie of two 16- or 17-digit candidates)
    unsure = (np.abs(g15) < MARGIN) | (np.abs(g16) < MARGIN) | (a16 < MARGIN) | (np.abs(f) > 0.5 - MARGIN)
    pow2 = frac == 0 if frac.min() == 0 else None  # zeros and powers of two: from the table
    sub = b == 0 if b.min() == 0 else None  # zeros and subnormals: repr
    if pow2 is not None:
        unsure &= ~pow2
    if sub is not None:
        unsure |= sub
        if pow2 is not None:
            unsure &= ~pow2
    if unsure.any():  # exact ties and strings exactly half an ulp away, mostly
        j = np.flatnonzero(unsure if sub is None else unsure & ~sub)
        # every quantity exact when 10**(16-E) is a double (P2 = 0) and Y = m 5**p 2**(e+p) a multiple of
        # 2**-45: f, u15 and u16 have at most 52 bits below 100, t15, t16 and h are exact, so is every comparison
        m = frac[j] | (1 << 52)
        low = np.frexp((m & -m).astype(np.float64))[1] - 1  # trailing zero bits of m
        exact = T.exact[i[j]] & (b[j] - 1075 + low + 16 - (i[j] + EMIN) >= -45)
        jj = j[exact]
        if len(jj):
            D[jj], unsure[jj] = _resolve_exact(D17[jj], f[jj], q[jj], r1[jj], u15[jj], u16[jj], h[jj],
                                               (frac[jj] & 1) == 0)
    E = i + EMIN
    if D.max() == 10**17:
        carry = D == 10**17
        D[carry] = 10**16
        E += carry
    if pow2 is not None:
        p = np.flatnonzero(pow2)
        D[p] = T.pow2_D.take(b[p])
        E[p] = T.pow2_E.take(b[p])
    bad = np.flatnonzero(unsure)
    for j, v in zip(bad.tolist(), np.abs(x[bad]).tolist()):
        D[j], E[j] = _parse(repr(v))
    return D, E, bad


def _resolve_exact(D17, f, q, r1, u15, u16, h, even):
    """dtoa's choice where every quantity is exact: a string exactly half an ulp away reads back when the
    significand is even (round half to even), and of two candidates equally near it takes the one with an
    even last digit.  (D, still unsure): a tie whose candidates are exactly half an ulp away is left to
    ``repr`` (dtoa keeps the lower one there)."""
    t15 = np.minimum(np.abs(u15), 100.0 - u15)
    t16 = np.minimum(np.abs(u16), 10.0 - u16)
    ok15 = (t15 < h) | ((t15 == h) & even)
    ok16 = (t16 < h) | ((t16 == h) & even)
    tie16 = u16 == 5.0
    q16 = (D17 - r1) // 10 + (u16 > 5.0)
    q16 += tie16 & (q16 % 2 == 1)  # of q16 and q16 + 1, the even one
    tie17 = np.abs(f) == 0.5
    D17 = D17 + (tie17 & (D17 % 2 == 1)) * np.sign(f).astype(np.int64)  # of D17 and D17 + 2f, the even one
    D = np.where(ok15, (q + (u15 > 50.0)) * 100, np.where(ok16, 10 * q16, D17))
    return D, tie16 & (t16 == h)


def float_cells(x: np.ndarray, out: np.ndarray | None = None) -> np.ndarray:
    """``repr`` of each finite double in ``x`` as a row of ASCII bytes (a uint8 matrix, a row per value), zero
    bytes where a text is shorter than the matrix is wide (they may fall inside a row: drop them all).

    ``out`` (optional): a uint8 matrix (a view too) of ``len(x)`` rows and at least :func:`cells_width` ``(x)``
    columns to write the cells into (the columns beyond the cells' width zeroed); it is returned.  (Into a band of
    a matrix of wide rows, a matrix of its own and one copy are faster: the cells are written in a few passes.)

    >>> c = float_cells(np.array([0.1, -2.5e-07, 1e16, 123.0]))
    >>> [bytes(row[row != 0]).decode() for row in c]
    ['0.1', '-2.5e-07', '1e+16', '123.0']
    """
    x = np.ascontiguousarray(x, dtype=np.float64)
    if not len(x):
        return np.zeros((0, 0), dtype=np.uint8) if out is None else out
    D, E, _ = _digits(x)
    return _layout(D, E, np.signbit(x), out)


def cells_width(x: np.ndarray, bounds: tuple[float, float] | None = None) -> int:
    """A width of :func:`float_cells` ``(x, out)``'s ``out`` that holds every cell of ``x`` (finite doubles): at least
    the width of the matrix :func:`float_cells` ``(x)`` makes, from the decimal exponents of the least and the
    greatest ``|x|`` (two reductions, no formatting).  ``bounds``: ``(x.min(), x.max())`` when the caller has them
    (then no pass over ``x`` at all unless its values have both signs).

    >>> cells_width(np.array([1.5, 2.25])), cells_width(np.array([0.001, -7.0])), cells_width(np.array([1e20]))
    (19, 22, 24)
    >>> cells_width(np.array([-3.0, -0.5]), (-3.0, -0.5))
    20
    """
    x = np.asarray(x, dtype=np.float64)
    if not len(x):
        return 0
    if bounds is not None and bounds[0] > 0.0:  # all positive: |x| has the same least and greatest
        lo, hi = float(bounds[0]), float(bounds[1])
    elif bounds is not None and bounds[1] < 0.0:  # all negative
        lo, hi = -float(bounds[1]), -float(bounds[0])
    else:
        a = np.abs(x)
        lo, hi = float(a.min()), float(a.max())
    zero = lo == 0.0
    if zero:
        if hi == 0.0:
            return _width(0)
        lo = float(a[a > 0.0].min())
    if lo < 2.2250738585072014e-308:  # a subnormal: scientific notation
        return WIDTH
    T = _tables()
    e_lo, e_hi = (int(T.K0[b]) + (v >= float(T.TK[b])) + EMIN
                  for v, b in ((lo, math.frexp(lo)[1] + 1022), (hi, math.frexp(hi)[1] + 1022)))
    if zero:  # zeros have exponent 0
        e_lo, e_hi = min(e_lo, 0), max(e_hi, 0)
    # the shortest text may round up to the next power of ten (1e+23 for 9.999999999999999e22): one more at the top
    if e_lo < -4 or e_hi + 1 > 15:
        return WIDTH
    return _width(e_lo)


def _layout(D, E, neg, dest=None) -> np.ndarray:
    """The text of (D, E, sign) as :func:`float_cells` writes it: values of one decimal exponent at a time
    (their decimal point is in one place), all of them at once when they share it, as most columns do.
    ``dest``: the matrix to write into (at least as wide as the cells; the rest zeroed), else a new one."""
    sign = neg.view(np.uint8) * np.uint8(45)  # "-" or nothing
    lo, hi = int(E.min()), int(E.max())
    if lo == hi or lo > 15 or hi < -4 or (lo < -4 and hi > 15 and not ((E >= -4) & (E <= 15)).any()):
        w = _width(lo)
        out = np.empty((len(D), w), dtype=np.uint8) if dest is None else _check_dest(dest, len(D), w)
        _cells(out[:, :w], D, E, lo, sign)
        if out.shape[1] > w:
            out[:, w:] = 0
        return out
    groups = []
    sci = (E < -4) | (E > 15)
    if lo < -4 or hi > 15:
        groups.append((np.flatnonzero(sci), 16))
    for e in range(max(lo, -4), min(hi, 15) + 1):
        rows = np.flatnonzero(E == e)
        if len(rows):
            groups.append((rows, e))
    w = max(_width(e) for _, e in groups)
    if dest is None:
        out = np.zeros((len(D), w), dtype=np.uint8)
    else:
        out = _check_dest(dest, len(D), w)
        out[:] = 0
    for rows, e in groups:
        block = np.empty((len(rows), _width(e)), dtype=np.uint8)
        _cells(block, D[rows], E[rows], e, sign[rows])
        out[rows, :block.shape[1]] = block
    return out


def _check_dest(dest, n: int, w: int):
    if dest.dtype != np.uint8 or dest.ndim != 2 or dest.shape[0] != n or dest.shape[1] < w:
        raise ValueError(f"float_cells: out must be a uint8 matrix of {n} rows and at least {w} columns, "
                         f"not {dest.dtype} {dest.shape}")
    return dest


def _width(e: int) -> int:
    """The width of the cells of values with decimal exponent ``e`` (16 for any of scientific notation)."""
    return 24 if e < -4 or e > 15 else 19 - min(e, 0)


def _cells(out, D, E, e: int, sign) -> None:
    """Write the cells of values with decimal exponent ``e`` into ``out`` (its width :func:`_width` (e)): positional
    ``-ddd.ddd`` / ``0.000ddd`` for ``-4 <= e <= 15``, else scientific ``-d.ddde-XX`` (``E`` then gives each
    value's exponent)."""
    T = _tables()
    positional = -4 <= e <= 15
    # digits 0..e+1 are written even if zero ("1000.0"); in scientific notation the first
    protect = e + 2 if positional and e >= 0 else 1
    hi = D // 100_000_000
    lo = (D - hi * 100_000_000).astype(np.uint32)
    hi = hi.astype(np.uint32)
    a = hi // 10000
    g0 = a // 10000  # the first digit, then four words of four digits
    words = [a - g0 * 10000, hi - a * 10000, lo // 10000]
    words.append(lo - words[2] * 10000)
    U = np.empty((len(D), 5), dtype=np.uint32)
    U[:, 0] = T.dig4.take(g0)  # "000d"
    tail = None  # whether every word after this one is zero: this one loses its trailing zeros
    for j in range(4, 0, -1):
        g = words[j - 1]
        table = T.words[min(4, max(0, protect - (4 * j - 3)))]
        U[:, j] = table.take(g + 10000 if tail is None else g + tail * np.uint32(10000))
        zero = g == 0
        tail = zero if tail is None else tail & zero
    G = U.view(np.uint8)[:, 3:]  # the 17 digits (zero bytes for trailing zeros)
    out[:, 0] = sign
    if positional and e >= 0:
        out[:, 1:e + 2] = G[:, :e + 1]
        out[:, e + 2] = 46  # "."
        out[:, e + 3:] = G[:, e + 1:]
    elif positional:
        lead = 1 - e  # "0." and -e-1 zeros
        out[:, 1:1 + lead] = np.frombuffer(b"0." + b"0" * (lead - 2), dtype=np.uint8)
        out[:, 1 + lead:] = G
    else:
        out[:, 1] = G[:, 0]
        out[:, 2] = (~tail).view(np.uint8) * np.uint8(46)  # "1e+16" has no "."
        out[:, 3:19] = G[:, 1:]
        out[:, 19:] = T.exp8.take(E + 400).view(np.uint8).reshape(len(D), 8)[:, :5]


def repr_floats(x) -> list[str]:
    """``[repr(v) for v in x]`` for finite doubles, vectorised.

    >>> repr_floats([0.1 + 0.2, -0.0, 1e-05, 1e16, 5e-324])
    ['0.30000000000000004', '-0.0', '1e-05', '1e+16', '5e-324']
    """
    x = np.asarray(x, dtype=np.float64).ravel()
    if not len(x):
        return []
    if not np.isfinite(x).all():
        raise ValueError("repr_floats: non-finite value")
    cells = float_cells(x)
    text = np.empty((len(x), cells.shape[1] + 1), dtype=np.uint8)
    text[:, :-1] = cells
    text[:, -1] = 10
    return text.tobytes().translate(None, b"\0").decode("ascii").split("\n")[:-1]


HARD = [0.1, 0.3, 0.1 + 0.2, 1e16, 9999999999999998.0, 1e15, 123456789012345680.0, 2.0 ** 53 + 2, 1e-05, 0.0001,
        0.00012, 1e22, 1e23, 5e-324, 2.2250738585072014e-308, 1.7976931348623157e308, 9.000015258789062,
        1.5, 38.57142857142857, 0.12080476003796083, -10.456694566187274, 2.5e-300, 1e300, 4.35, 2.675,
        123456.789, 1.0, -0.0, 0.0, 3.0e-8, 7.1e15, 1.2345678901234567e-7, 1974014630000000.2, 4.9e17,
        1974014630000000.25, 9.0000152587890625, 2.0 ** -1022, 2.0 ** -1000, 2.0 ** 60, 2.0 ** 1023]


def available() -> bool:
    """Whether :func:`float_cells` agrees with ``repr`` here (checked once, on hard cases and their neighbours:
    the arithmetic assumes IEEE doubles rounded to nearest)."""
    global _OK
    if _OK is None:
        try:
            xs = np.array(HARD + [math.nextafter(v, d) for v in HARD for d in (math.inf, -math.inf)])
            xs = xs[np.isfinite(xs)]
            xs = np.concatenate([xs, -xs])
            _OK = repr_floats(xs) == [repr(v) for v in xs.tolist()]
        except Exception:  # noqa: BLE001 - any failure means: keep repr
            _OK = False
    return _OK
