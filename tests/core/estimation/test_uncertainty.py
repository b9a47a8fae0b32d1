"""Per-parameter uncertainty: standard errors from R, expected ones from the noise bound, verdicts."""

import numpy as np
import pytest
from hypothesis import given
from hypothesis import settings as hypothesis_settings
from hypothesis import strategies as st

from jointid.estimation.solver import solve_least_squares
from jointid.estimation.uncertainty import (
    NOT_DETERMINED,
    WEAK,
    WELL_DETERMINED,
    covariance_factor,
    parameter_uncertainty,
    verdict,
)
from jointid.present.status import fit_warnings, status_message
from jointid.studies.experiment import run_experiment
from jointid.synthetic.settings import Settings

LAB_SENTENCE = "Positive parameter signs alone do not establish an accurate physical model."


def closed_form(X, y, bound):
    """Standard errors the textbook way, with an explicit inverse of X^T X (tests only)."""
    inverse = np.linalg.inv(X.T @ X)
    theta = inverse @ X.T @ y
    rss = float(np.sum((y - X @ theta) ** 2))
    dof = X.shape[0] - X.shape[1]
    return inverse, np.sqrt(rss / dof * np.diag(inverse)), np.sqrt(bound**2 / 3 * np.diag(inverse))


@hypothesis_settings(max_examples=100, deadline=None)
@given(
    seed=st.integers(0, 2**32 - 1),
    columns=st.integers(1, 4),
    extra_rows=st.integers(1, 12),
    exponents=st.lists(st.floats(-3, 3), min_size=4, max_size=4),
)
def test_standard_errors_match_the_explicit_inverse_on_small_problems(seed, columns, extra_rows, exponents):
    rng = np.random.default_rng(seed)
    # Different column magnitudes make the pivot order differ from the column order.
    X = rng.normal(size=(columns + extra_rows, columns)) * 10.0 ** np.asarray(exponents[:columns])
    y = rng.normal(size=columns + extra_rows)
    inverse, std_error, expected = closed_form(X, y, 0.3)
    uncertainty = parameter_uncertainty(solve_least_squares(X, y), noise_bound=0.3)
    scale = np.sqrt(np.outer(np.diag(inverse), np.diag(inverse)))
    np.testing.assert_allclose(uncertainty.covariance_factor / scale, inverse / scale, atol=1e-9)
    np.testing.assert_allclose(uncertainty.residual_std_error, std_error, rtol=1e-8)
    np.testing.assert_allclose(uncertainty.noise_bound_std_error, expected, rtol=1e-8)


def test_covariance_factor_undoes_pivoting_and_scaling_on_a_hand_problem():
    # Columns e1, 10 (e1 + e2), 100 (e1 + e2 + e3): after e1 the third column keeps
    # more of its norm than the second, so pivoting swaps them. X is upper
    # triangular with inverse [[1, -1, 0], [0, 0.1, -0.1], [0, 0, 0.01]] (rows 1..3).
    X = np.array([[1.0, 10.0, 100.0], [0.0, 10.0, 100.0], [0.0, 0.0, 100.0], [0.0, 0.0, 0.0]])
    solution = solve_least_squares(X, np.ones(4))
    assert solution.permutation.tolist() == [0, 2, 1]
    x_inverse = np.array([[1.0, -1.0, 0.0], [0.0, 0.1, -0.1], [0.0, 0.0, 0.01]])
    np.testing.assert_allclose(covariance_factor(solution), x_inverse @ x_inverse.T, rtol=1e-12, atol=1e-15)


@pytest.mark.parametrize(
    "motion, expected",
    [("rich", (0.016950, 0.002777, 0.029016)), ("slow", (5.425077, 0.004864, 1.013808))],
)
def test_expected_standard_errors_at_noise_020_to_six_decimals(motion, expected):
    result = run_experiment(Settings(motion=motion, noise=0.2))
    assert tuple(round(float(v), 6) for v in result.uncertainty.noise_bound_std_error) == expected


def test_slow_motion_inertia_and_damping_are_not_determined():
    uncertainty = run_experiment(Settings(motion="slow", noise=0.2)).uncertainty
    assert uncertainty.verdict_basis == "expected"
    assert uncertainty.verdicts == (NOT_DETERMINED, WELL_DETERMINED, NOT_DETERMINED)
    # |I| = 1.607788 with expected error 5.425077: 337 %.
    assert uncertainty.relative_std_pct[0] == pytest.approx(100 * 5.425077 / 1.607788, rel=1e-5)


def test_rich_motion_damping_is_weak_at_noise_020():
    uncertainty = run_experiment(Settings(motion="rich", noise=0.2)).uncertainty
    assert uncertainty.verdicts == (WELL_DETERMINED, WELL_DETERMINED, WEAK)


@pytest.mark.parametrize(
    "relative, expected",
    [(0.0, WELL_DETERMINED), (10.0, WELL_DETERMINED), (10.0001, WEAK), (30.0, WEAK), (30.0001, NOT_DETERMINED),
     (float("inf"), NOT_DETERMINED)],
)
def test_verdict_limits(relative, expected):
    assert verdict(relative) == expected


