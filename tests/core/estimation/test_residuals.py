"""Residual data for the residual view: measured minus fitted torque against t, q, qd, qdd."""

import numpy as np
import pytest

from jointid.estimation.fit import fit_joint
from jointid.estimation.residuals import AXES, residual_data
from jointid.samples import JointData
from jointid.studies.experiment import run_experiment
from jointid.synthetic.settings import Settings


def test_residuals_are_measured_minus_fitted_and_orthogonal_to_the_columns():
    result = run_experiment(Settings(motion="rich", noise=0.2))
    data = residual_data(result)
    X, y = result.training_regressor, result.training.tau
    expected = y - X @ np.linalg.lstsq(X, y, rcond=None)[0]
    np.testing.assert_allclose(data.residuals, expected, atol=1e-12)
    np.testing.assert_allclose(X.T @ data.residuals, 0.0, atol=1e-10)
    assert float(np.sqrt(np.mean(data.residuals**2))) == pytest.approx(result.training_rmse, rel=1e-12)


def test_every_axis_has_values_and_a_one_line_note():
    result = run_experiment(Settings(motion="slow", noise=0.2))
    data = residual_data(result)
    assert tuple(data.axes) == AXES
    np.testing.assert_array_equal(data.axes["t"], result.training.t)
    np.testing.assert_array_equal(data.axes["qd"], result.training.qd)
    assert all(len(data.note(axis)) and "\n" not in data.note(axis) for axis in AXES)
    assert "Coulomb friction" in data.note("qd") and "qd = 0" in data.note("qd")


def test_holds_residuals_come_from_the_basic_solution():
    result = run_experiment(Settings(motion="holds", noise=0.2))
    data = residual_data(result)
    assert not data.unique_fit
    tau = result.training.tau
    np.testing.assert_allclose(data.residuals, tau - tau.mean(), atol=1e-13)


def test_data_without_times_plot_against_the_sample_index():
    base = run_experiment(Settings(noise=0.2)).training
    untimed = JointData(t=None, q=base.q, qd=base.qd, qdd=base.qdd, tau=base.tau)
    data = residual_data(fit_joint(untimed))
    assert not data.has_times
    np.testing.assert_array_equal(data.axes["t"], np.arange(base.count))
