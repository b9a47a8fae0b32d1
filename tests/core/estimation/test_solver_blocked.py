"""The blocked least-squares path against a copy of the previous solver, numpy's lstsq and itself.

`todays_solve` below is the solver as it was before the row-block reduction (column
scaling, pivoted Householder QR in numpy on the whole X). Small problems reach the
blocked path through an explicit `block_rows`. Estimates are compared in unit-column
coordinates, relative to the larger of the scaled estimate and y: that is the scale on
which a least-squares solution is determined (when y is nearly orthogonal to X's
columns, the estimate is tiny and its own relative error means nothing).
"""

import tracemalloc

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from test_solver import (
    dependent_column_problems,
    exponents,
    make_one_column_dependent,
    random_problem,
    reference_solution,
    seeds,
)

from jointid.estimation import solver
from jointid.estimation.solver import (
    BLOCK_VALUES,
    DIRECT_ROWS,
    RANK_TOLERANCE,
    LeastSquaresSolution,
    NonFiniteError,
    block_rows_for,
    solve_least_squares,
)
from jointid.studies.experiment import run_experiment
from jointid.studies.sweep import run_sweep
from jointid.synthetic.settings import Settings

AGREEMENT = 1e-12
"""Largest scaled difference allowed between the blocked path and the previous solver."""


def todays_solve(X, y, tolerance=RANK_TOLERANCE):
    """The previous solver, verbatim but for layout: scale, then pivoted Householder on the whole X."""
    X = np.asarray(X, dtype=float)
    y = np.asarray(y, dtype=float)
    rows, columns = X.shape
    norms = np.sqrt(np.einsum("ij,ij->j", X, X))
    scales = np.where(norms > 0, norms, 1.0)
    work = np.empty((rows, columns), order="F")
    np.divide(X, scales, out=work)
    targets = np.array(y.T if y.ndim == 2 else y[None, :], order="C")
    permutation = np.arange(columns)
    rank = 0
    for k in range(min(rows, columns)):
        trailing = work[k:, k:]
        remaining = np.sqrt(np.einsum("ij,ij->j", trailing, trailing))
        pivot = k + int(np.argmax(remaining))
        if remaining[pivot - k] <= tolerance:
            break
        if pivot != k:
            work[:, [k, pivot]] = work[:, [pivot, k]]
            permutation[[k, pivot]] = permutation[[pivot, k]]
        head = work[k, k]
        alpha = -remaining[pivot - k] if head >= 0 else remaining[pivot - k]
        v = work[k:, k].copy()
        v[0] -= alpha
        v /= np.linalg.norm(v)
        for j in range(k + 1, columns):
            column = work[k:, j]
            column -= (2.0 * (v @ column)) * v
        tails = targets[:, k:]
        tails -= (2.0 * (tails * v).sum(axis=1))[:, None] * v
        work[k:, k] = 0.0
        work[k, k] = alpha
        rank += 1
    residual_norms = np.sqrt(np.square(targets[:, rank:]).sum(axis=1))
    qty = np.array(targets[:, :rank].T, order="C")
    return LeastSquaresSolution(
        rank=rank,
        column_count=columns,
        row_count=rows,
        scales=scales,
        permutation=permutation,
        r_factor=np.triu(work[:rank, :]),
        qty=qty if y.ndim == 2 else qty[:, 0],
        residual_norm=residual_norms if y.ndim == 2 else float(residual_norms[0]),
    )


def scaled_difference(theta, reference, X, y):
    """Largest difference of two estimates in unit-column coordinates, relative to max(|scaled reference|, |y|)."""
    norms = np.linalg.norm(X, axis=0)
    size = max(np.linalg.norm(reference * norms), np.linalg.norm(y))
    return float(np.max(np.abs((theta - reference) * norms), initial=0.0) / size)


