"""Synthetic experiments: settings in, a fit on generated data out."""

from __future__ import annotations

from functools import lru_cache

from .dataset import JointData
from .fit import FitResult, fit_joint
from .motions import VALIDATION_MOTION, VALIDATION_SAMPLES, Motion, sample_times
from .noise import torque_noise
from .settings import Settings
from .truth import LESSON_JOINT, TrueJoint


def measured_states(motion: Motion, count: int, joint: TrueJoint) -> JointData:
    """A motion sampled at `count` instants over 0..8 s as the joint's sensors report it, without noise."""
    states = motion.states(sample_times(count))
    return JointData(t=states.t, q=joint.logged_angle(states.q), qd=states.qd, qdd=states.qdd,
                     tau=joint.measured_torque(states.q, states.qd, states.qdd))


def training_data(settings: Settings) -> JointData:
    """Training states of the chosen motion with the true joint's measured torque plus seeded bounded noise."""
    exact = measured_states(settings.training_motion, settings.samples, settings.true_joint)
    noisy = exact.tau + torque_noise(settings.noise, settings.samples, settings.seed)
    return JointData(t=exact.t, q=exact.q, qd=exact.qd, qdd=exact.qdd, tau=noisy)


@lru_cache(maxsize=8)
def validation_data(joint: TrueJoint = LESSON_JOINT) -> JointData:
    """The 16 held-out states of the validation motion with the joint's noiseless measured torque."""
    return measured_states(VALIDATION_MOTION, VALIDATION_SAMPLES, joint)


def run_experiment(settings: Settings = Settings()) -> FitResult:
    """Generate training data for `settings`, fit its model and predict the validation motion."""
    return fit_joint(
        training_data(settings),
        validation_data(settings.true_joint),
        model=settings.joint_model,
        constrained=settings.constrained,
        heldout_is_noiseless=True,
        noise_bound=settings.noise,
    )
