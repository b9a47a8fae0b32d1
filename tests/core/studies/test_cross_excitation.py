"""Cross-excitation table: each training motion's fit predicting every motion's noiseless torque."""

import numpy as np
import pytest

from jointid.model.terms import TRUE_PARAMETERS, regressor
from jointid.studies.cross_excitation import PREDICTION_MOTIONS, cross_excitation
from jointid.studies.experiment import run_experiment
from jointid.synthetic.motions import ALL_MOTIONS
from jointid.synthetic.settings import Settings

NOISY = Settings(noise=0.2)


def independent_rmse(motion, count, theta):
    """RMSE of a fit's torque against truth on `count` samples over 0..8 s, built from scratch."""
    t = 8.0 * np.arange(count) / (count - 1)
    states = ALL_MOTIONS[motion].states(t)
    X = regressor(states.q, states.qd, states.qdd)
    return float(np.sqrt(np.mean((X @ (np.asarray(theta) - TRUE_PARAMETERS)) ** 2)))


def test_validation_column_reproduces_the_lessons_heldout_rmse():
    table = cross_excitation(NOISY)
    assert round(table.cell("rich", "test").rmse, 6) == 0.014150
    assert round(table.cell("slow", "test").rmse, 6) == 2.261865
    for motion in ("rich", "slow"):
        assert table.cell(motion, "test").rmse == run_experiment(Settings(motion=motion, noise=0.2)).heldout_rmse


@pytest.mark.parametrize("training, predicted", [("rich", "rich"), ("rich", "slow"), ("slow", "rich"), ("slow", "slow")])
def test_moving_columns_use_the_experiments_sample_count(training, predicted):
    settings = Settings(noise=0.2, samples=37, seed=11)
    table = cross_excitation(settings)
    estimate = run_experiment(Settings(motion=training, noise=0.2, samples=37, seed=11)).estimate
    assert table.cell(training, predicted).rmse == pytest.approx(
        independent_rmse(predicted, 37, estimate), rel=1e-9
    )


def test_validation_column_uses_its_16_states():
    table = cross_excitation(Settings(noise=0.2, samples=50))
    estimate = table.rows[0].fit.estimate
    assert table.cell("rich", "test").rmse == pytest.approx(independent_rmse("test", 16, estimate), rel=1e-9)


def test_only_a_rows_own_motion_is_marked_training_data():
    table = cross_excitation(NOISY)
    assert table.prediction_motions == PREDICTION_MOTIONS == ("rich", "slow", "test")
    for row in table.rows:
        flags = {cell.prediction_motion: cell.is_training_data for cell in row.cells}
        assert flags == {motion: motion == row.training_motion for motion in PREDICTION_MOTIONS}


def test_holds_row_is_unavailable():
    table = cross_excitation(NOISY)
    holds = table.rows[2]
    assert holds.training_motion == "holds" and not holds.available
    assert all(cell.rmse is None for cell in holds.cells)
    assert np.isnan(table.rmse_matrix[2]).all()


def test_slow_fit_predicts_rich_motion_badly_although_it_fits_its_own():
    table = cross_excitation(NOISY)
    assert table.cell("slow", "slow").rmse < 0.05 < 1.0 < table.cell("slow", "rich").rmse


def test_noiseless_fits_predict_every_motion_exactly():
    table = cross_excitation(Settings())
    np.testing.assert_allclose(table.rmse_matrix[:2], 0.0, atol=1e-12)
