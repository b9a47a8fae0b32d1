"""The synthetic joint's samples: a motion's states at the sample times, with its measured torque and seeded noise."""

from __future__ import annotations

from functools import lru_cache

from ..checks import checked, instance_of
from ..model.truth import LESSON_JOINT, TrueJoint
from ..options import VALIDATION_SAMPLES
from ..samples import JointData
from .motions import VALIDATION_MOTION, Motion, sample_times
from .noise import torque_noise
from .settings import Settings


def measured_states(motion: Motion, count: int, joint: TrueJoint) -> JointData:
    """A motion sampled at `count` instants over 0..8 s as the joint's sensors report it, without noise."""
    states = motion.states(sample_times(count))
    return JointData(t=states.t, q=joint.logged_angle(states.q), qd=states.qd, qdd=states.qdd,
                     tau=joint.measured_torque(states.q, states.qd, states.qdd))


@checked(settings=instance_of(Settings, "a Settings, e.g. jointid.Settings(motion='slow')"))
def training_data(settings: Settings) -> JointData:
    """Training states of the chosen motion with the true joint's measured torque plus seeded bounded noise.

    Parameters
    ----------
    settings : Settings
        The experiment; its samples are spread evenly over 0..8 s (t_i = 8 i / (N - 1)).

    Returns
    -------
    JointData
        Exact states and the lesson's LCG noise added to the torque (drawn before each sample).
    """
    exact = measured_states(settings.training_motion, settings.samples, settings.true_joint)
    noisy = exact.tau + torque_noise(settings.noise, settings.samples, settings.seed)
    return JointData(t=exact.t, q=exact.q, qd=exact.qd, qdd=exact.qdd, tau=noisy)


@checked(joint=instance_of(TrueJoint, "a TrueJoint (Settings.true_joint)"))
@lru_cache(maxsize=8)
def validation_data(joint: TrueJoint = LESSON_JOINT) -> JointData:
    """The 16 held-out states of the validation motion with the joint's noiseless measured torque.

    Parameters
    ----------
    joint : TrueJoint
        The synthetic joint (the lesson's by default, or one with missing physics).

    Returns
    -------
    JointData
        States at t_i = 8 i / 15 on the validation motion and their exact torque.
    """
    return measured_states(VALIDATION_MOTION, VALIDATION_SAMPLES, joint)