def assert_same_fit(blocked, today, X, y):
    """Same rank, same estimate (or none), same residual and same fitted values within AGREEMENT."""
    assert blocked.rank == today.rank
    assert (blocked.estimate is None) == (today.estimate is None)
    if today.estimate is not None:
        assert scaled_difference(blocked.estimate, today.estimate, X, y) <= AGREEMENT
    size = np.linalg.norm(y)
    assert abs(blocked.residual_norm - today.residual_norm) <= AGREEMENT * size
    # The fitted values (the projection of y) are unique even where the estimate is not.
    fitted = np.linalg.norm(X @ blocked.basic_estimate - X @ today.basic_estimate)
    assert fitted <= AGREEMENT * size


def draw_block_rows(data, rows):
    """A block size smaller than `rows`, so that the problem goes through the reduction."""
    return data.draw(st.integers(1, max(1, rows - 1)), label="block rows")


@settings(max_examples=200, deadline=None)
@given(seed=seeds, columns=st.integers(1, 6), extra_rows=st.integers(2, 60), column_exponents=exponents,
       fitted=st.booleans(), data=st.data())
def test_blocked_full_rank_agrees_with_todays_solver_and_lstsq(seed, columns, extra_rows, column_exponents,
                                                             fitted, data):
    X, y = random_problem(seed, columns + extra_rows, columns, column_exponents)
    block_rows = draw_block_rows(data, len(X))
    if fitted:  # y mostly explained by X, as in a real identification
        y = X @ (1.0 / np.linalg.norm(X, axis=0)) + 1e-3 * y
    blocked = solve_least_squares(X, y, block_rows=block_rows)
    today = todays_solve(X, y)
    assert blocked.rank == today.rank == columns
    assert_same_fit(blocked, today, X, y)
    expected, _ = reference_solution(X, y)
    assert scaled_difference(blocked.estimate, expected, X, y) <= 1e-9


@settings(max_examples=200, deadline=None)
@given(**dependent_column_problems)
def test_blocked_dependent_columns_give_todays_rank_and_fit(
    seed, columns, extra_rows, column_exponents, kind, factor_exponent, data
):
    X, y = random_problem(seed, columns + extra_rows, columns, column_exponents)
    block_rows = draw_block_rows(data, len(X))
    make_one_column_dependent(X, data, kind, factor_exponent)
    blocked = solve_least_squares(X, y, block_rows=block_rows)
    assert blocked.rank == columns - 1
    assert_same_fit(blocked, todays_solve(X, y), X, y)


@settings(max_examples=100, deadline=None)
@given(seed=seeds, columns=st.integers(3, 6), column_exponents=exponents, data=st.data())
def test_blocked_fewer_rows_than_columns_give_todays_rank(seed, columns, column_exponents, data):
    rows = data.draw(st.integers(2, columns - 1), label="rows")
    X, y = random_problem(seed, rows, columns, column_exponents)
    block_rows = draw_block_rows(data, rows)
    blocked = solve_least_squares(X, y, block_rows=block_rows)
    assert blocked.rank == todays_solve(X, y).rank == min(rows, columns)
    assert_same_fit(blocked, todays_solve(X, y), X, y)


@settings(max_examples=100, deadline=None)
@given(seed=seeds, columns=st.integers(0, 6), extra_rows=st.integers(0, 60), column_exponents=exponents,
       count=st.integers(1, 5))
def test_small_problems_take_todays_path_bit_for_bit(seed, columns, extra_rows, column_exponents, count):
    X, _ = random_problem(seed, columns + extra_rows, columns, column_exponents)
    Y = np.random.default_rng(seed).normal(size=(len(X), count))
    for y in (Y[:, 0], Y):
        new, old = solve_least_squares(X, y), todays_solve(X, y)
        assert new.rank == old.rank
        for field in ("scales", "permutation", "r_factor", "qty", "residual_norm", "basic_estimate"):
            np.testing.assert_array_equal(getattr(new, field), getattr(old, field))


