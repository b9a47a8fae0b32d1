"""Synthetic experiments: settings in, a fit on generated data out."""

from __future__ import annotations

from ..checks import checked, instance_of
from ..estimation.fit import FitResult, fit_joint
from ..synthetic.samples import training_data, validation_data
from ..synthetic.settings import Settings


@checked(settings=instance_of(Settings, "a Settings, e.g. jointid.Settings(motion='slow')"))
def run_experiment(settings: Settings = Settings()) -> FitResult:
    """Generate training data for `settings`, fit its model and predict the validation motion.

    Parameters
    ----------
    settings : Settings
        Motion, noise bound, samples, seed, model and the synthetic joint's missing physics.

    Returns
    -------
    FitResult
        The fit, scored on the 16 noiseless held-out states of the validation motion.

    Examples
    --------
    >>> import jointid
    >>> result = jointid.run_experiment(jointid.Settings(motion="slow", noise=0.2))
    >>> round(result.params["I"], 6), round(result.heldout_rmse, 6)
    (-1.607788, 2.261865)
    """
    return fit_joint(
        training_data(settings),
        validation_data(settings.true_joint),
        model=settings.joint_model,
        constrained=settings.constrained,
        heldout_is_noiseless=True,
        noise_bound=settings.noise,
        settings=settings,
    )