def test_verdicts_use_empirical_errors_without_a_noise_bound():
    result = run_experiment(Settings(motion="slow", noise=0.2))
    uncertainty = parameter_uncertainty(result.solution, noise_bound=None)
    assert uncertainty.noise_bound_std_error is None and uncertainty.verdict_basis == "empirical"
    np.testing.assert_array_equal(uncertainty.verdict_std_error, uncertainty.residual_std_error)


def test_interval_is_student_t_with_n_minus_p_degrees_of_freedom():
    uncertainty = run_experiment(Settings(motion="rich", noise=0.2)).uncertainty
    low, high = uncertainty.interval95.T
    np.testing.assert_allclose((low + high) / 2, uncertainty.estimate, rtol=1e-14)
    # t(0.975, 21) = 2.0796 from printed tables.
    np.testing.assert_allclose((high - low) / 2 / uncertainty.residual_std_error, 2.0796, atol=1e-4)


def test_no_residual_degrees_of_freedom_gives_no_standard_errors_and_a_warning():
    result = run_experiment(Settings(motion="rich", noise=0.2, samples=3))
    assert result.rank == 3
    uncertainty = result.uncertainty
    assert uncertainty.residual_std_error is None and uncertainty.interval95 is None
    assert uncertainty.noise_bound_std_error is not None  # the design still has a known variance
    assert any("no residual degrees of freedom" in w for w in fit_warnings(result))
    assert "no residual degrees of freedom" in status_message(result)


def test_rank_deficient_fit_has_no_uncertainty():
    assert run_experiment(Settings(motion="holds")).uncertainty is None


def test_slow_message_says_the_unique_fit_is_not_accurate_and_keeps_the_lab_sentences():
    message = status_message(run_experiment(Settings(motion="slow", noise=0.2)))
    assert message.startswith("Rank 3 of 3: a unique least-squares fit. Held-out torque RMSE is 2.261865 N m.")
    assert "Fitted inertia -1.607788 kg m² fails this joint model's requirement I > 0." in message
    assert "inertia and damping are not determined (expected standard errors I 5.425077, B 1.013808)" in message


def test_noiseless_rich_message_is_the_lab_text_alone():
    message = status_message(run_experiment(Settings()))
    assert message == (
        "Rank 3 of 3: a unique least-squares fit. Held-out torque RMSE is 0.000000 N m. " + LAB_SENTENCE
    )


@pytest.mark.parametrize("motion, expected", [("rich", 1.28), ("slow", 3.78)])
def test_condition_number_of_the_scaled_regressor(motion, expected):
    result = run_experiment(Settings(motion=motion, noise=0.2))
    X = result.training_regressor
    assert round(result.condition_number, 2) == expected
    assert result.condition_number == pytest.approx(np.linalg.cond(X / np.linalg.norm(X, axis=0)), rel=1e-12)


def test_modest_condition_number_comes_with_its_caveat_when_a_parameter_is_undetermined():
    warnings = fit_warnings(run_experiment(Settings(motion="slow", noise=0.2)))
    assert any("condition number 3.78 is modest" in w for w in warnings)
    assert fit_warnings(run_experiment(Settings())) == ()


def test_condition_number_is_infinite_for_holds():
    assert run_experiment(Settings(motion="holds")).condition_number == float("inf")


def _newey_west_by_pairs(X, residuals, positions, lag):
    """The Newey-West sum written out pair by pair on the evenly spaced grid: the definition, slowly."""
    p = X.shape[1]
    meat, autocorrelation = np.zeros((p, p)), 0.0
    c0 = float(residuals @ residuals)
    for a, (i, u) in enumerate(zip(positions, X * residuals[:, None])):
        for b, (j, v) in enumerate(zip(positions, X * residuals[:, None])):
            k = abs(int(i) - int(j))
            if k <= lag:
                weight = 1 - k / (lag + 1)
                meat += weight * np.outer(u, v)
                autocorrelation += weight * residuals[a] * residuals[b] / c0
    return meat, max(autocorrelation, 1.0)


@pytest.mark.parametrize("lag", [0, 1, 3, 7, 500])
def test_newey_west_sum_matches_its_definition_on_a_grid_with_gaps(lag):
    from jointid.estimation.uncertainty import newey_west_sum

    rng = np.random.default_rng(5)
    positions = np.sort(rng.choice(60, 45, replace=False))
    X = rng.standard_normal((45, 3))
    residuals = np.convolve(rng.standard_normal(49), np.ones(5) / 5, mode="valid")  # correlated, as filtered ones
    meat, autocorrelation = newey_west_sum(X, residuals, positions, lag)
    expected_meat, expected_autocorrelation = _newey_west_by_pairs(X, residuals, positions, lag)
    assert np.allclose(meat, expected_meat, rtol=1e-12, atol=1e-12)
    assert autocorrelation == pytest.approx(expected_autocorrelation, rel=1e-12)