@settings(max_examples=100, deadline=None)
@given(seed=seeds, columns=st.integers(1, 6), extra_rows=st.integers(1, 60), column_exponents=exponents,
       count=st.integers(2, 6), deficient=st.booleans(), data=st.data())
def test_blocked_many_right_hand_sides_equal_single_solves_bit_for_bit(
    seed, columns, extra_rows, column_exponents, count, deficient, data
):
    X, _ = random_problem(seed, columns + extra_rows, columns, column_exponents)
    block_rows = draw_block_rows(data, len(X))
    if deficient:
        X[:, 0] = 0.0
    Y = np.random.default_rng(seed).normal(size=(len(X), count))
    many = solve_least_squares(X, Y, block_rows=block_rows)
    for k in range(count):
        one = solve_least_squares(X, Y[:, k], block_rows=block_rows)
        assert one.rank == many.rank
        np.testing.assert_array_equal(many.qty[:, k], one.qty)
        np.testing.assert_array_equal(many.basic_estimate[:, k], one.basic_estimate)
        assert many.residual_norm[k] == one.residual_norm


@pytest.mark.skipif(solver._lapack_qr_in_place is None, reason="this numpy has no importable qr gufunc")
@settings(max_examples=60, deadline=None)
@given(seed=seeds, columns=st.integers(1, 6), extra_rows=st.integers(1, 60), column_exponents=exponents,
       count=st.integers(0, 3), deficient=st.booleans(), data=st.data())
def test_factoring_in_place_gives_numpy_qrs_bits(seed, columns, extra_rows, column_exponents, count, deficient,
                                                  data):
    """The reduction factors its blocks with numpy's gufunc where they lie; through numpy.linalg.qr (the
    fallback for a numpy without that gufunc) every number is the same."""
    X, _ = random_problem(seed, columns + extra_rows, columns, column_exponents)
    block_rows = draw_block_rows(data, len(X))
    if deficient:
        X[:, 0] = 0.0
    Y = np.random.default_rng(seed).normal(size=(len(X), count)) if count else X[:, 0] + 1.0
    in_place = solve_least_squares(X, Y, block_rows=block_rows)
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(solver, "_lapack_qr_in_place", None)
        through_numpy = solve_least_squares(X, Y, block_rows=block_rows)
    assert in_place.rank == through_numpy.rank
    for name in ("r_factor", "qty", "residual_norm", "scales", "permutation"):
        np.testing.assert_array_equal(getattr(in_place, name), getattr(through_numpy, name))


def test_zero_columns_on_the_blocked_path():
    y = np.arange(9.0)
    solution = solve_least_squares(np.zeros((9, 0)), y, block_rows=2)
    assert solution.rank == 0 and solution.estimate.shape == (0,)
    assert solution.residual_norm == pytest.approx(np.linalg.norm(y))
    no_targets = solve_least_squares(np.eye(9, 3), np.zeros((9, 0)), block_rows=2)
    assert no_targets.rank == 3 and no_targets.qty.shape == (3, 0) and no_targets.residual_norm.shape == (0,)


def test_above_direct_rows_the_default_path_agrees_and_keeps_bit_identity():
    rng = np.random.default_rng(8)
    rows = 3 * DIRECT_ROWS + 17
    X = rng.normal(size=(rows, 4)) * [1e-3, 1.0, 1e3, 2.0]
    X[:, 3] += X[:, 1]  # correlated, not dependent
    Y = X @ rng.normal(size=(4, 6)) + 0.1 * rng.normal(size=(rows, 6))
    many = solve_least_squares(X, Y)
    for k in range(6):
        one = solve_least_squares(X, Y[:, k])
        np.testing.assert_array_equal(many.estimate[:, k], one.estimate)
        assert many.residual_norm[k] == one.residual_norm
        assert_same_fit(one, todays_solve(X, Y[:, k]), X, Y[:, k])


