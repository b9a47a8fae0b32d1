"""Synthetic experiments: settings in, a fit on generated data out."""

from __future__ import annotations

from functools import lru_cache

from .dataset import JointData
from .fit import FitResult, fit_joint
from .model import TRUE_PARAMETERS, predict_torque
from .motions import TRAINING_MOTIONS, VALIDATION_MOTION, VALIDATION_SAMPLES, sample_times
from .noise import torque_noise
from .settings import Settings


def training_data(settings: Settings) -> JointData:
    """Training states of the chosen motion with the true joint's torque plus seeded bounded noise."""
    states = TRAINING_MOTIONS[settings.motion].states(sample_times(settings.samples))
    exact = predict_torque(states.q, states.qd, states.qdd, TRUE_PARAMETERS)
    measured = exact + torque_noise(settings.noise, settings.samples, settings.seed)
    return JointData(t=states.t, q=states.q, qd=states.qd, qdd=states.qdd, tau=measured)


@lru_cache(maxsize=1)
def validation_data() -> JointData:
    """The 16 held-out states of the validation motion with the true joint's noiseless torque."""
    states = VALIDATION_MOTION.states(sample_times(VALIDATION_SAMPLES))
    exact = predict_torque(states.q, states.qd, states.qdd, TRUE_PARAMETERS)
    return JointData(t=states.t, q=states.q, qd=states.qd, qdd=states.qdd, tau=exact)


def run_experiment(settings: Settings = Settings()) -> FitResult:
    """Generate training data for `settings`, fit its model and predict the validation motion."""
    return fit_joint(
        training_data(settings),
        validation_data(),
        model=settings.joint_model,
        heldout_is_noiseless=True,
        noise_bound=settings.noise,
    )
