"""Synthetic experiments: settings in, a fit on generated data out."""

from __future__ import annotations

from ..estimation.fit import FitResult, fit_joint
from ..synthetic.samples import training_data, validation_data
from ..synthetic.settings import Settings


def run_experiment(settings: Settings = Settings()) -> FitResult:
    """Generate training data for `settings`, fit its model and predict the validation motion."""
    return fit_joint(
        training_data(settings),
        validation_data(settings.true_joint),
        model=settings.joint_model,
        constrained=settings.constrained,
        heldout_is_noiseless=True,
        noise_bound=settings.noise,
        settings=settings,
    )