def test_sweep_above_direct_rows_equals_a_per_seed_loop_exactly():
    settings = Settings(motion="rich", noise=0.2, samples=DIRECT_ROWS + 500, seed=40)
    sweep = run_sweep(settings, 12, chunk_size=5)
    for k, seed in enumerate(range(40, 52)):
        single = run_experiment(Settings(settings.motion, settings.noise, settings.samples, seed))
        np.testing.assert_array_equal(sweep.estimates[:, k], single.estimate)
        assert sweep.training_rmse[k] == single.training_rmse


@pytest.mark.parametrize("block_rows", [None, 7])
def test_huge_and_tiny_columns_keep_their_rank(block_rows):
    # Squares of 1e200 overflow and of 1e-200 underflow: the previous solver found rank 0 here.
    rng = np.random.default_rng(2)
    unit = rng.normal(size=(100, 3))
    y = unit @ [1.0, -2.0, 0.5] + 0.1 * rng.normal(size=100)
    magnitudes = np.array([1e200, 1e-200, 1.0])
    solution = solve_least_squares(unit * magnitudes, y, block_rows=block_rows)
    expected = todays_solve(unit, y).estimate / magnitudes
    assert solution.rank == 3
    np.testing.assert_allclose(solution.estimate * magnitudes, expected * magnitudes, rtol=1e-12)
    np.testing.assert_allclose(solution.scales / magnitudes, np.linalg.norm(unit, axis=0), rtol=1e-12)


@pytest.mark.parametrize("block_rows", [1, 2])
def test_rank_threshold_is_the_same_on_the_blocked_path(block_rows):
    for angle, expected_rank in [(1e-9, 2), (1e-11, 1)]:
        X = np.array([[1.0, np.cos(angle)], [0.0, np.sin(angle)], [0.0, 0.0]])
        assert solve_least_squares(X, np.ones(3), block_rows=block_rows).rank == expected_rank


def test_memory_order_changes_no_bit_and_inputs_stay_unchanged():
    X, y = random_problem(4, 5000, 5, [3, -2, 0, 7, -7])
    XF = np.asfortranarray(X)
    before = X.copy(), y.copy()
    c_order = solve_least_squares(X, y, block_rows=300)
    f_order = solve_least_squares(XF, y, block_rows=300)
    np.testing.assert_array_equal(c_order.estimate, f_order.estimate)
    assert c_order.residual_norm == f_order.residual_norm
    assert np.array_equal(X, before[0]) and np.array_equal(XF, before[0]) and np.array_equal(y, before[1])


def test_blocked_path_needs_little_memory():
    rng = np.random.default_rng(6)
    X = rng.normal(size=(1_000_000, 3))
    y = X @ [0.8, 0.4, 0.15] + 0.1 * rng.normal(size=len(X))
    tracemalloc.start()
    solution = solve_least_squares(X, y)
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    assert solution.rank == 3
    assert peak <= 0.1 * X.nbytes  # about 0.04 (one group of blocks); the previous solver copied X: 2.0


@pytest.mark.parametrize("block_rows", [None, 5])
@pytest.mark.parametrize("bad", [np.nan, np.inf])
def test_non_finite_data_are_refused_on_both_paths(block_rows, bad):
    X, y = random_problem(1, 40, 3, [0, 0, 0])
    X[17, 1] = bad
    with pytest.raises(NonFiniteError, match="not finite"):
        solve_least_squares(X, y, block_rows=block_rows)


def test_block_rows_must_be_positive():
    with pytest.raises(ValueError):
        solve_least_squares(np.ones((4, 1)), np.ones(4), block_rows=0)


def test_blocks_stay_below_openblas_thread_thresholds():
    for columns in range(1, 90):
        assert block_rows_for(columns) * columns <= BLOCK_VALUES
    assert block_rows_for(3) > 2000 and block_rows_for(6) > 1000
