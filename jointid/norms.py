"""Euclidean norms and root mean squares that neither overflow nor underflow for finite data.

Squaring a value beyond about 1.3e154 overflows to infinity, and squares below
about 1e-154 lose digits (below 1e-162, all of them): a column of such values
would look infinite, or missing. Where a plain sum of squares leaves the safe
range, its values are divided by a power of two near their largest magnitude
and the sum is taken again. Dividing by a power of two is exact in binary
floating point, so the rescaled result is what the plain formula would give
with unlimited exponent range; data whose sums are in range take the plain
formula itself, so their results are bit for bit what they always were.

Each function keeps its caller's formula (einsum or square-and-sum, sum or
mean): summation order decides the last bits, and results elsewhere are
checked bit for bit against each other.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

_SAFE_SUMS = (2.0**-900, np.finfo(float).max)
"""Sums of squares trusted as computed: finite, and far above where any square's lost digits could matter."""


def power_of_two_scale(largest) -> np.ndarray:
    """2**e with 2**(e-1) <= largest < 2**e, elementwise; 1 where largest is 0 or not finite."""
    largest = np.asarray(largest, dtype=float)
    usable = np.isfinite(largest) & (largest > 0)
    exponent = np.frexp(np.where(usable, largest, 1.0))[1]
    return np.where(usable, np.ldexp(1.0, exponent), 1.0)


def _rescaled_sums(values: np.ndarray, axis: int, sums_of_squares: Callable[[np.ndarray], np.ndarray]):
    """(sums, scales): sums_of_squares(values) along `axis`, recomputed on values/scale where out of range.

    The true sum of squares is sums * scales**2.
    """
    with np.errstate(over="ignore", under="ignore"):
        sums = np.asarray(sums_of_squares(values), dtype=float)
    low, high = _SAFE_SUMS
    suspect = ~((sums >= low) & (sums <= high))  # also all-zero vectors: they cost one more pass
    if values.size == 0 or not suspect.any():
        return sums, np.ones(sums.shape)
    scales = np.where(suspect, power_of_two_scale(np.max(np.abs(values), axis=axis)), 1.0)
    with np.errstate(under="ignore"):
        rescaled = np.asarray(sums_of_squares(values / np.expand_dims(scales, axis)), dtype=float)
    return np.where(suspect, rescaled, sums), scales


def column_norms(X: np.ndarray) -> np.ndarray:
    """(p,) Euclidean norm of each column of X (N, p)."""
    sums, scales = _rescaled_sums(X, 0, lambda a: np.einsum("ij,ij->j", a, a))
    return np.sqrt(sums) * scales


def row_norms(rows: np.ndarray) -> np.ndarray:
    """(K,) Euclidean norm of each row of a (K, N) array."""
    sums, scales = _rescaled_sums(rows, 1, lambda a: np.square(a).sum(axis=1))
    return np.sqrt(sums) * scales


def rms(values: np.ndarray) -> float:
    """Root mean square of a 1-D array (0 for an empty one)."""
    values = np.asarray(values, dtype=float)
    if not len(values):
        return 0.0
    mean, scale = _rescaled_sums(values, 0, lambda a: np.mean(np.square(a)))
    return float(np.sqrt(mean) * scale)


def row_rms(rows: np.ndarray) -> np.ndarray:
    """(K,) Root mean square of each row of a (K, M) array, each row as `rms` computes it alone."""
    means, scales = _rescaled_sums(rows, 1, lambda a: np.mean(np.square(a), axis=1))
    return np.sqrt(means) * scales


def all_finite(values: np.ndarray) -> bool:
    """True when every value of a 1-D float array is finite, as np.isfinite(values).all().

    One sum of the values: a NaN or an infinity makes it NaN or infinite, with no
    temporary and in numpy's own loop (BLAS's dot, tried before, woke OpenBLAS's
    threads and took 8-18 ms on a million values, the sum 2 ms). Only when it is
    not finite, which values beyond about 1e302 also make it by overflowing, are
    the values tested one by one.
    """
    with np.errstate(over="ignore", invalid="ignore"):
        if math.isfinite(np.add.reduce(values)):
            return True
    return bool(np.isfinite(values).all())
