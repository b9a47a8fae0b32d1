"""The robust step's concentration-step machinery against plain numpy: the trimmed sets, their sums and refits.

References: np.partition / np.sort for the keep smallest squares of each row,
np.linalg.lstsq for the least-squares refits and the bisquare's weighted fits.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from jointid.estimation import exclusion
from jointid.estimation.exclusion import _concentrated, _corrected, _smallest


def reference_smallest(squares: np.ndarray, keep: int) -> tuple[np.ndarray, np.ndarray]:
    """((K,) sums of the keep smallest, (K,) the keep-th smallest) of each row, by sorting."""
    ordered = np.sort(squares, axis=1)
    return ordered[:, :keep].sum(axis=1), ordered[:, keep - 1]


@pytest.mark.parametrize("rows", [1, 3, 10, 11, 200])
def test_smallest_picks_the_keep_smallest_of_every_row(rows):
    rng = np.random.default_rng(rows)
    squares = rng.standard_t(3, (rows, 1500)) ** 2 * 10.0 ** rng.uniform(-30, 30, (rows, 1))
    keep = 750
    values, chosen, kth, _ = _smallest(squares, keep, np.full(rows, math.nan), np.empty_like(squares))
    sums, kths = reference_smallest(squares, keep)
    following = np.sort(squares, axis=1)[:, keep]
    assert ((kth >= kths) & (kth < following)).all()  # the keep-th itself, or a threshold below the next
    assert np.array_equal(chosen, squares <= kths[:, None])
    assert np.allclose(values, sums, rtol=1e-13, atol=0)


def test_smallest_with_ties_near_float32_roundings_zeros_and_huge_values():
    rng = np.random.default_rng(5)
    squares = rng.uniform(1, 2, (40, 101))
    squares[0] = 1.0  # every value tied
    squares[1, :60] = np.nextafter(1.5, 2.0) * (1 + np.arange(60) * 1e-16)  # many in one float32 rounding
    squares[2] = 0.0
    squares[3, ::2] = 1e300  # beyond float32's range
    squares[4, :50] = 1e-320  # subnormal, rounds to float32 zero
    squares[5, 7] = math.nan
    keep = 51
    values, chosen, _, _ = _smallest(squares, keep, np.full(len(squares), math.nan), np.empty_like(squares))
    assert (chosen.sum(axis=1) == keep).all()
    finite = np.isfinite(squares).all(axis=1)
    sums, kths = reference_smallest(squares[finite], keep)
    assert np.allclose(values[finite], sums, rtol=1e-13, atol=0)
    # The chosen are the keep smallest: none left out is below the largest chosen.
    for row, picked in zip(squares[finite], chosen[finite]):
        assert not (row[~picked] < row[picked].max()).any()


@pytest.mark.parametrize("direct", [False, True])
def test_smallest_where_the_model_fits_exactly(direct):
    rng = np.random.default_rng(2)
    squares = (rng.integers(0, 4, (30, 1500)) * np.finfo(float).eps) ** 2  # an exact fit's residuals: ties
    keep = 750
    values, chosen, kth, unsure = _smallest(squares, keep, np.full(30, math.nan), np.empty_like(squares), direct)
    sums, kths = reference_smallest(squares, keep)
    assert unsure > 15  # most thresholds fail on ties
    assert (chosen.sum(axis=1) == keep).all()
    assert (kth >= kths).all()
    assert np.allclose(values, sums, rtol=1e-13, atol=0)
    for row, picked in zip(squares, chosen):
        assert not (row[~picked] < row[picked].max()).any()


def test_smallest_from_a_guess_matches_a_partition():
    rng = np.random.default_rng(9)
    squares = rng.exponential(1.0, (4, 20000))
    keep = 10000
    _, _, exact, _ = _smallest(squares, keep, np.full(4, math.nan), np.empty_like(squares))
    guesses = exact * np.array([1.0, 1.01, 0.7, 1.3])  # near, and too far for the band
    values, chosen, kth, _ = _smallest(squares, keep, guesses, np.empty_like(squares))
    sums, kths = reference_smallest(squares, keep)
    assert np.array_equal(kth, kths)
    assert (chosen.sum(axis=1) == keep).all()
    assert np.allclose(values, sums, rtol=1e-13, atol=0)


@pytest.mark.parametrize("rows", [1500, 40000])
def test_concentration_steps_refit_each_trimmed_set_by_least_squares(rows):
    rng = np.random.default_rng(rows)
    X = np.column_stack([np.ones(rows), rng.uniform(-1, 1, (rows, 4))])
    y = X @ np.array([0.3, 1.0, -0.5, 0.2, 0.8]) + rng.standard_t(2, rows) * 0.05
    starts = np.array([np.linalg.lstsq(X[rows_], y[rows_], rcond=None)[0]
                       for rows_ in (rng.choice(rows, 5, replace=False) for _ in range(3))])
    keep = max(X.shape[1] + 1, int(exclusion.COVERAGE * rows))
    values, thetas = _concentrated(X, y, starts, 1)
    for start, theta, value in zip(starts, thetas, values):
        chosen = np.argsort((y - X @ start) ** 2, kind="stable")[:keep]
        expected = np.linalg.lstsq(X[chosen], y[chosen], rcond=None)[0]
        assert np.allclose(theta, expected, rtol=1e-9, atol=1e-12)
        assert value == pytest.approx(np.sort((y - X @ theta) ** 2)[:keep].sum(), rel=1e-12)


def test_corrected_is_the_weighted_least_squares_fit_and_falls_back_when_ill_conditioned():
    rng = np.random.default_rng(3)
    X = rng.normal(size=(5000, 5))
    y = X @ np.arange(1.0, 6.0) + rng.normal(size=5000)
    weights = rng.uniform(0, 1, 5000)
    root = np.sqrt(weights)
    expected = np.linalg.lstsq(X * root[:, None], y * root, rcond=None)[0]
    assert np.allclose(_corrected(X, y, np.zeros(5), weights), expected, rtol=1e-10)
    collinear = X.copy()
    collinear[:, 4] = collinear[:, 3] * (1 + 1e-9)  # a Gram matrix beyond GRAM_CONDITION
    expected = np.linalg.lstsq(collinear, y, rcond=None)[0]
    assert np.allclose(_corrected(collinear, y, np.zeros(5)), expected, rtol=1e-6)
