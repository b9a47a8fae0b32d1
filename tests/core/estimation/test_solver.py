"""Property tests of the column-scaled, pivoted Householder least-squares solver."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from jointid.estimation.solver import RANK_TOLERANCE, solve_least_squares

seeds = st.integers(0, 2**32 - 1)
column_counts = st.integers(1, 6)
# Column magnitudes from 1e-8 to 1e8, as the issue asks.
exponents = st.lists(st.floats(-8, 8), min_size=6, max_size=6)
dependent_column_problems = dict(
    seed=seeds,
    columns=st.integers(2, 6),
    extra_rows=st.integers(2, 40),
    column_exponents=exponents,
    kind=st.sampled_from(["zero", "duplicate", "proportional"]),
    factor_exponent=st.floats(-6, 6),
    data=st.data(),
)
"""The strategies of a problem with one dependent column (see `make_one_column_dependent`)."""


def random_problem(seed, rows, columns, column_exponents):
    """A well-conditioned random X whose columns have wildly different units, and a y."""
    rng = np.random.default_rng(seed)
    X = rng.normal(size=(rows, columns)) * 10.0 ** np.asarray(column_exponents[:columns])
    return X, rng.normal(size=rows)


def reference_solution(X, y):
    """numpy's SVD least squares on the unit-norm-column matrix, mapped back to X's units.

    lstsq's default cutoff would discard a 1e-8 column next to a 1e8 one as rank
    deficient, so the reference solves the same column-scaled problem our solver does.
    """
    norms = np.linalg.norm(X, axis=0)
    scaled, _, rank, _ = np.linalg.lstsq(X / norms, y, rcond=None)
    return scaled / norms, rank


def make_one_column_dependent(X, data, kind, factor_exponent):
    """Make one drawn column of X zero, a copy of another, or -10**factor_exponent times another, in place."""
    columns = X.shape[1]
    source = data.draw(st.integers(0, columns - 1), label="source column")
    target = data.draw(st.integers(0, columns - 1).filter(lambda j: j != source), label="target column")
    if kind == "zero":
        X[:, target] = 0.0
    elif kind == "duplicate":
        X[:, target] = X[:, source]
    else:
        X[:, target] = -(10.0**factor_exponent) * X[:, source]


@settings(max_examples=150, deadline=None)
@given(seed=seeds, columns=column_counts, extra_rows=st.integers(2, 60), column_exponents=exponents)
def test_full_rank_problems_agree_with_numpy_lstsq(seed, columns, extra_rows, column_exponents):
    X, y = random_problem(seed, columns + extra_rows, columns, column_exponents)
    solution = solve_least_squares(X, y)
    expected, expected_rank = reference_solution(X, y)
    assert expected_rank == columns
    assert solution.rank == columns
    norms = np.linalg.norm(X, axis=0)
    # Compare in unit-column coordinates so every component is judged on the same footing.
    np.testing.assert_allclose(solution.estimate * norms, expected * norms, rtol=1e-9, atol=1e-9)
    residual = np.linalg.norm(X @ expected - y)
    assert solution.residual_norm == pytest.approx(residual, rel=1e-9, abs=1e-12)


@settings(max_examples=150, deadline=None)
@given(**dependent_column_problems)
def test_dependent_columns_lower_the_rank_and_give_no_estimate(
    seed, columns, extra_rows, column_exponents, kind, factor_exponent, data
):
    X, y = random_problem(seed, columns + extra_rows, columns, column_exponents)
    make_one_column_dependent(X, data, kind, factor_exponent)
    solution = solve_least_squares(X, y)
    assert solution.rank == columns - 1
    assert solution.estimate is None


@settings(max_examples=100, deadline=None)
@given(seed=seeds, columns=column_counts, column_exponents=exponents, data=st.data())
def test_fewer_rows_than_columns_give_rank_rows_and_no_estimate(seed, columns, column_exponents, data):
    rows = data.draw(st.integers(0, columns - 1), label="rows")
    X, y = random_problem(seed, rows, columns, column_exponents)
    solution = solve_least_squares(X, y)
    assert solution.rank == rows
    assert solution.estimate is None


@settings(max_examples=100, deadline=None)
@given(seed=seeds, columns=column_counts, extra_rows=st.integers(2, 30), column_exponents=exponents, data=st.data())
def test_permuting_columns_permutes_the_estimate(seed, columns, extra_rows, column_exponents, data):
    X, y = random_problem(seed, columns + extra_rows, columns, column_exponents)
    order = np.array(data.draw(st.permutations(range(columns)), label="order"))
    original = solve_least_squares(X, y).estimate
    permuted = solve_least_squares(X[:, order], y).estimate
    norms = np.linalg.norm(X, axis=0)[order]
    np.testing.assert_allclose(permuted * norms, original[order] * norms, rtol=1e-10, atol=1e-10)


def test_zero_columns_give_an_empty_unique_estimate():
    solution = solve_least_squares(np.zeros((5, 0)), np.arange(5.0))
    assert solution.rank == 0
    assert solution.estimate.shape == (0,)
    assert solution.residual_norm == pytest.approx(np.linalg.norm(np.arange(5.0)))


def test_inputs_are_not_modified():
    X, y = random_problem(3, 10, 3, [0, 4, -4])
    X_before, y_before = X.copy(), y.copy()
    solve_least_squares(X, y)
    assert np.array_equal(X, X_before) and np.array_equal(y, y_before)


def test_rank_threshold_is_the_remaining_scaled_column_norm():
    # Two unit columns at angle epsilon: the second's remaining norm is sin(epsilon).
    for angle, expected_rank in [(1e-9, 2), (1e-11, 1)]:
        X = np.array([[1.0, np.cos(angle)], [0.0, np.sin(angle)], [0.0, 0.0]])
        assert solve_least_squares(X, np.ones(3)).rank == expected_rank
    assert RANK_TOLERANCE == 1e-10


def test_millions_of_rows_fit_in_linear_memory():
    rng = np.random.default_rng(5)
    rows = 2_000_000
    X = rng.normal(size=(rows, 3)) * [1.0, 9.81, 0.5]
    theta = np.array([0.8, 0.4, 0.15])
    y = X @ theta + 0.01 * rng.normal(size=rows)
    solution = solve_least_squares(X, y)
    expected, _ = reference_solution(X, y)
    np.testing.assert_allclose(solution.estimate, expected, rtol=1e-9)


def test_mismatched_shapes_are_refused():
    with pytest.raises(ValueError):
        solve_least_squares(np.zeros((4, 2)), np.zeros(3))
